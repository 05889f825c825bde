/* emis_rule_check.c - the default emissivity rule (SEA_EMIS_AUTO) against
 * the adaptive Eq 7 (SEA_EMIS_FULL) over random conditions: what the
 * rule's orders were fitted and checked on (seabake-model(7), the auto
 * method).  make check runs it for the figures of the manual (the four
 * seeds of tests/claims.csv, 50 s of CPU; about 1 s of CPU per 100
 * conditions with correlated shadowing):
 *
 *   tests/emis_rule_check [-n CONDITIONS] [-s SEED] [--smith]
 *
 * Conditions, from the seed: slope variances along x and y log-uniform in
 * 1e-5..0.2 each (so anisotropic up to 2e4:1), correlation |r| <= 0.8, a
 * mean slope of 0 (30 %) or of length u1 u2 2 (u uniform) in a uniform
 * direction, the view uniform in cos theta up to 85 deg and in azimuth, 4
 * or 10 um (Hale & Querry, salinity 35); correlated shadowing unless
 * --smith.  Prints the largest |auto - full|, where it is and the orders
 * the rule took there, and exits 1 when it is above 1e-6 (the rule's
 * promise). */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "seabake.h"

/* A 32-bit linear congruential generator: the conditions depend on the
 * seed alone, on every platform. */
static double uniform(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / 16777216.0;
}

int main(int argc, char **argv)
{
    long n = 2000;
    unsigned seed = 12345, seed0;
    int smith = 0;
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "-n") == 0 && a + 1 < argc)
            n = strtol(argv[++a], NULL, 10);
        else if (strcmp(argv[a], "-s") == 0 && a + 1 < argc)
            seed = (unsigned)strtoul(argv[++a], NULL, 10);
        else if (strcmp(argv[a], "--smith") == 0)
            smith = 1;
        else {
            fprintf(stderr, "usage: emis_rule_check [-n CONDITIONS] [-s SEED] [--smith]\n");
            return 2;
        }
    }
    if (n < 1) {
        fprintf(stderr, "emis_rule_check: -n must be at least 1\n");
        return 2;
    }
    seed0 = seed;
    sea_init();
    sea_error err;
    sea_water *water = NULL;
    sea_optics *p = NULL;
    double complex N[2];
    if (sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &water, &err) != SEA_OK ||
        sea_water_index(water, 4e-6, &N[0], &err) != SEA_OK ||
        sea_water_index(water, 10e-6, &N[1], &err) != SEA_OK ||
        sea_optics_alloc(&p, &err) != SEA_OK) {
        fprintf(stderr, "emis_rule_check: %s\n", err.msg);
        return 1;
    }
    sea_optics_set_shadowing(p, smith ? SEA_SHADOW_SMITH : SEA_SHADOW_CORRELATED);
    double worst = 0.0, sum2 = 0.0;
    sea_slope_stats at = { { 0, 0 }, { 0, 0, 0 } };
    sea_dir at_v = { 0, 0 };
    int at_l = 0;
    for (long i = 0; i < n; i++) {
        const double lo = log(1e-5), hi = log(0.2);
        const double vx = exp(lo + uniform(&seed) * (hi - lo));
        const double vy = exp(lo + uniform(&seed) * (hi - lo));
        const double r = (2.0 * uniform(&seed) - 1.0) * 0.8;
        const double mr = uniform(&seed) < 0.3 ? 0.0 : uniform(&seed) * uniform(&seed) * 2.0;
        const double ma = uniform(&seed) * 2.0 * M_PI;
        const sea_slope_stats st = { { mr * cos(ma), mr * sin(ma) }, { vx, vy, r * sqrt(vx * vy) } };
        const double cz = 1.0 - uniform(&seed) * (1.0 - cos(85.0 * M_PI / 180.0));
        const sea_dir v = { acos(cz), uniform(&seed) * 2.0 * M_PI };
        const int l = uniform(&seed) < 0.5;
        double ea, ef;
        if (sea_emissivity(p, SEA_EMIS_AUTO, N[l], &st, v, &ea, &err) != SEA_OK ||
            sea_emissivity(p, SEA_EMIS_FULL, N[l], &st, v, &ef, &err) != SEA_OK) {
            fprintf(stderr, "emis_rule_check: condition %ld: %s\n", i, err.msg);
            return 1;
        }
        const double d = fabs(ea - ef);
        sum2 += d * d;
        if (d > worst) {
            worst = d;
            at = st;
            at_v = v;
            at_l = l;
        }
    }
    const sea_emis_rule rule = sea_emissivity_auto_rule(&at, at_v);
    printf("%ld conditions (seed %u, %s shadowing): largest |auto - full| %.3g, RMS %.3g\n", n,
           seed0, smith ? "Smith's" : "correlated", worst, sqrt(sum2 / (double)n));
    printf("  at theta %.2f deg, phi %.1f deg, %d um, mean slope (%.4g, %.4g), covariance "
           "(%.4g, %.4g, %.4g): orders %d x %d\n",
           at_v.theta * 180.0 / M_PI, at_v.phi * 180.0 / M_PI, at_l ? 10 : 4, at.mean.x,
           at.mean.y, at.cov.xx, at.cov.yy, at.cov.xy, rule.n_gl, rule.n_gh);
    sea_optics_free(p);
    sea_water_free(water);
    return worst <= 1e-6 ? 0 : 1;
}
