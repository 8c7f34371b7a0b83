/*
 * Running a machine from C: jog an axis and release the button, take a new target while
 * moving (PLCopen Aborting), queue moves behind each other (Buffered), run in velocity mode,
 * and turn the override knob (0 % holds the axis in its motion, 200 % resumes faster), on a
 * stepped emulated card so every figure printed is the same on any machine.
 *
 *     cc -std=c11 machine.c $(pkg-config --cflags --libs motioncard) -o machine && ./machine
 */
#include "expect.h"

#include <math.h>

#define RATE 10000u

static mc_status status(mc_card c, uint32_t axis) {
    mc_status s;
    CHECK(mc_get_status(c, axis, &s));
    return s;
}

/* Step until the axis's motion bits contain `bit` (at most `max` ticks); the ticks taken. */
static unsigned step_until_flag(mc_card c, uint32_t axis, uint32_t bit, unsigned max) {
    for (unsigned k = 1; k <= max; k++) {
        CHECK(mc_sim_step(c, 1));
        if (status(c, axis).raw.motion_flags & bit) return k;
    }
    ASSERT(0, "motion bit %#x not set in %u ticks", bit, max);
    return 0;
}

int main(void) {
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, RATE, &c));
    const uint32_t x = 0;
    CHECK(mc_enable(c, x));
    mc_axis_settings cfg;
    CHECK(mc_axis_settings_default(&cfg));

    /* Jog: the button held for 0.3 s, then released (a halt at the jog deceleration). */
    mc_motion jog;
    EXPECT(mc_jog(c, x, cfg.jog_max_vel * 2.0, &jog), MC_ERR_OUT_OF_RANGE);
    CHECK(mc_jog(c, x, 20000.0, &jog));
    double v = 0.0;
    CHECK(mc_motion_wait_in_velocity(c, jog, 10000, &v));
    ASSERT(v == 20000.0, "in velocity at %f", v);
    ASSERT(status(c, x).state == MC_AXIS_STATE_CONTINUOUS_MOTION, "state");
    CHECK(mc_sim_step(c, (uint64_t)(0.3 * RATE)));
    mc_motion release;
    CHECK(mc_jog_release(c, x, &release));
    EXPECT(mc_motion_wait(c, jog, 0, NULL), MC_ERR_ABORTED); /* the jog ends by the halt */
    double at = 0.0;
    CHECK(mc_motion_wait(c, release, 10000, &at));
    printf("jog: released at %.0f counts\n", at);

    /* A new target while moving: it takes over at once, the first move is aborted. */
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(100000.0, 1e6, 5e7, &lim));
    mc_motion first, second;
    CHECK(mc_move_absolute(c, x, 200000.0, &lim, &first));
    CHECK(mc_sim_step(c, 1000)); /* 0.1 s: accelerating, 5,000 counts out */
    const double before = status(c, x).command_acceleration;
    CHECK(mc_move_absolute(c, x, -10000.0, &lim, &second));
    CHECK(mc_sim_step(c, 1));
    mc_status s = status(c, x);
    ASSERT(s.command_acceleration < before, "acceleration %f -> %f", before,
           s.command_acceleration);
    ASSERT(fabs(s.command_acceleration - before) <= 5e7 / RATE * (1 + 1e-6),
           "a step in acceleration");
    EXPECT(mc_motion_wait(c, first, 0, NULL), MC_ERR_ABORTED);
    CHECK(mc_motion_wait(c, second, 60000, &at));
    ASSERT(fabs(at + 10000.0) <= 1.0, "retargeted move ended at %f", at);
    printf("abort: retargeted to -10000, in position at %.0f\n", at);

    /* Buffered moves: each starts when the one before is done, and reports its own done. */
    mc_motion q[3];
    for (int k = 0; k < 3; k++) {
        CHECK(mc_move(c, x, MC_MOVE_KIND_RELATIVE, 1000.0, &lim, MC_BUFFER_BUFFERED, &q[k]));
    }
    EXPECT(mc_move(c, x, 7, 1.0, &lim, MC_BUFFER_BUFFERED, NULL), MC_ERR_BAD_CONFIG);
    for (int k = 0; k < 3; k++) {
        CHECK(mc_motion_wait(c, q[k], 60000, &at));
        ASSERT(fabs(at - (-10000.0 + 1000.0 * (k + 1))) <= 1.0, "buffered %d at %f", k, at);
    }
    printf("buffered: three moves of 1000, ended at %.0f\n", at);

    /* Velocity mode, then the override knob: 50 %, 0 % (held in ContinuousMotion), 200 %. */
    mc_velocity_limits vl = {1e6, 1e6, 5e7};
    mc_motion vm;
    CHECK(mc_move_velocity(c, x, 40000.0, &vl, &vm));
    CHECK(mc_motion_wait_in_velocity(c, vm, 10000, NULL));
    CHECK(mc_set_override(c, x, 0.5));
    unsigned ticks = step_until_flag(c, x, MC_MOTION_IN_VELOCITY, 10000);
    ASSERT(status(c, x).command_velocity == 20000.0, "50 %%");
    printf("override 50 %%: at 20000 counts/s after %u ticks\n", ticks);
    CHECK(mc_set_override(c, x, 0.0));
    step_until_flag(c, x, MC_MOTION_IN_VELOCITY, 10000);
    s = status(c, x);
    ASSERT(s.command_velocity == 0.0 && s.state == MC_AXIS_STATE_CONTINUOUS_MOTION,
           "0 %% holds: v %f state %u", s.command_velocity, s.state);
    EXPECT(mc_set_override(c, x, 2.5), MC_ERR_OVERRIDE_RANGE);
    CHECK(mc_set_override(c, x, 2.0));
    step_until_flag(c, x, MC_MOTION_IN_VELOCITY, 10000);
    ASSERT(status(c, x).command_velocity == 80000.0, "200 %%");
    printf("override 0 %% held, 200 %%: at 80000 counts/s\n");
    mc_motion halt;
    CHECK(mc_halt(c, x, 1e6, 5e7, &halt));
    CHECK(mc_motion_wait(c, halt, 60000, NULL));
    ASSERT(status(c, x).state == MC_AXIS_STATE_STANDSTILL, "halted");

    CHECK(mc_close(c));
    printf("PASS machine (%u checks)\n", checks);
    return 0;
}
