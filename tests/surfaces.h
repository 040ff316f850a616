/* Test helpers over a renderer's last frame (they read internals: include
 * after "renderer.h"). */
#ifndef EW_TEST_SURFACES_H
#define EW_TEST_SURFACES_H

/* Whether face f uses light style `style`. */
static inline int face_uses_style(const ew_face *f, int style) {
    for (int k = 0; k < 4 && f->styles[k] != 255; k++)
        if (f->styles[k] == style) return 1;
    return 0;
}

/* The distinct lit surfaces (cache entries) of the last frame's surfaces
 * that won spans, into out (room for r->el.nsurfs); their count. */
static inline int frame_entries(const ew_renderer *r, ew_cached_surf **out) {
    int n = 0;
    for (int s = 1; s < r->el.nsurfs; s++) {
        ew_cached_surf *e = r->lit.surf_cache[s];
        int seen = !e;
        for (int i = 0; i < n && !seen; i++) seen = out[i] == e;
        if (!seen) out[n++] = e;
    }
    return n;
}

#endif
