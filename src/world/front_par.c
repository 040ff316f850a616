/* The front end on several threads, for the methods whose faces go through
 * ew_emit_face (the edge list and those that share its front end).
 *
 * The walk stays on the calling thread, but only lists each visible face
 * (face, clipflags, key) in BSP order.  Every CHUNK faces it publishes; the
 * pool's other threads take chunks as they appear and do the costly part:
 * clip each face to the frustum, project its vertices and set up each of
 * its polygon edges (position, step, scanlines, nearest 1/z).  The calling
 * thread, between faces of the walk and after it, merges the prepared
 * chunks strictly in order: the frame's edge cache (one world edge shared
 * by the two faces on it), edge and surface numbers, the per-scanline lists
 * of new edges and the counters come out exactly as ew_emit_face makes
 * them one face at a time, since the merge is that same decision made in
 * the same order on the same numbers (world/edge_math.h computes both).
 * So the edge list, and every span and pixel after it, are the same for
 * any thread count.
 *
 * The phase that follows (the scan of the bands) runs in the same pool
 * run: the calling thread, done with the walk, the merge and `tail` (the
 * brush models), releases the others into it, so the parallel front end
 * adds no wait for all threads to the frame.
 *
 * Faces and prepared edges live in arrays sized for the world (each face
 * of the world tree is on one node, visited once); if a malformed tree
 * shows more, the faces listed so far are merged and the rest of the walk
 * emits one face at a time, as the serial front end does. */
#define _POSIX_C_SOURCE 200809L  /* sched_yield */
#include "renderer.h"
#include "ew_util.h"
#include "world/edge_math.h"

#include <limits.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#define CHUNK 32       /* faces a thread prepares at a time */
/* Threads that prepare besides the calling one: preparing is about twice
 * the walk and merge, so a few keep up with it; more would only spin. */
#define HELPERS 3
#define PE_CLIP INT32_MIN  /* a prepared edge the clip made (no world edge) */

typedef struct pface {
    int face, clipflags, key;
    int pe;            /* its first prepared edge */
    int m;             /* prepared edges; -1: none (too many edges, or clipped away) */
} pface;

typedef struct pedge {
    ew_edge e;         /* u, u_step, v_first, v_last and nearzi (the larger 1/z of its ends) */
    int32_t se;        /* the signed world surfedge it lies on, or PE_CLIP */
    int8_t  down;      /* its second end is lower on the screen */
    int8_t  crosses;   /* it crosses a scanline centre */
} pedge;

struct ew_front_par {
    /* Written by the walk (calling thread), read by the workers. */
    _Alignas(64) atomic_int published;  /* faces listed so far, a multiple of CHUNK until the walk ends */
    atomic_int walk_done;
    _Alignas(64) atomic_int next_chunk; /* the next chunk to prepare */
    _Alignas(64) pface *faces;
    pedge      *pedges;
    pedge      *own;                   /* EW_MAX_POLY: the calling thread's, for a chunk it will not wait for */
    atomic_int *chunk_gen;             /* gen: prepared this frame */
    int         cap_faces, cap_pedges;
    int         gen;
    /* Only the calling thread: */
    int         nfaces, npe, merged;   /* chunks merged */
    int         direct;                /* overflowed: the rest of the walk emits directly */
    /* What follows in the same pool phase (ew_walk_world_parallel). */
    void      (*tail)(void *arg);
    void       *tail_arg;
    void      (*then)(void *ctx, int thread);
    _Alignas(64) atomic_int front_done; /* the tail has run: the edge list is complete */
};

/* One round of waiting on another thread; after a while the processor is
 * given up each round, so a waiting thread on a busy machine does not keep
 * the thread it waits for off its core. */
static inline void relax(int *rounds) {
    if (++*rounds > 256) {
        sched_yield();
        return;
    }
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

void ew_front_par_free(struct ew_front_par *fp) {
    if (!fp) return;
    free(fp->faces), free(fp->pedges), free(fp->chunk_gen), free(fp->own);
    free(fp);
}

static struct ew_front_par *front_par_new(const ew_world *w) {
    long cap_pe = (long)w->numsurfedges + 4L * w->numfaces + 8;
    if (cap_pe > INT_MAX / 2) return NULL;
    struct ew_front_par *fp = aligned_alloc(64, (sizeof *fp + 63) / 64 * 64);
    if (!fp) return NULL;
    memset(fp, 0, sizeof *fp);
    fp->cap_faces = w->numfaces + 1;
    fp->cap_pedges = (int)cap_pe;
    int nchunks = fp->cap_faces / CHUNK + 2;
    fp->faces = malloc(sizeof(pface) * (size_t)fp->cap_faces);
    fp->pedges = malloc(sizeof(pedge) * (size_t)fp->cap_pedges);
    fp->own = malloc(sizeof(pedge) * EW_MAX_POLY);
    fp->chunk_gen = malloc(sizeof(atomic_int) * (size_t)nchunks);
    if (!fp->faces || !fp->pedges || !fp->chunk_gen || !fp->own) {
        ew_front_par_free(fp);
        return NULL;
    }
    for (int i = 0; i < nchunks; i++) atomic_init(&fp->chunk_gen[i], 0);
    return fp;
}

/* ---- prepare (any thread): what ew_emit_face computes, minus the list ---- */

static void set_pedge(pedge *p, const ew_proj *a, const ew_proj *b, int32_t se) {
    p->se = se;
    p->down = b->v > a->v;
    p->crosses = (int8_t)ew_edge_setup(a, b, &p->e);
    p->e.nearzi = a->zi > b->zi ? a->zi : b->zi;
}

static void prepare(const ew_renderer *r, pface *pf, pedge *out) {
    const ew_world *w = r->world;
    const ew_face *f = &w->faces[pf->face];
    int n = f->numedges;
    pf->m = -1;
    if (n > EW_MAX_POLY - 8) return;
    ew_proj pj[EW_MAX_POLY];
    if (pf->clipflags == 0) {
        for (int i = 0; i < n; i++) ew_project(&r->view, w->verts[ew_face_vertex(w, f, i)], &pj[i]);
        for (int i = 0; i < n; i++)
            set_pedge(&out[i], &pj[i], &pj[i + 1 == n ? 0 : i + 1], w->surfedges[f->firstedge + i]);
        pf->m = n;
        return;
    }
    float in[EW_MAX_POLY][3], cl[EW_MAX_POLY][3];
    int tin[EW_MAX_POLY], tout[EW_MAX_POLY];
    for (int i = 0; i < n; i++) {
        const float *p = w->verts[ew_face_vertex(w, f, i)];
        in[i][0] = p[0], in[i][1] = p[1], in[i][2] = p[2];
        tin[i] = i;
    }
    int m = ew_clip_poly(&r->view, pf->clipflags, in, n, cl, tin, tout);
    if (m < 3) return;
    for (int i = 0; i < m; i++) ew_project(&r->view, cl[i], &pj[i]);
    for (int i = 0; i < m; i++)
        set_pedge(&out[i], &pj[i], &pj[i + 1 == m ? 0 : i + 1],
                  tout[i] >= 0 ? w->surfedges[f->firstedge + tout[i]] : PE_CLIP);
    pf->m = m;
}

static void prepare_chunk(const ew_renderer *r, struct ew_front_par *fp, int c, int end) {
    int hi = (c + 1) * CHUNK < end ? (c + 1) * CHUNK : end;
    for (int i = c * CHUNK; i < hi; i++) prepare(r, &fp->faces[i], fp->pedges + fp->faces[i].pe);
    atomic_store_explicit(&fp->chunk_gen[c], fp->gen, memory_order_release);
}

/* ---- merge (calling thread only): ew_emit_face's decisions, in order ---- */

static int add_prepared(ew_renderer *r, const pedge *p, int s) {
    if (!p->crosses) return -1;
    if (r->el.nedges >= r->el.max_edges) {
        r->stats.dropped++;
        return -1;
    }
    r->el.edges[r->el.nedges] = p->e;
    return ew_edge_link(&r->el, p->down, s);
}

static void merge_face(ew_renderer *r, const pface *pf, const pedge *pe) {
    const ew_world *w = r->world;
    const ew_face *f = &w->faces[pf->face];
    int n = f->numedges;
    if (r->el.nsurfs >= r->el.max_surfs || n > EW_MAX_POLY - 8 || r->el.nedges + n + 4 > r->el.max_edges) {
        r->stats.dropped++;
        return;
    }
    if (pf->m < 0) return;
    int s = r->el.nsurfs;
    float nearzi = 0;
    for (int k = 0; k < pf->m; k++) {
        const pedge *p = &pe[k];
        float zi = p->e.nearzi;
        if (p->se == PE_CLIP)
            add_prepared(r, p, s);
        else if (!ew_edge_cache_take(r, p->se, s, &zi))
            ew_edge_cache_note(r, p->se, add_prepared(r, p, s), p->down);
        if (zi > nearzi) nearzi = zi;
    }
    ew_surf_add_world(r, pf->face, pf->key, nearzi);
}

static void merge_chunk(ew_renderer *r, struct ew_front_par *fp, int c, int end) {
    int hi = (c + 1) * CHUNK < end ? (c + 1) * CHUNK : end;
    for (int i = c * CHUNK; i < hi; i++) merge_face(r, &fp->faces[i], fp->pedges + fp->faces[i].pe);
}

/* Merges every chunk prepared so far, in order, without waiting. */
static void merge_ready(ew_renderer *r, struct ew_front_par *fp, int end) {
    int nchunks = (end + CHUNK - 1) / CHUNK;
    while (fp->merged < nchunks &&
           atomic_load_explicit(&fp->chunk_gen[fp->merged], memory_order_acquire) == fp->gen)
        merge_chunk(r, fp, fp->merged++, end);
}

/* Chunk c, whose preparing thread is late (descheduled on a busy machine):
 * the calling thread prepares each face again in its own buffer and merges
 * it, leaving the other thread's copy alone (it is never read). */
static void merge_own(ew_renderer *r, struct ew_front_par *fp, int c, int end) {
    int hi = (c + 1) * CHUNK < end ? (c + 1) * CHUNK : end;
    for (int i = c * CHUNK; i < hi; i++) {
        const pface *q = &fp->faces[i];  /* face, clipflags, key: written by this thread */
        pface pf = {q->face, q->clipflags, q->key, 0, -1};
        prepare(r, &pf, fp->own);
        merge_face(r, &pf, fp->own);
    }
}

/* The walk is over (or the lists are full): publishes the last faces, then
 * merges every chunk in order, preparing unclaimed ones itself meanwhile;
 * a claimed chunk not ready after WAIT_MS it prepares again itself, so the
 * front end never waits a time slice for a thread the system put aside. */
#define WAIT_MS 0.02
static void finish(ew_renderer *r, struct ew_front_par *fp) {
    int end = fp->nfaces, nchunks = (end + CHUNK - 1) / CHUNK, take = 1, rounds = 0;
    double since = -1;
    atomic_store_explicit(&fp->published, end, memory_order_release);
    atomic_store_explicit(&fp->walk_done, 1, memory_order_release);
    while (fp->merged < nchunks) {
        int before = fp->merged;
        merge_ready(r, fp, end);
        if (fp->merged >= nchunks) break;
        if (take) {
            int k = atomic_fetch_add(&fp->next_chunk, 1);
            if (k < nchunks) {
                prepare_chunk(r, fp, k, end);
                continue;
            }
            take = 0;
        }
        if (fp->merged != before || since < 0) {
            since = ew_now_ms(), rounds = 0;
        } else if ((++rounds & 15) == 0 && ew_now_ms() - since > WAIT_MS) {
            merge_own(r, fp, fp->merged++, end);
            since = -1;
            continue;
        }
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
    }
}

/* The walk's face sink on the calling thread. */
static void collect(ew_renderer *r, int fi, int clipflags, int key) {
    struct ew_front_par *fp = r->fpar;
    if (fp->direct) {
        ew_emit_face(r, fi, clipflags, key);
        return;
    }
    int n = fp->nfaces, need = r->world->faces[fi].numedges + 4;
    if (n >= fp->cap_faces || need > fp->cap_pedges - fp->npe) {
        finish(r, fp);  /* everything listed so far, in order, then this face directly */
        fp->direct = 1;
        ew_emit_face(r, fi, clipflags, key);
        return;
    }
    pface *pf = &fp->faces[n];
    pf->face = fi, pf->clipflags = clipflags, pf->key = key, pf->pe = fp->npe, pf->m = -1;
    if (need <= EW_MAX_POLY - 4) fp->npe += need;  /* larger ones are dropped, and prepare writes none */
    fp->nfaces = ++n;
    if (n % CHUNK == 0) {
        atomic_store_explicit(&fp->published, n, memory_order_release);
        merge_ready(r, fp, n);
    }
}

static void worker(ew_renderer *r, struct ew_front_par *fp) {
    for (;;) {
        int c = atomic_fetch_add(&fp->next_chunk, 1), lo = c * CHUNK, end, rounds = 0;
        for (;;) {
            int done = atomic_load_explicit(&fp->walk_done, memory_order_acquire);
            int pub = atomic_load_explicit(&fp->published, memory_order_acquire);
            if (pub >= lo + CHUNK) {
                end = pub;
                break;
            }
            if (done) {
                if (pub <= lo) return;
                end = pub;
                break;
            }
            relax(&rounds);
        }
        prepare_chunk(r, fp, c, end);
    }
}

static void job_front(void *ctx, int thread) {
    ew_renderer *r = ctx;
    struct ew_front_par *fp = r->fpar;
    if (thread != 0) {
        if (thread <= HELPERS) worker(r, fp);
        int rounds = 0;
        while (!atomic_load_explicit(&fp->front_done, memory_order_acquire)) relax(&rounds);
    } else {
        ew_walk_world_to(r, collect);
        if (!fp->direct) finish(r, fp);
        fp->tail(fp->tail_arg);
        atomic_store_explicit(&fp->front_done, 1, memory_order_release);
    }
    fp->then(r, thread);
}

int ew_walk_world_parallel(ew_renderer *r, void (*tail)(void *arg), void *arg, void (*then)(void *ctx, int thread)) {
    if (r->sched.nthreads < 2 || !r->sched.pool || r->cfg.hsr->face != ew_emit_face) return -1;
    if (!r->fpar && !(r->fpar = front_par_new(r->world))) return -1;
    struct ew_front_par *fp = r->fpar;
    if (++fp->gen == INT_MAX) {
        int nchunks = fp->cap_faces / CHUNK + 2;
        for (int i = 0; i < nchunks; i++) atomic_store(&fp->chunk_gen[i], 0);
        fp->gen = 1;
    }
    fp->nfaces = fp->npe = fp->merged = fp->direct = 0;
    fp->tail = tail, fp->tail_arg = arg, fp->then = then;
    atomic_store(&fp->published, 0);
    atomic_store(&fp->walk_done, 0);
    atomic_store(&fp->next_chunk, 0);
    atomic_store(&fp->front_done, 0);
    ew_pool_run(r->sched.pool, job_front, r);
    return 0;
}
