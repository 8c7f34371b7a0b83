/*
 * A NURBS path longer than the card's move queue, from C: an emulated card opened with
 * explicit options (mc_open_sim: stepped clock, 2 axes), knot vectors from
 * mc_nurbs_clamped_uniform_knots, and 40 cubic pieces sent with mc_group_move_nurbs_path,
 * which waits for earlier pieces whenever the card's queue (32 moves) is full. Then the error
 * paths of those calls, and cards with the free-running and real-time clocks.
 *
 * Positions in counts (scale 1). The argument is ignored.
 *
 *     cc -std=c11 nurbs_path.c $(pkg-config --cflags --libs motioncard) -lm -o nurbs_path
 */
#include "expect.h"

#include <math.h>


#define PIECES 40
#define NCTRL 5
#define DEGREE 3
#define NKNOTS (NCTRL + DEGREE + 1)

static const double L = 2000.0; /* counts along x per piece */
static const double H = 500.0;  /* bulge in y */

static double ctrl[PIECES][NCTRL * 2];
static double weights[NCTRL] = {1, 1, 1, 1, 1};
static double knots[NKNOTS];
static mc_nurbs_curve path[PIECES];

static mc_group_status group(mc_card c) {
    mc_group_status s;
    CHECK(mc_group_get_status(c, 0, &s));
    return s;
}

static void knot_vector(void) {
    size_t needed = 0;
    EXPECT(mc_nurbs_clamped_uniform_knots(NCTRL, DEGREE, NULL, 0, &needed),
           MC_ERR_BUFFER_TOO_SMALL);
    ASSERT(needed == NKNOTS, "needed %zu", needed);
    double small[NKNOTS - 1];
    for (size_t i = 0; i < NKNOTS - 1; i++) small[i] = -1.0;
    size_t needed2 = 0;
    EXPECT(mc_nurbs_clamped_uniform_knots(NCTRL, DEGREE, small, NKNOTS - 1, &needed2),
           MC_ERR_BUFFER_TOO_SMALL);
    ASSERT(needed2 == NKNOTS && small[0] == -1.0, "too small a buffer was written");
    EXPECT(mc_nurbs_clamped_uniform_knots(NCTRL, DEGREE, knots, NKNOTS, &needed), MC_OK);
    const double want[NKNOTS] = {0, 0, 0, 0, 0.5, 1, 1, 1, 1};
    for (size_t i = 0; i < NKNOTS; i++) {
        ASSERT(knots[i] == want[i], "knot %zu is %f, want %f", i, knots[i], want[i]);
    }
    /* Refused: the codes the card gives for such curves. */
    double k[16];
    EXPECT(mc_nurbs_clamped_uniform_knots(NCTRL, 0, k, 16, &needed), MC_ERR_NURBS_DEGREE);
    EXPECT(mc_nurbs_clamped_uniform_knots(NCTRL, 6, k, 16, &needed), MC_ERR_NURBS_DEGREE);
    EXPECT(mc_nurbs_clamped_uniform_knots(3, DEGREE, k, 16, &needed), MC_ERR_NURBS_CTRL_COUNT);
    EXPECT(mc_nurbs_clamped_uniform_knots(2000, DEGREE, k, 16, &needed),
           MC_ERR_NURBS_CTRL_COUNT);
    EXPECT(mc_nurbs_clamped_uniform_knots(NCTRL, DEGREE, k, 16, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_nurbs_clamped_uniform_knots(NCTRL, DEGREE, NULL, 16, &needed),
           MC_ERR_NULL_POINTER);
    ASSERT(needed == NKNOTS, "needed written by a refused call");
}

/* Piece i goes from (i L, 0) to ((i+1) L, 0), bulging to +-H in y. */
static void build_path(void) {
    for (int i = 0; i < PIECES; i++) {
        const double x0 = i * L, h = (i % 2 ? -H : H);
        const double pts[NCTRL * 2] = {x0, 0, x0 + L / 4, h, x0 + L / 2, 0,
                                       x0 + 3 * L / 4, -h, x0 + L, 0};
        memcpy(ctrl[i], pts, sizeof pts);
        path[i] = (mc_nurbs_curve){.degree = DEGREE, .dim = 2, .ctrl = ctrl[i],
                                   .n_ctrl = NCTRL, .weights = weights, .knots = knots,
                                   .n_knots = NKNOTS};
    }
}

static void refused_paths(mc_card c, const mc_nurbs_feed *feed) {
    const uint32_t before = group(c).move_count;
    mc_group_motion m = {77, 77};
    EXPECT(mc_group_move_nurbs_path(c, 0, NULL, 3, feed, 1000, &m), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_nurbs_path(c, 0, path, 3, NULL, 1000, &m), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_nurbs_path(c, 0, NULL, 0, feed, 1000, &m), MC_ERR_UNSUPPORTED);
    expect_in_message("empty NURBS path");
    EXPECT(mc_group_move_nurbs_path(c, 7, path, 3, feed, 1000, &m), MC_ERR_BAD_GROUP);
    EXPECT(mc_group_move_nurbs_path(0, 0, path, 3, feed, 1000, &m), MC_ERR_BAD_HANDLE);
    /* A bad piece anywhere: nothing is sent. */
    mc_nurbs_curve bad[3] = {path[0], path[1], path[2]};
    double bad_knots[NKNOTS];
    memcpy(bad_knots, knots, sizeof knots);
    bad_knots[4] = 2.0; /* then 1: decreasing */
    bad[2].knots = bad_knots;
    EXPECT(mc_group_move_nurbs_path(c, 0, bad, 3, feed, 1000, &m), MC_ERR_NURBS_KNOTS_DECREASING);
    expect_in_message("curve 2: ");
    bad[2] = path[2];
    bad[1].weights = NULL;
    EXPECT(mc_group_move_nurbs_path(c, 0, bad, 3, feed, 1000, &m), MC_ERR_NULL_POINTER);
    expect_in_message("curves[1].weights is NULL");
    bad[1] = path[1];
    bad[0].degree = 6;
    EXPECT(mc_group_move_nurbs_path(c, 0, bad, 3, feed, 1000, &m), MC_ERR_NURBS_DEGREE);
    expect_in_message("curve 0: ");
    ASSERT(m.group == 77 && m.seq == 77, "motion written by a refused path");
    ASSERT(group(c).move_count == before && group(c).state == MC_GROUP_STATE_STANDBY,
           "a refused path moved the group");
}

static void long_path(void) {
    mc_sim_options o;
    CHECK(mc_sim_options_default(&o));
    ASSERT(o.clock == MC_SIM_CLOCK_REAL_TIME && o.axes == 8 && o.servo_rate_hz == 10000 &&
               o.plant == MC_SIM_PLANT_DEFAULT,
           "defaults %u %u %u %u", o.clock, o.axes, o.servo_rate_hz, o.plant);
    o.clock = MC_SIM_CLOCK_STEPPED;
    o.axes = 2;
    mc_card c = 0;
    CHECK(mc_open_sim(&o, &c));
    mc_card_info info;
    CHECK(mc_get_info(c, &info));
    ASSERT(info.axes == 2 && info.servo_rate_hz == 10000, "axes %u rate %u", info.axes,
           info.servo_rate_hz);
    double t0 = -1.0;
    CHECK(mc_sim_time(c, &t0)); /* stepped: mc_sim_time works */

    const uint32_t xy[2] = {0, 1};
    for (int i = 0; i < 2; i++) CHECK(mc_enable(c, xy[i]));
    mc_group_settings gs;
    CHECK(mc_group_settings_new(xy, 2, &gs));
    CHECK(mc_group_configure(c, 0, &gs));
    CHECK(mc_group_enable(c, 0));
    mc_nurbs_feed feed; /* the SDK's default chord tolerance, not saturation-aware */
    CHECK(mc_nurbs_feed_new(40000.0, 1e6, 1e8, &feed));
    refused_paths(c, &feed);

    const uint32_t before = group(c).move_count;
    mc_group_motion m;
    CHECK(mc_group_move_nurbs_path(c, 0, path, PIECES, &feed, 60000, &m));
    /* More pieces than the queue holds: the call waited for the first ones. */
    ASSERT(group(c).move_count - before > PIECES - 32, "%u pieces started while sending",
           group(c).move_count - before);
    CHECK(mc_group_motion_wait(c, m, 60000));
    mc_group_status g = group(c);
    ASSERT(g.state == MC_GROUP_STATE_STANDBY && g.move_count - before == PIECES,
           "state %u, %u moves", g.state, g.move_count - before);
    const double end[2] = {PIECES * L, 0.0};
    for (int i = 0; i < 2; i++) {
        mc_status s;
        CHECK(mc_get_status(c, xy[i], &s));
        ASSERT(s.command_position == end[i] && fabs(s.actual_position - end[i]) <= 1.0,
               "axis %d commanded %f, at %f, end %f", i, s.command_position,
               s.actual_position, end[i]);
    }
    double t1 = 0.0;
    CHECK(mc_sim_time(c, &t1));
    printf("NURBS path: %d pieces to x = %.0f in %.3f s of card time\n", PIECES, end[0],
           t1 - t0);
    CHECK(mc_close(c));
}

/* The other clocks, and options the library refuses. */
static void clocks_and_options(void) {
    mc_sim_options o;
    CHECK(mc_sim_options_default(&o));
    mc_card c = 777;
    const mc_sim_options ok = o;
    EXPECT(mc_open_sim(NULL, &c), MC_ERR_NULL_POINTER);
    EXPECT(mc_open_sim(&ok, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_sim_options_default(NULL), MC_ERR_NULL_POINTER);
    o.clock = 3;
    EXPECT(mc_open_sim(&o, &c), MC_ERR_BAD_CONFIG);
    expect_in_message("unknown clock 3");
    o = ok;
    o.plant = 2;
    EXPECT(mc_open_sim(&o, &c), MC_ERR_BAD_CONFIG);
    const uint32_t bad_axes[] = {0, 9, 0xFFFFFFFFu};
    for (size_t i = 0; i < 3; i++) {
        o = ok;
        o.axes = bad_axes[i];
        EXPECT(mc_open_sim(&o, &c), MC_ERR_BAD_CONFIG);
    }
    expect_in_message("axes");
    const uint32_t bad_rates[] = {0, 999, 20001};
    for (size_t i = 0; i < 3; i++) {
        o = ok;
        o.servo_rate_hz = bad_rates[i];
        EXPECT(mc_open_sim(&o, &c), MC_ERR_BAD_CONFIG);
    }
    expect_in_message("servo rate");
    /* The stepped shortcut refuses the same values instead of clamping them. */
    EXPECT(mc_open_sim_stepped(0, 10000, &c), MC_ERR_BAD_CONFIG);
    EXPECT(mc_open_sim_stepped(9, 10000, &c), MC_ERR_BAD_CONFIG);
    EXPECT(mc_open_sim_stepped(2, 50, &c), MC_ERR_BAD_CONFIG);
    EXPECT(mc_open_sim_stepped(2, 50000, &c), MC_ERR_BAD_CONFIG);
    ASSERT(c == 777, "handle written by a refused open");

    /* A free-running card and a real-time one with the die bonder's plant at 1 kHz. */
    const uint32_t clocks[2] = {MC_SIM_CLOCK_FREE_RUNNING, MC_SIM_CLOCK_REAL_TIME};
    for (int k = 0; k < 2; k++) {
        o = ok;
        o.clock = clocks[k];
        o.axes = 2;
        if (k == 1) {
            o.plant = MC_SIM_PLANT_DIE_BONDER;
            o.servo_rate_hz = 1000;
        }
        CHECK(mc_open_sim(&o, &c));
        if (o.clock == MC_SIM_CLOCK_FREE_RUNNING) {
            /* Card time runs far ahead of the wall clock the library's heartbeat keeps: 5 ms of
               card time pass between two beats and the watchdog trips. Give it ~71 minutes of
               card time and clear a trip that came first. */
            CHECK(mc_set_watchdog_timeout(c, 0xFFFFFFFFu));
            CHECK(mc_reset_faults(c));
        } else {
            CHECK(relax_watchdog(c)); /* see check.h */
        }
        double t = 0.0;
        EXPECT(mc_sim_time(c, &t), MC_ERR_UNSUPPORTED); /* not a stepped card */
        mc_card_info info;
        CHECK(mc_get_info(c, &info));
        ASSERT(info.axes == 2 && info.servo_rate_hz == o.servo_rate_hz, "axes %u rate %u",
               info.axes, info.servo_rate_hz);
        if (k == 1) {
            mc_pdplus_settings pd;
            CHECK(mc_pdplus_settings_die_bonder(0, &pd));
            CHECK(mc_axis_configure_pdplus(c, 0, &pd));
        }
        mc_move_limits lim;
        CHECK(mc_move_limits_symmetric(50000.0, 1e6, 1e8, &lim));
        CHECK(mc_enable(c, 0));
        CHECK(mc_move_relative(c, 0, 2000.0, &lim, NULL));
        double at = 0.0;
        CHECK(mc_wait_done(c, 0, 10000, &at));
        ASSERT(fabs(at - 2000.0) <= 2.0, "clock %u: done at %f", o.clock, at);
        CHECK(mc_close(c));
    }
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    knot_vector();
    build_path();
    long_path();
    clocks_and_options();
    printf("%u checks\n", checks);
    printf("PASS nurbs_path\n");
    return 0;
}
