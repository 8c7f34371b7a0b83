/*
 * A G-code program from C: a part program in memory (a work offset set by G10 L2 and used, a
 * rectangle with blended corners, the spindle and coolant through the host's hooks, an M0
 * pause and a resume, a message), run on a 3-axis group of a stepped emulated card; the end
 * position checked exactly in machine coordinates. Then a program file with a subroutine and
 * a loop; a host's pause at the end of a block (mc_gcode_pause); the refusals (a wrong line named with its number before anything moves, an M100
 * with no hook, NULL pointers, bad and closed handles). The run's report (mc_gcode_report): its
 * time, deviation, contour and following errors. Last, the spindle on the card's axis 3
 * and flood coolant on output 5: a rigid tap (G33.1) that goes down and comes back to its
 * start with the spindle turning forward again; G33 without a spindle refused with its line.
 * Last, a helix in the G18 plane of a coordinate system rotated about Z.
 *
 * Positions in mm (scale 1000 counts per mm).
 *
 *     cc -std=c11 gcode.c $(pkg-config --cflags --libs motioncard) -lm -o gcode && ./gcode
 */
#include "expect.h"

#include <math.h>

#define RATE 10000u

static const uint32_t G = 0;
static const uint32_t XYZ[3] = {0, 1, 2};

/* What the hooks saw. */
struct seen_hooks {
    int spindle_calls;
    double speed;
    uint32_t direction;
    int coolant_calls;
    uint32_t flood;
    int messages;
    char message[64];
    int pauses;
};

static int on_spindle(double speed, uint32_t direction, void *user) {
    struct seen_hooks *s = user;
    s->spindle_calls++;
    s->speed = speed;
    s->direction = direction;
    return 0;
}

static int on_coolant(uint32_t mist, uint32_t flood, void *user) {
    struct seen_hooks *s = user;
    (void)mist;
    s->coolant_calls++;
    s->flood = flood;
    return 0;
}

static void on_message(uint32_t line, const char *text, void *user) {
    struct seen_hooks *s = user;
    (void)line;
    s->messages++;
    snprintf(s->message, sizeof s->message, "%s", text);
}

static int on_pause(uint32_t kind, void *user) {
    struct seen_hooks *s = user;
    (void)kind;
    s->pauses++;
    return 1; /* pause */
}

static void expect_machine_at(mc_card c, double x, double y, double z, const char *what) {
    const double t[3] = {x, y, z};
    for (int i = 0; i < 3; i++) {
        mc_status s;
        CHECK(mc_get_status(c, XYZ[i], &s));
        ASSERT(fabs(s.command_position - t[i]) < 1e-9, "%s: axis %d at %.9f, expected %.9f",
               what, i, s.command_position, t[i]);
    }
    checks++;
}

static const char PART[] =
    "%\n"
    "(a rectangle 20 x 10 in G54, which G10 puts at X10 Y5)\n"
    "G21 G90 G17 G64 P0.01\n"
    "G10 L2 P1 X10 Y5\n"
    "G54 G0 X0 Y0\n"
    "S1200 M3 M8\n"
    "(MSG, cutting)\n"
    "G1 X20 F1200\n"
    "Y10\n"
    "X0\n"
    "Y0\n"
    "M0\n"
    "G0 Z2\n"
    "M5 M9\n"
    "M2\n"
    "%\n";

static void part(mc_card c) {
    mc_gcode_settings s;
    CHECK(mc_gcode_default_settings(&s));
    ASSERT(strcmp(s.axes, "XYZ") == 0 && s.rapid_feed > 0.0 && s.tolerance > 0.0,
           "defaults: axes %s, rapid %f, tolerance %f", s.axes, s.rapid_feed, s.tolerance);
    mc_gcode p = 0;
    CHECK(mc_gcode_load_string(c, G, PART, NULL, &s, &p));
    ASSERT(p != 0, "handle %u", p);
    struct seen_hooks hooked = {0};
    mc_gcode_hooks hooks = {0};
    hooks.spindle = on_spindle;
    hooks.coolant = on_coolant;
    hooks.message = on_message;
    hooks.pause = on_pause;
    CHECK(mc_gcode_set_hooks(p, &hooks, &hooked));

    uint32_t state = 99;
    CHECK(mc_gcode_run(p, 60000, &state));
    ASSERT(state == MC_GCODE_PAUSED, "state %u at the M0", state);
    ASSERT(hooked.pauses == 1, "%d pauses", hooked.pauses);
    uint32_t running = 99, read = 0;
    CHECK(mc_gcode_line(p, &running, &read));
    ASSERT(read == 12, "paused having read line %u, the M0 is line 12", read);
    /* The rectangle closed at the work origin: machine X10 Y5. */
    expect_machine_at(c, 10.0, 5.0, 0.0, "at the M0");
    ASSERT(hooked.spindle_calls == 1 && hooked.speed == 1200.0 && hooked.direction == 3,
           "spindle: %d calls, %f rpm, M%u", hooked.spindle_calls, hooked.speed, hooked.direction);
    ASSERT(hooked.coolant_calls == 1 && hooked.flood == 1, "coolant: %d calls, flood %u",
           hooked.coolant_calls, hooked.flood);
    ASSERT(hooked.messages == 1 && strstr(hooked.message, "cutting"), "message %d '%s'",
           hooked.messages, hooked.message);

    CHECK(mc_gcode_resume(p));
    CHECK(mc_gcode_run(p, 60000, &state));
    ASSERT(state == MC_GCODE_DONE, "state %u at the end", state);
    expect_machine_at(c, 10.0, 5.0, 2.0, "at the end");
    ASSERT(hooked.spindle_calls == 2 && hooked.direction == 5, "spindle off: %d calls, M%u",
           hooked.spindle_calls, hooked.direction);
    ASSERT(hooked.coolant_calls == 2 && hooked.flood == 0, "coolant off: %d calls, flood %u",
           hooked.coolant_calls, hooked.flood);
    uint32_t line = 99;
    char text[128];
    size_t needed = 0;
    CHECK(mc_gcode_error(p, &line, text, sizeof text, &needed));
    ASSERT(line == 0 && text[0] == 0 && needed == 1, "no error: line %u '%s'", line, text);

    /* What the run did: the card was stepped a tick a poll, so every tick was seen. Six
     * motions (two rapids, four cuts); the 60 mm of cuts at 20 mm/s alone take 3 s; the
     * corners blended within the program's P0.01; the actual path (the plant's encoders)
     * trails the commanded one. */
    mc_path_report r;
    CHECK(mc_gcode_report(p, &r));
    ASSERT(r.segments == 6, "%llu segments", (unsigned long long)r.segments);
    ASSERT(r.ticks == r.ticks_seen && r.ticks > 3 * RATE, "ticks %llu, seen %llu",
           (unsigned long long)r.ticks, (unsigned long long)r.ticks_seen);
    ASSERT(r.path_time > 3.0 && r.path_time < 10.0, "path time %f s", r.path_time);
    ASSERT(r.max_deviation <= 0.0101, "deviation %f mm", r.max_deviation);
    ASSERT(r.peak_velocity_ratio <= 1.0 + 1e-9 && r.peak_acceleration_ratio <= 1.0 + 1e-9,
           "peaks %f %f", r.peak_velocity_ratio, r.peak_acceleration_ratio);
    ASSERT(r.max_following_error > 0.0 && r.max_contour_error > 0.0 &&
               r.max_contour_error <= r.max_following_error + r.max_deviation,
           "following %f mm, contour %f mm", r.max_following_error, r.max_contour_error);
    ASSERT(r.exact_stops >= 2, "%llu stops (the spindle's wait, the M0)",
           (unsigned long long)r.exact_stops);
    printf("G-code report: %.4f s, deviation %.6f mm, contour error %.6f mm, following error "
           "%.6f mm, %llu ticks\n",
           r.path_time, r.max_deviation, r.max_contour_error, r.max_following_error,
           (unsigned long long)r.ticks);
    CHECK(mc_gcode_close(p));
    EXPECT(mc_gcode_close(p), MC_ERR_BAD_HANDLE);
    EXPECT(mc_gcode_poll(p, &state), MC_ERR_BAD_HANDLE);
    printf("G-code part: paused at line %u, ended at machine X10 Y5 Z2\n", read);
}

/* A host's pause at the end of a block: a zigzag under G61 (an exact stop at every corner),
 * paused while its fourth side (line 5) runs, comes to rest exactly on that side's end and
 * holds there; the group's own pause state says so; a resume runs the rest. */
static void pause_at_the_end_of_a_block(mc_card c) {
    char text[512] = "G61 G1 F3000 Z2\n";
    for (int i = 1; i <= 8; i++) {
        char line[32];
        snprintf(line, sizeof line, "X%d Y%d\n", 10 * i, i % 2 ? 10 : 0);
        strcat(text, line);
    }
    /* (back where the program before left the machine, for the refusals after) */
    strcat(text, "G0 X42 Y5 Z-3\nM2\n");
    mc_gcode p = 0;
    CHECK(mc_gcode_load_string(c, G, text, NULL, NULL, &p));
    uint32_t state = 99, running = 0, read = 0;
    for (int k = 0; running != 5; k++) {
        ASSERT(k < 100000, "line 5 never ran (at %u)", running);
        CHECK(mc_gcode_poll(p, &state));
        CHECK(mc_sim_step(c, 1));
        CHECK(mc_gcode_line(p, &running, &read));
    }
    CHECK(mc_gcode_pause(p));
    CHECK(mc_gcode_run(p, 60000, &state));
    ASSERT(state == MC_GCODE_PAUSED, "state %u after the pause", state);
    CHECK(mc_gcode_line(p, &running, &read));
    ASSERT(running == 5, "paused after line %u", running);
    uint32_t ps = 99, id = 0;
    CHECK(mc_group_path_pause_state(c, G, &ps, &id));
    ASSERT(ps == MC_PATH_PAUSE_PAUSED && id == 5, "pause state %u, id %u", ps, id);
    /* line 1 lifts Z to 2; line n + 1 is the n-th side: line 5 ends at X40 Y0 (this
       program's coordinates are the machine's: no offset of the part before is its own) */
    expect_machine_at(c, 40.0, 0.0, 2.0, "paused");
    CHECK(mc_sim_step(c, 1000));
    expect_machine_at(c, 40.0, 0.0, 2.0, "held");
    CHECK(mc_gcode_resume(p));
    CHECK(mc_gcode_run(p, 60000, &state));
    ASSERT(state == MC_GCODE_DONE, "state %u at the end", state);
    expect_machine_at(c, 42.0, 5.0, -3.0, "at the end");
    CHECK(mc_group_path_pause_state(c, G, &ps, NULL));
    ASSERT(ps == MC_PATH_PAUSE_NONE, "pause state %u after the run", ps);
    EXPECT(mc_group_path_pause_state(c, G, NULL, NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_gcode_close(p));
    printf("G-code pause: at rest on the end of line 5 (X40 Y0), then on to the end\n");
}

/* A subroutine called in a while loop, from a file: three passes down in Z. */
static void file_with_a_loop(mc_card c) {
    const char *path = "gcode_loop.ngc";
    FILE *f = fopen(path, "w");
    ASSERT(f != NULL, "cannot write %s", path);
    fputs("o100 sub\n"
          "  G1 Z[#1] F600\n"
          "o100 endsub\n"
          "#1 = 42\n"
          "#2 = 0\n"
          "o101 while [#2 LT 3]\n"
          "  #2 = [#2 + 1]\n"
          "  o100 call [-#2]\n"
          "o101 endwhile\n"
          "G0 X[#1]\n"
          "M30\n",
          f);
    fclose(f);
    mc_gcode p = 0;
    CHECK(mc_gcode_load_file(c, G, path, NULL, NULL, &p));
    uint32_t state = 99;
    CHECK(mc_gcode_run(p, 60000, &state));
    ASSERT(state == MC_GCODE_DONE, "state %u", state);
    /* Three passes to Z -3; #1 restored to 42 after each call. A program's parameters are
       its own: the G54 offset of the part before is not this one's. */
    expect_machine_at(c, 42.0, 5.0, -3.0, "after the loop");
    CHECK(mc_gcode_close(p));
    remove(path);
    printf("G-code file: a subroutine in a loop, ended at X42 Z-3\n");
}

static void refusals(mc_card c) {
    mc_gcode p = 0;
    /* A wrong line: refused at load, nothing queued, the line in the message. */
    EXPECT(mc_gcode_load_string(c, G, "G1 X1 F100\nG1 X2 Y\n", NULL, NULL, &p), MC_ERR_GCODE);
    expect_in_message("line 2");
    ASSERT(p == 0, "handle written on failure: %u", p);
    EXPECT(mc_gcode_load_string(c, G, NULL, NULL, NULL, &p), MC_ERR_NULL_POINTER);
    EXPECT(mc_gcode_load_string(c, G, "G0 X1", NULL, NULL, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_gcode_load_file(c, G, "/nonexistent/part.ngc", NULL, NULL, &p), MC_ERR_IO);
    EXPECT(mc_gcode_load_string(c, 7, "G0 X1", NULL, NULL, &p), MC_ERR_BAD_GROUP);
    mc_gcode_settings bad;
    CHECK(mc_gcode_default_settings(&bad));
    bad.rapid_feed = NAN;
    EXPECT(mc_gcode_load_string(c, G, "G0 X1", NULL, &bad, &p), MC_ERR_BAD_CONFIG);
    CHECK(mc_gcode_default_settings(&bad));
    strcpy(bad.axes, "XY");
    EXPECT(mc_gcode_load_string(c, G, "G0 X1", NULL, &bad, &p), MC_ERR_BAD_CONFIG);
    CHECK(mc_gcode_default_settings(&bad));
    ASSERT(bad.probe_input == -1, "default probe input %d", bad.probe_input);
    bad.probe_input = 16;
    EXPECT(mc_gcode_load_string(c, G, "G0 X1", NULL, &bad, &p), MC_ERR_BAD_CONFIG);
    CHECK(mc_gcode_default_settings(&bad));
    ASSERT(bad.report == 1, "default report %u", bad.report);
    bad.report = 2;
    EXPECT(mc_gcode_load_string(c, G, "G0 X1", NULL, &bad, &p), MC_ERR_BAD_CONFIG);
    EXPECT(mc_gcode_poll(0, NULL), MC_ERR_BAD_HANDLE);
    EXPECT(mc_gcode_default_settings(NULL), MC_ERR_NULL_POINTER);
    mc_path_report r;
    EXPECT(mc_gcode_report(0, &r), MC_ERR_BAD_HANDLE);
    /* Loaded not to be measured: no report. */
    bad.report = 0;
    CHECK(mc_gcode_load_string(c, G, "G0 X1\n", NULL, &bad, &p));
    EXPECT(mc_gcode_report(p, &r), MC_ERR_UNSUPPORTED);
    EXPECT(mc_gcode_report(p, NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_gcode_close(p));

    /* M100 with no hook: the run stops there with its line. */
    CHECK(mc_gcode_load_string(c, G, "G0 X1\nM100 P3\nG0 X2\n", NULL, NULL, &p));
    uint32_t state = 99;
    EXPECT(mc_gcode_run(p, 60000, &state), MC_ERR_UNSUPPORTED);
    uint32_t line = 0;
    char text[256];
    size_t needed = 0;
    CHECK(mc_gcode_error(p, &line, text, sizeof text, &needed));
    ASSERT(line == 2 && strstr(text, "M100"), "error at line %u: %s", line, text);
    CHECK(mc_gcode_poll(p, &state));
    ASSERT(state == MC_GCODE_ABORTED, "state %u after the error", state);
    expect_machine_at(c, 1.0, 5.0, -3.0, "stopped before line 3");
    CHECK(mc_gcode_close(p));

    /* A probing move with no probe input in the settings: an error naming its line. */
    CHECK(mc_gcode_load_string(c, G, "G0 X1\nG38.2 Z-10 F100\n", NULL, NULL, &p));
    EXPECT(mc_gcode_run(p, 60000, &state), MC_ERR_GCODE);
    CHECK(mc_gcode_error(p, &line, text, sizeof text, &needed));
    ASSERT(line == 2 && strstr(text, "probe input"), "error at line %u: %s", line, text);
    CHECK(mc_gcode_close(p));
    printf("G-code refusals: %u checks\n", checks);
}

/* The spindle on axis 3 (revolutions: 10,000 counts each), flood on output 5: S600 M3 turns
   it at 10 rev/s, M8 sets the output, G33.1 taps 5 mm at 1 mm a turn and comes back. */
static void spindle_on_the_card(mc_card c) {
    const uint32_t SPINDLE = 3;
    CHECK(mc_set_scale(c, SPINDLE, 10000.0));
    CHECK(mc_enable(c, SPINDLE));
    mc_gcode_settings s;
    CHECK(mc_gcode_default_settings(&s));
    ASSERT(s.spindle_axis == -1 && s.mist_output == -1 && s.flood_output == -1,
           "defaults: spindle %d, mist %d, flood %d", s.spindle_axis, s.mist_output,
           s.flood_output);
    mc_gcode p = 0;
    /* Without a spindle on the card G33 is refused when it is read, with its line. */
    CHECK(mc_gcode_load_string(c, G, "S600 M3\nG33 Z-8 K1\nM2\n", NULL, &s, &p));
    uint32_t state = 99;
    EXPECT(mc_gcode_run(p, 60000, &state), MC_ERR_GCODE);
    uint32_t line = 0;
    char text[256];
    size_t needed = 0;
    CHECK(mc_gcode_error(p, &line, text, sizeof text, &needed));
    ASSERT(line == 2 && strstr(text, "no spindle"), "error at line %u: %s", line, text);
    CHECK(mc_gcode_close(p));
    /* A spindle axis that is one of the group's is a bad configuration. */
    s.spindle_axis = 2;
    EXPECT(mc_gcode_load_string(c, G, "M2\n", NULL, &s, &p), MC_ERR_BAD_CONFIG);

    s.spindle_axis = (int32_t)SPINDLE;
    s.flood_output = 5;
    CHECK(mc_gcode_load_string(c, G, "S600 M3 M8\nG0 Z2\nG33.1 Z-3 K1\nM2\n", NULL, &s, &p));
    CHECK(mc_gcode_run(p, 60000, &state));
    ASSERT(state == MC_GCODE_DONE, "state %u", state);
    expect_machine_at(c, 1.0, 5.0, 2.0, "after the tap");
    mc_status sp;
    CHECK(mc_get_status(c, SPINDLE, &sp));
    ASSERT(sp.command_velocity == 10.0, "the spindle at %f rev/s after the tap",
           sp.command_velocity);
    uint32_t outputs = 0;
    CHECK(mc_get_outputs(c, &outputs));
    ASSERT(outputs & (1u << 5), "flood output off: %08x", outputs);
    CHECK(mc_gcode_close(p));
    checks++;
    printf("G-code spindle: a tap to Z-3 and back to Z2, the spindle at %.1f rev/s\n",
           sp.command_velocity);
}

/* A helix in a G18 plane of a coordinate system rotated 30 degrees about Z (G10 L2 R30): it
   runs on the card as an arc about the rotated Y axis (MC_OP_PATH_ARC_NORMAL), 1.75 turns of
   radius 5 rising 6 mm along that axis, and ends exactly where the rotated system puts the
   program's end; the run's report finds the commanded path on the programmed helix. */
static void rotated_helix(mc_card c) {
    mc_gcode p = 0;
    CHECK(mc_gcode_load_string(c, G,
                               "G21 G90 G61\n"
                               "G10 L2 P1 X3 Y-4 R30\n"
                               "G54 G0 X0 Y0 Z0\n"
                               "G18 G2 X5 Z5 Y6 I5 K0 P2 F1200\n"
                               "M2\n",
                               NULL, NULL, &p));
    uint32_t state = 99;
    CHECK(mc_gcode_run(p, 600000, &state));
    ASSERT(state == MC_GCODE_DONE, "state %u", state);
    const double s30 = 0.5, c30 = sqrt(3.0) / 2.0;
    /* work X5 Y6 Z5 turned 30 degrees, then moved to X3 Y-4 */
    expect_machine_at(c, 3.0 + 5.0 * c30 - 6.0 * s30, -4.0 + 5.0 * s30 + 6.0 * c30, 5.0,
                      "at the helix's end");
    mc_path_report r;
    CHECK(mc_gcode_report(p, &r));
    ASSERT(r.max_deviation <= 1e-6, "deviation %g mm", r.max_deviation);
    ASSERT(r.path_time > 2.5, "path time %f s (55 mm of helix at 20 mm/s)", r.path_time);
    CHECK(mc_gcode_close(p));
    printf("G-code rotated helix: ended on the rotated plane's helix, deviation %.2g mm\n",
           r.max_deviation);
}

int main(void) {
    mc_card c = 0;
    CHECK(mc_open_sim_stepped(4, RATE, &c));
    for (int i = 0; i < 3; i++) {
        CHECK(mc_set_scale(c, XYZ[i], 1000.0));
        CHECK(mc_enable(c, XYZ[i]));
    }
    mc_group_settings gs;
    CHECK(mc_group_settings_new(XYZ, 3, &gs));
    CHECK(mc_group_configure(c, G, &gs));
    CHECK(mc_group_enable(c, G));
    mc_path_settings ps;
    CHECK(mc_path_settings_uniform(3, 100.0, 1000.0, 1e5, &ps));
    CHECK(mc_group_configure_path(c, G, &ps));

    part(c);
    file_with_a_loop(c);
    pause_at_the_end_of_a_block(c);
    refusals(c);
    spindle_on_the_card(c);
    rotated_helix(c);

    CHECK(mc_close(c));
    printf("PASS gcode (%u checks)\n", checks);
    return 0;
}
