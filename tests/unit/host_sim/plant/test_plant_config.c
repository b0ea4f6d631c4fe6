/* Configuration: the default is valid; every invalid parameter is rejected
 * with its error class and a message; a rejected plant does not run. */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "plant.h"
#include "plant_test_support.h"

static void test_default_is_valid(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    const char *msg = NULL;
    assert_int_equal(plant_config_validate(&c, &msg), PLANT_OK);
    assert_string_equal(msg, "ok");
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_string_equal(plant_error_message(&p), "ok");
    assert_near(plant_period_s(&p), 50e-6, 1e-18);
    const plant_true_state_t *s = plant_true_state(&p);
    assert_true(s->t_s == 0.0 && s->i_d_A == 0.0 && s->omega_m_rad_s == 0.0);
    /* a stiff 48 V bus, no fault, outputs on */
    assert_true(c.dc_link.capacitance_F == 0.0);
    assert_true(s->v_dc_V == 48.0 && s->v_source_V == 48.0 && s->i_source_A == 0.0);
    assert_true(s->source_connected && !s->rotor_locked && s->outputs_enabled);
    assert_false(s->open_circuit || s->rectifying || s->brake_on);
    for (int x = 0; x < 3; ++x)
        assert_true(s->phase_state[x] == PLANT_PHASE_DRIVEN && !s->phase_open[x]);
}

typedef void (*mutate_fn)(plant_config_t *c);
#define MUT(name, body)                                                                            \
    static void name(plant_config_t *c)                                                            \
    {                                                                                              \
        body;                                                                                      \
    }

MUT(m_r_neg, c->motor.R_ohm = -0.1)
MUT(m_r_nan, c->motor.R_ohm = NAN)
MUT(m_ld_zero, c->motor.Ld_H = 0.0)
MUT(m_lq_inf, c->motor.Lq_H = INFINITY)
MUT(m_psi_neg, c->motor.psi_Wb = -0.17)
MUT(m_np_zero, c->motor.pole_pairs = 0u)
MUT(m_j_neg, c->motor.J_kgm2 = -1.0)
MUT(m_b_neg, c->motor.B_Nm_s_rad = -1e-3)
MUT(m_coul_no_eps, c->motor.tau_coulomb_Nm = 0.1)
MUT(m_g3_too_big, c->motor.g3_amplitude_per_kgm2 = 1.0 / 0.012)
MUT(m_cog_no_slots, c->motor.cogging.n_harmonics = 1u)
MUT(m_cog_too_many, c->motor.cogging.n_harmonics = PLANT_MAX_COG_HARMONICS + 1u;
    c->motor.cogging.slots = 9u)
MUT(m_mis_r_zero, c->mismatch.R = 0.0)
MUT(m_mis_j_nan, c->mismatch.J = NAN)
MUT(m_fpwm_zero, c->inverter.f_pwm_Hz = 0.0)
MUT(m_dead_half, c->inverter.t_dead_s = 25e-6)
MUT(m_drop_neg, c->inverter.v_device_drop_V = -0.7)
MUT(m_band_neg, c->inverter.dead_time_current_band_A = -1.0)
MUT(m_vdc_nan, sim_profile_set_constant(&c->inverter.v_dc_V, NAN))
MUT(m_gain_inf, c->sensors.current.gain[1] = INFINITY)
MUT(m_noise_neg, c->sensors.current.noise_rms_A = -0.1)
MUT(m_bits_no_fs, c->sensors.current.adc_bits = 12u)
MUT(m_bits_big, c->sensors.current.adc_bits = 30u; c->sensors.current.full_scale_A = 10.0)
MUT(m_vdc_bits_no_fs, c->sensors.vdc.adc_bits = 10u)
MUT(m_enc_off_nan, c->sensors.encoder.offset_rad = NAN)
MUT(m_load_order, c->load_torque_Nm.points[0].t_s = 1.0; c->load_torque_Nm.points[1].t_s = 0.0;
    c->load_torque_Nm.n_points = 2u)
MUT(m_substeps_zero, c->substeps_per_period = 0u)
MUT(m_half_odd, c->inverter.duty_update = PLANT_DUTY_UPDATE_HALF_PERIOD;
    c->substeps_per_period = 5u)
MUT(m_update_bad, c->inverter.duty_update = (plant_duty_update_t)7)
MUT(m_link_c_neg, c->dc_link.capacitance_F = -1e-3)
MUT(m_link_rs_stiff, c->dc_link.source_resistance_ohm = 0.1)
MUT(m_link_brake_stiff, c->dc_link.brake_resistance_ohm = 10.0; c->dc_link.brake_on_V = 60.0)
MUT(m_link_v0_stiff, c->dc_link.v0_given = true; c->dc_link.v0_V = 48.0)
MUT(m_link_rs_zero, c->dc_link.capacitance_F = 1e-3)
MUT(m_link_rb_neg, c->dc_link.capacitance_F = 1e-3; c->dc_link.source_resistance_ohm = 0.1;
    c->dc_link.brake_resistance_ohm = -1.0)
MUT(m_link_hyst, c->dc_link.capacitance_F = 1e-3; c->dc_link.source_resistance_ohm = 0.1;
    c->dc_link.brake_resistance_ohm = 10.0; c->dc_link.brake_on_V = 60.0;
    c->dc_link.brake_off_V = 60.0)
MUT(m_link_on_zero, c->dc_link.capacitance_F = 1e-3; c->dc_link.source_resistance_ohm = 0.1;
    c->dc_link.brake_resistance_ohm = 10.0)
MUT(m_link_thresholds_no_brake, c->dc_link.capacitance_F = 1e-3;
    c->dc_link.source_resistance_ohm = 0.1; c->dc_link.brake_on_V = 60.0;
    c->dc_link.brake_off_V = 55.0)
MUT(m_link_v0_neg, c->dc_link.capacitance_F = 1e-3; c->dc_link.source_resistance_ohm = 0.1;
    c->dc_link.v0_given = true; c->dc_link.v0_V = -1.0)
MUT(m_link_v0_not_given, c->dc_link.capacitance_F = 1e-3; c->dc_link.source_resistance_ohm = 0.1;
    c->dc_link.v0_V = 10.0)
MUT(m_theta0_inf, c->theta_m0_rad = INFINITY)
MUT(m_omega0_nan, c->omega_m0_rad_s = NAN)

static void test_invalid_configs_rejected(void **state)
{
    (void)state;
    const struct {
        mutate_fn fn;
        int code;
    } cases[] = {
        { m_r_neg, PLANT_ERR_MOTOR },           { m_r_nan, PLANT_ERR_MOTOR },
        { m_ld_zero, PLANT_ERR_MOTOR },         { m_lq_inf, PLANT_ERR_MOTOR },
        { m_psi_neg, PLANT_ERR_MOTOR },         { m_np_zero, PLANT_ERR_MOTOR },
        { m_j_neg, PLANT_ERR_MOTOR },           { m_b_neg, PLANT_ERR_MOTOR },
        { m_coul_no_eps, PLANT_ERR_MOTOR },     { m_g3_too_big, PLANT_ERR_MOTOR },
        { m_cog_no_slots, PLANT_ERR_MOTOR },    { m_cog_too_many, PLANT_ERR_MOTOR },
        { m_mis_r_zero, PLANT_ERR_MISMATCH },   { m_mis_j_nan, PLANT_ERR_MISMATCH },
        { m_fpwm_zero, PLANT_ERR_INVERTER },    { m_dead_half, PLANT_ERR_INVERTER },
        { m_drop_neg, PLANT_ERR_INVERTER },     { m_band_neg, PLANT_ERR_INVERTER },
        { m_vdc_nan, PLANT_ERR_PROFILE },       { m_gain_inf, PLANT_ERR_SENSOR },
        { m_noise_neg, PLANT_ERR_SENSOR },      { m_bits_no_fs, PLANT_ERR_SENSOR },
        { m_bits_big, PLANT_ERR_SENSOR },       { m_vdc_bits_no_fs, PLANT_ERR_SENSOR },
        { m_enc_off_nan, PLANT_ERR_SENSOR },    { m_load_order, PLANT_ERR_PROFILE },
        { m_substeps_zero, PLANT_ERR_SOLVER },  { m_theta0_inf, PLANT_ERR_SOLVER },
        { m_omega0_nan, PLANT_ERR_SOLVER },     { m_half_odd, PLANT_ERR_SOLVER },
        { m_update_bad, PLANT_ERR_INVERTER },   { m_link_c_neg, PLANT_ERR_DC_LINK },
        { m_link_rs_stiff, PLANT_ERR_DC_LINK }, { m_link_brake_stiff, PLANT_ERR_DC_LINK },
        { m_link_v0_stiff, PLANT_ERR_DC_LINK }, { m_link_rs_zero, PLANT_ERR_DC_LINK },
        { m_link_rb_neg, PLANT_ERR_DC_LINK },   { m_link_hyst, PLANT_ERR_DC_LINK },
        { m_link_on_zero, PLANT_ERR_DC_LINK },  { m_link_thresholds_no_brake, PLANT_ERR_DC_LINK },
        { m_link_v0_neg, PLANT_ERR_DC_LINK },   { m_link_v0_not_given, PLANT_ERR_DC_LINK },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        plant_config_t c;
        plant_config_default(&c);
        cases[i].fn(&c);
        const char *msg = NULL;
        assert_int_equal(plant_config_validate(&c, &msg), cases[i].code);
        assert_non_null(msg);
        assert_string_not_equal(msg, "ok");
        plant_t p;
        assert_int_equal(plant_init(&p, &c), cases[i].code);
        assert_string_equal(plant_error_message(&p), msg);
        /* a rejected plant ignores advance: time does not move */
        const double duty[3] = { 0.5, 0.5, 0.5 };
        plant_advance(&p, duty, true);
        assert_true(plant_true_state(&p)->t_s == 0.0);
    }
    /* the messages name the dc_link field */
    plant_config_t c;
    plant_config_default(&c);
    m_link_rs_zero(&c);
    const char *msg = NULL;
    assert_int_equal(plant_config_validate(&c, &msg), PLANT_ERR_DC_LINK);
    assert_non_null(strstr(msg, "source_resistance_ohm"));
    plant_config_default(&c);
    m_link_hyst(&c);
    assert_int_equal(plant_config_validate(&c, &msg), PLANT_ERR_DC_LINK);
    assert_non_null(strstr(msg, "brake_off_V must be below brake_on_V"));
    assert_int_equal(plant_config_validate(NULL, NULL), PLANT_ERR_NULL);
    assert_int_equal(plant_init(NULL, NULL), PLANT_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_is_valid),
        cmocka_unit_test(test_invalid_configs_rejected),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
