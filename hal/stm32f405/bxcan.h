/*
 * CAN1 (bxCAN, RM0090 32): classic frames, one filter bank accepting
 * everything into FIFO 0, the three transmit mailboxes, automatic bus-off
 * recovery, transmit in request order (TXFP). Polled from the background
 * loop (hal/can.h).
 */
#ifndef STM32_BXCAN_H
#define STM32_BXCAN_H

#include <stdbool.h>
#include <stdint.h>

#include "board.h"
#include "hal/can.h"

/* Bit timing: prescaler and segments (in time quanta) for a bit rate. */
typedef struct {
    uint32_t brp;   /* 1..1024 */
    uint32_t tseg1; /* 1..16 */
    uint32_t tseg2; /* 1..8 */
    uint32_t sjw;   /* 1..4 */
} stm32_can_timing_t;

/* The timing for bitrate_bps from pclk1_hz: 8..25 quanta per bit, the
 * sample point nearest 87.5 % (CiA 301's recommendation), an exact bit
 * rate; false if none is exact. */
bool stm32_can_timing_for(uint32_t pclk1_hz, uint32_t bitrate_bps,
                          stm32_can_timing_t *t);

/* Initialisation mode, the timing, the filter, normal mode. HAL_ERR_PARAM
 * for a bit rate without an exact timing, HAL_ERR_HW if the controller
 * does not acknowledge a mode change (a timeout). */
hal_status_t stm32_can_init(const stm32_board_t *b, uint32_t pclk1_hz,
                            uint32_t bitrate_bps);

hal_status_t stm32_can_send(const hal_can_frame_t *f);
hal_status_t stm32_can_receive(hal_can_frame_t *f);
void stm32_can_stats(hal_can_stats_t *s);

#endif /* STM32_BXCAN_H */
