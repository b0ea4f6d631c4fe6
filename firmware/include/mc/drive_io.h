/*
 * What goes into and comes out of the drive: states, control modes, the
 * command set from outside the ISR and the telemetry record of one fast ISR
 * (the record the ISR fills while it runs; blocks read their inputs from it
 * and write their outputs into it). See mc/app.h for the exchange.
 */
#ifndef MC_DRIVE_IO_H
#define MC_DRIVE_IO_H

#include <stdbool.h>
#include <stdint.h>

typedef enum {
    MC_STATE_IDLE = 0,
    MC_STATE_CALIBRATING,
    MC_STATE_RUN,
    MC_STATE_FAULT,
    MC_STATE_ALIGN /* sensorless start (appended: keeps the values
                      of the older states) */
} mc_state_t;

typedef enum {
    MC_MODE_CURRENT = 0, /* i_d_ref_A, i_q_ref_A (torque control) */
    MC_MODE_SPEED,       /* omega_m_ref_rad_s */
    MC_MODE_POSITION     /* theta_m_ref_rad */
} mc_mode_t;

/* Command set from outside the ISR. */
typedef struct {
    bool enable;      /* level: run while true */
    bool clear_fault; /* rising edge requests a fault clear */
    mc_mode_t mode;
    float i_d_ref_A, i_q_ref_A; /* MC_MODE_CURRENT */
    float omega_m_ref_rad_s;    /* MC_MODE_SPEED */
    float theta_m_ref_rad;      /* MC_MODE_POSITION (multi-turn) */
    bool comm_lost; /* the command link timed out (mc/can_node.h): a cause
                       of MC_FAULT_COMM_TIMEOUT while true */
} mc_command_t;

/* Telemetry of the latest fast ISR that wrote it (every ISR, or with
 * timing.telemetry_every_isr off every ISR but the steady RUN ISRs
 * between slow ticks: mc/timing.h). 8-byte aligned: a whole number of
 * 8-byte units, which the ISR's clear relies on (fast_isr.c). */
typedef struct {
    _Alignas(8) uint32_t isr_count; /* number of fast ISRs since init */
    mc_state_t state;
    mc_mode_t mode;
    uint32_t faults_latched; /* mc_fault_t bits, latched */
    uint32_t faults_active;  /* mc_fault_t bits, cause present now */
    uint32_t first_fault;    /* the bits latched by the first faulting ISR
                                since the last clear (0: none) */
    float i_abc_A[3];        /* offset-corrected phase currents */
    float i_offset_abc_A[3]; /* calibrated offsets */
    float v_dc_V;
    float i_d_A, i_q_A; /* in the controller's frame */
    float i_d_ref_A, i_q_ref_A;
    float v_d_V, v_q_V;        /* voltage references (after the limit) */
    float v_alpha_V, v_beta_V; /* voltage the duties apply (after the
                                  modulator's limit; 0 with PWM off) */
    bool v_saturated;
    bool current_limited;     /* the current-limit loop corrected the voltage */
    float theta_e_rad;        /* angle used by the controller */
    float theta_m_rad;        /* multi-turn mechanical position */
    uint32_t encoder_count;   /* hal_encoder_count() of this sample (a
                                 controller that needs the integer count) */
    float encoder_edge_age_s; /* hal_encoder_edge_age of this sample, s;
                                 -1: the HAL keeps no edge times */
    float omega_m_rad_s;      /* speed estimate */
    float tau_L_hat_Nm;       /* load-torque estimate (0 from an
                                 estimator without one) */
    float flux_ratio_sq;      /* |rho_hat|^2 of the flux observer
                                 (sensorless; 1 when converged) */
    float omega_m_ref_rad_s;
    float theta_m_ref_rad;
    float duty_abc[3]; /* written to the HAL (next period) */
    bool outputs_enabled;
    float isr_cost_s;      /* cost of this ISR, entry to duty write */
    float isr_cost_max_s;  /* maximum since init */
    uint32_t isr_overruns; /* ISRs with cost > period since init */
    bool slow_loop_ran;    /* this ISR ran the decimated speed /
                              position loop */
} mc_telemetry_t;

#endif /* MC_DRIVE_IO_H */
