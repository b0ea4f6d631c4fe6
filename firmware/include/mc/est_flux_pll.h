/*
 * Estimator "flux_pll": sensorless, currents only: the flux observer front
 * end (mc/est_flux_front.h: paper 001 (12)-(14)) and a PLL on its angle
 * with speed and load-torque states (mc/pll_observer.h), the estimator of
 * the "NAM" baseline of paper 001 (Fig. 11). The angle is the PLL's. The
 * PLL's phase detector is the cross product of rho_hat = eta / Phi with
 * its predicted direction (mc_pll_obs_update_vector_f32), and the PLL
 * holds its angle as that direction: the observer's own angle (13) is not
 * formed (no atan2, no wrap; mc_flux_front_update without it), the sine
 * and cosine are the PLL's direction (no polynomial), and the angle, its
 * arctangent, is formed only where the telemetry record is written. The
 * direction is renormalised on the slow tick: between, its length is
 * short by at most (N - 1) d^4 / 24 (N the slow decimation, d the PLL's
 * step; 4.9e-6 at N = 10 and 0.06 rad per sample, 1 % at N = 1000 and
 * 0.125), which scales the detector's gain and the Park currents alike;
 * the angle's own error is the loop's to correct (mc/pll_observer.h).
 * Interface: mc/estimator.h.
 */
#ifndef MC_EST_FLUX_PLL_H
#define MC_EST_FLUX_PLL_H

#include <stdint.h>

#include "mc/compiler.h"
#include "mc/est_flux_front.h"
#include "mc/estimator.h"
#include "mc/params.h"
#include "mc/pll_observer.h"
#include "mc/timing.h"

typedef struct {
    float bandwidth_rad_s; /* triple pole of the PLL, > 0 */
} mc_est_flux_pll_config_t;

typedef struct {
    mc_flux_front_t front;
    mc_pll_obs_f32_t pll;
} mc_est_flux_pll_t;

MC_ESTIMATOR_INTERFACE(flux_pll);

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_est_flux_pll_step(mc_est_flux_pll_t *est,
                                                    const mc_est_input_t *in,
                                                    mc_telemetry_t *t,
                                                    mc_est_sincos_t *sc)
{
    if (!in->running) {
        mc_flux_front_held(&est->front, in, t, sc);
        return MC_FAULT_NONE;
    }
    const mc_flux_front_sample_t s =
        mc_flux_front_update(&est->front, in, false);
    /* the PLL's cross-product detector on rho_hat = eta / Phi (13);
     * electrical-torque feed-forward kt i_q over the interval; its
     * direction renormalised on the slow tick */
    float r_al;
    float r_be;
    mc_flux_obs_rho_f32(&est->front.obs, &r_al, &r_be);
    const float finite = mc_pll_obs_update_vector_f32(
        &est->pll, r_al, r_be, est->front.kt_Nm_per_A * s.i_q_mean_A,
        in->slow_tick);
    const mc_flux_front_speed_t sp = {
        .finite = finite,
        .theta_e_rad = 0.0f, /* unused: the direction pll_sc gives it */
        .d_theta_e_rad = mc_pll_obs_d_theta_e_f32(&est->pll),
        .omega_m_rad_s = mc_pll_obs_omega_m_f32(&est->pll),
        .tau_L_Nm = mc_pll_obs_tau_L_f32(&est->pll),
    };
    mc_est_sincos_t pll_sc;
    mc_pll_obs_sincos_f32(&est->pll, &pll_sc.sin_e, &pll_sc.cos_e);
    return mc_flux_front_finish(&est->front, in, &s, &sp, &pll_sc,
                                &est->pll.bounds, t, sc);
}

#endif /* MC_EST_FLUX_PLL_H */
