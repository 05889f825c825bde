/* mc_sea_oracle.c - writes tests/data/mc_sea_emissivity.csv: the single-bounce
 * emissivity by Monte Carlo ray tracing (tests/mc.c) over periodic surfaces
 * of many scales, synthesised from the sea spectrum, next to the model's
 * low-resolution emissivity for each surface's own slope covariance, with
 * Smith's and with the correlated shadowing.  A minute of CPU; make check
 * traces a few directions again on other surfaces (tests/mc_regen.sh):
 *
 *   tests/mc_sea_oracle -o ../tests/data/mc_sea_emissivity.csv
 *
 * and, with the longer waves (5 min of CPU), the two-scale table:
 *
 *   tests/mc_sea_oracle -n 8192 -d 0.04 -s 4 -r 50000 -w 5,10,15 -t 75,80,82,85 \
 *       -p 0,90 -o ../tests/data/mc_sea_full_emissivity.csv
 *
 * The one-scale surfaces of tests/mc_oracle.c have the Gaussian correlation
 * the correlated shadowing assumes; these have the sea's.  Heights: white
 * noise filtered (mc_filtered_noise) with the amplitude sqrt(Psi(k) dk^2) of the
 * Elfouhaily directional spectrum (wind along x, fully developed), kept
 * between the grid's period and a quarter of its Nyquist wavenumber
 * (Gaussian taper above, so that the cells are small against the shortest
 * wave: the triangle mesh then follows the surface), cell size dx.  Each
 * seed is one surface; every direction traces `rays` rays over it; the
 * model is evaluated at that surface's measured triangle slope covariance
 * (the long waves make it vary from seed to seed). */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mc.h"

enum { MAXL = 16 };

static void usage(void)
{
    fprintf(stderr, "usage: mc_sea_oracle [-n GRID] [-d CELL_M] [-s SEEDS] [-r RAYS_PER_SEED]\n"
                    "                     [-w WINDS] [-t THETAS_DEG] [-p PHIS_DEG] [-S FIRST_SEED]\n"
                    "                     [-o FILE]\n");
    exit(2);
}

/* Gaussian taper above a quarter of the Nyquist wavenumber. */
static double taper(double k, double dx)
{
    const double kc = M_PI / dx / 4.0;
    return k < kc ? 1.0 : exp(-pow((k - kc) / (0.25 * kc), 2.0));
}

/* The sea's amplitude sqrt(Psi(k) dk^2), tapered, at index-space
 * wavenumbers (radians per cell). */
typedef struct {
    const sea_spectrum *sp;
    double dx, dk;
} sea_filter;

static double sea_amplitude(double kx, double ky, void *ctx)
{
    const sea_filter *f = ctx;
    const double k = hypot(kx, ky) / f->dx;
    return k > 0.0 ? sqrt(sea_spectrum_directional(f->sp, k, atan2(ky, kx)) * f->dk * f->dk) *
                         taper(k, f->dx)
                   : 0.0;
}

/* Heights of one surface (n x n, cell dx) of the spectrum sp, seed. */
static int sea_heights(const sea_spectrum *sp, int n, double dx, unsigned long seed, double *h)
{
    sea_filter f = { sp, dx, 2.0 * M_PI / (n * dx) };
    if (mc_filtered_noise(n, seed, sea_amplitude, &f, h))
        return -1;
    /* white noise of unit variance has |H| ~ n: heights of variance sum Psi dk^2 */
    for (long k = 0; k < (long)n * n; k++)
        h[k] /= n;
    return 0;
}

int main(int argc, char **argv)
{
    int n = 1024, seeds = 6;
    unsigned long seed0 = 1;
    double dx = 0.04;
    long rays = 50000;
    double winds[MAXL] = { 10 }, ths[MAXL] = { 70, 75, 80, 85 }, phs[MAXL] = { 0, 90 };
    int nw = 1, nt = 4, np = 2;
    const char *outpath = NULL;
    int opt_at = 1, opt, r;
    const char *optv;
    while ((r = mc_next_option(argc, argv, &opt_at, &opt, &optv)) > 0) {
        const char *v = optv;
        switch (opt) {
        case 'n': n = atoi(v); break;
        case 'd': dx = atof(v); break;
        case 's': seeds = atoi(v); break;
        case 'r': rays = atol(v); break;
        case 'w': nw = mc_parse_list(v, winds, MAXL); break;
        case 't': nt = mc_parse_list(v, ths, MAXL); break;
        case 'p': np = mc_parse_list(v, phs, MAXL); break;
        case 'S': seed0 = strtoul(v, NULL, 10); break;
        case 'o': outpath = v; break;
        default: usage();
        }
    }
    if (r < 0)
        usage();
    if (n < 8 || n % 2 || !(dx > 0) || seeds < 2 || rays < 1 || nw < 1 || nt < 1 || np < 1)
        usage();
    sea_init();
    const clock_t c0 = clock();
    const time_t wall0 = time(NULL);
    sea_error err;
    sea_water *water = NULL;
    sea_optics *P = NULL, *PC = NULL;
    double complex N;
    if (sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &water, &err) != SEA_OK ||
        sea_water_index(water, 4e-6, &N, &err) != SEA_OK || sea_optics_alloc(&P, &err) != SEA_OK ||
        sea_optics_alloc(&PC, &err) != SEA_OK) {
        fprintf(stderr, "mc_sea_oracle: %s\n", err.msg);
        return 1;
    }
    sea_optics_set_shadowing(P, SEA_SHADOW_SMITH); /* the paper's */
    sea_optics_set_shadowing(PC, SEA_SHADOW_CORRELATED);
    double *h = malloc(sizeof(double) * (size_t)n * n);
    const int ndir = nt * np;
    /* per wind, direction, seed: eps1, Smith's and the correlated model */
    const size_t cells = (size_t)nw * ndir * seeds;
    double *e1 = calloc(cells, sizeof *e1), *ms = calloc(cells, sizeof *ms);
    double *mc = calloc(cells, sizeof *mc);
    sea_cov2 *cv = calloc((size_t)nw * seeds, sizeof *cv);
    if (h == NULL || e1 == NULL || ms == NULL || mc == NULL || cv == NULL)
        return 1;
    long leaks = 0;
    for (int w = 0; w < nw; w++) {
        sea_spectrum sp;
        if (sea_spectrum_init(&sp, winds[w], INFINITY, 0.0, &err) != SEA_OK) {
            fprintf(stderr, "mc_sea_oracle: %s\n", err.msg);
            return 1;
        }
        for (int s = 0; s < seeds; s++) {
            const unsigned long sd = seed0 + (unsigned long)s;
            mc_surface surf;
            const double A[2][2] = { { dx, 0 }, { 0, dx } };
            if (sea_heights(&sp, n, dx, sd, h) || mc_surface_from_heights(&surf, n, h, A)) {
                fprintf(stderr, "mc_sea_oracle: cannot build the surface\n");
                return 1;
            }
            cv[(size_t)w * seeds + s] = surf.cov;
            const sea_slope_stats st = { { 0, 0 }, surf.cov };
            for (int d = 0; d < ndir; d++) {
                const sea_dir v = { ths[d / np] * M_PI / 180, phs[d % np] * M_PI / 180 };
                mc_tally T;
                const size_t k = ((size_t)w * ndir + d) * seeds + s;
                if (mc_trace(&surf, v, &N, 1, rays, sd * 1000003UL + (unsigned long)d, &T) ||
                    sea_emissivity(P, SEA_EMIS_AUTO, N, &st, v, &ms[k], &err) != SEA_OK ||
                    sea_emissivity(PC, SEA_EMIS_AUTO, N, &st, v, &mc[k], &err) != SEA_OK) {
                    fprintf(stderr, "mc_sea_oracle: trace or model failed\n");
                    return 1;
                }
                e1[k] = T.eps1[0] / rays;
                leaks += T.leaks;
            }
            mc_surface_free(&surf);
            fprintf(stderr, "mc_sea_oracle: wind %g m/s, seed %d of %d (%.0f s CPU)\n", winds[w],
                    s + 1, seeds, (double)(clock() - c0) / CLOCKS_PER_SEC);
        }
    }
    FILE *f = outpath ? fopen(outpath, "w") : stdout;
    if (f == NULL) {
        perror(outpath);
        return 1;
    }
    char date[64], wl[256] = "";
    strftime(date, sizeof date, "%Y-%m-%d", gmtime(&wall0));
    for (int w = 0; w < nw; w++)
        snprintf(wl + strlen(wl), sizeof wl - strlen(wl), "%s%g", w ? "," : "", winds[w]);
    fprintf(f,
            "# Single-bounce emissivity at 4 um by Monte Carlo ray tracing (tests/mc.c) over\n"
            "# sea-spectrum surfaces, against the model's low-resolution emissivity\n"
            "# (sea_emissivity, SEA_EMIS_AUTO) at each surface's own triangle slope covariance,\n"
            "# with Smith's shadowing (model_smith) and the correlated one (model_corr).\n"
            "# Generated by tests/mc_sea_oracle.c on %s: -n %d -d %g -s %d -r %ld -w %s\n"
            "# Surfaces: Elfouhaily spectrum, wind along x, fully developed, wavelengths from\n"
            "# %.3g m (a quarter of the Nyquist wavenumber, tapered above) to %.3g m (the period),\n"
            "# %d x %d cells of %g m; seeds %lu..%lu, one surface each; Hale & Querry, salinity 35.\n"
            "# CPU %.0f s; rays found below the surface (tests/mc.h: leaks) %ld.\n",
            date, n, dx, seeds, rays, wl, 8.0 * dx, n * dx, n, n, dx, seed0, seed0 + seeds - 1,
            (double)(clock() - c0) / CLOCKS_PER_SEC, leaks);
    fprintf(f, "wind_ms,seed,theta_deg,phi_deg,sxx,syy,sxy,eps1,model_smith,model_corr\n");
    for (int w = 0; w < nw; w++)
        for (int d = 0; d < ndir; d++)
            for (int s = 0; s < seeds; s++) {
                const size_t k = ((size_t)w * ndir + d) * seeds + s;
                const sea_cov2 c = cv[(size_t)w * seeds + s];
                fprintf(f, "%g,%lu,%g,%g,%.10g,%.10g,%.10g,%.6f,%.9f,%.9f\n", winds[w],
                        seed0 + (unsigned long)s,
                        ths[d / np], phs[d % np], c.xx, c.yy, c.xy, e1[k], ms[k], mc[k]);
            }
    fprintf(stderr, "\nmodel - ray tracing (single bounce), mean over seeds +- standard error, x 1e-3\n");
    for (int w = 0; w < nw; w++)
        for (int d = 0; d < ndir; d++) {
            double a[2] = { 0 }, q[2] = { 0 };
            for (int s = 0; s < seeds; s++) {
                const size_t k = ((size_t)w * ndir + d) * seeds + s;
                const double g[2] = { ms[k] - e1[k], mc[k] - e1[k] };
                for (int m = 0; m < 2; m++)
                    a[m] += g[m] / seeds, q[m] += g[m] * g[m] / seeds;
            }
            fprintf(stderr, "%4g m/s %4g deg phi %3g: Smith %+6.2f +- %.2f  correlated %+6.2f +- %.2f\n",
                    winds[w], ths[d / np], phs[d % np], 1e3 * a[0],
                    1e3 * sqrt(fmax(q[0] - a[0] * a[0], 0) / (seeds - 1)), 1e3 * a[1],
                    1e3 * sqrt(fmax(q[1] - a[1] * a[1], 0) / (seeds - 1)));
        }
    if (outpath)
        fclose(f);
    free(e1), free(ms), free(mc), free(cv);
    free(h);
    sea_optics_free(P);
    sea_optics_free(PC);
    sea_water_free(water);
    return 0;
}
