/* The lit surfaces' state (light/light.h ew_lit): what lighting keeps
 * from frame to frame (the surface cache, the light curve) and its rooms
 * per surface of the edge list and per thread. */
#include "light/light.h"

#include <stdlib.h>
#include <string.h>

int ew_lit_init(ew_lit *lit, const ew_world *w, const uint8_t *palette, const uint8_t *colormap, int max_surfs,
                size_t budget, int bpp) {
    int maxlm = 1;
    for (int i = 0; i < w->numfaces; i++) {
        int n = ew_face_samples(w, &w->faces[i]);
        if (!(w->faces[i].flags & (EW_SURF_SKY | EW_SURF_TURB)) && n > maxlm) maxlm = n;
    }
    lit->maxlm = maxlm;
    ew_lightcurve_fit(&lit->curve, palette, colormap);
    lit->surf_cache = malloc(sizeof(ew_cached_surf *) * (size_t)max_surfs);
    /* the edge list's surfaces and as many see-through ones (world/divert.c) */
    lit->to_build = malloc(sizeof(ew_cached_surf *) * (size_t)max_surfs * 2);
    lit->surf_state = malloc((size_t)max_surfs);
    lit->surf_mip = malloc((size_t)max_surfs);
    lit->grad_list = malloc(sizeof(int) * (size_t)max_surfs);
    if (!lit->surf_cache || !lit->to_build || !lit->surf_state || !lit->surf_mip ||
        !lit->grad_list)
        return -1;
    if (ew_cache_init(&lit->cache, w->numfaces, budget) < 0) return -1;
    lit->cache.bpp = bpp;
    return 0;
}

int ew_lit_threads(ew_lit *lit, int nthreads) {
    free(lit->blocklights);
    lit->blocklights = nthreads > 0 ? malloc(sizeof(int) * 3 * (size_t)lit->maxlm * (size_t)nthreads) : NULL;  /* RGB */
    return nthreads <= 0 || lit->blocklights ? 0 : -1;
}

void ew_lit_free(ew_lit *lit) {
    ew_cache_free(&lit->cache);
    free(lit->surf_cache), free(lit->to_build), free(lit->grad_list);
    free(lit->surf_state), free(lit->surf_mip), free(lit->tp_faces), free(lit->blocklights);
    lit->surf_cache = lit->to_build = NULL;
    lit->grad_list = NULL, lit->surf_state = lit->surf_mip = NULL;
    lit->tp_faces = NULL, lit->blocklights = NULL;
}
