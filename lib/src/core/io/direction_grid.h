/* Internal: the direction sets a reader of an evaluable format (an RGL-EPFL material,
 * an NVIDIA mbsdf table) can be asked for instead of its measured points
 * (bf_read_options.grid):
 *   "merl"       every MERL cell centre (merl.h) with both directions above the
 *                horizon: 1,096,216 samples addressed by cells;
 *   "uniform:N"  theta_i, theta_o at the N cell centres of [0, 90) degrees and the
 *                azimuth difference at the N cell centres of [0, 180] (isotropic data
 *                needs no more), phi_i = 0: N^3 samples, 1 <= N <= 128;
 *   FILE         a CSV with columns theta_i, phi_i, theta_o, phi_o in degrees (other
 *                columns ignored), one sample per row, in order. */
#ifndef BF_DIRECTION_GRID_H
#define BF_DIRECTION_GRID_H

#include "brdfit/error.h"
#include "brdfit/samples.h"

/* Samples with the grid's directions and `channels` zeroed values, for the caller to
 * fill. Errors name the grid ("grid uniform:0: ...", "FILE:LINE: ..."). */
bf_status bf_direction_grid(const char *spec, int channels, bf_samples **out, bf_error *err);

#endif
