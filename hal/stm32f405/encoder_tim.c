/* The encoder timer (encoder_tim.h). */
#include "encoder_tim.h"

#include "gpio_cfg.h"
#include "regs.h"

/* Input filter f_DTS / 32, N = 8 on both channels (IC1F, IC2F = 1111 is
 * the strongest; 0011 = f_CK_INT, N = 8 keeps edges up to ~10 MHz). */
#define ENCODER_IC_FILTER 3u

bool stm32_encoder_init(const stm32_board_t *b)
{
    const uint32_t cpr = b->encoder_counts_per_rev;
    if (cpr < 4u || cpr > 65536u) {
        return false;
    }
    STM32_RCC->APB1ENR |= RCC_APB1ENR_TIM3EN;
    stm32_tim_t *t = STM32_TIM3;
    t->CR1 = 0u;
    t->SMCR = TIM_SMCR_SMS_ENC3;
    /* CC1S = CC2S = 01 (TI1, TI2), IC1F, IC2F (bits 7:4, 15:12) */
    t->CCMR1 = TIM_CCMR_CC_TI | (ENCODER_IC_FILTER << 4u) |
               (TIM_CCMR_CC_TI << 8u) | (ENCODER_IC_FILTER << 12u);
    t->CCER = 0u; /* both polarities non-inverted */
    t->PSC = 0u;
    t->ARR = cpr - 1u;
    t->CNT = 0u;
    t->CR1 = TIM_CR1_CEN;
    stm32_gpio_setup(&b->encoder_a, GPIO_MODE_AF, STM32_PULL_UP);
    stm32_gpio_setup(&b->encoder_b, GPIO_MODE_AF, STM32_PULL_UP);
    return true;
}
