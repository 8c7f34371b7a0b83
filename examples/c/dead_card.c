/*
 * A card that dies, or stops, is reported as such by every call, never as stale data:
 *
 *     dead_card emu:NAME kill   the card process is killed while this program waits: the wait
 *                               and every later call return MC_ERR_CARD_GONE at once;
 *     dead_card emu:NAME stop   the card process is stopped (SIGSTOP) while this program
 *                               waits: the wait and every read return MC_ERR_NOT_RESPONDING
 *                               once the card's tick has stood still too long; a command
 *                               fails once its deadline has passed, and the card, when it
 *                               continues, refuses it: it never runs.
 *
 * The program prints READY when its move runs and it is about to wait; whoever runs it then
 * kills or stops the card process (the Rust test does; by hand: kill -9 / kill -STOP, then
 * kill -CONT, the pid of card-emu).
 */
#define _POSIX_C_SOURCE 200809L
#include "expect.h"

#include <math.h>
#include <time.h>

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

int main(int argc, char **argv) {
    ASSERT(argc > 2 && strncmp(argv[1], "emu:", 4) == 0 &&
               (strcmp(argv[2], "kill") == 0 || strcmp(argv[2], "stop") == 0),
           "usage: dead_card emu:NAME kill|stop");
    const int killed = strcmp(argv[2], "kill") == 0;
    const mc_result dead = killed ? MC_ERR_CARD_GONE : MC_ERR_NOT_RESPONDING;
    mc_card c = 0;
    CHECK(mc_open(argv[1], &c));
    CHECK(mc_set_watchdog_timeout(c, 250000));
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 1e8, &lim));
    CHECK(mc_enable(c, 0));
    CHECK(mc_enable(c, 1));
    mc_motion m;
    CHECK(mc_move_relative(c, 0, killed ? 1e8 : 20000.0, &lim, &m));
    printf("READY\n");
    fflush(stdout);

    /* Blocked until the card dies or stops. */
    if (killed) {
        EXPECT(mc_motion_wait(c, m, 30000, NULL), MC_ERR_CARD_GONE);
    } else {
        EXPECT(mc_motion_wait(c, m, 30000, NULL), MC_ERR_NOT_RESPONDING);
    }
    printf("WAIT-ENDED %.3f\n", now_ms());
    fflush(stdout);

    /* Every read says so: never the old snapshot. */
    uint64_t tick = 0;
    mc_status st = {.state = 99};
    mc_safety_status ss = {.protocol_errors = 99};
    mc_event ev;
    double t0 = now_ms();
    EXPECT(mc_get_tick(c, &tick), dead);
    EXPECT(mc_get_status(c, 0, &st), dead);
    EXPECT(mc_get_safety_status(c, &ss), dead);
    ASSERT(tick == 0 && st.state == 99 && ss.protocol_errors == 99, "outputs written");
    /* (events posted before it died still come out: drain them, then the wait fails) */
    mc_result r;
    while ((r = mc_wait_event(c, 5000, &ev)) == MC_OK) {
    }
    EXPECT(r, dead);
    const double reads_ms = now_ms() - t0;

    if (killed) {
        t0 = now_ms();
        EXPECT(mc_move_relative(c, 1, 1000.0, &lim, NULL), MC_ERR_CARD_GONE);
        EXPECT(mc_ping(c), MC_ERR_CARD_GONE);
        ASSERT(now_ms() - t0 < 50.0, "commands to a gone card took %.1f ms", now_ms() - t0);
        CHECK(mc_close(c));
        printf("killed: reads and waits failed in %.1f ms\n", reads_ms);
        printf("PASS dead_card\n");
        return 0;
    }

    /* Stopped: a command gives up once its deadline has passed, knowing it cannot run. */
    t0 = now_ms();
    EXPECT(mc_move_relative(c, 1, 50000.0, &lim, NULL), MC_ERR_NOT_RESPONDING);
    expect_in_message("will not run");
    const double gave_up_ms = now_ms() - t0;
    printf("GAVE-UP %.1f\n", gave_up_ms);
    fflush(stdout);

    /* The card continues: the first move finishes, the refused one never ran. */
    double at = 0.0;
    r = MC_ERR_NOT_RESPONDING;
    for (int i = 0; i < 100 && r != MC_OK; i++) {
        r = mc_motion_wait(c, m, 100, &at);
        if (r == MC_ERR_TIMEOUT) r = MC_ERR_NOT_RESPONDING;
    }
    CHECK(r);
    ASSERT(fabs(at - 20000.0) <= 1.0, "the first move ended at %f", at);
    struct timespec pause = {0, 200 * 1000 * 1000};
    nanosleep(&pause, NULL);
    CHECK(mc_get_status(c, 1, &st));
    ASSERT(st.raw.move_count == 0 && fabs(st.actual_position) <= 1.0 &&
               st.state == MC_AXIS_STATE_STANDSTILL,
           "axis 1 ran the command given up on: %u moves, at %f", st.raw.move_count,
           st.actual_position);
    CHECK(mc_close(c));
    printf("stopped: reads and waits failed in %.1f ms, a command gave up after %.1f ms\n",
           reads_ms, gave_up_ms);
    printf("PASS dead_card\n");
    return 0;
}
