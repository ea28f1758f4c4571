/* Axis ranges from the data and their ticks (plot_extent, plot_pad, plot_make_ticks):
 * numbers only, no Cairo. The decisions on ranges and ticks are plot.h's. Labels are
 * markup: a negative number starts with the minus sign (U+2212), large and small values
 * read m x 10^{e}, and an axis's labels share one notation. */
#include "plot/plot.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int plot_extent(size_t n, const double *v, int log, double *lo, double *hi)
{
    double a = INFINITY, b = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(v[i]) || (log && !(v[i] > 0.0)))
            continue;
        a = fmin(a, v[i]);
        b = fmax(b, v[i]);
    }
    if (!(a <= b))
        return 0;
    *lo = a;
    *hi = b;
    return 1;
}

void plot_pad(double lo, double hi, int have, int log, double *out_lo, double *out_hi)
{
    if (!have) {
        lo = log ? 0.1 : 0.0;
        hi = log ? 10.0 : 1.0;
    }
    double a = log ? log10(lo) : lo, b = log ? log10(hi) : hi;
    double mag = fmax(fabs(a), fabs(b));
    double min_span = log ? 0.1 : (mag > 0.0 ? 0.1 * mag : 1.0);
    if (b - a < min_span) {
        double mid = 0.5 * (a + b);
        a = mid - 0.5 * min_span;
        b = mid + 0.5 * min_span;
    }
    double pad = 0.05 * (b - a);
    a -= pad;
    b += pad;
    *out_lo = log ? pow(10.0, a) : a;
    *out_hi = log ? pow(10.0, b) : b;
}

/* ASCII '-' as the typographic minus sign. */
static void minus_sign(char *s, size_t size)
{
    if (s[0] != '-' || strlen(s) + 3 > size)
        return;
    memmove(s + 3, s + 1, strlen(s));
    memcpy(s, "\xe2\x88\x92", 3);
}

/* A tick value with `decimals` digits after the point, or as m x 10^{e} when
 * scientific (e: the exponent shared by the axis). */
static void fmt_tick(double v, int decimals, int sci, int e, char *out, size_t size)
{
    if (sci) {
        double m = v / pow(10.0, e);
        if (fabs(m) < 1e-9)
            snprintf(out, size, "0");
        else {
            char mb[32];
            snprintf(mb, sizeof mb, "%.*f", decimals, m);
            minus_sign(mb, sizeof mb);
            snprintf(out, size,
                     "%s\xc3\x97"
                     "10^{%d}",
                     mb, e);
        }
    } else {
        snprintf(out, size, "%.*f", decimals, fabs(v) < 1e-12 ? 0.0 : v);
    }
    if (out[0] == '-') {
        char tmp[PLOT_LABEL_LEN];
        snprintf(tmp, sizeof tmp, "%s", out);
        minus_sign(tmp, sizeof tmp);
        snprintf(out, size, "%s", tmp);
    }
    /* "m x 10^{e}" exponents keep the ASCII '-'; plot_text_run shows it as a minus. */
}

/* Labels for ticks[0..n) at a common step: fixed decimals, or scientific with the
 * exponent of the largest magnitude when values are very large or very small. */
static void label_linear(plot_ticks *t, double step)
{
    double mag = 0.0;
    for (int i = 0; i < t->n; i++)
        mag = fmax(mag, fabs(t->value[i]));
    int e = mag > 0.0 ? (int)floor(log10(mag) + 1e-9) : 0;
    int sci = mag > 0.0 && (e >= 5 || e <= -4);
    double s = sci ? step / pow(10.0, e) : step;
    int decimals = s >= 1.0 - 1e-9 ? 0 : (int)ceil(-log10(s) - 1e-9);
    if (decimals > 12)
        decimals = 12;
    for (int i = 0; i < t->n; i++)
        fmt_tick(t->value[i], decimals, sci, e, t->label[i], PLOT_LABEL_LEN);
}

/* Shortest label that reads back as v (to 1e-9): m x 10^{e} when sci, else plain. */
static void label_as(double v, int sci, char *out, size_t size)
{
    double a = fabs(v);
    if (a > 0.0 && sci) {
        int e = (int)floor(log10(a) + 1e-9);
        double m = v / pow(10.0, e);
        char mb[32];
        int d = 0;
        while (d < 6 && fabs(strtod((snprintf(mb, sizeof mb, "%.*f", d, m), mb), NULL) - m) > 1e-9 * fabs(m))
            d++;
        minus_sign(mb, sizeof mb);
        if (!strcmp(mb, "1"))
            snprintf(out, size, "10^{%d}", e);
        else
            snprintf(out, size,
                     "%s\xc3\x97"
                     "10^{%d}",
                     mb, e);
        return;
    }
    int d = 0;
    while (d < 12 && fabs(strtod((snprintf(out, size, "%.*f", d, v), out), NULL) - v) > 1e-9 * fmax(a, 1e-300))
        d++;
    minus_sign(out, size);
}

/* As label_as, scientific outside [1e-3, 1e5). */
static void label_value(double v, char *out, size_t size)
{
    double a = fabs(v);
    label_as(v, a > 0.0 && (a < 1e-3 || a >= 1e5), out, size);
}

static void linear_ticks(double lo, double hi, int target, int integer, double step, plot_ticks *t)
{
    if (!(step > 0.0)) {
        /* The 1-2-5 step whose tick count comes nearest the target (ties: fewer). */
        double raw = (hi - lo) / (target > 1 ? target : 1), e = floor(log10(raw));
        int best = -1;
        for (int j = 2; j >= -1; j--)
            for (int k = 2; k >= 0; k--) {
                static const double m[3] = {1.0, 2.0, 5.0};
                double c = m[k] * pow(10.0, e + j);
                int count = (int)(floor(hi / c + 1e-9) - ceil(lo / c - 1e-9)) + 1;
                if (best < 0 || abs(count - target) < best) {
                    best = abs(count - target);
                    step = c;
                }
            }
    }
    if (integer && step < 1.0)
        step = 1.0;
    t->n = 0;
    double first = ceil(lo / step - 1e-9);
    for (double k = first; t->n < PLOT_MAX_TICKS; k += 1.0) {
        double v = k * step;
        if (v > hi + 1e-9 * step)
            break;
        t->value[t->n++] = fabs(v) < 1e-12 * step ? 0.0 : v;
    }
    label_linear(t, step);
}

/* The labelled 1-2-5 values in [lo, hi] on a log axis: 1 when there are 3 to most. */
static int log_125(double lo, double hi, int most, plot_ticks *t)
{
    static const double m125[3] = {1.0, 2.0, 5.0};
    memset(t, 0, sizeof *t);
    int d0 = (int)floor(log10(lo)), d1 = (int)floor(log10(hi));
    for (int k = d0; k <= d1; k++)
        for (int j = 0; j < 3; j++) {
            double v = m125[j] * pow(10.0, k);
            if (v >= lo * (1 - 1e-12) && v <= hi * (1 + 1e-12) && t->n < PLOT_MAX_TICKS)
                t->value[t->n++] = v;
        }
    if (t->n < 3 || t->n > most)
        return 0;
    /* One notation for the whole axis: 10^{-4} beside 0.001 reads as a mistake. */
    int sci = t->value[0] < 1e-3 || t->value[t->n - 1] >= 1e5;
    for (int i = 0; i < t->n; i++)
        label_as(t->value[i], sci, t->label[i], PLOT_LABEL_LEN);
    /* Minor ticks at the other whole multiples (3, 4, 6 ... x 10^k). */
    for (int k = d0; k <= d1; k++)
        for (int m = 3; m <= 9 && t->nminor < 4 * PLOT_MAX_TICKS; m++) {
            double v = m * pow(10.0, k);
            if (m != 5 && v >= lo && v <= hi)
                t->minor[t->nminor++] = v;
        }
    return 1;
}

void plot_make_ticks(double lo, double hi, int log, int target, int integer, double step, plot_ticks *t)
{
    memset(t, 0, sizeof *t);
    if (target < 2)
        target = 2;
    if (!log) {
        linear_ticks(lo, hi, target, integer, step, t);
        return;
    }
    double a = log10(lo), b = log10(hi);
    int d0 = (int)ceil(a - 1e-9), d1 = (int)floor(b + 1e-9), ndec = d1 - d0 + 1;
    /* Under three decades two or three decade ticks say too little: the labelled 1-2-5
     * values instead, when they are not too many. */
    if (ndec >= 2 && b - a < 3.0 && log_125(lo, hi, target + 3, t))
        return;
    memset(t, 0, sizeof *t);
    if (ndec >= 2) {
        /* Whole decades, every stride-th (a 1-2-5 stride) when there are many. */
        int stride = 1;
        while (ndec / stride + 1 > target + 1)
            stride = stride == 1 ? 2 : stride == 2 ? 5 : stride * 2;
        int start = (int)ceil((double)d0 / stride) * stride;
        for (int k = start; k <= d1 && t->n < PLOT_MAX_TICKS; k += stride) {
            t->value[t->n] = pow(10.0, k);
            snprintf(t->label[t->n], PLOT_LABEL_LEN, "10^{%d}", k);
            t->n++;
        }
        /* Minor ticks at 2..9 x 10^k when each decade has a tick and there is room. */
        if (stride == 1 && ndec <= 8)
            for (int k = d0 - 1; k <= d1; k++)
                for (int m = 2; m <= 9 && t->nminor < 4 * PLOT_MAX_TICKS; m++) {
                    double v = m * pow(10.0, k);
                    if (v >= lo && v <= hi)
                        t->minor[t->nminor++] = v;
                }
        return;
    }
    /* Less than two decades: the 1-2-5 values inside, if there are enough of them. */
    if (log_125(lo, hi, PLOT_MAX_TICKS, t))
        return;
    /* A narrow range: linear 1-2-5 ticks of the values. */
    memset(t, 0, sizeof *t);
    linear_ticks(lo, hi, target < 4 ? target : 4, integer, step, t);
    if (t->n < 2) { /* never fewer than the two ends */
        t->n = 2;
        t->value[0] = lo;
        t->value[1] = hi;
        label_value(lo, t->label[0], PLOT_LABEL_LEN);
        label_value(hi, t->label[1], PLOT_LABEL_LEN);
    }
}
