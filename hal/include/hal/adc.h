/*
 * HAL contract: the analog samples of one PWM period.
 *
 * The conversions are triggered at the PWM centre (all low-side switches on
 * or all high-side switches on, no switching edge nearby) and are complete
 * when the fast ISR runs.
 */
#ifndef HAL_ADC_H
#define HAL_ADC_H

#include <stdbool.h>

typedef struct {
    float i_abc_A[3]; /* phase currents a, b, c in A (positive into the motor),
                         scaled by the backend's nominal gain; any offset is
                         left for the firmware to calibrate */
    float v_dc_V;     /* DC-bus voltage in V */
    float temp_degC;  /* power-stage temperature in degC, if temp_valid */
    bool temp_valid;  /* false when the board has no temperature sensor */
} hal_adc_sample_t;

#ifdef HAL_INLINE_ACCESSORS
#include HAL_INLINE_ACCESSORS /* the binding's static inline definitions */
#else
/* Read the samples converted at this period's PWM centre.
 * out: non-NULL. Interrupt context: yes (it is meant for the
 * fast ISR; elsewhere it returns the latest completed conversion). */
void hal_adc_read(hal_adc_sample_t *out);
#endif

#endif /* HAL_ADC_H */
