/* Particles: z-buffered squares of one palette colour, shrinking with
 * distance (about 2 pixels at 100 units on a 640-wide, 90-degree view;
 * the size scales with the projection, so with the frame width). */
#include "raster/alias.h"

#include <math.h>

#define PARTICLE_NEAR 4.0f

void ew_draw_particles_rows(const ew_frame *f, ew_zfill *zf, const ew_particle *p, int n, const ew_rows *rows) {
    if (!f || !p || n <= 0) return;
    const ew_view *v = &f->view;
    float k = v->xscale * 0.625f;          /* size in pixels = k / z */
    int maxsize = v->width / 80 > 4 ? v->width / 80 : 4;
    long pixels = 0;
    int drawn = 0;
    for (int i = 0; i < n; i++) {
        float q[3];
        if (!isfinite(p[i].org[0]) || !isfinite(p[i].org[1]) || !isfinite(p[i].org[2])) continue;
        ew_view_transform(v, p[i].org, q);
        if (!(q[2] >= PARTICLE_NEAR)) continue;
        float zi = 1.0f / q[2];
        float u = v->xcenter + v->xscale * q[0] * zi, vv = v->ycenter - v->yscale * q[1] * zi;
        if (!(u > -1e6f && u < 1e6f && vv > -1e6f && vv < 1e6f)) continue;
        int size = (int)(k * zi + 0.5f);
        if (size < 1) size = 1;
        if (size > maxsize) size = maxsize;
        /* The square's pixel centres around the projected point. */
        int x0 = (int)floorf(u + 0.5f) - (size - 1) / 2, y0 = (int)floorf(vv + 0.5f) - (size - 1) / 2;
        int x1 = x0 + size, y1 = y0 + size;
        if (x0 < 0) x0 = 0;
        if (x1 > v->width) x1 = v->width;
        if (x0 >= x1 || y1 <= 0 || y0 >= v->height) continue;
        drawn++;  /* on screen, whichever rows this call owns */
        if (y0 < rows->y0) y0 = rows->y0;
        if (y1 > rows->y1) y1 = rows->y1;
        if (y0 >= y1) continue;
        uint8_t color = p[i].color;
        const int bpp = f->target.bpp;  /* read once: the stores could alias the renderer */
        const uint32_t *rgba = f->target.rgba;
        ew_zfill_rect(zf, x0, y0, x1, y1);
        for (int y = y0; y < y1; y++) {
            float *zr = ew_target_z(&f->target, 0, y);
            uint8_t *fr = ew_target_at(&f->target, 0, y);
            for (int x = x0; x < x1; x++) {
                if (zi >= zr[x]) {
                    zr[x] = zi;
                    ew_put_via(bpp, rgba, fr, x, color);
                    pixels++;
                }
            }
        }
    }
    if (rows->first) rows->stats->particles += drawn;
    rows->stats->alias_pixels += pixels;
}

int ew_particle_field(ew_particle *out, int n, const float center[3], float radius, uint32_t seed) {
    if (!out || n < 0 || !center) return 0;
    uint32_t s = seed * 2654435761u + 12345u;
    for (int i = 0; i < n; i++) {
        float d[3];
        /* Uniform in the unit ball by rejection (an LCG, so the same seed
         * always gives the same cloud). */
        for (int tries = 0;; tries++) {
            for (int k = 0; k < 3; k++) {
                s = s * 1664525u + 1013904223u;
                d[k] = (float)(s >> 8) * (2.0f / 16777216.0f) - 1.0f;
            }
            if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= 1.0f || tries > 64) break;
        }
        for (int k = 0; k < 3; k++) out[i].org[k] = center[k] + d[k] * radius;
        s = s * 1664525u + 1013904223u;
        out[i].color = (uint8_t)(0x60 + ((s >> 24) & 15));  /* one 16-colour ramp */
    }
    return n;
}
