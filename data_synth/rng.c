/* The generator: xoshiro256** seeded by splitmix64, and the uniform, normal and
 * Poisson draws the patterns and noise models take from it. */
#include "synth.h"

#include <math.h>

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += UINT64_C(0x9e3779b97f4a7c15));
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

static inline uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

/* splitmix64 never yields four zero words in a row, so the state is never all zero
 * (xoshiro's one forbidden state). */
void bf_synth_rng_seed(bf_synth_rng *r, uint64_t seed)
{
    for (int i = 0; i < 4; i++)
        r->s[i] = splitmix64(&seed);
    r->spare = 0.0;
    r->has_spare = 0;
}

uint64_t bf_synth_next(bf_synth_rng *r)
{
    uint64_t *s = r->s;
    const uint64_t result = rotl(s[1] * 5, 7) * 9;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

void bf_synth_rng_jump(bf_synth_rng *r)
{
    static const uint64_t jump[4] = {UINT64_C(0x180ec6d33cfd0aba), UINT64_C(0xd5a61266f0c9392c),
                                     UINT64_C(0xa9582618e03fc9aa), UINT64_C(0x39abdc4529b1661c)};
    uint64_t t[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; i++)
        for (int b = 0; b < 64; b++) {
            if (jump[i] & (UINT64_C(1) << b))
                for (int w = 0; w < 4; w++)
                    t[w] ^= r->s[w];
            bf_synth_next(r);
        }
    for (int w = 0; w < 4; w++)
        r->s[w] = t[w];
    r->has_spare = 0;
}

double bf_synth_uniform(bf_synth_rng *r)
{
    return (double)(bf_synth_next(r) >> 11) * 0x1.0p-53;
}

uint64_t bf_synth_below(bf_synth_rng *r, uint64_t n)
{
    /* Reject the lowest 2^64 mod n values so that every residue is equally likely. */
    const uint64_t threshold = (0 - n) % n;
    for (;;) {
        uint64_t x = bf_synth_next(r);
        if (x >= threshold)
            return x % n;
    }
}

double bf_synth_normal(bf_synth_rng *r)
{
    if (r->has_spare) {
        r->has_spare = 0;
        return r->spare;
    }
    double u, v, s;
    do {
        u = 2.0 * bf_synth_uniform(r) - 1.0;
        v = 2.0 * bf_synth_uniform(r) - 1.0;
        s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = sqrt(-2.0 * log(s) / s);
    r->spare = v * f;
    r->has_spare = 1;
    return u * f;
}

/* Knuth: the number of uniforms whose running product stays above e^-mean. Its cost
 * grows with the mean, hence only below 10. */
static double poisson_small(bf_synth_rng *r, double mean)
{
    const double limit = exp(-mean);
    double p = bf_synth_uniform(r), k = 0.0;
    while (p > limit) {
        p *= bf_synth_uniform(r);
        k += 1.0;
    }
    return k;
}

/* PTRS: W. Hoermann, "The transformed rejection method for generating Poisson random
 * variables", Insurance: Mathematics and Economics 12 (1993) 39-45; exact for any mean
 * >= 10, about 1.2 uniform pairs per draw. k is a double so that the tails (us -> 0)
 * never overflow an integer. */
static double poisson_ptrs(bf_synth_rng *r, double mean)
{
    const double slam = sqrt(mean), loglam = log(mean);
    const double b = 0.931 + 2.53 * slam;
    const double a = -0.059 + 0.02483 * b;
    const double inv_alpha = 1.1239 + 1.1328 / (b - 3.4);
    const double vr = 0.9277 - 3.6224 / (b - 2.0);
    for (;;) {
        const double u = bf_synth_uniform(r) - 0.5;
        const double v = bf_synth_uniform(r);
        const double us = 0.5 - fabs(u);
        if (us == 0.0)
            continue; /* u = -0.5: the hat is infinite there */
        const double k = floor((2.0 * a / us + b) * u + mean + 0.43);
        if (us >= 0.07 && v <= vr)
            return k;
        if (k < 0.0 || (us < 0.013 && v > us))
            continue;
        if (log(v) + log(inv_alpha) - log(a / (us * us) + b) <= -mean + k * loglam - lgamma(k + 1.0))
            return k;
    }
}

double bf_synth_poisson(bf_synth_rng *r, double mean)
{
    if (!(mean > 0.0))
        return 0.0;
    if (mean < 10.0)
        return poisson_small(r, mean);
    if (mean <= 1e9)
        return poisson_ptrs(r, mean);
    /* PTRS's acceptance test subtracts terms of size mean log(mean); past 1e9 their
     * rounding starts to matter, while the normal approximation is already exact to
     * far better than any noise level a fit could resolve. */
    const double k = floor(mean + sqrt(mean) * bf_synth_normal(r) + 0.5);
    return k > 0.0 ? k : 0.0;
}
