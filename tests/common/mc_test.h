/*
 * The include block every cmocka test needs (in the order cmocka requires)
 * and the constants the tests share, in double precision.
 */
#ifndef MC_TEST_H
#define MC_TEST_H

/* cmocka needs these before cmocka.h */
/* clang-format off */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
/* clang-format on */

#include <math.h>

/* |a - b| <= tol in double; NaN or an infinite difference fails. Use it
 * instead of cmocka's assert_float_equal, which (1.1.x) compares in float
 * and passes when an operand is NaN (it fails only on "diff > epsilon"). */
static inline void mc_test_assert_near(double a, double b, double tol, const char *expr,
                                       const char *file, int line)
{
    if (!(fabs(a - b) <= tol)) {
        print_error("%s = %.17g, expected %.17g +- %.3g\n", expr, a, b, tol);
        _fail(file, line);
    }
}

#define assert_near(a, b, tol)                                                                     \
    mc_test_assert_near((double)(a), (double)(b), (double)(tol), #a, __FILE__, __LINE__)

#define MC_TEST_PI            3.14159265358979323846
#define MC_TEST_TWO_PI        (2.0 * MC_TEST_PI)
#define MC_TEST_RAD_S_PER_RPM (MC_TEST_PI / 30.0) /* rad/s per rpm */

#endif /* MC_TEST_H */
