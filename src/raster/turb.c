/* Liquids ('*' textures): drawn straight from the texture, unlit, with each
 * coordinate displaced by a sine of the other that drifts with time. */
#include "raster/span_step.h"

#include <math.h>

void ew_turb_table(int32_t table[128], int *held, double time) {
    int phase = (int)fmod(time * 20.0, 128.0);
    if (*held == phase + 1 + 128) return;  /* phase is in (-128, 128) */
    *held = phase + 1 + 128;
    for (int i = 0; i < 128; i++)
        table[i] = (int32_t)(8 * 65536.0 * (1.0 + sin((i + phase) * 2 * 3.14159265358979 / 128)));
}

/* The warped coordinates are never negative (unsigned, shifted down), so
 * for power-of-two textures a mask gives what the remainder would. */
static inline uint8_t turb_texel(const int32_t table[128], const ew_texture *t, int32_t s, int32_t tt,
                                 unsigned wmask, unsigned hmask) {
    unsigned x = ((uint32_t)s + (uint32_t)table[(tt >> 16) & 127]) >> 16;
    unsigned y = ((uint32_t)tt + (uint32_t)table[(s >> 16) & 127]) >> 16;
    if (wmask && hmask) return t->mip[0][(y & hmask) * (unsigned)t->width + (x & wmask)];
    return t->mip[0][(y % (unsigned)t->height) * (unsigned)t->width + (x % (unsigned)t->width)];
}

static unsigned pow2_mask(int n) { return n > 0 && (n & (n - 1)) == 0 ? (unsigned)n - 1 : 0; }

uint8_t ew_turb_texel(const int32_t table[128], const ew_texture *t, int32_t s, int32_t tt) {
    return turb_texel(table, t, s, tt, pow2_mask(t->width), pow2_mask(t->height));
}

void ew_draw_turb_span(const ew_span_ctx *c, const ew_span *sp, const ew_gradients *g, const ew_texture *t) {
    uint8_t *dst = ew_target_at(c->target, sp->u, sp->v);
    const int bpp = c->target->bpp;  /* read once: the stores could alias the target */
    const uint32_t *rgba = c->target->rgba;
    unsigned wmask = pow2_mask(t->width), hmask = pow2_mask(t->height);
    ew_stepper st;
    int32_t s, tt, ds, dt;
    int n;
    ew_step_begin(&st, g, c->subdiv_shift, sp->u, sp->v, sp->count);
    int x = 0;
    while ((n = ew_step_next(&st, &s, &tt, &ds, &dt)) > 0) {
        for (int i = 0; i < n; i++) {
            ew_put_via(bpp, rgba, dst, x++, turb_texel(c->turb, t, s, tt, wmask, hmask));
            s += ds;
            tt += dt;
        }
    }
}
