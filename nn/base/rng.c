/* rng.c: xoshiro256** with splitmix64 seeding (see rng.h). */
#include <math.h>
#include "rng.h"

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

void ws_rng_seed(ws_rng *rng, uint64_t seed) {
    uint64_t z = seed;
    for (int i = 0; i < 4; i++) {
        z += 0x9e3779b97f4a7c15ULL;
        uint64_t x = z;
        x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
        x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
        rng->s[i] = x ^ (x >> 31);
    }
}

uint64_t ws_rng_next(ws_rng *rng) {
    uint64_t *s = rng->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double ws_rng_uniform(ws_rng *rng) { return (ws_rng_next(rng) >> 11) * 0x1.0p-53; }

uint64_t ws_rng_below(ws_rng *rng, uint64_t n) {
    uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    uint64_t x;
    do x = ws_rng_next(rng);
    while (x >= limit);
    return x % n;
}

double ws_rng_normal(ws_rng *rng) {
    double u1 = 1.0 - ws_rng_uniform(rng); /* in (0, 1]: log never sees 0 */
    double u2 = ws_rng_uniform(rng);
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}
