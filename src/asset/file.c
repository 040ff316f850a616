/* Whole-file reads. */
#define _POSIX_C_SOURCE 200809L
#include "ew_util.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

/* Nothing edgewise reads (maps, paks, lumps) comes near this; a bigger file
 * is a mistake, and refusing it keeps every size comfortably in int range. */
#define EW_MAX_FILE ((size_t)1 << 30)

int ew_read_file(const char *path, uint8_t **data, size_t *size, ew_error *err) {
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return ew_fail(err, "%s: cannot open: %s", path, strerror(errno));

    struct stat st;
    if (fstat(fileno(f), &st) != 0) {
        int e = errno;
        fclose(f);
        return ew_fail(err, "%s: cannot open: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        fclose(f);
        return ew_fail(err, "%s: not a regular file", path);
    }
    if (st.st_size < 0 || (uint64_t)st.st_size > EW_MAX_FILE) {
        fclose(f);
        return ew_fail(err, "%s: file too large (%lld bytes, limit 1 GiB)", path,
                       (long long)st.st_size);
    }
    size_t n = (size_t)st.st_size;
    uint8_t *buf = malloc(n ? n : 1);  /* non-NULL even for an empty file */
    if (!buf) {
        fclose(f);
        return ew_fail(err, "%s: out of memory (%zu bytes)", path, n);
    }
    /* A short read (I/O error, or the file shrank since fstat) is an error. */
    if (fread(buf, 1, n, f) != n || ferror(f)) {
        free(buf);
        fclose(f);
        return ew_fail(err, "%s: read error", path);
    }
    fclose(f);
    *data = buf;
    *size = n;
    return 0;
}
