/*
 * Q31 Clarke, inverse Clarke, Park and inverse Park against a double
 * reference, against the float32 versions, and at saturation.
 *
 * Bounds (LSB = 2^-31):
 *  - Clarke: output = round(X * c / 2^31), X the exact integer expression,
 *    c a Q31 constant within 1/2 of the exact 2^31 k, so
 *      |q31 - X k| <= 1/2 (final rounding) + |X| / 2^32 (constant).
 *  - inverse Clarke b, c: same form with X = beta (k = sqrt(3)/2), the
 *    alpha/2 term being exact.
 *  - Park / inverse Park: the exact sum of two Q62 products rounded once,
 *    so |q31 - exact| <= 1/2.
 *  - Saturation: clamping is 1-Lipschitz, so the bound holds against the
 *    clamped reference too; at the extremes results must equal the saturated
 *    value exactly.
 *  - float32 versions: unit roundoff u = 2^-24. Converting the Q31 inputs to
 *    float and every float operation each add at most u times the magnitude
 *    of the quantity rounded; summing over the roundings gives
 *      Clarke alpha: 3 input + 2 sub + 1 constant + 1 mul, each on at most
 *        S = (2|a| + |b| + |c|) / 3  -> 7 u S;
 *      Clarke beta: 2 input + 1 sub + 1 constant + 1 mul on (|b| + |c|)
 *        / sqrt(3) -> 5 u (|b| + |c|) / sqrt(3); two-input: same with
 *        (|a| + 2|b|) / sqrt(3);
 *      Park: 4 inputs, 2 mul, 1 add on |x1 y1| + |x2 y2| -> 7 u (...)
 *    (first order in u; the second-order terms are below 1e-6 of these,
 *    covered by the factor 1.01). Expected: |q31 - float| <= q31 bound +
 *    float bound (in LSB) + the 1e-3 LSB allowed for the double reference.
 */
#include "mc_test.h"

#include <math.h>

#include "mc/clarke.h"
#include "mc/clarke_q31.h"
#include "mc/park.h"
#include "mc/park_q31.h"
#include "q31_test_util.h"

#define REF_SLACK_LSB 1e-3 /* double reference: < 1e-5 LSB, see above */
#define F32_MARGIN    1.01
#define N_RANDOM      200000
#define N_GRID        400

static const double k_sqrt3 = 1.7320508075688772935;

static const int32_t k_edges[] = { INT32_MIN, INT32_MIN + 1, -1, 0, 1, INT32_MAX - 1, INT32_MAX };
#define N_EDGES (sizeof k_edges / sizeof k_edges[0])

/* clamp a real (per-unit) to the representable Q31 interval, in LSB */
static double clamp_lsb(double x_pu)
{
    const double lsb = x_pu * Q31_SCALE;
    return lsb > INT32_MAX ? INT32_MAX : (lsb < INT32_MIN ? INT32_MIN : lsb);
}

static void assert_within(int32_t got, double want_pu, double bound_lsb)
{
    const double err = fabs((double)got - clamp_lsb(want_pu));
    if (err > bound_lsb) {
        fail_msg("got %ld, want %.3f LSB: error %.3f > bound %.3f", (long)got, want_pu * Q31_SCALE,
                 err, bound_lsb);
    }
}

static float to_f32(int32_t x)
{
    return (float)q31_to_real(x);
}

/* |value| < 1 - margin: the float result is not saturated */
static int inside(double x_pu)
{
    return fabs(x_pu) < 1.0 - 1e-6;
}

/* ---- Clarke ----------------------------------------------------------- */

static void check_clarke3(int32_t a, int32_t b, int32_t c)
{
    int32_t alpha, beta;
    mc_clarke_q31(a, b, c, &alpha, &beta);
    const double x_alpha = 2.0 * a - (double)b - (double)c; /* exact */
    const double x_beta = (double)b - (double)c;            /* exact */
    const double alpha_ref = x_alpha / 3.0 / Q31_SCALE;
    const double beta_ref = x_beta / k_sqrt3 / Q31_SCALE;
    const double bound_alpha = 0.5 + fabs(x_alpha) / 4294967296.0 + REF_SLACK_LSB;
    const double bound_beta = 0.5 + fabs(x_beta) / 4294967296.0 + REF_SLACK_LSB;
    assert_within(alpha, alpha_ref, bound_alpha);
    assert_within(beta, beta_ref, bound_beta);

    float alpha_f, beta_f;
    mc_clarke_f32(to_f32(a), to_f32(b), to_f32(c), &alpha_f, &beta_f);
    const double ra = fabs(q31_to_real(a)), rb = fabs(q31_to_real(b)), rc = fabs(q31_to_real(c));
    if (inside(alpha_ref)) {
        const double f_bound = F32_MARGIN * 7.0 * U_F32 * (2 * ra + rb + rc) / 3.0;
        assert_within(alpha, alpha_f, bound_alpha + f_bound * Q31_SCALE);
    }
    if (inside(beta_ref)) {
        const double f_bound = F32_MARGIN * 5.0 * U_F32 * (rb + rc) / k_sqrt3;
        assert_within(beta, beta_f, bound_beta + f_bound * Q31_SCALE);
    }
}

static void check_clarke2(int32_t a, int32_t b)
{
    int32_t alpha, beta;
    mc_clarke2_q31(a, b, &alpha, &beta);
    const double x_beta = (double)a + 2.0 * b;
    const double beta_ref = x_beta / k_sqrt3 / Q31_SCALE;
    const double bound_beta = 0.5 + fabs(x_beta) / 4294967296.0 + REF_SLACK_LSB;
    assert_int_equal(alpha, a);
    assert_within(beta, beta_ref, bound_beta);

    float alpha_f, beta_f;
    mc_clarke2_f32(to_f32(a), to_f32(b), &alpha_f, &beta_f);
    if (inside(beta_ref)) {
        const double f_bound =
            F32_MARGIN * 5.0 * U_F32 * (fabs(q31_to_real(a)) + 2 * fabs(q31_to_real(b))) / k_sqrt3;
        assert_within(beta, beta_f, bound_beta + f_bound * Q31_SCALE);
    }
}

static void test_clarke_balanced_grid(void **state)
{
    (void)state;
    for (int ia = 0; ia <= 20; ++ia) {
        const double amp = 0.05 * ia; /* up to full scale */
        for (int it = 0; it < N_GRID; ++it) {
            const double th = MC_TEST_TWO_PI * it / N_GRID;
            const int32_t a = real_to_q31_sat(amp * cos(th));
            const int32_t b = real_to_q31_sat(amp * cos(th - MC_TEST_TWO_PI / 3.0));
            const int32_t c = real_to_q31_sat(amp * cos(th + MC_TEST_TWO_PI / 3.0));
            check_clarke3(a, b, c);
            check_clarke2(a, b);
            /* amplitude invariance: a balanced set of amplitude A maps to a
             * vector of length A. Error: input quantisation <= 1 LSB per
             * phase (rounding, or 1.0 saturated to INT32_MAX) gives
             * (2 + 1 + 1) / 3 on alpha and 2 / sqrt(3) on beta; computation
             * <= 1/2 + 3 * 2^31 / 2^32 = 2 on alpha, 1/2 + 1 on beta; the
             * length error is at most the sum. */
            int32_t alpha, beta;
            mc_clarke_q31(a, b, c, &alpha, &beta);
            const double len = hypot(q31_to_real(alpha), q31_to_real(beta));
            const double len_bound = 4.0 / 3.0 + 2.0 + 2.0 / k_sqrt3 + 1.5;
            assert_true(fabs(len - amp) * Q31_SCALE <= len_bound);
        }
    }
}

static void test_clarke_random(void **state)
{
    (void)state;
    uint64_t seed = 0xC1A4CEULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const int32_t a = prng_q31(&seed), b = prng_q31(&seed), c = prng_q31(&seed);
        check_clarke3(a, b, c);
        check_clarke2(a, b);
        /* small signals: relative accuracy at low amplitude */
        check_clarke3(a / 4096, b / 4096, c / 4096);
        check_clarke2(a / 4096, b / 4096);
    }
}

static void test_clarke_saturates(void **state)
{
    (void)state;
    for (size_t i = 0; i < N_EDGES; ++i) {
        for (size_t j = 0; j < N_EDGES; ++j) {
            check_clarke2(k_edges[i], k_edges[j]);
            for (size_t k = 0; k < N_EDGES; ++k) {
                check_clarke3(k_edges[i], k_edges[j], k_edges[k]);
            }
        }
    }
    int32_t alpha, beta;
    /* alpha = (2 + 2 + 2^-30) / 3 > 1 -> saturates, beta = 0 exactly */
    mc_clarke_q31(INT32_MAX, INT32_MIN, INT32_MIN, &alpha, &beta);
    assert_int_equal(alpha, INT32_MAX);
    assert_int_equal(beta, 0);
    mc_clarke_q31(INT32_MIN, INT32_MAX, INT32_MAX, &alpha, &beta);
    assert_int_equal(alpha, INT32_MIN);
    assert_int_equal(beta, 0);
    /* beta = (1 + 1) / sqrt(3) = 1.15 -> +max, and the mirrored case */
    mc_clarke_q31(0, INT32_MAX, INT32_MIN, &alpha, &beta);
    assert_int_equal(alpha, 0);
    assert_int_equal(beta, INT32_MAX);
    mc_clarke_q31(0, INT32_MIN, INT32_MAX, &alpha, &beta);
    assert_int_equal(beta, INT32_MIN);
    /* two-input: (1 + 2) / sqrt(3) = 1.73 */
    mc_clarke2_q31(INT32_MAX, INT32_MAX, &alpha, &beta);
    assert_int_equal(beta, INT32_MAX);
    mc_clarke2_q31(INT32_MIN, INT32_MIN, &alpha, &beta);
    assert_int_equal(alpha, INT32_MIN);
    assert_int_equal(beta, INT32_MIN);
}

/* ---- inverse Clarke ----------------------------------------------------- */

static void check_inv_clarke(int32_t alpha, int32_t beta)
{
    int32_t a, b, c;
    mc_inv_clarke_q31(alpha, beta, &a, &b, &c);
    const double al = q31_to_real(alpha), be = q31_to_real(beta);
    const double bound = 0.5 + fabs((double)beta) / 4294967296.0 + REF_SLACK_LSB;
    assert_int_equal(a, alpha);
    assert_within(b, -0.5 * al + 0.5 * k_sqrt3 * be, bound);
    assert_within(c, -0.5 * al - 0.5 * k_sqrt3 * be, bound);
}

static void test_inv_clarke(void **state)
{
    (void)state;
    uint64_t seed = 0x1C1A4CEULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        check_inv_clarke(prng_q31(&seed), prng_q31(&seed));
    }
    for (size_t i = 0; i < N_EDGES; ++i) {
        for (size_t j = 0; j < N_EDGES; ++j) {
            check_inv_clarke(k_edges[i], k_edges[j]);
        }
    }
    int32_t a, b, c;
    mc_inv_clarke_q31(INT32_MIN, INT32_MAX, &a, &b, &c); /* b = 1.37 */
    assert_int_equal(b, INT32_MAX);
    mc_inv_clarke_q31(INT32_MAX, INT32_MAX, &a, &b, &c); /* c = -1.37 */
    assert_int_equal(c, INT32_MIN);
}

/* ---- Park --------------------------------------------------------------- */

static void check_park(int32_t x, int32_t y, int32_t s, int32_t co)
{
    const double xr = q31_to_real(x), yr = q31_to_real(y);
    const double sr = q31_to_real(s), cr = q31_to_real(co);
    const double bound = 0.5 + REF_SLACK_LSB;
    const double f_bound_pu =
        F32_MARGIN * 7.0 * U_F32 * (fabs(xr * cr) + fabs(yr * sr) + fabs(xr * sr) + fabs(yr * cr));
    const double f_bound = bound + f_bound_pu * Q31_SCALE;
    int32_t d, q, al, be;
    float d_f, q_f, al_f, be_f;

    mc_park_q31(x, y, s, co, &d, &q);
    const double d_ref = xr * cr + yr * sr, q_ref = -xr * sr + yr * cr;
    assert_within(d, d_ref, bound);
    assert_within(q, q_ref, bound);
    mc_park_f32(to_f32(x), to_f32(y), to_f32(s), to_f32(co), &d_f, &q_f);
    if (inside(d_ref)) {
        assert_within(d, d_f, f_bound);
    }
    if (inside(q_ref)) {
        assert_within(q, q_f, f_bound);
    }

    /* inverse Park with (x, y) taken as (d, q) */
    mc_inv_park_q31(x, y, s, co, &al, &be);
    const double al_ref = xr * cr - yr * sr, be_ref = xr * sr + yr * cr;
    assert_within(al, al_ref, bound);
    assert_within(be, be_ref, bound);
    mc_inv_park_f32(to_f32(x), to_f32(y), to_f32(s), to_f32(co), &al_f, &be_f);
    if (inside(al_ref)) {
        assert_within(al, al_f, f_bound);
    }
    if (inside(be_ref)) {
        assert_within(be, be_f, f_bound);
    }
}

static void test_park_grid_and_random(void **state)
{
    (void)state;
    uint64_t seed = 0x9A4CULL;
    for (int it = 0; it < 4 * N_GRID; ++it) {
        const double th = MC_TEST_TWO_PI * it / (4 * N_GRID);
        const int32_t s = real_to_q31_sat(sin(th)), co = real_to_q31_sat(cos(th));
        for (int k = 0; k < 50; ++k) {
            check_park(prng_q31(&seed), prng_q31(&seed), s, co);
            check_park(prng_q31(&seed) / 65536, prng_q31(&seed) / 65536, s, co);
        }
    }
    for (int i = 0; i < N_RANDOM; ++i) { /* arbitrary, also non-unit s, c */
        check_park(prng_q31(&seed), prng_q31(&seed), prng_q31(&seed), prng_q31(&seed));
    }
}

/* Park then inverse Park returns the input: the rotation is orthogonal up
 * to the sin/cos quantisation. Error: Park rounding (1/2 each) carried
 * through the inverse rotation (|c| + |s|) / 2, plus the inverse's own 1/2,
 * plus the scale error |x| |s^2 + c^2 - 1| of the quantised pair. */
static void test_park_round_trip(void **state)
{
    (void)state;
    uint64_t seed = 0x7219ULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const double th = prng_uniform(&seed, -MC_TEST_PI, MC_TEST_PI);
        const int32_t s = real_to_q31_sat(sin(th)), co = real_to_q31_sat(cos(th));
        const double sr = q31_to_real(s), cr = q31_to_real(co);
        /* |(x, y)| < 1 so that d, q do not saturate */
        const int32_t x = prng_q31(&seed) / 2, y = prng_q31(&seed) / 2;
        int32_t d, q, x2, y2;
        mc_park_q31(x, y, s, co, &d, &q);
        mc_inv_park_q31(d, q, s, co, &x2, &y2);
        const double norm_err = fabs(sr * sr + cr * cr - 1.0);
        const double bound_x =
            0.5 * (fabs(sr) + fabs(cr)) + 0.5 + fabs((double)x) * norm_err + REF_SLACK_LSB;
        const double bound_y =
            0.5 * (fabs(sr) + fabs(cr)) + 0.5 + fabs((double)y) * norm_err + REF_SLACK_LSB;
        assert_true(fabs((double)x2 - x) <= bound_x);
        assert_true(fabs((double)y2 - y) <= bound_y);
    }
}

static void test_park_saturates(void **state)
{
    (void)state;
    for (size_t i = 0; i < N_EDGES; ++i) {
        for (size_t j = 0; j < N_EDGES; ++j) {
            for (size_t k = 0; k < N_EDGES; ++k) {
                for (size_t l = 0; l < N_EDGES; ++l) {
                    check_park(k_edges[i], k_edges[j], k_edges[k], k_edges[l]);
                }
            }
        }
    }
    const int32_t r2 = real_to_q31_sat(sqrt(0.5)); /* sin = cos = 0.7071 */
    int32_t d, q;
    mc_park_q31(INT32_MAX, INT32_MAX, r2, r2, &d, &q); /* d = 1.414 */
    assert_int_equal(d, INT32_MAX);
    assert_int_equal(q, 0);
    mc_park_q31(INT32_MIN, INT32_MIN, r2, r2, &d, &q); /* d = -1.414 */
    assert_int_equal(d, INT32_MIN);
    assert_int_equal(q, 0);
    mc_park_q31(INT32_MIN, INT32_MAX, r2, r2, &d, &q); /* q = +1.414 */
    assert_int_equal(q, INT32_MAX);
    /* all -1: d = 1 + 1 = 2, its Q62 sum is 2^63 (not an int64) */
    mc_park_q31(INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN, &d, &q);
    assert_int_equal(d, INT32_MAX);
    assert_int_equal(q, 0);
    int32_t al, be;
    /* alpha = 1.414 saturates; beta = (MAX + MIN) r2 = -0.71 LSB rounds to -1 */
    mc_inv_park_q31(INT32_MAX, INT32_MIN, r2, r2, &al, &be);
    assert_int_equal(al, INT32_MAX);
    assert_int_equal(be, -1);
    mc_inv_park_q31(INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN, &al, &be);
    assert_int_equal(al, 0);
    assert_int_equal(be, INT32_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clarke_balanced_grid), cmocka_unit_test(test_clarke_random),
        cmocka_unit_test(test_clarke_saturates),     cmocka_unit_test(test_inv_clarke),
        cmocka_unit_test(test_park_grid_and_random), cmocka_unit_test(test_park_round_trip),
        cmocka_unit_test(test_park_saturates),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
