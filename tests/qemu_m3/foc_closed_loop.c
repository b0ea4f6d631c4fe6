/*
 * Closed loop of the M3 images: the plant (host_sim/plant, double; its
 * cost is not counted) and the bare current path of foc_m3.h, one call per
 * PWM period, each call's instructions counted (isr_meter_measure).
 *
 * Period k (t_k = k Ts), the timing of host_sim/engine with the plant's
 * default update event (PLANT_DUTY_UPDATE_NEXT_PERIOD):
 *   1. plant_sample: phase currents through the plant's 12-bit mid-tread
 *      quantiser, turned back into the ADC's offset-binary codes, and the
 *      encoder count, into the register block foc_io_t;
 *   2. foc_isr (counted);
 *   3. plant_advance over [t_k, t_k+1) with the PREVIOUS call's compare
 *      values (duty = ccr / arr): call k acts over [t_k+1, t_k+2), 1.5
 *      periods after its sample.
 *
 * Scenario (the numbers come from tests/qemu_m3/CMakeLists.txt, which
 * also computes the expectations from them): the paper-001 motor of
 * plant_config_default (checked against the numbers the expectations use;
 * the image exits 2 if they differ), ideal inverter on a stiff bus, the
 * rotor locked at theta_m0; i_q* steps 0 -> QM3_IQ_STEP_A at period
 * QM3_STEP_K; at QM3_RELEASE_K the rotor is released and i_q* becomes
 * QM3_IQ_FREE_A (no load: the rotor accelerates); the run ends after
 * QM3_END_K periods. i_d* = 0 throughout.
 *
 * Output (semihosting; run_qemu_test.py compares the CHECK lines):
 *   CHECK step_iq_n<n>_A     true i_q at t = (QM3_STEP_K + n) Ts, for each
 *                            n of QM3_CHECKPOINTS
 *   CHECK locked_max_abs_i_d_A, free_max_abs_i_d_A   true |i_d|, maximum
 *                            over the locked step / the free rotor
 *   CHECK final_i_q_A, final_omega_m_rad_s           at t = QM3_END_K Ts
 *   CHECK saturated_isrs     calls whose PI output reached its limit or
 *                            whose SVPWM reduced the command
 *   CHECK isr_count, isr_min_instr, isr_mean_instr, isr_max_instr
 */
#include <math.h>
#include <stdint.h>

#include "foc_m3.h"
#include "isr_meter.h"
#include "plant.h"
#include "qemu_m4.h"

static const uint32_t checkpoints[] = { QM3_CHECKPOINTS };
#define N_CHECKPOINTS (sizeof checkpoints / sizeof checkpoints[0])

static plant_t plant; /* ~1 kB: static, not on the stack */

static void print_value(const char *key, const char *suffix, uint32_t n, double v,
                        unsigned decimals)
{
    qemu_m4_puts("CHECK ");
    qemu_m4_puts(key);
    if (suffix != 0) {
        qemu_m4_put_u32(n);
        qemu_m4_puts(suffix);
    }
    qemu_m4_puts(" ");
    qemu_m4_put_fixed(v, decimals);
    qemu_m4_puts("\n");
}

/* A setup error (not a test result): say why, main's status 2. */
static int refuse(const char *why)
{
    qemu_m4_puts("FAIL (setup): ");
    qemu_m4_puts(why);
    qemu_m4_puts("\n");
    return 2;
}

/* The motor the expectations are computed for (paper 001). */
static int motor_as_expected(const plant_motor_params_t *m)
{
    return m->R_ohm == QM3_R_OHM && m->Ld_H == QM3_L_H && m->Lq_H == QM3_L_H &&
           m->psi_Wb == QM3_PSI_WB && m->pole_pairs == QM3_POLE_PAIRS && m->J_kgm2 == QM3_J_KGM2 &&
           m->B_Nm_s_rad == 0.0 && m->tau_coulomb_Nm == 0.0 && m->cogging.n_harmonics == 0u &&
           m->g3_amplitude_per_kgm2 == 0.0;
}

static void plant_setup(plant_config_t *pc)
{
    plant_config_default(pc);
    pc->inverter.f_pwm_Hz = QM3_F_PWM_HZ;
    pc->inverter.duty_update = PLANT_DUTY_UPDATE_NEXT_PERIOD;
    sim_profile_set_constant(&pc->inverter.v_dc_V, QM3_V_DC_V);
    pc->inverter.t_dead_s = 0.0;
    pc->inverter.v_device_drop_V = 0.0;
    pc->sensors.current.adc_bits = QM3_ADC_BITS;
    pc->sensors.current.full_scale_A = QM3_I_FS_A;
    pc->sensors.encoder.lines = QM3_ENC_LINES;
    pc->sensors.encoder.offset_rad = 0.0;
    pc->substeps_per_period = PLANT_SUBSTEPS_FAST;
    pc->locked_rotor = true;
    pc->theta_m0_rad = QM3_THETA_M0_RAD;
}

/* The ADC register of a measured current (the plant quantised it). */
static uint16_t adc_raw(double i_meas_A)
{
    const double amp_per_code = 2.0 * QM3_I_FS_A / (double)(1u << QM3_ADC_BITS);
    const long code = lround(i_meas_A / amp_per_code);
    return (uint16_t)(code + (1L << (QM3_ADC_BITS - 1u)));
}

int main(void)
{
    qemu_m4_puts("M3 closed loop: bare encoder-FOC current path, ");
    qemu_m4_puts(foc_format_name);
    qemu_m4_puts("\n");

    plant_config_t pc;
    plant_setup(&pc);
    if (!motor_as_expected(&pc.motor)) {
        return refuse("plant_config_default's motor differs from the "
                      "expectations' (tests/qemu_m3/CMakeLists.txt)");
    }
    if (plant_init(&plant, &pc) != PLANT_OK) {
        qemu_m4_puts(plant_error_message(&plant));
        return refuse("plant_init");
    }
    const foc_design_t design = {
        .R_ohm = QM3_R_OHM,
        .L_H = QM3_L_H,
        .w_c_rad_s = QM3_W_C_RAD_S,
        .v_dc_V = QM3_V_DC_V,
        .f_pwm_Hz = QM3_F_PWM_HZ,
        .i_fs_A = QM3_I_FS_A,
        .adc_bits = QM3_ADC_BITS,
        .pole_pairs = QM3_POLE_PAIRS,
        .cpr = 4u * QM3_ENC_LINES,
        .arr = QM3_ARR,
    };
    if (foc_init(&design) != 0) {
        return refuse("foc_init");
    }
    qemu_m4_puts("counter overhead (instr) ");
    qemu_m4_put_u32(isr_meter_overhead());
    qemu_m4_puts("\n");

    foc_io_t io = { .ccr = { QM3_ARR / 2u, QM3_ARR / 2u, QM3_ARR / 2u } };
    double duty[3] = { 0.5, 0.5, 0.5 }; /* before the first call: 0 V */
    isr_stats_t stats;
    isr_stats_reset(&stats);
    uint32_t saturated = 0u;
    uint32_t next_cp = 0u;
    double locked_max_id = 0.0;
    double free_max_id = 0.0;
    double max_v_pu = 0.0;
    const plant_true_state_t *ts = plant_true_state(&plant);

    for (uint32_t k = 0u; k < QM3_END_K; ++k) {
        if (k == QM3_STEP_K) {
            foc_set_reference(0.0, QM3_IQ_STEP_A);
        }
        if (k == QM3_RELEASE_K) {
            foc_set_reference(0.0, QM3_IQ_FREE_A);
            if (plant_set_rotor_locked(&plant, false) != PLANT_OK) {
                return refuse("plant_set_rotor_locked");
            }
        }
        plant_measurement_t m;
        plant_sample(&plant, &m);
        for (unsigned x = 0u; x < 3u; ++x) {
            io.adc[x] = adc_raw(m.i_abc_A[x]);
        }
        io.enc_count = m.encoder_count;

        isr_stats_add(&stats, isr_meter_measure(foc_isr, &io));

        foc_monitor_t mon;
        foc_monitor(&mon);
        const double lim = FOC_PI_LIMIT_PU * (1.0 - 1e-9);
        if (mon.overmodulated || fabs(mon.v_d_pu) >= lim || fabs(mon.v_q_pu) >= lim) {
            ++saturated;
        }
        max_v_pu = fmax(max_v_pu, hypot(mon.v_d_pu, mon.v_q_pu));

        plant_advance(&plant, duty, true);
        for (unsigned x = 0u; x < 3u; ++x) {
            duty[x] = (double)io.ccr[x] / (double)QM3_ARR;
        }

        /* true state at t_(k+1) */
        ts = plant_true_state(&plant);
        const uint32_t n = k + 1u - QM3_STEP_K;
        if (k + 1u > QM3_STEP_K && next_cp < N_CHECKPOINTS && n == checkpoints[next_cp]) {
            print_value("step_iq_n", "_A", n, ts->i_q_A, 6u);
            ++next_cp;
        }
        if (k + 1u > QM3_STEP_K && k + 1u <= QM3_RELEASE_K) {
            locked_max_id = fmax(locked_max_id, fabs(ts->i_d_A));
        } else if (k + 1u > QM3_RELEASE_K) {
            free_max_id = fmax(free_max_id, fabs(ts->i_d_A));
        }
        if ((k + 1u) % 2000u == 0u) {
            qemu_m4_puts("t ");
            qemu_m4_put_fixed(ts->t_s, 3u);
            qemu_m4_puts(" s: i_d ");
            qemu_m4_put_fixed(ts->i_d_A, 5u);
            qemu_m4_puts(" A, i_q ");
            qemu_m4_put_fixed(ts->i_q_A, 5u);
            qemu_m4_puts(" A, omega_m ");
            qemu_m4_put_fixed(ts->omega_m_rad_s, 4u);
            qemu_m4_puts(" rad/s\n");
        }
    }
    if (next_cp != N_CHECKPOINTS) {
        return refuse("checkpoints not increasing or beyond the run");
    }

    qemu_m4_puts("max |v_dq| (per-unit of v_dc) ");
    qemu_m4_put_fixed(max_v_pu, 4u);
    qemu_m4_puts("\n");
    print_value("locked_max_abs_i_d_A", 0, 0u, locked_max_id, 6u);
    print_value("free_max_abs_i_d_A", 0, 0u, free_max_id, 6u);
    print_value("final_i_q_A", 0, 0u, ts->i_q_A, 6u);
    print_value("final_omega_m_rad_s", 0, 0u, ts->omega_m_rad_s, 5u);
    print_value("saturated_isrs", 0, 0u, (double)saturated, 0u);
    isr_stats_print("isr", &stats);
    print_value("isr_count", 0, 0u, (double)stats.n, 0u);
    print_value("isr_min_instr", 0, 0u, (double)stats.min, 0u);
    print_value("isr_mean_instr", 0, 0u, (double)stats.sum / (double)stats.n, 1u);
    print_value("isr_max_instr", 0, 0u, (double)stats.max, 0u);
    return 0;
}
