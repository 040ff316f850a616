/* The front end's state (world/front.h): made with the renderer, freed with
 * it.  Apart from the walk (bsp_walk.c, edges.c) and the parallel phases
 * (front_par.c), so that neither schedule's file calls the other's. */
#include "world/front.h"

int ew_front_init(ew_front *fr, ew_frame *f, ew_marks *marks, ew_edge_list *el, int width, int height) {
    *fr = (ew_front){.f = f, .marks = marks, .el = el};
    return ew_occ_init(&fr->occ, width, height);
}

void ew_front_free(ew_front *fr) {
    ew_front_par_free(fr->par);
    ew_occ_free(&fr->occ);
    fr->par = NULL;
}
