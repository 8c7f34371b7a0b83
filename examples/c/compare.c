/*
 * Digital I/O and position compare from C (layout 1.7).
 *
 * Inputs: polarity and debounce set with mc_configure_io, the stepped sim's pins driven with
 * mc_sim_set_input, the debounced word read with mc_get_inputs, and an MC_EVENT_INPUT on the
 * edges asked for, exactly `debounce` ticks after the pin changed. Outputs: mc_set_outputs.
 *
 * Compare ("EQU" outputs): with the axis running at 10^6 counts/s, a series of 1000 pulses
 * fires every one (none missed), a table of 6000 positions is streamed in on its low-water
 * events and fires every one, a series armed behind the axis reports its passed positions
 * missed, and every compare error code is returned.
 *
 * Runs on a stepped card (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 compare.c $(pkg-config --cflags --libs motioncard) -lm -o compare && ./compare
 */
#include "expect.h"

#include <math.h>

static double position(mc_card c) {
    mc_status s;
    CHECK(mc_get_status(c, 0, &s));
    return s.actual_position;
}

static mc_compare_info info(mc_card c, uint32_t ch) {
    mc_compare_info i;
    CHECK(mc_compare_get_status(c, 0, ch, &i));
    return i;
}

/* Take every queued event; count those of `kind` with `code` (any code: -1). */
static unsigned drain(mc_card c, uint32_t kind, int code, mc_event *last) {
    mc_event e;
    unsigned n = 0;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        if (e.kind == kind && (code < 0 || e.code == code)) {
            n++;
            if (last) *last = e;
        }
    }
    return n;
}

/* Step `ticks` in slices the event ring holds, counting events as `drain` does. */
static unsigned step_drain(mc_card c, uint64_t ticks, uint32_t kind, int code) {
    unsigned n = 0;
    for (uint64_t t = 0; t < ticks; t += 100) {
        CHECK(mc_sim_step(c, ticks - t < 100 ? ticks - t : 100));
        n += drain(c, kind, code, NULL);
    }
    return n;
}

static void digital_io(mc_card c) {
    mc_io_settings io;
    EXPECT(mc_io_settings_default(NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_io_settings_default(&io));
    ASSERT(io.polarity == 0 && io.debounce[0] == 0, "defaults");
    io.polarity = 1u << 1;        /* input 1 is active low */
    io.rise_events = 1u << 0;     /* an event when input 0 becomes active */
    io.debounce[0] = 4;           /* ... after 4 ticks */
    io.debounce[5] = 10001;
    EXPECT(mc_configure_io(c, &io), MC_ERR_IO_CONFIG);
    io.debounce[5] = 0;
    CHECK(mc_configure_io(c, &io));
    CHECK(mc_sim_step(c, 1));
    uint32_t in = 0;
    CHECK(mc_get_inputs(c, &in));
    ASSERT(in == 1u << 1, "input 1 (active low, pin low) reads active: %#x", in);
    drain(c, MC_EVENT_INPUT, -1, NULL);

    /* A 3-tick glitch on input 0 never shows; a level held shows 4 ticks after it came. */
    CHECK(mc_sim_set_input(c, 0, 1));
    CHECK(mc_sim_step(c, 3));
    CHECK(mc_sim_set_input(c, 0, 0));
    CHECK(mc_sim_step(c, 10));
    ASSERT(drain(c, MC_EVENT_INPUT, -1, NULL) == 0, "the glitch passed the debounce");
    uint64_t t0 = 0;
    CHECK(mc_get_tick(c, &t0));
    CHECK(mc_sim_set_input(c, 0, 1));
    CHECK(mc_sim_step(c, 10));
    mc_event e;
    ASSERT(drain(c, MC_EVENT_INPUT, 1, &e) == 1 && e.axis == 0, "no rising edge event");
    ASSERT(e.tick == t0 + 1 + 4, "the edge came at tick %llu, not %llu",
           (unsigned long long)e.tick, (unsigned long long)(t0 + 5));
    CHECK(mc_get_inputs(c, &in));
    ASSERT(in == (1u << 1 | 1u), "inputs %#x", in);
    printf("inputs: debounced edge %llu ticks after the pin (debounce 4)\n",
           (unsigned long long)(e.tick - t0 - 1));

    /* Outputs from the host. */
    uint32_t out = 0;
    CHECK(mc_set_outputs(c, 0xF0, 0x50));
    CHECK(mc_get_outputs(c, &out));
    ASSERT((out & 0xF0) == 0x50, "outputs %#x", out);
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(1, 10000, &c));
    CHECK(mc_enable(c, 0));
    digital_io(c);

    /* Refusals: each with its own code, nothing armed. */
    EXPECT(mc_compare_single(c, 0, 4, 0, 10, 100.0, MC_COMPARE_POSITIVE), MC_ERR_IO_CHANNEL);
    EXPECT(mc_compare_single(c, 0, 0, 16, 10, 100.0, MC_COMPARE_POSITIVE), MC_ERR_COMPARE_MODE);
    EXPECT(mc_compare_single(c, 0, 0, 0, 10, NAN, MC_COMPARE_POSITIVE), MC_ERR_NOT_FINITE);
    EXPECT(mc_compare_series(c, 0, 0, 0, 10, 0.0, 10.0, 5, MC_COMPARE_EITHER), MC_ERR_BAD_CONFIG);
    EXPECT(mc_compare_series(c, 0, 0, 0, 10, 0.0, 0.5, 5, MC_COMPARE_POSITIVE),
           MC_ERR_COMPARE_MODE);
    EXPECT(mc_compare_get_status(c, 0, 0, NULL), MC_ERR_NULL_POINTER);
    ASSERT(info(c, 0).state == MC_IO_STATE_IDLE, "armed by a refused call");
    CHECK(mc_compare_single(c, 0, 0, 0, 10, 1e9, MC_COMPARE_EITHER));
    EXPECT(mc_compare_single(c, 0, 0, 1, 10, 1e9, MC_COMPARE_POSITIVE), MC_ERR_COMPARE_BUSY);
    EXPECT(mc_compare_single(c, 0, 1, 0, 10, 1e9, MC_COMPARE_POSITIVE), MC_ERR_COMPARE_BUSY);
    CHECK(mc_compare_disarm(c, 0, 0));

    /* The axis at 10^6 counts/s (1 m/s on a 1 um scale). */
    mc_velocity_limits vl = {5e6, 5e6, 5e8};
    mc_motion m;
    CHECK(mc_move_velocity(c, 0, 1e6, &vl, &m));
    CHECK(mc_motion_wait_in_velocity(c, m, 10000, NULL));
    drain(c, 0, -1, NULL);

    /* A series of 1000 pulses, 500 counts apart, 5 us wide on output 2. */
    double start = floor(position(c)) + 1000.0;
    CHECK(mc_compare_series(c, 0, 1, 2, 5, start, 500.0, 1000, MC_COMPARE_POSITIVE));
    unsigned fired_events = step_drain(c, 5200, MC_EVENT_COMPARE, MC_COMPARE_FIRED);
    mc_compare_info i = info(c, 1);
    ASSERT(i.state == MC_IO_STATE_DONE && i.fires == 1000 && i.missed == 0 &&
               i.last_fired == start + 999 * 500.0,
           "series: state %u, %u fired, %u missed", i.state, i.fires, i.missed);
    ASSERT(fired_events == 1000, "%u fired events", fired_events); /* one per tick here */
    printf("compare: series of 1000 at 1e6 counts/s: %u fired, %u missed\n", i.fires, i.missed);

    /* A table of 6000 positions streamed on low water (the buffer holds 4096). */
    enum { TOTAL = 6000, CHUNK = 512 };
    static double table[TOTAL];
    double p = floor(position(c)) + 20000.0;
    for (int k = 0; k < TOTAL; k++) {
        table[k] = p;
        p += 97.0 + (k % 5);
    }
    EXPECT(mc_compare_push(c, 0, 2, MC_COMPARE_POSITIVE, NULL, 3, NULL), MC_ERR_NULL_POINTER);
    size_t room = 0, sent = 0;
    CHECK(mc_compare_push(c, 0, 2, MC_COMPARE_POSITIVE, table, 4096, &room));
    sent = 4096;
    ASSERT(room == 0, "room %zu", room);
    EXPECT(mc_compare_push(c, 0, 2, MC_COMPARE_POSITIVE, table + sent, 1, &room),
           MC_ERR_COMPARE_FULL);
    EXPECT(mc_compare_push(c, 0, 2, MC_COMPARE_POSITIVE, table, TOTAL, &room), MC_ERR_COMPARE_FULL);
    CHECK(mc_compare_table(c, 0, 2, 3, 5, 1000, MC_COMPARE_POSITIVE));
    unsigned refills = 0;
    while (sent < TOTAL) {
        mc_event e;
        CHECK(mc_wait_event(c, 1000, &e));
        if (e.kind == MC_EVENT_COMPARE && e.code == MC_COMPARE_LOW_WATER) {
            size_t n = TOTAL - sent < CHUNK * 4 ? TOTAL - sent : CHUNK * 4;
            CHECK(mc_compare_push(c, 0, 2, MC_COMPARE_POSITIVE, table + sent, n, &room));
            sent += n;
            refills++;
        }
    }
    while (info(c, 2).pending > 0) step_drain(c, 100, 0, -1);
    i = info(c, 2);
    ASSERT(i.fires == TOTAL && i.missed == 0 && i.last_fired == table[TOTAL - 1],
           "table: %u fired, %u missed", i.fires, i.missed);
    /* Out of order, the other direction: refused. Behind the axis: queued, then missed. */
    double ahead[2] = {position(c) + 1e6, position(c) + 5e5};
    EXPECT(mc_compare_push(c, 0, 2, MC_COMPARE_POSITIVE, ahead, 2, NULL), MC_ERR_COMPARE_ORDER);
    EXPECT(mc_compare_push(c, 0, 2, MC_COMPARE_NEGATIVE, ahead, 1, NULL), MC_ERR_COMPARE_BUSY);
    double back = table[TOTAL - 1] - 1.0;
    CHECK(mc_compare_push(c, 0, 2, MC_COMPARE_POSITIVE, &back, 1, NULL));
    step_drain(c, 1, 0, -1);
    ASSERT(info(c, 2).missed == 1, "queued behind, not missed");
    (void)refills;
    printf("compare: table of %d streamed on low water: %u fired, %u missed\n", TOTAL, i.fires,
           i.missed);
    CHECK(mc_compare_disarm(c, 0, 2));

    /* Armed behind the axis: the 10 positions already passed are reported missed. */
    drain(c, 0, -1, NULL);
    start = floor(position(c)) - 1000.0 + 0.25;
    CHECK(mc_compare_series(c, 0, 3, 4, 5, start, 100.0, 20, MC_COMPARE_POSITIVE));
    CHECK(mc_sim_step(c, 50));
    i = info(c, 3);
    mc_event last;
    ASSERT(drain(c, MC_EVENT_COMPARE, MC_COMPARE_MISSED, &last) == 1 && i.missed >= 10 &&
               i.fires + i.missed == 20 && last.value == i.last_missed,
           "behind: %u fired, %u missed", i.fires, i.missed);
    printf("compare: armed 1000 counts behind: %u missed, %u fired\n", i.missed, i.fires);

    CHECK(mc_halt(c, 0, 5e6, 5e8, &m));
    CHECK(mc_motion_wait(c, m, 10000, NULL));
    CHECK(mc_close(c));
    const mc_result codes[] = {MC_ERR_IO_CONFIG,   MC_ERR_IO_CHANNEL,    MC_ERR_COMPARE_MODE,
                               MC_ERR_COMPARE_FULL, MC_ERR_COMPARE_ORDER, MC_ERR_COMPARE_BUSY};
    for (size_t k = 0; k < sizeof codes / sizeof codes[0]; k++) {
        ASSERT(seen[-codes[k]], "code %d (%s) never returned", (int)codes[k],
               mc_result_str(codes[k]));
    }
    printf("%u checks\n", checks);
    printf("PASS compare\n");
    return 0;
}
