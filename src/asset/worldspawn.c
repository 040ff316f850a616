/* The worldspawn entity's rendering keys (see worldspawn.h).
 *
 * Conventions, as today's source ports read these keys (QuakeSpasm,
 * vkQuake, Ironwail: R_ParseWorldspawn and Fog_ParseWorldspawn):
 *
 *   "_wateralpha" "_slimealpha" "_lavaalpha" "_telealpha"  opacity 0..1 of
 *       '*' surfaces of that liquid (by texture name: *slime..., *lava...,
 *       *tele..., any other '*' is water).  The ports strip one leading
 *       underscore from every worldspawn key, so "wateralpha" works as
 *       well; if both spellings are present the later pair wins, as it
 *       would there.  A value of 0 means "not set" in the ports (their
 *       surface alpha takes the fallback when it is not > 0), so 0 here is
 *       opaque, without a warning.
 *       A map that sets only _wateralpha leaves slime, lava and teleporters
 *       opaque: the ports' fallback for an unset liquid is the player's
 *       r_wateralpha setting (QuakeSpasm's and vkQuake's map_fallbackalpha,
 *       default 1 in QuakeSpasm), not the map's _wateralpha; here the
 *       player's override is ew_set_liquid_alpha.
 *   "fog" "density red green blue"  (FitzQuake's syntax; "_fog" too)
 *       density >= 0 (0: no fog), colour components 0..1.  A value with
 *       the density alone keeps the ports' default colour, gray 0.3.
 *
 * Anything else (not a number, NaN, inf, out of range, two or three fog
 * numbers, text after the numbers) is malformed: one warning naming the
 * map, the key and the value (cut to 100 characters, so the line keeps
 * its reason), and that key keeps its default. */
#include "worldspawn.h"
#include "entity_lump.h"
#include "ew_util.h"

#include <string.h>

/* Skips blanks; 1 if nothing but blanks remain at s. */
static int only_blanks(const char *s) {
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') s++;
    return *s == '\0';
}

int ew_parse_opacity(const char *value, float *alpha, const char **problem) {
    const char *end;
    double d = 0;
    int rc = ew_entity_number(value, &end, 0, 1, &d);
    if (rc < 0) {
        *problem = "not a number";
        return 0;
    }
    if (rc == 0) {
        *problem = "not an opacity from 0 to 1";
        return 0;
    }
    if (!only_blanks(end)) {
        *problem = "text after the number";
        return 0;
    }
    *alpha = d > 0 ? (float)d : 1.0f;  /* 0: not set, opaque */
    return 1;
}

/* The pair of e whose key is name, with or without one leading '_' (the
 * last such pair, as the ports read them in order), or NULL. */
static const ew_entity_pair *find_key(const ew_entity *e, const char *name) {
    for (int i = e->count - 1; i >= 0; i--) {
        const char *k = e->pairs[i].key;
        if (k[0] == '_') k++;
        if (strcmp(k, name) == 0) return &e->pairs[i];
    }
    return NULL;
}

static void read_alpha(ew_world *w, const ew_entity *e, const char *name, int liquid) {
    const ew_entity_pair *p = find_key(e, name);
    if (!p) return;
    const char *problem;
    float a;
    if (ew_parse_opacity(p->value, &a, &problem))
        w->worldspawn.liquid_alpha[liquid] = a;
    else
        ew_warn(&w->warnings, &w->nwarnings, "%s: worldspawn \"%.64s\" \"%.100s\": %s; the liquid stays opaque",
                w->name, p->key, p->value, problem);
}

/* "density" or "density red green blue". */
static const char *parse_fog(const char *s, float *density, float rgb[3]) {
    double v[4];
    int n = 0;
    const char *end = s;
    while (n < 4) {
        int rc = n == 0 ? ew_entity_number(s, &end, 0, EW_FOG_MAX_DENSITY, &v[0])
                        : ew_entity_number(s, &end, 0, 1, &v[n]);
        if (rc < 0) break;
        if (rc == 0)
            return n == 0 ? "the density is not a number from 0 to 1e6"
                          : "a colour component is not a number from 0 to 1";
        n++;
        s = end;
    }
    if (n == 0) return "not a number";
    if (!only_blanks(s)) return "text after the numbers";
    if (n != 1 && n != 4) return "expected \"density\" or \"density red green blue\"";
    *density = (float)v[0];
    for (int k = 0; k < 3; k++) rgb[k] = n == 4 ? (float)v[k + 1] : EW_FOG_DEFAULT_GRAY;
    return NULL;
}

static void read_fog(ew_world *w, const ew_entity *e) {
    const ew_entity_pair *p = find_key(e, "fog");
    if (!p) return;
    float density, rgb[3];
    const char *problem = parse_fog(p->value, &density, rgb);
    if (problem) {
        ew_warn(&w->warnings, &w->nwarnings, "%s: worldspawn \"%.64s\" \"%.100s\": %s; no fog", w->name, p->key,
                p->value, problem);
        return;
    }
    w->worldspawn.fog_density = density;
    memcpy(w->worldspawn.fog_rgb, rgb, sizeof rgb);
}

void ew_worldspawn_read(ew_world *w) {
    for (int i = 0; i < EW_NUM_LIQUIDS; i++) w->worldspawn.liquid_alpha[i] = 1;
    w->worldspawn.fog_density = 0;
    for (int k = 0; k < 3; k++) w->worldspawn.fog_rgb[k] = EW_FOG_DEFAULT_GRAY;

    const char *text = w->entities ? w->entities : "";
    ew_entities ents;
    ew_error err;
    /* A damaged lump still yields the entities closed before the damage;
     * the scene reads it the same way. */
    ew_entities_parse(text, strlen(text), &ents, &err);
    const ew_entity *ws = NULL;
    for (int i = 0; i < ents.count && !ws; i++) {
        const char *cls = ew_entity_get(&ents.ents[i], "classname");
        if (cls && strcmp(cls, "worldspawn") == 0) ws = &ents.ents[i];
    }
    if (ws) {
        read_alpha(w, ws, "wateralpha", EW_LIQUID_WATER);
        read_alpha(w, ws, "slimealpha", EW_LIQUID_SLIME);
        read_alpha(w, ws, "lavaalpha", EW_LIQUID_LAVA);
        read_alpha(w, ws, "telealpha", EW_LIQUID_TELE);
        read_fog(w, ws);
    }
    ew_entities_free(&ents);
}
