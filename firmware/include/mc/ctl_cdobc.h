/*
 * Controller "cdobc": paper 002's noncascade speed regulators (mc/cdobc.h)
 * in the drive. One controller for the whole family: the internal models
 * the observer carries are configuration, so
 *   CDOBC  = 6th electrical + Q-th mechanical harmonics + polynomial N = 2
 *            (the defaults),
 *   GPIOBC = polynomial only (dead_time_model false, cogging_order 0),
 *   HDOBC  = harmonics only (poly_order 0),
 * and `pid` true runs the paper's noncascade PID baseline (23, 10, 0.0167)
 * instead of the observer, with the same d-axis PI, voltage limits,
 * applied-voltage bookkeeping and protection. Optional models: 1st and
 * 2nd electrical (current-sensor offset and gain errors: the paper's
 * plant (2)-(3) has them, its observer (7) does not), their pairs at
 * damping sensor_zeta (0.5: they converge in about 10 ms at 500 rpm,
 * where the 6e / Q pairs' 0.03 would take 160 ms; mc/cdobc.h).
 *
 * Voltage: the regulator commands v_q (and v_d from a PI on -i_d) directly,
 * with no current loop, like mc/ctl_eeo.h; each axis is clamped to
 * +-v_max_V by the block, then the vector to the SVPWM circle v_dc /
 * sqrt(3) (keep angle) here, so that the voltage the observer is told is
 * the one the modulator applies. The application's measured-current limit
 * (mc/current_limit.h) acts afterwards, like on every controller; the
 * voltage it leaves (mc_drive_t.v_q_last_V, circle-limited again at the
 * next step with that step's bus) is what the observer takes as the
 * voltage applied over the period (mc_cdobc_f32_t.v_cur, the (6)
 * coupling term of that step removed). The supervisor, the trips and the
 * limit loop's fault act unchanged.
 *
 * Speed: the observer is driven by -omega (mc/cdobc.h), and its design
 * takes omega for the rotor's speed at the sample. With an encoder
 * (count_periods N > 0, default 4) the law gets the count difference over
 * the last N periods, 2 pi dc / (cpr N Ts): the mean speed over them, N / 2
 * periods late, quantised to 2 pi / (cpr N Ts) (1.6 rad/s with 10000
 * counts, 10 kHz, N = 4), with no other filter; where the HAL keeps the
 * edges' times (hal_encoder_edge_age) the counts over the time between
 * the last edges before the window's first and last samples (M/T: the
 * same mean speed, as late, without the quantisation;
 * mc_ctl_cdobc_count_speed). Not the encoder PLL's
 * estimate: that is omega low-passed by w_pll^2 / (s + w_pll)^2 (lag 2 /
 * w_pll, 20 periods at 1000 rad/s and 10 kHz; measured -96 degrees and gain
 * 0.39 at 200 Hz), which the observer does not model. In the unit tests'
 * plant (no dead time) the loop tolerates a pure delay of the speed of 4
 * periods with observer poles at -1000 (6 at -520) and is unstable with the
 * PLL's estimate at 1000 or 3000 rad/s; on the host bench only the dead
 * time's linear band (31 ohm at no load) kept it stable, and under load it
 * limit-cycled (host_sim/scenarios/README.md, "Paper 002 bench"). N = 1 is
 * the least late but its quantisation (one count per period) drives v_q to
 * the limit with poles at -1000. The first N steps after a (re)start take
 * t->omega_m_rad_s (a count of one period at standstill would be a 60 rpm
 * step). Without an encoder (sensorless estimators) or with N = 0:
 * t->omega_m_rad_s. The PID baseline, the outer loop and the limits keep
 * t->omega_m_rad_s. Speed reference: the shared setpoint stage
 * (mc/outer_loop.h) on its slow tick, so position mode works through its P
 * loop; current mode runs the d/q current loop (bumpless both ways: the
 * regulator restarts at the measured speed). With ref_pole_rad_s > 0 the
 * observer law takes omega* through the reference prefilter
 * (mc_cdobc_prefilter_f32_t: a step answered as by controller poles at
 * -ref_pole, disturbances by those at -ctl_pole), at rest at the measured
 * speed on each (re)start; the PID baseline and the redesign take omega*
 * unfiltered.
 *
 * Delay: the block models exactly one period between the computation and
 * the start of the hold (voltage computed at t_k held over (t_k + Ts,
 * t_k + 2 Ts]), which is the HAL's sample-to-apply delay d = 1.5 (centre
 * sampling, duties of the next period: the host bench). d = 1.0 (the
 * configuration check's nominal, or a HAL that applies within the period)
 * is half a period early against that model; d > 1.75 is rejected (an
 * unmodelled extra period).
 *
 * Design and redesign (the model frequencies follow |omega*|): the design
 * (double, about 85k multiply-adds for the largest model set, 21 KB of
 * stack) runs at init for design_speed_rad_s (the bench's 500 rpm). The
 * application offers no context below the fast ISR (its slow loop is a
 * decimated part of the ISR, mc/app.h), so by default (redesign_rel_tol =
 * 0) the design stays fixed: a reference away from design_speed_rad_s
 * detunes the harmonic models (1 % detuning leaves about 15 % of a
 * harmonic, mc/cdobc.h). redesign_rel_tol > 0 redesigns on the slow tick
 * whenever mc_cdobc_needs_redesign_f32 says so, inside the ISR: a few ms
 * of soft double on a Cortex-M4F, far beyond a 100 us period, so for the
 * host bench only. The MCU plan: a background task that designs into the
 * spare half of a double-buffered coefficient set and a flag the ISR
 * polls to swap (mc_cdobc_set_coef_f32, about n^2 + 4 n words).
 * Interface: mc/drive.h.
 */
#ifndef MC_CTL_CDOBC_H
#define MC_CTL_CDOBC_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/cdobc.h"
#include "mc/circle_limit.h"
#include "mc/compiler.h"
#include "mc/drive.h"
#include "mc/estimator.h"
#include "mc/faults.h"
#include "mc/params.h"
#include "mc/timing.h"

#define MC_CTL_CDOBC_COUNT_MAX 8u /* periods of the count speed */

typedef struct {
    uint32_t poly_order;      /* N of the polynomial model, 0 .. 3 (2) */
    bool dead_time_model;     /* 6th electrical harmonic (true) */
    uint32_t cogging_order;   /* Q-th mechanical harmonic, 0 = none (32) */
    bool sensor_offset_model; /* 1st electrical harmonic (false) */
    bool sensor_gain_model;   /* 2nd electrical harmonic (false) */
    bool robust_placement;    /* harmonic observer pairs at their
                                 frequency (true) or all at -obs_pole
                                 (false: the paper's literal design) */
    float harm_zeta;          /* robust: damping of those pairs (0.03) */
    float sensor_zeta;        /* robust: damping of the 1st and 2nd
                                 electrical pairs (0.5) */
    float ctl_pole_rad_s;     /* controller poles at -this (200) */
    float ref_pole_rad_s;     /* > 0: the reference prefilter's double
                                 pole at -this (mc_cdobc_prefilter_f32_t);
                                 0: none (0, the paper's law) */
    float obs_pole_rad_s;     /* observer poles at -this (520) */
    float kp_d_V_A;           /* d-axis PI (120) */
    float ki_d_V_As;          /* (240) */
    float v_max_V;            /* |v_q|, |v_d| limit before the circle (200) */
    float omega_min_rad_s;    /* floor of |omega*| for the frequencies (10) */
    float design_speed_rad_s; /* |omega*| of the init design (500 rpm) */
    float redesign_rel_tol;   /* > 0: redesign in the ISR's slow tick when
                                 |omega*| moves by more (host only); 0 */
    bool pid;                 /* the noncascade PID baseline instead */
    float pid_kp_V_s;         /* V per rad/s (23) */
    float pid_ki_V;           /* V per rad (10) */
    float pid_kd_V_s2;        /* V s^2 / rad (0.0167) */
    bool pid_feedforward;     /* add the (6) back-EMF term (false) */
    uint32_t count_periods;   /* observer speed from the encoder count
                                 over this many periods, 1 .. 8 (4);
                                 0: the estimator's speed */
} mc_ctl_cdobc_config_t;

typedef struct {
    mc_cdobc_f32_t law;     /* observer regulator (its d-axis PI also
                               serves the PID variant) */
    mc_cdobc_pid_f32_t pid; /* baseline */
    mc_cdobc_params_t p;    /* for the redesign */
    mc_cdobc_prefilter_f32_t prefilter; /* of omega* (use_prefilter) */
    bool use_prefilter;
    bool use_pid;
    bool restart;        /* reset at the next step */
    float redesign_tol;  /* 0: fixed design */
    float u_c_prev_V;    /* (6) coupling term of the last step */
    float v_dc_prev_V;   /* bus of the last step */
    uint32_t cpr;        /* counts per turn of the count speed, 0: none */
    int32_t half_cpr;    /* cpr / 2 */
    uint32_t n_count;    /* periods of the count speed */
    float count_rad_s;   /* 2 pi / (cpr n_count Ts): one count */
    float rad_per_count; /* 2 pi / cpr */
    float window_s;      /* n_count Ts */
    uint32_t count_last; /* count of the last step */
    /* the last n_count steps of the count, each wrapped to [-cpr/2,
     * cpr/2), in a ring (next: the oldest), and their sum; beside each
     * step the edge age of its sample (t->encoder_edge_age_s) */
    int32_t count_steps[MC_CTL_CDOBC_COUNT_MAX];
    float edge_ages_s[MC_CTL_CDOBC_COUNT_MAX];
    uint32_t count_next;
    uint32_t count_valid; /* steps in the ring since the start */
    int32_t count_sum;
} mc_ctl_cdobc_t;

MC_CONTROLLER_INTERFACE(cdobc);

/* Redesign for |omega*| (slow tick, redesign_rel_tol > 0). A failed
 * design (e.g. a model frequency beyond a quarter of the sampling rate)
 * keeps the coefficients in use. Interrupt context: yes, but unbounded
 * against the period on an MCU (see above). */
void mc_ctl_cdobc_redesign(mc_ctl_cdobc_t *ctl, float omega_ref_rad_s);

/* The speed of the count's last n_count steps (count_sum): with the
 * edge ages of their first and last samples (both >= 0: the HAL keeps
 * edge times) the counts over the time between the edges before those
 * samples (M/T: n_count Ts + age_old - age, > 0 whenever the count
 * moved), else over n_count Ts, quantised to count_rad_s. No motion
 * over the window is 0 either way. Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_ctl_cdobc_count_speed(const mc_ctl_cdobc_t *ctl,
                                                     float age_old_s,
                                                     float age_s)
{
    const float dt_s = ctl->window_s + age_old_s - age_s;
    if (ctl->count_sum != 0 && age_old_s >= 0.0f && age_s >= 0.0f &&
        dt_s > 0.0f) {
        return (float)ctl->count_sum * ctl->rad_per_count / dt_s;
    }
    return (float)ctl->count_sum * ctl->count_rad_s;
}

/* The observer's speed of this sample (ctl->restart: the window starts
 * here): the count difference over the last n_count periods
 * (mc_ctl_cdobc_count_speed), t->omega_m_rad_s until there are n_count
 * steps since the start or without a count. The periods' wrapped steps
 * are kept as a running sum (integers: exact, the same as summing them
 * anew; |sum| < 2^26), each beside its sample's edge age. Interrupt
 * context: yes. */
MC_STATIC_FORCEINLINE float mc_ctl_cdobc_observer_speed(mc_ctl_cdobc_t *ctl,
                                                        const mc_telemetry_t *t)
{
    float w_obs = t->omega_m_rad_s;
    if (ctl->cpr == 0u) {
        return w_obs;
    }
    const uint32_t n = ctl->n_count;
    const uint32_t c = t->encoder_count;
    if (ctl->restart) {
        /* the ages too: the window's first sample is this one (its age
         * is read with the n-th step) */
        for (uint32_t i = 0u; i < n; ++i) {
            ctl->count_steps[i] = 0;
            ctl->edge_ages_s[i] = t->encoder_edge_age_s;
        }
        ctl->count_next = 0u;
        ctl->count_valid = 0u;
        ctl->count_sum = 0;
    } else {
        const int32_t half = ctl->half_cpr;
        int32_t s = (int32_t)c - (int32_t)ctl->count_last;
        if (s >= half) {
            s -= (int32_t)ctl->cpr;
        } else if (s < -half) {
            s += (int32_t)ctl->cpr;
        }
        const uint32_t i = ctl->count_next;
        ctl->count_sum += s - ctl->count_steps[i];
        ctl->count_steps[i] = s;
        const float age_old_s = ctl->edge_ages_s[i]; /* n_count ago */
        const float age_s = t->encoder_edge_age_s;
        ctl->edge_ages_s[i] = age_s;
        ctl->count_next = (i + 1u == n) ? 0u : i + 1u;
        if (ctl->count_valid < n) {
            ctl->count_valid++;
        }
        if (ctl->count_valid == n) {
            w_obs = mc_ctl_cdobc_count_speed(ctl, age_old_s, age_s);
        }
    }
    ctl->count_last = c;
    return w_obs;
}

/* Speed / position mode: v_d, v_q into *t. Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_cdobc_voltages(mc_ctl_cdobc_t *ctl,
                                                     mc_drive_t *d,
                                                     const mc_command_t *cmd,
                                                     mc_telemetry_t *t)
{
    mc_outer_loop_f32_t *o = &d->outer;
    const bool tick = mc_outer_loop_speed_f32(o, cmd, t);
    mc_outer_loop_publish_f32(o, t);
    t->i_d_ref_A = 0.0f; /* no current loop */
    t->i_q_ref_A = 0.0f;
    const float w = t->omega_m_rad_s;
    const float w_ref = o->omega_m_ref_rad_s;
    const float w_obs = mc_ctl_cdobc_observer_speed(ctl, t);
    if (ctl->restart) {
        if (mc_cdobc_reset_f32(&ctl->law, w) != MC_OK ||
            mc_cdobc_pid_reset_f32(&ctl->pid, w) != MC_OK) {
            return MC_FAULT_NONFINITE;
        }
        /* the reference's change from the measured speed on is filtered */
        mc_cdobc_prefilter_reset_f32(&ctl->prefilter, w);
        ctl->u_c_prev_V = 0.0f;
        ctl->restart = false;
    }
    /* the voltage applied over the current period: the last command after
     * the current limit and the modulator's circle */
    float v_d = d->v_d_last_V;
    float v_q = d->v_q_last_V;
    const float r_prev = ctl->v_dc_prev_V * 0.57735027f;
    if (r_prev > 0.0f) {
        (void)mc_circle_limit_f32(&v_d, &v_q, r_prev);
    }
    ctl->law.v_cur = v_q - ctl->u_c_prev_V;
    if (tick && ctl->redesign_tol > 0.0f &&
        mc_cdobc_needs_redesign_f32(&ctl->law, w_ref, ctl->redesign_tol)) {
        mc_ctl_cdobc_redesign(ctl, w_ref);
    }
    mc_cdobc_out_t out;
    if (ctl->use_pid) {
        if (mc_cdobc_pid_step_f32(&ctl->pid, w, w_ref, &out.v_q_V) != MC_OK) {
            return MC_FAULT_NONFINITE;
        }
        /* unchecked: a non-finite i_d gives a NaN v_d (mc/pi.h), which
         * the circle limit keeps and the output check catches; the
         * restart resets the integrator */
        out.v_d_V = mc_pi_step_unchecked_f32(&ctl->law.pi_d, -t->i_d_A);
        out.q_limited =
            !(out.v_q_V < ctl->law.v_max_V) || !(out.v_q_V > -ctl->law.v_max_V);
        out.d_limited = false;
        ctl->u_c_prev_V = 0.0f;
    } else {
        /* the step inline (d_hat not needed); nothing changes on a
         * non-finite input or result */
        const float w_ref_law =
            ctl->use_prefilter
                ? mc_cdobc_prefilter_step_f32(&ctl->prefilter, w_ref)
                : w_ref;
        if (!mc_cdobc_step_core_f32(&ctl->law, w_obs, w_ref_law, t->i_d_A,
                                    &out)) {
            return MC_FAULT_NONFINITE;
        }
        ctl->u_c_prev_V = out.v_q_V - ctl->law.v_cur;
    }
    const float v_dc = (t->v_dc_V > 0.0f) ? t->v_dc_V : 0.0f;
    ctl->v_dc_prev_V = v_dc;
    bool circle = false;
    if (v_dc > 0.0f) {
        circle =
            mc_circle_limit_f32(&out.v_d_V, &out.v_q_V, v_dc * 0.57735027f);
    }
    t->v_d_V = out.v_d_V;
    t->v_q_V = out.v_q_V;
    t->v_saturated = out.q_limited || out.d_limited || circle;
    return MC_FAULT_NONE;
}

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_cdobc_step(mc_ctl_cdobc_t *ctl,
                                                 mc_drive_t *d,
                                                 const mc_command_t *cmd,
                                                 mc_telemetry_t *t)
{
    if (cmd->mode == MC_MODE_CURRENT) {
        mc_outer_loop_f32_t *o = &d->outer;
        mc_outer_loop_current_f32(o, cmd);
        mc_outer_loop_publish_f32(o, t);
        mc_drive_current_step(d, t);
        return MC_FAULT_NONE;
    }
    return mc_ctl_cdobc_voltages(ctl, d, cmd, t);
}

#endif /* MC_CTL_CDOBC_H */
