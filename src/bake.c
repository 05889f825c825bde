/* bake.c - maps of every clipmap level at one time (issue 5): the facet
 * moments of each high-resolution level of the multiresolution sea's frame
 * (exactly as sea_waves_facets gives them), flipped to north-up rows, the
 * optics of each facet toward the sensor, and the view maps: what the
 * sensor sees along the ray through each map point, asked of the
 * multiresolution sea as seabake render asks it (sea_multires_look_at);
 * low-resolution levels are constants.  The derived renderer maps (normal,
 * roughness) are small total functions of the moments.
 *
 * Nothing here writes files: the bake directory's writer (bakedir.c,
 * <seabake/bakedir.h>) turns a sea_bake into EXR maps, previews and a
 * manifest. */
#include "config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "seabake.h"
#include "internal.h"

static void level_free(sea_bake_level *bl)
{
    free(bl->moments);
    free(bl->optics);
    free(bl->view);
    bl->moments = NULL;
    bl->optics = NULL;
    bl->view = NULL;
}

void sea_bake_free(sea_bake *b)
{
    if (b == NULL)
        return;
    for (size_t l = 0; l < b->n_levels; l++)
        level_free(&b->levels[l]);
    memset(b, 0, sizeof *b);
}

/* Directions from the sea point (x, y) toward the sensor and the sun, in
 * the local frame there, and the range from the sensor to it, m. */
static void texel_dirs(const sea_camera *c, const double sun_vec[3], double x, double y,
                       sea_dir *obs, sea_dir *sun, double *range)
{
    sea_pixel_geom g;
    memset(&g, 0, sizeof g);
    double q[3];
    sea_camera_sea_point(c, x, y, q, g.normal);
    double d[3] = { c->pos[0] - q[0], c->pos[1] - q[1], c->pos[2] - q[2] };
    const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    *range = len;
    for (int i = 0; i < 3; i++)
        d[i] /= len;
    *obs = sea_camera_local_dir(&g, d);
    /* A texel at or beyond the sensor's horizon (a sensor a hair above
     * the sea, where the window's far texels round to 90 deg, or a round
     * Earth's horizon inside a clipmap window) is given the optics of the
     * grazing view, their limit, as the horizon mesh is: render never
     * sees it, and 90 deg itself is outside the optics' domain. */
    if (!(obs->theta < M_PI_2))
        obs->theta = nextafter(M_PI_2, 0.0);
    *sun = sea_camera_local_dir(&g, sun_vec);
}

/* The arrays of one high-resolution level: its optics and view texels,
 * and (copy) its facet moments, north first, from the frame's (rows south
 * first).  The arrays are spare's, the level before's once handed to the
 * caller (sea_bake_frame_each), when they have room (its level's facets,
 * view_k alike): the clipmap's levels have one size, and fresh arrays
 * would be faulted in page by page again (at 2048^2 facets and K = 3, 440
 * MB a level).  Without copy the level's moments are the frame's own,
 * turned north first in place while the caller reads them (bake_frame):
 * 24 bytes a facet less held (100 MB a level at 2048^2 facets). */
static sea_status level_arrays(const sea_multires_frame *f, sea_bake_level *bl,
                               sea_bake_level *spare, int copy, sea_error *err)
{
    const sea_clip_level *lv = &bl->level;
    const size_t nx = lv->nx, ny = lv->ny, n = nx * ny, k2 = bl->view_k * bl->view_k;
    sea_status st = sea_check_size(n, sizeof(sea_facet) + sizeof(sea_facet_optics) +
                                          k2 * (sizeof(float) + 2),
                                   "bake level", err);
    if (st != SEA_OK)
        return st;
    if (spare->optics != NULL && spare->level.nx * spare->level.ny >= n &&
        (spare->moments != NULL || !copy)) {
        bl->optics = spare->optics;
        bl->view = spare->view;
        bl->moments = copy ? spare->moments : NULL;
        spare->optics = NULL;
        spare->view = NULL;
        if (copy)
            spare->moments = NULL;
        level_free(spare);
    } else {
        level_free(spare);
        bl->optics = malloc(n * sizeof *bl->optics);
        bl->view = malloc(n * k2 * sizeof *bl->view);
        if (copy)
            bl->moments = malloc(n * sizeof *bl->moments);
    }
    if (bl->optics == NULL || bl->view == NULL || (copy && bl->moments == NULL))
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for level %d (%zu x %zu texels)",
                        lv->level, nx, ny);
    if (copy) {
        const sea_facet *south = sea_heightfield_facets(sea_multires_frame_level(f, lv->level));
#pragma omp parallel for schedule(static)
        for (size_t row = 0; row < ny; row++)
            memcpy(bl->moments + row * nx, south + (ny - 1 - row) * nx, nx * sizeof *south);
    }
    return SEA_OK;
}

/* The optics of a texel at range (m) from the sensor, with what the
 * sensor receives of it across the air (o->seen). */
static sea_status texel_optics(const sea_view *r, sea_slope_stats s, sea_dir obs, sea_dir sun,
                               double range, sea_facet_optics *o, const sea_bake_level *bl,
                               size_t i, size_t row, sea_error *err)
{
    sea_status st = sea_view_facet_seen(r, &s, obs, sun, range, o, err);
    if (st == SEA_OK &&
        !(isfinite(o->radiance) && isfinite(o->reflectivity) && isfinite(o->seen)))
        st = sea_fail(err, SEA_ERR_NUMERIC, "radiance %g at texel (%zu, %zu) of level %d",
                      o->radiance, i, row, bl->level.level);
    return st;
}

/* Where the view texels are worth computing: those the sensor sees (their
 * centre projects into the image, onto the sea) outside the hole (x0, y0,
 * x1, y1: the next finer level's rectangle, shown instead), and within
 * VIEW_MARGIN texels of them, which a renderer's bilinear lookup reaches. */
enum { VIEW_MARGIN = 2 };
static unsigned char *view_mask(const sea_camera *cam, const sea_clip_level *lv, size_t k,
                                const double hole[4])
{
    const size_t vx = k * lv->nx, vy = k * lv->ny;
    unsigned char *seen = calloc(vx * vy, 1), *mask = calloc(vx * vy, 1);
    if (seen == NULL || mask == NULL) {
        free(seen);
        free(mask);
        return NULL;
    }
    const double cell = lv->facet / (double)k;
#pragma omp parallel for schedule(static)
    for (size_t R = 0; R < vy; R++) {
        const double y = (double)lv->j0 * lv->facet + ((double)(vy - R) - 0.5) * cell;
        for (size_t i = 0; i < vx; i++) {
            const double x = (double)lv->i0 * lv->facet + ((double)i + 0.5) * cell;
            if (hole != NULL && x > hole[0] && x < hole[2] && y > hole[1] && y < hole[3])
                continue;
            double q[3], n[3], u, v;
            sea_camera_sea_point(cam, x, y, q, n);
            if (!sea_camera_project(cam, q, &u, &v) || !(u >= 0.0 && u <= cam->width) ||
                !(v >= 0.0 && v <= cam->height))
                continue;
            seen[R * vx + i] = (unsigned char)sea_camera_hits(cam, u, v);
        }
    }
    /* within VIEW_MARGIN of a seen texel (the square around it): along the
     * rows into mask, then along the columns back into seen */
#pragma omp parallel for schedule(static)
    for (size_t R = 0; R < vy; R++) {
        const unsigned char *in = seen + R * vx;
        unsigned char *out = mask + R * vx;
        for (size_t i = 0; i < vx; i++) {
            const size_t i0 = i >= VIEW_MARGIN ? i - VIEW_MARGIN : 0;
            const size_t i1 = i + VIEW_MARGIN < vx ? i + VIEW_MARGIN : vx - 1;
            unsigned char any = 0;
            for (size_t ii = i0; ii <= i1 && !any; ii++)
                any = in[ii];
            out[i] = any;
        }
    }
#pragma omp parallel for schedule(static)
    for (size_t R = 0; R < vy; R++) {
        const size_t r0 = R >= VIEW_MARGIN ? R - VIEW_MARGIN : 0;
        const size_t r1 = R + VIEW_MARGIN < vy ? R + VIEW_MARGIN : vy - 1;
        unsigned char *out = seen + R * vx;
        memset(out, 0, vx);
        for (size_t rr = r0; rr <= r1; rr++) {
            const unsigned char *in = mask + rr * vx;
            for (size_t i = 0; i < vx; i++)
                out[i] |= in[i];
        }
    }
    free(mask);
    return seen;
}

/* Progress over a frame: work done and to do (texel evaluations), and
 * whether the caller asked to stop. */
typedef struct {
    sea_progress_fn fn;
    void *ctx;
    double done, work;
    int cancelled;
} bake_progress;

/* Reports done + part; returns non-zero once the caller asked to stop. */
static int report(bake_progress *bp, double part)
{
    if (bp->fn != NULL && bp->work > 0.0 && !bp->cancelled)
        bp->cancelled = bp->fn(bp->ctx, fmin((bp->done + part) / bp->work, 1.0)) != 0;
    return bp->cancelled;
}

/* The synthesis's share of a bake's progress. */
typedef struct {
    bake_progress *bp;
    double work; /* facets synthesised in all */
} synth_progress;

static int synth_report(void *ctx, double fraction)
{
    synth_progress *sp = ctx;
    return report(sp->bp, fraction * sp->work);
}

/* The optics of one high-resolution level: of its own facets (view 0), or
 * of what the sensor sees on its view grid (view 1: the frame's answer for
 * the ray through the texel centre; where the mask is 0, or that ray meets
 * no sea, the facet's own optics).  The view texels hold what the sensor
 * receives, across the air along the range the ray meets the sea at (the
 * facet's own: along the range to its centre), as seabake render's pixel. */
static sea_status level_optics(const sea_view *r, const sea_multires_frame *f,
                               sea_bake_level *bl, int view, const unsigned char *mask,
                               size_t row0, size_t step, bake_progress *bp, sea_error *err)
{
    const sea_clip_level *lv = &bl->level;
    const size_t nx = lv->nx, ny = lv->ny, k = view ? bl->view_k : 1;
    /* the facets' moments: the frame's, rows south first */
    const sea_facet *south = sea_heightfield_facets(sea_multires_frame_level(f, lv->level));
    const size_t cols = k * nx, rows = k * ny;
    const double cell = lv->facet / (double)k;
    const sea_scene *sc = sea_view_scene(r);
    const sea_camera *cam = sea_view_camera(r);
    const double sun_vec[3] = { sin(sc->sun_zenith) * cos(sc->sun_azimuth),
                                sin(sc->sun_zenith) * sin(sc->sun_azimuth), cos(sc->sun_zenith) };
    int failed = 0;
    size_t rows_done = 0;
    sea_error first = { { 0 } };
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t R = 0; R < rows; R++) {
        /* texel rows row0, row0 + step, ... only (with their view rows) */
        if (failed || (R / k) % step != row0)
            continue;
        if (bp->fn != NULL) {
            int stop = 0;
#pragma omp critical(sea_bake_progress)
            {
                /* any thread, one at a time */
                stop = report(bp, (double)(rows_done * cols));
                rows_done++;
            }
            if (stop) {
#pragma omp critical(sea_bake_error)
                {
                    if (!failed)
                        sea_fail(&first, SEA_ERR_CANCELLED, "bake cancelled in level %d",
                                 lv->level);
                    failed = 1;
                }
                continue;
            }
        }
        const double y = (double)lv->j0 * lv->facet + ((double)(rows - R) - 0.5) * cell;
        for (size_t i = 0; i < cols; i++) {
            const size_t q = R * cols + i;
            sea_error e1;
            sea_status s1 = SEA_OK;
            if (view && !mask[q]) {
                bl->view[q] = (float)bl->optics[(R / k) * nx + i / k].seen;
                continue;
            }
            const double x = (double)lv->i0 * lv->facet + ((double)i + 0.5) * cell;
            sea_dir obs = { 0.0, 0.0 }, sun = { 0.0, 0.0 };
            double range = 0.0;
            if (!view)
                texel_dirs(cam, sun_vec, x, y, &obs, &sun, &range);
            if (!view) {
                s1 = texel_optics(r, sea_facet_stats(&south[(ny - 1 - R) * nx + i]), obs, sun,
                                  range, &bl->optics[q], bl, i, R, &e1);
            } else {
                sea_multires_sample vs;
                double u, v;
                if (!sea_multires_look_at(f, x, y, &vs, &u, &v)) {
                    bl->view[q] = (float)bl->optics[(R / k) * nx + i / k].seen;
                    continue;
                }
                sea_pixel_geom g;
                memcpy(g.normal, vs.normal, sizeof g.normal);
                sea_facet_optics o;
                s1 = texel_optics(r, sea_moments_stats(&vs.moments), vs.obs,
                                  sea_camera_local_dir(&g, sun_vec), vs.range, &o, bl, i, R,
                                  &e1);
                bl->view[q] = (float)o.seen;
            }
            if (s1 != SEA_OK) {
#pragma omp critical(sea_bake_error)
                {
                    if (!failed)
                        first = e1;
                    failed = 1;
                }
                break;
            }
        }
    }
    if (failed) {
        if (err != NULL)
            *err = first;
        return bp->cancelled ? SEA_ERR_CANCELLED : SEA_ERR_NUMERIC;
    }
    return SEA_OK;
}

sea_status sea_bake_frame(const sea_view *r, double t, int view_k, sea_bake *out,
                          sea_progress_fn progress, void *ctx, sea_error *err)
{
    return sea_bake_frame_each(r, t, view_k, out, progress, ctx, NULL, NULL, err);
}

sea_status sea_bake_frame_each(const sea_view *r, double t, int view_k, sea_bake *out,
                               sea_progress_fn progress, void *ctx, sea_bake_level_fn each,
                               void *each_ctx, sea_error *err)
{
    return sea_bake_frame_rows(r, t, view_k, 0, 1, out, progress, ctx, each, each_ctx, err);
}

static sea_status bake_frame(const sea_view *r, double t, int view_k, int row0, int step,
                             sea_image *img, sea_bake *out, sea_progress_fn progress, void *ctx,
                             sea_bake_level_fn each, void *each_ctx, sea_error *err);

sea_status sea_bake_frame_image(const sea_view *r, double t, int view_k, sea_image *img,
                                sea_bake *out, sea_progress_fn progress, void *ctx,
                                sea_bake_level_fn each, void *each_ctx, sea_error *err)
{
    return bake_frame(r, t, view_k, 0, 1, img, out, progress, ctx, each, each_ctx, err);
}

sea_status sea_bake_frame_rows(const sea_view *r, double t, int view_k, int row0, int step,
                               sea_bake *out, sea_progress_fn progress, void *ctx,
                               sea_bake_level_fn each, void *each_ctx, sea_error *err)
{
    return bake_frame(r, t, view_k, row0, step, NULL, out, progress, ctx, each, each_ctx, err);
}

/* Seconds of a monotonic clock (the bake's parts, sea_bake_times). */
static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The most memory, bytes, a bake's surfaces spend on storing the bounds of
 * their finest cells (8 bytes a facet: 8.4 million facets, six levels of
 * 1182^2): stored, the march reads them instead of computing each from
 * nine nodes, 8.5 % of the instructions of a bake at 128^2 a level; at
 * 512^2 (bench/clipmap2048.ini's scene) the bake took 9.52 s instead of
 * 10.13 s (means of seven interleaved runs) and 116 MB instead of 96.  Six
 * levels of 2048^2 would need 201 MB more, beyond the bench's 1.5 GB
 * (make bench). */
static const double BAKE_STORED_BOUNDS_MAX = 64.0 * 1048576.0;

/* Texel rows of an ny-row level that row0, row0 + step, ... are. */
static size_t share_rows(size_t ny, size_t row0, size_t step)
{
    return row0 < ny ? (ny - row0 + step - 1) / step : 0;
}

/* The arguments bake_frame checks before anything is synthesised. */
static sea_status bake_check_args(double t, int view_k, int row0, int step, sea_error *err)
{
    if (sea_time_check(t, err) != SEA_OK)
        return SEA_ERR_DOMAIN;
    if (view_k < 1 || view_k > SEA_BAKE_VIEW_K_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "view texels per facet %d (allowed: 1 to %d)", view_k,
                        SEA_BAKE_VIEW_K_MAX);
    if (row0 < 0 || step < 1 || row0 >= step)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "texel rows from %d every %d (allowed: step >= 1, 0 <= first row < step)",
                        row0, step);
    return SEA_OK;
}

/* The low-resolution constants every level carries: seen from the image
 * centre, as the renderer's choice of spectral samples sees them. */
typedef struct {
    sea_dir obs, sun;
    sea_moments moments;
    sea_facet_optics optics;
} bake_lr;

static sea_status bake_lr_of(const sea_view *r, bake_lr *lr, sea_error *err)
{
    const sea_scene *sc = sea_view_scene(r);
    const sea_camera *cam = sea_view_camera(r);
    const double sun_vec[3] = { sin(sc->sun_zenith) * cos(sc->sun_azimuth),
                                sin(sc->sun_zenith) * sin(sc->sun_azimuth), cos(sc->sun_zenith) };
    sea_pixel_geom g;
    sea_camera_pixel(cam, 0.5 * cam->width, 0.5 * cam->height, &g);
    lr->obs = g.hit ? g.obs : (sea_dir){ sc->look_zenith, 0.0 };
    lr->sun = sea_camera_local_dir(&g, sun_vec);
    lr->moments = sea_view_lr_moments(r);
    const sea_slope_stats lrs = sea_moments_stats(&lr->moments);
    return sea_view_facet_optics(r, &lrs, lr->obs, lr->sun, &lr->optics, err);
}

/* One frame's bake in progress: what its levels share. */
typedef struct {
    const sea_view *r;
    sea_multires_frame *f;
    const sea_clip_level *lv;
    size_t r0, rs;         /* texel rows r0, r0 + rs, ... */
    bake_progress bp;
    sea_bake_level spare;  /* (level_arrays) */
    sea_bake_level_fn each;
    void *each_ctx;
    sea_bake *out;
} bake_job;

/* Counts work w done; once the caller asks to stop, st (if still SEA_OK)
 * becomes SEA_ERR_CANCELLED.  Returns st. */
static sea_status bake_done(bake_job *b, double w, sea_status st, sea_error *err)
{
    b->bp.done += w;
    if (st == SEA_OK && report(&b->bp, 0.0))
        st = sea_fail(err, SEA_ERR_CANCELLED, "bake cancelled");
    return st;
}

/* High-resolution level l's maps: the optics of its facets, then of what
 * the sensor sees on its view grid (where the mask says it is worth it),
 * handed to b->each if set. */
static sea_status bake_level(bake_job *b, size_t l, sea_error *err)
{
    const sea_clip_level *lv = b->lv;
    sea_bake *out = b->out;
    sea_bake_level *bl = &out->levels[l];
    sea_status st;
    if ((st = level_arrays(b->f, bl, &b->spare, b->each == NULL, err)) != SEA_OK)
        return st;
    double hole[4];
    const int has_hole = l > 0 && !lv[l - 1].low_res;
    if (has_hole) {
        hole[0] = (double)lv[l - 1].i0 * lv[l - 1].facet;
        hole[1] = (double)lv[l - 1].j0 * lv[l - 1].facet;
        hole[2] = hole[0] + (double)lv[l - 1].nx * lv[l - 1].facet;
        hole[3] = hole[1] + (double)lv[l - 1].ny * lv[l - 1].facet;
    }
    double t0 = now_s();
    const double texels = (double)(lv[l].nx * share_rows(lv[l].ny, b->r0, b->rs));
    if (st == SEA_OK)
        st = level_optics(b->r, b->f, bl, 0, NULL, b->r0, b->rs, &b->bp, err);
    st = bake_done(b, texels, st, err);
    double t1 = now_s();
    out->seconds.optics += t1 - t0;
    t0 = t1;
    unsigned char *mask = view_mask(sea_view_camera(b->r), &lv[l], bl->view_k,
                                    has_hole ? hole : NULL);
    if (mask == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the view mask of level %d",
                        lv[l].level);
    if (st == SEA_OK)
        st = level_optics(b->r, b->f, bl, 1, mask, b->r0, b->rs, &b->bp, err);
    st = bake_done(b, texels * (double)(bl->view_k * bl->view_k), st, err);
    free(mask);
    out->seconds.view += now_s() - t0;
    if (st == SEA_OK && b->each != NULL) {
        /* the frame's moments of the level, north first while each
         * reads them (no look at the surfaces meanwhile) */
        bl->moments = sea_multires_frame_flip_rows(b->f, lv[l].level);
        st = b->each(b->each_ctx, out, l, err);
        sea_multires_frame_flip_rows(b->f, lv[l].level);
        bl->moments = NULL;
        level_free(&b->spare);
        b->spare = *bl;
        bl->optics = NULL;
        bl->view = NULL;
    }
    return st;
}

/* sea_bake_frame_rows, and with img not NULL sea_bake_frame_image. */
static sea_status bake_frame(const sea_view *r, double t, int view_k, int row0, int step,
                             sea_image *img, sea_bake *out, sea_progress_fn progress, void *ctx,
                             sea_bake_level_fn each, void *each_ctx, sea_error *err)
{
    memset(out, 0, sizeof *out);
    sea_status st = bake_check_args(t, view_k, row0, step, err);
    if (st != SEA_OK)
        return st;
    st = img != NULL ? sea_view_check_image(r, img, err) : SEA_OK;
    if (st != SEA_OK)
        return st; /* before the frame is synthesised */
    const size_t r0 = (size_t)row0, rs = (size_t)step;
    out->time = t;
    const sea_clip_level *lv;
    const size_t n = sea_view_levels(r, &lv);
    bake_lr lr;
    if ((st = bake_lr_of(r, &lr, err)) != SEA_OK)
        return st;
    out->n_levels = n;
    /* progress: facets synthesised, facet optics and view optics (the
     * view texels' count is an upper bound of their work) */
    bake_job b = { .r = r, .lv = lv, .r0 = r0, .rs = rs, .bp = { progress, ctx, 0.0, 0.0, 0 },
                   .each = each, .each_ctx = each_ctx, .out = out };
    double synth = 0.0;
    for (size_t l = 0; l < n; l++)
        if (!lv[l].low_res) {
            synth += (double)(lv[l].nx * lv[l].ny);
            b.bp.work += (double)(lv[l].nx * share_rows(lv[l].ny, r0, rs)) *
                         (2.0 + (double)(view_k * view_k));
        }
    synth_progress sp = { &b.bp, synth };
    sea_multires_frame *f = NULL;
    double t0 = now_s();
    /* The surfaces keep the bounds of their finest cells (8 bytes a facet)
     * where those take at most BAKE_STORED_BOUNDS_MAX; beyond, they compute
     * them from the nodes as the rays ask (the same bounds, bit for bit). */
    const int lean = sea_view_bake_lean(r) || synth * 8.0 > BAKE_STORED_BOUNDS_MAX;
    st = (lean ? sea_multires_frame_alloc_lean : sea_multires_frame_alloc)(
        sea_view_multires(r), t, progress != NULL ? synth_report : NULL, &sp, &f, err);
    if (st == SEA_OK)
        st = bake_done(&b, synth, st, err);
    b.f = f;
    double t1 = now_s();
    out->seconds.waves = t1 - t0;
    /* the sensor's image from the same surfaces, before the levels' maps
     * are made (the frame is the one sea_view_render_frame would synthesise) */
    if (st == SEA_OK && img != NULL) {
        st = sea_view_render_frame_in(r, f, t, img, err);
        t0 = t1;
        t1 = now_s();
        out->seconds.image = t1 - t0;
    }
    for (size_t l = 0; l < n && st == SEA_OK; l++) {
        sea_bake_level *bl = &out->levels[l];
        bl->level = lv[l];
        bl->lr_moments = lr.moments;
        bl->lr_optics = lr.optics;
        bl->lr_obs = lr.obs;
        bl->lr_sun = lr.sun;
        bl->view_k = (size_t)view_k;
    }
    for (size_t l = 0; l < n && st == SEA_OK; l++)
        if (!lv[l].low_res)
            st = bake_level(&b, l, err);
    level_free(&b.spare);
    sea_multires_frame_free(f);
    if (st != SEA_OK)
        sea_bake_free(out);
    return st;
}

void sea_bake_normal(const sea_moments *m, double n[3])
{
    const double len = sqrt(m->mx * m->mx + m->my * m->my + 1.0);
    n[0] = -m->mx / len;
    n[1] = -m->my / len;
    n[2] = 1.0 / len;
}

void sea_bake_roughness(const sea_moments *m, double *roughness, double *anisotropy,
                        double *rotation)
{
    const sea_slope_stats s = sea_moments_stats(m);
    const double tr = s.cov.xx + s.cov.yy;
    const double diff = s.cov.xx - s.cov.yy;
    /* l1 - l2 = sqrt((xx - yy)^2 + 4 xy^2), l1 + l2 = trace */
    const double spread = hypot(diff, 2.0 * s.cov.xy);
    *roughness = sqrt(sqrt(tr));
    *anisotropy = tr > 0.0 ? fmin(1.0, spread / tr) : 0.0;
    double angle = spread > 0.0 ? 0.5 * atan2(2.0 * s.cov.xy, diff) : 0.0; /* (-pi/2, pi/2] */
    if (angle < 0.0)
        angle += M_PI;
    if (angle >= M_PI)
        angle -= M_PI;
    *rotation = angle / (2.0 * M_PI);
}
