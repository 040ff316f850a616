/*
 * Demos (.dem): the CD-track line, then blocks of an int32 length, three
 * float view angles and that many bytes of server messages.  Each message
 * a client needs to draw is applied to the state (ew_demo_state in
 * edgewise.h); the others are skipped by their known lengths.  Protocols
 * 15 (NetQuake), 666 (FitzQuake) and 999 (RMQ, whose flags choose the
 * size of coordinates and angles).  Written from the format's published
 * facts; every length, count and index read from the file is checked.
 */
#include "ew_util.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { PROTO_NQ = 15, PROTO_FITZ = 666, PROTO_RMQ = 999 };

/* The message kinds (svc_*). */
enum {
    SVC_BAD = 0, SVC_NOP, SVC_DISCONNECT, SVC_UPDATESTAT, SVC_VERSION, SVC_SETVIEW, SVC_SOUND,
    SVC_TIME, SVC_PRINT, SVC_STUFFTEXT, SVC_SETANGLE, SVC_SERVERINFO, SVC_LIGHTSTYLE,
    SVC_UPDATENAME, SVC_UPDATEFRAGS, SVC_CLIENTDATA, SVC_STOPSOUND, SVC_UPDATECOLORS,
    SVC_PARTICLE, SVC_DAMAGE, SVC_SPAWNSTATIC, SVC_SPAWNBINARY, SVC_SPAWNBASELINE,
    SVC_TEMP_ENTITY, SVC_SETPAUSE, SVC_SIGNONNUM, SVC_CENTERPRINT, SVC_KILLEDMONSTER,
    SVC_FOUNDSECRET, SVC_SPAWNSTATICSOUND, SVC_INTERMISSION, SVC_FINALE, SVC_CDTRACK,
    SVC_SELLSCREEN, SVC_CUTSCENE,
    /* FitzQuake */
    SVC_SKYBOX = 37, SVC_BF = 40, SVC_FOG = 41, SVC_SPAWNBASELINE2 = 42, SVC_SPAWNSTATIC2 = 43,
    SVC_SPAWNSTATICSOUND2 = 44
};

static const char *const svc_names[EW_DEMO_SVC_KINDS] = {
    "svc_bad", "svc_nop", "svc_disconnect", "svc_updatestat", "svc_version", "svc_setview",
    "svc_sound", "svc_time", "svc_print", "svc_stufftext", "svc_setangle", "svc_serverinfo",
    "svc_lightstyle", "svc_updatename", "svc_updatefrags", "svc_clientdata", "svc_stopsound",
    "svc_updatecolors", "svc_particle", "svc_damage", "svc_spawnstatic", "svc_spawnbinary",
    "svc_spawnbaseline", "svc_temp_entity", "svc_setpause", "svc_signonnum", "svc_centerprint",
    "svc_killedmonster", "svc_foundsecret", "svc_spawnstaticsound", "svc_intermission",
    "svc_finale", "svc_cdtrack", "svc_sellscreen", "svc_cutscene", NULL, NULL, "svc_skybox",
    NULL, NULL, "svc_bf", "svc_fog", "svc_spawnbaseline2", "svc_spawnstatic2",
    "svc_spawnstaticsound2",
};

const char *ew_demo_svc_name(int svc) {
    return svc >= 0 && svc < EW_DEMO_SVC_KINDS ? svc_names[svc] : NULL;
}

/* Entity update bits (the message byte has bit 7 set). */
#define U_MOREBITS    (1u << 0)
#define U_ORIGIN1     (1u << 1)
#define U_ORIGIN2     (1u << 2)
#define U_ORIGIN3     (1u << 3)
#define U_ANGLE2      (1u << 4)
#define U_NOLERP      (1u << 5)
#define U_FRAME       (1u << 6)
#define U_ANGLE1      (1u << 8)
#define U_ANGLE3      (1u << 9)
#define U_MODEL       (1u << 10)
#define U_COLORMAP    (1u << 11)
#define U_SKIN        (1u << 12)
#define U_EFFECTS     (1u << 13)
#define U_LONGENTITY  (1u << 14)
#define U_EXTEND1     (1u << 15)
#define U_ALPHA       (1u << 16)
#define U_FRAME2      (1u << 17)
#define U_MODEL2      (1u << 18)
#define U_LERPFINISH  (1u << 19)
#define U_SCALE       (1u << 20)
#define U_EXTEND2     (1u << 23)

/* Client data bits. */
#define SU_VIEWHEIGHT   (1u << 0)
#define SU_IDEALPITCH   (1u << 1)
#define SU_PUNCH1       (1u << 2)
#define SU_VELOCITY1    (1u << 5)
#define SU_ITEMS        (1u << 9)
#define SU_ONGROUND     (1u << 10)
#define SU_INWATER      (1u << 11)
#define SU_WEAPONFRAME  (1u << 12)
#define SU_ARMOR        (1u << 13)
#define SU_WEAPON       (1u << 14)
#define SU_EXTEND1      (1u << 15)
#define SU_WEAPON2      (1u << 16)
#define SU_ARMOR2       (1u << 17)
#define SU_AMMO2        (1u << 18)
#define SU_SHELLS2      (1u << 19)
#define SU_NAILS2       (1u << 20)
#define SU_ROCKETS2     (1u << 21)
#define SU_CELLS2       (1u << 22)
#define SU_EXTEND2      (1u << 23)
#define SU_WEAPONFRAME2 (1u << 24)
#define SU_WEAPONALPHA  (1u << 25)

/* svc_spawnbaseline2 / svc_spawnstatic2 bits. */
#define B_LARGEMODEL 1
#define B_LARGEFRAME 2
#define B_ALPHA      4

/* svc_sound field mask. */
#define SND_VOLUME      1
#define SND_ATTENUATION 2
#define SND_LARGEENTITY 8
#define SND_LARGESOUND  16

#define DEFAULT_VIEWHEIGHT 22
#define MAX_SOUNDS 4096

struct ew_demo {
    char     name[256];
    uint8_t *data;
    size_t   size;
    size_t   first;        /* the first block's offset (after the CD-track line) */
    int      nblocks;      /* whole blocks */
    char     framing[400]; /* why the block after the last whole one is not whole ("" if none) */
    size_t   pos;          /* the next block's offset */
    int      next;         /* the next block's index */
    char     failed[500];  /* the error that stopped reading ("" while reading) */
    int      cap_ents;
    ew_demo_state st;
};

/* ---- the cursor over one block's messages ---------------------------------- */

typedef struct cursor {
    const uint8_t *p;
    size_t n, i;
    int    short_;  /* a read ran past the block */
} cursor;

static int need(cursor *c, size_t k) {
    if (c->short_ || c->n - c->i < k) {
        c->short_ = 1;
        c->i = c->n;
        return 0;
    }
    return 1;
}
static int rd_byte(cursor *c) { return need(c, 1) ? c->p[c->i++] : 0; }
static int rd_char(cursor *c) { return need(c, 1) ? (int8_t)c->p[c->i++] : 0; }
static int rd_short(cursor *c) {
    if (!need(c, 2)) return 0;
    int v = (int16_t)(uint16_t)(c->p[c->i] | c->p[c->i + 1] << 8);
    c->i += 2;
    return v;
}
static int rd_ushort(cursor *c) { return rd_short(c) & 0xffff; }
static int32_t rd_long(cursor *c) {
    if (!need(c, 4)) return 0;
    uint32_t v = ew_u32(c->p + c->i);
    c->i += 4;
    return (int32_t)v;
}
static float rd_float(cursor *c) {
    int32_t l = rd_long(c);
    float f;
    memcpy(&f, &l, 4);
    return f;
}
/* A NUL-terminated string into out (cut to size - 1); a string without its
 * NUL before the block's end is a short read. */
static void rd_string(cursor *c, char *out, size_t size) {
    size_t k = 0;
    for (;;) {
        if (!need(c, 1)) break;
        uint8_t ch = c->p[c->i++];
        if (!ch) break;
        if (out && k + 1 < size) out[k++] = (char)ch;
    }
    if (out && size) out[k] = 0;
}

/* ---- protocol-dependent numbers -------------------------------------------- */

static float rd_coord(ew_demo *d, cursor *c) {
    unsigned fl = d->st.protocol == PROTO_RMQ ? d->st.protocol_flags : 0;
    if (fl & EW_DEMO_PRFL_FLOATCOORD) return rd_float(c);
    if (fl & EW_DEMO_PRFL_INT32COORD) return (float)rd_long(c) * (1.0f / 16);
    if (fl & EW_DEMO_PRFL_24BITCOORD) {
        int whole = rd_short(c);
        int frac = rd_byte(c);
        return (float)whole + (float)frac * (1.0f / 255);
    }
    return (float)rd_short(c) * (1.0f / 8);
}
static float rd_angle(ew_demo *d, cursor *c) {
    unsigned fl = d->st.protocol == PROTO_RMQ ? d->st.protocol_flags : 0;
    if (fl & EW_DEMO_PRFL_FLOATANGLE) return rd_float(c);
    if (fl & EW_DEMO_PRFL_SHORTANGLE) return (float)rd_short(c) * (360.0f / 65536);
    return (float)rd_char(c) * (360.0f / 256);
}

/* ---- errors ---------------------------------------------------------------- */

static int fail_at(ew_demo *d, ew_error *err, int block, size_t at, const char *fmt, ...) EW_PRINTF(5, 6);
static int fail_at(ew_demo *d, ew_error *err, int block, size_t at, const char *fmt, ...) {
    char what[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    snprintf(d->failed, sizeof d->failed, "%.180s: block %d at byte %zu: %.280s", d->name, block, at, what);
    return ew_fail(err, "%s", d->failed);
}

/* ---- opening --------------------------------------------------------------- */

static void reset_state(ew_demo *d) {
    ew_demo_entity *ents = d->st.entities;
    ew_demo_baseline *base = d->st.baselines;
    memset(&d->st, 0, sizeof d->st);
    d->st.entities = ents, d->st.baselines = base;
    d->st.view_height = DEFAULT_VIEWHEIGHT;
    d->st.weapon_alpha = 1;
    for (int i = 0; i < d->cap_ents; i++) {
        memset(&ents[i], 0, sizeof ents[i]);
        ents[i].msgtime = -1, ents[i].alpha = 1;
        memset(&base[i], 0, sizeof base[i]);
        base[i].alpha = 1;
    }
    d->st.nentities = 0;
    d->st.offset = d->first;
    d->pos = d->first;
    d->next = 0;
    d->failed[0] = 0;
}

ew_demo *ew_demo_open_memory(const uint8_t *data, size_t size, const char *name, ew_error *err) {
    if (!name) name = "demo";
    /* The CD track: an optional '-', digits, '\n' (some recorders write
     * blanks or a '\r' before it) within the first 16 bytes. */
    size_t i = 0;
    while (i < size && i < 16 && data[i] != '\n') {
        uint8_t ch = data[i];
        if (!(ch == '-' || (ch >= '0' && ch <= '9') || ch == ' ' || ch == '\r')) break;
        i++;
    }
    if (i >= size || i >= 16 || data[i] != '\n' || i == 0) {
        ew_fail(err, "%s: not a demo (no CD-track line at the start)", name);
        return NULL;
    }
    ew_demo *d = calloc(1, sizeof *d);
    if (!d || !(d->data = malloc(size))) {
        free(d);
        ew_fail(err, "%s: out of memory", name);
        return NULL;
    }
    memcpy(d->data, data, size);
    d->size = size;
    snprintf(d->name, sizeof d->name, "%s", name);
    d->first = i + 1;
    /* The blocks' framing, up to the first that is not whole. */
    size_t pos = d->first;
    while (pos < size) {
        size_t left = size - pos;
        if (left < 16) {
            snprintf(d->framing, sizeof d->framing, "block %d at byte %zu: header cut short (%zu of 16 bytes)",
                     d->nblocks, pos, left);
            break;
        }
        int32_t len = (int32_t)ew_u32(data + pos);
        if (len < 0 || len > EW_DEMO_MAX_BLOCK) {
            snprintf(d->framing, sizeof d->framing, "block %d at byte %zu: absurd length %d (0 to %d)",
                     d->nblocks, pos, (int)len, EW_DEMO_MAX_BLOCK);
            break;
        }
        if ((size_t)len > left - 16) {
            snprintf(d->framing, sizeof d->framing,
                     "block %d at byte %zu: length %d runs past the end of the file (%zu bytes left)", d->nblocks,
                     pos, (int)len, left - 16);
            break;
        }
        pos += 16 + (size_t)len;
        d->nblocks++;
    }
    if (d->nblocks == 0 && d->framing[0]) {
        ew_fail(err, "%s: %s", name, d->framing);
        ew_demo_close(d);
        return NULL;
    }
    reset_state(d);
    return d;
}

ew_demo *ew_demo_open(const char *path, ew_error *err) {
    uint8_t *data = NULL;
    size_t size = 0;
    if (ew_read_file(path, &data, &size, err) != 0) return NULL;
    ew_demo *d = ew_demo_open_memory(data, size, path, err);
    free(data);
    return d;
}

void ew_demo_close(ew_demo *d) {
    if (!d) return;
    free(d->st.entities);
    free(d->st.baselines);
    free(d->data);
    free(d);
}

int ew_demo_block_count(const ew_demo *d) { return d ? d->nblocks : 0; }
const ew_demo_state *ew_demo_get_state(const ew_demo *d) { return d ? &d->st : NULL; }
void ew_demo_rewind(ew_demo *d) {
    if (d) reset_state(d);
}

/* ---- entities -------------------------------------------------------------- */

/* Room for entity n; 0, or -1 out of memory. */
static int grow_entities(ew_demo *d, int n) {
    if (n < d->cap_ents) {
        if (n >= d->st.nentities) d->st.nentities = n + 1;
        return 0;
    }
    int cap = d->cap_ents ? d->cap_ents : 64;
    while (cap <= n) cap *= 2;
    if (cap > EW_DEMO_MAX_ENTITIES) cap = EW_DEMO_MAX_ENTITIES;
    ew_demo_entity *e = realloc(d->st.entities, sizeof *e * (size_t)cap);
    if (!e) return -1;
    d->st.entities = e;
    ew_demo_baseline *b = realloc(d->st.baselines, sizeof *b * (size_t)cap);
    if (!b) return -1;
    d->st.baselines = b;
    for (int i = d->cap_ents; i < cap; i++) {
        memset(&e[i], 0, sizeof e[i]);
        e[i].msgtime = -1, e[i].alpha = 1;
        memset(&b[i], 0, sizeof b[i]);
        b[i].alpha = 1;
    }
    d->cap_ents = cap;
    if (n >= d->st.nentities) d->st.nentities = n + 1;
    return 0;
}

/* FitzQuake's alpha byte: 0 the default (opaque), else (a - 1) / 254. */
static float alpha_of(int a) { return a == 0 ? 1.0f : (float)(a - 1) / 254.0f; }

static void rd_baseline(ew_demo *d, cursor *c, int version2, ew_demo_baseline *b) {
    int bits = version2 ? rd_byte(c) : 0;
    b->model = (bits & B_LARGEMODEL) ? rd_ushort(c) : rd_byte(c);
    b->frame = (bits & B_LARGEFRAME) ? rd_ushort(c) : rd_byte(c);
    b->colormap = rd_byte(c);
    b->skin = rd_byte(c);
    for (int k = 0; k < 3; k++) {
        b->origin[k] = rd_coord(d, c);
        b->angles[k] = rd_angle(d, c);
    }
    b->alpha = (bits & B_ALPHA) ? alpha_of(rd_byte(c)) : 1;
}

static int finite3(const float v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

/* An entity update (the fast message); cmd is its first byte. */
static int entity_update(ew_demo *d, cursor *c, int cmd, int block, size_t at, ew_error *err) {
    ew_demo_state *st = &d->st;
    unsigned bits = (unsigned)cmd & 0x7f;
    if (bits & U_MOREBITS) bits |= (unsigned)rd_byte(c) << 8;
    if (st->protocol != PROTO_NQ) {
        if (bits & U_EXTEND1) bits |= (unsigned)rd_byte(c) << 16;
        if (bits & U_EXTEND2) bits |= (unsigned)rd_byte(c) << 24;
    }
    int num = (bits & U_LONGENTITY) ? rd_ushort(c) : rd_byte(c);
    if (c->short_) return 0;
    if (num >= EW_DEMO_MAX_ENTITIES)
        return fail_at(d, err, block, at, "entity update: entity %d (at most %d)", num, EW_DEMO_MAX_ENTITIES - 1);
    if (grow_entities(d, num) < 0) return fail_at(d, err, block, at, "out of memory for entity %d", num);
    ew_demo_entity *e = &st->entities[num];
    const ew_demo_baseline *b = &st->baselines[num];
    int model = (bits & U_MODEL) ? rd_byte(c) : b->model;
    int frame = (bits & U_FRAME) ? rd_byte(c) : b->frame;
    int colormap = (bits & U_COLORMAP) ? rd_byte(c) : b->colormap;
    int skin = (bits & U_SKIN) ? rd_byte(c) : b->skin;
    int effects = (bits & U_EFFECTS) ? rd_byte(c) : 0;
    float org[3], ang[3];
    unsigned obit[3] = {U_ORIGIN1, U_ORIGIN2, U_ORIGIN3}, abit[3] = {U_ANGLE1, U_ANGLE2, U_ANGLE3};
    for (int k = 0; k < 3; k++) {
        org[k] = (bits & obit[k]) ? rd_coord(d, c) : b->origin[k];
        ang[k] = (bits & abit[k]) ? rd_angle(d, c) : b->angles[k];
    }
    float alpha = b->alpha;
    if (st->protocol != PROTO_NQ) {
        if (bits & U_ALPHA) alpha = alpha_of(rd_byte(c));
        if (bits & U_SCALE) rd_byte(c);
        if (bits & U_FRAME2) frame |= rd_byte(c) << 8;
        if (bits & U_MODEL2) model |= rd_byte(c) << 8;
        if (bits & U_LERPFINISH) rd_byte(c);
    }
    if (c->short_) return 0;
    if (model >= EW_DEMO_MAX_MODELS)
        return fail_at(d, err, block, at, "entity %d: model %d (at most %d)", num, model, EW_DEMO_MAX_MODELS - 1);
    if (!finite3(org) || !finite3(ang))
        return fail_at(d, err, block, at, "entity %d: a coordinate or angle that is not a number", num);
    /* Interpolated from the update before only when that came in the
     * message before this one, the model is the same, nothing asks not
     * to, and it moved less than 100 units on every axis (a teleport). */
    int link = e->msgtime != st->prev_time || e->msgtime < 0 || model != e->model || (bits & U_NOLERP);
    for (int k = 0; k < 3 && !link; k++)
        if (fabsf(org[k] - e->origin[k]) > 100) link = 1;
    for (int k = 0; k < 3; k++) {
        e->prev_origin[k] = link ? org[k] : e->origin[k];
        e->prev_angles[k] = link ? ang[k] : e->angles[k];
        e->origin[k] = org[k], e->angles[k] = ang[k];
    }
    e->model = model, e->frame = frame, e->colormap = colormap, e->skin = skin;
    e->effects = effects, e->alpha = alpha;
    e->msgtime = st->time;
    st->entity_updates++;
    st->updates_last_block++;
    return 0;
}

/* ---- the other messages ---------------------------------------------------- */

static void add_event(ew_demo_state *st, const ew_demo_event *ev) {
    if (st->nevents < EW_DEMO_MAX_EVENTS) st->events[st->nevents++] = *ev;
}

static int temp_entity(ew_demo *d, cursor *c, int block, size_t at, ew_error *err) {
    ew_demo_event ev = {0};
    ev.type = rd_byte(c);
    ev.time = d->st.time;
    switch (ev.type) {
    case EW_TE_SPIKE: case EW_TE_SUPERSPIKE: case EW_TE_GUNSHOT: case EW_TE_EXPLOSION:
    case EW_TE_TAREXPLOSION: case EW_TE_WIZSPIKE: case EW_TE_KNIGHTSPIKE: case EW_TE_LAVASPLASH:
    case EW_TE_TELEPORT:
        for (int k = 0; k < 3; k++) ev.start[k] = rd_coord(d, c);
        break;
    case EW_TE_EXPLOSION2:
        for (int k = 0; k < 3; k++) ev.start[k] = rd_coord(d, c);
        ev.color = rd_byte(c);
        ev.count = rd_byte(c);
        break;
    case EW_TE_LIGHTNING1: case EW_TE_LIGHTNING2: case EW_TE_LIGHTNING3: case EW_TE_BEAM:
        ev.entity = rd_ushort(c);
        for (int k = 0; k < 3; k++) ev.start[k] = rd_coord(d, c);
        for (int k = 0; k < 3; k++) ev.end[k] = rd_coord(d, c);
        break;
    default:
        if (c->short_) return 0;
        return fail_at(d, err, block, at, "svc_temp_entity: unknown temp entity %d", ev.type);
    }
    if (c->short_) return 0;
    if (!finite3(ev.start) || !finite3(ev.end))
        return fail_at(d, err, block, at, "svc_temp_entity: a coordinate that is not a number");
    add_event(&d->st, &ev);
    return 0;
}

static int server_info(ew_demo *d, cursor *c, int block, size_t at, ew_error *err) {
    ew_demo_state *st = &d->st;
    int proto = rd_long(c);
    if (c->short_) return 0;
    if (proto != PROTO_NQ && proto != PROTO_FITZ && proto != PROTO_RMQ)
        return fail_at(d, err, block, at, "svc_serverinfo: protocol %d (edgewise reads 15, 666 and 999)", proto);
    unsigned flags = proto == PROTO_RMQ ? (unsigned)rd_long(c) : 0;
    /* A new level: the client forgets the old one's entities. */
    long msgs[EW_DEMO_SVC_KINDS];
    memcpy(msgs, st->messages, sizeof msgs);
    long updates = st->entity_updates;
    int nev = st->nevents, blk = st->block, upd = st->updates_last_block;
    ew_demo_event *keep = NULL;
    size_t offset = st->offset;
    float va[3], pva[3];
    memcpy(va, st->view_angles, sizeof va), memcpy(pva, st->prev_view_angles, sizeof pva);
    if (nev && (keep = malloc(sizeof *keep * (size_t)nev))) memcpy(keep, st->events, sizeof *keep * (size_t)nev);
    size_t pos = d->pos;
    int next = d->next;
    reset_state(d);
    d->pos = pos, d->next = next;
    memcpy(st->messages, msgs, sizeof msgs);
    st->entity_updates = updates, st->block = blk, st->updates_last_block = upd, st->offset = offset;
    memcpy(st->view_angles, va, sizeof va), memcpy(st->prev_view_angles, pva, sizeof pva);
    if (keep) memcpy(st->events, keep, sizeof *keep * (size_t)nev), st->nevents = nev;
    free(keep);
    st->protocol = proto;
    st->protocol_flags = flags;
    st->maxclients = rd_byte(c);
    st->gametype = rd_byte(c);
    rd_string(c, st->level, sizeof st->level);
    for (int i = 1;; i++) {
        char name[64];
        rd_string(c, name, sizeof name);
        if (c->short_) return 0;
        if (!name[0]) break;
        if (i >= EW_DEMO_MAX_MODELS)
            return fail_at(d, err, block, at, "svc_serverinfo: more than %d models", EW_DEMO_MAX_MODELS - 1);
        memcpy(st->models[i], name, sizeof name);
        st->nmodels = i;
    }
    for (int i = 1;; i++) {
        char name[64];
        rd_string(c, name, sizeof name);
        if (c->short_) return 0;
        if (!name[0]) break;
        if (i >= MAX_SOUNDS) return fail_at(d, err, block, at, "svc_serverinfo: more than %d sounds", MAX_SOUNDS - 1);
        st->nsounds = i;
    }
    return 0;
}

static void client_data(ew_demo *d, cursor *c) {
    ew_demo_state *st = &d->st;
    unsigned bits = (unsigned)rd_ushort(c);
    if (st->protocol != PROTO_NQ) {
        if (bits & SU_EXTEND1) bits |= (unsigned)rd_byte(c) << 16;
        if (bits & SU_EXTEND2) bits |= (unsigned)rd_byte(c) << 24;
    }
    int vh = (bits & SU_VIEWHEIGHT) ? rd_char(c) : DEFAULT_VIEWHEIGHT;
    if (bits & SU_IDEALPITCH) rd_char(c);
    for (int k = 0; k < 3; k++) {
        if (bits & (SU_PUNCH1 << k)) rd_char(c);
        if (bits & (SU_VELOCITY1 << k)) rd_char(c);
    }
    int items = rd_long(c);  /* always sent (SU_ITEMS) */
    int weaponframe = (bits & SU_WEAPONFRAME) ? rd_byte(c) : 0;
    int armor = (bits & SU_ARMOR) ? rd_byte(c) : 0;
    int weapon = (bits & SU_WEAPON) ? rd_byte(c) : 0;
    int health = rd_short(c);
    int ammo = rd_byte(c);
    int shells = rd_byte(c), nails = rd_byte(c), rockets = rd_byte(c), cells = rd_byte(c);
    int active = rd_byte(c);
    float walpha = 1;
    if (st->protocol != PROTO_NQ) {
        if (bits & SU_WEAPON2) weapon |= rd_byte(c) << 8;
        if (bits & SU_ARMOR2) armor |= rd_byte(c) << 8;
        if (bits & SU_AMMO2) ammo |= rd_byte(c) << 8;
        if (bits & SU_SHELLS2) shells |= rd_byte(c) << 8;
        if (bits & SU_NAILS2) nails |= rd_byte(c) << 8;
        if (bits & SU_ROCKETS2) rockets |= rd_byte(c) << 8;
        if (bits & SU_CELLS2) cells |= rd_byte(c) << 8;
        if (bits & SU_WEAPONFRAME2) weaponframe |= rd_byte(c) << 8;
        if (bits & SU_WEAPONALPHA) walpha = alpha_of(rd_byte(c));
    }
    if (c->short_) return;
    st->view_height = vh;
    st->items = items, st->weapon_frame = weaponframe, st->armor = armor, st->weapon_model = weapon;
    st->health = health, st->ammo = ammo, st->active_weapon = active, st->weapon_alpha = walpha;
    st->on_ground = !!(bits & SU_ONGROUND), st->in_water = !!(bits & SU_INWATER);
    st->stats[0] = health, st->stats[2] = weapon, st->stats[3] = ammo, st->stats[4] = armor;
    st->stats[5] = weaponframe, st->stats[6] = shells, st->stats[7] = nails, st->stats[8] = rockets;
    st->stats[9] = cells, st->stats[10] = active;
}

/* One message other than an entity update: 0, or -1 with err set. */
static int message(ew_demo *d, cursor *c, int cmd, int block, size_t at, ew_error *err) {
    ew_demo_state *st = &d->st;
    char text[1024];
    switch (cmd) {
    case SVC_NOP: case SVC_KILLEDMONSTER: case SVC_FOUNDSECRET: case SVC_SELLSCREEN: case SVC_BF:
        return 0;
    case SVC_DISCONNECT:
        return 0;
    case SVC_UPDATESTAT: {
        int i = rd_byte(c), v = rd_long(c);
        if (c->short_) return 0;
        if (i >= 32) return fail_at(d, err, block, at, "svc_updatestat: stat %d (at most 31)", i);
        st->stats[i] = v;
        if (i == 2) st->weapon_model = v;
        if (i == 5) st->weapon_frame = v;
        return 0;
    }
    case SVC_VERSION: rd_long(c); return 0;
    case SVC_SETVIEW: st->view_entity = rd_ushort(c); return 0;
    case SVC_SOUND: {
        int mask = rd_byte(c);
        if (mask & SND_VOLUME) rd_byte(c);
        if (mask & SND_ATTENUATION) rd_byte(c);
        if (st->protocol != PROTO_NQ && (mask & SND_LARGEENTITY)) rd_short(c), rd_byte(c);
        else rd_short(c);
        if (st->protocol != PROTO_NQ && (mask & SND_LARGESOUND)) rd_short(c);
        else rd_byte(c);
        for (int k = 0; k < 3; k++) rd_coord(d, c);
        return 0;
    }
    case SVC_TIME: {
        float t = rd_float(c);
        if (c->short_) return 0;
        if (!isfinite(t) || fabsf(t) > 1e9f) return fail_at(d, err, block, at, "svc_time: %g is no time", (double)t);
        st->prev_time = st->time;
        st->time = t;
        return 0;
    }
    case SVC_PRINT: case SVC_STUFFTEXT: case SVC_CENTERPRINT: case SVC_SKYBOX:
        rd_string(c, NULL, 0);
        return 0;
    case SVC_SETANGLE: {
        float a[3];
        for (int k = 0; k < 3; k++) a[k] = rd_angle(d, c);
        if (!c->short_ && finite3(a)) memcpy(st->set_angles, a, sizeof a);
        return 0;
    }
    case SVC_SERVERINFO: return server_info(d, c, block, at, err);
    case SVC_LIGHTSTYLE: {
        int i = rd_byte(c);
        rd_string(c, text, sizeof text);
        if (c->short_) return 0;
        if (i >= EW_DEMO_LIGHTSTYLES)
            return fail_at(d, err, block, at, "svc_lightstyle: style %d (at most %d)", i, EW_DEMO_LIGHTSTYLES - 1);
        snprintf(st->lightstyles[i], sizeof st->lightstyles[i], "%.64s", text);
        st->lightstyle_bits |= (uint64_t)1 << i;
        st->lightstyles_seen |= (uint64_t)1 << i;
        return 0;
    }
    case SVC_UPDATENAME: rd_byte(c); rd_string(c, NULL, 0); return 0;
    case SVC_UPDATEFRAGS: rd_byte(c); rd_short(c); return 0;
    case SVC_CLIENTDATA: client_data(d, c); return 0;
    case SVC_STOPSOUND: rd_short(c); return 0;
    case SVC_UPDATECOLORS: rd_byte(c); rd_byte(c); return 0;
    case SVC_PARTICLE: {
        ew_demo_event ev = {0};
        ev.type = EW_DEMO_EV_PARTICLES;
        ev.time = st->time;
        for (int k = 0; k < 3; k++) ev.start[k] = rd_coord(d, c);
        for (int k = 0; k < 3; k++) ev.dir[k] = (float)rd_char(c) * (1.0f / 16);
        ev.count = rd_byte(c);
        ev.color = rd_byte(c);
        if (ev.count == 255) ev.count = 1024;
        if (!c->short_ && finite3(ev.start)) add_event(st, &ev);
        return 0;
    }
    case SVC_DAMAGE:
        rd_byte(c), rd_byte(c);
        for (int k = 0; k < 3; k++) rd_coord(d, c);
        return 0;
    case SVC_SPAWNSTATIC: case SVC_SPAWNSTATIC2: {
        ew_demo_baseline b;
        rd_baseline(d, c, cmd == SVC_SPAWNSTATIC2, &b);
        if (c->short_) return 0;
        if (st->nstatics >= EW_DEMO_MAX_STATICS)
            return fail_at(d, err, block, at, "%s: more than %d static entities", svc_names[cmd], EW_DEMO_MAX_STATICS);
        if (b.model >= EW_DEMO_MAX_MODELS || !finite3(b.origin) || !finite3(b.angles))
            return fail_at(d, err, block, at, "%s: model %d or its place out of range", svc_names[cmd], b.model);
        st->statics[st->nstatics++] = b;
        return 0;
    }
    case SVC_SPAWNBASELINE: case SVC_SPAWNBASELINE2: {
        int num = rd_ushort(c);
        ew_demo_baseline b;
        rd_baseline(d, c, cmd == SVC_SPAWNBASELINE2, &b);
        if (c->short_) return 0;
        if (num >= EW_DEMO_MAX_ENTITIES)
            return fail_at(d, err, block, at, "%s: entity %d (at most %d)", svc_names[cmd], num, EW_DEMO_MAX_ENTITIES - 1);
        if (b.model >= EW_DEMO_MAX_MODELS || !finite3(b.origin) || !finite3(b.angles))
            return fail_at(d, err, block, at, "%s: model %d or its place out of range", svc_names[cmd], b.model);
        if (grow_entities(d, num) < 0) return fail_at(d, err, block, at, "out of memory for entity %d", num);
        st->baselines[num] = b;
        return 0;
    }
    case SVC_TEMP_ENTITY: return temp_entity(d, c, block, at, err);
    case SVC_SETPAUSE: st->paused = rd_byte(c); return 0;
    case SVC_SIGNONNUM: st->signon = rd_byte(c); return 0;
    case SVC_SPAWNSTATICSOUND: case SVC_SPAWNSTATICSOUND2:
        for (int k = 0; k < 3; k++) rd_coord(d, c);
        if (cmd == SVC_SPAWNSTATICSOUND2) rd_short(c);
        else rd_byte(c);
        rd_byte(c), rd_byte(c);
        return 0;
    case SVC_INTERMISSION: st->intermission = 1; return 0;
    case SVC_FINALE: rd_string(c, NULL, 0); st->intermission = 2; return 0;
    case SVC_CUTSCENE: rd_string(c, NULL, 0); st->intermission = 3; return 0;
    case SVC_CDTRACK: rd_byte(c), rd_byte(c); return 0;
    case SVC_FOG: {
        int dens = rd_byte(c), r = rd_byte(c), g = rd_byte(c), b = rd_byte(c);
        rd_short(c);
        if (c->short_) return 0;
        st->fog[0] = (float)dens / 255, st->fog[1] = (float)r / 255;
        st->fog[2] = (float)g / 255, st->fog[3] = (float)b / 255;
        st->fog_set = 1;
        return 0;
    }
    default:
        return fail_at(d, err, block, at, "unknown message %d (%s)", cmd,
                       cmd == SVC_BAD ? "svc_bad" : cmd == SVC_SPAWNBINARY ? "svc_spawnbinary, obsolete" : "not in protocols 15, 666, 999");
    }
}

int ew_demo_read_block(ew_demo *d, ew_error *err) {
    if (!d) return ew_fail(err, "demo: none");
    if (d->failed[0]) return ew_fail(err, "%s", d->failed);
    ew_demo_state *st = &d->st;
    int block = d->next;
    if (block >= d->nblocks) {
        if (d->framing[0]) {
            snprintf(d->failed, sizeof d->failed, "%.100s: %.380s", d->name, d->framing);
            return ew_fail(err, "%s", d->failed);
        }
        return 0;
    }
    size_t pos = d->pos;
    uint32_t len = ew_u32(d->data + pos);  /* checked at open */
    float va[3];
    for (int k = 0; k < 3; k++) {
        uint32_t u = ew_u32(d->data + pos + 4 + 4 * (size_t)k);
        memcpy(&va[k], &u, 4);
    }
    if (!finite3(va) || fabsf(va[0]) > 1e6f || fabsf(va[1]) > 1e6f || fabsf(va[2]) > 1e6f)
        return fail_at(d, err, block, pos + 4, "view angles that are not numbers");
    memcpy(st->prev_view_angles, block ? st->view_angles : va, sizeof va);
    memcpy(st->view_angles, va, sizeof va);
    st->nevents = 0;
    st->updates_last_block = 0;
    st->lightstyle_bits = 0;
    size_t base = pos + 16;
    cursor c = {d->data + base, len, 0, 0};
    d->pos = base + len;
    d->next = block + 1;
    st->block = block + 1;
    st->offset = d->pos;
    while (c.i < c.n) {
        size_t at = base + c.i;
        int cmd = rd_byte(&c);
        int rc;
        const char *what;
        if (cmd & 0x80) {
            rc = entity_update(d, &c, cmd, block, at, err);
            what = "entity update";
        } else {
            if (cmd < EW_DEMO_SVC_KINDS && svc_names[cmd]) st->messages[cmd]++;
            rc = message(d, &c, cmd, block, at, err);
            what = cmd < EW_DEMO_SVC_KINDS && svc_names[cmd] ? svc_names[cmd] : "message";
        }
        if (rc < 0) return -1;
        if (c.short_) return fail_at(d, err, block, at, "%s runs past the end of its block (%u bytes)", what, len);
    }
    return 1;
}
