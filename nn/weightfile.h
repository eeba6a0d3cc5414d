/* weightfile.h: the flat CLIP weight file (format in weights/README.md).
 *
 * Little-endian: a header (magic "WSKCLIP\0", version, the architecture),
 * a tensor table (name, dtype f32 or f16, shape, offset), 64-byte aligned
 * data, and a zlib crc32 of everything before it as the last 4 bytes. The
 * file is mmap'ed; f16 tensors are widened to f32 once, at open. A file that
 * is truncated, has a bad magic, an unknown version, a malformed table or a
 * bad checksum is refused with one line naming the file and the problem. */
#ifndef NN_WEIGHTFILE_H
#define NN_WEIGHTFILE_H
#include <stdint.h>
#include "base/status.h"

enum { WF_F32 = 0, WF_F16 = 1 };

typedef struct {
    int width, layers, heads, patch, resolution, output_dim;
} wf_arch;

typedef struct {
    char name[64];
    int dtype;         /* as stored in the file */
    int ndim;
    int64_t shape[4];
    int64_t numel;
    const float *data; /* f32 values: in the mapping, or widened copies */
} wf_tensor;

typedef struct wf_file wf_file;

int wf_open(wf_file **f, const char *path, ws_status *st);
void wf_close(wf_file *f);
const wf_arch *wf_architecture(const wf_file *f);
const char *wf_path(const wf_file *f);
/* The tensor `name` with exactly the given shape (ndim entries); on a
 * missing or mis-shaped tensor: WS_EINPUT, "PATH: tensor NAME missing" or
 * "PATH: tensor NAME has shape [a, b], expected [c, d]". */
int wf_get(const wf_file *f, const char *name, int ndim, const int64_t *shape,
           const float **data, ws_status *st);
int wf_count(const wf_file *f);
const wf_tensor *wf_tensor_at(const wf_file *f, int i);

#endif
