/* Every registered hidden-surface method's capabilities (ew_hsr.flags,
 * hsr/hsr.h) against what it does, on views of e1m1 and start (fences) at
 * 320x200:
 *   EW_HSR_EDGE_LIST    its edge list and surfaces are the front end's own,
 *                       byte for byte (the edge method's list); and every
 *                       method's frame is the same with the front end's
 *                       parallel phases on two threads (which build that list
 *                       instead of calling face/poly: only for the flag);
 *   EW_HSR_OCCLUSION    occlusion culling leaves its frame unchanged and does
 *                       drop surfaces; without it the surfaces stay;
 *   EW_HSR_MAKES_SPANS  every row of every band is covered by its spans;
 *                       without it no span at all and the frame still right;
 *   EW_HSR_EXACT_ONCE   every row tiled by its spans once, left to right, and
 *                       overdraw exactly 1.0; without it (and spans) the bands
 *                       say their spans may overlap;
 *   EW_HSR_FENCES       without it no fence face in its surfaces; a method
 *                       given it does take them;
 *   EW_HSR_OWN_COMPOSE  the pass list is its own compose;
 *   EW_HSR_SHOWS_EDGES  the edges debug view draws edges over its frame, and
 *                       changes nothing without it.
 * Every frame also agrees with the reference's face ids (the raycast
 * approximates: 90%). */
#include "renderer.h"
#include "util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200
#define NVIEWS 10

static uint64_t mix(uint64_t h, const void *p, size_t n) {
    const uint8_t *b = p;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* The edge list and its surfaces, every field the front end sets. */
static uint64_t list_sig(const ew_renderer *r) {
    const ew_edge_list *el = &r->el;
    uint64_t h = 1469598103934665603ull;
    h = mix(h, &el->nedges, sizeof el->nedges), h = mix(h, &el->nsurfs, sizeof el->nsurfs);
    for (int i = 0; i < el->nedges; i++) {
        const ew_edge *e = &el->edges[i];
        h = mix(h, &e->u, sizeof e->u), h = mix(h, &e->u_step, sizeof e->u_step);
        h = mix(h, &e->v_first, sizeof e->v_first), h = mix(h, &e->v_last, sizeof e->v_last);
        h = mix(h, e->surfs, sizeof e->surfs), h = mix(h, &e->nearzi, sizeof e->nearzi);
    }
    for (int i = 0; i < el->nsurfs; i++) {
        const ew_surf *s = &el->surfs[i];
        h = mix(h, &s->key, sizeof s->key), h = mix(h, &s->face, sizeof s->face);
        h = mix(h, &s->flags, sizeof s->flags), h = mix(h, &s->insubmodel, sizeof s->insubmodel);
        h = mix(h, &s->nearzi, sizeof s->nearzi);
        if (s->insubmodel)  /* the 1/z plane the front end keeps (world faces': the method's own, if any) */
            h = mix(h, &s->zi_u, sizeof s->zi_u), h = mix(h, &s->zi_v, sizeof s->zi_v),
            h = mix(h, &s->zi_0, sizeof s->zi_0);
    }
    return h;
}

static size_t frame_bytes(const ew_renderer *r) { return (size_t)r->f.target.pitch * (size_t)r->f.target.height; }

/* The bands' spans: rows covered, rows tiled once left to right, any band unsorted. */
typedef struct span_facts {
    long spans;
    int  rows_covered, rows_tiled, unsorted;
} span_facts;

static span_facts spans_of(const ew_renderer *r) {
    span_facts f = {0, 0, 0, 0};
    static uint8_t mark[W];
    for (int i = 0; i < r->sched.nbands; i++) {
        const ew_band *b = &r->sched.bands[i];
        f.spans += b->nspans;
        f.unsorted |= b->unsorted;
        int k = 0;
        for (int v = b->y0; v < b->y1; v++) {
            memset(mark, 0, sizeof mark);
            int end = 0, tiled = 1;
            for (; k < b->nspans && b->spans[k].v == v; k++) {
                const ew_span *sp = &b->spans[k];
                tiled = tiled && sp->u == end && sp->count > 0;
                end = sp->u + sp->count;
                for (int x = sp->u; x < sp->u + sp->count && x < W; x++)
                    if (x >= 0) mark[x] = 1;
            }
            int covered = 1;
            for (int x = 0; x < W; x++) covered = covered && mark[x];
            f.rows_covered += covered;
            f.rows_tiled += tiled && end == W;
        }
    }
    return f;
}

static int fence_surfaces(const ew_renderer *r) {
    int n = 0;
    for (int s = 1; s < r->el.nsurfs; s++)
        n += r->el.surfs[s].face >= 0 && (r->f.world->faces[r->el.surfs[s].face].flags & EW_SURF_FENCE);
    return n;
}

static ew_renderer *make(const ew_assets *a, int threads) {
    ew_error err;
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){.world = a->world, .palette = a->palette,
                                                            .colormap = a->colormap, .width = W, .height = H,
                                                            .threads = threads},
                                        &err);
    CHECK(r != NULL, "renderer: %s", err.msg);
    if (!r) return NULL;
    ew_enable_face_ids(r, 1);
    ew_set_occlusion_cull(r, EW_OCCLUSION_OFF);
    if (threads > 1) ew_set_front_mode(r, EW_FRONT_PHASES);
    return r;
}

typedef struct tally {
    int  views, occl_dropped, underwater, overdraw_exact;
    long occl_frames_differ, occl_kept_differ, phases_differ, list_differ, fence_surfs, edges_drawn_px,
        edges_nodebug_px, spans;
    int  rows_covered, rows_tiled, unsorted, rows;
    double worst_agree;
} tally;

static void check_map(const char *map, tally *t) {
    ew_scene *scene = NULL;
    ew_camera views[EW_MAX_VIEWS];
    int nv = 0;
    ew_assets *a = ew_t_load_map_scene(map, &scene, views, &nv);
    if (!a) return;
    ew_scene_destroy(scene);
    ew_renderer *r1 = make(a, 1), *r2 = make(a, 2);
    int *ref = malloc(sizeof(int) * W * H);
    uint8_t *p1 = malloc((size_t)W * H * 4);
    if (!r1 || !r2 || !ref || !p1) goto done;
    if (nv > NVIEWS) nv = NVIEWS;
    for (int v = 0; v < nv; v++) {
        ew_error err;
        CHECK(ew_render_reference(r1, &views[v], NULL, ref, &err) == 0, "%s view %d: %s", map, v, err.msg);
        uint64_t edge_list = 0;
        for (int m = 0; m < EW_HSR_COUNT; m++) {
            const ew_hsr *h = ew_hsr_get(m);
            if (!h) continue;
            tally *tm = &t[m];
            const unsigned fl = h->flags;
            ew_set_hsr(r1, (ew_hsr_method)m), ew_set_hsr(r2, (ew_hsr_method)m);
            ew_stats st;
            CHECK(ew_render(r1, &views[v], &st) == 0, "%s view %d %s: render", map, v, h->name);
            memcpy(p1, r1->f.target.pixels, frame_bytes(r1));
            tm->views++;
            /* the reference's faces */
            long same = 0;
            const int *ids = ew_frame_face_ids(r1);
            for (int i = 0; i < W * H; i++) same += ids[i] == ref[i];
            double ag = (double)same / (W * H);
            if (tm->views == 1 || ag < tm->worst_agree) tm->worst_agree = ag;
            /* spans */
            span_facts sf = spans_of(r1);
            tm->spans += sf.spans, tm->rows_covered += sf.rows_covered, tm->rows_tiled += sf.rows_tiled;
            tm->unsorted |= sf.unsorted, tm->rows += H;
            tm->overdraw_exact += st.overdraw == 1.0;
            /* the edge list, occlusion off */
            uint64_t sig = list_sig(r1);
            if (m == EW_HSR_EDGE) edge_list = sig;
            tm->list_differ += sig != edge_list;
            tm->fence_surfs += fence_surfaces(r1);
            int nsurfs = r1->el.nsurfs, under = r1->f.eye_contents != EW_CONTENTS_EMPTY;
            /* OWN_COMPOSE: the pass list */
            int own = ew_pass_count(&r1->passes) >= 2 && strcmp(ew_pass_name(&r1->passes, 1), "compose") == 0;
            CHECK(own == !!(fl & EW_HSR_OWN_COMPOSE), "%s: its pass list %s its own compose, flags %#x", h->name,
                  own ? "is" : "is not", fl);
            /* occlusion culling on */
            ew_set_occlusion_cull(r1, EW_OCCLUSION_ALWAYS);
            CHECK(ew_render(r1, &views[v], NULL) == 0, "render");
            tm->occl_frames_differ += memcmp(p1, r1->f.target.pixels, frame_bytes(r1)) != 0;
            tm->occl_dropped += r1->el.nsurfs < nsurfs;
            tm->occl_kept_differ += r1->el.nsurfs != nsurfs;
            ew_set_occlusion_cull(r1, EW_OCCLUSION_OFF);
            /* the edges debug view, over the frame above water */
            if (under) {
                tm->underwater++;
            } else {
                ew_set_debug(r1, EW_DEBUG_EDGES);
                CHECK(ew_render(r1, &views[v], NULL) == 0, "render");
                ew_set_debug(r1, EW_DEBUG_NONE);
                long px = 0;
                for (size_t i = 0; i < frame_bytes(r1); i++) px += p1[i] != r1->f.target.pixels[i];
                tm->edges_drawn_px += px;
                tm->edges_nodebug_px += (fl & EW_HSR_SHOWS_EDGES) ? 0 : px;
            }
            /* the front end's phases on two threads */
            CHECK(ew_render(r2, &views[v], NULL) == 0, "render");
            tm->phases_differ += memcmp(p1, r2->f.target.pixels, frame_bytes(r2)) != 0;
        }
    }
    /* EW_HSR_FENCES: the front end routes fence faces by it alone. */
    if (!strcmp(map, "start") && nv > 3) {
        ew_hsr fenced = ew_hsr_edge;
        fenced.flags |= EW_HSR_FENCES;
        ew_set_hsr(r1, EW_HSR_EDGE);
        CHECK(ew_render(r1, &views[3], NULL) == 0, "render");
        int before = fence_surfaces(r1);
        r1->f.cfg.hsr = &fenced;
        CHECK(ew_render(r1, &views[3], NULL) == 0, "render");
        int after = fence_surfaces(r1);
        r1->f.cfg.hsr = &ew_hsr_edge;
        CHECK(before == 0 && after > 0, "start view 3: fence faces in the edge list %d, with EW_HSR_FENCES %d",
              before, after);
    }
done:
    free(ref), free(p1);
    ew_renderer_destroy(r1), ew_renderer_destroy(r2);
    ew_assets_destroy(a);
}

int main(void) {
    if (!ew_t_have_shared("data/librequake/maps/e1m1.bsp") || !ew_t_have_shared("data/librequake/maps/start.bsp")) {
        fprintf(stderr, "../shared/data/librequake not found (set EW_SHARED): skipped\n");
        return 77;
    }
    tally t[EW_HSR_COUNT];
    memset(t, 0, sizeof t);
    check_map("e1m1", t);
    check_map("start", t);
    for (int m = 0; m < EW_HSR_COUNT; m++) {
        const ew_hsr *h = ew_hsr_get(m);
        if (!h) continue;
        const tally *tm = &t[m];
        const unsigned fl = h->flags;
        const char *n = h->name;
        CHECK(tm->views >= 2 * NVIEWS - 2, "%s: %d views", n, tm->views);
        if (!tm->views) continue;
        CHECK(tm->worst_agree >= (m == EW_HSR_RAYCAST ? 0.90 : 0.99), "%s: %.3f%% of pixels agree with the reference",
              n, 100 * tm->worst_agree);
        if (fl & EW_HSR_EDGE_LIST)
            CHECK(tm->list_differ == 0, "%s takes the front end's edge list, yet its list differs on %ld views", n,
                  tm->list_differ);
        CHECK(tm->phases_differ == 0, "%s: the frame changes with the front end's phases on %ld views", n,
              tm->phases_differ);
        if (fl & EW_HSR_OCCLUSION) {
            CHECK(tm->occl_frames_differ == 0, "%s: occlusion culling changes its frame on %ld views", n,
                  tm->occl_frames_differ);
            CHECK(tm->occl_dropped > 0, "%s: occlusion culling never dropped a surface", n);
        } else {
            CHECK(tm->occl_kept_differ == 0, "%s: occlusion culling changed its surfaces on %ld views", n,
                  tm->occl_kept_differ);
        }
        if (fl & EW_HSR_MAKES_SPANS)
            CHECK(tm->spans > 0 && tm->rows_covered == tm->rows, "%s: %ld spans, %d of %d rows covered", n, tm->spans,
                  tm->rows_covered, tm->rows);
        else
            CHECK(tm->spans == 0, "%s makes no spans, yet made %ld", n, tm->spans);
        if (fl & EW_HSR_EXACT_ONCE)
            CHECK(tm->rows_tiled == tm->rows && tm->overdraw_exact == tm->views && !tm->unsorted,
                  "%s: %d of %d rows tiled once, overdraw 1.0 on %d of %d views, unsorted %d", n, tm->rows_tiled,
                  tm->rows, tm->overdraw_exact, tm->views, tm->unsorted);
        else if (fl & EW_HSR_MAKES_SPANS)
            CHECK(tm->unsorted, "%s may overdraw, yet its bands say their spans are in order", n);
        if (!(fl & EW_HSR_FENCES))
            CHECK(tm->fence_surfs == 0, "%s: %ld fence faces among its surfaces", n, tm->fence_surfs);
        if (fl & EW_HSR_SHOWS_EDGES)
            CHECK(tm->edges_drawn_px > 0, "%s: the edges debug view drew no edge", n);
        else
            CHECK(tm->edges_nodebug_px == 0, "%s: the edges debug view changed %ld pixels", n, tm->edges_nodebug_px);
        printf("%-10s flags %#04x  views %2d  agree min %7.3f%%  spans %7ld  rows tiled %5d/%d  occlusion dropped on %d "
               "views  edges view px %ld\n",
               n, fl, tm->views, 100 * tm->worst_agree, tm->spans, tm->rows_tiled, tm->rows, tm->occl_dropped,
               tm->edges_drawn_px);
    }
    return ew_t_finish();
}
