/*
 * The drive's CAN node: the protocol of tools/dbc/pmsm_drive.dbc (the
 * single source of truth; its pack/unpack code is generated from it at
 * build time, firmware/can_codec) on the HAL's CAN queues (hal/can.h).
 *
 * Identifiers: 11-bit, node_id * 32 + message number (node_id 0..63).
 * Which frames are the node's:
 *   - an identifier above 0x7FF (a 29-bit one outside the 11-bit range),
 *     or whose id >> 5 is another node's: not for us, ignored (not
 *     counted);
 *   - our node id with the number of a message the drive itself sends
 *     (telemetry 16..24, Rsp_Param 25, Rsp_Error 26), whatever its flags:
 *     ignored (not counted), so that a bus echo or a second drive
 *     configured with the same node id cannot start an endless exchange of
 *     error replies;
 *   - any other frame with our node id is taken (counted in rx_frames):
 *     an extended or remote (RTR) one is rejected as
 *     MC_CAN_REJ_UNKNOWN_MESSAGE, as is a message number that is no
 *     command (0, 11..15, 27..31).
 * A command frame (messages 1..10) must have exactly its DLC
 * (MC_CAN_REJ_WRONG_DLC otherwise; a DLC over 8 from a faulty binding is
 * reported as 8) and in-range values (the generated _is_in_range
 * checks; for float32 signals also finite): MC_CAN_REJ_BAD_VALUE. Commands
 * never saturate a value: out of range is rejected.
 *
 * Replies, exactly one per rejected frame and none for an accepted command
 * other than a parameter command:
 *   - Cmd_ParamRead, Cmd_ParamWrite and Cmd_Controller frames that pass
 *     the frame checks above are answered with Rsp_Param, Status 0 (ok,
 *     with the value now in force), 1 (unknown id:
 *     MC_CAN_REJ_UNKNOWN_PARAM), 2 (refused: MC_CAN_REJ_REFUSED_STATE),
 *     3 (the validation or the apply callback rejected the value:
 *     MC_CAN_REJ_BAD_VALUE) or 4 (wrong type: MC_CAN_REJ_WRONG_PARAM_TYPE);
 *     a rejected one carries the value in force (0 for an unknown id);
 *   - every other rejected frame is answered with Rsp_Error {message
 *     number, cause, DLC}.
 * A rejected frame is counted by cause and changes nothing (the command,
 * the telemetry rates and the configuration in force stay; it does not
 * feed the command timeout). An accepted frame (rx_accepted) feeds the
 * timeout, clears comm_lost and hands the node's command to the drive
 * (mc_app_set_command), whatever its message.
 *
 * Commands: Cmd_Enable (level), Cmd_Mode, Cmd_Current / Cmd_Speed /
 * Cmd_Position set the references of their mode only (the mode is
 * Cmd_Mode's). Cmd_ClearFaults raises mc_command_t.clear_fault and lowers
 * it once at least one fast ISR has run with it (the telemetry's isr_count
 * moved since a snapshot taken after the raise: with one poll per ISR, the
 * ISR sees it for exactly one ISR; the ISR acts on its rising edge).
 * Cmd_TelemetryRate sets decimation[msg - 16].
 *
 * Parameters (mc/can_params.h): read at any time; a write (Cmd_ParamWrite,
 * Cmd_Controller = a write of "controller") only while the drive is
 * stopped: the telemetry's state IDLE or FAULT AND the node's command does
 * not enable the drive (the apply callback re-initialises the drive, which
 * would otherwise restart a drive whose enable is still set, bypassing the
 * re-arm rule of mc/app.h), and an apply callback was given; otherwise
 * refused (Status 2). The value goes into a copy of drive_cfg, the copy
 * through mc_config_validate(), then to the apply callback; only when it
 * returns MC_OK is the copy the configuration in force. An apply callback
 * returning MC_ERR_STATE is a refusal (Status 2), any other error a
 * rejected value (Status 3); it must leave the drive on its previous
 * configuration then. After every apply call the node hands its command
 * to the drive again (a re-initialised drive starts with a zero command).
 *
 * Outside the ISR: mc_can_node_poll() runs in the background loop (the
 * host bench calls it after each fast ISR). It touches the drive only
 * through mc_app_set_command() / mc_app_get_telemetry() (mc/app.h) and,
 * for a parameter write while the drive is stopped, through the
 * integrator's apply callback (a new validated configuration: the host
 * bench re-initialises the drive between two ISRs; an MCU masks the PWM
 * interrupt around mc_app_init()). Bounded time: at most
 * MC_CAN_NODE_RX_PER_POLL received frames (each a parameter lookup over
 * the table at most, and one validation for a write) and one frame per
 * telemetry message per call. Stack: a parameter write uses a copy of
 * mc_config_t plus mc_config_validate()'s (about 2 kB together).
 *
 * Command timeout: while the command enables the drive, a valid command
 * frame must arrive at least every timeout_s (moteus: 0.1 s); otherwise
 * (hal_time_ticks() - the last valid frame > timeout_s * hal_time_tick_hz(),
 * in integer ticks, computed at init) the node sets
 * mc_command_t.comm_lost, which the ISR latches as MC_FAULT_COMM_TIMEOUT
 * (PWM off: the drive coasts). The next valid command clears comm_lost;
 * the fault then clears as any other (Cmd_ClearFaults, and a restart only
 * after Enable 0). timeouts counts the rising edges of comm_lost.
 *
 * Telemetry (messages 16..24): each at most every decimation[k] fast ISRs
 * (0 = off; due when never sent or when the telemetry's isr_count moved
 * by decimation[k] since its last frame), from the latest telemetry
 * snapshot (none this poll when mc_app_get_telemetry() reports
 * MC_ERR_STATE), with the E2E protection of mc/can_e2e.h (CRC-8 and a
 * 0..14 counter per message, advanced for every frame built, so a frame
 * the HAL refused shows as a gap). Telemetry saturates, commands never
 * do: a value outside its signal's DBC range is sent as the range's end,
 * and a non-finite value (NaN, +-Inf) as the signal's MAXIMUM (one rule
 * for every signal: the maximum reads "saturated or not finite").
 * Tlm_Status: Enabled is the node's command, Controller the configuration
 * in force, Faults_latched / First_fault the low 16 bits (every fault bit
 * of mc/faults.h). Tlm_Estimates: theta_e wrapped to [0, 2 pi).
 * Tlm_IsrCost: in microseconds; Cost_avg is the mean of isr_cost_s over
 * the distinct snapshots the node saw since the previous Tlm_IsrCost
 * frame. Tlm_Errors: rejected[] by cause 1..4 (the causes 5 and 6 have no
 * field there; they are in the counters), hal_can_stats() rx_overruns and
 * tx_drops, each modulo 256. Tlm_Counters: the telemetry's isr_overruns
 * and hal_can_stats() bus_errors (saturated at 2^24 - 1).
 * Every frame the node sends (telemetry and replies) the HAL either
 * queues (tx_frames) or refuses (tx_drops: queue full, HAL_ERR_BUSY, or
 * any other error); the node never waits and never retries.
 *
 * Units: SI (s, A, V, rad, rad/s, N m).
 */
#ifndef MC_CAN_NODE_H
#define MC_CAN_NODE_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/can.h"
#include "mc/app.h"
#include "mc/config.h"
#include "mc/status.h"

#define MC_CAN_NODE_ID_MAX      63u
#define MC_CAN_NODE_RX_PER_POLL 16u /* frames taken per mc_can_node_poll */
#define MC_CAN_TLM_FIRST        16u /* first telemetry message number */
#define MC_CAN_TLM_COUNT        9u  /* telemetry messages 16..24 */

/* Rejection causes (Rsp_Error.Cause, the DBC's value table). */
typedef enum {
    MC_CAN_REJ_NONE = 0,            /* accepted (not a cause) */
    MC_CAN_REJ_UNKNOWN_MESSAGE = 1, /* also extended / remote frames */
    MC_CAN_REJ_WRONG_DLC = 2,
    MC_CAN_REJ_BAD_VALUE = 3,     /* non-finite or outside the DBC range */
    MC_CAN_REJ_REFUSED_STATE = 4, /* not allowed in the drive's state */
    MC_CAN_REJ_UNKNOWN_PARAM = 5,
    MC_CAN_REJ_WRONG_PARAM_TYPE = 6,
    MC_CAN_REJ_COUNT = 7 /* causes are 1 .. MC_CAN_REJ_COUNT - 1 */
} mc_can_reject_t;

typedef struct {
    uint32_t node_id; /* 0 .. MC_CAN_NODE_ID_MAX */
    float timeout_s;  /* command timeout while enabled, (0, 60] (0.1) */
    uint16_t decimation[MC_CAN_TLM_COUNT]; /* per telemetry message, in
                                              fast ISRs, 0 = off */
} mc_can_node_config_t;

typedef struct {
    uint32_t rx_frames;   /* frames of this node taken from the HAL */
    uint32_t rx_accepted; /* valid commands (they feed the timeout) */
    uint32_t rejected[MC_CAN_REJ_COUNT]; /* by cause, [0] unused */
    uint32_t tx_frames;                  /* frames the HAL accepted */
    uint32_t tx_drops; /* frames the HAL refused (queue full) */
    uint32_t timeouts; /* command timeouts (rising edges of comm_lost) */
} mc_can_counters_t;

/* The integrator's way to put a new configuration in force while the
 * drive is stopped (IDLE or FAULT); the node has validated it
 * (mc_config_validate). Returns MC_OK when it is in force. Not called from
 * an ISR. */
typedef mc_status_t (*mc_can_apply_config_fn)(void *ctx,
                                              const mc_config_t *cfg);

typedef struct {
    mc_can_node_config_t cfg;
    mc_config_t drive_cfg; /* the configuration in force */
    mc_can_apply_config_fn apply;
    void *apply_ctx;
    mc_command_t cmd;          /* the command built from the frames */
    uint64_t last_valid_ticks; /* hal_time_ticks() of the last valid
                                  command */
    bool have_valid;           /* a valid command since init */
    uint32_t tlm_last_isr[MC_CAN_TLM_COUNT]; /* isr_count of the last
                                                frame of each message */
    bool tlm_sent[MC_CAN_TLM_COUNT];
    uint8_t tlm_counter[MC_CAN_TLM_COUNT]; /* E2E counters */
    float cost_sum_s;                      /* ISR cost mean: sum and */
    uint32_t cost_n;                       /* number of snapshots */
    uint32_t last_isr_count;               /* of the last snapshot */
    bool have_snapshot;                    /* last_isr_count is set */
    uint64_t timeout_ticks; /* timeout_s in hal_time_ticks() units */
    bool clear_pending;     /* clear_fault raised, not yet seen by an ISR */
    bool clear_armed;       /* clear_isr_count holds a snapshot taken after
                               the raise */
    uint32_t clear_isr_count;
    mc_can_counters_t counters;
} mc_can_node_t;

/* Default node configuration: node 0, timeout 0.1 s, Tlm_Status every
 * 1000 ISRs, the other messages off. Interrupt context: no. */
void mc_can_node_config_default(mc_can_node_config_t *cfg);

/* Validate cfg (node_id <= MC_CAN_NODE_ID_MAX, timeout_s finite in
 * (0, 60]), keep a copy of the drive's configuration in force (drive_cfg,
 * the one the drive was initialised with: not validated again) and the
 * apply callback (NULL: parameter and controller writes are refused with
 * MC_CAN_REJ_REFUSED_STATE). The command starts disabled, in
 * MC_MODE_CURRENT, all references 0; every counter 0, no telemetry sent
 * yet. Reads hal_time_tick_hz() (the timeout in ticks). MC_ERR_PARAM for a
 * bad cfg, a NULL pointer or a tick rate of 0 (*n untouched).
 * Interrupt context: no. */
mc_status_t mc_can_node_init(mc_can_node_t *n, const mc_can_node_config_t *cfg,
                             const mc_config_t *drive_cfg,
                             mc_can_apply_config_fn apply, void *apply_ctx);

/* Background step: take up to MC_CAN_NODE_RX_PER_POLL frames from
 * hal_can_receive() and handle them (commands -> mc_app_set_command,
 * parameter reads/writes, replies through hal_can_send), check the
 * command timeout against hal_time_ticks(), then send the telemetry that
 * is due. Interrupt context: no. */
void mc_can_node_poll(mc_can_node_t *n, mc_app_t *app);

/* The counters (monotonic, wrapping at 2^32). Interrupt context: no. */
const mc_can_counters_t *mc_can_node_counters(const mc_can_node_t *n);

#endif /* MC_CAN_NODE_H */
