/*
 * Host binding of the HAL contract (the headers in hal/include/hal) to the
 * simulator: the mailbox binding of hal/sim_mailbox (see there), with:
 *
 * Cycle counter: the host's monotonic clock in ns (clock_gettime(
 * CLOCK_MONOTONIC), served by the vDSO without a system call: about 25 ns
 * a reading where CLOCK_THREAD_CPUTIME_ID is a system call of about
 * 500 ns), hal_cycle_counter_hz() = 1e9. The firmware's ISR cost (first
 * to last reading of its fast ISR) is therefore host wall time: the mean
 * over a run is the ISR's cost on this host; a single ISR during which the
 * OS preempted the simulator or served a page fault reads long, so the
 * maximum is an upper bound (sim_engine.c sets the overrun limit with
 * this in mind).
 *
 * Binding: per thread (_Thread_local); one thread may run several engines
 * by rebinding before each step. A HAL call while unbound aborts.
 *
 * CAN: the mailbox's queues (hal_sim_can.c); a SocketCAN bridge moves
 * frames between them and a CAN interface.
 */
#ifndef HAL_HOST_H
#define HAL_HOST_H

#include "hal_sim_mailbox.h"

/* How hal_cycle_counter measures (for reports of the ISR cost). */
#define HAL_HOST_CYCLE_COUNTER_METHOD                                          \
    "host wall time of each firmware fast ISR, entry to duty write "           \
    "(clock_gettime(CLOCK_MONOTONIC) through the vDSO, the host HAL cycle "    \
    "counter); host time, not MCU cycles; it includes any preemption of the "  \
    "simulator, so the max is an upper bound"

/* HAL_HOST_CYCLE_COUNTER_METHOD (a static string). Not for the firmware. */
const char *hal_host_cycle_counter_method(void);

#endif /* HAL_HOST_H */
