/* rng.h: the deterministic random number generator of wiresketch.
 *
 * xoshiro256** seeded through splitmix64: the same seed gives the same
 * stream on every machine and compiler. Every random choice of a run (curve
 * initialisation, view order, augmentations) draws from a ws_rng, so a seed
 * fixes a run; the state is plain data, so checkpoints save and restore it.
 *
 * nn/base holds the project's base types, shared by both layers (nn/ and
 * src/), so its names keep the project's ws_ prefix; the rest of nn/ uses
 * nn_ (and clip_, wf_ for the CLIP tower and its weight file). */
#ifndef NN_BASE_RNG_H
#define NN_BASE_RNG_H
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
