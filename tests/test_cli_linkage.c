/* The command on the public API: build/edgewise (EW_CLI) is linked against
 * the shared library.  Reads the ELF dynamic section of the executable
 * itself (no readelf needed) and checks that its NEEDED entries name
 * libedgewise.so.MAJOR, that it carries a run path (RUNPATH or RPATH) so
 * that it runs from the build folder, and that it runs.  Exits 77 (skipped)
 * where the command is linked statically on purpose (EW_BUILD_SHARED off,
 * the sanitizer builds: EW_CLI_SHARED=0). */
#define _POSIX_C_SOURCE 200809L  /* mkdtemp */
#include "util.h"

#include <elf.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef EW_SOVERSION
#error "EW_SOVERSION: the shared library's major version (CMake sets it)"
#endif

/* The file, malloc'd; NULL if unreadable. */
static uint8_t *read_all(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    uint8_t *buf = NULL;
    size_t cap = 0, n = 0;
    for (;;) {
        if (n == cap) {
            cap = cap ? cap * 2 : 1 << 20;
            uint8_t *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = nb;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        if (got == 0) break;
        n += got;
    }
    fclose(f);
    *size = n;
    return buf;
}

typedef struct dyn_info {
    char needed[16][128];
    int  nneeded;
    int  has_runpath;
} dyn_info;

/* The NEEDED names and whether a run path is set, from a 64-bit ELF
 * image; 0, or -1 with why in *why. */
static int read_dynamic(const uint8_t *img, size_t size, dyn_info *out, const char **why) {
    memset(out, 0, sizeof *out);
    if (size < sizeof(Elf64_Ehdr) || memcmp(img, ELFMAG, SELFMAG) != 0) return *why = "not an ELF file", -1;
    if (img[EI_CLASS] != ELFCLASS64) return *why = "not a 64-bit ELF file", -1;
    Elf64_Ehdr eh;
    memcpy(&eh, img, sizeof eh);
    if (eh.e_shoff == 0 || eh.e_shentsize != sizeof(Elf64_Shdr) ||
        eh.e_shoff + (uint64_t)eh.e_shnum * sizeof(Elf64_Shdr) > size)
        return *why = "no section headers", -1;
    for (int i = 0; i < eh.e_shnum; i++) {
        Elf64_Shdr sh, strh;
        memcpy(&sh, img + eh.e_shoff + (size_t)i * sizeof sh, sizeof sh);
        if (sh.sh_type != SHT_DYNAMIC) continue;
        if (sh.sh_link >= eh.e_shnum) return *why = "bad dynamic string table", -1;
        memcpy(&strh, img + eh.e_shoff + (size_t)sh.sh_link * sizeof strh, sizeof strh);
        if (sh.sh_offset + sh.sh_size > size || strh.sh_offset + strh.sh_size > size)
            return *why = "dynamic section outside the file", -1;
        const char *strtab = (const char *)img + strh.sh_offset;
        for (size_t k = 0; k + sizeof(Elf64_Dyn) <= sh.sh_size; k += sizeof(Elf64_Dyn)) {
            Elf64_Dyn d;
            memcpy(&d, img + sh.sh_offset + k, sizeof d);
            if (d.d_tag == DT_NULL) break;
            if (d.d_tag == DT_RUNPATH || d.d_tag == DT_RPATH) out->has_runpath = 1;
            if (d.d_tag == DT_NEEDED && d.d_un.d_val < strh.sh_size && out->nneeded < 16) {
                snprintf(out->needed[out->nneeded], sizeof out->needed[0], "%s", strtab + d.d_un.d_val);
                out->nneeded++;
            }
        }
        return 0;
    }
    return *why = "no dynamic section (a static executable)", -1;
}

int main(void) {
    const char *cli = getenv("EW_CLI");
    const char *shared = getenv("EW_CLI_SHARED");
    if (!cli || !*cli) {
        fprintf(stderr, "EW_CLI is not set (run through ctest): skipped\n");
        return 77;
    }
    if (shared && strcmp(shared, "0") == 0) {
        fprintf(stderr, "the command is linked statically in this build (EW_BUILD_SHARED off): skipped\n");
        return 77;
    }
    size_t size = 0;
    uint8_t *img = read_all(cli, &size);
    CHECK(img != NULL, "cannot read %s", cli);
    if (img) {
        dyn_info di;
        const char *why = "";
        int ok = read_dynamic(img, size, &di, &why) == 0;
        CHECK(ok, "%s: %s", cli, why);
        char want[64];
        snprintf(want, sizeof want, "libedgewise.so.%d", EW_SOVERSION);
        int found = 0;
        for (int i = 0; ok && i < di.nneeded; i++) found |= strcmp(di.needed[i], want) == 0;
        CHECK(!ok || found, "%s does not need %s (%d NEEDED entries)", cli, want, di.nneeded);
        CHECK(!ok || di.has_runpath, "%s has no RUNPATH/RPATH: it would not find %s in the build folder", cli, want);
        free(img);
    }
    /* and it runs, finding the library by its run path */
    char tmp[] = "/tmp/ew_linkage_XXXXXX";
    CHECK(mkdtemp(tmp) != NULL, "mkdtemp");
    ew_t_run r;
    const char *args[] = { "--version", NULL };
    ew_t_run_cli(&r, tmp, args);
    CHECK(r.status == 0 && strstr(r.out, ew_version()) != NULL, "edgewise --version: status %d, out '%s' err '%s'",
          r.status, r.out, r.err);
    char path[64];
    snprintf(path, sizeof path, "%s/stdout.txt", tmp), remove(path);
    snprintf(path, sizeof path, "%s/stderr.txt", tmp), remove(path);
    rmdir(tmp);
    return ew_t_finish();
}
