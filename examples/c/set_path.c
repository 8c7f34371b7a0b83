/*
 * A path across cards from C (layout 1.14): two stepped cards on one sync bus, a 12-axis path
 * (blended lines, a helix, a dwell, exact stops) whose dimensions are split over the cards'
 * groups, streamed in two releases (the second while the path runs). The same path is run
 * split 6 + 6 and 8 + 4: every dimension's commanded position is the same, to the bit, on
 * every tick sampled, whichever card and split computed it, and every axis ends at its final
 * target exactly. Then a hold, a resume and a halt, each timed to one tick on both cards (every
 * axis stops at the same fraction of a 12-axis line); the refusals: a line of the wrong count,
 * a NULL target, a card not in the set, the card's refusals of staging entries sent raw
 * (MC_ERR_PATH_MORE, an MC_OP_PATH_MORE alone; MC_ERR_PATH_RELEASE, a release of nothing
 * staged; MC_ERR_PATH_DIMS, a release to a group without dimensions); a pause timed on both
 * cards (every axis stops on the end of the segment it is in) and the path going on; a closed
 * handle.
 *
 * Runs on stepped cards (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 set_path.c $(pkg-config --cflags --libs motioncard) -lm -o set_path && ./set_path
 */
#include "expect.h"

#include <math.h>
#include <string.h>

#define RATE 10000u
#define N 12        /* dimensions */
#define MAXT 40000  /* ticks sampled from the start */
#define NSEGS 6

/* Commanded positions per tick from the first release, per run; whether sampled. */
static double pos[2][MAXT][N];
static unsigned char have[2][MAXT];

static double pt(double k, int d) {
    return k * (1000.0 + 137.0 * d) * (d % 2 == 0 ? 1.0 : -0.5);
}

/* The final target of every dimension. */
static double final_of(int d) { return 250.0 * (d + 1) * (d % 3 == 1 ? -1.0 : 1.0); }

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

static uint64_t tick_of(mc_card c) {
    uint64_t t = 0;
    CHECK(mc_get_tick(c, &t));
    return t;
}

/* Two stepped cards of 8 axes on one bus; card k's group 0 over its first split[k] axes,
   enabled. */
static void open_cards(const int split[2], mc_card cards[2]) {
    CHECK(mc_open_sim_bus(2, 8, RATE, cards));
    for (int k = 0; k < 2; k++) {
        uint32_t axes[8];
        for (int a = 0; a < split[k]; a++) {
            axes[a] = (uint32_t)a;
            CHECK(mc_enable(cards[k], (uint32_t)a));
        }
        mc_group_settings gs;
        CHECK(mc_group_settings_new(axes, (size_t)split[k], &gs));
        CHECK(mc_group_configure(cards[k], 0, &gs));
        CHECK(mc_group_enable(cards[k], 0));
    }
}

static void settings(mc_set_path_settings *s) {
    static const double v[3] = {4e4, 6e4, 5e4}, a[3] = {6e5, 8e5, 1e6}, j[3] = {6e7, 1e8, 8e7};
    CHECK(mc_set_path_settings_uniform(N, 1.0, 1.0, 1.0, s));
    for (int d = 0; d < N; d++) {
        s->vmax[d] = v[d % 3];
        s->amax[d] = a[d % 3];
        s->jmax[d] = j[d % 4 % 3];
    }
}

static mc_set_path open_path(mc_card cards[2]) {
    static const mc_path_part parts[2] = {{0, 0}, {1, 0}};
    mc_set_path_settings s;
    settings(&s);
    mc_set_path p = 0;
    CHECK(mc_set_path_open(cards, 2, parts, 2, &s, &p));
    uint32_t n = 0;
    CHECK(mc_set_path_dims(p, &n));
    ASSERT(n == N, "%u dimensions", n);
    return p;
}

/* Dimension d's card and axis under a split. */
static void owner(const int split[2], mc_card cards[2], int d, mc_card *c, uint32_t *a) {
    *c = d < split[0] ? cards[0] : cards[1];
    *a = (uint32_t)(d < split[0] ? d : d - split[0]);
}

static void sample(int run, const int split[2], mc_card cards[2], uint64_t t0) {
    uint64_t t = tick_of(cards[0]);
    ASSERT(tick_of(cards[1]) == t, "the cards' ticks apart");
    uint64_t rel = t - t0;
    if (rel >= MAXT) return;
    for (int d = 0; d < N; d++) {
        mc_card c;
        uint32_t a;
        owner(split, cards, d, &c, &a);
        pos[run][rel][d] = axis(c, a).command_position;
    }
    have[run][rel] = 1;
}

static int at_rest(mc_card cards[2]) {
    for (int k = 0; k < 2; k++) {
        mc_group_status g;
        CHECK(mc_group_get_status(cards[k], 0, &g));
        if (g.state != MC_GROUP_STATE_STANDBY || g.path_queued != 0) return 0;
    }
    return 1;
}

/* Run the path under `split`, sampling every tick from the first release; the second
   release's tick after the first in *gap. Leaves the cards open in cards[]. */
static void run_split(int run, const int split[2], mc_card cards[2], uint64_t *gap) {
    open_cards(split, cards);
    mc_set_path p = open_path(cards);
    double a[N], b[N], h[N - 2], c[N], f[N];
    for (int d = 0; d < N; d++) {
        a[d] = pt(1.0, d);
        b[d] = pt(2.0, d);
        c[d] = pt(0.5, d);
        f[d] = final_of(d);
    }
    for (int d = 2; d < N; d++) h[d - 2] = 3.0 * pt(1.0, d) - 400.0 * d;
    /* first release: two blended lines and a helix (half a turn in dimensions 0 and 1, the
       other ten rising) */
    CHECK(mc_set_path_line(p, 1, a, N, 3e4, 5.0));
    CHECK(mc_set_path_line(p, 2, b, N, 2e4, 5.0));
    mc_arc arc = {MC_ARC_BY_CENTRE, 1, {b[0] + 8000.0, b[1]}, {b[0] + 4000.0, b[1]}};
    CHECK(mc_set_path_arc(p, 3, &arc, MC_ARC_PLANE_XY, h, N - 2, 2.5e4, 2.0));
    uint32_t staged = 0;
    CHECK(mc_set_path_progress(p, &staged, NULL, NULL));
    ASSERT(staged == 3, "%u staged", staged);
    uint64_t t1 = 0, t2 = 0;
    CHECK(mc_set_path_release(p, &t1));
    for (int k = 0; k < 1500; k++) {
        sample(run, split, cards, t1);
        CHECK(mc_sim_step(cards[0], 1));
    }
    /* second release, while it runs: a dwell, an exact stop, the end */
    CHECK(mc_set_path_dwell(p, 4, 0.002));
    CHECK(mc_set_path_line(p, 5, c, N, 4e4, 0.0));
    CHECK(mc_set_path_line(p, 6, f, N, 5e4, 0.0));
    CHECK(mc_set_path_release(p, &t2));
    *gap = t2 - t1;
    uint32_t done = 0, queued = 0;
    for (int k = 0; k < MAXT && !at_rest(cards); k++) {
        sample(run, split, cards, t1);
        CHECK(mc_sim_step(cards[0], 1));
    }
    sample(run, split, cards, t1);
    CHECK(mc_set_path_wait(p, 1000));
    CHECK(mc_set_path_progress(p, &staged, &queued, &done));
    ASSERT(staged == 0 && queued == 0 && done == NSEGS, "staged %u queued %u done %u", staged,
           queued, done);
    for (int d = 0; d < N; d++) {
        mc_card cd;
        uint32_t ad;
        owner(split, cards, d, &cd, &ad);
        mc_status s = axis(cd, ad);
        ASSERT(s.command_position == f[d] && s.command_velocity == 0.0,
               "split %d+%d dimension %d ended at %.9f, target %.9f", split[0], split[1], d,
               s.command_position, f[d]);
    }
    CHECK(mc_set_path_close(p));
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    static const int splits[2][2] = {{6, 6}, {8, 4}};
    mc_card cards[2][2];
    uint64_t gap[2];
    for (int r = 0; r < 2; r++) {
        run_split(r, splits[r], cards[r], &gap[r]);
        if (r == 1)
            for (int k = 1; k >= 0; k--) CHECK(mc_close(cards[r][k]));
    }
    ASSERT(gap[0] == gap[1], "second release %llu and %llu ticks after the first",
           (unsigned long long)gap[0], (unsigned long long)gap[1]);
    /* every tick both runs sampled: every dimension bit-identical, whichever card computed
       it; and the path moved */
    unsigned compared = 0, last = 0;
    for (unsigned t = 0; t < MAXT; t++) {
        if (!have[0][t] || !have[1][t]) continue;
        for (int d = 0; d < N; d++)
            ASSERT(memcmp(&pos[0][t][d], &pos[1][t][d], sizeof(double)) == 0,
                   "tick %u after the start, dimension %d: %.12f (6+6) against %.12f (8+4)", t,
                   d, pos[0][t][d], pos[1][t][d]);
        compared++;
        last = t;
    }
    ASSERT(compared > 1000 && pos[0][last / 2][0] != 0.0, "%u ticks compared", compared);
    printf("set_path: 12 axes split 6+6 and 8+4 bit-identical on %u ticks (release 2 at +%llu, "
           "at rest at +%u), every axis at its target\n",
           compared, (unsigned long long)gap[0], last);

    /* A halt timed to one tick on both cards (the 6+6 cards): along a 12-axis line, every
       dimension stops at the same fraction of it. */
    mc_card *cs = cards[0];
    mc_set_path p = open_path(cs);
    double from[N], to[N];
    for (int d = 0; d < N; d++) {
        from[d] = final_of(d);
        to[d] = from[d] + 1000.0 * (d + 1) * (d % 2 ? -1.0 : 1.0);
    }
    CHECK(mc_set_path_line(p, 10, to, N, 3e4, 0.0));
    uint64_t tr = 0, th = 0;
    CHECK(mc_set_path_release(p, &tr));
    /* a wait shorter than the path: MC_ERR_TIMEOUT after 50 ms of card time (500 ticks) */
    uint64_t tw = tick_of(cs[0]);
    EXPECT(mc_set_path_wait(p, 50), MC_ERR_TIMEOUT);
    tw = tick_of(cs[0]) - tw;
    ASSERT(tw >= 500 && tw < 600, "a wait of 50 ms took %llu ticks", (unsigned long long)tw);
    CHECK(mc_sim_step(cs[0], 500));
    /* a hold on one tick: every axis comes to rest on the line, at one fraction of it */
    uint64_t tho = 0, tre = 0;
    CHECK(mc_set_path_hold(p, &tho));
    CHECK(mc_sim_step(cs[0], 3000));
    double held = -1.0;
    for (int d = 0; d < N; d++) {
        mc_status s = axis(cs[d / 6], (uint32_t)(d % 6));
        double frac = (s.command_position - from[d]) / (to[d] - from[d]);
        if (d == 0) held = frac;
        ASSERT(s.command_velocity == 0.0 && fabs(frac - held) < 1e-9 && frac > 0.0,
               "held: dimension %d at %.12f of the line (velocity %g), dimension 0 at %.12f", d,
               frac, s.command_velocity, held);
    }
    CHECK(mc_set_path_override(p, 1.0, &tre));
    ASSERT(tr < tho && tho < tre, "release %llu, hold %llu, resume %llu",
           (unsigned long long)tr, (unsigned long long)tho, (unsigned long long)tre);
    CHECK(mc_sim_step(cs[0], 1000));
    CHECK(mc_set_path_halt(p, 2e5, 5e7, &th));
    ASSERT(th > tre, "halt on %llu, resume on %llu", (unsigned long long)th,
           (unsigned long long)tre);
    for (int k = 0; k < 100 && !at_rest(cs); k++) CHECK(mc_sim_step(cs[0], 100));
    CHECK(mc_set_path_wait(p, 1000));
    double frac0 = -1.0;
    for (int d = 0; d < N; d++) {
        mc_status s = axis(cs[d / 6], (uint32_t)(d % 6));
        double frac = (s.command_position - from[d]) / (to[d] - from[d]);
        if (d == 0) frac0 = frac;
        ASSERT(s.command_velocity == 0.0 && fabs(frac - frac0) < 1e-9,
               "dimension %d stopped at %.12f of the line, dimension 0 at %.12f", d, frac,
               frac0);
    }
    ASSERT(frac0 > held + 0.01 && frac0 < 0.95, "held at %.6f, halted at %.6f of the line", held,
           frac0);
    printf("set_path: held on tick %llu at %.6f of a 12-axis line, resumed on %llu; halt on "
           "tick %llu, every axis stopped at %.6f of the line\n",
           (unsigned long long)tho, held, (unsigned long long)tre, (unsigned long long)th, frac0);

    /* The refusals. */
    double t11[N];
    for (int d = 0; d < N; d++) t11[d] = 1.0;
    EXPECT(mc_set_path_line(p, 20, t11, N - 1, 1e4, 0.0), MC_ERR_BAD_AXIS);
    EXPECT(mc_set_path_line(p, 20, NULL, N, 1e4, 0.0), MC_ERR_NULL_POINTER);
    EXPECT(mc_set_path_dwell(p, 20, -1.0), MC_ERR_NON_POSITIVE_LIMIT);
    mc_set_path_settings s;
    settings(&s);
    mc_set_path q = 0;
    const mc_path_part far[2] = {{0, 0}, {2, 0}};
    EXPECT(mc_set_path_open(cs, 2, far, 2, &s, &q), MC_ERR_BAD_CONFIG);
    const mc_path_part parts[2] = {{0, 0}, {1, 0}};
    s.ndims = N - 1;
    EXPECT(mc_set_path_open(cs, 2, parts, 2, &s, &q), MC_ERR_BAD_AXIS);
    EXPECT(mc_set_path_open(cs, 2, parts, 2, NULL, &q), MC_ERR_NULL_POINTER);
    /* the cards' own refusals of staging entries, sent raw */
    const double more[6] = {1.0, 2.0, 3.0, 4.0, 0.0, 0.0};
    EXPECT(mc_send_raw(cs[1], MC_OP_PATH_MORE, 0, 0, more, 4, NULL), MC_ERR_PATH_MORE);
    const double one = 1.0;
    EXPECT(mc_send_raw(cs[0], MC_OP_PATH_RELEASE, 0, 0, &one, 1, NULL), MC_ERR_PATH_RELEASE);
    uint32_t g1[2] = {6, 7};
    CHECK(mc_enable(cs[0], 6));
    CHECK(mc_enable(cs[0], 7));
    mc_group_settings gs;
    CHECK(mc_group_settings_new(g1, 2, &gs));
    CHECK(mc_group_configure(cs[0], 1, &gs));
    CHECK(mc_group_enable(cs[0], 1));
    EXPECT(mc_send_raw(cs[0], MC_OP_PATH_RELEASE, 1, 0, &one, 1, NULL), MC_ERR_PATH_DIMS);
    uint32_t staged = 9, queued = 9;
    CHECK(mc_set_path_progress(p, &staged, &queued, NULL));
    ASSERT(staged == 0 && queued == 0, "after the refusals: %u staged, %u queued", staged,
           queued);
    /* nothing moved: the path still goes on from where it stopped; back to the start through
       a midpoint blended (tolerance 50 counts), paused on one tick on both cards: every axis
       stops at the end of the segment it is in, the midpoint, exactly; then on to the end */
    double back[N], mid[N];
    for (int d = 0; d < N; d++) {
        back[d] = from[d];
        mid[d] = 0.5 * (from[d] + axis(cs[d / 6], (uint32_t)(d % 6)).command_position);
    }
    CHECK(mc_set_path_line(p, 21, mid, N, 3e4, 50.0));
    CHECK(mc_set_path_line(p, 22, back, N, 3e4, 0.0));
    uint64_t tb = 0, tp = 0, tu = 0;
    CHECK(mc_set_path_release(p, &tb));
    CHECK(mc_set_path_pause(p, 1, &tp));
    CHECK(mc_sim_step(cs[0], 20000));
    for (int d = 0; d < N; d++) {
        mc_status s = axis(cs[d / 6], (uint32_t)(d % 6));
        ASSERT(s.command_velocity == 0.0 && fabs(s.command_position - mid[d]) < 1e-6,
               "paused: dimension %d at %.9f (velocity %g), the segment ends at %.9f", d,
               s.command_position, s.command_velocity, mid[d]);
    }
    CHECK(mc_set_path_progress(p, NULL, &queued, NULL));
    ASSERT(queued == 1, "paused with %u segments queued, not 1", queued);
    CHECK(mc_set_path_pause(p, 0, &tu));
    ASSERT(tb < tp && tp < tu, "release %llu, pause %llu, go on %llu", (unsigned long long)tb,
           (unsigned long long)tp, (unsigned long long)tu);
    printf("set_path: paused on tick %llu at the end of segment 21 on both cards, every axis on "
           "its end; went on on tick %llu\n",
           (unsigned long long)tp, (unsigned long long)tu);
    for (int k = 0; k < 200 && !at_rest(cs); k++) CHECK(mc_sim_step(cs[0], 100));
    CHECK(mc_set_path_wait(p, 1000));
    for (int d = 0; d < N; d++)
        ASSERT(axis(cs[d / 6], (uint32_t)(d % 6)).command_position == from[d],
               "dimension %d not back", d);
    CHECK(mc_set_path_close(p));
    EXPECT(mc_set_path_dwell(p, 22, 0.1), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_path_close(p), MC_ERR_BAD_HANDLE);
    for (int k = 1; k >= 0; k--) CHECK(mc_close(cs[k]));
    printf("PASS set_path (%u refusals)\n", checks);
    return 0;
}
