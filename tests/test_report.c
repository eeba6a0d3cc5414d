/* test_report.c: the outputs people look at: GIFs (read back with giflib),
 * the turntable cameras and renders, and report.html (sections, escaping,
 * no network references, the curve JSON). */
#include <cJSON.h>
#include <gif_lib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "base/paths.h"
#include "check.h"
#include "test_util.h"
#include "io/gif.h"
#include "io/report.h"
#include "io/turntable.h"

static const char *dir;

static const char *in_dir(const char *name) {
    static char path[4][256];
    static int slot;
    slot = (slot + 1) % 4;
    snprintf(path[slot], sizeof path[slot], "%s/%s", dir, name);
    return path[slot];
}

static int count(const char *s, const char *what) {
    int n = 0;
    for (const char *p = s; (p = strstr(p, what)); p += strlen(what)) n++;
    return n;
}

/* No file and no temporary file beside it. */
static int left_nothing(const char *path) {
    char dir[WS_PATH_MAX];
    const char *slash = strrchr(path, '/');
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    return access(path, F_OK) != 0 && temporaries_in(dir, slash + 1) == 0;
}

static GifFileType *read_gif(const char *path) {
    int err = 0;
    GifFileType *g = DGifOpenFileName(path, &err);
    CHECK(g != NULL, "%s: DGifOpenFileName: %s", path, GifErrorString(err));
    if (!g) return NULL;
    int ok = DGifSlurp(g) == GIF_OK;
    CHECK(ok, "%s: DGifSlurp failed: %d", path, g->Error);
    if (!ok) {
        DGifCloseFile(g, &err);
        return NULL;
    }
    return g;
}

/* The NETSCAPE2.0 block with loop count 0 among the first frame's
 * extension blocks. */
static int loops_forever(const GifFileType *g) {
    const SavedImage *im = &g->SavedImages[0];
    for (int k = 0; k + 1 < im->ExtensionBlockCount; k++) {
        const ExtensionBlock *e = &im->ExtensionBlocks[k], *sub = &im->ExtensionBlocks[k + 1];
        if (e->Function == APPLICATION_EXT_FUNC_CODE && e->ByteCount == 11 &&
            !memcmp(e->Bytes, "NETSCAPE2.0", 11) && sub->ByteCount == 3 && sub->Bytes[0] == 1 &&
            sub->Bytes[1] == 0 && sub->Bytes[2] == 0)
            return 1;
    }
    return 0;
}

static void test_gif_gray(void) {
    enum { W = 20, H = 13, N = 3 };
    static unsigned char frames[N][H * W];
    for (int f = 0; f < N; f++)
        for (int k = 0; k < H * W; k++) frames[f][k] = (unsigned char)((k * 7 + f * 85) % 256);
    const char *path = in_dir("gray.gif");
    ws_status st;
    ws_gif gif;
    int rc = ws_gif_open(&gif, path, W, H, 1, 7, &st);
    for (int f = 0; f < N && !rc; f++) rc = ws_gif_add_frame(&gif, frames[f], &st);
    rc = rc ? rc : ws_gif_commit(&gif, &st);
    CHECK(rc == WS_OK, "gray GIF: %s", st.msg);
    GifFileType *g = read_gif(path);
    if (!g) return;
    CHECK(g->ImageCount == N, "frames %d", g->ImageCount);
    CHECK(g->SWidth == W && g->SHeight == H, "size %d x %d", g->SWidth, g->SHeight);
    CHECK(loops_forever(g), "no NETSCAPE2.0 loop-forever extension");
    int bad = 0, delays_ok = 1;
    for (int f = 0; f < g->ImageCount && f < N; f++) {
        const SavedImage *im = &g->SavedImages[f];
        const ColorMapObject *map = im->ImageDesc.ColorMap ? im->ImageDesc.ColorMap : g->SColorMap;
        for (int k = 0; k < H * W; k++) {
            const GifColorType *c = &map->Colors[im->RasterBits[k]];
            bad += c->Red != frames[f][k] || c->Green != frames[f][k] || c->Blue != frames[f][k];
        }
        GraphicsControlBlock gcb;
        delays_ok &= DGifSavedExtensionToGCB(g, f, &gcb) == GIF_OK && gcb.DelayTime == 7;
    }
    CHECK(bad == 0, "%d gray pixels did not round-trip", bad);
    CHECK(delays_ok, "frame delay is not 7/100 s");
    DGifCloseFile(g, NULL);
}

/* RGB frames go through the 6 x 7 x 6 cube: the cube's corners exactly,
 * anything else within half a level. */
static void test_gif_rgb(void) {
    enum { W = 16, H = 16 };
    static unsigned char px[H * W * 3];
    ws_rng rng;
    ws_rng_seed(&rng, 3);
    for (int k = 0; k < H * W * 3; k++) px[k] = (unsigned char)ws_rng_below(&rng, 256);
    static const unsigned char corners[4][3] = {{255, 0, 0}, {0, 255, 0}, {255, 255, 255}, {0, 0, 0}};
    memcpy(px, corners, sizeof corners);
    const char *path = in_dir("rgb.gif");
    ws_status st;
    ws_gif gif;
    int rc = ws_gif_open(&gif, path, W, H, 3, 10, &st);
    rc = rc ? rc : ws_gif_add_frame(&gif, px, &st);
    rc = rc ? rc : ws_gif_commit(&gif, &st);
    CHECK(rc == WS_OK, "RGB GIF: %s", st.msg);
    GifFileType *g = read_gif(path);
    if (!g) return;
    const SavedImage *im = &g->SavedImages[0];
    const ColorMapObject *map = im->ImageDesc.ColorMap ? im->ImageDesc.ColorMap : g->SColorMap;
    int exact = 1;
    double worst[3] = {0, 0, 0};
    for (int k = 0; k < H * W; k++) {
        const GifColorType *c = &map->Colors[im->RasterBits[k]];
        int got[3] = {c->Red, c->Green, c->Blue};
        for (int ch = 0; ch < 3; ch++) {
            worst[ch] = fmax(worst[ch], abs(got[ch] - px[3 * k + ch]));
            if (k < 4) exact &= got[ch] == px[3 * k + ch];
        }
    }
    CHECK(exact, "pure colours did not round-trip exactly");
    /* Half a level: 255/10 for 6 levels, 255/12 for 7, plus rounding. */
    CHECK(worst[0] <= 26 && worst[1] <= 22 && worst[2] <= 26, "RGB error %g %g %g", worst[0],
          worst[1], worst[2]);
    DGifCloseFile(g, NULL);
}

static void test_gif_failures(void) {
    ws_status st;
    ws_gif gif;
    const char *path = in_dir("missing/a.gif");
    int rc = ws_gif_open(&gif, path, 8, 8, 1, 5, &st);
    CHECK(rc == WS_EIO && strstr(st.msg, path) && strstr(st.msg, "cannot write"),
          "GIF into a missing directory: %d %s", rc, st.msg);
    ws_gif_abort(&gif); /* harmless after a failure */
    CHECK(left_nothing(path), "GIF left a file behind");

    path = in_dir("empty.gif");
    rc = ws_gif_open(&gif, path, 8, 8, 1, 5, &st);
    rc = rc ? rc : ws_gif_commit(&gif, &st);
    CHECK(rc == WS_EINTERNAL && !strcmp(st.msg + strlen(path), ": GIF has no frames"),
          "empty GIF: %d %s", rc, st.msg);
    CHECK(left_nothing(path), "empty GIF left a file behind");

    path = in_dir("aborted.gif");
    static unsigned char px[64];
    rc = ws_gif_open(&gif, path, 8, 8, 1, 5, &st);
    rc = rc ? rc : ws_gif_add_frame(&gif, px, &st);
    CHECK(rc == WS_OK, "aborted GIF: %s", st.msg);
    ws_gif_abort(&gif);
    ws_gif_abort(&gif);
    CHECK(left_nothing(path), "aborted GIF left a file behind");

    rc = ws_gif_open(&gif, in_dir("bad.gif"), 8, 8, 2, 5, &st);
    CHECK(rc == WS_EINTERNAL && strstr(st.msg, "1 or 3 channels, not 2"), "2 channels: %s", st.msg);
}

static double norm3(const double a[3]) {
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/* Every turntable camera looks at the centre from the same distance, with
 * the world's +z up in the image; the elevation goes -10 -> +40 -> -10. */
static void test_turntable_cameras(void) {
    const double center[3] = {1.5, -2.0, 0.7}, dist = 4.0, angle = 0.69;
    enum { N = 24, SIZE = 64 };
    ws_status st;
    int centred = 1, at_distance = 1, upright = 1, init_ok = 1, rigid = 1;
    double elev[N];
    for (int i = 0; i < N; i++) {
        ws_camera cam;
        if (ws_turntable_camera(&cam, center, dist, angle, SIZE, i, N, &st)) {
            init_ok = 0;
            break;
        }
        /* A rotation: orthonormal columns, right-handed (x cross y = z). */
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double dot = 0;
                for (int k = 0; k < 3; k++) dot += cam.c2w[k][a] * cam.c2w[k][b];
                rigid &= fabs(dot - (a == b)) < 1e-12;
            }
        const double(*m)[4] = cam.c2w;
        rigid &= fabs(m[0][0] * m[1][1] - m[1][0] * m[0][1] - m[2][2]) < 1e-12;
        double c[3], pos[3], rel[3], above[3] = {center[0], center[1], center[2] + 0.3}, ca[3];
        ws_camera_to_cam(&cam, center, c);
        double d = -c[2], u = SIZE / 2.0 + cam.focal * c[0] / d, v = SIZE / 2.0 - cam.focal * c[1] / d;
        centred &= fabs(u - SIZE / 2.0) < 1e-9 && fabs(v - SIZE / 2.0) < 1e-9;
        ws_camera_position(&cam, pos);
        for (int k = 0; k < 3; k++) rel[k] = pos[k] - center[k];
        at_distance &= fabs(norm3(rel) - dist) < 1e-12 && fabs(d - dist) < 1e-12;
        elev[i] = asin(rel[2] / norm3(rel)) * 180 / M_PI;
        ws_camera_to_cam(&cam, above, ca);
        upright &= SIZE / 2.0 - cam.focal * ca[1] / -ca[2] < SIZE / 2.0 - 1;
    }
    CHECK(init_ok, "turntable camera: %s", st.msg);
    CHECK(rigid, "a camera rotation is not a right-handed rotation");
    CHECK(centred, "the centre does not project to the image centre");
    CHECK(at_distance, "a camera is not at the given distance");
    CHECK(upright, "world +z does not point up in the image");
    CHECK(fabs(elev[0] + 10) < 1e-9 && fabs(elev[N / 2] - 40) < 1e-9 && fabs(elev[N / 4] - 15) < 1e-9,
          "elevations %g %g %g", elev[0], elev[N / 4], elev[N / 2]);
    ws_camera first;
    ws_turntable_camera(&first, center, dist, angle, SIZE, 0, N, &st);
    double pos[3];
    ws_camera_position(&first, pos);
    CHECK(fabs(pos[0] - center[0]) < 1e-12 && pos[1] < center[1],
          "frame 0 is not in front (-y): %g %g", pos[0], pos[1]);

    int rc = ws_turntable_camera(&first, center, 0.0, angle, SIZE, 0, N, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, "turntable: camera distance 0 is not positive"),
          "zero distance: %s", st.msg);

    /* The distance: mean over the split's cameras. */
    ws_view views[2];
    ws_split split = {2, views};
    ws_turntable_camera(&views[0].cam, center, 3.0, angle, SIZE, 0, N, &st);
    ws_turntable_camera(&views[1].cam, center, 5.0, angle, SIZE, 7, N, &st);
    CHECK(check_close(ws_turntable_distance(&split, center), 4.0, 1e-12, 1),
          "mean distance %g", ws_turntable_distance(&split, center));
}

/* A curve through the centre draws black strokes there on white. */
static void test_turntable_render(void) {
    const double center[3] = {0, 0, 0};
    ws_status st;
    ws_curves c;
    if (ws_curves_alloc(&c, 1, &st)) {
        CHECK(0, "%s", st.msg);
        return;
    }
    c.thickness = 0.05;
    c.overlap = 0.6;
    for (int j = 0; j < 4; j++) {
        c.P[j * 3 + 0] = -0.5 + j / 3.0;
        c.P[j * 3 + 1] = c.P[j * 3 + 2] = 0;
    }
    enum { SIZE = 48, N = 4 };
    ws_sketch_renderer r;
    ws_camera cam;
    int rc = ws_sketch_renderer_init(&r, SIZE, SIZE, &st);
    rc = rc ? rc : ws_turntable_camera(&cam, center, 3.0, 0.69, SIZE, 0, N, &st);
    rc = rc ? rc : ws_sketch_render(&r, &c, &cam, &st);
    CHECK(rc == WS_OK, "render: %s", st.msg);
    if (rc == WS_OK)
        CHECK(r.gray[SIZE / 2 * SIZE + SIZE / 2] < 64 && r.gray[0] == 255 && r.gray[SIZE * SIZE - 1] == 255,
              "centre %d corners %d %d", r.gray[SIZE / 2 * SIZE + SIZE / 2], r.gray[0],
              r.gray[SIZE * SIZE - 1]);
    ws_sketch_renderer_free(&r);

    const char *path = in_dir("turntable.gif");
    rc = ws_turntable_gif(path, &c, center, 3.0, 0.69, SIZE, N, NULL, NULL, &st);
    CHECK(rc == WS_OK, "turntable GIF: %s", st.msg);
    GifFileType *g = read_gif(path);
    if (g) {
        GraphicsControlBlock gcb = {0};
        DGifSavedExtensionToGCB(g, 0, &gcb);
        CHECK(g->ImageCount == N && g->SWidth == SIZE && loops_forever(g) && gcb.DelayTime == 150,
              "turntable GIF: %d frames, width %d, delay %d", g->ImageCount, g->SWidth, gcb.DelayTime);
        const SavedImage *im = &g->SavedImages[N / 2];
        CHECK(g->SColorMap->Colors[im->RasterBits[SIZE / 2 * SIZE + SIZE / 2]].Red < 64,
              "the curve is not in the middle of frame %d", N / 2);
        DGifCloseFile(g, NULL);
    }
    ws_curves_free(&c);
}

/* The text between `open` and the next `close`, copied (NULL if absent). */
static char *between(const char *s, const char *open, const char *close) {
    const char *a = strstr(s, open);
    if (!a) return NULL;
    a += strlen(open);
    const char *b = strstr(a, close);
    if (!b) return NULL;
    char *out = malloc((size_t)(b - a) + 1);
    memcpy(out, a, (size_t)(b - a));
    out[b - a] = '\0';
    return out;
}

static void test_report(void) {
    ws_status st;
    ws_curves c;
    if (ws_curves_alloc(&c, 3, &st)) {
        CHECK(0, "%s", st.msg);
        return;
    }
    c.thickness = 0.02;
    c.overlap = 0.6;
    for (int k = 0; k < 36; k++) c.P[k] = sin(1.7 * k);
    c.P[WS_CURVE_FLOATS + 5] = NAN; /* curve 1 is left out */

    enum { NT = 400 };
    long tstep[NT], vstep[5];
    double tloss[NT], vloss[5];
    for (int k = 0; k < NT; k++) {
        tstep[k] = k;
        tloss[k] = 3.0 * exp(-k / 60.0) + 0.01;
    }
    tloss[17] = NAN;
    tloss[18] = INFINITY;
    for (int k = 0; k < 5; k++) {
        vstep[k] = 80 * k + 79;
        vloss[k] = tloss[vstep[k]];
    }
    ws_report_item settings[] = {{.key = "lr", .value = "0.005"}, {.key = "note<x>", .value = "a & b \"q\" 'z' <script>"}};
    ws_report_item metrics[] = {{"test loss", "0.25", "line loss, 0 perfect; good <= 0.15", "poor"},
                                {"steps", "400", "", NULL}};
    ws_report_view tests[] = {{"r_0", "test/r_0.png", "test/r_0 photo#1.png", 0.25, 200, {40, 20, 100}},
                              {"r<1>", "test/r_1.png", NULL, NAN, 200, {0, 0, 0}}};
    const long phase_step[] = {0, 100, 250};
    const char *const phase_label[] = {"1 of 4 levels", "2 of 4 levels", "4 of 4 levels"};
    const double cameras[] = {4, 0, 0, -1, 0, 0, 0, 4, 0, 0, -1, 0};
    ws_report_image images[] = {{"turntable", "turntable.gif"}};
    ws_report r = {.title = "Fit <rose> & co", .scene_path = "../scenes/a&b",
                   .settings = settings, .n_settings = 2, .metrics = metrics, .n_metrics = 2,
                   .warning = "gt.ply: the ground truth misses <part>", .phase_step = phase_step,
                   .phase_label = phase_label, .n_phases = 3, .phase_note = "the loss climbs where a phase begins",
                   .cameras = cameras, .n_cameras = 2,
                   .train_step = tstep, .train_loss = tloss, .n_train = NT, .val_step = vstep,
                   .val_loss = vloss, .n_val = 5, .tests = tests, .n_tests = 2, .images = images,
                   .n_images = 1, .wall_seconds = 125.25, .curves = &c};
    const char *path = in_dir("report.html");
    int rc = ws_report_write(path, &r, &st);
    CHECK(rc == WS_OK, "report: %s", st.msg);
    char *html = slurp(path, NULL);
    CHECK(html != NULL, "report.html not written");
    if (!html) return;

    static const char *sections[] = {"id=\"metrics\"", "id=\"loss\"", "id=\"test-views\"",
                                     "id=\"curves-3d\"", "id=\"images\"", "id=\"settings\"",
                                     "id=\"wall-time\"", "<canvas id=\"view3d\""};
    for (size_t k = 0; k < sizeof sections / sizeof *sections; k++)
        CHECK(strstr(html, sections[k]), "report lacks %s", sections[k]);
    CHECK(count(html, "<svg") == 1 && count(html, "</svg>") == 1, "svg not closed");
    static const char *pairs[][2] = {{"<section", "</section>"}, {"<table", "</table>"},
                                     {"<figure", "</figure>"}, {"<script", "</script>"},
                                     {"<html", "</html>"}, {"<body", "</body>"}};
    for (size_t k = 0; k < sizeof pairs / sizeof *pairs; k++)
        CHECK(count(html, pairs[k][0]) == count(html, pairs[k][1]), "%s: %d opened, %d closed",
              pairs[k][0], count(html, pairs[k][0]), count(html, pairs[k][1]));
    CHECK(!strstr(html, "http://") && !strstr(html, "https://") && !strstr(html, "//cdn"),
          "report references the network");
    CHECK(strstr(html, "<h1>Fit &lt;rose&gt; &amp; co</h1>") && !strstr(html, "<rose>"),
          "title not escaped");
    CHECK(strstr(html, "<th>note&lt;x&gt;</th><td>a &amp; b &quot;q&quot; &#39;z&#39; &lt;script&gt;</td>"),
          "setting not escaped");
    CHECK(strstr(html, "../scenes/a&amp;b"), "scene path not escaped");
    CHECK(strstr(html, "src=\"test/r_0%20photo%231.png\""), "path not percent-encoded");
    CHECK(strstr(html, "src=\"turntable.gif\""), "animation not referenced");
    CHECK(strstr(html, "r&lt;1&gt;") && count(html, "alt=\"photo\"") == 1, "test views");
    CHECK(strstr(html, "2 min 5 s (125.2 s)"), "wall time");
    /* metrics with scale and verdict; the warning above them */
    CHECK(strstr(html, "<tr><th>metric</th><th>value</th><th>unit and scale</th><th>verdict</th></tr>") &&
              strstr(html, "<tr><th>test loss</th><td>0.25</td><td class=\"scale\">line loss, 0 perfect; good "
                           "&lt;= 0.15</td><td class=\"verdict\"><span class=\"poor\">poor</span></td></tr>") &&
              strstr(html, "<tr><th>steps</th><td>400</td><td class=\"scale\"></td><td class=\"verdict\"></td></tr>"),
          "the metrics' scale and verdict columns");
    CHECK(strstr(html, "<p class=\"warning\" id=\"gt-warning\">Warning: gt.ply: the ground truth misses "
                       "&lt;part&gt;</p>") && strstr(html, "id=\"gt-warning\"") < strstr(html, "<table"),
          "the warning above the metrics");
    CHECK(count(html, "<line class=\"phase\"") == 3 && strstr(html, ">2 of 4 levels</text>") &&
              strstr(html, "<p class=\"hint\">the loss climbs where a phase begins</p>"),
          "the phases on the plot");
    /* r_0 cropped to 100 px at (40, 20) of 200: scaled 2.24 into 224 px */
    CHECK(count(html, "<div class=\"crop\"><img style=\"width:448.0px;margin:-44.8px 0 0 -89.6px\"") == 2 &&
              count(html, "<div class=\"crop\">") == 2,
          "the test views cropped to the object");
    CHECK(strstr(html, "loss (log scale)"), "a 300x range should get a log axis");
    char *svg = between(html, "<svg", "</svg>");
    CHECK(svg && !strstr(svg, "nan") && !strstr(svg, "inf"), "non-finite numbers in the SVG");
    CHECK(svg && count(svg, "<circle") == 5, "validation points: %d", svg ? count(svg, "<circle") : -1);
    free(svg);

    char *json = between(html, "<script type=\"application/json\" id=\"curve-data\">", "</script>");
    cJSON *doc = json ? cJSON_Parse(json) : NULL;
    CHECK(doc != NULL, "curve JSON does not parse");
    cJSON *curves = cJSON_GetObjectItemCaseSensitive(doc, "curves");
    CHECK(cJSON_IsArray(curves) && cJSON_GetArraySize(curves) == 2, "curves: %d",
          cJSON_GetArraySize(curves));
    if (cJSON_GetArraySize(curves) == 2) {
        cJSON *last = cJSON_GetArrayItem(curves, 1);
        int n = cJSON_GetArraySize(last);
        cJSON *p0 = cJSON_GetArrayItem(last, 0), *pn = cJSON_GetArrayItem(last, n - 1);
        int ok = n == 64 && cJSON_GetArraySize(p0) == 3;
        for (int k = 0; k < 3 && ok; k++)
            ok = check_close(cJSON_GetArrayItem(p0, k)->valuedouble, c.P[24 + k], 1e-5, 1e-6) &&
                 check_close(cJSON_GetArrayItem(pn, k)->valuedouble, c.P[33 + k], 1e-5, 1e-6);
        CHECK(ok, "curve 2 polyline: %d points, ends not at its end control points", n);
    }
    cJSON *cams = cJSON_GetObjectItemCaseSensitive(doc, "cameras");
    CHECK(cJSON_GetArraySize(cams) == 2 && cJSON_GetArraySize(cJSON_GetArrayItem(cams, 1)) == 6 &&
              cJSON_GetArrayItem(cJSON_GetArrayItem(cams, 1), 1)->valuedouble == 4,
          "the cameras in the 3D view's data");
    cJSON_Delete(doc);
    free(json);
    free(html);

    /* A narrow range gets a linear axis; nothing at all gets a note. */
    for (int k = 0; k < NT; k++) tloss[k] = 1.0 + 0.1 * sin(k);
    r.n_val = 0;
    r.curves = NULL;
    rc = ws_report_write(path, &r, &st);
    html = rc ? NULL : slurp(path, NULL);
    CHECK(html && !strstr(html, "log scale") && strstr(html, ">loss</text>") &&
              !strstr(html, "curve-data") && !strstr(html, "#curves-3d"),
          "linear report: %s", st.msg);
    free(html);
    r.n_train = 0;
    rc = ws_report_write(path, &r, &st);
    html = rc ? NULL : slurp(path, NULL);
    CHECK(html && !strstr(html, "<svg") && strstr(html, "No finite loss values"), "empty loss");
    free(html);

    const char *bad = in_dir("no/such/dir/report.html");
    rc = ws_report_write(bad, &r, &st);
    CHECK(rc == WS_EIO && strstr(st.msg, bad) == st.msg && strstr(st.msg, "cannot write"),
          "report into a missing directory: %d %s", rc, st.msg);
    CHECK(left_nothing(bad), "failed report left a file");
    ws_curves_free(&c);
}

int main(void) {
    dir = test_tmpdir("report");
    test_gif_gray();
    test_gif_rgb();
    test_gif_failures();
    test_turntable_cameras();
    test_turntable_render();
    test_report();
    static const char *files[] = {"gray.gif", "rgb.gif", "turntable.gif", "report.html"};
    for (size_t k = 0; k < sizeof files / sizeof *files; k++) unlink(in_dir(files[k]));
    CHECK(rmdir(dir) == 0, "%s: stray files left", dir);
    return check_summary();
}
