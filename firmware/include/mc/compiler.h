/*
 * Compiler helpers. MC_STATIC_FORCEINLINE marks the small per-sample steps
 * of the fast-ISR path that must be inlined into their one caller even at
 * -Os (as CMSIS's __STATIC_FORCEINLINE): the glue of the controllers and
 * estimators, the dispatch and the setpoint stage stay in their own files
 * without a call per sample. MC_LIKELY / MC_UNLIKELY tell the compiler
 * the common case of a test on that path, which it then lays out as the
 * fall-through: a taken branch costs the M4 a pipeline refill (1 to 3
 * cycles), and a common case placed out of line a branch back as well.
 */
#ifndef MC_COMPILER_H
#define MC_COMPILER_H

#if defined(__GNUC__) || defined(__clang__)
#define MC_STATIC_FORCEINLINE static inline __attribute__((always_inline))
#define MC_LIKELY(x)          __builtin_expect(!!(x), 1)
#define MC_UNLIKELY(x)        __builtin_expect(!!(x), 0)
#else
#define MC_STATIC_FORCEINLINE static inline
#define MC_LIKELY(x)          (x)
#define MC_UNLIKELY(x)        (x)
#endif

#endif /* MC_COMPILER_H */
