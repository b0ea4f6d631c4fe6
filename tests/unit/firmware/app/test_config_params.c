/*
 * The configuration's parameter table (mc_config_params, mc/params.h):
 * unique names, every field inside mc_config_t at its member's place, no
 * overlap, no unpublished member (the only bytes no field covers are the
 * padding after a bool), one block per controller and estimator of the
 * lists, and every published float checked by mc_config_validate.
 */
#include "mc_test.h"

#include <math.h>
#include <stdalign.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "mc/config.h"

typedef struct {
    const char *block;
    const char *field;
    mc_param_type_t type;
    size_t offset; /* from the start of mc_config_t */
    size_t size;
} field_t;

#define MAX_FIELDS 256u

static size_t type_size(mc_param_type_t t)
{
    switch (t) {
    case MC_PARAM_F32: return sizeof(float);
    case MC_PARAM_U32: return sizeof(uint32_t);
    case MC_PARAM_BOOL: return sizeof(bool);
    case MC_PARAM_CONTROLLER: return sizeof(mc_controller_t);
    case MC_PARAM_ESTIMATOR: return sizeof(mc_estimator_t);
    }
    fail_msg("unknown parameter type %d", (int)t);
    return 0u;
}

static size_t type_align(mc_param_type_t t)
{
    switch (t) {
    case MC_PARAM_F32: return alignof(float);
    case MC_PARAM_U32: return alignof(uint32_t);
    case MC_PARAM_BOOL: return alignof(bool);
    case MC_PARAM_CONTROLLER: return alignof(mc_controller_t);
    case MC_PARAM_ESTIMATOR: return alignof(mc_estimator_t);
    }
    return 1u;
}

/* Every field of the table, flattened. */
static size_t collect(field_t *out)
{
    size_t n = 0u;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        assert_non_null(b->params);
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            assert_true(n < MAX_FIELDS);
            out[n] = (field_t){
                .block = b->name,
                .field = p->name,
                .type = p->type,
                .offset = (size_t)b->offset + (size_t)p->offset,
                .size = type_size(p->type),
            };
            ++n;
        }
    }
    return n;
}

static int by_offset(const void *a, const void *b)
{
    const field_t *x = a;
    const field_t *y = b;
    return (x->offset > y->offset) - (x->offset < y->offset);
}

static const mc_param_block_t *find_block(const char *name)
{
    const mc_param_block_t *found = NULL;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        if (strcmp(b->name, name) == 0) {
            assert_null(found); /* unique */
            found = b;
        }
    }
    return found;
}

static const field_t *find_field(const field_t *f, size_t n, const char *block, const char *field)
{
    for (size_t i = 0; i < n; ++i) {
        if (strcmp(f[i].block, block) == 0 && strcmp(f[i].field, field) == 0) {
            return &f[i];
        }
    }
    return NULL;
}

/* mc_param_size: the C type each table type stands for; the tables'
 * fields tile the configuration with these sizes (test_fields_tile_the_
 * config), and readers copy fields with them. */
static void test_param_sizes(void **state)
{
    (void)state;
    assert_int_equal(mc_param_size(MC_PARAM_F32), sizeof(float));
    assert_int_equal(mc_param_size(MC_PARAM_U32), sizeof(uint32_t));
    assert_int_equal(mc_param_size(MC_PARAM_BOOL), sizeof(bool));
    assert_int_equal(mc_param_size(MC_PARAM_CONTROLLER), sizeof(mc_controller_t));
    assert_int_equal(mc_param_size(MC_PARAM_ESTIMATOR), sizeof(mc_estimator_t));
    assert_int_equal(mc_param_size((mc_param_type_t)99), 0u);
}

static void test_names_unique(void **state)
{
    (void)state;
    const mc_param_block_t *blocks = mc_config_params();
    size_t nb = 0u;
    while (blocks[nb].name != NULL) {
        ++nb;
    }
    assert_true(nb > 2u);
    assert_string_equal(blocks[0].name, ""); /* top level first */
    assert_int_equal(blocks[0].offset, 0u);
    for (size_t i = 0; i < nb; ++i) {
        for (size_t j = i + 1u; j < nb; ++j) {
            if (strcmp(blocks[i].name, blocks[j].name) == 0) {
                fail_msg("block \"%s\" twice", blocks[i].name);
            }
        }
        const mc_param_t *p = blocks[i].params;
        assert_non_null(p);
        assert_non_null(p[0].name); /* no empty block */
        for (size_t a = 0; p[a].name != NULL; ++a) {
            assert_true(strlen(p[a].name) > 0u);
            for (size_t b = a + 1u; p[b].name != NULL; ++b) {
                if (strcmp(p[a].name, p[b].name) == 0) {
                    fail_msg("field %s.%s twice", blocks[i].name, p[a].name);
                }
            }
        }
    }
}

/* Inside mc_config_t, aligned, no overlap, and the only bytes no field
 * covers are the padding after a bool (shorter than a float): a float or
 * uint32_t member missing from the table would leave a gap of 4 bytes. */
static void test_fields_tile_the_config(void **state)
{
    (void)state;
    static field_t f[MAX_FIELDS];
    const size_t n = collect(f);
    for (size_t i = 0; i < n; ++i) {
        if (!(f[i].offset + f[i].size <= sizeof(mc_config_t))) {
            fail_msg("%s.%s outside mc_config_t", f[i].block, f[i].field);
        }
        if (f[i].offset % type_align(f[i].type) != 0u) {
            fail_msg("%s.%s misaligned", f[i].block, f[i].field);
        }
    }
    qsort(f, n, sizeof f[0], by_offset);
    assert_int_equal(f[0].offset, 0u);
    for (size_t i = 0; i + 1u < n; ++i) {
        const size_t end = f[i].offset + f[i].size;
        if (end > f[i + 1u].offset) {
            fail_msg("%s.%s overlaps %s.%s", f[i].block, f[i].field, f[i + 1u].block,
                     f[i + 1u].field);
        }
        const size_t gap = f[i + 1u].offset - end;
        if (gap != 0u && !(f[i].type == MC_PARAM_BOOL && gap < sizeof(float))) {
            fail_msg("%zu unpublished bytes after %s.%s", gap, f[i].block, f[i].field);
        }
    }
    const field_t *last = &f[n - 1u];
    const size_t tail = sizeof(mc_config_t) - (last->offset + last->size);
    assert_true(tail == 0u || (last->type == MC_PARAM_BOOL && tail < sizeof(float)));
}

/* Each block sits at the mc_config_t member of its name (mc/config.h). */
static void test_blocks_at_their_members(void **state)
{
    (void)state;
    const struct {
        const char *name;
        size_t offset;
    } expected[] = { { "motor", offsetof(mc_config_t, motor) },
                     { "timing", offsetof(mc_config_t, timing) },
                     { "limits", offsetof(mc_config_t, limits) },
                     { "protection", offsetof(mc_config_t, protection) },
                     { "current", offsetof(mc_config_t, current) },
                     { "deadtime", offsetof(mc_config_t, deadtime) },
                     { "position", offsetof(mc_config_t, position) },
                     { "align", offsetof(mc_config_t, align) },
                     { "flux_obs", offsetof(mc_config_t, flux_obs) },
                     { "emf_check", offsetof(mc_config_t, emf_check) },
#define X_EXPECT(name, NAME) { #name, offsetof(mc_config_t, name) },
                     MC_CONTROLLERS(X_EXPECT) MC_ESTIMATORS(X_EXPECT)
#undef X_EXPECT
    };
    size_t nb = 0u;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        ++nb;
    }
    /* the top level plus exactly these */
    assert_int_equal(nb, 1u + sizeof expected / sizeof expected[0]);
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; ++i) {
        const mc_param_block_t *b = find_block(expected[i].name);
        if (b == NULL) {
            fail_msg("no block \"%s\"", expected[i].name);
        }
        assert_int_equal(b->offset, expected[i].offset);
    }
}

/* One block per controller and per estimator, named by the lists. */
static void test_one_block_per_controller_and_estimator(void **state)
{
    (void)state;
    for (int k = 0; k < (int)MC_CONTROLLER_COUNT; ++k) {
        const char *name = mc_controller_name((mc_controller_t)k);
        assert_non_null(name);
        if (find_block(name) == NULL) {
            fail_msg("no block for controller %s", name);
        }
        for (int j = 0; j < k; ++j) {
            assert_string_not_equal(name, mc_controller_name((mc_controller_t)j));
        }
    }
    for (int k = 0; k < (int)MC_ESTIMATOR_COUNT; ++k) {
        const char *name = mc_estimator_name((mc_estimator_t)k);
        assert_non_null(name);
        if (find_block(name) == NULL) {
            fail_msg("no block for estimator %s", name);
        }
        for (int j = 0; j < k; ++j) {
            assert_string_not_equal(name, mc_estimator_name((mc_estimator_t)j));
        }
        for (int c = 0; c < (int)MC_CONTROLLER_COUNT; ++c) {
            assert_string_not_equal(name, mc_controller_name((mc_controller_t)c));
        }
    }
    assert_string_equal(mc_controller_name(MC_CONTROLLER_FOC_PI), "foc_pi");
    assert_string_equal(mc_controller_name(MC_CONTROLLER_IDAPBC), "idapbc");
    assert_string_equal(mc_estimator_name(MC_ESTIMATOR_ENCODER), "encoder");
    assert_string_equal(mc_estimator_name(MC_ESTIMATOR_FLUX_II), "flux_ii");
    assert_string_equal(mc_estimator_name(MC_ESTIMATOR_FLUX_PLL), "flux_pll");
    assert_null(mc_controller_name(MC_CONTROLLER_COUNT));
    assert_null(mc_estimator_name(MC_ESTIMATOR_COUNT));
    assert_null(mc_controller_name((mc_controller_t)1000));
    assert_null(mc_estimator_name((mc_estimator_t)1000));
}

/* A few keys, their types and places, written out from mc/config.h (the
 * scenario files spell them so). */
static void test_known_keys(void **state)
{
    (void)state;
    static field_t f[MAX_FIELDS];
    const size_t n = collect(f);
    const struct {
        const char *block, *field;
        mc_param_type_t type;
        size_t offset;
    } keys[] = {
        { "", "controller", MC_PARAM_CONTROLLER, offsetof(mc_config_t, controller) },
        { "", "estimator", MC_PARAM_ESTIMATOR, offsetof(mc_config_t, estimator) },
        { "motor", "R_ohm", MC_PARAM_F32, offsetof(mc_config_t, motor.R_ohm) },
        { "motor", "pole_pairs", MC_PARAM_U32, offsetof(mc_config_t, motor.pole_pairs) },
        { "motor", "B_Nm_s_rad", MC_PARAM_F32, offsetof(mc_config_t, motor.B_Nm_s_rad) },
        { "timing", "f_pwm_Hz", MC_PARAM_F32, offsetof(mc_config_t, timing.f_pwm_Hz) },
        { "timing", "isr_overrun_limit", MC_PARAM_U32,
          offsetof(mc_config_t, timing.isr_overrun_limit) },
        { "timing", "delay_periods", MC_PARAM_F32, offsetof(mc_config_t, timing.delay_periods) },
        { "timing", "delay_compensation", MC_PARAM_BOOL,
          offsetof(mc_config_t, timing.delay_compensation) },
        { "timing", "telemetry_every_isr", MC_PARAM_BOOL,
          offsetof(mc_config_t, timing.telemetry_every_isr) },
        { "protection", "i_trip_A", MC_PARAM_F32, offsetof(mc_config_t, protection.i_trip_A) },
        { "protection", "estimate_tau_max_Nm", MC_PARAM_F32,
          offsetof(mc_config_t, protection.estimate_tau_max_Nm) },
        { "current", "bandwidth_rad_s", MC_PARAM_F32,
          offsetof(mc_config_t, current.bandwidth_rad_s) },
        { "align", "settle_time_s", MC_PARAM_F32, offsetof(mc_config_t, align.settle_time_s) },
        { "flux_obs", "gamma", MC_PARAM_F32, offsetof(mc_config_t, flux_obs.gamma) },
        { "foc_pi", "speed_bandwidth_rad_s", MC_PARAM_F32,
          offsetof(mc_config_t, foc_pi.speed_bandwidth_rad_s) },
        { "idapbc", "integral_enabled", MC_PARAM_BOOL,
          offsetof(mc_config_t, idapbc.integral_enabled) },
        { "encoder", "counts_per_rev", MC_PARAM_U32,
          offsetof(mc_config_t, encoder.counts_per_rev) },
        { "flux_ii", "a2", MC_PARAM_F32, offsetof(mc_config_t, flux_ii.a2) },
        { "flux_pll", "bandwidth_rad_s", MC_PARAM_F32,
          offsetof(mc_config_t, flux_pll.bandwidth_rad_s) },
    };
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i) {
        const field_t *p = find_field(f, n, keys[i].block, keys[i].field);
        if (p == NULL) {
            fail_msg("no key %s.%s", keys[i].block, keys[i].field);
        }
        assert_int_equal(p->type, keys[i].type);
        assert_int_equal(p->offset, keys[i].offset);
    }
}

/* Every published float is checked: NaN (and +-Inf) in any one of them
 * makes the default configuration MC_ERR_NONFINITE, whatever controller
 * and estimator are selected (the table is checked as a whole). */
static void test_every_float_is_checked(void **state)
{
    (void)state;
    static field_t f[MAX_FIELDS];
    const size_t n = collect(f);
    const float bad[] = { NAN, INFINITY, -INFINITY };
    size_t n_f32 = 0u;
    for (size_t i = 0; i < n; ++i) {
        if (f[i].type != MC_PARAM_F32) {
            continue;
        }
        ++n_f32;
        for (int e = 0; e < (int)MC_ESTIMATOR_COUNT; ++e) {
            for (size_t b = 0; b < sizeof bad / sizeof bad[0]; ++b) {
                mc_config_t c;
                mc_config_init_default(&c);
                c.estimator = (mc_estimator_t)e;
                if (e != (int)MC_ESTIMATOR_ENCODER) {
                    c.controller = MC_CONTROLLER_IDAPBC;
                }
                assert_int_equal(mc_config_validate(&c), MC_OK);
                memcpy((unsigned char *)&c + f[i].offset, &bad[b], sizeof(float));
                const mc_status_t st = mc_config_validate(&c);
                if (st != MC_ERR_NONFINITE) {
                    fail_msg("%s.%s = %g (estimator %s): got %d", f[i].block, f[i].field,
                             (double)bad[b], mc_estimator_name((mc_estimator_t)e), (int)st);
                }
            }
        }
    }
    /* motor 6, timing 4, limits 2, protection 17, current 2, deadtime 3, position 1,
     * align 8, flux_obs 3, emf_check 7, foc_pi 1, idapbc 3, encoder 2,
     * flux_ii 2, flux_pll 1, eeo 10, cdobc 14 (the float members of
     * mc/config.h and its blocks). */
    assert_int_equal(n_f32, 86u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_param_sizes),
        cmocka_unit_test(test_names_unique),
        cmocka_unit_test(test_fields_tile_the_config),
        cmocka_unit_test(test_blocks_at_their_members),
        cmocka_unit_test(test_one_block_per_controller_and_estimator),
        cmocka_unit_test(test_known_keys),
        cmocka_unit_test(test_every_float_is_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
