/*
 * Analog I/O and the path-speed output from C (layout 1.11): an analog input's threshold event,
 * the ADC's sample, a spare DAC's quantised output, the PSO on a group gated by a digital
 * output, and the refusals.
 *
 * Runs on a stepped card (deterministic). The argument is ignored.
 *
 *     cc -std=c11 analog.c $(pkg-config --cflags --libs motioncard) -lm -o analog && ./analog
 */
#include <math.h>

#include "expect.h"

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_enable(c, 1));

    /* The refusals, each with its own code. */
    mc_analog_input_settings in = {0};
    in.threshold = 2.0;
    in.hysteresis = 0.5;
    in.rise_event = 1;
    in.fall_event = 1;
    EXPECT(mc_analog_input_configure(c, 8, &in), MC_ERR_ANALOG_CHANNEL);
    expect_in_message("analog");
    in.cutoff_hz = 6000.0; /* above Nyquist at 10 kHz */
    EXPECT(mc_analog_input_configure(c, 0, &in), MC_ERR_ANALOG_FILTER);
    in.cutoff_hz = 0.0;
    in.threshold = 11.0;
    EXPECT(mc_analog_input_configure(c, 0, &in), MC_ERR_ANALOG_THRESHOLD);
    in.threshold = 2.0;
    EXPECT(mc_analog_output_set(c, 4, 1.0, NULL), MC_ERR_ANALOG_CHANNEL);
    EXPECT(mc_analog_output_set(c, 0, NAN, NULL), MC_ERR_NOT_FINITE);
    mc_pso_settings pso = {0};
    pso.output = 2;
    pso.gate = 5;
    pso.min = 1.0;
    pso.max = 8.0;
    pso.v_ref = 50000.0;
    pso.filter_hz = 200.0;
    EXPECT(mc_pso_configure(c, 0, &pso), MC_ERR_PSO_GROUP); /* not configured */
    EXPECT(mc_pso_configure(c, 7, &pso), MC_ERR_PSO_GROUP); /* no such group */
    const uint32_t XY[] = {0, 1};
    mc_group_settings g;
    CHECK(mc_group_settings_new(XY, 2, &g));
    CHECK(mc_group_configure(c, 0, &g));
    pso.min = 9.0; /* min > max */
    EXPECT(mc_pso_configure(c, 0, &pso), MC_ERR_PSO_CONFIG);
    pso.min = 1.0;

    /* An input at 2.5 V, no filter: the threshold at 2 V posts MC_EVENT_ANALOG at once. */
    CHECK(mc_analog_input_configure(c, 0, &in));
    CHECK(mc_sim_set_analog_input(c, 0, 2.5));
    CHECK(mc_sim_step(c, 1));
    mc_event e;
    int found = 0;
    while (mc_wait_event(c, 0, &e) == MC_OK) {
        if (e.kind == MC_EVENT_ANALOG) {
            ASSERT(e.axis == 0 && e.code == 1 && e.value == 2.5, "event %d %d %f", e.axis, e.code,
                   e.value);
            found = 1;
        }
    }
    ASSERT(found, "no MC_EVENT_ANALOG");
    mc_analog_input_info info;
    CHECK(mc_analog_input_read(c, 0, &info));
    ASSERT(info.sample == 2.5 && info.above == 1 && info.settings.threshold == 2.0,
           "input 0: %f above %u", info.sample, info.above);
    CHECK(mc_sim_set_analog_input(c, 0, 1.0));
    CHECK(mc_sim_step(c, 1));
    CHECK(mc_analog_input_read(c, 0, &info));
    printf("analog: 1 V reads %.9f V (%.1f LSB)\n", info.sample, info.sample * 65536.0 / 20.0);

    /* A spare DAC: 3.3 V comes out as the 12-bit DAC's nearest step. */
    double v = 0.0;
    CHECK(mc_analog_output_set(c, 1, 3.3, &v));
    ASSERT(v == 676.0 * 20.0 / 4096.0, "DAC 1 puts out %f", v);
    CHECK(mc_sim_step(c, 1));
    double back = 0.0;
    CHECK(mc_analog_output_get(c, 1, &back));
    ASSERT(back == v, "read back %f", back);
    printf("analog: DAC 1 set to 3.3 V puts out %.8f V\n", back);

    /* The PSO on DAC 2: closed (0 V) until output 5 is on, then min at rest. */
    CHECK(mc_pso_configure(c, 0, &pso));
    EXPECT(mc_analog_output_set(c, 2, 1.0, NULL), MC_ERR_ANALOG_CHANNEL); /* the PSO's */
    CHECK(mc_sim_step(c, 1));
    mc_pso_info p;
    CHECK(mc_pso_get_info(c, &p));
    ASSERT(p.state == MC_PSO_STATE_CLOSED && p.value == 0.0, "PSO %u %f", p.state, p.value);
    CHECK(mc_set_outputs(c, 1u << 5, 1u << 5));
    CHECK(mc_sim_step(c, 1));
    CHECK(mc_pso_get_info(c, &p));
    ASSERT(p.state == MC_PSO_STATE_ON && p.value == 205.0 * 20.0 / 4096.0 && p.speed_counts == 0.0,
           "PSO %u %f %f", p.state, p.value, p.speed_counts);
    CHECK(mc_pso_off(c));
    CHECK(mc_sim_step(c, 1));
    CHECK(mc_analog_output_get(c, 2, &back));
    ASSERT(back == 0.0, "DAC 2 after the PSO: %f", back);

    /* The PSO as a PWM on digital output 3: no compare channel may pulse that output (layout
       1.12), and the channel stays free for another one. */
    pso.pwm = 1;
    pso.output = 3;
    pso.pwm_hz = 1000.0;
    pso.min = 0.0;
    pso.max = 1.0;
    CHECK(mc_pso_configure(c, 0, &pso));
    EXPECT(mc_compare_single(c, 0, 0, 3, 100, 10.0, MC_COMPARE_POSITIVE), MC_ERR_PSO_OUTPUT);
    CHECK(mc_compare_single(c, 0, 0, 4, 100, 10.0, MC_COMPARE_POSITIVE));
    CHECK(mc_compare_disarm(c, 0, 0));
    CHECK(mc_pso_off(c));

    CHECK(mc_close(c));
    printf("%u checks\n", checks);
    printf("PASS analog\n");
    return 0;
}
