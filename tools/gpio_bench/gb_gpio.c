/*
 * pmsm-gpio-bench: libgpiod v2 calls (chip, line request, values, edge
 * events) and the monotonic clock. Kept thin: no measurement logic here.
 */
#define _POSIX_C_SOURCE 200809L

#include "gb_gpio.h"

#include <dirent.h>
#include <errno.h>
#include <gpiod.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#define GB_CONSUMER      "pmsm-gpio-bench"
#define GB_EVENT_BUF     1024        /* the most libgpiod and the kernel buffer */
#define GB_WAIT_SLICE_NS 100000000LL /* 100 ms: signals seen that soon */
#define GB_NS_PER_S      1000000000LL

static volatile sig_atomic_t gb_stop_requested;

static void on_signal(int sig)
{
    (void)sig;
    gb_stop_requested = 1;
}

typedef struct {
    struct sigaction old_int;
    struct sigaction old_term;
} gb_signals_t;

static void signals_catch(gb_signals_t *s)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    gb_stop_requested = 0;
    sigaction(SIGINT, &sa, &s->old_int);
    sigaction(SIGTERM, &sa, &s->old_term);
}

static void signals_restore(const gb_signals_t *s)
{
    sigaction(SIGINT, &s->old_int, NULL);
    sigaction(SIGTERM, &s->old_term, NULL);
}

static int64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * GB_NS_PER_S + ts.tv_nsec;
}

/* Sleeps until the monotonic time t_ns or a stop signal. */
static void sleep_until(int64_t t_ns)
{
    const struct timespec ts = { .tv_sec = (time_t)(t_ns / GB_NS_PER_S),
                                 .tv_nsec = (long)(t_ns % GB_NS_PER_S) };
    while (!gb_stop_requested &&
           clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

/* Lists the gpiochip* entries of the folder of path into buf ("" if none). */
static void list_chips(const char *path, char *buf, size_t len)
{
    char dir[256];
    const char *slash = strrchr(path, '/');
    if (slash == NULL) {
        snprintf(dir, sizeof(dir), ".");
    } else if (slash == path) {
        snprintf(dir, sizeof(dir), "/");
    } else {
        snprintf(dir, sizeof(dir), "%.*s", (int)(slash - path), path);
    }
    buf[0] = '\0';
    DIR *d = opendir(dir);
    if (d == NULL) {
        return;
    }
    size_t used = 0;
    for (struct dirent *de = readdir(d); de != NULL; de = readdir(d)) {
        if (strncmp(de->d_name, "gpiochip", 8) != 0 || used + 1 >= len) {
            continue;
        }
        const int n = snprintf(buf + used, len - used, "%s%s", (used > 0) ? " " : "", de->d_name);
        used = (n > 0 && (size_t)n < len - used) ? used + (size_t)n : len - 1;
    }
    closedir(d);
}

/* Opens the chip, or says why not: 77 when this machine has no GPIO chip,
 * 2 when the path is wrong (another chip is there, or it is no chip), 1
 * otherwise (permissions, ...). */
static struct gpiod_chip *open_chip(const char *path, int *code, FILE *err)
{
    struct gpiod_chip *chip = gpiod_chip_open(path);
    if (chip != NULL) {
        *code = GB_EXIT_OK;
        return chip;
    }
    const int e = errno;
    if (e == ENOENT) {
        char chips[256];
        list_chips(path, chips, sizeof(chips));
        if (chips[0] == '\0') {
            fprintf(err,
                    "pmsm-gpio-bench: no GPIO chip %s: %s (this machine has no GPIO; run on the "
                    "bench host)\n",
                    path, strerror(e));
            *code = GB_EXIT_NO_GPIO;
        } else {
            fprintf(err, "pmsm-gpio-bench: no GPIO chip %s: %s (chips there: %s)\n", path,
                    strerror(e), chips);
            *code = GB_EXIT_USAGE;
        }
    } else if (e == ENODEV || e == ENOTTY) {
        fprintf(err, "pmsm-gpio-bench: %s is not a GPIO chip: %s\n", path, strerror(e));
        *code = GB_EXIT_USAGE;
    } else {
        fprintf(err, "pmsm-gpio-bench: cannot open %s: %s%s\n", path, strerror(e),
                (e == EACCES || e == EPERM) ? " (needs read-write access: root or group gpio)"
                                            : "");
        *code = GB_EXIT_FAIL;
    }
    return NULL;
}

/* One line requested with settings already filled in; NULL with a message. */
static struct gpiod_line_request *request_line(struct gpiod_chip *chip, const gb_args_t *a,
                                               struct gpiod_line_settings *settings,
                                               size_t event_buffer_size, FILE *err)
{
    struct gpiod_line_request *req = NULL;
    struct gpiod_line_config *line_cfg = gpiod_line_config_new();
    struct gpiod_request_config *req_cfg = gpiod_request_config_new();
    if (line_cfg == NULL || req_cfg == NULL) {
        fprintf(err, "pmsm-gpio-bench: out of memory\n");
        goto out;
    }
    const unsigned int offset = a->line;
    if (gpiod_line_config_add_line_settings(line_cfg, &offset, 1, settings) != 0) {
        fprintf(err, "pmsm-gpio-bench: line %u: %s\n", a->line, strerror(errno));
        goto out;
    }
    gpiod_request_config_set_consumer(req_cfg, GB_CONSUMER);
    if (event_buffer_size > 0) {
        gpiod_request_config_set_event_buffer_size(req_cfg, event_buffer_size);
    }
    req = gpiod_chip_request_lines(chip, req_cfg, line_cfg);
    if (req == NULL) {
        const int e = errno;
        fprintf(err, "pmsm-gpio-bench: cannot request line %u of %s: %s%s\n", a->line, a->chip,
                strerror(e), (e == EBUSY) ? " (used by another consumer: gpioinfo tells)" : "");
    }
out:
    if (req_cfg != NULL) {
        gpiod_request_config_free(req_cfg);
    }
    if (line_cfg != NULL) {
        gpiod_line_config_free(line_cfg);
    }
    return req;
}

/* Release what a command acquired (NULL: not acquired) and close the
 * chip. */
static void release_line(struct gpiod_chip *chip, struct gpiod_line_settings *settings,
                         struct gpiod_line_request *req)
{
    if (req != NULL) {
        gpiod_line_request_release(req);
    }
    if (settings != NULL) {
        gpiod_line_settings_free(settings);
    }
    gpiod_chip_close(chip);
}

int gb_gpio_sto(const gb_args_t *a, FILE *out, FILE *err)
{
    int code = GB_EXIT_FAIL;
    struct gpiod_chip *chip = open_chip(a->chip, &code, err);
    if (chip == NULL) {
        return code;
    }
    code = GB_EXIT_FAIL;
    struct gpiod_line_request *req = NULL;
    struct gpiod_line_settings *settings = gpiod_line_settings_new();
    const enum gpiod_line_value first =
        (a->sto_action == GB_STO_RELEASE) ? GPIOD_LINE_VALUE_INACTIVE : GPIOD_LINE_VALUE_ACTIVE;
    if (settings == NULL ||
        gpiod_line_settings_set_direction(settings, GPIOD_LINE_DIRECTION_OUTPUT) != 0 ||
        gpiod_line_settings_set_output_value(settings, first) != 0) {
        fprintf(err, "pmsm-gpio-bench: line settings: %s\n", strerror(errno));
        goto out;
    }
    gpiod_line_settings_set_active_low(settings, a->active_low);

    gb_signals_t sig;
    signals_catch(&sig);
    req = request_line(chip, a, settings, 0, err);
    const int64_t t0 = now_ns();
    if (req == NULL) {
        signals_restore(&sig);
        goto out;
    }
    const char *level_asserted = a->active_low ? "low" : "high";
    const char *level_released = a->active_low ? "high" : "low";
    if (a->sto_action == GB_STO_PULSE) {
        sleep_until(t0 + (int64_t)a->pulse_ms * 1000000LL);
        const int64_t t1 = now_ns();
        if (gpiod_line_request_set_value(req, a->line, GPIOD_LINE_VALUE_INACTIVE) != 0) {
            fprintf(err, "pmsm-gpio-bench: line %u: cannot release STO: %s\n", a->line,
                    strerror(errno));
        } else {
            fprintf(out,
                    "sto: %s line %u asserted (%s) for %.3f ms (pulse %ld ms), released (%s)\n",
                    a->chip, a->line, level_asserted, (double)(t1 - t0) / 1e6, a->pulse_ms,
                    level_released);
            code = GB_EXIT_OK;
        }
    } else {
        const bool asserted = (a->sto_action == GB_STO_ASSERT);
        fprintf(out, "sto: %s line %u %s (%s); ", a->chip, a->line,
                asserted ? "asserted" : "released", asserted ? level_asserted : level_released);
        if (a->hold_s > 0.0) {
            fprintf(out, "holding %.3f s (Ctrl-C ends)\n", a->hold_s);
        } else {
            fprintf(out, "holding until Ctrl-C\n");
        }
        fflush(out);
        const int64_t end = (a->hold_s > 0.0) ? t0 + (int64_t)(a->hold_s * 1e9) : INT64_MAX;
        while (!gb_stop_requested && now_ns() < end) {
            const int64_t t = now_ns();
            sleep_until((end - t > GB_WAIT_SLICE_NS) ? t + GB_WAIT_SLICE_NS : end);
        }
        fprintf(out, "sto: line %u released to the chip after %.3f s\n", a->line,
                (double)(now_ns() - t0) / 1e9);
        code = GB_EXIT_OK;
    }
    signals_restore(&sig);
out:
    release_line(chip, settings, req);
    return code;
}

int gb_gpio_isr_capture(const gb_args_t *a, gb_edges_t *e, double *capture_s, FILE *err)
{
    *capture_s = 0.0;
    int code = GB_EXIT_FAIL;
    struct gpiod_chip *chip = open_chip(a->chip, &code, err);
    if (chip == NULL) {
        return code;
    }
    code = GB_EXIT_FAIL;
    struct gpiod_line_request *req = NULL;
    struct gpiod_edge_event_buffer *buf = NULL;
    struct gpiod_line_settings *settings = gpiod_line_settings_new();
    if (settings == NULL ||
        gpiod_line_settings_set_direction(settings, GPIOD_LINE_DIRECTION_INPUT) != 0 ||
        gpiod_line_settings_set_edge_detection(settings, GPIOD_LINE_EDGE_BOTH) != 0 ||
        gpiod_line_settings_set_event_clock(settings, GPIOD_LINE_CLOCK_MONOTONIC) != 0) {
        fprintf(err, "pmsm-gpio-bench: line settings: %s\n", strerror(errno));
        goto out;
    }
    gpiod_line_settings_set_active_low(settings, a->active_low);
    req = request_line(chip, a, settings, GB_EVENT_BUF, err);
    if (req == NULL) {
        goto out;
    }
    buf = gpiod_edge_event_buffer_new(GB_EVENT_BUF);
    if (buf == NULL) {
        fprintf(err, "pmsm-gpio-bench: edge event buffer: %s\n", strerror(errno));
        goto out;
    }

    gb_signals_t sig;
    signals_catch(&sig);
    const int64_t t0 = now_ns();
    const int64_t deadline = t0 + (int64_t)(a->seconds * 1e9);
    code = GB_EXIT_OK;
    for (int64_t t = t0; !gb_stop_requested && t < deadline; t = now_ns()) {
        const int64_t slice = (deadline - t > GB_WAIT_SLICE_NS) ? GB_WAIT_SLICE_NS : deadline - t;
        const int rc = gpiod_line_request_wait_edge_events(req, slice);
        if (rc == 0 || (rc < 0 && errno == EINTR)) {
            continue;
        }
        const int n = (rc > 0) ? gpiod_line_request_read_edge_events(req, buf, GB_EVENT_BUF) : -1;
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            fprintf(err, "pmsm-gpio-bench: edge events of line %u: %s\n", a->line, strerror(errno));
            code = GB_EXIT_FAIL;
            break;
        }
        for (int i = 0; i < n; i++) {
            struct gpiod_edge_event *ev = gpiod_edge_event_buffer_get_event(buf, (unsigned long)i);
            const gb_edge_kind_t kind =
                (gpiod_edge_event_get_event_type(ev) == GPIOD_EDGE_EVENT_RISING_EDGE)
                    ? GB_EDGE_RISING
                    : GB_EDGE_FALLING;
            if (gb_edges_push(e, kind, gpiod_edge_event_get_timestamp_ns(ev),
                              gpiod_edge_event_get_global_seqno(ev),
                              gpiod_edge_event_get_line_seqno(ev)) != 0) {
                fprintf(err, "pmsm-gpio-bench: out of memory for the measurements\n");
                code = GB_EXIT_FAIL;
                break;
            }
        }
        if (code != GB_EXIT_OK) {
            break;
        }
    }
    *capture_s = (double)(now_ns() - t0) / 1e9;
    signals_restore(&sig);
out:
    if (buf != NULL) {
        gpiod_edge_event_buffer_free(buf);
    }
    release_line(chip, settings, req);
    return code;
}
