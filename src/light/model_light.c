/* The light an alias model is drawn with (see light/lightpoint.c). */
#include "renderer.h"
#include "scene/scene.h"

#include <math.h>

/* Light on a model: the floor under it, plus dynamic lights in reach, held
 * to a floor of 24 and a ceiling so shading keeps some contrast. */
void ew_model_light(const ew_renderer *r, const float origin[3], int *ambient, int *shade) {
    const struct ew_scene *sc = r->ents.scene;
    int l = ew_light_point(r, origin);
    for (int i = 0; i < sc->ndlights; i++) {
        const ew_dlight *d = &sc->dlights[i];
        float dx = origin[0] - d->origin[0], dy = origin[1] - d->origin[1], dz = origin[2] - d->origin[2];
        float add = d->radius - sqrtf(dx * dx + dy * dy + dz * dz);
        if (add > 0) l += (int)add;
    }
    int a = l < 24 ? 24 : l > 128 ? 128 : l, s = l < 24 ? 24 : l;
    if (a + s > 192) s = 192 - a;
    *ambient = a, *shade = s;
}
