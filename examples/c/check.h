/*
 * Helpers shared by the example programs: run a call and, when it fails, print its code,
 * the code's description and the thread's detailed message, then exit with status 1.
 *
 * Every program takes one optional argument: a card URI ("sim" when none is given), or
 * "stepped" for an emulated card whose time advances only while the program waits or steps
 * it (deterministic; see mc_open_sim_stepped).
 */
#ifndef MOTIONCARD_EXAMPLE_CHECK_H
#define MOTIONCARD_EXAMPLE_CHECK_H

#include <motioncard.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The calling thread's last error message (a placeholder when it does not fit). */
static inline const char *last_error(char *buf, size_t len) {
    size_t needed = 0;
    if (mc_last_error_message(buf, len, &needed) != MC_OK) {
        snprintf(buf, len, "(message of %zu bytes does not fit)", needed);
    }
    return buf;
}

static inline void fail_call(const char *what, mc_result r, const char *file, int line) {
    char msg[512];
    fprintf(stderr, "%s:%d: %s failed: %d (%s): %s\n", file, line, what, (int)r,
            mc_result_str(r), last_error(msg, sizeof msg));
    exit(1);
}

/* Run an mc_ call that must succeed. */
#define CHECK(call)                                                                       \
    do {                                                                                  \
        mc_result check_r_ = (call);                                                      \
        if (check_r_ != MC_OK) fail_call(#call, check_r_, __FILE__, __LINE__);            \
    } while (0)

/* A condition that must hold; the message is printf-style. */
#define ASSERT(cond, ...)                                                                 \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            fprintf(stderr, "%s:%d: ASSERT(%s) failed: ", __FILE__, __LINE__, #cond);     \
            fprintf(stderr, __VA_ARGS__);                                                 \
            fputc('\n', stderr);                                                          \
            exit(1);                                                                      \
        }                                                                                 \
    } while (0)

/* A real-time card's watchdog trips when the library's heartbeat thread is late by more than
   its timeout (default 100 ms, above what a loaded host without real-time scheduling delays
   it). These programs run beside a test suite that loads the machine further: allow 250 ms,
   and clear a trip that came before this call. (A stepped card beats as it steps: it needs
   neither.) */
static inline mc_result relax_watchdog(mc_card card) {
    mc_result r = mc_set_watchdog_timeout(card, 250000);
    return r == MC_OK ? mc_reset_faults(card) : r;
}

/* Open the card named on the command line (see above). */
static inline mc_result open_from_args(int argc, char **argv, mc_card *card) {
    const char *uri = argc > 1 ? argv[1] : "sim";
    if (strcmp(uri, "stepped") == 0) {
        return mc_open_sim_stepped(8, 10000, card);
    }
    mc_result r = mc_open(uri, card);
    return r == MC_OK ? relax_watchdog(*card) : r;
}

#endif
