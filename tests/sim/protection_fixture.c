#include "protection_fixture.h"

#include "mc_test.h"

#include <math.h>

#include "test_p001_bench.h"

mc_command_t prot_command;

mc_command_t prot_fixed_cmd(double t_s)
{
    (void)t_s;
    return prot_command;
}

mc_command_t prot_bench_cmd(double t_s)
{
    const double rpm = bench_ref_rpm(t_s - BENCH_T0_S);
    return (mc_command_t){ .enable = true,
                           .mode = MC_MODE_SPEED,
                           .omega_m_ref_rad_s = (float)(rpm / BENCH_RPM_PER_RAD_S) };
}

static double max_abs3(const double x[3])
{
    return fmax(fabs(x[0]), fmax(fabs(x[1]), fabs(x[2])));
}

prot_result_t prot_run(sim_engine_t *e, prot_command_fn cmd, double t_end_s, double t_after_s,
                       double i_max_A, double t_watch_s)
{
    return prot_run_observed(e, cmd, t_end_s, t_after_s, i_max_A, t_watch_s, NULL, NULL);
}

prot_result_t prot_run_observed(sim_engine_t *e, prot_command_fn cmd, double t_end_s,
                                double t_after_s, double i_max_A, double t_watch_s,
                                prot_observer_fn obs, void *ctx)
{
    prot_result_t r = { .t_fault_s = -1.0, .t_run_s = -1.0, .t_first_over_i_max_s = -1.0 };
    const double Ts = sim_engine_period_s(e);
    double t_stop = t_end_s;
    while (sim_engine_time_s(e) < t_stop - 0.5 * Ts) {
        const mc_command_t c = cmd(sim_engine_time_s(e));
        assert_int_equal(sim_engine_step(e, &c), SIM_ENGINE_OK);
        const sim_trace_sample_t *s = sim_engine_last(e);
        if (obs != NULL) {
            obs(s, ctx);
        }
        if (r.t_run_s < 0.0 && s->fw.state == MC_STATE_RUN) {
            r.t_run_s = s->t_s;
        }
        const double i = max_abs3(s->plant.i_abc_A);
        r.i_peak_A = fmax(r.i_peak_A, i);
        if (s->t_s >= t_watch_s - 0.5 * Ts) {
            r.i_peak_watch_A = fmax(r.i_peak_watch_A, i);
        }
        r.v_dc_max_V = fmax(r.v_dc_max_V, s->plant.v_dc_V);
        if (i > i_max_A) {
            if (r.t_first_over_i_max_s < 0.0) {
                r.t_first_over_i_max_s = s->t_s;
            }
            r.t_over_i_max_s += Ts;
        }
        if (r.t_first_over_i_max_s >= 0.0) {
            r.i_peak_after_i_max_A = fmax(r.i_peak_after_i_max_A, i);
        }
        if (r.t_fault_s < 0.0) {
            r.omega_max_abs_rad_s = fmax(r.omega_max_abs_rad_s, fabs(s->plant.omega_m_rad_s));
            if (s->fw.faults_latched != 0u) {
                r.first_fault = s->fw.first_fault;
                r.t_fault_s = s->t_s;
                r.outputs_off_at_fault = !s->outputs_applied;
                t_stop = fmin(t_end_s, s->t_s + t_after_s);
            }
        }
    }
    return r;
}

void prot_inject(sim_engine_t *e, const sim_injection_t *inj)
{
    const int rc = sim_engine_add_injection(e, inj);
    if (rc != SIM_ENGINE_OK) {
        print_error("injection: %s\n", sim_engine_message(e));
    }
    assert_int_equal(rc, SIM_ENGINE_OK);
}

void prot_print(const char *label, const prot_result_t *r)
{
    print_message("%s: first fault 0x%x at %.5f s (RUN from %.4f s), outputs off %d; "
                  "peak |i| %.3f A (%.3f A from the injection), above i_max from %.5f s for %.4f s "
                  "(peak %.3f A); "
                  "max |omega| before %.3f rad/s; max v_dc %.3f V\n",
                  label, (unsigned)r->first_fault, r->t_fault_s, r->t_run_s,
                  (int)r->outputs_off_at_fault, r->i_peak_A, r->i_peak_watch_A,
                  r->t_first_over_i_max_s, r->t_over_i_max_s, r->i_peak_after_i_max_A,
                  r->omega_max_abs_rad_s, r->v_dc_max_V);
}
