/*
 * The setpoint stage shared by the controllers: what each control mode
 * asks of the inner control law this ISR.
 *
 *   current mode   i_d_ref, i_q_ref from the command, limited to
 *                  |i_dq_ref| <= i_max (mc_circle_limit_f32; NaN stays
 *                  NaN, the application faults on it); omega_ref = 0.
 *   speed mode     omega_ref = the command limited to +-omega_max,
 *   position mode  omega_ref = the position P loop (mc/position_loop.h),
 *                  both on the slow tick (o->tick, set by the
 *                  application for each ISR, mc/app.h); i_d_ref = 0 (surface
 *                  PMSM: no reluctance torque). A speed controller then
 *                  sets i_q_ref (the baseline PI) or uses omega_ref
 *                  directly (IDA-PBC).
 * The references are held between slow ticks.
 *
 * Units: A, rad/s (mechanical), rad.
 */
#ifndef MC_OUTER_LOOP_H
#define MC_OUTER_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/circle_limit.h"
#include "mc/clamp.h"
#include "mc/compiler.h"
#include "mc/drive_io.h"
#include "mc/position_loop.h"
#include "mc/status.h"

typedef struct {
    float position_kp_per_s; /* P gain of the position loop, > 0 */
    float omega_max_rad_s;   /* speed reference limit, > 0 */
    float i_max_A;           /* current reference limit, > 0 */
} mc_outer_loop_params_t;

typedef struct {
    mc_position_loop_f32_t position;
    float omega_max_rad_s, i_max_A;
    bool tick; /* this call is a slow tick: the application's decimation
                  (mc/app.h), written before every call */
    float i_d_ref_A, i_q_ref_A, omega_m_ref_rad_s; /* held references */
} mc_outer_loop_f32_t;

/* Validate, store and reset. MC_ERR_NONFINITE / MC_ERR_PARAM (*o
 * untouched). Interrupt context: no. */
mc_status_t mc_outer_loop_init_f32(mc_outer_loop_f32_t *o,
                                   const mc_outer_loop_params_t *p);

/* References to zero (start of RUN). Interrupt context: yes. */
void mc_outer_loop_reset_f32(mc_outer_loop_f32_t *o);

/* Current mode: i_d_ref, i_q_ref from the command (limited to i_max),
 * omega_ref = 0. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_outer_loop_current_f32(mc_outer_loop_f32_t *o,
                                                     const mc_command_t *cmd)
{
    o->i_d_ref_A = cmd->i_d_ref_A;
    o->i_q_ref_A = cmd->i_q_ref_A;
    o->omega_m_ref_rad_s = 0.0f;
    /* |i_dq_ref| <= i_max (a documented limit; NaN stays NaN). */
    (void)mc_circle_limit_f32(&o->i_d_ref_A, &o->i_q_ref_A, o->i_max_A);
}

/* Speed / position mode: on a slow tick (o->tick; returns true, sets
 * t->slow_loop_ran) the speed reference from the command (position mode:
 * the position loop on t->theta_m_rad) and i_d_ref = 0; otherwise nothing
 * (false). Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_outer_loop_speed_f32(mc_outer_loop_f32_t *o,
                                                   const mc_command_t *cmd,
                                                   mc_telemetry_t *t)
{
    if (!o->tick) {
        return false;
    }
    t->slow_loop_ran = true;
    float w_ref;
    if (cmd->mode == MC_MODE_POSITION) {
        w_ref = mc_position_loop_step_f32(&o->position, cmd->theta_m_ref_rad,
                                          t->theta_m_rad);
    } else {
        const float w_max = o->omega_max_rad_s;
        w_ref = cmd->omega_m_ref_rad_s;
        w_ref = mc_clamp_sym_f32(w_ref, w_max);
    }
    o->omega_m_ref_rad_s = w_ref;
    o->i_d_ref_A = 0.0f; /* surface PMSM: no reluctance torque */
    return true;
}

/* The held references into the telemetry record. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void
mc_outer_loop_publish_f32(const mc_outer_loop_f32_t *o, mc_telemetry_t *t)
{
    t->i_d_ref_A = o->i_d_ref_A;
    t->i_q_ref_A = o->i_q_ref_A;
    t->omega_m_ref_rad_s = o->omega_m_ref_rad_s;
}

#endif /* MC_OUTER_LOOP_H */
