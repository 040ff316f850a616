/* An item box's lit surfaces, every face at every mip: boxes are small, so
 * all four are kept, built in the serial per-frame pass and rebuilt only
 * when a light style on the face or its texture frame changes; the bands
 * only read them. */
#include "light/light.h"

#include <stdlib.h>
#include <string.h>

void ew_box_surfs_free(ew_box_surfs **surfs, int n) {
    for (int i = 0; i < n; i++) {
        ew_box_surfs *b = surfs[i];
        for (int f = 0; b && f < b->nfaces; f++)
            for (int m = 0; m < 4; m++) free(b->face[f].pixels[m]);
        free(b);
    }
    free(surfs);
}

static void box_light(const ew_frame *fr, const ew_face *f, int light[4]) {
    for (int k = 0; k < 4; k++) light[k] = f->styles[k] == 255 ? 0 : fr->cfg.lightstyle[f->styles[k] & 63];
}

/* Makes scene model mi's box surfaces current; -1 when out of memory. */
int ew_box_surfs_prepare(ew_box_surfs ***surfs, int *n, const ew_lit *lit, const ew_frame *fr, int mi,
                         const ew_world *bw) {
    if (mi >= *n) {
        ew_box_surfs **p = realloc(*surfs, sizeof *p * (size_t)(mi + 1));
        if (!p) return -1;
        for (int i = *n; i <= mi; i++) p[i] = NULL;
        *surfs = p, *n = mi + 1;
    }
    const ew_model *m = &bw->models[0];
    ew_box_surfs *b = (*surfs)[mi];
    if (!b) {
        b = calloc(1, sizeof *b + sizeof(ew_box_surf) * (size_t)m->numfaces);
        if (!b) return -1;
        b->nfaces = m->numfaces;
        (*surfs)[mi] = b;
    }
    int rc = 0;
    for (int i = 0; i < b->nfaces; i++) {
        const ew_face *f = &bw->faces[m->firstface + i];
        ew_box_surf *bs = &b->face[i];
        if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) continue;
        int light[4];
        box_light(fr, f, light);
        const ew_texture *tex = ew_face_texture(bw, f, fr->view.time);
        if (bs->built && bs->tex == tex && bs->gen == lit->cache.gen && memcmp(light, bs->light, sizeof light) == 0)
            continue;
        bs->built = 0;
        int *scratch = malloc(sizeof(int) * 3 * (size_t)ew_face_samples(bw, f));
        int ok = scratch != NULL;
        for (int mip = 0; mip < 4 && ok; mip++) {
            int w = ew_face_surf_size(f, 0, mip), h = ew_face_surf_size(f, 1, mip);
            if (!bs->pixels[mip]) bs->pixels[mip] = malloc((size_t)w * h * (size_t)fr->target.bpp);
            ok = bs->pixels[mip] != NULL;
            if (ok) ew_build_surface(lit, fr, bw, f, tex, mip, light, 0, bs->pixels[mip], scratch);
            bs->width[mip] = w;
        }
        free(scratch);
        if (!ok) {
            rc = -1;
            continue;
        }
        memcpy(bs->light, light, sizeof light);
        bs->tex = tex, bs->gen = lit->cache.gen;
        bs->built = 1;
    }
    return rc;
}
