/* The independent watchdog (iwdg.h). */
#include "iwdg.h"

#define IWDG_WAIT_LOOPS 100000u /* the registers latch in ~5 LSI periods */

bool stm32_iwdg_start(void)
{
    stm32_iwdg_t *w = STM32_IWDG;
    w->KR = IWDG_KEY_START; /* starts the LSI and the counter */
    w->KR = IWDG_KEY_ACCESS;
    w->PR = STM32_IWDG_PRESCALER_32;
    w->RLR = STM32_IWDG_RELOAD;
    const bool latched =
        stm32_wait_bits(&w->SR, IWDG_SR_PVU | IWDG_SR_RVU, 0u, IWDG_WAIT_LOOPS);
    w->KR = IWDG_KEY_RELOAD;
    return latched;
}
