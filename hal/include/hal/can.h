/*
 * HAL contract: classic CAN (11- or 29-bit identifiers, up to 8 data bytes).
 *
 * Non-blocking: send queues a frame or reports HAL_ERR_BUSY, receive returns
 * a queued frame or HAL_ERR_EMPTY. Neither may be called from the fast
 * (PWM) ISR; they may be called from the thread/background loop or from the
 * CAN interrupt itself.
 * Bindings: hal/sim_mailbox (the simulator's queues, host and QEMU image;
 * hal/host bridges them to SocketCAN), a board port (its CAN peripheral).
 */
#ifndef HAL_CAN_H
#define HAL_CAN_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_status.h"

#define HAL_CAN_MAX_DLC    8u
#define HAL_CAN_STD_ID_MAX 0x7FFu      /* largest 11-bit identifier */
#define HAL_CAN_EXT_ID_MAX 0x1FFFFFFFu /* largest 29-bit identifier */

typedef struct {
    uint32_t id;   /* 11-bit (<= 0x7FF) or 29-bit identifier */
    bool extended; /* true: 29-bit identifier */
    bool rtr;      /* remote transmission request */
    uint8_t dlc;   /* data length, 0..8 */
    uint8_t data[HAL_CAN_MAX_DLC];
} hal_can_frame_t;

/* True if the frame fits its format: dlc <= HAL_CAN_MAX_DLC and the id
 * within its 11 or 29 bits (what hal_can_send refuses with HAL_ERR_PARAM).
 * Interrupt context: yes. */
static inline bool hal_can_frame_valid(const hal_can_frame_t *f)
{
    const uint32_t id_max =
        f->extended ? HAL_CAN_EXT_ID_MAX : HAL_CAN_STD_ID_MAX;
    return f->dlc <= HAL_CAN_MAX_DLC && f->id <= id_max;
}

/* Bring the controller up at bitrate_bps (e.g. 500000). HAL_ERR_PARAM for an
 * unsupported bitrate. Interrupt context: no. */
hal_status_t hal_can_init(uint32_t bitrate_bps);

/* Queue one frame for transmission. HAL_ERR_PARAM: dlc > 8 or id too large
 * for its format; HAL_ERR_BUSY: transmit queue full. Never blocks.
 * Interrupt context: no. */
hal_status_t hal_can_send(const hal_can_frame_t *frame);

/* Take the oldest received frame. HAL_ERR_EMPTY: none pending. Never
 * blocks. Interrupt context: no. */
hal_status_t hal_can_receive(hal_can_frame_t *frame);

/* Counts kept by the binding since hal_can_init (wrapping at 2^32). */
typedef struct {
    uint32_t rx_overruns; /* frames lost before hal_can_receive (receive
                             queue or FIFO full, SocketCAN SO_RXQ_OVFL) */
    uint32_t bus_errors;  /* bus error events (SocketCAN error frames,
                             a controller's error interrupt) */
} hal_can_stats_t;

/* Copy the binding's counts. Interrupt context: no. */
void hal_can_stats(hal_can_stats_t *stats);

#endif /* HAL_CAN_H */
