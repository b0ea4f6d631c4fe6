/* pmsm-sim: run a scenario in closed loop, report its metrics, write a CSV
 * trace, JSON metrics and a plot; or benchmark the closed loop. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "cli_args.h"
#include "keys.h"
#include "plot.h"
#include "report.h"
#include "run.h"

#define MSG_MAX 2048

static int fail(int code, const char *msg)
{
    fprintf(stderr, "pmsm-sim: error: %s\n", msg);
    return code;
}

/* The CSV the run writes: the user's, or a temporary one for the plot. */
static FILE *open_csv(const cli_args_t *args, char *tmp_path, size_t tmp_size)
{
    tmp_path[0] = '\0';
    if (args->csv != NULL) {
        return fopen(args->csv, "w");
    }
    if (args->plot == NULL) {
        return NULL;
    }
    const char *dir = getenv("TMPDIR");
    snprintf(tmp_path, tmp_size, "%s/pmsm-sim-trace-XXXXXX", dir != NULL ? dir : "/tmp");
    int fd = mkstemp(tmp_path);
    return fd >= 0 ? fdopen(fd, "w") : NULL;
}

static int write_outputs(const cli_args_t *args, const scenario_t *s, const run_result_t *res,
                         const char *csv_path, char *msg)
{
    report_t rep;
    report_compute(s, res, &rep);
    if (!args->quiet) {
        report_print_table(stdout, s, res, &rep);
    }
    if (args->json != NULL &&
        !report_write_json(args->json, args->scenario, s, res, &rep, msg, MSG_MAX)) {
        return CLI_EXIT_RUN_FAILED;
    }
    if (args->plot != NULL && !plot_trace(csv_path, args->plot, s->name, msg, MSG_MAX)) {
        return CLI_EXIT_RUN_FAILED;
    }
    return CLI_EXIT_OK;
}

static int command_run(const cli_args_t *args, const scenario_t *s, char *msg)
{
    char tmp_csv[4096];
    FILE *csv = open_csv(args, tmp_csv, sizeof(tmp_csv));
    if ((args->csv != NULL || args->plot != NULL) && csv == NULL) {
        snprintf(msg, MSG_MAX, "cannot open the CSV trace file %.1000s",
                 args->csv != NULL ? args->csv : tmp_csv);
        return CLI_EXIT_RUN_FAILED;
    }
    const run_options_t opt = { .csv = csv, .keep_series = true, .progress = !args->quiet };
    run_result_t res;
    int code = run_scenario(s, &opt, &res, msg, MSG_MAX) ? CLI_EXIT_OK : CLI_EXIT_RUN_FAILED;
    if (csv != NULL && fclose(csv) != 0 && code == CLI_EXIT_OK) {
        snprintf(msg, MSG_MAX, "cannot write the CSV trace");
        code = CLI_EXIT_RUN_FAILED;
    }
    if (code == CLI_EXIT_OK) {
        code = write_outputs(args, s, &res, args->csv != NULL ? args->csv : tmp_csv, msg);
    }
    if (tmp_csv[0] != '\0') {
        unlink(tmp_csv);
    }
    run_result_free(&res);
    return code;
}

static int command_bench(const cli_args_t *args, const scenario_t *s, char *msg)
{
    const run_options_t opt = { .csv = NULL, .keep_series = false, .progress = !args->quiet };
    run_result_t res;
    bool ok = run_scenario(s, &opt, &res, msg, MSG_MAX);
    run_result_free(&res);
    if (!ok) {
        return CLI_EXIT_RUN_FAILED;
    }
    printf("bench %s: %.3f s simulated in %.3f s wall = %.3f simulated s per wall s "
           "(%.0f PWM periods/s)\n",
           s->name, res.sim_s, res.wall_s, res.sim_s / res.wall_s,
           (double)res.periods / res.wall_s);
    printf("method: one engine step per PWM period (plant RK4 with %u substeps, host HAL,\n"
           "        firmware fast ISR with its decimated slow loop), single thread; wall time\n"
           "        of the step loop by CLOCK_MONOTONIC, excluding scenario loading, metrics\n"
           "        and outputs; one run, so repeat it to see the spread\n",
           (unsigned)s->plant.substeps_per_period);
    printf("firmware ISR cost (host CPU time) mean %.2f us, max %.2f us\n",
           1e6 * res.isr_cost_mean_s, 1e6 * res.isr_cost_max_s);
    return CLI_EXIT_OK;
}

int main(int argc, char **argv)
{
    static char msg[MSG_MAX];
    cli_args_t args;
    if (!cli_parse(argc, argv, &args, msg, sizeof(msg))) {
        fprintf(stderr, "pmsm-sim: %s (see pmsm-sim --help)\n", msg);
        return CLI_EXIT_USAGE;
    }
    if (args.command == CLI_HELP) {
        cli_print_help(stdout);
        return CLI_EXIT_OK;
    }
    if (args.command == CLI_KEYS) {
        keys_print(stdout);
        return CLI_EXIT_OK;
    }
    static scenario_t scenario;
    scn_error_t err;
    if (!scenario_load(args.scenario, args.overrides, args.n_overrides, &scenario, &err)) {
        scenario_error_format(&err, msg, sizeof(msg));
        return fail(CLI_EXIT_SCENARIO, msg);
    }
    int code = args.command == CLI_RUN ? command_run(&args, &scenario, msg)
                                       : command_bench(&args, &scenario, msg);
    return code == CLI_EXIT_OK ? code : fail(code, msg);
}
