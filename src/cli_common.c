/* cli_common.c - helpers shared by the subcommands: optional and required
 * options, integers, frame ranges, file names, output directories, time. */
#ifdef HAVE_CONFIG_H
#include <config.h>
#endif

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"

/* Option names in the tables carry no dashes; messages show "--name". */
static const char *dashed(const char *name, char *buf, size_t size)
{
    snprintf(buf, size, "--%s", name);
    return buf;
}

bool sea_cli_given(const sea_cli_args *args, const char *name)
{
    return sea_cli_args_get(args, name) != NULL;
}

sea_status sea_cli_require(const sea_cli_args *args, const char *name, const char *why,
                           sea_error *err)
{
    if (sea_cli_given(args, name))
        return SEA_OK;
    return sea_fail(err, SEA_ERR_DOMAIN, "missing --%s%s", name, why ? why : "");
}

sea_status sea_cli_opt_number(const sea_cli_args *args, const char *name,
                              const sea_cli_range *range, double def, double *out, sea_error *err)
{
    char opt[48];
    const char *text = sea_cli_args_get(args, name);
    if (!text) {
        *out = def;
        return SEA_OK;
    }
    return sea_cli_parse_number(dashed(name, opt, sizeof opt), text, range, out, err);
}

/* The range of [model] tolerance in scene.c. */
static const sea_cli_range SEA_CLI_RANGE_SCENE_TOL = {0.0, 0.1, true, false, ""};

sea_status sea_cli_opt_tolerance(const sea_cli_args *args, double *out, sea_error *err)
{
    return sea_cli_opt_number(args, "tolerance", &SEA_CLI_RANGE_SCENE_TOL, NAN, out, err);
}

void sea_cli_apply_tolerance(double tolerance, sea_scene *sc)
{
    if (!isnan(tolerance))
        sc->tolerance = tolerance;
}

sea_status sea_cli_opt_list(const sea_cli_args *args, const char *name, const sea_cli_range *range,
                            const char *def, sea_cli_list *out, sea_error *err)
{
    char opt[48];
    const char *text = sea_cli_args_get(args, name);
    return sea_cli_parse_list(dashed(name, opt, sizeof opt), text ? text : def, range, out, err);
}

sea_status sea_cli_opt_integer(const sea_cli_args *args, const char *name, long lo, long hi,
                               long def, long *out, sea_error *err)
{
    const char *text = sea_cli_args_get(args, name);
    if (!text) {
        *out = def;
        return SEA_OK;
    }
    char opt[48];
    const sea_cli_range range = {(double)lo, (double)hi, false, false, ""};
    double v;
    sea_status st = sea_cli_parse_number(dashed(name, opt, sizeof opt), text, &range, &v, err);
    if (st != SEA_OK)
        return st;
    if (v != floor(v))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: %s is not an integer", opt, text);
    *out = (long)v;
    return SEA_OK;
}

sea_status sea_cli_parse_frames(const char *text, long *a, long *b, sea_error *err)
{
    static const sea_cli_range frame = {0.0, SEA_CLI_FRAME_MAX, false, false, ""};
    const char *colon = strchr(text, ':');
    char first[64];
    if (colon == NULL || strchr(colon + 1, ':') != NULL || (size_t)(colon - text) >= sizeof first)
        return sea_fail(err, SEA_ERR_PARSE, "--frames: expected A:B (two frame numbers), got '%s'",
                        text);
    memcpy(first, text, (size_t)(colon - text));
    first[colon - text] = '\0';
    double va, vb;
    sea_status st = sea_cli_parse_number("--frames", first, &frame, &va, err);
    if (st == SEA_OK)
        st = sea_cli_parse_number("--frames", colon + 1, &frame, &vb, err);
    if (st != SEA_OK)
        return st;
    if (va != floor(va) || vb != floor(vb))
        return sea_fail(err, SEA_ERR_DOMAIN, "--frames: '%s' must hold integers", text);
    if (va > vb)
        return sea_fail(err, SEA_ERR_DOMAIN, "--frames: '%s' runs backwards (A:B needs A <= B)",
                        text);
    if (vb - va + 1.0 > SEA_CLI_FRAMES_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "--frames: '%s' has %.0f frames, more than %d", text,
                        vb - va + 1.0, SEA_CLI_FRAMES_MAX);
    *a = (long)va;
    *b = (long)vb;
    return SEA_OK;
}

bool sea_cli_has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n > m && strcasecmp(s + n - m, suffix) == 0;
}

char *sea_cli_path_join(const char *dir, const char *name)
{
    const size_t len = strlen(dir) + strlen(name) + 2;
    char *p = malloc(len);
    if (p != NULL)
        snprintf(p, len, "%s/%s", dir, name);
    return p;
}

sea_status sea_cli_check_parent_writable(const char *opt, const char *path, sea_error *err)
{
    const char *slash = strrchr(path, '/');
    char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
    if (dir == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_status st = SEA_OK;
    if (access(dir, W_OK | X_OK) != 0)
        st = sea_fail(err, SEA_ERR_IO, "%s: cannot write into directory '%s': %s", opt, dir,
                      strerror(errno));
    free(dir);
    return st;
}

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
