/* Light entities: which switchable light styles start off (see
 * light_entities.h).  In the game a light entity with a style of 32 or
 * more sets its style to "a" (off) if its spawnflags have START_OFF (1),
 * else "m" (on); light/styles.c turns the mask into those patterns. */
#include "light_entities.h"
#include "entity_lump.h"

#include <string.h>

#define START_OFF 1

uint64_t ew_light_styles_starting_off(const char *entities, size_t len) {
    if (!entities) return 0;
    ew_entities ents;
    ew_entities_parse(entities, len, &ents, NULL);  /* keeps what parsed before an error */
    uint64_t off = 0;
    for (int i = 0; i < ents.count; i++) {
        const ew_entity *e = &ents.ents[i];
        const char *cls = ew_entity_get(e, "classname");
        if (!cls || strncmp(cls, "light", 5) != 0) continue;
        int style = ew_entity_int(e, "style", 0);  /* checked: a bad number is the fallback */
        if (style < 32 || style > 63) continue;
        if (ew_entity_int(e, "spawnflags", 0) & START_OFF) off |= (uint64_t)1 << style;
        else off &= ~((uint64_t)1 << style);
    }
    ew_entities_free(&ents);
    return off;
}
