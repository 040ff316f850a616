/*
 * Triangle (alias) models: the MDL version 6 format ("IDPO"), validated
 * and read-only once loaded (internal).
 *
 * A model is a fixed triangle mesh with a texture coordinate per vertex
 * and a whole set of vertex positions per animation frame (bytes, scaled
 * and translated into model space).  Frames and skins may be groups that
 * animate by time.  Every count, size and index is checked by the loader,
 * so the renderer uses these structures without checks.
 */
#ifndef EW_MDL_H
#define EW_MDL_H

#include "edgewise.h"
#include <stddef.h>
#include <stdint.h>

/* Limits beyond which a file is refused as absurd (the game's own are far
 * smaller; these only keep every size well inside int range). */
#define EW_MDL_MAX_SKIN_SIDE 4096
#define EW_MDL_MAX_VERTS     65536
#define EW_MDL_MAX_TRIS      262144
#define EW_MDL_MAX_FRAMES    65536
#define EW_MDL_MAX_SKINS     4096

/* One frame vertex: packed position (model = v * scale + translate) and the
 * file's light normal index (kept, though shading uses the normals below). */
typedef struct ew_mdl_vert {
    uint8_t v[3];
    uint8_t normal;
} ew_mdl_vert;

typedef struct ew_mdl_st {
    int onseam;  /* nonzero: on the seam between the front and back skin halves */
    int s, t;    /* texel coordinates, 0..skinwidth, 0..skinheight */
} ew_mdl_st;

typedef struct ew_mdl_tri {
    int facesfront;  /* 0: the back skin half (onseam vertices use s + skinwidth/2) */
    int v[3];
} ew_mdl_tri;

/* One vertex set (a simple frame, or one frame of a group). */
typedef struct ew_mdl_pose {
    char  name[17];
    float mins[3], maxs[3];      /* model-space bounds of its vertices (computed) */
    const ew_mdl_vert *verts;    /* numverts */
    const float (*normals)[3];   /* numverts unit vertex normals (computed, model space) */
} ew_mdl_pose;

/* A frame or a skin: one pose/image, or a group animating through `count`
 * of them; times[i] is when item i ends (cumulative seconds), NULL if single. */
typedef struct ew_mdl_anim {
    int          first, count;
    const float *times;
} ew_mdl_anim;

typedef struct ew_mdl {
    char  name[64];
    float scale[3], translate[3], eye[3], size;
    float radius;  /* no vertex is farther from the origin (from scale and translate) */
    int   skinwidth, skinheight, numverts, numtris, synctype, flags;

    int          numskins;        /* skins (each maybe a group) */
    ew_mdl_anim *skins;
    int          numskinimages;
    uint8_t     *skinpixels;      /* numskinimages * skinwidth * skinheight */

    ew_mdl_st   *st;              /* numverts */
    ew_mdl_tri  *tris;            /* numtris */

    int          numframes;       /* frames (each maybe a group) */
    ew_mdl_anim *frames;
    int          numposes;
    ew_mdl_pose *poses;

    /* storage behind the pointers above */
    ew_mdl_vert *vertdata;        /* numposes * numverts */
    float      (*normaldata)[3];  /* numposes * numverts */
    float       *timedata;
} ew_mdl;

/* Parses a whole .mdl file (name is used in error lines).  Returns NULL with
 * one line in err ("progs/x.mdl: triangle 4 uses vertex 900 (only 120)"). */
ew_mdl *ew_mdl_load(const uint8_t *data, size_t size, const char *name, ew_error *err);
void    ew_mdl_free(ew_mdl *m);

/* The item of an animation at `time` (groups cycle through their times). */
int ew_mdl_anim_pick(const ew_mdl_anim *a, double time);

#endif
