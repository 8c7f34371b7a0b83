/*
 * Debugging a C program against the emulated card (README: "Debugging a C program"). Under
 * gdb or valgrind the library's heartbeat thread can be held up for seconds, longer than the
 * card's 100 ms watchdog. Set MOTIONCARD_SIM_WATCHDOG_MS and the `sim` card boots with that
 * timeout, and keeps it as the least a program can set: the watchdog stays armed.
 *
 *     MOTIONCARD_SIM_WATCHDOG_MS=10000 valgrind ./debug 10000
 *     MOTIONCARD_SIM_WATCHDOG_MS=10000 gdb --args ./debug 10000
 *
 * The argument is the timeout expected, in ms (100: the variable is not set). The program opens
 * `sim`, checks the card's timeout, asks for a shorter one (kept at the expected one), moves an
 * axis, and, when the timeout is at most 5 s, stops its heartbeat to see the watchdog trip.
 *
 *     cc -std=c11 debug.c $(pkg-config --cflags --libs motioncard) -o debug
 */
#define _POSIX_C_SOURCE 200809L
#include "expect.h"

#include <math.h>
#include <time.h>

static void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

static uint32_t timeout_us(mc_card c) {
    mc_card_safety_settings s;
    CHECK(mc_get_card_safety(c, &s));
    return s.watchdog_timeout_us;
}

int main(int argc, char **argv) {
    const uint32_t expected_ms = argc > 1 ? (uint32_t)atol(argv[1]) : 100;
    mc_card c = 0;
    CHECK(mc_open("sim", &c));
    ASSERT(timeout_us(c) == expected_ms * 1000, "the card's watchdog timeout is %u us, not %u ms",
           timeout_us(c), expected_ms);
    /* A program's own shorter timeout (check.h's 250 ms): the debugging one stays. */
    CHECK(mc_set_watchdog_timeout(c, 250000));
    const uint32_t kept = expected_ms >= 250 ? expected_ms * 1000 : 250000;
    ASSERT(timeout_us(c) == kept, "after asking for 250 ms: %u us", timeout_us(c));
    mc_safety_status st;
    CHECK(mc_get_safety_status(c, &st));
    ASSERT(st.watchdog_armed && !st.watchdog_tripped, "armed %u, tripped %u", st.watchdog_armed,
           st.watchdog_tripped);

    /* The first enable and a move work (under valgrind: slowly). */
    CHECK(mc_enable(c, 0));
    mc_move_limits l;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 1e8, &l));
    mc_motion m;
    CHECK(mc_move_relative(c, 0, 1000.0, &l, &m));
    double at = 0.0;
    CHECK(mc_motion_wait(c, m, 60000, &at));
    ASSERT(fabs(at - 1000.0) <= 2.0, "done at %f", at);

    /* Still armed: a heartbeat stopped for longer than the timeout trips it. */
    if (expected_ms <= 5000) {
        CHECK(mc_set_heartbeat(c, 0));
        /* Silence counted in the card's own ticks: an emulated card on a loaded machine runs
         * behind the wall clock, and its watchdog counts ticks. */
        mc_card_info info;
        CHECK(mc_get_info(c, &info));
        const uint64_t silence = ((uint64_t)kept / 1000 + 500) * info.servo_rate_hz / 1000;
        uint64_t t0 = 0, t = 0;
        CHECK(mc_get_tick(c, &t0));
        for (int waited = 0; waited < 60000; waited += 10) {
            CHECK(mc_get_tick(c, &t));
            if (t - t0 >= silence) {
                break;
            }
            sleep_ms(10);
        }
        CHECK(mc_set_heartbeat(c, 1));
        CHECK(mc_get_safety_status(c, &st));
        ASSERT(st.watchdog_tripped, "the watchdog did not trip after %u ms of silence",
               kept / 1000 + 500);
        EXPECT(mc_enable(c, 0), MC_ERR_WATCHDOG_TRIPPED);
        printf("debug: the watchdog tripped after %u ms without a heartbeat\n", kept / 1000 + 500);
    }
    CHECK(mc_close(c));
    printf("debug: watchdog timeout %u ms; enabled and moved to %.1f\n", kept / 1000, at);
    printf("PASS debug\n");
    return 0;
}
