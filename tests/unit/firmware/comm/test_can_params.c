/*
 * The parameter codec (mc/can_params.h): CRC-16/CCITT-FALSE (check value,
 * against the test's own bit-serial CRC), one id per parameter of
 * mc_config_params() with no collision, lookup, typed get/set on a
 * configuration (only the field changes, nothing on an error: wrong type,
 * non-finite float, an id outside the controller / estimator lists).
 */
#include "can_bench.h"

#include "mc/can_params.h"
#include "test_rng.h"

#define MAX_PARAMS 512u

static void test_crc16_check_value(void **state)
{
    (void)state;
    const uint8_t s[] = "123456789";
    assert_int_equal(mc_can_crc16_ccitt_false(s, 9u), 0x29B1u);
    assert_int_equal(ref_crc16_ccitt_false(s, 9u), 0x29B1u);
    assert_int_equal(mc_can_crc16_ccitt_false(s, 0u), 0xFFFFu);
    /* the name forms */
    assert_int_equal(mc_can_param_id("", "controller"), ref_param_id("", "controller"));
    assert_int_equal(mc_can_param_id(NULL, "controller"), ref_param_id("", "controller"));
    assert_int_equal(mc_can_param_id("cdobc", "obs_pole_rad_s"),
                     ref_crc16_ccitt_false((const uint8_t *)"cdobc.obs_pole_rad_s", 20u));
}

/* Every parameter: its id (the test's CRC of "block.field"), unique, and
 * found again by the lookup. */
static void test_ids_unique_and_found(void **state)
{
    (void)state;
    static uint16_t ids[MAX_PARAMS];
    uint32_t n = 0;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            const uint16_t id = ref_param_id(b->name, p->name);
            assert_int_equal(mc_can_param_id(b->name, p->name), id);
            for (uint32_t j = 0; j < n; ++j) {
                if (ids[j] == id) {
                    print_error("id collision: %s.%s 0x%04x\n", b->name, p->name, id);
                    fail();
                }
            }
            assert_true(n < MAX_PARAMS);
            ids[n++] = id;
            mc_can_param_ref_t ref;
            assert_true(mc_can_param_find(id, &ref));
            assert_ptr_equal(ref.block, b);
            assert_ptr_equal(ref.param, p);
            assert_int_equal(ref.id, id);
        }
    }
    assert_true(n > 50u);
    /* ids nobody has are not found (and leave ref alone) */
    uint32_t unknown = 0;
    for (uint32_t id = 0; id < 65536u && unknown < 200u; id += 97u) {
        bool used = false;
        for (uint32_t j = 0; j < n; ++j) {
            used = used || ids[j] == id;
        }
        if (!used) {
            mc_can_param_ref_t ref = { .id = 0x1234u };
            assert_false(mc_can_param_find((uint16_t)id, &ref));
            assert_int_equal(ref.id, 0x1234u);
            unknown++;
        }
    }
}

static void test_wire_types(void **state)
{
    (void)state;
    assert_int_equal(mc_can_param_wire_type(MC_PARAM_F32), MC_CAN_PARAM_TYPE_F32);
    assert_int_equal(mc_can_param_wire_type(MC_PARAM_U32), MC_CAN_PARAM_TYPE_U32);
    assert_int_equal(mc_can_param_wire_type(MC_PARAM_BOOL), MC_CAN_PARAM_TYPE_BOOL);
    assert_int_equal(mc_can_param_wire_type(MC_PARAM_CONTROLLER), MC_CAN_PARAM_TYPE_U32);
    assert_int_equal(mc_can_param_wire_type(MC_PARAM_ESTIMATOR), MC_CAN_PARAM_TYPE_U32);
}

/* Set then get every parameter with seeded values of its type: the value
 * comes back, and no other byte of the configuration moved; the other wire
 * types are refused without a change. */
static void test_get_set_every_parameter(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(0xCA4A11u);
    mc_config_t cfg;
    mc_config_init_default(&cfg);
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            mc_can_param_ref_t ref;
            assert_true(mc_can_param_find(mc_can_param_id(b->name, p->name), &ref));
            mc_can_param_value_t v = { .type = mc_can_param_wire_type(p->type) };
            const uint64_t r = test_rng_next_u64(&rng.state);
            switch (p->type) {
            case MC_PARAM_F32: v.f32 = (float)test_rng_range(&rng, -1e6, 1e6); break;
            case MC_PARAM_U32: v.u32 = (uint32_t)r; break;
            case MC_PARAM_BOOL: v.b = (r & 1u) != 0u; break;
            case MC_PARAM_CONTROLLER: v.u32 = (uint32_t)(r % MC_CONTROLLER_COUNT); break;
            case MC_PARAM_ESTIMATOR: v.u32 = (uint32_t)(r % MC_ESTIMATOR_COUNT); break;
            }
            const mc_config_t before = cfg;
            assert_int_equal(mc_can_param_set(&cfg, &ref, &v), MC_OK);
            mc_can_param_value_t got;
            assert_int_equal(mc_can_param_get(&cfg, &ref, &got), MC_OK);
            assert_int_equal(got.type, v.type);
            switch (v.type) {
            case MC_CAN_PARAM_TYPE_F32: assert_int_equal(f32_bits(got.f32), f32_bits(v.f32)); break;
            case MC_CAN_PARAM_TYPE_U32: assert_int_equal(got.u32, v.u32); break;
            case MC_CAN_PARAM_TYPE_BOOL: assert_true(got.b == v.b); break;
            case MC_CAN_PARAM_TYPE_COUNT: fail();
            }
            /* only the field's bytes may differ */
            const size_t off = b->offset + p->offset, sz = mc_param_size(p->type);
            const uint8_t *x = (const uint8_t *)&before, *y = (const uint8_t *)&cfg;
            for (size_t i = 0; i < sizeof cfg; ++i) {
                if (i < off || i >= off + sz) {
                    assert_int_equal(x[i], y[i]);
                }
            }
            /* the other wire types: MC_ERR_PARAM, nothing written */
            const mc_config_t kept = cfg;
            for (int t = 0; t < 3; ++t) {
                if ((mc_can_param_type_t)t == v.type) {
                    continue;
                }
                const mc_can_param_value_t w = {
                    .type = (mc_can_param_type_t)t, .f32 = 1.0f, .u32 = 1u, .b = true
                };
                assert_int_equal(mc_can_param_set(&cfg, &ref, &w), MC_ERR_PARAM);
                assert_memory_equal(&cfg, &kept, sizeof cfg);
            }
            if (p->type == MC_PARAM_F32) {
                const float bad[] = { NAN, INFINITY, -INFINITY };
                for (int i = 0; i < 3; ++i) {
                    const mc_can_param_value_t w = { .type = MC_CAN_PARAM_TYPE_F32, .f32 = bad[i] };
                    assert_int_equal(mc_can_param_set(&cfg, &ref, &w), MC_ERR_NONFINITE);
                    assert_memory_equal(&cfg, &kept, sizeof cfg);
                }
            }
            if (p->type == MC_PARAM_CONTROLLER || p->type == MC_PARAM_ESTIMATOR) {
                const uint32_t count = (p->type == MC_PARAM_CONTROLLER)
                                           ? (uint32_t)MC_CONTROLLER_COUNT
                                           : (uint32_t)MC_ESTIMATOR_COUNT;
                const uint32_t bad[] = { count, count + 1u, 0xFFFFFFFFu };
                for (int i = 0; i < 3; ++i) {
                    const mc_can_param_value_t w = { .type = MC_CAN_PARAM_TYPE_U32, .u32 = bad[i] };
                    assert_int_equal(mc_can_param_set(&cfg, &ref, &w), MC_ERR_RANGE);
                    assert_memory_equal(&cfg, &kept, sizeof cfg);
                }
            }
        }
    }
}

/* A ref that does not lie inside mc_config_t is refused. */
static void test_bad_ref(void **state)
{
    (void)state;
    mc_config_t cfg;
    mc_config_init_default(&cfg);
    const mc_param_t far = { "far", MC_PARAM_F32, (uint32_t)sizeof(mc_config_t) - 2u };
    const mc_param_block_t top = { "", 0u, &far };
    const mc_can_param_ref_t ref = { &top, &far, 0u };
    mc_can_param_value_t v = { .type = MC_CAN_PARAM_TYPE_F32, .f32 = 1.0f };
    assert_int_equal(mc_can_param_get(&cfg, &ref, &v), MC_ERR_PARAM);
    assert_int_equal(mc_can_param_set(&cfg, &ref, &v), MC_ERR_PARAM);
    const mc_param_block_t huge = { "x", 0xFFFFFFF0u, &far };
    const mc_can_param_ref_t ref2 = { &huge, &far, 0u };
    assert_int_equal(mc_can_param_get(&cfg, &ref2, &v), MC_ERR_PARAM);
    const mc_can_param_ref_t null_ref = { NULL, NULL, 0u };
    assert_int_equal(mc_can_param_get(&cfg, &null_ref, &v), MC_ERR_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc16_check_value), cmocka_unit_test(test_ids_unique_and_found),
        cmocka_unit_test(test_wire_types),        cmocka_unit_test(test_get_set_every_parameter),
        cmocka_unit_test(test_bad_ref),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
