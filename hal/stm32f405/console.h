/* The console: USART2 transmit only, polled (RM0090 30.6). For the boot
 * report and diagnostics from the background loop, never from the fast
 * ISR. */
#ifndef STM32_CONSOLE_H
#define STM32_CONSOLE_H

#include <stdint.h>

#include "board.h"
#include "clock.h"

/* 8N1 at baud from the APB1 clock pclk1_hz, TX pin per the board; a
 * board baud of 0 leaves the console off. */
void stm32_console_init(const stm32_board_t *b, uint32_t pclk1_hz);
void stm32_console_puts(const char *s);
/* Decimal, with a sign. */
void stm32_console_put_i32(int32_t v);

/* The first steps of every image: the clock tree (clock.h, its result in
 * *clk), the console at the resulting APB1 clock, and the banner line
 * "<what> <board name>". */
void stm32_boot(const char *what, stm32_clocks_t *clk);

#endif /* STM32_CONSOLE_H */
