/* bake.c - the bake subcommand of seabake: a scene file
 * (seabake-scene(5)) to a directory of per-level maps and a manifest.
 *
 * One prepare (as render), then one sea_bake_frame per frame.  Each
 * high-resolution clipmap level l gets, per frame, single-part scanline EXR
 * files of plain R, G, B(, A) channels named <quantity>_<l>[_<frame>].exr
 * (see BAKE_GROUPS) and an 8-bit PNG preview of each (see bake_previews:
 * one mapping per quantity for every level and frame of a bake).
 * Low-resolution levels get no files: their constants are in manifest.json,
 * which also places every map in the world (JSON through cJSON; the library
 * stays JSON-free).
 *
 * Atomic output.  Everything is written into a fresh sibling directory
 * DIR.tmp.XXXXXX (mkdtemp, same parent as DIR, so renames stay on one file
 * system).  Only when every file is there: an existing DIR (which must be a
 * directory) is renamed aside to DIR.old.XXXXXX, the new directory renamed
 * to DIR, and the old one removed.  On any failure before that the
 * temporary directory is removed and DIR is exactly as it was. */
#define _XOPEN_SOURCE 700
#include <assert.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli.h"
#include "config.h"
#include "bakedir.h"
#include "blender.h"
#include "exr.h"
#include "povray.h"
#include "preview.h"

/* ------------------------------------------------------------ constants */

/* Emission texels per facet side, odd.  Radiance is not linear in the slope
 * moments (the glint above all), so a renderer's bilinear lookup of the
 * radiance matches seabake render's bilinear lookup of the moments only on
 * a grid finer than the facets; and the grid must hold the facet centres,
 * where the interpolated moments have their kinks, or the error is of
 * first order (an even K, measured, is worse than K = 1).  Relative RMS
 * difference POV-Ray vs seabake render, tests/scenes/pov_slant.ini
 * (oblique) and pov_glint.ini (nadir): K = 1, 2.9 % and 0.65 %; K = 3,
 * 0.61 % and 0.23 %; K = 5, 0.25 % and 0.095 %; K = 7, 0.15 % and 0.055 %. */
enum { BAKE_VIEW_K_DEFAULT = 3 };
/* The emission maps carry radiance x scale, scale a power of ten putting
 * the largest radiance of the first frame at or just below this value:
 * well inside half range (65504) with its 3.3 significant digits, and
 * room for later frames' glints. */
static const double BAKE_EMISSION_TARGET = 1000.0;
/* The low-resolution sea to the horizon, for --pov and --blender
 * (sea_bake_horizon_make): its map, scaled as the emission maps. */
static const char HORIZON_MAP[] = "horizon.exr";
/* The sensor's image for --emission-space sensor: "sensor.exr", with
 * frames "sensor_FFFF.exr" (SENSOR_PREFIX and the frame number). */
static const char SENSOR_PREFIX[] = "sensor_";
static const int BAKE_MANIFEST_VERSION = 1;

/* The quantities a texel can carry. */
typedef enum {
    Q_MX, Q_MY, Q_MXX, Q_MYY, Q_MXY, Q_H, Q_ZERO,
    Q_EMISSIVITY, Q_REFLECTIVITY, Q_RADIANCE, Q_TEMPERATURE,
    Q_NX, Q_NY, Q_NZ, Q_ROUGHNESS, Q_ANISOTROPY, Q_ROTATION, Q_EMISSION
} bake_quantity;

static const struct {
    const char *name, *unit, *meaning;
} BAKE_Q[] = {
    [Q_MX] = {"mx", "1", "mean slope dz/dx (east)"},
    [Q_MY] = {"my", "1", "mean slope dz/dy (north)"},
    [Q_MXX] = {"mxx", "1", "mx^2 + C_xx"},
    [Q_MYY] = {"myy", "1", "my^2 + C_yy"},
    [Q_MXY] = {"mxy", "1", "mx my + C_xy"},
    [Q_H] = {"h", "m", "mean height of the generated waves"},
    [Q_ZERO] = {"unused", "1", "0 (unused)"},
    [Q_EMISSIVITY] = {"emissivity", "1", "effective emissivity toward the sensor"},
    [Q_REFLECTIVITY] = {"reflectivity", "sr^-1", "effective reflectivity sun -> sensor"},
    [Q_RADIANCE] = {"radiance", NULL, "Eq 23 radiance toward the sensor"},
    [Q_TEMPERATURE] = {"temperature", "K", "brightness temperature"},
    [Q_NX] = {"normal_x", "1", "(n_x + 1) / 2, tangent space, +x east"},
    [Q_NY] = {"normal_y", "1", "(n_y + 1) / 2, tangent space, +y north"},
    [Q_NZ] = {"normal_z", "1", "(n_z + 1) / 2"},
    [Q_ROUGHNESS] = {"roughness", "1", "Principled BSDF roughness = sqrt(sqrt(C_xx + C_yy))"},
    [Q_ANISOTROPY] = {"anisotropy", "1", "(l1 - l2) / (l1 + l2) of C"},
    [Q_ROTATION] = {"rotation", "turn", "major axis of C from east, counter-clockwise / 2 pi"},
    [Q_EMISSION] = {"emission", NULL,
                    "radiance x emission_scale of what the sensor sees there: the moments "
                    "seabake render reads (the level its footprint chooses, blended)"},
};

enum { GROUP_CH_MAX = 4 };
/* One file per group; preview = the channel shown in the PNG. */
static const struct {
    const char *name;
    size_t n;
    bake_quantity q[GROUP_CH_MAX];
    size_t preview;
} BAKE_GROUPS[] = {
    {"moments", 4, {Q_MX, Q_MY, Q_MXX, Q_MYY}, 0},
    {"moments2", 3, {Q_MXY, Q_H, Q_ZERO}, 0},
    {"optics", 4, {Q_EMISSIVITY, Q_REFLECTIVITY, Q_RADIANCE, Q_TEMPERATURE}, 2},
    {"normal", 3, {Q_NX, Q_NY, Q_NZ}, 0},
    {"roughness", 3, {Q_ROUGHNESS, Q_ANISOTROPY, Q_ROTATION}, 0},
    /* K x K texels a facet: one grey channel, Y (POV-Ray and Blender read
     * it as R = G = B), so only buf[0] is that large */
    {"emission", 1, {Q_EMISSION}, 0},
};
enum { BAKE_N_GROUPS = sizeof BAKE_GROUPS / sizeof BAKE_GROUPS[0] };
static const char *const CHANNEL_NAMES[GROUP_CH_MAX] = {"R", "G", "B", "A"};

/* Channel c of group g: Y alone, or R, G, B, A. */
static const char *channel_name(size_t g, size_t c)
{
    return BAKE_GROUPS[g].n == 1 ? "Y" : CHANNEL_NAMES[c];
}

/* ------------------------------------------------------------ help text */

static const char BAKE_HELP[] =
    "Usage: seabake bake SCENE.ini -o DIR [OPTIONS]\n"
    "\n"
    "Bakes the clipmap levels a scene's view needs (seabake-scene(5)) into DIR:\n"
    "for every high-resolution level l and frame, single-part EXR maps of plain\n"
    "R,G,B(,A) channels (Y alone for emission), <quantity>_<l>[_<frame>].exr, and\n"
    "a PNG preview of each:\n"
    "  moments_<l>    R mx, G my, B mx^2+C_xx, A my^2+C_yy (LEAN moments)\n"
    "  moments2_<l>   R mx my+C_xy, G height (m), B unused (0)\n"
    "  optics_<l>     R emissivity, G reflectivity sun -> sensor (sr^-1),\n"
    "                 B radiance (Eq 23), A brightness temperature (K)\n"
    "  normal_<l>     RGB (n+1)/2 of the mean-slope normal (+x east, +y north)\n"
    "  roughness_<l>  R roughness (GGX, Blender: sqrt(sqrt(C_xx+C_yy))),\n"
    "                 G anisotropy, B rotation (turns from east)\n"
    "  emission_<l>   Y radiance x scale of what the sensor sees (the moments\n"
    "                 seabake render reads there), K x K texels per facet (one\n"
    "                 grey channel: POV-Ray and Blender read it as R = G = B)\n"
    "With --pov or --blender (and --emission-space sensor, the default) also\n"
    "  sensor[_FFFF].exr  the sensor's image (Y radiance x scale), projected\n"
    "                 by both exports where the sensor sees\n"
    "  height_<l>     the waves' surface, 4 samples per facet side (fewer past\n"
    "                 256 facets a side): .png 16-bit (POV-Ray's height_field),\n"
    "                 .exr B in metres (Blender)\n"
    "Previews: one mapping per quantity for all levels and frames; normal in\n"
    "colour as stored, roughness in colour on an absolute scale (value\n"
    "roughness, saturation anisotropy, hue 2 x rotation); seabake(1), BAKE.\n"
    "Row 0 is the north edge.  Low-resolution levels get no maps; manifest.json\n"
    "lists every level (facet size, origin, extent, texels, files, channels,\n"
    "units), the scene, the sensor, seed, times, the emission scale and every\n"
    "file of DIR.  An existing DIR is replaced only if it is empty or a bake that\n"
    "seabake wrote (its manifest lists every file in it); anything else is refused\n"
    "before any work.  DIR is replaced atomically: a failed bake leaves it as it\n"
    "was.  Two bakes into one\n"
    "DIR both succeed (the later wins; one waits for the other's commit); the\n"
    "temporaries of a killed bake are removed by the next one.\n"
    "\n"
    "Options:\n"
    "  -o DIR              the output directory (required); its parent must exist;\n"
    "                      not '.', '..' or '/'; if it exists, empty or a bake\n"
    "                      seabake wrote; a symbolic link to a directory\n"
    "                      is followed (that directory replaced, the link kept)\n"
    "  --format F          float (default) or half channels, as in seabake render\n"
    "  --compression C     none, zip (default) or piz\n"
    "  --frames A:B        frames A to B, integers, 0 <= A <= B <= 999999; frame f\n"
    "                      at time + f / HZ, names get _FFFF; default: one frame\n"
    "                      at the scene's time, no number\n"
    "  --frame-rate HZ     frames per second, > 0; default 25 (only with --frames);\n"
    "                      every frame's time, [sea] time + frame / HZ, within\n"
    "                      +-1e9 s\n"
    "  --emission-texels K emission texels per facet side, odd, 1 to 7 (default 3)\n"
    "  --emission-space S  what the exported sea shows where the sensor sees it:\n"
    "                      sensor (default: the sensor's image, DIR/sensor.exr,\n"
    "                      projected from its position, so that the sensor's view\n"
    "                      is seabake render's image, on rings with the waves)\n"
    "                      or map (each level's emission map on flat rings);\n"
    "                      only with --pov or --blender\n"
    "  --pov               also a POV-Ray scene: DIR/scene.pov, sea.inc (the sea, to\n"
    "                      include in a scene of your own), scene.ini, seabake.inc;\n"
    "                      with --frames, scene.ini renders every frame\n"
    "  --blender           also the Blender import: DIR/seabake_import.py, run as\n"
    "                      blender -b --factory-startup --python DIR/seabake_import.py\n"
    "                        -- DIR/manifest.json [--save FILE.blend] [--render OUT.exr]\n"
    "                      (frames as image sequences; --render-frames OUT_####.exr)\n"
    "  --tolerance T       relative, (0, 0.1]: overrides the scene's [model]\n"
    "                      tolerance, as in seabake render\n"
    "  --reflections R     auto (default), 1, 2 or 3: overrides the scene's [model]\n"
    "                      reflections, as in seabake render\n"
    "  --reference         every approximation exact, as in seabake render\n"
    "  --shadowing S       correlated or smith: overrides the scene's [model]\n"
    "                      shadowing, as in seabake render\n"
    "  --scales N          2 or 1: overrides the scene's [model] scales, as in\n"
    "                      seabake render\n"
    "  --set SECTION.KEY=VALUE\n"
    "                      overrides a key of the scene file (as in seabake\n"
    "                      render); repeatable\n"
    "  --explain           what is modelled and why (as seabake render --explain)\n"
    "  --quiet             no progress bar and no summary line\n"
    "\n"
    "Under mpirun or srun (a build with MPI) the frames, or the texel rows of\n"
    "one frame, are shared among the ranks, rank 0 writing every file: DIR is\n"
    "that of one process; seabake(1), PARALLEL RUNS WITH MPI.\n";

/* ------------------------------------------------------------- the setup */

typedef struct {
    const char *scene_path;
    sea_scene sc;
    char *dir; /* -o without trailing slashes */
    bool framed;
    long frame_a, frame_b;
    double rate;
    sea_exr_options exr;
    bool quiet;
    bool pov;
    long view_k; /* emission texels per facet side */
    bool explain;
    bool blender;
    bool sensor; /* --emission-space sensor: the exports project the sensor's image */
} bake_setup;

static sea_status bake_parse(const sea_cli_args *args, bake_setup *s, sea_error *err)
{
    memset(s, 0, sizeof *s);
    sea_status st;
    if ((st = sea_cli_scene_arg(args, &s->scene_path, err)) != SEA_OK)
        return st;
    const char *out = sea_cli_args_get(args, "o");
    if (out == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "missing -o DIR (the output directory)");
    size_t len = strlen(out);
    while (len > 1 && out[len - 1] == '/')
        len--;
    if (len == 0)
        return sea_fail(err, SEA_ERR_PARSE, "-o: empty directory name");
    if ((st = sea_cli_opt_exr(args, &s->exr, err)) != SEA_OK)
        return st;
    if ((st = sea_cli_opt_frames(args, &s->framed, &s->frame_a, &s->frame_b, &s->rate, err)) !=
        SEA_OK)
        return st;
    s->pov = sea_cli_given(args, "pov");
    if ((st = sea_cli_opt_integer(args, "emission-texels", 1, SEA_BAKE_VIEW_K_MAX,
                                  BAKE_VIEW_K_DEFAULT, &s->view_k, err)) != SEA_OK)
        return st;
    if (s->view_k % 2 == 0)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--emission-texels: %ld is even (allowed: odd, 1 to %d: the texels must "
                        "hold the facet centres)",
                        s->view_k, SEA_BAKE_VIEW_K_MAX);
    s->blender = sea_cli_given(args, "blender");
    const char *space = sea_cli_args_get(args, "emission-space");
    if (space != NULL && strcmp(space, "sensor") != 0 && strcmp(space, "map") != 0)
        return sea_fail(err, SEA_ERR_PARSE, "--emission-space: '%s' is not sensor or map", space);
    if (space != NULL && !s->pov && !s->blender)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--emission-space applies only with --pov or --blender (it chooses what "
                        "their sea shows)");
    s->sensor = (s->pov || s->blender) && (space == NULL || strcmp(space, "sensor") == 0);
    s->explain = sea_cli_given(args, "explain");
    s->quiet = sea_cli_given(args, "quiet");
    sea_cli_model model;
    if ((st = sea_cli_opt_model(args, &model, err)) != SEA_OK)
        return st;
    if ((st = sea_cli_load_scene(args, s->scene_path, &s->sc, err)) != SEA_OK)
        return st;
    sea_cli_apply_model(&model, &s->sc);
    if ((st = sea_cli_check_frame_times(s->sc.time, s->framed, s->frame_a, s->frame_b, s->rate,
                                        err)) != SEA_OK)
        return st;
    /* The exports' sky is one radiance (POV-Ray's background, Blender's
     * world): a sky that changes with the zenith angle, or an atmosphere
     * along the camera's rays, would show wrong there. */
    if ((s->pov || s->blender) &&
        (s->sc.sky_model != SEA_SKY_ISOTROPIC || !isnan(s->sc.air_temperature) ||
         s->sc.atmosphere_table_file[0] != '\0'))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--%s: the exported scene has an isotropic sky and no atmosphere; %s "
                        "(allowed: --pov and --blender with [sky] model = isotropic and no "
                        "[atmosphere]; the maps alone are baked with any sky)",
                        s->pov ? "pov" : "blender",
                        s->sc.sky_model != SEA_SKY_ISOTROPIC ? "this scene's [sky] model is not"
                                                             : "this scene has an [atmosphere]");
    if ((s->dir = strndup(out, len)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    return SEA_OK;
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
typedef struct {
    sea_png_tone tone[BAKE_N_GROUPS];
    char range[BAKE_N_GROUPS][64], text[BAKE_N_GROUPS][160];
} bake_previews;

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
    }
    return 0.0;
}

/* "<group>_<level>[_<frame>]<ext>", malloc'ed. */
static char *map_name(const char *group, int level, bool framed, long frame, const char *ext)
{
    char buf[128];
    if (framed)
        snprintf(buf, sizeof buf, "%s_%d_%0*ld%s", group, level, SEA_CLI_FRAME_DIGITS, frame, ext);
    else
        snprintf(buf, sizeof buf, "%s_%d%s", group, level, ext);
    return strdup(buf);
}

static const char *radiance_unit(const sea_scene *sc)
{
    return sc->wavelength > 0.0 ? "W m^-2 sr^-1 um^-1" : "W m^-2 sr^-1";
}

static const char *quantity_unit(const sea_scene *sc, bake_quantity k)
{
    if (k == Q_RADIANCE)
        return radiance_unit(sc);
    if (k == Q_EMISSION)
        return sc->wavelength > 0.0 ? "W m^-2 sr^-1 um^-1 x emission_scale"
                                    : "W m^-2 sr^-1 x emission_scale";
    return BAKE_Q[k].unit;
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

/* The files of group g of level lv at one frame into tmp, from its channel
 * data (data[c], c < the group's channels; a repeated quantity reads the
 * channel before): the EXR map when exr, the PNG preview when png. */
static sea_status write_group(const bake_setup *s, const char *tmp, const sea_clip_level *lv,
                              size_t view_k, size_t g, long frame, double t, double scale,
                              float *const data[GROUP_CH_MAX], const bake_previews *pv, bool exr,
                              bool png, sea_error *err)
{
    char level_s[16], frame_s[32], time_s[32], facet_s[32], scale_s[32];
    snprintf(level_s, sizeof level_s, "%d", lv->level);
    snprintf(frame_s, sizeof frame_s, "%ld", frame);
    snprintf(time_s, sizeof time_s, "%.17g", t);
    snprintf(facet_s, sizeof facet_s, "%.17g", lv->facet);
    snprintf(scale_s, sizeof scale_s, "%.17g", scale);
    /* the emission map has K x K texels per facet */
    const size_t vk = BAKE_GROUPS[g].q[0] == Q_EMISSION ? view_k : 1;
    const size_t width = vk * lv->nx, height = vk * lv->ny;
    char channels[256] = "";
    size_t used = 0;
    sea_exr_channel ch[GROUP_CH_MAX];
    for (size_t c = 0; c < BAKE_GROUPS[g].n; c++) {
        const bake_quantity k = BAKE_GROUPS[g].q[c];
        ch[c].name = channel_name(g, c);
        ch[c].data = data[c];
        int w = snprintf(channels + used, sizeof channels - used, "%s%s=%s", c ? "," : "",
                         channel_name(g, c), BAKE_Q[k].name);
        if (w > 0 && (size_t)w < sizeof channels - used)
            used += (size_t)w;
    }
    const sea_exr_attr attrs[] = {{"seabake:quantity", BAKE_GROUPS[g].name},
                                  {"seabake:channels", channels},
                                  {"seabake:level", level_s},
                                  {"seabake:facet_m", facet_s},
                                  {"seabake:time_s", time_s},
                                  {"seabake:frame", frame_s},
                                  {"seabake:emission_scale", scale_s}};
    const size_t n_attrs = strcmp(BAKE_GROUPS[g].name, "emission") == 0 ? 7 : 6;
    char *exr_name = map_name(BAKE_GROUPS[g].name, lv->level, s->framed, frame, ".exr");
    char *png_name = map_name(BAKE_GROUPS[g].name, lv->level, s->framed, frame, ".png");
    char *exr_path = exr_name ? sea_cli_path_join(tmp, exr_name) : NULL;
    char *png_path = png_name ? sea_cli_path_join(tmp, png_name) : NULL;
    sea_status st = SEA_OK;
    if (exr_path == NULL || png_path == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    } else {
        if (exr)
            st = sea_exr_write(exr_path, (int)width, (int)height, ch, BAKE_GROUPS[g].n, attrs,
                               n_attrs, &s->exr, err);
        if (st == SEA_OK && png)
            st = write_preview(png_path, g, width, height, ch, pv, err);
    }
    free(exr_name);
    free(png_name);
    free(exr_path);
    free(png_path);
    return st;
}

/* The manifest entry of a level at one frame: its files' names. */
static sea_status files_json(const bake_setup *s, int level, long frame, cJSON *files,
                             sea_error *err)
{
    for (size_t g = 0; g < BAKE_N_GROUPS; g++) {
        char *exr_name = map_name(BAKE_GROUPS[g].name, level, s->framed, frame, ".exr");
        char *png_name = map_name(BAKE_GROUPS[g].name, level, s->framed, frame, ".png");
        cJSON *f = exr_name && png_name ? cJSON_AddObjectToObject(files, BAKE_GROUPS[g].name)
                                        : NULL;
        const bool ok = f != NULL && cJSON_AddStringToObject(f, "exr", exr_name) &&
                        cJSON_AddStringToObject(f, "png", png_name);
        free(exr_name);
        free(png_name);
        if (!ok)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    }
    return SEA_OK;
}

/* ------------------------------------------------------------- manifest */

/* Radiance of the sky in the maps' units (per um for one wavelength,
 * in-band for a band), as sea_render_frame computes it. */
static double sky_radiance(const sea_render *r)
{
    const sea_scene *sc = sea_render_scene(r);
    const double *wl, *wt;
    const size_t n = sea_render_samples(r, &wl, &wt);
    double L = 0.0;
    for (size_t i = 0; i < n; i++)
        L += wt[i] * (sc->sky_radiance >= 0.0 ? sc->sky_radiance
                                              : sea_planck_radiance(wl[i], sc->sky_temperature));
    return sc->wavelength > 0.0 ? 1e-6 * L : L;
}

static cJSON *number_or_null(double v)
{
    return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

static cJSON *vec(const double *v, size_t n)
{
    return cJSON_CreateDoubleArray(v, (int)n);
}

static double deg(double rad)
{
    return rad * 180.0 / M_PI;
}

static cJSON *scene_json(const bake_setup *s)
{
    const sea_scene *sc = &s->sc;
    static const char *const tables[] = {"hale-querry", "segelstein"};
    cJSON *o = cJSON_CreateObject();
    cJSON *sea = cJSON_AddObjectToObject(o, "sea");
    cJSON_AddNumberToObject(sea, "wind_speed_m_s", sc->wind_speed);
    cJSON_AddNumberToObject(sea, "wind_direction_deg", deg(sc->wind_dir));
    cJSON_AddItemToObject(sea, "fetch_m", number_or_null(sc->fetch)); /* null: infinite */
    cJSON_AddNumberToObject(sea, "temperature_K", sc->temperature);
    cJSON_AddNumberToObject(sea, "salinity_g_kg", sc->salinity);
    cJSON_AddStringToObject(sea, "water", sc->water_file[0] ? sc->water_file
                                          : sc->water_table >= 0 && sc->water_table < 2
                                              ? tables[sc->water_table]
                                              : "?");
    cJSON_AddNumberToObject(sea, "seed", (double)sc->seed);
    cJSON_AddNumberToObject(sea, "time_s", sc->time);
    cJSON_AddNumberToObject(sea, "loop_period_s", sc->loop_period);
    cJSON *sun = cJSON_AddObjectToObject(o, "sun");
    cJSON_AddNumberToObject(sun, "zenith_deg", deg(sc->sun_zenith));
    cJSON_AddNumberToObject(sun, "azimuth_deg", deg(sc->sun_azimuth));
    cJSON_AddItemToObject(sun, "irradiance_W_m2_um",
                          sc->sun_irradiance >= 0.0 ? cJSON_CreateNumber(sc->sun_irradiance * 1e-6)
                                                    : cJSON_CreateNull());
    cJSON_AddNumberToObject(sun, "temperature_K", sc->sun_temperature);
    cJSON_AddNumberToObject(sun, "solid_angle_sr", sc->sun_solid_angle);
    cJSON_AddNumberToObject(sun, "transmittance", sc->sun_transmittance);
    /* The sky and the air that were used: an isotropic sky's radiance (null:
     * from its temperature), a clear sky's zenith emissivity, a table's
     * file; the keys of a model that was not used are left out, so that
     * no default reads as part of the scene. */
    cJSON *sky = cJSON_AddObjectToObject(o, "sky");
    cJSON_AddStringToObject(sky, "model", sc->sky_model == SEA_SKY_CLEAR   ? "clear"
                                          : sc->sky_model == SEA_SKY_TABLE ? "table"
                                                                           : "isotropic");
    if (sc->sky_model == SEA_SKY_ISOTROPIC) {
        cJSON_AddItemToObject(sky, "radiance_W_m2_sr_um",
                              sc->sky_radiance >= 0.0
                                  ? cJSON_CreateNumber(sc->sky_radiance * 1e-6)
                                  : cJSON_CreateNull());
        cJSON_AddNumberToObject(sky, "temperature_K", sc->sky_temperature);
    } else if (sc->sky_model == SEA_SKY_CLEAR) {
        cJSON_AddNumberToObject(sky, "zenith_emissivity", sc->sky_zenith_emissivity);
    } else {
        cJSON_AddStringToObject(sky, "table", sc->sky_table_file);
    }
    /* null: no [atmosphere] (the paper's vacuum) */
    if (isnan(sc->air_temperature) && sc->atmosphere_table_file[0] == '\0') {
        cJSON_AddNullToObject(o, "atmosphere");
    } else {
        cJSON *air = cJSON_AddObjectToObject(o, "atmosphere");
        cJSON_AddItemToObject(air, "air_temperature_K", number_or_null(sc->air_temperature));
        if (sc->atmosphere_table_file[0] != '\0')
            cJSON_AddStringToObject(air, "table", sc->atmosphere_table_file);
        else
            cJSON_AddNumberToObject(air, "extinction_per_km", sc->extinction * 1e3);
    }
    cJSON *sen = cJSON_AddObjectToObject(o, "sensor");
    cJSON_AddNumberToObject(sen, "x_m", sc->sensor_x);
    cJSON_AddNumberToObject(sen, "y_m", sc->sensor_y);
    cJSON_AddNumberToObject(sen, "altitude_m", sc->altitude);
    cJSON_AddNumberToObject(sen, "look_zenith_deg", deg(sc->look_zenith));
    cJSON_AddNumberToObject(sen, "look_azimuth_deg", deg(sc->look_azimuth));
    cJSON_AddNumberToObject(sen, "roll_deg", deg(sc->roll));
    cJSON_AddNumberToObject(sen, "hfov_deg", deg(sc->hfov));
    cJSON_AddNumberToObject(sen, "width", sc->width);
    cJSON_AddNumberToObject(sen, "height", sc->height);
    if (sc->wavelength > 0.0) {
        cJSON_AddNumberToObject(sen, "wavelength_um", sc->wavelength * 1e6);
        cJSON_AddNullToObject(sen, "band_um");
    } else {
        cJSON_AddNullToObject(sen, "wavelength_um");
        const double band[2] = {sc->band_min * 1e6, sc->band_max * 1e6};
        cJSON_AddItemToObject(sen, "band_um", vec(band, 2));
    }
    cJSON_AddStringToObject(sen, "response", sc->response_file);
    cJSON_AddNumberToObject(sen, "samples", sc->band_samples);
    cJSON *mod = cJSON_AddObjectToObject(o, "model");
    cJSON_AddStringToObject(mod, "method", sea_facet_method_name((sea_facet_method)sc->method));
    cJSON_AddNumberToObject(mod, "n", sc->n);
    cJSON_AddNumberToObject(mod, "finest_m", sc->finest);
    if (sc->grid == SEA_GRID_AUTO)
        cJSON_AddStringToObject(mod, "grid", "auto");
    else
        cJSON_AddNumberToObject(mod, "grid", sc->grid);
    cJSON_AddStringToObject(mod, "emissivity",
                            sea_emis_method_name((sea_emis_method)sc->emissivity_method));
    cJSON_AddStringToObject(mod, "earth", sc->earth == SEA_EARTH_FLAT ? "flat" : "spherical");
    cJSON_AddStringToObject(mod, "windows",
                            sc->windows == SEA_WINDOWS_CLIPMAP ? "clipmap" : "view");
    cJSON_AddNumberToObject(mod, "tolerance", sc->tolerance);
    if (sc->reflections == SEA_REFLECTIONS_AUTO)
        cJSON_AddStringToObject(mod, "reflections", "auto");
    else
        cJSON_AddNumberToObject(mod, "reflections", sc->reflections);
    cJSON_AddBoolToObject(mod, "reference", sc->reference != 0);
    cJSON_AddStringToObject(mod, "shadowing", sea_shadowing_name((sea_shadowing)sc->shadowing));
    cJSON_AddNumberToObject(mod, "scales", sc->scales);
    return o;
}

static cJSON *camera_json(const sea_camera *c, double hfov)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddItemToObject(o, "position_m", vec(c->pos, 3));
    cJSON_AddItemToObject(o, "forward", vec(c->fwd, 3));
    cJSON_AddItemToObject(o, "right", vec(c->right, 3));
    cJSON_AddItemToObject(o, "up", vec(c->up, 3));
    cJSON_AddNumberToObject(o, "focal_px", c->focal);
    cJSON_AddNumberToObject(o, "width", c->width);
    cJSON_AddNumberToObject(o, "height", c->height);
    cJSON_AddNumberToObject(o, "hfov_deg", deg(hfov));
    cJSON_AddStringToObject(o, "earth", c->earth == SEA_EARTH_FLAT ? "flat" : "spherical");
    cJSON_AddStringToObject(o, "frame", "world x east, y north, z up, m; image u right, v down");
    return o;
}

static cJSON *moments_json(const sea_moments *m)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "mx", m->mx);
    cJSON_AddNumberToObject(o, "my", m->my);
    cJSON_AddNumberToObject(o, "mxx", m->mxx);
    cJSON_AddNumberToObject(o, "myy", m->myy);
    cJSON_AddNumberToObject(o, "mxy", m->mxy);
    cJSON_AddNumberToObject(o, "h", m->h);
    return o;
}

static cJSON *rect_json(const sea_clip_level *lv)
{
    cJSON *o = cJSON_CreateObject();
    const double origin[2] = {(double)lv->i0 * lv->facet, (double)lv->j0 * lv->facet};
    const double extent[2] = {(double)lv->nx * lv->facet, (double)lv->ny * lv->facet};
    cJSON_AddItemToObject(o, "origin_m", vec(origin, 2));
    cJSON_AddItemToObject(o, "extent_m", vec(extent, 2));
    return o;
}

/* The levels array: geometry from the first frame's bake; HR levels get a
 * "frames" array filled by write_level. */
static cJSON *levels_json(const bake_setup *s, const sea_bake *b)
{
    cJSON *arr = cJSON_CreateArray();
    for (size_t l = 0; l < b->n_levels; l++) {
        const sea_bake_level *bl = &b->levels[l];
        const sea_clip_level *lv = &bl->level;
        cJSON *o = cJSON_CreateObject();
        cJSON_AddItemToArray(arr, o);
        cJSON_AddNumberToObject(o, "index", lv->level);
        cJSON_AddNumberToObject(o, "facet_m", lv->facet);
        cJSON_AddBoolToObject(o, "low_res", lv->low_res);
        cJSON_AddNumberToObject(o, "generated_share", lv->generated_share);
        cJSON_AddNumberToObject(o, "sub_n", lv->sub_n);
        /* the hole: the next finer high-resolution level's rectangle */
        if (l > 0 && !b->levels[l - 1].level.low_res)
            cJSON_AddItemToObject(o, "hole", rect_json(&b->levels[l - 1].level));
        else
            cJSON_AddNullToObject(o, "hole");
        if (lv->low_res) {
            cJSON_AddItemToObject(o, "moments", moments_json(&bl->lr_moments));
            cJSON *op = cJSON_AddObjectToObject(o, "optics");
            cJSON_AddNumberToObject(op, "emissivity", bl->lr_optics.emissivity);
            cJSON_AddNumberToObject(op, "reflectivity", bl->lr_optics.reflectivity);
            cJSON_AddNumberToObject(op, "radiance", bl->lr_optics.radiance);
            cJSON_AddNumberToObject(op, "temperature", bl->lr_optics.temperature);
            cJSON_AddNumberToObject(op, "obs_theta_deg", deg(bl->lr_obs.theta));
            cJSON_AddNumberToObject(op, "obs_phi_deg", deg(bl->lr_obs.phi));
            cJSON_AddNumberToObject(op, "sun_theta_deg", deg(bl->lr_sun.theta));
            cJSON_AddNumberToObject(op, "sun_phi_deg", deg(bl->lr_sun.phi));
            cJSON_AddStringToObject(op, "toward", "the image centre");
            continue;
        }
        const double origin[2] = {(double)lv->i0 * lv->facet, (double)lv->j0 * lv->facet};
        const double extent[2] = {(double)lv->nx * lv->facet, (double)lv->ny * lv->facet};
        const double texels[2] = {(double)lv->nx, (double)lv->ny};
        const double first[2] = {(double)lv->i0, (double)lv->j0};
        cJSON_AddItemToObject(o, "origin_m", vec(origin, 2));
        cJSON_AddItemToObject(o, "extent_m", vec(extent, 2));
        cJSON_AddItemToObject(o, "texels", vec(texels, 2));
        const double etex[2] = {texels[0] * (double)bl->view_k, texels[1] * (double)bl->view_k};
        cJSON_AddItemToObject(o, "emission_texels", vec(etex, 2));
        cJSON_AddItemToObject(o, "first_facet", vec(first, 2));
        cJSON *maps = cJSON_AddObjectToObject(o, "maps");
        for (size_t g = 0; g < BAKE_N_GROUPS; g++) {
            cJSON *chs = cJSON_AddArrayToObject(maps, BAKE_GROUPS[g].name);
            for (size_t c = 0; c < BAKE_GROUPS[g].n; c++) {
                const bake_quantity k = BAKE_GROUPS[g].q[c];
                cJSON *ch = cJSON_CreateObject();
                cJSON_AddStringToObject(ch, "channel", channel_name(g, c));
                cJSON_AddStringToObject(ch, "quantity", BAKE_Q[k].name);
                cJSON_AddStringToObject(ch, "unit", quantity_unit(&s->sc, k));
                cJSON_AddStringToObject(ch, "meaning", BAKE_Q[k].meaning);
                cJSON_AddItemToArray(chs, ch);
            }
        }
        cJSON_AddArrayToObject(o, "frames");
    }
    return arr;
}

/* What --blender adds: the import script and the values it needs that the
 * rest of the manifest does not give directly. */
static cJSON *blender_json(const sea_render *r, double scale)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "script", SEA_BLENDER_SCRIPT);
    cJSON_AddStringToObject(o, "command",
                            "blender -b --factory-startup --python " SEA_BLENDER_SCRIPT
                            " -- manifest.json [--frame F] [--material emission|visible] "
                            "[--save FILE.blend] [--render OUT.exr] "
                            "[--render-frames OUT_####.exr]");
    cJSON *written = cJSON_AddArrayToObject(o, "written");
    cJSON_AddItemToArray(written, cJSON_CreateString(SEA_BLENDER_SCRIPT));
    /* As the POV-Ray scene's sky: band-weighted, in the maps' units. */
    cJSON_AddNumberToObject(o, "sky_radiance", sky_radiance(r));
    cJSON_AddNumberToObject(o, "sky_emission", sky_radiance(r) * scale);
    /* The normal maps need no Blender-specific copy: (n + 1) / 2 with +x
     * east and +y north is the Normal Map node's tangent space for UVs
     * that run east and north, as the import's do. */
    cJSON_AddStringToObject(o, "normal_map", "normal");
    cJSON_AddStringToObject(o, "normal_map_encoding",
                            "tangent space of the UV map (u east, v north): colour = 0.5 + 0.5 n, "
                            "Non-Color, as Blender's Normal Map node reads it");
    return o;
}

/* The horizon mesh for the Blender import: its nodes and map. */
static cJSON *horizon_json(const sea_bake_horizon *hz, const sea_camera *cam)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "exr", HORIZON_MAP);
    cJSON_AddStringToObject(o, "grid",
                            "node (i, j) at map point nadir + arc_m[i] (cos, sin)(azimuth_deg[j]) "
                            "(spherical: azimuthal equidistant, on the sphere); map texel (j, "
                            "row n_arc - 1 - i) holds its radiance x emission_scale");
    const double nadir[2] = {hz->x0, hz->y0};
    cJSON_AddItemToObject(o, "nadir_m", vec(nadir, 2));
    cJSON_AddStringToObject(o, "earth", cam->earth == SEA_EARTH_FLAT ? "flat" : "spherical");
    cJSON_AddNumberToObject(o, "earth_radius_m", SEA_EARTH_RADIUS);
    cJSON_AddItemToObject(o, "arc_m", vec(hz->arc, hz->n_arc));
    double *deg_az = malloc(hz->n_az * sizeof *deg_az);
    if (deg_az != NULL) {
        for (size_t j = 0; j < hz->n_az; j++)
            deg_az[j] = deg(hz->az[j]);
        cJSON_AddItemToObject(o, "azimuth_deg", vec(deg_az, hz->n_az));
        free(deg_az);
    }
    cJSON_AddBoolToObject(o, "full_turn", hz->full_turn);
    cJSON_AddNumberToObject(o, "max_error", hz->max_err);
    return o;
}

/* tmp/name: a w x h grey map (channel Y) of one value per texel (row 0 at
 * the top), value(ctx, q) x scale at texel q, with the attributes
 * quantity, the scale and one more (key, value). */
static sea_status write_grey(const bake_setup *s, const char *tmp, const char *name, size_t w,
                            size_t h, double (*value)(const void *, size_t), const void *ctx,
                            double scale, const char *quantity, const char *key,
                            const char *key_value, sea_error *err)
{
    float *map = malloc(w * h * sizeof *map);
    char *path = sea_cli_path_join(tmp, name);
    sea_status st = SEA_OK;
    if (map == NULL || path == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %s", name);
    } else {
        for (size_t q = 0; q < w * h; q++)
            map[q] = (float)(value(ctx, q) * scale);
        char scale_s[32];
        snprintf(scale_s, sizeof scale_s, "%.17g", scale);
        const sea_exr_attr attrs[] = {{"seabake:quantity", quantity},
                                      {"seabake:emission_scale", scale_s},
                                      {key, key_value}};
        const sea_exr_channel ch[1] = {{"Y", map}};
        st = sea_exr_write(path, (int)w, (int)h, ch, 1, attrs, 3, &s->exr, err);
    }
    free(map);
    free(path);
    return st;
}

/* HORIZON_MAP texel q: the farthest ring on row 0 (so that the nadir is
 * the bottom row, v = 0). */
static double horizon_texel(const void *ctx, size_t q)
{
    const sea_bake_horizon *hz = ctx;
    const size_t w = hz->n_az, i = hz->n_arc - 1 - q / w;
    return hz->radiance[i * w + q % w];
}

/* HORIZON_MAP: n_az x n_arc texels, Y = radiance x scale. */
static sea_status write_horizon(const bake_setup *s, const sea_bake_horizon *hz, const char *tmp,
                                double scale, sea_error *err)
{
    char err_s[32];
    snprintf(err_s, sizeof err_s, "%.3g", hz->max_err);
    return write_grey(s, tmp, HORIZON_MAP, hz->n_az, hz->n_arc, horizon_texel, hz, scale,
                     "horizon", "seabake:max_error", err_s, err);
}

static double image_texel(const void *ctx, size_t q)
{
    return ((const sea_image *)ctx)->radiance[q];
}

/* The sensor's image of frame f (--emission-space sensor): Y = the
 * radiance seabake render gives each pixel x scale, row 0 at the top, and
 * its entry in the manifest's "sensor" object. */
static sea_status write_sensor(const bake_setup *s, const sea_image *img, long f, double t,
                               const char *tmp, double scale, cJSON *manifest, sea_error *err)
{
    char name[64], time_s[32];
    if (s->framed)
        snprintf(name, sizeof name, "%s%0*ld.exr", SENSOR_PREFIX, SEA_CLI_FRAME_DIGITS, f);
    else
        snprintf(name, sizeof name, "sensor.exr");
    snprintf(time_s, sizeof time_s, "%.17g", t);
    const sea_status st = write_grey(s, tmp, name, (size_t)img->width, (size_t)img->height,
                                    image_texel, img, scale, "sensor", "seabake:time_s", time_s,
                                    err);
    if (st == SEA_OK) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "frame", (double)f);
        cJSON_AddNumberToObject(e, "time_s", t);
        cJSON_AddStringToObject(e, "exr", name);
        cJSON_AddItemToArray(cJSON_GetObjectItem(cJSON_GetObjectItem(manifest, "sensor"), "frames"),
                             e);
    }
    return st;
}

/* The waves' surface of a level for the exports (--emission-space
 * sensor): the surface seabake render marches (sea_heightfield_at of the
 * level's facet moments, Hermite patches through the facet centres),
 * sampled S = height_samples(level) times per facet side from the
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

static int height_samples(const sea_clip_level *lv)
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
    const size_t S = (size_t)height_samples(lv), nx = lv->nx, ny = lv->ny, W = S * nx + 1,
                 H = S * ny + 1;
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

/* The heights of level bl at frame f (level_heights): for --pov a 16-bit
 * grey PNG from *lo (black) to *hi (white), set here,
 * height_<l>[_FFFF].png, for --blender an EXR of the displacement in
 * metres (R = G = 0, B the height), height_<l>[_FFFF].exr. */
static sea_status write_heights(const bake_setup *s, const sea_camera *cam,
                                const sea_bake_level *bl, long f, const char *tmp, double *lo,
                                double *hi, sea_error *err)
{
    float *z = NULL;
    size_t W = 0, H = 0;
    sea_status st = level_heights(cam, bl, &z, &W, &H, lo, hi, err);
    if (st != SEA_OK)
        return st;
    const int level = bl->level.level;
    char *png = map_name("height", level, s->framed, f, ".png");
    char *exr = map_name("height", level, s->framed, f, ".exr");
    char *path = NULL;
    if (png == NULL || exr == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    if (st == SEA_OK && s->pov) {
        if ((path = sea_cli_path_join(tmp, png)) == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        else
            st = sea_png_write_gray(path, (int)W, (int)H, z, *lo, *hi, 16, err);
        free(path);
    }
    if (st == SEA_OK && s->blender) {
        /* a displacement vector (0, 0, height), as Blender's Displace
         * modifier reads RGB */
        float *zero = calloc(W * H, sizeof *zero);
        const sea_exr_attr attrs[] = {{"seabake:quantity", "height"}};
        const sea_exr_channel ch[3] = {{"R", zero}, {"G", zero}, {"B", z}};
        if ((path = sea_cli_path_join(tmp, exr)) == NULL || zero == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        else
            st = sea_exr_write(path, (int)W, (int)H, ch, 3, attrs, 1, &s->exr, err);
        free(path);
        free(zero);
    }
    free(png);
    free(exr);
    free(z);
    return st;
}

/* The "height" object of level lv's entry for frame f (write_heights). */
static sea_status height_json(const bake_setup *s, const sea_clip_level *lv, long f, double lo,
                              double hi, cJSON *entry, sea_error *err)
{
    const int S = height_samples(lv);
    char *png = map_name("height", lv->level, s->framed, f, ".png");
    char *exr = map_name("height", lv->level, s->framed, f, ".exr");
    cJSON *o = png != NULL && exr != NULL ? cJSON_AddObjectToObject(entry, "height") : NULL;
    const bool ok =
        o != NULL && cJSON_AddNumberToObject(o, "samples_per_facet", S) &&
        cJSON_AddNumberToObject(o, "width", (double)(S * (int)lv->nx + 1)) &&
        cJSON_AddNumberToObject(o, "height", (double)(S * (int)lv->ny + 1)) &&
        cJSON_AddNumberToObject(o, "min_m", lo) && cJSON_AddNumberToObject(o, "max_m", hi) &&
        (!s->pov || cJSON_AddStringToObject(o, "png", png)) &&
        (!s->blender || cJSON_AddStringToObject(o, "exr", exr));
    free(png);
    free(exr);
    return ok ? SEA_OK : sea_fail(err, SEA_ERR_NOMEM, "out of memory");
}

static cJSON *manifest_json(const bake_setup *s, const sea_render *r, const sea_bake *b,
                            const sea_bake_horizon *hz, double scale)
{
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "format", "seabake-bake");
    cJSON_AddNumberToObject(m, "version", BAKE_MANIFEST_VERSION);
    cJSON_AddStringToObject(m, "generator", PACKAGE_STRING);
    cJSON_AddStringToObject(m, "scene_file", s->scene_path);
    cJSON_AddItemToObject(m, "scene", scene_json(s));
    cJSON_AddItemToObject(m, "camera", camera_json(sea_render_camera(r), s->sc.hfov));
    cJSON_AddNumberToObject(m, "seed", (double)s->sc.seed);
    cJSON_AddNumberToObject(m, "time_s", s->sc.time);
    cJSON_AddBoolToObject(m, "framed", s->framed);
    cJSON_AddNumberToObject(m, "frame_rate_hz", s->rate);
    cJSON_AddArrayToObject(m, "frames");
    cJSON_AddStringToObject(m, "pixel_type", s->exr.pixel == SEA_EXR_HALF ? "half" : "float");
    cJSON_AddStringToObject(m, "compression",
                            s->exr.compression == SEA_EXR_NONE  ? "none"
                            : s->exr.compression == SEA_EXR_PIZ ? "piz"
                                                                : "zip");
    cJSON_AddStringToObject(m, "rows", "row 0 = north edge (largest y); texel (i, row) = facet "
                                       "(i0 + i, j0 + ny - 1 - row)");
    cJSON_AddNumberToObject(m, "emission_scale", scale);
    cJSON *u = cJSON_AddObjectToObject(m, "units");
    for (size_t k = 0; k < sizeof BAKE_Q / sizeof BAKE_Q[0]; k++)
        cJSON_AddStringToObject(u, BAKE_Q[k].name, quantity_unit(&s->sc, (bake_quantity)k));
    cJSON_AddStringToObject(m, "roughness_convention",
                            "GGX in Blender's Principled BSDF: alpha = sqrt(C_xx + C_yy) "
                            "(Beckmann-equivalent width), roughness = sqrt(alpha); anisotropy = "
                            "(l1 - l2) / (l1 + l2); rotation = major-axis angle from east / 2 pi");
    cJSON_AddItemToObject(m, "levels", levels_json(s, b));
    if (hz != NULL)
        cJSON_AddItemToObject(m, "horizon", horizon_json(hz, sea_render_camera(r)));
    if (s->sensor) {
        /* the sensor's image, projected by the exports where it sees */
        cJSON *o = cJSON_AddObjectToObject(m, "sensor");
        cJSON_AddStringToObject(o, "quantity", "radiance x emission_scale of each pixel, as "
                                               "seabake render gives it; row 0 at the top");
        cJSON_AddNumberToObject(o, "width", sea_render_camera(r)->width);
        cJSON_AddNumberToObject(o, "height", sea_render_camera(r)->height);
        cJSON_AddArrayToObject(o, "frames");
    }
    if (s->blender)
        cJSON_AddItemToObject(m, "blender", blender_json(r, scale));
    return m;
}

/* Writes text to tmp/name (a plain write: the directory as a whole is
 * what appears atomically). */
static sea_status write_text(const char *tmp, const char *name, const char *text, sea_error *err)
{
    char *path = sea_cli_path_join(tmp, name);
    sea_status st = SEA_OK;
    if (text == NULL || path == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    } else {
        FILE *f = fopen(path, "w");
        if (f == NULL) {
            st = sea_fail(err, SEA_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
        } else {
            const bool ok = fputs(text, f) >= 0;
            if (fclose(f) != 0 || !ok)
                st = sea_fail(err, SEA_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
        }
    }
    free(path);
    return st;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The manifest's "files": every file in the directory, sorted, the
 * manifest itself included (the temporary directory's marker, a dot file,
 * is not part of the bake).  A later bake replaces the directory only if
 * this list names everything in it (sea_cli_out_dir_begin). */
static sea_status list_files(const char *tmp, cJSON *m, sea_error *err)
{
    DIR *d = opendir(tmp);
    if (d == NULL)
        return sea_fail(err, SEA_ERR_IO, "cannot read '%s': %s", tmp, strerror(errno));
    /* room for one more name than read: manifest.json */
    size_t n = 0, cap = 64;
    char **names = malloc(cap * sizeof *names);
    bool nomem = names == NULL;
    struct dirent *e;
    while (!nomem && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        if (n + 2 > cap) {
            char **more = realloc(names, 2 * cap * sizeof *names);
            if ((nomem = more == NULL))
                break;
            names = more;
            cap *= 2;
        }
        nomem = (names[n] = strdup(e->d_name)) == NULL;
        n += !nomem;
    }
    closedir(d);
    if (!nomem)
        nomem = (names[n] = strdup("manifest.json")) == NULL;
    n += !nomem;
    cJSON *files = NULL;
    if (!nomem) {
        qsort(names, n, sizeof *names, compare_names);
        files = cJSON_CreateStringArray((const char *const *)names, (int)n);
        nomem = files == NULL || !cJSON_AddItemToObject(m, "files", files);
    }
    for (size_t i = 0; i < n; ++i)
        free(names[i]);
    free(names);
    return nomem ? sea_fail(err, SEA_ERR_NOMEM, "out of memory") : SEA_OK;
}

static sea_status write_manifest(const char *tmp, cJSON *m, sea_error *err)
{
    sea_status st = list_files(tmp, m, err);
    if (st != SEA_OK)
        return st;
    char *text = cJSON_Print(m);
    char *line = NULL;
    if (text != NULL && (line = malloc(strlen(text) + 2)) != NULL)
        snprintf(line, strlen(text) + 2, "%s\n", text);
    st = write_text(tmp, "manifest.json", line, err);
    free(text);
    free(line);
    return st;
}

/* ------------------------------------------------------------------ run */

/* The emission scale: a power of ten putting the largest radiance top (of
 * the HR texels, their view texels and the LR constant) at or below
 * BAKE_EMISSION_TARGET. */
static double emission_scale(double top)
{
    if (!(top > 0.0) || !isfinite(top))
        return 1.0;
    return pow(10.0, floor(log10(BAKE_EMISSION_TARGET / top)));
}

/* The POV-Ray scene: one ring per level (finest first), each with its
 * emission map (with --frames, the map of POV-Ray's frame_number) and the
 * next finer level cut out; the low-resolution level as the horizon mesh
 * (HORIZON_MAP); the scene's spectral samples for Seabake_Blackbody.  With
 * the sensor's image (--emission-space sensor) the rings carry the waves:
 * each level's height samples (write_heights) over their range of each
 * frame, height_lo and height_hi (bake_writer's).  lr_radiance: the
 * low-resolution levels' radiance (index as sea_render_levels). */
static sea_status write_pov(const bake_setup *s, const sea_render *r, const double *lr_radiance,
                            const sea_bake_horizon *hz, const char *tmp, double scale,
                            const double *height_lo, const double *height_hi, sea_error *err)
{
    sea_pov_level pl[SEA_CLIP_MAX_LEVELS];
    char *names[SEA_CLIP_MAX_LEVELS] = {NULL}, *heights[SEA_CLIP_MAX_LEVELS] = {NULL};
    size_t n = 0;
    sea_status st = SEA_OK;
    const sea_camera *cam = sea_render_camera(r);
    const double far = 1000.0 * s->sc.altitude;
    const sea_clip_level *levels;
    const size_t nlev = sea_render_levels(r, &levels);
    const size_t n_frames = (size_t)(s->framed ? s->frame_b - s->frame_a + 1 : 1);
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
            p->constant = lr_radiance[l] * scale;
        } else {
            p->x0 = (double)lv->i0 * lv->facet;
            p->y0 = (double)lv->j0 * lv->facet;
            p->w = (double)lv->nx * lv->facet;
            p->h = (double)lv->ny * lv->facet;
            /* with frames, the names up to the frame number */
            names[n] = s->framed ? map_name("emission", lv->level, false, 0, "_")
                                 : map_name("emission", lv->level, false, 0, ".exr");
            if (names[n] == NULL)
                st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
            p->emission_file = names[n];
            if (s->sensor) {
                heights[n] = s->framed ? map_name("height", lv->level, false, 0, "_")
                                       : map_name("height", lv->level, false, 0, ".png");
                if (heights[n] == NULL)
                    st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
                p->height_file = heights[n];
                p->height_samples = height_samples(lv);
                p->height_lo = height_lo + l * n_frames;
                p->height_hi = height_hi + l * n_frames;
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
    sea_pov_options o = {s->framed,
                         s->frame_a,
                         s->frame_b,
                         SEA_CLI_FRAME_DIGITS,
                         s->sc.time,
                         s->rate,
                         sea_render_samples(r, &wl, &wt),
                         NULL,
                         NULL,
                         s->sc.wavelength > 0.0 ? 1e-6 : 1.0,
                         hz,
                         HORIZON_MAP,
                         NULL};
    if (s->sensor)
        o.sensor_file = s->framed ? SENSOR_PREFIX : "sensor.exr";
    o.wavelength = wl;
    o.weight = wt;
    if (st == SEA_OK)
        st = sea_pov_write(tmp, cam, pl, n, sky_radiance(r) * scale, scale, &o, err);
    for (size_t l = 0; l < SEA_CLIP_MAX_LEVELS; l++) {
        free(names[l]);
        free(heights[l]);
    }
    return st;
}

/* SIGINT, SIGTERM or SIGHUP during a bake (sea_cli_signals_catch): the
 * bake stops at the next map it would write (or within a row of the frame
 * it computes), removes its temporary directory, and then dies of the
 * signal, DIR untouched. */
static sea_status bake_interrupted(sea_error *err)
{
    return sea_fail(err, SEA_ERR_IO, "interrupted by signal %d: the output directory is left as "
                                     "it was", sea_cli_interrupted());
}

/* What a bake did: facets baked, seconds computing and writing, and the
 * parts of the computing that this process's bakes timed. */
typedef struct {
    size_t texels;
    double compute, write;
    sea_bake_times parts;
} bake_stats;

/* The progress bar of a frame: the computation is its first COMPUTE_SHARE,
 * the files the rest. */
static const double COMPUTE_SHARE = 0.9;
typedef struct {
    sea_cli_progress bar;
    bool on;
} bake_progress;

/* The library's progress callback: the bar on a terminal, and a stop as
 * soon as a signal came. */
static int bake_progress_compute(void *ctx, double fraction)
{
    bake_progress *p = ctx;
    return sea_cli_progress_if(&p->bar, p->on, COMPUTE_SHARE * fraction);
}

/* ------------------------------------------------------------ streaming
 *
 * The library hands over one level at a time (sea_bake_frame_each) and
 * frees it once written, so that only one level's maps are held.  Within a
 * level the groups' files are written in parallel, each thread with its
 * own buffers.  The first frame sets what every frame shares: the
 * emission scale (from its largest radiance) and the tone curves of the
 * grey previews (from its texels of every level, bake_previews), so its
 * emission maps and those previews wait for the whole frame: their data
 * (the emission texels' radiance as the level holds it, the previewed
 * channel of moments, moments2 and optics as the float they are written
 * as; floats all) go to a
 * spill file of the level in the temporary directory, read back and
 * removed at the end of the frame.  The files are those of holding every
 * level, byte for byte. */

/* The groups whose preview needs the first frame's tone curve. */
static bool toned_group(size_t g)
{
    const bake_quantity k = BAKE_GROUPS[g].q[BAKE_GROUPS[g].preview];
    return k != Q_NX && k != Q_ROUGHNESS;
}

/* Spill file of a level: the previewed channel of each toned group but
 * emission (n floats each, in group order), then the n K^2 view radiances
 * (floats, as the level holds them). */
enum { SPILL_CHANNELS = 3 };
static const size_t SPILL_GROUP[SPILL_CHANNELS] = {0, 1, 2};

static char *spill_path(const char *tmp, int level)
{
    char name[64];
    snprintf(name, sizeof name, ".spill_%d", level);
    return sea_cli_path_join(tmp, name);
}

static sea_status spill_io(int fd, bool out, void *data, size_t bytes, size_t offset,
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

/* What the level callback needs. */
typedef struct {
    const bake_setup *s;
    const char *tmp;
    long frame;
    double t;
    bool defer;          /* the first frame: see above */
    double scale;        /* when not deferring */
    const bake_previews *pv;
    size_t threads;      /* writers at once */
    size_t nmax;         /* texels of the largest level */
    float *pool;         /* threads x GROUP_CH_MAX x nmax */
    float *emission;     /* K^2 nmax */
    double top;          /* deferring: the largest radiance so far */
    double seconds;      /* spent writing */
    size_t texels;
    /* --emission-space sensor: each level's and frame's height range
     * (write_heights), level l's frame f at l n_frames + f - first */
    double *height_lo, *height_hi;
    long first;
    size_t n_frames;
    const sea_camera *cam;
} bake_writer;

/* The jobs of a level's files: a group's files (its index), and two that
 * are not a group: the emission group's preview alone (its map, the
 * largest file, is then the job BAKE_EMISSION alone, so that the two run
 * on different threads), and the view texels into the spill file (while
 * the groups are written). */
enum {
    BAKE_EMISSION = BAKE_N_GROUPS - 1, /* the last group of BAKE_GROUPS */
    JOB_EMISSION_PNG = BAKE_N_GROUPS,
    JOB_SPILL_VIEW,
    JOB_MAX
};

/* Whether job g is one of the emission group's: BAKE_EMISSION (its map)
 * or JOB_EMISSION_PNG (its preview). */
static bool is_emission_job(size_t g)
{
    return g == BAKE_EMISSION || g == JOB_EMISSION_PNG;
}

/* Emission job g of level lv, from w->emission (filled before the jobs). */
static sea_status emission_job(bake_writer *w, const sea_clip_level *lv, size_t view_k, size_t g,
                               sea_error *err)
{
    float *const data[GROUP_CH_MAX] = {w->emission, NULL, NULL, NULL};
    return write_group(w->s, w->tmp, lv, view_k, BAKE_EMISSION, w->frame, w->t, w->scale, data,
                       w->pv, g == BAKE_EMISSION, g == JOB_EMISSION_PNG, err);
}

/* Runs the jobs (group indices and the JOB_ ones) of a level in parallel,
 * the first failure in job order returned; job(w, ctx, g, buffers, err). */
typedef sea_status (*group_job)(bake_writer *w, const void *ctx, size_t g,
                                float *const buf[GROUP_CH_MAX], sea_error *err);

static sea_status run_jobs(bake_writer *w, const void *ctx, const size_t *jobs, size_t n,
                           group_job job, sea_error *err)
{
    sea_status st[JOB_MAX];
    sea_error e[JOB_MAX];
#ifdef _OPENMP
    /* A job's EXR file compresses its chunks on a team of its own
     * (sea_exr_write): let that team run inside this one, so that the
     * largest file (emission, K^2 texels a facet) does not compress on one
     * thread while the others, done with the small groups, wait. */
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

static sea_status level_job(bake_writer *w, const void *ctx, size_t g,
                            float *const buf[GROUP_CH_MAX], sea_error *err)
{
    const level_job_ctx *c = ctx;
    const sea_bake_level *bl = c->bl;
    const size_t n = bl->level.nx * bl->level.ny;
    if (g == JOB_SPILL_VIEW)
        return spill_io(c->spill, true, bl->view, n * bl->view_k * bl->view_k * sizeof(float),
                        SPILL_CHANNELS * n * sizeof(float), err);
    if (is_emission_job(g))
        return emission_job(w, &bl->level, bl->view_k, g, err);
    fill_group(bl, g, w->scale, buf);
    if (w->defer && toned_group(g)) {
        for (size_t k = 0; k < SPILL_CHANNELS; k++)
            if (SPILL_GROUP[k] == g)
                return spill_io(c->spill, true, buf[BAKE_GROUPS[g].preview], n * sizeof(float),
                                k * n * sizeof(float), err) == SEA_OK
                           ? write_group(w->s, w->tmp, &bl->level, bl->view_k, g, w->frame, w->t,
                                         w->scale, buf, w->pv, true, false, err)
                           : SEA_ERR_IO;
    }
    return write_group(w->s, w->tmp, &bl->level, bl->view_k, g, w->frame, w->t, w->scale, buf,
                       w->pv, true, true, err);
}

/* sea_bake_level_fn: writes level l of b (see above). */
static sea_status level_ready(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    bake_writer *w = ctx;
    if (sea_cli_interrupted() != 0)
        return bake_interrupted(err);
    const double t0 = sea_cli_seconds();
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
        char *path = spill_path(w->tmp, bl->level.level);
        if (path == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        c.spill = open(path, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
        if (c.spill < 0)
            st = sea_fail(err, SEA_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
        free(path);
        jobs[nj++] = JOB_SPILL_VIEW; /* the largest first */
    } else {
        const double scale = w->scale;
#pragma omp parallel for schedule(static)
        for (size_t q = 0; q < nv; q++)
            w->emission[q] = (float)(bl->view[q] * scale);
        jobs[nj++] = BAKE_EMISSION; /* the largest first */
        jobs[nj++] = JOB_EMISSION_PNG;
    }
    for (size_t g = 0; g < BAKE_N_GROUPS; g++)
        if (BAKE_GROUPS[g].q[0] != Q_EMISSION)
            jobs[nj++] = g;
    if (st == SEA_OK)
        st = run_jobs(w, &c, jobs, nj, level_job, err);
    const size_t h = l * w->n_frames + (size_t)(w->frame - w->first);
    if (st == SEA_OK && w->height_lo != NULL)
        st = write_heights(w->s, w->cam, bl, w->frame, w->tmp, &w->height_lo[h],
                           &w->height_hi[h], err);
    if (c.spill >= 0 && close(c.spill) != 0 && st == SEA_OK)
        st = sea_fail(err, SEA_ERR_IO, "cannot write a spill file: %s", strerror(errno));
    w->texels += n;
    w->seconds += sea_cli_seconds() - t0;
    return st;
}

/* Every group's preview mapping, from the first frame's spill files (see
 * bake_previews): at most BAKE_PREVIEW_SAMPLES texels of every
 * high-resolution level, evenly strided. */
static sea_status previews_setup(const sea_bake *b, const char *tmp, double scale,
                                 bake_previews *pv, sea_error *err)
{
    enum { CHUNK = 1 << 16 };
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
            char *path = spill_path(tmp, bl->level.level);
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
                    st = spill_io(fd, false, chunk, (c1 - c0) * sizeof(float),
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

static sea_status spill_job(bake_writer *w, const void *ctx, size_t g,
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
    return write_group(w->s, w->tmp, c->lv, c->view_k, g, w->frame, w->t, w->scale, data, w->pv,
                       false, true, err);
}

static sea_status write_spilled(bake_writer *w, const sea_bake *b, sea_error *err)
{
    sea_status st = SEA_OK;
    for (size_t l = 0; l < b->n_levels && st == SEA_OK; l++) {
        const sea_bake_level *bl = &b->levels[l];
        if (bl->level.low_res)
            continue;
        if (sea_cli_interrupted() != 0) {
            st = bake_interrupted(err);
            break;
        }
        const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
        char *path = spill_path(w->tmp, bl->level.level);
        const int fd = path ? open(path, O_RDONLY | O_CLOEXEC) : -1;
        if (fd < 0)
            st = sea_fail(err, SEA_ERR_IO, "cannot open a spill file: %s", strerror(errno));
        /* the spilled channels in the last thread's buffers */
        float *spilled[SPILL_CHANNELS];
        for (size_t k = 0; k < SPILL_CHANNELS; k++) {
            spilled[k] = w->pool + ((w->threads - 1) * GROUP_CH_MAX + k) * w->nmax;
            if (st == SEA_OK)
                st = spill_io(fd, false, spilled[k], n * sizeof(float), k * n * sizeof(float),
                              err);
        }
        /* the view radiances, then as the emission map holds them */
        if (st == SEA_OK)
            st = spill_io(fd, false, w->emission, nv * sizeof(float),
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
        for (size_t k = 0; k < SPILL_CHANNELS; k++)
            jobs[2 + k] = SPILL_GROUP[k];
        if (st == SEA_OK)
            st = run_jobs(w, &c, jobs, 2 + SPILL_CHANNELS, spill_job, err);
    }
    return st;
}

/* ------------------------------------------------------------------ MPI
 *
 * Under mpirun or srun with N > 1 ranks (mpi.c; seabake(1), PARALLEL RUNS
 * WITH MPI) the frames of --frames A:B are shared round-robin: frame f is
 * computed by rank (f - A) mod N.  Rank 0 is the one writer: it owns the
 * temporary directory and writes every file, in frame order, exactly as one
 * process does (its own frames through sea_bake_frame_each, the others'
 * levels as they arrive, through the same level_ready), so the directory
 * is that of one process byte for byte; frame A, which sets the emission
 * scale and the previews' tone curves, is always rank 0's.  Another rank
 * queues each level of its frame as it is computed (bake_msg, then a copy
 * of the level's moments, optics and view texels as bytes: the ranks run
 * the same program on the same kind of machine), so that it computes its
 * whole frame while rank 0 is on earlier ones, then sends an END message
 * with its status and the frame's headers, and waits until rank 0 has
 * taken the frame and answered: so at most one frame a rank is in flight
 * (its maps held in the queue), and a failure
 * anywhere (a rank's computation, rank 0's writing, a signal) is answered
 * with STOP to every rank still sending, whose frame in flight rank 0
 * receives and drops.  Rank 0 then removes the temporary directory, and
 * every rank leaves with rank 0's error.  One frame (no --frames) is
 * shared by texel rows instead: see bake_rows_frame. */
enum { BAKE_MSG_LEVEL, BAKE_MSG_END };
enum { BAKE_TAG_MSG = 1, BAKE_TAG_DATA, BAKE_TAG_ACK };
enum { BAKE_ACK_GO = 0, BAKE_ACK_STOP = 1 };
typedef struct {
    int kind, status;
    size_t level, bytes; /* bytes: of a rows message's data */
    sea_error err;
    sea_bake b; /* the headers; pointers not meaningful */
} bake_msg;

static int bake_owner(const bake_setup *s, long f)
{
    return (int)((f - (s->framed ? s->frame_a : 0)) % sea_cli_mpi_size());
}

/* A copy of n bytes of p, queued to rank 0. */
static sea_status queue_copy(sea_cli_mpi_queue *q, const void *p, size_t n, int tag,
                             sea_error *err)
{
    void *copy = malloc(n + 1);
    if (copy == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the maps sent to rank 0");
    memcpy(copy, p, n);
    return sea_cli_mpi_queue_send(q, copy, n, 0, tag, err);
}

/* sea_bake_level_fn of a rank other than 0: level l queued to rank 0 (a
 * copy: the library frees its maps), so that the rank computes its whole
 * frame while rank 0 is still on earlier ones. */
typedef struct {
    sea_cli_mpi_queue q;
    bool broken; /* a level queued in part (no memory for a copy) */
} bake_outbox;

static sea_status level_send(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    bake_outbox *out = ctx;
    sea_cli_mpi_queue *q = &out->q;
    if (sea_cli_interrupted() != 0)
        return bake_interrupted(err);
    bake_msg m;
    memset(&m, 0, sizeof m);
    m.kind = BAKE_MSG_LEVEL;
    m.level = l;
    m.b = *b;
    const sea_bake_level *bl = &b->levels[l];
    const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
    sea_status st = queue_copy(q, &m, sizeof m, BAKE_TAG_MSG, err);
    if (st == SEA_OK)
        st = queue_copy(q, bl->moments, n * sizeof *bl->moments, BAKE_TAG_DATA, err);
    if (st == SEA_OK)
        st = queue_copy(q, bl->optics, n * sizeof *bl->optics, BAKE_TAG_DATA, err);
    if (st == SEA_OK)
        st = queue_copy(q, bl->view, nv * sizeof *bl->view, BAKE_TAG_DATA, err);
    out->broken = st != SEA_OK;
    return st;
}

/* A rank other than 0: its frames, each level to rank 0 (see above).  A
 * level whose copy failed for memory was not queued whole: the END that
 * follows cannot be told apart, so that failure aborts the job. */
static sea_status bake_send_frames(const bake_setup *s, const sea_render *r, sea_error *err)
{
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    const long first = s->framed ? s->frame_a : 0, last = s->framed ? s->frame_b : 0;
    sea_status st = SEA_OK;
    bake_outbox out = {{NULL, NULL, 0, 0}, false};
    sea_cli_mpi_queue *q = &out.q;
    sea_cli_mpi_queue_init(q);
    for (long f = first + rank; f <= last; f += size) {
        const double t = s->framed ? s->sc.time + (double)f / s->rate : s->sc.time;
        bake_progress prog = {{"bake", 0, 1, -1}, false};
        sea_bake b;
        st = sea_bake_frame_each(r, t, (int)s->view_k, &b, bake_progress_compute, &prog,
                                 level_send, &out, err);
        bake_msg m;
        memset(&m, 0, sizeof m);
        m.kind = BAKE_MSG_END;
        if (st == SEA_OK) {
            m.b = b;
            sea_bake_free(&b);
        }
        if (out.broken)
            sea_cli_mpi_abort(err);
        /* as bake_all: a signal's message, whatever stopped the bake */
        if (sea_cli_interrupted() != 0)
            st = bake_interrupted(err);
        m.status = (int)st;
        if (st != SEA_OK && err != NULL)
            m.err = *err;
        sea_cli_mpi_send(&m, sizeof m, 0, BAKE_TAG_MSG);
        /* rank 0 has taken the frame: then its answer */
        sea_cli_mpi_queue_wait(q);
        int ack = BAKE_ACK_STOP;
        sea_cli_mpi_recv(&ack, sizeof ack, 0, BAKE_TAG_ACK);
        if (st != SEA_OK || ack != BAKE_ACK_GO)
            break;
    }
    sea_cli_mpi_queue_free(q);
    return st;
}

/* Rank 0's buffers for the levels of the others' frames: the largest level. */
typedef struct {
    sea_facet *moments;
    sea_facet_optics *optics;
    float *view;
} bake_inbox;

/* Rank 0: frame f of rank k, each level written as it arrives (when st is
 * SEA_OK: otherwise received and dropped) until its END, whose headers go
 * to *b (no maps).  The first failure, rank 0's or rank k's, is returned. */
static sea_status bake_recv_frame(bake_writer *w, bake_inbox *in, int k, sea_status st,
                                  sea_bake *b, sea_error *err)
{
    bake_msg m;
    for (;;) {
        sea_cli_mpi_recv(&m, sizeof m, k, BAKE_TAG_MSG);
        if (m.kind == BAKE_MSG_END)
            break;
        sea_bake_level *bl = &m.b.levels[m.level];
        const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
        /* the same levels as rank 0's (one prepare): within the inbox */
        assert(n <= w->nmax && bl->view_k == (size_t)w->s->view_k);
        sea_cli_mpi_recv(in->moments, n * sizeof *in->moments, k, BAKE_TAG_DATA);
        sea_cli_mpi_recv(in->optics, n * sizeof *in->optics, k, BAKE_TAG_DATA);
        sea_cli_mpi_recv(in->view, nv * sizeof *in->view, k, BAKE_TAG_DATA);
        bl->moments = in->moments;
        bl->optics = in->optics;
        bl->view = in->view;
        if (st == SEA_OK)
            st = level_ready(w, &m.b, m.level, err);
    }
    if (st == SEA_OK && m.status != SEA_OK) {
        st = (sea_status)m.status;
        if (err != NULL)
            *err = m.err;
    }
    *b = m.b;
    for (size_t l = 0; l < SEA_CLIP_MAX_LEVELS; l++) {
        b->levels[l].moments = NULL;
        b->levels[l].optics = NULL;
        b->levels[l].view = NULL;
    }
    return st;
}

/* One frame (no --frames) under MPI: shared by texel rows.  Rank k bakes
 * texel rows k, k + N, ... of every level (sea_bake_frame_rows; every rank
 * synthesises the frame's waves itself) and, per level, sends rank 0 a
 * BAKE_MSG_LEVEL then its rows' optics and view texels, and waits for GO
 * or STOP; then an END with its status.  Rank 0 assembles each level (its
 * own rows, the others', the moments it has whole) and writes it through
 * level_ready, as one process does, then answers every rank.  A rank's
 * failure reaches rank 0 as its END; rank 0 then answers STOP, and after
 * its own bake drains every rank to its END. */
typedef struct {
    bake_writer *w;  /* rank 0 */
    bake_inbox *in;  /* rank 0: the level assembled */
    bool *open;      /* rank 0: ranks whose END has not come */
} bake_rows_ctx;

/* Bytes of one texel row of a level in a rank's message: its optics, then
 * its view_k rows of view texels. */
static size_t row_bytes(const sea_bake_level *bl)
{
    return bl->level.nx *
           (sizeof(sea_facet_optics) + bl->view_k * bl->view_k * sizeof(float));
}

/* Rank k's rows of level bl into (pack) or out of (unpack) buf. */
static void rows_pack(sea_bake_level *bl, int k, int size, unsigned char *buf, bool pack)
{
    const size_t nx = bl->level.nx, nv = bl->view_k * bl->view_k * nx;
    for (size_t row = (size_t)k; row < bl->level.ny; row += (size_t)size) {
        sea_facet_optics *o = bl->optics + row * nx;
        float *v = bl->view + row * nv;
        if (pack) {
            memcpy(buf, o, nx * sizeof *o);
            memcpy(buf + nx * sizeof *o, v, nv * sizeof *v);
        } else {
            memcpy(o, buf, nx * sizeof *o);
            memcpy(v, buf + nx * sizeof *o, nv * sizeof *v);
        }
        buf += row_bytes(bl);
    }
}

/* sea_bake_level_fn of a rank other than 0 (rows). */
static sea_status rows_send(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    (void)ctx;
    if (sea_cli_interrupted() != 0)
        return bake_interrupted(err);
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    sea_bake_level bl = b->levels[l];
    const size_t bytes = sea_cli_mpi_share(bl.level.ny, rank, size) * row_bytes(&bl);
    unsigned char *buf = malloc(bytes + 1);
    if (buf == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the rows sent to rank 0");
    rows_pack(&bl, rank, size, buf, true);
    bake_msg m;
    memset(&m, 0, sizeof m);
    m.kind = BAKE_MSG_LEVEL;
    m.level = l;
    m.bytes = bytes;
    sea_cli_mpi_send(&m, sizeof m, 0, BAKE_TAG_MSG);
    sea_cli_mpi_send(buf, bytes, 0, BAKE_TAG_DATA);
    free(buf);
    int ack = BAKE_ACK_STOP;
    sea_cli_mpi_recv(&ack, sizeof ack, 0, BAKE_TAG_ACK);
    /* stopped: rank 0 holds the failure that it will report */
    return ack == BAKE_ACK_GO ? SEA_OK : sea_fail(err, SEA_ERR_CANCELLED, "stopped by rank 0");
}

/* A rank other than 0: its rows of the one frame (see above). */
static sea_status bake_send_rows(const bake_setup *s, const sea_render *r, sea_error *err)
{
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    bake_progress prog = {{"bake", 0, 1, -1}, false};
    sea_bake b;
    sea_status st = sea_bake_frame_rows(r, s->sc.time, (int)s->view_k, rank, size, &b,
                                        bake_progress_compute, &prog, rows_send, NULL, err);
    if (st == SEA_OK)
        sea_bake_free(&b);
    if (sea_cli_interrupted() != 0)
        st = bake_interrupted(err);
    bake_msg m;
    memset(&m, 0, sizeof m);
    m.kind = BAKE_MSG_END;
    m.status = (int)st;
    if (st != SEA_OK && err != NULL)
        m.err = *err;
    sea_cli_mpi_send(&m, sizeof m, 0, BAKE_TAG_MSG);
    return st;
}

/* Rank 0: the next message of rank k; a level's rows into bl (or dropped
 * when bl is NULL).  Returns its kind; an END's failure into *st, *err
 * unless *st already failed. */
static int rows_recv(int k, sea_bake_level *bl, sea_status *st, sea_error *err)
{
    bake_msg m;
    sea_cli_mpi_recv(&m, sizeof m, k, BAKE_TAG_MSG);
    if (m.kind == BAKE_MSG_END) {
        if (*st == SEA_OK && m.status != SEA_OK) {
            *st = (sea_status)m.status;
            if (err != NULL)
                *err = m.err;
        }
        return BAKE_MSG_END;
    }
    /* the level of rank 0's own bake: the same headers (one prepare) */
    unsigned char *buf = NULL;
    if (bl != NULL) {
        assert(m.bytes == sea_cli_mpi_share(bl->level.ny, k, sea_cli_mpi_size()) * row_bytes(bl));
        if ((buf = malloc(m.bytes + 1)) == NULL && *st == SEA_OK)
            *st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the rows of rank %d", k);
    }
    if (buf != NULL) {
        sea_cli_mpi_recv(buf, m.bytes, k, BAKE_TAG_DATA);
        rows_pack(bl, k, sea_cli_mpi_size(), buf, false);
        free(buf);
    } else {
        sea_cli_mpi_drop(m.bytes, k, BAKE_TAG_DATA);
    }
    return BAKE_MSG_LEVEL;
}

/* sea_bake_level_fn of rank 0 (rows): the level assembled and written. */
static sea_status rows_gather(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    bake_rows_ctx *c = ctx;
    const int size = sea_cli_mpi_size();
    sea_bake whole = *b;
    sea_bake_level *bl = &whole.levels[l];
    const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
    memcpy(c->in->moments, bl->moments, n * sizeof *bl->moments);
    memcpy(c->in->optics, bl->optics, n * sizeof *bl->optics);
    memcpy(c->in->view, bl->view, nv * sizeof *bl->view);
    bl->moments = c->in->moments;
    bl->optics = c->in->optics;
    bl->view = c->in->view;
    sea_status st = sea_cli_interrupted() != 0 ? bake_interrupted(err) : SEA_OK;
    for (int k = 1; k < size; k++)
        if (c->open[k] && rows_recv(k, bl, &st, err) == BAKE_MSG_END)
            c->open[k] = false;
    if (st == SEA_OK)
        st = level_ready(c->w, &whole, l, err);
    const int ack = st == SEA_OK ? BAKE_ACK_GO : BAKE_ACK_STOP;
    for (int k = 1; k < size; k++)
        if (c->open[k])
            sea_cli_mpi_send(&ack, sizeof ack, k, BAKE_TAG_ACK);
    return st;
}

/* Rank 0: the one frame by rows, then every other rank to its END (a
 * level still coming is dropped and answered STOP). */
static sea_status bake_rows_frame(bake_writer *w, bake_inbox *in, bool *open, const sea_render *r,
                                  double t, bake_progress *prog, sea_bake *b, sea_error *err)
{
    const int size = sea_cli_mpi_size();
    bake_rows_ctx c = {w, in, open};
    sea_status st = sea_bake_frame_rows(r, t, (int)w->s->view_k, 0, size, b, bake_progress_compute,
                                        prog, rows_gather, &c, err);
    for (int k = 1; k < size; k++)
        while (open[k]) {
            sea_status later = st == SEA_OK ? SEA_OK : SEA_ERR_CANCELLED;
            sea_error dropped;
            if (rows_recv(k, NULL, &later, &dropped) == BAKE_MSG_END) {
                open[k] = false;
                if (st == SEA_OK && later != SEA_OK) {
                    st = later;
                    if (err != NULL)
                        *err = dropped;
                }
            } else {
                const int stop = BAKE_ACK_STOP;
                sea_cli_mpi_send(&stop, sizeof stop, k, BAKE_TAG_ACK);
            }
        }
    return st;
}

static sea_status bake_all(const bake_setup *s, const sea_render *r, const char *tmp,
                           bake_stats *stats, sea_error *err)
{
    const sea_clip_level *lv;
    const size_t nlev = sea_render_levels(r, &lv);
    size_t nmax = 1;
    for (size_t l = 0; l < nlev; l++)
        if (!lv[l].low_res && lv[l].nx * lv[l].ny > nmax)
            nmax = lv[l].nx * lv[l].ny;
    size_t threads = 1;
#ifdef _OPENMP
    threads = (size_t)omp_get_max_threads();
#endif
    if (threads > BAKE_N_GROUPS - 1)
        threads = BAKE_N_GROUPS - 1;
    if (threads < 1)
        threads = 1;
    const size_t k2 = (size_t)(s->view_k * s->view_k);
    bake_writer w = {s,    tmp, 0,   0.0, true, 1.0,  NULL, threads, nmax, NULL,
                     NULL, 0.0, 0.0, 0,   NULL, NULL, 0,    0,       NULL};
    /* each writer's GROUP_CH_MAX channels, and the emission map's K x K
     * texels per facet */
    sea_status st = sea_check_size(nmax, (threads * GROUP_CH_MAX + k2) * sizeof(float),
                                   "map buffers", err);
    if (st != SEA_OK)
        return st;
    w.pool = malloc(threads * GROUP_CH_MAX * nmax * sizeof(float));
    w.emission = malloc(k2 * nmax * sizeof(float));
    if (w.pool == NULL || w.emission == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the map buffers");
    cJSON *manifest = NULL;
    bake_previews pv;
    w.pv = &pv;
    const long first = s->framed ? s->frame_a : 0, last = s->framed ? s->frame_b : 0;
    memset(stats, 0, sizeof *stats);
    bake_progress prog = {{"bake", 0, (size_t)(last - first + 1), -1},
                          !s->quiet && isatty(STDERR_FILENO)};
    /* The exports' low-resolution sea, to the horizon: one for all frames
     * (time does not enter), made with the first frame's files (a failure
     * then stops the bake as a frame's would, ranks included). */
    sea_bake_horizon hz_store, *hz = NULL;
    /* under MPI: the others' levels, and which ranks still send */
    const int size = sea_cli_mpi_size();
    bake_inbox in = {NULL, NULL, NULL};
    bool *sending = NULL;
    if (st == SEA_OK && size > 1) {
        in.moments = malloc(nmax * sizeof *in.moments);
        in.optics = malloc(nmax * sizeof *in.optics);
        in.view = malloc(k2 * nmax * sizeof *in.view);
        sending = malloc((size_t)size * sizeof *sending);
        if (in.moments == NULL || in.optics == NULL || in.view == NULL || sending == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the levels of other ranks");
        for (int k = 0; sending != NULL && k < size; k++)
            sending[k] = true;
    }
    /* the exports' waves: each frame's height range of each level, and the
     * low-resolution levels' radiance, for the POV-Ray scene written last */
    double lr_radiance[SEA_CLIP_MAX_LEVELS] = {0};
    w.first = first;
    w.n_frames = (size_t)(last - first + 1);
    w.cam = sea_render_camera(r);
    if (st == SEA_OK && s->sensor &&
        (st = sea_check_size(w.n_frames, 2 * nlev * sizeof(double), "height ranges", err)) ==
            SEA_OK &&
        (w.height_lo = calloc(2 * nlev * w.n_frames, sizeof(double))) == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the height ranges");
    if (w.height_lo != NULL)
        w.height_hi = w.height_lo + nlev * w.n_frames;
    long f = first;
    for (; f <= last && st == SEA_OK; ++f) {
        const double t = s->framed ? s->sc.time + (double)f / s->rate : s->sc.time;
        const int owner = size > 1 ? bake_owner(s, f) : 0;
        sea_bake b;
        prog.bar.index = (size_t)(f - first);
        w.frame = f;
        w.t = t;
        w.defer = f == first;
        w.top = 0.0;
        const double written = w.seconds;
        double t0 = sea_cli_seconds();
        /* the sensor's image of this frame, as seabake render gives it:
         * made by the bake from the surfaces of its levels where this
         * process bakes the whole frame, else first, so that the render's
         * surfaces are freed before the bake's levels are made */
        sea_image view = {0};
        sea_status vst = SEA_OK; /* its failure stops the bake once the frame is in */
        sea_error verr;
        const bool whole = !(size > 1 && !s->framed) && owner == 0;
        if (s->sensor) {
            const sea_camera *cam = sea_render_camera(r);
            vst = sea_image_alloc(&view, cam->width, cam->height, &verr);
            if (vst == SEA_OK && !whole)
                vst = sea_render_frame(r, t, &view, NULL, NULL, &verr);
            const double t1 = sea_cli_seconds();
            stats->compute += t1 - t0;
            t0 = t1;
        }
        if (size > 1 && !s->framed)
            st = bake_rows_frame(&w, &in, sending, r, t, &prog, &b, err);
        else if (whole && s->sensor && vst == SEA_OK)
            st = sea_bake_frame_image(r, t, (int)s->view_k, &view, &b, bake_progress_compute,
                                      &prog, level_ready, &w, err);
        else if (owner == 0)
            st = sea_bake_frame_each(r, t, (int)s->view_k, &b, bake_progress_compute, &prog,
                                     level_ready, &w, err);
        else
            st = bake_recv_frame(&w, &in, owner, SEA_OK, &b, err);
        /* under MPI "maps" is rank 0's computing and waiting for the others */
        stats->compute += sea_cli_seconds() - t0 - (w.seconds - written);
        stats->write += w.seconds - written;
        if (st == SEA_OK && owner == 0) { /* this process's own bake */
            stats->parts.waves += b.seconds.waves;
            stats->parts.image += b.seconds.image;
            stats->parts.optics += b.seconds.optics;
            stats->parts.view += b.seconds.view;
        }
        if (st == SEA_OK && vst != SEA_OK) {
            sea_bake_free(&b);
            st = vst;
            if (err != NULL)
                *err = verr;
        }
        if (sea_cli_interrupted() != 0) {
            if (st == SEA_OK)
                sea_bake_free(&b);
            st = bake_interrupted(err);
        }
        if (st != SEA_OK) {
            sea_image_free(&view);
            if (owner != 0) {
                const int stop = BAKE_ACK_STOP;
                sea_cli_mpi_send(&stop, sizeof stop, owner, BAKE_TAG_ACK);
                sending[owner] = false;
            }
            break;
        }
        t0 = sea_cli_seconds();
        if (st == SEA_OK && manifest == NULL && (s->pov || s->blender)) {
            st = sea_bake_horizon_make(r, fmax(1e-5, s->sc.tolerance), &hz_store, err);
            if (st == SEA_OK)
                hz = &hz_store;
            const double t1 = sea_cli_seconds();
            stats->compute += t1 - t0;
            t0 = t1;
        }
        if (manifest == NULL && st == SEA_OK) {
            for (size_t l = 0; l < b.n_levels; l++)
                w.top = fmax(w.top, b.levels[l].lr_optics.radiance);
            for (size_t q = 0; hz != NULL && q < hz->n_arc * hz->n_az; q++)
                w.top = fmax(w.top, hz->radiance[q]);
            for (size_t q = 0; view.radiance != NULL &&
                               q < (size_t)view.width * (size_t)view.height; q++)
                w.top = fmax(w.top, view.radiance[q]);
            w.scale = emission_scale(w.top);
            manifest = manifest_json(s, r, &b, hz, w.scale);
            if (manifest != NULL && hz != NULL)
                st = write_horizon(s, hz, tmp, w.scale, err);
            if (manifest == NULL)
                st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
            else if (st == SEA_OK)
                st = previews_setup(&b, tmp, w.scale, &pv, err);
            if (st == SEA_OK)
                st = write_spilled(&w, &b, err);
        }
        if (st == SEA_OK && s->sensor)
            st = write_sensor(s, &view, f, t, tmp, w.scale, manifest, err);
        sea_image_free(&view);
        if (st == SEA_OK) {
            cJSON *fr = cJSON_CreateObject();
            cJSON_AddNumberToObject(fr, "frame", (double)f);
            cJSON_AddNumberToObject(fr, "time_s", t);
            cJSON_AddItemToArray(cJSON_GetObjectItem(manifest, "frames"), fr);
        }
        cJSON *levels = manifest ? cJSON_GetObjectItem(manifest, "levels") : NULL;
        for (size_t l = 0; l < b.n_levels && st == SEA_OK; l++) {
            if (b.levels[l].level.low_res)
                continue;
            cJSON *entry = cJSON_CreateObject();
            cJSON_AddNumberToObject(entry, "frame", (double)f);
            cJSON_AddNumberToObject(entry, "time_s", t);
            cJSON *files = cJSON_AddObjectToObject(entry, "files");
            cJSON_AddItemToArray(cJSON_GetObjectItem(cJSON_GetArrayItem(levels, (int)l), "frames"),
                                 entry);
            st = files_json(s, b.levels[l].level.level, f, files, err);
            if (st == SEA_OK && s->sensor)
                st = height_json(s, &b.levels[l].level, f,
                                 w.height_lo[l * w.n_frames + (size_t)(f - first)],
                                 w.height_hi[l * w.n_frames + (size_t)(f - first)], entry, err);
        }
        if (f == first)
            for (size_t l = 0; l < b.n_levels && l < SEA_CLIP_MAX_LEVELS; l++)
                lr_radiance[l] = b.levels[l].lr_optics.radiance;
        sea_bake_free(&b);
        stats->write += sea_cli_seconds() - t0;
        if (owner != 0) {
            const int ack = st == SEA_OK ? BAKE_ACK_GO : BAKE_ACK_STOP;
            sea_cli_mpi_send(&ack, sizeof ack, owner, BAKE_TAG_ACK);
            sending[owner] = st == SEA_OK;
        }
        if (prog.on && st == SEA_OK)
            sea_cli_progress_bar(&prog.bar, 1.0);
    }
    /* After a failure: the frame each rank still has in flight (the next
     * it owns), received, dropped and answered STOP. */
    for (; size > 1 && sending != NULL && f <= last; ++f) {
        const int owner = bake_owner(s, f);
        if (owner == 0 || !sending[owner])
            continue;
        sea_bake b;
        sea_error dropped;
        bake_recv_frame(&w, &in, owner, SEA_ERR_CANCELLED, &b, &dropped);
        const int stop = BAKE_ACK_STOP;
        sea_cli_mpi_send(&stop, sizeof stop, owner, BAKE_TAG_ACK);
        sending[owner] = false;
    }
    free(in.moments);
    free(in.optics);
    free(in.view);
    free(sending);
    stats->texels = w.texels;
    if (st == SEA_OK && s->pov) {
        const double t0 = sea_cli_seconds();
        st = write_pov(s, r, lr_radiance, hz, tmp, w.scale, w.height_lo, w.height_hi, err);
        stats->write += sea_cli_seconds() - t0;
    }
    free(w.height_lo);
    if (st == SEA_OK && s->blender)
        st = sea_blender_write_script(tmp, err);
    sea_cli_progress_end(&prog.bar);
    const double t0 = sea_cli_seconds();
    if (st == SEA_OK)
        st = write_manifest(tmp, manifest, err);
    stats->write += sea_cli_seconds() - t0;
    cJSON_Delete(manifest);
    sea_bake_horizon_free(hz);
    free(w.pool);
    free(w.emission);
    return st;
}

/* The bake directory's notes on standard error, "bake: TEXT" (the wait
 * for another bake's lock not with --quiet: ctx a bool, quiet). */
static void bake_note(void *ctx, sea_bake_note kind, const char *text)
{
    if (kind == SEA_BAKE_NOTE_WAITING && *(const bool *)ctx)
        return;
    fprintf(stderr, "bake: %s\n", text);
}

/* The bake directory gives up waiting for the lock once a signal came. */
static int bake_cancel(void *ctx, double fraction)
{
    (void)ctx;
    (void)fraction;
    return sea_cli_interrupted() != 0;
}

static sea_status run_bake(const sea_cli_args *args, FILE *out, sea_error *err)
{
    (void)out; /* files go to DIR, the summary to standard error */
    const double start = sea_cli_seconds();
    bake_setup s;
    sea_render *r = NULL;
    sea_bake_dir *od = NULL;
    bake_stats stats = {0};
    double prepare = 0.0;
    /* under MPI rank 0 alone owns the directory (see bake_send_frames) */
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    sea_status st = bake_parse(args, &s, err);
    if (st == SEA_OK)
        st = sea_cli_threads_start(err);
    /* Signals are caught before the temporary directory exists, so that one
     * during the preparation (seconds for a large scene) still removes it:
     * the bake then stops at its first check. */
    sea_cli_signals_catch();
    /* The temporary directory first: an unwritable or missing parent, or a
     * DIR that cannot be replaced, must not cost a whole bake. */
    if (st == SEA_OK && rank == 0) {
        const sea_bake_dir_hooks hooks = {"-o", bake_note, bake_cancel, &s.quiet};
        st = sea_bake_dir_begin(s.dir, &hooks, &od, err);
    }
    if (st == SEA_OK) {
        const double t0 = sea_cli_seconds();
        st = sea_render_prepare(&s.sc, &r, err);
        prepare = sea_cli_seconds() - t0;
        /* no sensor's image to render: the pixels' plans are not needed
         * (the maps' view texels plan theirs as they go) */
        if (st == SEA_OK && !s.sensor)
            sea_render_drop_pixels(r);
    }
    st = sea_cli_mpi_agree(st, 0, NULL, err);
    if (st == SEA_OK && s.explain && rank == 0)
        sea_cli_explain("bake", s.scene_path, r);
    if (st == SEA_OK)
        st = rank == 0   ? bake_all(&s, r, sea_bake_dir_path(od), &stats, err)
             : s.framed ? bake_send_frames(&s, r, err)
                        : bake_send_rows(&s, r, err);
    if (st == SEA_OK && sea_cli_interrupted() != 0)
        st = bake_interrupted(err);
    /* rank 0's error first: it holds the first failure of any rank */
    st = sea_cli_mpi_agree(st, rank, NULL, err);
    if (st == SEA_OK && rank == 0)
        st = sea_bake_dir_commit(od, err);
    sea_bake_dir_free(od);
    st = sea_cli_mpi_agree(st, rank, NULL, err);
    /* Under MPI the job ends together: the error is reported, not died of. */
    if (sea_cli_interrupted() != 0 && st != SEA_OK && size == 1) {
        /* the temporary directory is gone: die of the signal, as asked */
        sea_render_free(r);
        free(s.dir);
        sea_cli_die_of_signal(err->msg);
        return st;
    }
    sea_cli_signals_restore();
    if (st == SEA_OK && !s.quiet && rank == 0) {
        const double secs = sea_cli_seconds() - start;
        const sea_bake_times *p = &stats.parts;
        fprintf(stderr,
                "bake: %s: %zu texels in %.3g s (%.3g texels/s): prepare %.3g s, maps %.3g s "
                "(waves %.3g s, image %.3g s, texel optics %.3g s, view texels %.3g s), "
                "files %.3g s\n",
                s.dir, stats.texels, secs, secs > 0.0 ? (double)stats.texels / secs : 0.0,
                prepare, stats.compute, p->waves, p->image, p->optics, p->view, stats.write);
    }
    sea_render_free(r);
    free(s.dir);
    return st;
}

/* --------------------------------------------------------------- command */

static const sea_cli_option BAKE_OPTIONS[] = {
    {"scene", SEA_CLI_OPT_POSITIONAL},
    {"o", SEA_CLI_OPT_SHORT},
    {"frames", 0},
    {"frame-rate", 0},
    {"format", 0},
    {"emission-texels", 0},
    {"emission-space", 0},
    {"compression", 0},
    {"pov", SEA_CLI_OPT_FLAG},
    {"blender", SEA_CLI_OPT_FLAG},
    {"explain", SEA_CLI_OPT_FLAG},
    {"tolerance", 0},
    {"reflections", 0},
    {"reference", SEA_CLI_OPT_FLAG},
    {"shadowing", 0},
    {"scales", 0},
    {"set", SEA_CLI_OPT_ACCUMULATE},
    {"quiet", SEA_CLI_OPT_FLAG}};

const sea_cli_command sea_cli_cmd_bake = {
    "bake", "per-level EXR maps, previews and a manifest of a scene file", BAKE_HELP,
    BAKE_OPTIONS, SEA_CLI_COUNT(BAKE_OPTIONS), run_bake};
