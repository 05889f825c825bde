/* test_swell.c - swell added to the wind sea (seabake-model(7), SWELL):
 * the spectrum against independent quadratures, the synthesised heights'
 * Hs, the peak period of a time series, the slope variance of wind sea
 * plus swell, the direction of travel, the Douglas codes, bad input. */
#include <fftw3.h>
#include <stdlib.h>
#include <string.h>

#include "unit.h"

static const double G = 9.81;

static sea_spectrum sea_with_swell(double wind, double hs, double tp, double dir_deg,
                                   double spread_deg)
{
    sea_spectrum s;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_init(wind, INFINITY, 0.0, &s, &err), SEA_OK);
    const sea_swell sw = { .hs = hs, .tp = tp, .dir = dir_deg * DEG, .spread = spread_deg * DEG,
                           .gamma = 3.3 };
    sea_status st = sea_spectrum_add_swell(&s, &sw, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  sea_spectrum_add_swell: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    return s;
}

static sea_waves *plan(const sea_spectrum *s, sea_waves_kind kind, double finest, size_t fft)
{
    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = kind;
    p.finest = finest;
    p.fft_size = fft;
    sea_waves *w = NULL;
    sea_error err;
    sea_status st = sea_waves_alloc(s, &p, &w, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  sea_waves_alloc: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    return w;
}

/* The swell's height and slope moments by a plain midpoint rule over the
 * directional spectrum on a (ln k, phi) grid, independent of the closed
 * forms in spectrum.c (the JONSWAP normalisation in frequency, the wrapped
 * normal's exp(-2 spread^2)). */
static void grid_moments(const sea_spectrum *s, double *m0, sea_cov2 *slope)
{
    const int nk = 6000, np = 720;
    const double a = log(1e-3), b = log(10.0), dl = (b - a) / nk, dp = 2.0 * M_PI / np;
    *m0 = 0.0;
    *slope = (sea_cov2){ 0.0, 0.0, 0.0 };
    for (int i = 0; i < nk; i++) {
        const double k = exp(a + (i + 0.5) * dl);
        for (int j = 0; j < np; j++) {
            const double phi = (j + 0.5) * dp;
            /* Psi k dk dphi, dk = k d(ln k) */
            const double e = sea_spectrum_directional_swell(s, k, phi) * k * k * dl * dp;
            *m0 += e;
            slope->xx += e * k * k * cos(phi) * cos(phi);
            slope->yy += e * k * k * sin(phi) * sin(phi);
            slope->xy += e * k * k * cos(phi) * sin(phi);
        }
    }
}

/* The spectrum: Hs = 4 sqrt(m0) and the slope covariance of the swell by
 * the grid against the closed forms, to the grid's error (1e-4: the
 * band's hard ends cut a cell of 1.6e-3 in ln k). */
static void test_spectrum_moments(void)
{
    const double dirs[] = { 0.0, 40.0, 90.0, 200.0 }, spreads[] = { 5.0, 15.0, 45.0 };
    for (size_t d = 0; d < 4; d++) {
        for (size_t q = 0; q < 3; q++) {
            const sea_spectrum s = sea_with_swell(8.0, 2.5, 11.0, dirs[d], spreads[q]);
            const sea_spectrum wind = sea_with_swell(8.0, 2.5, 11.0, 0.0, 15.0);
            sea_spectrum bare = wind;
            bare.n_swell = 0;
            double m0;
            sea_cov2 g, with, without;
            grid_moments(&s, &m0, &g);
            ASSERT_REL(4.0 * sqrt(m0), 2.5, 1e-4, 0.0);
            CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&s, 0.0, &with, NULL), SEA_OK);
            CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&bare, 0.0, &without, NULL), SEA_OK);
            const double tr = g.xx + g.yy;
            ASSERT_ABS(with.xx - without.xx, g.xx, 2e-4 * tr);
            ASSERT_ABS(with.yy - without.yy, g.yy, 2e-4 * tr);
            ASSERT_ABS(with.xy - without.xy, g.xy, 2e-4 * tr);
            if (d == 1 && q == 1)
                MEASURED("swell Hs 2.5 m, Tp 11 s, spread 15 deg: slope variance %.4e "
                         "(wind sea at 8 m/s %.4e)\n",
                         tr, without.xx + without.yy);
        }
    }
    /* above the band the swell holds nothing */
    const sea_spectrum s = sea_with_swell(8.0, 2.5, 11.0, 0.0, 15.0);
    double klo, khi;
    sea_swell_band(&s.swell[0], &klo, &khi);
    CU_ASSERT(sea_swell_curvature(&s.swell[0], 1.01 * khi) == 0.0);
    CU_ASSERT(sea_swell_curvature(&s.swell[0], 0.99 * klo) == 0.0);
    CU_ASSERT(sea_swell_curvature(&s.swell[0], sqrt(klo * khi)) > 0.0);
    /* the wrapped normal's density integrates to 1 over a turn */
    for (size_t q = 0; q < 3; q++) {
        sea_swell sw = s.swell[0];
        sw.spread = spreads[q] * DEG;
        double sum = 0.0;
        for (int j = 0; j < 3600; j++)
            sum += sea_swell_direction_density(&sw, (j + 0.5) * 2.0 * M_PI / 3600) * 2.0 * M_PI /
                   3600;
        ASSERT_REL(sum, 1.0, 1e-12, 0.0);
    }
    /* the lowest wavenumber reaches the swell's band */
    CU_ASSERT(sea_spectrum_k_low(&s) <= klo);
}

static double height_hs(const double *h, size_t n)
{
    double m = 0.0, v = 0.0;
    for (size_t i = 0; i < n; i++)
        m += h[i];
    m /= (double)n;
    for (size_t i = 0; i < n; i++)
        v += (h[i] - m) * (h[i] - m);
    return 4.0 * sqrt(v / (double)n);
}

/* Hs of the synthesised heights over a large patch within 3 % of the asked
 * value, alone (wind 0.5 m/s: Hs 5 mm) and with a 10 m/s wind sea, whose
 * Hs adds in quadrature; both generators.  3 %: a patch of 8 km holds some
 * 35 peak wavelengths of a 12 s swell each way, and the sum of random
 * phases leaves the variance a sampling error of about 1 %. */
static void test_synthesised_hs(void)
{
    const size_t n = UNIT_QUICK ? 256 : 1024;
    const double step = 8.0; /* 8 km patch */
    double *h = malloc(n * n * sizeof *h);
    CU_ASSERT_FATAL(h != NULL);
    const double winds[2] = { 0.5, 10.0 };
    double worst = 0.0;
    for (int wi = 0; wi < 2; wi++) {
        const sea_spectrum s = sea_with_swell(winds[wi], 3.0, 12.0, 60.0, 15.0);
        sea_spectrum bare = s;
        bare.n_swell = 0;
        for (int kind = 0; kind < 2; kind++) {
            const int fft = kind == 1;
            sea_waves *w = plan(&s, fft ? SEA_WAVES_FFT : SEA_WAVES_SINUSOIDS, step, n);
            const sea_rect r = { step, 0, 0, n, n };
            CU_ASSERT_EQUAL_FATAL(sea_waves_sample(w, &r, 0.0, h, NULL, NULL, NULL), SEA_OK);
            const double hs = height_hs(h, n * n);
            sea_waves_free(w);
            double expect = 3.0;
            if (wi == 1) {
                /* the wind sea's own Hs over the same patch and plan */
                w = plan(&bare, fft ? SEA_WAVES_FFT : SEA_WAVES_SINUSOIDS, step, n);
                CU_ASSERT_EQUAL_FATAL(sea_waves_sample(w, &r, 0.0, h, NULL, NULL, NULL), SEA_OK);
                const double hw = height_hs(h, n * n);
                sea_waves_free(w);
                expect = sqrt(9.0 + hw * hw);
            }
            worst = fmax(worst, fabs(hs / expect - 1.0));
            MEASURED("swell Hs 3 m, Tp 12 s, wind %g m/s, %s: synthesised Hs %.4f m (expected "
                     "%.4f)\n",
                     winds[wi], fft ? "FFT" : "sinusoids", hs, expect);
        }
    }
    if (!UNIT_QUICK)
        ASSERT_CLAIM("swell_hs", worst, 0.0);
    free(h);
}

/* The peak period from the spectrum of time series of the height: 16
 * points 1 km apart, 4096 s each at 0.5 s, Hann window, periodogram
 * averaged over the points and smoothed over 9 bins (0.002 Hz), and the
 * peak frequency by Young's (1995) weighting int f S^4 / int S^4, which
 * a noisy periodogram does not throw off as its largest bin would.  Within
 * 5 %: the plan's wavenumber bins (8 per octave) are 4.4 % wide in
 * frequency, and the weighting leans 1-2 % toward the JONSWAP's heavier
 * high side. */
static void test_peak_period(void)
{
    const int N = UNIT_QUICK ? 1024 : 8192, npt = UNIT_QUICK ? 2 : 16;
    const double dt = 0.5;
    double *x = fftw_malloc((size_t)N * sizeof *x);
    fftw_complex *X = fftw_malloc((size_t)(N / 2 + 1) * sizeof *X);
    double *P = calloc((size_t)N / 2 + 1, sizeof *P);
    CU_ASSERT_FATAL(x != NULL && X != NULL && P != NULL);
    fftw_plan pl = fftw_plan_dft_r2c_1d(N, x, X, FFTW_ESTIMATE);
    const double tps[] = { 6.0, 10.0, 16.0 };
    double worst = 0.0;
    for (int t = 0; t < 3; t++) {
        const sea_spectrum s = sea_with_swell(0.5, 2.0, tps[t], 30.0, 20.0);
        sea_waves *w = plan(&s, SEA_WAVES_SINUSOIDS, 1.0, 0);
        memset(P, 0, (size_t)(N / 2 + 1) * sizeof *P);
        for (int pt = 0; pt < npt; pt++) {
            for (int i = 0; i < N; i++) {
                double h;
                sea_waves_at(w, M_PI, 1370.0 * pt, 910.0 * (pt % 4), i * dt, &h, NULL);
                x[i] = h * (0.5 - 0.5 * cos(2.0 * M_PI * i / N));
            }
            fftw_execute(pl);
            for (int i = 0; i <= N / 2; i++)
                P[i] += X[i][0] * X[i][0] + X[i][1] * X[i][1];
        }
        double num = 0.0, den = 0.0;
        for (int i = 5; i < N / 2 - 5; i++) {
            double v = 0.0;
            for (int j = -4; j <= 4; j++)
                v += P[i + j];
            const double v4 = v * v * v * v;
            num += i * v4;
            den += v4;
        }
        const double tp = N * dt * den / num;
        worst = fmax(worst, fabs(tp / tps[t] - 1.0));
        MEASURED("swell Tp %g s: recovered from time series %.3f s (%+.1f %%)\n", tps[t], tp,
                 100.0 * (tp / tps[t] - 1.0));
        sea_waves_free(w);
    }
    if (!UNIT_QUICK)
        ASSERT_CLAIM("swell_tp", worst, 0.0);
    fftw_destroy_plan(pl);
    fftw_free(x);
    fftw_free(X);
    free(P);
}

/* The slope variance of the synthesis equals wind sea plus swell: the
 * generated covariance of a plan with a swell minus that of the same plan
 * without is the swell's share of the spectrum below the plan's cut,
 * within 1 % (measured 1e-5: only the swells' direction quadrature and the
 * cut bin differ); and the heights' spatial slope variance over a large
 * patch matches the swell's closed form within 3 % (sampling). */
static void test_slope_variance(void)
{
    const double finest = 2.0, kc = M_PI / finest;
    const sea_spectrum s = sea_with_swell(10.0, 3.0, 12.0, 90.0, 15.0);
    sea_spectrum bare = s;
    bare.n_swell = 0;
    sea_cov2 all_w, all_b, cut_w, cut_b;
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&s, 0.0, &all_w, NULL), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&bare, 0.0, &all_b, NULL), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&s, kc, &cut_w, NULL), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&bare, kc, &cut_b, NULL), SEA_OK);
    /* the swell's slope covariance below the cut, from the spectrum */
    const sea_cov2 swell = { (all_w.xx - cut_w.xx) - (all_b.xx - cut_b.xx),
                             (all_w.yy - cut_w.yy) - (all_b.yy - cut_b.yy),
                             (all_w.xy - cut_w.xy) - (all_b.xy - cut_b.xy) };
    for (int kind = 0; kind < 2; kind++) {
        sea_waves *ww = plan(&s, kind ? SEA_WAVES_FFT : SEA_WAVES_SINUSOIDS, finest, 2048);
        sea_waves *wb = plan(&bare, kind ? SEA_WAVES_FFT : SEA_WAVES_SINUSOIDS, finest, 2048);
        const sea_cov2 gw = sea_waves_generated_cov(ww, kc), gb = sea_waves_generated_cov(wb, kc);
        const double tr = swell.xx + swell.yy;
        ASSERT_ABS(gw.xx - gb.xx, swell.xx, 0.01 * tr);
        ASSERT_ABS(gw.yy - gb.yy, swell.yy, 0.01 * tr);
        ASSERT_ABS(gw.xy - gb.xy, swell.xy, 0.01 * tr);
        /* the total: wind sea plus swell */
        ASSERT_CLAIM("swell_slope_variance", fabs((gw.xx + gw.yy) - (gb.xx + gb.yy) - tr) / tr,
                     0.0);
        MEASURED("%s: generated swell slope variance %.6e against the spectrum's %.6e\n",
                 kind ? "FFT" : "sinusoids", (gw.xx + gw.yy) - (gb.xx + gb.yy), tr);
        sea_waves_free(ww);
        sea_waves_free(wb);
    }
    /* spatial slope variance of the swell alone over 8 km */
    const sea_spectrum so = sea_with_swell(0.5, 3.0, 12.0, 90.0, 15.0);
    sea_cov2 so_all;
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&so, 0.0, &so_all, NULL), SEA_OK);
    sea_spectrum so_bare = so;
    so_bare.n_swell = 0;
    sea_cov2 so_b;
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_slope_cov(&so_bare, 0.0, &so_b, NULL), SEA_OK);
    const size_t n = UNIT_QUICK ? 256 : 1024;
    sea_waves *w = plan(&so, SEA_WAVES_SINUSOIDS, 8.0, 0);
    double *sx = malloc(n * n * sizeof *sx), *sy = malloc(n * n * sizeof *sy);
    CU_ASSERT_FATAL(sx != NULL && sy != NULL);
    const sea_rect r = { 8.0, 0, 0, n, n };
    CU_ASSERT_EQUAL_FATAL(sea_waves_sample(w, &r, 0.0, NULL, sx, sy, NULL), SEA_OK);
    double vx = 0.0, vy = 0.0;
    for (size_t i = 0; i < n * n; i++) {
        vx += sx[i] * sx[i];
        vy += sy[i] * sy[i];
    }
    const double spatial = (vx + vy) / (double)(n * n);
    /* the swell's share above k = pi/8 m (none: the band ends at 0.25 rad/m) */
    const double expect = (so_all.xx + so_all.yy) - (so_b.xx + so_b.yy);
    if (!UNIT_QUICK)
        ASSERT_REL(spatial, expect, 0.03, 0.0);
    MEASURED("swell alone: spatial slope variance %.5e, spectrum %.5e\n", spatial, expect);
    free(sx);
    free(sy);
    sea_waves_free(w);
}

/* A swell travels toward its direction: its waves carry omega > 0 along
 * wave vectors within its spread of `dir` (both generators), whatever the
 * wind's direction. */
static void test_direction_of_travel(void)
{
    sea_spectrum s;
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_init(0.5, INFINITY, 0.0, &s, NULL), SEA_OK);
    const sea_swell sw = { .hs = 2.0, .tp = 10.0, .dir = 150.0 * DEG, .spread = 10.0 * DEG,
                           .gamma = 3.3 };
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_add_swell(&s, &sw, NULL), SEA_OK);
    for (int kind = 0; kind < 2; kind++) {
        sea_waves *w = plan(&s, kind ? SEA_WAVES_FFT : SEA_WAVES_SINUSOIDS, 4.0, 1024);
        double num = 0.0, den = 0.0;
        for (size_t i = 0; i < sea_waves_count(w); i++) {
            const sea_wave o = sea_waves_get(w, i);
            const double e = o.amplitude * o.amplitude, k = hypot(o.kx, o.ky);
            /* the phase velocity's direction: sign(omega) k / |k| */
            const double along = (o.omega > 0 ? 1.0 : -1.0) *
                                 (o.kx * cos(sw.dir) + o.ky * sin(sw.dir)) / k;
            num += e * along;
            den += e;
        }
        /* the wrapped normal's mean of cos(phi - dir) is exp(-spread^2 / 2) = 0.985 */
        ASSERT_REL(num / den, exp(-0.5 * sw.spread * sw.spread), 0.01, 0.0);
        sea_waves_free(w);
    }
}

/* A swell leaves the wind sea's waves as they were: the plan without the
 * swell is a subset of the plan with it, wave for wave. */
static void test_wind_sea_kept(void)
{
    const sea_spectrum s = sea_with_swell(7.0, 1.5, 9.0, 45.0, 20.0);
    sea_spectrum bare = s;
    bare.n_swell = 0;
    sea_waves *ww = plan(&s, SEA_WAVES_SINUSOIDS, 1.0, 0);
    sea_waves *wb = plan(&bare, SEA_WAVES_SINUSOIDS, 1.0, 0);
    const size_t nw = sea_waves_count(ww), nb = sea_waves_count(wb);
    CU_ASSERT(nw > nb);
    size_t found = 0, j = 0;
    for (size_t i = 0; i < nb; i++) {
        const sea_wave b = sea_waves_get(wb, i);
        while (j < nw) {
            const sea_wave a = sea_waves_get(ww, j++);
            if (memcmp(&a, &b, sizeof a) == 0) {
                found++;
                break;
            }
        }
    }
    CU_ASSERT_EQUAL(found, nb);
    sea_waves_free(ww);
    sea_waves_free(wb);
}

static void test_douglas(void)
{
    double hs, tp, prev_hs = 0.0;
    for (int d = 1; d <= 8; d++) {
        CU_ASSERT_EQUAL_FATAL(sea_swell_douglas(d, &hs, &tp), 0);
        CU_ASSERT(hs >= prev_hs);
        prev_hs = hs;
        /* the peak wavelength of deep water g Tp^2 / (2 pi) is a class's length */
        const double lambda = G * tp * tp / (2.0 * M_PI);
        CU_ASSERT(fabs(lambda - 75.0) < 1e-9 || fabs(lambda - 150.0) < 1e-9 ||
                  fabs(lambda - 300.0) < 1e-9);
    }
    CU_ASSERT_EQUAL(sea_swell_douglas(4, &hs, &tp), 0);
    ASSERT_ABS(hs, 3.0, 0.0);
    ASSERT_ABS(tp, 9.8017, 1e-4); /* sqrt(2 pi 150 / 9.81) */
    CU_ASSERT_EQUAL(sea_swell_douglas(0, &hs, &tp), -1);
    CU_ASSERT_EQUAL(sea_swell_douglas(9, &hs, &tp), -1);
}

static void test_bad_input(void)
{
    sea_spectrum s;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_spectrum_init(10.0, INFINITY, 0.0, &s, NULL), SEA_OK);
    const sea_swell good = { .hs = 2.0, .tp = 10.0, .dir = 0.0, .spread = 15.0 * DEG,
                             .gamma = 3.3 };
    sea_swell bad[] = { good, good, good, good, good, good, good, good, good };
    bad[0].hs = 0.0;
    bad[1].hs = NAN;
    bad[2].tp = 2.0;
    bad[3].tp = 31.0;
    bad[4].dir = INFINITY;
    bad[5].spread = 0.5 * DEG;
    bad[6].spread = 61.0 * DEG;
    bad[7].gamma = 0.9;
    bad[8].gamma = NAN;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CU_ASSERT_EQUAL(sea_spectrum_add_swell(&s, &bad[i], &err), SEA_ERR_DOMAIN);
        CU_ASSERT(strstr(err.msg, "swell") != NULL);
    }
    CU_ASSERT_EQUAL(s.n_swell, 0);
    for (int i = 0; i < SEA_SWELL_MAX; i++)
        CU_ASSERT_EQUAL(sea_spectrum_add_swell(&s, &good, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_spectrum_add_swell(&s, &good, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "at most 4") != NULL);
    CU_ASSERT_EQUAL(s.n_swell, SEA_SWELL_MAX);
}

/* The mean brightness temperature of the rows between `from` and `to`
 * degrees below the horizontal of a flat-earth render (the band's radiance
 * averaged, then inverted). */
static double band_temperature(const sea_scene *sc, const sea_image *img, double from, double to)
{
    const double f = 0.5 * img->width / tan(0.5 * sc->hfov);
    double sum = 0.0;
    long n = 0;
    for (int j = 0; j < img->height; j++) {
        const double dep = (M_PI / 2.0 - sc->look_zenith) + atan((j + 0.5 - 0.5 * img->height) / f);
        if (dep < from * DEG || dep >= to * DEG)
            continue;
        for (int i = 0; i < img->width; i++, n++)
            sum += img->radiance[(size_t)j * (size_t)img->width + (size_t)i];
    }
    CU_ASSERT_FATAL(n > 0);
    /* one wavelength: the image is per um */
    return sea_planck_brightness_temperature(sc->wavelength, sum / (double)n * 1e6);
}

/* What swell changes at the horizon (seabake-model(7), SWELL): mast.ini at
 * night (no glint), 320 x 180, 4 um, sky 260 K, without a swell and with
 * Douglas 7 (5 m, 9.8 s) travelling along the view and across it: the mean
 * brightness temperature of the sea from the horizon to 2 deg below it.
 * Deterministic (one seed): the claims hold the figures to their rounding. */
static void test_horizon_change(void)
{
    if (UNIT_QUICK) {
        UNIT_SKIP("swell at the horizon: three renders of 320 x 180, not under a memory checker");
        return;
    }
    const char *over[][6] = {
        { "sensor.width=320", "sensor.height=180", "sun.zenith=100", NULL, NULL, NULL },
        { "sensor.width=320", "sensor.height=180", "sun.zenith=100", "swell.douglas=7",
          "swell.direction=0", NULL },
        { "sensor.width=320", "sensor.height=180", "sun.zenith=100", "swell.douglas=7",
          "swell.direction=90", NULL },
    };
    double T[3];
    for (int c = 0; c < 3; c++) {
        size_t n = 0;
        while (n < 6 && over[c][n] != NULL)
            n++;
        sea_scene sc;
        sea_error err;
        sea_status st = sea_scene_load_with(SEA_TOP_SRCDIR "/examples/mast.ini", over[c], n, &sc,
                                            &err);
        if (st != SEA_OK)
            fprintf(stderr, "  %s\n", err.msg);
        CU_ASSERT_FATAL(st == SEA_OK);
        sea_view *r = NULL;
        CU_ASSERT_FATAL(sea_view_alloc(&sc, &r, &err) == SEA_OK);
        sea_image img;
        CU_ASSERT_FATAL(sea_image_alloc(sc.width, sc.height, &img, &err) == SEA_OK);
        CU_ASSERT_FATAL(sea_view_render_frame(r, sc.time, &img, NULL, NULL, &err) == SEA_OK);
        T[c] = band_temperature(&sc, &img, 0.0, 2.0);
        sea_image_free(&img);
        sea_view_free(r);
    }
    MEASURED("mast.ini at night, 0-2 deg below the horizon: %.3f K; Douglas 7 along the view "
             "%+.3f K, across %+.3f K\n",
             T[0], T[1] - T[0], T[2] - T[0]);
    ASSERT_CLAIM("swell_horizon_along", T[1] - T[0], 0.0);
    ASSERT_CLAIM("swell_horizon_across", T[2] - T[0], 0.0);
}

int test_swell_register(void)
{
    CU_pSuite s = CU_add_suite("swell", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "spectrum moments", test_spectrum_moments) ||
           !CU_add_test(s, "synthesised Hs", test_synthesised_hs) ||
           !CU_add_test(s, "peak period of a time series", test_peak_period) ||
           !CU_add_test(s, "slope variance: wind sea plus swell", test_slope_variance) ||
           !CU_add_test(s, "direction of travel", test_direction_of_travel) ||
           !CU_add_test(s, "wind sea kept", test_wind_sea_kept) ||
           !CU_add_test(s, "Douglas codes", test_douglas) ||
           !CU_add_test(s, "bad input", test_bad_input) ||
           !CU_add_test(s, "what swell changes at the horizon", test_horizon_change);
}
