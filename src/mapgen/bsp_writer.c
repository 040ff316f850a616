/*
 * Map generator: from a cell grid to a BSP29 image.
 *
 * 1. The tree: a box region of cells is split at a grid plane until it holds
 *    one kind of cell; each leaf is then an exact box (convex by
 *    construction).  The split plane is the one that lies on the most
 *    content changes while cutting the fewest open cells, which peels walls
 *    off first and keeps rooms in few leaves.
 * 2. Faces: each boundary quad between an open cell (empty or water) and a
 *    cell of another kind gets a face looking into the open cell.  The node
 *    that separates the two cells splits on exactly that grid plane, so the
 *    face is stored there.  Quads with the same node, leaf and texture are
 *    merged into rectangles (at most 240 units a side).
 * 3. T-junctions: every face corner lying inside another face's edge is
 *    inserted into that edge, so neighbouring faces share vertices and edge
 *    records exactly (one uses +e, the other -e).
 * 4. Submodels (doors): each box of the scene becomes model *1, *2, ...
 *    with faces of its own and a small BSP of its own: a chain of six
 *    nodes on the box's planes, each holding the face on its plane, with
 *    an empty leaf outside every side and the solid leaf inside.  Their
 *    edges are shared only among the box's faces (the renderer clips them
 *    into the world's leaves; they never join the world's polygons).
 * 5. Light maps, PVS, and the lumps in file order.
 */
#include "mapgen_internal.h"
#include "ew_util.h"
#include "ew_world.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FACE_CELLS (240 / BI_CELL)
#define MAX_GRID 250  /* cells per axis: int16 bounds and the scratch arrays */

typedef struct bnode {
    int lo[3], hi[3];  /* region in cells, half-open */
    int leaf, kind;    /* leaf: one kind of cell */
    int axis, pos;     /* node: plane at cell coordinate pos along axis */
    int child[2];      /* [0] front (cells >= pos), [1] back */
    int out;           /* file node number, or file leaf number (0 = solid) */
} bnode;

typedef struct bface {
    int axis, pos, facing;  /* facing 0..5 = +x -x +y -y +z -z */
    int u0, u1, v0, v1;     /* rectangle in cells along (axis+1)%3, (axis+2)%3 */
    int tex, leaf, node;    /* leaf and node are tree indices */
    int texinfo;
    int firstvert, numverts;
    int out;
} bface;

/* One texinfo: world-aligned axes for faces on planes along axis, shifted
 * by (soff, toff) texels. */
typedef struct texinfo_def {
    int tex, axis, soff, toff;
} texinfo_def;

/* A face rectangle in world units: on the plane coordinate[axis] = pos,
 * spanning [u0,u1] x [v0,v1] along (axis+1)%3 and (axis+2)%3; facing as
 * in bface. */
typedef struct frect {
    int axis, pos, facing, u0, u1, v0, v1;
} frect;

/* A face of a submodel: the box side on node 6 * box + side. */
typedef struct sface {
    frect r;
    int   tex, texinfo, plane;
    int   firstedge;  /* into surfedges; always 4 edges */
} sface;

/* Open-addressing map from a 64-bit key to an int (values >= 0). */
typedef struct imap {
    uint64_t *keys;
    int      *vals;
    size_t    cap, count;
} imap;

typedef struct ctx {
    const bi_scene *s;
    const bi_grid  *g;
    int             oom;
    bnode *nodes;   int nnodes, capnodes, root;
    bface *faces;   int nfaces, capfaces;
    int    diff[3][MAX_GRID + 1], same[3][MAX_GRID + 1];
    int    numnodes_out, numleaves_out;
    int   *node_of_out, *leaf_of_out;  /* file index -> tree index */
    /* output geometry */
    int   *polys;   int npolys, cappolys;       /* vertex indices of every face */
    int  (*verts)[3]; int nverts, capverts;
    imap   vmap;
    int   (*edges)[3]; int nedges, capedges;    /* v0, v1, shared-with-reverse */
    imap   emap;                                /* directed (v0,v1) -> newest edge for it */
    int   *surfedges; int nsurfedges, capsurfedges;
    int    planes[3][MAX_GRID + 1];             /* plane number of (axis, pos), -1 */
    int    nplanes;
    texinfo_def *texinfo; int ntexinfo, captexinfo;
    sface  sfaces[BI_MAX_SUBMODELS * 6]; int nsfaces;
    int  (*extra_planes)[2];                    /* planes off the grid: axis, dist */
    int    nextra_planes, capextra;
    int    hull_head[2];                        /* clipnode heads of hulls 1 and 2 */
} ctx;

/* All lump payloads, written one after another into the image. */
typedef struct lumps {
    bi_buf l[EW_NUM_LUMPS];
    /* with options (bi_scene.opt): coloured light and the BSPX per-face lumps */
    bi_buf rgb, shift, ofs, style, dec;
} lumps;

/* Grows *p (element size sz) to hold at least n elements. */
static int grow(ctx *c, void **p, int *cap, int n, size_t sz) {
    if (n <= *cap) return 0;
    int nc = *cap ? *cap : 64;
    while (nc < n) nc *= 2;
    void *q = realloc(*p, (size_t)nc * sz);
    if (!q) { c->oom = 1; return -1; }
    *p = q, *cap = nc;
    return 0;
}
#define GROW(c, arr, cnt, capv, extra) grow((c), (void **)&(arr), &(capv), (cnt) + (extra), sizeof *(arr))

/* ---- imap ----------------------------------------------------------------- */

static uint64_t mix64(uint64_t k) {
    k ^= k >> 33; k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33; k *= 0xc4ceb9fe1a85ec53ULL;
    return k ^ (k >> 33);
}
static int imap_grow(imap *m) {
    size_t nc = m->cap ? m->cap * 2 : 1024;
    uint64_t *nk = malloc(nc * sizeof *nk);
    int *nv = malloc(nc * sizeof *nv);
    if (!nk || !nv) { free(nk), free(nv); return -1; }
    for (size_t i = 0; i < nc; i++) nv[i] = -1;
    for (size_t i = 0; i < m->cap; i++) {
        if (m->vals[i] < 0) continue;
        size_t h = mix64(m->keys[i]) & (nc - 1);
        while (nv[h] >= 0) h = (h + 1) & (nc - 1);
        nk[h] = m->keys[i], nv[h] = m->vals[i];
    }
    free(m->keys), free(m->vals);
    m->keys = nk, m->vals = nv, m->cap = nc;
    return 0;
}
/* Slot of key: vals[slot] < 0 if absent.  Returns (size_t)-1 on OOM. */
static size_t imap_slot(imap *m, uint64_t key) {
    if ((m->count + 1) * 2 > m->cap && imap_grow(m)) return (size_t)-1;
    size_t h = mix64(key) & (m->cap - 1);
    while (m->vals[h] >= 0 && m->keys[h] != key) h = (h + 1) & (m->cap - 1);
    return h;
}
static void imap_free(imap *m) { free(m->keys), free(m->vals); }

/* ---- the tree --------------------------------------------------------------- */

static int is_open(int kind) { return kind == BI_EMPTY || kind == BI_WATER; }

static int build(ctx *c, const int lo[3], const int hi[3]) {
    if (GROW(c, c->nodes, c->nnodes, c->capnodes, 1)) return -1;
    int idx = c->nnodes++;
    bnode *nd = &c->nodes[idx];
    memset(nd, 0, sizeof *nd);
    memcpy(nd->lo, lo, sizeof nd->lo);
    memcpy(nd->hi, hi, sizeof nd->hi);

    const bi_grid *g = c->g;
    for (int a = 0; a < 3; a++)
        for (int p = lo[a]; p <= hi[a]; p++) c->diff[a][p] = c->same[a][p] = 0;
    unsigned seen = 0;
    for (int z = lo[2]; z < hi[2]; z++)
        for (int y = lo[1]; y < hi[1]; y++)
            for (int x = lo[0]; x < hi[0]; x++) {
                int k = bi_kind(g, x, y, z);
                seen |= 1u << k;
                const int q[3] = {x, y, z};
                for (int a = 0; a < 3; a++) {
                    if (q[a] == lo[a]) continue;
                    int k2 = bi_kind(g, x - (a == 0), y - (a == 1), z - (a == 2));
                    if (k != k2) c->diff[a][q[a]]++;
                    else if (is_open(k)) c->same[a][q[a]]++;
                }
            }
    if ((seen & (seen - 1)) == 0) {
        nd->leaf = 1;
        for (int k = 0; k < BI_NUM_KINDS; k++)
            if (seen == 1u << k) nd->kind = k;
        return idx;
    }
    /* Best plane: on many content changes, through few open cells;
     * ties go to the more balanced split. */
    long best = LONG_MIN;
    int ba = 0, bp = 0;
    for (int a = 0; a < 3; a++)
        for (int p = lo[a] + 1; p < hi[a]; p++) {
            int m = p - lo[a] < hi[a] - p ? p - lo[a] : hi[a] - p;
            long sc = (long)(c->diff[a][p] - c->same[a][p]) * 1024 + m * 512L / (hi[a] - lo[a]);
            if (sc > best) best = sc, ba = a, bp = p;
        }
    int flo[3], fhi[3], blo[3], bhi[3];
    memcpy(flo, lo, sizeof flo), memcpy(fhi, hi, sizeof fhi);
    memcpy(blo, lo, sizeof blo), memcpy(bhi, hi, sizeof bhi);
    flo[ba] = bp, bhi[ba] = bp;
    int front = build(c, flo, fhi);
    if (front < 0) return -1;
    int back = build(c, blo, bhi);
    if (back < 0) return -1;
    nd = &c->nodes[idx];  /* the array may have moved */
    nd->axis = ba, nd->pos = bp;
    nd->child[0] = front, nd->child[1] = back;
    return idx;
}

/* Leaf holding a cell. */
static int find_leaf(const ctx *c, const int cell[3]) {
    int n = c->root;
    while (!c->nodes[n].leaf) {
        const bnode *nd = &c->nodes[n];
        n = nd->child[cell[nd->axis] >= nd->pos ? 0 : 1];
    }
    return n;
}
/* The node whose plane separates two cells (-1 if they share a leaf). */
static int find_split(const ctx *c, const int a[3], const int b[3]) {
    int n = c->root;
    while (!c->nodes[n].leaf) {
        const bnode *nd = &c->nodes[n];
        int sa = a[nd->axis] >= nd->pos ? 0 : 1, sb = b[nd->axis] >= nd->pos ? 0 : 1;
        if (sa != sb) return n;
        n = nd->child[sa];
    }
    return -1;
}

static void number_tree(ctx *c, int n) {
    bnode *nd = &c->nodes[n];
    if (nd->leaf) {
        if (nd->kind == BI_SOLID) nd->out = 0;
        else c->leaf_of_out[nd->out = c->numleaves_out++] = n;
        return;
    }
    c->node_of_out[nd->out = c->numnodes_out++] = n;
    number_tree(c, nd->child[0]);
    number_tree(c, nd->child[1]);
}

/* ---- faces ---------------------------------------------------------------- */

typedef struct slot {
    int tex, leaf, node, used;
} slot;

static int emit_face(ctx *c, int axis, int pos, int facing, int u0, int u1, int v0, int v1,
                     const slot *s) {
    if (GROW(c, c->faces, c->nfaces, c->capfaces, 1)) return -1;
    bface *f = &c->faces[c->nfaces++];
    memset(f, 0, sizeof *f);
    f->axis = axis, f->pos = pos, f->facing = facing;
    f->u0 = u0, f->u1 = u1, f->v0 = v0, f->v1 = v1;
    f->tex = s->tex, f->leaf = s->leaf, f->node = s->node;
    return 0;
}

static int make_faces(ctx *c, ew_error *err) {
    const bi_grid *g = c->g;
    int maxarea = 0;
    for (int a = 0; a < 3; a++) {
        int area = g->n[(a + 1) % 3] * g->n[(a + 2) % 3];
        if (area > maxarea) maxarea = area;
    }
    slot *sl = malloc(sizeof *sl * (size_t)maxarea);
    if (!sl) { c->oom = 1; return -1; }
    for (int a = 0; a < 3; a++) {
        int u = (a + 1) % 3, v = (a + 2) % 3, nu = g->n[u], nv = g->n[v];
        for (int p = 1; p < g->n[a]; p++)
            for (int side = 0; side < 2; side++) {
                /* side 0: looks along +axis from the upper cell; 1: along -axis */
                int facing = 2 * a + side;
                for (int j = 0; j < nv; j++)
                    for (int i = 0; i < nu; i++) {
                        slot *s = &sl[j * nu + i];
                        int cu[3], cl[3];
                        cu[a] = p, cu[u] = i, cu[v] = j;
                        memcpy(cl, cu, sizeof cl);
                        cl[a] = p - 1;
                        const int *self = side == 0 ? cu : cl, *other = side == 0 ? cl : cu;
                        int ks = bi_kind(g, self[0], self[1], self[2]);
                        int ko = bi_kind(g, other[0], other[1], other[2]);
                        s->used = 0;
                        s->tex = -1;
                        if (!is_open(ks) || ko == ks) continue;
                        int mat = ko == BI_SOLID ? bi_mat(g, other[0], other[1], other[2]) : 0;
                        s->tex = bi_face_texture(ks, ko, mat, facing);
                        s->leaf = find_leaf(c, self);
                        s->node = find_split(c, self, other);
                        if (s->node < 0 || c->nodes[s->node].axis != a || c->nodes[s->node].pos != p) {
                            free(sl);
                            return ew_fail(err, "builtin: face at %d/%d is not on its node's plane", a, p);
                        }
                    }
                /* greedy rectangles of equal slots */
                for (int j = 0; j < nv; j++)
                    for (int i = 0; i < nu; i++) {
                        slot *s = &sl[j * nu + i];
                        if (s->tex < 0 || s->used) continue;
#define SAME(t) ((t)->tex == s->tex && !(t)->used && (t)->leaf == s->leaf && (t)->node == s->node)
                        int w = 1, h = 1;
                        while (i + w < nu && w < MAX_FACE_CELLS && SAME(&sl[j * nu + i + w])) w++;
                        for (; j + h < nv && h < MAX_FACE_CELLS; h++) {
                            int ok = 1;
                            for (int k = 0; k < w && ok; k++) ok = SAME(&sl[(j + h) * nu + i + k]);
                            if (!ok) break;
                        }
#undef SAME
                        for (int jj = 0; jj < h; jj++)
                            for (int ii = 0; ii < w; ii++) sl[(j + jj) * nu + i + ii].used = 1;
                        if (emit_face(c, a, p, facing, i, i + w, j, j + h, s)) { free(sl); return -1; }
                    }
            }
    }
    free(sl);
    return 0;
}

static frect face_rect(const bface *f) {
    return (frect){f->axis, f->pos * BI_CELL, f->facing, f->u0 * BI_CELL, f->u1 * BI_CELL,
                   f->v0 * BI_CELL, f->v1 * BI_CELL};
}

/* Corners of a rectangle, clockwise seen from where it looks. */
static void rect_corners(const frect *f, int out[4][3]) {
    int a = f->axis, u = (a + 1) % 3, v = (a + 2) % 3;
    int uu[4], vv[4];
    if (f->facing & 1) {  /* looks along -axis */
        uu[0] = f->u0, vv[0] = f->v0, uu[1] = f->u1, vv[1] = f->v0;
        uu[2] = f->u1, vv[2] = f->v1, uu[3] = f->u0, vv[3] = f->v1;
    } else {
        uu[0] = f->u0, vv[0] = f->v0, uu[1] = f->u0, vv[1] = f->v1;
        uu[2] = f->u1, vv[2] = f->v1, uu[3] = f->u1, vv[3] = f->v0;
    }
    for (int i = 0; i < 4; i++) {
        out[i][a] = f->pos;
        out[i][u] = uu[i];
        out[i][v] = vv[i];
    }
}
static void face_corners(const bface *f, int out[4][3]) {
    frect r = face_rect(f);
    rect_corners(&r, out);
}

/* A point on an axis-parallel line: the line's axis, its two fixed
 * coordinates, and the position along it. */
typedef struct linept {
    int axis, c1, c2, t;
} linept;
static int linept_cmp(const void *pa, const void *pb) {
    const linept *a = pa, *b = pb;
    if (a->axis != b->axis) return a->axis < b->axis ? -1 : 1;
    if (a->c1 != b->c1) return a->c1 < b->c1 ? -1 : 1;
    if (a->c2 != b->c2) return a->c2 < b->c2 ? -1 : 1;
    return a->t < b->t ? -1 : a->t > b->t;
}

static uint64_t vkey(const int p[3]) {
    return (uint64_t)(uint32_t)(p[0] + 32768) << 40 ^ (uint64_t)(uint32_t)(p[1] + 32768) << 20 ^
           (uint64_t)(uint32_t)(p[2] + 32768);
}
static int vertex_index(ctx *c, const int p[3]) {
    size_t s = imap_slot(&c->vmap, vkey(p));
    if (s == (size_t)-1) { c->oom = 1; return -1; }
    if (c->vmap.vals[s] >= 0) return c->vmap.vals[s];
    if (GROW(c, c->verts, c->nverts, c->capverts, 1)) return -1;
    memcpy(c->verts[c->nverts], p, sizeof c->verts[0]);
    c->vmap.keys[s] = vkey(p), c->vmap.vals[s] = c->nverts, c->vmap.count++;
    return c->nverts++;
}

/* Polygons with T-junction vertices inserted; faces must be in file order. */
static int make_polygons(ctx *c) {
    size_t n = (size_t)c->nfaces * 12;
    linept *lp = malloc(sizeof *lp * n);
    if (!lp) { c->oom = 1; return -1; }
    size_t k = 0;
    for (int fi = 0; fi < c->nfaces; fi++) {
        int cr[4][3];
        face_corners(&c->faces[fi], cr);
        for (int i = 0; i < 4; i++)
            for (int a = 0; a < 3; a++)
                lp[k++] = (linept){a, cr[i][(a + 1) % 3], cr[i][(a + 2) % 3], cr[i][a]};
    }
    qsort(lp, n, sizeof *lp, linept_cmp);
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (m == 0 || linept_cmp(&lp[m - 1], &lp[i]) != 0) lp[m++] = lp[i];

    for (int fi = 0; fi < c->nfaces; fi++) {
        bface *f = &c->faces[fi];
        int cr[4][3];
        face_corners(f, cr);
        f->firstvert = c->npolys;
        for (int i = 0; i < 4; i++) {
            const int *p = cr[i], *q = cr[(i + 1) & 3];
            int a = p[0] != q[0] ? 0 : p[1] != q[1] ? 1 : 2;
            if (GROW(c, c->polys, c->npolys, c->cappolys, 1)) break;
            if ((c->polys[c->npolys] = vertex_index(c, p)) < 0) break;
            c->npolys++;
            /* binary search for the first point of this line after the lower end */
            int tlo = p[a] < q[a] ? p[a] : q[a], thi = p[a] < q[a] ? q[a] : p[a];
            linept key = {a, p[(a + 1) % 3], p[(a + 2) % 3], tlo};
            size_t l = 0, r = m;
            while (l < r) {
                size_t mid = (l + r) / 2;
                if (linept_cmp(&lp[mid], &key) <= 0) l = mid + 1; else r = mid;
            }
            size_t e = l;
            while (e < m && lp[e].axis == a && lp[e].c1 == key.c1 && lp[e].c2 == key.c2 && lp[e].t < thi) e++;
            for (size_t j = 0; j < e - l; j++) {
                /* walk from p towards q */
                const linept *t = p[a] < q[a] ? &lp[l + j] : &lp[e - 1 - j];
                int pt[3];
                pt[a] = t->t, pt[(a + 1) % 3] = t->c1, pt[(a + 2) % 3] = t->c2;
                if (GROW(c, c->polys, c->npolys, c->cappolys, 1)) break;
                if ((c->polys[c->npolys] = vertex_index(c, pt)) < 0) break;
                c->npolys++;
            }
        }
        f->numverts = c->npolys - f->firstvert;
        if (c->oom) break;
    }
    free(lp);
    return c->oom ? -1 : 0;
}

static uint64_t ekey(int a, int b) { return (uint64_t)(uint32_t)a << 32 | (uint32_t)b; }

/* Surfedges of every face: an edge first used a->b is shared by one later
 * use b->a, so each edge record serves at most two faces.  The map holds,
 * per directed vertex pair, the newest edge record made for it. */
static int make_edges(ctx *c) {
    if (GROW(c, c->edges, c->nedges, c->capedges, 1)) return -1;
    c->edges[c->nedges][0] = c->edges[c->nedges][1] = 0, c->edges[c->nedges][2] = 1;
    c->nedges++;  /* edge 0 is never used: -0 would be ambiguous */
    for (int fi = 0; fi < c->nfaces; fi++) {
        bface *f = &c->faces[fi];
        int first = c->nsurfedges;
        for (int i = 0; i < f->numverts; i++) {
            int a = c->polys[f->firstvert + i], b = c->polys[f->firstvert + (i + 1) % f->numverts];
            int se;
            size_t s = imap_slot(&c->emap, ekey(b, a));
            if (s == (size_t)-1) { c->oom = 1; return -1; }
            int e = c->emap.vals[s];
            if (e >= 0 && !c->edges[e][2]) {
                se = -e;
                c->edges[e][2] = 1;
            } else {
                if (GROW(c, c->edges, c->nedges, c->capedges, 1)) return -1;
                c->edges[c->nedges][0] = a, c->edges[c->nedges][1] = b, c->edges[c->nedges][2] = 0;
                se = c->nedges++;
                size_t t = imap_slot(&c->emap, ekey(a, b));
                if (t == (size_t)-1) { c->oom = 1; return -1; }
                if (c->emap.vals[t] < 0) c->emap.count++;
                /* a repeated a->b use replaces the older record as the one to share */
                c->emap.keys[t] = ekey(a, b), c->emap.vals[t] = se;
            }
            if (GROW(c, c->surfedges, c->nsurfedges, c->capsurfedges, 1)) return -1;
            c->surfedges[c->nsurfedges++] = se;
        }
        f->firstvert = first;  /* from here on: first surfedge */
    }
    return 0;
}

/* ---- texture axes ------------------------------------------------------------ */

/* Quake's world-aligned axes: floors s = x, t = -y; walls s = y or x, t = -z. */
static void tex_axes(int axis, int *sa, int *ssign, int *ta, int *tsign) {
    if (axis == 2) *sa = 0, *ssign = 1, *ta = 1, *tsign = -1;
    else if (axis == 0) *sa = 1, *ssign = 1, *ta = 2, *tsign = -1;
    else *sa = 0, *ssign = 1, *ta = 2, *tsign = -1;
}

/* Range of sign * coordinate along one axis (not the plane's) over a rectangle. */
static void rect_range(const frect *f, int ax, int sign, int *mn, int *mx) {
    int u = (f->axis + 1) % 3;
    int lo = ax == u ? f->u0 : f->v0, hi = ax == u ? f->u1 : f->v1;
    *mn = sign > 0 ? lo : -hi;
    *mx = sign > 0 ? hi : -lo;
}

/* The texinfo whose texture starts at the rectangle's corner (so a button
 * or a door shows whole); offsets are taken modulo tw, th. */
static texinfo_def corner_texinfo(const frect *f, int tex, int tw, int th) {
    int sa, ss, ta, ts, smin, smax, tmin, tmax;
    tex_axes(f->axis, &sa, &ss, &ta, &ts);
    rect_range(f, sa, ss, &smin, &smax);
    rect_range(f, ta, ts, &tmin, &tmax);
    return (texinfo_def){tex, f->axis, ((-smin) % tw + tw) % tw, ((-tmin) % th + th) % th};
}

/* Index of a texinfo, added if new; -1 when out of memory. */
static int texinfo_index(ctx *c, const texinfo_def *want) {
    int ti = 0;
    while (ti < c->ntexinfo && memcmp(&c->texinfo[ti], want, sizeof *want)) ti++;
    if (ti == c->ntexinfo) {
        if (GROW(c, c->texinfo, c->ntexinfo, c->captexinfo, 1)) return -1;
        c->texinfo[c->ntexinfo++] = *want;
    }
    return ti;
}

/* ---- submodels ----------------------------------------------------------------- */

/* Side k of a box (node k of its chain): k even the low side, looking
 * along -axis; k odd the high side, looking along +axis. */
static frect box_side(const bi_box *b, int k) {
    int a = k / 2, u = (a + 1) % 3, v = (a + 2) % 3;
    return (frect){a, k & 1 ? b->maxs[a] : b->mins[a], k & 1 ? 2 * a : 2 * a + 1,
                   b->mins[u], b->maxs[u], b->mins[v], b->maxs[v]};
}

static int make_submodels(ctx *c) {
    for (int m = 0; m < c->s->nsubmodels; m++) {
        const bi_box *b = &c->s->submodels[m];
        int first_edge = c->nedges;
        for (int k = 0; k < 6; k++) {
            sface *sf = &c->sfaces[c->nsfaces++];
            sf->r = box_side(b, k);
            sf->tex = b->tex;
            int tw, th;
            bi_texture_size(b->tex, &tw, &th);
            texinfo_def want = corner_texinfo(&sf->r, b->tex, tw, th);
            if ((sf->texinfo = texinfo_index(c, &want)) < 0) return -1;
            int cr[4][3];
            rect_corners(&sf->r, cr);
            sf->firstedge = c->nsurfedges;
            for (int i = 0; i < 4; i++) {
                int va = vertex_index(c, cr[i]), vb = vertex_index(c, cr[(i + 1) & 3]);
                if (va < 0 || vb < 0) return -1;
                /* the box's neighbouring face has made this edge the other way */
                int se = 0;
                for (int e = first_edge; e < c->nedges && !se; e++)
                    if (c->edges[e][0] == vb && c->edges[e][1] == va && !c->edges[e][2])
                        se = -e, c->edges[e][2] = 1;
                if (!se) {
                    if (GROW(c, c->edges, c->nedges, c->capedges, 1)) return -1;
                    c->edges[c->nedges][0] = va, c->edges[c->nedges][1] = vb, c->edges[c->nedges][2] = 0;
                    se = c->nedges++;
                }
                if (GROW(c, c->surfedges, c->nsurfedges, c->capsurfedges, 1)) return -1;
                c->surfedges[c->nsurfedges++] = se;
            }
        }
    }
    return 0;
}


static int contents_of(int kind) {
    static const int map[BI_NUM_KINDS] = {EW_CONTENTS_EMPTY, EW_CONTENTS_SOLID,
                                          EW_CONTENTS_WATER, EW_CONTENTS_SKY};
    return map[kind];
}

static void put_bounds_units(bi_buf *b, const int lo[3], const int hi[3]) {
    for (int k = 0; k < 3; k++) bi_put_i16(b, (int16_t)lo[k]);
    for (int k = 0; k < 3; k++) bi_put_i16(b, (int16_t)hi[k]);
}
static void put_bounds(bi_buf *b, const int lo[3], const int hi[3]) {
    int l[3], h[3];
    for (int k = 0; k < 3; k++) l[k] = lo[k] * BI_CELL, h[k] = hi[k] * BI_CELL;
    put_bounds_units(b, l, h);
}

static int floor_step(int v, int step) { return v >= 0 ? v / step * step : -((-v + step - 1) / step * step); }
static int ceil_step(int v, int step) { return -floor_step(-v, step); }

/* One light sample at p (looking along n): mono into lt, colour into rgb. */
static void put_sample(const bi_scene *s, const float p[3], const float n[3], bi_buf *lt, bi_buf *rgb) {
    uint8_t c[3];
    bi_put_u8(lt, (uint8_t)bi_light_point_rgb(s, p, n, c));
    if (rgb) bi_put(rgb, c, 3);
}

/* The light map of a rectangle: one sample per step texels (16: Quake's),
 * on the grid of its texinfo, lit from just in front of the face. */
static void put_lightmap(const bi_scene *s, const frect *f, const texinfo_def *ti, int step, bi_buf *lt,
                         bi_buf *rgb) {
    int sa, ss, ta, ts, smin, smax, tmin, tmax;
    tex_axes(f->axis, &sa, &ss, &ta, &ts);
    rect_range(f, sa, ss, &smin, &smax);
    rect_range(f, ta, ts, &tmin, &tmax);
    smin += ti->soff, smax += ti->soff, tmin += ti->toff, tmax += ti->toff;
    int mins_s = floor_step(smin, step), mins_t = floor_step(tmin, step);
    int ns = (ceil_step(smax, step) - mins_s) / step + 1, nt = (ceil_step(tmax, step) - mins_t) / step + 1;
    float n[3] = {0, 0, 0};
    n[f->axis] = f->facing & 1 ? -1.0f : 1.0f;
    for (int k = 0; k < nt; k++)
        for (int j = 0; j < ns; j++) {
            float p[3];
            int st[2] = {mins_s + step * j, mins_t + step * k};
            int ax[2] = {sa, ta}, sg[2] = {ss, ts}, lo[2] = {smin, tmin}, hi[2] = {smax, tmax};
            int off[2] = {ti->soff, ti->toff};
            for (int q = 0; q < 2; q++) {
                /* keep samples just inside the face so corners are not self-shadowed */
                double v = st[q];
                if (v < lo[q] + 1) v = lo[q] + 1;
                if (v > hi[q] - 1) v = hi[q] - 1;
                p[ax[q]] = (float)((v - off[q]) * sg[q]);
            }
            p[f->axis] = (float)f->pos + n[f->axis];
            put_sample(s, p, n, lt, rgb);
        }
}

/* DECOUPLED_LM: the light map on the two world axes of the face's plane,
 * `units` world units a sample; writes the samples and the face's 40-byte
 * record (uint16 width, height, int32 offset, 2x4 float world -> sample
 * matrix). */
static void put_lightmap_decoupled(const bi_scene *s, const frect *f, float units, int32_t ofs, bi_buf *lt,
                                   bi_buf *rgb, bi_buf *dec) {
    int ax[2] = {(f->axis + 1) % 3, (f->axis + 2) % 3};
    int lo[2] = {f->u0, f->v0}, hi[2] = {f->u1, f->v1}, base[2], size[2];
    for (int q = 0; q < 2; q++) {
        base[q] = (int)floorf((float)lo[q] / units);
        size[q] = (int)ceilf((float)hi[q] / units) - base[q] + 1;
    }
    float n[3] = {0, 0, 0};
    n[f->axis] = f->facing & 1 ? -1.0f : 1.0f;
    for (int k = 0; k < size[1]; k++)
        for (int j = 0; j < size[0]; j++) {
            float p[3];
            int idx[2] = {j, k};
            for (int q = 0; q < 2; q++) {
                float v = (float)(base[q] + idx[q]) * units;
                if (v < lo[q] + 1) v = (float)lo[q] + 1;
                if (v > hi[q] - 1) v = (float)hi[q] - 1;
                p[ax[q]] = v;
            }
            p[f->axis] = (float)f->pos + n[f->axis];
            put_sample(s, p, n, lt, rgb);
        }
    bi_put_u16(dec, (uint16_t)size[0]);
    bi_put_u16(dec, (uint16_t)size[1]);
    bi_put_i32(dec, ofs);
    for (int q = 0; q < 2; q++) {
        for (int k = 0; k < 3; k++) bi_put_f32(dec, k == ax[q] ? 1.0f / units : 0.0f);
        bi_put_f32(dec, (float)-base[q]);
    }
}

/* A face's light map in the layout the options ask for, and its BSPX
 * per-face records; returns its light offset (-1: special, none). */
static int32_t put_face_light(const bi_scene *s, lumps *L, const frect *r, const texinfo_def *ti, int special) {
    const ew_mapgen_options *o = s->opt;
    bi_buf *lt = &L->l[EW_LUMP_LIGHTING];
    bi_buf *rgb = o && (o->lit || o->rgblighting) ? &L->rgb : NULL;
    int32_t ofs = special ? -1 : (int32_t)lt->len;
    if (o && o->decoupled) {
        float units = o->decoupled_units > 0 ? o->decoupled_units : 12.0f;
        if (special) {
            bi_put_u16(&L->dec, 0), bi_put_u16(&L->dec, 0), bi_put_i32(&L->dec, -1);
            bi_put_zeros(&L->dec, 32);
        } else {
            put_lightmap_decoupled(s, r, units, ofs, lt, rgb, &L->dec);
        }
        return ofs;
    }
    int shift = o && o->lmshift_lumps ? o->lmshift : 4;
    if (!special) put_lightmap(s, r, ti, 1 << shift, lt, rgb);
    if (o && o->lmshift_lumps) {
        const uint8_t lit[4] = {0, 255, 255, 255}, unlit[4] = {255, 255, 255, 255};
        bi_put_u8(&L->shift, (uint8_t)shift);
        bi_put_i32(&L->ofs, ofs);
        bi_put(&L->style, special ? unlit : lit, 4);
    }
    return ofs;
}

static void put_face(bi_buf *b, int plane, int side, int firstedge, int numedges, int texinfo,
                     int special, int32_t lightofs) {
    bi_put_i16(b, (int16_t)plane);
    bi_put_i16(b, (int16_t)side);
    bi_put_i32(b, firstedge);
    bi_put_i16(b, (int16_t)numedges);
    bi_put_i16(b, (int16_t)texinfo);
    const uint8_t lit[4] = {0, 255, 255, 255}, unlit[4] = {255, 255, 255, 255};
    bi_put(b, special ? unlit : lit, 4);
    bi_put_i32(b, lightofs);
}

/* Plane number of (axis, dist in units): a node plane of the grid, or
 * one added after them. */
static int plane_of(ctx *c, bi_buf *planes, int axis, int dist) {
    if (dist % BI_CELL == 0 && dist >= 0 && dist / BI_CELL <= MAX_GRID && c->planes[axis][dist / BI_CELL] >= 0)
        return c->planes[axis][dist / BI_CELL];
    for (int i = 0; i < c->nextra_planes; i++)
        if (c->extra_planes[i][0] == axis && c->extra_planes[i][1] == dist) return c->nplanes - c->nextra_planes + i;
    if (GROW(c, c->extra_planes, c->nextra_planes, c->capextra, 1)) return 0;
    c->extra_planes[c->nextra_planes][0] = axis, c->extra_planes[c->nextra_planes][1] = dist;
    c->nextra_planes++;
    for (int k = 0; k < 3; k++) bi_put_f32(planes, k == axis ? 1.0f : 0.0f);
    bi_put_f32(planes, (float)dist);
    bi_put_i32(planes, axis);
    return c->nplanes++;
}

static int child_ref(const ctx *c, int n) {
    const bnode *nd = &c->nodes[n];
    return nd->leaf ? -1 - nd->out : nd->out;
}


static int write_vis(ctx *c, bi_buf *vis, int32_t *visofs) {
    int n = c->numleaves_out;
    int (*lo)[3] = malloc(sizeof *lo * (size_t)n), (*hi)[3] = malloc(sizeof *hi * (size_t)n);
    uint8_t *open = calloc((size_t)n, 1), *pvs = malloc((size_t)n * n);
    int rowbytes = (n - 1 + 7) / 8;
    uint8_t *row = malloc((size_t)rowbytes + 1);
    size_t *start = calloc((size_t)n, sizeof *start), *len = calloc((size_t)n, sizeof *len);
    int rc = -1;
    if (!lo || !hi || !open || !pvs || !row || !start || !len) goto done;
    for (int l = 1; l < n; l++) {
        const bnode *nd = &c->nodes[c->leaf_of_out[l]];
        for (int k = 0; k < 3; k++) lo[l][k] = nd->lo[k] * BI_CELL, hi[l][k] = nd->hi[k] * BI_CELL;
        open[l] = (uint8_t)is_open(nd->kind);
    }
    memset(lo[0], 0, sizeof lo[0]), memset(hi[0], 0, sizeof hi[0]);
    if (bi_compute_pvs(n, (const int (*)[3])lo, (const int (*)[3])hi, open, pvs)) goto done;
    for (int l = 0; l < n; l++) {
        visofs[l] = -1;
        if (!open[l]) continue;
        memset(row, 0, (size_t)rowbytes);
        for (int j = 1; j < n; j++)
            if (pvs[(size_t)l * n + j]) row[(j - 1) >> 3] |= (uint8_t)(1 << ((j - 1) & 7));
        /* zero bytes run-length coded: 0, count */
        start[l] = vis->len;
        for (int i = 0; i < rowbytes;) {
            if (row[i]) { bi_put_u8(vis, row[i++]); continue; }
            int run = 0;
            while (i < rowbytes && !row[i] && run < 255) i++, run++;
            bi_put_u8(vis, 0);
            bi_put_u8(vis, (uint8_t)run);
        }
        if (vis->failed) goto done;
        len[l] = vis->len - start[l];
        visofs[l] = (int32_t)start[l];
        /* leaves that see the same set share one row */
        for (int e = 1; e < l; e++)
            if (open[e] && len[e] == len[l] && !memcmp(vis->data + start[e], vis->data + start[l], len[l])) {
                vis->len = start[l];
                visofs[l] = (int32_t)start[e];
                start[l] = start[e];
                break;
            }
    }
    rc = 0;
done:
    free(lo), free(hi), free(open), free(pvs), free(row), free(start), free(len);
    if (rc) c->oom = 1;
    return rc;
}

static int write_lumps(ctx *c, const uint8_t palette[768], lumps *L) {
    const bi_scene *s = c->s;
    /* entities */
    bi_put(&L->l[EW_LUMP_ENTITIES], s->entities, strlen(s->entities) + 1);
    /* planes: one per (axis, position) used by a node */
    for (int a = 0; a < 3; a++)
        for (int p = 0; p <= MAX_GRID; p++) c->planes[a][p] = -1;
    for (int i = 0; i < c->numnodes_out; i++) {
        const bnode *nd = &c->nodes[c->node_of_out[i]];
        if (c->planes[nd->axis][nd->pos] >= 0) continue;
        c->planes[nd->axis][nd->pos] = c->nplanes++;
        bi_buf *b = &L->l[EW_LUMP_PLANES];
        for (int k = 0; k < 3; k++) bi_put_f32(b, k == nd->axis ? 1.0f : 0.0f);
        bi_put_f32(b, (float)(nd->pos * BI_CELL));
        bi_put_i32(b, nd->axis);
    }
    for (int i = 0; i < c->nsfaces; i++)
        c->sfaces[i].plane = plane_of(c, &L->l[EW_LUMP_PLANES], c->sfaces[i].r.axis, c->sfaces[i].r.pos);
    if (bi_write_textures(palette, &L->l[EW_LUMP_TEXTURES])) return -1;
    for (int i = 0; i < c->nverts; i++)
        for (int k = 0; k < 3; k++) bi_put_f32(&L->l[EW_LUMP_VERTEXES], (float)c->verts[i][k]);

    /* faces are sorted by node: each node's faces are one run */
    int *firstface = calloc((size_t)c->numnodes_out + 1, sizeof *firstface);
    int32_t *visofs = malloc(sizeof *visofs * (size_t)c->numleaves_out);
    if (!firstface || !visofs) { free(firstface), free(visofs); c->oom = 1; return -1; }
    for (int i = 0; i < c->nfaces; i++) firstface[c->nodes[c->faces[i].node].out + 1]++;
    for (int i = 0; i < c->numnodes_out; i++) firstface[i + 1] += firstface[i];

    if (write_vis(c, &L->l[EW_LUMP_VISIBILITY], visofs)) { free(firstface), free(visofs); return -1; }

    for (int i = 0; i < c->numnodes_out; i++) {
        const bnode *nd = &c->nodes[c->node_of_out[i]];
        bi_buf *b = &L->l[EW_LUMP_NODES];
        bi_put_i32(b, c->planes[nd->axis][nd->pos]);
        bi_put_i16(b, (int16_t)child_ref(c, nd->child[0]));
        bi_put_i16(b, (int16_t)child_ref(c, nd->child[1]));
        put_bounds(b, nd->lo, nd->hi);
        bi_put_u16(b, (uint16_t)firstface[i]);
        bi_put_u16(b, (uint16_t)(firstface[i + 1] - firstface[i]));
        /* clip hull: the same tree with contents in place of leaves */
        bi_buf *cb = &L->l[EW_LUMP_CLIPNODES];
        bi_put_i32(cb, c->planes[nd->axis][nd->pos]);
        for (int k = 0; k < 2; k++) {
            const bnode *ch = &c->nodes[nd->child[k]];
            bi_put_i16(cb, (int16_t)(ch->leaf ? contents_of(ch->kind) : ch->out));
        }
    }
    /* submodel chains: node 6m+k holds side k; outside it an empty leaf of
     * its own, inside the next node (the solid leaf after the last) */
    for (int i = 0; i < c->nsfaces; i++) {
        const sface *sf = &c->sfaces[i];
        const bi_box *box = &s->submodels[i / 6];
        int k = i % 6, node = c->numnodes_out + i;
        int inside = k < 5 ? node + 1 : -1, outside = -1 - (c->numleaves_out + i);
        int high = k & 1;  /* the high side's front is the outside */
        bi_buf *b = &L->l[EW_LUMP_NODES];
        bi_put_i32(b, sf->plane);
        bi_put_i16(b, (int16_t)(high ? outside : inside));
        bi_put_i16(b, (int16_t)(high ? inside : outside));
        put_bounds_units(b, box->mins, box->maxs);
        bi_put_u16(b, (uint16_t)(c->nfaces + i));
        bi_put_u16(b, 1);
        bi_buf *cb = &L->l[EW_LUMP_CLIPNODES];
        int cin = k < 5 ? node + 1 : EW_CONTENTS_SOLID;
        bi_put_i32(cb, sf->plane);
        bi_put_i16(cb, (int16_t)(high ? EW_CONTENTS_EMPTY : cin));
        bi_put_i16(cb, (int16_t)(high ? cin : EW_CONTENTS_EMPTY));
    }
    /* the player's clip hulls (clip_hull.c) after those: hull 1, hull 2 */
    static const int hull_mins[2][3] = {{-16, -16, -24}, {-32, -32, -24}};
    static const int hull_maxs[2][3] = {{16, 16, 32}, {32, 32, 64}};
    int next = c->numnodes_out + c->nsfaces;
    for (int h = 0; h < 2; h++) {
        bi_clipnode *cn;
        int ncn;
        if (bi_build_clip_hull(c->g, hull_mins[h], hull_maxs[h], &cn, &ncn)) {
            free(firstface), free(visofs);
            c->oom = 1;
            return -1;
        }
        c->hull_head[h] = next;
        if (next + ncn > 32767) {  /* int16 children: too big a hull; no collision rather than a bad one */
            c->hull_head[h] = 0;
            ncn = 0;
        }
        for (int i = 0; i < ncn; i++) {
            bi_buf *cb = &L->l[EW_LUMP_CLIPNODES];
            bi_put_i32(cb, plane_of(c, &L->l[EW_LUMP_PLANES], cn[i].axis, cn[i].dist));
            for (int k = 0; k < 2; k++)
                bi_put_i16(cb, (int16_t)(cn[i].child[k] >= 0 ? next + cn[i].child[k] : cn[i].child[k]));
        }
        next += ncn;
        free(cn);
    }
    for (int i = 0; i < c->ntexinfo; i++) {
        bi_buf *b = &L->l[EW_LUMP_TEXINFO];
        int sa, ss, ta, ts;
        const texinfo_def *t = &c->texinfo[i];
        tex_axes(t->axis, &sa, &ss, &ta, &ts);
        for (int k = 0; k < 3; k++) bi_put_f32(b, k == sa ? (float)ss : 0.0f);
        bi_put_f32(b, (float)t->soff);
        for (int k = 0; k < 3; k++) bi_put_f32(b, k == ta ? (float)ts : 0.0f);
        bi_put_f32(b, (float)t->toff);
        bi_put_i32(b, t->tex);
        bi_put_i32(b, bi_texture_is_special(t->tex) ? 1 : 0);
    }

    /* faces and their light maps */
    for (int i = 0; i < c->nfaces; i++) {
        const bface *f = &c->faces[i];
        bi_buf *b = &L->l[EW_LUMP_FACES], *lt = &L->l[EW_LUMP_LIGHTING];
        int special = bi_texture_is_special(f->tex);
        frect r = face_rect(f);
        int32_t lightofs = put_face_light(s, L, &r, &c->texinfo[f->texinfo], special);
        (void)lt;
        put_face(b, c->planes[f->axis][f->pos], f->facing & 1, f->firstvert, f->numverts, f->texinfo,
                 special, lightofs);
    }
    for (int i = 0; i < c->nsfaces; i++) {
        const sface *sf = &c->sfaces[i];
        int special = bi_texture_is_special(sf->tex);
        int32_t lightofs = put_face_light(s, L, &sf->r, &c->texinfo[sf->texinfo], special);
        put_face(&L->l[EW_LUMP_FACES], sf->plane, sf->r.facing & 1, sf->firstedge, 4, sf->texinfo,
                 special, lightofs);
    }

    /* leaves and marksurfaces: each open leaf lists the faces looking into it */
    int *markcount = calloc((size_t)c->numleaves_out + 1, sizeof *markcount);
    if (!markcount) { free(firstface), free(visofs); c->oom = 1; return -1; }
    for (int i = 0; i < c->nfaces; i++) markcount[c->nodes[c->faces[i].leaf].out + 1]++;
    for (int l = 0; l < c->numleaves_out; l++) markcount[l + 1] += markcount[l];
    for (int l = 0; l < c->numleaves_out; l++) {
        bi_buf *b = &L->l[EW_LUMP_LEAFS];
        if (l == 0) {
            static const int zero[3] = {0, 0, 0};
            bi_put_i32(b, EW_CONTENTS_SOLID);
            bi_put_i32(b, -1);
            put_bounds(b, zero, zero);
            bi_put_u16(b, 0), bi_put_u16(b, 0);
            bi_put_zeros(b, 4);
            continue;
        }
        const bnode *nd = &c->nodes[c->leaf_of_out[l]];
        bi_put_i32(b, contents_of(nd->kind));
        bi_put_i32(b, visofs[l]);
        put_bounds(b, nd->lo, nd->hi);
        bi_put_u16(b, (uint16_t)markcount[l]);
        bi_put_u16(b, (uint16_t)(markcount[l + 1] - markcount[l]));
        bi_put_zeros(b, 4);
        for (int i = 0; i < c->nfaces; i++)
            if (c->faces[i].leaf == c->leaf_of_out[l]) bi_put_u16(&L->l[EW_LUMP_MARKSURFACES], (uint16_t)i);
    }
    /* submodel leaves: the empty one outside each side lists that side's
     * face; its box is the face itself.  No PVS rows (past visleafs). */
    for (int i = 0; i < c->nsfaces; i++) {
        const frect *r = &c->sfaces[i].r;
        int lo[3], hi[3], u = (r->axis + 1) % 3, v = (r->axis + 2) % 3;
        lo[r->axis] = hi[r->axis] = r->pos;
        lo[u] = r->u0, hi[u] = r->u1, lo[v] = r->v0, hi[v] = r->v1;
        bi_buf *b = &L->l[EW_LUMP_LEAFS];
        bi_put_i32(b, EW_CONTENTS_EMPTY);
        bi_put_i32(b, -1);
        put_bounds_units(b, lo, hi);
        bi_put_u16(b, (uint16_t)(c->nfaces + i));
        bi_put_u16(b, 1);
        bi_put_zeros(b, 4);
        bi_put_u16(&L->l[EW_LUMP_MARKSURFACES], (uint16_t)(c->nfaces + i));
    }
    free(markcount), free(firstface), free(visofs);

    for (int i = 0; i < c->nedges; i++) {
        bi_put_u16(&L->l[EW_LUMP_EDGES], (uint16_t)c->edges[i][0]);
        bi_put_u16(&L->l[EW_LUMP_EDGES], (uint16_t)c->edges[i][1]);
    }
    for (int i = 0; i < c->nsurfedges; i++) bi_put_i32(&L->l[EW_LUMP_SURFEDGES], c->surfedges[i]);

    bi_buf *m = &L->l[EW_LUMP_MODELS];
    for (int k = 0; k < 3; k++) bi_put_f32(m, 0.0f);
    for (int k = 0; k < 3; k++) bi_put_f32(m, (float)(c->g->n[k] * BI_CELL));
    for (int k = 0; k < 3; k++) bi_put_f32(m, 0.0f);
    bi_put_i32(m, 0);  /* hull 0: node 0 */
    bi_put_i32(m, c->hull_head[0]), bi_put_i32(m, c->hull_head[1]);  /* the player's hulls */
    bi_put_i32(m, 0);  /* hull 3 (unused by Quake): the rendering tree's copy at clipnode 0 */
    bi_put_i32(m, c->numleaves_out - 1);
    bi_put_i32(m, 0);
    bi_put_i32(m, c->nfaces);
    for (int i = 0; i < s->nsubmodels; i++) {
        const bi_box *box = &s->submodels[i];
        for (int k = 0; k < 3; k++) bi_put_f32(m, (float)box->mins[k]);
        for (int k = 0; k < 3; k++) bi_put_f32(m, (float)box->maxs[k]);
        for (int k = 0; k < 3; k++) bi_put_f32(m, 0.0f);
        for (int k = 0; k < 4; k++) bi_put_i32(m, c->numnodes_out + 6 * i);  /* hull 0 and clip hulls */
        bi_put_i32(m, 0);  /* no PVS of its own */
        bi_put_i32(m, c->nfaces + 6 * i);
        bi_put_i32(m, 6);
    }
    return 0;
}

/* The BSPX directory and lumps the options ask for, after the standard
 * lumps (4-byte aligned, as compilers write them), and the .lit image.
 * Nothing without options. */
static int write_bspx(const bi_scene *s, lumps *L, bi_buf *out) {
    const ew_mapgen_options *o = s->opt;
    if (!o) return 0;
    if (L->rgb.failed || L->shift.failed || L->ofs.failed || L->style.failed || L->dec.failed) return -1;
    if (o->lit && s->lit_out) {
        bi_put(s->lit_out, "QLIT", 4);
        bi_put_i32(s->lit_out, 1);
        bi_put(s->lit_out, L->rgb.data, L->rgb.len);
        if (s->lit_out->failed) return -1;
    }
    struct { const char *name; const bi_buf *b; } x[5];
    int n = 0;
    if (o->rgblighting) x[n].name = "RGBLIGHTING", x[n++].b = &L->rgb;
    if (o->lmshift_lumps && !o->decoupled) {
        x[n].name = "LMSHIFT", x[n++].b = &L->shift;
        x[n].name = "LMOFFSET", x[n++].b = &L->ofs;
        x[n].name = "LMSTYLE", x[n++].b = &L->style;
    }
    if (o->decoupled) x[n].name = "DECOUPLED_LM", x[n++].b = &L->dec;
    if (!n) return 0;
    bi_put_zeros(out, (4 - out->len % 4) % 4);
    size_t dir = out->len;
    bi_put(out, "BSPX", 4);
    bi_put_i32(out, n);
    bi_put_zeros(out, 32 * (size_t)n);
    for (int i = 0; i < n; i++) {
        bi_put_zeros(out, (4 - out->len % 4) % 4);
        size_t ofs = out->len;
        bi_put(out, x[i].b->data, x[i].b->len);
        if (out->failed) return -1;
        uint8_t *e = out->data + dir + 8 + 32 * i;
        memset(e, 0, 24);
        memcpy(e, x[i].name, strlen(x[i].name));
        uint32_t v[2] = {(uint32_t)ofs, (uint32_t)x[i].b->len};
        for (int k = 0; k < 8; k++) e[24 + k] = (uint8_t)(v[k / 4] >> (8 * (k % 4)));
    }
    return out->failed ? -1 : 0;
}

int bi_build_bsp(const bi_scene *s, const uint8_t palette[768], bi_buf *out, ew_error *err) {
    ctx *c = calloc(1, sizeof *c);
    lumps *L = calloc(1, sizeof *L);
    int rc = -1;
    if (!c || !L) { free(c), free(L); return ew_fail(err, "builtin: out of memory"); }
    c->s = s, c->g = &s->grid;
    for (int k = 0; k < 3; k++)
        if (c->g->n[k] < 3 || c->g->n[k] > MAX_GRID) {
            ew_fail(err, "builtin: grid size %d out of range", c->g->n[k]);
            goto done;
        }
    const int lo[3] = {0, 0, 0};
    if ((c->root = build(c, lo, c->g->n)) < 0) goto oom;
    c->node_of_out = malloc(sizeof *c->node_of_out * (size_t)c->nnodes);
    c->leaf_of_out = malloc(sizeof *c->leaf_of_out * ((size_t)c->nnodes + 1));
    if (!c->node_of_out || !c->leaf_of_out) goto oom;
    c->numleaves_out = 1;  /* leaf 0: the shared solid leaf */
    c->leaf_of_out[0] = -1;
    if (c->nodes[c->root].leaf) {
        ew_fail(err, "builtin: the scene has no walls");
        goto done;
    }
    number_tree(c, c->root);
    if (make_faces(c, err)) { if (c->oom) goto oom; goto done; }

    /* stable sort by node (file order), then texinfo numbers in that order */
    {
        bface *sorted = malloc(sizeof *sorted * (size_t)c->nfaces);
        int *start = calloc((size_t)c->numnodes_out + 1, sizeof *start);
        if (!sorted || !start) { free(sorted), free(start); goto oom; }
        for (int i = 0; i < c->nfaces; i++) start[c->nodes[c->faces[i].node].out + 1]++;
        for (int i = 0; i < c->numnodes_out; i++) start[i + 1] += start[i];
        for (int i = 0; i < c->nfaces; i++) sorted[start[c->nodes[c->faces[i].node].out]++] = c->faces[i];
        free(c->faces);
        c->faces = sorted, c->capfaces = c->nfaces;
        free(start);
    }
    for (int i = 0; i < c->nfaces; i++) {
        bface *f = &c->faces[i];
        f->out = i;
        texinfo_def want = {f->tex, f->axis, 0, 0};
        if (f->tex == BI_T_BUTTON0 || f->tex == BI_T_BUTTON1) {
            /* a button shows whole: its texture starts at the face's corner */
            frect r = face_rect(f);
            want = corner_texinfo(&r, f->tex, 64, 64);
        }
        if ((f->texinfo = texinfo_index(c, &want)) < 0) goto oom;
    }
    if (s->nsubmodels < 0 || s->nsubmodels > BI_MAX_SUBMODELS) {
        ew_fail(err, "builtin: %d submodels (at most %d)", s->nsubmodels, BI_MAX_SUBMODELS);
        goto done;
    }
    for (int i = 0; i < s->nsubmodels; i++) {
        const bi_box *b = &s->submodels[i];
        for (int k = 0; k < 3; k++)
            if (b->mins[k] >= b->maxs[k] || b->mins[k] < -32768 || b->maxs[k] > 32767) {
                ew_fail(err, "builtin: submodel %d is an empty or oversized box", i + 1);
                goto done;
            }
        if (b->tex < 0 || b->tex >= BI_NUM_TEXTURES) {
            ew_fail(err, "builtin: submodel %d has texture %d", i + 1, b->tex);
            goto done;
        }
    }
    if (c->nfaces + 6 * s->nsubmodels > 65535 || c->numnodes_out + 6 * s->nsubmodels > 32767 ||
        c->numleaves_out + 6 * s->nsubmodels > 32767) {
        ew_fail(err, "builtin: scene too big for BSP29 (%d faces, %d nodes, %d leaves)", c->nfaces,
                c->numnodes_out, c->numleaves_out);
        goto done;
    }
    if (make_polygons(c) || make_edges(c) || make_submodels(c)) goto oom;
    if (c->nverts > 65535 || c->nedges > 65535) {
        ew_fail(err, "builtin: too many vertices or edges (%d, %d)", c->nverts, c->nedges);
        goto done;
    }
    if (write_lumps(c, palette, L) || c->oom) goto oom;

    /* header, then each lump 4-byte aligned */
    bi_put_i32(out, 29);
    size_t dir = out->len;
    bi_put_zeros(out, 8 * EW_NUM_LUMPS);
    for (int i = 0; i < EW_NUM_LUMPS; i++) {
        if (L->l[i].failed) goto oom;
        bi_put_zeros(out, (4 - out->len % 4) % 4);
        size_t ofs = out->len;
        bi_put(out, L->l[i].data, L->l[i].len);
        if (out->failed) goto oom;
        uint32_t v[2] = {(uint32_t)ofs, (uint32_t)L->l[i].len};
        for (int k = 0; k < 8; k++) out->data[dir + 8 * i + k] = (uint8_t)(v[k / 4] >> (8 * (k % 4)));
    }
    if (out->failed) goto oom;
    if (write_bspx(s, L, out)) goto oom;
    rc = 0;
    goto done;
oom:
    ew_fail(err, "builtin: out of memory");
done:
    if (c) {
        free(c->nodes), free(c->faces), free(c->node_of_out), free(c->leaf_of_out);
        free(c->polys), free(c->verts), free(c->edges), free(c->surfedges), free(c->texinfo);
        free(c->extra_planes);
        imap_free(&c->vmap), imap_free(&c->emap);
    }
    if (L) {
        for (int i = 0; i < EW_NUM_LUMPS; i++) free(L->l[i].data);
        free(L->rgb.data), free(L->shift.data), free(L->ofs.data), free(L->style.data), free(L->dec.data);
    }
    free(c), free(L);
    return rc;
}
