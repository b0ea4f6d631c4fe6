/* The stack guard: MPU region 0 over the lowest 32 bytes of the stack
 * (the linker script's __stack_guard__, 32-byte aligned), no access, no
 * execution; the default map for everything else (PRIVDEFENA). A stack
 * that grows into it takes a MemManage fault (enabled here) instead of
 * overwriting .bss. */
#ifndef STM32_STACK_GUARD_H
#define STM32_STACK_GUARD_H

#include <stdint.h>

#define STM32_STACK_GUARD_BYTES 32u

void stm32_stack_guard_init(uint32_t guard_addr);

#endif /* STM32_STACK_GUARD_H */
