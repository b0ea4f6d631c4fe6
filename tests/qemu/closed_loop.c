/* The harness of the closed-loop QEMU images (closed_loop.h). */
#include "closed_loop.h"

#include "qemu_m4.h"

void qemu_loop_plant_default(plant_config_t *pc, double t_load_s, double tau_L_Nm)
{
    plant_config_default(pc);
    pc->substeps_per_period = PLANT_SUBSTEPS_FAST;
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
    if (sim_engine_init(&l->engine, pc, fc) != SIM_ENGINE_OK) {
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
    l->s = sim_engine_last(&l->engine);
    return 0;
}

static void print_at(const char *what, double t_s)
{
    qemu_m4_puts(" at t ");
    qemu_m4_put_fixed(t_s, 5u);
    qemu_m4_puts(what);
}

int qemu_loop_step(qemu_loop_t *l, const mc_command_t *cmd)
{
    const mc_state_t before = l->s->fw.state;
    if (sim_engine_step(&l->engine, cmd) != SIM_ENGINE_OK) {
        return qemu_loop_fail(sim_engine_message(&l->engine));
    }
    const sim_trace_sample_t *s = sim_engine_last(&l->engine);
    l->s = s;
    const uint32_t n = isr_meter_last();
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
    if (before == MC_STATE_RUN && s->fw.state == MC_STATE_RUN) {
        isr_stats_add(s->fw.slow_loop_ran ? &l->run_slow : &l->run_fast, n);
        if (s->fw.isr_cost_s > l->fw_cost_max_s) {
            l->fw_cost_max_s = s->fw.isr_cost_s;
        }
    } else if (s->fw.state == MC_STATE_CALIBRATING) {
        isr_stats_add(&l->calib, n);
    } else if (s->fw.state == MC_STATE_ALIGN) {
        isr_stats_add(&l->align, n);
    }
    if (l->t_run_s < 0.0 && s->fw.state == MC_STATE_RUN) {
        l->t_run_s = s->t_s;
        qemu_loop_check("t_run_s", l->t_run_s, 5u);
    }
    return 0;
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
    qemu_loop_check("fw_self_max_instr", (double)l->fw_cost_max_s * (double)QEMU_M4_CORE_HZ, 0u);
    if (l->s->fw.isr_overruns != 0u) {
        return qemu_loop_fail("ISR overrun");
    }
    return 0;
}
