/* render.c - the render subcommand of seabake: a scene file
 * (seabake-scene(5)) to images; its options, help and run (the frames and
 * their files are render_frames.c's).
 *
 * One prepare (camera, levels, spectral samples, wave plan), then one
 * sea_view_render_frame per frame; each frame writes the radiance to OUT.exr
 * (channel Y), the requested AOVs to OUT.<aov>.exr and a brightness
 * temperature preview to OUT.png (each AOV its own OUT.<aov>.png), with a
 * frame suffix (OUT_0001.exr) when --frames is given.  The previews' tone
 * curves are fixed by the first frame (or --png-range), so a sequence
 * does not flicker.
 *
 * Every option is checked, and the scene file read, before any work; the
 * output directories are checked before the (long) rendering.  The
 * exporters write each file under a temporary name and rename it when
 * complete; if one file of a frame fails, the files this run already wrote
 * for that frame are removed, so a frame is all there or not at all. */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "render.h"

/* ------------------------------------------------------------ help text */

static const char RENDER_HELP[] =
    "Usage: seabake render SCENE.ini [-o OUT.exr] [OPTIONS]\n"
    "\n"
    "Renders the view described by a scene file (seabake-scene(5)): the radiance\n"
    "of every pixel (Eq 23 of the paper) over the clipmap levels the view needs.\n"
    "Writes OUT.exr (channel Y: spectral radiance, W m^-2 sr^-1 um^-1, for one\n"
    "wavelength; in-band radiance, W m^-2 sr^-1, for a band) and a PNG preview\n"
    "of the brightness temperature.  Files are written atomically, each in a\n"
    "marked temporary OUT.tmp.XXXXXX/; those a killed render left beside the\n"
    "same outputs are removed, with a note.  A summary line goes to standard\n"
    "error, and a progress bar on a terminal.  On SIGINT (Ctrl-C), SIGTERM or\n"
    "SIGHUP the frame in progress is not written (earlier frames stay) and\n"
    "seabake dies of the signal.\n"
    "\n"
    "Output:\n"
    "  -o OUT.exr          the radiance image; default: the scene file's base name\n"
    "                      with .exr, in the current directory; its directory\n"
    "                      must exist\n"
    "  --aov LIST          comma list of level (facet size, m; 0 for the sky),\n"
    "                      emissivity, reflectivity (sr^-1), temperature\n"
    "                      (brightness, K): each to OUT.<aov>.exr, channel Y;\n"
    "                      stokes: the linear Stokes parameters of the radiance\n"
    "                      in the camera's frame to OUT.stokes.exr, channels I,\n"
    "                      Q, U (radiance units; +Q along the image's up axis;\n"
    "                      Q and U with the model's surface hits, the second\n"
    "                      where it takes one; no preview)\n"
    "  --png FILE.png      the preview of the brightness temperature; default\n"
    "                      OUT.png; none: no previews at all.  Grey, two linear\n"
    "                      ramps: the 0.5 % quantile black, knee K = 2 median -\n"
    "                      that 80 % grey, the maximum white (one ramp when the\n"
    "                      hot tail is short), all from the first frame; each\n"
    "                      AOV gets OUT.<aov>.png (level in colour, one hue per\n"
    "                      facet size, sky black)\n"
    "  --png-tone T        the temperature previews' curve, from the first frame:\n"
    "                      scene (the ramps above, over every pixel), sea (one\n"
    "                      ramp from the sea pixels alone: their 0.5 % quantile\n"
    "                      black, 99.5 % white, the sky clamped) or auto\n"
    "                      (default): sea when the sky is far from the sea (its\n"
    "                      median beyond the sea's 0.5-99.5 % range by more than\n"
    "                      that range), else scene\n"
    "  --png-range LO:HI   kelvin, 0 < LO < HI <= 10000: one linear ramp instead,\n"
    "                      LO black, HI white (the temperature previews)\n"
    "  --png-depth D       bits per sample of the previews, 8 (default) or 16\n"
    "  --format F          float (default) or half channels (the level AOV stays\n"
    "                      float)\n"
    "  --compression C     none, zip (default) or piz\n"
    "\n"
    "A camera: a scene whose [sensor] gives any camera key (psf_sigma, f_number,\n"
    "mtf, fill_factor, netd, fpn_gain, fpn_offset, gain; seabake-scene(5)) gets,\n"
    "for each frame, what that camera makes of the radiance image beside it\n"
    "(OUT.exr unchanged): OUT.camera.exr (channel T: apparent brightness\n"
    "temperature, K; Y: the camera's radiance; always float; uncompressed\n"
    "unless --compression is given), its preview OUT.camera.png (the main\n"
    "preview's tone curve) and, with a gain, OUT.counts.png (the counts as they\n"
    "are, 8-bit for bit_depth 8, else 16-bit); the summary line counts the\n"
    "saturated pixels.\n"
    "\n"
    "Frames:\n"
    "  --frames A:B        frames A to B, integers, 0 <= A <= B <= 999999, at most\n"
    "                      100000; frame f at time + f / HZ; each file name gets\n"
    "                      the frame number: OUT_0001.exr, OUT_0001.level.exr,\n"
    "                      OUT_0001.png.  Default: one frame at the scene's time\n"
    "  --frame-rate HZ     frames per second, > 0; default 25 (only with --frames);\n"
    "                      every frame's time, [sea] time + frame / HZ, within\n"
    "                      +-1e9 s\n"
    "\n"
    "Scene:\n"
    "  --set SECTION.KEY=VALUE\n"
    "                      overrides a key of the scene file, checked as in the\n"
    "                      file (e.g. --set sea.wind_speed=12); repeatable\n"
    "  --unset SECTION.KEY removes a key of the scene file, its default back (e.g.\n"
    "                      --unset sensor.band --set sensor.wavelength=4);\n"
    "                      repeatable; not [swell] keys\n"
    "\n"
    "Running:\n"
    "  --tolerance T       relative, (0, 0.1]: overrides the scene's [model]\n"
    "                      tolerance (low-resolution levels, spectral samples,\n"
    "                      emissivity orders, wave directions, sub-facets skipped).\n"
    "                      Default: the scene's; a scene with a [sensor] netd\n"
    "                      and no tolerance gets a tenth of the NETD's radiance\n"
    "                      over the sea's, at most 0.1 (seabake-model(7), The\n"
    "                      tolerance from the NETD; --explain shows it)\n"
    "  --reflections R     auto (default), 1, 2 or 3: overrides the scene's [model]\n"
    "                      reflections (auto: a second hit where it can move a\n"
    "                      pixel by a hundredth of the tolerance; 1, the paper:\n"
    "                      a mirror ray brings the sky, examples/mast.ini up to\n"
    "                      12 % off the reference at 0.7 of auto's CPU time; 2,\n"
    "                      3: every mirror ray may meet the sea again first, 3\n"
    "                      at 1.2 times 2's CPU time and no closer to ray\n"
    "                      tracing)\n"
    "  --reference         every approximation the tolerance allows replaced by\n"
    "                      its exact form, at least two hits: the yardstick the\n"
    "                      default keeps within the tolerance of (10-40 times\n"
    "                      its time; seabake(1), REFERENCE)\n"
    "  --shadowing S       overrides the scene's [model] shadowing: correlated\n"
    "                      (default; within 1.1e-3 of ray tracing to 85 deg) or\n"
    "                      smith (the paper's, up to 12e-3 low at 75-85 deg)\n"
    "  --scales N          overrides the scene's [model] scales: 2 (default: the\n"
    "                      slopes of waves longer than the half-variance split\n"
    "                      count as facets, every level agrees with low\n"
    "                      resolution) or 1 (one Gaussian surface, the paper)\n"
    "  --emissivity M      overrides the scene's [model] emissivity rule: auto\n"
    "                      (default: within 1e-6 of full), fast (Eq 12) or full\n"
    "  --threads N         OpenMP threads, 1 to 4 x the online CPUs (at most 1024);\n"
    "                      default: the OpenMP default\n"
    "  --quiet             no progress bar and no summary line\n"
    "  --explain           print on standard error what was chosen: the clipmap\n"
    "                      levels (facet size, window, resolution, pixels, sub-\n"
    "                      facets), why levels are low-resolution or sub-facets\n"
    "                      skipped, the emissivity rule, the wave components, the\n"
    "                      fallbacks taken (seabake(1), LIMITS AND FALLBACKS), the\n"
    "                      spectral samples\n"
    "\n"
    "Under mpirun or srun (a build with MPI) the frames, or the rows of one\n"
    "frame, are shared among the ranks, and the files are those of one process;\n"
    "seabake(1), PARALLEL RUNS WITH MPI.\n";

/* ------------------------------------------------------------- the setup */

static void render_setup_free(sea_cli_render *s)
{
    free(s->out_stem);
    free(s->png_stem);
    sea_imager_free(s->camera);
    s->out_stem = s->png_stem = NULL;
    s->camera = NULL;
}

/* The upper end of [model] tolerance's range (0, 0.1] in scene.c. */
#define RENDER_TOL_MAX 0.1

/* A scene with a camera's netd: the tolerance that keeps the model's error
 * within SEA_IMAGER_NETD_FRACTION of the NETD (sea_imager_scene_tolerance),
 * kept in tol_netd for --explain, and made the render's when neither the
 * scene nor --tolerance gives one (clamped to the range; no lower end). */
static sea_status netd_tolerance(sea_cli_render *s, bool option_given, sea_error *err)
{
    if (isnan(s->sc.netd))
        return SEA_OK;
    sea_error lib = {{0}};
    sea_status st = sea_imager_scene_tolerance(&s->sc, SEA_IMAGER_NETD_FRACTION, &s->tol_netd,
                                               &lib);
    if (st != SEA_OK)
        return sea_fail(err, st, "%s: %s", s->scene_path, lib.msg);
    if (!s->sc.tolerance_given && !option_given) {
        s->sc.tolerance = fmin(s->tol_netd, RENDER_TOL_MAX);
        s->tol_from_netd = true;
    }
    return SEA_OK;
}

/* --explain's lines about the camera: its keys, its files, and where the
 * tolerance came from. */
static void explain_camera(const sea_cli_render *s)
{
    if (s->camera != NULL) {
        char text[512];
        sea_cli_camera_text(&s->sc, text, sizeof text);
        fprintf(stderr,
                "render: camera: %s (seabake-model(7), THE CAMERA): applied to each frame after "
                "rendering, to %s.camera.exr (T: apparent brightness temperature, K; Y: "
                "radiance)%s%s\n",
                text, s->out_stem, s->png ? ", its preview .camera.png" : "",
                sea_imager_counts(s->camera) ? ", counts .counts.png" : "");
    }
    if (isnan(s->sc.netd))
        return;
    const double f = SEA_IMAGER_NETD_FRACTION;
    char formula[320];
    snprintf(formula, sizeof formula,
             "f NETD dL/dT(T_n) / L(T_sea), f = %g, NETD = %g K, T_n = %g K, T_sea = %g K: %.4g", f,
             s->sc.netd, s->sc.netd_temperature, s->sc.temperature, s->tol_netd);
    if (s->tol_from_netd)
        fprintf(stderr,
                "render: tolerance %.4g from the camera's NETD (neither the scene nor --tolerance "
                "gives one): %s%s\n",
                s->sc.tolerance, formula,
                s->tol_netd > RENDER_TOL_MAX ? ", clamped to the range (0, 0.1]" : "");
    else
        fprintf(stderr, "render: tolerance %g given; the camera's NETD would give %s\n",
                s->sc.tolerance, formula);
}

/* "--aov level,temperature,stokes". */
static sea_status parse_aovs(const char *text, bool aov[AOV_COUNT], bool *stokes, sea_error *err)
{
    const char *p = text;
    for (;;) {
        const char *end = strchr(p, ',');
        const size_t len = end ? (size_t)(end - p) : strlen(p);
        int k = -1;
        for (int q = 0; q < AOV_COUNT; ++q)
            if (strlen(RENDER_AOVS[q].name) == len && strncmp(RENDER_AOVS[q].name, p, len) == 0)
                k = q;
        const bool is_stokes = len == 6 && strncmp(p, "stokes", 6) == 0;
        if (k < 0 && !is_stokes)
            return sea_fail(err, SEA_ERR_PARSE,
                            "--aov: '%.*s' is not one of level, emissivity, reflectivity, "
                            "temperature, stokes (in '%s')",
                            (int)len, p, text);
        if (is_stokes ? *stokes : aov[k])
            return sea_fail(err, SEA_ERR_PARSE, "--aov: '%s' is given twice (in '%s')",
                            is_stokes ? "stokes" : RENDER_AOVS[k].name, text);
        if (is_stokes)
            *stokes = true;
        else
            aov[k] = true;
        if (end == NULL)
            return SEA_OK;
        p = end + 1;
    }
}

/* --png-range LO:HI, kelvin, 0 < LO < HI <= SEA_CLI_PNG_RANGE_MAX. */
static sea_status parse_png_range(const sea_cli_args *args, sea_cli_render *s, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "png-range");
    if (text == NULL)
        return SEA_OK;
    if (!s->png)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--png-range applies only to a preview, not --png none");
    static const sea_cli_range kelvin = {0.0, SEA_CLI_PNG_RANGE_MAX, true, false, "K"};
    const char *colon = strchr(text, ':');
    char lo_s[64];
    if (colon == NULL || strchr(colon + 1, ':') != NULL || (size_t)(colon - text) >= sizeof lo_s)
        return sea_fail(err, SEA_ERR_PARSE,
                        "--png-range: '%s' is not LO:HI (kelvin, 0 < LO < HI <= %g)", text,
                        SEA_CLI_PNG_RANGE_MAX);
    snprintf(lo_s, sizeof lo_s, "%.*s", (int)(colon - text), text);
    sea_status st;
    if ((st = sea_cli_parse_number("--png-range", lo_s, &kelvin, &s->png_lo, err)) != SEA_OK ||
        (st = sea_cli_parse_number("--png-range", colon + 1, &kelvin, &s->png_hi, err)) != SEA_OK)
        return st;
    if (!(s->png_lo < s->png_hi))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--png-range: '%s': LO must be below HI (kelvin, 0 < LO < HI <= %g)",
                        text, SEA_CLI_PNG_RANGE_MAX);
    s->png_range = true;
    return SEA_OK;
}

/* --png-tone auto|scene|sea (auto when absent); not with --png-range,
 * which fixes the curve, nor --png none. */
static sea_status parse_png_tone(const sea_cli_args *args, sea_cli_render *s, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "png-tone");
    s->png_tone = RENDER_TONE_AUTO;
    if (text == NULL)
        return SEA_OK;
    if (!s->png)
        return sea_fail(err, SEA_ERR_DOMAIN, "--png-tone applies only to a preview, not --png none");
    if (s->png_range)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--png-tone and --png-range: choose one (--png-range fixes the curve)");
    if (strcmp(text, "auto") == 0)
        s->png_tone = RENDER_TONE_AUTO;
    else if (strcmp(text, "scene") == 0)
        s->png_tone = RENDER_TONE_SCENE;
    else if (strcmp(text, "sea") == 0)
        s->png_tone = RENDER_TONE_SEA;
    else
        return sea_fail(err, SEA_ERR_PARSE,
                        "--png-tone: '%s' is not a tone (allowed: auto, scene, sea)", text);
    return SEA_OK;
}

/* The default output: the scene file's base name, its extension replaced
 * by .exr, in the current directory. */
static char *default_stem(const char *scene_path)
{
    const char *base = strrchr(scene_path, '/');
    base = base ? base + 1 : scene_path;
    const char *dot = strrchr(base, '.');
    const size_t len = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    return strndup(base, len);
}

/* Every option, then the scene file (its errors are usage errors, exit 2,
 * or SEA_ERR_IO when it cannot be read). */
static sea_status render_parse(const sea_cli_args *args, sea_cli_render *s, sea_error *err)
{
    memset(s, 0, sizeof *s);
    sea_status st;
    if ((st = sea_cli_scene_arg(args, &s->scene_path, err)) != SEA_OK)
        return st;

    const char *out = sea_cli_args_get(args, "o");
    if (out != NULL && !sea_cli_has_suffix(out, ".exr"))
        return sea_fail(err, SEA_ERR_PARSE, "-o: '%s' must end in .exr", out);
    const char *png = sea_cli_args_get(args, "png");
    s->png = png == NULL || strcmp(png, "none") != 0;
    if (png != NULL && s->png && !sea_cli_has_suffix(png, ".png"))
        return sea_fail(err, SEA_ERR_PARSE, "--png: '%s' must end in .png (or be none)", png);
    long depth;
    if ((st = sea_cli_opt_integer(args, "png-depth", 8, 16, 8, &depth, err)) != SEA_OK)
        return st;
    if (depth != 8 && depth != 16)
        return sea_fail(err, SEA_ERR_DOMAIN, "--png-depth: %ld is not 8 or 16", depth);
    if (!s->png && sea_cli_given(args, "png-depth"))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--png-depth applies only to a preview, not --png none");
    s->png_depth = (int)depth;
    if ((st = parse_png_range(args, s, err)) != SEA_OK ||
        (st = parse_png_tone(args, s, err)) != SEA_OK)
        return st;
    const char *aov = sea_cli_args_get(args, "aov");
    if (aov != NULL && (st = parse_aovs(aov, s->aov, &s->stokes, err)) != SEA_OK)
        return st;

    if ((st = sea_cli_opt_frames(args, &s->framed, &s->frame_a, &s->frame_b, &s->rate, err)) !=
        SEA_OK)
        return st;
    if ((st = sea_cli_opt_threads(args, err)) != SEA_OK)
        return st;
    if ((st = sea_cli_opt_exr(args, &s->exr, err)) != SEA_OK)
        return st;
    s->camera_compression = sea_cli_given(args, "compression") ? s->exr.compression : SEA_EXR_NONE;
    s->quiet = sea_cli_given(args, "quiet");
    s->explain = sea_cli_given(args, "explain");
    s->progress = !s->quiet && isatty(STDERR_FILENO);
    sea_cli_model model;
    if ((st = sea_cli_opt_model(args, &model, err)) != SEA_OK)
        return st;

    /* The scene is read last: a typing mistake on the command line is
     * reported first. */
    if ((st = sea_cli_load_scene(args, s->scene_path, &s->sc, err)) != SEA_OK)
        return st;
    sea_cli_apply_model(&model, &s->sc);
    if ((st = netd_tolerance(s, !isnan(model.tolerance), err)) != SEA_OK)
        return st;
    if ((st = sea_cli_check_frame_times(s->sc.time, s->framed, s->frame_a, s->frame_b, s->rate,
                                        err)) != SEA_OK)
        return st;

    if (out != NULL) {
        s->out_stem = strndup(out, strlen(out) - strlen(".exr"));
        s->out_ext = out + strlen(out) - strlen(".exr");
    } else {
        s->out_stem = default_stem(s->scene_path);
        s->out_ext = ".exr";
    }
    if (s->png && png != NULL) {
        s->png_stem = strndup(png, strlen(png) - strlen(".png"));
        s->png_ext = png + strlen(png) - strlen(".png");
    } else if (s->png) {
        s->png_stem = s->out_stem ? strdup(s->out_stem) : NULL;
        s->png_ext = ".png";
    }
    if (s->out_stem == NULL || (s->png && s->png_stem == NULL))
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    return SEA_OK;
}

static sea_status run_render(const sea_cli_args *args, FILE *out, sea_error *err)
{
    (void)out; /* the images go to files, the reports to standard error */
    const double start = sea_cli_seconds();
    sea_cli_render s;
    sea_view *r = NULL;
    sea_status st = render_parse(args, &s, err);
    if (st == SEA_OK)
        st = sea_cli_render_check_outputs(&s, err);
    if (st == SEA_OK)
        st = sea_cli_threads_start(err);
    if (st == SEA_OK)
        st = sea_view_alloc(&s.sc, &r, err);
    /* The scene's camera, if it gives one: planned once for every frame. */
    if (st == SEA_OK) {
        sea_error lib = {{0}};
        if ((st = sea_imager_from_render(r, &s.camera, &lib)) != SEA_OK)
            sea_fail(err, st, "%s: [sensor] %s", s.scene_path, lib.msg);
    }
    /* Under MPI every rank has read the same arguments and files; a rank
     * that could not (a file system one node does not see) stops them all. */
    const int size = sea_cli_mpi_size();
    st = sea_cli_mpi_agree(st, 0, NULL, err);
    if (st == SEA_OK && s.explain && sea_cli_mpi_rank() == 0) {
        sea_cli_explain("render", s.scene_path, r);
        explain_camera(&s);
    }
    /* What a render killed before its rename left beside these outputs
     * (SIGKILL, a crash): removed with a note, by one rank, before any
     * rank writes (a live writer's flock keeps its own). */
    if (st == SEA_OK && sea_cli_mpi_rank() == 0) {
        sea_cli_clean_stale_files("render", s.out_stem);
        if (s.png && strcmp(s.png_stem, s.out_stem) != 0)
            sea_cli_clean_stale_files("render", s.png_stem);
    }
    if (st == SEA_OK) {
        sea_cli_signals_catch();
        st = size == 1   ? sea_cli_render_frames(&s, r, start, err)
             : s.framed ? sea_cli_render_frames_mpi(&s, r, start, err)
                        : sea_cli_render_rows_mpi(&s, r, start, err);
        /* Under MPI the job ends together: the error is reported, not died of. */
        if (st != SEA_OK && sea_cli_interrupted() != 0 && size == 1) {
            sea_view_free(r);
            render_setup_free(&s);
            sea_cli_die_of_signal(err->msg);
            return st;
        }
        sea_cli_signals_restore();
    }
    sea_view_free(r);
    render_setup_free(&s);
    return st;
}

/* --------------------------------------------------------------- command */

static const sea_cli_option RENDER_OPTIONS[] = {
    {"scene", SEA_CLI_OPT_POSITIONAL},
    {"o", SEA_CLI_OPT_SHORT},
    {"frames", 0},
    {"frame-rate", 0},
    {"aov", 0},
    {"png", 0},
    {"png-depth", 0},
    {"format", 0},
    {"compression", 0},
    {"set", SEA_CLI_OPT_ACCUMULATE},
    {"unset", SEA_CLI_OPT_ACCUMULATE},
    {"png-range", 0},
    {"png-tone", 0},
    {"threads", 0},
    {"tolerance", 0},
    {"reflections", 0},
    {"reference", SEA_CLI_OPT_FLAG},
    {"shadowing", 0},
    {"scales", 0},
    {"emissivity", 0},
    {"quiet", SEA_CLI_OPT_FLAG},
    {"explain", SEA_CLI_OPT_FLAG}};

const sea_cli_command sea_cli_cmd_render = {
    "render", "images of a scene file: radiance EXR, AOVs, PNG preview", RENDER_HELP,
    RENDER_OPTIONS, SEA_CLI_COUNT(RENDER_OPTIONS), run_render};
