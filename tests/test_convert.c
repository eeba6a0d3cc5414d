/* slow test */
/* test_convert.c: runs tools/test_convert.py, the checks of the weight
 * converter (tools/convert_weights.py: good inputs in every format, unknown
 * formats, hostile pickles, missing and mis-shaped tensors; deep JSON and
 * module nesting, a zip bomb, stride-0 views, damaged members, malformed or
 * overlapping safetensors entries, NaN, FIFOs, OUT onto IN, signals), and
 * counts each of its "ok NAME" / "FAIL NAME: detail" lines as one assertion.
 * The converter and its checks need python3 with the standard library only. */
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include "check.h"

/* tools/test_convert.py makes this many checks; fewer means it stopped early. */
enum { EXPECTED_CHECKS = 102 };

int main(void) {
    FILE *p = popen("python3 tools/test_convert.py 2>&1", "r");
    CHECK(p != NULL, "cannot run python3 tools/test_convert.py");
    if (!p) return check_summary();
    char line[4096];
    int seen = 0;
    while (fgets(line, sizeof line, p)) {
        line[strcspn(line, "\n")] = '\0';
        if (strncmp(line, "ok ", 3) == 0) {
            CHECK(1, "%s", line);
            seen++;
        } else if (strncmp(line, "FAIL ", 5) == 0) {
            CHECK(0, "tools/test_convert.py: %s", line);
            seen++;
        } else if (strcmp(line, "all checks passed") != 0) {
            fprintf(stderr, "%s\n", line); /* a traceback or a failure's detail */
        }
    }
    int status = pclose(p);
    CHECK(status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0,
          "tools/test_convert.py exited with status %d", status);
    CHECK(seen == EXPECTED_CHECKS, "tools/test_convert.py made %d checks, expected %d", seen, EXPECTED_CHECKS);
    return check_summary();
}
