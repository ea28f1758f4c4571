/* Internal: the library's one random generator (its clock: brdfit/clock.h).
 *
 * splitmix64 (Steele, Lea and Flood 2014): one 64-bit state, every seed (0 included)
 * gives a full-period, well-mixed stream; subsampling, multistart, folds and the
 * train/test split each seed their own stream from the user's --seed, so a result
 * depends on the seed alone, never on threads or timing. */
#ifndef BF_RNG_H
#define BF_RNG_H

#include <stdint.h>

static inline uint64_t bf_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1) with 53 random bits. */
static inline double bf_uniform01(uint64_t *state)
{
    return (double)(bf_splitmix64(state) >> 11) * 0x1.0p-53;
}

#endif
