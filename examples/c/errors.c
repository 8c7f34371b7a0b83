/*
 * Every error path an application can hit, and misuse of the API: each call returns its own
 * code, sets a message, leaves its outputs untouched, and never crashes. NULL pointers,
 * unknown and closed handles, double close, buffers too small, NaN and infinite arguments,
 * calls in the wrong state, refusals by the card, time-outs and aborted motions.
 *
 * The card is a stepped emulated one (deterministic); one real-time `sim` card is opened to
 * show what a stepped-only call does on it. The argument is ignored.
 */
#include "expect.h"

#include <math.h>


/* Every result code of the header (the Rust test checks this list against motioncard.h). */
static const mc_result ALL_CODES[] = {
    MC_ERR_BAD_URI,        MC_ERR_NOT_FOUND,       MC_ERR_BUSY,
    MC_ERR_VERSION_MISMATCH, MC_ERR_NOT_RESPONDING, MC_ERR_PROTOCOL,
    MC_ERR_RING_FULL,      MC_ERR_TIMEOUT,         MC_ERR_ABORTED,
    MC_ERR_BAD_AXIS,       MC_ERR_NOT_FINITE,      MC_ERR_NON_POSITIVE_LIMIT,
    MC_ERR_AXIS_DISABLED,  MC_ERR_INVALID_STATE,   MC_ERR_BAD_CONFIG,
    MC_ERR_INFEASIBLE,     MC_ERR_OUT_OF_RANGE,    MC_ERR_AXES_ENABLED,
    MC_ERR_UNKNOWN_COMMAND, MC_ERR_IO,             MC_ERR_UNSUPPORTED,
    /* groups */
    MC_ERR_BAD_GROUP,      MC_ERR_AXIS_IN_OTHER_GROUP, MC_ERR_AXIS_NOT_IN_GROUP,
    MC_ERR_AXIS_BUSY,      MC_ERR_AXIS_GROUPED,    MC_ERR_ZERO_LENGTH_ARC,
    MC_ERR_CENTRE_NOT_EQUIDISTANT, MC_ERR_RADIUS_TOO_SMALL, MC_ERR_COLLINEAR_POINTS,
    MC_ERR_QUEUE_FULL,     MC_ERR_INCOMPATIBLE_MODE, MC_ERR_GROUP_DISABLED,
    MC_ERR_FILTER_BUSY,    MC_ERR_PLANE_AXES,
    /* NURBS */
    MC_ERR_NURBS_SEQUENCE, MC_ERR_NURBS_DEGREE,    MC_ERR_NURBS_DIMENSION,
    MC_ERR_NURBS_CTRL_COUNT, MC_ERR_NURBS_KNOT_COUNT, MC_ERR_NURBS_KNOTS_DECREASING,
    MC_ERR_NURBS_KNOT_MULTIPLICITY, MC_ERR_NURBS_NOT_CLAMPED, MC_ERR_NURBS_WEIGHT,
    MC_ERR_NURBS_POINT,    MC_ERR_NURBS_START,     MC_ERR_NURBS_ZERO_LENGTH,
    MC_ERR_NURBS_KNOT,
    /* safety */
    MC_ERR_WATCHDOG_TRIPPED, MC_ERR_ESTOP_ACTIVE,  MC_ERR_HARD_LIMIT,
    MC_ERR_SOFT_LIMIT,     MC_ERR_CAUSE_ACTIVE,    MC_ERR_WATCHDOG_TIMEOUT,
    MC_ERR_BAD_CATEGORY,
    /* limits, deadlines, stops, sessions, the card's life */
    MC_ERR_LIMIT_RANGE,    MC_ERR_PLAN_CHECK,      MC_ERR_EXPIRED,
    MC_ERR_STOP_TOO_LONG,  MC_ERR_SESSION,         MC_ERR_CARD_GONE,
    MC_ERR_CLOSED,         MC_ERR_CANCELLED,       MC_ERR_PERMISSION_DENIED,
    MC_ERR_NO_SESSION,
    /* motion modes, homing */
    MC_ERR_OVERRIDE_RANGE, MC_ERR_HOMING_METHOD,   MC_ERR_AXIS_HOMING,
    MC_ERR_HOMING_FAILED,
    /* the continuous path */
    MC_ERR_PATH_MODE,      MC_ERR_PATH_ZERO_LENGTH, MC_ERR_PATH_OUTPUT,
    MC_ERR_PATH_BUSY,      MC_ERR_PATH_ID,         MC_ERR_PATH_CURVE,
    /* digital I/O, compare, probes */
    MC_ERR_IO_CONFIG,      MC_ERR_IO_CHANNEL,      MC_ERR_COMPARE_MODE,
    MC_ERR_COMPARE_FULL,   MC_ERR_COMPARE_ORDER,   MC_ERR_COMPARE_BUSY,
    MC_ERR_PROBE_INPUT,
    /* synchronised motion (layout 1.7) */
    MC_ERR_GEAR_RATIO,     MC_ERR_SYNC_MASTER,     MC_ERR_PVT_TIME,
    MC_ERR_PVT_LIMIT,      MC_ERR_PVT_SEQUENCE,    MC_ERR_CAM_TABLE,
    MC_ERR_CAM_SEQUENCE,
    /* the scope (layout 1.8) */
    MC_ERR_SCOPE_SIGNAL,   MC_ERR_SCOPE_CHANNELS,  MC_ERR_SCOPE_DIVIDER,
    MC_ERR_SCOPE_TRIGGER,  MC_ERR_SCOPE_PRETRIGGER, MC_ERR_SCOPE_STATE,
    /* configuration files (layout 1.8) */
    MC_ERR_CONFIG_KIND,    MC_ERR_CONFIG_FILE,
    /* G-code programs */
    MC_ERR_GCODE,
    /* leadscrew compensation (layout 1.9) */
    MC_ERR_COMP_TABLE,     MC_ERR_COMP_SEQUENCE,   MC_ERR_COMP_ORDER,
    MC_ERR_COMP_BOUND,     MC_ERR_COMP_BUSY,
    /* the handwheel (layout 1.10) */
    MC_ERR_HANDWHEEL_INPUT, MC_ERR_HANDWHEEL_RATIO,
    /* waits with nothing to wait for */
    MC_ERR_NO_MOTION,
    /* gantry axes (layout 1.10) */
    MC_ERR_GANTRY_SLAVE,   MC_ERR_GANTRY_IN_USE,   MC_ERR_GANTRY_AXES,
    MC_ERR_GANTRY_GAINS,   MC_ERR_GANTRY_STATE,
    /* group homing (layout 1.11) */
    MC_ERR_HOME_AXIS,      MC_ERR_HOME_TWICE,      MC_ERR_HOME_STAGE,
    /* rotary (modulo) axes (layout 1.10) */
    MC_ERR_MODULO_ZERO,    MC_ERR_MODULO_RANGE,    MC_ERR_MODULO_BUSY,
    MC_ERR_MODULO_MOVE,
    /* servo filters and PID+FF (layout 1.11) */
    MC_ERR_FILTER_KIND,    MC_ERR_FILTER_FREQ,     MC_ERR_FILTER_PARAM,
    MC_ERR_FILTER_UNSTABLE, MC_ERR_PIDFF_GAINS,
    /* analog I/O and the path-speed output (layout 1.11) */
    MC_ERR_ANALOG_CHANNEL, MC_ERR_ANALOG_FILTER,   MC_ERR_ANALOG_THRESHOLD,
    MC_ERR_PSO_CONFIG,     MC_ERR_PSO_GROUP,
    /* the sync bus and timed commands (layout 1.12) */
    MC_ERR_TICK_PASSED,    MC_ERR_TIMED_FULL,      MC_ERR_TIMED_ALONE,
    MC_ERR_TICK_FAR,       MC_ERR_COMMIT_LATE,     MC_ERR_NOT_MASTER,
    MC_ERR_NOT_COMMITTED,  MC_ERR_SYNC_LOST,       MC_ERR_TIMED_REFUSED,
    MC_ERR_TIMED_CANCELLED,
    MC_ERR_ARC_NORMAL,     MC_ERR_ARC_AXES,        MC_ERR_ARC_OFF_PLANE,
    /* normal-vector arcs in the move queue (layout 1.13) */
    MC_ERR_ARC_PIECE,
    /* the frequency response (layout 1.12) */
    MC_ERR_FREQ_RANGE,     MC_ERR_FREQ_AMPLITUDE,  MC_ERR_FREQ_LIMITS,
    MC_ERR_FREQ_BUSY,
    /* a compare channel on the PSO's PWM output (layout 1.12) */
    MC_ERR_PSO_OUTPUT,
    /* compare on a rotary axis (layout 1.13) */
    MC_ERR_COMPARE_TURN,
    /* paths across cards (layout 1.14) */
    MC_ERR_PATH_DIMS,      MC_ERR_PATH_MORE,       MC_ERR_PATH_RELEASE,
    /* listing and opening by name or serial */
    MC_ERR_AMBIGUOUS,
    /* the ABI's own */
    MC_ERR_BAD_HANDLE,     MC_ERR_NULL_POINTER,    MC_ERR_BUFFER_TOO_SMALL,
    MC_ERR_PANIC,
};
#define NCODES (sizeof ALL_CODES / sizeof ALL_CODES[0])

/* Codes this program does not return. Some no emulated card can provoke from C: a card with
   another layout, one that corrupts the protocol, a full command ring, a command the library
   never sends (NURBS data out of sequence, a command past its deadline: mc_send_raw sends no
   deadline), a plan the card's own check refuses (no input
   reaches it through a correct planner), a limit switch (an input only the
   Rust fault injector presses), another user's card, a path segment id that is not an
   integer in 0..2^32-1 (ids are uint32_t in C), a configuration read-back of a block kind
   the card does not know. The Rust tests cover the SDK side of
   those; here they are only checked to exist and be described. The others are returned by
   the programs named (the Rust test checks that every code is expected by some program or
   listed as not provokable). */
static const mc_result NOT_PROVOKED[] = {
    /* not provokable from C */
    MC_ERR_VERSION_MISMATCH, MC_ERR_PROTOCOL, MC_ERR_RING_FULL,
    MC_ERR_NURBS_SEQUENCE, MC_ERR_HARD_LIMIT, MC_ERR_PLAN_CHECK, MC_ERR_EXPIRED,
    MC_ERR_PERMISSION_DENIED, MC_ERR_PATH_ID,
    /* dead_card.c (a card process killed, then stopped) */
    MC_ERR_CARD_GONE, MC_ERR_NOT_RESPONDING,
    /* list.c (two card-emu cards of one serial) */
    MC_ERR_AMBIGUOUS,
    /* lifecycle.c (waits in other threads) */
    MC_ERR_CLOSED, MC_ERR_CANCELLED,
    /* groups.c */
    MC_ERR_BAD_GROUP, MC_ERR_AXIS_IN_OTHER_GROUP, MC_ERR_AXIS_GROUPED, MC_ERR_ZERO_LENGTH_ARC,
    MC_ERR_CENTRE_NOT_EQUIDISTANT, MC_ERR_RADIUS_TOO_SMALL, MC_ERR_COLLINEAR_POINTS,
    MC_ERR_INCOMPATIBLE_MODE, MC_ERR_GROUP_DISABLED, MC_ERR_FILTER_BUSY, MC_ERR_NURBS_DEGREE,
    MC_ERR_NURBS_DIMENSION, MC_ERR_NURBS_CTRL_COUNT, MC_ERR_NURBS_KNOT_COUNT,
    MC_ERR_NURBS_KNOTS_DECREASING, MC_ERR_NURBS_KNOT_MULTIPLICITY, MC_ERR_NURBS_NOT_CLAMPED,
    MC_ERR_NURBS_WEIGHT, MC_ERR_NURBS_POINT, MC_ERR_NURBS_START, MC_ERR_NURBS_ZERO_LENGTH,
    MC_ERR_NURBS_KNOT,
    /* safety.c (raw commands: a detach of this program's session and of another, an unknown
       opcode) */
    MC_ERR_WATCHDOG_TRIPPED, MC_ERR_ESTOP_ACTIVE, MC_ERR_SOFT_LIMIT, MC_ERR_CAUSE_ACTIVE,
    MC_ERR_WATCHDOG_TIMEOUT, MC_ERR_BAD_CATEGORY, MC_ERR_STOP_TOO_LONG, MC_ERR_NO_SESSION,
    MC_ERR_SESSION, MC_ERR_UNKNOWN_COMMAND,
    /* busy.c (a card served by another process), panic.c (a test build's panic hook) */
    MC_ERR_BUSY, MC_ERR_PANIC,
    /* homing.c (and machine.c) */
    MC_ERR_OVERRIDE_RANGE, MC_ERR_HOMING_METHOD, MC_ERR_AXIS_HOMING, MC_ERR_HOMING_FAILED,
    /* path.c */
    MC_ERR_PATH_MODE, MC_ERR_PATH_ZERO_LENGTH, MC_ERR_PATH_OUTPUT, MC_ERR_PATH_BUSY,
    MC_ERR_PATH_CURVE, MC_ERR_ARC_NORMAL, MC_ERR_ARC_AXES, MC_ERR_ARC_OFF_PLANE,
    /* normal_arc.c (a piece of the move sent raw) */
    MC_ERR_ARC_PIECE,
    /* compare.c, probe.c */
    MC_ERR_IO_CONFIG, MC_ERR_IO_CHANNEL, MC_ERR_COMPARE_MODE, MC_ERR_COMPARE_FULL,
    MC_ERR_COMPARE_ORDER, MC_ERR_COMPARE_BUSY, MC_ERR_PROBE_INPUT,
    /* gearing.c, pvt.c, cam.c */
    MC_ERR_GEAR_RATIO, MC_ERR_SYNC_MASTER, MC_ERR_PVT_TIME, MC_ERR_PVT_LIMIT, MC_ERR_PVT_SEQUENCE,
    MC_ERR_CAM_TABLE,
    /* not provokable from C: the ABI loads a table in order (cam data out of sequence) */
    MC_ERR_CAM_SEQUENCE,
    /* scope.c */
    MC_ERR_SCOPE_SIGNAL, MC_ERR_SCOPE_CHANNELS, MC_ERR_SCOPE_DIVIDER, MC_ERR_SCOPE_TRIGGER,
    MC_ERR_SCOPE_PRETRIGGER, MC_ERR_SCOPE_STATE,
    /* not provokable from C: the ABI reads back only the block kinds the card knows */
    MC_ERR_CONFIG_KIND,
    /* config.c (a file that does not validate, one that cannot be read) */
    MC_ERR_CONFIG_FILE, MC_ERR_IO,
    /* gcode.c (a program with a wrong line) */
    MC_ERR_GCODE,
    /* comp.c */
    MC_ERR_COMP_TABLE, MC_ERR_COMP_ORDER, MC_ERR_COMP_BOUND, MC_ERR_COMP_BUSY,
    /* not provokable from C: the ABI sends a compensation table in order */
    MC_ERR_COMP_SEQUENCE,
    /* handwheel.c */
    MC_ERR_HANDWHEEL_INPUT, MC_ERR_HANDWHEEL_RATIO,
    /* rotary.c */
    MC_ERR_MODULO_ZERO, MC_ERR_MODULO_RANGE, MC_ERR_MODULO_BUSY, MC_ERR_MODULO_MOVE,
    MC_ERR_COMPARE_TURN,
    /* servo.c */
    MC_ERR_FILTER_KIND, MC_ERR_FILTER_FREQ, MC_ERR_FILTER_PARAM, MC_ERR_FILTER_UNSTABLE,
    MC_ERR_PIDFF_GAINS,
    /* analog.c */
    MC_ERR_ANALOG_CHANNEL, MC_ERR_ANALOG_FILTER, MC_ERR_ANALOG_THRESHOLD, MC_ERR_PSO_CONFIG,
    MC_ERR_PSO_GROUP, MC_ERR_PSO_OUTPUT,
    /* sync.c */
    MC_ERR_TICK_PASSED, MC_ERR_TIMED_FULL, MC_ERR_TIMED_ALONE, MC_ERR_TICK_FAR,
    MC_ERR_COMMIT_LATE, MC_ERR_NOT_MASTER, MC_ERR_NOT_COMMITTED, MC_ERR_TIMED_CANCELLED,
    /* not provokable from C: a lost master needs a killed card-emu process; the command of a
       refused timing is never waited for (the timing's refusal is the error) */
    MC_ERR_SYNC_LOST, MC_ERR_TIMED_REFUSED,
    /* freq.c */
    MC_ERR_FREQ_RANGE, MC_ERR_FREQ_AMPLITUDE, MC_ERR_FREQ_LIMITS,
    /* not provokable from C: mc_axis_freq_response returns once its sweep has ended (a move
       during a sweep: tests/freq.rs) */
    MC_ERR_FREQ_BUSY,
    /* set_path.c (staging entries sent raw) */
    MC_ERR_PATH_DIMS, MC_ERR_PATH_MORE, MC_ERR_PATH_RELEASE,
};

static void result_strings(void) {
    for (size_t i = 0; i < NCODES; i++) {
        const char *d = mc_result_str(ALL_CODES[i]);
        ASSERT(d && *d && strcmp(d, mc_result_str(12345)) != 0, "code %d undescribed",
               (int)ALL_CODES[i]);
        for (size_t j = 0; j < i; j++) {
            ASSERT(ALL_CODES[i] != ALL_CODES[j] && strcmp(d, mc_result_str(ALL_CODES[j])) != 0,
                   "codes %d and %d collide", (int)ALL_CODES[i], (int)ALL_CODES[j]);
        }
        ASSERT(ALL_CODES[i] < 0, "code %d is not negative", (int)ALL_CODES[i]);
    }
    ASSERT(strcmp(mc_result_str(MC_OK), "success") == 0, "MC_OK: %s", mc_result_str(MC_OK));
    ASSERT(strcmp(mc_result_str(12345), "unknown result code") == 0, "12345");
    ASSERT(strcmp(mc_result_str(-12345), "unknown result code") == 0, "-12345");
    checks += NCODES + 3;
}

static void buffers(void) {
    /* Size query, too small (buffer untouched), exact fit. */
    char version[64];
    size_t needed = 0;
    EXPECT(mc_version_string(NULL, 0, &needed), MC_ERR_BUFFER_TOO_SMALL);
    expect_in_message("bytes");
    ASSERT(needed >= 6, "needed %zu", needed);
    char small[4] = {'x', 'x', 'x', 'x'};
    size_t needed2 = 0;
    EXPECT(mc_version_string(small, sizeof small, &needed2), MC_ERR_BUFFER_TOO_SMALL);
    ASSERT(needed2 == needed && memcmp(small, "xxxx", 4) == 0, "small buffer written");
    EXPECT(mc_version_string(version, needed, &needed2), MC_OK);
    ASSERT(strlen(version) + 1 == needed, "version \"%s\" needed %zu", version, needed);
    EXPECT(mc_version_string(NULL, 8, &needed2), MC_ERR_NULL_POINTER);
    EXPECT(mc_version_string(version, sizeof version, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_version(NULL), MC_ERR_NULL_POINTER);

    /* The last error message: a too-small buffer does not replace the message it reports. */
    EXPECT(mc_get_tick(4242, NULL), MC_ERR_NULL_POINTER);
    char msg[8] = "-------";
    size_t msg_needed = 0;
    ASSERT(mc_last_error_message(msg, sizeof msg, &msg_needed) == MC_ERR_BUFFER_TOO_SMALL,
           "8 bytes were enough");
    ASSERT(strcmp(msg, "-------") == 0 && msg_needed == strlen("tick is NULL") + 1,
           "msg \"%s\", needed %zu", msg, msg_needed);
    ASSERT(mc_last_error_message(NULL, 0, &msg_needed) == MC_ERR_BUFFER_TOO_SMALL,
           "size query");
    ASSERT(mc_last_error_message(NULL, 5, &msg_needed) == MC_ERR_NULL_POINTER, "NULL buf");
    ASSERT(mc_last_error_message(msg, sizeof msg, NULL) == MC_ERR_NULL_POINTER, "NULL needed");
    char big[64];
    ASSERT(mc_last_error_message(big, sizeof big, &msg_needed) == MC_OK, "big buffer");
    ASSERT(strcmp(big, "tick is NULL") == 0, "message is now \"%s\"", big);
    checks += 6;
}

static void opening(void) {
    mc_card c = 777;
    EXPECT(mc_open(NULL, &c), MC_ERR_NULL_POINTER);
    EXPECT(mc_open("sim", NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_open("bogus", &c), MC_ERR_BAD_URI);
    expect_in_message("bogus");
    EXPECT(mc_open("", &c), MC_ERR_BAD_URI);
    EXPECT(mc_open("\xff\xfe", &c), MC_ERR_BAD_URI); /* not UTF-8 */
    EXPECT(mc_open("uio:/dev/uio987", &c), MC_ERR_NOT_FOUND);
    EXPECT(mc_open("pci:0000:fe:1f.7", &c), MC_ERR_NOT_FOUND);
    EXPECT(mc_open("emu:nobody-serves-this-name", &c), MC_ERR_NOT_FOUND);
    EXPECT(mc_open_sim_stepped(-1, 10000, &c), MC_ERR_BAD_CONFIG);
    EXPECT(mc_open_sim_stepped(2, 10000, NULL), MC_ERR_NULL_POINTER);
    ASSERT(c == 777, "handle written by a failed open");
}

/* Every call that takes a card, with handle h: all must give MC_ERR_BAD_HANDLE. */
static void all_calls_bad_handle(mc_card h) {
    mc_card_info info = {.axes = 99};
    mc_status st = {.state = 99};
    mc_axis_settings cfg;
    mc_move_limits lim;
    mc_motion m = {0, 1};
    mc_event ev = {.kind = 99};
    uint64_t u64 = 99;
    uint32_t u32 = 99;
    size_t n = 99;
    double d = 99.0;
    int fd = 99;
    mc_safety_status ss = {.protocol_errors = 99};
    mc_safety_settings saf;
    mc_stop_info si = {.reason = 99};
    CHECK(mc_axis_settings_default(&cfg));
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    CHECK(mc_safety_settings_default(&saf));
    EXPECT(mc_get_info(h, &info), MC_ERR_BAD_HANDLE);
    EXPECT(mc_get_tick(h, &u64), MC_ERR_BAD_HANDLE);
    EXPECT(mc_ping(h), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_servo_rate(h, 2000), MC_ERR_BAD_HANDLE);
    EXPECT(mc_events_lost(h, &u64, &u32), MC_ERR_BAD_HANDLE);
    EXPECT(mc_configure(h, 0, &cfg), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_scale(h, 0, 2.0), MC_ERR_BAD_HANDLE);
    EXPECT(mc_enable(h, 0), MC_ERR_BAD_HANDLE);
    EXPECT(mc_disable(h, 0), MC_ERR_BAD_HANDLE);
    EXPECT(mc_move_absolute(h, 0, 1.0, &lim, &m), MC_ERR_BAD_HANDLE);
    EXPECT(mc_move_relative(h, 0, 1.0, &lim, &m), MC_ERR_BAD_HANDLE);
    EXPECT(mc_halt(h, 0, 1e6, 1e7, &m), MC_ERR_BAD_HANDLE);
    EXPECT(mc_stop(h, 0, 1e6, 1e7, &m), MC_ERR_BAD_HANDLE);
    EXPECT(mc_release_stop(h, 0), MC_ERR_BAD_HANDLE);
    EXPECT(mc_reset(h, 0), MC_ERR_BAD_HANDLE);
    EXPECT(mc_get_status(h, 0, &st), MC_ERR_BAD_HANDLE);
    EXPECT(mc_motion_wait(h, m, 0, &d), MC_ERR_BAD_HANDLE);
    EXPECT(mc_wait_done(h, 0, 0, &d), MC_ERR_BAD_HANDLE);
    EXPECT(mc_wait_event(h, 0, &ev), MC_ERR_BAD_HANDLE);
    EXPECT(mc_irq_fd(h, &fd), MC_ERR_BAD_HANDLE);
    EXPECT(mc_poll_events(h, &n), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_event_callback(h, NULL, NULL), MC_ERR_BAD_HANDLE);
    EXPECT(mc_dispatch_events(h, 0, &n), MC_ERR_BAD_HANDLE);
    EXPECT(mc_sim_step(h, 1), MC_ERR_BAD_HANDLE);
    EXPECT(mc_sim_time(h, &d), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_heartbeat(h, 1), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_watchdog_timeout(h, 5000), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_estop_input_category(h, MC_STOP_CATEGORY_1), MC_ERR_BAD_HANDLE);
    EXPECT(mc_estop(h, MC_STOP_CATEGORY_0), MC_ERR_BAD_HANDLE);
    EXPECT(mc_reset_faults(h), MC_ERR_BAD_HANDLE);
    EXPECT(mc_get_safety_status(h, &ss), MC_ERR_BAD_HANDLE);
    EXPECT(mc_set_max_stop_time(h, 500000), MC_ERR_BAD_HANDLE);
    EXPECT(mc_cancel_waits(h), MC_ERR_BAD_HANDLE);
    EXPECT(mc_inherited_stops(h, &u32), MC_ERR_BAD_HANDLE);
    const uint32_t ax0 = 0;
    EXPECT(mc_get_statuses(h, &ax0, 1, &st), MC_ERR_BAD_HANDLE);
    EXPECT(mc_configure_safety(h, 0, &saf), MC_ERR_BAD_HANDLE);
    EXPECT(mc_get_stop_info(h, 0, &si), MC_ERR_BAD_HANDLE);
    EXPECT(mc_send_raw(h, MC_OP_NOP, 0, 0, NULL, 0, &d), MC_ERR_BAD_HANDLE);
    EXPECT(mc_close(h), MC_ERR_BAD_HANDLE);
    ASSERT(info.axes == 99 && st.state == 99 && ev.kind == 99 && u64 == 99 && u32 == 99 &&
               n == 99 && d == 99.0 && fd == 99 && m.seq == 1 && ss.protocol_errors == 99 &&
               si.reason == 99,
           "an output was written by a failed call");
}

static void handles(void) {
    all_calls_bad_handle(0);
    expect_in_message("card handle 0 ");
    all_calls_bad_handle(12345);
    all_calls_bad_handle(0xFFFFFFFFu);

    mc_card a = 0;
    CHECK(mc_open_sim_stepped(1, 1000, &a));
    CHECK(mc_close(a));
    all_calls_bad_handle(a); /* closed */
    EXPECT(mc_close(a), MC_ERR_BAD_HANDLE); /* double close: harmless */
    /* A new card may take the closed one's slot: the old handle still means nothing. */
    mc_card b = 0;
    CHECK(mc_open_sim_stepped(1, 1000, &b));
    ASSERT(b != a, "a closed handle came back: %u", a);
    all_calls_bad_handle(a);
    mc_card_info info;
    CHECK(mc_get_info(b, &info));
    ASSERT(info.axes == 1 && info.servo_rate_hz == 1000, "axes %u rate %u", info.axes,
           info.servo_rate_hz);
    CHECK(mc_close(b));
}

static void null_outputs(mc_card c) {
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    mc_motion m = {0, 0};
    uint64_t u64;
    uint32_t u32;
    EXPECT(mc_get_info(c, NULL), MC_ERR_NULL_POINTER);
    expect_in_message("info is NULL");
    EXPECT(mc_get_tick(c, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_events_lost(c, NULL, &u32), MC_ERR_NULL_POINTER);
    EXPECT(mc_events_lost(c, &u64, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_axis_settings_default(NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_configure(c, 0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_move_limits_symmetric(1.0, 1.0, 1.0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_move_absolute(c, 0, 1.0, NULL, &m), MC_ERR_NULL_POINTER);
    expect_in_message("limits is NULL");
    EXPECT(mc_move_relative(c, 0, 1.0, NULL, &m), MC_ERR_NULL_POINTER);
    EXPECT(mc_get_status(c, 0, NULL), MC_ERR_NULL_POINTER);
    /* The batch read: its arrays, their length, its axes. */
    const uint32_t both[2] = {1, 0}, wrong[2] = {0, 9};
    mc_status two[2];
    two[0].state = 99;
    EXPECT(mc_get_statuses(c, both, 2, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_get_statuses(c, NULL, 2, two), MC_ERR_NULL_POINTER);
    EXPECT(mc_get_statuses(c, both, 0, two), MC_ERR_BAD_AXIS);
    EXPECT(mc_get_statuses(c, both, 9, two), MC_ERR_BAD_AXIS);
    EXPECT(mc_get_statuses(c, wrong, 2, two), MC_ERR_BAD_AXIS);
    ASSERT(two[0].state == 99, "statuses written by a failed call");
    mc_status one;
    CHECK(mc_get_statuses(c, both, 2, two));
    CHECK(mc_get_status(c, 1, &one));
    ASSERT(two[0].raw.tick == one.raw.tick && two[0].state == one.state &&
               two[1].raw.tick == one.raw.tick,
           "batch and single reads of one tick differ");
    EXPECT(mc_inherited_stops(c, NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_inherited_stops(c, &u32));
    ASSERT(u32 == 0, "a fresh card inherited %u stops", u32);
    /* (A wait's position is optional: below.) */
    EXPECT(mc_wait_event(c, 0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_irq_fd(c, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_poll_events(c, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_dispatch_events(c, 0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_sim_time(c, NULL), MC_ERR_NULL_POINTER);
    /* Optional outputs: a move's motion may be NULL. */
    EXPECT(mc_enable(c, 1), MC_OK);
    EXPECT(mc_move_relative(c, 1, 10.0, &lim, NULL), MC_OK);
    double at = 0.0;
    EXPECT(mc_wait_done(c, 1, 1000, &at), MC_OK);
    ASSERT(fabs(at - 10.0) <= 1.0, "done at %f", at);
    /* So may a wait's position. The card is stepped: its time advances only in waits, so the
       axis is where it is because these waits waited. */
    mc_status st;
    EXPECT(mc_move_relative(c, 1, 1000.0, &lim, NULL), MC_OK);
    EXPECT(mc_wait_done(c, 1, 1000, NULL), MC_OK);
    CHECK(mc_get_status(c, 1, &st));
    ASSERT(st.state == MC_AXIS_STATE_STANDSTILL && fabs(st.actual_position - 1010.0) <= 1.0,
           "after a wait without position: state %u at %f", st.state, st.actual_position);
    mc_motion back;
    EXPECT(mc_move_relative(c, 1, -1000.0, &lim, &back), MC_OK);
    EXPECT(mc_motion_wait(c, back, 1000, NULL), MC_OK);
    CHECK(mc_get_status(c, 1, &st));
    ASSERT(st.state == MC_AXIS_STATE_STANDSTILL && fabs(st.actual_position - 10.0) <= 1.0,
           "after a wait without position: state %u at %f", st.state, st.actual_position);
    /* With or without a position, a wait checks its handle and times out alike. */
    EXPECT(mc_motion_wait(c, m, 0, NULL), MC_ERR_BAD_HANDLE);
    EXPECT(mc_wait_done(c, 0, 0, NULL), MC_ERR_NO_MOTION);
    mc_motion far;
    EXPECT(mc_move_relative(c, 1, 1e6, &lim, &far), MC_OK);
    EXPECT(mc_motion_wait(c, far, 5, NULL), MC_ERR_TIMEOUT);
    EXPECT(mc_wait_done(c, 1, 5, NULL), MC_ERR_TIMEOUT);
    EXPECT(mc_disable(c, 1), MC_OK);
    EXPECT(mc_motion_wait(c, far, 10, NULL), MC_ERR_ABORTED);
}

static void arguments(mc_card c) {
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    mc_motion m = {77, 77};
    mc_status st = {.state = 99};

    /* Axes: the card has 2. */
    EXPECT(mc_enable(c, 2), MC_ERR_BAD_AXIS);
    expect_in_message("axis 2 does not exist");
    EXPECT(mc_get_status(c, 99, &st), MC_ERR_BAD_AXIS);
    EXPECT(mc_set_scale(c, 0xFFFFFFFFu, 1.0), MC_ERR_BAD_AXIS);
    EXPECT(mc_move_absolute(c, 7, 1.0, &lim, &m), MC_ERR_BAD_AXIS);
    ASSERT(st.state == 99 && m.seq == 77, "output written by a failed call");

    /* A disabled axis refuses moves; the card says so. */
    EXPECT(mc_move_absolute(c, 0, 100.0, &lim, &m), MC_ERR_AXIS_DISABLED);
    ASSERT(m.seq == 77, "motion written by a refused move");
    EXPECT(mc_enable(c, 0), MC_OK);

    /* NaN and infinity, caught before the card sees them. */
    EXPECT(mc_move_absolute(c, 0, NAN, &lim, &m), MC_ERR_NOT_FINITE);
    expect_in_message("target position is not a finite number");
    EXPECT(mc_move_relative(c, 0, INFINITY, &lim, &m), MC_ERR_NOT_FINITE);
    mc_move_limits bad = lim;
    bad.velocity = NAN;
    EXPECT(mc_move_absolute(c, 0, 100.0, &bad, &m), MC_ERR_NOT_FINITE);
    bad = lim;
    bad.jerk[3] = INFINITY;
    EXPECT(mc_move_absolute(c, 0, 100.0, &bad, &m), MC_ERR_NOT_FINITE);
    EXPECT(mc_halt(c, 0, NAN, 1e7, &m), MC_ERR_NOT_FINITE);
    EXPECT(mc_stop(c, 0, 1e6, NAN, &m), MC_ERR_NOT_FINITE);
    EXPECT(mc_set_scale(c, 0, NAN), MC_ERR_NOT_FINITE);
    mc_axis_settings cfg;
    CHECK(mc_axis_settings_default(&cfg));
    cfg.ffpiv.kp = NAN;
    EXPECT(mc_configure(c, 0, &cfg), MC_ERR_NOT_FINITE);

    /* Zero and negative limits. */
    bad = lim;
    bad.deceleration = 0.0;
    EXPECT(mc_move_relative(c, 0, 100.0, &bad, &m), MC_ERR_NON_POSITIVE_LIMIT);
    bad = lim;
    bad.acceleration = -1.0;
    EXPECT(mc_move_relative(c, 0, 100.0, &bad, &m), MC_ERR_NON_POSITIVE_LIMIT);
    EXPECT(mc_halt(c, 0, -1.0, 1e7, &m), MC_ERR_NON_POSITIVE_LIMIT);
    /* Zero, subnormal and absurd scales (a negative one is a direction). */
    EXPECT(mc_set_scale(c, 0, 0.0), MC_ERR_BAD_CONFIG);
    EXPECT(mc_set_scale(c, 0, 1e-320), MC_ERR_BAD_CONFIG);
    expect_in_message("|scale| must lie in");
    EXPECT(mc_set_scale(c, 0, 1e300), MC_ERR_BAD_CONFIG);
    ASSERT(m.seq == 77, "motion written by a refused call");

    /* Limits outside what the card accepts: subnormal, absurdly small or large. The card
       refuses them (each move and each stop). */
    bad = lim;
    bad.jerk[0] = 1e-300;
    EXPECT(mc_move_relative(c, 0, 100.0, &bad, &m), MC_ERR_LIMIT_RANGE);
    expect_in_message("outside the range the card accepts");
    bad = lim;
    bad.acceleration = 5e-324;
    EXPECT(mc_move_relative(c, 0, 100.0, &bad, &m), MC_ERR_LIMIT_RANGE);
    bad = lim;
    bad.velocity = 1e300;
    EXPECT(mc_move_relative(c, 0, 100.0, &bad, &m), MC_ERR_LIMIT_RANGE);
    EXPECT(mc_halt(c, 0, 5e6, 1e-300, &m), MC_ERR_LIMIT_RANGE);
    ASSERT(m.seq == 77, "motion written by a refused call");

    /* Values the card refuses. */
    cfg.ffpiv.kp = -3.0;
    EXPECT(mc_configure(c, 0, &cfg), MC_ERR_BAD_CONFIG);
    expect_in_message("card refused");
    EXPECT(mc_move_absolute(c, 0, 1e17, &lim, &m), MC_ERR_OUT_OF_RANGE);
    mc_move_limits crawl = lim;
    for (int i = 0; i < 4; i++) crawl.jerk[i] = 1e-12;
    EXPECT(mc_move_absolute(c, 0, 1e9, &crawl, &m), MC_ERR_INFEASIBLE);
    EXPECT(mc_set_servo_rate(c, 50), MC_ERR_BAD_CONFIG);
    expect_in_message("on the card"); /* a card-wide command names the card, not an axis */
    EXPECT(mc_set_servo_rate(c, 2000), MC_ERR_AXES_ENABLED);

    /* Nothing moved. */
    CHECK(mc_get_status(c, 0, &st));
    ASSERT(st.state == MC_AXIS_STATE_STANDSTILL && st.raw.move_count == 0,
           "state %u, %u moves after refused ones", st.state, st.raw.move_count);
}

static void states(mc_card c) {
    /* Axis 0 is enabled, at standstill, no motion started yet. */
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    double at = -1.0;
    EXPECT(mc_wait_done(c, 0, 0, &at), MC_ERR_NO_MOTION);
    ASSERT(at == -1.0, "position written by a wait with nothing to wait for");
    expect_in_message("nothing to wait for on axis 0");
    EXPECT(mc_reset(c, 0), MC_ERR_INVALID_STATE); /* only from ErrorStop */
    EXPECT(mc_release_stop(c, 0), MC_ERR_INVALID_STATE);
    mc_motion unknown = {0, 999999};
    EXPECT(mc_motion_wait(c, unknown, 0, &at), MC_ERR_BAD_HANDLE);
    expect_in_message("no motion with seq 999999");

    /* A long move: a short wait times out, a second move takes over (PLCopen Aborting, layout
       1.5) and aborts it, a halt aborts that one. */
    mc_motion long_move, halt, again;
    EXPECT(mc_move_absolute(c, 0, 1e6, &lim, &long_move), MC_OK);
    EXPECT(mc_motion_wait(c, long_move, 5, &at), MC_ERR_TIMEOUT);
    ASSERT(at == -1.0, "position written by a timed-out wait");
    EXPECT(mc_move_absolute(c, 0, 9e5, &lim, &again), MC_OK);
    EXPECT(mc_motion_wait(c, long_move, 0, &at), MC_ERR_ABORTED);
    expect_in_message("aborted by MoveAbsolute");
    mc_status st;
    CHECK(mc_get_status(c, 0, &st));
    ASSERT(st.state == MC_AXIS_STATE_DISCRETE_MOTION, "state %u", st.state);
    EXPECT(mc_halt(c, 0, 5e5, 2e7, &halt), MC_OK);
    EXPECT(mc_motion_wait(c, again, 0, &at), MC_ERR_ABORTED);
    expect_in_message("aborted by Halt");
    EXPECT(mc_motion_wait(c, halt, 5000, &at), MC_OK);
    CHECK(mc_get_status(c, 0, &st));
    ASSERT(st.state == MC_AXIS_STATE_STANDSTILL && fabs(at - st.raw.target) <= 1.0 &&
               at < 1e6,
           "halted at %f, state %u", at, st.state);
    EXPECT(mc_motion_wait(c, halt, 0, &at), MC_OK); /* a motion can be waited for again */

    /* Stop holds Stopping: moves and halts refused until released. */
    mc_motion stop;
    EXPECT(mc_move_relative(c, 0, 5e5, &lim, NULL), MC_OK);
    EXPECT(mc_sim_step(c, 2000), MC_OK);
    EXPECT(mc_stop(c, 0, 1e6, 5e7, &stop), MC_OK);
    EXPECT(mc_motion_wait(c, stop, 5000, &at), MC_OK);
    EXPECT(mc_move_relative(c, 0, 10.0, &lim, NULL), MC_ERR_INVALID_STATE);
    EXPECT(mc_halt(c, 0, 1e6, 1e7, NULL), MC_ERR_INVALID_STATE);
    EXPECT(mc_release_stop(c, 0), MC_OK);
    EXPECT(mc_sim_step(c, 1), MC_OK);
    CHECK(mc_get_status(c, 0, &st));
    ASSERT(st.state == MC_AXIS_STATE_STANDSTILL, "state %u after release", st.state);

    /* Power off mid-move aborts the motion. */
    mc_motion m;
    EXPECT(mc_move_relative(c, 0, 5e5, &lim, &m), MC_OK);
    EXPECT(mc_sim_step(c, 500), MC_OK);
    EXPECT(mc_disable(c, 0), MC_OK);
    EXPECT(mc_motion_wait(c, m, 10, &at), MC_ERR_ABORTED);
    expect_in_message("PowerOff");

    /* Events: after draining, a zero wait times out and leaves the output alone. */
    size_t n = 0;
    EXPECT(mc_dispatch_events(c, 0, &n), MC_OK);
    ASSERT(n > 0, "no events were queued");
    mc_event ev = {.kind = 99};
    EXPECT(mc_wait_event(c, 0, &ev), MC_ERR_TIMEOUT);
    ASSERT(ev.kind == 99, "event written by a timed-out wait");
    uint64_t dropped = 9;
    uint32_t lost = 9;
    EXPECT(mc_events_lost(c, &dropped, &lost), MC_OK);
    ASSERT(dropped == 0 && lost == 0, "events lost: %llu, %u", (unsigned long long)dropped, lost);
}

/* The constructors of plain structs: filled on success, untouched on failure. */
static void constructors(void) {
    mc_filter_settings f = {.rapid = {.kind = 99}};
    EXPECT(mc_filter_settings_all(9, 0.03, &f), MC_ERR_BAD_CONFIG);
    expect_in_message("unknown filter kind 9");
    EXPECT(mc_filter_settings_all(MC_FILTER_KIND_LINEAR, 0.03, NULL), MC_ERR_NULL_POINTER);
    ASSERT(f.rapid.kind == 99, "settings written by a failed call");
    EXPECT(mc_filter_settings_all(MC_FILTER_KIND_BELL, 0.04, &f), MC_OK);
    const mc_filter all[3] = {f.rapid, f.cutting, f.jog};
    for (int i = 0; i < 3; i++) {
        ASSERT(all[i].kind == MC_FILTER_KIND_BELL && all[i].tau == 0.04, "filter %d: %u %f", i,
               all[i].kind, all[i].tau);
    }
    mc_path_limits p;
    EXPECT(mc_path_limits_new(1.0, 2.0, 3.0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_path_limits_new(1.0, 2.0, 3.0, &p), MC_OK);
    ASSERT(p.velocity == 1.0 && p.acceleration == 2.0 && p.deceleration == 2.0 && p.jerk == 3.0,
           "path limits %f %f %f %f", p.velocity, p.acceleration, p.deceleration, p.jerk);
    mc_nurbs_feed n;
    EXPECT(mc_nurbs_feed_new(1.0, 2.0, 3.0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_nurbs_feed_new(1.0, 2.0, 3.0, &n), MC_OK);
    ASSERT(n.feed == 1.0 && n.accel == 2.0 && n.jerk == 3.0 && n.chord_tolerance == 0.0 &&
               n.saturation_budget == 0.0,
           "nurbs feed %f %f %f %f %f", n.feed, n.accel, n.jerk, n.chord_tolerance,
           n.saturation_budget);
}

/* Group refusals the groups program does not make: a group enabled while one of its axes moves
   on its own, an arc in a plane the group does not have, a full move queue. */
static void group_refusals(void) {
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    const uint32_t xy[2] = {0, 1};
    for (int i = 0; i < 2; i++) CHECK(mc_enable(c, xy[i]));
    mc_group_settings gs;
    CHECK(mc_group_settings_new(xy, 2, &gs));
    CHECK(mc_group_configure(c, 0, &gs));
    CHECK(mc_move_relative(c, 0, 1e5, &lim, NULL));
    EXPECT(mc_group_enable(c, 0), MC_ERR_AXIS_BUSY);
    expect_in_message("moving on its own");
    CHECK(mc_halt(c, 0, 1e6, 5e7, NULL));
    double at = 0.0;
    CHECK(mc_wait_done(c, 0, 5000, &at));
    EXPECT(mc_group_enable(c, 0), MC_OK);

    const mc_path_limits feed = {50000.0, 5e5, 5e5, 5e7};
    const mc_move_options now = {0}, queued = {.buffered = 1};
    const mc_arc arc = {.mode = MC_ARC_BY_CENTRE, .ccw = 1, .end = {0, 0}, .aux = {-500, 0}};
    mc_group_motion m = {77, 77};
    EXPECT(mc_group_move_circular(c, 0, &arc, MC_ARC_PLANE_YZ, NULL, 0, &feed, &now, &m),
           MC_ERR_AXIS_NOT_IN_GROUP);
    expect_in_message("on group 0"); /* the group, not "axis 0" */
    /* A plane of any two group axes (layout 1.10): one axis twice is the card's refusal, an
       axis beyond the group's two the library's. */
    EXPECT(mc_group_move_circular(c, 0, &arc,
                                  MC_ARC_PLANE_AXES | 1u << MC_ARC_PLANE_U_SHIFT |
                                      1u << MC_ARC_PLANE_V_SHIFT,
                                  NULL, 0, &feed, &now, &m),
           MC_ERR_PLANE_AXES);
    EXPECT(mc_group_move_circular(c, 0, &arc,
                                  MC_ARC_PLANE_AXES | 0u << MC_ARC_PLANE_U_SHIFT |
                                      2u << MC_ARC_PLANE_V_SHIFT,
                                  NULL, 0, &feed, &now, &m),
           MC_ERR_BAD_AXIS);
    /* Refused by the library before anything was sent: the message names the group and the
       card's groups, once (not "group on group 7 not sent: no such group"). */
    mc_group_status gst;
    EXPECT(mc_group_get_status(c, 7, &gst), MC_ERR_BAD_GROUP);
    expect_in_message("group 7 does not exist: the card has 4 groups (0 to 3)");
    {
        char msg[512];
        ASSERT(!strstr(last_error(msg, sizeof msg), "on group"), "message \"%s\"", msg);
    }
    /* The queue holds 32 moves, the running one included (time stands still meanwhile). */
    double t[2] = {1e6, 0.0};
    EXPECT(mc_group_move_linear(c, 0, t, 2, &feed, &now, NULL), MC_OK);
    for (int k = 1; k < 32; k++) {
        t[1] += 1000.0;
        EXPECT(mc_group_move_linear(c, 0, t, 2, &feed, &queued, NULL), MC_OK);
    }
    t[1] += 1000.0;
    EXPECT(mc_group_move_linear(c, 0, t, 2, &feed, &queued, &m), MC_ERR_QUEUE_FULL);
    ASSERT(m.group == 77 && m.seq == 77, "motion written by a refused move");
    CHECK(mc_close(c));
}

/* Gantries (layout 1.10): each refusal with its own code. */
static void gantry_refusals(void) {
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(3, 10000, &c));
    for (uint32_t a = 0; a < 3; a++) CHECK(mc_enable(c, a));
    const mc_gantry_settings s = {.kp = 1e6, .ki = 0.0, .skew_limit = 100.0};
    const uint32_t self[1] = {0}, one[1] = {1};
    EXPECT(mc_gantry_form(c, 0, 0, self, 1, &s, NULL), MC_ERR_GANTRY_AXES);
    const mc_gantry_settings bad = {.kp = -1.0, .ki = 0.0, .skew_limit = 100.0};
    EXPECT(mc_gantry_form(c, 0, 0, one, 1, &bad, NULL), MC_ERR_GANTRY_GAINS);
    mc_gantry_info info;
    EXPECT(mc_gantry_get_info(c, 0, &info), MC_ERR_GANTRY_STATE);
    CHECK(mc_gantry_form(c, 0, 0, one, 1, &s, NULL));
    /* The slave moves only with its master; it cannot join another gantry. */
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    EXPECT(mc_move_relative(c, 1, 1000.0, &lim, NULL), MC_ERR_GANTRY_SLAVE);
    EXPECT(mc_gantry_form(c, 1, 2, one, 1, &s, NULL), MC_ERR_GANTRY_IN_USE);
    CHECK(mc_gantry_dissolve(c, 0));
    EXPECT(mc_gantry_dissolve(c, 0), MC_ERR_GANTRY_STATE);
    CHECK(mc_close(c));
}

/* Group homing (layout 1.11): each refusal of an order with its own code, then the group homed
   in two stages (each axis's boot method: the current position). */
static void group_home_refusals(void) {
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(3, 10000, &c));
    const uint32_t xyz[3] = {0, 1, 2};
    for (int i = 0; i < 3; i++) CHECK(mc_enable(c, xyz[i]));
    mc_group_settings gs;
    CHECK(mc_group_settings_new(xyz, 3, &gs));
    CHECK(mc_group_configure(c, 0, &gs));
    const uint32_t z_then_xy[3] = {2, 0, 1}, sizes[2] = {1, 2};
    EXPECT(mc_group_home(c, 0, z_then_xy, sizes, 2, 5000, NULL), MC_ERR_GROUP_DISABLED);
    CHECK(mc_group_enable(c, 0));
    const uint32_t beyond[1] = {3}, one[1] = {1};
    EXPECT(mc_group_home(c, 0, beyond, one, 1, 5000, NULL), MC_ERR_HOME_AXIS);
    const uint32_t twice[3] = {0, 1, 0}, two_one[2] = {2, 1};
    EXPECT(mc_group_home(c, 0, twice, two_one, 2, 5000, NULL), MC_ERR_HOME_TWICE);
    const uint32_t empty[2] = {1, 0};
    EXPECT(mc_group_home(c, 0, z_then_xy, empty, 2, 5000, NULL), MC_ERR_HOME_STAGE);
    uint32_t run = 0;
    CHECK(mc_group_home(c, 0, z_then_xy, sizes, 2, 5000, &run));
    ASSERT(run == 2, "stages run %u", (unsigned)run);
    CHECK(mc_close(c));
}

static void realtime_card(void) {
    /* Stepping is for stepped cards only. */
    mc_card rt = 0;
    CHECK(mc_open("sim", &rt));
    double t = -1.0;
    EXPECT(mc_sim_step(rt, 10), MC_ERR_UNSUPPORTED);
    expect_in_message("not a stepped sim");
    EXPECT(mc_sim_time(rt, &t), MC_ERR_UNSUPPORTED);
    ASSERT(t == -1.0, "time written by a failed call");
    CHECK(mc_close(rt));
    EXPECT(mc_close(rt), MC_ERR_BAD_HANDLE);
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    result_strings();
    buffers();
    opening();
    handles();
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    null_outputs(c);
    arguments(c);
    states(c);
    CHECK(mc_close(c));
    all_calls_bad_handle(c);
    constructors();
    group_refusals();
    gantry_refusals();
    group_home_refusals();
    realtime_card();

    /* Every code was returned by some call, except those no emulated card can provoke. */
    for (size_t i = 0; i < NCODES; i++) {
        int skip = 0;
        for (size_t j = 0; j < sizeof NOT_PROVOKED / sizeof NOT_PROVOKED[0]; j++) {
            skip |= NOT_PROVOKED[j] == ALL_CODES[i];
        }
        ASSERT(skip || seen[-ALL_CODES[i]], "code %d (%s) never returned", (int)ALL_CODES[i],
               mc_result_str(ALL_CODES[i]));
    }
    printf("%u checks: every error path returned its code, outputs untouched on failure\n",
           checks);
    printf("PASS errors\n");
    return 0;
}
