/*
 * TIM1: centre-aligned three-phase PWM with complementary outputs and dead
 * time (RM0090 17.3.9-17.3.12), the break input, and the compare event of
 * channel 4 that triggers the current sampling (adc_inj.h).
 *
 * Counter 0 -> ARR -> 0 (centre-aligned mode 1), PWM mode 1: a high side
 * is on while CNT < CCRx, so every low side conducts around the top of
 * the count, where channel 4 (CCR4 = ARR - 1, compare events only while
 * counting down in mode 1) triggers the ADCs: the sample at the centre of
 * the low-side conduction. The compare registers are preloaded and load
 * at every update event, at both ends of the count (RCR = 0): duties the
 * fast ISR writes after the sample at the top act from the bottom, half a
 * period later, for one period: the HAL's sample-to-apply delay d = 1
 * (hal/pwm.h), provided the ISR ends within half a period.
 *
 * Outputs: MOE off leaves all six at their idle level, low (OSSI = 1,
 * OISx = 0: every transistor off); the break input, if the board wires
 * one, clears MOE in hardware.
 */
#ifndef STM32_PWM_TIM1_H
#define STM32_PWM_TIM1_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/pwm_duty.h"
#include "regs.h"

typedef struct {
    uint32_t tim_clk_hz; /* TIM1's kernel clock (168 MHz) */
    float f_pwm_Hz;
    float dead_time_s;
    bool break_enable;
    bool break_active_high;
} stm32_pwm_cfg_t;

typedef struct {
    uint32_t arr;        /* half the period in counts */
    uint32_t dtg;        /* BDTR.DTG */
    float period_s;      /* 2 ARR / f_clk */
    float dead_time_s;   /* realised, >= the request */
    float delay_periods; /* 1.0 (above) */
} stm32_pwm_t;

typedef enum {
    STM32_PWM_OK = 0,
    STM32_PWM_BAD_FREQUENCY, /* ARR outside [100, 65535] or not finite */
    STM32_PWM_BAD_DEAD_TIME  /* beyond 1008 DTS clocks or not finite */
} stm32_pwm_status_t;

#define STM32_PWM_ARR_MIN 100u

/* BDTR.DTG for the shortest dead time >= dead_time_s at tim_clk_hz
 * (CKD = 00: t_DTS = 1 / tim_clk_hz), its realised time in *realised_s;
 * false beyond the field's range (1008 t_DTS). */
bool stm32_tim_dtg_for(float dead_time_s, uint32_t tim_clk_hz, uint32_t *dtg,
                       float *realised_s);

/* Configure and start TIM1 with the outputs off (MOE = 0). The caller
 * sets the pins up after this (hal_stm32.c), so they never see an
 * unconfigured output. */
stm32_pwm_status_t stm32_pwm_tim1_init(const stm32_pwm_cfg_t *cfg,
                                       stm32_pwm_t *out);

/* The compare value of a duty in [0, 1]: d ARR rounded; a duty outside
 * [0, 1] takes the nearer bound, NaN 0.5 (the HAL contract's
 * protection). */
static inline uint32_t stm32_pwm_ccr(float duty, float arr_f)
{
    return (uint32_t)(hal_duty_saturate_f32(duty) * arr_f + 0.5f);
}

#endif /* STM32_PWM_TIM1_H */
