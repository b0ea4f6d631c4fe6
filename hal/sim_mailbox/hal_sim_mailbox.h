/*
 * The HAL contract (hal/include/hal) bound to a simulator's mailbox: shared
 * by the host binding (hal/host) and the QEMU image (hal/qemu_m4), which
 * both run the firmware against the plant model through host_sim/engine.
 *
 * The engine owns a mailbox per simulated drive and binds it before it
 * calls into the firmware; the HAL functions read the engine's inputs from
 * it and write the firmware's outputs into it. The firmware never sees
 * plant state except through these HAL calls.
 *
 *   engine -> firmware: ADC sample, encoder count/index, fault input, time,
 *                       the PWM the simulated inverter makes (its rate and
 *                       its sample-to-apply delay: hal/pwm.h), whether the
 *                       board has over-current comparators and whether an
 *                       armed one trips at this sample
 *   firmware -> engine: duties, PWM outputs enable, power-stage enable,
 *                       debug pin, the comparators' level
 *   both ways:          CAN frames (hal_sim_can.c: a bounded queue each
 *                       way; the engine or a bridge to SocketCAN fills
 *                       the receive queue and empties the transmit one)
 *
 * hal_sim_mailbox.c implements the PWM, ADC, encoder, GPIO and
 * hal_time_ticks functions on the bound mailbox (monotonic time = the
 * SIMULATED time in ns, hal_time_tick_hz() = 1e9). Each backend provides
 * the rest: where the binding is kept (hal_sim_bind, hal_sim_bound) and
 * the cycle counter (hal_cycle_counter, hal_cycle_counter_hz).
 */
/* The HAL types first, outside the guard: with HAL_INLINE_ACCESSORS,
 * hal/adc.h includes the binding's accessors, which include this header
 * for the mailbox type. */
#include "hal/adc.h"
#include "hal/can.h"

#ifndef HAL_SIM_MAILBOX_H
#define HAL_SIM_MAILBOX_H

#include <stdbool.h>
#include <stdint.h>

#define HAL_SIM_CAN_QUEUE_LEN 64u /* frames per direction */

/* A bounded FIFO of CAN frames (single producer, single consumer, both
 * on the engine's thread). */
typedef struct {
    hal_can_frame_t frames[HAL_SIM_CAN_QUEUE_LEN];
    uint32_t head, count; /* oldest frame, frames queued */
} hal_sim_can_queue_t;

typedef struct {
    /* engine -> firmware */
    hal_adc_sample_t adc;
    uint32_t encoder_cpr;
    uint32_t encoder_count;
    float encoder_edge_age_s; /* hal_encoder_edge_age: the simulator
                                 keeps edge times (none: the maximum) */
    bool encoder_index_seen;
    uint32_t encoder_count_at_index;
    bool fault_input_active;
    bool oc_comparator; /* the simulated board has over-current
                           comparators (hal_pwm_overcurrent_arm) */
    bool oc_active;     /* an armed comparator sees a phase current beyond
                           its level at this sample */
    uint64_t sim_time_ns;
    float pwm_f_Hz;          /* the plant's PWM rate: hal_pwm_init
                                realises its period 1 / pwm_f_Hz */
    float pwm_delay_periods; /* the engine's sample-to-apply delay */
    /* firmware -> engine */
    float oc_trip_A;   /* the comparators' level, 0: not armed */
    float duty_abc[3]; /* [0, 1], applied from the next period */
    bool pwm_outputs_enabled;
    bool power_stage_enabled;
    bool debug_pin;
    /* CAN (hal_sim_can.c) */
    bool can_up; /* hal_can_init succeeded */
    uint32_t can_bitrate_bps;
    hal_sim_can_queue_t can_rx; /* engine -> firmware */
    hal_sim_can_queue_t can_tx; /* firmware -> engine */
    hal_can_stats_t can_stats;  /* rx_overruns: can_rx full */
} hal_sim_mailbox_t;

/* Bind (or with NULL unbind) the mailbox used by every HAL call.
 * Backend-provided (host: per thread; QEMU image: one per image). */
void hal_sim_bind(hal_sim_mailbox_t *mailbox);

/* The bound mailbox. Backend-provided; a HAL call while unbound is a
 * wiring error of the test bench and ends the program (never returns
 * NULL). */
hal_sim_mailbox_t *hal_sim_bound(void);

/* The mailbox at a fixed address that the backend's accessors reach
 * directly, as a board's binding reaches its peripheral registers (the
 * QEMU image: one engine), or NULL: each engine keeps its own (host: per
 * thread). An engine uses the fixed one when there is one.
 * Backend-provided. */
hal_sim_mailbox_t *hal_sim_fixed_mailbox(void);

/* Zero a mailbox: duties 0.5, everything disabled, no fault input, no
 * encoder edge yet. */
void hal_sim_mailbox_reset(hal_sim_mailbox_t *mailbox);

/* Queue a frame for the firmware (engine side). false, counted in
 * can_stats.rx_overruns, when the receive queue is full. */
bool hal_sim_can_deliver(hal_sim_mailbox_t *mailbox,
                         const hal_can_frame_t *frame);

/* Take the oldest frame the firmware sent (engine side); false if none. */
bool hal_sim_can_collect(hal_sim_mailbox_t *mailbox, hal_can_frame_t *frame);

/* True when the inverter switches: PWM outputs AND power stage enabled, and
 * no armed over-current comparator tripped (oc_active). */
bool hal_sim_outputs_active(const hal_sim_mailbox_t *mailbox);

#endif /* HAL_SIM_MAILBOX_H */
