/* render.c - radiance images of a scene (Eq 23; seabake-model(7), RADIANCE).
 * Top-down: the scene, the sensor (sea_camera), the multiresolution sea
 * (multires.c: levels, one realisation per frame, what each pixel sees),
 * the optics of what each pixel sees (Eq 7, 13: emissivity toward the
 * sensor, reflectivity sun -> sensor), the radiance (Eq 23) over the
 * spectral samples of the band. */
#include "config.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_integration.h>

#include "seabake.h"
#include "internal.h"

/* Largest automatic number of spectral samples. */
enum { SAMPLES_AUTO_MAX = 64 };

/* The band radiance's table for the brightness temperature: ln T uniform
 * over 30-6000 K. */
enum { SEA_TB_N = 256 };
static const double SEA_TB_LNT0 = 3.4011973816621555;          /* ln 30 */
static const double SEA_TB_STEP = 5.2983173665480363 / 255.0; /* ln(6000/30) / (N - 1) */

struct sea_view {
    sea_scene sc;
    sea_camera cam;
    sea_multires *mr;
    sea_water *water;
    size_t nsamp;
    double *wl, *wt, *esun, *lsky;
    double *lsea;    /* blackbody radiance at the sea's temperature, per sample */
    double *pa, *pb; /* per sample, B(lambda, T) = pa / expm1(pb / T) */
    double *lair;    /* ... at the air's ([atmosphere] air_temperature), 0 without */
    sea_sky sky;     /* the sky's model over the samples (radiance: lsky, lair or a table's
                        profile) */
    /* tables ([sky] model = table, [atmosphere] table): the grids, and per
     * sample their profiles on the grid's x (zenith or range) */
    sea_grid *sky_grid, *atm_grid;
    size_t sky_nx, atm_nx;
    double *sky_x, *sky_v;             /* sky_v[k sky_nx + i] */
    double *atm_x, *atm_tau, *atm_path; /* [k atm_nx + i] */
    double atm_range_max;
    double air_L;    /* sum_k w_k lair[k]: the band's B(T_air), SI */
    double complex *N;
    double wsum;
    /* the band's ln radiance at ln T = TB_LNT0 + k TB_STEP (several samples):
     * the brightness temperature's first guess */
    double tb_lnL[SEA_TB_N];
    sea_view_choices choices;
    /* the facets' emissivity: the default model or the scene's choices
     * (its two-scale table, the sea around, where second hits matter) */
    sea_model *model;
    int bake_lean; /* a bake computes its surfaces' finest bounds from the nodes
                      whatever their size (sea_view_set_bake_lean) */
};

sea_status sea_image_alloc(int width, int height, sea_image *img, sea_error *err)
{
    memset(img, 0, sizeof *img);
    if (width < 1 || height < 1)
        return sea_fail(err, SEA_ERR_DOMAIN, "image size %d x %d must be positive", width, height);
    const size_t n = (size_t)width * (size_t)height;
    sea_status st = sea_check_size(n, 5 * sizeof(float), "image", err);
    if (st != SEA_OK)
        return st;
    img->width = width;
    img->height = height;
    float **planes[5] = { &img->radiance, &img->temperature, &img->level, &img->emissivity,
                          &img->reflectivity };
    for (int i = 0; i < 5; i++) {
        *planes[i] = calloc(n, sizeof(float));
        if (*planes[i] == NULL) {
            sea_image_free(img);
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %d x %d image", width,
                            height);
        }
    }
    return SEA_OK;
}

void sea_image_free(sea_image *img)
{
    if (img == NULL)
        return;
    free(img->radiance);
    free(img->temperature);
    free(img->level);
    free(img->emissivity);
    free(img->reflectivity);
    memset(img, 0, sizeof *img);
}

void sea_view_free(sea_view *r)
{
    if (r == NULL)
        return;
    sea_multires_free(r->mr);
    sea_water_free(r->water);
    sea_model_free(r->model);
    free(r->wl);
    free(r->wt);
    free(r->esun);
    free(r->lsky);
    free(r->lsea);
    free(r->pa);
    free(r->pb);
    free(r->lair);
    free(r->N);
    sea_grid_free(r->sky_grid);
    sea_grid_free(r->atm_grid);
    free(r->sky_x);
    free(r->sky_v);
    free(r->atm_x);
    free(r->atm_tau);
    free(r->atm_path);
    free(r);
}

size_t sea_view_levels(const sea_view *r, const sea_clip_level **levels)
{
    return sea_multires_levels(r->mr, levels);
}

size_t sea_view_samples(const sea_view *r, const double **wavelength, const double **weight)
{
    *wavelength = r->wl;
    *weight = r->wt;
    return r->nsamp;
}

/* Linear interpolation of the response curve, 0 outside it (flat 1 when
 * there is none). */
static double response_at(const sea_response *resp, double wl)
{
    if (resp == NULL || resp->n == 0)
        return 1.0;
    if (wl < resp->wavelength[0] || wl > resp->wavelength[resp->n - 1])
        return 0.0;
    const size_t lo = sea_interval_of(resp->wavelength, resp->n, wl), hi = lo + 1;
    const double a = (wl - resp->wavelength[lo]) / (resp->wavelength[hi] - resp->wavelength[lo]);
    return (1.0 - a) * resp->value[lo] + a * resp->value[hi];
}

/* The tables' profiles at k spectral samples (sky: one column, atmosphere:
 * two, k x rows doubles each) are checked against the memory the process
 * may use before any is allocated, as the plan is (check_plan in
 * multires.c): they grow with rows x samples, and 5e5 ranges at 512
 * samples took 4.1 GB for a 64 x 48 image.  The message names the keys. */
static sea_status check_tables(const sea_view *r, size_t k, sea_error *err)
{
    const double GiB = 1073741824.0, per = (double)k * (double)sizeof(double);
    const double sky = r->sky_grid != NULL ? per * (double)r->sky_nx : 0.0;
    const double atm = r->atm_grid != NULL ? 2.0 * per * (double)r->atm_nx : 0.0;
    const double avail = (double)sea_memory_available();
    if (sky + atm <= avail)
        return SEA_OK;
    const sea_scene *sc = &r->sc;
    char what[2 * SEA_SCENE_PATH_MAX + 200];
    if (sky > 0.0 && atm > 0.0)
        snprintf(what, sizeof what,
                 "[sky] table %s (%zu zenith angles) and [atmosphere] table %s (%zu ranges, two "
                 "columns)",
                 sc->sky_table_file, r->sky_nx, sc->atmosphere_table_file, r->atm_nx);
    else if (sky > 0.0)
        snprintf(what, sizeof what, "[sky] table %s (%zu zenith angles)", sc->sky_table_file,
                 r->sky_nx);
    else
        snprintf(what, sizeof what, "[atmosphere] table %s (%zu ranges, two columns)",
                 sc->atmosphere_table_file, r->atm_nx);
    return sea_fail(err, SEA_ERR_NOMEM,
                    "%s: at %zu spectral samples its rows need %.3g GiB (rows x samples x 8 "
                    "bytes a column); this process may use %.3g GiB (allowed: fewer rows or "
                    "[sensor] samples)",
                    what, k, (sky + atm) / GiB, avail / GiB);
}

/* Spectral samples: one wavelength, or a Gauss-Legendre rule of k nodes on
 * the band weighted by the response. */
static sea_status set_samples(sea_view *r, size_t k, const sea_response *resp, sea_error *err)
{
    sea_status tst = check_tables(r, k, err);
    if (tst != SEA_OK)
        return tst;
    free(r->wl);
    free(r->wt);
    free(r->esun);
    free(r->lsky);
    free(r->lsea);
    free(r->pa);
    free(r->pb);
    free(r->lair);
    free(r->N);
    r->wl = malloc(k * sizeof(double));
    r->wt = malloc(k * sizeof(double));
    r->esun = malloc(k * sizeof(double));
    r->lsky = malloc(k * sizeof(double));
    r->lsea = malloc(k * sizeof(double));
    r->pa = malloc(k * sizeof(double));
    r->pb = malloc(k * sizeof(double));
    r->lair = malloc(k * sizeof(double));
    r->N = malloc(k * sizeof(double complex));
    if (!r->wl || !r->wt || !r->esun || !r->lsky || !r->lsea || !r->pa || !r->pb || !r->lair ||
        !r->N)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu spectral samples", k);
    r->nsamp = k;
    const sea_scene *sc = &r->sc;
    if (sc->wavelength > 0.0) {
        r->wl[0] = sc->wavelength;
        r->wt[0] = 1.0;
    } else {
        gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc(k);
        if (gl == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu-point rule", k);
        for (size_t i = 0; i < k; i++) {
            double x, w;
            gsl_integration_glfixed_point(sc->band_min, sc->band_max, i, &x, &w, gl);
            r->wl[i] = x;
            r->wt[i] = w * response_at(resp, x);
        }
        gsl_integration_glfixed_table_free(gl);
    }
    r->wsum = 0.0;
    for (size_t i = 0; i < k; i++) {
        sea_status st = sea_water_index(r->water, r->wl[i], &r->N[i], err);
        if (st != SEA_OK)
            return st;
        r->esun[i] = sc->sun_irradiance >= 0.0
                         ? sc->sun_irradiance
                         : sc->sun_transmittance * sc->sun_solid_angle *
                               sea_planck_radiance(r->wl[i], sc->sun_temperature);
        r->lsky[i] = sc->sky_radiance >= 0.0 ? sc->sky_radiance
                                             : sea_planck_radiance(r->wl[i], sc->sky_temperature);
        r->lsea[i] = sea_planck_radiance(r->wl[i], sc->temperature);
        sea_planck_coefficients(r->wl[i], &r->pa[i], &r->pb[i]);
        r->lair[i] = isnan(sc->air_temperature)
                         ? 0.0
                         : sea_planck_radiance(r->wl[i], sc->air_temperature);
        r->wsum += r->wt[i];
    }
    r->air_L = 0.0;
    for (size_t i = 0; i < k; i++)
        r->air_L += r->wt[i] * r->lair[i];
    r->sky = (sea_sky){ sc->sky_model, sc->sky_zenith_emissivity,
                        sc->sky_model == SEA_SKY_CLEAR ? r->lair : r->lsky, 0, NULL };
    /* the tables' profiles at each sample's wavelength */
    const struct {
        const sea_grid *g;
        size_t nx, cols;
        double **x, **v[2];
    } tab[2] = { { r->sky_grid, r->sky_nx, 1, &r->sky_x, { &r->sky_v, NULL } },
                 { r->atm_grid, r->atm_nx, 2, &r->atm_x, { &r->atm_tau, &r->atm_path } } };
    for (int t = 0; t < 2; t++) {
        if (tab[t].g == NULL)
            continue;
        const size_t nx = tab[t].nx;
        for (size_t c = 0; c < tab[t].cols; c++) {
            free(*tab[t].v[c]);
            *tab[t].v[c] = malloc(k * nx * sizeof(double));
            if (*tab[t].v[c] == NULL)
                return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the tables");
            for (size_t i = 0; i < k; i++) {
                sea_status st = sea_grid_profile(tab[t].g, r->wl[i], c, *tab[t].x,
                                                 *tab[t].v[c] + i * nx, err);
                if (st != SEA_OK)
                    return st;
            }
        }
    }
    if (r->sky_grid != NULL)
        r->sky = (sea_sky){ SEA_SKY_TABLE, NAN, r->sky_v, r->sky_nx, r->sky_x };
    if (!(r->wsum > 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN, "the response is zero over the whole band");
    for (int j = 0; j < SEA_TB_N; j++) {
        const double T = exp(SEA_TB_LNT0 + j * SEA_TB_STEP);
        double L = 0.0;
        for (size_t i = 0; i < k; i++)
            L += r->wt[i] * r->pa[i] / expm1(r->pb[i] / T);
        r->tb_lnL[j] = log(L); /* (-inf where L underflows: below every pixel's) */
    }
    return SEA_OK;
}

sea_emis_rule sea_view_emis_rule(double emis_scale, const sea_slope_stats *st, sea_dir v)
{
    return sea_model_emis_rule(emis_scale, st, v);
}

sea_view_choices sea_view_choices_of(const sea_view *r)
{
    return r->choices;
}

/* The sun's disc is not resolved where its glint's radiance is certainly
 * below this fraction of the tolerance of the pixel's other radiance (so
 * below 1e-6 of it at the default tolerance). */
static const double SEA_GLINT_NEGLIGIBLE = 1e-3;

/* Radiance of a facet with stats st seen from obs, sun from sun (or none),
 * summed over the samples with their weights; band means of emissivity and
 * reflectivity through *e and *rho. */
static sea_status facet_radiance(const sea_view *r, const sea_slope_stats *st, sea_dir obs,
                                 sea_dir sun, int sun_up, double *L, double *e, double *rho,
                                 double *Lk, sea_error *err)
{
    double sl = 0.0, se = 0.0, sr = 0.0;
    double eps_all[SEA_SCENE_BAND_MAX], rr_all[SEA_SCENE_BAND_MAX];
    /* An isotropic sky (Eq 23) is seen in 1 - eps, with reflections >= 2
     * as well: what the mirror rays do not meet again.  Any other sky is
     * integrated over the facets' mirror rays (Eq 22, sea_emissivity_sky_n). */
    const int directional = r->sc.sky_model != SEA_SKY_ISOTROPIC;
    double ksky_all[SEA_SCENE_BAND_MAX];
    sea_status s = sea_model_emissivity(r->model, st, obs, eps_all, ksky_all, err);
    if (s != SEA_OK)
        return s;
    /* the sky the facets reflect, per sample */
    double sky_all[SEA_SCENE_BAND_MAX];
    for (size_t i = 0; i < r->nsamp; i++)
        sky_all[i] = directional ? ksky_all[i] : (1.0 - eps_all[i]) * r->lsky[i];
    if (sun_up) {
        /* the glint is negligible where its radiance is below 1e-3 tolerance
         * of what the pixel has without it, at every sample */
        double negligible = INFINITY;
        for (size_t i = 0; i < r->nsamp; i++) {
            const double other = eps_all[i] * r->lsea[i] + sky_all[i];
            negligible = r->esun[i] > 0.0
                             ? fmin(negligible, SEA_GLINT_NEGLIGIBLE * r->sc.tolerance * other /
                                                    r->esun[i])
                             : negligible;
        }
        sea_reflectivity_disc_n(sea_model_optics(r->model), r->N, r->nsamp, st, sun, obs,
                                r->sc.sun_radius,
                                0.1 * r->sc.tolerance, isfinite(negligible) ? negligible : 0.0,
                                rr_all);
    }
    for (size_t i = 0; i < r->nsamp; i++) {
        const double eps = eps_all[i];
        const double rr = sun_up ? rr_all[i] : 0.0;
        const double Li = rr * r->esun[i] + sky_all[i] + eps * r->lsea[i];
        if (Lk != NULL)
            Lk[i] = Li;
        sl += r->wt[i] * Li;
        se += r->wt[i] * eps;
        sr += r->wt[i] * rr;
    }
    *L = sl;
    *e = se / r->wsum;
    *rho = sr / r->wsum;
    return SEA_OK;
}

/* Brightness temperature of a (band) radiance: the T whose blackbody gives
 * the same weighted sum, by safeguarded Newton iterations on ln T.  Each
 * iteration takes one expm1 and one division per sample (B = a / E,
 * E = expm1(x), x = b / T, dB/dT = B x (1 + 1/E) / T), the wavelength's
 * powers found once. */
static double band_temperature(const sea_view *r, double L)
{
    if (r->nsamp == 1)
        return sea_planck_brightness_temperature(r->wl[0], L / r->wt[0]);
    double lo = 1.0, hi = 1e5;
    double T;
    int from_table = 0;
    const double lnL = log(L);
    if (lnL > r->tb_lnL[1] && lnL < r->tb_lnL[SEA_TB_N - 2]) {
        /* the table: the interval holding ln L (within [1, N - 3], as ln L
         * lies between the second and the next-to-last entries), then the
         * cubic through four points (ln T as a function of ln L), within
         * about 1e-7 */
        const int a = (int)sea_interval_of(r->tb_lnL, SEA_TB_N, lnL);
        double lnT = 0.0;
        for (int p = a - 1; p <= a + 2; p++) {
            double w = 1.0;
            for (int q = a - 1; q <= a + 2; q++)
                if (q != p)
                    w *= (lnL - r->tb_lnL[q]) / (r->tb_lnL[p] - r->tb_lnL[q]);
            lnT += w * (SEA_TB_LNT0 + p * SEA_TB_STEP);
        }
        T = exp(lnT);
        from_table = 1;
    } else {
        T = sea_planck_brightness_temperature(r->wl[r->nsamp / 2], L / r->wsum);
    }
    if (!(T > lo && T < hi))
        T = 300.0;
    for (int it = 0; it < 100; it++) {
        double f = -L, df = 0.0;
        const double inv_T = 1.0 / T;
        for (size_t i = 0; i < r->nsamp; i++) {
            const double x = r->pb[i] * inv_T, inv_E = 1.0 / expm1(x), B = r->pa[i] * inv_E;
            f += r->wt[i] * B;
            df += r->wt[i] * (B * x * (1.0 + inv_E) * inv_T);
        }
        if (f > 0.0)
            hi = T;
        else
            lo = T;
        double Tn = T - f / df;
        if (!(Tn > lo && Tn < hi))
            Tn = 0.5 * (lo + hi);
        if (fabs(Tn - T) <= 1e-9 * T)
            return Tn;
        /* Newton's error after a step is (f''/2f') e^2, here at most
         * (x / 2) (e / T)^2 T with x = b / T the largest (x <= 200 down to
         * 30 K at 3 um): from the table's start a step of 1e-6 T or less
         * leaves at most 1e-10 T, so it needs no second evaluation */
        if (it == 0 && from_table && fabs(Tn - T) <= 1e-6 * T)
            return Tn;
        T = Tn;
    }
    return T;
}

/* Radiance unit of the images: per um for one wavelength (SI is per m). */
static double radiance_unit(const sea_view *r)
{
    return r->nsamp == 1 && r->sc.wavelength > 0.0 ? 1e-6 : 1.0;
}

void sea_view_band(const sea_view *r, sea_band *out)
{
    out->n = r->nsamp;
    out->wavelength = r->wl;
    out->weight = r->wt;
    out->unit = radiance_unit(r);
}

double sea_view_brightness_temperature(const sea_view *r, double radiance)
{
    return radiance > 0.0 ? band_temperature(r, radiance / radiance_unit(r)) : 0.0;
}

sea_status sea_view_facet_optics(const sea_view *r, const sea_slope_stats *st, sea_dir obs,
                                   sea_dir sun, sea_facet_optics *out, sea_error *err)
{
    double L, e, rho;
    sea_status s = facet_radiance(r, st, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho, NULL, err);
    if (s != SEA_OK)
        return s;
    out->emissivity = e;
    out->reflectivity = rho;
    out->radiance = L * radiance_unit(r);
    out->temperature = band_temperature(r, L);
    out->seen = out->radiance;
    return SEA_OK;
}

/* The extinction of the air, 1/m: 0 without [atmosphere]. */
static double air_extinction(const sea_view *r)
{
    return isnan(r->sc.air_temperature) ? 0.0 : r->sc.extinction;
}

/* What the sensor receives of a sea point at range (m) whose radiance is
 * L (SI, summed over the samples with their weights; Lk per sample, read
 * with a table only): Beer-Lambert, tau L + (1 - tau) B(T_air) with
 * tau = exp(-extinction range); or per sample the table's transmittance
 * x Lk + path radiance at the range (linear in range, its ends held
 * beyond); L itself without air. */
static double through_air(const sea_view *r, double L, const double *Lk, double range)
{
    const double ext = air_extinction(r);
    if (ext > 0.0) {
        const double tau = exp(-ext * range);
        return tau * L + (1.0 - tau) * r->air_L;
    }
    if (r->atm_grid == NULL)
        return L;
    double s = 0.0;
    for (size_t k = 0; k < r->nsamp; k++) {
        const double *tk = &r->atm_tau[k * r->atm_nx], *pk = &r->atm_path[k * r->atm_nx];
        s += r->wt[k] * (sea_profile_at(r->atm_x, tk, r->atm_nx, range) * Lk[k] +
                         sea_profile_at(r->atm_x, pk, r->atm_nx, range));
    }
    return s;
}

int sea_view_has_air(const sea_view *r)
{
    return air_extinction(r) > 0.0 || r->atm_grid != NULL;
}

sea_status sea_view_facet_seen(const sea_view *r, const sea_slope_stats *st, sea_dir obs,
                                 sea_dir sun, double range, sea_facet_optics *out,
                                 sea_error *err)
{
    double L, e, rho;
    double Lk[SEA_SCENE_BAND_MAX];
    sea_status s = facet_radiance(r, st, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho,
                                  r->atm_grid != NULL ? Lk : NULL, err);
    if (s != SEA_OK)
        return s;
    const double unit = radiance_unit(r);
    out->emissivity = e;
    out->reflectivity = rho;
    out->radiance = L * unit;
    out->temperature = band_temperature(r, L);
    out->seen = sea_view_has_air(r) ? through_air(r, L, Lk, range) * unit : out->radiance;
    return SEA_OK;
}

double sea_view_sky_toward(const sea_view *r, double cos_zenith)
{
    double L = 0.0;
    for (size_t k = 0; k < r->nsamp; k++)
        L += r->wt[k] * sea_sky_radiance(&r->sky, k, cos_zenith);
    return L * radiance_unit(r);
}

const sea_scene *sea_view_scene(const sea_view *r)
{
    return &r->sc;
}

void sea_view_set_bake_lean(sea_view *r, int lean)
{
    r->bake_lean = lean != 0;
}

int sea_view_bake_lean(const sea_view *r)
{
    return r->bake_lean;
}

const sea_camera *sea_view_camera(const sea_view *r)
{
    return &r->cam;
}

const sea_waves *sea_view_waves(const sea_view *r)
{
    return sea_multires_waves(r->mr);
}

sea_moments sea_view_lr_moments(const sea_view *r)
{
    return sea_multires_lr_moments(r->mr);
}

const sea_multires *sea_view_multires(const sea_view *r)
{
    return r->mr;
}

void sea_view_drop_pixels(sea_view *r)
{
    sea_multires_drop_pixels(r->mr);
}

/* ------------------------------------------------------------- prepare */

/* The facets' model for the samples set (sea_model_alloc), replacing any
 * earlier one: the scene's choices, or (simple) one hit and one scale, for
 * choosing the samples.  reflections = auto skips the second hit where it
 * moves a pixel's radiance by less than SEA_AUTO_SKIP of the tolerance: the
 * radiance's relative change per unit of emissivity is at most the sea's
 * blackbody against the sky's (its zenith's and horizon's) over the least
 * radiance a pixel of emissivity 0.8 or more can have (where second hits
 * can be skipped the views are within 70 deg of the facets: water's
 * emissivity is 0.87 or more there, 3-14 um). */
static sea_status set_model(sea_view *r, const sea_spectrum *spec, const sea_slope_stats *lr,
                            int simple, sea_error *err)
{
    const sea_scene *sc = &r->sc;
    sea_model_free(r->model);
    r->model = NULL;
    sea_model_params mp;
    sea_model_params_default(&mp);
    mp.shadowing = sc->shadowing;
    mp.scales = simple ? 1 : sc->scales;
    mp.reflections = simple ? 1 : sc->reflections;
    mp.tolerance = sc->tolerance;
    mp.reference = simple ? 0 : sc->reference;
    mp.method = sc->emissivity_method;
    double dmax = 0.0, lmin = 0.0;
    for (size_t k = 0; k < r->nsamp; k++) {
        const double s1 = sea_sky_radiance(&r->sky, k, 1.0), s0 = sea_sky_radiance(&r->sky, k, 0.0);
        dmax += r->wt[k] * fmax(fabs(r->lsea[k] - s1), fabs(r->lsea[k] - s0));
        lmin += r->wt[k] * (0.8 * r->lsea[k] + 0.2 * fmin(s1, s0));
    }
    mp.sensitivity = lmin > 0.0 ? dmax / lmin : 1e300;
    /* the finest sub-facet covariance in view: the waves shorter than the
     * finest level's (sub-)facets */
    const sea_clip_level *cl;
    const size_t nl = sea_multires_levels(r->mr, &cl);
    double L = INFINITY;
    for (size_t l = 0; l < nl; l++)
        if (!cl[l].low_res)
            L = fmin(L, cl[l].facet / (double)(1 << cl[l].sub_n));
    sea_cov2 fine = lr->cov;
    if (isfinite(L)) {
        sea_status st = sea_spectrum_slope_cov(spec, M_PI / L, &fine, err);
        if (st != SEA_OK)
            return st;
    }
    return sea_model_alloc(&mp, spec, lr, &fine, r->N, r->nsamp, &r->sky, &r->model, err);
}

sea_status sea_view_alloc(const sea_scene *sc, sea_view **out, sea_error *err)
{
    *out = NULL;
    sea_view *r = calloc(1, sizeof *r);
    if (r == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    r->sc = *sc;
    r->choices.tolerance = sc->tolerance;
    r->choices.emis_scale = sc->emissivity_method == SEA_EMIS_AUTO && !sc->reference
                                ? sea_model_emis_scale(sc->tolerance)
                                : 1.0;
    sea_status st;
    sea_response resp = { 0, NULL, NULL };
#define TRY(expr)                                                                                 \
    do {                                                                                          \
        if ((st = (expr)) != SEA_OK)                                                              \
            goto fail;                                                                            \
    } while (0)
    /* the sensor, then the sea it sees */
    TRY(sea_camera_init(sc->sensor_x, sc->sensor_y, sc->altitude, sc->look_zenith, sc->look_azimuth,
                        sc->roll, sc->hfov, sc->width, sc->height, sc->earth, &r->cam,
                        err));
    TRY(sea_multires_alloc(sc, &r->cam, &r->mr, err));
    const sea_clip_level *lv;
    const size_t nlev = sea_multires_levels(r->mr, &lv);
    for (size_t l = 0; l < nlev; l++)
        r->choices.sub_skipped += lv[l].sub_skipped;
    const sea_waves *waves = sea_multires_waves(r->mr);
    if (waves != NULL) {
        const sea_waves_params *wp = sea_waves_params_of(waves);
        r->choices.bins_per_octave = wp->bins_per_octave;
        r->choices.directions = wp->kind == SEA_WAVES_SINUSOIDS ? wp->directions : 0;
        r->choices.wave_count = sea_waves_count(waves);
    }
    /* the optics */
    TRY(sc->water_file[0] ? sea_water_load(sc->water_file, sc->salinity, &r->water, err)
                          : sea_water_alloc(sc->water_table, sc->salinity,
                                            &r->water, err));
    /* the sky's and the air's tables */
    double x_max, w_min, w_max;
    if (sc->sky_model == SEA_SKY_TABLE) {
        TRY(sea_sky_table_load(sc->sky_table_file, &r->sky_grid, err));
        sea_grid_axes(r->sky_grid, &r->sky_nx, &x_max, &w_min, &w_max);
        if ((r->sky_x = malloc(r->sky_nx * sizeof(double))) == NULL)
            TRY(sea_fail(err, SEA_ERR_NOMEM, "out of memory for the sky table"));
    }
    if (sc->atmosphere_table_file[0] != '\0') {
        TRY(sea_atmosphere_table_load(sc->atmosphere_table_file, &r->atm_grid, err));
        sea_grid_axes(r->atm_grid, &r->atm_nx, &x_max, &w_min, &w_max);
        r->atm_range_max = x_max;
        if ((r->atm_x = malloc(r->atm_nx * sizeof(double))) == NULL)
            TRY(sea_fail(err, SEA_ERR_NOMEM, "out of memory for the atmosphere table"));
    }

    /* spectral samples */
    if (sc->wavelength <= 0.0 && sc->response_file[0])
        TRY(sea_response_load(sc->response_file, &resp, err));
    sea_spectrum spec;
    TRY(sea_scene_spectrum(sc, &spec, err));
    const sea_moments lrm = sea_multires_lr_moments(r->mr);
    const sea_slope_stats lrs = sea_moments_stats(&lrm);
    size_t k = 1;
    if (sc->wavelength <= 0.0) {
        if (sc->band_samples > 0) {
            k = (size_t)sc->band_samples;
        } else {
            /* as few as the tolerance allows: double the rule until the
             * low-resolution radiance at the image centre settles (a band's
             * spectral detail: one hit and one scale tell it) */
            const double sun_vec[3] = { sin(sc->sun_zenith) * cos(sc->sun_azimuth),
                                        sin(sc->sun_zenith) * sin(sc->sun_azimuth),
                                        cos(sc->sun_zenith) };
            sea_pixel_geom g;
            sea_camera_pixel(&r->cam, 0.5 * sc->width, 0.5 * sc->height, &g);
            const sea_dir obs = g.hit ? g.obs : (sea_dir){ sc->look_zenith, 0.0 };
            const sea_dir sun = sea_camera_local_dir(&g, sun_vec);
            double prev = NAN;
            for (k = 2; k <= SAMPLES_AUTO_MAX; k *= 2) {
                double L, e, rho;
                TRY(set_samples(r, k, &resp, err));
                TRY(set_model(r, &spec, &lrs, 1, err));
                TRY(facet_radiance(r, &lrs, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho,
                                   NULL, err));
                if (fabs(L - prev) <= sc->tolerance * fabs(L))
                    break;
                prev = L;
            }
            if (k > SAMPLES_AUTO_MAX)
                k = SAMPLES_AUTO_MAX;
            /* the reference: twice as many, as far as they go */
            if (sc->reference && k < SAMPLES_AUTO_MAX)
                k *= 2;
        }
    }
    TRY(set_samples(r, k, &resp, err));
    TRY(set_model(r, &spec, &lrs, 0, err));
    r->choices.two_scale_split = sea_model_split_wavelength(r->model);
#undef TRY
    sea_response_free(&resp);
    *out = r;
    return SEA_OK;
fail:
    sea_response_free(&resp);
    sea_view_free(r);
    return st;
}

/* --------------------------------------------------------------- frame */

sea_status sea_view_render_frame(const sea_view *r, double t, sea_image *img,
                            sea_progress_fn progress, void *ctx, sea_error *err)
{
    return sea_view_render_rows(r, t, 0, 1, img, progress, ctx, err);
}

/* What every pixel of a frame shares. */
typedef struct {
    double facet[SEA_CLIP_MAX_LEVELS]; /* facet size of each level, m */
    double sun_vec[3];
    double sky_L, unit, ext;
    float sky_T;
} pixel_consts;

/* Pixel (i, j) of img from what it sees, s: the sky, or the sea's radiance
 * through the air. */
static sea_status shade_pixel(const sea_view *r, const pixel_consts *pc,
                              const sea_multires_sample *s, size_t i, size_t j, sea_image *img,
                              sea_error *err)
{
    const sea_scene *sc = &r->sc;
    const size_t q = j * (size_t)sc->width + i;
    if (!s->hit) {
        double Ls = pc->sky_L;
        float Ts = pc->sky_T;
        if (sc->sky_model != SEA_SKY_ISOTROPIC) { /* the sky toward the ray */
            double d[3];
            sea_camera_ray(&r->cam, (double)i + 0.5, (double)j + 0.5, d);
            Ls = 0.0;
            for (size_t k = 0; k < r->nsamp; k++)
                Ls += r->wt[k] * sea_sky_radiance(&r->sky, k, d[2]);
            Ts = (float)band_temperature(r, Ls);
        }
        img->radiance[q] = (float)(Ls * pc->unit);
        img->temperature[q] = Ts;
        img->level[q] = 0.0f;
        img->emissivity[q] = img->reflectivity[q] = 0.0f;
        return SEA_OK;
    }
    sea_pixel_geom g;
    memcpy(g.normal, s->normal, sizeof g.normal);
    const sea_dir sun = sea_camera_local_dir(&g, pc->sun_vec);
    const sea_slope_stats ss = sea_moments_stats(&s->moments);
    double L, e, rho;
    double Lk[SEA_SCENE_BAND_MAX];
    sea_status st = facet_radiance(r, &ss, s->obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho,
                                   r->atm_grid != NULL ? Lk : NULL, err);
    /* the air along the range met (through_air, shared with the bake's
     * maps: sea_view_facet_seen); the table's transmittance and path
     * radiance must reach that range */
    if (st == SEA_OK && pc->ext == 0.0 && r->atm_grid != NULL && s->range > r->atm_range_max)
        st = sea_fail(err, SEA_ERR_DOMAIN,
                      "pixel (%zu, %zu) meets the sea at %.6g m, beyond the "
                      "[atmosphere] table's last range_m %.6g (allowed: a table that "
                      "reaches the farthest sea in view)",
                      i, j, s->range, r->atm_range_max);
    if (pc->ext > 0.0 || (st == SEA_OK && r->atm_grid != NULL))
        L = through_air(r, L, Lk, s->range);
    if (st == SEA_OK && !(isfinite(L) && L > 0.0 && isfinite(rho)))
        st = sea_fail(err, SEA_ERR_NUMERIC, "radiance %g at pixel (%zu, %zu)", L, i, j);
    if (st != SEA_OK)
        return st;
    img->radiance[q] = (float)(L * pc->unit);
    img->temperature[q] = (float)band_temperature(r, L);
    img->level[q] = (float)pc->facet[s->level];
    img->emissivity[q] = (float)e;
    img->reflectivity[q] = (float)rho;
    return SEA_OK;
}

static sea_status render_rows(const sea_view *r, const sea_multires_frame *given, double t,
                              int row0, int step, sea_image *img, sea_progress_fn progress,
                              void *ctx, sea_error *err);

sea_status sea_view_render_rows(const sea_view *r, double t, int row0, int step, sea_image *img,
                           sea_progress_fn progress, void *ctx, sea_error *err)
{
    return render_rows(r, NULL, t, row0, step, img, progress, ctx, err);
}

sea_status sea_view_render_frame_in(const sea_view *r, const sea_multires_frame *f, double t,
                               sea_image *img, sea_error *err)
{
    return render_rows(r, f, t, 0, 1, img, NULL, NULL, err);
}

sea_status sea_view_check_image(const sea_view *r, const sea_image *img, sea_error *err)
{
    const sea_scene *sc = &r->sc;
    if (img->width != sc->width || img->height != sc->height)
        return sea_fail(err, SEA_ERR_DOMAIN, "image %d x %d does not match the scene's %d x %d",
                        img->width, img->height, sc->width, sc->height);
    return SEA_OK;
}

/* Row blocks row0, row0 + step, ... of an image of H rows (blocks of
 * SEA_RENDER_ROW_BLOCK rows): how many (none when row0 is past the last),
 * and the rows they hold (*nrows, set when there is a block). */
static size_t row_blocks(size_t H, size_t row0, size_t step, size_t *nrows)
{
    const size_t B = SEA_RENDER_ROW_BLOCK;
    const size_t nb_all = (H + B - 1) / B;
    const size_t nblk = row0 < nb_all ? (nb_all - row0 + step - 1) / step : 0;
    *nrows = 0;
    for (size_t jb = 0; jb < nblk; jb++) {
        const size_t j_lo = (row0 + jb * step) * B;
        *nrows += (j_lo + B < H ? j_lo + B : H) - j_lo;
    }
    return nblk;
}

/* What every pixel of r's frames shares: the levels' facet sizes, the
 * sun, the sky's radiance and temperature, the radiance unit and the
 * air's extinction. */
static void pixel_consts_of(const sea_view *r, pixel_consts *pc)
{
    const sea_scene *sc = &r->sc;
    const sea_clip_level *lv;
    const size_t nlev = sea_multires_levels(r->mr, &lv);
    memset(pc, 0, sizeof *pc);
    for (size_t l = 0; l < nlev; l++)
        pc->facet[lv[l].level] = lv[l].facet;
    pc->sun_vec[0] = sin(sc->sun_zenith) * cos(sc->sun_azimuth);
    pc->sun_vec[1] = sin(sc->sun_zenith) * sin(sc->sun_azimuth);
    pc->sun_vec[2] = cos(sc->sun_zenith);
    for (size_t i = 0; i < r->nsamp; i++)
        pc->sky_L += r->wt[i] * r->lsky[i];
    pc->unit = radiance_unit(r); /* per um */
    pc->sky_T = (float)band_temperature(r, pc->sky_L);
    /* the air between the sensor and the sea: Beer-Lambert along the range
     * met, the path radiating (1 - tau) B(T_air) (through_air) */
    pc->ext = air_extinction(r);
}

/* sea_view_render_rows from the frame given (of r's multiresolution sea at t),
 * or from one of its own (NULL). */
static sea_status render_rows(const sea_view *r, const sea_multires_frame *given, double t,
                              int row0, int step, sea_image *img, sea_progress_fn progress,
                              void *ctx, sea_error *err)
{
    const sea_scene *sc = &r->sc;
    sea_status st = sea_view_check_image(r, img, err);
    if (st != SEA_OK)
        return st;
    if (sea_time_check(t, err) != SEA_OK)
        return SEA_ERR_DOMAIN;
    if (row0 < 0 || step < 1)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "row blocks from %d every %d (allowed: first block >= 0, step >= 1)", row0,
                        step);
    const size_t H = (size_t)sc->height, B = SEA_RENDER_ROW_BLOCK;
    size_t nrows;
    const size_t nblk = row_blocks(H, (size_t)row0, (size_t)step, &nrows);
    if (nblk == 0)
        return SEA_OK;
    sea_multires_frame *own = NULL;
    if (given == NULL && (st = sea_multires_frame_alloc(r->mr, t, NULL, NULL, &own, err)) != SEA_OK)
        return st;
    const sea_multires_frame *f = given != NULL ? given : own;
    pixel_consts pc;
    pixel_consts_of(r, &pc);
    const size_t W = (size_t)sc->width;
    size_t rows_done = 0;
    int failed = 0, cancelled = 0, nomem = 0;
    sea_error first = { { 0 } };
    /* Each block bottom row first: a pixel's rays start their march where
     * the rays of the pixel below met the sea, when the ordering allows
     * (sea_multires_pixel_hinted); the block's lowest row starts afresh,
     * so the image does not depend on who renders which block. */
#pragma omp parallel
    {
        sea_multires_hint *hints = malloc(2 * W * sizeof *hints);
        if (hints == NULL) {
#pragma omp critical(sea_view_error)
            {
                if (!failed) {
                    sea_fail(&first, SEA_ERR_NOMEM, "out of memory for the rays of two rows");
                    nomem = 1;
                }
                failed = 1;
            }
        }
#pragma omp for schedule(dynamic, 1)
        for (size_t jb = 0; jb < nblk; jb++) {
            const size_t j_lo = ((size_t)row0 + jb * (size_t)step) * B;
            const size_t j_hi = j_lo + B < H ? j_lo + B : H;
            for (size_t j = j_hi; j-- > j_lo;) {
                if (failed)
                    break;
                const sea_multires_hint *below = j + 1 < j_hi ? hints + ((j + 1) % 2) * W : NULL;
                sea_multires_hint *top = hints + (j % 2) * W;
                for (size_t i = 0; i < W; i++) {
                    sea_multires_sample s;
                    sea_multires_pixel_hinted(f, (int)i, (int)j, below != NULL ? &below[i] : NULL,
                                              &top[i], &s);
                    sea_error e1;
                    if (shade_pixel(r, &pc, &s, i, j, img, &e1) != SEA_OK) {
#pragma omp critical(sea_view_error)
                        {
                            if (!failed)
                                first = e1;
                            failed = 1;
                        }
                        break;
                    }
                }
                if (progress != NULL) {
                    int stop = 0;
#pragma omp critical(sea_view_progress)
                    {
                        /* any thread, one at a time: a thread that does no row
                         * must not keep a stop from being seen */
                        rows_done++;
                        stop = progress(ctx, (double)rows_done / (double)nrows) != 0;
                    }
                    if (stop) {
#pragma omp critical(sea_view_error)
                        {
                            if (!failed) {
                                sea_fail(&first, SEA_ERR_CANCELLED,
                                         "render cancelled at row %zu of %zu", j, H);
                                cancelled = 1;
                            }
                            failed = 1;
                        }
                    }
                }
            }
        }
        free(hints);
    }
    sea_multires_frame_free(own);
    if (failed) {
        if (err != NULL)
            *err = first;
        return cancelled ? SEA_ERR_CANCELLED : nomem ? SEA_ERR_NOMEM : SEA_ERR_NUMERIC;
    }
    return SEA_OK;
}
