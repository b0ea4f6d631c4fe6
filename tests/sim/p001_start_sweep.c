#include "p001_start_sweep.h"

#include "mc_test.h"

#include <math.h>
#include <stdio.h>

double p001_sweep_offset_e_rad(unsigned k)
{
    return (k < 12u) ? (double)k * MC_TEST_PI / 6.0 : MC_TEST_PI - 1e-3;
}

static bench_result_t run_case(mc_controller_t controller, unsigned k)
{
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, controller);
    assert_true(pc.motor.B_Nm_s_rad == 0.0);
    const double off = p001_sweep_offset_e_rad(k);
    pc.theta_m0_rad = ((double)fc.align.angle_e_rad + off) / (double)pc.motor.pole_pairs;
    char label[64];
    (void)snprintf(label, sizeof label, "%s start %+.4f rad",
                   controller == MC_CONTROLLER_IDAPBC ? "paper" : "NAM", off);
    return bench_run_to(&pc, &fc, label, 2.5);
}

void p001_sweep_assert_range(mc_controller_t controller, unsigned k_begin, unsigned k_end)
{
    assert_true(k_begin < k_end && k_end <= P001_SWEEP_N);
    double t_max = 0.0, err_max = 0.0, w_max = 0.0, i_max = 0.0;
    for (unsigned k = k_begin; k < k_end; ++k) {
        const bench_result_t r = run_case(controller, k);
        assert_int_equal(r.faults, 0u);
        assert_true(r.t_first_fault_s < 0.0);
        assert_true(r.t_run_s > 0.0 && r.t_run_s <= BENCH_T0_S);
        assert_true(fabs(r.align_angle_err_rad) <= 0.02);
        assert_true(fabs(r.align_omega_m_rad_s) <= 0.01);
        assert_true(r.peak_current_align_A <= 3.0);
        assert_true(r.rms_speed_err_50_rpm <= 0.05);
        assert_true(r.dip_load_1s_rpm <= 20.0);
        assert_true(r.rms_angle_err_50_rad <= 1e-3);
        t_max = fmax(t_max, r.t_align_s);
        err_max = fmax(err_max, fabs(r.align_angle_err_rad));
        w_max = fmax(w_max, fabs(r.align_omega_m_rad_s));
        i_max = fmax(i_max, r.peak_current_align_A);
    }
    printf("start angles %u..%u: ALIGN <= %.4f s, |angle err| <= %.3g rad, "
           "|w| <= %.3g rad/s, ALIGN current <= %.4g A\n",
           k_begin, k_end - 1u, t_max, err_max, w_max, i_max);
}
