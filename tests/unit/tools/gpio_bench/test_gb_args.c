/*
 * The command line of pmsm-gpio-bench (gb_args.c).
 */
#include "mc_test.h"

#include "gb_args.h"

#include <string.h>

static int parse(gb_args_t *a, char *why, int argc, char **argv)
{
    return gb_args_parse(argc, argv, a, why, 160);
}

#define PARSE(a, why, ...)                                                                         \
    parse((a), (why), (int)(sizeof((char *[]){ __VA_ARGS__ }) / sizeof(char *)),                   \
          (char *[]){ __VA_ARGS__ })

static void test_sto_forms(void **state)
{
    (void)state;
    gb_args_t a;
    char why[160];
    assert_int_equal(PARSE(&a, why, "b", "sto", "--chip", "/dev/gpiochip2", "--line", "17",
                           "--active-low", "pulse", "250"),
                     GB_EXIT_OK);
    assert_int_equal(a.cmd, GB_CMD_STO);
    assert_string_equal(a.chip, "/dev/gpiochip2");
    assert_int_equal(a.line, 17);
    assert_true(a.active_low);
    assert_int_equal(a.sto_action, GB_STO_PULSE);
    assert_int_equal(a.pulse_ms, 250);

    assert_int_equal(PARSE(&a, why, "b", "sto", "assert", "--line", "3", "--hold", "1.5"),
                     GB_EXIT_OK);
    assert_int_equal(a.sto_action, GB_STO_ASSERT);
    assert_string_equal(a.chip, GB_DEFAULT_CHIP);
    assert_near(a.hold_s, 1.5, 0.0);
    assert_false(a.active_low);

    assert_int_equal(PARSE(&a, why, "b", "sto", "--line", "3", "release"), GB_EXIT_OK);
    assert_int_equal(a.sto_action, GB_STO_RELEASE);
    assert_near(a.hold_s, 0.0, 0.0);
}

static void test_isr_forms(void **state)
{
    (void)state;
    gb_args_t a;
    char why[160];
    assert_int_equal(PARSE(&a, why, "b", "isr", "--line", "5", "--seconds", "2.5",
                           "--expect-period-us", "50", "--json", "out.json", "--glitch-ns", "0",
                           "--bin-us", "0.5", "--max-lost", "3", "--max-jitter-us", "1.25"),
                     GB_EXIT_OK);
    assert_int_equal(a.cmd, GB_CMD_ISR);
    assert_near(a.seconds, 2.5, 0.0);
    assert_int_equal(a.expect_period_ns, 50000);
    assert_string_equal(a.json, "out.json");
    assert_int_equal(a.glitch_ns, 0);
    assert_int_equal(a.bin_ns, 500);
    assert_int_equal(a.max_lost, 3);
    assert_int_equal(a.max_jitter_ns, 1250);

    assert_int_equal(PARSE(&a, why, "b", "isr", "--line", "5", "--seconds", "1"), GB_EXIT_OK);
    assert_int_equal(a.expect_period_ns, 0);
    assert_null(a.json);
    assert_int_equal(a.glitch_ns, GB_DEFAULT_GLITCH_NS);
    assert_int_equal(a.bin_ns, 0);
    assert_int_equal(a.max_lost, -1);
    assert_int_equal(a.max_jitter_ns, -1);
}

static void test_help(void **state)
{
    (void)state;
    gb_args_t a;
    char why[160];
    assert_int_equal(PARSE(&a, why, "b", "--help"), GB_EXIT_OK);
    assert_int_equal(a.cmd, GB_CMD_HELP);
    assert_int_equal(PARSE(&a, why, "b", "isr", "-h"), GB_EXIT_OK);
    assert_int_equal(a.cmd, GB_CMD_HELP);
    assert_non_null(strstr(gb_args_usage(), "77 no GPIO chip"));
}

/* Each bad command line is usage (2) with its reason. */
static void test_usage_errors(void **state)
{
    (void)state;
    gb_args_t a;
    char why[160];
#define BAD(reason, ...)                                                                           \
    do {                                                                                           \
        assert_int_equal(PARSE(&a, why, __VA_ARGS__), GB_EXIT_USAGE);                              \
        assert_non_null(strstr(why, reason));                                                      \
    } while (0)
    BAD("a command is required", "b");
    BAD("unknown command 'foo'", "b", "foo");
    BAD("--line OFFSET is required", "b", "sto", "assert");
    BAD("--line needs an offset", "b", "sto", "--line", "x", "assert");
    BAD("--line needs an offset", "b", "sto", "--line", "-1", "assert");
    BAD("--line needs an offset", "b", "sto", "--line");
    BAD("an action is required", "b", "sto", "--line", "1");
    BAD("one action only", "b", "sto", "--line", "1", "assert", "release");
    BAD("pulse needs a width", "b", "sto", "--line", "1", "pulse");
    BAD("pulse needs a width", "b", "sto", "--line", "1", "pulse", "0");
    BAD("pulse needs a width", "b", "sto", "--line", "1", "pulse", "1e3");
    BAD("--hold applies to assert and release", "b", "sto", "--line", "1", "--hold", "1", "pulse",
        "5");
    BAD("unknown argument '--seconds'", "b", "sto", "--line", "1", "--seconds", "1", "assert");
    BAD("--seconds S is required", "b", "isr", "--line", "1");
    BAD("--seconds needs a duration", "b", "isr", "--line", "1", "--seconds", "0");
    BAD("--seconds needs a duration", "b", "isr", "--line", "1", "--seconds", "nan");
    BAD("--seconds needs a duration", "b", "isr", "--line", "1", "--seconds", "601");
    BAD("--expect-period-us needs", "b", "isr", "--line", "1", "--seconds", "1",
        "--expect-period-us", "-5");
    BAD("--json needs a file name", "b", "isr", "--line", "1", "--seconds", "1", "--json");
    BAD("--chip needs a path", "b", "isr", "--chip", "", "--line", "1", "--seconds", "1");
    BAD("unknown argument 'assert'", "b", "isr", "--line", "1", "--seconds", "1", "assert");
#undef BAD
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sto_forms),
        cmocka_unit_test(test_isr_forms),
        cmocka_unit_test(test_help),
        cmocka_unit_test(test_usage_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
