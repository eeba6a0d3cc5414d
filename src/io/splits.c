/* splits.c: the splits' names (see splits.h). */
#include "io/splits.h"

const char *const ws_split_names[WS_NSPLITS] = {"train", "val", "test"};
