/* The harness of the closed-loop QEMU images (closed_loop.h). */
#include "closed_loop.h"

#include "qemu_m4.h"
#include "semihost.h"

#define SEMIHOST_SYS_READC 0x07u

volatile qemu_loop_report_t qemu_loop_report = { UINT32_MAX, 0u, 0u, 0u };

__attribute__((noinline)) void qemu_loop_report_begin(void)
{
    __asm volatile("" ::: "memory");
}

void qemu_loop_plant_default(plant_config_t *pc, double t_load_s, double tau_L_Nm)
{
    plant_config_default(pc);
    pc->substeps_per_period = PLANT_SUBSTEPS_FAST;
    /* the image's board compares the phase currents in hardware, as an
     * MCU's comparators into the timer's break input would: its steady
     * ISRs leave their levels to it (hal_pwm_overcurrent_arm) */
    pc->inverter.overcurrent_comparator = true;
    sim_profile_clear(&pc->load_torque_Nm);
    pc->load_torque_Nm.points[0] = (sim_profile_point_t){ t_load_s, 0.0 };
    pc->load_torque_Nm.points[1] = (sim_profile_point_t){ t_load_s, tau_L_Nm };
    pc->load_torque_Nm.n_points = 2u;
}

void qemu_loop_check(const char *name, double v, unsigned decimals)
{
    qemu_m4_puts("CHECK ");
    qemu_m4_puts(name);
    qemu_m4_puts(" ");
    qemu_m4_put_fixed(v, decimals);
    qemu_m4_puts("\n");
}

void qemu_loop_line(const char *what, double tb, double v, unsigned decimals, const char *unit)
{
    qemu_m4_puts(what);
    qemu_m4_puts(" at tb ");
    qemu_m4_put_fixed(tb, 2u);
    qemu_m4_puts(" s: ");
    qemu_m4_put_fixed(v, decimals);
    qemu_m4_puts(" ");
    qemu_m4_puts(unit);
    qemu_m4_puts("\n");
}

int qemu_loop_fail(const char *why)
{
    qemu_m4_puts("FAIL: ");
    qemu_m4_puts(why);
    qemu_m4_puts("\n");
    return 1;
}

int qemu_loop_init(qemu_loop_t *l, const char *title, const plant_config_t *pc,
                   const mc_config_t *fc)
{
    qemu_m4_puts(title);
    qemu_m4_puts("\n");
    /* the drive as an MCU build runs it: its steady RUN ISRs between slow
     * ticks spare the telemetry record's stores (mc/timing.h) */
    mc_config_t mcu = *fc;
    mcu.timing.telemetry_every_isr = false;
    if (sim_engine_init(&l->engine, pc, &mcu) != SIM_ENGINE_OK) {
        qemu_m4_puts(sim_engine_message(&l->engine));
        return qemu_loop_fail("sim_engine_init");
    }
    qemu_m4_puts("counter overhead (instr) ");
    qemu_m4_put_u32(isr_meter_overhead());
    qemu_m4_puts("\n");
    isr_stats_reset(&l->calib);
    isr_stats_reset(&l->align);
    isr_stats_reset(&l->run_fast);
    isr_stats_reset(&l->run_slow);
    l->t_run_s = -1.0;
    l->fw_cost_max_s = 0.0f;
    l->isr_index = 0u;
    l->reported = 0u;
    l->report_state = 0;
    l->s = sim_engine_last(&l->engine);
    return 0;
}

static void print_at(const char *what, double t_s)
{
    qemu_m4_puts(" at t ");
    qemu_m4_put_fixed(t_s, 5u);
    qemu_m4_puts(what);
}

/* The ISR report (closed_loop.h): one line for the ISR just run, or the
 * mark before the first reported ISR. 0 or QEMU_LOOP_STOPPED. */
static int report(qemu_loop_t *l, uint32_t index, uint32_t n, const char *cls)
{
    if (l->report_state == 1) {
        qemu_m4_puts("ISR ");
        qemu_m4_put_u32(index);
        qemu_m4_puts(" ");
        qemu_m4_put_u32(n);
        qemu_m4_puts(" ");
        qemu_m4_puts(cls);
        qemu_m4_puts("\n");
        l->reported++;
    }
    if (l->report_state == 1 && l->reported >= qemu_loop_report.count) {
        l->report_state = 2;
        qemu_m4_puts("ISR report done\n");
        if (qemu_loop_report.stop != 0u) {
            qemu_m4_puts("STOP after the ISR report\n");
            return QEMU_LOOP_STOPPED;
        }
    }
    if (l->report_state == 0 && l->s->fw.state == MC_STATE_RUN &&
        l->run_fast.n + l->run_slow.n >= qemu_loop_report.skip) {
        l->report_state = qemu_loop_report.count > 0u ? 1 : 2;
        if (qemu_loop_report.wait != 0u) {
            qemu_m4_puts("ISR report: waiting\n");
            (void)semihost_call(SEMIHOST_SYS_READC, 0u);
        }
        qemu_loop_report_begin();
    }
    return 0;
}

int qemu_loop_step(qemu_loop_t *l, const mc_command_t *cmd)
{
    const mc_state_t before = l->s->fw.state;
    const uint32_t published_before = l->s->fw.isr_count;
    if (sim_engine_step(&l->engine, cmd) != SIM_ENGINE_OK) {
        return qemu_loop_fail(sim_engine_message(&l->engine));
    }
    const sim_trace_sample_t *s = sim_engine_last(&l->engine);
    l->s = s;
    const uint32_t n = isr_meter_last();
    const uint32_t index = l->isr_index++;
    const char *cls = "other";
    if (s->fw.state != before) {
        qemu_m4_puts("state ");
        qemu_m4_put_u32((uint32_t)s->fw.state);
        print_at(" s\n", s->t_s);
    }
    if (s->fw.faults_latched != 0u) {
        qemu_m4_puts("faults 0x");
        qemu_m4_put_u32(s->fw.faults_latched);
        print_at("\n", s->t_s);
        return qemu_loop_fail("fault latched");
    }
    /* The record as the ISR before left it: a steady RUN ISR between
     * slow ticks, the one kind that does not write it (mc/timing.h). */
    const bool published = s->fw.isr_count != published_before;
    if (!published) {
        isr_stats_add(&l->run_fast, n);
        cls = "run_fast";
    } else if (before == MC_STATE_RUN && s->fw.state == MC_STATE_RUN) {
        isr_stats_add(s->fw.slow_loop_ran ? &l->run_slow : &l->run_fast, n);
        cls = s->fw.slow_loop_ran ? "run_slow" : "run_fast";
        if (s->fw.isr_cost_s > l->fw_cost_max_s) {
            l->fw_cost_max_s = s->fw.isr_cost_s;
        }
    } else if (s->fw.state == MC_STATE_CALIBRATING) {
        isr_stats_add(&l->calib, n);
        cls = "calib";
    } else if (s->fw.state == MC_STATE_ALIGN) {
        isr_stats_add(&l->align, n);
        cls = "align";
    }
    if (l->t_run_s < 0.0 && s->fw.state == MC_STATE_RUN) {
        l->t_run_s = s->t_s;
        qemu_loop_check("t_run_s", l->t_run_s, 5u);
    }
    return report(l, index, n, cls);
}

static double mean(const isr_stats_t *s)
{
    return s->n ? (double)s->sum / (double)s->n : 0.0;
}

int qemu_loop_finish(const qemu_loop_t *l)
{
    if (l->t_run_s < 0.0) {
        return qemu_loop_fail("RUN never reached");
    }
    qemu_loop_check("isr_overruns", (double)l->s->fw.isr_overruns, 0u);
    isr_stats_print("isr calib", &l->calib);
    isr_stats_print("isr align", &l->align);
    isr_stats_print("isr run_fast", &l->run_fast);
    isr_stats_print("isr run_slow", &l->run_slow);
    qemu_loop_check("run_fast_max_instr", (double)l->run_fast.max, 0u);
    qemu_loop_check("run_slow_max_instr", (double)l->run_slow.max, 0u);
    qemu_loop_check("run_slow_count", (double)l->run_slow.n, 0u);
    qemu_loop_check("run_fast_count", (double)l->run_fast.n, 0u);
    qemu_loop_check("run_fast_mean_instr", mean(&l->run_fast), 3u);
    qemu_loop_check("run_slow_mean_instr", mean(&l->run_slow), 3u);
    const uint32_t run_n = l->run_fast.n + l->run_slow.n;
    qemu_loop_check("run_max_instr",
                    (double)(l->run_fast.max > l->run_slow.max ? l->run_fast.max : l->run_slow.max),
                    0u);
    qemu_loop_check("run_mean_instr",
                    run_n ? (double)(l->run_fast.sum + l->run_slow.sum) / (double)run_n : 0.0, 3u);
    qemu_loop_check("isr_meter_errors", (double)isr_meter_errors(), 0u);
    qemu_loop_check("mc_app_bytes", (double)sizeof l->engine.app, 0u);
    qemu_loop_check("fw_self_max_instr", (double)l->fw_cost_max_s * (double)QEMU_M4_CORE_HZ, 0u);
    if (l->s->fw.isr_overruns != 0u) {
        return qemu_loop_fail("ISR overrun");
    }
    return 0;
}
