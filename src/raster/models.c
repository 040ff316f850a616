/* The scene's z-buffered moving things, drawn in each piece of the draw's
 * rows after its world spans: alias models, sprites, item boxes, then
 * particles (the "models" pass of scene/passes.c).  Which ones and their
 * light were settled once for the frame (world/entities.c); alias models
 * are posed and item boxes projected once for the frame too, in the pass's
 * parallel work, so a piece only rasterizes. */
#include "ew_util.h"
#include "raster/alias.h"
#include "world/edge_math.h"  /* ew_project */
#include "asset/scene.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
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

int ew_boxes_grow(ew_ents *en, int nents, int nfaces) {
    if (nents > en->max_box_frame) {
        ew_box_frame *bf = realloc(en->box_frame, sizeof *bf * (size_t)nents);
        if (bf) en->box_frame = bf;
        int *list = realloc(en->box_list, sizeof *list * (size_t)nents);
        if (list) en->box_list = list;
        if (!bf || !list) return -1;
        for (int i = en->max_box_frame; i < nents; i++) bf[i].frame = -1;
        en->max_box_frame = nents;
    }
    if (nfaces > en->max_box_faces) {
        ew_box_face *f = realloc(en->box_faces, sizeof *f * (size_t)nfaces);
        if (!f) return -1;
        en->box_faces = f, en->max_box_faces = nfaces;
    }
    return 0;
}

/* Does the opaque world hide every pixel of [x0, x1) x [y0, y1) (clipped
 * to the frame) from a thing nowhere nearer than 1/z = zi?  The world's
 * 1/z there comes from this frame's spans, each surface's 1/z plane taken
 * as the z-fill takes it (ew_face_zplane gives the gradients' zi_u, zi_v,
 * zi_0), so it is the z-buffer the thing would be tested against.  Along a
 * span 1/z is linear (and its rounded values monotone), so a span's two
 * ends bound it.  A row with no spans indexed, or a span of the background
 * (1/z 0), hides nothing. */
static int world_hides(const ew_models *md, const ew_frame *fr, int x0, int y0, int x1, int y1, float zi) {
    const ew_zfill *z = md->zf;
    const ew_world *w = fr->world;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > fr->target.width) x1 = fr->target.width;
    if (y1 > fr->target.height) y1 = fr->target.height;
    if (x0 >= x1 || y0 >= y1) return 0;
    /* The planes of the last few surfaces met: a thing's rows cross few. */
    enum { NPLANES = 8 };
    int psurf[NPLANES];
    float plane[NPLANES][3];
    for (int i = 0; i < NPLANES; i++) psurf[i] = -1;
    for (int y = y0; y < y1; y++) {
        const ew_span *sp;
        int sorted, n = ew_zfill_row_spans(z, y, x0, &sp, &sorted);
        if (n == 0) return 0;
        for (int i = 0; i < n; i++, sp++) {
            if (sp->u >= x1 && sorted) break;
            int a = sp->u > x0 ? sp->u : x0, e = sp->u + sp->count < x1 ? sp->u + sp->count : x1;
            if (a >= e) continue;
            const ew_surf *sf = &md->el->surfs[sp->surf];
            if (sp->surf == 0 || sf->face < 0) return 0;
            int slot = sp->surf & (NPLANES - 1);
            if (psurf[slot] != sp->surf) {
                ew_face_zplane(w, sf->view, &w->faces[sf->face], plane[slot]);
                psurf[slot] = sp->surf;
            }
            const float *pl = plane[slot];
            float z0 = pl[0] * sp->u + pl[1] * sp->v + pl[2];
            float za = z0 + (float)(a - sp->u) * pl[0], ze = z0 + (float)(e - 1 - sp->u) * pl[0];
            if (!(za > zi && ze > zi)) return 0;
        }
    }
    return 1;
}

/* A moving thing with screen box [umin, umax] x [vmin, vmax], none of it
 * behind the eye, and no pixel nearer than 1/z = zi_near, that the world
 * hides.  The box gets a pixel more each way (for snapped vertices), and
 * zi_near 2% more: a pixel's 1/z is interpolated between corners' or
 * vertices' that are at most zi_near, and 2% covers that arithmetic's
 * rounding many times over, so the test never hides a pixel that would
 * pass the z test. */
static int screen_box_hidden(const ew_models *md, const ew_frame *fr, float umin, float umax, float vmin, float vmax, float zi_near) {
    if (!fr->cfg.hide_occluded || !(umin <= umax && vmin <= vmax) || !(zi_near < 1e30f)) return 0;
    float wd = (float)fr->target.width, ht = (float)fr->target.height;
    int x0 = (int)floorf(fminf(fmaxf(umin, -2), wd)) - 1, x1 = (int)ceilf(fminf(fmaxf(umax, -2), wd)) + 2;
    int y0 = (int)floorf(fminf(fmaxf(vmin, -2), ht)) - 1, y1 = (int)ceilf(fminf(fmaxf(vmax, -2), ht)) + 2;
    return world_hides(md, fr, x0, y0, x1, y1, zi_near * 1.02f);
}

/* An alias model placed (ew_alias_place): its bounds' screen box and
 * nearest corner. */
static int alias_hidden(const ew_models *md, const ew_frame *fr, const ew_alias_xf *xf) {
    return !xf->behind && screen_box_hidden(md, fr, xf->umin, xf->umax, xf->vmin, xf->vmax, xf->zi_near);
}

/* A world-space box, every corner more than a unit in front of the eye
 * (ew_project clamps a corner to the frame's border, as the test's box is
 * clamped anyway). */
static int box_hidden(const ew_models *md, const ew_frame *fr, const float lo[3], const float hi[3]) {
    float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f, zi_near = 0;
    for (int c = 0; c < 8; c++) {
        const float p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
        ew_proj j;
        ew_project(&fr->view, p, &j);
        if (!(j.zi < 1.0f)) return 0;  /* near the eye or behind it (or NaN) */
        umin = fminf(umin, j.u), umax = fmaxf(umax, j.u), vmin = fminf(vmin, j.v), vmax = fmaxf(vmax, j.v);
        zi_near = fmaxf(zi_near, j.zi);
    }
    return screen_box_hidden(md, fr, umin, umax, vmin, vmax, zi_near);
}

/* Item box entity ei this frame: its corners moved and projected once for
 * the faces that share them, its faces turned to the eye projected and
 * oriented, the rows they reach, and the faces left to fill (those with a
 * pixel centre inside and a surface to draw).  Once a frame, on any
 * thread; the pieces of the draw only fill (draw_box). */
static void prepare_box(const ew_models *md, const ew_frame *fr, int ei) {
    const struct ew_scene *sc = md->ents->scene;
    const ew_scene_entity *e = &sc->ents[ei];
    const ew_world *bw = sc->models[e->model].data;
    const ew_box_surfs *surfs = e->model < md->ents->nbox_surfs ? md->ents->box_surfs[e->model] : NULL;
    const ew_model *m = &bw->models[0];
    ew_box_frame *bf = &md->ents->box_frame[ei];
    ew_box_face *out = md->ents->box_faces + bf->face0;
    const int h = fr->target.height;
    bf->frame = md->marks->framecount;
    bf->in_view = bf->nfaces = bf->dropped = bf->zrect = bf->hidden = 0;
    bf->y0 = bf->y1 = 0;
    float ax[3][3];
    ew_entity_axes(e->angles, ax);
    /* Its vertices' box (ew_scene_model.lo, hi), moved: it holds every pixel
     * of its faces. */
    const ew_scene_model *sm = &sc->models[e->model];
    float lo[3], hi[3];
    ew_moved_box(ax, e->origin, sm->lo, sm->hi, lo, hi);
    if (ew_cull_box(&fr->view, lo, hi, 15) < 0) return;
    if (box_hidden(md, fr, lo, hi)) {
        bf->hidden = 1;
        return;
    }
    ew_view_to_model(&fr->view, ax, e->origin, &bf->mv);
    box_corner corner[BOX_CORNERS];
    uint8_t made[BOX_CORNERS];
    int16_t front[BOX_FACES];
    int shared = bw->numverts <= BOX_CORNERS && m->numfaces <= BOX_FACES, nfront = 0;
    /* The faces turned to the eye and their corners first: when the
     * frustum cuts none of them, the z-fill of the rectangle around them
     * all serves every face (the world's 1/z, wherever it is filled, is the
     * same values). */
    if (shared) {
        memset(made, 0, (size_t)bw->numverts);
        float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
        int cut = 0;
        for (int i = 0; i < m->numfaces; i++) {
            const ew_face *f = &bw->faces[m->firstface + i];
            if (!box_face_front(bw, f, &bf->mv)) continue;
            front[nfront++] = (int16_t)i;
            for (int k = 0; k < f->numedges; k++) {  /* every one, for the faces below */
                const box_corner *bc = box_corner_at(&fr->view, bw, ax, e->origin, corner, made, ew_face_vertex(bw, f, k));
                cut |= bc->out;
                if (cut) continue;
                if (bc->u < umin) umin = bc->u;
                if (bc->u > umax) umax = bc->u;
                if (bc->v < vmin) vmin = bc->v;
                if (bc->v > vmax) vmax = bc->v;
            }
        }
        if (!cut && umin <= umax) {
            /* ew_zpoly_close's rectangle, of all the corners: it holds every face's */
            bf->zrect = 1;
            bf->zx0 = ew_ceilf_int(umin), bf->zx1 = ew_ceilf_int(umax);
            bf->zy0 = ew_ceilf_int(vmin), bf->zy1 = ew_ceilf_int(vmax);
        }
    }
    int in_view = 0, fy0 = h, fy1 = 0;
    for (int fi = 0, nf = shared ? nfront : m->numfaces; fi < nf; fi++) {
        int i = shared ? front[fi] : fi;
        const ew_face *f = &bw->faces[m->firstface + i];
        if (!shared && !box_face_front(bw, f, &bf->mv)) continue;
        int lit = !(f->flags & (EW_SURF_SKY | EW_SURF_TURB));
        int has_surf = !lit || (surfs && i < surfs->nfaces && surfs->face[i].built);
        ew_zpoly *zp = &out[bf->nfaces].zp;
        int n = f->numedges, cut = 0;
        float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
        if (shared) {
            /* Unclipped, the polygon is its corners as they are (made above). */
            zp->nearzi = 0;
            for (int k = 0; k < n && !cut; k++) {
                const box_corner *bc = &corner[ew_face_vertex(bw, f, k)];
                cut = bc->out;
                zp->u[k] = bc->u, zp->v[k] = bc->v;
                if (bc->zi > zp->nearzi) zp->nearzi = bc->zi;
                if (bc->u < umin) umin = bc->u;
                if (bc->u > umax) umax = bc->u;
                if (bc->v < vmin) vmin = bc->v;
                if (bc->v > vmax) vmax = bc->v;
            }
        }
        int holds;  /* its rectangle holds a pixel centre */
        if (!shared || cut) {
            float p[EW_MAX_POLY][3];
            for (int k = 0; k < n; k++) box_move(ax, e->origin, bw->verts[ew_face_vertex(bw, f, k)], p[k]);
            if (!ew_zpoly_project(&fr->view, p, n, zp)) continue;
            holds = zp->x0 <= zp->x1 && zp->y0 <= zp->y1;
        } else {
            if (n < 3) continue;
            holds = ew_zpoly_rect(&fr->view, zp, n, umin, umax, vmin, vmax);
            /* Most faces of a far box fall between pixel centres: once the
             * box is known to be in view (and no surface is missing, which
             * is counted below), their orientation tells nothing. */
            if (!holds && in_view && has_surf) continue;
            if (!ew_zpoly_orient(zp)) continue;
        }
        in_view = 1;
        int ylo = zp->y0 < zp->y1 ? zp->y0 : zp->y1, yhi = (zp->y0 > zp->y1 ? zp->y0 : zp->y1) + 1;
        if (!has_surf) {  /* no memory for it */
            bf->dropped++;
            continue;
        }
        if (!holds) continue;  /* nothing to fill, and an empty z-fill rectangle */
        if (ylo < fy0) fy0 = ylo;
        if (yhi > fy1) fy1 = yhi;
        out[bf->nfaces++].face = i;
    }
    bf->in_view = in_view;
    bf->y0 = fy0 < 0 ? 0 : fy0 > h ? h : fy0;
    bf->y1 = fy1 < bf->y0 ? bf->y0 : fy1 > h ? h : fy1;
}

/* An item box in the rows of one piece of the draw: its prepared faces
 * filled, z-buffered; whether it is in view. */
static int draw_box(const ew_models *md, const ew_frame *fr, const ew_world *bw, const ew_box_surfs *surfs, int ei, const ew_rows *rows) {
    if (ei >= md->ents->max_box_frame || md->ents->box_frame[ei].frame != md->marks->framecount) return 0;
    const ew_box_frame *bf = &md->ents->box_frame[ei];
    if (rows->first) rows->stats->dropped += bf->dropped;
    if (bf->y1 <= rows->y0 || bf->y0 >= rows->y1) return bf->in_view;
    if (bf->zrect)
        ew_zfill_rect(md->zf, bf->zx0, bf->zy0 > rows->y0 ? bf->zy0 : rows->y0, bf->zx1,
                      bf->zy1 < rows->y1 ? bf->zy1 : rows->y1);
    const ew_model *m = &bw->models[0];
    long won = 0;
    for (int k = 0; k < bf->nfaces; k++) {
        const ew_box_face *bx = &md->ents->box_faces[bf->face0 + k];
        const ew_zpoly *zp = &bx->zp;
        if (zp->y1 < rows->y0 || zp->y0 >= rows->y1) continue;  /* another piece's rows */
        const ew_face *f = &bw->faces[m->firstface + bx->face];
        ew_zpoly_look look = {bw, f, &bf->mv, ew_face_texture(bw, f, fr->view.time), NULL, 0, 0, 1, EW_ZP_OPAQUE,
                              NULL, 256};
        if (!(f->flags & (EW_SURF_SKY | EW_SURF_TURB))) {
            const ew_box_surf *bs = &surfs->face[bx->face];  /* built: prepare_box kept only such */
            look.mip = ew_face_mip(&fr->view, bw, f, zp->nearzi);
            look.surf = bs->pixels[look.mip], look.surf_width = bs->width[look.mip];
        }
        if (!bf->zrect)
            ew_zfill_rect(md->zf, zp->x0, zp->y0 > rows->y0 ? zp->y0 : rows->y0, zp->x1 + 1,
                          zp->y1 + 1 < rows->y1 ? zp->y1 + 1 : rows->y1);
        won += ew_zpoly_fill(md->draw, zp, &look, NULL, 0, rows->y0, rows->y1);
    }
    rows->stats->alias_pixels += won;
    return bf->in_view;
}

static void tint_palette(const ew_models *md, const ew_ent_frame *ef, int i, ew_alias_xf *xf);

/* An entity's pose this frame. */
static ew_model_pose entity_pose(const ew_frame *fr, const ew_scene_entity *e, const ew_scene_model *m,
                                 const ew_ent_frame *ef) {
    ew_model_pose pose = {{e->origin[0], e->origin[1], e->origin[2]},
                          {e->angles[0], e->angles[1], e->angles[2]},
                          e->frame, e->skin, fr->view.time, ef->ambient, ef->shade};
    if (m->kind == EW_MODEL_ALIAS) {
        /* Time walks a model through its frames at the game's 10 a second
         * (frame groups animate by their own intervals too). */
        const ew_mdl *mdl = m->data;
        if (fr->view.time > 0 && mdl->numframes > 1)
            pose.frame = (int)(((long long)ew_int_checked(fr->view.time * 10, 0, INT_MAX, 0) + e->frame) % mdl->numframes);
    }
    return pose;
}

/* The models pass's work: the frame's visible alias models posed, then its
 * item boxes projected. */
void ew_models_work(const ew_models *md, const ew_frame *fr, int item) {
    if (item >= md->ents->nalias) {
        prepare_box(md, fr, md->ents->box_list[item - md->ents->nalias]);
        return;
    }
    const struct ew_scene *sc = md->ents->scene;
    int i = md->ents->alias_list[item];
    const ew_scene_entity *e = &sc->ents[i];
    const ew_scene_model *m = &sc->models[e->model];
    const ew_ent_frame *ef = &md->ents->ent_frame[i];
    ew_model_pose pose = entity_pose(fr, e, m, ef);
    ew_alias_xf *xf = &md->ents->xf[i];
    /* Sprite-cache: a reused image needs no vertex posed. */
    ew_sc_slot *slot = ew_sprite_cache_slot(md->ents->sprite_cache, fr, i);
    if (slot) slot->use = 0;  /* not last frame's decision, whatever happens below */
    if (!ew_alias_place(fr, m->data, &pose, xf)) return;
    if (alias_hidden(md, fr, xf)) {
        xf->visible = 0, xf->hidden = 1;  /* nothing to pose or draw */
        return;
    }
    if (ef->tinted) tint_palette(md, ef, i, xf);
    if (slot && ew_sprite_cache_reuse(fr, slot, m->data, xf, &pose, ew_sprite_cache_tol(md->ents->sprite_cache))) return;
    ew_alias_pose_verts(fr, m->data, &pose, xf, md->ents->xverts + ef->xvert0);
    if (slot) ew_sprite_cache_redraw(fr, slot, m->data, xf, &pose);
}

/* The palette in the colour of the light under model i. */
static void tint_palette(const ew_models *md, const ew_ent_frame *ef, int i, ew_alias_xf *xf) {
    /* The palette in the colour of the light under the model: a pixel table
     * in true colour, the nearest colours in 8-bit. */
    const ew_lightcurve *lc = &md->lit->curve;
    uint32_t *rgba = md->ents->tint_rgba + (size_t)i * 256;
    uint8_t *remap = md->ents->tint_remap + (size_t)i * 256;
    for (int c = 0; c < 256; c++) {
        int v[3];
        for (int k = 0; k < 3; k++) {
            int x = lc->fullbright[c] ? lc->palette[c * 3 + k] : (lc->palette[c * 3 + k] * ef->tint[k]) >> 8;
            v[k] = x > 255 ? 255 : x;
        }
        rgba[c] = ew_rgba(v[0], v[1], v[2]);
        remap[c] = lc->fullbright[c] || !md->lit->nearest ? (uint8_t)c : md->lit->nearest[ew_blend_at(md->lit->blend, v[0], v[1], v[2])];
    }
    xf->rgba = rgba, xf->remap = remap;
}

/* Entity i (of model kind) was left out because the world hides it. */
static int entity_hidden(const ew_models *md, int i, int kind) {
    if (kind == EW_MODEL_ALIAS) return md->ents->nalias && md->ents->xf[i].hidden;
    return kind == EW_MODEL_BOX && i < md->ents->max_box_frame && md->ents->box_frame[i].frame == md->marks->framecount &&
           md->ents->box_frame[i].hidden;
}

void ew_draw_models(const ew_models *md, const ew_frame *fr, const ew_rows *rows) {
    const struct ew_scene *sc = md->ents->scene;
    if (!sc) return;
    for (int i = 0; i < md->ents->nent_frame && i < sc->nents; i++) {
        const ew_scene_entity *e = &sc->ents[i];
        const ew_ent_frame *ef = &md->ents->ent_frame[i];
        if (!ef->visible) continue;
        const ew_scene_model *m = &sc->models[e->model];
        ew_model_pose pose = entity_pose(fr, e, m, ef);
        int drawn = 0;
        if (m->kind == EW_MODEL_ALIAS) {
            /* Posed once for the frame (ew_pose_alias), unless that had no
             * memory; from its cached image in sprite-cache mode. */
            const ew_sc_slot *slot = md->ents->nalias ? ew_sprite_cache_slot(md->ents->sprite_cache, fr, i) : NULL;
            if (slot && slot->use) {
                ew_sprite_cache_draw(fr, md->zf, slot, rows);
                drawn = 1;
            } else {
                drawn = md->ents->nalias ? ew_alias_draw(fr, md->zf, m->data, &md->ents->xf[i], rows)
                                       : ew_draw_alias_rows(fr, md->zf, m->data, &pose, rows);
            }
        } else if (m->kind == EW_MODEL_SPRITE) {
            drawn = ew_draw_sprite_rows(fr, md->zf, m->data, &pose, rows);
        } else if (m->kind == EW_MODEL_BOX) {
            drawn = draw_box(md, fr, m->data, e->model < md->ents->nbox_surfs ? md->ents->box_surfs[e->model] : NULL, i, rows);
        }
        if (rows->first) {
            if (drawn) rows->stats->entities_drawn++;
            else rows->stats->entities_culled++;
            if (!drawn && entity_hidden(md, i, m->kind)) rows->stats->entities_hidden++;
        }
    }
    if (sc->nparticles) ew_draw_particles_rows(fr, md->zf, sc->particles, sc->nparticles, rows);
}
