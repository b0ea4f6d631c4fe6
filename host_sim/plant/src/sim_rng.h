/*
 * sim_rng.h - the plant's own deterministic PRNG (SplitMix64, Steele et al.
 * 2014), so results depend only on the seed and never on the C library.
 */
#ifndef SIM_RNG_H
#define SIM_RNG_H

#include <stdint.h>

/* Next 64-bit output; advances *state. */
uint64_t sim_rng_next_u64(uint64_t *state);

/* Stateless hash of (seed, index) with the same mixer: the index-th draw of
 * an independent stream, used where random values must be evaluable in any
 * order (profile noise tones). */
uint64_t sim_rng_hash(uint64_t seed, uint64_t index);

/* Map 64 random bits to a double uniform in [0, 1). */
double sim_rng_unit(uint64_t bits);

#endif /* SIM_RNG_H */
