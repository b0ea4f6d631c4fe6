/* Rotor alignment with active damping and a settle check (mc/align.h). */
#include "mc/align.h"

#include <math.h>

#include "mc/angle.h"
#include "mc/clamp.h"
#include "mc/finite.h"
#include "mc/park.h"

#define MC_ALIGN_ZETA_MAX 10.0f
/* Speed-filter time constant in units of 1 / omega_n. */
#define MC_ALIGN_LPF_TAU_OMEGA_N 0.1f
/* Phase 1 only has to leave the rotor well away from phase 2's dead
 * point: a 10x looser speed threshold (|sin(delta)| bound 10x larger). */
#define MC_ALIGN_PHASE1_SPEED_FACTOR 10.0f
/* Largest sample count of the whole alignment (timeout_s / Ts_s; ramp and
 * settle are shorter): the counts are rounded into uint32_t, so anything
 * beyond would wrap to a wrong, shorter timeout. 2^30 (15 h at 20 kHz). */
#define MC_ALIGN_COUNT_MAX 1073741824.0f

static bool params_ok(const mc_align_params_t *p)
{
    const mc_align_config_t *c = &p->cfg;
    return c->current_A > 0.0f && c->timeout_s > 0.0f &&
           c->timeout_s <= MC_ALIGN_TIMEOUT_MAX_S && c->ramp_s >= 0.0f &&
           c->ramp_s <= c->timeout_s && fabsf(c->angle_e_rad) <= MC_TWO_PI_F &&
           c->damping_ratio > 0.0f && c->damping_ratio <= MC_ALIGN_ZETA_MAX &&
           c->i_q_max_A > 0.0f && c->settle_speed_e_rad_s > 0.0f &&
           c->settle_time_s >= p->Ts_s && c->settle_time_s < c->timeout_s &&
           p->R_ohm >= 0.0f && p->L_H > 0.0f && p->psi_Wb > 0.0f &&
           p->J_kgm2 > 0.0f && p->kt_Nm_per_A > 0.0f && p->pole_pairs >= 1u &&
           p->Ts_s > 0.0f;
}

mc_status_t mc_align_init_f32(mc_align_f32_t *a, const mc_align_params_t *p)
{
    const mc_align_config_t *c = &p->cfg;
    const float f[] = {
        c->current_A,
        c->ramp_s,
        c->timeout_s,
        c->angle_e_rad,
        c->damping_ratio,
        c->i_q_max_A,
        c->settle_speed_e_rad_s,
        c->settle_time_s,
        p->R_ohm,
        p->L_H,
        p->psi_Wb,
        p->J_kgm2,
        p->kt_Nm_per_A,
        p->Ts_s,
    };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (!params_ok(p) ||
        !(c->timeout_s / p->Ts_s <= MC_ALIGN_COUNT_MAX)) { /* Ts > 0 checked */
        return MC_ERR_PARAM;
    }
    const float n_p = (float)p->pole_pairs;
    /* omega_n^2 = n_p kt I_a / J > 0 (all factors checked > 0). */
    const float omega_n =
        sqrtf(n_p * p->kt_Nm_per_A * c->current_A / p->J_kgm2);
    const float tau_lpf = MC_ALIGN_LPF_TAU_OMEGA_N / omega_n;
    mc_align_f32_t d = {
        .current_A = c->current_A,
        .i_q_max_A = c->i_q_max_A,
        .k_d_A_s_per_rad = 2.0f * c->damping_ratio * omega_n * p->J_kgm2 /
                           (n_p * p->kt_Nm_per_A),
        .R_ohm = p->R_ohm,
        .L_over_Ts_ohm = p->L_H / p->Ts_s,
        .inv_psi_per_Wb = 1.0f / p->psi_Wb,
        .lpf_a = p->Ts_s / (p->Ts_s + tau_lpf),
        .settle_speed_e_rad_s = c->settle_speed_e_rad_s,
        .ramp_n = (uint32_t)lroundf(c->ramp_s / p->Ts_s),
        .timeout_n = (uint32_t)lroundf(c->timeout_s / p->Ts_s),
        .settle_n = (uint32_t)lroundf(c->settle_time_s / p->Ts_s),
    };
    const float th[2] = { c->angle_e_rad + 0.5f * MC_PI_F, c->angle_e_rad };
    for (uint32_t k = 0u; k < 2u; ++k) {
        d.theta_e_rad[k] = mc_wrap_pi_f32(th[k]);
        mc_sincos_f32(d.theta_e_rad[k], &d.sin_e[k], &d.cos_e[k]);
    }
    const float g[] = { d.k_d_A_s_per_rad, d.L_over_Ts_ohm, d.lpf_a,
                        d.inv_psi_per_Wb };
    if (!mc_all_finite_f32(g, 4u) || d.timeout_n < 1u || d.settle_n < 1u) {
        return MC_ERR_PARAM; /* extreme but finite inputs */
    }
    *a = d;
    mc_align_reset_f32(a);
    return MC_OK;
}

void mc_align_reset_f32(mc_align_f32_t *a)
{
    a->phase = 0u;
    a->n_total = 0u;
    a->n_phase = 0u;
    a->n_settled = 0u;
    a->i_al_prev_A = 0.0f;
    a->i_be_prev_A = 0.0f;
    a->have_prev = false;
    a->omega_e_hat_rad_s = 0.0f;
    a->state = MC_ALIGN_BUSY;
}

/* Settle bookkeeping after a sample of the current phase. */
static void advance(mc_align_f32_t *a)
{
    a->n_total++;
    a->n_phase++;
    const bool ramping = (a->phase == 0u && a->n_phase < a->ramp_n);
    const float w_th = (a->phase == 0u) ? MC_ALIGN_PHASE1_SPEED_FACTOR *
                                              a->settle_speed_e_rad_s
                                        : a->settle_speed_e_rad_s;
    if (!ramping && fabsf(a->omega_e_hat_rad_s) < w_th) {
        a->n_settled++;
    } else {
        a->n_settled = 0u;
    }
    if (a->n_settled >= a->settle_n) {
        if (a->phase == 0u) {
            a->phase = 1u;
            a->n_phase = 0u;
            a->n_settled = 0u;
        } else {
            a->state = MC_ALIGN_DONE;
            return;
        }
    }
    if (a->n_total >= a->timeout_n) {
        a->state = MC_ALIGN_TIMEOUT;
    }
}

mc_status_t mc_align_step_f32(mc_align_f32_t *a, float i_alpha_A,
                              float i_beta_A, float v_alpha_V, float v_beta_V,
                              mc_align_out_t *out)
{
    const float in[] = { i_alpha_A, i_beta_A, v_alpha_V, v_beta_V };
    if (!mc_all_finite_f32(in, 4u)) {
        return MC_ERR_NONFINITE;
    }
    const uint32_t ph = a->phase;
    const float s = a->sin_e[ph];
    const float c = a->cos_e[ph];
    float i_d;
    float i_q;
    float i_d_prev;
    float i_q_prev;
    float v_d;
    float v_q;
    mc_park_f32(i_alpha_A, i_beta_A, s, c, &i_d, &i_q);
    mc_park_f32(a->i_al_prev_A, a->i_be_prev_A, s, c, &i_d_prev, &i_q_prev);
    mc_park_f32(v_alpha_V, v_beta_V, s, c, &v_d, &v_q);
    (void)i_d;
    (void)i_d_prev;
    float w = a->omega_e_hat_rad_s;
    if (a->have_prev) {
        const float e_q = v_q - a->R_ohm * 0.5f * (i_q + i_q_prev) -
                          a->L_over_Ts_ohm * (i_q - i_q_prev);
        w += a->lpf_a * (e_q * a->inv_psi_per_Wb - w);
    }
    if (!isfinite(w)) {
        return MC_ERR_NONFINITE;
    }
    a->omega_e_hat_rad_s = w;
    a->i_al_prev_A = i_alpha_A;
    a->i_be_prev_A = i_beta_A;
    a->have_prev = true;

    float ramp = 1.0f;
    if (ph == 0u && a->n_phase < a->ramp_n) {
        ramp = (float)(a->n_phase + 1u) / (float)a->ramp_n; /* ramp_n > 0 */
    }
    const float i_q_ref =
        mc_clamp_sym_f32(-a->k_d_A_s_per_rad * w, a->i_q_max_A);
    if (a->state == MC_ALIGN_BUSY) {
        advance(a);
    }
    out->i_d_ref_A = ramp * a->current_A;
    out->i_q_ref_A = i_q_ref;
    out->omega_e_hat_rad_s = w;
    out->state = a->state;
    return MC_OK;
}
