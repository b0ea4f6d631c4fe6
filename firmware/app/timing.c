/* The drive's timing record (mc/timing.h). */
#include "mc/timing.h"

#include <math.h>

#include "mc/delay_comp.h"

/* A slow-loop rate divides the PWM rate when the quotient is an integer
 * within this absolute tolerance. */
#define MC_TIMING_DECIMATION_TOL 1.0e-3f

mc_status_t mc_timing_init(mc_timing_t *tm, const mc_timing_config_t *c,
                           float realised_period_s, float hal_delay_periods)
{
    const float f_pwm = c->f_pwm_Hz;
    if (!isfinite(f_pwm) || !isfinite(c->slow_loop_Hz) ||
        !isfinite(c->calib_time_s) || !isfinite(c->delay_periods) ||
        !isfinite(realised_period_s) || !isfinite(hal_delay_periods)) {
        return MC_ERR_NONFINITE;
    }
    if (f_pwm < MC_TIMING_F_PWM_MIN_HZ || f_pwm > MC_TIMING_F_PWM_MAX_HZ ||
        !(c->slow_loop_Hz > 0.0f) || !(c->calib_time_s > 0.0f) ||
        c->isr_overrun_limit < 1u ||
        c->isr_overrun_limit > MC_TIMING_OVERRUN_LIMIT_MAX ||
        !(realised_period_s > 0.0f) ||
        fabsf(realised_period_s * f_pwm - 1.0f) > MC_TIMING_PERIOD_REL_TOL) {
        return MC_ERR_PARAM;
    }
    const float n_slow = f_pwm / c->slow_loop_Hz;
    const float n_slow_round = roundf(n_slow);
    const float n_calib = roundf(c->calib_time_s / realised_period_s);
    if (!(n_slow_round >= 1.0f) ||
        n_slow_round > (float)MC_TIMING_DECIMATION_MAX ||
        fabsf(n_slow - n_slow_round) > MC_TIMING_DECIMATION_TOL ||
        !(n_calib >= 1.0f) || n_calib > (float)MC_TIMING_CALIB_SAMPLES_MAX) {
        return MC_ERR_PARAM;
    }
    const float d =
        (c->delay_periods == 0.0f) ? hal_delay_periods : c->delay_periods;
    if (!(d >= MC_DELAY_PERIODS_MIN && d <= MC_DELAY_PERIODS_MAX)) {
        return MC_ERR_PARAM;
    }
    const uint32_t n = (uint32_t)n_slow_round;
    *tm = (mc_timing_t){
        .Ts_s = realised_period_s,
        .delay_periods = d,
        .slow_decimation = n,
        .Ts_slow_s = realised_period_s * (float)n,
        .calib_samples = (uint32_t)n_calib,
        .isr_overrun_limit = c->isr_overrun_limit,
        .delay_compensation = c->delay_compensation,
        .telemetry_every_isr = c->telemetry_every_isr,
    };
    return MC_OK;
}
