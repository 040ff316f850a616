/* PAK archives: "PACK", int32 dirofs, int32 dirlen; the directory is
 * dirlen/64 entries of char name[56], int32 filepos, int32 filelen. */
#include "ew_util.h"

#include <stdio.h>
#include <stdlib.h>

#define PAK_HEADER 12
#define PAK_ENTRY 64
#define PAK_NAME 56
/* Far above any real pak (Quake's own limit is 2048), low enough that a
 * corrupt dirlen cannot ask for an absurd allocation. */
#define PAK_MAX_ENTRIES (1 << 20)

/* An entry name for a message: bytes outside printable ASCII (and the
 * backslash) as \xNN, so a corrupt directory prints as one readable line. */
static void escaped_name(const char *name, char *out, size_t size) {
    size_t n = 0;
    for (const unsigned char *p = (const unsigned char *)name; *p && n + 5 < size; p++) {
        if (*p < 0x20 || *p >= 0x7f || *p == '\\')
            n += (size_t)snprintf(out + n, size - n, "\\x%02x", *p);
        else
            out[n++] = (char)*p;
    }
    out[n] = '\0';
}

int ew_pak_parse(const uint8_t *data, size_t size, const char *filename,
                 ew_pak_entry **entries, int *count, ew_error *err) {
    *entries = NULL;
    *count = 0;
    if (size < PAK_HEADER)
        return ew_fail(err, "%s: file too short for a PAK header (%zu bytes)", filename, size);
    if (memcmp(data, "PACK", 4) != 0)
        return ew_fail(err, "%s: not a PAK file (no \"PACK\" magic)", filename);
    int32_t dirofs = ew_i32(data + 4), dirlen = ew_i32(data + 8);
    if (dirofs < 0 || dirlen < 0)
        return ew_fail(err, "%s: bad directory (offset %d, length %d)", filename,
                       (int)dirofs, (int)dirlen);
    if (dirlen % PAK_ENTRY != 0)
        return ew_fail(err, "%s: directory length %d is not a multiple of %d", filename,
                       (int)dirlen, PAK_ENTRY);
    if ((uint64_t)dirofs + (uint64_t)dirlen > size)
        return ew_fail(err, "%s: directory at offset %d (length %d) past end of file (%zu bytes)",
                       filename, (int)dirofs, (int)dirlen, size);
    int n = dirlen / PAK_ENTRY;
    if (n > PAK_MAX_ENTRIES)
        return ew_fail(err, "%s: too many entries (%d, limit %d)", filename, n, PAK_MAX_ENTRIES);

    ew_pak_entry *e = calloc(n ? (size_t)n : 1, sizeof *e);
    if (!e) return ew_fail(err, "%s: out of memory (%d entries)", filename, n);
    for (int i = 0; i < n; i++) {
        const uint8_t *p = data + dirofs + (size_t)i * PAK_ENTRY;
        const uint8_t *nul = memchr(p, 0, PAK_NAME);
        if (!nul) {
            free(e);
            return ew_fail(err, "%s: entry %d: name not NUL-terminated within %d bytes",
                           filename, i, PAK_NAME);
        }
        memcpy(e[i].name, p, (size_t)(nul - p));
        e[i].name[nul - p] = '\0';
        int32_t ofs = ew_i32(p + PAK_NAME), len = ew_i32(p + PAK_NAME + 4);
        if (ofs < 0 || len < 0 || (uint64_t)ofs + (uint64_t)len > size) {
            char shown[PAK_NAME * 4 + 1];
            escaped_name(e[i].name, shown, sizeof shown);
            if (ofs < 0 || len < 0)
                ew_fail(err, "%s: entry %d ('%s'): negative %s %ld", filename, i, shown,
                        ofs < 0 ? "offset" : "size", (long)(ofs < 0 ? ofs : len));
            else
                ew_fail(err, "%s: entry %d ('%s'): offset %ld + size %ld past end of file (%zu bytes)",
                        filename, i, shown, (long)ofs, (long)len, size);
            free(e);
            return -1;
        }
        e[i].offset = (uint32_t)ofs;
        e[i].size = (uint32_t)len;
    }
    *entries = e;
    *count = n;
    return 0;
}
