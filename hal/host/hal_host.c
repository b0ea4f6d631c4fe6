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

uint32_t hal_cycle_counter(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0) {
        abort(); /* POSIX requires this clock */
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
    return HAL_HOST_CYCLE_COUNTER_METHOD;
}
