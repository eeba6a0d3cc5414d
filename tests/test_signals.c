/* test_signals.c: how runs end when the world around them fails.
 *
 * - stdout into a full disk (/dev/full) or closed (`>&-`): every command
 *   that prints exits 1 with one line, never 0 having written nothing.
 * - A fit stopped by SIGHUP, SIGTERM, SIGXCPU, by the file size limit
 *   (SIGXFSZ) or by a progress pipe whose reader is gone ends like Ctrl-C:
 *   one line, exit 128 + the signal, its checkpoint loading and its outputs
 *   written where they fit, no temporary file left.
 * - render, export and scene past the file size limit: exit 1, the file
 *   named, no temporary file left.
 *
 * The harness that runs the tests may ignore SIGXFSZ and SIGPIPE (an
 * ignored signal stays ignored across exec), which would hide what a
 * user's shell sees: every child here gets them back at their defaults. */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "fit/checkpoint.h"

static char scene[300];
static const char *bin, *tmp;

/* Where a child's stdout goes: a path, or closed. */
#define CLOSED NULL

/* Starts bin with the words of `args` (split on spaces), stdout to
 * `out` (or closed), stderr to err_fd, at most fsize_kib KiB per file
 * (0: no limit). */
static pid_t start(const char *args, const char *out, int err_fd, long fsize_kib) {
    char copy[2048], *argv[64];
    int n = 0;
    snprintf(copy, sizeof copy, "%s", args);
    argv[n++] = (char *)bin;
    for (char *w = strtok(copy, " "); w && n < 63; w = strtok(NULL, " ")) argv[n++] = w;
    argv[n] = NULL;
    pid_t pid = fork();
    if (pid == 0) {
        signal(SIGXFSZ, SIG_DFL);
        signal(SIGPIPE, SIG_DFL);
        if (fsize_kib > 0) {
            struct rlimit lim = {(rlim_t)fsize_kib * 1024, (rlim_t)fsize_kib * 1024};
            if (setrlimit(RLIMIT_FSIZE, &lim) != 0) _exit(126);
        }
        if (dup2(err_fd, 2) < 0) _exit(126);
        if (out) {
            int fd = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd < 0 || dup2(fd, 1) < 0) _exit(126);
            close(fd);
        } else {
            close(1);
        }
        execv(bin, argv);
        _exit(127);
    }
    return pid;
}

/* The exit code, or 1000 + the signal that ended the process. */
static int finish(pid_t pid) {
    int status;
    if (waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

static char err_path[300];

/* Runs args to its end; stderr into err_path. */
static int run_to_end(const char *args, const char *out, long fsize_kib) {
    int fd = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int rc = finish(start(args, out, fd, fsize_kib));
    close(fd);
    return rc;
}

static int stderr_is(const char *want) {
    char got[4096];
    read_text(err_path, got, sizeof got);
    if (strcmp(got, want)) fprintf(stderr, "stderr: %s", got);
    return !strcmp(got, want);
}

/* Files named NAME.tmp.PID anywhere below dir. */
static int temporaries(const char *dir) {
    char cmd[600];
    int n = 0;
    snprintf(cmd, sizeof cmd, "find %s -name '*.tmp.*' 2>/dev/null | wc -l", dir);
    FILE *p = popen(cmd, "r");
    if (p) {
        if (fscanf(p, "%d", &n) != 1) n = -1;
        pclose(p);
    }
    return n;
}

static int exists(const char *dir, const char *name) {
    char path[600];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, F_OK) == 0;
}

/* The step of dir's checkpoint; -1 when it does not load. */
static long checkpoint_step(const char *dir) {
    char path[600];
    snprintf(path, sizeof path, "%s/checkpoint.bin", dir);
    ws_fit_state s;
    ws_status st = {0};
    int argc;
    char **argv;
    if (ws_checkpoint_load(path, &s, &argc, &argv, &st)) return -1;
    long step = s.global_step;
    ws_fit_state_free(&s);
    ws_checkpoint_free_args(argc, argv);
    return step;
}

static void test_stdout(void) {
    char image[400], tiny[] = "tests/fuzz/corpus/weights/tiny_f32.bin";
    snprintf(image, sizeof image, "%s/rgb/train/r_0.png", scene);
    char lines[7][1024];
    snprintf(lines[0], sizeof lines[0], "--help");
    snprintf(lines[1], sizeof lines[1], "fit --help");
    snprintf(lines[2], sizeof lines[2], "scene trefoil --out %s/s --size 16 --views-train 2 --views-val 1 --views-test 1", tmp);
    snprintf(lines[3], sizeof lines[3], "eval %s --curves %s/gt_curves.json --loss edges --threads 1 --size 64", scene,
             scene);
    snprintf(lines[4], sizeof lines[4], "rank %s --loss edges --threads 1", scene);
    snprintf(lines[5], sizeof lines[5], "embed --weights %s %s", tiny, image);
    snprintf(lines[6], sizeof lines[6], "check %s", scene);
    for (int k = 0; k < 7; k++) {
        int rc = run_to_end(lines[k], "/dev/full", 0);
        CHECK(rc == 1 && stderr_is("wiresketch: standard output: write failed: No space left on device\n"),
              "`%s >/dev/full`: exit %d", lines[k], rc);
        rc = run_to_end(lines[k], CLOSED, 0);
        CHECK(rc == 1 && stderr_is("wiresketch: standard output: write failed: Bad file descriptor\n"),
              "`%s >&-`: exit %d", lines[k], rc);
    }
    /* a closed stdout's number is not handed to an output file */
    char png[400];
    snprintf(png, sizeof png, "%s/s/rgb/train/r_0.png", tmp);
    char head[8] = "";
    read_text(png, head, sizeof head);
    CHECK(!memcmp(head, "\x89PNG", 4), "%s is not a PNG after a run with stdout closed", png);
}

/* A fit of the small scene that checkpoints every step and would run long. */
static const char *fit_args(char *buf, size_t size, const char *out, int quiet) {
    snprintf(buf, size,
             "fit %s --out %s --size 64 --loss edges --length 0.3 --epochs 1000 --threads 1 "
             "--checkpoint-minutes 0.0001 --max-steps 100000%s",
             scene, out, quiet ? " --quiet" : "");
    return buf;
}

/* Starts a fit, sends sig once its first checkpoint is there and a few
 * steps ran; the run ends with 128 + sig, its line, whole outputs and a
 * checkpoint that loads. */
static void test_fit_signal(int sig, const char *name) {
    char out[300], args[1024], ckpt[400], want[1024];
    snprintf(out, sizeof out, "%s/fit_%d", tmp, sig);
    snprintf(ckpt, sizeof ckpt, "%s/checkpoint.bin", out);
    int fd = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = start(fit_args(args, sizeof args, out, 1), "/dev/null", fd, 0);
    close(fd);
    /* a checkpoint after a step (the first is written before the fit times its steps) */
    for (int i = 0; i < 3000 && checkpoint_step(out) <= 0; i++) usleep(10000);
    kill(pid, sig);
    int rc = finish(pid);
    CHECK(rc == 128 + sig, "fit stopped by %s: exit %d", name, rc);
    snprintf(want, sizeof want,
             "wiresketch: stopped by %s; outputs and checkpoint written to %s; continue with "
             "`wiresketch fit --resume %s`\n",
             name, out, out);
    CHECK(stderr_is(want), "fit stopped by %s: not its line", name);
    CHECK(exists(out, "report.html") && exists(out, "curves.json") && exists(out, "log.csv"),
          "fit stopped by %s: outputs missing", name);
    long step = checkpoint_step(out);
    CHECK(step > 0 && step < 100000, "fit stopped by %s: checkpoint at step %ld", name, step);
    CHECK(temporaries(out) == 0, "fit stopped by %s left temporaries", name);
}

/* stderr is a pipe nobody reads: the first progress line fails (EPIPE),
 * the run stops as if by SIGPIPE (141) with its outputs written instead of
 * dying by it with nothing. */
static void test_fit_broken_pipe(void) {
    char out[300], args[1024];
    snprintf(out, sizeof out, "%s/fit_pipe", tmp);
    int p[2];
    if (pipe(p) != 0) return;
    close(p[0]);
    pid_t pid = start(fit_args(args, sizeof args, out, 0), "/dev/null", p[1], 0);
    close(p[1]);
    int rc = finish(pid);
    CHECK(rc == 128 + SIGPIPE, "fit with a broken progress pipe: exit %d", rc);
    CHECK(exists(out, "report.html") && exists(out, "curves.json") && checkpoint_step(out) > 0,
          "fit with a broken progress pipe: outputs or checkpoint missing");
    CHECK(temporaries(out) == 0, "fit with a broken progress pipe left temporaries");
}

/* ulimit -f 60 (KiB): the checkpoint, written every step, grows past it
 * (its log and snapshots grow). The fit stops like on SIGINT; the outputs
 * that fit are written, the checkpoint that does not is named; the last one
 * that did stays whole and resumes. */
static void test_fit_file_limit(void) {
    char out[300], args[1024], want[2048];
    snprintf(out, sizeof out, "%s/fit_fsize", tmp);
    int rc = run_to_end(fit_args(args, sizeof args, out, 1), "/dev/null", 60);
    CHECK(rc == 128 + SIGXFSZ, "fit past the file size limit: exit %d", rc);
    snprintf(want, sizeof want,
             "wiresketch: stopped by SIGXFSZ (the file size limit, ulimit -f); %s/checkpoint.bin: write "
             "failed: File too large; what could be written is in %s; continue with `wiresketch fit "
             "--resume %s`\n",
             out, out, out);
    CHECK(stderr_is(want), "fit past the file size limit: not its line");
    CHECK(exists(out, "curves.json") && exists(out, "metrics.json"), "fit past the file size limit: no outputs");
    CHECK(checkpoint_step(out) > 0, "fit past the file size limit: the last checkpoint does not load");
    CHECK(temporaries(out) == 0, "fit past the file size limit left temporaries");
}

/* render, export and scene past ulimit -f 4 (KiB): exit 1 naming the file,
 * rather than killed by SIGXFSZ with a temporary left. */
static void test_file_limit(void) {
    char args[2048], want[1024], dir[300];
    snprintf(dir, sizeof dir, "%s/limit", tmp);
    mkdir(dir, 0777);
    snprintf(args, sizeof args, "scene trefoil --out %s/s --size 128 --views-train 2 --views-val 1 --views-test 1", dir);
    int rc = run_to_end(args, "/dev/null", 4);
    snprintf(want, sizeof want, "wiresketch: %s/s/rgb/train/r_0.png: write failed: File too large\n", dir);
    CHECK(rc == 1 && stderr_is(want), "scene past the file size limit: exit %d", rc);
    snprintf(args, sizeof args, "render %s/gt_curves.json --scene %s --out %s/r --size 256", scene, scene, dir);
    rc = run_to_end(args, "/dev/null", 4);
    snprintf(want, sizeof want, "wiresketch: %s/r/r_0.png: write failed: File too large\n", dir);
    CHECK(rc == 1 && stderr_is(want), "render past the file size limit: exit %d", rc);
    snprintf(args, sizeof args, "export %s/gt_curves.json --obj %s/c.obj", scene, dir);
    rc = run_to_end(args, "/dev/null", 4);
    snprintf(want, sizeof want, "wiresketch: %s/c.obj: write failed: File too large\n", dir);
    CHECK(rc == 1 && stderr_is(want), "export past the file size limit: exit %d", rc);
    CHECK(temporaries(dir) == 0, "a run past the file size limit left temporaries");
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("signals");
    snprintf(err_path, sizeof err_path, "%s/stderr.txt", tmp);
    snprintf(scene, sizeof scene, "%s/scene", tmp);
    char args[1024];
    snprintf(args, sizeof args, "scene trefoil --out %s --size 64 --views-train 6 --views-val 1 --views-test 1", scene);
    CHECK(run_to_end(args, "/dev/null", 0) == 0, "scene generation failed");
    test_stdout();
    test_fit_signal(SIGHUP, "SIGHUP");
    test_fit_signal(SIGTERM, "SIGTERM");
    test_fit_signal(SIGXCPU, "SIGXCPU (the CPU time limit, ulimit -t)");
    test_fit_broken_pipe();
    test_fit_file_limit();
    test_file_limit();
    return check_summary();
}
