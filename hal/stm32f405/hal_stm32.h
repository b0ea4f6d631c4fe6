/*
 * The HAL contract (hal/include/hal) on the STM32F405 and the board of
 * board.h: TIM1 PWM (pwm_tim1.h), injected ADC sampling (adc_inj.h), the
 * TIM3 encoder, CAN1, GPIO, the DWT cycle counter and a 1 kHz SysTick
 * time base. The fast ISR's accessors are static inline
 * (hal_stm32_inline.h, HAL_INLINE_ACCESSORS) and read the state below.
 */
#ifndef HAL_STM32_H
#define HAL_STM32_H

#include <stdbool.h>
#include <stdint.h>

#include "adc_inj.h"
#include "clock.h"
#include "regs.h"

typedef struct {
    stm32_clocks_t clocks;
    stm32_adc_map_t adc;
    float arr_f;          /* TIM1 ARR, float for the duty products */
    volatile uint64_t ms; /* SysTick count */
} stm32_hal_t;

extern stm32_hal_t stm32_hal;

typedef enum {
    STM32_HAL_OK = 0,
    STM32_HAL_CLOCK,      /* not on the PLL (clock.h): the drive stays off */
    STM32_HAL_ADC_MAP,    /* the board's channels make no sequence */
    STM32_HAL_ENCODER,    /* the board's counts per revolution */
    STM32_HAL_GATE_DRIVER /* the DRV8301 did not take its settings */
} stm32_hal_status_t;

/* After stm32_clock_init: the cycle counter, the 1 kHz time base, the
 * GPIO (gates off, EN_GATE, fault input, debug pin), the gate driver and
 * the encoder. The PWM and the ADCs come up in hal_pwm_init (called by
 * mc_app_init). */
stm32_hal_status_t stm32_hal_init(const stm32_clocks_t *clocks);

/* The fast ISR's entry (the ADC interrupt): clears ADC1's JEOC. */
static inline void stm32_hal_isr_ack(void)
{
    STM32_ADC(1)->SR = ~ADC_SR_JEOC;
}

#endif /* HAL_STM32_H */
