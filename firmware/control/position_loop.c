/* Baseline position P loop (see mc/position_loop.h). */
#include "mc/position_loop.h"

#include <math.h>

mc_status_t mc_position_loop_init_f32(mc_position_loop_f32_t *pl,
                                      float kp_per_s, float omega_max_rad_s)
{
    if (!isfinite(kp_per_s) || !isfinite(omega_max_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    if (!(kp_per_s > 0.0f) || !(omega_max_rad_s > 0.0f)) {
        return MC_ERR_PARAM;
    }
    pl->kp_per_s = kp_per_s;
    pl->omega_max_rad_s = omega_max_rad_s;
    return MC_OK;
}
