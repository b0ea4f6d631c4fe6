/* CAN on the bound simulator mailbox (hal_sim_mailbox.h): the contract of
 * hal/can.h over two bounded queues. Classic CAN only: 1 Mbit/s, 500,
 * 250 or 125 kbit/s are accepted (the rate has no effect here). */
#include "hal_sim_mailbox.h"

#include <stddef.h>

static bool queue_push(hal_sim_can_queue_t *q, const hal_can_frame_t *f)
{
    if (q->count >= HAL_SIM_CAN_QUEUE_LEN) {
        return false;
    }
    q->frames[(q->head + q->count) % HAL_SIM_CAN_QUEUE_LEN] = *f;
    q->count++;
    return true;
}

static bool queue_pop(hal_sim_can_queue_t *q, hal_can_frame_t *f)
{
    if (q->count == 0u) {
        return false;
    }
    *f = q->frames[q->head];
    q->head = (q->head + 1u) % HAL_SIM_CAN_QUEUE_LEN;
    q->count--;
    return true;
}

bool hal_sim_can_deliver(hal_sim_mailbox_t *mailbox,
                         const hal_can_frame_t *frame)
{
    if (!queue_push(&mailbox->can_rx, frame)) {
        mailbox->can_stats.rx_overruns++;
        return false;
    }
    return true;
}

bool hal_sim_can_collect(hal_sim_mailbox_t *mailbox, hal_can_frame_t *frame)
{
    return queue_pop(&mailbox->can_tx, frame);
}

hal_status_t hal_can_init(uint32_t bitrate_bps)
{
    hal_sim_mailbox_t *m = hal_sim_bound();
    if (bitrate_bps != 1000000u && bitrate_bps != 500000u &&
        bitrate_bps != 250000u && bitrate_bps != 125000u) {
        return HAL_ERR_PARAM;
    }
    m->can_bitrate_bps = bitrate_bps;
    m->can_up = true;
    return HAL_OK;
}

hal_status_t hal_can_send(const hal_can_frame_t *frame)
{
    hal_sim_mailbox_t *m = hal_sim_bound();
    if (!hal_can_frame_valid(frame)) {
        return HAL_ERR_PARAM;
    }
    if (!m->can_up) {
        return HAL_ERR_HW; /* hal_can_init not called */
    }
    return queue_push(&m->can_tx, frame) ? HAL_OK : HAL_ERR_BUSY;
}

hal_status_t hal_can_receive(hal_can_frame_t *frame)
{
    return queue_pop(&hal_sim_bound()->can_rx, frame) ? HAL_OK : HAL_ERR_EMPTY;
}

void hal_can_stats(hal_can_stats_t *stats)
{
    *stats = hal_sim_bound()->can_stats;
}
