/*
 * The PWM contract's duty protection (hal/pwm.h), for the bindings: a
 * duty outside [0, 1] takes the nearer bound, a NaN gives 0.5 (zero
 * voltage), a duty inside passes bit for bit.
 */
#ifndef HAL_PWM_DUTY_H
#define HAL_PWM_DUTY_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

/* d in [+0, 1] by its IEEE 754 binary32 bits, one integer comparison: the
 * non-negative floats order as their bits, and every negative float (-0
 * included) and every NaN lies above the bits of 1.0f. On the M4 this
 * is 3 instructions against the 6 of two float comparisons (and no
 * FPSCR transfer). */
static inline bool hal_duty_bits_in_unit(float d)
{
    uint32_t bits;
    memcpy(&bits, &d, sizeof bits);
    return bits <= 0x3f800000u;
}

/* The bound of a duty outside [+0, 1]: -0 itself, a NaN 0.5, else the
 * nearer bound. */
static inline float hal_duty_outside_unit_f32(float d)
{
    if (d == 0.0f) {
        return d; /* -0 */
    }
    if (isnan(d)) {
        return 0.5f;
    }
    return (d < 0.0f) ? 0.0f : 1.0f;
}

/* The protected duty: d itself in [0, 1] (-0 included), else the nearer
 * bound, NaN 0.5. The common case inline, the rest a call. Interrupt
 * context: yes. */
static inline __attribute__((always_inline)) float
hal_duty_saturate_f32(float d)
{
    /* the common case laid out as the fall-through */
    return __builtin_expect(hal_duty_bits_in_unit(d), 1)
               ? d
               : hal_duty_outside_unit_f32(d);
}

#endif /* HAL_PWM_DUTY_H */
