/* timing.h: where the time of a training step goes.
 *
 * A ws_step_timing is optional everywhere: the step and the loss take a
 * pointer that is NULL in an ordinary fit, and then read no clock at all.
 * When it is set (the benchmarks), each part adds its wall time to its
 * slot; the caller times the whole step into WS_TIME_TOTAL, and "other" is
 * what the named parts leave of it. */
#ifndef WS_TIMING_H
#define WS_TIMING_H
#include <time.h>

enum {
    WS_TIME_SPLAT,         /* splatting forward and backward */
    WS_TIME_AUGMENT,       /* augmentation of strokes and photos, forward and backward */
    WS_TIME_CLIP_FORWARD,  /* CLIP forward of the stroke images (with tape) */
    WS_TIME_CLIP_PHOTO,    /* CLIP forward of photos whose features are not cached */
    WS_TIME_CLIP_BACKWARD, /* CLIP backward of the stroke images */
    WS_TIME_OPTIMISER,     /* Adam */
    WS_TIME_TOTAL,         /* the whole step */
    WS_TIME_PARTS
};

typedef struct {
    double seconds[WS_TIME_PARTS];
} ws_step_timing;

/* "splat", "augment", "clip_forward", ...: stable names (JSON keys). */
extern const char *const ws_time_names[WS_TIME_PARTS];

/* Monotonic wall time in seconds. */
static inline double ws_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* t0 = ws_time_start(t); ...work...; ws_time_add(t, WS_TIME_SPLAT, t0); */
static inline double ws_time_start(const ws_step_timing *t) { return t ? ws_seconds() : 0.0; }
static inline void ws_time_add(ws_step_timing *t, int part, double t0) {
    if (t) t->seconds[part] += ws_seconds() - t0;
}

#endif
