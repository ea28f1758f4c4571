/* MERL tables: the cell grid (90 theta_h x 90 theta_d x 180 phi_d, theta_h on a square
 * root scale) and its arithmetic. A sample set read from a MERL table is addressed by
 * cells (samples.h); reading and writing the files is formats.h.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_MERL_H
#define BRDFIT_MERL_H

#include <stdint.h>

#include "brdfit/api.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A sample set addressed by MERL table cells: each sample stands for the direction pair
 * at the centre of its cell (cell = phi_d + theta_d*180 + theta_h*180*90), so the
 * directions need no arrays of their own. raw is the table as read (3 planes of
 * BF_MERL_CELLS doubles, scale factors not applied, invalid cells included), kept only
 * when asked for (bf_read_options.keep_origin): with it, writing the samples back as a
 * MERL table gives the same bytes. */
#define BF_MERL_TH 90
#define BF_MERL_TD 90
#define BF_MERL_PD 180
#define BF_MERL_CELLS (BF_MERL_TH * BF_MERL_TD * BF_MERL_PD)
typedef struct bf_merl_origin {
    double *raw;   /* NULL, or 3 * BF_MERL_CELLS, planes R, G, B */
    int32_t *cell; /* per sample */
} bf_merl_origin;

/* MERL cell centre <-> directions in degrees (Rusinkiewicz half/difference angles,
 * phi_h = 0). */
BF_API void bf_merl_cell_directions(int32_t cell, double *theta_i, double *phi_i, double *theta_o, double *phi_o);
/* The cell whose centre these directions are (within 1e-9 rad in theta_h and theta_d;
 * phi_d within 1e-9 rad plus its own rounding, which grows as H nears N), or -1. */
BF_API int32_t bf_merl_cell_of(double theta_i, double phi_i, double theta_o, double phi_o);

#ifdef __cplusplus
}
#endif
#endif
