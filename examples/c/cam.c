/*
 * Camming from C (layout 1.7): a periodic cubic cam table of 65 points (a rotary knife: one
 * knife turn of 10000 counts per sheet of 20000 conveyor counts, the blade at 0.8 x the web at
 * the cut) loaded into the card, a slave on it behind a master axis (the slave on the table at
 * every tick), a second table taking over at the end of a cycle, CamOut, and the refusals.
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 cam.c $(pkg-config --cflags --libs motioncard) -lm -o cam && ./cam
 */
#include "expect.h"

#include <math.h>

#define NPTS 65
#define SHEET 20000.0
#define TURN 10000.0

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
    const uint32_t slave = 0, master = 1;
    CHECK(mc_enable(c, slave));
    CHECK(mc_enable(c, master));

    const double tau = 6.283185307179586, k = (0.8 - TURN / SHEET) * SHEET / tau;
    double m[NPTS], s[NPTS], s2[NPTS];
    for (int i = 0; i < NPTS; i++) {
        m[i] = SHEET * i / (NPTS - 1);
        s[i] = TURN / SHEET * m[i] + k * sin(tau * m[i] / SHEET);
        const double w = 1.0 - cos(tau * m[i] / SHEET);
        s2[i] = s[i] + 300.0 * w * w; /* another path between the same cuts */
    }

    /* The refusals. */
    double bad_m[2] = {0.0, 0.0}, bad_s[2] = {0.0, 1.0};
    EXPECT(mc_cam_load_table(c, 3, bad_m, bad_s, 2, 0), MC_ERR_CAM_TABLE);
    EXPECT(mc_cam_load_table(c, MC_CAM_TABLES, m, s, NPTS, 0), MC_ERR_CAM_TABLE);
    EXPECT(mc_cam_load_table(c, 0, m, s, NPTS, 8), MC_ERR_BAD_CONFIG);
    EXPECT(mc_cam_load_table(c, 0, NULL, s, NPTS, 0), MC_ERR_NULL_POINTER);

    CHECK(mc_cam_load_table(c, 0, m, s, NPTS, MC_CAM_CUBIC | MC_CAM_PERIODIC));
    CHECK(mc_cam_load_table(c, 1, m, s2, NPTS, MC_CAM_CUBIC | MC_CAM_PERIODIC));
    mc_cam_settings cam = {0, 0.0, 0.0, 1.0, 1.0, 0};
    mc_sync_limits lim = {30000.0, 3e5, 3e7};
    mc_cam_settings missing = cam;
    missing.table = 2;
    EXPECT(mc_cam_in(c, slave, MC_MASTER_COMMANDED, master, &missing, &lim, NULL),
           MC_ERR_CAM_TABLE);
    EXPECT(mc_cam_switch(c, slave, MC_MASTER_COMMANDED, master, &cam, &lim, NULL),
           MC_ERR_INVALID_STATE);

    /* The master at 10000 counts/s; the slave on the cam. */
    mc_velocity_limits vl = {1e5, 1e5, 1e7};
    mc_motion mv, mc;
    CHECK(mc_move_velocity(c, master, 10000.0, &vl, &mv));
    CHECK(mc_motion_wait_in_velocity(c, mv, 10000, NULL));
    CHECK(mc_cam_in(c, slave, MC_MASTER_COMMANDED, master, &cam, &lim, &mc));
    CHECK(mc_motion_wait_in_sync(c, mc, 10000, NULL));
    EXPECT(mc_cam_load_table(c, 0, m, s, NPTS, MC_CAM_CUBIC | MC_CAM_PERIODIC), MC_ERR_CAM_TABLE);

    /* One cycle: whenever the master (its command of the same tick) is on a table point, the
       slave is on the table's value there (the table repeats, rising a turn per sheet). */
    int hits = 0;
    double worst = 0.0;
    for (int t = 0; t < 20000; t++) {
        CHECK(mc_sim_step(c, 1));
        const double x = axis(c, slave).command_position;
        const double mm = axis(c, master).command_position;
        const double cycles = floor(mm / SHEET);
        const double u = mm - cycles * SHEET;
        const double step = SHEET / (NPTS - 1);
        const double idx = u / step;
        if (fabs(idx - round(idx)) * step < 1e-6) {
            const int i = (int)round(idx); /* 0 .. NPTS - 1: s[NPTS - 1] is s[0] + TURN */
            const double err = fabs(x - (s[i] + cycles * TURN));
            if (err > worst) worst = err;
            hits++;
        }
    }
    ASSERT(hits >= 32 && worst < 1e-6, "%d points met, worst %g", hits, worst);
    printf("cam: %d table points met, worst error %g counts\n", hits, worst);

    /* Table 1 takes over at the end of the cycle. */
    mc_cam_settings next = cam;
    next.table = 1;
    mc_motion sw;
    CHECK(mc_cam_switch(c, slave, MC_MASTER_COMMANDED, master, &next, &lim, &sw));
    double at = 0.0;
    CHECK(mc_motion_wait_cam_switch(c, sw, 30000, &at));
    printf("switched at %.3f\n", at);

    /* CamOut: velocity mode at the slave's velocity; then halt. */
    mc_motion out;
    CHECK(mc_cam_out(c, slave, &out));
    CHECK(mc_motion_wait_in_velocity(c, out, 10000, NULL));
    EXPECT(mc_motion_wait(c, mc, 0, NULL), MC_ERR_ABORTED);
    CHECK(mc_halt(c, slave, 3e5, 3e7, &out));
    CHECK(mc_motion_wait(c, out, 10000, NULL));

    CHECK(mc_close(c));
    const mc_result codes[] = {MC_ERR_CAM_TABLE};
    for (size_t i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        ASSERT(seen[-codes[i]], "code %d (%s) never returned", (int)codes[i],
               mc_result_str(codes[i]));
    }
    printf("%u checks\n", checks);
    printf("PASS cam\n");
    return 0;
}
