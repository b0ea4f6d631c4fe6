/* The register fake of the STM32F405 port's host tests: the port's driver
 * sources compiled with STM32_REGS_FAKE write into these RAM structs
 * (hal/stm32f405/regs.h) instead of the peripherals. */
#ifndef STM32_FAKE_REGS_H
#define STM32_FAKE_REGS_H

#include "regs.h"

/* Every fake register to zero (the reset state the tests start from). */
void stm32_fake_reset(void);

#endif /* STM32_FAKE_REGS_H */
