/*
 * The ISR-path HAL functions of the simulator mailbox binding, one body for
 * two linkages: hal_sim_mailbox.c defines them as functions on
 * hal_sim_bound() (the host binding); an image includes them as static
 * inline accessors on its own mailbox pointer through HAL_INLINE_ACCESSORS
 * (hal/include/hal/adc.h), as a board's binding reads and writes its
 * peripheral registers.
 *
 * The includer defines HAL_SIM_ACCESSOR (the linkage) and HAL_SIM_MAILBOX
 * (an expression: the bound mailbox).
 */
#ifndef HAL_SIM_ACCESSORS_H
#define HAL_SIM_ACCESSORS_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/pwm_duty.h"
#include "hal_sim_mailbox.h"

#if !defined(HAL_SIM_ACCESSOR) || !defined(HAL_SIM_MAILBOX)
#error "define HAL_SIM_ACCESSOR and HAL_SIM_MAILBOX before this header"
#endif

/* Field by field, as registers are read: the compiler keeps only the
 * fields the caller uses (a whole-struct copy goes through memory). */
HAL_SIM_ACCESSOR void hal_adc_read(hal_adc_sample_t *out)
{
    const hal_adc_sample_t *a = &HAL_SIM_MAILBOX->adc;
    for (unsigned k = 0u; k < 3u; ++k) {
        out->i_abc_A[k] = a->i_abc_A[k];
    }
    out->v_dc_V = a->v_dc_V;
    out->temp_degC = a->temp_degC;
    out->temp_valid = a->temp_valid;
}

HAL_SIM_ACCESSOR uint32_t hal_encoder_count(void)
{
    return HAL_SIM_MAILBOX->encoder_count;
}

HAL_SIM_ACCESSOR bool hal_encoder_edge_age(float *age_s)
{
    *age_s = HAL_SIM_MAILBOX->encoder_edge_age_s;
    return true;
}

HAL_SIM_ACCESSOR bool hal_gpio_fault_input_active(void)
{
    return HAL_SIM_MAILBOX->fault_input_active;
}

HAL_SIM_ACCESSOR void hal_gpio_power_stage_enable(bool enable)
{
    HAL_SIM_MAILBOX->power_stage_enabled = enable;
}

HAL_SIM_ACCESSOR void hal_gpio_debug_pin_set(bool level)
{
    HAL_SIM_MAILBOX->debug_pin = level;
}

/* The compare registers saturate (hal/pwm_duty.h): whatever the firmware
 * computed, a duty in [0, 1] (the contract: protect the hardware). */
HAL_SIM_ACCESSOR void hal_pwm_set_duties(const float duty_abc[3])
{
    hal_sim_mailbox_t *m = HAL_SIM_MAILBOX;
#pragma GCC unroll 3
    for (unsigned k = 0u; k < 3u; ++k) {
        m->duty_abc[k] = hal_duty_saturate_f32(duty_abc[k]);
    }
}

HAL_SIM_ACCESSOR void hal_pwm_enable_outputs(void)
{
    HAL_SIM_MAILBOX->pwm_outputs_enabled = true;
}

HAL_SIM_ACCESSOR void hal_pwm_disable_outputs(void)
{
    HAL_SIM_MAILBOX->pwm_outputs_enabled = false;
}

HAL_SIM_ACCESSOR bool hal_pwm_outputs_enabled(void)
{
    return HAL_SIM_MAILBOX->pwm_outputs_enabled;
}

HAL_SIM_ACCESSOR bool hal_pwm_overcurrent_active(void)
{
    return HAL_SIM_MAILBOX->oc_active;
}

#endif /* HAL_SIM_ACCESSORS_H */
