/* Internal: the CIE colour-matching functions and illuminant spectra (cie_tables.c
 * says where each number comes from). */
#ifndef BF_COLOR_CIE_TABLES_H
#define BF_COLOR_CIE_TABLES_H

#define BF_CIE_ROWS 95 /* 360, 365, ..., 830 nm */

typedef struct bf_cie_row {
    double nm;
    double xbar, ybar, zbar; /* CIE 1931 2 degree observer */
    double d65, d50;         /* relative spectral power, 100 at 560 nm */
} bf_cie_row;

extern const bf_cie_row bf_cie_table[BF_CIE_ROWS];

/* CIE standard illuminant A at nm (relative, 100 at 560 nm), from its definition. */
double bf_cie_illuminant_a(double nm);

#endif
