/*
 * Safety from C: the host watchdog (the heartbeat stopped), an e-stop in categories 1 and 2,
 * a soft limit, a following error, and the session gate (a session ended by a raw detach
 * moves nothing; a raw attach arms the watchdog). Each trips on a stepped emulated card; the program
 * checks the axes' state, stop reason, fault and I/O bits, the card's timing of the stop
 * (mc_get_stop_info), the MC_EVENT_SAFETY_STOP and MC_EVENT_AT_REST events, each safety
 * MC_ERR_ code the card gives while a fault is latched or a move would go beyond a limit,
 * then resets and moves again.
 *
 * MC_ERR_HARD_LIMIT is not provoked here: limit switches are inputs of the emulated machine,
 * which only the Rust fault injector can press (tests/safety.rs covers it).
 *
 * Runs on stepped cards (time advances only in mc_sim_step and in waits), so tick counts are
 * checked exactly. Positions in counts (scale 1). The argument is ignored.
 *
 *     cc -std=c11 safety.c $(pkg-config --cflags --libs motioncard) -lm -o safety && ./safety
 */
#include "expect.h"

#include <math.h>


static const uint32_t AXES = 4;
static const uint32_t RATE = 10000; /* Hz: a tick is 100 us */

static mc_card open_card(void) {
    mc_card c = 0;
    CHECK(mc_open_sim_stepped((int)AXES, RATE, &c));
    return c;
}

static mc_status axis(mc_card c, uint32_t a) {
    mc_status s;
    CHECK(mc_get_status(c, a, &s));
    return s;
}

static mc_safety_status safety(mc_card c) {
    mc_safety_status s;
    CHECK(mc_get_safety_status(c, &s));
    return s;
}

static mc_stop_info stop_info(mc_card c, uint32_t a) {
    mc_stop_info i;
    CHECK(mc_get_stop_info(c, a, &i));
    return i;
}

static int drive_on(mc_status s) { return (s.io & MC_IO_DRIVE_ENABLE) != 0; }

/* Safety events taken from the card, by axis (index 8: card-wide) and stop reason. */
typedef struct {
    unsigned stop[9][32];
    unsigned rest[9][32];
    double stop_value[9][32];
} safety_events;

static void take_events(mc_card c, safety_events *ev) {
    memset(ev, 0, sizeof *ev);
    mc_event e;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        if (e.kind != MC_EVENT_SAFETY_STOP && e.kind != MC_EVENT_AT_REST) continue;
        const unsigned a = e.axis == MC_EVENT_CARD_WIDE ? 8 : e.axis;
        ASSERT(a <= 8 && e.code >= 0 && e.code < 32, "event axis %u code %d", e.axis, e.code);
        if (e.kind == MC_EVENT_SAFETY_STOP) {
            ev->stop[a][e.code]++;
            ev->stop_value[a][e.code] = e.value;
        } else {
            ev->rest[a][e.code]++;
        }
    }
}

/* Step until the axis's drive is off (category 0 and 1 stops end there), at most `max`
   ticks; returns the largest deceleration commanded meanwhile. */
static double step_until_drive_off(mc_card c, uint32_t a, unsigned max) {
    double peak_dec = 0.0;
    for (unsigned n = 0; n < max; n++) {
        mc_status s = axis(c, a);
        if (!drive_on(s)) return peak_dec;
        if (-s.command_acceleration > peak_dec) peak_dec = -s.command_acceleration;
        CHECK(mc_sim_step(c, 1));
    }
    ASSERT(0, "axis %u still powered after %u ticks", a, max);
    return peak_dec;
}

/* Normal stops have their reasons too; the axis's io shows the drive. */
static void normal_stop_reasons(void) {
    mc_card c = open_card();
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    mc_status s = axis(c, 0);
    ASSERT(s.stop_reason == MC_STOP_REASON_NONE && !drive_on(s), "reason %u io %#x",
           s.stop_reason, s.io);
    CHECK(mc_enable(c, 0));
    CHECK(mc_sim_step(c, 1)); /* the card writes its outputs in the servo tick */
    ASSERT(drive_on(axis(c, 0)), "enabled, drive off");
    double at = 0.0;
    CHECK(mc_move_relative(c, 0, 1000.0, &lim, NULL));
    CHECK(mc_wait_done(c, 0, 5000, &at));
    s = axis(c, 0);
    ASSERT(s.stop_reason == MC_STOP_REASON_DONE && s.raw.stop_reason == MC_STOP_REASON_DONE,
           "reason %u", s.stop_reason);
    CHECK(mc_move_relative(c, 0, 1e6, &lim, NULL));
    CHECK(mc_sim_step(c, 1000));
    mc_motion h;
    CHECK(mc_halt(c, 0, 1e6, 5e7, &h));
    CHECK(mc_motion_wait(c, h, 5000, &at));
    ASSERT(axis(c, 0).stop_reason == MC_STOP_REASON_HALT, "reason %u", axis(c, 0).stop_reason);
    mc_stop_info i = stop_info(c, 0);
    ASSERT(i.reason == MC_STOP_REASON_HALT && i.stop_tick == 0 && i.at_rest == 0 &&
               i.rest_tick == 0,
           "no safety stop yet: reason %u stop %llu rest %llu", i.reason,
           (unsigned long long)i.stop_tick, (unsigned long long)i.rest_tick);
    CHECK(mc_disable(c, 0));
    CHECK(mc_sim_step(c, 1));
    s = axis(c, 0);
    ASSERT(s.stop_reason == MC_STOP_REASON_POWER_OFF && !drive_on(s), "reason %u io %#x",
           s.stop_reason, s.io);
    mc_safety_status ss = safety(c);
    ASSERT(ss.watchdog_armed && !ss.watchdog_tripped && !ss.estop_command && !ss.estop_input &&
               ss.protocol_errors == 0,
           "safety status of a healthy card");
    CHECK(mc_close(c));
}

/* The heartbeat stops mid-move: the watchdog trips after its timeout, every enabled axis
   makes a category 1 stop and ends without power; the trip stays latched until reset. */
static void watchdog(void) {
    mc_card c = open_card();
    mc_move_limits fast;
    CHECK(mc_move_limits_symmetric(300000.0, 3e6, 3e8, &fast));
    EXPECT(mc_set_watchdog_timeout(c, 0), MC_ERR_WATCHDOG_TIMEOUT);
    EXPECT(mc_set_watchdog_timeout(c, 1499), MC_ERR_WATCHDOG_TIMEOUT); /* < 1.5 x 1 ms */
    EXPECT(mc_set_watchdog_timeout(c, 1500), MC_OK);
    EXPECT(mc_set_watchdog_timeout(c, 5000), MC_OK);
    const unsigned timeout_ticks = 5000 * RATE / 1000000; /* 50 */

    mc_motion m[2];
    CHECK(mc_enable(c, 0));
    CHECK(mc_enable(c, 3));
    CHECK(mc_move_relative(c, 0, 1e6, &fast, &m[0]));
    CHECK(mc_move_relative(c, 3, -1e6, &fast, &m[1]));
    CHECK(mc_sim_step(c, 3000)); /* cruising */
    ASSERT(axis(c, 0).command_velocity == 300000.0, "v %f", axis(c, 0).command_velocity);
    safety_events ev;
    take_events(c, &ev);

    CHECK(mc_set_heartbeat(c, 0));
    unsigned n = 0;
    mc_safety_status ss;
    do {
        CHECK(mc_sim_step(c, 1));
        n++;
        ss = safety(c);
    } while (!ss.watchdog_tripped && n < 10 * timeout_ticks);
    /* The card last saw the heartbeat the tick before it stopped; it trips the first tick the
       heartbeat is 5 ms old. */
    ASSERT(n == timeout_ticks, "tripped after %u ticks, timeout %u", n, timeout_ticks);
    ASSERT(ss.watchdog_trip_tick - ss.last_heartbeat_tick == timeout_ticks &&
               ss.trip_heartbeat_tick == ss.last_heartbeat_tick,
           "trip at %llu, last heartbeat %llu", (unsigned long long)ss.watchdog_trip_tick,
           (unsigned long long)ss.last_heartbeat_tick);
    double at = 0.0;
    for (int k = 0; k < 2; k++) {
        EXPECT(mc_motion_wait(c, m[k], 0, &at), MC_ERR_ABORTED);
        expect_in_message("watchdog");
    }

    mc_safety_settings def;
    CHECK(mc_safety_settings_default(&def));
    const double peak_dec = step_until_drive_off(c, 0, 20000);
    ASSERT(peak_dec <= def.stop_deceleration * (1 + 1e-9) &&
               peak_dec > 0.9 * def.stop_deceleration,
           "category 1 ramp at %f, stop deceleration %f", peak_dec, def.stop_deceleration);
    step_until_drive_off(c, 3, 20000);
    CHECK(mc_sim_step(c, 10));
    const uint32_t moved[2] = {0, 3};
    for (int k = 0; k < 2; k++) {
        const uint32_t a = moved[k];
        mc_status s = axis(c, a);
        ASSERT(s.state == MC_AXIS_STATE_ERROR_STOP && s.stop_reason == MC_STOP_REASON_WATCHDOG,
               "axis %u state %u reason %u", a, s.state, s.stop_reason);
        ASSERT(s.faults & MC_AXIS_FAULT_WATCHDOG, "axis %u faults %#x", a, s.faults);
        ASSERT(!drive_on(s) && s.dac_volts == 0.0, "axis %u io %#x dac %f", a, s.io,
               s.dac_volts);
        mc_stop_info i = stop_info(c, a);
        ASSERT(i.reason == MC_STOP_REASON_WATCHDOG && i.at_rest == 1 &&
                   i.stop_tick == ss.watchdog_trip_tick && i.rest_tick > i.stop_tick &&
                   i.ramp_time > 0.0,
               "axis %u stop info: reason %u at rest %u, ticks %llu..%llu, ramp %f", a,
               i.reason, i.at_rest, (unsigned long long)i.stop_tick,
               (unsigned long long)i.rest_tick, i.ramp_time);
        /* At rest within the timeout plus the planned ramp (rounded up to whole ticks). */
        const double bound = timeout_ticks + ceil(i.ramp_time * RATE);
        ASSERT((double)(i.rest_tick - ss.last_heartbeat_tick) <= bound,
               "axis %u at rest %llu ticks after the last heartbeat, bound %.0f", a,
               (unsigned long long)(i.rest_tick - ss.last_heartbeat_tick), bound);
    }
    take_events(c, &ev);
    ASSERT(ev.stop[8][MC_STOP_REASON_WATCHDOG] == 1, "card-wide watchdog events: %u",
           ev.stop[8][MC_STOP_REASON_WATCHDOG]);
    for (int k = 0; k < 2; k++) {
        const uint32_t a = moved[k];
        ASSERT(ev.stop[a][MC_STOP_REASON_WATCHDOG] == 1 && ev.rest[a][MC_STOP_REASON_WATCHDOG] == 1,
               "axis %u: %u safety-stop and %u at-rest events", a,
               ev.stop[a][MC_STOP_REASON_WATCHDOG], ev.rest[a][MC_STOP_REASON_WATCHDOG]);
    }

    /* The heartbeat comes back: still latched. Commands that would move are refused. */
    CHECK(mc_set_heartbeat(c, 1));
    CHECK(mc_sim_step(c, 100));
    ASSERT(safety(c).watchdog_tripped, "the trip did not latch");
    EXPECT(mc_enable(c, 1), MC_ERR_WATCHDOG_TRIPPED);
    EXPECT(mc_reset(c, 0), MC_ERR_WATCHDOG_TRIPPED);
    /* A reset without a live heartbeat is refused. */
    CHECK(mc_set_heartbeat(c, 0));
    CHECK(mc_sim_step(c, 100));
    EXPECT(mc_reset_faults(c), MC_ERR_CAUSE_ACTIVE);
    expect_in_message("still present");
    CHECK(mc_set_heartbeat(c, 1));
    CHECK(mc_sim_step(c, 1));
    EXPECT(mc_reset_faults(c), MC_OK);
    ASSERT(!safety(c).watchdog_tripped, "still tripped after the reset");
    for (int k = 0; k < 2; k++) {
        const uint32_t a = moved[k];
        ASSERT(axis(c, a).state == MC_AXIS_STATE_DISABLED, "axis %u state %u", a,
               axis(c, a).state);
        CHECK(mc_enable(c, a));
        CHECK(mc_move_relative(c, a, 1000.0, &fast, NULL));
        CHECK(mc_wait_done(c, a, 1000, &at));
        ASSERT(axis(c, a).stop_reason == MC_STOP_REASON_DONE, "axis %u reason %u", a,
               axis(c, a).stop_reason);
    }
    printf("watchdog: tripped %u ticks after the heartbeat stopped, axis 0 at rest %llu ticks "
           "later, peak deceleration %.0f counts/s^2\n",
           n, (unsigned long long)(stop_info(c, 0).rest_tick - stop_info(c, 0).stop_tick),
           peak_dec);
    CHECK(mc_close(c));
}

/* The host's e-stop: category 1 on moving axes (stop, then power off), category 2 (power
   kept, position held); unknown categories refused. */
static void estop(void) {
    mc_card c = open_card();
    mc_move_limits fast;
    CHECK(mc_move_limits_symmetric(300000.0, 3e6, 3e8, &fast));
    mc_motion m[4];
    for (uint32_t a = 0; a < AXES; a++) {
        CHECK(mc_enable(c, a));
        CHECK(mc_move_relative(c, a, 1e6, &fast, &m[a]));
    }
    CHECK(mc_sim_step(c, 2000));
    safety_events ev;
    take_events(c, &ev);
    EXPECT(mc_estop(c, 3), MC_ERR_BAD_CATEGORY);
    expect_in_message("unknown stop category 3");
    EXPECT(mc_set_estop_input_category(c, 7), MC_ERR_BAD_CATEGORY);
    ASSERT(axis(c, 0).state == MC_AXIS_STATE_DISCRETE_MOTION, "a refused e-stop stopped axis 0");

    EXPECT(mc_estop(c, MC_STOP_CATEGORY_1), MC_OK);
    mc_status s = axis(c, 2);
    ASSERT(s.state == MC_AXIS_STATE_ERROR_STOP && s.stop_reason == MC_STOP_REASON_ESTOP_COMMAND &&
               (s.faults & MC_AXIS_FAULT_ESTOP),
           "state %u reason %u faults %#x", s.state, s.stop_reason, s.faults);
    CHECK(mc_sim_step(c, 1));
    ASSERT(drive_on(axis(c, 2)), "category 1 removed power before the ramp");
    double at = 0.0;
    EXPECT(mc_motion_wait(c, m[2], 0, &at), MC_ERR_ABORTED);
    CHECK(mc_sim_step(c, 10000));
    for (uint32_t a = 0; a < AXES; a++) {
        s = axis(c, a);
        ASSERT(s.state == MC_AXIS_STATE_ERROR_STOP && !drive_on(s) &&
                   s.stop_reason == MC_STOP_REASON_ESTOP_COMMAND,
               "axis %u state %u io %#x reason %u", a, s.state, s.io, s.stop_reason);
        mc_stop_info i = stop_info(c, a);
        ASSERT(i.at_rest && i.rest_tick > i.stop_tick && i.ramp_time > 0.0,
               "axis %u: at rest %u ticks %llu..%llu", a, i.at_rest,
               (unsigned long long)i.stop_tick, (unsigned long long)i.rest_tick);
    }
    mc_safety_status ss = safety(c);
    ASSERT(ss.estop_command && !ss.estop_input && !ss.watchdog_tripped, "e-stop not latched");
    take_events(c, &ev);
    ASSERT(ev.stop[8][MC_STOP_REASON_ESTOP_COMMAND] == 1, "card-wide e-stop events: %u",
           ev.stop[8][MC_STOP_REASON_ESTOP_COMMAND]);
    for (uint32_t a = 0; a < AXES; a++) {
        ASSERT(ev.stop[a][MC_STOP_REASON_ESTOP_COMMAND] == 1 &&
                   ev.rest[a][MC_STOP_REASON_ESTOP_COMMAND] == 1,
               "axis %u: %u safety-stop and %u at-rest events", a,
               ev.stop[a][MC_STOP_REASON_ESTOP_COMMAND], ev.rest[a][MC_STOP_REASON_ESTOP_COMMAND]);
    }
    EXPECT(mc_reset(c, 0), MC_ERR_ESTOP_ACTIVE);
    EXPECT(mc_enable(c, 0), MC_ERR_ESTOP_ACTIVE);
    EXPECT(mc_reset_faults(c), MC_OK);
    ASSERT(!safety(c).estop_command, "e-stop still latched");
    for (uint32_t a = 0; a < AXES; a++) {
        ASSERT(axis(c, a).state == MC_AXIS_STATE_DISABLED, "axis %u state %u", a,
               axis(c, a).state);
    }

    /* Category 2: power kept, position held; after the reset the axes are at standstill. */
    CHECK(mc_enable(c, 1));
    const double held = axis(c, 1).command_position;
    EXPECT(mc_estop(c, MC_STOP_CATEGORY_2), MC_OK);
    CHECK(mc_sim_step(c, 1000));
    s = axis(c, 1);
    ASSERT(s.state == MC_AXIS_STATE_ERROR_STOP && drive_on(s) && s.command_velocity == 0.0 &&
               s.command_position == held && fabs(s.following_error) <= 2.0,
           "category 2: state %u io %#x ferr %f", s.state, s.io, s.following_error);
    EXPECT(mc_reset_faults(c), MC_OK);
    ASSERT(axis(c, 1).state == MC_AXIS_STATE_STANDSTILL, "state %u", axis(c, 1).state);
    /* The input's category (the input itself is the machine's: not pressed from here). */
    EXPECT(mc_set_estop_input_category(c, MC_STOP_CATEGORY_0), MC_OK);
    CHECK(mc_close(c));
    printf("e-stop: category 1 stopped %u axes, category 2 held axis 1 at %.1f\n", AXES, held);
}

/* Soft limits (once the axis is homed): moves beyond are refused; an axis that overshoots is
   stopped there. */
static void soft_limit(void) {
    mc_card c = open_card();
    const uint32_t a = 1;
    mc_safety_settings s;
    CHECK(mc_safety_settings_default(&s));
    ASSERT(!s.soft_limits && s.hard_limits && s.amp_alarm && s.encoder_checks &&
               s.limit_stop == MC_STOP_CATEGORY_1 && s.ferror == 10000.0 &&
               s.min_ferror == 1000.0 && s.stop_deceleration == 5e6,
           "defaults");
    s.soft_limits = 1;
    s.soft_limit_neg = -1000.0;
    s.soft_limit_pos = 1000.0;
    /* Refused settings change nothing. */
    mc_safety_settings bad = s;
    bad.limit_stop = 3;
    EXPECT(mc_configure_safety(c, a, &bad), MC_ERR_BAD_CATEGORY);
    bad = s;
    bad.soft_limit_neg = NAN;
    EXPECT(mc_configure_safety(c, a, &bad), MC_ERR_NOT_FINITE);
    bad = s;
    bad.soft_limit_neg = bad.soft_limit_pos;
    EXPECT(mc_configure_safety(c, a, &bad), MC_ERR_BAD_CONFIG);
    bad = s;
    bad.ferror = bad.min_ferror / 2;
    EXPECT(mc_configure_safety(c, a, &bad), MC_ERR_BAD_CONFIG);
    EXPECT(mc_configure_safety(c, AXES, &s), MC_ERR_BAD_AXIS);
    EXPECT(mc_configure_safety(c, a, NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_configure_safety(c, a, &s));

    CHECK(mc_enable(c, a));
    /* Soft limits hold once the axis is homed: MC_SetPosition where it stands. */
    ASSERT(!(axis(c, a).raw.motion_flags & MC_MOTION_HOMED), "homed at boot");
    CHECK(mc_set_position(c, a, 0.0, MC_SET_POSITION_RELATIVE));
    ASSERT(axis(c, a).raw.motion_flags & MC_MOTION_HOMED, "not homed by mc_set_position");
    mc_move_limits lim, fast;
    CHECK(mc_move_limits_symmetric(10000.0, 1e6, 1e8, &lim));
    CHECK(mc_move_limits_symmetric(50000.0, 1e6, 1e8, &fast));
    mc_motion m = {77, 77};
    EXPECT(mc_move_absolute(c, a, 1000.5, &lim, &m), MC_ERR_SOFT_LIMIT);
    expect_in_message("soft limit");
    EXPECT(mc_move_relative(c, a, -1001.0, &lim, &m), MC_ERR_SOFT_LIMIT);
    ASSERT(m.seq == 77, "motion written by a refused move");
    double at = 0.0;
    CHECK(mc_move_absolute(c, a, 990.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 5000, &at));
    ASSERT(fabs(at - 990.0) <= 1.0, "at %f", at);

    /* A fast move halted far too gently: the stop would end beyond -1000. */
    safety_events ev;
    take_events(c, &ev);
    CHECK(mc_move_absolute(c, a, -990.0, &fast, &m));
    unsigned n = 0;
    while (axis(c, a).actual_position > -800.0 && n++ < 100000) CHECK(mc_sim_step(c, 1));
    CHECK(mc_halt(c, a, 1e3, 1e5, NULL));
    EXPECT(mc_motion_wait(c, m, 0, &at), MC_ERR_ABORTED);
    CHECK(mc_sim_step(c, 20000));
    mc_status st = axis(c, a);
    ASSERT(st.state == MC_AXIS_STATE_ERROR_STOP && st.stop_reason == MC_STOP_REASON_SOFT_LIMIT_NEG,
           "state %u reason %u", st.state, st.stop_reason);
    ASSERT(st.actual_position < -1000.0 && st.actual_position > -1100.0 &&
               (st.faults & MC_AXIS_FAULT_SOFT_LIMIT_NEG),
           "stopped at %f, faults %#x", st.actual_position, st.faults);
    mc_stop_info i = stop_info(c, a);
    ASSERT(i.reason == MC_STOP_REASON_SOFT_LIMIT_NEG && i.at_rest, "reason %u at rest %u",
           i.reason, i.at_rest);
    take_events(c, &ev);
    ASSERT(ev.stop[a][MC_STOP_REASON_SOFT_LIMIT_NEG] == 1 && ev.stop[8][MC_STOP_REASON_SOFT_LIMIT_NEG] == 0,
           "soft-limit events: axis %u, card-wide %u", ev.stop[a][MC_STOP_REASON_SOFT_LIMIT_NEG],
           ev.stop[8][MC_STOP_REASON_SOFT_LIMIT_NEG]);

    /* Reset: moves further out are refused, moves back in allowed. */
    EXPECT(mc_reset(c, a), MC_OK);
    if (axis(c, a).state == MC_AXIS_STATE_DISABLED) CHECK(mc_enable(c, a));
    EXPECT(mc_move_relative(c, a, -1.0, &lim, NULL), MC_ERR_SOFT_LIMIT);
    CHECK(mc_move_absolute(c, a, 0.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 5000, &at));
    ASSERT(fabs(at) <= 1.0, "back at %f", at);
    printf("soft limit: refused beyond, stopped at %.1f after an overshoot\n", st.actual_position);
    CHECK(mc_close(c));
}

/* A tight following-error limit and a move far beyond what the motor can follow: the card
   trips in the tick the error first exceeds its limit and removes power at once. */
static void following_error(void) {
    mc_card c = open_card();
    const uint32_t a = 2;
    mc_safety_settings s;
    CHECK(mc_safety_settings_default(&s));
    s.ferror = 20.0;
    s.min_ferror = 5.0;
    s.max_velocity = 1e6;
    CHECK(mc_configure_safety(c, a, &s));
    CHECK(mc_enable(c, a));
    mc_move_limits brutal; /* 1e8 counts/s^2: ten times what the default motor can give */
    CHECK(mc_move_limits_symmetric(1e6, 1e8, 1e12, &brutal));
    mc_motion m;
    CHECK(mc_move_relative(c, a, 1e5, &brutal, &m));
    mc_status first_over = {.state = 99};
    uint32_t state_before = MC_AXIS_STATE_DISCRETE_MOTION;
    for (unsigned n = 0; n < 10000; n++) {
        CHECK(mc_sim_step(c, 1));
        mc_status st = axis(c, a);
        double limit = s.ferror * fabs(st.command_velocity) / s.max_velocity;
        if (limit < s.min_ferror) limit = s.min_ferror;
        if (fabs(st.following_error) > limit) {
            first_over = st;
            break;
        }
        ASSERT(st.state != MC_AXIS_STATE_ERROR_STOP, "tripped within the limit");
        state_before = st.state;
    }
    ASSERT(first_over.state == MC_AXIS_STATE_ERROR_STOP &&
               state_before == MC_AXIS_STATE_DISCRETE_MOTION,
           "the error passed its limit: state %u (before: %u)", first_over.state, state_before);
    ASSERT(first_over.stop_reason == MC_STOP_REASON_FOLLOWING_ERROR &&
               (first_over.faults & MC_AXIS_FAULT_FOLLOWING_ERROR) && !drive_on(first_over) &&
               first_over.dac_volts == 0.0,
           "reason %u faults %#x io %#x dac %f", first_over.stop_reason, first_over.faults,
           first_over.io, first_over.dac_volts);
    double at = 0.0;
    EXPECT(mc_motion_wait(c, m, 0, &at), MC_ERR_ABORTED);
    expect_in_message("following error");
    mc_stop_info i = stop_info(c, a);
    ASSERT(i.reason == MC_STOP_REASON_FOLLOWING_ERROR && i.ramp_time == 0.0 &&
               i.stop_tick == first_over.raw.tick,
           "reason %u ramp %f stop tick %llu, trip seen at %llu", i.reason, i.ramp_time,
           (unsigned long long)i.stop_tick, (unsigned long long)first_over.raw.tick);
    safety_events ev;
    take_events(c, &ev);
    ASSERT(ev.stop[a][MC_STOP_REASON_FOLLOWING_ERROR] == 1 &&
               fabs(ev.stop_value[a][MC_STOP_REASON_FOLLOWING_ERROR]) > s.min_ferror,
           "following-error events %u, value %f", ev.stop[a][MC_STOP_REASON_FOLLOWING_ERROR],
           ev.stop_value[a][MC_STOP_REASON_FOLLOWING_ERROR]);
    EXPECT(mc_reset(c, a), MC_OK);
    ASSERT(axis(c, a).state == MC_AXIS_STATE_DISABLED, "state %u", axis(c, a).state);
    printf("following error: tripped at %.1f counts (limit %.1f) in tick %llu, power off\n",
           first_over.following_error, s.min_ferror, (unsigned long long)i.stop_tick);
    CHECK(mc_close(c));
}

/* Outside a session (issue 31). This program detaches its own session with a raw command
   (mc_send_raw) and keeps the card open: the card refuses every motion and power command,
   raw or typed, with MC_ERR_NO_SESSION, and nothing moves while nothing watches; it still
   takes pings, halts and reads. A raw attach of the same session arms the watchdog at once:
   silent from then on, the program trips it the timeout after the attach. */
static void no_session(void) {
    mc_card c = open_card();
    for (uint32_t a = 0; a < AXES; a++) CHECK(mc_enable(c, a));
    CHECK(mc_sim_step(c, 10));
    const uint32_t own = safety(c).session;
    ASSERT(own != 0, "no session");
    /* Only the attached session detaches; an unknown opcode is refused for what it is. */
    EXPECT(mc_send_raw(c, MC_OP_HOST_DETACH, 0, own ^ 1u, NULL, 0, NULL), MC_ERR_SESSION);
    EXPECT(mc_send_raw(c, 0x7777, 0, 0, NULL, 0, NULL), MC_ERR_UNKNOWN_COMMAND);
    EXPECT(mc_send_raw(c, MC_OP_HOST_DETACH, 0, own, NULL, 0, NULL), MC_OK);
    mc_safety_status ss = safety(c);
    ASSERT(ss.session == 0 && !ss.watchdog_armed, "session %u armed %u", ss.session,
           ss.watchdog_armed);
    for (uint32_t a = 0; a < AXES; a++) {
        const double v[4] = {a % 2 ? -100000.0 : 100000.0, 1e6, 1e6, 1e8};
        EXPECT(mc_send_raw(c, MC_OP_MOVE_VELOCITY, a, 0, v, 4, NULL), MC_ERR_NO_SESSION);
        expect_in_message("no host session");
    }
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 1e8, &lim));
    EXPECT(mc_move_relative(c, 0, 1000.0, &lim, NULL), MC_ERR_NO_SESSION);
    EXPECT(mc_set_outputs(c, 1, 1), MC_ERR_NO_SESSION);
    EXPECT(mc_set_watchdog_timeout(c, 5000000), MC_ERR_NO_SESSION);
    EXPECT(mc_ping(c), MC_OK);
    EXPECT(mc_halt(c, 1, 1e6, 1e8, NULL), MC_OK);
    /* Bad raw commands: nothing sent. */
    const double fifteen[15] = {0};
    EXPECT(mc_send_raw(c, 70000, 0, 0, NULL, 0, NULL), MC_ERR_OUT_OF_RANGE);
    EXPECT(mc_send_raw(c, MC_OP_NOP, 0, 0, fifteen, 15, NULL), MC_ERR_OUT_OF_RANGE);
    EXPECT(mc_send_raw(c, MC_OP_NOP, 0, 0, NULL, 2, NULL), MC_ERR_NULL_POINTER);
    /* 2 s with the heartbeat stopped too: nothing moved, nothing tripped. */
    CHECK(mc_set_heartbeat(c, 0));
    CHECK(mc_sim_step(c, 2 * RATE));
    ss = safety(c);
    ASSERT(!ss.watchdog_tripped && ss.session == 0, "tripped %u session %u",
           ss.watchdog_tripped, ss.session);
    for (uint32_t a = 0; a < AXES; a++) {
        mc_status s = axis(c, a);
        ASSERT(s.state == MC_AXIS_STATE_STANDSTILL && s.command_velocity == 0.0 &&
                   fabs(s.actual_velocity) < 1.0 && drive_on(s),
               "axis %u: state %u velocity %f", a, s.state, s.command_velocity);
    }
    /* The same session attached again by a raw command, the program still silent: armed at
       once, and the watchdog stops the velocity move the timeout (100 ms) after the attach. */
    EXPECT(mc_send_raw(c, MC_OP_HOST_ATTACH, 0, own, NULL, 0, NULL), MC_OK);
    ss = safety(c);
    ASSERT(ss.session == own && ss.watchdog_armed && ss.last_heartbeat_tick == ss.attach_tick,
           "session %u armed %u heartbeat tick %llu attach tick %llu", ss.session,
           ss.watchdog_armed, (unsigned long long)ss.last_heartbeat_tick,
           (unsigned long long)ss.attach_tick);
    const double v[4] = {100000.0, 1e6, 1e6, 1e8};
    double value = -1.0;
    EXPECT(mc_send_raw(c, MC_OP_MOVE_VELOCITY, 0, 0, v, 4, &value), MC_OK);
    ASSERT(value == 0.0, "ack value %f", value);
    CHECK(mc_sim_step(c, RATE / 10 + 1));
    ss = safety(c);
    ASSERT(ss.watchdog_tripped && ss.watchdog_trip_tick - ss.attach_tick == RATE / 10,
           "tripped %u at %llu, attached at %llu", ss.watchdog_tripped,
           (unsigned long long)ss.watchdog_trip_tick, (unsigned long long)ss.attach_tick);
    mc_status s0 = axis(c, 0);
    ASSERT(s0.state == MC_AXIS_STATE_ERROR_STOP && s0.stop_reason == MC_STOP_REASON_WATCHDOG,
           "state %u reason %u", s0.state, s0.stop_reason);
    CHECK(mc_set_heartbeat(c, 1));
    CHECK(mc_close(c));
    printf("no session: 4 velocity moves refused, nothing moved; a raw attach armed the "
           "watchdog at tick %llu, tripped at %llu\n",
           (unsigned long long)ss.attach_tick, (unsigned long long)ss.watchdog_trip_tick);
}

/* NULL pointers and unknown axes on the safety calls: outputs untouched. */
static void misuse(void) {
    mc_card c = open_card();
    mc_safety_status ss = {.protocol_errors = 99};
    mc_stop_info i = {.reason = 99};
    EXPECT(mc_get_safety_status(c, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_safety_settings_default(NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_get_stop_info(c, 0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_get_stop_info(c, AXES, &i), MC_ERR_BAD_AXIS);
    ASSERT(ss.protocol_errors == 99 && i.reason == 99, "output written by a failed call");
    EXPECT(mc_set_heartbeat(c, 7), MC_OK); /* any non-zero is on */
    CHECK(mc_close(c));
}

/* Every stop ends within the card's maximum stop time (default 2 s): a halt with a ramp that
   would take minutes runs on the axis's stop ramp instead; configurations that could not stop
   in time are refused. */
static void bounded_stops(void) {
    mc_card c = open_card();
    const uint32_t a = 2;
    mc_safety_settings s;
    CHECK(mc_safety_settings_default(&s));
    mc_safety_settings slow = s;
    slow.stop_deceleration = 1e5; /* 10 s from max_velocity (10^6 counts/s) */
    EXPECT(mc_configure_safety(c, a, &slow), MC_ERR_STOP_TOO_LONG);
    expect_in_message("maximum stop time");
    EXPECT(mc_set_max_stop_time(c, 5000), MC_ERR_STOP_TOO_LONG); /* under 10 ms */
    EXPECT(mc_set_max_stop_time(c, 100000), MC_ERR_STOP_TOO_LONG); /* the ramp needs 0.21 s */
    CHECK(mc_set_max_stop_time(c, 1000000));

    mc_move_limits fast;
    CHECK(mc_move_limits_symmetric(300000.0, 3e6, 3e8, &fast));
    CHECK(mc_enable(c, a));
    CHECK(mc_move_relative(c, a, 1e7, &fast, NULL));
    CHECK(mc_sim_step(c, 3000)); /* cruising */
    /* Its own ramp (1000 counts/s^2 from 300,000 counts/s) would take 300 s. */
    mc_motion h;
    CHECK(mc_halt(c, a, 1000.0, 1e6, &h));
    mc_status st = axis(c, a);
    ASSERT(st.raw.planned_time <= 1.0 && st.raw.planned_time > 0.05,
           "halt planned for %f s, bound 1 s", st.raw.planned_time);
    double at = 0.0;
    CHECK(mc_motion_wait(c, h, 2000, &at));
    st = axis(c, a);
    ASSERT(st.state == MC_AXIS_STATE_STANDSTILL && st.stop_reason == MC_STOP_REASON_HALT,
           "after the halt: state %u, reason %u", st.state, st.stop_reason);
    ASSERT(st.raw.peak_dec <= s.stop_deceleration * (1 + 1e-9), "decelerated at %f",
           st.raw.peak_dec);
    mc_safety_status ss = safety(c);
    ASSERT(ss.session != 0 && ss.host_changes == 0 && ss.late_heartbeats == 0,
           "session %u, host changes %u, late heartbeats %u", ss.session, ss.host_changes,
           ss.late_heartbeats);
    CHECK(mc_close(c));
    printf("bounded stops: a 300 s halt ran on the stop ramp in %.3f s\n", st.raw.planned_time);
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    bounded_stops();
    normal_stop_reasons();
    watchdog();
    estop();
    soft_limit();
    following_error();
    no_session();
    misuse();

    /* Every safety code was returned, except the one no C program can provoke. */
    const mc_result safety_codes[] = {MC_ERR_WATCHDOG_TRIPPED, MC_ERR_ESTOP_ACTIVE,
                                      MC_ERR_SOFT_LIMIT,       MC_ERR_CAUSE_ACTIVE,
                                      MC_ERR_WATCHDOG_TIMEOUT, MC_ERR_BAD_CATEGORY,
                                      MC_ERR_STOP_TOO_LONG,    MC_ERR_SESSION,
                                      MC_ERR_NO_SESSION};
    for (size_t k = 0; k < sizeof safety_codes / sizeof safety_codes[0]; k++) {
        ASSERT(seen[-safety_codes[k]], "code %d (%s) never returned", (int)safety_codes[k],
               mc_result_str(safety_codes[k]));
    }
    printf("%u checks\n", checks);
    printf("PASS safety\n");
    return 0;
}
