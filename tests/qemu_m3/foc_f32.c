/*
 * The current path of foc_m3.h in float32 on the firmware's float core,
 * the same steps as foc_q31.c: currents in A, voltages in V, angle in rad.
 * Built with -mfloat-abi=soft for the M3 every float operation is a
 * libgcc call (__aeabi_fmul, __aeabi_fadd, ...): the comparison of the two
 * images is what the missing FPU costs this path; built for the M4F the
 * same file runs on the FPU (hal/qemu_m3/README.md).
 *
 * Electrical angle: ((count * n_p) mod cpr + n_p / 2) * 2 pi / cpr in
 * [0, 2 pi): the middle of the count's interval, as in foc_q31.c.
 */
#include "foc_m3.h"
#include "mc/angle.h"
#include "mc/clarke.h"
#include "mc/park.h"
#include "mc/pi.h"
#include "mc/svpwm.h"

const char foc_format_name[] = "f32";

typedef struct {
    mc_pi_f32_t pi_d, pi_q; /* V per A */
    float i_d_ref, i_q_ref; /* A */
    int32_t adc_offset;     /* code of 0 A */
    float amp_per_code;     /* 2 i_fs / 2^bits */
    uint32_t pole_pairs, cpr;
    float rad_per_count;  /* 2 pi / cpr */
    float half_count_rad; /* n_p pi / cpr */
    float v_dc_V;
    float arr;
    float v_d, v_q; /* latest PI outputs, V (monitor) */
    bool overmodulated;
} foc_f32_state_t;

static foc_f32_state_t st;

int foc_init(const foc_design_t *d)
{
    if (d->adc_bits < 2u || d->adc_bits > 16u || d->cpr == 0u || d->arr == 0u) {
        return -1;
    }
    const double two_pi = 6.283185307179586;
    const float lim = (float)(FOC_PI_LIMIT_PU * d->v_dc_V);
    const float kp = (float)(d->L_H * d->w_c_rad_s);
    const float ki = (float)(d->R_ohm * d->w_c_rad_s);
    const float ts = (float)(1.0 / d->f_pwm_Hz);
    if (mc_pi_init_f32(&st.pi_d, kp, ki, ts, -lim, lim) != MC_OK ||
        mc_pi_init_f32(&st.pi_q, kp, ki, ts, -lim, lim) != MC_OK) {
        return -3;
    }
    st.adc_offset = (int32_t)1 << (d->adc_bits - 1u);
    st.amp_per_code = (float)(2.0 * d->i_fs_A / (double)(1u << d->adc_bits));
    st.pole_pairs = d->pole_pairs;
    st.cpr = d->cpr;
    st.rad_per_count = (float)(two_pi / (double)d->cpr);
    st.half_count_rad = (float)(0.5 * two_pi * (double)d->pole_pairs / (double)d->cpr);
    st.v_dc_V = (float)d->v_dc_V;
    st.arr = (float)d->arr;
    st.i_d_ref = 0.0f;
    st.i_q_ref = 0.0f;
    return 0;
}

void foc_set_reference(double i_d_A, double i_q_A)
{
    st.i_d_ref = (float)i_d_A;
    st.i_q_ref = (float)i_q_A;
}

static inline float adc_amp(uint16_t raw)
{
    return (float)((int32_t)raw - st.adc_offset) * st.amp_per_code;
}

void foc_isr(void *arg)
{
    foc_io_t *io = arg;
    float i_alpha;
    float i_beta;
    mc_clarke_f32(adc_amp(io->adc[0]), adc_amp(io->adc[1]), adc_amp(io->adc[2]), &i_alpha, &i_beta);

    const uint32_t e_count = (io->enc_count * st.pole_pairs) % st.cpr;
    const float theta = (float)e_count * st.rad_per_count + st.half_count_rad;
    float s;
    float c;
    mc_sincos_f32(theta, &s, &c);

    float i_d;
    float i_q;
    mc_park_f32(i_alpha, i_beta, s, c, &i_d, &i_q);
    st.v_d = mc_pi_step_f32(&st.pi_d, st.i_d_ref - i_d);
    st.v_q = mc_pi_step_f32(&st.pi_q, st.i_q_ref - i_q);

    float v_alpha;
    float v_beta;
    mc_inv_park_f32(st.v_d, st.v_q, s, c, &v_alpha, &v_beta);
    mc_svpwm_out_f32_t pwm;
    (void)mc_svpwm_f32(v_alpha, v_beta, st.v_dc_V, MC_SVPWM_LIMIT_CIRCLE, &pwm);
    st.overmodulated = pwm.overmodulated;
    for (unsigned k = 0u; k < 3u; ++k) {
        io->ccr[k] = (uint32_t)(pwm.duty[k] * st.arr + 0.5f);
    }
}

void foc_monitor(foc_monitor_t *m)
{
    m->v_d_pu = (double)st.v_d / (double)st.v_dc_V;
    m->v_q_pu = (double)st.v_q / (double)st.v_dc_V;
    m->overmodulated = st.overmodulated;
}
