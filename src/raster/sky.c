/* Sky: Quake's two scrolling layers seen as a flattened dome.  The ray
 * through the pixel, with its height stretched 3x, is normalized and its
 * x, y pick texels; the front layer (left half, colour 0 = clear) scrolls
 * twice as fast as the back layer (right half).  Unlit.  Spans compute the
 * exact coordinates every 32 pixels and step linearly between, as the
 * original did; the reference path computes every pixel. */
#include "raster/raster.h"

#include <math.h>

#define SKY_STEP 32

static int wrap(int x, int n) {
    x %= n;
    return x < 0 ? x + n : x;
}

/* Layer coordinates (texels, before scrolling) of the ray through (u, y). */
static void sky_st(const ew_view *v, const ew_texture *t, float u, float y, float *s, float *tt) {
    float a = (u - v->width * 0.5f) / v->xscale, b = (v->height * 0.5f - y) / v->yscale;
    float d[3];
    for (int k = 0; k < 3; k++) d[k] = v->forward[k] + a * v->right[k] + b * v->up[k];
    d[2] *= 3.0f;
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    float reach = 6.0f * (t->height / 2 - 1) / (len > 0 ? len : 1);
    *s = reach * d[0];
    *tt = reach * d[1];
}

float ew_sky_scroll(double time) { return (float)fmod(time * 8.0, 4096.0); }

static uint8_t sky_texel(const ew_view *v, const ew_texture *t, float s, float tt) {
    int half = t->width / 2 > 0 ? t->width / 2 : 1, rows = t->height;
    float scroll = ew_sky_scroll(v->time);
    const uint8_t *px = t->mip[0];
    uint8_t front = px[wrap((int)floorf(tt + 2 * scroll), rows) * t->width +
                       wrap((int)floorf(s + 2 * scroll), half)];
    if (front) return front;
    return px[wrap((int)floorf(tt + scroll), rows) * t->width + half +
              wrap((int)floorf(s + scroll), half)];
}

uint8_t ew_sky_pixel(const ew_view *v, const ew_texture *t, float u, float y) {
    float s, tt;
    sky_st(v, t, u, y, &s, &tt);
    return sky_texel(v, t, s, tt);
}

void ew_draw_sky_span(const ew_span_ctx *c, const ew_span *sp, const ew_texture *t) {
    const ew_view *v = c->view;
    int half = t->width / 2, rows = t->height;
    /* Power-of-two layers (Quake's are 128x128) wrap with a mask; others
     * take the exact path per pixel. */
    int pow2 = half > 0 && (half & (half - 1)) == 0 && rows > 0 && (rows & (rows - 1)) == 0;
    float scroll = c->sky_scroll;
    const uint8_t *px = t->mip[0];
    uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
    /* Read once: the pixel stores could alias the target struct. */
    const int bpp = c->target->bpp;
    const uint32_t *rgba = c->target->rgba;
    float s0, t0, s1, t1;
    int step = c->subdiv_shift ? SKY_STEP : 1;  /* exact mode: every pixel */
    sky_st(v, t, (float)sp->u, (float)sp->v, &s0, &t0);
    for (int i = 0; i < sp->count; i += step) {
        int n = sp->count - i < step ? sp->count - i : step;
        sky_st(v, t, (float)(sp->u + i + step), (float)sp->v, &s1, &t1);
        if (!pow2) {
            float ds = (s1 - s0) / step, dt = (t1 - t0) / step;
            for (int k = 0; k < n; k++) ew_put_via(bpp, rgba, dst, i + k, sky_texel(v, t, s0 + ds * k, t0 + dt * k));
        } else {
            /* 16.16 fixed point from the same floored start, two layers. */
            int32_t fs = (int32_t)floorf((s0 + 2 * scroll) * 65536.0f), ft = (int32_t)floorf((t0 + 2 * scroll) * 65536.0f);
            int32_t bs = (int32_t)floorf((s0 + scroll) * 65536.0f), bt = (int32_t)floorf((t0 + scroll) * 65536.0f);
            int32_t ds = (int32_t)((s1 - s0) * 65536.0f / step), dt = (int32_t)((t1 - t0) * 65536.0f / step);
            unsigned hm = (unsigned)half - 1, rm = (unsigned)rows - 1;
            for (int k = 0; k < n; k++) {
                uint8_t px_front = px[(((unsigned)ft >> 16) & rm) * (unsigned)t->width + (((unsigned)fs >> 16) & hm)];
                ew_put_via(bpp, rgba, dst, i + k,
                             px_front ? px_front
                                      : px[(((unsigned)bt >> 16) & rm) * (unsigned)t->width + (unsigned)half +
                                           (((unsigned)bs >> 16) & hm)]);
                fs += ds, ft += dt, bs += ds, bt += dt;
            }
        }
        s0 = s1, t0 = t1;
    }
}
