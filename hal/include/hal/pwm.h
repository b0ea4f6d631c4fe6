/*
 * HAL contract: three-phase centre-aligned PWM of the power stage.
 *
 * Bound at link time: exactly one backend (hal/host, hal/qemu_m4, a board
 * port) provides these functions in a build.
 *
 * Timing model: the ADC conversion of a period is triggered at the PWM centre
 * and raises the fast ISR; duties written in that ISR are latched into the
 * shadow registers and take effect at the start of the NEXT period.
 * Disabling the outputs is immediate (no shadow register): the gate drivers
 * switch all six transistors off within the current period.
 */
#ifndef HAL_PWM_H
#define HAL_PWM_H

#include <stdbool.h>

#include "hal/hal_status.h"

/* Configure the carrier for f_pwm_hz (centre-aligned, the period is
 * 1/f_pwm_hz) and leave the outputs disabled.
 * f_pwm_hz: finite, > 0; the backend may reject frequencies it cannot make
 * (HAL_ERR_PARAM). NOT Interrupt context: yes. */
hal_status_t hal_pwm_init(float f_pwm_hz);

/* PWM period in seconds as configured by hal_pwm_init (0 before init).
 * Interrupt context: yes. */
float hal_pwm_period_s(void);

/* Write the three duty cycles (phase a, b, c), each the high-side on-time as a
 * fraction of the period in [0, 1]. They take effect at the next period.
 * Out-of-range or non-finite values are a caller bug: the backend clamps them
 * to [0, 1] (NaN -> 0.5) only to protect the hardware; the firmware checks
 * its duties before calling. Interrupt context: yes. */
void hal_pwm_set_duties(const float duty_abc[3]);

/* Enable the gate outputs (takes effect with the next period's duties).
 * Interrupt context: yes. */
void hal_pwm_enable_outputs(void);

/* Disable all six gate outputs immediately (all transistors off).
 * Interrupt context: yes. */
void hal_pwm_disable_outputs(void);

/* True while the outputs are enabled. Interrupt context: yes. */
bool hal_pwm_outputs_enabled(void);

#endif /* HAL_PWM_H */
