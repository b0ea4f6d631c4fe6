/* The register fake's storage (stm32_fake_regs.h). */
#include "stm32_fake_regs.h"

#include <string.h>

#define STM32_FAKE_DEFINE(type, name, dims) type stm32_fake_##name dims;
STM32_FAKE_LIST(STM32_FAKE_DEFINE)
#undef STM32_FAKE_DEFINE

void stm32_fake_reset(void)
{
#define STM32_FAKE_CLEAR(type, name, dims)                                                         \
    memset((void *)&stm32_fake_##name, 0, sizeof stm32_fake_##name);
    STM32_FAKE_LIST(STM32_FAKE_CLEAR)
#undef STM32_FAKE_CLEAR
}
