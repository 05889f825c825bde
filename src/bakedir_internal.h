/* bakedir_internal.h - what the files of the bake directory's writer share
 * (bakedir.c: the writer, its frames and the exports; bakemaps.c: a level's
 * maps, previews and spill files, and the waves' heights; manifest.c:
 * manifest.json).  Not installed. */
#ifndef SEABAKE_BAKEDIR_INTERNAL_H
#define SEABAKE_BAKEDIR_INTERNAL_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include "bakedir.h"
#include "internal.h"
#include "preview.h"

/* ------------------------------------------------- quantities and groups */

/* The quantities a texel can carry. */
typedef enum {
    Q_MX, Q_MY, Q_MXX, Q_MYY, Q_MXY, Q_H, Q_ZERO,
    Q_EMISSIVITY, Q_REFLECTIVITY, Q_RADIANCE, Q_TEMPERATURE,
    Q_NX, Q_NY, Q_NZ, Q_ROUGHNESS, Q_ANISOTROPY, Q_ROTATION, Q_EMISSION,
    Q_COUNT
} bake_quantity;

typedef struct {
    const char *name, *unit, *meaning;
} bake_quantity_info;
SEA_INTERNAL extern const bake_quantity_info SEA_BAKE_Q[Q_COUNT];

enum { GROUP_CH_MAX = 4 };
/* One file per group (and level and frame); preview = the channel shown in
 * its PNG. */
typedef struct {
    const char *name;
    size_t n;
    bake_quantity q[GROUP_CH_MAX];
    size_t preview;
} bake_group;
enum { BAKE_N_GROUPS = 6 };
SEA_INTERNAL extern const bake_group SEA_BAKE_GROUPS[BAKE_N_GROUPS];

/* Channel c of group g: Y alone, or R, G, B, A. */
SEA_INTERNAL const char *sea_bakemaps_channel(size_t g, size_t c);
/* The unit of quantity k in sc's maps (radiance: per um or in-band). */
SEA_INTERNAL const char *sea_bakemaps_unit(const sea_scene *sc, bake_quantity k);
/* "<group>_<level>[_<frame>]<ext>", the frame number when framed, malloc'ed. */
SEA_INTERNAL char *sea_bakemaps_name(const char *group, int level, int framed, long frame,
                                     const char *ext);
/* Height samples per facet side of level lv (bakemaps.c). */
SEA_INTERNAL int sea_bakemaps_height_samples(const sea_clip_level *lv);

/* The low-resolution sea to the horizon, for the exports: its map's name. */
#define SEA_BAKE_HORIZON_MAP "horizon.exr"
/* The sensor's image: "sensor.exr", with frames "sensor_FFFF.exr". */
#define SEA_BAKE_SENSOR_PREFIX "sensor_"

/* ------------------------------------------------------- the exports' sky */

/* A directional sky ([sky] model = clear or table) for the exports, as a
 * function of s = sqrt(max(cos zenith, 0)) (the horizon's value at and
 * below it, as seabake render's sky): n nodes s[0] = 0 < ... < s[n-1] = 1
 * and the radiance x emission scale at each, linear between them (a
 * POV-Ray color_map, a Blender image).  The square root spreads the nodes
 * toward the horizon, where a clear sky of small zenith emissivity
 * changes fastest in cos zenith; the nodes are then placed where the
 * interpolation misses most (sea_bakedir_sky_table).  n = 0: an isotropic
 * sky, one radiance. */
enum { SEA_BAKE_SKY_MAX = 256 };
typedef struct {
    size_t n;
    double s[SEA_BAKE_SKY_MAX];
    double value[SEA_BAKE_SKY_MAX];
    double max_err; /* the largest relative error of the interpolation, measured */
} sea_bake_sky;
/* The table of r's sky (values in the images' units, to be scaled by the
 * caller); n = 0 for an isotropic sky. */
SEA_INTERNAL void sea_bakedir_sky_table(const sea_view *r, sea_bake_sky *out);

/* ------------------------------------------------------------ the writer */

/* The mapping of each group's preview, one for every level and frame of a
 * bake (bakemaps.c). */
typedef struct {
    sea_png_tone tone[BAKE_N_GROUPS];
    char range[BAKE_N_GROUPS][64], text[BAKE_N_GROUPS][160];
} bake_previews;

struct sea_bake_writer {
    const sea_view *r;
    const sea_scene *sc;       /* r's */
    sea_bake_options o;        /* o.scene_file is scene_file */
    char *scene_file, *dir;
    int sensor;                /* the exports project the sensor's image */
    sea_progress_fn progress;
    void *ctx;
    double reported;           /* the fraction last given to progress */
    int failed;
    /* the frames: first..last, n_frames of them; next is frame_begin's */
    long first, last, next;
    size_t n_frames;
    /* the frame being written */
    int in_frame;
    long frame;
    double t;
    int defer;                 /* the first frame (bakemaps.c, streaming) */
    double top;                /* deferring: the largest radiance so far */
    double scale;              /* the emission scale, from the first frame */
    unsigned long written;     /* bit l: level l of this frame is written */
    /* the maps' buffers: threads writers of GROUP_CH_MAX channels of the
     * largest level's nmax texels, and its K^2 nmax emission texels */
    size_t nlev, threads, nmax;
    float *pool, *emission;
    bake_previews pv;
    /* what the first frame sets for the rest and for the finish */
    cJSON *manifest;
    sea_bake_horizon hz;
    int have_hz;
    sea_bake_sky sky;          /* a directional sky's table (n = 0: isotropic) */
    double lr_radiance[SEA_CLIP_MAX_LEVELS];
    /* emission space sensor: each level's and frame's height range,
     * level l's frame f at l n_frames + f - first */
    double *height_lo, *height_hi;
    sea_bake_stats stats;
};

/* Seconds of a monotonic clock. */
SEA_INTERNAL double sea_bakedir_seconds(void);
/* Non-zero when the writer's progress function asks to stop (asked with
 * the fraction it was last given). */
SEA_INTERNAL int sea_bakedir_cancelled(sea_bake_writer *w);

/* bakemaps.c: level l of b, this frame: its maps and previews (the first
 * frame's emission maps and toned previews to its spill file), and with
 * the sensor's image its heights. */
SEA_INTERNAL sea_status sea_bakemaps_level(sea_bake_writer *w, const sea_bake *b, size_t l,
                                           sea_error *err);
/* bakemaps.c, the first frame's end: the previews' tone curves from the
 * spill files, then the deferred files from them (the spill files go). */
SEA_INTERNAL sea_status sea_bakemaps_previews_setup(sea_bake_writer *w, const sea_bake *b,
                                                    sea_error *err);
SEA_INTERNAL sea_status sea_bakemaps_spilled(sea_bake_writer *w, const sea_bake *b,
                                             sea_error *err);
/* bakemaps.c: dir/name, a w x h grey map (channel Y) of value(ctx, q) x
 * scale at texel q (row 0 the top), with the attributes quantity, the
 * scale and (key, key_value). */
SEA_INTERNAL sea_status sea_bakemaps_grey(const sea_bake_writer *w, const char *name, size_t wd,
                                          size_t ht, double (*value)(const void *, size_t),
                                          const void *ctx, const char *quantity, const char *key,
                                          const char *key_value, sea_error *err);

/* manifest.c: the manifest of the bake from the first frame's headers b
 * (NULL without memory); its entries of frame f (time t): the frame, the
 * levels' files and heights, and the sensor's image; written as
 * manifest.json with every file of the directory listed. */
SEA_INTERNAL cJSON *sea_manifest_alloc(const sea_bake_writer *w, const sea_bake *b);
SEA_INTERNAL sea_status sea_manifest_frame(sea_bake_writer *w, const sea_bake *b,
                                           const char *sensor_exr, sea_error *err);
SEA_INTERNAL sea_status sea_manifest_write(const sea_bake_writer *w, sea_error *err);
/* manifest.c: the sky's radiance in the maps' units, as sea_view_render_frame
 * computes it (the POV-Ray scene's sky and the Blender world's). */
SEA_INTERNAL double sea_manifest_sky_radiance(const sea_view *r);

#endif /* SEABAKE_BAKEDIR_INTERNAL_H */
