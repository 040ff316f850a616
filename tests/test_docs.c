/*
 * The documentation against the program (issue 33, item 7), so it cannot
 * drift again:
 *   - every `--stats` example in README.md and the .md files of docs/ (a code block
 *     line starting {"map":) lists exactly the top-level fields that
 *     `edgewise render builtin --stats` prints, in its order;
 *   - README.md's code blocks run the command as ./build/edgewise (or
 *     build/edgewise), never a bare `edgewise` that is not on PATH after
 *     `make build`;
 *   - README.md gives the time `make demo` and `make test` take;
 *   - every worldspawn key the loader reads (src/asset/worldspawn.c) is in
 *     docs/seethrough.md's worldspawn table, `_fog` and `fog` included.
 */
#define _DEFAULT_SOURCE
#include "util.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_KEYS 256

static char *slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)(n > 0 ? n : 0) + 1);
    size_t got = b ? fread(b, 1, (size_t)(n > 0 ? n : 0), f) : 0;
    if (b) b[got] = '\0';
    fclose(f);
    return b;
}

/* The names of the top-level object's fields in a JSON-like text (a doc
 * example's "..." placeholders are not strings, so they are skipped as
 * any other value); their count. */
static int top_keys(const char *s, char keys[MAX_KEYS][64]) {
    int depth = 0, n = 0;
    for (const char *p = s; *p; p++) {
        if (*p == '{' || *p == '[') depth++;
        else if (*p == '}' || *p == ']') {
            if (--depth == 0) break;
        } else if (*p == '"') {
            const char *q = strchr(p + 1, '"');
            if (!q) break;
            const char *after = q + 1;
            while (*after == ' ') after++;
            if (depth == 1 && *after == ':' && n < MAX_KEYS) {
                snprintf(keys[n], sizeof keys[n], "%.*s", (int)(q - p - 1), p + 1);
                n++;
            }
            p = q;
        }
    }
    return n;
}

static int nreal;
static char real[MAX_KEYS][64];

/* Every {"map": example in the file checked (an example's lines joined
 * into one); their count. */
static int check_examples(const char *path, const char *label) {
    char *text = slurp(path);
    if (!text) return 0;
    for (char *p = text; (p = strstr(p, "\n{\"map\":"));) {
        char *end = strstr(p, "\n```");
        for (char *q = p + 1; end && q < end; q++)
            if (*q == '\n') *q = ' ';
        p = end ? end : p + 1;
    }
    int found = 0;
    int in_code = 0;
    for (char *line = text; *line;) {
        char *nl = strchr(line, '\n');
        if (!strncmp(line, "```", 3)) in_code = !in_code;
        else if (in_code && !strncmp(line, "{\"map\":", 7)) {
            static char doc[MAX_KEYS][64];
            int n = top_keys(line, doc);
            found++;
            int same = n == nreal;
            for (int i = 0; same && i < n; i++) same = !strcmp(doc[i], real[i]);
            if (!same) {
                for (int i = 0; i < nreal; i++) {
                    int in = 0;
                    for (int j = 0; j < n && !in; j++) in = !strcmp(doc[j], real[i]);
                    if (!in) fprintf(stderr, "%s: the --stats example lacks \"%s\"\n", label, real[i]);
                }
                for (int j = 0; j < n; j++) {
                    int in = 0;
                    for (int i = 0; i < nreal && !in; i++) in = !strcmp(doc[j], real[i]);
                    if (!in) fprintf(stderr, "%s: the --stats example has \"%s\", which is not printed\n", label,
                                     doc[j]);
                }
            }
            CHECK(same, "%s: the --stats example's %d fields are not the %d that render --stats prints, in order",
                  label, n, nreal);
        }
        if (!nl) break;
        line = nl + 1;
    }
    free(text);
    return found;
}

int main(void) {
    const char *src = getenv("EW_SOURCE");
    if (!src) {
        ew_t_skip("EW_SOURCE not set (ctest sets it)");
        return ew_t_finish();
    }
    char tmpdir[] = "/tmp/ew_docs_XXXXXX";
    if (!mkdtemp(tmpdir)) return 1;
    ew_t_run r;
    const char *args[] = { "render", "builtin", "--size", "320x200", "--out", "d.png", "--stats", NULL };
    ew_t_run_cli(&r, tmpdir, args);
    CHECK(r.status == 0, "render builtin --stats: %d %s", r.status, r.err);
    nreal = top_keys(r.out, real);
    CHECK(nreal > 40, "render --stats printed %d fields", nreal);

    /* The examples in README.md and the .md files of docs/. */
    char path[1024];
    snprintf(path, sizeof path, "%s/README.md", src);
    int examples = check_examples(path, "README.md");
    snprintf(path, sizeof path, "%s/docs", src);
    DIR *d = opendir(path);
    struct dirent *e;
    while (d && (e = readdir(d))) {
        size_t l = strlen(e->d_name);
        if (l < 4 || strcmp(e->d_name + l - 3, ".md")) continue;
        char file[1200], label[300];
        snprintf(file, sizeof file, "%s/docs/%s", src, e->d_name);
        snprintf(label, sizeof label, "docs/%s", e->d_name);
        examples += check_examples(file, label);
    }
    if (d) closedir(d);
    CHECK(examples >= 1, "found %d --stats examples in README.md and docs/", examples);

    /* README: the command as built, the times of the two commands. */
    snprintf(path, sizeof path, "%s/README.md", src);
    char *readme = slurp(path);
    CHECK(readme != NULL, "README.md");
    if (readme) {
        int in_code = 0, bare = 0;
        for (char *line = readme; *line;) {
            char *nl = strchr(line, '\n');
            if (!strncmp(line, "```", 3)) in_code = !in_code;
            else if (in_code && !strncmp(line, "edgewise ", 9)) {
                fprintf(stderr, "README.md: %.*s\n", nl ? (int)(nl - line) : (int)strlen(line), line);
                bare++;
            }
            if (!nl) break;
            line = nl + 1;
        }
        CHECK(bare == 0, "README.md: %d command lines call a bare 'edgewise' (not on PATH after make build)", bare);
        CHECK(strstr(readme, "make demo") && strstr(readme, "make test") && strstr(readme, "2-core machine") &&
              strstr(readme, " s ") && strstr(readme, " min"), "README.md gives the times of make demo and make test");
        free(readme);
    }

    /* Worldspawn keys: the loader's against docs/seethrough.md. */
    snprintf(path, sizeof path, "%s/src/asset/worldspawn.c", src);
    char *loader = slurp(path);
    snprintf(path, sizeof path, "%s/docs/seethrough.md", src);
    char *doc = slurp(path);
    CHECK(loader && doc, "worldspawn.c and seethrough.md");
    if (loader && doc) {
        int keys = 0;
        /* read_alpha(w, ws, "wateralpha", ...) and read_fog's find_key(e, "fog") */
        for (const char *p = loader; (p = strstr(p, "(w, ws, \"")) != NULL;) {
            p += 9;
            char key[64], want[80];
            snprintf(key, sizeof key, "%.*s", (int)strcspn(p, "\""), p);
            snprintf(want, sizeof want, "`_%s`", key);
            CHECK(strstr(doc, want) != NULL, "docs/seethrough.md documents the worldspawn key %s", want);
            keys++;
        }
        CHECK(strstr(loader, "find_key(e, \"fog\")") != NULL, "the loader reads fog");
        CHECK(strstr(doc, "`fog`") && strstr(doc, "`_fog`"), "docs/seethrough.md documents `fog` and `_fog`");
        CHECK(keys >= 4, "the loader's liquid keys: %d", keys);
        CHECK(strstr(doc, "## Worldspawn keys") != NULL, "docs/seethrough.md has a worldspawn keys section");
    }
    free(loader);
    free(doc);
    snprintf(path, sizeof path, "%s/d.png", tmpdir);
    unlink(path);
    rmdir(tmpdir);
    return ew_t_finish();
}
