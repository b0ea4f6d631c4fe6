/*
 * The drive application: fast ISR (sample, protect, estimate, control, write
 * duties), the decimated slow loop (speed / position), the state machine and
 * the faults. Talks to the hardware only through the HAL (hal/include/hal).
 *
 * State machine:
 *   IDLE --enable--> CALIBRATING (PWM off, average calib_samples current
 *   samples = offsets) --done--> RUN (PWM on) --!enable--> IDLE
 *   Sensorless (MC_ANGLE_SOURCE_FLUX_OBSERVER): CALIBRATING --done-->
 *   ALIGN (PWM on; mc/align.h: a current vector of align_current_A first
 *   at align_angle_e_rad + 90 deg electrical (ramped over align_ramp_s),
 *   then at align_angle_e_rad, each held until the rotor has settled,
 *   with active damping from a back-EMF speed estimate, so the start works
 *   from ANY rotor angle, the dead point 180 deg away included)
 *   --settled: observers start at align_angle_e_rad--> RUN;
 *   ALIGN --not settled within align_time_s--> FAULT (MC_FAULT_ESTIMATE:
 *   RUN never starts with an unsettled rotor); ALIGN --!enable--> IDLE.
 *   ALIGN lasts a variable time: 0.89-1.52 s for the default motor and
 *   configuration, depending on the start angle (measured over 13 start
 *   angles in tests/sim/test_p001_start; each phase: a damped swing of up
 *   to 90 deg, then align_settle_time_s of quiet).
 *   any --fault--> FAULT (PWM off in the same ISR call, latched)
 *   FAULT --clear_fault rising edge, no cause present--> IDLE
 * Every protection check runs in every ISR and state (under-voltage not in
 * IDLE); "cause present" = faults_active of that ISR.
 * After a fault the drive restarts only once enable has been seen false
 * (re-arm), so a stuck enable cannot restart a drive after a clear.
 *
 * Outside -> ISR: mc_app_set_command() (a double buffer: the ISR always sees
 * a complete command). ISR -> outside: mc_app_get_telemetry() (sequence
 * counter, retried if the ISR wrote meanwhile). Nothing else of mc_app_t may
 * be touched from outside.
 *
 * Deadline: the ISR measures its own cost with the HAL cycle counter; an ISR
 * costing more than the PWM period is an overrun, counted in telemetry;
 * isr_overrun_limit consecutive overruns latch MC_FAULT_ISR_OVERRUN (PWM
 * off in that ISR). On an MCU a too-slow ISR overruns every period, so a
 * small limit trips within a few periods; on the host, whose cycle counter
 * is real thread CPU time, a limit > 1 ignores isolated OS/VM hiccups
 * (measured: 1 ISR in 20000 costs 20-50 us, the mean is 0.4 us).
 *
 * The slow loop (speed/position) runs inside the fast ISR every
 * speed_loop_decimation-th call, so the whole control path is one
 * deterministic ISR whose cost the deadline check covers.
 *
 * Selectable algorithms (plain enums, a switch in the ISR, no function
 * pointers): angle_source and controller below.
 */
#ifndef MC_APP_H
#define MC_APP_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/align.h"
#include "mc/current_loop.h"
#include "mc/delay_comp.h"
#include "mc/encoder_tracker.h"
#include "mc/faults.h"
#include "mc/flux_observer.h"
#include "mc/idapbc.h"
#include "mc/pi.h"
#include "mc/pll_observer.h"
#include "mc/position_loop.h"
#include "mc/speed_load_observer.h"
#include "mc/speed_loop.h"
#include "mc/status.h"

typedef enum {
    MC_STATE_IDLE = 0,
    MC_STATE_CALIBRATING,
    MC_STATE_RUN,
    MC_STATE_FAULT,
    MC_STATE_ALIGN         /* sensorless start (appended: keeps the values
                              of the older states) */
} mc_state_t;

typedef enum {
    MC_MODE_CURRENT = 0,   /* i_d_ref_A, i_q_ref_A (torque control) */
    MC_MODE_SPEED,         /* omega_m_ref_rad_s */
    MC_MODE_POSITION       /* theta_m_ref_rad */
} mc_mode_t;

typedef enum {
    MC_ANGLE_SOURCE_ENCODER = 0,  /* incremental encoder + PLL speed */
    MC_ANGLE_SOURCE_FLUX_OBSERVER /* sensorless, currents only: gradient flux
                                     observer (paper 001 (12)-(14)); speed
                                     and load from the I&I observer (15)-(16)
                                     with MC_CONTROLLER_IDAPBC, from the PLL
                                     (mc/pll_observer.h, whose angle the
                                     controller then uses) with
                                     MC_CONTROLLER_FOC_PI: the "NAM"
                                     baseline of paper 001, Fig. 11 */
} mc_angle_source_t;

typedef enum {
    MC_CONTROLLER_FOC_PI = 0,     /* baseline cascaded FOC (this module) */
    MC_CONTROLLER_IDAPBC          /* paper 001 output-feedback speed
                                     controller (11) in speed and position
                                     modes (current mode: the FOC current
                                     loop); needs the flux observer */
} mc_controller_t;

/* Configuration. Motor parameters are the controller's NOMINAL values (the
 * plant may differ). */
typedef struct {
    /* nominal motor */
    float R_ohm;
    float Ld_H, Lq_H;
    float psi_Wb;
    uint32_t pole_pairs;
    float J_kgm2;
    float B_Nms;                  /* viscous friction, N m s/rad */
    /* timing */
    float f_pwm_hz;               /* fast ISR rate, [1 kHz, 100 kHz] */
    uint32_t speed_loop_decimation;  /* slow loop every N fast ISRs, >= 1 */
    uint32_t calib_samples;       /* offset calibration length, >= 1 */
    uint32_t isr_overrun_limit;   /* consecutive overruns that make the
                                     MC_FAULT_ISR_OVERRUN fault, [1, 100];
                                     every overrun is counted in telemetry */
    /* encoder */
    uint32_t encoder_cpr;         /* must equal hal_encoder_counts_per_rev() */
    float encoder_offset_e_rad;   /* theta_e at count 0 (alignment) */
    float pll_bandwidth_rad_s;    /* speed-estimator PLL bandwidth */
    /* loop design */
    float current_bandwidth_rad_s;   /* w_c of the d/q current loops */
    float speed_bandwidth_rad_s;     /* w_s of the speed loop */
    float position_kp_per_s;         /* position P gain */
    float modulation_margin;         /* v_max = m * v_dc / sqrt(3), (0, 1] */
    /* limits */
    float i_max_A;                /* current reference limit (|i_dq_ref|) */
    float omega_max_rad_s;        /* speed reference limit */
    float i_offset_max_A;         /* calibration fault above this offset */
    mc_fault_limits_t fault_limits;
    /* algorithm selection */
    mc_angle_source_t angle_source;
    mc_controller_t controller;
    /* sensorless estimation (MC_ANGLE_SOURCE_FLUX_OBSERVER) */
    float flux_obs_gamma;         /* gamma of (12), 1/(Wb^2 s), > 0 */
    float speed_obs_a1;           /* I&I gain a1 of (15), > 0 */
    float speed_obs_a2;           /* I&I gain a2 of (15), > 0 */
    float sensorless_pll_bandwidth_rad_s; /* NAM PLL, >= 2 x speed loop */
    float est_omega_max_rad_s;    /* |omega_hat| above: MC_FAULT_ESTIMATE */
    float est_tau_max_Nm;         /* |tau_hat| above: MC_FAULT_ESTIMATE */
    float est_flux_ratio_min;     /* |rho_hat| (= |eta| / psi) outside */
    float est_flux_ratio_max;     /* [min, max]: MC_FAULT_ESTIMATE */
    bool delay_comp_enabled;      /* advance the output voltage angle by
                                     n_p omega_hat delay_periods Ts */
    float delay_periods;          /* sample -> applied-voltage centre in
                                     periods, [0.5, 1.5] (mc/delay_comp.h) */
    float idapbc_r_ohm;           /* damping r of (11); 0 = critically
                                     damped (mc_idapbc_critical_damping_f32) */
    bool idapbc_integral_enabled; /* integral action on w_ref - w_hat added
                                     to the torque reference of (11)
                                     (mc/idapbc.h; beyond the paper, default
                                     false = the paper's scheme) */
    float idapbc_integral_pole_rad_s; /* its slow closed-loop pole p, 1/s,
                                     > 0 (mc_idapbc_integral_design_f32) */
    float idapbc_integral_tau_max_Nm; /* anti-windup: |tau_I| limit, > 0 */
    /* sensorless start (ALIGN state, mc/align.h) */
    float align_current_A;        /* vector current, (0, i_max_A) */
    float align_ramp_s;           /* phase-1 linear ramp, [0, align_time_s] */
    float align_time_s;           /* TIMEOUT of the whole ALIGN (both
                                     phases): not settled by then =
                                     MC_FAULT_ESTIMATE; (0, 10] */
    float align_angle_e_rad;      /* electrical angle, |.| <= 2 pi */
    float align_damping_ratio;    /* zeta of the damped alignment, (0, 10];
                                     k_d = 2 zeta omega_n J / (n_p kt) */
    float align_i_q_max_A;        /* damping current limit, > 0 and
                                     hypot(align_current_A, .) <= i_max_A */
    float align_settle_speed_e_rad_s; /* settled: |omega_e_hat| below */
    float align_settle_time_s;    /* for this long, [Ts, align_time_s) */
} mc_config_t;

/* Command set from outside the ISR. */
typedef struct {
    bool enable;                  /* level: run while true */
    bool clear_fault;             /* rising edge requests a fault clear */
    mc_mode_t mode;
    float i_d_ref_A, i_q_ref_A;   /* MC_MODE_CURRENT */
    float omega_m_ref_rad_s;      /* MC_MODE_SPEED */
    float theta_m_ref_rad;        /* MC_MODE_POSITION (multi-turn) */
} mc_command_t;

/* Telemetry of the latest fast ISR. */
typedef struct {
    uint32_t isr_count;           /* number of fast ISRs since init */
    mc_state_t state;
    mc_mode_t mode;
    uint32_t faults_latched;      /* mc_fault_t bits, latched */
    uint32_t faults_active;       /* mc_fault_t bits, cause present now */
    float i_abc_A[3];             /* offset-corrected phase currents */
    float i_offset_abc_A[3];      /* calibrated offsets */
    float v_dc_V;
    float i_d_A, i_q_A;
    float i_d_ref_A, i_q_ref_A;
    float v_d_V, v_q_V;           /* voltage references (after the limit) */
    float v_alpha_V, v_beta_V;    /* voltage the duties apply (after the
                                     modulator's limit; 0 with PWM off) */
    bool v_saturated;
    float theta_e_rad;            /* angle used by the controller */
    float theta_m_rad;            /* multi-turn mechanical position */
    float omega_m_rad_s;          /* speed estimate */
    float tau_L_hat_Nm;           /* load-torque estimate (sensorless; 0
                                     with the encoder) */
    float flux_ratio_sq;          /* |rho_hat|^2 of the flux observer
                                     (sensorless; 1 when converged) */
    float omega_m_ref_rad_s;
    float theta_m_ref_rad;
    float duty_abc[3];            /* written to the HAL (next period) */
    bool outputs_enabled;
    float isr_cost_s;             /* cost of this ISR, entry to duty write */
    float isr_cost_max_s;         /* maximum since init */
    uint32_t isr_overruns;        /* ISRs with cost > period since init */
    bool slow_loop_ran;           /* this ISR ran the decimated speed /
                                     position loop */
} mc_telemetry_t;

/* Application instance, owned by the caller (one per drive). Opaque:
 * the fields are private to firmware/app. */
typedef struct {
    mc_config_t cfg;
    float Ts_s;                   /* PWM period */
    float s_per_cycle;            /* 1 / hal_cycle_counter_hz() */
    mc_state_t state;
    uint32_t faults_latched;
    bool enable_armed;
    bool clear_prev;
    /* command double buffer (mc_app_set_command) */
    mc_command_t cmd_buf[2];
    volatile uint32_t cmd_index;
    mc_command_t cmd;             /* the ISR's copy */
    mc_mode_t mode;               /* mode of the previous RUN ISR */
    /* calibration */
    uint32_t calib_count;
    float calib_sum_A[3];
    float i_offset_A[3];
    /* estimation and control */
    mc_encoder_tracker_f32_t encoder;
    mc_current_loop_f32_t current;
    mc_speed_loop_f32_t speed;
    mc_position_loop_f32_t position;
    uint32_t slow_counter;
    float i_d_ref_A, i_q_ref_A;   /* held between slow-loop runs */
    float omega_m_ref_rad_s;
    /* sensorless estimation and the paper-001 controller */
    float kt_Nm_per_A;            /* 1.5 n_p psi (amplitude-invariant) */
    mc_flux_obs_f32_t flux_obs;
    mc_speed_load_obs_f32_t speed_obs;
    mc_pll_obs_f32_t pll_obs;
    mc_idapbc_f32_t idapbc;
    mc_pi_f32_t idapbc_int;       /* integral action tau_I (mc/idapbc.h) */
    float v_d_last_V, v_q_last_V; /* voltage of the previous RUN ISR (the
                                     current loop's bumpless start) */
    mc_delay_comp_f32_t delay_comp;
    mc_applied_voltage_f32_t v_applied; /* commands -> voltage over the
                                           last sample interval */
    float i_q_hat_prev_A;         /* i_q_hat at the previous sample */
    float theta_e_hat_prev_rad;   /* for the multi-turn position */
    float theta_m_hat_rad;        /* multi-turn position estimate */
    mc_align_f32_t align;         /* ALIGN sequence (mc/align.h) */
    /* timing */
    uint32_t isr_count;
    float isr_cost_s;             /* cost of the latest complete ISR */
    float isr_cost_max_s;
    uint32_t isr_overruns;        /* total */
    uint32_t overrun_streak;      /* consecutive, up to the latest ISR */
    /* telemetry (sequence counter: odd while the ISR writes) */
    volatile uint32_t tlm_seq;
    mc_telemetry_t tlm;
} mc_app_t;

/* Defaults for the paper-001 motor (R 0.225 ohm, L 3.8 mH, psi 0.17 Wb,
 * n_p 3, J 0.012 kg m^2) on a 48 V bus at 20 kHz; see config.c for every
 * value and its reason. Interrupt context: no. */
void mc_config_init_default(mc_config_t *cfg);

/* Check a configuration (finite values, ranges, discrete stability of the
 * designed loops). MC_OK, MC_ERR_NONFINITE or MC_ERR_PARAM.
 * Interrupt context: no. */
mc_status_t mc_config_validate(const mc_config_t *cfg);

/* Validate cfg, design the loops, configure the HAL PWM (outputs off, power
 * stage disabled) and enter IDLE. The encoder CPR must match the HAL's
 * (MC_ERR_PARAM otherwise). Interrupt context: no (call before the fast
 * ISR is enabled). */
mc_status_t mc_app_init(mc_app_t *app, const mc_config_t *cfg);

/* Hand a new command to the ISR (takes effect at the next fast ISR).
 * MC_ERR_PARAM for an unknown mode (the previous command stays). The
 * references are not checked here: a non-finite reference used in RUN is a
 * MC_FAULT_NONFINITE fault. Call from thread/background context only, never
 * from the fast ISR; single writer. */
mc_status_t mc_app_set_command(mc_app_t *app, const mc_command_t *cmd);

/* The fast ISR: call once per PWM period after the ADC conversions at the
 * PWM centre. Interrupt context (this is the ISR body); bounded time. */
void mc_app_fast_isr(mc_app_t *app);

/* Copy the telemetry of the latest complete fast ISR. MC_ERR_STATE if the
 * ISR rewrote it during each of a few copy attempts (reader starved; *out
 * then holds no consistent snapshot). Call from thread/background context,
 * not from the fast ISR. */
mc_status_t mc_app_get_telemetry(const mc_app_t *app, mc_telemetry_t *out);

#endif /* MC_APP_H */
