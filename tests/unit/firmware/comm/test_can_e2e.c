/*
 * E2E protection of the telemetry (mc/can_e2e.h) against the test's own
 * bit-serial CRC-8/SAE-J1850 (can_bench.h): the check value, the CRC over
 * the data ID and bytes 1..7 for seeded random frames, detection of every
 * single-bit error, the length limits and the 0..14 counter.
 */
#include "can_bench.h"

#include "mc/can_e2e.h"
#include "test_rng.h"

static void test_crc8_check_value(void **state)
{
    (void)state;
    const uint8_t s[] = "123456789";
    assert_int_equal(mc_can_crc8_j1850(s, 9u), 0x4Bu);
    assert_int_equal(ref_crc8_j1850(s, 9u), 0x4Bu);
    assert_int_equal(mc_can_crc8_j1850(s, 0u), 0x00u); /* 0xFF ^ 0xFF */
}

static void test_e2e_against_reference(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(0xE2E0001u);
    for (int k = 0; k < 5000; ++k) {
        const uint64_t r = test_rng_next_u64(&rng.state);
        hal_can_frame_t f = { .id = (uint32_t)(r & 0x7FFu), .dlc = 8u };
        const uint64_t p = test_rng_next_u64(&rng.state);
        memcpy(f.data, &p, 8);
        assert_true(mc_can_e2e_protect(f.id, f.data, 8u));
        assert_true(ref_e2e_ok(&f));
        assert_true(mc_can_e2e_check(f.id, f.data, 8u));
        /* every single-bit error of bytes 1..7 and of the identifier */
        const unsigned bit = (unsigned)((r >> 16) % 56u);
        f.data[1 + bit / 8u] ^= (uint8_t)(1u << (bit % 8u));
        assert_false(mc_can_e2e_check(f.id, f.data, 8u));
        f.data[1 + bit / 8u] ^= (uint8_t)(1u << (bit % 8u));
        const unsigned idbit = (unsigned)((r >> 24) % 11u);
        assert_false(mc_can_e2e_check(f.id ^ (1u << idbit), f.data, 8u));
        f.data[0] ^= 1u;
        assert_false(mc_can_e2e_check(f.id, f.data, 8u));
    }
}

static void test_e2e_lengths(void **state)
{
    (void)state;
    uint8_t d[9] = { 0x55, 1, 2, 3, 4, 5, 6, 7, 8 };
    assert_false(mc_can_e2e_protect(0x123u, d, 0u));
    assert_false(mc_can_e2e_protect(0x123u, d, 9u));
    assert_int_equal(d[0], 0x55u); /* untouched */
    assert_false(mc_can_e2e_check(0x123u, d, 0u));
    assert_int_equal(mc_can_e2e_crc(0x123u, d, 9u), 0u);
    /* len 1: the data ID only */
    const uint8_t id_bytes[2] = { 0x23u, 0x01u };
    assert_true(mc_can_e2e_protect(0x123u, d, 1u));
    assert_int_equal(d[0], ref_crc8_j1850(id_bytes, 2u));
    /* len 4: bytes 1..3 */
    const uint8_t m[5] = { 0x23u, 0x01u, 1, 2, 3 };
    assert_true(mc_can_e2e_protect(0x123u, d, 4u));
    assert_int_equal(d[0], ref_crc8_j1850(m, 5u));
}

static void test_counter_wraps_at_14(void **state)
{
    (void)state;
    uint8_t c = 0u;
    for (int k = 1; k <= 45; ++k) {
        c = mc_can_e2e_counter_next(c);
        assert_int_equal(c, (uint32_t)(k % 15));
    }
    assert_int_equal(mc_can_e2e_counter_next(14u), 0u);
    assert_int_equal(mc_can_e2e_counter_next(15u), 0u);
    assert_int_equal(mc_can_e2e_counter_next(255u), 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc8_check_value),
        cmocka_unit_test(test_e2e_against_reference),
        cmocka_unit_test(test_e2e_lengths),
        cmocka_unit_test(test_counter_wraps_at_14),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
