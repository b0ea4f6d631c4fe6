/*
 * Exact zero-order-hold discretisation of x' = M x + g u over one period,
 * design time (double). Used by the gain designs of the paper regulators
 * (mc/eeo.h internal model, mc/cdobc.h observer and plant models).
 */
#ifndef MC_ZOH_H
#define MC_ZOH_H

#include <stdint.h>

#include "mc/status.h"

#define MC_ZOH_NMAX 16u /* largest state dimension */

/* D = exp(M Ts) - I (n x n, row major) and E = int_0^Ts exp(M t) g dt
 * (n), 1 <= n <= MC_ZOH_NMAX, M row major. Method: exp of the augmented
 * matrix X = [M g; 0 0] Ts, exp(X) - I = [D E; 0 0], by a 20-term Taylor
 * series of exp(.) - I on X / 2^s (||X / 2^s||_inf <= 0.5, truncation
 * below 0.5^21 / 21!) and s squarings in the form (I + D)^2 - I =
 * 2 D + D^2, which keeps D accurate when exp(M Ts) is close to I.
 * MC_ERR_NONFINITE for a non-finite input; MC_ERR_PARAM if Ts <= 0,
 * ||X||_inf > 1e3 or a non-finite result; outputs untouched on error.
 * Bounded time: at most 20 + 11 products of (n+1) x (n+1) matrices.
 * Interrupt context: no. */
mc_status_t mc_zoh_f64(uint32_t n, const double *M, const double *g,
                       double Ts_s, double *D, double *E);

/* y = a b for (n x n) row-major matrices, n >= 1; y must not alias a or
 * b. Design-time helper shared by the ZOH and the regulator analyses.
 * Interrupt context: no. */
void mc_mat_mul_f64(uint32_t n, const double *a, const double *b, double *y);

#endif /* MC_ZOH_H */
