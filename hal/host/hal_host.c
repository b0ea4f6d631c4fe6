/* Host backend of the simulator mailbox binding (hal_host.h). */
#define _POSIX_C_SOURCE 199309L

#include "hal_host.h"

#include <stdlib.h>
#include <time.h>

#include "hal/time.h"

#define HAL_HOST_NS_PER_S 1000000000u

static _Thread_local hal_sim_mailbox_t *bound;

void hal_sim_bind(hal_sim_mailbox_t *mailbox)
{
    bound = mailbox;
}

hal_sim_mailbox_t *hal_sim_bound(void)
{
    if (bound == NULL) {
        abort(); /* wiring error of the test bench: no mailbox bound */
    }
    return bound;
}

hal_sim_mailbox_t *hal_sim_fixed_mailbox(void)
{
    return NULL; /* engines per thread, each with its own */
}

static _Thread_local clockid_t cycle_clock = CLOCK_MONOTONIC;

void hal_host_cycle_counter_thread_time(bool on)
{
    cycle_clock = on ? CLOCK_THREAD_CPUTIME_ID : CLOCK_MONOTONIC;
}

uint32_t hal_cycle_counter(void)
{
    struct timespec ts;
    if (clock_gettime(cycle_clock, &ts) != 0) {
        abort(); /* POSIX requires both clocks */
    }
    const uint64_t ns =
        (uint64_t)ts.tv_sec * HAL_HOST_NS_PER_S + (uint64_t)ts.tv_nsec;
    return (uint32_t)ns; /* wraps every 4.29 s: differences stay valid */
}

uint32_t hal_cycle_counter_hz(void)
{
    return HAL_HOST_NS_PER_S;
}

const char *hal_host_cycle_counter_method(void)
{
    if (cycle_clock == CLOCK_THREAD_CPUTIME_ID) {
        return "host CPU time of the simulator's thread in each firmware "
               "fast ISR, entry to duty write (clock_gettime("
               "CLOCK_THREAD_CPUTIME_ID), the host HAL cycle counter in a "
               "real-time run); host time, not MCU cycles; the time the OS "
               "gave to other threads is not in it";
    }
    return "host wall time of each firmware fast ISR, entry to duty write "
           "(clock_gettime(CLOCK_MONOTONIC) through the vDSO, the host HAL "
           "cycle counter); host time, not MCU cycles; it includes any "
           "preemption of the simulator, so the max is an upper bound";
}
