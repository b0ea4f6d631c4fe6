/* TIM1 PWM (pwm_tim1.h). */
#include <math.h>

#include "pwm_tim1.h"

bool stm32_tim_dtg_for(float dead_time_s, uint32_t tim_clk_hz, uint32_t *dtg,
                       float *realised_s)
{
    if (!(dead_time_s >= 0.0f && dead_time_s <= 1.0f) || tim_clk_hz == 0u) {
        return false;
    }
    /* whole t_DTS clocks, rounded up (never shorter than asked) */
    const float clocks_f = ceilf(dead_time_s * (float)tim_clk_hz - 1e-3f);
    if (clocks_f > 1008.0f) {
        return false;
    }
    uint32_t c = (clocks_f > 0.0f) ? (uint32_t)clocks_f : 0u;
    uint32_t code;
    if (c <= 127u) { /* DTG[7] = 0: c clocks */
        code = c;
    } else if (c <= 254u) { /* 10x: (64 + DTG[5:0]) x 2 */
        c = (c + 1u) / 2u * 2u;
        code = 0x80u | (c / 2u - 64u);
    } else if (c <= 504u) { /* 110: (32 + DTG[4:0]) x 8 */
        c = (c + 7u) / 8u * 8u;
        code = 0xC0u | (c / 8u - 32u);
    } else { /* 111: (32 + DTG[4:0]) x 16 */
        c = (c + 15u) / 16u * 16u;
        code = 0xE0u | (c / 16u - 32u);
    }
    *dtg = code;
    *realised_s = (float)c / (float)tim_clk_hz;
    return true;
}

stm32_pwm_status_t stm32_pwm_tim1_init(const stm32_pwm_cfg_t *cfg,
                                       stm32_pwm_t *out)
{
    if (!(cfg->f_pwm_Hz > 0.0f) || cfg->tim_clk_hz == 0u) {
        return STM32_PWM_BAD_FREQUENCY;
    }
    const float arr_f = roundf((float)cfg->tim_clk_hz / (2.0f * cfg->f_pwm_Hz));
    if (!(arr_f >= (float)STM32_PWM_ARR_MIN && arr_f <= 65535.0f)) {
        return STM32_PWM_BAD_FREQUENCY;
    }
    uint32_t dtg;
    float dt_s;
    if (!stm32_tim_dtg_for(cfg->dead_time_s, cfg->tim_clk_hz, &dtg, &dt_s)) {
        return STM32_PWM_BAD_DEAD_TIME;
    }
    const uint32_t arr = (uint32_t)arr_f;

    STM32_RCC->APB2ENR |= RCC_APB2ENR_TIM1EN;
    stm32_tim_t *t = STM32_TIM1;
    t->CR1 = 0u; /* stopped while configured */
    t->BDTR = 0u;
    t->PSC = 0u;
    t->ARR = arr;
    t->RCR = 0u; /* an update event at both ends of the count */
    for (uint32_t k = 0u; k < 3u; ++k) {
        t->CCR[k] = arr / 2u;
    }
    t->CCR[3] = arr - 1u; /* the ADC trigger just after the top */
    const uint32_t pwm = TIM_CCMR_OC_PWM1 | TIM_CCMR_OC_PE;
    t->CCMR1 = pwm | (pwm << 8u);            /* channels 1, 2 */
    t->CCMR2 = pwm | (TIM_CCMR_OC_PE << 8u); /* 3; 4 frozen (no pin) */
    t->CCER = TIM_CCER_CCE(0) | TIM_CCER_CCNE(0) | TIM_CCER_CCE(1) |
              TIM_CCER_CCNE(1) | TIM_CCER_CCE(2) | TIM_CCER_CCNE(2);
    t->CR2 = 0u; /* idle levels low (OISx = OISxN = 0) */
    uint32_t bdtr = dtg | TIM_BDTR_OSSI | TIM_BDTR_OSSR;
    if (cfg->break_enable) {
        bdtr |= TIM_BDTR_BKE | (cfg->break_active_high ? TIM_BDTR_BKP : 0u);
    }
    t->BDTR = bdtr;      /* MOE = 0: outputs off */
    t->EGR = TIM_EGR_UG; /* load the preloaded registers */
    t->SR = 0u;
    t->CR1 = TIM_CR1_CMS_CENTER1 | TIM_CR1_ARPE | TIM_CR1_CEN;

    *out = (stm32_pwm_t){
        .arr = arr,
        .dtg = dtg,
        .period_s = 2.0f * arr_f / (float)cfg->tim_clk_hz,
        .dead_time_s = dt_s,
        .delay_periods = 1.0f,
    };
    return STM32_PWM_OK;
}
