/*
 * EXPECT, for the programs that check error paths: a call must return a given code, a failure
 * must leave a detailed message for the calling thread, and every code returned is recorded in
 * `seen` (by -code) so a program can require that it provoked the codes it means to.
 */
#ifndef MOTIONCARD_EXAMPLE_EXPECT_H
#define MOTIONCARD_EXAMPLE_EXPECT_H

#include "check.h"

static unsigned checks; /* EXPECTs passed */
static int seen[256];   /* codes returned, by -code */

/* A failure left a message for this thread. */
static inline void expect_message(const char *what) {
    char msg[512];
    size_t needed = 0;
    ASSERT(mc_last_error_message(msg, sizeof msg, &needed) == MC_OK, "reading the message");
    ASSERT(needed == strlen(msg) + 1 && needed > 1, "%s left no message", what);
}

/* The last error message contains `part`. */
static inline void expect_in_message(const char *part) {
    char msg[512];
    ASSERT(strstr(last_error(msg, sizeof msg), part), "\"%s\" not in \"%s\"", part, msg);
}

/* `call` must return `code`. */
#define EXPECT(call, code)                                                                \
    do {                                                                                  \
        mc_result expect_r_ = (call);                                                     \
        if (expect_r_ != (code)) {                                                        \
            char msg_[512];                                                               \
            fprintf(stderr, "%s:%d: %s returned %d (%s), expected %d (%s); last error: %s\n", \
                    __FILE__, __LINE__, #call, (int)expect_r_, mc_result_str(expect_r_),  \
                    (int)(code), mc_result_str(code), last_error(msg_, sizeof msg_));     \
            exit(1);                                                                      \
        }                                                                                 \
        if (expect_r_ != MC_OK) expect_message(#call);                                    \
        if (-expect_r_ >= 0 && -expect_r_ < 256) seen[-expect_r_] = 1;                    \
        checks++;                                                                         \
    } while (0)

#endif
