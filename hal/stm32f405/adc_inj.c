/* Current and bus sampling (adc_inj.h). */
#include "adc_inj.h"

#include "gpio_cfg.h"
#include "regs.h"

#define ADC_FULL_SCALE 4096.0f
#define SMP_15_CYCLES  1u

bool stm32_adc_map_for(const stm32_board_t *b, stm32_adc_map_t *map)
{
    uint8_t seq[3][4];
    uint8_t len[3] = { 0u, 0u, 0u };
    uint32_t measured = 0u;
    *map = (stm32_adc_map_t){ 0 };
    for (uint32_t k = 0u; k < 3u; ++k) {
        if (b->current_channel[k] == STM32_NO_ADC_CHANNEL) {
            continue;
        }
        const uint8_t a = b->current_adc[k];
        if (a < 1u || a > 3u || len[a - 1u] != 0u ||
            b->current_channel[k] > 18u) {
            return false;
        }
        seq[a - 1u][len[a - 1u]] = b->current_channel[k];
        map->current_adc[k] = a;
        map->current_jdr[k] = len[a - 1u]++;
        measured++;
    }
    /* the scale factors divide by these */
    if (measured < 2u || b->vbus_channel > 18u ||
        !(b->current_gain * b->shunt_ohm > 0.0f) || !(b->adc_vref_V > 0.0f)) {
        return false;
    }
    seq[0][len[0]] = b->vbus_channel;
    map->vbus_jdr = len[0]++;
    /* simultaneous mode: equal lengths, the shorter ones padded */
    uint8_t n = 1u;
    for (uint32_t a = 0u; a < 3u; ++a) {
        n = (len[a] > n) ? len[a] : n;
    }
    for (uint32_t a = 0u; a < 3u; ++a) {
        if (len[a] == 0u) {
            /* An ADC without a current (only when ADC1 has one: at least
             * two currents, one per ADC; so ADC1's sequence is [current,
             * bus], n = 2): dummy conversions of ADC1's two channels in
             * the other order, so that no rank converts one channel on
             * two ADCs at once (RM0090 13.9.1: no overlapping sampling of
             * the same channel; the bus channel alone, as before, would
             * meet ADC1's bus conversion in the second rank). */
            for (uint32_t i = 0u; i < len[0]; ++i) {
                seq[a][i] = seq[0][(i + 1u) % len[0]];
            }
            len[a] = len[0];
        }
        while (len[a] < n) {
            seq[a][len[a]] = seq[a][len[a] - 1u];
            len[a]++;
        }
        uint32_t jsqr = (uint32_t)(n - 1u) << ADC_JSQR_JL_POS;
        for (uint32_t i = 0u; i < n; ++i) {
            const uint32_t slot = 4u - n + i; /* JSQ(5-n+i), 0-based */
            jsqr |= (uint32_t)seq[a][i] << (5u * slot);
        }
        map->jsqr[a] = jsqr;
    }
    const float volts_per_count = b->adc_vref_V / ADC_FULL_SCALE;
    map->amps_per_count = volts_per_count / (b->current_gain * b->shunt_ohm);
    map->zero_counts = b->current_zero_V / volts_per_count;
    map->volts_per_count = volts_per_count * b->vbus_divider;
    return true;
}

/* SMPR bits for a channel: 3 bits each, 0..9 in SMPR2, 10..18 in SMPR1. */
static void set_sample_time(stm32_adc_t *adc, uint32_t ch)
{
    if (ch < 10u) {
        adc->SMPR2 |= SMP_15_CYCLES << (3u * ch);
    } else {
        adc->SMPR1 |= SMP_15_CYCLES << (3u * (ch - 10u));
    }
}

void stm32_adc_inj_init(const stm32_board_t *b, const stm32_adc_map_t *map)
{
    STM32_RCC->APB2ENR |=
        RCC_APB2ENR_ADC1EN | RCC_APB2ENR_ADC2EN | RCC_APB2ENR_ADC3EN;
    for (uint32_t k = 0u; k < 3u; ++k) {
        if (b->current_channel[k] != STM32_NO_ADC_CHANNEL) {
            stm32_gpio_setup(&b->current_pin[k], GPIO_MODE_ANALOG,
                             STM32_PULL_NONE);
        }
    }
    stm32_gpio_setup(&b->vbus_pin, GPIO_MODE_ANALOG, STM32_PULL_NONE);
    /* ADC clock PCLK2 / 4; triple mode, injected simultaneous only */
    STM32_ADC_COMMON->CCR =
        (1u << ADC_CCR_ADCPRE_POS) | ADC_CCR_MULTI_TRIPLE_INJ;
    for (uint32_t a = 1u; a <= 3u; ++a) {
        stm32_adc_t *adc = STM32_ADC(a);
        adc->CR2 = 0u;
        adc->CR1 = ADC_CR1_SCAN | ((a == 1u) ? ADC_CR1_JEOCIE : 0u);
        adc->SMPR1 = 0u;
        adc->SMPR2 = 0u;
        const uint32_t n = ((map->jsqr[a - 1u] >> ADC_JSQR_JL_POS) & 3u) + 1u;
        for (uint32_t slot = 4u - n; slot < 4u; ++slot) {
            set_sample_time(adc, (map->jsqr[a - 1u] >> (5u * slot)) & 0x1Fu);
        }
        adc->JSQR = map->jsqr[a - 1u];
        adc->SR = 0u;
        /* the master (ADC1) takes TIM1's CC4 on its rising edge; the
         * others follow it in triple mode */
        adc->CR2 = ADC_CR2_ADON |
                   ((a == 1u) ? ((ADC_JEXTSEL_TIM1_CC4 << ADC_CR2_JEXTSEL_POS) |
                                 (ADC_JEXTEN_RISING << ADC_CR2_JEXTEN_POS))
                              : 0u);
    }
    STM32_NVIC->IPR[STM32_IRQ_ADC] = 0u; /* the highest priority */
}

void stm32_adc_irq_enable(bool on)
{
    const uint32_t bit = 1u << (STM32_IRQ_ADC % 32u);
    if (on) {
        STM32_NVIC->ISER[STM32_IRQ_ADC / 32u] = bit;
    } else {
        STM32_NVIC->ICER[STM32_IRQ_ADC / 32u] = bit;
        stm32_barrier(); /* no ADC interrupt past this point */
    }
}
