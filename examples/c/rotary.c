/*
 * Rotary (modulo) axes from C (layout 1.10): the period set and read back, its refusals (zero,
 * out of range, a change while moving: nothing changes), absolute moves the shortest way and
 * the way they name, a target outside the turn refused, the status wrapping in velocity
 * mode while the encoder runs on, and position compare on the turn (layout 1.13): a trigger
 * every 10 degrees and one at 90 on every turn, each crossing fired once, and its refusals.
 *
 * Runs on a stepped card (deterministic). Positions in degrees (10,000 counts a turn). The
 * argument is ignored.
 *
 *     cc -std=c11 rotary.c $(pkg-config --cflags --libs motioncard) -lm -o rotary && ./rotary
 */
#include "expect.h"

#include <math.h>

static mc_status axis(mc_card c) {
    mc_status s;
    CHECK(mc_get_status(c, 0, &s));
    return s;
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(1, 10000, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_set_scale(c, 0, 10000.0 / 360.0));

    /* The refusals: nothing changes. */
    double period = -1.0;
    EXPECT(mc_axis_set_modulo(c, 0, 0.0), MC_ERR_MODULO_ZERO);
    EXPECT(mc_axis_set_modulo(c, 0, -360.0), MC_ERR_MODULO_RANGE);
    EXPECT(mc_axis_set_modulo(c, 0, NAN), MC_ERR_MODULO_RANGE);
    EXPECT(mc_axis_set_modulo(c, 0, 1e10), MC_ERR_MODULO_RANGE);
    EXPECT(mc_axis_get_modulo(c, 0, NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_axis_get_modulo(c, 0, &period));
    if (period != 0.0) {
        fprintf(stderr, "a refused period was kept: %g\n", period);
        return 1;
    }

    /* Set and read back. */
    CHECK(mc_axis_set_modulo(c, 0, 360.0));
    CHECK(mc_axis_get_modulo(c, 0, &period));
    if (fabs(period - 360.0) > 1e-9) {
        fprintf(stderr, "period %g\n", period);
        return 1;
    }

    /* Absolute moves: to 10, then to 350 the shortest way (back 20), then positively to 340
     * (forward 350). */
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(720.0, 36000.0, 3.6e6, &lim));
    mc_motion m;
    double done = 0.0;
    CHECK(mc_move_absolute(c, 0, 10.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, &done));
    int64_t e0 = axis(c).raw.encoder;
    CHECK(mc_move_absolute_dir(c, 0, 350.0, MC_MOVE_DIR_SHORTEST, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, &done));
    int64_t e1 = axis(c).raw.encoder;
    CHECK(mc_move_absolute_dir(c, 0, 340.0, MC_MOVE_DIR_POSITIVE, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, &done));
    int64_t e2 = axis(c).raw.encoder;
    printf("rotary: shortest to 350 moved %lld counts, positive to 340 moved %lld, done at %.3f\n",
           (long long)(e1 - e0), (long long)(e2 - e1), done);
    if (llabs((long long)(e1 - e0) + 556) > 2 || llabs((long long)(e2 - e1) - 9722) > 2 ||
        fabs(done - 340.0) > 0.1) {
        fprintf(stderr, "the moves went the wrong way\n");
        return 1;
    }
    EXPECT(mc_move_absolute(c, 0, 360.0, &lim, &m), MC_ERR_MODULO_MOVE);
    EXPECT(mc_move_absolute_dir(c, 0, 10.0, 7, &lim, &m), MC_ERR_BAD_CONFIG);

    /* Velocity mode: the status wraps, the encoder runs on; a change refused while moving. */
    mc_velocity_limits vl = {36000.0, 36000.0, 3.6e6};
    CHECK(mc_move_velocity(c, 0, 1800.0, &vl, NULL));
    EXPECT(mc_axis_set_modulo(c, 0, 720.0), MC_ERR_MODULO_BUSY);
    for (int k = 0; k < 100; k++) {
        CHECK(mc_sim_step(c, 100));
        mc_status s = axis(c);
        if (!(s.actual_position >= 0.0 && s.actual_position < 360.0)) {
            fprintf(stderr, "not wrapped: %g\n", s.actual_position);
            return 1;
        }
    }
    if (axis(c).raw.encoder < 40000) {
        fprintf(stderr, "the encoder did not run on: %lld\n", (long long)axis(c).raw.encoder);
        return 1;
    }
    CHECK(mc_axis_get_modulo(c, 0, &period));
    if (fabs(period - 360.0) > 1e-9) {
        fprintf(stderr, "changed while moving: %g\n", period);
        return 1;
    }

    /* Compare on the turn (layout 1.13): a camera trigger every 10 degrees from 5 (count 0:
     * a whole turn) and a pulse at 90 either way, on every turn, over 2 s (10 turns at
     * 1800 degrees/s). Off the turn, a series longer than the turn, each turn on a linear
     * axis, a period change while a channel watches: refused. */
    EXPECT(mc_compare_single_each_turn(c, 0, 0, 1, 5, 360.0, MC_COMPARE_POSITIVE),
           MC_ERR_COMPARE_TURN);
    EXPECT(mc_compare_series(c, 0, 0, 1, 5, 0.0, 10.0, 37, MC_COMPARE_POSITIVE),
           MC_ERR_COMPARE_TURN);
    CHECK(mc_compare_series_each_turn(c, 0, 0, 1, 5, 5.0, 10.0, 0, MC_COMPARE_POSITIVE));
    CHECK(mc_compare_single_each_turn(c, 0, 1, 2, 5, 90.0, MC_COMPARE_EITHER));
    /* Where the comparator sees the axis: the middle of the count's cell. */
    const double half = 0.5 * 360.0 / 10000.0;
    double p0 = axis(c).actual_position + half;
    int64_t n0 = axis(c).raw.encoder;
    CHECK(mc_sim_step(c, 20000));
    double p1 = p0 + (double)(axis(c).raw.encoder - n0) * 360.0 / 10000.0;
    mc_compare_info grid, ninety;
    CHECK(mc_compare_get_status(c, 0, 0, &grid));
    CHECK(mc_compare_get_status(c, 0, 1, &ninety));
    double want_grid = floor((p1 - 5.0) / 10.0) - floor((p0 - 5.0) / 10.0);
    double want_ninety = floor((p1 - 90.0) / 360.0) - floor((p0 - 90.0) / 360.0);
    printf("compare on the turn: %u fires every 10 degrees (%g crossed), %u at 90 (%g), "
           "pending %u and %u\n",
           grid.fires, want_grid, ninety.fires, want_ninety, grid.pending, ninety.pending);
    if (grid.fires != (unsigned)want_grid || grid.missed != 0 ||
        ninety.fires != (unsigned)want_ninety || ninety.missed != 0 || grid.pending != 36 ||
        ninety.pending != 1 || grid.state != MC_IO_STATE_ARMED || want_grid < 350) {
        fprintf(stderr, "compare on the turn missed a crossing\n");
        return 1;
    }
    CHECK(mc_halt(c, 0, 36000.0, 3.6e6, &m));
    CHECK(mc_motion_wait(c, m, 10000, &done));
    EXPECT(mc_axis_set_modulo(c, 0, 720.0), MC_ERR_COMPARE_TURN);
    CHECK(mc_compare_disarm(c, 0, 0));
    CHECK(mc_compare_disarm(c, 0, 1));
    CHECK(mc_axis_clear_modulo(c, 0));
    EXPECT(mc_compare_single_each_turn(c, 0, 0, 1, 5, 90.0, MC_COMPARE_POSITIVE),
           MC_ERR_COMPARE_TURN);
    CHECK(mc_close(c));
    printf("%u checks\n", checks);
    printf("PASS rotary\n");
    return 0;
}
