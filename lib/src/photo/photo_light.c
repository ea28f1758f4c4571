/* Per-pixel light and view (photo_impl.h), from the stack's camera (docs/images.md):
 * an orthographic camera puts pixel (x, y) at a point of its image plane and looks along
 * its -z; a pinhole camera's ray through the pixel meets the world plane z = 0 (the
 * sample's plane). Directional lights are the same everywhere; a point light's direction
 * and 1/r^2 irradiance follow the pixel's surface point. */
#include <math.h>

#include "photo_impl.h"

static void rotate(const double *R, const double a[3], double b[3])
{
    for (int i = 0; i < 3; i++)
        b[i] = R[3 * i] * a[0] + R[3 * i + 1] * a[1] + R[3 * i + 2] * a[2];
}

void photo_to_world(const bf_stack *s, const double c[3], double w[3])
{
    rotate(s->camera.rotation, c, w);
}

void photo_to_camera(const bf_stack *s, const double w[3], double c[3])
{
    const double *R = s->camera.rotation;
    for (int i = 0; i < 3; i++)
        c[i] = R[i] * w[0] + R[3 + i] * w[1] + R[6 + i] * w[2];
}

static void normalise(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0.0)
        for (int i = 0; i < 3; i++)
            v[i] /= l;
}

void photo_lights_at(const bf_stack *s, int x, int y, photo_lights *pl)
{
    const bf_stack_camera *cam = &s->camera;
    double P[3], cv[3];
    if (cam->type == BF_CAMERA_PINHOLE) {
        double d_cam[3] = {(x + 0.5 - cam->cx) / cam->fx, -(y + 0.5 - cam->cy) / cam->fy, -1.0}, d[3];
        rotate(cam->rotation, d_cam, d);
        /* The ray position + t d meets z = 0 at t = -position_z / d_z (a camera looking
         * away from the plane gets the point behind it: its pixels see nothing real). */
        double t = fabs(d[2]) > 1e-12 ? -cam->position[2] / d[2] : 0.0;
        for (int i = 0; i < 3; i++) {
            P[i] = cam->position[i] + t * d[i];
            pl->v[i] = -d[i];
        }
        normalise(pl->v);
    } else {
        double q[3] = {(x + 0.5 - 0.5 * s->width) * cam->pixel_size, -(y + 0.5 - 0.5 * s->height) * cam->pixel_size,
                       0.0},
               r[3];
        rotate(cam->rotation, q, r);
        for (int i = 0; i < 3; i++)
            P[i] = cam->center[i] + r[i];
        cv[0] = cv[1] = 0.0;
        cv[2] = 1.0;
        rotate(cam->rotation, cv, pl->v);
    }
    int C = s->channels;
    for (int k = 0; k < s->nimages; k++) {
        const bf_stack_image *im = &s->images[k];
        double *l = pl->l + 3 * k, f = 1.0;
        if (im->point) {
            double r2 = 0.0;
            for (int i = 0; i < 3; i++) {
                l[i] = im->pos[i] - P[i];
                r2 += l[i] * l[i];
            }
            normalise(l);
            f = r2 > 0.0 ? 1.0 / r2 : 0.0;
        } else {
            for (int i = 0; i < 3; i++)
                l[i] = im->dir[i];
            normalise(l);
        }
        for (int c = 0; c < C; c++)
            pl->e[k * C + c] = im->intensity[c] * f;
    }
}
