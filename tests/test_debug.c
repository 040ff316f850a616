/* Debug modes (ew_set_debug, ew_set_pvs_lock) on real frames of e1m1 at
 * 320x200, in both pixel formats: each mode's picture is checked against
 * what it claims to show, and turning a mode off gives the normal frame
 * back byte for byte.  EW_DEBUG_PICTURES=DIR writes one PNG per mode there
 * (docs/debug/). */
#include "util.h"
#include "edgewise_lab.h"
#include "renderer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 320
#define H 200

static const ew_debug_mode all_modes[] = {EW_DEBUG_SPANS,    EW_DEBUG_EDGES,    EW_DEBUG_OVERDRAW, EW_DEBUG_LIGHTING,
                                          EW_DEBUG_TEXTURES, EW_DEBUG_MIPS,     EW_DEBUG_BUILDS};
static const char *const mode_names[] = {"none", "spans", "edges", "overdraw", "lighting", "textures", "mips", "builds"};

static ew_assets *A;
static ew_camera views[EW_MAX_VIEWS];
static int nviews;

static ew_renderer *make(ew_color_mode color, int classic) {
    ew_renderer_desc d = {0};
    d.world = A->world, d.palette = A->palette, d.colormap = A->colormap;
    d.width = W, d.height = H, d.threads = 2, d.color = color, d.classic = classic;
    ew_error err = {""};
    ew_renderer *r = ew_renderer_create(&d, &err);
    CHECK(r != NULL, "%s", err.msg);
    return r;
}

static size_t frame_bytes(const ew_renderer *r) { return (size_t)W * H * (size_t)r->f.target.bpp; }
static uint8_t *copy_frame(const ew_renderer *r) {
    uint8_t *p = malloc(frame_bytes(r));
    memcpy(p, r->f.target.pixels, frame_bytes(r));
    return p;
}
/* Pixel i as a number (palette index or the 4 bytes). */
static uint32_t px(const ew_renderer *r, const uint8_t *f, size_t i) {
    if (r->f.target.bpp == 1) return f[i];
    uint32_t v;
    memcpy(&v, f + i * 4, 4);
    return v;
}
static double brightness(const ew_renderer *r, const uint8_t *f, size_t i) {
    int rgb[3];
    if (r->f.target.bpp == 1) {
        for (int k = 0; k < 3; k++) rgb[k] = r->f.palette[f[i] * 3 + k];
    } else {
        ew_rgba_split(px(r, f, i), rgb);
    }
    return 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2];
}

static ew_stats render(ew_renderer *r, const ew_camera *c) {
    ew_stats st;
    memset(&st, 0, sizeof st);
    CHECK(ew_render(r, c, &st) == 0, "render");
    return st;
}

static const char *color_name(const ew_renderer *r) { return r->f.target.bpp == 1 ? "8-bit" : "true colour"; }

/* Each mode on, then off: the normal frame again, byte for byte (the
 * cache holds surfaces of the debug mode in between). */
static void modes_off_give_normal(ew_renderer *r, const ew_camera *c) {
    render(r, c);
    uint8_t *normal = copy_frame(r);
    for (size_t m = 0; m < sizeof all_modes / sizeof *all_modes; m++) {
        CHECK(ew_set_debug(r, all_modes[m]) == 0 && ew_get_debug(r) == all_modes[m], "set %s", mode_names[all_modes[m]]);
        render(r, c);
        /* builds on a warm cache: nothing to show */
        int differs = memcmp(normal, r->f.target.pixels, frame_bytes(r)) != 0 || all_modes[m] == EW_DEBUG_BUILDS;
        CHECK(differs, "%s: mode %s changes the frame", color_name(r), mode_names[all_modes[m]]);
        ew_set_debug(r, EW_DEBUG_NONE);
        render(r, c);
        CHECK(memcmp(normal, r->f.target.pixels, frame_bytes(r)) == 0, "%s: %s off gives the normal frame back",
              color_name(r), mode_names[all_modes[m]]);
    }
    free(normal);
}

/* Spans: runs of one colour along each row are the spans, one for one. */
static void spans(ew_renderer *r, const ew_camera *c) {
    ew_set_debug(r, EW_DEBUG_SPANS);
    ew_stats st = render(r, c);
    long runs = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            runs += x == 0 || px(r, r->f.target.pixels, (size_t)y * W + x) != px(r, r->f.target.pixels, (size_t)y * W + x - 1);
    CHECK(runs == st.spans && st.spans > H, "%s: %ld runs of one colour, %d spans", color_name(r), runs, st.spans);
    printf("spans (%s): %d spans, %ld runs\n", color_name(r), st.spans, runs);
    ew_set_debug(r, EW_DEBUG_NONE);
}

/* Edges: the frame as normal except edge pixels, which are the edge colour;
 * the reference method has no edge list: its frame is unchanged. */
static void edges(ew_renderer *r, const ew_camera *c) {
    ew_stats st = render(r, c);
    uint8_t *normal = copy_frame(r);
    ew_set_debug(r, EW_DEBUG_EDGES);
    render(r, c);
    long changed = 0, wrong = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        if (px(r, normal, i) == px(r, r->f.target.pixels, i)) continue;
        changed++;
        wrong += px(r, r->f.target.pixels, i) != r->dbg.edge;
    }
    CHECK(changed > 2 * H && wrong == 0, "%s: %ld pixels changed, %ld not the edge colour", color_name(r), changed, wrong);
    printf("edges (%s): %d edges, %ld pixels changed to the edge colour\n", color_name(r), st.edges, changed);
    ew_set_hsr(r, EW_HSR_REFERENCE);
    ew_set_debug(r, EW_DEBUG_NONE);
    render(r, c);
    uint8_t *ref = copy_frame(r);
    ew_set_debug(r, EW_DEBUG_EDGES);
    render(r, c);
    CHECK(memcmp(ref, r->f.target.pixels, frame_bytes(r)) == 0, "reference method: no edges drawn");
    ew_set_hsr(r, EW_HSR_EDGE);
    ew_set_debug(r, EW_DEBUG_NONE);
    free(normal), free(ref);
}

static long count_colour(const ew_renderer *r, uint32_t colour) {
    long n = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) n += px(r, r->f.target.pixels, i) == colour;
    return n;
}

/* Overdraw: the edge list alone writes every world pixel once; models and
 * see-through surfaces add writes. */
static void overdraw(ew_color_mode color) {
    ew_renderer *r = make(color, 1);
    CHECK(ew_set_debug(r, EW_DEBUG_OVERDRAW) == 0, "overdraw buffers");
    long once = 0;
    for (int v = 0; v < nviews; v++) {
        ew_stats st = render(r, &views[v]);
        once = count_colour(r, r->dbg.heat[1]);
        CHECK(once == (long)W * H && st.pixels_covered == (long)W * H,
              "%s view %d: %ld of %d pixels written once (covered %ld)", color_name(r), v, once, W * H, st.pixels_covered);
    }
    ew_renderer_destroy(r);
    /* With the map's entities and see-through liquids: 2 and more somewhere. */
    r = make(color, 0);
    ew_error err = {""};
    ew_scene *s = ew_scene_create_from_map(A->world, ew_t_shared("data/librequake/maps/e1m1.bsp"), NULL, &err);
    CHECK(s != NULL, "%s", err.msg);
    ew_set_scene(r, s);
    ew_set_liquid_alpha(r, 0.5f);
    ew_set_debug(r, EW_DEBUG_OVERDRAW);
    long more = 0, model_px = 0;
    int views_more = 0;
    for (int v = 0; v < nviews; v++) {
        ew_stats st = render(r, &views[v]);
        long m = 0;
        for (int k = 2; k < EW_DBG_HEAT; k++) m += count_colour(r, r->dbg.heat[k]);
        long zero = count_colour(r, r->dbg.heat[0]);
        CHECK(zero == 0, "%s view %d: %ld pixels never written", color_name(r), v, zero);
        /* at least as many as the passes reported writing (a write that
         * leaves a pixel as it was is not seen) */
        model_px += st.alias_pixels + st.translucent_pixels + st.fence_pixels;
        more += m, views_more += m > 0;
    }
    CHECK(views_more > 0, "%s: some view shows 2+ writes", color_name(r));
    printf("overdraw (%s): %d views one colour over every pixel (edge list); with entities and liquids at 0.5: "
           "%d of %d views show 2+ writes, %ld such pixels (passes reported %ld writes)\n",
           color_name(r), nviews, views_more, nviews, more, model_px);
    ew_renderer_destroy(r);
    ew_scene_destroy(s);
}

/* Lighting only: block means follow the normal frame's; the texture detail
 * is gone: the step from a pixel to its right neighbour, relative to the
 * brightness, is far smaller (light changes smoothly, a texture does not). */
static void lighting(ew_renderer *r, const ew_camera *c) {
    render(r, c);
    uint8_t *normal = copy_frame(r);
    ew_set_debug(r, EW_DEBUG_LIGHTING);
    render(r, c);
    enum { B = 16, NB = (W / B) * (H / B) };
    double mn[NB], ml[NB], var_n = 0, var_l = 0;
    for (int by = 0; by < H / B; by++)
        for (int bx = 0; bx < W / B; bx++) {
            double sn = 0, sl = 0, qn = 0, ql = 0;
            for (int y = by * B; y < by * B + B; y++)
                for (int x = bx * B; x < bx * B + B; x++) {
                    double a = brightness(r, normal, (size_t)y * W + x), b = brightness(r, r->f.target.pixels, (size_t)y * W + x);
                    sn += a, sl += b, qn += a * a, ql += b * b;
                }
            int k = by * (W / B) + bx;
            mn[k] = sn / (B * B), ml[k] = sl / (B * B);
            var_n += qn / (B * B) - mn[k] * mn[k], var_l += ql / (B * B) - ml[k] * ml[k];
        }
    double dn = 0, dl = 0, sn = 0, sl = 0;
    for (int y = 0; y < H; y++)
        for (int x = 1; x < W; x++) {
            size_t i = (size_t)y * W + x;
            double a = brightness(r, normal, i) - brightness(r, normal, i - 1);
            double b = brightness(r, r->f.target.pixels, i) - brightness(r, r->f.target.pixels, i - 1);
            dn += a * a, dl += b * b;
            sn += brightness(r, normal, i) * brightness(r, normal, i);
            sl += brightness(r, r->f.target.pixels, i) * brightness(r, r->f.target.pixels, i);
        }
    double detail_n = sqrt(dn / sn), detail_l = sqrt(dl / sl);
    double an = 0, al = 0, cov = 0, vn = 0, vl = 0;
    for (int k = 0; k < NB; k++) an += mn[k] / NB, al += ml[k] / NB;
    for (int k = 0; k < NB; k++)
        cov += (mn[k] - an) * (ml[k] - al), vn += (mn[k] - an) * (mn[k] - an), vl += (ml[k] - al) * (ml[k] - al);
    double corr = cov / sqrt(vn * vl);
    CHECK(corr > 0.8, "%s: block brightness correlation %.3f", color_name(r), corr);
    CHECK(detail_l < 0.5 * detail_n, "%s: relative neighbour step %.4f (normal %.4f)", color_name(r), detail_l, detail_n);
    printf("lighting (%s): block-mean correlation %.3f; relative step to the next pixel %.4f (normal frame %.4f); "
           "mean in-block variance %.1f (normal %.1f)\n", color_name(r), corr, detail_l, detail_n, var_l / NB, var_n / NB);
    ew_set_debug(r, EW_DEBUG_NONE);
    free(normal);
}

/* Textures only: the frame of the same map without light data (every
 * sample at normal light, colormap row 32), whatever the light styles. */
static void textures(ew_renderer *r, const ew_camera *c) {
    ew_set_debug(r, EW_DEBUG_TEXTURES);
    ew_set_lightstyle(r, 0, 40);  /* dark: textures-only ignores it */
    render(r, c);
    uint8_t *tex = copy_frame(r);
    ew_set_lightstyle(r, 0, 256);
    ew_set_debug(r, EW_DEBUG_NONE);
    render(r, c);
    int differs = memcmp(tex, r->f.target.pixels, frame_bytes(r)) != 0;
    CHECK(differs, "%s: textures-only differs from the lit frame", color_name(r));
    ew_world *w = A->world;
    uint8_t *lighting = w->lighting, *rgb = w->rgblight;
    w->lighting = NULL, w->rgblight = NULL;
    ew_renderer *unlit = make(r->f.target.bpp == 4 ? EW_COLOR_TRUE : EW_COLOR_8BIT, r->f.cfg.classic);
    render(unlit, c);
    long diff = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) diff += px(r, tex, i) != px(r, unlit->f.target.pixels, i);
    CHECK(diff == 0, "%s: textures-only vs the map without light: %ld pixels differ", color_name(r), diff);
    printf("textures (%s): equal to the map without light data (%ld pixels differ), styles ignored\n", color_name(r),
           diff);
    ew_renderer_destroy(unlit);
    w->lighting = lighting, w->rgblight = rgb;
    free(tex);
}

static int face_is_lit(const ew_world *w, int face) {
    return face >= 0 && !(w->faces[face].flags & (EW_SURF_SKY | EW_SURF_TURB));
}

/* Mips: every pixel of a lit surface is one of the four tints. */
static void mips(ew_renderer *r) {
    ew_enable_face_ids(r, 1);
    ew_set_debug(r, EW_DEBUG_MIPS);
    long per[4] = {0}, other = 0, lit = 0;
    for (int v = 0; v < nviews; v++) {
        render(r, &views[v]);
        const int *ids = ew_frame_face_ids(r);
        for (size_t i = 0; i < (size_t)W * H; i++) {
            if (!face_is_lit(A->world, ids[i])) continue;
            lit++;
            uint32_t p = px(r, r->f.target.pixels, i);
            int k = 0;
            while (k < 4 && p != r->dbg.mip[k]) k++;
            if (k < 4) per[k]++; else other++;
        }
    }
    CHECK(other == 0 && lit > 0, "%s: %ld of %ld lit-surface pixels not a mip tint", color_name(r), other, lit);
    CHECK(per[0] > 0 && per[1] > 0, "%s: mips 0 and 1 seen (%ld, %ld)", color_name(r), per[0], per[1]);
    printf("mips (%s): over %d views, pixels at mip 0..3: %ld %ld %ld %ld, others %ld\n", color_name(r), nviews, per[0],
           per[1], per[2], per[3], other);
    ew_set_debug(r, EW_DEBUG_NONE);
    ew_enable_face_ids(r, 0);
}

/* Builds: nothing on a warm cache; after a light style changes, exactly
 * the pixels of the faces using it. */
static void builds(ew_renderer *r) {
    ew_enable_face_ids(r, 1);
    /* a view showing a face with a light style other than 0 (else view 0) */
    const ew_camera *c = &views[0];
    for (int v = 0, found = 0; v < nviews && !found; v++) {
        render(r, &views[v]);
        const int *id = ew_frame_face_ids(r);
        for (size_t i = 0; i < (size_t)W * H && !found; i++)
            for (int k = 1; k < 4 && face_is_lit(A->world, id[i]); k++)
                if (A->world->faces[id[i]].styles[k] != 255 || A->world->faces[id[i]].styles[0] != 0) found = 1;
        if (found) c = &views[v];
    }
    render(r, c);
    render(r, c);
    uint8_t *normal = copy_frame(r);
    ew_set_debug(r, EW_DEBUG_BUILDS);
    ew_stats st = render(r, c);
    CHECK(st.surfaces_built == 0 && memcmp(normal, r->f.target.pixels, frame_bytes(r)) == 0,
          "%s: warm cache: nothing highlighted (%d built)", color_name(r), st.surfaces_built);
    /* a style some visible face uses, other than 0 if there is one */
    const int *ids = ew_frame_face_ids(r);
    int style = 0;
    for (size_t i = 0; i < (size_t)W * H && !style; i++)
        if (face_is_lit(A->world, ids[i]))
            for (int k = 0; k < 4; k++) {
                int s = A->world->faces[ids[i]].styles[k];
                if (s != 255 && s != 0) style = s;
            }
    ew_set_lightstyle(r, style, 300);
    st = render(r, c);
    long hl = 0, bad = 0, others = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        int f = ids[i], uses = 0;
        if (face_is_lit(A->world, f))
            for (int k = 0; k < 4; k++) uses |= A->world->faces[f].styles[k] == style;
        uint32_t p = px(r, r->f.target.pixels, i);
        if (uses) {
            hl++;
            bad += p != r->dbg.build;
        } else {
            others++;
            bad += p != px(r, normal, i);
        }
    }
    CHECK(hl > 0 && bad == 0 && st.surfaces_built > 0, "%s: style %d: %ld pixels to highlight, %ld wrong", color_name(r),
          style, hl, bad);
    printf("builds (%s): warm cache 0 highlighted; light style %d changed: %d surfaces rebuilt, %ld pixels highlighted, "
           "%ld others as before, %ld wrong\n", color_name(r), style, st.surfaces_built, hl, others, bad);
    ew_set_lightstyle(r, style, 256);
    ew_set_debug(r, EW_DEBUG_NONE);
    ew_enable_face_ids(r, 0);
    free(normal);
}

/* PVS lock: the set of the view where it was set, wherever the camera goes. */
static void pvs_lock(ew_renderer *r) {
    const ew_camera *a = &views[0];
    int far = 0;
    float best = 0;
    for (int v = 1; v < nviews; v++) {
        float d = 0;
        for (int k = 0; k < 3; k++) d += (views[v].origin[k] - a->origin[k]) * (views[v].origin[k] - a->origin[k]);
        if (d > best) best = d, far = v;
    }
    const ew_camera *b = &views[far];
    int na = render(r, a).visible_leaves;
    uint8_t *fa = copy_frame(r);
    int nb = render(r, b).visible_leaves;
    uint8_t *fb = copy_frame(r);
    render(r, a);
    ew_set_pvs_lock(r, 1);
    int na_locked = render(r, a).visible_leaves;
    CHECK(na_locked == na && memcmp(fa, r->f.target.pixels, frame_bytes(r)) == 0, "locked where it was set: as normal");
    int nb_locked = render(r, b).visible_leaves;
    int same = memcmp(fb, r->f.target.pixels, frame_bytes(r)) == 0;
    CHECK(nb_locked != nb && !same, "locked at view 0, at view %d: %d leaves (unlocked %d)", far, nb_locked, nb);
    ew_camera side = *a;
    side.angles[1] += 90;
    render(r, &side);
    int nb_again = render(r, b).visible_leaves;
    CHECK(nb_again == nb_locked, "locked set fixed while moving: %d then %d", nb_locked, nb_again);
    ew_set_pvs_lock(r, 0);
    int nb_unlocked = render(r, b).visible_leaves;
    CHECK(nb_unlocked == nb && memcmp(fb, r->f.target.pixels, frame_bytes(r)) == 0, "unlocked: normal counts again");
    printf("pvs lock (%s): view 0 %d leaves; view %d %d leaves unlocked, %d locked at view 0 (again %d), %d unlocked\n",
           color_name(r), na, far, nb, nb_locked, nb_again, nb_unlocked);
    free(fa), free(fb);
}

static void cli(void) {
    ew_t_run run;
    const char *data = ew_t_shared_abs("data/librequake");
    static char d[512];
    snprintf(d, sizeof d, "%s", data);
    const char *ok[] = {"render", "e1m1", "--data", d, "--size", "320x200", "--debug", "overdraw", "--out", "o.png", NULL};
    if (!getenv("EW_CLI")) return;  /* run by ctest */
    ew_t_run_cli(&run, "/tmp", ok);
    CHECK(run.status == 0, "render --debug overdraw: %s", run.err);
    const char *bad[] = {"render", "e1m1", "--data", d, "--debug", "wires", "--out", "o.png", NULL};
    ew_t_run_cli(&run, "/tmp", bad);
    CHECK(run.status != 0 && strstr(run.err, "--debug wires"), "bad mode refused: %s", run.err);
    const char *bench[] = {"bench", "e1m1", "--data", d, "--size", "320x200", "--passes", "1", "--debug", "spans", NULL};
    ew_t_run_cli(&run, "/tmp", bench);
    CHECK(run.status == 0 && strstr(run.out, "\"debug\":\"spans\""), "bench --debug spans: %s", run.err);
    remove("/tmp/o.png");
}

static void pictures(const char *dir, const ew_camera *c) {
    ew_renderer *r = make(EW_COLOR_8BIT, 0);
    ew_error err = {""};
    ew_scene *s = ew_scene_create_from_map(A->world, ew_t_shared("data/librequake/maps/e1m1.bsp"), NULL, &err);
    ew_set_scene(r, s);
    char path[1024];
    for (size_t m = 0; m < sizeof all_modes / sizeof *all_modes; m++) {
        ew_camera warm = *c;
        warm.origin[0] -= 96, warm.angles[1] += 30;  /* builds: the cache warm from a step back */
        render(r, &warm);
        ew_set_debug(r, all_modes[m]);
        render(r, c);
        snprintf(path, sizeof path, "%s/%s.png", dir, mode_names[all_modes[m]]);
        CHECK(ew_write_frame_png(r, path, &err) == 0, "%s", err.msg);
        ew_set_debug(r, EW_DEBUG_NONE);
    }
    ew_renderer_destroy(r);
    ew_scene_destroy(s);
}

int main(void) {
    A = ew_t_load_map("e1m1");
    if (!A) return ew_t_finish();
    nviews = ew_benchmark_views(A->world, views);
    CHECK(nviews > 1, "views");
    int pic_view = getenv("EW_DEBUG_VIEW") ? atoi(getenv("EW_DEBUG_VIEW")) : 0;
    if (getenv("EW_DEBUG_PICTURES")) {
        pictures(getenv("EW_DEBUG_PICTURES"), &views[pic_view % nviews]);
        ew_assets_destroy(A);
        return ew_t_finish();
    }
    for (int ci = 0; ci < 2; ci++) {
        ew_color_mode color = ci ? EW_COLOR_TRUE : EW_COLOR_8BIT;
        ew_renderer *r = make(color, 1);
        if (!r) continue;
        modes_off_give_normal(r, &views[0]);
        spans(r, &views[0]);
        spans(r, &views[nviews / 2]);
        edges(r, &views[0]);
        lighting(r, &views[0]);
        textures(r, &views[0]);
        mips(r);
        builds(r);
        if (ci == 0) pvs_lock(r);
        ew_renderer_destroy(r);
        overdraw(color);
    }
    cli();
    ew_assets_destroy(A);
    return ew_t_finish();
}
