/*
 * Open the emulated card, configure an axis in millimetres, move it and wait until it is in
 * position, then check where it ended and what the card measured during the move.
 *
 *     cc -std=c11 move.c $(pkg-config --cflags --libs motioncard) -o move && ./move [sim|stepped|URI]
 */
#include "check.h"

#include <math.h>

int main(int argc, char **argv) {
    char version[32];
    size_t needed = 0;
    CHECK(mc_version_string(version, sizeof version, &needed));
    ASSERT(needed == strlen(version) + 1, "needed %zu for \"%s\"", needed, version);
    uint32_t packed = 0;
    CHECK(mc_version(&packed));

    mc_card card = 0;
    CHECK(open_from_args(argc, argv, &card));
    mc_card_info info;
    CHECK(mc_get_info(card, &info));
    printf("libmotioncard %s (%#x), firmware %u.%u.%u, layout %u.%u, %u axes at %u Hz\n",
           version, packed, info.firmware_version >> 16, (info.firmware_version >> 8) & 0xff,
           info.firmware_version & 0xff, info.layout_major, info.layout_minor, info.axes,
           info.servo_rate_hz);
    ASSERT(info.axes == 8 && info.capabilities & MC_CARD_CAP_SCURVE, "axes %u caps %#x",
           info.axes, info.capabilities);

    /* Axis 0 drives a 5 mm lead screw with a 10,000 count/rev encoder: 2,000 counts per mm. */
    const uint32_t x = 0;
    const double counts_per_mm = 10000.0 / 5.0;
    CHECK(mc_set_scale(card, x, counts_per_mm));
    mc_axis_settings settings;
    CHECK(mc_axis_settings_default(&settings));
    settings.in_pos_window = 2.0; /* counts */
    CHECK(mc_configure(card, x, &settings));
    CHECK(mc_enable(card, x));

    mc_move_limits limits; /* mm/s, mm/s^2, mm/s^3 */
    CHECK(mc_move_limits_symmetric(100.0, 2000.0, 50000.0, &limits));
    limits.deceleration = 1000.0;
    mc_motion motion;
    CHECK(mc_move_absolute(card, x, 25.0, &limits, &motion));
    double at = 0.0;
    CHECK(mc_motion_wait(card, motion, 10000, &at)); /* motion done = in position */

    mc_status s;
    CHECK(mc_get_status(card, x, &s));
    const double window_mm = settings.in_pos_window / counts_per_mm;
    ASSERT(fabs(at - 25.0) <= window_mm, "done at %.6f mm", at);
    ASSERT(s.state == MC_AXIS_STATE_STANDSTILL, "state %u", s.state);
    ASSERT(s.raw.move_count == 1 && s.raw.target == 25.0 * counts_per_mm,
           "move_count %u target %f", s.raw.move_count, s.raw.target);
    /* The card measured the move: its peaks stay within the limits (in counts). */
    ASSERT(s.raw.peak_vel <= 100.0 * counts_per_mm * (1 + 1e-9), "peak v %f", s.raw.peak_vel);
    ASSERT(s.raw.peak_acc <= 2000.0 * counts_per_mm * (1 + 1e-9), "peak a %f", s.raw.peak_acc);
    ASSERT(s.raw.peak_dec <= 1000.0 * counts_per_mm * (1 + 1e-9), "peak d %f", s.raw.peak_dec);
    ASSERT(s.raw.move_time >= s.raw.planned_time, "done before the profile ended");
    printf("moved axis 0 to %.4f mm (target 25 mm) in %.3f s (planned %.3f s), "
           "peak following error %.4f mm\n",
           at, s.raw.move_time, s.raw.planned_time, s.raw.max_ferr / counts_per_mm);

    /* A relative move back, waited for as the axis's last motion. */
    CHECK(mc_move_relative(card, x, -5.0, &limits, NULL));
    CHECK(mc_wait_done(card, x, 10000, &at));
    ASSERT(fabs(at - 20.0) <= window_mm, "done at %.6f mm", at);
    printf("moved axis 0 back to %.4f mm\n", at);

    CHECK(mc_disable(card, x));
    CHECK(mc_get_status(card, x, &s));
    ASSERT(s.state == MC_AXIS_STATE_DISABLED, "state %u", s.state);
    CHECK(mc_close(card));
    printf("PASS move\n");
    return 0;
}
