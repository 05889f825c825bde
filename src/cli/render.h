/* render.h - what the files of seabake render share: render.c (options,
 * help, the setup and the run) and render_frames.c (the frame loop, the
 * files of each frame, their previews, and the MPI sharing of frames and
 * rows). */
#ifndef SEABAKE_CLI_RENDER_H
#define SEABAKE_CLI_RENDER_H

#include <stdbool.h>

#include "cli.h"
#include "exr.h"
#include "preview.h"

/* Arbitrary output variables, each in its own file OUT.<name>.exr. */
typedef enum { AOV_LEVEL, AOV_EMISSIVITY, AOV_REFLECTIVITY, AOV_TEMPERATURE, AOV_COUNT } render_aov;

typedef struct {
    const char *name;
    const char *unit;
    const char *quantity;
} render_aov_info;
extern const render_aov_info RENDER_AOVS[AOV_COUNT];

/* --png-tone: the temperature previews' curve from every pixel (scene),
 * from the sea pixels alone (sea), or sea when the sky lies far from the
 * sea (auto, the default: sea_png_sky_apart), else scene. */
typedef enum { RENDER_TONE_AUTO, RENDER_TONE_SCENE, RENDER_TONE_SEA } render_tone;

/* The render's setup from its options and scene file. */
typedef struct {
    const char *scene_path;
    sea_scene sc;
    /* OUT.exr as stem + extension; the preview likewise (png false: none) */
    char *out_stem, *png_stem;
    const char *out_ext, *png_ext;
    bool png;
    int png_depth;
    bool png_range; /* --png-range given: png_lo:png_hi, K */
    int png_tone;   /* --png-tone: a render_tone */
    double png_lo, png_hi;
    bool aov[AOV_COUNT];
    bool stokes; /* --aov stokes: OUT.stokes.exr, channels I, Q, U */
    bool framed;
    long frame_a, frame_b;
    double rate;
    sea_exr_options exr;
    /* OUT.camera.exr's compression: --compression's when given, else none
     * (its noise compresses to 69 % at 0.67 s of CPU a 1920 x 1080 frame,
     * more than the camera itself costs) */
    sea_exr_compression camera_compression;
    bool quiet, explain, progress;
    /* The scene's camera (sea_imager_from_render; NULL: none), made after
     * the prepare: each frame's camera image goes to OUT.camera.exr (and
     * OUT.camera.png, OUT.counts.png).  Owned by run_render. */
    sea_imager *camera;
    /* The tolerance followed from the camera's NETD (no --tolerance, no
     * [model] tolerance): tol_netd is sea_imager_scene_tolerance's, before
     * the clamp to the scene's range. */
    bool tol_from_netd;
    double tol_netd;
} sea_cli_render;

/* The previews' mappings, fixed by the first frame (or --png-range) for
 * the whole run, so that a sequence does not flicker. */
typedef struct {
    bool ready;
    sea_png_tone tone[AOV_COUNT]; /* AOV_TEMPERATURE also the main preview */
    char text[AOV_COUNT][160];    /* the tEXt "seabake:tone" of each */
    char range[AOV_COUNT][64];    /* the tEXt "seabake:range[_K]": LO:HI */
    const sea_clip_level *levels; /* the level AOV's palette */
    size_t n_levels;
    char palette[SEA_CLIP_MAX_LEVELS * 32];
} render_previews;
/* render_previews.c.  Every mapping, from the first frame (sets
 * pv->ready); pv->levels and pv->n_levels are the caller's. */
sea_status render_previews_setup(const sea_cli_render *s, const sea_image *img,
                                render_previews *pv, sea_error *err);
/* The preview of AOV k (k < 0: the main preview) of one frame, to path. */
sea_status render_write_preview(const sea_cli_render *s, const sea_image *img, int k,
                                const render_previews *pv, const char *path, sea_error *err);

/* render_frames.c.  The directories of the outputs, checked before the
 * rendering: a typing mistake in -o must not cost a whole render. */
sea_status sea_cli_render_check_outputs(const sea_cli_render *s, sea_error *err);
/* Every frame, written as it is done, then the summary line: in one
 * process, or under MPI frames shared among the ranks (--frames) or the
 * row blocks of the one frame. */
sea_status sea_cli_render_frames(const sea_cli_render *s, const sea_view *r, double start,
                                 sea_error *err);
sea_status sea_cli_render_frames_mpi(const sea_cli_render *s, const sea_view *r, double start,
                                     sea_error *err);
/* The scene's camera keys in one line ("optics gaussian psf_sigma 1.5
 * pixels, fill_factor 1, netd 0.05 K at 300 K, ..."), "" without any. */
void sea_cli_camera_text(const sea_scene *sc, char *buf, size_t size);
sea_status sea_cli_render_rows_mpi(const sea_cli_render *s, const sea_view *r, double start,
                                   sea_error *err);

#endif /* SEABAKE_CLI_RENDER_H */
