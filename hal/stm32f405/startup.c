/*
 * Reset and the vector table of the STM32F405 (RM0090 table 61: 16 system
 * exceptions and 82 device interrupts; the table sits at the start of the
 * flash, aliased at 0, VTOR = 0x08000000 set explicitly).
 *
 * Reset_Handler (hal/cortex_m/reset_handler.h: FPU, .data copied from the
 * flash, .bss zeroed), then main(). Every fault and every unexpected interrupt
 * calls stm32_fatal (its default: all gates off and the console's report, then
 * a wait for the watchdog's reset; an image may define its own).
 */
#include <stdint.h>

#include "board.h"
#include "gpio_cfg.h"
#include "regs.h"
#include "reset_handler.h"
#include "startup.h"

extern uint32_t __StackTop;
extern int main(void);

void stm32_c_start(void);

CORTEX_M_RESET_HANDLER(stm32_c_start)

void stm32_c_start(void)
{
    STM32_SCB->VTOR = (uint32_t)(uintptr_t)stm32_vectors;
    stm32_barrier();
    (void)main();
    stm32_fatal("main returned");
}

/* All six gates off at once: MOE cleared (their idle level, low) and the
 * gate driver disabled. */
void stm32_gates_off(void)
{
    STM32_TIM1->BDTR &= ~TIM_BDTR_MOE;
    stm32_gpio_write(&stm32_board.enable_gate, false);
}

__attribute__((weak, noreturn)) void stm32_fatal(const char *what)
{
    stm32_gates_off();
    (void)what; /* the console is not safe to use from a fault */
    for (;;) {
        /* the watchdog, if started, resets the MCU */
    }
}

static void nmi(void)
{
    stm32_fatal("NMI");
}
static void hard_fault(void)
{
    stm32_fatal("HardFault");
}
static void mem_manage(void)
{
    stm32_fatal("MemManage (stack guard?)");
}
static void bus_fault(void)
{
    stm32_fatal("BusFault");
}
static void usage_fault(void)
{
    stm32_fatal("UsageFault");
}
static void unexpected(void)
{
    stm32_fatal("unexpected interrupt");
}

/* The device interrupts the images handle; the rest are unexpected. */
void ADC_IRQHandler(void) __attribute__((weak, alias("stm32_unexpected")));
void TIM2_IRQHandler(void) __attribute__((weak, alias("stm32_unexpected")));
void SysTick_Handler(void) __attribute__((weak, alias("stm32_unexpected")));
void stm32_unexpected(void);
void stm32_unexpected(void)
{
    unexpected();
}

/* Device interrupt n is entry 16 + n; the ranges between the handled
 * ones are the unexpected. */
_Static_assert(STM32_IRQ_ADC < STM32_IRQ_TIM2, "the order below");
__attribute__((section(".isr_vector"), used))
const stm32_vector_t stm32_vectors[16u + STM32_IRQ_COUNT] = {
    [0] = (stm32_vector_t)(uintptr_t)&__StackTop,
    [1] = Reset_Handler,
    [2] = nmi,
    [3] = hard_fault,
    [4] = mem_manage,
    [5] = bus_fault,
    [6] = usage_fault,
    [11] = unexpected, /* SVCall */
    [12] = unexpected, /* DebugMonitor */
    [14] = unexpected, /* PendSV */
    [15] = SysTick_Handler,
    [16 ... 16 + STM32_IRQ_ADC - 1] = unexpected,
    [16 + STM32_IRQ_ADC] = ADC_IRQHandler,
    [16 + STM32_IRQ_ADC + 1 ... 16 + STM32_IRQ_TIM2 - 1] = unexpected,
    [16 + STM32_IRQ_TIM2] = TIM2_IRQHandler,
    [16 + STM32_IRQ_TIM2 + 1 ... 16 + STM32_IRQ_COUNT - 1] = unexpected,
};
