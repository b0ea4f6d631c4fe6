/*
 * Current and bus sampling: ADC1, ADC2, ADC3 in triple injected
 * simultaneous mode (RM0090 13.9), triggered by TIM1's channel-4 compare
 * (pwm_tim1.h), 12 bits, ADC clock PCLK2 / 4 (21 MHz), 15-cycle sampling:
 * each conversion 27 ADC clocks, 1.3 us. ADC1 converts the bus voltage
 * (after its current, if it has one); its end of injected conversion
 * (JEOC) raises the ADC interrupt: the fast ISR.
 *
 * An injected sequence of length L uses JSQ(5-L) .. JSQ4 (RM0090 13.13.12:
 * the sequence is aligned to JSQ4) and its results land in JDR1 .. JDRL.
 */
#ifndef STM32_ADC_INJ_H
#define STM32_ADC_INJ_H

#include <stdbool.h>
#include <stdint.h>

#include "board.h"

/* Where each value lands: ADC (1..3) and JDR index (0..3). */
typedef struct {
    uint8_t current_adc[3], current_jdr[3]; /* current_adc 0: computed
                                               as minus the others' sum */
    uint8_t vbus_jdr;                       /* in ADC1 */
    uint32_t jsqr[3];                       /* of ADC1..3 */
    float amps_per_count;
    float zero_counts;
    float volts_per_count; /* bus */
} stm32_adc_map_t;

/* The sequences of the board's channels; false if a phase's ADC is not
 * 1..3, two phases share one, fewer than two currents are measured, or
 * the board's gain x shunt or ADC reference is not positive. */
bool stm32_adc_map_for(const stm32_board_t *b, stm32_adc_map_t *map);

/* Configure the three ADCs (after stm32_adc_map_for), the analog pins and
 * the interrupt on ADC1's JEOC at the highest priority, not yet enabled
 * in the NVIC: the image enables it once the drive is initialised. */
void stm32_adc_inj_init(const stm32_board_t *b, const stm32_adc_map_t *map);

/* The fast ISR (the ADC interrupt) on or off in the NVIC; off also waits
 * until no ADC interrupt can start any more. */
void stm32_adc_irq_enable(bool on);

#endif /* STM32_ADC_INJ_H */
