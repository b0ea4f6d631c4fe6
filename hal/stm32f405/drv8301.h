/*
 * The DRV8301 gate driver over SPI3 (its datasheet, SPI and registers):
 * 16-bit frames, SCLK idle low, data captured on the falling edge (CPOL 0,
 * CPHA 1), at most 10 MHz (here PCLK1 / 8 = 5.25 MHz), nSCS high between
 * frames. A frame is R/W (bit 15, 1 = read), the address (bits 14:11) and
 * 11 data bits; a read's answer comes in the next frame.
 *
 * Set-up: write control registers 1 and 2 (addresses 2, 3), read both back
 * and compare. The driver forgets them whenever EN_GATE goes low, so the
 * port keeps EN_GATE high once they are set (hal_stm32.c).
 */
#ifndef STM32_DRV8301_H
#define STM32_DRV8301_H

#include <stdbool.h>
#include <stdint.h>

#include "board.h"

#define DRV8301_ADDR_CTRL1 2u
#define DRV8301_ADDR_CTRL2 3u

/* A frame: read flag, address, 11 data bits. */
static inline uint16_t drv8301_frame(bool read, uint32_t addr, uint32_t data)
{
    return (uint16_t)((read ? 0x8000u : 0u) | ((addr & 0xFu) << 11u) |
                      (data & 0x7FFu));
}

typedef enum {
    STM32_DRV_OK = 0,
    STM32_DRV_SPI_TIMEOUT, /* the SPI never finished a frame */
    STM32_DRV_READBACK     /* a register read back differently */
} stm32_drv_status_t;

/* SPI3 and the chip-select pin up, the two control registers written and
 * verified. */
stm32_drv_status_t stm32_drv8301_setup(const stm32_board_t *b);

#endif /* STM32_DRV8301_H */
