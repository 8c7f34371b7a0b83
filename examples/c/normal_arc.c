/*
 * MC_MoveCircular in a plane given by a normal vector, in the group's move queue, from C
 * (layout 1.13): a four-axis group runs a tilted circle (normal (1, -2, 2), radius 5000, a
 * quarter turn and one full turn more) while its fourth axis climbs 3000 counts, then a helix
 * rising 800 counts along the normal; every tick's commanded point is checked against the
 * circle and the plane; then the refusals (a zero normal, an axis twice, a centre off the
 * plane, an end off the circle, an end off the plane without a rise, a NULL arc, a lone
 * piece of the move sent raw).
 *
 * Runs on a stepped emulated card (deterministic: time advances only in waits and
 * mc_sim_step). Positions in counts (scale 1). The argument is ignored.
 *
 *     cc -std=c11 normal_arc.c $(pkg-config --cflags --libs motioncard) -lm -o normal_arc && ./normal_arc
 */
#include "expect.h"

#include <math.h>

static const uint32_t G = 0;
static const uint32_t AXES[4] = {0, 1, 2, 3};
static const mc_move_options NOW = {0};
static const mc_path_limits FEED = {20000.0, 4e5, 4e5, 4e7};
static const double R = 5000.0;

static double dot(const double *a, const double *b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void unit(double *v) {
    double m = sqrt(dot(v, v));
    for (int k = 0; k < 3; k++) v[k] /= m;
}

/* Commanded positions of the four axes. */
static void commanded(mc_card c, double *p) {
    mc_status s[4];
    CHECK(mc_get_statuses(c, AXES, 4, s));
    for (int k = 0; k < 4; k++) p[k] = s[k].command_position;
}

/* Step the card until the group stands by, checking every tick's point: its distance from
 * the circle's axis (through `centre` along `nh`) is R, its height along `nh` above the
 * centre is `rise` times the fourth axis's share of `w1` (0 for a circle), both within 1e-6
 * of R. Returns the worst relative error. */
static double run_on_circle(mc_card c, const double *centre, const double *nh, double rise,
                            double w0, double w1) {
    double worst = 0.0;
    mc_group_status g;
    int ticks = 0;
    do {
        CHECK(mc_sim_step(c, 1));
        double p[4], d[3];
        commanded(c, p);
        for (int k = 0; k < 3; k++) d[k] = p[k] - centre[k];
        double h = dot(d, nh);
        double radial[3] = {d[0] - h * nh[0], d[1] - h * nh[1], d[2] - h * nh[2]};
        double share = (p[3] - w0) / (w1 - w0);
        double er = fabs(sqrt(dot(radial, radial)) - R) / R;
        double eh = fabs(h - share * rise) / R;
        if (er > worst) worst = er;
        if (eh > worst) worst = eh;
        CHECK(mc_group_get_status(c, G, &g));
        ASSERT(++ticks < 400000, "the move did not end");
    } while (g.state != MC_GROUP_STATE_STANDBY);
    return worst;
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(4, 10000, &c));
    for (uint32_t a = 0; a < 4; a++) CHECK(mc_enable(c, a));
    mc_group_settings s;
    CHECK(mc_group_settings_new(AXES, 4, &s));
    CHECK(mc_group_configure(c, G, &s));
    CHECK(mc_group_enable(c, G));

    /* The tilted circle: from the origin around centre = -R u, a quarter turn to centre + R w
     * (w = n x u), and one more turn; the fourth axis to 3000. */
    double nh[3] = {1.0, -2.0, 2.0}, u[3] = {2.0, 1.0, 0.0};
    unit(nh);
    unit(u);
    double w[3] = {nh[1] * u[2] - nh[2] * u[1], nh[2] * u[0] - nh[0] * u[2],
                   nh[0] * u[1] - nh[1] * u[0]};
    mc_normal_arc arc = {{0, 1, 2}, {1.0, -2.0, 2.0}, {0}, {0}, 0, 1};
    for (int k = 0; k < 3; k++) {
        arc.centre[k] = -R * u[k];
        arc.end[k] = arc.centre[k] + R * w[k];
    }
    const double climb = 3000.0;
    mc_group_motion m;
    CHECK(mc_group_move_circular_normal(c, G, &arc, &climb, 1, &FEED, &NOW, &m));
    double worst = run_on_circle(c, arc.centre, nh, 0.0, 0.0, climb);
    CHECK(mc_group_motion_wait(c, m, 1000));
    double p[4];
    commanded(c, p);
    for (int k = 0; k < 3; k++)
        ASSERT(fabs(p[k] - arc.end[k]) < 1e-9, "axis %d ended at %.12f, not %.12f", k, p[k],
               arc.end[k]);
    ASSERT(p[3] == climb, "the fourth axis ended at %.12f", p[3]);
    ASSERT(worst <= 1e-6, "the circle's worst relative error %g", worst);
    printf("normal_arc: tilted circle, 1.25 turns, worst relative error %.1e\n", worst);

    /* A helix rising 800 along the normal: half a turn on around the same axis, the fourth
     * axis back to 0. */
    mc_normal_arc helix = arc;
    helix.rise = 1;
    helix.turns = 0;
    double start[3] = {p[0], p[1], p[2]};
    for (int k = 0; k < 3; k++) {
        helix.centre[k] = arc.centre[k];
        helix.end[k] = 2.0 * arc.centre[k] - start[k] + 800.0 * nh[k];
    }
    const double back = 0.0;
    CHECK(mc_group_move_circular_normal(c, G, &helix, &back, 1, &FEED, &NOW, &m));
    worst = run_on_circle(c, helix.centre, nh, 800.0, climb, back);
    CHECK(mc_group_motion_wait(c, m, 1000));
    commanded(c, p);
    for (int k = 0; k < 3; k++)
        ASSERT(fabs(p[k] - helix.end[k]) < 1e-9, "helix: axis %d ended at %.12f", k, p[k]);
    ASSERT(worst <= 1e-6, "the helix's worst relative error %g", worst);
    printf("normal_arc: helix rising 800 along the normal, worst relative error %.1e\n", worst);

    /* The refusals, from where the helix ended (nothing moves). */
    unsigned before = checks;
    mc_normal_arc bad = arc;
    for (int k = 0; k < 3; k++) {
        bad.centre[k] = p[k] - R * u[k];
        bad.end[k] = bad.centre[k] + R * w[k];
    }
    bad.turns = 0;
    mc_normal_arc zero = bad;
    zero.normal[0] = zero.normal[1] = zero.normal[2] = 0.0;
    EXPECT(mc_group_move_circular_normal(c, G, &zero, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_ARC_NORMAL);
    mc_normal_arc twice = bad;
    twice.axes[2] = 1;
    EXPECT(mc_group_move_circular_normal(c, G, &twice, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_ARC_AXES);
    mc_normal_arc off = bad;
    for (int k = 0; k < 3; k++) off.centre[k] += 10.0 * nh[k];
    EXPECT(mc_group_move_circular_normal(c, G, &off, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_ARC_OFF_PLANE);
    mc_normal_arc wide = bad;
    for (int k = 0; k < 3; k++) wide.end[k] += 10.0 * w[k];
    EXPECT(mc_group_move_circular_normal(c, G, &wide, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_CENTRE_NOT_EQUIDISTANT);
    mc_normal_arc up = bad;
    for (int k = 0; k < 3; k++) up.end[k] += 10.0 * nh[k];
    EXPECT(mc_group_move_circular_normal(c, G, &up, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_ARC_OFF_PLANE);
    EXPECT(mc_group_move_circular_normal(c, G, NULL, NULL, 0, &FEED, &NOW, &m),
           MC_ERR_NULL_POINTER);
    /* The move's second entry alone (raw): the card refuses the piece. */
    const double piece[6] = {0.0, 1.0, 2.0, 0.0, 0.0, 1.0};
    EXPECT(mc_send_raw(c, MC_OP_GROUP_CIRCULAR_PLANE, G, 0, piece, 6, NULL), MC_ERR_ARC_PIECE);
    double q[4];
    commanded(c, q);
    for (int k = 0; k < 4; k++) ASSERT(q[k] == p[k], "axis %d moved on a refusal", k);
    mc_group_status g;
    CHECK(mc_group_get_status(c, G, &g));
    ASSERT(g.state == MC_GROUP_STATE_STANDBY && g.queued == 0, "group state %u, %u queued",
           g.state, g.queued);
    CHECK(mc_close(c));
    printf("PASS normal_arc (%u refusals)\n", checks - before);
    return 0;
}
