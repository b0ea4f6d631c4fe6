/* The cost of a run, estimated before it starts (run_estimate.h). */
#include "run_estimate.h"

#include <math.h>
#include <string.h>

#include "run.h"
#include "trace_csv.h"

/* The CSV bytes of the whole trace (header included). */
static void estimate_csv(const scenario_t *s, run_estimate_t *e)
{
    e->csv_rows = (e->periods + s->trace_decimation - 1u) / s->trace_decimation;
    e->csv_row_bytes = trace_csv_row_bytes();
    size_t header = 0;
    for (size_t i = 0; i < trace_csv_column_count(); i++) {
        header += strlen(trace_csv_column_name(i)) + 1u; /* its comma or newline */
    }
    e->csv_bytes = (double)header + (double)e->csv_rows * (double)e->csv_row_bytes;
}

/* The first RUN_ESTIMATE_PILOT_PERIODS periods of s, timed. */
static bool run_pilot(const scenario_t *s, bool with_csv, bool keep_series, run_estimate_t *e,
                      char *msg, size_t msg_size)
{
    static scenario_t pilot; /* large: off the stack */
    pilot = *s;
    pilot.duration_s = (double)RUN_ESTIMATE_PILOT_PERIODS / s->plant.inverter.f_pwm_Hz;
    FILE *sink = NULL;
    if (with_csv && (sink = fopen("/dev/null", "w")) == NULL) {
        snprintf(msg, msg_size, "cannot open /dev/null for the pilot run's CSV");
        return false;
    }
    const run_options_t opt = { .csv = sink, .keep_series = keep_series };
    run_result_t res;
    const bool ok = run_scenario(&pilot, &opt, &res, msg, msg_size);
    if (sink != NULL) {
        fclose(sink);
    }
    run_result_free(&res);
    if (ok) {
        e->pilot_periods = res.periods;
        e->wall_per_period_s = res.wall_s / (double)res.periods;
        e->wall_s = e->wall_per_period_s * (double)e->periods;
    }
    return ok;
}

bool run_estimate(const scenario_t *s, bool with_csv, bool keep_series, run_estimate_t *e,
                  char *msg, size_t msg_size)
{
    *e = (run_estimate_t){ .sim_s = s->duration_s,
                           .f_pwm_Hz = s->plant.inverter.f_pwm_Hz,
                           .wall_s = NAN };
    e->periods = (uint64_t)llround(e->sim_s * e->f_pwm_Hz);
    if (with_csv) {
        estimate_csv(s, e);
    }
    return e->periods <= RUN_ESTIMATE_PILOT_PERIODS ||
           run_pilot(s, with_csv, keep_series, e, msg, msg_size);
}

void run_estimate_realtime(run_estimate_t *e)
{
    e->realtime = true;
    if (!(e->wall_s > e->sim_s)) { /* NAN without a pilot */
        e->wall_s = e->sim_s;
    }
}

double run_estimate_load(const run_estimate_t *e)
{
    return e->pilot_periods > 0 ? e->wall_per_period_s * e->f_pwm_Hz : NAN;
}

bool run_estimate_is_long(const run_estimate_t *e)
{
    return e->wall_s > RUN_ESTIMATE_LONG_WALL_S || e->csv_bytes > RUN_ESTIMATE_LONG_CSV_BYTES;
}

/* "11 h", "4.2 min", "35 s". */
static void duration_text(double s, char *buf, size_t size)
{
    if (s >= 3600.0) {
        snprintf(buf, size, "%.3g h", s / 3600.0);
    } else if (s >= 60.0) {
        snprintf(buf, size, "%.3g min", s / 60.0);
    } else {
        snprintf(buf, size, "%.3g s", s);
    }
}

/* "35 GB", "120 MB" (decimal units). */
static void bytes_text(double bytes, char *buf, size_t size)
{
    static const char *const units[] = { "bytes", "kB", "MB", "GB", "TB", "PB" };
    size_t u = 0;
    while (bytes >= 1000.0 && u + 1 < sizeof(units) / sizeof(units[0])) {
        bytes /= 1000.0;
        u++;
    }
    snprintf(buf, size, "%.3g %s", bytes, units[u]);
}

void run_estimate_print(FILE *f, const run_estimate_t *e)
{
    fprintf(f, "pmsm-sim: %s: %g s simulated = %.3g PWM periods at %g kHz; ",
            run_estimate_is_long(e) ? "a long run" : "the run", e->sim_s, (double)e->periods,
            e->f_pwm_Hz / 1e3);
    if (e->realtime) {
        char wall[32];
        duration_text(e->wall_s, wall, sizeof(wall));
        fprintf(f, "wall time about %s (paced to real time", wall);
        if (e->pilot_periods > 0) {
            fprintf(f,
                    "; the simulation needs %.3g us per period of %.3g us, measured on a pilot "
                    "run of its first %llu periods",
                    e->wall_per_period_s * 1e6, 1e6 / e->f_pwm_Hz,
                    (unsigned long long)e->pilot_periods);
        }
        fputs(")", f);
    } else if (e->pilot_periods > 0) {
        char wall[32];
        duration_text(e->wall_s, wall, sizeof(wall));
        fprintf(f,
                "wall time about %s (%.3g us per period, measured on a pilot run of its first "
                "%llu periods)",
                wall, e->wall_per_period_s * 1e6, (unsigned long long)e->pilot_periods);
    } else {
        fprintf(f, "wall time not measured (the run is no longer than the %u-period pilot)",
                (unsigned)RUN_ESTIMATE_PILOT_PERIODS);
    }
    if (e->csv_rows > 0) {
        char size[32];
        bytes_text(e->csv_bytes, size, sizeof(size));
        fprintf(f, "; CSV trace %.3g rows x %zu bytes = about %s", (double)e->csv_rows,
                e->csv_row_bytes, size);
    }
    fputs("\n", f);
}
