/*
 * What a map asks of the renderer (internal): the worldspawn keys read into
 * ew_world.worldspawn, and the opacity values of entity "alpha" keys.
 * Every number is checked; a malformed value adds one warning to its world
 * or scene and leaves the default.  The conventions are today's source
 * ports' (FitzQuake's lineage: QuakeSpasm, vkQuake, Ironwail); see
 * worldspawn.c.
 */
#ifndef EW_WORLDSPAWN_H
#define EW_WORLDSPAWN_H

#include "ew_world.h"

/* Fog colour of a "fog" key that gives only a density (the ports' gray). */
#define EW_FOG_DEFAULT_GRAY 0.3f
/* Largest fog density accepted (as ew_set_fog). */
#define EW_FOG_MAX_DENSITY 1e6

/* Sets w->worldspawn from the map's worldspawn entity (its first entity of
 * classname "worldspawn"): the defaults (opaque liquids, no fog) for any
 * key absent or malformed, one warning on w per malformed key. */
void ew_worldspawn_read(ew_world *w);

/* An opacity value ("_wateralpha", an entity's "alpha"): one number from 0
 * to 1, blanks around it allowed.  Returns 1 with *alpha set (0, "not
 * set" in the ports, becomes 1 = opaque), or 0 with *problem set to a
 * short description for the warning (*alpha untouched). */
int ew_parse_opacity(const char *value, float *alpha, const char **problem);

#endif
