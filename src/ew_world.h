/*
 * The loaded world (internal).  Both BSP29 and BSP2 load into these same
 * 32-bit structures; every index in them has been validated by the loader,
 * so the renderer may use them without checks.  A world is read-only after
 * loading: all per-frame marks (visframes, edge caches) live in the
 * renderer.
 */
#ifndef EW_WORLD_H
#define EW_WORLD_H

#include "edgewise.h"
#include <stdint.h>

enum {
    EW_LUMP_ENTITIES, EW_LUMP_PLANES, EW_LUMP_TEXTURES, EW_LUMP_VERTEXES,
    EW_LUMP_VISIBILITY, EW_LUMP_NODES, EW_LUMP_TEXINFO, EW_LUMP_FACES,
    EW_LUMP_LIGHTING, EW_LUMP_CLIPNODES, EW_LUMP_LEAFS, EW_LUMP_MARKSURFACES,
    EW_LUMP_EDGES, EW_LUMP_SURFEDGES, EW_LUMP_MODELS, EW_NUM_LUMPS
};

/* Leaf contents: EW_CONTENTS_* (edgewise.h). */

/* Face flags. */
enum {
    EW_SURF_PLANEBACK = 1,  /* face looks along -plane normal */
    EW_SURF_SKY       = 2,  /* texture name starts with "sky" */
    EW_SURF_TURB      = 4,  /* '*' liquid: warped, unlit */
    EW_SURF_FENCE     = 8,  /* '{' texture: index 255 is see-through */
    EW_SURF_MISSING   = 16  /* texture slot without pixel data */
};

/* Largest texture extent of a lit face, in texels (the loader refuses
 * more): bounds lit surfaces, and the span drawer's 16-bit texel maths. */
#define EW_MAX_EXTENT 2048

typedef struct ew_plane {
    float normal[3];
    float dist;
    int   type;      /* 0..2 axial x/y/z, else 3..5 */
} ew_plane;

/* Liquids, by texture name ("*lava...", "*slime...", "*tele...", other '*'). */
enum { EW_LIQUID_NONE, EW_LIQUID_WATER, EW_LIQUID_SLIME, EW_LIQUID_LAVA, EW_LIQUID_TELE, EW_NUM_LIQUIDS };

typedef struct ew_texture {
    char     name[16];
    int      liquid;            /* EW_LIQUID_* ('*' textures), else EW_LIQUID_NONE */
    int      width, height;     /* mip 0 size; >= 8, multiples of 8 */
    const uint8_t *mip[4];      /* pixel data of each mip level */
    int      flags;             /* EW_SURF_SKY / TURB / FENCE / MISSING */
    /* animation (+0..+9 and +a..+j): cycle of anim_total frames;
     * this texture is frame anim_min..anim_max-1 of it (in 0.2 s steps) */
    int      anim_total, anim_min, anim_max;
    int      anim_next;         /* next texture in the cycle, -1 none */
    int      alternate_anims;   /* first texture of the +a cycle, -1 none */
} ew_texture;

typedef struct ew_texinfo {
    float vecs[2][4];  /* s = dot(p, vecs[0].xyz) + vecs[0][3], likewise t */
    int   texture;     /* index into world->textures */
    int   flags;       /* file flags (1 = special: sky/liquid) */
    float mipadjust;   /* texture scale factor used in mip selection */
} ew_texinfo;

/* A face's light map where it is not Quake's (one sample every 16 texels
 * from texturemins, (extents >> 4) + 1 a side): BSPX LMSHIFT (1 << shift
 * texels a sample) or DECOUPLED_LM (its own size and projection).  Light
 * sample (u, v) of texture point (s, t): u = st_to_lm[0] . (s, t, 1),
 * v = st_to_lm[1] . (s, t, 1), in samples from the map's first. */
typedef struct ew_facelm {
    int   width, height;     /* samples a side */
    int   lightofs;          /* first sample (byte offset into lighting), -1 none */
    float st_to_lm[2][3];
} ew_facelm;

typedef struct ew_face {
    int     plane;
    int     firstedge, numedges;  /* into surfedges, numedges >= 3 */
    int     texinfo;
    int     flags;                /* EW_SURF_* */
    uint8_t styles[4];            /* 255 = unused */
    int     lightofs;             /* byte offset into lighting, -1 none */
    int     texturemins[2];       /* multiples of 16 */
    int     extents[2];           /* texels, multiples of 16, 0..2048 (0: the face is
                                   * flat in texture space along that axis, as a
                                   * compiler may write; one row of light samples) */
} ew_face;

/* A face's lit surface at a mip level along axis a (0 s, 1 t): extents >>
 * mip texels, at least 1 (a face of extent 0 along an axis is one texel
 * wide there: every pixel of it samples that row). */
static inline int ew_face_surf_size(const ew_face *f, int a, int mip) {
    int n = f->extents[a] >> mip;
    return n > 0 ? n : 1;
}

/* children[i] >= 0: node index; < 0: leaf index -1 - children[i]. */
typedef struct ew_node {
    int   plane;
    int   children[2];
    float mins[3], maxs[3];
    int   firstface, numfaces;
    int   parent;                 /* -1 for a model's head node */
} ew_node;

/* One node of a clip hull (the clipnodes lump): children >= 0 are
 * clipnodes, < 0 are contents (EW_CONTENTS_*, -1..-15). */
typedef struct ew_clipnode {
    int plane;
    int children[2];  /* [0] front (dist >= 0), [1] back */
} ew_clipnode;

typedef struct ew_leaf {
    int     contents;
    int     visofs;               /* into visdata, -1 none */
    float   mins[3], maxs[3];
    int     firstmark, nummarks;  /* into marksurfaces */
    int     parent;
    uint8_t ambient[4];
} ew_leaf;

typedef struct ew_model {
    float mins[3], maxs[3], origin[3];
    int   headnode;               /* hull 0 */
    /* Head of the clip hulls 1 (the player's 32x32x56 box) and 2 (64x64x88):
     * a clipnode index, or a contents value (< 0) for a hull that is one
     * leaf.  Checked only when world->clip_ok. */
    int   cliphead[2];
    int   visleafs;
    int   firstface, numfaces;
} ew_model;

struct ew_world {
    char         name[256];
    char         version[8];      /* "29", "BSP2", "2PSB" */
    ew_lump_info lumps[EW_NUM_LUMPS];

    ew_plane   *planes;       int numplanes;
    float     (*verts)[3];    int numverts;
    uint32_t  (*edges)[2];    int numedges;
    int        *surfedges;    int numsurfedges;
    int        *surfverts;    /* per surfedge: the vertex it starts from (ew_face_vertex) */
    ew_texinfo *texinfo;      int numtexinfo;
    ew_texture *textures;     int numtextures;  /* the last one is the placeholder */
    ew_face    *faces;        int numfaces;
    float     (*face_box)[2][3];  /* per face: the mins and maxs of its corners */
    int        *marksurfaces; int nummarksurfaces;
    ew_node    *nodes;        int numnodes;
    ew_leaf    *leaves;       int numleaves;
    ew_model   *models;       int nummodels;
    ew_clipnode *clipnodes;   int numclipnodes;
    /* 1 when the clip hulls 1 and 2 of every model passed the loader's
     * checks (indices in range, no cycle): collision (world/move.c) works.
     * 0 for a map without clip hulls, or with bad ones (then a warning). */
    int         clip_ok;
    uint8_t    *lighting;     int lightsize;
    /* Coloured light (3 bytes a sample, the same samples as lighting): from
     * a .lit file beside the map or the BSPX RGBLIGHTING lump; NULL if none. */
    uint8_t    *rgblight;
    ew_facelm  *facelm;       /* numfaces (BSPX LMSHIFT / DECOUPLED_LM), or NULL: Quake's */
    ew_bspx_lump_info *bspx;  /* the BSPX directory as read (ew_world_bspx_lump) */
    int         nbspx;
    uint8_t    *visdata;      int vissize;
    char       *entities;     /* NUL-terminated copy */
    uint64_t    styles_start_off; /* bit s: a light entity starts switchable style s off (asset/light_entities.c) */
    int         textures_missing;

    uint8_t    *texpixels;    /* owned pixel storage behind ew_texture.mip */

    /* What the map's worldspawn asks for (asset/worldspawn.c), checked:
     * a malformed key leaves its default and adds a warning. */
    struct {
        float liquid_alpha[EW_NUM_LIQUIDS];  /* per EW_LIQUID_*: 1 = opaque (the default) */
        float fog_density;                   /* 0: no fog */
        float fog_rgb[3];                    /* 0..1 */
    } worldspawn;
    char      **warnings;     /* ew_world_warning */
    int         nwarnings;
};

/* Vertex index of the i-th corner of face f. */
static inline int ew_face_vertex(const ew_world *w, const ew_face *f, int i) {
    /* One load: through surfedges and edges it was two, one waiting on the
     * other, and in the front end's emission both usually missed the cache. */
    return w->surfverts[f->firstedge + i];
}
/* Face f's corners copied into p (room for f->numedges). */
static inline void ew_face_points(const ew_world *w, const ew_face *f, float (*p)[3]) {
    for (int i = 0; i < f->numedges; i++) {
        const float *q = w->verts[ew_face_vertex(w, f, i)];
        p[i][0] = q[0], p[i][1] = q[1], p[i][2] = q[2];
    }
}
/* Edge index (always >= 0) of the i-th side of face f. */
static inline int ew_face_edge(const ew_world *w, const ew_face *f, int i) {
    int se = w->surfedges[f->firstedge + i];
    return se >= 0 ? se : -se;
}

#endif
