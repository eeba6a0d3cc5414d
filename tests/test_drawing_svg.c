/* test_drawing_svg.c: the SVG of the drawing a user gets (io/export.h):
 * a straight curve across a 64 px view whose drawing keeps curves only on
 * the image's left half is cut at the middle; the hull's line pixels (a
 * square ring of 16 and a lone pixel) come as polylines through their
 * centres, every pixel once, and a dot. `export --drawing` on the fixture:
 * hull adds the hull's lines, curves leaves them out, anything else is
 * refused with its one-line message. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "io/export.h"

#define N 64
#define FIXTURE "tests/fixtures/scene_small"

int main(void) {
    ws_status st;
    ws_status_clear(&st);
    const char *bin = program_path(), *tmp = test_tmpdir("drawing_svg");
    char path[512];
    static char out[1 << 14], svg[1 << 16];
    /* a camera at +z 4 looking down at the origin; a curve along x */
    ws_camera cam;
    double c2w[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 4}, {0, 0, 0, 1}};
    CHECK(ws_camera_init(&cam, c2w, 0.8, N, N, "camera", &st) == 0, "%s", st.msg);
    ws_curves c = {0};
    c.n = 1;
    c.thickness = 0.01;
    c.overlap = 0.6;
    double P[12] = {-1, 0, 0, -1.0 / 3, 0, 0, 1.0 / 3, 0, 0, 1, 0, 0};
    c.P = P;
    static uint8_t keep[N * N], lines[N * N];
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N / 2; j++) keep[i * N + j] = 1;
    for (int k = 10; k < 15; k++) lines[10 * N + k] = lines[14 * N + k] = lines[k * N + 10] = lines[k * N + 14] = 1;
    lines[40 * N + 40] = 1;
    ws_svg_drawing drawing = {.keep = keep, .lines = lines};
    snprintf(path, sizeof path, "%s/d.svg", tmp);
    CHECK(ws_export_svg(path, &c, &cam, NULL, &drawing, &st) == 0, "%s", st.msg);
    read_text(path, svg, sizeof svg);
    /* the curve: from its start (left of the frame's middle) to about the middle, one subpath */
    const char *curve = strstr(svg, "<path id=\"curve_0\"");
    double x0 = 0, y0 = 0;
    CHECK(curve && sscanf(strstr(curve, " d=\"") + 4, "M%lf %lf", &x0, &y0) == 2 && x0 < N / 2 - 5,
          "the curve's start: %s", curve ? curve : svg);
    const char *end = curve ? strstr(curve, "\"/>") : NULL;
    const char *last_c = NULL;
    for (const char *q = curve; q && (q = strstr(q, " C")) && q < end; q++) last_c = q;
    double x3 = 0, y3 = 0, ignore[4];
    CHECK(last_c && sscanf(last_c, " C%lf %lf %lf %lf %lf %lf", &ignore[0], &ignore[1], &ignore[2], &ignore[3], &x3,
                           &y3) == 6 && fabs(x3 - N / 2) < 1 && fabs(y3 - N / 2) < 1e-6,
          "the curve cut where the drawing stops keeping curves: ends at %.3f %.3f", x3, y3);
    int moves = 0;
    for (const char *q = curve; q && (q = strchr(q, 'M')) && q < end; q++) moves++;
    CHECK(moves == 1, "%d subpaths", moves);
    /* the lines: polylines whose points are the line pixels' centres, each once */
    const char *group = strstr(svg, "<g id=\"hull_lines\" stroke-width=\"1\">");
    CHECK(group != NULL, "no hull_lines group: %s", svg);
    static int seen[N * N];
    int points = 0, off = 0, again = 0, dots = 0, paths = 0;
    for (const char *q = group; q && (q = strstr(q, "<path d=\"")); paths++) {
        q += 9;
        const char *stop = strstr(q, "\"/>");
        dots += strncmp(stop - 5, " l0 0", 5) == 0;
        while (q < stop && (*q == 'M' || *q == ' ')) {
            if (*q == ' ') q++;
            if (*q == 'L' || *q == 'M') q++;
            else break;
            double x, y;
            int used;
            if (sscanf(q, "%lf %lf%n", &x, &y, &used) != 2) break;
            q += used;
            int j = (int)floor(x), i = (int)floor(y);
            points++;
            off += fabs(x - j - 0.5) > 1e-9 || fabs(y - i - 0.5) > 1e-9 || !lines[i * N + j];
            again += seen[i * N + j]++ > 0;
        }
    }
    CHECK(points == 17 && off == 0 && again == 0, "%d points, %d off the line pixels' centres, %d twice", points, off,
          again);
    CHECK(paths == 2 && dots == 1, "%d paths, %d dots: the ring and the lone pixel", paths, dots);
    /* without a drawing: the curve whole, no lines */
    CHECK(ws_export_svg(path, &c, &cam, NULL, NULL, &st) == 0, "%s", st.msg);
    read_text(path, svg, sizeof svg);
    CHECK(!strstr(svg, "hull_lines") && strstr(svg, "d=\"M") != NULL, "the curves alone: %s", svg);
    /* the CLI */
    int rc = run_cmd(out, sizeof out, "%s export " FIXTURE "/gt_curves.json --svg %s/hull.svg --scene " FIXTURE
                     " --size 64 --view 1", bin, tmp);
    snprintf(path, sizeof path, "%s/hull.svg", tmp);
    read_text(path, svg, sizeof svg);
    /* a wire knot, thin at 64 px: drawn by its curves, where the hull draws no outline */
    CHECK(rc == 0 && strstr(svg, "<g id=\"hull_lines\"") && strstr(svg, "<path id=\"curve_"),
          "export --drawing hull: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s export " FIXTURE "/gt_curves.json --svg %s/curves.svg --scene " FIXTURE
                 " --size 64 --view 1 --drawing curves", bin, tmp);
    snprintf(path, sizeof path, "%s/curves.svg", tmp);
    read_text(path, svg, sizeof svg);
    CHECK(rc == 0 && !strstr(svg, "hull_lines"), "export --drawing curves: %d %s", rc, out);
    rc = run_cmd(out, sizeof out, "%s export " FIXTURE "/gt_curves.json --svg %s/x.svg --scene " FIXTURE
                 " --drawing lines", bin, tmp);
    CHECK(rc == 2 && !strcmp(out, "wiresketch: --drawing: 'lines' is not hull or curves\n"), "a bad mode: %s", out);
    return check_summary();
}
