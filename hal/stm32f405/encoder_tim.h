/* The incremental encoder on TIM3 in encoder mode 3 (RM0090 18.3.12):
 * both edges of both channels counted, ARR = counts per revolution - 1,
 * so CNT is the count within the revolution. No index (the board's Z is
 * not used: hal_encoder_index reports none). */
#ifndef STM32_ENCODER_TIM_H
#define STM32_ENCODER_TIM_H

#include <stdbool.h>
#include <stdint.h>

#include "board.h"

/* False for a count per revolution outside [4, 65536]. */
bool stm32_encoder_init(const stm32_board_t *b);

#endif /* STM32_ENCODER_TIM_H */
