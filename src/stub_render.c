/* TEMPORARY stub: replaced by the renderer. */
#include "ew_util.h"
ew_renderer *ew_renderer_create(const ew_world *w, const uint8_t p[768], const uint8_t c[EW_COLORMAP_SIZE], int wi, int he, ew_error *e) { (void)w; (void)p; (void)c; (void)wi; (void)he; ew_fail(e, "renderer: not implemented"); return NULL; }
void ew_renderer_free(ew_renderer *r) { (void)r; }
int ew_render(ew_renderer *r, const ew_camera *c, ew_stats *s) { (void)r; (void)c; (void)s; return -1; }
int ew_frame_width(const ew_renderer *r) { (void)r; return 0; }
int ew_frame_height(const ew_renderer *r) { (void)r; return 0; }
const uint8_t *ew_frame_pixels(const ew_renderer *r) { (void)r; return NULL; }
const float *ew_frame_zbuffer(const ew_renderer *r) { (void)r; return NULL; }
void ew_set_lightstyle(ew_renderer *r, int s, int v) { (void)r; (void)s; (void)v; }
void ew_enable_face_ids(ew_renderer *r, int on) { (void)r; (void)on; }
const int *ew_frame_face_ids(const ew_renderer *r) { (void)r; return NULL; }
int ew_render_reference(ew_renderer *r, const ew_camera *c, uint8_t *p, int *f, ew_error *e) { (void)r; (void)c; (void)p; (void)f; return ew_fail(e, "reference: not implemented"); }
