/*
 * The drive image: the firmware on the STM32F405 board of board.h, driven
 * over CAN1 at 1 Mbit/s with the node of mc/can_node.h.
 *
 * Boot: the clock tree (clock.h; on anything but the PLL from the crystal
 * the drive refuses to start and says why on the console), the console's
 * report, the stack guard, the HAL (gate driver, encoder), the drive
 * (mc_app_init brings TIM1 and the ADCs up through hal_pwm_init), CAN,
 * the watchdog. The fast ISR is the ADC interrupt (ADC1's end of injected
 * conversion); the background loop polls the CAN node and refreshes the
 * watchdog. A parameter write re-initialises the drive with the ADC
 * interrupt masked (mc/can_node.h).
 */
#include <stdint.h>

#include "adc_inj.h"
#include "board.h"
#include "clock.h"
#include "console.h"
#include "hal/can.h"
#include "hal/encoder.h"
#include "hal_stm32.h"
#include "iwdg.h"
#include "mc/app.h"
#include "mc/can_node.h"
#include "mc/config.h"
#include "regs.h"
#include "stack_guard.h"
#include "startup.h"

#define CAN_BITRATE_BPS 1000000u

extern uint32_t __stack_guard__;

static mc_app_t app;
static mc_can_node_t node;

void ADC_IRQHandler(void)
{
    stm32_hal_isr_ack();
    mc_app_fast_isr(&app);
}

static mc_status_t apply_config(void *ctx, const mc_config_t *cfg)
{
    (void)ctx;
    stm32_adc_irq_enable(false);
    const mc_status_t st = mc_app_init(&app, cfg);
    stm32_adc_irq_enable(true);
    return st;
}

static void report(const char *what, int32_t value)
{
    stm32_console_puts(what);
    stm32_console_put_i32(value);
    stm32_console_puts("\r\n");
}

int main(void)
{
    stm32_clocks_t clk;
    stm32_boot("pmsm drive on", &clk);
    report("clock status ", (int32_t)clk.status);
    report("sysclk Hz ", (int32_t)clk.sysclk_hz);
    stm32_stack_guard_init((uint32_t)(uintptr_t)&__stack_guard__);

    const stm32_hal_status_t hs = stm32_hal_init(&clk);
    if (hs != STM32_HAL_OK) {
        report("HAL init failed: ", (int32_t)hs);
        stm32_fatal("HAL init");
    }
    /* the defaults (mc/config.h) with the board's encoder, and the
     * telemetry record written at the slow ticks in RUN, not by every ISR
     * (mc/timing.h: its CAN telemetry then refreshes at the slow-loop
     * rate, 2 kHz by default); the motor and the tuning come over CAN
     * (parameter writes) */
    mc_config_t cfg;
    mc_config_init_default(&cfg);
    cfg.encoder.counts_per_rev = hal_encoder_counts_per_rev();
    cfg.timing.telemetry_every_isr = false;
    const mc_status_t st = mc_app_init(&app, &cfg);
    if (st != MC_OK) {
        report("drive init failed: ", (int32_t)st);
        stm32_fatal("drive init");
    }
    const hal_status_t cs = hal_can_init(CAN_BITRATE_BPS);
    report("CAN status ", (int32_t)cs);
    mc_can_node_config_t ncfg;
    mc_can_node_config_default(&ncfg);
    if (mc_can_node_init(&node, &ncfg, &cfg, apply_config, NULL) != MC_OK) {
        stm32_fatal("CAN node init");
    }
    stm32_adc_irq_enable(true); /* the fast ISR runs from here */
    if (!stm32_iwdg_start()) {
        stm32_fatal("watchdog");
    }
    for (;;) {
        mc_can_node_poll(&node, &app);
        stm32_iwdg_refresh();
    }
}
