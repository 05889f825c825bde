/* twoscale.c - the two-scale effective emissivity (an addition to the
 * paper; seabake-model(7), TWO SCALES).
 *
 * The one-scale Eq 7 treats every slope of the sea as one Gaussian surface
 * with one correlation scale.  The sea's slopes come from waves of many
 * scales, and the long waves hide the short ones' troughs in a way the
 * one-scale shadowing cannot see: ray-traced sea-spectrum surfaces are up
 * to 0.02 above it at 85 degrees (tests/data/mc_sea_full_emissivity.csv).
 * Here the slopes are split into a resolved band (the longer waves,
 * covariance C_res) carrying facets and a sub-facet band (C_sub) on each
 * facet: the facets' slopes m ~ N(m0, C_res) each count by their projected
 * area g = 1 - m_X tan(theta) times the chance the longer waves leave them
 * in view (the correlated function C(z, t) when the optics use it, else
 * 1), and each shows its own eps~ (Eq 7 with mean m and covariance C_sub):
 *
 *   eps_2 = E[g C eps~(v; m, C_sub)] / E[g C]
 *
 * which is also what an image at facets of the split's size shows
 * (multires.c): low resolution and the finest level then agree.  The
 * quadrature: Gauss-Legendre over t = (m_X - m0_X)/s_X on [-6, min(z, 6)]
 * (z = (cot theta - m0_X)/s_X: the facets the view does not turn away)
 * and Gauss-Hermite over m_Y given m_X. */
#include <gsl/gsl_integration.h>
#include <math.h>
#include <stdlib.h>

#include "seabake.h"
#include "internal.h"

enum { TS_NX = 24, TS_NY = 8 };      /* the reference's orders */
enum { TAB_NX = 12, TAB_NY = 4 };    /* the table's (within 1e-4 of them, tests) */

sea_status sea_spectrum_split_at(const sea_spectrum *s, double kc, double resolved,
                                 double *k_split, sea_cov2 *res, sea_cov2 *sub, sea_error *err)
{
    if (!(kc >= 0.0) || !isfinite(kc))
        return sea_fail(err, SEA_ERR_DOMAIN, "cutoff wavenumber %g (allowed: finite, >= 0)", kc);
    sea_cov2 all, c;
    sea_status st = sea_spectrum_slope_cov(s, kc, &all, err);
    if (st != SEA_OK)
        return st;
    if (!(resolved > 0.0 && resolved < all.xx + all.yy))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "resolved slope variance %g (allowed: (0, %g), the waves' above the "
                        "cutoff)",
                        resolved, all.xx + all.yy);
    /* the shorter waves keep the rest (exact for resolved = half: Sterbenz) */
    const double rest = (all.xx + all.yy) - resolved;
    /* bisection in log k: the slope variance of waves with |k| >= k
     * decreases with k */
    double lo = kc > 0.0 ? kc : 1e-4, hi = 1e5;
    for (int it = 0; it < 80 && hi / lo > 1.0 + 1e-9; it++) {
        const double k = sqrt(lo * hi);
        if ((st = sea_spectrum_slope_cov(s, k, &c, err)) != SEA_OK)
            return st;
        if (c.xx + c.yy > rest)
            lo = k;
        else
            hi = k;
    }
    *k_split = sqrt(lo * hi);
    if ((st = sea_spectrum_slope_cov(s, *k_split, sub, err)) != SEA_OK)
        return st;
    *res = (sea_cov2){ all.xx - sub->xx, all.yy - sub->yy, all.xy - sub->xy };
    return SEA_OK;
}

sea_status sea_spectrum_split_half(const sea_spectrum *s, double kc, double *k_half,
                                   sea_cov2 *res, sea_cov2 *sub, sea_error *err)
{
    if (!(kc >= 0.0) || !isfinite(kc))
        return sea_fail(err, SEA_ERR_DOMAIN, "cutoff wavenumber %g (allowed: finite, >= 0)", kc);
    sea_cov2 all;
    sea_status st = sea_spectrum_slope_cov(s, kc, &all, err);
    if (st != SEA_OK)
        return st;
    return sea_spectrum_split_at(s, kc, 0.5 * (all.xx + all.yy), k_half, res, sub, err);
}

static sea_status two_scale(const sea_optics *p, double complex N, const sea_slope_stats *sub,
                            sea_cov2 res, sea_dir v, int nx, int ny, double *out, sea_error *err)
{
    sea_status st = sea_slope_stats_check(sub, err);
    if (st != SEA_OK)
        return st;
    if (!(res.xx >= 0.0 && res.yy >= 0.0) || !isfinite(res.xx) || !isfinite(res.yy) ||
        !isfinite(res.xy) || res.xy * res.xy > res.xx * res.yy * (1.0 + 1e-9))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "resolved slope covariance (%g, %g, %g) is not a covariance", res.xx,
                        res.yy, res.xy);
    if (!(v.theta >= 0.0 && v.theta < M_PI / 2.0) || !isfinite(v.phi))
        return sea_fail(err, SEA_ERR_DOMAIN, "view zenith %g rad (allowed: [0, pi/2))", v.theta);
    /* the resolved covariance in the view's frame: X along the view azimuth */
    const double c = cos(v.phi), s = sin(v.phi);
    const double vX = c * c * res.xx + 2.0 * c * s * res.xy + s * s * res.yy;
    const double vY = s * s * res.xx - 2.0 * c * s * res.xy + c * c * res.yy;
    const double cXY = (c * c - s * s) * res.xy + c * s * (res.yy - res.xx);
    const double m0X = c * sub->mean.x + s * sub->mean.y;
    const double tant = tan(v.theta), cott = 1.0 / tant;
    const double sX = sqrt(vX);
    const double z = sX > 0.0 ? (cott - m0X) / sX : INFINITY;
    const double tb = fmin(z, 6.0);
    if (!(vX > 1e-12 * (sub->cov.xx + sub->cov.yy)) || !(tb > -6.0))
        /* no resolved band, or every facet turned away: one scale */
        return sea_emissivity(p, SEA_EMIS_AUTO, N, sub, v, out, err);
    const double slope = cXY / vX, sY = sqrt(fmax(vY - cXY * cXY / vX, 0.0));
    const int correlated = sea_optics_shadowing(p) == SEA_SHADOW_CORRELATED;

    gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc((size_t)nx);
    gsl_integration_fixed_workspace *gh =
        gsl_integration_fixed_alloc(gsl_integration_fixed_hermite, (size_t)ny, 0.0, 0.5, 0.0, 0.0);
    if (gl == NULL || gh == NULL) {
        gsl_integration_glfixed_table_free(gl);
        gsl_integration_fixed_free(gh);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the two-scale quadrature");
    }
    const double *y = gsl_integration_fixed_nodes(gh), *wy = gsl_integration_fixed_weights(gh);
    double num = 0.0, den = 0.0;
    for (int i = 0; i < nx && st == SEA_OK; i++) {
        double t, wt;
        gsl_integration_glfixed_point(-6.0, tb, (size_t)i, &t, &wt, gl);
        const double mX = m0X + sX * t;
        const double g = 1.0 - mX * tant;
        const double V = correlated ? sea_shadow_correlated(z, t) : 1.0;
        const double w = wt * exp(-0.5 * t * t) * g * V;
        if (!(w > 0.0))
            continue;
        for (int j = 0; j < ny; j++) {
            /* the facet's slope in the view frame, back to x, y */
            const double dX = sX * t, dY = slope * dX + sY * y[j];
            sea_slope_stats f = *sub;
            f.mean.x += c * dX - s * dY;
            f.mean.y += s * dX + c * dY;
            double e;
            if ((st = sea_emissivity(p, SEA_EMIS_AUTO, N, &f, v, &e, err)) != SEA_OK)
                break;
            num += w * wy[j] * e;
            den += w * wy[j];
        }
    }
    gsl_integration_glfixed_table_free(gl);
    gsl_integration_fixed_free(gh);
    if (st != SEA_OK)
        return st;
    if (!(den > 0.0))
        return sea_emissivity(p, SEA_EMIS_AUTO, N, sub, v, out, err);
    *out = num / den;
    return SEA_OK;
}

sea_status sea_emissivity_two_scale(const sea_optics *p, double complex N,
                                    const sea_slope_stats *sub, sea_cov2 res, sea_dir v,
                                    double *out, sea_error *err)
{
    return two_scale(p, N, sub, res, v, TS_NX, TS_NY, out, err);
}

/* ------------------------------------------------------------------ table
 *
 * What two scales add to a facet's one-scale eps~, as a function of the
 * view seen from the facet (its mean slope's plane), the view's azimuth to
 * the wind and how much of the split's resolved band the facet's own
 * covariance holds, f = (tr C - tr C_h) / (tr C_LR - tr C_h) in [0, 1]
 * (C_h: the waves shorter than the split; f = 1 low resolution, 0 a facet
 * no larger than the split).  A facet of mean slope m seen from v is taken
 * as a level facet seen from v's direction in its own plane: against the
 * two scales under the facet's mean slope this is within 5e-5 at 70-85 deg
 * (seabake-model(7), TWO SCALES).  The rows of view angles are computed
 * when a pixel first needs them: a view that never grazes computes none. */
enum { TAB_NT = 32, TAB_NP = 5, TAB_NF = 5 };
#define TAB_T0 (50.0 * M_PI / 180.0)
#define TAB_T1 (96.0 * M_PI / 180.0)
/* views beyond it from the facet's plane: a facet tilted away by the
 * excess, seen from here */
#define TAB_TV (85.0 * M_PI / 180.0)

struct sea_two_scale_table {
    const sea_optics *p;
    double complex N;
    sea_cov2 split_sub, total;
    double wind_dir;
    double cw, sw; /* cos and sin of wind_dir */
    double tr_h, tr_lr;
    /* ready[it]: row it computed (read with acquire, written with release
     * after its values) */
    int ready[TAB_NT];
    /* delta[(it * TAB_NP + ip) * TAB_NF + jf]: theta node it, azimuth
     * ip 22.5 deg to the wind, f = jf / (TAB_NF - 1) */
    double delta[TAB_NT * TAB_NP * TAB_NF];
};

sea_status sea_two_scale_table_alloc(const sea_optics *p, double complex N, sea_cov2 split_sub,
                                     sea_cov2 total, double wind_dir,
                                     sea_two_scale_table **out, sea_error *err)
{
    *out = NULL;
    const double tr_h = split_sub.xx + split_sub.yy, tr_lr = total.xx + total.yy;
    if (!(tr_h > 0.0 && tr_lr > tr_h) || !isfinite(tr_lr) || !isfinite(wind_dir) ||
        !isfinite(creal(N)) || !isfinite(cimag(N)))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "two-scale table: the split's covariance (trace %g) must be below the "
                        "total's (%g), both positive and finite, and the index finite",
                        tr_h, tr_lr);
    sea_two_scale_table *t = calloc(1, sizeof *t);
    if (t == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the two-scale table");
    t->p = p;
    t->N = N;
    t->split_sub = split_sub;
    t->total = total;
    t->wind_dir = wind_dir;
    t->cw = cos(wind_dir);
    t->sw = sin(wind_dir);
    t->tr_h = tr_h;
    t->tr_lr = tr_lr;
    *out = t;
    return SEA_OK;
}

/* Row it: every azimuth and facet size (f = 0 adds nothing). */
static sea_status table_row(sea_two_scale_table *t, int it, sea_error *err)
{
    const double tl = TAB_T0 + (TAB_T1 - TAB_T0) * it / (TAB_NT - 1);
    const double tilt = tan(fmax(tl - TAB_TV, 0.0)); /* along the view, away */
    const sea_cov2 hs = t->split_sub, tot = t->total;
    for (int ip = 0; ip < TAB_NP; ip++) {
        const sea_dir v = { fmin(tl, TAB_TV), t->wind_dir + M_PI / 8.0 * ip };
        const sea_vec2 m = { tilt * cos(v.phi), tilt * sin(v.phi) };
        for (int jf = 1; jf < TAB_NF; jf++) {
            const double f = (double)jf / (TAB_NF - 1);
            const sea_cov2 res = { f * (tot.xx - hs.xx), f * (tot.yy - hs.yy),
                                   f * (tot.xy - hs.xy) };
            const sea_slope_stats one = { m, { hs.xx + res.xx, hs.yy + res.yy, hs.xy + res.xy } };
            const sea_slope_stats sub = { m, hs };
            double e1, e2;
            sea_status st = sea_emissivity(t->p, SEA_EMIS_AUTO, t->N, &one, v, &e1, err);
            if (st == SEA_OK)
                st = two_scale(t->p, t->N, &sub, res, v, TAB_NX, TAB_NY, &e2, err);
            if (st != SEA_OK)
                return st;
            t->delta[(it * TAB_NP + ip) * TAB_NF + jf] = e2 - e1;
        }
    }
    return SEA_OK;
}

/* Rows k[0..3] computed, the first caller that needs one computing it
 * while the others wait. */
static sea_status table_rows(sea_two_scale_table *t, const int k[4], sea_error *err)
{
    sea_status st = SEA_OK;
    for (int a = 0; a < 4 && st == SEA_OK; a++) {
        if (__atomic_load_n(&t->ready[k[a]], __ATOMIC_ACQUIRE))
            continue;
#pragma omp critical(sea_two_scale_row)
        {
            if (!__atomic_load_n(&t->ready[k[a]], __ATOMIC_ACQUIRE)) {
                st = table_row(t, k[a], err);
                if (st == SEA_OK)
                    __atomic_store_n(&t->ready[k[a]], 1, __ATOMIC_RELEASE);
            }
        }
    }
    return st;
}

size_t sea_two_scale_table_rows(const sea_two_scale_table *t)
{
    size_t n = 0;
    for (int it = 0; it < TAB_NT; it++)
        n += __atomic_load_n(&t->ready[it], __ATOMIC_ACQUIRE) != 0;
    return n;
}

void sea_two_scale_table_free(sea_two_scale_table *t)
{
    free(t);
}

/* Four node indices around x in [0, n - 1] (clamped at the ends) and the
 * fraction between the middle two. */
static double cr_nodes(double x, int n, int k[4])
{
    int i = (int)floor(x);
    if (i < 0)
        i = 0;
    if (i > n - 2)
        i = n - 2;
    for (int a = 0; a < 4; a++) {
        int j = i - 1 + a;
        k[a] = j < 0 ? 0 : j > n - 1 ? n - 1 : j;
    }
    return x - i;
}

sea_status sea_two_scale_delta(sea_two_scale_table *t, sea_dir v, const sea_slope_stats *st,
                               double *out, sea_error *err)
{
    *out = 0.0;
    /* the view in the plane of the facet's mean slope: normal n, tangent
     * axes the wind projected on the plane and n x that */
    const double mx = st->mean.x, my = st->mean.y;
    const double nn = sqrt(1.0 + mx * mx + my * my);
    const double n[3] = { -mx / nn, -my / nn, 1.0 / nn };
    const double d[3] = { sin(v.theta) * cos(v.phi), sin(v.theta) * sin(v.phi), cos(v.theta) };
    const double ct = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    if (!(ct < cos(TAB_T0)))
        return SEA_OK; /* below the table's first angle (or not a number): nothing to add */
    /* the wind's direction projected on the plane: the azimuth is read
     * from it, whatever the scene's axes */
    const double cw = t->cw, sw = t->sw;
    const double wn = cw * n[0] + sw * n[1];
    double ex[3] = { cw - wn * n[0], sw - wn * n[1], -wn * n[2] };
    const double ne = sqrt(ex[0] * ex[0] + ex[1] * ex[1] + ex[2] * ex[2]);
    for (int a = 0; a < 3; a++)
        ex[a] /= ne;
    const double ey[3] = { n[1] * ex[2] - n[2] * ex[1], n[2] * ex[0] - n[0] * ex[2],
                           n[0] * ex[1] - n[1] * ex[0] };
    const double px = d[0] * ex[0] + d[1] * ex[1] + d[2] * ex[2];
    const double py = d[0] * ey[0] + d[1] * ey[1] + d[2] * ey[2];
    const double theta = acos(fmax(ct, -1.0)); /* beyond 90: the facet's plane turned away */
    const double phi = fabs(remainder(atan2(py, px), M_PI)); /* to the wind, [0, pi/2] */
    double f = (st->cov.xx + st->cov.yy - t->tr_h) / (t->tr_lr - t->tr_h);
    f = isfinite(f) ? fmin(fmax(f, 0.0), 1.0) : 0.0;

    int kt[4], kf[4], kp[4];
    double wt[4], wf[4], wp[4];
    sea_catmull_rom(cr_nodes((fmin(theta, TAB_T1) - TAB_T0) / (TAB_T1 - TAB_T0) * (TAB_NT - 1),
                        TAB_NT, kt),
               wt);
    sea_catmull_rom(cr_nodes(f * (TAB_NF - 1), TAB_NF, kf), wf);
    const sea_status status = table_rows(t, kt, err);
    if (status != SEA_OK)
        return status;
    /* the azimuth: the table is even about 0 and about 90 degrees (the
     * sea's slopes are symmetric about the wind and across it), so the
     * nodes beyond the ends are mirrored, not clamped */
    const double xp = phi / (M_PI / 8.0);
    int i0 = (int)floor(xp);
    if (i0 > TAB_NP - 2)
        i0 = TAB_NP - 2;
    for (int a = 0; a < 4; a++) {
        int j = i0 - 1 + a;
        kp[a] = j < 0 ? -j : j > TAB_NP - 1 ? 2 * (TAB_NP - 1) - j : j;
    }
    sea_catmull_rom(xp - i0, wp);
    /* along the sub-facet share, then the azimuth, then the angle: 16
     * short sums side by side instead of one chain of 64 additions */
    double s = 0.0;
    for (int i = 0; i < 4; i++) {
        const double *row = &t->delta[kt[i] * TAB_NP * TAB_NF];
        double si = 0.0;
        for (int p = 0; p < 4; p++) {
            const double *dp = row + kp[p] * TAB_NF;
            si += wp[p] * ((wf[0] * dp[kf[0]] + wf[1] * dp[kf[1]]) +
                           (wf[2] * dp[kf[2]] + wf[3] * dp[kf[3]]));
        }
        s += wt[i] * si;
    }
    *out = s;
    return SEA_OK;
}
