#include "gripper_fw.h"

#include <string.h>

uint8_t gfw_crc7(const uint8_t* bytes, uint8_t n) {
  uint8_t crc = 0;
  for (uint8_t i = 0; i < n; ++i) {
    crc ^= bytes[i];
    for (uint8_t b = 0; b < 8; ++b) {
      if (crc & 1) crc ^= 0x91;
      crc >>= 1;
    }
  }
  return crc & 0x7F;
}

/* Data bytes each command takes. 0xFF: not a command. */
static uint8_t data_count(uint8_t cmd) {
  switch (cmd) {
    case GFW_CMD_GET_VERSION:
    case GFW_CMD_EXIT_SAFE_START:
    case GFW_CMD_STOP:
    case GFW_CMD_CALIBRATE:
    case GFW_CMD_GET_STATE:
    case GFW_CMD_GET_ERROR:
      return 0;
    case GFW_CMD_OPEN:
      return 1;
    case GFW_CMD_CLOSE:
    case GFW_CMD_GO_TO:
      return 3;
    case GFW_CMD_SET_TIMEOUT:
      return 2;
    default:
      return 0xFF;
  }
}

static uint16_t u14(const uint8_t* d) {
  return (uint16_t)(d[0] | ((uint16_t)d[1] << 7));
}

static void put14(uint8_t* out, int32_t v) {
  uint16_t u = (uint16_t)(v & 0x3FFF);
  out[0] = (uint8_t)(u & 0x7F);
  out[1] = (uint8_t)(u >> 7);
}

uint8_t gfw_flags(const gfw_state* s) {
  uint8_t f = 0;
  if (s->calibrated) f |= GFW_FLAG_CALIBRATED;
  if (s->velocity > 20 || s->velocity < -20) f |= GFW_FLAG_MOVING;
  if (s->mode == GFW_MODE_HOLDING) f |= GFW_FLAG_HOLDING;
  if (s->stalled) f |= GFW_FLAG_STALLED;
  if (s->over_current) f |= GFW_FLAG_OVER_CURRENT;
  if (s->safe_start) f |= GFW_FLAG_SAFE_START;
  if (s->error) f |= GFW_FLAG_ERROR;
  return f;
}

void gfw_init(gfw_state* s, uint32_t now_ms) {
  memset(s, 0, sizeof(*s));
  s->safe_start = 1;
  s->timeout_ms = GFW_DEFAULT_TIMEOUT_MS;
  s->last_command_ms = now_ms;
  s->last_tick_ms = now_ms;
  s->mode = GFW_MODE_IDLE;
}

static void reply(gfw_state* s, const uint8_t* data, uint8_t n) {
  s->tx[0] = s->cmd;
  for (uint8_t i = 0; i < n; ++i) s->tx[1 + i] = data[i];
  s->tx[1 + n] = gfw_crc7(s->tx, (uint8_t)(1 + n));
  s->tx_len = (uint8_t)(2 + n);
}

/* A motion command while locked off or out of range: refused, latched. */
static uint8_t motion_allowed(gfw_state* s) {
  if (s->safe_start) {
    s->error |= GFW_ERR_FORMAT;
    return 0;
  }
  return 1;
}

static void execute(gfw_state* s, uint32_t now_ms) {
  uint8_t out[8];
  s->last_command_ms = now_ms;
  switch (s->cmd) {
    case GFW_CMD_GET_VERSION:
      out[0] = GFW_PROTOCOL_VERSION;
      out[1] = GFW_VERSION_MAJOR;
      out[2] = GFW_VERSION_MINOR;
      out[3] = GFW_BOARD_ID;
      reply(s, out, 4);
      return;
    case GFW_CMD_EXIT_SAFE_START:
      s->safe_start = 0;
      s->over_current = 0;
      break;
    case GFW_CMD_OPEN:
      if (motion_allowed(s)) {
        s->speed = s->data[0];
        s->mode = GFW_MODE_OPENING;
        s->stalled = 0;
        s->stall_since_ms = 0;
      }
      break;
    case GFW_CMD_CLOSE: {
      const uint16_t limit = u14(s->data + 1);
      if (limit == 0 || limit > GFW_ABS_CURRENT_LIMIT_MA) {
        s->error |= GFW_ERR_FORMAT;
      } else if (motion_allowed(s)) {
        s->speed = s->data[0];
        s->current_limit_ma = limit;
        s->mode = GFW_MODE_CLOSING;
        s->stalled = 0;
        s->limit_since_ms = 0;
        s->stall_since_ms = 0; /* the stall timer is shared with OPEN and CALIBRATE */
      }
      break;
    }
    case GFW_CMD_STOP:
      s->mode = GFW_MODE_IDLE;
      break;
    case GFW_CMD_GO_TO:
      if (!s->calibrated) {
        s->error |= GFW_ERR_NOT_CALIBRATED;
      } else if (motion_allowed(s)) {
        s->target = (int16_t)u14(s->data);
        s->speed = s->data[2];
        s->mode = GFW_MODE_GO_TO;
        s->stalled = 0;
      }
      break;
    case GFW_CMD_CALIBRATE:
      if (motion_allowed(s)) {
        s->mode = GFW_MODE_CALIBRATING;
        s->calibrated = 0;
        s->stall_since_ms = 0;
      }
      break;
    case GFW_CMD_GET_STATE:
      put14(out, s->position);
      put14(out + 2, s->velocity);
      put14(out + 4, s->current_ma);
      out[6] = gfw_flags(s);
      out[7] = s->error;
      reply(s, out, 8);
      return;
    case GFW_CMD_GET_ERROR:
      out[0] = s->error;
      s->error = 0;
      reply(s, out, 1);
      return;
    case GFW_CMD_SET_TIMEOUT:
      s->timeout_ms = u14(s->data);
      break;
    default:
      return;
  }
  reply(s, out, 0);
}

void gfw_receive(gfw_state* s, uint8_t byte, uint8_t line_error, uint32_t now_ms) {
  s->error |= (uint8_t)(line_error & (GFW_ERR_FRAMING | GFW_ERR_OVERRUN));
  if (byte & 0x80) {
    /* A command byte always starts a packet, whatever came before. */
    s->want = data_count(byte);
    if (s->want == 0xFF) {
      s->error |= GFW_ERR_FORMAT;
      s->cmd = 0;
      return;
    }
    s->cmd = byte;
    s->n_data = 0;
    return;
  }
  if (s->cmd == 0) return; /* data with no command: skip to the next command */
  if (s->n_data < s->want) {
    s->data[s->n_data++] = byte;
    return;
  }
  /* This byte is the CRC of command + data. */
  {
    uint8_t packet[1 + GFW_MAX_DATA];
    packet[0] = s->cmd;
    for (uint8_t i = 0; i < s->n_data; ++i) packet[1 + i] = s->data[i];
    if (gfw_crc7(packet, (uint8_t)(1 + s->n_data)) != byte) {
      s->error |= GFW_ERR_CRC;
    } else {
      execute(s, now_ms);
    }
  }
  s->cmd = 0;
}

static int16_t clamp_pwm(int32_t v) {
  if (v > 255) return 255;
  if (v < -255) return -255;
  return (int16_t)v;
}

void gfw_tick(gfw_state* s, int32_t raw_encoder, uint16_t current_ma, uint32_t now_ms) {
  /* Velocity over 20 ms windows: per tick, one encoder count is already
   * 1000 counts/s, too coarse to tell slow from still. */
  const uint32_t window_ms = now_ms - s->window_start_ms;
  if (window_ms >= 20) {
    s->velocity = (int16_t)((raw_encoder - s->window_raw) * 1000 / (int32_t)window_ms);
    s->window_raw = raw_encoder;
    s->window_start_ms = now_ms;
  }
  s->last_tick_ms = now_ms;
  s->position = (int16_t)(raw_encoder - s->encoder_offset);
  s->current_ma = current_ma;

  /* Safety first: absolute over-current, serial timeout. */
  if (current_ma > GFW_ABS_CURRENT_LIMIT_MA) {
    s->over_current = 1;
    s->error |= GFW_ERR_OVER_CURRENT;
    s->safe_start = 1;
    s->mode = GFW_MODE_IDLE;
  }
  /* Signed: a command stamped a millisecond after this tick (the UART and
   * the tick read the clock at different moments) is not 49 days old. */
  if (s->timeout_ms && (int32_t)(now_ms - s->last_command_ms) > (int32_t)s->timeout_ms &&
      !s->safe_start) {
    s->error |= GFW_ERR_TIMEOUT;
    s->safe_start = 1;
    s->mode = GFW_MODE_IDLE;
  }
  if (s->safe_start && s->mode != GFW_MODE_IDLE) s->mode = GFW_MODE_IDLE;

  const int32_t drive = (int32_t)s->speed * 2; /* 0..254 */
  const int16_t previous_pwm = s->pwm;
  const uint8_t still = s->velocity < 20 && s->velocity > -20;
  switch (s->mode) {
    case GFW_MODE_IDLE:
      s->pwm = 0;
      break;
    case GFW_MODE_OPENING:
      /* Open until the fingers rest on the open stop, then let the motor
       * go: pushing on at a stall would heat it for nothing. */
      s->pwm = clamp_pwm(-drive);
      if (still) {
        if (s->stall_since_ms == 0) s->stall_since_ms = now_ms;
        if (now_ms - s->stall_since_ms >= GFW_OPEN_REST_MS) {
          s->mode = GFW_MODE_IDLE;
          s->pwm = 0;
        }
      } else {
        s->stall_since_ms = 0;
      }
      break;
    case GFW_MODE_CALIBRATING:
      /* Slowly to the open stop; there, still for 200 ms: zero. */
      s->pwm = -60;
      if (still) {
        if (s->stall_since_ms == 0) s->stall_since_ms = now_ms;
        if (now_ms - s->stall_since_ms >= 200) {
          s->encoder_offset = raw_encoder;
          s->position = 0;
          s->calibrated = 1;
          s->mode = GFW_MODE_IDLE;
          s->pwm = 0;
        }
      } else {
        s->stall_since_ms = 0;
      }
      break;
    case GFW_MODE_CLOSING:
      s->pwm = clamp_pwm(drive);
      if (current_ma >= s->current_limit_ma) {
        if (s->limit_since_ms == 0) s->limit_since_ms = now_ms;
        if (now_ms - s->limit_since_ms >= 50) s->mode = GFW_MODE_HOLDING;
      } else {
        s->limit_since_ms = 0;
      }
      /* Still under drive without reaching the limit: the closed stop
       * (an empty grasp) or a jam. */
      if (still && current_ma < s->current_limit_ma) {
        if (s->stall_since_ms == 0) s->stall_since_ms = now_ms;
        s->stalled = now_ms - s->stall_since_ms >= 300;
      } else {
        s->stall_since_ms = 0;
      }
      break;
    case GFW_MODE_HOLDING: {
      /* Hold the current at the limit: a proportional trim on the PWM. */
      const int32_t err = (int32_t)s->current_limit_ma - (int32_t)current_ma;
      s->pwm = clamp_pwm(s->pwm + err / 64);
      if (s->pwm < 0) s->pwm = 0;
      break;
    }
    case GFW_MODE_GO_TO: {
      const int32_t err = (int32_t)s->target - s->position;
      int32_t cmd = err * 2;
      if (cmd > drive) cmd = drive;
      if (cmd < -drive) cmd = -drive;
      s->pwm = clamp_pwm(cmd);
      if (err < 5 && err > -5) s->mode = GFW_MODE_IDLE;
      break;
    }
  }
  /* Slew limit: reversing a moving motor at once would drive the supply
   * plus the back-EMF through the winding (plugging), a current spike that
   * trips the over-current limit. Braking (0) is immediate. */
  if (s->pwm != 0) {
    const int32_t step = (int32_t)s->pwm - previous_pwm;
    if (step > GFW_PWM_SLEW_PER_MS) s->pwm = (int16_t)(previous_pwm + GFW_PWM_SLEW_PER_MS);
    if (step < -GFW_PWM_SLEW_PER_MS) s->pwm = (int16_t)(previous_pwm - GFW_PWM_SLEW_PER_MS);
  }
}
