/*
 * Cards on one sync bus from C (layout 1.12): three stepped cards on one clock, a synchronised
 * start of two axes on each (every axis starts on one tick, their positions bit-identical), a
 * synchronised hold and halt, a command timed to a tick, and the refusals of timing.
 *
 * Runs on stepped cards (deterministic). Positions in counts (scale 1). The argument is
 * ignored.
 *
 *     cc -std=c11 sync.c $(pkg-config --cflags --libs motioncard) -lm -o sync && ./sync
 */
#include "expect.h"
#include <string.h>

#define NCARDS 3

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

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card cards[NCARDS];
    CHECK(mc_open_sim_bus(NCARDS, 2, 10000, cards));
    mc_bus_status st;
    CHECK(mc_sim_step(cards[1], 1));
    CHECK(mc_get_bus_status(cards[0], &st));
    ASSERT(st.role == MC_BUS_MASTER && st.followers == 2, "master: role %u, %u followers",
           st.role, st.followers);
    CHECK(mc_get_bus_status(cards[2], &st));
    ASSERT(st.role == MC_BUS_FOLLOWER && st.state == MC_BUSST_LOCKED &&
               strcmp(st.master, "sim0") == 0,
           "follower: role %u state %u master %s", st.role, st.state, st.master);
    for (int k = 0; k < NCARDS; k++) {
        CHECK(mc_enable(cards[k], 0));
        CHECK(mc_enable(cards[k], 1));
    }
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(50000.0, 1e6, 1e8, &lim));

    /* A synchronised start: six axes on three cards, one tick. */
    uint64_t t0 = 0, t1 = 0;
    mc_motion m[2 * NCARDS];
    CHECK(mc_sync_begin(cards, NCARDS, &t0));
    for (int k = 0; k < NCARDS; k++)
        for (uint32_t a = 0; a < 2; a++)
            CHECK(mc_move_absolute(cards[k], a, 10000.0, &lim, &m[2 * k + a]));
    CHECK(mc_sync_start(&t1));
    ASSERT(t0 == t1, "started on %llu, announced %llu", (unsigned long long)t1,
           (unsigned long long)t0);
    for (int n = 0; n < 200; n++) {
        CHECK(mc_sim_step(cards[0], 7));
        double p = axis(cards[0], 0).command_position;
        for (int k = 0; k < NCARDS; k++)
            for (uint32_t a = 0; a < 2; a++)
                ASSERT(axis(cards[k], a).command_position == p, "card %d axis %u apart", k, a);
    }
    for (int i = 0; i < 2 * NCARDS; i++) {
        double at;
        CHECK(mc_motion_wait(cards[i / 2], m[i], 10000, &at));
        ASSERT(at == 10000.0, "ended at %.3f", at);
    }
    printf("sync: 6 axes on 3 cards started on tick %llu\n", (unsigned long long)t1);

    /* Hold and halt on one tick. */
    for (int k = 0; k < NCARDS; k++)
        CHECK(mc_move_absolute(cards[k], 0, 500000.0, &lim, &m[k]));
    CHECK(mc_sim_step(cards[0], 2000));
    uint64_t th = 0, tr = 0, tt = 0;
    CHECK(mc_sync_hold(cards, NCARDS, &th));
    CHECK(mc_sim_step(cards[0], 2000));
    double held = axis(cards[0], 0).command_position;
    for (int k = 0; k < NCARDS; k++) {
        mc_status s = axis(cards[k], 0);
        ASSERT(s.command_velocity == 0.0 && s.command_position == held, "card %d not held", k);
    }
    CHECK(mc_sync_override(cards, NCARDS, 1.0, &tr));
    CHECK(mc_sim_step(cards[0], 300));
    CHECK(mc_sync_halt(cards, NCARDS, 1e6, 1e8, &tt));
    ASSERT(th < tr && tr < tt, "ticks %llu %llu %llu", (unsigned long long)th,
           (unsigned long long)tr, (unsigned long long)tt);
    CHECK(mc_sim_step(cards[0], 3000));
    double end = axis(cards[0], 0).command_position;
    for (int k = 0; k < NCARDS; k++)
        ASSERT(axis(cards[k], 0).command_position == end, "card %d halted elsewhere", k);

    /* One card, a command timed to a tick: the output rises on it exactly. */
    mc_card c = cards[0];
    uint64_t now = tick_of(c);
    CHECK(mc_timed_begin(now + 10, 0));
    CHECK(mc_set_outputs(c, 1u, 1u));
    CHECK(mc_timed_end(1000));
    ASSERT(tick_of(c) >= now + 10, "answered before its tick");
    uint32_t out = 0;
    CHECK(mc_get_outputs(c, &out));
    ASSERT(out & 1u, "output 0 not set");

    /* The refusals. */
    now = tick_of(c);
    CHECK(mc_timed_begin(now, 0));
    EXPECT(mc_move_absolute(c, 1, 0.0, &lim, NULL), MC_ERR_TICK_PASSED);
    CHECK(mc_timed_end(0));
    CHECK(mc_timed_begin(now + 10000000, 0));
    EXPECT(mc_move_absolute(c, 1, 0.0, &lim, NULL), MC_ERR_TICK_FAR);
    CHECK(mc_timed_end(0));
    CHECK(mc_timed_begin(now + 5000, 0));
    for (int k = 0; k < 16; k++)
        CHECK(mc_set_outputs(c, 2u, 0u));
    EXPECT(mc_set_outputs(c, 2u, 0u), MC_ERR_TIMED_FULL);
    mc_sync_abort();
    uint32_t dropped = 0;
    CHECK(mc_timed_cancel(c, 0, &dropped));
    ASSERT(dropped == 16, "%u dropped", dropped);
    double a[2] = {(double)(now + 100), 0.0};
    EXPECT(mc_send_raw(c, MC_OP_AT_TICK, 0, 0, a, 2, NULL), MC_ERR_TIMED_ALONE);
    EXPECT(mc_sync_commit(cards[1], 9, now + 100), MC_ERR_NOT_MASTER);
    EXPECT(mc_sync_commit(c, 9, now), MC_ERR_COMMIT_LATE);
    /* A key never committed: refused on its tick, nothing done. */
    now = tick_of(c);
    CHECK(mc_timed_begin(now + 20, 77));
    CHECK(mc_set_outputs(c, 4u, 4u));
    EXPECT(mc_timed_end(1000), MC_ERR_NOT_COMMITTED);
    CHECK(mc_get_outputs(c, &out));
    ASSERT(!(out & 4u), "an uncommitted command ran");
    /* Cancelled before its tick. */
    CHECK(mc_timed_begin(now + 500, 78));
    CHECK(mc_set_outputs(c, 4u, 4u));
    CHECK(mc_timed_cancel(c, 78, &dropped));
    EXPECT(mc_timed_end(1000), MC_ERR_TIMED_CANCELLED);
    EXPECT(mc_timed_end(0), MC_ERR_INVALID_STATE);
    printf("sync: timed output on its tick, refusals checked\n");

    for (int k = NCARDS - 1; k >= 0; k--)
        CHECK(mc_close(cards[k]));
    printf("PASS sync\n");
    return 0;
}
