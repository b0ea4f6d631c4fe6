/*
 * Pulse generator for a gpio-sim line (tests/gpio_vm): writes "pull-up" /
 * "pull-down" to the line's sysfs pull attribute on a fixed grid (monotonic
 * clock, absolute sleeps), N pulses of WIDTH_US every PERIOD_US, and prints
 * for every edge the monotonic time just before and just after its write:
 *
 *     <1 = pulse start | 0 = pulse end> <before_ns> <after_ns>
 *
 * The kernel raises the line's interrupt inside that write (gpio-sim sets it
 * pending, the interrupt simulator runs it from an irq_work on this CPU), so
 * the edge's timestamp lies between the two. Without --low a pulse is a high
 * level (pull-up), with --low a low one; the line starts at the opposite
 * level (the caller sets it; written once more before the first pulse, which
 * makes no edge).
 *
 * usage: gpio_sim_pulses PULL_FILE N WIDTH_US PERIOD_US [--low]
 * exit 0, or 1 with a message on stderr (a write failed, bad arguments).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define NS_PER_S  1000000000LL
#define NS_PER_US 1000LL

static int64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * NS_PER_S + ts.tv_nsec;
}

static void sleep_until(int64_t t_ns)
{
    const struct timespec ts = { .tv_sec = (time_t)(t_ns / NS_PER_S),
                                 .tv_nsec = (long)(t_ns % NS_PER_S) };
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

static long parse_positive(const char *s, const char *what)
{
    char *end = NULL;
    errno = 0;
    const long v = strtol(s, &end, 10);
    if (errno != 0 || end == s || *end != '\0' || v <= 0) {
        fprintf(stderr, "gpio_sim_pulses: %s must be a positive integer: %s\n", what, s);
        exit(1);
    }
    return v;
}

/* Writes one pull setting; prints the edge with its bracketing times. */
static void edge(int fd, const char *pull, int start)
{
    const size_t len = strlen(pull);
    const int64_t before = now_ns();
    const ssize_t n = pwrite(fd, pull, len, 0);
    const int64_t after = now_ns();
    if (n != (ssize_t)len) {
        fprintf(stderr, "gpio_sim_pulses: write %s: %s\n", pull,
                (n < 0) ? strerror(errno) : "short write");
        exit(1);
    }
    printf("%d %lld %lld\n", start, (long long)before, (long long)after);
}

int main(int argc, char **argv)
{
    if (argc != 5 && !(argc == 6 && strcmp(argv[5], "--low") == 0)) {
        fprintf(stderr, "usage: gpio_sim_pulses PULL_FILE N WIDTH_US PERIOD_US [--low]\n");
        return 1;
    }
    const long n = parse_positive(argv[2], "N");
    const int64_t width = parse_positive(argv[3], "WIDTH_US") * NS_PER_US;
    const int64_t period = parse_positive(argv[4], "PERIOD_US") * NS_PER_US;
    if (width >= period) {
        fprintf(stderr, "gpio_sim_pulses: WIDTH_US must be below PERIOD_US\n");
        return 1;
    }
    const char *on = (argc == 6) ? "pull-down" : "pull-up";
    const char *off = (argc == 6) ? "pull-up" : "pull-down";
    const int fd = open(argv[1], O_WRONLY);
    if (fd < 0) {
        fprintf(stderr, "gpio_sim_pulses: %s: %s\n", argv[1], strerror(errno));
        return 1;
    }
    /* the idle level once more: no edge, but the write path is warm for the
     * first pulse (a first run of code is slow under TCG) */
    if (pwrite(fd, off, strlen(off), 0) != (ssize_t)strlen(off)) {
        fprintf(stderr, "gpio_sim_pulses: write %s: %s\n", off, strerror(errno));
        return 1;
    }
    const int64_t t0 = now_ns() + period;
    for (long k = 0; k < n; k++) {
        sleep_until(t0 + k * period);
        edge(fd, on, 1);
        sleep_until(t0 + k * period + width);
        edge(fd, off, 0);
    }
    close(fd);
    return (fflush(stdout) == 0) ? 0 : 1;
}
