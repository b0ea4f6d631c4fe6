/*
 * PLL-type speed / load-torque estimator: the baseline of paper 001 (its
 * reference [4], Nam, "NAM" in Fig. 11; also its [11]), fed by the flux
 * observer's angle (mc/flux_observer.h), float32.
 *
 * A tracking loop on the mechanical model, driven by the angle error
 * eps = wrap(theta_obs - theta_hat) (electrical rad):
 *   theta_hat' = n_p w_hat + l1 eps
 *   w_hat'     = (tau_e_ff - tau_hat) / J + l2 eps
 *   tau_hat'   = -l3 eps
 * tau_e_ff is an optional electrical-torque feed-forward (kt * i_q, or 0).
 * With e = [theta - theta_hat; w - w_hat; tau - tau_hat] (true
 * theta' = n_p w, J w' = tau_e_ff - tau) the error dynamics are linear:
 *   e' = [ -l1  n_p  0    ]
 *        [ -l2  0   -1/J  ] e,
 *        [  l3  0    0    ]
 * characteristic polynomial s^3 + l1 s^2 + n_p l2 s + n_p l3 / J. Placing a
 * triple pole at -w_b (the designed bandwidth):
 *   l1 = 3 w_b,  l2 = 3 w_b^2 / n_p,  l3 = J w_b^3 / n_p.
 * Type-3 loop: a speed ramp (constant acceleration, e.g. without torque
 * feed-forward) is tracked with zero steady-state error; tau_hat then
 * absorbs -J * acceleration. Default w_b = 40 rad/s, close to the natural
 * frequency sqrt(n_p a2 / J) = 38.7 rad/s of the I&I observer with the
 * paper's gains, for a like-for-like comparison.
 *
 * Discretisation (Ts): predict with explicit Euler, then correct with the
 * new angle, so the outputs after step k are the estimates at t_k:
 *   theta^- = theta + Ts n_p w;  w^- = w + Ts (tau_e_ff - tau) / J
 *   eps = wrap(theta_obs,k - theta^-)
 *   theta = theta^- + Ts l1 eps; w = w^- + Ts l2 eps;
 *   tau = tau - Ts l3 eps.
 * The angle is held as its direction (cos theta, sin theta), rotated by
 * each step's increment d_theta = Ts (n_p w + l1 eps) (mc_rotate_unit_f32:
 * a short series, angle error <= |d_theta|^5 / 30 per step) and brought
 * back to unit length by the caller every few steps (mc_renormalise_unit_f32
 * with the update's renormalise flag; the series shrinks it by at most
 * d_theta^4 / 24 per step): no wrap, no compensation, and the fast ISR gets
 * the sine and cosine without a polynomial. The angle itself is the
 * direction's arctangent (mc_pll_obs_theta_e_f32). w_hat is accumulated
 * with Kahan compensation: its per-sample increments are far below its ulp
 * at speed, and plain float32 rounding would bias the type-3 loop
 * (measured with the angle so accumulated: 6e-5 N m load error).
 * init requires w_b Ts <= 0.1 so the discrete poles stay within 1 % of the
 * design (z = 1 - w_b Ts + O((w_b Ts)^2) per pole).
 *
 * Two phase detectors give eps: the wrapped angle difference above (the
 * checked step mc_pll_obs_step_f32, for tests and host tools), or, for a
 * caller that has the observed direction as a vector (the flux), its cross
 * product with the predicted direction (mc_pll_obs_update_vector_f32: no
 * atan2, no wrap; the ISR of the drive's "flux_pll" estimator). The latter
 * is sin-shaped and scaled by the vector's length: the same loop for small
 * errors, with the gains times that length (the flux check keeps it near
 * 1), and a steady-state angle offset of atan(d) - d = -d^3 / 3 + ...
 * (d = n_p Ts w_hat, the prediction's advance, which it applies to first
 * order): -7.2e-5 rad at d = 0.06 (200 Hz electrical at 20 kHz). Beyond
 * pi / 2 its gain falls and pi is an unstable equilibrium: the drive
 * starts the PLL at the aligned angle.
 *
 * Units: rad (electrical), rad/s (MECHANICAL w_hat), N m, kg m^2, s.
 */
#ifndef MC_PLL_OBSERVER_H
#define MC_PLL_OBSERVER_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/angle.h"
#include "mc/compensated_sum.h"
#include "mc/compiler.h"
#include "mc/estimate_bounds.h"
#include "mc/status.h"

#define MC_PLL_OBS_BANDWIDTH_DEFAULT_RAD_S 40.0f
#define MC_PLL_OBS_MAX_BANDWIDTH_TS        0.1f

typedef struct {
    float bandwidth_rad_s; /* w_b > 0, w_b Ts <= MC_PLL_OBS_MAX_BANDWIDTH_TS */
    uint32_t pole_pairs;   /* n_p >= 1 */
    float J_kgm2;          /* > 0 */
    float Ts_s;            /* > 0 */
    mc_estimate_bounds_t bounds;
} mc_pll_obs_params_t;

typedef struct {
    /* configuration: gains times Ts */
    float l1_Ts; /* rad/rad */
    float l2_Ts; /* (rad/s)/rad */
    float l3_Ts; /* N m/rad */
    float np_Ts;
    float Ts_over_J;
    mc_estimate_bounds_t bounds;
    /* state: estimates at the last step */
    float sin_e, cos_e; /* the angle's direction, length 1 up to the
                           rotations since the last renormalisation */
    float omega_m_rad_s;
    float omega_comp_rad_s; /* rounding carried into the next speed update */
    float tau_L_Nm;
    float d_theta_e_rad; /* the angle's increment over the last step */
} mc_pll_obs_f32_t;

/* Validate (finite, positive, bandwidth bound, bounds valid), design the
 * gains and reset to zero. MC_ERR_NONFINITE / MC_ERR_PARAM (*pll untouched).
 * Interrupt context: no. */
mc_status_t mc_pll_obs_init_f32(mc_pll_obs_f32_t *pll,
                                const mc_pll_obs_params_t *p);

/* Restart from known estimates (e.g. aligned angle, 0, 0).
 * Non-finite: MC_ERR_NONFINITE; |theta| > MC_ANGLE_MAX_ABS_RAD:
 * MC_ERR_RANGE; state untouched. Interrupt context: yes. */
mc_status_t mc_pll_obs_reset_f32(mc_pll_obs_f32_t *pll, float theta_e_rad,
                                 float omega_m_rad_s, float tau_L_Nm);

/* One sample with the observed (wrapped) electrical angle at t_k and the
 * torque feed-forward over [t_{k-1}, t_k] (N m, 0 for none), by the angle
 * detector (the predicted angle from mc_pll_obs_theta_e_f32), the
 * direction renormalised. Non-finite input or result: MC_ERR_NONFINITE,
 * state untouched. Interrupt context: yes (bounded, one division). */
mc_status_t mc_pll_obs_step_f32(mc_pll_obs_f32_t *pll, float theta_obs_e_rad,
                                float tau_e_ff_Nm);

/* The step's prediction and correction by the angle error eps (rad, from
 * either detector), unchecked, the same for both; the direction
 * renormalised if renormalise. NaN and Inf propagate into the state.
 * Returns the sum of x * 0 over the new speed, its carried rounding, the
 * load and the sine: +-0 if all are finite, NaN otherwise (the aggregate
 * of mc/finite.h); the cosine comes from the same rotation as the sine, so
 * it is finite exactly when the sine is. Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE float mc_pll_obs_correct_f32(mc_pll_obs_f32_t *pll,
                                                   float eps, float tau_e_ff_Nm,
                                                   bool renormalise)
{
    /* predict (explicit Euler of the mechanical model) and correct with
     * the angle error eps; the speed is accumulated with compensation
     * (mc/compensated_sum.h) */
    const float w = pll->omega_m_rad_s;
    float w_comp;
    const float d_theta = pll->np_Ts * w + pll->l1_Ts * eps;
    const float w_new = mc_kahan_add_f32(
        w, pll->omega_comp_rad_s,
        pll->Ts_over_J * (tau_e_ff_Nm - pll->tau_L_Nm) + pll->l2_Ts * eps,
        &w_comp);
    const float tau_new = pll->tau_L_Nm - pll->l3_Ts * eps;
    float s = pll->sin_e;
    float c = pll->cos_e;
    mc_rotate_unit_f32(d_theta, &s, &c);
    if (renormalise) {
        mc_renormalise_unit_f32(&s, &c);
    }
    pll->sin_e = s;
    pll->cos_e = c;
    pll->omega_m_rad_s = w_new;
    pll->omega_comp_rad_s = w_comp;
    pll->tau_L_Nm = tau_new;
    pll->d_theta_e_rad = d_theta;
    return s * 0.0f + w_new * 0.0f + w_comp * 0.0f + tau_new * 0.0f;
}

/*
 * The step with the cross-product detector (above): (r_alpha, r_beta) = r
 * [cos theta_obs; sin theta_obs] the observed direction at t_k (r > 0,
 * e.g. eta / Phi of mc/flux_observer.h). The last step's direction
 * (c, s) is advanced by d = n_p Ts w_hat to first order, (s + d c,
 * c - d s) = sqrt(1 + d^2) [sin; cos](theta + atan d), and
 *   eps = r_beta c_pred - r_alpha s_pred
 *       = r sqrt(1 + d^2) sin(theta_obs - theta - atan d).
 * renormalise: as mc_pll_obs_correct_f32 (the drive: on its slow tick).
 * Unchecked: NaN and Inf propagate into the state and the aggregate it
 * returns (mc_pll_obs_correct_f32). Interrupt context: yes (no division,
 * no libm).
 */
MC_STATIC_FORCEINLINE float
mc_pll_obs_update_vector_f32(mc_pll_obs_f32_t *pll, float r_alpha, float r_beta,
                             float tau_e_ff_Nm, bool renormalise)
{
    const float d = pll->np_Ts * pll->omega_m_rad_s;
    const float s_pred = pll->sin_e + d * pll->cos_e;
    const float c_pred = pll->cos_e - d * pll->sin_e;
    return mc_pll_obs_correct_f32(pll, r_beta * c_pred - r_alpha * s_pred,
                                  tau_e_ff_Nm, renormalise);
}

/* The increment the last step rotated the angle by, rad. Interrupt
 * context: yes. */
static inline float mc_pll_obs_d_theta_e_f32(const mc_pll_obs_f32_t *pll)
{
    return pll->d_theta_e_rad;
}

/* Filtered electrical angle at t_k, [-pi, pi]: the direction's
 * arctangent (mc_atan2_unchecked_f32, error <= MC_ATAN2_MAX_ERR_RAD; the
 * state is finite after a finite step). Interrupt context: yes (one
 * division). */
MC_STATIC_FORCEINLINE float mc_pll_obs_theta_e_f32(const mc_pll_obs_f32_t *pll)
{
    return mc_atan2_unchecked_f32(pll->sin_e, pll->cos_e);
}

/* The sine and cosine of that angle (the direction; its length is 1 up
 * to the rotations since the last renormalisation). Interrupt context:
 * yes. */
static inline void mc_pll_obs_sincos_f32(const mc_pll_obs_f32_t *pll,
                                         float *sin_out, float *cos_out)
{
    *sin_out = pll->sin_e;
    *cos_out = pll->cos_e;
}

/* Mechanical speed estimate, rad/s. Interrupt context: yes. */
static inline float mc_pll_obs_omega_m_f32(const mc_pll_obs_f32_t *pll)
{
    return pll->omega_m_rad_s;
}

/* Load-torque estimate, N m. Interrupt context: yes. */
static inline float mc_pll_obs_tau_L_f32(const mc_pll_obs_f32_t *pll)
{
    return pll->tau_L_Nm;
}

/* MC_OK if the estimates are inside the configured bounds, MC_ERR_RANGE
 * otherwise. Interrupt context: yes. */
static inline mc_status_t mc_pll_obs_check_f32(const mc_pll_obs_f32_t *pll)
{
    return mc_estimate_bounds_check(&pll->bounds, pll->omega_m_rad_s,
                                    pll->tau_L_Nm);
}

#endif /* MC_PLL_OBSERVER_H */
