/*
 * The demo reader (src/asset/demo.c, ew_demo_* in edgewise.h):
 *   - LibreQuake's demo3.dem (RMQ 999, flags 0x82) read through: every
 *     block, the messages by kind, entities per block, precaches;
 *   - hand-made demos in protocols 15, 666 and 999 (float coordinates):
 *     each field of server info, baselines, entity updates with their
 *     extended bits, client data, temp entities, particles, light styles,
 *     static entities, intermission, decoded to the values written;
 *     interpolation's rules (a jump of more than 100 units, U_NOLERP, an
 *     entity missing from the message before);
 *   - damaged demos: cut short anywhere, random bytes in messages, absurd
 *     lengths, an unknown message: one error line naming the block and the
 *     byte offset, every block before it read, never a crash (ASan build).
 */
#include "util.h"
#include "asset/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- a demo writer ----------------------------------------------------------- */

typedef struct wbuf {
    uint8_t d[1 << 16];
    size_t  n;
    size_t  block;  /* offset of the open block's header */
    int     proto;
    unsigned flags;
} wbuf;

static void put(wbuf *b, const void *p, size_t n) {
    memcpy(b->d + b->n, p, n);
    b->n += n;
}
static void b8(wbuf *b, int v) { b->d[b->n++] = (uint8_t)v; }
static void b16(wbuf *b, int v) { b8(b, v & 255), b8(b, (v >> 8) & 255); }
static void b32(wbuf *b, uint32_t v) { b16(b, (int)(v & 0xffff)), b16(b, (int)(v >> 16)); }
static void bf(wbuf *b, float f) {
    uint32_t u;
    memcpy(&u, &f, 4);
    b32(b, u);
}
static void bstr(wbuf *b, const char *s) { put(b, s, strlen(s) + 1); }
static void bcoord(wbuf *b, float v) {
    if (b->proto == 999 && (b->flags & EW_DEMO_PRFL_FLOATCOORD)) bf(b, v);
    else if (b->proto == 999 && (b->flags & EW_DEMO_PRFL_INT32COORD)) b32(b, (uint32_t)(int32_t)lrintf(v * 16));
    else b16(b, (int)lrintf(v * 8));
}
static void bangle(wbuf *b, float v) {
    if (b->proto == 999 && (b->flags & EW_DEMO_PRFL_SHORTANGLE)) b16(b, (int)lrintf(v * 65536 / 360));
    else b8(b, (int)lrintf(v * 256 / 360));
}
static void begin(wbuf *b, float yaw) {
    b->block = b->n;
    b32(b, 0), bf(b, 0), bf(b, yaw), bf(b, 0);
}
static void end(wbuf *b) {
    uint32_t len = (uint32_t)(b->n - b->block - 16);
    memcpy(b->d + b->block, &len, 4);
}
static void serverinfo(wbuf *b, int proto, unsigned flags) {
    b8(b, 11), b32(b, (uint32_t)proto);
    if (proto == 999) b32(b, flags);
    b->proto = proto, b->flags = flags;
    b8(b, 1), b8(b, 0), bstr(b, "test level");
    bstr(b, "maps/x.bsp"), bstr(b, "*1"), bstr(b, "progs/player.mdl"), bstr(b, "");
    bstr(b, "weapons/r_exp3.wav"), bstr(b, "");
}

/* ---- demo3.dem ---------------------------------------------------------------- */

static void demo3(void) {
    if (!ew_t_need_shared("data/demos/demo3.dem")) return;
    ew_error err = {{0}};
    ew_demo *d = ew_demo_open(ew_t_shared("data/demos/demo3.dem"), &err);
    CHECK(d != NULL, "open demo3: %s", err.msg);
    if (!d) return;
    CHECK(ew_demo_block_count(d) == 1238, "1238 blocks (%d)", ew_demo_block_count(d));
    for (int pass = 0; pass < 2; pass++) {
        int rc, n = 0, most = 0, blocks_with = 0, bad_ent = 0;
        while ((rc = ew_demo_read_block(d, &err)) == 1) {
            const ew_demo_state *st = ew_demo_get_state(d);
            n++;
            if (st->updates_last_block > most) most = st->updates_last_block;
            blocks_with += st->updates_last_block > 0;
            for (int i = 0; i < st->nentities; i++)
                if (st->entities[i].msgtime >= 0 && st->entities[i].model > st->nmodels) bad_ent++;
        }
        const ew_demo_state *st = ew_demo_get_state(d);
        CHECK(rc == 0 && n == 1238, "pass %d: read through (%d blocks, rc %d: %s)", pass, n, rc, rc ? err.msg : "");
        CHECK(st->protocol == 999 && st->protocol_flags == 0x82, "RMQ 999 flags 0x82 (%d %#x)", st->protocol,
              st->protocol_flags);
        CHECK(strcmp(st->level, "Hyperborea") == 0, "level '%s'", st->level);
        CHECK(st->nmodels == 49 && strcmp(st->models[1], "maps/lqdm3.bsp") == 0 &&
              strcmp(st->models[9], "progs/player.mdl") == 0, "49 models (%d: %s, %s)", st->nmodels, st->models[1],
              st->models[9]);
        CHECK(st->nsounds == 74, "74 sounds (%d)", st->nsounds);
        /* the messages by kind */
        struct { int svc; long n; } want[] = {
            {7, 1233}, {15, 1233}, {12, 64}, {20, 22}, {22, 36}, {29, 22}, {3, 13}, {5, 2}, {11, 1},
            {25, 3}, {34, 1}, {10, 1}, {2, 1}};
        for (size_t i = 0; i < sizeof want / sizeof want[0]; i++)
            CHECK(st->messages[want[i].svc] == want[i].n, "%s: %ld (want %ld)", ew_demo_svc_name(want[i].svc),
                  st->messages[want[i].svc], want[i].n);
        CHECK(st->entity_updates == 2423, "2423 entity updates (%ld)", st->entity_updates);
        CHECK(most == 3 && blocks_with == 1233, "entities per block: at most 3 (%d), in 1233 blocks (%d)", most,
              blocks_with);
        CHECK(bad_ent == 0, "every entity's model is a precache (%d not)", bad_ent);
        CHECK(st->nstatics == 22 && st->view_entity == 1, "22 statics (%d), view entity 1 (%d)", st->nstatics,
              st->view_entity);
        CHECK(st->intermission == 3, "the demo is a cutscene (%d)", st->intermission);
        CHECK(fabs(st->time - 446.694) < 0.01, "ends at 446.694 s (%.3f)", st->time);
        ew_demo_rewind(d);
    }
    ew_demo_close(d);
}

/* ---- hand-made demos in each protocol ------------------------------------------ */

static ew_demo *open_buf(const wbuf *b, ew_error *err) { return ew_demo_open_memory(b->d, b->n, "made.dem", err); }

static int read_all(ew_demo *d, ew_error *err, int *blocks) {
    int rc;
    *blocks = 0;
    while ((rc = ew_demo_read_block(d, err)) == 1) ++*blocks;
    return rc;
}

static void made(int proto, unsigned flags) {
    static wbuf b;
    memset(&b, 0, sizeof b);
    put(&b, "-1\n", 3);
    begin(&b, 10);
    serverinfo(&b, proto, flags);
    b8(&b, 5), b16(&b, 1);                                  /* setview 1 */
    b8(&b, 12), b8(&b, 3), bstr(&b, "mmamammmmammamamaaamammma"); /* lightstyle 3 */
    b8(&b, 22), b16(&b, 2);                                 /* baseline of entity 2: the player model */
    b8(&b, 3), b8(&b, 0), b8(&b, 0), b8(&b, 0);
    for (int k = 0; k < 3; k++) bcoord(&b, 100.0f * (float)(k + 1)), bangle(&b, 0);
    b8(&b, 20), b8(&b, 3), b8(&b, 1), b8(&b, 0), b8(&b, 0); /* a static entity */
    for (int k = 0; k < 3; k++) bcoord(&b, -8), bangle(&b, 90);
    end(&b);
    /* block 1: time 1.0, the player at (8, 16, 24) yaw 90, client data */
    begin(&b, 20);
    b8(&b, 7), bf(&b, 1.0f);
    b8(&b, 0x80 | 0x01 | 0x02 | 0x04 | 0x08 | 0x10), b8(&b, 0x01 | 0x02); /* origin 1-3, angle 2; angle1, angle3 */
    b8(&b, 1);  /* entity 1 */
    bcoord(&b, 8), bangle(&b, 0), bcoord(&b, 16), bangle(&b, 90), bcoord(&b, 24), bangle(&b, 0);
    b8(&b, 0x80), b8(&b, 2);  /* entity 2 as its baseline */
    b8(&b, 15), b16(&b, 1 | (1 << 14) | (1 << 12)); /* view height, weapon, weapon frame */
    b8(&b, 30), b32(&b, 0x1001), b8(&b, 3), b8(&b, 3), b16(&b, 100);
    for (int k = 0; k < 6; k++) b8(&b, k + 1);
    end(&b);
    /* block 2: time 1.1, the player moved 40 units, entity 2 missing; temp entities */
    begin(&b, 30);
    b8(&b, 7), bf(&b, 1.1f);
    b8(&b, 0x80 | 0x02), b8(&b, 1), bcoord(&b, 48);
    b8(&b, 23), b8(&b, EW_TE_EXPLOSION), bcoord(&b, 1), bcoord(&b, 2), bcoord(&b, 3);
    b8(&b, 23), b8(&b, EW_TE_LIGHTNING2), b16(&b, 1);
    for (int k = 0; k < 6; k++) bcoord(&b, (float)k * 10);
    b8(&b, 18);
    for (int k = 0; k < 3; k++) bcoord(&b, 5);
    b8(&b, 16), b8(&b, -16 & 255), b8(&b, 0), b8(&b, 255), b8(&b, 73);  /* particles: 255 is 1024 */
    end(&b);
    /* block 3: time 1.2, the player jumps 500 units (a teleport); entity 2 back */
    begin(&b, 40);
    b8(&b, 7), bf(&b, 1.2f);
    b8(&b, 0x80 | 0x02), b8(&b, 1), bcoord(&b, 548);
    b8(&b, 0x80 | 0x02), b8(&b, 2), bcoord(&b, 120);
    if (proto != 15) {
        /* FitzQuake's extended bits: alpha, a model and a frame above 255 */
        b8(&b, 0x80 | 0x01 | 0x40), b8(&b, 0x80 | 0x04), b8(&b, 0x01 | 0x02 | 0x04); /* more, frame; model;
                                                                                    * extend1: alpha frame2 model2 */
        b8(&b, 3), b8(&b, 7), b8(&b, 2), b8(&b, 128), b8(&b, 1), b8(&b, 1); /* entity 3: model 7, frame 2, alpha,
                                                                             * frame2, model2 */
        b8(&b, 42), b16(&b, 4), b8(&b, 1 | 2 | 4), b16(&b, 300), b16(&b, 400), b8(&b, 0), b8(&b, 0);
        for (int k = 0; k < 3; k++) bcoord(&b, 0), bangle(&b, 0);
        b8(&b, 128);
    }
    b8(&b, 30);  /* intermission */
    end(&b);

    ew_error err = {{0}};
    ew_demo *d = open_buf(&b, &err);
    CHECK(d != NULL, "protocol %d: open: %s", proto, err.msg);
    if (!d) return;
    const ew_demo_state *st = ew_demo_get_state(d);
    CHECK(ew_demo_read_block(d, &err) == 1, "p%d block 0: %s", proto, err.msg);
    CHECK(st->protocol == proto && st->protocol_flags == (proto == 999 ? flags : 0u), "p%d: protocol", proto);
    CHECK(st->nmodels == 3 && strcmp(st->models[3], "progs/player.mdl") == 0 && st->nsounds == 1,
          "p%d: precaches (%d)", proto, st->nmodels);
    CHECK(strcmp(st->level, "test level") == 0 && st->view_entity == 1, "p%d: level, view", proto);
    CHECK(strcmp(st->lightstyles[3], "mmamammmmammamamaaamammma") == 0 && (st->lightstyle_bits & 8),
          "p%d: light style", proto);
    CHECK(st->nentities >= 3 && st->baselines[2].model == 3 && fabsf(st->baselines[2].origin[2] - 300) < 0.2f,
          "p%d: baseline", proto);
    CHECK(st->nstatics == 1 && st->statics[0].model == 3 && fabsf(st->statics[0].angles[1] - 90) < 1.5f &&
          fabsf(st->statics[0].origin[0] + 8) < 0.2f, "p%d: static entity", proto);
    CHECK(st->view_angles[1] == 10, "p%d: the block's view angles", proto);

    CHECK(ew_demo_read_block(d, &err) == 1, "p%d block 1: %s", proto, err.msg);
    const ew_demo_entity *e1 = &st->entities[1];
    CHECK(st->time == 1.0 && fabsf(e1->origin[0] - 8) < 0.2f && fabsf(e1->origin[1] - 16) < 0.2f &&
          fabsf(e1->origin[2] - 24) < 0.2f && fabsf(e1->angles[1] - 90) < 1.5f, "p%d: entity 1 at (%g %g %g) yaw %g",
          proto, e1->origin[0], e1->origin[1], e1->origin[2], e1->angles[1]);
    CHECK(memcmp(e1->prev_origin, e1->origin, sizeof e1->origin) == 0, "p%d: a new entity is not interpolated", proto);
    CHECK(st->entities[2].model == 3 && fabsf(st->entities[2].origin[1] - 200) < 0.2f, "p%d: entity 2 = baseline",
          proto);
    CHECK(st->view_height == 30 && st->weapon_model == 3 && st->weapon_frame == 3 && st->health == 100 &&
          st->items == 0x1001 && st->active_weapon == 6, "p%d: client data (vh %d wm %d wf %d hp %d)", proto,
          st->view_height, st->weapon_model, st->weapon_frame, st->health);
    CHECK(st->updates_last_block == 2, "p%d: 2 updates", proto);

    CHECK(ew_demo_read_block(d, &err) == 1, "p%d block 2: %s", proto, err.msg);
    CHECK(fabsf(e1->origin[0] - 48) < 0.2f && fabsf(e1->prev_origin[0] - 8) < 0.2f, "p%d: moved 40: interpolated",
          proto);
    CHECK(fabsf(e1->origin[1]) < 0.2f, "p%d: a field left out takes the baseline's value", proto);
    CHECK(st->nevents == 3 && st->events[0].type == EW_TE_EXPLOSION && fabsf(st->events[0].start[2] - 3) < 0.2f &&
          st->events[1].type == EW_TE_LIGHTNING2 && st->events[1].entity == 1 && fabsf(st->events[1].end[2] - 50) < 0.2f &&
          st->events[2].type == EW_DEMO_EV_PARTICLES && st->events[2].count == 1024 && st->events[2].color == 73 &&
          st->events[2].dir[0] == 1 && st->events[2].dir[1] == -1, "p%d: temp entities and particles (%d)", proto, st->nevents);

    CHECK(ew_demo_read_block(d, &err) == 1, "p%d block 3: %s", proto, err.msg);
    CHECK(fabsf(e1->origin[0] - 548) < 0.2f && e1->prev_origin[0] == e1->origin[0], "p%d: a 500-unit jump is not "
          "interpolated", proto);
    CHECK(st->entities[2].prev_origin[0] == st->entities[2].origin[0], "p%d: an entity missing from the message "
          "before is not interpolated", proto);
    if (proto != 15) {
        const ew_demo_entity *e3 = &st->entities[3];
        CHECK(e3->model == (7 | 1 << 8) && e3->frame == (2 | 1 << 8) && fabsf(e3->alpha - 127.0f / 254) < 1e-3f,
              "p%d: extended bits: model %d frame %d alpha %g", proto, e3->model, e3->frame, e3->alpha);
        CHECK(st->baselines[4].model == 300 && st->baselines[4].frame == 400 &&
              fabsf(st->baselines[4].alpha - 127.0f / 254) < 1e-3f, "p%d: svc_spawnbaseline2", proto);
    }
    CHECK(st->intermission == 1, "p%d: intermission", proto);
    CHECK(ew_demo_read_block(d, &err) == 0, "p%d: the end: %s", proto, err.msg);
    ew_demo_close(d);
}

/* ---- damaged demos ------------------------------------------------------------- */

static uint32_t rng(uint32_t *s) {
    *s ^= *s << 13, *s ^= *s >> 17, *s ^= *s << 5;
    return *s;
}

/* Reads a damaged demo through: the error, when there is one, is one line
 * naming the demo, a block and a byte. */
static int damaged(const uint8_t *p, size_t n, const char *what, int *blocks, char *msg) {
    ew_error err = {{0}};
    ew_demo *d = ew_demo_open_memory(p, n, "bad.dem", &err);
    *blocks = 0;
    int rc = -2;
    if (d) {
        rc = read_all(d, &err, blocks);
        CHECK(rc == 0 || (rc == -1 && strstr(err.msg, "bad.dem: block ") && strstr(err.msg, " at byte ")),
              "%s: rc %d, '%s'", what, rc, err.msg);
        if (rc < 0) CHECK(ew_demo_read_block(d, &err) == -1, "%s: stays failed", what);
        ew_demo_close(d);
    } else {
        CHECK(strncmp(err.msg, "bad.dem: ", 9) == 0, "%s: open error '%s'", what, err.msg);
    }
    CHECK(!strchr(err.msg, '\n'), "%s: one line", what);
    if (msg) snprintf(msg, 512, "%s", err.msg);
    return rc;
}

static void corrupt(void) {
    if (!ew_t_need_shared("data/demos/demo3.dem")) return;
    uint8_t *data = NULL;
    size_t size = 0;
    ew_error err;
    if (ew_read_file(ew_t_shared("data/demos/demo3.dem"), &data, &size, &err) != 0) {
        CHECK(0, "%s", err.msg);
        return;
    }
    /* block offsets */
    size_t offs[1300];
    int nb = 0;
    for (size_t p = 3; p + 16 <= size && nb < 1300; p += 16 + ew_t_le32(data + p)) offs[nb++] = p;
    CHECK(nb == 1238, "blocks by hand: %d", nb);
    int blocks;
    char msg[512];
    /* cut short: a cut inside block k leaves blocks 0..k-1 */
    for (int k = 1; k < nb; k += EW_T_SANITIZED ? 97 : 13) {
        size_t cut = offs[k] + 1 + (size_t)k % 40;
        int rc = damaged(data, cut, "cut", &blocks, msg);
        CHECK(rc == -1 && blocks == k, "cut in block %d: rc %d, %d blocks read: %s", k, rc, blocks, msg);
        char want[64];
        snprintf(want, sizeof want, "block %d at byte %zu", k, offs[k]);
        CHECK(strstr(msg, want) != NULL, "cut: '%s' names '%s'", msg, want);
    }
    CHECK(damaged(data, offs[600], "cut at a block's start", &blocks, NULL) == 0 && blocks == 600, "cut between blocks");
    CHECK(damaged(data, 2, "two bytes", &blocks, NULL) == -2, "two bytes: no demo");
    CHECK(damaged((const uint8_t *)"hello world\n", 12, "text", &blocks, NULL) == -2, "text: no demo");
    /* absurd lengths */
    uint8_t *copy = malloc(size);
    memcpy(copy, data, size);
    ew_t_put_le32(copy + offs[5], 0x7fffffffu);
    CHECK(damaged(copy, size, "absurd", &blocks, msg) == -1 && blocks == 5 && strstr(msg, "absurd length"),
          "absurd length in block 5: %d blocks, %s", blocks, msg);
    memcpy(copy, data, size);
    ew_t_put_le32(copy + offs[7], 0xfffffff0u);
    CHECK(damaged(copy, size, "negative", &blocks, msg) == -1 && blocks == 7, "negative length: %s", msg);
    memcpy(copy, data, size);
    ew_t_put_le32(copy + offs[9], ew_t_le32(data + offs[9]) + 3);  /* runs into the next block */
    CHECK(damaged(copy, size, "longer", &blocks, msg) == -1 && blocks >= 9, "a block 3 bytes too long: %s", msg);
    /* an unknown message at the start of block 10's messages */
    memcpy(copy, data, size);
    copy[offs[10] + 16] = 60;
    char want[64];
    snprintf(want, sizeof want, "block 10 at byte %zu: unknown message 60", offs[10] + 16);
    CHECK(damaged(copy, size, "unknown", &blocks, msg) == -1 && blocks == 10 && strstr(msg, want),
          "unknown message: '%s' (want '%s')", msg, want);
    /* random bytes in messages */
    uint32_t seed = 12345;
    int failed = 0, rounds = EW_T_SANITIZED ? 150 : 600;
    for (int r = 0; r < rounds; r++) {
        memcpy(copy, data, size);
        int k = (int)(rng(&seed) % (uint32_t)nb);
        uint32_t len = ew_t_le32(data + offs[k]);
        int flips = 1 + (int)(rng(&seed) % 8);
        for (int f = 0; f < flips && len; f++) copy[offs[k] + 16 + rng(&seed) % len] = (uint8_t)rng(&seed);
        if (damaged(copy, size, "random bytes", &blocks, NULL) == -1) {
            failed++;
            CHECK(blocks >= k, "random bytes in block %d: %d blocks read before the error", k, blocks);
        }
    }
    CHECK(failed > rounds / 10, "random bytes: some are caught (%d of %d)", failed, rounds);
    /* random bytes anywhere, headers too */
    for (int r = 0; r < rounds; r++) {
        memcpy(copy, data, size);
        for (int f = 0; f < 4; f++) copy[rng(&seed) % size] = (uint8_t)rng(&seed);
        damaged(copy, size, "random anywhere", &blocks, NULL);
    }
    free(copy);
    free(data);
}

/* ---- the client over the built-in world ---------------------------------------- */

static void client(void) {
    static wbuf b;
    memset(&b, 0, sizeof b);
    put(&b, "-1\n", 3);
    begin(&b, 10);
    serverinfo(&b, 15, 0);  /* models: 1 map, 2 "*1", 3 progs/player.mdl */
    b8(&b, 5), b16(&b, 1);
    end(&b);
    for (int blk = 0; blk < 3; blk++) {
        float x = blk == 2 ? 140 : 100;
        begin(&b, blk == 2 ? 30 : 20);
        b8(&b, 7), bf(&b, blk == 0 ? 1.0f : blk == 1 ? 1.0f : 1.1f);
        /* entity 1 (the view) at (x, 200, 50) yaw 90 */
        b8(&b, 0x80 | 0x01 | 0x02 | 0x04 | 0x08 | 0x10), b8(&b, 0x01 | 0x02);
        b8(&b, 1), bcoord(&b, x), bangle(&b, 0), bcoord(&b, 200), bangle(&b, 90), bcoord(&b, 50), bangle(&b, 0);
        /* entity 2: the door "*1" rising; entity 3: a muzzle flash */
        b8(&b, 0x80 | 0x01 | 0x08), b8(&b, 0x04), b8(&b, 2), b8(&b, 2), bcoord(&b, blk == 2 ? 16 : 8);
        b8(&b, 0x80 | 0x01 | 0x02), b8(&b, 0x04 | 0x20), b8(&b, 3), b8(&b, 3), b8(&b, 2), bcoord(&b, 300);
        b8(&b, 15), b16(&b, 0), b32(&b, 0), b16(&b, 100);
        for (int k = 0; k < 6; k++) b8(&b, 0);
        if (blk == 2) {
            b8(&b, 23), b8(&b, EW_TE_EXPLOSION), bcoord(&b, 300), bcoord(&b, 300), bcoord(&b, 100);
            b8(&b, 18), bcoord(&b, 310), bcoord(&b, 300), bcoord(&b, 100), b8(&b, 0), b8(&b, 0), b8(&b, 0);
            b8(&b, 20), b8(&b, 73);
        }
        end(&b);
    }
    begin(&b, 30);
    b8(&b, 7), bf(&b, 4.0f);
    b8(&b, 0x80 | 0x02), b8(&b, 1), bcoord(&b, 140);
    end(&b);

    ew_error err = {{0}};
    ew_assets *a = ew_assets_create_builtin(&err);
    ew_demo *d = open_buf(&b, &err);
    ew_demo_client *c = a && d ? ew_demo_client_create(d, a->world, NULL, &err) : NULL;
    CHECK(c != NULL, "client: %s", err.msg);
    if (!c) {
        ew_demo_close(d), ew_assets_destroy(a);
        return;
    }
    ew_camera cam;
    CHECK(ew_demo_client_frame(c, 0, &cam) == -1, "no frame before the server info");
    for (int i = 0; i < 4; i++) CHECK(ew_demo_client_read(c, &err) == 1, "client block %d: %s", i, err.msg);
    CHECK(strcmp(ew_demo_client_map(c), "maps/x.bsp") == 0, "the map: %s", ew_demo_client_map(c));
    CHECK(ew_demo_client_missing(c) == 1, "player.mdl missing without a game directory (%d)", ew_demo_client_missing(c));
    const ew_scene *s = ew_demo_client_scene(c);
    CHECK(ew_demo_client_frame(c, 1.05, &cam) == 0, "frame at 1.05");
    CHECK(fabsf(cam.origin[0] - 120) < 0.2f && fabsf(cam.origin[2] - 72) < 0.2f,
          "the camera halfway, at the eye (%g %g %g)", cam.origin[0], cam.origin[1], cam.origin[2]);
    CHECK(fabsf(cam.angles[1] - 25) < 0.01f && cam.time == 1.05, "the view angles halfway between blocks (%g)",
          cam.angles[1]);
    CHECK(s->nents == 1 && s->ents[0].model == -2 && fabsf(s->ents[0].origin[2] - 12) < 0.2f,
          "the door, halfway up (%d entities)", s->nents);
    CHECK(s->ndlights == 2, "two dynamic lights, the explosion's and the muzzle flash (%d)", s->ndlights);
    int n1 = s->nparticles;
    CHECK(n1 > 500, "the explosion's particles (%d)", n1);
    ew_particle *copy = malloc(sizeof *copy * (size_t)(n1 ? n1 : 1));
    memcpy(copy, s->particles, sizeof *copy * (size_t)n1);
    ew_demo_client_frame(c, 1.09, &cam);
    int moved = s->nparticles != n1 || memcmp(copy, s->particles, sizeof *copy * (size_t)n1) != 0;
    CHECK(moved, "particles move with time");
    ew_demo_client_frame(c, 1.05, &cam);
    CHECK(s->nparticles == n1 && memcmp(copy, s->particles, sizeof *copy * (size_t)n1) == 0,
          "the same time, the same particles");
    free(copy);
    CHECK(ew_demo_client_read(c, &err) == 1, "last block: %s", err.msg);
    ew_demo_client_frame(c, 4.0, &cam);
    CHECK(s->nparticles == 0 && s->ndlights == 0 && s->nents == 0,
          "three seconds on: no particles, lights or entities not in the last message (%d %d %d)", s->nparticles,
          s->ndlights, s->nents);
    CHECK(ew_demo_client_read(c, &err) == 0, "the end");
    ew_demo_client_destroy(c);
    ew_demo_close(d);
    ew_assets_destroy(a);
}

/* The weapon: the view weapon's model at the eye with the view's angles,
 * and none in an intermission.  Needs LibreQuake's progs/v_shot.mdl. */
static void weapon(void) {
    if (!ew_t_need_shared("data/librequake/progs/v_shot.mdl")) return;
    static wbuf b;
    memset(&b, 0, sizeof b);
    put(&b, "-1\n", 3);
    begin(&b, 0);
    b8(&b, 11), b32(&b, 15), b8(&b, 1), b8(&b, 0), bstr(&b, "weapon");
    bstr(&b, "maps/x.bsp"), bstr(&b, "progs/v_shot.mdl"), bstr(&b, ""), bstr(&b, "");
    b.proto = 15;
    b8(&b, 5), b16(&b, 1);
    end(&b);
    for (int blk = 0; blk < 2; blk++) {
        begin(&b, 40);
        b.d[b.block + 4] = 0, b.d[b.block + 5] = 0, b.d[b.block + 6] = 0x20, b.d[b.block + 7] = 0x41;  /* pitch 10 */
        b8(&b, 7), bf(&b, 1.0f + 0.1f * (float)blk);
        b8(&b, 0x80 | 0x02 | 0x04 | 0x08), b8(&b, 1), bcoord(&b, 64), bcoord(&b, 64), bcoord(&b, 24);
        b8(&b, 15), b16(&b, (1 << 12) | (1 << 14)), b32(&b, 0), b8(&b, 3), b8(&b, 2), b16(&b, 100);
        for (int k = 0; k < 6; k++) b8(&b, 0);
        if (blk == 1) b8(&b, 30);  /* an intermission after the second block's frame */
        end(&b);
    }
    ew_error err = {{0}};
    ew_assets *a = ew_assets_create_builtin(&err);
    ew_demo *d = open_buf(&b, &err);
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", ew_t_shared("data/librequake"));
    ew_demo_client *c = a && d ? ew_demo_client_create(d, a->world, dir, &err) : NULL;
    CHECK(c != NULL, "weapon client: %s", err.msg);
    if (c) {
        CHECK(ew_demo_client_read(c, &err) == 1 && ew_demo_client_read(c, &err) == 1, "weapon blocks: %s", err.msg);
        CHECK(ew_demo_client_missing(c) == 0, "v_shot.mdl found (%d missing)", ew_demo_client_missing(c));
        ew_camera cam;
        ew_demo_client_frame(c, 1.0, &cam);
        const ew_scene *s = ew_demo_client_scene(c);
        CHECK(s->nents == 1 && s->ents[0].model >= 0 && s->models[s->ents[0].model].kind == EW_MODEL_ALIAS &&
              strcmp(s->models[s->ents[0].model].name, "progs/v_shot.mdl") == 0, "the weapon is the one entity (%d)",
              s->nents);
        if (s->nents == 1) {
            CHECK(memcmp(s->ents[0].origin, cam.origin, sizeof cam.origin) == 0 && s->ents[0].frame == 3,
                  "at the eye, its frame 3 (%d)", s->ents[0].frame);
            CHECK(s->ents[0].angles[0] == -cam.angles[0] && cam.angles[0] == 10 && s->ents[0].angles[1] == 40,
                  "the view's angles, pitch negated as the game's alias models want (%g %g)", s->ents[0].angles[0],
                  s->ents[0].angles[1]);
        }
        CHECK(fabsf(cam.origin[2] - 46) < 0.2f, "the eye 22 above the origin (%g)", cam.origin[2]);
        CHECK(ew_demo_client_read(c, &err) == 1, "intermission block: %s", err.msg);
        ew_demo_client_frame(c, 1.1, &cam);
        CHECK(s->nents == 0 && fabsf(cam.origin[2] - 24) < 0.2f, "intermission: no weapon, the entity's own origin");
    }
    ew_demo_client_destroy(c);
    ew_demo_close(d);
    ew_assets_destroy(a);
}

int main(void) {
    demo3();
    made(15, 0);
    made(666, 0);
    made(999, EW_DEMO_PRFL_FLOATCOORD);
    made(999, EW_DEMO_PRFL_INT32COORD | EW_DEMO_PRFL_SHORTANGLE);
    corrupt();
    client();
    weapon();
    return ew_t_finish();
}
