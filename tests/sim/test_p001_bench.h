/*
 * Paper 001, Section 5.1 benchmark in closed loop (shared by the
 * test_p001_* executables): the paper's motor on the fixture's 48 V,
 * 20 kHz plant (ideal sensors, no dead time), currents the only
 * measurement the sensorless controller uses.
 *
 * Benchmark time tb = t - BENCH_T0_S: the drive calibrates its current
 * offsets (25.6 ms) and aligns the rotor (mc/align.h: two damped phases
 * that end once the rotor has settled, about 1.3 s from the aligned
 * position, at most 1.6 s from any angle on this bench) before tb = 0 and
 * holds a zero speed reference in RUN until then. Speed reference: 0 -> 50 rpm at
 * 50 rpm/s (tb = 1 s), hold to 3 s, 35 rpm/s to 120 rpm (5 s), hold to
 * 7 s, 60 rpm/s down to 0 (9 s), hold to 10 s. Load: 0 N m for tb < 1 s
 * and 2.5 <= tb < 5 s, 1 N m otherwise.
 *
 * Metrics from the engine's TRUE plant state against the reference and
 * the true load (not from the controller's own estimates).
 */
#ifndef TEST_P001_BENCH_H
#define TEST_P001_BENCH_H

#include <stdbool.h>
#include <stdint.h>

#include "mc_test.h"
#include "sim_fixture.h"

#define BENCH_T0_S          2.0
#define BENCH_LENGTH_S      10.0
#define BENCH_RPM_PER_RAD_S (60.0 / MC_TEST_TWO_PI)

typedef struct {
    double rms_speed_err_120_rpm;      /* tb in [5.5, 7) */
    double rms_speed_err_50_rpm;       /* tb in [1.5, 2.5) */
    double mean_speed_err_120_rpm;     /* mean of ref - w, tb in [5.5, 7) */
    double mean_speed_est_err_120_rpm; /* mean of w_hat - w, same window */
    double dip_load_1s_rpm;            /* max (ref - w) in tb [1, 1.5) */
    double dip_load_5s_rpm;            /* max (ref - w) in tb [5, 5.5) */
    double rms_angle_err_50_rad;       /* tb in [1.5, 3), electrical */
    double rms_angle_err_120_rad;      /* tb in [5.5, 7) */
    double rms_tau_err_120_Nm;         /* tau_hat - tau_L, tb in [5.5, 7) */
    double max_speed_err_moving_rpm;   /* |ref - w|, tb in [0.5, 8.5) */
    double max_angle_err_moving_rad;   /* tb in [0.5, 8.5) */
    double peak_current_A;             /* max |i_abc| from enable to the end */
    double peak_current_profile_A;     /* max |i_abc|, tb >= 0 */
    /* zero speed at the end, tb in [9.5, 10) */
    double max_abs_speed_end_rpm;
    double max_angle_err_end_rad;
    double max_tau_err_end_Nm;
    /* the start (ALIGN), true plant state at the first RUN sample */
    double t_run_s;              /* sim time of the first RUN sample */
    double t_align_s;            /* time spent in ALIGN */
    double align_angle_err_rad;  /* true theta_e - align.angle_e_rad */
    double align_omega_m_rad_s;  /* true omega_m */
    double peak_current_align_A; /* max |i_abc| during ALIGN */
    /* faults */
    uint32_t faults;        /* latched at the end */
    double t_first_fault_s; /* tb of the first fault, or -1 */
} bench_result_t;

/* Plant of the fixture with the paper's machine (its Phi = 0.17 Wb given
 * power-invariant, motor_convention.h: psi = 0.1388 Wb here), the
 * benchmark load and these mismatch multipliers (plant = nominal * m; the
 * controller stays nominal). */
void bench_plant_config(plant_config_t *pc, double m_R, double m_L, double m_psi);

/* Firmware for the plant pc (fixture_fw_config), sensorless with this
 * controller: MC_CONTROLLER_IDAPBC = the paper (estimator flux_ii: flux
 * observer + I&I), MC_CONTROLLER_FOC_PI = the NAM baseline (estimator
 * flux_pll: flux observer + PLL). */
void bench_fw_config(const plant_config_t *pc, mc_config_t *fc, mc_controller_t controller);

/* Speed reference (rpm) at benchmark time tb (s). */
double bench_ref_rpm(double tb_s);

/* Run the whole benchmark (asserts the drive reaches RUN before
 * BENCH_T0_S), print the metrics with `label`, return them. */
bench_result_t bench_run(const plant_config_t *pc, const mc_config_t *fc, const char *label);

/* The same up to benchmark time tb_end_s (<= BENCH_LENGTH_S); metrics of
 * windows not reached are NaN (RMS) or 0 (maxima). */
bench_result_t bench_run_to(const plant_config_t *pc, const mc_config_t *fc, const char *label,
                            double tb_end_s);

#endif /* TEST_P001_BENCH_H */
