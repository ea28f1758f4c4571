/* Shared by the render files: a model's C channels as one RGB pixel. */
#ifndef BRDFIT_RENDER_COLOR_H
#define BRDFIT_RENDER_COLOR_H

/* C = 1: grey; C = 3: as is; otherwise the mean of the channels, as grey. */
static inline void bf_channels_to_rgb(const double *v, int C, double rgb[3])
{
    if (C == 3) {
        rgb[0] = v[0];
        rgb[1] = v[1];
        rgb[2] = v[2];
        return;
    }
    double s = 0.0;
    for (int c = 0; c < C; c++)
        s += v[c];
    rgb[0] = rgb[1] = rgb[2] = s / C;
}

#endif
