/* check.h: the assertions every test program uses.
 *
 * CHECK(cond, fmt, ...) counts one passed or failed assertion and prints the
 * message of a failure with its file and line. A test program ends with
 * `return check_summary();`, which prints "N passed, N failed" (tests/run.sh
 * adds these lines up) and returns non-zero when anything failed. */
#ifndef WS_CHECK_H
#define WS_CHECK_H
#include <math.h>
#include <stdio.h>

static int check_passed, check_failed;

#define CHECK(cond, ...)                                                  \
    do {                                                                  \
        if (cond) {                                                       \
            check_passed++;                                               \
        } else {                                                          \
            check_failed++;                                               \
            fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);          \
            fprintf(stderr, __VA_ARGS__);                                 \
            fputc('\n', stderr);                                          \
        }                                                                 \
    } while (0)

/* |a - b| <= tol * max(|a|, |b|, floor): relative error with an absolute
 * floor so that values near zero are compared sensibly. */
static inline int check_close(double a, double b, double tol, double floor_) {
    double m = fabs(a) > fabs(b) ? fabs(a) : fabs(b);
    if (m < floor_) m = floor_;
    return isfinite(a) && isfinite(b) && fabs(a - b) <= tol * m;
}

static inline int check_summary(void) {
    printf("%d passed, %d failed\n", check_passed, check_failed);
    return check_failed ? 1 : 0;
}
#endif
