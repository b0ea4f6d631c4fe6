/*
 * Estimator "flux_pll": sensorless, currents only: the flux observer front
 * end (mc/est_flux_front.h: paper 001 (12)-(14)) and a PLL on its angle
 * with speed and load-torque states (mc/pll_observer.h), the estimator of
 * the "NAM" baseline of paper 001 (Fig. 11). The angle is the PLL's.
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
    const mc_flux_front_sample_t s = mc_flux_front_update(&est->front, in);
    /* Electrical-torque feed-forward kt i_q over the interval. */
    const float finite = mc_pll_obs_update_f32(
        &est->pll, s.theta_obs_rad, est->front.kt_Nm_per_A * s.i_q_mean_A);
    const mc_flux_front_speed_t sp = {
        .finite = finite,
        .theta_e_rad = mc_pll_obs_theta_e_f32(&est->pll),
        .d_theta_e_rad = mc_pll_obs_d_theta_e_f32(&est->pll),
        .omega_m_rad_s = mc_pll_obs_omega_m_f32(&est->pll),
        .tau_L_Nm = mc_pll_obs_tau_L_f32(&est->pll),
    };
    return mc_flux_front_finish(&est->front, in, &s, &sp, false,
                                &est->pll.bounds, t, sc);
}

#endif /* MC_EST_FLUX_PLL_H */
