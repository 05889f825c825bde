/* render_frames.c - the frames of seabake render (render.h): each frame's
 * files (the radiance, the AOVs, the camera's image, the previews, whose
 * tone curves the first frame or --png-range fixes), all of a frame or
 * none of it, the summary line, and under MPI the frames or the row blocks
 * of one frame shared among the ranks. */
#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "preview.h"
#include "render.h"

const render_aov_info RENDER_AOVS[AOV_COUNT] = {
    {"level", "m", "facet size of the clipmap level (0: sky)"},
    {"emissivity", "1", "effective emissivity"},
    {"reflectivity", "sr^-1", "effective reflectivity sun -> sensor"},
    {"temperature", "K", "brightness temperature"},
};

/* ------------------------------------------------------------------ files */

/* "STEM[_FFFF][MIDDLE]EXT", malloc'ed. */
static char *frame_path(const char *stem, bool framed, long frame, const char *middle,
                        const char *ext)
{
    char num[32] = "";
    if (framed)
        snprintf(num, sizeof num, "_%0*ld", SEA_CLI_FRAME_DIGITS, frame);
    const size_t len = strlen(stem) + strlen(num) + strlen(middle) + strlen(ext) + 1;
    char *p = malloc(len);
    if (p != NULL)
        snprintf(p, len, "%s%s%s%s", stem, num, middle, ext);
    return p;
}

/* ------------------------------------------------------------- reporting */

/* "1,2,512(LR) m": facet sizes of the levels prepare chose, finest first,
 * and the pixels on coarser facets than they ask, if any. */
static void levels_text(const sea_view *r, char *buf, size_t size)
{
    const sea_clip_level *lv;
    const size_t n = sea_view_levels(r, &lv);
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < n && used < size; ++i) {
        int w = snprintf(buf + used, size - used, "%s%.10g%s", i ? "," : "", lv[i].facet,
                         lv[i].low_res ? "(LR)" : "");
        if (w < 0)
            break;
        used += (size_t)w;
    }
    /* the pixels that read coarser facets than their footprint asks, for
     * want of a larger grid: said in the summary, with the grid */
    size_t grid_needed = 0;
    const size_t fb = sea_multires_fallback(sea_view_multires(r), &grid_needed);
    if (used < size)
        used += (size_t)snprintf(buf + used, size - used, " m");
    if (fb > 0 && used < size)
        snprintf(buf + used, size - used,
                 " (%zu pixel%s on coarser facets than they ask: grid = %zu would hold them)", fb,
                 fb == 1 ? "" : "s", grid_needed);
}

/* ---------------------------------------------------------------- camera */

/* The files of the camera's frame (a scene with camera keys, s->camera):
 * OUT.camera.exr, its preview OUT.camera.png (with the previews) and the
 * counts OUT.counts.png (with a gain), each with the frame suffix. */
#define CAMERA_MIDDLE ".camera"
#define COUNTS_MIDDLE ".counts"
enum { CAMERA_FILES = 3 };

void sea_cli_camera_text(const sea_scene *sc, char *buf, size_t size)
{
    sea_imager_params p;
    size_t used = 0;
    buf[0] = '\0';
    if (!sea_imager_params_from_scene(sc, &p))
        return;
#define PUT(...)                                                                                   \
    do {                                                                                           \
        if (used < size) {                                                                         \
            const int w_ = snprintf(buf + used, size - used, __VA_ARGS__);                         \
            used += w_ > 0 ? (size_t)w_ : 0;                                                       \
        }                                                                                          \
    } while (0)
    switch (p.psf) {
    case SEA_PSF_GAUSSIAN:
        PUT("optics gaussian psf_sigma %.10g pixels", p.psf_sigma);
        break;
    case SEA_PSF_DIFFRACTION:
        PUT("optics diffraction f_number %.10g, pitch %.10g um", p.f_number, p.pitch * 1e6);
        break;
    case SEA_PSF_TABLE:
        PUT("optics mtf %s", sc->mtf_file);
        break;
    default:
        PUT("optics none");
        break;
    }
    PUT(", fill_factor %.10g", p.fill_factor);
    if (p.netd > 0.0)
        PUT(", netd %.10g K at %.10g K, noise_seed %llu", p.netd, p.netd_temperature,
            (unsigned long long)p.noise_seed);
    else
        PUT(", no temporal noise");
    if (p.fpn_gain > 0.0 || p.fpn_offset > 0.0)
        PUT(", fpn_gain %.10g, fpn_offset %.10g K, fpn_seed %llu", p.fpn_gain, p.fpn_offset,
            (unsigned long long)p.fpn_seed);
    if (p.gain > 0.0)
        PUT(", counts: gain %.10g, offset %.10g, bit_depth %d", p.gain, p.offset, p.bit_depth);
#undef PUT
}

/* The camera's frame to its files (see above), each path appended to
 * written; attrs (n_attrs) are the radiance image's, the frame's too. */
static sea_status write_camera(const sea_cli_render *s, const sea_imager_image *cam, long frame,
                               const sea_exr_attr *attrs, size_t n_attrs,
                               const render_previews *pv, char **written, size_t *n_written,
                               sea_error *err)
{
    const int w = cam->width, h = cam->height;
    char text[512], saturated[96];
    sea_cli_camera_text(&s->sc, text, sizeof text);
    snprintf(saturated, sizeof saturated, "%zu high, %zu low", cam->saturated_high,
             cam->saturated_low);
    sea_exr_attr a[16];
    size_t n = 0;
    for (size_t i = 0; i < n_attrs && n < 12; i++)
        a[n++] = attrs[i];
    a[0].value = "camera: radiance (Y) and its apparent brightness temperature (T, K)";
    a[n++] = (sea_exr_attr){"seabake:unit_T", "K"};
    a[n++] = (sea_exr_attr){"seabake:camera", text};
    if (cam->counts != NULL)
        a[n++] = (sea_exr_attr){"seabake:saturated", saturated};
    /* Always FLOAT: HALF's steps are 0.25 K at 300 K, more than a NETD. */
    const sea_exr_options opt = {SEA_EXR_FLOAT, s->camera_compression};
    const sea_exr_channel ch[2] = {{"T", cam->temperature}, {"Y", cam->radiance}};
    char *path = frame_path(s->out_stem, s->framed, frame, CAMERA_MIDDLE, s->out_ext);
    if (path == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_status st = sea_exr_write(path, w, h, ch, 2, a, n, &opt, err);
    if (st != SEA_OK) {
        free(path);
        return st;
    }
    written[(*n_written)++] = path;

    if (s->png) {
        /* the main preview's tone curve: the two images compare grey for grey */
        const sea_png_text t[] = {
            {"seabake:quantity", "camera: apparent brightness temperature"},
            {"seabake:range_K", pv->range[AOV_TEMPERATURE]},
            {"seabake:tone", pv->text[AOV_TEMPERATURE]},
            {"seabake:camera", text}};
        if ((path = frame_path(s->out_stem, s->framed, frame, CAMERA_MIDDLE, ".png")) == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        st = sea_png_write_toned(path, w, h, cam->temperature, &pv->tone[AOV_TEMPERATURE],
                                 s->png_depth, t, 4, err);
        if (st != SEA_OK) {
            free(path);
            return st;
        }
        written[(*n_written)++] = path;
    }

    if (cam->counts != NULL) {
        /* The counts as they are, not scaled: 8-bit for a bit depth of 8,
         * else 16-bit (the values below 2^bit_depth). */
        const size_t npix = (size_t)w * (size_t)h;
        float *c = malloc((npix > 0 ? npix : 1) * sizeof *c);
        if (c == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        for (size_t q = 0; q < npix; q++)
            c[q] = (float)cam->counts[q];
        sea_imager_params p;
        sea_imager_params_from_scene(&s->sc, &p);
        const int bits = p.bit_depth <= 8 ? 8 : 16;
        sea_png_tone tone;
        sea_png_tone_linear(0.0, bits == 8 ? 255.0 : 65535.0, &tone, NULL);
        char depth[16];
        snprintf(depth, sizeof depth, "%d", p.bit_depth);
        const sea_png_text t[] = {{"seabake:quantity", "camera: counts, as they are (not scaled)"},
                                  {"seabake:bit_depth", depth},
                                  {"seabake:saturated", saturated},
                                  {"seabake:camera", text}};
        if ((path = frame_path(s->out_stem, s->framed, frame, COUNTS_MIDDLE, ".png")) == NULL) {
            free(c);
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        }
        st = sea_png_write_toned(path, w, h, c, &tone, bits, t, 4, err);
        free(c);
        if (st != SEA_OK) {
            free(path);
            return st;
        }
        written[(*n_written)++] = path;
    }
    return SEA_OK;
}

/* ---------------------------------------------------------------- frames */

/* Widens [*t_min, *t_max] to the frame's brightness temperatures. */
static void temperature_range(const sea_image *img, size_t npix, double *t_min, double *t_max)
{
    for (size_t q = 0; q < npix; ++q) {
        *t_min = fmin(*t_min, img->temperature[q]);
        *t_max = fmax(*t_max, img->temperature[q]);
    }
}

/* Writes every file of one frame; on a failure removes those it wrote. */
static sea_status write_frame(const sea_cli_render *s, const sea_image *img,
                              const sea_imager_image *cam, long frame, double t, const char *levels,
                              render_previews *pv, sea_error *err)
{
    const sea_scene *sc = &s->sc;
    char *written[3 + 2 * AOV_COUNT + CAMERA_FILES];
    size_t n_written = 0;
    sea_status st = s->png && !pv->ready ? render_previews_setup(s, img, pv, err) : SEA_OK;
    if (st != SEA_OK)
        return st;
    char time_s[32], seed[32], frame_s[32];
    snprintf(time_s, sizeof time_s, "%.10g", t);
    snprintf(seed, sizeof seed, "%lu", sc->seed);
    snprintf(frame_s, sizeof frame_s, "%ld", frame);
    sea_exr_attr attrs[] = {{"seabake:quantity", "radiance"},
                            {"seabake:unit", sc->wavelength > 0.0 ? "W m^-2 sr^-1 um^-1"
                                                                  : "W m^-2 sr^-1"},
                            {"seabake:scene", s->scene_path},
                            {"seabake:time_s", time_s},
                            {"seabake:seed", seed},
                            {"seabake:levels", levels},
                            {"seabake:frame", frame_s}};
    const size_t n_attrs = sizeof attrs / sizeof attrs[0] - (s->framed ? 0 : 1);
    const sea_exr_options opt = s->exr;
    const sea_exr_options opt_float = {SEA_EXR_FLOAT, s->exr.compression};

    char *path = frame_path(s->out_stem, s->framed, frame, "", s->out_ext);
    if (path == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_exr_channel ch = {"Y", img->radiance};
    st = sea_exr_write(path, img->width, img->height, &ch, 1, attrs, n_attrs, &opt, err);
    if (st == SEA_OK)
        written[n_written++] = path;
    else
        free(path);

    const float *planes[AOV_COUNT] = {img->level, img->emissivity, img->reflectivity,
                                      img->temperature};
    for (int k = 0; k < AOV_COUNT && st == SEA_OK; ++k) {
        if (!s->aov[k])
            continue;
        char middle[32];
        snprintf(middle, sizeof middle, ".%s", RENDER_AOVS[k].name);
        if ((path = frame_path(s->out_stem, s->framed, frame, middle, s->out_ext)) == NULL) {
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
            break;
        }
        attrs[0].value = RENDER_AOVS[k].name;
        attrs[1].value = RENDER_AOVS[k].unit;
        ch.data = planes[k];
        /* Level sizes reach L0 2^23 m, beyond HALF's 65504: always FLOAT. */
        st = sea_exr_write(path, img->width, img->height, &ch, 1, attrs, n_attrs,
                           k == AOV_LEVEL ? &opt_float : &opt, err);
        if (st == SEA_OK)
            written[n_written++] = path;
        else
            free(path);
        /* its preview beside it: OUT.<aov>.png */
        if (st != SEA_OK || !s->png)
            continue;
        if ((path = frame_path(s->out_stem, s->framed, frame, middle, ".png")) == NULL) {
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
            break;
        }
        st = render_write_preview(s, img, k, pv, path, err);
        if (st == SEA_OK)
            written[n_written++] = path;
        else
            free(path);
    }

    /* the Stokes parameters, with the radiance's unit */
    if (st == SEA_OK && s->stokes) {
        if ((path = frame_path(s->out_stem, s->framed, frame, ".stokes", s->out_ext)) == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        attrs[0].value = "stokes";
        attrs[1].value = sc->wavelength > 0.0 ? "W m^-2 sr^-1 um^-1" : "W m^-2 sr^-1";
        const sea_exr_channel iqu[3] = {{"I", img->stokes_i}, {"Q", img->stokes_q},
                                        {"U", img->stokes_u}};
        if (st == SEA_OK)
            st = sea_exr_write(path, img->width, img->height, iqu, 3, attrs, n_attrs, &opt, err);
        if (st == SEA_OK)
            written[n_written++] = path;
        else
            free(path);
    }

    /* the camera's image, with the radiance's attributes */
    if (st == SEA_OK && cam != NULL) {
        attrs[1].value = sc->wavelength > 0.0 ? "W m^-2 sr^-1 um^-1" : "W m^-2 sr^-1";
        st = write_camera(s, cam, frame, attrs, n_attrs, pv, written, &n_written, err);
    }

    if (st == SEA_OK && s->png) {
        if ((path = frame_path(s->png_stem, s->framed, frame, "", s->png_ext)) == NULL) {
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        } else {
            st = render_write_preview(s, img, -1, pv, path, err);
            if (st == SEA_OK)
                written[n_written++] = path;
            else
                free(path);
        }
    }

    for (size_t i = 0; i < n_written; ++i) {
        if (st != SEA_OK)
            unlink(written[i]);
        free(written[i]);
    }
    return st;
}

/* The directories of the outputs, before the rendering: a typing mistake
 * in -o must not cost a whole render. */
sea_status sea_cli_render_check_outputs(const sea_cli_render *s, sea_error *err)
{
    char *probe = frame_path(s->out_stem, s->framed, s->frame_a, "", s->out_ext);
    if (probe == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_status st = sea_cli_check_parent_writable("-o", probe, err);
    /* A scene file called x.exr would be its own default output. */
    struct stat a, b;
    if (st == SEA_OK && stat(probe, &a) == 0 && stat(s->scene_path, &b) == 0 &&
        a.st_dev == b.st_dev && a.st_ino == b.st_ino)
        st = sea_fail(err, SEA_ERR_DOMAIN, "-o: '%s' is the scene file", probe);
    free(probe);
    if (st != SEA_OK || !s->png)
        return st;
    if ((probe = frame_path(s->png_stem, false, 0, "", s->png_ext)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    st = sea_cli_check_parent_writable("--png", probe, err);
    free(probe);
    return st;
}

/* The library's progress callback: the bar on a terminal, and a stop as
 * soon as a signal came (sea_cli_signals_catch). */
typedef struct {
    sea_cli_progress bar;
    bool on;
} render_progress;

static int render_progress_fn(void *ctx, double fraction)
{
    render_progress *p = ctx;
    return sea_cli_progress_if(&p->bar, p->on, fraction);
}

/* What the camera made of the frames written: its apparent temperatures
 * and, with counts, the saturated pixels (over every frame). */
typedef struct {
    bool on, counts;
    double t_min, t_max;
    size_t high, low;
} camera_tally;

static void camera_tally_init(const sea_cli_render *s, camera_tally *ct)
{
    ct->on = s->camera != NULL;
    ct->counts = ct->on && sea_imager_counts(s->camera);
    ct->t_min = INFINITY;
    ct->t_max = -INFINITY;
    ct->high = ct->low = 0;
}

static void camera_tally_add(camera_tally *ct, const sea_imager_image *cam)
{
    const size_t npix = (size_t)cam->width * (size_t)cam->height;
    for (size_t q = 0; q < npix; ++q) {
        ct->t_min = fmin(ct->t_min, cam->temperature[q]);
        ct->t_max = fmax(ct->t_max, cam->temperature[q]);
    }
    ct->high += cam->saturated_high;
    ct->low += cam->saturated_low;
}

/* The tallies of every rank, to each (MPI, --frames). */
static void camera_tally_reduce(camera_tally *ct)
{
    if (!ct->on)
        return;
    sea_cli_mpi_minmax(&ct->t_min, &ct->t_max);
    sea_cli_mpi_sum(&ct->high);
    sea_cli_mpi_sum(&ct->low);
}

/* The closing line on standard error: files, size, levels, frames, the
 * seconds since start, the brightness temperatures of all frames; with a
 * camera its apparent temperatures and, with counts, the saturated pixels
 * of all frames. */
static sea_status render_summary(const sea_cli_render *s, const char *levels, double start,
                                 double t_min, double t_max, const camera_tally *ct,
                                 sea_error *err)
{
    const long first = s->framed ? s->frame_a : 0, last = s->framed ? s->frame_b : 0;
    char *a = frame_path(s->out_stem, s->framed, first, "", s->out_ext);
    char *b = frame_path(s->out_stem, s->framed, last, "", s->out_ext);
    char camera[256] = "";
    if (ct->on) {
        const size_t n = ct->high + ct->low;
        int w = snprintf(camera, sizeof camera, "; camera: apparent temperature %.2f to %.2f K",
                         ct->t_min, ct->t_max);
        if (ct->counts && w > 0 && (size_t)w < sizeof camera)
            snprintf(camera + w, sizeof camera - (size_t)w,
                     ", %zu saturated pixel%s (%zu high, %zu low)", n, n == 1 ? "" : "s",
                     ct->high, ct->low);
    }
    if (a != NULL && b != NULL)
        fprintf(stderr,
                "render: %s%s%s: %d x %d, levels %s, %ld frame%s, %.3g s, brightness "
                "temperature %.2f to %.2f K%s\n",
                a, last > first ? " to " : "", last > first ? b : "", s->sc.width, s->sc.height,
                levels, last - first + 1, last > first ? "s" : "", sea_cli_seconds() - start, t_min,
                t_max, camera);
    free(a);
    free(b);
    return a != NULL && b != NULL ? SEA_OK : sea_fail(err, SEA_ERR_NOMEM, "out of memory");
}

/* Every frame, written as it is done; then the summary line.  A signal
 * stops the frame being rendered within a row: its files are not written
 * (the frames before it are complete and stay). */
sea_status sea_cli_render_frames(const sea_cli_render *s, const sea_view *r, double start,
                                sea_error *err)
{
    sea_image img;
    sea_status st = sea_image_alloc(s->sc.width, s->sc.height, &img, err);
    if (st == SEA_OK && s->stokes)
        st = sea_image_alloc_stokes(&img, err);
    if (st != SEA_OK)
        return st;
    char levels[SEA_CLIP_MAX_LEVELS * 24 + 128];
    levels_text(r, levels, sizeof levels);
    const long first = s->framed ? s->frame_a : 0, last = s->framed ? s->frame_b : 0;
    render_progress prog = {{"render", 0, (size_t)(last - first + 1), -1, 0.0}, s->progress};
    const size_t npix = (size_t)s->sc.width * (size_t)s->sc.height;
    double t_min = INFINITY, t_max = -INFINITY;
    render_previews pv;
    memset(&pv, 0, sizeof pv);
    pv.n_levels = sea_view_levels(r, &pv.levels);
    camera_tally ct;
    camera_tally_init(s, &ct);
    sea_imager_image cam;
    memset(&cam, 0, sizeof cam);
    if (st == SEA_OK && ct.on)
        st = sea_imager_image_alloc(s->camera, &cam, err);
    long done = 0;
    for (long f = first; f <= last && st == SEA_OK; ++f) {
        const double t = s->framed ? s->sc.time + (double)f / s->rate : s->sc.time;
        prog.bar.index = (size_t)(f - first);
        st = sea_view_render_frame(r, t, &img, render_progress_fn, &prog, err);
        bool wrote = false;
        /* the camera's frame f: its temporal noise is drawn for f */
        if (st == SEA_OK && ct.on && sea_cli_interrupted() == 0)
            st = sea_imager_apply(s->camera, &img, (uint64_t)f, &cam, err);
        if (st == SEA_OK && sea_cli_interrupted() == 0) {
            st = write_frame(s, &img, ct.on ? &cam : NULL, f, t, levels, &pv, err);
            wrote = st == SEA_OK;
        }
        /* a frame written before the signal was seen is complete: counted */
        if (wrote)
            ++done;
        if (sea_cli_interrupted() != 0) {
            st = done == 0 ? sea_fail(err, SEA_ERR_CANCELLED,
                                      "interrupted by signal %d: no file written",
                                      sea_cli_interrupted())
                           : sea_fail(err, SEA_ERR_CANCELLED,
                                      "interrupted by signal %d: %ld frame%s written (%ld to %ld), "
                                      "the rest not",
                                      sea_cli_interrupted(), done, done > 1 ? "s" : "", first,
                                      first + done - 1);
        }
        if (st != SEA_OK)
            break;
        temperature_range(&img, npix, &t_min, &t_max);
        if (ct.on)
            camera_tally_add(&ct, &cam);
        if (prog.on)
            sea_cli_progress_bar(&prog.bar, 1.0);
    }
    /* The bar's line is ended whatever happened: an error or an interrupt
     * message starts on a line of its own. */
    sea_cli_progress_end(&prog.bar);
    sea_image_free(&img);
    sea_imager_image_free(&cam);
    if (st != SEA_OK || s->quiet)
        return st;
    return render_summary(s, levels, start, t_min, t_max, &ct, err);
}

/* ------------------------------------------------------------------ MPI
 *
 * Under mpirun or srun with N > 1 ranks (mpi.c; seabake(1), PARALLEL RUNS
 * WITH MPI) the work is shared and the files are those of one process,
 * byte for byte:
 *  - --frames A:B: in rounds of N frames, rank k renders and writes frame
 *    A + N round + k with the same atomic writes as one process (the
 *    output's directory must then be one that every rank sees).  The
 *    previews' tone curves are the first frame's: rank 0 renders frame A
 *    in round 0 and broadcasts what render_previews_setup made of it before any
 *    rank writes.  After each round the ranks agree on the first failed
 *    frame (sea_cli_mpi_agree); the frames after it that the round wrote
 *    are removed, so that what stays is what one process leaves: the
 *    frames before the failure.
 *  - one frame: rank k renders the blocks of SEA_RENDER_ROW_BLOCK rows
 *    k, k + N, ... (sea_view_render_rows, interleaved so that sky and sea rows
 *    are shared evenly) and sends them to rank 0, which writes every file.
 * Rank 0 alone shows progress and prints the summary, whose temperatures
 * are reduced over the ranks. */

/* Removes the files write_frame wrote for frame (a frame after a failed
 * one). */
static void remove_frame(const sea_cli_render *s, long frame)
{
    char *paths[3 + 2 * AOV_COUNT + CAMERA_FILES];
    size_t n = 0;
    paths[n++] = frame_path(s->out_stem, s->framed, frame, "", s->out_ext);
    if (s->camera != NULL) {
        paths[n++] = frame_path(s->out_stem, s->framed, frame, CAMERA_MIDDLE, s->out_ext);
        if (s->png)
            paths[n++] = frame_path(s->out_stem, s->framed, frame, CAMERA_MIDDLE, ".png");
        if (sea_imager_counts(s->camera))
            paths[n++] = frame_path(s->out_stem, s->framed, frame, COUNTS_MIDDLE, ".png");
    }
    for (int k = 0; k < AOV_COUNT; ++k) {
        if (!s->aov[k])
            continue;
        char middle[32];
        snprintf(middle, sizeof middle, ".%s", RENDER_AOVS[k].name);
        paths[n++] = frame_path(s->out_stem, s->framed, frame, middle, s->out_ext);
        if (s->png)
            paths[n++] = frame_path(s->out_stem, s->framed, frame, middle, ".png");
    }
    if (s->stokes)
        paths[n++] = frame_path(s->out_stem, s->framed, frame, ".stokes", s->out_ext);
    if (s->png)
        paths[n++] = frame_path(s->png_stem, s->framed, frame, "", s->png_ext);
    for (size_t i = 0; i < n; i++) {
        if (paths[i] != NULL)
            unlink(paths[i]);
        free(paths[i]);
    }
}

/* render_previews_setup's result on rank 0 to every rank. */
static void previews_bcast(render_previews *pv)
{
    sea_cli_mpi_bcast(pv->tone, sizeof pv->tone, 0);
    sea_cli_mpi_bcast(pv->text, sizeof pv->text, 0);
    sea_cli_mpi_bcast(pv->range, sizeof pv->range, 0);
    sea_cli_mpi_bcast(pv->palette, sizeof pv->palette, 0);
    pv->ready = true;
}

/* A signal under MPI, seen by the rank whose frames before `kept` are all
 * written (the agreement picks the smallest). */
static sea_status interrupted_mpi(long first, long kept, sea_error *err)
{
    const int sig = sea_cli_interrupted();
    if (kept <= first)
        return sea_fail(err, SEA_ERR_CANCELLED, "interrupted by signal %d: no file written", sig);
    return sea_fail(err, SEA_ERR_CANCELLED,
                    "interrupted by signal %d: %ld frame%s written (%ld to %ld), the rest not", sig,
                    kept - first, kept - first > 1 ? "s" : "", first, kept - 1);
}

/* --frames A:B shared among the ranks (see above). */
sea_status sea_cli_render_frames_mpi(const sea_cli_render *s, const sea_view *r, double start,
                                    sea_error *err)
{
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    sea_image img;
    sea_status st = sea_image_alloc(s->sc.width, s->sc.height, &img, err);
    if (st == SEA_OK && s->stokes)
        st = sea_image_alloc_stokes(&img, err);
    if ((st = sea_cli_mpi_agree(st, 0, NULL, err)) != SEA_OK) {
        sea_image_free(&img);
        return st;
    }
    char levels[SEA_CLIP_MAX_LEVELS * 24 + 128];
    levels_text(r, levels, sizeof levels);
    const long first = s->frame_a, last = s->frame_b;
    render_progress prog = {{"render", 0, (size_t)(last - first + 1), -1, 0.0},
                            s->progress && rank == 0};
    const size_t npix = (size_t)s->sc.width * (size_t)s->sc.height;
    double t_min = INFINITY, t_max = -INFINITY;
    render_previews pv;
    memset(&pv, 0, sizeof pv);
    pv.n_levels = sea_view_levels(r, &pv.levels);
    /* each rank's camera makes its own frames: the noise of frame f is f's */
    camera_tally ct;
    camera_tally_init(s, &ct);
    sea_imager_image cam;
    memset(&cam, 0, sizeof cam);
    if (ct.on)
        st = sea_imager_image_alloc(s->camera, &cam, err);
    if ((st = sea_cli_mpi_agree(st, 0, NULL, err)) != SEA_OK) {
        sea_image_free(&img);
        sea_imager_image_free(&cam);
        return st;
    }
    for (long base = first; base <= last; base += size) {
        /* the round's frames, one a rank (sea_cli_mpi_frame_owner) */
        const long f = base + rank;
        assert(sea_cli_mpi_frame_owner(first, f) == rank);
        const bool mine = f <= last;
        const double t = s->sc.time + (double)f / s->rate;
        long key = f, failed;
        bool wrote = false, write = mine;
        prog.bar.index = (size_t)(base - first);
        if (mine)
            st = sea_view_render_frame(r, t, &img, render_progress_fn, &prog, err);
        if (mine && st == SEA_OK && ct.on && sea_cli_interrupted() == 0)
            st = sea_imager_apply(s->camera, &img, (uint64_t)f, &cam, err);
        /* as sea_cli_render_frames: a signal's message, whatever stopped the frame */
        if (sea_cli_interrupted() != 0)
            st = interrupted_mpi(first, f, err);
        if (s->png && base == first) {
            /* Frame A is rank 0's: its tone curves to every rank before
             * anyone writes.  Without them (rank 0 failed) no rank writes,
             * and the agreement below reports rank 0's failure. */
            int ready = 0;
            if (rank == 0 && st == SEA_OK)
                ready = (st = render_previews_setup(s, &img, &pv, err)) == SEA_OK;
            sea_cli_mpi_bcast(&ready, sizeof ready, 0);
            if (ready)
                previews_bcast(&pv);
            write = write && ready;
        }
        if (write && st == SEA_OK) {
            st = write_frame(s, &img, ct.on ? &cam : NULL, f, t, levels, &pv, err);
            wrote = st == SEA_OK;
        }
        /* a frame written before the signal was seen is complete: kept */
        if (st == SEA_OK && sea_cli_interrupted() != 0) {
            key = f + 1;
            st = interrupted_mpi(first, key, err);
        }
        if ((st = sea_cli_mpi_agree(st, key, &failed, err)) != SEA_OK) {
            if (wrote && f >= failed)
                remove_frame(s, f);
            break;
        }
        if (wrote)
            temperature_range(&img, npix, &t_min, &t_max);
        if (wrote && ct.on)
            camera_tally_add(&ct, &cam);
        if (prog.on)
            sea_cli_progress_bar(&prog.bar, 1.0);
    }
    sea_cli_progress_end(&prog.bar);
    sea_image_free(&img);
    sea_imager_image_free(&cam);
    if (st != SEA_OK || s->quiet)
        return st;
    sea_cli_mpi_minmax(&t_min, &t_max);
    camera_tally_reduce(&ct);
    return rank == 0 ? render_summary(s, levels, start, t_min, t_max, &ct, err) : SEA_OK;
}

/* The five planes of img, in the order rows are packed. */
enum { RENDER_PLANES = 8 };
/* The image's planes, the Stokes planes when it has them; returns how many. */
static int image_planes(const sea_image *img, float *planes[RENDER_PLANES])
{
    planes[0] = img->radiance;
    planes[1] = img->temperature;
    planes[2] = img->level;
    planes[3] = img->emissivity;
    planes[4] = img->reflectivity;
    if (img->stokes_i == NULL)
        return 5;
    planes[5] = img->stokes_i;
    planes[6] = img->stokes_q;
    planes[7] = img->stokes_u;
    return 8;
}

/* The rows of rank k > 0 to rank 0, through pack (room for the largest
 * share of rows, of every plane) and rows (its row numbers). */
static void gather_rows(sea_image *img, float *pack, size_t *rows, int rank, int size)
{
    const size_t W = (size_t)img->width, H = (size_t)img->height;
    float *planes[RENDER_PLANES];
    const size_t np = (size_t)image_planes(img, planes);
    for (int k = 1; k < size; k++) {
        if (rank != 0 && rank != k)
            continue;
        const size_t n = sea_cli_mpi_rows(H, SEA_RENDER_ROW_BLOCK, k, size, rows);
        if (n == 0)
            continue;
        for (size_t i = 0; rank == k && i < n; i++)
            for (size_t p = 0; p < np; p++)
                memcpy(pack + (i * np + p) * W, planes[p] + rows[i] * W,
                       W * sizeof *pack);
        const size_t bytes = n * np * W * sizeof *pack;
        if (rank == k) {
            sea_cli_mpi_send(pack, bytes, 0, k);
            continue;
        }
        sea_cli_mpi_recv(pack, bytes, k, k);
        for (size_t i = 0; i < n; i++)
            for (size_t p = 0; p < np; p++)
                memcpy(planes[p] + rows[i] * W, pack + (i * np + p) * W,
                       W * sizeof *pack);
    }
}

/* One frame shared by rows among the ranks, written by rank 0 (see above). */
sea_status sea_cli_render_rows_mpi(const sea_cli_render *s, const sea_view *r, double start,
                                  sea_error *err)
{
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    const size_t W = (size_t)s->sc.width;
    sea_image img;
    sea_status st = sea_image_alloc(s->sc.width, s->sc.height, &img, err);
    if (st == SEA_OK && s->stokes)
        st = sea_image_alloc_stokes(&img, err);
    float *pack = NULL;
    size_t *rows = NULL, most = 0;
    for (int k = 1; k < size; k++) {
        const size_t n = sea_cli_mpi_rows((size_t)s->sc.height, SEA_RENDER_ROW_BLOCK, k, size, NULL);
        most = n > most ? n : most;
    }
    if (st == SEA_OK &&
        (st = sea_check_size(most * RENDER_PLANES, W * sizeof *pack, "the rows sent to rank 0",
                             err)) == SEA_OK &&
        ((pack = malloc((most * RENDER_PLANES * W + 1) * sizeof *pack)) == NULL ||
         (rows = malloc((most + 1) * sizeof *rows)) == NULL))
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the rows sent to rank 0");
    char levels[SEA_CLIP_MAX_LEVELS * 24 + 128];
    levels_text(r, levels, sizeof levels);
    render_progress prog = {{"render", 0, 1, -1, 0.0}, s->progress && rank == 0};
    const double t = s->sc.time;
    if (st == SEA_OK)
        st = sea_view_render_rows(r, t, rank, size, &img, render_progress_fn, &prog, err);
    if (st == SEA_OK && sea_cli_interrupted() != 0)
        st = sea_fail(err, SEA_ERR_CANCELLED, "interrupted by signal %d: no file written",
                      sea_cli_interrupted());
    if ((st = sea_cli_mpi_agree(st, 0, NULL, err)) == SEA_OK)
        gather_rows(&img, pack, rows, rank, size);
    double t_min = INFINITY, t_max = -INFINITY;
    camera_tally ct;
    camera_tally_init(s, &ct);
    sea_imager_image cam;
    memset(&cam, 0, sizeof cam);
    if (st == SEA_OK && rank == 0) {
        render_previews pv;
        memset(&pv, 0, sizeof pv);
        pv.n_levels = sea_view_levels(r, &pv.levels);
        /* the camera sees the gathered frame, on rank 0 */
        if (ct.on && (st = sea_imager_image_alloc(s->camera, &cam, err)) == SEA_OK)
            st = sea_imager_apply(s->camera, &img, 0, &cam, err);
        if (st == SEA_OK)
            st = write_frame(s, &img, ct.on ? &cam : NULL, 0, t, levels, &pv, err);
        if (st == SEA_OK && ct.on)
            camera_tally_add(&ct, &cam);
        for (size_t q = 0; st == SEA_OK && q < W * (size_t)s->sc.height; ++q) {
            t_min = fmin(t_min, img.temperature[q]);
            t_max = fmax(t_max, img.temperature[q]);
        }
        if (prog.on && st == SEA_OK)
            sea_cli_progress_bar(&prog.bar, 1.0);
    }
    sea_cli_progress_end(&prog.bar);
    st = sea_cli_mpi_agree(st, 0, NULL, err);
    free(pack);
    free(rows);
    sea_image_free(&img);
    sea_imager_image_free(&cam);
    if (st != SEA_OK || s->quiet || rank != 0)
        return st;
    return render_summary(s, levels, start, t_min, t_max, &ct, err);
}

