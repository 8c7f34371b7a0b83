/*
 * The cards present, and opening one by name or serial: mc_list_cards fills an array of
 * mc_card_listing (ask for the count first with an empty array), each with its URI, name,
 * serial, axes, servo rate, sync role and whether a host holds it; mc_open takes
 * "name:NAME" and "serial:N" as well as a card's URI. A name or serial nobody has is
 * MC_ERR_NOT_FOUND, one two cards share MC_ERR_AMBIGUOUS.
 *
 *     card-emu --name a --serial 11 & card-emu --name b --serial 12 & card-emu --name c --serial 11 &
 *     cc -std=c11 list.c $(pkg-config --cflags --libs motioncard) -o list && ./list a b c 11 12
 */
#include "expect.h"

#include <inttypes.h>
#include <stdlib.h>

/* The listing of `emu:NAME` in `cards`, or NULL. */
static const mc_card_listing *find(const mc_card_listing *cards, size_t n, const char *name) {
    char uri[128];
    snprintf(uri, sizeof uri, "emu:%s", name);
    for (size_t i = 0; i < n; i++) {
        if (strcmp(cards[i].uri, uri) == 0) return &cards[i];
    }
    return NULL;
}

static void show(const mc_card_listing *l) {
    const char *role = l->sync_role == MC_BUS_MASTER     ? "master"
                       : l->sync_role == MC_BUS_FOLLOWER ? "follower"
                                                         : "alone";
    printf("%s: %s, serial %" PRIu64 ", %u axes at %u Hz, %s%s%s, %s\n", l->uri, l->name,
           l->serial, l->axes, l->servo_rate_hz, role, l->master[0] ? " of " : "", l->master,
           l->available ? "available" : "busy");
}

int main(int argc, char **argv) {
    ASSERT(argc == 6, "usage: list NAME_A NAME_B NAME_C SERIAL_A SERIAL_B (C has A's serial)");
    const char *a = argv[1], *b = argv[2], *c = argv[3];
    const uint64_t serial_a = strtoull(argv[4], NULL, 10), serial_b = strtoull(argv[5], NULL, 10);

    /* How many, then the listing (cards can come and go in between: ask again if it grew). */
    size_t needed = 0, n = 0;
    EXPECT(mc_list_cards(NULL, 0, &needed), MC_ERR_BUFFER_TOO_SMALL);
    ASSERT(needed >= 3, "%zu cards listed", needed);
    mc_card_listing *cards = NULL;
    mc_result r = MC_ERR_BUFFER_TOO_SMALL;
    while (r == MC_ERR_BUFFER_TOO_SMALL) {
        free(cards);
        n = needed;
        cards = calloc(n, sizeof *cards);
        ASSERT(cards, "out of memory");
        r = mc_list_cards(cards, n, &needed);
    }
    CHECK(r);
    n = needed;
    const mc_card_listing *la = find(cards, n, a), *lb = find(cards, n, b);
    ASSERT(la && lb && find(cards, n, c), "not every card listed");
    for (const mc_card_listing *l = la; l; l = l == la ? lb : NULL) {
        ASSERT(l->error == MC_OK, "%s: %s", l->uri, l->error_message);
        ASSERT(l->axes == 2 && l->servo_rate_hz == 10000, "%s: %u axes, %u Hz", l->uri, l->axes,
               l->servo_rate_hz);
        ASSERT(l->sync_role == MC_BUS_ALONE && l->sync_state == MC_BUSST_FREE, "%s", l->uri);
        ASSERT(l->available && !l->open_here, "%s held", l->uri);
        show(l);
    }
    ASSERT(strcmp(la->name, a) == 0 && la->serial == serial_a, "%s: %s", la->uri, la->name);
    ASSERT(strcmp(lb->name, b) == 0 && lb->serial == serial_b, "%s: %s", lb->uri, lb->name);
    free(cards);

    /* By name, then by serial: the card of that URI. */
    char uri[160];
    mc_card ca = 0, cb = 0, none = 777;
    snprintf(uri, sizeof uri, "name:%s", a);
    CHECK(mc_open(uri, &ca));
    snprintf(uri, sizeof uri, "serial:%" PRIu64, serial_b);
    CHECK(mc_open(uri, &cb));
    mc_card_info info;
    CHECK(mc_get_info(cb, &info));
    ASSERT(info.axes == 2, "%u axes", info.axes);
    /* Held now: listed busy, and open here. */
    mc_card_listing again[64];
    CHECK(mc_list_cards(again, 64, &needed));
    const mc_card_listing *ha = find(again, needed, a);
    ASSERT(ha && !ha->available && ha->open_here, "emu:%s not listed busy", a);
    CHECK(mc_close(ca));
    CHECK(mc_close(cb));

    /* Nobody has it; two cards have it. */
    snprintf(uri, sizeof uri, "name:%s-nobody", a);
    EXPECT(mc_open(uri, &none), MC_ERR_NOT_FOUND);
    expect_in_message("no card named");
    snprintf(uri, sizeof uri, "serial:%" PRIu64, serial_a);
    EXPECT(mc_open(uri, &none), MC_ERR_AMBIGUOUS);
    expect_in_message("matches 2 cards");
    EXPECT(mc_open("serial:0", &none), MC_ERR_BAD_URI);
    ASSERT(none == 777, "handle written by a refused open");
    printf("PASS list\n");
    return 0;
}
