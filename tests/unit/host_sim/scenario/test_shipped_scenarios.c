/* The scenarios shipped in host_sim/scenarios load, and carry the motors and
 * profiles stated in the papers (numbers typed from the paper texts); the
 * full example of host_sim/scenarios/README.md is valid. */
#include "mc_test.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "sim/scenario.h"

static scenario_t scn;

static void load(const char *name)
{
    char path[1024];
    scn_error_t err;
    snprintf(path, sizeof(path), "%s/%s", SCENARIOS_DIR, name);
    if (!scenario_load(path, NULL, 0, &scn, &err)) {
        char line[2048];
        scenario_error_format(&err, line, sizeof(line));
        fail_msg("%s", line);
    }
}

static void near(double actual, double expected)
{
    assert_true(fabs(actual - expected) <= 1e-9 * fmax(1.0, fabs(expected)));
}

/* The loaded scenario's motor has these parameters. */
static void check_motor(double R_ohm, double Ld_H, double Lq_H, double psi_Wb, int pole_pairs,
                        double J_kgm2)
{
    const plant_motor_params_t *m = &scn.plant.motor;
    near(m->R_ohm, R_ohm);
    near(m->Ld_H, Ld_H);
    near(m->Lq_H, Lq_H);
    near(m->psi_Wb, psi_Wb);
    assert_int_equal(m->pole_pairs, pole_pairs);
    near(m->J_kgm2, J_kgm2);
}

/* Paper 001 Section 5: motor and the benchmark speed/load profiles, in
 * profile time tb = t - t0 (t0: calibration and alignment before tb = 0). */
static void check_paper001_benchmark(double t0)
{
    /* the paper's Phi = 0.17 Wb is two-phase (power-invariant): the
     * plant's psi is Phi sqrt(2/3) (motor_convention.h) */
    check_motor(0.225, 3.8e-3, 3.8e-3, 0.17 * sqrt(2.0 / 3.0), 3, 0.012);
    near(scn.plant.inverter.f_pwm_Hz, 20e3);
    near(scn.time_offset_s, t0);
    near(scn.duration_s, 10.0 + t0);
    assert_int_equal(scn.reference.mode, MC_MODE_SPEED);
    /* 50 rpm/s to 50 rpm (1 s), hold to 3 s, 35 rpm/s to 120 rpm (5 s),
     * hold 2 s, 60 rpm/s down to 0 (9 s), hold to 10 s */
    const sim_profile_t *w = &scn.reference.value;
    near(sim_profile_eval(w, t0 - 0.1), 0.0);
    near(sim_profile_eval(w, t0 + 0.5), 25.0 * MC_TEST_RAD_S_PER_RPM);
    near(sim_profile_eval(w, t0 + 2.0), 50.0 * MC_TEST_RAD_S_PER_RPM);
    near(sim_profile_eval(w, t0 + 4.0), 85.0 * MC_TEST_RAD_S_PER_RPM);
    near(sim_profile_eval(w, t0 + 6.0), 120.0 * MC_TEST_RAD_S_PER_RPM);
    near(sim_profile_eval(w, t0 + 8.0), 60.0 * MC_TEST_RAD_S_PER_RPM);
    near(sim_profile_eval(w, t0 + 9.5), 0.0);
    /* 0 N m for tb < 1 s and 2.5 <= tb < 5 s, 1 N m otherwise */
    const sim_profile_t *tl = &scn.plant.load_torque_Nm;
    near(sim_profile_eval(tl, t0 + 0.5), 0.0);
    near(sim_profile_eval(tl, t0 + 1.0), 1.0);
    near(sim_profile_eval(tl, t0 + 2.49), 1.0);
    near(sim_profile_eval(tl, t0 + 2.5), 0.0);
    near(sim_profile_eval(tl, t0 + 4.99), 0.0);
    near(sim_profile_eval(tl, t0 + 5.0), 1.0);
    near(sim_profile_eval(tl, t0 + 9.9), 1.0);
    assert_int_equal(scn.metrics.n_load_steps, 3);
    near(scn.metrics.load_step_t_s[0], t0 + 1.0);
    near(scn.metrics.load_step_t_s[2], t0 + 5.0);
}

static void paper001_benchmark(void **state)
{
    (void)state;
    load("paper001_benchmark_foc.json");
    check_paper001_benchmark(0.0);
    assert_int_equal(scn.firmware.controller, MC_CONTROLLER_FOC_PI);
    assert_int_equal(scn.firmware.estimator, MC_ESTIMATOR_ENCODER);
    assert_int_equal(scn.firmware.encoder.counts_per_rev, 10000); /* 2500 lines */
}

/* The window named name spans [tb0, tb1] of profile time. */
static void expect_window(const char *name, double tb0, double tb1)
{
    for (size_t i = 0; i < scn.metrics.n_windows; i++) {
        if (strcmp(scn.metrics.windows[i].name, name) == 0) {
            near(scn.metrics.windows[i].t0_s - scn.time_offset_s, tb0);
            near(scn.metrics.windows[i].t1_s - scn.time_offset_s, tb1);
            return;
        }
    }
    fail_msg("no metrics window %s", name);
}

/* The sensorless benchmark (paper 001 Section 5.1, shifted by the 2 s of
 * calibration and alignment) with the windows of the acceptance:
 * angle error at 50 and 120 rpm, speed and load estimate at 120 rpm, the
 * final zero-speed hold; the plant integrator of the benchmark tests. */
static void check_paper001_sensorless(mc_controller_t controller, mc_estimator_t estimator)
{
    check_paper001_benchmark(2.0);
    assert_int_equal(scn.firmware.estimator, estimator);
    assert_int_equal(scn.firmware.controller, controller);
    assert_int_equal(scn.plant.substeps_per_period, PLANT_SUBSTEPS_FAST);
    near(sim_profile_eval(&scn.plant.inverter.v_dc_V, 1.0), 48.0);
    expect_window("at_50rpm", 1.5, 3.0);
    expect_window("at_120rpm", 5.5, 7.0);
    expect_window("zero_speed_hold", 9.5, 10.0);
}

static void paper001_sensorless_idapbc(void **state)
{
    (void)state;
    load("paper001_benchmark_idapbc.json");
    /* paper 001: flux observer + I&I speed/load observer, IDA-PBC */
    check_paper001_sensorless(MC_CONTROLLER_IDAPBC, MC_ESTIMATOR_FLUX_II);
}

static void paper001_sensorless_nam(void **state)
{
    (void)state;
    load("paper001_benchmark_nam.json");
    /* NAM (Fig. 11): flux observer + PLL, cascaded PI FOC */
    check_paper001_sensorless(MC_CONTROLLER_FOC_PI, MC_ESTIMATOR_FLUX_PLL);
}

/* The robustness cases of paper 001 Section 5.1 (plant R +50 %, L +50 %,
 * flux +15 %; the controller keeps the nominal motor) are shipped as files
 * that extend the nominal benchmark: each equals its base except for the
 * plant multiplier and the name. */
static scenario_t base;

static void expect_same_profile(const sim_profile_t *a, const sim_profile_t *b)
{
    for (double t = 0.0; t <= 12.0; t += 0.25) {
        near(sim_profile_eval(a, t), sim_profile_eval(b, t));
    }
}

static void expect_robustness_case(const char *file, const char *base_file, double R, double L,
                                   double psi)
{
    load(base_file);
    base = scn;
    load(file);
    char stem[64];
    snprintf(stem, sizeof(stem), "%.*s", (int)strcspn(file, "."), file);
    assert_string_equal(scn.name, stem);
    /* the plant mismatch of the case; the base has none */
    near(base.plant.mismatch.R, 1.0);
    near(base.plant.mismatch.L, 1.0);
    near(base.plant.mismatch.psi, 1.0);
    near(scn.plant.mismatch.R, R);
    near(scn.plant.mismatch.L, L);
    near(scn.plant.mismatch.psi, psi);
    near(scn.plant.mismatch.J, 1.0);
    /* the paper's motor, nominal in the plant and in the controller */
    check_paper001_sensorless(base.firmware.controller, base.firmware.estimator);
    near(scn.firmware.motor.R_ohm, 0.225f);
    near(scn.firmware.motor.Ld_H, 3.8e-3f);
    near(scn.firmware.motor.Lq_H, 3.8e-3f);
    near(scn.firmware.motor.psi_Wb, (float)(0.17 * sqrt(2.0 / 3.0)));
    /* otherwise the base */
    near(scn.duration_s, base.duration_s);
    near(scn.time_offset_s, base.time_offset_s);
    assert_int_equal(scn.firmware.estimator, base.firmware.estimator);
    near(scn.firmware.flux_obs.gamma, base.firmware.flux_obs.gamma);
    near(scn.firmware.flux_ii.a1, base.firmware.flux_ii.a1);
    near(scn.firmware.flux_ii.a2, base.firmware.flux_ii.a2);
    near(scn.firmware.flux_pll.bandwidth_rad_s, base.firmware.flux_pll.bandwidth_rad_s);
    near(scn.firmware.foc_pi.speed_bandwidth_rad_s, base.firmware.foc_pi.speed_bandwidth_rad_s);
    near(scn.firmware.limits.i_max_A, base.firmware.limits.i_max_A);
    near(scn.plant.motor.J_kgm2, base.plant.motor.J_kgm2);
    near(scn.plant.motor.B_Nm_s_rad, base.plant.motor.B_Nm_s_rad);
    expect_same_profile(&scn.reference.value, &base.reference.value);
    expect_same_profile(&scn.plant.load_torque_Nm, &base.plant.load_torque_Nm);
    expect_same_profile(&scn.plant.inverter.v_dc_V, &base.plant.inverter.v_dc_V);
    assert_int_equal(scn.metrics.n_windows, base.metrics.n_windows);
    near(scn.metrics.steady_t0_s, base.metrics.steady_t0_s);
    near(scn.metrics.dip_window_s, base.metrics.dip_window_s);
    assert_int_equal(scn.trace_decimation, base.trace_decimation);
}

static void paper001_robustness_idapbc(void **state)
{
    (void)state;
    const char *b = "paper001_benchmark_idapbc.json";
    expect_robustness_case("paper001_idapbc_R150.json", b, 1.5, 1.0, 1.0);
    assert_int_equal(scn.firmware.controller, MC_CONTROLLER_IDAPBC);
    expect_robustness_case("paper001_idapbc_L150.json", b, 1.0, 1.5, 1.0);
    expect_robustness_case("paper001_idapbc_psi115.json", b, 1.0, 1.0, 1.15);
}

static void paper001_robustness_nam(void **state)
{
    (void)state;
    const char *b = "paper001_benchmark_nam.json";
    expect_robustness_case("paper001_nam_R150.json", b, 1.5, 1.0, 1.0);
    assert_int_equal(scn.firmware.controller, MC_CONTROLLER_FOC_PI);
    expect_robustness_case("paper001_nam_L150.json", b, 1.0, 1.5, 1.0);
    expect_robustness_case("paper001_nam_psi115.json", b, 1.0, 1.0, 1.15);
}

/* Paper 002 Section IV: the experimental motor, Case I (10 kHz, 300 V,
 * dead time 3 us, cogging at Q theta_m, speed step 0 -> 500 rpm at
 * profile time 0 = after the 25.6 ms calibration). */
static void paper002_case1(void **state)
{
    (void)state;
    load("paper002_case1_foc.json");
    check_motor(9.7, 26e-3, 26e-3, 0.084, 4, 1.35e-4);
    const plant_motor_params_t *m = &scn.plant.motor;
    near(m->B_Nm_s_rad, 7.4e-5);
    assert_int_equal(m->cogging.slots, 32);
    near(scn.plant.inverter.t_dead_s, 3e-6);
    near(scn.plant.inverter.f_pwm_Hz, 10e3);
    assert_int_equal(scn.plant.sensors.encoder.lines, 2500);
    near(scn.time_offset_s, 0.0256);
    near(scn.duration_s, 0.4256);
    const double t0 = scn.time_offset_s;
    near(sim_profile_eval(&scn.reference.value, t0 - 1e-6), 0.0);
    near(sim_profile_eval(&scn.reference.value, t0 + 1e-6), 500.0 * MC_TEST_RAD_S_PER_RPM);
    near(sim_profile_eval(&scn.plant.load_torque_Nm, t0 + 0.3), 0.0);
    assert_true(scn.metrics.has_step && scn.metrics.has_steady_window);
    near(scn.metrics.step_t_s, t0);
    near(scn.metrics.steady_t0_s, t0 + 0.2);
    near(scn.metrics.steady_t1_s, t0 + 0.4);
    assert_int_equal(scn.metrics.n_windows, 1);
    assert_string_equal(scn.metrics.windows[0].name, "spectrum");
    const mc_config_t *c = &scn.firmware;
    assert_int_equal(c->controller, MC_CONTROLLER_FOC_PI);
    assert_int_equal(c->estimator, MC_ESTIMATOR_ENCODER);
    assert_false(c->deadtime.compensation);
    near(c->foc_pi.speed_bandwidth_rad_s, 200.0);
    near(c->limits.i_max_A, 6.0);
    near(c->motor.R_ohm, 9.7f);
    assert_int_equal(c->motor.pole_pairs, 4);
}

/* Case II: Case I plus the paper's changes at profile time 0.2 s: gains
 * 1.05 / 0.96 then offsets -0.5 / +0.8 A on phases a / b, dead time 7 us. */
static void paper002_case2(void **state)
{
    (void)state;
    load("paper002_case2_foc.json");
    check_motor(9.7, 26e-3, 26e-3, 0.084, 4, 1.35e-4);
    near(scn.plant.inverter.t_dead_s, 3e-6);
    assert_int_equal(scn.n_injections, 7);
    const sim_injection_t *inj = &scn.injections[2];
    const double t = 0.2 + scn.time_offset_s;
    assert_int_equal(inj[0].kind, SIM_INJECT_CURRENT_GAIN);
    assert_int_equal(inj[0].phase, 0);
    near(inj[0].value, 1.05);
    assert_int_equal(inj[1].kind, SIM_INJECT_CURRENT_GAIN);
    assert_int_equal(inj[1].phase, 1);
    near(inj[1].value, 0.96);
    assert_int_equal(inj[2].kind, SIM_INJECT_CURRENT_OFFSET);
    assert_int_equal(inj[2].phase, 0);
    near(inj[2].value, -0.5);
    assert_int_equal(inj[3].kind, SIM_INJECT_CURRENT_OFFSET);
    assert_int_equal(inj[3].phase, 1);
    near(inj[3].value, 0.8);
    assert_int_equal(inj[4].kind, SIM_INJECT_DEAD_TIME);
    near(inj[4].value, 7e-6);
    for (int i = 0; i < 5; i++) {
        near(inj[i].t_start_s, t);
        assert_true(isinf(inj[i].t_end_s));
    }
}

/* Cases III and IV: the paper's load, 0 (t < 0.1 s), 1.5 N m (0.1-0.2 s),
 * 1.5 + sin(50 pi t) N m (0.2-0.4 s); Case III the step alone. */
static void paper002_case3_case4(void **state)
{
    (void)state;
    load("paper002_case3_foc.json");
    const double t0 = scn.time_offset_s;
    const sim_profile_t *l = &scn.plant.load_torque_Nm;
    near(sim_profile_eval(l, t0 + 0.099), 0.0);
    near(sim_profile_eval(l, t0 + 0.1001), 1.5);
    near(sim_profile_eval(l, t0 + 0.35), 1.5);
    assert_int_equal(scn.metrics.n_load_steps, 1);
    near(scn.metrics.load_step_t_s[0], t0 + 0.1);
    near(scn.metrics.dip_window_s, 0.1);
    near(scn.metrics.recovery_band, 10.0);
    load("paper002_case4_foc.json");
    l = &scn.plant.load_torque_Nm;
    near(sim_profile_eval(l, t0 + 0.099), 0.0);
    near(sim_profile_eval(l, t0 + 0.15), 1.5);
    for (double tb = 0.2; tb <= 0.4; tb += 0.0137) {
        assert_true(fabs(sim_profile_eval(l, t0 + tb) -
                         (1.5 + sin(50.0 * 3.14159265358979323846 * tb))) < 1e-9);
    }
    assert_int_equal(scn.metrics.n_load_steps, 1);
    near(scn.metrics.steady_t0_s, t0 + 0.2);
    near(scn.metrics.steady_t1_s, t0 + 0.4);
}

/* Paper 000 Table 1 motor, g3 = 1/j + 1e4 sin(t), position regulation. */
static void paper000_position(void **state)
{
    (void)state;
    load("paper000_position_foc.json");
    /* L = Ld = Lq = 20 mH, j = 0.55367 kg cm^2 */
    check_motor(7.2, 20e-3, 20e-3, 0.06 * sqrt(2.0 / 3.0), 8, 0.55367e-4); /* two-phase, too */
    const plant_motor_params_t *m = &scn.plant.motor;
    near(m->B_Nm_s_rad, 0.006);
    near(m->g3_amplitude_per_kgm2, 1e4);
    near(m->g3_omega_rad_s, 1.0);
    assert_int_equal(scn.reference.mode, MC_MODE_POSITION);
    const mc_config_t *c = &scn.firmware;
    assert_int_equal(c->controller, MC_CONTROLLER_FOC_PI);
    assert_int_equal(c->estimator, MC_ESTIMATOR_ENCODER);
    near(c->foc_pi.speed_bandwidth_rad_s, 200.0);
    near(c->position.kp_per_s, 50.0);
    near(c->limits.i_max_A, 3.0);
    assert_int_equal(c->motor.pole_pairs, 8);
}

/* Paper 000 bench: the regulator (controller eeo) and the
 * baseline FOC in the four load cases, theta* = 1 rad from t = 0 (profile
 * time), 20 s, g3 = 1/j + 1e4 sin(t) on the plant; the assumed loads
 * (the paper gives none); the 16-bit encoder variants. */
static void check_paper000_case(int c_case)
{
    check_motor(7.2, 20e-3, 20e-3, 0.06 * sqrt(2.0 / 3.0), 8, 0.55367e-4);
    near(scn.plant.motor.g3_amplitude_per_kgm2, 1e4);
    near(scn.time_offset_s, 0.0256);
    near(scn.duration_s, 20.0256);
    assert_int_equal(scn.plant.substeps_per_period, 4);
    assert_int_equal(scn.reference.mode, MC_MODE_POSITION);
    near(sim_profile_eval(&scn.reference.value, 0.0), 1.0);
    near(sim_profile_eval(&scn.reference.value, 20.0), 1.0);
    const sim_profile_t *tl = &scn.plant.load_torque_Nm;
    const double tb = 1.3; /* profile time */
    double expect = 0.0;
    if (c_case >= 2) {
        expect = 0.2;
    }
    if (c_case >= 3) {
        expect += 0.1 * sin(tb + 0.7853981633974483); /* pi/4 */
    }
    if (c_case == 4) {
        near(tl->noise.rms, 0.1);
        near(tl->noise.cutoff_Hz, 5.0);
    } else {
        near(tl->noise.rms, 0.0);
        near(sim_profile_eval(tl, tb + 0.0256), expect);
    }
}

static void paper000_eeo_bench(void **state)
{
    (void)state;
    char f[64];
    for (int c = 1; c <= 4; ++c) {
        (void)snprintf(f, sizeof f, "paper000_eeo_case%d.json", c);
        load(f);
        check_paper000_case(c);
        assert_int_equal(scn.firmware.controller, MC_CONTROLLER_EEO);
        assert_int_equal(scn.firmware.estimator, MC_ESTIMATOR_ENCODER);
        assert_int_equal(scn.firmware.encoder.counts_per_rev, 1u << 23);
        near(scn.firmware.eeo.g3_amplitude_per_kgm2, 1e4);
        near(scn.firmware.eeo.kappa, 1e3);
        near(scn.firmware.eeo.b_bar_Nm_per_Vs, 20.0);
        (void)snprintf(f, sizeof f, "paper000_position_foc_case%d.json", c);
        load(f);
        check_paper000_case(c);
        assert_int_equal(scn.firmware.controller, MC_CONTROLLER_FOC_PI);
        if (c <= 3) {
            (void)snprintf(f, sizeof f, "paper000_eeo_case%d_enc16.json", c);
            load(f);
            check_paper000_case(c);
            assert_int_equal(scn.firmware.controller, MC_CONTROLLER_EEO);
            assert_int_equal(scn.firmware.encoder.counts_per_rev, 65536u);
        }
    }
}

/* The ```json block after "## A full example" in README.md, NUL-terminated
 * in place inside text. */
static char *readme_example(char *text)
{
    char *section = strstr(text, "## A full example");
    assert_non_null(section);
    char *start = strstr(section, "```json\n");
    assert_non_null(start);
    start += strlen("```json\n");
    char *end = strstr(start, "\n```");
    assert_non_null(end);
    *end = '\0';
    return start;
}

static void readme_full_example_is_valid(void **state)
{
    (void)state;
    static char text[262144];
    FILE *f = fopen(SCENARIOS_DIR "/README.md", "rb");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof(text) - 1, f);
    const bool whole = feof(f) != 0;
    fclose(f);
    if (!whole) {
        fail_msg("README.md is longer than the %zu bytes read: enlarge text[]", n);
    }
    text[n] = '\0';
    scn_error_t err;
    if (!scenario_load_text(readme_example(text), "README.md", NULL, 0, &scn, &err)) {
        char line[2048];
        scenario_error_format(&err, line, sizeof(line));
        fail_msg("%s", line);
    }
    near(scn.plant.mismatch.R, 1.5);
    assert_int_equal(scn.plant.motor.cogging.slots, 36);
    assert_int_equal(scn.plant.substeps_per_period, 4);
    assert_int_equal(scn.n_injections, 1);
    near(scn.metrics.step_end_s, 1.0);
}

/* The realistic variants: the base benchmark with the inverter and
 * sensors of tests/sim/test_p001_realistic.c (whose acceptance they are),
 * nothing else changed. */
static void expect_realistic(const char *file, const char *base_file)
{
    load(base_file);
    base = scn;
    load(file);
    const plant_inverter_params_t *inv = &scn.plant.inverter;
    const plant_current_sensor_t *c = &scn.plant.sensors.current;
    near(inv->t_dead_s, 1e-6);
    near(inv->dead_time_current_band_A, 0.16);
    near(c->noise_rms_A, 0.01);
    assert_int_equal(c->adc_bits, 12);
    near(c->full_scale_A, 25.0);
    const double gain[3] = { 1.005, 0.995, 1.0 };
    const double offset[3] = { 0.02, -0.02, 0.01 };
    for (int x = 0; x < 3; ++x) {
        near(c->gain[x], gain[x]);
        near(c->offset_A[x], offset[x]);
    }
    assert_int_equal(scn.plant.sensors.vdc.adc_bits, 12);
    near(scn.plant.sensors.vdc.full_scale_V, 100.0);
    /* the firmware states the dead time and compensates it */
    near(scn.firmware.deadtime.dead_time_s, (float)1e-6);
    assert_true(scn.firmware.deadtime.compensation);
    assert_int_equal(scn.firmware.controller, base.firmware.controller);
    assert_int_equal(scn.firmware.estimator, base.firmware.estimator);
    near(scn.duration_s, base.duration_s);
    near(scn.plant.motor.psi_Wb, base.plant.motor.psi_Wb);
}

static void paper001_realistic(void **state)
{
    (void)state;
    expect_realistic("paper001_idapbc_realistic.json", "paper001_benchmark_idapbc.json");
    expect_realistic("paper001_nam_realistic.json", "paper001_benchmark_nam.json");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(paper001_benchmark),      cmocka_unit_test(paper001_sensorless_idapbc),
        cmocka_unit_test(paper001_sensorless_nam), cmocka_unit_test(paper001_robustness_idapbc),
        cmocka_unit_test(paper001_robustness_nam), cmocka_unit_test(paper002_case1),
        cmocka_unit_test(paper002_case2),          cmocka_unit_test(paper002_case3_case4),
        cmocka_unit_test(paper000_position),       cmocka_unit_test(readme_full_example_is_valid),
        cmocka_unit_test(paper001_realistic),      cmocka_unit_test(paper000_eeo_bench),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
