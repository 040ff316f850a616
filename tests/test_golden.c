/* Frames stay what they were: every view of every shared map with views
 * (and the built-in scene), with their entities, on one thread and on two,
 * hashed (FNV-1a 64 over the frame's bytes) and compared against
 * tests/golden/frames.txt:
 *   - the classic look (--classic) at 320x200 and 1920x1080: the list made
 *     from the frames of the commit before the restructuring (cde885f),
 *     made again once when trigger brushes stopped being drawn (66 of the
 *     351 frames, those with a trigger in view, changed then);
 *   - the default look at 320x200, at a fixed time (1.3 s: light styles,
 *     liquids and animated textures away from their first frame), in 8-bit
 *     and true colour ("default/" and "true/" lines), and the same with
 *     fog and half-transparent liquids ("fog/" and "fogtrue/"): coloured
 *     light from the maps' .lit files, fences, translucent liquids, fog.
 * A refactor that changes one pixel of one of those frames fails here.
 *
 * EW_GOLDEN_WRITE=FILE writes the list instead of checking it. */
#include "util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char *const maps[] = {"e1m1", "e2m1", "e4m1", "lqdm1", "lqdm7", "slope", "start", "builtin"};
static const int sizes[][2] = {{320, 200}, {1920, 1080}};

/* The looks: classic (both sizes), then the default look's four at 320x200. */
static const struct look {
    const char *prefix;   /* before the map's name in the list ("" for classic) */
    int classic, color, fog, sizes;
} looks[] = {
    {"", 1, EW_COLOR_8BIT, 0, 2},
    {"default/", 0, EW_COLOR_8BIT, 0, 1},
    {"true/", 0, EW_COLOR_TRUE, 0, 1},
    {"fog/", 0, EW_COLOR_8BIT, 1, 1},
    {"fogtrue/", 0, EW_COLOR_TRUE, 1, 1},
};
#define LOOK_TIME 1.3

static uint64_t fnv1a(const uint8_t *p, size_t n) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

typedef struct entry {
    char     map[48];
    int      w, h, view;
    uint64_t hash;
} entry;

static entry *golden;
static int ngolden;

static void read_golden(const char *path) {
    FILE *f = fopen(path, "r");
    CHECK(f != NULL, "%s: cannot open", path);
    if (!f) return;
    char line[256];
    int cap = 0;
    while (fgets(line, sizeof line, f)) {
        entry e;
        unsigned long long h;
        if (line[0] == '#' || sscanf(line, "%47s %dx%d %d %llx", e.map, &e.w, &e.h, &e.view, &h) != 5) continue;
        e.hash = h;
        if (ngolden == cap) {
            cap = cap ? cap * 2 : 256;
            golden = realloc(golden, sizeof *golden * (size_t)cap);
        }
        golden[ngolden++] = e;
    }
    fclose(f);
}

static const entry *find(const char *map, int w, int h, int view) {
    for (int i = 0; i < ngolden; i++)
        if (!strcmp(golden[i].map, map) && golden[i].w == w && golden[i].h == h && golden[i].view == view)
            return &golden[i];
    return NULL;
}

int main(void) {
    const char *write = getenv("EW_GOLDEN_WRITE");
    const char *src = getenv("EW_SOURCE");
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/golden/frames.txt", src ? src : "..");
    FILE *out = NULL;
    if (write && *write) {
        out = fopen(write, "w");
        CHECK(out != NULL, "%s: cannot write", write);
        if (!out) return ew_t_finish();
        fprintf(out, "# [look/]map WxH view fnv1a64 of the frame's bytes (with entities; 1 and 2 threads agree)\n");
    } else {
        read_golden(path);
        CHECK(ngolden > 0, "%s: no entries", path);
    }
    long frames = 0, differ = 0, missing = 0;
    for (size_t m = 0; m < sizeof maps / sizeof *maps; m++) {
        ew_error err;
        ew_scene *sc;
        ew_camera views[EW_MAX_VIEWS];
        int nv;
        ew_assets *a = ew_t_load_map_scene(maps[m], &sc, views, &nv);
        if (!a) continue;
        for (size_t l = 0; l < sizeof looks / sizeof *looks; l++) {
            const struct look *lk = &looks[l];
            char key[64];
            snprintf(key, sizeof key, "%s%s", lk->prefix, maps[m]);
            for (int s = 0; s < lk->sizes; s++) {
                int w = sizes[s][0], h = sizes[s][1];
                for (int threads = 1; threads <= 2; threads++) {
                    ew_renderer *r = ew_renderer_create(&(ew_renderer_desc){
                            .world = a->world, .palette = a->palette, .colormap = a->colormap, .width = w,
                            .height = h, .threads = 1, .classic = lk->classic, .color = lk->color }, &err);
                    CHECK(r != NULL, "%s: %s", maps[m], err.msg);
                    if (!r) continue;
                    CHECK(ew_set_threads(r, threads) == threads, "%s: %d threads", maps[m], threads);
                    ew_set_scene(r, sc);
                    if (lk->fog) {
                        ew_set_fog(r, 0.05f, 0.3f, 0.3f, 0.35f);
                        ew_set_liquid_alpha(r, 0.5f);
                    }
                    for (int v = 0; v < nv; v++) {
                        ew_camera cam = views[v];
                        if (!lk->classic) cam.time = LOOK_TIME;
                        CHECK(ew_render(r, &cam, NULL) == 0, "%s view %d", key, v);
                        const uint8_t *px = lk->color == EW_COLOR_TRUE ? (const uint8_t *)ew_frame_rgba(r)
                                                                         : ew_frame_pixels(r);
                        uint64_t hash = fnv1a(px, (size_t)w * h * (lk->color == EW_COLOR_TRUE ? 4 : 1));
                        frames++;
                        if (out) {
                            if (threads == 1) fprintf(out, "%s %dx%d %d %016llx\n", key, w, h, v, (unsigned long long)hash);
                            continue;
                        }
                        const entry *e = find(key, w, h, v);
                        if (!e) {
                            missing++;
                            CHECK(0, "%s %dx%d view %d: not in the list", key, w, h, v);
                        } else if (e->hash != hash) {
                            differ++;
                            CHECK(0, "%s %dx%d view %d, %d thread(s): frame differs from the list", key, w, h, v,
                                  threads);
                        }
                    }
                    ew_renderer_destroy(r);
                }
            }
        }
        ew_scene_destroy(sc);
        ew_assets_destroy(a);
    }
    if (out) fclose(out);
    printf("%ld frames, %ld differ from the list, %ld not in it\n", frames, differ, missing);
    if (!out) CHECK(frames >= ngolden * 2, "%ld frames rendered for %d entries", frames, ngolden);
    free(golden);
    return ew_t_finish();
}
