/* pov_driver.c - the test driver of tests/povray.sh (and tests/blender.sh):
 * exports a scene with sea_pov_write and checks POV-Ray's render of it
 * against seabake's own.
 *
 *   pov_driver export SCENE.ini DIR   writes DIR/scene.pov, sea.inc, scene.ini,
 *                                     seabake.inc, level_<l>.exr, render.exr
 *   pov_driver check SCENE.ini DIR    compares DIR/scene.exr (POV-Ray) with
 *                                     seabake's render; prints the numbers
 *   pov_driver compare ...            seabake render against a renderer's
 *                                     image of a bake (below)
 *   pov_driver dump MAP.exr OUT.raw   a map's texels as seabake reads them
 *   pov_driver wide ...               the exported sensor's image from a
 *                                     camera of twice its field
 *   pov_driver heights ...            a POV-Ray probe of the waves' heights
 *   pov_driver same A.exr B.exr TOL   two images alike
 *
 * The scene must render to a uniform radiance (pov_nadir.ini: sun below the
 * horizon, sky as warm as the sea), so that each clipmap level's emission
 * map is that constant, the same over its whole window, which any bake
 * must give.  The finest level's map also carries markers: single texels of
 * distinct values whose images must land where sea_camera_project puts the
 * texel centres.  Exit status 0 pass, 1 fail, 99 hard error. */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exr.h"
#include "povray.h"
#include "seabake.h"

enum { N_MARKERS = 5, MIN_MARKERS = 3, MARKER_WINDOW = 3, MARKER_GRID_U = 5, MARKER_GRID_V = 6 };
/* Markers at least this far apart and from the image's edges, pixels. */
static const double MARKER_SPACING = 8.0, MARKER_MARGIN = 4.0;
/* POV-Ray's sky is exported at this fraction of seabake's, so that the
 * sky/sea boundary shows in a uniform scene. */
static const double SKY_FACTOR = 0.5;
/* The low-resolution ring reaches this many altitudes from the sensor;
 * pixels whose sea point lies beyond it are not compared (POV-Ray shows the
 * sky there). */
static const double LR_EXTENT = 1e3;
/* Marker k's map value: the constant times this (well apart, inside half range). */
static double marker_gain(int k)
{
    return 2.0 + 0.5 * k;
}
/* Half floats keep 11 significant bits: relative rounding <= 2^-11. */
static const double HALF_REL = 4.9e-4;
/* The render must be uniform to this (it is epsilon B + (1 - epsilon) B). */
static const double UNIFORM_REL = 1e-6;

typedef struct {
    sea_scene sc;
    sea_view *r;
    sea_camera cam;
    sea_image img;
    double L;     /* the uniform sea radiance of seabake's render */
    double sky;   /* its sky radiance */
    double scale; /* POV value = radiance * scale */
    size_t n_levels;
    const sea_clip_level *lv;
    int fine;     /* index of the finest high-resolution level */
    int n_markers;
    long mi[N_MARKERS], mj[N_MARKERS]; /* marker facets (world facet indices) */
} setup;

static int die(const char *what, const sea_error *e)
{
    fprintf(stderr, "pov_driver: %s: %s\n", what, e ? e->msg : "");
    return 99;
}

static int prepare(const char *scene, setup *s)
{
    sea_error e;
    memset(s, 0, sizeof *s);
    if (sea_scene_load(scene, &s->sc, &e) != SEA_OK || sea_view_alloc(&s->sc, &s->r, &e) ||
        sea_camera_init(s->sc.sensor_x, s->sc.sensor_y, s->sc.altitude, s->sc.look_zenith,
                        s->sc.look_azimuth, s->sc.roll, s->sc.hfov, s->sc.width,
                        s->sc.height, s->sc.earth, &s->cam, &e) ||
        sea_image_alloc(s->sc.width, s->sc.height, &s->img, &e) ||
        sea_view_render_frame(s->r, s->sc.time, &s->img, NULL, NULL, &e))
        return die(scene, &e);
    const size_t npix = (size_t)s->sc.width * (size_t)s->sc.height;
    double lo = INFINITY, hi = -INFINITY;
    int any_sky = 0;
    for (size_t q = 0; q < npix; q++) {
        if (s->img.level[q] > 0.0f) {
            lo = fmin(lo, s->img.radiance[q]);
            hi = fmax(hi, s->img.radiance[q]);
        } else {
            s->sky = s->img.radiance[q];
            any_sky = 1;
        }
    }
    if (!(hi - lo <= UNIFORM_REL * hi))
        return die("the render is not uniform over the sea", NULL);
    s->L = 0.5 * (lo + hi);
    if (!any_sky)
        s->sky = s->L;
    /* A power of two puts the constant near 1 without changing its digits. */
    s->scale = exp2(-round(log2(s->L)));
    s->n_levels = sea_view_levels(s->r, &s->lv);
    s->fine = -1;
    for (size_t k = 0; k < s->n_levels && s->fine < 0; k++)
        if (!s->lv[k].low_res)
            s->fine = (int)k;
    if (s->fine < 0)
        return die("the scene has no high-resolution level", NULL);
    /* Markers: points of a grid over the image that fall in the finest
     * level's window, well apart. */
    if (s->sc.width < 2 * MARKER_MARGIN || s->sc.height < 2 * MARKER_MARGIN)
        return die("the image is too small for markers", NULL);
    const sea_clip_level *f = &s->lv[s->fine];
    double au[N_MARKERS], av[N_MARKERS];
    for (int b = 0; b < MARKER_GRID_V && s->n_markers < N_MARKERS; b++)
        for (int a = 0; a < MARKER_GRID_U && s->n_markers < N_MARKERS; a++) {
            const double u = (a + 0.5 + 0.2 * (b % 2)) / MARKER_GRID_U * s->sc.width;
            const double v = (b + 0.5) / MARKER_GRID_V * s->sc.height;
            /* Only where seabake itself used the finest level: the pixels
             * there are no larger than about a texel, so a one-texel marker
             * cannot fall between two pixel centres. */
            const size_t q = (size_t)v * (size_t)s->sc.width + (size_t)u;
            if (s->img.level[q] != (float)f->facet)
                continue;
            sea_pixel_geom g;
            sea_camera_pixel(&s->cam, u, v, &g);
            if (!g.hit)
                continue;
            const long i = (long)floor(g.x / f->facet), j = (long)floor(g.y / f->facet);
            if (i < f->i0 || j < f->j0 || i >= f->i0 + (long)f->nx || j >= f->j0 + (long)f->ny)
                continue;
            const double p[3] = { (i + 0.5) * f->facet, (j + 0.5) * f->facet, 0.0 };
            double pu, pv;
            if (!sea_camera_project(&s->cam, p, &pu, &pv) || pu < MARKER_MARGIN ||
                pv < MARKER_MARGIN || pu > s->sc.width - MARKER_MARGIN ||
                pv > s->sc.height - MARKER_MARGIN)
                continue;
            int apart = 1;
            for (int k = 0; k < s->n_markers; k++)
                if (hypot(pu - au[k], pv - av[k]) < MARKER_SPACING)
                    apart = 0;
            if (!apart)
                continue;
            au[s->n_markers] = pu;
            av[s->n_markers] = pv;
            s->mi[s->n_markers] = i;
            s->mj[s->n_markers] = j;
            s->n_markers++;
        }
    if (s->n_markers < MIN_MARKERS)
        return die("too few marker places in the finest level's window", NULL);
    return 0;
}

static void release(setup *s)
{
    sea_image_free(&s->img);
    sea_view_free(s->r);
}

static int do_export(const char *dir, setup *s)
{
    sea_error e;
    sea_pov_level pl[SEA_CLIP_MAX_LEVELS];
    char names[SEA_CLIP_MAX_LEVELS][32];
    const double c = s->L * s->scale;
    for (size_t k = 0; k < s->n_levels; k++) {
        const sea_clip_level *l = &s->lv[k];
        sea_pov_level *p = &pl[k];
        memset(p, 0, sizeof *p);
        p->level = l->level;
        p->facet = l->facet;
        p->constant = c;
        if (k > 0 && !s->lv[k - 1].low_res) {
            const sea_clip_level *h = &s->lv[k - 1];
            p->has_hole = 1;
            p->hx0 = (double)h->i0 * h->facet;
            p->hy0 = (double)h->j0 * h->facet;
            p->hw = (double)h->nx * h->facet;
            p->hh = (double)h->ny * h->facet;
        }
        if (l->low_res) {
            /* Every LR facet is the same: a ring far beyond the view. */
            const double R = LR_EXTENT * s->sc.altitude;
            p->x0 = s->sc.sensor_x - R;
            p->y0 = s->sc.sensor_y - R;
            p->w = p->h = 2.0 * R;
            continue;
        }
        p->x0 = (double)l->i0 * l->facet;
        p->y0 = (double)l->j0 * l->facet;
        p->w = (double)l->nx * l->facet;
        p->h = (double)l->ny * l->facet;
        snprintf(names[k], sizeof names[k], "level_%d.exr", l->level);
        p->emission_file = names[k];
        const size_t nt = l->nx * l->ny;
        float *map = malloc(nt * sizeof *map);
        if (map == NULL)
            return die("out of memory", NULL);
        for (size_t t = 0; t < nt; t++)
            map[t] = (float)c;
        if ((int)k == s->fine)
            for (int m = 0; m < s->n_markers; m++) {
                /* Row 0 is the top of the image: the northernmost facets. */
                const size_t col = (size_t)(s->mi[m] - l->i0);
                const size_t row = l->ny - 1 - (size_t)(s->mj[m] - l->j0);
                map[row * l->nx + col] = (float)(c * marker_gain(m));
            }
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        const sea_exr_channel ch[3] = { { "R", map }, { "G", map }, { "B", map } };
        const sea_exr_options opt = { SEA_EXR_HALF, SEA_EXR_ZIP };
        sea_status st = sea_exr_write(path, (int)l->nx, (int)l->ny, ch, 3, NULL, 0, &opt, &e);
        free(map);
        if (st != SEA_OK)
            return die(path, &e);
    }
    /* Outside every ring (none here) and in the sky: the sky radiance. */
    if (sea_pov_write(dir, &s->cam, pl, s->n_levels, SKY_FACTOR * s->sky * s->scale, s->scale, NULL,
                      &e) != SEA_OK)
        return die(dir, &e);
    printf("exported %zu levels, constant %.6g x scale %.6g, %d markers\n", s->n_levels, s->L,
           s->scale, s->n_markers);
    return 0;
}

static int do_check(const char *dir, setup *s)
{
    sea_error e;
    char path[4096];
    snprintf(path, sizeof path, "%s/scene.exr", dir);
    sea_exr_image pov;
    if (sea_exr_read(path, &pov, &e) != SEA_OK)
        return die(path, &e);
    int fails = 0;
    const float *R = sea_exr_image_channel(&pov, "R");
    const int W = s->sc.width, H = s->sc.height;
    if (R == NULL || pov.width != W || pov.height != H) {
        fprintf(stderr, "FAIL: %s: %d x %d, no R channel or size not %d x %d\n", path, pov.width,
                pov.height, W, H);
        sea_exr_image_free(&pov);
        return 1;
    }
    /* (b) markers: centroid of the excess over the constant. */
    const double c = s->L * s->scale;
    double mu[N_MARKERS], mv[N_MARKERS], worst = 0.0;
    for (int k = 0; k < s->n_markers; k++) {
        const sea_clip_level *f = &s->lv[s->fine];
        const double p[3] = { ((double)s->mi[k] + 0.5) * f->facet,
                              ((double)s->mj[k] + 0.5) * f->facet, 0.0 };
        sea_camera_project(&s->cam, p, &mu[k], &mv[k]);
        const int ci = (int)floor(mu[k]), cj = (int)floor(mv[k]);
        double sw = 0.0, su = 0.0, sv = 0.0, peak = 0.0;
        for (int j = cj - MARKER_WINDOW; j <= cj + MARKER_WINDOW; j++)
            for (int i = ci - MARKER_WINDOW; i <= ci + MARKER_WINDOW; i++) {
                if (i < 0 || j < 0 || i >= W || j >= H)
                    continue;
                const double x = R[j * W + i] - c;
                if (x <= 0.0)
                    continue;
                sw += x;
                su += x * (i + 0.5);
                sv += x * (j + 0.5);
                peak = fmax(peak, x);
            }
        const double du = sw > 0.0 ? su / sw - mu[k] : INFINITY;
        const double dv = sw > 0.0 ? sv / sw - mv[k] : INFINITY;
        const double d = hypot(du, dv);
        worst = fmax(worst, d);
        /* The bilinear footprint of one texel peaks at its value where a
         * pixel centre falls on the texel centre; less elsewhere. */
        printf("marker %d: expected (%.3f, %.3f), POV centroid (%.3f, %.3f), error %.3f px, "
               "peak excess %.3g of %.3g\n",
               k, mu[k], mv[k], mu[k] + du, mv[k] + dv, d, peak, c * (marker_gain(k) - 1.0));
        if (!(d <= 1.0)) {
            fprintf(stderr, "FAIL: marker %d lands %.3f px from its projection\n", k, d);
            fails++;
        }
    }
    /* (a) geometry and values: every pixel away from the markers. */
    size_t n_sea = 0, n_sky = 0, n_far = 0, bad = 0;
    const double reach = LR_EXTENT * s->sc.altitude;
    double max_rel = 0.0, sum2 = 0.0;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            int near = 0;
            for (int k = 0; k < s->n_markers; k++)
                if (fabs(i + 0.5 - mu[k]) < MARKER_WINDOW + 1 &&
                    fabs(j + 0.5 - mv[k]) < MARKER_WINDOW + 1)
                    near = 1;
            if (near)
                continue;
            sea_pixel_geom g;
            sea_camera_pixel(&s->cam, i + 0.5, j + 0.5, &g);
            if (g.hit && (fabs(g.x - s->sc.sensor_x) > reach || fabs(g.y - s->sc.sensor_y) > reach)) {
                n_far++;
                continue;
            }
            const size_t q = (size_t)j * (size_t)W + (size_t)i;
            const double want = s->img.radiance[q] * (s->img.level[q] > 0.0f ? 1.0 : SKY_FACTOR);
            const double got = R[q] / s->scale;
            const double rel = fabs(got - want) / want;
            if (s->img.level[q] > 0.0f)
                n_sea++;
            else
                n_sky++;
            max_rel = fmax(max_rel, rel);
            sum2 += rel * rel;
            if (!(rel <= HALF_REL)) {
                if (bad++ < 5)
                    fprintf(stderr, "FAIL: pixel (%d, %d): POV %.7g, seabake %.7g (rel %.3g)\n",
                            i, j, got, want, rel);
            }
        }
    const double rms = sqrt(sum2 / (double)(n_sea + n_sky));
    printf("pixels: %zu sea, %zu sky compared (markers and %zu beyond the rings excluded); "
           "relative difference max %.3g, RMS %.3g; markers worst %.3f px\n",
           n_sea, n_sky, n_far, max_rel, rms, worst);
    if (bad) {
        fprintf(stderr, "FAIL: %zu pixels differ by more than %g\n", bad, HALF_REL);
        fails++;
    }
    sea_exr_image_free(&pov);
    return fails ? 1 : 0;
}

/* The grey value of a map: its Y channel (seabake's grey maps), else its R
 * (a renderer's output, R = G = B). */
static const float *grey_of(const sea_exr_image *img)
{
    const float *y = sea_exr_image_channel(img, "Y");
    return y != NULL ? y : sea_exr_image_channel(img, "R");
}

/* dump MAP.exr OUT.raw: the file's R, G, B, A channels as seabake's EXR
 * reader gives them, float32 in native byte order, RGBA interleaved, row 0
 * at the top; a file without A gets 1 there (as Blender shows an RGB image),
 * a grey file (Y alone) Y in R, G and B (as Blender shows it).  Prints
 * "WIDTH HEIGHT CHANNELS".  For tests/blender_check.py. */
static int do_dump(const char *map, const char *raw)
{
    sea_exr_image img;
    sea_error err;
    if (sea_exr_read(map, &img, &err) != SEA_OK)
        return die(map, &err);
    static const char *const names[4] = { "R", "G", "B", "A" };
    const float *ch[4];
    int n = 0;
    for (int c = 0; c < 4; c++)
        if ((ch[c] = sea_exr_image_channel(&img, names[c])) != NULL)
            n = c + 1;
    const float *y = sea_exr_image_channel(&img, "Y");
    if (n == 0 && y != NULL && img.n_channels == 1) {
        ch[0] = ch[1] = ch[2] = y;
        n = 1;
    }
    int rc = 0;
    if ((n < 3 && n != 1) || ch[0] == NULL || ch[1] == NULL || ch[2] == NULL) {
        fprintf(stderr, "pov_driver: %s: neither R, G and B channels nor Y alone\n", map);
        rc = 99;
    }
    FILE *f = rc ? NULL : fopen(raw, "wb");
    if (rc == 0 && f == NULL) {
        perror(raw);
        rc = 99;
    }
    const size_t npix = (size_t)img.width * (size_t)img.height;
    for (size_t q = 0; q < npix && f != NULL && rc == 0; q++) {
        const float px[4] = { ch[0][q], ch[1][q], ch[2][q], n == 4 ? ch[3][q] : 1.0f };
        if (fwrite(px, sizeof px, 1, f) != 1) {
            perror(raw);
            rc = 99;
        }
    }
    if (f != NULL && fclose(f) != 0 && rc == 0) {
        perror(raw);
        rc = 99;
    }
    if (rc == 0)
        printf("%d %d %d\n", img.width, img.height, n);
    sea_exr_image_free(&img);
    return rc;
}

/* compare REF.exr LEVEL.exr POV.exr SCALE MAX [RENDERER]: seabake render's
 * radiance (channel Y) against another renderer's image of the baked export
 * (POV-Ray's or Cycles', channel R, divided by the emission scale, passed
 * as SCALE) over the sea pixels (level > 0) and over the whole image;
 * fails when either relative RMS difference exceeds MAX (or the rows below
 * the horizon's exceeds MAX_HORIZON, when given).  RENDERER names it in the report (default
 * POV-Ray). */
/* The HORIZON_ROWS topmost sea pixels of each column: the rows a
 * background shows, where the sea meets the sky. */
enum { HORIZON_ROWS = 10 };

static int do_compare(const char *ref, const char *level, const char *povimg, double scale,
                      double max_rms, const char *renderer, double max_rms_horizon)
{
    sea_exr_image a, l, b;
    sea_error err;
    memset(&a, 0, sizeof a);
    memset(&l, 0, sizeof l);
    memset(&b, 0, sizeof b);
    int rc = 1;
    if (sea_exr_read(ref, &a, &err) != SEA_OK || sea_exr_read(level, &l, &err) != SEA_OK ||
        sea_exr_read(povimg, &b, &err) != SEA_OK) {
        fprintf(stderr, "FAIL: %s\n", err.msg);
        goto done;
    }
    const float *pa = sea_exr_image_channel(&a, "Y"), *pl = sea_exr_image_channel(&l, "Y");
    const float *pb = sea_exr_image_channel(&b, "R");
    if (pa == NULL || pl == NULL || pb == NULL || a.width != b.width || a.height != b.height) {
        fprintf(stderr, "FAIL: channels or sizes do not match\n");
        goto done;
    }
    double sum2 = 0.0, max_rel = 0.0;
    size_t n = 0;
    /* per level (the level AOV holds the facet size, a power of two) */
    enum { NL = SEA_CLIP_MAX_LEVELS + 8 };
    double lsum2[NL] = { 0 }, lmax[NL] = { 0 }, lsize[NL] = { 0 };
    size_t ln[NL] = { 0 };
    for (size_t i = 0; i < (size_t)a.width * (size_t)a.height; i++) {
        if (pl[i] == 0.0f)
            continue;
        const double rel = fabs(pb[i] / scale - pa[i]) / pa[i];
        sum2 += rel * rel;
        max_rel = fmax(max_rel, rel);
        n++;
        const long k = lround(log2(pl[i])) + 4;
        if (k >= 0 && k < NL) {
            lsum2[k] += rel * rel;
            lmax[k] = fmax(lmax[k], rel);
            lsize[k] = pl[i];
            ln[k]++;
        }
    }
    const double rms = n ? sqrt(sum2 / (double)n) : INFINITY;
    printf("seabake render vs %s of the bake: %zu sea pixels, relative RMS %.3g, max %.3g\n",
           renderer, n, rms, max_rel);
    for (int k = 0; k < NL; k++)
        if (ln[k])
            printf("  pixels of the %g m level: %zu, relative RMS %.3g, max %.3g\n", lsize[k],
                   ln[k], sqrt(lsum2[k] / (double)ln[k]), lmax[k]);
    /* below the horizon: per column, the first HORIZON_ROWS sea pixels from
     * the top (only columns whose top pixel is sky: a horizon in view) */
    double hsum2 = 0.0, hmax = 0.0;
    size_t hn = 0;
    const size_t W = (size_t)a.width, H = (size_t)a.height;
    for (size_t x = 0; x < W; x++) {
        if (pl[x] != 0.0f)
            continue;
        size_t taken = 0;
        for (size_t y = 0; y < H && taken < HORIZON_ROWS; y++) {
            const size_t i = y * W + x;
            if (pl[i] == 0.0f)
                continue;
            const double rel = fabs(pb[i] / scale - pa[i]) / pa[i];
            hsum2 += rel * rel;
            hmax = fmax(hmax, rel);
            hn++;
            taken++;
        }
    }
    const double hrms = hn ? sqrt(hsum2 / (double)hn) : 0.0;
    if (hn)
        printf("  the %d rows below the horizon: %zu pixels, relative RMS %.3g, max %.3g\n",
               HORIZON_ROWS, hn, hrms, hmax);
    /* the sky pixels alone, and how much the reference's sky varies (a
     * sky that changes with the direction: more than the error allowed, or
     * one radiance everywhere would pass too) */
    double ssum2 = 0.0, smax = 0.0, slo = INFINITY, shi = 0.0;
    size_t sn = 0;
    for (size_t i = 0; i < W * H; i++) {
        if (pl[i] != 0.0f)
            continue;
        const double rel = fabs(pb[i] / scale - pa[i]) / fmax(fabs(pa[i]), 1e-30);
        ssum2 += rel * rel;
        smax = fmax(smax, rel);
        slo = fmin(slo, pa[i]);
        shi = fmax(shi, pa[i]);
        sn++;
    }
    if (sn)
        printf("  the sky: %zu pixels, relative RMS %.3g, max %.3g, spread %.3g\n", sn,
               sqrt(ssum2 / (double)sn), smax, shi / slo - 1.0);
    /* the whole image, sky included (a sea pixel shown as sky, or the
     * reverse, counts here) */
    double isum2 = 0.0, imax = 0.0;
    for (size_t i = 0; i < W * H; i++) {
        const double rel = fabs(pb[i] / scale - pa[i]) / fmax(fabs(pa[i]), 1e-30);
        isum2 += rel * rel;
        imax = fmax(imax, rel);
    }
    const double irms = sqrt(isum2 / (double)(W * H));
    printf("  the whole image: %zu pixels, relative RMS %.3g, max %.3g\n", W * H, irms, imax);
    rc = rms < max_rms && irms < max_rms && !(hrms >= max_rms_horizon) ? 0 : 1;
    if (!(rms < max_rms))
        fprintf(stderr, "FAIL: relative RMS %.3g >= %.3g\n", rms, max_rms);
    else if (!(irms < max_rms))
        fprintf(stderr, "FAIL: relative RMS %.3g over the whole image >= %.3g\n", irms, max_rms);
    else if (rc)
        fprintf(stderr, "FAIL: relative RMS %.3g below the horizon >= %.3g\n", hrms,
                max_rms_horizon);
done:
    sea_exr_image_free(&a);
    sea_exr_image_free(&l);
    sea_exr_image_free(&b);
    return rc;
}

/* wide SENSOR.exr LEVEL.exr SENSOR_WIDE.exr MAPS_WIDE.exr: a camera at the
 * sensor's position and axes with half its focal length, same pixel count
 * (twice the field both ways), renders an --emission-space sensor export
 * with its sensor's image (SENSOR_WIDE) and without it (MAPS_WIDE: the
 * maps alone, Seabake_Use_Sensor off).  Its pixel (i, j) looks along the sensor's image coordinates
 * (2 i + 1 - W/2, 2 j + 1 - H/2): inside the sensor's view the projection
 * falls between the 2 x 2 texels of sensor.exr from column 2 i - W/2, row
 * 2 j - H/2, so bilinear lookup gives their mean (checked where all four
 * are sea in LEVEL, the render's level AOV, within two half-float
 * roundings, 1e-3); outside it the sea shows its maps, so the two renders
 * agree exactly.  Pixels within 1 of the view's edge are left out (there
 * the lookup meets the edge texels).  W and H must be even. */
static int do_wide(const char *sensor, const char *level, const char *swide, const char *mwide)
{
    sea_exr_image a, l, b, c;
    sea_error err;
    memset(&a, 0, sizeof a);
    memset(&l, 0, sizeof l);
    memset(&b, 0, sizeof b);
    memset(&c, 0, sizeof c);
    int rc = 1;
    if (sea_exr_read(sensor, &a, &err) != SEA_OK || sea_exr_read(level, &l, &err) != SEA_OK ||
        sea_exr_read(swide, &b, &err) != SEA_OK || sea_exr_read(mwide, &c, &err) != SEA_OK) {
        fprintf(stderr, "FAIL: %s\n", err.msg);
        goto done;
    }
    const float *pa = grey_of(&a), *pl = sea_exr_image_channel(&l, "Y");
    const float *pb = sea_exr_image_channel(&b, "R"), *pc = sea_exr_image_channel(&c, "R");
    const int W = a.width, H = a.height;
    if (pa == NULL || pl == NULL || pb == NULL || pc == NULL || W % 2 || H % 2 ||
        l.width != W || b.width != W || c.width != W || l.height != H || b.height != H ||
        c.height != H) {
        fprintf(stderr, "FAIL: channels or sizes do not match (or odd)\n");
        goto done;
    }
    size_t n_in = 0, n_out = 0, bad_out = 0;
    double max_in = 0.0;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            /* distance from the view's edge, wide pixels (> 0 inside) */
            const double du = 0.25 * W - fabs(i + 0.5 - 0.5 * W),
                         dv = 0.25 * H - fabs(j + 0.5 - 0.5 * H);
            const size_t q = (size_t)j * (size_t)W + (size_t)i;
            if (du >= 1.0 && dv >= 1.0) {
                const int x = 2 * i - W / 2, y = 2 * j - H / 2;
                double mean = 0.0;
                int sea = 1;
                for (int k = 0; k < 4; k++) {
                    const size_t p = (size_t)(y + k / 2) * (size_t)W + (size_t)(x + k % 2);
                    sea &= pl[p] > 0.0f;
                    mean += 0.25 * pa[p];
                }
                if (!sea)
                    continue;
                max_in = fmax(max_in, fabs(pb[q] - mean) / mean);
                n_in++;
            } else if (du <= -1.0 || dv <= -1.0) {
                bad_out += pb[q] != pc[q];
                n_out++;
            }
        }
    printf("inside the sensor's view: %zu sea pixels, largest relative difference from the "
           "2 x 2 mean %.3g; outside: %zu pixels, %zu differ from the maps alone\n",
           n_in, max_in, n_out, bad_out);
    rc = n_in > 0 && n_out > 0 && max_in < 1e-3 && bad_out == 0 ? 0 : 1;
done:
    sea_exr_image_free(&a);
    sea_exr_image_free(&l);
    sea_exr_image_free(&b);
    sea_exr_image_free(&c);
    return rc;
}

/* heights SCENE.ini DIR S: writes DIR/probe.pov, which includes DIR's
 * sea.inc (a bake of SCENE.ini at the scene's time, S height samples per
 * facet side) and traces each level's height field, Seabake_Height_k,
 * straight down at points of its rectangle: nodes of its sample grid and
 * points between them, each against the height seabake render's surface
 * has there (the frame's level surface, sea_heightfield_at, on its sea
 * point: q_z + h n_z).  POV-Ray prints "heights: ..." with the largest
 * differences over the nodes and over the points, and the misses. */
enum { PROBE_NODES = 40, PROBE_POINTS = 40 };

static double probe_rand(unsigned long long *x)
{
    *x = *x * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*x >> 11) / 9007199254740992.0;
}

static int do_heights(const char *scene, const char *dir, int S)
{
    sea_scene sc;
    sea_view *r = NULL;
    sea_multires_frame *fr = NULL;
    sea_error e;
    if (sea_scene_load(scene, &sc, &e) != SEA_OK || sea_view_alloc(&sc, &r, &e) != SEA_OK ||
        sea_multires_frame_alloc(sea_view_multires(r), sc.time, NULL, NULL, &fr, &e) != SEA_OK) {
        sea_view_free(r);
        return die(scene, &e);
    }
    const sea_camera *cam = sea_view_camera(r);
    const sea_clip_level *lv;
    const size_t n = sea_view_levels(r, &lv);
    char path[4096];
    snprintf(path, sizeof path, "%s/probe.pov", dir);
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        perror(path);
        sea_multires_frame_free(fr);
        sea_view_free(r);
        return 99;
    }
    fputs("#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n#include \"sea.inc\"\n"
          "#declare Dn = 0; #declare Dp = 0; #declare Miss = 0; #declare N = <0, 0, 0>;\n"
          "#macro Probe(Obj, X, Y, Z, Node)\n"
          "  #declare Q = trace(Obj, <X, 1e7, Y>, -y, N);\n"
          "  #if (vlength(N) = 0)\n    #declare Miss = Miss + 1;\n"
          "  #elseif (Node)\n    #declare Dn = max(Dn, abs(Q.y - Z));\n"
          "  #else\n    #declare Dp = max(Dp, abs(Q.y - Z));\n  #end\n#end\n",
          f);
    unsigned long long seed = 12345;
    size_t k = 0;
    for (size_t l = 0; l < n; l++) {
        if (lv[l].low_res)
            continue;
        const sea_heightfield *hf = sea_multires_frame_level(fr, lv[l].level);
        const double L = lv[l].facet, step = L / S;
        const long nx = (long)lv[l].nx * S, ny = (long)lv[l].ny * S;
        for (int q = 0; q < PROBE_NODES + PROBE_POINTS; q++) {
            const int node = q < PROBE_NODES;
            /* nodes inside the edge; points anywhere a sample inside */
            const double gi = node ? (double)(1 + (long)(probe_rand(&seed) * (double)(nx - 1)))
                                   : 1.0 + probe_rand(&seed) * (double)(nx - 2);
            const double gj = node ? (double)(1 + (long)(probe_rand(&seed) * (double)(ny - 1)))
                                   : 1.0 + probe_rand(&seed) * (double)(ny - 2);
            const double x = (double)lv[l].i0 * L + gi * step, y = (double)lv[l].j0 * L + gj * step;
            double p[3], nv[3];
            sea_camera_sea_point(cam, x, y, p, nv);
            const double z = p[2] + sea_heightfield_at(hf, x, y).h * nv[2];
            fprintf(f, "Probe(Seabake_Height_%zu, %.17g, %.17g, %.17g, %d)\n", k, x, y, z, node);
        }
        k++;
    }
    fputs("#debug concat(\"heights: nodes \", str(Dn, 0, -1), \" m, points \", str(Dp, 0, -1),\n"
          "              \" m, misses \", str(Miss, 0, 0), \"\\n\")\n"
          "camera { location <0, 1e6, 0> look_at 0 }\n",
          f);
    const int bad = fclose(f) != 0;
    printf("%zu levels, %d nodes and %d points each\n", k, PROBE_NODES, PROBE_POINTS);
    sea_multires_frame_free(fr);
    sea_view_free(r);
    return bad ? 99 : 0;
}

/* same A.exr B.exr TOL: the grey values (grey_of) of both within TOL
 * relative (of B). */
static int do_same(const char *pa, const char *pb, double tol)
{
    sea_exr_image a, b;
    sea_error err;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    int rc = 1;
    if (sea_exr_read(pa, &a, &err) != SEA_OK || sea_exr_read(pb, &b, &err) != SEA_OK) {
        fprintf(stderr, "FAIL: %s\n", err.msg);
    } else {
        const float *ra = grey_of(&a), *rb = grey_of(&b);
        if (ra == NULL || rb == NULL || a.width != b.width || a.height != b.height) {
            fprintf(stderr, "FAIL: channels or sizes do not match\n");
        } else {
            double worst = 0.0;
            const size_t np = (size_t)a.width * (size_t)a.height;
            for (size_t q = 0; q < np; q++)
                worst = fmax(worst, fabs(ra[q] - rb[q]) / fmax(fabs(rb[q]), 1e-30));
            printf("%zu pixels, largest relative difference %.3g\n", np, worst);
            rc = worst <= tol ? 0 : 1;
        }
    }
    sea_exr_image_free(&a);
    sea_exr_image_free(&b);
    return rc;
}

int main(int argc, char **argv)
{
    sea_init();
    if (argc >= 7 && argc <= 9 && strcmp(argv[1], "compare") == 0)
        return do_compare(argv[2], argv[3], argv[4], atof(argv[5]), atof(argv[6]),
                          argc >= 8 ? argv[7] : "POV-Ray", argc == 9 ? atof(argv[8]) : INFINITY);
    if (argc == 4 && strcmp(argv[1], "dump") == 0)
        return do_dump(argv[2], argv[3]);
    if (argc == 6 && strcmp(argv[1], "wide") == 0)
        return do_wide(argv[2], argv[3], argv[4], argv[5]);
    if (argc == 5 && strcmp(argv[1], "heights") == 0)
        return do_heights(argv[2], argv[3], atoi(argv[4]));
    if (argc == 5 && strcmp(argv[1], "same") == 0)
        return do_same(argv[2], argv[3], atof(argv[4]));
    if (argc != 4 || (strcmp(argv[1], "export") != 0 && strcmp(argv[1], "check") != 0)) {
        fprintf(stderr, "usage: pov_driver export|check SCENE.ini DIR\n"
                        "       pov_driver compare REF.exr LEVEL.exr POV.exr SCALE MAX_RMS "
                        "[RENDERER [MAX_RMS_HORIZON]]\n"
                        "       pov_driver dump MAP.exr OUT.raw\n"
                        "       pov_driver wide SENSOR.exr LEVEL.exr SENSOR_WIDE.exr "
                        "MAPS_WIDE.exr\n"
                        "       pov_driver heights SCENE.ini DIR S\n"
                        "       pov_driver same A.exr B.exr TOL\n");
        return 99;
    }
    setup s;
    int rc = prepare(argv[2], &s);
    if (rc == 0)
        rc = strcmp(argv[1], "export") == 0 ? do_export(argv[3], &s) : do_check(argv[3], &s);
    release(&s);
    return rc;
}
