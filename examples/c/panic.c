/*
 * The panic boundary, seen from C: a panic inside the library never unwinds into the caller.
 * The call returns MC_ERR_PANIC, leaves its outputs untouched and the panic's message for the
 * thread; the card, the thread and other threads carry on.
 *
 * Needs a library built with the test-panic feature (the C tests build one): it exports
 * mc__test_panic_next_call, which makes the calling thread's next mc_ call panic. An installed
 * library does not have it, and motioncard.h does not declare it. The argument is ignored.
 */
#include "check.h"

#include <pthread.h>

/* `call` must return `code`. */
#define EXPECT(call, code)                                                                \
    do {                                                                                  \
        mc_result expect_r_ = (call);                                                     \
        ASSERT(expect_r_ == (code), "%s returned %d (%s), expected %d", #call,            \
               (int)expect_r_, mc_result_str(expect_r_), (int)(code));                    \
    } while (0)

/* Hidden test hook, declared here (not in motioncard.h). */
mc_result mc__test_panic_next_call(void);

static const char PANIC_MESSAGE[] = "libmotioncard panicked: test panic requested";

static mc_card card;

static void expect_panic_message(void) {
    char msg[512];
    ASSERT(strstr(last_error(msg, sizeof msg), PANIC_MESSAGE), "message \"%s\"", msg);
}

/* Another thread's panic: its own code and message; the main thread's message is its own. */
static void *other_thread(void *arg) {
    (void)arg;
    CHECK(mc__test_panic_next_call());
    EXPECT(mc_ping(card), MC_ERR_PANIC);
    expect_panic_message();
    CHECK(mc_ping(card));
    return NULL;
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    CHECK(mc_open_sim_stepped(2, 10000, &card));

    /* A call with an output: MC_ERR_PANIC, output untouched, message kept. */
    mc_status st = {.state = 99};
    CHECK(mc__test_panic_next_call());
    EXPECT(mc_get_status(card, 0, &st), MC_ERR_PANIC);
    ASSERT(st.state == 99, "output written by a call that panicked");
    ASSERT(strcmp(mc_result_str(MC_ERR_PANIC), "internal error in libmotioncard (panic)") == 0,
           "%s", mc_result_str(MC_ERR_PANIC));
    expect_panic_message();
    /* Reading the message does not panic (only the next guarded call does), and the next call
       works. */
    CHECK(mc_get_status(card, 0, &st));
    ASSERT(st.state == MC_AXIS_STATE_DISABLED, "state %u", st.state);

    /* A command: the card is left as it was, and takes the next command. */
    CHECK(mc__test_panic_next_call());
    EXPECT(mc_enable(card, 0), MC_ERR_PANIC);
    CHECK(mc_get_status(card, 0, &st));
    ASSERT(st.state == MC_AXIS_STATE_DISABLED, "a call that panicked enabled the axis");
    CHECK(mc_enable(card, 0));
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(1e5, 1e6, 5e7, &lim));
    CHECK(mc_move_relative(card, 0, 1000.0, &lim, NULL));
    double at = 0.0;
    CHECK(mc_wait_done(card, 0, 5000, &at));

    /* Per thread. */
    EXPECT(mc_get_tick(card, NULL), MC_ERR_NULL_POINTER);
    pthread_t t;
    ASSERT(pthread_create(&t, NULL, other_thread, NULL) == 0, "pthread_create");
    ASSERT(pthread_join(t, NULL) == 0, "pthread_join");
    char msg[512];
    ASSERT(strcmp(last_error(msg, sizeof msg), "tick is NULL") == 0, "main thread's message: %s",
           msg);

    /* Close panics too: the card stays open (the panic came first), a second close closes. */
    CHECK(mc__test_panic_next_call());
    EXPECT(mc_close(card), MC_ERR_PANIC);
    CHECK(mc_ping(card));
    CHECK(mc_close(card));
    EXPECT(mc_close(card), MC_ERR_BAD_HANDLE);
    printf("a panic in 4 calls on 2 threads became MC_ERR_PANIC\n");
    printf("PASS panic\n");
    return 0;
}
