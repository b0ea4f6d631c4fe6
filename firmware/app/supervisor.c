/* The drive's supervision of every sample (mc/supervisor.h). */
#include "mc/supervisor.h"

#include <float.h>
#include <math.h>

/* Consecutive samples of a condition; true once it held n in a row. */
static bool persist(uint32_t *count, bool condition, uint32_t n)
{
    if (!condition) {
        *count = 0u;
        return false;
    }
    if (*count < n) {
        (*count)++;
    }
    return *count >= n;
}

/* round(time / step) steps, at least one. */
static mc_status_t samples(float time_s, float step_s, uint32_t *n)
{
    const float x = roundf(time_s / step_s); /* step > 0 checked */
    if (!(x >= 1.0f) || x > 4.0e9f) {
        return MC_ERR_PARAM;
    }
    *n = (uint32_t)x;
    return MC_OK;
}

mc_status_t mc_supervisor_init(mc_supervisor_t *sv,
                               const mc_fault_limits_t *lim, float step_s)
{
    if (!(step_s > 0.0f) || !isfinite(step_s)) {
        return MC_ERR_PARAM;
    }
    mc_supervisor_t s = {
        .overspeed_rad_s = lim->overspeed_rad_s,
        .stall_current_sq_A2 = lim->stall_current_A * lim->stall_current_A,
        .stall_speed_rad_s = lim->stall_speed_rad_s,
        .i2t_cont_sq_A2 = lim->i2t_continuous_A * lim->i2t_continuous_A,
        .i2t_limit_A2s = (lim->i2t_peak_A * lim->i2t_peak_A -
                          lim->i2t_continuous_A * lim->i2t_continuous_A) *
                         lim->i2t_peak_time_s,
        .step_s = step_s,
        .sum_max_A = lim->current_sum_max_A,
    };
    mc_status_t st = samples(lim->stall_time_s, step_s, &s.stall_n);
    if (st == MC_OK) {
        st = samples(lim->current_sum_time_s, step_s, &s.sum_n);
    }
    if (st == MC_OK) {
        st = samples(lim->current_limit_time_s, step_s, &s.limit_n);
    }
    if (st == MC_OK && !(s.i2t_limit_A2s > 0.0f && isfinite(s.i2t_limit_A2s))) {
        st = MC_ERR_PARAM;
    }
    if (st == MC_OK) {
        *sv = s;
    }
    return st;
}

uint32_t mc_supervisor_step(mc_supervisor_t *sv, const mc_telemetry_t *t,
                            bool running, bool powered, bool limiting)
{
    /* The thermal model runs in every state: a stopped motor cools. */
    uint32_t faults = MC_FAULT_NONE;
    const float i_sq = t->i_d_A * t->i_d_A + t->i_q_A * t->i_q_A;
    if (i_sq < FLT_MAX) { /* a non-finite current (its own fault) does
                             not corrupt the thermal state */
        /* compensated sum (valid: the project never uses -ffast-math) */
        const float y =
            (i_sq - sv->i2t_cont_sq_A2) * sv->step_s - sv->i2t_comp_A2s;
        const float x = sv->i2t_A2s + y;
        if (x > 0.0f) {
            sv->i2t_comp_A2s = (x - sv->i2t_A2s) - y;
            sv->i2t_A2s = x;
        } else { /* cold */
            sv->i2t_comp_A2s = 0.0f;
            sv->i2t_A2s = 0.0f;
        }
    }
    if (sv->i2t_A2s > sv->i2t_limit_A2s) {
        faults |= MC_FAULT_I2T;
    }
    if (!powered) {
        sv->stall_count = 0u;
        sv->sum_count = 0u;
        sv->limit_count = 0u;
        return faults;
    }
    const float w = fabsf(t->omega_m_rad_s);
    if (w > sv->overspeed_rad_s) {
        faults |= MC_FAULT_OVERSPEED;
    }
    const bool stalled =
        running && i_sq > sv->stall_current_sq_A2 && w < sv->stall_speed_rad_s;
    if (persist(&sv->stall_count, stalled, sv->stall_n)) {
        faults |= MC_FAULT_STALL;
    }
    if (persist(&sv->limit_count, running && limiting, sv->limit_n)) {
        faults |= MC_FAULT_CURRENT_LIMIT;
    }
    const float sum = t->i_abc_A[0] + t->i_abc_A[1] + t->i_abc_A[2];
    if (persist(&sv->sum_count, !(fabsf(sum) <= sv->sum_max_A), sv->sum_n)) {
        faults |= MC_FAULT_CURRENT_SENSOR;
    }
    return faults;
}
