/*
 * Overspeed, a locked rotor under the baseline FOC (stall) and the I^2 t
 * thermal model, in closed loop on the paper-001 motor (J = 0.012 kg m^2,
 * no friction, kt = 1.5 n_p psi = 0.765 N m / A; firmware defaults,
 * mc/config.h).
 *
 * Overspeed: current mode at i_q = i_max = 10 A, no load, a 56 V source
 * (at 48 V the back-EMF near 48 rad/s saturates the modulator and the
 * current falls short of 10 A): the rotor accelerates at kt i_max / J =
 * 637.5 rad/s^2 and passes the 48 rad/s trip J omega_os / (kt i_max) =
 * 75.3 ms after RUN, later by the current's rise (the loop's 1 / w_c =
 * 0.4 ms, and its recovery from the feed-forward's lagging speed: within
 * 2 ms in all). The encoder speed (the integral branch of a type-2 PLL, a
 * low-pass w_pll^2 / (s + w_pll)^2 of the speed) lags a ramp by
 * 2 / w_pll = 2 ms; the supervision sees the estimate on the slow tick
 * (mc/app.h), up to N - 1 = 9 samples later: MC_FAULT_OVERSPEED 2 ms (+ up
 * to two samples + 9 samples) after the TRUE speed passed 48 rad/s, which
 * is then below 48 + 637.5 x 2.55 ms = 49.6 rad/s. The reaction, coasting, must not charge the bus
 * (mc/app.h): on a 1 mF link behind the source (which cannot sink current) the line back-EMF at 50
 * rad/s (44 V) stays below the link: once the phase currents have decayed through the diodes (their
 * magnetic energy, 0.29 J, lifts the link by a few volts) no phase conducts and the link voltage
 * stays where it is, below the 60 V trip.
 *
 * Stall: speed mode at 8 rad/s, a shaft brake at 0.3 s: the encoder sees
 * the stop within a few 1 / w_pll, the speed loop asks for i_max: |i| >
 * 7 A at |omega_hat| < 1 rad/s, held stall_time_s = 0.5 s:
 * MC_FAULT_STALL in [0.5, 0.52] s after the lock, current <= i_max + 5 %.
 *
 * Sustained current limit: the paper's IDA-PBC (sensorless, benchmark
 * start, 50 rpm) meets a 9 N m load step at tb = 1.5 s, more than the
 * 8.4 N m of the 11 A limit: the limit loop (mc/current_limit.h) holds the
 * measured |i| at 11 A and, acting for current_limit_time_s = 0.1 s
 * without a break, faults: MC_FAULT_CURRENT_LIMIT 0.1 s (- one slow tick
 * T = 0.5 ms: the supervision samples the loop's activity on the tick, the
 * first tick within T after it engages, the fault 0.1 s / T - 1 ticks
 * later; - two samples: the loop sees |i_dq|, the phase maximum may cross
 * a sample later; + 5 ms for the loop's engagement) after the true phase
 * current first passed 11 A; the true current above 11 A for at most
 * those 0.1 s + T, peak
 * below 11 A + 5 % (a first-order loop does not overshoot; 5 % for the
 * discretisation and the back-EMF).
 *
 * I^2 t: speed mode at 10 rad/s against a 6.12 N m load (8.0 A): the
 * thermal state x' = |i|^2 - i_cont^2 (x >= 0) integrated in double from
 * the TRUE currents at the slow ticks (the supervision's samples, period
 * T = 0.5 ms; independent of the firmware's float sum) crosses the limit
 * (i_peak^2 - i_cont^2) t_peak = 150 A^2 s in the tick the drive faults
 * (one tick is 64 A^2 x 0.5 ms = 3.2e-2 A^2 s), about 150 / (64 - 25) =
 * 3.85 s after the current rose: MC_FAULT_I2T; integrated from every
 * sample it is then within 0.1 % of the limit (the subsampling of a
 * steady current).
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "protection_fixture.h"
#include "test_p001_bench.h"

#define J_KGM2 0.012

static double kt(const mc_config_t *fc)
{
    return 1.5 * fc->motor.pole_pairs * (double)fc->motor.psi_Wb;
}

/* ---- overspeed ----------------------------------------------------------- */

typedef struct {
    double os_rad_s, t_cross_s; /* the trip; the true speed's crossing */
    double t_fault_s;           /* from the firmware's latch */
    double t_settled_s;
    double v_dc_settled_V, v_dc_end_V, v_dc_max_V;
    bool conducting_after_settle;
} coast_t;

static void watch_coast(const sim_trace_sample_t *s, void *ctx)
{
    coast_t *c = ctx;
    if (c->t_cross_s < 0.0 && fabs(s->plant.omega_m_rad_s) > c->os_rad_s) {
        c->t_cross_s = s->t_s;
    }
    c->v_dc_max_V = fmax(c->v_dc_max_V, s->plant.v_dc_V);
    if (c->t_fault_s < 0.0 && s->fw.faults_latched != 0u) {
        c->t_fault_s = s->t_s;
        c->t_settled_s = s->t_s + 0.005; /* 5 ms: the currents have decayed */
    }
    if (c->t_fault_s >= 0.0 && s->t_s >= c->t_settled_s) {
        if (c->v_dc_settled_V < 0.0) {
            c->v_dc_settled_V = s->plant.v_dc_V;
        }
        c->v_dc_end_V = s->plant.v_dc_V;
        c->conducting_after_settle |= !s->plant.open_circuit;
    }
}

static void test_overspeed(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    sim_profile_set_constant(&pc.inverter.v_dc_V, 56.0);
    pc.dc_link.capacitance_F = 1e-3;
    pc.dc_link.source_resistance_ohm = 0.05;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    prot_command =
        (mc_command_t){ .enable = true, .mode = MC_MODE_CURRENT, .i_q_ref_A = fc.limits.i_max_A };
    coast_t c = { .os_rad_s = (double)fc.protection.overspeed_rad_s,
                  .t_cross_s = -1.0,
                  .t_fault_s = -1.0,
                  .v_dc_settled_V = -1.0 };
    const prot_result_t r =
        prot_run_observed(e, prot_fixed_cmd, 0.5, 0.2, fc.limits.i_max_A, 0.0, watch_coast, &c);
    prot_print("overspeed, 10 A unloaded", &r);
    print_message("  true speed above the trip from %.5f s (analytic %.5f s)\n", c.t_cross_s,
                  r.t_run_s + J_KGM2 * c.os_rad_s / (kt(&fc) * (double)fc.limits.i_max_A));
    print_message("  coast: link %.4f V 5 ms after the fault, %.4f V at the end, max %.4f V; "
                  "a phase conducting after that: %d\n",
                  c.v_dc_settled_V, c.v_dc_end_V, c.v_dc_max_V, (int)c.conducting_after_settle);
    free(e);
    const double os = (double)fc.protection.overspeed_rad_s;
    const double a = kt(&fc) * (double)fc.limits.i_max_A / J_KGM2;
    const double t_an = r.t_run_s + os / a;
    const double Ts = 1.0 / (double)fc.timing.f_pwm_Hz;
    const double n_slow = round((double)fc.timing.f_pwm_Hz / (double)fc.timing.slow_loop_Hz);
    const double lag = 2.0 / (double)fc.encoder.pll_bandwidth_rad_s + (1.0 + n_slow) * Ts;
    assert_int_equal(r.first_fault, MC_FAULT_OVERSPEED);
    assert_true(r.outputs_off_at_fault);
    assert_true(c.t_cross_s >= t_an && c.t_cross_s <= t_an + 0.002);
    assert_true(r.t_fault_s >= c.t_cross_s);
    assert_true(r.t_fault_s <= c.t_cross_s + lag);
    assert_true(r.omega_max_abs_rad_s <= os + a * lag);
    /* coasting: no conduction once the currents decayed, the link holds */
    assert_false(c.conducting_after_settle);
    assert_true(fabs(c.v_dc_end_V - c.v_dc_settled_V) <= 1e-9 * c.v_dc_settled_V);
    assert_true(c.v_dc_max_V < (double)fc.protection.v_dc_max_V);
}

/* ---- stall --------------------------------------------------------------- */

static void test_stall_locked_rotor(void **state)
{
    (void)state;
    const double t_lock = 0.3;
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const sim_injection_t inj = { .kind = SIM_INJECT_ROTOR_LOCK,
                                  .t_start_s = t_lock,
                                  .t_end_s = INFINITY };
    prot_inject(e, &inj);
    prot_command =
        (mc_command_t){ .enable = true, .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = 8.0f };
    const prot_result_t r = prot_run(e, prot_fixed_cmd, 2.0, 0.05, fc.limits.i_max_A, t_lock);
    prot_print("locked rotor, FOC at 8 rad/s", &r);
    free(e);
    const double t_stall = (double)fc.protection.stall_time_s;
    assert_int_equal(r.first_fault, MC_FAULT_STALL);
    assert_true(r.outputs_off_at_fault);
    assert_true(r.t_fault_s >= t_lock + t_stall);
    assert_true(r.t_fault_s <= t_lock + t_stall + 0.02);
    assert_true(r.i_peak_watch_A <= 1.05 * (double)fc.limits.i_max_A);
}

/* ---- I^2 t --------------------------------------------------------------- */

typedef struct {
    double i_cont_sq, limit, Ts, T_tick;
    double x;          /* true thermal state, every sample, A^2 s */
    double x_tick;     /* the same from the slow ticks' samples */
    double x_at_fault; /* at the faulting tick */
    double x_tick_at_fault;
    double x_tick_before;   /* at the tick before it */
    long k, k_tick;         /* this sample, the latest tick */
    long fault_ticks_after; /* samples from that tick to the fault */
    double t_heating_s;     /* first sample with |i| > i_cont */
    bool latched;
} thermal_t;

static void watch_thermal(const sim_trace_sample_t *s, void *ctx)
{
    thermal_t *th = ctx;
    if (th->latched) {
        return;
    }
    const double i_sq = s->plant.i_d_A * s->plant.i_d_A + s->plant.i_q_A * s->plant.i_q_A;
    if (th->t_heating_s < 0.0 && i_sq > th->i_cont_sq) {
        th->t_heating_s = s->t_s;
    }
    th->x = fmax(0.0, th->x + (i_sq - th->i_cont_sq) * th->Ts);
    th->k++;
    /* the slow ticks: slow_loop_ran in speed mode, and the faulting ISR
     * (its supervision faults before the control, which does not run) */
    const bool faulted = s->fw.faults_latched != 0u;
    if (s->fw.slow_loop_ran || faulted) {
        th->x_tick_before = th->x_tick;
        th->x_tick = fmax(0.0, th->x_tick + (i_sq - th->i_cont_sq) * th->T_tick);
        th->fault_ticks_after = th->k - th->k_tick;
        th->k_tick = th->k;
    }
    if (faulted) {
        th->latched = true;
        th->x_at_fault = th->x;
        th->x_tick_at_fault = th->x_tick;
    }
}

static void test_i2t(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    const double i_load = 8.0;
    sim_profile_set_constant(&pc.load_torque_Nm, kt(&fc) * i_load);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const mc_fault_limits_t *p = &fc.protection;
    thermal_t th = {
        .i_cont_sq = (double)p->i2t_continuous_A * (double)p->i2t_continuous_A,
        .limit = ((double)p->i2t_peak_A * (double)p->i2t_peak_A -
                  (double)p->i2t_continuous_A * (double)p->i2t_continuous_A) *
                 (double)p->i2t_peak_time_s,
        .Ts = sim_engine_period_s(e),
        .T_tick = 1.0 / (double)fc.timing.slow_loop_Hz,
        .t_heating_s = -1.0,
    };
    prot_command =
        (mc_command_t){ .enable = true, .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = 10.0f };
    const prot_result_t r =
        prot_run_observed(e, prot_fixed_cmd, 6.0, 0.01, fc.limits.i_max_A, 0.0, watch_thermal, &th);
    prot_print("I^2 t, 8 A at 10 rad/s", &r);
    print_message("  true thermal state at the ticks %.6f A^2 s at the fault (limit %.1f), "
                  "%.6f before; from every sample %.6f; %.4f s after the current passed "
                  "i_cont (steady 8 A: %.4f s)\n",
                  th.x_tick_at_fault, th.limit, th.x_tick_before, th.x_at_fault,
                  r.t_fault_s - th.t_heating_s, th.limit / (i_load * i_load - th.i_cont_sq));
    free(e);
    assert_int_equal(r.first_fault, MC_FAULT_I2T);
    assert_true(r.outputs_off_at_fault);
    /* the crossing tick, to the float rounding of the firmware's
     * measured-current sum (1e-5 relative) */
    assert_true(fabs(th.fault_ticks_after * th.Ts - th.T_tick) < 0.01 * th.Ts); /* on a tick */
    assert_true(th.x_tick_at_fault > th.limit * (1.0 - 1e-5));
    assert_true(th.x_tick_before <= th.limit * (1.0 + 1e-5));
    assert_true(fabs(th.x_at_fault - th.limit) <= 1e-3 * th.limit);
    assert_true(r.i_peak_A <= 1.05 * (double)fc.limits.i_max_A);
}

/* ---- sustained current limit ----------------------------------------------- */

static void test_current_limit_idapbc(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    sim_profile_clear(&pc.load_torque_Nm);
    pc.load_torque_Nm.points[0] = (sim_profile_point_t){ BENCH_T0_S + 1.5, 0.0 };
    pc.load_torque_Nm.points[1] = (sim_profile_point_t){ BENCH_T0_S + 1.5, 9.0 };
    pc.load_torque_Nm.n_points = 2u;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const prot_result_t r = prot_run(e, prot_bench_cmd, BENCH_T0_S + BENCH_LENGTH_S, 0.05,
                                     (double)fc.protection.current_limit_A, BENCH_T0_S);
    prot_print("IDA-PBC, a 9 N m load step at 50 rpm", &r);
    free(e);
    const double t_limit = (double)fc.protection.current_limit_time_s;
    const double Ts = 1.0 / (double)fc.timing.f_pwm_Hz;
    assert_int_equal(r.first_fault, MC_FAULT_CURRENT_LIMIT);
    assert_true(r.outputs_off_at_fault);
    assert_true(r.t_first_over_i_max_s >= BENCH_T0_S + 1.5);
    const double T_tick = 1.0 / (double)fc.timing.slow_loop_Hz;
    assert_true(r.t_fault_s >= r.t_first_over_i_max_s + t_limit - T_tick - 2.0 * Ts);
    assert_true(r.t_fault_s <= r.t_first_over_i_max_s + t_limit + 0.005);
    assert_true(r.t_over_i_max_s <= t_limit + T_tick);
    assert_true(r.i_peak_A <= 1.05 * (double)fc.protection.current_limit_A);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_overspeed),
        cmocka_unit_test(test_stall_locked_rotor),
        cmocka_unit_test(test_i2t),
        cmocka_unit_test(test_current_limit_idapbc),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
