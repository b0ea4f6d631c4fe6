/*
 * Paper 001 sensorless scheme: the firmware's float32 observers against an
 * independent DOUBLE-precision implementation of the paper's observers
 * (p001_double_reference.h: flux observer (12)-(14) with atan2, speed/load
 * observer (15)-(16) in the paper's original xi / unwrapped-angle form) on
 * the nominal Section 5.1 benchmark (test_p001_bench.h, IDA-PBC, delay
 * compensation on).
 *
 * Project requirement: float32 equals double within 0.01 rpm on the
 * benchmark.
 *
 * OPEN-LOOP REPLAY of the closed-loop trajectory: the firmware (float32)
 * drives the plant; the double observers only listen. At every PWM period
 * after the alignment they get the same inputs as the firmware's
 * observers (mc/est_flux_front.h, mc/est_flux_ii.h, firmware/app/fast_isr.c):
 *   - currents: the ISR's offset-corrected i_abc (telemetry), Clarke
 *     (amplitude-invariant, three inputs) done here in double;
 *   - voltage: the mean applied alpha-beta voltage over [t_{k-1}, t_k] as
 *     the firmware forms it (mc_applied_voltage_last_f32, read BEFORE this
 *     ISR pushes its command): v_bar_k = w v_{k-2} + (1 - w) v_{k-1},
 *     w = d - 1/2 with d the delay of the firmware's timing record (the
 *     HAL's, 1.5 on this bench), v_j the telemetry v_alpha/beta_V of ISR j
 *     (the alignment ISRs included: they precede the first RUN sample);
 *   - I&I input: the trapezoid 0.5 (i_q,k + i_q,k-1) of i^T Jcal rho_hat,
 *     each computed with the (double) observer's own rho_hat at that
 *     sample, as the firmware does with its float one;
 *   - start: in the last ALIGN ISR (the first whose telemetry says RUN) the
 *     firmware resets the flux observer at align.angle_e_rad with that
 *     ISR's currents, the speed observer at that angle with zero speed and
 *     load, and i_q,prev from the reset rho_hat; the double observers are
 *     reset in the same ISR the same way and both step from the next one.
 * Variables: the PAPER's. The firmware works in amplitude-invariant
 * variables (mc/motor.h); the reference runs (12)-(16) literally in the
 * paper's two-phase (power-invariant) ones: currents and voltages times
 * G = sqrt(3/2), Phi = G psi, kt = n_p Phi, gamma and a1, a2 as configured
 * (the firmware's flux_obs.gamma is the paper's; its observer uses
 * (3/2) gamma in its variables). Angles, speeds and torques are the same
 * in both, so they are compared directly: the comparison also checks the
 * firmware's conversion.
 * Parameters: the firmware configuration's (float) values, promoted to
 * double; Ts = 1 / f_pwm in double.
 * The delay d and the firmware's float period come from the timing record
 * of the engine the replay listens to (mc_app_timing(): what the HAL
 * reported), read at its first step.
 *
 * The per-period hook: bench_run() (the shared runner, reused unchanged)
 * calls sim_engine_step(); this executable is linked with
 * -Wl,--wrap=sim_engine_step, so every step of the benchmark goes through
 * __wrap_sim_engine_step below, which steps the engine and then replays
 * the sample.
 *
 * Assertions (after the alignment, over the whole benchmark):
 *   |omega_hat_float - omega_hat_double| <= 0.01 rpm   (the requirement)
 *   |theta_hat_float - theta_hat_double| (wrapped) <= a worst-case
 *     float32 rounding bound (derived below; loose)
 * and reports max |tau_hat_float - tau_hat_double| (no useful
 * epsilon-derived bound, see below); no fault; the double
 * observer's own tracking of the true plant (sanity that the replay is
 * aligned: a one-period voltage misalignment shows up as a mrad angle
 * offset).
 */
#include "mc_test.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <time.h>

#include "p001_double_reference.h"
#include "test_p001_bench.h"

/* The requirement. */
#define SPEED_BOUND_RPM 0.01

/*
 * Angle: worst-case bound from float32 rounding (eps = 2^-24), computed
 * by angle_bound_rad() from the run itself. Both observers get identical
 * inputs, so their difference evolves with the observer's error map plus
 * the float32 injections. In the stationary frame the true flux increments
 * cancel in that map and what is left is the gradient term, whose
 * Jacobian I - 2 Ts gamma Phi^2 rho rho^T (near the circle) contracts the
 * radial part and leaves the tangential (angle) part unchanged: the map is
 * non-expansive, so injected errors can at most add up. Per sample:
 *   - the rounding of lambda_k (|lambda| < 0.25 Wb, ulp 2^-26): at most
 *     2^-27 per component, plus that of the increment (< 8 eps of
 *     Ts (|v| + |R i| + ...), < 2e-9 Wb with |v| <= 48 V): per component
 *     LAMBDA_ROUND_WB, |vector| <= sqrt(2) LAMBDA_ROUND_WB, as an angle
 *     / (0.99 Phi) (rho_sq stays within 1 % of 1 here);
 *   - Ts itself: float(1/20 kHz) differs from the double by a relative
 *     |Ts_f/Ts - 1|, which scales the integrated flux increments
 *     sum Ts |v_bar - R i| (accumulated in the replay);
 * not accumulated: eta = lambda - L i (one rounding, same size) and
 * mc_atan2_f32 (<= MC_ATAN2_MAX_ERR_RAD = 1e-6 rad).
 * This is a true worst case (every rounding aligned with the tangent every
 * sample) and is loose; it only catches gross float-specific errors. The
 * measured value is printed next to it.
 */
#define LAMBDA_ROUND_WB       (7.4506e-9 + 2.0e-9)
#define ATAN2_F32_MAX_ERR_RAD 1.0e-6

/*
 * Load estimate: no bound derived from float32 epsilon that is tighter
 * than useless (tau_hat responds to angle differences through -a2 s^2 /
 * (s^2 + n_p a1 s + n_p a2 / J), feedthrough a2 = 6 N m/rad, so the angle
 * worst case above would give ~0.1 N m); reported, not asserted.
 */

typedef struct {
    const mc_config_t *fc;
    bool have_timing;     /* w_older, Ts_f_s read from the engine */
    double delay_periods; /* the firmware's d (its timing record) */
    double w_older;       /* d - 1/2 */
    double Ts_f_s;        /* the firmware's (float) period */
    double v_older[2];    /* telemetry voltage of ISR k-2 */
    double v_newer[2];    /* ... of ISR k-1 */
    mc_state_t prev_state;
    bool started;
    bool left_run;
    double t_start_s;
    double i_q_prev_A;
    p001d_flux_obs_t flux;
    p001d_speed_obs_t speed;
    /* float - double */
    uint64_t n;
    double max_dw_rpm, tb_max_dw;
    double max_dth_rad, tb_max_dth;
    double max_dtau_Nm, tb_max_dtau;
    double max_dth_moving_rad; /* tb < 9 s (before the standstill) */
    double sum_sq_dw_rpm;
    double flux_path_Wb; /* sum Ts |v_bar - R i|, for the Ts term */
    /* double observer vs the true plant, tb in [0.5, 8.5) */
    double max_ref_angle_err_rad;
    double max_ref_speed_err_rpm;
} replay_t;

static replay_t g_replay;
static bool g_replay_on;

static void clarke_d(const float i_abc[3], double *al, double *be)
{
    const double a = (double)i_abc[0];
    const double b = (double)i_abc[1];
    const double c = (double)i_abc[2];
    *al = (2.0 * a - b - c) / 3.0;
    *be = (b - c) / sqrt(3.0);
}

/* sqrt(3/2): the paper's currents, voltages, fluxes per firmware one */
#define PAPER_GAIN 1.2247448713915890491

static void replay_init(replay_t *r, const mc_config_t *fc)
{
    *r = (replay_t){ .fc = fc, .prev_state = MC_STATE_IDLE };
    const mc_motor_params_t *m = &fc->motor;
    const double Ts = 1.0 / (double)fc->timing.f_pwm_Hz;
    const double np = (double)m->pole_pairs;
    const double Phi = PAPER_GAIN * (double)m->psi_Wb;
    p001d_flux_obs_init(&r->flux, (double)m->R_ohm, (double)m->Lq_H, Phi,
                        (double)fc->flux_obs.gamma, Ts);
    p001d_speed_obs_init(&r->speed, (double)fc->flux_ii.a1, (double)fc->flux_ii.a2, np,
                         (double)m->J_kgm2, np * Phi, Ts);
}

/* The firmware's timing as the HAL gave it (before the first sample). */
static void replay_timing(replay_t *r, const sim_engine_t *e)
{
    r->delay_periods = (double)mc_app_timing(&e->app)->delay_periods;
    r->w_older = r->delay_periods - 0.5;
    r->Ts_f_s = (double)mc_app_timing(&e->app)->Ts_s;
    r->have_timing = true;
}

/* Worst-case float32 angle difference for this replay (see above). */
static double angle_bound_rad(const replay_t *r)
{
    const double Phi = r->flux.Phi_Wb;
    const double Ts_f = r->Ts_f_s;
    /* the firmware's lambda (its variables) against its psi = Phi / G */
    const double per_sample = sqrt(2.0) * LAMBDA_ROUND_WB / (0.99 * Phi / PAPER_GAIN);
    return (double)r->n * per_sample +
           fabs(Ts_f / r->flux.Ts_s - 1.0) * r->flux_path_Wb / (0.99 * Phi) + per_sample +
           ATAN2_F32_MAX_ERR_RAD;
}

static void replay_sample(replay_t *r, const sim_trace_sample_t *s)
{
    const mc_telemetry_t *fw = &s->fw;
    const double tb = s->t_s - BENCH_T0_S;
    double i_al;
    double i_be;
    clarke_d(fw->i_abc_A, &i_al, &i_be);
    i_al *= PAPER_GAIN; /* the paper's variables */
    i_be *= PAPER_GAIN;
    if (r->started && fw->state != MC_STATE_RUN) {
        r->left_run = true;
    }
    if (r->started && !r->left_run) {
        const double v_al = r->w_older * r->v_older[0] + (1.0 - r->w_older) * r->v_newer[0];
        const double v_be = r->w_older * r->v_older[1] + (1.0 - r->w_older) * r->v_newer[1];
        const double R = r->flux.R_ohm;
        r->flux_path_Wb += r->flux.Ts_s * hypot(v_al - R * i_al, v_be - R * i_be);
        p001d_flux_obs_step(&r->flux, i_al, i_be, v_al, v_be);
        const double i_q = p001d_flux_obs_iq(&r->flux, i_al, i_be);
        const double i_q_mean = 0.5 * (i_q + r->i_q_prev_A);
        r->i_q_prev_A = i_q;
        p001d_speed_obs_step(&r->speed, r->flux.theta_e, i_q_mean);

        const double dw = fabs((double)fw->omega_m_rad_s - r->speed.omega_m) * BENCH_RPM_PER_RAD_S;
        const double dth =
            fabs(remainder((double)fw->theta_e_rad - r->flux.theta_e, MC_TEST_TWO_PI));
        const double dtau = fabs((double)fw->tau_L_hat_Nm - r->speed.tau_L);
        r->n++;
        r->sum_sq_dw_rpm += dw * dw;
        if (dw > r->max_dw_rpm) {
            r->max_dw_rpm = dw;
            r->tb_max_dw = tb;
        }
        if (dth > r->max_dth_rad) {
            r->max_dth_rad = dth;
            r->tb_max_dth = tb;
        }
        if (tb < 9.0) {
            r->max_dth_moving_rad = fmax(r->max_dth_moving_rad, dth);
        }
        if (dtau > r->max_dtau_Nm) {
            r->max_dtau_Nm = dtau;
            r->tb_max_dtau = tb;
        }
        if (tb >= 0.5 && tb < 8.5) {
            r->max_ref_angle_err_rad =
                fmax(r->max_ref_angle_err_rad,
                     fabs(remainder(r->flux.theta_e - s->plant.theta_e_rad, MC_TEST_TWO_PI)));
            r->max_ref_speed_err_rpm =
                fmax(r->max_ref_speed_err_rpm,
                     fabs(r->speed.omega_m - s->plant.omega_m_rad_s) * BENCH_RPM_PER_RAD_S);
        }
    }
    if (!r->started && r->prev_state == MC_STATE_ALIGN && fw->state == MC_STATE_RUN) {
        /* the firmware's mc_app_sensorless_start in this ISR */
        const double th0 = remainder((double)r->fc->align.angle_e_rad, MC_TEST_TWO_PI);
        p001d_flux_obs_reset(&r->flux, th0, i_al, i_be);
        p001d_speed_obs_reset(&r->speed, r->flux.theta_e, 0.0, 0.0);
        r->i_q_prev_A = p001d_flux_obs_iq(&r->flux, i_al, i_be);
        r->started = true;
        r->t_start_s = s->t_s;
    }
    r->prev_state = fw->state;
    /* this ISR's command becomes the history of the next sample */
    r->v_older[0] = r->v_newer[0];
    r->v_older[1] = r->v_newer[1];
    r->v_newer[0] = PAPER_GAIN * (double)fw->v_alpha_V;
    r->v_newer[1] = PAPER_GAIN * (double)fw->v_beta_V;
}

int __real_sim_engine_step(sim_engine_t *e, const mc_command_t *cmd);
int __wrap_sim_engine_step(sim_engine_t *e, const mc_command_t *cmd);

int __wrap_sim_engine_step(sim_engine_t *e, const mc_command_t *cmd)
{
    if (g_replay_on && !g_replay.have_timing) {
        replay_timing(&g_replay, e);
    }
    const int rc = __real_sim_engine_step(e, cmd);
    if (rc == SIM_ENGINE_OK && g_replay_on) {
        replay_sample(&g_replay, sim_engine_last(e));
    }
    return rc;
}

/* The operator A of the reference: continuous through +-pi both ways. */
static void test_unwrap_operator(void **state)
{
    (void)state;
    p001d_unwrap_t u;
    const double step = 0.3;
    for (int dir = -1; dir <= 1; dir += 2) {
        double truth = 3.0 * (double)dir;
        p001d_unwrap_reset(&u, truth);
        for (int k = 0; k < 100; ++k) {
            truth += step * (double)dir;
            const double y = p001d_unwrap_step(&u, remainder(truth, MC_TEST_TWO_PI));
            assert_true(fabs(y - truth) < 1e-12);
        }
    }
}

static void test_float_equals_double_on_benchmark(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    /* The replay's alignment check below compares the observers with the
     * true angle from the start: with ideal sensors the alignment can
     * settle far tighter than the default (set for noisy sensors, 6.5e-3
     * rad): 0.002 electrical rad/s for 50 ms, 2.1e-4 rad (mc/align.h). */
    fc.align.settle_speed_e_rad_s = 0.002f;
    fc.align.settle_time_s = 0.05f;
    replay_init(&g_replay, &fc);
    g_replay_on = true;
    const clock_t c0 = clock();
    const bench_result_t res = bench_run(&pc, &fc, "float vs double");
    const double cpu_s = (double)(clock() - c0) / CLOCKS_PER_SEC;
    g_replay_on = false;
    const replay_t *r = &g_replay;

    printf("[float vs double] replay from t = %.4f s (tb %.4f s), %llu "
           "samples, %.2f s CPU; firmware delay %.2f periods (from the HAL)\n",
           r->t_start_s, r->t_start_s - BENCH_T0_S, (unsigned long long)r->n, cpu_s,
           r->delay_periods);
    printf("[float vs double] max |w_f - w_d| = %.3e rpm (tb %.4f s), RMS "
           "%.3e rpm (bound %.3g rpm)\n",
           r->max_dw_rpm, r->tb_max_dw, (r->n > 0u) ? sqrt(r->sum_sq_dw_rpm / (double)r->n) : NAN,
           SPEED_BOUND_RPM);
    const double th_bound = angle_bound_rad(r);
    printf("[float vs double] max |theta_f - theta_d| = %.3e rad (tb %.4f "
           "s) (float32 worst case %.3g rad)\n",
           r->max_dth_rad, r->tb_max_dth, th_bound);
    printf("[float vs double] max |theta_f - theta_d| before the standstill "
           "(tb < 9 s) = %.3e rad\n",
           r->max_dth_moving_rad);
    printf("[float vs double] max |tau_f - tau_d| = %.3e N m (tb %.4f s) "
           "(reported)\n",
           r->max_dtau_Nm, r->tb_max_dtau);
    printf("[float vs double] double reference vs plant, tb 0.5-8.5 s: max "
           "angle err %.3e rad, max speed err %.3e rpm\n",
           r->max_ref_angle_err_rad, r->max_ref_speed_err_rpm);

    assert_int_equal(res.faults, 0u);
    /* the bench's next-period duty update: the HAL reports 1.5 periods */
    assert_true(r->have_timing);
    assert_true(r->delay_periods == (double)SIM_ENGINE_DELAY_NEXT_PERIOD);
    assert_true(r->started);
    assert_false(r->left_run);
    /* the replay covers the whole benchmark: RUN from before tb = 0 */
    assert_true(r->t_start_s <= BENCH_T0_S);
    assert_true((double)r->n * (1.0 / (double)fc.timing.f_pwm_Hz) >= BENCH_LENGTH_S);
    /* The double observer tracks the true plant: the replay is aligned.
     * Nominal parameters, ideal sensors and the exact mean voltage leave
     * only discretisation error (trapezoidal R i: ~R Ts^3 |i''| / 12 =
     * 5e-12 Wb per sample, < 1e-5 rad over the run) and the plant
     * solver's; 1e-4 rad keeps a wide margin and still fails a voltage
     * history shifted by half a period (measured 9.3e-4 rad). */
    assert_true(r->max_ref_angle_err_rad <= 1e-4);
    assert_true(r->max_dw_rpm <= SPEED_BOUND_RPM);
    assert_true(r->max_dth_rad <= th_bound);
    assert_true(isfinite(r->max_dtau_Nm));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unwrap_operator),
        cmocka_unit_test(test_float_equals_double_on_benchmark),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
