/* Maps from the project's map writer, for tests (header-only). */
#ifndef EW_TEST_MAPGEN_UTIL_H
#define EW_TEST_MAPGEN_UTIL_H

#include "mapgen.h"
#include "util.h"

#include <stdlib.h>

typedef struct gen {
    uint8_t *bsp, *lit;
    size_t   size, lit_size;
} gen;

/* The built-in level written with options o (its palette and colormap into pal, cmap). */
static inline gen generate_map(const ew_mapgen_options *o, uint8_t pal[768], uint8_t cmap[EW_COLORMAP_SIZE]) {
    gen g = {0};
    ew_error err = {""};
    int rc = ew_builtin_generate_ex(o, &g.bsp, &g.size, pal, cmap, &g.lit, &g.lit_size, &err);
    CHECK(rc == 0, "generate: %s", err.msg);
    return g;
}
static inline void gen_free(gen *g) { free(g->bsp), free(g->lit); }

#endif
