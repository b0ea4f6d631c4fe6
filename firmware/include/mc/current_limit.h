/*
 * Current-limit loop on the MEASURED current, for every controller: a
 * voltage controller (IDA-PBC, paper 001 (11)) has no current reference a
 * clamp could limit, so the drive corrects its voltage command instead.
 *
 * With i the measured current vector (controller frame), |i| above
 * limit_A, the command is pulled back along the current's direction:
 *   e = |i| - limit,  u = kp e + u_I,  u_I += ki Ts e  (u_I >= 0),
 *   v_dq <- v_dq - u i / |i|
 * Along i the machine is L di/dt = v - R i - (back-EMF): with kp = L w_c,
 * ki = R w_c (the current loop's pole-zero cancellation, mc/current_loop.h)
 * the loop (kp + ki/s)/(L s + R) = w_c / s holds |i| at the limit with the
 * current loop's bandwidth whatever the controller commands; below the
 * limit u_I winds back to 0 (with the same gain) and the command passes
 * unchanged. The controller is not told: a sustained limit is a fault
 * (MC_FAULT_CURRENT_LIMIT, mc/supervisor.h).
 *
 * Units: A, V, ohm, H, rad/s, s.
 */
#ifndef MC_CURRENT_LIMIT_H
#define MC_CURRENT_LIMIT_H

#include <stdbool.h>

#include "mc/compiler.h"
#include "mc/status.h"

typedef struct {
    float limit_A;         /* |i| above which the loop acts, > 0 */
    float R_ohm, L_H;      /* nominal motor: R >= 0, L > 0 */
    float bandwidth_rad_s; /* w_c, w_c Ts <= 0.5 */
    float Ts_s;            /* sample period, > 0 */
} mc_current_limit_params_t;

typedef struct {
    float limit_A, limit_sq_A2;
    float kp_V_per_A, ki_Ts_V_per_A;
    float u_int_V; /* integral part, >= 0 */
} mc_current_limit_f32_t;

/* Validate, design and reset. MC_ERR_NONFINITE / MC_ERR_PARAM (*cl
 * untouched). Interrupt context: no. */
mc_status_t mc_current_limit_init_f32(mc_current_limit_f32_t *cl,
                                      const mc_current_limit_params_t *p);

/* Integral part to zero. Interrupt context: yes. */
static inline void mc_current_limit_reset_f32(mc_current_limit_f32_t *cl)
{
    cl->u_int_V = 0.0f;
}

/* The loop is acting (its integral is wound up: a controller asking for
 * more than the limit). Interrupt context: yes. */
static inline bool mc_current_limit_active_f32(const mc_current_limit_f32_t *cl)
{
    return cl->u_int_V > 0.0f;
}

/* The part of mc_current_limit_step_f32 that runs only above the limit or
 * while the integral winds back, given |i_dq|^2 = i_sq_A2 of the sample.
 * Interrupt context: yes. */
bool mc_current_limit_act_f32(mc_current_limit_f32_t *cl, float i_sq_A2,
                              float i_d_A, float i_q_A, float *v_d_V,
                              float *v_q_V);

/* One sample: the measured currents (A) and the controller's command
 * *v_d_V, *v_q_V (V), corrected in place when the loop acts. Returns true
 * while it acts. Bounded: one square root only above the limit or while
 * the integral winds back. Non-finite inputs propagate into the command.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_current_limit_step_f32(mc_current_limit_f32_t *cl,
                                                     float i_d_A, float i_q_A,
                                                     float *v_d_V, float *v_q_V)
{
    const float i_sq = i_d_A * i_d_A + i_q_A * i_q_A;
    if (MC_LIKELY(i_sq <= cl->limit_sq_A2 && cl->u_int_V == 0.0f)) {
        return false; /* the common case: no square root (a NaN current
                         goes on and propagates into the command) */
    }
    /* through locals: the caller's voltages stay in registers on the
     * common path (their address is not taken) */
    float v_d = *v_d_V;
    float v_q = *v_q_V;
    const bool acted =
        mc_current_limit_act_f32(cl, i_sq, i_d_A, i_q_A, &v_d, &v_q);
    *v_d_V = v_d;
    *v_q_V = v_q;
    return acted;
}

#endif /* MC_CURRENT_LIMIT_H */
