/* Paper 002 regulator: the internal-model list -> the observer's
 * continuous model (7). See mc/cdobc.h. */
#include "mc/cdobc.h"

#include <stddef.h>

/* frequency multiple of |omega_m| (mechanical) of harmonic i */
static uint32_t mech_multiple(const mc_cdobc_harm_t *h, uint32_t pole_pairs)
{
    return (h->axis == MC_CDOBC_ELEC) ? h->order * pole_pairs : h->order;
}

mc_status_t mc_cdobc_models_check(const mc_cdobc_models_t *m,
                                  uint32_t pole_pairs)
{
    if (m == NULL || m->n_harm > MC_CDOBC_HARM_MAX ||
        m->poly_order > MC_CDOBC_POLY_MAX ||
        (m->n_harm == 0u && m->poly_order == 0u) || pole_pairs < 1u ||
        pole_pairs > 100u) {
        return MC_ERR_PARAM;
    }
    for (uint32_t i = 0; i < m->n_harm; ++i) {
        const mc_cdobc_harm_t *h = &m->harm[i];
        if ((h->axis != MC_CDOBC_ELEC && h->axis != MC_CDOBC_MECH) ||
            h->order < 1u || h->order > 1000u ||
            !(h->zeta == 0.0f || (h->zeta > 0.0f && h->zeta < 1.0f))) {
            return MC_ERR_PARAM;
        }
        for (uint32_t j = 0; j < i; ++j) {
            if (mech_multiple(h, pole_pairs) ==
                mech_multiple(&m->harm[j], pole_pairs)) {
                return MC_ERR_PARAM; /* same frequency: unobservable */
            }
        }
    }
    return MC_OK;
}

uint32_t mc_cdobc_models_order(const mc_cdobc_models_t *m)
{
    return 1u + 2u * m->n_harm + m->poly_order;
}

void mc_cdobc_models_build(const mc_cdobc_models_t *m, uint32_t pole_pairs,
                           double omega_rad_s, double a_per_s, double *A,
                           uint32_t *level, double *h, double *w_rad_s)
{
    const uint32_t n = mc_cdobc_models_order(m);
    for (uint32_t i = 0; i < n * n; ++i) {
        A[i] = 0.0;
    }
    for (uint32_t i = 0; i < n; ++i) {
        h[i] = 0.0;
    }
    /* x2' = -a x2 + sum of the model outputs (7) */
    A[0] = -a_per_s;
    level[0] = 0u;
    uint32_t s = 1u;
    for (uint32_t i = 0; i < m->n_harm; ++i, s += 2u) {
        const double w =
            (double)mech_multiple(&m->harm[i], pole_pairs) * omega_rad_s;
        w_rad_s[i] = w;
        A[s] = 1.0;                     /* into x2' */
        A[s * n + s + 1u] = 1.0;        /* x_h' = x_h+1 */
        A[(s + 1u) * n + s] = -(w * w); /* x_h+1' = -w^2 x_h */
        level[s] = 1u;
        level[s + 1u] = 2u;
        h[s] = 1.0;
    }
    for (uint32_t j = 0; j < m->poly_order; ++j) {
        if (j == 0u) {
            A[s] = 1.0; /* x7 into x2' */
            h[s] = 1.0;
        } else {
            A[(s + j - 1u) * n + s + j] = 1.0; /* x_{6+j}' = x_{7+j} */
        }
        level[s + j] = j + 1u;
    }
}
