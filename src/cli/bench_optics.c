/* bench_optics.c - the optics half of `seabake bench`: speed against accuracy
 * of every way the program computes the emissivity (the adaptive reference
 * of Eq 7, Eq 12, the default, fixed product rules of several orders), of
 * the reflectivity and of the energy balance, over one fixed set of
 * conditions, with the chart of seconds per call against the largest error.
 *
 * Errors are against SEA_EMIS_FULL, evaluated on the same conditions in the
 * same run.  Times are wall-clock seconds per call on one thread, the best
 * of a few passes over the whole set (one pass for the slow reference). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* Slope statistics of the set: near-mirror (variance 1e-5) through
 * Cox-Munk at 20 m/s (0.05) to very rough (0.2), anisotropic, correlated,
 * mean slopes up to 2.  mx, my, Cxx, Cyy, Cxy. */
static const double SEA_CLI_BENCH_STATS[][5] = {
    {0.0, 0.0, 1e-5, 1e-5, 0.0},      {0.3, -0.2, 1e-5, 6e-6, 2e-6},
    {0.1, 0.05, 0.02, 0.015, 0.003},  {0.0, 0.0, 0.036, 0.025, 0.0},
    {0.15, -0.15, 0.036, 0.025, 0.004}, {0.0, 0.0, 0.06, 0.04, 0.01},
    {-0.3, 0.4, 0.06, 0.04, -0.01},   {0.0, 0.0, 0.2, 0.15, 0.05},
    {0.5, 0.0, 0.2, 0.2, -0.05},      {2.0, 0.0, 0.02, 0.02, 0.0},
    {-1.2, 1.5, 0.05, 0.03, -0.01},   {1.4, -1.4, 0.2, 0.2, 0.1},
    {0.2, 0.1, 0.001, 0.08, 0.005},   {0.0, 0.45, 0.12, 0.01, 0.02},
};
enum { SEA_CLI_BENCH_NSTATS = sizeof SEA_CLI_BENCH_STATS / sizeof SEA_CLI_BENCH_STATS[0] };
static const double SEA_CLI_BENCH_THETA_DEG[] = {0, 20, 40, 60, 70, 75, 80, 85};
static const double SEA_CLI_BENCH_THETA_QUICK_DEG[] = {0, 40, 70, 85};
static const double SEA_CLI_BENCH_PHI_DEG[] = {0, 35, 100, 225};
static const double SEA_CLI_BENCH_PHI_QUICK_DEG[] = {35, 225};
static const double SEA_CLI_BENCH_WAVELENGTH_UM[] = {4.0, 10.0};
/* The energy balance integrates the reflectance adaptively (milliseconds a
 * call): it runs on every ENERGY_STRIDE-th condition. */
enum { SEA_CLI_BENCH_ENERGY_STRIDE = 8 };
/* The fixed product rules timed: Gauss-Legendre x Gauss-Hermite orders. */
static const int SEA_CLI_BENCH_GL[] = {8, 16, 32, 64, 128};
static const int SEA_CLI_BENCH_GH[] = {4, 8, 16};
/* Passes over the set per timing, the best kept (one for the reference). */
enum { SEA_CLI_BENCH_REPS = 5, SEA_CLI_BENCH_REPS_QUICK = 2 };
/* The goal the default is sized for (issue 6), drawn on the chart. */
static const double SEA_CLI_BENCH_GOAL_ERROR = 1e-4;
static const double SEA_CLI_BENCH_GOAL_SPEEDUP = 100.0;
/* Whole-image rows: the side of the scaled-down scenes (pixels). */
enum { SEA_CLI_BENCH_IMAGE = 96, SEA_CLI_BENCH_IMAGE_QUICK = 32 };
/* Chart floor for an error that is exactly 0 (a log axis has no 0). */
static const double SEA_CLI_BENCH_ERROR_FLOOR = 1e-17;

typedef struct {
    sea_slope_stats st;
    sea_dir v;
    double complex N;
} bench_cond;

/* The condition set: theta x phi x stats x wavelength, as the column
 * `conditions` describes it. */
static sea_status bench_conditions(bool quick, bench_cond **out, size_t *n, char *desc,
                                   size_t desc_size, sea_error *err)
{
    const double *th = quick ? SEA_CLI_BENCH_THETA_QUICK_DEG : SEA_CLI_BENCH_THETA_DEG;
    const double *ph = quick ? SEA_CLI_BENCH_PHI_QUICK_DEG : SEA_CLI_BENCH_PHI_DEG;
    const size_t nth = quick ? 4 : 8, nph = quick ? 2 : 4, nlam = quick ? 1 : 2;
    const size_t sstep = quick ? 2 : 1; /* every other slope case with --quick */
    const size_t nst = (SEA_CLI_BENCH_NSTATS + sstep - 1) / sstep;
    bench_cond *c = malloc(nth * nph * nst * nlam * sizeof *c);
    sea_water *w = NULL;
    double complex N[2];
    sea_status st = sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, err);
    for (size_t l = 0; l < nlam && st == SEA_OK; ++l)
        st = sea_water_index(w, SEA_CLI_BENCH_WAVELENGTH_UM[l] * 1e-6, &N[l], err);
    sea_water_free(w);
    if (st == SEA_OK && c == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the bench conditions");
    if (st != SEA_OK) {
        free(c);
        return st;
    }
    size_t k = 0;
    for (size_t s = 0; s < SEA_CLI_BENCH_NSTATS; s += sstep)
        for (size_t a = 0; a < nth; ++a)
            for (size_t b = 0; b < nph; ++b)
                for (size_t l = 0; l < nlam; ++l) {
                    const double *q = SEA_CLI_BENCH_STATS[s];
                    c[k++] = (bench_cond){{{q[0], q[1]}, {q[2], q[3], q[4]}},
                                          {th[a] * M_PI / 180.0, ph[b] * M_PI / 180.0},
                                          N[l]};
                }
    snprintf(desc, desc_size,
             "%zu: theta %g-%g deg (%zu) x phi (%zu) x %zu slope cases (var 1e-5..0.2 |m| "
             "<= 2) x %s um",
             k, th[0], th[nth - 1], nth, nph, nst, quick ? "4" : "4 and 10");
    *out = c;
    *n = k;
    return SEA_OK;
}

/* What one emissivity row evaluates. */
typedef struct {
    bool fixed;            /* rule, else method */
    sea_emis_method method;
    sea_emis_rule rule;
} emis_case;

static sea_status emis_eval(const sea_optics *p, const emis_case *e, const bench_cond *c,
                            double *out, sea_error *err)
{
    return e->fixed ? sea_emissivity_rule(p, e->rule, c->N, &c->st, c->v, out, err)
                    : sea_emissivity(p, e->method, c->N, &c->st, c->v, out, err);
}

/* Values over the set, and seconds per call (best of reps passes). */
static sea_status emis_pass(const sea_optics *p, const emis_case *e, const bench_cond *c,
                            size_t n, int reps, double *vals, double *seconds, sea_error *err)
{
    *seconds = INFINITY;
    for (int r = 0; r < reps; ++r) {
        const double t0 = sea_cli_seconds();
        for (size_t i = 0; i < n; ++i) {
            sea_status st = emis_eval(p, e, &c[i], &vals[i], err);
            if (st != SEA_OK)
                return st;
        }
        *seconds = fmin(*seconds, (sea_cli_seconds() - t0) / (double)n);
    }
    return SEA_OK;
}

/* Largest and RMS |a - b| over n values. */
static void bench_errors(const double *a, const double *b, size_t n, double *max, double *rms)
{
    double m = 0.0, s = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const double d = fabs(a[i] - b[i]);
        m = fmax(m, d);
        s += d * d;
    }
    *max = m;
    *rms = n > 0 ? sqrt(s / (double)n) : 0.0;
}

static sea_cli_bench_row *bench_add(sea_cli_bench_row *rows, size_t *n, const char *quantity,
                                    const char *method, double seconds, double max, double rms,
                                    const char *conditions)
{
    sea_cli_bench_row *r = &rows[(*n)++];
    memset(r, 0, sizeof *r);
    r->quantity = quantity;
    snprintf(r->method, sizeof r->method, "%s", method);
    r->seconds = seconds;
    r->max_err = max;
    r->rms_err = rms;
    snprintf(r->conditions, sizeof r->conditions, "%s", conditions);
    return r;
}

sea_status sea_cli_bench_optics(bool quick, sea_cli_bench_row **rows_out, size_t *nrows_out,
                                sea_cli_bench_summary *sum, sea_error *err)
{
    enum { NGL = sizeof SEA_CLI_BENCH_GL / sizeof SEA_CLI_BENCH_GL[0] };
    enum { NGH = sizeof SEA_CLI_BENCH_GH / sizeof SEA_CLI_BENCH_GH[0] };
    enum { MAX_ROWS = 3 + 2 + NGL * NGH + 1 + 3 };
    const int reps = quick ? SEA_CLI_BENCH_REPS_QUICK : SEA_CLI_BENCH_REPS;
    sea_optics *p = NULL, *pc = NULL;
    bench_cond *c = NULL;
    double *ref = NULL, *vals = NULL;
    char desc[160], edesc[200];
    size_t n = 0, nrows = 0;
    sea_cli_bench_row *rows = calloc(MAX_ROWS, sizeof *rows);
    sea_status st = rows == NULL ? sea_fail(err, SEA_ERR_NOMEM, "out of memory") : SEA_OK;
    if (st == SEA_OK)
        st = sea_optics_alloc(&p, err);
    if (st == SEA_OK) {
        sea_optics_set_shadowing(p, SEA_SHADOW_SMITH); /* the paper's */
        st = sea_optics_alloc(&pc, err);
    }
    if (st == SEA_OK)
        sea_optics_set_shadowing(pc, SEA_SHADOW_CORRELATED);
    if (st == SEA_OK)
        st = bench_conditions(quick, &c, &n, desc, sizeof desc, err);
    if (st != SEA_OK)
        goto fail;
    ref = malloc(n * sizeof *ref);
    vals = malloc(n * sizeof *vals);
    if (ref == NULL || vals == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the bench values");
        goto fail;
    }

    /* The reference first: every error below is against its values. */
    double sec, mx, rms;
    const emis_case full = {false, SEA_EMIS_FULL, {0, 0}};
    if ((st = emis_pass(p, &full, c, n, 1, ref, &sec, err)) != SEA_OK)
        goto fail;
    snprintf(bench_add(rows, &nrows, "emissivity", "full", sec, 0.0, 0.0, desc)->settings,
             sizeof rows[0].settings, "Eq 7 nested adaptive GSL (reference)");
    sum->full_seconds = sec;

    const emis_case fast = {false, SEA_EMIS_FAST, {0, 0}};
    if ((st = emis_pass(p, &fast, c, n, reps, vals, &sec, err)) != SEA_OK)
        goto fail;
    bench_errors(vals, ref, n, &mx, &rms);
    snprintf(bench_add(rows, &nrows, "emissivity", "fast", sec, mx, rms, desc)->settings,
             sizeof rows[0].settings, "Eq 12 GL 64");
    sum->fast_seconds = sec, sum->fast_max = mx, sum->fast_rms = rms;

    const emis_case deflt = {false, SEA_EMIS_AUTO, {0, 0}};
    if ((st = emis_pass(p, &deflt, c, n, reps, vals, &sec, err)) != SEA_OK)
        goto fail;
    bench_errors(vals, ref, n, &mx, &rms);
    sea_emis_rule lo = {SEA_EMIS_GL_MAX, SEA_EMIS_GH_MAX}, hi = {0, 0};
    for (size_t i = 0; i < n; ++i) {
        const sea_emis_rule r = sea_emissivity_auto_rule(&c[i].st, c[i].v);
        lo.n_gl = r.n_gl < lo.n_gl ? r.n_gl : lo.n_gl;
        lo.n_gh = r.n_gh < lo.n_gh ? r.n_gh : lo.n_gh;
        hi.n_gl = r.n_gl > hi.n_gl ? r.n_gl : hi.n_gl;
        hi.n_gh = r.n_gh > hi.n_gh ? r.n_gh : hi.n_gh;
    }
    snprintf(bench_add(rows, &nrows, "emissivity", "auto", sec, mx, rms, desc)->settings,
             sizeof rows[0].settings, "Eq 7 default: GL %d-%d x GH %d-%d from the spreads",
             lo.n_gl, hi.n_gl, lo.n_gh, hi.n_gh);
    sum->auto_seconds = sec, sum->auto_max = mx, sum->auto_rms = rms;
    sum->conditions = n;

    /* The program's default, correlated shadowing, against its own
     * reference (the same weights, adaptive quadrature); then ref holds
     * Smith's reference again. */
    double *ref_c = malloc(n * sizeof *ref_c);
    if (ref_c == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the bench values");
        goto fail;
    }
    if ((st = emis_pass(pc, &full, c, n, 1, ref_c, &sec, err)) != SEA_OK) {
        free(ref_c);
        goto fail;
    }
    snprintf(bench_add(rows, &nrows, "emissivity", "full", sec, 0.0, 0.0, desc)->settings,
             sizeof rows[0].settings, "Eq 7 adaptive with correlated shadowing (reference)");
    if ((st = emis_pass(pc, &deflt, c, n, reps, vals, &sec, err)) != SEA_OK) {
        free(ref_c);
        goto fail;
    }
    bench_errors(vals, ref_c, n, &mx, &rms);
    free(ref_c);
    snprintf(bench_add(rows, &nrows, "emissivity", "auto", sec, mx, rms, desc)->settings,
             sizeof rows[0].settings, "Eq 7 default with correlated shadowing (the program's)");
    sum->corr_seconds = sec, sum->corr_max = mx;

    for (size_t a = 0; a < NGL; ++a)
        for (size_t b = 0; b < NGH; ++b) {
            const emis_case e = {true, SEA_EMIS_AUTO, {SEA_CLI_BENCH_GL[a], SEA_CLI_BENCH_GH[b]}};
            if ((st = emis_pass(p, &e, c, n, reps, vals, &sec, err)) != SEA_OK)
                goto fail;
            bench_errors(vals, ref, n, &mx, &rms);
            sea_cli_bench_row *r = bench_add(rows, &nrows, "emissivity", "rule", sec, mx, rms, desc);
            snprintf(r->settings, sizeof r->settings, "Eq 7 GL %d x GH %d", e.rule.n_gl,
                     e.rule.n_gh);
        }

    /* Reflectivity: a closed form (Eq 13-14), so a time and no error.  Each
     * view with two incidences: near the mirror and off it. */
    sec = INFINITY;
    double sink = 0.0;
    for (int r = 0; r < reps; ++r) {
        const double t0 = sea_cli_seconds();
        for (size_t i = 0; i < n; ++i) {
            const sea_dir mirror = {c[i].v.theta, c[i].v.phi + M_PI};
            const sea_dir off = {0.7, c[i].v.phi + 2.0};
            sink += sea_reflectivity(c[i].N, &c[i].st, mirror, c[i].v) +
                    sea_reflectivity(c[i].N, &c[i].st, off, c[i].v);
        }
        sec = fmin(sec, (sea_cli_seconds() - t0) / (2.0 * (double)n));
    }
    if (!isfinite(sink)) {
        st = sea_fail(err, SEA_ERR_NUMERIC, "bench: a reflectivity is not finite");
        goto fail;
    }
    snprintf(bench_add(rows, &nrows, "reflectivity", "closed-form", sec, NAN, NAN, desc)->settings,
             sizeof rows[0].settings, "Eq 13-14 at the mirror incidence and 40 deg off");

    /* Energy (Eq 21): emissivity by each method plus the reflectance, whose
     * integral (adaptive outer x 128-node inner) is the same in every row;
     * the error is |total - total with the reference emissivity|. */
    const size_t ne = (n + SEA_CLI_BENCH_ENERGY_STRIDE - 1) / SEA_CLI_BENCH_ENERGY_STRIDE;
    snprintf(edesc, sizeof edesc, "every %dth of %s", SEA_CLI_BENCH_ENERGY_STRIDE, desc);
    static const sea_emis_method emethods[] = {SEA_EMIS_FULL, SEA_EMIS_AUTO, SEA_EMIS_FAST};
    for (size_t m = 0; m < 3; ++m) {
        const double t0 = sea_cli_seconds();
        for (size_t i = 0, j = 0; i < n; i += SEA_CLI_BENCH_ENERGY_STRIDE, ++j) {
            sea_energy en;
            if ((st = sea_energy_balance(p, emethods[m], c[i].N, &c[i].st, c[i].v, &en, err)) !=
                SEA_OK)
                goto fail;
            (m == 0 ? ref : vals)[j] = en.total;
        }
        sec = (sea_cli_seconds() - t0) / (double)ne;
        if (m == 0)
            mx = rms = 0.0;
        else
            bench_errors(vals, ref, ne, &mx, &rms);
        sea_cli_bench_row *r = bench_add(rows, &nrows, "energy", sea_emis_method_name(emethods[m]),
                                         sec, mx, rms, edesc);
        snprintf(r->settings, sizeof r->settings,
                 "emissivity %s + reflectance adaptive x GL 128%s", sea_emis_method_name(emethods[m]),
                 m == 0 ? " (reference)" : "");
    }
    *rows_out = rows;
    *nrows_out = nrows;
    rows = NULL;
fail:
    free(rows);
    free(ref);
    free(vals);
    free(c);
    sea_optics_free(p);
    sea_optics_free(pc);
    return st;
}

bool sea_cli_bench_is_reference(const sea_cli_bench_row *r)
{
    return strcmp(r->method, "full") == 0 || strcmp(r->method, "reference") == 0;
}

/* The emissivity rows other than the reference, for the chart. */
static bool chart_point(const sea_cli_bench_row *r)
{
    return strcmp(r->quantity, "emissivity") == 0 && !sea_cli_bench_is_reference(r);
}

static void chart_label(const sea_cli_bench_row *r, char *buf, size_t size)
{
    if (strcmp(r->method, "rule") == 0) {
        int a = 0, b = 0;
        sscanf(r->settings, "Eq 7 GL %d x GH %d", &a, &b);
        snprintf(buf, size, "%dx%d", a, b);
    } else {
        snprintf(buf, size, "%s", strcmp(r->method, "fast") == 0 ? "fast (Eq 12)" : r->method);
    }
}

char *sea_cli_bench_chart_script(const sea_cli_bench_row *rows, size_t nrows)
{
    sea_cli_script script;
    FILE *f = sea_cli_gnuplot_begin(&script, 1000, 700);
    if (f == NULL)
        return NULL;
    double full = NAN;
    for (size_t i = 0; i < nrows; ++i)
        if (strcmp(rows[i].quantity, "emissivity") == 0 && sea_cli_bench_is_reference(&rows[i]))
            full = rows[i].seconds;
    fputs("$P << EOD\n", f);
    char label[64];
    for (size_t i = 0; i < nrows; ++i)
        if (chart_point(&rows[i])) {
            chart_label(&rows[i], label, sizeof label);
            fprintf(f, "%.6g %.6g \"%s\"\n", rows[i].seconds,
                    fmax(rows[i].max_err, SEA_CLI_BENCH_ERROR_FLOOR), label);
        }
    /* The Pareto front: by increasing time, each point more accurate than
     * every faster one. */
    fputs("EOD\n$F << EOD\n", f);
    const sea_cli_bench_row *front[64];
    size_t nf = 0;
    for (size_t i = 0; i < nrows; ++i) {
        if (!chart_point(&rows[i]))
            continue;
        bool dominated = false;
        for (size_t j = 0; j < nrows && !dominated; ++j)
            dominated = j != i && chart_point(&rows[j]) &&
                        rows[j].seconds <= rows[i].seconds && rows[j].max_err <= rows[i].max_err &&
                        (rows[j].seconds < rows[i].seconds || rows[j].max_err < rows[i].max_err);
        if (!dominated && nf < sizeof front / sizeof front[0])
            front[nf++] = &rows[i];
    }
    for (size_t a = 1; a < nf; ++a) /* insertion sort by time */
        for (size_t b = a; b > 0 && front[b]->seconds < front[b - 1]->seconds; --b) {
            const sea_cli_bench_row *t = front[b];
            front[b] = front[b - 1];
            front[b - 1] = t;
        }
    for (size_t a = 0; a < nf; ++a)
        fprintf(f, "%.6g %.6g\n", front[a]->seconds,
                fmax(front[a]->max_err, SEA_CLI_BENCH_ERROR_FLOOR));
    fputs("EOD\n", f);
    fputs("set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\n"
          "set xlabel 'seconds per evaluation (one thread)'\n"
          "set ylabel 'max |emissivity - Eq 7 reference|'\n"
          "set key bottom left opaque\n",
          f);
    fputs("set title 'Emissivity: speed against accuracy over the bench conditions'\n", f);
    fprintf(f, "set arrow from graph 0, first %g to graph 1, first %g nohead dt 2 lc rgb 'gray40'\n",
            SEA_CLI_BENCH_GOAL_ERROR, SEA_CLI_BENCH_GOAL_ERROR);
    fprintf(f, "set label 'goal: error %g' at graph 0.01, first %g offset 0,0.7 tc rgb 'gray40'\n",
            SEA_CLI_BENCH_GOAL_ERROR, SEA_CLI_BENCH_GOAL_ERROR * 1.3);
    if (isfinite(full) && full > 0.0) {
        const double x = full / SEA_CLI_BENCH_GOAL_SPEEDUP;
        fprintf(f, "set arrow from first %g, graph 0 to first %g, graph 1 nohead dt 2 lc rgb 'gray40'\n",
                x, x);
        fprintf(f, "set label 'full / %g' at first %g, graph 0.97 offset 0.5,0 tc rgb 'gray40'\n",
                SEA_CLI_BENCH_GOAL_SPEEDUP, x);
        fprintf(f, "set arrow from first %g, graph 0 to first %g, graph 1 nohead lw 2 lc rgb 'black'\n",
                full, full);
        fprintf(f,
                "set label 'full (reference) %.3g s' at first %g, graph 0.5 center rotate by 90 "
                "offset -1,0\n",
                full, full);
        fprintf(f, "set xrange [*:%g]\n", full * 2.0);
    }
    fputs("plot $F using 1:2 with lines lw 2 lc rgb '#d62728' title 'Pareto front', \\\n"
          "  $P using 1:2 with points pt 7 ps 1.2 lc rgb '#1f77b4' title 'method / rule GLxGH', \\\n"
          "  $P using 1:2:3 with labels offset 0.8,0.6 left font ',9' notitle\n"
          "set output\n",
          f);
    return sea_cli_gnuplot_end(&script);
}

/* ---------------------------------------------------------------- images */

/* Whole images of the paper's three scenes (examples/fig7.ini, fig8.ini,
 * fig9.ini), scaled down to side x side pixels with the same geometry (so
 * footprints are 500/side times larger and the levels coarser). */
static void bench_fig_scene(int fig, int side, sea_scene *sc)
{
    sea_scene_defaults(sc);
    sc->wind_dir = 90.0 * M_PI / 180.0;
    sc->temperature = 288.0;
    sc->seed = 1;
    sc->sun_azimuth = M_PI;
    sc->sky_temperature = 250.0;
    sc->look_azimuth = M_PI;
    sc->width = sc->height = side;
    sc->wavelength = 4e-6;
    sc->method = SEA_METHOD_VARIABLE_STEP;
    if (fig == 7) {
        sc->wind_speed = 10.0;
        sc->sun_zenith = 0.0;
        sc->altitude = 389.0;
        sc->look_zenith = 0.0;
        sc->hfov = 50.0 * M_PI / 180.0;
        sc->finest = 1.0;
        sc->grid = 256;
    } else {
        sc->wind_speed = 15.0;
        sc->sun_zenith = 40.0 * M_PI / 180.0;
        sc->altitude = fig == 8 ? 500.0 : 1500.0;
        sc->look_zenith = 36.0 * M_PI / 180.0;
        sc->hfov = 80.0 * M_PI / 180.0;
        sc->finest = fig == 8 ? 2.0 : 8.0;
        sc->grid = 512;
    }
}

/* Renders sc once: the radiance into img (allocated here), the wall-clock
 * seconds of prepare and frame into *seconds. */
static sea_status bench_image(const sea_scene *sc, sea_image *img, double *seconds,
                              sea_error *err)
{
    sea_view *r = NULL;
    const double t0 = sea_cli_seconds();
    sea_status st = sea_view_alloc(sc, &r, err);
    if (st == SEA_OK)
        st = sea_image_alloc(sc->width, sc->height, img, err);
    if (st == SEA_OK)
        st = sea_view_render_frame(r, sc->time, img, NULL, NULL, err);
    *seconds = sea_cli_seconds() - t0;
    sea_view_free(r);
    return st;
}

sea_status sea_cli_bench_images(bool quick, int threads, sea_cli_bench_row **rows_out,
                                size_t *nrows_out, sea_error *err)
{
    static const int figs[] = {7, 8, 9};
    static const struct {
        sea_facet_method method;
        int n;
    } cases[] = {{SEA_METHOD_VARIABLE_STEP, 0},    {SEA_METHOD_VARIABLE_STEP_2N, 1},
                 {SEA_METHOD_VARIABLE_STEP_2N, 2}, {SEA_METHOD_VARIABLE_STEP_2N, 3},
                 {SEA_METHOD_ONE_METER, 0}};
    enum { NCASES = sizeof cases / sizeof cases[0], NFIGS = sizeof figs / sizeof figs[0] };
    const int side = quick ? SEA_CLI_BENCH_IMAGE_QUICK : SEA_CLI_BENCH_IMAGE;
    sea_cli_bench_row *rows = calloc(NFIGS * (NCASES + 1), sizeof *rows);
    if (rows == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    size_t n = 0;
    sea_status st = SEA_OK;
    for (size_t f = 0; f < NFIGS && st == SEA_OK; ++f) {
        sea_scene sc;
        bench_fig_scene(figs[f], side, &sc);
        /* The reference: sub-facets down to L0 on every level (one-meter's
         * statistics, but on the same sinusoids as the rows) and the
         * adaptive Eq 7. */
        sea_scene ref_sc = sc;
        ref_sc.method = SEA_METHOD_VARIABLE_STEP_2N;
        ref_sc.n = 20;
        ref_sc.emissivity_method = SEA_EMIS_FULL;
        sea_image ref = {0};
        double ref_s;
        char cond[sizeof rows[0].conditions];
        snprintf(cond, sizeof cond,
                 "fig%d.ini at %dx%d (same geometry); U10=%g m/s; 4 um; relative radiance "
                 "error per pixel; %d threads",
                 figs[f], side, side, sc.wind_speed, threads);
        st = bench_image(&ref_sc, &ref, &ref_s, err);
        if (st == SEA_OK) {
            sea_cli_bench_row *r =
                bench_add(rows, &n, "image", "reference", ref_s, 0.0, 0.0, cond);
            snprintf(r->settings, sizeof r->settings,
                     "fig%d variable-step-2n n=20 (sub-facets to L0) + full Eq 7", figs[f]);
        }
        for (size_t c = 0; c < NCASES && st == SEA_OK; ++c) {
            sea_scene s = sc;
            s.method = cases[c].method;
            s.n = cases[c].n;
            sea_image img = {0};
            double sec;
            st = bench_image(&s, &img, &sec, err);
            if (st == SEA_OK) {
                const size_t np = (size_t)side * (size_t)side;
                double m = 0.0, ss = 0.0;
                for (size_t q = 0; q < np; ++q) {
                    const double d = fabs((double)img.radiance[q] - (double)ref.radiance[q]) /
                                     (double)ref.radiance[q];
                    m = fmax(m, d);
                    ss += d * d;
                }
                sea_cli_bench_row *r =
                    bench_add(rows, &n, "image", sea_facet_method_name(cases[c].method), sec, m,
                              sqrt(ss / (double)np), cond);
                if (cases[c].method == SEA_METHOD_VARIABLE_STEP_2N)
                    snprintf(r->settings, sizeof r->settings, "fig%d n=%d; auto; tolerance %g",
                             figs[f], cases[c].n, s.tolerance);
                else if (cases[c].method == SEA_METHOD_ONE_METER)
                    snprintf(r->settings, sizeof r->settings,
                             "fig%d FFT waves (another realisation); auto; tolerance %g", figs[f],
                             s.tolerance);
                else
                    snprintf(r->settings, sizeof r->settings, "fig%d auto; tolerance %g",
                             figs[f], s.tolerance);
            }
            sea_image_free(&img);
        }
        sea_image_free(&ref);
    }
    if (st != SEA_OK) {
        free(rows);
        return st;
    }
    *rows_out = rows;
    *nrows_out = n;
    return SEA_OK;
}

char *sea_cli_bench_image_chart_script(const sea_cli_bench_row *rows, size_t nrows)
{
    sea_cli_script script;
    FILE *f = sea_cli_gnuplot_begin(&script, 1000, 700);
    if (f == NULL)
        return NULL;
    static const char *const figs[] = {"fig7", "fig8", "fig9"};
    for (size_t k = 0; k < 3; ++k) {
        fprintf(f, "$F%zu << EOD\n", k);
        for (size_t i = 0; i < nrows; ++i) {
            const sea_cli_bench_row *r = &rows[i];
            if (strcmp(r->quantity, "image") != 0 || sea_cli_bench_is_reference(r) ||
                strncmp(r->settings, figs[k], 4) != 0)
                continue;
            int nn = 0;
            char label[32];
            if (sscanf(r->settings + 5, "n=%d", &nn) == 1)
                snprintf(label, sizeof label, "2n n=%d", nn);
            else
                snprintf(label, sizeof label, "%s", r->method);
            fprintf(f, "%.6g %.6g %.6g \"%s\"\n", r->seconds,
                    fmax(r->max_err, SEA_CLI_BENCH_ERROR_FLOOR),
                    fmax(r->rms_err, SEA_CLI_BENCH_ERROR_FLOOR), label);
        }
        fputs("EOD\n", f);
    }
    fputs("set logscale xy\nset format y '10^{%L}'\nset grid\n"
          "set xlabel 'seconds per image (all threads)'\n"
          "set ylabel 'relative radiance error against the reference'\n"
          "set key top right opaque\n"
          "set title 'Whole images (Fig. 7-9 scenes, scaled down): RMS (filled) and max "
          "(open) error'\n"
          "plot for [k=0:2] '$F'.k using 1:3 with points pt 7 ps 1.3 lc k+1 "
          "title sprintf('fig%d RMS', k+7), \\\n"
          "  for [k=0:2] '$F'.k using 1:2 with points pt 6 ps 1.3 lc k+1 "
          "title sprintf('fig%d max', k+7), \\\n"
          "  for [k=0:2] '$F'.k using 1:3:4 with labels offset 0.8,0.5 left font ',8' notitle\n"
          "set output\n",
          f);
    return sea_cli_gnuplot_end(&script);
}
