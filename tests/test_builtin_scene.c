/*
 * The built-in scene: the generated BSP29 image is deterministic, loads
 * through the real loader, and is a well-formed world: faces on their
 * nodes' planes, wound clockwise, watertight (every edge shared by exactly
 * two faces), leaves listing the faces that bound them, light maps that
 * vary, a PVS that culls something but never hides a leaf a straight line
 * can reach, and a view set inside open space.  The door is submodel *1:
 * a box of six faces on a chain of six nodes of its own, in open space,
 * spawned by the entity lump's func_door.  The triangle model
 * (bi_model_generate) is a valid, deterministic MDL: it loads, animates,
 * and every part of it is a closed surface wound outwards.
 *
 * Debug aid: EW_BUILTIN_DUMP=file.bsp writes the image out, so it can be
 * inspected with `edgewise info file.bsp` or a map viewer.
 */
#include "util.h"
#include "ew_util.h"
#include "ew_world.h"
#include "mapgen.h"
#include "asset/mdl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Generation time is printed for the record; speed is the benchmark's
 * business, never a test's (a loaded machine must not fail it). */
static double cpu_ms(void) { return 1000.0 * (double)clock() / CLOCKS_PER_SEC; }

static uint8_t pal[768], cmap[EW_COLORMAP_SIZE];

/* ---- helpers over the loaded world ---------------------------------------- */

static double plane_dist(const ew_world *w, int plane, const double p[3]) {
    const ew_plane *pl = &w->planes[plane];
    return p[0] * pl->normal[0] + p[1] * pl->normal[1] + p[2] * pl->normal[2] - pl->dist;
}
static void vert(const ew_world *w, int v, double p[3]) {
    for (int k = 0; k < 3; k++) p[k] = w->verts[v][k];
}

static int point_leaf_in(const ew_world *w, int model, const double p[3]) {
    int n = w->models[model].headnode;
    while (n >= 0) n = w->nodes[n].children[plane_dist(w, w->nodes[n].plane, p) >= 0 ? 0 : 1];
    return -1 - n;
}
static int point_leaf(const ew_world *w, const double p[3]) { return point_leaf_in(w, 0, p); }
static int leaf_open(const ew_world *w, int leaf) {
    int c = w->leaves[leaf].contents;
    return c == EW_CONTENTS_EMPTY || c == EW_CONTENTS_WATER;
}

/* 1 if the segment a-b crosses only open leaves, split through the tree
 * (independent of the generator's own grid walk). */
static int segment_clear(const ew_world *w, int n, const double a[3], const double b[3]) {
    if (n < 0) return leaf_open(w, -1 - n);
    double da = plane_dist(w, w->nodes[n].plane, a), db = plane_dist(w, w->nodes[n].plane, b);
    if (da >= 0 && db >= 0) return segment_clear(w, w->nodes[n].children[0], a, b);
    if (da < 0 && db < 0) return segment_clear(w, w->nodes[n].children[1], a, b);
    double f = da / (da - db), m[3];
    for (int k = 0; k < 3; k++) m[k] = a[k] + f * (b[k] - a[k]);
    int s = da < 0;
    return segment_clear(w, w->nodes[n].children[s], a, m) &&
           segment_clear(w, w->nodes[n].children[!s], m, b);
}

/* Decompresses leaf's PVS row into row[0..visleafs] (row[0] unused); -1 on
 * malformed data. */
static int pvs_row(const ew_world *w, int leaf, uint8_t *row) {
    int vl = w->models[0].visleafs;
    memset(row, 0, (size_t)vl + 1);
    if (w->leaves[leaf].visofs < 0) return 1;
    int pos = w->leaves[leaf].visofs, j = 0;
    while (j < vl) {
        if (pos >= w->vissize) return -1;
        uint8_t byte = w->visdata[pos++];
        if (byte) {
            for (int k = 0; k < 8 && j < vl; k++, j++) row[j + 1] = (byte >> k) & 1;
            continue;
        }
        if (pos >= w->vissize) return -1;
        j += 8 * w->visdata[pos++];
    }
    return 0;
}

/* ---- checks ---------------------------------------------------------------- */

static void check_header(const uint8_t *b, size_t n) {
    CHECK(n > 124 && ew_i32(b) == 29, "version %d", n > 4 ? ew_i32(b) : -1);
    static const int recsize[EW_NUM_LUMPS] = {1, 20, 1, 12, 1, 24, 40, 20, 1, 8, 28, 2, 4, 4, 64};
    for (int i = 0; i < EW_NUM_LUMPS && n > 124; i++) {
        uint32_t ofs = ew_u32(b + 4 + 8 * i), len = ew_u32(b + 8 + 8 * i);
        CHECK(ofs % 4 == 0 && ofs >= 124 && (uint64_t)ofs + len <= n, "lump %d at %u+%u of %zu", i, ofs, len, n);
        CHECK(len % (uint32_t)recsize[i] == 0, "lump %d length %u", i, len);
    }
}

static void check_palette_colormap(void) {
    int identity = 0, fullbright_ok = 1, darker = 1;
    for (int c = 0; c < 224; c++) identity += cmap[32 * 256 + c] == c;
    for (int r = 0; r < 64; r++)
        for (int c = 224; c < 256; c++) fullbright_ok &= cmap[r * 256 + c] == c;
    for (int c = 0; c < 224; c++) {
        const uint8_t *lo = pal + 3 * cmap[63 * 256 + c], *mid = pal + 3 * cmap[32 * 256 + c];
        darker &= lo[0] + lo[1] + lo[2] <= mid[0] + mid[1] + mid[2];
        darker &= lo[0] + lo[1] + lo[2] < 40;
    }
    CHECK(identity >= 220, "colormap row 32 keeps only %d of 224 colours", identity);
    CHECK(fullbright_ok, "fullbright colours change with light");
    CHECK(darker, "row 63 is not dark");
    CHECK(pal[0] == 0 && pal[1] == 0 && pal[2] == 0, "colour 0 is not black");
    int brighter = 0;
    for (int c = 0; c < 224; c++) {
        const uint8_t *hi = pal + 3 * cmap[c], *mid = pal + 3 * c;
        brighter += hi[0] + hi[1] + hi[2] > mid[0] + mid[1] + mid[2];
    }
    CHECK(brighter > 150, "row 0 brightens only %d colours", brighter);
}

static void check_textures(const ew_world *w) {
    CHECK(w->numtextures >= BI_NUM_TEXTURES, "%d textures", w->numtextures);
    CHECK(w->textures_missing == 0, "%d textures missing", w->textures_missing);
    int sky = -1, water = -1, b0 = -1, b1 = -1;
    for (int i = 0; i < w->numtextures; i++) {
        const ew_texture *t = &w->textures[i];
        if (!strncmp(t->name, "sky", 3)) sky = i;
        if (!strcmp(t->name, "*water")) water = i;
        if (!strcmp(t->name, "+0button")) b0 = i;
        if (!strcmp(t->name, "+1button")) b1 = i;
    }
    CHECK(sky >= 0 && w->textures[sky].width == 256 && w->textures[sky].height == 128 &&
              (w->textures[sky].flags & EW_SURF_SKY),
          "sky texture");
    CHECK(water >= 0 && (w->textures[water].flags & EW_SURF_TURB), "water texture");
    CHECK(b0 >= 0 && b1 >= 0 && w->textures[b0].anim_total == 2 && w->textures[b0].anim_next == b1 &&
              w->textures[b1].anim_next == b0,
          "button animation %d %d", b0, b1);
    /* the sky's front layer (left half) has clear (0) and cloud pixels */
    if (sky >= 0) {
        const ew_texture *t = &w->textures[sky];
        int clear = 0;
        for (int y = 0; y < t->height; y++)
            for (int x = 0; x < t->width / 2; x++) clear += t->mip[0][y * t->width + x] == 0;
        CHECK(clear > 0 && clear < t->width / 2 * t->height, "sky front layer: %d clear pixels", clear);
    }
    /* textures are not flat colour */
    for (int i = 0; i < BI_NUM_TEXTURES && i < w->numtextures; i++) {
        const ew_texture *t = &w->textures[i];
        int hist[256] = {0}, distinct = 0;
        for (int p = 0; p < t->width * t->height; p++) hist[t->mip[0][p]]++;
        for (int c = 0; c < 256; c++) distinct += hist[c] > 0;
        CHECK(distinct >= 6, "texture %s has %d colours", t->name, distinct);
    }
}

static void check_faces(const ew_world *w) {
    int bad_edges = -1, bad_tex = -1, bad_plane = -1, bad_wind = -1, bad_node = -1;
    int *owner = malloc(sizeof *owner * (size_t)w->numfaces);
    for (int i = 0; i < w->numfaces; i++) owner[i] = -1;
    /* every face belongs to exactly one node and lies on its plane */
    for (int n = 0; n < w->numnodes; n++) {
        const ew_node *nd = &w->nodes[n];
        for (int i = nd->firstface; i < nd->firstface + nd->numfaces; i++) {
            if (owner[i] >= 0 || w->faces[i].plane != nd->plane) bad_node = i;
            owner[i] = n;
            for (int k = 0; k < w->faces[i].numedges; k++) {
                double p[3];
                vert(w, ew_face_vertex(w, &w->faces[i], k), p);
                if (fabs(plane_dist(w, nd->plane, p)) > 0.01) bad_node = i;
                for (int q = 0; q < 3; q++)
                    if (p[q] < nd->mins[q] || p[q] > nd->maxs[q]) bad_node = i;
            }
        }
    }
    for (int i = 0; i < w->numfaces; i++) {
        const ew_face *f = &w->faces[i];
        if (owner[i] < 0) bad_node = i;
        if (f->numedges < 3) bad_edges = i;
        const ew_texture *t = &w->textures[w->texinfo[f->texinfo].texture];
        if ((t->flags & EW_SURF_MISSING) || !t->mip[0]) bad_tex = i;
        /* Newell normal: clockwise seen from the front points away from it */
        double nn[3] = {0, 0, 0};
        for (int k = 0; k < f->numedges; k++) {
            double a[3], b[3];
            vert(w, ew_face_vertex(w, f, k), a);
            vert(w, ew_face_vertex(w, f, (k + 1) % f->numedges), b);
            nn[0] += (a[1] - b[1]) * (a[2] + b[2]);
            nn[1] += (a[2] - b[2]) * (a[0] + b[0]);
            nn[2] += (a[0] - b[0]) * (a[1] + b[1]);
            if (fabs(plane_dist(w, f->plane, a)) > 0.01) bad_plane = i;
        }
        const float *pn = w->planes[f->plane].normal;
        double d = nn[0] * pn[0] + nn[1] * pn[1] + nn[2] * pn[2];
        if ((f->flags & EW_SURF_PLANEBACK) ? d <= 0 : d >= 0) bad_wind = i;
    }
    CHECK(bad_node < 0, "face %d is not on exactly one node's plane within its box", bad_node);
    CHECK(bad_edges < 0, "face %d has fewer than 3 edges", bad_edges);
    CHECK(bad_tex < 0, "face %d has a texture without data", bad_tex);
    CHECK(bad_plane < 0, "face %d has a vertex off its plane", bad_plane);
    CHECK(bad_wind < 0, "face %d is not wound clockwise", bad_wind);
    free(owner);

    /* watertight, no T-junctions: each edge used once each way */
    int *fwd = calloc((size_t)w->numedges, sizeof *fwd), *back = calloc((size_t)w->numedges, sizeof *back);
    for (int i = 0; i < w->numsurfedges; i++) {
        int se = w->surfedges[i];
        if (se >= 0) fwd[se]++; else back[-se]++;
    }
    int unshared = 0, overused = 0;
    for (int e = 1; e < w->numedges; e++) {
        unshared += fwd[e] != 1 || back[e] != 1;
        overused += fwd[e] > 1 || back[e] > 1;
    }
    CHECK(fwd[0] == 0 && back[0] == 0, "edge 0 is used");
    CHECK(overused == 0, "%d edges used twice in one direction", overused);
    CHECK(unshared == 0, "%d of %d edges are not shared by exactly two faces", unshared, w->numedges - 1);
    free(fwd), free(back);
}

static void check_leaves(const ew_world *w) {
    int kinds[4] = {0, 0, 0, 0}, bad_mark = -1, bad_box = -1;
    CHECK(w->leaves[0].contents == EW_CONTENTS_SOLID, "leaf 0 contents %d", w->leaves[0].contents);
    /* the world's leaves first (all with PVS rows), then six per submodel */
    CHECK(w->models[0].visleafs == w->numleaves - 1 - 6 * (w->nummodels - 1), "visleafs %d of %d (%d models)",
          w->models[0].visleafs, w->numleaves, w->nummodels);
    for (int l = 1; l < w->numleaves; l++) {
        const ew_leaf *lf = &w->leaves[l];
        kinds[0] += lf->contents == EW_CONTENTS_EMPTY;
        kinds[1] += lf->contents == EW_CONTENTS_WATER;
        kinds[2] += lf->contents == EW_CONTENTS_SKY;
        kinds[3] += lf->contents == EW_CONTENTS_SOLID;
        /* the box is inside its parents' boxes */
        for (int p = lf->parent; p >= 0; p = w->nodes[p].parent)
            for (int q = 0; q < 3; q++)
                if (lf->mins[q] < w->nodes[p].mins[q] || lf->maxs[q] > w->nodes[p].maxs[q]) bad_box = l;
        /* each listed face lies on a side of the leaf's box and looks into it */
        for (int m = 0; m < lf->nummarks; m++) {
            const ew_face *f = &w->faces[w->marksurfaces[lf->firstmark + m]];
            const ew_plane *pl = &w->planes[f->plane];
            int ax = pl->type, back = (f->flags & EW_SURF_PLANEBACK) != 0;
            if (ax > 2 || pl->dist != (back ? lf->maxs[ax] : lf->mins[ax])) bad_mark = l;
            for (int k = 0; k < f->numedges; k++) {
                double p[3];
                vert(w, ew_face_vertex(w, f, k), p);
                for (int q = 0; q < 3; q++)
                    if (p[q] < lf->mins[q] || p[q] > lf->maxs[q]) bad_mark = l;
            }
        }
        if (lf->contents == EW_CONTENTS_EMPTY && lf->nummarks == 0) bad_mark = l;
    }
    CHECK(kinds[0] > 0 && kinds[1] > 0 && kinds[2] > 0, "leaves: %d empty, %d water, %d sky", kinds[0],
          kinds[1], kinds[2]);
    CHECK(kinds[3] == 0, "%d solid leaves besides leaf 0", kinds[3]);
    CHECK(bad_box < 0, "leaf %d sticks out of a parent's box", bad_box);
    CHECK(bad_mark < 0, "leaf %d lists a face not bounding it (or none)", bad_mark);
    /* every face is listed by some leaf */
    uint8_t *listed = calloc((size_t)w->numfaces, 1);
    for (int i = 0; i < w->nummarksurfaces; i++) listed[w->marksurfaces[i]] = 1;
    int unlisted = 0;
    for (int i = 0; i < w->numfaces; i++) unlisted += !listed[i];
    CHECK(unlisted == 0, "%d faces in no leaf", unlisted);
    free(listed);
}

static void check_lighting(const ew_world *w) {
    int lit = 0, lo = 255, hi = 0, bad = -1, unlit_special = 1;
    for (int i = 0; i < w->numfaces; i++) {
        const ew_face *f = &w->faces[i];
        if (f->flags & (EW_SURF_SKY | EW_SURF_TURB)) {
            unlit_special &= f->lightofs < 0;
            continue;
        }
        if (f->lightofs < 0) { bad = i; continue; }
        lit++;
        int size = ((f->extents[0] >> 4) + 1) * ((f->extents[1] >> 4) + 1);
        if (f->extents[0] > 256 || f->extents[1] > 256 || f->lightofs + size > w->lightsize) bad = i;
        else
            for (int k = 0; k < size; k++) {
                int v = w->lighting[f->lightofs + k];
                lo = v < lo ? v : lo, hi = v > hi ? v : hi;
            }
    }
    CHECK(lit > 0 && bad < 0, "face %d: light map missing or out of range", bad);
    CHECK(unlit_special, "sky or water face with a light map");
    CHECK(hi - lo > 100, "light maps range only %d..%d", lo, hi);
}

static void check_pvs(const ew_world *w) {
    int n = w->models[0].visleafs + 1, bad = -1, hidden = 0, pairs = 0;
    uint8_t *vis = calloc((size_t)n * n, 1);
    for (int a = 1; a < n; a++) {
        if (pvs_row(w, a, vis + (size_t)a * n) < 0) bad = a;
        if (leaf_open(w, a) && (w->leaves[a].visofs < 0 || !vis[(size_t)a * n + a])) bad = a;
    }
    CHECK(bad < 0, "leaf %d: PVS row malformed or without itself", bad);
    for (int a = 1; a < n; a++)
        for (int b = 1; b < n; b++)
            if (leaf_open(w, a) && leaf_open(w, b)) {
                pairs++;
                hidden += !vis[(size_t)a * n + b];
            }
    CHECK(hidden > 0, "PVS is trivial: every leaf sees every leaf");
    printf("PVS: %d of %d open leaf pairs culled\n", hidden, pairs);

    /* conservative: random straight lines through open space never
     * connect two leaves that do not see each other */
    uint32_t s = 12345;
    int clear = 0, misses = 0;
    const ew_model *m = &w->models[0];
    for (int i = 0; i < 100000; i++) {
        double p[2][3];
        int l[2];
        for (int q = 0; q < 2; q++)
            for (;;) {
                for (int k = 0; k < 3; k++) {
                    s = s * 1103515245u + 12345u;
                    p[q][k] = m->mins[k] + (s >> 8) / 16777216.0 * (m->maxs[k] - m->mins[k]);
                }
                if (leaf_open(w, l[q] = point_leaf(w, p[q]))) break;
            }
        if (!segment_clear(w, m->headnode, p[0], p[1])) continue;
        clear++;
        if (!vis[(size_t)l[0] * n + l[1]] || !vis[(size_t)l[1] * n + l[0]]) {
            if (misses++ < 5)
                fprintf(stderr, "leaves %d and %d see each other along (%.1f %.1f %.1f)-(%.1f %.1f %.1f)\n",
                        l[0], l[1], p[0][0], p[0][1], p[0][2], p[1][0], p[1][1], p[1][2]);
        }
    }
    CHECK(clear > 1000 && misses == 0, "%d of %d clear lines join leaves the PVS separates", misses, clear);
    free(vis);
}

static void check_views(const ew_world *w) {
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(w, views);
    CHECK(nv == 5, "view set has %d views (player start x4 + intermission)", nv);
    int outside = -1;
    for (int i = 0; i < nv; i++) {
        double p[3] = {views[i].origin[0], views[i].origin[1], views[i].origin[2]};
        if (w->leaves[point_leaf(w, p)].contents != EW_CONTENTS_EMPTY) outside = i;
        /* room around the eye: nothing solid within 16 units */
        for (int k = 0; k < 6; k++) {
            double q[3] = {p[0], p[1], p[2]};
            q[k / 2] += k & 1 ? -16 : 16;
            if (!segment_clear(w, w->models[0].headnode, p, q)) outside = i;
        }
    }
    CHECK(outside < 0, "view %d is not in open space", outside);
    /* the player stands 24 units above a floor */
    if (nv > 0) {
        double eye[3] = {views[0].origin[0], views[0].origin[1], views[0].origin[2]};
        double feet[3] = {eye[0], eye[1], eye[2] - 22 - 24 + 1};
        double below[3] = {feet[0], feet[1], feet[2] - 2};
        CHECK(segment_clear(w, w->models[0].headnode, eye, feet) &&
                  !segment_clear(w, w->models[0].headnode, feet, below),
              "player start is not 24 units above a floor");
    }
    /* the lights of the entity lump are in open space */
    int lights = 0, bad = 0;
    for (const char *e = strchr(w->entities, '{'); e; e = strchr(e + 1, '{')) {
        const char *end = strchr(e, '}'), *cls = strstr(e, "\"classname\" \"light\""),
                   *o = strstr(e, "\"origin\"");
        double p[3];
        if (!end || !cls || cls > end || !o || o > end) continue;
        if (sscanf(o, "\"origin\" \"%lf %lf %lf\"", &p[0], &p[1], &p[2]) != 3) continue;
        lights++;
        bad += w->leaves[point_leaf(w, p)].contents != EW_CONTENTS_EMPTY;
    }
    CHECK(lights >= 3 && bad == 0, "%d lights, %d not in open space", lights, bad);
}

/* The door: submodel *1, a box of six faces with a tree of its own. */
static void check_submodels(const ew_world *w) {
    CHECK(w->nummodels == 2, "%d models (the world and the door)", w->nummodels);
    if (w->nummodels < 2) return;
    const ew_model *m0 = &w->models[0], *d = &w->models[1];
    CHECK(m0->firstface == 0 && d->firstface == m0->numfaces && d->numfaces == 6 &&
              d->firstface + d->numfaces == w->numfaces,
          "faces: world %d+%d, door %d+%d of %d", m0->firstface, m0->numfaces, d->firstface, d->numfaces,
          w->numfaces);
    CHECK(d->visleafs == 0 && d->origin[0] == 0 && d->origin[1] == 0 && d->origin[2] == 0,
          "door: visleafs %d, origin %g %g %g", d->visleafs, d->origin[0], d->origin[1], d->origin[2]);
    double size[3];
    for (int k = 0; k < 3; k++) size[k] = d->maxs[k] - d->mins[k];
    CHECK(size[0] >= 4 && size[1] >= 32 && size[2] >= 64, "door box %g x %g x %g", size[0], size[1], size[2]);

    /* the tree: a chain of six nodes, each holding one face on its plane,
     * with the solid leaf inside and an empty leaf outside listing that face */
    int stack[16], sp = 0, nodes = 0, bad = -1, used[6] = {0, 0, 0, 0, 0, 0};
    stack[sp++] = d->headnode;
    while (sp > 0 && nodes < 16) {
        int n = stack[--sp];
        const ew_node *nd = &w->nodes[n];
        nodes++;
        if (nd->numfaces != 1 || nd->firstface < d->firstface || nd->firstface >= d->firstface + 6) {
            bad = n;
            continue;
        }
        int f = nd->firstface;
        used[f - d->firstface]++;
        for (int k = 0; k < 3; k++)
            if (nd->mins[k] > d->mins[k] || nd->maxs[k] < d->maxs[k]) bad = n;
        int solid = 0, empty = 0;
        for (int c = 0; c < 2; c++) {
            int ch = nd->children[c];
            if (ch >= 0) {
                if (sp < 16) stack[sp++] = ch;
                continue;
            }
            const ew_leaf *lf = &w->leaves[-1 - ch];
            if (-1 - ch == 0) { solid++; continue; }
            if (-1 - ch <= m0->visleafs || lf->contents != EW_CONTENTS_EMPTY || lf->visofs != -1 ||
                lf->nummarks != 1 || w->marksurfaces[lf->firstmark] != f)
                bad = n;
            /* the empty child is the side the face looks into */
            int back = (w->faces[f].flags & EW_SURF_PLANEBACK) != 0;
            if (c != back) bad = n;
            empty++;
        }
        if (empty != 1) bad = n;
        (void)solid;
    }
    CHECK(nodes == 6 && bad < 0, "door tree: %d nodes, node %d malformed", nodes, bad);
    for (int i = 0; i < 6; i++) CHECK(used[i] == 1, "door face %d is on %d nodes", i, used[i]);

    /* inside is solid; just outside each face is an empty leaf listing it */
    double centre[3];
    for (int k = 0; k < 3; k++) centre[k] = (d->mins[k] + d->maxs[k]) / 2;
    CHECK(point_leaf_in(w, 1, centre) == 0, "the door's inside is not solid");
    for (int i = 0; i < 6; i++) {
        const ew_face *f = &w->faces[d->firstface + i];
        const ew_plane *pl = &w->planes[f->plane];
        double sign = (f->flags & EW_SURF_PLANEBACK) ? -1 : 1, p[3] = {0, 0, 0};
        for (int k = 0; k < f->numedges; k++) {
            double q[3];
            vert(w, ew_face_vertex(w, f, k), q);
            for (int j = 0; j < 3; j++) p[j] += q[j] / f->numedges;
        }
        for (int j = 0; j < 3; j++) p[j] += sign * pl->normal[j];
        int l = point_leaf_in(w, 1, p);
        CHECK(l > m0->visleafs && w->leaves[l].contents == EW_CONTENTS_EMPTY && w->leaves[l].nummarks == 1 &&
                  w->marksurfaces[w->leaves[l].firstmark] == d->firstface + i,
              "outside door face %d: leaf %d", i, l);
        /* its own texture, light-mapped */
        const ew_texture *t = &w->textures[w->texinfo[f->texinfo].texture];
        CHECK(!strcmp(t->name, "door") && f->lightofs >= 0 && !(f->flags & (EW_SURF_SKY | EW_SURF_TURB)),
              "door face %d: texture %s, light %d", i, t->name, f->lightofs);
        CHECK(f->numedges == 4, "door face %d has %d edges", i, f->numedges);
    }

    /* its edges are its own: no world face uses them */
    uint8_t *world_edge = calloc((size_t)w->numedges, 1);
    for (int i = m0->firstface; i < m0->firstface + m0->numfaces; i++)
        for (int k = 0; k < w->faces[i].numedges; k++) {
            int se = w->surfedges[w->faces[i].firstedge + k];
            world_edge[se < 0 ? -se : se] = 1;
        }
    int shared = 0;
    for (int i = d->firstface; i < d->firstface + d->numfaces; i++)
        for (int k = 0; k < w->faces[i].numedges; k++) {
            int se = w->surfedges[w->faces[i].firstedge + k];
            shared += world_edge[se < 0 ? -se : se];
        }
    CHECK(shared == 0, "%d door edges are shared with the world", shared);
    free(world_edge);

    /* it stands in open space (in part: it has slid half into the wall),
     * never in water or sky */
    int open = 0, solid = 0, other = 0;
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 9; j++)
            for (int k = 0; k < 13; k++) {
                double p[3] = {d->mins[0] + (i + 0.5) * size[0] / 5, d->mins[1] + (j + 0.5) * size[1] / 9,
                               d->mins[2] + (k + 0.5) * size[2] / 13};
                int c = w->leaves[point_leaf(w, p)].contents;
                open += c == EW_CONTENTS_EMPTY, solid += c == EW_CONTENTS_SOLID;
                other += c != EW_CONTENTS_EMPTY && c != EW_CONTENTS_SOLID;
            }
    CHECK(open >= (open + solid) * 2 / 5 && other == 0, "door: %d samples in open space, %d solid, %d other",
          open, solid, other);

    /* the entity lump spawns it */
    const char *e = strstr(w->entities, "\"classname\" \"func_door\"");
    const char *end = e ? strchr(e, '}') : NULL, *model = e ? strstr(e, "\"model\" \"*1\"") : NULL;
    CHECK(e && end && model && model < end, "no func_door with model *1 in the entity lump");
}

/* Union-find over the model's vertices, for its parts. */
static int find_root(int *parent, int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

static int cmp_u64(const void *a, const void *b) {
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* The triangle model: deterministic, loads, animates, closed and wound outwards. */
static void check_model(void) {
    uint8_t *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    ew_error err = {{0}};
    double t0 = cpu_ms();
    int rc = bi_model_generate(&a, &na, &err);
    double t1 = cpu_ms();
    CHECK(rc == 0, "model: %s", err.msg);
    if (rc) return;
    printf("model: %zu bytes in %.1f ms of CPU\n", na, t1 - t0);
    CHECK(bi_model_generate(&b, &nb, &err) == 0 && nb == na && !memcmp(a, b, na), "two model generations differ");
    free(b);
    ew_mdl *m = ew_mdl_load(a, na, "builtin/bearer.mdl", &err);
    CHECK(m != NULL, "ew_mdl_load: %s", err.msg);
    free(a);
    if (!m) return;
    printf("model: %d vertices, %d triangles, %d poses, skin %dx%d\n", m->numverts, m->numtris, m->numposes,
           m->skinwidth, m->skinheight);
    CHECK(m->numskins == 1 && m->numskinimages == 1 && m->skinwidth == BI_MODEL_SKIN_W &&
              m->skinheight == BI_MODEL_SKIN_H,
          "skins: %d (%d images) of %dx%d", m->numskins, m->numskinimages, m->skinwidth, m->skinheight);
    CHECK(m->numverts >= 100 && m->numverts <= 400 && m->numtris >= 300 && m->numtris <= 800,
          "%d vertices, %d triangles", m->numverts, m->numtris);
    CHECK(m->numframes == 1 && m->numposes == BI_MODEL_POSES && m->frames[0].count == BI_MODEL_POSES &&
              m->frames[0].times != NULL,
          "frames %d, poses %d", m->numframes, m->numposes);
    if (m->frames[0].times)
        for (int i = 0; i < m->frames[0].count; i++)
            CHECK(fabsf(m->frames[0].times[i] - BI_MODEL_INTERVAL * (float)(i + 1)) < 1e-5f, "pose %d ends at %g", i,
                  (double)m->frames[0].times[i]);
    /* time picks each pose in turn, and the cycle repeats */
    for (int i = 0; i < BI_MODEL_POSES; i++)
        CHECK(ew_mdl_anim_pick(&m->frames[0], (i + 0.5) * BI_MODEL_INTERVAL) == i &&
                  ew_mdl_anim_pick(&m->frames[0], (i + 0.5 + BI_MODEL_POSES) * BI_MODEL_INTERVAL) == i,
              "time does not pick pose %d", i);

    /* closed and consistently wound: every directed edge once, its reverse once */
    int nt = m->numtris, nv = m->numverts;
    uint64_t *e = malloc(sizeof *e * (size_t)nt * 3);
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            e[t * 3 + k] = (uint64_t)m->tris[t].v[k] << 32 | (uint32_t)m->tris[t].v[(k + 1) % 3];
    qsort(e, (size_t)nt * 3, sizeof *e, cmp_u64);
    int dup = 0, open = 0;
    for (int i = 0; i < nt * 3; i++) {
        if (i > 0 && e[i] == e[i - 1]) dup++;
        uint64_t rev = (e[i] & 0xffffffffu) << 32 | e[i] >> 32;
        if (!bsearch(&rev, e, (size_t)nt * 3, sizeof *e, cmp_u64)) open++;
    }
    CHECK(dup == 0 && open == 0, "%d edges used twice one way, %d without a neighbour", dup, open);
    free(e);

    /* every part encloses a positive volume in every pose (outward winding:
     * the outward normal of a, b, c is (c - a) x (b - a)) */
    int *parent = malloc(sizeof *parent * (size_t)nv);
    for (int i = 0; i < nv; i++) parent[i] = i;
    for (int t = 0; t < nt; t++)
        for (int k = 1; k < 3; k++) {
            int x = find_root(parent, m->tris[t].v[0]), y = find_root(parent, m->tris[t].v[k]);
            if (x != y) parent[x] = y;
        }
    int parts = 0;
    for (int i = 0; i < nv; i++) parts += find_root(parent, i) == i;
    CHECK(parts == 4, "%d parts (body, two arms, lantern)", parts);
    double *vol = malloc(sizeof *vol * (size_t)nv);
    int inverted = 0, moved = 0;
    for (int p = 0; p < m->numposes; p++) {
        const ew_mdl_pose *pose = &m->poses[p];
        for (int i = 0; i < nv; i++) vol[i] = 0;
        for (int t = 0; t < nt; t++) {
            double q[3][3];
            for (int k = 0; k < 3; k++)
                for (int j = 0; j < 3; j++) q[k][j] = pose->verts[m->tris[t].v[k]].v[j] * m->scale[j] + m->translate[j];
            double e1[3], e2[3];
            for (int j = 0; j < 3; j++) e1[j] = q[1][j] - q[0][j], e2[j] = q[2][j] - q[0][j];
            double n[3] = {e2[1] * e1[2] - e2[2] * e1[1], e2[2] * e1[0] - e2[0] * e1[2], e2[0] * e1[1] - e2[1] * e1[0]};
            vol[find_root(parent, m->tris[t].v[0])] += (q[0][0] * n[0] + q[0][1] * n[1] + q[0][2] * n[2]) / 6;
        }
        for (int i = 0; i < nv; i++)
            if (find_root(parent, i) == i && !(vol[i] > 1)) inverted++;
        /* it floats: its lowest point is above its origin */
        CHECK(pose->mins[2] > 0 && pose->maxs[2] > 55 && pose->maxs[2] < 90, "pose %d spans z %g..%g", p,
              (double)pose->mins[2], (double)pose->maxs[2]);
        if (p > 0)
            for (int i = 0; i < nv; i++) moved += memcmp(pose->verts[i].v, m->poses[0].verts[i].v, 3) != 0;
    }
    CHECK(inverted == 0, "%d parts enclose no positive volume (wound inwards)", inverted);
    CHECK(moved > nv, "the poses hardly differ (%d vertex moves)", moved);
    free(vol), free(parent);

    /* the skin's two halves: back triangles use the back half or the seam */
    int fronts = 0, backs = 0, onseam = 0, misuse = 0;
    for (int i = 0; i < nv; i++) onseam += m->st[i].onseam != 0;
    for (int t = 0; t < nt; t++) {
        if (m->tris[t].facesfront) { fronts++; continue; }
        backs++;
        for (int k = 0; k < 3; k++) {
            const ew_mdl_st *st = &m->st[m->tris[t].v[k]];
            misuse += !st->onseam && st->s < m->skinwidth / 2;
        }
    }
    CHECK(fronts > 0 && backs > 0 && onseam > 0 && misuse == 0,
          "%d front, %d back triangles, %d onseam vertices, %d back uses of the front half", fronts, backs, onseam,
          misuse);
    int hist[256] = {0}, distinct = 0, fullbright = 0;
    for (int i = 0; i < m->skinwidth * m->skinheight; i++) hist[m->skinpixels[i]]++;
    for (int c = 0; c < 256; c++) distinct += hist[c] > 0, fullbright += c >= 224 ? hist[c] : 0;
    CHECK(distinct >= 24 && fullbright > 0, "skin: %d colours, %d fullbright texels", distinct, fullbright);
    ew_mdl_free(m);
}

int main(void) {
    uint8_t *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    static uint8_t pal2[768], cmap2[EW_COLORMAP_SIZE];
    ew_error err = {{0}};
    double t0 = cpu_ms();
    int rc = ew_builtin_generate(&a, &na, pal, cmap, &err);
    double t1 = cpu_ms();
    CHECK(rc == 0, "generate: %s", err.msg);
    if (rc) return ew_t_finish();
    printf("generated %zu bytes in %.1f ms of CPU\n", na, t1 - t0);
    CHECK(ew_builtin_generate(&b, &nb, pal2, cmap2, &err) == 0, "second generate: %s", err.msg);
    CHECK(b && na == nb && !memcmp(a, b, na), "two generations differ");
    CHECK(!memcmp(pal, pal2, sizeof pal) && !memcmp(cmap, cmap2, sizeof cmap), "palette/colormap differ");
    free(b);

    const char *dump = getenv("EW_BUILTIN_DUMP");
    if (dump && *dump) {
        FILE *f = fopen(dump, "wb");
        CHECK(f && fwrite(a, 1, na, f) == na, "cannot write %s", dump);
        if (f) fclose(f);
    }

    check_header(a, na);
    check_palette_colormap();
    ew_world *w = ew_world_create(a, na, "builtin", &err);
    CHECK(w != NULL, "load: %s", err.msg);
    free(a);
    if (w) {
        ew_world_info info;
        ew_world_get_info(w, &info);
        printf("%d faces, %d leaves, %d nodes, %d textures, %d edges, %d vertices\n", info.faces,
               info.leaves, info.nodes, info.textures, w->numedges, w->numverts);
        check_textures(w);
        check_faces(w);
        check_leaves(w);
        check_lighting(w);
        check_pvs(w);
        check_views(w);
        check_submodels(w);
        ew_world_destroy(w);
    }

    check_model();

    ew_assets *as = NULL;
    CHECK((as = ew_assets_create_builtin(&err)) != NULL && as->world, "ew_assets_create_builtin: %s", err.msg);
    CHECK(!memcmp(as->palette, pal, sizeof pal) && !memcmp(as->colormap, cmap, sizeof cmap),
          "assets palette/colormap differ from the generated ones");
    ew_assets_destroy(as);
    return ew_t_finish();
}
