/* The coverage map's per-face test (internal; world/occlude.c): inline,
 * since every face the edge method is handed takes it, and most are seen
 * or hidden after a look at a few words of the map. */
#ifndef EW_WORLD_OCCLUDE_H
#define EW_WORLD_OCCLUDE_H

#include "world/edge_math.h"

/* The faces of the strip's pending key are in: their tiles count now. */
void ew_occ_flush(ew_occlusion *o, ew_occ_strip *s);
/* A face seen in strip s notes the tiles it covers there (box b's rows
 * ra..rb), to be set when a larger key comes. */
void ew_occ_note(ew_occlusion *o, ew_occ_strip *s, const ew_proj *p, int n, ew_occ_box b);

/* The bits of word w of a row that tiles tx0..tx1 take. */
static inline uint64_t ew_occ_mask(int w, int tx0, int tx1) {
    uint64_t m = ~0ull;
    if (w == tx0 >> 6) m &= ~0ull << (tx0 & 63);
    if (w == tx1 >> 6) m &= ~0ull >> (63 - (tx1 & 63));
    return m;
}

/* Bits tx0..tx1 of a row of words: all set? */
static inline int ew_occ_row_full(const uint64_t *row, int tx0, int tx1) {
    for (int w = tx0 >> 6; w <= tx1 >> 6; w++) {
        uint64_t m = ew_occ_mask(w, tx0, tx1);
        if ((row[w] & m) != m) return 0;
    }
    return 1;
}

/* The projected face p[0..n) with box b (ew_occ_box_of) and BSP key key,
 * in strip s: 1 if faces with smaller keys cover every tile of b in the
 * strip (or b has none there), else 0, its covered tiles noted. */
static inline int ew_occ_face(ew_occlusion *o, ew_occ_strip *s, const ew_proj *p, int n, ew_occ_box b, int key) {
    if (key != s->key) {
        if (s->npend) ew_occ_flush(o, s);
        s->key = key;
    }
    int ty0 = b.ty0 > s->ty0 ? b.ty0 : s->ty0, ty1 = b.ty1 < s->ty1 ? b.ty1 : s->ty1;
    if (ty0 > ty1) return 1;  /* no pixel in this strip */
    int hidden = s->any && !s->failed;  /* nothing can be hidden before a tile is set */
    for (int ty = ty0; hidden && ty <= ty1; ty++)
        hidden = ew_occ_row_full(o->bits + (size_t)ty * (size_t)o->words, b.tx0, b.tx1);
    if (hidden) return 1;
    if (b.ra <= b.rb && b.ra <= s->ty1 && b.rb >= s->ty0) ew_occ_note(o, s, p, n, b);
    return 0;
}

#endif
