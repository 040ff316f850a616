/* Sutherland-Hodgman clipping of a world-space polygon against the
 * frustum planes a node or face still crosses.  Each output vertex keeps
 * the tag of the original edge leaving it (or -1 for an edge the clip
 * made), so the edge list can reuse whole world edges. */
#include "world/view.h"

int ew_clip_poly(const ew_view *v, int clipflags, float (*in)[3], int nin,
                 float (*out)[3], int *tag_in, int *tag_out) {
    float buf[2][EW_MAX_POLY][3];
    int tagbuf[2][EW_MAX_POLY];
    float (*src)[3] = in;
    int *stag = tag_in, n = nin;
    int which = 0;
    for (int pi = 0; pi < 4; pi++) {
        if (!(clipflags & (1 << pi))) continue;
        const ew_plane *p = &v->frustum[pi];
        float d[EW_MAX_POLY];
        int any_out = 0;
        for (int i = 0; i < n; i++) {
            d[i] = src[i][0] * p->normal[0] + src[i][1] * p->normal[1] + src[i][2] * p->normal[2] - p->dist;
            if (d[i] < 0) any_out = 1;
        }
        if (!any_out) continue;
        float (*dst)[3] = buf[which];
        int *dtag = tagbuf[which];
        int m = 0;
        for (int i = 0; i < n && m < EW_MAX_POLY - 2; i++) {
            int j = i + 1 == n ? 0 : i + 1;
            int in_i = d[i] >= 0, in_j = d[j] >= 0;
            if (in_i) {
                dst[m][0] = src[i][0], dst[m][1] = src[i][1], dst[m][2] = src[i][2];
                dtag[m++] = in_j ? stag[i] : -1;
            }
            if (in_i != in_j) {
                /* Always interpolate from the inside end, so the two faces that
                 * share this edge get bit-identical points and no crack. */
                const float *a = in_i ? src[i] : src[j], *b = in_i ? src[j] : src[i];
                float da = in_i ? d[i] : d[j], db = in_i ? d[j] : d[i];
                float t = da / (da - db);
                for (int k = 0; k < 3; k++) dst[m][k] = a[k] + t * (b[k] - a[k]);
                dtag[m++] = -1;
            }
        }
        src = dst, stag = dtag, n = m;
        which ^= 1;
        if (n < 3) return 0;
    }
    for (int i = 0; i < n; i++) {
        out[i][0] = src[i][0], out[i][1] = src[i][1], out[i][2] = src[i][2];
        tag_out[i] = stag[i];
    }
    return n;
}
