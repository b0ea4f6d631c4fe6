/* SocketCAN bridge of the host simulator (socketcan.h). Linux only. */
#define _GNU_SOURCE

#include "socketcan.h"

#include <errno.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>

/* Where a user finds how to get CAN on this machine. */
#define SOCKETCAN_DOC "see the CAN section of host_sim/scenarios/README.md"

/* Frames hal_socketcan_flush drops at most (a socket's receive buffer
 * holds a few hundred): bounded even against a sender faster than it. */
#define SOCKETCAN_FLUSH_MAX 1000000u

/* Message numbers per node: identifier = node_id * 32 + message number. */
#define SOCKETCAN_NODE_SHIFT 5u

/* Record a failure: "CAN interface <if>: <what>: <strerror>[ (<hint>)]";
 * returns -err. */
static int fail(hal_socketcan_t *s, int err, const char *what, const char *hint)
{
    s->last_error = err;
    if (hint != NULL) {
        snprintf(s->message, sizeof s->message, "CAN interface %s: %s: %s (%s)",
                 s->ifname, what, strerror(err), hint);
    } else {
        snprintf(s->message, sizeof s->message, "CAN interface %s: %s: %s",
                 s->ifname, what, strerror(err));
    }
    return -err;
}

static int fail_open(hal_socketcan_t *s, int err, const char *what,
                     const char *hint)
{
    const int code = fail(s, err, what, hint);
    if (s->fd >= 0) {
        close(s->fd);
        s->fd = -1;
    }
    return code;
}

/* The socket options of socketcan.h: filter, error frames, drop count. */
static int configure(hal_socketcan_t *s)
{
    const struct can_filter filter = {
        .can_id = s->node_id << SOCKETCAN_NODE_SHIFT,
        /* the node's 32 identifiers, standard frames only (RTR passes) */
        .can_mask = CAN_EFF_FLAG |
                    (CAN_SFF_MASK & ~((1u << SOCKETCAN_NODE_SHIFT) - 1u)),
    };
    if (setsockopt(s->fd, SOL_CAN_RAW, CAN_RAW_FILTER, &filter,
                   sizeof filter) != 0) {
        return fail_open(s, errno, "setsockopt(CAN_RAW_FILTER)", NULL);
    }
    const can_err_mask_t err_mask = CAN_ERR_MASK;
    if (setsockopt(s->fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask,
                   sizeof err_mask) != 0) {
        return fail_open(s, errno, "setsockopt(CAN_RAW_ERR_FILTER)", NULL);
    }
    const int on = 1;
    if (setsockopt(s->fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0) {
        return fail_open(s, errno, "setsockopt(SO_RXQ_OVFL)", NULL);
    }
    return 0;
}

int hal_socketcan_open(hal_socketcan_t *s, const char *ifname, uint32_t node_id)
{
    if (s == NULL) {
        return -EINVAL;
    }
    *s = (hal_socketcan_t){ .fd = -1, .node_id = node_id };
    snprintf(s->message, sizeof s->message, "ok");
    const size_t len = ifname != NULL ? strlen(ifname) : 0u;
    snprintf(s->ifname, sizeof s->ifname, "%s", ifname != NULL ? ifname : "");
    if (len == 0u || len >= HAL_SOCKETCAN_IFNAME_MAX) {
        s->last_error = EINVAL;
        snprintf(s->message, sizeof s->message,
                 "CAN interface name '%.64s' must have 1 to %u characters",
                 ifname != NULL ? ifname : "", HAL_SOCKETCAN_IFNAME_MAX - 1u);
        return -EINVAL;
    }
    if (node_id > MC_CAN_NODE_ID_MAX) {
        s->last_error = EINVAL;
        snprintf(s->message, sizeof s->message,
                 "CAN interface %s: node id %u is not in 0..%u", s->ifname,
                 (unsigned)node_id, (unsigned)MC_CAN_NODE_ID_MAX);
        return -EINVAL;
    }
    s->fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (s->fd < 0) {
        const int err = errno;
        return fail_open(s, err, "socket(PF_CAN)",
                         err == EAFNOSUPPORT
                             ? "this kernel has no CAN; " SOCKETCAN_DOC
                             : NULL);
    }
    char hint[160];
    const unsigned index = if_nametoindex(s->ifname);
    if (index == 0u) {
        snprintf(hint, sizeof hint,
                 "create a virtual one: ip link add dev %s type vcan && ip "
                 "link set up %s; "
                 "%s",
                 s->ifname, s->ifname, SOCKETCAN_DOC);
        return fail_open(s, ENODEV, "if_nametoindex", hint);
    }
    const int code = configure(s);
    if (code != 0) {
        return code;
    }
    struct sockaddr_can addr = { .can_family = AF_CAN,
                                 .can_ifindex = (int)index };
    if (bind(s->fd, (const struct sockaddr *)&addr, sizeof addr) != 0) {
        const int err = errno;
        return fail_open(s, err, "bind",
                         err == ENODEV ? "not a CAN interface" : NULL);
    }
    struct ifreq ifr;
    memset(&ifr, 0, sizeof ifr);
    memcpy(ifr.ifr_name, s->ifname, len + 1u);
    /* a down interface neither sends nor receives: say so now (an ioctl
     * this socket cannot serve is no reason to refuse) */
    if (ioctl(s->fd, SIOCGIFFLAGS, &ifr) == 0 &&
        (ifr.ifr_flags & IFF_UP) == 0) {
        snprintf(hint, sizeof hint, "bring it up: ip link set up %s",
                 s->ifname);
        return fail_open(s, ENETDOWN, "SIOCGIFFLAGS", hint);
    }
    return 0;
}

/* The kernel's cumulative drop count of this frame's ancillary data into
 * the counters (its increment since the last one seen; e NULL: only the
 * new baseline, nothing counted). */
static void take_drop_count(hal_socketcan_t *s, sim_engine_t *e,
                            struct msghdr *msg)
{
    for (struct cmsghdr *c = CMSG_FIRSTHDR(msg); c != NULL;
         c = CMSG_NXTHDR(msg, c)) {
        if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SO_RXQ_OVFL ||
            c->cmsg_len < CMSG_LEN(sizeof(uint32_t))) {
            continue;
        }
        uint32_t total;
        memcpy(&total, CMSG_DATA(c), sizeof total);
        const uint32_t delta = total - s->rxq_ovfl_last; /* modulo 2^32 */
        s->rxq_ovfl_last = total;
        if (e != NULL && delta != 0u) {
            s->counters.rx_overflow_drops += delta;
            sim_engine_can_count_link_events(e, delta, 0u);
        }
    }
}

/* One received frame: error frames counted, the others delivered. */
static void take_frame(hal_socketcan_t *s, sim_engine_t *e,
                       const struct can_frame *cf)
{
    if ((cf->can_id & CAN_ERR_FLAG) != 0u) {
        s->counters.bus_errors++;
        sim_engine_can_count_link_events(e, 0u, 1u);
        return;
    }
    hal_can_frame_t f = { 0 };
    f.extended = (cf->can_id & CAN_EFF_FLAG) != 0u;
    f.rtr = (cf->can_id & CAN_RTR_FLAG) != 0u;
    f.id = cf->can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    f.dlc = cf->len <= HAL_CAN_MAX_DLC ? cf->len : (uint8_t)HAL_CAN_MAX_DLC;
    memcpy(f.data, cf->data, f.dlc);
    if (sim_engine_can_deliver(e, &f)) {
        s->counters.rx++;
    } else {
        s->counters.rx_refused++;
    }
}

/* Up to max frames the socket holds, into e (NULL: dropped); the frames
 * read, or -errno. */
static int pump_rx(hal_socketcan_t *s, sim_engine_t *e, uint64_t max)
{
    int moved = 0;
    for (uint64_t n_read = 0; n_read < max;) {
        struct can_frame cf;
        union {
            char buf[CMSG_SPACE(sizeof(uint32_t))];
            struct cmsghdr align;
        } control;
        struct iovec iov = { .iov_base = &cf, .iov_len = sizeof cf };
        struct msghdr msg = { .msg_iov = &iov,
                              .msg_iovlen = 1,
                              .msg_control = control.buf,
                              .msg_controllen = sizeof control.buf };
        const ssize_t n = recvmsg(s->fd, &msg, MSG_DONTWAIT);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            if (errno == EAGAIN || errno == EWOULDBLOCK) {
                return moved;
            }
            return fail(s, errno, "recvmsg", NULL);
        }
        take_drop_count(s, e, &msg);
        n_read++;
        if ((size_t)n != sizeof cf) { /* classic frames only (no CAN FD) */
            continue;
        }
        if (e != NULL) {
            take_frame(s, e, &cf);
        } else {
            s->counters.rx_flushed++;
        }
        moved++;
    }
    return moved;
}

/* Everything the drive sent; the frames taken, or -errno. */
static int pump_tx(hal_socketcan_t *s, sim_engine_t *e)
{
    int moved = 0;
    hal_can_frame_t f;
    while (sim_engine_can_collect(e, &f)) {
        struct can_frame cf;
        memset(&cf, 0, sizeof cf);
        cf.can_id = f.extended ? (f.id & CAN_EFF_MASK) | CAN_EFF_FLAG
                               : f.id & CAN_SFF_MASK;
        if (f.rtr) {
            cf.can_id |= CAN_RTR_FLAG;
        }
        cf.len = f.dlc <= HAL_CAN_MAX_DLC ? f.dlc : (uint8_t)HAL_CAN_MAX_DLC;
        memcpy(cf.data, f.data, cf.len);
        moved++;
        ssize_t n;
        do {
            n = send(s->fd, &cf, sizeof cf, MSG_DONTWAIT);
        } while (n < 0 && errno == EINTR);
        if (n == (ssize_t)sizeof cf) {
            s->counters.tx++;
            continue;
        }
        s->counters.tx_dropped++;
        if (n >= 0) {
            return fail(s, EIO, "send (short write)", NULL);
        }
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != ENOBUFS) {
            return fail(s, errno, "send", NULL);
        }
    }
    return moved;
}

/* "the bridge is not open" (-EBADF). */
static int not_open(hal_socketcan_t *s)
{
    s->last_error = EBADF;
    snprintf(s->message, sizeof s->message,
             "CAN interface %s: the bridge is not open", s->ifname);
    return -EBADF;
}

int hal_socketcan_pump(hal_socketcan_t *s, sim_engine_t *e)
{
    if (s == NULL || e == NULL) {
        return -EINVAL;
    }
    if (s->fd < 0) {
        return not_open(s);
    }
    const int rx = pump_rx(s, e, HAL_SOCKETCAN_RX_PER_PUMP);
    if (rx < 0) {
        return rx;
    }
    const int tx = pump_tx(s, e);
    return tx < 0 ? tx : rx + tx;
}

int hal_socketcan_flush(hal_socketcan_t *s)
{
    if (s == NULL) {
        return -EINVAL;
    }
    if (s->fd < 0) {
        return not_open(s);
    }
    return pump_rx(s, NULL, SOCKETCAN_FLUSH_MAX);
}

const hal_socketcan_counters_t *hal_socketcan_counters(const hal_socketcan_t *s)
{
    return &s->counters;
}

const char *hal_socketcan_message(const hal_socketcan_t *s)
{
    return s == NULL ? "bridge is NULL" : s->message;
}

void hal_socketcan_close(hal_socketcan_t *s)
{
    if (s != NULL && s->fd >= 0) {
        close(s->fd);
        s->fd = -1;
    }
}
