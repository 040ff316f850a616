/* Moving things over the world: brush model entities in the edge list
 * (doors occlude, zero overdraw kept, agreement with the reference path
 * extended to them) and dynamic lights (exactly the faces in reach are
 * rebuilt, the rest stay cached). */
#include "edgewise_lab.h"
#include "util.h"
#include "renderer.h"
#include "asset/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200

static int is_submodel_face(const ew_world *w, int face) {
    return face >= 0 && face >= w->models[0].firstface + w->models[0].numfaces;
}

static void agreement(const char *map, double limit) {
    char path[256];
    ew_error err;
    snprintf(path, sizeof path, "data/librequake/maps/%s.bsp", map);
    ew_assets *a = ew_assets_create(ew_t_shared(path), NULL, &err);
    if (!a) {
        CHECK(0, "%s", err.msg);
        return;
    }
    ew_scene *sc = ew_scene_create_from_map(a->world, ew_t_shared(path), NULL, &err);
    CHECK(sc != NULL, "%s", err.msg);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    ew_set_scene(r, sc);
    ew_enable_face_ids(r, 1);
    ew_camera views[EW_MAX_VIEWS];
    int nv = ew_benchmark_views(a->world, views), sub_pixels = 0;
    int *ids = malloc(sizeof(int) * W * H), *ref = malloc(sizeof(int) * W * H);
    uint8_t *px = malloc(W * H), *ref_px = malloc(W * H);
    double worst = 1, sum = 0, worst_col = 1;
    int drawn = 0, tris = 0;
    int nents, unknown, missing;
    ew_scene_counts(sc, &nents, &unknown, &missing);
    CHECK(nents > 10 && missing == 0, "%s: %d entities, %d unknown, %d missing", map, nents, unknown, missing);
    /* Exact texturing in both paths, so colours compare pixel for pixel,
     * models included (they meet each path's own z-buffer). */
    ew_set_subdivision(r, 1);
    for (int v = 0; v < nv; v++) {
        ew_stats st;
        CHECK(ew_render(r, &views[v], &st) == 0, "%s view %d", map, v);
        memcpy(px, ew_frame_pixels(r), W * H);
        drawn += st.entities_drawn, tris += st.alias_tris;
        CHECK(st.overdraw == 1.0 && st.pixels_covered == st.pixels && st.dropped == 0,
              "%s view %d with entities: overdraw %g, covered %ld of %ld, dropped %d", map, v,
              st.overdraw, st.pixels_covered, st.pixels, st.dropped);
        memcpy(ids, ew_frame_face_ids(r), sizeof(int) * W * H);
        CHECK(ew_render_reference(r, &views[v], ref_px, ref, &err) == 0, "%s", err.msg);
        long same = 0, same_col = 0;
        for (int i = 0; i < W * H; i++) {
            same += ids[i] == ref[i];
            same_col += px[i] == ref_px[i];
            sub_pixels += is_submodel_face(a->world, ids[i]);
        }
        double ag = (double)same / (W * H), agc = (double)same_col / (W * H);
        CHECK(ag >= limit, "%s view %d with entities: %.2f%% agree with the reference", map, v, 100 * ag);
        CHECK(agc >= limit, "%s view %d with entities: colours %.2f%% agree with the reference", map, v, 100 * agc);
        if (agc < worst_col) worst_col = agc;
        sum += ag;
        if (ag < worst) worst = ag;
    }
    CHECK(sub_pixels > 0, "%s: no brush model pixel in any view", map);
    CHECK(drawn > nv && tris > 0, "%s: %d entities drawn, %d alias triangles over the views", map, drawn, tris);
    printf("entities agreement %-6s views %2d  surfaces: mean %.3f%% worst %.3f%%  colours worst %.3f%%  "
           "brush-model pixels %d, entities drawn %d, alias triangles %d\n",
           map, nv, 100 * sum / nv, 100 * worst, 100 * worst_col, sub_pixels, drawn, tris);
    free(ids), free(ref), free(px), free(ref_px);
    ew_renderer_destroy(r);
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

/* Trigger volumes are not drawn: start has 26 func_wall brush entities and
 * 26 trigger brushes (trigger_once, _teleport, _changelevel); only the
 * walls join the scene, and no face of a trigger's submodel is in view. */
static void triggers_hidden(void) {
    ew_error err;
    const char *path = ew_t_shared("data/librequake/maps/start.bsp");
    ew_assets *a = ew_assets_create(path, NULL, &err);
    CHECK(a != NULL, "%s", a ? "" : err.msg);
    if (!a) return;
    ew_scene *sc = ew_scene_create_from_map(a->world, path, NULL, &err);
    CHECK(sc != NULL, "%s", sc ? "" : err.msg);
    int brushes = 0;
    for (int i = 0; sc && i < sc->nents; i++) brushes += sc->ents[i].model < 0;
    CHECK(brushes == 26, "start: %d brush entities in the scene, want its 26 func_wall", brushes);
    ew_scene_destroy(sc);
    ew_assets_destroy(a);
}

int main(void) {
    if (!ew_t_need_shared("data/librequake/maps/e1m1.bsp")) return ew_t_finish();
    agreement("e1m1", 0.98);
    agreement("start", 0.98);
    triggers_hidden();

    ew_error err;
    ew_assets *a = NULL;
    const char *path = ew_t_shared("data/librequake/maps/e1m1.bsp");
    CHECK((a = ew_assets_create(path, NULL, &err)) != NULL, "%s", err.msg);
    if (!a) return ew_t_finish();
    ew_camera views[EW_MAX_VIEWS];
    ew_benchmark_views(a->world, views);
    ew_scene *sc = ew_scene_create_from_map(a->world, path, NULL, &err);
    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){ .world = a->world, .palette = a->palette,
            .colormap = a->colormap, .width = W, .height = H, .threads = 1 }, &err);
    ew_enable_face_ids(r, 1);
    int *world_ids = malloc(sizeof(int) * W * H);
    float *world_z = malloc(sizeof(float) * W * H);

    /* The closed door at e1m1's start: without it the room beyond shows;
     * with it every pixel there is the door, nearer than what it hides. */
    ew_render(r, &views[0], NULL);
    memcpy(world_ids, ew_frame_face_ids(r), sizeof(int) * W * H);
    memcpy(world_z, ew_frame_zbuffer(r), sizeof(float) * W * H);
    ew_set_scene(r, sc);
    ew_stats st;
    ew_render(r, &views[0], &st);
    long door = 0, nearer = 0;
    for (int i = 0; i < W * H; i++)
        if (is_submodel_face(a->world, ew_frame_face_ids(r)[i])) {
            door++;
            nearer += ew_frame_zbuffer(r)[i] > world_z[i] && !is_submodel_face(a->world, world_ids[i]);
        }
    CHECK(door > W * H / 10 && nearer == door, "door covers %ld px, %ld of them in front of the world", door, nearer);
    CHECK(st.overdraw == 1.0 && st.pixels_covered == st.pixels, "door view overdraw %g", st.overdraw);
    CHECK(st.entities_drawn >= 1, "entities drawn %d", st.entities_drawn);

    /* A soldier in front of the door is drawn; the same soldier behind the
     * closed door (in the room beyond) passes the frustum but is hidden. */
    uint8_t *mdl_data;
    size_t mdl_size;
    CHECK(ew_read_file(ew_t_shared("data/librequake/progs/soldier.mdl"), &mdl_data, &mdl_size, &err) == 0, "%s", err.msg);
    int soldier = ew_scene_load_model(sc, "progs/soldier.mdl", mdl_data, mdl_size, &err);
    CHECK(soldier >= 0, "%s", err.msg);
    free(mdl_data);
    const float *eye = views[0].origin;  /* looking along +x at the door */
    float front[3] = {eye[0] + 100, eye[1], eye[2] - 20}, behind[3] = {eye[0] + 420, eye[1], eye[2] - 20};
    int ent = ew_scene_add_entity(sc, soldier, front, NULL, 0, 0);
    CHECK(ent >= 0, "add entity");
    ew_stats sm;
    ew_render(r, &views[0], &sm);
    long in_front = sm.alias_pixels;
    CHECK(in_front > 500 && sm.alias_tris > 0, "soldier in front: %ld pixels, %d triangles", in_front, sm.alias_tris);
    /* Move it behind the door: same frustum, hidden by the door's z. */
    ew_scene *hidden = ew_scene_create_from_map(a->world, path, NULL, &err);
    CHECK(ew_read_file(ew_t_shared("data/librequake/progs/soldier.mdl"), &mdl_data, &mdl_size, &err) == 0, "%s", err.msg);
    int s2 = ew_scene_load_model(hidden, "progs/soldier.mdl", mdl_data, mdl_size, &err);
    free(mdl_data);
    ew_scene_add_entity(hidden, s2, behind, NULL, 0, 0);
    ew_set_scene(r, hidden);
    /* The door's 1/z hides its whole screen box: it is not even drawn
     * (raster/models.c); drawn anyway, every pixel fails the z test. */
    ew_render(r, &views[0], &sm);
    CHECK(sm.alias_pixels == 0 && sm.alias_tris == 0 && sm.entities_hidden == 1,
          "soldier behind the closed door: %ld pixels from %d triangles, %d hidden", sm.alias_pixels, sm.alias_tris,
          sm.entities_hidden);
    ew_set_hide_occluded(r, 0);
    ew_render(r, &views[0], &sm);
    CHECK(sm.alias_pixels == 0 && sm.alias_tris > 0 && sm.entities_hidden == 0,
          "soldier behind the closed door, drawn: %ld pixels from %d triangles", sm.alias_pixels, sm.alias_tris);
    ew_set_hide_occluded(r, 1);
    printf("soldier: %ld pixels in front of the door; behind it %ld pixels, %d triangles tested "
           "(entities drawn %d, culled %d)\n", in_front, sm.alias_pixels, sm.alias_tris,
           sm.entities_drawn, sm.entities_culled);
    ew_scene_destroy(hidden);
    ew_set_scene(r, sc);

    /* A door pushed into a wall is cut by the world BSP: still one write per pixel. */
    ew_scene *moved = ew_scene_create(a->world, &err);
    for (int sub = 1; sub < a->world->nummodels; sub++) {
        float off[3] = {(float)(sub % 3) * 40 - 40, (float)(sub % 5) * 20 - 40, 0}, ang[3] = {0, (float)(sub * 7 % 30), 0};
        ew_scene_add_brush(moved, sub, off, ang);
    }
    ew_set_scene(r, moved);
    ew_camera *vs = views;
    for (int v = 0; v < 29; v++) {
        ew_render(r, &vs[v], &st);
        CHECK(st.overdraw == 1.0 && st.pixels_covered == st.pixels && st.dropped == 0,
              "moved brush models, view %d: overdraw %g covered %ld", v, st.overdraw, st.pixels_covered);
    }

    /* Dynamic light: exactly the faces it reaches are rebuilt. */
    const int dv = 12;  /* a big room: some faces in reach of the light, most not */
    ew_set_scene(r, sc);
    ew_render(r, &views[dv], &st);
    ew_render(r, &views[dv], &st);  /* everything cached now */
    CHECK(st.surfaces_built == 0, "warm frame built %d", st.surfaces_built);
    float at[3] = {views[dv].origin[0], views[dv].origin[1], views[dv].origin[2] - 30};
    float radius = 80;
    CHECK(ew_scene_add_dlight(sc, at, radius) == 0, "add dlight");
    ew_stats sd;
    ew_render(r, &views[dv], &sd);
    int lit = 0, lit_far = 0, near_unlit = 0, drawn = 0;
    /* Count each lit surface once: brush faces come in fragments. */
    const ew_cached_surf **seen = calloc((size_t)r->el.nsurfs, sizeof *seen);
    for (int s = 1; s < r->el.nsurfs; s++) {
        int fi = r->el.surfs[s].face;
        const ew_face *f = &a->world->faces[fi];
        if (f->flags & (EW_SURF_SKY | EW_SURF_TURB) || !r->lit.surf_cache[s]) continue;
        int dup = 0;
        for (int k = 0; k < drawn && !dup; k++) dup = seen[k] == r->lit.surf_cache[s];
        if (dup) continue;
        seen[drawn] = r->lit.surf_cache[s];
        drawn++;
        const ew_plane *pl = &a->world->planes[f->plane];
        float d = fabsf(at[0] * pl->normal[0] + at[1] * pl->normal[1] + at[2] * pl->normal[2] - pl->dist);
        float closest = 1e30f;
        for (int k = 0; k < f->numedges; k++) {
            const float *p = a->world->verts[ew_face_vertex(a->world, f, k)];
            float dx = p[0] - at[0], dy = p[1] - at[1], dz = p[2] - at[2];
            float dist = sqrtf(dx * dx + dy * dy + dz * dz);
            if (dist < closest) closest = dist;
        }
        int marked = ew_face_dlights(&r->marks, fi) != 0;
        lit += marked;
        lit_far += marked && d > radius;
        near_unlit += !marked && closest < radius;
    }
    CHECK(lit > 0 && lit < drawn && sd.surfaces_rebuilt_by_dlights == lit, "dlight: %d faces in reach, %d rebuilt", lit,
          sd.surfaces_rebuilt_by_dlights);
    CHECK(sd.surfaces_cached == drawn - lit, "dlight: %d cached of %d drawn (%d lit)", sd.surfaces_cached, drawn, lit);
    CHECK(lit_far == 0 && near_unlit == 0, "dlight reach: %d marked beyond the radius, %d near faces missed",
          lit_far, near_unlit);
    printf("dlight radius %.0f: %d of %d drawn surfaces rebuilt, %d cached\n", radius, lit, drawn, sd.surfaces_cached);

    /* Bands: the same frames, world and moving things, with 1, 2, 3, 7 and
     * 64 threads (different band boundaries every time; 64, the cap, runs
     * oversubscribed on a small machine, more threads than the 25 bands of
     * 200 rows) are identical. */
    float glow[3] = {views[8].origin[0], views[8].origin[1] + 40, views[8].origin[2]};
    ew_scene_add_dlight(sc, glow, 200);
    ew_scene_add_particles(sc, 2000, glow, 120, 7);
    uint8_t *one = malloc(W * H);
    long differ = 0;
    int compared = 0;
    for (int v = 0; v < 29; v += 4) {
        ew_set_threads(r, 1);
        ew_stats s1, sn;
        ew_render(r, &views[v], &s1);
        memcpy(one, ew_frame_pixels(r), W * H);
        int counts[4] = {2, 3, 7, EW_MAX_THREADS};
        for (int k = 0; k < 4; k++) {
            CHECK(ew_set_threads(r, counts[k]) == counts[k], "threads %d", counts[k]);
            ew_render(r, &views[v], &sn);
            ew_render(r, &views[v], &sn);  /* bands re-cut by the first frame's cost */
            for (int i = 0; i < W * H; i++) differ += one[i] != ew_frame_pixels(r)[i];
            CHECK(sn.alias_tris == s1.alias_tris && sn.particles == s1.particles &&
                      sn.entities_drawn == s1.entities_drawn && sn.overdraw == 1.0,
                  "view %d, %d threads: counters differ (tris %d/%d, particles %d/%d, drawn %d/%d)", v,
                  counts[k], sn.alias_tris, s1.alias_tris, sn.particles, s1.particles, sn.entities_drawn,
                  s1.entities_drawn);
            compared++;
        }
    }
    CHECK(differ == 0, "%ld pixels differ between 1 thread and several", differ);
    printf("threads: %d frames with 2, 3, 7 and %d threads identical to 1 thread\n", compared, EW_MAX_THREADS);
    ew_set_threads(r, 1);
    free(one);

    free(world_ids), free(world_z), free((void *)seen);
    ew_renderer_destroy(r);
    ew_scene_destroy(sc);
    ew_scene_destroy(moved);
    ew_assets_destroy(a);
    return ew_t_finish();
}
