/*
 * Estimator "encoder": incremental encoder (mc/encoder_tracker.h): the
 * electrical angle from the count, the multi-turn position, the speed from
 * a tracking PLL. No load-torque estimate (tau_L_hat = 0). A count step
 * faster than twice the overspeed trip is MC_FAULT_ENCODER. In RUN the
 * drive checks its angle and speed against the measured back-EMF
 * (mc/emf_monitor.h): a slip or a frozen encoder is MC_FAULT_ENCODER.
 * The angle's sine and cosine: in RUN between slow ticks the last
 * sample's, rotated by the angle's change d, n_p times the count
 * difference (mc_rotate_unit_f32: per rotation an angle error within
 * |d|^5 / 30 and a shortening within d^4 / 24, plus roundings; 3e-11 rad
 * and 2.5e-9 at the paper 001 drive's 0.016 rad per sample at 1000 rpm); on
 * the slow tick, and outside RUN, the polynomial of the angle
 * (mc_sincos_in_range_f32), so at most N - 1 rotations run from it (N
 * the slow decimation, 10 by default, at most MC_TIMING_DECIMATION_MAX):
 * the length short by at most (N - 1) d^4 / 24 and the angle off by at
 * most (N - 1) |d|^5 / 30 plus roundings, 4.9e-6 and 2.3e-7 rad at N = 10
 * and 0.06 rad per sample, 1 % and 1e-3 rad at N = 1000 and 0.125 rad per
 * sample (beyond, the rotation is exact but for roundings). Interface:
 * mc/estimator.h.
 */
#ifndef MC_EST_ENCODER_H
#define MC_EST_ENCODER_H

#include <stdint.h>

#include "mc/compiler.h"
#include "mc/encoder_tracker.h"
#include "mc/estimator.h"
#include "mc/faults.h"
#include "mc/params.h"
#include "mc/timing.h"

typedef struct {
    uint32_t counts_per_rev;   /* must equal hal_encoder_counts_per_rev() */
    float offset_e_rad;        /* theta_e at count 0 (alignment) */
    float pll_bandwidth_rad_s; /* speed-estimate PLL bandwidth */
} mc_est_encoder_config_t;

typedef struct {
    mc_encoder_tracker_f32_t tracker;
    mc_est_sincos_t sc_last; /* of the last sample's angle (the step's) */
} mc_est_encoder_t;

MC_ESTIMATOR_INTERFACE(encoder);

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_est_encoder_step(mc_est_encoder_t *est,
                                                   const mc_est_input_t *in,
                                                   mc_telemetry_t *t,
                                                   mc_est_sincos_t *sc)
{
    mc_encoder_estimate_t e;
    if (mc_encoder_tracker_update_inline_f32(&est->tracker, in->encoder_count,
                                             &e) != MC_OK ||
        e.count_jump) {
        mc_est_sincos_of(t->theta_e_rad, sc);
        return MC_FAULT_ENCODER;
    }
    /* one finiteness test of the sample's estimates (mc/finite.h) */
    if (e.theta_e_rad * 0.0f + e.theta_m_rad * 0.0f + e.omega_m_rad_s * 0.0f !=
        0.0f) {
        mc_est_sincos_of(t->theta_e_rad, sc);
        return MC_FAULT_NONFINITE;
    }
    t->theta_e_rad = e.theta_e_rad;
    t->theta_m_rad = e.theta_m_rad;
    t->omega_m_rad_s = e.omega_m_rad_s;
    if (in->running && !in->slow_tick) {
        /* the last sample's direction (every step that reports an angle
         * keeps it; a fault stops RUN, and the next step takes the
         * polynomial) turned by the count's step */
        float s = est->sc_last.sin_e;
        float c = est->sc_last.cos_e;
        mc_rotate_unit_f32(e.d_theta_e_rad, &s, &c);
        sc->sin_e = s;
        sc->cos_e = c;
    } else {
        /* finite (tested above) and wrapped to (-pi, pi] by the tracker */
        mc_sincos_in_range_f32(e.theta_e_rad, &sc->sin_e, &sc->cos_e);
    }
    est->sc_last = *sc;
    return MC_FAULT_NONE;
}

#endif /* MC_EST_ENCODER_H */
