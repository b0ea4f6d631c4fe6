/*
 * SVPWM against geometry computed independently in double: phase voltages
 * of a vector |v| at angle psi are |v| cos(psi - x 2pi/3); the inverter
 * hexagon has its flat sides at distance v_dc/sqrt(3) (centres at 30 deg +
 * k 60 deg), so its radius at angle psi is
 * (v_dc/sqrt(3)) / cos((psi mod 60 deg) - 30 deg).
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/svpwm.h"
#include "test_rng.h"

#define DEG60    (MC_TEST_PI / 3.0)
#define N_RANDOM 300000

typedef struct {
    double v_dc;
    double mag;
    double psi; /* in [0, 2 pi) */
    mc_svpwm_limit_t limit;
} command_t;

static command_t random_command(test_rng_t *rng, double mag_lo_rel, double mag_hi_rel)
{
    command_t c;
    c.v_dc = test_rng_range(rng, 5.0, 600.0);
    c.mag = test_rng_range(rng, mag_lo_rel, mag_hi_rel) * c.v_dc / sqrt(3.0);
    c.psi = test_rng_range(rng, 0.0, MC_TEST_TWO_PI);
    c.limit = (test_rng_unit(rng) < 0.5) ? MC_SVPWM_LIMIT_CIRCLE : MC_SVPWM_LIMIT_HEXAGON;
    return c;
}

static mc_status_t run(const command_t *c, mc_svpwm_out_f32_t *out)
{
    return mc_svpwm_f32((float)(c->mag * cos(c->psi)), (float)(c->mag * sin(c->psi)),
                        (float)c->v_dc, c->limit, out);
}

static double hexagon_radius(double v_dc, double psi)
{
    return v_dc / sqrt(3.0) / cos(fmod(psi, DEG60) - DEG60 / 2.0);
}

/* Line-to-line voltages made by the duties equal those of the vector
 * (mag, psi): v_ab = sqrt(3) mag cos(psi + 30 deg), etc. */
static void assert_line_voltages(const mc_svpwm_out_f32_t *o, double v_dc, double mag, double psi)
{
    for (int x = 0; x < 3; x++) {
        assert_true(o->duty[x] >= 0.0f && o->duty[x] <= 1.0f);
    }
    for (int x = 0; x < 3; x++) {
        const int y = (x + 1) % 3;
        const double made = ((double)o->duty[x] - o->duty[y]) * v_dc;
        const double want =
            mag * (cos(psi - x * MC_TEST_TWO_PI / 3.0) - cos(psi - y * MC_TEST_TWO_PI / 3.0));
        assert_true(fabs(made - want) <= 1e-5 * v_dc);
    }
}

/* Sector s holds [(s-1) 60, s 60) deg; skip angles within 1e-5 rad of a
 * boundary, where either neighbour is allowed. */
static void assert_sector(const mc_svpwm_out_f32_t *o, double psi)
{
    const double pos = psi / DEG60;
    if (fabs(pos - round(pos)) * DEG60 > 1e-5) {
        assert_int_equal(o->sector, (int)floor(pos) % 6 + 1);
    } else {
        assert_true(o->sector >= 1 && o->sector <= 6);
    }
}

static void test_svpwm_linear_range(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(41);
    for (int n = 0; n < N_RANDOM; n++) {
        const command_t c = random_command(&rng, 0.0, 1.0 - 1e-6);
        mc_svpwm_out_f32_t o;
        assert_int_equal(run(&c, &o), MC_OK);
        assert_false(o.overmodulated);
        assert_true(o.v_alpha_V == (float)(c.mag * cos(c.psi)));
        assert_true(o.v_beta_V == (float)(c.mag * sin(c.psi)));
        assert_line_voltages(&o, c.v_dc, c.mag, c.psi);
        assert_sector(&o, c.psi);
        /* min-max injection centres the duties: max + min = 1 */
        const double d_max = fmax(o.duty[0], fmax(o.duty[1], o.duty[2]));
        const double d_min = fmin(o.duty[0], fmin(o.duty[1], o.duty[2]));
        assert_true(fabs(d_max + d_min - 1.0) <= 1e-6);
    }
}

/* Dense angle grid exactly on the linear-range circle. */
static void test_svpwm_on_the_circle(void **state)
{
    (void)state;
    const double v_dc = 48.0;
    for (double psi = 0.0; psi < MC_TEST_TWO_PI; psi += 1e-4) {
        const command_t c = { v_dc, v_dc / sqrt(3.0), psi, MC_SVPWM_LIMIT_CIRCLE };
        mc_svpwm_out_f32_t o;
        assert_int_equal(run(&c, &o), MC_OK);
        assert_line_voltages(&o, v_dc, c.mag, psi);
        assert_sector(&o, psi);
    }
}

static void check_overmodulated(const command_t *c)
{
    mc_svpwm_out_f32_t o;
    assert_int_equal(run(c, &o), MC_OK);
    assert_true(o.overmodulated);
    const double applied_psi = atan2(o.v_beta_V, o.v_alpha_V);
    assert_true(fabs(remainder(applied_psi - c->psi, MC_TEST_TWO_PI)) <= 1e-4);
    const double applied_mag = hypot(o.v_alpha_V, o.v_beta_V);
    const double boundary =
        (c->limit == MC_SVPWM_LIMIT_CIRCLE) ? c->v_dc / sqrt(3.0) : hexagon_radius(c->v_dc, c->psi);
    assert_true(fabs(applied_mag - boundary) <= 1e-5 * boundary);
    assert_line_voltages(&o, c->v_dc, boundary, c->psi);
    assert_sector(&o, c->psi);
    if (c->limit == MC_SVPWM_LIMIT_HEXAGON) {
        /* on the hexagon one phase is always on, one always off */
        const double d_max = fmax(o.duty[0], fmax(o.duty[1], o.duty[2]));
        const double d_min = fmin(o.duty[0], fmin(o.duty[1], o.duty[2]));
        assert_true(d_max >= 1.0 - 1e-6 && d_min <= 1e-6);
    }
}

static void test_svpwm_overmodulation_keeps_angle(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(42);
    for (int n = 0; n < N_RANDOM; n++) {
        command_t c = random_command(&rng, 1.0 + 1e-4, 20.0);
        if (c.limit == MC_SVPWM_LIMIT_HEXAGON &&
            c.mag <= hexagon_radius(c.v_dc, c.psi) * (1.0 + 1e-4)) {
            continue; /* inside the hexagon: linear there (tested below) */
        }
        check_overmodulated(&c);
    }
    /* huge commands, also against a tiny (normal) DC link */
    const double v_dc[] = { 300.0, 1e-30 };
    for (size_t i = 0; i < 2; i++) {
        for (double psi = 0.01; psi < MC_TEST_TWO_PI; psi += 0.1) {
            command_t c = { v_dc[i], 1e30, psi, MC_SVPWM_LIMIT_CIRCLE };
            check_overmodulated(&c);
            c.limit = MC_SVPWM_LIMIT_HEXAGON;
            check_overmodulated(&c);
        }
    }
}

/* Between circle and hexagon the HEXAGON policy is still exact. */
static void test_svpwm_hexagon_region_is_reproduced(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(43);
    for (int n = 0; n < N_RANDOM; n++) {
        command_t c = random_command(&rng, 0.0, 1.0);
        c.limit = MC_SVPWM_LIMIT_HEXAGON;
        c.mag = test_rng_range(&rng, 0.0, 1.0 - 1e-6) * hexagon_radius(c.v_dc, c.psi);
        mc_svpwm_out_f32_t o;
        assert_int_equal(run(&c, &o), MC_OK);
        assert_false(o.overmodulated);
        assert_line_voltages(&o, c.v_dc, c.mag, c.psi);
        assert_sector(&o, c.psi);
    }
}

static void assert_rejected(float va, float vb, float vdc, mc_svpwm_limit_t limit,
                            mc_status_t expected)
{
    mc_svpwm_out_f32_t o;
    memset(&o, 0xA5, sizeof o);
    mc_svpwm_out_f32_t before;
    memcpy(&before, &o, sizeof o);
    assert_int_equal(mc_svpwm_f32(va, vb, vdc, limit, &o), expected);
    assert_memory_equal(&o, &before, sizeof o);
}

static void test_svpwm_rejects_bad_input(void **state)
{
    (void)state;
    const mc_svpwm_limit_t c = MC_SVPWM_LIMIT_CIRCLE;
    assert_rejected(NAN, 1.0f, 24.0f, c, MC_ERR_NONFINITE);
    assert_rejected(1.0f, NAN, 24.0f, c, MC_ERR_NONFINITE);
    assert_rejected(1.0f, 1.0f, NAN, c, MC_ERR_NONFINITE);
    assert_rejected(INFINITY, 1.0f, 24.0f, c, MC_ERR_NONFINITE);
    assert_rejected(1.0f, -INFINITY, 24.0f, MC_SVPWM_LIMIT_HEXAGON, MC_ERR_NONFINITE);
    assert_rejected(1.0f, 1.0f, INFINITY, c, MC_ERR_NONFINITE);
    assert_rejected(1.0f, 1.0f, 0.0f, c, MC_ERR_RANGE);
    assert_rejected(1.0f, 1.0f, -0.0f, c, MC_ERR_RANGE);
    assert_rejected(1.0f, 1.0f, -24.0f, c, MC_ERR_RANGE);
    assert_rejected(0.0f, 0.0f, 1e-45f, c, MC_ERR_RANGE);  /* denormal */
    assert_rejected(3e38f, 3e38f, 24.0f, c, MC_ERR_RANGE); /* overflows */
    assert_rejected(1.0f, 1.0f, 24.0f, (mc_svpwm_limit_t)7, MC_ERR_PARAM);
}

/* The unchecked variant (the ISR path's) computes exactly what the checked
 * one does for every valid command, and what the ISR's output check relies
 * on for an invalid one: a non-finite or overflowing command reaches the
 * duties as a non-finite value (never a clamped, finite one). */
static void test_svpwm_unchecked_matches_and_propagates(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(7);
    for (int n = 0; n < N_RANDOM; n++) {
        const command_t c = random_command(&rng, 0.0, 3.0);
        const float a = (float)(c.mag * cos(c.psi));
        const float b = (float)(c.mag * sin(c.psi));
        mc_svpwm_out_f32_t checked;
        mc_svpwm_out_f32_t unchecked;
        memset(&checked, 0, sizeof checked); /* padding equal too */
        memset(&unchecked, 0, sizeof unchecked);
        assert_int_equal(mc_svpwm_f32(a, b, (float)c.v_dc, c.limit, &checked), MC_OK);
        unchecked.sector = checked.sector; /* not written by the variant */
        const bool linear = mc_svpwm_unchecked_f32(a, b, (float)c.v_dc, c.limit, &unchecked);
        assert_memory_equal(&checked, &unchecked, sizeof checked);
        /* inline exactly strictly inside the hand-over circle, and then
         * nothing limited */
        const double n_sq = ((double)a * a + (double)b * b) / (c.v_dc * c.v_dc);
        if (fabs(n_sq - MC_SVPWM_INLINE_SQ) > 1e-5) {
            assert_true(linear == (n_sq < MC_SVPWM_INLINE_SQ));
        }
        if (linear) {
            assert_false(checked.overmodulated);
        }
    }
    const float bad[][2] = { { NAN, 1.0f },       { 1.0f, NAN },      { INFINITY, 0.0f },
                             { -INFINITY, 1.0f }, { 0.0f, INFINITY }, { 1.0f, -INFINITY },
                             { NAN, NAN },        { 3e38f, -3e38f },  { -3e38f, 3e38f } };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        for (int limit = 0; limit < 2; limit++) {
            mc_svpwm_out_f32_t o;
            assert_false(
                mc_svpwm_unchecked_f32(bad[i][0], bad[i][1], 300.0f, (mc_svpwm_limit_t)limit, &o));
            assert_false(isfinite(o.duty[0]) && isfinite(o.duty[1]) && isfinite(o.duty[2]));
        }
    }
    /* (a bus that is not finite and >= FLT_MIN is the caller's check; a
     * NaN one still reaches the duties) */
    mc_svpwm_out_f32_t o;
    assert_false(mc_svpwm_unchecked_f32(1.0f, 2.0f, NAN, MC_SVPWM_LIMIT_CIRCLE, &o));
    assert_false(isfinite(o.duty[0]) && isfinite(o.duty[1]) && isfinite(o.duty[2]));
}

/* The inline modulator against the out-of-line one (the whole algorithm:
 * the limit, the clamp of the duties): the same output, bit for bit,
 * inside the linear range, at its edge (MC_SVPWM_INLINE_SQ, where the
 * inline one hands over) and beyond. */
static void test_svpwm_inline_matches_edge(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(11);
    const double edge = sqrt(3.0 * (double)MC_SVPWM_INLINE_SQ);
    for (int n = 0; n < N_RANDOM; n++) {
        command_t c = random_command(&rng, 0.0, 1.2);
        if (n % 4 == 0) { /* around the hand-over */
            c.mag = edge * test_rng_range(&rng, 1.0 - 1e-6, 1.0 + 1e-6) * c.v_dc / sqrt(3.0);
        }
        const float a = (float)(c.mag * cos(c.psi));
        const float b = (float)(c.mag * sin(c.psi));
        mc_svpwm_out_f32_t in;
        mc_svpwm_unchecked_f32(a, b, (float)c.v_dc, c.limit, &in);
        const mc_svpwm_out_f32_t out = mc_svpwm_edge_f32(a, b, (float)c.v_dc, c.limit);
        assert_memory_equal(in.duty, out.duty, sizeof in.duty);
        assert_true(in.overmodulated == out.overmodulated);
        assert_memory_equal(&in.v_alpha_V, &out.v_alpha_V, sizeof(float));
        assert_memory_equal(&in.v_beta_V, &out.v_beta_V, sizeof(float));
    }
}

static void test_svpwm_zero_vector(void **state)
{
    (void)state;
    mc_svpwm_out_f32_t o;
    assert_int_equal(mc_svpwm_f32(0.0f, 0.0f, 24.0f, MC_SVPWM_LIMIT_CIRCLE, &o), MC_OK);
    for (int x = 0; x < 3; x++) {
        assert_true(o.duty[x] == 0.5f);
    }
    assert_int_equal(o.sector, 1);
    assert_false(o.overmodulated);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_svpwm_linear_range),
        cmocka_unit_test(test_svpwm_on_the_circle),
        cmocka_unit_test(test_svpwm_overmodulation_keeps_angle),
        cmocka_unit_test(test_svpwm_hexagon_region_is_reproduced),
        cmocka_unit_test(test_svpwm_rejects_bad_input),
        cmocka_unit_test(test_svpwm_zero_vector),
        cmocka_unit_test(test_svpwm_unchecked_matches_and_propagates),
        cmocka_unit_test(test_svpwm_inline_matches_edge),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
