/* Liquids ('*' textures): drawn straight from the texture, unlit, with each
 * coordinate displaced by a sine of the other that drifts with time. */
#include "span_step.h"

#include <math.h>

void ew_turb_table(int32_t table[128], double time) {
    int phase = (int)fmod(time * 20.0, 128.0);
    for (int i = 0; i < 128; i++)
        table[i] = (int32_t)(8 * 65536.0 * (1.0 + sin((i + phase) * 2 * 3.14159265358979 / 128)));
}

uint8_t ew_turb_texel(const int32_t table[128], const ew_texture *t, int32_t s, int32_t tt) {
    int x = (int)(((uint32_t)s + (uint32_t)table[(tt >> 16) & 127]) >> 16);
    int y = (int)(((uint32_t)tt + (uint32_t)table[(s >> 16) & 127]) >> 16);
    return t->mip[0][(y % t->height) * t->width + (x % t->width)];
}

void ew_draw_turb_span(ew_renderer *r, const ew_span *sp, const ew_gradients *g, const ew_texture *t) {
    uint8_t *dst = r->frame + (size_t)sp->v * r->width + sp->u;
    ew_stepper st;
    int32_t s, tt, ds, dt;
    int n;
    ew_step_begin(&st, g, r->subdiv_shift, sp->u, sp->v, sp->count);
    while ((n = ew_step_next(&st, &s, &tt, &ds, &dt)) > 0) {
        for (int i = 0; i < n; i++) {
            *dst++ = ew_turb_texel(r->turb, t, s, tt);
            s += ds;
            tt += dt;
        }
    }
}
