/* test_metrics.c: the PLY reader, exact nearest neighbours, surface
 * distance, curve Chamfer and F-score (METHOD.md section 8). */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "metrics/metrics.h"
#include "metrics/line_metrics.h"
#include "nn/base/rng.h"

/* A ground-truth point set and what is known of it independently: its
 * size, bounding box bounds and diagonal. The fixture's values come from
 * tools/make_scene_fixture.py, which wrote it; the rose's is checked by
 * `make test-scenes`. */
typedef struct {
    const char *name, *path;
    int n;
    double x_lo, x_hi, z_lo, z_hi; /* lo[0] > x_lo, hi[0] < x_hi, same for z */
    double diagonal;
} gt_set;
static gt_set GT = {"fixture", "tests/fixtures/scene_small/gt_points.ply", 1200, -0.44, 1.04, 0.22, 0.78,
                    2.08140569};

static const char *tmpdir;
static char path[256];

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Writes a test file (header text then optional binary data) at `path`. */
static void write_file(const char *header, const void *data, size_t len) {
    snprintf(path, sizeof path, "%s/t.ply", tmpdir);
    FILE *f = fopen(path, "wb");
    fputs(header, f);
    if (len) fwrite(data, 1, len, f);
    fclose(f);
}

/* Loads `path` expecting failure with exactly "PATH: msg". */
static void expect_error(const char *msg, int line) {
    ws_pointcloud pc;
    ws_status st;
    ws_status_clear(&st);
    char want[1100];
    snprintf(want, sizeof want, "%s: %s", path, msg);
    int rc = ws_pointcloud_load_ply(path, &pc, &st);
    CHECK(rc == WS_EINPUT && !strcmp(st.msg, want) && pc.xyz == NULL,
          "line %d: rc %d, got '%s', want '%s'", line, rc, st.msg, want);
}

static void test_gt_ply(void) {
    ws_pointcloud pc;
    ws_status st;
    ws_status_clear(&st);
    int rc = ws_pointcloud_load_ply(GT.path, &pc, &st);
    CHECK(rc == WS_OK, "%s: %s", GT.name, st.msg);
    if (rc) return;
    CHECK(pc.n == GT.n, "%s: %d points", GT.name, pc.n);
    /* The first and last vertices, decoded independently of the reader. */
    FILE *f = fopen(GT.path, "rb");
    static char buf[1 << 21];
    size_t len = fread(buf, 1, sizeof buf, f);
    fclose(f);
    char *end = strstr(buf, "end_header\n");
    float first[3], last[3];
    memcpy(first, end + 11, 12);
    memcpy(last, buf + len - 12, 12);
    int same = 1;
    for (int a = 0; a < 3; a++)
        same &= pc.xyz[a] == first[a] && pc.xyz[(size_t)(pc.n - 1) * 3 + a] == last[a];
    CHECK(same, "%s: first/last vertex differ from the raw floats", GT.name);
    double lo[3], hi[3];
    ws_points_bbox(pc.xyz, pc.n, lo, hi);
    double diag = ws_points_diagonal(pc.xyz, pc.n);
    CHECK(lo[0] > GT.x_lo && hi[0] < GT.x_hi && lo[2] > GT.z_lo && hi[2] < GT.z_hi,
          "%s bbox [%g %g %g]-[%g %g %g]", GT.name, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    CHECK(check_close(diag, GT.diagonal, 1e-6, 0), "%s diagonal %.9g", GT.name, diag);
    ws_pointcloud_free(&pc);
}

static void put_bytes(unsigned char **p, uint64_t bits, int size, int big) {
    for (int i = 0; i < size; i++) (*p)[big ? size - 1 - i : i] = (unsigned char)(bits >> (8 * i));
    *p += size;
}

static uint64_t bits_f(float v) {
    uint32_t u;
    memcpy(&u, &v, 4);
    return u;
}

static uint64_t bits_d(double v) {
    uint64_t u;
    memcpy(&u, &v, 8);
    return u;
}

/* Binary files of mixed types in both byte orders: a skipped element with a
 * list before the vertices; x double, a uchar, y short, a vertex list, z
 * float, then a face element that is never read. */
static void test_binary_types(void) {
    for (int big = 0; big < 2; big++) {
        char header[512];
        snprintf(header, sizeof header,
                 "ply\nformat binary_%s_endian 1.0\ncomment mixed types\n"
                 "element camera 2\nproperty list uchar int ids\nproperty float w\n"
                 "element vertex 2\nproperty float64 x\nproperty uchar red\nproperty int16 y\n"
                 "property list uint8 float ignored\nproperty float z\n"
                 "element face 5\nproperty list uchar int vertex_indices\nend_header\n",
                 big ? "big" : "little");
        unsigned char data[256], *p = data;
        put_bytes(&p, 2, 1, big); /* camera 0: 2 ids and w */
        put_bytes(&p, 7, 4, big);
        put_bytes(&p, 8, 4, big);
        put_bytes(&p, bits_f(1), 4, big);
        put_bytes(&p, 0, 1, big); /* camera 1: no ids */
        put_bytes(&p, bits_f(2), 4, big);
        double xs[2] = {0.1, -1e300};
        short ys[2] = {-300, 32767};
        float zs[2] = {2.5f, -0.0f};
        for (int v = 0; v < 2; v++) {
            put_bytes(&p, bits_d(xs[v]), 8, big);
            put_bytes(&p, 255, 1, big);
            put_bytes(&p, (uint16_t)ys[v], 2, big);
            put_bytes(&p, 1, 1, big);
            put_bytes(&p, bits_f(9), 4, big);
            put_bytes(&p, bits_f(zs[v]), 4, big);
        }
        write_file(header, data, (size_t)(p - data));
        ws_pointcloud pc;
        ws_status st;
        ws_status_clear(&st);
        int rc = ws_pointcloud_load_ply(path, &pc, &st);
        CHECK(rc == WS_OK, "binary %d: %s", big, st.msg);
        if (rc) continue;
        double want[6] = {0.1, -300, 2.5, -1e300, 32767, 0};
        CHECK(pc.n == 2 && !memcmp(pc.xyz, want, 5 * sizeof(double)) && pc.xyz[5] == 0,
              "binary %d: values %g %g %g %g %g %g", big, pc.xyz[0], pc.xyz[1], pc.xyz[2],
              pc.xyz[3], pc.xyz[4], pc.xyz[5]);
        ws_pointcloud_free(&pc);
    }
}

static void test_ascii(void) {
    write_file("ply\r\nformat ascii 1.0\r\ncomment CRLF lines, extra properties\r\n"
               "obj_info anything at all\r\n"
               "element vertex 3\r\nproperty float nx\r\nproperty float z\r\nproperty uchar red\r\n"
               "property float y\r\nproperty list uchar int idx\r\nproperty float x\r\n"
               "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
               "0.5 3 255 2 2 7 8 1\r\n9 -6e-1 0 5.25 0 -4\r\n"
               "1\t1e2 1 1 3 1 2 3 0x10\r\n3 0 1 2\r\n",
               NULL, 0);
    ws_pointcloud pc;
    ws_status st;
    ws_status_clear(&st);
    int rc = ws_pointcloud_load_ply(path, &pc, &st);
    CHECK(rc == WS_OK, "ascii: %s", st.msg);
    if (rc) return;
    double want[9] = {1, 2, 3, -4, 5.25, -0.6, 16, 1, 100};
    CHECK(pc.n == 3 && !memcmp(pc.xyz, want, sizeof want), "ascii: values %g %g %g / %g %g %g",
          pc.xyz[0], pc.xyz[1], pc.xyz[2], pc.xyz[3], pc.xyz[4], pc.xyz[5]);
    ws_pointcloud_free(&pc);
}

static void test_hostile_ply(void) {
    const char *xyz = "property float x\nproperty float y\nproperty float z\n";
    char h[1024];
    float twelve[3] = {1, 2, 3};

    snprintf(path, sizeof path, "%s/missing.ply", tmpdir);
    ws_pointcloud pc;
    ws_status st;
    ws_status_clear(&st);
    CHECK(ws_pointcloud_load_ply(path, &pc, &st) == WS_EINPUT && strstr(st.msg, "missing.ply: cannot open"),
          "missing file: %s", st.msg);

    write_file("hello\nworld\n", NULL, 0);
    expect_error("not a PLY file (the first line is not 'ply')", __LINE__);
    write_file("", NULL, 0);
    expect_error("not a PLY file (the first line is not 'ply')", __LINE__);
    write_file("ply", NULL, 0);
    expect_error("the header has no end_header line", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", NULL, 0);
    expect_error("the header has no end_header line", __LINE__);
    write_file("ply\nelement vertex 1\nend_header\n", NULL, 0);
    expect_error("the header has no format line", __LINE__);
    write_file("ply\nformat binary_middle_endian 1.0\nend_header\n", NULL, 0);
    expect_error("unsupported PLY format 'binary_middle_endian'", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\nend_header\n", NULL, 0);
    expect_error("header line 3: element count '99999999999999999999999' is not a valid count", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement vertex -5\nend_header\n", NULL, 0);
    expect_error("header line 3: element count '-5' is not a valid count", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", NULL, 0);
    expect_error("header line 4: unknown property type 'float128'", __LINE__);
    write_file("ply\nformat ascii 1.0\nproperty float x\nend_header\n", NULL, 0);
    expect_error("header line 3: property before any element", __LINE__);
    write_file("ply\nformat ascii 1.0\nvertices 3\nend_header\n", NULL, 0);
    expect_error("header line 3: unknown keyword 'vertices'", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement face 1\nend_header\n", NULL, 0);
    expect_error("no vertex element", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
               "end_header\n1 2\n", NULL, 0);
    expect_error("vertex element has no property 'z'", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n"
               "property float y\nproperty float z\nend_header\n", NULL, 0);
    expect_error("vertex property 'x' is a list", __LINE__);
    snprintf(h, sizeof h, "ply\nformat ascii 1.0\nelement vertex 0\n%send_header\n", xyz);
    write_file(h, NULL, 0);
    expect_error("no vertices", __LINE__);

    /* A count that fits in 64 bits but not in the file: refused before any
     * allocation, for the vertices and for an element skipped before them. */
    snprintf(h, sizeof h, "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n%send_header\n", xyz);
    write_file(h, twelve, 12);
    expect_error("element 'vertex' claims 1000000000000 rows but only 12 bytes of data follow", __LINE__);
    snprintf(h, sizeof h, "ply\nformat binary_little_endian 1.0\nelement face 4611686018427387904\n"
             "property list uchar int idx\nelement vertex 1\n%send_header\n", xyz);
    write_file(h, twelve, 12);
    expect_error("element 'face' claims 4611686018427387904 rows but only 12 bytes of data follow", __LINE__);
    /* Binary rows cut short; a list whose length runs past the end. */
    snprintf(h, sizeof h, "ply\nformat binary_little_endian 1.0\nelement vertex 2\n%send_header\n", xyz);
    write_file(h, twelve, 12);
    expect_error("element 'vertex' claims 2 rows but only 12 bytes of data follow", __LINE__);
    unsigned char listed[16] = {200};
    memcpy(listed + 4, twelve, 12);
    write_file("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty list uchar int l\n"
               "property float x\nproperty float y\nproperty float z\nend_header\n", listed, 16);
    expect_error("truncated: 0 of 1 vertex rows present", __LINE__);
    snprintf(h, sizeof h, "ply\nformat ascii 1.0\nelement vertex 3\n%send_header\n1 2 3\n4 5 6\n7 8\n", xyz);
    write_file(h, NULL, 0);
    expect_error("truncated: 2 of 3 vertex rows present", __LINE__);
    snprintf(h, sizeof h, "ply\nformat ascii 1.0\nelement vertex 1\n%send_header\n1 abc 3\n", xyz);
    write_file(h, NULL, 0);
    expect_error("vertex row 0: 'abc' is not a number", __LINE__);
    snprintf(h, sizeof h, "ply\nformat ascii 1.0\nelement vertex 2\n%send_header\n1 2 3\n1 nan 3\n", xyz);
    write_file(h, NULL, 0);
    expect_error("vertex row 1 has a non-finite coordinate", __LINE__);
    float inf3[3] = {1, INFINITY, 0};
    snprintf(h, sizeof h, "ply\nformat binary_little_endian 1.0\nelement vertex 1\n%send_header\n", xyz);
    write_file(h, inf3, 12);
    expect_error("vertex row 0 has a non-finite coordinate", __LINE__);
    write_file("ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar int l\nproperty float x\n"
               "property float y\nproperty float z\nend_header\n-1 1 2 3\n", NULL, 0);
    expect_error("vertex row 0: bad list length", __LINE__);

    /* An element without properties but an absurd count takes no bytes and
     * no time; the vertices after it still read. */
    snprintf(h, sizeof h, "ply\nformat binary_little_endian 1.0\nelement nothing 9000000000000000000\n"
             "element vertex 1\n%send_header\n", xyz);
    write_file(h, twelve, 12);
    ws_status_clear(&st);
    int rc = ws_pointcloud_load_ply(path, &pc, &st);
    CHECK(rc == WS_OK && pc.n == 1 && pc.xyz[2] == 3, "empty element: %s", st.msg);
    if (!rc) ws_pointcloud_free(&pc);
}

static void random_points(ws_rng *rng, double *xyz, int n, double scale) {
    for (int i = 0; i < n * 3; i++) xyz[i] = scale * (2 * ws_rng_uniform(rng) - 1);
}

/* Brute force: the lowest index at the smallest distance. */
static void brute_nearest(const double *set, int n, const double *q, double *dist, int *index) {
    double best = INFINITY;
    int bi = -1;
    for (int i = 0; i < n; i++) {
        double dx = q[0] - set[i * 3], dy = q[1] - set[i * 3 + 1], dz = q[2] - set[i * 3 + 2];
        double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 < best) {
            best = d2;
            bi = i;
        }
    }
    *dist = sqrt(best);
    *index = bi;
}

static void test_nearest_vs_brute(void) {
    ws_rng rng;
    ws_rng_seed(&rng, 7);
    static const int sizes[] = {1, 2, 31, 32, 33, 65, 1000, 20000};
    int nq = 3000;
    double *q = malloc((size_t)nq * 3 * sizeof(double));
    double *d = malloc((size_t)nq * sizeof(double));
    int *idx = malloc((size_t)nq * sizeof(int));
    for (int s = 0; s < (int)(sizeof sizes / sizeof sizes[0]); s++)
        for (int kind = 0; kind < 2; kind++) {
            int n = sizes[s];
            double *set = malloc((size_t)n * 3 * sizeof(double));
            /* kind 0: continuous coordinates; kind 1: a coarse integer
             * lattice with duplicate points and many exact distance ties. */
            random_points(&rng, set, n, 1);
            if (kind)
                for (int i = 0; i < n * 3; i++) set[i] = round(set[i] * 3);
            random_points(&rng, q, nq, kind ? 4 : 3);
            if (kind)
                for (int i = 0; i < nq * 3; i++) q[i] = round(q[i] * 2) / 2;
            for (int i = 0; i < nq / 10; i++) /* queries on set points: distance 0 */
                memcpy(q + i * 3, set + (i % n) * 3, 3 * sizeof(double));
            ws_nearest t;
            ws_status st;
            ws_status_clear(&st);
            if (ws_nearest_build(&t, set, n, &st)) {
                CHECK(0, "build %d: %s", n, st.msg);
                free(set);
                continue;
            }
            ws_nearest_query(&t, q, nq, d, idx);
            int bad = 0;
            for (int i = 0; i < nq; i++) {
                double bd;
                int bi;
                brute_nearest(set, n, q + i * 3, &bd, &bi);
                bad += bd != d[i] || bi != idx[i];
            }
            CHECK(bad == 0, "n %d kind %d: %d of %d queries differ from brute force", n, kind, bad, nq);
            ws_nearest_free(&t);
            free(set);
        }
    ws_nearest t;
    ws_status st;
    ws_status_clear(&st);
    CHECK(ws_nearest_build(&t, q, 0, &st) == WS_EINPUT && !strcmp(st.msg, "nearest-neighbour set is empty"),
          "empty set: %s", st.msg);
    q[4] = NAN;
    CHECK(ws_nearest_build(&t, q, 3, &st) == WS_ENUMERIC &&
              !strcmp(st.msg, "nearest-neighbour set: point 1 is not finite"),
          "NaN set: %s", st.msg);
    free(q);
    free(d);
    free(idx);
}

/* Surface distance on the ground-truth set: gt points themselves give exactly 0; the
 * query speed is measured on Gaussian-like points around the object, and
 * the answer must not depend on the thread count. */
static void test_surface_gt(void) {
    ws_pointcloud pc;
    ws_status st;
    ws_status_clear(&st);
    if (ws_pointcloud_load_ply(GT.path, &pc, &st)) {
        CHECK(0, "%s: %s", GT.name, st.msg);
        return;
    }
    double t0 = now();
    ws_surface_gt gt;
    int rc = ws_surface_gt_init(&gt, &pc, &st);
    double t_build = now() - t0;
    CHECK(rc == WS_OK, "%s gt: %s", GT.name, st.msg);
    if (rc) {
        ws_pointcloud_free(&pc);
        return;
    }
    /* The tree itself does not depend on the thread count either. */
    ws_nearest tree1, tree2;
    omp_set_num_threads(1);
    rc = ws_nearest_build(&tree1, pc.xyz, pc.n, &st);
    omp_set_num_threads(2);
    rc |= ws_nearest_build(&tree2, pc.xyz, pc.n, &st);
    size_t nodes = ((size_t)2 << tree1.depth) - 1;
    CHECK(rc == WS_OK && tree1.depth == tree2.depth && !memcmp(tree1.xyz, tree2.xyz, (size_t)pc.n * 24) &&
              !memcmp(tree1.index, tree2.index, (size_t)pc.n * sizeof(int)) &&
              !memcmp(tree1.box, tree2.box, nodes * 6 * sizeof(double)),
          "k-d tree differs between 1 and 2 threads");
    ws_nearest_free(&tree1);
    ws_nearest_free(&tree2);

    int n = 50000;
    ws_gaussians g = {.n = n, .mu = malloc((size_t)n * 3 * sizeof(double))};
    for (int i = 0; i < n; i++) memcpy(g.mu + i * 3, pc.xyz + (size_t)((i * 7919L) % pc.n) * 3, 24);
    ws_surface_metrics m;
    rc = ws_surface_distance(&gt, &g, &m, &st);
    CHECK(rc == WS_OK && m.n == n && m.mean == 0 && m.p90 == 0, "on gt: %s mean %g p90 %g", st.msg, m.mean, m.p90);

    /* Points spread over the bounding box grown by 20% (like a fit's
     * Gaussians early on), plus a tight shell near the surface. */
    ws_rng rng;
    ws_rng_seed(&rng, 3);
    double lo[3], hi[3];
    ws_points_bbox(pc.xyz, pc.n, lo, hi);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            double c = 0.5 * (lo[a] + hi[a]), r = 0.6 * (hi[a] - lo[a]);
            g.mu[i * 3 + a] = i % 2 ? c + r * (2 * ws_rng_uniform(&rng) - 1)
                                    : pc.xyz[(size_t)(i % pc.n) * 3 + a] + 0.01 * ws_rng_normal(&rng);
        }
    ws_surface_metrics m1, m2;
    omp_set_num_threads(1);
    t0 = now();
    rc = ws_surface_distance(&gt, &g, &m1, &st);
    double t1 = now() - t0;
    omp_set_num_threads(2);
    t0 = now();
    rc |= ws_surface_distance(&gt, &g, &m2, &st);
    double t2 = now() - t0;
    CHECK(rc == WS_OK && m1.n == m2.n && m1.mean == m2.mean && m1.p90 == m2.p90,
          "thread count changes the result");
    CHECK(m1.mean > 0 && m1.p90 > m1.mean && m1.p90 < 0.5, "%s spread: mean %g p90 %g", GT.name, m1.mean, m1.p90);
    printf("%s gt %d points: tree build %.1f ms; %d queries: %.0f points/s (1 thread), %.0f points/s (2 threads)\n",
           GT.name, pc.n, 1e3 * t_build, n, n / t1, n / t2);
    printf("%s spread: mean %.4f p90 %.4f (of the diagonal)\n", GT.name, m1.mean, m1.p90);
    free(g.mu);
    ws_surface_gt_free(&gt);
    ws_pointcloud_free(&pc);
}

/* Exact values: gt points (0,0,0) and (10,0,0), diagonal 10; centres at
 * (0, y, 0), y = 1..n in shuffled order, are y away from the gt. */
static void test_surface_exact(void) {
    double gtp[6] = {0, 0, 0, 10, 0, 0};
    ws_pointcloud pc = {.n = 2, .xyz = gtp};
    ws_surface_gt gt;
    ws_status st;
    ws_status_clear(&st);
    if (ws_surface_gt_init(&gt, &pc, &st)) {
        CHECK(0, "exact gt: %s", st.msg);
        return;
    }
    CHECK(gt.diagonal == 10, "diagonal %g", gt.diagonal);
    for (int n = 10; n <= 11; n++) {
        double mu[33] = {0};
        for (int i = 0; i < n; i++) mu[i * 3 + 1] = 1 + (i * 7) % n;
        ws_gaussians g = {.n = n, .mu = mu};
        ws_surface_metrics m;
        int rc = ws_surface_distance(&gt, &g, &m, &st);
        /* mean (n + 1) / 2 / 10; nearest rank ceil(0.9 n) = 9 for 10, 10 for 11. */
        CHECK(rc == WS_OK && check_close(m.mean, (n + 1) / 20.0, 1e-15, 0) && m.p90 == (n == 10 ? 0.9 : 1.0),
              "n %d: mean %g p90 %g", n, m.mean, m.p90);
    }
    ws_gaussians empty = {0};
    ws_surface_metrics m;
    CHECK(ws_surface_distance(&gt, &empty, &m, &st) == WS_EINPUT &&
              !strcmp(st.msg, "surface distance: Gaussian centres: no points to measure"),
          "no centres: %s", st.msg);
    double bad[3] = {0, NAN, 0};
    ws_gaussians nan_g = {.n = 1, .mu = bad};
    CHECK(ws_surface_distance(&gt, &nan_g, &m, &st) == WS_ENUMERIC &&
              !strcmp(st.msg, "surface distance: Gaussian centres: point 0 is not finite"),
          "NaN centre: %s", st.msg);
    ws_surface_gt_free(&gt);
    pc.n = 1;
    CHECK(ws_surface_gt_init(&gt, &pc, &st) == WS_EINPUT &&
              !strcmp(st.msg, "ground-truth points: the bounding box has a zero diagonal"),
          "one gt point: %s", st.msg);
}

/* Per curve: gt points (0,0,0) and (10,0,0), diagonal 10; curve 0 holds
 * centres 1 and 2 away, curve 1 centres 3 .. 10 away, curve 2 none. Over
 * the 10 centres the mean is 55 / 100 and the p90 (nearest rank 9) 9 / 10:
 * curve 0 adds 3 / 100, curve 1 52 / 100, and only the centre 10 away lies
 * beyond the p90. */
static void test_surface_by_curve(void) {
    double gtp[6] = {0, 0, 0, 10, 0, 0}, mu[30] = {0};
    int curve[10];
    for (int i = 0; i < 10; i++) {
        mu[i * 3 + 1] = 1 + i;
        curve[i] = i < 2 ? 0 : 1;
    }
    ws_pointcloud pc = {.n = 2, .xyz = gtp};
    ws_gaussians g = {.n = 10, .mu = mu, .curve = curve};
    ws_surface_gt gt;
    ws_status st;
    ws_status_clear(&st);
    if (ws_surface_gt_init(&gt, &pc, &st)) {
        CHECK(0, "per-curve gt: %s", st.msg);
        return;
    }
    ws_surface_curve per[3];
    ws_surface_metrics m;
    int rc = ws_surface_distance_by_curve(&gt, &g, 3, per, &st) || ws_surface_distance(&gt, &g, &m, &st);
    CHECK(rc == WS_OK && per[0].n == 2 && per[1].n == 8 && per[2].n == 0, "counts %d %d %d (%s)", per[0].n,
          per[1].n, per[2].n, st.msg);
    CHECK(check_close(per[0].adds, 0.03, 1e-15, 0) && check_close(per[1].adds, 0.52, 1e-15, 0) &&
              per[2].adds == 0 && check_close(per[0].adds + per[1].adds, m.mean, 1e-15, 0),
          "adds %g %g %g, mean %g", per[0].adds, per[1].adds, per[2].adds, m.mean);
    CHECK(check_close(per[0].mean, 0.15, 1e-15, 0) && check_close(per[1].mean, 0.65, 1e-15, 0) && per[2].mean == 0,
          "means %g %g %g", per[0].mean, per[1].mean, per[2].mean);
    CHECK(per[0].beyond_p90 == 0 && per[1].beyond_p90 == 1 && per[2].beyond_p90 == 0, "beyond p90 %d %d %d",
          per[0].beyond_p90, per[1].beyond_p90, per[2].beyond_p90);
    curve[4] = 3;
    CHECK(ws_surface_distance_by_curve(&gt, &g, 3, per, &st) == WS_EINTERNAL &&
              !strcmp(st.msg, "surface distance: Gaussian 4 belongs to curve 3 of 3"),
          "curve out of range: %s", st.msg);
    ws_surface_gt_free(&gt);
}

/* A straight curve from a to b, control points at thirds (uniform speed). */
static void segment(ws_curves *c, int ci, const double a[3], const double b[3]) {
    for (int j = 0; j < 4; j++)
        for (int x = 0; x < 3; x++) c->P[ci * WS_CURVE_FLOATS + j * 3 + x] = a[x] + (b[x] - a[x]) * j / 3.0;
}

static void test_curve_metrics(void) {
    ws_status st;
    ws_status_clear(&st);
    ws_rng rng;
    ws_rng_seed(&rng, 11);
    ws_curves a, b;
    double center[3] = {0.5, -0.2, 1};
    if (ws_curves_init_random(&a, 25, center, 0.8, 0.5, 0.02, 0.6, &rng, &st)) {
        CHECK(0, "init: %s", st.msg);
        return;
    }
    /* Bend the straight initial curves so that the sets are not trivial. */
    for (int i = 0; i < 25 * WS_CURVE_FLOATS; i++) a.P[i] += 0.1 * ws_rng_normal(&rng);
    ws_curve_metrics m, m2;
    int rc = ws_curve_metrics_compute(&a, &a, &m, &st);
    CHECK(rc == WS_OK && m.chamfer == 0 && m.precision == 1 && m.recall == 1 && m.fscore == 1,
          "identical: %s chamfer %g F %g", st.msg, m.chamfer, m.fscore);
    CHECK(m.n_gt == m.n_result && m.n_gt > 25 * 100 && m.spacing == m.diagonal / 1000 &&
              m.threshold == m.diagonal / 100,
          "identical: %d samples, spacing %g of %g", m.n_gt, m.spacing, m.diagonal);

    /* Determinism across thread counts, with a perturbed result. */
    ws_curves_alloc(&b, 20, &st);
    memcpy(b.P, a.P, 20 * WS_CURVE_FLOATS * sizeof(double));
    for (int i = 0; i < 20 * WS_CURVE_FLOATS; i++) b.P[i] += 0.02 * ws_rng_normal(&rng);
    omp_set_num_threads(1);
    rc = ws_curve_metrics_compute(&b, &a, &m, &st);
    omp_set_num_threads(2);
    rc |= ws_curve_metrics_compute(&b, &a, &m2, &st);
    CHECK(rc == WS_OK && m.n_result == m2.n_result && m.n_gt == m2.n_gt && m.chamfer == m2.chamfer &&
              m.precision == m2.precision && m.recall == m2.recall && m.fscore == m2.fscore,
          "thread count changes the curve metrics");
    CHECK(m.chamfer > 0 && m.fscore > 0 && m.fscore < 1 && m.recall < 0.9,
          "perturbed: chamfer %g P %g R %g F %g", m.chamfer, m.precision, m.recall, m.fscore);
    ws_curves_free(&b);
    ws_curves_free(&a);

    /* Parallel unit segments delta apart: every sample's nearest is its
     * twin, so chamfer = delta / D with D = 1; F = 1 iff delta <= 0.01. */
    ws_curves_alloc(&a, 1, &st);
    ws_curves_alloc(&b, 1, &st);
    double o[3] = {0, 0, 0}, x1[3] = {1, 0, 0};
    segment(&a, 0, o, x1);
    for (int k = 0; k < 2; k++) {
        double delta = k ? 0.02 : 0.005;
        double p[3] = {0, delta, 0}, q[3] = {1, delta, 0};
        segment(&b, 0, p, q);
        rc = ws_curve_metrics_compute(&b, &a, &m, &st);
        CHECK(rc == WS_OK && m.diagonal == 1 && m.n_gt == m.n_result && abs(m.n_gt - 1000) <= 1 &&
                  check_close(m.chamfer, delta, 1e-9, 0) && m.fscore == (k ? 0 : 1),
              "offset %g: %s D %g n %d/%d chamfer %.12g F %g", delta, st.msg, m.diagonal, m.n_gt,
              m.n_result, m.chamfer, m.fscore);
    }
    /* Result tilted by slope s = 0.1 from the gt's start: result points lie
     * s u from the gt (mean s / 2), gt points s x / sqrt(1 + s^2) from the
     * result (mean s / (2 sqrt(1 + s^2))); within tau = 0.01 are u <= 0.1
     * and x <= 0.1 sqrt(1 + s^2). Sampling moves these by O(h). */
    double s = 0.1, tip[3] = {1, s, 0};
    segment(&b, 0, o, tip);
    rc = ws_curve_metrics_compute(&b, &a, &m, &st);
    double r = sqrt(1 + s * s), P = 0.01 / s, R = 0.01 * r / s;
    CHECK(rc == WS_OK && check_close(m.chamfer, (s / 2 + s / (2 * r)) / 2, 1e-4, 0),
          "tilted: chamfer %.9g want %.9g", m.chamfer, (s / 2 + s / (2 * r)) / 2);
    CHECK(fabs(m.precision - P) < 2e-3 && fabs(m.recall - R) < 2e-3 &&
              check_close(m.fscore, 2 * P * R / (P + R), 1e-2, 0),
          "tilted: P %g (%g) R %g (%g) F %g", m.precision, P, m.recall, R, m.fscore);

    /* Bad input. */
    ws_curves none = {0};
    CHECK(ws_curve_metrics_compute(&none, &a, &m, &st) == WS_EINPUT &&
              !strcmp(st.msg, "curve metrics: the result has no curves"), "no result: %s", st.msg);
    CHECK(ws_curve_metrics_compute(&a, &none, &m, &st) == WS_EINPUT &&
              !strcmp(st.msg, "curve metrics: the ground truth has no curves"), "no gt: %s", st.msg);
    segment(&b, 0, x1, x1);
    CHECK(ws_curve_metrics_compute(&a, &b, &m, &st) == WS_EINPUT &&
              !strcmp(st.msg, "curve metrics: the ground-truth curves have a zero-diagonal bounding box"),
          "point gt: %s", st.msg);
    /* A degenerate result curve is one sample: the gt's end point. */
    rc = ws_curve_metrics_compute(&b, &a, &m, &st);
    CHECK(rc == WS_OK && m.n_result == 1 && m.precision == 1 && check_close(m.chamfer, 0.25, 1e-3, 0),
          "point result: %s chamfer %g P %g", st.msg, m.chamfer, m.precision);
    b.P[7] = INFINITY;
    CHECK(ws_curve_metrics_compute(&b, &a, &m, &st) == WS_ENUMERIC &&
              !strcmp(st.msg, "curve metrics: result control points: point 2 is not finite"),
          "inf result: %s", st.msg);
    ws_curves_free(&a);
    ws_curves_free(&b);
}

/* line_metrics.h against closed forms: parallel segments delta apart,
 * a tilted segment, and bad input. */
static void test_line_metrics(void) {
    ws_status st;
    ws_status_clear(&st);
    ws_curves a, b, none = {0};
    ws_curves_alloc(&a, 1, &st);
    ws_curves_alloc(&b, 1, &st);
    double o[3] = {0, 0, 0}, x1[3] = {2, 0, 0};
    segment(&a, 0, o, x1); /* S = 2, spacing 0.01 */
    ws_line_metrics m;
    const double deltas[3] = {0.015, 0.03, 0.06}; /* within tau 0.02 and 0.04; within 0.04; neither */
    for (int k = 0; k < 3; k++) {
        double p[3] = {0, deltas[k], 0}, q[3] = {2, deltas[k], 0};
        segment(&b, 0, p, q);
        int rc = ws_line_metrics_compute(&b, &a, &m, &st);
        double d = deltas[k] / 2;
        CHECK(rc == WS_OK && m.side == 2 && abs(m.n_gt - 200) <= 1 && m.n_result == m.n_gt &&
                  check_close(m.accuracy, d, 1e-9, 0) && check_close(m.completeness, d, 1e-9, 0) &&
                  check_close(m.chamfer, 2 * d, 1e-9, 0) && m.fscore[0] == (k == 0) &&
                  m.fscore[1] == (k <= 1) && m.precision[1] == (k <= 1) && m.recall[0] == (k == 0),
              "offset %g: %s S %g n %d acc %g comp %g F %g %g", deltas[k], st.msg, m.side, m.n_gt,
              m.accuracy, m.completeness, m.fscore[0], m.fscore[1]);
    }
    /* slope s = 0.1 from the start (as in test_curve_metrics, S = 2): result
     * points lie s u from the gt, gt points s x / sqrt(1 + s^2) from it;
     * within tau are u <= tau / s and x <= tau sqrt(1 + s^2) / s. */
    double s = 0.1, tip[3] = {2, 2 * s, 0}, r = sqrt(1 + s * s);
    segment(&b, 0, o, tip);
    int rc = ws_line_metrics_compute(&b, &a, &m, &st);
    CHECK(rc == WS_OK && check_close(m.accuracy, s / 2, 2e-3, 0) &&
              check_close(m.completeness, s / (2 * r), 2e-3, 0),
          "tilted: acc %g comp %g", m.accuracy, m.completeness);
    for (int k = 0; k < WS_LINE_NTAU; k++) {
        double tau = WS_LINE_TAU[k] * 2, P = tau / s / (2 * r), R = tau * r / s / 2;
        CHECK(fabs(m.precision[k] - P) < 1e-2 && fabs(m.recall[k] - R) < 1e-2,
              "tilted tau %g: P %g (%g) R %g (%g)", tau, m.precision[k], P, m.recall[k], R);
    }
    CHECK(ws_line_metrics_compute(&none, &a, &m, &st) == WS_EINPUT &&
              !strcmp(st.msg, "line metrics: the result has no curves"), "no result: %s", st.msg);
    CHECK(ws_line_metrics_compute(&a, &none, &m, &st) == WS_EINPUT &&
              !strcmp(st.msg, "line metrics: the ground truth has no curves"), "no gt: %s", st.msg);
    segment(&b, 0, x1, x1);
    CHECK(ws_line_metrics_compute(&a, &b, &m, &st) == WS_EINPUT &&
              !strcmp(st.msg, "line metrics: the ground-truth curves' bounding box has no extent"),
          "point gt: %s", st.msg);
    ws_curves_free(&a);
    ws_curves_free(&b);
}

/* With a scenes folder as argument (make test-scenes), the ground-truth
 * checks run on its rose instead of the fixture. */
int main(int argc, char **argv) {
    double t0 = now();
    static char rose[1100];
    if (argc > 1) {
        snprintf(rose, sizeof rose, "%s/rose/gt_points.ply", argv[1]);
        GT = (gt_set){"rose", rose, 136205, 11, 14, 3.5, 7.5, 4.1609178};
    }
    tmpdir = test_tmpdir("metrics");
    test_gt_ply();
    test_binary_types();
    test_ascii();
    test_hostile_ply();
    test_nearest_vs_brute();
    test_surface_exact();
    test_surface_by_curve();
    test_surface_gt();
    test_curve_metrics();
    test_line_metrics();
    printf("test_metrics: %.2f s\n", now() - t0);
    return check_summary();
}
