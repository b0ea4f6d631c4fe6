/*
 * A fake of the libgpiod v2 calls pmsm-gpio-bench makes (and of the
 * monotonic clock), bound at link time: the test executables are linked with
 * -Wl,--wrap=<function> for each of them and without libgpiod, so a call
 * the fake does not cover fails the link. The fake records what was
 * requested and when (fake time), and plays a script of edge events.
 */
#ifndef FAKE_GPIOD_H
#define FAKE_GPIOD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define FAKE_MAX_EVENTS 4096
#define FAKE_MAX_SETS   16
#define FAKE_T0_NS      1000000000000LL /* the fake monotonic clock starts at 1000 s */

typedef struct {
    int type; /* GPIOD_EDGE_EVENT_RISING_EDGE / _FALLING_EDGE */
    uint64_t ts_ns;
    unsigned long global_seqno;
    unsigned long line_seqno;
} fake_event_t;

typedef struct {
    int value; /* enum gpiod_line_value */
    int64_t t_ns;
} fake_set_t;

typedef struct {
    /* the chip: gpiod_chip_open fails with open_errno unless chip_present */
    bool chip_present;
    int open_errno;
    int request_errno; /* gpiod_chip_request_lines fails with it when not 0 */
    char opened_path[256];
    int chips_open; /* opened - closed */

    /* the one request made */
    int requests;
    int releases;
    size_t num_offsets;
    unsigned int offset;
    int direction; /* enum gpiod_line_direction */
    int edge;      /* enum gpiod_line_edge, 0 if never set */
    int clock;     /* enum gpiod_line_clock, 0 if never set */
    bool active_low;
    int output_value; /* enum gpiod_line_value at the request */
    char consumer[64];
    size_t event_buffer_size;
    int64_t request_t_ns;
    int64_t release_t_ns;
    fake_set_t sets[FAKE_MAX_SETS]; /* gpiod_line_request_set_value calls */
    int nsets;
    int objects_live; /* settings, configs, buffers: allocated - freed */

    /* edge events played to wait / read */
    fake_event_t events[FAKE_MAX_EVENTS];
    size_t nevents;
    size_t next_event;

    /* the fake monotonic clock */
    int64_t now_ns;
    int sleeps;
    int sigint_at_sleep; /* raise SIGINT in that sleep (1-based); 0: never */
} fake_gpiod_t;

extern fake_gpiod_t fake;

/* A chip present, no events, the clock at FAKE_T0_NS. */
void fake_reset(void);

/* Appends an edge event to the script (timestamps in increasing order). */
void fake_add_event(int type, uint64_t ts_ns, unsigned long global_seqno, unsigned long line_seqno);

#endif /* FAKE_GPIOD_H */
