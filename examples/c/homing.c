/*
 * Homing from C: MC_SetPosition (absolute and relative; the raw encoder count does not move),
 * MC_Home on the index pulse (CiA 402 method 34: the emulated encoder pulses once per
 * revolution, every 10000 counts) and on the current position (37), a homing that fails
 * (method 19 looks for a home switch the emulated machine does not have, and gives up after
 * max_distance), a move refused while the axis homes and a halt that aborts a homing. Every
 * homing code of the header is returned (and the override's range, returned by no other
 * program).
 *
 * Home switches, limit switches and hard stops are parts of the emulated machine only the Rust
 * tests place (tests/homing.rs covers those methods).
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 homing.c $(pkg-config --cflags --libs motioncard) -lm -o homing && ./homing
 */
#include "expect.h"

#include <math.h>


static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

static int homed(mc_card c, uint32_t a) { return (axis(c, a).raw.motion_flags & MC_MOTION_HOMED) != 0; }

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    const uint32_t a = 0;
    CHECK(mc_enable(c, a));

    /* MC_SetPosition: the frame moves, the axis and its raw count do not. */
    ASSERT(!homed(c, a), "homed at boot");
    const int64_t raw = axis(c, a).raw.encoder;
    CHECK(mc_set_position(c, a, 500.0, 0));
    mc_status s = axis(c, a);
    ASSERT(s.actual_position == 500.0 && s.raw.encoder == raw && homed(c, a),
           "set position: at %f, raw %lld", s.actual_position, (long long)s.raw.encoder);
    CHECK(mc_set_position(c, a, -20.0, MC_SET_POSITION_RELATIVE));
    ASSERT(axis(c, a).actual_position == 480.0, "relative: at %f", axis(c, a).actual_position);
    EXPECT(mc_set_position(c, a, 0.0, 4), MC_ERR_BAD_CONFIG);
    EXPECT(mc_set_position(c, a, NAN, 0), MC_ERR_NOT_FINITE);

    /* Settings: the defaults, and the methods the card refuses. */
    mc_homing_settings h;
    EXPECT(mc_homing_settings_default(NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_homing_settings_default(&h));
    ASSERT(h.method == MC_HOMING_METHOD_CURRENT_POSITION &&
               h.flags == (MC_HOMING_FLAG_INDEX | MC_HOMING_FLAG_MOVE_TO_HOME) &&
               h.creep_vel < h.search_vel,
           "defaults: method %d flags %u", (int)h.method, h.flags);
    mc_homing_settings bad = h;
    bad.method = 15;
    EXPECT(mc_configure_homing(c, a, &bad), MC_ERR_HOMING_METHOD);
    expect_in_message("homing method");
    bad.method = 34;
    bad.flags = MC_HOMING_FLAG_MOVE_TO_HOME; /* an index method without an index channel */
    EXPECT(mc_configure_homing(c, a, &bad), MC_ERR_HOMING_METHOD);
    bad = h;
    bad.creep_vel = 2.0 * h.search_vel;
    EXPECT(mc_configure_homing(c, a, &bad), MC_ERR_BAD_CONFIG);
    EXPECT(mc_configure_homing(c, a, NULL), MC_ERR_NULL_POINTER);

    /* Method 34: the next index pulse in the positive direction (10000) reads 100 + 25. */
    h.method = 34;
    h.home_offset = 25.0;
    CHECK(mc_configure_homing(c, a, &h));
    mc_motion m;
    CHECK(mc_home(c, a, 100.0, &m));
    ASSERT(axis(c, a).state == MC_AXIS_STATE_HOMING && !homed(c, a), "not homing");
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(10000.0, 1e6, 1e8, &lim));
    EXPECT(mc_move_absolute(c, a, 0.0, &lim, NULL), MC_ERR_AXIS_HOMING);
    EXPECT(mc_jog(c, a, 1000.0, NULL), MC_ERR_AXIS_HOMING);
    double at = 0.0;
    CHECK(mc_motion_wait(c, m, 30000, &at));
    s = axis(c, a);
    ASSERT(homed(c, a) && s.state == MC_AXIS_STATE_STANDSTILL && fabs(at - 125.0) <= 1.0,
           "index: at %f", at);
    /* The home point is the pulse: the raw count there is 10000. */
    ASSERT(fabs(s.raw.encoder - (s.actual_position - 125.0) - 10000.0) <= 1.0,
           "index home point at raw %f", s.raw.encoder - (s.actual_position - 125.0));
    printf("homed on the index: at %.1f (home offset 25)\n", at);

    /* Method 37: the current position reads -7, nothing moves. */
    h.method = MC_HOMING_METHOD_CURRENT_POSITION;
    h.home_offset = 0.0;
    CHECK(mc_configure_homing(c, a, &h));
    const int64_t before = axis(c, a).raw.encoder;
    CHECK(mc_home(c, a, -7.0, &m));
    CHECK(mc_motion_wait(c, m, 1000, &at));
    ASSERT(at == -7.0 && axis(c, a).raw.encoder == before, "current position: at %f", at);

    /* Method 19 on a machine without a home switch: the search gives up after 50000 counts. */
    h.method = 19;
    h.max_distance = 50000.0;
    CHECK(mc_configure_homing(c, a, &h));
    CHECK(mc_home(c, a, 0.0, &m));
    EXPECT(mc_motion_wait(c, m, 30000, &at), MC_ERR_HOMING_FAILED);
    expect_in_message("maximum distance");
    mc_event e;
    int failed = 0;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        if (e.kind == MC_EVENT_HOMING_FAILED && e.seq == m.seq) {
            failed = 1;
            ASSERT(e.code == MC_HOMING_ERROR_DISTANCE, "code %d", e.code);
        }
    }
    s = axis(c, a);
    ASSERT(failed && s.state == MC_AXIS_STATE_STANDSTILL && !homed(c, a) &&
               s.stop_reason == MC_STOP_REASON_HOMING_FAILED,
           "failed homing: state %u reason %u", s.state, s.stop_reason);

    /* A halt aborts a homing. */
    CHECK(mc_home(c, a, 0.0, &m));
    CHECK(mc_sim_step(c, 2000));
    CHECK(mc_halt(c, a, 1e6, 1e8, NULL));
    EXPECT(mc_motion_wait(c, m, 0, &at), MC_ERR_ABORTED);

    /* The override's range (no other program asks for it). */
    EXPECT(mc_set_override(c, a, 3.0), MC_ERR_OVERRIDE_RANGE);

    CHECK(mc_close(c));
    const mc_result codes[] = {MC_ERR_HOMING_METHOD, MC_ERR_AXIS_HOMING, MC_ERR_HOMING_FAILED,
                               MC_ERR_OVERRIDE_RANGE};
    for (size_t k = 0; k < sizeof codes / sizeof codes[0]; k++) {
        ASSERT(seen[-codes[k]], "code %d (%s) never returned", (int)codes[k],
               mc_result_str(codes[k]));
    }
    printf("%u checks\n", checks);
    printf("PASS homing\n");
    return 0;
}
