/* Command line of pmsm-sim. */
#include "cli_args.h"

#include "mc/can_node.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void cli_print_help(FILE *f)
{
    fputs(
        "usage: pmsm-sim run SCENARIO.json [--set KEY.PATH=VALUE ...] [--csv FILE]\n"
        "                    [--json FILE] [--plot FILE.png] [--quiet] [--dry-run]\n"
        "                    [--can IFNAME [--can-node N] [--can-timeout S]] [--realtime]\n"
        "       pmsm-sim bench SCENARIO.json [--set KEY.PATH=VALUE ...] [--quiet]\n"
        "       pmsm-sim keys\n"
        "       pmsm-sim --help\n"
        "\n"
        "run     simulate the scenario in closed loop (plant + host HAL + drive firmware,\n"
        "        one fast ISR per PWM period) and print its metrics: rise/settling time,\n"
        "        overshoot, offset error, fluctuation and fluctuation rate (paper 002),\n"
        "        RMS tracking error, load-step dips, peak phase current/voltage per phase\n"
        "        of the run (start, hold, profile, after a fault), ISR cost, faults.\n"
        "        Progress goes to stderr when a run takes more than 2 s.\n"
        "bench   simulate the scenario without outputs and report simulated seconds per\n"
        "        wall-clock second of the step loop.\n"
        "keys    list the keys of the scenario's firmware section (taken from the\n"
        "        firmware's parameter table) with their types and defaults, the plant\n"
        "        keys whose range is the firmware's (sensors.encoder.lines, ...), and\n"
        "        the columns of the CSV trace.\n"
        "\n"
        "options:\n"
        "  --set KEY.PATH=VALUE  override a scenario key before validation (repeatable);\n"
        "                        VALUE is JSON (0.3, [1, 2], true), else a string;\n"
        "                        arrays are indexed as KEY[i] (reference.speed_rpm.points[2][1])\n"
        "  --csv FILE            write the trace (one row every output.trace_decimation periods)\n"
        "  --json FILE           write the metrics as JSON\n"
        "  --plot FILE.png       plot the trace with tools/plot_trace.py (project .venv;\n"
        "                        PMSM_SIM_PYTHON / PMSM_SIM_PLOT_SCRIPT override the paths)\n"
        "  --quiet               no table, no progress (errors, warnings and the estimate of a\n"
        "                        long run are still reported)\n"
        "  --dry-run             check the scenario, the outputs, the plotting environment and\n"
        "                        the --can interface, print the run's estimate (simulated and\n"
        "                        wall time, CSV size) on stdout, and stop: only the pilot runs,\n"
        "                        nothing is written\n"
        "  --can IFNAME          give the drive its CAN node (protocol tools/dbc/pmsm_drive.dbc)\n"
        "                        on the SocketCAN interface IFNAME (vcan0, can0; Linux): the\n"
        "                        drive's commands then come over CAN, NOT from the scenario's\n"
        "                        reference; it starts disabled and waits for Cmd_Enable. The\n"
        "                        run lasts duration_s, the fault injections still act; the\n"
        "                        metrics against the reference are not computed (the table\n"
        "                        and JSON keep the phases, ISR cost, faults and CAN counts)\n"
        "  --can-node N          its node id, 0..63: identifiers N*32 + message (default 0)\n"
        "  --can-timeout S       its command timeout while enabled, in (0, 60] s (default 0.1)\n"
        "  --realtime            pace the run to wall time (CLOCK_MONOTONIC, a sleep per batch\n"
        "                        of PWM periods of 1 ms); the summary and JSON count the missed\n"
        "                        periods (reached over one period after their due time).\n"
        "                        Without it a --can run goes as fast as the machine can, so a\n"
        "                        host on the bus sees the drive's time run faster than its own\n"
        "\n"
        "Before a run the outputs are checked (directory exists and is writable, not the\n"
        "scenario file, no two the same) and, with --plot, the plotting environment; each\n"
        "file is written next to its target and moved there only when the whole run and\n"
        "every output succeeded, so a failure leaves no partial file. The wall time of a\n"
        "run is measured on a short pilot run of its first PWM periods; a run estimated\n"
        "to take over a minute, or to write over 1 GB of CSV, states its simulated time,\n"
        "wall time and trace size on stderr first.\n"
        "\n"
        "scenario format: host_sim/scenarios/README.md\n"
        "CAN: this needs a kernel with SocketCAN (vcan: ip link add dev vcan0 type vcan &&\n"
        "ip link set up vcan0); see the CAN section of host_sim/scenarios/README.md.\n"
        "\n"
        "exit status: 0 ok, 1 simulation or output failed, 2 bad command line or the --can\n"
        "               interface cannot be opened (no CAN in the kernel, no such interface),\n"
        "             3 scenario unreadable or invalid (the message names file and key),\n"
        "             4 an output cannot be written or the plotting environment is missing\n"
        "               (found before the run); a run stopped by SIGINT, SIGTERM or SIGHUP\n"
        "               removes its unfinished outputs and ends by that signal\n",
        f);
}

/* The value of an option that takes one (argv[*i + 1]). */
static const char *option_value(int argc, char **argv, int *i, char *msg, size_t msg_size)
{
    if (*i + 1 >= argc) {
        snprintf(msg, msg_size, "option %s needs a value", argv[*i]);
        return NULL;
    }
    *i += 1;
    return argv[*i];
}

static bool parse_option(int argc, char **argv, int *i, cli_args_t *out, char *msg, size_t msg_size)
{
    const char *opt = argv[*i];
    if (strcmp(opt, "--quiet") == 0) {
        out->quiet = true;
        return true;
    }
    if (out->command == CLI_RUN && strcmp(opt, "--dry-run") == 0) {
        out->dry_run = true;
        return true;
    }
    if (out->command == CLI_RUN && strcmp(opt, "--realtime") == 0) {
        out->realtime = true;
        return true;
    }
    const char **slot = NULL;
    if (strcmp(opt, "--set") == 0) {
        if (out->n_overrides == CLI_MAX_OVERRIDES) {
            snprintf(msg, msg_size, "more than %d --set options", CLI_MAX_OVERRIDES);
            return false;
        }
        slot = &out->overrides[out->n_overrides++];
    } else if (out->command == CLI_RUN && strcmp(opt, "--csv") == 0) {
        slot = &out->csv;
    } else if (out->command == CLI_RUN && strcmp(opt, "--json") == 0) {
        slot = &out->json;
    } else if (out->command == CLI_RUN && strcmp(opt, "--plot") == 0) {
        slot = &out->plot;
    } else if (out->command == CLI_RUN && strcmp(opt, "--can") == 0) {
        slot = &out->can_ifname;
    } else if (out->command == CLI_RUN && strcmp(opt, "--can-node") == 0) {
        slot = &out->can_node_text;
    } else if (out->command == CLI_RUN && strcmp(opt, "--can-timeout") == 0) {
        slot = &out->can_timeout_text;
    } else if (out->command == CLI_BENCH &&
               (strcmp(opt, "--can") == 0 || strcmp(opt, "--can-node") == 0 ||
                strcmp(opt, "--can-timeout") == 0 || strcmp(opt, "--realtime") == 0)) {
        snprintf(msg, msg_size, "%s is an option of run, not of bench", opt);
        return false;
    } else {
        snprintf(msg, msg_size, "unknown option %s", opt);
        return false;
    }
    if (*slot != NULL) {
        snprintf(msg, msg_size, "%s given twice", opt);
        return false;
    }
    *slot = option_value(argc, argv, i, msg, msg_size);
    return *slot != NULL;
}

/* --can-node and --can-timeout: their values, and --can with them. */
static bool parse_can(cli_args_t *out, char *msg, size_t msg_size)
{
    out->can_node_id = 0;
    out->can_timeout_s = CLI_CAN_TIMEOUT_DEFAULT_S;
    if (out->can_ifname == NULL) {
        const char *alone = out->can_node_text != NULL      ? "--can-node"
                            : out->can_timeout_text != NULL ? "--can-timeout"
                                                            : NULL;
        if (alone != NULL) {
            snprintf(msg, msg_size, "%s needs --can IFNAME", alone);
            return false;
        }
        return true;
    }
    if (out->can_ifname[0] == '\0') {
        snprintf(msg, msg_size, "--can needs an interface name (vcan0, can0)");
        return false;
    }
    char *end;
    if (out->can_node_text != NULL) {
        errno = 0;
        const unsigned long n = strtoul(out->can_node_text, &end, 10);
        if (errno != 0 || end == out->can_node_text || *end != '\0' ||
            out->can_node_text[0] == '-' || n > MC_CAN_NODE_ID_MAX) {
            snprintf(msg, msg_size, "--can-node '%.40s' is not a node id 0..%u", out->can_node_text,
                     (unsigned)MC_CAN_NODE_ID_MAX);
            return false;
        }
        out->can_node_id = (uint32_t)n;
    }
    if (out->can_timeout_text != NULL) {
        const double t = strtod(out->can_timeout_text, &end);
        if (end == out->can_timeout_text || *end != '\0' || !isfinite(t) || !(t > 0.0) ||
            t > CLI_CAN_TIMEOUT_MAX_S) {
            snprintf(msg, msg_size, "--can-timeout '%.40s' is not a time in (0, %g] s",
                     out->can_timeout_text, CLI_CAN_TIMEOUT_MAX_S);
            return false;
        }
        out->can_timeout_s = t;
    }
    return true;
}

bool cli_parse(int argc, char **argv, cli_args_t *out, char *msg, size_t msg_size)
{
    *out = (cli_args_t){ .command = CLI_HELP };
    if (argc < 2) {
        snprintf(msg, msg_size, "missing command");
        return false;
    }
    const char *command = argv[1];
    if (strcmp(command, "--help") == 0 || strcmp(command, "-h") == 0 ||
        strcmp(command, "help") == 0) {
        return true;
    }
    if (strcmp(command, "run") == 0) {
        out->command = CLI_RUN;
    } else if (strcmp(command, "bench") == 0) {
        out->command = CLI_BENCH;
    } else if (strcmp(command, "keys") == 0) {
        out->command = CLI_KEYS;
        if (argc > 2) {
            snprintf(msg, msg_size, "keys takes no argument, found '%s'", argv[2]);
            return false;
        }
        return true;
    } else {
        snprintf(msg, msg_size, "unknown command '%s'", command);
        return false;
    }
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            out->command = CLI_HELP;
            return true;
        }
        if (strncmp(argv[i], "--", 2) == 0) {
            if (!parse_option(argc, argv, &i, out, msg, msg_size)) {
                return false;
            }
        } else if (out->scenario == NULL) {
            out->scenario = argv[i];
        } else {
            snprintf(msg, msg_size, "unexpected argument '%s'", argv[i]);
            return false;
        }
    }
    if (out->scenario == NULL) {
        snprintf(msg, msg_size, "missing SCENARIO file");
        return false;
    }
    return parse_can(out, msg, msg_size);
}
