/* Surface cache: lit surfaces survive across frames, one slot per face and
 * mip level, keyed by the texture frame and the light style values they
 * were built with, so a change of either rebuilds them.  Least recently
 * used surfaces are evicted once the byte budget is exceeded; a surface
 * used in the current frame is never evicted, and the cache never holds
 * more than twice its budget. */
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

int ew_cache_init(ew_surf_cache *c, int numfaces, size_t budget) {
    memset(c, 0, sizeof *c);
    c->slot = calloc((size_t)numfaces * 4 + 1, sizeof *c->slot);
    c->budget = budget;
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
    c->bytes -= (size_t)e->width * e->height;
    free(e->pixels);
    free(e);
}

void ew_cache_free(ew_surf_cache *c) {
    while (c->lru_head) evict(c, c->lru_head);
    free(c->slot);
    c->slot = NULL;
}

ew_cached_surf *ew_cache_lookup(ew_renderer *r, int face, int mip, int *build) {
    ew_surf_cache *c = &r->lit.cache;
    const ew_world *w = r->world;
    const ew_face *f = &w->faces[face];
    const ew_texture *tex = ew_face_texture(w, f, r->view.time);
    int texture = (int)(tex - w->textures);
    int light[4];
    for (int k = 0; k < 4; k++) light[k] = f->styles[k] == 255 ? 0 : r->cfg.lightstyle[f->styles[k] & 63];

    unsigned dl = ew_face_dlights(r, face);
    ew_cached_surf *e = c->slot[face * 4 + mip];
    *build = 0;
    /* A dynamically lit surface is good only for the frame that built it. */
    if (e && e->texture == texture && memcmp(e->light, light, sizeof light) == 0 && e->dlights == dl &&
        (!dl || e->last_frame == r->marks.framecount)) {
        if (e->last_frame != r->marks.framecount) r->stats.surfaces_cached++;
        lru_unlink(c, e);
        lru_push_front(c, e);
        e->last_frame = r->marks.framecount;
        return e;
    }
    int width = f->extents[0] >> mip, height = f->extents[1] >> mip;
    if (!e) {
        e = calloc(1, sizeof *e);
        if (!e) return NULL;
        e->face = face, e->mip = mip;
        c->slot[face * 4 + mip] = e;
    } else {
        lru_unlink(c, e);
        c->bytes -= (size_t)e->width * e->height;
        if (e->width * e->height != width * height) free(e->pixels), e->pixels = NULL;
    }
    /* Surfaces of this frame are never evicted, so a frame needing more
     * than the budget grows the cache; past twice the budget the surface
     * is refused (drawn flat, counted in dropped), so no map can make the
     * cache grow without bound. */
    size_t need = (size_t)width * height;
    while (c->bytes + need > c->budget && c->lru_tail && c->lru_tail->last_frame != r->marks.framecount)
        evict(c, c->lru_tail);
    if (c->bytes + need > 2 * c->budget) {
        c->slot[face * 4 + mip] = NULL;
        free(e->pixels);
        free(e);
        return NULL;
    }
    if (!e->pixels) e->pixels = malloc((size_t)width * height);
    if (!e->pixels) {
        c->slot[face * 4 + mip] = NULL;
        free(e);
        return NULL;
    }
    if (dl || e->dlights) r->stats.surfaces_rebuilt_by_dlights++;
    e->width = width, e->height = height, e->texture = texture, e->dlights = dl;
    memcpy(e->light, light, sizeof light);
    c->bytes += (size_t)width * height;
    lru_push_front(c, e);
    e->last_frame = r->marks.framecount;
    while (c->bytes > c->budget && c->lru_tail && c->lru_tail->last_frame != r->marks.framecount)
        evict(c, c->lru_tail);
    r->stats.surfaces_built++;
    *build = 1;
    return e;
}

void ew_cache_build(const ew_renderer *r, ew_cached_surf *e, int *scratch) {
    const ew_face *f = &r->world->faces[e->face];
    ew_build_surface(r, r->world, f, &r->world->textures[e->texture], e->mip, e->light, e->dlights, e->pixels,
                     scratch);
}
