/*
 * Finiteness of a batch of values: the check behind "every non-finite
 * value is a fault, not a zero".
 */
#ifndef MC_FINITE_H
#define MC_FINITE_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/compiler.h"

/* True if every element of x[0..n) is finite. Interrupt context: yes.
 * x * 0 is exactly +-0 for a finite x and NaN for a NaN or an infinity
 * (IEEE 754; the project never builds with -ffinite-math-only), and a sum
 * of zeros is zero: one comparison for the whole batch, no branch per
 * value. Inline and unrolled: the callers' batches are small and of
 * constant size, so the check is one multiply-add per value. */
MC_STATIC_FORCEINLINE bool mc_all_finite_f32(const float *x, uint32_t n)
{
    float acc = 0.0f;
#pragma GCC unroll 16
    for (uint32_t k = 0u; k < n; ++k) {
        acc += x[k] * 0.0f;
    }
    return acc == 0.0f;
}

/* *y = (float)x if that is finite and, for x != 0, nonzero (a design
 * value that overflows or underflows float32 is an error, not a 0 or
 * an infinity); returns false and leaves *y otherwise. Interrupt
 * context: yes. */
bool mc_f64_to_f32(double x, float *y);

#endif /* MC_FINITE_H */
