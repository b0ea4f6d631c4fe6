/*
 * Test double of the HAL contract for the firmware unit tests: plain
 * variables the test sets (inputs) and reads (outputs). Linked instead of a
 * real backend (link-time binding).
 */
#ifndef HAL_STUB_H
#define HAL_STUB_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/adc.h"
#include "hal/hal_status.h"

typedef struct {
    /* inputs */
    hal_adc_sample_t adc;
    uint32_t encoder_cpr;
    uint32_t encoder_count;
    bool encoder_edge_capture; /* hal_encoder_edge_age reports ... */
    float encoder_edge_age_s;  /* ... this */
    bool fault_input;
    bool oc_comparator;           /* hal_pwm_overcurrent_arm succeeds */
    bool oc_active;               /* hal_pwm_overcurrent_active returns this */
    uint32_t cycle_now;           /* hal_cycle_counter() returns this ... */
    uint32_t cycle_step;          /* ... and then adds this */
    uint32_t cycle_hz;            /* hal_cycle_counter_hz() (0: no counter) */
    hal_status_t pwm_init_status; /* returned by hal_pwm_init (not HAL_OK:
                                   *timing untouched) */
    float pwm_period_s;           /* realised period reported by hal_pwm_init;
                                     0: exactly 1 / the requested rate */
    float pwm_delay_periods;      /* sample-to-apply delay reported */
    /* outputs */
    float f_pwm_Hz;     /* rate requested by the last hal_pwm_init */
    uint32_t pwm_inits; /* hal_pwm_init calls */
    float duty_abc[3];
    bool outputs_enabled;
    bool power_stage;
    float oc_trip_A; /* the level armed, 0: none */
    uint32_t duty_writes;
} hal_stub_t;

#define HAL_STUB_CYCLE_HZ      1000000u /* 1 cycle = 1 us */
#define HAL_STUB_DELAY_PERIODS 1.5f     /* default reported delay */

extern hal_stub_t g_hal;

/* Defaults: 48 V, zero currents, cpr 10000, count 0, ISR cost 2 us, cycle
 * counter at HAL_STUB_CYCLE_HZ, PWM accepted with the exact requested
 * period and a delay of HAL_STUB_DELAY_PERIODS. */
void hal_stub_reset(void);

#endif /* HAL_STUB_H */
