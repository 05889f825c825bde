/* mc_sea_oracle.c - the ray tracer's truth over sea-spectrum surfaces: the
 * emissivity by Monte Carlo ray tracing (tests/mc.c) over periodic surfaces
 * of many scales, synthesised from the sea spectrum, next to the model for
 * each surface's own slope covariance.  Two formats (-f):
 *
 * seeds (the default): one row per surface and direction, at one
 * wavelength (4 um unless -L says), the single-bounce emissivity eps1 and
 * the model's low-resolution emissivity (sea_emissivity) with Smith's and
 * with the correlated shadowing.  A minute of CPU; make check traces a few
 * directions again on other surfaces (tests/mc_regen.sh):
 *
 *   tests/mc_sea_oracle -o ../tests/data/mc_sea_emissivity.csv
 *
 * and, with the longer waves (5 min of CPU), the two-scale table:
 *
 *   tests/mc_sea_oracle -n 8192 -d 0.04 -s 4 -r 50000 -w 5,10,15 -t 75,80,82,85 \
 *       -p 0,90 -o ../tests/data/mc_sea_full_emissivity.csv
 *
 * means: one row per wind, wavelength and direction, the means over the
 * surfaces and their standard errors of the first-hit eps1 and of the
 * every-hit eps (unpolarised rho at each hit), every wavelength traced on
 * the same paths, and the model at the surfaces' mean covariance: one
 * scale, one hit (Smith's, correlated) and the default model (model.c:
 * sea_model_params_default, sea_model_alloc with the wind's spectrum and
 * that covariance as the low resolution).  The truth of the default model,
 * tests/data/mc_sea_all_hits.csv (11 min of CPU):
 *
 *   tests/mc_sea_oracle -f means -n 8192 -d 0.04 -s 5 -r 50000 -w 3,5,10,15 \
 *       -L 4,10 -t 60,70,75,80,85 -p 0,90 -o ../tests/data/mc_sea_all_hits.csv
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
 * (the long waves make it vary from seed to seed), or in the means format
 * at their mean (the difference from the mean of the model over the
 * surfaces is measured and written in the file's comment). */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mc.h"

enum { MAXL = MC_LIST_MAX };

static void usage(void)
{
    fprintf(stderr, "usage: mc_sea_oracle [-f seeds|means] [-n GRID] [-d CELL_M] [-s SEEDS]\n"
                    "                     [-r RAYS_PER_SEED] [-w WINDS] [-L WAVELENGTHS_UM]\n"
                    "                     [-t THETAS_DEG] [-p PHIS_DEG] [-S FIRST_SEED] [-o FILE]\n"
                    "(the seeds format: one wavelength)\n");
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

/* The models at slope covariance c toward every direction, for the nl
 * indices N: one scale, one hit, Smith's (ms) and correlated (mc), and the
 * default model (md) made for the spectrum sp with c as the low resolution;
 * out[(d * nl + l)].  0, or -1 with the message printed. */
static int models(const sea_optics *P, const sea_optics *PC, const sea_spectrum *sp, sea_cov2 c,
                  const double complex *N, int nl, const double *ths, const double *phs, int nt,
                  int np, double *ms, double *mc, double *md)
{
    sea_error err;
    sea_model_params mp;
    sea_model_params_default(&mp);
    const sea_slope_stats st = { { 0, 0 }, c };
    sea_model *m = NULL;
    if (sea_model_alloc(&mp, sp, &st, NULL, N, (size_t)nl, NULL, &m, &err) != SEA_OK)
        goto fail;
    for (int d = 0; d < nt * np; d++) {
        const sea_dir v = { ths[d / np] * M_PI / 180, phs[d % np] * M_PI / 180 };
        if (sea_model_emissivity(m, &st, v, &md[d * nl], NULL, &err) != SEA_OK)
            goto fail;
        for (int l = 0; l < nl; l++)
            if (sea_emissivity(P, SEA_EMIS_AUTO, N[l], &st, v, &ms[d * nl + l], &err) != SEA_OK ||
                sea_emissivity(PC, SEA_EMIS_AUTO, N[l], &st, v, &mc[d * nl + l], &err) != SEA_OK)
                goto fail;
    }
    sea_model_free(m);
    return 0;
fail:
    fprintf(stderr, "mc_sea_oracle: the model: %s\n", err.msg);
    sea_model_free(m);
    return -1;
}

int main(int argc, char **argv)
{
    int n = 1024, seeds = 6;
    unsigned long seed0 = 1;
    double dx = 0.04;
    long rays = 50000;
    double winds[MAXL] = { 10 }, ths[MAXL] = { 70, 75, 80, 85 }, phs[MAXL] = { 0, 90 };
    double wls[MC_MAXWL] = { 4 };
    int nw = 1, nt = 4, np = 2, nl = 1, means = 0;
    const char *outpath = NULL;
    int opt_at = 1, opt, r;
    const char *optv;
    while ((r = mc_next_option(argc, argv, &opt_at, &opt, &optv)) > 0) {
        const char *v = optv;
        switch (opt) {
        case 'f':
            if (strcmp(v, "means") != 0 && strcmp(v, "seeds") != 0)
                usage();
            means = strcmp(v, "means") == 0;
            break;
        case 'n': n = atoi(v); break;
        case 'd': dx = atof(v); break;
        case 's': seeds = atoi(v); break;
        case 'r': rays = atol(v); break;
        case 'w': nw = mc_parse_list(v, winds, MAXL); break;
        case 'L': nl = mc_parse_list(v, wls, MC_MAXWL); break;
        case 't': nt = mc_parse_list(v, ths, MAXL); break;
        case 'p': np = mc_parse_list(v, phs, MAXL); break;
        case 'S': seed0 = strtoul(v, NULL, 10); break;
        case 'o': outpath = v; break;
        default: usage();
        }
    }
    if (r < 0)
        usage();
    if (n < 8 || n % 2 || !(dx > 0) || seeds < 2 || rays < 1 || nw < 1 || nt < 1 || np < 1 ||
        nl < 1 || (!means && nl != 1))
        usage();
    sea_init();
    const clock_t c0 = clock();
    const time_t wall0 = time(NULL);
    sea_error err;
    sea_water *water = NULL;
    sea_optics *P = NULL, *PC = NULL;
    double complex N[MC_MAXWL];
    if (sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &water, &err) != SEA_OK ||
        sea_optics_alloc(&P, &err) != SEA_OK || sea_optics_alloc(&PC, &err) != SEA_OK) {
        fprintf(stderr, "mc_sea_oracle: %s\n", err.msg);
        return 1;
    }
    for (int l = 0; l < nl; l++)
        if (sea_water_index(water, wls[l] * 1e-6, &N[l], &err) != SEA_OK) {
            fprintf(stderr, "mc_sea_oracle: %s\n", err.msg);
            return 1;
        }
    sea_optics_set_shadowing(P, SEA_SHADOW_SMITH); /* the paper's */
    sea_optics_set_shadowing(PC, SEA_SHADOW_CORRELATED);
    double *h = malloc(sizeof(double) * (size_t)n * n);
    const int ndir = nt * np;
    /* per wind, direction, wavelength, seed: eps1, eps (every hit), and the
     * models at the surface's covariance: Smith's, correlated, default */
#define AT(w, d, l, s) ((((size_t)(w) * ndir + (size_t)(d)) * nl + (size_t)(l)) * seeds + (size_t)(s))
    const size_t cells = (size_t)nw * ndir * nl * seeds;
    double *e1 = calloc(cells, sizeof *e1), *ea = calloc(cells, sizeof *ea);
    double *ms = calloc(cells, sizeof *ms), *mc = calloc(cells, sizeof *mc);
    double *md = calloc(cells, sizeof *md);
    double *multi = calloc((size_t)nw * ndir * seeds, sizeof *multi);
    double *row_s = calloc((size_t)ndir * nl, sizeof *row_s);
    double *row_c = calloc((size_t)ndir * nl, sizeof *row_c);
    double *row_d = calloc((size_t)ndir * nl, sizeof *row_d);
    sea_cov2 *cv = calloc((size_t)nw * seeds, sizeof *cv);
    if (h == NULL || e1 == NULL || ea == NULL || ms == NULL || mc == NULL || md == NULL ||
        multi == NULL || row_s == NULL || row_c == NULL || row_d == NULL || cv == NULL)
        return 1;
    long leaks = 0, stopped = 0;
    double max_energy = 0.0, max_residual = 0.0;
    for (int w = 0; w < nw; w++) {
        sea_spectrum sp;
        if (sea_spectrum_init(winds[w], INFINITY, 0.0, &sp, &err) != SEA_OK) {
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
            for (int d = 0; d < ndir; d++) {
                const sea_dir v = { ths[d / np] * M_PI / 180, phs[d % np] * M_PI / 180 };
                mc_tally T;
                if (mc_trace(&surf, v, N, nl, rays, sd * 1000003UL + (unsigned long)d, &T)) {
                    fprintf(stderr, "mc_sea_oracle: bad trace arguments\n");
                    return 1;
                }
                for (int l = 0; l < nl; l++) {
                    e1[AT(w, d, l, s)] = T.eps1[l] / rays;
                    ea[AT(w, d, l, s)] = T.eps[l] / rays;
                    max_residual = fmax(max_residual, T.residual[l] / rays);
                }
                multi[((size_t)w * ndir + d) * seeds + s] = (double)T.multi / rays;
                max_energy = fmax(max_energy, T.max_energy_err);
                leaks += T.leaks;
                stopped += T.stopped;
            }
            mc_surface_free(&surf);
            /* the models at this surface's covariance (the default model
             * only in the means format: its columns) */
            if (means ? models(P, PC, &sp, cv[(size_t)w * seeds + s], N, nl, ths, phs, nt, np,
                               row_s, row_c, row_d)
                      : 0)
                return 1;
            for (int d = 0; d < ndir; d++)
                for (int l = 0; l < nl; l++) {
                    const size_t k = AT(w, d, l, s);
                    const sea_slope_stats st = { { 0, 0 }, cv[(size_t)w * seeds + s] };
                    const sea_dir v = { ths[d / np] * M_PI / 180, phs[d % np] * M_PI / 180 };
                    if (means) {
                        ms[k] = row_s[d * nl + l], mc[k] = row_c[d * nl + l];
                        md[k] = row_d[d * nl + l];
                    } else if (sea_emissivity(P, SEA_EMIS_AUTO, N[l], &st, v, &ms[k], &err) !=
                                   SEA_OK ||
                               sea_emissivity(PC, SEA_EMIS_AUTO, N[l], &st, v, &mc[k], &err) !=
                                   SEA_OK) {
                        fprintf(stderr, "mc_sea_oracle: %s\n", err.msg);
                        return 1;
                    }
                }
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
    if (!means) {
        fprintf(f,
                "# Single-bounce emissivity at %g um by Monte Carlo ray tracing (tests/mc.c) over\n"
                "# sea-spectrum surfaces, against the model's low-resolution emissivity\n"
                "# (sea_emissivity, SEA_EMIS_AUTO) at each surface's own triangle slope covariance,\n"
                "# with Smith's shadowing (model_smith) and the correlated one (model_corr).\n"
                "# Generated by tests/mc_sea_oracle.c on %s: -n %d -d %g -s %d -r %ld -w %s\n"
                "# Surfaces: Elfouhaily spectrum, wind along x, fully developed, wavelengths from\n"
                "# %.3g m (a quarter of the Nyquist wavenumber, tapered above) to %.3g m (the period),\n"
                "# %d x %d cells of %g m; seeds %lu..%lu, one surface each; Hale & Querry, salinity 35.\n"
                "# CPU %.0f s; rays found below the surface (tests/mc.h: leaks) %ld.\n",
                wls[0], date, n, dx, seeds, rays, wl, 8.0 * dx, n * dx, n, n, dx, seed0,
                seed0 + seeds - 1, (double)(clock() - c0) / CLOCKS_PER_SEC, leaks);
        fprintf(f, "wind_ms,seed,theta_deg,phi_deg,sxx,syy,sxy,eps1,model_smith,model_corr\n");
        for (int w = 0; w < nw; w++)
            for (int d = 0; d < ndir; d++)
                for (int s = 0; s < seeds; s++) {
                    const size_t k = AT(w, d, 0, s);
                    const sea_cov2 c = cv[(size_t)w * seeds + s];
                    fprintf(f, "%g,%lu,%g,%g,%.10g,%.10g,%.10g,%.6f,%.9f,%.9f\n", winds[w],
                            seed0 + (unsigned long)s, ths[d / np], phs[d % np], c.xx, c.yy, c.xy,
                            e1[k], ms[k], mc[k]);
                }
        fprintf(stderr, "\nmodel - ray tracing (single bounce), mean over seeds +- standard error, "
                        "x 1e-3\n");
        double *g = calloc((size_t)seeds * 2, sizeof *g);
        if (g == NULL)
            return 1;
        for (int w = 0; w < nw; w++)
            for (int d = 0; d < ndir; d++) {
                double a[2], se[2];
                for (int s = 0; s < seeds; s++) {
                    const size_t k = AT(w, d, 0, s);
                    g[s] = ms[k] - e1[k];
                    g[seeds + s] = mc[k] - e1[k];
                }
                mc_mean_se(g, seeds, &a[0], &se[0]);
                mc_mean_se(g + seeds, seeds, &a[1], &se[1]);
                fprintf(stderr,
                        "%4g m/s %4g deg phi %3g: Smith %+6.2f +- %.2f  correlated %+6.2f +- %.2f\n",
                        winds[w], ths[d / np], phs[d % np], 1e3 * a[0], 1e3 * se[0], 1e3 * a[1],
                        1e3 * se[1]);
            }
        free(g);
    } else {
        /* the models at the surfaces' mean covariance, per wind; and how far
         * that is from the models' mean over the surfaces */
        const size_t rows = (size_t)nw * ndir * nl;
        double *rs = calloc(rows, sizeof *rs), *rc = calloc(rows, sizeof *rc);
        double *rd = calloc(rows, sizeof *rd);
        sea_cov2 *cm = calloc((size_t)nw, sizeof *cm);
        if (rs == NULL || rc == NULL || rd == NULL || cm == NULL)
            return 1;
        double jensen = 0.0;
        for (int w = 0; w < nw; w++) {
            sea_spectrum sp;
            if (sea_spectrum_init(winds[w], INFINITY, 0.0, &sp, &err) != SEA_OK)
                return 1;
            for (int s = 0; s < seeds; s++) {
                const sea_cov2 c = cv[(size_t)w * seeds + s];
                cm[w].xx += c.xx / seeds, cm[w].yy += c.yy / seeds, cm[w].xy += c.xy / seeds;
            }
            const size_t r0 = (size_t)w * ndir * nl;
            if (models(P, PC, &sp, cm[w], N, nl, ths, phs, nt, np, &rs[r0], &rc[r0], &rd[r0]))
                return 1;
            for (int d = 0; d < ndir; d++)
                for (int l = 0; l < nl; l++) {
                    double a[3] = { 0, 0, 0 };
                    for (int s = 0; s < seeds; s++) {
                        const size_t k = AT(w, d, l, s);
                        a[0] += ms[k] / seeds, a[1] += mc[k] / seeds, a[2] += md[k] / seeds;
                    }
                    const size_t q = r0 + (size_t)d * nl + (size_t)l;
                    jensen = fmax(jensen, fmax(fabs(a[0] - rs[q]),
                                               fmax(fabs(a[1] - rc[q]), fabs(a[2] - rd[q]))));
                }
        }
        const double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
        char wls_s[128] = "";
        for (int l = 0; l < nl; l++)
            snprintf(wls_s + strlen(wls_s), sizeof wls_s - strlen(wls_s), "%s%g",
                     l ? " and " : "", wls[l]);
        fprintf(f, "# Emissivity by Monte Carlo ray tracing (tests/mc.c) over sea-spectrum surfaces,\n"
                   "# first hit and every hit, against the model.  Generated by tests/mc_sea_oracle.c\n"
                   "# on %s:\n#  ", date);
        for (int a = 0; a < argc; a++)
            fprintf(f, " %s", a == 0 ? "tests/mc_sea_oracle" : argv[a]);
        fprintf(f,
                "\n# (run in the build directory).  Surfaces: Elfouhaily spectrum, wind along x,\n"
                "# fully developed, wavelengths from %.3g m (a quarter of the Nyquist wavenumber,\n"
                "# tapered above) to %.3g m (the period), %d x %d cells of %g m; seeds %lu..%lu,\n"
                "# one surface each per wind; %ld rays per surface and direction, the same paths\n"
                "# for every wavelength (%s um); Hale & Querry, salinity 35.\n"
                "# One row per wind, wavelength and direction: means over the %d surfaces; _se:\n"
                "# standard error of the mean over the surfaces (their spread: the long waves' and\n"
                "# the rays' together).  sxx, syy, sxy: the surfaces' measured triangle slope\n"
                "# covariance, mean.  eps1: first hit, 1 - rho (single bounce); eps: every hit,\n"
                "# unpolarised rho at each; multi: fraction of rays hitting twice or more.\n"
                "# The models at the row's covariance C: model_smith, model_corr: sea_emissivity\n"
                "# (SEA_EMIS_AUTO; one scale, one hit) with Smith's and the correlated shadowing;\n"
                "# model_default: the default model, sea_model_params_default (correlated, two\n"
                "# scales, reflections auto, tolerance 1e-3), sea_model_alloc(the spectrum of the\n"
                "# row's wind as above, lr = (mean 0, C), fine NULL, every wavelength's index, no\n"
                "# sky), then sea_model_emissivity(lr, the row's direction).  Its two scales split\n"
                "# the spectrum's whole slope variance (sea_spectrum_split_half, kc = 0), which\n"
                "# counts the waves under 0.32 m that the surfaces lack (tests/test_mc.c also\n"
                "# computes the split at half the surfaces' own variance).  At each surface's own\n"
                "# covariance, averaged over the surfaces, the three models differ from these\n"
                "# columns by at most %.1e.\n"
                "# CPU %.0f s (%d threads' total); energy closure max %.1e per ray, weight left at\n"
                "# the 1e-6 cut max %.1e, rays found below the surface (leaks) %ld, stopped %ld.\n",
                8.0 * dx, n * dx, n, n, dx, seed0, seed0 + seeds - 1, rays, wls_s, seeds, jensen,
                cpu, mc_threads(), max_energy, max_residual, leaks, stopped);
        fprintf(f, "wind_ms,wavelength_um,theta_deg,phi_deg,sxx,syy,sxy,eps1,eps1_se,eps,eps_se,"
                   "multi,model_smith,model_corr,model_default,period_m\n");
        fprintf(stderr, "\nmodel - ray tracing (every hit), x 1e-3; eps_se\n");
        double *x = calloc((size_t)seeds, sizeof *x);
        if (x == NULL)
            return 1;
        for (int w = 0; w < nw; w++)
            for (int l = 0; l < nl; l++)
                for (int d = 0; d < ndir; d++) {
                    double a1, se1, af, sef, mu = 0.0;
                    for (int s = 0; s < seeds; s++)
                        x[s] = e1[AT(w, d, l, s)];
                    mc_mean_se(x, seeds, &a1, &se1);
                    for (int s = 0; s < seeds; s++)
                        x[s] = ea[AT(w, d, l, s)];
                    mc_mean_se(x, seeds, &af, &sef);
                    for (int s = 0; s < seeds; s++)
                        mu += multi[((size_t)w * ndir + d) * seeds + s] / seeds;
                    const size_t q = ((size_t)w * ndir + d) * nl + l;
                    fprintf(f, "%g,%g,%g,%g,%.10g,%.10g,%.10g,%.6f,%.6f,%.6f,%.6f,%.4f,%.9f,%.9f,"
                               "%.9f,%.10g\n",
                            winds[w], wls[l], ths[d / np], phs[d % np], cm[w].xx, cm[w].yy,
                            cm[w].xy, a1, se1, af, sef, mu, rs[q], rc[q], rd[q], n * dx);
                    fprintf(stderr, "%4g m/s %4g um %4g deg phi %3g: Smith %+7.2f  correlated "
                                    "%+7.2f  default %+7.2f  (se %.2f; eps - eps1 %.2f)\n",
                            winds[w], wls[l], ths[d / np], phs[d % np], 1e3 * (rs[q] - af),
                            1e3 * (rc[q] - af), 1e3 * (rd[q] - af), 1e3 * sef, 1e3 * (af - a1));
                }
        fprintf(stderr, "CPU %.0f s; energy closure %.1e; leaks %ld; stopped %ld; models at the "
                        "mean covariance against their mean %.1e\n",
                cpu, max_energy, leaks, stopped, jensen);
        free(x);
        free(rs), free(rc), free(rd), free(cm);
    }
    if (outpath)
        fclose(f);
    free(e1), free(ea), free(ms), free(mc), free(md), free(multi), free(cv);
    free(row_s), free(row_c), free(row_d);
    free(h);
    sea_optics_free(P);
    sea_optics_free(PC);
    sea_water_free(water);
    return 0;
}
