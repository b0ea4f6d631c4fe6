/*
 * The drive's CAN node: the protocol of tools/dbc/pmsm_drive.dbc (the
 * single source of truth; its pack/unpack code is generated from it at
 * build time, firmware/can_codec) on the HAL's CAN queues (hal/can.h).
 *
 * Identifiers: 11-bit, node_id * 32 + message number (node_id 0..63).
 * Frames of other nodes are ignored (not counted); extended or remote
 * frames, an unknown message number, a wrong DLC, a non-finite or
 * out-of-range value, a command refused in the drive's state, an unknown
 * parameter id or a wrong parameter type are rejected: counted by cause,
 * answered with Rsp_Error (or Rsp_Param with its status), and they change
 * nothing (they do not feed the command timeout either).
 *
 * Outside the ISR: mc_can_node_poll() runs in the background loop (the
 * host bench calls it after each fast ISR). It touches the drive only
 * through mc_app_set_command() / mc_app_get_telemetry() (mc/app.h) and,
 * for a parameter write while the drive is stopped, through the
 * integrator's apply callback (a new validated configuration: the host
 * bench re-initialises the drive between two ISRs; an MCU masks the PWM
 * interrupt around mc_app_init()). Bounded time: at most
 * MC_CAN_NODE_RX_PER_POLL received frames and one frame per telemetry
 * message per call.
 *
 * Command timeout: while the command enables the drive, a valid command
 * frame must arrive at least every timeout_s (moteus: 0.1 s); otherwise
 * the node sets mc_command_t.comm_lost, which the ISR latches as
 * MC_FAULT_COMM_TIMEOUT (PWM off: the drive coasts). The next valid
 * command clears comm_lost; the fault then clears as any other
 * (Cmd_ClearFaults, and a restart only after Enable 0).
 *
 * Telemetry (messages 16..24): each at most every decimation[k] fast ISRs
 * (0 = off), from the latest telemetry snapshot, with the E2E protection
 * of mc/can_e2e.h (CRC-8 and a 0..14 counter per message).
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
    mc_can_counters_t counters;
} mc_can_node_t;

/* Default node configuration: node 0, timeout 0.1 s, Tlm_Status every
 * 1000 ISRs, the other messages off. Interrupt context: no. */
void mc_can_node_config_default(mc_can_node_config_t *cfg);

/* Validate cfg, keep a copy of the drive's configuration in force
 * (drive_cfg) and the apply callback (NULL: parameter and controller
 * writes are refused with MC_CAN_REJ_REFUSED_STATE). The command starts
 * disabled, in drive_cfg's default mode, all references 0. MC_ERR_PARAM
 * for a bad cfg (*n untouched). Interrupt context: no. */
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
