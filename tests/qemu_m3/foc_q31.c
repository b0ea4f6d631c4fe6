/*
 * The current path of foc_m3.h in Q31 fixed point: integer only in the ISR.
 *
 * Scaling: currents (measured, references, PI errors) are Q31 of the ADC
 * full scale i_fs; voltages (PI outputs, alpha/beta command) Q31 of the
 * design bus voltage v_dc, which is what mc_svpwm_q31 takes. The PI gains
 * are therefore kp i_fs / v_dc and ki Ts i_fs / v_dc (mc/pi_q31.h).
 *
 * Electrical angle: a uint32_t fraction of a turn (2^32 = 2 pi),
 *   theta = count * k_enc + k_enc / 2,  k_enc = round(n_p 2^32 / cpr),
 * wrapping modulo one electrical turn by itself; the half count puts the
 * angle in the middle of the count's interval (|error| <= n_p pi / cpr);
 * the rounding of k_enc adds count * 1/2 2^-32 turn (2.8e-6 rad at cpr
 * 10000, n_p 3).
 *
 * sin/cos: the library's Q31 core has none (its Park takes Q31 sin and
 * cos from the caller); here a sine table of SINCOS_N entries per turn
 * with linear interpolation: |error| <= (2 pi / N)^2 / 8 = 4.7e-6 of full
 * scale for N = 1024 (plus the table's own rounding, 1/2 LSB), filled at
 * initialisation from libm's double sin (4.9 kB of RAM; const data in a
 * product). cos(theta) is read from the same table a quarter turn ahead.
 */
#include <math.h>
#include <stddef.h>

#include "foc_m3.h"
#include "mc/clarke_q31.h"
#include "mc/park_q31.h"
#include "mc/pi_q31.h"
#include "mc/svpwm_q31.h"

#define SINCOS_BITS 10u
#define SINCOS_N    (1u << SINCOS_BITS)
#define Q31_ONE     2147483648.0 /* 2^31 */

const char foc_format_name[] = "q31";

typedef struct {
    mc_pi_q31_t pi_d, pi_q;
    mc_q31_t i_d_ref, i_q_ref; /* Q31 of i_fs */
    int32_t adc_offset;        /* code of 0 A: 2^(bits-1) */
    int32_t adc_scale;         /* code -> Q31: 2^(32-bits) */
    uint32_t k_enc;            /* angle per count, 2^32 = one turn */
    uint32_t k_enc_half;       /* half a count */
    uint32_t arr;
    mc_q31_t v_d, v_q; /* latest PI outputs (monitor) */
    bool overmodulated;
    double i_fs_A; /* thread context only (references) */
} foc_q31_state_t;

static foc_q31_state_t st;

/* sin over one turn and a quarter (cos = sin a quarter turn ahead), one
 * more entry for the interpolation at the end. */
static mc_q31_t sin_table[SINCOS_N + SINCOS_N / 4u + 1u];

/* Nearest Q31 value of x, saturated (|x| < 2^32: the design's numbers). */
static mc_q31_t q31_of(double x)
{
    return mc_sat_q31((int64_t)llround(x * Q31_ONE));
}

/* A dimensionless gain g >= 0 as frac * 2^shift / 2^31 (mc/pi_q31.h). */
static int q31_gain(double g, mc_q31_t *frac, uint8_t *shift)
{
    unsigned s = 0u;
    while (g >= 1.0) {
        g *= 0.5;
        if (++s > MC_PI_Q31_MAX_SHIFT) {
            return -1;
        }
    }
    *frac = q31_of(g);
    *shift = (uint8_t)s;
    return 0;
}

/* Interpolated table value at entry t[0] + frac16 / 2^16. */
static inline mc_q31_t table_lerp(const mc_q31_t *t, uint32_t frac16)
{
    const int64_t step = (int64_t)t[1] - (int64_t)t[0];
    return (mc_q31_t)((int64_t)t[0] + mc_round_shift_q63(step * (int64_t)frac16, 16u));
}

static inline void sincos_q31(uint32_t theta, mc_q31_t *s, mc_q31_t *c)
{
    const uint32_t idx = theta >> (32u - SINCOS_BITS);
    const uint32_t frac16 = (theta >> (16u - SINCOS_BITS)) & 0xFFFFu;
    *s = table_lerp(&sin_table[idx], frac16);
    *c = table_lerp(&sin_table[idx + SINCOS_N / 4u], frac16);
}

int foc_init(const foc_design_t *d)
{
    if (d->adc_bits < 2u || d->adc_bits > 16u || d->cpr == 0u || d->arr == 0u) {
        return -1;
    }
    const double two_pi = 6.283185307179586;
    for (size_t k = 0u; k < sizeof sin_table / sizeof sin_table[0]; ++k) {
        sin_table[k] = q31_of(sin(two_pi * (double)k / (double)SINCOS_N));
    }
    const double ts = 1.0 / d->f_pwm_Hz;
    const double e_per_u = d->i_fs_A / d->v_dc_V; /* E_fs / U_fs */
    mc_q31_t kp_frac;
    mc_q31_t ki_frac;
    uint8_t kp_shift;
    uint8_t ki_shift;
    if (q31_gain(d->L_H * d->w_c_rad_s * e_per_u, &kp_frac, &kp_shift) != 0 ||
        q31_gain(d->R_ohm * d->w_c_rad_s * ts * e_per_u, &ki_frac, &ki_shift) != 0) {
        return -2;
    }
    const mc_q31_t lim = q31_of(FOC_PI_LIMIT_PU);
    if (mc_pi_init_q31(&st.pi_d, kp_frac, kp_shift, ki_frac, ki_shift, -lim, lim) != MC_OK ||
        mc_pi_init_q31(&st.pi_q, kp_frac, kp_shift, ki_frac, ki_shift, -lim, lim) != MC_OK) {
        return -3;
    }
    st.adc_offset = (int32_t)1 << (d->adc_bits - 1u);
    st.adc_scale = (int32_t)1 << (32u - d->adc_bits);
    st.k_enc = (uint32_t)nearbyint((double)d->pole_pairs * 4294967296.0 / (double)d->cpr);
    st.k_enc_half = st.k_enc / 2u;
    st.arr = d->arr;
    st.i_fs_A = d->i_fs_A;
    st.i_d_ref = 0;
    st.i_q_ref = 0;
    return 0;
}

void foc_set_reference(double i_d_A, double i_q_A)
{
    st.i_d_ref = q31_of(i_d_A / st.i_fs_A);
    st.i_q_ref = q31_of(i_q_A / st.i_fs_A);
}

static inline mc_q31_t adc_q31(uint16_t raw)
{
    return ((int32_t)raw - st.adc_offset) * st.adc_scale;
}

void foc_isr(void *arg)
{
    foc_io_t *io = arg;
    mc_q31_t i_alpha;
    mc_q31_t i_beta;
    mc_clarke_q31(adc_q31(io->adc[0]), adc_q31(io->adc[1]), adc_q31(io->adc[2]), &i_alpha, &i_beta);

    const uint32_t theta = io->enc_count * st.k_enc + st.k_enc_half;
    mc_q31_t s;
    mc_q31_t c;
    sincos_q31(theta, &s, &c);

    mc_q31_t i_d;
    mc_q31_t i_q;
    mc_park_q31(i_alpha, i_beta, s, c, &i_d, &i_q);
    st.v_d = mc_pi_step_q31(&st.pi_d, mc_sub_sat_q31(st.i_d_ref, i_d));
    st.v_q = mc_pi_step_q31(&st.pi_q, mc_sub_sat_q31(st.i_q_ref, i_q));

    mc_q31_t v_alpha;
    mc_q31_t v_beta;
    mc_inv_park_q31(st.v_d, st.v_q, s, c, &v_alpha, &v_beta);
    mc_svpwm_out_q31_t pwm;
    (void)mc_svpwm_q31(v_alpha, v_beta, MC_SVPWM_LIMIT_CIRCLE, &pwm);
    st.overmodulated = pwm.overmodulated;
    for (unsigned k = 0u; k < 3u; ++k) {
        /* round(duty * arr), duty = pwm.duty / 2^31 in [0, 1) */
        io->ccr[k] =
            (uint32_t)(((uint64_t)(uint32_t)pwm.duty[k] * st.arr + ((uint64_t)1 << 30)) >> 31);
    }
}

void foc_monitor(foc_monitor_t *m)
{
    m->v_d_pu = (double)st.v_d / Q31_ONE;
    m->v_q_pu = (double)st.v_q / Q31_ONE;
    m->overmodulated = st.overmodulated;
}
