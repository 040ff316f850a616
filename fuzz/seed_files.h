/*
 * Seed file generators (internal to fuzz/ and the regression test): a tiny
 * valid BSP29 room (sky, liquid, fence, animated and missing textures, two
 * light styles, a PVS row, both plane sides, shared edges), its BSP2/2PSB
 * conversion, a PAK, an alias model and a sprite.  Nothing is copied from
 * game data.  Allocation failure aborts: these only run in tools.
 */
#ifndef EW_SEED_FILES_H
#define EW_SEED_FILES_H

#include <stddef.h>
#include <stdint.h>

typedef struct ew_seed_buf {
    uint8_t *d;
    size_t   len, cap;
} ew_seed_buf;

/* Each appends to out (start from {0}; free out->d when done). */
void ew_seed_room(ew_seed_buf *out);
/* A valid BSP29 rewritten with the 32-bit records of BSP2 (bsp2 = 1, float
 * bounds) or 2PSB (bsp2 = 0, 16-bit bounds).  0, or -1 if not BSP29. */
int  ew_seed_convert29(const uint8_t *d, size_t size, int bsp2, ew_seed_buf *out);
/* A PAK holding the room, the palette and a text file. */
void ew_seed_pak(ew_seed_buf *out, const uint8_t *room, size_t room_len, const uint8_t palette[768]);
/* A tetrahedron: 8x8 skins (one single, one group), a single frame and a
 * frame group. */
void ew_seed_mdl(ew_seed_buf *out);
/* An 8x8 sprite: one single frame and a group of two. */
void ew_seed_spr(ew_seed_buf *out);
/* A demo (.dem) of protocol proto (15, 666 or 999 with flags): server
 * info, a baseline, a static entity, a light style, then a few blocks of
 * time, entity updates (FitzQuake's extended bits where the protocol has
 * them), client data, temp entities and a particle burst. */
void ew_seed_demo(ew_seed_buf *out, int proto, unsigned flags);

#endif
