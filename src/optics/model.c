/* model.c - the default model of a facet's emissivity, the one the scenes,
 * the calculators and the library share (seabake-model(7), THE DEFAULT
 * MODEL): correlated shadowing, two scales, and a second surface hit where
 * it changes the result by more than a small fraction of the tolerance,
 * each computed only as finely as the tolerance asks; or the same model
 * with every approximation replaced by its exact form (the reference).
 *
 * What it holds: the quadrature plan, the two-scale table (what two scales
 * add, at the band's middle index), the sea around (what the mirror rays
 * meet, tabulated over their directions) and, with reflections = auto, the
 * cells of view zenith and mean slope where a second hit may matter. */
#include "config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "seabake.h"
#include "internal.h"

/* reflections = auto: the second hit's largest addition to the emissivity,
 * for a view zenith on SKIP_NT nodes 0, 5, .. 90 deg and a facet mean slope
 * |m| on SKIP_NM nodes SKIP_M[] (any azimuth of m and of the view; the
 * finest sub-facet covariance and low resolution), each cell marked where
 * it may change a result by more than SEA_AUTO_SKIP of the tolerance. */
enum { SKIP_NT = 19, SKIP_NM = 10 };
static const double SKIP_M[SKIP_NM] = { 0.0, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.55, 0.7, 1.0 };
static const double SKIP_DTHETA = 5.0 * M_PI / 180.0;

/* The second hits' orders (sea_around_set_orders) by tolerance: at T <=
 * 1e-3 the split rule's (0.5 n_gl along, at least 3; 0.5 n_gh across, at
 * least 2), within 4.3e-4 of converged on facets of mean slope to twice
 * the resolved spread at 55-90 deg, 3-15 m/s, 4 and 10 um, and within 5.1e-5
 * of the reference on examples/mast.ini; the reference's (2, 6, 1, 4)
 * converged to 1e-7 on the same conditions. */
static const double SEA_MODEL_ORDERS[4] = { 0.5, 3.0, 0.5, 2.0 };
static const double SEA_MODEL_ORDERS_REF[4] = { 2.0, 6.0, 1.0, 4.0 };
/* Finer tolerances (T <= SEA_MODEL_FINE_TOL): the second hits at the full
 * orders (1, 3, 1, 2: within 4e-7 of converged where half was 4.2e-4
 * off), and two scales by quadrature at every facet (the table is within
 * 1.1e-4 to 85 deg, 5.5e-4 at 88 deg, which such a tolerance does not
 * allow). */
static const double SEA_MODEL_FINE_TOL = 2e-4;
/* The two scales' table is read only at T >= SEA_MODEL_TABLE_TOL: its
 * interpolation is up to 7.4e-4 off the quadrature at its own orders (a
 * facet just inside the visibility limit, z = 0.056 at 81 deg, where the
 * addition turns sharply: tests/test_mc.c), which put a pixel of
 * examples/mast.ini 1.12 T from the reference at T = 6.04e-4.  Between
 * the two, each facet's addition by quadrature at the table's orders
 * (within 5.3e-5 of the reference on that image, 4.2 times the CPU). */
static const double SEA_MODEL_TABLE_TOL = 1e-3;
static const double SEA_MODEL_ORDERS_FINE[4] = { 1.0, 3.0, 1.0, 2.0 };

struct sea_model {
    sea_model_params mp;
    sea_optics *optics;
    size_t n;
    double complex *N;
    int has_sky;
    sea_sky sky;
    double emis_scale;
    /* scales = 2 */
    sea_two_scale_table *ts;
    sea_cov2 split_sub, total;
    double split_wavelength;
    /* reflections != 1 or the reference */
    sea_around *around;
    int hits;      /* of the facets a second hit reaches */
    int auto_hits; /* reflections = auto: the skip cells decide */
    unsigned char skip[SKIP_NT][SKIP_NM];
};

void sea_model_params_default(sea_model_params *mp)
{
    mp->shadowing = SEA_SHADOW_CORRELATED;
    mp->scales = 2;
    mp->reflections = SEA_REFLECTIONS_AUTO;
    mp->tolerance = 1e-3;
    mp->reference = 0;
    mp->method = SEA_EMIS_AUTO;
    mp->sensitivity = 1.0;
}

double sea_model_emis_scale(double tol)
{
    return tol <= SEA_TOL_EMIS_T1 ? 1.0 : tol <= SEA_TOL_EMIS_T2 ? 0.65 : 0.5;
}

void sea_model_free(sea_model *m)
{
    if (m == NULL)
        return;
    sea_optics_free(m->optics);
    sea_two_scale_table_free(m->ts);
    sea_around_free(m->around);
    free(m->N);
    free(m);
}

/* E_1 toward v for every index (eps) and with a sky model the sky the facets
 * reflect (ksky). */
static sea_status one_hit(const sea_model *m, const sea_emis_rule *rule,
                          const sea_slope_stats *st, sea_dir v, double *eps, double *ksky,
                          sea_error *err)
{
    return m->has_sky ? sea_emissivity_sky_n(m->optics, m->mp.method, rule, m->N, m->n, st, v, 1,
                                             &m->sky, eps, ksky, err)
                      : sea_emissivity_multi_n(m->optics, m->mp.method, rule, m->N, m->n, st, v,
                                               1, eps, err);
}

/* The cells of reflections = auto: 1 where the second hit's addition to the
 * emissivity, at most over the azimuths of the view (along and across the
 * wind) and of the mean slope (four, relative to the view) and over the
 * covariances fine and low-resolution, times the sensitivity (doubled for
 * safety), exceeds SEA_AUTO_SKIP of the tolerance.  Rows from nadir up,
 * until a row is marked throughout: every row beyond is marked too. */
static sea_status skip_table(sea_model *m, const sea_slope_stats *lr, const sea_cov2 *fine,
                             double wind_dir, sea_error *err)
{
    const double limit = SEA_AUTO_SKIP * m->mp.tolerance;
    const double sens = 2.0 * m->mp.sensitivity;
    const sea_cov2 covs[2] = { *fine, lr->cov };
    int all_from = SKIP_NT;
    for (int it = 0; it < SKIP_NT; it++) {
        int marked = 0;
        for (int im = 0; im < SKIP_NM; im++) {
            double worst = 0.0;
            for (int c = 0; c < 2 && worst * sens <= limit; c++)
                for (int a = 0; a < 2 && worst * sens <= limit; a++) {
                    const sea_dir v = { fmin(it * SKIP_DTHETA, 89.9 * M_PI / 180.0),
                                        wind_dir + a * M_PI / 2.0 };
                    for (int b = 0; b < (im == 0 ? 1 : 4) && worst * sens <= limit; b++) {
                        const double az = v.phi + b * M_PI / 2.0;
                        const sea_slope_stats st = {
                            { SKIP_M[im] * cos(az), SKIP_M[im] * sin(az) }, covs[c]
                        };
                        double e1[SEA_SCENE_BAND_MAX], e2[SEA_SCENE_BAND_MAX];
                        double k1[SEA_SCENE_BAND_MAX], k2[SEA_SCENE_BAND_MAX];
                        sea_status s = one_hit(m, NULL, &st, v, e1, k1, err);
                        if (s == SEA_OK)
                            s = sea_emissivity_around_n(m->optics, SEA_EMIS_AUTO, NULL, m->N,
                                                        m->n, &st, v, m->around,
                                                        m->has_sky ? &m->sky : NULL, e2,
                                                        m->has_sky ? k2 : NULL, err);
                        if (s != SEA_OK)
                            return s;
                        for (size_t k = 0; k < m->n; k++)
                            worst = fmax(worst, fabs(e2[k] - e1[k]));
                    }
                }
            m->skip[it][im] = worst * sens > limit;
            marked += m->skip[it][im];
        }
        if (marked == SKIP_NM) {
            all_from = it;
            break;
        }
    }
    for (int it = all_from; it < SKIP_NT; it++)
        for (int im = 0; im < SKIP_NM; im++)
            m->skip[it][im] = 1;
    return SEA_OK;
}

sea_status sea_model_alloc(const sea_model_params *mp, const sea_spectrum *spectrum,
                           const sea_slope_stats *lr, const sea_cov2 *fine,
                           const double complex *N, size_t n, const sea_sky *sky,
                           sea_model **out, sea_error *err)
{
    *out = NULL;
    if (n < 1 || n > SEA_SCENE_BAND_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "the model: %zu indices (allowed: 1 to %d)", n,
                        SEA_SCENE_BAND_MAX);
    if (mp->scales != 1 && mp->scales != 2)
        return sea_fail(err, SEA_ERR_DOMAIN, "the model: scales %d (allowed: 1, 2)", mp->scales);
    if (mp->scales == 2 && spectrum == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "the model: two scales split a sea spectrum's slopes (allowed: scales 1 "
                        "without a spectrum)");
    if (mp->reflections != SEA_REFLECTIONS_AUTO &&
        (mp->reflections < 1 || mp->reflections > SEA_REFLECTIONS_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "the model: reflections %d (allowed: auto, 1 to %d)",
                        mp->reflections, SEA_REFLECTIONS_MAX);
    if (!(mp->tolerance > 0.0 && mp->tolerance <= 0.1) || !(mp->sensitivity >= 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "the model: tolerance %g (allowed: (0, 0.1]) or sensitivity %g (>= 0)",
                        mp->tolerance, mp->sensitivity);
    sea_status st = sea_slope_stats_check(lr, err);
    if (st != SEA_OK)
        return st;
    sea_model *m = calloc(1, sizeof *m);
    if (m == NULL || (m->N = malloc(n * sizeof *m->N)) == NULL) {
        free(m);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the model");
    }
    m->mp = *mp;
    m->n = n;
    memcpy(m->N, N, n * sizeof *N);
    m->has_sky = sky != NULL && sky->model != SEA_SKY_ISOTROPIC;
    if (m->has_sky)
        m->sky = *sky;
    m->emis_scale =
        mp->method == SEA_EMIS_AUTO && !mp->reference ? sea_model_emis_scale(mp->tolerance) : 1.0;
#define TRY(expr)                                                                                 \
    do {                                                                                          \
        if ((st = (expr)) != SEA_OK)                                                              \
            goto fail;                                                                            \
    } while (0)
    TRY(sea_optics_alloc(&m->optics, err));
    sea_optics_set_shadowing(m->optics, mp->shadowing);
    if (mp->scales == 2) {
        sea_cov2 res, sub;
        double kh;
        TRY(sea_spectrum_split_half(spectrum, 0.0, &kh, &res, &sub, err));
        m->split_sub = sub;
        m->total = (sea_cov2){ sub.xx + res.xx, sub.yy + res.yy, sub.xy + res.xy };
        m->split_wavelength = 2.0 * M_PI / kh;
        /* the table's rows are computed as queries need them: none for
         * the reference, which computes every facet's addition */
        TRY(sea_two_scale_table_alloc(m->optics, N, n, sub, m->total, spectrum->wind_dir, &m->ts,
                                      err));
    }
    if (mp->reflections != 1 || mp->reference) {
        const int R = mp->reflections >= 2 ? mp->reflections : 2;
        TRY(sea_around_alloc(m->optics, lr, N, n, R, m->has_sky ? &m->sky : NULL, mp->reference,
                             &m->around, err));
        const double *o = mp->reference                          ? SEA_MODEL_ORDERS_REF
                          : mp->tolerance <= SEA_MODEL_FINE_TOL ? SEA_MODEL_ORDERS_FINE
                                                                : SEA_MODEL_ORDERS;
        sea_around_set_orders(m->around, o[0], o[1], o[2], o[3]);
        m->hits = R;
        m->auto_hits = mp->reflections == SEA_REFLECTIONS_AUTO && !mp->reference;
        if (m->auto_hits)
            TRY(skip_table(m, lr, fine != NULL ? fine : &lr->cov,
                           spectrum != NULL ? spectrum->wind_dir : 0.0, err));
    }
#undef TRY
    *out = m;
    return SEA_OK;
fail:
    sea_model_free(m);
    return st;
}

const sea_optics *sea_model_optics(const sea_model *m)
{
    return m->optics;
}

double sea_model_split_wavelength(const sea_model *m)
{
    return m->split_wavelength;
}

size_t sea_model_two_scale_rows(const sea_model *m)
{
    return m->ts != NULL ? sea_two_scale_table_rows(m->ts) : 0;
}

int sea_model_hits(const sea_model *m, const sea_slope_stats *st, sea_dir v)
{
    if (m->around == NULL)
        return 1;
    if (!m->auto_hits)
        return m->hits;
    const double xt = v.theta / SKIP_DTHETA;
    const double tau = hypot(st->mean.x, st->mean.y);
    if (!(xt >= 0.0) || !(tau <= SKIP_M[SKIP_NM - 1]))
        return 2;
    int it = (int)xt;
    if (it > SKIP_NT - 2)
        it = SKIP_NT - 2;
    int im = 0;
    while (im < SKIP_NM - 2 && SKIP_M[im + 1] < tau)
        im++;
    return m->skip[it][im] | m->skip[it + 1][im] | m->skip[it][im + 1] | m->skip[it + 1][im + 1]
               ? 2
               : 1;
}

sea_status sea_model_emissivity(const sea_model *m, const sea_slope_stats *st, sea_dir v,
                                double *eps, double *ksky, sea_error *err)
{
    /* a scaled auto rule: the same orders for every index */
    sea_emis_rule rule = { 0, 0 };
    const int scaled = m->mp.method == SEA_EMIS_AUTO && m->emis_scale < 1.0;
    if (scaled && sea_slope_stats_check(st, NULL) == SEA_OK && v.theta >= 0.0 &&
        v.theta < M_PI_2)
        rule = sea_model_emis_rule(m->emis_scale, st, v);
    const sea_emis_rule *r = scaled && rule.n_gl > 0 ? &rule : NULL;
    double kbuf[SEA_SCENE_BAND_MAX];
    double *k = ksky != NULL ? ksky : kbuf;
    sea_status s;
    if (sea_model_hits(m, st, v) >= 2)
        s = sea_emissivity_around_n(m->optics, m->mp.method, r, m->N, m->n, st, v, m->around,
                                    m->has_sky ? &m->sky : NULL, eps, m->has_sky ? k : NULL, err);
    else
        s = one_hit(m, r, st, v, eps, k, err);
    if (s != SEA_OK || m->mp.scales != 2)
        return s;
    /* two scales (seabake-model(7), TWO SCALES): the emissivity gains what
     * the longer waves' facets add; the sky is seen in the rest (a
     * directional sky's reflection scaled by the reflectance's change, so
     * that a uniform sky still closes) */
    double d[SEA_SCENE_BAND_MAX];
    s = m->mp.reference || m->mp.tolerance <= SEA_MODEL_FINE_TOL
            ? sea_two_scale_delta_exact(m->ts, v, st, d, err)
        : m->mp.tolerance < SEA_MODEL_TABLE_TOL ? sea_two_scale_delta_direct(m->ts, v, st, d, err)
                                                 : sea_two_scale_delta(m->ts, v, st, d, err);
    if (s != SEA_OK)
        return s;
    for (size_t i = 0; i < m->n; i++) {
        if (d[i] == 0.0)
            continue;
        const double e0 = eps[i], e1 = fmin(fmax(e0 + d[i], 0.0), 1.0);
        if (m->has_sky && ksky != NULL)
            ksky[i] = e0 < 1.0 ? ksky[i] * (1.0 - e1) / (1.0 - e0) : 0.0;
        eps[i] = e1;
    }
    return SEA_OK;
}

sea_status sea_model_polarisation(const sea_model *m, const sea_slope_stats *st, sea_dir v,
                                  double *q, double *u, sea_error *err)
{
    sea_stokes es[SEA_SCENE_BAND_MAX];
    sea_status s = sea_polar_emissivity_n(m->optics, SEA_EMIS_AUTO, NULL, m->N, m->n, st, v, es,
                                          err);
    if (s != SEA_OK)
        return s;
    for (size_t i = 0; i < m->n; i++) {
        q[i] = es[i].q;
        u[i] = es[i].u;
    }
    double dq[SEA_SCENE_BAND_MAX], du[SEA_SCENE_BAND_MAX];
    if (sea_model_hits(m, st, v) >= 2) {
        /* the second hits by the rule sea_model_emissivity's take */
        sea_emis_rule rule = { 0, 0 };
        const int scaled = m->mp.method == SEA_EMIS_AUTO && m->emis_scale < 1.0;
        if (scaled)
            rule = sea_model_emis_rule(m->emis_scale, st, v);
        if ((s = sea_optics_polar_hits(m->optics, m->mp.method,
                                       scaled && rule.n_gl > 0 ? &rule : NULL, m->N, m->n, st, v,
                                       m->hits, m->around, dq, du, err)) != SEA_OK)
            return s;
        for (size_t i = 0; i < m->n; i++) {
            q[i] += dq[i];
            u[i] += du[i];
        }
    }
    if (m->mp.scales != 2)
        return SEA_OK;
    /* two scales, as sea_model_emissivity reads them by tolerance */
    const int how = m->mp.reference || m->mp.tolerance <= SEA_MODEL_FINE_TOL ? 2
                    : m->mp.tolerance < SEA_MODEL_TABLE_TOL                   ? 1
                                                                              : 0;
    if ((s = sea_two_scale_polar_delta(m->ts, v, st, how, dq, du, err)) != SEA_OK)
        return s;
    for (size_t i = 0; i < m->n; i++) {
        q[i] += dq[i];
        u[i] += du[i];
    }
    return SEA_OK;
}

sea_emis_rule sea_model_emis_rule(double emis_scale, const sea_slope_stats *st, sea_dir v)
{
    sea_emis_rule a = sea_emissivity_auto_rule(st, v);
    if (emis_scale >= 1.0)
        return a;
    a.n_gl = (int)fmax(2.0, ceil(emis_scale * a.n_gl));
    a.n_gh = (int)fmax(1.0, ceil(emis_scale * a.n_gh));
    return a;
}
