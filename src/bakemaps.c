/* bakemaps.c - a bake directory's maps (bakedir.h): each high-resolution
 * level's groups of quantities as single-part EXR files of plain R, G,
 * B(, A) channels (Y alone for emission), <group>_<l>[_<frame>].exr
 * (SEA_BAKE_GROUPS), an 8-bit PNG preview of each, and for the exports
 * the waves' heights of each level.
 *
 * Streaming.  sea_bake_frame_each hands over one level at a time and frees
 * it once written, so that only one level's maps are held.  Within a level
 * the groups' files are written in parallel, each thread with its own
 * buffers.  The first frame sets what every frame shares: the emission
 * scale (from its largest radiance) and the tone curves of the grey
 * previews (from its texels of every level, bake_previews), so its
 * emission maps and those previews wait for the whole frame: their data
 * (the emission texels' radiance as the level holds it, the previewed
 * channel of moments, moments2 and optics as the float they are written
 * as; floats all) go to a spill file of the level in the directory, read
 * back and removed at the end of the frame.  The files are those of
 * holding every level, byte for byte. */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bakedir_internal.h"
#include "exr.h"
#include "preview.h"

/* ---------------------------------------------------------- the groups */

const bake_quantity_info SEA_BAKE_Q[Q_COUNT] = {
    [Q_MX] = {"mx", "1", "mean slope dz/dx (east)"},
    [Q_MY] = {"my", "1", "mean slope dz/dy (north)"},
    [Q_MXX] = {"mxx", "1", "mx^2 + C_xx"},
    [Q_MYY] = {"myy", "1", "my^2 + C_yy"},
    [Q_MXY] = {"mxy", "1", "mx my + C_xy"},
    [Q_H] = {"h", "m", "mean height of the generated waves"},
    [Q_ZERO] = {"unused", "1", "0 (unused)"},
    [Q_EMISSIVITY] = {"emissivity", "1", "effective emissivity toward the sensor"},
    [Q_REFLECTIVITY] = {"reflectivity", "sr^-1", "effective reflectivity sun -> sensor"},
    [Q_RADIANCE] = {"radiance", NULL,
                    "Eq 23 radiance toward the sensor, as it leaves the sea (no air)"},
    [Q_TEMPERATURE] = {"temperature", "K", "brightness temperature"},
    [Q_NX] = {"normal_x", "1", "(n_x + 1) / 2, tangent space, +x east"},
    [Q_NY] = {"normal_y", "1", "(n_y + 1) / 2, tangent space, +y north"},
    [Q_NZ] = {"normal_z", "1", "(n_z + 1) / 2"},
    [Q_ROUGHNESS] = {"roughness", "1", "Principled BSDF roughness = sqrt(sqrt(C_xx + C_yy))"},
    [Q_ANISOTROPY] = {"anisotropy", "1", "(l1 - l2) / (l1 + l2) of C"},
    [Q_ROTATION] = {"rotation", "turn", "major axis of C from east, counter-clockwise / 2 pi"},
    [Q_EMISSION] = {"emission", NULL,
                    "radiance x emission_scale of what the sensor sees there: the moments "
                    "seabake render reads (the level its footprint chooses, blended), "
                    "across the air along the range to the sensor (with [atmosphere]: "
                    "tau L + path, as seabake render's pixel)"},
};

const bake_group SEA_BAKE_GROUPS[BAKE_N_GROUPS] = {
    {"moments", 4, {Q_MX, Q_MY, Q_MXX, Q_MYY}, 0},
    {"moments2", 3, {Q_MXY, Q_H, Q_ZERO}, 0},
    {"optics", 4, {Q_EMISSIVITY, Q_REFLECTIVITY, Q_RADIANCE, Q_TEMPERATURE}, 2},
    {"normal", 3, {Q_NX, Q_NY, Q_NZ}, 0},
    {"roughness", 3, {Q_ROUGHNESS, Q_ANISOTROPY, Q_ROTATION}, 0},
    /* K x K texels a facet: one grey channel, Y (POV-Ray and Blender read
     * it as R = G = B), so only buf[0] is that large */
    {"emission", 1, {Q_EMISSION}, 0},
};
#define BAKE_GROUPS SEA_BAKE_GROUPS
#define BAKE_Q SEA_BAKE_Q

static const char *const CHANNEL_NAMES[GROUP_CH_MAX] = {"R", "G", "B", "A"};

const char *sea_bakemaps_channel(size_t g, size_t c)
{
    return BAKE_GROUPS[g].n == 1 ? "Y" : CHANNEL_NAMES[c];
}

char *sea_bakemaps_name(const char *group, int level, int framed, long frame, const char *ext)
{
    char buf[128];
    if (framed)
        snprintf(buf, sizeof buf, "%s_%d_%0*ld%s", group, level, SEA_BAKE_FRAME_DIGITS, frame,
                 ext);
    else
        snprintf(buf, sizeof buf, "%s_%d%s", group, level, ext);
    return strdup(buf);
}

const char *sea_bakemaps_unit(const sea_scene *sc, bake_quantity k)
{
    if (k == Q_RADIANCE)
        return sc->wavelength > 0.0 ? "W m^-2 sr^-1 um^-1" : "W m^-2 sr^-1";
    if (k == Q_EMISSION)
        return sc->wavelength > 0.0 ? "W m^-2 sr^-1 um^-1 x emission_scale"
                                    : "W m^-2 sr^-1 x emission_scale";
    return BAKE_Q[k].unit;
}

/* -------------------------------------------------------------- previews */

/* The mapping of each group's preview, one for every level and frame of a
 * bake, so that levels and frames compare: set from the first frame's
 * texels of every high-resolution level (at most BAKE_PREVIEW_SAMPLES of
 * them, evenly strided).  moments (mx) and moments2 (mx my + C_xy): grey,
 * linear, symmetric about 0 (mid grey), +-the 99.5 % quantile of |value|;
 * optics (radiance) and emission: grey, the tone curve of render's
 * preview (sea_png_tone_auto); normal: RGB = the map's (n + 1) / 2 as
 * stored; roughness: colour on an absolute scale, hue = 2 x rotation (the
 * major axis, a half turn around the colour wheel), saturation =
 * anisotropy, value = roughness (clamped to [0, 1]). */
enum { BAKE_PREVIEW_SAMPLES = 1 << 22 };

static void hsv_rgb(double h, double sat, double v, float rgb[3])
{
    h = 6.0 * (h - floor(h));
    sat = sat < 0.0 ? 0.0 : sat > 1.0 ? 1.0 : sat;
    v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
    const int i = (int)h % 6;
    const double f = h - floor(h), p = v * (1 - sat), q = v * (1 - sat * f),
                 t = v * (1 - sat * (1 - f));
    const double c[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)c[i][k];
}

/* The preview of group g (its channels in ch) to path. */
static sea_status write_preview(const char *path, size_t g, size_t width, size_t height,
                                const sea_exr_channel *ch, const bake_previews *pv,
                                sea_error *err)
{
    const bake_quantity q0 = BAKE_GROUPS[g].q[0];
    const size_t n = width * height;
    if (q0 == Q_NX || q0 == Q_ROUGHNESS) {
        float *rgb = malloc(3 * n * sizeof *rgb);
        if (rgb == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        for (size_t i = 0; i < n; i++) {
            if (q0 == Q_NX)
                for (int c = 0; c < 3; c++)
                    rgb[3 * i + c] = ch[c].data[i];
            else
                hsv_rgb(2.0 * ch[2].data[i], ch[1].data[i], ch[0].data[i], rgb + 3 * i);
        }
        const sea_png_text text[] = {
            {"seabake:quantity", BAKE_GROUPS[g].name},
            {"seabake:tone", q0 == Q_NX ? "RGB = (n + 1) / 2 as stored in the map"
                                        : "hue = 2 rotation (turns), saturation = anisotropy, "
                                          "value = roughness, absolute [0, 1]"}};
        sea_status st = sea_png_write_rgb(path, (int)width, (int)height, rgb, 8, text, 2, err);
        free(rgb);
        return st;
    }
    const char *quantity = BAKE_Q[BAKE_GROUPS[g].q[BAKE_GROUPS[g].preview]].name;
    const sea_png_text text[] = {{"seabake:quantity", quantity},
                                 {"seabake:range", pv->range[g]},
                                 {"seabake:tone", pv->text[g]}};
    return sea_png_write_toned(path, (int)width, (int)height, ch[BAKE_GROUPS[g].preview].data,
                               &pv->tone[g], 8, text, 3, err);
}

/* ------------------------------------------------------------------ maps */

static double texel_value(const sea_bake_level *bl, size_t q, bake_quantity k, double scale)
{
    const sea_moments mo = sea_facet_moments(&bl->moments[q]), *m = &mo;
    const sea_facet_optics *o = &bl->optics[q];
    double n[3], r[3];
    switch (k) {
    case Q_MX: return m->mx;
    case Q_MY: return m->my;
    case Q_MXX: return m->mxx;
    case Q_MYY: return m->myy;
    case Q_MXY: return m->mxy;
    case Q_H: return m->h;
    case Q_ZERO: return 0.0;
    case Q_EMISSIVITY: return o->emissivity;
    case Q_REFLECTIVITY: return o->reflectivity;
    case Q_RADIANCE: return o->radiance;
    case Q_TEMPERATURE: return o->temperature;
    case Q_NX:
    case Q_NY:
    case Q_NZ: sea_bake_normal(m, n); return 0.5 * (n[k - Q_NX] + 1.0);
    case Q_ROUGHNESS:
    case Q_ANISOTROPY:
    case Q_ROTATION:
        sea_bake_roughness(m, &r[0], &r[1], &r[2]);
        return r[k - Q_ROUGHNESS];
    case Q_EMISSION: return bl->view[q] * scale;
    case Q_COUNT: break;
    }
    return 0.0;
}

/* Fills the channels of group g of level bl: out[c] for each channel c
 * (the emission group's one channel of K x K texels a facet); the values
 * of texel_value, computed once a texel (the normal and the roughness give
 * their three channels at once). */
static void fill_group(const sea_bake_level *bl, size_t g, double scale,
                       float *const out[GROUP_CH_MAX])
{
    const bake_quantity q0 = BAKE_GROUPS[g].q[0];
    const size_t n = bl->level.nx * bl->level.ny;
    if (q0 == Q_EMISSION) {
        const size_t nv = n * bl->view_k * bl->view_k;
        for (size_t q = 0; q < nv; q++)
            out[0][q] = (float)(bl->view[q] * scale);
    } else if (q0 == Q_NX) {
        for (size_t q = 0; q < n; q++) {
            double nn[3];
            const sea_moments m = sea_facet_moments(&bl->moments[q]);
            sea_bake_normal(&m, nn);
            for (int c = 0; c < 3; c++)
                out[c][q] = (float)(0.5 * (nn[c] + 1.0));
        }
    } else if (q0 == Q_ROUGHNESS) {
        for (size_t q = 0; q < n; q++) {
            double r[3];
            const sea_moments m = sea_facet_moments(&bl->moments[q]);
            sea_bake_roughness(&m, &r[0], &r[1], &r[2]);
            for (int c = 0; c < 3; c++)
                out[c][q] = (float)r[c];
        }
    } else {
        for (size_t c = 0; c < BAKE_GROUPS[g].n; c++) {
            const bake_quantity k = BAKE_GROUPS[g].q[c];
            if (k == Q_ZERO) {
                memset(out[c], 0, n * sizeof *out[c]);
                continue;
            }
            for (size_t q = 0; q < n; q++)
                out[c][q] = (float)texel_value(bl, q, k, scale);
        }
    }
}

/* The files of group g of level lv at the writer's frame, from its channel
 * data (data[c], c < the group's channels; a repeated quantity reads the
 * channel before): the EXR map when exr, the PNG preview when png (and the
 * bake has previews). */
static sea_status write_group(const sea_bake_writer *w, const sea_clip_level *lv, size_t view_k,
                              size_t g, float *const data[GROUP_CH_MAX], int exr, int png,
                              sea_error *err)
{
    png = png && w->o.previews;
    char level_s[16], frame_s[32], time_s[32], facet_s[32], scale_s[32];
    snprintf(level_s, sizeof level_s, "%d", lv->level);
    snprintf(frame_s, sizeof frame_s, "%ld", w->frame);
    snprintf(time_s, sizeof time_s, "%.17g", w->t);
    snprintf(facet_s, sizeof facet_s, "%.17g", lv->facet);
    snprintf(scale_s, sizeof scale_s, "%.17g", w->scale);
    /* the emission map has K x K texels per facet */
    const size_t vk = BAKE_GROUPS[g].q[0] == Q_EMISSION ? view_k : 1;
    const size_t width = vk * lv->nx, height = vk * lv->ny;
    char channels[256] = "";
    size_t used = 0;
    sea_exr_channel ch[GROUP_CH_MAX];
    for (size_t c = 0; c < BAKE_GROUPS[g].n; c++) {
        const bake_quantity k = BAKE_GROUPS[g].q[c];
        ch[c].name = sea_bakemaps_channel(g, c);
        ch[c].data = data[c];
        int n = snprintf(channels + used, sizeof channels - used, "%s%s=%s", c ? "," : "",
                         sea_bakemaps_channel(g, c), BAKE_Q[k].name);
        if (n > 0 && (size_t)n < sizeof channels - used)
            used += (size_t)n;
    }
    const sea_exr_attr attrs[] = {{"seabake:quantity", BAKE_GROUPS[g].name},
                                  {"seabake:channels", channels},
                                  {"seabake:level", level_s},
                                  {"seabake:facet_m", facet_s},
                                  {"seabake:time_s", time_s},
                                  {"seabake:frame", frame_s},
                                  {"seabake:emission_scale", scale_s}};
    const size_t n_attrs = strcmp(BAKE_GROUPS[g].name, "emission") == 0 ? 7 : 6;
    const char *name = BAKE_GROUPS[g].name;
    char *exr_name = sea_bakemaps_name(name, lv->level, w->o.framed, w->frame, ".exr");
    char *png_name = sea_bakemaps_name(name, lv->level, w->o.framed, w->frame, ".png");
    char *exr_path = exr_name ? sea_path_join(w->dir, exr_name) : NULL;
    char *png_path = png_name ? sea_path_join(w->dir, png_name) : NULL;
    sea_status st = SEA_OK;
    if (exr_path == NULL || png_path == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    } else {
        if (exr)
            st = sea_exr_write(exr_path, (int)width, (int)height, ch, BAKE_GROUPS[g].n, attrs,
                               n_attrs, &w->o.exr, err);
        if (st == SEA_OK && png)
            st = write_preview(png_path, g, width, height, ch, &w->pv, err);
    }
    free(exr_name);
    free(png_name);
    free(exr_path);
    free(png_path);
    return st;
}

sea_status sea_bakemaps_grey(const sea_bake_writer *w, const char *name, size_t wd, size_t ht,
                             double (*value)(const void *, size_t), const void *ctx,
                             const char *quantity, const char *key, const char *key_value,
                             sea_error *err)
{
    float *map = malloc(wd * ht * sizeof *map);
    char *path = sea_path_join(w->dir, name);
    sea_status st = SEA_OK;
    if (map == NULL || path == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %s", name);
    } else {
        const double scale = w->scale;
        for (size_t q = 0; q < wd * ht; q++)
            map[q] = (float)(value(ctx, q) * scale);
        char scale_s[32];
        snprintf(scale_s, sizeof scale_s, "%.17g", scale);
        const sea_exr_attr attrs[] = {{"seabake:quantity", quantity},
                                      {"seabake:emission_scale", scale_s},
                                      {key, key_value}};
        const sea_exr_channel ch[1] = {{"Y", map}};
        st = sea_exr_write(path, (int)wd, (int)ht, ch, 1, attrs, 3, &w->o.exr, err);
    }
    free(map);
    free(path);
    return st;
}

/* ------------------------------------------------------------ the heights
 *
 * The waves' surface of a level for the exports (emission space sensor):
 * the surface seabake render marches (sea_heightfield_at of the level's
 * facet moments, Hermite patches through the facet centres), sampled S =
 * sea_bakemaps_height_samples(level) times per facet side from the
 * rectangle's south-west corner to its north-east one, (S nx + 1) x
 * (S ny + 1) samples, row 0 the north edge; each sample's height is that of
 * its sea point (sea_camera_sea_point: on a spherical Earth the sphere's
 * drop) plus the surface's height along the local vertical.  S is
 * BAKE_HEIGHT_S_MAX (6.9 mm from the surface between samples on 1 m
 * facets, where 2 gave 5.1 cm), fewer on a level wider than
 * BAKE_HEIGHT_SIDE / BAKE_HEIGHT_S_MAX facets so that a side keeps at most
 * BAKE_HEIGHT_SIDE + 1 samples (at least one a facet: a 2048-facet level
 * has 2049 x 2049, 8 MB of PNG, not 8193 x 8193). */
enum { BAKE_HEIGHT_S_MAX = 4, BAKE_HEIGHT_SIDE = 1024, BAKE_HEIGHT_STRIP = 64 };

int sea_bakemaps_height_samples(const sea_clip_level *lv)
{
    const size_t side = lv->nx > lv->ny ? lv->nx : lv->ny;
    const size_t s = side > 0 ? BAKE_HEIGHT_SIDE / side : BAKE_HEIGHT_S_MAX;
    return s < 1 ? 1 : s > BAKE_HEIGHT_S_MAX ? BAKE_HEIGHT_S_MAX : (int)s;
}

static sea_status level_heights(const sea_camera *cam, const sea_bake_level *bl, float **out,
                                size_t *width, size_t *height, double *lo, double *hi,
                                sea_error *err)
{
    const sea_clip_level *lv = &bl->level;
    const size_t S = (size_t)sea_bakemaps_height_samples(lv), nx = lv->nx, ny = lv->ny,
                 W = S * nx + 1, H = S * ny + 1;
    *out = NULL;
    sea_status st = sea_check_size(W, H * sizeof(float), "height samples", err);
    if (st != SEA_OK)
        return st;
    /* by strips of BAKE_HEIGHT_STRIP node rows (and the next), each a
     * surface of its own: a sample between two node rows reads only them
     * (beyond the outer rows the surface continues from the outer cell), so
     * the whole level's surface is never held twice */
    const size_t strip = ny - 1 < BAKE_HEIGHT_STRIP ? ny - 1 : BAKE_HEIGHT_STRIP;
    sea_facet *south = malloc((strip + 1) * nx * sizeof *south);
    float *z = malloc(W * H * sizeof *z);
    if (south == NULL || z == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the heights of level %d", lv->level);
    for (size_t j0 = 0; st == SEA_OK && j0 + 1 < ny; j0 += strip) {
        const size_t j1 = j0 + strip < ny - 1 ? j0 + strip : ny - 1; /* node rows j0..j1 */
        for (size_t j = j0; j <= j1; j++) /* bl->moments: north first */
            memcpy(south + (j - j0) * nx, bl->moments + (ny - 1 - j) * nx, nx * sizeof *south);
        const sea_rect rect = {lv->facet, lv->i0, lv->j0 + (long)j0, nx, j1 - j0 + 1};
        sea_heightfield *hf = NULL;
        if ((st = sea_heightfield_alloc_facets(&rect, south, &hf, err)) != SEA_OK)
            break;
        const double step = lv->facet / (double)S;
#pragma omp parallel for schedule(static)
        for (size_t r = 0; r < H; r++) {
            /* sample row m = H - 1 - r, at node row position m / S - 1/2 */
            const double fm = (double)(H - 1 - r) / (double)S - 0.5;
            if (!((j0 == 0 || fm >= (double)j0) && (j1 == ny - 1 || fm < (double)j1)))
                continue;
            const double y = (double)lv->j0 * lv->facet + (double)(H - 1 - r) * step;
            for (size_t k = 0; k < W; k++) {
                const double x = (double)lv->i0 * lv->facet + (double)k * step;
                double q[3], n[3];
                sea_camera_sea_point(cam, x, y, q, n);
                z[r * W + k] = (float)(q[2] + sea_heightfield_at(hf, x, y).h * n[2]);
            }
        }
        sea_heightfield_free(hf);
    }
    if (st == SEA_OK) {
        double a = INFINITY, b = -INFINITY;
        for (size_t q = 0; q < W * H; q++) {
            a = fmin(a, z[q]);
            b = fmax(b, z[q]);
        }
        if (!(isfinite(a) && isfinite(b)))
            st = sea_fail(err, SEA_ERR_NUMERIC, "level %d: a height is not finite", lv->level);
        /* a flat level still gets a range */
        if (!(b > a)) {
            a -= 0.5;
            b += 0.5;
        }
        *lo = a;
        *hi = b;
    }
    free(south);
    if (st != SEA_OK) {
        free(z);
        return st;
    }
    *out = z;
    *width = W;
    *height = H;
    return SEA_OK;
}

/* The heights of level bl at the writer's frame (level_heights): for the
 * POV-Ray scene a 16-bit grey PNG from *lo (black) to *hi (white), set
 * here, height_<l>[_FFFF].png, for Blender an EXR of the displacement in
 * metres (R = G = 0, B the height), height_<l>[_FFFF].exr. */
static sea_status write_heights(const sea_bake_writer *w, const sea_bake_level *bl, double *lo,
                                double *hi, sea_error *err)
{
    float *z = NULL;
    size_t W = 0, H = 0;
    sea_status st = level_heights(sea_view_camera(w->r), bl, &z, &W, &H, lo, hi, err);
    if (st != SEA_OK)
        return st;
    const int level = bl->level.level;
    char *png = sea_bakemaps_name("height", level, w->o.framed, w->frame, ".png");
    char *exr = sea_bakemaps_name("height", level, w->o.framed, w->frame, ".exr");
    char *path = NULL;
    if (png == NULL || exr == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    if (st == SEA_OK && w->o.pov) {
        if ((path = sea_path_join(w->dir, png)) == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        else
            st = sea_png_write_gray(path, (int)W, (int)H, z, *lo, *hi, 16, err);
        free(path);
    }
    if (st == SEA_OK && w->o.blender) {
        /* a displacement vector (0, 0, height), as Blender's Displace
         * modifier reads RGB */
        float *zero = calloc(W * H, sizeof *zero);
        const sea_exr_attr attrs[] = {{"seabake:quantity", "height"}};
        const sea_exr_channel ch[3] = {{"R", zero}, {"G", zero}, {"B", z}};
        if ((path = sea_path_join(w->dir, exr)) == NULL || zero == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        else
            st = sea_exr_write(path, (int)W, (int)H, ch, 3, attrs, 1, &w->o.exr, err);
        free(path);
        free(zero);
    }
    free(png);
    free(exr);
    free(z);
    return st;
}

/* ------------------------------------------------------------ streaming */

/* The groups whose preview needs the first frame's tone curve. */
static int toned_group(size_t g)
{
    const bake_quantity k = BAKE_GROUPS[g].q[BAKE_GROUPS[g].preview];
    return k != Q_NX && k != Q_ROUGHNESS;
}

/* Spill file of a level: the previewed channel of each toned group but
 * emission (n floats each, in group order), then the n K^2 view radiances
 * (floats, as the level holds them). */
enum { SPILL_CHANNELS = 3 };
static const size_t SPILL_GROUP[SPILL_CHANNELS] = {0, 1, 2};

static char *spill_path(const char *dir, int level)
{
    char name[64];
    snprintf(name, sizeof name, ".spill_%d", level);
    return sea_path_join(dir, name);
}

static sea_status spill_io(int fd, int out, void *data, size_t bytes, size_t offset,
                           sea_error *err)
{
    unsigned char *p = data;
    while (bytes > 0) {
        const ssize_t k = out ? pwrite(fd, p, bytes, (off_t)offset)
                              : pread(fd, p, bytes, (off_t)offset);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return sea_fail(err, SEA_ERR_IO, "cannot %s a spill file: %s",
                            out ? "write" : "read", k < 0 ? strerror(errno) : "short file");
        p += k;
        bytes -= (size_t)k;
        offset += (size_t)k;
    }
    return SEA_OK;
}

/* The jobs of a level's files: a group's files (its index), and two that
 * are not a group: the emission group's preview alone (its map, the
 * largest file, is then the job BAKE_EMISSION alone, so that the two run
 * on different threads), and the view texels into the spill file (while
 * the groups are written). */
enum {
    BAKE_EMISSION = BAKE_N_GROUPS - 1, /* the last group of SEA_BAKE_GROUPS */
    JOB_EMISSION_PNG = BAKE_N_GROUPS,
    JOB_SPILL_VIEW,
    JOB_MAX
};

/* Whether job g is one of the emission group's: BAKE_EMISSION (its map)
 * or JOB_EMISSION_PNG (its preview). */
static int is_emission_job(size_t g)
{
    return g == BAKE_EMISSION || g == JOB_EMISSION_PNG;
}

/* Emission job g of level lv, from w->emission (filled before the jobs). */
static sea_status emission_job(const sea_bake_writer *w, const sea_clip_level *lv, size_t view_k,
                               size_t g, sea_error *err)
{
    float *const data[GROUP_CH_MAX] = {w->emission, NULL, NULL, NULL};
    return write_group(w, lv, view_k, BAKE_EMISSION, data, g == BAKE_EMISSION,
                       g == JOB_EMISSION_PNG, err);
}

/* Runs the jobs (group indices and the JOB_ ones) of a level in parallel,
 * the first failure in job order returned; job(w, ctx, g, buffers, err). */
typedef sea_status (*group_job)(const sea_bake_writer *w, const void *ctx, size_t g,
                                float *const buf[GROUP_CH_MAX], sea_error *err);

static sea_status run_jobs(const sea_bake_writer *w, const void *ctx, const size_t *jobs,
                           size_t n, group_job job, sea_error *err)
{
    sea_status st[JOB_MAX];
    sea_error e[JOB_MAX];
#ifdef _OPENMP
    /* A job's EXR file compresses its chunks on a team of its own
     * (sea_exr_write): let that team run inside this one, so that the
     * largest file (emission, K^2 texels a facet) does not compress on one
     * thread while the others, done with the small groups, wait.  (OpenMP's
     * setting, the process's: restored below.) */
    const int levels = omp_get_max_active_levels();
    if (levels < 2)
        omp_set_max_active_levels(2);
#endif
#pragma omp parallel for schedule(dynamic, 1) num_threads((int)w->threads) if (w->threads > 1)
    for (size_t i = 0; i < n; i++) {
        size_t id = 0;
#ifdef _OPENMP
        id = (size_t)omp_get_thread_num();
#endif
        float *buf[GROUP_CH_MAX];
        for (size_t c = 0; c < GROUP_CH_MAX; c++)
            buf[c] = w->pool + (id * GROUP_CH_MAX + c) * w->nmax;
        st[i] = job(w, ctx, jobs[i], buf, &e[i]);
    }
#ifdef _OPENMP
    omp_set_max_active_levels(levels);
#endif
    for (size_t i = 0; i < n; i++)
        if (st[i] != SEA_OK) {
            if (err != NULL)
                *err = e[i];
            return st[i];
        }
    return SEA_OK;
}

/* A level's group g now: its maps, and its preview unless deferred (then
 * the previewed channel to the spill file). */
typedef struct {
    const sea_bake_level *bl;
    int spill;
} level_job_ctx;

static sea_status level_job(const sea_bake_writer *w, const void *ctx, size_t g,
                            float *const buf[GROUP_CH_MAX], sea_error *err)
{
    const level_job_ctx *c = ctx;
    const sea_bake_level *bl = c->bl;
    const size_t n = bl->level.nx * bl->level.ny;
    if (g == JOB_SPILL_VIEW)
        return spill_io(c->spill, 1, bl->view, n * bl->view_k * bl->view_k * sizeof(float),
                        SPILL_CHANNELS * n * sizeof(float), err);
    if (is_emission_job(g))
        return emission_job(w, &bl->level, bl->view_k, g, err);
    fill_group(bl, g, w->scale, buf);
    if (w->defer && w->o.previews && toned_group(g)) {
        for (size_t k = 0; k < SPILL_CHANNELS; k++)
            if (SPILL_GROUP[k] == g)
                return spill_io(c->spill, 1, buf[BAKE_GROUPS[g].preview], n * sizeof(float),
                                k * n * sizeof(float), err) == SEA_OK
                           ? write_group(w, &bl->level, bl->view_k, g, buf, 1, 0, err)
                           : SEA_ERR_IO;
    }
    return write_group(w, &bl->level, bl->view_k, g, buf, 1, 1, err);
}

sea_status sea_bakemaps_level(sea_bake_writer *w, const sea_bake *b, size_t l, sea_error *err)
{
    const sea_bake_level *bl = &b->levels[l];
    const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
    sea_status st = SEA_OK;
    level_job_ctx c = {bl, -1};
    size_t jobs[JOB_MAX], nj = 0;
    if (w->defer) {
        /* (the radiances are finite: sea_bake checks them) */
        double top = w->top;
#pragma omp parallel for schedule(static) reduction(max : top)
        for (size_t q = 0; q < n; q++)
            top = fmax(top, bl->optics[q].radiance);
#pragma omp parallel for schedule(static) reduction(max : top)
        for (size_t q = 0; q < nv; q++)
            top = fmax(top, bl->view[q]);
        w->top = top;
        char *path = spill_path(w->dir, bl->level.level);
        if (path == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        c.spill = open(path, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
        if (c.spill < 0)
            st = sea_fail(err, SEA_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
        free(path);
        jobs[nj++] = JOB_SPILL_VIEW; /* the largest first */
    } else {
        const double scale = w->scale;
        float *const e = w->emission;
#pragma omp parallel for schedule(static)
        for (size_t q = 0; q < nv; q++)
            e[q] = (float)(bl->view[q] * scale);
        jobs[nj++] = BAKE_EMISSION; /* the largest first */
        if (w->o.previews)
            jobs[nj++] = JOB_EMISSION_PNG;
    }
    for (size_t g = 0; g < BAKE_N_GROUPS; g++)
        if (BAKE_GROUPS[g].q[0] != Q_EMISSION)
            jobs[nj++] = g;
    if (st == SEA_OK)
        st = run_jobs(w, &c, jobs, nj, level_job, err);
    const size_t h = l * w->n_frames + (size_t)(w->frame - w->first);
    if (st == SEA_OK && w->height_lo != NULL)
        st = write_heights(w, bl, &w->height_lo[h], &w->height_hi[h], err);
    if (c.spill >= 0 && close(c.spill) != 0 && st == SEA_OK)
        st = sea_fail(err, SEA_ERR_IO, "cannot write a spill file: %s", strerror(errno));
    w->stats.texels += n;
    return st;
}

/* Every group's preview mapping, from the first frame's spill files (see
 * bake_previews): at most BAKE_PREVIEW_SAMPLES texels of every
 * high-resolution level, evenly strided. */
sea_status sea_bakemaps_previews_setup(sea_bake_writer *w, const sea_bake *b, sea_error *err)
{
    enum { CHUNK = 1 << 16 };
    bake_previews *pv = &w->pv;
    const double scale = w->scale;
    float *v = malloc(BAKE_PREVIEW_SAMPLES * sizeof *v);
    float *chunk = malloc(CHUNK * sizeof *chunk);
    sea_status st = SEA_OK;
    if (v == NULL || chunk == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the preview ranges");
    for (size_t g = 0; g < BAKE_N_GROUPS && st == SEA_OK; g++) {
        const bake_quantity k = BAKE_GROUPS[g].q[BAKE_GROUPS[g].preview];
        sea_png_tone *t = &pv->tone[g];
        snprintf(pv->range[g], sizeof pv->range[g], "absolute");
        snprintf(pv->text[g], sizeof pv->text[g], "see seabake(1), BAKE");
        sea_png_tone_linear(0.0, 1.0, t, NULL);
        if (!toned_group(g))
            continue; /* RGB on absolute scales */
        size_t spilled = 0;
        while (spilled < SPILL_CHANNELS && SPILL_GROUP[spilled] != g)
            spilled++;
        size_t total = 0, m = 0;
        for (size_t l = 0; l < b->n_levels; l++)
            if (!b->levels[l].level.low_res)
                total += b->levels[l].level.nx * b->levels[l].level.ny *
                         (k == Q_EMISSION ? b->levels[l].view_k * b->levels[l].view_k : 1);
        const size_t stride = total / BAKE_PREVIEW_SAMPLES + 1;
        size_t at = 0; /* index into the levels' texels, one after another */
        for (size_t l = 0; l < b->n_levels && st == SEA_OK; l++) {
            const sea_bake_level *bl = &b->levels[l];
            if (bl->level.low_res)
                continue;
            const size_t nf = bl->level.nx * bl->level.ny;
            const size_t n = nf * (k == Q_EMISSION ? bl->view_k * bl->view_k : 1);
            char *path = spill_path(w->dir, bl->level.level);
            const int fd = path ? open(path, O_RDONLY | O_CLOEXEC) : -1;
            if (fd < 0)
                st = sea_fail(err, SEA_ERR_IO, "cannot open a spill file: %s", strerror(errno));
            free(path);
            size_t q = (stride - at % stride) % stride, c0 = 0, c1 = 0; /* chunk [c0, c1) */
            for (; q < n && m < BAKE_PREVIEW_SAMPLES && st == SEA_OK; q += stride) {
                if (q >= c1) {
                    c0 = q;
                    c1 = q + CHUNK < n ? q + CHUNK : n;
                    /* (the view radiances after the other channels) */
                    const size_t from = k == Q_EMISSION ? SPILL_CHANNELS * nf : spilled * nf;
                    st = spill_io(fd, 0, chunk, (c1 - c0) * sizeof(float),
                                  (from + c0) * sizeof(float), err);
                }
                if (k == Q_EMISSION)
                    v[m++] = (float)(chunk[q - c0] * scale);
                else
                    v[m++] = chunk[q - c0];
            }
            if (fd >= 0)
                close(fd);
            at += n;
        }
        if (st != SEA_OK)
            break;
        if (k == Q_RADIANCE || k == Q_EMISSION) {
            sea_png_tone_auto(v, m, t);
        } else {
            /* slopes: symmetric about 0 */
            static const double p[2] = {0.005, 0.995};
            double qv[2];
            sea_png_quantiles(v, m, p, 2, qv);
            double a = fmax(fabs(qv[0]), fabs(qv[1]));
            if (!(a > 0.0) || !isfinite(a))
                a = 1.0;
            sea_png_tone_linear(-a, a, t, NULL);
        }
        snprintf(pv->range[g], sizeof pv->range[g], "%.6g:%.6g", t->lo, t->hi);
        if (t->knee < t->hi)
            snprintf(pv->text[g], sizeof pv->text[g],
                     "%s: linear %.6g black, %.6g %.0f %% grey; linear to %.6g white",
                     BAKE_Q[k].name, t->lo, t->knee, 100.0 * SEA_PNG_KNEE_GREY, t->hi);
        else
            snprintf(pv->text[g], sizeof pv->text[g], "%s: linear %.6g black to %.6g white",
                     BAKE_Q[k].name, t->lo, t->hi);
    }
    free(v);
    free(chunk);
    return st;
}

/* The deferred files of one level of the first frame, from its spill file. */
typedef struct {
    const sea_clip_level *lv;
    size_t view_k;
    float *const *spilled; /* SPILL_CHANNELS channels of n floats */
} spill_job_ctx;

static sea_status spill_job(const sea_bake_writer *w, const void *ctx, size_t g,
                            float *const buf[GROUP_CH_MAX], sea_error *err)
{
    (void)buf;
    const spill_job_ctx *c = ctx;
    if (is_emission_job(g))
        return emission_job(w, c->lv, c->view_k, g, err);
    float *data[GROUP_CH_MAX] = {NULL, NULL, NULL, NULL};
    for (size_t k = 0; k < SPILL_CHANNELS; k++)
        if (SPILL_GROUP[k] == g)
            data[BAKE_GROUPS[g].preview] = c->spilled[k];
    return write_group(w, c->lv, c->view_k, g, data, 0, 1, err);
}

sea_status sea_bakemaps_spilled(sea_bake_writer *w, const sea_bake *b, sea_error *err)
{
    sea_status st = SEA_OK;
    /* without previews only the emission maps waited */
    const size_t n_spilled = w->o.previews ? SPILL_CHANNELS : 0;
    for (size_t l = 0; l < b->n_levels && st == SEA_OK; l++) {
        const sea_bake_level *bl = &b->levels[l];
        if (bl->level.low_res)
            continue;
        if (sea_bakedir_cancelled(w)) {
            st = sea_fail(err, SEA_ERR_CANCELLED, "bake cancelled writing level %d",
                          bl->level.level);
            break;
        }
        const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
        char *path = spill_path(w->dir, bl->level.level);
        const int fd = path ? open(path, O_RDONLY | O_CLOEXEC) : -1;
        if (fd < 0)
            st = sea_fail(err, SEA_ERR_IO, "cannot open a spill file: %s", strerror(errno));
        /* the spilled channels in the last thread's buffers */
        float *spilled[SPILL_CHANNELS];
        for (size_t k = 0; k < SPILL_CHANNELS; k++) {
            spilled[k] = w->pool + ((w->threads - 1) * GROUP_CH_MAX + k) * w->nmax;
            if (st == SEA_OK && k < n_spilled)
                st = spill_io(fd, 0, spilled[k], n * sizeof(float), k * n * sizeof(float), err);
        }
        /* the view radiances, then as the emission map holds them */
        if (st == SEA_OK)
            st = spill_io(fd, 0, w->emission, nv * sizeof(float),
                          SPILL_CHANNELS * n * sizeof(float), err);
        if (st == SEA_OK) {
            const double scale = w->scale;
            float *const e = w->emission;
#pragma omp parallel for schedule(static)
            for (size_t q = 0; q < nv; q++)
                e[q] = (float)(e[q] * scale);
        }
        if (fd >= 0)
            close(fd);
        if (path != NULL)
            unlink(path);
        free(path);
        const spill_job_ctx c = {&bl->level, bl->view_k, spilled};
        /* the emission map and its preview first, the largest */
        size_t jobs[2 + SPILL_CHANNELS] = {BAKE_EMISSION, JOB_EMISSION_PNG};
        size_t nj = w->o.previews ? 2 : 1;
        for (size_t k = 0; k < n_spilled; k++)
            jobs[nj++] = SPILL_GROUP[k];
        if (st == SEA_OK)
            st = run_jobs(w, &c, jobs, nj, spill_job, err);
    }
    return st;
}
