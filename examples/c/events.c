/*
 * Events three ways: the card's interrupt descriptor in the application's own epoll loop with
 * a callback run by mc_dispatch_events, mc_wait_event with a timeout, and dispatching without
 * a callback (events dropped).
 */
#define _POSIX_C_SOURCE 200809L
#include "check.h"

#include <math.h>
#include <sys/epoll.h>
#include <unistd.h>

#define MAX_LOGGED 256

struct event_log {
    mc_card card;
    size_t count;
    mc_event events[MAX_LOGGED];
};

/* Runs inside mc_dispatch_events, on the thread that called it. */
static void on_event(mc_card card, const mc_event *event, void *user) {
    struct event_log *log = user;
    ASSERT(card == log->card, "callback for card %u, expected %u", card, log->card);
    if (log->count < MAX_LOGGED) log->events[log->count++] = *event;
}

static const mc_event *find(const struct event_log *log, uint32_t kind, uint32_t seq) {
    for (size_t i = 0; i < log->count; i++) {
        if (log->events[i].kind == kind && log->events[i].seq == seq) return &log->events[i];
    }
    return NULL;
}

static int saw_state(const struct event_log *log, uint32_t axis, int32_t state) {
    for (size_t i = 0; i < log->count; i++) {
        const mc_event *e = &log->events[i];
        if (e->kind == MC_EVENT_STATE_CHANGED && e->axis == axis && e->code == state) return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    mc_card card = 0;
    CHECK(open_from_args(argc, argv, &card));
    const int stepped = mc_sim_step(card, 0) == MC_OK;
    mc_move_limits limits;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &limits));

    /* 1. The interrupt descriptor in our epoll loop; callbacks from mc_dispatch_events. */
    int fd = -1;
    CHECK(mc_irq_fd(card, &fd));
    int ep = epoll_create1(EPOLL_CLOEXEC);
    ASSERT(ep >= 0, "epoll_create1");
    struct epoll_event want = {.events = EPOLLIN, .data.fd = fd};
    ASSERT(epoll_ctl(ep, EPOLL_CTL_ADD, fd, &want) == 0, "epoll_ctl");

    static struct event_log log; /* static: large */
    log.card = card;
    CHECK(mc_set_event_callback(card, on_event, &log));
    CHECK(mc_enable(card, 0));
    mc_motion m;
    CHECK(mc_move_relative(card, 0, 5000.0, &limits, &m));
    unsigned wakeups = 0, rounds = 0;
    while (!find(&log, MC_EVENT_MOTION_DONE, m.seq)) {
        ASSERT(++rounds < 100000, "no motion-done event after %u rounds", rounds);
        if (stepped) CHECK(mc_sim_step(card, 10));
        struct epoll_event got;
        int n = epoll_wait(ep, &got, 1, stepped ? 0 : 100);
        ASSERT(n >= 0, "epoll_wait");
        wakeups += n;
        /* Readable: take the events. On a timeout too: a wait in another call may have taken
           the interrupt while leaving events queued (see the header's "Event loop"). */
        size_t dispatched = 0;
        CHECK(mc_dispatch_events(card, 0, &dispatched));
    }
    const mc_event *done = find(&log, MC_EVENT_MOTION_DONE, m.seq);
    ASSERT(done->axis == 0 && fabs(done->value - 5000.0) <= 1.0, "done on axis %u at %f",
           done->axis, done->value);
    ASSERT(saw_state(&log, 0, MC_AXIS_STATE_STANDSTILL), "no Standstill event");
    ASSERT(saw_state(&log, 0, MC_AXIS_STATE_DISCRETE_MOTION), "no DiscreteMotion event");
    ASSERT(wakeups > 0, "the descriptor never became readable");
    printf("epoll: %u wakeups, %zu events through the callback, done at %.1f\n", wakeups,
           log.count, done->value);

    /* 2. mc_wait_event with a timeout, no callback. */
    CHECK(mc_set_event_callback(card, NULL, NULL));
    size_t before = log.count;
    CHECK(mc_move_relative(card, 0, -2000.0, &limits, &m));
    mc_event e;
    unsigned taken = 0;
    for (;;) {
        CHECK(mc_wait_event(card, 5000, &e));
        taken++;
        if (e.kind == MC_EVENT_MOTION_DONE && e.seq == m.seq) break;
        ASSERT(taken < 1000, "no motion-done event in %u events", taken);
    }
    ASSERT(fabs(e.value - 3000.0) <= 1.0, "done at %f", e.value);
    ASSERT(log.count == before, "the cleared callback was called");
    printf("mc_wait_event: %u events, done at %.1f\n", taken, e.value);

    /* 3. Dispatch without a callback takes the events and drops them. */
    CHECK(mc_disable(card, 0));
    size_t dropped = 0;
    CHECK(mc_dispatch_events(card, 1000, &dropped));
    ASSERT(dropped >= 1, "the disable raised no event");
    mc_event untouched = {.kind = 12345};
    ASSERT(mc_wait_event(card, 0, &untouched) == MC_ERR_TIMEOUT, "an event was left");
    ASSERT(untouched.kind == 12345, "output written on failure");
    printf("dispatch without a callback: %zu events dropped\n", dropped);

    close(ep);
    CHECK(mc_close(card));
    printf("PASS events\n");
    return 0;
}
