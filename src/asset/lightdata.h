/*
 * Light data beyond the BSP's own lighting lump (internal): the BSPX lump
 * directory and its light lumps (lightdata.c), read by ew_world_create;
 * .lit files go through the public ew_world_attach_lit.  Everything here
 * is optional data: a malformed part adds one warning to the world and is
 * ignored, the map keeps what is valid.
 */
#ifndef EW_LIGHTDATA_H
#define EW_LIGHTDATA_H

#include "ew_world.h"
#include <stddef.h>
#include <stdint.h>

/* A checked BSPX directory (pointers into the BSP image, valid while it
 * is).  dir == NULL: the file has none (or a malformed one, warned). */
typedef struct ew_bspx {
    const uint8_t *file;
    size_t         size;
    const uint8_t *dir;   /* first 32-byte entry */
    int            n;     /* entries */
    int            present;  /* a 'BSPX' id was found (even if the directory was bad) */
} ew_bspx;

/* Looks for the directory right after the standard header (if no lump
 * starts there) and else after the last standard lump (rounded up to 4
 * bytes, where compilers write it).  lumps: the header's 15 lumps, already
 * checked against the file.  A directory that overruns the file, a lump
 * outside the file or overlapping the directory or another lump: one
 * warning on w, x->dir NULL. */
void ew_bspx_open(ew_bspx *x, const uint8_t *data, size_t size, const ew_lump_info lumps[EW_NUM_LUMPS],
                  ew_world *w, const char *file);
/* The named lump's bytes (len set), NULL if absent. */
const uint8_t *ew_bspx_find(const ew_bspx *x, const char *name, size_t *len);
/* 1 if the directory has a lump that moves face light maps (LMSHIFT,
 * LMOFFSET, DECOUPLED_LM), or a BSPX directory too broken to tell: the loader then keeps a face whose Quake-layout
 * light map does not fit in the lump (unlit) instead of refusing the map. */
int ew_bspx_moves_light(const ew_bspx *x);
/* RGBLIGHTING (after the lighting lump is loaded, before the faces): sets
 * w->rgblight; a map without a mono lump gets one made from it (the mean
 * of the channels). */
void ew_bspx_rgb(const ew_bspx *x, ew_world *w, const char *file);
/* LMSHIFT / LMOFFSET / LMSTYLE / DECOUPLED_LM (after the faces): fills
 * w->facelm and the faces' styles and offsets.  faces: the file's face
 * lump, rec bytes a record, the 4 style bytes at styles_at and the int32
 * light offset right after them. */
void ew_bspx_layout(const ew_bspx *x, ew_world *w, const char *file, const uint8_t *faces, int rec,
                    int styles_at);

/* The Quake layout of face f as an ew_facelm (one sample every 16 texels
 * from texturemins). */
void ew_facelm_quake(const ew_face *f, ew_facelm *out);

/* 1 if the game directory has the file (loose or in a pak), asset/fs.c. */
int ew_fs_exists(const ew_fs *fs, const char *name);
/* Where name is found, for messages: "DIR/name", or "DIR/pakN.pak: name"
 * inside a pak. */
void ew_fs_where(const ew_fs *fs, const char *name, char *out, size_t size);

#endif
