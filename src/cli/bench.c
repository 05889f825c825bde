/* bench.c - the bench subcommand of seabake: speed of the large-scale
 * wave generators (this file), then speed against accuracy of the optics
 * and of whole images (bench_optics.c); tables on standard output,
 * DIR/bench.csv and two gnuplot charts. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli.h"

/* The speed target of the program's default emissivity (correlated
 * shadowing), per call on one thread, at its accuracy (issue 14). */
static const double SEA_CLI_BENCH_EMIS_TARGET_S = 5e-7, SEA_CLI_BENCH_EMIS_TARGET_ERR = 1e-6;

/* ------------------------------------------------------------ constants */

/* The bench: U10 = 10 m/s, facets of 4 m. */
static const double SEA_CLI_BENCH_WIND = 10.0;
static const double SEA_CLI_BENCH_FACET = 4.0;
/* Side of the sub-rectangle sampled with the converted sinusoids. */
#define SEA_CLI_BENCH_SUB 32

/* ------------------------------------------------------------ help text */

static const char SEA_CLI_HELP_BENCH[] =
    "Usage: seabake bench [--quick] [-o DIR] [--threads N]\n"
    "\n"
    "Speed of the large-scale wave generators (best of 3 runs, 1 with --quick):\n"
    "facets per second of each method at U10 = 10 m/s, L = 4 m, and the cost of\n"
    "an FFT plan's waves summed as sinusoids against the FFT itself.  Then the\n"
    "optics on one thread over a fixed set of conditions (896; 56 with --quick):\n"
    "seconds per call and max/RMS error against the adaptive Eq 7 reference of\n"
    "the emissivity by full, fast (Eq 12), auto (the default) and fixed product\n"
    "rules GL 8..128 x GH 4..16, of the reflectivity and of the energy balance.\n"
    "Then whole images of the scenes of examples/fig7-9.ini scaled down to 96 x 96\n"
    "pixels (32 x 32 with --quick): seconds per image and max/RMS relative radiance\n"
    "error against a reference (sub-facets down to L0 on the same waves and the\n"
    "adaptive Eq 7) of variable-step, variable-step-2n n = 1, 2, 3 and one-meter.\n"
    "Prints tables and writes DIR/bench.csv, DIR/speed_accuracy.png (optics) and\n"
    "DIR/image_speed_accuracy.png (images) with gnuplot, all or nothing: the\n"
    "tables are printed at the end and a failure leaves no file (without gnuplot:\n"
    "the CSV and the tables, no chart, exit status 1).\n"
    "\n"
    "  --quick             smaller sizes and condition set, fewer runs\n"
    "  -o DIR              output directory, created if missing (its parent must\n"
    "                      exist); default .\n"
    "  --threads N         OpenMP threads, 1 to 4 x the online CPUs (at most 1024);\n"
    "                      default: the OpenMP default\n"
    "\n"
    "CSV columns: quantity,method,settings,seconds_per_call,max_error,rms_error,\n"
    "  conditions (waves: seconds per facet or cell; empty errors: no reference).\n";

static int max_threads(void)
{
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

static const sea_cli_option SEA_CLI_BENCH_OPTIONS[] = {
    {"quick", SEA_CLI_OPT_FLAG}, {"o", SEA_CLI_OPT_SHORT}, {"threads", 0}};

typedef struct {
    const char *method;
    char settings[128];
    size_t facets;
    double seconds;
} bench_row;

static void bench_print(FILE *out, const bench_row *r, int threads)
{
    fprintf(out, "%-6s %-18s %-46s %9zu %10.4g %11.4g %3d\n", "waves", r->method, r->settings,
            r->facets, r->seconds, (double)r->facets / r->seconds, threads);
    fflush(out);
}

/* Facets per second of one method: the plan is made once (its time is in
 * the settings), the facets computed reps times, the best time kept. */
static sea_status bench_facets(const sea_spectrum *spec, sea_waves_kind kind, size_t fft_size,
                               sea_facet_method method, int n_arg, size_t side, int reps,
                               bench_row *row, sea_error *err)
{
    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = kind;
    p.finest = 1.0;
    if (kind == SEA_WAVES_FFT)
        p.fft_size = fft_size;
    sea_waves *w = NULL;
    sea_moments *mo = NULL;
    int n;
    const double t0 = sea_cli_seconds();
    sea_status st = sea_waves_alloc(spec, &p, &w, err);
    const double plan = sea_cli_seconds() - t0;
    if (st == SEA_OK)
        st = sea_facet_method_n(w, method, n_arg, SEA_CLI_BENCH_FACET, &n, err);
    if (st == SEA_OK)
        st = sea_check_size(side * side, sizeof *mo, "bench facet moments", err);
    if (st != SEA_OK)
        goto done;
    if ((mo = malloc(side * side * sizeof *mo)) == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu x %zu facets", side, side);
        goto done;
    }
    const sea_rect rect = {SEA_CLI_BENCH_FACET, -(long)(side / 2), -(long)(side / 2), side, side};
    row->method = sea_facet_method_name(method);
    row->facets = side * side;
    row->seconds = INFINITY;
    for (int r = 0; r < reps && st == SEA_OK; ++r) {
        const double t1 = sea_cli_seconds();
        st = sea_waves_facets(w, &rect, n, 0.0, mo, err);
        row->seconds = fmin(row->seconds, sea_cli_seconds() - t1);
    }
    if (kind == SEA_WAVES_FFT)
        snprintf(row->settings, sizeof row->settings, "fft N=%zu L=%gm n=%d U10=%g plan=%.3gs",
                 fft_size, SEA_CLI_BENCH_FACET, n, SEA_CLI_BENCH_WIND, plan);
    else
        snprintf(row->settings, sizeof row->settings,
                 "sinusoids %zu waves L=%gm n=%d U10=%g plan=%.3gs", sea_waves_count(w),
                 SEA_CLI_BENCH_FACET, n, SEA_CLI_BENCH_WIND, plan);
done:
    free(mo);
    sea_waves_free(w);
    return st;
}

/* An FFT plan's whole grid at step L0, against the same waves summed as
 * sinusoids on a 32 x 32 corner of it: time per cell and agreement. */
static sea_status bench_fft_vs_sinusoids(const sea_spectrum *spec, size_t N, int reps,
                                         bench_row rows[2], double *max_rel_diff,
                                         sea_error *err)
{
    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = SEA_WAVES_FFT;
    p.finest = 1.0;
    p.fft_size = N;
    sea_waves *fft = NULL, *sin = NULL;
    double *full = NULL, *sub = NULL;
    const size_t S = SEA_CLI_BENCH_SUB;
    sea_status st = sea_waves_alloc(spec, &p, &fft, err);
    if (st == SEA_OK)
        st = sea_waves_to_sinusoids(fft, &sin, err);
    if (st == SEA_OK)
        st = sea_check_size(3 * N * N, sizeof(double), "bench FFT grid", err);
    if (st != SEA_OK)
        goto done;
    full = malloc(3 * N * N * sizeof *full);
    sub = malloc(3 * S * S * sizeof *sub);
    if (full == NULL || sub == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu grid", N, N);
        goto done;
    }
    const sea_rect rf = {1.0, -(long)(N / 2), -(long)(N / 2), N, N};
    const sea_rect rs = {1.0, -(long)(S / 2), -(long)(S / 2), S, S};
    rows[0] = (bench_row){"fft-sample", "", N * N, INFINITY};
    rows[1] = (bench_row){"sinusoids-sample", "", S * S, INFINITY};
    for (int r = 0; r < reps && st == SEA_OK; ++r) {
        const double t0 = sea_cli_seconds();
        st = sea_waves_sample(fft, &rf, 0.0, full, full + N * N, full + 2 * N * N, err);
        rows[0].seconds = fmin(rows[0].seconds, sea_cli_seconds() - t0);
    }
    for (int r = 0; r < reps && st == SEA_OK; ++r) {
        const double t0 = sea_cli_seconds();
        st = sea_waves_sample(sin, &rs, 0.0, sub, sub + S * S, sub + 2 * S * S, err);
        rows[1].seconds = fmin(rows[1].seconds, sea_cli_seconds() - t0);
    }
    if (st != SEA_OK)
        goto done;
    /* Largest difference of each field over the corner, relative to the
     * field's largest magnitude over the whole grid. */
    *max_rel_diff = 0.0;
    for (int q = 0; q < 3; ++q) {
        const double *F = full + (size_t)q * N * N, *G = sub + (size_t)q * S * S;
        double scale = 0.0, diff = 0.0;
        for (size_t i = 0; i < N * N; ++i)
            scale = fmax(scale, fabs(F[i]));
        for (size_t j = 0; j < S; ++j)
            for (size_t i = 0; i < S; ++i) {
                const size_t fj = (size_t)(rs.j0 - rf.j0) + j, fi = (size_t)(rs.i0 - rf.i0) + i;
                diff = fmax(diff, fabs(F[fj * N + fi] - G[j * S + i]));
            }
        *max_rel_diff = fmax(*max_rel_diff, scale > 0.0 ? diff / scale : diff);
    }
    snprintf(rows[0].settings, sizeof rows[0].settings, "fft N=%zu step=1m %zu modes U10=%g", N,
             sea_waves_count(fft), SEA_CLI_BENCH_WIND);
    snprintf(rows[1].settings, sizeof rows[1].settings,
             "same waves as sinusoids %zux%zu cells max_rel_diff=%.2g", S, S, *max_rel_diff);
done:
    free(full);
    free(sub);
    sea_waves_free(sin);
    sea_waves_free(fft);
    return st;
}

typedef struct {
    const sea_cli_bench_row *rows;
    size_t n;
} bench_chart;

static char *bench_chart_script(const void *ctx)
{
    const bench_chart *bc = ctx;
    return sea_cli_bench_chart_script(bc->rows, bc->n);
}

static char *bench_image_chart_script(const void *ctx)
{
    const bench_chart *bc = ctx;
    return sea_cli_bench_image_chart_script(bc->rows, bc->n);
}

/* All or nothing, as convergence: the tables go to memory and are printed
 * at the end; bench.csv and the charts are written under temporary names
 * and renamed only when all are complete.  Without gnuplot the CSV and the
 * tables are kept and the command fails (exit 1). */
static sea_status run_bench(const sea_cli_args *args, FILE *stdout_f, sea_error *err)
{
    const bool quick = sea_cli_given(args, "quick");
    const char *dir = sea_cli_args_get(args, "o");
    char *csv = NULL, *png1 = NULL, *png2 = NULL;
    char *text = NULL;
    size_t text_len = 0;
    FILE *out = NULL;
    bool created = false, absent = false;
    sea_cli_atomic_file af = {NULL, NULL, NULL}, chart1 = {NULL, NULL, NULL},
                        chart2 = {NULL, NULL, NULL};
    enum { NROWS = 6 };
    bench_row rows[NROWS];
    size_t nrows = 0;
    double diff = 0.0;
    sea_spectrum spec;
    sea_cli_bench_row *orows = NULL, *irows = NULL;
    size_t nopt = 0, nimg = 0;
    sea_cli_bench_summary sum;
    sea_status st = sea_cli_opt_threads(args, err);
    if (st != SEA_OK)
        return st;
    if (dir == NULL)
        dir = ".";
    if ((st = sea_cli_make_dir("-o", dir, &created, err)) != SEA_OK)
        return st;
    if ((csv = sea_cli_path_join(dir, "bench.csv")) == NULL ||
        (png1 = sea_cli_path_join(dir, "speed_accuracy.png")) == NULL ||
        (png2 = sea_cli_path_join(dir, "image_speed_accuracy.png")) == NULL ||
        (out = open_memstream(&text, &text_len)) == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        goto done;
    }
    /* what a killed run left beside them (marked, its maker gone) */
    sea_cli_clean_stale_files("bench", csv);
    sea_cli_clean_stale_files("bench", png1);
    sea_cli_clean_stale_files("bench", png2);
    const int threads = max_threads(), reps = quick ? 1 : 3;
    const size_t side = quick ? 256 : 1024, patch = quick ? 1024 : 4096, N = quick ? 128 : 256;
    if ((st = sea_spectrum_init(SEA_CLI_BENCH_WIND, INFINITY, 0.0, &spec, err)) != SEA_OK)
        goto done;

    fprintf(out, "%-6s %-18s %-46s %9s %10s %11s %3s\n", "section", "method", "settings",
            "facets", "seconds", "facets/s", "thr");
    static const struct {
        sea_waves_kind kind;
        sea_facet_method method;
        int n;
    } cases[] = {{SEA_WAVES_SINUSOIDS, SEA_METHOD_VARIABLE_STEP, 0},
                 {SEA_WAVES_SINUSOIDS, SEA_METHOD_VARIABLE_STEP_2N, 2},
                 {SEA_WAVES_FFT, SEA_METHOD_ONE_METER, 0},
                 {SEA_WAVES_FFT, SEA_METHOD_VARIABLE_STEP, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        if ((st = bench_facets(&spec, cases[i].kind, patch, cases[i].method, cases[i].n, side,
                               reps, &rows[nrows], err)) != SEA_OK)
            goto done;
        bench_print(out, &rows[nrows++], threads);
    }
    if ((st = bench_fft_vs_sinusoids(&spec, N, reps, &rows[nrows], &diff, err)) != SEA_OK)
        goto done;
    bench_print(out, &rows[nrows++], threads);
    bench_print(out, &rows[nrows++], threads);
    const double per_fft = rows[4].seconds / (double)rows[4].facets;
    const double per_sin = rows[5].seconds / (double)rows[5].facets;
    fprintf(out,
            "\nFFT to sinusoids at equal spectrum resolution (N = %zu, step 1 m): FFT %.3g s per "
            "cell, sinusoids %.3g s per cell, ratio %.4g; max |difference| %.3g relative\n",
            N, per_fft, per_sin, per_sin / per_fft, diff);

    /* The optics: speed against accuracy, one thread. */
    fputs("\nOptics, one thread, errors against the adaptive Eq 7 reference (full):\n", out);
    fprintf(out, "%-12s %-11s %-52s %10s %10s %10s\n", "quantity", "method", "settings",
            "s/call", "max err", "rms err");
    if ((st = sea_cli_bench_optics(quick, &orows, &nopt, &sum, err)) != SEA_OK)
        goto done;
    for (size_t i = 0; i < nopt; ++i) {
        const sea_cli_bench_row *r = &orows[i];
        fprintf(out, "%-12s %-11s %-52s %10.3g ", r->quantity, r->method, r->settings,
                r->seconds);
        /* No reference (the closed-form reflectivity): "-", as bench.csv
         * leaves the fields empty; seabake never prints NaN. */
        if (isnan(r->max_err))
            fprintf(out, "%10s %10s\n", "-", "-");
        else
            fprintf(out, "%10.3g %10.3g\n", r->max_err, r->rms_err);
    }
    fprintf(out,
            "\nDefault emissivity (auto) over %zu conditions, theta <= 85 deg: %.3g s per call, "
            "%.4g times faster than full (%.3g s); max |error| %.3g, RMS %.3g\n"
            "With correlated shadowing (the program's default): %.3g s per call (%.3g times "
            "Smith's), max |error| %.3g against its reference; target %.3g s at %.3g: ratio "
            "target / time %.2f (> 1: met)\n"
            "Eq 12 (fast): %.3g s per call, %.4g times faster than full; max |error| %.3g, "
            "RMS %.3g\n",
            sum.conditions, sum.auto_seconds, sum.full_seconds / sum.auto_seconds,
            sum.full_seconds, sum.auto_max, sum.auto_rms, sum.corr_seconds,
            sum.corr_seconds / sum.auto_seconds, sum.corr_max, SEA_CLI_BENCH_EMIS_TARGET_S,
            SEA_CLI_BENCH_EMIS_TARGET_ERR, SEA_CLI_BENCH_EMIS_TARGET_S / sum.corr_seconds,
            sum.fast_seconds,
            sum.full_seconds / sum.fast_seconds, sum.fast_max, sum.fast_rms);
    fflush(out);

    /* Whole images: the paper's scenes, scaled down. */
    if ((st = sea_cli_bench_images(quick, threads, &irows, &nimg, err)) != SEA_OK)
        goto done;
    fputs("\nWhole images, relative radiance error against the reference (the first row of "
          "each scene):\n",
          out);
    fprintf(out, "%-17s %-66s %10s %10s %10s\n", "method", "settings", "s/image", "max err",
            "rms err");
    for (size_t i = 0; i < nimg; ++i) {
        const sea_cli_bench_row *r = &irows[i];
        fprintf(out, "%-17s %-66s %10.3g %10.3g %10.3g\n", r->method, r->settings, r->seconds,
                r->max_err, r->rms_err);
    }
    if (nimg > 0)
        fprintf(out, "(%s)\n", irows[0].conditions);
    fflush(out);

    if ((st = sea_cli_atomic_open(&af, "-o", csv, err)) != SEA_OK)
        goto done;
    fputs("quantity,method,settings,seconds_per_call,max_error,rms_error,conditions\n", af.f);
    for (size_t i = 0; i < nrows; ++i) {
        /* Per facet (per cell for the samplers); the one error is the
         * sinusoids' largest difference from the FFT on the same cells. */
        fprintf(af.f, "waves,%s,%s %zu facets,%.6g,", rows[i].method, rows[i].settings,
                rows[i].facets, rows[i].seconds / (double)rows[i].facets);
        if (i == 5)
            fprintf(af.f, "%.6g,", diff);
        else
            fputs(",", af.f);
        fprintf(af.f, ",U10=%g m/s; %d threads\n", SEA_CLI_BENCH_WIND, threads);
    }
    for (size_t i = 0; i < nopt; ++i) {
        const sea_cli_bench_row *r = &orows[i];
        fprintf(af.f, "%s,%s,%s,%.6g,", r->quantity, r->method, r->settings, r->seconds);
        if (isnan(r->max_err))
            fputs(",,", af.f);
        else
            fprintf(af.f, "%.6g,%.6g,", r->max_err, r->rms_err);
        fprintf(af.f, "%s\n", r->conditions);
    }
    for (size_t i = 0; i < nimg; ++i) {
        const sea_cli_bench_row *r = &irows[i];
        fprintf(af.f, "%s,%s,%s,%.6g,%.6g,%.6g,%s\n", r->quantity, r->method, r->settings,
                r->seconds, r->max_err, r->rms_err, r->conditions);
    }
    if (fflush(af.f) != 0 || ferror(af.f)) {
        st = sea_fail(err, SEA_ERR_IO, "-o: cannot write '%s'", csv);
        goto done;
    }
    const bench_chart bc = {orows, nopt};
    st = sea_cli_draw_chart(png1, bench_chart_script, &bc, &chart1, &absent, err);
    /* Seconds per image and per-pixel errors do not share the optics'
     * scales: a second chart. */
    const bench_chart bi = {irows, nimg};
    if (st == SEA_OK)
        st = sea_cli_draw_chart(png2, bench_image_chart_script, &bi, &chart2, &absent, err);
    if (st != SEA_OK && !absent)
        goto done;
    if ((st = sea_cli_atomic_commit(&af, "-o", err)) != SEA_OK)
        goto done;
    created = false; /* DIR holds the result now */
    if (!absent && ((st = sea_cli_atomic_commit(&chart1, "-o", err)) != SEA_OK ||
                    (st = sea_cli_atomic_commit(&chart2, "-o", err)) != SEA_OK))
        goto done;
    if (fclose(out) != 0) {
        out = NULL;
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the tables");
        goto done;
    }
    out = NULL;
    fwrite(text, 1, text_len, stdout_f);
    fflush(stdout_f);
    if ((st = sea_cli_check_written(stdout_f, err)) != SEA_OK)
        goto done;
    if (absent)
        st = sea_fail(err, SEA_ERR_NUMERIC, "gnuplot not found: bench.csv written, charts not "
                                            "drawn");
done:
    sea_cli_atomic_abort(&af);
    sea_cli_atomic_abort(&chart1);
    sea_cli_atomic_abort(&chart2);
    if (out != NULL)
        fclose(out);
    free(text);
    if (created)
        rmdir(dir);
    free(orows);
    free(irows);
    free(csv);
    free(png1);
    free(png2);
    return st;
}

/* --------------------------------------------------------------- command */

const sea_cli_command sea_cli_cmd_bench = {
    "bench", "speed of the wave generators; speed against accuracy of the optics",
    SEA_CLI_HELP_BENCH, SEA_CLI_BENCH_OPTIONS, SEA_CLI_COUNT(SEA_CLI_BENCH_OPTIONS), run_bench};
