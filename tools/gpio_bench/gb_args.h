/*
 * pmsm-gpio-bench: the command line, parsed without touching any GPIO.
 */
#ifndef GB_ARGS_H
#define GB_ARGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Exit codes of pmsm-gpio-bench (README.md, "Exit codes"). */
enum {
    GB_EXIT_OK = 0,      /* done; every criterion given was met */
    GB_EXIT_FAIL = 1,    /* measurement failed, a criterion not met, GPIO error */
    GB_EXIT_USAGE = 2,   /* bad command line, or a chip path that is not there */
    GB_EXIT_NO_GPIO = 77 /* no GPIO chip on this machine (ctest: skipped) */
};

typedef enum { GB_CMD_NONE, GB_CMD_HELP, GB_CMD_STO, GB_CMD_ISR } gb_cmd_t;

typedef enum { GB_STO_ASSERT, GB_STO_RELEASE, GB_STO_PULSE } gb_sto_action_t;

#define GB_DEFAULT_CHIP         "/dev/gpiochip0"
#define GB_DEFAULT_GLITCH_NS    250
#define GB_MAX_SECONDS          600.0
#define GB_MAX_PULSE_MS         60000L
#define GB_MAX_HOLD_S           86400.0
#define GB_MAX_EXPECT_PERIOD_US 1.0e6

typedef struct {
    gb_cmd_t cmd;
    const char *chip;  /* --chip (default GB_DEFAULT_CHIP) */
    unsigned int line; /* --line (required) */
    bool active_low;   /* --active-low */
    /* sto */
    gb_sto_action_t sto_action;
    long pulse_ms; /* pulse MS */
    double hold_s; /* --hold S: assert/release held S s; 0: until SIGINT/SIGTERM */
    /* isr */
    double seconds;           /* --seconds (required) */
    int64_t expect_period_ns; /* --expect-period-us; 0: jitter against the mean */
    const char *json;         /* --json FILE, or NULL */
    int64_t glitch_ns;        /* --glitch-ns: high pulses shorter than this are glitches */
    int64_t bin_ns;           /* --bin-us; 0: adaptive (1 us, widened past 40 bins) */
    long max_lost;            /* --max-lost; -1: not a criterion */
    int64_t max_jitter_ns;    /* --max-jitter-us; -1: not a criterion */
} gb_args_t;

/* Parses argv (argv[0] is the program). Returns GB_EXIT_OK with *a filled
 * (a->cmd == GB_CMD_HELP for -h/--help), or GB_EXIT_USAGE with a one-line
 * reason in err (NUL-terminated, at most err_len bytes). Strings in *a point
 * into argv. */
int gb_args_parse(int argc, char **argv, gb_args_t *a, char *err, size_t err_len);

/* The usage text (several lines, ends with a newline). */
const char *gb_args_usage(void);

#endif /* GB_ARGS_H */
