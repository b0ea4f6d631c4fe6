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
 * Output (semihosting), parsed by run_qemu_test.py:
 *   CHECK <name> <value>   checkpoints (TRUE plant state) and counts
 *   isr ...                instruction statistics
 * Exit status 0 only if RUN was reached, no fault latched, no ISR overrun,
 * and the final true speed is within 2 % of W_REF (the image's own
 * plausibility check; the ctest compares the CHECK values with analytic
 * expectations independently).
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "isr_meter.h"
#include "qemu_m4.h"
#include "sim_engine.h"

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

static sim_engine_t engine;

static void check_line(const char *name, double v, unsigned decimals)
{
    qemu_m4_puts("CHECK ");
    qemu_m4_puts(name);
    qemu_m4_puts(" ");
    qemu_m4_put_fixed(v, decimals);
    qemu_m4_puts("\n");
}

static int fail(const char *why)
{
    qemu_m4_puts("FAIL: ");
    qemu_m4_puts(why);
    qemu_m4_puts("\n");
    return 1;
}

int main(void)
{
    qemu_m4_puts("qemu p001 " SCEN_NAME "\n");
    plant_config_t pc;
    plant_config_default(&pc);
    pc.substeps_per_period = PLANT_SUBSTEPS_FAST;
    sim_profile_clear(&pc.load_torque_Nm);
    pc.load_torque_Nm.points[0] = (sim_profile_point_t){ T_LOAD, 0.0 };
    pc.load_torque_Nm.points[1] = (sim_profile_point_t){ T_LOAD, TAU_L };
    pc.load_torque_Nm.n_points = 2u;

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
    if (sim_engine_init(&engine, &pc, &fc) != SIM_ENGINE_OK) {
        qemu_m4_puts(sim_engine_message(&engine));
        return fail("sim_engine_init");
    }
    qemu_m4_puts("counter overhead (instr) ");
    qemu_m4_put_u32(isr_meter_overhead());
    qemu_m4_puts("\n");

    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    isr_stats_t st_fast, st_slow, st_calib, st_align;
    isr_stats_reset(&st_fast);
    isr_stats_reset(&st_slow);
    isr_stats_reset(&st_calib);
    isr_stats_reset(&st_align);
    double t_run = -1.0;
    bool noload_done = false;
    float fw_cost_max_s = 0.0f;
    const sim_trace_sample_t *s = sim_engine_last(&engine);
    while (sim_engine_time_s(&engine) < T_END) {
        const double t = sim_engine_time_s(&engine);
        cmd.omega_m_ref_rad_s = (t_run >= 0.0 && t - t_run >= T_STEP) ? (float)W_REF : 0.0f;
        const mc_state_t before = s->fw.state;
        if (sim_engine_step(&engine, &cmd) != SIM_ENGINE_OK) {
            return fail(sim_engine_message(&engine));
        }
        s = sim_engine_last(&engine);
        const uint32_t n = isr_meter_last();
        if (s->fw.state != before) {
            qemu_m4_puts("state ");
            qemu_m4_put_u32((uint32_t)s->fw.state);
            qemu_m4_puts(" at t ");
            qemu_m4_put_fixed(s->t_s, 5u);
            qemu_m4_puts(" s\n");
        }
        if (s->fw.faults_latched != 0u) {
            qemu_m4_puts("faults 0x");
            qemu_m4_put_u32(s->fw.faults_latched);
            qemu_m4_puts(" at t ");
            qemu_m4_put_fixed(s->t_s, 5u);
            qemu_m4_puts("\n");
            return fail("fault latched");
        }
        if (before == MC_STATE_RUN && s->fw.state == MC_STATE_RUN) {
            isr_stats_add(s->fw.slow_loop_ran ? &st_slow : &st_fast, n);
            if (s->fw.isr_cost_s > fw_cost_max_s) {
                fw_cost_max_s = s->fw.isr_cost_s;
            }
        } else if (s->fw.state == MC_STATE_CALIBRATING) {
            isr_stats_add(&st_calib, n);
        } else if (s->fw.state == MC_STATE_ALIGN) {
            isr_stats_add(&st_align, n);
        }
        if (t_run < 0.0 && s->fw.state == MC_STATE_RUN) {
            t_run = s->t_s;
            check_line("t_run_s", t_run, 5u);
            if (t_run + T_STEP + 0.15 > T_LOAD) {
                return fail("RUN too late for the load step");
            }
        }
        if (!noload_done && s->t_s >= T_CHECK_NOLOAD) {
            noload_done = true;
            check_line("noload_omega_m_rad_s", s->plant.omega_m_rad_s, 5u);
            check_line("noload_i_q_A", s->plant.i_q_A, 5u);
        }
    }
    if (t_run < 0.0) {
        return fail("RUN never reached");
    }
    /* Final: the true state at the last sample, the firmware's speed and
     * load estimates. */
    check_line("final_omega_m_rad_s", s->plant.omega_m_rad_s, 5u);
    check_line("final_i_q_A", s->plant.i_q_A, 5u);
    check_line("final_i_d_A", s->plant.i_d_A, 5u);
    check_line("final_fw_omega_m_rad_s", (double)s->fw.omega_m_rad_s, 5u);
    check_line("isr_overruns", (double)s->fw.isr_overruns, 0u);
    isr_stats_print("isr calib", &st_calib);
    isr_stats_print("isr align", &st_align);
    isr_stats_print("isr run_fast", &st_fast);
    isr_stats_print("isr run_slow", &st_slow);
    check_line("run_fast_max_instr", (double)st_fast.max, 0u);
    check_line("run_slow_max_instr", (double)st_slow.max, 0u);
    check_line("run_slow_count", (double)st_slow.n, 0u);
    check_line("run_fast_count", (double)st_fast.n, 0u);
    /* The firmware's own deadline measurement (hal_cycle_counter):
     * instructions from its first to its last counter read. */
    check_line("fw_self_max_instr", (double)fw_cost_max_s * (double)QEMU_M4_CORE_HZ, 0u);
    if (s->fw.isr_overruns != 0u) {
        return fail("ISR overrun");
    }
    if (!(fabs(s->plant.omega_m_rad_s - W_REF) <= 0.02 * W_REF)) {
        return fail("final speed not within 2 % of the reference");
    }
    qemu_m4_puts("PASS " SCEN_NAME "\n");
    return 0;
}
