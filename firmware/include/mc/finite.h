/*
 * Finiteness of a batch of values: the check behind "every non-finite
 * value is a fault, not a zero".
 */
#ifndef MC_FINITE_H
#define MC_FINITE_H

#include <stdbool.h>
#include <stdint.h>

/* True if every element of x[0..n) is finite. Interrupt context: yes. */
bool mc_all_finite_f32(const float *x, uint32_t n);

/* *y = (float)x if that is finite and, for x != 0, nonzero (a design
 * value that overflows or underflows float32 is an error, not a 0 or
 * an infinity); returns false and leaves *y otherwise. Interrupt
 * context: yes. */
bool mc_f64_to_f32(double x, float *y);

#endif /* MC_FINITE_H */
