/* test_mc.c - the Monte Carlo ray-tracing oracle (tests/mc.c) checked
 * against exact answers; its stored tables (tests/data/mc_*.csv): their
 * model columns and today's model against an independent Eq 7
 * (tests/indep.c), and the figures of the manuals measured on them at the
 * values tests/claims.csv states.  Small grids and few rays; the tables'
 * checks take 8 s (every row's Eq 7 by adaptive quadrature). */
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "all_hits.h"
#include "indep.h"
#include "mc.h"
#include "unit.h"

#ifndef SEA_TOP_SRCDIR
#define SEA_TOP_SRCDIR "."
#endif

static double complex N4, N10; /* sea water at 4 and 10 um, salinity 35 (Hale & Querry) */
static sea_optics *P, *PC; /* Smith's shadowing (set: whatever the library's default), correlated */

static int setup(void)
{
    sea_water *w = NULL;
    if (sea_optics_alloc(&P, NULL) != SEA_OK || sea_optics_alloc(&PC, NULL) != SEA_OK ||
        sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) != SEA_OK ||
        sea_water_index(w, 4e-6, &N4, NULL) != SEA_OK ||
        sea_water_index(w, 10e-6, &N10, NULL) != SEA_OK)
        return 1;
    sea_water_free(w);
    sea_optics_set_shadowing(P, SEA_SHADOW_SMITH); /* the paper's */
    sea_optics_set_shadowing(PC, SEA_SHADOW_CORRELATED);
    return 0;
}

static int teardown(void)
{
    sea_optics_free(P);
    sea_optics_free(PC);
    return 0;
}

static sea_cov2 lr_cov(double wind)
{
    sea_spectrum s;
    sea_cov2 c = { 0, 0, 0 };
    CU_ASSERT(sea_spectrum_init(wind, INFINITY, 0.0, &s, NULL) == SEA_OK);
    CU_ASSERT(sea_spectrum_slope_cov(&s, 0.0, &c, NULL) == SEA_OK);
    return c;
}

/* Flat surface (C = 0): every ray hits the plane with cos psi = cos theta
 * exactly and its reflection escapes, so eps1 = eps = eps_pol = 1 - rho(theta)
 * and all the escaping energy has one bounce.  Tolerance 1e-12: the sums of
 * 20000 equal terms (rounding 20000 x 1.1e-16 relative at most); eps_pol
 * also checks the tracer's complex amplitudes r_s, r_p against its real
 * form ((|r_s|^2 + |r_p|^2) / 2 = rho to rounding; both tests/indep.c,
 * checked against closed forms by test_fresnel_closed_forms). */
static void test_flat(void)
{
    mc_surface s;
    sea_cov2 zero = { 0, 0, 0 };
    CU_ASSERT_FATAL(mc_surface_gaussian(&s, 16, 4, &zero, 1) == 0);
    const double ths[] = { 0, 40, 80, 85, 89.9 };
    double complex N[2] = { N4, N10 };
    for (int i = 0; i < 5; i++) {
        mc_tally T;
        long R = 20000;
        CU_ASSERT_FATAL(mc_trace(&s, (sea_dir){ ths[i] * DEG, 0.3 }, N, 2, R, 7, &T) == 0);
        for (int q = 0; q < 2; q++) {
            double want = 1 - indep_fresnel(cos(ths[i] * DEG), creal(N[q]), cimag(N[q]));
            ASSERT_ABS(T.eps1[q] / R, want, 1e-12);
            ASSERT_ABS(T.eps[q] / R, want, 1e-12);
            ASSERT_ABS(T.eps_pol[q] / R, want, 1e-12);
            ASSERT_ABS(T.escaped[q][1] / R, 1 - want, 1e-12);
        }
        CU_ASSERT(T.multi == 0 && T.leaks == 0 && T.stopped == 0);
    }
    mc_surface_free(&s);
}

/* The ray tracer's Fresnel (tests/indep.c: Born & Wolf's real form with
 * their u, v for the unpolarised reflectance, the amplitudes r_s and r_p in
 * the ratio form for the polarised one), and the library's
 * sea_fresnel_unpolarized, against values known in closed form for complex
 * indices at oblique incidence:
 *  - 60 deg, N^2 = 3/4 + 2i: then w = sqrt(N^2 - sin^2) = 1 + i exactly, and
 *    by hand R_s = |1/2 - 1 - i|^2 / |1/2 + 1 + i|^2 = 5/13, r_p =
 *    (N^2/2 - w)/(N^2/2 + w) = (-5/8)/(11/8 + 2i), R_p = 25/377, so the
 *    unpolarised R = 85/377 (N = 1.2347 + 0.8099 i);
 *  - 45 deg, N^2 = 1/2 + 2i: w = 1 + i again, R_s = (5/2 - sqrt 2)/(5/2 +
 *    sqrt 2), and R_p = R_s^2 (Abeles's relation at 45 deg, true for any
 *    complex index: F. Abeles, Ann. Phys. (Paris) 5, 596 (1950));
 *  - Abeles's relation for sea water at 4 and 10 um and a metal-like
 *    N = 1.5 + 3i;
 *  - k = 0: Fresnel's angle forms R_s = sin^2(i - t)/sin^2(i + t), R_p =
 *    tan^2(i - t)/tan^2(i + t) with Snell's sin t = sin i / n (Eq 1), and
 *    R_p = 0 at Brewster's tan i = n;
 *  - normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
 * Tolerances: 1e-15 (a few ulps of the values, about 0.2) and 2e-14 for
 * the angle forms (sin^2 of small differences: relative rounding of 1e-15
 * in each factor).  The library's formula is the complex one of seabake.h;
 * over a grid of cos psi it agrees with the tracer's within 1e-14. */
static void test_fresnel_closed_forms(void)
{
    /* 60 deg, w = 1 + i */
    const double complex Na = csqrt(0.75 + 2.0 * I);
    const double c60 = 0.5; /* exactly cos 60 deg */
    double complex rs, rp;
    indep_fresnel_amplitudes(c60, Na, &rs, &rp);
    ASSERT_ABS(creal(rs * conj(rs)), 5.0 / 13.0, 1e-15);
    ASSERT_ABS(creal(rp * conj(rp)), 25.0 / 377.0, 1e-15);
    ASSERT_ABS(indep_fresnel(c60, creal(Na), cimag(Na)), 85.0 / 377.0, 1e-15);
    ASSERT_ABS(sea_fresnel_unpolarized(c60, Na), 85.0 / 377.0, 1e-15);
    /* 45 deg, w = 1 + i */
    const double complex Nb = csqrt(0.5 + 2.0 * I);
    const double c45 = M_SQRT1_2;
    const double Rs45 = (2.5 - M_SQRT2) / (2.5 + M_SQRT2);
    indep_fresnel_amplitudes(c45, Nb, &rs, &rp);
    ASSERT_ABS(creal(rs * conj(rs)), Rs45, 1e-15);
    ASSERT_ABS(creal(rp * conj(rp)), Rs45 * Rs45, 1e-15);
    ASSERT_ABS(indep_fresnel(c45, creal(Nb), cimag(Nb)), 0.5 * (Rs45 + Rs45 * Rs45), 1e-15);
    ASSERT_ABS(sea_fresnel_unpolarized(c45, Nb), 0.5 * (Rs45 + Rs45 * Rs45), 1e-15);
    /* Abeles at 45 deg for other indices */
    const double complex Ns[3] = { N4, N10, 1.5 + 3.0 * I };
    for (int q = 0; q < 3; q++) {
        indep_fresnel_amplitudes(c45, Ns[q], &rs, &rp);
        const double Rs = creal(rs * conj(rs)), Rp = creal(rp * conj(rp));
        ASSERT_ABS(Rp, Rs * Rs, 1e-15);
        ASSERT_ABS(indep_fresnel(c45, creal(Ns[q]), cimag(Ns[q])), 0.5 * (Rs + Rs * Rs), 1e-15);
        /* normal incidence */
        const double n = creal(Ns[q]), k = cimag(Ns[q]);
        const double R0 = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
        ASSERT_ABS(indep_fresnel(1.0, n, k), R0, 1e-15);
    }
    /* a real index: the angle forms, and Brewster's angle */
    const double n = 1.33;
    const double angles[] = { 0.6174, 75 * DEG, 88 * DEG };
    for (int a = 0; a < 3; a++) {
        const double i_ = angles[a], t = asin(sin(i_) / n);
        const double Rs = pow(sin(i_ - t) / sin(i_ + t), 2), Rp = pow(tan(i_ - t) / tan(i_ + t), 2);
        ASSERT_REL(indep_fresnel(cos(i_), n, 0.0), 0.5 * (Rs + Rp), 2e-14, 0);
        indep_fresnel_amplitudes(cos(i_), n, &rs, &rp);
        ASSERT_REL(creal(rs * conj(rs)), Rs, 2e-14, 0);
        ASSERT_REL(creal(rp * conj(rp)), Rp, 2e-14, 1e-3);
    }
    indep_fresnel_amplitudes(cos(atan(n)), n, &rs, &rp);
    ASSERT_ABS(cabs(rp), 0.0, 1e-15);
    /* the library's formula against the tracer's over cos psi in [0, 1] */
    double worst = 0.0;
    for (int q = 0; q < 3; q++)
        for (int j = 0; j <= 1000; j++) {
            const double c = j / 1000.0;
            worst = fmax(worst, fabs(sea_fresnel_unpolarized(c, Ns[q]) -
                                     indep_fresnel(c, creal(Ns[q]), cimag(Ns[q]))));
        }
    MEASURED("Fresnel: library against the ray tracer's, max difference %.1e\n", worst);
    CU_ASSERT(worst <= 1e-14);
}

/* The synthesised surface: triangle slope covariance equal to the target
 * (1e-12 relative: the rescaling is exact up to rounding of sums over 2 n^2
 * triangles), mean slope 0 (a periodic mesh's forward differences sum to 0;
 * 1e-15 absolute). */
static void test_surface_covariance(void)
{
    sea_cov2 tgt[] = { lr_cov(10.0), { 0.04, 0.01, 0.012 } };
    for (int k = 0; k < 2; k++) {
        mc_surface s;
        CU_ASSERT_FATAL(mc_surface_gaussian(&s, 128, 6, &tgt[k], 3 + k) == 0);
        ASSERT_REL(s.cov.xx, tgt[k].xx, 1e-12, 0);
        ASSERT_REL(s.cov.yy, tgt[k].yy, 1e-12, 0);
        ASSERT_ABS(s.cov.xy, tgt[k].xy, 1e-12 * sqrt(tgt[k].xx * tgt[k].yy));
        ASSERT_ABS(s.mean.x, 0, 1e-15);
        ASSERT_ABS(s.mean.y, 0, 1e-15);
        mc_surface_free(&s);
    }
    mc_surface s;
    sea_cov2 bad = { 0.01, 0.0, 0.0 };
    CU_ASSERT(mc_surface_gaussian(&s, 128, 6, &bad, 1) == -1);
}

/* Energy conservation on a rough surface at grazing views, where rays hit
 * two and more times: per ray, absorbed + escaped = 1 to rounding (1e-12);
 * over the beam, eps + escaped energy = rays; no ray leaks through the mesh;
 * eps >= eps1 (absorption only adds); the polarised and unpolarised totals
 * share their first hit, and differ by less than the multiple part. */
static void test_energy(void)
{
    mc_surface s;
    sea_cov2 c = { 0.08, 0.06, 0.01 }; /* rougher than 40 m/s */
    CU_ASSERT_FATAL(mc_surface_gaussian(&s, 128, 6, &c, 5) == 0);
    double complex N[2] = { N4, N10 };
    const double ths[] = { 60, 80, 88 };
    for (int i = 0; i < 3; i++) {
        mc_tally T;
        long R = 20000;
        CU_ASSERT_FATAL(mc_trace(&s, (sea_dir){ ths[i] * DEG, 0.7 }, N, 2, R, 11, &T) == 0);
        CU_ASSERT(T.max_energy_err <= 1e-12);
        CU_ASSERT(T.leaks == 0 && T.stopped == 0);
        CU_ASSERT(T.multi > 0);
        for (int q = 0; q < 2; q++) {
            double esc = 0;
            for (int b = 0; b < MC_NBOUNCE; b++)
                esc += T.escaped[q][b];
            ASSERT_REL(T.eps[q] + esc, (double)R, 1e-12, 1);
            CU_ASSERT(T.eps[q] >= T.eps1[q]);
            CU_ASSERT(T.eps_pol[q] >= T.eps1[q]);
            CU_ASSERT(fabs(T.eps_pol[q] - T.eps[q]) <= T.eps[q] - T.eps1[q]);
            CU_ASSERT(T.residual[q] <= 1e-6 * R);
        }
    }
    mc_surface_free(&s);
}

/* A roof of tilted planes: periodic triangle wave along x, slopes +a and -a
 * over equal halves.  Seen from azimuth 0 with a tan(theta) < 1 nothing is
 * shadowed and the projected areas give the fraction of first hits on the
 * +a face exactly: (1 - a tan theta) / 2; with a tan theta > 1 that face is
 * turned away: 0 exactly; from azimuth 90 deg: 1/2.  The single-bounce
 * emissivity is then f (1 - rho(psi+)) + (1 - f) (1 - rho(psi-)), cos psi+-
 * = (cos theta -+ a sin theta cos phi) / sqrt(1 + a^2).  Tolerance 4
 * binomial standard errors sqrt(f (1 - f) / R) (and that times the
 * emissivity contrast, plus 1e-12 rounding); the seeds are fixed, so the
 * check is reproducible, and 4 sigma rejects a correct tracer with
 * probability 6e-5 for any other seed. */
static void test_roof(void)
{
    const int n = 64;
    const double a = 0.3;
    double *h = malloc(sizeof(double) * n * n);
    CU_ASSERT_FATAL(h != NULL);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            h[j * n + i] = a * (i < n - i ? i : n - i);
    const double A[2][2] = { { 1, 0 }, { 0, 1 } };
    mc_surface s;
    CU_ASSERT_FATAL(mc_surface_from_heights(&s, n, h, A) == 0);
    free(h);
    ASSERT_REL(s.cov.xx, a * a, 1e-13, 0);
    const double cases[][2] = { { 60, 0 }, { 30, 0 }, { 80, 0 }, { 70, 90 } };
    for (int c = 0; c < 4; c++) {
        double th = cases[c][0] * DEG, ph = cases[c][1] * DEG;
        double f = cos(ph) > 0.5 ? fmax(0, (1 - a * tan(th)) / 2) : 0.5;
        long R = 100000;
        mc_tally T;
        CU_ASSERT_FATAL(mc_trace(&s, (sea_dir){ th, ph }, &N4, 1, R, 13, &T) == 0);
        double se = sqrt(f * (1 - f) / R);
        ASSERT_ABS((double)T.first_up / R, f, 4 * se + 1e-12);
        double cp = (cos(th) - a * sin(th) * cos(ph)) / sqrt(1 + a * a);
        double cm = (cos(th) + a * sin(th) * cos(ph)) / sqrt(1 + a * a);
        double ep = 1 - indep_fresnel(fmax(cp, 0), creal(N4), cimag(N4));
        double em = 1 - indep_fresnel(cm, creal(N4), cimag(N4));
        ASSERT_ABS(T.eps1[0] / R, f * ep + (1 - f) * em, 4 * se * fabs(ep - em) + 1e-12);
        CU_ASSERT(T.leaks == 0 && T.max_energy_err <= 1e-12);
    }
    mc_surface_free(&s);
}

/* Same rays, same sums whatever the number of threads (partial sums in a
 * fixed order): bit for bit. */
static void test_reproducible(void)
{
#ifdef _OPENMP
    mc_surface s;
    sea_cov2 c = lr_cov(10.0);
    CU_ASSERT_FATAL(mc_surface_gaussian(&s, 64, 4, &c, 2) == 0);
    mc_tally a, b;
    int nt = omp_get_max_threads();
    omp_set_num_threads(1);
    CU_ASSERT(mc_trace(&s, (sea_dir){ 80 * DEG, 0 }, &N4, 1, 20000, 3, &a) == 0);
    omp_set_num_threads(nt > 1 ? nt : 2);
    CU_ASSERT(mc_trace(&s, (sea_dir){ 80 * DEG, 0 }, &N4, 1, 20000, 3, &b) == 0);
    omp_set_num_threads(nt);
    CU_ASSERT(a.eps[0] == b.eps[0] && a.eps1[0] == b.eps1[0] && a.eps_pol[0] == b.eps_pol[0]);
    mc_surface_free(&s);
#else
    UNIT_SKIP("the tracer's sums whatever the threads: built without OpenMP");
#endif
}

/* At nadir and 40 deg (cot theta = 6 sigma at 10 m/s: Smith's Lambda
 * ~ 1e-11, no shadowing to speak of) the model's default emissivity is the
 * exact projected-area average of 1 - rho over Gaussian slopes, which is
 * what the oracle's single-bounce eps1 estimates: they must agree within
 * the oracle's statistical error.  Tolerance 4 standard errors of the mean
 * over 4 seeds (4 x 20000 rays, n = 256, ell = 8: the table's mesh
 * resolution) plus 1e-6 (the default rule's own error, < 7.6e-7): a check
 * of the tracer itself on small surfaces; the manual's figure (1.7e-5 to
 * 40 deg) is asserted on the stored table's rows (test_table).
 * Measured: nadir |d| / se and 40 deg printed below. */
static void test_against_model(void)
{
    sea_cov2 c = lr_cov(10.0);
    sea_slope_stats st = { { 0, 0 }, c };
    const double ths[] = { 0, 40 };
    const int S = 4;
    double m[2][4];
    for (int k = 0; k < S; k++) {
        mc_surface s;
        CU_ASSERT_FATAL(mc_surface_gaussian(&s, 256, 8, &c, 100 + k) == 0);
        for (int i = 0; i < 2; i++) {
            mc_tally T;
            long R = 20000;
            CU_ASSERT_FATAL(mc_trace(&s, (sea_dir){ ths[i] * DEG, 0 }, &N4, 1, R, 17 + k, &T) == 0);
            m[i][k] = T.eps1[0] / R;
        }
        mc_surface_free(&s);
    }
    for (int i = 0; i < 2; i++) {
        double mean = 0, var = 0, model = NAN;
        for (int k = 0; k < S; k++)
            mean += m[i][k] / S;
        for (int k = 0; k < S; k++)
            var += (m[i][k] - mean) * (m[i][k] - mean) / (S - 1);
        double se = sqrt(var / S);
        CU_ASSERT(sea_emissivity(P, SEA_EMIS_AUTO, N4, &st, (sea_dir){ ths[i] * DEG, 0 }, &model,
                                 NULL) == SEA_OK);
        MEASURED("mc oracle at %g deg, 10 m/s, 4 um: model - eps1 = %.2e, se %.2e\n", ths[i],
                 model - mean, se);
        ASSERT_ABS(mean, model, 4 * se + 1e-6);
    }
}

/* A table of tests/data, or NULL. */
static FILE *open_data(const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/%s", SEA_TOP_SRCDIR, name);
    return fopen(path, "r");
}

/* The first max comma-separated numbers of a table row into x: how many. */
static int csv_numbers(const char *line, double *x, int max)
{
    const char *p = line;
    char *end;
    int k = 0;
    for (; k < max; k++) {
        x[k] = strtod(p, &end);
        if (end == p)
            break;
        p = *end == ',' ? end + 1 : end;
    }
    return k;
}

/* The visibility of the correlated shadowing, for tests/indep.c's Eq 7. */
static double corr_vis(double z, double t)
{
    return sea_shadow_correlated(z, t);
}

/* Rows' gaps d (model minus ray tracing) against a figure of
 * tests/claims.csv.  A bound ("<=") must hold on every row with that row's
 * standard error: the row asserted is the one closest to its bound, |d| - k
 * se largest (k the claim's multiple of se).  A value ("=") is the largest
 * |d|, asserted with its row's standard error. */
typedef struct {
    const char *id;
    double d, se, crit;
    int n;
} gap;

static void gap_add(gap *g, double d, double se)
{
    const claim *c = unit_claim_find(g->id);
    const int bound = c == NULL || c->kind == CLAIM_LE;
    const double crit = bound ? fabs(d) - (c != NULL ? c->se_mult : 3.0) * se : fabs(d);
    if (g->n++ == 0 || crit > g->crit) {
        g->crit = crit;
        g->d = fabs(d);
        g->se = se;
    }
}

static void gap_assert(const gap *g)
{
    CU_ASSERT(g->n > 0);
    ASSERT_CLAIM(g->id, g->d, g->se);
}

/* The stored table (tests/data/mc_emissivity.csv), its model column first:
 * it was written by the library (tests/mc_model_refresh.c rewrites it), so
 * it and today's sea_emissivity are both held against Eq 7 computed
 * independently (tests/indep.c: its own Fresnel, adaptive quadrature, Smith's
 * Lambda in closed form) at the default rule's promise, 1e-6.  The slope
 * variances are sea_spectrum_slope_cov's (9 digits: 1e-8).  Then the
 * figures of seabake-model(7), TRUTH BY RAY TRACING, SHADOWING and
 * MULTIPLE REFLECTIONS (tests/claims.csv), each against the ray tracer's
 * columns with their standard errors: eps1 (single bounce) for one
 * reflection, eps (every hit) for reflections = 2 and for the energy one
 * reflection misses. */
static void test_table(void)
{
    FILE *f = open_data("mc_emissivity.csv");
    CU_ASSERT_FATAL(f != NULL);
    char line[1024];
    int rows = 0, header = 0, need = 0;
    double col_worst = 0.0, lib_worst = 0.0;
    double se80 = 0.0, se85 = 0.0, pol_min = INFINITY, pol_max = 0.0;
    gap agree40 = { .id = "mc_agree_40" }, agree60 = { .id = "mc_agree_60" };
    gap corr1[3] = { { .id = "corr_single_75" }, { .id = "corr_single_80" }, { .id = "corr_single_85" } };
    gap smith1[3] = { { .id = "smith_single_75" }, { .id = "smith_single_80" }, { .id = "smith_single_85" } };
    gap corr2[3] = { { .id = "multi_corr_75" }, { .id = "multi_corr_80" }, { .id = "multi_corr_85" } };
    gap smith2[3] = { { .id = "multi_smith_75" }, { .id = "multi_smith_80" }, { .id = "multi_smith_85" } };
    gap corr_all1[3] = { { .id = "single_corr_75" }, { .id = "single_corr_80" }, { .id = "single_corr_85" } };
    gap smith_all1[3] = { { .id = "single_smith_75" }, { .id = "single_smith_80" }, { .id = "single_smith_85" } };
    sea_water *w = NULL;
    CU_ASSERT_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) == SEA_OK);
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        if (!header) {
            CU_ASSERT(strncmp(line, "wind_ms,wavelength_um,theta_deg,phi_deg,sxx,syy,eps1,eps1_se,"
                                    "eps,eps_se,", 64) == 0);
            header = 1;
            continue;
        }
        double x[17];
        CU_ASSERT_FATAL(csv_numbers(line, x, 17) == 17);
        const double wind = x[0], wl = x[1], th = x[2], ph = x[3];
        const double eps1 = x[6], eps1_se = x[7], eps = x[8], eps_se = x[9], eps_pol = x[10];
        sea_cov2 c = lr_cov(wind);
        ASSERT_REL(x[4], c.xx, 1e-8, 0);
        ASSERT_REL(x[5], c.yy, 1e-8, 0);
        double complex N;
        CU_ASSERT(sea_water_index(w, wl * 1e-6, &N, NULL) == SEA_OK);
        const sea_slope_stats st = { { 0, 0 }, c };
        const sea_dir v = { th * DEG, ph * DEG };
        double model = NAN;
        CU_ASSERT(sea_emissivity(P, SEA_EMIS_AUTO, N, &st, v, &model, NULL) == SEA_OK);
        if (!UNIT_QUICK || rows % 8 == 0) { /* (under a memory checker: the same code, less) */
            const double indep = indep_emissivity(N, 0, 0, c.xx, c.yy, 0, v.theta, v.phi, NULL);
            CU_ASSERT(isfinite(indep));
            col_worst = fmax(col_worst, fabs(x[16] - indep));
            lib_worst = fmax(lib_worst, fabs(model - indep));
        }
        if (th <= 40)
            gap_add(&agree40, model - eps1, eps1_se);
        if (th <= 60)
            gap_add(&agree60, model - eps1, eps1_se);
        if (th >= 60) {
            double e2 = NAN, ec = NAN, ec2 = NAN;
            CU_ASSERT(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N, 1, &st, v, 2, &e2,
                                             NULL) == SEA_OK);
            CU_ASSERT(sea_emissivity(PC, SEA_EMIS_AUTO, N, &st, v, &ec, NULL) == SEA_OK);
            CU_ASSERT(sea_emissivity_multi_n(PC, SEA_EMIS_AUTO, NULL, &N, 1, &st, v, 2, &ec2,
                                             NULL) == SEA_OK);
            const int b = th <= 75 ? 0 : th <= 80 ? 1 : 2;
            gap_add(&smith1[b], model - eps1, eps1_se);
            gap_add(&corr1[b], ec - eps1, eps1_se);
            gap_add(&smith_all1[b], model - eps, eps_se);
            gap_add(&corr_all1[b], ec - eps, eps_se);
            gap_add(&smith2[b], e2 - eps, eps_se);
            gap_add(&corr2[b], ec2 - eps, eps_se);
        }
        if (th == 80)
            se80 = fmax(se80, fmax(eps1_se, eps_se));
        if (th == 85)
            se85 = fmax(se85, fmax(eps1_se, eps_se));
        if (th >= 70 && th <= 85) {
            pol_min = fmin(pol_min, eps - eps_pol);
            pol_max = fmax(pol_max, eps - eps_pol);
        }
        if ((wind == 5 || wind == 10) && (wl == 4 || wl == 10) &&
            (th == 70 || th == 80 || th == 85) && ph == 0)
            need++;
        rows++;
    }
    fclose(f);
    sea_water_free(w);
    CU_ASSERT(header && rows > 0);
    CU_ASSERT(need == 12); /* the rows the manual quotes */
    MEASURED("mc table: |model column - independent Eq 7| <= %.1e, |sea_emissivity - independent "
             "Eq 7| <= %.1e over %d rows\n", col_worst, lib_worst, rows);
    ASSERT_CLAIM("auto_within_full", col_worst, 0.0);
    ASSERT_CLAIM("auto_within_full", lib_worst, 0.0);
    gap_assert(&agree40);
    gap_assert(&agree60);
    for (int b = 0; b < 3; b++) {
        gap_assert(&corr1[b]);
        gap_assert(&smith1[b]);
        gap_assert(&corr2[b]);
        gap_assert(&smith2[b]);
        gap_assert(&corr_all1[b]);
        gap_assert(&smith_all1[b]);
    }
    ASSERT_CLAIM("mc_se_80", se80, 0.0);
    ASSERT_CLAIM("mc_se_85", se85, 0.0);
    ASSERT_CLAIM("mc_pol_min", pol_min, 0.0);
    ASSERT_CLAIM("mc_pol_max", pol_max, 0.0);
}

/* The sea-spectrum tables' rows grouped by direction (wind x[0], theta
 * x[2], phi x[3]): two gaps per row, model - ray tracing, summed so that
 * their means over the surfaces and standard errors can be read. */
enum { DIRS_MAX = 32 };
typedef struct {
    double key[3], sum[2], sq[2];
    int cnt;
} dir_tally;

static void tally_add(dir_tally *t, int *nd, const double *x, const double g[2])
{
    int d = 0;
    while (d < *nd && !(t[d].key[0] == x[0] && t[d].key[1] == x[2] && t[d].key[2] == x[3]))
        d++;
    if (d == *nd) {
        CU_ASSERT_FATAL(*nd < DIRS_MAX);
        t[d] = (dir_tally){ { x[0], x[2], x[3] }, { 0.0, 0.0 }, { 0.0, 0.0 }, 0 };
        (*nd)++;
    }
    for (int m = 0; m < 2; m++) {
        t[d].sum[m] += g[m];
        t[d].sq[m] += g[m] * g[m];
    }
    t[d].cnt++;
}

static void tally_mean(const dir_tally *t, double mean[2], double se[2])
{
    for (int m = 0; m < 2; m++) {
        mean[m] = t->sum[m] / t->cnt;
        se[m] = sqrt(fmax(t->sq[m] / t->cnt - mean[m] * mean[m], 0.0) / (t->cnt - 1));
    }
}

/* A sea table's model columns (Smith's x[8], correlated x[9]) and today's
 * sea_emissivity against Eq 7 computed independently (tests/indep.c; the
 * correlated one weighs the facets by the library's tabulated C(z, t),
 * whose own accuracy tests/test_shadow.c checks against the exact integral
 * and ray-traced profiles): the larger differences into *col and *lib.
 * Under a memory checker (SEA_UNIT_QUICK) every 8th row: the same code. */
static void model_columns(const double *x, int row, double *col, double *lib)
{
    if (UNIT_QUICK && row % 8 != 0)
        return;
    const sea_slope_stats st = { { 0, 0 }, { x[4], x[5], x[6] } };
    const sea_dir v = { x[2] * DEG, x[3] * DEG };
    double es = NAN, ec = NAN;
    CU_ASSERT(sea_emissivity(P, SEA_EMIS_AUTO, N4, &st, v, &es, NULL) == SEA_OK);
    CU_ASSERT(sea_emissivity(PC, SEA_EMIS_AUTO, N4, &st, v, &ec, NULL) == SEA_OK);
    const double is = indep_emissivity(N4, 0, 0, x[4], x[5], x[6], v.theta, v.phi, NULL);
    const double ic = indep_emissivity(N4, 0, 0, x[4], x[5], x[6], v.theta, v.phi, corr_vis);
    CU_ASSERT(isfinite(is) && isfinite(ic));
    *col = fmax(*col, fmax(fabs(x[8] - is), fabs(x[9] - ic)));
    *lib = fmax(*lib, fmax(fabs(es - is), fabs(ec - ic)));
}

/* The many-scale table (tests/mc_sea_oracle.c): every row's model columns,
 * and today's model, are Eq 7 at the row's slope covariance computed
 * independently (1e-6, as above), and what it shows stays true: over sea-spectrum surfaces (many scales, where
 * the correlated function assumes one) the correlated shadowing is closer
 * to ray tracing than Smith's at 75-85 deg but still low, by about half of
 * Smith's gap at 80-85 deg along the wind (seabake-model(7), TRUTH BY RAY
 * TRACING), where the figures at 85 deg along the wind at 10 m/s are
 * asserted (tests/claims.csv, 3 standard errors of the 12 surfaces' mean).
 * Bounds from the table's seed means and standard errors. */
static void test_sea_table(void)
{
    FILE *f = open_data("mc_sea_emissivity.csv");
    CU_ASSERT_FATAL(f != NULL);
    char line[1024];
    int header = 0, rows = 0, nd = 0;
    double col_worst = 0.0, lib_worst = 0.0;
    dir_tally tally[DIRS_MAX];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        if (!header) {
            CU_ASSERT(strcmp(line, "wind_ms,seed,theta_deg,phi_deg,sxx,syy,sxy,eps1,model_smith,"
                                   "model_corr\n") == 0);
            header = 1;
            continue;
        }
        double x[10];
        CU_ASSERT_FATAL(csv_numbers(line, x, 10) == 10);
        model_columns(x, rows, &col_worst, &lib_worst);
        const double g[2] = { x[8] - x[7], x[9] - x[7] };
        tally_add(tally, &nd, x, g);
        rows++;
    }
    fclose(f);
    CU_ASSERT(header && rows >= 2 * nd && nd >= 8);
    MEASURED("sea table: |model columns - independent Eq 7| <= %.1e, |sea_emissivity - "
             "independent Eq 7| <= %.1e over %d rows\n", col_worst, lib_worst, rows);
    ASSERT_CLAIM("auto_within_full", col_worst, 0.0);
    ASSERT_CLAIM("auto_within_full", lib_worst, 0.0);
    int quoted = 0;
    for (int d = 0; d < nd; d++) {
        double mean[2], se[2];
        tally_mean(&tally[d], mean, se);
        const double *key = tally[d].key;
        MEASURED("sea-spectrum surfaces, %g m/s, %g deg, phi %g: model - ray tracing: Smith's "
                 "%+.4f +- %.4f, correlated %+.4f +- %.4f\n",
                 key[0], key[1], key[2], mean[0], se[0], mean[1], se[1]);
        /* within 3 standard errors: correlated at least as close as Smith's,
         * and never above the truth by more than that */
        CU_ASSERT(fabs(mean[1]) <= fabs(mean[0]) + 3.0 * se[1]);
        CU_ASSERT(mean[1] <= 3.0 * se[1] + 5e-4);
        if (key[1] >= 85.0)
            CU_ASSERT(mean[1] < -3.0 * se[1]); /* the gap that remains */
        if (key[0] == 10.0 && key[1] == 85.0 && key[2] == 0.0) {
            /* seabake-model(7)'s figures: 15.3e-3 low, Smith's 25.0e-3 */
            ASSERT_CLAIM("sea_corr_85_10", mean[1], se[1]);
            ASSERT_CLAIM("sea_smith_85_10", mean[0], se[0]);
            quoted++;
        }
    }
    CU_ASSERT_EQUAL(quoted, 1);
}

/* Two scales (sea_emissivity_two_scale) against the sea-spectrum surfaces
 * of the full table (tests/data/mc_sea_full_emissivity.csv: waves from 0.32
 * to 328 m, 4 surfaces per wind, 5-15 m/s, 75-85 deg along and across the
 * wind).  Each surface's slopes split as the render splits the sea's
 * (sea_spectrum_split_at, which sea_spectrum_split_half calls with half the
 * variance) at half the surface's measured variance (the surfaces lack the
 * waves under 0.32 m that the spectrum's variance counts): the resolved
 * band is the spectrum's from the period's wavenumber to the split, the
 * sub-facet band the rest of the measured covariance.  The table's model
 * columns, and today's model, against the independent Eq 7 (1e-6).  The
 * figures of seabake-model(7) (tests/claims.csv; measured model - ray
 * tracing, mean over the surfaces): two scales within 1.4e-3 to 82 deg
 * and 4.6e-3 at 85, each direction to its figure plus 3 standard errors
 * of its 4 surfaces' mean, where one scale is up to 8.1e-3 and 19.7e-3
 * low; and two scales never further from the truth than one. */
static void test_two_scale_table(void)
{
    FILE *f = open_data("mc_sea_full_emissivity.csv");
    CU_ASSERT_FATAL(f != NULL);
    const double kmin = 2.0 * M_PI / (8192 * 0.04); /* the surfaces' period */
    char line[1024];
    int header = 0, nd = 0, rows = 0;
    double col_worst = 0.0, lib_worst = 0.0;
    dir_tally tally[DIRS_MAX];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        if (!header) {
            header = 1;
            continue;
        }
        double x[10];
        CU_ASSERT_FATAL(csv_numbers(line, x, 10) == 10);
        model_columns(x, rows++, &col_worst, &lib_worst);
        sea_spectrum sp;
        CU_ASSERT_FATAL(sea_spectrum_init(x[0], INFINITY, 0.0, &sp, NULL) == SEA_OK);
        /* the render's split (sea_spectrum_split_half calls it with half the
         * spectrum's variance), at half the surface's own variance */
        double k;
        sea_cov2 res, spec_sub;
        CU_ASSERT_FATAL(sea_spectrum_split_at(&sp, kmin, 0.5 * (x[4] + x[5]), &k, &res, &spec_sub,
                                              NULL) == SEA_OK);
        const sea_slope_stats sub = { { 0, 0 }, { x[4] - res.xx, x[5] - res.yy, x[6] - res.xy } };
        const sea_dir v = { x[2] * DEG, x[3] * DEG };
        double e2 = NAN;
        CU_ASSERT_FATAL(sea_emissivity_two_scale(PC, N4, &sub, res, v, &e2, NULL) == SEA_OK);
        const double g[2] = { x[9] - x[7], e2 - x[7] };
        tally_add(tally, &nd, x, g);
    }
    fclose(f);
    CU_ASSERT(header && nd == 24);
    ASSERT_CLAIM("auto_within_full", col_worst, 0.0);
    ASSERT_CLAIM("auto_within_full", lib_worst, 0.0);
    gap two[2] = { { .id = "two_scale_82" }, { .id = "two_scale_85" } };
    gap one[2] = { { .id = "one_scale_82" }, { .id = "one_scale_85" } };
    for (int d = 0; d < nd; d++) {
        double mean[2], se[2];
        tally_mean(&tally[d], mean, se);
        const double *key = tally[d].key;
        MEASURED("sea-spectrum surfaces to 328 m, %g m/s, %g deg, phi %g: model - ray tracing: "
                 "one scale %+.4f, two scales %+.4f +- %.4f\n",
                 key[0], key[1], key[2], mean[0], mean[1], se[1]);
        gap_add(&two[key[1] > 82.0], mean[1], se[1]);
        gap_add(&one[key[1] > 82.0], mean[0], se[0]);
        CU_ASSERT(fabs(mean[1]) <= fabs(mean[0]) + 3.0 * se[1]);
    }
    for (int b = 0; b < 2; b++) {
        gap_assert(&two[b]);
        gap_assert(&one[b]);
    }
    /* the render's function is this split at half the variance, to the bit */
    sea_spectrum sp;
    CU_ASSERT_FATAL(sea_spectrum_init(10.0, INFINITY, 0.5, &sp, NULL) == SEA_OK);
    for (int c = 0; c < 2; c++) {
        const double kc = c ? kmin : 0.0;
        double kh, ka;
        sea_cov2 r1, s1, r2, s2, all;
        CU_ASSERT_FATAL(sea_spectrum_split_half(&sp, kc, &kh, &r1, &s1, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_spectrum_slope_cov(&sp, kc, &all, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_spectrum_split_at(&sp, kc, 0.5 * (all.xx + all.yy), &ka, &r2, &s2,
                                              NULL) == SEA_OK);
        CU_ASSERT(kh == ka && r1.xx == r2.xx && r1.yy == r2.yy && s1.xx == s2.xx);
        ASSERT_REL(r1.xx + r1.yy, s1.xx + s1.yy, 1e-8, 0); /* halves */
    }
}

/* Two scales' limits: a resolved band vanishing (1e-6 of the variance) is
 * the one-scale Eq 7 (2e-6: the default rule's 1e-6 and the band's own
 * 1e-6 of the slopes; the quadrature runs: the shortcut for no band at
 * all is below 1e-12 of the trace); at
 * nadir every facet counts alike (g = 1, nothing hidden) and the mixture
 * of Gaussians is the Gaussian of the summed covariance (1e-6: the two
 * quadratures); with a vanishing sub-facet band it is the one-scale
 * correlated Eq 7 of the resolved band (the same weights; 1e-4: 24 x 8
 * nodes against the auto rule); a flat sea is Fresnel.  And the table the
 * render adds (sea_two_scale_delta) against the direct difference, for
 * facets of 1 m, 8 m and low resolution, tilted ones too, 60-88 deg. */
static void test_two_scale_limits(void)
{
    const double winds[] = { 3, 10, 15 };
    for (int a = 0; a < 3; a++) {
        const sea_cov2 C = lr_cov(winds[a]);
        const sea_cov2 half = { 0.5 * C.xx, 0.5 * C.yy, 0.5 * C.xy };
        const sea_slope_stats all = { { 0, 0 }, C }, sub = { { 0, 0 }, half };
        /* a resolved band a million times narrower than the sea's: the
         * quadrature over its facets (above the cut to one scale, 1e-12 of
         * the trace) gives the one-scale value, whose own rule error is
         * 1e-6; the first order of the band is 1e-6 of the slopes' */
        const sea_cov2 narrow = { 1e-6 * C.xx, 1e-6 * C.yy, 1e-6 * C.xy };
        for (double th = 0.0; th < 89.5; th += 20.0) {
            const sea_dir v = { th * DEG, 0.3 };
            double e1, e2;
            CU_ASSERT_FATAL(sea_emissivity(PC, SEA_EMIS_FULL, N4, &all, v, &e1, NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity_two_scale(PC, N4, &all, narrow, v, &e2, NULL) == SEA_OK);
            ASSERT_ABS(e2, e1, 2e-6);
        }
        const sea_dir nadir = { 0.0, 0.0 };
        double e1, e2;
        CU_ASSERT_FATAL(sea_emissivity(PC, SEA_EMIS_FULL, N4, &all, nadir, &e1, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_emissivity_two_scale(PC, N4, &sub, half, nadir, &e2, NULL) == SEA_OK);
        ASSERT_ABS(e2, e1, 1e-6);
        const sea_slope_stats tiny = { { 0, 0 }, { 1e-9, 1e-9, 0 } };
        for (double th = 40.0; th < 86.0; th += 15.0) {
            const sea_dir v = { th * DEG, 0.3 };
            CU_ASSERT_FATAL(sea_emissivity(PC, SEA_EMIS_FULL, N4, &all, v, &e1, NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity_two_scale(PC, N4, &tiny, C, v, &e2, NULL) == SEA_OK);
            ASSERT_ABS(e2, e1, 1e-4);
        }
    }
    const sea_slope_stats flat = { { 0, 0 }, { 1e-12, 1e-12, 0 } };
    const sea_cov2 zero = { 1e-14, 1e-14, 0 };
    const sea_dir v60 = { 60 * DEG, 0 };
    double e, rho;
    CU_ASSERT_FATAL(sea_emissivity_two_scale(PC, N4, &flat, zero, v60, &e, NULL) == SEA_OK);
    rho = sea_fresnel_unpolarized(cos(v60.theta), N4);
    ASSERT_ABS(e, 1.0 - rho, 1e-6);

    /* the table */
    sea_spectrum sp;
    CU_ASSERT_FATAL(sea_spectrum_init(10.0, INFINITY, 0.5, &sp, NULL) == SEA_OK);
    double kh;
    sea_cov2 res, hsub;
    CU_ASSERT_FATAL(sea_spectrum_split_half(&sp, 0.0, &kh, &res, &hsub, NULL) == SEA_OK);
    const sea_cov2 tot = { res.xx + hsub.xx, res.yy + hsub.yy, res.xy + hsub.xy };
    sea_two_scale_table *t = NULL;
    CU_ASSERT_FATAL(sea_two_scale_table_alloc(PC, &N4, 1, hsub, tot, 0.5, &t, NULL) == SEA_OK);
    /* nothing computed until asked; far from the visibility limit nothing
     * is (low resolution at 45 deg: z = 6.3) */
    CU_ASSERT_EQUAL(sea_two_scale_table_rows(t), 0);
    const sea_slope_stats lr = { { 0, 0 }, tot };
    double d0 = NAN;
    CU_ASSERT(sea_two_scale_delta(t, (sea_dir){ 45 * DEG, 0.2 }, &lr, &d0, NULL) == SEA_OK);
    CU_ASSERT(d0 == 0.0 && sea_two_scale_table_rows(t) == 0);
    CU_ASSERT(sea_two_scale_delta(t, (sea_dir){ 80 * DEG, 0.2 }, &lr, &d0, NULL) == SEA_OK);
    CU_ASSERT(d0 > 0.0 && sea_two_scale_table_rows(t) > 0 && sea_two_scale_table_rows(t) <= 16);
    /* the table against its exact form (sea_two_scale_delta_exact) and
     * against the direct difference of the facet's own covariance */
    double worst[2] = { 0.0, 0.0 }, own = 0.0; /* to 85 deg, beyond */
    const double facets[] = { 1.0, 8.0, 0.0 }; /* m; 0: low resolution */
    for (int l = 0; l < 3; l++) {
        sea_cov2 fc;
        CU_ASSERT_FATAL(sea_spectrum_slope_cov(&sp, facets[l] > 0 ? M_PI / facets[l] : 0.0, &fc,
                                               NULL) == SEA_OK);
        const sea_cov2 fres = { fc.xx - hsub.xx, fc.yy - hsub.yy, fc.xy - hsub.xy };
        const double means[3][2] = { { 0, 0 }, { 0.08, -0.03 }, { -0.05, 0.06 } };
        for (int m = 0; m < (l < 2 ? 3 : 1); m++)
            for (double th = 60.0; th < 89.5; th += 7.0)
                for (double ph = 0.0; ph < 180.0; ph += 50.0) {
                    const sea_dir v = { th * DEG, ph * DEG };
                    const sea_slope_stats one = { { means[m][0], means[m][1] }, fc };
                    const sea_slope_stats two = { { means[m][0], means[m][1] }, hsub };
                    double e1, e2, d = NAN, x = NAN;
                    CU_ASSERT_FATAL(sea_emissivity(PC, SEA_EMIS_AUTO, N4, &one, v, &e1, NULL) ==
                                    SEA_OK);
                    CU_ASSERT_FATAL(sea_emissivity_two_scale(PC, N4, &two, fres, v, &e2, NULL) ==
                                    SEA_OK);
                    CU_ASSERT(sea_two_scale_delta(t, v, &one, &d, NULL) == SEA_OK);
                    CU_ASSERT(sea_two_scale_delta_exact(t, v, &one, &x, NULL) == SEA_OK);
                    CU_ASSERT(isfinite(d) && isfinite(x));
                    const int k = th > 85.0;
                    worst[k] = fmax(worst[k], fabs(d - x));
                    own = fmax(own, fabs(x - (e2 - e1)));
                }
    }
    /* measured 1.19e-4 to 85 deg and 5.40e-4 at 88 (additions of
     * 0.002-0.07: the table's orders 12 x 4 against 24 x 8 and its
     * interpolation, worst near the visibility limit), and 6.9e-4 between
     * the exact form and the difference with the facet's own covariance
     * (a 1 m facet's covariance is not exactly on the line from the
     * split's to low resolution's, whose trace defines the addition). */
    MEASURED("two-scale table: worst |table - exact| %.2e to 85 deg, %.2e at 88; "
             "|exact - own covariance| %.2e\n",
             worst[0], worst[1], own);
    ASSERT_CLAIM("two_scale_table_85", worst[0], 0.0);
    ASSERT_CLAIM("two_scale_table_88", worst[1], 0.0);
    CU_ASSERT(own <= 1e-3);
    /* Near the visibility limit the addition turns sharply (z of 0 to
     * 0.02, where the one-scale facet's mean plane starts to face the
     * view), and the table's Catmull-Rom stencil across the turn is far
     * worse than on the grid above: a scan in z there, over facets on the
     * split's line (f of 0.35 and 0.75), mean slopes across the view of
     * 0.045 and -0.185, azimuths on both sides of the wind, 72-85 deg (the
     * worst point of examples/mast.ini at the NETD's tolerance, 81.4 deg,
     * azimuth -122 deg to the wind, z = 0.056, f = 0.35, is one of them).
     * The quadrature at the table's orders without interpolation (what T
     * below 1e-3 uses, sea_two_scale_delta_direct) is checked there too. */
    double limit = 0.0, direct = 0.0;
    const double fs[2] = { 0.35, 0.75 }, ths[4] = { 72.0, 76.0, 81.36, 85.0 };
    const double psis[3] = { -122.27, 55.0, 10.0 }, mys[2] = { 0.045, -0.185 };
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 4; b++)
            for (int c = 0; c < 3; c++)
                for (int g = 0; g < 2; g++)
                    for (double z = -0.2; z < 0.5; z += 0.02) {
                        const double f = fs[a], phi = 0.5 + psis[c] * DEG;
                        const sea_cov2 C = { hsub.xx + f * (tot.xx - hsub.xx),
                                             hsub.yy + f * (tot.yy - hsub.yy),
                                             hsub.xy + f * (tot.xy - hsub.xy) };
                        const double cp = cos(phi), sp_ = sin(phi);
                        const double sX = sqrt(C.xx * cp * cp + 2.0 * C.xy * sp_ * cp +
                                               C.yy * sp_ * sp_);
                        const double mX = 1.0 / tan(ths[b] * DEG) - z * sX;
                        const sea_slope_stats st = {
                            { mX * cp - mys[g] * sp_, mX * sp_ + mys[g] * cp }, C };
                        const sea_dir v = { ths[b] * DEG, phi };
                        double d = NAN, x = NAN, y = NAN;
                        CU_ASSERT(sea_two_scale_delta(t, v, &st, &d, NULL) == SEA_OK);
                        CU_ASSERT(sea_two_scale_delta_exact(t, v, &st, &x, NULL) == SEA_OK);
                        CU_ASSERT(sea_two_scale_delta_direct(t, v, &st, &y, NULL) == SEA_OK);
                        limit = fmax(limit, fabs(d - x));
                        direct = fmax(direct, fabs(y - x));
                    }
    /* measured 6.8e-4 (table) and 2.1e-5 (direct): the table only at
     * T >= 1e-3 (model.c, SEA_MODEL_TABLE_TOL), the direct quadrature
     * below */
    MEASURED("two-scale table near the visibility limit: worst |table - exact| %.2e, "
             "|direct - exact| %.2e\n",
             limit, direct);
    ASSERT_CLAIM("two_scale_table_limit", limit, 0.0);
    ASSERT_CLAIM("two_scale_direct", direct, 0.0);
    sea_two_scale_table_free(t);
}

/* Multiple reflections: reflections = 1 is the paper's emissivity to the
 * bit; a flat sea's mirror ray never meets the sea again (Lambda = 0), so
 * every R gives 1 - rho(theta) exactly; E_1 <= E_2 <= E_3 (a hit again only
 * adds emission: the same rule serves the facets met again at R = 2
 * and 3, so the inequality holds to rounding, 1e-15: where no mirror ray
 * may meet the sea, E_2 is E_1 summed in another order); and the extra emission is
 * at most the energy the single-scattering balance (Eq 21) loses, the
 * energy the mirror rays bring back to the sea: 0 <= E_2 - E_1 <= 1 - total
 * (tolerance 2e-5: the reflectance's adaptive quadrature, 1e-5, and the
 * default rule's own error, < 1e-5 here).  Also the ratio, the mean
 * emissivity of the facets met again, is measured. */
static void test_multi(void)
{
    const double winds[] = { 3, 10, 15 }, ths[] = { 0, 40, 70, 80, 85, 89 };
    double complex N[2] = { N4, N10 };
    for (int a = 0; a < 3; a++) {
        sea_slope_stats st = { { 0, 0 }, lr_cov(winds[a]) };
        sea_slope_stats tilted = { { 0.1, -0.05 }, lr_cov(winds[a]) };
        for (int i = 0; i < 6; i++) {
            const sea_dir v = { ths[i] * DEG, 0.4 };
            double e1[2], r1[2], e2[2], e3[2];
            CU_ASSERT_FATAL(sea_emissivity_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st, v, e1, NULL) ==
                            SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st, v, 1, r1,
                                                   NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st, v, 2, e2,
                                                   NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st, v, 3, e3,
                                                   NULL) == SEA_OK);
            for (int q = 0; q < 2; q++) {
                CU_ASSERT(r1[q] == e1[q]);
                CU_ASSERT(e2[q] >= e1[q] - 1e-15 && e3[q] >= e2[q] - 1e-15 && e3[q] <= 1.0);
                if (a == 1 && ths[i] >= 70 && ths[i] <= 85) {
                    sea_energy en;
                    CU_ASSERT_FATAL(sea_energy_balance(P, SEA_EMIS_AUTO, N[q], &st, v, &en,
                                                       NULL) == SEA_OK);
                    const double lost = 1.0 - en.total;
                    CU_ASSERT(e2[q] - e1[q] <= lost + 2e-5);
                    MEASURED("10 m/s %g deg %s um: E2 - E1 = %.4f of the %.4f lost at one "
                             "reflection (mean emissivity met again %.3f)\n",
                             ths[i], q ? "10" : "4", e2[q] - e1[q], lost,
                             (e2[q] - e1[q]) / lost);
                }
            }
            double t1, t2;
            CU_ASSERT_FATAL(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, N, 1, &tilted, v, 1,
                                                   &t1, NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, N, 1, &tilted, v, 2,
                                                   &t2, NULL) == SEA_OK);
            CU_ASSERT(t2 >= t1 && t2 <= 1.0);
        }
    }
    /* Eq 22 under a uniform sky: the sky reflected is (1 - E_R) L, for the
     * isotropic model and for a black clear sky (eps_z = 1), at every R
     * (1e-12: the same weights, summed in another order); a clear sky of
     * eps_z = 0.7 gives less, and more at 85 deg (mirror rays near the
     * horizon) than the zenith's share at nadir. */
    {
        sea_slope_stats st10 = { { 0.05, 0 }, lr_cov(10) };
        const double L[2] = { 2.0, 3.0 };
        const sea_sky iso = { SEA_SKY_ISOTROPIC, NAN, L, 0, NULL },
                      black = { SEA_SKY_CLEAR, 1.0, L, 0, NULL },
                      grey = { SEA_SKY_CLEAR, 0.7, L, 0, NULL };
        for (int i = 0; i < 6; i++)
            for (int R = 1; R <= SEA_REFLECTIONS_MAX; R++) {
                const sea_dir v = { ths[i] * DEG, 0.4 };
                double e[2], k[2], ek[2], kk[2], eg[2], kg[2];
                CU_ASSERT_FATAL(sea_emissivity_sky_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st10, v, R,
                                                     &iso, e, k, NULL) == SEA_OK);
                CU_ASSERT_FATAL(sea_emissivity_sky_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st10, v, R,
                                                     &black, ek, kk, NULL) == SEA_OK);
                CU_ASSERT_FATAL(sea_emissivity_sky_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st10, v, R,
                                                     &grey, eg, kg, NULL) == SEA_OK);
                for (int q = 0; q < 2; q++) {
                    double em;
                    CU_ASSERT(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N[q], 1, &st10, v, R,
                                                     &em, NULL) == SEA_OK);
                    ASSERT_ABS(e[q], em, 1e-12);
                    ASSERT_ABS(k[q], (1.0 - e[q]) * L[q], 1e-12);
                    ASSERT_ABS(kk[q], (1.0 - ek[q]) * L[q], 1e-12);
                    CU_ASSERT(kg[q] < kk[q] && kg[q] > 0.7 * kk[q]);
                }
            }
        sea_sky bad = { SEA_SKY_CLEAR, 0.0, L, 0, NULL };
        double e[2], k[2];
        CU_ASSERT(sea_emissivity_sky_n(P, SEA_EMIS_AUTO, NULL, N, 2, &st10, (sea_dir){ 1, 0 }, 1,
                                       &bad, e, k, NULL) == SEA_ERR_DOMAIN);
    }
    /* A slope distribution without spread but tilted (a facet seen from
     * afar on a glassy sea): a mirror ray that falls, or rises below the
     * tilt, "meets the sea again" in Smith's terms, but no facet of that
     * distribution faces it; it escapes, so the closure holds (up to 0.95
     * of the energy vanished before; the fuzzing of 20000 random conditions,
     * variances 0 to 2, |m| to 3, 0-89.99 deg, R 1-3, that found it now
     * finds nothing above 1.4e-15) */
    {
        /* mean slope x, y; zenith (deg), azimuth (rad) */
        const double tilt[3][4] = { { -1.73229, -1.21914, 29.4276, 2.2475 },
                                    { -0.454923, 0.725688, 45.7160, 1.6197 },
                                    { 2.04836, 1.1981, 58.2060, 5.4947 } };
        const double L[2] = { 2.0, 3.0 };
        const sea_sky black = { SEA_SKY_CLEAR, 1.0, L, 0, NULL };
        for (int c = 0; c < 3; c++)
            for (int R = 1; R <= SEA_REFLECTIONS_MAX; R++) {
                const sea_slope_stats glassy = { { tilt[c][0], tilt[c][1] }, { 0, 0, 0 } };
                double e[2], k[2];
                CU_ASSERT_FATAL(sea_emissivity_sky_n(P, SEA_EMIS_AUTO, NULL, N, 2, &glassy,
                                                     (sea_dir){ tilt[c][2] * DEG, tilt[c][3] },
                                                     R, &black,
                                                     e, k, NULL) == SEA_OK);
                for (int q = 0; q < 2; q++) {
                    CU_ASSERT(e[q] > 0.0 && e[q] < 1.0);
                    ASSERT_ABS(e[q] + k[q] / L[q], 1.0, 1e-12);
                }
            }
    }
    sea_slope_stats flat = { { 0, 0 }, { 0, 0, 0 } };
    for (int i = 1; i < 6; i++) {
        const sea_dir v = { ths[i] * DEG, 0.4 };
        for (int R = 1; R <= SEA_REFLECTIONS_MAX; R++) {
            double e;
            CU_ASSERT_FATAL(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N4, 1, &flat, v, R,
                                                   &e, NULL) == SEA_OK);
            ASSERT_ABS(e, 1.0 - sea_fresnel_unpolarized(cos(v.theta), N4), 1e-15);
        }
    }
    sea_slope_stats st = { { 0, 0 }, lr_cov(10) };
    double e;
    sea_error err;
    CU_ASSERT(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N4, 1, &st, (sea_dir){ 1.0, 0 }, 0,
                                     &e, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N4, 1, &st, (sea_dir){ 1.0, 0 },
                                     SEA_REFLECTIONS_MAX + 1, &e, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N4, 1, &st, (sea_dir){ M_PI_2, 0 },
                                     2, &e, &err) == SEA_ERR_DOMAIN);
}

/* The default model against every hit (issue "Right and fast by default":
 * within 3e-3 of the ray-traced truth with every hit to 85 deg, 3-15 m/s,
 * 4 and 10 um).  tests/data/mc_sea_all_hits.csv (tests/mc_sea_oracle.c,
 * -f means): sea-spectrum surfaces of 328 m (waves from 0.32 m), 5 per
 * wind at 3 and 5 m/s and 25 at 10 and 15 m/s, 60-85 deg along and
 * across the wind; a row per direction and wavelength, the means over
 * the surfaces of eps (every hit, unpolarised rho at each) with their
 * standard errors eps_se.  Each
 * wind's models are made as a program makes them (sea_model_alloc, both
 * wavelengths' indices, the wind's spectrum) with the surfaces' mean
 * covariance C as the low resolution, and evaluated at C:
 *  - the default model so made (sea_model_params_default): its two
 *    scales split the spectrum's whole slope variance, which counts the
 *    waves under 0.32 m that the surfaces lack, so that at 10 and 15 m/s
 *    the split falls below the surfaces' shortest waves and two scales add
 *    nothing; reported (MEASURED and the claim default_spectrum_85), and
 *    its column of the table held to it (1e-6, the other tables' rule:
 *    tests/mc_model_refresh rewrites the column after a change of the
 *    model);
 *  - the default model of the surfaces' sea, asserted: the default's own
 *    composition (sea_model_emissivity: one scale with reflections = auto,
 *    plus the two-scale table's addition, clamped to [0, 1]) with its
 *    table made as the default makes a sea's, split at half the sea's
 *    slope variance, here the surfaces' own (sea_spectrum_split_at from
 *    the period's wavenumber, as test_two_scale_table splits them;
 *    tests/all_hits.c, which the benchmark of the physics choices shares).
 *    That this composition is sea_model_emissivity is checked on every row
 *    with the spectrum's table: equal to the bit (the same calls on the
 *    same numbers);
 *  - one scale with reflections = auto, and the paper's model (Smith's,
 *    one scale, one hit), reported so that the gain shows; the paper's
 *    worst per angle asserted at the figures of seabake-model(7).
 * Every row to 85 deg: |default - eps| <= 3e-3 + 3 eps_se, the issue's
 * target plus what another draw of the surfaces could move the row's
 * mean by (with 5 surfaces the standard error is itself uncertain: at its
 * 4 degrees of freedom 3 of them bound a correct row's gap with 96 %, not
 * 99.7 %; with 25, 99.4 %), also as the claim default_hits_target, which
 * the manual states.  The worst row per angle at seabake-model(7)'s
 * figures (tests/claims.csv, rounding and 3 standard errors): at 85 deg
 * that is 4.5e-3, beyond the target on the four rows of 15 m/s (within
 * it only with the standard errors, 0.5e-3 to 1.1e-3 over 25 surfaces).
 * Worst and RMS per angle and wavelength are printed for the four
 * models. */
static void test_default_all_hits(void)
{
    enum { NTH = 5, NMOD = 4 };
    static double x[AH_ROWS_MAX][AH_COLS];
    const int nr = all_hits_read(SEA_TOP_SRCDIR "/tests/data/mc_sea_all_hits.csv", x, AH_ROWS_MAX);
    CU_ASSERT_FATAL(nr > 0);
    const double ths[NTH] = { 60, 70, 75, 80, 85 };
    const char *names[NMOD] = { "default", "default, the spectrum's split", "one scale, auto",
                                "paper" };
    /* per model, angle, wavelength: worst |d|, sum of d^2, rows */
    double worst[NMOD][NTH][2] = { { { 0 } } }, sq[NMOD][NTH][2] = { { { 0 } } };
    int cnt[NTH][2] = { { 0 } }, target_rows = 0;
    gap dflt[NTH] = { { .id = "default_hits_60" }, { .id = "default_hits_70" },
                      { .id = "default_hits_75" }, { .id = "default_hits_80" },
                      { .id = "default_hits_85" } };
    gap paper[NTH] = { { .id = "paper_hits_60" }, { .id = "paper_hits_70" },
                       { .id = "paper_hits_75" }, { .id = "paper_hits_80" },
                       { .id = "paper_hits_85" } };
    gap spec85 = { .id = "default_spectrum_85" }, target = { .id = "default_hits_target" };
    const double complex N[2] = { N4, N10 };
    for (int a = 0; a < nr;) {
        /* the rows of one wind: one set of surfaces, one covariance */
        const int b = all_hits_wind_end(x, nr, a);
        sea_spectrum sp;
        CU_ASSERT_FATAL(sea_spectrum_init(x[a][AH_WIND], INFINITY, 0.0, &sp, NULL) == SEA_OK);
        const sea_slope_stats lr = { { 0, 0 }, { x[a][AH_SXX], x[a][AH_SYY], x[a][AH_SXY] } };
        sea_model_params pd, p1, pp;
        sea_model_params_default(&pd);
        p1 = pd;
        p1.scales = 1;
        pp = p1;
        pp.reflections = 1;
        pp.shadowing = SEA_SHADOW_SMITH;
        sea_model *md = NULL, *m1 = NULL, *mp = NULL;
        CU_ASSERT_FATAL(sea_model_alloc(&pd, &sp, &lr, NULL, N, 2, NULL, &md, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_model_alloc(&p1, &sp, &lr, NULL, N, 2, NULL, &m1, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_model_alloc(&pp, &sp, &lr, NULL, N, 2, NULL, &mp, NULL) == SEA_OK);
        /* the default made as sea_model_alloc makes it (the spectrum's
         * split), and for the surfaces' sea (their own split): the
         * composition of tests/all_hits.c */
        all_hits_model ms, mo;
        CU_ASSERT_FATAL(all_hits_model_alloc(&pd, &sp, &lr, 0.0, N, 2, &ms, NULL) == SEA_OK);
        CU_ASSERT_FATAL(all_hits_model_alloc(&pd, &sp, &lr, x[a][AH_PERIOD], N, 2, &mo, NULL) ==
                        SEA_OK);
        for (int r = a; r < b; r++) {
            const double wl = x[r][AH_WL], th = x[r][AH_THETA], eps = x[r][AH_EPS],
                         eps_se = x[r][AH_EPS_SE];
            const int q = wl == 10.0;
            int t = 0;
            while (t < NTH && ths[t] != th)
                t++;
            CU_ASSERT_FATAL((wl == 4.0 || wl == 10.0) && t < NTH);
            const sea_dir v = { th * DEG, x[r][AH_PHI] * DEG };
            double ed[2], e1[2], ep[2], es2[2], eo[2], es, ec;
            CU_ASSERT_FATAL(sea_model_emissivity(md, &lr, v, ed, NULL, NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_model_emissivity(m1, &lr, v, e1, NULL, NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_model_emissivity(mp, &lr, v, ep, NULL, NULL) == SEA_OK);
            CU_ASSERT_FATAL(all_hits_model_emissivity(&ms, &lr, v, es2, NULL) == SEA_OK);
            CU_ASSERT_FATAL(all_hits_model_emissivity(&mo, &lr, v, eo, NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity(P, SEA_EMIS_AUTO, N[q], &lr, v, &es, NULL) == SEA_OK);
            CU_ASSERT_FATAL(sea_emissivity(PC, SEA_EMIS_AUTO, N[q], &lr, v, &ec, NULL) == SEA_OK);
            /* the composition is sea_model_emissivity's, to the bit */
            const double spec = es2[q], own = eo[q];
            CU_ASSERT(spec == ed[q]);
            ASSERT_ABS(x[r][AH_SMITH], es, 1e-6);
            ASSERT_ABS(x[r][AH_CORR], ec, 1e-6);
            ASSERT_ABS(x[r][AH_DEFAULT], ed[q], 1e-6);
            CU_ASSERT(ep[q] == es); /* the paper's model is Eq 7 with Smith's */
            const double d[NMOD] = { own - eps, ed[q] - eps, e1[q] - eps, ep[q] - eps };
            for (int m = 0; m < NMOD; m++) {
                worst[m][t][q] = fmax(worst[m][t][q], fabs(d[m]));
                sq[m][t][q] += d[m] * d[m];
            }
            cnt[t][q]++;
            /* the target, every row to 85 deg */
            ASSERT_ABS(own, eps, 3e-3 + 3.0 * eps_se);
            gap_add(&target, d[0], eps_se);
            target_rows++;
            gap_add(&dflt[t], d[0], eps_se);
            gap_add(&paper[t], d[3], eps_se);
            if (t == 4)
                gap_add(&spec85, d[1], eps_se);
            MEASURED("all hits, %g m/s, %g um, %g deg, phi %g: eps %.5f +- %.5f; model - eps: "
                     "default %+.5f, with the spectrum's split %+.5f, one scale (auto) %+.5f, "
                     "paper %+.5f\n",
                     x[r][AH_WIND], wl, th, x[r][AH_PHI], eps, eps_se, d[0], d[1], d[2], d[3]);
        }
        all_hits_model_free(&ms);
        all_hits_model_free(&mo);
        sea_model_free(md);
        sea_model_free(m1);
        sea_model_free(mp);
        a = b;
    }
    CU_ASSERT(target_rows == 80); /* 4 winds, 2 wavelengths, 5 angles, 2 azimuths */
    for (int m = 0; m < NMOD; m++)
        for (int t = 0; t < NTH; t++)
            for (int q = 0; q < 2; q++)
                MEASURED("all hits, %g deg, %s um, %s: worst |model - eps| %.2e, RMS %.2e over "
                         "%d rows\n",
                         ths[t], q ? "10" : "4", names[m], worst[m][t][q],
                         cnt[t][q] > 0 ? sqrt(sq[m][t][q] / cnt[t][q]) : NAN, cnt[t][q]);
    for (int t = 0; t < NTH; t++) {
        gap_assert(&dflt[t]);
        gap_assert(&paper[t]);
    }
    gap_assert(&spec85);
    gap_assert(&target);
}

/* What each physics choice buys against the same truth (seabake-model(7),
 * TRUTH BY RAY TRACING, "What each choice buys"; the chart of
 * scripts/bench-physics, whose bench/physics_truth computes these figures
 * with the same models, tests/all_hits.c): the paper's model (one hit,
 * Smith's, one scale), correlated shadowing, two scales, two and three
 * hits, and the default, each made for the surfaces' sea as above, at
 * every row of tests/data/mc_sea_all_hits.csv.  Asserted per model
 * (tests/claims.csv): the worst |model - eps| over the rows, "=" with the
 * standard error of its row, and the RMS over the rows, "=" with the RMS of
 * the rows' standard errors (the rows moved by delta_i move an RMS by at
 * most the RMS of the delta_i); the worst at 75-80 deg of two and of three
 * hits, which overshoot there; and what the page says of them: every
 * model's worst row is at 85 deg, and at these views (60-85 deg, the low
 * resolution's statistics) the default takes the second hit at every row,
 * so that its figures are those of two hits to the bit.  Times are the
 * benchmark's, never a test's. */
static void test_models_all_hits(void)
{
    static double x[AH_ROWS_MAX][AH_COLS];
    const int nr = all_hits_read(SEA_TOP_SRCDIR "/tests/data/mc_sea_all_hits.csv", x, AH_ROWS_MAX);
    CU_ASSERT_FATAL(nr > 0);
    const double complex N[2] = { N4, N10 };
    static const char *const ids[AH_NMODELS][2] = {
        { "physics_paper_worst", "physics_paper_rms" },
        { "physics_correlated_worst", "physics_correlated_rms" },
        { "physics_two_scales_worst", "physics_two_scales_rms" },
        { "physics_two_hits_worst", "physics_two_hits_rms" },
        { "physics_three_hits_worst", "physics_three_hits_rms" },
        { "physics_default_worst", "physics_default_rms" }
    };
    static double d[AH_NMODELS][AH_ROWS_MAX];
    int default_hits2 = 0;
    /* at 75-80 deg: two hits' worst, and three hits' (which overshoots) */
    gap mid2 = { .id = "physics_two_hits_75_80" }, mid3 = { .id = "physics_three_hits_75_80" };
    double mid3_signed = 0.0;
    for (int k = 0; k < AH_NMODELS; k++) {
        sea_model_params mp;
        const char *name;
        all_hits_model_params(k, &mp, &name);
        gap worst = { .id = ids[k][0] };
        double sq = 0.0, se2 = 0.0, worst_any = 0.0, worst85 = 0.0;
        for (int a = 0; a < nr;) {
            const int b = all_hits_wind_end(x, nr, a);
            sea_spectrum sp;
            CU_ASSERT_FATAL(sea_spectrum_init(x[a][AH_WIND], INFINITY, 0.0, &sp, NULL) == SEA_OK);
            const sea_slope_stats lr = { { 0, 0 }, { x[a][AH_SXX], x[a][AH_SYY], x[a][AH_SXY] } };
            all_hits_model m;
            CU_ASSERT_FATAL(all_hits_model_alloc(&mp, &sp, &lr, x[a][AH_PERIOD], N, 2, &m, NULL) ==
                            SEA_OK);
            for (int r = a; r < b; r++) {
                const sea_dir v = { x[r][AH_THETA] * DEG, x[r][AH_PHI] * DEG };
                const double se = x[r][AH_EPS_SE];
                double e[2];
                CU_ASSERT_FATAL(all_hits_model_emissivity(&m, &lr, v, e, NULL) == SEA_OK);
                d[k][r] = e[x[r][AH_WL] == 10.0] - x[r][AH_EPS];
                gap_add(&worst, d[k][r], se);
                sq += d[k][r] * d[k][r];
                se2 += se * se;
                worst_any = fmax(worst_any, fabs(d[k][r]));
                if (x[r][AH_THETA] == 85.0)
                    worst85 = fmax(worst85, fabs(d[k][r]));
                if (k == AH_DEFAULT_MODEL)
                    default_hits2 += sea_model_hits(m.one, &lr, v) == 2;
                if (x[r][AH_THETA] == 75.0 || x[r][AH_THETA] == 80.0) {
                    if (k == AH_TWO_HITS)
                        gap_add(&mid2, d[k][r], se);
                    if (k == AH_THREE_HITS) {
                        gap_add(&mid3, d[k][r], se);
                        if (fabs(d[k][r]) > fabs(mid3_signed))
                            mid3_signed = d[k][r];
                    }
                }
            }
            all_hits_model_free(&m);
            a = b;
        }
        MEASURED("all hits, %s: worst |model - eps| %.3e (at 85 deg %.3e), RMS %.3e over %d "
                 "rows\n",
                 name, worst_any, worst85, sqrt(sq / nr), nr);
        CU_ASSERT(worst85 == worst_any); /* every model's worst row is at 85 deg */
        gap_assert(&worst);
        ASSERT_CLAIM(ids[k][1], sqrt(sq / nr), sqrt(se2 / nr));
    }
    MEASURED("all hits, 75-80 deg: three hits' worst model - eps %+.3e\n", mid3_signed);
    gap_assert(&mid2);
    gap_assert(&mid3);
    CU_ASSERT(mid3_signed > 0.0); /* three hits overshoot there */
    /* the default is two hits at every row */
    CU_ASSERT(default_hits2 == nr);
    for (int r = 0; r < nr; r++)
        CU_ASSERT(d[AH_DEFAULT_MODEL][r] == d[AH_TWO_HITS][r]);
}

int test_mc_register(void)
{
    CU_pSuite s = CU_add_suite("mc oracle", setup, teardown);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "the tracer's Fresnel: closed forms, the library's",
                        test_fresnel_closed_forms) ||
           !CU_add_test(s, "flat surface -> 1 - rho, one bounce", test_flat) ||
           !CU_add_test(s, "surface slope covariance = target", test_surface_covariance) ||
           !CU_add_test(s, "energy conserved per ray", test_energy) ||
           !CU_add_test(s, "roof of tilted planes: visible fractions", test_roof) ||
           !CU_add_test(s, "same sums whatever the threads", test_reproducible) ||
           !CU_add_test(s, "agrees with the model at 0 and 40 deg", test_against_model) ||
           !CU_add_test(s, "stored table: model column = independent Eq 7; figures", test_table) ||
           !CU_add_test(s, "sea-spectrum surfaces: the table and what it shows", test_sea_table) ||
           !CU_add_test(s, "two scales against sea-spectrum surfaces to 328 m",
                        test_two_scale_table) ||
           !CU_add_test(s, "two scales: limits and the render's table", test_two_scale_limits) ||
           !CU_add_test(s, "multiple reflections: limits and energy", test_multi) ||
           !CU_add_test(s, "the default model against every hit, 3-15 m/s, 60-85 deg",
                        test_default_all_hits) ||
           !CU_add_test(s, "each physics choice against every hit: what it buys",
                        test_models_all_hits);
}
