/* The setpoint stage shared by the controllers (see mc/outer_loop.h). */
#include "mc/outer_loop.h"

#include <math.h>

mc_status_t mc_outer_loop_init_f32(mc_outer_loop_f32_t *o,
                                   const mc_outer_loop_params_t *p)
{
    if (!isfinite(p->i_max_A)) {
        return MC_ERR_NONFINITE;
    }
    if (!(p->i_max_A > 0.0f)) {
        return MC_ERR_PARAM;
    }
    mc_position_loop_f32_t pl;
    const mc_status_t st = mc_position_loop_init_f32(&pl, p->position_kp_per_s,
                                                     p->omega_max_rad_s);
    if (st != MC_OK) {
        return st;
    }
    *o = (mc_outer_loop_f32_t){
        .position = pl,
        .omega_max_rad_s = p->omega_max_rad_s,
        .i_max_A = p->i_max_A,
    };
    return MC_OK;
}

void mc_outer_loop_reset_f32(mc_outer_loop_f32_t *o)
{
    o->i_d_ref_A = 0.0f;
    o->i_q_ref_A = 0.0f;
    o->omega_m_ref_rad_s = 0.0f;
}
