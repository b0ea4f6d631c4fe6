/*
 * Paper 002's regulator (controller "cdobc", mc/ctl_cdobc.h) in closed
 * loop inside QEMU (mps2-an386, Cortex-M4F): the same firmware C code as
 * the bench's host_sim/scenarios/paper002_case1_cdobc.json, with the plant
 * (host_sim/plant, double precision = soft-float on the M4) in the image
 * through host_sim/engine and the hal/qemu_m4 binding.
 *
 * Configuration (= paper002_case1_cdobc.json and the paper002_case1_foc.json
 * it extends, without the current-sensor errors): paper 002 motor (n_p 4,
 * R 9.7 ohm, L 26 mH, psi 0.084 Wb, J 1.35e-4 kg m^2, B 7.4e-5 N m s/rad),
 * cogging 0.02 N m cos(32 theta_m), 300 V, 10 kHz, dead time 3 us with the
 * 0.29 A current band, not compensated, 2500-line encoder (PLL at the
 * default 1000 rad/s), ideal current sensors, plant with
 * PLANT_SUBSTEPS_FAST; CDOBC (the controller's defaults: 6th electrical +
 * 32nd mechanical harmonic models, polynomial N = 2, the observer's speed
 * from the count over 4 periods, designed at init for 500 rpm) with the
 * observer poles at -1000 rad/s and the reference prefilter to -230 rad/s;
 * no load. Speed reference 0 until
 * T_RUN = 25.6 ms (the end of the offset calibration, the scenario's
 * time_offset_s; checked against the first RUN sample), then 500 rpm; end
 * at T_RUN + QEMU_P002_T_S.
 *
 * Output: the harness's (closed_loop.h), the speed every 10 ms (printed
 * only), and the checkpoints (TRUE plant state):
 *   final_speed_rpm  mechanical speed at the end
 *   init_instr       instructions of the engine's initialisation (plant
 *                    and firmware init, the regulator's design in double)
 *   init_stack_bytes stack depth reached up to the end of it, main's
 *                    frame included (painted stack; the image has 64 kB;
 *                    the RUN ISRs reach less)
 * Exit status 0 only if RUN was reached at T_RUN, no fault latched, no
 * ISR overrun and the speed stayed finite.
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "closed_loop.h"
#include "qemu_m4.h"

#ifndef QEMU_P002_T_S
#error "define QEMU_P002_T_S (simulated seconds after the start of RUN)"
#endif

#define T_RUN       0.0256 /* s: end of the offset calibration */
#define RPM         (3.14159265358979323846 / 30.0)
#define W_REF_RPM   500.0
#define T_END       (T_RUN + (double)QEMU_P002_T_S)
#define T_REPORT    0.01 /* s between the printed speeds */
#define STACK_PAINT 0xA5A5A5A5u

/* CMSDK APB timer 0 of the board (25 MHz like SysTick, so 1.6 ticks per
 * instruction under -icount shift=6) as a 32-bit down counter: it spans
 * the initialisation, which can exceed SysTick's 24-bit range. */
#define TIMER0_CTRL   (*(volatile uint32_t *)0x40000000u)
#define TIMER0_VALUE  (*(volatile uint32_t *)0x40000004u)
#define TIMER0_RELOAD (*(volatile uint32_t *)0x40000008u)

extern uint32_t __StackLimit[];
extern uint32_t __StackTop[];

static qemu_loop_t loop;

/* Fill the stack from its limit up to 256 bytes below this frame. */
static void __attribute__((noinline)) paint_stack(void)
{
    volatile uint32_t here = 0u;
    uint32_t *end = (uint32_t *)((uintptr_t)&here - 256u);
    for (uint32_t *p = __StackLimit; p < end; p++) {
        *p = STACK_PAINT;
    }
}

/* Bytes from the stack's top to the deepest word written since the
 * painting. */
static uint32_t stack_used(void)
{
    const uint32_t *p = __StackLimit;
    while (p < __StackTop && *p == STACK_PAINT) {
        p++;
    }
    return (uint32_t)((uintptr_t)__StackTop - (uintptr_t)p);
}

static void plant_paper002(plant_config_t *pc)
{
    qemu_loop_plant_default(pc, 0.0, 0.0);
    pc->motor.R_ohm = 9.7;
    pc->motor.Ld_H = 0.026;
    pc->motor.Lq_H = 0.026;
    pc->motor.psi_Wb = 0.084;
    pc->motor.pole_pairs = 4u;
    pc->motor.J_kgm2 = 1.35e-4;
    pc->motor.B_Nm_s_rad = 7.4e-5;
    pc->motor.cogging.slots = 32u;
    pc->motor.cogging.n_harmonics = 1u;
    pc->motor.cogging.amplitude_Nm[0] = 0.02;
    pc->inverter.f_pwm_Hz = 10000.0;
    sim_profile_set_constant(&pc->inverter.v_dc_V, 300.0);
    pc->inverter.t_dead_s = 3e-6;
    pc->inverter.dead_time_current_band_A = 0.29;
    pc->sensors.encoder.lines = 2500u;
    pc->theta_m0_rad = 0.1472622; /* a cogging detent, as the scenario */
}

static void firmware_paper002(const plant_config_t *pc, mc_config_t *fc)
{
    mc_config_init_default(fc);
    sim_engine_firmware_from_plant(pc, fc);
    fc->controller = MC_CONTROLLER_CDOBC;
    fc->estimator = MC_ESTIMATOR_ENCODER;
    fc->cdobc.obs_pole_rad_s = 1000.0f;
    fc->cdobc.ref_pole_rad_s = 230.0f;
    fc->foc_pi.speed_bandwidth_rad_s = 200.0f;
    fc->deadtime.compensation = false;
    fc->emf_check.ratio_high = 10.0f;
    fc->limits.omega_max_rad_s = 100.0f;
    fc->limits.i_max_A = 6.0f;
    mc_fault_limits_t *p = &fc->protection;
    p->i_trip_A = 12.0f;
    p->v_dc_max_V = 400.0f;
    p->v_dc_min_V = 200.0f;
    p->current_limit_A = 9.0f;
    p->overspeed_rad_s = 120.0f;
    p->stall_current_A = 8.0f;
    p->i2t_continuous_A = 6.0f;
    p->i2t_peak_A = 10.0f;
}

int main(void)
{
    plant_config_t pc;
    plant_paper002(&pc);
    mc_config_t fc;
    firmware_paper002(&pc, &fc);
    sim_profile_t ref;
    sim_profile_clear(&ref);
    ref.points[0] = (sim_profile_point_t){ T_RUN, 0.0 };
    ref.points[1] = (sim_profile_point_t){ T_RUN, W_REF_RPM * RPM };
    ref.n_points = 2u;

    paint_stack();
    TIMER0_CTRL = 0u;
    TIMER0_RELOAD = 0xFFFFFFFFu;
    TIMER0_CTRL = 1u;
    const uint32_t t0 = TIMER0_VALUE;
    int status = qemu_loop_init(&loop, "qemu p002 cdobc case 1", &pc, &fc);
    const uint32_t t1 = TIMER0_VALUE;
    if (status != 0) {
        return status;
    }
    const uint32_t init_stack = stack_used();
    const double Ts = sim_engine_period_s(&loop.engine);
    double next_report = T_REPORT;
    while (sim_engine_time_s(&loop.engine) < T_END - 0.5 * Ts) {
        const double t_run = loop.t_run_s;
        const mc_command_t cmd = {
            .enable = true,
            .mode = MC_MODE_SPEED,
            .omega_m_ref_rad_s = (float)sim_profile_eval(&ref, sim_engine_time_s(&loop.engine)),
        };
        status = qemu_loop_step(&loop, &cmd);
        if (status != 0) {
            return status;
        }
        if (t_run < 0.0 && loop.t_run_s >= 0.0 && fabs(loop.t_run_s - T_RUN) > 0.5 * Ts) {
            return qemu_loop_fail("RUN not at the speed step");
        }
        const sim_trace_sample_t *s = loop.s;
        const double tb = s->t_s - T_RUN;
        if (!isfinite(s->plant.omega_m_rad_s)) {
            return qemu_loop_fail("speed not finite");
        }
        if (tb >= next_report - 0.5 * Ts) {
            qemu_loop_line("speed", next_report, s->plant.omega_m_rad_s / RPM, 4u, "rpm");
            next_report += T_REPORT;
        }
    }
    qemu_loop_check("final_speed_rpm", loop.s->plant.omega_m_rad_s / RPM, 4u);
    qemu_loop_check("init_instr", (double)qemu_m4_ticks_to_instr(t0 - t1), 0u);
    qemu_loop_check("init_stack_bytes", (double)init_stack, 0u);
    status = qemu_loop_finish(&loop);
    if (status != 0) {
        return status;
    }
    qemu_m4_puts("PASS p002 cdobc case 1\n");
    return 0;
}
