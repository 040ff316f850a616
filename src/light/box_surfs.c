/* An item box's lit surfaces, every face at every mip: boxes are small, so
 * all four are kept, built in the serial per-frame pass and rebuilt only
 * when a light style on the face or its texture frame changes; the bands
 * only read them. */
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

void ew_free_box_surfs(ew_renderer *r) {
    for (int i = 0; i < r->ents.nbox_surfs; i++) {
        ew_box_surfs *b = r->ents.box_surfs[i];
        for (int f = 0; b && f < b->nfaces; f++)
            for (int m = 0; m < 4; m++) free(b->face[f].pixels[m]);
        free(b);
    }
    free(r->ents.box_surfs);
    r->ents.box_surfs = NULL;
    r->ents.nbox_surfs = 0;
}

static void box_light(const ew_renderer *r, const ew_face *f, int light[4]) {
    for (int k = 0; k < 4; k++) light[k] = f->styles[k] == 255 ? 0 : r->f.cfg.lightstyle[f->styles[k] & 63];
}

/* Makes scene model mi's box surfaces current; -1 when out of memory. */
int ew_prepare_box(ew_renderer *r, int mi, const ew_world *bw) {
    if (mi >= r->ents.nbox_surfs) {
        ew_box_surfs **p = realloc(r->ents.box_surfs, sizeof *p * (size_t)(mi + 1));
        if (!p) return -1;
        for (int i = r->ents.nbox_surfs; i <= mi; i++) p[i] = NULL;
        r->ents.box_surfs = p, r->ents.nbox_surfs = mi + 1;
    }
    const ew_model *m = &bw->models[0];
    ew_box_surfs *b = r->ents.box_surfs[mi];
    if (!b) {
        b = calloc(1, sizeof *b + sizeof(ew_box_surf) * (size_t)m->numfaces);
        if (!b) return -1;
        b->nfaces = m->numfaces;
        r->ents.box_surfs[mi] = b;
    }
    int rc = 0;
    for (int i = 0; i < b->nfaces; i++) {
        const ew_face *f = &bw->faces[m->firstface + i];
        ew_box_surf *bs = &b->face[i];
        if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) continue;
        int light[4];
        box_light(r, f, light);
        const ew_texture *tex = ew_face_texture(bw, f, r->f.view.time);
        if (bs->built && bs->tex == tex && bs->gen == r->lit.cache.gen && memcmp(light, bs->light, sizeof light) == 0)
            continue;
        bs->built = 0;
        int *scratch = malloc(sizeof(int) * 3 * (size_t)ew_face_samples(bw, f));
        int ok = scratch != NULL;
        for (int mip = 0; mip < 4 && ok; mip++) {
            int w = f->extents[0] >> mip, h = f->extents[1] >> mip;
            if (!bs->pixels[mip]) bs->pixels[mip] = malloc((size_t)w * h * (size_t)r->f.target.bpp);
            ok = bs->pixels[mip] != NULL;
            if (ok) ew_build_surface(r, bw, f, tex, mip, light, 0, bs->pixels[mip], scratch);
            bs->width[mip] = w;
        }
        free(scratch);
        if (!ok) {
            rc = -1;
            continue;
        }
        memcpy(bs->light, light, sizeof light);
        bs->tex = tex, bs->gen = r->lit.cache.gen;
        bs->built = 1;
    }
    return rc;
}
