/*
 * Seeded pseudo-random inputs for the unit tests (xorshift64*), so every
 * run checks the same inputs and a failure is reproducible.
 */
#ifndef TEST_RNG_H
#define TEST_RNG_H

#include <stdint.h>

/* One xorshift64* step on a raw state (must be non-zero): advances *state
 * and returns the 64-bit output. */
static inline uint64_t test_rng_next_u64(uint64_t *state)
{
    uint64_t x = *state;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *state = x;
    return x * 0x2545F4914F6CDD1Dull;
}

/* Uniform double in [0, 1) from the top 53 bits of a 64-bit output. */
static inline double test_rng_u64_to_unit(uint64_t x)
{
    return (double)(x >> 11) * 0x1.0p-53;
}

typedef struct {
    uint64_t state;
} test_rng_t;

static inline test_rng_t test_rng_seed(uint64_t seed)
{
    test_rng_t r = { seed ? seed : 0x9E3779B97F4A7C15ull };
    return r;
}

/* Uniform double in [0, 1) with 53 random bits. */
static inline double test_rng_unit(test_rng_t *r)
{
    return test_rng_u64_to_unit(test_rng_next_u64(&r->state));
}

/* Uniform double in [lo, hi). */
static inline double test_rng_range(test_rng_t *r, double lo, double hi)
{
    return lo + (hi - lo) * test_rng_unit(r);
}

#endif /* TEST_RNG_H */
