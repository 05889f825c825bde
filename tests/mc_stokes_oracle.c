/* mc_stokes_oracle.c - writes tests/data/mc_stokes.csv: the Stokes
 * emissivity of a wind-roughened sea by Monte Carlo ray tracing with
 * polarisation followed through every hit (tests/mc_stokes.c), next to the
 * one-hit model's (sea_polar_emissivity, the default optics, SEA_EMIS_AUTO).
 * A couple of minutes of CPU; run in the build directory and copied:
 *
 *   tests/mc_stokes_oracle -o ../tests/data/mc_stokes.csv
 *
 * As tests/mc_oracle.c: for each wind the target is the low-resolution
 * slope covariance (wind along x, mean slope 0); each seed is one periodic
 * Gaussian-correlated surface whose triangle slopes have it exactly; each
 * view traces `rays` rays over it, the same paths for both wavelengths.
 * Standard errors are those of the mean of the per-seed means.  The two
 * routes of mc_stokes.h (forward Mueller, reciprocal Jones) are compared
 * ray by ray: their largest difference goes into the header. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mc_stokes.h"

enum { MAXL = MC_LIST_MAX };

static void usage(void)
{
    fprintf(stderr, "usage: mc_stokes_oracle [-n GRID] [-l ELL_CELLS] [-s SEEDS] [-r RAYS_PER_SEED]\n"
                    "                        [-w WINDS] [-L WAVELENGTHS_UM] [-t THETAS_DEG]\n"
                    "                        [-p PHIS_DEG] [-S FIRST_SEED] [-o FILE]\n");
    exit(2);
}

int main(int argc, char **argv)
{
    mc_grid_options o = { .n = 512, .seeds = 16, .ell = 8, .rays = 30000, .seed0 = 1,
                          .winds = { 5, 10, 15 }, .wls = { 4, 10 },
                          .ths = { 60, 70, 75, 80, 85 }, .phs = { 0, 45 },
                          .nw = 3, .nl = 2, .nt = 5, .np = 2 };
    if (mc_grid_options_parse(argc, argv, &o) != 0)
        usage();
    const int n = o.n, seeds = o.seeds, nw = o.nw, nl = o.nl, nt = o.nt, np = o.np;
    const double ell = o.ell, *winds = o.winds, *wls = o.wls, *ths = o.ths, *phs = o.phs;
    const long rays = o.rays;
    const unsigned long seed0 = o.seed0;
    const char *outpath = o.outpath;
    sea_init();
    const clock_t c0 = clock();
    const time_t wall0 = time(NULL);
    sea_error err;
    sea_water *water = NULL;
    sea_optics *P = NULL;
    double complex N[MC_MAXWL];
    if (sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &water, &err) != SEA_OK ||
        sea_optics_alloc(&P, &err) != SEA_OK) {
        fprintf(stderr, "mc_stokes_oracle: %s\n", err.msg);
        return 1;
    }
    for (int l = 0; l < nl; l++)
        if (sea_water_index(water, wls[l] * 1e-6, &N[l], &err) != SEA_OK) {
            fprintf(stderr, "mc_stokes_oracle: %s\n", err.msg);
            return 1;
        }
    const int ndir = nt * np;
    /* per wind, direction, wavelength, seed: the per-seed means of
     * e (I, Q, U, V) and e1 (I, Q, U) and the DoLPs */
    enum { NV = 9 };
    const size_t cells = (size_t)nw * ndir * nl * seeds;
    double *val = calloc(cells * NV, sizeof *val);
    double *multi = calloc((size_t)nw * ndir * seeds, sizeof *multi);
    double max_route = 0, max_cov_err = 0;
    long leaks = 0, stopped = 0;
    if (!val || !multi)
        return 1;
#define AT(w, d, l, s) ((((size_t)(w) * ndir + (d)) * nl + (l)) * seeds + (s))
    sea_cov2 cov[MAXL];
    for (int w = 0; w < nw; w++) {
        sea_spectrum sp;
        if (sea_spectrum_init(winds[w], INFINITY, 0.0, &sp, &err) != SEA_OK ||
            sea_spectrum_slope_cov(&sp, 0.0, &cov[w], &err) != SEA_OK) {
            fprintf(stderr, "mc_stokes_oracle: %s\n", err.msg);
            return 1;
        }
        for (int s = 0; s < seeds; s++) {
            mc_surface surf;
            const unsigned long sd = seed0 + (unsigned long)s;
            if (mc_surface_gaussian(&surf, n, ell, &cov[w], sd)) {
                fprintf(stderr, "mc_stokes_oracle: cannot build the surface\n");
                return 1;
            }
            double ce = fmax(fabs(surf.cov.xx / cov[w].xx - 1), fabs(surf.cov.yy / cov[w].yy - 1));
            ce = fmax(ce, fabs(surf.cov.xy) / sqrt(cov[w].xx * cov[w].yy));
            max_cov_err = fmax(max_cov_err, ce);
            for (int d = 0; d < ndir; d++) {
                const sea_dir v = { ths[d / np] * M_PI / 180, phs[d % np] * M_PI / 180 };
                mc_stokes_tally T;
                if (mc_trace_stokes(&surf, v, N, nl, rays, sd * 1000003UL + (unsigned long)d,
                                    &T)) {
                    fprintf(stderr, "mc_stokes_oracle: bad trace arguments\n");
                    return 1;
                }
                for (int l = 0; l < nl; l++) {
                    double *x = &val[AT(w, d, l, s) * NV];
                    for (int m = 0; m < 4; m++)
                        x[m] = T.e[l][m] / rays;
                    for (int m = 0; m < 3; m++)
                        x[4 + m] = T.e1[l][m] / rays;
                    x[7] = hypot(x[1], x[2]) / x[0];
                    x[8] = hypot(x[5], x[6]) / x[4];
                }
                multi[((size_t)w * ndir + d) * seeds + s] = (double)T.multi / rays;
                max_route = fmax(max_route, T.max_route_diff);
                leaks += T.leaks;
                stopped += T.stopped;
            }
            mc_surface_free(&surf);
            fprintf(stderr, "mc_stokes_oracle: wind %g m/s, seed %d of %d (%.0f s CPU)\n",
                    winds[w], s + 1, seeds, (double)(clock() - c0) / CLOCKS_PER_SEC);
        }
    }
    const double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
    FILE *f = outpath ? fopen(outpath, "w") : stdout;
    if (f == NULL) {
        perror(outpath);
        return 1;
    }
    char date[64];
    strftime(date, sizeof date, "%Y-%m-%d", gmtime(&wall0));
    fprintf(f, "# Stokes emissivity of a wind-roughened sea by Monte Carlo ray tracing with\n"
               "# polarisation followed through every hit (tests/mc_stokes.c), against the\n"
               "# one-hit model (sea_polar_emissivity, default optics, SEA_EMIS_AUTO).\n"
               "# Generated by tests/mc_stokes_oracle.c on %s:\n#  ", date);
    for (int a = 0; a < argc; a++)
        fprintf(f, " %s", a == 0 ? "tests/mc_stokes_oracle" : argv[a]);
    fprintf(f, "\n# Surfaces: periodic Gaussian-correlated heights on a %d x %d grid, correlation\n"
               "# length %g cells, two triangles per cell, triangle slope covariance = the\n"
               "# low-resolution covariance of sea_spectrum_slope_cov(kc = 0) (wind along x,\n"
               "# fully developed, mean slope 0) to %.1e relative; seeds %lu..%lu (%d surfaces\n"
               "# per wind), %ld rays per seed and direction, the same paths for every\n"
               "# wavelength.  Sea water: Hale & Querry, salinity 35.  Sky at 0 K.\n"
               "# Frame: seabake.h POLARISATION (+Q vertical, in the view's plane).\n"
               "# I, Q, U: all hits; V: circular part (all hits); dolp = sqrt(Q^2 + U^2) / I of\n"
               "# the means; I1, Q1, U1, dolp1: the first hit's emission alone; _se: standard\n"
               "# error over the seeds (a dolp's from its per-seed values); multi: fraction of\n"
               "# rays hitting twice or more; model_*: sea_polar_emissivity today.\n"
               "# Forward (Mueller) and reciprocal (Jones) routes: largest difference per ray\n"
               "# %.1e.  CPU time %.0f s (%d threads' total); leaks %ld, stopped rays %ld.\n",
            n, n, ell, max_cov_err, seed0, seed0 + seeds - 1, seeds, rays, max_route, cpu,
            mc_threads(), leaks, stopped);
    fprintf(f, "wind_ms,wavelength_um,theta_deg,phi_deg,sxx,syy,I,I_se,Q,Q_se,U,U_se,V,dolp,"
               "dolp_se,I1,Q1,U1,dolp1,dolp1_se,multi,model_I,model_Q,model_U,model_dolp\n");
    fprintf(stderr, "\nDoLP x 1e-3: model - first hit, model - all hits (+- se)\n");
    double *col = malloc(sizeof(double) * (size_t)seeds);
    for (int w = 0; w < nw; w++)
        for (int l = 0; l < nl; l++)
            for (int d = 0; d < ndir; d++) {
                const double th = ths[d / np], ph = phs[d % np];
                double m[NV], se[NV], mu, mu_se;
                for (int k = 0; k < NV; k++) {
                    for (int s = 0; s < seeds; s++)
                        col[s] = val[AT(w, d, l, s) * NV + k];
                    mc_mean_se(col, seeds, &m[k], &se[k]);
                }
                for (int s = 0; s < seeds; s++)
                    col[s] = multi[((size_t)w * ndir + d) * seeds + s];
                mc_mean_se(col, seeds, &mu, &mu_se);
                const sea_slope_stats st = { { 0, 0 }, cov[w] };
                sea_stokes e;
                if (sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N[l], &st,
                                         (sea_dir){ th * M_PI / 180, ph * M_PI / 180 }, &e,
                                         &err) != SEA_OK) {
                    fprintf(stderr, "mc_stokes_oracle: %s\n", err.msg);
                    return 1;
                }
                const double dolp = hypot(m[1], m[2]) / m[0], dolp1 = hypot(m[4 + 1], m[4 + 2]) / m[4];
                fprintf(f,
                        "%g,%g,%g,%g,%.6g,%.6g,%.8f,%.2e,%.8f,%.2e,%.8f,%.2e,%.2e,%.8f,%.2e,"
                        "%.8f,%.8f,%.8f,%.8f,%.2e,%.5f,%.8f,%.8f,%.8f,%.8f\n",
                        winds[w], wls[l], th, ph, cov[w].xx, cov[w].yy, m[0], se[0], m[1], se[1],
                        m[2], se[2], m[3], dolp, se[7], m[4], m[5], m[6], dolp1, se[8], mu, e.i,
                        e.q, e.u, sea_stokes_dolp(&e));
                fprintf(stderr, "%4.0f m/s %4.0f um %4.0f deg phi %3.0f: %+7.3f +- %.3f  %+7.3f +- %.3f\n",
                        winds[w], wls[l], th, ph, 1e3 * (sea_stokes_dolp(&e) - dolp1),
                        1e3 * se[8], 1e3 * (sea_stokes_dolp(&e) - dolp), 1e3 * se[7]);
            }
    free(col);
    if (f != stdout)
        fclose(f);
    fprintf(stderr, "CPU %.0f s, route difference %.1e, leaks %ld, stopped %ld\n", cpu, max_route,
            leaks, stopped);
    free(val);
    free(multi);
    sea_optics_free(P);
    sea_water_free(water);
    return 0;
}
