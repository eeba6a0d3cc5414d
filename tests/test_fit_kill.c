/* test_fit_kill.c: a kill -9 at a random moment of a fit never leaves a
 * corrupt checkpoint.
 *
 * A fit of a small synthetic scene checkpoints after every step
 * (--checkpoint-minutes 0.0001), so that a large share of its time is spent
 * writing checkpoints; it is killed with SIGKILL at random moments, from
 * before its first checkpoint to deep into the run, the new fit and the
 * resumed ones alike. After every kill, DIR/checkpoint.bin is either absent
 * or loads completely, and `fit --resume DIR` either continues from it (one
 * more step, exit 0) or says that there is no checkpoint (exit 1), and
 * removes the temporary file the kill left (its PID is dead). The moments
 * are printed, so a failure can be replayed.
 *
 * Other commands end on SIGTERM, removing their temporary files first; a
 * run writing into a directory removes stale temporaries of dead PIDs and
 * keeps those of live ones. */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "check.h"
#include "test_util.h"
#include "fit/checkpoint.h"

static char dir[300], ckpt[400];
static const char *bin, *tmp;

/* The last run's stderr is exactly `want`. */
static int stderr_is(const char *want) { return !strcmp(run_stderr(), want); }

/* The step the checkpoint on disk is at: -1 when there is none, -2 when it
 * does not load. */
static long checkpoint_step(void) {
    if (access(ckpt, F_OK) != 0) return -1;
    ws_fit_state s;
    ws_status st = {0};
    int argc;
    char **argv;
    if (ws_checkpoint_load(ckpt, &s, &argc, &argv, &st)) {
        fprintf(stderr, "%s\n", st.msg);
        return -2;
    }
    long step = s.global_step;
    ws_fit_state_free(&s);
    ws_checkpoint_free_args(argc, argv);
    return step;
}

/* Temporaries in dir: each is a checkpoint write a kill interrupted (never
 * read; the next run writing into dir removes them). */
static int temporaries(void) { return temporaries_in(dir, "checkpoint.bin"); }

/* Starts a fit of at most `steps` steps that checkpoints after every step
 * (resume: `fit --resume DIR`, which keeps the stored settings). Its
 * schedule (1000 epochs of 6 views x 5 steps) is longer than any fit here
 * runs, so a resume always has a next step, however fast the machine. */
static pid_t start_fit(int resume, const char *steps) {
    char scene[300];
    snprintf(scene, sizeof scene, "%s/scene", tmp);
    pid_t pid = fork();
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stderr)) _exit(126);
        if (resume)
            execl(bin, bin, "fit", "--resume", dir, "--max-steps", steps, (char *)NULL);
        else
            execl(bin, bin, "fit", scene, "--out", dir, "--size", "64", "--loss", "edges", "--length",
                  "0.3", "--epochs", "1000", "--threads", "1", "--quiet", "--checkpoint-minutes", "0.0001",
                  "--snapshot-every", "1", "--max-steps", steps, (char *)NULL);
        _exit(127);
    }
    return pid;
}

/* Starts a long fit, SIGKILLs it after `ms` milliseconds; returns 1 if it
 * was still running then. */
static int fit_and_kill(int resume, int ms) {
    pid_t pid = start_fit(resume, "100000");
    struct timespec wait = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&wait, NULL);
    kill(pid, SIGKILL);
    int status;
    waitpid(pid, &status, 0);
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

/* SIGTERM while an output is being written: render is stopped (SIGSTOP)
 * the moment one of its temporary files is seen in its output folder, and
 * if the file is still there once it stands still, it gets SIGTERM (and
 * SIGCONT). The handler removes the file, and the process ends by SIGTERM.
 * Views of 512 x 512 make each PNG's write long enough to be caught. */
static void test_sigterm_removes_temporaries(void) {
    char out[300], curves[300], scene[300];
    snprintf(out, sizeof out, "%s/render", tmp);
    snprintf(scene, sizeof scene, "%s/scene", tmp);
    snprintf(curves, sizeof curves, "%s/scene/gt_curves.json", tmp);
    int caught = 0, status = 0;
    for (int attempt = 0; attempt < 20 && !caught; attempt++) {
        mkdir(out, 0777);
        pid_t pid = fork();
        if (pid == 0) {
            int null = open("/dev/null", O_WRONLY);
            if (null < 0 || dup2(null, 1) < 0 || dup2(null, 2) < 0) _exit(126);
            execl(bin, bin, "render", curves, "--scene", scene, "--split", "train", "--out", out, "--size", "512",
                  (char *)NULL);
            _exit(127);
        }
        while (!caught && waitpid(pid, &status, WNOHANG) == 0) {
            if (temporaries_in(out, NULL) == 0) continue;
            kill(pid, SIGSTOP);
            waitpid(pid, &status, WUNTRACED);
            caught = temporaries_in(out, NULL) > 0;
            if (caught) kill(pid, SIGTERM);
            kill(pid, SIGCONT);
        }
        if (caught) waitpid(pid, &status, 0);
    }
    CHECK(caught, "render was never caught with a temporary file");
    CHECK(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM, "render did not end by SIGTERM");
    CHECK(temporaries_in(out, NULL) == 0, "SIGTERM left a temporary file in %s", out);
}

/* A run writing into a directory removes this program's temporary files
 * of a dead PID and keeps one of a live PID (this test's own). */
static void test_stale_temporaries(void) {
    char out[300], dead[400], live[400], args[1024];
    snprintf(out, sizeof out, "%s/export", tmp);
    mkdir(out, 0777);
    snprintf(dead, sizeof dead, "%s/.wiresketch.tmp.999999999.0.curves.obj", out);
    snprintf(live, sizeof live, "%s/.wiresketch.tmp.%ld.0.other.obj", out, (long)getpid());
    fclose(fopen(dead, "w"));
    fclose(fopen(live, "w"));
    snprintf(args, sizeof args, "export %s/scene/gt_curves.json --obj %s/curves.obj", tmp, out);
    CHECK(run("%s", args) == 0, "export failed");
    CHECK(access(dead, F_OK) != 0, "the stale temporary of a dead PID stayed");
    CHECK(access(live, F_OK) == 0, "the temporary of a live PID was removed");
}

int main(void) {
    bin = program_path();
    tmp = test_tmpdir("fit_kill");
    snprintf(dir, sizeof dir, "%s/fit", tmp);
    snprintf(ckpt, sizeof ckpt, "%s/checkpoint.bin", dir);
    char args[1024];
    snprintf(args, sizeof args,
             "scene trefoil --out %s/scene --size 64 --views-train 6 --views-val 1 --views-test 1", tmp);
    CHECK(run("%s", args) == 0, "scene generation failed");
    unsigned seed = (unsigned)time(NULL);
    srand(seed);
    int killed = 0, resumed = 0, none = 0, interrupted = 0;
    for (int round = 0; round < 10; round++) {
        /* rounds 0-2 start new fits and kill them early, often before their
         * first checkpoint; rounds 3-9 resume one and kill it anywhere */
        int fresh = round < 3;
        if (fresh) {
            remove_tree(dir);
            if (access(dir, F_OK) == 0) break;
        } else if (round == 3 && checkpoint_step() == -1) {
            int status;
            waitpid(start_fit(0, "1"), &status, 0);
            CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0, "the fit to resume from failed");
        }
        int ms = fresh ? rand() % 60 : 20 + rand() % 400;
        int before = temporaries();
        killed += fit_and_kill(!fresh, ms);
        interrupted += temporaries() - before;
        long step = checkpoint_step();
        CHECK(step != -2, "seed %u round %d: checkpoint corrupt after kill -9 at %d ms", seed, round, ms);
        CHECK(fresh || step >= 0, "seed %u round %d: the checkpoint vanished", seed, round);
        /* --resume continues from it for one step, or says there is none */
        snprintf(args, sizeof args, "fit --resume %s --max-steps %ld", dir, step + 1);
        int rc = run("%s", args);
        if (step == -1) {
            char want[600];
            snprintf(want, sizeof want, "wiresketch: %s: no checkpoint to resume from\n", ckpt);
            CHECK(rc == 1 && stderr_is(want), "seed %u round %d: no checkpoint, resume said otherwise",
                  seed, round);
            none++;
        } else if (step >= 0) {
            CHECK(rc == 0 && checkpoint_step() == step + 1,
                  "seed %u round %d: resume from step %ld failed (exit %d)", seed, round, step, rc);
            CHECK(temporaries() == 0, "seed %u round %d: the resumed run left stale temporaries", seed,
                  round);
            resumed++;
        }
    }
    test_sigterm_removes_temporaries();
    test_stale_temporaries();
    CHECK(killed >= 8, "only %d of 10 fits were still running when killed", killed);
    CHECK(resumed >= 7, "only %d rounds had a checkpoint to resume", resumed);
    printf("kill -9 at random moments (seed %u): %d killed, %d resumed, %d without checkpoint, %d "
           "checkpoint writes interrupted\n",
           seed, killed, resumed, none, interrupted);
    return check_summary();
}
