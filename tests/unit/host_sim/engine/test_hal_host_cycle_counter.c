/*
 * The host binding's cycle counter (hal/host/hal_host.h): by default the
 * monotonic clock, which counts a sleep; with
 * hal_host_cycle_counter_thread_time(true) the thread's CPU time, which
 * does not (a sleeping thread uses no CPU: what the time the OS gives to
 * other processes looks like to the simulator's thread). Each mode names
 * itself in the report's method string.
 */
#define _POSIX_C_SOURCE 199309L

#include "mc_test.h"

#include <string.h>
#include <time.h>

#include "hal/time.h"
#include "hal_host.h"

#define SLEEP_NS 20000000L /* 20 ms */

static uint32_t ns_across_sleep(void)
{
    const struct timespec ts = { .tv_sec = 0, .tv_nsec = SLEEP_NS };
    const uint32_t t0 = hal_cycle_counter();
    assert_int_equal(nanosleep(&ts, NULL), 0);
    return hal_cycle_counter() - t0;
}

static void test_monotonic_counts_a_sleep(void **state)
{
    (void)state;
    hal_host_cycle_counter_thread_time(false);
    assert_int_equal(hal_cycle_counter_hz(), 1000000000u);
    assert_true(ns_across_sleep() >= (uint32_t)SLEEP_NS);
    assert_non_null(strstr(hal_host_cycle_counter_method(), "CLOCK_MONOTONIC"));
}

static void test_thread_time_leaves_a_sleep_out(void **state)
{
    (void)state;
    hal_host_cycle_counter_thread_time(true);
    /* the calls around the sleep cost microseconds of CPU, not 10 ms */
    assert_true(ns_across_sleep() < (uint32_t)(SLEEP_NS / 2));
    assert_non_null(strstr(hal_host_cycle_counter_method(), "CLOCK_THREAD_CPUTIME_ID"));
    hal_host_cycle_counter_thread_time(false);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_monotonic_counts_a_sleep),
        cmocka_unit_test(test_thread_time_leaves_a_sleep_out),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
