/* Limits on sizes that files declare, checked before any arithmetic or allocation:
 * hostile or broken files must get a one-line error, not an overflow or an attempt to
 * allocate terabytes. */
#ifndef BRDFIT_LIMITS_H
#define BRDFIT_LIMITS_H

/* Channels of a sample set or a model (wavelengths of a spectral measurement, values of
 * an ALTA row, "channels" of a parameter file). Spectral data at 1 nm from 300 to
 * 2500 nm has 2,201; this leaves room and keeps a model's parameter vector (at most 64
 * parameters x channels) and every count derived from it far inside int. */
#define BF_MAX_CHANNELS 10000

/* Columns of a CSV table (channels plus angles, weights and ignored columns). */
#define BF_CSV_MAX_COLUMNS 65536

#endif
