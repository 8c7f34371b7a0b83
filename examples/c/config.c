/*
 * Configuration files from C (layout 1.8): a card set up through the setters, its settings
 * read back from the card with the getters, saved to a TOML file, loaded on a fresh card and
 * saved again (the same bytes), compared with mc_config_diff, and a file with one bad value
 * refused (MC_ERR_CONFIG_FILE, the message naming the key and its line) without changing the
 * card.
 *
 * Runs on stepped cards (deterministic). The files go to $TMPDIR (or /tmp), named after the
 * process. The argument is ignored.
 *
 *     cc -std=c11 config.c $(pkg-config --cflags --libs motioncard) -o config && ./config
 */
#define _POSIX_C_SOURCE 200809L
#include "expect.h"

#include <math.h>
#include <unistd.h>

/* The whole of a small file. */
static char *slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    ASSERT(f, "open %s", path);
    static char buf[65536];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    ASSERT(n < sizeof buf - 1, "%s is too large", path);
    buf[n] = 0;
    char *s = malloc(n + 1);
    ASSERT(s, "malloc");
    memcpy(s, buf, n + 1);
    return s;
}

static void spit(const char *path, const char *text) {
    FILE *f = fopen(path, "wb");
    ASSERT(f && fputs(text, f) >= 0 && fclose(f) == 0, "write %s", path);
}

int main(int argc, char **argv) {
    (void)argc;
    (void)argv;
    const char *dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char a_path[512], b_path[512], bad_path[512];
    snprintf(a_path, sizeof a_path, "%s/mc_config_%ld_a.toml", dir, (long)getpid());
    snprintf(b_path, sizeof b_path, "%s/mc_config_%ld_b.toml", dir, (long)getpid());
    snprintf(bad_path, sizeof bad_path, "%s/mc_config_%ld_bad.toml", dir, (long)getpid());

    /* Card A, set up through the setters. */
    mc_card a = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &a));
    mc_axis_settings s;
    CHECK(mc_axis_settings_default(&s));
    s.ffpiv.kp *= 1.5;
    s.in_pos_window = 3.0;
    CHECK(mc_configure(a, 0, &s));
    CHECK(mc_set_scale(a, 0, 1000.0));
    mc_homing_settings h;
    CHECK(mc_homing_settings_default(&h));
    h.method = 17;
    h.flags = MC_HOMING_FLAG_MOVE_TO_HOME;
    CHECK(mc_configure_homing(a, 1, &h));
    mc_io_settings io;
    CHECK(mc_io_settings_default(&io));
    io.polarity = 0x3;
    io.debounce[2] = 7;
    CHECK(mc_configure_io(a, &io));
    mc_pdplus_settings pd;
    CHECK(mc_pdplus_settings_die_bonder(1, &pd));
    CHECK(mc_axis_configure_pdplus(a, 1, &pd));

    /* The getters read back what the card holds. */
    mc_axis_settings back;
    EXPECT(mc_axis_get_settings(a, 0, NULL), MC_ERR_NULL_POINTER);
    EXPECT(mc_axis_get_settings(a, 7, &back), MC_ERR_BAD_AXIS);
    CHECK(mc_axis_get_settings(a, 0, &back));
    ASSERT(back.ffpiv.kp == s.ffpiv.kp && back.in_pos_window == 3.0 && back.scale == 1000.0,
           "axis settings: kp %g window %g scale %g", back.ffpiv.kp, back.in_pos_window,
           back.scale);
    mc_pdplus_settings pd_back;
    uint32_t active = 9;
    CHECK(mc_axis_get_pdplus(a, 1, &pd_back, &active));
    ASSERT(active == 1 && pd_back.gains.kp == pd.gains.kp && pd_back.umax == pd.umax, "PD+");
    CHECK(mc_axis_get_pdplus(a, 0, &pd_back, &active));
    ASSERT(active == 0 && pd_back.umax == 0.0, "FFPIV axis: no PD+");
    mc_homing_settings h_back;
    CHECK(mc_axis_get_homing(a, 1, &h_back));
    ASSERT(h_back.method == 17 && h_back.flags == MC_HOMING_FLAG_MOVE_TO_HOME, "homing");
    mc_io_settings io_back;
    CHECK(mc_get_io_settings(a, &io_back));
    ASSERT(io_back.polarity == 0x3 && io_back.debounce[2] == 7, "io");
    mc_filter_settings f;
    CHECK(mc_axis_get_filters(a, 0, &f));
    ASSERT(f.rapid.kind == MC_FILTER_KIND_BELL && f.cutting.kind == MC_FILTER_KIND_LINEAR, "filters");
    mc_safety_settings sf;
    CHECK(mc_axis_get_safety(a, 0, &sf));
    ASSERT(sf.hard_limits == 1 && sf.ferror == 10.0, "safety in user units: ferror %g",
           sf.ferror);
    mc_card_safety_settings cs;
    CHECK(mc_get_card_safety(a, &cs));
    ASSERT(cs.watchdog_timeout_us == 100000 && cs.max_stop_time_us == 2000000, "card safety");
    uint32_t hz = 0;
    CHECK(mc_get_servo_rate(a, &hz));
    ASSERT(hz == 10000, "servo rate %u", hz);
    mc_group_settings g;
    uint32_t configured = 9;
    CHECK(mc_group_get_settings(a, 0, &g, &configured));
    ASSERT(configured == 0 && g.naxes == 0, "group 0 is not configured");

    /* Save, load on a fresh card, save: the same bytes. */
    EXPECT(mc_config_save(a, NULL), MC_ERR_NULL_POINTER);
    CHECK(mc_config_save(a, a_path));
    mc_card b = 0;
    CHECK(mc_open_sim_stepped(2, 10000, &b));
    char diff[8192];
    size_t needed = 0;
    uint32_t n = 0;
    CHECK(mc_config_diff(b, a_path, &n, diff, sizeof diff, &needed));
    ASSERT(n >= 4 && strstr(diff, "axis.0.ffpiv.kp: file ") && needed == strlen(diff) + 1,
           "%u differences:\n%s", n, diff);
    EXPECT(mc_config_diff(b, a_path, &n, diff, 4, &needed), MC_ERR_BUFFER_TOO_SMALL);
    CHECK(mc_config_load(b, a_path));
    CHECK(mc_config_save(b, b_path));
    char *ta = slurp(a_path), *tb = slurp(b_path);
    ASSERT(strcmp(ta, tb) == 0, "the files differ:\n%s\n----\n%s", ta, tb);
    CHECK(mc_config_diff(b, a_path, &n, diff, sizeof diff, &needed));
    ASSERT(n == 0 && diff[0] == 0, "equal: %u", n);

    /* One bad value: refused with its key and line, the card unchanged. */
    char *at = strstr(ta, "\nkp = ");
    ASSERT(at, "kp in the file");
    size_t line = 2;
    for (const char *p = ta; p < at; p++) line += *p == '\n';
    size_t cut = (size_t)(at - ta) + 1, rest = strcspn(at + 1, "\n");
    char *bad = malloc(strlen(ta) + 32);
    ASSERT(bad, "malloc");
    memcpy(bad, ta, cut);
    strcpy(bad + cut, "kp = -1.0");
    strcat(bad, at + 1 + rest);
    spit(bad_path, bad);
    EXPECT(mc_config_load(b, bad_path), MC_ERR_CONFIG_FILE);
    char want[600], msg[512];
    snprintf(want, sizeof want, "%s:%zu: axis.0.ffpiv.kp: ", bad_path, line);
    ASSERT(strstr(last_error(msg, sizeof msg), want), "\"%s\" not in \"%s\"", want, msg);
    CHECK(mc_config_save(b, b_path));
    char *tb2 = slurp(b_path);
    ASSERT(strcmp(ta, tb2) == 0, "the bad file changed the card");
    EXPECT(mc_config_load(b, "/nonexistent/mc.toml"), MC_ERR_IO);

    free(ta);
    free(tb);
    free(tb2);
    free(bad);
    remove(a_path);
    remove(b_path);
    remove(bad_path);
    CHECK(mc_close(a));
    CHECK(mc_close(b));
    ASSERT(seen[-MC_ERR_CONFIG_FILE], "MC_ERR_CONFIG_FILE never returned");
    printf("%u checks\n", checks);
    printf("PASS config\n");
    return 0;
}
