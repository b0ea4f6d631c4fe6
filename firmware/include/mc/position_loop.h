/*
 * Baseline position loop: proportional, outer to the speed loop.
 *   omega_m_ref = kp * (theta_m_ref - theta_m), limited to +-omega_max.
 * With an ideal speed loop the position closed loop is first order with
 * bandwidth kp; choose kp <= w_s / 4 (w_s the speed-loop bandwidth).
 *
 * Units: rad (mechanical, multi-turn), rad/s, 1/s.
 */
#ifndef MC_POSITION_LOOP_H
#define MC_POSITION_LOOP_H

#include "mc/status.h"

typedef struct {
    float kp_per_s;        /* > 0 */
    float omega_max_rad_s; /* > 0 */
} mc_position_loop_f32_t;

/* Validate and store. MC_ERR_PARAM / MC_ERR_NONFINITE on invalid values.
 * Interrupt context: no. */
mc_status_t mc_position_loop_init_f32(mc_position_loop_f32_t *pl,
                                      float kp_per_s, float omega_max_rad_s);

/* Speed reference in rad/s for a position error theta_m_ref - theta_m (rad).
 * NaN propagates (the application faults on it). Callable from interrupt
 * context: yes. */
static inline float mc_position_loop_step_f32(const mc_position_loop_f32_t *pl,
                                              float theta_m_ref_rad,
                                              float theta_m_rad)
{
    float w = pl->kp_per_s * (theta_m_ref_rad - theta_m_rad);
    if (w > pl->omega_max_rad_s) {
        w = pl->omega_max_rad_s;
    } else if (w < -pl->omega_max_rad_s) {
        w = -pl->omega_max_rad_s;
    }
    return w;
}

#endif /* MC_POSITION_LOOP_H */
