/* povray.h - POV-Ray 3.7 scenes of a baked sea (issue 5; seabake(1), bake).
 * Installed as <seabake/povray.h>; ownership and the thread-safety words
 * follow seabake.h.  sea_bake_write (<seabake/bakedir.h>) writes these
 * files with the maps they read; a program that writes maps of its own can
 * call sea_pov_write directly.
 *
 * A scene is a directory holding scene.pov, sea.inc, scene.ini, seabake.inc (the
 * macros of exporters/povray/seabake.inc) and the level maps the caller
 * wrote there.  Rendered with `povray scene.ini` run in that directory, it
 * gives an EXR image (+FE, half floats) whose pixels are the sensor's
 * radiances times `scale`.
 *
 * Geometry.  World (x east, y north, z up) maps to POV <x, z, y>.  The
 * camera is the pinhole sensor given as explicit location, direction, right
 * and up vectors (direction = focal * fwd, right = width * right,
 * up = height * up), so a world point lands on the pixel sea_camera_project
 * gives, at any look angle and roll.  The sea is the plane z = 0 cut into
 * nested rings, one mesh2 per level; each coarser level lies 1e-3 finest
 * facets below the next finer one so that overlapping windows show the
 * finer level.  For a spherical-Earth camera the rings
 * stay flat at z = 0 in map coordinates (the azimuthal equidistant map of
 * sea_camera_pixel): the scene is then an approximation near the horizon. */
#ifndef SEABAKE_POVRAY_H
#define SEABAKE_POVRAY_H

#include <stddef.h>

#include "seabake.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One clipmap level of the exported sea. */
typedef struct {
    int level;            /* clipmap level index l */
    double facet;         /* m */
    double x0, y0, w, h;  /* the level's rectangle in metres (lower-left corner, size) */
    int has_hole;         /* 1: the next finer level's rectangle is cut out */
    double hx0, hy0, hw, hh;
    const char *emission_file; /* RGB EXR, relative to dir, or NULL for a low-resolution level */
    double constant;      /* scaled radiance of a low-resolution level (used when emission_file is NULL) */
    /* The waves (may be NULL: a flat ring): a 16-bit grey PNG of heights
     * (relative, as emission_file; with frames the name up to the frame
     * number), (S nx + 1) x (S ny + 1) samples from the rectangle's corner
     * (x0, y0) to (x0 + w, y0 + h), row 0 the north edge, black at
     * height_lo[k] and white at height_hi[k] for the k-th frame from the
     * first (one when not framed); the level's ring is then a height_field
     * clipped to the rectangle minus every finer level's. */
    const char *height_file;
    const double *height_lo, *height_hi;
    int height_samples; /* S, samples per facet side */
} sea_pov_level;

/* What an exported scene holds beyond its geometry (NULL: a still, and no
 * blackbody macro).
 *
 * Frames (framed != 0): the maps of frames first..last (0 <= first <= last
 * <= 999999), frame f at time time0 + f / rate s (rate > 0, finite); each
 * level's emission_file is then the part of the name before the frame
 * number, which follows zero-padded to frame_digits (1..9) digits, then
 * ".exr" (emission_3_ -> emission_3_0007.exr).  sea.inc picks the maps of
 * POV-Ray's frame_number (the first frame when POV-Ray runs no animation);
 * scene.ini renders every frame.
 *
 * Spectral samples (n_samples >= 1): Seabake_Blackbody(T) in sea.inc gives
 * unit * sum_i weight[i] B(wavelength[i], T) * scale, the scaled radiance of
 * a blackbody at T kelvin in the maps' units (wavelength in m, > 0; weight
 * finite, >= 0; unit > 0: 1e-6 for a single wavelength's per-um
 * radiance, 1 for a band's). */
typedef struct {
    int framed;
    long first, last;
    int frame_digits;
    double time0, rate;
    size_t n_samples;
    const double *wavelength, *weight;
    double unit;
    /* The low-resolution sea to the horizon (may be NULL): a mesh2 on the
     * grid's nodes (sea_camera_sea_point of each, so on a sphere the mesh
     * follows it), below every ring, textured with horizon_file (a relative
     * name, as emission_file), texel (j, row n_arc - 1 - i) at node (i, j). */
    const sea_bake_horizon *horizon;
    const char *horizon_file;
    /* The sensor's image (may be NULL: the maps alone): an RGB EXR of the
     * radiance seabake render gives each pixel, times the scale, row 0 at
     * the top (a relative name as emission_file; with frames the name up to
     * the frame number).  Within the camera's view every ring and the
     * horizon mesh show it projected from the camera's position (the value
     * of the pixel whose ray meets the point), elsewhere their maps. */
    const char *sensor_file;
    /* The sky toward each direction (sky_n 0: sky_scaled everywhere, a
     * background): a sky_sphere whose pigment is the function
     * s = sqrt(max(y, 0)) of the ray's direction (POV y is up: its zenith
     * cosine) through a color_map of sky_n entries (2 to 256), sky_s[i]
     * from 0 to 1, increasing, sky_value[i] >= 0 the scaled radiance there,
     * linear between them (so the horizon's below it).  sky_error: the
     * interpolation's largest relative error, as measured by the caller,
     * stated in a comment. */
    size_t sky_n;
    const double *sky_s, *sky_value;
    double sky_error;
} sea_pov_options;

/* Largest value POV-Ray can read from or write to a half-float EXR. */
#define SEA_POV_HALF_MAX 65504.0
/* Most entries of a POV-Ray color_map. */
#define SEA_POV_SKY_MAX 256

/* Writes dir/sea.inc, dir/scene.pov, dir/scene.ini and dir/seabake.inc.
 *
 * sea.inc is the sea alone, for a scene of the user's own: it includes
 * seabake.inc and declares Seabake_Radiance_Scale, Seabake_Sky_Radiance
 * (with a sky table also Seabake_Sky_Pigment, the sky_sphere's pigment),
 * Seabake_Camera (the sensor), Seabake_Sea (the rings), with frames
 * Seabake_Frame and Seabake_Time, and with spectral samples
 * Seabake_Blackbody(T).  scene.pov includes it and adds the camera, the
 * sky and the sea.
 *
 * cam: the sensor (sea_camera_init).  levels[0..n-1], n >= 1, in any
 * order (finest first reads best), facet > 0: each is a ring, its rectangle (w, h > 0,
 * finite) minus its hole when has_hole (hw, hh > 0, finite; normally the
 * next finer level's rectangle).  The hole is clipped to the rectangle: one
 * that misses it cuts nothing, one that covers it hides the level (no ring
 * is made).  A level
 * with emission_file is textured with that map, texel (0, bottom row) at
 * the rectangle's lower-left corner and the top-right texel at its
 * top-right corner, so a map of nx x ny texels over nx x ny facets puts
 * each texel on its facet; emission_file is a relative path without '"',
 * '\\' or control characters (it is not opened here).  A level without one
 * emits `constant`.  sky_scaled: the colour of rays that meet no ring
 * (with opt's sky table, the floor's under the waves; the table's
 * horizon value is the natural choice).
 * constant and sky_scaled in [0, SEA_POV_HALF_MAX]; scale > 0, finite: the
 * factor already applied to the radiances (POV value = radiance * scale),
 * written to scene.pov as Seabake_Radiance_Scale.
 *
 * scene.ini: Width, Height, Antialias=off, Output_File_Type=E,
 * Output_File_Name=scene.exr, Input_File_Name=scene.pov; with frames,
 * Initial_Frame and Final_Frame (POV-Ray then numbers the images:
 * scene0.exr ... or scene00.exr ..., as many digits as the last frame).
 *
 * The four files are written to temporary names and renamed only when all
 * are written; on failure none of them is created or changed.  Returns
 * SEA_ERR_DOMAIN for invalid arguments (naming the level), SEA_ERR_IO
 * naming the file and the system error, SEA_ERR_NOMEM.  Thread-safe:
 * reads its arguments; threads writing into one dir at once each write
 * temporaries of their own, and the last renames win. */
sea_status sea_pov_write(const char *dir, const sea_camera *cam, const sea_pov_level *levels,
                         size_t n, double sky_scaled, double scale, const sea_pov_options *opt,
                         sea_error *err);

#ifdef __cplusplus
}
#endif
#endif /* SEABAKE_POVRAY_H */
