/*
 * The QEMU smoke image (qemu-system-arm -M netduinoplus2, an STM32F405 as
 * QEMU 7.2 models it: Cortex-M4F, flash, SRAM, USARTs, TIM2-5, ADCs, SPI,
 * EXTI, SYSCFG; RCC, TIM1, bxCAN, GPIO, IWDG unimplemented). What it runs
 * is the port's own code: the reset handler, the clock tree, the console,
 * the vector table, the stack guard; the checks go out as "CHECK <key>
 * <value>" lines over the console (USART2, QEMU's second serial port),
 * checked by tests/qemu/run_qemu_test.py:
 *   clock_status    the clock code's result: 1 = HSE timeout (QEMU's RCC
 *                   reads 0), the path a dead crystal takes
 *   vectors_at_flash  VTOR and the table at 0x08000000, its first words
 *                   the stack top and the reset handler
 *   sp_in_stack     the running stack between the guard and the top
 *   data_copied     .data copied from its flash image, .bss zeroed
 *   systick_period_tim2_counts  TIM2 counts per SysTick interrupt: SysTick
 *                   set for 1 kHz, TIM2 counting freely at 1 MHz, both
 *                   in QEMU's virtual time (-icount): 1000 expected
 *   drv8301_status  the gate driver's set-up over SPI3 (QEMU models the
 *                   SPI, with no chip on it): five frames exchanged
 *                   without a timeout, every answer 0, so the read-back
 *                   check fails: 2 (STM32_DRV_READBACK) expected
 * Then it reads the stack guard: the MPU must turn that into a MemManage
 * fault, whose handler exits QEMU with status SMOKE_EXIT_GUARD (any other
 * fault: SMOKE_EXIT_FAULT).
 */
#include <stdint.h>
#include <string.h>

#include "board.h"
#include "clock.h"
#include "console.h"
#include "drv8301.h"
#include "regs.h"
#include "semihost.h"
#include "stack_guard.h"
#include "startup.h"

#define SMOKE_EXIT_GUARD 7
#define SMOKE_EXIT_FAULT 1

/* QEMU 7.2's clocks (README.md): SysTick on the CPU clock, TIM2-5 at
 * 1 GHz (the SoC's clock-frequency property). A board's come from
 * clock.h. */
#define QEMU_CPU_CLK_HZ 168000000u
#define QEMU_TIM_CLK_HZ 1000000000u
#define SYSTICK_RATE_HZ 1000u
#define TIM2_COUNT_HZ   1000000u
#define SYSTICK_PERIODS 20u

extern uint32_t __StackTop;
extern uint32_t __StackLimit;
extern uint32_t __stack_guard__;

static volatile uint32_t data_word = 0x5A5AA5A5u;
static volatile uint32_t bss_word;
static volatile uint32_t systick_irqs;
static volatile uint32_t tim2_first, tim2_last;

void SysTick_Handler(void)
{
    const uint32_t now = STM32_TIM2->CNT;
    const uint32_t n = systick_irqs + 1u;
    if (n == 1u) {
        tim2_first = now;
    } else if (n == 1u + SYSTICK_PERIODS) {
        tim2_last = now;
    }
    systick_irqs = n;
}

void stm32_fatal(const char *what)
{
    stm32_gates_off();
    stm32_console_puts("FATAL ");
    stm32_console_puts(what);
    stm32_console_puts("\r\n");
    semihost_exit(strncmp(what, "MemManage", 9) == 0 ? SMOKE_EXIT_GUARD
                                                     : SMOKE_EXIT_FAULT);
}

static void check(const char *key, int32_t value)
{
    stm32_console_puts("CHECK ");
    stm32_console_puts(key);
    stm32_console_puts(" ");
    stm32_console_put_i32(value);
    stm32_console_puts("\r\n");
}

static uint32_t stack_pointer(void)
{
    uint32_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* TIM2 counting freely at TIM2_COUNT_HZ, the SysTick interrupt at
 * SYSTICK_RATE_HZ: TIM2's counts over SYSTICK_PERIODS interrupts, per
 * period; -1 if too few interrupts came. */
static int32_t measure_systick_period(void)
{
    STM32_RCC->APB1ENR |= RCC_APB1ENR_TIM2EN;
    stm32_tim_t *t = STM32_TIM2;
    t->PSC = QEMU_TIM_CLK_HZ / TIM2_COUNT_HZ - 1u;
    t->ARR = 0xFFFFu;
    t->CNT = 0u;
    t->CR1 = TIM_CR1_CEN;
    STM32_SYSTICK->LOAD = QEMU_CPU_CLK_HZ / SYSTICK_RATE_HZ - 1u;
    STM32_SYSTICK->VAL = 0u;
    STM32_SYSTICK->CTRL =
        SYSTICK_CTRL_CLKSOURCE | SYSTICK_CTRL_TICKINT | SYSTICK_CTRL_ENABLE;
    /* 21 interrupts take 21 ms of virtual time; bounded by a loop count */
    for (uint32_t k = 0u; k < 50000000u && systick_irqs <= SYSTICK_PERIODS;
         ++k) {
        __asm__ volatile("" ::: "memory");
    }
    STM32_SYSTICK->CTRL = 0u;
    t->CR1 = 0u;
    if (systick_irqs <= SYSTICK_PERIODS) {
        return -1;
    }
    return (int32_t)(((tim2_last - tim2_first) & 0xFFFFu) / SYSTICK_PERIODS);
}

int main(void)
{
    stm32_clocks_t clk;
    stm32_boot("STM32F405 port smoke image, board", &clk);
    check("clock_status", (int32_t)clk.status);
    check("sysclk_hz", (int32_t)clk.sysclk_hz);

    const uint32_t *vt = (const uint32_t *)(uintptr_t)STM32_SCB->VTOR;
    check("vectors_at_flash",
          STM32_SCB->VTOR == 0x08000000u &&
              (uintptr_t)stm32_vectors == 0x08000000u &&
              vt[0] == (uint32_t)(uintptr_t)&__StackTop &&
              vt[1] == (uint32_t)(uintptr_t)stm32_vectors[1]);
    const uint32_t sp = stack_pointer();
    check("sp_in_stack", sp > (uint32_t)(uintptr_t)&__StackLimit &&
                             sp <= (uint32_t)(uintptr_t)&__StackTop);
    check("data_copied", data_word == 0x5A5AA5A5u && bss_word == 0u);
    check("systick_period_tim2_counts", measure_systick_period());
    check("drv8301_status", (int32_t)stm32_drv8301_setup(&stm32_board));

    stm32_stack_guard_init((uint32_t)(uintptr_t)&__stack_guard__);
    stm32_console_puts("reading the stack guard\r\n");
    (void)*(volatile uint32_t *)(uintptr_t)&__stack_guard__;
    stm32_console_puts("the guard did not fault\r\n");
    return 0;
}
