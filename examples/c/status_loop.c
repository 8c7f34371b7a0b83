/*
 * Read an axis's status in a loop while it moves, as a PLC-style application or an HMI does:
 * every snapshot is consistent (the card publishes it under a seqlock), the tick only goes
 * forward, the profile stays within its limits, and the loop ends when the motion is done.
 */
#define _POSIX_C_SOURCE 200809L
#include "check.h"

#include <math.h>
#include <time.h>

static void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

int main(int argc, char **argv) {
    mc_card card = 0;
    CHECK(open_from_args(argc, argv, &card));
    const uint32_t axis = 1;
    const double distance = 20000.0, vmax = 100000.0, amax = 1e6; /* counts, counts/s, /s^2 */
    CHECK(mc_enable(card, axis));
    mc_move_limits limits;
    CHECK(mc_move_limits_symmetric(vmax, amax, 5e7, &limits));
    mc_motion motion;
    CHECK(mc_move_relative(card, axis, distance, &limits, &motion));

    /* A stepped card advances only when told; a real-time one on its own. */
    const int stepped = mc_sim_step(card, 0) == MC_OK;
    uint64_t last_tick = 0;
    unsigned reads = 0, moving = 0;
    double peak_ferr = 0.0, at = 0.0;
    for (;;) {
        mc_status s;
        CHECK(mc_get_status(card, axis, &s));
        reads++;
        ASSERT(s.raw.tick >= last_tick, "tick went back from %llu to %llu",
               (unsigned long long)last_tick, (unsigned long long)s.raw.tick);
        last_tick = s.raw.tick;
        ASSERT(s.state == MC_AXIS_STATE_STANDSTILL || s.state == MC_AXIS_STATE_DISCRETE_MOTION,
               "state %u", s.state);
        moving += s.state == MC_AXIS_STATE_DISCRETE_MOTION;
        ASSERT(s.command_position >= -1e-9 && s.command_position <= distance + 1e-9,
               "commanded position %f outside [0, %f]", s.command_position, distance);
        ASSERT(fabs(s.command_velocity) <= vmax * (1 + 1e-9), "commanded velocity %f",
               s.command_velocity);
        ASSERT(fabs(s.command_acceleration) <= amax * (1 + 1e-9), "commanded acceleration %f",
               s.command_acceleration);
        ASSERT(isfinite(s.actual_position) && isfinite(s.dac_volts) && fabs(s.dac_volts) <= 10.0,
               "actual %f, dac %f V", s.actual_position, s.dac_volts);
        if (fabs(s.following_error) > peak_ferr) peak_ferr = fabs(s.following_error);

        mc_result done = mc_motion_wait(card, motion, 0, &at); /* 0: only look */
        if (done == MC_OK) break;
        if (done != MC_ERR_TIMEOUT) fail_call("mc_motion_wait", done, __FILE__, __LINE__);
        ASSERT(reads < 1000000, "the move never finished (%u reads)", reads);
        if (stepped) {
            CHECK(mc_sim_step(card, 10)); /* 1 ms */
        } else {
            sleep_ms(1);
        }
    }
    mc_status s;
    CHECK(mc_get_status(card, axis, &s));
    ASSERT(s.state == MC_AXIS_STATE_STANDSTILL && s.raw.move_count == 1, "state %u, moves %u",
           s.state, s.raw.move_count);
    ASSERT(fabs(at - distance) <= 1.0, "done at %f", at);
    ASSERT(moving > 0, "never saw the axis moving in %u reads", reads);
    printf("%u status reads (%u while moving), peak following error %.2f counts, done at %.1f\n",
           reads, moving, peak_ferr, at);
    CHECK(mc_close(card));
    printf("PASS status_loop\n");
    return 0;
}
