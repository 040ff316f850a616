/* Scenes: the entities of a map (or of a program) drawn over its world.
 * Models are loaded once per scene and shared by the entities using them. */
#include "asset/scene.h"
#include "asset/entity_lump.h"
#include "asset/worldspawn.h"
#include "ew_util.h"
#include "raster/alias.h"

#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

ew_scene *ew_scene_create(const ew_world *w, ew_error *err) {
    ew_scene *s = calloc(1, sizeof *s);
    if (!s) {
        ew_fail(err, "scene: out of memory");
        return NULL;
    }
    s->world = w;
    return s;
}

void ew_scene_destroy(ew_scene *s) {
    if (!s) return;
    for (int i = 0; i < s->nmodels; i++) {
        ew_scene_model *m = &s->models[i];
        if (m->kind == EW_MODEL_ALIAS) ew_mdl_free(m->data);
        else if (m->kind == EW_MODEL_SPRITE) ew_spr_free(m->data);
        else if (m->kind == EW_MODEL_BOX) ew_world_destroy(m->data);
    }
    free(s->ents);
    free(s->models);
    free(s->particles);
    free(s->missing_files);
    ew_warn_free(s->warnings, s->nwarnings);
    free(s);
}

const char *ew_scene_missing_file(const ew_scene *s, int i) {
    return s && i >= 0 && i < s->nmissing_files ? s->missing_files[i] : NULL;
}

const char *ew_scene_warning(const ew_scene *s, int i) {
    return s && i >= 0 && i < s->nwarnings ? s->warnings[i] : NULL;
}

int ew_scene_load_model(ew_scene *s, const char *name, const uint8_t *data, size_t size, ew_error *err) {
    for (int i = 0; i < s->nmodels; i++)
        if (strcmp(s->models[i].name, name) == 0) return i;
    int kind;
    void *model;
    if (size >= 4 && memcmp(data, "IDPO", 4) == 0) {
        kind = EW_MODEL_ALIAS, model = ew_mdl_load(data, size, name, err);
    } else if (size >= 4 && memcmp(data, "IDSP", 4) == 0) {
        kind = EW_MODEL_SPRITE, model = ew_spr_load(data, size, name, err);
    } else {
        kind = EW_MODEL_BOX, model = ew_world_create(data, size, name, err);
    }
    if (!model) return -1;
    if (s->nmodels == s->cap_models) {
        int cap = s->cap_models ? s->cap_models * 2 : 16;
        ew_scene_model *m = realloc(s->models, sizeof *m * (size_t)cap);
        if (!m) {
            if (kind == EW_MODEL_ALIAS) ew_mdl_free(model);
            else if (kind == EW_MODEL_SPRITE) ew_spr_free(model);
            else ew_world_destroy(model);
            return ew_fail(err, "%s: out of memory", name);
        }
        s->models = m, s->cap_models = cap;
    }
    ew_scene_model *m = &s->models[s->nmodels];
    *m = (ew_scene_model){.kind = kind, .data = model};  /* lo, hi 0 but for item boxes */
    if (kind == EW_MODEL_BOX) {
        const ew_world *bw = model;
        const ew_model *bm = &bw->models[0];
        for (int k = 0; k < 3; k++) m->lo[k] = bm->mins[k], m->hi[k] = bm->maxs[k];
        for (int i = 0; i < bw->numverts; i++)
            for (int k = 0; k < 3; k++) {
                if (bw->verts[i][k] < m->lo[k]) m->lo[k] = bw->verts[i][k];
                if (bw->verts[i][k] > m->hi[k]) m->hi[k] = bw->verts[i][k];
            }
    }
    snprintf(m->name, sizeof m->name, "%s", name);
    return s->nmodels++;
}

int ew_scene_add_entity(ew_scene *s, int model, const float origin[3], const float angles[3],
                        int frame, int skin) {
    if (model >= s->nmodels || (model < 0 && -1 - model >= s->world->nummodels)) return -1;
    /* A moved model must stay where the projection's float arithmetic is
     * exact enough to keep its points on the screen (world/edge_math.h). */
    for (int k = 0; k < 3; k++)
        if ((origin && !(fabsf(origin[k]) <= EW_MAX_ENTITY_COORD)) || (angles && !isfinite(angles[k]))) return -1;
    if (s->nents == s->cap_ents) {
        int cap = s->cap_ents ? s->cap_ents * 2 : 64;
        ew_scene_entity *e = realloc(s->ents, sizeof *e * (size_t)cap);
        if (!e) return -1;
        s->ents = e, s->cap_ents = cap;
    }
    ew_scene_entity *e = &s->ents[s->nents];
    memset(e, 0, sizeof *e);
    e->model = model;
    for (int k = 0; k < 3; k++) {
        e->origin[k] = origin ? origin[k] : 0;
        e->angles[k] = angles ? angles[k] : 0;
    }
    e->frame = frame, e->skin = skin;
    e->alpha = 1;
    return s->nents++;
}

int ew_scene_add_brush(ew_scene *s, int submodel, const float origin[3], const float angles[3]) {
    if (submodel <= 0 || submodel >= s->world->nummodels) return -1;
    return ew_scene_add_entity(s, -1 - submodel, origin, angles, 0, 0);
}

int ew_scene_set_alpha(ew_scene *s, int entity, float alpha) {
    if (!s || entity < 0 || entity >= s->nents || !(alpha > 0 && alpha <= 1)) return -1;
    s->ents[entity].alpha = alpha;
    return 0;
}

int ew_scene_add_dlight_rgb(ew_scene *s, const float origin[3], float radius, const float color[3]) {
    int i = ew_scene_add_dlight(s, origin, radius);
    if (i < 0 || !color) return i;
    for (int k = 0; k < 3; k++)
        s->dlights[i].color[k] = color[k] >= 0 ? (color[k] <= 1 ? color[k] : 1) : 0;  /* NaN: 0 */
    return i;
}

int ew_scene_add_dlight(ew_scene *s, const float origin[3], float radius) {
    if (s->ndlights >= EW_MAX_DLIGHTS || !(radius > 0) || radius > 1e5f) return -1;
    ew_dlight *d = &s->dlights[s->ndlights];
    for (int k = 0; k < 3; k++) d->origin[k] = origin[k], d->color[k] = 1;
    d->radius = radius;
    return s->ndlights++;
}

int ew_scene_add_particles(ew_scene *s, int n, const float center[3], float radius, uint32_t seed) {
    if (n < 0 || n > 1000000 || !(radius >= 0) || radius > 1e5f) return -1;
    ew_particle *p = realloc(s->particles, sizeof *p * (size_t)(s->nparticles + n + 1));
    if (!p) return -1;
    s->particles = p;
    s->cap_particles = s->nparticles + n;
    ew_particle_field(p + s->nparticles, n, center, radius, seed);
    s->nparticles += n;
    return n;
}

void ew_scene_clear(ew_scene *s) {
    if (!s) return;
    s->nents = 0;
    s->ndlights = 0;
    s->nparticles = 0;
}

int ew_scene_add_particle(ew_scene *s, const float org[3], int color) {
    if (!s || !org || color < 0 || color > 255) return -1;
    for (int k = 0; k < 3; k++)
        if (!(fabsf(org[k]) <= EW_MAX_ENTITY_COORD)) return -1;
    if (s->nparticles >= s->cap_particles) {
        if (s->nparticles >= 1000000) return -1;
        int cap = s->cap_particles ? s->cap_particles * 2 : 1024;
        ew_particle *p = realloc(s->particles, sizeof *p * (size_t)(cap + 1));
        if (!p) return -1;
        s->particles = p, s->cap_particles = cap;
    }
    ew_particle *p = &s->particles[s->nparticles];
    for (int k = 0; k < 3; k++) p->org[k] = org[k];
    p->color = (uint8_t)color;
    return s->nparticles++;
}

void ew_scene_counts(const ew_scene *s, int *entities, int *unknown, int *missing) {
    if (entities) *entities = s->nents;
    if (unknown) *unknown = s->unknown;
    if (missing) *missing = s->missing;
}

/* ---- the standard Quake classnames ---------------------------------------- */

typedef struct class_model {
    const char *classname;
    const char *model;    /* %c: the key's world type letter (w, m, b) */
    const char *model_big; /* spawnflags & 1 (big boxes, rotten health) */
    const char *model_mega; /* spawnflags & 2 (megahealth) */
    int skin;
} class_model;

static const class_model class_models[] = {
    {"monster_army", "progs/soldier.mdl", 0, 0, 0},
    {"monster_dog", "progs/dog.mdl", 0, 0, 0},
    {"monster_ogre", "progs/ogre.mdl", 0, 0, 0},
    {"monster_ogre_marksman", "progs/ogre.mdl", 0, 0, 0},
    {"monster_knight", "progs/knight.mdl", 0, 0, 0},
    {"monster_hell_knight", "progs/hknight.mdl", 0, 0, 0},
    {"monster_zombie", "progs/zombie.mdl", 0, 0, 0},
    {"monster_demon1", "progs/demon.mdl", 0, 0, 0},
    {"monster_shambler", "progs/shambler.mdl", 0, 0, 0},
    {"monster_wizard", "progs/wizard.mdl", 0, 0, 0},
    {"monster_enforcer", "progs/enforcer.mdl", 0, 0, 0},
    {"monster_shalrath", "progs/shalrath.mdl", 0, 0, 0},
    {"monster_tarbaby", "progs/tarbaby.mdl", 0, 0, 0},
    {"monster_fish", "progs/fish.mdl", 0, 0, 0},
    {"monster_boss", "progs/boss.mdl", 0, 0, 0},
    {"monster_oldone", "progs/oldone.mdl", 0, 0, 0},
    {"item_armor1", "progs/armor.mdl", 0, 0, 0},
    {"item_armor2", "progs/armor.mdl", 0, 0, 1},
    {"item_armorInv", "progs/armor.mdl", 0, 0, 2},
    {"weapon_supershotgun", "progs/g_shot.mdl", 0, 0, 0},
    {"weapon_nailgun", "progs/g_nail.mdl", 0, 0, 0},
    {"weapon_supernailgun", "progs/g_nail2.mdl", 0, 0, 0},
    {"weapon_grenadelauncher", "progs/g_rock.mdl", 0, 0, 0},
    {"weapon_rocketlauncher", "progs/g_rock2.mdl", 0, 0, 0},
    {"weapon_lightning", "progs/g_light.mdl", 0, 0, 0},
    {"item_health", "maps/b_bh25.bsp", "maps/b_bh10.bsp", "maps/b_bh100.bsp", 0},
    {"item_shells", "maps/b_shell0.bsp", "maps/b_shell1.bsp", 0, 0},
    {"item_spikes", "maps/b_nail0.bsp", "maps/b_nail1.bsp", 0, 0},
    {"item_rockets", "maps/b_rock0.bsp", "maps/b_rock1.bsp", 0, 0},
    {"item_cells", "maps/b_batt0.bsp", "maps/b_batt1.bsp", 0, 0},
    {"item_key1", "progs/%c_s_key.mdl", 0, 0, 0},
    {"item_key2", "progs/%c_g_key.mdl", 0, 0, 0},
    {"item_artifact_super_damage", "progs/quaddama.mdl", 0, 0, 0},
    {"item_artifact_invulnerability", "progs/invulner.mdl", 0, 0, 0},
    {"item_artifact_envirosuit", "progs/suit.mdl", 0, 0, 0},
    {"item_artifact_invisibility", "progs/invisibl.mdl", 0, 0, 0},
    {"item_sigil", "progs/end1.mdl", 0, 0, 0},
    {"light_flame_large_yellow", "progs/flame2.mdl", 0, 0, 0},
    {"light_flame_small_yellow", "progs/flame2.mdl", 0, 0, 0},
    {"light_flame_small_white", "progs/flame2.mdl", 0, 0, 0},
    {"light_torch_small_walltorch", "progs/flame.mdl", 0, 0, 0},
    {"light_globe", "progs/s_light.spr", 0, 0, 0},
    {"misc_teleporttrain", "progs/teleport.mdl", 0, 0, 0},
    {"misc_explobox", "maps/b_explob.bsp", 0, 0, 0},
    {"misc_explobox2", "maps/b_exbox2.bsp", 0, 0, 0},
};

/* Classnames that are known to draw nothing (triggers, lights, markers). */
static int invisible_class(const char *c) {
    static const char *prefixes[] = {"info_", "light", "trigger_", "path_", "ambient_", "func_",
                                     "target_", "trap_", "worldspawn", "air_bubbles", "event_", "misc_noisemaker",
                                     "misc_fireball", "viewthing", "noclass"};
    for (size_t i = 0; i < sizeof prefixes / sizeof *prefixes; i++)
        if (strncmp(c, prefixes[i], strlen(prefixes[i])) == 0) return 1;
    return 0;
}

/* The game directory of a map: data_dir, or the folder above maps/NAME.bsp. */
static ew_fs *open_game_dir(const char *map, const char *data_dir) {
    ew_error err;
    if (data_dir) return ew_fs_create(data_dir, &err);
    if (!map) return NULL;  /* a world made in memory has no game directory */
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", map ? map : "");
    char *slash = strrchr(dir, '/');
    if (!slash) {
        snprintf(dir, sizeof dir, "..");
    } else {
        *slash = 0;
        size_t n = strlen(dir);
        if (n + 4 >= sizeof dir) return NULL;
        memcpy(dir + n, "/..", 4);
    }
    return ew_fs_create(dir, &err);
}

/* A brush entity's "alpha", as the ports read it (FitzQuake's per-entity
 * alpha, kept by QuakeSpasm, vkQuake, Ironwail): absent or 0 = the default,
 * opaque; (0, 1] = that opacity.  Not a number, NaN, inf, negative or
 * above 1 is malformed here: one warning and opaque.  (The ports' own
 * encoding would clamp above 1 to opaque too, so that case looks the same;
 * a negative value, which FitzQuake documents as "invisible" for -1, is
 * drawn rather than hidden, so a typo cannot make a door disappear.) */
static void brush_alpha(ew_scene *s, const ew_entity *e, int index, const char *cls, int sub, int ent) {
    const char *v = ew_entity_get(e, "alpha");
    if (!v) return;
    float a;
    const char *problem;
    if (ew_parse_opacity(v, &a, &problem)) {
        s->ents[ent].alpha = a;
        return;
    }
    ew_warn(&s->warnings, &s->nwarnings, "%s: entity %d (%.64s, model *%d) \"alpha\" \"%.100s\": %s; drawn opaque",
            s->world->name, index, cls, sub, v, problem);
}

/* The model files a map's entities asked for that could not be loaded:
 * distinct names, the first few kept for the warning. */
#define MISSING_SHOWN 4
typedef struct missing_files {
    char names[MISSING_SHOWN][64];
    int  files, entities, boxes;  /* distinct files, entities without a model, of them maps/b_*.bsp files */
    char seen[64][64];            /* every distinct file (class_models names fewer than 64) */
    int  nseen;
} missing_files;

static void note_missing(missing_files *m, const char *path) {
    m->entities++;
    for (int i = 0; i < m->nseen; i++)
        if (strcmp(m->seen[i], path) == 0) return;
    if (m->nseen < 64) snprintf(m->seen[m->nseen++], 64, "%s", path);
    if (m->files < MISSING_SHOWN) snprintf(m->names[m->files], 64, "%s", path);
    m->files++;
    if (strncmp(path, "maps/b_", 7) == 0) m->boxes++;
}

/* One warning line: how many files, the first few, and a note when item
 * boxes are among them (they live in the game directory's maps/). */
static void warn_missing(ew_scene *s, const missing_files *m, int have_dir) {
    if (!m->files) return;
    char list[4 * 70 + 32];
    size_t n = 0;
    list[0] = '\0';
    for (int i = 0; i < m->files && i < MISSING_SHOWN; i++)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", m->names[i]);
    if (m->files > MISSING_SHOWN)
        snprintf(list + n, sizeof list - n, " and %d more", m->files - MISSING_SHOWN);
    ew_warn(&s->warnings, &s->nwarnings, "%s: %d model file%s missing or unreadable (%s), %d entit%s not drawn%s",
            s->world->name, m->files, m->files == 1 ? "" : "s", list, m->entities, m->entities == 1 ? "y" : "ies",
            !have_dir ? "; no game directory (give --data DIR)"
            : m->boxes ? "; item boxes (maps/b_*.bsp) are not in the game directory" : "");
}

ew_scene *ew_scene_create_from_map(const ew_world *w, const char *map, const char *data_dir, ew_error *err) {
    ew_scene *s = ew_scene_create(w, err);
    if (!s) return NULL;
    const char *text = ew_world_entities(w);
    ew_entities ents;
    ew_error perr;
    ew_entities_parse(text, strlen(text), &ents, &perr);  /* keeps what parsed */
    ew_fs *fs = open_game_dir(map, data_dir);
    static const missing_files none;
    missing_files *miss = malloc(sizeof *miss);
    if (miss) *miss = none;
    char worldtype = 'w';
    for (int i = 0; i < ents.count; i++) {
        const char *cls = ew_entity_get(&ents.ents[i], "classname");
        if (cls && strcmp(cls, "worldspawn") == 0 && ew_entity_get(&ents.ents[i], "worldtype")) {
            int wt = ew_entity_int(&ents.ents[i], "worldtype", 0);
            worldtype = wt == 1 ? 'm' : wt == 2 ? 'b' : 'w';
        }
    }
    for (int i = 0; i < ents.count; i++) {
        const ew_entity *e = &ents.ents[i];
        const char *cls = ew_entity_get(e, "classname");
        const char *model = ew_entity_get(e, "model");
        if (!cls || strcmp(cls, "worldspawn") == 0) continue;
        float origin[3] = {0, 0, 0}, angles[3] = {0, 0, 0};
        ew_entity_floats(e, "origin", origin, 3);
        /* Trigger volumes are brush models the game never draws (it clears
         * their model when it sets them up): drawn, they would hang in the
         * air as boxes of the trigger texture. */
        if (model && model[0] == '*' && strncmp(cls, "trigger_", 8) == 0) continue;
        if (model && model[0] == '*') {
            /* A brush entity's "angle" is its direction of travel, not a turn. */
            int sub = ew_entity_submodel(e), ent;
            if (sub <= 0 || sub >= w->nummodels || (ent = ew_scene_add_brush(s, sub, origin, angles)) < 0)
                s->missing++;
            else
                brush_alpha(s, e, i, cls, sub, ent);
            continue;
        }
        const class_model *cm = NULL;
        for (size_t k = 0; k < sizeof class_models / sizeof *class_models && !cm; k++)
            if (strcmp(cls, class_models[k].classname) == 0) cm = &class_models[k];
        if (!cm) {
            if (!invisible_class(cls)) s->unknown++;
            continue;
        }
        const char *pattern = cm->model;
        int sf = ew_entity_int(e, "spawnflags", 0);
        if ((sf & 2) && cm->model_mega) pattern = cm->model_mega;
        else if ((sf & 1) && cm->model_big) pattern = cm->model_big;
        char path[64];
        snprintf(path, sizeof path, pattern, worldtype);
        ew_entity_floats(e, "angle", &angles[1], 1);
        int mi = -1;
        uint8_t *data;
        size_t size;
        ew_error merr;
        if (fs && ew_fs_load(fs, path, &data, &size, &merr) == 0) {
            mi = ew_scene_load_model(s, path, data, size, &merr);
            free(data);
        }
        if (mi < 0 && miss) note_missing(miss, path);
        if (mi < 0 || ew_scene_add_entity(s, mi, origin, angles, 0, cm->skin) < 0) s->missing++;
    }
    /* A world made in memory (no map, no directory) has no model files to miss. */
    if (miss && (map || data_dir)) warn_missing(s, miss, fs != NULL);
    if (miss && miss->nseen && (s->missing_files = malloc(sizeof *s->missing_files * (size_t)miss->nseen))) {
        memcpy(s->missing_files, miss->seen, sizeof *s->missing_files * (size_t)miss->nseen);
        s->nmissing_files = miss->nseen;
    }
    free(miss);
    ew_fs_destroy(fs);
    ew_entities_free(&ents);
    return s;
}
