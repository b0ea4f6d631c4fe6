/*
 * Reset and exception vectors of the QEMU mps2-an386 image.
 *
 * Reset_Handler (naked, no compiler-generated code before the FPU is on):
 * enables CP10/CP11 full access in CPACR, copies .data if its load address
 * differs from its run address (not with the linker script here: LMA =
 * VMA), zeroes .bss, then calls main() and exits through semihosting with
 * main's return value. Every fault prints its name and exits with status
 * QEMU_M4_EXIT_FAULT.
 */
#include <stdint.h>

#include "qemu_m4.h"
#include "semihost.h"

extern uint32_t __StackTop;
extern int main(void);

void Reset_Handler(void);
void qemu_m4_c_start(void);
void NMI_Handler(void);
void HardFault_Handler(void);
void MemManage_Handler(void);
void BusFault_Handler(void);
void UsageFault_Handler(void);
void Default_Handler(void);

__attribute__((naked, noreturn)) void Reset_Handler(void)
{
    __asm__ volatile(
        /* CPACR (0xE000ED88): CP10 and CP11 full access, bits 20-23. */
        "ldr r0, =0xE000ED88\n"
        "ldr r1, [r0]\n"
        "orr r1, r1, #(0xF << 20)\n"
        "str r1, [r0]\n"
        "dsb\n"
        "isb\n"
        /* .data: copy only when LMA != VMA. */
        "ldr r0, =__data_load__\n"
        "ldr r1, =__data_start__\n"
        "ldr r2, =__data_end__\n"
        "cmp r0, r1\n"
        "beq 2f\n"
        "1: cmp r1, r2\n"
        "bhs 2f\n"
        "ldr r3, [r0], #4\n"
        "str r3, [r1], #4\n"
        "b 1b\n"
        /* .bss: zero. */
        "2: ldr r1, =__bss_start__\n"
        "ldr r2, =__bss_end__\n"
        "movs r3, #0\n"
        "3: cmp r1, r2\n"
        "bhs 4f\n"
        "str r3, [r1], #4\n"
        "b 3b\n"
        "4: bl qemu_m4_c_start\n"
        "b .\n");
}

void qemu_m4_c_start(void)
{
    qemu_m4_counter_init();
    semihost_exit(main());
}

static __attribute__((noreturn)) void fault(const char *name)
{
    semihost_puts("FATAL: ");
    semihost_puts(name);
    semihost_puts("\n");
    semihost_exit(QEMU_M4_EXIT_FAULT);
}

void NMI_Handler(void)
{
    fault("NMI");
}
void HardFault_Handler(void)
{
    fault("HardFault");
}
void MemManage_Handler(void)
{
    fault("MemManage");
}
void BusFault_Handler(void)
{
    fault("BusFault");
}
void UsageFault_Handler(void)
{
    fault("UsageFault");
}
void Default_Handler(void)
{
    fault("unexpected interrupt");
}

typedef void (*vector_t)(void);

/* 16 system exceptions; no device interrupt is enabled by the image. */
__attribute__((section(".isr_vector"), used))
const vector_t qemu_m4_vectors[16] = {
    (vector_t)(uintptr_t)&__StackTop,
    Reset_Handler,
    NMI_Handler,
    HardFault_Handler,
    MemManage_Handler,
    BusFault_Handler,
    UsageFault_Handler,
    0,
    0,
    0,
    0,
    Default_Handler, /* SVCall */
    Default_Handler, /* DebugMonitor */
    0,
    Default_Handler, /* PendSV */
    Default_Handler, /* SysTick (its interrupt stays disabled) */
};
