/* The report viewer's tables (internal): a model or a measurement tabulated on a small
 * half/difference grid and stored compactly for the page (docs/report.md, "Tables").
 *
 * The grid (nodes, values at the node; the viewer interpolates linearly between them):
 *   theta_h = 90 deg * (i / (NH - 1))^2  (square-root spacing: the highlight keeps nodes)
 *   theta_d = 90 deg * j / (ND - 1)
 *   phi_d   = 90 deg * k / (NP - 1)      (isotropic and reciprocal BRDFs repeat over
 *                                         phi_d -> -phi_d and phi_d -> phi_d + 180, so
 *                                         [0, 90] holds everything), phi_h = 0.
 * Values are display RGB (bf_channels_to_rgb), NaN where a direction is below the
 * horizon or nothing was measured. */
#ifndef BRDFIT_COMPARE_VIEWER_TABLE_H
#define BRDFIT_COMPARE_VIEWER_TABLE_H

#include <cjson/cJSON.h>
#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"

enum { VIEWER_NH = 48, VIEWER_ND = 24, VIEWER_NP = 12 };
#define VIEWER_NODES ((size_t)VIEWER_NH * VIEWER_ND * VIEWER_NP)

/* Node (i, j, k)'s half/difference angles in radians. */
void viewer_node_angles(int i, int j, int k, double *theta_h, double *theta_d, double *phi_d);

/* 3 * VIEWER_NODES values, channel-major ([c][k][j][i], i fastest). */
bf_status viewer_table_model(const bf_model *m, const double *x, double *v, bf_error *err);
/* From samples addressed by MERL cells: at each node, interpolated between the centres of
 * the cells around it that have a value. */
bf_status viewer_table_merl(const bf_samples *merl, double *v, bf_error *err);

/* Values as a JSON object {"lo": [3], "step": [3], "data": "data:...;base64,..."}: per
 * channel, 16-bit codes (0 no value, 1 zero or below, else exp(lo + (code - 2) * step)),
 * differenced along runs of `run` values, high bytes then low bytes, deflated (zlib).
 * channels x count values, channel-major. NULL when out of memory (err set). */
cJSON *viewer_encode(const double *v, int channels, size_t count, size_t run, bf_error *err);
/* The same for plain 16-bit integers (angles in hundredths of a degree), columns of
 * `count`, differenced along each column: {"data": ...}. */
cJSON *viewer_encode_u16(const uint16_t *codes, int columns, size_t count, bf_error *err);

#endif
