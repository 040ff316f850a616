/* The front end on every thread of the pool, for the methods whose faces go
 * through ew_front_face (ew_front_out.edge_list: the edge list and those
 * that share its front end), making exactly the edge list the one-thread
 * walk makes: the second schedule of the one front end.
 *
 * The plan (once per world).  The nodes whose subtree is small are cut off
 * the top of the tree: each such subtree (a "root") is walked as one task,
 * and the nodes above them ("top" nodes) are walked by the calling thread.
 * Each face lies on one node and is marked only by leaves below that node,
 * so a subtree's faces are marked by its own leaves; faces on top nodes may
 * be marked by several subtrees.  An edge of the world lies on at most two
 * faces, in opposite directions.  A tree where any of this does not hold
 * (a malformed map) is walked as before.
 *
 * A frame, in one pool run (phases numbered as in job_front):
 *   - (calling thread) the brush entities in the frustum;
 *   1 (all) the PVS leaves and the nodes above them marked;
 *   - (calling thread) the top nodes walked front to back into a list of
 *     segments: a subtree to walk, or a top node's faces, in BSP order;
 *   2 (all) each subtree is walked with a key of its own from 0, listing
 *     its faces; a face on a top node marked by its leaves records the
 *     earliest segment that marked it;
 *   3 (all) a top node's faces are listed if a segment before it marked
 *     them (as in the one-thread walk, where only the leaves walked before
 *     a node's faces can have marked them);
 *   - (calling thread) keys, face positions and edge slots are laid out by
 *     prefix sums over the segments; the faces for the see-through pass
 *     are handed over, in order;
 *   4 (all) every face is clipped, projected and its edges set up, noting
 *     on each world edge which face lies on it; the leaves' keys are made
 *     global; the entities are tested against the frustum and the PVS;
 *   5 (all) for the edge method, the faces that nearer faces hide are
 *     found, each strip of the screen's coverage map (world/occlude.c)
 *     going through every face in BSP order;
 *   6 (all) every edge on a world edge is settled: of the two faces on it
 *     that are not hidden, the first in BSP order adds it and the second
 *     takes its free side (the edge cache of the one-thread emission);
 *     each face's surface and added edges are counted; the brush entities
 *     are split into the world's leaves and their fragments clipped,
 *     projected and set up;
 *   - (calling thread) surface and edge numbers by prefix sums over chunks
 *     of faces and over brush entities;
 *   7 (all) surfaces and edges written at their numbers;
 *   - (calling thread) the per-scanline lists of new edges linked in edge
 *     order, then tail(arg) (the bands placed);
 *   then(then_ctx, thread) on every thread: the scan.
 * The decisions are the one-thread emission's, by the same rules
 * (world/face.h: the clip, the budgets, the verdict on a face, adding an
 * edge; world/edge_math.h: the numbers), so the edge list, and every span and
 * pixel after it, are the same for any thread count.  If the edge list
 * would overflow, the prepared faces are merged one at a time as the
 * one-thread emission does, which is where its limits apply.
 *
 * A pool of one thread walks the tree in one loop (ew_walk_world), which
 * costs 10-20% less than the phases, unless ew_set_front_mode asks for the
 * phases (bench does, to measure the serial share of a many-thread frame).
 * Then the chunks of phase 4 run in order, so their faces go straight to
 * ew_front_face ("direct"): no staging, nothing for phases 6 and 7 but the
 * brush entities (and ew_front_face finds the hidden faces itself).  The
 * phases and their serial steps stay the same, so the serial share still
 * describes the run of many threads (which does the staging: a little
 * more work in all). */
#define _POSIX_C_SOURCE 200809L  /* sched_yield */
#include "ew_util.h"
#include "asset/scene.h"
#include "world/face.h"

#include <limits.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define CHUNK 8            /* faces a thread takes at a time in phases 3, 4, 6 and 7 */
#define PE_CLIP EW_FACE_CLIP_EDGE  /* a prepared edge the clip made (no world edge) */
#define M_DROPPED (-2)     /* a face with too many edges (counted as dropped) */
#define ENT_CHUNK 4        /* entities a thread tests at a time (a light trace each) */
#define PVS_CHUNK 64       /* PVS leaves a thread marks at a time */
#define NODE_CHUNK 8       /* top nodes whose faces a thread lists at a time */
#define NPHASES 8          /* phases 1..7 */

typedef struct pface {
    int   face, clipflags, key;
    int   pe;       /* its first prepared edge */
    int   m;        /* prepared edges; -1: clipped away; M_DROPPED */
    int   ls;       /* its surface among its chunk's faces that have one, -1 none */
    int   nemit;    /* edges it adds to the list */
    float nearzi;
} pface;

typedef struct pedge {
    ew_edge e;      /* u, u_step, v_first, v_last and nearzi (the larger 1/z of its ends) */
    int32_t se;     /* the signed world surfedge it lies on, or PE_CLIP */
    int32_t partner;/* the later face (position) taking its other side, -1 */
    int8_t  down;   /* its second end is lower on the screen */
    int8_t  crosses;/* it crosses a scanline centre */
    int8_t  emit;   /* this face adds it to the list */
    int8_t  skipped;/* not set up: the face on its other side, earlier, had it (prepare's may_skip) */
} pedge;

/* A face the walk listed, in its segment's range: key local to the
 * segment; pe its first edge slot from the segment's first. */
typedef struct lface { int face, clipflags, key, pe, kind; float alpha; } lface;

/* A brush entity's fragment: for the method (its edges prepared as
 * ew_front_poly makes them) or for the see-through pass (its vertices). */
typedef struct pfrag {
    int   face, key, kind;
    float alpha;
    const ew_view *view;
    int   m;        /* edges; -1 clipped away; M_DROPPED; see-through: its vertex count */
    int   pe;       /* its first edge (or vertex) in its arena */
    int   nemit;
    float nearzi;
} pfrag;

/* What one thread's brush entities made this frame. */
typedef struct arena {
    pfrag *frags;  int nfrags, cap_frags;
    pedge *edges;  int nedges, cap_edges;
    float (*verts)[3]; int nverts, cap_verts;
    int    failed;  /* out of memory: the brush entities go serially */
} arena;

/* One brush entity's result: where its fragments are, and its numbers. */
typedef struct bres {
    int arena, f0, nf, drawn, dropped, ns, ne, s0, e0;
} bres;

enum { SEG_TREE, SEG_NODE };
typedef struct seg {
    int   kind, n, clipflags, depth;  /* SEG_TREE: node (or leaf, < 0) n's subtree; SEG_NODE: node n's faces */
    int   side;
    float d;
    int   lf0, lfend, leaf0;          /* its range in lf, its first slot in leaves */
    /* filled by its walk: */
    int   nfaces, nsee, nleaves, nkeys, npe, visible_leaves, dropped;
    /* laid out after: */
    int   key0, face0, pe0;
} seg;

typedef struct phase {
    _Alignas(64) atomic_int next;
    _Alignas(64) atomic_int done;
    int n;
} phase;

struct ew_front_par {
    _Alignas(64) atomic_int stage;      /* the phase the calling thread has opened */
    _Alignas(64) atomic_int front_done; /* the tail has run: the edge list is complete */
    phase ph[NPHASES];
    int    time_items;                  /* the row profile: items timed (one thread) */
    int    direct;                      /* one thread: phase 4 hands the faces to ew_front_face in BSP order */
    double longest[NPHASES];            /* then per phase its largest item, ms */
    /* The plan. */
    int   top_n;                        /* a top node has more nodes than this below it */
    int   head_root;                    /* 1: the head node is itself a root (a small tree) */
    int  *node_root;                    /* per node: its root's number, -1 for a top node */
    int  *face_root;                    /* per face: its node's root number, -1 top node, -2 no world node */
    int  *node_lf0, *node_lfend;        /* per node: a root's (or top node's) range in lf */
    int  *node_leaf0;                   /* and its first slot in leaves (a top node: two, its leaf children's) */
    int (*edge_faces)[2];               /* per world edge: the faces on it, -1 */
    int   max_segs;
    /* Per frame. */
    seg  *segs;   int nsegs;
    int  *tree_segs; int ntree;         /* the SEG_TREE segments: phase 2's items */
    int  *node_segs; int nnode;         /* the SEG_NODE segments: phase 3's, NODE_CHUNK an item */
    lface *lf;
    int  *leaves;
    pface *faces; int nfaces;
    pedge *pedges; int cap_pedges;
    /* Faces that nearer faces hide (world/occlude.c), when the list leaves
     * them out: per prepared edge its first point, per face position its
     * tiles and whether some strip of the screen found it not hidden. */
    int   occ;                          /* this frame (never in direct mode: ew_front_face decides there) */
    ew_proj *pts;
    ew_occ_box *boxes;
    atomic_uchar *vis;
    int  *chunk_occluded;
    int  *chunk_seg, *chunk_ns, *chunk_ne, *chunk_cached, *chunk_dropped, *chunk_s0, *chunk_e0;
    int   nchunks;
    /* Per world edge, per face on it (edge_faces order): which prepared
     * edge of which face position lies on it this frame. */
    struct eside { _Atomic int frame; int pos, pe; } (*eside)[2];
    _Atomic uint64_t *topmark;          /* per face of a top node: frame << 32 | ~earliest segment that marked it */
    int   last_frame;
    /* Brush entities (phase 6 splits them, phase 7 writes them). */
    ew_brush_item *bitems; bres *bres; int nbitems, cap_bitems, bculled;
    int   nent_items;                   /* phase 4 also tests the entities, ENT_CHUNK at a time */
    arena arenas[EW_MAX_THREADS];
    void (*tail)(void *arg);
    void  *tail_arg;
    void (*then)(void *ctx, int thread);
    void  *then_ctx;
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
    free(fp->node_root), free(fp->face_root), free(fp->node_lf0), free(fp->node_lfend), free(fp->node_leaf0), free(fp->edge_faces);
    free(fp->segs), free(fp->tree_segs), free(fp->node_segs), free(fp->lf), free(fp->leaves), free(fp->faces), free(fp->pedges);
    free(fp->chunk_seg), free(fp->chunk_ns), free(fp->chunk_ne), free(fp->chunk_cached), free(fp->chunk_dropped);
    free(fp->chunk_s0), free(fp->chunk_e0), free((void *)fp->eside), free((void *)fp->topmark);
    free(fp->pts), free(fp->boxes), free((void *)fp->vis), free(fp->chunk_occluded);
    free(fp->bitems), free(fp->bres);
    for (int i = 0; i < EW_MAX_THREADS; i++) free(fp->arenas[i].frags), free(fp->arenas[i].edges), free(fp->arenas[i].verts);
    free(fp);
}

/* ---- the plan ---- */

typedef struct plan_ctx {
    const ew_world *w;
    struct ew_front_par *fp;
    int *size;       /* per node: nodes in its subtree */
    int *seen_leaf;  /* non-solid leaves reached */
    int  bad;
} plan_ctx;

/* Nodes below n (and n); marks the tree irregular if a node or non-solid
 * leaf is reached twice or the tree is deeper than the walk goes. */
static int count_nodes(plan_ctx *c, int n, int depth) {
    if (c->bad) return 0;
    if (depth > EW_MAX_WALK_DEPTH) return c->bad = 1, 0;
    if (n < 0) {
        int li = -1 - n;
        if (c->w->leaves[li].contents != EW_CONTENTS_SOLID && c->seen_leaf[li]++) c->bad = 1;
        return 0;
    }
    if (c->size[n]) return c->bad = 1, 0;
    c->size[n] = -1;  /* on the way */
    const ew_node *nd = &c->w->nodes[n];
    int s = 1 + count_nodes(c, nd->children[0], depth + 1) + count_nodes(c, nd->children[1], depth + 1);
    return c->size[n] = s;
}

/* Gives subtree n root number `root`; its faces and leaves ranges grow by
 * what it holds. */
static void own_subtree(plan_ctx *c, int n, int root, int *nlf, int *nleaves) {
    if (n < 0) {
        (*nleaves)++;
        return;
    }
    const ew_node *nd = &c->w->nodes[n];
    c->fp->node_root[n] = root;
    *nlf += nd->numfaces;
    own_subtree(c, nd->children[0], root, nlf, nleaves);
    own_subtree(c, nd->children[1], root, nlf, nleaves);
}

/* Cuts the tree below top node n (or n itself if it is small): roots get
 * their numbers and ranges, top nodes their faces' range. */
static void cut(plan_ctx *c, int n, int *nroots, int *nlf, int *nleaves) {
    struct ew_front_par *fp = c->fp;
    if (n < 0 || c->size[n] <= fp->top_n) return;
    const ew_node *nd = &c->w->nodes[n];
    fp->node_root[n] = -1;
    fp->node_lf0[n] = *nlf;
    *nlf += nd->numfaces;
    fp->node_lfend[n] = *nlf;
    for (int k = 0; k < 2; k++) {
        int ch = nd->children[k];
        if (ch >= 0 && c->size[ch] > fp->top_n) {
            cut(c, ch, nroots, nlf, nleaves);
        } else if (ch >= 0) {
            fp->node_lf0[ch] = *nlf, fp->node_leaf0[ch] = *nleaves;
            own_subtree(c, ch, (*nroots)++, nlf, nleaves);
            fp->node_lfend[ch] = *nlf;
        }
        /* A leaf child is walked as its own segment: its one leaf slot
         * is kept at the top node (node_leaf0), one per child. */
    }
    fp->node_leaf0[n] = *nleaves;
    *nleaves += 2;
}

static struct ew_front_par *front_par_new(const ew_world *w) {
    long cap_pe = (long)w->numsurfedges + 4L * w->numfaces + 8;
    if (cap_pe > INT_MAX / 2 || w->numnodes < 1) return NULL;
    struct ew_front_par *fp = aligned_alloc(64, (sizeof *fp + 63) / 64 * 64);
    if (!fp) return NULL;
    memset(fp, 0, sizeof *fp);
    int nn = w->numnodes, nf = w->numfaces, ne = w->numedges, nl = w->numleaves;
    fp->cap_pedges = (int)cap_pe;
    fp->node_root = malloc(sizeof(int) * (size_t)nn);
    fp->face_root = malloc(sizeof(int) * (size_t)(nf + 1));
    fp->node_lf0 = calloc((size_t)nn, sizeof(int));
    fp->node_lfend = calloc((size_t)nn, sizeof(int));
    fp->node_leaf0 = calloc((size_t)nn, sizeof(int));
    fp->edge_faces = malloc(sizeof *fp->edge_faces * (size_t)(ne + 1));
    plan_ctx c = {w, fp, calloc((size_t)nn, sizeof(int)), calloc((size_t)nl + 1, sizeof(int)), 0};
    int ok = fp->node_root && fp->face_root && fp->node_lf0 && fp->node_lfend && fp->node_leaf0 && fp->edge_faces && c.size && c.seen_leaf;
    int head = w->models[0].headnode;
    if (ok) {
        for (int i = 0; i < nn; i++) fp->node_root[i] = -2;  /* not in the world tree */
        count_nodes(&c, head, 0);
    }
    if (ok && !c.bad) {
        /* A top node has more than 1/128 of the world's nodes below it. */
        int total = head >= 0 ? c.size[head] : 0;
        fp->top_n = total / 128 > 64 ? total / 128 : 64;
        int nroots = 0, nlf = 0, nleaves = 0;
        if (head < 0 || c.size[head] <= fp->top_n) {
            fp->head_root = 1;
            if (head >= 0) own_subtree(&c, head, nroots++, &nlf, &nleaves), fp->node_lfend[head] = nlf;
            else nleaves = 1;
        } else {
            cut(&c, head, &nroots, &nlf, &nleaves);
        }
        /* Segments: at most one per top node and two per its children. */
        int ntop = 0;
        for (int i = 0; i < nn; i++) ntop += fp->node_root[i] == -1;
        fp->max_segs = 3 * ntop + 2;
        /* Faces: each on one node of the world tree; edges: at most two
         * faces, opposite ways. */
        for (int i = 0; i <= nf; i++) fp->face_root[i] = -2;
        for (int i = 0; i <= ne; i++) fp->edge_faces[i][0] = fp->edge_faces[i][1] = -1;
        for (int n = 0; n < nn && !c.bad; n++) {
            if (fp->node_root[n] == -2) continue;
            const ew_node *nd = &w->nodes[n];
            for (int i = 0; i < nd->numfaces && !c.bad; i++) {
                int fi = nd->firstface + i;
                if (fp->face_root[fi] != -2) {
                    c.bad = 1;
                    break;
                }
                fp->face_root[fi] = fp->node_root[n];
                const ew_face *f = &w->faces[fi];
                for (int k = 0; k < f->numedges; k++) {
                    int se = w->surfedges[f->firstedge + k], e = se >= 0 ? se : -se;
                    if (e >= ne) {
                        c.bad = 1;
                        break;
                    }
                    int *ef = fp->edge_faces[e];
                    if (ef[0] < 0) {
                        ef[0] = fi;
                    } else if (ef[1] < 0 && ef[0] != fi) {
                        const ew_face *g = &w->faces[ef[0]];
                        int gse = 0;
                        for (int q = 0; q < g->numedges; q++) {
                            int s2 = w->surfedges[g->firstedge + q];
                            if (s2 == e || s2 == -e) gse = s2;
                        }
                        if ((gse >= 0) == (se >= 0)) c.bad = 1;
                        ef[1] = fi;
                    } else {
                        c.bad = 1;
                    }
                }
            }
        }
        /* A leaf marks only faces of its own subtree or of top nodes. */
        for (int n = 0; n < nn && !c.bad; n++) {
            int root = fp->node_root[n];
            if (root == -2) continue;
            const ew_node *nd = &w->nodes[n];
            for (int k = 0; k < 2; k++) {
                int ch = nd->children[k];
                if (ch >= 0) continue;
                const ew_leaf *lf = &w->leaves[-1 - ch];
                for (int i = 0; i < lf->nummarks; i++) {
                    int o = fp->face_root[w->marksurfaces[lf->firstmark + i]];
                    if (o >= 0 && o != root) c.bad = 1;
                }
            }
        }
        fp->segs = malloc(sizeof(seg) * (size_t)fp->max_segs);
        fp->tree_segs = malloc(sizeof(int) * (size_t)fp->max_segs);
        fp->node_segs = malloc(sizeof(int) * (size_t)fp->max_segs);
        fp->lf = malloc(sizeof(lface) * (size_t)(nlf + 1));
        fp->leaves = malloc(sizeof(int) * (size_t)(nleaves + 1));
        fp->faces = malloc(sizeof(pface) * (size_t)(nf + 1));
        fp->pedges = malloc(sizeof(pedge) * (size_t)fp->cap_pedges);
        int nch = nf / CHUNK + 2;
        fp->chunk_seg = malloc(sizeof(int) * (size_t)nch);
        fp->chunk_ns = malloc(sizeof(int) * (size_t)nch);
        fp->chunk_ne = malloc(sizeof(int) * (size_t)nch);
        fp->chunk_cached = malloc(sizeof(int) * (size_t)nch);
        fp->chunk_dropped = malloc(sizeof(int) * (size_t)nch);
        fp->chunk_s0 = malloc(sizeof(int) * (size_t)nch);
        fp->chunk_e0 = malloc(sizeof(int) * (size_t)nch);
        fp->chunk_occluded = malloc(sizeof(int) * (size_t)nch);
        fp->pts = malloc(sizeof(ew_proj) * (size_t)fp->cap_pedges);
        fp->boxes = malloc(sizeof(ew_occ_box) * (size_t)(nf + 1));
        fp->vis = malloc((size_t)nf + 1);
        fp->eside = calloc((size_t)ne + 1, sizeof *fp->eside);
        fp->topmark = calloc((size_t)nf + 1, sizeof(uint64_t));
        ok = fp->segs && fp->tree_segs && fp->node_segs && fp->lf && fp->leaves && fp->faces && fp->pedges && fp->chunk_seg &&
             fp->chunk_ns && fp->chunk_ne && fp->chunk_cached && fp->chunk_dropped && fp->chunk_s0 &&
             fp->chunk_e0 && fp->eside && fp->topmark && fp->chunk_occluded && fp->pts && fp->boxes && fp->vis;
    }
    free(c.size), free(c.seen_leaf);
    if (!ok || c.bad) {
        ew_front_par_free(fp);
        return NULL;
    }
    return fp;
}

/* ---- before 2 (calling thread): the top nodes, front to back, into segments ---- */

static void add_seg(struct ew_front_par *fp, int kind, int n, int clipflags, int depth, int leaf0) {
    seg *s = &fp->segs[fp->nsegs];
    memset(s, 0, sizeof *s);
    s->kind = kind, s->n = n, s->clipflags = clipflags, s->depth = depth, s->leaf0 = leaf0;
    if (n >= 0) s->lf0 = fp->node_lf0[n], s->lfend = fp->node_lfend[n];
    if (kind == SEG_TREE) fp->tree_segs[fp->ntree++] = fp->nsegs;
    else fp->node_segs[fp->nnode++] = fp->nsegs;
    fp->nsegs++;
}

static void top_walk(ew_front *fr, struct ew_front_par *fp, int n, int clipflags, int depth) {
    const ew_world *w = fr->f->world;
    if (depth > EW_MAX_WALK_DEPTH) return;  /* cannot be: the plan measured the tree */
    ew_walker wk = {.fr = fr};
    float d;
    int side = ew_walk_enter(&wk, n, &clipflags, &d);
    if (side < 0) return;
    const ew_node *nd = &w->nodes[n];
    for (int k = 0; k < 2; k++) {
        int ch = nd->children[k == 0 ? side : !side];
        if (k == 1) {
            add_seg(fp, SEG_NODE, n, clipflags, depth, 0);
            fp->segs[fp->nsegs - 1].side = side, fp->segs[fp->nsegs - 1].d = d;
        }
        if (ch >= 0 && fp->node_root[ch] == -1) {
            top_walk(fr, fp, ch, clipflags, depth + 1);
        } else if (ch >= 0) {
            if (fr->marks->node_frame[ch] == fr->marks->framecount)
                add_seg(fp, SEG_TREE, ch, clipflags, depth + 1, fp->node_leaf0[ch]);
        } else {
            int li = -1 - ch;
            if (fr->marks->leaf_frame[li] == fr->marks->framecount && w->leaves[li].contents != EW_CONTENTS_SOLID)
                add_seg(fp, SEG_TREE, ch, clipflags, depth + 1, fp->node_leaf0[n] + (ch == nd->children[1]));
        }
    }
}

/* ---- 2: a subtree's walk ---- */

typedef struct task_walker {
    ew_walker wk;
    struct ew_front_par *fp;
    seg *s;
    int  segno;
} task_walker;

static void task_leaf(ew_walker *wk, int li) {
    task_walker *t = (task_walker *)wk;
    ew_front *fr = wk->fr;
    const ew_world *w = fr->f->world;
    const ew_leaf *leaf = &w->leaves[li];
    const int frame = fr->marks->framecount, *face_root = t->fp->face_root;
    /* The root number of this subtree: that of its first node (a leaf
     * segment has no node of its own and can only mark top faces). */
    int root = t->s->n >= 0 ? t->fp->node_root[t->s->n] : -3;
    t->fp->leaves[t->s->leaf0 + t->s->nleaves++] = li;
    uint64_t want = (uint64_t)frame << 32 | (uint32_t)~(uint32_t)t->segno;
    for (int i = 0; i < leaf->nummarks; i++) {
        int fi = w->marksurfaces[leaf->firstmark + i], o = face_root[fi];
        if (o == root) {
            fr->marks->face_frame[fi] = frame;
        } else if (o == -1) {
            _Atomic uint64_t *m = &t->fp->topmark[fi];
            uint64_t cur = atomic_load_explicit(m, memory_order_relaxed);
            if (t->fp->direct) {  /* one thread: no locked instruction */
                if (cur < want) atomic_store_explicit(m, want, memory_order_relaxed);
                continue;
            }
            while (cur < want && !atomic_compare_exchange_weak_explicit(m, &cur, want, memory_order_relaxed,
                                                                        memory_order_relaxed)) {
            }
        }
    }
}

/* Listed faces: those for the hidden-surface method from the front of the
 * segment's range, those for the see-through pass from its back. */
static void list_face(ew_walker *wk, int fi, int clipflags, int kind, float alpha) {
    task_walker *t = (task_walker *)wk;
    seg *s = t->s;
    const ew_face *f = &wk->fr->f->world->faces[fi];
    if (ew_see_to_hsr(wk->fr, kind)) {
        int need = f->numedges + 4;
        t->fp->lf[s->lf0 + s->nfaces++] = (lface){fi, clipflags, wk->key, s->npe, kind, alpha};
        if (need <= EW_MAX_POLY - 4) s->npe += need;  /* larger ones are dropped, and prepare writes none */
    } else {
        t->fp->lf[s->lfend - 1 - s->nsee++] = (lface){fi, clipflags, wk->key, 0, kind, alpha};
    }
}

static void walk_seg(ew_front *fr, struct ew_front_par *fp, int segno) {
    seg *s = &fp->segs[segno];
    task_walker t = {{.fr = fr, .leaf = task_leaf, .face = list_face}, fp, s, segno};
    ew_walk_node(&t.wk, s->n, s->clipflags, s->depth);
    s->nkeys = t.wk.key, s->visible_leaves = t.wk.visible_leaves, s->dropped = t.wk.dropped;
}

/* ---- 3: a top node's faces ---- */

/* A top node's faces marked by a segment before it (its own number).  The
 * segments touch only their own faces and their own ranges of lf. */
static void node_faces(ew_front *fr, struct ew_front_par *fp, int segno) {
    seg *s = &fp->segs[segno];
    const ew_node *nd = &fr->f->world->nodes[s->n];
    const int frame = fr->marks->framecount;
    for (int i = 0; i < nd->numfaces; i++) {
        int fi = nd->firstface + i;
        uint64_t v = atomic_load_explicit(&fp->topmark[fi], memory_order_relaxed);
        int marked = (int)(v >> 32) == frame && (int)~(uint32_t)v < segno;
        fr->marks->face_frame[fi] = marked ? frame : frame - 1;
    }
    task_walker t = {{.fr = fr, .leaf = task_leaf, .face = list_face}, fp, s, segno};
    ew_walk_faces(&t.wk, s->n, s->clipflags, s->side, s->d);
    s->nkeys = 1;
}

/* ---- between 3 and 4 (calling thread): the layout ---- */

static void layout(ew_front *fr, struct ew_front_par *fp) {
    int key = 0, nf = 0, npe = 0, c = 0;
    for (int j = 0; j < fp->nsegs; j++) {
        seg *s = &fp->segs[j];
        s->key0 = key, s->face0 = nf, s->pe0 = npe;
        for (; c * CHUNK < nf + s->nfaces; c++) fp->chunk_seg[c] = j;
        nf += s->nfaces, npe += s->npe;
        for (int i = 0; i < s->nsee; i++) {
            const lface *l = &fp->lf[s->lfend - 1 - i];
            ew_walk_see_add(fr, l->face, key + l->key, l->kind, l->alpha);
        }
        key += s->nkeys;
        fr->f->stats.visible_leaves += s->visible_leaves;
        fr->f->stats.dropped += s->dropped;
    }
    fp->nfaces = nf, fp->nchunks = c;
}

/* ---- 4: faces clipped, projected and their edges set up (any thread) ---- */

static void set_pedge(pedge *p, const ew_proj *a, const ew_proj *b, int32_t se) {
    p->se = se;
    p->down = b->v > a->v;
    p->crosses = (int8_t)ew_face_setup_edge(a, b, &p->e);
    p->e.nearzi = a->zi > b->zi ? a->zi : b->zi;  /* also where it crosses none: the face's 1/z counts it */
}

/* World edge se of the face at position p lies at prepared edge pe: noted
 * for the face on its other side.  1 if that face, earlier in BSP order,
 * has noted it already: then this face only takes the edge's free side,
 * and its own setup of it is never read. */
static int note_edge(const ew_front *fr, struct ew_front_par *fp, int face, int32_t se, int p, int pe) {
    int e = se >= 0 ? se : -se, side = fp->edge_faces[e][0] == face ? 0 : 1;
    const int frame = fr->marks->framecount;
    struct eside *mine = &fp->eside[e][side], *other = &fp->eside[e][!side];
    mine->pos = p, mine->pe = pe;
    atomic_store_explicit(&mine->frame, frame, memory_order_release);
    return atomic_load_explicit(&other->frame, memory_order_acquire) == frame && other->pos < p;
}

/* What ew_front_face computes of a face before it touches the list (the
 * rules of world/face.h); with may_skip, not the setup of edges the face
 * will take from another. */
static void prepare(const ew_front *fr, struct ew_front_par *fp, int p, int may_skip) {
    pface *pf = &fp->faces[p];
    pedge *out = fp->pedges + pf->pe;
    const ew_world *w = fr->f->world;
    const ew_face *f = &w->faces[pf->face];
    int n = f->numedges;
    pf->m = -1;
    if (ew_face_too_big(n)) {
        pf->m = M_DROPPED;
        return;
    }
    ew_proj pj[EW_MAX_POLY];
    uint8_t valid[EW_MAX_POLY];
    float cl[EW_MAX_POLY][3];
    int tout[EW_MAX_POLY];
    int m = ew_face_clip(&fr->f->view, w, f, pf->clipflags, cl, tout);
    if (m < 3) return;
    if (fp->occ) {
        /* Every point, for the coverage map (the cull phase), kept. */
        for (int i = 0; i < m; i++) {
            ew_project(&fr->f->view, ew_face_point(w, f, cl, pf->clipflags, i), &pj[i]);
            fp->pts[pf->pe + i] = pj[i];
        }
        memset(valid, 1, (size_t)m);
        fp->boxes[p] = ew_occ_box_of(&fr->occ, pj, m, fr->f->target.width, fr->f->target.height);
    } else {
        /* Vertices projected as the edges that are set up need them. */
        memset(valid, 0, (size_t)m);
    }
    for (int i = 0; i < m; i++) {
        int j = i + 1 == m ? 0 : i + 1;
        int32_t se = ew_face_world_edge(w, f, pf->clipflags, tout, i);
        out[i].skipped = 0;
        if (se != PE_CLIP && note_edge(fr, fp, pf->face, se, p, pf->pe + i) && may_skip) {
            out[i].se = se, out[i].crosses = 0, out[i].skipped = 1;
            continue;
        }
        if (!valid[i]) ew_project(&fr->f->view, ew_face_point(w, f, cl, pf->clipflags, i), &pj[i]), valid[i] = 1;
        if (!valid[j]) ew_project(&fr->f->view, ew_face_point(w, f, cl, pf->clipflags, j), &pj[j]), valid[j] = 1;
        set_pedge(&out[i], &pj[i], &pj[j], se);
    }
    pf->m = m;
}

static void prepare_chunk(ew_front *fr, struct ew_front_par *fp, int c) {
    int j = fp->chunk_seg[c], hi = (c + 1) * CHUNK < fp->nfaces ? (c + 1) * CHUNK : fp->nfaces;
    for (int p = c * CHUNK; p < hi; p++) {
        while (p >= fp->segs[j].face0 + fp->segs[j].nfaces) j++;
        const seg *s = &fp->segs[j];
        const lface *l = &fp->lf[s->lf0 + (p - s->face0)];
        if (fp->direct) {  /* straight to the list: nothing staged */
            ew_front_face(fr, l->face, l->clipflags, s->key0 + l->key);
            continue;
        }
        pface *pf = &fp->faces[p];
        pf->face = l->face, pf->clipflags = l->clipflags, pf->key = s->key0 + l->key, pf->pe = s->pe0 + l->pe;
        atomic_store_explicit(&fp->vis[p], 0, memory_order_relaxed);
        prepare(fr, fp, p, 1);
    }
}

/* A subtree's leaves get their keys in the frame's order. */
static void fix_leaf_keys(ew_front *fr, struct ew_front_par *fp, int segno) {
    const seg *s = &fp->segs[segno];
    for (int i = 0; i < s->nleaves; i++) fr->marks->leaf_key[fp->leaves[s->leaf0 + i]] += s->key0;
}

/* ---- 5: faces that nearer ones hide, strip by strip (any thread) ---- */

/* Every face in BSP order against strip i of the coverage map: a face not
 * hidden in some strip is kept.  Any number of strips decides as the
 * one-thread emission's one does (world/occlude.c). */
static void cull_strip(ew_front *fr, struct ew_front_par *fp, int i) {
    ew_occ_strip *st = &fr->occ.strips[i];
    for (int p = 0; p < fp->nfaces; p++) {
        const pface *pf = &fp->faces[p];
        if (pf->m < 3) continue;  /* clipped away or dropped: not in the map, as in ew_front_face */
        if (!ew_occ_face(&fr->occ, st, fp->pts + pf->pe, pf->m, fp->boxes[p], pf->key))
            atomic_store_explicit(&fp->vis[p], 1, memory_order_relaxed);
    }
}

/* Face position p was found hidden (and is left out). */
static inline int hidden_at(const struct ew_front_par *fp, int p) {
    return fp->occ && !atomic_load_explicit(&fp->vis[p], memory_order_relaxed);
}

/* ---- 6: the edges shared by two faces settled (any thread) ---- */

/* The edge cache's decisions: the first face (in BSP order) on a world
 * edge adds it, the second takes its free side and its 1/z, or nothing if
 * it crosses no scanline. */
static void resolve_chunk(ew_front *fr, struct ew_front_par *fp, int c) {
    const int frame = fr->marks->framecount;
    int hi = (c + 1) * CHUNK < fp->nfaces ? (c + 1) * CHUNK : fp->nfaces;
    int ns = 0, ne = 0, cached = 0, dropped = 0, occluded = 0;
    for (int p = c * CHUNK; p < hi; p++) {
        pface *pf = &fp->faces[p];
        pf->ls = -1, pf->nemit = 0;
        if (pf->m < 0) {
            dropped += pf->m == M_DROPPED;
            continue;
        }
        if (hidden_at(fp, p)) {
            occluded++;
            continue;
        }
        pf->ls = ns++;
        float nearzi = 0;
        int nemit = 0;
        for (int k = 0; k < pf->m; k++) {
            pedge *pe = &fp->pedges[pf->pe + k];
            pe->partner = -1;
            if (pe->se == PE_CLIP) {
                pe->emit = pe->crosses;
            } else {
                int e = pe->se >= 0 ? pe->se : -pe->se, side = fp->edge_faces[e][0] == pf->face ? 0 : 1;
                const struct eside *o = &fp->eside[e][!side];
                int q = atomic_load_explicit(&o->frame, memory_order_relaxed) == frame ? o->pos : -1;
                if (q >= 0 && hidden_at(fp, q)) {
                    /* The face on the other side is left out: this one adds
                     * the edge, as ew_front_face finds no cached one. */
                    q = -1;
                    if (pe->skipped) {
                        set_pedge(pe, &fp->pts[pf->pe + k], &fp->pts[pf->pe + (k + 1 == pf->m ? 0 : k + 1)], pe->se);
                        pe->skipped = 0;
                    }
                }
                if (q >= 0 && q < p) {  /* second: the earlier face's edge */
                    const pedge *gp = &fp->pedges[o->pe];
                    pe->emit = 0;
                    cached += gp->crosses;
                    float zi = gp->crosses ? gp->e.nearzi : 0;
                    if (zi > nearzi) nearzi = zi;
                    continue;
                }
                pe->emit = pe->crosses;
                if (q > p && pe->crosses) pe->partner = q;
            }
            nemit += pe->emit;
            if (pe->e.nearzi > nearzi) nearzi = pe->e.nearzi;
        }
        pf->nemit = nemit, pf->nearzi = nearzi;
        ne += nemit;
    }
    fp->chunk_ns[c] = ns, fp->chunk_ne[c] = ne, fp->chunk_cached[c] = cached, fp->chunk_dropped[c] = dropped;
    fp->chunk_occluded[c] = occluded;
}

/* ---- 5, also: brush entities split into fragments (any thread) ---- */

static int grow(void **p, int *cap, int need, size_t size) {
    if (need <= *cap) return 1;
    int c = *cap ? *cap : 64;
    while (c < need) c *= 2;
    void *q = realloc(*p, size * (size_t)c);
    if (!q) return 0;
    *p = q, *cap = c;
    return 1;
}

typedef struct frag_ctx {
    ew_front *fr;
    arena       *a;
} frag_ctx;

/* ew_front_poly's work on a fragment, or its vertices kept for the
 * see-through pass. */
static void frag_sink(void *ctx, float (*p)[3], int n, int face, const ew_view *v, int key, int kind, float alpha) {
    frag_ctx *fc = ctx;
    ew_front *fr = fc->fr;
    arena *a = fc->a;
    if (a->failed || !grow((void **)&a->frags, &a->cap_frags, a->nfrags + 1, sizeof(pfrag))) {
        a->failed = 1;
        return;
    }
    pfrag *fg = &a->frags[a->nfrags++];
    *fg = (pfrag){face, key, kind, alpha, v, -1, 0, 0, 0};
    if (!ew_see_to_hsr(fr, kind)) {
        if (!grow((void **)&a->verts, &a->cap_verts, a->nverts + n, sizeof *a->verts)) {
            a->failed = 1;
            return;
        }
        memcpy(a->verts + a->nverts, p, sizeof *a->verts * (size_t)n);
        fg->pe = a->nverts, fg->m = n;
        a->nverts += n;
        return;
    }
    if (n > EW_MAX_POLY - 8) {
        fg->m = M_DROPPED;
        return;
    }
    ew_proj pj[EW_MAX_POLY];
    float nearzi;
    int m = ew_poly_project(&fr->f->view, p, n, pj, &nearzi);
    if (m < 3) return;
    if (!grow((void **)&a->edges, &a->cap_edges, a->nedges + m, sizeof(pedge))) {
        a->failed = 1;
        return;
    }
    int nemit = 0;
    for (int i = 0; i < m; i++) {
        pedge *pe = &a->edges[a->nedges + i];
        set_pedge(pe, &pj[i], &pj[i + 1 == m ? 0 : i + 1], PE_CLIP);
        pe->emit = pe->crosses, pe->partner = -1;
        nemit += pe->crosses;
    }
    fg->m = m, fg->pe = a->nedges, fg->nemit = nemit, fg->nearzi = nearzi;
    a->nedges += m;
}

static void split_brush(ew_front *fr, struct ew_front_par *fp, int i, int thread) {
    bres *b = &fp->bres[i];
    arena *a = &fp->arenas[thread];
    frag_ctx fc = {fr, a};
    b->arena = thread, b->f0 = a->nfrags;
    b->drawn = ew_brush_split(fr, &fp->bitems[i], frag_sink, &fc, &b->dropped);
    b->nf = a->nfrags - b->f0;
    b->ns = b->ne = 0;
    for (int k = b->f0; k < a->nfrags; k++) {
        const pfrag *fg = &a->frags[k];
        if (!ew_see_to_hsr(fr, fg->kind)) continue;
        b->dropped += fg->m == M_DROPPED;
        if (fg->m >= 0) b->ns++, b->ne += fg->nemit;
    }
}

/* ---- between 5 and 6 (calling thread): numbers, or the serial merge ---- */

/* The chunks whose faces wait in fp->faces for phases 6 and 7: none when
 * phase 4 handed them to the list itself. */
static int staged_chunks(const struct ew_front_par *fp) { return fp->direct ? 0 : fp->nchunks; }

/* ew_front_face's decisions (world/face.h) one face at a time, with its
 * limits, on the prepared face. */
static void merge_face(ew_front *fr, const pface *pf, const pedge *pe, int hidden) {
    int n = fr->f->world->faces[pf->face].numedges;
    int verdict = ew_face_verdict(ew_face_too_big(n), ew_face_list_full(fr->el, n), pf->m < 0 ? 0 : pf->m, hidden);
    if (!ew_face_counted(&fr->f->stats, verdict)) return;
    int s = fr->el->nsurfs;
    float nearzi = 0;
    for (int k = 0; k < pf->m; k++) {
        const pedge *p = &pe[k];
        float zi = p->e.nearzi;
        if (p->se == PE_CLIP || !ew_edge_cache_take(fr, p->se, s, &zi))
            ew_face_add_edge(fr, p->se, &p->e, p->crosses, p->down, s);
        if (zi > nearzi) nearzi = zi;
    }
    ew_surf_add_world(fr, pf->face, pf->key, nearzi);
}

/* Returns 1 if the faces and fragments fit the lists (phase 7 writes
 * them), else merges them here one at a time, as the serial front end
 * does, and returns 0. */
static int number(ew_front *fr, struct ew_front_par *fp) {
    int s = fr->el->nsurfs, e = fr->el->nedges, failed = 0;
    long cached = 0, dropped = 0, occluded = 0;
    for (int c = 0; c < staged_chunks(fp); c++) {
        fp->chunk_s0[c] = s, fp->chunk_e0[c] = e;
        s += fp->chunk_ns[c], e += fp->chunk_ne[c];
        cached += fp->chunk_cached[c], dropped += fp->chunk_dropped[c], occluded += fp->chunk_occluded[c];
    }
    for (int i = 0; i < fp->nbitems; i++) {
        bres *b = &fp->bres[i];
        b->s0 = s, b->e0 = e;
        s += b->ns, e += b->ne;
    }
    for (int t = 0; t < EW_MAX_THREADS; t++) failed |= fp->arenas[t].failed;
    /* No face would meet ew_front_face's limits, nor a fragment
     * ew_front_poly's: the same list. */
    if (!failed && s <= fr->el->max_surfs && (long)e + EW_MAX_POLY <= fr->el->max_edges) {
        fr->f->stats.edges_cached += cached;
        fr->f->stats.dropped += dropped;
        fr->f->stats.faces_occluded += (int)occluded;
        fr->f->stats.entities_culled += fp->bculled;
        for (int i = 0; i < fp->nbitems; i++) {
            const bres *b = &fp->bres[i];
            const arena *a = &fp->arenas[b->arena];
            fr->f->stats.dropped += b->dropped;
            if (b->drawn) fr->f->stats.entities_drawn++;
            else fr->f->stats.entities_culled++;
            for (int k = b->f0; k < b->f0 + b->nf; k++) {
                const pfrag *fg = &a->frags[k];
                if (!ew_see_to_hsr(fr, fg->kind))
                    fr->out.see(fr->out.ctx, a->verts + fg->pe, fg->m, fg->face, fg->view, fg->key, fg->kind, fg->alpha);
            }
        }
        return 1;
    }
    for (int p = 0; !fp->direct && p < fp->nfaces; p++) {  /* direct: the faces are in the list */
        prepare(fr, fp, p, 0);  /* every edge set up: an earlier face may be dropped here */
        merge_face(fr, &fp->faces[p], fp->pedges + fp->faces[p].pe, hidden_at(fp, p));
    }
    ew_walk_brush_models(fr);
    return 0;
}

/* ---- 6: surfaces and edges written at their numbers (any thread) ---- */

static void write_chunk(ew_front *fr, struct ew_front_par *fp, int c) {
    int hi = (c + 1) * CHUNK < fp->nfaces ? (c + 1) * CHUNK : fp->nfaces;
    int idx = fp->chunk_e0[c];
    for (int p = c * CHUNK; p < hi; p++) {
        const pface *pf = &fp->faces[p];
        if (pf->ls < 0) continue;
        int s = fp->chunk_s0[c] + pf->ls;
        for (int k = 0; k < pf->m; k++) {
            const pedge *pe = &fp->pedges[pf->pe + k];
            if (!pe->emit) continue;
            int other = 0, q = pe->partner;
            if (q >= 0) other = fp->chunk_s0[q / CHUNK] + fp->faces[q].ls;
            ew_edge *ed = &fr->el->edges[idx++];
            *ed = pe->e;
            ed->surfs[0] = (uint16_t)(pe->down ? s : other);
            ed->surfs[1] = (uint16_t)(pe->down ? other : s);
        }
        ew_surf_set_world(fr->f, &fr->el->surfs[s], pf->face, pf->key, pf->nearzi);
    }
}

static void write_brush(ew_front *fr, struct ew_front_par *fp, int i) {
    const bres *b = &fp->bres[i];
    const arena *a = &fp->arenas[b->arena];
    int s = b->s0, idx = b->e0;
    for (int k = b->f0; k < b->f0 + b->nf; k++) {
        const pfrag *fg = &a->frags[k];
        if (!ew_see_to_hsr(fr, fg->kind) || fg->m < 0) continue;
        for (int j = 0; j < fg->m; j++) {
            const pedge *pe = &a->edges[fg->pe + j];
            if (!pe->emit) continue;
            ew_edge *ed = &fr->el->edges[idx++];
            *ed = pe->e;
            ed->surfs[0] = (uint16_t)(pe->down ? s : 0);
            ed->surfs[1] = (uint16_t)(pe->down ? 0 : s);
        }
        ew_surf_set_fragment(fr->f->world, &fr->el->surfs[s++], fg->face, fg->key, fg->nearzi, fg->view);
    }
}

/* ---- the pool run ---- */

/* Item i of phase k.  The items likely to be largest come first, so that
 * no thread starts one when the others are nearly done: the entity tests
 * (a light trace each) in phase 4, the brush entities in phase 6. */
static void do_item(ew_front *fr, struct ew_front_par *fp, int k, int i, int thread) {
    switch (k) {
    case 1: {
        int from = i * PVS_CHUNK, to = from + PVS_CHUNK < fr->marks->nvis ? from + PVS_CHUNK : fr->marks->nvis;
        ew_pvs_apply(fr, from, to);
        break;
    }
    case 2: walk_seg(fr, fp, fp->tree_segs[i]); break;
    case 3:
        for (int q = i * NODE_CHUNK; q < fp->nnode && q < (i + 1) * NODE_CHUNK; q++) node_faces(fr, fp, fp->node_segs[q]);
        break;
    case 4:
        if (i < fp->nent_items) {
            int e0 = i * ENT_CHUNK, n = fr->scene->nents;
            ew_test_entities(fr, e0, e0 + ENT_CHUNK < n ? e0 + ENT_CHUNK : n);
        } else if ((i -= fp->nent_items) < fp->nchunks) {
            prepare_chunk(fr, fp, i);
        } else if (fp->segs[i - fp->nchunks].kind == SEG_TREE) {
            fix_leaf_keys(fr, fp, i - fp->nchunks);
        }
        break;
    case 5: cull_strip(fr, fp, i); break;
    case 6:
        if (i < fp->nbitems) split_brush(fr, fp, i, thread);
        else resolve_chunk(fr, fp, i - fp->nbitems);  /* not in direct mode: no such items */
        break;
    case 7:
        if (i < staged_chunks(fp)) write_chunk(fr, fp, i);
        else write_brush(fr, fp, i - staged_chunks(fp));
        break;
    }
}

static void run_items(ew_front *fr, struct ew_front_par *fp, int k, int thread) {
    phase *ph = &fp->ph[k];
    if (fp->direct && !fp->time_items) {  /* one thread: the items in order, no locked instructions */
        for (int i = 0; i < ph->n; i++) do_item(fr, fp, k, i, thread);
        atomic_store_explicit(&ph->done, ph->n, memory_order_relaxed);
        return;
    }
    for (int i; (i = atomic_fetch_add_explicit(&ph->next, 1, memory_order_relaxed)) < ph->n;) {
        /* The row profile (one thread) times each item: the largest of a
         * phase bounds it on any number of threads. */
        double t0 = fp->time_items ? ew_now_ms() : 0;
        do_item(fr, fp, k, i, thread);
        if (fp->time_items) {
            double ms = ew_now_ms() - t0;
            if (ms > fp->longest[k]) fp->longest[k] = ms;
        }
        atomic_fetch_add_explicit(&ph->done, 1, memory_order_release);
    }
}

static void open_phase(struct ew_front_par *fp, int k, int n) {
    phase *ph = &fp->ph[k];
    ph->n = n;
    atomic_store_explicit(&ph->next, 0, memory_order_relaxed);
    atomic_store_explicit(&ph->done, 0, memory_order_relaxed);
    atomic_store_explicit(&fp->stage, k, memory_order_release);
}

static void wait_done(struct ew_front_par *fp, int k) {
    int rounds = 0;
    while (atomic_load_explicit(&fp->ph[k].done, memory_order_acquire) < fp->ph[k].n) relax(&rounds);
}

/* The calling thread's side of phase k: opened with n items, its share
 * taken, then every item waited for. */
static void run_phase(ew_front *fr, struct ew_front_par *fp, int k, int n) {
    open_phase(fp, k, n);
    run_items(fr, fp, k, 0);
    wait_done(fp, k);
}

typedef struct front_run {
    ew_front *fr;
    double    serial_ms[2];
} front_run;

static void job_front(void *ctx, int thread) {
    front_run *run = ctx;
    ew_front *fr = run->fr;
    struct ew_front_par *fp = fr->par;
    if (thread != 0) {
        for (int k = 1; k < NPHASES; k++) {
            int rounds = 0;
            while (atomic_load_explicit(&fp->stage, memory_order_acquire) < k) relax(&rounds);
            run_items(fr, fp, k, thread);
        }
        int rounds = 0;
        while (!atomic_load_explicit(&fp->front_done, memory_order_acquire)) relax(&rounds);
        fp->then(fp->then_ctx, thread);
        return;
    }
    double t = ew_now_ms(), ser = 0;
    fp->nbitems = fp->bculled = fp->nent_items = 0;
    if (fr->scene) {
        fp->nbitems = ew_brush_items(fr, fp->bitems, &fp->bculled);
        if (fr->ent_frame) fp->nent_items = (fr->scene->nents + ENT_CHUNK - 1) / ENT_CHUNK;  /* room for their answers */
    }
    for (int i = 0; i < fr->nthreads && i < EW_MAX_THREADS; i++)
        fp->arenas[i].nfrags = fp->arenas[i].nedges = fp->arenas[i].nverts = fp->arenas[i].failed = 0;
    run->serial_ms[1] = ew_now_ms() - t;
    run_phase(fr, fp, 1, (fr->marks->nvis + PVS_CHUNK - 1) / PVS_CHUNK);
    fr->marks->vis_pending = 0;
    t = ew_now_ms();
    fp->nsegs = fp->ntree = fp->nnode = 0;
    int head = fr->f->world->models[0].headnode;
    if (fp->head_root) add_seg(fp, SEG_TREE, head, 15, 0, 0);
    else top_walk(fr, fp, head, 15, 0);
    ser += ew_now_ms() - t;
    run_phase(fr, fp, 2, fp->ntree);
    run_phase(fr, fp, 3, (fp->nnode + NODE_CHUNK - 1) / NODE_CHUNK);
    t = ew_now_ms();
    layout(fr, fp);
    ser += ew_now_ms() - t;
    run_phase(fr, fp, 4, fp->nchunks + fp->nsegs + fp->nent_items);
    if (fp->nent_items) fr->tested_frame = fr->marks->framecount;
    run_phase(fr, fp, 5, fp->occ ? fr->occ.nstrips : 0);
    run_phase(fr, fp, 6, staged_chunks(fp) + fp->nbitems);
    t = ew_now_ms();
    int fits = number(fr, fp);
    ser += ew_now_ms() - t;
    run_phase(fr, fp, 7, fits ? staged_chunks(fp) + fp->nbitems : 0);
    t = ew_now_ms();
    if (fits) {
        if (fp->nbitems > 0) {
            const bres *b = &fp->bres[fp->nbitems - 1];
            fr->el->nsurfs = b->s0 + b->ns, fr->el->nedges = b->e0 + b->ne;
        } else if (staged_chunks(fp) > 0) {
            int last = staged_chunks(fp) - 1;
            fr->el->nsurfs = fp->chunk_s0[last] + fp->chunk_ns[last];
            fr->el->nedges = fp->chunk_e0[last] + fp->chunk_ne[last];
        }
    }
    ser += ew_now_ms() - t;
    run->serial_ms[0] = ser;
    fp->tail(fp->tail_arg);
    atomic_store_explicit(&fp->front_done, 1, memory_order_release);
    fp->then(fp->then_ctx, thread);
}

int ew_walk_world_parallel(ew_front *fr, int phases, void (*tail)(void *arg), void *arg,
                           void (*then)(void *ctx, int thread), void *then_ctx, double serial_ms[2]) {
    /* One or two threads walk the tree in one loop unless the phases are
     * asked for (ew_set_front_mode). */
    if (ew_front_walks_alone(fr->nthreads, phases) || !fr->out.edge_list || fr->par_bad) return -1;
    if (!fr->par && !(fr->par = front_par_new(fr->f->world))) {
        fr->par_bad = 1;  /* an irregular tree (or no memory): the serial front end from now on */
        return -1;
    }
    struct ew_front_par *fp = fr->par;
    if (fp->cap_bitems < fr->max_ent_views + 1) {
        int cap = fr->max_ent_views + 1;
        ew_brush_item *bi = realloc(fp->bitems, sizeof *bi * (size_t)cap);
        if (bi) fp->bitems = bi;
        bres *br = realloc(fp->bres, sizeof *br * (size_t)cap);
        if (br) fp->bres = br;
        if (!bi || !br) return -1;
        fp->cap_bitems = cap;
    }
    const int frame = fr->marks->framecount;
    if (frame < fp->last_frame) {  /* the frame number wrapped: forget the old marks */
        for (int i = 0; i <= fr->f->world->numedges; i++)
            for (int k = 0; k < 2; k++) atomic_store_explicit(&fp->eside[i][k].frame, 0, memory_order_relaxed);
        for (int i = 0; i <= fr->f->world->numfaces; i++) atomic_store_explicit(&fp->topmark[i], 0, memory_order_relaxed);
    }
    fp->last_frame = frame;
    fp->tail = tail, fp->tail_arg = arg, fp->then = then, fp->then_ctx = then_ctx;
    atomic_store(&fp->stage, 0);
    atomic_store(&fp->front_done, 0);
    fp->time_items = fr->profile_rows && fr->nthreads == 1;
    /* One thread takes the chunks in order: the faces can go straight to
     * the list, as the serial walk hands them, with no staging. */
    fp->direct = fr->nthreads == 1;
    /* Hidden faces: decided inline by ew_front_face in direct mode, else
     * in phase 5 on strips of the map, two a thread. */
    fp->occ = fr->occ.on && !fp->direct;
    if (fp->occ && ew_occ_strips(&fr->occ, 2 * fr->nthreads) < 0) return -1;
    memset(fp->longest, 0, sizeof fp->longest);
    front_run run = {fr, {0, 0}};
    ew_pool_run(fr->pool, job_front, &run);
    serial_ms[0] = run.serial_ms[0], serial_ms[1] = run.serial_ms[1];
    fr->ms_front_items = 0;
    for (int k = 1; k < NPHASES; k++) fr->ms_front_items += fp->longest[k];
    return 0;
}
