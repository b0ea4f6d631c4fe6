/* The harnesses' invariant check: a violated one aborts, which libFuzzer
 * reports as a finding with the input that caused it. */
#ifndef FUZZ_CHECK_H
#define FUZZ_CHECK_H

#include <stdlib.h>

#define CHECK(c)                                                                                   \
    do {                                                                                           \
        if (!(c)) {                                                                                \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

#endif /* FUZZ_CHECK_H */
