/* cmd_bench_memory.c: `wiresketch bench memory`: the peak resident memory
 * of a default fit, measured as a child process (`fit --max-steps 5` with
 * the random-weight files, f32 and f16) by the kernel's account of it
 * (wait4's ru_maxrss). */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include "base/paths.h"
#include "cli/cli_bench.h"

/* Runs `exe fit scene --out dir/fit ...` with weights; *kb its peak RSS. */
static int child_fit(const ws_cli_bench *ctx, const char *weights, const char *dir, long *kb,
                     ws_status *st) {
    char out[WS_PATH_MAX], log[WS_PATH_MAX];
    snprintf(out, sizeof out, "%s/fit", dir);
    snprintf(log, sizeof log, "%s/stderr.txt", dir);
    char *argv[] = {(char *)ctx->exe, "fit", (char *)ctx->scene_dir, "--out", out, "--weights",
                    (char *)weights, "--max-steps", "5", "--eval-every", "0", "--quiet", NULL};
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) return ws_fail(st, WS_EIO, "bench memory: cannot fork");
    if (pid == 0) {
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644), null = open("/dev/null", O_WRONLY);
        if (fd >= 0) dup2(fd, 2);
        if (null >= 0) dup2(null, 1);
        execv(ctx->exe, argv);
        _exit(127);
    }
    int status;
    struct rusage ru;
    if (wait4(pid, &status, 0, &ru) != pid) return ws_fail(st, WS_EIO, "bench memory: lost the child fit");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        char last[512] = "";
        FILE *f = fopen(log, "r");
        while (f && fgets(last, sizeof last, f)) continue;
        if (f) fclose(f);
        last[strcspn(last, "\n")] = '\0';
        return ws_fail(st, WS_EINPUT, "bench memory: the fit with %s failed: %s", weights, last);
    }
    *kb = ru.ru_maxrss;
    return WS_OK;
}

int ws_cli_bench_memory(ws_cli_bench *ctx, cJSON *out, ws_status *st) {
    const char *files[2] = {ctx->weights_f32, ctx->weights_f16}, *names[2] = {"f32", "f16"};
    cJSON *j = cJSON_AddObjectToObject(out, "memory");
    if (!ctx->json) printf("\n## Peak memory of a default fit\n\n");
    for (int k = 0; k < 2; k++) {
        if (access(files[k], R_OK) != 0) {
            if (!ctx->json) printf("(%s: no file; `make bench` makes it)\n", files[k]);
            continue;
        }
        char dir[] = "/tmp/ws_bench_XXXXXX", cmd[64];
        if (!mkdtemp(dir)) return ws_fail(st, WS_EIO, "bench memory: cannot make a temporary directory");
        long kb = 0;
        int rc = child_fit(ctx, files[k], dir, &kb, st);
        snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
        if (system(cmd) != 0 && !rc) rc = ws_fail(st, WS_EIO, "bench memory: cannot remove %s", dir);
        if (rc) return rc;
        ws_cli_bench_add(j, names[k], 1024.0 * kb);
        if (!ctx->json)
            printf("- `fit %s --weights %s --max-steps 5`: peak resident memory **%.0f MB** (%.2f GiB)\n",
                   ctx->scene_dir, files[k], kb * 1024 / 1e6, kb / 1048576.0);
    }
    return WS_OK;
}
