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

#endif /* MC_FINITE_H */
