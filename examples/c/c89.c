/*
 * A program in C89 (ANSI C), as some industrial toolchains still compile: motioncard.h asks
 * for nothing newer. It opens a stepped emulated card, moves an axis out and waits for the
 * position, moves it back and waits without one (NULL), then reads where it ended.
 *
 *     cc -std=c89 -pedantic-errors c89.c $(pkg-config --cflags --libs motioncard) -o c89 && ./c89
 */
#include <motioncard.h>
#include <stdio.h>
#include <stdlib.h>

static void check(mc_result r, const char *what, int line) {
    char msg[256];
    size_t needed = 0;
    if (r == MC_OK) {
        return;
    }
    if (mc_last_error_message(msg, sizeof msg, &needed) != MC_OK) {
        msg[0] = '\0';
    }
    fprintf(stderr, "c89.c:%d: %s failed: %d (%s): %s\n", line, what, (int)r, mc_result_str(r),
            msg);
    exit(1);
}

#define CHECK(call) check((call), #call, __LINE__)

static int near(double a, double b) {
    return a - b <= 1.0 && b - a <= 1.0;
}

int main(void) {
    mc_card card = 0;
    mc_move_limits limits;
    mc_motion out;
    mc_status status;
    uint64_t tick = 0;
    double at = 0.0;

    CHECK(mc_open_sim_stepped(1, 10000, &card));
    CHECK(mc_enable(card, 0));
    CHECK(mc_move_limits_symmetric(50000.0, 1e6, 5e7, &limits)); /* counts/s, /s^2, /s^3 */
    CHECK(mc_move_absolute(card, 0, 10000.0, &limits, &out));
    CHECK(mc_motion_wait(card, out, 5000, &at));
    CHECK(mc_move_relative(card, 0, -4000.0, &limits, NULL));
    CHECK(mc_wait_done(card, 0, 5000, NULL)); /* the position is optional */
    CHECK(mc_get_status(card, 0, &status));
    CHECK(mc_get_tick(card, &tick));
    if (!near(at, 10000.0) || !near(status.actual_position, 6000.0) ||
        status.state != MC_AXIS_STATE_STANDSTILL) {
        fprintf(stderr, "c89.c: out to %f, back to %f, state %lu\n", at, status.actual_position,
                (unsigned long)status.state);
        return 1;
    }
    printf("C89: out to %.1f, back to %.1f counts at tick %.0f\n", at, status.actual_position,
           (double)tick);
    CHECK(mc_close(card));
    printf("PASS c89\n");
    return 0;
}
