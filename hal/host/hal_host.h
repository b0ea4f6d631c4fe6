/*
 * Host binding of the HAL contract (the headers in hal/include/hal) to the
 * simulator: the mailbox binding of hal/sim_mailbox (see there), with:
 *
 * Cycle counter: by default the host's monotonic clock in ns
 * (clock_gettime(CLOCK_MONOTONIC), served by the vDSO without a system
 * call: about 25 ns a reading where CLOCK_THREAD_CPUTIME_ID is a system
 * call of about 500 ns), hal_cycle_counter_hz() = 1e9. The firmware's ISR
 * cost (first to last reading of its fast ISR) is then host wall time: the
 * mean over a run is the ISR's cost on this host; a single ISR during which
 * the OS preempted the simulator or served a page fault reads long, so the
 * maximum is an upper bound (sim_engine.c sets the overrun limit with
 * this in mind). hal_host_cycle_counter_thread_time(true) switches it to
 * the calling thread's CPU time (CLOCK_THREAD_CPUTIME_ID): the ISR's own
 * execution, as an MCU's cycle counter sees an ISR nothing preempts, for
 * runs paced to real time next to other processes (pmsm-sim --realtime),
 * where a reading's cost does not matter.
 *
 * Binding: per thread (_Thread_local); one thread may run several engines
 * by rebinding before each step. A HAL call while unbound aborts.
 *
 * CAN: the mailbox's queues (hal_sim_can.c); a SocketCAN bridge moves
 * frames between them and a CAN interface.
 */
#ifndef HAL_HOST_H
#define HAL_HOST_H

#include <stdbool.h>

#include "hal_sim_mailbox.h"

/* The clock of hal_cycle_counter for this thread: false (the default) the
 * monotonic clock, true the thread's CPU time (above). Set it before the
 * engine's first step. Not for the firmware. */
void hal_host_cycle_counter_thread_time(bool on);

/* How hal_cycle_counter measures on this thread, for reports of the ISR
 * cost (a static string). Not for the firmware. */
const char *hal_host_cycle_counter_method(void);

#endif /* HAL_HOST_H */
