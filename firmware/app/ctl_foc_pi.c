/* Controller "foc_pi": the baseline cascaded FOC (mc/ctl_foc_pi.h). */
#include "mc/ctl_foc_pi.h"

#include "mc/config.h"

/* Speed loop at least 5x below the current loop, and 2x below the speed
 * estimate that feeds it. */
#define FOC_SPEED_TO_CURRENT_MAX  0.2f
#define FOC_SPEED_TO_ESTIMATE_MAX 0.5f

const mc_param_t mc_ctl_foc_pi_params[] = {
    MC_PARAM(mc_ctl_foc_pi_config_t, speed_bandwidth_rad_s, MC_PARAM_F32),
    MC_PARAM_END,
};

void mc_ctl_foc_pi_config_default(mc_ctl_foc_pi_config_t *c)
{
    /* Speed loop 8 Hz (w_s Ts_slow = 0.025 at 2 kHz). */
    *c = (mc_ctl_foc_pi_config_t){ .speed_bandwidth_rad_s = 50.0f };
}

mc_status_t mc_ctl_foc_pi_init(mc_ctl_foc_pi_t *ctl, const mc_config_t *cfg,
                               const mc_timing_t *tm,
                               const mc_estimator_info_t *est)
{
    const float w_s = cfg->foc_pi.speed_bandwidth_rad_s;
    const mc_speed_loop_params_t sp = {
        .J_kgm2 = cfg->motor.J_kgm2,
        .B_Nm_s_rad = cfg->motor.B_Nm_s_rad,
        .kt_Nm_per_A = mc_motor_kt_f32(&cfg->motor),
        .bandwidth_rad_s = w_s,
        .i_q_max_A = cfg->limits.i_max_A,
        .Ts_s = tm->Ts_slow_s,
    };
    const mc_status_t st = mc_speed_loop_init_f32(&ctl->speed, &sp);
    if (st != MC_OK) {
        return st;
    }
    const bool slower_than_estimate =
        est->speed_bandwidth_rad_s == 0.0f ||
        w_s <= FOC_SPEED_TO_ESTIMATE_MAX * est->speed_bandwidth_rad_s;
    if (w_s > FOC_SPEED_TO_CURRENT_MAX * cfg->current.bandwidth_rad_s ||
        !slower_than_estimate || cfg->position.kp_per_s > w_s) {
        return MC_ERR_PARAM;
    }
    return MC_OK;
}

void mc_ctl_foc_pi_start(mc_ctl_foc_pi_t *ctl)
{
    mc_speed_loop_reset_f32(&ctl->speed);
}

void mc_ctl_foc_pi_mode_change(mc_ctl_foc_pi_t *ctl, mc_drive_t *d,
                               mc_mode_t from, mc_mode_t to,
                               const mc_telemetry_t *t)
{
    /* The current loop runs in every mode and simply continues. */
    (void)d;
    (void)from;
    (void)to;
    (void)t;
    mc_speed_loop_reset_f32(&ctl->speed);
}
