/* Finiteness of a batch of values (mc/finite.h). */
#include "mc/finite.h"

#include <math.h>

bool mc_f64_to_f32(double x, float *y)
{
    const float f = (float)x;
    if (!isfinite(f) || (x != 0.0 && f == 0.0f)) {
        return false;
    }
    *y = f;
    return true;
}
