/* progress.c - time and the progress bar of render and bake. */
#include <math.h>
#include <stdio.h>
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
    const double done = ((double)p->index + fmin(fmax(fraction, 0.0), 1.0)) / (double)p->count;
    const int pct = (int)floor(100.0 * done);
    if (pct == p->shown)
        return 0;
    p->shown = pct;
    char bar[PROGRESS_BAR + 1];
    const int full = (int)floor(PROGRESS_BAR * done);
    for (int i = 0; i < PROGRESS_BAR; ++i)
        bar[i] = i < full ? '#' : '.';
    bar[PROGRESS_BAR] = '\0';
    if (p->count > 1)
        fprintf(stderr, "\r%s: [%s] %3d%% frame %zu/%zu", p->what, bar, pct, p->index + 1,
                p->count);
    else
        fprintf(stderr, "\r%s: [%s] %3d%%", p->what, bar, pct);
    fflush(stderr);
    return 0;
}
