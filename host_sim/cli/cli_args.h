/* Command line of pmsm-sim (the usage text is cli_print_help). */
#ifndef PMSM_SIM_CLI_ARGS_H
#define PMSM_SIM_CLI_ARGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define CLI_MAX_OVERRIDES 64

/* Exit codes. */
enum {
    CLI_EXIT_OK = 0,
    CLI_EXIT_RUN_FAILED = 1, /* engine error or an output could not be written */
    CLI_EXIT_USAGE = 2,      /* bad command line, or the --can interface
                                cannot be opened */
    CLI_EXIT_SCENARIO = 3,   /* scenario file unreadable or invalid */
    CLI_EXIT_OUTPUT = 4      /* an output cannot be written or the plotting environment
                                is missing: found before the run, nothing simulated */
};

typedef enum { CLI_HELP, CLI_RUN, CLI_BENCH, CLI_KEYS } cli_command_t;

typedef struct {
    cli_command_t command;
    const char *scenario;
    const char *overrides[CLI_MAX_OVERRIDES];
    size_t n_overrides;
    const char *csv; /* NULL: none */
    const char *json;
    const char *plot;
    bool quiet;
    bool dry_run; /* run: check everything and state the estimate, no run */
    /* run: the drive's CAN node on a SocketCAN interface */
    const char *can_ifname;                       /* --can IFNAME; NULL: no CAN node */
    uint32_t can_node_id;                         /* --can-node N (0) */
    double can_timeout_s;                         /* --can-timeout S (CLI_CAN_TIMEOUT_DEFAULT_S) */
    bool realtime;                                /* --realtime: paced to wall time */
    const char *can_node_text, *can_timeout_text; /* as given; NULL: not */
} cli_args_t;

#define CLI_CAN_TIMEOUT_DEFAULT_S 0.1
#define CLI_CAN_TIMEOUT_MAX_S     60.0 /* mc/can_node.h: (0, 60] */

/* Parse argv; false with msg on a usage error. */
bool cli_parse(int argc, char **argv, cli_args_t *out, char *msg, size_t msg_size);

void cli_print_help(FILE *f);

#endif /* PMSM_SIM_CLI_ARGS_H */
