/*
 * Compiler helpers. MC_STATIC_FORCEINLINE marks the small per-sample steps
 * of the fast-ISR path that must be inlined into their one caller even at
 * -Os (as CMSIS's __STATIC_FORCEINLINE): the glue of the controllers and
 * estimators, the dispatch and the setpoint stage stay in their own files
 * without a call per sample.
 */
#ifndef MC_COMPILER_H
#define MC_COMPILER_H

#if defined(__GNUC__) || defined(__clang__)
#define MC_STATIC_FORCEINLINE static inline __attribute__((always_inline))
#else
#define MC_STATIC_FORCEINLINE static inline
#endif

#endif /* MC_COMPILER_H */
