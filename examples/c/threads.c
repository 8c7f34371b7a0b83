/*
 * One card, many threads at once: a mover thread per axis (enable, a series of moves, each
 * waited for and checked), status readers scanning every axis, and a thread pinging the card.
 * Every result is checked, including each thread's own last-error message.
 */
#define _POSIX_C_SOURCE 200809L
#include "check.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <time.h>

#define MOVERS 4
#define MOVES 5
#define READERS 2

static mc_card card;
static atomic_int movers_left = MOVERS;

static void pause_briefly(void) {
    struct timespec t = {0, 200000L}; /* 0.2 ms */
    nanosleep(&t, NULL);
}

static void *mover(void *arg) {
    const uint32_t axis = (uint32_t)(uintptr_t)arg;
    mc_move_limits limits;
    CHECK(mc_move_limits_symmetric(2e5, 4e6, 2e8, &limits));
    CHECK(mc_enable(card, axis));
    for (int i = 0; i < MOVES; i++) {
        const double target = (i % 2 ? -1.0 : 1.0) * (1000.0 * (axis + 1) + 100.0 * i);
        mc_motion m;
        CHECK(mc_move_absolute(card, axis, target, &limits, &m));
        ASSERT(m.axis == axis, "motion on axis %u, expected %u", m.axis, axis);
        double at = 0.0;
        CHECK(mc_motion_wait(card, m, 10000, &at));
        ASSERT(fabs(at - target) <= 1.0, "axis %u move %d done at %f, target %f", axis, i, at,
               target);
        mc_status s;
        CHECK(mc_get_status(card, axis, &s));
        ASSERT(s.state == MC_AXIS_STATE_STANDSTILL && s.raw.move_count == (uint32_t)i + 1 &&
                   s.raw.target == target,
               "axis %u after move %d: state %u, moves %u, target %f", axis, i, s.state,
               s.raw.move_count, s.raw.target);

        /* A failure on this thread gives this thread's message, whatever the others do. */
        const uint32_t bad = 100 + axis;
        ASSERT(mc_enable(card, bad) == MC_ERR_BAD_AXIS, "axis %u accepted", bad);
        char msg[256], expect[32];
        snprintf(expect, sizeof expect, "axis %u ", bad);
        ASSERT(strstr(last_error(msg, sizeof msg), expect), "thread of axis %u got \"%s\"", axis,
               msg);
    }
    CHECK(mc_disable(card, axis));
    atomic_fetch_sub(&movers_left, 1);
    return NULL;
}

static void *reader(void *arg) {
    unsigned long *reads = arg;
    uint64_t last_tick[MOVERS] = {0};
    while (atomic_load(&movers_left) > 0) {
        for (uint32_t axis = 0; axis < MOVERS; axis++) {
            mc_status s;
            CHECK(mc_get_status(card, axis, &s));
            ASSERT(s.raw.tick >= last_tick[axis], "axis %u tick went back", axis);
            last_tick[axis] = s.raw.tick;
            ASSERT(s.state == MC_AXIS_STATE_DISABLED || s.state == MC_AXIS_STATE_STANDSTILL ||
                       s.state == MC_AXIS_STATE_DISCRETE_MOTION,
                   "axis %u state %u", axis, s.state);
            ASSERT(isfinite(s.command_position) && fabs(s.command_position) <= 10000.0,
                   "axis %u commanded position %f", axis, s.command_position);
            (*reads)++;
        }
        pause_briefly();
    }
    return NULL;
}

static void *pinger(void *arg) {
    unsigned long *pings = arg;
    while (atomic_load(&movers_left) > 0) {
        CHECK(mc_ping(card));
        mc_card_info info;
        CHECK(mc_get_info(card, &info));
        ASSERT(info.axes == 8, "axes %u", info.axes);
        (*pings)++;
        pause_briefly();
    }
    return NULL;
}

int main(int argc, char **argv) {
    CHECK(open_from_args(argc, argv, &card));
    pthread_t movers[MOVERS], readers[READERS], ping;
    unsigned long reads[READERS] = {0}, pings = 0;
    for (uintptr_t a = 0; a < MOVERS; a++) {
        ASSERT(pthread_create(&movers[a], NULL, mover, (void *)a) == 0, "pthread_create");
    }
    for (int r = 0; r < READERS; r++) {
        ASSERT(pthread_create(&readers[r], NULL, reader, &reads[r]) == 0, "pthread_create");
    }
    ASSERT(pthread_create(&ping, NULL, pinger, &pings) == 0, "pthread_create");
    for (int a = 0; a < MOVERS; a++) pthread_join(movers[a], NULL);
    for (int r = 0; r < READERS; r++) pthread_join(readers[r], NULL);
    pthread_join(ping, NULL);

    unsigned total_moves = 0;
    for (uint32_t axis = 0; axis < MOVERS; axis++) {
        mc_status s;
        CHECK(mc_get_status(card, axis, &s));
        ASSERT(s.state == MC_AXIS_STATE_DISABLED, "axis %u state %u", axis, s.state);
        total_moves += s.raw.move_count;
    }
    ASSERT(total_moves == MOVERS * MOVES, "%u moves", total_moves);
    ASSERT(reads[0] > 0 && reads[1] > 0, "a reader never read");
    printf("%d threads moved %u times, %d readers read %lu statuses, %lu pings: all checked\n",
           MOVERS, total_moves, READERS, reads[0] + reads[1], pings);
    CHECK(mc_close(card));
    printf("PASS threads\n");
    return 0;
}
