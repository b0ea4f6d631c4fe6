/*
 * Baseline d/q current loop: two PI regulators with decoupling feed-forward
 * and a circular voltage limit with anti-windup.
 *
 *   v_d = PI_d(i_d_ref - i_d) - omega_e * Lq * i_q
 *   v_q = PI_q(i_q_ref - i_q) + omega_e * (Ld * i_d + psi)
 *
 * Voltage limit: |v_dq| <= v_max = m * v_dc / sqrt(3), m = modulation margin
 * factor in (0, 1] (the SVPWM linear range is v_dc/sqrt(3)). The d axis has
 * priority: v_d is limited to [-v_max, v_max], then v_q to
 * +-sqrt(v_max^2 - v_d^2). Anti-windup: the PI output limits are set each
 * sample to the room left after the feed-forward, so each integrator stops
 * (clamps) exactly when its axis saturates.
 *
 * Gain design (pole-zero cancellation): the axis plant is 1/(L s + R); with
 * kp = L * w_c and ki = R * w_c the open loop is w_c / s and the closed loop
 * the first-order lag w_c / (s + w_c) (10-90 % rise time ln(9)/w_c), up to the
 * computation + PWM delay (at most 1.5 periods), which is negligible for
 * w_c * 1.5 * Ts << 1.
 *
 * Units: A, V, rad/s (electrical), H, ohm, Wb, s.
 */
#ifndef MC_CURRENT_LOOP_H
#define MC_CURRENT_LOOP_H

#include <math.h>
#include <stdbool.h>

#include "mc/clarke.h"
#include "mc/compiler.h"
#include "mc/pi.h"
#include "mc/status.h"

/* PI gains of one axis: u = kp * e + ki_per_s * integral(e dt). */
typedef struct {
    float kp_V_per_A;
    float ki_V_per_As;
} mc_current_pi_gains_t;

/* Design kp = L_H * w_c_rad_s, ki = R_ohm * w_c_rad_s (pole-zero
 * cancellation, first-order closed loop of bandwidth w_c).
 * Requires finite R_ohm >= 0, L_H > 0, w_c_rad_s > 0: MC_ERR_PARAM
 * otherwise (MC_ERR_NONFINITE for NaN/Inf). Interrupt context: no. */
mc_status_t mc_current_pi_design_f32(float R_ohm, float L_H, float w_c_rad_s,
                                     mc_current_pi_gains_t *out);

/* Smallest q-axis room, as a fraction of v_max, when the d axis takes the
 * whole voltage circle: keeps the q PI limits a proper interval
 * (out_min < out_max). The resulting |v_dq| exceeds v_max by at most
 * 5e-9 v_max (relative), far below float resolution of the duties. */
#define MC_CL_Q_ROOM_MIN 1.0e-4f

/* Largest w_c Ts: with up to 1.5 periods of computation + PWM delay the
 * phase margin is 90 deg - 1.5 w_c Ts rad >= 47 deg. */
#define MC_CURRENT_LOOP_WTS_MAX 0.5f

/* The tunable part (the configuration block "current"). */
typedef struct {
    float bandwidth_rad_s;   /* designed closed-loop bandwidth w_c, > 0,
                                w_c Ts <= MC_CURRENT_LOOP_WTS_MAX */
    float modulation_margin; /* m in (0, 1]: v_max = m * v_dc / sqrt(3) */
} mc_current_loop_config_t;

typedef struct {
    mc_current_loop_config_t cfg;
    float R_ohm;      /* nominal stator resistance */
    float Ld_H, Lq_H; /* nominal d/q inductances */
    float psi_Wb;     /* nominal PM flux linkage */
    float Ts_s;       /* sample period (PWM period) */
} mc_current_loop_params_t;

typedef struct {
    mc_pi_f32_t pi_d, pi_q;
    float Ld_H, Lq_H, psi_Wb;
    float v_max_per_V_dc; /* m / sqrt(3): the voltage limit per V of bus */
} mc_current_loop_f32_t;

/* Output of one step. */
typedef struct {
    float v_d_V, v_q_V; /* limited voltage references */
    bool saturated;     /* the voltage limit was active on either axis */
} mc_current_loop_out_t;

/* Validate the parameters, design the gains and reset the integrators.
 * MC_ERR_PARAM / MC_ERR_NONFINITE on invalid parameters (the instance is
 * then unusable). Interrupt context: no. */
mc_status_t mc_current_loop_init_f32(mc_current_loop_f32_t *cl,
                                     const mc_current_loop_params_t *p);

/* Zero both integrators. Interrupt context: yes. */
void mc_current_loop_reset_f32(mc_current_loop_f32_t *cl);

/* Bumpless take-over from another voltage source: set the integrators so
 * that a step with zero current error at these currents (A) and omega_e
 * (electrical rad/s) outputs (v_d_V, v_q_V), i.e. I_d = v_d - ff_d,
 * I_q = v_q - ff_q (the next step clamps them into its limits; non-finite
 * arguments make the next step's output non-finite: the caller's fault).
 * Interrupt context: yes. */
void mc_current_loop_preset_f32(mc_current_loop_f32_t *cl, float v_d_V,
                                float v_q_V, float i_d_A, float i_q_A,
                                float omega_e_rad_s);

/* Decoupling feed-forward (rotor-frame voltage equations):
 * ff_d = -omega_e Lq i_q, ff_q = omega_e (Ld i_d + psi).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE void
mc_current_loop_feed_forward_f32(const mc_current_loop_f32_t *cl, float i_d_A,
                                 float i_q_A, float omega_e_rad_s,
                                 float *ff_d_V, float *ff_q_V)
{
    *ff_d_V = -omega_e_rad_s * cl->Lq_H * i_q_A;
    *ff_q_V = omega_e_rad_s * (cl->Ld_H * i_d_A + cl->psi_Wb);
}

/* One axis: the PI output is limited to the room the feed-forward leaves
 * within +-v_lim_V (anti-windup, mc/pi.h); returns PI(error) + ff. *sat
 * tells that the PI sits on a limit. The limits are finite and ordered
 * whenever the inputs are finite (v_lim_V > 0); a non-finite input
 * reaches the result. Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_current_loop_axis_f32(mc_pi_f32_t *pi,
                                                     float v_lim_V, float ff_V,
                                                     float error_A, bool *sat)
{
    /* limits [-v_lim - ff, v_lim - ff]: centre -ff, half-width v_lim */
    return mc_pi_step_centred_unchecked_f32(pi, error_A, -ff_V, v_lim_V, sat) +
           ff_V;
}

/* One sample without checks, for an ISR path that checks v_dc_V before
 * (finite, > 0: the caller's precondition) and v_d, v_q after: currents
 * and references in A, omega_e in rad/s (electrical), v_dc in V. A NaN or
 * infinite current, reference or speed gives a non-finite v_d or v_q
 * (and may leave an integrator non-finite until the next reset).
 * Interrupt context: yes (bounded: one sqrtf). */
MC_STATIC_FORCEINLINE mc_current_loop_out_t mc_current_loop_step_unchecked_f32(
    mc_current_loop_f32_t *cl, float i_d_A, float i_q_A, float i_d_ref_A,
    float i_q_ref_A, float omega_e_rad_s, float v_dc_V)
{
    const float v_max = cl->v_max_per_V_dc * v_dc_V;
    float ff_d;
    float ff_q;
    mc_current_loop_feed_forward_f32(cl, i_d_A, i_q_A, omega_e_rad_s, &ff_d,
                                     &ff_q);
    mc_current_loop_out_t out;
    bool sat_d;
    bool sat_q;
    /* d axis first: the PI may use what the feed-forward leaves. */
    out.v_d_V = mc_current_loop_axis_f32(&cl->pi_d, v_max, ff_d,
                                         i_d_ref_A - i_d_A, &sat_d);
    /* q axis: the rest of the circle, at least room_min = MC_CL_Q_ROOM_MIN
     * v_max (sqrt guarded: its argument >= room_min^2 >= 0; a NaN room_sq
     * takes room_min). */
    const float v_max_sq = v_max * v_max;
    const float room_min_sq = (MC_CL_Q_ROOM_MIN * MC_CL_Q_ROOM_MIN) * v_max_sq;
    const float room_sq = v_max_sq - out.v_d_V * out.v_d_V;
    const float v_q_max =
        sqrtf((room_sq > room_min_sq) ? room_sq : room_min_sq);
    out.v_q_V = mc_current_loop_axis_f32(&cl->pi_q, v_q_max, ff_q,
                                         i_q_ref_A - i_q_A, &sat_q);
    out.saturated = sat_d || sat_q;
    return out;
}

/* One sample, checked: the same with v_dc_V checked (MC_ERR_NONFINITE,
 * MC_ERR_RANGE if not > 0: outputs zeroed, integrators untouched) and
 * MC_ERR_NONFINITE if an output is not finite (outputs zeroed). The caller
 * checks its inputs for finiteness. Interrupt context: yes (bounded: one
 * sqrtf). */
mc_status_t mc_current_loop_step_f32(mc_current_loop_f32_t *cl, float i_d_A,
                                     float i_q_A, float i_d_ref_A,
                                     float i_q_ref_A, float omega_e_rad_s,
                                     float v_dc_V, mc_current_loop_out_t *out);

#endif /* MC_CURRENT_LOOP_H */
