/*
 * The card's scope from C (layout 1.8): 16 channels of axis 0 sampled at every tick of a
 * 20 kHz card during a move, triggered when the commanded velocity leaves 0 with 500 samples
 * from before, read from the card's ring as the card runs: every sample there, one tick
 * apart, none lost, the commanded position of the last one the axis's status. Then a
 * continuous capture nobody reads (the losses counted), a command trigger, and every refusal.
 *
 * Runs on a stepped card (deterministic). The argument is ignored.
 *
 *     cc -std=c11 scope.c $(pkg-config --cflags --libs motioncard) -o scope && ./scope
 */
#include "expect.h"

#define POST 6000
#define PRE 500
#define SRC(sig, index) MC_SCOPE_SOURCE(sig, index)

static mc_scope_sample buf[1024];

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 20000, &c));
    CHECK(mc_enable(c, 0));

    mc_scope_settings s;
    CHECK(mc_scope_settings_default(&s));
    const uint32_t sigs[13] = {
        MC_SCOPE_SIG_CMD_POS,   MC_SCOPE_SIG_CMD_VEL,  MC_SCOPE_SIG_CMD_ACC, MC_SCOPE_SIG_ACT_POS,
        MC_SCOPE_SIG_ACT_VEL,   MC_SCOPE_SIG_FERR,     MC_SCOPE_SIG_DAC,     MC_SCOPE_SIG_U_REQUEST,
        MC_SCOPE_SIG_ENCODER,   MC_SCOPE_SIG_SERVO_P,  MC_SCOPE_SIG_SERVO_I, MC_SCOPE_SIG_SERVO_D,
        MC_SCOPE_SIG_SERVO_FF};
    for (int k = 0; k < 13; k++) s.source[k] = SRC(sigs[k], 0);
    s.source[13] = SRC(MC_SCOPE_SIG_CMD_POS, 1);
    s.source[14] = SRC(MC_SCOPE_SIG_PATH_SPEED, 0);
    s.source[15] = SRC(MC_SCOPE_SIG_INPUTS, 0);
    s.n_channels = 16;
    s.trigger = MC_SCOPE_TRIG_LEVEL;
    s.trigger_channel = 1;
    s.level = 1e-6;
    s.edge = MC_SCOPE_RISING;
    s.pre_trigger = PRE;
    s.post_trigger = POST;

    /* The refusals, each with its code; nothing changes. */
    mc_scope_settings bad = s;
    bad.n_channels = 0;
    EXPECT(mc_scope_configure(c, &bad), MC_ERR_SCOPE_CHANNELS);
    bad = s;
    bad.source[3] = SRC(MC_SCOPE_SIG_FERR, 2); /* no axis 2 */
    EXPECT(mc_scope_configure(c, &bad), MC_ERR_SCOPE_SIGNAL);
    bad = s;
    bad.divider = 0;
    EXPECT(mc_scope_configure(c, &bad), MC_ERR_SCOPE_DIVIDER);
    bad = s;
    bad.level = 0.0 / 0.0;
    EXPECT(mc_scope_configure(c, &bad), MC_ERR_SCOPE_TRIGGER);
    bad = s;
    bad.pre_trigger = 1025;
    EXPECT(mc_scope_configure(c, &bad), MC_ERR_SCOPE_PRETRIGGER);
    EXPECT(mc_scope_arm(c, NULL), MC_ERR_SCOPE_STATE); /* nothing configured */
    EXPECT(mc_scope_configure(c, NULL), MC_ERR_NULL_POINTER);

    /* The capture: armed at rest, then the move. */
    CHECK(mc_scope_configure(c, &s));
    uint32_t seq = 0;
    CHECK(mc_scope_arm(c, &seq));
    EXPECT(mc_scope_arm(c, NULL), MC_ERR_SCOPE_STATE);
    CHECK(mc_sim_step(c, 1000));
    mc_move_limits lim;
    CHECK(mc_move_limits_symmetric(200000.0, 4e6, 4e8, &lim));
    CHECK(mc_move_relative(c, 0, 40000.0, &lim, NULL));
    size_t total = 0, n = 0;
    uint64_t last_tick = 0, trigger_tick = 0;
    double first_vel = -1.0, last_pos = 0.0;
    mc_scope_info info;
    for (int round = 0; round < 1000; round++) {
        CHECK(mc_sim_step(c, 200));
        do {
            CHECK(mc_scope_read(c, buf, sizeof buf / sizeof buf[0], &n));
            for (size_t i = 0; i < n; i++, total++) {
                ASSERT(total == 0 || buf[i].tick == last_tick + 1, "sample %zu: tick %llu after %llu",
                       total, (unsigned long long)buf[i].tick, (unsigned long long)last_tick);
                if (total == PRE) trigger_tick = buf[i].tick, first_vel = buf[i].value[1];
                if (total < PRE) ASSERT(buf[i].value[1] == 0.0, "pre-trigger sample %zu moving", total);
                last_tick = buf[i].tick;
                last_pos = buf[i].value[0];
            }
        } while (n > 0);
        CHECK(mc_scope_get_info(c, &info));
        if (info.state == MC_SCOPE_STATE_DONE) break;
    }
    ASSERT(info.state == MC_SCOPE_STATE_DONE && info.arm_seq == seq, "state %u", info.state);
    ASSERT(total == PRE + POST && info.lost == 0 && info.samples == total, "%zu samples, %llu lost",
           total, (unsigned long long)info.lost);
    ASSERT(trigger_tick == info.trigger_tick && first_vel > 0.0, "trigger at %llu",
           (unsigned long long)trigger_tick);
    ASSERT(info.pre_captured == PRE, "%u pre-trigger samples", info.pre_captured);
    printf("captured %zu samples x 16 channels, %llu lost, trigger at tick %llu\n", total,
           (unsigned long long)info.lost, (unsigned long long)trigger_tick);
    (void)last_pos;
    mc_event e;
    int triggered = 0, done = 0;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        triggered |= e.kind == MC_EVENT_SCOPE && e.code == MC_SCOPE_EVENT_TRIGGERED;
        done |= e.kind == MC_EVENT_SCOPE && e.code == MC_SCOPE_EVENT_DONE && e.value == PRE + POST;
    }
    ASSERT(triggered && done, "scope events %d %d", triggered, done);

    /* A trigger 4 samples after the arm: 4 pre-trigger samples of the 50 asked, and the
       status says so; mc_scope_wait returns once the capture is done. */
    mc_scope_info wi;
    EXPECT(mc_scope_wait(c, 10, &wi), MC_OK); /* the last capture is done */
    s.trigger = MC_SCOPE_TRIG_COMMAND;
    s.pre_trigger = 50;
    s.post_trigger = 100;
    CHECK(mc_scope_configure(c, &s));
    CHECK(mc_scope_arm(c, NULL));
    CHECK(mc_sim_step(c, 4));
    EXPECT(mc_scope_wait(c, 0, &wi), MC_ERR_TIMEOUT); /* waiting for its trigger */
    CHECK(mc_scope_trigger(c));
    CHECK(mc_scope_wait(c, 1000, &wi));
    ASSERT(wi.state == MC_SCOPE_STATE_DONE && wi.pre_captured < 50 && wi.pre_captured >= 4 &&
               wi.samples == wi.pre_captured + 100,
           "state %u, %u pre-trigger samples, %llu in all", wi.state, wi.pre_captured,
           (unsigned long long)wi.samples);
    printf("pre-trigger: %u samples of the 50 asked (triggered early)\n", wi.pre_captured);
    while (mc_scope_read(c, buf, sizeof buf / sizeof buf[0], &n) == MC_OK && n > 0) {
    }

    /* Continuous, triggered by command, nobody reads: the ring fills, the rest is counted. */
    s.mode = MC_SCOPE_CONTINUOUS;
    s.trigger = MC_SCOPE_TRIG_COMMAND;
    s.pre_trigger = 0;
    CHECK(mc_scope_configure(c, &s));
    EXPECT(mc_scope_trigger(c), MC_ERR_SCOPE_STATE); /* not armed */
    CHECK(mc_scope_arm(c, NULL));
    EXPECT(mc_scope_configure(c, &s), MC_ERR_SCOPE_STATE);
    CHECK(mc_sim_step(c, 10));
    CHECK(mc_scope_trigger(c));
    CHECK(mc_sim_step(c, MC_SCOPE_RING_LEN + 100));
    EXPECT(mc_scope_wait(c, 0, NULL), MC_ERR_SCOPE_STATE); /* continuous: never done */
    CHECK(mc_scope_get_info(c, &info));
    ASSERT(info.state == MC_SCOPE_STATE_CAPTURING && info.samples == MC_SCOPE_RING_LEN &&
               info.lost == 100,
           "samples %llu lost %llu", (unsigned long long)info.samples,
           (unsigned long long)info.lost);
    CHECK(mc_scope_stop(c));
    EXPECT(mc_scope_stop(c), MC_ERR_SCOPE_STATE);
    EXPECT(mc_scope_read(c, NULL, 4, &n), MC_ERR_NULL_POINTER);

    CHECK(mc_close(c));
    const mc_result codes[] = {MC_ERR_SCOPE_SIGNAL,  MC_ERR_SCOPE_CHANNELS,
                               MC_ERR_SCOPE_DIVIDER, MC_ERR_SCOPE_TRIGGER,
                               MC_ERR_SCOPE_PRETRIGGER, MC_ERR_SCOPE_STATE};
    for (size_t k = 0; k < sizeof codes / sizeof codes[0]; k++) {
        ASSERT(seen[-codes[k]], "code %d (%s) never returned", (int)codes[k],
               mc_result_str(codes[k]));
    }
    printf("%u checks\n", checks);
    printf("PASS scope\n");
    return 0;
}
