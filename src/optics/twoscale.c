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
#include <string.h>

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

/* The arguments of a two-scale average: valid statistics, a covariance
 * res, a view above the horizon. */
static sea_status two_scale_check(const sea_slope_stats *sub, sea_cov2 res, sea_dir v,
                                  sea_error *err)
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
    return SEA_OK;
}

static sea_status two_scale(const sea_optics *p, double complex N, const sea_slope_stats *sub,
                            sea_cov2 res, sea_dir v, int nx, int ny, double *out, sea_error *err)
{
    sea_status st = two_scale_check(sub, res, v, err);
    if (st != SEA_OK)
        return st;
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

/* Two scales for n indices at once (two_scale for N[0..n), each node's
 * emissivity by sea_emissivity_n), by the Gauss-Legendre table gl (nx
 * nodes) and the Gauss-Hermite workspace gh (ny nodes).  pol not NULL:
 * the same mixture of each node's one-hit Stokes emissivity
 * (sea_polar_emissivity_n) into pol[k], out unused. */
static sea_status two_scale_n(const sea_optics *p, const double complex *N, size_t n,
                              const sea_slope_stats *sub, sea_cov2 res, sea_dir v,
                              const gsl_integration_glfixed_table *gl, int nx,
                              const gsl_integration_fixed_workspace *gh, int ny, double *out,
                              sea_stokes *pol, sea_error *err)
{
    const double c = cos(v.phi), s = sin(v.phi);
    const double vX = c * c * res.xx + 2.0 * c * s * res.xy + s * s * res.yy;
    const double vY = s * s * res.xx - 2.0 * c * s * res.xy + c * c * res.yy;
    const double cXY = (c * c - s * s) * res.xy + c * s * (res.yy - res.xx);
    const double m0X = c * sub->mean.x + s * sub->mean.y;
    const double tant = tan(v.theta);
    const double sX = sqrt(fmax(vX, 0.0));
    const double z = sX > 0.0 ? (1.0 / tant - m0X) / sX : INFINITY;
    const double tb = fmin(z, 6.0);
    if (!(vX > 1e-12 * (sub->cov.xx + sub->cov.yy)) || !(tb > -6.0))
        return pol != NULL ? sea_polar_emissivity_n(p, SEA_EMIS_AUTO, NULL, N, n, sub, v, pol, err)
                           : sea_emissivity_n(p, SEA_EMIS_AUTO, NULL, N, n, sub, v, out, err);
    const double slope = cXY / vX, sY = sqrt(fmax(vY - cXY * cXY / vX, 0.0));
    const int correlated = sea_optics_shadowing(p) == SEA_SHADOW_CORRELATED;
    const double *y = gsl_integration_fixed_nodes(gh), *wy = gsl_integration_fixed_weights(gh);
    double num[SEA_SCENE_BAND_MAX], den = 0.0;
    sea_stokes pnum[SEA_SCENE_BAND_MAX];
    for (size_t k = 0; k < n; k++) {
        num[k] = 0.0;
        pnum[k] = (sea_stokes){ 0.0, 0.0, 0.0 };
    }
    for (int i = 0; i < nx; i++) {
        double t, wt;
        gsl_integration_glfixed_point(-6.0, tb, (size_t)i, &t, &wt, gl);
        const double mX = m0X + sX * t;
        const double g = 1.0 - mX * tant;
        const double V = correlated ? sea_shadow_correlated(z, t) : 1.0;
        const double w = wt * exp(-0.5 * t * t) * g * V;
        if (!(w > 0.0))
            continue;
        for (int j = 0; j < ny; j++) {
            const double dX = sX * t, dY = slope * dX + sY * y[j];
            sea_slope_stats f = *sub;
            f.mean.x += c * dX - s * dY;
            f.mean.y += s * dX + c * dY;
            double e[SEA_SCENE_BAND_MAX];
            sea_stokes es[SEA_SCENE_BAND_MAX];
            sea_status st = pol != NULL
                                ? sea_polar_emissivity_n(p, SEA_EMIS_AUTO, NULL, N, n, &f, v, es, err)
                                : sea_emissivity_n(p, SEA_EMIS_AUTO, NULL, N, n, &f, v, e, err);
            if (st != SEA_OK)
                return st;
            for (size_t k = 0; k < n; k++) {
                if (pol != NULL) {
                    pnum[k].i += w * wy[j] * es[k].i;
                    pnum[k].q += w * wy[j] * es[k].q;
                    pnum[k].u += w * wy[j] * es[k].u;
                } else {
                    num[k] += w * wy[j] * e[k];
                }
            }
            den += w * wy[j];
        }
    }
    if (!(den > 0.0))
        return pol != NULL ? sea_polar_emissivity_n(p, SEA_EMIS_AUTO, NULL, N, n, sub, v, pol, err)
                           : sea_emissivity_n(p, SEA_EMIS_AUTO, NULL, N, n, sub, v, out, err);
    for (size_t k = 0; k < n; k++) {
        if (pol != NULL)
            pol[k] = (sea_stokes){ pnum[k].i / den, pnum[k].q / den, pnum[k].u / den };
        else
            out[k] = num[k] / den;
    }
    return SEA_OK;
}

sea_status sea_polar_emissivity_two_scale(const sea_optics *p, double complex N,
                                          const sea_slope_stats *sub, sea_cov2 res, sea_dir v,
                                          sea_stokes *out, sea_error *err)
{
    sea_status st = two_scale_check(sub, res, v, err);
    if (st != SEA_OK)
        return st;
    gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc(TS_NX);
    gsl_integration_fixed_workspace *gh =
        gsl_integration_fixed_alloc(gsl_integration_fixed_hermite, TS_NY, 0.0, 0.5, 0.0, 0.0);
    if (gl == NULL || gh == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the two-scale quadrature");
    else
        st = two_scale_n(p, &N, 1, sub, res, v, gl, TS_NX, gh, TS_NY, NULL, out, err);
    if (gl != NULL)
        gsl_integration_glfixed_table_free(gl);
    if (gh != NULL)
        gsl_integration_fixed_free(gh);
    return st;
}

/* ------------------------------------------------------------------ table
 *
 * What two scales add to a facet's one-scale eps~.  A facet of statistics
 * (m, C) holds the fraction f = (tr C - tr C_h) / (tr C_LR - tr C_h) of the
 * split's resolved band (C_h: the waves shorter than the split; f = 1 low
 * resolution, 0 a facet no larger than the split): two scales give it
 * facets of slopes N(m, f (C_LR - C_h)) each of covariance C_h, against the
 * one scale (m, C_h + f (C_LR - C_h)).  The addition is a function of the
 * standardised visibility margin of the one-scale facet along the view,
 * z = (cot theta - m_X) / s_X (s_X the spread of its slopes along the view
 * azimuth), to within a few tenths of a percent of itself whatever the
 * mean slope that makes it (8 m/s, 4 um, f = 0.34: 0.04937-0.05088 at
 * z = 0 from 72 to 88 deg with m_X from 0.33 to 0.035, and m_Y moving it by
 * 0.3 %), and smoothly of f, of the view's azimuth to the wind, of the
 * view zenith and of the index.  It is tabulated on those axes: z from
 * TAB_Z0 in steps TAB_DZ (beyond, the addition is below 1e-5 and none is
 * added), f^(1/4) on TAB_NF nodes (the addition climbs steeply from
 * f = 0 near the visibility limit), the azimuth on TAB_NP nodes of [0, 90]
 * deg (even at both ends), theta on TAB_NT nodes 10 deg apart to 90 deg,
 * per index; Catmull-Rom in each (linear ghost nodes at the ends of z, f
 * and theta).  A facet below the table's z (its mean plane turned away
 * from the view, which a ray meeting the surface never finds at its hit
 * point; blends and footprint averages can) is computed directly.  A
 * theta row of z nodes is computed when a query first needs it (TAB_NF x
 * TAB_NP nodes, each sea_emissivity_n and two scales at orders 12 x 4,
 * within 1e-4 of 24 x 8), by one thread while the others wait. */
enum { TAB_NZ = 31, TAB_NF = 9, TAB_NP = 3, TAB_NT = 9, TAB_NY2 = 2 };
/* the second m_Y node: the addition is even in m_Y and within 0.1 % of
 * quadratic to it (1.3 % of itself at 0.4 near the visibility limit) */
static const double TAB_MY = 0.4, TAB_MY_MAX = 0.6;
static const double TAB_Z0 = -0.25, TAB_DZ = 0.125;
#define TAB_T0 (10.0 * M_PI / 180.0)
#define TAB_DT (10.0 * M_PI / 180.0)
enum { TAB_ROWS = TAB_NT * TAB_NZ, TAB_ROW = TAB_NF * TAB_NP * TAB_NY2 };

struct sea_two_scale_table {
    const sea_optics *p;
    size_t n;
    double complex N[SEA_SCENE_BAND_MAX];
    sea_cov2 split_sub, total;
    double wind_dir;
    double cw, sw; /* cos and sin of wind_dir */
    double tr_h, tr_lr;
    gsl_integration_glfixed_table *gl, *gl_ref;
    gsl_integration_fixed_workspace *gh, *gh_ref;
    /* ready[row]: row (it, iz) computed (read with acquire, written with
     * release after its values) */
    int ready[TAB_ROWS];
    /* delta[(((row TAB_NF + jf) TAB_NP + ip) TAB_NY2 + iy) n + k] */
    double *delta;
    /* The polarisation's additions (sea_two_scale_polar_delta), made on
     * the first query that needs them: Q at
     * pdelta[(((row TAB_NF + jf) PTAB_NP + ip) PTAB_NY + iy) 2n + k], U n
     * further; pready[row TAB_NF + jf] as ready, per share of the band. */
    double *pdelta;
    int pready[TAB_ROWS * TAB_NF];
};

void sea_two_scale_table_free(sea_two_scale_table *t)
{
    if (t == NULL)
        return;
    if (t->gl != NULL) /* GSL's _free does not take NULL */
        gsl_integration_glfixed_table_free(t->gl);
    if (t->gl_ref != NULL)
        gsl_integration_glfixed_table_free(t->gl_ref);
    if (t->gh != NULL)
        gsl_integration_fixed_free(t->gh);
    if (t->gh_ref != NULL)
        gsl_integration_fixed_free(t->gh_ref);
    free(t->delta);
    free(t->pdelta);
    free(t);
}

sea_status sea_two_scale_table_alloc(const sea_optics *p, const double complex *N, size_t n,
                                     sea_cov2 split_sub, sea_cov2 total, double wind_dir,
                                     sea_two_scale_table **out, sea_error *err)
{
    *out = NULL;
    const double tr_h = split_sub.xx + split_sub.yy, tr_lr = total.xx + total.yy;
    int finite = n >= 1 && n <= SEA_SCENE_BAND_MAX;
    for (size_t k = 0; finite && k < n; k++)
        finite = isfinite(creal(N[k])) && isfinite(cimag(N[k]));
    if (!(tr_h > 0.0 && tr_lr > tr_h) || !isfinite(tr_lr) || !isfinite(wind_dir) || !finite)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "two-scale table: the split's covariance (trace %g) must be below the "
                        "total's (%g), both positive and finite, and 1 to %d finite indices",
                        tr_h, tr_lr, SEA_SCENE_BAND_MAX);
    sea_two_scale_table *t = calloc(1, sizeof *t);
    if (t == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the two-scale table");
    t->p = p;
    t->n = n;
    memcpy(t->N, N, n * sizeof *N);
    t->split_sub = split_sub;
    t->total = total;
    t->wind_dir = wind_dir;
    t->cw = cos(wind_dir);
    t->sw = sin(wind_dir);
    t->tr_h = tr_h;
    t->tr_lr = tr_lr;
    t->delta = malloc((size_t)TAB_ROWS * TAB_ROW * n * sizeof *t->delta);
    t->gl = gsl_integration_glfixed_table_alloc(TAB_NX);
    t->gl_ref = gsl_integration_glfixed_table_alloc(TS_NX);
    t->gh = gsl_integration_fixed_alloc(gsl_integration_fixed_hermite, TAB_NY, 0.0, 0.5, 0.0, 0.0);
    t->gh_ref = gsl_integration_fixed_alloc(gsl_integration_fixed_hermite, TS_NY, 0.0, 0.5, 0.0,
                                            0.0);
    if (t->delta == NULL || t->gl == NULL || t->gl_ref == NULL || t->gh == NULL ||
        t->gh_ref == NULL) {
        sea_two_scale_table_free(t);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the two-scale table");
    }
    *out = t;
    return SEA_OK;
}

/* A facet of mean slope m holding f of the resolved band: the band's
 * share res it carries, its one-scale statistics and its facets'. */
static void delta_stats(const sea_two_scale_table *t, sea_vec2 m, double f, sea_cov2 *res,
                        sea_slope_stats *one, sea_slope_stats *sub)
{
    const sea_cov2 hs = t->split_sub, tot = t->total;
    *res = (sea_cov2){ f * (tot.xx - hs.xx), f * (tot.yy - hs.yy), f * (tot.xy - hs.xy) };
    *one = (sea_slope_stats){ m, { hs.xx + res->xx, hs.yy + res->yy, hs.xy + res->xy } };
    *sub = (sea_slope_stats){ m, hs };
}

/* two_scale_n for the table's indices at the reference's orders (ref) or
 * the table's. */
static sea_status table_two_scale(const sea_two_scale_table *t, int ref,
                                  const sea_slope_stats *sub, sea_cov2 res, sea_dir v,
                                  double *out, sea_stokes *pol, sea_error *err)
{
    return ref ? two_scale_n(t->p, t->N, t->n, sub, res, v, t->gl_ref, TS_NX, t->gh_ref, TS_NY,
                             out, pol, err)
               : two_scale_n(t->p, t->N, t->n, sub, res, v, t->gl, TAB_NX, t->gh, TAB_NY, out,
                             pol, err);
}

/* The addition for a facet of mean slope m seen from v whose covariance
 * holds f of the resolved band, by two scales at the given orders. */
static sea_status delta_at(const sea_two_scale_table *t, sea_vec2 m, double f, sea_dir v,
                           int ref, double *out, sea_error *err)
{
    sea_cov2 res;
    sea_slope_stats one, sub;
    delta_stats(t, m, f, &res, &one, &sub);
    double e1[SEA_SCENE_BAND_MAX], e2[SEA_SCENE_BAND_MAX];
    sea_status st = sea_emissivity_n(t->p, SEA_EMIS_AUTO, NULL, t->N, t->n, &one, v, e1, err);
    if (st == SEA_OK)
        st = table_two_scale(t, ref, &sub, res, v, e2, NULL, err);
    if (st != SEA_OK)
        return st;
    for (size_t k = 0; k < t->n; k++)
        out[k] = e2[k] - e1[k];
    return SEA_OK;
}

/* The share f of the resolved band that a facet of covariance C holds
 * (from the traces), and the spread along the view azimuth phi of the
 * covariance the addition is defined with, C_h + f (C_LR - C_h): the
 * facet's own covariance enters its one-scale emissivity, and only its
 * trace the addition. */
static void facet_axes(const sea_two_scale_table *t, const sea_cov2 *C, double phi, double *sX,
                       double *f)
{
    const double ff = (C->xx + C->yy - t->tr_h) / (t->tr_lr - t->tr_h);
    *f = isfinite(ff) ? fmin(fmax(ff, 0.0), 1.0) : 0.0;
    const sea_cov2 hs = t->split_sub, tot = t->total;
    const sea_cov2 Cf = { hs.xx + *f * (tot.xx - hs.xx), hs.yy + *f * (tot.yy - hs.yy),
                          hs.xy + *f * (tot.xy - hs.xy) };
    const double c = cos(phi), s = sin(phi);
    *sX = sqrt(fmax(Cf.xx * c * c + 2.0 * Cf.xy * s * c + Cf.yy * s * s, 0.0));
}

/* The mean slope of a table node's facet: seen from zenith th and azimuth
 * phi, holding f of the resolved band, at margin z (the m_X that puts it
 * there) and m_Y across the view. */
static sea_vec2 node_facet(const sea_two_scale_table *t, double f, double phi, double th,
                           double z, double mY)
{
    const sea_cov2 hs = t->split_sub, tot = t->total;
    const sea_cov2 C = { hs.xx + f * (tot.xx - hs.xx), hs.yy + f * (tot.yy - hs.yy),
                         hs.xy + f * (tot.xy - hs.xy) };
    double sX, fc;
    facet_axes(t, &C, phi, &sX, &fc);
    const double mX = 1.0 / tan(th) - z * sX;
    const double c = cos(phi), s = sin(phi);
    return (sea_vec2){ mX * c - mY * s, mX * s + mY * c };
}

/* Row (it, iz): every f, azimuth and m_Y node; the node's facet has the
 * m_X that puts it at z. */
static sea_status table_row(sea_two_scale_table *t, int row, sea_error *err)
{
    const int it = row / TAB_NZ, iz = row % TAB_NZ;
    const double th = fmin(TAB_T0 + it * TAB_DT, 89.9 * M_PI / 180.0);
    const double z = TAB_Z0 + iz * TAB_DZ;
    for (int jf = 0; jf < TAB_NF; jf++) {
        const double u = (double)jf / (TAB_NF - 1), u2 = u * u, f = u2 * u2;
        for (int ip = 0; ip < TAB_NP; ip++)
            for (int iy = 0; iy < TAB_NY2; iy++) {
                double *out = &t->delta[((((size_t)row * TAB_NF + (size_t)jf) * TAB_NP +
                                          (size_t)ip) * TAB_NY2 + (size_t)iy) * t->n];
                if (jf == 0) { /* f = 0: one scale */
                    for (size_t k = 0; k < t->n; k++)
                        out[k] = 0.0;
                    continue;
                }
                const double phi = t->wind_dir + M_PI / 2.0 * ip / (TAB_NP - 1);
                const sea_vec2 m = node_facet(t, f, phi, th, z, iy * TAB_MY);
                sea_status st = delta_at(t, m, f, (sea_dir){ th, phi }, 0, out, err);
                if (st != SEA_OK)
                    return st;
            }
    }
    return SEA_OK;
}

/* The entries ids[0..nid) of a lazily filled table computed by fill (its
 * row, or a cell of the polarisation's), ready[id] set after each: the
 * first caller that needs one computing it while the others wait. */
typedef sea_status (*table_fill_fn)(sea_two_scale_table *t, int id, sea_error *err);
static sea_status table_fill(sea_two_scale_table *t, int *ready, const int *ids, int nid,
                             table_fill_fn fill, sea_error *err)
{
    sea_status st = SEA_OK;
    for (int a = 0; a < nid && st == SEA_OK; a++) {
        if (__atomic_load_n(&ready[ids[a]], __ATOMIC_ACQUIRE))
            continue;
#pragma omp critical(sea_two_scale_row)
        {
            if (!__atomic_load_n(&ready[ids[a]], __ATOMIC_ACQUIRE)) {
                st = fill(t, ids[a], err);
                if (st == SEA_OK)
                    __atomic_store_n(&ready[ids[a]], 1, __ATOMIC_RELEASE);
            }
        }
    }
    return st;
}

size_t sea_two_scale_table_rows(const sea_two_scale_table *t)
{
    size_t n = 0;
    for (int r = 0; r < TAB_ROWS; r++)
        n += __atomic_load_n(&t->ready[r], __ATOMIC_ACQUIRE) != 0;
    return n;
}

/* Catmull-Rom nodes and weights of x in [0, nn - 1]; past an end the
 * ghost node is the linear extrapolation 2 f_0 - f_1 (ghost = 1: folded
 * into the weights) or, mirrored (ghost = 0), the node inside. */
static void cr_axis(double x, int nn, int mirror, int k[4], double w[4])
{
    int i = (int)floor(x);
    if (i < 0)
        i = 0;
    if (i > nn - 2)
        i = nn - 2;
    sea_catmull_rom(fmin(fmax(x - i, 0.0), 1.0), w);
    for (int a = 0; a < 4; a++)
        k[a] = i - 1 + a;
    if (k[0] < 0) {
        if (mirror) {
            k[0] = 1;
        } else {
            w[1] += 2.0 * w[0];
            w[2] -= w[0];
            w[0] = 0.0;
            k[0] = 0;
        }
    }
    if (k[3] > nn - 1) {
        if (mirror) {
            k[3] = nn - 2;
        } else {
            w[2] += 2.0 * w[3];
            w[1] -= w[3];
            w[3] = 0.0;
            k[3] = nn - 1;
        }
    }
}

/* Linear interpolation: nodes k[0] = i and k[1] = i + 1 of x in [0, nn -
 * 1] (clamped), weights 1 - f and f. */
static void lin_axis(double x, int nn, int k[2], double w[2])
{
    int i = (int)floor(x);
    if (i < 0)
        i = 0;
    if (i > nn - 2)
        i = nn - 2;
    const double f = fmin(fmax(x - i, 0.0), 1.0);
    k[0] = i;
    k[1] = i + 1;
    w[0] = 1.0 - f;
    w[1] = f;
}

sea_status sea_two_scale_delta(sea_two_scale_table *t, sea_dir v, const sea_slope_stats *st,
                               double *out, sea_error *err)
{
    for (size_t k = 0; k < t->n; k++)
        out[k] = 0.0;
    double sX, f;
    facet_axes(t, &st->cov, v.phi, &sX, &f);
    if (!(f > 0.0) || !(v.theta > 0.0 && v.theta < M_PI / 2.0) || !(sX > 0.0))
        return SEA_OK; /* one scale, nadir, no spread, or not a number: nothing to add */
    const double mX = st->mean.x * cos(v.phi) + st->mean.y * sin(v.phi);
    const double z = (1.0 / tan(v.theta) - mX) / sX;
    const double xz = (z - TAB_Z0) / TAB_DZ;
    if (xz >= TAB_NZ - 1)
        return SEA_OK; /* far from the visibility limit: below 1e-5 */
    const double mY_abs = fabs(-st->mean.x * sin(v.phi) + st->mean.y * cos(v.phi));
    if (!(xz >= 0.0) || mY_abs > TAB_MY_MAX) /* turned away, or far across: directly */
        return delta_at(t, st->mean, f, v, 0, out, err);
    int kz[4], kf[4], kp[2], kt[2];
    double wz[4], wf[4], wp[2], wt[2];
    cr_axis(xz, TAB_NZ, 0, kz, wz);
    cr_axis(sqrt(sqrt(f)) * (TAB_NF - 1), TAB_NF, 0, kf, wf);
    /* the azimuth to the wind in [0, 90] deg: the table is even about both
     * ends (the sea's slopes are symmetric about the wind and across it) */
    const double phi = fabs(remainder(v.phi - t->wind_dir, M_PI));
    /* the addition changes by a few percent of itself over the azimuth and
     * the zenith, smoothly: linear in both (Catmull-Rom in each, 4 times the
     * reads, was closer to the reference by at most 4e-5 of the radiance on
     * the images of seabake(1), REFERENCE) */
    lin_axis(fmin(phi, M_PI / 2.0) / (M_PI / 2.0) * (TAB_NP - 1), TAB_NP, kp, wp);
    lin_axis((v.theta - TAB_T0) / TAB_DT, TAB_NT, kt, wt);
    int rows[8], nr = 0;
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 4; b++)
            if (wt[a] != 0.0 && wz[b] != 0.0)
                rows[nr++] = kt[a] * TAB_NZ + kz[b];
    sea_status status = table_fill(t, t->ready, rows, nr, table_row, err);
    if (status != SEA_OK)
        return status;
    /* m_Y: linear in m_Y^2 between the two nodes (extrapolated beyond) */
    const double mY = -st->mean.x * sin(v.phi) + st->mean.y * cos(v.phi);
    const double y = mY * mY / (TAB_MY * TAB_MY), wy[2] = { 1.0 - y, y };
    const size_t n = t->n;
    /* each (f, azimuth) node's place in a row, found once */
    size_t off[4][2];
    for (int c = 0; c < 4; c++)
        for (int d = 0; d < 2; d++)
            off[c][d] = ((size_t)kf[c] * TAB_NP + (size_t)kp[d]) * TAB_NY2 * n;
    for (int a = 0; a < 2; a++) {
        if (wt[a] == 0.0)
            continue;
        for (int b = 0; b < 4; b++) {
            if (wz[b] == 0.0)
                continue;
            const double wab = wt[a] * wz[b];
            const double *row = &t->delta[(size_t)(kt[a] * TAB_NZ + kz[b]) * TAB_ROW * n];
            for (int c = 0; c < 4; c++) {
                const double wabc = wab * wf[c];
                if (wabc == 0.0)
                    continue;
                for (int d = 0; d < 2; d++) {
                    if (wp[d] == 0.0)
                        continue;
                    const double wcd = wabc * wp[d];
                    const double *q = row + off[c][d];
                    for (int e = 0; e < TAB_NY2; e++, q += n) {
                        const double w = wcd * wy[e];
                        /* one index (a wavelength, not a band): without the
                         * loop, 92 million fewer instructions of 6.7 billion
                         * on mast.ini at 480 x 270 */
                        if (n == 1)
                            out[0] += w * q[0];
                        else
                            for (size_t k = 0; k < n; k++)
                                out[k] += w * q[k];
                    }
                }
            }
        }
    }
    return SEA_OK;
}

/* The addition at the facet's own statistics by quadrature, at the
 * reference's orders (ref) or the table's. */
static sea_status delta_own(const sea_two_scale_table *t, sea_dir v, const sea_slope_stats *st,
                            int ref, double *out, sea_error *err)
{
    for (size_t k = 0; k < t->n; k++)
        out[k] = 0.0;
    double sX, f;
    facet_axes(t, &st->cov, v.phi, &sX, &f);
    if (!(f > 0.0) || !(v.theta > 0.0 && v.theta < M_PI / 2.0))
        return SEA_OK;
    return delta_at(t, st->mean, f, v, ref, out, err);
}

sea_status sea_two_scale_delta_exact(const sea_two_scale_table *t, sea_dir v,
                                     const sea_slope_stats *st, double *out, sea_error *err)
{
    return delta_own(t, v, st, 1, out, err);
}

sea_status sea_two_scale_delta_direct(const sea_two_scale_table *t, sea_dir v,
                                      const sea_slope_stats *st, double *out, sea_error *err)
{
    return delta_own(t, v, st, 0, out, err);
}

/* ---------------------------------------------------- the polarisation
 *
 * What two scales add to a facet's one-hit Stokes e_Q and e_U (the
 * facets' Stokes emissivities averaged as two_scale averages the
 * emissivity, against the one scale).  On the axes of the emissivity's
 * table (z, f, theta), but not folded: U changes sign with the mirror
 * image of the view (the resolved band's cross term and m_Y together), and
 * varies with the azimuth to the wind mainly as sin 2phi, which the
 * emissivity's three linear nodes over [0, 90] deg would miss by 30 %.  So
 * the azimuth to the wind takes PTAB_NP = 6 nodes over the period of 180
 * deg, read by trigonometric interpolation (harmonics of 2phi to the
 * third: 4 nodes left 3.5e-4, 8 no better than 6), and m_Y the nodes -0.4,
 * 0 and 0.4 (Catmull-Rom, linear ghosts; beyond 0.6: directly; 5 nodes
 * 0.2 apart halved the worst error, 1.1e-4, at 1.3 times the cost). */
enum { PTAB_NP = 6, PTAB_NY = 3, PTAB_ROW = TAB_NF * PTAB_NP * PTAB_NY };
static const double PTAB_DY = 0.4; /* m_Y from -0.4 */

/* The additions to e_Q (q) and e_U (u) for a facet of mean slope m seen
 * from v whose covariance holds f of the resolved band, by two scales at
 * the reference's orders (ref) or the table's. */
static sea_status polar_delta_at(const sea_two_scale_table *t, sea_vec2 m, double f, sea_dir v,
                                 int ref, double *q, double *u, sea_error *err)
{
    sea_cov2 res;
    sea_slope_stats one, sub;
    delta_stats(t, m, f, &res, &one, &sub);
    sea_stokes e1[SEA_SCENE_BAND_MAX], e2[SEA_SCENE_BAND_MAX];
    sea_status st = sea_polar_emissivity_n(t->p, SEA_EMIS_AUTO, NULL, t->N, t->n, &one, v, e1, err);
    if (st == SEA_OK)
        st = table_two_scale(t, ref, &sub, res, v, NULL, e2, err);
    if (st != SEA_OK)
        return st;
    for (size_t k = 0; k < t->n; k++) {
        q[k] = e2[k].q - e1[k].q;
        u[k] = e2[k].u - e1[k].u;
    }
    return SEA_OK;
}

/* Share jf of row (it, iz) of the polarisation's table, cell = row TAB_NF
 * + jf: every azimuth and m_Y node, the node's facet at z as in
 * table_row.  Cells are computed as queries need them (table_fill): a
 * scene's facets hold few shares (low resolution only f = 1), so most are
 * never computed. */
static sea_status polar_cell(sea_two_scale_table *t, int cell, sea_error *err)
{
    if (t->pdelta == NULL) /* (the first cell: made under table_fill's lock) */
        t->pdelta = malloc((size_t)TAB_ROWS * PTAB_ROW * 2 * t->n * sizeof *t->pdelta);
    if (t->pdelta == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the two-scale table's "
                        "polarisation");
    const int row = cell / TAB_NF, jf = cell % TAB_NF;
    const int it = row / TAB_NZ, iz = row % TAB_NZ;
    const double th = fmin(TAB_T0 + it * TAB_DT, 89.9 * M_PI / 180.0);
    const double z = TAB_Z0 + iz * TAB_DZ;
    const size_t n = t->n;
    const double uu = (double)jf / (TAB_NF - 1), u2 = uu * uu, f = u2 * u2;
    for (int ip = 0; ip < PTAB_NP; ip++)
        for (int iy = 0; iy < PTAB_NY; iy++) {
            double *q = &t->pdelta[(((size_t)cell * PTAB_NP + (size_t)ip) * PTAB_NY + (size_t)iy) *
                                   2 * n];
            if (jf == 0) { /* f = 0: one scale */
                for (size_t k = 0; k < 2 * n; k++)
                    q[k] = 0.0;
                continue;
            }
            const double phi = t->wind_dir + M_PI * ip / PTAB_NP;
            const sea_vec2 m = node_facet(t, f, phi, th, z, (iy - (PTAB_NY - 1) / 2) * PTAB_DY);
            sea_status st = polar_delta_at(t, m, f, (sea_dir){ th, phi }, 0, q, q + n, err);
            if (st != SEA_OK)
                return st;
        }
    return SEA_OK;
}


sea_status sea_two_scale_polar_delta(sea_two_scale_table *t, sea_dir v, const sea_slope_stats *st,
                                     int how, double *q, double *u, sea_error *err)
{
    const size_t n = t->n;
    for (size_t k = 0; k < n; k++)
        q[k] = u[k] = 0.0;
    double sX, f;
    facet_axes(t, &st->cov, v.phi, &sX, &f);
    if (!(f > 0.0) || !(v.theta > 0.0 && v.theta < M_PI / 2.0))
        return SEA_OK; /* one scale, nadir, or not a number: nothing to add */
    if (how != 0)
        return polar_delta_at(t, st->mean, f, v, how == 2, q, u, err);
    if (!(sX > 0.0))
        return SEA_OK;
    const double mX = st->mean.x * cos(v.phi) + st->mean.y * sin(v.phi);
    const double z = (1.0 / tan(v.theta) - mX) / sX;
    const double xz = (z - TAB_Z0) / TAB_DZ;
    if (xz >= TAB_NZ - 1)
        return SEA_OK; /* far from the visibility limit */
    const double mY = -st->mean.x * sin(v.phi) + st->mean.y * cos(v.phi);
    if (!(xz >= 0.0) || fabs(mY) > TAB_MY_MAX) /* turned away, or far across: directly */
        return polar_delta_at(t, st->mean, f, v, 0, q, u, err);
    int kz[4], kf[4], kt[2], ky[4];
    double wz[4], wf[4], wt[2], wp[PTAB_NP], wy[4];
    cr_axis(xz, TAB_NZ, 0, kz, wz);
    cr_axis(sqrt(sqrt(f)) * (TAB_NF - 1), TAB_NF, 0, kf, wf);
    lin_axis((v.theta - TAB_T0) / TAB_DT, TAB_NT, kt, wt);
    /* the azimuth: trigonometric interpolation in a = 2 (phi - wind) on
     * the nodes a_i = i pi / 2: (1 + 2 cos(a - a_i) + cos 2(a - a_i)) / 4 */
    const double a = 2.0 * (v.phi - t->wind_dir);
    for (int i = 0; i < PTAB_NP; i++) {
        const double d = a - 2.0 * M_PI * i / PTAB_NP;
        double w = 1.0 + cos(0.5 * PTAB_NP * d);
        for (int h = 1; h < PTAB_NP / 2; h++)
            w += 2.0 * cos(h * d);
        wp[i] = w / PTAB_NP;
    }
    /* m_Y: Catmull-Rom on its nodes (linear ghosts) */
    cr_axis(mY / PTAB_DY + (PTAB_NY - 1) / 2, PTAB_NY, 0, ky, wy);
    int cells[32], nc = 0;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 4; j++)
            for (int c = 0; c < 4; c++)
                if (wt[i] != 0.0 && wz[j] != 0.0 && wf[c] != 0.0)
                    cells[nc++] = (kt[i] * TAB_NZ + kz[j]) * TAB_NF + kf[c];
    sea_status status = table_fill(t, t->pready, cells, nc, polar_cell, err);
    if (status != SEA_OK)
        return status;
    for (int i = 0; i < 2; i++) {
        if (wt[i] == 0.0)
            continue;
        for (int j = 0; j < 4; j++) {
            if (wz[j] == 0.0)
                continue;
            const double *row = &t->pdelta[(size_t)(kt[i] * TAB_NZ + kz[j]) * PTAB_ROW * 2 * n];
            for (int c = 0; c < 4; c++) {
                const double wc = wt[i] * wz[j] * wf[c];
                if (wc == 0.0)
                    continue;
                for (int d = 0; d < PTAB_NP; d++)
                    for (int e = 0; e < 4; e++) {
                        const double w = wc * wp[d] * wy[e];
                        if (w == 0.0)
                            continue;
                        const double *x =
                            row + (((size_t)kf[c] * PTAB_NP + (size_t)d) * PTAB_NY + (size_t)ky[e]) *
                                      2 * n;
                        for (size_t k = 0; k < n; k++) {
                            q[k] += w * x[k];
                            u[k] += w * x[n + k];
                        }
                    }
            }
        }
    }
    return SEA_OK;
}
