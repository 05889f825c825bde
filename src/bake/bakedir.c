/* bakedir.c - the bake directory's writer (bakedir.h): its options, its
 * frames (computed here, or their levels handed over by a caller that
 * computed them elsewhere), what the first frame sets for every frame (the
 * emission scale, the previews' tone curves, the horizon, the manifest),
 * the exports (the sensor's image, the POV-Ray scene, the Blender script)
 * and the whole bake in one call.  The maps are bakemaps.c's, the manifest
 * manifest.c's, the atomic directory atomicdir.c's. */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bakedir_internal.h"
#include "blender.h"
#include "povray.h"

/* The emission maps carry radiance x scale, scale a power of ten putting
 * the largest radiance of the first frame at or just below this value:
 * well inside half range (65504) with its 3.3 significant digits, and
 * room for later frames' glints. */
static const double BAKE_EMISSION_TARGET = 1000.0;
/* The progress of a frame the writer computes: the computation is its
 * first COMPUTE_SHARE, the files the rest. */
static const double COMPUTE_SHARE = 0.9;
/* The horizon mesh is refined to the scene's tolerance, but no finer than
 * sea_bake_horizon_alloc takes. */
static const double BAKE_HORIZON_TOL_MIN = 1e-5;
/* Emission texels per facet side by default.  Radiance is not linear in
 * the slope moments (the glint above all), so a renderer's bilinear lookup
 * of the radiance matches seabake render's bilinear lookup of the moments
 * only on a grid finer than the facets; and the grid must hold the facet
 * centres, where the interpolated moments have their kinks, or the error
 * is of first order (an even K, measured, is worse than K = 1).  Relative
 * RMS difference POV-Ray vs seabake render, tests/scenes/pov_slant.ini
 * (oblique) and pov_glint.ini (nadir): K = 1, 2.9 % and 0.65 %; K = 3,
 * 0.61 % and 0.23 %; K = 5, 0.25 % and 0.095 %; K = 7, 0.15 % and
 * 0.055 %. */
enum { BAKE_VIEW_K_DEFAULT = 3 };
/* The frame rate of seabake bake --frames without --frame-rate. */
static const double BAKE_FRAME_RATE_DEFAULT = 25.0;

double sea_bakedir_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---------------------------------------------------------------- options */

void sea_bake_options_default(sea_bake_options *o)
{
    memset(o, 0, sizeof *o);
    o->exr.pixel = SEA_EXR_FLOAT;
    o->exr.compression = SEA_EXR_ZIP;
    o->frame_rate = BAKE_FRAME_RATE_DEFAULT;
    o->view_k = BAKE_VIEW_K_DEFAULT;
    o->emission_space = SEA_BAKE_SPACE_SENSOR;
    o->previews = 1;
}

double sea_bake_options_frame_time(const sea_bake_options *o, double time0, long f)
{
    return o->framed ? time0 + (double)f / o->frame_rate : time0;
}

sea_status sea_bake_options_check(const sea_bake_options *o, const sea_scene *sc, sea_error *err)
{
    if (sc != NULL && !isnan(sc->polarizer))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "[sensor] polarizer = %.6g deg: a bake's maps are the radiance I (allowed: "
                        "no polarizer in a scene to bake; seabake render applies one)",
                        sc->polarizer * 180.0 / M_PI);
    if (o->exr.pixel != SEA_EXR_FLOAT && o->exr.pixel != SEA_EXR_HALF)
        return sea_fail(err, SEA_ERR_DOMAIN, "bake options: exr.pixel %d is not float or half",
                        (int)o->exr.pixel);
    if (o->exr.compression != SEA_EXR_NONE && o->exr.compression != SEA_EXR_ZIP &&
        o->exr.compression != SEA_EXR_PIZ)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "bake options: exr.compression %d is not none, zip or piz",
                        (int)o->exr.compression);
    if (o->view_k < 1 || o->view_k > SEA_BAKE_VIEW_K_MAX || o->view_k % 2 == 0)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "bake options: view_k %d is not odd in [1, %d] (the emission texels "
                        "must hold the facet centres)",
                        o->view_k, SEA_BAKE_VIEW_K_MAX);
    if (o->emission_space != SEA_BAKE_SPACE_SENSOR && o->emission_space != SEA_BAKE_SPACE_MAP)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "bake options: emission_space %d is not sensor or map",
                        (int)o->emission_space);
    if (o->framed) {
        if (!(o->first >= 0 && o->first <= o->last && o->last <= SEA_BAKE_FRAME_MAX))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "bake options: frames %ld to %ld are not 0 <= first <= last <= %d",
                            o->first, o->last, SEA_BAKE_FRAME_MAX);
        if (o->last - o->first >= SEA_BAKE_FRAMES_MAX)
            return sea_fail(err, SEA_ERR_DOMAIN, "bake options: %ld frames, more than %d",
                            o->last - o->first + 1, SEA_BAKE_FRAMES_MAX);
        if (!(o->frame_rate > 0.0) || !isfinite(o->frame_rate))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "bake options: frame_rate %g Hz is not finite and > 0",
                            o->frame_rate);
        /* time + f / rate runs monotonically from the first frame to the
         * last: the two ends bound every frame's time */
        const long ends[2] = {o->first, o->last};
        for (int k = 0; k < 2; k++) {
            const double t = sea_bake_options_frame_time(o, sc->time, ends[k]);
            if (!(fabs(t) <= SEA_TIME_MAX))
                return sea_fail(err, SEA_ERR_DOMAIN,
                                "bake options: frame %ld at %g s is outside [%.10g, %.10g] s",
                                ends[k], t, -SEA_TIME_MAX, SEA_TIME_MAX);
        }
    }
    return SEA_OK;
}

/* ------------------------------------------------------- the exports' sky */

_Static_assert(SEA_BAKE_SKY_MAX <= SEA_POV_SKY_MAX, "the sky table is a POV-Ray color_map");

/* The table starts with SKY_START nodes uniform in s; the interval whose
 * linear interpolation misses the sky most (at SKY_PROBES points evenly
 * inside it, relative) is halved until every interval is within SKY_TOL or
 * the table is full; max_err is then measured at SKY_MEASURE points inside
 * every interval.  Measured on clear skies at 10 um (256 nodes each; the
 * figures agree with a check against the formula at 4e5 points): zenith
 * emissivity 0.7, 1.9e-6; 0.3, 8.4e-6; 0.1, 2.8e-5; 0.01, 1.3e-4, all well
 * below half-float rounding (4.9e-4).  256 nodes uniform in s gave 1.7e-5,
 * 5.6e-5 and 5.8e-4 at 0.3, 0.1 and 0.01; uniform in cos zenith 3.9e-5,
 * 4.4e-4 and 3.3e-2. */
enum { SKY_START = 17, SKY_PROBES = 7, SKY_MEASURE = 64 };
static const double SKY_TOL = 1e-7;
/* Relative errors are taken against at least this fraction of the
 * table's largest value (a table's sky may be 0 somewhere). */
static const double SKY_FLOOR = 1e-6;

static double sky_at(const sea_view *r, double s)
{
    return sea_view_sky_toward(r, s * s);
}

/* The largest relative error of the interpolation over interval i of t,
 * at probes points evenly inside it. */
static double sky_interval_error(const sea_view *r, const sea_bake_sky *t, size_t i,
                                 int probes, double vmax)
{
    double e = 0.0;
    for (int j = 1; j <= probes; j++) {
        const double a = (double)j / (double)(probes + 1);
        const double exact = sky_at(r, (1.0 - a) * t->s[i] + a * t->s[i + 1]);
        const double lin = (1.0 - a) * t->value[i] + a * t->value[i + 1];
        e = fmax(e, fabs(lin - exact) / fmax(fabs(exact), SKY_FLOOR * vmax));
    }
    return e;
}

void sea_bakedir_sky_table(const sea_view *r, sea_bake_sky *t)
{
    memset(t, 0, sizeof *t);
    if (sea_view_scene(r)->sky_model == SEA_SKY_ISOTROPIC)
        return;
    double vmax = 0.0, err[SEA_BAKE_SKY_MAX];
    t->n = SKY_START;
    for (size_t i = 0; i < t->n; i++) {
        t->s[i] = (double)i / (double)(t->n - 1);
        t->value[i] = sky_at(r, t->s[i]);
        vmax = fmax(vmax, fabs(t->value[i]));
    }
    for (size_t i = 0; i + 1 < t->n; i++)
        err[i] = sky_interval_error(r, t, i, SKY_PROBES, vmax);
    while (t->n < SEA_BAKE_SKY_MAX) {
        size_t w = 0;
        for (size_t i = 1; i + 1 < t->n; i++)
            if (err[i] > err[w])
                w = i;
        if (!(err[w] > SKY_TOL))
            break;
        /* the midpoint of interval w becomes node w + 1 */
        memmove(&t->s[w + 2], &t->s[w + 1], (t->n - w - 1) * sizeof t->s[0]);
        memmove(&t->value[w + 2], &t->value[w + 1], (t->n - w - 1) * sizeof t->value[0]);
        memmove(&err[w + 2], &err[w + 1], (t->n - w - 2) * sizeof err[0]);
        t->n++;
        t->s[w + 1] = 0.5 * (t->s[w] + t->s[w + 2]);
        t->value[w + 1] = sky_at(r, t->s[w + 1]);
        vmax = fmax(vmax, fabs(t->value[w + 1]));
        err[w] = sky_interval_error(r, t, w, SKY_PROBES, vmax);
        err[w + 1] = sky_interval_error(r, t, w + 1, SKY_PROBES, vmax);
    }
    t->max_err = 0.0;
    for (size_t i = 0; i + 1 < t->n; i++)
        t->max_err = fmax(t->max_err, sky_interval_error(r, t, i, SKY_MEASURE, vmax));
}

/* ------------------------------------------------------------ the writer */

/* Gives progress the fraction f of the whole bake; non-zero: stop. */
static int report(sea_bake_writer *w, double f)
{
    w->reported = f;
    return w->progress != NULL && w->progress(w->ctx, f) != 0;
}

int sea_bakedir_cancelled(sea_bake_writer *w)
{
    return w->progress != NULL && w->progress(w->ctx, w->reported) != 0;
}

/* The writer's failures: it takes nothing more but its free. */
static sea_status failed(sea_bake_writer *w, sea_status st)
{
    if (st != SEA_OK)
        w->failed = 1;
    return st;
}

static sea_status usable(const sea_bake_writer *w, sea_error *err)
{
    return w->failed ? sea_fail(err, SEA_ERR_DOMAIN, "the bake writer failed before") : SEA_OK;
}

sea_status sea_bake_writer_alloc(const sea_view *r, const sea_bake_options *o, const char *dir,
                                 sea_progress_fn progress, void *ctx, sea_bake_writer **out,
                                 sea_error *err)
{
    *out = NULL;
    const sea_scene *sc = sea_view_scene(r);
    sea_status st = sea_bake_options_check(o, sc, err);
    if (st != SEA_OK)
        return st;
    sea_bake_writer *w = calloc(1, sizeof *w);
    if (w == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    w->r = r;
    w->sc = sc;
    w->o = *o;
    w->progress = progress;
    w->ctx = ctx;
    w->sensor = (o->pov || o->blender) && o->emission_space == SEA_BAKE_SPACE_SENSOR;
    w->first = o->framed ? o->first : 0;
    w->last = o->framed ? o->last : 0;
    w->next = w->first;
    w->n_frames = (size_t)(w->last - w->first + 1);
    w->scale = 1.0;
    if ((w->dir = strdup(dir)) == NULL ||
        (o->scene_file != NULL && (w->scene_file = strdup(o->scene_file)) == NULL))
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    w->o.scene_file = w->scene_file;
    const sea_clip_level *lv;
    w->nlev = sea_view_levels(r, &lv);
    w->nmax = 1;
    for (size_t l = 0; l < w->nlev; l++)
        if (!lv[l].low_res && lv[l].nx * lv[l].ny > w->nmax)
            w->nmax = lv[l].nx * lv[l].ny;
    /* as many writers of a level's files as there are groups besides the
     * emission map, which compresses on a team of its own */
    w->threads = 1;
#ifdef _OPENMP
    w->threads = (size_t)omp_get_max_threads();
#endif
    if (w->threads > BAKE_N_GROUPS - 1)
        w->threads = BAKE_N_GROUPS - 1;
    if (w->threads < 1)
        w->threads = 1;
    const size_t k2 = (size_t)(o->view_k * o->view_k);
    /* each writer's GROUP_CH_MAX channels, and the emission map's K x K
     * texels per facet */
    if (st == SEA_OK)
        st = sea_check_size(w->nmax, (w->threads * GROUP_CH_MAX + k2) * sizeof(float),
                            "map buffers", err);
    if (st == SEA_OK) {
        w->pool = malloc(w->threads * GROUP_CH_MAX * w->nmax * sizeof(float));
        w->emission = malloc(k2 * w->nmax * sizeof(float));
        if (w->pool == NULL || w->emission == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the map buffers");
    }
    /* the exports' waves: each frame's height range of each level */
    if (st == SEA_OK && w->sensor &&
        (st = sea_check_size(w->n_frames, 2 * w->nlev * sizeof(double), "height ranges", err)) ==
            SEA_OK) {
        if ((w->height_lo = calloc(2 * w->nlev * w->n_frames, sizeof(double))) == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the height ranges");
        else
            w->height_hi = w->height_lo + w->nlev * w->n_frames;
    }
    if (st != SEA_OK) {
        sea_bake_writer_free(w);
        return st;
    }
    *out = w;
    return SEA_OK;
}

void sea_bake_writer_free(sea_bake_writer *w)
{
    if (w == NULL)
        return;
    cJSON_Delete(w->manifest);
    if (w->have_hz)
        sea_bake_horizon_free(&w->hz);
    free(w->height_lo);
    free(w->pool);
    free(w->emission);
    free(w->dir);
    free(w->scene_file);
    free(w);
}

long sea_bake_writer_next_frame(const sea_bake_writer *w)
{
    return w->next;
}

int sea_bake_writer_wants_view(const sea_bake_writer *w)
{
    return w->sensor;
}

void sea_bake_writer_stats(const sea_bake_writer *w, sea_bake_stats *out)
{
    *out = w->stats;
}

/* ------------------------------------------------------------ a frame */

sea_status sea_bake_writer_frame_begin(sea_bake_writer *w, long frame, sea_error *err)
{
    sea_status st = usable(w, err);
    if (st != SEA_OK)
        return st;
    if (w->in_frame || frame != w->next || frame > w->last)
        return failed(w, sea_fail(err, SEA_ERR_DOMAIN,
                                  "bake writer: frame %ld begun where frame %ld was due%s", frame,
                                  w->next, w->in_frame ? " (the last one not ended)" : ""));
    w->in_frame = 1;
    w->frame = frame;
    w->t = sea_bake_options_frame_time(&w->o, w->sc->time, frame);
    w->defer = frame == w->first;
    w->top = 0.0;
    w->written = 0;
    if (report(w, (double)(frame - w->first) / (double)w->n_frames))
        return failed(w, sea_fail(err, SEA_ERR_CANCELLED, "bake cancelled before frame %ld",
                                  frame));
    return SEA_OK;
}

/* SEA_OK when level l of b is one of the writer's levels (the same
 * preparation), with maps, not yet written this frame. */
static sea_status check_level(const sea_bake_writer *w, const sea_bake *b, size_t l,
                              sea_error *err)
{
    const sea_clip_level *lv;
    const size_t nlev = sea_view_levels(w->r, &lv);
    if (b->n_levels != nlev || l >= nlev)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "bake writer: level %zu of a bake of %zu levels, not this one's %zu", l,
                        b->n_levels, nlev);
    const sea_bake_level *bl = &b->levels[l];
    if (lv[l].low_res || bl->level.low_res || bl->level.nx != lv[l].nx ||
        bl->level.ny != lv[l].ny || bl->level.level != lv[l].level ||
        bl->view_k != (size_t)w->o.view_k || bl->moments == NULL || bl->optics == NULL ||
        bl->view == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "bake writer: level %zu is not a high-resolution level of this bake "
                        "with its maps (view_k %d)",
                        l, w->o.view_k);
    if (w->written & (1ul << l))
        return sea_fail(err, SEA_ERR_DOMAIN, "bake writer: level %zu of frame %ld written twice",
                        l, w->frame);
    return SEA_OK;
}

sea_status sea_bake_writer_level(void *writer, const sea_bake *b, size_t l, sea_error *err)
{
    sea_bake_writer *w = writer;
    sea_status st = usable(w, err);
    if (st != SEA_OK)
        return st;
    if (!w->in_frame)
        return failed(w, sea_fail(err, SEA_ERR_DOMAIN, "bake writer: a level outside a frame"));
    if ((st = check_level(w, b, l, err)) != SEA_OK)
        return failed(w, st);
    if (sea_bakedir_cancelled(w))
        return failed(w, sea_fail(err, SEA_ERR_CANCELLED, "bake cancelled writing level %d",
                                  b->levels[l].level.level));
    const double t0 = sea_bakedir_seconds();
    st = sea_bakemaps_level(w, b, l, err);
    w->written |= 1ul << l;
    w->stats.files += sea_bakedir_seconds() - t0;
    return failed(w, st);
}

/* The emission scale: a power of ten putting the largest radiance top (of
 * the HR texels, their view texels, the LR constants, the horizon and the
 * sensor's image) at or below BAKE_EMISSION_TARGET. */
static double emission_scale(double top)
{
    if (!(top > 0.0) || !isfinite(top))
        return 1.0;
    return pow(10.0, floor(log10(BAKE_EMISSION_TARGET / top)));
}

/* SEA_BAKE_HORIZON_MAP texel q: the farthest ring on row 0 (so that the
 * nadir is the bottom row, v = 0). */
static double horizon_texel(const void *ctx, size_t q)
{
    const sea_bake_horizon *hz = ctx;
    const size_t w = hz->n_az, i = hz->n_arc - 1 - q / w;
    return hz->radiance[i * w + q % w];
}

static double image_texel(const void *ctx, size_t q)
{
    return ((const sea_image *)ctx)->radiance[q];
}

/* What the first frame sets for every frame: the horizon (the exports'),
 * the emission scale (from the largest radiance of the frame's levels, the
 * horizon and the sensor's image), the manifest, the horizon's map, the
 * previews' tone curves; then the frame's deferred files. */
static sea_status first_frame(sea_bake_writer *w, const sea_bake *b, const sea_image *view,
                              sea_error *err)
{
    sea_status st = SEA_OK;
    if (w->o.pov || w->o.blender) {
        /* one for all frames: time does not enter */
        const double t0 = sea_bakedir_seconds();
        st = sea_bake_horizon_alloc(w->r, fmax(BAKE_HORIZON_TOL_MIN, w->sc->tolerance), &w->hz,
                                   err);
        w->have_hz = st == SEA_OK;
        const double dt = sea_bakedir_seconds() - t0;
        w->stats.maps += dt;
        w->stats.files -= dt; /* (counted as computing, not writing) */
        if (st != SEA_OK)
            return st;
    }
    /* a directional sky's table: its values count toward the scale (an
     * isotropic sky's never did: its scale, and so its files, stay) */
    sea_bakedir_sky_table(w->r, &w->sky);
    double top = w->top;
    for (size_t q = 0; q < w->sky.n; q++)
        top = fmax(top, w->sky.value[q]);
    for (size_t l = 0; l < b->n_levels; l++)
        top = fmax(top, b->levels[l].lr_optics.radiance);
    for (size_t q = 0; w->have_hz && q < w->hz.n_arc * w->hz.n_az; q++)
        top = fmax(top, w->hz.radiance[q]);
    for (size_t q = 0; view != NULL && q < (size_t)view->width * (size_t)view->height; q++)
        top = fmax(top, view->radiance[q]);
    w->top = top;
    w->scale = emission_scale(top);
    for (size_t q = 0; q < w->sky.n; q++)
        w->sky.value[q] *= w->scale;
    if ((w->manifest = sea_manifest_alloc(w, b)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    if (w->have_hz) {
        char err_s[32];
        snprintf(err_s, sizeof err_s, "%.3g", w->hz.max_err);
        st = sea_bakemaps_grey(w, SEA_BAKE_HORIZON_MAP, w->hz.n_az, w->hz.n_arc, horizon_texel,
                               &w->hz, "horizon", "seabake:max_error", err_s, err);
    }
    if (st == SEA_OK && w->o.previews)
        st = sea_bakemaps_previews_setup(w, b, err);
    if (st == SEA_OK)
        st = sea_bakemaps_spilled(w, b, err);
    for (size_t l = 0; l < b->n_levels && l < SEA_CLIP_MAX_LEVELS; l++)
        w->lr_radiance[l] = b->levels[l].lr_optics.radiance;
    return st;
}

/* The sensor's image of the frame: Y = the radiance seabake render gives
 * each pixel x scale, row 0 at the top, sensor[_FFFF].exr (its name into
 * name). */
static sea_status write_sensor(sea_bake_writer *w, const sea_image *img, char name[64],
                               sea_error *err)
{
    char time_s[32];
    if (w->o.framed)
        snprintf(name, 64, "%s%0*ld.exr", SEA_BAKE_SENSOR_PREFIX, SEA_BAKE_FRAME_DIGITS,
                 w->frame);
    else
        snprintf(name, 64, "sensor.exr");
    snprintf(time_s, sizeof time_s, "%.17g", w->t);
    return sea_bakemaps_grey(w, name, (size_t)img->width, (size_t)img->height, image_texel, img,
                             "sensor", "seabake:time_s", time_s, err);
}

sea_status sea_bake_writer_frame_end(sea_bake_writer *w, const sea_bake *b, const sea_image *view,
                                     sea_error *err)
{
    sea_status st = usable(w, err);
    if (st != SEA_OK)
        return st;
    if (!w->in_frame)
        return failed(w, sea_fail(err, SEA_ERR_DOMAIN, "bake writer: no frame to end"));
    const sea_camera *cam = sea_view_camera(w->r);
    if (w->sensor && (view == NULL || view->radiance == NULL || view->width != cam->width ||
                      view->height != cam->height))
        return failed(w, sea_fail(err, SEA_ERR_DOMAIN,
                                  "bake writer: frame %ld needs the sensor's %d x %d image",
                                  w->frame, cam->width, cam->height));
    if (b->n_levels != w->nlev)
        return failed(w, sea_fail(err, SEA_ERR_DOMAIN,
                                  "bake writer: a bake of %zu levels, not this one's %zu",
                                  b->n_levels, w->nlev));
    for (size_t l = 0; l < b->n_levels; l++)
        if (!b->levels[l].level.low_res && !(w->written & (1ul << l)))
            return failed(w, sea_fail(err, SEA_ERR_DOMAIN,
                                      "bake writer: level %zu of frame %ld was not written", l,
                                      w->frame));
    const double t0 = sea_bakedir_seconds();
    if (w->manifest == NULL)
        st = first_frame(w, b, w->sensor ? view : NULL, err);
    char sensor_name[64] = "";
    if (st == SEA_OK && w->sensor)
        st = write_sensor(w, view, sensor_name, err);
    if (st == SEA_OK)
        st = sea_manifest_frame(w, b, w->sensor ? sensor_name : NULL, err);
    w->stats.files += sea_bakedir_seconds() - t0;
    if (st != SEA_OK)
        return failed(w, st);
    w->in_frame = 0;
    w->next = w->frame + 1;
    if (report(w, (double)(w->frame - w->first + 1) / (double)w->n_frames))
        return failed(w, sea_fail(err, SEA_ERR_CANCELLED, "bake cancelled after frame %ld",
                                  w->frame));
    return SEA_OK;
}

/* The computation's progress within the frame, as a share of the bake. */
static int compute_progress(void *ctx, double fraction)
{
    sea_bake_writer *w = ctx;
    const double k = (double)(w->frame - w->first);
    return report(w, (k + COMPUTE_SHARE * fraction) / (double)w->n_frames);
}

sea_status sea_bake_writer_frame(sea_bake_writer *w, sea_error *err)
{
    sea_status st = sea_bake_writer_frame_begin(w, w->next, err);
    if (st != SEA_OK)
        return st;
    /* the sensor's image of this frame, as seabake render gives it, made by
     * the bake from the surfaces of its levels */
    sea_image view = {0};
    const sea_camera *cam = sea_view_camera(w->r);
    if (w->sensor && (st = sea_image_alloc(cam->width, cam->height, &view, err)) != SEA_OK)
        return failed(w, st);
    const double written = w->stats.files, t0 = sea_bakedir_seconds();
    sea_bake b;
    if (w->sensor)
        st = sea_bake_frame_image(w->r, w->t, w->o.view_k, &view, &b, compute_progress, w,
                                  sea_bake_writer_level, w, err);
    else
        st = sea_bake_frame_each(w->r, w->t, w->o.view_k, &b, compute_progress, w,
                                 sea_bake_writer_level, w, err);
    /* the computing is what the levels' files did not take */
    w->stats.maps += sea_bakedir_seconds() - t0 - (w->stats.files - written);
    if (st == SEA_OK) {
        w->stats.parts.waves += b.seconds.waves;
        w->stats.parts.image += b.seconds.image;
        w->stats.parts.optics += b.seconds.optics;
        w->stats.parts.view += b.seconds.view;
        st = sea_bake_writer_frame_end(w, &b, w->sensor ? &view : NULL, err);
        sea_bake_free(&b);
    }
    sea_image_free(&view);
    return failed(w, st);
}

/* ------------------------------------------------------------ the finish */

/* The POV-Ray scene: one ring per level (finest first), each with its
 * emission map (with frames, the map of POV-Ray's frame_number) and the
 * next finer level cut out; the low-resolution level as the horizon mesh
 * (SEA_BAKE_HORIZON_MAP); the scene's spectral samples for
 * Seabake_Blackbody.  With the sensor's image the rings carry the waves:
 * each level's height samples over their range of each frame. */
static sea_status write_pov(const sea_bake_writer *w, sea_error *err)
{
    sea_pov_level pl[SEA_CLIP_MAX_LEVELS];
    char *names[SEA_CLIP_MAX_LEVELS] = {NULL}, *heights[SEA_CLIP_MAX_LEVELS] = {NULL};
    size_t n = 0;
    sea_status st = SEA_OK;
    const sea_view *r = w->r;
    const sea_camera *cam = sea_view_camera(r);
    /* the low-resolution ring without a horizon mesh: out to 1000
     * altitudes, where a grazing ray meets the sea at 0.06 degrees */
    const double far = 1000.0 * w->sc->altitude;
    const sea_clip_level *levels;
    const size_t nlev = sea_view_levels(r, &levels);
    const sea_bake_horizon *hz = w->have_hz ? &w->hz : NULL;
    const double scale = w->scale;
    for (size_t l = 0; l < nlev && st == SEA_OK; l++) {
        const sea_clip_level *lv = &levels[l];
        if (lv->low_res && hz != NULL)
            continue; /* the horizon mesh shows it */
        sea_pov_level *p = &pl[n];
        memset(p, 0, sizeof *p);
        p->level = lv->level;
        p->facet = lv->facet;
        if (lv->low_res) {
            p->x0 = cam->pos[0] - far;
            p->y0 = cam->pos[1] - far;
            p->w = p->h = 2.0 * far;
            p->constant = w->lr_radiance[l] * scale;
        } else {
            p->x0 = (double)lv->i0 * lv->facet;
            p->y0 = (double)lv->j0 * lv->facet;
            p->w = (double)lv->nx * lv->facet;
            p->h = (double)lv->ny * lv->facet;
            /* with frames, the names up to the frame number */
            names[n] = w->o.framed ? sea_bakemaps_name("emission", lv->level, 0, 0, "_")
                                   : sea_bakemaps_name("emission", lv->level, 0, 0, ".exr");
            if (names[n] == NULL)
                st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
            p->emission_file = names[n];
            if (w->sensor) {
                heights[n] = w->o.framed ? sea_bakemaps_name("height", lv->level, 0, 0, "_")
                                         : sea_bakemaps_name("height", lv->level, 0, 0, ".png");
                if (heights[n] == NULL)
                    st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
                p->height_file = heights[n];
                p->height_samples = sea_bakemaps_height_samples(lv);
                p->height_lo = w->height_lo + l * w->n_frames;
                p->height_hi = w->height_hi + l * w->n_frames;
            }
        }
        if (n > 0) {
            p->has_hole = 1;
            p->hx0 = pl[n - 1].x0;
            p->hy0 = pl[n - 1].y0;
            p->hw = pl[n - 1].w;
            p->hh = pl[n - 1].h;
        }
        n++;
    }
    const double *wl, *wt;
    sea_pov_options o = {w->o.framed,
                         w->o.framed ? w->o.first : 0,
                         w->o.framed ? w->o.last : 0,
                         SEA_BAKE_FRAME_DIGITS,
                         w->sc->time,
                         w->o.frame_rate,
                         sea_view_samples(r, &wl, &wt),
                         NULL,
                         NULL,
                         w->sc->wavelength > 0.0 ? 1e-6 : 1.0,
                         hz,
                         SEA_BAKE_HORIZON_MAP,
                         NULL,
                         /* a directional sky by direction; its horizon's value for
                          * the rest */
                         w->sky.n,
                         w->sky.s,
                         w->sky.value,
                         w->sky.max_err};
    if (w->sensor)
        o.sensor_file = w->o.framed ? SEA_BAKE_SENSOR_PREFIX : "sensor.exr";
    o.wavelength = wl;
    o.weight = wt;
    const double sky = w->sky.n > 0 ? w->sky.value[0] : sea_manifest_sky_radiance(r) * scale;
    if (st == SEA_OK)
        st = sea_pov_write(w->dir, cam, pl, n, sky, scale, &o, err);
    for (size_t l = 0; l < SEA_CLIP_MAX_LEVELS; l++) {
        free(names[l]);
        free(heights[l]);
    }
    return st;
}

sea_status sea_bake_writer_finish(sea_bake_writer *w, sea_error *err)
{
    sea_status st = usable(w, err);
    if (st != SEA_OK)
        return st;
    if (w->in_frame || w->next <= w->last)
        return failed(w, sea_fail(err, SEA_ERR_DOMAIN,
                                  "bake writer: finished before frame %ld was written", w->next));
    const double t0 = sea_bakedir_seconds();
    if (w->o.pov)
        st = write_pov(w, err);
    if (st == SEA_OK && w->o.blender)
        st = sea_blender_write_script(w->dir, err);
    if (st == SEA_OK)
        st = sea_manifest_write(w, err);
    w->stats.files += sea_bakedir_seconds() - t0;
    return failed(w, st);
}

/* ------------------------------------------------------------ one call */

sea_status sea_bake_write(const sea_view *r, const sea_bake_options *o, const char *path,
                          sea_progress_fn progress, void *ctx, sea_bake_stats *stats,
                          sea_error *err)
{
    if (stats != NULL)
        memset(stats, 0, sizeof *stats);
    /* the options first: nothing is made for a bake that cannot run */
    sea_status st = sea_bake_options_check(o, sea_view_scene(r), err);
    if (st != SEA_OK)
        return st;
    const sea_bake_dir_hooks hooks = {NULL, NULL, progress, ctx};
    sea_bake_dir *d = NULL;
    sea_bake_writer *w = NULL;
    if ((st = sea_bake_dir_begin(path, &hooks, &d, err)) != SEA_OK)
        return st;
    st = sea_bake_writer_alloc(r, o, sea_bake_dir_path(d), progress, ctx, &w, err);
    while (st == SEA_OK && sea_bake_writer_next_frame(w) <= w->last)
        st = sea_bake_writer_frame(w, err);
    if (st == SEA_OK)
        st = sea_bake_writer_finish(w, err);
    if (st == SEA_OK)
        st = sea_bake_dir_commit(d, err);
    if (stats != NULL && w != NULL)
        sea_bake_writer_stats(w, stats);
    sea_bake_writer_free(w);
    sea_bake_dir_free(d);
    return st;
}
