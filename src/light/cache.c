/* Surface cache: lit surfaces survive across frames, one slot per face and
 * mip level, keyed by the texture frame and the light style values they
 * were built with, so a change of either rebuilds them.  Least recently
 * used surfaces are evicted once the byte budget is exceeded; a surface
 * used in the current frame is never evicted, and the cache never holds
 * more than twice its budget.
 *
 * Memory: an entry and its pixels are one block carved from a few large
 * slabs (about a quarter of the budget each, allocated when first needed).
 * A freed block merges with free neighbours (each block records its own
 * size and its lower neighbour's) and goes on a free list by size class;
 * an allocation takes the first block that fits from the smallest class
 * that may hold one and splits off the rest.  So once the slabs have
 * settled, building and evicting surfaces allocates nothing.  Blocks never
 * move, so a surface's pixels stay put for the whole frame. */
#include "light/light.h"

#include <stdlib.h>
#include <string.h>

/* A block: its size in bytes with the tag (a multiple of ALIGN; bit 0 set
 * while in use) and the size of the block below it in the slab (0 for the
 * first).  A free block keeps its free-list links after the tag.  A slab
 * ends with a used block of size 0, so nothing merges past its end. */
struct ew_cache_block {
    size_t size, below;
};
typedef struct {
    ew_cache_block *next, *prev;
} free_links;
struct ew_cache_slab {
    ew_cache_slab *next;
};

#define ALIGN       ((size_t)16)
#define ROUND(n)    (((n) + ALIGN - 1) & ~(ALIGN - 1))
#define USED        ((size_t)1)
#define TAG         ROUND(sizeof(ew_cache_block))
#define MIN_BLOCK   ROUND(TAG + sizeof(free_links))
#define SLAB_HEAD   ROUND(sizeof(ew_cache_slab))
#define SLAB_MIN    ((size_t)256 << 10)
#define SLAB_MAX    ((size_t)64 << 20)

static size_t bsize(const ew_cache_block *b) { return b->size & ~USED; }
static ew_cache_block *above(ew_cache_block *b) { return (ew_cache_block *)((char *)b + bsize(b)); }
static ew_cache_block *below(ew_cache_block *b) { return (ew_cache_block *)((char *)b - b->below); }
static free_links *links(ew_cache_block *b) { return (free_links *)((char *)b + TAG); }

/* Size classes: four per power of two (sizes are at least MIN_BLOCK = 32). */
static int size_class(size_t size) {
    int lg = 0;
    while ((size >> lg) > 1) lg++;
    int k = (lg - 5) * 4 + (int)((size >> (lg - 2)) & 3);
    return k < 0 ? 0 : k >= EW_CACHE_BINS ? EW_CACHE_BINS - 1 : k;
}

static void bin_insert(ew_surf_cache *c, ew_cache_block *b) {
    int k = size_class(bsize(b));
    links(b)->prev = NULL;
    links(b)->next = c->bins[k];
    if (c->bins[k]) links(c->bins[k])->prev = b;
    c->bins[k] = b;
}

static void bin_remove(ew_surf_cache *c, ew_cache_block *b) {
    free_links *l = links(b);
    if (l->prev) links(l->prev)->next = l->next; else c->bins[size_class(bsize(b))] = l->next;
    if (l->next) links(l->next)->prev = l->prev;
}

/* A new slab holding at least one block of size bytes, or NULL.  Slabs are
 * added only while their free space is under half the budget (or one
 * minimum slab), so they total at most what is in use, plus that, plus
 * one slab; a surface that finds no room then (free space too scattered)
 * is refused like one past the cap (drawn flat, counted in dropped). */
static ew_cache_block *add_slab(ew_surf_cache *c, size_t size) {
    size_t sb = c->budget / 4;
    if (sb < SLAB_MIN) sb = SLAB_MIN;
    if (sb > SLAB_MAX) sb = SLAB_MAX;
    sb = ROUND(sb);
    if (sb < SLAB_HEAD + size + TAG) sb = SLAB_HEAD + size + TAG;
    size_t spare = c->budget / 2 > SLAB_MIN ? c->budget / 2 : SLAB_MIN;
    if (c->slab_bytes - c->used_bytes >= spare) return NULL;
    ew_cache_slab *s = malloc(sb);
    if (!s) return NULL;
    s->next = c->slabs;
    c->slabs = s;
    c->slab_bytes += sb;
    ew_cache_block *b = (ew_cache_block *)((char *)s + SLAB_HEAD);
    b->size = sb - SLAB_HEAD - TAG;
    b->below = 0;
    ew_cache_block *end = above(b);
    end->size = 0 | USED;
    end->below = bsize(b);
    return b;
}

static void *block_alloc(ew_surf_cache *c, size_t n) {
    size_t size = ROUND(TAG + n);
    if (size < MIN_BLOCK) size = MIN_BLOCK;
    ew_cache_block *b = NULL;
    for (int k = size_class(size); k < EW_CACHE_BINS && !b; k++)
        for (ew_cache_block *f = c->bins[k]; f; f = links(f)->next)
            if (bsize(f) >= size) {
                b = f;
                bin_remove(c, b);
                break;
            }
    if (!b && !(b = add_slab(c, size))) return NULL;
    size_t rest = bsize(b) - size;
    if (rest >= MIN_BLOCK) {
        b->size = size;
        ew_cache_block *r = above(b);
        r->size = rest;
        r->below = size;
        above(r)->below = rest;
        bin_insert(c, r);
    }
    b->size |= USED;
    c->used_bytes += bsize(b);
    return (char *)b + TAG;
}

static void block_free(ew_surf_cache *c, void *p) {
    ew_cache_block *b = (ew_cache_block *)((char *)p - TAG);
    b->size &= ~USED;
    c->used_bytes -= b->size;
    ew_cache_block *n = above(b);
    if (!(n->size & USED)) {
        bin_remove(c, n);
        b->size += n->size;
    }
    if (b->below) {
        ew_cache_block *l = below(b);
        if (!(l->size & USED)) {
            bin_remove(c, l);
            l->size += b->size;
            b = l;
        }
    }
    above(b)->below = b->size;
    bin_insert(c, b);
}

int ew_cache_init(ew_surf_cache *c, int numfaces, size_t budget) {
    memset(c, 0, sizeof *c);
    c->slot = calloc((size_t)numfaces * 4 + 1, sizeof *c->slot);
    c->budget = budget;
    c->bpp = 1;
    return c->slot ? 0 : -1;
}

static void lru_unlink(ew_surf_cache *c, ew_cached_surf *e) {
    if (e->lru_prev) e->lru_prev->lru_next = e->lru_next; else c->lru_head = e->lru_next;
    if (e->lru_next) e->lru_next->lru_prev = e->lru_prev; else c->lru_tail = e->lru_prev;
    e->lru_prev = e->lru_next = NULL;
}

static void lru_push_front(ew_surf_cache *c, ew_cached_surf *e) {
    e->lru_prev = NULL;
    e->lru_next = c->lru_head;
    if (c->lru_head) c->lru_head->lru_prev = e; else c->lru_tail = e;
    c->lru_head = e;
}

static void evict(ew_surf_cache *c, ew_cached_surf *e) {
    lru_unlink(c, e);
    c->slot[e->face * 4 + e->mip] = NULL;
    c->bytes -= (size_t)e->width * e->height * c->bpp;
    block_free(c, e);
}

void ew_cache_flush(ew_surf_cache *c) {
    while (c->lru_tail) evict(c, c->lru_tail);
    c->gen++;  /* and what keeps its own surfaces by the gen (item boxes) rebuilds them */
}

void ew_cache_free(ew_surf_cache *c) {
    while (c->slabs) {
        ew_cache_slab *s = c->slabs;
        c->slabs = s->next;
        free(s);
    }
    free(c->slot);
    memset(c, 0, sizeof *c);
}

/* The entry's texture and light styles as they are this frame. */
static int current_look(const ew_frame *fr, const ew_face *f, int light[4]) {
    const ew_world *w = fr->world;
    for (int k = 0; k < 4; k++) light[k] = f->styles[k] == 255 ? 0 : fr->cfg.lightstyle[f->styles[k] & 63];
    return (int)(ew_face_texture(w, f, fr->view.time) - w->textures);
}

ew_cached_surf *ew_lit_peek(const ew_lit *lit, const ew_frame *fr, int face, int mip) {
    const ew_surf_cache *c = &lit->cache;
    ew_cached_surf *e = c->slot[face * 4 + mip];
    if (!e) return NULL;
    int light[4], texture = current_look(fr, &fr->world->faces[face], light);
    unsigned dl = ew_face_dlights(lit->marks, face);
    /* A dynamically lit surface is good only for the frame that built it. */
    if (e->texture == texture && memcmp(e->light, light, sizeof light) == 0 && e->dlights == dl && e->gen == c->gen &&
        (!dl || e->last_frame == lit->marks->framecount))
        return e;
    return NULL;
}

void ew_lit_touch(ew_lit *lit, ew_frame *fr, ew_cached_surf *e) {
    ew_surf_cache *c = &lit->cache;
    int frame = lit->marks->framecount;
    if (e->last_frame != frame) fr->stats.surfaces_cached++;
    lru_unlink(c, e);
    lru_push_front(c, e);
    e->last_frame = frame;
}

ew_cached_surf *ew_lit_lookup(ew_lit *lit, ew_frame *fr, int face, int mip, int *build) {
    ew_surf_cache *c = &lit->cache;
    const ew_face *f = &fr->world->faces[face];
    const int frame = lit->marks->framecount;
    *build = 0;
    ew_cached_surf *e = ew_lit_peek(lit, fr, face, mip);
    if (e) {
        ew_lit_touch(lit, fr, e);
        return e;
    }
    int light[4], texture = current_look(fr, f, light);
    unsigned dl = ew_face_dlights(lit->marks, face);
    e = c->slot[face * 4 + mip];
    int width = ew_face_surf_size(f, 0, mip), height = ew_face_surf_size(f, 1, mip);
    unsigned old_dl = 0;
    if (e) {
        /* Stale: rebuilt in place (a face's size at a mip never changes,
         * but a block of the wrong size would be given back). */
        lru_unlink(c, e);
        c->bytes -= (size_t)e->width * e->height * c->bpp;
        old_dl = e->dlights;
        if (e->width != width || e->height != height) {
            c->slot[face * 4 + mip] = NULL;
            block_free(c, e);
            e = NULL;
        }
    }
    /* Surfaces of this frame are never evicted, so a frame needing more
     * than the budget grows the cache; past twice the budget the surface
     * is refused (drawn flat, counted in dropped), so no map can make the
     * cache grow without bound. */
    size_t need = (size_t)width * height * c->bpp;
    while (c->bytes + need > c->budget && c->lru_tail && c->lru_tail->last_frame != frame)
        evict(c, c->lru_tail);
    if (c->bytes + need > 2 * c->budget) {
        c->slot[face * 4 + mip] = NULL;
        if (e) block_free(c, e);
        return NULL;
    }
    if (!e) {
        e = block_alloc(c, sizeof *e + need);
        if (!e) return NULL;
        memset(e, 0, sizeof *e);
        e->face = face, e->mip = mip;
        e->pixels = (uint8_t *)(e + 1);
        c->slot[face * 4 + mip] = e;
    }
    if (dl || old_dl) fr->stats.surfaces_rebuilt_by_dlights++;
    e->width = width, e->height = height, e->texture = texture, e->dlights = dl, e->gen = c->gen;
    memcpy(e->light, light, sizeof light);
    c->bytes += need;
    lru_push_front(c, e);
    e->last_frame = frame;
    while (c->bytes > c->budget && c->lru_tail && c->lru_tail->last_frame != frame)
        evict(c, c->lru_tail);
    fr->stats.surfaces_built++;
    *build = 1;
    return e;
}

void ew_lit_build(const ew_lit *lit, const ew_frame *fr, ew_cached_surf *e, int *scratch) {
    const ew_face *f = &fr->world->faces[e->face];
    ew_build_surface(lit, fr, fr->world, f, &fr->world->textures[e->texture], e->mip, e->light, e->dlights, e->pixels,
                     scratch);
}
