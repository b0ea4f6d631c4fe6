/*
 * The drive's timing: what is configured (mc_timing_config_t) and the one
 * record every block is designed with (mc_timing_t), built once at init
 * from the PWM period the HAL realised and its sample-to-apply delay
 * (hal/pwm.h).
 *
 * Sample-to-apply delay d (periods): the voltage commanded by the ISR that
 * follows the current sample at t_k acts over [t_k + (d - 1/2) Ts,
 * t_k + (d + 1/2) Ts]. The HAL backend reports it (1.0 when the duties
 * latch half a period after the sample, 1.5 when a full period after);
 * delay_periods in the configuration overrides it (0 = the HAL's). The
 * delay compensation and the applied-voltage history (mc/delay_comp.h)
 * take d from here.
 *
 * Durations are configured in seconds and rates in Hz and converted to
 * whole periods here, once: calibration samples = round(calib_time_s /
 * Ts); the slow (speed/position) loop runs every N-th fast ISR with
 * N = f_pwm_Hz / slow_loop_Hz, which must be an integer (within 1e-3).
 */
#ifndef MC_TIMING_H
#define MC_TIMING_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/status.h"

#define MC_TIMING_F_PWM_MIN_HZ 1000.0f
#define MC_TIMING_F_PWM_MAX_HZ 100000.0f
/* Largest relative difference between the realised and the requested
 * period (a timer rounds the period to whole counts: 1/8400 at 20 kHz
 * from 168 MHz). */
#define MC_TIMING_PERIOD_REL_TOL    1.0e-3f
#define MC_TIMING_DECIMATION_MAX    1000u
#define MC_TIMING_CALIB_SAMPLES_MAX 65536u
#define MC_TIMING_OVERRUN_LIMIT_MAX 100u

typedef struct {
    float f_pwm_Hz;             /* requested PWM = fast ISR rate,
                                   [MC_TIMING_F_PWM_MIN_HZ, _MAX_HZ] */
    float slow_loop_Hz;         /* speed/position loop rate, divides f_pwm */
    float calib_time_s;         /* current-offset calibration, PWM off */
    uint32_t isr_overrun_limit; /* consecutive overruns that make the
                                   MC_FAULT_ISR_OVERRUN fault, [1, 100] */
    float delay_periods;        /* 0: the HAL's sample-to-apply delay; else
                                   an override in [0.5, 1.5] */
    bool delay_compensation;    /* advance the output voltage angle by
                                   omega_e d Ts (mc/delay_comp.h) */
    bool telemetry_every_isr;   /* the telemetry record written by every
                                   fast ISR (a simulation's traces); false:
                                   by every ISR but the steady RUN ISRs
                                   between slow ticks, which spare its
                                   stores (mc/app.h) */
} mc_timing_config_t;

typedef struct {
    float Ts_s;               /* realised PWM period (the HAL's) */
    float delay_periods;      /* sample-to-apply delay in use */
    uint32_t slow_decimation; /* slow loop every N fast ISRs, >= 1 */
    float Ts_slow_s;          /* N Ts */
    uint32_t calib_samples;   /* >= 1 */
    uint32_t isr_overrun_limit;
    bool delay_compensation;
    bool telemetry_every_isr;
} mc_timing_t;

/* Build the record from the configuration, the period the HAL realised
 * and the HAL's sample-to-apply delay (periods). MC_ERR_NONFINITE for a
 * non-finite value, MC_ERR_PARAM for a value out of range, a realised
 * period more than MC_TIMING_PERIOD_REL_TOL from the request, a slow-loop
 * rate that does not divide the PWM rate, or a delay outside [0.5, 1.5]
 * (*tm untouched on error). Interrupt context: no. */
mc_status_t mc_timing_init(mc_timing_t *tm, const mc_timing_config_t *c,
                           float realised_period_s, float hal_delay_periods);

#endif /* MC_TIMING_H */
