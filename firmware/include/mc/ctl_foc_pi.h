/*
 * Controller "foc_pi": the baseline cascaded FOC. Current mode: the d/q
 * current loop (mc/current_loop.h) on the commanded currents; speed and
 * position modes: the setpoint stage (mc/outer_loop.h) and a speed PI
 * (mc/speed_loop.h) on the slow tick give i_q_ref for the current loop.
 * Works with any estimator; with the flux observer + PLL it is the "NAM"
 * baseline of paper 001 (Fig. 11).
 * Interface: mc/drive.h.
 */
#ifndef MC_CTL_FOC_PI_H
#define MC_CTL_FOC_PI_H

#include <stdint.h>

#include "mc/compiler.h"
#include "mc/drive.h"
#include "mc/estimator.h"
#include "mc/params.h"
#include "mc/speed_loop.h"
#include "mc/timing.h"

typedef struct {
    float speed_bandwidth_rad_s; /* w_s of the speed PI: <= 0.2 x the
                                    current-loop bandwidth, <= half the
                                    estimator's speed bandwidth, >= the
                                    position gain, w_s Ts_slow <= 0.2 */
} mc_ctl_foc_pi_config_t;

typedef struct {
    mc_speed_loop_f32_t speed;
} mc_ctl_foc_pi_t;

MC_CONTROLLER_INTERFACE(foc_pi);

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_foc_pi_step(mc_ctl_foc_pi_t *ctl,
                                                  mc_drive_t *d,
                                                  const mc_command_t *cmd,
                                                  mc_telemetry_t *t)
{
    mc_outer_loop_f32_t *o = &d->outer;
    if (cmd->mode == MC_MODE_CURRENT) {
        mc_outer_loop_current_f32(o, cmd);
    } else if (mc_outer_loop_speed_f32(o, cmd, t)) {
        o->i_q_ref_A = mc_speed_loop_step_f32(&ctl->speed, o->omega_m_ref_rad_s,
                                              t->omega_m_rad_s);
    }
    mc_outer_loop_publish_f32(o, t);
    mc_drive_current_step(d, t);
    return MC_FAULT_NONE;
}

#endif /* MC_CTL_FOC_PI_H */
