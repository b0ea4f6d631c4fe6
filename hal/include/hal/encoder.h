/*
 * HAL contract: incremental (quadrature) position encoder with index.
 */
#ifndef HAL_ENCODER_H
#define HAL_ENCODER_H

#include <stdbool.h>
#include <stdint.h>

/* Counts per mechanical revolution (edges, i.e. 4x the line count), > 0.
 * Interrupt context: yes. */
uint32_t hal_encoder_counts_per_rev(void);

#ifdef HAL_INLINE_ACCESSORS
#include HAL_INLINE_ACCESSORS /* the binding's static inline definitions */
#else
/* Position counter latched at this period's PWM centre, in counts, in
 * [0, counts_per_rev). Increases with positive mechanical rotation and wraps
 * at counts_per_rev. Interrupt context: yes. */
uint32_t hal_encoder_count(void);
#endif

/* True once the index pulse has been seen since power-up; *count_at_index
 * (may be NULL) receives the counter value latched at the last index pulse.
 * Interrupt context: yes. */
bool hal_encoder_index(uint32_t *count_at_index);

#endif /* HAL_ENCODER_H */
