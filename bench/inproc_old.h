/* bench/inproc_old.h: side A of bench/inproc.c for a revision from before
 * the public calls inproc.c makes (ew_assets_create, ew_set_classic), such
 * as cde885f, the many-core work's baseline.  bench/inproc_old.c
 * is built against that revision's own header and library; only the plain
 * C types below cross between the two. */
#ifndef EW_INPROC_OLD_H
#define EW_INPROC_OLD_H

#include <stdint.h>

typedef struct inproc_old inproc_old;
/* The map with its entities (or world only), a renderer of w x h on
 * threads threads; NULL and a message in err on failure. */
inproc_old *inproc_old_open(const char *map, const char *data, int w, int h, int threads, int entities,
                            char *err, int errsize);
void        inproc_old_close(inproc_old *o);
int         inproc_old_views(const inproc_old *o);
/* Renders view v; ms gets the frame's front, scan, draw and models times
 * from its stats.  0, or -1. */
int            inproc_old_render(inproc_old *o, int v, double ms[4]);
const uint8_t *inproc_old_pixels(const inproc_old *o);

#endif
