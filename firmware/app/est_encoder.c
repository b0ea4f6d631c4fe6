/* Estimator "encoder" (mc/est_encoder.h). */
#include "mc/est_encoder.h"

#include <math.h>

#include "mc/config.h"

const mc_param_t mc_est_encoder_params[] = {
    MC_PARAM(mc_est_encoder_config_t, counts_per_rev, MC_PARAM_U32),
    MC_PARAM(mc_est_encoder_config_t, offset_e_rad, MC_PARAM_F32),
    MC_PARAM(mc_est_encoder_config_t, pll_bandwidth_rad_s, MC_PARAM_F32),
    MC_PARAM_END,
};

void mc_est_encoder_config_default(mc_est_encoder_config_t *c)
{
    /* 2500-line encoder (x4), aligned: count 0 at theta_e = 0; PLL at 20x
     * the default speed loop (lag 2/w_pll = 2 ms). */
    *c = (mc_est_encoder_config_t){
        .counts_per_rev = 10000u,
        .offset_e_rad = 0.0f,
        .pll_bandwidth_rad_s = 1000.0f,
    };
}

mc_estimator_info_t mc_est_encoder_info(const mc_config_t *cfg)
{
    return (mc_estimator_info_t){
        .speed_bandwidth_rad_s = cfg->encoder.pll_bandwidth_rad_s,
        .encoder_cpr = cfg->encoder.counts_per_rev,
    };
}

mc_status_t mc_est_encoder_init(mc_est_encoder_t *est, const mc_config_t *cfg,
                                const mc_timing_t *tm)
{
    /* A plausible count step: at most twice the overspeed trip (the trip
     * comes first; the rotor cannot double its speed within the PLL lag),
     * under half a turn per sample (mc/encoder_tracker.h). */
    const mc_est_encoder_config_t *c = &cfg->encoder;
    /* no sample yet: a rotation before the first step gives NaN (a
     * fault), never an angle of zero */
    est->sc_last = (mc_est_sincos_t){ .sin_e = NAN, .cos_e = NAN };
    return mc_encoder_tracker_init_f32(
        &est->tracker, c->counts_per_rev, cfg->motor.pole_pairs,
        c->offset_e_rad, c->pll_bandwidth_rad_s,
        2.0f * cfg->protection.overspeed_rad_s, tm->Ts_s);
}

void mc_est_encoder_hold(mc_est_encoder_t *est, float theta_e_rad)
{
    (void)est; /* the encoder never needs an alignment */
    (void)theta_e_rad;
}

uint32_t mc_est_encoder_start(mc_est_encoder_t *est, float theta_e_rad,
                              const mc_est_input_t *in)
{
    (void)est;
    (void)theta_e_rad;
    (void)in;
    return MC_FAULT_NONE;
}
