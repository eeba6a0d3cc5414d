/* splits.h: a scene's three splits (scene.h), in the order of nerfstudio's
 * split lists and of every per-split array. */
#ifndef WS_SPLITS_H
#define WS_SPLITS_H

enum { WS_TRAIN = 0, WS_VAL = 1, WS_TEST = 2, WS_NSPLITS = 3 };

/* "train", "val", "test" */
extern const char *const ws_split_names[WS_NSPLITS];

#endif
