/*
 * A continuous path from C (layout 1.6): a group of two axes and its path configured and read
 * back, a square streamed with corner blends (within 100 counts of each corner) and a progress
 * callback, an output set 5000 counts into the first side and cleared at its end, a dwell, a
 * last segment whose motion is waited for; the end position checked exactly, the output seen
 * on and off, the segment events counted. Then the refusals: a NaN target, a line of length
 * zero, output 16, unknown modes, a segment while a group move runs and a group move while the
 * path runs, a stream stopped at its refused item with what came before it queued; and the
 * card's outputs set directly. Last, a NURBS curve as one segment between a stop and a blended
 * line, and the curves the card refuses (a cusp, a start away from the path's end). Then an
 * arc in a plane given by a normal vector (layout 1.12) on a second group, and its refusals.
 *
 * Runs on a stepped emulated card (deterministic: time advances only in waits and
 * mc_sim_step), so positions are checked exactly. Positions are in counts (scale 1), except
 * where the scales are set to check the path settings' conversion.
 *
 *     cc -std=c11 path.c $(pkg-config --cflags --libs motioncard) -lm -o path && ./path
 */
#include "expect.h"

#include <math.h>

#define RATE 10000u
#define OUT_BIT 3u /* the output the path sets and clears */

static const uint32_t G = 0;          /* the group */
static const uint32_t XY[2] = {0, 1}; /* its card axes */
static const mc_move_options NOW = {0};
static const mc_move_options QUEUED = {.buffered = 1};
static const mc_path_limits FEED = {50000.0, 5e5, 5e5, 5e7};

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

static mc_group_status group_of(mc_card c, uint32_t g) {
    mc_group_status s;
    CHECK(mc_group_get_status(c, g, &s));
    return s;
}

static mc_group_status group(mc_card c) {
    mc_group_status s;
    CHECK(mc_group_get_status(c, G, &s));
    return s;
}

static uint32_t outputs(mc_card c) {
    uint32_t o = 0xDEAD;
    CHECK(mc_get_outputs(c, &o));
    return o;
}

static uint32_t path_free(mc_card c) {
    uint32_t n = 0;
    CHECK(mc_group_path_free(c, G, &n));
    return n;
}

/* The group at rest on `x, y`: commanded positions exactly there, actual within 1 count, the
   group in GroupStandby with an empty path. */
static void expect_at(mc_card c, double x, double y, const char *what) {
    const double t[2] = {x, y};
    for (int i = 0; i < 2; i++) {
        mc_status s = axis(c, XY[i]);
        ASSERT(s.command_position == t[i], "%s: axis %d commanded %.9f, target %.9f", what, i,
               s.command_position, t[i]);
        ASSERT(fabs(s.actual_position - t[i]) <= 1.0, "%s: axis %d at %.3f, target %.3f", what,
               i, s.actual_position, t[i]);
    }
    mc_group_status g = group(c);
    ASSERT(g.state == MC_GROUP_STATE_STANDBY && g.path_queued == 0 &&
               g.path_free == MC_PATH_SEGMENTS && (g.path_flags & MC_PATH_STATUS_RUNNING) == 0,
           "%s: group state %u, path %u queued, %u free, flags %#x", what, g.state,
           g.path_queued, g.path_free, g.path_flags);
    checks += 3;
}

static mc_path_segment line(uint32_t id, double x, double y, double feed, double tolerance) {
    const double t[2] = {x, y};
    mc_path_segment s;
    CHECK(mc_path_segment_line(id, t, 2, feed, tolerance, &s));
    return s;
}

/* The same settings, field by field (the struct has padding: no memcmp). */
static int same_settings(const mc_path_settings *a, const mc_path_settings *b) {
    if (a->naxes != b->naxes || a->lookahead != b->lookahead || a->low_water != b->low_water ||
        a->accel != b->accel || a->jerk != b->jerk || a->plan_period != b->plan_period ||
        a->chord_fit != b->chord_fit)
        return 0;
    for (int i = 0; i < 8; i++) {
        if (a->vmax[i] != b->vmax[i] || a->amax[i] != b->amax[i] || a->jmax[i] != b->jmax[i])
            return 0;
    }
    return 1;
}

/* Settings: the uniform constructor, the card's checks, and the read-back in user units. */
static void settings(mc_card c) {
    mc_path_settings ps;
    EXPECT(mc_path_settings_uniform(0, 1.0, 1.0, 1.0, &ps), MC_ERR_BAD_AXIS);
    EXPECT(mc_path_settings_uniform(9, 1.0, 1.0, 1.0, &ps), MC_ERR_BAD_AXIS);
    EXPECT(mc_path_settings_uniform(2, 1.0, 1.0, 1.0, NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_path_settings_uniform(2, 50000.0, 5e5, 5e7, &ps));
    ASSERT(ps.naxes == 2 && ps.lookahead == 256 && ps.low_water == 0 && ps.accel == 0.0 &&
               ps.jerk == 0.0 && ps.vmax[1] == 50000.0 && ps.amax[1] == 5e5 &&
               ps.jmax[1] == 5e7 && ps.vmax[2] == 0.0 && ps.plan_period == 0.0 &&
               ps.chord_fit == 1,
           "uniform: %u axes, look-ahead %u", ps.naxes, ps.lookahead);

    /* In user units of 2 and 4 counts: the same limits in counts. */
    CHECK(mc_set_scale(c, 0, 2.0));
    CHECK(mc_set_scale(c, 1, 4.0));
    mc_path_settings user = ps;
    user.lookahead = 128;
    user.low_water = 16;
    user.plan_period = 2e-3; /* the planner every 2 ms (20 servo ticks at 10 kHz) */
    for (int i = 0; i < 2; i++) {
        const double scale = i == 0 ? 2.0 : 4.0;
        user.vmax[i] /= scale;
        user.amax[i] /= scale;
        user.jmax[i] /= scale;
    }
    CHECK(mc_group_configure_path(c, G, &user));
    mc_path_settings back;
    memset(&back, 0xFF, sizeof back);
    CHECK(mc_group_get_path_settings(c, G, &back));
    ASSERT(same_settings(&back, &user), "read back in user units: vmax %f %f",
           back.vmax[0], back.vmax[1]);
    CHECK(mc_set_scale(c, 0, 1.0));
    CHECK(mc_set_scale(c, 1, 1.0));
    CHECK(mc_group_get_path_settings(c, G, &back));
    ASSERT(back.vmax[0] == 50000.0 && back.vmax[1] == 50000.0 && back.amax[0] == 5e5 &&
               back.jmax[1] == 5e7 && back.lookahead == 128 && back.low_water == 16,
           "read back in counts: vmax %f %f, look-ahead %u", back.vmax[0], back.vmax[1],
           back.lookahead);

    /* Refused, and the card keeps what it had. */
    mc_path_settings bad = ps;
    bad.naxes = 3;
    bad.vmax[2] = bad.amax[2] = bad.jmax[2] = 1.0;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_BAD_AXIS);
    bad = ps;
    bad.vmax[1] = 0.0;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_NON_POSITIVE_LIMIT);
    bad = ps;
    bad.jmax[0] = NAN;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_NOT_FINITE);
    bad = ps;
    bad.lookahead = 0;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_BAD_CONFIG);
    bad.lookahead = MC_PATH_SEGMENTS + 1;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_BAD_CONFIG);
    bad = ps;
    bad.plan_period = NAN;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_NOT_FINITE);
    bad.plan_period = 0.02;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_OUT_OF_RANGE);
    bad.plan_period = -1e-3;
    EXPECT(mc_group_configure_path(c, G, &bad), MC_ERR_OUT_OF_RANGE);
    EXPECT(mc_group_configure_path(c, G, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_configure_path(c, 1, &ps), MC_ERR_GROUP_DISABLED);
    EXPECT(mc_group_get_path_settings(c, 1, &back), MC_ERR_GROUP_DISABLED);
    EXPECT(mc_group_get_path_settings(c, 99, &back), MC_ERR_BAD_GROUP);
    CHECK(mc_group_get_path_settings(c, G, &back));
    ASSERT(back.lookahead == 128 && back.vmax[0] == 50000.0, "kept: look-ahead %u",
           back.lookahead);

    /* The path runs with the settings of the square. */
    CHECK(mc_group_configure_path(c, G, &ps));
}

/* What the card refuses, or the library before it, with the path idle: nothing is queued. */
static void refusals(mc_card c) {
    mc_group_motion m = {77, 77};
    mc_path_segment s = line(1, NAN, 0.0, 40000.0, 100.0);
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_NOT_FINITE);
    s = line(1, 0.0, 0.0, 40000.0, 100.0); /* where the group is */
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_PATH_ZERO_LENGTH);
    s = line(1, 1000.0, 0.0, 0.0, 100.0);
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_NON_POSITIVE_LIMIT);
    s = line(1, 1000.0, 0.0, 40000.0, -1.0);
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_OUT_OF_RANGE);
    s = line(1, 1000.0, 0.0, 40000.0, 100.0);
    s.buffer = 6;
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_PATH_MODE);
    s.buffer = MC_PATH_BUFFER_BLEND_HIGH;
    s.transition = 4; /* 3 is MC_PATH_TRANSITION_TIME_SHIFT */
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_PATH_MODE);
    s.transition = MC_PATH_TRANSITION_CORNER_DISTANCE;
    s.naxes = 3;
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_BAD_AXIS);
    s.naxes = 2;
    s.kind = 9;
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_BAD_CONFIG);
    EXPECT(mc_group_path_push(c, G, NULL, &m), MC_ERR_NULL_POINTER);
    s = line(1, 1000.0, 0.0, 40000.0, 100.0);
    EXPECT(mc_group_path_push(c, 1, &s, &m), MC_ERR_GROUP_DISABLED);
    EXPECT(mc_path_segment_line(1, NULL, 2, 1.0, 0.0, &s), MC_ERR_NULL_POINTER);
    CHECK(mc_path_segment_dwell(1, 0.0, &s));
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_NON_POSITIVE_LIMIT);
    ASSERT(m.group == 77 && m.seq == 77, "motion written by a refused push");

    EXPECT(mc_group_path_output(c, G, MC_CARD_OUTPUTS, 1, MC_OUTPUT_AT_START, 0.0),
           MC_ERR_PATH_OUTPUT);
    EXPECT(mc_group_path_output(c, G, 0, 1, 3, 0.0), MC_ERR_PATH_MODE);
    EXPECT(mc_group_path_output(c, G, 0, 1, MC_OUTPUT_AT_DISTANCE, -1.0), MC_ERR_OUT_OF_RANGE);
    EXPECT(mc_group_path_output(c, G, 0, 1, MC_OUTPUT_AT_DISTANCE, NAN), MC_ERR_NOT_FINITE);

    /* A stream refused at its first item says so. (Refused by the card, it is the only item:
       items sent behind a refused one may be in flight, see mc_group_path_stream.) */
    size_t accepted = 99;
    mc_group_motion last = {77, 77};
    mc_path_segment two[2] = {line(1, 0.0, 0.0, 40000.0, 100.0), line(2, 10.0, 0.0, 1.0, 0.0)};
    EXPECT(mc_group_path_stream(c, G, two, 1, NULL, NULL, &accepted, &last),
           MC_ERR_PATH_ZERO_LENGTH);
    ASSERT(accepted == 0 && last.seq == 77, "accepted %zu", accepted);
    /* Refused by the library: checked before anything is sent. */
    two[0].target[0] = NAN;
    accepted = 99;
    EXPECT(mc_group_path_stream(c, G, two, 2, NULL, NULL, &accepted, NULL), MC_ERR_NOT_FINITE);
    ASSERT(accepted == 0, "accepted %zu", accepted);
    accepted = 99;
    EXPECT(mc_group_path_stream(c, G, NULL, 1, NULL, NULL, &accepted, NULL),
           MC_ERR_NULL_POINTER);
    ASSERT(accepted == 0, "accepted %zu", accepted);

    /* A segment while a group move runs: the path and the move queue do not mix. */
    const double to[2] = {1000.0, 0.0}, home[2] = {0.0, 0.0};
    mc_group_motion mv;
    CHECK(mc_group_move_linear(c, G, to, 2, &FEED, &NOW, &mv));
    s = line(1, 500.0, 500.0, 40000.0, 100.0);
    EXPECT(mc_group_path_push(c, G, &s, &m), MC_ERR_PATH_BUSY);
    CHECK(mc_group_motion_wait(c, mv, 30000));
    CHECK(mc_group_move_linear(c, G, home, 2, &FEED, &NOW, &mv));
    CHECK(mc_group_motion_wait(c, mv, 30000));
    expect_at(c, 0.0, 0.0, "after the refusals");
    ASSERT(path_free(c) == MC_PATH_SEGMENTS, "free %u", path_free(c));
    uint32_t n = 0;
    EXPECT(mc_group_path_free(c, G, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_path_free(c, 99, &n), MC_ERR_BAD_GROUP);
}

/* The card's outputs, set directly. */
static void direct_outputs(mc_card c) {
    ASSERT(outputs(c) == 0, "outputs %#x at start", outputs(c));
    CHECK(mc_set_outputs(c, 0x00F0, 0x0030));
    ASSERT(outputs(c) == 0x30, "outputs %#x", outputs(c));
    CHECK(mc_set_outputs(c, 0x0010, 0));
    ASSERT(outputs(c) == 0x20, "outputs %#x", outputs(c));
    EXPECT(mc_set_outputs(c, 1u << MC_CARD_OUTPUTS, 0), MC_ERR_PATH_OUTPUT);
    EXPECT(mc_set_outputs(c, 1, 1u << MC_CARD_OUTPUTS), MC_ERR_PATH_OUTPUT);
    ASSERT(outputs(c) == 0x20, "outputs %#x after a refusal", outputs(c));
    CHECK(mc_set_outputs(c, 0xFFFF, 0));
    ASSERT(outputs(c) == 0, "outputs %#x cleared", outputs(c));
    EXPECT(mc_get_outputs(c, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_set_outputs(4242, 1, 1), MC_ERR_BAD_HANDLE);
}

/* What the progress callback saw. */
struct progress {
    unsigned calls;
    uint64_t sent, accepted;
};

static void on_progress(const mc_path_progress *p, void *user) {
    struct progress *prog = user;
    ASSERT(p->sent == prog->sent + 1 && p->accepted >= prog->accepted && p->accepted <= p->sent,
           "progress: sent %llu, accepted %llu after %llu, %llu", (unsigned long long)p->sent,
           (unsigned long long)p->accepted, (unsigned long long)prog->sent,
           (unsigned long long)prog->accepted);
    prog->calls++;
    prog->sent = p->sent;
    prog->accepted = p->accepted;
}

/* The segment events. */
struct segments {
    unsigned starts, ends, starved;
    double last_start, last_end;
};

static void on_event(mc_card card, const mc_event *e, void *user) {
    (void)card;
    struct segments *seg = user;
    if (e->axis != G) return;
    if (e->kind == MC_EVENT_SEGMENT_START) {
        ASSERT(e->value == seg->last_start + 1, "segment %.0f started after %.0f", e->value,
               seg->last_start);
        seg->starts++;
        seg->last_start = e->value;
    } else if (e->kind == MC_EVENT_SEGMENT_END) {
        ASSERT(e->value == seg->last_end + 1, "segment %.0f ended after %.0f", e->value,
               seg->last_end);
        seg->ends++;
        seg->last_end = e->value;
    } else if (e->kind == MC_EVENT_PATH_STARVED) {
        seg->starved++;
    }
}

/* The square: four sides of 20000 counts blended within 100 counts of each corner, output 3
   set 5000 counts into the first side and cleared at its end, a dwell, then a last line. */
static void square(mc_card c) {
    const double side = 20000.0, feed = 40000.0, tol = 100.0;
    mc_path_segment items[8];
    CHECK(mc_path_segment_output(OUT_BIT, 1, MC_OUTPUT_AT_DISTANCE, 5000.0, &items[0]));
    CHECK(mc_path_segment_output(OUT_BIT, 0, MC_OUTPUT_AT_END, 0.0, &items[1]));
    items[2] = line(1, side, 0.0, feed, tol);
    items[3] = line(2, side, side, feed, tol);
    items[4] = line(3, 0.0, side, feed, tol);
    items[5] = line(4, 0.0, 0.0, feed, tol);
    CHECK(mc_path_segment_dwell(5, 0.1, &items[6]));
    items[7] = line(6, 5000.0, 5000.0, feed, tol);
    items[7].last = 1;

    struct segments seg = {0, 0, 0, 0.0, 0.0};
    CHECK(mc_set_event_callback(c, on_event, &seg));
    size_t n = 0;
    CHECK(mc_dispatch_events(c, 0, &n)); /* what came before */
    seg = (struct segments){0, 0, 0, 0.0, 0.0};

    const uint32_t done0 = group(c).path_done;
    struct progress prog = {0, 0, 0};
    size_t accepted = 0;
    mc_group_motion last = {0, 0};
    CHECK(mc_group_path_stream(c, G, items, 8, on_progress, &prog, &accepted, &last));
    ASSERT(accepted == 8 && prog.calls == 8 && prog.sent == 8, "accepted %zu, %u calls, sent %llu",
           accepted, prog.calls, (unsigned long long)prog.sent);
    ASSERT(last.group == G && last.seq != 0, "last {%u, %u}", last.group, last.seq);

    /* The path runs: no group move, no new settings meanwhile. */
    const double to[2] = {1.0, 1.0};
    EXPECT(mc_group_move_linear(c, G, to, 2, &FEED, &QUEUED, NULL), MC_ERR_PATH_BUSY);
    mc_path_settings ps;
    CHECK(mc_group_get_path_settings(c, G, &ps));
    EXPECT(mc_group_configure_path(c, G, &ps), MC_ERR_PATH_BUSY);

    /* Step through it: the output on only in the first side, from 5000 counts in to its end. */
    unsigned ticks_on = 0, switched = 0, ticks = 0;
    uint32_t id_at_on = 0, was = 0;
    for (;;) {
        CHECK(mc_sim_step(c, 1));
        CHECK(mc_dispatch_events(c, 0, &n));
        ticks++;
        ASSERT(ticks < 30u * RATE, "the path did not end in 30 s");
        const mc_group_status g = group(c);
        const uint32_t on = outputs(c) & (1u << OUT_BIT);
        if (on != was) {
            switched++;
            if (on) id_at_on = g.path_id;
            was = on;
        }
        if (on) ticks_on++;
        if (g.state == MC_GROUP_STATE_STANDBY && g.path_queued == 0) break;
    }
    CHECK(mc_group_motion_wait(c, last, 0)); /* done: the path is at rest at its end */
    expect_at(c, 5000.0, 5000.0, "square");
    /* On at 5000 counts into side 1, off as the path leaves it (within the corner's blend):
       at least 14000 counts at no more than the feed. */
    ASSERT(switched == 2 && id_at_on == 1 && outputs(c) == 0,
           "output switched %u times, on in segment %u, outputs %#x", switched, id_at_on,
           outputs(c));
    ASSERT(ticks_on >= (unsigned)(14000.0 / feed * RATE) &&
               ticks_on <= (unsigned)(15000.0 / feed * RATE * 2.0),
           "output on for %u ticks", ticks_on);
    ASSERT(group(c).path_done - done0 == 6, "%u segments done", group(c).path_done - done0);
    CHECK(mc_dispatch_events(c, 0, &n));
    ASSERT(seg.starts == 6 && seg.ends == 6 && seg.last_end == 6.0 && seg.starved == 0,
           "segments: %u started, %u ended (last %.0f), %u starved", seg.starts, seg.ends,
           seg.last_end, seg.starved);
    printf("path: square with blends ended at (5000, 5000) after %u ticks; output %u on for %u "
           "ticks\n",
           ticks, OUT_BIT, ticks_on);

    /* A stream stopped by the card at its second item: the first is queued and runs, to rest
       at its end (starved: it is not marked last). */
    mc_path_segment two[2] = {line(10, 6000.0, 5000.0, feed, tol),
                              line(11, 6000.0, 5000.0, feed, tol)};
    accepted = 99;
    last.seq = 77;
    seg.last_start = seg.last_end = 9.0;
    EXPECT(mc_group_path_stream(c, G, two, 2, NULL, NULL, &accepted, &last),
           MC_ERR_PATH_ZERO_LENGTH);
    ASSERT(accepted == 1 && last.seq == 77, "accepted %zu", accepted);
    CHECK(mc_group_wait_done(c, G, 30000));
    expect_at(c, 6000.0, 5000.0, "stream stopped at its refused item");
    CHECK(mc_dispatch_events(c, 0, &n));
    ASSERT(seg.starved == 1 && seg.last_end == 10.0, "starved %u, last ended %.0f",
           seg.starved, seg.last_end);
    CHECK(mc_set_event_callback(c, NULL, NULL));
}

/* A cubic Bezier (a NURBS of one span) from (6000, 5000) to (16000, 9000) as one segment, then
   a line blended to it; its middle point (11000, 7000) is passed within a tick's travel. */
static void curve(mc_card c) {
    const double ctrl[8] = {6000.0, 5000.0, 10000.0, 5000.0, 12000.0, 9000.0, 16000.0, 9000.0};
    const double w[4] = {1.0, 1.0, 1.0, 1.0};
    const double knots[8] = {0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0};
    const mc_nurbs_curve bezier = {3, 2, ctrl, 4, w, knots, 8};
    mc_path_segment items[2];
    CHECK(mc_path_segment_nurbs(20, &bezier, 40000.0, 0.0, 0.5, &items[0]));
    items[1] = line(21, 16000.0, 12000.0, 40000.0, 50.0);
    items[1].last = 1;
    mc_group_motion last = {0, 0};
    CHECK(mc_group_path_stream(c, G, items, 2, NULL, NULL, NULL, &last));
    const mc_group_status g0 = group(c);
    /* a curve takes one buffer entry per piece; a polynomial cubic is one quintic piece */
    ASSERT(g0.path_queued == 2 && g0.path_free == MC_PATH_SEGMENTS - 2,
           "curve: %u queued, %u free", g0.path_queued, g0.path_free);
    double nearest = 1e300;
    unsigned ticks = 0;
    for (;;) {
        CHECK(mc_sim_step(c, 1));
        ticks++;
        ASSERT(ticks < 30u * RATE, "the curve did not end in 30 s");
        const double x = axis(c, 0).command_position, y = axis(c, 1).command_position;
        nearest = fmin(nearest, hypot(x - 11000.0, y - 7000.0));
        const mc_group_status g = group(c);
        if (g.state == MC_GROUP_STATE_STANDBY && g.path_queued == 0) break;
    }
    CHECK(mc_group_motion_wait(c, last, 0));
    expect_at(c, 16000.0, 12000.0, "curve");
    ASSERT(nearest <= 40000.0 / RATE + 0.5, "the curve's middle missed by %.3f", nearest);
    printf("path: a NURBS segment and a line in %u ticks, the curve's middle passed within "
           "%.2f counts\n",
           ticks, nearest);

    /* A cusp (a stop inside the curve) and a curve away from where the path ends. */
    const double cusp[10] = {16000.0, 12000.0, 17000.0, 12000.0, 17000.0,
                             12000.0, 17000.0, 12000.0, 18000.0, 13000.0};
    const double w5[5] = {1.0, 1.0, 1.0, 1.0, 1.0};
    const double k5[9] = {0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0};
    const mc_nurbs_curve stop = {3, 2, cusp, 5, w5, k5, 9};
    mc_path_segment s;
    CHECK(mc_path_segment_nurbs(22, &stop, 40000.0, 0.0, 0.5, &s));
    EXPECT(mc_group_path_push(c, G, &s, NULL), MC_ERR_PATH_CURVE);
    CHECK(mc_path_segment_nurbs(23, &bezier, 40000.0, 0.0, 0.5, &s));
    EXPECT(mc_group_path_push(c, G, &s, NULL), MC_ERR_NURBS_START);
    ASSERT(group(c).path_queued == 0, "refused curves queued %u", group(c).path_queued);
}

/* Chords of a circle streamed as CAM posts them: the library sends them as the curve they
   sample (mc_path_settings.chord_fit, on from mc_path_settings_uniform), a few segments for 360
   lines, ending exactly on the last one's end, each line counted as accepted; with chord_fit 0
   every line is a segment of its own. */
static void chords(mc_card c) {
    const double pi = 3.14159265358979323846, r = 20000.0;
    mc_path_settings ps;
    for (int fit = 1; fit >= 0; fit--) {
        CHECK(mc_path_settings_uniform(2, 50000.0, 5e5, 5e7, &ps));
        ps.chord_fit = (uint32_t)fit;
        CHECK(mc_group_configure_path(c, G, &ps));
        const double x0 = axis(c, 0).command_position, y0 = axis(c, 1).command_position;
        mc_path_segment items[360];
        for (int i = 0; i < 360; i++) {
            const double a = (i + 1) * pi / 180.0;
            /* (rounded to whole counts, as a post rounds to its decimals) */
            items[i] = line(100u + (uint32_t)i, round(x0 - r + r * cos(a)),
                            round(y0 + r * sin(a)), 40000.0, 5.0);
        }
        items[359].last = 1;
        size_t accepted = 0;
        mc_group_motion last = {0, 0};
        CHECK(mc_group_path_stream(c, G, items, 360, NULL, NULL, &accepted, &last));
        const uint32_t queued = group(c).path_queued;
        ASSERT(accepted == 360, "accepted %u of 360 lines", (unsigned)accepted);
        if (fit)
            ASSERT(queued <= 8, "fitted: %u segments for 360 chords", queued);
        else
            ASSERT(queued == 360, "one by one: %u segments for 360 chords", queued);
        CHECK(mc_group_motion_wait(c, last, 60000));
        expect_at(c, round(x0), round(y0), "the chords' end");
        printf("path: 360 chords of a circle queued as %u segments (chord_fit %d)\n", queued, fit);
    }
}

/* Layout 1.12: an arc in a plane given by a normal vector, on group 1 of axes 2, 3, 4: a half
   turn about (1, 1, 1) from the origin around (10000, -10000, 0) ends exactly mirrored through
   the centre, every point on its circle; then the card's refusals, each with its own code. */
static void oblique(mc_card c) {
    const uint32_t g1 = 1, axes[3] = {2, 3, 4}, plane[3] = {0, 1, 2};
    mc_group_settings gs;
    CHECK(mc_group_settings_new(axes, 3, &gs));
    CHECK(mc_group_configure(c, g1, &gs));
    for (int i = 0; i < 3; i++)
        CHECK(mc_enable(c, axes[i]));
    CHECK(mc_group_enable(c, g1));
    mc_path_settings ps;
    CHECK(mc_path_settings_uniform(3, 50000.0, 5e5, 5e7, &ps));
    CHECK(mc_group_configure_path(c, g1, &ps));
    const double n[3] = {1.0, 1.0, 1.0}, centre[3] = {10000.0, -10000.0, 0.0};
    const double end[3] = {20000.0, -20000.0, 0.0};
    mc_path_segment s;
    CHECK(mc_path_segment_arc_normal(1, plane, n, centre, end, 40000.0, 5.0, &s));
    s.last = 1;
    mc_group_motion m = {0, 0};
    CHECK(mc_group_path_push(c, g1, &s, &m));
    double worst = 0.0;
    const double r = 10000.0 * sqrt(2.0);
    for (int k = 0; k < 200000 && group_of(c, g1).state != MC_GROUP_STATE_STANDBY; k++) {
        CHECK(mc_sim_step(c, 1));
        double d2 = 0.0, h = 0.0;
        for (int i = 0; i < 3; i++) {
            const double d = axis(c, axes[i]).command_position - centre[i];
            d2 += d * d;
            h += d / sqrt(3.0);
        }
        worst = fmax(worst, fmax(fabs(sqrt(d2) - r), fabs(h)));
    }
    for (int i = 0; i < 3; i++)
        ASSERT(axis(c, axes[i]).command_position == end[i], "axis %u at %.17g", axes[i],
               axis(c, axes[i]).command_position);
    ASSERT(worst < 1e-6, "%g off the circle or the plane", worst);
    /* the refusals: nothing queued */
    const uint32_t twice[3] = {0, 1, 1};
    const double zero[3] = {0.0, 0.0, 0.0}, z[3] = {0.0, 0.0, 1.0};
    const double c0[3] = {end[0] - 1000.0, end[1], end[2]}, e0[3] = {end[0] - 2000.0, end[1], end[2]};
    const double c_up[3] = {c0[0], c0[1], 50.0}, e_off[3] = {e0[0] - 50.0, e0[1], e0[2]};
    CHECK(mc_path_segment_arc_normal(2, plane, zero, c0, e0, 40000.0, 5.0, &s));
    EXPECT(mc_group_path_push(c, g1, &s, NULL), MC_ERR_ARC_NORMAL);
    CHECK(mc_path_segment_arc_normal(2, twice, z, c0, e0, 40000.0, 5.0, &s));
    EXPECT(mc_group_path_push(c, g1, &s, NULL), MC_ERR_ARC_AXES);
    CHECK(mc_path_segment_arc_normal(2, plane, z, c_up, e0, 40000.0, 5.0, &s));
    EXPECT(mc_group_path_push(c, g1, &s, NULL), MC_ERR_ARC_OFF_PLANE);
    CHECK(mc_path_segment_arc_normal(2, plane, z, c0, e_off, 40000.0, 5.0, &s));
    EXPECT(mc_group_path_push(c, g1, &s, NULL), MC_ERR_CENTRE_NOT_EQUIDISTANT);
    EXPECT(mc_path_segment_arc_normal(2, plane, NULL, c0, e0, 40000.0, 5.0, &s),
           MC_ERR_NULL_POINTER);
    ASSERT(group_of(c, g1).path_queued == 0, "queued %u", group_of(c, g1).path_queued);
    printf("path: a half turn about (1, 1, 1) on its circle to within %.1e counts\n", worst);
}

int main(void) {
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(5, RATE, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_enable(c, 1));
    mc_group_settings gs;
    CHECK(mc_group_settings_new(XY, 2, &gs));
    CHECK(mc_group_configure(c, G, &gs));
    CHECK(mc_group_enable(c, G));
    mc_group_status g = group(c);
    ASSERT(g.path_queued == 0 && g.path_free == MC_PATH_SEGMENTS && g.path_flags == 0,
           "idle path: %u queued, %u free, flags %#x", g.path_queued, g.path_free, g.path_flags);
    ASSERT(path_free(c) == 4096, "free %u", path_free(c));

    settings(c);
    refusals(c);
    direct_outputs(c);
    printf("path: settings, refusals and outputs checked without moving the path\n");
    fflush(stdout);

    square(c);
    ASSERT(path_free(c) == 4096, "free %u after the path", path_free(c));
    curve(c);
    chords(c);
    oblique(c);

    CHECK(mc_close(c));
    printf("PASS path (%u checks)\n", checks);
    return 0;
}
