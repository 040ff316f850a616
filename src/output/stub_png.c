/* TEMPORARY stub: the CLI/PNG owner deletes this file. */
#include "ew_util.h"
int ew_write_png(const char *p, const uint8_t *px, int w, int h, const uint8_t pal[768], ew_error *e) { (void)px; (void)w; (void)h; (void)pal; return ew_fail(e, "%s: not implemented", p); }
int ew_read_png_rgb(const char *p, uint8_t **rgb, int *w, int *h, ew_error *e) { (void)rgb; (void)w; (void)h; return ew_fail(e, "%s: not implemented", p); }
int ew_view_set(const ew_world *w, ew_camera v[EW_MAX_VIEWS]) { (void)w; (void)v; return 0; }
