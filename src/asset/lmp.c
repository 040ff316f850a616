/* palette.lmp and colormap.lmp: raw tables, only their sizes can be wrong. */
#include "ew_util.h"

int ew_palette_parse(const uint8_t *data, size_t size, const char *filename,
                     uint8_t palette[768], ew_error *err) {
    if (size < 768)
        return ew_fail(err, "%s: palette too short (%zu bytes, need 768)", filename, size);
    memcpy(palette, data, 768);
    return 0;
}

int ew_colormap_parse(const uint8_t *data, size_t size, const char *filename,
                      uint8_t colormap[EW_COLORMAP_SIZE], ew_error *err) {
    /* Quake's file has 64 rows (16384 bytes); some have a trailing byte. */
    if (size < EW_COLORMAP_SIZE)
        return ew_fail(err, "%s: colormap too short (%zu bytes, need %d)", filename, size,
                       EW_COLORMAP_SIZE);
    memcpy(colormap, data, EW_COLORMAP_SIZE);
    return 0;
}
