/*
 * plant_test_support.h - helpers shared by the plant unit tests, written
 * independently of the plant sources (their own Clarke inverse, PRNG).
 */
#ifndef PLANT_TEST_SUPPORT_H
#define PLANT_TEST_SUPPORT_H

#include <stdint.h>

/* Duties that put the phase-voltage vector (v_alpha, v_beta) [V] on an ideal
 * inverter with bus v_dc (sine PWM around 0.5, no common mode). */
void test_duties_for_alpha_beta(double v_alpha, double v_beta, double v_dc, double duty[3]);

/* Test-local xorshift64 PRNG: uniform in [lo, hi). */
double test_uniform(uint64_t *state, double lo, double hi);

/* |got - want| / |want| */
double test_rel_err(double got, double want);

/* Mean DC current [A] of a six-diode bridge fed by a star of three equal
 * resistances R_ohm (no inductance) with balanced sinusoidal back-EMFs of
 * line peak E_V into a stiff bus v_V (0 <= v < E; with diode drops v_f,
 * v = v_dc + 2 v_f: every conducting path crosses one upper and one lower
 * diode, or shift all terminals by v_f). Over each 60 degree window the
 * largest line back-EMF is E cos(phi), |phi| <= pi/6.
 * v >= E cos(pi/6): one pair conducts while E cos(phi) > v, |phi| < phi0 =
 *   acos(v / E), carrying (E cos(phi) - v) / (2 R) (the third terminal stays
 *   between the rails), so
 *     i_avg = (3/pi) int_{-phi0}^{phi0} (E cos(phi) - v) / (2 R) dphi
 *           = (3/pi) (2 E sin(phi0) - 2 v phi0) / (2 R).
 * v < E cos(pi/6): the third phase joins near the windows' ends. Phase
 *   back-EMFs e_k = Ep cos(theta - 2 pi k / 3), Ep = E / sqrt(3); in the
 *   window theta in [0, pi/3] e_a >= e_b >= e_c, a on its upper diode, c on
 *   its lower one. With b on its lower diode too the star sits at v/3 and
 *   i_b = (-v/3 - e_b) / R > 0 needs e_b < -v/3; the bridge then carries
 *   -i_a = (e_a - 2 v / 3) / R. With b blocking (pair a-c) its terminal
 *   e_b - e_c - R I stays in [0, v] exactly while -v/3 <= e_b <= v/3; b on
 *   its upper diode (e_b > v/3) mirrors the first case. e_b = -v/3 at
 *   theta1 = acos(kappa) - pi/3, kappa = v / (sqrt(3) E), so
 *     i_avg = (3/pi) [ 2 (Ep sin(theta1) - 2 v theta1 / 3) / R
 *                    + (2 E sin(pi/6 - theta1) - v (pi/3 - 2 theta1)) / (2 R) ].
 *   The forms agree at v = E cos(pi/6) (theta1 = 0, phi0 = pi/6). (The
 *   one-pair value (3 E / pi - v) / (2 R) is not this: at v = 0 it gives
 *   3 E / (2 pi R) where the shorted star carries sqrt(3) E / (pi R).) */
double test_six_pulse_current_A(double E_V, double v_V, double R_ohm);

#endif /* PLANT_TEST_SUPPORT_H */
