/*
 * Host binding of the HAL contract (the headers in hal/include/hal) to the simulator.
 *
 * The simulator engine owns a mailbox per simulated drive and binds it
 * before it calls into the firmware; the HAL functions read the engine's
 * inputs from it and write the firmware's outputs into it. The firmware
 * never sees plant state except through these HAL calls.
 *
 *   engine -> firmware: ADC sample, encoder count/index, fault input, time
 *   firmware -> engine: duties, PWM outputs enable, power-stage enable,
 *                       debug pin, PWM period
 *
 * Cycle counter: the calling thread's CPU time in ns
 * (clock_gettime(CLOCK_THREAD_CPUTIME_ID)), so the measured ISR cost is real
 * host time spent in the ISR, not inflated when the OS preempts the
 * simulator. hal_cycle_counter_hz() = 1e9.
 * Monotonic time (hal_time_ticks): the SIMULATED time in ns, set by the
 * engine; hal_time_tick_hz() = 1e9.
 *
 * CAN has no host binding yet (SocketCAN comes with a later issue):
 * hal_can_* are not defined by this library.
 *
 * Threading: the binding is per thread (_Thread_local); one thread may run
 * several engines by rebinding before each step.
 */
#ifndef HAL_HOST_H
#define HAL_HOST_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/adc.h"

typedef struct {
    /* engine -> firmware */
    hal_adc_sample_t adc;
    uint32_t encoder_cpr;
    uint32_t encoder_count;
    bool encoder_index_seen;
    uint32_t encoder_count_at_index;
    bool fault_input_active;
    uint64_t sim_time_ns;
    /* firmware -> engine */
    float pwm_period_s;          /* 0 until hal_pwm_init */
    float duty_abc[3];           /* [0, 1], applied from the next period */
    bool pwm_outputs_enabled;
    bool power_stage_enabled;
    bool debug_pin;
} hal_host_mailbox_t;

/* Bind (or with NULL unbind) the mailbox used by every HAL call of the
 * calling thread. Calling a HAL function while unbound aborts the program
 * (a test-bench wiring error). */
void hal_host_bind(hal_host_mailbox_t *mailbox);

/* Zero a mailbox: duties 0.5, everything disabled, no fault input. */
void hal_host_mailbox_reset(hal_host_mailbox_t *mailbox);

/* True when the inverter switches: PWM outputs AND power stage enabled. */
bool hal_host_outputs_active(const hal_host_mailbox_t *mailbox);

#endif /* HAL_HOST_H */
