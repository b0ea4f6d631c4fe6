/* Encoder position / angle / speed tracking (see mc/encoder_tracker.h). */
#include "mc/encoder_tracker.h"

#include <math.h>

#include "mc/angle.h"
#include "mc/motor.h"

mc_status_t mc_encoder_tracker_init_f32(mc_encoder_tracker_f32_t *et,
                                        uint32_t cpr, uint32_t pole_pairs,
                                        float offset_e_rad, float w_pll_rad_s,
                                        float step_speed_max_rad_s, float Ts_s)
{
    if (!isfinite(offset_e_rad) || !isfinite(w_pll_rad_s) || !isfinite(Ts_s) ||
        !isfinite(step_speed_max_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    if (cpr < MC_ENCODER_CPR_MIN || cpr > MC_ENCODER_CPR_MAX ||
        pole_pairs < 1u || pole_pairs > MC_MOTOR_POLE_PAIRS_MAX ||
        fabsf(offset_e_rad) > MC_TWO_PI_F || !(w_pll_rad_s > 0.0f) ||
        !(Ts_s > 0.0f) || w_pll_rad_s * Ts_s > MC_ENCODER_PLL_WTS_MAX ||
        !(step_speed_max_rad_s > 0.0f) ||
        !(step_speed_max_rad_s * Ts_s < MC_PI_F)) {
        return MC_ERR_PARAM;
    }
    et->cpr = cpr;
    et->pole_pairs = pole_pairs;
    et->rad_per_count = MC_TWO_PI_F / (float)cpr;
    /* (n_p count mod cpr + e_origin) 2 pi / cpr in (-pi, pi]: less cpr
     * where count_e + e_origin > cpr / 2 (a count on the edge rounds either
     * way: the update's wrap takes it) */
    const float offset_wrapped = mc_wrap_pi_f32(offset_e_rad); /* |.| <= 2 pi */
    et->e_origin_counts =
        0.5f * (float)pole_pairs + offset_wrapped / et->rad_per_count;
    const float e_threshold = 0.5f * (float)cpr - et->e_origin_counts;
    if (e_threshold < 0.0f) {
        et->e_upper = 0u;
    } else if (e_threshold >= (float)cpr) {
        et->e_upper = cpr;
    } else {
        et->e_upper = (uint32_t)e_threshold + 1u;
    }
    /* < cpr / 2 + 2 (step_speed_max Ts < pi): no overflow */
    et->step_max_counts =
        (uint32_t)ceilf(step_speed_max_rad_s * Ts_s / et->rad_per_count) + 1u;
    /* Critically damped PLL: s^2 + kp s + ki = (s + w)^2. */
    et->kp_per_s = 2.0f * w_pll_rad_s;
    et->ki_Ts_per_s = w_pll_rad_s * w_pll_rad_s * Ts_s; /* ki Ts, once */
    et->Ts_s = Ts_s;
    et->primed = false;
    et->last_count = 0u;
    et->position_counts = 0;
    et->theta_hat_rad = 0.0f;
    et->omega_hat_rad_s = 0.0f;
    return MC_OK;
}

mc_status_t mc_encoder_tracker_update_f32(mc_encoder_tracker_f32_t *et,
                                          uint32_t count,
                                          mc_encoder_estimate_t *out)
{
    return mc_encoder_tracker_update_inline_f32(et, count, out);
}
