/* Gripper board firmware: protocol and control logic in portable C. It
 * builds for the ATmega328P (avr_main.c adds the registers) and for the
 * host, where the simulated board runs it. No dynamic memory, no floating
 * point, bounded work per call. */
#ifndef GRIPPER_FW_H
#define GRIPPER_FW_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum {
  GFW_CMD_GET_VERSION = 0x81,
  GFW_CMD_EXIT_SAFE_START = 0x82,
  GFW_CMD_OPEN = 0x83,
  GFW_CMD_CLOSE = 0x84,
  GFW_CMD_STOP = 0x85,
  GFW_CMD_GO_TO = 0x86,
  GFW_CMD_CALIBRATE = 0x87,
  GFW_CMD_GET_STATE = 0x88,
  GFW_CMD_GET_ERROR = 0x89,
  GFW_CMD_SET_TIMEOUT = 0x8A
};

enum {
  GFW_ERR_FRAMING = 1u << 0,
  GFW_ERR_OVERRUN = 1u << 1,
  GFW_ERR_CRC = 1u << 2,
  GFW_ERR_FORMAT = 1u << 3,
  GFW_ERR_TIMEOUT = 1u << 4,
  GFW_ERR_OVER_CURRENT = 1u << 5,
  GFW_ERR_NOT_CALIBRATED = 1u << 6
};

enum {
  GFW_FLAG_CALIBRATED = 1u << 0,
  GFW_FLAG_MOVING = 1u << 1,
  GFW_FLAG_HOLDING = 1u << 2,
  GFW_FLAG_STALLED = 1u << 3,
  GFW_FLAG_OVER_CURRENT = 1u << 4,
  GFW_FLAG_SAFE_START = 1u << 5,
  GFW_FLAG_ERROR = 1u << 6
};

#define GFW_PROTOCOL_VERSION 1
#define GFW_VERSION_MAJOR 1
#define GFW_VERSION_MINOR 0
#define GFW_BOARD_ID 0x42
#define GFW_MAX_DATA 4
#define GFW_MAX_REPLY 12
#define GFW_ABS_CURRENT_LIMIT_MA 2500
#define GFW_DEFAULT_TIMEOUT_MS 500
#define GFW_PWM_SLEW_PER_MS 4 /* full reversal in about 130 ms */
#define GFW_OPEN_REST_MS 250  /* still this long while opening: on the open stop */

uint8_t gfw_crc7(const uint8_t* bytes, uint8_t n);

typedef enum {
  GFW_MODE_IDLE = 0, /* motor braked */
  GFW_MODE_OPENING,
  GFW_MODE_CLOSING,
  GFW_MODE_HOLDING,
  GFW_MODE_GO_TO,
  GFW_MODE_CALIBRATING
} gfw_mode;

typedef struct {
  /* Parser. */
  uint8_t cmd, n_data, want, data[GFW_MAX_DATA + 1];
  /* Reply waiting to be sent (the board's main loop drains it). */
  uint8_t tx[GFW_MAX_REPLY], tx_len;
  /* Control. */
  gfw_mode mode;
  uint8_t calibrated, safe_start, error, stalled, over_current;
  uint8_t speed;             /* 0..127 */
  uint16_t current_limit_ma; /* CLOSE */
  int16_t target;            /* GO_TO, counts */
  int32_t encoder_offset;    /* raw count at the open stop */
  int16_t position;          /* counts from the open stop */
  int16_t velocity;          /* counts/s */
  uint16_t current_ma;
  uint16_t timeout_ms;
  uint32_t last_command_ms, stall_since_ms, limit_since_ms, last_tick_ms;
  int32_t window_raw; /* encoder at the start of the velocity window */
  uint32_t window_start_ms;
  int16_t pwm; /* -255..255 to the motor driver; positive closes */
} gfw_state;

void gfw_init(gfw_state* s, uint32_t now_ms);
/* One received byte; `line_error` carries the UART's framing / overrun
 * bits for that byte (0 on the host). May queue a reply in s->tx. */
void gfw_receive(gfw_state* s, uint8_t byte, uint8_t line_error, uint32_t now_ms);
/* The control step, at 1 kHz: encoder (raw counts, closing positive),
 * motor current (mA). Sets s->pwm. */
void gfw_tick(gfw_state* s, int32_t raw_encoder, uint16_t current_ma, uint32_t now_ms);
uint8_t gfw_flags(const gfw_state* s);

#ifdef __cplusplus
}
#endif

#endif
