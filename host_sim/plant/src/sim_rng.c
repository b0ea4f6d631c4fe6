#include "sim_rng.h"

#define SPLITMIX_GAMMA 0x9E3779B97F4A7C15ull

static uint64_t splitmix_mix(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

uint64_t sim_rng_next_u64(uint64_t *state)
{
    *state += SPLITMIX_GAMMA;
    return splitmix_mix(*state);
}

uint64_t sim_rng_hash(uint64_t seed, uint64_t index)
{
    return splitmix_mix(seed + (index + 1u) * SPLITMIX_GAMMA);
}

double sim_rng_unit(uint64_t bits)
{
    return (double)(bits >> 11) * 0x1.0p-53; /* 53 random mantissa bits */
}
