/*
 * options.c - the command line's one option table and its parser
 * (options.h).  Each row: an option of the commands in its mask, with the
 * help text those commands print.  An option whose help differs between
 * commands (--size is one size in render, a list in bench) has a row per
 * meaning; no command has two rows of one name (tests/test_cli_table.c).
 */
#include "options.h"
#include "cli.h"

#include <stdio.h>
#include <string.h>

#define B(c) CLI_BIT(CLI_##c)
/* The commands that take the drawing options (what is drawn). */
#define DRAWN (B(RENDER) | B(DEMO) | B(BENCH) | B(HSR) | B(SOAK) | B(SHOTS) | B(FLY) | B(VIEW) | B(TIMEDEMO))
#define ALL ((1u << CLI_NCMDS) - 1)

const cli_command cli_commands[CLI_NCMDS] = {
    [CLI_RENDER] = { "render", "render", "MAP [options]", "render one frame of MAP to a PNG" },
    [CLI_DEMO] = { "demo", "demo", "[options]", "render the built-in scene (needs no game data)" },
    [CLI_VIEWS] = { "views", "views", "MAP [--data DIR]", "list the view set: INDEX X Y Z PITCH YAW ROLL" },
    [CLI_INFO] = { "info", "info", "MAP [--data DIR]", "BSP version, lumps, BSPX lumps (used or not), counts" },
    [CLI_BENCH] = { "bench", "bench", "MAP... [options]\n--floor [--size WxH]... [--table] [--out FILE]",
                    "time the view set (see edgewise bench --help)" },
    [CLI_HSR] = { "hsr", "hsr", "MAP... [options]\n--stress LIST [options]",
                  "the hidden-surface lab: every method timed and checked" },
    [CLI_SOAK] = { "soak", "soak", "MAP --frames N [options]", "render N frames and check every frame's counters" },
    [CLI_SHOTS] = { "shots", "shots", "MAP|DIR|PAK... [options]", "pictures of many maps (see edgewise shots --help)" },
    [CLI_FLY] = { "fly", "fly", "MAP --out FILE [options]\n--demo DEMO --out FILE [options]",
                  "a flythrough video, or a demo's (see edgewise fly --help)" },
    [CLI_VIEW] = { "view", "view", "MAP [options]\n--demo DEMO [options]", "walk through MAP in a window (see edgewise view --help)" },
    [CLI_TIMEDEMO] = { "timedemo", "timedemo", "DEMO [options]",
                       "play a recorded game (.dem), every block one frame, as fast as it goes" },
    [CLI_RENDER_POLYHEDRA] = { "render", "render builtin:polyhedra", "[options]", "" },
    [CLI_VIEW_POLYHEDRA] = { "view", "view builtin:polyhedra", "[options]", "" },
    [CLI_HELP] = { "help", "help", "\n--help\n--version", "this text" },
};

const cli_option cli_options[] = {
    /* ---- every command ---- */
    { "--help", NULL, CLI_ARG_NONE, NULL, ALL, 0, "this text", NULL },
    /* ---- render and demo ---- */
    { "--game", "DIR", CLI_ARG_DIR, NULL, B(RENDER) | B(VIEWS) | B(INFO) | B(BENCH) | B(HSR) | B(SOAK) | B(VIEW) |
      B(SHOTS) | B(FLY) | B(TIMEDEMO), 0,
      "a mod's game directory, searched before --data's (maps, models, gfx, paks), as Quake's -game over id1", NULL },
    { "--data", "DIR", CLI_ARG_DIR, NULL, B(RENDER) | B(VIEWS) | B(INFO), 0,
      "game directory (maps/, gfx/palette.lmp, gfx/colormap.lmp)", NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(RENDER) | B(DEMO), 0,
      "frame size, 320x200 up to 7680x4320 (default 640x480)", NULL },
    { "--view", "N", CLI_ARG_NUMBER, NULL, B(RENDER) | B(DEMO), 0, "camera N of the view set (default 0)", NULL },
    { "--pos", "X,Y,Z", CLI_ARG_NUMBER, NULL, B(RENDER), 0, "free camera position (needs --angles; not with --view)",
      NULL },
    { "--angles", "P,Y,R", CLI_ARG_NUMBER, NULL, B(RENDER), 0,
      "free camera pitch, yaw, roll in degrees\n(each three numbers from -1000000 to 1000000 separated by commas)",
      NULL },
    { "--fov", "DEG", CLI_ARG_NUMBER, NULL, B(RENDER) | B(DEMO), 0,
      "horizontal field of view, " FOV_RULE " (default 90)", NULL },
    { "--time", "T", CLI_ARG_NUMBER, NULL, B(RENDER) | B(DEMO), 0,
      "seconds, for animated textures, sky and liquids (default 0)", NULL },
    { "--out", "FILE.png", CLI_ARG_FILE, NULL, B(RENDER) | B(DEMO), 0,
      "output (default MAPNAME_vN.png, MAPNAME_free.png with --pos; demo.png for demo)", NULL },
    { "--stats", NULL, CLI_ARG_NONE, NULL, B(RENDER) | B(DEMO), 0,
      "print the frame's counters and times as one JSON object", NULL },
    { "--dlight", "X,Y,Z,R[,r,g,b]", CLI_ARG_NUMBER, NULL, B(RENDER) | B(DEMO), 0,
      "a dynamic light of radius R above 0, at most 100000, white or of\ncolour r,g,b (0 to 1 each); repeatable, up to 32",
      NULL },
    { "--particles", "N", CLI_ARG_NUMBER, NULL, B(RENDER) | B(DEMO), 0,
      "a deterministic cloud of N particles in front of the camera", NULL },
    { "--threads", "N", CLI_ARG_NUMBER, NULL, B(RENDER) | B(DEMO), 0,
      "render bands of the frame on N threads, " THREADS_RULE " (default 1)", NULL },
    { "--quiet", NULL, CLI_ARG_NONE, NULL, B(RENDER) | B(DEMO) | B(VIEWS) | B(INFO) | B(SOAK) | B(FLY) | B(VIEW), 0,
      "no warning lines about the map's optional data", NULL },
    /* ---- bench ---- */
    { "--data", "DIR", CLI_ARG_DIR, NULL, B(BENCH) | B(HSR) | B(SOAK) | B(VIEW), 0, "game directory (maps/, gfx/)",
      NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(BENCH), 0, "frame size; repeat for several (default 640x480)", NULL },
    { "--threads", "N", CLI_ARG_NUMBER, NULL, B(BENCH), 0,
      "render threads, " THREADS_RULE "; repeat for several (default 1)", NULL },
    { "--passes", "P", CLI_ARG_NUMBER, NULL, B(BENCH), 0, "timed passes over the view set, 1 to 1000 (default 5)",
      NULL },
    { "--gap", "MS", CLI_ARG_NUMBER, NULL, B(BENCH), 0,
      "a pause of MS milliseconds before each frame, 0 to 1000\n(default 0): frames spaced out as a viewer paces "
      "them,\nthe render threads asleep between them", NULL },
    { "--bands", "N", CLI_ARG_NUMBER, NULL, B(BENCH), 0,
      "also report the imbalance of N bands and the speed-up\npredicted on N cores, N 1 to 256 and at most "
      "height/8;\nrepeat for several", NULL },
    { "--table", NULL, CLI_ARG_NONE, NULL, B(BENCH), 0, "a human-readable table on stdout (JSON then only to --out)",
      NULL },
    { "--out", "FILE.jsonl", CLI_ARG_FILE, NULL, B(BENCH), 0, "write the JSON lines to FILE instead of stdout", NULL },
    { "--floor", NULL, CLI_ARG_NONE, NULL, B(BENCH), 0, "only measure the fill floor (and the lookup floor) for each --size", NULL },
    { "--per-view", NULL, CLI_ARG_NONE, NULL, B(BENCH), 0,
      "also each view's median time, stages and counts (what\nmakes the slow views slow; with --table also the "
      "level\nof the geometry, the draw and the pixel work alone)", NULL },
    { "--cold", NULL, CLI_ARG_NONE, NULL, B(BENCH), 0,
      "empty the surface cache before each frame (untimed), so\nevery frame builds the surfaces it shows, as the "
      "first\nframe of a new view does", NULL },
    { "--simd", "LEVEL", CLI_ARG_WORD, "best sse2 avx2 avx512", B(BENCH), 0,
      "the widest loops chosen at run time may use: best (the\nprocessor's widest, the default), sse2, avx2 or "
      "avx512;\ntimes here what a processor without AVX-512 runs", NULL },
    { "--quiet", NULL, CLI_ARG_NONE, NULL, B(BENCH) | B(HSR) | B(SHOTS), 0,
      "no warning lines about the maps' optional data", NULL },
    /* ---- hsr ---- */
    { "--methods", "LIST", CLI_ARG_WORD, "edge edge-z spans zbuffer painter drawbuffer beamtree raycast reference",
      B(HSR), 0, "comma list of methods (default every one this build has)", NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(HSR), 0,
      "frame size; repeat for several\n(default 320x200, 640x480 and 1920x1080; with --stress 640x480)", NULL },
    { "--threads", "N", CLI_ARG_NUMBER, NULL, B(HSR) | B(SOAK), 0, "render threads, " THREADS_RULE " (default 1)",
      NULL },
    { "--repeat", "N", CLI_ARG_NUMBER, NULL, B(HSR), 0, "timed passes over the view set, 1 to 1000 (default 5)",
      NULL },
    { "--json", "FILE|-", CLI_ARG_FILE, NULL, B(HSR), 0, "JSON lines to FILE (- : to stdout instead of the table)",
      NULL },
    { "--heatmap", "DIR", CLI_ARG_DIR, NULL, B(HSR), 0,
      "an overdraw heat map per method and view:\nDIR/MAP_WxH_vN_METHOD.png", NULL },
    { "--svg", "FILE", CLI_ARG_FILE, NULL, B(HSR), 0,
      "a bar chart of time and overdraw per method (with --stress:\ntime against the polygons in view, a line per "
      "method)", NULL },
    { "--stress", "LIST", CLI_ARG_NUMBER, NULL, B(HSR), 0,
      "instead of MAPs: the built-in stress hall at each detail of\nthe comma list (0 to 26000, about that many "
      "polygons in view),\nas MAP builtin:detail=N", NULL },
    /* ---- soak ---- */
    { "--frames", "N", CLI_ARG_NUMBER, NULL, B(SOAK), 0, "frames to render (required)", NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(SOAK), 0, "frame size (default 320x200)", NULL },
    { "--seed", "S", CLI_ARG_NUMBER, NULL, B(SOAK), 0, "random cameras' seed (default 1)", NULL },
    /* ---- shots ---- */
    { "--data", "DIR", CLI_ARG_DIR, NULL, B(SHOTS) | B(FLY), 0, "game directory for palette, colormap and models",
      NULL },
    { "--out", "DIR", CLI_ARG_DIR, NULL, B(SHOTS), 0, "where the pictures go (default shots; made if missing)",
      NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(SHOTS), 0, "picture size (default 640x360)", NULL },
    { "--views", "V", CLI_ARG_WORD, "best all", B(SHOTS), 0,
      "best (default): the first info_intermission camera\nas the mapper aimed it; without one the first player\n"
      "start's eye, level, turned to the most open of 24\ndirections (rays traced through the world every 15\n"
      "degrees, each direction scored by the mean free\ndistance of the five rays within 30 degrees of it);\n"
      "all: the whole view set; N,M,...: those views", NULL },
    { "--jobs", "N", CLI_ARG_NUMBER, NULL, B(SHOTS), 0, "maps rendered at once, 1 to 256 worker processes\n(default 1)",
      NULL },
    { "--force", NULL, CLI_ARG_NONE, NULL, B(SHOTS), 0,
      "render again pictures that already exist (otherwise\nthey are skipped, so an interrupted batch resumes)",
      NULL },
    { "--manifest", "FILE", CLI_ARG_FILE, NULL, B(SHOTS), 0, "JSON lines appended (default OUTDIR/manifest.jsonl)",
      NULL },
    { "--contact-sheet", "FILE", CLI_ARG_FILE, NULL, B(SHOTS), 0,
      "a grid PNG of the batch's pictures with their names", NULL },
    /* ---- fly ---- */
    { "--path", "views|straight|FILE", CLI_ARG_FILE_OR_WORD, "views straight", B(FLY), 0,
      "views (default): a smooth path\nthrough the map's view set that stays in the open: the\ndistinct view "
      "origins in order, joined straight where the\nway is clear, else by a path through open space (a grid\n"
      "search, checked with traces); a view whose eye is in solid\nor that no open path reaches is skipped (a "
      "warning says so);\nthe angles turn the shortest way between views; with a\nsingle origin, a slow full turn "
      "in place.\nstraight: a Catmull-Rom spline straight through the view\norigins, which may pass through walls.\n"
      "FILE: a camera path as "
      "the viewer's --record writes it, lines\n'time x y z pitch yaw roll' (decimal numbers, # comments),\nsampled "
      "every 1/F seconds from its first time to its last\n(linear in between); times not going back, spanning at\n"
      "most 3600 s; positions and angles within +-1000000", NULL },
    { "--seconds", "S", CLI_ARG_NUMBER, NULL, B(FLY), 0,
      "the video's length, more than 0 up to 3600 (default: 2 s\nper path segment, 8 s for a turn; --path FILE: "
      "its span)", NULL },
    { "--fps", "F", CLI_ARG_NUMBER, NULL, B(FLY), 0, "frames a second, 1 to 240 (default 30; --demo: 60)", NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(FLY), 0, "frame size, even width and height (default 640x360)", NULL },
    { "--out", "FILE", CLI_ARG_FILE, NULL, B(FLY), 0,
      ".y4m: YUV4MPEG2 4:2:0 (BT.601 full range); .mp4: y4m piped\nto ffmpeg (libx264; ffmpeg must be on PATH); a "
      "name with\none %d conversion (e.g. frames/%05d.png): one PNG a frame,\nnumbered from 0", NULL },
    { "--demo", "DEMO", CLI_ARG_FILE, NULL, B(FLY), 0,
      "instead of MAP and a path: a recorded game (.dem), its map and\nmodels from --game/--data, the camera the "
      "game's client\nwould show, entities interpolated, at --fps frames a second\n(the camera's time is the demo's)",
      NULL },
    { "--from", "S", CLI_ARG_NUMBER, NULL, B(FLY), 0,
      "--demo: start S seconds after the demo's first frame (default 0)", NULL },
    { "--to", "S", CLI_ARG_NUMBER, NULL, B(FLY), 0,
      "--demo: end S seconds after the demo's first frame (default: its end)", NULL },
    { "--threads", "N", CLI_ARG_NUMBER, NULL, B(FLY), 0, "render threads, " THREADS_RULE " (default 1)", NULL },
    { "--cameras", "FILE", CLI_ARG_FILE, NULL, B(FLY), 0,
      "writes each frame's camera, lines 'frame time x y z pitch\nyaw roll' (edgewise render --pos X,Y,Z --angles "
      "P,Y,R\n--time T draws the same frame)", NULL },
    /* ---- view ---- */
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(VIEW), 0,
      "rendered frame size (default: the window's; fixed when given)", NULL },
    { "--scale", "N", CLI_ARG_NUMBER, NULL, B(VIEW), 0, "each rendered pixel shown as NxN, 1 to 8 (default 1)", NULL },
    { "--threads", "N", CLI_ARG_NUMBER, NULL, B(VIEW), 0, "render threads, 0 = all cores (default 0)", NULL },
    { "--fov", "DEG", CLI_ARG_NUMBER, NULL, B(VIEW), 0, "horizontal field of view, " FOV_RULE " (default 90)", NULL },
    { "--view", "N", CLI_ARG_NUMBER, NULL, B(VIEW), 0, "start at camera N of the view set (default 0)", NULL },
    { "--fullscreen", NULL, CLI_ARG_NONE, NULL, B(VIEW), 0, "fill the screen", NULL },
    { "--present", "MODE", CLI_ARG_WORD, "auto surface texture software", B(VIEW), 0,
      "how frames reach the window: auto (default), surface, texture, software", NULL },
    { "--script", "FILE", CLI_ARG_FILE, NULL, B(VIEW), 0,
      "play timed commands (deterministic frames: time from the script)", NULL },
    { "--demo", "DEMO", CLI_ARG_FILE, NULL, B(VIEW), 0,
      "instead of MAP: play a recorded game (.dem) on its map; P pause,\n[ and ] 5 s back and on, G the free camera and back",
      NULL },
    { "--record", "FILE", CLI_ARG_FILE, NULL, B(VIEW), 0,
      "write the camera path: one line 'time x y z pitch yaw roll' a frame", NULL },
    /* ---- timedemo ---- */
    { "--data", "DIR", CLI_ARG_DIR, NULL, B(TIMEDEMO), 0,
      "game directory: the demo's map (maps/), its models (progs/), gfx/", NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(TIMEDEMO), 0, "frame size, 320x200 up to 7680x4320 (default 640x480)",
      NULL },
    { "--threads", "N", CLI_ARG_NUMBER, NULL, B(TIMEDEMO), 0, "render threads, " THREADS_RULE " (default 0)", NULL },
    { "--out", "FILE.png", CLI_ARG_FILE, NULL, B(TIMEDEMO), 0,
      "also write one frame: the first drawn at demo time --at or later\n(default: the last frame)", NULL },
    { "--at", "T", CLI_ARG_NUMBER, NULL, B(TIMEDEMO), 0, "the demo time (seconds, as the demo's svc_time) of --out",
      NULL },
    { "--to", "T", CLI_ARG_NUMBER, NULL, B(TIMEDEMO), 0, "stop at demo time T (default: the whole demo)", NULL },
    { "--quiet", NULL, CLI_ARG_NONE, NULL, B(TIMEDEMO), 0, "no warning lines (missing models, the map's optional data)",
      NULL },
    /* ---- render builtin:polyhedra ---- */
    { "--time", "T", CLI_ARG_NUMBER, NULL, B(RENDER_POLYHEDRA), 0, "seconds, 0 to 1000000 (default 0)", NULL },
    { "--size", "WxH", CLI_ARG_NUMBER, NULL, B(RENDER_POLYHEDRA) | B(VIEW_POLYHEDRA), 0,
      "frame size, 320x200 up to 7680x4320 (default 640x480)", NULL },
    { "--objects", "N", CLI_ARG_NUMBER, NULL, B(RENDER_POLYHEDRA) | B(VIEW_POLYHEDRA), 0,
      "number of polyhedra, 1 to 64 (default 12)", NULL },
    { "--out", "FILE.png", CLI_ARG_FILE, NULL, B(RENDER_POLYHEDRA), 0, "output (default polyhedra.png)", NULL },
    { "--stats", NULL, CLI_ARG_NONE, NULL, B(RENDER_POLYHEDRA), 0,
      "the frame's counters as one JSON object, with its agreement\nwith a per-pixel z-buffer of the same polygons",
      NULL },
    { "--independent", NULL, CLI_ARG_NONE, NULL, B(RENDER_POLYHEDRA), 0,
      "no intersection resolution: the chapter's independent span\nsorting, wrong where objects pass through each "
      "other", NULL },
    { "--zbuffer", NULL, CLI_ARG_NONE, NULL, B(RENDER_POLYHEDRA), 0, "draw the frame by the z-buffer instead", NULL },
    /* ---- view builtin:polyhedra ---- */
    { "--scale", "N", CLI_ARG_NUMBER, NULL, B(VIEW_POLYHEDRA), 0, "each pixel shown as NxN, 1 to 8 (default 1)", NULL },
    { "--time", "T", CLI_ARG_NUMBER, NULL, B(VIEW_POLYHEDRA), 0, "start time in seconds, 0 to 1000000 (default 0)",
      NULL },
    { "--frames", "N", CLI_ARG_NUMBER, NULL, B(VIEW_POLYHEDRA), 0,
      "quit after N frames, time stepping 1/30 s a frame (not the clock)", NULL },
    { "--out", "FILE.png", CLI_ARG_FILE, NULL, B(VIEW_POLYHEDRA), 0, "write the last frame on quit", NULL },
    /* ---- what is drawn (cli/draw_options.c) ---- */
    { "--no-entities", NULL, CLI_ARG_NONE, NULL, DRAWN, 1, "the world only: no doors, monsters, items, flames", NULL },
    { "--alias-raster", "MODE", CLI_ARG_WORD, "auto affine subdiv masks sprite-cache", DRAWN, 1,
      "how triangle models are drawn", "auto (by size, the default), affine, subdiv, masks or sprite-cache" },
    { "--subdiv-threshold", "PX", CLI_ARG_NUMBER, NULL, DRAWN, 1, "auto: subdivide models shorter than PX on screen",
      "a number of pixels above 0, at most 10000 (default 40)" },
    { "--full-zfill", NULL, CLI_ARG_NONE, NULL, DRAWN, 1,
      "z-fill under every world span (default: only under moving things)", NULL },
    { "--occlusion", "MODE", CLI_ARG_WORD, "off auto always", DRAWN, 1,
      "leave out of the edge list the world faces nearer ones hide (the same picture)",
      "off, auto (where the PVS lets 500 leaves or more through; the default) or always" },
    { "--classic", NULL, CLI_ARG_NONE, NULL, DRAWN, 1, "the 1996 look: no see-through surfaces, fog or underwater warp",
      NULL },
    { "--wateralpha", "A", CLI_ARG_NUMBER, NULL, DRAWN, 1, "opacity of every liquid, whatever the map asks",
      "a number above 0, at most 1 (1 = opaque)" },
    { "--fog", "D,R,G,B", CLI_ARG_NUMBER, NULL, DRAWN, 1, "fog instead of the map's",
      "a density from 0 to 100 (0 = none) and red, green, blue from 0 to 1, e.g. 0.05,0.3,0.3,0.35" },
    { "--no-fog", NULL, CLI_ARG_NONE, NULL, DRAWN, 1, "no fog, whatever the map asks", NULL },
    { "--no-waterwarp", NULL, CLI_ARG_NONE, NULL, DRAWN, 1, "no underwater warp and tint", NULL },
    { "--hsr", "METHOD", CLI_ARG_WORD, "edge reference edge-z spans zbuffer painter drawbuffer beamtree raycast", DRAWN,
      1, "hidden-surface removal",
      "edge (the global edge list, the default), reference (a z-buffer per pixel, slow), edge-z, spans, zbuffer, "
      "painter, drawbuffer, beamtree or raycast (docs/hsr.md)" },
    { "--color", "MODE", CLI_ARG_WORD, "8bit true", DRAWN, 1, "pixel format of the frame",
      "8bit (palette indices, the software look; the default) or true (32-bit, light in RGB)" },
    { "--no-lit", NULL, CLI_ARG_NONE, NULL, DRAWN, 1,
      "ignore coloured light (.lit file, BSPX RGBLIGHTING): white light", NULL },
    { "--dither", NULL, CLI_ARG_NONE, NULL, DRAWN, 1,
      "8-bit frames with coloured light: an ordered dither of two palette colours mixed to the tint", NULL },
    { "--lighting", "MODE", CLI_ARG_WORD, "cache two-pass", DRAWN, 1, "how lit faces get their light",
      "cache (light-mapped surfaces built once and kept, the default) or two-pass "
      "(texture, then light per pixel: chapter 69's alternative, docs/lighting.md)" },
    { "--lightstyle", "N=V", CLI_ARG_NUMBER, NULL, DRAWN, 1, "one light style instead of its pattern (repeatable)",
      "a style 0 to 63, '=', then a value 0 to 1024 (264 is normal), a pattern of 1 to 64 "
      "letters a to z (ten a second), 'on' or 'off'" },
    { "--gamma", "G", CLI_ARG_NUMBER, NULL, DRAWN, 1, "output gamma (above 1 brightens)",
      "a number from 0.5 to 3 (default 1)" },
    { "--debug", "MODE", CLI_ARG_WORD, "spans edges overdraw lighting textures mips builds", DRAWN, 1,
      "a view of the pipeline instead of the normal frame",
      "spans (each span its own colour), edges (the edge list over the frame), overdraw "
      "(writes per pixel), lighting (light maps only), textures (no light), mips (a colour "
      "per mip level) or builds (surfaces the frame built, magenta: a single render builds every one, "
      "so all is magenta; view and fly show the rebuilds between frames)" },
};
const int cli_noptions = (int)(sizeof cli_options / sizeof cli_options[0]);

int cli_command_of(const char *name) {
    for (int c = 0; c < CLI_NCMDS; c++)
        if (strcmp(cli_commands[c].name, name) == 0) return c;
    return -1;
}

const cli_option *cli_find(cli_cmd cmd, const char *name, int len) {
    size_t n = len < 0 ? strlen(name) : (size_t)len;
    if (n == 2 && strncmp(name, "-h", 2) == 0) name = "--help", n = 6;
    for (int k = 0; k < cli_noptions; k++) {
        const cli_option *o = &cli_options[k];
        if ((o->cmds & CLI_BIT(cmd)) && strlen(o->name) == n && strncmp(o->name, name, n) == 0) return o;
    }
    return NULL;
}

int cli_is(const cli_option *opt, const char *name) { return opt && strcmp(opt->name, name) == 0; }

/* The column the help text starts at: past the longest "--name METAVAR"
 * of the command's own options (a longer one than 20 characters has its
 * text two blanks after it). */
static int help_column(cli_cmd cmd) {
    int col = 0;
    for (int k = 0; k < cli_noptions; k++) {
        const cli_option *o = &cli_options[k];
        if (!(o->cmds & CLI_BIT(cmd)) || o->draw || cli_is(o, "--help")) continue;
        int n = (int)strlen(o->name) + (o->metavar ? 1 + (int)strlen(o->metavar) : 0);
        if (n > col && n <= 20) col = n;
    }
    return col + 2;
}

static void print_text(FILE *f, int indent, const char *text) {
    for (const char *p = text; *p;) {
        size_t n = strcspn(p, "\n");
        fprintf(f, "%.*s\n", (int)n, p);
        p += n;
        if (*p == '\n') {
            p++;
            fprintf(f, "  %*s", indent, "");
        }
    }
}

/* Row o as cmd's help shows it, its text from column col. */
static void print_option(FILE *f, const cli_option *o, int col, int draw) {
    char head[64];
    snprintf(head, sizeof head, "%s%s%s", o->name, o->metavar ? " " : "", o->metavar ? o->metavar : "");
    if ((int)strlen(head) >= col) fprintf(f, "  %s  ", head);
    else fprintf(f, "  %-*s ", col, head);
    if (draw && o->rule)
        fprintf(f, "%s;\n  %-*s   %s must be %s\n", o->help, col, "", o->metavar, o->rule);
    else
        print_text(f, col + 1, o->help);
}

void cli_print_options(FILE *f, cli_cmd cmd, int draw) {
    int col = draw ? 22 : help_column(cmd);
    /* in the table's order, --quiet (a row most commands share) last */
    for (int pass = 0; pass < 2; pass++)
        for (int k = 0; k < cli_noptions; k++) {
            const cli_option *o = &cli_options[k];
            if ((o->cmds & CLI_BIT(cmd)) && o->draw == draw && !cli_is(o, "--help") && cli_is(o, "--quiet") == pass)
                print_option(f, o, col, draw);
        }
}

void cli_print_help(FILE *f, cli_cmd cmd, const char *text) {
    const char *m = strstr(text, CLI_OPTIONS_HERE);
    if (!m) {
        fputs(text, f);
        return;
    }
    fprintf(f, "%.*s", (int)(m - text), text);
    cli_print_options(f, cmd, 0);
    fputs(m + strlen(CLI_OPTIONS_HERE), f);
}

void cli_unknown_command(const char *name) {
    char list[256] = "";
    size_t n = 0;
    for (int c = 0; c < CLI_NCMDS; c++) {
        if (strcmp(cli_commands[c].form, cli_commands[c].name) != 0) continue;  /* a form */
        n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", n ? ", " : "", cli_commands[c].name);
        if (n >= sizeof list) break;
    }
    error_line("unknown command '%s' (commands: %s)", name, list);
}

void cli_parser_init(cli_parser *p, cli_cmd cmd, int argc, char **argv, int first) {
    p->cmd = cmd, p->argc = argc, p->argv = argv, p->i = first, p->only_positional = 0;
}

/* Some command takes an option of this name. */
static int known_anywhere(const char *name, size_t n) {
    for (int c = 0; c < CLI_NCMDS; c++)
        if (cli_find((cli_cmd)c, name, (int)n)) return 1;
    return 0;
}

/* --game DIR, taken by the parser itself for every command that has it:
 * the command line's one mod directory (cli_search_path). */
static const char *cli_game;

const char *cli_search_path(const char *data) {
    static char path[8192];
    if (!cli_game) return data;
    if (!data) return cli_game;
    snprintf(path, sizeof path, "%s:%s", cli_game, data);
    return path;
}

int cli_parse(cli_parser *p, const cli_option **opt, const char **value) {
    const char *form = cli_commands[p->cmd].form;
    *opt = NULL, *value = NULL;
    while (p->i < p->argc) {
        const char *a = p->argv[p->i++];
        if (!p->only_positional && strcmp(a, "--") == 0) {
            p->only_positional = 1;
            continue;
        }
        if (p->only_positional || a[0] != '-' || !a[1]) {
            *value = a;
            return CLI_POSITIONAL;
        }
        const char *eq = strchr(a, '=');
        size_t n = eq ? (size_t)(eq - a) : strlen(a);
        const cli_option *o = cli_find(p->cmd, a, (int)n);
        if (!o) {
            if (known_anywhere(a, n))
                error_line("%s: option '%.*s' does not apply here (see edgewise %s --help)", form, (int)n, a, form);
            else
                error_line("%s: unknown option '%.*s' (see edgewise %s --help)", form, (int)n, a, form);
            return -1;
        }
        if (!o->metavar) {
            if (eq) {
                error_line("%s: option '%s' takes no value", form, o->name);
                return -1;
            }
        } else if (eq) {
            *value = eq + 1;
        } else if (p->i < p->argc) {
            *value = p->argv[p->i++];
        } else {
            error_line("%s: option '%s' needs a value", form, o->name);
            return -1;
        }
        if (cli_is(o, "--game")) {
            if (!**value || strchr(*value, ':')) {
                error_line("%s: --game '%s': %s", form, *value, **value ? "a directory name without ':'" : "empty directory name");
                return -1;
            }
            if (cli_game && strcmp(cli_game, *value) != 0) {
                error_line("%s: --game given twice", form);
                return -1;
            }
            cli_game = *value;
            continue;
        }
        *opt = o;
        return CLI_OPTION;
    }
    return CLI_END;
}
