/* The starts of RUN and ALIGN and the ALIGN sample (see mc/app.h); the
 * RUN sample and the modulator are run_path.h. */
#include "app_internal.h"
#include "dispatch.h"
#include "run_path.h"

void mc_app_start_run(mc_app_t *app)
{
    mc_drive_t *d = &app->drive;
    mc_current_loop_reset_f32(&d->current);
    mc_outer_loop_reset_f32(&d->outer);
    mc_current_limit_reset_f32(&d->limit);
    d->v_d_last_V = 0.0f;
    d->v_q_last_V = 0.0f;
    mc_dispatch_controller_start(app);
    app->mode = mc_app_command(app)->mode;
    app->slow_left = 0u; /* the first RUN ISR ticks */
    app->state = MC_STATE_RUN;
}

void mc_app_start_align(mc_app_t *app)
{
    mc_current_loop_reset_f32(&app->drive.current);
    mc_align_reset_f32(&app->align);
    mc_dispatch_estimator_hold(app, app->cfg.align.angle_e_rad);
    app->state = MC_STATE_ALIGN;
}

/* One sample of the ALIGN sequence: the current references in the frame
 * of the ALIGN vector (the estimator reports its angle outside RUN) and
 * the sequence's state. */
static uint32_t align_references(mc_app_t *app, const mc_frame_t *fr,
                                 mc_telemetry_t *t, mc_align_state_t *state)
{
    float v_al;
    float v_be;
    mc_applied_voltage_last_f32(&app->v_applied, &v_al, &v_be);
    mc_align_out_t o;
    if (mc_align_step_f32(&app->align, fr->in.i_alpha_A, fr->in.i_beta_A, v_al,
                          v_be, &o) != MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    t->i_d_ref_A = o.i_d_ref_A;
    t->i_q_ref_A = o.i_q_ref_A;
    *state = o.state;
    return (o.state == MC_ALIGN_TIMEOUT) ? MC_FAULT_ESTIMATE : MC_FAULT_NONE;
}

uint32_t mc_app_align(mc_app_t *app, const mc_frame_t *fr, mc_telemetry_t *t)
{
    mc_align_state_t st = MC_ALIGN_BUSY;
    /* the bus: as in mc_app_run */
    uint32_t faults = align_references(app, fr, t, &st);
    bool linear = false;
    if (faults == MC_FAULT_NONE) {
        mc_drive_current_step(&app->drive, t);
        mc_app_out_t out; /* the ISR's write phase reads *t */
        linear = mc_app_modulate(app, fr, t->v_d_V, t->v_q_V, true, t, &out);
    }
    faults |= mc_app_check_outputs(t, linear);
    if (faults == MC_FAULT_NONE && st == MC_ALIGN_DONE) {
        faults = mc_dispatch_estimator_start(app, app->cfg.align.angle_e_rad,
                                             &fr->in);
        if (faults == MC_FAULT_NONE) {
            mc_app_start_run(app);
        }
    }
    return faults;
}
