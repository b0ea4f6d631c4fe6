/* Sensors: current offset/gain, quantisation, noise statistics, bus voltage,
 * encoder counts and index, determinism per seed. */
#include "mc_test.h"

#include <math.h>

#include "plant.h"
#include "plant_test_support.h"

/* Locked rotor with a known current: measured = gain * true + offset. */
static void test_current_offset_and_gain(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.locked_rotor = true;
    c.theta_m0_rad = 0.3;
    const double gain[3] = { 1.05, 0.96, 1.0 }, off[3] = { -0.5, 0.8, 0.0 }; /* paper 002 case II */
    for (int x = 0; x < 3; ++x) {
        c.sensors.current.gain[x] = gain[x];
        c.sensors.current.offset_A[x] = off[x];
    }
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double duty[3] = { 0.6, 0.45, 0.45 };
    for (int k = 0; k < 100; ++k)
        plant_advance(&p, duty, true);
    plant_measurement_t m;
    plant_sample(&p, &m);
    const plant_true_state_t *s = plant_true_state(&p);
    assert_true(fabs(s->i_abc_A[0]) > 1.0);
    for (int x = 0; x < 3; ++x)
        assert_near(m.i_abc_A[x], gain[x] * s->i_abc_A[x] + off[x], 1e-12);
    assert_near(m.v_dc_V, 48.0, 0.0);
    assert_near(m.t_s, s->t_s, 0.0);
}

/* 12-bit ADC over +-10 A: LSB = 20/4096. With zero current the offset is
 * the ADC input; over a uniform sweep the error is within LSB/2, zero mean,
 * RMS LSB/sqrt(12); inputs beyond the range clip to the end codes. */
static void test_current_quantisation(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.sensors.current.adc_bits = 12u;
    c.sensors.current.full_scale_A = 10.0;
    const double lsb = 20.0 / 4096.0;
    plant_t p;
    plant_measurement_t m;
    const int n = 4000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const double in = -9.0 + 18.0 * (i + 0.5) / n;
        c.sensors.current.offset_A[0] = in;
        assert_int_equal(plant_init(&p, &c), PLANT_OK);
        plant_sample(&p, &m);
        const double err = m.i_abc_A[0] - in;
        assert_true(fabs(err) <= 0.5 * lsb + 1e-12);
        assert_near(m.i_abc_A[0] / lsb, nearbyint(m.i_abc_A[0] / lsb), 1e-9); /* on a code */
        sum += err;
        sum2 += err * err;
    }
    assert_near(sum / n, 0.0, 0.02 * lsb);
    assert_near(sqrt(sum2 / n), lsb / sqrt(12.0), 0.02 * lsb);
    c.sensors.current.offset_A[0] = 25.0;
    c.sensors.current.offset_A[1] = -25.0;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    plant_sample(&p, &m);
    assert_near(m.i_abc_A[0], 2047.0 * lsb, 1e-12);
    assert_near(m.i_abc_A[1], -2048.0 * lsb, 1e-12);
}

/* Gaussian noise: zero mean, the configured RMS, 68.3 % within one sigma,
 * phases uncorrelated. */
static void test_current_noise_statistics(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.sensors.current.noise_rms_A = 0.1;
    c.sensors.seed = 2024u;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const int n = 40000;
    double sum = 0.0, sum2 = 0.0, cross = 0.0;
    int within = 0;
    plant_measurement_t m;
    for (int k = 0; k < n; ++k) {
        plant_sample(&p, &m);
        sum += m.i_abc_A[0];
        sum2 += m.i_abc_A[0] * m.i_abc_A[0];
        cross += m.i_abc_A[0] * m.i_abc_A[1];
        within += fabs(m.i_abc_A[0]) < 0.1;
    }
    const double se = 0.1 / sqrt((double)n); /* standard error of the mean */
    assert_near(sum / n, 0.0, 4.0 * se);
    assert_near(sqrt(sum2 / n), 0.1, 0.02 * 0.1);
    assert_near(cross / n, 0.0, 4.0 * 0.01 / sqrt((double)n));
    /* P(|X| < sigma) of a normal X: erf(1 / sqrt 2) = 0.6827 */
    assert_near((double)within / n, erf(1.0 / sqrt(2.0)), 0.01);
}

static void test_vdc_sensing(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.sensors.vdc = (plant_vdc_sensor_t){
        .gain = 1.02, .offset_V = -0.3, .adc_bits = 10u, .full_scale_V = 100.0
    };
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    plant_measurement_t m;
    plant_sample(&p, &m);
    const double lsb = 100.0 / 1024.0, in = 1.02 * 48.0 - 0.3;
    assert_near(m.v_dc_V, nearbyint(in / lsb) * lsb, 1e-12);
    assert_true(fabs(m.v_dc_V - in) <= 0.5 * lsb);
}

/* count = floor(frac((theta + offset) / 2 pi) * 4 lines), also for
 * negative angles and several turns. */
static void test_encoder_counts(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.sensors.encoder = (plant_encoder_t){ .lines = 1000u, .offset_rad = 0.25 };
    plant_t p;
    plant_measurement_t m;
    const double angles[] = { 0.0, 1e-4, 1.0, 3.0, -0.25, -1.0, 6.0, 20.0, -40.0 };
    for (size_t i = 0; i < sizeof angles / sizeof angles[0]; ++i) {
        c.theta_m0_rad = angles[i];
        assert_int_equal(plant_init(&p, &c), PLANT_OK);
        plant_sample(&p, &m);
        const double rev = (angles[i] + 0.25) / MC_TEST_TWO_PI;
        const double want = floor((rev - floor(rev)) * 4000.0);
        assert_int_equal(m.encoder_count, (uint32_t)want);
    }
    c.theta_m0_rad = -0.25; /* exactly on the index mark */
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    plant_sample(&p, &m);
    assert_int_equal(m.encoder_count, 0u);
}

/* Spinning freely (outputs off, currents zero, no friction) at constant
 * speed: the index flags once per crossing of theta + offset = 0 mod 2 pi. */
static void test_encoder_index(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.sensors.encoder = (plant_encoder_t){ .lines = 500u, .offset_rad = 1.0 };
    c.omega_m0_rad_s = -25.0; /* negative direction too */
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double duty[3] = { 0.5, 0.5, 0.5 };
    plant_measurement_t m;
    int flags = 0;
    uint32_t prev = 0;
    for (int k = 0; k < 8000; ++k) { /* 0.4 s: 10 rad, 1.59 turns */
        plant_advance(&p, duty, false);
        plant_sample(&p, &m);
        if (m.encoder_index) {
            ++flags;
            assert_true(m.encoder_count > 1990u); /* just below the mark, going down */
        } else if (k > 0) {
            assert_true(prev >= m.encoder_count); /* decreasing, no wrap */
        }
        prev = m.encoder_count;
    }
    const double theta_end = -25.0 * 0.4;
    assert_near(plant_true_state(&p)->theta_m_rad, theta_end, 1e-9);
    const int want = (int)(floor(1.0 / MC_TEST_TWO_PI) - floor((theta_end + 1.0) / MC_TEST_TWO_PI));
    assert_int_equal(flags, want);
    assert_int_equal(want, 2);
}

/* The edge age at each sample, spinning freely at constant speed both
 * ways: t - age is the time of the count's last edge, so it stays put
 * while the count does, lies between the two samples when the count
 * changes, and the counts over the time between the first and the last
 * edge (M/T) are the speed (exact at constant speed); at rest there is no
 * edge (INFINITY). */
static void test_encoder_edge_age(void **state)
{
    (void)state;
    const double speeds[] = { 25.0, -25.0, 0.0 };
    for (size_t i = 0; i < sizeof speeds / sizeof speeds[0]; ++i) {
        plant_config_t c;
        plant_config_default(&c);
        c.sensors.encoder = (plant_encoder_t){ .lines = 500u, .offset_rad = 1.0 };
        c.omega_m0_rad_s = speeds[i];
        plant_t p;
        assert_int_equal(plant_init(&p, &c), PLANT_OK);
        const double duty[3] = { 0.5, 0.5, 0.5 };
        plant_measurement_t m;
        plant_sample(&p, &m);
        if (speeds[i] == 0.0) {
            assert_true(isinf(m.encoder_edge_age_s) && m.encoder_edge_age_s > 0.0);
            continue;
        }
        double t_prev = m.t_s;
        double edge_prev = m.t_s - m.encoder_edge_age_s;
        uint32_t count_prev = m.encoder_count;
        double edge_first = -1.0;
        double edge_last = 0.0;
        int64_t counts = 0; /* from the first edge on */
        for (int k = 0; k < 2000; ++k) {
            plant_advance(&p, duty, false);
            plant_sample(&p, &m);
            const double edge = m.t_s - m.encoder_edge_age_s;
            assert_true(m.encoder_edge_age_s >= 0.0);
            if (m.encoder_count == count_prev) {
                assert_near(edge, edge_prev, 1e-12);
            } else {
                assert_true(edge > t_prev - 1e-12 && edge <= m.t_s + 1e-12);
                int64_t step = (int64_t)m.encoder_count - (int64_t)count_prev;
                step += (step > 1000) ? -2000 : ((step < -1000) ? 2000 : 0);
                if (edge_first < 0.0) {
                    edge_first = edge;
                } else {
                    counts += step;
                }
                edge_last = edge;
            }
            t_prev = m.t_s;
            edge_prev = edge;
            count_prev = m.encoder_count;
        }
        const double w_mt = (double)counts * MC_TEST_TWO_PI / 2000.0 / (edge_last - edge_first);
        assert_near(w_mt, speeds[i], 1e-6 * fabs(speeds[i]));
    }
}

/* The encoder where the turn count does not fit an int64_t: a huge load
 * torque (9e24 N m, the reported case) drives the plant state to NaN in
 * the first period, and an angle of 1e30 rad is 1.6e29 turns. Converting
 * those turns to int64_t is undefined (UBSan's float-cast-overflow stops
 * the test; on x86 it yields INT64_MIN, so the first NaN sample flagged an
 * index). Now: a non-finite angle reads count 0 and no index; a huge finite
 * one the count floor(frac(rev) cpr) computed here, no index at rest. */
static void test_encoder_at_huge_angles(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.sensors.encoder = (plant_encoder_t){ .lines = 1000u, .offset_rad = 0.0 };
    sim_profile_set_constant(&c.load_torque_Nm, 9e24);
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double duty[3] = { 0.5, 0.5, 0.5 };
    plant_measurement_t m;
    for (int k = 0; k < 4; ++k) {
        plant_advance(&p, duty, k % 2 == 0);
        plant_sample(&p, &m);
        assert_false(isfinite(plant_true_state(&p)->theta_m_rad)); /* diverged at once */
        assert_int_equal(m.encoder_count, 0u);
        assert_false(m.encoder_index);
    }
    const double huge_rad = 1e30;
    c.theta_m0_rad = huge_rad;
    c.locked_rotor = true;
    sim_profile_set_constant(&c.load_torque_Nm, 0.0);
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double rev = huge_rad / MC_TEST_TWO_PI;
    const uint32_t want = (uint32_t)floor((rev - floor(rev)) * 4000.0);
    for (int k = 0; k < 2; ++k) {
        plant_advance(&p, duty, false);
        plant_sample(&p, &m);
        assert_int_equal(m.encoder_count, want);
        assert_false(m.encoder_index);
    }
}

/* Same seed: identical samples; another seed: different noise. Load noise
 * (profile) and sensor noise both included. */
static void run_noisy(uint64_t seed, double out[64])
{
    plant_config_t c;
    plant_config_default(&c);
    c.sensors.seed = seed;
    c.sensors.current.noise_rms_A = 0.05;
    c.sensors.vdc.noise_rms_V = 0.2;
    c.load_torque_Nm.noise = (sim_profile_noise_t){ .rms = 0.1, .cutoff_Hz = 100.0, .seed = seed };
    c.substeps_per_period = 4u;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double duty[3] = { 0.55, 0.5, 0.45 };
    plant_measurement_t m;
    for (int k = 0; k < 16; ++k) {
        plant_advance(&p, duty, true);
        plant_sample(&p, &m);
        out[4 * k + 0] = m.i_abc_A[0];
        out[4 * k + 1] = m.i_abc_A[2];
        out[4 * k + 2] = m.v_dc_V;
        out[4 * k + 3] = plant_true_state(&p)->omega_m_rad_s;
    }
}

static void test_determinism_per_seed(void **state)
{
    (void)state;
    double a[64], b[64], d[64];
    run_noisy(11u, a);
    run_noisy(11u, b);
    run_noisy(12u, d);
    assert_memory_equal(a, b, sizeof a);
    int differ = 0;
    for (int k = 0; k < 64; ++k)
        differ += a[k] != d[k];
    assert_int_equal(differ, 64);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_current_offset_and_gain),
        cmocka_unit_test(test_current_quantisation),
        cmocka_unit_test(test_current_noise_statistics),
        cmocka_unit_test(test_vdc_sensing),
        cmocka_unit_test(test_encoder_counts),
        cmocka_unit_test(test_encoder_index),
        cmocka_unit_test(test_encoder_edge_age),
        cmocka_unit_test(test_encoder_at_huge_angles),
        cmocka_unit_test(test_determinism_per_seed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
