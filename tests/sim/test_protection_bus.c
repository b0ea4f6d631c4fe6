/*
 * The DC link under the baseline FOC (encoder): a capacitor behind a 48 V
 * source through 0.05 ohm and a diode (plant_dc_link_t: the source cannot
 * sink current), firmware defaults (trips at 60 V and 20 V).
 *
 * Regeneration: the speed reference ramps to 40 rad/s in 0.3 s (a step
 * would overshoot, and braking the overshoot alone charges this link past
 * 60 V), then steps to 0 at 0.5 s, on 4.7 mF (room for 3.0 J between 48
 * and 60 V; the rotor holds 9.6 J at 40 rad/s); the speed
 * loop brakes at i_max: about kt i_max omega - 1.5 R i_max^2 = 272 W flow
 * into the link, 1.2 kV/s: MC_FAULT_DC_OVERVOLTAGE in the first sample
 * whose (ideal) measurement is above 60 V, i.e. within one period of the
 * true crossing. The reaction, coasting, does not make it worse: the
 * phase currents decay through the diodes in about 1 ms (their magnetic
 * energy, 0.75 L i_max^2 = 0.29 J, and the back-EMF's work while they
 * flow lift the link by about a volt), and then no phase conducts: the
 * line back-EMF at 40 rad/s (35 V) is below the link (the overspeed rule
 * in mc_config_validate keeps it below the trip at any speed the drive
 * reaches). With a brake chopper (10 ohm, on at 56 V, off at 54 V) the
 * same deceleration completes without a fault, the link below 60 V.
 *
 * Source loss at 8 rad/s under a 1 N m load, 1 mF: the link alone feeds the
 * motor, P = tau omega + 1.5 R (tau / kt)^2 = 8.58 W (ideal inverter),
 * and falls from 48 V to 20 V in C (48^2 - 20^2) / (2 P) = 111 ms (5 %:
 * the speed and current transients of the falling bus):
 * MC_FAULT_DC_UNDERVOLTAGE within one period of the true crossing.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "protection_fixture.h"

#define C_REGEN_F 4.7e-3
#define C_LOSS_F  1e-3

typedef struct {
    double level_V; /* the trip level whose true crossing is timed */
    bool rising;
    double t_cross_s;
    double t_fault_s;
    double v_after_fault_V[2]; /* 5 ms after the fault, at the end */
    bool conducting_late;      /* a phase conducts 5 ms after the fault */
} link_t;

static void watch_link(const sim_trace_sample_t *s, void *ctx)
{
    link_t *l = ctx;
    const double v = s->plant.v_dc_V;
    if (l->t_cross_s < 0.0 && (l->rising ? v > l->level_V : v < l->level_V)) {
        l->t_cross_s = s->t_s;
    }
    if (l->t_fault_s < 0.0 && s->fw.faults_latched != 0u) {
        l->t_fault_s = s->t_s;
    }
    if (l->t_fault_s >= 0.0 && s->t_s >= l->t_fault_s + 0.005) {
        if (!(l->v_after_fault_V[0] > 0.0)) {
            l->v_after_fault_V[0] = v;
        }
        l->v_after_fault_V[1] = v;
        l->conducting_late |= !s->plant.open_circuit;
    }
}

static void link_configs(plant_config_t *pc, mc_config_t *fc, double C_F)
{
    fixture_configs(pc, fc);
    pc->dc_link.capacitance_F = C_F;
    pc->dc_link.source_resistance_ohm = 0.05;
}

static double g_t_step;
static double g_w_before;

static mc_command_t step_cmd(double t_s)
{
    const double w = (t_s < g_t_step) ? g_w_before * fmin(t_s / 0.3, 1.0) : 0.0;
    return (mc_command_t){ .enable = true, .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = (float)w };
}

static void test_regeneration(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    link_configs(&pc, &fc, C_REGEN_F);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    g_t_step = 0.5;
    g_w_before = 40.0;
    link_t l = { .level_V = (double)fc.protection.v_dc_max_V,
                 .rising = true,
                 .t_cross_s = -1.0,
                 .t_fault_s = -1.0 };
    const prot_result_t r =
        prot_run_observed(e, step_cmd, 1.0, 0.1, fc.limits.i_max_A, g_t_step, watch_link, &l);
    prot_print("regeneration, 40 rad/s to 0", &r);
    print_message("  link above 60 V from %.5f s; %.3f V 5 ms after the fault, %.3f V at the "
                  "end; a phase conducting then: %d\n",
                  l.t_cross_s, l.v_after_fault_V[0], l.v_after_fault_V[1], (int)l.conducting_late);
    free(e);
    const double Ts = 1.0 / (double)fc.timing.f_pwm_Hz;
    assert_int_equal(r.first_fault, MC_FAULT_DC_OVERVOLTAGE);
    assert_true(r.outputs_off_at_fault);
    assert_true(l.t_cross_s > g_t_step);
    assert_true(r.t_fault_s >= l.t_cross_s && r.t_fault_s <= l.t_cross_s + 1.01 * Ts);
    assert_false(l.conducting_late);
    assert_true(fabs(l.v_after_fault_V[1] - l.v_after_fault_V[0]) <= 1e-9 * l.v_after_fault_V[0]);
}

static void test_regeneration_with_brake(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    link_configs(&pc, &fc, C_REGEN_F);
    pc.dc_link.brake_resistance_ohm = 10.0;
    pc.dc_link.brake_on_V = 56.0;
    pc.dc_link.brake_off_V = 54.0;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    g_t_step = 0.5;
    g_w_before = 40.0;
    const prot_result_t r = prot_run(e, step_cmd, 1.0, 0.1, fc.limits.i_max_A, g_t_step);
    prot_print("regeneration into a brake chopper", &r);
    free(e);
    assert_int_equal(r.first_fault, 0u);
    assert_true(r.v_dc_max_V < (double)fc.protection.v_dc_max_V);
}

static mc_command_t run_cmd(double t_s)
{
    (void)t_s;
    return (mc_command_t){ .enable = true, .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = 8.0f };
}

static void test_source_loss(void **state)
{
    (void)state;
    const double t_loss = 0.4, load = 1.0, w = 8.0;
    plant_config_t pc;
    mc_config_t fc;
    link_configs(&pc, &fc, C_LOSS_F);
    sim_profile_set_constant(&pc.load_torque_Nm, load);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const sim_injection_t inj = { .kind = SIM_INJECT_BUS_SOURCE_LOSS,
                                  .t_start_s = t_loss,
                                  .t_end_s = INFINITY };
    prot_inject(e, &inj);
    link_t l = { .level_V = (double)fc.protection.v_dc_min_V,
                 .rising = false,
                 .t_cross_s = -1.0,
                 .t_fault_s = -1.0 };
    const prot_result_t r =
        prot_run_observed(e, run_cmd, 1.0, 0.05, fc.limits.i_max_A, t_loss, watch_link, &l);
    prot_print("source loss at 8 rad/s, 1 N m", &r);
    const double kt = 1.5 * fc.motor.pole_pairs * (double)fc.motor.psi_Wb;
    const double i = load / kt;
    const double P = load * w + 1.5 * pc.motor.R_ohm * i * i;
    const double v0 = 48.0, v1 = (double)fc.protection.v_dc_min_V;
    const double t_an = t_loss + C_LOSS_F * (v0 * v0 - v1 * v1) / (2.0 * P);
    print_message("  link below %.0f V from %.5f s (analytic %.5f s)\n", v1, l.t_cross_s, t_an);
    free(e);
    const double Ts = 1.0 / (double)fc.timing.f_pwm_Hz;
    assert_int_equal(r.first_fault, MC_FAULT_DC_UNDERVOLTAGE);
    assert_true(r.outputs_off_at_fault);
    assert_true(r.t_fault_s >= l.t_cross_s && r.t_fault_s <= l.t_cross_s + 1.01 * Ts);
    assert_true(fabs(l.t_cross_s - t_an) <= 0.05 * (t_an - t_loss));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_regeneration),
        cmocka_unit_test(test_regeneration_with_brake),
        cmocka_unit_test(test_source_loss),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
