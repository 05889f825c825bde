/* radiometry.c - a facet's optics to radiance (radiometry.h): the band's
 * spectral samples and what each sees of the sun, the sky, the sea's and the
 * air's blackbodies (Eq 23; seabake-model(7), RADIANCE), the brightness
 * temperature of a band radiance, the air between the sea and the sensor
 * (THE SKY AND THE AIR). */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_integration.h>

#include "seabake.h"
#include "internal.h"
#include "view/radiometry.h"

/* The brightness temperature's table (SEA_TB_N entries): ln T uniform over
 * 30-6000 K. */
static const double SEA_TB_LNT0 = 3.4011973816621555;          /* ln 30 */
static const double SEA_TB_STEP = 5.2983173665480363 / 255.0; /* ln(6000/30) / (N - 1) */

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
static sea_status check_tables(const sea_radiometry *rad, size_t k, sea_error *err)
{
    const double GiB = 1073741824.0, per = (double)k * (double)sizeof(double);
    const double sky = rad->sky_grid != NULL ? per * (double)rad->sky_nx : 0.0;
    const double atm = rad->atm_grid != NULL ? 2.0 * per * (double)rad->atm_nx : 0.0;
    const double avail = (double)sea_memory_available();
    if (sky + atm <= avail)
        return SEA_OK;
    const sea_scene *sc = rad->sc;
    char what[2 * SEA_SCENE_PATH_MAX + 200];
    if (sky > 0.0 && atm > 0.0)
        snprintf(what, sizeof what,
                 "[sky] table %s (%zu zenith angles) and [atmosphere] table %s (%zu ranges, two "
                 "columns)",
                 sc->sky_table_file, rad->sky_nx, sc->atmosphere_table_file, rad->atm_nx);
    else if (sky > 0.0)
        snprintf(what, sizeof what, "[sky] table %s (%zu zenith angles)", sc->sky_table_file,
                 rad->sky_nx);
    else
        snprintf(what, sizeof what, "[atmosphere] table %s (%zu ranges, two columns)",
                 sc->atmosphere_table_file, rad->atm_nx);
    return sea_fail(err, SEA_ERR_NOMEM,
                    "%s: at %zu spectral samples its rows need %.3g GiB (rows x samples x 8 "
                    "bytes a column); this process may use %.3g GiB (allowed: fewer rows or "
                    "[sensor] samples)",
                    what, k, (sky + atm) / GiB, avail / GiB);
}

/* Spectral samples: one wavelength, or a Gauss-Legendre rule of k nodes on
 * the band weighted by the response. */
sea_status sea_radiometry_samples(sea_radiometry *rad, size_t k, const sea_response *resp,
                                  sea_error *err)
{
    sea_status tst = check_tables(rad, k, err);
    if (tst != SEA_OK)
        return tst;
    free(rad->wl);
    free(rad->wt);
    free(rad->esun);
    free(rad->lsky);
    free(rad->lsea);
    free(rad->pa);
    free(rad->pb);
    free(rad->lair);
    free(rad->N);
    rad->wl = malloc(k * sizeof(double));
    rad->wt = malloc(k * sizeof(double));
    rad->esun = malloc(k * sizeof(double));
    rad->lsky = malloc(k * sizeof(double));
    rad->lsea = malloc(k * sizeof(double));
    rad->pa = malloc(k * sizeof(double));
    rad->pb = malloc(k * sizeof(double));
    rad->lair = malloc(k * sizeof(double));
    rad->N = malloc(k * sizeof(double complex));
    if (!rad->wl || !rad->wt || !rad->esun || !rad->lsky || !rad->lsea || !rad->pa || !rad->pb || !rad->lair ||
        !rad->N)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu spectral samples", k);
    rad->nsamp = k;
    const sea_scene *sc = rad->sc;
    if (sc->wavelength > 0.0) {
        rad->wl[0] = sc->wavelength;
        rad->wt[0] = 1.0;
    } else {
        gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc(k);
        if (gl == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu-point rule", k);
        for (size_t i = 0; i < k; i++) {
            double x, w;
            gsl_integration_glfixed_point(sc->band_min, sc->band_max, i, &x, &w, gl);
            rad->wl[i] = x;
            rad->wt[i] = w * response_at(resp, x);
        }
        gsl_integration_glfixed_table_free(gl);
    }
    rad->wsum = 0.0;
    for (size_t i = 0; i < k; i++) {
        sea_status st = sea_water_index(rad->water, rad->wl[i], &rad->N[i], err);
        if (st != SEA_OK)
            return st;
        rad->esun[i] = sc->sun_irradiance >= 0.0
                         ? sc->sun_irradiance
                         : sc->sun_transmittance * sc->sun_solid_angle *
                               sea_planck_radiance(rad->wl[i], sc->sun_temperature);
        rad->lsky[i] = sc->sky_radiance >= 0.0 ? sc->sky_radiance
                                             : sea_planck_radiance(rad->wl[i], sc->sky_temperature);
        rad->lsea[i] = sea_planck_radiance(rad->wl[i], sc->temperature);
        sea_planck_coefficients(rad->wl[i], &rad->pa[i], &rad->pb[i]);
        rad->lair[i] = isnan(sc->air_temperature)
                         ? 0.0
                         : sea_planck_radiance(rad->wl[i], sc->air_temperature);
        rad->wsum += rad->wt[i];
    }
    rad->air_L = 0.0;
    for (size_t i = 0; i < k; i++)
        rad->air_L += rad->wt[i] * rad->lair[i];
    rad->sky = (sea_sky){ sc->sky_model, sc->sky_zenith_emissivity,
                        sc->sky_model == SEA_SKY_CLEAR ? rad->lair : rad->lsky, 0, NULL };
    /* the tables' profiles at each sample's wavelength */
    const struct {
        const sea_grid *g;
        size_t nx, cols;
        double **x, **v[2];
    } tab[2] = { { rad->sky_grid, rad->sky_nx, 1, &rad->sky_x, { &rad->sky_v, NULL } },
                 { rad->atm_grid, rad->atm_nx, 2, &rad->atm_x, { &rad->atm_tau, &rad->atm_path } } };
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
                sea_status st = sea_grid_profile(tab[t].g, rad->wl[i], c, *tab[t].x,
                                                 *tab[t].v[c] + i * nx, err);
                if (st != SEA_OK)
                    return st;
            }
        }
    }
    if (rad->sky_grid != NULL)
        rad->sky = (sea_sky){ SEA_SKY_TABLE, NAN, rad->sky_v, rad->sky_nx, rad->sky_x };
    if (!(rad->wsum > 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN, "the response is zero over the whole band");
    for (int j = 0; j < SEA_TB_N; j++) {
        const double T = exp(SEA_TB_LNT0 + j * SEA_TB_STEP);
        double L = 0.0;
        for (size_t i = 0; i < k; i++)
            L += rad->wt[i] * rad->pa[i] / expm1(rad->pb[i] / T);
        rad->tb_lnL[j] = log(L); /* (-inf where L underflows: below every pixel's) */
    }
    return SEA_OK;
}

/* The sun's disc is not resolved where its glint's radiance is certainly
 * below this fraction of the tolerance of the pixel's other radiance (so
 * below 1e-6 of it at the default tolerance). */
static const double SEA_GLINT_NEGLIGIBLE = 1e-3;

/* Radiance of a facet with stats st seen from obs, sun from sun (or none),
 * summed over the samples with their weights; band means of emissivity and
 * reflectivity through *e and *rho. */
/* The linear polarisation of a facet's radiance per sample, in the frame of
 * the view (reference e_v, seabake.h POLARISATION): the Stokes
 * emissivity's polarised part (e_Q, e_U; sea_model_polarisation: one hit,
 * the second where the model takes one, and two scales) against the contrast
 * between the sea's blackbody and the sky the facets reflect,
 *     Q = e_Q (B_sea - L_sky),  U = e_U (B_sea - L_sky),
 * and, under a sky that varies with the zenith, the one-hit reflection
 * -e_Q,1 L_sky replaced by each facet's own mirror ray's sky (q_sky of
 * sea_polar_sky_n): Q = e_Q (B_sea - L_sky) + q_sky + e_Q,1 L_sky,
 * L_sky = sky_all / (1 - eps) the radiance of the sky the model's facets
 * reflect (eps the model's emissivity, sky_all what they reflect of it):
 * under a uniform sky exactly emission's e_Q B plus the sky's reflection
 * -e_Q L_sky (at two hits too: what the facets met send back is e_Q's
 * second-hit part times B - L), and 0 in a blackbody enclosure (sky at the
 * sea's temperature) whatever the model; the second hits and two scales
 * of a sky that is not uniform are those of a uniform one of the same
 * reflected radiance.  The
 * sun's glint (rr_all) is polarised as its mirror facet reflects it
 * (sea_polar_reflectivity). */
static sea_status facet_stokes(const sea_radiometry *rad, const sea_model *model,
                               const sea_slope_stats *st, sea_dir obs, sea_dir sun, int sun_up,
                               const double *eps_all, const double *sky_all,
                               const double *rr_all, double *Qk, double *Uk, sea_error *err)
{
    double eq[SEA_SCENE_BAND_MAX], eu[SEA_SCENE_BAND_MAX];
    sea_status s = sea_model_polarisation(model, st, obs, eq, eu, err);
    if (s != SEA_OK)
        return s;
    /* a sky that varies with the zenith: its one-hit reflection exactly,
     * each facet's mirror ray's sky (sea_polar_sky_n), in place of the
     * uniform sky of the same reflected radiance, -e_Q,1 L_sky */
    sea_stokes e1[SEA_SCENE_BAND_MAX], r1[SEA_SCENE_BAND_MAX];
    const int directional = rad->sc->sky_model != SEA_SKY_ISOTROPIC;
    if (directional &&
        ((s = sea_polar_emissivity_n(sea_model_optics(model), SEA_EMIS_AUTO, NULL, rad->N,
                                     rad->nsamp, st, obs, e1, err)) != SEA_OK ||
         (s = sea_polar_sky_n(sea_model_optics(model), SEA_EMIS_AUTO, NULL, rad->N, rad->nsamp, st,
                              obs, &rad->sky, r1, err)) != SEA_OK))
        return s;
    for (size_t i = 0; i < rad->nsamp; i++) {
        const double refl = 1.0 - eps_all[i];
        const double L_sky = refl > 0.0 ? sky_all[i] / refl : 0.0;
        const double contrast = rad->lsea[i] - L_sky;
        Qk[i] = eq[i] * contrast;
        Uk[i] = eu[i] * contrast;
        if (directional) {
            Qk[i] += r1[i].q + e1[i].q * L_sky;
            Uk[i] += r1[i].u + e1[i].u * L_sky;
        }
        if (sun_up && rr_all[i] > 0.0 && rad->esun[i] > 0.0) {
            sea_stokes ps;
            sea_polar_reflectivity(rad->N[i], st, sun, obs, &ps);
            if (ps.i > 0.0) {
                Qk[i] += rr_all[i] * rad->esun[i] * ps.q / ps.i;
                Uk[i] += rr_all[i] * rad->esun[i] * ps.u / ps.i;
            }
        }
    }
    return SEA_OK;
}

double sea_radiometry_transmitted(const sea_radiometry *rad, const double *Xk, double range)
{
    const double ext = sea_radiometry_extinction(rad);
    double s = 0.0;
    for (size_t k = 0; k < rad->nsamp; k++) {
        double tau = 1.0;
        if (ext > 0.0)
            tau = exp(-ext * range);
        else if (rad->atm_grid != NULL)
            tau = sea_profile_at(rad->atm_x, &rad->atm_tau[k * rad->atm_nx], rad->atm_nx, range);
        s += rad->wt[k] * tau * Xk[k];
    }
    return s;
}

sea_status sea_radiometry_facet(const sea_radiometry *rad, const sea_model *model,
                                const sea_slope_stats *st, sea_dir obs, sea_dir sun, int sun_up,
                                double *L, double *e, double *rho, double *Lk, double *Qk,
                                double *Uk, sea_error *err)
{
    double sl = 0.0, se = 0.0, sr = 0.0;
    double eps_all[SEA_SCENE_BAND_MAX], rr_all[SEA_SCENE_BAND_MAX];
    /* An isotropic sky (Eq 23) is seen in 1 - eps, with reflections >= 2
     * as well: what the mirror rays do not meet again.  Any other sky is
     * integrated over the facets' mirror rays (Eq 22, sea_emissivity_sky_n). */
    const int directional = rad->sc->sky_model != SEA_SKY_ISOTROPIC;
    double ksky_all[SEA_SCENE_BAND_MAX];
    sea_status s = sea_model_emissivity(model, st, obs, eps_all, ksky_all, err);
    if (s != SEA_OK)
        return s;
    /* the sky the facets reflect, per sample */
    double sky_all[SEA_SCENE_BAND_MAX];
    for (size_t i = 0; i < rad->nsamp; i++)
        sky_all[i] = directional ? ksky_all[i] : (1.0 - eps_all[i]) * rad->lsky[i];
    if (sun_up) {
        /* the glint is negligible where its radiance is below 1e-3 tolerance
         * of what the pixel has without it, at every sample */
        double negligible = INFINITY;
        for (size_t i = 0; i < rad->nsamp; i++) {
            const double other = eps_all[i] * rad->lsea[i] + sky_all[i];
            negligible = rad->esun[i] > 0.0
                             ? fmin(negligible, SEA_GLINT_NEGLIGIBLE * rad->sc->tolerance * other /
                                                    rad->esun[i])
                             : negligible;
        }
        sea_reflectivity_disc_n(sea_model_optics(model), rad->N, rad->nsamp, st, sun, obs,
                                rad->sc->sun_radius,
                                0.1 * rad->sc->tolerance, isfinite(negligible) ? negligible : 0.0,
                                rr_all);
    }
    if (Qk != NULL) {
        s = facet_stokes(rad, model, st, obs, sun, sun_up, eps_all, sky_all, rr_all, Qk, Uk, err);
        if (s != SEA_OK)
            return s;
    }
    for (size_t i = 0; i < rad->nsamp; i++) {
        const double eps = eps_all[i];
        const double rr = sun_up ? rr_all[i] : 0.0;
        const double Li = rr * rad->esun[i] + sky_all[i] + eps * rad->lsea[i];
        if (Lk != NULL)
            Lk[i] = Li;
        sl += rad->wt[i] * Li;
        se += rad->wt[i] * eps;
        sr += rad->wt[i] * rr;
    }
    *L = sl;
    *e = se / rad->wsum;
    *rho = sr / rad->wsum;
    return SEA_OK;
}

/* Brightness temperature of a (band) radiance: the T whose blackbody gives
 * the same weighted sum, by safeguarded Newton iterations on ln T.  Each
 * iteration takes one expm1 and one division per sample (B = a / E,
 * E = expm1(x), x = b / T, dB/dT = B x (1 + 1/E) / T), the wavelength's
 * powers found once. */
double sea_radiometry_temperature(const sea_radiometry *rad, double L)
{
    if (rad->nsamp == 1)
        return sea_planck_brightness_temperature(rad->wl[0], L / rad->wt[0]);
    double lo = 1.0, hi = 1e5;
    double T;
    int from_table = 0;
    const double lnL = log(L);
    if (lnL > rad->tb_lnL[1] && lnL < rad->tb_lnL[SEA_TB_N - 2]) {
        /* the table: the interval holding ln L (within [1, N - 3], as ln L
         * lies between the second and the next-to-last entries), then the
         * cubic through four points (ln T as a function of ln L), within
         * about 1e-7 */
        const int a = (int)sea_interval_of(rad->tb_lnL, SEA_TB_N, lnL);
        double lnT = 0.0;
        for (int p = a - 1; p <= a + 2; p++) {
            double w = 1.0;
            for (int q = a - 1; q <= a + 2; q++)
                if (q != p)
                    w *= (lnL - rad->tb_lnL[q]) / (rad->tb_lnL[p] - rad->tb_lnL[q]);
            lnT += w * (SEA_TB_LNT0 + p * SEA_TB_STEP);
        }
        T = exp(lnT);
        from_table = 1;
    } else {
        T = sea_planck_brightness_temperature(rad->wl[rad->nsamp / 2], L / rad->wsum);
    }
    if (!(T > lo && T < hi))
        T = 300.0;
    for (int it = 0; it < 100; it++) {
        double f = -L, df = 0.0;
        const double inv_T = 1.0 / T;
        for (size_t i = 0; i < rad->nsamp; i++) {
            const double x = rad->pb[i] * inv_T, inv_E = 1.0 / expm1(x), B = rad->pa[i] * inv_E;
            f += rad->wt[i] * B;
            df += rad->wt[i] * (B * x * (1.0 + inv_E) * inv_T);
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
double sea_radiometry_unit(const sea_radiometry *rad)
{
    return rad->nsamp == 1 && rad->sc->wavelength > 0.0 ? 1e-6 : 1.0;
}

/* The extinction of the air, 1/m: 0 without [atmosphere]. */
double sea_radiometry_extinction(const sea_radiometry *rad)
{
    return isnan(rad->sc->air_temperature) ? 0.0 : rad->sc->extinction;
}

/* What the sensor receives of a sea point at range (m) whose radiance is
 * L (SI, summed over the samples with their weights; Lk per sample, read
 * with a table only): Beer-Lambert, tau L + (1 - tau) B(T_air) with
 * tau = exp(-extinction range); or per sample the table's transmittance
 * x Lk + path radiance at the range (linear in range, its ends held
 * beyond); L itself without air. */
double sea_radiometry_through_air(const sea_radiometry *rad, double L, const double *Lk,
                                  double range)
{
    const double ext = sea_radiometry_extinction(rad);
    if (ext > 0.0) {
        const double tau = exp(-ext * range);
        return tau * L + (1.0 - tau) * rad->air_L;
    }
    if (rad->atm_grid == NULL)
        return L;
    double s = 0.0;
    for (size_t k = 0; k < rad->nsamp; k++) {
        const double *tk = &rad->atm_tau[k * rad->atm_nx], *pk = &rad->atm_path[k * rad->atm_nx];
        s += rad->wt[k] * (sea_profile_at(rad->atm_x, tk, rad->atm_nx, range) * Lk[k] +
                         sea_profile_at(rad->atm_x, pk, rad->atm_nx, range));
    }
    return s;
}


sea_status sea_radiometry_alloc(const sea_scene *sc, sea_radiometry *rad, sea_error *err)
{
    rad->sc = sc;
    sea_status st = sc->water_file[0]
                        ? sea_water_load(sc->water_file, sc->salinity, &rad->water, err)
                        : sea_water_alloc(sc->water_table, sc->salinity, &rad->water, err);
    if (st != SEA_OK)
        return st;
    double x_max, w_min, w_max;
    if (sc->sky_model == SEA_SKY_TABLE) {
        if ((st = sea_sky_table_load(sc->sky_table_file, &rad->sky_grid, err)) != SEA_OK)
            return st;
        sea_grid_axes(rad->sky_grid, &rad->sky_nx, &x_max, &w_min, &w_max);
        if ((rad->sky_x = malloc(rad->sky_nx * sizeof(double))) == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the sky table");
    }
    if (sc->atmosphere_table_file[0] != '\0') {
        if ((st = sea_atmosphere_table_load(sc->atmosphere_table_file, &rad->atm_grid, err)) !=
            SEA_OK)
            return st;
        sea_grid_axes(rad->atm_grid, &rad->atm_nx, &x_max, &w_min, &w_max);
        rad->atm_range_max = x_max;
        if ((rad->atm_x = malloc(rad->atm_nx * sizeof(double))) == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the atmosphere table");
    }
    return SEA_OK;
}

void sea_radiometry_free(sea_radiometry *rad)
{
    sea_water_free(rad->water);
    free(rad->wl);
    free(rad->wt);
    free(rad->esun);
    free(rad->lsky);
    free(rad->lsea);
    free(rad->pa);
    free(rad->pb);
    free(rad->lair);
    free(rad->N);
    sea_grid_free(rad->sky_grid);
    sea_grid_free(rad->atm_grid);
    free(rad->sky_x);
    free(rad->sky_v);
    free(rad->atm_x);
    free(rad->atm_tau);
    free(rad->atm_path);
}
