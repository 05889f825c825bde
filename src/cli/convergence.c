/* convergence.c - the convergence subcommand of seabake: the paper's Fig.
 * 5-6 study, high-resolution emissivity and reflectivity of growing facets
 * against the low-resolution values, with a CSV table (written atomically)
 * and a gnuplot chart in the output directory. */
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

/* ------------------------------------------------------------ constants */

/* The convergence sweep: L = 2^(x-1) m, x = 1..11 (1 m to 1024 m), as in
 * the paper's Fig. 5-6; facets per side; the 1 Meter Step FFT patch. */
#define SEA_CLI_CONV_X_MAX 11
#define SEA_CLI_CONV_FACETS_MAX 256
#define SEA_CLI_CONV_FACETS_DEFAULT 16
#define SEA_CLI_CONV_FFT_MAX 4096
static const double SEA_CLI_CONV_TOL_DEFAULT = 1e-3;
/* The paper's finest resolution (MATISSE): sub-facets of at least 1 m. */
static const double SEA_CLI_CONV_FINEST = 1.0;

static const sea_cli_range SEA_CLI_RANGE_ZENITH = {0.0, 90.0, false, true, "degrees"};
static const sea_cli_range SEA_CLI_RANGE_TOL = {0.0, 1.0, true, true, ""};

/* ------------------------------------------------------------ help text */

static const char SEA_CLI_HELP_CONVERGENCE[] =
    "Usage: seabake convergence --wavelength UM --wind LIST --theta DEG [OPTIONS]\n"
    "\n"
    "Convergence of the high-resolution effective emissivity and reflectivity to\n"
    "the low-resolution ones as the facet grows (the paper's Fig. 5-6): for each\n"
    "wind and each size L = 2^(x-1) m, x = 1..11, K x K facets centred on the\n"
    "origin of one seeded sea (the same seed for every wind).  Writes\n"
    "DIR/convergence.csv and DIR/convergence.png (gnuplot) and prints a table and\n"
    "the converged size per wind, all or nothing: a failure leaves no file (without\n"
    "gnuplot: the CSV and the table, no chart, exit status 1).\n"
    "\n"
    "Geometry:\n"
    "  --theta DEG         observation zenith, degrees, [0, 90) (required)\n"
    "  --phi DEG           observation azimuth, degrees; default 0\n"
    "  --inc THETA,PHI     source direction, signed zenith in (-90, 90) and\n"
    "                      azimuth; default -THETA,PHI (specular)\n"
    "\n"
    "Sea:\n"
    "  --wind LIST         wind speeds at 10 m, m/s, [0.5, 40] (required)\n"
    "  --fetch F           fetch, m, [1000, inf]; default inf (fully developed)\n"
    "  --wind-dir DEG      wind azimuth from the x axis, degrees; default 0\n"
    "  --seed S            unsigned integer; default 1\n"
    "  --method M          variable-step (default), variable-step-2n or one-meter\n"
    "                      (FFT patch of min(4096, K L) m per size)\n"
    "  --n N               sub-facet exponent of variable-step-2n, 0..20; sub-facets\n"
    "                      stay >= 1 m (n = min(N, x - 1))\n"
    "  --facets K          facets per side, 1..256; default 16\n"
    "  --sizes X1:X2       sweep x = X1..X2 only, 1 <= X1 <= X2 <= 11; default 1:11\n"
    SEA_CLI_HELP_SHADOWING
    "  --converged REL     relative deviation, (0, 1); default 0.001: a size counts\n"
    "                      as converged when it and every larger size have\n"
    "                      max |HR - LR| <= REL |LR|\n"
    "\n"
    "Water:\n"
    "  --wavelength UM     wavelength, um, > 0 (required), inside the water table\n"
    "  --water TABLE       hale-querry (default), segelstein, or a CSV file with\n"
    "                      columns wavelength_um,n,k\n"
    "  --salinity S        salinity, g/kg, [0, 45]; default 35\n"
    "\n"
    "Output:\n"
    "  -o DIR              output directory, created if missing (its parent must\n"
    "                      exist); default .\n"
    "  --quiet             no progress line on standard error\n"
    "\n"
    "LIST is A:B:STEP, A,B,C or one value.\n"
    "CSV columns: wind_m_s,x,L_m,facets,n,emis_lr,emis_origin,emis_mean,\n"
    "  emis_rms_dev,emis_max_dev,refl_lr,refl_origin,refl_mean,refl_rms_dev,\n"
    "  refl_max_dev,var_mx,var_my (dev = HR - LR over the facets; origin = the\n"
    "  facet with its lower-left corner at the origin; facets = per side).\n";

/* =========================================================== convergence */

static const sea_cli_option SEA_CLI_CONVERGENCE_OPTIONS[] = {
    {"wavelength", 0}, {"water", 0},     {"salinity", 0},  {"wind", 0},
    {"fetch", 0},      {"wind-dir", 0},  {"theta", 0},     {"phi", 0},
    {"inc", 0},        {"seed", 0},      {"method", 0},    {"n", 0},
    {"facets", 0},     {"sizes", 0},     {"converged", 0}, {"o", SEA_CLI_OPT_SHORT},
    {"shadowing", 0},  {"quiet", SEA_CLI_OPT_FLAG}};

typedef struct {
    double wavelength_um;
    double complex N;
    double theta_deg, phi_deg, inc_deg[2];
    sea_dir obs, inc;
    sea_cli_list winds;
    double fetch, wind_dir_deg;
    unsigned long seed;
    sea_facet_method method;
    sea_shadowing shadowing;
    int n;
    long K;
    int x1, x2;
    double tol;
    const char *dir;
    const char *water, *salinity;
    bool progress;
} conv_setup;

/* One row of the table: one wind, one size. */
typedef struct {
    double wind, L;
    int x, n;
    size_t facets; /* per side */
    double emis_lr, emis_origin, emis_mean, emis_rms, emis_max;
    double refl_lr, refl_origin, refl_mean, refl_rms, refl_max;
    double var_mx, var_my;
} conv_row;

/* --sizes X1:X2 (or one X). */
static sea_status conv_sizes(const sea_cli_args *args, int *x1, int *x2, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "sizes");
    *x1 = 1;
    *x2 = SEA_CLI_CONV_X_MAX;
    if (text == NULL)
        return SEA_OK;
    const sea_cli_range r = {1.0, SEA_CLI_CONV_X_MAX, false, false, ""};
    const char *colon = strchr(text, ':');
    char first[64];
    double a, b;
    if (colon != NULL && (strchr(colon + 1, ':') || (size_t)(colon - text) >= sizeof first))
        return sea_fail(err, SEA_ERR_PARSE, "--sizes: '%s' is not X1:X2", text);
    if (colon != NULL) {
        memcpy(first, text, (size_t)(colon - text));
        first[colon - text] = '\0';
    }
    sea_status st = sea_cli_parse_number("--sizes", colon ? first : text, &r, &a, err);
    if (st == SEA_OK)
        st = colon ? sea_cli_parse_number("--sizes", colon + 1, &r, &b, err) : SEA_OK;
    if (st != SEA_OK)
        return st;
    if (!colon)
        b = a;
    if (a != floor(a) || b != floor(b))
        return sea_fail(err, SEA_ERR_DOMAIN, "--sizes: '%s' must hold integers", text);
    if (a > b)
        return sea_fail(err, SEA_ERR_DOMAIN, "--sizes: '%s' runs backwards (X1 <= X2)", text);
    *x1 = (int)a;
    *x2 = (int)b;
    return SEA_OK;
}

static sea_status conv_parse(const sea_cli_args *args, conv_setup *c, sea_error *err)
{
    long K;
    sea_status st = sea_cli_require(args, "wind", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_parse_list("--wind", sea_cli_args_get(args, "wind"), &SEA_CLI_RANGE_WIND,
                                &c->winds, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "fetch", &SEA_CLI_RANGE_FETCH, INFINITY, &c->fetch, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wind-dir", &SEA_CLI_RANGE_AZIMUTH, 0.0, &c->wind_dir_deg,
                                err);
    if (st == SEA_OK)
        st = sea_cli_require(args, "theta", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "theta", &SEA_CLI_RANGE_ZENITH, 0.0, &c->theta_deg, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "phi", &SEA_CLI_RANGE_AZIMUTH, 0.0, &c->phi_deg, err);
    if (st != SEA_OK)
        return st;
    /* The default incidence is the specular one of Fig. 6. */
    c->inc_deg[0] = -c->theta_deg;
    c->inc_deg[1] = c->phi_deg;
    const char *inc = sea_cli_args_get(args, "inc");
    if (inc != NULL &&
        (st = sea_cli_parse_tuple("--inc", inc, 2, SEA_CLI_RANGE_DIRECTION, "THETA,PHI",
                                  c->inc_deg, err)) != SEA_OK)
        return st;
    c->obs = sea_dir_fold(sea_cli_radians(c->theta_deg), sea_cli_radians(c->phi_deg));
    c->inc = sea_dir_fold(sea_cli_radians(c->inc_deg[0]), sea_cli_radians(c->inc_deg[1]));

    if ((st = sea_cli_opt_seed(args, &c->seed, err)) != SEA_OK ||
        (st = sea_cli_opt_facet_method(args, &c->method, &c->n, err)) != SEA_OK ||
        (st = sea_cli_opt_shadowing(args, SEA_SHADOW_CORRELATED, &c->shadowing, err)) !=
            SEA_OK ||
        (st = sea_cli_opt_integer(args, "facets", 1, SEA_CLI_CONV_FACETS_MAX,
                                  SEA_CLI_CONV_FACETS_DEFAULT, &K, err)) != SEA_OK ||
        (st = conv_sizes(args, &c->x1, &c->x2, err)) != SEA_OK ||
        (st = sea_cli_opt_number(args, "converged", &SEA_CLI_RANGE_TOL, SEA_CLI_CONV_TOL_DEFAULT,
                                 &c->tol, err)) != SEA_OK)
        return st;
    c->K = K;
    c->dir = sea_cli_args_get(args, "o");
    if (c->dir == NULL)
        c->dir = ".";
    c->water = sea_cli_args_get(args, "water");
    if (c->water == NULL)
        c->water = "hale-querry";
    c->salinity = sea_cli_args_get(args, "salinity");
    if (c->salinity == NULL)
        c->salinity = "35";
    c->progress = !sea_cli_given(args, "quiet") && isatty(STDERR_FILENO);
    /* The water table is read last: a typing mistake is reported first. */
    return sea_cli_water(args, &c->wavelength_um, &c->N, err);
}

/* Emissivity toward obs and reflectivity inc -> obs of each facet; the
 * facets are independent, so threads change nothing in the result. */
static sea_status conv_optics(const conv_setup *c, const sea_optics *optics,
                              const sea_moments *mo, size_t count, double *emis, double *refl,
                              sea_error *err)
{
    int *status = malloc(count * sizeof *status);
    if (status == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
#pragma omp parallel for schedule(dynamic, 4)
    for (long q = 0; q < (long)count; ++q) {
        const sea_slope_stats st = sea_moments_stats(&mo[q]);
        status[q] = (int)sea_emissivity(optics, SEA_EMIS_AUTO, c->N, &st, c->obs, &emis[q], NULL);
        refl[q] = sea_reflectivity(c->N, &st, c->inc, c->obs);
    }
    sea_status res = SEA_OK;
    for (size_t q = 0; q < count && res == SEA_OK; ++q) {
        if (status[q] != SEA_OK) {
            /* Again, in this thread, for the message. */
            const sea_slope_stats st = sea_moments_stats(&mo[q]);
            sea_error lib = {{0}};
            res = sea_emissivity(optics, SEA_EMIS_AUTO, c->N, &st, c->obs, &emis[q], &lib);
            if (res == SEA_OK)
                res = SEA_ERR_NUMERIC;
            res = sea_fail(err, res, "emissivity of facet %zu: %s", q, lib.msg);
        } else if (!isfinite(emis[q]) || !isfinite(refl[q])) {
            res = sea_fail(err, SEA_ERR_NUMERIC,
                           "emissivity or reflectivity of facet %zu is not finite", q);
        }
    }
    free(status);
    return res;
}

/* Mean, RMS and largest |.| of v - ref. */
static void deviations(const double *v, size_t n, double ref, double *mean, double *rms,
                       double *max)
{
    double s = 0.0, s2 = 0.0, m = 0.0;
    for (size_t q = 0; q < n; ++q) {
        const double d = v[q] - ref;
        s += v[q];
        s2 += d * d;
        m = fmax(m, fabs(d));
    }
    *mean = s / (double)n;
    *rms = sqrt(s2 / (double)n);
    *max = m;
}

static double variance(const sea_moments *mo, size_t n, bool y)
{
    double s = 0.0, s2 = 0.0;
    for (size_t q = 0; q < n; ++q)
        s += y ? mo[q].my : mo[q].mx;
    const double mean = s / (double)n;
    for (size_t q = 0; q < n; ++q) {
        const double d = (y ? mo[q].my : mo[q].mx) - mean;
        s2 += d * d;
    }
    return s2 / (double)n;
}

static void conv_progress(const conv_setup *c, double wind, double L, size_t done, size_t total)
{
    if (!c->progress)
        return;
    fprintf(stderr, "\rconvergence: U=%g m/s L=%g m (%zu/%zu)   ", wind, L, done, total);
    fflush(stderr);
}

/* Every size of one wind: rows[0 .. x2 - x1]. */
static sea_status conv_wind(const conv_setup *c, const sea_optics *optics, double wind,
                            conv_row *rows, size_t *done, size_t total, sea_error *err)
{
    sea_spectrum spec;
    sea_cov2 lr;
    sea_waves *waves = NULL;
    const size_t kmax = (size_t)c->K * (size_t)c->K;
    sea_moments *mo = malloc(kmax * sizeof *mo);
    double *emis = malloc(kmax * sizeof *emis), *refl = malloc(kmax * sizeof *refl);
    sea_status st = SEA_OK;
    if (mo == NULL || emis == NULL || refl == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu facets", kmax);
        goto done;
    }
    if ((st = sea_spectrum_init(wind, c->fetch, sea_cli_radians(c->wind_dir_deg), &spec, err)) !=
            SEA_OK ||
        (st = sea_spectrum_slope_cov(&spec, 0.0, &lr, err)) != SEA_OK)
        goto done;
    /* Low resolution: zero mean, the covariance of every wave (Eq 15). */
    const sea_slope_stats lr_stats = {{0.0, 0.0}, lr};
    double emis_lr, refl_lr;
    sea_error lib = {{0}};
    if ((st = sea_emissivity(optics, SEA_EMIS_AUTO, c->N, &lr_stats, c->obs, &emis_lr, &lib)) !=
        SEA_OK) {
        st = sea_fail(err, st, "low-resolution emissivity at %g m/s: %s", wind, lib.msg);
        goto done;
    }
    refl_lr = sea_reflectivity(c->N, &lr_stats, c->inc, c->obs);

    sea_waves_params p;
    sea_waves_params_default(&p);
    p.finest = SEA_CLI_CONV_FINEST;
    p.seed = c->seed;
    if (c->method != SEA_METHOD_ONE_METER &&
        (st = sea_waves_alloc(&spec, &p, &waves, err)) != SEA_OK)
        goto done;

    for (int x = c->x1; x <= c->x2; ++x) {
        const double L = exp2(x - 1);
        size_t K = (size_t)c->K;
        int n = 0;
        switch (c->method) {
        case SEA_METHOD_VARIABLE_STEP:
            n = 0;
            break;
        case SEA_METHOD_VARIABLE_STEP_2N:
            n = c->n < x - 1 ? c->n : x - 1; /* sub-facets of at least 1 m */
            break;
        case SEA_METHOD_ONE_METER: {
            /* A patch per size that covers the K x K facets, up to 4096 m:
             * fewer facets beyond (the patch never repeats).  Sizes that
             * need the same patch share it: the same parameters would draw
             * the same waves again. */
            double N = sea_cli_pow2_ceil(fmax((double)K * L / SEA_CLI_CONV_FINEST, 2.0));
            if (N > SEA_CLI_CONV_FFT_MAX)
                N = SEA_CLI_CONV_FFT_MAX;
            if ((double)K * L > N * SEA_CLI_CONV_FINEST)
                K = (size_t)fmax(1.0, floor(N * SEA_CLI_CONV_FINEST / L));
            n = x - 1;
            if (waves != NULL && p.fft_size == (size_t)N)
                break;
            sea_waves_free(waves);
            waves = NULL;
            p.kind = SEA_WAVES_FFT;
            p.fft_size = (size_t)N;
            if ((st = sea_waves_alloc(&spec, &p, &waves, err)) != SEA_OK)
                goto done;
            break;
        }
        }
        const size_t count = K * K;
        const sea_rect rect = {L, -(long)(K / 2), -(long)(K / 2), K, K};
        conv_progress(c, wind, L, *done + 1, total);
        if ((st = sea_waves_facets(waves, &rect, n, 0.0, mo, err)) != SEA_OK ||
            (st = conv_optics(c, optics, mo, count, emis, refl, err)) != SEA_OK)
            goto done;
        /* Facet (0, 0), whose lower-left corner is the origin. */
        const size_t origin = (K / 2) * K + K / 2;
        conv_row *r = &rows[x - c->x1];
        r->wind = wind;
        r->x = x;
        r->L = L;
        r->facets = K;
        r->n = n;
        r->emis_lr = emis_lr;
        r->refl_lr = refl_lr;
        r->emis_origin = emis[origin];
        r->refl_origin = refl[origin];
        deviations(emis, count, emis_lr, &r->emis_mean, &r->emis_rms, &r->emis_max);
        deviations(refl, count, refl_lr, &r->refl_mean, &r->refl_rms, &r->refl_max);
        r->var_mx = variance(mo, count, false);
        r->var_my = variance(mo, count, true);
        ++*done;
    }
done:
    sea_waves_free(waves);
    free(mo);
    free(emis);
    free(refl);
    return st;
}

/* Index of the smallest size from which every larger size is within the
 * --converged deviation; n when even the largest is not. */
static size_t conv_converged(const conv_row *rows, size_t n, bool refl, double tol)
{
    size_t first = n;
    for (size_t i = n; i-- > 0;) {
        const double dev = refl ? rows[i].refl_max : rows[i].emis_max;
        const double lr = refl ? rows[i].refl_lr : rows[i].emis_lr;
        if (!(dev <= tol * fabs(lr)))
            break;
        first = i;
    }
    return first;
}

/* The table into af, a temporary file the caller commits with the chart. */
static sea_status conv_csv(const conv_setup *c, const conv_row *rows, size_t nrows,
                           sea_cli_atomic_file *af, sea_error *err)
{
    FILE *f = af->f;
    fprintf(f,
            "# seabake convergence: high- to low-resolution effective emissivity and "
            "reflectivity (Caillault et al. 2007, Fig. 5-6)\n");
    fprintf(f,
            "# wavelength_um=%.10g theta_obs_deg=%.10g phi_obs_deg=%.10g theta_inc_deg=%.10g "
            "phi_inc_deg=%.10g\n",
            c->wavelength_um, c->theta_deg, c->phi_deg, c->inc_deg[0], c->inc_deg[1]);
    fprintf(f, "# seed=%lu method=%s", c->seed, sea_facet_method_name(c->method));
    if (c->method == SEA_METHOD_VARIABLE_STEP_2N)
        fprintf(f, " n=%d", c->n);
    fprintf(f, " generator=%s finest_m=%g facets_per_side=%ld converged=%.10g shadowing=%s\n",
            c->method == SEA_METHOD_ONE_METER ? "fft" : "sinusoids", SEA_CLI_CONV_FINEST, c->K,
            c->tol, sea_shadowing_name(c->shadowing));
    char fetch[32];
    snprintf(fetch, sizeof fetch, isinf(c->fetch) ? "inf" : "%.10g", c->fetch);
    fprintf(f, "# fetch_m=%s wind_dir_deg=%.10g water=%s salinity_g_kg=%s index=%.10g+%.10gi\n",
            fetch, c->wind_dir_deg, c->water, c->salinity, creal(c->N), cimag(c->N));
    fprintf(f, "# dev = HR - LR over the facets; origin = facet (0,0), lower-left corner at the "
               "origin; facets = facets per side; var_m = variance of the facet mean slopes\n");
    fputs("wind_m_s,x,L_m,facets,n,emis_lr,emis_origin,emis_mean,emis_rms_dev,emis_max_dev,"
          "refl_lr,refl_origin,refl_mean,refl_rms_dev,refl_max_dev,var_mx,var_my\n",
          f);
    for (size_t i = 0; i < nrows; ++i) {
        const conv_row *r = &rows[i];
        fprintf(f,
                "%.10g,%d,%.10g,%zu,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,"
                "%.10g,%.10g,%.10g\n",
                r->wind, r->x, r->L, r->facets, r->n, r->emis_lr, r->emis_origin, r->emis_mean,
                r->emis_rms, r->emis_max, r->refl_lr, r->refl_origin, r->refl_mean, r->refl_rms,
                r->refl_max, r->var_mx, r->var_my);
    }
    if (fflush(f) != 0 || ferror(f))
        return sea_fail(err, SEA_ERR_IO, "-o: cannot write '%s'", af->path);
    return SEA_OK;
}

static void conv_table(FILE *out, const conv_setup *c, const conv_row *rows, size_t nrows,
                       size_t per_wind)
{
    fprintf(out, "%7s %3s %6s %6s %3s  %-11s %-11s %-10s  %-11s %-11s %-10s\n", "U10_m_s", "x",
            "L_m", "facets", "n", "emis_lr", "emis_origin", "max_dev/lr", "refl_lr",
            "refl_origin", "max_dev/lr");
    for (size_t i = 0; i < nrows; ++i) {
        const conv_row *r = &rows[i];
        /* A zero LR value (a direction no facet reflects into) has no
         * relative deviation: "-" rather than an infinity. */
        char rel[2][32];
        const double dev[2] = {r->emis_max, r->refl_max}, lr[2] = {r->emis_lr, r->refl_lr};
        for (int q = 0; q < 2; ++q) {
            if (lr[q] != 0.0)
                snprintf(rel[q], sizeof rel[q], "%.3g", dev[q] / fabs(lr[q]));
            else
                snprintf(rel[q], sizeof rel[q], "-");
        }
        fprintf(out, "%7g %3d %6g %6zu %3d  %-11.8f %-11.8f %-10s  %-11.6g %-11.6g %s\n",
                r->wind, r->x, r->L, r->facets, r->n, r->emis_lr, r->emis_origin, rel[0],
                r->refl_lr, r->refl_origin, rel[1]);
    }
    fputc('\n', out);
    const double last_L = exp2(c->x2 - 1);
    for (size_t w = 0; w < nrows / per_wind; ++w) {
        const conv_row *r = &rows[w * per_wind];
        const size_t ie = conv_converged(r, per_wind, false, c->tol);
        const size_t ir = conv_converged(r, per_wind, true, c->tol);
        fprintf(out, "U10 = %g m/s: emissivity ", r->wind);
        if (ie < per_wind)
            fprintf(out, "within %g%% of LR for L >= %g m", 100.0 * c->tol, r[ie].L);
        else
            fprintf(out, "within %g%% of LR not reached by %g m", 100.0 * c->tol, last_L);
        if (ir < per_wind)
            fprintf(out, ", reflectivity for L >= %g m\n", r[ir].L);
        else
            fprintf(out, ", reflectivity not reached by %g m\n", last_L);
    }
}

typedef struct {
    const conv_setup *c;
    const conv_row *rows;
    size_t nrows, per_wind;
} conv_chart;

/* The gnuplot script: two panels, one curve set per wind, the data inline. */
static char *conv_script(const void *ctx)
{
    const conv_chart *cc = ctx;
    const conv_setup *c = cc->c;
    const conv_row *rows = cc->rows;
    const size_t nrows = cc->nrows, per_wind = cc->per_wind;
    sea_cli_script script;
    FILE *f = sea_cli_gnuplot_begin(&script, 1400, 560);
    if (f == NULL)
        return NULL;
    const size_t nwind = nrows / per_wind;
    for (size_t w = 0; w < nwind; ++w) {
        fprintf(f, "$W%zu << EOD\n", w);
        for (size_t i = 0; i < per_wind; ++i) {
            const conv_row *r = &rows[w * per_wind + i];
            fprintf(f, "%d %.10g %.10g %.10g %.10g %.10g %.10g %.10g %.10g\n", r->x,
                    r->emis_origin, r->emis_mean, r->emis_rms, r->emis_lr, r->refl_origin,
                    r->refl_mean, r->refl_rms, r->refl_lr);
        }
        fputs("EOD\n", f);
    }
    fprintf(f,
            "set multiplot layout 1,2 title '%g µm, observation (%g°, %g°), incidence (%g°, "
            "%g°), seed %lu, %s, %ld x %ld facets'\n",
            c->wavelength_um, c->theta_deg, c->phi_deg, c->inc_deg[0], c->inc_deg[1], c->seed,
            sea_facet_method_name(c->method), c->K, c->K);
    fprintf(f, "set xrange [%g:%g]\n", c->x1 - 0.5, c->x2 + 0.5);
    fputs("set xtics 1\nset xlabel 'x   (L = 2^{x-1} m)'\nset grid\n"
          "set key outside bottom center horizontal maxrows 3 font ',9'\n"
          "set x2tics (",
          f);
    for (int x = c->x1; x <= c->x2; ++x)
        fprintf(f, "%s'%g m' %d", x > c->x1 ? ", " : "", exp2(x - 1), x);
    fputs(")\n", f);
    fprintf(f, "set x2range [%g:%g]\n", c->x1 - 0.5, c->x2 + 0.5);
    const char *panel[2] = {"Effective emissivity", "Effective reflectivity (1/sr)"};
    for (int q = 0; q < 2; ++q) {
        const int col = 2 + 4 * q; /* origin, mean, rms, lr */
        fprintf(f, "set title '%s'\nset ylabel '%s'\nplot ", panel[q],
                q == 0 ? "emissivity" : "reflectivity (1/sr)");
        for (size_t w = 0; w < nwind; ++w) {
            const int lc = (int)w + 1;
            const double U = rows[w * per_wind].wind;
            fprintf(f,
                    "%s$W%zu using 1:%d with linespoints lc %d lw 2 pt 7 title 'U10 = %g m/s, "
                    "origin facet', \\\n"
                    "  $W%zu using 1:%d:%d with yerrorbars lc %d pt 6 title 'U10 = %g m/s, mean "
                    "± RMS dev.', \\\n"
                    "  $W%zu using 1:%d with lines lc %d dt 2 lw 2 title 'U10 = %g m/s, LR'",
                    w > 0 ? ", \\\n  " : "", w, col, lc, U, w, col + 1, col + 2, lc, U, w,
                    col + 3, lc, U);
        }
        fputc('\n', f);
    }
    fputs("unset multiplot\nset output\n", f);
    return sea_cli_gnuplot_end(&script);
}

/* All or nothing: DIR/convergence.csv and DIR/convergence.png are written
 * under temporary names and renamed only when both are complete, and the
 * table is printed only then; a failure leaves neither (nor a DIR this run
 * created).  Without gnuplot the chart is skipped: the CSV, which is the
 * result, is kept and the table printed, and the command fails (exit 1). */
static sea_status run_convergence(const sea_cli_args *args, FILE *out, sea_error *err)
{
    conv_setup c;
    memset(&c, 0, sizeof c);
    sea_optics *optics = NULL;
    conv_row *rows = NULL;
    char *csv = NULL, *png = NULL;
    sea_cli_atomic_file csv_f = {NULL, NULL, NULL}, png_f = {NULL, NULL, NULL};
    bool created = false, absent = false;
    sea_status st = conv_parse(args, &c, err);
    if (st != SEA_OK)
        goto done;
    if ((st = sea_cli_make_dir("-o", c.dir, &created, err)) != SEA_OK)
        goto done;
    if ((csv = sea_cli_path_join(c.dir, "convergence.csv")) == NULL ||
        (png = sea_cli_path_join(c.dir, "convergence.png")) == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        goto done;
    }
    /* what a killed run left beside them (marked, its maker gone) */
    sea_cli_clean_stale_files("convergence", csv);
    sea_cli_clean_stale_files("convergence", png);
    const size_t per_wind = (size_t)(c.x2 - c.x1 + 1), nrows = c.winds.n * per_wind;
    rows = calloc(nrows, sizeof *rows);
    if (rows == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu rows", nrows);
        goto done;
    }
    if ((st = sea_optics_alloc(&optics, err)) != SEA_OK)
        goto done;
    sea_optics_set_shadowing(optics, c.shadowing);
    size_t done_rows = 0;
    for (size_t w = 0; w < c.winds.n && st == SEA_OK; ++w)
        st = conv_wind(&c, optics, c.winds.values[w], rows + w * per_wind, &done_rows, nrows, err);
    if (c.progress)
        fputs("\r\033[K", stderr);
    if (st != SEA_OK)
        goto done;
    if ((st = sea_cli_atomic_open(&csv_f, "-o", csv, err)) != SEA_OK ||
        (st = conv_csv(&c, rows, nrows, &csv_f, err)) != SEA_OK)
        goto done;
    const conv_chart cc = {&c, rows, nrows, per_wind};
    st = sea_cli_draw_chart(png, conv_script, &cc, &png_f, &absent, err);
    if (st != SEA_OK && !absent)
        goto done;
    if ((st = sea_cli_atomic_commit(&csv_f, "-o", err)) != SEA_OK)
        goto done;
    created = false; /* DIR holds the result now */
    if (!absent && (st = sea_cli_atomic_commit(&png_f, "-o", err)) != SEA_OK)
        goto done;
    conv_table(out, &c, rows, nrows, per_wind);
    fflush(out);
    if ((st = sea_cli_check_written(out, err)) != SEA_OK)
        goto done;
    if (absent)
        st = sea_fail(err, SEA_ERR_NUMERIC, "gnuplot not found: convergence.csv written, chart "
                                            "not drawn");
done:
    sea_cli_atomic_abort(&csv_f);
    sea_cli_atomic_abort(&png_f);
    if (created)
        rmdir(c.dir);
    sea_optics_free(optics);
    sea_cli_list_free(&c.winds);
    free(rows);
    free(csv);
    free(png);
    return st;
}

/* --------------------------------------------------------------- command */

const sea_cli_command sea_cli_cmd_convergence = {
    "convergence", "high- to low-resolution convergence (paper Fig. 5-6)", SEA_CLI_HELP_CONVERGENCE,
    SEA_CLI_CONVERGENCE_OPTIONS, SEA_CLI_COUNT(SEA_CLI_CONVERGENCE_OPTIONS), run_convergence};
