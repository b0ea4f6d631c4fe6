/*
 * Paper 000's position regulator (controller "eeo", mc/ctl_eeo.h) in
 * closed loop inside QEMU (mps2-an386, Cortex-M4F): the same firmware C
 * code as the bench's host_sim/scenarios/paper000_eeo_case2.json, with the
 * plant (host_sim/plant, double precision = soft-float on the M4) in the
 * image through host_sim/engine and the hal/qemu_m4 binding.
 *
 * Configuration (= paper000_eeo_case2.json): Table 1 motor given in the
 * paper's two-phase convention (motor_convention.h: L 20 mH, R 7.2 ohm,
 * lambda_m 0.06 Wb, n_p 8, j 5.5367e-5 kg m^2, B 0.006 N m s/rad), g3 =
 * 1/j + 1e4 sin(t) on the plant and known to the observer (phase = t at
 * the start of RUN), encoder of 2^21 lines (2^23 counts per turn), 48 V,
 * 20 kHz, plant with PLANT_SUBSTEPS_FAST (the scenario's 4 substeps),
 * i_max 3 A; theta* = 1 rad from t = 0 in position mode; load 0.2 N m from
 * T_RUN = 25.6 ms, the end of the offset calibration (the scenario's
 * time_offset_s; checked against the first RUN sample), so the rotor
 * starts at standstill. End at T_RUN + QEMU_P000_T_S (profile time tb =
 * t - T_RUN, as in the scenario's metrics).
 *
 * Output: the harness's (closed_loop.h), the angle error every 250 ms
 * (printed only), and the checkpoints, the angles from the TRUE plant
 * state:
 *   final_angle_error_rad theta_m - theta* at the end
 *   settled_s             last tb with |theta_m - theta*| > 1e-3 rad
 *   peak_v_paper_V        max |v_dq| in RUN in the paper's units (sqrt(3/2)
 *                         times the drive's), over the records the drive
 *                         wrote (closed_loop.h: its slow ticks)
 * Exit status 0 only if RUN was reached at T_RUN, no fault latched, no
 * ISR overrun, the angle stayed finite and the peak voltage stayed within
 * the SVPWM circle (v_dc / sqrt(2) in the paper's units).
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "closed_loop.h"
#include "motor_convention.h"
#include "qemu_m4.h"

#ifndef QEMU_P000_T_S
#error "define QEMU_P000_T_S (simulated seconds after the start of RUN)"
#endif

#define T_RUN     0.0256 /* s: end of the offset calibration */
#define THETA_REF 1.0    /* rad */
#define TAU_L     0.2    /* N m (case 2) */
#define G3_AMP    1e4    /* 1/(kg m^2) */
#define G3_OMEGA  1.0    /* rad/s */
#define T_END     (T_RUN + (double)QEMU_P000_T_S)
#define T_REPORT  0.25 /* s between the printed angle errors */
#define V_DC      48.0
#define SQRT_3_2  1.2247448713915890

static qemu_loop_t loop;

int main(void)
{
    plant_config_t pc;
    qemu_loop_plant_default(&pc, T_RUN, TAU_L);
    pc.motor = (plant_motor_params_t){
        .R_ohm = 7.2,
        .Ld_H = 0.020,
        .Lq_H = 0.020,
        .psi_Wb = 0.06,
        .pole_pairs = 8u,
        .J_kgm2 = 5.5367e-5,
        .B_Nm_s_rad = 0.006,
        .g3_amplitude_per_kgm2 = G3_AMP,
        .g3_omega_rad_s = G3_OMEGA,
    };
    plant_motor_to_amplitude_invariant(&pc.motor, PLANT_POWER_INVARIANT);
    pc.sensors.encoder.lines = 1u << 21;

    mc_config_t fc;
    mc_config_init_default(&fc);
    sim_engine_firmware_from_plant(&pc, &fc);
    fc.controller = MC_CONTROLLER_EEO;
    fc.estimator = MC_ESTIMATOR_ENCODER;
    fc.limits.i_max_A = 3.0f;
    fc.eeo.g3_bound_per_kgm2 = (float)G3_AMP;
    fc.eeo.g3_amplitude_per_kgm2 = (float)G3_AMP;
    fc.eeo.g3_omega_rad_s = (float)G3_OMEGA;
    fc.eeo.g3_phase_rad = (float)(G3_OMEGA * T_RUN);
    int status = qemu_loop_init(&loop, "qemu p000 eeo case 2", &pc, &fc);
    if (status != 0) {
        return status;
    }
    const mc_command_t cmd = { .enable = true,
                               .mode = MC_MODE_POSITION,
                               .theta_m_ref_rad = (float)THETA_REF };
    const double Ts = sim_engine_period_s(&loop.engine);
    double settled_s = 0.0;
    double peak_v = 0.0;
    double next_report = T_REPORT;
    while (sim_engine_time_s(&loop.engine) < T_END - 0.5 * Ts) {
        const double t_run = loop.t_run_s;
        status = qemu_loop_step(&loop, &cmd);
        if (status != 0) {
            return status;
        }
        const sim_trace_sample_t *s = loop.s;
        if (t_run < 0.0 && loop.t_run_s >= 0.0 && fabs(loop.t_run_s - T_RUN) > 0.5 * Ts) {
            return qemu_loop_fail("RUN not at the load's start");
        }
        const double tb = s->t_s - T_RUN;
        if (tb < 0.0) {
            continue;
        }
        const double err = s->plant.theta_m_rad - THETA_REF;
        if (!isfinite(err)) {
            return qemu_loop_fail("angle not finite");
        }
        if (fabs(err) > 1e-3) {
            settled_s = tb;
        }
        if (tb >= next_report - 0.5 * Ts) {
            qemu_loop_line("angle error", next_report, err, 7u, "rad");
            next_report += T_REPORT;
        }
        if (s->fw.state == MC_STATE_RUN) {
            peak_v = fmax(peak_v, SQRT_3_2 * hypot(s->fw.v_d_V, s->fw.v_q_V));
        }
    }
    const sim_trace_sample_t *s = loop.s;
    if (loop.t_run_s >= 0.0) {
        qemu_loop_check("final_angle_error_rad", s->plant.theta_m_rad - THETA_REF, 9u);
        qemu_loop_check("settled_s", settled_s, 5u);
        qemu_loop_check("peak_v_paper_V", peak_v, 4u);
    }
    status = qemu_loop_finish(&loop);
    if (status != 0) {
        return status;
    }
    if (!(peak_v <= V_DC / sqrt(2.0) * 1.0001)) {
        return qemu_loop_fail("voltage beyond the SVPWM circle");
    }
    qemu_m4_puts("PASS p000 eeo case 2\n");
    return 0;
}
