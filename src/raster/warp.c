/* The underwater view: with the eye in water, slime or lava the finished
 * frame wobbles (each row shifted sideways and each column up and down by
 * sines that drift with time, the picture shrunk a little so no edge shows)
 * and takes on the liquid's colour, as the original renderer did.  It reads
 * pixels of other rows, so it runs after every band is drawn, from a copy. */
#include "raster/raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The liquid's colour and how far the frame moves towards it (of 256):
 * the original's contents shifts. */
static int tint_of(int contents, int rgb[3]) {
    static const int water[4] = {130, 80, 50, 128}, slime[4] = {0, 25, 5, 150}, lava[4] = {255, 80, 0, 150};
    const int *c = contents == EW_CONTENTS_WATER ? water : contents == EW_CONTENTS_SLIME ? slime : lava;
    rgb[0] = c[0], rgb[1] = c[1], rgb[2] = c[2];
    return c[3];
}

int ew_warp_begin(ew_warp *w, ew_frame *f, ew_blend *blend) {
    int c = f->eye_contents;
    if (f->cfg.classic || !f->cfg.waterwarp ||
        (c != EW_CONTENTS_WATER && c != EW_CONTENTS_SLIME && c != EW_CONTENTS_LAVA))
        return 0;
    const ew_target *t = &f->target;
    size_t frame = (size_t)t->pitch * (size_t)t->height;
    if (!w->copy) {
        /* the copy, then per row its x shift and per column its y shift */
        w->copy = malloc(frame + sizeof(int32_t) * (size_t)(t->width + t->height));
        if (!w->copy) {
            f->stats.dropped++;
            return 0;
        }
    }
    int rgb[3], amount = tint_of(c, rgb);
    w->tint = ew_blend_tint(blend, rgb, amount);
    for (int k = 0; k < 3; k++) w->rgb[k] = rgb[k];
    w->amount = amount;
    memcpy(w->copy, t->pixels, frame);
    /* Amplitude: 2.5 pixels at 320x200, in proportion above. */
    float amp = 2.5f * (float)t->height / 200.0f, tm = (float)f->view.time;
    int32_t *xs = (int32_t *)(void *)(w->copy + frame), *ys = xs + t->height;
    for (int y = 0; y < t->height; y++)
        xs[y] = (int32_t)lrintf(amp * (1 + sinf(6.2831853f * 3.0f * (float)y / (float)t->height + tm * 3.0f)));
    for (int x = 0; x < t->width; x++)
        ys[x] = (int32_t)lrintf(amp * (1 + sinf(6.2831853f * 4.0f * (float)x / (float)t->width + tm * 2.5f)));
    f->stats.underwater = 1;
    return 1;
}

void ew_warp_free(ew_warp *w) {
    free(w->copy);
    w->copy = NULL;
}

void ew_warp_rows(const ew_warp *w, const ew_target *t, int y0, int y1) {
    size_t frame = (size_t)t->pitch * (size_t)t->height;
    const int32_t *xs = (const int32_t *)(const void *)(w->copy + frame), *ys = xs + t->height;
    const uint8_t *tint = w->tint;
    /* Shrunk by twice the amplitude so the shifts stay inside the frame. */
    int amp2 = (int)lrintf(5.0f * (float)t->height / 200.0f);
    int sw = t->width - 1 - amp2, sh = t->height - 1 - amp2;
    if (sw < 1 || sh < 1) return;
    for (int y = y0; y < y1; y++) {
        uint8_t *dst = ew_target_at(t, 0, y);
        int by = (int)((int64_t)y * sh / (t->height - 1));
        for (int x = 0; x < t->width; x++) {
            int sx = (int)((int64_t)x * sw / (t->width - 1)) + xs[y];
            int sy = by + ys[x];
            sx = sx < 0 ? 0 : sx >= t->width ? t->width - 1 : sx;
            sy = sy < 0 ? 0 : sy >= t->height ? t->height - 1 : sy;
            const uint8_t *src = w->copy + (size_t)sy * t->pitch;
            if (t->bpp == 1) {
                dst[x] = tint[src[sx]];
            } else {  /* the same shift towards the liquid's colour, exactly */
                int c[3];
                ew_rgba_split(ew_get32(src, sx), c);
                for (int k = 0; k < 3; k++) c[k] += ((w->rgb[k] - c[k]) * w->amount) >> 8;
                ew_set32(dst, x, ew_rgba(c[0], c[1], c[2]));
            }
        }
    }
}
