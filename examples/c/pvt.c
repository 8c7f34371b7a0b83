/*
 * PT/PVT streaming from C (layout 1.7): a PVT stream of 2000 points (a cosine, every 10 ms
 * for 20 s) sent 500 at a time, each refill on the card's low-water event, met exactly at
 * every point; a PT stream (velocities estimated by the card); a point that breaks the limits
 * or comes too early, refused by name; a stream that runs dry, stopped and reported.
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 pvt.c $(pkg-config --cflags --libs motioncard) -lm -o pvt && ./pvt
 */
#include "expect.h"

#include <math.h>

#define N 2000
#define DT 0.01 /* s between points: 100 ticks at 10 kHz */

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

/* Point k (1..N) of A (1 - cos 2 pi t / 4 s), back at rest at the last. */
static mc_pvt_point point(int k) {
    const double a = 3000.0, w = 2.0 * 3.14159265358979323846 / 4.0, t = k * DT;
    mc_pvt_point p = {t, a * (1.0 - cos(w * t)), k == N ? 0.0 : a * w * sin(w * t)};
    return p;
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(1, 10000, &c));
    const uint32_t x = 0;
    CHECK(mc_enable(c, x));
    mc_pvt_limits lim = {20000.0, 2e5};

    /* The refusals. */
    mc_pvt_point one = point(1);
    EXPECT(mc_pvt_push(c, x, &one, 1, 0, NULL), MC_ERR_PVT_SEQUENCE); /* no stream */
    EXPECT(mc_pvt_begin(c, x, 7, &lim, 0), MC_ERR_BAD_CONFIG);
    EXPECT(mc_pvt_begin(c, x, MC_PVT_MODE_PVT, NULL, 0), MC_ERR_NULL_POINTER);
    CHECK(mc_pvt_begin(c, x, MC_PVT_MODE_PVT, &lim, 200));
    mc_pvt_point bad[2] = {point(1), point(1)};
    EXPECT(mc_pvt_push(c, x, bad, 2, 0, NULL), MC_ERR_PVT_TIME);
    expect_in_message("PT/PVT point 1");
    mc_pvt_point fast = {0.02, 5000.0, 0.0}; /* 5000 counts in 10 ms */
    EXPECT(mc_pvt_push(c, x, &fast, 1, 0, NULL), MC_ERR_PVT_LIMIT);
    EXPECT(mc_pvt_push(c, x, NULL, 3, 0, NULL), MC_ERR_NULL_POINTER);
    size_t queued = 0, free_ = 0;
    CHECK(mc_sim_step(c, 1));
    CHECK(mc_pvt_room(c, x, &queued, &free_));
    ASSERT(queued == 1 && free_ == MC_PVT_LEN - 1, "room %zu %zu", queued, free_);

    /* The stream: 500 points now, the rest on each low-water event. */
    mc_pvt_point pts[N];
    for (int k = 0; k < N; k++) pts[k] = point(k + 1);
    size_t sent = 1;
    CHECK(mc_pvt_push(c, x, pts + 1, 499, 0, &free_));
    sent = 500;
    mc_motion m;
    CHECK(mc_pvt_start(c, x, &m));
    double worst = 0.0;
    int refills = 0;
    for (int tick = 1; tick <= N * 100 + 2000; tick++) {
        CHECK(mc_sim_step(c, 1));
        if (tick % 100 == 0 && tick / 100 <= N) {
            const mc_pvt_point *p = &pts[tick / 100 - 1];
            const double err = fabs(axis(c, x).command_position - p->position);
            if (err > worst) worst = err;
        }
        mc_event e;
        while (mc_wait_event(c, 0, &e) == MC_OK) {
            ASSERT(!(e.kind == MC_EVENT_PVT && e.code == MC_PVT_EVENT_STARVED), "starved");
            if (e.kind == MC_EVENT_PVT && e.code == MC_PVT_EVENT_LOW_WATER && sent < N) {
                size_t take = N - sent < 500 ? N - sent : 500;
                CHECK(mc_pvt_push(c, x, pts + sent, take, sent + take == N, NULL));
                sent += take;
                refills++;
            }
        }
    }
    double at = 0.0;
    CHECK(mc_motion_wait(c, m, 10000, &at));
    ASSERT(sent == N && refills >= 3 && worst <= 1e-6, "sent %zu refills %d worst %g", sent,
           refills, worst);
    ASSERT(axis(c, x).state == MC_AXIS_STATE_STANDSTILL, "state %u", axis(c, x).state);
    printf("PVT: %d points, %d refills, worst error at the points %g counts, done at %.3f\n", N,
           refills, worst, at);

    /* PT: the card estimates the velocities; the stream still meets every point. */
    CHECK(mc_pvt_begin(c, x, MC_PVT_MODE_PT, &lim, 0));
    const double base = axis(c, x).command_position;
    mc_pvt_point pt[4] = {{0.1, base + 200.0, 0.0}, {0.2, base + 600.0, 0.0},
                          {0.3, base + 900.0, 0.0}, {0.4, base + 1000.0, 0.0}};
    CHECK(mc_pvt_push(c, x, pt, 4, 1, NULL));
    CHECK(mc_pvt_start(c, x, &m));
    for (int k = 0; k < 4; k++) {
        CHECK(mc_sim_step(c, 1000));
        const double p = axis(c, x).command_position;
        ASSERT(fabs(p - pt[k].position) <= 1e-9 * fabs(pt[k].position), "PT point %d: %f", k, p);
    }
    CHECK(mc_motion_wait(c, m, 10000, NULL));

    /* A stream that runs dry: the axis stops, the motion is aborted, the event says why. */
    CHECK(mc_pvt_begin(c, x, MC_PVT_MODE_PVT, &lim, 0));
    const double p0 = axis(c, x).command_position;
    mc_pvt_point dry[2] = {{0.1, p0 + 100.0, 2000.0}, {0.2, p0 + 400.0, 4000.0}};
    CHECK(mc_pvt_push(c, x, dry, 2, 0, NULL));
    CHECK(mc_pvt_start(c, x, &m));
    EXPECT(mc_motion_wait(c, m, 10000, NULL), MC_ERR_ABORTED);
    CHECK(mc_sim_step(c, 1000));
    ASSERT(axis(c, x).state == MC_AXIS_STATE_STANDSTILL, "dry: state %u", axis(c, x).state);
    int starved = 0;
    mc_event e;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        starved |= e.kind == MC_EVENT_PVT && e.code == MC_PVT_EVENT_STARVED;
    }
    ASSERT(starved, "no MC_PVT_EVENT_STARVED");

    CHECK(mc_close(c));
    const mc_result codes[] = {MC_ERR_PVT_TIME, MC_ERR_PVT_LIMIT, MC_ERR_PVT_SEQUENCE};
    for (size_t k = 0; k < sizeof codes / sizeof codes[0]; k++) {
        ASSERT(seen[-codes[k]], "code %d (%s) never returned", (int)codes[k],
               mc_result_str(codes[k]));
    }
    printf("%u checks\n", checks);
    printf("PASS pvt\n");
    return 0;
}
