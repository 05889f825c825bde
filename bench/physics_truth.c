/* physics_truth.c - the physics choices against ray-traced truth, for
 * scripts/bench-physics (the second chart of `make bench`): each model of
 * tests/all_hits.c (the paper's: one hit, Smith's shadowing, one scale;
 * correlated shadowing; two scales; two and three hits; the default) at
 * every row of tests/data/mc_sea_all_hits.csv (every hit over sea-spectrum
 * surfaces, 3-15 m/s, 4 and 10 um, 60-85 deg along and across the wind),
 * made for the surfaces' sea as the unit test makes it (test_mc.c,
 * test_default_all_hits: the two scales split at half of the surfaces' own
 * slope variance), and its CPU time.  Built by make, not installed:
 *
 *   bench/physics_truth [-t SECONDS] TABLE.csv
 *
 * Prints CSV on stdout, a row per model:
 *   model       its name (all_hits_model_params)
 *   worst, rms  the largest and the RMS |model - eps| over the rows
 *   worst_TH, rms_TH  the same over the rows at zenith TH (60, 70, 75, 80,
 *               85 deg: both wavelengths, azimuths and every wind)
 *   rows        rows compared
 *   us_per_eval CPU microseconds of one evaluation (both wavelengths' at
 *               once, as the table's models are made) at the rows'
 *               directions and the low resolution's statistics, single
 *               thread: every row evaluated once first (the two-scale
 *               table fills its rows as queries need them), then all the
 *               rows again and again until SECONDS (0.5) of CPU have passed
 *   evals       the evaluations timed
 *   alloc_ms    CPU milliseconds to make the model of one wind (its tables),
 *               the mean over the winds
 * The errors are deterministic (the same figures as the unit test's claims,
 * tests/claims.csv); the times are a shared machine's (10-30 % noise). */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "all_hits.h"

#define DEG (M_PI / 180.0)
enum { NTH = 5, NWIND_MAX = 16 };
static const double THS[NTH] = { 60, 70, 75, 80, 85 };

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void usage(void)
{
    fprintf(stderr, "usage: physics_truth [-t SECONDS] TABLE.csv\n");
    exit(2);
}

int main(int argc, char **argv)
{
    double min_cpu = 0.5;
    int c;
    while ((c = getopt(argc, argv, "t:")) != -1) {
        if (c == 't') {
            char *end;
            min_cpu = strtod(optarg, &end);
            if (*end != '\0' || !(min_cpu >= 0.0 && min_cpu <= 600.0))
                usage();
        } else
            usage();
    }
    if (optind + 1 != argc)
        usage();
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    sea_init();
    static double x[AH_ROWS_MAX][AH_COLS];
    const int nr = all_hits_read(argv[optind], x, AH_ROWS_MAX);
    if (nr < 0)
        return 1;
    /* the winds: each a run of rows over one set of surfaces */
    int start[NWIND_MAX + 1], nw = 0;
    for (int a = 0; a < nr; a = all_hits_wind_end(x, nr, a)) {
        if (nw == NWIND_MAX) {
            fprintf(stderr, "physics_truth: more than %d winds\n", NWIND_MAX);
            return 1;
        }
        start[nw++] = a;
    }
    start[nw] = nr;
    for (int r = 0; r < nr; r++) {
        int t = 0;
        while (t < NTH && THS[t] != x[r][AH_THETA])
            t++;
        if (t == NTH || (x[r][AH_WL] != 4.0 && x[r][AH_WL] != 10.0)) {
            fprintf(stderr, "physics_truth: row %d: zenith %g or wavelength %g not in the table's\n",
                    r + 1, x[r][AH_THETA], x[r][AH_WL]);
            return 1;
        }
    }
    double complex N[2];
    sea_error err;
    if (all_hits_indices(N, &err) != SEA_OK) {
        fprintf(stderr, "physics_truth: %s\n", err.msg);
        return 1;
    }
    printf("model,worst,rms");
    for (int t = 0; t < NTH; t++)
        printf(",worst_%g,rms_%g", THS[t], THS[t]);
    printf(",rows,us_per_eval,evals,alloc_ms\n");
    for (int k = 0; k < AH_NMODELS; k++) {
        sea_model_params mp;
        const char *name;
        all_hits_model_params(k, &mp, &name);
        all_hits_model m[NWIND_MAX];
        sea_spectrum sp[NWIND_MAX];
        sea_slope_stats lr[NWIND_MAX];
        double alloc = 0.0;
        for (int w = 0; w < nw; w++) {
            const int a = start[w];
            lr[w] = (sea_slope_stats){ { 0, 0 }, { x[a][AH_SXX], x[a][AH_SYY], x[a][AH_SXY] } };
            const double t0 = cpu_seconds();
            if (sea_spectrum_init(x[a][AH_WIND], INFINITY, 0.0, &sp[w], &err) != SEA_OK ||
                all_hits_model_alloc(&mp, &sp[w], &lr[w], x[a][AH_PERIOD], N, 2, &m[w], &err) !=
                    SEA_OK) {
                fprintf(stderr, "physics_truth: %s, %g m/s: %s\n", name, x[a][AH_WIND],
                        err.msg);
                return 1;
            }
            alloc += cpu_seconds() - t0;
        }
        /* the errors, every row once (which also fills the two-scale
         * tables' rows the timing then reads) */
        double worst = 0.0, sq = 0.0, wt[NTH] = { 0 }, st[NTH] = { 0 };
        int nt[NTH] = { 0 };
        for (int w = 0; w < nw; w++)
            for (int r = start[w]; r < start[w + 1]; r++) {
                const sea_dir v = { x[r][AH_THETA] * DEG, x[r][AH_PHI] * DEG };
                double e[2];
                if (all_hits_model_emissivity(&m[w], &lr[w], v, e, &err) != SEA_OK) {
                    fprintf(stderr, "physics_truth: %s, row %d: %s\n", name, r + 1, err.msg);
                    return 1;
                }
                const double d = fabs(e[x[r][AH_WL] == 10.0] - x[r][AH_EPS]);
                int t = 0;
                while (THS[t] != x[r][AH_THETA])
                    t++;
                worst = fmax(worst, d);
                sq += d * d;
                wt[t] = fmax(wt[t], d);
                st[t] += d * d;
                nt[t]++;
            }
        /* the time of one evaluation */
        long evals = 0;
        double sink = 0.0;
        const double t0 = cpu_seconds();
        double used;
        do {
            for (int w = 0; w < nw; w++)
                for (int r = start[w]; r < start[w + 1]; r++) {
                    const sea_dir v = { x[r][AH_THETA] * DEG, x[r][AH_PHI] * DEG };
                    double e[2];
                    all_hits_model_emissivity(&m[w], &lr[w], v, e, NULL);
                    sink += e[0] + e[1];
                    evals++;
                }
            used = cpu_seconds() - t0;
        } while (used < min_cpu);
        for (int w = 0; w < nw; w++)
            all_hits_model_free(&m[w]);
        if (!isfinite(sink)) {
            fprintf(stderr, "physics_truth: %s: an emissivity not finite\n", name);
            return 1;
        }
        printf("%s,%.6e,%.6e", name, worst, sqrt(sq / nr));
        for (int t = 0; t < NTH; t++)
            printf(",%.6e,%.6e", wt[t], nt[t] > 0 ? sqrt(st[t] / nt[t]) : NAN);
        printf(",%d,%.3f,%ld,%.2f\n", nr, 1e6 * used / evals, evals, 1e3 * alloc / nw);
        fflush(stdout);
    }
    return 0;
}
