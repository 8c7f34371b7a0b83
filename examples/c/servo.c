/*
 * The PID + feed-forward servo law and the servo output's biquad filters from C (layout 1.11):
 * the default PID+FF gains, the switch to them and back at rest without a step of the DAC, the
 * gains read back, a notch and a low-pass set, read back with the card's coefficients and
 * cleared, a move under them, and the refusals (nothing changes).
 *
 * Runs on a stepped card (deterministic). Positions in counts. The argument is ignored.
 *
 *     cc -std=c11 servo.c $(pkg-config --cflags --libs motioncard) -lm -o servo && ./servo
 */
#include "expect.h"

#include <math.h>

static double dac(mc_card c) {
    mc_status s;
    CHECK(mc_get_status(c, 0, &s));
    return s.dac_volts;
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(1, 10000, &c));
    CHECK(mc_enable(c, 0));
    CHECK(mc_sim_step(c, 1000));

    /* PID+FF with the default tuning; read back. */
    mc_pidff_settings pid, back;
    uint32_t active = 7;
    CHECK(mc_pidff_settings_for_drive(0.0, 0.0, &pid));
    CHECK(mc_axis_get_pidff(c, 0, &back, &active));
    ASSERT(active == 0, "PID+FF active before it was set");
    double before = dac(c);
    CHECK(mc_axis_configure_pidff(c, 0, &pid));
    CHECK(mc_sim_step(c, 10));
    ASSERT(fabs(dac(c) - before) < 0.01, "the switch stepped the DAC: %g -> %g", before, dac(c));
    CHECK(mc_axis_get_pidff(c, 0, &back, &active));
    ASSERT(active == 1 && back.kp == pid.kp && back.friction_deadband == pid.friction_deadband,
           "PID+FF read back");

    /* The refusals: nothing changes. */
    mc_pidff_settings bad = pid;
    bad.ki = -1.0;
    EXPECT(mc_axis_configure_pidff(c, 0, &bad), MC_ERR_PIDFF_GAINS);
    bad = pid;
    bad.kd = NAN;
    EXPECT(mc_axis_configure_pidff(c, 0, &bad), MC_ERR_NOT_FINITE);
    EXPECT(mc_pidff_settings_for_drive(-1.0, 60.0, &bad), MC_ERR_BAD_CONFIG);
    CHECK(mc_axis_get_pidff(c, 0, &back, &active));
    ASSERT(active == 1 && back.ki == pid.ki, "a refused gain was kept");

    /* A notch at 300 Hz, -20 dB, and a low-pass at 1.5 kHz. */
    mc_servo_filter notch = {0}, low = {0}, got;
    notch.kind = MC_BIQUAD_NOTCH;
    notch.freq_hz = 300.0;
    notch.damping = 0.2;
    notch.depth_db = -20.0;
    low.kind = MC_BIQUAD_LOWPASS;
    low.freq_hz = 1500.0;
    low.damping = 0.7;
    CHECK(mc_axis_set_servo_filter(c, 0, 0, &notch));
    CHECK(mc_axis_set_servo_filter(c, 0, 1, &low));
    CHECK(mc_axis_get_servo_filter(c, 0, 0, &got));
    ASSERT(got.kind == MC_BIQUAD_NOTCH && got.freq_hz == 300.0, "the notch read back");
    /* The notch's DC gain is 1: (b0 + b1 + b2) / (1 + a1 + a2). */
    double dc = (got.coeffs[0] + got.coeffs[1] + got.coeffs[2]) /
                (1.0 + got.coeffs[3] + got.coeffs[4]);
    ASSERT(fabs(dc - 1.0) < 1e-9, "notch DC gain %g", dc);

    mc_servo_filter f = notch;
    f.freq_hz = 5000.0; /* the Nyquist frequency at 10 kHz */
    EXPECT(mc_axis_set_servo_filter(c, 0, 2, &f), MC_ERR_FILTER_FREQ);
    f = notch;
    f.depth_db = 6.0;
    EXPECT(mc_axis_set_servo_filter(c, 0, 2, &f), MC_ERR_FILTER_PARAM);
    f = notch;
    f.kind = 9;
    EXPECT(mc_axis_set_servo_filter(c, 0, 2, &f), MC_ERR_FILTER_KIND);
    EXPECT(mc_axis_set_servo_filter(c, 0, MC_BIQUADS, &notch), MC_ERR_FILTER_KIND);
    mc_servo_filter raw = {0};
    raw.kind = MC_BIQUAD_RAW;
    raw.coeffs[0] = 1.0;
    raw.coeffs[3] = -1.5; /* a pole at 1.5 */
    EXPECT(mc_axis_set_servo_filter(c, 0, 2, &raw), MC_ERR_FILTER_UNSTABLE);
    f = notch;
    f.damping = INFINITY;
    EXPECT(mc_axis_set_servo_filter(c, 0, 2, &f), MC_ERR_NOT_FINITE);
    CHECK(mc_axis_get_servo_filter(c, 0, 2, &got));
    ASSERT(got.kind == MC_BIQUAD_NONE, "a refused filter was kept");

    /* A move under PID+FF and both filters ends in position. */
    mc_move_limits lim = {1e5, 1e6, 1e6, {1e8, 1e8, 1e8, 1e8}};
    mc_motion m;
    double at = 0.0;
    CHECK(mc_move_relative(c, 0, 20000.0, &lim, &m));
    CHECK(mc_motion_wait(c, m, 10000, &at));
    ASSERT(fabs(at - 20000.0) <= 1.0, "ended at %g", at);

    /* Cleared; back to FFPIV (bumpless). */
    CHECK(mc_axis_clear_servo_filter(c, 0, 0));
    CHECK(mc_axis_clear_servo_filter(c, 0, 1));
    CHECK(mc_axis_get_servo_filter(c, 0, 1, &got));
    ASSERT(got.kind == MC_BIQUAD_NONE, "a cleared filter was kept");
    mc_axis_settings s;
    CHECK(mc_axis_get_settings(c, 0, &s));
    ASSERT(s.servo_law == MC_SERVO_PIDFF, "law %u", s.servo_law);
    CHECK(mc_configure(c, 0, &s));
    CHECK(mc_axis_get_pidff(c, 0, &back, &active));
    ASSERT(active == 0, "still PID+FF");

    printf("servo: PID+FF kp %.3g V/count, notch at 300 Hz and low-pass at 1500 Hz; move ended at %.0f\n",
           pid.kp, at);
    CHECK(mc_close(c));
    printf("PASS servo (%u refusals)\n", checks);
    return 0;
}
