/* options.c - the accessors of options (given, required, number, list,
 * integer, frames, tolerance, scene) and the ranges and option helpers that
 * several subcommands share (seed, facet method, sea state, threads, EXR
 * format, the scene file with --set), on top of args.c's scanning and
 * parsing.  Every failure leaves a one-line message naming the option, the
 * text the user gave and what would have been accepted. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli.h"

/* ------------------------------------------------------------- accessors */

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

sea_status sea_cli_opt_model(const sea_cli_args *args, sea_cli_model *out, sea_error *err)
{
    sea_status st =
        sea_cli_opt_number(args, "tolerance", &SEA_CLI_RANGE_SCENE_TOL, NAN, &out->tolerance, err);
    if (st == SEA_OK)
        st = sea_cli_opt_reflections(args, -1, &out->reflections, err);
    out->reference = sea_cli_given(args, "reference");
    out->shadowing = -1;
    if (st == SEA_OK && sea_cli_args_get(args, "shadowing") != NULL) {
        sea_shadowing s;
        st = sea_cli_opt_shadowing(args, SEA_SHADOW_CORRELATED, &s, err);
        out->shadowing = (int)s;
    }
    if (st == SEA_OK)
        st = sea_cli_opt_integer(args, "scales", 1, 2, 0, &out->scales, err);
    out->emissivity = -1;
    if (st == SEA_OK && sea_cli_args_get(args, "emissivity") != NULL) {
        sea_emis_method e = SEA_EMIS_AUTO;
        st = sea_cli_opt_emissivity(args, &e, err);
        out->emissivity = (int)e;
    }
    return st;
}

sea_status sea_cli_opt_reflections(const sea_cli_args *args, long def, long *out, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "reflections");
    *out = def;
    if (text == NULL)
        return SEA_OK;
    const int r = sea_reflections_from_name(text);
    if (r < 0)
        return sea_fail(err, SEA_ERR_PARSE,
                        "--reflections: '%s' is not a number of surface hits (allowed: auto, 1, "
                        "2, 3)",
                        text);
    *out = r;
    return SEA_OK;
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

void sea_cli_apply_model(const sea_cli_model *m, sea_scene *sc)
{
    if (!isnan(m->tolerance))
        sc->tolerance = m->tolerance;
    if (m->reflections >= 0)
        sc->reflections = (int)m->reflections;
    if (m->reference)
        sc->reference = 1;
    if (m->shadowing >= 0)
        sc->shadowing = m->shadowing;
    if (m->scales > 0)
        sc->scales = (int)m->scales;
    if (m->emissivity >= 0)
        sc->emissivity_method = (sea_emis_method)m->emissivity;
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

sea_status sea_cli_check_frame_times(double time, bool framed, long a, long b, double rate,
                                     sea_error *err)
{
    if (!framed)
        return SEA_OK;
    /* time + f / rate runs monotonically from frame a to frame b */
    const long ends[2] = {a, b};
    for (int i = 0; i < 2; ++i) {
        const double t = time + (double)ends[i] / rate;
        if (!(fabs(t) <= SEA_TIME_MAX))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "--frames %ld:%ld at --frame-rate %g Hz: frame %ld falls at %g s, "
                            "outside [%.10g, %.10g] s (allowed: a rate and frames that keep every "
                            "frame's time, [sea] time + frame / rate, in that range)",
                            a, b, rate, ends[i], t, -SEA_TIME_MAX, SEA_TIME_MAX);
    }
    return SEA_OK;
}

/* ------------------------------------------------- shared ranges, helpers */

const sea_cli_range SEA_CLI_RANGE_WIND = {SEA_WIND_MIN, SEA_WIND_MAX, false, false, "m/s"};
const sea_cli_range SEA_CLI_RANGE_FETCH = {SEA_FETCH_MIN, INFINITY, false, false, "m"};
const sea_cli_range SEA_CLI_RANGE_AZIMUTH = {-INFINITY, INFINITY, true, true, "degrees"};
/* Largest facet size: far beyond the size at which the high-resolution
 * statistics have converged to the low-resolution ones (seabake-model(7)). */
#define SEA_CLI_FACET_MAX 1e6
const sea_cli_range SEA_CLI_RANGE_FACET = {0.0, SEA_CLI_FACET_MAX, false, false, "m"};
/* A THETA,PHI pair: signed zenith and azimuth. */
const sea_cli_range SEA_CLI_RANGE_DIRECTION[2] = {
    {-90.0, 90.0, true, true, "degrees"},
    {-INFINITY, INFINITY, true, true, "degrees"}};

/* --seed: a decimal unsigned integer, read exactly (not through a double). */
sea_status sea_cli_opt_seed(const sea_cli_args *args, unsigned long *out, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "seed");
    if (!text) {
        *out = 1;
        return SEA_OK;
    }
    size_t len = strlen(text);
    if (len == 0 || strspn(text, "0123456789") != len)
        return sea_fail(err, SEA_ERR_PARSE, "--seed: '%s' is not an unsigned integer", text);
    errno = 0;
    unsigned long v = strtoul(text, NULL, 10);
    if (errno == ERANGE)
        return sea_fail(err, SEA_ERR_DOMAIN, "--seed: %s is outside [0, %lu]", text, ULONG_MAX);
    *out = v;
    return SEA_OK;
}

/* --method (default variable-step) and --n, which only variable-step-2n
 * takes and requires. */
sea_status sea_cli_opt_facet_method(const sea_cli_args *args, sea_facet_method *method, int *n,
                                    sea_error *err)
{
    const char *text = sea_cli_args_get(args, "method");
    int m = sea_facet_method_from_name(text ? text : "variable-step");
    if (m < 0)
        return sea_fail(err, SEA_ERR_PARSE,
                        "--method: '%s' is not one of variable-step, variable-step-2n, one-meter",
                        text);
    *method = (sea_facet_method)m;
    *n = 0;
    if (*method != SEA_METHOD_VARIABLE_STEP_2N) {
        if (sea_cli_given(args, "n"))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "--n applies only to --method variable-step-2n, not %s",
                            sea_facet_method_name(*method));
        return SEA_OK;
    }
    long v;
    sea_status st =
        sea_cli_require(args, "n", " (the sub-facet exponent of variable-step-2n)", err);
    if (st == SEA_OK)
        st = sea_cli_opt_integer(args, "n", 0, SEA_CLI_N_MAX, 0, &v, err);
    if (st == SEA_OK)
        *n = (int)v;
    return st;
}

/* Sea state from --wind (one value), --fetch, --wind-dir. */
sea_status sea_cli_opt_sea_state(const sea_cli_args *args, double *wind, double *fetch,
                                 double *wind_dir_deg, sea_error *err)
{
    sea_status st = sea_cli_require(args, "wind", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wind", &SEA_CLI_RANGE_WIND, 0.0, wind, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "fetch", &SEA_CLI_RANGE_FETCH, INFINITY, fetch, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wind-dir", &SEA_CLI_RANGE_AZIMUTH, 0.0, wind_dir_deg, err);
    return st;
}

/* The largest --threads: SEA_CLI_THREADS_PER_CPU x the online CPUs.  More
 * threads than that only cost memory (a stack each); libgomp reports a
 * failed thread creation by printing and exiting, so the count is bounded
 * here, with the range in the message. */
static long online_cpus(void)
{
    const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    return cpus < 1 ? 1 : cpus;
}

long sea_cli_threads_max(void)
{
    const long cpus = online_cpus();
    if (cpus > SEA_CLI_THREADS_LIMIT / SEA_CLI_THREADS_PER_CPU)
        return SEA_CLI_THREADS_LIMIT;
    return SEA_CLI_THREADS_PER_CPU * cpus;
}

/* --threads N: sets the OpenMP thread count. */
sea_status sea_cli_opt_threads(const sea_cli_args *args, sea_error *err)
{
    const long max = sea_cli_threads_max();
    long n;
    sea_status st = sea_cli_opt_integer(args, "threads", 1, max, 0, &n, err);
    if (st != SEA_OK) {
        if (err != NULL && strstr(err->msg, " is outside ") != NULL) {
            char msg[SEA_ERROR_MSG_MAX];
            snprintf(msg, sizeof msg, "%s", err->msg);
            return sea_fail(err, st, "%s (at most %d threads a CPU, %ld online)", msg,
                            SEA_CLI_THREADS_PER_CPU, online_cpus());
        }
        return st;
    }
#ifdef _OPENMP
    if (n > 0)
        omp_set_num_threads((int)n);
#endif
    return SEA_OK;
}

#ifdef _OPENMP
/* A thread that does nothing: sea_cli_threads_start's probe. */
static void *idle_thread(void *arg)
{
    return arg;
}
#endif

sea_status sea_cli_threads_start(sea_error *err)
{
#ifdef _OPENMP
    const int n = omp_get_max_threads();
    pthread_t *t = n > 1 ? malloc((size_t)(n - 1) * sizeof *t) : NULL;
    if (n > 1 && t == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %d threads", n);
    /* The probe: as many threads as the team will hold beside this one,
     * with libgomp's attributes (the default stack, unless OMP_STACKSIZE
     * sets one, which the message cannot know). */
    int made = 0, e = 0;
    while (made < n - 1 && (e = pthread_create(&t[made], NULL, idle_thread, NULL)) == 0)
        made++;
    for (int i = 0; i < made; i++)
        pthread_join(t[i], NULL);
    free(t);
    if (e != 0) {
        size_t stack = 0;
        pthread_attr_t attr;
        if (pthread_attr_init(&attr) == 0) {
            pthread_attr_getstacksize(&attr, &stack);
            pthread_attr_destroy(&attr);
        }
        return sea_fail(err, SEA_ERR_NOMEM,
                        "cannot start %d threads (%d did, with stacks of %.3g MiB): %s "
                        "(allowed: fewer threads, by OMP_NUM_THREADS or --threads, or a larger "
                        "ulimit -v or -s)",
                        n, made + 1, (double)stack / 1048576.0, strerror(e));
    }
    /* libgomp makes its team at the first parallel region and keeps it
     * for the later ones.  Made here, before any file exists, its thread
     * creation cannot fail in the middle of the work, where libgomp
     * prints its own message and exits, leaving temporaries behind. */
    int started = 0;
#pragma omp parallel reduction(+ : started)
    started += 1;
    (void)started;
#else
    (void)err;
#endif
    return SEA_OK;
}

/* --format float|half and --compression none|zip|piz of render and bake. */
sea_status sea_cli_opt_exr(const sea_cli_args *args, sea_exr_options *out, sea_error *err)
{
    out->pixel = SEA_EXR_FLOAT;
    out->compression = SEA_EXR_ZIP;
    const char *format = sea_cli_args_get(args, "format");
    if (format != NULL) {
        if (strcmp(format, "half") == 0)
            out->pixel = SEA_EXR_HALF;
        else if (strcmp(format, "float") != 0)
            return sea_fail(err, SEA_ERR_PARSE, "--format: '%s' is not float or half", format);
    }
    const char *comp = sea_cli_args_get(args, "compression");
    if (comp != NULL) {
        if (strcmp(comp, "none") == 0)
            out->compression = SEA_EXR_NONE;
        else if (strcmp(comp, "piz") == 0)
            out->compression = SEA_EXR_PIZ;
        else if (strcmp(comp, "zip") != 0)
            return sea_fail(err, SEA_ERR_PARSE, "--compression: '%s' is not none, zip or piz",
                            comp);
    }
    return SEA_OK;
}

/* SCENE.ini with the --unset and --set overrides of render and bake: the
 * keys removed first (so that --unset sensor.band --set sensor.wavelength=4
 * holds in either order), then the keys set. */
sea_status sea_cli_load_scene(const sea_cli_args *args, const char *path, sea_scene *sc,
                              sea_error *err)
{
    const size_t nu = sea_cli_args_count(args, "unset"), ns = sea_cli_args_count(args, "set");
    for (size_t i = 0; i < nu; ++i) {
        const char *u = sea_cli_args_nth(args, "unset", i);
        if (strchr(u, '=') != NULL || strchr(u, '.') == NULL)
            return sea_fail(err, SEA_ERR_PARSE,
                            "--unset %s: not SECTION.KEY (allowed: e.g. sensor.band; --set "
                            "gives a value)",
                            u);
    }
    for (size_t i = 0; i < ns; ++i) {
        const char *o = sea_cli_args_nth(args, "set", i);
        if (strchr(o, '=') == NULL)
            return sea_fail(err, SEA_ERR_PARSE,
                            "--set %s: not SECTION.KEY=VALUE (allowed: e.g. sea.wind_speed=12; "
                            "--unset removes a key)",
                            o);
    }
    if (nu + ns == 0)
        return sea_scene_load(path, sc, err);
    const char **over = malloc((nu + ns) * sizeof *over);
    if (over == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < nu; ++i)
        over[i] = sea_cli_args_nth(args, "unset", i);
    for (size_t i = 0; i < ns; ++i)
        over[nu + i] = sea_cli_args_nth(args, "set", i);
    sea_status st = sea_scene_load_with(path, over, nu + ns, sc, err);
    free(over);
    return st;
}

/* The smallest power of two >= x (x >= 1, finite). */
double sea_cli_pow2_ceil(double x)
{
    double e = ceil(log2(x));
    if (exp2(e - 1.0) >= x)
        e -= 1.0;
    if (exp2(e) < x)
        e += 1.0;
    return exp2(e);
}
