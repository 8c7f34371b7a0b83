/*
 * Axes groups from C: a 2-axis group configured and enabled, a linear move, a full circle by
 * its centre with a buffered move queued behind it, a synchronised point-to-point move,
 * post-interpolation acc/dec filters (Shin's Table 1), a NURBS quarter circle, halt and stop,
 * PD+ settings; then the error paths: bad arcs and curves, NULL pointers, unknown groups,
 * handles and motions, disabled groups, unknown enumeration values. Every failed call must
 * leave its outputs untouched and a message for the thread.
 *
 * Runs on a stepped emulated card (deterministic: time advances only in waits and
 * mc_sim_step), so positions are checked exactly. Positions are in counts (scale 1).
 *
 *     cc -std=c11 groups.c $(pkg-config --cflags --libs motioncard) -lm -o groups && ./groups
 */
#include "expect.h"

#include <math.h>


static const double PI = 3.14159265358979323846;
static const uint32_t G = 0;                /* the group */
static const uint32_t XY[2] = {0, 1};       /* its card axes */
static const mc_move_options NOW = {0};    /* absolute, group at rest, cutting feed */
static const mc_move_options QUEUED = {.buffered = 1};
static const mc_path_limits FEED = {50000.0, 5e5, 5e5, 5e7}; /* counts/s, /s², /s², /s³ */

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

static mc_group_status group(mc_card c, uint32_t g) {
    mc_group_status s;
    CHECK(mc_group_get_status(c, g, &s));
    return s;
}

/* The group ended on `x, y`: commanded positions exactly there, actual within 1 count, both
   axes at standstill, the group in GroupStandby. */
static void expect_at(mc_card c, double x, double y, const char *what) {
    const double t[2] = {x, y};
    for (int i = 0; i < 2; i++) {
        mc_status s = axis(c, XY[i]);
        ASSERT(s.command_position == t[i], "%s: axis %d commanded %.9f, target %.9f", what, i,
               s.command_position, t[i]);
        ASSERT(fabs(s.actual_position - t[i]) <= 1.0, "%s: axis %d at %.3f, target %.3f", what,
               i, s.actual_position, t[i]);
        ASSERT(s.state == MC_AXIS_STATE_STANDSTILL, "%s: axis %d state %u", what, i, s.state);
    }
    mc_group_status g = group(c, G);
    ASSERT(g.state == MC_GROUP_STATE_STANDBY && g.queued == 0, "%s: group state %u, %u queued",
           what, g.state, g.queued);
    checks += 3;
}

static void configure(mc_card c, uint32_t accdec) {
    mc_group_settings s;
    CHECK(mc_group_settings_new(XY, 2, &s));
    ASSERT(s.naxes == 2 && s.axes[0] == 0 && s.axes[1] == 1 &&
               s.accdec == MC_GROUP_ACCDEC_PRE && s.interpolator == MC_GROUP_INTERP_EXACT &&
               s.tolerance > 0.0,
           "settings: %u axes, accdec %u, interpolator %u, tolerance %f", s.naxes, s.accdec,
           s.interpolator, s.tolerance);
    s.accdec = accdec;
    CHECK(mc_group_configure(c, G, &s));
    CHECK(mc_group_enable(c, G));
    ASSERT(group(c, G).state == MC_GROUP_STATE_STANDBY, "state %u after enable", group(c, G).state);
}

/* A line, then a full circle by its centre with a line back queued behind it. */
static void lines_and_circles(mc_card c) {
    const double x = 30000.0, y = -40000.0, r = 10000.0;
    mc_group_motion m = {99, 99};
    const double to[2] = {x, y};
    CHECK(mc_group_move_linear(c, G, to, 2, &FEED, &NOW, &m));
    ASSERT(m.group == G && m.seq != 0, "motion {%u, %u}", m.group, m.seq);
    CHECK(mc_group_motion_wait(c, m, 30000));
    expect_at(c, x, y, "line");

    /* The whole turn counter-clockwise around (x - r, y), back to where it starts. */
    const mc_arc circle = {.mode = MC_ARC_BY_CENTRE, .ccw = 1, .end = {x, y}, .aux = {x - r, y}};
    mc_group_motion turn, back;
    CHECK(mc_group_move_circular(c, G, &circle, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &turn));
    const double origin[2] = {0.0, 0.0};
    CHECK(mc_group_move_linear(c, G, origin, 2, &FEED, &QUEUED, &back));
    ASSERT(back.seq != turn.seq, "two moves, one seq");
    mc_group_status g = group(c, G);
    ASSERT(g.state == MC_GROUP_STATE_MOVING && g.queued >= 1, "state %u, %u queued", g.state,
           g.queued);
    EXPECT(mc_group_move_linear(c, G, origin, 2, &FEED, &NOW, NULL), MC_ERR_INVALID_STATE);

    /* Follow the circle tick by tick: every commanded point on the radius, a full turn. */
    double worst = 0.0, swept = 0.0, last = atan2(0.0, r);
    unsigned ticks = 0;
    while ((g = group(c, G)).state == MC_GROUP_STATE_MOVING) {
        CHECK(mc_sim_step(c, 1));
        g = group(c, G);
        if (g.active_seq != turn.seq) continue;
        mc_status sx = axis(c, 0), sy = axis(c, 1);
        double dx = sx.command_position - (x - r), dy = sy.command_position - y;
        worst = fmax(worst, fabs(hypot(dx, dy) - r));
        double a = atan2(dy, dx), d = a - last;
        if (d < -PI) d += 2 * PI;
        if (d > PI) d -= 2 * PI;
        ASSERT(d >= 0.0, "turned clockwise by %g rad at tick %u", d, ticks);
        swept += d;
        last = a;
        ticks++;
    }
    /* Feed 50,000 counts/s at 10 kHz: at most 5 counts (5e-4 rad) per tick. */
    ASSERT(worst < 1e-6, "radius error %g counts", worst);
    ASSERT(fabs(swept - 2 * PI) < 1e-3, "swept %.6f rad over %u ticks", swept, ticks);
    ASSERT(ticks > 2 * PI * r / FEED.velocity * 10000.0, "the circle took %u ticks", ticks);
    CHECK(mc_group_motion_wait(c, turn, 0)); /* done: the line took over */
    CHECK(mc_group_wait_done(c, G, 30000));  /* the group's last move */
    CHECK(mc_group_motion_wait(c, back, 0)); /* and again, by its handle */
    expect_at(c, 0.0, 0.0, "circle and line back");
    printf("circle: %u ticks, radius error %.2e counts, swept %.6f rad\n", ticks, worst, swept);

    /* Synchronised point-to-point: both axes start and end together. */
    const double ptp[2] = {-12000.0, 3000.0};
    CHECK(mc_group_move_ptp(c, G, ptp, 2, &FEED, &NOW, &m));
    CHECK(mc_group_motion_wait(c, m, 30000));
    expect_at(c, ptp[0], ptp[1], "ptp");

    /* Each axis within its own limits: y, allowed a tenth of x's velocity, sets the time. */
    const mc_path_limits own[2] = {
        FEED, {FEED.velocity / 10.0, FEED.acceleration, FEED.deceleration, FEED.jerk}};
    const double home[2] = {0.0, 0.0};
    EXPECT(mc_group_move_ptp_axes(c, G, home, 2, own, 1, &NOW, &m), MC_ERR_BAD_AXIS);
    EXPECT(mc_group_move_ptp_axes(c, G, home, 2, NULL, 2, &NOW, &m), MC_ERR_NULL_POINTER);
    double t0 = 0.0, t1 = 0.0;
    CHECK(mc_sim_time(c, &t0));
    CHECK(mc_group_move_ptp_axes(c, G, home, 2, own, 2, &NOW, &m));
    mc_group_status gs;
    do {
        CHECK(mc_sim_step(c, 1));
        CHECK(mc_group_get_status(c, G, &gs));
    } while (gs.state == MC_GROUP_STATE_MOVING);
    CHECK(mc_sim_time(c, &t1));
    CHECK(mc_group_motion_wait(c, m, 30000));
    expect_at(c, 0.0, 0.0, "ptp with per-axis limits");
    /* y travels 3,000 counts at 5,000 counts/s at most: 0.6 s, not x's 0.24 s. */
    ASSERT(t1 - t0 > 0.6, "took %g s", t1 - t0);
    /* The snap to the programmed end corrected nothing a filter or sum lost. */
    ASSERT(gs.snap_last <= 1e-12 && gs.snap_max <= 1e-12, "snap corrections %g, %g counts",
           gs.snap_last, gs.snap_max);
}

/* Post-interpolation acc/dec: constant feed along the path, each axis's filter after it. */
static void filters(mc_card c) {
    mc_filter_settings f, z;
    CHECK(mc_filter_settings_shin_table1(&f));
    CHECK(mc_filter_settings_shin_table1_z(&z));
    ASSERT(f.rapid.kind == MC_FILTER_KIND_BELL && f.rapid.tau == 0.035 &&
               f.cutting.kind == MC_FILTER_KIND_LINEAR && f.cutting.tau == 0.030 &&
               f.jog.kind == MC_FILTER_KIND_EXPONENTIAL && f.jog.tau == 0.050,
           "Shin Table 1: rapid %u %g, cutting %u %g, jog %u %g", f.rapid.kind, f.rapid.tau,
           f.cutting.kind, f.cutting.tau, f.jog.kind, f.jog.tau);
    ASSERT(z.rapid.tau == 0.085 && z.jog.tau == 0.040, "Shin Table 1 z: %g %g", z.rapid.tau,
           z.jog.tau);
    CHECK(mc_group_disable(c, G));
    for (int i = 0; i < 2; i++) CHECK(mc_axis_set_filters(c, XY[i], &f));
    configure(c, MC_GROUP_ACCDEC_POST);

    /* 30,000 counts along +x at the cutting feed: the linear filter (30 ms) ramps the velocity
       from 0 to the feed in 30 ms, so the acceleration is feed / tau at most. */
    mc_status start = axis(c, 0);
    const double to[2] = {start.command_position + 30000.0, axis(c, 1).command_position};
    mc_group_motion m;
    CHECK(mc_group_move_linear(c, G, to, 2, &FEED, &NOW, &m));
    double peak_acc = 0.0, peak_vel = 0.0;
    unsigned ticks = 0;
    for (; group(c, G).state == MC_GROUP_STATE_MOVING && ticks < 100000; ticks++) {
        CHECK(mc_sim_step(c, 1));
        mc_status s = axis(c, 0);
        peak_acc = fmax(peak_acc, fabs(s.command_acceleration));
        peak_vel = fmax(peak_vel, fabs(s.command_velocity));
        if (ticks == 100) {
            /* The filters hold distance while the move runs. */
            EXPECT(mc_axis_set_filters(c, 0, &f), MC_ERR_FILTER_BUSY);
        }
    }
    CHECK(mc_group_motion_wait(c, m, 30000));
    expect_at(c, to[0], to[1], "post acc/dec line");
    const double a_max = FEED.velocity / f.cutting.tau;
    ASSERT(fabs(peak_vel - FEED.velocity) <= 1e-6 * FEED.velocity, "peak velocity %f", peak_vel);
    ASSERT(peak_acc <= a_max * 1.001 && peak_acc >= a_max * 0.9,
           "peak acceleration %f, feed / tau = %f", peak_acc, a_max);
    /* At constant feed the move takes its length / feed, plus the filter's 30 ms. */
    ASSERT(fabs(ticks / 10000.0 - (30000.0 / FEED.velocity + f.cutting.tau)) < 0.005,
           "%u ticks", ticks);
    printf("post acc/dec: peak velocity %.1f, peak acceleration %.0f (feed / tau %.0f)\n",
           peak_vel, peak_acc, a_max);

    CHECK(mc_group_disable(c, G));
    configure(c, MC_GROUP_ACCDEC_PRE);
}

/* A quarter circle as a rational quadratic NURBS from where the group is. */
static void nurbs(mc_card c) {
    const double r = 8000.0;
    const double px = axis(c, 0).command_position, py = axis(c, 1).command_position;
    const double cx = px - r, cy = py; /* the centre: the curve starts at (cx + r, cy) */
    const double ctrl[6] = {cx + r, cy, cx + r, cy + r, cx, cy + r};
    const double w[3] = {1.0, sqrt(0.5), 1.0};
    const double knots[6] = {0, 0, 0, 1, 1, 1};
    const mc_nurbs_feed feed = {40000.0, 1e6, 1e8, 1.0, 0.0};
    mc_group_motion m = {99, 99};
    CHECK(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, knots, 6, &feed, &NOW, &m));
    ASSERT(m.group == G && m.seq != 0, "motion {%u, %u}", m.group, m.seq);
    double worst = 0.0;
    unsigned ticks = 0;
    for (; group(c, G).state == MC_GROUP_STATE_MOVING && ticks < 100000; ticks++) {
        CHECK(mc_sim_step(c, 1));
        mc_status sx = axis(c, 0), sy = axis(c, 1);
        worst = fmax(worst, fabs(hypot(sx.command_position - cx, sy.command_position - cy) - r));
    }
    CHECK(mc_group_motion_wait(c, m, 30000));
    ASSERT(worst < 1e-6, "NURBS radius error %g counts", worst);
    for (int i = 0; i < 2; i++) {
        mc_status s = axis(c, XY[i]);
        const double t = i == 0 ? cx : cy + r;
        ASSERT(fabs(s.command_position - t) < 1e-6, "NURBS end: axis %d commanded %.9f, not %.3f",
               i, s.command_position, t);
        ASSERT(fabs(s.actual_position - t) <= 1.0, "NURBS end: axis %d at %.3f", i,
               s.actual_position);
    }
    ASSERT(ticks > PI / 2 * r / feed.feed * 10000.0, "the quarter circle took %u ticks", ticks);
    printf("NURBS quarter circle: %u ticks, radius error %.2e counts, ended at (%.3f, %.3f)\n",
           ticks, worst, axis(c, 0).command_position, axis(c, 1).command_position);
}

/* Halt and stop abort what runs and what is queued. */
static void halt_and_stop(mc_card c) {
    const double far[2] = {400000.0, 300000.0}, near[2] = {0.0, 0.0};
    mc_group_motion m, q, h;
    CHECK(mc_group_move_linear(c, G, far, 2, &FEED, &NOW, &m));
    CHECK(mc_group_move_linear(c, G, near, 2, &FEED, &QUEUED, &q));
    EXPECT(mc_group_motion_wait(c, m, 5), MC_ERR_TIMEOUT);
    CHECK(mc_group_halt(c, G, 5e5, 5e7, &h));
    EXPECT(mc_group_motion_wait(c, m, 0), MC_ERR_ABORTED);
    EXPECT(mc_group_motion_wait(c, q, 0), MC_ERR_ABORTED);
    CHECK(mc_group_motion_wait(c, h, 30000));
    mc_group_status g = group(c, G);
    ASSERT(g.state == MC_GROUP_STATE_STANDBY && g.queued == 0, "after halt: %u, %u queued",
           g.state, g.queued);
    double x = axis(c, 0).command_position;
    ASSERT(x < far[0] && x > 0.0, "halted at x = %f", x);

    CHECK(mc_group_move_linear(c, G, near, 2, &FEED, &NOW, &m));
    CHECK(mc_sim_step(c, 1000));
    CHECK(mc_group_stop(c, G, 5e5, 5e7, &h));
    CHECK(mc_group_motion_wait(c, h, 30000));
    EXPECT(mc_group_motion_wait(c, m, 0), MC_ERR_ABORTED);
    ASSERT(group(c, G).state == MC_GROUP_STATE_STOPPING, "state %u", group(c, G).state);
    EXPECT(mc_group_move_linear(c, G, near, 2, &FEED, &NOW, NULL), MC_ERR_INVALID_STATE);
    CHECK(mc_group_release_stop(c, G));
    CHECK(mc_sim_step(c, 1));
    ASSERT(group(c, G).state == MC_GROUP_STATE_STANDBY, "state %u", group(c, G).state);
    EXPECT(mc_group_reset(c, G), MC_ERR_INVALID_STATE); /* only from GroupErrorStop */
    /* Home, for the error paths below. */
    CHECK(mc_group_move_linear(c, G, near, 2, &FEED, &NOW, &m));
    CHECK(mc_group_motion_wait(c, m, 30000));
    expect_at(c, 0.0, 0.0, "home");
}

static void pdplus(mc_card c) {
    mc_pdplus_settings x = {0}, y = {0}, untouched = {.gains = {.kp = 42.0}};
    CHECK(mc_pdplus_settings_die_bonder(0, &x));
    CHECK(mc_pdplus_settings_die_bonder(1, &y));
    ASSERT(x.gains.kp > 0 && x.gains.kd > 0 && x.drive.tau == 0.31 && y.drive.tau == 0.135 &&
               x.umax == 10.0,
           "die bonder: kp %g kd %g tau %g / %g umax %g", x.gains.kp, x.gains.kd, x.drive.tau,
           y.drive.tau, x.umax);
    EXPECT(mc_pdplus_settings_die_bonder(2, &untouched), MC_ERR_BAD_AXIS);
    EXPECT(mc_pdplus_settings_die_bonder(0, NULL), MC_ERR_NULL_POINTER);
    ASSERT(untouched.gains.kp == 42.0, "settings written by a failed call");
    /* Axis 5 is not in the group. */
    CHECK(mc_axis_configure_pdplus(c, 5, &x));
    mc_pdplus_settings bad = x;
    bad.gains.kd = NAN;
    EXPECT(mc_axis_configure_pdplus(c, 5, &bad), MC_ERR_NOT_FINITE);
    bad = x;
    bad.umax = 1000.0; /* above the DAC's limit */
    EXPECT(mc_axis_configure_pdplus(c, 5, &bad), MC_ERR_BAD_CONFIG);
    bad = x;
    bad.drive.tau = -1.0;
    EXPECT(mc_axis_configure_pdplus(c, 5, &bad), MC_ERR_BAD_CONFIG);
    EXPECT(mc_axis_configure_pdplus(c, 5, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_axis_configure_pdplus(c, 8, &x), MC_ERR_BAD_AXIS);
}

/* Curves and arcs the library or the card refuses; the group is at rest at (0, 0). */
static void bad_geometry(mc_card c) {
    mc_group_motion m = {77, 77};
    const mc_nurbs_feed feed = {40000.0, 1e6, 1e8, 1.0, 0.0};
    const double ctrl[6] = {0, 0, 5000, 5000, 10000, 0};
    const double w[3] = {1, 1, 1};
    const double k[6] = {0, 0, 0, 1, 1, 1};

    /* Arcs from (0, 0). */
    mc_arc arc = {.mode = MC_ARC_BY_RADIUS, .ccw = 1, .end = {30000, 0}, .aux = {1000, 0}};
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_RADIUS_TOO_SMALL);
    expect_in_message("radius");
    arc = (mc_arc){.mode = MC_ARC_BY_CENTRE, .end = {30000, 0}, .aux = {10000, 0}};
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_CENTRE_NOT_EQUIDISTANT);
    arc = (mc_arc){.mode = MC_ARC_BY_BORDER, .end = {30000, 0}, .aux = {10000, 0}};
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_COLLINEAR_POINTS);
    arc = (mc_arc){.mode = MC_ARC_BY_CENTRE, .end = {0, 0}, .aux = {0, 0}};
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_ZERO_LENGTH_ARC);
    arc.mode = 9;
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_BAD_CONFIG);
    expect_in_message("unknown arc mode 9");
    arc.mode = MC_ARC_BY_CENTRE;
    EXPECT(mc_group_move_circular(c, G, &arc, 7, NULL, 0, &FEED, &NOW, &m), MC_ERR_BAD_CONFIG);
    /* A 2-axis group has no third axis to climb. */
    const double z = 100.0;
    arc = (mc_arc){.mode = MC_ARC_BY_CENTRE, .ccw = 1, .end = {0, 0}, .aux = {-5000, 0}};
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, &z, 1, &FEED, &NOW, &m),
           MC_ERR_BAD_AXIS);

    /* Curves: each fault its own code, the same whether the library or the card finds it. */
    EXPECT(mc_group_move_nurbs(c, G, 0, ctrl, 3, 2, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_DEGREE);
    EXPECT(mc_group_move_nurbs(c, G, 6, ctrl, 3, 2, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_DEGREE);
    const double ctrl3d[9] = {0, 0, 0, 5000, 5000, 0, 10000, 0, 0};
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl3d, 3, 3, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_DIMENSION); /* a 3-d curve on a 2-axis group */
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 1, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_DIMENSION);
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 2, 2, w, k, 5, &feed, &NOW, &m),
           MC_ERR_NURBS_CTRL_COUNT); /* 2 points for degree 2 */
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 5, &feed, &NOW, &m),
           MC_ERR_NURBS_KNOT_COUNT);
    expect_in_message("5 knots, expected");
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 7000000, &feed, &NOW, &m),
           MC_ERR_NURBS_KNOT_COUNT); /* refused before anything is read */
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 5000000, 2, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_CTRL_COUNT);
    const double decreasing[6] = {0, 0, 0, 1, 0.5, 1};
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, decreasing, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_KNOTS_DECREASING);
    expect_in_message("knot 4 is below knot 3");
    const double unclamped[6] = {0, 0, 0.5, 1, 1, 1};
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, unclamped, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_NOT_CLAMPED);
    const double ctrl4[8] = {0, 0, 3000, 3000, 6000, 0, 9000, 3000};
    const double w4[4] = {1, 1, 1, 1};
    const double multiple[6] = {0, 0, 0.5, 0.5, 1, 1}; /* 0.5 twice in a degree-1 curve */
    EXPECT(mc_group_move_nurbs(c, G, 1, ctrl4, 4, 2, w4, multiple, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_KNOT_MULTIPLICITY);
    const double zero_w[3] = {1, 0, 1};
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, zero_w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_WEIGHT);
    const double nan_pt[6] = {0, 0, NAN, 5000, 10000, 0};
    EXPECT(mc_group_move_nurbs(c, G, 2, nan_pt, 3, 2, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_POINT);
    const double nan_knot[6] = {0, 0, 0, NAN, 1, 1};
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, nan_knot, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_KNOT);
    const double inf_knot[6] = {0, 0, 0, 1, 1, INFINITY};
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, inf_knot, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_KNOT);
    const double elsewhere[6] = {100, 0, 5000, 5000, 10000, 0};
    EXPECT(mc_group_move_nurbs(c, G, 2, elsewhere, 3, 2, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_START); /* the card: the group is at (0, 0) */
    const double still[6] = {0, 0, 0, 0, 0, 0};
    EXPECT(mc_group_move_nurbs(c, G, 2, still, 3, 2, w, k, 6, &feed, &NOW, &m),
           MC_ERR_NURBS_ZERO_LENGTH);
    mc_nurbs_feed aware = feed;
    aware.saturation_budget = 0.8; /* needs PD+ on both axes */
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 6, &aware, &NOW, &m),
           MC_ERR_INCOMPATIBLE_MODE);
    aware.saturation_budget = 1.5;
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 6, &aware, &NOW, &m),
           MC_ERR_BAD_CONFIG);
    mc_nurbs_feed slow = feed;
    slow.feed = -1.0;
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 6, &slow, &NOW, &m),
           MC_ERR_NON_POSITIVE_LIMIT);

    /* Lines: targets, limits, options. */
    const double nan_target[2] = {NAN, 0}, three[3] = {1, 2, 3};
    EXPECT(mc_group_move_linear(c, G, nan_target, 2, &FEED, &NOW, &m), MC_ERR_NOT_FINITE);
    EXPECT(mc_group_move_linear(c, G, three, 3, &FEED, &NOW, &m), MC_ERR_BAD_AXIS);
    EXPECT(mc_group_move_ptp(c, G, three, 1, &FEED, &NOW, &m), MC_ERR_BAD_AXIS);
    EXPECT(mc_group_move_linear(c, G, three, 9, &FEED, &NOW, &m), MC_ERR_BAD_AXIS);
    expect_in_message("at most 8 axes");
    mc_path_limits lim = FEED;
    lim.jerk = 0.0;
    EXPECT(mc_group_move_linear(c, G, three, 2, &lim, &NOW, &m), MC_ERR_NON_POSITIVE_LIMIT);
    lim = FEED;
    lim.velocity = INFINITY;
    EXPECT(mc_group_move_ptp(c, G, three, 2, &lim, &NOW, &m), MC_ERR_NOT_FINITE);
    mc_move_options opt = {.feed_type = 3};
    EXPECT(mc_group_move_linear(c, G, three, 2, &FEED, &opt, &m), MC_ERR_BAD_CONFIG);
    expect_in_message("unknown feed type 3");
    EXPECT(mc_group_halt(c, G, NAN, 1e7, &m), MC_ERR_NOT_FINITE);
    EXPECT(mc_group_stop(c, G, 1e6, -1.0, &m), MC_ERR_NON_POSITIVE_LIMIT);
    ASSERT(m.group == 77 && m.seq == 77, "motion written by a refused call");

    /* Nothing moved. */
    expect_at(c, 0.0, 0.0, "after refused moves");
}

static void null_pointers(mc_card c) {
    mc_group_settings s;
    CHECK(mc_group_settings_new(XY, 2, &s));
    const double t[2] = {0, 0};
    const mc_arc arc = {.mode = MC_ARC_BY_CENTRE, .ccw = 1, .end = {0, 0}, .aux = {-5000, 0}};
    const double ctrl[6] = {0, 0, 5000, 5000, 10000, 0};
    const double w[3] = {1, 1, 1}, k[6] = {0, 0, 0, 1, 1, 1};
    const mc_nurbs_feed feed = {40000.0, 1e6, 1e8, 1.0, 0.0};

    EXPECT(mc_group_settings_new(NULL, 2, &s), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_settings_new(XY, 2, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_configure(c, G, NULL), MC_ERR_NULL_POINTER);
    expect_in_message("settings is NULL");
    EXPECT(mc_group_move_linear(c, G, NULL, 2, &FEED, &NOW, NULL), MC_ERR_NULL_POINTER);
    expect_in_message("target is NULL");
    EXPECT(mc_group_move_linear(c, G, t, 2, NULL, &NOW, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_linear(c, G, t, 2, &FEED, NULL, NULL), MC_ERR_NULL_POINTER);
    expect_in_message("options is NULL");
    EXPECT(mc_group_move_ptp(c, G, NULL, 2, &FEED, &NOW, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_ptp(c, G, t, 2, NULL, &NOW, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_ptp(c, G, t, 2, &FEED, NULL, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_circular(c, G, NULL, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, NULL),
           MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 1, &FEED, &NOW, NULL),
           MC_ERR_NULL_POINTER);
    expect_in_message("helix is NULL");
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, NULL, &NOW, NULL),
           MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, NULL, NULL),
           MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_nurbs(c, G, 2, NULL, 3, 2, w, k, 6, &feed, &NOW, NULL),
           MC_ERR_NULL_POINTER);
    expect_in_message("ctrl is NULL");
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, NULL, k, 6, &feed, &NOW, NULL),
           MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, NULL, 6, &feed, &NOW, NULL),
           MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 6, NULL, &NOW, NULL),
           MC_ERR_NULL_POINTER);
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 6, &feed, NULL, NULL),
           MC_ERR_NULL_POINTER);
    EXPECT(mc_group_get_status(c, G, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_axis_set_filters(c, 0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_filter_settings_shin_table1(NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_filter_settings_shin_table1_z(NULL), MC_ERR_NULL_POINTER);
    /* A move's motion may be NULL: the move still runs and can be waited for by group. */
    const double to[2] = {1000.0, 0.0};
    CHECK(mc_group_move_linear(c, G, to, 2, &FEED, &NOW, NULL));
    CHECK(mc_group_wait_done(c, G, 30000));
    expect_at(c, 1000.0, 0.0, "move without a motion handle");
    CHECK(mc_group_move_linear(c, G, t, 2, &FEED, &NOW, NULL));
    CHECK(mc_group_wait_done(c, G, 30000));
}

/* Every group call with an unknown group; every one with an unknown card. */
static void unknown_groups_and_cards(mc_card c) {
    mc_group_settings s;
    CHECK(mc_group_settings_new(XY, 2, &s));
    const double t[2] = {0, 0};
    const mc_arc arc = {.mode = MC_ARC_BY_CENTRE, .ccw = 1, .end = {0, 0}, .aux = {-5000, 0}};
    const double ctrl[6] = {0, 0, 5000, 5000, 10000, 0};
    const double w[3] = {1, 1, 1}, k[6] = {0, 0, 0, 1, 1, 1};
    const mc_nurbs_feed feed = {40000.0, 1e6, 1e8, 1.0, 0.0};
    mc_filter_settings f;
    mc_pdplus_settings pd;
    CHECK(mc_filter_settings_shin_table1(&f));
    CHECK(mc_pdplus_settings_die_bonder(0, &pd));
    mc_group_motion m = {77, 77};
    mc_group_status st = {.state = 99};

    const uint32_t bad_groups[] = {MC_GROUP_COUNT, 0xFFFFFFFFu};
    for (size_t i = 0; i < 2; i++) {
        const uint32_t g = bad_groups[i];
        EXPECT(mc_group_configure(c, g, &s), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_enable(c, g), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_disable(c, g), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_reset(c, g), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_halt(c, g, 1e6, 1e7, &m), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_stop(c, g, 1e6, 1e7, &m), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_release_stop(c, g), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_move_linear(c, g, t, 2, &FEED, &NOW, &m), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_move_ptp(c, g, t, 2, &FEED, &NOW, &m), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_move_circular(c, g, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
               MC_ERR_BAD_GROUP);
        EXPECT(mc_group_move_nurbs(c, g, 2, ctrl, 3, 2, w, k, 6, &feed, &NOW, &m),
               MC_ERR_BAD_GROUP);
        EXPECT(mc_group_wait_done(c, g, 0), MC_ERR_BAD_GROUP);
        EXPECT(mc_group_get_status(c, g, &st), MC_ERR_BAD_GROUP);
    }
    /* The message names the group and the card's groups. */
    expect_in_message("group 4294967295 does not exist: the card has 4 groups (0 to 3)");

    /* Motions this card never started, or started on another group. */
    mc_group_motion unknown = {G, 999999};
    EXPECT(mc_group_motion_wait(c, unknown, 0), MC_ERR_BAD_HANDLE);
    expect_in_message("no group motion with seq 999999 on group 0");
    CHECK(mc_group_move_linear(c, G, t, 2, &FEED, &NOW, &m)); /* already there: done at once */
    CHECK(mc_group_motion_wait(c, m, 30000));
    mc_group_motion other = {1, m.seq};
    EXPECT(mc_group_motion_wait(c, other, 0), MC_ERR_BAD_HANDLE);
    other = (mc_group_motion){MC_GROUP_COUNT, m.seq};
    EXPECT(mc_group_motion_wait(c, other, 0), MC_ERR_BAD_HANDLE);

    /* Unknown and closed cards. */
    mc_card closed = 0;
    CHECK(mc_open_sim_stepped(2, 1000, &closed));
    CHECK(mc_close(closed));
    const mc_card bad_cards[] = {0, 12345, closed};
    for (size_t i = 0; i < 3; i++) {
        const mc_card h = bad_cards[i];
        EXPECT(mc_group_configure(h, G, &s), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_enable(h, G), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_disable(h, G), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_reset(h, G), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_halt(h, G, 1e6, 1e7, &m), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_stop(h, G, 1e6, 1e7, &m), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_release_stop(h, G), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_move_linear(h, G, t, 2, &FEED, &NOW, &m), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_move_ptp(h, G, t, 2, &FEED, &NOW, &m), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_move_circular(h, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
               MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_move_nurbs(h, G, 2, ctrl, 3, 2, w, k, 6, &feed, &NOW, &m),
               MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_motion_wait(h, m, 0), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_wait_done(h, G, 0), MC_ERR_BAD_HANDLE);
        EXPECT(mc_group_get_status(h, G, &st), MC_ERR_BAD_HANDLE);
        EXPECT(mc_axis_set_filters(h, 0, &f), MC_ERR_BAD_HANDLE);
        EXPECT(mc_axis_configure_pdplus(h, 0, &pd), MC_ERR_BAD_HANDLE);
    }
    ASSERT(st.state == 99 && m.group == G, "output written by a failed call");
}

/* Disabled and unconfigured groups, states, axes that belong to a group. */
static void disabled_groups(mc_card c) {
    const double t[2] = {5000, 5000};
    const mc_arc arc = {.mode = MC_ARC_BY_CENTRE, .ccw = 1, .end = {0, 0}, .aux = {-5000, 0}};
    const double ctrl[6] = {0, 0, 5000, 5000, 10000, 0};
    const double w[3] = {1, 1, 1}, k[6] = {0, 0, 0, 1, 1, 1};
    const mc_nurbs_feed feed = {40000.0, 1e6, 1e8, 1.0, 0.0};
    mc_group_motion m = {77, 77};
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));

    /* Axes of an enabled group move only with it; they cannot join a second group. */
    EXPECT(mc_move_absolute(c, 0, 100.0, &lim, NULL), MC_ERR_AXIS_GROUPED);
    mc_group_settings s;
    CHECK(mc_group_settings_new(XY, 2, &s));
    EXPECT(mc_group_configure(c, 1, &s), MC_ERR_AXIS_IN_OTHER_GROUP);
    const uint32_t nine = 9;
    mc_group_settings wrong = s;
    wrong.axes[1] = nine;
    EXPECT(mc_group_configure(c, 2, &wrong), MC_ERR_BAD_AXIS);
    wrong = s;
    wrong.naxes = 0;
    EXPECT(mc_group_configure(c, 2, &wrong), MC_ERR_BAD_AXIS);
    wrong = s;
    wrong.accdec = 0;
    EXPECT(mc_group_configure(c, 2, &wrong), MC_ERR_BAD_CONFIG);
    wrong = s;
    wrong.interpolator = MC_GROUP_INTERP_REFERENCE_WORD; /* needs post acc/dec */
    EXPECT(mc_group_configure(c, 2, &wrong), MC_ERR_INCOMPATIBLE_MODE);
    EXPECT(mc_group_settings_new(XY, 9, &s), MC_ERR_BAD_AXIS);
    EXPECT(mc_group_settings_new(XY, 0, &s), MC_ERR_BAD_AXIS);
    EXPECT(mc_group_configure(c, G, &s), MC_ERR_INVALID_STATE); /* enabled */

    /* A never-configured group and a disabled one refuse moves. */
    EXPECT(mc_group_move_linear(c, 3, t, 2, &FEED, &NOW, &m), MC_ERR_GROUP_DISABLED);
    EXPECT(mc_group_wait_done(c, 3, 0), MC_ERR_NO_MOTION); /* nothing queued there */
    CHECK(mc_group_disable(c, G));
    ASSERT(group(c, G).state == MC_GROUP_STATE_DISABLED, "state %u", group(c, G).state);
    EXPECT(mc_group_move_linear(c, G, t, 2, &FEED, &NOW, &m), MC_ERR_GROUP_DISABLED);
    expect_in_message("disabled");
    EXPECT(mc_group_move_ptp(c, G, t, 2, &FEED, &NOW, &m), MC_ERR_GROUP_DISABLED);
    EXPECT(mc_group_move_circular(c, G, &arc, MC_ARC_PLANE_XY, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_GROUP_DISABLED);
    EXPECT(mc_group_move_nurbs(c, G, 2, ctrl, 3, 2, w, k, 6, &feed, &NOW, &m),
           MC_ERR_GROUP_DISABLED);
    ASSERT(m.group == 77 && m.seq == 77, "motion written by a refused move");
    /* Disabled, its axes are free again. */
    CHECK(mc_move_absolute(c, 0, 100.0, &lim, NULL));
    double at = 0.0;
    CHECK(mc_wait_done(c, 0, 30000, &at));
    ASSERT(fabs(at - 100.0) <= 1.0, "axis 0 at %f", at);
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(8, 10000, &c));
    for (int i = 0; i < 2; i++) CHECK(mc_enable(c, XY[i]));
    ASSERT(group(c, G).state == MC_GROUP_STATE_DISABLED, "state %u", group(c, G).state);
    EXPECT(mc_group_wait_done(c, G, 0), MC_ERR_NO_MOTION); /* nothing queued yet */
    configure(c, MC_GROUP_ACCDEC_PRE);

    lines_and_circles(c);
    filters(c);
    nurbs(c);
    halt_and_stop(c);
    pdplus(c);
    bad_geometry(c);
    null_pointers(c);
    unknown_groups_and_cards(c);
    disabled_groups(c);

    CHECK(mc_close(c));
    printf("%u checks\n", checks);
    printf("PASS groups\n");
    return 0;
}
