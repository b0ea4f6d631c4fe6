/*
 * HAL contract: three-phase centre-aligned PWM of the power stage.
 *
 * Bound at link time: exactly one backend (hal/host, hal/qemu_m4, a board
 * port) provides these functions in a build.
 *
 * Timing model: the ADC conversion of a period is triggered at a fixed
 * point of the carrier (normally its centre of the low-side conduction,
 * where shunt currents are read) and raises the fast ISR; duties written in
 * that ISR are latched into the shadow registers at the timer's next update
 * event and act for one period from there. The backend reports the
 * resulting sample-to-apply delay d: the voltage the ISR after the sample
 * at t_k commands acts over [t_k + (d - 1/2) Ts, t_k + (d + 1/2) Ts]:
 *   d = 1.0  update half a period after the sample (update events at both
 *            ends of a centre-aligned carrier, or at the opposite one);
 *   d = 1.5  update a full period after the sample (one update event per
 *            period, at the sampling point).
 * The firmware designs its delay compensation and its applied-voltage
 * history with d (firmware/include/mc/timing.h).
 * Disabling the outputs is immediate (no shadow register): the gate drivers
 * switch all six transistors off within the current period.
 */
#ifndef HAL_PWM_H
#define HAL_PWM_H

#include <stdbool.h>

#include "hal/hal_status.h"

/* What the backend realised. */
typedef struct {
    float period_s;      /* carrier period (a timer rounds to whole
                            counts), > 0 */
    float delay_periods; /* sample-to-apply delay d (above), [0.5, 1.5] */
} hal_pwm_timing_t;

/* Configure the carrier for f_pwm_Hz (centre-aligned), leave the outputs
 * disabled and report the realised timing in *timing.
 * f_pwm_Hz: finite, > 0; the backend may reject frequencies it cannot make
 * (HAL_ERR_PARAM, *timing untouched). Interrupt context: no. */
hal_status_t hal_pwm_init(float f_pwm_Hz, hal_pwm_timing_t *timing);

/* Hardware over-current protection, where the board has it: comparators on
 * the phase currents that stop the outputs by themselves (e.g. into the
 * timer's break input), without the firmware. Sets their level to
 * +-trip_A and returns true; a board without them, or whose comparators
 * cannot be set to trip_A, returns false, and the firmware compares the
 * sampled currents itself. Armed, the outputs go off when a phase current
 * goes beyond the level and stay off while it is (hal_pwm_overcurrent_
 * active; hal_pwm_enable_outputs cannot override it). trip_A not finite
 * or not > 0: false. Call after hal_pwm_init. Interrupt context: no. */
bool hal_pwm_overcurrent_arm(float trip_A);

#ifdef HAL_INLINE_ACCESSORS
#include HAL_INLINE_ACCESSORS /* the binding's static inline definitions */
#else
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

/* True while the armed comparators see a phase current beyond their level
 * (as of this period's sample); false when they are not armed.
 * Interrupt context: yes. */
bool hal_pwm_overcurrent_active(void);
#endif

#endif /* HAL_PWM_H */
