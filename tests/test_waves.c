/* test_waves.c - the large-scale wave realisation and facet slope moments
 * (seabake-model(7), TWO SCALES): statistics against the spectrum integrals,
 * FFT against the direct sum of its own modes, exact LEAN averaging,
 * determinism, time, convergence of high to low resolution, bad input. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "unit.h"

static sea_spectrum sea_state(double wind, double wind_dir)
{
    sea_spectrum s;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_init(wind, INFINITY, wind_dir, &s, &err), SEA_OK);
    return s;
}

static sea_waves *plan(const sea_spectrum *s, sea_waves_kind kind, size_t fft_size,
                       unsigned long seed)
{
    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = kind;
    p.fft_size = fft_size;
    p.seed = seed;
    sea_waves *w = NULL;
    sea_error err;
    sea_status st = sea_waves_alloc(s, &p, &w, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  sea_waves_alloc: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    return w;
}

static sea_cov2 lr_cov(const sea_spectrum *s, double kc)
{
    sea_cov2 c;
    sea_error err;
    CU_ASSERT_EQUAL(sea_spectrum_slope_cov(s, kc, &c, &err), SEA_OK);
    return c;
}

/* Spatial mean and (population) covariance of slope samples. */
static void field_cov(const double *sx, const double *sy, size_t n, sea_cov2 *c)
{
    double mx = 0.0, my = 0.0;
    for (size_t i = 0; i < n; i++) {
        mx += sx[i];
        my += sy[i];
    }
    mx /= (double)n;
    my /= (double)n;
    c->xx = c->yy = c->xy = 0.0;
    for (size_t i = 0; i < n; i++) {
        c->xx += (sx[i] - mx) * (sx[i] - mx);
        c->yy += (sy[i] - my) * (sy[i] - my);
        c->xy += (sx[i] - mx) * (sy[i] - my);
    }
    c->xx /= (double)n;
    c->yy /= (double)n;
    c->xy /= (double)n;
}

/* The generated bins hold exactly the spectrum's slope variance between
 * the lowest bin edge (<= k_p/4, below which L_PM < exp(-20)) and pi/L, so
 * generated + sub-facet (Eq 17) = low resolution for every 2^i m facet.
 * Tolerance 1e-6: the spectrum integrals are asked for 1e-8 relative and
 * the bins use a 16-point Gauss rule; 1e-6 leaves room for both. */
static void test_generated_plus_subfacet_is_lr(void)
{
    const double winds[] = { 0.5, 3.0, 10.0, 20.0, 40.0 };
    for (size_t a = 0; a < sizeof winds / sizeof *winds; a++) {
        sea_spectrum s = sea_state(winds[a], 30.0 * DEG);
        sea_waves *w = plan(&s, SEA_WAVES_SINUSOIDS, 0, 7);
        const sea_cov2 lr = lr_cov(&s, 0.0);
        for (double L = 1.0; L <= 1024.0; L *= 2.0) {
            const sea_cov2 g = sea_waves_generated_cov(w, M_PI / L), c = lr_cov(&s, M_PI / L);
            ASSERT_REL(g.xx + c.xx, lr.xx, 1e-6, 0.0);
            ASSERT_REL(g.yy + c.yy, lr.yy, 1e-6, 0.0);
            ASSERT_ABS(g.xy + c.xy, lr.xy, 1e-6 * lr.xx);
        }
        for (size_t i = 0; i < sea_waves_count(w); i++) {
            const sea_wave o = sea_waves_get(w, i);
            CU_ASSERT(isfinite(o.amplitude) && o.amplitude >= 0.0);
            CU_ASSERT(hypot(o.kx, o.ky) <= M_PI);
        }
        sea_waves_free(w);
    }
}

/* The slope variance of one realisation over a large area equals the
 * generated (ensemble) variance: deterministic amplitudes leave only the
 * cross terms of the components, which average out over an area of many
 * wavelengths.  Checked where the generated band is broad (L <= 8 m: waves
 * from k_p/4 to pi/8, most of their slope variance in waves far shorter
 * than the 768 m square): 3 % (measured 0.3-2.8 %).  For L = 32 m the band
 * is only the spectral peak (90 m waves, 8 x 8 of them in the square) and
 * the sampling error is about 20 %; there only the sum below is checked,
 * in which the generated part is 2 % of the whole.  Facet means + Eq 17
 * must give the low-resolution covariance within 2 % for every facet size
 * (the issue's bound). */
static void test_spatial_statistics(void)
{
    sea_spectrum s = sea_state(10.0, 0.0);
    sea_waves *w = plan(&s, SEA_WAVES_SINUSOIDS, 0, 1);
    const sea_cov2 lr = lr_cov(&s, 0.0);
    double prev = INFINITY;
    const int quick = UNIT_QUICK;
    const double side = quick ? 64.0 : 768.0;
    for (double L = 2.0; L <= 1024.0; L *= 4.0) {
        const size_t n = L < side ? (size_t)(side / L) : 4;
        sea_moments *mo = malloc(n * n * sizeof *mo);
        double *sx = malloc(n * n * sizeof *sx), *sy = malloc(n * n * sizeof *sy);
        CU_ASSERT_FATAL(mo != NULL && sx != NULL && sy != NULL);
        const sea_rect r = { L, -(long)n / 2, -(long)n / 2, n, n };
        sea_error err;
        CU_ASSERT_EQUAL_FATAL(sea_waves_facets(w, &r, 0, 0.0, mo, &err), SEA_OK);
        sea_cov2 sub = { 0.0, 0.0, 0.0 };
        for (size_t i = 0; i < n * n; i++) {
            sx[i] = mo[i].mx;
            sy[i] = mo[i].my;
            const sea_slope_stats st = sea_moments_stats(&mo[i]);
            sub.xx += st.cov.xx / (double)(n * n);
            sub.yy += st.cov.yy / (double)(n * n);
        }
        sea_cov2 f;
        field_cov(sx, sy, n * n, &f);
        const sea_cov2 g = sea_waves_generated_cov(w, M_PI / L);
        if (quick) {
            CU_ASSERT(isfinite(f.xx) && isfinite(f.yy) && isfinite(sub.xx) && isfinite(sub.yy));
            free(mo);
            free(sx);
            free(sy);
            continue;
        }
        if (L <= 8.0) {
            ASSERT_REL(f.xx, g.xx, 0.03, 0.0);
            ASSERT_REL(f.yy, g.yy, 0.03, 0.0);
            MEASURED("L = %g m: spatial/generated slope variance %.4f (x), %.4f (y)\n", L,
                     f.xx / g.xx, f.yy / g.yy);
        }
        ASSERT_REL(f.xx + sub.xx, lr.xx, 0.02, 0.0);
        ASSERT_REL(f.yy + sub.yy, lr.yy, 0.02, 0.0);
        /* The facet means lose variance as L grows, down to nothing. */
        CU_ASSERT(f.xx + f.yy <= prev);
        prev = f.xx + f.yy;
        if (L >= 512.0)
            CU_ASSERT(f.xx + f.yy < 1e-6 * (lr.xx + lr.yy));
        free(mo);
        free(sx);
        free(sy);
    }
    sea_waves_free(w);
}

/* An FFT plan is a sum of sinusoids over its modes: sampling the converted
 * plan reproduces the inverse FFT at the finest step and at a coarser level,
 * at t = 0 and t = 7.3 s (so the Hermitian pairing of each mode with its
 * mirror, each travelling its own way, is checked).  Round-off of a
 * 3000-term sum: 1e-11 of the field's RMS. */
static void test_fft_is_sum_of_its_modes(void)
{
    sea_spectrum s = sea_state(10.0, 20.0 * DEG);
    sea_waves *w = plan(&s, SEA_WAVES_FFT, 64, 3), *d = NULL;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_waves_to_sinusoids(w, &d, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_waves_count(d), sea_waves_count(w));
    const double steps[] = { 1.0, 4.0 }, times[] = { 0.0, 7.3 };
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) {
            const size_t n = (size_t)(64.0 / steps[a]);
            const sea_rect r = { steps[a], 0, 0, n, n };
            double *f = malloc(6 * n * n * sizeof *f);
            CU_ASSERT_FATAL(f != NULL);
            CU_ASSERT_EQUAL(sea_waves_sample(w, &r, times[b], f, f + n * n, f + 2 * n * n, &err),
                            SEA_OK);
            CU_ASSERT_EQUAL(sea_waves_sample(d, &r, times[b], f + 3 * n * n, f + 4 * n * n,
                                             f + 5 * n * n, &err),
                            SEA_OK);
            for (int q = 0; q < 3; q++) {
                double rms = 0.0, dmax = 0.0;
                for (size_t i = 0; i < n * n; i++) {
                    const double u = f[q * n * n + i], v = f[(q + 3) * n * n + i];
                    rms += u * u;
                    dmax = fmax(dmax, fabs(u - v));
                }
                rms = sqrt(rms / (double)(n * n));
                CU_ASSERT(rms > 0.0);
                CU_ASSERT(dmax <= 1e-11 * rms);
            }
            free(f);
        }
    sea_waves_free(d);
    sea_waves_free(w);
}

/* FFT and sinusoids are two realisations of one spectrum: their slope
 * variances (and so the up/cross-wind anisotropy) agree.  Each is checked
 * against the spectrum integral over the waves it holds within 3 % (same
 * argument as above; the FFT patch is 1024 m), and the two against each
 * other within 4 %. */
static void test_fft_and_sinusoids_agree(void)
{
    sea_spectrum s = sea_state(10.0, 0.0);
    const int quick = UNIT_QUICK;
    sea_waves *wf = plan(&s, SEA_WAVES_FFT, quick ? 64 : 1024, 5),
              *ws = plan(&s, SEA_WAVES_SINUSOIDS, 0, 5);
    const size_t n = quick ? 32 : 512;
    const sea_rect r = { 2.0, 0, 0, n, n };
    double *f = malloc(4 * n * n * sizeof *f);
    CU_ASSERT_FATAL(f != NULL);
    sea_error err;
    CU_ASSERT_EQUAL(sea_waves_sample(wf, &r, 0.0, NULL, f, f + n * n, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_waves_sample(ws, &r, 0.0, NULL, f + 2 * n * n, f + 3 * n * n, &err),
                    SEA_OK);
    sea_cov2 cf, cs;
    field_cov(f, f + n * n, n * n, &cf);
    field_cov(f + 2 * n * n, f + 3 * n * n, n * n, &cs);
    const sea_cov2 band = sea_waves_generated_cov(ws, M_PI / 2.0);
    if (quick) {
        CU_ASSERT(cf.xx > 0.0 && cs.xx > 0.0 && isfinite(cf.yy) && isfinite(cs.yy));
        free(f);
        sea_waves_free(wf);
        sea_waves_free(ws);
        return;
    }
    ASSERT_REL(cf.xx, band.xx, 0.03, 0.0);
    ASSERT_REL(cf.yy, band.yy, 0.03, 0.0);
    ASSERT_REL(cs.xx, band.xx, 0.03, 0.0);
    ASSERT_REL(cs.yy, band.yy, 0.03, 0.0);
    ASSERT_REL(cf.xx / cf.yy, cs.xx / cs.yy, 0.04, 0.0);
    CU_ASSERT(cf.xx > 1.3 * cf.yy && cs.xx > 1.3 * cs.yy); /* upwind slopes steeper */
    MEASURED("FFT / sinusoids slope variance at 2 m: %.4f (x), %.4f (y); anisotropy %.3f vs %.3f\n",
             cf.xx / cs.xx, cf.yy / cs.yy, cf.xx / cf.yy, cs.xx / cs.yy);
    /* The FFT plan's own bookkeeping: its modes hold the spectrum between
     * 2 pi/P and pi/L0 to the midpoint rule's accuracy. */
    const sea_cov2 gf = sea_waves_generated_cov(wf, M_PI), lr = lr_cov(&s, 0.0), c1 = lr_cov(&s, M_PI);
    ASSERT_REL(gf.xx + c1.xx, lr.xx, 0.02, 0.0);
    ASSERT_REL(gf.yy + c1.yy, lr.yy, 0.02, 0.0);
    free(f);
    sea_waves_free(wf);
    sea_waves_free(ws);
}

static void average_2x2(const sea_moments *fine, size_t nf, size_t ci, size_t cj, sea_moments *o)
{
    const sea_moments *q[4] = { &fine[2 * cj * nf + 2 * ci], &fine[2 * cj * nf + 2 * ci + 1],
                                &fine[(2 * cj + 1) * nf + 2 * ci],
                                &fine[(2 * cj + 1) * nf + 2 * ci + 1] };
    memset(o, 0, sizeof *o);
    for (int k = 0; k < 4; k++) {
        o->mx += q[k]->mx / 4.0;
        o->my += q[k]->my / 4.0;
        o->mxx += q[k]->mxx / 4.0;
        o->mxy += q[k]->mxy / 4.0;
        o->myy += q[k]->myy / 4.0;
        o->h += q[k]->h / 4.0;
    }
}

/* LEAN filtering: the 2 x 2 average of the moments of facets L (n) is the
 * moments of the facet 2L (n + 1), with the same sub-facets.  Only the
 * order of the sums differs: 1e-12 of the second moments. */
static void check_lean(sea_waves *w, double L, int n)
{
    const size_t nf = 4, nc = 2;
    sea_moments fine[16], coarse[4];
    const sea_rect rf = { L, -2, -2, nf, nf }, rc = { 2.0 * L, -1, -1, nc, nc };
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_waves_facets(w, &rf, n, 1.5, fine, &err), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_waves_facets(w, &rc, n + 1, 1.5, coarse, &err), SEA_OK);
    for (size_t cj = 0; cj < nc; cj++)
        for (size_t ci = 0; ci < nc; ci++) {
            sea_moments a;
            average_2x2(fine, nf, ci, cj, &a);
            const sea_moments *c = &coarse[cj * nc + ci];
            const double scale = c->mxx + c->myy;
            ASSERT_ABS(a.mx, c->mx, 1e-12 * sqrt(scale));
            ASSERT_ABS(a.my, c->my, 1e-12 * sqrt(scale));
            ASSERT_ABS(a.mxx, c->mxx, 1e-12 * scale);
            ASSERT_ABS(a.mxy, c->mxy, 1e-12 * scale);
            ASSERT_ABS(a.myy, c->myy, 1e-12 * scale);
            ASSERT_ABS(a.h, c->h, 1e-12);
            /* and the covariance is really there: sub-facets differ */
            const sea_slope_stats st = sea_moments_stats(c);
            const sea_cov2 sub = lr_cov(sea_waves_spectrum(w), M_PI * (double)(1 << (n + 1)) / (2.0 * L));
            CU_ASSERT(st.cov.xx > sub.xx);
        }
}

static void test_lean_averaging_exact(void)
{
    sea_spectrum s = sea_state(10.0, 45.0 * DEG);
    sea_waves *ws = plan(&s, SEA_WAVES_SINUSOIDS, 0, 11), *wf = plan(&s, SEA_WAVES_FFT, 256, 11);
    check_lean(ws, 8.0, 1);  /* variable-step-2n, 4 m sub-facets */
    check_lean(ws, 4.0, 2);  /* 1 m sub-facets (the 1 Meter Step with sinusoids) */
    check_lean(wf, 2.0, 1);  /* one-meter on the FFT grid */
    check_lean(wf, 16.0, 4);
    sea_waves_free(ws);
    sea_waves_free(wf);
}

/* Variable Step is L/2^n with n = 0: slope at the centre, C = C_<L. */
static void test_variable_step_is_centre_slope(void)
{
    sea_spectrum s = sea_state(7.0, 0.0);
    sea_waves *w = plan(&s, SEA_WAVES_SINUSOIDS, 0, 2);
    const double L = 8.0;
    sea_moments mo[9];
    const sea_rect r = { L, -1, -1, 3, 3 };
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_waves_facets(w, &r, 0, 2.0, mo, &err), SEA_OK);
    const sea_cov2 sub = lr_cov(&s, M_PI / L);
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            double h;
            sea_vec2 g;
            sea_waves_at(w, M_PI / L, (i - 1 + 0.5) * L, (j - 1 + 0.5) * L, 2.0, &h, &g);
            const sea_moments *m = &mo[j * 3 + i];
            ASSERT_ABS(m->mx, g.x, 1e-12);
            ASSERT_ABS(m->my, g.y, 1e-12);
            ASSERT_ABS(m->h, h, 1e-12);
            const sea_slope_stats st = sea_moments_stats(m);
            ASSERT_REL(st.cov.xx, sub.xx, 1e-9, 0.0);
            ASSERT_REL(st.cov.yy, sub.yy, 1e-9, 0.0);
        }
    sea_waves_free(w);
}

static int same_facets(sea_waves *w, double t, sea_moments *a, size_t n)
{
    const sea_rect r = { 2.0, -(long)n / 2, 3, n, n };
    sea_error err;
    return sea_waves_facets(w, &r, 1, t, a, &err) == SEA_OK;
}

/* Same seed, same sea, bit for bit, whatever the thread count; another
 * seed, another sea. */
static void test_determinism(void)
{
    sea_spectrum s = sea_state(12.0, 0.0);
    const size_t n = 40;
    sea_moments *a = malloc(n * n * sizeof *a), *b = malloc(n * n * sizeof *b);
    CU_ASSERT_FATAL(a != NULL && b != NULL);
    for (int kind = 0; kind < 2; kind++) {
        sea_waves *w1 = plan(&s, (sea_waves_kind)kind, 128, 42);
        sea_waves *w2 = plan(&s, (sea_waves_kind)kind, 128, 42);
        sea_waves *w3 = plan(&s, (sea_waves_kind)kind, 128, 43);
#ifdef _OPENMP
        const int saved = omp_get_max_threads();
        omp_set_num_threads(1);
#endif
        CU_ASSERT(same_facets(w1, 0.5, a, n));
#ifdef _OPENMP
        omp_set_num_threads(saved > 1 ? saved : 2);
#endif
        CU_ASSERT(same_facets(w2, 0.5, b, n));
#ifdef _OPENMP
        omp_set_num_threads(saved);
#endif
        CU_ASSERT(memcmp(a, b, n * n * sizeof *a) == 0);
        CU_ASSERT(same_facets(w3, 0.5, b, n));
        CU_ASSERT(memcmp(a, b, n * n * sizeof *a) != 0);
        sea_waves_free(w1);
        sea_waves_free(w2);
        sea_waves_free(w3);
    }
    free(a);
    free(b);
}

/* FFT plans are planned once, in sea_waves_alloc, and only executed by the
 * sampling calls: several threads sampling every level of one plan at once,
 * each at its own time, get what one thread gets, bit for bit.  N = 96 has
 * levels 96 ... 3 (the odd one goes through FFTW's alignment buffer). */
static void test_fft_concurrent_sampling(void)
{
    sea_spectrum s = sea_state(8.7, 0.6174);
    const size_t N = 96;
    sea_waves *w = plan(&s, SEA_WAVES_FFT, N, 17);
    enum { LEVELS = 6, TIMES = 4, TASKS = LEVELS * TIMES };
    double *one[TASKS], *many[TASKS];
    size_t cells[TASKS];
    for (int q = 0; q < TASKS; q++) {
        const size_t M = N >> (q % LEVELS);
        cells[q] = M * M;
        one[q] = malloc(3 * cells[q] * sizeof(double));
        many[q] = malloc(3 * cells[q] * sizeof(double));
        CU_ASSERT_FATAL(one[q] != NULL && many[q] != NULL);
    }
#ifdef _OPENMP
    const int saved = omp_get_max_threads();
    omp_set_num_threads(1);
#endif
    int fails = 0;
    for (int q = 0; q < TASKS; q++) {
        const size_t M = N >> (q % LEVELS);
        const sea_rect r = { exp2(q % LEVELS), -7, 3, M, M };
        double *f = one[q];
        sea_error err;
        fails += sea_waves_sample(w, &r, 0.37 * q, f, f + cells[q], f + 2 * cells[q], &err) !=
                 SEA_OK;
    }
#ifdef _OPENMP
    omp_set_num_threads(saved);
#pragma omp parallel for schedule(dynamic) num_threads(4) reduction(+ : fails)
#endif
    for (int q = TASKS - 1; q >= 0; q--) {
        const size_t M = N >> (q % LEVELS);
        const sea_rect r = { exp2(q % LEVELS), -7, 3, M, M };
        double *f = many[q];
        sea_error err;
        fails += sea_waves_sample(w, &r, 0.37 * q, f, f + cells[q], f + 2 * cells[q], &err) !=
                 SEA_OK;
    }
    CU_ASSERT_EQUAL(fails, 0);
    for (int q = 0; q < TASKS; q++) {
        CU_ASSERT(memcmp(one[q], many[q], 3 * cells[q] * sizeof(double)) == 0);
        free(one[q]);
        free(many[q]);
    }
    sea_waves_free(w);
}

/* A plan with another finest size shares the bins it has in common: the
 * waves of 4 m and longer are the same sea. */
static void test_plans_share_bins(void)
{
    sea_spectrum s = sea_state(10.0, 0.0);
    sea_waves_params p;
    sea_waves_params_default(&p);
    sea_waves *a = NULL, *b = NULL;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_waves_alloc(&s, &p, &a, &err), SEA_OK);
    p.finest = 4.0;
    CU_ASSERT_EQUAL_FATAL(sea_waves_alloc(&s, &p, &b, &err), SEA_OK);
    CU_ASSERT(sea_waves_count(b) < sea_waves_count(a));
    double ha, hb;
    sea_vec2 ga, gb;
    sea_waves_at(a, M_PI / 8.0, 123.0, -45.0, 3.0, &ha, &ga);
    sea_waves_at(b, M_PI / 8.0, 123.0, -45.0, 3.0, &hb, &gb);
    ASSERT_ABS(ha, hb, 1e-12);
    ASSERT_ABS(ga.x, gb.x, 1e-12);
    ASSERT_ABS(ga.y, gb.y, 1e-12);
    sea_waves_free(a);
    sea_waves_free(b);
}

/* Each wave travels downwind at its phase speed omega/k with omega from
 * the dispersion relation: the longest wave alone, shifted by c t along
 * its direction of travel, is the same wave. */
static void test_phase_speed(void)
{
    sea_spectrum s = sea_state(8.0, 60.0 * DEG);
    sea_waves *w = plan(&s, SEA_WAVES_SINUSOIDS, 0, 9);
    const sea_wave o = sea_waves_get(w, 0);
    const double k = hypot(o.kx, o.ky);
    ASSERT_REL(fabs(o.omega), sea_spectrum_omega(k), 1e-14, 0.0);
    for (size_t i = 0; i < sea_waves_count(w); i++) {
        const sea_wave q = sea_waves_get(w, i);
        /* downwind: omega (k . wind) >= 0 */
        CU_ASSERT(q.omega * (q.kx * cos(s.wind_dir) + q.ky * sin(s.wind_dir)) >= -1e-12);
    }
    const double c = o.omega / k; /* signed: along k if > 0 */
    const double t = 4.0, ux = o.kx / k, uy = o.ky / k;
    for (int p = 0; p < 5; p++) {
        const double x = 13.0 * p - 20.0, y = 7.0 * p + 3.0;
        double h0, h1;
        sea_waves_at(w, k, x, y, 0.0, &h0, NULL);
        sea_waves_at(w, k, x + c * t * ux, y + c * t * uy, t, &h1, NULL);
        ASSERT_ABS(h1, h0, 1e-10 * o.amplitude);
        CU_ASSERT(fabs(h0) <= o.amplitude * (1.0 + 1e-12));
    }
    /* and at a fixed point it does move */
    double ha, hb;
    sea_waves_at(w, k, 0.0, 0.0, 0.0, &ha, NULL);
    sea_waves_at(w, k, 0.0, 0.0, 0.25 * M_PI / fabs(o.omega), &hb, NULL);
    CU_ASSERT(fabs(ha - hb) > 1e-3 * o.amplitude);
    sea_waves_free(w);
}

/* A loop period T rounds every frequency to a multiple of 2 pi/T: the sea
 * at t + T is the sea at t (to the round-off of omega T, some 1e-12). */
static void test_loop_period(void)
{
    sea_spectrum s = sea_state(10.0, 0.0);
    for (int kind = 0; kind < 2; kind++) {
        sea_waves_params p;
        sea_waves_params_default(&p);
        p.kind = (sea_waves_kind)kind;
        p.fft_size = 64;
        p.loop_period = 12.5;
        sea_waves *w = NULL;
        sea_error err;
        CU_ASSERT_EQUAL_FATAL(sea_waves_alloc(&s, &p, &w, &err), SEA_OK);
        sea_moments a[16], b[16], c[16];
        const sea_rect r = { 4.0, 0, 0, 4, 4 };
        CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 1, 3.0, a, &err), SEA_OK);
        CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 1, 3.0 + 12.5, b, &err), SEA_OK);
        CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 1, 3.0 + 6.0, c, &err), SEA_OK);
        double dmax = 0.0, dmid = 0.0;
        for (int i = 0; i < 16; i++) {
            dmax = fmax(dmax, fabs(a[i].mx - b[i].mx) + fabs(a[i].h - b[i].h));
            dmid = fmax(dmid, fabs(a[i].mx - c[i].mx) + fabs(a[i].h - c[i].h));
        }
        CU_ASSERT(dmax < 1e-10);
        CU_ASSERT(dmid > 1e-3);
        sea_waves_free(w);
    }
}

/* Fig. 5-6: at 4 um, theta = 80 deg, the emissivity and reflectivity of
 * high-resolution facets converge to the low-resolution values as L grows,
 * later for a stronger wind (paper: 64 m at 5 m/s, 512 m at 20 m/s).
 * Criterion: the largest deviation over 8 x 8 facets within 1e-3 of the
 * LR value for L >= L_conv; L_conv must be within a factor 2 of the
 * paper's, and at L_conv / 8 the facets must still differ by > 1e-2. */
static void test_convergence_to_low_resolution(void)
{
    sea_error err;
    sea_water *water = NULL;
    sea_optics *op = NULL;
    CU_ASSERT_EQUAL_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 0.0, &water, &err), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_optics_alloc(&op, &err), SEA_OK);
    sea_optics_set_shadowing(op, SEA_SHADOW_SMITH); /* the paper's Fig. 5-6 */
    double complex N;
    CU_ASSERT_EQUAL_FATAL(sea_water_index(water, 4e-6, &N, &err), SEA_OK);
    const double winds[] = { 5.0, 20.0 }, paper[] = { 64.0, 512.0 };
    const sea_dir obs = { 80.0 * DEG, 0.0 }, inc = sea_dir_fold(-80.0 * DEG, 0.0);
    for (int a = 0; a < 2; a++) {
        sea_spectrum s = sea_state(winds[a], 0.0);
        sea_waves *w = plan(&s, SEA_WAVES_SINUSOIDS, 0, 1);
        const sea_slope_stats lr = { { 0.0, 0.0 }, lr_cov(&s, 0.0) };
        double e_lr;
        CU_ASSERT_EQUAL(sea_emissivity(op, SEA_EMIS_AUTO, N, &lr, obs, &e_lr, &err), SEA_OK);
        const double r_lr = sea_reflectivity(N, &lr, inc, obs);
        double conv = 0.0, dev_at[12] = { 0 };
        int x = 0;
        for (double L = 1.0; L <= 1024.0; L *= 2.0, x++) {
            sea_moments mo[64];
            const sea_rect r = { L, -4, -4, 8, 8 };
            CU_ASSERT_EQUAL_FATAL(sea_waves_facets(w, &r, 0, 0.0, mo, &err), SEA_OK);
            double dev = 0.0;
            for (int i = 0; i < 64; i++) {
                const sea_slope_stats st = sea_moments_stats(&mo[i]);
                double e;
                CU_ASSERT_EQUAL(sea_emissivity(op, SEA_EMIS_AUTO, N, &st, obs, &e, &err), SEA_OK);
                const double rr = sea_reflectivity(N, &st, inc, obs);
                CU_ASSERT(e >= 0.0 && e <= 1.0 && rr >= 0.0 && isfinite(rr));
                dev = fmax(dev, fmax(fabs(e - e_lr) / e_lr, fabs(rr - r_lr) / r_lr));
            }
            dev_at[x] = dev;
            if (dev > 1e-3)
                conv = 0.0;
            else if (conv == 0.0)
                conv = L;
        }
        MEASURED("U10 = %g m/s: HR within 1e-3 of LR from L = %g m (paper %g m)\n", winds[a],
                 conv, paper[a]);
        CU_ASSERT(conv >= paper[a] / 2.0 && conv <= paper[a] * 2.0);
        CU_ASSERT(conv > 0.0 && dev_at[(int)log2(conv) - 3] > 1e-2);
        sea_waves_free(w);
    }
    sea_optics_free(op);
    sea_water_free(water);
}

/* Bad input: named, in range, nothing half-done. */
static void test_bad_input(void)
{
    sea_spectrum s = sea_state(10.0, 0.0);
    sea_waves_params p;
    sea_waves *w = NULL;
    sea_error err;
    sea_waves_params_default(&p);
    p.finest = 0.0;
    CU_ASSERT_EQUAL(sea_waves_alloc(&s, &p, &w, &err), SEA_ERR_DOMAIN);
    CU_ASSERT_PTR_NULL(w);
    sea_waves_params_default(&p);
    p.directions = 4;
    CU_ASSERT_EQUAL(sea_waves_alloc(&s, &p, &w, &err), SEA_ERR_DOMAIN);
    sea_waves_params_default(&p);
    p.kind = SEA_WAVES_FFT;
    p.fft_size = 63;
    CU_ASSERT_EQUAL(sea_waves_alloc(&s, &p, &w, &err), SEA_ERR_DOMAIN);
    p.fft_size = 64;
    p.loop_period = -1.0;
    CU_ASSERT_EQUAL(sea_waves_alloc(&s, &p, &w, &err), SEA_ERR_DOMAIN);
    p.loop_period = 0.0;
    CU_ASSERT_EQUAL_FATAL(sea_waves_alloc(&s, &p, &w, &err), SEA_OK);

    sea_moments mo[4];
    sea_rect r = { 0.5, 0, 0, 2, 2 }; /* below the finest facet */
    CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 0, 0.0, mo, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "finest") != NULL);
    r.step = -1.0;
    CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 0, 0.0, mo, &err), SEA_ERR_DOMAIN);
    r.step = 4.0;
    CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 3, 0.0, mo, &err), SEA_ERR_DOMAIN); /* 0.5 m */
    CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 0, NAN, mo, &err), SEA_ERR_DOMAIN);
    r.step = 3.0; /* not 2^m on the FFT grid */
    CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 0, 0.0, mo, &err), SEA_ERR_DOMAIN);
    r = (sea_rect){ 32.0, 0, 0, 2, 3 }; /* 96 m > the 64 m period */
    CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 0, 0.0, mo, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "period") != NULL);
    r = (sea_rect){ 4.0, 0, 0, 0, 2 };
    CU_ASSERT_EQUAL(sea_waves_facets(w, &r, 0, 0.0, mo, &err), SEA_ERR_DOMAIN);
    int n;
    CU_ASSERT_EQUAL(sea_facet_method_n(w, SEA_METHOD_ONE_METER, 0, 12.0, &n, &err), SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_facet_method_n(w, SEA_METHOD_ONE_METER, 0, 16.0, &n, &err), SEA_OK);
    CU_ASSERT_EQUAL(n, 4);
    CU_ASSERT_EQUAL(sea_facet_method_n(w, SEA_METHOD_VARIABLE_STEP_2N, 21, 16.0, &n, &err),
                    SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_facet_method_from_name("one-meter"), SEA_METHOD_ONE_METER);
    CU_ASSERT_EQUAL(sea_facet_method_from_name("variable-step-2n"), SEA_METHOD_VARIABLE_STEP_2N);
    CU_ASSERT_EQUAL(sea_facet_method_from_name("1m"), -1);
    CU_ASSERT_EQUAL(sea_check_size((size_t)1 << 40, (size_t)1 << 30, "test", &err), SEA_ERR_NOMEM);
    CU_ASSERT_EQUAL(sea_check_size(SIZE_MAX / 2, 4, "test", &err), SEA_ERR_NOMEM);
    CU_ASSERT(strstr(err.msg, "test") != NULL);
    CU_ASSERT_EQUAL(sea_check_size(1000, 8, "test", &err), SEA_OK);
    sea_waves_free(w);
}

/* Moments to statistics stays positive semi-definite under round-off. */
static void test_moments_stats(void)
{
    const sea_moments m = { 0.1, -0.2, 0.01 - 1e-18, -0.02 + 1e-9, 0.04 + 1e-6, 0.0 };
    const sea_slope_stats st = sea_moments_stats(&m);
    sea_error err;
    CU_ASSERT_EQUAL(sea_slope_stats_check(&st, &err), SEA_OK);
    CU_ASSERT(st.cov.xx == 0.0);
    CU_ASSERT(st.cov.xy == 0.0);
    ASSERT_REL(st.cov.yy, 1e-6, 1e-9, 0.0);
}

/* Facets (sea_facet) keep the height exactly and the slopes' mean and
 * covariance to a float each: a covariance of 1e-6 under a mean slope of
 * 0.3 (raw second moment 0.09, where a float of M would leave C to 1e-2)
 * comes back within 2^-24 relative (6e-8); statistics come back positive
 * semi-definite even where the rounding pushes |C_xy| past sqrt(C_xx C_yy);
 * every byte is defined (the padding field is 0). */
static void test_facets(void)
{
    const double cxx = 1e-6, cyy = 3e-6, cxy = -1.7e-6, mx = 0.3, my = -0.25, h = 1.234567890123;
    const sea_moments m = { mx, my, mx * mx + cxx, mx * my + cxy, my * my + cyy, h };
    const sea_facet f = sea_facet_of(&m);
    CU_ASSERT_EQUAL(sizeof f, 32u);
    CU_ASSERT(f.h == h);
    CU_ASSERT(f.zero == 0.0f);
    const sea_slope_stats st = sea_facet_stats(&f);
    /* the double subtraction M - m m^T itself loses 0.09 x 2^-53 / 1e-6 =
     * 1e-11 relative; the float 6e-8 */
    ASSERT_REL(st.mean.x, mx, 6e-8, 0.0);
    ASSERT_REL(st.mean.y, my, 6e-8, 0.0);
    ASSERT_REL(st.cov.xx, cxx, 6e-8, 0.0);
    ASSERT_REL(st.cov.yy, cyy, 6e-8, 0.0);
    ASSERT_REL(st.cov.xy, cxy, 6e-8, 0.0);
    const sea_moments back = sea_facet_moments(&f);
    const sea_slope_stats st2 = sea_moments_stats(&back);
    ASSERT_REL(st2.cov.xx, cxx, 1e-7, 0.0);
    CU_ASSERT(back.h == h);
    /* |C_xy| = sqrt(C_xx C_yy) in double, past it in float */
    const double exx = 3.0 / 7.0, eyy = 1.1;
    const sea_moments edge = { 0.0, 0.0, exx, sqrt(exx * eyy), eyy, 0.0 };
    const sea_facet fe = sea_facet_of(&edge);
    CU_ASSERT((double)fe.cxy * fe.cxy > (double)fe.cxx * fe.cyy);
    const sea_slope_stats se = sea_facet_stats(&fe);
    sea_error err;
    CU_ASSERT_EQUAL(sea_slope_stats_check(&se, &err), SEA_OK);
    CU_ASSERT(se.cov.xy * se.cov.xy <= se.cov.xx * se.cov.yy);
    unsigned char bytes[sizeof fe];
    memcpy(bytes, &fe, sizeof fe);
    CU_ASSERT(bytes[28] == 0 && bytes[29] == 0 && bytes[30] == 0 && bytes[31] == 0);
}

int test_waves_register(void)
{
    CU_pSuite s = CU_add_suite("waves", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "generated + sub-facet = LR", test_generated_plus_subfacet_is_lr) ||
           !CU_add_test(s, "spatial statistics", test_spatial_statistics) ||
           !CU_add_test(s, "FFT = sum of its modes", test_fft_is_sum_of_its_modes) ||
           !CU_add_test(s, "FFT and sinusoids agree", test_fft_and_sinusoids_agree) ||
           !CU_add_test(s, "LEAN 2x2 averaging exact", test_lean_averaging_exact) ||
           !CU_add_test(s, "Variable Step = centre slope", test_variable_step_is_centre_slope) ||
           !CU_add_test(s, "determinism", test_determinism) ||
           !CU_add_test(s, "FFT: concurrent sampling", test_fft_concurrent_sampling) ||
           !CU_add_test(s, "plans share bins", test_plans_share_bins) ||
           !CU_add_test(s, "phase speed", test_phase_speed) ||
           !CU_add_test(s, "loop period", test_loop_period) ||
           !CU_add_test(s, "HR converges to LR (Fig. 5-6)", test_convergence_to_low_resolution) ||
           !CU_add_test(s, "bad input", test_bad_input) ||
           !CU_add_test(s, "moments to stats", test_moments_stats) ||
           !CU_add_test(s, "facets: float slopes, double height", test_facets);
}
