/*
 * A path streamed from a thread of the library (mc_group_path_stream_start): the program
 * watches its progress, and it ends with mc_path_streamer_join. A zigzag of 4500 lines, more
 * than the card's path buffer of 4096 holds, so the stream waits for room as the path runs;
 * then one cancelled while it waits (what the card accepted stays queued; a halt drops it);
 * and an item the library refuses (nothing sent, no handle).
 *
 *     cc -std=c11 path_stream.c $(pkg-config --cflags --libs motioncard) -o path_stream && ./path_stream [sim|URI]
 */
#define _POSIX_C_SOURCE 200809L
#include "expect.h"

#include <math.h>
#include <time.h>

#define N 4500
#define G 0

static mc_path_segment items[N];

static void zigzag(double feed) {
    for (uint32_t i = 0; i < N; i++) {
        const double t[2] = {100.0 * (i + 1), (i % 2 == 0) ? 1.0 : 0.0};
        CHECK(mc_path_segment_line(i + 1, t, 2, feed, 10.0, &items[i]));
    }
    items[N - 1].last = 1;
}

static void sleep_ms(long ms) {
    struct timespec t = {0, ms * 1000000L};
    nanosleep(&t, NULL);
}

int main(int argc, char **argv) {
    mc_card c = 0;
    CHECK(open_from_args(argc, argv, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_enable(c, 1));
    const uint32_t xy[2] = {0, 1};
    mc_group_settings gs;
    CHECK(mc_group_settings_new(xy, 2, &gs));
    CHECK(mc_group_configure(c, G, &gs));
    CHECK(mc_group_enable(c, G));
    mc_path_settings ps;
    CHECK(mc_path_settings_uniform(2, 4e5, 4e6, 4e8, &ps));
    ps.chord_fit = 0; /* every line sent as a line */
    CHECK(mc_group_configure_path(c, G, &ps));

    /* Refused before anything is sent: no handle. */
    zigzag(2e5);
    mc_path_streamer st = 777;
    items[10].target[1] = NAN;
    EXPECT(mc_group_path_stream_start(c, G, items, N, &st), MC_ERR_NOT_FINITE);
    expect_in_message("path item 10");
    ASSERT(st == 777, "a handle was written");
    zigzag(2e5);
    EXPECT(mc_group_path_stream_start(c, G, items, N, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_group_path_stream_start(c, G, NULL, N, &st), MC_ERR_NULL_POINTER);

    /* The whole zigzag, watched as it goes. */
    CHECK(mc_group_path_stream_start(c, G, items, N, &st));
    mc_path_progress p, before = {0, 0, 0, 0};
    uint32_t finished = 0;
    unsigned polls = 0;
    do {
        CHECK(mc_path_streamer_progress(st, &p, &finished));
        ASSERT(p.sent >= before.sent && p.accepted >= before.accepted && p.accepted <= p.sent &&
                   p.sent <= N,
               "progress went back: sent %llu, accepted %llu", (unsigned long long)p.sent,
               (unsigned long long)p.accepted);
        before = p;
        polls++;
        if (!finished) sleep_ms(2);
    } while (!finished);
    size_t accepted = 0;
    mc_group_motion last;
    CHECK(mc_path_streamer_join(st, &accepted, &last));
    ASSERT(accepted == N && last.seq != 0, "accepted %zu", accepted);
    EXPECT(mc_path_streamer_join(st, NULL, NULL), MC_ERR_BAD_HANDLE);
    EXPECT(mc_path_streamer_progress(st, &p, NULL), MC_ERR_BAD_HANDLE);
    EXPECT(mc_path_streamer_cancel(st), MC_ERR_BAD_HANDLE);
    CHECK(mc_group_motion_wait(c, last, 60000));
    mc_status sx;
    CHECK(mc_get_status(c, 0, &sx));
    ASSERT(sx.command_position == 100.0 * N, "x ended at %f", sx.command_position);
    printf("path_stream: %d lines streamed from the library's thread, %u polls\n", N, polls);

    /* A slow zigzag: the buffer fills, the stream waits for room; cancelled there. */
    for (uint32_t i = 0; i < N; i++) {
        const double t[2] = {100.0 * N + 100.0 * (i + 1), (i % 2 == 0) ? 1.0 : 0.0};
        CHECK(mc_path_segment_line(i + 1, t, 2, 2000.0, 10.0, &items[i]));
    }
    CHECK(mc_group_path_stream_start(c, G, items, N, &st));
    do {
        CHECK(mc_path_streamer_progress(st, &p, &finished));
        sleep_ms(2);
    } while (p.accepted < MC_PATH_SEGMENTS - 64 && !finished);
    ASSERT(!finished, "the slow stream ended by itself");
    CHECK(mc_path_streamer_cancel(st));
    EXPECT(mc_path_streamer_join(st, &accepted, NULL), MC_ERR_CANCELLED);
    ASSERT(accepted >= MC_PATH_SEGMENTS - 64 && accepted < N, "accepted %zu", accepted);
    mc_group_motion h;
    CHECK(mc_group_halt(c, G, 1e6, 1e8, &h));
    CHECK(mc_group_motion_wait(c, h, 10000));
    printf("path_stream: cancelled after %zu of %d lines\n", accepted, N);

    CHECK(mc_close(c));
    printf("PASS path_stream\n");
    return 0;
}
