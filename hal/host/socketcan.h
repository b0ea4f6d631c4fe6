/*
 * SocketCAN bridge of the host simulator (Linux only): moves CAN frames
 * between a CAN interface (vcan0, can0, ...) and the CAN queues of a
 * simulated drive (sim_engine_can_deliver / sim_engine_can_collect), so
 * that a program on the host or on the bus (candump, python-can, the
 * telemetry tool) talks to the simulated drive's CAN node.
 *
 * The socket: PF_CAN / SOCK_RAW / CAN_RAW, non-blocking, bound to the
 * interface, with
 *   - a receive filter for the drive's identifiers: standard (11-bit)
 *     frames with id >> 5 == node_id (node_id * 32 + message number; data
 *     and remote frames: the node rejects the remote ones itself);
 *   - the error frames (CAN_RAW_ERR_FILTER = CAN_ERR_MASK): counted as bus
 *     errors, never delivered;
 *   - SO_RXQ_OVFL: the kernel's count of frames it dropped because the
 *     socket's receive buffer was full, read from each received frame's
 *     ancillary data (a cumulative count: the bridge keeps the increments).
 * The bridge's own frames are not received back (CAN_RAW_RECV_OWN_MSGS is
 * off), other sockets on the interface see them.
 *
 * Nothing blocks: hal_socketcan_pump() takes what the socket holds, at
 * most HAL_SOCKETCAN_RX_PER_PUMP frames a call, and sends what the drive
 * queued; a frame the socket cannot take (its send buffer or the
 * interface's queue full: EAGAIN, ENOBUFS) is dropped and counted.
 * Pumped once per PWM period, the receive side delivers up to 16 frames a
 * period (160000 a second at 10 kHz: more than a 1 Mbit/s bus carries, about
 * 9000), which is what the node takes per poll (MC_CAN_NODE_RX_PER_POLL),
 * so the drive's receive queue never overflows because of the bridge:
 * when the simulation falls behind wall time the frames wait in the
 * socket's buffer, and only the kernel's drops of a full buffer are lost
 * (counted). The lost frames and bus errors are also added to the drive's
 * hal_can_stats() (sim_engine_can_count_link_events), which its telemetry
 * reports. hal_socketcan_flush() drops what arrived before the run starts
 * (a drive does not see the frames sent before it was up).
 *
 * Errors: the functions return 0 or a negative errno value; the sentence
 * of hal_socketcan_message() names the interface, the failed call and the
 * reason, with a hint for the usual causes (no CAN in the kernel, no such
 * interface, not a CAN interface, interface down).
 *
 * Host only, not for the firmware: the engine does not depend on it (it
 * depends on the engine's CAN functions only). Single-threaded: call it
 * from the thread that steps the engine.
 */
#ifndef HAL_HOST_SOCKETCAN_H
#define HAL_HOST_SOCKETCAN_H

#include <stdbool.h>
#include <stdint.h>

#include "sim_engine.h"

#define HAL_SOCKETCAN_IFNAME_MAX  16u  /* IFNAMSIZ, terminator included */
#define HAL_SOCKETCAN_RX_PER_PUMP 16u  /* frames read per pump, at most */
#define HAL_SOCKETCAN_MESSAGE_MAX 320u /* hal_socketcan_message() */

/* Counts since hal_socketcan_open (64-bit: no wrap in practice). */
typedef struct {
    uint64_t rx;                /* frames delivered to the drive */
    uint64_t rx_refused;        /* frames the drive's receive queue had no
                                   room for (lost; the drive counts them in
                                   its rx_overruns) */
    uint64_t rx_flushed;        /* frames dropped by hal_socketcan_flush */
    uint64_t rx_overflow_drops; /* frames the kernel dropped before the
                                   bridge read them (SO_RXQ_OVFL) */
    uint64_t bus_errors;        /* error frames received */
    uint64_t tx;                /* drive frames written to the socket */
    uint64_t tx_dropped;        /* drive frames the socket refused (buffer
                                   or interface queue full; or an error) */
} hal_socketcan_counters_t;

typedef struct {
    int fd; /* -1: not open */
    uint32_t node_id;
    char ifname[HAL_SOCKETCAN_IFNAME_MAX];
    uint32_t rxq_ovfl_last; /* the kernel's cumulative drop count, as last
                               read */
    hal_socketcan_counters_t counters;
    int last_error; /* errno of the latest failure, 0: none */
    char message[HAL_SOCKETCAN_MESSAGE_MAX];
} hal_socketcan_t;

/* Open the bridge for the drive node_id (0..63) on the CAN interface
 * ifname. 0, or a negative errno value (then s is closed and
 * hal_socketcan_message says why): -EINVAL for a bad node_id or an empty
 * or too long ifname, -EAFNOSUPPORT when the kernel has no CAN, -ENODEV
 * when ifname does not exist or is not a CAN interface, -ENETDOWN when it
 * is down, or what socket, setsockopt or bind reported. */
int hal_socketcan_open(hal_socketcan_t *s, const char *ifname,
                       uint32_t node_id);

/* Move the frames the socket holds into the drive, the oldest first and
 * at most HAL_SOCKETCAN_RX_PER_PUMP (error frames counted, not delivered;
 * the rest wait for the next call), and every frame the drive sent out to
 * the socket. Never blocks. The number of frames moved (both ways), or a
 * negative errno value when the socket failed (a receive or send error
 * other than "would block" / "no buffer space"; hal_socketcan_message
 * says which); the bridge stays open. */
int hal_socketcan_pump(hal_socketcan_t *s, sim_engine_t *e);

/* Drop every frame the socket holds (counted in rx_flushed; the kernel's
 * drops so far are not counted) without delivering any: call it when the
 * run starts, so that frames sent while the simulator was preparing are
 * not taken as the drive's. The number dropped, or a negative errno. */
int hal_socketcan_flush(hal_socketcan_t *s);

/* The counts since open. */
const hal_socketcan_counters_t *
hal_socketcan_counters(const hal_socketcan_t *s);

/* The sentence about the latest failure ("ok" when none). */
const char *hal_socketcan_message(const hal_socketcan_t *s);

/* Close the socket. Idempotent; s must have been through
 * hal_socketcan_open (successful or not: a failed open leaves it closed). */
void hal_socketcan_close(hal_socketcan_t *s);

#endif /* HAL_HOST_SOCKETCAN_H */
