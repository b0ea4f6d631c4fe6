/* Private helpers shared by the files of firmware/app. */
#ifndef MC_APP_INTERNAL_H
#define MC_APP_INTERNAL_H

#include <math.h>
#include <stdatomic.h>

#include "mc/app.h"
#include "mc/compiler.h"

/* The sample of this ISR as the estimators and the control path see it
 * (Clarke once per ISR) and sin / cos of the controller's angle (from the
 * estimator). */
typedef struct {
    mc_est_input_t in;
    mc_est_sincos_t sc;
    float v_dc_V; /* the bus (as t->v_dc_V; positive and normal where a
                     voltage is computed: mc_app_t.protection_powered) */
} mc_frame_t;

/* The modulator's outputs as the write phase of the fast ISR takes them:
 * in registers on a steady ISR's path (their copies in the telemetry
 * record are for its reader). */
typedef struct {
    float duty[3];             /* for the HAL */
    float v_alpha_V, v_beta_V; /* for the applied-voltage record */
} mc_app_out_t;

/* Design every block of *app from cfg with the timing *tm (no HAL call):
 * the estimator, the controller, the shared blocks, and the ALIGN
 * sequence for a sensorless estimator. Status of the first block that
 * rejects its parameters. Used by mc_app_init and, on a scratch instance,
 * by mc_config_validate. Interrupt context: no. */
mc_status_t mc_app_configure(mc_app_t *app, const mc_config_t *cfg,
                             const mc_timing_t *tm);

/* The slot of cmd_buf (and cmd_run_key) mc_app_set_command completed last
 * (the writer runs in thread context, which the ISR preempts: the slot
 * does not change while the ISR runs). Interrupt context: yes. */
static inline uint32_t mc_app_command_slot(const mc_app_t *app)
{
    return app->cmd_index & 1u;
}

/* The command of this ISR: that slot's buffer. Interrupt context: yes. */
static inline const mc_command_t *mc_app_command(const mc_app_t *app)
{
    return &app->cmd_buf[mc_app_command_slot(app)];
}

/* The command's position reference is not finite in MC_MODE_POSITION
 * (the mode that uses it): a fault (mc_app_run) and a bit of the run key
 * (mc_app_run_key). Interrupt context: yes. */
static inline bool mc_app_position_ref_nonfinite(const mc_command_t *cmd)
{
    return cmd->mode == MC_MODE_POSITION && !isfinite(cmd->theta_m_ref_rad);
}

/* A command's enable, communication loss, clear request, a non-finite
 * position reference in MC_MODE_POSITION (ref_nonfinite) and mode in one
 * word, so the fast ISR tests them in one comparison: a steady ISR
 * (mc_app_fast_isr) continues a command with the same clear request as
 * the general ISR before it (which took its edge) and a finite position
 * reference (the general ISR's mc_app_run reports one that is not). No
 * command's is MC_APP_NO_RUN_KEY (bits 4 to 7 are 0). Interrupt context:
 * yes. */
static inline uint32_t mc_app_run_key(bool enable, bool comm_lost,
                                      bool clear_fault, bool ref_nonfinite,
                                      mc_mode_t mode)
{
    return (uint32_t)enable | ((uint32_t)comm_lost << 1u) |
           ((uint32_t)clear_fault << 2u) | ((uint32_t)ref_nonfinite << 3u) |
           ((uint32_t)mode << 8u);
}

/* Writing the telemetry record in place: begin makes the sequence counter
 * odd and returns the record, end makes it even again (the reader's side:
 * mc_app_get_telemetry). Used by init and by the fast ISR. Interrupt
 * context: yes. */
MC_STATIC_FORCEINLINE mc_telemetry_t *mc_app_tlm_begin(mc_app_t *app)
{
    app->tlm_seq = app->tlm_seq + 1u; /* odd: writing */
    atomic_signal_fence(memory_order_seq_cst);
    return &app->tlm;
}

MC_STATIC_FORCEINLINE void mc_app_tlm_end(mc_app_t *app)
{
    atomic_signal_fence(memory_order_seq_cst);
    app->tlm_seq = app->tlm_seq + 1u; /* even: complete */
}

/* RUN begins (after the calibration, or after ALIGN): the controller and
 * the shared blocks start from zero. Interrupt context: yes. */
void mc_app_start_run(mc_app_t *app);

/* ALIGN begins: the estimator holds at the alignment angle. Interrupt
 * context: yes. */
void mc_app_start_align(mc_app_t *app);

/* One ALIGN sample (mc/align.h) through the current loop and the
 * modulator; once settled the estimator starts at the alignment angle and
 * RUN begins; a settle timeout is MC_FAULT_ESTIMATE. Fault bits.
 * Interrupt context: yes. */
uint32_t mc_app_align(mc_app_t *app, const mc_frame_t *fr, mc_telemetry_t *t);

#endif /* MC_APP_INTERNAL_H */
