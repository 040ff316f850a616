/* Light entities of a map (internal): what the renderer's light styles
 * need from them (asset/light_entities.c). */
#ifndef EW_LIGHT_ENTITIES_H
#define EW_LIGHT_ENTITIES_H

#include <stddef.h>
#include <stdint.h>

/* The switchable styles (32..63) that start off: bit s is set when the
 * last light entity (classname "light...") with "style" s in the entity
 * text has spawnflags bit 1 (START_OFF), as the game spawns them in
 * order, each setting its style.  A damaged lump gives what parsed. */
uint64_t ew_light_styles_starting_off(const char *entities, size_t len);

#endif
