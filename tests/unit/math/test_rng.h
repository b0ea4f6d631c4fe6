/*
 * Seeded pseudo-random inputs for the math tests (xorshift64*), so every
 * run checks the same inputs and a failure is reproducible.
 */
#ifndef TEST_RNG_H
#define TEST_RNG_H

#include <stdint.h>

typedef struct {
    uint64_t state;
} test_rng_t;

static inline test_rng_t test_rng_seed(uint64_t seed)
{
    test_rng_t r = {seed ? seed : 0x9E3779B97F4A7C15ull};
    return r;
}

/* Uniform double in [0, 1) with 53 random bits. */
static inline double test_rng_unit(test_rng_t *r)
{
    r->state ^= r->state >> 12;
    r->state ^= r->state << 25;
    r->state ^= r->state >> 27;
    const uint64_t x = r->state * 0x2545F4914F6CDD1Dull;
    return (double)(x >> 11) * 0x1.0p-53;
}

/* Uniform double in [lo, hi). */
static inline double test_rng_range(test_rng_t *r, double lo, double hi)
{
    return lo + (hi - lo) * test_rng_unit(r);
}

#endif /* TEST_RNG_H */
