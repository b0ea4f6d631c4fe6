/* Finiteness of a batch of values (mc/finite.h). */
#include "mc/finite.h"

#include <math.h>

bool mc_all_finite_f32(const float *x, uint32_t n)
{
    /* x * 0 is exactly +-0 for a finite x and NaN for a NaN or an
     * infinity (IEEE 754; the project never builds with
     * -ffinite-math-only), and a sum of zeros is zero: one comparison for
     * the whole batch, no branch per value. */
    float acc = 0.0f;
    for (uint32_t k = 0u; k < n; ++k) {
        acc += x[k] * 0.0f;
    }
    return acc == 0.0f;
}

bool mc_f64_to_f32(double x, float *y)
{
    const float f = (float)x;
    if (!isfinite(f) || (x != 0.0 && f == 0.0f)) {
        return false;
    }
    *y = f;
    return true;
}
