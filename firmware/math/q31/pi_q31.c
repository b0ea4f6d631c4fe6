/* Q31 PI controller configuration (see mc/pi_q31.h). Integer only. */
#include "mc/pi_q31.h"

#include <stdbool.h>

/* Q31 -> Q47 without shifting a negative value */
static int64_t q31_to_q47(mc_q31_t x)
{
    return (int64_t)x * ((int64_t)1 << MC_PI_Q31_GUARD_BITS);
}

static bool gain_valid(mc_q31_t frac, uint8_t shift)
{
    return frac >= 0 && shift <= MC_PI_Q31_MAX_SHIFT;
}

mc_status_t mc_pi_init_q31(mc_pi_q31_t *pi, mc_q31_t kp_frac, uint8_t kp_shift,
                           mc_q31_t ki_ts_frac, uint8_t ki_ts_shift,
                           mc_q31_t out_min, mc_q31_t out_max)
{
    if (!gain_valid(kp_frac, kp_shift) ||
        !gain_valid(ki_ts_frac, ki_ts_shift) ||
        (kp_frac == 0 && ki_ts_frac == 0) || out_min >= out_max) {
        return MC_ERR_PARAM;
    }
    pi->kp_frac = kp_frac;
    pi->kp_shift = kp_shift;
    pi->ki_ts_frac = ki_ts_frac;
    pi->ki_ts_shift = ki_ts_shift;
    pi->out_min_q47 = q31_to_q47(out_min);
    pi->out_max_q47 = q31_to_q47(out_max);
    pi->integrator_q47 = mc_pi_clamp_q31(0, pi->out_min_q47, pi->out_max_q47);
    return MC_OK;
}

void mc_pi_reset_q31(mc_pi_q31_t *pi, mc_q31_t integrator)
{
    pi->integrator_q47 = q31_to_q47(integrator);
}

mc_status_t mc_pi_set_limits_q31(mc_pi_q31_t *pi, mc_q31_t out_min,
                                 mc_q31_t out_max)
{
    if (out_min >= out_max) {
        return MC_ERR_PARAM;
    }
    pi->out_min_q47 = q31_to_q47(out_min);
    pi->out_max_q47 = q31_to_q47(out_max);
    return MC_OK;
}
