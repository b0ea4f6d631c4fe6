/*
 * Entry check shared by the observers' reset functions, private to
 * mc_observers: a restart from a known angle and two more known values.
 * Interrupt context: yes.
 */
#ifndef MC_RESET_ANGLE_H
#define MC_RESET_ANGLE_H

#include <math.h>

#include "mc/angle.h"
#include "mc/status.h"

/* MC_ERR_NONFINITE if any of the three inputs is NaN/Inf, MC_ERR_RANGE if
 * theta_e_rad is outside the wrap's accepted range, else MC_OK with the
 * wrapped angle in *theta_out (untouched on error). */
static inline mc_status_t mc_obs_reset_angle_f32(float theta_e_rad, float a,
                                                 float b, float *theta_out)
{
    if (!isfinite(theta_e_rad) || !isfinite(a) || !isfinite(b)) {
        return MC_ERR_NONFINITE;
    }
    const float theta = mc_wrap_pi_f32(theta_e_rad);
    if (!isfinite(theta)) { /* outside the wrap's accepted range */
        return MC_ERR_RANGE;
    }
    *theta_out = theta;
    return MC_OK;
}

#endif /* MC_RESET_ANGLE_H */
