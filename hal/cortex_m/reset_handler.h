/*
 * The reset handler the Cortex-M ports share (hal/qemu_m4, hal/qemu_m3,
 * hal/stm32f405): CORTEX_M_RESET_HANDLER(c_entry) defines Reset_Handler,
 * naked (no compiler-generated code runs before the FPU is on): CP10 and
 * CP11 full access in CPACR (harmless on a core without an FPU), .data
 * copied from its load address when that differs from its run address
 * (__data_load__, __data_start__, __data_end__ of the linker script),
 * .bss zeroed (__bss_start__, __bss_end__), then c_entry(), which must
 * not return.
 */
#ifndef CORTEX_M_RESET_HANDLER_H
#define CORTEX_M_RESET_HANDLER_H

#define CORTEX_M_RESET_HANDLER(c_entry)                                        \
    void Reset_Handler(void);                                                  \
    __attribute__((naked, noreturn)) void Reset_Handler(void)                  \
    {                                                                          \
        __asm__ volatile(/* CPACR (0xE000ED88): CP10, CP11 bits 20-23 */       \
                         "ldr r0, =0xE000ED88\n"                               \
                         "ldr r1, [r0]\n"                                      \
                         "orr r1, r1, #(0xF << 20)\n"                          \
                         "str r1, [r0]\n"                                      \
                         "dsb\n"                                               \
                         "isb\n" /* .data: copy only when LMA != VMA */        \
                         "ldr r0, =__data_load__\n"                            \
                         "ldr r1, =__data_start__\n"                           \
                         "ldr r2, =__data_end__\n"                             \
                         "cmp r0, r1\n"                                        \
                         "beq 2f\n"                                            \
                         "1: cmp r1, r2\n"                                     \
                         "bhs 2f\n"                                            \
                         "ldr r3, [r0], #4\n"                                  \
                         "str r3, [r1], #4\n"                                  \
                         "b 1b\n" /* .bss: zero */                             \
                         "2: ldr r1, =__bss_start__\n"                         \
                         "ldr r2, =__bss_end__\n"                              \
                         "movs r3, #0\n"                                       \
                         "3: cmp r1, r2\n"                                     \
                         "bhs 4f\n"                                            \
                         "str r3, [r1], #4\n"                                  \
                         "b 3b\n"                                              \
                         "4: bl " #c_entry "\n"                                \
                         "b .\n");                                             \
    }

#endif /* CORTEX_M_RESET_HANDLER_H */
