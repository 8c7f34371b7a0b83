/*
 * One unit rule for every event (mc_event): a value that is a position or a distance is in
 * user units of the axis it concerns, whatever the kind. Axis 0 is scaled to 1000 counts per
 * millimetre; a compare channel, a touch probe and the motion events on it all report
 * millimetres.
 *
 * Runs on a stepped card (deterministic); the argument is ignored.
 *
 *     cc -std=c11 units.c $(pkg-config --cflags --libs motioncard) -lm -o units && ./units
 */
#include "check.h"

#include <math.h>

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    const double counts_per_mm = 1000.0;
    CHECK(mc_set_scale(c, 0, counts_per_mm));
    CHECK(mc_enable(c, 0));

    /* Compare channel 0 pulses output 0 at 1 mm; probe channel 0 captures axis 0 at the
       encoder's index pulse. */
    CHECK(mc_compare_single(c, 0, 0, 0, 10, 1.0, MC_COMPARE_POSITIVE));
    mc_probe_trigger t;
    memset(&t, 0, sizeof t);
    t.input = MC_PROBE_INPUT_INDEX;
    t.edges = MC_PROBE_EDGE_RISING;
    CHECK(mc_touch_probe(c, 0, 0, &t));

    mc_move_limits l; /* mm/s, mm/s^2, mm/s^3 */
    CHECK(mc_move_limits_symmetric(50.0, 500.0, 20000.0, &l));
    mc_motion m;
    CHECK(mc_move_absolute(c, 0, 15.0, &l, &m));
    double at = 0.0;
    CHECK(mc_motion_wait(c, m, 10000, &at));
    mc_probe_info pi;
    CHECK(mc_probe_get_status(c, 0, 0, &pi));

    int compare = 0, done = 0, probe = 0;
    mc_event e;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        if (e.kind == MC_EVENT_COMPARE && e.code == MC_COMPARE_FIRED) {
            /* Within a count (0.001 mm) of the position armed. */
            ASSERT(fabs(e.value - 1.0) <= 1.0 / counts_per_mm, "compare fired at %f", e.value);
            compare++;
        } else if (e.kind == MC_EVENT_MOTION_DONE && e.axis == 0) {
            ASSERT(fabs(e.value - 15.0) <= 0.01 && e.value == at, "done at %f", e.value);
            done++;
        } else if (e.kind == MC_EVENT_PROBE && e.axis == 0) {
            /* The index pulse comes once per revolution of 10,000 counts, at 10000.5 counts:
               10.0005 mm; the status gives the same position in the same units. */
            ASSERT(fabs(e.value - 10.0005) <= 1e-9, "probe captured %f", e.value);
            ASSERT(e.value == pi.positions[0], "event %f, status %f", e.value, pi.positions[0]);
            probe++;
        }
    }
    ASSERT(compare == 1 && done == 1 && probe == 1, "%d compare, %d done, %d probe events",
           compare, done, probe);
    printf("units: compare, probe and motion-done events in mm (done at %.4f mm)\n", at);
    CHECK(mc_close(c));
    printf("PASS units\n");
    return 0;
}
