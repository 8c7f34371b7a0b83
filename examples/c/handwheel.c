/*
 * The handwheel from C (layout 1.10): an auxiliary encoder jogs an axis at x10, its input handed
 * over to another axis, let go, and the refusals.
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 handwheel.c $(pkg-config --cflags --libs motioncard) -lm -o handwheel && ./handwheel
 */
#include "expect.h"

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

/* Turn auxiliary encoder 0 by `counts` (one count a tick), then let the axes settle. */
static void turn(mc_card c, int counts) {
    CHECK(mc_sim_set_aux_velocity(c, 0, counts < 0 ? -10000.0 : 10000.0));
    CHECK(mc_sim_step(c, (uint64_t)(counts < 0 ? -counts : counts)));
    CHECK(mc_sim_set_aux_velocity(c, 0, 0.0));
    CHECK(mc_sim_step(c, 2000));
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_enable(c, 1));

    /* The refusals: an input, a ratio, a detent, nothing to let go. */
    const uint32_t d = MC_HANDWHEEL_DEFAULT_DETENT;
    EXPECT(mc_handwheel_select(c, 0, MC_AUX_ENCODERS, 10, d, NULL), MC_ERR_HANDWHEEL_INPUT);
    expect_in_message("handwheel");
    EXPECT(mc_handwheel_select(c, 0, 0, 0, d, NULL), MC_ERR_HANDWHEEL_RATIO);
    EXPECT(mc_handwheel_select(c, 0, 0, 10001, d, NULL), MC_ERR_HANDWHEEL_RATIO);
    EXPECT(mc_handwheel_select(c, 0, 0, 10, 0, NULL), MC_ERR_HANDWHEEL_RATIO);
    EXPECT(mc_handwheel_off(c, 0), MC_ERR_INVALID_STATE);
    ASSERT(axis(c, 0).state == MC_AXIS_STATE_STANDSTILL, "a refusal changed the state");

    /* x10: 10 detents of 4 counts move axis 0 by 100 counts. */
    mc_motion m0, m1;
    CHECK(mc_handwheel_select(c, 0, 0, 10, d, &m0));
    ASSERT(axis(c, 0).state == MC_AXIS_STATE_SYNCHRONIZED_MOTION, "not synchronized");
    const double x0 = axis(c, 0).command_position;
    turn(c, 40);
    double x = axis(c, 0).command_position - x0;
    ASSERT(x == 100.0, "10 detents x10: %.3f counts", x);
    printf("handwheel: 10 detents x10: %.1f counts\n", x);

    /* Axis 1 takes the input: axis 0 is done where the wheel put it, axis 1 turns. */
    CHECK(mc_handwheel_select(c, 1, 0, -1, d, &m1));
    double at;
    CHECK(mc_motion_wait(c, m0, 10000, &at));
    ASSERT(axis(c, 0).state == MC_AXIS_STATE_STANDSTILL, "axis 0 still driven");
    turn(c, 40);
    ASSERT(axis(c, 0).command_position - x0 == 100.0, "axis 0 moved after the hand-over");
    x = axis(c, 1).command_position;
    ASSERT(x == -10.0, "10 detents x-1: %.3f counts", x);

    /* Let go: done; the wheel no longer moves it. */
    CHECK(mc_handwheel_off(c, 1));
    CHECK(mc_motion_wait(c, m1, 10000, &at));
    turn(c, 40);
    ASSERT(axis(c, 1).command_position == -10.0, "axis 1 moved after it was let go");

    CHECK(mc_close(c));
    printf("%u checks\n", checks);
    printf("PASS handwheel\n");
    return 0;
}
