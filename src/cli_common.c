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

sea_status sea_cli_scene_arg(const sea_cli_args *args, const char **path, sea_error *err)
{
    *path = sea_cli_args_get(args, "scene");
    if (*path == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "missing SCENE.ini (the scene file, seabake-scene(5))");
    if ((*path)[0] == '\0')
        return sea_fail(err, SEA_ERR_PARSE, "empty scene file name");
    return SEA_OK;
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

sea_status sea_cli_opt_frames(const sea_cli_args *args, bool *framed, long *a, long *b,
                              double *rate, sea_error *err)
{
    static const sea_cli_range RATE = {0.0, INFINITY, true, true, "Hz"};
    const char *frames = sea_cli_args_get(args, "frames");
    sea_status st;
    *framed = frames != NULL;
    *a = *b = 0;
    if (*framed && (st = sea_cli_parse_frames(frames, a, b, err)) != SEA_OK)
        return st;
    const char *text = sea_cli_args_get(args, "frame-rate");
    *rate = SEA_CLI_FRAME_RATE_DEFAULT;
    if (text == NULL)
        return SEA_OK;
    if (!*framed)
        return sea_fail(err, SEA_ERR_DOMAIN, "--frame-rate applies only with --frames");
    return sea_cli_parse_number("--frame-rate", text, &RATE, rate, err);
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

/* Wavelengths listed by --explain before "...". */
enum { EXPLAIN_SAMPLES = 16 };

/* --explain of render and bake: what sea_render_prepare chose, and why. */
void sea_cli_explain(const char *what, const char *scene_path, const sea_render *r)
{
    const sea_scene *sc = sea_render_scene(r);
    const sea_clip_level *lv;
    const size_t n = sea_render_levels(r, &lv);
    const size_t npix = (size_t)sc->width * (size_t)sc->height;
    size_t sea_pixels = 0;
    for (size_t i = 0; i < n; ++i)
        sea_pixels += lv[i].pixels;
    fprintf(stderr,
            "%s: %s: %d x %d pixels, %zu sea and %zu sky; %zu clipmap level%s of facets "
            "%g m x 2^l (grid %d, tolerance %g, method %s):\n", what,
            scene_path, sc->width, sc->height, sea_pixels, npix - sea_pixels, n,
            n == 1 ? "" : "s", sc->finest, sc->grid, sc->tolerance,
            sea_facet_method_name((sea_facet_method)sc->method));
    for (size_t i = 0; i < n; ++i) {
        const sea_clip_level *l = &lv[i];
        if (l->low_res)
            fprintf(stderr,
                    "  level %2d: %.10g m, low-resolution (m = 0, C = C_LR, no facets), generated "
                    "share %.3g, %zu pixels\n",
                    l->level, l->facet, l->generated_share, l->pixels);
        else
            fprintf(stderr,
                    "  level %2d: %.10g m, window %zu x %zu facets from (%ld, %ld) = (%g m, %g m), "
                    "generated share %.3g, %zu pixels, sub-facets 2^%d x 2^%d%s\n",
                    l->level, l->facet, l->nx, l->ny, l->i0, l->j0, (double)l->i0 * l->facet,
                    (double)l->j0 * l->facet, l->generated_share, l->pixels, l->sub_n, l->sub_n,
                    l->sub_skipped ? " (skipped)" : "");
    }
    /* Sub-facets: what each level resolves, and which the tolerance skipped. */
    for (size_t i = 0; i < n; ++i) {
        const sea_clip_level *l = &lv[i];
        if (l->low_res || (l->sub_n == 0 && !l->sub_skipped))
            continue;
        const int want = l->sub_skipped ? (sc->n < l->level ? sc->n : l->level) : l->sub_n;
        fprintf(stderr,
                "  level %2d: sub-facets of %g m resolve %.3g of the slope variance: %s\n",
                l->level, l->facet / (double)(1L << want), l->sub_share,
                l->sub_skipped ? "skipped, less than the tolerance (n = 0)"
                               : "computed, at least the tolerance");
    }
    /* The first low-resolution level is the end of every pixel's chain. */
    for (size_t i = 0; i < n; ++i) {
        if (!lv[i].low_res)
            continue;
        fprintf(stderr,
                "  levels from %g m are low-resolution: the waves longer than 2 x %g m carry "
                "%.3g of the slope variance, less than the tolerance %g\n",
                lv[i].facet, lv[i].facet, lv[i].generated_share, sc->tolerance);
        break;
    }
    fprintf(stderr,
            "  a pixel of footprint F reads level round(log2(F / %g m)), or a coarser one outside "
            "that level's window; \"pixels\" counts the pixels whose footprint chose it\n",
            sc->finest);
    /* The fallbacks of seabake(1), LIMITS AND FALLBACKS, that this scene takes. */
    sea_spectrum sp;
    if (sea_spectrum_init(&sp, sc->wind_speed, sc->fetch, sc->wind_dir, NULL) == SEA_OK &&
        sea_spectrum_alpha_m_continued(&sp))
        fprintf(stderr,
                "%s: fallback: at %g m/s u*/c_m is below exp(-0.9): the short-wave "
                "alpha_m = %.3g comes from the positive low-wind continuation, not Elfouhaily's "
                "1e-2 (1 + ln(u*/c_m)) (seabake(1), LIMITS AND FALLBACKS)\n", what,
                sc->wind_speed, sp.alpha_m);
    if (sc->sun_zenith >= M_PI / 2.0)
        fprintf(stderr,
                "%s: fallback: the sun (zenith %g deg) is below the horizon%s: no sun term, "
                "as with irradiance 0\n", what,
                sc->sun_zenith * 180.0 / M_PI,
                sc->earth == SEA_EARTH_SPHERICAL ? " at the nadir point" : "");
    if (sc->windows == SEA_WINDOWS_CLIPMAP)
        fprintf(stderr, "  windows = clipmap: every high-resolution level is %d x %d facets "
                        "around the point the optical axis meets, whether pixels read it or not\n",
                sc->grid, sc->grid);
    const sea_render_choices ch = sea_render_choices_of(r);
    if (sc->emissivity_method == SEA_EMIS_AUTO)
        fprintf(stderr,
                "%s: emissivity: auto rule, orders x %g (%s): n_gl = ceil(%g (16 + 12 s_X)), "
                "n_gh = ceil(%g (2 + 6 s + 16 s^2))\n", what,
                ch.emis_scale,
                ch.emis_scale < 1.0 ? "scaled down: the tolerance allows an emissivity error "
                                      "of a tenth of it"
                                    : "the full rule, about 1e-5",
                ch.emis_scale, ch.emis_scale);
    else
        fprintf(stderr, "%s: emissivity: %s (not scaled by the tolerance)\n", what,
                sea_emis_method_name((sea_emis_method)sc->emissivity_method));
    if (ch.wave_count == 0)
        fprintf(stderr, "%s: waves: none (every level is low-resolution)\n", what);
    else if (ch.directions > 0)
        fprintf(stderr,
                "%s: waves: %zu sinusoids, %d bins per octave x %d directions%s\n", what,
                ch.wave_count, ch.bins_per_octave, ch.directions,
                ch.directions < 32 ? " (fewer directions: the tolerance allows a noisier "
                                     "windowed slope variance)"
                                   : "");
    else
        fprintf(stderr, "%s: waves: %zu FFT modes (not thinned by the tolerance)\n", what,
                ch.wave_count);
    const double *wl, *wt;
    const size_t k = sea_render_samples(r, &wl, &wt);
    if (sc->wavelength > 0.0) {
        fprintf(stderr, "%s: 1 spectral sample, at %g um\n", what, wl[0] * 1e6);
        return;
    }
    fprintf(stderr, "%s: %zu spectral sample%s over %g-%g um (%s, %s response):", what, k,
            k == 1 ? "" : "s", sc->band_min * 1e6, sc->band_max * 1e6,
            sc->band_samples > 0 ? "samples in the scene" : "chosen by the tolerance",
            sc->response_file[0] ? "the file's" : "flat");
    for (size_t i = 0; i < k && i < EXPLAIN_SAMPLES; ++i)
        fprintf(stderr, "%s%.4g", i ? ", " : " ", wl[i] * 1e6);
    fprintf(stderr, "%s um\n", k > EXPLAIN_SAMPLES ? ", ..." : "");
}

FILE *sea_cli_gnuplot_begin(sea_cli_script *s, int width, int height)
{
    s->text = NULL;
    s->len = 0;
    FILE *f = s->f = open_memstream(&s->text, &s->len);
    if (f == NULL)
        return NULL;
    fprintf(f,
            "set encoding utf8\n"
            "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
            "  set terminal pngcairo size %d,%d font 'sans,10'\n"
            "} else {\n"
            "  set terminal png size %d,%d\n"
            "}\n",
            width, height, width, height);
    return f;
}

char *sea_cli_gnuplot_end(sea_cli_script *s)
{
    if (fclose(s->f) != 0) {
        free(s->text);
        return NULL;
    }
    return s->text;
}
