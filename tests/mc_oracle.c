/* mc_oracle.c - writes tests/data/mc_emissivity.csv: the emissivity of a
 * wind-roughened sea by Monte Carlo ray tracing (tests/mc.c) next to the
 * model's low-resolution effective emissivity (sea_emissivity, default
 * rule), and prints the model minus the oracle per angle.  Minutes of CPU;
 * make check traces a few rows again on other surfaces (tests/mc_regen.sh):
 *
 *   tests/mc_oracle -o ../tests/data/mc_emissivity.csv
 *
 * For each wind speed the target is the low-resolution slope covariance
 * sea_spectrum_slope_cov(kc = 0) (wind along x, mean slope 0); each seed is
 * one periodic Gaussian-correlated surface (n x n, correlation length ell
 * cells) whose triangle slopes have that covariance exactly; every view
 * direction traces `rays` rays over it, and the one path serves both
 * wavelengths (geometry does not depend on the index).  The standard error
 * is that of the mean of the per-seed means (seed-to-seed spread: the
 * surface's own randomness and the rays' together). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mc.h"

enum { MAXL = MC_LIST_MAX };

static void usage(void)
{
    fprintf(stderr, "usage: mc_oracle [-n GRID] [-l ELL_CELLS] [-s SEEDS] [-r RAYS_PER_SEED]\n"
                    "                 [-w WINDS] [-L WAVELENGTHS_UM] [-t THETAS_DEG]\n"
                    "                 [-p PHIS_DEG] [-S FIRST_SEED] [-o FILE]\n");
    exit(2);
}

int main(int argc, char **argv)
{
    mc_grid_options o = { .n = 512, .seeds = 8, .ell = 8, .rays = 60000, .seed0 = 1,
                          .winds = { 3, 5, 10, 15 }, .wls = { 4, 10 },
                          .ths = { 0, 40, 60, 70, 75, 80, 85 }, .phs = { 0, 90 },
                          .nw = 4, .nl = 2, .nt = 7, .np = 2 };
    if (mc_grid_options_parse(argc, argv, &o) != 0)
        usage();
    const int n = o.n, seeds = o.seeds, nw = o.nw, nl = o.nl, nt = o.nt, np = o.np;
    const double ell = o.ell, *winds = o.winds, *wls = o.wls, *ths = o.ths, *phs = o.phs;
    const long rays = o.rays;
    const unsigned long seed0 = o.seed0;
    const char *outpath = o.outpath;
    sea_init();
    clock_t c0 = clock();
    time_t wall0 = time(NULL);
    sea_error err;
    sea_water *water = NULL;
    sea_optics *P = NULL;
    double complex N[MC_MAXWL];
    if (sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &water, &err) != SEA_OK ||
        sea_optics_alloc(&P, &err) != SEA_OK) {
        fprintf(stderr, "mc_oracle: %s\n", err.msg);
        return 1;
    }
    sea_optics_set_shadowing(P, SEA_SHADOW_SMITH); /* the paper's */
    for (int l = 0; l < nl; l++)
        if (sea_water_index(water, wls[l] * 1e-6, &N[l], &err) != SEA_OK) {
            fprintf(stderr, "mc_oracle: %s\n", err.msg);
            return 1;
        }
    int ndir = nt * np;
    /* per wind, direction, wavelength, seed: the per-seed means */
    size_t cells = (size_t)nw * ndir * nl * seeds;
    double *m1 = calloc(cells, sizeof *m1), *mf = calloc(cells, sizeof *mf);
    double *mp = calloc(cells, sizeof *mp), *esc = calloc(cells * 3, sizeof *esc);
    double *multi = calloc((size_t)nw * ndir * seeds, sizeof *multi);
    double max_energy = 0, max_residual = 0, max_cov_err = 0;
    long leaks = 0, stopped = 0;
    if (!m1 || !mf || !mp || !esc || !multi)
        return 1;
#define AT(w, d, l, s) ((((size_t)(w) * ndir + (d)) * nl + (l)) * seeds + (s))
    sea_cov2 cov[MAXL];
    for (int w = 0; w < nw; w++) {
        sea_spectrum sp;
        if (sea_spectrum_init(winds[w], INFINITY, 0.0, &sp, &err) != SEA_OK ||
            sea_spectrum_slope_cov(&sp, 0.0, &cov[w], &err) != SEA_OK) {
            fprintf(stderr, "mc_oracle: %s\n", err.msg);
            return 1;
        }
        for (int s = 0; s < seeds; s++) {
            mc_surface surf;
            unsigned long sd = seed0 + (unsigned long)s;
            if (mc_surface_gaussian(&surf, n, ell, &cov[w], sd)) {
                fprintf(stderr, "mc_oracle: cannot build the surface\n");
                return 1;
            }
            double ce = fmax(fabs(surf.cov.xx / cov[w].xx - 1), fabs(surf.cov.yy / cov[w].yy - 1));
            ce = fmax(ce, fabs(surf.cov.xy) / sqrt(cov[w].xx * cov[w].yy));
            max_cov_err = fmax(max_cov_err, ce);
            for (int d = 0; d < ndir; d++) {
                sea_dir v = { ths[d / np] * M_PI / 180, phs[d % np] * M_PI / 180 };
                mc_tally T;
                if (mc_trace(&surf, v, N, nl, rays, sd * 1000003UL + (unsigned long)d, &T)) {
                    fprintf(stderr, "mc_oracle: bad trace arguments\n");
                    return 1;
                }
                for (int l = 0; l < nl; l++) {
                    size_t k = AT(w, d, l, s);
                    m1[k] = T.eps1[l] / rays;
                    mf[k] = T.eps[l] / rays;
                    mp[k] = T.eps_pol[l] / rays;
                    esc[3 * k] = T.escaped[l][1] / rays;
                    esc[3 * k + 1] = T.escaped[l][2] / rays;
                    double rest = 0;
                    for (int b = 3; b < MC_NBOUNCE; b++)
                        rest += T.escaped[l][b];
                    esc[3 * k + 2] = rest / rays;
                    max_residual = fmax(max_residual, T.residual[l] / rays);
                }
                multi[((size_t)w * ndir + d) * seeds + s] = (double)T.multi / rays;
                max_energy = fmax(max_energy, T.max_energy_err);
                leaks += T.leaks;
                stopped += T.stopped;
            }
            mc_surface_free(&surf);
            fprintf(stderr, "mc_oracle: wind %g m/s, seed %d of %d (%.0f s CPU)\n", winds[w],
                    s + 1, seeds, (double)(clock() - c0) / CLOCKS_PER_SEC);
        }
    }
    double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
    FILE *f = outpath ? fopen(outpath, "w") : stdout;
    if (f == NULL) {
        perror(outpath);
        return 1;
    }
    char date[64];
    strftime(date, sizeof date, "%Y-%m-%d", gmtime(&wall0));
    fprintf(f, "# Emissivity of a wind-roughened sea by Monte Carlo ray tracing (tests/mc.c)\n"
               "# against the model's low-resolution effective emissivity (sea_emissivity,\n"
               "# SEA_EMIS_AUTO).  Generated by tests/mc_oracle.c on %s:\n#  ", date);
    for (int a = 0; a < argc; a++)
        fprintf(f, " %s", a == 0 ? "tests/mc_oracle" : argv[a]);
    fprintf(f, "\n# Surfaces: periodic Gaussian-correlated heights on a %d x %d grid, correlation\n"
               "# length %g cells, two triangles per cell, triangle slope covariance = the\n"
               "# low-resolution covariance of sea_spectrum_slope_cov(kc = 0) (wind along x,\n"
               "# fully developed, mean slope 0) to %.1e relative; seeds %lu..%lu (%d surfaces\n"
               "# per wind), %ld rays per seed and direction, the same paths for every\n"
               "# wavelength.  Sea water: Hale & Querry, salinity 35.  _se: standard error of\n"
               "# the mean over the seeds.  eps1: first-hit 1 - rho (single bounce); eps: all\n"
               "# hits, unpolarised rho at each; eps_pol: all hits, polarisation followed;\n"
               "# esc1, esc2, esc3: energy escaping after 1, 2, >= 3 hits; multi: fraction of\n"
               "# rays hitting twice or more; model: sea_emissivity today (tests/test_mc.c\n"
               "# checks it still is).  sxx, syy: target slope variances.\n"
               "# CPU time %.0f s (%d threads' total); energy closure max %.1e per ray, weight\n"
               "# left at the 1e-6 cut max %.1e, leaks %ld, stopped rays %ld.\n",
            n, n, ell, max_cov_err, seed0, seed0 + seeds - 1, seeds, rays, cpu,
            mc_threads(),
            max_energy, max_residual, leaks, stopped);
    fprintf(f, "wind_ms,wavelength_um,theta_deg,phi_deg,sxx,syy,eps1,eps1_se,eps,eps_se,"
               "eps_pol,eps_pol_se,esc1,esc2,esc3,multi,model\n");
    /* summary: model minus oracle */
    fprintf(stderr, "\nmodel - oracle (single bounce; all hits), +- standard error, x 1e-3\n");
    for (int w = 0; w < nw; w++)
        for (int l = 0; l < nl; l++)
            for (int d = 0; d < ndir; d++) {
                double th = ths[d / np], ph = phs[d % np];
                double s1 = 0, q1 = 0, sf = 0, qf = 0, spl = 0, qp = 0, e3[3] = { 0 }, mu = 0;
                for (int s = 0; s < seeds; s++) {
                    size_t k = AT(w, d, l, s);
                    s1 += m1[k], q1 += m1[k] * m1[k];
                    sf += mf[k], qf += mf[k] * mf[k];
                    spl += mp[k], qp += mp[k] * mp[k];
                    for (int b = 0; b < 3; b++)
                        e3[b] += esc[3 * k + b] / seeds;
                    mu += multi[((size_t)w * ndir + d) * seeds + s] / seeds;
                }
                double S = seeds;
                double a1 = s1 / S, af = sf / S, ap = spl / S;
                double se1 = sqrt(fmax(q1 / S - a1 * a1, 0) / (S - 1));
                double sef = sqrt(fmax(qf / S - af * af, 0) / (S - 1));
                double sep = sqrt(fmax(qp / S - ap * ap, 0) / (S - 1));
                sea_slope_stats st = { { 0, 0 }, cov[w] };
                double model;
                if (sea_emissivity(P, SEA_EMIS_AUTO, N[l], &st,
                                   (sea_dir){ th * M_PI / 180, ph * M_PI / 180 }, &model,
                                   &err) != SEA_OK) {
                    fprintf(stderr, "mc_oracle: %s\n", err.msg);
                    return 1;
                }
                fprintf(f, "%g,%g,%g,%g,%.9g,%.9g,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.3e,%.3e,%.3e,%.4f,%.9f\n",
                        winds[w], wls[l], th, ph, cov[w].xx, cov[w].yy, a1, se1, af, sef, ap, sep,
                        e3[0], e3[1], e3[2], mu, model);
                fprintf(stderr, "%4g m/s %4g um %4g deg phi %3g: model %.4f  -eps1 %+7.2f +- %.2f"
                                "  -eps %+7.2f +- %.2f  -eps_pol %+7.2f +- %.2f\n",
                        winds[w], wls[l], th, ph, model, 1e3 * (model - a1), 1e3 * se1,
                        1e3 * (model - af), 1e3 * sef, 1e3 * (model - ap), 1e3 * sep);
            }
    fprintf(stderr, "CPU %.0f s; max energy closure error %.1e; leaks %ld; max slope cov error %.1e\n",
            cpu, max_energy, leaks, max_cov_err);
    if (outpath)
        fclose(f);
    free(m1), free(mf), free(mp), free(esc), free(multi);
    sea_optics_free(P);
    sea_water_free(water);
    return leaks || max_energy > 1e-9 ? 1 : 0;
}
