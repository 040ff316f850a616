/* test_layers: the library's stages are layers (docs/architecture.md).
 *
 * Reads the library's own sources (EW_SOURCE) for #include "..." edges and
 * the static library (EW_LIB, through nm) for call and data edges between
 * its files, then checks, on its own account of the layer map below:
 *   - no edge runs from a lower stage up to a higher one,
 *   - no circle among library files (a .c and its .h are one node),
 *   - at most EW_MAX_HUB files outside tests/ include src/renderer.h.
 * It prints what it finds (the figures of docs/architecture.md). */
#define _POSIX_C_SOURCE 200809L
#include "util.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define EW_MAX_HUB 8
#define MAX_NODES 512
#define MAX_EDGES 8192

/* Low to high.  A file's layer is that of the first prefix (relative to
 * src/) it starts with; the top-level files not named here are the
 * assembly (renderer.c, bands.c, lab.c, builtin.c, ...). */
static const struct {
    const char *prefix;
    int layer;
    const char *name;
} layer_map[] = {
    {"ew_util", 0, "base"},   {"ew_simd", 0, "base"},     {"util", 0, "base"},     {"version", 0, "base"},
    {"frame", 0, "base"},     {"pool", 0, "base"},        {"output/", 0, "base"},
    {"ew_world", 0, "base"}, {"asset/", 1, "asset"},     {"mapgen/", 2, "mapgen"},
    {"world/", 3, "world"},   {"light/", 4, "light"},     {"raster/", 5, "raster"},
    {"hsr/", 6, "hsr"},       {"scene/", 7, "scene"},     {"overlay/", 7, "overlay"},
    {"polyhedra/", 7, "polyhedra"},
};
#define ASSEMBLY 8

typedef struct {
    char name[160]; /* path relative to src/, no extension */
    int layer;
    int has_c; /* a .c file: an object of the library */
    int index, low, on_stack; /* Tarjan */
} node;

static node nodes[MAX_NODES];
static int n_nodes;
static int edge_from[MAX_EDGES], edge_to[MAX_EDGES];
static char edge_how[MAX_EDGES][48];
static int n_edges;

static int layer_of(const char *name)
{
    for (size_t i = 0; i < sizeof layer_map / sizeof layer_map[0]; i++) {
        size_t n = strlen(layer_map[i].prefix);
        if (strncmp(name, layer_map[i].prefix, n) == 0 &&
            (layer_map[i].prefix[n - 1] == '/' || name[n] == '\0'))
            return layer_map[i].layer;
    }
    return ASSEMBLY;
}

static const char *layer_name(int layer)
{
    for (size_t i = 0; i < sizeof layer_map / sizeof layer_map[0]; i++)
        if (layer_map[i].layer == layer)
            return layer_map[i].name;
    return "assembly";
}

static int node_of(const char *rel) /* rel: "world/edges.c" */
{
    char stem[160];
    snprintf(stem, sizeof stem, "%s", rel);
    char *dot = strrchr(stem, '.');
    if (dot && strchr(dot, '/') == NULL)
        *dot = '\0';
    for (int i = 0; i < n_nodes; i++)
        if (strcmp(nodes[i].name, stem) == 0)
            return i;
    if (n_nodes == MAX_NODES)
        return -1;
    snprintf(nodes[n_nodes].name, sizeof nodes[n_nodes].name, "%s", stem);
    nodes[n_nodes].layer = layer_of(stem);
    nodes[n_nodes].index = -1;
    return n_nodes++;
}

static void add_edge(int a, int b, const char *how)
{
    if (a < 0 || b < 0 || a == b)
        return;
    for (int i = 0; i < n_edges; i++)
        if (edge_from[i] == a && edge_to[i] == b)
            return;
    if (n_edges == MAX_EDGES)
        return;
    edge_from[n_edges] = a;
    edge_to[n_edges] = b;
    snprintf(edge_how[n_edges], sizeof edge_how[n_edges], "%s", how);
    n_edges++;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* #include "x": relative to the file's folder, then to src/; public headers
 * (include/) are below every stage and not nodes. */
static void scan_includes(const char *src, const char *rel)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", src, rel);
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char dir[256];
    snprintf(dir, sizeof dir, "%s", rel);
    char *slash = strrchr(dir, '/');
    if (slash)
        slash[1] = '\0';
    else
        dir[0] = '\0';
    int self = node_of(rel);
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        char *p = line;
        while (*p == ' ' || *p == '\t')
            p++;
        if (strncmp(p, "#include", 8) != 0)
            continue;
        char *q = strchr(p, '"');
        if (!q)
            continue;
        char *e = strchr(q + 1, '"');
        if (!e)
            continue;
        *e = '\0';
        char cand[512], full[1024];
        snprintf(cand, sizeof cand, "%s%s", dir, q + 1);
        snprintf(full, sizeof full, "%s/%s", src, cand);
        if (!exists(full)) {
            snprintf(cand, sizeof cand, "%s", q + 1);
            snprintf(full, sizeof full, "%s/%s", src, cand);
            if (!exists(full))
                continue; /* a public or system header */
        }
        add_edge(self, node_of(cand), "include");
    }
    fclose(f);
}

static void walk(const char *src, const char *rel)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", src, rel);
    DIR *d = opendir(path);
    if (!d)
        return;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        if (de->d_name[0] == '.')
            continue;
        char sub[512];
        snprintf(sub, sizeof sub, "%s%s%s", rel, rel[0] ? "/" : "", de->d_name);
        char full[1024];
        snprintf(full, sizeof full, "%s/%s", src, sub);
        struct stat st;
        if (stat(full, &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode)) {
            walk(src, sub);
        } else {
            size_t n = strlen(sub);
            if (n > 2 && (strcmp(sub + n - 2, ".c") == 0 || strcmp(sub + n - 2, ".h") == 0)) {
                int v = node_of(sub);
                if (v >= 0 && strcmp(sub + n - 2, ".c") == 0)
                    nodes[v].has_c = 1;
                scan_includes(src, sub);
            }
        }
    }
    closedir(d);
}

/* "renderer.c.o" -> the node whose .c file has that base name (base names
 * of .c files are unique in src/; a header may share one: asset/scene.h). */
static int node_of_member(const char *member)
{
    char base[160];
    snprintf(base, sizeof base, "%s", member);
    char *o = strstr(base, ".c.o");
    if (!o)
        return -1;
    *o = '\0';
    for (int i = 0; i < n_nodes; i++) {
        if (!nodes[i].has_c)
            continue;
        const char *b = strrchr(nodes[i].name, '/');
        b = b ? b + 1 : nodes[i].name;
        if (strcmp(b, base) == 0)
            return i;
    }
    return -1;
}

typedef struct {
    char sym[128];
    int node;
} def;
static def defs[16384];
static int n_defs;

/* Lines of `nm -A LIB`: "LIB:member.c.o:ADDR T sym" or "LIB:member.c.o:  U sym". */
static int scan_calls(const char *lib)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "nm -A '%s' 2>/dev/null", lib);
    for (int pass = 0; pass < 2; pass++) {
        FILE *p = popen(cmd, "r");
        if (!p)
            return 0;
        char line[1024];
        int lines = 0;
        while (fgets(line, sizeof line, p)) {
            lines++;
            char *c1 = strstr(line, ".a:");
            if (!c1)
                continue;
            char *member = c1 + 3;
            char *c2 = strchr(member, ':');
            if (!c2)
                continue;
            *c2 = '\0';
            char type = 0, sym[128] = "";
            char *rest = c2 + 1;
            char a[64], t[64];
            int got = sscanf(rest, "%63s %63s %127s", a, t, sym);
            if (got >= 2 && strlen(a) == 1) { /* "U sym": no address */
                type = a[0];
                snprintf(sym, sizeof sym, "%s", t);
            } else if (got == 3 && strlen(t) == 1) {
                type = t[0];
            } else {
                continue;
            }
            int who = node_of_member(member);
            if (who < 0)
                continue;
            if (pass == 0 && strchr("TDBRCV", type) && n_defs < 16384) {
                snprintf(defs[n_defs].sym, sizeof defs[n_defs].sym, "%s", sym);
                defs[n_defs++].node = who;
            } else if (pass == 1 && type == 'U') {
                for (int i = 0; i < n_defs; i++)
                    if (strcmp(defs[i].sym, sym) == 0) {
                        char how[48];
                        snprintf(how, sizeof how, "uses %.40s", sym);
                        add_edge(who, defs[i].node, how);
                        break;
                    }
            }
        }
        pclose(p);
        if (lines == 0)
            return 0;
    }
    return 1;
}

/* Tarjan's strongly connected components: each of more than one file is a circle. */
static int tj_index, tj_stack[MAX_NODES], tj_sp, circles;

static void strong(int v)
{
    nodes[v].index = nodes[v].low = tj_index++;
    tj_stack[tj_sp++] = v;
    nodes[v].on_stack = 1;
    for (int e = 0; e < n_edges; e++) {
        if (edge_from[e] != v)
            continue;
        int w = edge_to[e];
        if (nodes[w].index < 0) {
            strong(w);
            if (nodes[w].low < nodes[v].low)
                nodes[v].low = nodes[w].low;
        } else if (nodes[w].on_stack && nodes[w].index < nodes[v].low) {
            nodes[v].low = nodes[w].index;
        }
    }
    if (nodes[v].low == nodes[v].index) {
        int members[MAX_NODES], n = 0, w;
        do {
            w = tj_stack[--tj_sp];
            nodes[w].on_stack = 0;
            members[n++] = w;
        } while (w != v);
        if (n > 1) {
            circles++;
            printf("circle of %d files:", n);
            for (int i = 0; i < n; i++)
                printf(" %s", nodes[members[i]].name);
            printf("\n");
            for (int e = 0; e < n_edges; e++) /* its edges, to see where to cut it */
                for (int i = 0; i < n; i++)
                    for (int j = 0; j < n; j++)
                        if (edge_from[e] == members[i] && edge_to[e] == members[j])
                            printf("  %s -> %s: %s\n", nodes[members[i]].name, nodes[members[j]].name,
                                   edge_how[e]);
        }
    }
}

/* Files outside tests/ that include src/renderer.h. */
static int hub_in(const char *root, const char *rel, int *count)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    DIR *d = opendir(path);
    if (!d)
        return 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        if (de->d_name[0] == '.')
            continue;
        char sub[512], full[1200];
        snprintf(sub, sizeof sub, "%s/%s", rel, de->d_name);
        snprintf(full, sizeof full, "%s/%s", root, sub);
        struct stat st;
        if (stat(full, &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode)) {
            hub_in(root, sub, count);
            continue;
        }
        size_t n = strlen(sub);
        if (n < 2 || (strcmp(sub + n - 2, ".c") && strcmp(sub + n - 2, ".h")))
            continue;
        FILE *f = fopen(full, "r");
        if (!f)
            continue;
        char line[512];
        while (fgets(line, sizeof line, f))
            if (strstr(line, "#include") && strstr(line, "renderer.h\"") &&
                !strstr(line, "_renderer.h")) {
                printf("includes renderer.h: %s\n", sub);
                (*count)++;
                break;
            }
        fclose(f);
    }
    closedir(d);
    return 1;
}

int main(void)
{
    const char *source = getenv("EW_SOURCE");
    const char *lib = getenv("EW_LIB");
    if (!source || !lib) {
        printf("SKIP: EW_SOURCE or EW_LIB not set (run through ctest)\n");
        return 77;
    }
    char src[1024];
    snprintf(src, sizeof src, "%s/src", source);
    walk(src, "");
    CHECK(n_nodes > 50, "%d library files found under %s", n_nodes, src);
    int include_edges = n_edges;
    int have_nm = scan_calls(lib);
    if (!have_nm) {
        printf("SKIP: nm could not read %s\n", lib);
        return 77;
    }
    printf("%d files, %d include edges, %d call/data edges\n", n_nodes, include_edges,
           n_edges - include_edges);

    int upward = 0;
    for (int e = 0; e < n_edges; e++) {
        const node *a = &nodes[edge_from[e]], *b = &nodes[edge_to[e]];
        if (b->layer > a->layer) {
            upward++;
            printf("upward: %s (%s) -> %s (%s): %s\n", a->name, layer_name(a->layer), b->name,
                   layer_name(b->layer), edge_how[e]);
        }
    }
    int pairs = 0; /* distinct (lower stage, higher stage) pairs among them */
    for (int la = 0; la <= ASSEMBLY; la++)
        for (int lb = la + 1; lb <= ASSEMBLY; lb++)
            for (int e = 0; e < n_edges; e++)
                if (nodes[edge_from[e]].layer == la && nodes[edge_to[e]].layer == lb) {
                    pairs++;
                    break;
                }
    printf("upward stage pairs %d\n", pairs);
    for (int v = 0; v < n_nodes; v++)
        if (nodes[v].index < 0)
            strong(v);

    int hub = 0;
    static const char *roots[] = {"src", "cli", "app", "bench", "examples", "fuzz", "include"};
    for (size_t i = 0; i < sizeof roots / sizeof roots[0]; i++)
        hub_in(source, roots[i], &hub);

    printf("upward edges %d, circles %d, files including renderer.h %d\n", upward, circles, hub);
    CHECK(upward == 0, "%d edges run from a lower stage up to a higher one", upward);
    CHECK(circles == 0, "%d circles among library files", circles);
    CHECK(hub <= EW_MAX_HUB, "%d files include renderer.h (at most %d)", hub, EW_MAX_HUB);

    /* The check can fail: a made-up upward edge is seen. */
    int world = node_of("world/edges.c"), scene = node_of("scene/passes.c");
    CHECK(world >= 0 && scene >= 0 && nodes[scene].layer > nodes[world].layer,
          "layer map: scene above world");
    return ew_t_finish();
}
