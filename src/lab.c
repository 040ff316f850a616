/*
 * lab.c - the lab's calls (edgewise_lab.h) that read the renderer's and the
 * world's insides for the command: the frame's probes and budgets, the
 * world tree's leaves and planes, the stress hall, the benchmark views'
 * roles.  Part of the assembly layer, beside renderer.c: the one place
 * outside the stages that may look into struct ew_renderer and ew_world,
 * so that cli/ and app/ need nothing but the public headers.
 */
#include "edgewise_lab.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "asset/entity_lump.h"
#include "scene/bench_views.h"
#include "ew_util.h"
#include "ew_world.h"
#include "mapgen/mapgen.h"
#include "renderer.h"

void ew_frame_lab_stats(const ew_renderer *r, ew_lab_stats *lab) {
    if (!lab) return;
    if (!r) {
        memset(lab, 0, sizeof *lab);
        return;
    }
    *lab = r->lab;
}

double ew_clock_ms(void) { return ew_now_ms(); }

int ew_frame_budget_full(const ew_renderer *r) {
    if (!r) return 0;
    if (r->el.nsurfs >= r->el.max_surfs || r->el.nedges + EW_MAX_POLY + 4 > r->el.max_edges) return 1;
    for (int i = 0; i < r->sched.nbands; i++)
        if (ew_band_budget_full(&r->sched.bands[i])) return 1;
    return 0;
}

/* ---- the world tree -------------------------------------------------------- */

int ew_world_point_leaf(const ew_world *w, const float p[3]) {
    if (!w || w->nummodels < 1) return 0;
    return ew_point_leaf(w, w->models[0].headnode, p);
}

int ew_world_leaf_contents(const ew_world *w, int leaf) {
    if (!w || leaf < 0 || leaf >= w->numleaves) return EW_CONTENTS_SOLID;
    return w->leaves[leaf].contents;
}

/* Open to a camera: sky volumes are closed to the player as solid is. */
static int open_contents(int c) { return c != EW_CONTENTS_SOLID && c != EW_CONTENTS_SKY; }

int ew_world_open_leaves(const ew_world *w, int *leaves) {
    if (!w || w->nummodels < 1) return 0;
    int n = 0, head = w->models[0].headnode;
    for (int i = 1; i < w->numleaves; i++) {
        if (!open_contents(w->leaves[i].contents)) continue;
        int node = w->leaves[i].parent, top = -1;
        for (int steps = 0; node >= 0 && steps <= w->numnodes; steps++) top = node, node = w->nodes[node].parent;
        if (top != head) continue;
        if (leaves) leaves[n] = i;
        n++;
    }
    return n;
}

int ew_world_leaf_bounds(const ew_world *w, int leaf, float mins[3], float maxs[3]) {
    if (!w || leaf < 0 || leaf >= w->numleaves) return -1;
    for (int k = 0; k < 3; k++) mins[k] = w->leaves[leaf].mins[k], maxs[k] = w->leaves[leaf].maxs[k];
    return 0;
}

static float plane_dist(const ew_plane *pl, const float p[3]) {
    return p[0] * pl->normal[0] + p[1] * pl->normal[1] + p[2] * pl->normal[2] - pl->dist;
}

float ew_world_leaf_clearance(const ew_world *w, int leaf, const float p[3]) {
    float best = FLT_MAX;
    if (!w || leaf < 0 || leaf >= w->numleaves) return best;
    int steps = 0;
    for (int n = w->leaves[leaf].parent; n >= 0 && steps++ <= w->numnodes; n = w->nodes[n].parent) {
        float d = fabsf(plane_dist(&w->planes[w->nodes[n].plane], p));
        if (d < best) best = d;
    }
    return best;
}

float ew_world_plane_clearance(const ew_world *w, const float p[3]) {
    float best = FLT_MAX;
    if (!w) return best;
    for (int i = 0; i < w->numplanes; i++) {
        float d = fabsf(plane_dist(&w->planes[i], p));
        if (d < best) best = d;
    }
    return best;
}

/* ---- maps and views ---------------------------------------------------------- */

_Static_assert(EW_STRESS_MAX_DETAIL == 26000, "edgewise_lab.h and mapgen.h agree on the stress hall's detail");

ew_assets *ew_assets_create_stress(int detail, const char *name, ew_error *err) {
    if (detail < 0 || detail > EW_STRESS_MAX_DETAIL) {
        ew_fail(err, "%s: the detail must be a whole number from 0 to %d", name ? name : "builtin",
                     EW_STRESS_MAX_DETAIL);
        return NULL;
    }
    ew_assets *a = calloc(1, sizeof *a);
    uint8_t *bsp = NULL;
    size_t size = 0;
    if (!a) {
        ew_fail(err, "builtin: out of memory");
        return NULL;
    }
    if (ew_stress_generate(detail, &bsp, &size, a->palette, a->colormap, err) == 0)
        a->world = ew_world_create(bsp, size, name ? name : "builtin", err);
    free(bsp);
    if (!a->world) {
        free(a);
        return NULL;
    }
    return a;
}

void ew_benchmark_view_roles(const ew_world *w, int *inter, int *start) {
    *inter = *start = -1;
    const char *text = w ? ew_world_entities(w) : NULL;
    if (!text) return;
    ew_entities ents;
    ew_entities_parse(text, strlen(text), &ents, NULL);
    int n = 0;
    for (int i = 0; i < ents.count && n < EW_MAX_VIEWS; i++) {
        const char *cls = ew_entity_get(&ents.ents[i], "classname");
        if (!cls) continue;
        if (!strncmp(cls, "info_player", 11)) {
            if (*start < 0) *start = n;
            n += 4;
        } else if (!strcmp(cls, "info_intermission")) {
            if (*inter < 0) *inter = n;
            n++;
        }
    }
    ew_entities_free(&ents);
}

/* ---- the row profile (bench --bands) ---- */

int ew_set_row_profile(ew_renderer *r, int on) {
    r->sched.profile_rows = on != 0;
    return ew_set_threads(r, r->sched.nthreads > 0 ? r->sched.nthreads : 1);
}

int ew_frame_row_ms(const ew_renderer *r, float *scan_ms, float *draw_ms, int n) {
    for (int i = 0; scan_ms && i < r->sched.nbands; i++) {
        const ew_band *b = &r->sched.bands[i];
        float per_row = (float)(b->ms / (b->y1 - b->y0));
        for (int v = b->y0; v < b->y1 && v < n; v++) scan_ms[v] = per_row;
    }
    for (int i = 0; draw_ms && i < r->sched.nitems; i++) {
        const ew_draw_item *it = &r->sched.items[i];
        float per_row = it->y1 > it->y0 ? (float)(it->ms / (it->y1 - it->y0)) : 0;
        for (int v = it->y0; v < it->y1 && v < n; v++) draw_ms[v] = per_row;
    }
    return r->f.target.height;
}

/* ---- cameras and light for choosing and checking pictures ---- */

int ew_entity_cameras(const ew_world *w, ew_camera *cams, int *kinds, int max) {
    const char *text = w ? ew_world_entities(w) : NULL;
    if (!text || !cams || max <= 0) return 0;
    ew_entities ents;
    ew_entities_parse(text, strlen(text), &ents, NULL);  /* keep what parsed */
    int n = 0;
    for (int i = 0; i < ents.count && n < max; i++) {
        int inter;
        if (!ew_entity_camera(&ents.ents[i], &cams[n], &inter)) continue;
        if (kinds) kinds[n] = inter;
        n++;
    }
    ew_entities_free(&ents);
    return n;
}

double ew_world_light_mean(const ew_world *w) {
    if (!w || !w->lighting || w->lightsize <= 0) return -1;
    double sum = 0;
    for (int i = 0; i < w->lightsize; i++) sum += w->lighting[i];
    return sum / w->lightsize;
}

int ew_world_has_rgb_light(const ew_world *w) { return w && w->rgblight != NULL; }
