/* The hidden-surface methods by ew_hsr_method: names for every one, the
 * implementation where this build has it (hsr/hsr.h). */
#include "hsr/ref_compose.h"
#include "hsr/surf_poly.h"

#include <stdlib.h>
#include <string.h>

static const char *const names[EW_HSR_COUNT] = {
    [EW_HSR_EDGE] = "edge",         [EW_HSR_REFERENCE] = "reference", [EW_HSR_EDGE_Z] = "edge-z",
    [EW_HSR_SPANS] = "spans",       [EW_HSR_ZBUFFER] = "zbuffer",     [EW_HSR_PAINTER] = "painter",
    [EW_HSR_DRAWBUFFER] = "drawbuffer", [EW_HSR_BEAMTREE] = "beamtree", [EW_HSR_RAYCAST] = "raycast",
};

static const ew_hsr *const methods[EW_HSR_COUNT] = {
    [EW_HSR_EDGE] = &ew_hsr_edge,
    [EW_HSR_REFERENCE] = &ew_hsr_reference,
    [EW_HSR_EDGE_Z] = &ew_hsr_edge_z,
    [EW_HSR_SPANS] = &ew_hsr_spans,
    [EW_HSR_ZBUFFER] = &ew_hsr_zbuffer,
    [EW_HSR_PAINTER] = &ew_hsr_painter,
    [EW_HSR_DRAWBUFFER] = &ew_hsr_drawbuffer,
    [EW_HSR_BEAMTREE] = &ew_hsr_beamtree,
    [EW_HSR_RAYCAST] = &ew_hsr_raycast,
};

const ew_hsr *ew_hsr_get(int method) { return method >= 0 && method < EW_HSR_COUNT ? methods[method] : NULL; }

const char *ew_hsr_name(ew_hsr_method method) {
    return (int)method >= 0 && method < EW_HSR_COUNT ? names[method] : NULL;
}

int ew_hsr_from_name(const char *name) {
    for (int m = 0; name && m < EW_HSR_COUNT; m++)
        if (strcmp(name, names[m]) == 0) return m;
    return -1;
}

const char *ew_hsr_counter_name(ew_hsr_method method, int i) {
    const ew_hsr *h = ew_hsr_get((int)method);
    return h && i >= 0 && i < EW_HSR_COUNTERS ? h->counters[i] : NULL;
}

int ew_hsr_available(ew_hsr_method method) { return ew_hsr_get((int)method) != NULL; }

void ew_hsr_ctx_free(ew_hsr_ctx *c) {
    ew_spolys_free(c->spolys);
    c->spolys = NULL;
    if (c->ref) free(c->ref->polys), free(c->ref->poly_of), ew_ref_compose_free(c->ref->compose);
    free(c->ref);
    c->ref = NULL;
}
