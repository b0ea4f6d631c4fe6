/* Text echoed in messages is terminal-safe (sim/text_escape.h), and a
 * scenario error made of hostile keys, values and file names renders as one
 * printable line (scenario_error_format). */
#include "mc_test.h"

#include <stdio.h>
#include <string.h>

#include "sim/scenario.h"
#include "sim/text_escape.h"

static void expect_escaped(const char *in, const char *want)
{
    char out[256];
    const size_t need = text_escape(in, out, sizeof out);
    assert_string_equal(out, want);
    assert_int_equal(need, strlen(want));
}

/* No byte below 0x20 or at 0x7f, and no C1 control encoded in UTF-8. */
static void assert_printable(const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p != '\0'; p++) {
        if (*p < 0x20u || *p == 0x7fu || (p[0] == 0xc2u && p[1] >= 0x80u && p[1] <= 0x9fu)) {
            fail_msg("raw control byte 0x%02x at %d of \"%s\"", *p,
                     (int)(p - (const unsigned char *)s), s);
        }
    }
}

static void control_characters(void **state)
{
    (void)state;
    expect_escaped("plain key_1.x[2]", "plain key_1.x[2]");
    expect_escaped("a\nb\tc\rd", "a\\nb\\tc\\rd");
    expect_escaped("\x1b[2J", "\\x1b[2J"); /* clear screen */
    expect_escaped("\x01\x7f", "\\x01\\x7f");
    expect_escaped("back\\slash", "back\\slash"); /* unchanged: idempotent */
}

static void utf8(void **state)
{
    (void)state;
    expect_escaped("M\xc3\xbcller \xe2\x82\xac", "M\xc3\xbcller \xe2\x82\xac"); /* printable */
    expect_escaped("\xc2\x9b"
                   "31m",
                   "\\xc2\\x9b31m"); /* C1 CSI */
    expect_escaped("a\xe2\x80\xae"
                   "b",
                   "a\\xe2\\x80\\xaeb");               /* RIGHT-TO-LEFT OVERRIDE */
    expect_escaped("\xe2\x80\xa8", "\\xe2\\x80\\xa8"); /* LINE SEPARATOR */
    expect_escaped("\xff\xfe", "\\xff\\xfe");          /* not UTF-8 */
    expect_escaped("\xc0\xaf", "\\xc0\\xaf");          /* overlong '/' */
    expect_escaped("\xed\xa0\x80", "\\xed\\xa0\\x80"); /* surrogate */
    expect_escaped("\xe2\x82", "\\xe2\\x82");          /* truncated */
}

static void idempotent_and_bounded(void **state)
{
    (void)state;
    const char *hostile = "k\x1b]0;title\x07\n\xc2\x85\xff";
    char once[128];
    char twice[128];
    text_escape(hostile, once, sizeof once);
    text_escape(once, twice, sizeof twice);
    assert_string_equal(once, twice);
    assert_printable(once);
    /* a small buffer keeps whole escapes only, and the need is reported */
    char small[6];
    assert_int_equal(text_escape("ab\ncd", small, sizeof small), 6u);
    assert_string_equal(small, "ab\\nc");
    assert_int_equal(text_escape("ab\ncd", small, 4), 6u);
    assert_string_equal(small, "ab"); /* not "ab\\" */
    assert_int_equal(text_escape("\x1b", small, 4), 4u);
    assert_string_equal(small, "");
}

/* A scenario with control characters in a key, in a string value and in
 * its file name: the error line shows them escaped. */
static void scenario_errors_are_escaped(void **state)
{
    (void)state;
    static scenario_t scn;
    scn_error_t err;
    char line[4096];
    const char *key_doc = "{\"format_version\": 2, \"duration_s\": 1,"
                          " \"motor\": {\"R_ohm\": 0.2, \"Ld_H\": 0.004, \"psi_Wb\": 0.17,"
                          " \"pole_pairs\": 3, \"J_kgm2\": 0.01, \"R\\u001b[2J\\nx\": 1},"
                          " \"reference\": {\"mode\": \"speed\", \"speed_rad_s\": 0}}";
    assert_false(scenario_load_text(key_doc, "dir/s\tc\x1b.json", NULL, 0, &scn, &err));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "motor.R\x1b[2J\nx"); /* the record keeps the raw key */
    scenario_error_format(&err, line, sizeof line);
    assert_printable(line);
    assert_non_null(strstr(line, "dir/s\\tc\\x1b.json: motor.R\\x1b[2J\\nx: unknown key"));
    const char *value_doc = "{\"format_version\": 2, \"duration_s\": 1,"
                            " \"motor\": {\"R_ohm\": 0.2, \"Ld_H\": 0.004, \"psi_Wb\": 0.17,"
                            " \"pole_pairs\": 3, \"J_kgm2\": 0.01},"
                            " \"reference\": {\"mode\": \"sp\\u0007eed\\r\\n\"}}";
    assert_false(scenario_load_text(value_doc, "v.json", NULL, 0, &scn, &err));
    scenario_error_format(&err, line, sizeof line);
    assert_printable(line);
    assert_non_null(strstr(line, "reference.mode: out of range"));
    assert_non_null(strstr(line, "found string \"sp\\x07eed\\r\\n\""));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(control_characters),
        cmocka_unit_test(utf8),
        cmocka_unit_test(idempotent_and_bounded),
        cmocka_unit_test(scenario_errors_are_escaped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
