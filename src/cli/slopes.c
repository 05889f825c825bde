/* slopes.c - the slopes subcommand of seabake: the facet slope moments of
 * one seeded realisation of the waves (Variable Step, Variable Step L/2^n,
 * 1 Meter Step; seabake-model(7)) over a rectangle of facets centred on the
 * origin, as CSV (standard output or a file) or EXR.
 *
 * Every option is validated before anything is allocated or written; sizes
 * that cannot fit in memory are refused with sea_check_size.  A file is
 * written under a temporary name in its directory and renamed when
 * complete, so a failure leaves nothing behind. */
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "exr.h"

/* ------------------------------------------------------------ constants */

/* Facets per side of slopes: also the largest EXR image side. */
#define SEA_CLI_SIDE_MAX 65536
/* Largest facet and finest size: far beyond convergence to low resolution. */
#define SEA_CLI_LENGTH_MAX 1e6
/* Largest FFT patch the library plans (sea_waves_params.fft_size). */
#define SEA_CLI_FFT_MAX 16384
/* Relative slack when comparing lengths, so that sizes typed as decimals
 * (0.1 x 2^n) are not refused for rounding: a ratio is a power of two
 * within it, as in the library's own test (sea_facet_method_n). */
static const double SEA_CLI_LENGTH_REL_TOL = 1e-9;

static const sea_cli_range SEA_CLI_RANGE_LENGTH = {0.0, SEA_CLI_LENGTH_MAX, true, false, "m"};
/* The library's times (SEA_TIME_MAX: beyond it the phases lose every digit). */
static const sea_cli_range SEA_CLI_RANGE_TIME = {-SEA_TIME_MAX, SEA_TIME_MAX, false, false, "s"};
static const sea_cli_range SEA_CLI_RANGE_LOOP = {0.0, INFINITY, false, true, "s"};
static const sea_cli_range SEA_CLI_RANGE_SIZE[2] = {
    {1.0, SEA_CLI_SIDE_MAX, false, false, "facets"},
    {1.0, SEA_CLI_SIDE_MAX, false, false, "facets"}};

/* ------------------------------------------------------------ help text */

static const char SEA_CLI_HELP_SLOPES[] =
    "Usage: seabake slopes --wind U --facet L [OPTIONS]\n"
    "\n"
    "Slope moments of a rectangle of facets of one seeded realisation of the\n"
    "large-scale waves (Variable Step, Variable Step L/2^n, 1 Meter Step): the\n"
    "mean slope, the raw second moments (sub-facet covariance included) and the\n"
    "mean height of each facet.  NX x NY facets of size L centred on the origin;\n"
    "rows j outer, i inner.  A one-line summary goes to standard error.\n"
    "\n"
    "Sea state:\n"
    "  --wind U            wind speed at 10 m, m/s, [0.5, 40] (required)\n"
    "  --fetch F           fetch, m, [1000, inf]; default inf (fully developed)\n"
    "  --wind-dir DEG      wind azimuth from the x axis, degrees; default 0\n"
    "\n"
    "Facets:\n"
    "  --facet L           facet size, m, (0, 1e6] (required)\n"
    "  --size NX,NY        facets along x and y, each 1..65536; default 64,64\n"
    "  --method M          variable-step (default), variable-step-2n or one-meter\n"
    "  --n N               sub-facet exponent of variable-step-2n, 0..20: 2^N x 2^N\n"
    "                      sub-facets of L/2^N (required with it, refused otherwise)\n"
    "\n"
    "Waves:\n"
    "  --seed S            unsigned integer, the same seed gives the same sea;\n"
    "                      default 1\n"
    "  --time T            time, s, [-1e9, 1e9]; default 0 (waves travel downwind)\n"
    "  --finest L0         finest facet size of the wave plan, m, (0, 1e6];\n"
    "                      default 1\n"
    "  --generator G       sinusoids or fft; default fft for one-meter, sinusoids\n"
    "                      otherwise.  The FFT patch is the smallest power of two\n"
    "                      covering the rectangle (at most 16384 x L0), so it\n"
    "                      never repeats\n"
    "  --loop-period T     s, >= 0: frequencies rounded to multiples of 2 pi/T, so\n"
    "                      the sea repeats after T; default 0 (no loop)\n"
    "\n"
    "Output:\n"
    "  -o FILE             FILE.csv or FILE.exr, written atomically; default CSV\n"
    "                      on standard output\n"
    "  --quiet             no summary on standard error\n"
    "\n"
    "Columns: i,j,x_m,y_m,mx,my,mxx,mxy,myy,h\n"
    "  i, j: facet indices (facet (0,0) has its lower-left corner at the origin);\n"
    "  x_m, y_m: facet centre, m; mx, my: mean slope; mxx = mx^2 + Cxx,\n"
    "  mxy = mx my + Cxy, myy = my^2 + Cyy; h: mean height of the generated\n"
    "  waves, m.  EXR: channels mx, my, mxx, mxy, myy, h (FLOAT, ZIP), image\n"
    "  row 0 = the largest j (north up), attributes seabake:*.\n";

/* --------------------------------------------------------------- numbers */

/* e with r = 2^e, e in [0, emax], within SEA_CLI_LENGTH_REL_TOL; false if r
 * is not such a power of two. */
static bool pow2_exponent(double r, int emax, int *e)
{
    const double m = round(log2(r));
    if (!(m >= 0.0) || m > emax || fabs(r - exp2(m)) > SEA_CLI_LENGTH_REL_TOL * r)
        return false;
    *e = (int)m;
    return true;
}

/* ================================================================ slopes */

static const sea_cli_option SEA_CLI_SLOPES_OPTIONS[] = {
    {"wind", 0},       {"fetch", 0},     {"wind-dir", 0},  {"facet", 0},
    {"method", 0},     {"n", 0},         {"seed", 0},      {"time", 0},
    {"size", 0},       {"finest", 0},    {"generator", 0}, {"loop-period", 0},
    {"o", SEA_CLI_OPT_SHORT},          {"quiet", SEA_CLI_OPT_FLAG}};

typedef enum { SLOPES_STDOUT, SLOPES_CSV, SLOPES_EXR } slopes_output;

/* Everything slopes computes from, validated. */
typedef struct {
    double wind, fetch, wind_dir_deg;
    double facet, finest, time, loop_period;
    sea_facet_method method;
    int n; /* sub-facet exponent in use (one-meter: log2(L/L0)) */
    unsigned long seed;
    size_t nx, ny;
    sea_waves_kind kind;
    size_t fft_size;
    slopes_output output;
    const char *path;
    bool quiet;
} slopes_setup;

static const char *generator_name(sea_waves_kind k)
{
    return k == SEA_WAVES_FFT ? "fft" : "sinusoids";
}

static sea_status slopes_size(const sea_cli_args *args, size_t *nx, size_t *ny, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "size");
    double v[2];
    sea_status st = sea_cli_parse_tuple("--size", text ? text : "64,64", 2, SEA_CLI_RANGE_SIZE,
                                        "NX,NY", v, err);
    if (st != SEA_OK)
        return st;
    for (int q = 0; q < 2; ++q)
        if (v[q] != floor(v[q]))
            return sea_fail(err, SEA_ERR_DOMAIN, "--size: %g is not an integer", v[q]);
    *nx = (size_t)v[0];
    *ny = (size_t)v[1];
    return SEA_OK;
}

/* The generator and, for FFT, the patch: the smallest power of two of
 * points that covers the rectangle, so that it never repeats. */
static sea_status slopes_generator(const sea_cli_args *args, slopes_setup *s, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "generator");
    if (text == NULL)
        s->kind = s->method == SEA_METHOD_ONE_METER ? SEA_WAVES_FFT : SEA_WAVES_SINUSOIDS;
    else if (strcmp(text, "sinusoids") == 0)
        s->kind = SEA_WAVES_SINUSOIDS;
    else if (strcmp(text, "fft") == 0)
        s->kind = SEA_WAVES_FFT;
    else
        return sea_fail(err, SEA_ERR_PARSE, "--generator: '%s' is not one of sinusoids, fft",
                        text);
    s->fft_size = 0;
    if (s->kind != SEA_WAVES_FFT)
        return SEA_OK;

    const double delta = s->facet / exp2(s->n);
    int m;
    if (!pow2_exponent(delta / s->finest, 62, &m))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--generator fft samples steps of --finest %g m times 2^m: the "
                        "sub-facet size %g m is not one (use --generator sinusoids)",
                        s->finest, delta);
    /* Each side holds the rectangle, and the level grid of the sub-facets
     * has at least two cells (the library samples up to half a period). */
    const double side = s->nx > s->ny ? (double)s->nx : (double)s->ny;
    double need = fmax(side * s->facet / s->finest, 2.0 * delta / s->finest);
    need = sea_cli_pow2_ceil(fmax(need, 2.0));
    if (need > SEA_CLI_FFT_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--size %zu,%zu: %g m x %g m needs an FFT patch of %.0f points per side "
                        "at --finest %g m, above the limit of %d (use --generator sinusoids, a "
                        "smaller --size or --facet, or a larger --finest)",
                        s->nx, s->ny, (double)s->nx * s->facet, (double)s->ny * s->facet, need,
                        s->finest, SEA_CLI_FFT_MAX);
    s->fft_size = (size_t)need;
    return SEA_OK;
}

static sea_status slopes_parse(const sea_cli_args *args, slopes_setup *s, sea_error *err)
{
    sea_status st = sea_cli_opt_sea_state(args, &s->wind, &s->fetch, &s->wind_dir_deg, err);
    if (st == SEA_OK)
        st = sea_cli_require(args, "facet", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "facet", &SEA_CLI_RANGE_LENGTH, 0.0, &s->facet, err);
    if (st == SEA_OK)
        st = sea_cli_opt_facet_method(args, &s->method, &s->n, err);
    if (st == SEA_OK)
        st = sea_cli_opt_seed(args, &s->seed, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "time", &SEA_CLI_RANGE_TIME, 0.0, &s->time, err);
    if (st == SEA_OK)
        st = slopes_size(args, &s->nx, &s->ny, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "finest", &SEA_CLI_RANGE_LENGTH, 1.0, &s->finest, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "loop-period", &SEA_CLI_RANGE_LOOP, 0.0, &s->loop_period,
                                err);
    if (st != SEA_OK)
        return st;

    s->quiet = sea_cli_given(args, "quiet");
    s->path = sea_cli_args_get(args, "o");
    s->output = SLOPES_STDOUT;
    if (s->path != NULL) {
        if (sea_cli_has_suffix(s->path, ".csv"))
            s->output = SLOPES_CSV;
        else if (sea_cli_has_suffix(s->path, ".exr"))
            s->output = SLOPES_EXR;
        else
            return sea_fail(err, SEA_ERR_PARSE, "-o: '%s' must end in .csv or .exr", s->path);
    }

    /* The sub-facets: L / 2^n, at least the plan's finest size. */
    if (s->method == SEA_METHOD_ONE_METER) {
        if (!pow2_exponent(s->facet / s->finest, SEA_CLI_N_MAX, &s->n))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "--facet: one-meter needs L = --finest %g m times 2^n, n in [0, "
                            "%d]; %g m is not",
                            s->finest, SEA_CLI_N_MAX, s->facet);
    }
    const double delta = s->facet / exp2(s->n);
    if (delta < s->finest * (1.0 - SEA_CLI_LENGTH_REL_TOL)) {
        if (s->n == 0)
            return sea_fail(err, SEA_ERR_DOMAIN, "--facet: %g m is below --finest %g m",
                            s->facet, s->finest);
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--n: sub-facets of %g m / 2^%d = %g m are below --finest %g m", s->facet,
                        s->n, delta, s->finest);
    }
    return slopes_generator(args, s, err);
}

static sea_status slopes_csv(FILE *f, const char *where, const sea_rect *r,
                             const sea_moments *mo, sea_error *err)
{
    fputs("i,j,x_m,y_m,mx,my,mxx,mxy,myy,h\n", f);
    for (size_t j = 0; j < r->ny; ++j) {
        /* Lattice indices (I is complex.h's imaginary unit). */
        const long fj = r->j0 + (long)j;
        for (size_t i = 0; i < r->nx; ++i) {
            const long fi = r->i0 + (long)i;
            const sea_moments *m = &mo[j * r->nx + i];
            fprintf(f, "%ld,%ld,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", fi, fj,
                    ((double)fi + 0.5) * r->step, ((double)fj + 0.5) * r->step, m->mx, m->my,
                    m->mxx, m->mxy, m->myy, m->h);
        }
        if (ferror(f))
            return sea_fail(err, SEA_ERR_IO, "cannot write to %s", where);
    }
    return SEA_OK;
}

static sea_status slopes_exr(const slopes_setup *s, const sea_rect *r, const sea_moments *mo,
                             sea_error *err)
{
    const size_t np = r->nx * r->ny;
    float *buf = malloc(6 * np * sizeof(float));
    if (buf == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu image", r->nx, r->ny);
    /* Row 0 of the image is the northernmost facet row (the largest j). */
    for (size_t row = 0; row < r->ny; ++row) {
        const size_t j = r->ny - 1 - row;
        for (size_t i = 0; i < r->nx; ++i) {
            const sea_moments *m = &mo[j * r->nx + i];
            const size_t d = row * r->nx + i;
            buf[d] = (float)m->mx;
            buf[np + d] = (float)m->my;
            buf[2 * np + d] = (float)m->mxx;
            buf[3 * np + d] = (float)m->mxy;
            buf[4 * np + d] = (float)m->myy;
            buf[5 * np + d] = (float)m->h;
        }
    }
    const sea_exr_channel ch[] = {{"mx", buf},           {"my", buf + np},
                                  {"mxx", buf + 2 * np}, {"mxy", buf + 3 * np},
                                  {"myy", buf + 4 * np}, {"h", buf + 5 * np}};
    char facet[32], n[16], wind[32], dir[32], fetch[32], seed[32], t[32], origin[64], finest[32],
        loop[32], fft[32];
    snprintf(facet, sizeof facet, "%.10g", s->facet);
    snprintf(n, sizeof n, "%d", s->n);
    snprintf(wind, sizeof wind, "%.10g", s->wind);
    snprintf(dir, sizeof dir, "%.10g", s->wind_dir_deg);
    snprintf(fetch, sizeof fetch, isinf(s->fetch) ? "inf" : "%.10g", s->fetch);
    snprintf(seed, sizeof seed, "%lu", s->seed);
    snprintf(t, sizeof t, "%.10g", s->time);
    snprintf(origin, sizeof origin, "%.10g,%.10g", (double)r->i0 * r->step,
             (double)r->j0 * r->step);
    snprintf(finest, sizeof finest, "%.10g", s->finest);
    snprintf(loop, sizeof loop, "%.10g", s->loop_period);
    snprintf(fft, sizeof fft, "%zu", s->fft_size);
    const sea_exr_attr attrs[] = {{"seabake:method", sea_facet_method_name(s->method)},
                                  {"seabake:facet_m", facet},
                                  {"seabake:n", n},
                                  {"seabake:wind", wind},
                                  {"seabake:wind_dir_deg", dir},
                                  {"seabake:fetch_m", fetch},
                                  {"seabake:seed", seed},
                                  {"seabake:time_s", t},
                                  {"seabake:origin", origin},
                                  {"seabake:generator", generator_name(s->kind)},
                                  {"seabake:finest_m", finest},
                                  {"seabake:loop_period_s", loop},
                                  {"seabake:fft_size", fft}};
    const size_t n_attrs = sizeof attrs / sizeof attrs[0] - (s->kind == SEA_WAVES_FFT ? 0 : 1);
    const sea_exr_options opt = {SEA_EXR_FLOAT, SEA_EXR_ZIP};
    sea_status st = sea_exr_write(s->path, (int)r->nx, (int)r->ny, ch, 6, attrs, n_attrs, &opt,
                                  err);
    free(buf);
    return st;
}

/* One line on stderr: the generated part (variance of the facet means) plus
 * the sub-facet part (mean of M - m m^T) against the low-resolution
 * covariance; the ratio is near 1 on a rectangle much larger than the
 * longest waves. */
static sea_status slopes_summary(const slopes_setup *s, const sea_spectrum *spec,
                                 const sea_rect *r, const sea_moments *mo, sea_error *err)
{
    const size_t np = r->nx * r->ny;
    double mx = 0.0, my = 0.0;
    for (size_t q = 0; q < np; ++q) {
        mx += mo[q].mx;
        my += mo[q].my;
    }
    mx /= (double)np;
    my /= (double)np;
    sea_cov2 var = {0.0, 0.0, 0.0}, sub = {0.0, 0.0, 0.0}, lr;
    for (size_t q = 0; q < np; ++q) {
        const double dx = mo[q].mx - mx, dy = mo[q].my - my;
        var.xx += dx * dx;
        var.yy += dy * dy;
        var.xy += dx * dy;
        sub.xx += mo[q].mxx - mo[q].mx * mo[q].mx;
        sub.yy += mo[q].myy - mo[q].my * mo[q].my;
        sub.xy += mo[q].mxy - mo[q].mx * mo[q].my;
    }
    var.xx /= (double)np;
    var.yy /= (double)np;
    var.xy /= (double)np;
    sub.xx /= (double)np;
    sub.yy /= (double)np;
    sub.xy /= (double)np;
    sea_status st = sea_spectrum_slope_cov(spec, 0.0, &lr, err);
    if (st != SEA_OK)
        return st;
    fprintf(stderr,
            "slopes: %zu x %zu facets of %g m, %s n=%d (%s): mean slope %.4g,%.4g; variance of "
            "facet means xx,yy,xy %.4g,%.4g,%.4g; mean sub-facet covariance %.4g,%.4g,%.4g; "
            "(variance + sub-facet)/LR x %.4f, y %.4f\n",
            r->nx, r->ny, s->facet, sea_facet_method_name(s->method), s->n,
            generator_name(s->kind), mx, my, var.xx, var.yy, var.xy, sub.xx, sub.yy, sub.xy,
            (var.xx + sub.xx) / lr.xx, (var.yy + sub.yy) / lr.yy);
    return SEA_OK;
}

static sea_status run_slopes(const sea_cli_args *args, FILE *out, sea_error *err)
{
    slopes_setup s;
    sea_spectrum spec;
    sea_waves *waves = NULL;
    sea_moments *mo = NULL;
    sea_cli_atomic_file af = {NULL, NULL, NULL};
    sea_status st = slopes_parse(args, &s, err);
    if (st != SEA_OK)
        return st;
    const size_t np = s.nx * s.ny;
    /* The moments, and the float image when writing EXR, before any work. */
    char what[64];
    snprintf(what, sizeof what, "--size %zu,%zu", s.nx, s.ny);
    const size_t per_facet = sizeof(sea_moments) + (s.output == SLOPES_EXR ? 6 * sizeof(float) : 0);
    if ((st = sea_check_size(np, per_facet, what, err)) != SEA_OK)
        return st;
    if (s.output != SLOPES_STDOUT &&
        (st = sea_cli_check_parent_writable("-o", s.path, err)) != SEA_OK)
        return st;
    /* what a killed run left beside the output (marked, its maker gone) */
    if (s.output != SLOPES_STDOUT)
        sea_cli_clean_stale_files("slopes", s.path);
    if ((st = sea_spectrum_init(s.wind, s.fetch, sea_cli_radians(s.wind_dir_deg), &spec, err)) !=
        SEA_OK)
        return st;

    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = s.kind;
    p.finest = s.finest;
    p.seed = s.seed;
    p.loop_period = s.loop_period;
    if (s.kind == SEA_WAVES_FFT)
        p.fft_size = s.fft_size;
    if ((st = sea_waves_alloc(&spec, &p, &waves, err)) != SEA_OK)
        goto done;
    mo = malloc(np * sizeof *mo);
    if (mo == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu x %zu facets", s.nx, s.ny);
        goto done;
    }
    const sea_rect rect = {s.facet, -(long)(s.nx / 2), -(long)(s.ny / 2), s.nx, s.ny};
    if ((st = sea_waves_facets(waves, &rect, s.n, s.time, mo, err)) != SEA_OK)
        goto done;
    for (size_t q = 0; q < np; ++q) {
        const sea_moments *m = &mo[q];
        if (!isfinite(m->mx) || !isfinite(m->my) || !isfinite(m->mxx) || !isfinite(m->mxy) ||
            !isfinite(m->myy) || !isfinite(m->h)) {
            st = sea_fail(err, SEA_ERR_NUMERIC, "the moments of facet %zu are not finite", q);
            goto done;
        }
    }

    switch (s.output) {
    case SLOPES_STDOUT:
        st = slopes_csv(out, "standard output", &rect, mo, err);
        break;
    case SLOPES_CSV:
        if ((st = sea_cli_atomic_open(&af, "-o", s.path, err)) != SEA_OK)
            break;
        if ((st = slopes_csv(af.f, s.path, &rect, mo, err)) != SEA_OK)
            break;
        st = sea_cli_atomic_commit(&af, "-o", err);
        break;
    case SLOPES_EXR:
        st = slopes_exr(&s, &rect, mo, err);
        break;
    }
    if (st == SEA_OK && !s.quiet)
        st = slopes_summary(&s, &spec, &rect, mo, err);
done:
    sea_cli_atomic_abort(&af);
    free(mo);
    sea_waves_free(waves);
    return st;
}

/* --------------------------------------------------------------- command */

const sea_cli_command sea_cli_cmd_slopes = {
    "slopes", "facet slope moments of one seeded sea (CSV or EXR)", SEA_CLI_HELP_SLOPES,
    SEA_CLI_SLOPES_OPTIONS, SEA_CLI_COUNT(SEA_CLI_SLOPES_OPTIONS), run_slopes};
