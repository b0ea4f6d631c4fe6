/*
 * The front end shared by the sensorless estimators "flux_ii" and
 * "flux_pll": the gradient flux observer of paper 001 (12)-(14)
 * (mc/flux_observer.h) on the offset-corrected currents and the voltage
 * applied over the last interval, its plausibility check |rho_hat| in
 * [ratio_min, ratio_max] (MC_FAULT_ESTIMATE outside; the upper bound on
 * the slow tick, mc_flux_front_finish), the q current over
 * the interval (trapezoid of i_q_hat at both samples) for the speed
 * estimator, and the multi-turn position from the electrical-angle
 * increments / n_p (the absolute mechanical angle is known only modulo
 * 2 pi / n_p after the alignment).
 *
 * Outside RUN the observer is held and the ALIGN vector's angle is
 * reported (mc/align.h: the rotor is pulled to it).
 */
#ifndef MC_EST_FLUX_FRONT_H
#define MC_EST_FLUX_FRONT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/drive_io.h"
#include "mc/estimate_bounds.h"
#include "mc/estimator.h"
#include "mc/faults.h"
#include "mc/flux_observer.h"
#include "mc/params.h"
#include "mc/timing.h"

typedef struct {
    float gamma;     /* gamma of (12) as the paper gives it, in its
                        two-phase (power-invariant) variables (mc/motor.h),
                        1/(Wb^2 s), > 0 */
    float ratio_min; /* |rho_hat| (= |eta| / psi) outside */
    float ratio_max; /* [min, max]: MC_FAULT_ESTIMATE;
                        0 < min < 1 < max */
} mc_flux_obs_config_t;

typedef struct {
    mc_flux_obs_f32_t obs;
    float ratio_min_sq, ratio_max_sq;
    float inv_n_p;        /* 1 / pole pairs */
    float kt_Nm_per_A;    /* torque per A of q current */
    float i_q_hat_prev_A; /* i_q_hat at the previous sample */
    float theta_m_rad;    /* multi-turn position estimate */
} mc_flux_front_t;

extern const mc_param_t mc_flux_obs_params[];

/* Interrupt context: no. */
void mc_flux_obs_config_default(mc_flux_obs_config_t *c);

/* Design from cfg->flux_obs and the nominal motor (non-salient model of
 * the paper: L = Lq). Interrupt context: no. */
mc_status_t mc_flux_front_init(mc_flux_front_t *f, const mc_config_t *cfg,
                               const mc_timing_t *tm);

/* ALIGN starts: the position is theta_e_rad / n_p. Interrupt context: yes. */
void mc_flux_front_hold(mc_flux_front_t *f, float theta_e_rad);

/* ALIGN ends at theta_e_rad: restart the observer there with this
 * sample's currents (eta = psi [cos; sin]). Fault bits (NONFINITE).
 * Interrupt context: yes. */
uint32_t mc_flux_front_start(mc_flux_front_t *f, float theta_e_rad,
                             const mc_est_input_t *in);

/* Held (not running): the hold angle (and its sine and cosine into *sc),
 * the position, zero speed and load and the observer's |rho_hat|^2 into
 * *t. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_flux_front_held(const mc_flux_front_t *f,
                                              const mc_est_input_t *in,
                                              mc_telemetry_t *t,
                                              mc_est_sincos_t *sc)
{
    t->flux_ratio_sq = mc_flux_obs_rho_sq_f32(&f->obs);
    t->theta_e_rad = in->theta_e_hold_rad;
    t->theta_m_rad = f->theta_m_rad;
    t->omega_m_rad_s = 0.0f;
    t->tau_L_hat_Nm = 0.0f;
    mc_est_sincos_of(in->theta_e_hold_rad, sc);
}

/* What one running sample of the front end gives the speed estimator. */
typedef struct {
    float theta_obs_rad;   /* the observer's angle (13), [-pi, pi] */
    float d_theta_obs_rad; /* its increment over the interval */
    float i_q_mean_A;      /* the q current over the interval */
    float rho_sq;          /* |rho_hat|^2 */
    float finite;          /* +-0 if the observer's step is finite, else NaN
                              (mc_flux_obs_update_f32) */
} mc_flux_front_sample_t;

/* What the speed estimator behind the front end made of the sample. */
typedef struct {
    float theta_e_rad;   /* the reported angle, (-pi, pi] (unused when the
                            estimator gives its direction instead:
                            mc_flux_front_finish's angle_sc) */
    float d_theta_e_rad; /* its increment over the interval */
    float omega_m_rad_s;
    float tau_L_Nm;
    float finite; /* +-0 if its new states are finite, else NaN */
} mc_flux_front_speed_t;

/* Running: one observer step (unchecked: mc_flux_front_finish checks the
 * sample once), with_angle its angle (13) (else the sample's theta_obs_rad
 * and d_theta_obs_rad are 0 and the observer's angle state is not
 * advanced: for a speed estimator that takes rho_hat instead),
 * |rho_hat|^2 and the q current over the interval (trapezoid of i_q_hat at
 * both samples). Interrupt context: yes. */
MC_STATIC_FORCEINLINE mc_flux_front_sample_t mc_flux_front_update(
    mc_flux_front_t *f, const mc_est_input_t *in, bool with_angle)
{
    float v_al;
    float v_be;
    mc_applied_voltage_last_f32(in->v_applied, &v_al, &v_be);
    mc_flux_front_sample_t s;
    if (with_angle) {
        s.finite = mc_flux_obs_update_f32(&f->obs, in->i_alpha_A, in->i_beta_A,
                                          v_al, v_be, in->slow_tick);
        s.theta_obs_rad = mc_flux_obs_theta_e_f32(&f->obs);
        s.d_theta_obs_rad = mc_flux_obs_d_theta_e_f32(&f->obs);
    } else {
        s.finite = mc_flux_obs_advance_f32(&f->obs, in->i_alpha_A, in->i_beta_A,
                                           v_al, v_be);
        s.theta_obs_rad = 0.0f;
        s.d_theta_obs_rad = 0.0f;
    }
    s.rho_sq = mc_flux_obs_rho_sq_f32(&f->obs);
    /* i_q over [t_{k-1}, t_k]: trapezoid of the two samples. */
    const float i_q_hat =
        mc_flux_obs_iq_f32(&f->obs, in->i_alpha_A, in->i_beta_A);
    s.i_q_mean_A = 0.5f * (i_q_hat + f->i_q_hat_prev_A);
    f->i_q_hat_prev_A = i_q_hat;
    return s;
}

/* The sample's estimates into *t and the position into the front end;
 * the angle sp->theta_e_rad, or with the speed estimator's direction
 * angle_sc (not NULL) its arctangent (mc_atan2_unchecked_f32: formed only
 * where the record is written). Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_flux_front_publish(
    mc_flux_front_t *f, float rho_sq, const mc_flux_front_speed_t *sp,
    const mc_est_sincos_t *angle_sc, float theta_m_rad, mc_telemetry_t *t)
{
    f->theta_m_rad = theta_m_rad;
    t->flux_ratio_sq = rho_sq;
    t->theta_e_rad =
        (angle_sc != NULL)
            ? mc_atan2_unchecked_f32(angle_sc->sin_e, angle_sc->cos_e)
            : sp->theta_e_rad;
    t->theta_m_rad = theta_m_rad;
    t->omega_m_rad_s = sp->omega_m_rad_s;
    t->tau_L_hat_Nm = sp->tau_L_Nm;
}

/* The fault bits of a sample that failed mc_flux_front_finish's common
 * case (see there), from its |rho_hat|^2, the observer's and the speed
 * estimator's finiteness aggregates, the position and the speed and load
 * estimates (by value: the common case keeps them in registers);
 * MC_FAULT_NONFINITE among them if and only if its estimates are not all
 * finite. Interrupt context: yes. */
uint32_t mc_flux_front_fault(const mc_flux_front_t *f, float rho_sq,
                             float obs_finite, float speed_finite,
                             float theta_m_rad, float omega_m_rad_s,
                             float tau_L_Nm, const mc_estimate_bounds_t *b);

/* The sine and cosine of the observer's angle theta_obs = atan2(eta) (13)
 * from the flux estimate: eta / |eta| with |eta| = |rho_hat| Phi, rho_sq
 * = |rho_hat|^2 > 0 (the caller has checked it against ratio_min), one
 * square root and one division (measured on the M4: 19 instructions
 * fewer than the polynomial, the same cycles). Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_flux_front_sincos(const mc_flux_front_t *f,
                                                float rho_sq,
                                                mc_est_sincos_t *sc)
{
    const float inv_eta = f->obs.inv_psi_per_Wb / sqrtf(rho_sq);
    sc->sin_e = f->obs.eta_beta_Wb * inv_eta;
    sc->cos_e = f->obs.eta_alpha_Wb * inv_eta;
}

/* After the speed estimator's step: the multi-turn position from the
 * reported angle's increment / n_p, ONE finiteness test over the sample's
 * new states and outputs, the estimates into *t, the sine and cosine of
 * the angle in *t into *sc (angle_sc: the speed estimator's direction,
 * whose arctangent is its angle (mc_flux_front_publish); NULL: its angle
 * sp->theta_e_rad is the observer's (13), mc_flux_front_sincos) and the
 * fault bits:
 * NONFINITE for a non-finite value (with ESTIMATE for an implausible
 * |rho_hat| if the observer's step itself was finite, as the checked
 * steps report it; *t and the position keep the last sample's values),
 * else ESTIMATE for |rho_hat| below ratio_min (every sample: it guards
 * mc_flux_front_sincos's division) and, on a slow tick (in->slow_tick:
 * a plausibility test, a slow-loop period late at most), for |rho_hat|
 * above ratio_max or an estimate outside *b; any sample that finds a
 * fault reports them all. On NONFINITE the observers' states may hold
 * NaN: the fault stops RUN, which restarts through hold (the position)
 * and start (every other state this step writes). Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE uint32_t mc_flux_front_finish(
    mc_flux_front_t *f, const mc_est_input_t *in,
    const mc_flux_front_sample_t *s, const mc_flux_front_speed_t *sp,
    const mc_est_sincos_t *angle_sc, const mc_estimate_bounds_t *b,
    mc_telemetry_t *t, mc_est_sincos_t *sc)
{
    const float theta_m = f->theta_m_rad + sp->d_theta_e_rad * f->inv_n_p;
    /* the common case in one chain of comparisons, each false for NaN */
    if (s->finite + sp->finite + theta_m * 0.0f == 0.0f &&
        s->rho_sq >= f->ratio_min_sq &&
        (!in->slow_tick ||
         (s->rho_sq <= f->ratio_max_sq &&
          mc_estimate_bounds_hold(b, sp->omega_m_rad_s, sp->tau_L_Nm)))) {
        mc_flux_front_publish(f, s->rho_sq, sp, angle_sc, theta_m, t);
        if (angle_sc != NULL) {
            *sc = *angle_sc;
        } else {
            mc_flux_front_sincos(f, s->rho_sq, sc);
        }
        return MC_FAULT_NONE;
    }
    /* the uncommon case: finite estimates are published, and the sine
     * and cosine are those of the angle in *t (*t's address stays here:
     * isr_body) */
    const uint32_t faults =
        mc_flux_front_fault(f, s->rho_sq, s->finite, sp->finite, theta_m,
                            sp->omega_m_rad_s, sp->tau_L_Nm, b);
    if ((faults & MC_FAULT_NONFINITE) == 0u) {
        mc_flux_front_publish(f, s->rho_sq, sp, angle_sc, theta_m, t);
    }
    mc_est_sincos_of(t->theta_e_rad, sc);
    return faults;
}

#endif /* MC_EST_FLUX_FRONT_H */
