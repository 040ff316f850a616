/* A Quake game directory: loose files first, then pak0.pak, pak1.pak, ...
 * searched from the highest number down, so later paks override earlier. */
#define _POSIX_C_SOURCE 200809L
#include "ew_util.h"
#include "asset/lightdata.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

/* Quake stops at the first missing pakN; the cap only guards against a
 * directory full of generated names. */
#define FS_MAX_PAKS 1000

typedef struct fs_pak {
    char         *path;
    uint8_t      *data;
    size_t        size;
    ew_pak_entry *entries;
    int           count;
} fs_pak;

struct ew_fs {
    char   *dir;
    fs_pak *paks;
    int     npaks;
    struct ew_fs *next;  /* a search list's next directory ("GAME:BASE"), NULL at its end */
};

static char *dup_str(const char *s) {
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

/* "dir/name" in a fresh allocation. */
static char *join(const char *dir, const char *name) {
    size_t a = strlen(dir), b = strlen(name);
    char *p = malloc(a + b + 2);
    if (!p) return NULL;
    memcpy(p, dir, a);
    p[a] = '/';
    memcpy(p + a + 1, name, b + 1);
    return p;
}

void ew_fs_destroy(ew_fs *fs) {
    if (!fs) return;
    ew_fs_destroy(fs->next);
    for (int i = 0; i < fs->npaks; i++) {
        free(fs->paks[i].path);
        free(fs->paks[i].data);
        free(fs->paks[i].entries);
    }
    free(fs->paks);
    free(fs->dir);
    free(fs);
}

static ew_fs *fs_create_one(const char *dir, ew_error *err);

/* A search list: "GAME:BASE" (any number of directories) when dir is not
 * itself a directory; each one is opened as a game directory of its own
 * and searched in the list's order, as Quake's -game over id1. */
ew_fs *ew_fs_create(const char *dir, ew_error *err) {
    struct stat st;
    const char *colon = strchr(dir, ':');
    if (!colon || (stat(dir, &st) == 0 && S_ISDIR(st.st_mode))) return fs_create_one(dir, err);
    if (colon == dir || !colon[1]) {
        ew_fail(err, "%s: an empty directory in the search list", dir);
        return NULL;
    }
    char *first = malloc((size_t)(colon - dir) + 1);
    if (!first) {
        ew_fail(err, "%s: out of memory", dir);
        return NULL;
    }
    memcpy(first, dir, (size_t)(colon - dir));
    first[colon - dir] = 0;
    ew_fs *fs = fs_create_one(first, err);
    free(first);
    if (!fs) return NULL;
    if (!(fs->next = ew_fs_create(colon + 1, err))) {
        ew_fs_destroy(fs);
        return NULL;
    }
    return fs;
}

static ew_fs *fs_create_one(const char *dir, ew_error *err) {
    struct stat st;
    if (stat(dir, &st) != 0) {
        ew_fail(err, "%s: cannot open: %s", dir, strerror(errno));
        return NULL;
    }
    if (!S_ISDIR(st.st_mode)) {
        ew_fail(err, "%s: not a directory", dir);
        return NULL;
    }
    ew_fs *fs = calloc(1, sizeof *fs);
    if (!fs || !(fs->dir = dup_str(dir))) {
        free(fs);
        ew_fail(err, "%s: out of memory", dir);
        return NULL;
    }
    for (int i = 0; i < FS_MAX_PAKS; i++) {
        char name[32];
        snprintf(name, sizeof name, "pak%d.pak", i);
        char *path = join(dir, name);
        if (!path) {
            ew_fail(err, "%s: out of memory", dir);
            goto fail;
        }
        if (stat(path, &st) != 0) {  /* the first missing pak ends the list */
            free(path);
            break;
        }
        fs_pak *grown = realloc(fs->paks, (size_t)(fs->npaks + 1) * sizeof *grown);
        if (!grown) {
            free(path);
            ew_fail(err, "%s: out of memory", dir);
            goto fail;
        }
        fs->paks = grown;
        fs_pak *p = &fs->paks[fs->npaks++];
        memset(p, 0, sizeof *p);
        p->path = path;
        if (ew_read_file(path, &p->data, &p->size, err) != 0 ||
            ew_pak_parse(p->data, p->size, path, &p->entries, &p->count, err) != 0)
            goto fail;
    }
    return fs;
fail:
    ew_fs_destroy(fs);
    return NULL;
}

static int fs_load_one(const ew_fs *fs, const char *name, uint8_t **data, size_t *size,
                       ew_error *err) {
    *data = NULL;
    *size = 0;
    char *path = join(fs->dir, name);
    if (!path) return ew_fail(err, "%s: out of memory", fs->dir);
    struct stat st;
    if (stat(path, &st) == 0) {  /* a loose file wins over every pak */
        int rc = ew_read_file(path, data, size, err);
        free(path);
        return rc;
    }
    free(path);
    for (int i = fs->npaks - 1; i >= 0; i--) {
        const fs_pak *p = &fs->paks[i];
        for (int j = 0; j < p->count; j++) {
            if (!ew_same_name(p->entries[j].name, name)) continue;
            /* ew_pak_parse checked the entry lies inside the pak. */
            size_t n = p->entries[j].size;
            uint8_t *buf = malloc(n ? n : 1);
            if (!buf) return ew_fail(err, "%s: %s: out of memory (%zu bytes)", p->path, name, n);
            memcpy(buf, p->data + p->entries[j].offset, n);
            *data = buf;
            *size = n;
            return 0;
        }
    }
    return 1;  /* not here */
}

int ew_fs_load(const ew_fs *fs, const char *name, uint8_t **data, size_t *size,
               ew_error *err) {
    for (const ew_fs *d = fs; d; d = d->next) {
        int rc = fs_load_one(d, name, data, size, err);
        if (rc <= 0) return rc;
    }
    if (!fs->next)
        return ew_fail(err, "%s: %s not found (searched %s and %d pak%s)", fs->dir, name, fs->dir,
                       fs->npaks, fs->npaks == 1 ? "" : "s");
    char dirs[400] = "";
    for (const ew_fs *d = fs; d; d = d->next) {
        size_t n = strlen(dirs);
        snprintf(dirs + n, sizeof dirs - n, "%s%s (%d pak%s)", d == fs ? "" : ", ", d->dir, d->npaks,
                 d->npaks == 1 ? "" : "s");
    }
    return ew_fail(err, "%s: %s not found (searched %s)", fs->dir, name, dirs);
}

static int fs_exists_one(const ew_fs *fs, const char *name);

/* asset/lightdata.h: where ew_fs_load finds name, for messages. */
void ew_fs_where(const ew_fs *fs, const char *name, char *out, size_t size) {
    for (const ew_fs *d = fs->next; d; d = d->next)  /* found further down the list */
        if (!fs_exists_one(fs, name) && fs_exists_one(d, name)) {
            ew_fs_where(d, name, out, size);
            return;
        }
    snprintf(out, size, "%s/%s", fs->dir, name);
    struct stat st;
    if (stat(out, &st) == 0) return;  /* the loose file */
    for (int i = fs->npaks - 1; i >= 0; i--)
        for (int j = 0; j < fs->paks[i].count; j++)
            if (ew_same_name(fs->paks[i].entries[j].name, name)) {
                snprintf(out, size, "%s: %s", fs->paks[i].path, name);
                return;
            }
}

/* asset/lightdata.h: optional files (a map's .lit) are looked for quietly. */
int ew_fs_exists(const ew_fs *fs, const char *name) {
    for (; fs; fs = fs->next)
        if (fs_exists_one(fs, name)) return 1;
    return 0;
}

static int fs_exists_one(const ew_fs *fs, const char *name) {
    if (!fs || !name) return 0;
    char *path = join(fs->dir, name);
    if (!path) return 0;
    struct stat st;
    int found = stat(path, &st) == 0 && S_ISREG(st.st_mode);
    free(path);
    for (int i = fs->npaks - 1; i >= 0 && !found; i--)
        for (int j = 0; j < fs->paks[i].count && !found; j++)
            found = ew_same_name(fs->paks[i].entries[j].name, name);
    return found;
}
