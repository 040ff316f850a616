/* The scene's z-buffered moving things, drawn in each band's rows after its
 * world spans: alias models, sprites, item boxes, then particles (the
 * "models" pass of scene/passes.c).  Which ones and their light were
 * settled once for the frame (world/entities.c). */
#include "renderer.h"
#include "ew_util.h"
#include "raster/alias.h"
#include "scene/scene.h"

#include <math.h>
#include <string.h>

/* An item box's corner, moved and projected once for all the faces that
 * share it (a box's faces share their corners three or four ways). */
typedef struct box_corner {
    float p[3];       /* world space */
    int   out;        /* the frustum planes it is behind (ew_clip_poly's test) */
    float u, v, zi;   /* on screen, when out is 0 */
} box_corner;
enum { BOX_CORNERS = 256, BOX_FACES = 256 };  /* more: each face on its own, as any polygon */

/* Face f of box world bw faces the eye (mv: the camera in the box's space)
 * and is not too big to clip. */
static int box_face_front(const ew_world *bw, const ew_face *f, const ew_view *mv) {
    const ew_plane *pl = &bw->planes[f->plane];
    float dist = mv->origin[0] * pl->normal[0] + mv->origin[1] * pl->normal[1] + mv->origin[2] * pl->normal[2] - pl->dist;
    int back = (f->flags & EW_SURF_PLANEBACK) != 0;
    return !((back && dist >= 0) || (!back && dist <= 0) || f->numedges > EW_MAX_POLY - 8);
}

/* Box corner q moved by the entity's axes and origin into world space. */
static void box_move(const float ax[3][3], const float origin[3], const float *q, float p[3]) {
    for (int k = 0; k < 3; k++) p[k] = origin[k] + ax[k][0] * q[0] + ax[k][1] * q[1] + ax[k][2] * q[2];
}

/* Corner vi of the box, from c or made there now. */
static const box_corner *box_corner_at(const ew_view *v, const ew_world *bw, const float ax[3][3],
                                       const float origin[3], box_corner *c, uint8_t *made, int vi) {
    box_corner *bc = &c[vi];
    if (made[vi]) return bc;
    made[vi] = 1;
    box_move(ax, origin, bw->verts[vi], bc->p);
    /* Exactly ew_clip_poly's distance and test: a polygon none of whose
     * corners is behind a plane comes out of it unchanged. */
    bc->out = 0;
    for (int i = 0; i < 4; i++) {
        const ew_plane *pl = &v->frustum[i];
        float d = bc->p[0] * pl->normal[0] + bc->p[1] * pl->normal[1] + bc->p[2] * pl->normal[2] - pl->dist;
        if (d < 0) bc->out |= 1 << i;
    }
    if (!bc->out) {
        ew_zpoly_vertex(v, bc->p, &bc->u, &bc->v, &bc->zi);
        /* A wild corner (a NaN origin) goes the clipping path, as it did. */
        if (!isfinite(bc->u) || !isfinite(bc->v)) bc->out = 1 << 4;
    }
    return bc;
}

/* Whether any of the box's front faces, none cut by the frustum (their
 * corners made), has an area on screen: draw_box's in-view answer. */
static int box_unclipped_in_view(const ew_world *bw, const ew_model *m, const int16_t *front, int nfront,
                                 const box_corner *corner) {
    for (int fi = 0; fi < nfront; fi++) {
        const ew_face *f = &bw->faces[m->firstface + front[fi]];
        ew_zpoly zp;
        int n = f->numedges;
        if (n < 3) continue;
        for (int k = 0; k < n; k++) {
            const box_corner *bc = &corner[ew_face_vertex(bw, f, k)];
            zp.u[k] = bc->u, zp.v[k] = bc->v;
        }
        zp.n = n;
        if (ew_zpoly_orient(&zp)) return 1;
    }
    return 0;
}

/* An item box: faces of a small world of its own, z-buffered. */
static int draw_box(ew_renderer *r, const ew_world *bw, const ew_box_surfs *surfs,
                    const ew_scene_entity *e, int ei, const ew_rows *rows) {
    const ew_model *m = &bw->models[0];
    /* Another band found this frame which rows its faces reach: when these
     * are not among them, nothing below would draw here.  The first band
     * returns whether the box is in view (it counts that), when known. */
    _Atomic uint64_t *known = ei < r->ents.nbox_rows && r->target.height < 1 << 15 ? &r->ents.box_rows[ei] : NULL;
    uint64_t frame = (uint64_t)(uint32_t)r->marks.framecount;
    if (known) {
        uint64_t k = atomic_load_explicit(known, memory_order_relaxed);
        int ky0 = (int)(k >> 15 & 0x7FFF), ky1 = (int)(k & 0x7FFF);
        if (k >> 32 == frame && (ky1 <= rows->y0 || ky0 >= rows->y1)) {
            if (!rows->first) return 0;
            if (k >> 31 & 1) return (int)(k >> 30 & 1);
        }
    }
    float ax[3][3];
    ew_entity_axes(e->angles, ax);
    float lo[3], hi[3];
    ew_moved_box(ax, e->origin, m->mins, m->maxs, lo, hi);
    if (ew_cull_box(&r->view, lo, hi, 15) < 0) return 0;
    ew_view mv;  /* the camera in the box's space */
    ew_view_to_model(&r->view, ax, e->origin, &mv);
    box_corner corner[BOX_CORNERS];
    uint8_t made[BOX_CORNERS];
    int16_t front[BOX_FACES];
    int shared = bw->numverts <= BOX_CORNERS && m->numfaces <= BOX_FACES, nfront = 0;
    /* The faces turned to the eye and their corners first: when the
     * frustum cuts none of them, the z-fill of the rectangle around them
     * all serves every face (the world's 1/z, wherever it is filled, is the
     * same values). */
    int zrect = 0, ry0 = 0, ry1 = 0;
    if (shared) {
        memset(made, 0, (size_t)bw->numverts);
        float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
        int out = 0;
        for (int i = 0; i < m->numfaces; i++) {
            const ew_face *f = &bw->faces[m->firstface + i];
            if (!box_face_front(bw, f, &mv)) continue;
            front[nfront++] = (int16_t)i;
            for (int k = 0; k < f->numedges; k++) {  /* every one, for the faces below */
                const box_corner *bc = box_corner_at(&r->view, bw, ax, e->origin, corner, made, ew_face_vertex(bw, f, k));
                out |= bc->out;
                if (out) continue;
                if (bc->u < umin) umin = bc->u;
                if (bc->u > umax) umax = bc->u;
                if (bc->v < vmin) vmin = bc->v;
                if (bc->v > vmax) vmax = bc->v;
            }
        }
        if (!out && umin <= umax) {
            /* ew_zpoly_close's rectangle, of all the corners: it holds every face's */
            int x0 = ew_ceilf_int(umin), x1 = ew_ceilf_int(umax), y0 = ew_ceilf_int(vmin), y1 = ew_ceilf_int(vmax);
            ew_zfill_rect(&r->zf, x0, y0 > rows->y0 ? y0 : rows->y0, x1, y1 < rows->y1 ? y1 : rows->y1);
            zrect = 1;
            /* and its rows, every face's rows among them */
            ry0 = y0 < 0 ? 0 : y0 > r->target.height ? r->target.height : y0;
            ry1 = y1 < ry0 ? ry0 : y1 > r->target.height ? r->target.height : y1;
        } else if (nfront == 0) {
            zrect = 1, ry0 = ry1 = 0;  /* no face turned to the eye */
        }
    }
    if (zrect && known) {
        atomic_store_explicit(known, frame << 32 | (uint64_t)ry0 << 15 | (uint64_t)ry1, memory_order_relaxed);
        if (ry1 <= rows->y0 || ry0 >= rows->y1) {  /* not in these rows: only whether in view */
            if (!rows->first) return 0;
            int in_view = box_unclipped_in_view(bw, m, front, nfront, corner);
            atomic_store_explicit(known, frame << 32 | 1ull << 31 | (uint64_t)in_view << 30 | (uint64_t)ry0 << 15 | (uint64_t)ry1,
                                  memory_order_relaxed);
            return in_view;
        }
    }
    long won = 0;
    int in_view = 0, fy0 = r->target.height, fy1 = 0;
    for (int fi = 0, nf = shared ? nfront : m->numfaces; fi < nf; fi++) {
        int i = shared ? front[fi] : fi;
        const ew_face *f = &bw->faces[m->firstface + i];
        if (!shared && !box_face_front(bw, f, &mv)) continue;
        const ew_box_surf *bs = NULL;
        int lit = !(f->flags & (EW_SURF_SKY | EW_SURF_TURB));
        if (lit) bs = surfs && i < surfs->nfaces && surfs->face[i].built ? &surfs->face[i] : NULL;
        ew_zpoly zp;
        int n = f->numedges, out = 0;
        float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
        if (shared) {
            /* Unclipped, the polygon is its corners as they are (made above). */
            zp.nearzi = 0;
            for (int k = 0; k < n && !out; k++) {
                const box_corner *bc = &corner[ew_face_vertex(bw, f, k)];
                out = bc->out;
                zp.u[k] = bc->u, zp.v[k] = bc->v;
                if (bc->zi > zp.nearzi) zp.nearzi = bc->zi;
                if (bc->u < umin) umin = bc->u;
                if (bc->u > umax) umax = bc->u;
                if (bc->v < vmin) vmin = bc->v;
                if (bc->v > vmax) vmax = bc->v;
            }
        }
        int holds;  /* its rectangle holds a pixel centre */
        if (!shared || out) {
            float p[EW_MAX_POLY][3];
            for (int k = 0; k < n; k++) box_move(ax, e->origin, bw->verts[ew_face_vertex(bw, f, k)], p[k]);
            if (!ew_zpoly_project(&r->view, p, n, &zp)) continue;
            holds = zp.x0 <= zp.x1 && zp.y0 <= zp.y1;
        } else {
            if (n < 3) continue;
            holds = ew_zpoly_rect(&r->view, &zp, n, umin, umax, vmin, vmax);
            /* Most faces of a far box fall between pixel centres: once the
             * box is known to be in view (and no surface is missing, which
             * is counted below), their orientation tells nothing. */
            if (!holds && in_view && (bs || !lit)) continue;
            if (!ew_zpoly_orient(&zp)) continue;
        }
        in_view = 1;
        /* The rows of the faces that get this far (one that cannot be
         * drawn still counts a missing surface), for the other bands. */
        if ((zp.y0 < zp.y1 ? zp.y0 : zp.y1) < fy0) fy0 = zp.y0 < zp.y1 ? zp.y0 : zp.y1;
        if ((zp.y0 > zp.y1 ? zp.y0 : zp.y1) + 1 > fy1) fy1 = (zp.y0 > zp.y1 ? zp.y0 : zp.y1) + 1;
        if (zp.y1 < rows->y0 || zp.y0 >= rows->y1) continue;  /* another band's rows */
        if (lit && !bs) {  /* no memory for it */
            rows->stats->dropped++;
            continue;
        }
        if (!holds) continue;  /* nothing to fill, and an empty z-fill rectangle */
        ew_zpoly_look look = {bw, f, &mv, ew_face_texture(bw, f, r->view.time), NULL, 0, 0, 1, EW_ZP_OPAQUE, NULL, 256};
        if (bs) {
            look.mip = ew_face_mip(&r->view, bw, f, zp.nearzi);
            look.surf = bs->pixels[look.mip], look.surf_width = bs->width[look.mip];
        }
        if (!zrect)
            ew_zfill_rect(&r->zf, zp.x0, zp.y0 > rows->y0 ? zp.y0 : rows->y0, zp.x1 + 1,
                          zp.y1 + 1 < rows->y1 ? zp.y1 + 1 : rows->y1);
        won += ew_zpoly_fill(&r->draw, &zp, &look, NULL, 0, rows->y0, rows->y1);
    }
    rows->stats->alias_pixels += won;
    if (known) {  /* clamped to the frame, the same for every band; none: empty */
        int h = r->target.height;
        fy0 = fy0 < 0 ? 0 : fy0 > h ? h : fy0;
        fy1 = fy1 < fy0 ? fy0 : fy1 > h ? h : fy1;
        atomic_store_explicit(known, frame << 32 | 1ull << 31 | (uint64_t)in_view << 30 | (uint64_t)fy0 << 15 | (uint64_t)fy1,
                              memory_order_relaxed);
    }
    return in_view;
}

static void tint_palette(ew_renderer *r, const ew_ent_frame *ef, int i, ew_alias_xf *xf);

/* An entity's pose this frame. */
static ew_model_pose entity_pose(const ew_renderer *r, const ew_scene_entity *e, const ew_scene_model *m,
                                 const ew_ent_frame *ef) {
    ew_model_pose pose = {{e->origin[0], e->origin[1], e->origin[2]},
                          {e->angles[0], e->angles[1], e->angles[2]},
                          e->frame, e->skin, r->view.time, ef->ambient, ef->shade};
    if (m->kind == EW_MODEL_ALIAS) {
        /* Time walks a model through its frames at the game's 10 a second
         * (frame groups animate by their own intervals too). */
        const ew_mdl *mdl = m->data;
        if (r->view.time > 0 && mdl->numframes > 1)
            pose.frame = (int)(((long long)(r->view.time * 10) + e->frame) % mdl->numframes);
    }
    return pose;
}

void ew_pose_alias(ew_renderer *r, int item) {
    const struct ew_scene *sc = r->ents.scene;
    int i = r->ents.alias_list[item];
    const ew_scene_entity *e = &sc->ents[i];
    const ew_scene_model *m = &sc->models[e->model];
    const ew_ent_frame *ef = &r->ents.ent_frame[i];
    ew_model_pose pose = entity_pose(r, e, m, ef);
    ew_alias_xf *xf = &r->ents.xf[i];
    /* Sprite-cache: a reused image needs no vertex posed. */
    ew_sc_slot *slot = ew_sprite_cache_slot(r, i);
    if (slot) slot->use = 0;  /* not last frame's decision, whatever happens below */
    if (!ew_alias_place(r, m->data, &pose, xf)) return;
    if (ef->tinted) tint_palette(r, ef, i, xf);
    if (slot && ew_sprite_cache_reuse(r, slot, m->data, xf, &pose, ew_sprite_cache_tol(r))) return;
    ew_alias_pose_verts(r, m->data, &pose, xf, r->ents.xverts + ef->xvert0);
    if (slot) ew_sprite_cache_redraw(r, slot, m->data, xf, &pose);
}

/* The palette in the colour of the light under model i. */
static void tint_palette(ew_renderer *r, const ew_ent_frame *ef, int i, ew_alias_xf *xf) {
    /* The palette in the colour of the light under the model: a pixel table
     * in true colour, the nearest colours in 8-bit. */
    const ew_lightcurve *lc = &r->lit.curve;
    uint32_t *rgba = r->ents.tint_rgba + (size_t)i * 256;
    uint8_t *remap = r->ents.tint_remap + (size_t)i * 256;
    for (int c = 0; c < 256; c++) {
        int v[3];
        for (int k = 0; k < 3; k++) {
            int x = lc->fullbright[c] ? lc->palette[c * 3 + k] : (lc->palette[c * 3 + k] * ef->tint[k]) >> 8;
            v[k] = x > 255 ? 255 : x;
        }
        rgba[c] = ew_rgba(v[0], v[1], v[2]);
        remap[c] = lc->fullbright[c] || !r->lit.nearest ? (uint8_t)c : r->lit.nearest[ew_blend_at(&r->blend, v[0], v[1], v[2])];
    }
    xf->rgba = rgba, xf->remap = remap;
}

void ew_draw_models(ew_renderer *r, const ew_rows *rows) {
    const struct ew_scene *sc = r->ents.scene;
    if (!sc) return;
    for (int i = 0; i < r->ents.nent_frame && i < sc->nents; i++) {
        const ew_scene_entity *e = &sc->ents[i];
        const ew_ent_frame *ef = &r->ents.ent_frame[i];
        if (!ef->visible) continue;
        const ew_scene_model *m = &sc->models[e->model];
        ew_model_pose pose = entity_pose(r, e, m, ef);
        int drawn = 0;
        if (m->kind == EW_MODEL_ALIAS) {
            /* Posed once for the frame (ew_pose_alias), unless that had no
             * memory; from its cached image in sprite-cache mode. */
            const ew_sc_slot *slot = r->ents.nalias ? ew_sprite_cache_slot(r, i) : NULL;
            if (slot && slot->use) {
                ew_sprite_cache_draw(r, slot, rows);
                drawn = 1;
            } else {
                drawn = r->ents.nalias ? ew_alias_draw(r, m->data, &r->ents.xf[i], rows)
                                       : ew_draw_alias_rows(r, m->data, &pose, rows);
            }
        } else if (m->kind == EW_MODEL_SPRITE) {
            drawn = ew_draw_sprite_rows(r, m->data, &pose, rows);
        } else if (m->kind == EW_MODEL_BOX) {
            drawn = draw_box(r, m->data, e->model < r->ents.nbox_surfs ? r->ents.box_surfs[e->model] : NULL, e, i, rows);
        }
        if (rows->first) {
            if (drawn) rows->stats->entities_drawn++;
            else rows->stats->entities_culled++;
        }
    }
    if (sc->nparticles) ew_draw_particles_rows(r, sc->particles, sc->nparticles, rows);
}
