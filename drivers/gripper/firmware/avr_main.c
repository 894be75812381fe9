/* The gripper board's register-level part, kept thin: UART, Timer0 PWM to
 * motor 1 (PD5/PD6), the quadrature encoder on pin-change interrupts,
 * the motor-current ADC and a 1 kHz tick. Everything else is gripper_fw.c.
 * Baby Orangutan B-328: ATmega328P at 20 MHz. */
#include <avr/interrupt.h>
#include <avr/io.h>

#include "gripper_fw.h"

#define BAUD 115200UL
#define CURRENT_ADC_CHANNEL 6 /* current-sense amplifier on ADC6 */
#define MA_PER_ADC_COUNT 5    /* 5 V / 1024 counts, 1 V per A sense: ~4.9 mA */

static volatile uint32_t g_ms;
static volatile int32_t g_encoder;
static volatile uint8_t g_tick_due;
static uint8_t g_last_ab;

/* Quadrature on PC2 (A) and PC3 (B): +1 / -1 per valid transition. */
ISR(PCINT1_vect) {
  static const int8_t table[16] = {0, 1, -1, 0, -1, 0, 0, 1, 1, 0, 0, -1, 0, -1, 1, 0};
  const uint8_t ab = (PINC >> 2) & 3;
  g_encoder += table[(g_last_ab << 2) | ab];
  g_last_ab = ab;
}

/* Timer2, CTC at 1 kHz. */
ISR(TIMER2_COMPA_vect) {
  ++g_ms;
  g_tick_due = 1;
}

static void uart_init(void) {
  UCSR0A = (uint8_t)(1 << U2X0);
  const uint16_t ubrr = (uint16_t)((F_CPU / (8UL * BAUD)) - 1);
  UBRR0H = (uint8_t)(ubrr >> 8);
  UBRR0L = (uint8_t)ubrr;
  UCSR0B = (uint8_t)((1 << RXEN0) | (1 << TXEN0));
  UCSR0C = (uint8_t)((1 << UCSZ01) | (1 << UCSZ00)); /* 8N1 */
}

static void pwm_init(void) {
  DDRD |= (uint8_t)((1 << PD5) | (1 << PD6));
  /* Fast PWM, OC0A and OC0B non-inverting, clk/8: ~9.8 kHz at 20 MHz. */
  TCCR0A = (uint8_t)((1 << COM0A1) | (1 << COM0B1) | (1 << WGM01) | (1 << WGM00));
  TCCR0B = (uint8_t)(1 << CS01);
  OCR0A = 0;
  OCR0B = 0;
}

/* Positive closes: PWM on PD6 (OC0A) with PD5 low; negative the reverse;
 * 0 brakes (both low). */
static void motor_set(int16_t pwm) {
  if (pwm >= 0) {
    OCR0B = 0;
    OCR0A = (uint8_t)pwm;
  } else {
    OCR0A = 0;
    OCR0B = (uint8_t)(-pwm);
  }
}

static void tick_init(void) {
  TCCR2A = (uint8_t)(1 << WGM21);               /* CTC */
  TCCR2B = (uint8_t)((1 << CS22));              /* clk/64 */
  OCR2A = (uint8_t)(F_CPU / 64UL / 1000UL - 1); /* 1 kHz */
  TIMSK2 = (uint8_t)(1 << OCIE2A);
}

static void encoder_init(void) {
  DDRC &= (uint8_t) ~((1 << PC2) | (1 << PC3));
  PORTC |= (uint8_t)((1 << PC2) | (1 << PC3)); /* pull-ups */
  PCMSK1 = (uint8_t)((1 << PCINT10) | (1 << PCINT11));
  PCICR = (uint8_t)(1 << PCIE1);
  g_last_ab = (PINC >> 2) & 3;
}

static uint16_t current_ma(void) {
  ADMUX = (uint8_t)((1 << REFS0) | CURRENT_ADC_CHANNEL);
  ADCSRA = (uint8_t)((1 << ADEN) | (1 << ADSC) | (1 << ADPS2) | (1 << ADPS1) | (1 << ADPS0));
  while (ADCSRA & (1 << ADSC)) {
  } /* ~104 us at clk/128: bounded by the hardware */
  return (uint16_t)(ADC * MA_PER_ADC_COUNT);
}

int main(void) {
  static gfw_state s;
  uart_init();
  pwm_init();
  encoder_init();
  tick_init();
  sei();
  gfw_init(&s, 0);
  uint8_t tx_pos = 0, sending = 0;
  for (;;) {
    if (UCSR0A & (1 << RXC0)) {
      const uint8_t status = UCSR0A;
      const uint8_t byte = UDR0;
      uint8_t line_error = 0;
      if (status & (1 << FE0)) line_error |= GFW_ERR_FRAMING;
      if (status & (1 << DOR0)) line_error |= GFW_ERR_OVERRUN;
      cli();
      const uint32_t now = g_ms;
      sei();
      gfw_receive(&s, byte, line_error, now);
    }
    /* A queued reply goes out a byte at a time between the other work. */
    if (!sending && s.tx_len) {
      sending = 1;
      tx_pos = 0;
    }
    if (sending && (UCSR0A & (1 << UDRE0))) {
      UDR0 = s.tx[tx_pos++];
      if (tx_pos >= s.tx_len) {
        s.tx_len = 0;
        sending = 0;
      }
    }
    if (g_tick_due) {
      cli();
      g_tick_due = 0;
      const uint32_t now = g_ms;
      const int32_t enc = g_encoder;
      sei();
      gfw_tick(&s, enc, current_ma(), now);
      motor_set(s.pwm);
    }
  }
}
