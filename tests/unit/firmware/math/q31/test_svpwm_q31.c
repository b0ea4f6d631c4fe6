/*
 * Q31 SVPWM against an independent double reference of the method in
 * mc/svpwm.h, against mc_svpwm_f32, and at full scale.
 *
 * Reference (exact reals from the Q31 inputs, v_dc = 1):
 *   v = inverse Clarke(alpha, beta); CIRCLE: if alpha^2 + beta^2 > 1/3 scale
 *   the command by (1/sqrt 3) / |v|; HEXAGON: if max - min > 1 scale it by
 *   1 / (max - min); duty_k = 1/2 + v_k - (max + min) / 2;
 *   sector = floor(atan2(beta, alpha) / 60 deg) + 1 on [0, 360).
 *
 * Q31 error bounds (LSB = 2^-31), derived from the implementation's
 * roundings:
 *   applied command (e_ab): 0 when not reduced. CIRCLE: |v| = floor(sqrt)
 *     is within 1 LSB, the constant 2^31/sqrt(3) within 1/2, the scale
 *     factor s rounded to 1/2 LSB, so
 *       e_s = s (1/2 / K + 1 / |v|) + 1/2,   e_ab = 1/2 + |x| e_s / 2^31.
 *     HEXAGON: the spread comes from phase values within 1 LSB each (2 LSB),
 *     s = 2^62 / spread rounded: e_s = s * 2 / spread + 1/2, same e_ab.
 *   phases: inverse Clarke adds <= 1/2 + |beta| / 2^32 <= 1, and the
 *     command error propagates with |da| + |db| sqrt(3)/2:
 *       e_v = 1 + e_ab,alpha / 2 + e_ab,beta sqrt(3) / 2 (and e_ab,alpha
 *       for phase a, smaller).
 *   duty = round(1/2 + v_k - (max + min) / 2): max/min of perturbed values
 *     move by at most e_v, so e_duty = 2 e_v + 1/2.
 *   Duties are saturated to [0, INT32_MAX]; the reference is clamped the
 *   same way (clamping is 1-Lipschitz).
 * float32 bound (u = 2^-24, M = |alpha| + |beta| bounds every |v_k|):
 *   phases: input + constant + product + sum roundings, e_v <= 4 u M;
 *   reduced: scale error eps_s (HEXAGON 2 e_v / spread + 2u: spread error
 *   and the division; CIRCLE 8u: 1/spread cancels in r_lin_n / mag_n, the
 *   rest is two products, two squares, a sum, sqrt, constant and division),
 *   scaled phases e_v' = s (e_v + M (eps_s + u)), M' = s M;
 *   offset -(max+min)/2: e_v + u M; duty 1/2 + (v + off): + 2 u M + u.
 *   Total e_f = e_v + (e_v + u M) + 2 u M + u, first order (factor 1.01).
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/svpwm.h"
#include "mc/svpwm_q31.h"
#include "q31_test_util.h"

#define N_RANDOM     200000
#define N_GRID_ANGLE 720
#define F32_MARGIN   1.01

static const double k_sqrt3 = 1.7320508075688772935;
static const int32_t k_edges[] = { INT32_MIN, INT32_MIN + 1, INT32_MIN / 2, -1,       0,
                                   1,         INT32_MAX / 2, INT32_MAX - 1, INT32_MAX };
#define N_EDGES (sizeof k_edges / sizeof k_edges[0])

typedef struct {
    double duty[3]; /* per unit, exact */
    double alpha;   /* applied command, per unit of v_dc */
    double beta;
    double scale;  /* 1 when not reduced */
    double spread; /* max - min of the unreduced phases */
    double mag;    /* |v| of the unreduced command */
    int reduced;
    int sector;
} svpwm_ref_t;

static void phases(double alpha, double beta, double v[3])
{
    v[0] = alpha;
    v[1] = -0.5 * alpha + 0.5 * k_sqrt3 * beta;
    v[2] = -0.5 * alpha - 0.5 * k_sqrt3 * beta;
}

static double vmax3(const double v[3])
{
    return fmax(v[0], fmax(v[1], v[2]));
}
static double vmin3(const double v[3])
{
    return fmin(v[0], fmin(v[1], v[2]));
}

static svpwm_ref_t svpwm_ref(double alpha, double beta, mc_svpwm_limit_t limit)
{
    svpwm_ref_t r;
    double v[3];
    phases(alpha, beta, v);
    r.spread = vmax3(v) - vmin3(v);
    r.mag = hypot(alpha, beta);
    r.scale = 1.0;
    if (limit == MC_SVPWM_LIMIT_CIRCLE && alpha * alpha + beta * beta > 1.0 / 3.0) {
        r.scale = 1.0 / (k_sqrt3 * r.mag);
    } else if (limit == MC_SVPWM_LIMIT_HEXAGON && r.spread > 1.0) {
        r.scale = 1.0 / r.spread;
    }
    r.reduced = r.scale < 1.0;
    r.alpha = alpha * r.scale;
    r.beta = beta * r.scale;
    phases(r.alpha, r.beta, v);
    const double offset = -0.5 * (vmax3(v) + vmin3(v));
    for (int k = 0; k < 3; ++k) {
        r.duty[k] = 0.5 + v[k] + offset;
    }
    double angle = atan2(beta, alpha);
    if (angle < 0.0) {
        angle += MC_TEST_TWO_PI;
    }
    r.sector = (alpha == 0.0 && beta == 0.0) ? 1 : 1 + (int)floor(angle / (MC_TEST_PI / 3.0)) % 6;
    return r;
}

/* distance (per unit) of (alpha, beta) to the nearest sector boundary line */
static double boundary_distance(double alpha, double beta)
{
    const double d0 = fabs(beta);
    const double d1 = fabs(0.5 * k_sqrt3 * alpha - 0.5 * beta);
    const double d2 = fabs(0.5 * k_sqrt3 * alpha + 0.5 * beta);
    return fmin(d0, fmin(d1, d2));
}

static double clamp_duty_lsb(double duty_pu)
{
    const double lsb = duty_pu * Q31_SCALE;
    return lsb < 0.0 ? 0.0 : (lsb > INT32_MAX ? INT32_MAX : lsb);
}

/* error bound of the Q31 applied command, in LSB, per the header comment */
static double q31_command_bound(const svpwm_ref_t *r, double x_pu, mc_svpwm_limit_t limit)
{
    if (!r->reduced) {
        return 0.0;
    }
    const double s_lsb = r->scale * Q31_SCALE;
    double e_s;
    if (limit == MC_SVPWM_LIMIT_CIRCLE) {
        e_s = s_lsb * (0.5 / (Q31_SCALE / k_sqrt3) + 1.0 / (r->mag * Q31_SCALE)) + 0.5;
    } else {
        e_s = s_lsb * 2.0 / (r->spread * Q31_SCALE) + 0.5;
    }
    return 0.5 + fabs(x_pu) * e_s;
}

static double f32_duty_bound_pu(const svpwm_ref_t *r, double alpha, double beta,
                                mc_svpwm_limit_t limit)
{
    const double u = U_F32;
    double m = fabs(alpha) + fabs(beta);
    double e_v = 4.0 * u * m;
    if (r->reduced) {
        const double eps_s =
            limit == MC_SVPWM_LIMIT_HEXAGON ? 2.0 * e_v / r->spread + 2.0 * u : 8.0 * u;
        e_v = r->scale * (e_v + m * (eps_s + u));
        m *= r->scale;
    }
    return F32_MARGIN * (e_v + (e_v + u * m) + 2.0 * u * m + u);
}

static void check_svpwm(int32_t alpha, int32_t beta, mc_svpwm_limit_t limit)
{
    const double al = q31_to_real(alpha), be = q31_to_real(beta);
    const svpwm_ref_t r = svpwm_ref(al, be, limit);
    mc_svpwm_out_q31_t out;
    assert_int_equal(mc_svpwm_q31(alpha, beta, limit, &out), MC_OK);

    /* applied command */
    const double e_alpha = q31_command_bound(&r, al, limit) + 1e-3;
    const double e_beta = q31_command_bound(&r, be, limit) + 1e-3;
    assert_true(lsb_error(out.v_alpha_pu, r.alpha) <= e_alpha);
    assert_true(lsb_error(out.v_beta_pu, r.beta) <= e_beta);

    /* duties */
    const double e_v = 1.0 + 0.5 * e_alpha + 0.5 * k_sqrt3 * e_beta;
    const double e_duty = 2.0 * e_v + 0.5;
    for (int k = 0; k < 3; ++k) {
        assert_true(out.duty[k] >= 0);
        const double err = fabs((double)out.duty[k] - clamp_duty_lsb(r.duty[k]));
        if (err > e_duty) {
            fail_msg("alpha %ld beta %ld limit %d phase %d: duty %ld, ref %.2f, "
                     "error %.2f > %.2f",
                     (long)alpha, (long)beta, (int)limit, k, (long)out.duty[k],
                     r.duty[k] * Q31_SCALE, err, e_duty);
        }
    }

    /* overmodulation flag: the CIRCLE test is exact on the Q31 input; the
     * HEXAGON spread is within 2 LSB */
    if (limit == MC_SVPWM_LIMIT_CIRCLE) {
        if (fabs(al * al + be * be - 1.0 / 3.0) > 1e-12) {
            assert_int_equal(out.overmodulated, r.reduced);
        }
    } else if (fabs(r.spread - 1.0) * Q31_SCALE > 2.0 + 1e-3) {
        assert_int_equal(out.overmodulated, r.reduced);
    }

    /* sector: the Q31 boundary tests are exact up to 1/2 LSB of |alpha| */
    if (boundary_distance(al, be) * Q31_SCALE > 1.0) {
        assert_int_equal(out.sector, r.sector);
    }

    /* float32 version (v_dc = 1) */
    mc_svpwm_out_f32_t out_f;
    assert_int_equal(mc_svpwm_f32((float)al, (float)be, 1.0f, limit, &out_f), MC_OK);
    const double e_f = f32_duty_bound_pu(&r, al, be, limit) * Q31_SCALE;
    for (int k = 0; k < 3; ++k) {
        const double err = fabs((double)out.duty[k] - clamp_duty_lsb(out_f.duty[k]));
        if (err > e_duty + e_f) {
            fail_msg("alpha %ld beta %ld limit %d phase %d: q31 %ld vs f32 %.2f: "
                     "%.2f > %.2f",
                     (long)alpha, (long)beta, (int)limit, k, (long)out.duty[k],
                     out_f.duty[k] * Q31_SCALE, err, e_duty + e_f);
        }
    }
    const double f_flag_zone = 1e-5; /* relative: 170 u, far beyond float noise */
    const double flag_measure = limit == MC_SVPWM_LIMIT_CIRCLE ? r.mag * k_sqrt3 : r.spread;
    if (fabs(flag_measure - 1.0) > f_flag_zone) {
        assert_int_equal(out.overmodulated, out_f.overmodulated);
    }
    if (boundary_distance(al, be) > 1e-5 * (fabs(al) + fabs(be))) {
        assert_int_equal(out.sector, out_f.sector);
    }
}

static void test_svpwm_polar_grid(void **state)
{
    (void)state;
    /* magnitudes through the linear range, the circle, the hexagon and
     * beyond (up to 1.3 v_dc), all angles */
    for (int im = 0; im <= 26; ++im) {
        const double mag = 0.05 * im;
        for (int it = 0; it < N_GRID_ANGLE; ++it) {
            const double th = MC_TEST_TWO_PI * (it + 0.25) / N_GRID_ANGLE;
            const int32_t a = real_to_q31_sat(mag * cos(th));
            const int32_t b = real_to_q31_sat(mag * sin(th));
            check_svpwm(a, b, MC_SVPWM_LIMIT_CIRCLE);
            check_svpwm(a, b, MC_SVPWM_LIMIT_HEXAGON);
        }
    }
}

static void test_svpwm_random(void **state)
{
    (void)state;
    uint64_t seed = 0x5F3ULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const int32_t a = prng_q31(&seed), b = prng_q31(&seed);
        check_svpwm(a, b, MC_SVPWM_LIMIT_CIRCLE);
        check_svpwm(a, b, MC_SVPWM_LIMIT_HEXAGON);
        /* linear range and small commands */
        check_svpwm(a / 4, b / 4, MC_SVPWM_LIMIT_HEXAGON);
        check_svpwm(a / 65536, b / 65536, MC_SVPWM_LIMIT_CIRCLE);
    }
}

/* In the linear range line-to-line voltages are reproduced exactly:
 * duty_a - duty_b = v_a - v_b = 3/2 alpha - sqrt(3)/2 beta (and cyclic). */
static void test_svpwm_line_to_line(void **state)
{
    (void)state;
    uint64_t seed = 0x11EULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const double mag = prng_uniform(&seed, 0.0, 0.577);
        const double th = prng_uniform(&seed, -MC_TEST_PI, MC_TEST_PI);
        const int32_t a = real_to_q31_sat(mag * cos(th));
        const int32_t b = real_to_q31_sat(mag * sin(th));
        mc_svpwm_out_q31_t out;
        assert_int_equal(mc_svpwm_q31(a, b, MC_SVPWM_LIMIT_HEXAGON, &out), MC_OK);
        assert_false(out.overmodulated);
        const double al = q31_to_real(a), be = q31_to_real(b);
        /* each duty within 2 * 1 + 1/2 of exact (linear: e_ab = 0) */
        const double v_ab = 1.5 * al - 0.5 * k_sqrt3 * be;
        const double v_bc = k_sqrt3 * be;
        assert_true(lsb_error(out.duty[0] - out.duty[1], v_ab) <= 5.0);
        assert_true(lsb_error(out.duty[1] - out.duty[2], v_bc) <= 5.0);
    }
}

static void test_svpwm_full_scale_saturates(void **state)
{
    (void)state;
    for (size_t i = 0; i < N_EDGES; ++i) {
        for (size_t j = 0; j < N_EDGES; ++j) {
            check_svpwm(k_edges[i], k_edges[j], MC_SVPWM_LIMIT_CIRCLE);
            check_svpwm(k_edges[i], k_edges[j], MC_SVPWM_LIMIT_HEXAGON);
        }
    }
    /* (-1, -1): |v| = sqrt 2 at 225 deg, sector 4, reduced keeping the
     * angle. CIRCLE: onto |v| = 1/sqrt 3 (each component within the e_ab
     * bound, < 4 LSB, so the radius within 4 sqrt 2 < 6 LSB). HEXAGON: onto
     * the boundary, c the largest phase (duty 1), a the smallest (duty 0),
     * within the e_duty bound (< 12 LSB). */
    mc_svpwm_out_q31_t out;
    assert_int_equal(mc_svpwm_q31(INT32_MIN, INT32_MIN, MC_SVPWM_LIMIT_CIRCLE, &out), MC_OK);
    assert_true(out.overmodulated);
    assert_int_equal(out.sector, 4);
    assert_int_equal(out.v_alpha_pu, out.v_beta_pu);
    assert_true(fabs(hypot(out.v_alpha_pu, out.v_beta_pu) - Q31_SCALE / k_sqrt3) < 6.0);
    assert_int_equal(mc_svpwm_q31(INT32_MIN, INT32_MIN, MC_SVPWM_LIMIT_HEXAGON, &out), MC_OK);
    assert_true(out.overmodulated);
    assert_int_equal(out.sector, 4);
    assert_int_equal(out.v_alpha_pu, out.v_beta_pu);
    assert_true(out.duty[0] < 12);
    assert_true(out.duty[2] > INT32_MAX - 12);
    /* hexagon vertex along +alpha: applied alpha = 2/3, duties 1, 0, 0 */
    assert_int_equal(mc_svpwm_q31(INT32_MAX, 0, MC_SVPWM_LIMIT_HEXAGON, &out), MC_OK);
    assert_true(lsb_error(out.v_alpha_pu, 2.0 / 3.0) <= 2.0);
    assert_int_equal(out.duty[0], INT32_MAX);
    assert_true(out.duty[1] <= 2 && out.duty[2] <= 2);
}

/* The overmodulation thresholds at the LSB level. CIRCLE: the test is
 * exact, so two commands found (offline, by search) at 3.7 and -75 Q62 LSB
 * from alpha^2 + beta^2 = 1/3 must be classified exactly; the test first
 * checks their position in exact long double arithmetic (3 s vs 2^62, all
 * integers below 2^64). HEXAGON along beta = 0: spread = 1.5 alpha (odd
 * alpha: 1.5 alpha - 1/2 after rounding -alpha/2), decided exactly outside
 * the 2 LSB rounding zone of the spread. */
static void test_svpwm_limit_thresholds_exact(void **state)
{
    (void)state;
    static const int32_t above[2] = { 1063584733, 637193996 };
    static const int32_t below[2] = { 1067557751, 630514965 };
    const long double two_62 = ldexpl(1.0L, 62);
    const long double s_above = (long double)above[0] * above[0] + (long double)above[1] * above[1];
    const long double s_below = (long double)below[0] * below[0] + (long double)below[1] * below[1];
    assert_true(3.0L * s_above > two_62);
    assert_true(3.0L * s_below < two_62);
    mc_svpwm_out_q31_t out;
    assert_int_equal(mc_svpwm_q31(above[0], above[1], MC_SVPWM_LIMIT_CIRCLE, &out), MC_OK);
    assert_true(out.overmodulated);
    assert_int_equal(mc_svpwm_q31(below[0], below[1], MC_SVPWM_LIMIT_CIRCLE, &out), MC_OK);
    assert_false(out.overmodulated);

    const int32_t alpha_edge = 1431655765; /* floor(2^31 / 1.5) */
    for (int32_t alpha = alpha_edge - 64; alpha <= alpha_edge + 64; ++alpha) {
        const double spread_lsb = 1.5 * alpha - ((alpha & 1) ? 0.5 : 0.0);
        assert_int_equal(mc_svpwm_q31(alpha, 0, MC_SVPWM_LIMIT_HEXAGON, &out), MC_OK);
        if (fabs(spread_lsb - Q31_SCALE) > 2.0) {
            assert_int_equal(out.overmodulated, spread_lsb > Q31_SCALE);
        }
        assert_true(out.duty[0] >= INT32_MAX - 2 || !out.overmodulated);
        check_svpwm(alpha, 0, MC_SVPWM_LIMIT_HEXAGON);
        check_svpwm(-alpha, 0, MC_SVPWM_LIMIT_HEXAGON);
    }
}

static void test_svpwm_rejects_bad_limit(void **state)
{
    (void)state;
    mc_svpwm_out_q31_t out, before;
    memset(&out, 0x5A, sizeof out);
    before = out;
    assert_int_equal(mc_svpwm_q31(0, 0, (mc_svpwm_limit_t)7, &out), MC_ERR_PARAM);
    assert_memory_equal(&out, &before, sizeof out);
    assert_int_equal(mc_svpwm_q31(0, 0, MC_SVPWM_LIMIT_CIRCLE, &out), MC_OK);
    for (int k = 0; k < 3; ++k) {
        assert_int_equal(out.duty[k], 1 << 30); /* zero vector: 50 % */
    }
    assert_int_equal(out.sector, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_svpwm_polar_grid),
        cmocka_unit_test(test_svpwm_random),
        cmocka_unit_test(test_svpwm_line_to_line),
        cmocka_unit_test(test_svpwm_full_scale_saturates),
        cmocka_unit_test(test_svpwm_limit_thresholds_exact),
        cmocka_unit_test(test_svpwm_rejects_bad_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
