/*
 * The bare encoder-FOC current path of the Cortex-M3 images
 * (hal/qemu_m3/README.md), in one of two number formats:
 *   foc_q31.c  Q31 fixed point on the firmware's Q31 core (mc/clarke_q31.h,
 *              mc/park_q31.h, mc/pi_q31.h, mc/svpwm_q31.h) and a Q31
 *              sine table: integer only, no float in the ISR;
 *   foc_f32.c  float32 on the firmware's float core (mc/clarke.h,
 *              mc/park.h, mc/pi.h, mc/svpwm.h, mc_sincos_f32): on the M3
 *              every float operation is a libgcc call.
 * An image links exactly one of them with the harness foc_closed_loop.c.
 *
 * One ISR call (foc_isr) is one PWM period: three phase-current
 * conversions (12-bit ADC, offset binary) and the encoder count in; Clarke,
 * electrical angle from the count, sin/cos, Park, PI on d and on q (gains
 * by pole-zero cancellation, kp = L w_c, ki = R w_c, outputs limited to
 * +-FOC_PI_LIMIT_PU of v_dc), inverse Park, SVPWM (circle limit) and three
 * timer compare values out. No decoupling feed-forward, no bus-voltage
 * compensation (the design bus voltage is used), no protection: the
 * current path only.
 */
#ifndef QEMU_M3_FOC_M3_H
#define QEMU_M3_FOC_M3_H

#include <stdbool.h>
#include <stdint.h>

/* PI output limits, per-unit of the bus voltage (per axis). */
#define FOC_PI_LIMIT_PU 0.5

/* The peripheral registers the ISR reads and writes (the harness stands
 * in for the ADC, the encoder counter and the PWM timer). */
typedef struct {
    uint16_t adc[3];    /* phase currents a, b, c: code + 2^(bits-1) */
    uint32_t enc_count; /* x4 quadrature count, 0 .. cpr - 1 */
    uint32_t ccr[3];    /* compare values 0 .. arr (duty = ccr / arr) */
} foc_io_t;

/* Design data, converted at initialisation (double; not in the ISR). */
typedef struct {
    double R_ohm, L_H;   /* nominal stator resistance, inductance */
    double w_c_rad_s;    /* current-loop bandwidth */
    double v_dc_V;       /* design bus voltage */
    double f_pwm_Hz;     /* PWM = sample frequency */
    double i_fs_A;       /* ADC full scale: codes cover [-i_fs, i_fs) */
    uint32_t adc_bits;   /* ADC resolution, 2 .. 16 */
    uint32_t pole_pairs; /* n_p */
    uint32_t cpr;        /* encoder counts per mechanical turn */
    uint32_t arr;        /* timer period in compare counts */
} foc_design_t;

/* What the harness reads after a call (the ISR stores it anyway). */
typedef struct {
    double v_d_pu, v_q_pu; /* PI outputs, per-unit of v_dc */
    bool overmodulated;    /* SVPWM reduced the command */
} foc_monitor_t;

/* Name of the number format ("q31" / "f32"). */
extern const char foc_format_name[];

/* 0, or non-zero if the design cannot be represented. Thread context. */
int foc_init(const foc_design_t *d);

/* Current references in A (d, q). Thread context, between ISR calls. */
void foc_set_reference(double i_d_A, double i_q_A);

/* One PWM period; arg is the foc_io_t. Interrupt context. */
void foc_isr(void *arg);

/* The latest call's outputs. Thread context. */
void foc_monitor(foc_monitor_t *m);

#endif /* QEMU_M3_FOC_M3_H */
