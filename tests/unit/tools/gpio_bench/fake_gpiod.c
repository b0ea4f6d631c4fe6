/*
 * The fake libgpiod and clock of fake_gpiod.h (the __wrap_ side of
 * -Wl,--wrap).
 */
#define _POSIX_C_SOURCE 200809L

#include "fake_gpiod.h"

#include <errno.h>
#include <gpiod.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

fake_gpiod_t fake;

/* The opaque types of gpiod.h, as this fake needs them. */
struct gpiod_chip {
    int id;
};

struct gpiod_line_settings {
    int direction;
    int edge;
    int clock;
    bool active_low;
    int output_value;
};

struct gpiod_line_config {
    bool has_settings;
    size_t num_offsets;
    unsigned int offset;
    struct gpiod_line_settings settings;
};

struct gpiod_request_config {
    char consumer[64];
    size_t event_buffer_size;
};

struct gpiod_line_request {
    unsigned int offset;
};

struct gpiod_edge_event {
    fake_event_t e;
};

struct gpiod_edge_event_buffer {
    size_t capacity;
    size_t n;
    struct gpiod_edge_event ev[1024];
};

void fake_reset(void)
{
    memset(&fake, 0, sizeof(fake));
    fake.chip_present = true;
    fake.open_errno = ENOENT;
    fake.now_ns = FAKE_T0_NS;
}

void fake_add_event(int type, uint64_t ts_ns, unsigned long global_seqno, unsigned long line_seqno)
{
    if (fake.nevents < FAKE_MAX_EVENTS) {
        fake.events[fake.nevents++] = (fake_event_t){ type, ts_ns, global_seqno, line_seqno };
    }
}

/* Prototypes of the wrappers (-Wmissing-prototypes). */
struct gpiod_chip *__wrap_gpiod_chip_open(const char *path);
void __wrap_gpiod_chip_close(struct gpiod_chip *chip);
struct gpiod_line_settings *__wrap_gpiod_line_settings_new(void);
void __wrap_gpiod_line_settings_free(struct gpiod_line_settings *s);
int __wrap_gpiod_line_settings_set_direction(struct gpiod_line_settings *s,
                                             enum gpiod_line_direction d);
int __wrap_gpiod_line_settings_set_edge_detection(struct gpiod_line_settings *s,
                                                  enum gpiod_line_edge e);
int __wrap_gpiod_line_settings_set_event_clock(struct gpiod_line_settings *s,
                                               enum gpiod_line_clock c);
void __wrap_gpiod_line_settings_set_active_low(struct gpiod_line_settings *s, bool active_low);
int __wrap_gpiod_line_settings_set_output_value(struct gpiod_line_settings *s,
                                                enum gpiod_line_value v);
struct gpiod_line_config *__wrap_gpiod_line_config_new(void);
void __wrap_gpiod_line_config_free(struct gpiod_line_config *c);
int __wrap_gpiod_line_config_add_line_settings(struct gpiod_line_config *c,
                                               const unsigned int *offsets, size_t num_offsets,
                                               struct gpiod_line_settings *s);
struct gpiod_request_config *__wrap_gpiod_request_config_new(void);
void __wrap_gpiod_request_config_free(struct gpiod_request_config *c);
void __wrap_gpiod_request_config_set_consumer(struct gpiod_request_config *c, const char *consumer);
void __wrap_gpiod_request_config_set_event_buffer_size(struct gpiod_request_config *c, size_t size);
struct gpiod_line_request *__wrap_gpiod_chip_request_lines(struct gpiod_chip *chip,
                                                           struct gpiod_request_config *rc,
                                                           struct gpiod_line_config *lc);
void __wrap_gpiod_line_request_release(struct gpiod_line_request *r);
int __wrap_gpiod_line_request_set_value(struct gpiod_line_request *r, unsigned int offset,
                                        enum gpiod_line_value v);
int __wrap_gpiod_line_request_wait_edge_events(struct gpiod_line_request *r, int64_t timeout_ns);
int __wrap_gpiod_line_request_read_edge_events(struct gpiod_line_request *r,
                                               struct gpiod_edge_event_buffer *b,
                                               size_t max_events);
struct gpiod_edge_event_buffer *__wrap_gpiod_edge_event_buffer_new(size_t capacity);
void __wrap_gpiod_edge_event_buffer_free(struct gpiod_edge_event_buffer *b);
struct gpiod_edge_event *__wrap_gpiod_edge_event_buffer_get_event(struct gpiod_edge_event_buffer *b,
                                                                  unsigned long index);
enum gpiod_edge_event_type __wrap_gpiod_edge_event_get_event_type(struct gpiod_edge_event *ev);
uint64_t __wrap_gpiod_edge_event_get_timestamp_ns(struct gpiod_edge_event *ev);
unsigned long __wrap_gpiod_edge_event_get_global_seqno(struct gpiod_edge_event *ev);
unsigned long __wrap_gpiod_edge_event_get_line_seqno(struct gpiod_edge_event *ev);
int __wrap_clock_gettime(clockid_t clk, struct timespec *ts);
int __wrap_clock_nanosleep(clockid_t clk, int flags, const struct timespec *req,
                           struct timespec *rem);

static void *fake_alloc(size_t size)
{
    void *p = calloc(1, size);
    if (p != NULL) {
        fake.objects_live++;
    }
    return p;
}

static void fake_free(void *p)
{
    if (p != NULL) {
        fake.objects_live--;
        free(p);
    }
}

struct gpiod_chip *__wrap_gpiod_chip_open(const char *path)
{
    snprintf(fake.opened_path, sizeof(fake.opened_path), "%s", path);
    if (!fake.chip_present) {
        errno = fake.open_errno;
        return NULL;
    }
    struct gpiod_chip *c = calloc(1, sizeof(*c));
    if (c != NULL) {
        fake.chips_open++;
    }
    return c;
}

void __wrap_gpiod_chip_close(struct gpiod_chip *chip)
{
    if (chip != NULL) {
        fake.chips_open--;
        free(chip);
    }
}

struct gpiod_line_settings *__wrap_gpiod_line_settings_new(void)
{
    struct gpiod_line_settings *s = fake_alloc(sizeof(*s));
    if (s != NULL) {
        s->direction = GPIOD_LINE_DIRECTION_AS_IS;
        s->output_value = GPIOD_LINE_VALUE_INACTIVE;
    }
    return s;
}

void __wrap_gpiod_line_settings_free(struct gpiod_line_settings *s)
{
    fake_free(s);
}

int __wrap_gpiod_line_settings_set_direction(struct gpiod_line_settings *s,
                                             enum gpiod_line_direction d)
{
    s->direction = d;
    return 0;
}

int __wrap_gpiod_line_settings_set_edge_detection(struct gpiod_line_settings *s,
                                                  enum gpiod_line_edge e)
{
    s->edge = e;
    return 0;
}

int __wrap_gpiod_line_settings_set_event_clock(struct gpiod_line_settings *s,
                                               enum gpiod_line_clock c)
{
    s->clock = c;
    return 0;
}

void __wrap_gpiod_line_settings_set_active_low(struct gpiod_line_settings *s, bool active_low)
{
    s->active_low = active_low;
}

int __wrap_gpiod_line_settings_set_output_value(struct gpiod_line_settings *s,
                                                enum gpiod_line_value v)
{
    s->output_value = v;
    return 0;
}

struct gpiod_line_config *__wrap_gpiod_line_config_new(void)
{
    return fake_alloc(sizeof(struct gpiod_line_config));
}

void __wrap_gpiod_line_config_free(struct gpiod_line_config *c)
{
    fake_free(c);
}

int __wrap_gpiod_line_config_add_line_settings(struct gpiod_line_config *c,
                                               const unsigned int *offsets, size_t num_offsets,
                                               struct gpiod_line_settings *s)
{
    c->has_settings = true;
    c->num_offsets = num_offsets;
    c->offset = offsets[0];
    c->settings = *s; /* libgpiod copies the settings too */
    return 0;
}

struct gpiod_request_config *__wrap_gpiod_request_config_new(void)
{
    return fake_alloc(sizeof(struct gpiod_request_config));
}

void __wrap_gpiod_request_config_free(struct gpiod_request_config *c)
{
    fake_free(c);
}

void __wrap_gpiod_request_config_set_consumer(struct gpiod_request_config *c, const char *consumer)
{
    snprintf(c->consumer, sizeof(c->consumer), "%s", consumer);
}

void __wrap_gpiod_request_config_set_event_buffer_size(struct gpiod_request_config *c, size_t size)
{
    c->event_buffer_size = size;
}

struct gpiod_line_request *__wrap_gpiod_chip_request_lines(struct gpiod_chip *chip,
                                                           struct gpiod_request_config *rc,
                                                           struct gpiod_line_config *lc)
{
    (void)chip;
    fake.requests++;
    if (fake.request_errno != 0) {
        errno = fake.request_errno;
        return NULL;
    }
    if (lc == NULL || !lc->has_settings) {
        errno = EINVAL;
        return NULL;
    }
    fake.num_offsets = lc->num_offsets;
    fake.offset = lc->offset;
    fake.direction = lc->settings.direction;
    fake.edge = lc->settings.edge;
    fake.clock = lc->settings.clock;
    fake.active_low = lc->settings.active_low;
    fake.output_value = lc->settings.output_value;
    if (rc != NULL) {
        snprintf(fake.consumer, sizeof(fake.consumer), "%s", rc->consumer);
        fake.event_buffer_size = rc->event_buffer_size;
    }
    fake.request_t_ns = fake.now_ns;
    struct gpiod_line_request *r = fake_alloc(sizeof(*r));
    if (r != NULL) {
        r->offset = lc->offset;
    }
    return r;
}

void __wrap_gpiod_line_request_release(struct gpiod_line_request *r)
{
    fake.releases++;
    fake.release_t_ns = fake.now_ns;
    fake_free(r);
}

int __wrap_gpiod_line_request_set_value(struct gpiod_line_request *r, unsigned int offset,
                                        enum gpiod_line_value v)
{
    if (offset != r->offset || fake.nsets >= FAKE_MAX_SETS) {
        errno = EINVAL;
        return -1;
    }
    fake.sets[fake.nsets++] = (fake_set_t){ v, fake.now_ns };
    return 0;
}

/* An event pending within the timeout: the clock goes to it; none: the
 * clock goes on by the timeout. */
int __wrap_gpiod_line_request_wait_edge_events(struct gpiod_line_request *r, int64_t timeout_ns)
{
    (void)r;
    if (fake.next_event < fake.nevents &&
        (int64_t)fake.events[fake.next_event].ts_ns <= fake.now_ns + timeout_ns) {
        if ((int64_t)fake.events[fake.next_event].ts_ns > fake.now_ns) {
            fake.now_ns = (int64_t)fake.events[fake.next_event].ts_ns;
        }
        return 1;
    }
    fake.now_ns += timeout_ns;
    return 0;
}

/* Every event up to now (at most max_events). */
int __wrap_gpiod_line_request_read_edge_events(struct gpiod_line_request *r,
                                               struct gpiod_edge_event_buffer *b, size_t max_events)
{
    (void)r;
    b->n = 0;
    while (fake.next_event < fake.nevents && b->n < max_events && b->n < b->capacity &&
           (int64_t)fake.events[fake.next_event].ts_ns <= fake.now_ns) {
        b->ev[b->n++].e = fake.events[fake.next_event++];
    }
    return (int)b->n;
}

struct gpiod_edge_event_buffer *__wrap_gpiod_edge_event_buffer_new(size_t capacity)
{
    struct gpiod_edge_event_buffer *b = fake_alloc(sizeof(*b));
    if (b != NULL) {
        b->capacity = (capacity == 0) ? 64 : (capacity > 1024) ? 1024 : capacity;
    }
    return b;
}

void __wrap_gpiod_edge_event_buffer_free(struct gpiod_edge_event_buffer *b)
{
    fake_free(b);
}

struct gpiod_edge_event *__wrap_gpiod_edge_event_buffer_get_event(struct gpiod_edge_event_buffer *b,
                                                                  unsigned long index)
{
    return (index < b->n) ? &b->ev[index] : NULL;
}

enum gpiod_edge_event_type __wrap_gpiod_edge_event_get_event_type(struct gpiod_edge_event *ev)
{
    return (enum gpiod_edge_event_type)ev->e.type;
}

uint64_t __wrap_gpiod_edge_event_get_timestamp_ns(struct gpiod_edge_event *ev)
{
    return ev->e.ts_ns;
}

unsigned long __wrap_gpiod_edge_event_get_global_seqno(struct gpiod_edge_event *ev)
{
    return ev->e.global_seqno;
}

unsigned long __wrap_gpiod_edge_event_get_line_seqno(struct gpiod_edge_event *ev)
{
    return ev->e.line_seqno;
}

int __wrap_clock_gettime(clockid_t clk, struct timespec *ts)
{
    (void)clk;
    ts->tv_sec = (time_t)(fake.now_ns / 1000000000LL);
    ts->tv_nsec = (long)(fake.now_ns % 1000000000LL);
    return 0;
}

/* Sleeps take no time: the clock jumps to the end of the sleep. */
int __wrap_clock_nanosleep(clockid_t clk, int flags, const struct timespec *req,
                           struct timespec *rem)
{
    (void)clk;
    (void)rem;
    fake.sleeps++;
    if (fake.sigint_at_sleep != 0 && fake.sleeps == fake.sigint_at_sleep) {
        raise(SIGINT);
        return EINTR;
    }
    const int64_t t = (int64_t)req->tv_sec * 1000000000LL + req->tv_nsec;
    if (flags & TIMER_ABSTIME) {
        fake.now_ns = (t > fake.now_ns) ? t : fake.now_ns;
    } else {
        fake.now_ns += t;
    }
    return 0;
}
