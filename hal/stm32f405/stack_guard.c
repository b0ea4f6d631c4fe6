/* The stack guard (stack_guard.h), ARMv7-M ARM B3.5. */
#include "stack_guard.h"

#include "regs.h"

void stm32_stack_guard_init(uint32_t guard_addr)
{
    stm32_mpu_t *mpu = STM32_MPU;
    mpu->RNR = 0u;
    mpu->RBAR = guard_addr & ~(STM32_STACK_GUARD_BYTES - 1u);
    /* SIZE = 4: 2^(4 + 1) = 32 bytes; AP = 000; XN */
    mpu->RASR = MPU_RASR_XN | (0u << MPU_RASR_AP_POS) |
                (4u << MPU_RASR_SIZE_POS) | MPU_RASR_ENABLE;
    STM32_SCB->SHCSR |= SCB_SHCSR_MEMFAULTENA;
    mpu->CTRL = MPU_CTRL_PRIVDEFENA | MPU_CTRL_ENABLE;
    stm32_barrier();
}
