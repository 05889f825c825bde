/* render.c - radiance images of a scene (Eq 23; seabake-model(7), RADIANCE):
 * per-pixel geometry, the clipmap levels the view needs, facet moments per
 * level from one wave realisation, and the optics of each pixel.
 *
 * Levels.  A sea pixel of footprint L wants the level l = round(log2(L/L0)).
 * Level l is a window of at most grid x grid facets of L0 2^l over the
 * ground points of the pixels that want it (centred on them when they do
 * not fit); a pixel outside its level's window uses the next coarser level
 * that holds it.  From the first level whose waves above the facet size hold
 * less than `tolerance` of the slope variance, levels are low-resolution:
 * m = 0, C = C_LR, no synthesis and no facets.
 *
 * No seams.  Moments are linear (LEAN), so blending them is averaging
 * surfaces: a pixel whose log2(L/L0) lies within BLEND_HALF of the midpoint
 * between two levels mixes them, reaching 50/50 at the midpoint; and within
 * EDGE facets of a window's edge a level fades into the next coarser one
 * (as geometry clipmaps do).  Inside a level the moments are interpolated
 * bilinearly between facet centres, like a renderer's texture lookup. */
#include "config.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_integration.h>

#include "seabake.h"

/* Half-width, in log2 of the footprint, of the band around a level
 * midpoint where two levels are blended. */
static const double BLEND_HALF = 0.15;
/* The finest and coarsest level exponents considered. */
enum { LEVEL_MAX = SEA_CLIP_MAX_LEVELS - 1 };
/* Largest automatic number of spectral samples. */
enum { SAMPLES_AUTO_MAX = 64 };

typedef struct {
    double x, y;
    sea_dir obs, sun;
    double lam;      /* log2(footprint / L0) */
    int hit, sun_up;
    int level;       /* wanted level */
    int neighbour;   /* level blended in, -1 none */
    double alpha;    /* weight of the neighbour */
    uint32_t need;   /* bit l: the pixel reads level l */
} pixel;

struct sea_render {
    sea_scene sc;
    sea_camera cam;
    sea_spectrum spec;
    sea_water *water;
    sea_optics *optics;
    sea_waves *waves;
    size_t nsamp;
    double *wl, *wt, *esun, *lsky;
    double *lsea;    /* blackbody radiance at the sea's temperature, per sample */
    double complex *N;
    double wsum;
    sea_moments lr;  /* moments of a low-resolution facet */
    size_t npix;
    pixel *px;
    int first_lr;    /* levels >= first_lr are low-resolution */
    sea_clip_level lev[SEA_CLIP_MAX_LEVELS]; /* indexed by level exponent */
    int used[SEA_CLIP_MAX_LEVELS];
    sea_clip_level compact[SEA_CLIP_MAX_LEVELS]; /* the used levels, finest first */
    size_t ncompact;
    sea_render_choices choices;
};

sea_status sea_image_alloc(sea_image *img, int width, int height, sea_error *err)
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

void sea_render_free(sea_render *r)
{
    if (r == NULL)
        return;
    sea_water_free(r->water);
    sea_optics_free(r->optics);
    sea_waves_free(r->waves);
    free(r->wl);
    free(r->wt);
    free(r->esun);
    free(r->lsky);
    free(r->lsea);
    free(r->N);
    free(r->px);
    free(r);
}

size_t sea_render_levels(const sea_render *r, const sea_clip_level **levels)
{
    *levels = r->compact;
    return r->ncompact;
}

size_t sea_render_samples(const sea_render *r, const double **wavelength, const double **weight)
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
    size_t lo = 0, hi = resp->n - 1;
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        if (resp->wavelength[mid] <= wl)
            lo = mid;
        else
            hi = mid;
    }
    const double a = (wl - resp->wavelength[lo]) / (resp->wavelength[hi] - resp->wavelength[lo]);
    return (1.0 - a) * resp->value[lo] + a * resp->value[hi];
}

/* Spectral samples: one wavelength, or a Gauss-Legendre rule of k nodes on
 * the band weighted by the response. */
static sea_status set_samples(sea_render *r, size_t k, const sea_response *resp, sea_error *err)
{
    free(r->wl);
    free(r->wt);
    free(r->esun);
    free(r->lsky);
    free(r->lsea);
    free(r->N);
    r->wl = malloc(k * sizeof(double));
    r->wt = malloc(k * sizeof(double));
    r->esun = malloc(k * sizeof(double));
    r->lsky = malloc(k * sizeof(double));
    r->lsea = malloc(k * sizeof(double));
    r->N = malloc(k * sizeof(double complex));
    if (!r->wl || !r->wt || !r->esun || !r->lsky || !r->lsea || !r->N)
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
        r->wsum += r->wt[i];
    }
    if (!(r->wsum > 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN, "the response is zero over the whole band");
    return SEA_OK;
}

/* The tolerance's rules (see sea_render_choices in seabake.h for the
 * measurements behind each step). */
static double tol_emis_scale(double tol)
{
    return tol <= SEA_TOL_EMIS_T1 ? 1.0 : tol <= SEA_TOL_EMIS_T2 ? 0.65 : 0.5;
}


sea_emis_rule sea_render_emis_rule(double emis_scale, const sea_slope_stats *st, sea_dir v)
{
    sea_emis_rule a = sea_emissivity_auto_rule(st, v);
    if (emis_scale >= 1.0)
        return a;
    a.n_gl = (int)fmax(2.0, ceil(emis_scale * a.n_gl));
    a.n_gh = (int)fmax(1.0, ceil(emis_scale * a.n_gh));
    return a;
}

sea_render_choices sea_render_choices_of(const sea_render *r)
{
    return r->choices;
}

/* Radiance of a facet with stats st seen from obs, sun from sun (or none),
 * summed over the samples with their weights; band means of emissivity and
 * reflectivity through *e and *rho. */
static sea_status facet_radiance(const sea_render *r, const sea_slope_stats *st, sea_dir obs,
                                 sea_dir sun, int sun_up, double *L, double *e, double *rho,
                                 sea_error *err)
{
    double sl = 0.0, se = 0.0, sr = 0.0;
    /* a scaled auto rule: the same orders for every wavelength */
    const int scaled = r->sc.emissivity_method == SEA_EMIS_AUTO && r->choices.emis_scale < 1.0;
    sea_emis_rule rule = { 0, 0 };
    if (scaled && sea_slope_stats_check(st, NULL) == SEA_OK && obs.theta >= 0.0 &&
        obs.theta < M_PI_2)
        rule = sea_render_emis_rule(r->choices.emis_scale, st, obs);
    /* Every sample's emissivity from one set of nodes: the geometry is the
     * same at every wavelength. */
    double eps_all[SEA_SCENE_BAND_MAX], rr_all[SEA_SCENE_BAND_MAX];
    sea_status s = sea_emissivity_n(r->optics, (sea_emis_method)r->sc.emissivity_method,
                                    scaled ? &rule : NULL, r->N, r->nsamp, st, obs, eps_all, err);
    if (s != SEA_OK)
        return s;
    if (sun_up)
        sea_reflectivity_n(r->N, r->nsamp, st, sun, obs, rr_all);
    for (size_t i = 0; i < r->nsamp; i++) {
        const double eps = eps_all[i];
        const double rr = sun_up ? rr_all[i] : 0.0;
        const double Li = rr * r->esun[i] + (1.0 - eps) * r->lsky[i] + eps * r->lsea[i];
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
 * the same weighted sum, by safeguarded Newton iterations on ln T. */
static double band_temperature(const sea_render *r, double L)
{
    if (r->nsamp == 1)
        return sea_planck_brightness_temperature(r->wl[0], L / r->wt[0]);
    double lo = 1.0, hi = 1e5;
    double T = sea_planck_brightness_temperature(r->wl[r->nsamp / 2], L / r->wsum);
    if (!(T > lo && T < hi))
        T = 300.0;
    for (int it = 0; it < 100; it++) {
        double f = -L, df = 0.0;
        for (size_t i = 0; i < r->nsamp; i++) {
            f += r->wt[i] * sea_planck_radiance(r->wl[i], T);
            df += r->wt[i] * sea_planck_radiance_dT(r->wl[i], T);
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
        T = Tn;
    }
    return T;
}

/* Radiance unit of the images: per um for one wavelength (SI is per m). */
static double radiance_unit(const sea_render *r)
{
    return r->nsamp == 1 && r->sc.wavelength > 0.0 ? 1e-6 : 1.0;
}

sea_status sea_render_facet_optics(const sea_render *r, const sea_slope_stats *st, sea_dir obs,
                                   sea_dir sun, sea_facet_optics *out, sea_error *err)
{
    double L, e, rho;
    sea_status s = facet_radiance(r, st, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho, err);
    if (s != SEA_OK)
        return s;
    out->emissivity = e;
    out->reflectivity = rho;
    out->radiance = L * radiance_unit(r);
    out->temperature = band_temperature(r, L);
    return SEA_OK;
}

const sea_scene *sea_render_scene(const sea_render *r)
{
    return &r->sc;
}

const sea_camera *sea_render_camera(const sea_render *r)
{
    return &r->cam;
}

const sea_waves *sea_render_waves(const sea_render *r)
{
    return r->waves;
}

sea_moments sea_render_lr_moments(const sea_render *r)
{
    return r->lr;
}

/* Weight of window lv at (x, y): 1 inside, fading to 0 over the outer
 * EDGE facets (at least 2, a sixteenth of the window), 0 outside; *fx, *fy
 * get the position in facet-centre units. */
static double edge_weight(const sea_clip_level *lv, double x, double y, double *fx, double *fy)
{
    *fx = x / lv->facet - (double)lv->i0 - 0.5;
    *fy = y / lv->facet - (double)lv->j0 - 0.5;
    const double nx = (double)lv->nx, ny = (double)lv->ny;
    const double edge = fmin(fmin(*fx + 0.5, nx - 0.5 - *fx), fmin(*fy + 0.5, ny - 0.5 - *fy));
    if (!(edge > 0.0))
        return 0.0;
    const double band = fmax(2.0, fmin(nx, ny) / 16.0);
    return fmin(1.0, edge / band);
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median x and y of the ground points of the pixels that want level l
 * (of those that read it, if none wants it). */
static sea_status median_point(const sea_render *r, int l, double *mx, double *my,
                               sea_error *err)
{
    double *v = malloc(2 * r->npix * sizeof(double));
    if (v == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu pixels", r->npix);
    size_t n = 0;
    for (int pass = 0; pass < 2 && n == 0; pass++)
        for (size_t q = 0; q < r->npix; q++) {
            const pixel *p = &r->px[q];
            if (!p->hit || (pass == 0 ? p->level != l : !(p->need & ((uint32_t)1 << l))))
                continue;
            v[n] = p->x;
            v[r->npix + n] = p->y;
            n++;
        }
    if (n == 0) {
        free(v);
        *mx = *my = 0.0;
        return SEA_OK;
    }
    qsort(v, n, sizeof(double), compare_double);
    qsort(v + r->npix, n, sizeof(double), compare_double);
    *mx = v[n / 2];
    *my = v[r->npix + n / 2];
    free(v);
    return SEA_OK;
}

/* ------------------------------------------------------------- prepare */

static void to_moments(const sea_slope_stats *st, sea_moments *m)
{
    m->mx = st->mean.x;
    m->my = st->mean.y;
    m->mxx = st->mean.x * st->mean.x + st->cov.xx;
    m->mxy = st->mean.x * st->mean.y + st->cov.xy;
    m->myy = st->mean.y * st->mean.y + st->cov.yy;
    m->h = 0.0;
}

/* The levels a footprint of log2(L / L0) = lam reads: the nearest level,
 * blended with its neighbour (weight alpha, up to 1/2 at the midpoint)
 * within BLEND_HALF of the midpoint between them.  Every low-resolution
 * level is the same surface (m = 0, C = C_LR), so levels from first_lr on
 * are first_lr; a neighbour equal to the level is none (-1, alpha 0). */
static void choose_levels(const sea_render *r, double lam, int *level, int *neighbour,
                          double *alpha)
{
    const double c = fmin(fmax(lam, 0.0), (double)LEVEL_MAX);
    int l = (int)lround(c);
    const double d = lam - l;
    int nb = -1;
    double a = 0.0;
    if (fabs(d) > 0.5 - BLEND_HALF) {
        nb = l + (d > 0.0 ? 1 : -1);
        a = fmin(0.5 * (fabs(d) - (0.5 - BLEND_HALF)) / BLEND_HALF, 0.5);
        if (nb < 0 || nb > LEVEL_MAX) {
            nb = -1;
            a = 0.0;
        }
    }
    if (l > r->first_lr)
        l = r->first_lr;
    if (nb > r->first_lr)
        nb = r->first_lr;
    if (nb == l) {
        nb = -1;
        a = 0.0;
    }
    *level = l;
    *neighbour = nb;
    *alpha = a;
}

/* The memory a render of npix pixels holds at once, checked as a whole
 * before anything is allocated (each array alone may fit while together
 * they do not: 16384^2 pixels need 22 GiB of geometry and 5 GiB of image).
 * The per-level moments are bounded by the grid and checked when known. */
static sea_status check_plan(size_t npix, sea_error *err)
{
    const double GiB = 1073741824.0;
    const double image = (double)npix * 5.0 * sizeof(float);    /* sea_image_alloc */
    const double geometry = (double)npix * (double)sizeof(pixel); /* r->px */
    const double scratch = (double)npix * 2.0 * sizeof(double);  /* median_point */
    const double need = image + geometry + scratch;
    const double avail = (double)sea_memory_available();
    if (need > avail)
        return sea_fail(err, SEA_ERR_NOMEM,
                        "the render of %zu pixels needs %.3g GiB (image %.3g, per-pixel geometry "
                        "%.3g, scratch %.3g GiB); this process may use %.3g GiB",
                        npix, need / GiB, image / GiB, geometry / GiB, scratch / GiB,
                        avail / GiB);
    return SEA_OK;
}

sea_status sea_render_prepare(const sea_scene *sc, sea_render **out, sea_error *err)
{
    *out = NULL;
    sea_render *r = calloc(1, sizeof *r);
    if (r == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    r->sc = *sc;
    r->choices.tolerance = sc->tolerance;
    r->choices.emis_scale =
        sc->emissivity_method == SEA_EMIS_AUTO ? tol_emis_scale(sc->tolerance) : 1.0;
    sea_status st;
#define TRY(expr)                                                                                 \
    do {                                                                                          \
        if ((st = (expr)) != SEA_OK) {                                                            \
            sea_render_free(r);                                                                   \
            return st;                                                                            \
        }                                                                                         \
    } while (0)
    TRY(sea_camera_init(&r->cam, sc->sensor_x, sc->sensor_y, sc->altitude, sc->look_zenith,
                        sc->look_azimuth, sc->roll, sc->hfov, sc->width, sc->height, sc->earth,
                        err));
    TRY(sea_spectrum_init(&r->spec, sc->wind_speed, sc->fetch, sc->wind_dir, err));
    TRY(sc->water_file[0] ? sea_water_load(sc->water_file, sc->salinity, &r->water, err)
                          : sea_water_alloc((sea_water_table)sc->water_table, sc->salinity,
                                            &r->water, err));
    TRY(sea_optics_alloc(&r->optics, err));
    sea_cov2 lr;
    TRY(sea_spectrum_slope_cov(&r->spec, 0.0, &lr, err));
    const sea_slope_stats lrs = { { 0.0, 0.0 }, lr };
    to_moments(&lrs, &r->lr);

    /* per-pixel geometry */
    const size_t W = (size_t)sc->width, H = (size_t)sc->height;
    r->npix = W * H;
    TRY(check_plan(r->npix, err));
    r->px = malloc(r->npix * sizeof(pixel));
    if (r->px == NULL) {
        sea_render_free(r);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu pixels", r->npix);
    }
    const double sun_vec[3] = { sin(sc->sun_zenith) * cos(sc->sun_azimuth),
                                sin(sc->sun_zenith) * sin(sc->sun_azimuth), cos(sc->sun_zenith) };
    const double L0 = sc->finest;

    /* low-resolution threshold */
    const double tr_lr = lr.xx + lr.yy;
    r->first_lr = LEVEL_MAX;
    for (int l = 0; l <= LEVEL_MAX; l++) {
        sea_cov2 c;
        TRY(sea_spectrum_slope_cov(&r->spec, M_PI / (L0 * exp2(l)), &c, err));
        const double share = tr_lr > 0.0 ? 1.0 - (c.xx + c.yy) / tr_lr : 0.0;
        r->lev[l].level = l;
        r->lev[l].facet = L0 * exp2(l);
        r->lev[l].generated_share = fmax(share, 0.0);
        if (share < sc->tolerance && r->first_lr == LEVEL_MAX)
            r->first_lr = l;
    }

#pragma omp parallel for schedule(dynamic, 8)
    for (size_t j = 0; j < H; j++) {
        for (size_t i = 0; i < W; i++) {
            pixel *p = &r->px[j * W + i];
            sea_pixel_geom g;
            sea_camera_pixel(&r->cam, (double)i + 0.5, (double)j + 0.5, &g);
            p->hit = g.hit;
            p->x = g.x;
            p->y = g.y;
            p->obs = g.obs;
            p->sun = sea_camera_local_dir(&g, sun_vec);
            p->sun_up = g.hit && p->sun.theta < M_PI / 2.0;
            p->lam = isfinite(g.footprint) ? log2(g.footprint / L0) : (double)LEVEL_MAX;
            choose_levels(r, p->lam, &p->level, &p->neighbour, &p->alpha);
            p->need = 0;
            if (g.hit) {
                p->need = (uint32_t)1 << p->level;
                if (p->neighbour >= 0)
                    p->need |= (uint32_t)1 << p->neighbour;
            }
        }
    }

    /* Windows, finest first: the bounding box of the ground points that read
     * a level, capped at grid x grid facets around their centre.  Pixels
     * outside a window, or in its fading edge, read the next coarser level
     * too, so that level's window covers them. */
    for (size_t q = 0; q < r->npix; q++)
        if (r->px[q].hit)
            r->lev[r->px[q].level].pixels++;
    size_t fft_cells = 2;
    int any_hr = 0;
    /* The centre of clipmap windows: where the optical axis meets the sea,
     * else the nadir point. */
    double look_x = sc->sensor_x, look_y = sc->sensor_y;
    {
        sea_pixel_geom g;
        sea_camera_pixel(&r->cam, 0.5 * sc->width, 0.5 * sc->height, &g);
        if (g.hit) {
            look_x = g.x;
            look_y = g.y;
        }
    }
    for (int l = 0; l <= LEVEL_MAX; l++) {
        sea_clip_level *lv = &r->lev[l];
        const uint32_t bit = (uint32_t)1 << l;
        double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
        for (size_t q = 0; q < r->npix; q++) {
            const pixel *p = &r->px[q];
            if (!(p->need & bit))
                continue;
            xmin = fmin(xmin, p->x);
            xmax = fmax(xmax, p->x);
            ymin = fmin(ymin, p->y);
            ymax = fmax(ymax, p->y);
        }
        const int clipmap = sc->windows == SEA_WINDOWS_CLIPMAP && l < r->first_lr;
        if (!(xmin <= xmax) && !clipmap)
            continue;
        r->used[l] = 1;
        lv->low_res = l >= r->first_lr;
        if (lv->low_res)
            continue;
        any_hr = 1;
        const double L = lv->facet;
        const size_t grid = (size_t)sc->grid;
        long i_lo, i_hi, j_lo, j_hi;
        if (xmin <= xmax) {
            /* margin: the fading edge (see edge_weight) plus one facet, so
             * that a window that is not capped holds its pixels at full
             * weight */
            const double span = fmax(xmax - xmin, ymax - ymin) / L;
            const long margin = (long)ceil(fmax(2.0, (span + 2.0) / 14.0)) + 2;
            i_lo = (long)floor(xmin / L) - margin, i_hi = (long)floor(xmax / L) + margin;
            j_lo = (long)floor(ymin / L) - margin, j_hi = (long)floor(ymax / L) + margin;
        } else {
            /* No pixel reads this level (a clipmap window all the same):
             * the bounds stay infinite, and converting them is undefined. */
            i_lo = i_hi = j_lo = j_hi = 0;
        }
        if (clipmap) {
            /* concentric: grid x grid facets around the look point */
            i_lo = (long)floor(look_x / L) - (long)grid / 2;
            j_lo = (long)floor(look_y / L) - (long)grid / 2;
            i_hi = i_lo + (long)grid - 1;
            j_hi = j_lo + (long)grid - 1;
        } else if ((size_t)(i_hi - i_lo + 1) > grid || (size_t)(j_hi - j_lo + 1) > grid) {
            /* capped: centre on the median ground point of the pixels whose
             * footprint chose this level (the bounding box also holds
             * pixels pushed up from finer windows) */
            double cxm = 0.0, cym = 0.0;
            TRY(median_point(r, l, &cxm, &cym, err));
            if ((size_t)(i_hi - i_lo + 1) > grid) {
                i_lo = (long)floor(cxm / L) - (long)grid / 2;
                i_hi = i_lo + (long)grid - 1;
            }
            if ((size_t)(j_hi - j_lo + 1) > grid) {
                j_lo = (long)floor(cym / L) - (long)grid / 2;
                j_hi = j_lo + (long)grid - 1;
            }
        }
        lv->i0 = i_lo;
        lv->j0 = j_lo;
        lv->nx = (size_t)(i_hi - i_lo + 1);
        lv->ny = (size_t)(j_hi - j_lo + 1);
        switch ((sea_facet_method)sc->method) {
        case SEA_METHOD_VARIABLE_STEP: lv->sub_n = 0; break;
        case SEA_METHOD_VARIABLE_STEP_2N: lv->sub_n = sc->n < l ? sc->n : l; break;
        case SEA_METHOD_ONE_METER: lv->sub_n = l; break;
        }
        if (lv->sub_n > 0) {
            /* The sub-facets resolve the waves between L / 2^n and L: the
             * slope variance they move from C into the spread of the mean
             * slopes.  Below the tolerance of the total, variable-step-2n
             * skips them (one-meter is the reference and keeps them). */
            sea_cov2 c_l, c_fine;
            TRY(sea_spectrum_slope_cov(&r->spec, M_PI / L, &c_l, err));
            TRY(sea_spectrum_slope_cov(&r->spec, M_PI * exp2(lv->sub_n) / L, &c_fine, err));
            const double band = (c_l.xx + c_l.yy) - (c_fine.xx + c_fine.yy);
            lv->sub_share = tr_lr > 0.0 ? fmax(band, 0.0) / tr_lr : 0.0;
            if (sc->method == SEA_METHOD_VARIABLE_STEP_2N && lv->sub_share < sc->tolerance) {
                lv->sub_n = 0;
                lv->sub_skipped = 1;
                r->choices.sub_skipped++;
            }
        }
        const size_t ext = (lv->nx > lv->ny ? lv->nx : lv->ny) << l;
        while (fft_cells < ext)
            fft_cells *= 2;
        if (l < LEVEL_MAX) {
            for (size_t q = 0; q < r->npix; q++) {
                pixel *p = &r->px[q];
                double fx, fy;
                if ((p->need & bit) && edge_weight(lv, p->x, p->y, &fx, &fy) < 1.0)
                    p->need |= bit << 1;
            }
        }
    }
    /* Every pixel falls back to a coarser level when outside its window:
     * the low-resolution level closes the chain. */
    r->used[r->first_lr] = 1;
    r->lev[r->first_lr].low_res = 1;

    if (any_hr) {
        sea_waves_params wp;
        sea_waves_params_default(&wp);
        wp.finest = L0;
        wp.seed = sc->seed;
        wp.loop_period = sc->loop_period;
        if (sc->method == SEA_METHOD_ONE_METER) {
            wp.kind = SEA_WAVES_FFT;
            if (fft_cells > 16384) {
                sea_render_free(r);
                return sea_fail(err, SEA_ERR_DOMAIN,
                                "one-meter: the levels span %zu cells of %g m, beyond the "
                                "16384-cell FFT patch; use variable-step-2n or a smaller grid",
                                fft_cells, L0);
            }
            wp.fft_size = fft_cells;
        }
        TRY(sea_waves_create(&r->spec, &wp, &r->waves, err));
        r->choices.bins_per_octave = wp.bins_per_octave;
        r->choices.directions = wp.kind == SEA_WAVES_SINUSOIDS ? wp.directions : 0;
        r->choices.wave_count = sea_waves_count(r->waves);
    }

    /* spectral samples */
    sea_response resp = { 0, NULL, NULL };
    if (sc->wavelength <= 0.0 && sc->response_file[0])
        TRY(sea_response_load(sc->response_file, &resp, err));
    size_t k = 1;
    if (sc->wavelength <= 0.0) {
        if (sc->band_samples > 0) {
            k = (size_t)sc->band_samples;
        } else {
            /* as few as the tolerance allows: double the rule until the
             * low-resolution radiance at the image centre settles */
            sea_pixel_geom g;
            sea_camera_pixel(&r->cam, 0.5 * W, 0.5 * H, &g);
            const sea_dir obs = g.hit ? g.obs : (sea_dir){ sc->look_zenith, 0.0 };
            const sea_dir sun = sea_camera_local_dir(&g, sun_vec);
            double prev = NAN;
            for (k = 2; k <= SAMPLES_AUTO_MAX; k *= 2) {
                double L, e, rho;
                st = set_samples(r, k, &resp, err);
                if (st == SEA_OK)
                    st = facet_radiance(r, &lrs, obs, sun, sun.theta < M_PI / 2.0, &L, &e, &rho,
                                        err);
                if (st != SEA_OK) {
                    sea_response_free(&resp);
                    sea_render_free(r);
                    return st;
                }
                if (fabs(L - prev) <= sc->tolerance * fabs(L))
                    break;
                prev = L;
            }
            if (k > SAMPLES_AUTO_MAX)
                k = SAMPLES_AUTO_MAX;
        }
    }
    st = set_samples(r, k, &resp, err);
    sea_response_free(&resp);
    if (st != SEA_OK) {
        sea_render_free(r);
        return st;
    }
#undef TRY
    for (int l = 0; l < SEA_CLIP_MAX_LEVELS; l++)
        if (r->used[l])
            r->compact[r->ncompact++] = r->lev[l];
    *out = r;
    return SEA_OK;
}

/* --------------------------------------------------------------- frame */

typedef struct {
    sea_moments *m[SEA_CLIP_MAX_LEVELS];
} level_data;

/* Moments of level l at (x, y) by bilinear interpolation and the weight of
 * the level there (1 inside, fading to 0 over the EDGE outer facets, 0
 * outside). */
static double level_sample(const sea_render *r, const level_data *ld, int l, double x, double y,
                           sea_moments *o)
{
    const sea_clip_level *lv = &r->lev[l];
    if (lv->low_res) {
        *o = r->lr;
        return 1.0;
    }
    if (ld->m[l] == NULL)
        return 0.0;
    double fx, fy;
    const double w = edge_weight(lv, x, y, &fx, &fy);
    if (w <= 0.0)
        return 0.0;
    const double nx = (double)lv->nx, ny = (double)lv->ny;
    const double cx = fmin(fmax(fx, 0.0), nx - 1.0), cy = fmin(fmax(fy, 0.0), ny - 1.0);
    size_t i = (size_t)cx, j = (size_t)cy;
    if (i >= lv->nx - 1)
        i = lv->nx > 1 ? lv->nx - 2 : 0;
    if (j >= lv->ny - 1)
        j = lv->ny > 1 ? lv->ny - 2 : 0;
    const double a = lv->nx > 1 ? cx - (double)i : 0.0, b = lv->ny > 1 ? cy - (double)j : 0.0;
    const size_t i1 = lv->nx > 1 ? i + 1 : i, j1 = lv->ny > 1 ? j + 1 : j;
    const sea_moments *m = ld->m[l];
    const sea_moments *q00 = &m[j * lv->nx + i], *q10 = &m[j * lv->nx + i1],
                      *q01 = &m[j1 * lv->nx + i], *q11 = &m[j1 * lv->nx + i1];
    const double w00 = (1 - a) * (1 - b), w10 = a * (1 - b), w01 = (1 - a) * b, w11 = a * b;
#define MIX(f) (w00 * q00->f + w10 * q10->f + w01 * q01->f + w11 * q11->f)
    o->mx = MIX(mx);
    o->my = MIX(my);
    o->mxx = MIX(mxx);
    o->mxy = MIX(mxy);
    o->myy = MIX(myy);
    o->h = MIX(h);
#undef MIX
    return w;
}

static void axpy(sea_moments *acc, double w, const sea_moments *m)
{
    acc->mx += w * m->mx;
    acc->my += w * m->my;
    acc->mxx += w * m->mxx;
    acc->mxy += w * m->mxy;
    acc->myy += w * m->myy;
    acc->h += w * m->h;
}

/* Level l at (x, y), faded into the coarser levels where its window ends;
 * *dominant gets the level with the largest weight. */
static void chain_sample(const sea_render *r, const level_data *ld, int l, double x, double y,
                         sea_moments *o, int *dominant)
{
    memset(o, 0, sizeof *o);
    double rest = 1.0, best = -1.0;
    for (int q = l; q <= LEVEL_MAX && rest > 0.0; q++) {
        if (!r->used[q] && q < r->first_lr)
            continue;
        sea_moments m;
        const double w = q >= r->first_lr ? 1.0 : level_sample(r, ld, q, x, y, &m);
        if (q >= r->first_lr)
            m = r->lr;
        if (w <= 0.0)
            continue;
        const double share = rest * w;
        axpy(o, share, &m);
        if (share > best) {
            best = share;
            *dominant = q;
        }
        rest -= share;
    }
}

/* The moments a pixel reads at (x, y): level l blended with neighbour nb
 * (weight alpha), each faded into coarser levels where its window ends;
 * *dominant gets the level of largest weight. */
static void mix_levels(const sea_render *r, const level_data *ld, int l, int nb, double alpha,
                       double x, double y, sea_moments *o, int *dominant)
{
    *dominant = l;
    chain_sample(r, ld, l, x, y, o, dominant);
    if (nb >= 0 && alpha > 0.0) {
        sea_moments mn;
        int domn = nb;
        chain_sample(r, ld, nb, x, y, &mn, &domn);
        sea_moments b = { 0 };
        axpy(&b, 1.0 - alpha, o);
        axpy(&b, alpha, &mn);
        *o = b;
    }
}

sea_status sea_render_view_moments(const sea_render *r,
                                   const sea_moments *const south[SEA_CLIP_MAX_LEVELS],
                                   double x, double y, int own, sea_moments *out, int *level,
                                   sea_error *err)
{
    if (own < 0 || own >= SEA_CLIP_MAX_LEVELS || !r->used[own])
        return sea_fail(err, SEA_ERR_DOMAIN, "level %d is not a level of this view", own);
    level_data ld;
    for (int l = 0; l < SEA_CLIP_MAX_LEVELS; l++)
        ld.m[l] = l < r->first_lr && r->used[l] ? (sea_moments *)south[l] : NULL;
    double q[3], n[3], u, v;
    sea_camera_sea_point(&r->cam, x, y, q, n);
    int l = own, nb = -1;
    double alpha = 0.0;
    if (sea_camera_project(&r->cam, q, &u, &v)) {
        sea_pixel_geom g;
        sea_camera_pixel(&r->cam, u, v, &g);
        if (g.hit && isfinite(g.footprint) && g.footprint > 0.0)
            choose_levels(r, log2(g.footprint / r->sc.finest), &l, &nb, &alpha);
    }
    mix_levels(r, &ld, l, nb, alpha, x, y, out, level);
    return SEA_OK;
}

sea_status sea_render_frame(const sea_render *r, double t, sea_image *img,
                            sea_progress_fn progress, void *ctx, sea_error *err)
{
    const sea_scene *sc = &r->sc;
    if (img->width != sc->width || img->height != sc->height)
        return sea_fail(err, SEA_ERR_DOMAIN, "image %d x %d does not match the scene's %d x %d",
                        img->width, img->height, sc->width, sc->height);
    if (!isfinite(t))
        return sea_fail(err, SEA_ERR_DOMAIN, "time %g s must be finite", t);
    level_data ld;
    memset(&ld, 0, sizeof ld);
    sea_status st = SEA_OK;
    for (int l = 0; l < r->first_lr && st == SEA_OK; l++) {
        const sea_clip_level *lv = &r->lev[l];
        if (!r->used[l])
            continue;
        st = sea_check_size(lv->nx * lv->ny, sizeof(sea_moments), "clipmap level", err);
        if (st != SEA_OK)
            break;
        ld.m[l] = malloc(lv->nx * lv->ny * sizeof(sea_moments));
        if (ld.m[l] == NULL) {
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for level %d", l);
            break;
        }
        const sea_rect rect = { lv->facet, lv->i0, lv->j0, lv->nx, lv->ny };
        st = sea_waves_facets(r->waves, &rect, lv->sub_n, t, ld.m[l], err);
    }
    const size_t W = (size_t)sc->width, H = (size_t)sc->height;
    double sky_L = 0.0;
    for (size_t i = 0; i < r->nsamp; i++)
        sky_L += r->wt[i] * r->lsky[i];
    const double unit = radiance_unit(r); /* per um */
    const float sky_T = (float)band_temperature(r, sky_L);
    size_t rows_done = 0;
    int failed = st != SEA_OK, cancelled = 0;
    sea_error first = { { 0 } };
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t j = 0; j < H; j++) {
        if (failed)
            continue;
        for (size_t i = 0; i < W; i++) {
            const size_t q = j * W + i;
            const pixel *p = &r->px[q];
            if (!p->hit) {
                img->radiance[q] = (float)(sky_L * unit);
                img->temperature[q] = sky_T;
                img->level[q] = 0.0f;
                img->emissivity[q] = img->reflectivity[q] = 0.0f;
                continue;
            }
            sea_moments m;
            int dom;
            mix_levels(r, &ld, p->level, p->neighbour, p->alpha, p->x, p->y, &m, &dom);
            const sea_slope_stats s = sea_moments_stats(&m);
            double L, e, rho;
            sea_error e1;
            sea_status s1 = facet_radiance(r, &s, p->obs, p->sun, p->sun_up, &L, &e, &rho, &e1);
            if (s1 == SEA_OK && !(isfinite(L) && L > 0.0 && isfinite(rho)))
                s1 = sea_fail(&e1, SEA_ERR_NUMERIC, "radiance %g at pixel (%zu, %zu)", L, i, j);
            if (s1 != SEA_OK) {
#pragma omp critical(sea_render_error)
                {
                    if (!failed)
                        first = e1;
                    failed = 1;
                }
                break;
            }
            img->radiance[q] = (float)(L * unit);
            img->temperature[q] = (float)band_temperature(r, L);
            img->level[q] = (float)r->lev[dom].facet;
            img->emissivity[q] = (float)e;
            img->reflectivity[q] = (float)rho;
        }
        if (progress != NULL) {
            int stop = 0;
#pragma omp critical(sea_render_progress)
            {
                /* any thread, one at a time: a thread that does no row
                 * must not keep a stop from being seen */
                rows_done++;
                stop = progress(ctx, (double)rows_done / (double)H) != 0;
            }
            if (stop) {
#pragma omp critical(sea_render_error)
                {
                    if (!failed) {
                        sea_fail(&first, SEA_ERR_CANCELLED, "render cancelled at row %zu of %zu",
                                 j, H);
                        cancelled = 1;
                    }
                    failed = 1;
                }
            }
        }
    }
    for (int l = 0; l < SEA_CLIP_MAX_LEVELS; l++)
        free(ld.m[l]);
    if (st != SEA_OK)
        return st;
    if (failed) {
        if (err != NULL)
            *err = first;
        return cancelled ? SEA_ERR_CANCELLED : SEA_ERR_NUMERIC;
    }
    return SEA_OK;
}
