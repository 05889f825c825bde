/* progress.c - time, the progress bar of render and bake, and their
 * handling of SIGINT, SIGTERM and SIGHUP. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cli.h"

double sea_cli_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Width of the progress bar, characters. */
enum { PROGRESS_BAR = 30 };

int sea_cli_progress_bar(void *ctx, double fraction)
{
    sea_cli_progress *p = ctx;
    const double now = sea_cli_seconds();
    if (p->start <= 0.0)
        p->start = now;
    const double done = ((double)p->index + fmin(fmax(fraction, 0.0), 1.0)) / (double)p->count;
    const int pct = (int)floor(100.0 * done);
    if (pct == p->shown)
        return sea_cli_interrupted() != 0;
    p->shown = pct;
    char bar[PROGRESS_BAR + 1];
    const int full = (int)floor(PROGRESS_BAR * done);
    for (int i = 0; i < PROGRESS_BAR; ++i)
        bar[i] = i < full ? '#' : '.';
    bar[PROGRESS_BAR] = '\0';
    /* the time left, at the pace so far (blank until it means something;
     * the trailing blanks wipe a longer line drawn before) */
    char left[48] = "";
    const double elapsed = now - p->start;
    if (done >= 0.01 && done < 1.0 && elapsed >= 1.0) {
        const double rest = elapsed * (1.0 - done) / done;
        if (rest >= 3600.0)
            snprintf(left, sizeof left, ", %.0f h %02.0f min left", floor(rest / 3600.0),
                     floor(fmod(rest, 3600.0) / 60.0));
        else if (rest >= 60.0)
            snprintf(left, sizeof left, ", %.0f min %02.0f s left", floor(rest / 60.0),
                     floor(fmod(rest, 60.0)));
        else
            snprintf(left, sizeof left, ", %.0f s left", ceil(rest));
    }
    if (p->count > 1)
        fprintf(stderr, "\r%s: [%s] %3d%% frame %zu/%zu%s   ", p->what, bar, pct, p->index + 1,
                p->count, left);
    else
        fprintf(stderr, "\r%s: [%s] %3d%%%s   ", p->what, bar, pct, left);
    fflush(stderr);
    return sea_cli_interrupted() != 0;
}

int sea_cli_progress_if(sea_cli_progress *p, bool on, double fraction)
{
    return on ? sea_cli_progress_bar(p, fraction) : sea_cli_interrupted() != 0;
}

void sea_cli_progress_end(sea_cli_progress *p)
{
    if (p->shown >= 0)
        fputc('\n', stderr);
    p->shown = -1;
}

/* ---------------------------------------------------------------- signals */

static volatile sig_atomic_t caught = 0;
static const int SIGNALS[] = {SIGINT, SIGTERM, SIGHUP};
enum { N_SIGNALS = sizeof SIGNALS / sizeof SIGNALS[0] };
static struct sigaction saved[N_SIGNALS];
static int installed = 0;

static void on_signal(int sig)
{
    caught = sig;
}

void sea_cli_signals_catch(void)
{
    struct sigaction on;
    memset(&on, 0, sizeof on);
    on.sa_handler = on_signal;
    sigemptyset(&on.sa_mask);
    caught = 0;
    for (size_t i = 0; i < N_SIGNALS; i++) {
        /* a signal ignored on entry (nohup) stays ignored */
        sigaction(SIGNALS[i], NULL, &saved[i]);
        if (saved[i].sa_handler != SIG_IGN)
            sigaction(SIGNALS[i], &on, NULL);
    }
    installed = 1;
}

void sea_cli_signals_restore(void)
{
    if (!installed)
        return;
    for (size_t i = 0; i < N_SIGNALS; i++)
        sigaction(SIGNALS[i], &saved[i], NULL);
    installed = 0;
}

int sea_cli_interrupted(void)
{
    return caught;
}

void sea_cli_die_of_signal(const char *msg)
{
    const int sig = caught;
    sea_cli_signals_restore();
    fprintf(stderr, "seabake: error: %s\n", msg);
    fflush(stderr);
    if (sig != 0)
        raise(sig);
}
