/*
 * Reset and exception vectors of the QEMU mps2-an386 image.
 *
 * Reset_Handler (hal/cortex_m/reset_handler.h: FPU, .data (LMA = VMA
 * with the linker script here: nothing to copy), .bss), then main(), and
 * the exit through semihosting with main's return value. Every fault prints its
 * name and exits with status QEMU_M4_EXIT_FAULT.
 */
#include <stdint.h>

#include "qemu_m4.h"
#include "reset_handler.h"
#include "semihost.h"

extern uint32_t __StackTop;
extern int main(void);

void qemu_m4_c_start(void);
void NMI_Handler(void);
void HardFault_Handler(void);
void MemManage_Handler(void);
void BusFault_Handler(void);
void UsageFault_Handler(void);
void Default_Handler(void);

CORTEX_M_RESET_HANDLER(qemu_m4_c_start)

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
