/* pmsm-sim: run a scenario in closed loop, report its metrics, write a CSV
 * trace, JSON metrics and a plot; or benchmark the closed loop. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_args.h"
#include "hal_host.h"
#include "keys.h"
#include "outputs.h"
#include "plot.h"
#include "report.h"
#include "run.h"
#include "run_estimate.h"
#include "sim/text_escape.h"
#include "socketcan.h"

#define MSG_MAX 2048

/* The signal that asked the run to stop (0: none). */
static volatile sig_atomic_t stop_signal;

static void on_stop_signal(int signo)
{
    stop_signal = signo;
}

/* SIGINT, SIGTERM, SIGHUP end the run at the next check, so that the
 * staged outputs are removed before the process ends by that signal. */
static void catch_stop_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    const int signals[] = { SIGINT, SIGTERM, SIGHUP };
    for (size_t i = 0; i < sizeof(signals) / sizeof(signals[0]); i++) {
        sigaction(signals[i], &sa, NULL);
    }
}

/* After the cleanup: end by the signal that stopped the run, if one did. */
static void reraise_stop_signal(void)
{
    if (stop_signal != 0) {
        signal(stop_signal, SIG_DFL);
        raise(stop_signal);
    }
}

/* One error line on stderr; echoed names and values escaped
 * (sim/text_escape.h). */
static int fail(int code, const char *prefix, const char *msg)
{
    static char escaped[4 * MSG_MAX];
    text_escape(msg, escaped, sizeof(escaped));
    fprintf(stderr, "pmsm-sim: %s%s\n", prefix, escaped);
    return code;
}

static int write_outputs(const cli_args_t *args, const outputs_t *out, const scenario_t *s,
                         const run_result_t *res, char *msg)
{
    report_t rep;
    report_compute(s, res, &rep);
    if (!args->quiet) {
        report_print_table(stdout, s, res, &rep);
    }
    if (args->json != NULL && !report_write_json(outputs_path(out, OUTPUT_JSON), args->scenario, s,
                                                 res, &rep, msg, MSG_MAX)) {
        return CLI_EXIT_RUN_FAILED;
    }
    if (args->plot != NULL && !plot_trace(outputs_path(out, OUTPUT_CSV),
                                          outputs_path(out, OUTPUT_PLOT), s->name, msg, MSG_MAX)) {
        return CLI_EXIT_RUN_FAILED;
    }
    return CLI_EXIT_OK;
}

/* The CAN node of --can: the firmware's default with the node id and the
 * command timeout of the command line. */
static mc_can_node_config_t can_config(const cli_args_t *args)
{
    mc_can_node_config_t cfg;
    mc_can_node_config_default(&cfg);
    cfg.node_id = args->can_node_id;
    cfg.timeout_s = (float)args->can_timeout_s;
    return cfg;
}

/* The run and its outputs into the staged files. */
static int run_into(const cli_args_t *args, const outputs_t *out, const scenario_t *s,
                    hal_socketcan_t *can, char *msg)
{
    const char *csv_path = outputs_path(out, OUTPUT_CSV);
    FILE *csv = NULL;
    if (csv_path[0] != '\0' && (csv = fopen(csv_path, "w")) == NULL) {
        snprintf(msg, MSG_MAX, "cannot open the CSV trace file %.1000s", csv_path);
        return CLI_EXIT_RUN_FAILED;
    }
    run_options_t opt = { .csv = csv,
                          .keep_series = can == NULL,
                          .progress = !args->quiet,
                          .stop = &stop_signal,
                          .realtime = args->realtime,
                          .can = can };
    if (can != NULL) {
        opt.can_cfg = can_config(args);
    }
    run_result_t res;
    int code = run_scenario(s, &opt, &res, msg, MSG_MAX) ? CLI_EXIT_OK : CLI_EXIT_RUN_FAILED;
    if (csv != NULL && (ferror(csv) || fclose(csv) != 0) && code == CLI_EXIT_OK) {
        snprintf(msg, MSG_MAX, "cannot write the CSV trace %.1000s",
                 args->csv != NULL ? args->csv : csv_path);
        code = CLI_EXIT_RUN_FAILED;
    }
    if (code == CLI_EXIT_OK) {
        code = write_outputs(args, out, s, &res, msg);
    }
    run_result_free(&res);
    return code;
}

/* What --can and --realtime mean for this run, on stderr before it: the
 * command source (unless --quiet), and the warnings: --can running faster
 * than real time, --realtime on a machine too slow for it. */
static void state_run_mode(const cli_args_t *args, const run_estimate_t *est)
{
    const double load = run_estimate_load(est);
    if (args->can_ifname != NULL && !args->quiet) {
        const unsigned first = (unsigned)args->can_node_id << 5;
        char ifname[4 * HAL_SOCKETCAN_IFNAME_MAX];
        text_escape(args->can_ifname, ifname, sizeof(ifname));
        fprintf(stderr,
                "pmsm-sim: CAN node %u on %s (identifiers 0x%03X-0x%03X), command timeout %g s: "
                "the drive's commands come over CAN, not from the scenario's reference; it "
                "starts disabled\n",
                (unsigned)args->can_node_id, ifname, first, first + 31u, args->can_timeout_s);
    }
    if (args->can_ifname != NULL && !args->realtime) {
        fprintf(stderr, "pmsm-sim: warning: --can without --realtime: the run goes as fast as "
                        "this machine can");
        if (isfinite(load) && load > 0.0) {
            fprintf(stderr, " (about %.3g x real time)", 1.0 / load);
        }
        fprintf(stderr, ", so a host on the bus sees the drive's time run faster than its own "
                        "(command timeout, telemetry rates); add --realtime to pace it\n");
    }
    if (args->realtime && isfinite(load) && load > 1.0) {
        fprintf(stderr,
                "pmsm-sim: warning: --realtime: this machine needs about %.3g us per PWM period "
                "of %.3g us, so the run cannot keep up and will miss periods\n",
                est->wall_per_period_s * 1e6, 1e6 / est->f_pwm_Hz);
    }
}

/* Outputs checked and staged, the plotting environment checked, the cost
 * stated (all before the run); the staged files moved onto their targets
 * only when everything succeeded. */
static int command_run_on(const cli_args_t *args, const scenario_t *s, hal_socketcan_t *can,
                          char *msg)
{
    outputs_t out;
    if (!outputs_prepare(&out, args, msg, MSG_MAX)) {
        return CLI_EXIT_OUTPUT;
    }
    if (args->plot != NULL && !plot_check_environment(msg, MSG_MAX)) {
        outputs_discard(&out);
        return CLI_EXIT_OUTPUT;
    }
    run_estimate_t est;
    if (!run_estimate(s, outputs_path(&out, OUTPUT_CSV)[0] != '\0', can == NULL, &est, msg,
                      MSG_MAX)) {
        outputs_discard(&out);
        return CLI_EXIT_RUN_FAILED;
    }
    if (args->realtime) {
        run_estimate_realtime(&est);
        /* paced next to other processes (a CAN harness): the ISR cost is
         * the simulator thread's own CPU time (hal_host.h) */
        hal_host_cycle_counter_thread_time(true);
    }
    if (args->dry_run) {
        run_estimate_print(stdout, &est);
        outputs_discard(&out);
        return CLI_EXIT_OK;
    }
    if (run_estimate_is_long(&est)) {
        run_estimate_print(stderr, &est);
    }
    state_run_mode(args, &est);
    catch_stop_signals();
    int code = run_into(args, &out, s, can, msg);
    if (code == CLI_EXIT_OK && !outputs_commit(&out, msg, MSG_MAX)) {
        code = CLI_EXIT_RUN_FAILED;
    }
    if (code != CLI_EXIT_OK) {
        outputs_discard(&out);
    }
    return code;
}

/* With --can, the interface first: one that cannot be opened (no CAN in
 * the kernel, no such interface) is a usage error, found before anything
 * else is done. */
static int command_run(const cli_args_t *args, const scenario_t *s, char *msg)
{
    static hal_socketcan_t bridge;
    if (args->can_ifname == NULL) {
        return command_run_on(args, s, NULL, msg);
    }
    if (hal_socketcan_open(&bridge, args->can_ifname, args->can_node_id) != 0) {
        snprintf(msg, MSG_MAX, "%s", hal_socketcan_message(&bridge));
        return CLI_EXIT_USAGE;
    }
    const int code = command_run_on(args, s, &bridge, msg);
    hal_socketcan_close(&bridge);
    return code;
}

static int command_bench(const cli_args_t *args, const scenario_t *s, char *msg)
{
    run_estimate_t est;
    if (!run_estimate(s, false, false, &est, msg, MSG_MAX)) {
        return CLI_EXIT_RUN_FAILED;
    }
    if (run_estimate_is_long(&est)) {
        run_estimate_print(stderr, &est);
    }
    catch_stop_signals();
    const run_options_t opt = {
        .csv = NULL, .keep_series = false, .progress = !args->quiet, .stop = &stop_signal
    };
    run_result_t res;
    bool ok = run_scenario(s, &opt, &res, msg, MSG_MAX);
    run_result_free(&res);
    if (!ok) {
        return CLI_EXIT_RUN_FAILED;
    }
    char name[4 * SCENARIO_NAME_MAX];
    text_escape(s->name, name, sizeof(name));
    printf("bench %s: %.3f s simulated in %.3f s wall = %.3f simulated s per wall s "
           "(%.0f PWM periods/s)\n",
           name, res.sim_s, res.wall_s, res.sim_s / res.wall_s, (double)res.periods / res.wall_s);
    const plant_config_t *pc = &s->plant;
    const bool exact = pc->solver_method == PLANT_SOLVER_EXACT && pc->motor.Ld_H == pc->motor.Lq_H;
    printf("method: one engine step per PWM period (plant %s with %u substeps, host HAL,\n"
           "        firmware fast ISR with its decimated slow loop), single thread; wall time\n"
           "        of the step loop by CLOCK_MONOTONIC, excluding scenario loading, metrics\n"
           "        and outputs; one run, so repeat it to see the spread\n",
           exact ? "exact (RK4 where not linear)" : "RK4", (unsigned)pc->substeps_per_period);
    printf("firmware ISR cost (host wall time) mean %.2f us, max %.2f us\n",
           1e6 * res.isr_cost_mean_s, 1e6 * res.isr_cost_max_s);
    return CLI_EXIT_OK;
}

int main(int argc, char **argv)
{
    static char msg[MSG_MAX];
    cli_args_t args;
    if (!cli_parse(argc, argv, &args, msg, sizeof(msg))) {
        static char usage[MSG_MAX + 32];
        snprintf(usage, sizeof(usage), "%s (see pmsm-sim --help)", msg);
        return fail(CLI_EXIT_USAGE, "", usage);
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
        return fail(CLI_EXIT_SCENARIO, "error: ", msg);
    }
    int code = args.command == CLI_RUN ? command_run(&args, &scenario, msg)
                                       : command_bench(&args, &scenario, msg);
    if (code == CLI_EXIT_OK) {
        return code;
    }
    fail(code, "error: ", msg);
    reraise_stop_signal();
    return code;
}
