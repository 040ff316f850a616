/* What is drawn over the opaque world, in this order.  The edge list has
 * given every pixel exactly one world surface; each pass adds what can be
 * seen in front of (or through) it, z-tested against what is there. */
#include "renderer.h"

static const ew_pass passes[] = {
    {"models", ew_prepare_entities, ew_draw_models},  /* alias models, sprites, item boxes, particles */
    /* next: fences and translucent surfaces (back to front), then fog */
};

void ew_passes_prepare(ew_renderer *r) {
    for (size_t i = 0; i < sizeof passes / sizeof *passes; i++)
        if (passes[i].prepare) passes[i].prepare(r);
}

void ew_passes_draw(ew_renderer *r, const ew_rows *rows) {
    for (size_t i = 0; i < sizeof passes / sizeof *passes; i++) passes[i].draw(r, rows);
}
