/* Sky: Quake's two scrolling layers seen as a flattened dome.  The ray
 * through the pixel, with its height stretched 3x, is normalized and its
 * x, y pick texels; the front layer (left half, colour 0 = clear) scrolls
 * twice as fast as the back layer (right half).  Unlit. */
#include "ew_render.h"

#include <math.h>

static int wrap(int x, int n) {
    x %= n;
    return x < 0 ? x + n : x;
}

uint8_t ew_sky_pixel(const ew_view *v, const ew_texture *t, float u, float y) {
    float a = (u - v->xcenter) / v->xscale, b = (v->ycenter - y) / v->yscale;
    float d[3];
    for (int k = 0; k < 3; k++) d[k] = v->forward[k] + a * v->right[k] + b * v->up[k];
    d[2] *= 3.0f;
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 0) d[0] /= len, d[1] /= len;
    int half = t->width / 2, rows = t->height;
    if (half < 1) half = 1;
    float reach = 6.0f * (rows / 2 - 1);
    float scroll = (float)fmod(v->time * 8.0, 65536.0);
    float s = reach * d[0], tt = reach * d[1];
    const uint8_t *px = t->mip[0];
    int fs = wrap((int)floorf(s + 2 * scroll), half), ft = wrap((int)floorf(tt + 2 * scroll), rows);
    uint8_t front = px[ft * t->width + fs];
    if (front) return front;
    int bs = wrap((int)floorf(s + scroll), half), bt = wrap((int)floorf(tt + scroll), rows);
    return px[bt * t->width + half + bs];
}

void ew_draw_sky_spans(ew_renderer *r, const ew_band *b, int surf, const ew_texture *t) {
    for (int si = b->span_head[surf]; si >= 0; si = b->spans[si].next) {
        const ew_span *sp = &b->spans[si];
        uint8_t *dst = r->frame + (size_t)sp->v * r->width + sp->u;
        for (int i = 0; i < sp->count; i++) dst[i] = ew_sky_pixel(&r->view, t, (float)(sp->u + i), (float)sp->v);
    }
}
