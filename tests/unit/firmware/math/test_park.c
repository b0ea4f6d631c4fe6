/*
 * Park transforms against the rotation of a vector given in polar form:
 * (alpha, beta) = M (cos psi, sin psi)  ->  (d, q) = M (cos(psi - theta),
 * sin(psi - theta)), computed in double.
 */
#include "mc_test.h"

#include <math.h>
#include <stdbool.h>

#include "mc/angle.h"
#include "mc/park.h"
#include "test_rng.h"

#define N_RANDOM  200000
#define FLT_EPS_D 1.1920929e-7

typedef void (*rotation_f32_t)(float x, float y, float sin_theta, float cos_theta, float *x_out,
                               float *y_out);

/* One vector M (cos psi, sin psi) through `rotate`: the result must be
 * M (cos(psi + sign theta), sin(psi + sign theta)) within 4 eps M per
 * component (sign -1: Park, +1: inverse Park); with check_norm also
 * |v| preserved by the rotation. */
static void check_rotation(rotation_f32_t rotate, double sign, double mag, double psi, double theta,
                           bool check_norm)
{
    float x, y;
    rotate((float)(mag * cos(psi)), (float)(mag * sin(psi)), (float)sin(theta), (float)cos(theta),
           &x, &y);
    const double tol = 4.0 * FLT_EPS_D * mag;
    assert_true(fabs(x - mag * cos(psi + sign * theta)) <= tol);
    assert_true(fabs(y - mag * sin(psi + sign * theta)) <= tol);
    if (check_norm) {
        assert_true(fabs(hypot(x, y) - mag) <= tol);
    }
}

/* N_RANDOM vectors, magnitude in [0, 100], angles in [-pi, pi]. */
static void check_random_rotations(uint64_t seed, rotation_f32_t rotate, double sign,
                                   bool check_norm)
{
    test_rng_t rng = test_rng_seed(seed);
    for (int n = 0; n < N_RANDOM; n++) {
        const double mag = test_rng_range(&rng, 0.0, 100.0);
        const double psi = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        const double theta = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        check_rotation(rotate, sign, mag, psi, theta, check_norm);
    }
}

static void test_park_rotates_by_minus_theta(void **state)
{
    (void)state;
    check_random_rotations(11, mc_park_f32, -1.0, true);
}

static void test_inv_park_rotates_by_plus_theta(void **state)
{
    (void)state;
    check_random_rotations(12, mc_inv_park_f32, +1.0, false);
}

/* Park then inverse Park with the firmware's own sincos (the way the fast
 * loop uses them) returns the input within the sincos error bound. */
static void test_park_round_trip_with_fast_sincos(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(13);
    for (int n = 0; n < N_RANDOM; n++) {
        const float alpha = (float)test_rng_range(&rng, -100.0, 100.0);
        const float beta = (float)test_rng_range(&rng, -100.0, 100.0);
        const float theta = (float)test_rng_range(&rng, -1.0e4, 1.0e4);
        float s, c, d, q, alpha2, beta2;
        mc_sincos_f32(theta, &s, &c);
        mc_park_f32(alpha, beta, s, c, &d, &q);
        mc_inv_park_f32(d, q, s, c, &alpha2, &beta2);
        const double mag = hypot(alpha, beta);
        /* R(theta) R(-theta) = (s^2 + c^2) I; |s^2 + c^2 - 1| <=
         * 2 * 1.0 * MC_SINCOS_MAX_ABS_ERR (+ rounding) */
        const double tol = mag * (4.0 * MC_SINCOS_MAX_ABS_ERR + 8.0 * FLT_EPS_D);
        assert_true(fabs(alpha2 - alpha) <= tol);
        assert_true(fabs(beta2 - beta) <= tol);
    }
}

/* Dense grid: a fixed vector seen from every angle on a 1e-4 rad grid. */
static void test_park_dense_angle_grid(void **state)
{
    (void)state;
    const double mag = 7.5;
    const double psi = 0.3;
    for (double theta = -MC_TEST_PI; theta <= MC_TEST_PI; theta += 1e-4) {
        check_rotation(mc_park_f32, -1.0, mag, psi, theta, false);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_park_rotates_by_minus_theta),
        cmocka_unit_test(test_inv_park_rotates_by_plus_theta),
        cmocka_unit_test(test_park_round_trip_with_fast_sincos),
        cmocka_unit_test(test_park_dense_angle_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
