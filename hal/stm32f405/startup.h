/* Reset, the vector table and the fatal-fault path (startup.c). */
#ifndef STM32_STARTUP_H
#define STM32_STARTUP_H

#include <stdint.h>

typedef void (*stm32_vector_t)(void);

extern const stm32_vector_t stm32_vectors[];

/* All gates off (TIM1 MOE cleared, EN_GATE low). Any context. */
void stm32_gates_off(void);

/* A fault or an impossible state: gates off, then never returns. Weak:
 * an image may define its own (the QEMU smoke image exits QEMU). */
__attribute__((noreturn)) void stm32_fatal(const char *what);

/* The interrupt handlers the images may define (weak defaults: fatal). */
void ADC_IRQHandler(void);
void TIM2_IRQHandler(void);
void SysTick_Handler(void);

#endif /* STM32_STARTUP_H */
