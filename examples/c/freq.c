/*
 * The frequency response measured on the card from C (layout 1.12): a sweep of the closed
 * loop on an axis at rest, its points (gain dB, phase deg, with the plant's and the open
 * loop's), the result read again, the resonances, and the refusals (nothing changes).
 *
 * Runs on a stepped card (deterministic). Positions in counts. The argument is ignored.
 *
 *     cc -std=c11 freq.c $(pkg-config --cflags --libs motioncard) -lm -o freq && ./freq
 */
#include "expect.h"

#include <math.h>

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(1, 10000, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_sim_step(c, 1000));

    mc_freq_sweep s = {0};
    s.mode = MC_FREQ_MODE_REFERENCE;
    s.points = 8;
    s.from_hz = 5.0;
    s.to_hz = 200.0;
    s.amplitude = 100.0;
    s.cycles = 4;
    s.settle_s = 0.2;

    /* The refusals: nothing changes. */
    mc_freq_point pts[16];
    size_t n = 0;
    mc_freq_sweep bad = s;
    bad.to_hz = 6000.0; /* above the Nyquist frequency */
    EXPECT(mc_axis_freq_response(c, 0, &bad, 60000, pts, 16, &n), MC_ERR_FREQ_RANGE);
    bad = s;
    bad.amplitude = -1.0;
    EXPECT(mc_axis_freq_response(c, 0, &bad, 60000, pts, 16, &n), MC_ERR_FREQ_AMPLITUDE);
    bad.amplitude = NAN;
    EXPECT(mc_axis_freq_response(c, 0, &bad, 60000, pts, 16, &n), MC_ERR_NOT_FINITE);
    bad = s;
    bad.amplitude = 600.0; /* twice that beyond the 1000-count following error at rest */
    EXPECT(mc_axis_freq_response(c, 0, &bad, 60000, pts, 16, &n), MC_ERR_FREQ_LIMITS);
    bad = s;
    bad.mode = 7;
    EXPECT(mc_axis_freq_response(c, 0, &bad, 60000, pts, 16, &n), MC_ERR_FREQ_RANGE);

    /* The sweep. */
    CHECK(mc_axis_freq_response(c, 0, &s, 600000, pts, 16, &n));
    ASSERT(n == 8, "%zu points", n);
    ASSERT(fabs(pts[0].hz - 5.0) < 0.01 && fabs(pts[7].hz - 200.0) < 1.0, "%g..%g Hz", pts[0].hz,
           pts[7].hz);
    ASSERT(fabs(pts[0].gain_db) < 1.0, "closed loop at 5 Hz %g dB", pts[0].gain_db);
    ASSERT(pts[7].gain_db < -20.0, "closed loop at 200 Hz %g dB", pts[7].gain_db);
    mc_freq_point again[16];
    size_t m = 0;
    uint32_t complete = 0;
    CHECK(mc_axis_freq_result(c, 0, again, 16, &m, &complete));
    ASSERT(m == 8 && complete == 1 && again[3].gain_db == pts[3].gain_db, "result read again");
    EXPECT(mc_axis_freq_result(c, 0, again, 4, &m, &complete), MC_ERR_BUFFER_TOO_SMALL);
    ASSERT(m == 8, "needed %zu", m);
    mc_freq_resonance res[8];
    size_t r = 0;
    CHECK(mc_axis_freq_resonances(c, 0, res, 8, &r));
    CHECK(mc_axis_freq_stop(c, 0));

    printf("freq: closed loop %.2f dB at %.1f Hz, %.2f dB %.1f deg at %.1f Hz; %zu resonances\n",
           pts[0].gain_db, pts[0].hz, pts[7].gain_db, pts[7].phase_deg, pts[7].hz, r);
    CHECK(mc_close(c));
    printf("PASS freq (%u refusals)\n", checks);
    return 0;
}
