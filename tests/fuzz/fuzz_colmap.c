/* fuzz_colmap.c: the COLMAP model reader (ws_colmap_read), text and
 * binary, that scene loading uses on a capture's sparse/0.
 * An input's first byte picks the file it replaces (its value mod 3:
 * cameras, images, points3D) and the format (bit 2: text); the rest is
 * that file, beside the two others of a small valid model.
 * Seeds: tests/fuzz/corpus/colmap (each file of a two-camera model with
 * OPENCV and OPENCV_FISHEYE lenses, both formats). */
#include <math.h>
#include "fuzz_input.h"
#include "io/colmap.h"

/* The valid model written beside each fuzzed file. */
static void valid_model(ws_colmap_model *m, ws_colmap_camera cams[2], ws_colmap_image ims[2],
                        double points[6]) {
    static const double opencv[8] = {100, 101, 64, 48, -0.1, 0.01, 0.001, -0.001};
    static const double fisheye[8] = {60, 60, 64, 48, 0.05, -0.01, 0.002, 0};
    ws_status st = {0};
    cams[0].id = 1;
    cams[1].id = 2;
    if (ws_lens_from_colmap(&cams[0].lens, "OPENCV", opencv, 8, 128, 96, "c", &st) ||
        ws_lens_from_colmap(&cams[1].lens, "OPENCV_FISHEYE", fisheye, 8, 128, 96, "c", &st))
        abort();
    for (int k = 0; k < 2; k++) {
        ims[k] = (ws_colmap_image){.id = k + 1, .camera_id = k + 1, .q = {1, 0, 0, 0}, .t = {0, 0, 4}};
        snprintf(ims[k].name, sizeof ims[k].name, "img%d.jpg", k);
    }
    for (int i = 0; i < 6; i++) points[i] = 0.1 * i;
    *m = (ws_colmap_model){2, 2, 2, cams, ims, points};
}

static char folders[6][4096];

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    fuzz_setup("colmap");
    ws_colmap_model m;
    ws_colmap_camera cams[2];
    ws_colmap_image ims[2];
    double points[6];
    valid_model(&m, cams, ims, points);
    for (int k = 0; k < 6; k++) {
        ws_status st = {0};
        snprintf(folders[k], sizeof folders[k], "%s/%d", fuzz_dir, k);
        if (mkdir(folders[k], 0700) || ws_colmap_write(&m, folders[k], k < 3, &st)) abort();
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    static const char *const names[2][3] = {{"cameras.bin", "images.bin", "points3D.bin"},
                                            {"cameras.txt", "images.txt", "points3D.txt"}};
    const int file = data[0] % 3, text = (data[0] >> 2) & 1, k = 3 * text + file;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", folders[k], names[text][file]);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data + 1, 1, size - 1, f) != size - 1 || fclose(f) != 0) abort();
    ws_colmap_model m;
    ws_status st = {0};
    if (ws_colmap_read(&m, folders[k], &st)) {
        fuzz_expect_refusal(&st, WS_EINPUT, folders[k]);
        return 0;
    }
    if (m.nimages < 1) abort();
    for (int i = 0; i < m.nimages; i++)
        if (!ws_colmap_camera_of(&m, &m.images[i])) abort();
    for (int i = 0; i < 3 * m.npoints; i++)
        if (!isfinite(m.points[i])) abort();
    ws_colmap_free(&m);
    return 0;
}
