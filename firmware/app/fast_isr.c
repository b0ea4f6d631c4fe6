/* The fast ISR: sample, protect, estimate, control, write duties; the state
 * machine and fault latching (see mc/app.h). */
#include <math.h>

#include "app_internal.h"
#include "hal/adc.h"
#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"
#include "mc/angle.h"
#include "mc/circle_limit.h"
#include "mc/clarke.h"
#include "mc/park.h"
#include "mc/svpwm.h"

#define MC_DUTY_ZERO_VOLTAGE 0.5f

static void outputs_off(void)
{
    hal_pwm_disable_outputs();
    hal_gpio_power_stage_enable(false);
}

/* Latch faults; from any other state the PWM goes off right here. */
static void raise_faults(mc_app_t *app, uint32_t faults)
{
    if (faults == MC_FAULT_NONE) {
        return;
    }
    app->faults_latched |= faults;
    if (app->state != MC_STATE_FAULT) {
        outputs_off();
        app->state = MC_STATE_FAULT;
        app->enable_armed = false;
    }
}

/* The sample in the stationary frame (Clarke once per ISR) and sin / cos
 * of the controller's electrical angle. */
typedef struct {
    float i_alpha_A, i_beta_A;
    float s, c;
} mc_frame_t;

/* Angle source (config enum): theta_e, theta_m, omega_m (and tau_L_hat,
 * flux_ratio_sq when sensorless) into *t. */
static uint32_t estimate(mc_app_t *app, uint32_t count, const mc_frame_t *fr,
                         mc_telemetry_t *t)
{
    uint32_t faults = MC_FAULT_NONE;
    switch (app->cfg.angle_source) {
    case MC_ANGLE_SOURCE_ENCODER: {
        mc_encoder_estimate_t est;
        if (mc_encoder_tracker_update_f32(&app->encoder, count, &est) != MC_OK) {
            return MC_FAULT_ENCODER;
        }
        t->theta_e_rad = est.theta_e_rad;
        t->theta_m_rad = est.theta_m_rad;
        t->omega_m_rad_s = est.omega_m_rad_s;
        break;
    }
    case MC_ANGLE_SOURCE_FLUX_OBSERVER:
        faults = mc_app_sensorless_estimate(app, fr->i_alpha_A,
                                            fr->i_beta_A, t);
        break;
    default:
        return MC_FAULT_NONFINITE; /* unreachable: init validates the enum */
    }
    const float e[] = { t->theta_e_rad, t->theta_m_rad, t->omega_m_rad_s,
                        t->tau_L_hat_Nm };
    return faults |
           (mc_all_finite_f32(e, 4u) ? MC_FAULT_NONE : MC_FAULT_NONFINITE);
}

static void start_run(mc_app_t *app)
{
    mc_current_loop_reset_f32(&app->current);
    mc_speed_loop_reset_f32(&app->speed);
    mc_app_idapbc_reset(app);
    app->v_d_last_V = 0.0f;
    app->v_q_last_V = 0.0f;
    app->slow_counter = 0u;
    app->i_d_ref_A = 0.0f;
    app->i_q_ref_A = 0.0f;
    app->omega_m_ref_rad_s = 0.0f;
    app->mode = app->cmd.mode;
    app->state = MC_STATE_RUN;
}

/* Sensorless start: hold the rotor at the alignment angle first. */
static void start_align(mc_app_t *app)
{
    mc_current_loop_reset_f32(&app->current);
    mc_align_reset_f32(&app->align);
    app->theta_m_hat_rad =
        app->cfg.align_angle_e_rad / (float)app->cfg.pole_pairs;
    app->state = MC_STATE_ALIGN;
}

/* Offset calibration with the PWM off: average calib_samples raw samples. */
static uint32_t calibrate(mc_app_t *app, const float i_raw_A[3])
{
    for (uint32_t k = 0u; k < 3u; ++k) {
        app->calib_sum_A[k] += i_raw_A[k];
    }
    if (++app->calib_count < app->cfg.calib_samples) {
        return MC_FAULT_NONE;
    }
    const float inv_n = 1.0f / (float)app->cfg.calib_samples;
    uint32_t faults = MC_FAULT_NONE;
    for (uint32_t k = 0u; k < 3u; ++k) {
        const float offset = app->calib_sum_A[k] * inv_n;
        if (!isfinite(offset)) {
            faults |= MC_FAULT_NONFINITE;
        } else if (fabsf(offset) > app->cfg.i_offset_max_A) {
            faults |= MC_FAULT_CALIBRATION;
        } else {
            app->i_offset_A[k] = offset;
        }
    }
    if (faults == MC_FAULT_NONE) {
        if (app->cfg.angle_source == MC_ANGLE_SOURCE_FLUX_OBSERVER) {
            start_align(app);
        } else {
            start_run(app);
        }
    }
    return faults;
}

/* Outer loops: the current references of this ISR. Speed and position run
 * every speed_loop_decimation-th call (t->slow_loop_ran); current mode
 * follows the command every call. */
static void references(mc_app_t *app, const mc_command_t *cmd,
                       mc_telemetry_t *t)
{
    if (cmd->mode != app->mode) {
        mc_speed_loop_reset_f32(&app->speed);
        app->slow_counter = 0u;
        if (app->cfg.controller == MC_CONTROLLER_IDAPBC) {
            if (cmd->mode == MC_MODE_CURRENT) {
                /* The current loop takes over from (11), its integrators
                 * stale (ALIGN or an earlier current mode): restart them
                 * at (11)'s last voltage, bumpless. (FOC_PI: the current
                 * loop runs in every mode and simply continues.) */
                mc_current_loop_preset_f32(
                    &app->current, app->v_d_last_V, app->v_q_last_V,
                    t->i_d_A, t->i_q_A,
                    (float)app->cfg.pole_pairs * t->omega_m_rad_s);
            } else if (app->mode == MC_MODE_CURRENT) {
                /* (11) takes over: its integral action starts at 0;
                 * kept between speed and position ((11) runs in both) */
                mc_app_idapbc_reset(app);
            }
        }
        app->mode = cmd->mode;
    }
    if (cmd->mode == MC_MODE_CURRENT) {
        app->i_d_ref_A = cmd->i_d_ref_A;
        app->i_q_ref_A = cmd->i_q_ref_A;
        app->omega_m_ref_rad_s = 0.0f;
        /* |i_dq_ref| <= i_max (a documented limit; NaN stays NaN). */
        (void)mc_circle_limit_f32(&app->i_d_ref_A, &app->i_q_ref_A,
                                  app->cfg.i_max_A);
        return;
    }
    const bool slow_tick = (app->slow_counter == 0u);
    if (++app->slow_counter >= app->cfg.speed_loop_decimation) {
        app->slow_counter = 0u;
    }
    if (!slow_tick) {
        return;
    }
    t->slow_loop_ran = true;
    float w_ref;
    if (cmd->mode == MC_MODE_POSITION) {
        w_ref = mc_position_loop_step_f32(&app->position, cmd->theta_m_ref_rad,
                                          t->theta_m_rad);
    } else {
        const float w_max = app->cfg.omega_max_rad_s;
        w_ref = cmd->omega_m_ref_rad_s;
        w_ref = (w_ref > w_max) ? w_max : ((w_ref < -w_max) ? -w_max : w_ref);
    }
    app->omega_m_ref_rad_s = w_ref;
    app->i_d_ref_A = 0.0f; /* surface PMSM: no reluctance torque */
    if (app->cfg.controller == MC_CONTROLLER_FOC_PI) {
        app->i_q_ref_A = mc_speed_loop_step_f32(&app->speed, w_ref,
                                                t->omega_m_rad_s);
    } /* IDA-PBC: the speed reference enters (11) directly */
}

/* sin / cos of the controller's angle into *fr; measured d/q currents
 * (Park) for control and telemetry. */
static void measure_dq(mc_frame_t *fr, mc_telemetry_t *t)
{
    mc_sincos_f32(t->theta_e_rad, &fr->s, &fr->c);
    mc_park_f32(fr->i_alpha_A, fr->i_beta_A, fr->s, fr->c, &t->i_d_A,
                &t->i_q_A);
}

/* The fault of a failed current-loop or SVPWM step: a bus at or below 0 V
 * (reachable when v_dc_min_V = 0 disables the under-voltage check) is an
 * under-voltage; anything else is a non-finite value. */
static uint32_t voltage_step_fault(float v_dc_V)
{
    return (v_dc_V <= 0.0f) ? MC_FAULT_DC_UNDERVOLTAGE : MC_FAULT_NONFINITE;
}

/* Baseline current loop: d/q PI + decoupling; v_d, v_q of *t. */
static uint32_t control_foc_pi(mc_app_t *app, mc_telemetry_t *t)
{
    const float omega_e = (float)app->cfg.pole_pairs * t->omega_m_rad_s;
    mc_current_loop_out_t v;
    const mc_status_t st = mc_current_loop_step_f32(
        &app->current, t->i_d_A, t->i_q_A, t->i_d_ref_A, t->i_q_ref_A,
        omega_e, t->v_dc_V, &v);
    if (st != MC_OK) {
        return voltage_step_fault(t->v_dc_V);
    }
    t->v_d_V = v.v_d_V;
    t->v_q_V = v.v_q_V;
    t->v_saturated = v.saturated;
    return MC_FAULT_NONE;
}

/* v_d, v_q of *t -> duties: inverse Park at the voltage angle (advanced by
 * the delay compensation, mc/delay_comp.h), SVPWM with the circle limit.
 * Also fills the alpha/beta voltage the inverter will apply. */
static uint32_t modulate(mc_app_t *app, const mc_frame_t *fr,
                         mc_telemetry_t *t)
{
    float s = fr->s;
    float c = fr->c;
    if (app->delay_comp.enabled) {
        const float theta_v = mc_delay_comp_angle_f32(
            &app->delay_comp, t->theta_e_rad,
            (float)app->cfg.pole_pairs * t->omega_m_rad_s);
        if (!isfinite(theta_v)) {
            return MC_FAULT_NONFINITE;
        }
        mc_sincos_f32(theta_v, &s, &c);
    }
    float v_al;
    float v_be;
    mc_inv_park_f32(t->v_d_V, t->v_q_V, s, c, &v_al, &v_be);
    mc_svpwm_out_f32_t pwm;
    if (mc_svpwm_f32(v_al, v_be, t->v_dc_V, MC_SVPWM_LIMIT_CIRCLE, &pwm) !=
        MC_OK) {
        return voltage_step_fault(t->v_dc_V);
    }
    t->v_saturated = t->v_saturated || pwm.overmodulated;
    t->v_alpha_V = pwm.v_alpha_V;
    t->v_beta_V = pwm.v_beta_V;
    for (uint32_t k = 0u; k < 3u; ++k) {
        t->duty_abc[k] = pwm.duty[k];
    }
    return MC_FAULT_NONE;
}

/* Non-finite anywhere in references or outputs is a fault. */
static uint32_t check_outputs(const mc_telemetry_t *t)
{
    const float x[] = { t->i_d_ref_A, t->i_q_ref_A, t->omega_m_ref_rad_s,
                        t->i_d_A, t->i_q_A, t->v_d_V, t->v_q_V,
                        t->duty_abc[0], t->duty_abc[1], t->duty_abc[2] };
    return mc_all_finite_f32(x, (uint32_t)(sizeof x / sizeof x[0]))
               ? MC_FAULT_NONE
               : MC_FAULT_NONFINITE;
}

static uint32_t run(mc_app_t *app, const mc_command_t *cmd,
                    const mc_frame_t *fr, mc_telemetry_t *t)
{
    references(app, cmd, t);
    t->i_d_ref_A = app->i_d_ref_A;
    t->i_q_ref_A = app->i_q_ref_A;
    t->omega_m_ref_rad_s = app->omega_m_ref_rad_s;
    t->theta_m_ref_rad = cmd->theta_m_ref_rad;

    uint32_t faults;
    switch (app->cfg.controller) {
    case MC_CONTROLLER_FOC_PI:
        faults = control_foc_pi(app, t);
        break;
    case MC_CONTROLLER_IDAPBC:
        faults = (cmd->mode == MC_MODE_CURRENT) ? control_foc_pi(app, t)
                                                : mc_app_idapbc_voltages(app, t);
        break;
    default:
        faults = MC_FAULT_NONFINITE; /* unreachable: init validates it */
        break;
    }
    app->v_d_last_V = t->v_d_V;
    app->v_q_last_V = t->v_q_V;
    if (faults == MC_FAULT_NONE) {
        faults = modulate(app, fr, t);
    }
    faults |= check_outputs(t);
    if (cmd->mode == MC_MODE_POSITION && !isfinite(cmd->theta_m_ref_rad)) {
        faults |= MC_FAULT_NONFINITE;
    }
    return faults;
}

/* ALIGN (mc/align.h): the damped two-phase alignment through the current
 * loop, in the frame of the ALIGN vector (the estimate() reports its angle
 * outside RUN); once settled the observers start at the alignment angle
 * and RUN begins; a settle timeout is MC_FAULT_ESTIMATE. */
static uint32_t align(mc_app_t *app, const mc_frame_t *fr,
                      mc_telemetry_t *t)
{
    mc_align_state_t st = MC_ALIGN_BUSY;
    uint32_t faults =
        mc_app_sensorless_align(app, fr->i_alpha_A, fr->i_beta_A, t, &st);
    if (faults == MC_FAULT_NONE) {
        faults = control_foc_pi(app, t);
    }
    if (faults == MC_FAULT_NONE) {
        faults = modulate(app, fr, t);
    }
    faults |= check_outputs(t);
    if (faults == MC_FAULT_NONE && st == MC_ALIGN_DONE) {
        faults = mc_app_sensorless_start(app, fr->i_alpha_A, fr->i_beta_A);
        if (faults == MC_FAULT_NONE) {
            start_run(app);
        }
    }
    return faults;
}

/* State transitions and actions of this ISR (after the protection). */
static void state_machine(mc_app_t *app, const mc_command_t *cmd,
                          const float i_raw_A[3], uint32_t active,
                          const mc_frame_t *fr, mc_telemetry_t *t)
{
    const bool clear_edge = cmd->clear_fault && !app->clear_prev;
    app->clear_prev = cmd->clear_fault;
    if (!cmd->enable) {
        app->enable_armed = true;
    }
    switch (app->state) {
    case MC_STATE_IDLE:
        if (cmd->enable && app->enable_armed) {
            app->calib_count = 0u;
            for (uint32_t k = 0u; k < 3u; ++k) {
                app->calib_sum_A[k] = 0.0f;
            }
            app->state = MC_STATE_CALIBRATING;
        }
        break;
    case MC_STATE_CALIBRATING:
        if (!cmd->enable) {
            app->state = MC_STATE_IDLE;
        } else {
            raise_faults(app, calibrate(app, i_raw_A));
        }
        break;
    case MC_STATE_ALIGN:
        if (!cmd->enable) {
            app->state = MC_STATE_IDLE;
        } else {
            raise_faults(app, align(app, fr, t));
        }
        break;
    case MC_STATE_RUN:
        if (!cmd->enable) {
            app->state = MC_STATE_IDLE;
        } else {
            raise_faults(app, run(app, cmd, fr, t));
        }
        break;
    case MC_STATE_FAULT:
    default:
        if (clear_edge && active == MC_FAULT_NONE) {
            app->faults_latched = MC_FAULT_NONE;
            app->state = MC_STATE_IDLE;
        }
        break;
    }
}

void mc_app_fast_isr(mc_app_t *app)
{
    const uint32_t t_start = hal_cycle_counter();
    hal_gpio_debug_pin_set(true);
    app->isr_count++;
    app->cmd = app->cmd_buf[app->cmd_index & 1u];
    const mc_command_t *cmd = &app->cmd;

    /* Sample (converted at this period's PWM centre). */
    hal_adc_sample_t adc;
    hal_adc_read(&adc);
    const uint32_t count = hal_encoder_count();
    mc_telemetry_t t = {
        .v_dc_V = adc.v_dc_V,
        .duty_abc = { MC_DUTY_ZERO_VOLTAGE, MC_DUTY_ZERO_VOLTAGE,
                      MC_DUTY_ZERO_VOLTAGE },
    };
    for (uint32_t k = 0u; k < 3u; ++k) {
        t.i_abc_A[k] = adc.i_abc_A[k] - app->i_offset_A[k];
    }
    mc_frame_t fr;
    mc_clarke_f32(t.i_abc_A[0], t.i_abc_A[1], t.i_abc_A[2], &fr.i_alpha_A,
                  &fr.i_beta_A);

    /* Protect and estimate: the causes present now. Under-voltage is not
     * checked in IDLE (the bus may be legitimately down while the drive is
     * off); in FAULT it is, so a clear waits for the bus to recover. */
    const bool check_uv = (app->state != MC_STATE_IDLE);
    uint32_t active = mc_faults_check_sample(&app->cfg.fault_limits,
                                             t.i_abc_A, t.v_dc_V, check_uv);
    if (hal_gpio_fault_input_active()) {
        active |= MC_FAULT_EXTERNAL;
    }
    if (app->overrun_streak >= app->cfg.isr_overrun_limit) {
        active |= MC_FAULT_ISR_OVERRUN; /* still overrunning */
    }
    active |= estimate(app, count, &fr, &t);
    measure_dq(&fr, &t);
    raise_faults(app, active);

    /* Transitions, calibration, control. */
    state_machine(app, cmd, adc.i_abc_A, active, &fr, &t);

    /* Write: duties for the next period, or everything off. The voltage
     * they apply is recorded for the flux observer (mc/delay_comp.h). */
    if (app->state == MC_STATE_RUN || app->state == MC_STATE_ALIGN) {
        hal_pwm_set_duties(t.duty_abc);
        hal_pwm_enable_outputs();
        hal_gpio_power_stage_enable(true);
    } else {
        outputs_off();
        for (uint32_t k = 0u; k < 3u; ++k) {
            t.duty_abc[k] = MC_DUTY_ZERO_VOLTAGE;
        }
        hal_pwm_set_duties(t.duty_abc);
        t.v_alpha_V = 0.0f;
        t.v_beta_V = 0.0f;
    }
    /* Finite here: checked in run()/align(), zero otherwise. */
    (void)mc_applied_voltage_push_f32(&app->v_applied, t.v_alpha_V,
                                      t.v_beta_V);

    /* Deadline check: counted; the limit-th consecutive overrun is a
     * fault, PWM off in this ISR. */
    const uint32_t cycles = hal_cycle_counter() - t_start;
    app->isr_cost_s = (float)cycles * app->s_per_cycle;
    if (app->isr_cost_s > app->isr_cost_max_s) {
        app->isr_cost_max_s = app->isr_cost_s;
    }
    if (app->isr_cost_s > app->Ts_s) {
        app->isr_overruns++;
        app->overrun_streak++;
        if (app->overrun_streak >= app->cfg.isr_overrun_limit) {
            active |= MC_FAULT_ISR_OVERRUN;
            raise_faults(app, MC_FAULT_ISR_OVERRUN);
        }
    } else {
        app->overrun_streak = 0u;
    }
    hal_gpio_debug_pin_set(false);

    t.isr_count = app->isr_count;
    t.state = app->state;
    t.mode = cmd->mode;
    t.faults_latched = app->faults_latched;
    t.faults_active = active;
    t.outputs_enabled = hal_pwm_outputs_enabled();
    t.isr_cost_s = app->isr_cost_s;
    t.isr_cost_max_s = app->isr_cost_max_s;
    t.isr_overruns = app->isr_overruns;
    for (uint32_t k = 0u; k < 3u; ++k) {
        t.i_offset_abc_A[k] = app->i_offset_A[k];
    }
    mc_app_publish_telemetry(app, &t);
}
