/*
 * Sprites: the SPR version 1 format ("IDSP"), validated and read-only once
 * loaded (internal).  A sprite is a set of frames (single pictures or
 * groups animating by time); each picture is a palette-indexed image with
 * an origin (the offset of its top-left corner from the entity's position,
 * x right, y up).  Index 255 is transparent.
 */
#ifndef EW_SPR_H
#define EW_SPR_H

#include "edgewise.h"
#include <stddef.h>
#include <stdint.h>

#define EW_SPR_MAX_SIDE   4096
#define EW_SPR_MAX_FRAMES 65536

/* How the sprite's quad is oriented (the file's type field). */
enum {
    EW_SPR_VP_PARALLEL_UPRIGHT = 0,  /* faces the view plane, stays vertical */
    EW_SPR_FACING_UPRIGHT = 1,       /* faces the viewer's position, stays vertical */
    EW_SPR_VP_PARALLEL = 2,          /* parallel to the view plane */
    EW_SPR_ORIENTED = 3,             /* fixed in the world by the entity's angles */
    EW_SPR_VP_PARALLEL_ORIENTED = 4  /* parallel to the view plane, rolled by the entity */
};

typedef struct ew_spr_pic {
    int origin[2];           /* left, top (y up) relative to the entity */
    int width, height;
    const uint8_t *pixels;   /* width * height, row 0 at the top */
} ew_spr_pic;

typedef struct ew_spr_frame {
    int          first, count;  /* pictures; count > 1 for a group */
    const float *times;         /* cumulative end times of a group, NULL if single */
} ew_spr_frame;

typedef struct ew_spr {
    char  name[64];
    int   type, maxwidth, maxheight, synctype;
    float radius;            /* no picture corner is farther from the entity (computed) */
    float beamlength;
    int           numframes;
    ew_spr_frame *frames;
    int           numpics;
    ew_spr_pic   *pics;
    uint8_t      *pixeldata;
    float        *timedata;
} ew_spr;

ew_spr *ew_spr_load(const uint8_t *data, size_t size, const char *name, ew_error *err);
void    ew_spr_free(ew_spr *s);

/* The picture of frame `frame` (clamped to the frames there are) at `time`. */
const ew_spr_pic *ew_spr_pick(const ew_spr *s, int frame, double time);

#endif
