/* The independent watchdog (RM0090 21): LSI (17..47 kHz, 32 kHz typical)
 * / 32, reload 50: a reset 34..94 ms after the last refresh (50 ms
 * typical). Once started it cannot be stopped; the background loop
 * refreshes it. */
#ifndef STM32_IWDG_H
#define STM32_IWDG_H

#include <stdbool.h>

#include "regs.h"

#define STM32_IWDG_PRESCALER_32 3u /* PR = 011: LSI / 32 */
#define STM32_IWDG_RELOAD       50u

/* Start it; false if the prescaler/reload never latched (SR busy). */
bool stm32_iwdg_start(void);

static inline void stm32_iwdg_refresh(void)
{
    STM32_IWDG->KR = IWDG_KEY_RELOAD;
}

#endif /* STM32_IWDG_H */
