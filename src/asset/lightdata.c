/*
 * Coloured light and per-face light-map layouts: .lit files and the BSPX
 * lumps RGBLIGHTING, LMSHIFT, LMOFFSET, LMSTYLE and DECOUPLED_LM.
 *
 * The formats, as documented publicly (written here from those facts):
 *  - .lit: "QLIT", int32 version 1, then 3 bytes (r, g, b) for every byte
 *    of the BSP's lighting lump, in the same order.
 *  - BSPX directory: "BSPX", int32 count, then count entries of a 24-byte
 *    zero-padded name, int32 file offset, int32 length (FTE's
 *    specs/bspx.txt).  It follows the standard header, or (as compilers
 *    write it) the last standard lump, 4-byte aligned.
 *  - RGBLIGHTING: a .lit without its 8-byte header.
 *  - LMSHIFT: one byte a face, 1 << shift texels a light sample; the light
 *    map covers the face's texture extents floored / ceiled to that step,
 *    (extent >> shift) + 1 samples a side (Quake's rule with 16 replaced
 *    by the step).  LMOFFSET: int32 a face, replaces the light offset.
 *    LMSTYLE: 4 bytes a face, replaces the styles.
 *  - DECOUPLED_LM (ericw-tools): 40 bytes a face: uint16 width, uint16
 *    height (samples), int32 offset into the lighting lump (-1 none), then
 *    a 2x4 float matrix (row major) from world point to light-map sample
 *    coordinates: u = row0 . (x, y, z, 1), v = row1 . (x, y, z, 1); sample
 *    (i, j) sits at (u, v) = (i, j).  ericw-tools writes a face with no
 *    light map as all zeros (0x0 samples, offset -1).
 *
 * A face with no light map in any layout (offset -1, no styles, a
 * DECOUPLED_LM size of 0) gets Quake's grid with offset -1: it is drawn
 * dark, exactly as the same map without BSPX draws its unlit faces.
 *
 * Which coloured light wins: the RGBLIGHTING lump is read with the map, a
 * .lit attached afterwards replaces it (Quakespasm-Spiked's order: the
 * external .lit first, the lump only when no .lit loads).
 */
#include "asset/lightdata.h"
#include "ew_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define BSPX_MAX_LUMPS 1024
#define MAX_SHIFT 8
/* Light maps larger than this a side are refused (Quake's layout reaches
 * EW_MAX_EXTENT / 16 + 1; a 1-texel step 2049). */
#define MAX_LM_SIDE (EW_MAX_EXTENT + 1)

/* ---- .lit ---------------------------------------------------------------- */

int ew_world_attach_lit(ew_world *w, const uint8_t *data, size_t size, const char *filename) {
    if (!w) return 1;
    const char *f = filename ? filename : "(lit)";
    if (!data || size < 8) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: truncated .lit header (%zu bytes, need 8); coloured light ignored",
                f, data ? size : 0);
        return 1;
    }
    if (memcmp(data, "QLIT", 4) != 0) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: not a .lit file (magic is not \"QLIT\"); coloured light ignored", f);
        return 1;
    }
    int32_t version = ew_i32(data + 4);
    if (version != 1) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: .lit version %d (only 1 is known); coloured light ignored", f,
                (int)version);
        return 1;
    }
    uint64_t want = 3 * (uint64_t)w->lightsize;
    if (w->lightsize <= 0) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: the map has no light data for a .lit to colour; ignored", f);
        return 1;
    }
    if (size - 8 < want) {
        ew_warn(&w->warnings, &w->nwarnings,
                "%s: truncated .lit: %zu bytes of light, the map's %d samples need %llu; coloured light ignored", f,
                size - 8, w->lightsize, (unsigned long long)want);
        return 1;
    }
    if (size - 8 > want) {
        ew_warn(&w->warnings, &w->nwarnings,
                "%s: .lit size does not match the map: %zu bytes of light for %d samples (need %llu); coloured light ignored",
                f, size - 8, w->lightsize, (unsigned long long)want);
        return 1;
    }
    uint8_t *rgb = malloc((size_t)want);
    if (!rgb) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: out of memory for coloured light; ignored", f);
        return 1;
    }
    memcpy(rgb, data + 8, (size_t)want);
    free(w->rgblight);
    w->rgblight = rgb;
    for (int i = 0; i < w->nbspx; i++)
        if (w->bspx[i].use == EW_BSPX_USED && strcmp(w->bspx[i].name, "RGBLIGHTING") == 0)
            w->bspx[i].use = EW_BSPX_REPLACED;
    return 0;
}

/* ---- BSPX directory -------------------------------------------------------- */

/* 1 if a 'BSPX' id is at pos. */
static int bspx_at(const uint8_t *data, size_t size, uint64_t pos) {
    return pos + 4 <= size && memcmp(data + pos, "BSPX", 4) == 0;
}

void ew_bspx_open(ew_bspx *x, const uint8_t *data, size_t size, const ew_lump_info lumps[EW_NUM_LUMPS],
                  ew_world *w, const char *file) {
    memset(x, 0, sizeof *x);
    x->file = data, x->size = size;
    if (!data) return;
    const uint64_t header = 4 + 8 * EW_NUM_LUMPS;
    int taken = 0;
    uint64_t end = header;
    for (int i = 0; i < EW_NUM_LUMPS; i++) {
        if (lumps[i].length > 0 && lumps[i].offset == header) taken = 1;
        uint64_t e = (uint64_t)lumps[i].offset + lumps[i].length;
        if (lumps[i].length > 0 && e > end) end = e;
    }
    uint64_t pos;
    if (!taken && bspx_at(data, size, header))
        pos = header;
    else if (bspx_at(data, size, (end + 3) & ~(uint64_t)3))
        pos = (end + 3) & ~(uint64_t)3;
    else
        return;  /* no BSPX: nothing to say */
    x->present = 1;

    if (pos + 8 > size) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX directory at offset %llu is truncated (file is %zu bytes); BSPX ignored",
                file, (unsigned long long)pos, size);
        return;
    }
    int32_t n = ew_i32(data + pos + 4);
    if (n < 0 || n > BSPX_MAX_LUMPS) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX directory claims %d lumps (0..%d); BSPX ignored", file, (int)n,
                BSPX_MAX_LUMPS);
        return;
    }
    uint64_t dir_end = pos + 8 + 32 * (uint64_t)n;
    if (dir_end > size) {
        ew_warn(&w->warnings, &w->nwarnings,
                "%s: BSPX directory of %d lumps at offset %llu overruns the file (%zu bytes); BSPX ignored", file, (int)n,
                (unsigned long long)pos, size);
        return;
    }
    const uint8_t *dir = data + pos + 8;
    for (int i = 0; i < n; i++) {
        const uint8_t *e = dir + 32 * i;
        if (!memchr(e, 0, 24)) {
            ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX lump %d: name not zero-terminated; BSPX ignored", file, i);
            return;
        }
        int32_t ofs = ew_i32(e + 24), len = ew_i32(e + 28);
        if (ofs < 0 || len < 0 || (uint64_t)ofs + (uint64_t)len > size) {
            ew_warn(&w->warnings, &w->nwarnings,
                    "%s: BSPX lump '%s' at offset %d, length %d lies outside the file (%zu bytes); BSPX ignored", file,
                    (const char *)e, (int)ofs, (int)len, size);
            return;
        }
        if (len == 0) continue;
        if ((uint64_t)ofs < dir_end && (uint64_t)ofs + (uint64_t)len > pos) {
            ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX lump '%s' overlaps the BSPX directory; BSPX ignored", file,
                    (const char *)e);
            return;
        }
        for (int j = 0; j < i; j++) {
            const uint8_t *o = dir + 32 * j;
            int32_t oo = ew_i32(o + 24), ol = ew_i32(o + 28);
            if (ol > 0 && ofs < (int64_t)oo + ol && oo < (int64_t)ofs + len) {
                ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX lumps '%s' and '%s' overlap; BSPX ignored", file,
                        (const char *)o, (const char *)e);
                return;
            }
        }
    }
    x->dir = dir;
    x->n = n;
    /* The list `edgewise info` shows: every lump, known or not; the
     * readers below mark the ones they use. */
    free(w->bspx);
    w->bspx = NULL, w->nbspx = 0;
    if (n > 0 && (w->bspx = calloc((size_t)n, sizeof *w->bspx)) != NULL) {
        for (int i = 0; i < n; i++) {
            const uint8_t *e = dir + 32 * i;
            memcpy(w->bspx[i].name, e, 24);  /* NUL within the 24 bytes: checked above */
            w->bspx[i].offset = (uint32_t)ew_i32(e + 24), w->bspx[i].length = (uint32_t)ew_i32(e + 28);
            w->bspx[i].use = EW_BSPX_UNUSED;
        }
        w->nbspx = n;
    }
}

/* Records how the lump of that name was taken (every entry of the name). */
static void bspx_mark(ew_world *w, const char *name, ew_bspx_use use) {
    for (int i = 0; i < w->nbspx; i++)
        if (strcmp(w->bspx[i].name, name) == 0) w->bspx[i].use = use;
}

const uint8_t *ew_bspx_find(const ew_bspx *x, const char *name, size_t *len) {
    *len = 0;
    if (!x->dir) return NULL;
    for (int i = 0; i < x->n; i++) {
        const uint8_t *e = x->dir + 32 * i;
        if (strcmp((const char *)e, name) != 0) continue;  /* open() checked the NUL */
        *len = (size_t)ew_i32(e + 28);
        return x->file + ew_i32(e + 24);
    }
    return NULL;
}

int ew_bspx_moves_light(const ew_bspx *x) {
    size_t n;
    if (x->present && !x->dir) return 1;
    return ew_bspx_find(x, "LMSHIFT", &n) || ew_bspx_find(x, "LMOFFSET", &n) ||
           ew_bspx_find(x, "DECOUPLED_LM", &n);
}

/* ---- RGBLIGHTING ------------------------------------------------------------- */

void ew_bspx_rgb(const ew_bspx *x, ew_world *w, const char *file) {
    size_t len;
    const uint8_t *p = ew_bspx_find(x, "RGBLIGHTING", &len);
    if (!p) return;
    bspx_mark(w, "RGBLIGHTING", EW_BSPX_IGNORED);  /* until it is taken */
    if (w->lightsize == 0 && len > 0 && len % 3 == 0 && len / 3 <= (size_t)INT32_MAX) {
        /* the mono lump may be left out when this one is present */
        int n = (int)(len / 3);
        uint8_t *mono = malloc((size_t)n), *rgb = malloc(len);
        if (!mono || !rgb) {
            free(mono), free(rgb);
            ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX lump 'RGBLIGHTING': out of memory; ignored", file);
            return;
        }
        for (int i = 0; i < n; i++) mono[i] = (uint8_t)((p[3 * i] + p[3 * i + 1] + p[3 * i + 2]) / 3);
        memcpy(rgb, p, len);
        free(w->lighting);
        w->lighting = mono, w->lightsize = n, w->rgblight = rgb;
        bspx_mark(w, "RGBLIGHTING", EW_BSPX_USED);
        return;
    }
    if (len != 3 * (uint64_t)w->lightsize || len == 0) {
        ew_warn(&w->warnings, &w->nwarnings,
                "%s: BSPX lump 'RGBLIGHTING' has %zu bytes, the light lump's %d samples need %llu; coloured light ignored",
                file, len, w->lightsize, 3 * (unsigned long long)w->lightsize);
        return;
    }
    uint8_t *rgb = malloc(len);
    if (!rgb) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX lump 'RGBLIGHTING': out of memory; ignored", file);
        return;
    }
    memcpy(rgb, p, len);
    free(w->rgblight);
    w->rgblight = rgb;
    bspx_mark(w, "RGBLIGHTING", EW_BSPX_USED);
}

/* ---- layouts ------------------------------------------------------------------ */

void ew_facelm_quake(const ew_face *f, ew_facelm *out) {
    out->width = (f->extents[0] >> 4) + 1;
    out->height = (f->extents[1] >> 4) + 1;
    out->lightofs = f->lightofs;
    for (int j = 0; j < 2; j++) {
        out->st_to_lm[j][0] = j == 0 ? 1.0f / 16 : 0;
        out->st_to_lm[j][1] = j == 1 ? 1.0f / 16 : 0;
        out->st_to_lm[j][2] = -(float)f->texturemins[j] / 16;
    }
}

/* Texture-space bounds of a face, single precision as the loader. */
static void face_st_bounds(const ew_world *w, const ew_face *f, float mins[2], float maxs[2]) {
    const ew_texinfo *ti = &w->texinfo[f->texinfo];
    mins[0] = mins[1] = INFINITY, maxs[0] = maxs[1] = -INFINITY;
    for (int e = 0; e < f->numedges; e++) {
        const float *v = w->verts[ew_face_vertex(w, f, e)];
        for (int j = 0; j < 2; j++) {
            float val = v[0] * ti->vecs[j][0] + v[1] * ti->vecs[j][1] + v[2] * ti->vecs[j][2] + ti->vecs[j][3];
            if (val < mins[j]) mins[j] = val;
            if (val > maxs[j]) maxs[j] = val;
        }
    }
}

/* LMSHIFT layout: 0 or -1 with why filled. */
static int shift_layout(const ew_world *w, const ew_face *f, int shift, ew_facelm *lm, char *why, size_t nwhy) {
    if (shift < 0 || shift > MAX_SHIFT) {
        snprintf(why, nwhy, "LMSHIFT %d out of range 0..%d", shift, MAX_SHIFT);
        return -1;
    }
    float mins[2], maxs[2];
    face_st_bounds(w, f, mins, maxs);  /* the loader kept these within +-1e8 */
    float step = (float)(1 << shift);
    for (int j = 0; j < 2; j++) {
        double bmin = floor(mins[j] / step), bmax = ceil(maxs[j] / step);
        double side = bmax - bmin + 1;
        if (!(side >= 1 && side <= MAX_LM_SIDE)) {
            snprintf(why, nwhy, "light map of %.0f samples a side (LMSHIFT %d; limit %d)", side, shift, MAX_LM_SIDE);
            return -1;
        }
        int n = ew_int_checked(side, 1, MAX_LM_SIDE, 1);
        if (j == 0) lm->width = n; else lm->height = n;
        lm->st_to_lm[j][0] = j == 0 ? 1.0f / step : 0;
        lm->st_to_lm[j][1] = j == 1 ? 1.0f / step : 0;
        lm->st_to_lm[j][2] = (float)-bmin;
    }
    return 0;
}

/* DECOUPLED_LM: the world -> light-map matrix m (2x4) expressed in the
 * face's texture coordinates: points of the face plane are p0 + a e1 + b e2;
 * (s, t) and (u, v) are both affine in (a, b), so (u, v) is affine in (s, t). */
static int decoupled_layout(const ew_world *w, const ew_face *f, const float m[2][4], ew_facelm *lm, char *why,
                            size_t nwhy) {
    for (int j = 0; j < 2; j++)
        for (int k = 0; k < 4; k++)
            if (!isfinite(m[j][k]) || fabsf(m[j][k]) > 1e7f) {
                snprintf(why, nwhy, "DECOUPLED_LM projection is not finite or out of range");
                return -1;
            }
    const ew_plane *pl = &w->planes[f->plane];
    const ew_texinfo *ti = &w->texinfo[f->texinfo];
    double n[3] = {pl->normal[0], pl->normal[1], pl->normal[2]};
    double nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(nl > 1e-6)) {
        snprintf(why, nwhy, "plane %d has no normal", f->plane);
        return -1;
    }
    for (int k = 0; k < 3; k++) n[k] /= nl;
    /* e1: n x (the axis least along n), e2 = n x e1 */
    int ax = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2) : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
    double a[3] = {0, 0, 0};
    a[ax] = 1;
    double e1[3] = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]};
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; k++) e1[k] /= l1;
    double e2[3] = {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
    double p0[3];
    for (int k = 0; k < 3; k++) p0[k] = n[k] * pl->dist / nl;

#define DOT3(v, q) ((double)(v)[0] * (q)[0] + (double)(v)[1] * (q)[1] + (double)(v)[2] * (q)[2])
    double sa = DOT3(ti->vecs[0], e1), sb = DOT3(ti->vecs[0], e2);
    double ta = DOT3(ti->vecs[1], e1), tb = DOT3(ti->vecs[1], e2);
    double s0 = DOT3(ti->vecs[0], p0) + ti->vecs[0][3], t0 = DOT3(ti->vecs[1], p0) + ti->vecs[1][3];
    double det = sa * tb - sb * ta;
    double scale = (fabs(sa) + fabs(sb)) * (fabs(ta) + fabs(tb));
    if (!(fabs(det) > 1e-9 * scale) || !(scale > 0)) {
        snprintf(why, nwhy, "texture axes are degenerate on the face plane");
        return -1;
    }
    for (int j = 0; j < 2; j++) {
        double ua = DOT3(m[j], e1), ub = DOT3(m[j], e2), u0 = DOT3(m[j], p0) + m[j][3];
        /* (a, b) = inverse([[sa sb][ta tb]]) (s - s0, t - t0) */
        double cs = (ua * tb - ub * ta) / det, ct = (-ua * sb + ub * sa) / det;
        double c0 = u0 - cs * s0 - ct * t0;
        if (!isfinite(cs) || !isfinite(ct) || !isfinite(c0) || fabs(c0) > 1e9) {
            snprintf(why, nwhy, "DECOUPLED_LM projection out of range on this face");
            return -1;
        }
        lm->st_to_lm[j][0] = (float)cs, lm->st_to_lm[j][1] = (float)ct, lm->st_to_lm[j][2] = (float)c0;
    }
#undef DOT3
    return 0;
}

void ew_bspx_layout(const ew_bspx *x, ew_world *w, const char *file, const uint8_t *faces, int rec,
                    int styles_at) {
    const int nf = w->numfaces;
    size_t len_shift, len_ofs, len_style, len_dec;
    const uint8_t *shift = ew_bspx_find(x, "LMSHIFT", &len_shift);
    const uint8_t *ofs = ew_bspx_find(x, "LMOFFSET", &len_ofs);
    const uint8_t *style = ew_bspx_find(x, "LMSTYLE", &len_style);
    const uint8_t *dec = ew_bspx_find(x, "DECOUPLED_LM", &len_dec);
    if (!shift && !ofs && !style && !dec) return;
    /* left out unless the layout below is taken */
    static const char *const layout_lumps[] = {"LMSHIFT", "LMOFFSET", "LMSTYLE", "DECOUPLED_LM"};
    for (int k = 0; k < 4; k++) bspx_mark(w, layout_lumps[k], EW_BSPX_IGNORED);

    /* per-face counts first: a lump for another face count is dropped */
    if (dec && len_dec != 40 * (uint64_t)nf) {
        ew_warn(&w->warnings, &w->nwarnings,
                "%s: BSPX lump 'DECOUPLED_LM' has %zu bytes, %d faces need %llu; ignored", file, len_dec, nf,
                40 * (unsigned long long)nf);
        dec = NULL;
    }
    if ((shift && len_shift != (uint64_t)nf) || (ofs && len_ofs != 4 * (uint64_t)nf) ||
        (style && len_style != 4 * (uint64_t)nf)) {
        const char *bad = shift && len_shift != (uint64_t)nf ? "LMSHIFT" : ofs && len_ofs != 4 * (uint64_t)nf ? "LMOFFSET" : "LMSTYLE";
        size_t blen = !strcmp(bad, "LMSHIFT") ? len_shift : !strcmp(bad, "LMOFFSET") ? len_ofs : len_style;
        ew_warn(&w->warnings, &w->nwarnings,
                "%s: BSPX lump '%s' has %zu bytes for %d faces (%d a face); LMSHIFT/LMOFFSET/LMSTYLE ignored", file,
                bad, blen, nf, !strcmp(bad, "LMSHIFT") ? 1 : 4);
        shift = ofs = style = NULL;
    }
    if (!shift && !ofs && !style && !dec) return;
    const char *lumpname = dec ? "DECOUPLED_LM" : shift ? "LMSHIFT" : ofs ? "LMOFFSET" : "LMSTYLE";

    ew_facelm *lm = calloc(nf > 0 ? (size_t)nf : 1, sizeof *lm);
    uint8_t (*styles)[4] = malloc((nf > 0 ? (size_t)nf : 1) * 4);
    if (!lm || !styles) {
        free(lm), free(styles);
        ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX light layout: out of memory; ignored", file);
        return;
    }
    char why[200];
    for (int i = 0; i < nf; i++) {
        const ew_face *f = &w->faces[i];
        const uint8_t *rec_p = faces + (size_t)rec * i;
        memcpy(styles[i], style ? style + 4 * i : rec_p + styles_at, 4);
        int32_t lightofs = ofs ? ew_i32(ofs + 4 * i) : ew_i32(rec_p + styles_at + 4);
        if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) {
            ew_facelm_quake(f, &lm[i]);
            lm[i].lightofs = -1;
            memset(styles[i], 255, 4);
            continue;
        }
        /* styles after the first unused one are unused too */
        int ns = 0;
        while (ns < 4 && styles[i][ns] != 255) ns++;
        for (int k = ns; k < 4; k++) styles[i][k] = 255;
        const uint8_t *d = dec ? dec + 40 * (size_t)i : NULL;
        if (d) lightofs = ew_i32(d + 4);
        /* No light map: an offset of -1, no styles, or (DECOUPLED_LM, which
         * ericw writes as all zeros: 0x0 samples, offset -1) no samples.
         * Quake's grid with no samples, so the face is drawn dark as the
         * same map without BSPX draws it, and nothing reads past the
         * layout (its matrix is never used: not checked). */
        if (lightofs == -1 || ns == 0 || (d && (ew_u16(d) == 0 || ew_u16(d + 2) == 0))) {
            ew_facelm_quake(f, &lm[i]);
            lm[i].lightofs = -1;
            memset(styles[i], 255, 4);
            continue;
        }
        int rc;
        if (d) {
            float m[2][4];
            for (int k = 0; k < 8; k++) m[k / 4][k % 4] = ew_f32(d + 8 + 4 * k);
            lm[i].width = ew_u16(d), lm[i].height = ew_u16(d + 2);
            rc = decoupled_layout(w, f, m, &lm[i], why, sizeof why);
            if (rc == 0 && (lm[i].width > MAX_LM_SIDE || lm[i].height > MAX_LM_SIDE)) {
                snprintf(why, sizeof why, "light map of %dx%d samples (1..%d a side)", lm[i].width, lm[i].height,
                         MAX_LM_SIDE);
                rc = -1;
            }
        } else {
            rc = shift_layout(w, f, shift ? shift[i] : 4, &lm[i], why, sizeof why);
        }
        if (rc == 0) {
            int64_t need = (int64_t)lm[i].width * lm[i].height * ns;
            if (lightofs < 0 || lightofs + need > w->lightsize) {
                snprintf(why, sizeof why, "light samples at offset %d (%lld bytes) outside the light lump (%d bytes)",
                         (int)lightofs, (long long)need, w->lightsize);
                rc = -1;
            }
        }
        if (rc) {
            ew_warn(&w->warnings, &w->nwarnings, "%s: BSPX lump '%s': face %d: %s; light layout ignored", file,
                    lumpname, i, why);
            free(lm), free(styles);
            return;
        }
        lm[i].lightofs = lightofs;
    }
    /* Accepted: the faces take the new styles; ew_face.lightofs keeps the
     * offset only where Quake's layout also fits, so any reader that
     * ignores facelm stays inside the lump. */
    for (int i = 0; i < nf; i++) {
        ew_face *f = &w->faces[i];
        memcpy(f->styles, styles[i], 4);
        f->lightofs = lm[i].lightofs;
        if (f->lightofs < 0) continue;
        int ns = 0;
        while (ns < 4 && f->styles[ns] != 255) ns++;
        int64_t quake = (int64_t)((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1) * ns;
        if (f->lightofs + quake > w->lightsize) f->lightofs = -1;
    }
    free(styles);
    free(w->facelm);
    w->facelm = lm;
    /* DECOUPLED_LM gives its own sizes and offsets: LMSHIFT and LMOFFSET
     * beside it stay unused */
    if (dec) bspx_mark(w, "DECOUPLED_LM", EW_BSPX_USED);
    if (style) bspx_mark(w, "LMSTYLE", EW_BSPX_USED);
    if (shift && !dec) bspx_mark(w, "LMSHIFT", EW_BSPX_USED);
    if (ofs && !dec) bspx_mark(w, "LMOFFSET", EW_BSPX_USED);
}
