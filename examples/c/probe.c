/*
 * Touch probes from C (PLCopen MC_TouchProbe, MC_AbortTrigger; layout 1.7).
 *
 * A part on the axis's travel (the stepped sim's sensor on input 3, mc_sim_set_sensor) is hit
 * at 2*10^6 counts/s (2 m/s on a 1 um scale): the position captured at its edge is within a
 * count of where the part is, in both directions, and an MC_EVENT_PROBE carries it. A
 * continuous probe on the encoder's index pulse inside a window captures the pulses in the
 * window only (the emulated encoder pulses every 10000 counts); MC_AbortTrigger stops it.
 * The refusals return MC_ERR_PROBE_INPUT.
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 probe.c $(pkg-config --cflags --libs motioncard) -lm -o probe && ./probe
 */
#include "expect.h"

#include <math.h>

static double position(mc_card c) {
    mc_status s;
    CHECK(mc_get_status(c, 0, &s));
    return s.actual_position;
}

static void run_at(mc_card c, double v) {
    mc_velocity_limits vl = {5e6, 5e6, 5e8};
    mc_motion m;
    CHECK(mc_move_velocity(c, 0, v, &vl, &m));
    CHECK(mc_motion_wait_in_velocity(c, m, 10000, NULL));
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(1, 10000, &c));
    CHECK(mc_enable(c, 0));

    mc_probe_trigger t;
    memset(&t, 0, sizeof t);
    t.input = 17;
    t.edges = MC_PROBE_EDGE_RISING;
    EXPECT(mc_touch_probe(c, 0, 0, &t), MC_ERR_PROBE_INPUT);
    t.input = 3;
    t.edges = 0;
    EXPECT(mc_touch_probe(c, 0, 0, &t), MC_ERR_PROBE_INPUT);
    t.edges = MC_PROBE_EDGE_RISING;
    t.use_window = 1;
    t.window_lo = 10.0;
    t.window_hi = 5.0;
    EXPECT(mc_touch_probe(c, 0, 0, &t), MC_ERR_PROBE_INPUT);
    EXPECT(mc_touch_probe(c, 0, 4, &t), MC_ERR_IO_CHANNEL);
    EXPECT(mc_touch_probe(c, 0, 0, NULL), MC_ERR_NULL_POINTER);
    t.use_window = 0;

    /* Hit a part at speed, both ways. */
    double worst = 0.0;
    for (int k = 0; k < 6; k++) {
        double v = (k % 2 == 0 ? 1.0 : -1.0) * 2e6;
        run_at(c, v);
        double part = position(c) + (v > 0 ? 1.0 : -1.0) * (2000.0 + 0.31 * k);
        CHECK(mc_sim_set_sensor(c, 3, 0, part, v > 0));
        CHECK(mc_sim_step(c, 1));
        t.edges = MC_PROBE_EDGE_RISING;
        CHECK(mc_touch_probe(c, 0, 1, &t));
        double got = 0.0;
        CHECK(mc_probe_wait(c, 0, 1, 1, 1000, &got));
        mc_probe_info pi;
        CHECK(mc_probe_get_status(c, 0, 1, &pi));
        ASSERT(pi.state == MC_IO_STATE_DONE && pi.captures == 1 && pi.positions[0] == got,
               "state %u, %u captures", pi.state, pi.captures);
        mc_event e;
        int seen_event = 0;
        while (mc_wait_event(c, 0, &e) == MC_OK) {
            if (e.kind == MC_EVENT_PROBE && e.axis == 1 && e.code == 1 && e.value == got) {
                seen_event = 1;
            }
        }
        ASSERT(seen_event, "no probe event");
        double err = got - part;
        ASSERT(fabs(err) <= 1.0, "captured %f for a part at %f", got, part);
        if (fabs(err) > worst) worst = fabs(err);
    }
    printf("probe: 6 parts hit at 2e6 counts/s, worst error %.3f counts\n", worst);

    /* Continuous on the index pulse from 5000 to 115000, inside [15000, 95000]. */
    mc_motion m;
    CHECK(mc_halt(c, 0, 5e6, 5e8, &m));
    CHECK(mc_motion_wait(c, m, 10000, NULL));
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(5e5, 5e6, 5e8, &lim));
    CHECK(mc_move_absolute(c, 0, 5000.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, NULL));
    memset(&t, 0, sizeof t);
    t.input = MC_PROBE_INPUT_INDEX;
    t.edges = MC_PROBE_EDGE_RISING;
    t.continuous = 1;
    t.use_window = 1;
    t.window_lo = 15000.0;
    t.window_hi = 95000.0;
    CHECK(mc_touch_probe(c, 0, 2, &t));
    CHECK(mc_move_absolute(c, 0, 115000.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, NULL));
    mc_probe_info pi;
    CHECK(mc_probe_get_status(c, 0, 2, &pi));
    /* 10000, 100000 and 110000 are outside. (Rest ends away from a pulse: an axis holding
     * on a pulse's count dithers across it, and the encoder latches it each time.) */
    ASSERT(pi.state == MC_IO_STATE_ARMED && pi.captures == 8 && pi.count == 8 &&
               pi.outside == 3,
           "index: %u captures, %u outside", pi.captures, pi.outside);
    for (uint32_t k = 0; k < pi.count; k++) {
        ASSERT(pi.positions[k] == 20000.0 + 10000.0 * k + 0.5, "capture %u at %f", k,
               pi.positions[k]);
    }
    printf("probe: index pulses in the window: %u captured (20000.5 .. %.1f), %u outside\n",
           pi.captures, pi.positions[pi.count - 1], pi.outside);
    CHECK(mc_abort_trigger(c, 0, 2));
    CHECK(mc_probe_get_status(c, 0, 2, &pi));
    ASSERT(pi.state == MC_IO_STATE_IDLE, "aborted: state %u", pi.state);

    CHECK(mc_close(c));
    ASSERT(seen[-MC_ERR_PROBE_INPUT], "MC_ERR_PROBE_INPUT never returned");
    printf("%u checks\n", checks);
    printf("PASS probe\n");
    return 0;
}
