/*
 * The drive application: fast ISR (sample, protect, estimate, control, write
 * duties), the decimated slow loop (speed / position), the state machine and
 * the faults. Talks to the hardware only through the HAL (hal/include/hal).
 * The configuration is mc/config.h; the selected controller and estimator
 * come from their lists (mc/controllers.h, mc/estimators.h).
 *
 * State machine:
 *   IDLE --enable--> CALIBRATING (PWM off, average the current samples of
 *   timing.calib_time_s = offsets) --done--> RUN (PWM on) --!enable--> IDLE
 *   Sensorless estimator: CALIBRATING --done--> ALIGN (PWM on; mc/align.h:
 *   a current vector of align.current_A first at align.angle_e_rad + 90 deg
 *   electrical (ramped over align.ramp_s), then at align.angle_e_rad, each
 *   held until the rotor has settled, with active damping from a back-EMF
 *   speed estimate, so the start works from ANY rotor angle, the dead point
 *   180 deg away included) --settled: the estimator starts at
 *   align.angle_e_rad--> RUN; ALIGN --not settled within align.timeout_s-->
 *   FAULT (MC_FAULT_ESTIMATE: RUN never starts with an unsettled rotor);
 *   ALIGN --!enable--> IDLE.
 *   ALIGN lasts a variable time: 0.89-1.52 s for the default motor and
 *   configuration, depending on the start angle (measured over 13 start
 *   angles in tests/sim/test_p001_start; each phase: a damped swing of up
 *   to 90 deg, then align.settle_time_s of quiet).
 *   any --fault--> FAULT (PWM off in the same ISR call, latched)
 *   FAULT --clear_fault rising edge, no cause present--> IDLE
 * The checks of the sample (over-current, bus, the fault input, the
 * command link, the estimate's bounds and finiteness) run in every ISR and
 * state (under-voltage not in IDLE); the supervision (mc/supervisor.h) and
 * the back-EMF check (mc/emf_monitor.h) once per slow tick, their causes
 * held to the next. "Cause present" = faults_active of that ISR.
 * After a fault the drive restarts only once enable has been seen false
 * (re-arm), so a stuck enable cannot restart a drive after a clear.
 *
 * Outside -> ISR: mc_app_set_command() (a double buffer: the ISR always sees
 * a complete command). ISR -> outside: mc_app_get_telemetry() (sequence
 * counter, retried if the ISR wrote meanwhile). Nothing else of mc_app_t may
 * be touched from outside.
 *
 * Telemetry rate: with timing.telemetry_every_isr (the default, and the
 * simulator's) every fast ISR writes the record. Without it the steady RUN
 * ISRs between slow ticks (RUN continues in the same mode, no fault, no
 * overrun streak) do not: their blocks hand their values on through a
 * scratch record the compiler keeps in registers, the same arithmetic bit
 * for bit (tests/sim/test_telemetry_rate.c), about 30 instructions less per
 * such ISR on the Cortex-M4. The record then holds the latest slow tick's
 * or other writing ISR's values (isr_count says which ISR); a fault latched
 * in such an ISR is in the fault history at once (mc_app_fault_history,
 * with its sample) and in the record from the next ISR on.
 *
 * Timing: mc_app_init() configures the PWM first and designs every block
 * with the period the HAL realised and its sample-to-apply delay
 * (mc/timing.h).
 *
 * Deadline: the ISR measures its own cost with the HAL cycle counter; an ISR
 * costing more than the PWM period is an overrun, counted in telemetry;
 * timing.isr_overrun_limit consecutive overruns latch MC_FAULT_ISR_OVERRUN
 * (PWM off in that ISR). On an MCU a too-slow ISR overruns every period, so
 * a small limit trips within a few periods; on the host, whose cycle counter
 * is host wall time, a limit > 1 ignores isolated OS/VM hiccups
 * (measured: 1 ISR in 20000 costs 20-50 us, the mean is 0.4 us).
 *
 * The slow tick: every N-th fast ISR (N = timing.slow_decimation, from
 * slow_loop_Hz), in every state; RUN starts with a tick, and a mode change
 * makes its ISR a tick of the slow loop and counts on from there. The slow
 * loop (speed/position) and the supervision run inside the fast ISR of the
 * tick, so the whole control path is one deterministic ISR whose cost the
 * deadline check covers.
 */
#ifndef MC_APP_H
#define MC_APP_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/align.h"
#include "mc/config.h"
#include "mc/delay_comp.h"
#include "mc/drive.h"
#include "mc/drive_io.h"
#include "mc/emf_monitor.h"
#include "mc/estimator.h"
#include "mc/supervisor.h"
#include "mc/timing.h"

/* Fault events kept (the latest ones; older ones are overwritten). */
#define MC_FAULT_HISTORY_LEN 8u

/* One fault event: an ISR that latched new fault bits. */
typedef struct {
    uint32_t isr_count; /* the ISR (mc_telemetry_t.isr_count) */
    uint32_t faults;    /* the bits it latched (not latched before) */
    mc_state_t state;   /* the state it interrupted */
    float i_abc_A[3];   /* offset-corrected phase currents */
    float v_dc_V;
    float omega_m_rad_s; /* speed estimate */
} mc_fault_event_t;

/* mc_app_t.steady_key when RUN does not continue: no command's run key. */
#define MC_APP_NO_RUN_KEY UINT32_MAX

/* Application instance, owned by the caller (one per drive). Opaque:
 * the fields are private to firmware/app. */
typedef struct {
    /* The fields the fast ISR reads and writes every period come first:
     * the M4's floating-point loads and stores reach 1020 bytes from the
     * instance's address, one instruction more beyond. */
    mc_state_t state;
    mc_mode_t mode;             /* mode of the previous RUN ISR */
    mc_state_t tlm_entry_state; /* state at the previous ISR's entry */
    bool enable_armed;
    bool clear_prev;
    bool oc_in_hardware; /* the phase currents' levels watched by the HAL's
                            comparators (hal_pwm_overcurrent_arm) */
    uint32_t faults_latched;
    uint32_t first_fault; /* bits of the first faulting ISR */
    uint32_t slow_left;   /* ISRs before the next slow tick (0: this
                             one ticks), < N */
    uint32_t slow_faults; /* causes the supervision found at the latest
                             slow tick (held to the next) */
    /* the speed estimate in the latest ISR's record at its end: where a
     * scratch record starts (isr_body), as the record would */
    float omega_last_rad_s;
    /* command double buffer (mc_app_set_command) */
    mc_command_t cmd_buf[2];
    uint32_t cmd_run_key[2]; /* mc_app_run_key of each buffer */
    volatile uint32_t cmd_index;
    uint32_t steady_key; /* the run key of a command that continues this
                            RUN in the next ISR in a steady instance,
                            MC_APP_NO_RUN_KEY if RUN did not continue or
                            the next ISR must write the record in the
                            general instance (mc_app_fast_isr) */
    float i_offset_A[3];
    /* deadline */
    float s_per_cycle;      /* 1 / hal_cycle_counter_hz() */
    uint32_t period_cycles; /* the most cycles within Ts (the deadline) */
    uint32_t isr_count;
    uint32_t isr_cost_cycles;     /* the latest ISR's cost, and ... */
    uint32_t isr_cost_max_cycles; /* the costliest since init: written
                                     under tlm_seq, in seconds in the
                                     copy (mc_app_get_telemetry) */
    uint32_t isr_overruns;        /* total */
    uint32_t overrun_streak;      /* consecutive, up to the latest ISR */
    mc_timing_t timing;           /* from the HAL's realised PWM */
    /* telemetry (sequence counter: odd while the ISR writes) */
    volatile uint32_t tlm_seq;
    mc_telemetry_t tlm;
    /* estimation and control */
    mc_applied_voltage_f32_t v_applied; /* commands -> voltage over the
                                           last sample interval */
    mc_delay_comp_f32_t delay_comp;
    mc_drive_t drive;                     /* blocks shared by the controllers */
    mc_estimator_instance_t est;          /* the selected estimator */
    mc_controller_instance_t ctl;         /* the selected controller */
    mc_fault_limits_t protection_powered; /* cfg.protection as the sample
                                             check applies it: the
                                             under-voltage trip (every
                                             state but IDLE) at least
                                             FLT_MIN, so a bus that passes
                                             is positive and normal (the
                                             modulator's division:
                                             mc_app_run) */
    mc_config_t cfg;
    mc_estimator_info_t est_info; /* of cfg.estimator */
    mc_align_f32_t align;         /* ALIGN sequence (sensorless) */
    mc_supervisor_t supervisor;   /* drive-level checks (mc/supervisor.h) */
    mc_emf_check_f32_t emf;       /* the estimate against the measured
                                     back-EMF (mc/emf_monitor.h) */
    mc_fault_event_t history[MC_FAULT_HISTORY_LEN]; /* ring */
    volatile uint32_t history_count;                /* events since init */
    volatile uint32_t history_seq; /* odd while the ISR writes */
    /* calibration */
    uint32_t calib_count;
    float calib_sum_A[3];
} mc_app_t;

/* Validate cfg (mc_config_validate), configure the HAL PWM (outputs off,
 * power stage disabled), design every block with the realised timing and
 * enter IDLE. MC_ERR_PARAM also when the HAL rejects the PWM rate, realises
 * a period too far from the request (mc/timing.h), reports no cycle
 * counter, or when an encoder estimator's counts per revolution differ
 * from the HAL's. Interrupt context: no (call before the fast ISR is
 * enabled). */
mc_status_t mc_app_init(mc_app_t *app, const mc_config_t *cfg);

/* Hand a new command to the ISR (takes effect at the next fast ISR).
 * MC_ERR_PARAM for an unknown mode (the previous command stays). The
 * references are not checked here: a non-finite reference used in RUN is a
 * MC_FAULT_NONFINITE fault. Call from thread/background context only, never
 * from the fast ISR; single writer. Interrupt context: no. */
mc_status_t mc_app_set_command(mc_app_t *app, const mc_command_t *cmd);

/* The fast ISR: call once per PWM period after the ADC conversions.
 * Interrupt context: yes (this is the ISR body); bounded time. */
void mc_app_fast_isr(mc_app_t *app);

/* The timing record the drive was designed with (mc/timing.h: the
 * realised PWM period, the sample-to-apply delay in use, the slow-loop
 * decimation, the calibration length). Constant after mc_app_init.
 * Interrupt context: yes. */
const mc_timing_t *mc_app_timing(const mc_app_t *app);

/* Copy up to n of the latest fault events, newest first, into out; the
 * number copied. MC_ERR_STATE (0 copied) when the ISR kept writing during
 * a few attempts. Interrupt context: no. */
mc_status_t mc_app_fault_history(const mc_app_t *app, mc_fault_event_t *out,
                                 uint32_t n, uint32_t *copied);

/* Copy the telemetry of the latest complete fast ISR that wrote it (the
 * telemetry rate above; isr_cost_s, isr_cost_max_s: the latest ISR's and
 * the largest, whichever wrote the record). MC_ERR_STATE if the
 * ISR rewrote it during each of a few copy attempts (reader starved; *out
 * then holds no consistent snapshot). Call from thread/background context.
 * Interrupt context: no. */
mc_status_t mc_app_get_telemetry(const mc_app_t *app, mc_telemetry_t *out);

#endif /* MC_APP_H */
