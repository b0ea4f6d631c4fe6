/* Back-EMF monitor (mc/emf_monitor.h). */
#include "mc/emf_monitor.h"

#include <math.h>

#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/finite.h"

#define MC_EMF_DECIMATION_MAX 1000u

/* The period of the steps, N Ts. */
static float step_period_s(const mc_emf_monitor_params_t *p)
{
    return (float)p->decimation * p->Ts_s;
}

mc_status_t mc_emf_monitor_init_f32(mc_emf_monitor_f32_t *m,
                                    const mc_emf_monitor_params_t *p)
{
    const float f[] = { p->R_ohm, p->L_H, p->psi_Wb, p->Ts_s, p->filter_s };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    const float T_step = step_period_s(p);
    if (p->R_ohm < 0.0f || !(p->L_H > 0.0f) || !(p->psi_Wb > 0.0f) ||
        !(p->Ts_s > 0.0f) || p->decimation < 1u ||
        p->decimation > MC_EMF_DECIMATION_MAX || !(p->filter_s >= T_step)) {
        return MC_ERR_PARAM;
    }
    *m = (mc_emf_monitor_f32_t){
        .R_ohm = p->R_ohm,
        .L_over_Ts_ohm = p->L_H / p->Ts_s,
        .psi_Wb = p->psi_Wb,
        .half_Ts_s = 0.5f * p->Ts_s,
        .lpf_a = T_step / (T_step + p->filter_s),
    };
    return MC_OK;
}

void mc_emf_monitor_reset_f32(mc_emf_monitor_f32_t *m)
{
    m->have_prev = false;
    m->e_meas_V[0] = 0.0f;
    m->e_meas_V[1] = 0.0f;
    m->e_pred_V[0] = 0.0f;
    m->e_pred_V[1] = 0.0f;
}

/* The step, inlined into each check (one call per ISR, not two). */
MC_STATIC_FORCEINLINE void step(mc_emf_monitor_f32_t *m, float i_alpha_A,
                                float i_beta_A, float v_alpha_V, float v_beta_V,
                                float sin_theta_e, float cos_theta_e,
                                float omega_e_rad_s)
{
    if (m->have_prev) {
        const float e_al = v_alpha_V -
                           m->R_ohm * 0.5f * (i_alpha_A + m->i_al_prev_A) -
                           m->L_over_Ts_ohm * (i_alpha_A - m->i_al_prev_A);
        const float e_be = v_beta_V -
                           m->R_ohm * 0.5f * (i_beta_A + m->i_be_prev_A) -
                           m->L_over_Ts_ohm * (i_beta_A - m->i_be_prev_A);
        const float delta = omega_e_rad_s * m->half_Ts_s;
        const float s = sin_theta_e - delta * cos_theta_e;
        const float c = cos_theta_e + delta * sin_theta_e;
        const float mag = m->psi_Wb * omega_e_rad_s;
        const float a = m->lpf_a;
        m->e_meas_V[0] += a * (e_al - m->e_meas_V[0]);
        m->e_meas_V[1] += a * (e_be - m->e_meas_V[1]);
        m->e_pred_V[0] += a * (-mag * s - m->e_pred_V[0]);
        m->e_pred_V[1] += a * (mag * c - m->e_pred_V[1]);
    }
    m->i_al_prev_A = i_alpha_A;
    m->i_be_prev_A = i_beta_A;
    m->have_prev = true;
}

void mc_emf_monitor_step_f32(mc_emf_monitor_f32_t *m, float i_alpha_A,
                             float i_beta_A, float v_alpha_V, float v_beta_V,
                             float sin_theta_e, float cos_theta_e,
                             float omega_e_rad_s)
{
    step(m, i_alpha_A, i_beta_A, v_alpha_V, v_beta_V, sin_theta_e, cos_theta_e,
         omega_e_rad_s);
}

/* Largest check time in steps (the counter saturates there). */
#define MC_EMF_CHECK_SAMPLES_MAX 1000000.0f
#define MC_EMF_FILTER_MAX_S      1.0f

mc_status_t mc_emf_check_init_f32(mc_emf_check_f32_t *chk,
                                  const mc_emf_check_config_t *c,
                                  const mc_emf_monitor_params_t *p)
{
    const float f[] = { c->filter_s,          c->check_time_s,  c->min_V,
                        c->min_speed_e_rad_s, c->angle_max_rad, c->ratio_low,
                        c->ratio_high };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (!(c->filter_s <= MC_EMF_FILTER_MAX_S) || !(c->check_time_s > 0.0f) ||
        !(c->min_V > 0.0f) || !(c->min_speed_e_rad_s > 0.0f) ||
        !(c->angle_max_rad > 0.0f) || c->angle_max_rad > 0.5f * MC_PI_F ||
        !(c->ratio_low > 0.0f) || !(c->ratio_low < 1.0f) ||
        !(c->ratio_high > 1.0f)) {
        return MC_ERR_PARAM;
    }
    mc_emf_monitor_params_t mp = *p;
    mp.filter_s = c->filter_s;
    mc_emf_check_f32_t k = { 0 };
    const mc_status_t st = mc_emf_monitor_init_f32(&k.mon, &mp);
    if (st != MC_OK) {
        return st;
    }
    const float n = c->check_time_s / step_period_s(p); /* > 0 checked */
    if (!(n >= 1.0f) || n > MC_EMF_CHECK_SAMPLES_MAX) {
        return MC_ERR_PARAM;
    }
    float s;
    float co;
    mc_sincos_f32(c->angle_max_rad, &s, &co);
    k.e_min_sq_V2 = c->min_V * c->min_V;
    k.cos_max = co;
    k.ratio_low_sq = c->ratio_low * c->ratio_low;
    k.ratio_high_sq = c->ratio_high * c->ratio_high;
    k.min_speed_e_rad_s = c->min_speed_e_rad_s;
    k.n_required = (uint32_t)(n + 0.5f);
    *chk = k;
    return MC_OK;
}

void mc_emf_check_reset_f32(mc_emf_check_f32_t *chk)
{
    mc_emf_monitor_reset_f32(&chk->mon);
    chk->count = 0u;
}

/* The condition held this sample: count it; true once it held n samples. */
static bool persist(mc_emf_check_f32_t *chk, bool condition)
{
    if (!condition) {
        chk->count = 0u;
        return false;
    }
    if (chk->count < chk->n_required) {
        chk->count++;
    }
    return chk->count >= chk->n_required;
}

/* The measured back-EMF's angle is off the estimate's by more than
 * angle_max (a slip, an observer out of lock), the estimate turning. */
static bool slipped(const mc_emf_check_f32_t *chk, float omega_e_rad_s)
{
    return fabsf(omega_e_rad_s) > chk->min_speed_e_rad_s &&
           mc_emf_monitor_angle_exceeds_f32(&chk->mon, chk->cos_max,
                                            chk->e_min_sq_V2);
}

bool mc_emf_check_encoder_f32(mc_emf_check_f32_t *chk, float i_alpha_A,
                              float i_beta_A, float v_alpha_V, float v_beta_V,
                              float sin_theta_e, float cos_theta_e,
                              float omega_e_rad_s)
{
    step(&chk->mon, i_alpha_A, i_beta_A, v_alpha_V, v_beta_V, sin_theta_e,
         cos_theta_e, omega_e_rad_s);
    const mc_emf_monitor_f32_t *m = &chk->mon;
    const bool frozen =
        mc_emf_monitor_meas_sq_f32(m) >
        chk->ratio_high_sq * mc_emf_monitor_pred_sq_f32(m) + chk->e_min_sq_V2;
    return persist(chk, slipped(chk, omega_e_rad_s) || frozen);
}

bool mc_emf_check_sensorless_f32(mc_emf_check_f32_t *chk, float i_alpha_A,
                                 float i_beta_A, float v_alpha_V,
                                 float v_beta_V, float sin_theta_e,
                                 float cos_theta_e, float omega_e_rad_s)
{
    step(&chk->mon, i_alpha_A, i_beta_A, v_alpha_V, v_beta_V, sin_theta_e,
         cos_theta_e, omega_e_rad_s);
    const mc_emf_monitor_f32_t *m = &chk->mon;
    const bool stalled = fabsf(omega_e_rad_s) > chk->min_speed_e_rad_s &&
                         mc_emf_monitor_meas_sq_f32(m) <
                             chk->ratio_low_sq * mc_emf_monitor_pred_sq_f32(m);
    return persist(chk, stalled || slipped(chk, omega_e_rad_s));
}
