/*
 * The blocks every controller may use, owned by the application and handed
 * to the selected controller's glue (mc/controllers.h): the d/q current loop
 * (also used by the ALIGN start), the setpoint stage, the current-limit
 * loop the application applies after every controller, and the previous
 * RUN voltage (bumpless transfers).
 *
 * The interface every controller of the list implements, in its own glue
 * file (firmware/app/ctl_<name>.c):
 *   mc_ctl_<name>_config_default(cfg)   its configuration block
 *   mc_ctl_<name>_params[]              the block's parameter table
 *   mc_ctl_<name>_init(ctl, cfg, timing, estimator info)   design and check
 *                                       what it needs from the estimator
 *   mc_ctl_<name>_start(ctl)            RUN begins
 *   mc_ctl_<name>_mode_change(ctl, drive, from, to, t)     bumpless transfer
 *   mc_ctl_<name>_step(ctl, drive, cmd, t)  one RUN sample: v_d, v_q (and
 *                                       the references) into *t; fault bits
 * Interrupt context: start, mode_change and step yes; the others no.
 */
#ifndef MC_DRIVE_H
#define MC_DRIVE_H

#include <stdint.h>

#include "mc/compiler.h"
#include "mc/current_limit.h"
#include "mc/current_loop.h"
#include "mc/deadtime_comp.h"
#include "mc/drive_io.h"
#include "mc/estimator.h"
#include "mc/faults.h"
#include "mc/outer_loop.h"

typedef struct {
    mc_current_loop_f32_t current;   /* d/q PI + decoupling + voltage limit */
    mc_current_limit_f32_t limit;    /* on the measured current, after every
                                        controller (mc/current_limit.h) */
    mc_deadtime_comp_f32_t deadtime; /* on the duties (mc/deadtime_comp.h) */
    mc_outer_loop_f32_t outer;       /* setpoints of the control modes */
    float n_p;                       /* pole pairs */
    float v_d_last_V, v_q_last_V;    /* voltage of the previous RUN ISR */
} mc_drive_t;

/* The current loop on t's measured i_d, i_q and references i_d_ref,
 * i_q_ref at omega_e = n_p t->omega_m_rad_s and t->v_dc_V, which the
 * caller has checked (positive and normal): v_d, v_q, v_saturated into
 * *t. A non-finite current, reference or speed gives a non-finite v_d or
 * v_q, which the application's output check turns into
 * MC_FAULT_NONFINITE (it resets the current loop before the next use).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_drive_current_step(mc_drive_t *d,
                                                 mc_telemetry_t *t)
{
    const float v_dc = t->v_dc_V;
    const mc_current_loop_out_t v = mc_current_loop_step_unchecked_f32(
        &d->current, t->i_d_A, t->i_q_A, t->i_d_ref_A, t->i_q_ref_A,
        d->n_p * t->omega_m_rad_s, v_dc);
    t->v_d_V = v.v_d_V;
    t->v_q_V = v.v_q_V;
    t->v_saturated = v.saturated;
}

/* Hands the current loop over from a controller that commands the voltage
 * itself: its integrators restart at the drive's last voltage at t's
 * currents and speed, bumpless. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void
mc_drive_current_loop_takeover(mc_drive_t *d, const mc_telemetry_t *t)
{
    mc_current_loop_preset_f32(&d->current, d->v_d_last_V, d->v_q_last_V,
                               t->i_d_A, t->i_q_A, d->n_p * t->omega_m_rad_s);
}

/* Declares the interface above for controller `name`, after its
 * mc_ctl_<name>_config_t and mc_ctl_<name>_t: the parameter table and every
 * function but the step, which the glue header defines
 * MC_STATIC_FORCEINLINE (it runs in the ISR). One declaration for every
 * controller, so their signatures cannot drift apart. */
#define MC_CONTROLLER_INTERFACE(name)                                          \
    extern const mc_param_t mc_ctl_##name##_params[];                          \
    void mc_ctl_##name##_config_default(mc_ctl_##name##_config_t *c);          \
    mc_status_t mc_ctl_##name##_init(                                          \
        mc_ctl_##name##_t *ctl, const mc_config_t *cfg, const mc_timing_t *tm, \
        const mc_estimator_info_t *est);                                       \
    void mc_ctl_##name##_start(mc_ctl_##name##_t *ctl);                        \
    void mc_ctl_##name##_mode_change(mc_ctl_##name##_t *ctl, mc_drive_t *d,    \
                                     mc_mode_t from, mc_mode_t to,             \
                                     const mc_telemetry_t *t)

#endif /* MC_DRIVE_H */
