/* The screen polygons of the frame's surfaces (internal), for the methods
 * that need each surface's shape rather than its edges: the beam tree
 * (hsr/beamtree.c) and the raycast (hsr/raycast.c).  Both keep the edge
 * list's front end unchanged (ew_edge_face / ew_edge_poly make the surfaces
 * the back end draws) and record, serially as faces arrive, each new
 * surface's clipped, projected polygon, the surfaces in BSP order, and the
 * world face -> surface map of the frame.
 *
 * Every polygon winds so that its inside is a*x + b*y + c > 0 for each of
 * its edge lines.  Vertices are snapped to 1/1024 pixel, so a line's
 * coefficients, computed from its two ends, are exact, and so is the test
 * of a pixel centre against it: edges on one line (shared, or meeting at a
 * T-junction) agree on every pixel, and a pixel centre on the line goes by
 * ew_line_in's tie rule to exactly one side.  inv scales the test to a
 * distance in pixels for the geometry. */
#ifndef EW_HSR_SURF_POLY_H
#define EW_HSR_SURF_POLY_H

#include "hsr/hsr.h"

/* grid: made from two points of the 1/1024 grid (or axis-aligned through
 * one): a, b, c exact, so two such lines can be compared exactly. */
typedef struct ew_line { double a, b, c, inv; int grid; } ew_line;

/* A vertex and the line of the edge leaving it. */
typedef struct ew_spoly_vert {
    double  x, y;
    ew_line l;
} ew_spoly_vert;

typedef struct ew_spoly {
    int   first, n;              /* into verts; n 0: no polygon */
    int   eplane0, neplanes;     /* world faces: into eplanes */
    float x0, y0, x1, y1;        /* bounding box, screen units */
} ew_spoly;

typedef struct ew_spolys {
    ew_spoly      *polys;  int cap_polys;          /* per surface of the edge list */
    ew_spoly_vert *verts;  int nverts, cap_verts;
    int           *order;  int norder, cap_order;  /* surfaces by BSP key, nearest first (stable) */
    int           *face_surf, *face_frame;         /* world face -> its surface, when face_frame is this frame */
    /* World faces' edges as planes through them, perpendicular to the face,
     * normals inward (x, y, z, dist): the raycast's point-in-face test. */
    float        (*eplanes)[4]; int neplanes, cap_eplanes;
    int            nfaces, frame, failed;          /* failed: out of memory this frame */
} ew_spolys;

/* The pixel centre (x, y) is inside the line's half-plane; on the line,
 * the side its normal points right (or down when vertical) wins, so a
 * line and its exact negation never both take a pixel. */
static inline int ew_line_in(const ew_line *l, double x, double rowc) {
    double f = l->a * x + rowc;  /* rowc: l->b * y + l->c, the same for the whole row */
    return f > 0 || (f == 0 && (l->a > 0 || (l->a == 0 && l->b > 0)));
}
static inline double ew_line_row(const ew_line *l, double y) { return l->b * y + l->c; }
/* Exact negation: the same line, the other side inside. */
static inline ew_line ew_line_neg(ew_line l) { return (ew_line){-l.a, -l.b, -l.c, l.inv, l.grid}; }
/* Signed distance in pixels (positive inside). */
static inline double ew_line_dist(const ew_line *l, double x, double y) { return (l->a * x + l->b * y + l->c) * l->inv; }
/* The line through (x0, y0) -> (x1, y1), inside where a polygon wound
 * that way (positive sum of x_i y_j - x_j y_i, the winding surf_poly.c
 * gives every polygon) lies; 0 if degenerate. */
int ew_line_through(double x0, double y0, double x1, double y1, ew_line *out);
/* The line (a, b, c) with its inv; 0 if a and b are both 0. */
int ew_line_norm(double a, double b, double c, ew_line *out);

/* The frame's polygons (c->spolys, made on first use), begun with the
 * edge list's begin; NULL when out of memory. */
ew_spolys *ew_spolys_begin(ew_hsr_ctx *c);
/* The edge list's face / poly, then the new surface's polygon recorded. */
void ew_spolys_face(ew_hsr_ctx *c, int face, int clipflags, int key);
void ew_spolys_poly(ew_hsr_ctx *c, float (*verts)[3], int n, int fi, const ew_view *v, int key);
size_t ew_spolys_memory(const ew_hsr_ctx *c);
void ew_spolys_free(ew_spolys *sp);

#endif
