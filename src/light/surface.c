/* Surface building: tile the face's texture (at the chosen mip level) into a
 * buffer the size of the face, lighting each texel from the face's light
 * map through the colormap.  Light samples sit every 16 texels and are
 * interpolated bilinearly between them; up to four light styles add up. */
#include "renderer.h"

int ew_face_mip(const ew_view *v, const ew_world *w, const ew_face *f, float nearzi) {
    float scale = nearzi * (v->xscale > v->yscale ? v->xscale : v->yscale) * w->texinfo[f->texinfo].mipadjust;
    /* Coarser mips once a texel covers less than a pixel (0.8 leaves a little
     * sharpness margin, as the original did). */
    if (scale >= 1.0f) return 0;
    if (scale >= 0.4f) return 1;
    if (scale >= 0.2f) return 2;
    return 3;
}

const ew_texture *ew_face_texture(const ew_world *w, const ew_face *f, double time) {
    const ew_texture *t = &w->textures[w->texinfo[f->texinfo].texture];
    if (t->anim_total <= 0 || time <= 0) return t;
    int frame = (int)(time * 5.0) % t->anim_total;  /* five frames a second */
    for (int guard = 0; guard < 20 && !(frame >= t->anim_min && frame < t->anim_max); guard++) {
        if (t->anim_next < 0) break;
        t = &w->textures[t->anim_next];
    }
    return t;
}

static int wrap(int x, int n) {
    x %= n;
    return x < 0 ? x + n : x;
}

void ew_build_surface(const ew_renderer *r, const ew_world *w, const ew_face *f,
                      const ew_texture *tex, int mip, const int light[4], unsigned dlights,
                      uint8_t *out, int *scratch) {
    const uint8_t *cmap = r->colormap;
    int smax = (f->extents[0] >> 4) + 1, tmax = (f->extents[1] >> 4) + 1;
    int *bl = scratch;
    int size = smax * tmax;

    if (!w->lighting) {
        for (int i = 0; i < size; i++) bl[i] = 32 << 8;  /* unlit map: colours as they are */
    } else {
        /* Start dark; a face without a light map stays dark, as in Quake. */
        for (int i = 0; i < size; i++) bl[i] = 0;
        if (f->lightofs >= 0) {
            const uint8_t *lm = w->lighting + f->lightofs;
            for (int k = 0; k < 4 && f->styles[k] != 255; k++, lm += size)
                for (int i = 0; i < size; i++) bl[i] += lm[i] * light[k];
        }
        if (w == r->world) ew_add_dlights(r, f, dlights, bl);
        /* Light 0..255*256 becomes a colormap row in 8.8: bright maps to
         * low rows; the top is held just short of the overbright end. */
        for (int i = 0; i < size; i++) {
            int t = (255 * 256 - bl[i]) >> 2;
            bl[i] = t < (1 << 6) ? (1 << 6) : t;
        }
    }

    int bs = 16 >> mip, shift = 4 - mip;
    int tw = tex->width >> mip, th = tex->height >> mip;
    const uint8_t *tp = tex->mip[mip];
    int width = f->extents[0] >> mip;
    int s0 = wrap(f->texturemins[0] >> mip, tw), t0 = wrap(f->texturemins[1] >> mip, th);

    for (int j = 0; j < tmax - 1; j++) {
        for (int i = 0; i < smax - 1; i++) {
            int l00 = bl[j * smax + i], l10 = bl[j * smax + i + 1];
            int l01 = bl[(j + 1) * smax + i], l11 = bl[(j + 1) * smax + i + 1];
            /* Stepped in fixed point from the right-hand sample leftwards, as
             * the original did: the same rounding gives the same light rings. */
            int lstep = (l01 - l00) >> shift, rstep = (l11 - l10) >> shift;
            int left = l00, right = l10;
            for (int y = 0; y < bs; y++, left += lstep, right += rstep) {
                const uint8_t *row = tp + ((t0 + j * bs + y) % th) * tw;
                uint8_t *dst = out + (size_t)(j * bs + y) * width + i * bs;
                int step = (left - right) >> shift, l = right;
                int sx = (s0 + i * bs + bs - 1) % tw;
                for (int x = bs - 1; x >= 0; x--, l += step) {
                    dst[x] = cmap[(l & 0xFF00) + row[sx]];
                    if (--sx < 0) sx = tw - 1;
                }
            }
        }
    }
}
