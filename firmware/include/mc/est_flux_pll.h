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
                                                    mc_telemetry_t *t)
{
    float theta_obs;
    float i_q_mean;
    uint32_t faults;
    if (!mc_flux_front_step(&est->front, in, t, &theta_obs, &i_q_mean,
                            &faults)) {
        return faults;
    }
    /* Electrical-torque feed-forward kt i_q over the interval. */
    mc_status_t st = mc_pll_obs_step_f32(&est->pll, theta_obs,
                                         est->front.kt_Nm_per_A * i_q_mean);
    if (st == MC_OK) {
        st = mc_pll_obs_check_f32(&est->pll);
    }
    t->theta_e_rad = mc_pll_obs_theta_e_f32(&est->pll);
    t->omega_m_rad_s = mc_pll_obs_omega_m_f32(&est->pll);
    t->tau_L_hat_Nm = mc_pll_obs_tau_L_f32(&est->pll);
    mc_flux_front_track(&est->front, t);
    return faults | mc_flux_front_bounds_fault(st);
}

#endif /* MC_EST_FLUX_PLL_H */
