/* The fast ISR: sample, protect, estimate, run the state machine, write
 * the duties, check the deadline, publish telemetry; the offset
 * calibration and the fault latching (see mc/app.h). The control path of
 * RUN is run_path.h, of ALIGN control_path.c. */
#include <math.h>
#include <stdatomic.h>

#include "app_internal.h"
#include "dispatch.h"
#include "hal/adc.h"
#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"
#include "mc/angle.h"
#include "mc/clarke.h"
#include "mc/park.h"
#include "run_path.h"

#define MC_DUTY_ZERO_VOLTAGE 0.5f

/* Clear the telemetry record word by word: its size is a multiple of 8
 * (_Alignas(8)), and the C library's size-optimised memset costs about 170
 * instructions for it on the M4, the unrolled stores about 40. The words
 * are written through a may_alias type (GCC's documented exception to the
 * aliasing rules). */
typedef uint32_t mc_tlm_word_t __attribute__((may_alias));
_Static_assert(sizeof(mc_telemetry_t) % 8u == 0u, "whole 8-byte units");

static void tlm_clear(mc_telemetry_t *t)
{
    mc_tlm_word_t *w = (mc_tlm_word_t *)(void *)t;
#pragma GCC unroll 64
    for (uint32_t k = 0u; k < sizeof *t / sizeof *w; ++k) {
        w[k] = 0u;
    }
}

static void outputs_off(void)
{
    hal_pwm_disable_outputs();
    hal_gpio_power_stage_enable(false);
}

/* Record a fault event (the history ring, sequence counter odd while
 * writing: mc_app_fault_history) of the sample i_abc_A, v_dc_V and the
 * speed estimate omega_m_rad_s. */
static void record_fault(mc_app_t *app, uint32_t new_bits, float i_a_A,
                         float i_b_A, float i_c_A, float v_dc_V,
                         float omega_m_rad_s)
{
    app->history_seq = app->history_seq + 1u;
    atomic_signal_fence(memory_order_seq_cst);
    mc_fault_event_t *ev =
        &app->history[app->history_count % MC_FAULT_HISTORY_LEN];
    ev->isr_count = app->isr_count;
    ev->faults = new_bits;
    ev->state = app->state;
    ev->i_abc_A[0] = i_a_A;
    ev->i_abc_A[1] = i_b_A;
    ev->i_abc_A[2] = i_c_A;
    ev->v_dc_V = v_dc_V;
    ev->omega_m_rad_s = omega_m_rad_s;
    app->history_count = app->history_count + 1u;
    atomic_signal_fence(memory_order_seq_cst);
    app->history_seq = app->history_seq + 1u;
}

/* Latch the new fault bits; from any other state the PWM goes off right
 * here (the reaction: coast, mc/app.h). They are recorded with the
 * sample (record_fault), the first ones since the last clear kept as the
 * first fault. */
static void latch_faults(mc_app_t *app, uint32_t new_bits, float i_a_A,
                         float i_b_A, float i_c_A, float v_dc_V,
                         float omega_m_rad_s)
{
    if (app->faults_latched == MC_FAULT_NONE) {
        app->first_fault = new_bits;
    }
    app->faults_latched |= new_bits;
    record_fault(app, new_bits, i_a_A, i_b_A, i_c_A, v_dc_V, omega_m_rad_s);
    if (app->state != MC_STATE_FAULT) {
        outputs_off();
        app->state = MC_STATE_FAULT;
        app->enable_armed = false;
    }
}

/* latch_faults with the sample of *t, taken by value: the record's
 * address does not reach the out-of-line latch, so a steady ISR's scratch
 * record stays in registers (isr_body). Interrupt context: yes. */
MC_STATIC_FORCEINLINE void latch_faults_of(mc_app_t *app, uint32_t new_bits,
                                           const mc_telemetry_t *t)
{
    latch_faults(app, new_bits, t->i_abc_A[0], t->i_abc_A[1], t->i_abc_A[2],
                 t->v_dc_V, t->omega_m_rad_s);
}

/* Latch the bits of faults not latched yet (inline: usually none); true
 * if there were any (then the state is FAULT). */
MC_STATIC_FORCEINLINE bool raise_faults(mc_app_t *app, uint32_t faults,
                                        const mc_telemetry_t *t)
{
    const uint32_t new_bits = faults & ~app->faults_latched;
    if (new_bits != MC_FAULT_NONE) {
        latch_faults_of(app, new_bits, t);
        return true;
    }
    return false;
}

/* raise_faults in a steady ISR that has not stopped (isr_body): in RUN
 * nothing is latched (latch_faults latches with FAULT, only the clear in
 * FAULT empties the latch), so every bit is new. */
MC_STATIC_FORCEINLINE bool raise_faults_in_run(mc_app_t *app, uint32_t faults,
                                               const mc_telemetry_t *t)
{
    if (MC_UNLIKELY(faults != MC_FAULT_NONE)) {
        latch_faults_of(app, faults, t);
        return true;
    }
    return false;
}

/* The estimate against the measured back-EMF (mc/emf_monitor.h) over the
 * interval before this sample, on the slow tick in RUN: a sensorless
 * estimate that turns while the rotor does not is LOSS_OF_LOCK; an encoder
 * that slipped or froze is ENCODER. fr->sc: the sine and cosine of
 * the estimate's angle. */
static uint32_t check_estimate(mc_app_t *app, const mc_frame_t *fr,
                               const mc_telemetry_t *t, bool running)
{
    if (!running) {
        mc_emf_check_reset_f32(&app->emf);
        return MC_FAULT_NONE;
    }
    float v_al;
    float v_be;
    mc_applied_voltage_last_f32(&app->v_applied, &v_al, &v_be);
    const float w_e = app->drive.n_p * t->omega_m_rad_s;
    if (app->est_info.sensorless) {
        return mc_emf_check_sensorless_f32(&app->emf, fr->in.i_alpha_A,
                                           fr->in.i_beta_A, v_al, v_be,
                                           fr->sc.sin_e, fr->sc.cos_e, w_e)
                   ? MC_FAULT_LOSS_OF_LOCK
                   : MC_FAULT_NONE;
    }
    return mc_emf_check_encoder_f32(&app->emf, fr->in.i_alpha_A,
                                    fr->in.i_beta_A, v_al, v_be, fr->sc.sin_e,
                                    fr->sc.cos_e, w_e)
               ? MC_FAULT_ENCODER
               : MC_FAULT_NONE;
}

/* Offset calibration with the PWM off: average calib_samples raw samples. */
static uint32_t calibrate(mc_app_t *app, const float i_raw_A[3])
{
    for (uint32_t k = 0u; k < 3u; ++k) {
        app->calib_sum_A[k] += i_raw_A[k];
    }
    if (++app->calib_count < app->timing.calib_samples) {
        return MC_FAULT_NONE;
    }
    const float inv_n = 1.0f / (float)app->timing.calib_samples;
    uint32_t faults = MC_FAULT_NONE;
    for (uint32_t k = 0u; k < 3u; ++k) {
        const float offset = app->calib_sum_A[k] * inv_n;
        if (!isfinite(offset)) {
            faults |= MC_FAULT_NONFINITE;
        } else if (fabsf(offset) > app->cfg.protection.i_offset_max_A) {
            faults |= MC_FAULT_CALIBRATION;
        } else {
            app->i_offset_A[k] = offset;
        }
    }
    if (faults == MC_FAULT_NONE) {
        if (app->est_info.sensorless) {
            mc_app_start_align(app);
        } else {
            mc_app_start_run(app);
        }
    }
    return faults;
}

/* The RUN case of a steady ISR (mc_app_fast_isr: RUN, enabled, the same
 * mode and clear request, a finite position reference): the control path
 * unless this ISR's protection stopped RUN (stopped); true if RUN stopped
 * here or before. */
MC_STATIC_FORCEINLINE bool
state_run_steady(mc_app_t *app, const mc_command_t *cmd, const mc_frame_t *fr,
                 mc_telemetry_t *t, bool stopped, mc_app_out_t *out)
{
    if (stopped) {
        return true;
    }
    return raise_faults_in_run(app, mc_app_run(app, cmd, fr, t, false, out), t);
}

/* In RUN now: a steady ISR is in RUN until it latches a fault (stopped:
 * only that stops its RUN), so it knows without reading the state back
 * after every call that may latch; the other instance reads it. */
MC_STATIC_FORCEINLINE bool isr_in_run(const mc_app_t *app, bool steady,
                                      bool stopped)
{
    return steady ? !stopped : (app->state == MC_STATE_RUN);
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
            raise_faults(app, calibrate(app, i_raw_A), t);
        }
        break;
    case MC_STATE_ALIGN:
        if (!cmd->enable) {
            app->state = MC_STATE_IDLE;
        } else {
            raise_faults(app, mc_app_align(app, fr, t), t);
        }
        break;
    case MC_STATE_RUN:
        if (!cmd->enable) {
            app->state = MC_STATE_IDLE;
        } else {
            if (cmd->mode != app->mode) {
                mc_app_change_mode(app, cmd, t);
            }
            mc_app_out_t out; /* the write phase reads *t */
            raise_faults(app, mc_app_run(app, cmd, fr, t, true, &out), t);
        }
        break;
    case MC_STATE_FAULT:
    default:
        if (clear_edge && active == MC_FAULT_NONE) {
            app->faults_latched = MC_FAULT_NONE;
            app->first_fault = MC_FAULT_NONE;
            app->state = MC_STATE_IDLE;
        }
        break;
    }
}

/* The ISR's body. steady, a constant in each of the three instances:
 * this ISR is in RUN after a RUN ISR, in the same mode, enabled, with the
 * same clear request and a finite position reference, without a
 * communication loss or an overrun streak (the last ISR's steady_key
 * equals the command's run key, mc_app_run_key): the common case, whose two
 * instances (steady_slow, also a constant: with the slow tick or without) the
 * compiler strips of everything else; the general instance runs every
 * ISR with the same code. publish, a constant too: this ISR writes the
 * telemetry record (false only in the steady instance without the slow
 * tick, which runs with timing.telemetry_every_isr off; with it on, the
 * general instance runs those ISRs). Each instance inlines the whole
 * control path (15 to 16 kB of flash each at -O2): the slow tick's own
 * instance saves its ISR the general one's state handling, about 100
 * instructions. */
MC_STATIC_FORCEINLINE void isr_body(mc_app_t *app, const mc_command_t *cmd,
                                    uint32_t t_start, const bool steady,
                                    const bool steady_slow, const bool publish)
{
    hal_gpio_debug_pin_set(true);
    const uint32_t isr_count = app->isr_count + 1u;
    app->isr_count = isr_count;
    /* The slow tick (mc/app.h): the outer loop's and the supervision's. */
    const bool slow_tick = steady ? steady_slow : (app->slow_left == 0u);
    app->slow_left =
        slow_tick ? app->timing.slow_decimation - 1u : app->slow_left - 1u;

    /* Sample (converted at this period's sampling instant). */
    hal_adc_sample_t adc;
    hal_adc_read(&adc);
    /* The telemetry record, written in place under its sequence counter
     * until the end of this ISR. It restarts from zero unless this ISR and
     * the previous one both begin in RUN in the same mode: a steady RUN
     * ISR writes every field its path sets (the rest keep their zero), so
     * it spares the 152-byte clear. A steady ISR between slow ticks (the
     * instance with publish false: timing.telemetry_every_isr off) writes
     * a scratch record instead, which the compiler keeps in registers
     * (nothing takes its address: latch_faults_of, the cold paths' copies):
     * the blocks hand their values on as before and the stores of the
     * record are spared; the record keeps the latest publishing ISR's.
     * Its fields read before this ISR writes them are zero, but the
     * speed estimate, which starts where the record's would (the fault
     * history records it); only uncommon paths that stop RUN read any. */
    mc_telemetry_t scratch = { .omega_m_rad_s = app->omega_last_rad_s };
    mc_telemetry_t *const t = publish ? mc_app_tlm_begin(app) : &scratch;
    const bool same_run = steady || (app->state == MC_STATE_RUN &&
                                     app->tlm_entry_state == MC_STATE_RUN &&
                                     cmd->mode == app->mode);
    /* (RUN in a steady ISR: refreshed on its slow tick, as often as
     * when the slow ticks ran the general instance) */
    if (!steady || steady_slow) {
        app->tlm_entry_state = app->state;
    }
    if (!same_run) {
        tlm_clear(t);
    }
    t->slow_loop_ran = false; /* set by the outer loop's tick */
    t->v_dc_V = adc.v_dc_V;
    /* (unrolled: a record indexed by a variable would stay in memory) */
    t->i_abc_A[0] = adc.i_abc_A[0] - app->i_offset_A[0];
    t->i_abc_A[1] = adc.i_abc_A[1] - app->i_offset_A[1];
    t->i_abc_A[2] = adc.i_abc_A[2] - app->i_offset_A[2];
    mc_frame_t fr; /* every field set before use (no zeroing cost) */
    fr.in.encoder_count = hal_encoder_count();
    t->encoder_count = fr.in.encoder_count;
    float edge_age_s = -1.0f; /* -1 if the HAL keeps no edge times */
    (void)hal_encoder_edge_age(&edge_age_s);
    t->encoder_edge_age_s = edge_age_s;
    fr.v_dc_V = adc.v_dc_V;
    fr.in.v_applied = &app->v_applied;
    fr.in.running = steady || (app->state == MC_STATE_RUN);
    fr.in.slow_tick = slow_tick;
    fr.in.theta_e_hold_rad = steady ? 0.0f /* unused in RUN */
                                    : mc_align_theta_e_f32(&app->align);
    mc_clarke_f32(t->i_abc_A[0], t->i_abc_A[1], t->i_abc_A[2], &fr.in.i_alpha_A,
                  &fr.in.i_beta_A);

    /* Protect and estimate: the causes present now. Under-voltage is not
     * checked in IDLE (the bus may be legitimately down while the drive is
     * off); in FAULT it is, so a clear waits for the bus to recover; in
     * every state but IDLE the bus is also one the modulator can divide by
     * (mc_app_t.protection_powered). */
    const bool check_uv = steady || (app->state != MC_STATE_IDLE);
    const mc_fault_limits_t *limits = &app->protection_powered;
    /* The phase currents' levels: a steady ISR leaves them to the HAL's
     * comparators when they are armed (which stop the outputs by
     * themselves), every other ISR compares them too. */
    uint32_t active =
        (steady && app->oc_in_hardware)
            ? mc_faults_check_bus_fast(limits, t->i_abc_A, t->v_dc_V, check_uv)
            : mc_faults_check_sample_fast(limits, t->i_abc_A, t->v_dc_V,
                                          check_uv);
    if (MC_UNLIKELY(hal_pwm_overcurrent_active())) {
        active |= MC_FAULT_OVERCURRENT;
    }
    if (MC_UNLIKELY(hal_gpio_fault_input_active())) {
        active |= MC_FAULT_EXTERNAL;
    }
    if (!steady && cmd->comm_lost) {
        active |= MC_FAULT_COMM_TIMEOUT;
    }
    if (!steady && app->overrun_streak >= app->timing.isr_overrun_limit) {
        active |= MC_FAULT_ISR_OVERRUN; /* still overrunning */
    }
    /* the estimate into *t (finite: mc/estimator.h) with the sine and
     * cosine of its angle; measured d/q currents (Park) for control and
     * telemetry. */
    active |= mc_dispatch_estimator_step(app, &fr.in, t, &fr.sc);
    mc_park_f32(fr.in.i_alpha_A, fr.in.i_beta_A, fr.sc.sin_e, fr.sc.cos_e,
                &t->i_d_A, &t->i_q_A);
    if (slow_tick) {
        const bool running = steady || (app->state == MC_STATE_RUN);
        app->slow_faults =
            mc_supervisor_step(&app->supervisor, t, running,
                               running || app->state == MC_STATE_ALIGN,
                               mc_current_limit_active_f32(&app->drive.limit)) |
            check_estimate(app, &fr, t, running);
    }
    /* the currents for the EMF check of the next slow tick: a steady ISR
     * keeps them only before one (slow_left counted down to 0 above) */
    if (!steady || MC_UNLIKELY(app->slow_left == 0u)) {
        mc_emf_monitor_remember_f32(&app->emf.mon, fr.in.i_alpha_A,
                                    fr.in.i_beta_A);
    }
    active |= app->slow_faults;
    /* whether a steady ISR latched a fault (isr_in_run) */
    bool stopped = steady ? raise_faults_in_run(app, active, t)
                          : raise_faults(app, active, t);

    /* Transitions, calibration, control (the outer loop's tick written
     * here, next to its use: the compiler sees the value it reads). */
    app->drive.outer.tick = slow_tick;
    mc_app_out_t out; /* a steady ISR's outputs (else *t's) */
    if (steady) {
        stopped = state_run_steady(app, cmd, &fr, t, stopped, &out);
    } else {
        state_machine(app, cmd, adc.i_abc_A, active, &fr, t);
    }

    /* Write: duties for the next period, or everything off. The voltage
     * they apply is recorded for the observers (mc/delay_comp.h). */
    if (isr_in_run(app, steady, stopped) ||
        (!steady && app->state == MC_STATE_ALIGN)) {
        if (steady) {
            hal_pwm_set_duties(out.duty);
        } else {
            hal_pwm_set_duties(t->duty_abc);
            hal_pwm_enable_outputs();
            hal_gpio_power_stage_enable(true);
            out.v_alpha_V = t->v_alpha_V;
            out.v_beta_V = t->v_beta_V;
        }
    } else {
        outputs_off();
        for (uint32_t k = 0u; k < 3u; ++k) {
            t->duty_abc[k] = MC_DUTY_ZERO_VOLTAGE;
        }
        hal_pwm_set_duties(t->duty_abc);
        t->v_alpha_V = 0.0f;
        t->v_beta_V = 0.0f;
        out.v_alpha_V = 0.0f;
        out.v_beta_V = 0.0f;
    }
    /* Finite here: checked in the control path, zero otherwise. */
    mc_applied_voltage_push_unchecked_f32(&app->v_applied, out.v_alpha_V,
                                          out.v_beta_V);

    /* Deadline check: counted; the limit-th consecutive overrun is a
     * fault, PWM off in this ISR. */
    const uint32_t cycles = hal_cycles_since(t_start);
    app->isr_cost_cycles = cycles; /* the costs in seconds: the reader's */
    if (cycles > app->isr_cost_max_cycles) {
        app->isr_cost_max_cycles = cycles;
    }
    const bool overran = cycles > app->period_cycles; /* cost > Ts */
    if (overran) {
        app->isr_overruns++;
        t->isr_overruns = app->isr_overruns;
        app->overrun_streak++;
        if (app->overrun_streak >= app->timing.isr_overrun_limit) {
            active |= MC_FAULT_ISR_OVERRUN;
            stopped = raise_faults(app, MC_FAULT_ISR_OVERRUN, t) || stopped;
        }
    } else if (!steady) { /* a steady ISR's streak is 0 (isr_body) */
        app->overrun_streak = 0u;
    }
    hal_gpio_debug_pin_set(false);

    t->isr_count = isr_count;
    /* The rest is constant in RUN (no active fault; the overruns written
     * above when they change): a steady ISR still in RUN finds it in the
     * record. */
    if (!steady || MC_UNLIKELY(stopped)) {
        t->isr_overruns = app->isr_overruns;
        t->faults_active = active;
        t->state = app->state;
        t->mode = cmd->mode;
        t->faults_latched = app->faults_latched;
        t->first_fault = app->first_fault;
        t->outputs_enabled = hal_pwm_outputs_enabled();
    }
    if (!same_run) {
        for (uint32_t k = 0u; k < 3u; ++k) {
            t->i_offset_abc_A[k] = app->i_offset_A[k];
        }
    }
    if (publish) {
        mc_app_tlm_end(app);
    }
    app->omega_last_rad_s = t->omega_m_rad_s;
    const bool no_streak = steady ? !overran : (app->overrun_streak == 0u);
    /* the next ISR may run a steady instance: RUN continues, and the
     * next ISR is a slow tick or need not write the record (an ISR that
     * did not write it knows: mc_app_fast_isr) */
    const bool next_steady =
        isr_in_run(app, steady, stopped) && no_streak &&
        (!publish || app->slow_left == 0u || !app->timing.telemetry_every_isr);
    if (!steady) {
        app->steady_key = next_steady
                              ? mc_app_run_key(true, false, cmd->clear_fault,
                                               false, app->mode)
                              : MC_APP_NO_RUN_KEY;
    } else if (MC_UNLIKELY(!next_steady)) { /* else the key stays */
        app->steady_key = MC_APP_NO_RUN_KEY;
    }
}

/* The three instances, out of line: each a tail call from
 * mc_app_fast_isr, so their frames do not add up. */
static __attribute__((noinline)) void
isr_steady(mc_app_t *app, const mc_command_t *cmd, uint32_t t_start)
{
    isr_body(app, cmd, t_start, true, false, false);
}

static __attribute__((noinline)) void
isr_steady_slow(mc_app_t *app, const mc_command_t *cmd, uint32_t t_start)
{
    isr_body(app, cmd, t_start, true, true, true);
}

static __attribute__((noinline)) void
isr_general(mc_app_t *app, const mc_command_t *cmd, uint32_t t_start)
{
    isr_body(app, cmd, t_start, false, false, true);
}

void mc_app_fast_isr(mc_app_t *app)
{
    const uint32_t t_start = hal_cycle_counter();
    const uint32_t k = mc_app_command_slot(app);
    const mc_command_t *cmd = &app->cmd_buf[k];
    /* steady (isr_body): the last ISR ended in RUN without an overrun
     * streak and this command continues it; with the slow tick, or
     * without it and without writing the telemetry record (the last
     * ISR's key says whether a steady instance may run this one: with
     * timing.telemetry_every_isr only at a slow tick) */
    if (app->cmd_run_key[k] != app->steady_key) {
        isr_general(app, cmd, t_start);
    } else if (app->slow_left == 0u) {
        isr_steady_slow(app, cmd, t_start);
    } else {
        isr_steady(app, cmd, t_start);
    }
}
