/*
 * Telemetry frames (can_node_internal.h: mc_can_tlm_frame) decoded with the
 * test's own arithmetic from the DBC's text: values in range within half a
 * resolution step, the saturation rule (outside the range: the range's
 * end; NaN and +-Inf: the maximum), the range ends themselves (no raw
 * overflow), theta_e wrapped to [0, 2 pi), masks and modulo counts, the
 * counter nibble and the E2E CRC.
 */
#include "can_bench.h"

#include <math.h>

#include "can_node_internal.h"

/* a scaled signal of a telemetry message, from the DBC */
typedef struct {
    uint32_t msg;
    uint32_t byte; /* start bit / 8 */
    uint32_t bits;
    bool is_signed;
    double scale, min, max;
    size_t field; /* offset of the float in mc_telemetry_t (SIZE_MAX: other) */
} sig_t;

#define TLM(member) offsetof(mc_telemetry_t, member)
#define OTHER       SIZE_MAX

static const sig_t sigs[] = {
    { MSG_CURRENTS, 2, 16, true, 0.002, -65.536, 65.534, TLM(i_d_A) },
    { MSG_CURRENTS, 4, 16, true, 0.002, -65.536, 65.534, TLM(i_q_A) },
    { MSG_CURRENTS, 6, 16, false, 0.01, 0.0, 655.35, TLM(v_dc_V) },
    { MSG_VOLTAGES, 2, 16, true, 0.01, -327.68, 327.67, TLM(v_d_V) },
    { MSG_VOLTAGES, 4, 16, true, 0.01, -327.68, 327.67, TLM(v_q_V) },
    { MSG_VOLTAGES, 6, 16, true, 0.002, -65.536, 65.534, TLM(i_q_ref_A) },
    { MSG_MOTION, 2, 24, true, 0.001, -8388.608, 8388.607, TLM(omega_m_rad_s) },
    { MSG_MOTION, 5, 24, true, 0.001, -8388.608, 8388.607, TLM(theta_m_rad) },
    { MSG_ESTIMATES, 4, 16, true, 0.001, -32.768, 32.767, TLM(tau_L_hat_Nm) },
    { MSG_ESTIMATES, 6, 16, false, 0.0001, 0.0, 6.5535, TLM(flux_ratio_sq) },
    { MSG_REFERENCES, 2, 24, true, 0.001, -8388.608, 8388.607, TLM(omega_m_ref_rad_s) },
    { MSG_REFERENCES, 5, 24, true, 0.001, -8388.608, 8388.607, TLM(theta_m_ref_rad) },
};

static mc_telemetry_t tlm;
static mc_can_counters_t counters;
static mc_can_tlm_input_t in;

static int setup(void **state)
{
    (void)state;
    memset(&tlm, 0, sizeof tlm);
    memset(&counters, 0, sizeof counters);
    in = (mc_can_tlm_input_t){ .tlm = &tlm, .counters = &counters };
    return 0;
}

static hal_can_frame_t frame(uint32_t msg, uint8_t counter)
{
    hal_can_frame_t f;
    assert_true(mc_can_tlm_frame(9u, msg, &in, counter, &f));
    assert_int_equal(f.id, 9u * 32u + msg);
    assert_int_equal(f.dlc, 8u);
    assert_false(f.extended || f.rtr);
    assert_true(ref_e2e_ok(&f));
    assert_int_equal(f.data[1] & 0x0Fu, counter);
    return f;
}

static int32_t raw_of(const hal_can_frame_t *f, const sig_t *s)
{
    const uint32_t u = (s->bits == 16u) ? get_u16(&f->data[s->byte]) : get_u24(&f->data[s->byte]);
    return s->is_signed ? sign_extend(u, s->bits) : (int32_t)u;
}

static double decode(const sig_t *s, float v, uint8_t counter)
{
    memcpy((uint8_t *)&tlm + s->field, &v, sizeof v);
    const hal_can_frame_t f = frame(s->msg, counter);
    return raw_of(&f, s) * s->scale;
}

static void test_scaled_signals_and_saturation(void **state)
{
    (void)state;
    uint8_t c = 0;
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; ++i) {
        const sig_t *s = &sigs[i];
        const double half = 0.5 * s->scale * 1.0001;
        /* inside: within half a step */
        const double vals[] = { 0.0, s->min * 0.37, s->max * 0.81, s->max * 0.5 + 0.123 };
        for (size_t k = 0; k < 4; ++k) {
            assert_near(decode(s, (float)vals[k], c), vals[k], half + fabs(vals[k]) * 1e-7);
            c = (uint8_t)((c + 1u) % 15u);
        }
        /* the ends and beyond: the ends */
        const double hi = s->max, lo = s->min;
        assert_near(decode(s, (float)hi, c), hi, half);
        assert_near(decode(s, (float)lo, c), lo, half);
        assert_near(decode(s, (float)(hi * 1.5 + 1.0), c), hi, half);
        assert_near(decode(s, 3.0e38f, c), hi, half);
        assert_near(decode(s, (float)(lo - 1.0 - fabs(lo)), c), lo, half);
        assert_near(decode(s, -3.0e38f, c), lo, half);
        /* non-finite: the maximum, whatever the sign */
        assert_near(decode(s, NAN, c), hi, half);
        assert_near(decode(s, INFINITY, c), hi, half);
        assert_near(decode(s, -INFINITY, c), hi, half);
        memset(&tlm, 0, sizeof tlm);
    }
}

static void test_theta_e_wrapped(void **state)
{
    (void)state;
    const double step = 9.58737992428526e-05;
    const struct {
        float in;
        double out;
    } cases[] = {
        { 0.0f, 0.0 },
        { 1.0f, 1.0 },
        { -0.1f, MC_TEST_TWO_PI - 0.1 },
        { 7.0f, 7.0 - MC_TEST_TWO_PI },
        { -20.0f, -20.0 + 4.0 * MC_TEST_TWO_PI },
        { 3.14159f, 3.14159 },
        { (float)(MC_TEST_TWO_PI - 1e-5), 6.28309 }, /* above the range: its end */
        { NAN, 6.28309 },
        { INFINITY, 6.28309 },
        { 1.0e6f, 6.28309 }, /* beyond the wrap's accepted range: non-finite */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        tlm.theta_e_rad = cases[i].in;
        const hal_can_frame_t f = frame(MSG_ESTIMATES, 3u);
        assert_near(get_u16(&f.data[2]) * step, cases[i].out, 0.51 * step + 2e-6);
    }
}

static void test_status_fields(void **state)
{
    (void)state;
    tlm.state = MC_STATE_ALIGN;
    tlm.mode = MC_MODE_POSITION;
    tlm.outputs_enabled = true;
    tlm.current_limited = true;
    tlm.faults_latched = 0xFFFFFFFFu;
    tlm.first_fault = 0x00018001u;
    in.enabled = true;
    in.controller = 2u;
    hal_can_frame_t f = frame(MSG_STATUS, 14u);
    assert_int_equal(f.data[1] >> 4, 4u);
    assert_int_equal(f.data[2] & 0x0Fu, 2u);
    assert_int_equal((f.data[2] >> 4) & 1u, 1u); /* outputs */
    assert_int_equal((f.data[2] >> 5) & 1u, 0u); /* v_saturated */
    assert_int_equal((f.data[2] >> 6) & 1u, 1u); /* current limited */
    assert_int_equal((f.data[2] >> 7) & 1u, 1u); /* enabled */
    assert_int_equal(get_u16(&f.data[3]), 0xFFFFu);
    assert_int_equal(get_u16(&f.data[5]), 0x8001u);
    assert_int_equal(f.data[7], 2u);
    /* values beyond the fields' ranges saturate */
    tlm.state = (mc_state_t)9;
    in.controller = 77u;
    f = frame(MSG_STATUS, 0u);
    assert_int_equal(f.data[1] >> 4, 4u);
    assert_int_equal(f.data[7], 3u);
}

static void test_cost_errors_counters(void **state)
{
    (void)state;
    tlm.isr_cost_s = 12.34e-6f;
    tlm.isr_cost_max_s = 1.0f; /* 1e6 us: the maximum */
    in.cost_avg_s = NAN;
    hal_can_frame_t f = frame(MSG_ISRCOST, 1u);
    assert_int_equal(get_u16(&f.data[2]), 1234u);
    assert_int_equal(get_u16(&f.data[4]), 65535u);
    assert_int_equal(get_u16(&f.data[6]), 65535u);
    tlm.isr_cost_s = -1.0f; /* below the range: 0 */
    f = frame(MSG_ISRCOST, 2u);
    assert_int_equal(get_u16(&f.data[2]), 0u);

    counters.rejected[MC_CAN_REJ_UNKNOWN_MESSAGE] = 300u;
    counters.rejected[MC_CAN_REJ_WRONG_DLC] = 255u;
    counters.rejected[MC_CAN_REJ_BAD_VALUE] = 256u;
    counters.rejected[MC_CAN_REJ_REFUSED_STATE] = 7u;
    counters.rejected[MC_CAN_REJ_UNKNOWN_PARAM] = 50u; /* no field */
    counters.tx_drops = 513u;
    in.stats.rx_overruns = 0xFFFFFFFFu;
    f = frame(MSG_ERRORS, 5u);
    const uint8_t expect[6] = { 44u, 255u, 0u, 7u, 255u, 1u };
    assert_memory_equal(&f.data[2], expect, 6);

    tlm.isr_overruns = 1u << 24;
    in.stats.bus_errors = 12345u;
    f = frame(MSG_COUNTERS, 6u);
    assert_int_equal(get_u24(&f.data[2]), 0xFFFFFFu);
    assert_int_equal(get_u24(&f.data[5]), 12345u);
}

static void test_not_telemetry(void **state)
{
    (void)state;
    hal_can_frame_t f;
    const uint32_t msgs[] = { 0u, 1u, 15u, 25u, 26u, 31u };
    for (size_t i = 0; i < sizeof msgs / sizeof msgs[0]; ++i) {
        assert_false(mc_can_tlm_frame(1u, msgs[i], &in, 0u, &f));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_scaled_signals_and_saturation, setup),
        cmocka_unit_test_setup(test_theta_e_wrapped, setup),
        cmocka_unit_test_setup(test_status_fields, setup),
        cmocka_unit_test_setup(test_cost_errors_counters, setup),
        cmocka_unit_test_setup(test_not_telemetry, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
