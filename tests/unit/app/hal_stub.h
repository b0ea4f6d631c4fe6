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

typedef struct {
    /* inputs */
    hal_adc_sample_t adc;
    uint32_t encoder_cpr;
    uint32_t encoder_count;
    bool fault_input;
    uint32_t cycle_now;       /* hal_cycle_counter() returns this ... */
    uint32_t cycle_step;      /* ... and then adds this */
    /* outputs */
    float f_pwm_hz;
    float duty_abc[3];
    bool outputs_enabled;
    bool power_stage;
    uint32_t duty_writes;
} hal_stub_t;

#define HAL_STUB_CYCLE_HZ 1000000u /* 1 cycle = 1 us */

extern hal_stub_t g_hal;

/* Defaults: 48 V, zero currents, cpr 10000, count 0, ISR cost 2 us. */
void hal_stub_reset(void);

#endif /* HAL_STUB_H */
