/*
 * sim_engine.h - closed-loop simulation: plant + host HAL + drive firmware.
 *
 * One sim_engine_step() is one PWM period k (t_k = k Ts):
 *   0. the command goes to the firmware (mc_app_set_command); the plant's
 *      runtime faults are set to what the plant-side injections active at
 *      t_k say (plant_set_*: they act from this period's advance on);
 *   1. plant_sample(): currents, v_dc, encoder at the PWM centre t_k;
 *   2. active measurement-side injections edit that measurement / the
 *      fault input;
 *   3. the host HAL mailbox gets the sample, the firmware fast ISR runs;
 *   4. the plant advances over [t_k, t_k + Ts). The duties latch at the
 *      inverter's update event (plant inverter.duty_update):
 *      PLANT_DUTY_UPDATE_NEXT_PERIOD (default): at t_{k+1}, so the period
 *        runs on the PREVIOUS ISR's duties; ISR k's act over
 *        [t_{k+1}, t_{k+2}): sample-to-apply delay 1.5 periods;
 *      PLANT_DUTY_UPDATE_HALF_PERIOD: at t_k + Ts/2 (plant_advance_split):
 *        ISR k's act over [t_k + Ts/2, t_{k+1} + Ts/2): delay 1.0 period.
 *      The engine reports that delay to the firmware through the HAL
 *      (hal/pwm.h). The PWM outputs follow the same update when they are
 *      ENABLED, but a disable is immediate (no shadow register), so an ISR
 *      that trips a fault at t_k stops the inverter for [t_k, t_k + Ts)
 *      already.
 *   5. the trace sample of period k is recorded (sim_engine_last()).
 *
 * The firmware sees the plant only through the HAL. The plant and firmware
 * PWM frequencies and encoder resolutions must agree (checked by init).
 *
 * Fault injection (for tests and scenarios) is driven by the sample time:
 * an injection is active for t_start_s <= t_k < t_end_s.
 *
 * CAN (optional, sim_engine_can_attach): the drive gets a CAN node
 * (mc/can_node.h) on its HAL mailbox's CAN queues. From then on the drive's
 * command comes from the node: the command argument of sim_engine_step is
 * ignored, and the node is polled (mc_can_node_poll) after every fast ISR
 * of step 3, with the mailbox bound and hal_time_ticks() = t_k. Frames go
 * in and out through sim_engine_can_deliver / sim_engine_can_collect (a
 * test, or a bridge to a CAN interface: hal/host/socketcan.h).
 *
 * Host only (C11, double precision, no allocation: the caller owns the
 * engine, about 11 kB, plant and CAN node included; allocate it statically
 * or on the heap, and do not copy an initialised engine: the CAN node keeps
 * a pointer to it). Single-threaded per engine; several engines may be
 * stepped in turn from one thread (each step binds its own HAL mailbox).
 */
#ifndef SIM_ENGINE_H
#define SIM_ENGINE_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/can.h"
#include "hal_sim_mailbox.h"
#include "mc/app.h"
#include "mc/can_node.h"
#include "plant.h"

#define SIM_ENGINE_MAX_INJECTIONS 16u

/* Sample-to-apply delays of the two duty-update models (periods). */
#define SIM_ENGINE_DELAY_NEXT_PERIOD 1.5f
#define SIM_ENGINE_DELAY_HALF_PERIOD 1.0f

typedef enum {
    SIM_ENGINE_OK = 0,
    SIM_ENGINE_ERR_NULL = -1,
    SIM_ENGINE_ERR_PLANT = -2,     /* plant_init failed, or the plant refused
                                      a plant-side fault (see the message) */
    SIM_ENGINE_ERR_MISMATCH = -3,  /* plant and firmware disagree (PWM
                                      frequency, encoder cpr) */
    SIM_ENGINE_ERR_FIRMWARE = -4,  /* mc_app_init failed */
    SIM_ENGINE_ERR_INJECTION = -5, /* invalid injection or table full */
    SIM_ENGINE_ERR_COMMAND = -6,   /* mc_app_set_command rejected it */
    SIM_ENGINE_ERR_STATE = -7,     /* step on an engine whose init failed;
                                      a CAN node attached twice */
    SIM_ENGINE_ERR_CAN = -8        /* hal_can_init or mc_can_node_init
                                      refused (see the message) */
} sim_engine_err_t;

/* Measurement-side kinds (CURRENT_*, VDC_MEASURED, FAULT_INPUT, ENCODER_*)
 * edit what the HAL reports (the measurement of step 2); the plant itself
 * is untouched. Several active ones are applied in the order they were
 * added, each to the measurement as the earlier ones left it (a
 * current_offset after a current_stuck adds to the stuck value; an
 * encoder_frozen holds whatever count reached it). The encoder kinds edit
 * the count only, in the counts the HAL reports (cpr = 4 x plant encoder
 * lines, 0..cpr-1); the index flag stays the plant's (the firmware does
 * not use the index).
 * Plant-side kinds (PHASE_OPEN, ROTOR_LOCK, BUS_SOURCE_LOSS, DEAD_TIME)
 * change the plant through plant_set_phase_open / _rotor_locked /
 * _source_connected / _dead_time
 * for the periods [t_k, t_k + Ts) whose sample t_k is in their window (the
 * true state shows the change from the next sample on). Outside every
 * window the plant is in its normal state: phases connected, the rotor
 * free (locked throughout if the plant config says locked_rotor), the
 * source connected. Overlapping windows of one fault add up (a phase is
 * open while any of its phase_open injections is active). */
typedef enum {
    SIM_INJECT_CURRENT_NAN = 0,     /* measured current of `phase` := NaN */
    SIM_INJECT_CURRENT_OFFSET,      /* measured current of `phase` += value (A):
                                       a sensor spike / fault */
    SIM_INJECT_VDC_MEASURED,        /* measured v_dc := value (V) */
    SIM_INJECT_FAULT_INPUT,         /* external fault / STO input asserted */
    SIM_INJECT_ENCODER_SLIP,        /* count := (count + slip) mod cpr, a slipped
                                       code wheel or a lost index correction:
                                       slip = round(angle_e_rad / n_p * cpr /
                                       (2 pi)) counts (n_p: the plant's pole
                                       pairs; round half away from zero);
                                       negative angles slip backwards */
    SIM_INJECT_ENCODER_FROZEN,      /* count := the count at the first active
                                       sample (a seized encoder, a cut cable
                                       with held inputs); the edge age
                                       (hal_encoder_edge_age) grows from the
                                       last edge before it. SLIP and
                                       COUNT_LOSS keep the true motion's
                                       edge age */
    SIM_INJECT_ENCODER_COUNT_LOSS,  /* lost counts: from the first active
                                       sample the count advances by
                                       (1 - lost_fraction) of each increment
                                       of the count (accumulated in whole
                                       counts plus a fractional remainder,
                                       rounded down, mod cpr); increments are
                                       taken modulo cpr as the shorter way
                                       round (less than half a turn per
                                       period) */
    SIM_INJECT_CURRENT_OFFSET_RAMP, /* measured current of `phase` +=
                                       rate_A_s * (t_k - t_start_s): an
                                       offset drifting from 0 at t_start */
    SIM_INJECT_CURRENT_STUCK,       /* measured current of `phase` := value
                                       (A): a stuck sensor or ADC channel */
    SIM_INJECT_PHASE_OPEN,          /* phase terminal `phase` disconnected */
    SIM_INJECT_ROTOR_LOCK,          /* a shaft brake holds the rotor */
    SIM_INJECT_BUS_SOURCE_LOSS,     /* the DC source is disconnected from the
                                       link (needs a link capacitance) */
    SIM_INJECT_CURRENT_GAIN,        /* measured current of `phase` *= value
                                       (a gain error; value finite, > 0) */
    SIM_INJECT_DEAD_TIME            /* plant side: the inverter's dead time
                                       is dead_time_s (plant_set_dead_time;
                                       the last active one in the table
                                       wins); outside every window the
                                       plant config's. The firmware keeps
                                       the dead time it was configured with */
} sim_inject_kind_t;

typedef struct {
    sim_inject_kind_t kind;
    double t_start_s;     /* active for t_start_s <= t_k < t_end_s */
    double t_end_s;       /* may be INFINITY */
    uint32_t phase;       /* 0, 1, 2 (a, b, c): CURRENT_NAN, CURRENT_OFFSET,
                             CURRENT_OFFSET_RAMP, CURRENT_STUCK,
                             CURRENT_GAIN, PHASE_OPEN */
    double value;         /* A or V: CURRENT_OFFSET, VDC_MEASURED,
                             CURRENT_STUCK; the factor of CURRENT_GAIN;
                             s: DEAD_TIME */
    double angle_e_rad;   /* ENCODER_SLIP: electrical rad */
    double lost_fraction; /* ENCODER_COUNT_LOSS: in (0, 1) */
    double rate_A_s;      /* CURRENT_OFFSET_RAMP: A/s */
} sim_injection_t;

/* Private: what an injection carries from sample to sample. */
typedef struct {
    bool started;            /* active at an earlier sample */
    uint32_t count;          /* ENCODER_SLIP: slip (0..cpr-1);
                                ENCODER_FROZEN: the held count;
                                ENCODER_COUNT_LOSS: the reported count */
    uint32_t count_in;       /* ENCODER_COUNT_LOSS: the count it received at
                                the previous sample */
    double remainder_counts; /* ENCODER_COUNT_LOSS: [0, 1) */
    double t_edge_s;         /* ENCODER_FROZEN: the last edge before it */
} sim_injection_state_t;

/* Private: the plant-side faults as the engine last set them. */
typedef struct {
    bool phase_open[3];
    bool rotor_locked;
    bool source_connected;
    double t_dead_s;
} sim_plant_faults_t;

/* Everything about PWM period k. */
typedef struct {
    uint64_t k;                 /* period index */
    double t_s;                 /* t_k = k Ts, the sampling instant */
    plant_true_state_t plant;   /* true plant state at t_k (its v_abc are
                                   the averages over the previous period) */
    plant_measurement_t meas;   /* what the HAL delivered (after the
                                   injections) */
    uint32_t injections_active; /* bit i: injection i was active at t_k */
    mc_command_t cmd;           /* command given for this step (with a CAN
                                   node attached: the node's command in
                                   force at this ISR) */
    mc_telemetry_t fw;          /* firmware telemetry of the ISR at t_k */
    double duty_applied[3];     /* duties the inverter used from t_k
                                   (to t_k + Ts, or to t_k + Ts/2 with the
                                   half-period update) */
    bool outputs_applied;       /* inverter switching in [t_k, t_k + Ts) */
    bool oc_tripped;            /* the board's armed over-current
                                   comparators tripped at t_k (the outputs
                                   off from there) */
} sim_trace_sample_t;

/* Private: the caller owns the storage; use the functions below. */
typedef struct {
    plant_t plant;
    mc_app_t app;
    mc_config_t fw_cfg;        /* the firmware configuration in force */
    hal_sim_mailbox_t mailbox; /* unless the backend has a fixed one
                                  (hal_sim_fixed_mailbox) */
    bool can_attached;
    mc_can_node_t can_node;
    double duty_next[3]; /* latched by the last ISR */
    bool outputs_next;
    bool half_period_update;         /* plant inverter.duty_update */
    uint32_t pole_pairs;             /* the plant's (encoder_slip) */
    bool dc_link_capacitive;         /* plant dc_link.capacitance_F > 0
                                        (bus_source_loss) */
    sim_plant_faults_t plant_normal; /* outside every window */
    sim_plant_faults_t plant_faults; /* in effect from the last step */
    sim_injection_t injections[SIM_ENGINE_MAX_INJECTIONS];
    sim_injection_state_t injection_state[SIM_ENGINE_MAX_INJECTIONS];
    uint32_t n_injections;
    uint64_t k;
    sim_trace_sample_t last;
    bool initialised;
    const char *message;
} sim_engine_t;

/* The firmware values the bench takes from the plant: the nominal motor
 * (the controller's model; the plant applies its mismatch), the PWM rate,
 * the inverter's dead time and device drop (what a board's firmware knows
 * of its own inverter) and the encoder resolution (4 x lines); and the ones
 * the host sets: the
 * ISR-overrun fault after MC_TIMING_OVERRUN_LIMIT_MAX periods over budget
 * in a row (the ISR is timed in host wall time, see sim_engine.c), and the
 * telemetry record written by every ISR (timing.telemetry_every_isr: the
 * traces and metrics read it after each). The rest of *fw is kept.
 * Call after mc_config_init_default() (or on any configuration). */
void sim_engine_firmware_from_plant(const plant_config_t *plant, mc_config_t *fw);

/* Initialise plant and firmware (the firmware enters IDLE with the PWM
 * off). Returns SIM_ENGINE_OK or a negative sim_engine_err_t; the message
 * (sim_engine_message) says what is wrong. */
int sim_engine_init(sim_engine_t *e, const plant_config_t *plant_cfg, const mc_config_t *fw_cfg);

/* Static sentence about the last init/add/step result ("ok"). */
const char *sim_engine_message(const sim_engine_t *e);

/* Add a fault injection to an initialised engine, before or between steps
 * (one whose start has passed is active from the next sample on). Rejects
 * (SIM_ENGINE_ERR_INJECTION, the message names the field): a non-finite
 * start, end < start (or NaN), a phase > 2 for the current kinds, a
 * non-finite value (CURRENT_OFFSET, VDC_MEASURED, CURRENT_STUCK),
 * angle_e_rad (ENCODER_SLIP) or rate_A_s (CURRENT_OFFSET_RAMP), a
 * lost_fraction outside (0, 1), an encoder kind on a plant without encoder
 * (lines 0), a phase > 2 for PHASE_OPEN, a BUS_SOURCE_LOSS on a stiff bus
 * (dc_link.capacitance_F 0), an unknown kind, or a full table.
 * SIM_ENGINE_ERR_STATE on an engine whose init failed. */
int sim_engine_add_injection(sim_engine_t *e, const sim_injection_t *inj);

/* Simulate one PWM period with this command (see the top of this file).
 * With a CAN node attached the command comes from the node: cmd is
 * ignored and may be NULL. SIM_ENGINE_ERR_COMMAND: unknown mode; nothing
 * changes (the period is NOT simulated, the sensors are not sampled,
 * sim_engine_last() is kept). SIM_ENGINE_ERR_PLANT: the plant refused a
 * plant-side fault (the message is the plant's); the period is not
 * simulated. */
int sim_engine_step(sim_engine_t *e, const mc_command_t *cmd);

/* The trace sample of the latest step (valid until the next step). */
const sim_trace_sample_t *sim_engine_last(const sim_engine_t *e);

/* Time of the next sampling instant t_{k+1} (s) = steps done * Ts. */
double sim_engine_time_s(const sim_engine_t *e);

/* PWM period Ts in s. */
double sim_engine_period_s(const sim_engine_t *e);

/* Give the drive a CAN node with configuration cfg (mc/can_node.h) on its
 * mailbox's CAN queues, at any time after init: brings the drive's CAN up
 * (hal_can_init(1000000)) and initialises the node with the firmware
 * configuration in force and the engine's apply callback. From the next
 * step on the drive's command is the node's (it starts disabled) and the
 * node is polled after every fast ISR; sim_engine_step's cmd is ignored.
 * A parameter write the node accepts (drive IDLE or FAULT) is put in
 * force inside that poll, between two ISRs: the engine re-initialises the
 * drive (mc_app_init: the drive restarts in IDLE, faults cleared, offsets
 * to be calibrated again at the next enable) with the new configuration.
 * A configuration the engine cannot run is refused (MC_ERR_STATE: the
 * drive is not IDLE or FAULT; MC_ERR_PARAM: PWM frequency or encoder
 * resolution no longer the plant's, or a telemetry rate
 * (timing.telemetry_every_isr) other than the one in force: the engine's
 * traces read the record after every ISR; mc_app_init's error) and the drive
 * stays exactly as it was (the engine puts back its copy of the drive
 * taken before mc_app_init): the node answers the write with the error.
 * Returns SIM_ENGINE_OK, SIM_ENGINE_ERR_NULL, SIM_ENGINE_ERR_STATE (init
 * failed, or a node is attached already) or SIM_ENGINE_ERR_CAN (cfg
 * refused by mc_can_node_init: node_id over 63, timeout_s outside
 * (0, 60]); on an error nothing changes. */
int sim_engine_can_attach(sim_engine_t *e, const mc_can_node_config_t *cfg);

/* Queue a frame for the drive's CAN node (the mailbox's receive queue,
 * read by the node's next poll). false: no node attached, a frame outside
 * the format limits of hal/can.h (dlc over 8, identifier too large), or
 * the queue (HAL_SIM_CAN_QUEUE_LEN frames) full: then the frame is lost
 * and counted in the drive's hal_can_stats rx_overruns, as a controller's
 * FIFO overrun. */
bool sim_engine_can_deliver(sim_engine_t *e, const hal_can_frame_t *f);

/* Take the oldest frame the drive sent (the mailbox's transmit queue);
 * false when none is pending or no node is attached. The node's frames
 * that found the queue full were dropped by the node and counted in its
 * tx_drops (mc_can_counters_t). */
bool sim_engine_can_collect(sim_engine_t *e, hal_can_frame_t *f);

/* Add link events seen outside the engine (a bridge's lost receive frames
 * and bus error frames) to the counts the drive reads through
 * hal_can_stats() (its Tlm_Counters / Tlm_Errors). No effect without a
 * node. */
void sim_engine_can_count_link_events(sim_engine_t *e, uint32_t rx_overruns, uint32_t bus_errors);

/* The attached CAN node (its counters: mc_can_node_counters), NULL when
 * none is attached. */
const mc_can_node_t *sim_engine_can_node(const sim_engine_t *e);

#endif /* SIM_ENGINE_H */
