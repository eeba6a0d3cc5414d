/* rng.h: the deterministic random number generator of wiresketch.
 *
 * xoshiro256** seeded through splitmix64: the same seed gives the same
 * stream on every machine and compiler. Every random choice of a run (curve
 * initialisation, view order, augmentations) draws from a ws_rng, so a seed
 * fixes a run; the state is plain data, so checkpoints save and restore it. */
#ifndef WS_RNG_H
#define WS_RNG_H
#include <stdint.h>

typedef struct {
    uint64_t s[4];
} ws_rng;

void ws_rng_seed(ws_rng *rng, uint64_t seed);
uint64_t ws_rng_next(ws_rng *rng);
/* Uniform in [0, 1) with 53 random bits. */
double ws_rng_uniform(ws_rng *rng);
/* Uniform integer in [0, n), n > 0, without modulo bias. */
uint64_t ws_rng_below(ws_rng *rng, uint64_t n);
/* Standard normal (Box-Muller, one value per call). */
double ws_rng_normal(ws_rng *rng);

#endif
