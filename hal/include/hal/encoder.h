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

/* The time from the latch of hal_encoder_count back to the counter's last
 * edge, in s, in [0, HAL_ENCODER_EDGE_AGE_MAX_S] (an older edge, or none,
 * reads as the maximum): true if the binding captures the edges' times
 * (a timer capture on the encoder inputs), false if it does not (*age_s
 * untouched). With two such ages the speed is counts over the time
 * between edges (M/T), without the count's quantisation. Interrupt
 * context: yes. */
bool hal_encoder_edge_age(float *age_s);
#endif

/* Largest edge age hal_encoder_edge_age reports, s. */
#define HAL_ENCODER_EDGE_AGE_MAX_S 1.0f

/* True once the index pulse has been seen since power-up; *count_at_index
 * (may be NULL) receives the counter value latched at the last index pulse.
 * Interrupt context: yes. */
bool hal_encoder_index(uint32_t *count_at_index);

#endif /* HAL_ENCODER_H */
