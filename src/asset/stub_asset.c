/* TEMPORARY stub: the loader owner deletes this file when the real loaders exist. */
#include "ew_util.h"
#include "ew_world.h"
int ew_read_file(const char *p, uint8_t **d, size_t *s, ew_error *e) { (void)d; (void)s; return ew_fail(e, "%s: not implemented", p); }
ew_fs *ew_fs_open(const char *dir, ew_error *e) { ew_fail(e, "%s: not implemented", dir); return NULL; }
void ew_fs_close(ew_fs *fs) { (void)fs; }
int ew_fs_load(const ew_fs *fs, const char *n, uint8_t **d, size_t *s, ew_error *e) { (void)fs; (void)d; (void)s; return ew_fail(e, "%s: not implemented", n); }
int ew_pak_parse(const uint8_t *d, size_t s, const char *f, ew_pak_entry **en, int *c, ew_error *e) { (void)d; (void)s; (void)en; (void)c; return ew_fail(e, "%s: not implemented", f); }
int ew_palette_parse(const uint8_t *d, size_t s, const char *f, uint8_t p[768], ew_error *e) { (void)d; (void)s; (void)p; return ew_fail(e, "%s: not implemented", f); }
int ew_colormap_parse(const uint8_t *d, size_t s, const char *f, uint8_t c[EW_COLORMAP_SIZE], ew_error *e) { (void)d; (void)s; (void)c; return ew_fail(e, "%s: not implemented", f); }
ew_world *ew_world_load(const uint8_t *d, size_t s, const char *f, ew_error *e) { (void)d; (void)s; ew_fail(e, "%s: not implemented", f); return NULL; }
void ew_world_free(ew_world *w) { (void)w; }
void ew_world_get_info(const ew_world *w, ew_world_info *i) { (void)w; (void)i; }
const char *ew_world_entities(const ew_world *w) { return w->entities; }
int ew_assets_load(const char *m, const char *d, ew_assets *o, ew_error *e) { (void)d; (void)o; return ew_fail(e, "%s: not implemented", m); }
void ew_assets_free(ew_assets *a) { (void)a; }
