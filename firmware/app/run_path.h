/*
 * The RUN sample of the control path (mode change; the controller, the
 * current limit, the modulator, the output checks) and the modulator and
 * output check it shares with the ALIGN sample (control_path.c): inline
 * into the fast ISR, no call on its path. Private to firmware/app.
 */
#ifndef MC_APP_RUN_PATH_H
#define MC_APP_RUN_PATH_H

#include <math.h>

#include "app_internal.h"
#include "dispatch.h"
#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/finite.h"
#include "mc/park.h"
#include "mc/svpwm.h"

/* v_d_V, v_q_V (as in *t, or limited) -> duties: inverse Park at the
 * voltage angle (advanced by the delay compensation, mc/delay_comp.h, its
 * advance updated from this sample's speed estimate if track_advance),
 * SVPWM with the circle limit, the dead-time compensation, on the bus
 * fr->v_dc_V the sample check has found positive and normal
 * (mc_app_t.protection_powered). The duties and the alpha/beta voltage the
 * inverter will apply into *t and *out. The modulator runs unchecked: a
 * non-finite voltage gives non-finite duties (mc_app_check_outputs).
 * Returns true if the command was strictly inside the linear range
 * (mc_svpwm_unchecked_f32): then v_alpha, v_beta are finite, so are v_d, v_q
 * (the inverse Park of a non-finite v_d or v_q by a finite sine and cosine is
 * not finite: a product with Inf or NaN is Inf or NaN, 0 x Inf NaN) and the
 * duties (the dead-time compensation of finite duties by the checked currents).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_app_modulate(mc_app_t *app, const mc_frame_t *fr,
                                           float v_d_V, float v_q_V,
                                           bool track_advance,
                                           mc_telemetry_t *t, mc_app_out_t *out)
{
    if (track_advance) {
        mc_delay_comp_track_f32(&app->delay_comp,
                                app->drive.n_p * t->omega_m_rad_s);
    }
    float s;
    float c;
    mc_delay_comp_sincos_f32(&app->delay_comp, fr->sc.sin_e, fr->sc.cos_e, &s,
                             &c);
    float v_al;
    float v_be;
    mc_inv_park_f32(v_d_V, v_q_V, s, c, &v_al, &v_be);
    mc_svpwm_out_f32_t pwm;
    const bool linear = mc_svpwm_unchecked_f32(v_al, v_be, fr->v_dc_V,
                                               MC_SVPWM_LIMIT_CIRCLE, &pwm);
    out->v_alpha_V = pwm.v_alpha_V;
    out->v_beta_V = pwm.v_beta_V;
    t->v_alpha_V = pwm.v_alpha_V;
    t->v_beta_V = pwm.v_beta_V;
    /* the inverter's dead time and drops: the duties deliver the command
     * on average (mc/deadtime_comp.h) */
    const bool limited = mc_deadtime_comp_apply_f32(
        &app->drive.deadtime, t->i_abc_A, fr->v_dc_V, pwm.duty);
    for (uint32_t k = 0u; k < 3u; ++k) {
        out->duty[k] = pwm.duty[k];
        t->duty_abc[k] = pwm.duty[k];
    }
    if (pwm.overmodulated || limited) { /* else the controller's flag */
        t->v_saturated = true;
    }
    return linear;
}

/* Non-finite anywhere in references or outputs is a fault. (The measured
 * i_d, i_q need no test: the Park transform of a sample that passed the
 * sample check, |i| <= i_trip, with an estimator's finite sine and
 * cosine, mc/estimator.h; a sample or estimate that failed stops RUN
 * and ALIGN before this.) linear: mc_app_modulate returned true, which
 * proves the voltages and the duties finite: only the references are
 * tested (a controller may limit a NaN reference away). Interrupt
 * context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_app_check_outputs(const mc_telemetry_t *t,
                                                    bool linear)
{
    const float refs[] = { t->i_d_ref_A, t->i_q_ref_A, t->omega_m_ref_rad_s };
    if (!mc_all_finite_f32(refs, (uint32_t)(sizeof refs / sizeof refs[0]))) {
        return MC_FAULT_NONFINITE;
    }
    if (linear) {
        return MC_FAULT_NONE;
    }
    const float outs[] = { t->v_d_V, t->v_q_V, t->duty_abc[0], t->duty_abc[1],
                           t->duty_abc[2] };
    return mc_all_finite_f32(outs, (uint32_t)(sizeof outs / sizeof outs[0]))
               ? MC_FAULT_NONE
               : MC_FAULT_NONFINITE;
}

/* The command's mode differs from the last RUN ISR's: the controller's
 * bumpless transfer, and this ISR ticks for the slow loop (the next tick
 * N ISRs on). Interrupt context: yes. */
static inline void mc_app_change_mode(mc_app_t *app, const mc_command_t *cmd,
                                      const mc_telemetry_t *t)
{
    app->drive.outer.tick = true;
    app->slow_left = app->timing.slow_decimation - 1u;
    mc_dispatch_controller_mode_change(app, app->mode, cmd->mode, t);
    app->mode = cmd->mode;
}

/* One RUN sample of the control path in the command's mode (after
 * mc_app_change_mode): the controller, the modulator, the output checks;
 * check_position_ref: also the command's position reference in
 * MC_MODE_POSITION (a steady ISR's is finite: mc_app_run_key). Fault
 * bits. Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t
mc_app_run(mc_app_t *app, const mc_command_t *cmd, const mc_frame_t *fr,
           mc_telemetry_t *t, bool check_position_ref, mc_app_out_t *out)
{
    t->theta_m_ref_rad = cmd->theta_m_ref_rad;
    /* read before the controller's stores: a steady ISR's constant */
    const bool slow_tick = app->drive.outer.tick;
    /* The bus of every voltage computation of the sample passed this
     * ISR's sample check (mc_app_t.protection_powered): positive and
     * normal. */
    uint32_t faults = mc_dispatch_controller_step(app, cmd, t);
    /* Every controller's voltage under the measured-current limit. */
    float v_d = t->v_d_V;
    float v_q = t->v_q_V;
    t->current_limited = mc_current_limit_step_f32(&app->drive.limit, t->i_d_A,
                                                   t->i_q_A, &v_d, &v_q);
    if (t->current_limited) {
        t->v_d_V = v_d;
        t->v_q_V = v_q;
    }
    app->drive.v_d_last_V = v_d;
    app->drive.v_q_last_V = v_q;
    bool linear = false;
    if (faults == MC_FAULT_NONE) {
        /* the advance: on the slow tick (mc/delay_comp.h) */
        linear = mc_app_modulate(app, fr, v_d, v_q, slow_tick, t, out);
    }
    faults |= mc_app_check_outputs(t, linear);
    if (check_position_ref && mc_app_position_ref_nonfinite(cmd)) {
        faults |= MC_FAULT_NONFINITE;
    }
    return faults;
}

#endif /* MC_APP_RUN_PATH_H */
