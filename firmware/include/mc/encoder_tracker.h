/*
 * Encoder processing: multi-turn mechanical position, electrical angle and a
 * speed estimate from an incremental encoder count.
 *
 * Position: the count difference between samples, wrapped to
 * [-cpr/2, cpr/2), is accumulated in an int64 (exact, multi-turn; the speed
 * must stay below cpr/2 counts per sample). theta_m = counts * 2 pi / cpr is
 * returned as float (resolution degrades beyond ~1e3 turns).
 *
 * Speed: a second-order angle-tracking PLL on the single-turn angle,
 *   e = wrap_pi(theta_meas - theta_hat)
 *   omega_hat += ki * Ts * e
 *   theta_hat = wrap_pi(theta_hat + Ts * (omega_hat + kp * e))
 * with kp = 2 w_pll, ki = w_pll^2 (critically damped double pole at -w_pll):
 * a ramp in position is tracked with zero steady-state speed error, the
 * encoder quantization is filtered with bandwidth ~w_pll. The difference +
 * low-pass alternative would have a ramp lag; the PLL has none.
 *
 * Electrical angle: theta_e = wrap_pi(n_p * theta_m_single_turn + offset_e),
 * taken from the measured count (no PLL lag).
 *
 * Plausibility: a count step larger than step_speed_max Ts (rounded up,
 * plus one count of quantization) is a jump no rotor below step_speed_max
 * makes: a slip, a glitch. The tracker follows it (position and PLL angle
 * jump with it, the speed estimate is kept) and flags it in that sample
 * only, so the fault it causes can be cleared.
 *
 * Quantization: a count c means the shaft is in [c, c+1) counts (the
 * encoder floors), so the measured angle is taken at the centre,
 * (c + 0.5) * 2 pi / cpr: unbiased, error within +-pi / cpr plus the
 * float32 rounding: 2 pi / cpr to 2^-24 relative (3.7e-7 rad over a turn),
 * the product to half an ulp (2.4e-7 rad), the wrap (1.2e-7 rad), at most
 * 7.3e-7 rad, under one count up to the largest cpr (2^23, where a count is
 * 7.5e-7 rad; measured over the counts of 2^20 to 2^23: 4.2e-7 rad).
 */
#ifndef MC_ENCODER_TRACKER_H
#define MC_ENCODER_TRACKER_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/status.h"

/* Counts per revolution: at least 4; at most 2^23, the largest count for
 * which count + 0.5 is exact in float32 (the angle is (count + 0.5) 2 pi /
 * cpr). */
#define MC_ENCODER_CPR_MIN 4u
#define MC_ENCODER_CPR_MAX (1u << 23)
/* Largest w_pll Ts: the discrete PLL stays well damped. */
#define MC_ENCODER_PLL_WTS_MAX 0.5f

typedef struct {
    uint32_t cpr;
    uint32_t pole_pairs;
    /* the electrical angle in counts: count_e = n_p count mod cpr, less
     * cpr from e_upper on, plus e_origin = n_p / 2 + offset / (2 pi /
     * cpr), with the offset wrapped to (-pi, pi]: within (-cpr/2, cpr/2]
     * up to rounding */
    float e_origin_counts;
    uint32_t e_upper;
    float rad_per_count;
    uint32_t step_max_counts; /* largest plausible count step */
    float kp_per_s;           /* 2 w_pll */
    float ki_Ts_per_s;        /* ki Ts = w_pll^2 Ts (per-sample gain) */
    float Ts_s;
    /* state */
    bool primed;
    uint32_t last_count;
    int64_t position_counts;
    float theta_hat_rad;   /* PLL angle, single turn, (-pi, pi]*/
    float omega_hat_rad_s; /* PLL speed, mechanical */
} mc_encoder_tracker_f32_t;

typedef struct {
    float theta_m_rad;   /* multi-turn mechanical position */
    float theta_e_rad;   /* electrical angle in (-pi, pi] */
    float d_theta_e_rad; /* its change since the last sample, n_p times the
                            count difference times 2 pi / cpr (not wrapped;
                            0 on the priming sample) */
    float omega_m_rad_s; /* mechanical speed estimate */
    bool count_jump;     /* the count stepped more than step_max_counts */
} mc_encoder_estimate_t;

/* cpr in [MC_ENCODER_CPR_MIN, MC_ENCODER_CPR_MAX], pole_pairs in [1, 64],
 * |offset_e_rad| <= 2 pi, w_pll_rad_s > 0, Ts_s > 0,
 * w_pll * Ts <= MC_ENCODER_PLL_WTS_MAX, step_speed_max_rad_s > 0 with
 * step_speed_max * Ts < pi (half a turn per sample): MC_ERR_PARAM otherwise
 * (MC_ERR_NONFINITE for NaN/Inf). The first update primes the tracker:
 * multi-turn position starts at that count's angle within the first turn, speed
 * at 0. Interrupt context: no. */
mc_status_t mc_encoder_tracker_init_f32(mc_encoder_tracker_f32_t *et,
                                        uint32_t cpr, uint32_t pole_pairs,
                                        float offset_e_rad, float w_pll_rad_s,
                                        float step_speed_max_rad_s, float Ts_s);

/* (float)x of a count, through the 32-bit conversion while x fits (the
 * same float: both round the same integer to nearest; the 64-bit one is a
 * library call on the M4). Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_encoder_counts_to_f32(int64_t x)
{
    return MC_LIKELY(x == (int64_t)(int32_t)x) ? (float)(int32_t)x : (float)x;
}

/* One sample: count in [0, cpr) (MC_ERR_RANGE otherwise, state unchanged,
 * *out untouched). The count may move by less than cpr/2 between samples.
 * Interrupt context: yes (bounded). */
mc_status_t mc_encoder_tracker_update_f32(mc_encoder_tracker_f32_t *et,
                                          uint32_t count,
                                          mc_encoder_estimate_t *out);

/* mc_encoder_tracker_update_f32 inline, for the estimator's step. The
 * angles are reduced in integers, so that they are in [-pi, pi] up to a
 * rounding, then wrapped by mc_wrap_pi_near_f32 (mc_wrap_pi_f32's
 * results): the measured angle (count + 1/2) 2 pi / cpr, from the count
 * less cpr in the upper half of the turn; the electrical angle, from n_p
 * count mod cpr (n_p cpr <= 2^29: exact) and the offset (see e_origin);
 * the PLL's error, a difference of two wrapped angles. Interrupt context:
 * yes (bounded). */
MC_STATIC_FORCEINLINE mc_status_t mc_encoder_tracker_update_inline_f32(
    mc_encoder_tracker_f32_t *et, uint32_t count, mc_encoder_estimate_t *out)
{
    if (count >= et->cpr) {
        return MC_ERR_RANGE;
    }
    /* Centre of the count's interval, single turn, in [-pi, pi] (up to
     * the product's rounding): the upper half of the turn from -cpr. */
    const int32_t count_c = (2u * count + 1u > et->cpr)
                                ? (int32_t)count - (int32_t)et->cpr
                                : (int32_t)count;
    const float theta_meas = ((float)count_c + 0.5f) * et->rad_per_count;
    if (!et->primed) {
        et->primed = true;
        et->last_count = count;
        et->position_counts = (int64_t)count;
        et->theta_hat_rad = theta_meas;
        et->omega_hat_rad_s = 0.0f;
    }
    /* Multi-turn position: count difference wrapped to [-cpr/2, cpr/2)
     * (counts below cpr <= 2^23: 32 bits suffice). */
    int32_t delta = (int32_t)count - (int32_t)et->last_count;
    const int32_t half = (int32_t)(et->cpr / 2u);
    if (MC_UNLIKELY(delta >= half)) {
        delta -= (int32_t)et->cpr;
    } else if (MC_UNLIKELY(delta < -half)) {
        delta += (int32_t)et->cpr;
    }
    et->position_counts += delta;
    et->last_count = count;
    const uint32_t step = (uint32_t)(delta < 0 ? -delta : delta);
    out->count_jump = step > et->step_max_counts;
    if (MC_UNLIKELY(out->count_jump)) {
        et->theta_hat_rad = theta_meas; /* follow it (header) */
    }

    /* Angle-tracking PLL (header): speed = integral branch. */
    const float e = mc_angle_diff_near_f32(theta_meas, et->theta_hat_rad);
    et->omega_hat_rad_s += et->ki_Ts_per_s * e;
    et->theta_hat_rad = mc_wrap_pi_near_f32(
        et->theta_hat_rad +
        et->Ts_s * (et->omega_hat_rad_s + et->kp_per_s * e));

    out->theta_m_rad = (mc_encoder_counts_to_f32(et->position_counts) + 0.5f) *
                       et->rad_per_count;
    /* the electrical angle of the count's centre, n_p (count + 1/2) 2 pi
     * / cpr + offset, its whole turns taken off in integers */
    const uint32_t count_e = (count * et->pole_pairs) % et->cpr;
    const int32_t count_e_c = (count_e >= et->e_upper)
                                  ? (int32_t)count_e - (int32_t)et->cpr
                                  : (int32_t)count_e;
    out->theta_e_rad = mc_wrap_pi_near_f32(
        ((float)count_e_c + et->e_origin_counts) * et->rad_per_count);
    /* n_p |delta| < n_p cpr / 2 <= 2^28: exact in int32 */
    out->d_theta_e_rad =
        (float)(delta * (int32_t)et->pole_pairs) * et->rad_per_count;
    out->omega_m_rad_s = et->omega_hat_rad_s;
    return MC_OK;
}

#endif /* MC_ENCODER_TRACKER_H */
