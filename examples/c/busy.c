/*
 * A card served by another process (`emu:NAME`, from `card-emu --name NAME`) can be held by
 * one host at a time: a second open, from this process or any other, is MC_ERR_BUSY until the
 * first host closes it. The next host clears the watchdog trip the first one's departure may
 * have left, and moves an axis.
 *
 *     card-emu --name demo &
 *     cc -std=c11 busy.c $(pkg-config --cflags --libs motioncard) -o busy && ./busy emu:demo
 */
#define _POSIX_C_SOURCE 200809L
#include "expect.h"

#include <math.h>
#include <time.h>

static void move_axis_0(mc_card c, double distance) {
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(50000.0, 1e6, 5e7, &lim));
    CHECK(mc_enable(c, 0));
    double at = 0.0;
    mc_status st;
    CHECK(mc_get_status(c, 0, &st));
    const double from = st.actual_position;
    CHECK(mc_move_relative(c, 0, distance, &lim, NULL));
    CHECK(mc_wait_done(c, 0, 10000, &at));
    ASSERT(fabs(at - (from + distance)) <= 2.0, "done at %f, from %f", at, from);
    CHECK(mc_disable(c, 0));
}

int main(int argc, char **argv) {
    ASSERT(argc > 1 && strncmp(argv[1], "emu:", 4) == 0, "usage: busy emu:NAME");
    const char *uri = argv[1];
    mc_card first = 0, second = 777;
    CHECK(mc_open(uri, &first));
    CHECK(relax_watchdog(first));
    EXPECT(mc_open(uri, &second), MC_ERR_BUSY);
    char msg[512];
    /* The message says where the card is open: here, not in another process. */
    ASSERT(strstr(last_error(msg, sizeof msg), "already open in this process") &&
               !strstr(msg, "another process"),
           "message \"%s\"", msg);
    ASSERT(second == 777, "handle written by a refused open");
    mc_card_info info;
    CHECK(mc_get_info(first, &info));
    move_axis_0(first, 1000.0);
    EXPECT(mc_open(uri, &second), MC_ERR_BUSY); /* still held */
    CHECK(mc_close(first));

    /* The card notices the closed connection on its own thread: retry while it does. */
    mc_result r = MC_ERR_BUSY;
    for (int tries = 0; tries < 500 && r == MC_ERR_BUSY; tries++) {
        r = mc_open(uri, &second);
        if (r == MC_ERR_BUSY) nanosleep(&(struct timespec){0, 10 * 1000 * 1000}, NULL);
    }
    CHECK(r);
    /* The first host's heartbeat stopped when it closed: clear a watchdog trip, then move. */
    CHECK(relax_watchdog(second));
    move_axis_0(second, -1000.0);
    CHECK(mc_close(second));
    printf("%s: a second open was MC_ERR_BUSY; reopened after close (%u axes at %u Hz)\n", uri,
           info.axes, info.servo_rate_hz);
    printf("PASS busy\n");
    return 0;
}
