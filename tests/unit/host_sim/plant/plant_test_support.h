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

#endif /* PLANT_TEST_SUPPORT_H */
