/* The reference method's own state and its compositing (internal,
 * hsr/ref_compose.c; the method in hsr/reference.c): kept in the context
 * (ew_hsr_ctx.ref) from frame to frame.  Named after the compositing, the
 * lower of the two files: the method calls it, not the other way. */
#ifndef EW_HSR_REF_COMPOSE_H
#define EW_HSR_REF_COMPOSE_H

#include "hsr/hsr.h"

typedef struct ew_ref_poly ew_ref_poly;
typedef struct ew_ref {
    ew_ref_poly *polys; int npolys, cap;         /* the polygons it fills band by band */
    int         *poly_of;  size_t npoly_of;      /* two-pass lighting: each pixel's polygon */
    ew_ref_compose *compose;                     /* its own compositing (hsr/ref_compose.c) */
} ew_ref;

/* hsr/ref_compose.c: begin (serial, a frame's start) returns the per-pixel
 * buffer of world faces the reference fills (NULL out of memory: no sky is
 * found); faces is that buffer, or NULL; ids_out copies rows [y0, y1) of
 * it to the caller's face ids. */
int *ew_ref_compose_begin(ew_hsr_ctx *c);
int *ew_ref_compose_faces(const ew_hsr_ctx *c);
void ew_ref_compose_ids_out(const ew_hsr_ctx *c, int *ids, int y0, int y1);
void ew_ref_compose_free(ew_ref_compose *rc);

#endif
