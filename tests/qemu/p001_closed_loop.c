/*
 * Closed loop inside QEMU (mps2-an386, Cortex-M4F): the paper-001 motor
 * (host_sim/plant, double precision, fast RK4 option) driven by the real
 * firmware through host_sim/engine and the hal/qemu_m4 binding, 20 kHz.
 *
 * Build-time scenario (QEMU_P001_SCENARIO):
 *   1 FOC     encoder + PLL, cascaded FOC PI (mc_config_init_default)
 * (the firmware takes the motor, PWM rate and encoder from the plant:
 * sim_engine_firmware_from_plant)
 *   2 IDAPBC  sensorless: flux observer + I&I speed/load observer, IDA-PBC
 *   3 NAM     sensorless baseline: flux observer + PLL, FOC PI
 * Timeline (t_r = time since the first RUN ISR): enable at t = 0
 * (calibration, and ALIGN for the sensorless drives), speed reference 0
 * until t_r = T_STEP, then W_REF; load torque TAU_L from the absolute time
 * T_LOAD (after RUN + the step's settling, checked), end at T_END.
 *
 * Output: the harness's (closed_loop.h) plus noload_* and final_* (TRUE
 * plant state).
 * Exit status 0 only if RUN was reached, no fault latched, no ISR overrun,
 * and the final true speed is within 2 % of W_REF (the image's own
 * plausibility check; the ctest compares the CHECK values with analytic
 * expectations independently).
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "closed_loop.h"
#include "qemu_m4.h"

#ifndef QEMU_P001_SCENARIO
#error "define QEMU_P001_SCENARIO (1 FOC, 2 IDAPBC, 3 NAM)"
#endif

#if QEMU_P001_SCENARIO == 1
#define SCEN_NAME "foc_encoder"
#define W_REF     20.0 /* rad/s mechanical (191 rpm) */
#define T_STEP    0.01 /* s after RUN */
#define T_LOAD    0.5  /* s absolute */
#define T_END     1.0
#else
#if QEMU_P001_SCENARIO == 2
#define SCEN_NAME "idapbc_sensorless"
#else
#define SCEN_NAME "nam_sensorless"
#endif
#define W_REF  5.0 /* rad/s mechanical (48 rpm, paper 001's 50 rpm) */
#define T_STEP 0.01
#define T_LOAD 1.8 /* ALIGN ends at about 1.31 s from theta = 0 */
#define T_END  2.6
#endif
#define TAU_L          0.5 /* N m */
#define T_CHECK_NOLOAD (T_LOAD - 0.01)

static qemu_loop_t loop;

int main(void)
{
    plant_config_t pc;
    qemu_loop_plant_default(&pc, T_LOAD, TAU_L);

    mc_config_t fc;
    mc_config_init_default(&fc);
    sim_engine_firmware_from_plant(&pc, &fc);
#if QEMU_P001_SCENARIO == 2
    fc.estimator = MC_ESTIMATOR_FLUX_II;
    fc.controller = MC_CONTROLLER_IDAPBC;
#elif QEMU_P001_SCENARIO == 3
    fc.estimator = MC_ESTIMATOR_FLUX_PLL;
    fc.controller = MC_CONTROLLER_FOC_PI;
#endif
    int status = qemu_loop_init(&loop, "qemu p001 " SCEN_NAME, &pc, &fc);
    if (status != 0) {
        return status;
    }
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    bool noload_done = false;
    while (sim_engine_time_s(&loop.engine) < T_END) {
        const double t = sim_engine_time_s(&loop.engine);
        const double t_run = loop.t_run_s;
        cmd.omega_m_ref_rad_s = (t_run >= 0.0 && t - t_run >= T_STEP) ? (float)W_REF : 0.0f;
        status = qemu_loop_step(&loop, &cmd);
        if (status != 0) {
            return status;
        }
        const sim_trace_sample_t *s = loop.s;
        if (t_run < 0.0 && loop.t_run_s >= 0.0 && loop.t_run_s + T_STEP + 0.15 > T_LOAD) {
            return qemu_loop_fail("RUN too late for the load step");
        }
        if (!noload_done && s->t_s >= T_CHECK_NOLOAD) {
            noload_done = true;
            qemu_loop_check("noload_omega_m_rad_s", s->plant.omega_m_rad_s, 5u);
            qemu_loop_check("noload_i_q_A", s->plant.i_q_A, 5u);
        }
    }
    /* Final: the true state at the last sample, the firmware's speed
     * estimate. */
    const sim_trace_sample_t *s = loop.s;
    if (loop.t_run_s >= 0.0) {
        qemu_loop_check("final_omega_m_rad_s", s->plant.omega_m_rad_s, 5u);
        qemu_loop_check("final_i_q_A", s->plant.i_q_A, 5u);
        qemu_loop_check("final_i_d_A", s->plant.i_d_A, 5u);
        qemu_loop_check("final_fw_omega_m_rad_s", (double)s->fw.omega_m_rad_s, 5u);
    }
    status = qemu_loop_finish(&loop);
    if (status != 0) {
        return status;
    }
    if (!(fabs(s->plant.omega_m_rad_s - W_REF) <= 0.02 * W_REF)) {
        return qemu_loop_fail("final speed not within 2 % of the reference");
    }
    qemu_m4_puts("PASS " SCEN_NAME "\n");
    return 0;
}
