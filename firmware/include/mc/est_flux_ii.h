/*
 * Estimator "flux_ii": sensorless, currents only: the flux observer front
 * end (mc/est_flux_front.h: paper 001 (12)-(14)) and the I&I speed and
 * load-torque observer (15)-(16) (mc/speed_load_observer.h), the paper 001
 * scheme. The angle is the flux observer's.
 * Interface: mc/estimator.h.
 */
#ifndef MC_EST_FLUX_II_H
#define MC_EST_FLUX_II_H

#include <stdint.h>

#include "mc/compiler.h"
#include "mc/est_flux_front.h"
#include "mc/estimator.h"
#include "mc/params.h"
#include "mc/speed_load_observer.h"
#include "mc/timing.h"

typedef struct {
    float a1; /* I&I gain a1 of (15), > 0 */
    float a2; /* I&I gain a2 of (15), > 0 */
} mc_est_flux_ii_config_t;

typedef struct {
    mc_flux_front_t front;
    mc_speed_load_obs_f32_t ii;
} mc_est_flux_ii_t;

MC_ESTIMATOR_INTERFACE(flux_ii);

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_est_flux_ii_step(mc_est_flux_ii_t *est,
                                                   const mc_est_input_t *in,
                                                   mc_telemetry_t *t,
                                                   mc_est_sincos_t *sc)
{
    if (!in->running) {
        mc_flux_front_held(&est->front, in, t, sc);
        return MC_FAULT_NONE;
    }
    const mc_flux_front_sample_t s =
        mc_flux_front_update(&est->front, in, true);
    const float finite = mc_speed_load_obs_advance_f32(
        &est->ii, s.d_theta_obs_rad, s.i_q_mean_A);
    const mc_flux_front_speed_t sp = {
        .finite = finite,
        .theta_e_rad = s.theta_obs_rad,
        .d_theta_e_rad = s.d_theta_obs_rad,
        .omega_m_rad_s = mc_speed_load_obs_omega_m_f32(&est->ii),
        .tau_L_Nm = mc_speed_load_obs_tau_L_f32(&est->ii),
    };
    return mc_flux_front_finish(&est->front, in, &s, &sp, NULL, &est->ii.bounds,
                                t, sc);
}

#endif /* MC_EST_FLUX_II_H */
