/*
 * Host binding of the HAL contract (the headers in hal/include/hal) to the
 * simulator: the mailbox binding of hal/sim_mailbox (see there), with:
 *
 * Cycle counter: the calling thread's CPU time in ns
 * (clock_gettime(CLOCK_THREAD_CPUTIME_ID)), so the measured ISR cost is real
 * host time spent in the ISR, not inflated when the OS preempts the
 * simulator. hal_cycle_counter_hz() = 1e9.
 *
 * Binding: per thread (_Thread_local); one thread may run several engines
 * by rebinding before each step. A HAL call while unbound aborts.
 *
 * CAN has no host binding yet (SocketCAN comes with a later issue):
 * hal_can_* are not defined by this library.
 */
#ifndef HAL_HOST_H
#define HAL_HOST_H

#include "hal_sim_mailbox.h"

#endif /* HAL_HOST_H */
