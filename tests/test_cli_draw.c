/*
 * The options that change what is drawn (cli/draw_options.c), through the
 * `edgewise` command (path in EW_CLI): each is accepted by render, demo,
 * bench and soak and shows in their JSON; they change the picture as they
 * say (--classic, --wateralpha, --fog, --no-fog); a bad value is one error
 * line, exit 2, with the same text in every command; the map's and the
 * scene's warnings are printed as "edgewise: warning: ..." unless --quiet.
 */
#define _POSIX_C_SOURCE 200809L
#include "util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char tmpdir[256];
static const char *data;  /* ../shared/data/librequake, absolute */

typedef ew_t_run run_result;

#define MAXARGS 32

/* Runs the command: base arguments, then extra ones (both NULL-terminated). */
static run_result *run2(const char *const *base, const char *const *extra) {
    const char *args[MAXARGS];
    int n = 0;
    for (; base && *base && n < MAXARGS - 1; base++) args[n++] = *base;
    for (; extra && *extra && n < MAXARGS - 1; extra++) args[n++] = *extra;
    args[n] = NULL;
    run_result *r = malloc(sizeof *r);
    ew_t_run_cli(r, tmpdir, args);
    return r;
}

#define ARGS(...) ((const char *const[]){ __VA_ARGS__, NULL })

static double num(const char *json, const char *key) { return ew_t_json_num(json, key); }

/* Every stderr line is "wrote ..." or a warning. */
static int clean_stderr(const char *err) {
    for (const char *p = err; *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : p + strlen(p))
        if (strncmp(p, "wrote ", 6) != 0 && strncmp(p, "edgewise: warning: ", 19) != 0)
            return 0;
    return 1;
}

/* The commands, each with fast settings; the option goes after them.
 * start when ../shared is there (the built-in scene takes longer to make). */
static const char *const *command(int c) {
    static const char *render[] = {"render", "builtin", "--size", "320x200", "--stats",
                                   "--out", "d.png", NULL, NULL, NULL};
    static const char *const demo[] = {"demo", "--size", "320x200", "--stats", "--out", "d.png", NULL};
    static const char *bench[] = {"bench", "builtin", "--size", "320x200", "--passes", "1", NULL, NULL, NULL};
    static const char *soak[] = {"soak", "builtin", "--frames", "4", NULL, NULL, NULL};
    if (data) {
        render[1] = bench[1] = soak[1] = "start";
        render[7] = bench[6] = soak[4] = "--data";
        render[8] = bench[7] = soak[5] = data;
    }
    const char *const *all[] = {render, demo, bench, soak};
    return all[c];
}
static const char *const command_names[] = {"render", "demo", "bench", "soak"};
enum { NCOMMANDS = 4 };

/* Each option, and what the JSON line says about it. */
static void options_accepted(void) {
    static const struct {
        const char *args[3];
        const char *json;  /* in every command's JSON line */
    } opts[] = {
        {{"--no-entities"}, "\"entities\":false"},
        {{"--alias-raster", "affine"}, "\"alias_raster\":\"affine\""},
        {{"--alias-raster", "masks"}, "\"alias_raster\":\"masks\""},
        {{"--alias-raster", "sprite-cache"}, "\"alias_raster\":\"sprite-cache\""},
        {{"--subdiv-threshold", "20"}, "\"subdiv_threshold\":20"},
        {{"--full-zfill"}, "\"zfill\":\"full\""},
        {{"--occlusion", "off"}, "\"occlusion\":\"off\""},
        {{"--occlusion", "always"}, "\"occlusion\":\"always\""},
        {{"--classic"}, "\"classic\":true"},
        {{"--wateralpha", "0.5"}, "\"wateralpha\":0.5"},
        {{"--wateralpha=1"}, "\"wateralpha\":1"},
        {{"--fog", "0.5,0.5,0.5,0.5"}, "\"fog\":[0.5,0.5,0.5,0.5]"},
        {{"--no-fog"}, "\"fog\":[0,0,0,0]"},
        {{"--no-waterwarp"}, "\"waterwarp\":false"},
        {{"--hsr", "reference"}, "\"hsr\":\"reference\""},
        {{"--hsr=edge"}, "\"hsr\":\"edge\""},
        {{"--color", "true"}, "\"color\":\"true\""},
        {{"--no-lit"}, "\"lit\":false"},
        {{"--dither"}, "\"dither\":true"},
        {{"--lighting", "two-pass"}, "\"lighting\":\"two-pass\""},
        {{"--lighting=cache"}, "\"lighting\":\"cache\""},
        {{"--gamma", "1.5"}, "\"gamma\":1.5"},
        {{"--lightstyle", "0=mmamma"}, "\"lightstyles\":[\"0=mmamma\"]"},
        {{"--lightstyle=33=off"}, "\"lightstyles\":[\"33=off\"]"},
    };
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++)
        for (int c = 0; c < NCOMMANDS; c++) {
            run_result *r = run2(command(c), opts[k].args);
            CHECK(r->status == 0 && clean_stderr(r->err), "%s %s: exit %d, stderr: %s", command_names[c],
                  opts[k].args[0], r->status, r->err);
            CHECK(strstr(r->out, opts[k].json) != NULL, "%s %s: no %s in: %.600s", command_names[c],
                  opts[k].args[0], opts[k].json, r->out);
            if (c == 3)
                CHECK(num(r->out, "anomalies") == 0, "soak %s: %s", opts[k].args[0], r->out);
            free(r);
        }
}

/* Bad values: one line, exit 2, stdout empty, the same text everywhere
 * (the command's name aside, for the form errors). */
static void bad_values(void) {
    static const struct {
        const char *args[5];
        const char *needle;
    } bad[] = {
        {{"--wateralpha", "0"}, "--wateralpha 0: A must be a number above 0, at most 1"},
        {{"--wateralpha", "1.5"}, "--wateralpha 1.5: A must be"},
        {{"--wateralpha", "nan"}, "--wateralpha nan: A must be"},
        {{"--wateralpha", " 0.5"}, "A must be"},
        {{"--fog", "1,2"}, "--fog 1,2: D,R,G,B must be a density from 0 to 100"},
        {{"--fog", "-1,0,0,0"}, "--fog -1,0,0,0: D,R,G,B must be"},
        {{"--fog", "0.1,0,0,2"}, "--fog 0.1,0,0,2: D,R,G,B must be"},
        {{"--fog", "0.1,0,0,0,0"}, "D,R,G,B must be"},
        {{"--hsr", "beam"}, "--hsr beam: METHOD must be edge"},
        {{"--alias-raster", "fast"}, "--alias-raster fast: MODE must be auto"},
        {{"--subdiv-threshold", "0"}, "--subdiv-threshold 0: PX must be"},
        {{"--classic", "--fog", "0,0,0,0"}, "--classic is the 1996 look"},
        {{"--no-waterwarp", "--classic"}, "--classic is the 1996 look"},
        {{"--fog", "0,0,0,0", "--no-fog"}, "--fog and --no-fog cannot be combined"},
        {{"--classic=yes"}, "option '--classic' takes no value"},
        {{"--hsr"}, "option '--hsr' needs a value"},
        {{"--color", "16bit"}, "--color 16bit: MODE must be 8bit"},
        {{"--classic", "--color", "true"}, "--classic is the 1996 look"},
        {{"--no-lit=1"}, "option '--no-lit' takes no value"},
        {{"--lighting", "3pass"}, "--lighting 3pass: MODE must be cache"},
        {{"--gamma", "4"}, "--gamma 4: G must be a number from 0.5 to 3"},
        {{"--lightstyle", "64=m"}, "--lightstyle 64=m: N=V must be a style 0 to 63"},
        {{"--lightstyle", "1=M"}, "--lightstyle 1=M: N=V must be"},
        {{"--lightstyle", "1=2000"}, "--lightstyle 1=2000: N=V must be"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char first[512] = "";
        for (int c = 0; c < NCOMMANDS; c++) {
            run_result *r = run2(command(c), bad[k].args);
            CHECK(r->status == 2, "%s %s: exit %d (want 2)", command_names[c], bad[k].args[0], r->status);
            CHECK(ew_t_count_lines(r->err) == 1 && strncmp(r->err, "edgewise: ", 10) == 0,
                  "%s %s: want one error line, got: %s", command_names[c], bad[k].args[0], r->err);
            CHECK(strstr(r->err, bad[k].needle) != NULL, "%s: '%s' not in: %s", command_names[c],
                  bad[k].needle, r->err);
            CHECK(r->out[0] == '\0', "%s %s: stdout: %s", command_names[c], bad[k].args[0], r->out);
            /* The same text once the command's own name is taken out. */
            char text[512];
            const char *t = r->err + 10;
            size_t cl = strlen(command_names[c]);
            if (strncmp(t, command_names[c], cl) == 0 && t[cl] == ':') t += cl + 1;
            snprintf(text, sizeof text, "%s", t);
            if (c == 0)
                snprintf(first, sizeof first, "%s", text);
            else
                CHECK(strcmp(first, text) == 0, "%s %s: '%s' differs from render's '%s'",
                      command_names[c], bad[k].args[0], text, first);
            free(r);
        }
    }
    /* views and info draw nothing. */
    run_result *r = run2(ARGS("info", "builtin", "--classic"), NULL);
    CHECK(r->status == 2 && strstr(r->err, "does not apply") != NULL, "info --classic: %d %s", r->status,
          r->err);
    free(r);
}

/* The help of each command states each rule as its error does. */
static void help_states_rules(void) {
    const char *rules[] = {"A must be a number above 0, at most 1 (1 = opaque)",
                           "D,R,G,B must be a density from 0 to 100", "METHOD must be edge",
                           "MODE must be auto", "--no-waterwarp", "--no-fog", "--full-zfill"};
    const char *const helps[][3] = {{"render", "--help"}, {"bench", "--help"}, {"soak", "--help"}};
    for (int h = 0; h < 3; h++) {
        run_result *r = run2(helps[h], NULL);
        CHECK(r->status == 0, "%s --help: exit %d", helps[h][0], r->status);
        for (size_t k = 0; k < sizeof rules / sizeof rules[0]; k++)
            CHECK(strstr(r->out, rules[k]) != NULL, "%s --help lacks '%s'", helps[h][0], rules[k]);
        free(r);
    }
}

static void slurp_png(const char *name, char *buf, size_t size, size_t *len) {
    char path[600];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "rb");
    *len = f ? fread(buf, 1, size, f) : 0;
    if (f) fclose(f);
}

/* The options change the picture as they say, in render's stats. */
static void pictures(void) {
    const char *const start3[] = {"render", "start", "--data", data, "--view", "3", "--size", "320x200",
                                  "--stats", NULL};
    run_result *def = run2(start3, ARGS("--out", "default.png"));
    run_result *cl = run2(start3, ARGS("--classic", "--out", "classic.png"));
    run_result *cl2 = run2(start3, ARGS("--classic", "--threads", "2", "--out", "classic2.png"));
    CHECK(def->status == 0 && cl->status == 0 && cl2->status == 0, "start view 3: %s %s %s", def->err, cl->err,
          cl2->err);
    CHECK(num(def->out, "classic") == 0 && num(cl->out, "classic") == 1, "classic in the stats");
    CHECK(num(def->out, "seethrough_surfaces") > 0 && num(cl->out, "seethrough_surfaces") == 0,
          "start view 3: see-through surfaces %g by default, %g classic", num(def->out, "seethrough_surfaces"),
          num(cl->out, "seethrough_surfaces"));
    static char a[1 << 20], b[1 << 20], c[1 << 20];
    size_t na, nb, nc;
    slurp_png("default.png", a, sizeof a, &na);
    slurp_png("classic.png", b, sizeof b, &nb);
    slurp_png("classic2.png", c, sizeof c, &nc);
    CHECK(na > 0 && nb > 0 && (na != nb || memcmp(a, b, na) != 0), "--classic draws the same as the default");
    CHECK(nb > 0 && nb == nc && memcmp(b, c, nb) == 0, "--classic differs with --threads 2");
    free(def), free(cl), free(cl2);

    /* e4m1 view 21 looks at water. */
    const char *const e4[] = {"render", "e4m1", "--data", data, "--view", "21", "--size", "320x200",
                              "--stats", "--out", "e4.png", NULL};
    run_result *op = run2(e4, ARGS("--wateralpha", "1")), *half = run2(e4, ARGS("--wateralpha", "0.5"));
    CHECK(op->status == 0 && num(op->out, "translucent_pixels") == 0, "--wateralpha 1: %s %s", op->err, op->out);
    CHECK(half->status == 0 && num(half->out, "translucent_pixels") > 0, "--wateralpha 0.5: %s %s", half->err,
          half->out);
    free(op), free(half);

    run_result *fog = run2(start3, ARGS("--fog", "0.5,0.5,0.5,0.5", "--out", "fog.png"));
    run_result *nofog = run2(start3, ARGS("--no-fog", "--out", "nofog.png"));
    CHECK(fog->status == 0 && num(fog->out, "fog_pixels") > 0, "--fog: %s %s", fog->err, fog->out);
    CHECK(nofog->status == 0 && num(nofog->out, "fog_pixels") == 0, "--no-fog: %s %s", nofog->err, nofog->out);
    CHECK(!isnan(num(fog->out, "underwater")) && !isnan(num(fog->out, "fence_pixels")), "stats fields");
    free(fog), free(nofog);

    /* bench and soak time and soak the same pictures. */
    run_result *r = run2(ARGS("bench", "start", "--data", data, "--size", "320x200", "--passes", "1",
                              "--classic"), NULL);
    CHECK(r->status == 0 && strstr(r->out, "\"classic\":true") && num(r->out, "seethrough_surfaces") == 0,
          "bench --classic: %s %s", r->err, r->out);
    free(r);
    r = run2(ARGS("bench", "start", "--data", data, "--size", "320x200", "--passes", "1", "--table"), NULL);
    CHECK(r->status == 0 && strstr(r->out, "seethr") != NULL, "bench --table: %s %s", r->err, r->out);
    free(r);
    r = run2(ARGS("bench", "start", "--data", data, "--size", "320x200", "--passes", "1"), NULL);
    CHECK(r->status == 0 && strstr(r->out, "\"classic\":false") && num(r->out, "seethrough_surfaces") > 0 &&
              !isnan(num(r->out, "fog_pixels")) && !isnan(num(r->out, "underwater")),
          "bench: %s %s", r->err, r->out);
    free(r);
    const char *const soaks[][3] = {{"--classic", NULL}, {"--wateralpha", "0.5", NULL}, {"--hsr", "reference", NULL}};
    for (int k = 0; k < 3; k++) {
        r = run2(ARGS("soak", "e4m1", "--data", data, "--frames", "8"), soaks[k]);
        CHECK(r->status == 0 && num(r->out, "anomalies") == 0 && num(r->out, "frames") == 8,
              "soak e4m1 %s: %d %s %s", soaks[k][0], r->status, r->err, r->out);
        CHECK(strstr(r->out, k == 0 ? "\"classic\":true" : k == 1 ? "\"wateralpha\":0.5" : "\"hsr\":\"reference\""),
              "soak %s: %s", soaks[k][0], r->out);
        free(r);
    }
}

/* Count the warning lines of stderr. */
static int warning_lines(const char *err) {
    int n = 0;
    for (const char *p = err; (p = strstr(p, "edgewise: warning: ")) != NULL; p++) n++;
    return n;
}

/* What the library warns about is what the commands print; --quiet: none. */
static void warnings(void) {
    const char *maps[] = {"start", "e4m1"};
    for (int m = 0; m < 2; m++) {
        ew_assets *a = ew_t_load_map(maps[m]);
        if (!a) continue;
        int nw = 0, ns = 0;
        while (ew_world_warning(a->world, nw)) nw++;
        char path[600];
        snprintf(path, sizeof path, "%s/maps/%s.bsp", data, maps[m]);
        ew_error err;
        ew_scene *s = ew_scene_create_from_map(a->world, path, data, &err);
        while (s && ew_scene_warning(s, ns)) ns++;
        ew_scene_destroy(s);
        ew_assets_destroy(a);
        const char *const render[] = {"render", maps[m], "--data", data, "--size", "320x200", "--out", "w.png", NULL};
        const char *const info[] = {"info", maps[m], "--data", data, NULL};
        const char *const views[] = {"views", maps[m], "--data", data, NULL};
        const char *const bench[] = {"bench", maps[m], "--data", data, "--size", "320x200", "--passes", "1", NULL};
        const char *const soak[] = {"soak", maps[m], "--data", data, "--frames", "2", NULL};
        const char *const *cmds[] = {render, info, views, bench, soak};
        const int want[] = {nw + ns, nw, nw, nw + ns, nw + ns};
        for (int c = 0; c < 5; c++) {
            run_result *r = run2(cmds[c], NULL), *q = run2(cmds[c], ARGS("--quiet"));
            CHECK(r->status == 0 && warning_lines(r->err) == want[c], "%s %s: %d warnings, want %d: %s",
                  cmds[c][0], maps[m], warning_lines(r->err), want[c], r->err);
            CHECK(q->status == 0 && warning_lines(q->err) == 0, "%s %s --quiet: %d %s", cmds[c][0], maps[m],
                  q->status, q->err);
            free(r), free(q);
        }
    }
    run_result *r = run2(ARGS("demo", "--quiet", "--out", "q.png"), NULL);
    CHECK(r->status == 0, "demo --quiet: %s", r->err);
    free(r);
}

/* --dlight with a colour: accepted by render; a colour outside 0..1 or a
 * count of numbers other than 4 or 7 is one error line, exit 2. */
static void coloured_dlights(void) {
    run_result *ok = run2(ARGS("render", "builtin", "--size", "320x200", "--color", "true", "--out", "d.png",
                               "--dlight", "0,0,64,200,1,0,0.25", "--stats"), NULL);
    CHECK(ok->status == 0 && num(ok->out, "surfaces_rebuilt_by_dlights") >= 0, "coloured dlight: exit %d %s",
          ok->status, ok->err);
    free(ok);
    const char *const bad[][3] = {{"--dlight", "0,0,0,100,2,0,0", NULL}, {"--dlight", "0,0,0,100,1,0", NULL},
                                  {"--dlight", "0,0,0,0", NULL}, {"--dlight", "0,0,0,100,nan,0,0", NULL}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        run_result *r = run2(ARGS("render", "builtin", "--size", "320x200", "--out", "d.png"), bad[k]);
        CHECK(r->status == 2 && ew_t_count_lines(r->err) == 1 && strstr(r->err, "X,Y,Z,R[,r,g,b] must be"),
              "--dlight %s: exit %d, stderr: %s", bad[k][1], r->status, r->err);
        free(r);
    }
}

int main(void) {
    if (!getenv("EW_CLI")) {
        fprintf(stderr, "EW_CLI not set\n");
        return 1;
    }
    snprintf(tmpdir, sizeof tmpdir, "/tmp/ew_draw_XXXXXX");
    if (!mkdtemp(tmpdir)) {
        fprintf(stderr, "cannot make a scratch folder\n");
        return 1;
    }
    static char abs_data[512];
    if (ew_t_need_shared("data/librequake/maps/e4m1.bsp")) {
        snprintf(abs_data, sizeof abs_data, "%s", ew_t_shared_abs("data/librequake"));
        data = abs_data;
    }
    options_accepted();
    bad_values();
    help_states_rules();
    coloured_dlights();
    if (data) {
        pictures();
        warnings();
    }
    const char *files[] = {"d.png", "default.png", "classic.png", "classic2.png", "e4.png", "fog.png",
                           "nofog.png", "w.png", "q.png", "stdout.txt", "stderr.txt"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char path[600];
        snprintf(path, sizeof path, "%s/%s", tmpdir, files[i]);
        unlink(path);
    }
    rmdir(tmpdir);
    return ew_t_finish();
}
