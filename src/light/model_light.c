/* The light an alias model is drawn with (see light/lightpoint.c). */
#include "light/light.h"
#include "ew_util.h"
#include "asset/scene.h"

#include <math.h>

/* Light on a model: the floor under it, plus dynamic lights in reach, held
 * to a floor of 24 and a ceiling so shading keeps some contrast. */
void ew_light_model(const ew_frame *f, const struct ew_scene *sc, const float origin[3], int *ambient, int *shade) {
    int l = ew_light_point(f, origin);
    for (int i = 0; i < sc->ndlights; i++) {
        const ew_dlight *d = &sc->dlights[i];
        float dx = origin[0] - d->origin[0], dy = origin[1] - d->origin[1], dz = origin[2] - d->origin[2];
        float add = d->radius - sqrtf(dx * dx + dy * dy + dz * dz);
        if (add > 0) l += ew_int_checked(add, 0, 1 << 20, 0);  /* the most shows as 192 */
    }
    int a = l < 24 ? 24 : l > 128 ? 128 : l, s = l < 24 ? 24 : l;
    if (a + s > 192) s = 192 - a;
    *ambient = a, *shade = s;
}

int ew_light_tint(const ew_frame *f, const float origin[3], int tint[3]) {
    tint[0] = tint[1] = tint[2] = 256;
    if (!ew_use_rgb_light(f, f->world)) return 0;
    int rgb[3];
    ew_light_point_rgb(f, origin, rgb);
    /* The hue of the light under the model, its brightness left to the
     * white level (ambient and shade): channel over the channels' mean. */
    int sum = rgb[0] + rgb[1] + rgb[2];
    if (sum <= 0 || (rgb[0] == rgb[1] && rgb[1] == rgb[2])) return 0;
    for (int k = 0; k < 3; k++) {
        int t = rgb[k] * 3 * 256 / sum;
        tint[k] = t > 768 ? 768 : t;
    }
    return 1;
}
