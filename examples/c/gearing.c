/*
 * Electronic gearing from C (layout 1.7): MC_GearIn on an auxiliary encoder (a conveyor) run
 * for 10^9 counts at 7/99991, the slave exactly where integer arithmetic puts it; MC_GearIn on
 * another axis's commanded position (the slave catches up within its limits, then follows at
 * the ratio); MC_GearOut (the slave keeps its velocity), MC_GearInPos (the slave at a given
 * position when the master is at a given position), a master disabled under its slave, and the
 * refusals.
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 gearing.c $(pkg-config --cflags --libs motioncard) -lm -o gearing && ./gearing
 */
#include "expect.h"

#include <math.h>

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

static int in_sync(mc_card c, uint32_t a) {
    return (axis(c, a).raw.motion_flags & MC_MOTION_IN_SYNC) != 0;
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    const uint32_t slave = 0, master = 1;
    CHECK(mc_enable(c, slave));
    CHECK(mc_enable(c, master));
    mc_sync_limits lim = {20000.0, 2e5, 2e7};

    /* The refusals: a ratio, a master, a state, pointers. */
    EXPECT(mc_gear_in(c, slave, MC_MASTER_AUX, 0, 1, 0, &lim, NULL), MC_ERR_GEAR_RATIO);
    expect_in_message("gear ratio");
    EXPECT(mc_gear_in(c, slave, MC_MASTER_AUX, 0, 3, -7, &lim, NULL), MC_ERR_GEAR_RATIO);
    EXPECT(mc_gear_in(c, slave, MC_MASTER_COMMANDED, slave, 1, 1, &lim, NULL),
           MC_ERR_SYNC_MASTER);
    EXPECT(mc_gear_in(c, slave, MC_MASTER_AUX, MC_AUX_ENCODERS, 1, 1, &lim, NULL),
           MC_ERR_SYNC_MASTER);
    EXPECT(mc_gear_in(c, slave, MC_MASTER_ACTUAL_LEAD, slave, 1, 1, &lim, NULL),
           MC_ERR_SYNC_MASTER);
    EXPECT(mc_gear_in(c, slave, 9, 0, 1, 1, &lim, NULL), MC_ERR_BAD_CONFIG);
    EXPECT(mc_gear_in(c, slave, MC_MASTER_AUX, 0, 1, 1, NULL, NULL), MC_ERR_NULL_POINTER);
    mc_sync_limits bad = lim;
    bad.jerk = NAN;
    EXPECT(mc_gear_in(c, slave, MC_MASTER_AUX, 0, 1, 1, &bad, NULL), MC_ERR_NOT_FINITE);
    EXPECT(mc_gear_out(c, slave, NULL), MC_ERR_INVALID_STATE);
    EXPECT(mc_aux_encoder(c, 5, &(int64_t){0}), MC_ERR_SYNC_MASTER);
    double offset = -1.0;
    EXPECT(mc_gear_get_offset(c, slave, &offset), MC_ERR_INVALID_STATE); /* not geared */
    EXPECT(mc_gear_get_offset(c, slave, NULL), MC_ERR_NULL_POINTER);

    /* A conveyor on aux encoder 0 at 10^8 counts/s for 10^5 ticks: 10^9 counts. */
    const double x0 = axis(c, slave).command_position;
    int64_t m0 = 0, m1 = 0;
    CHECK(mc_aux_encoder(c, 0, &m0));
    mc_motion g;
    CHECK(mc_gear_in(c, slave, MC_MASTER_AUX, 0, 7, 99991, &lim, &g));
    double at = 0.0;
    CHECK(mc_motion_wait_in_sync(c, g, 1000, &at));
    ASSERT(at == x0 && in_sync(c, slave), "in gear at rest: at %f", at);
    CHECK(mc_sim_set_aux_velocity(c, 0, 1e8));
    CHECK(mc_sim_step(c, 100000));
    CHECK(mc_sim_set_aux_velocity(c, 0, 0.0));
    CHECK(mc_sim_step(c, 3000));
    CHECK(mc_aux_encoder(c, 0, &m1));
    const int64_t dm = m1 - m0;
    ASSERT(dm == 1000000000, "the conveyor ran %lld counts", (long long)dm);
    const int64_t q = 7 * dm / 99991, r = 7 * dm % 99991;
    const double expected = x0 + (double)q + (double)r / 99991.0;
    mc_status s = axis(c, slave);
    ASSERT(s.command_position == expected && s.state == MC_AXIS_STATE_SYNCHRONIZED_MOTION,
           "after 1e9 counts: %.9f, expected %.9f", s.command_position, expected);
    printf("1e9 master counts at 7/99991: slave at %.6f, error %g counts\n", s.command_position,
           s.command_position - expected);

    /* Gear onto the master axis's commanded position (Aborting the conveyor's coupling): the
       slave catches up with half the master's 20000 counts/s, then follows it. */
    mc_velocity_limits vl = {2e5, 2e5, 2e7};
    mc_motion mv;
    CHECK(mc_move_velocity(c, master, 20000.0, &vl, &mv));
    CHECK(mc_motion_wait_in_velocity(c, mv, 10000, NULL));
    mc_motion g2;
    CHECK(mc_gear_in(c, slave, MC_MASTER_COMMANDED, master, 1, 2, &lim, &g2));
    EXPECT(mc_motion_wait(c, g, 0, &at), MC_ERR_ABORTED);
    CHECK(mc_motion_wait_in_sync(c, g2, 10000, &at));
    CHECK(mc_sim_step(c, 10));
    s = axis(c, slave);
    ASSERT(in_sync(c, slave) && s.command_velocity == 10000.0, "in gear at %f counts/s",
           s.command_velocity);
    printf("in gear at 1/2: %.1f counts/s\n", s.command_velocity);
    /* The coupling is relative to the engagement: slave = offset + master / 2 (counts), the
       offset where the card anchored the line; exact each tick, the master's command of the
       same tick (within its 1/65536 count). */
    CHECK(mc_gear_get_offset(c, slave, &offset));
    for (int k = 0; k < 100; k++) {
        CHECK(mc_sim_step(c, 1));
        const double x = axis(c, slave).command_position;
        const double m = axis(c, master).command_position;
        ASSERT(fabs(x - (offset + m / 2.0)) <= 1.0 / 65536.0, "tick %d: slave %f, master %f, "
               "offset %f", k, x, m, offset);
    }
    printf("gear offset %.4f counts: slave = offset + master / 2\n", offset);

    /* MC_GearOut: the slave keeps its velocity. */
    mc_motion out;
    CHECK(mc_gear_out(c, slave, &out));
    double v = 0.0;
    CHECK(mc_motion_wait_in_velocity(c, out, 10000, &v));
    ASSERT(v == 10000.0 && axis(c, slave).state == MC_AXIS_STATE_CONTINUOUS_MOTION,
           "gear out at %f", v);
    CHECK(mc_halt(c, slave, 2e5, 2e7, &out));
    CHECK(mc_motion_wait(c, out, 10000, NULL));

    /* MC_GearInPos at 1/2: the slave 5000 counts further when the master is 20000 further. */
    const double m_sync = round(axis(c, master).command_position) + 20000.0;
    EXPECT(mc_gear_in_pos(c, slave, MC_MASTER_COMMANDED, master, 1, 1,
                          axis(c, master).command_position + 10.0, 20000.0, &lim, NULL),
           MC_ERR_INFEASIBLE);
    const double s_sync = axis(c, slave).command_position + 5000.0;
    CHECK(mc_gear_in_pos(c, slave, MC_MASTER_COMMANDED, master, 1, 2, m_sync, s_sync, &lim,
                         &g));
    CHECK(mc_motion_wait_in_sync(c, g, 30000, &at));
    /* In sync in the tick the master's command reaches the sync point (within the 1/65536
       count the card counts a commanded master in). */
    ASSERT(fabs(at - s_sync) < 1e-3 &&
               axis(c, master).command_position >= m_sync - 1.0 / 65536.0,
           "in sync at %f, not %f (master %f, sync point %f)", at, s_sync,
           axis(c, master).command_position, m_sync);
    printf("in sync: slave %.3f when the master passed %.0f\n", at, m_sync);

    /* The master disabled: the slave stops on its stop ramp, and a sync event says why. */
    mc_event e;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
    }
    CHECK(mc_disable(c, master));
    EXPECT(mc_motion_wait(c, g, 1000, &at), MC_ERR_ABORTED);
    int lost = 0;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        lost |= e.kind == MC_EVENT_SYNC && e.code == MC_SYNC_MASTER_LOST && e.seq == g.seq;
    }
    ASSERT(lost, "no MC_SYNC_MASTER_LOST");
    CHECK(mc_sim_step(c, 5000));
    s = axis(c, slave);
    ASSERT(s.state == MC_AXIS_STATE_STANDSTILL && s.command_velocity == 0.0,
           "after the master was lost: state %u", s.state);
    EXPECT(mc_gear_in(c, slave, MC_MASTER_COMMANDED, master, 1, 1, &lim, NULL),
           MC_ERR_SYNC_MASTER);

    CHECK(mc_close(c));
    const mc_result codes[] = {MC_ERR_GEAR_RATIO, MC_ERR_SYNC_MASTER};
    for (size_t k = 0; k < sizeof codes / sizeof codes[0]; k++) {
        ASSERT(seen[-codes[k]], "code %d (%s) never returned", (int)codes[k],
               mc_result_str(codes[k]));
    }
    printf("%u checks\n", checks);
    printf("PASS gearing\n");
    return 0;
}
