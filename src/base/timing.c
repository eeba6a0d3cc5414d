/* timing.c: the names of the parts of a step (timing.h). */
#include "base/timing.h"

const char *const ws_time_names[WS_TIME_PARTS] = {
    "splat", "augment", "clip_forward", "clip_photo", "clip_backward", "optimiser", "total"};
