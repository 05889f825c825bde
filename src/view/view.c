/* view.c - radiance images of a scene (Eq 23; seabake-model(7), RADIANCE).
 * Top-down: the scene, the sensor (sea_camera), the multiresolution sea
 * (multires.c: levels, one realisation per frame, what each pixel sees),
 * the optics of what each pixel sees (Eq 7, 13: emissivity toward the
 * sensor, reflectivity sun -> sensor), the radiance (Eq 23) over the
 * spectral samples of the band (radiometry.c: the samples, the sun, the sky,
 * the air, a facet's radiance and its brightness temperature). */
#include "config.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "seabake.h"
#include "internal.h"
#include "view/radiometry.h"

/* Largest automatic number of spectral samples. */
enum { SAMPLES_AUTO_MAX = 64 };

struct sea_view {
    sea_scene sc;
    sea_camera cam;
    sea_multires *mr;
    /* the spectral samples, the sun, the sky, the air and the water: what
     * turns a facet's optics into radiance (radiometry.c) */
    sea_radiometry rad;
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
    free(img->stokes_i);
    free(img->stokes_q);
    free(img->stokes_u);
    memset(img, 0, sizeof *img);
}

sea_status sea_image_alloc_stokes(sea_image *img, sea_error *err)
{
    const size_t n = (size_t)img->width * (size_t)img->height;
    float **planes[3] = { &img->stokes_i, &img->stokes_q, &img->stokes_u };
    for (int i = 0; i < 3; i++)
        if (*planes[i] == NULL && (*planes[i] = calloc(n, sizeof(float))) == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %d x %d image's Stokes planes",
                            img->width, img->height);
    return SEA_OK;
}

void sea_view_free(sea_view *r)
{
    if (r == NULL)
        return;
    sea_multires_free(r->mr);
    sea_model_free(r->model);
    sea_radiometry_free(&r->rad);
    free(r);
}

size_t sea_view_levels(const sea_view *r, const sea_clip_level **levels)
{
    return sea_multires_levels(r->mr, levels);
}

size_t sea_view_samples(const sea_view *r, const double **wavelength, const double **weight)
{
    *wavelength = r->rad.wl;
    *weight = r->rad.wt;
    return r->rad.nsamp;
}

sea_emis_rule sea_view_emis_rule(double emis_scale, const sea_slope_stats *st, sea_dir v)
{
    return sea_model_emis_rule(emis_scale, st, v);
}

sea_view_choices sea_view_choices_of(const sea_view *r)
{
    return r->choices;
}

void sea_view_band(const sea_view *r, sea_band *out)
{
    out->n = r->rad.nsamp;
    out->wavelength = r->rad.wl;
    out->weight = r->rad.wt;
    out->unit = sea_radiometry_unit(&r->rad);
}

double sea_view_brightness_temperature(const sea_view *r, double radiance)
{
    return radiance > 0.0 ? sea_radiometry_temperature(&r->rad, radiance / sea_radiometry_unit(&r->rad)) : 0.0;
}

sea_status sea_view_facet_optics(const sea_view *r, const sea_slope_stats *st, sea_dir obs,
                                   sea_dir sun, sea_facet_optics *out, sea_error *err)
{
    double L, e, rho;
    sea_status s = sea_radiometry_facet(&r->rad, r->model, st, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho, NULL, NULL, NULL, err);
    if (s != SEA_OK)
        return s;
    out->emissivity = e;
    out->reflectivity = rho;
    out->radiance = L * sea_radiometry_unit(&r->rad);
    out->temperature = sea_radiometry_temperature(&r->rad, L);
    out->seen = out->radiance;
    return SEA_OK;
}

int sea_view_has_air(const sea_view *r)
{
    return sea_radiometry_extinction(&r->rad) > 0.0 || r->rad.atm_grid != NULL;
}

sea_status sea_view_facet_seen(const sea_view *r, const sea_slope_stats *st, sea_dir obs,
                                 sea_dir sun, double range, sea_facet_optics *out,
                                 sea_error *err)
{
    double L, e, rho;
    double Lk[SEA_SCENE_BAND_MAX];
    sea_status s = sea_radiometry_facet(&r->rad, r->model, st, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho,
                                  r->rad.atm_grid != NULL ? Lk : NULL, NULL, NULL, err);
    if (s != SEA_OK)
        return s;
    const double unit = sea_radiometry_unit(&r->rad);
    out->emissivity = e;
    out->reflectivity = rho;
    out->radiance = L * unit;
    out->temperature = sea_radiometry_temperature(&r->rad, L);
    out->seen = sea_view_has_air(r) ? sea_radiometry_through_air(&r->rad, L, Lk, range) * unit : out->radiance;
    return SEA_OK;
}

double sea_view_sky_toward(const sea_view *r, double cos_zenith)
{
    double L = 0.0;
    for (size_t k = 0; k < r->rad.nsamp; k++)
        L += r->rad.wt[k] * sea_sky_radiance(&r->rad.sky, k, cos_zenith);
    return L * sea_radiometry_unit(&r->rad);
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
    for (size_t k = 0; k < r->rad.nsamp; k++) {
        const double s1 = sea_sky_radiance(&r->rad.sky, k, 1.0), s0 = sea_sky_radiance(&r->rad.sky, k, 0.0);
        dmax += r->rad.wt[k] * fmax(fabs(r->rad.lsea[k] - s1), fabs(r->rad.lsea[k] - s0));
        lmin += r->rad.wt[k] * (0.8 * r->rad.lsea[k] + 0.2 * fmin(s1, s0));
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
    return sea_model_alloc(&mp, spec, lr, &fine, r->rad.N, r->rad.nsamp, &r->rad.sky, &r->model, err);
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
    /* the water, the sky's and the air's tables */
    TRY(sea_radiometry_alloc(&r->sc, &r->rad, err));

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
                TRY(sea_radiometry_samples(&r->rad, k, &resp, err));
                TRY(set_model(r, &spec, &lrs, 1, err));
                TRY(sea_radiometry_facet(&r->rad, r->model, &lrs, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho,
                                   NULL, NULL, NULL, err));
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
    TRY(sea_radiometry_samples(&r->rad, k, &resp, err));
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
    int polarised; /* Stokes planes asked for, or a polarizer */
} pixel_consts;

/* Pixel (i, j) of img from what it sees, s: the sky, or the sea's radiance
 * through the air. */
/* A pixel's linear polarisation (Q, U in the view's frame at the point met:
 * reference e_v, +45 toward e_h; seabake.h POLARISATION) turned into the
 * camera's frame: reference the image's up axis projected across the ray
 * through the pixel's centre, +45 toward the image's right.  With the
 * frame's angle psi from up to e_v (toward right, sea_camera_stokes_frame),
 *     Q' = Q cos 2psi - U sin 2psi,  U' = Q sin 2psi + U cos 2psi. */
static void pixel_stokes(const sea_view *r, const sea_multires_sample *s, size_t i, size_t j,
                         double Q, double U, double *Qc, double *Uc)
{
    double c2, s2;
    sea_camera_stokes_frame(&r->cam, (double)i + 0.5, (double)j + 0.5, s->normal, s->obs, &c2,
                            &s2);
    *Qc = Q * c2 - U * s2;
    *Uc = Q * s2 + U * c2;
}

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
            for (size_t k = 0; k < r->rad.nsamp; k++)
                Ls += r->rad.wt[k] * sea_sky_radiance(&r->rad.sky, k, d[2]);
            Ts = (float)sea_radiometry_temperature(&r->rad, Ls);
        }
        img->radiance[q] = (float)(Ls * pc->unit);
        img->temperature[q] = Ts;
        img->level[q] = 0.0f;
        img->emissivity[q] = img->reflectivity[q] = 0.0f;
        if (img->stokes_i != NULL) { /* the sky's emission: unpolarised */
            img->stokes_i[q] = img->radiance[q];
            img->stokes_q[q] = img->stokes_u[q] = 0.0f;
        }
        return SEA_OK;
    }
    sea_pixel_geom g;
    memcpy(g.normal, s->normal, sizeof g.normal);
    const sea_dir sun = sea_camera_local_dir(&g, pc->sun_vec);
    const sea_slope_stats ss = sea_moments_stats(&s->moments);
    double L, e, rho;
    double Lk[SEA_SCENE_BAND_MAX], Qk[SEA_SCENE_BAND_MAX], Uk[SEA_SCENE_BAND_MAX];
    const int polarised = pc->polarised;
    sea_status st = sea_radiometry_facet(&r->rad, r->model, &ss, s->obs, sun, sun.theta < M_PI / 2.0,
                                         &L, &e, &rho, r->rad.atm_grid != NULL ? Lk : NULL,
                                         polarised ? Qk : NULL, polarised ? Uk : NULL, err);
    /* the air along the range met (through_air, shared with the bake's
     * maps: sea_view_facet_seen); the table's transmittance and path
     * radiance must reach that range */
    if (st == SEA_OK && pc->ext == 0.0 && r->rad.atm_grid != NULL && s->range > r->rad.atm_range_max)
        st = sea_fail(err, SEA_ERR_DOMAIN,
                      "pixel (%zu, %zu) meets the sea at %.6g m, beyond the "
                      "[atmosphere] table's last range_m %.6g (allowed: a table that "
                      "reaches the farthest sea in view)",
                      i, j, s->range, r->rad.atm_range_max);
    if (pc->ext > 0.0 || (st == SEA_OK && r->rad.atm_grid != NULL))
        L = sea_radiometry_through_air(&r->rad, L, Lk, s->range);
    if (st == SEA_OK && !(isfinite(L) && L > 0.0 && isfinite(rho)))
        st = sea_fail(err, SEA_ERR_NUMERIC, "radiance %g at pixel (%zu, %zu)", L, i, j);
    if (st != SEA_OK)
        return st;
    double Lseen = L;
    if (polarised) {
        double Q, U;
        pixel_stokes(r, s, i, j, sea_radiometry_transmitted(&r->rad, Qk, s->range),
                     sea_radiometry_transmitted(&r->rad, Uk, s->range), &Q, &U);
        if (img->stokes_i != NULL) {
            img->stokes_i[q] = (float)(L * pc->unit);
            img->stokes_q[q] = (float)(Q * pc->unit);
            img->stokes_u[q] = (float)(U * pc->unit);
        }
        if (!isnan(sc->polarizer))
            Lseen = L + Q * cos(2.0 * sc->polarizer) + U * sin(2.0 * sc->polarizer);
        if (!(isfinite(Lseen) && Lseen > 0.0))
            return sea_fail(err, SEA_ERR_NUMERIC, "radiance %g behind the polarizer at pixel (%zu, %zu)",
                            Lseen, i, j);
    }
    img->radiance[q] = (float)(Lseen * pc->unit);
    img->temperature[q] = (float)sea_radiometry_temperature(&r->rad, Lseen);
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
    for (size_t i = 0; i < r->rad.nsamp; i++)
        pc->sky_L += r->rad.wt[i] * r->rad.lsky[i];
    pc->unit = sea_radiometry_unit(&r->rad); /* per um */
    pc->sky_T = (float)sea_radiometry_temperature(&r->rad, pc->sky_L);
    /* the air between the sensor and the sea: Beer-Lambert along the range
     * met, the path radiating (1 - tau) B(T_air) (through_air) */
    pc->ext = sea_radiometry_extinction(&r->rad);
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
    pc.polarised = img->stokes_i != NULL || !isnan(sc->polarizer);
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
