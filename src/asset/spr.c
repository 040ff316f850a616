/* SPR version 1 loader: header, then frames (single pictures or timed
 * groups of pictures).  Two passes, as the MDL loader: check and count,
 * then copy. */
#include "asset/spr.h"
#include "ew_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HEADER_SIZE 36

typedef struct sprload {
    const uint8_t *data;
    size_t size, pos;
    const char *name;
    ew_error *err;
    ew_spr *s;       /* NULL in the counting pass */
    int npics, ntimes;
    size_t pixbytes;
} sprload;

static int need(sprload *L, size_t n, const char *what, int frame) {
    if (n > L->size - L->pos)
        return ew_fail(L->err, "%s: truncated in %s of frame %d (needs %zu bytes at offset %zu, file has %zu)",
                       L->name, what, frame, n, L->pos, L->size);
    return 0;
}

static int parse_pic(sprload *L, int frame) {
    if (need(L, 16, "picture header", frame)) return -1;
    const uint8_t *p = L->data + L->pos;
    int32_t ox = ew_i32(p), oy = ew_i32(p + 4), w = ew_i32(p + 8), h = ew_i32(p + 12);
    if (w < 1 || h < 1 || w > EW_SPR_MAX_SIDE || h > EW_SPR_MAX_SIDE)
        return ew_fail(L->err, "%s: frame %d: picture size %dx%d (1..%d each way)", L->name, frame, w,
                       h, EW_SPR_MAX_SIDE);
    if (ox < -65536 || ox > 65536 || oy < -65536 || oy > 65536)
        return ew_fail(L->err, "%s: frame %d: origin (%d, %d) is absurd", L->name, frame, ox, oy);
    L->pos += 16;
    size_t n = (size_t)w * h;
    if (need(L, n, "pixels", frame)) return -1;
    if (L->s) {
        ew_spr_pic *pic = &L->s->pics[L->npics];
        uint8_t *dst = L->s->pixeldata + L->pixbytes;
        memcpy(dst, L->data + L->pos, n);
        *pic = (ew_spr_pic){{ox, oy}, w, h, dst};
    }
    L->pos += n;
    L->pixbytes += n;
    L->npics++;
    return 0;
}

static int parse_frames(sprload *L, int numframes) {
    L->pos = HEADER_SIZE;
    L->npics = L->ntimes = 0;
    L->pixbytes = 0;
    for (int i = 0; i < numframes; i++) {
        if (need(L, 4, "type", i)) return -1;
        int32_t type = ew_i32(L->data + L->pos);
        L->pos += 4;
        if (type == 0) {
            if (L->s) L->s->frames[i] = (ew_spr_frame){L->npics, 1, NULL};
            if (parse_pic(L, i)) return -1;
            continue;
        }
        if (type != 1)
            return ew_fail(L->err, "%s: frame %d has type %d (0 single, 1 group)", L->name, i, type);
        if (need(L, 4, "group", i)) return -1;
        int32_t n = ew_i32(L->data + L->pos);
        L->pos += 4;
        if (n < 1 || (size_t)n > (L->size - L->pos) / 4)
            return ew_fail(L->err, "%s: frame group %d has %d pictures", L->name, i, n);
        float *times = L->s ? L->s->timedata + L->ntimes : NULL;
        for (int k = 0; k < n; k++) {
            float f = ew_f32(L->data + L->pos + 4 * (size_t)k);
            if (!isfinite(f) || f <= 0)
                return ew_fail(L->err, "%s: frame group %d: interval %d is %g (must be positive)",
                               L->name, i, k, (double)f);
            if (times) times[k] = f;
        }
        L->pos += 4 * (size_t)n;
        if (L->s) L->s->frames[i] = (ew_spr_frame){L->npics, n, times};
        L->ntimes += n;
        for (int k = 0; k < n; k++)
            if (parse_pic(L, i)) return -1;
    }
    return 0;
}

ew_spr *ew_spr_load(const uint8_t *data, size_t size, const char *name, ew_error *err) {
    if (!name) name = "spr";
    if (!data || size < HEADER_SIZE) {
        ew_fail(err, "%s: %zu bytes is too short for a sprite header (%d)", name, size, HEADER_SIZE);
        return NULL;
    }
    if (memcmp(data, "IDSP", 4) != 0) {
        ew_fail(err, "%s: not a sprite file (no IDSP tag)", name);
        return NULL;
    }
    int32_t version = ew_i32(data + 4);
    if (version != 1) {
        ew_fail(err, "%s: sprite version %d (only 1 is supported)", name, version);
        return NULL;
    }
    int32_t type = ew_i32(data + 8), maxw = ew_i32(data + 16), maxh = ew_i32(data + 20);
    int32_t numframes = ew_i32(data + 24), sync = ew_i32(data + 32);
    float radius = ew_f32(data + 12), beam = ew_f32(data + 28);
    if (type < 0 || type > 4) {
        ew_fail(err, "%s: sprite type %d (0..4)", name, type);
        return NULL;
    }
    if (numframes < 1 || numframes > EW_SPR_MAX_FRAMES) {
        ew_fail(err, "%s: %d frames (1..%d)", name, numframes, EW_SPR_MAX_FRAMES);
        return NULL;
    }
    if (maxw < 0 || maxh < 0 || maxw > EW_SPR_MAX_SIDE || maxh > EW_SPR_MAX_SIDE) {
        ew_fail(err, "%s: maximum size %dx%d (0..%d each way)", name, maxw, maxh, EW_SPR_MAX_SIDE);
        return NULL;
    }
    if (!isfinite(radius) || !isfinite(beam)) {
        ew_fail(err, "%s: bounding radius or beam length is not a number", name);
        return NULL;
    }
    sprload L = {data, size, 0, name, err, NULL, 0, 0, 0};
    if (parse_frames(&L, numframes)) return NULL;

    ew_spr *s = calloc(1, sizeof *s);
    if (!s) goto oom;
    snprintf(s->name, sizeof s->name, "%s", name);
    s->type = type, s->maxwidth = maxw, s->maxheight = maxh, s->synctype = sync;
    s->beamlength = beam;
    s->numframes = numframes;
    s->numpics = L.npics;
    s->frames = calloc((size_t)numframes, sizeof *s->frames);
    s->pics = calloc((size_t)L.npics, sizeof *s->pics);
    s->pixeldata = malloc(L.pixbytes ? L.pixbytes : 1);
    s->timedata = malloc(sizeof(float) * (size_t)(L.ntimes ? L.ntimes : 1));
    if (!s->frames || !s->pics || !s->pixeldata || !s->timedata) goto oom;
    L.s = s;
    if (parse_frames(&L, numframes)) {  /* cannot fail: the first pass checked it */
        ew_spr_free(s);
        return NULL;
    }
    /* The farthest corner of any picture from the entity: the file's own
     * bounding radius is not trusted for culling. */
    float reach = 0;
    for (int i = 0; i < s->numpics; i++) {
        const ew_spr_pic *p = &s->pics[i];
        float x = fmaxf(fabsf((float)p->origin[0]), fabsf((float)p->origin[0] + (float)p->width));
        float y = fmaxf(fabsf((float)p->origin[1]), fabsf((float)p->origin[1] - (float)p->height));
        reach = fmaxf(reach, sqrtf(x * x + y * y));
    }
    s->radius = reach;
    return s;
oom:
    ew_spr_free(s);
    ew_fail(err, "%s: out of memory", name);
    return NULL;
}

void ew_spr_free(ew_spr *s) {
    if (!s) return;
    free(s->frames), free(s->pics), free(s->pixeldata), free(s->timedata);
    free(s);
}

const ew_spr_pic *ew_spr_pick(const ew_spr *s, int frame, double time) {
    if (frame < 0) frame = 0;
    if (frame >= s->numframes) frame = s->numframes - 1;
    const ew_spr_frame *f = &s->frames[frame];
    int pick = f->first;
    if (f->count > 1 && f->times) {
        double full = f->times[f->count - 1];
        if (full > 0 && isfinite(time)) {
            double t = fmod(time, full);
            if (t < 0) t += full;
            pick = f->first + f->count - 1;
            for (int i = 0; i < f->count - 1; i++)
                if (f->times[i] > t) {
                    pick = f->first + i;
                    break;
                }
        }
    }
    return &s->pics[pick];
}
