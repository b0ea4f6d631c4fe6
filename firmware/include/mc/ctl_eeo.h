/*
 * Controller "eeo": the position regulator of paper 000 (mc/eeo.h:
 * internal model (7), saturated control (12), enhanced extended observer
 * (13)) fed by the encoder count only. It commands the voltage directly,
 * with no current loop: v_d = 0 and v_q from the regulator, rotated by the
 * application's inverse Park at the estimator's electrical angle
 * (n_p theta from the count, (4)-(6)). In current mode the d/q current
 * loop runs instead (bumpless both ways: the regulator restarts matched).
 *
 * Modes: position follows cmd->theta_m_ref_rad; speed integrates
 * cmd->omega_m_ref_rad_s (limited to +-omega_max) into the position
 * reference (the paper's regulator has no speed mode; its internal model
 * and sigma_hat absorb the ramp's error); current: the current loop.
 *
 * Position in fixed point: the measured position is the unwrapped
 * multi-turn count (mc_eeo_counts_*) in units of 2^-f count, taken at the
 * centre of the count's interval (count + 1/2: the encoder floors, as in
 * mc/encoder_tracker.h); f in 1..8 is the largest with cpr 2^f <= 2^24 (a
 * turn exact in float32). The reference is rounded once to the same
 * units; theta - theta* is formed in integers (mc_eeo_count_error) and
 * only the difference reaches float32. A difference beyond int32 units
 * (at least 128 turns) is MC_FAULT_ENCODER.
 *
 * Motor convention: the firmware's variables are three-phase
 * amplitude-invariant (torque 1.5 n_p psi i_q); paper 000 writes a
 * two-phase (power-invariant) model, torque n_p lambda_m i_q, whose
 * voltages are sqrt(3/2) times ours. The regulator runs in the paper's
 * variables so that its printed gains (b_bar = 20, K, N, kappa) stay
 * literal: its v_q is the paper's, the glue applies v_q sqrt(2/3) and
 * gives it the limit v_dc / sqrt(3) * sqrt(3/2) = v_dc / sqrt(2) (the
 * SVPWM circle, mc/svpwm.h, in the paper's units). b = lambda_m n_p / L
 * is then the paper's: with lambda_m = sqrt(3/2) psi, 24 N m/(V s) on the
 * Table 1 motor against b_bar = 20.
 *
 * Delay: the HAL's sample-to-apply delay d (mc/timing.h) puts the voltage
 * computed at t_k over [t_k + (d - 1/2) Ts, t_k + (d + 1/2) Ts]: d = 1.5
 * is one period beyond the regulator's nominal hold (input_delay_steps =
 * 1, exact); d = 1.0 is half a period either way (0 is used).
 *
 * Protection: the application's measured-current limit loop acts on this
 * controller's voltage like on any other (mc/current_limit.h): above
 * protection.current_limit_A the voltage is pulled back along the current
 * and |i| is held at that limit at the current loop's bandwidth; the
 * regulator is not told (its observer sees the difference as a
 * disturbance in sigma_hat), and a limit sustained for
 * current_limit_time_s latches MC_FAULT_CURRENT_LIMIT (mc/supervisor.h):
 * PWM off, the current decays through the diodes. The trip, stall and
 * every other check of mc/faults.h act unchanged.
 *
 * g3: the observer uses g3 = 1/J, or, when g3_amplitude_per_kgm2 is not
 * 0, the known schedule 1/J + A sin(Omega t + phase) of the paper's
 * simulation (t from the start of RUN; phase = Omega t at that start),
 * updated every period (mc_eeo_set_g3_f32).
 * Interface: mc/drive.h.
 */
#ifndef MC_CTL_EEO_H
#define MC_CTL_EEO_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "mc/angle.h"
#include "mc/clamp.h"
#include "mc/compiler.h"
#include "mc/drive.h"
#include "mc/eeo.h"
#include "mc/estimator.h"
#include "mc/faults.h"
#include "mc/params.h"
#include "mc/timing.h"

/* sqrt(2/3): the paper's (two-phase) voltage to the drive's */
#define MC_CTL_EEO_PAPER_TO_DRIVE 0.81649658f

typedef struct {
    float kappa;             /* high gain of (13), > 0 (paper: 1e3) */
    float b_bar_Nm_per_Vs;   /* b_bar of (12), paper units (20) */
    float k1, k2, k3;        /* K of (12) on xi1, xi2, xi3 (-1 -3 -3) */
    float N_V;               /* sat_N level of (12), paper units (1e7) */
    float g3_bound_per_kgm2; /* design bounds 1/J +- this, < 1/J (paper: 1e4; 0
                                = 0.5/J) */
    float g3_amplitude_per_kgm2; /* known g3 variation A (0: constant
                                    1/J); |A| <= g3_bound */
    float g3_omega_rad_s;        /* its Omega */
    float g3_phase_rad;          /* Omega t at the start of RUN */
    bool matched_start;          /* xi1_hat(0) = n_p theta_err(0) (true)
                                    or 0 (the paper's zero start) */
} mc_ctl_eeo_config_t;

typedef struct {
    mc_eeo_f32_t law;
    mc_eeo_counts_t pos; /* unwrapped count */
    uint32_t cpr;
    uint32_t units_per_count; /* 2^f: position units of 2^-f count */
    float units_per_rad;      /* cpr 2^f / (2 pi) */
    float counts_per_rad;     /* cpr / (2 pi) */
    int64_t ref_units;        /* theta* in units */
    float ref_rad;            /* the command ref_units was made from */
    float ref_frac_units;     /* speed mode: fraction not yet in ref */
    float omega_max_rad_s;    /* speed mode limit */
    float Ts_s;
    bool primed;       /* pos follows the count */
    bool restart;      /* reset the regulator at the next step */
    bool ref_from_pos; /* speed mode: start the reference at the
                          measured position */
    bool matched;
    float g3_nominal, g3_amp, g3_dphase, g3_phase0, g3_phase; /* known
                                                                 schedule */
} mc_ctl_eeo_t;

MC_CONTROLLER_INTERFACE(eeo);

/* The measured position in units of 2^-f count (centre of the count). */
MC_STATIC_FORCEINLINE int64_t mc_ctl_eeo_pos_units(const mc_ctl_eeo_t *ctl)
{
    /* count 2^f (modulo 2^64 like the shift; a multiply by 32 bits is
     * cheaper than a 64-bit shift by a variable) plus half a count */
    return (int64_t)((uint64_t)ctl->pos.pos_counts * ctl->units_per_count) +
           (int64_t)(ctl->units_per_count >> 1u);
}

/* Follow the count (every mode); the first call after start primes the
 * multi-turn position on the estimator's theta_m (the turn the count is
 * in). Fault bits. Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_eeo_track(mc_ctl_eeo_t *ctl,
                                                const mc_telemetry_t *t)
{
    const uint32_t raw = t->encoder_count;
    if (ctl->primed) {
        return (mc_eeo_counts_update(&ctl->pos, raw) == MC_OK)
                   ? MC_FAULT_NONE
                   : MC_FAULT_ENCODER;
    }
    if (mc_eeo_counts_init(&ctl->pos, ctl->cpr, raw) != MC_OK ||
        !isfinite(t->theta_m_rad)) {
        return MC_FAULT_ENCODER;
    }
    const float turns =
        (t->theta_m_rad * ctl->counts_per_rad - (float)raw) / (float)ctl->cpr;
    ctl->pos.pos_counts += (int64_t)lrintf(turns) * (int64_t)ctl->cpr;
    ctl->primed = true;
    return MC_FAULT_NONE;
}

/* Position / speed mode: the reference in units, theta - theta* in
 * integers, the regulator, v_q in the drive's units. Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_eeo_voltages(mc_ctl_eeo_t *ctl,
                                                   const mc_command_t *cmd,
                                                   mc_telemetry_t *t)
{
    if (cmd->mode == MC_MODE_POSITION) {
        if (cmd->theta_m_ref_rad != ctl->ref_rad) {
            const float r = cmd->theta_m_ref_rad;
            if (!isfinite(r)) {
                return MC_FAULT_NONFINITE;
            }
            ctl->ref_units = llrintf(r * ctl->units_per_rad);
            ctl->ref_rad = r;
        }
        t->omega_m_ref_rad_s = 0.0f;
    } else {
        if (ctl->ref_from_pos) {
            ctl->ref_units = mc_ctl_eeo_pos_units(ctl);
            ctl->ref_frac_units = 0.0f;
        }
        const float w_max = ctl->omega_max_rad_s;
        float w = cmd->omega_m_ref_rad_s;
        if (!isfinite(w)) {
            return MC_FAULT_NONFINITE;
        }
        w = mc_clamp_sym_f32(w, w_max);
        const float acc =
            ctl->ref_frac_units + w * ctl->Ts_s * ctl->units_per_rad;
        const float whole = rintf(acc);
        ctl->ref_units += (int64_t)whole;
        ctl->ref_frac_units = acc - whole;
        ctl->ref_rad = NAN; /* a later position command is taken anew */
        t->omega_m_ref_rad_s = w;
    }
    ctl->ref_from_pos = false;
    int32_t err;
    if (mc_eeo_count_error(mc_ctl_eeo_pos_units(ctl), ctl->ref_units, &err) !=
        MC_OK) {
        return MC_FAULT_ENCODER;
    }
    if (ctl->restart) {
        (void)mc_eeo_reset_f32(&ctl->law, err, ctl->matched);
        ctl->restart = false;
    }
    if (ctl->g3_amp != 0.0f) {
        float s;
        float c;
        /* the phase is kept wrapped to (-pi, pi] (below) */
        mc_sincos_in_range_f32(ctl->g3_phase, &s, &c);
        float g3 = ctl->g3_nominal + ctl->g3_amp * s;
        const float lo = ctl->law.g3_min_per_kgm2;
        const float hi = ctl->law.g3_max_per_kgm2;
        g3 = (g3 < lo) ? lo : ((g3 > hi) ? hi : g3);
        /* g3 in range: the unchecked core (its division's guard fails
         * for a NaN) */
        if (!mc_eeo_set_g3_core_f32(&ctl->law, g3)) {
            return MC_FAULT_NONFINITE;
        }
        /* inside (-pi, pi) mc_wrap_pi_f32 returns its argument (both
         * steps are within +-pi: the call only once per turn) */
        const float ph = ctl->g3_phase + ctl->g3_dphase;
        ctl->g3_phase = (fabsf(ph) < MC_PI_F) ? ph : mc_wrap_pi_f32(ph);
    }
    /* the drive's limit (SVPWM circle, v_d = 0) in the paper's units */
    const float v_dc = (t->v_dc_V > 0.0f) ? t->v_dc_V : 0.0f;
    ctl->law.v_q_max_V =
        v_dc * (1.0f / MC_CTL_EEO_PAPER_TO_DRIVE) * 0.57735027f;
    /* the step inline; nothing changes on a non-finite result */
    mc_eeo_out_t o;
    if (!mc_eeo_step_core_f32(&ctl->law, err, &o)) {
        return MC_FAULT_NONFINITE;
    }
    t->i_d_ref_A = 0.0f;
    t->i_q_ref_A = 0.0f;
    t->v_d_V = 0.0f;
    t->v_q_V = o.v_q_V * MC_CTL_EEO_PAPER_TO_DRIVE;
    t->v_saturated = o.v_limited;
    return MC_FAULT_NONE;
}

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_eeo_step(mc_ctl_eeo_t *ctl, mc_drive_t *d,
                                               const mc_command_t *cmd,
                                               mc_telemetry_t *t)
{
    const uint32_t f = mc_ctl_eeo_track(ctl, t);
    if (f != MC_FAULT_NONE) {
        return f;
    }
    if (cmd->mode == MC_MODE_CURRENT) {
        mc_outer_loop_f32_t *o = &d->outer;
        mc_outer_loop_current_f32(o, cmd);
        mc_outer_loop_publish_f32(o, t);
        mc_drive_current_step(d, t);
        return MC_FAULT_NONE;
    }
    return mc_ctl_eeo_voltages(ctl, cmd, t);
}

#endif /* MC_CTL_EEO_H */
