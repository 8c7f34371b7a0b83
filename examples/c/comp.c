/*
 * Leadscrew pitch-error and backlash compensation from C (layout 1.9): the refusals, a table
 * loaded and read back, the correction in the status (raw.comp_pos - raw.cmd_pos) after moves
 * from both sides, a change refused while the axis moves, and the table cleared.
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 comp.c $(pkg-config --cflags --libs motioncard) -lm -o comp && ./comp
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
    CHECK(mc_set_position(c, 0, 0.0, 0)); /* the table's frame: homed */

    mc_comp_settings set = {0, 8.0, 20.0, 2000.0, 2e6};
    mc_comp_table_point pts[3] = {{0.0, 0.0, 0.0}, {5000.0, -6.0, -6.0}, {10000.0, 10.0, 10.0}};

    /* The refusals: nothing changes. */
    mc_comp_table_point bad[3] = {{0.0, 0.0, 0.0}, {0.0, 1.0, 1.0}, {10.0, 0.0, 0.0}};
    EXPECT(mc_axis_set_compensation(c, 0, &set, bad, 3), MC_ERR_COMP_ORDER);
    bad[1].position = 5.0;
    bad[1].forward = bad[1].reverse = 17.0; /* + 4 of backlash > 20 */
    EXPECT(mc_axis_set_compensation(c, 0, &set, bad, 3), MC_ERR_COMP_BOUND);
    bad[1].forward = bad[1].reverse = NAN;
    EXPECT(mc_axis_set_compensation(c, 0, &set, bad, 3), MC_ERR_NOT_FINITE);
    bad[1].forward = 1.0;
    bad[1].reverse = 2.0; /* two columns in a one-column table */
    EXPECT(mc_axis_set_compensation(c, 0, &set, bad, 3), MC_ERR_COMP_BOUND);
    static mc_comp_table_point many[257];
    for (int i = 0; i < 257; i++) {
        many[i].position = i;
    }
    EXPECT(mc_axis_set_compensation(c, 0, &set, many, 257), MC_ERR_COMP_TABLE);
    mc_comp_settings slow = set;
    slow.ramp_velocity = 0.0;
    EXPECT(mc_axis_set_compensation(c, 0, &slow, pts, 3), MC_ERR_COMP_TABLE);
    EXPECT(mc_axis_set_compensation(c, 0, NULL, pts, 3), MC_ERR_NULL_POINTER);
    mc_comp_settings got;
    size_t n = 99;
    CHECK(mc_axis_get_compensation(c, 0, &got, NULL, 0, &n));
    if (n != 0 || got.bound != 0.0) {
        fprintf(stderr, "a refused table was kept: %zu points\n", n);
        return 1;
    }

    /* Loaded and read back. */
    CHECK(mc_axis_set_compensation(c, 0, &set, pts, 3));
    mc_comp_table_point back[3];
    EXPECT(mc_axis_get_compensation(c, 0, &got, back, 2, &n), MC_ERR_BUFFER_TOO_SMALL);
    CHECK(mc_axis_get_compensation(c, 0, &got, back, 3, &n));
    if (n != 3 || got.backlash != 8.0 || got.bound != 20.0 || back[1].forward != -6.0 ||
        back[2].position != 10000.0) {
        fprintf(stderr, "read back %zu points, backlash %g\n", n, got.backlash);
        return 1;
    }

    /* The correction in the status: -6 + 16 * 0.5 = 2 at 7500 (+-4 by the side), 6.8 + 4 at 9000. */
    mc_move_limits lim = {2e5, 2e6, 2e6, {1e8, 1e8, 1e8, 1e8}};
    const double targets[3] = {7500.0, 9000.0, 7500.0};
    const double want[3] = {2.0 + 4.0, 6.8 + 4.0, 2.0 - 4.0};
    for (int i = 0; i < 3; i++) {
        mc_motion m;
        CHECK(mc_move_absolute(c, 0, targets[i], &lim, &m));
        CHECK(mc_motion_wait(c, m, 10000, NULL));
        mc_status s = axis(c);
        const double corr = s.raw.comp_pos - s.raw.cmd_pos;
        printf("comp: at %.0f the correction is %.3f counts\n", targets[i], corr);
        if (fabs(corr - want[i]) > 1e-9 || fabs(s.actual_position - targets[i]) > 1.0) {
            fprintf(stderr, "at %g: correction %g, want %g; actual %g\n", targets[i], corr,
                    want[i], s.actual_position);
            return 1;
        }
    }

    /* Moving: refused, the table kept. */
    mc_motion m;
    CHECK(mc_move_absolute(c, 0, 0.0, &lim, &m));
    CHECK(mc_sim_step(c, 50));
    EXPECT(mc_axis_set_compensation(c, 0, &set, pts, 2), MC_ERR_COMP_BUSY);
    EXPECT(mc_axis_clear_compensation(c, 0), MC_ERR_COMP_BUSY);
    CHECK(mc_motion_wait(c, m, 10000, NULL));
    CHECK(mc_axis_get_compensation(c, 0, &got, back, 3, &n));
    if (n != 3) {
        fprintf(stderr, "the table changed while moving: %zu points\n", n);
        return 1;
    }

    CHECK(mc_axis_clear_compensation(c, 0));
    CHECK(mc_axis_get_compensation(c, 0, &got, back, 3, &n));
    if (n != 0) {
        fprintf(stderr, "cleared, yet %zu points\n", n);
        return 1;
    }
    CHECK(mc_close(c));
    printf("%u checks\n", checks);
    printf("PASS comp\n");
    return 0;
}
