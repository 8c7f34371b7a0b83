/*
 * The life of a session on a card served by another process (`emu:NAME`):
 * - mc_cancel_waits ends the waits other threads are blocked in (MC_ERR_CANCELLED), and only
 *   those: a wait that begins afterwards waits as usual;
 * - mc_close wakes every thread blocked on the card at once (MC_ERR_CLOSED), halts what moves
 *   and leaves the card ready: the next program opens it, inherits nothing, and moves without
 *   a reset (the watchdog is disarmed by a clean close, not tripped).
 *
 *     card-emu --name demo &
 *     cc -std=c11 lifecycle.c $(pkg-config --cflags --libs motioncard) -lpthread -o lifecycle
 *     ./lifecycle emu:demo
 */
#define _POSIX_C_SOURCE 200809L
#include "expect.h"

#include <math.h>
#include <pthread.h>
#include <time.h>

static mc_card card;
static mc_motion motion;
static mc_result ending; /* what the waits in progress must return */

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

static void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

typedef struct {
    mc_result result;
    double at_ms;
} outcome;

/* Blocked in a motion wait (30 s) until something ends it. */
static void *motion_waiter(void *arg) {
    outcome *o = arg;
    if (ending == MC_ERR_CANCELLED) {
        EXPECT(mc_motion_wait(card, motion, 30000, NULL), MC_ERR_CANCELLED);
    } else {
        EXPECT(mc_motion_wait(card, motion, 30000, NULL), MC_ERR_CLOSED);
    }
    o->result = ending;
    o->at_ms = now_ms();
    return NULL;
}

/* Blocked in event waits (30 s each) until one fails. */
static void *event_waiter(void *arg) {
    outcome *o = arg;
    mc_event e;
    mc_result r;
    while ((r = mc_wait_event(card, 30000, &e)) == MC_OK) {
    }
    EXPECT(r, ending);
    o->result = r;
    o->at_ms = now_ms();
    return NULL;
}

/* Start both waiters, let them block, run `end` on this thread, and check that both waits
   returned `code` within 100 ms of it. */
static double end_waits(mc_result (*end)(mc_card), mc_result code) {
    outcome om = {1, 0}, oe = {1, 0};
    pthread_t tm, te;
    ending = code;
    ASSERT(pthread_create(&tm, NULL, motion_waiter, &om) == 0, "thread");
    ASSERT(pthread_create(&te, NULL, event_waiter, &oe) == 0, "thread");
    sleep_ms(100); /* both are blocked now */
    const double t0 = now_ms();
    EXPECT(end(card), MC_OK);
    pthread_join(tm, NULL);
    pthread_join(te, NULL);
    ASSERT(om.result == code && oe.result == code, "waits returned %d and %d", om.result,
           oe.result);
    const double worst = fmax(om.at_ms, oe.at_ms) - t0;
    ASSERT(worst < 100.0, "the waits returned %.1f ms after", worst);
    return worst;
}

static mc_result open_when_free(const char *uri, mc_card *c) {
    mc_result r = MC_ERR_BUSY;
    for (int tries = 0; tries < 500 && r == MC_ERR_BUSY; tries++) {
        r = mc_open(uri, c);
        if (r == MC_ERR_BUSY) sleep_ms(10);
    }
    return r;
}

int main(int argc, char **argv) {
    ASSERT(argc > 1 && strncmp(argv[1], "emu:", 4) == 0, "usage: lifecycle emu:NAME");
    const char *uri = argv[1];
    CHECK(mc_open(uri, &card));
    uint32_t inherited = 99;
    CHECK(mc_inherited_stops(card, &inherited));
    ASSERT(inherited == 0, "a fresh card: %u axes inherited", inherited);
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 1e8, &lim));
    CHECK(mc_enable(card, 0));
    CHECK(mc_move_relative(card, 0, 1e8, &lim, &motion)); /* 1000 s */

    /* Cancel: the waits in progress end, a later one does not. */
    const double cancelled = end_waits(mc_cancel_waits, MC_ERR_CANCELLED);
    EXPECT(mc_motion_wait(card, motion, 20, NULL), MC_ERR_TIMEOUT);

    /* Close: every wait in progress ends; the handle is gone. */
    const double closed = end_waits(mc_close, MC_ERR_CLOSED);
    EXPECT(mc_motion_wait(card, motion, 20, NULL), MC_ERR_BAD_HANDLE);

    /* The next program: nothing inherited, nothing latched, the move was halted. */
    mc_card next = 0;
    CHECK(open_when_free(uri, &next));
    CHECK(mc_inherited_stops(next, &inherited));
    ASSERT(inherited == 0, "%u axes inherited after a clean close", inherited);
    mc_status st;
    double at = 0.0;
    for (int i = 0; i < 500; i++) { /* the halt's ramp: 0.1 s */
        CHECK(mc_get_status(next, 0, &st));
        if (st.state == MC_AXIS_STATE_STANDSTILL && st.command_velocity == 0.0) break;
        sleep_ms(5);
    }
    ASSERT(st.state == MC_AXIS_STATE_STANDSTILL && st.stop_reason == MC_STOP_REASON_HOST_DETACH,
           "after a clean close: state %u, stop reason %u", st.state, st.stop_reason);
    mc_safety_status ss;
    CHECK(mc_get_safety_status(next, &ss));
    ASSERT(!ss.watchdog_tripped && ss.host_changes == 0, "watchdog %u, host changes %u",
           ss.watchdog_tripped, ss.host_changes);
    CHECK(mc_enable(next, 0)); /* no mc_reset_faults needed */
    CHECK(mc_move_relative(next, 0, -1000.0, &lim, NULL));
    CHECK(mc_wait_done(next, 0, 10000, &at));
    ASSERT(fabs(at - (st.actual_position - 1000.0)) <= 2.0, "done at %f", at);
    CHECK(mc_close(next));
    printf("cancel ended the waits in %.1f ms, close in %.1f ms; the next program moved at "
           "once\n",
           cancelled, closed);
    printf("PASS lifecycle\n");
    return 0;
}
