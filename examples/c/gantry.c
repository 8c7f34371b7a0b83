/*
 * A gantry from C (layout 1.10): a bridge of two axes (master 0, slave 1) formed, homed (each
 * side by its own homing method, here the current position; then the slave squares the bridge
 * to its offset of 10 counts), the master moved with the slave following, the skew read, the
 * slave refusing a move of its own, and the gantry dissolved (the slave its own axis again).
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 gantry.c $(pkg-config --cflags --libs motioncard) -lm -o gantry && ./gantry
 */
#include "expect.h"

#include <math.h>

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_enable(c, 1));

    const uint32_t slaves[1] = {1};
    const double offsets[1] = {10.0};
    const mc_gantry_settings s = {.kp = 1e6, .ki = 0.0, .skew_limit = 200.0};
    CHECK(mc_gantry_form(c, 0, 0, slaves, 1, &s, offsets));
    mc_gantry_info info;
    CHECK(mc_gantry_get_info(c, 0, &info));
    ASSERT(info.phase == 1 && info.master == 0 && info.nslaves == 1 && info.slave[0] == 1 &&
               !info.squared,
           "formed: phase %u, master %u, %u slaves", info.phase, info.master, info.nslaves);

    /* Homed: square at the offset. */
    double skew = NAN;
    CHECK(mc_gantry_home(c, 0, 10000, &skew));
    CHECK(mc_gantry_get_info(c, 0, &info));
    ASSERT(info.squared && info.hold[0] == 10.0 && fabs(skew) <= 1.0,
           "homed: squared %u, offset in force %g, skew %g", info.squared, info.hold[0], skew);
    printf("gantry: squared, offset in force %.1f counts, skew %.0f counts\n", info.hold[0], skew);

    /* The master moves; the slave follows at its offset. */
    mc_move_limits lim = {2e5, 2e6, 2e6, {1e8, 1e8, 1e8, 1e8}};
    mc_motion m;
    CHECK(mc_move_absolute(c, 0, 20000.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, NULL));
    CHECK(mc_sim_step(c, 100));
    const mc_status m0 = axis(c, 0), s1 = axis(c, 1);
    CHECK(mc_gantry_get_info(c, 0, &info));
    printf("gantry: master at %.0f, slave at %.0f, largest skew %.0f counts\n",
           m0.actual_position, s1.actual_position, info.max_skew[0]);
    ASSERT(fabs(m0.actual_position - 20000.0) <= 1.0 &&
               fabs(s1.actual_position - 20010.0) <= 1.0 && info.max_skew[0] <= 1.0 &&
               fabs(info.skew[0]) <= 1.0,
           "after the move: master %g, slave %g, skew %g, largest %g", m0.actual_position,
           s1.actual_position, info.skew[0], info.max_skew[0]);

    /* A slave takes no command of its own; its master is in a gantry. */
    EXPECT(mc_move_absolute(c, 1, 0.0, &lim, &m), MC_ERR_GANTRY_SLAVE);
    EXPECT(mc_gantry_form(c, 1, 0, slaves, 1, &s, NULL), MC_ERR_GANTRY_IN_USE);

    /* Dissolved: the slave holds where it is, then moves on its own. */
    CHECK(mc_gantry_dissolve(c, 0));
    EXPECT(mc_gantry_get_info(c, 0, &info), MC_ERR_GANTRY_STATE);
    CHECK(mc_move_absolute(c, 1, 0.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, NULL));
    ASSERT(fabs(axis(c, 1).actual_position) <= 1.0 && fabs(axis(c, 0).actual_position - 20000.0) <= 1.0,
           "dissolved: the slave did not move alone");
    CHECK(mc_close(c));
    printf("%u checks\n", checks);
    printf("PASS gantry\n");
    return 0;
}
