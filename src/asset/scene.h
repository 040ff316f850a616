/* A scene: the moving things drawn over a world (internal).  Its types sit
 * here, below the stages that read a scene (world/, light/, raster/);
 * scene/scene.c loads and builds scenes. */
#ifndef EW_ASSET_SCENE_H
#define EW_ASSET_SCENE_H

#include "ew_world.h"

#include <stdint.h>

enum { EW_MODEL_ALIAS = 1, EW_MODEL_SPRITE, EW_MODEL_BOX };

/* Entity origins beyond this (or not finite) are refused: the world's own
 * vertices stop at the same bound (asset/bsp.c). */
#define EW_MAX_ENTITY_COORD 1.0e7f

typedef struct ew_scene_model {
    int   kind;      /* EW_MODEL_* */
    char  name[64];
    void *data;      /* ew_mdl *, ew_spr *, or ew_world * (item box) */
    float lo[3], hi[3];  /* item box: the box of its vertices (the file's model bounds lie a unit inside its faces) */
} ew_scene_model;

typedef struct ew_scene_entity {
    int   model;     /* >= 0: scene model; < 0: world submodel -1 - model (doors...) */
    float origin[3], angles[3];
    int   frame, skin;
    float alpha;     /* brush entities: opacity, 1 = opaque (the "alpha" key; 0 there means 1) */
} ew_scene_entity;

typedef struct ew_dlight {
    float origin[3];
    float radius;
    float color[3];   /* 0..1 each; white (1, 1, 1) unless told */
} ew_dlight;

#define EW_MAX_DLIGHTS 32

typedef struct ew_particle {
    float   org[3];
    uint8_t color;   /* palette index */
} ew_particle;

struct ew_scene {
    const ew_world  *world;
    ew_scene_model  *models;    int nmodels, cap_models;
    ew_scene_entity *ents;      int nents, cap_ents;
    ew_dlight        dlights[EW_MAX_DLIGHTS];
    int              ndlights;
    struct ew_particle *particles; int nparticles, cap_particles;
    int              unknown;   /* entities whose classname has no known model */
    int              missing;   /* entities whose model file was not found */
    char           **warnings;  /* ew_scene_warning */
    int              nwarnings;
    char           (*missing_files)[64];  /* ew_scene_missing_file: distinct model files not found */
    int              nmissing_files;
};

#endif
