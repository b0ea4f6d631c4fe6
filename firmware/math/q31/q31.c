/* Out-of-line Q31 helpers (see mc/q31.h). Integer only. */
#include "mc/q31.h"

uint32_t mc_isqrt_u64(uint64_t x)
{
    /* Digit-by-digit square root, base 4: after the loop root = floor(sqrt(x))
     * and x holds the remainder. `bit` walks the 32 even bit positions. */
    uint64_t root = 0U;
    uint64_t bit = (uint64_t)1 << 62;
    for (int i = 0; i < 32; ++i) {
        if (x >= root + bit) {
            x -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    return (uint32_t)root;
}
