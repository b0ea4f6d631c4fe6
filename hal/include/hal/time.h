/*
 * HAL contract: monotonic time and the cycle counter used to measure ISR
 * cost.
 */
#ifndef HAL_TIME_H
#define HAL_TIME_H

#include <stdint.h>

/* Monotonic time in ticks since power-up (never wraps in practice: 64 bit).
 * Interrupt context: yes. */
uint64_t hal_time_ticks(void);

/* Frequency of hal_time_ticks in Hz, > 0. Interrupt context:
 * yes. */
uint32_t hal_time_tick_hz(void);

#ifdef HAL_INLINE_ACCESSORS
#include HAL_INLINE_ACCESSORS /* the binding's static inline definitions */
#else
/* Free-running cycle counter, counting up. On a Cortex-M it is
 * DWT->CYCCNT; on the host it is the host's monotonic clock in ns (see
 * hal/host). It wraps at 2^32, or on a binding with a narrower timer at
 * that timer's width (at least 24 bits): measure intervals with
 * hal_cycles_since. Callable from interrupt context: yes; cost a few
 * cycles. */
uint32_t hal_cycle_counter(void);

/* Cycles from a hal_cycle_counter() value to now, for an interval shorter
 * than the counter's wrap. Callable from interrupt context: yes. */
static inline uint32_t hal_cycles_since(uint32_t start)
{
    return hal_cycle_counter() - start;
}
#endif

/* Frequency of hal_cycle_counter in Hz, > 0. Callable from interrupt
 * context: yes. */
uint32_t hal_cycle_counter_hz(void);

#endif /* HAL_TIME_H */
