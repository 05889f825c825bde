/* bake.c - the bake subcommand of seabake: a scene file
 * (seabake-scene(5)) to a directory of per-level maps and a manifest.
 *
 * The directory is the library's (<seabake/bakedir.h>): sea_bake_dir
 * checks -o and replaces it atomically, a sea_bake_writer computes and
 * writes every frame.  What stays here is the program's: the options and
 * their help, the progress bar, signals, the summary line, and the MPI
 * transport (frames, or the texel rows of one frame, computed by other
 * ranks and handed to rank 0's writer level by level). */
#define _XOPEN_SOURCE 700
#include <assert.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake.h"

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
    "  --emissivity M      auto, fast or full: overrides the scene's [model]\n"
    "                      emissivity rule, as in seabake render\n"
    "  --set SECTION.KEY=VALUE\n"
    "                      overrides a key of the scene file (as in seabake\n"
    "                      render); repeatable\n"
    "  --unset SECTION.KEY removes a key of the scene file (as in seabake render)\n"
    "  --explain           what is modelled and why (as seabake render --explain)\n"
    "  --png none          no PNG previews (nor their names in the manifest)\n"
    "  --threads N         OpenMP threads, 1 to 4 x the online CPUs (at most 1024);\n"
    "                      default: the OpenMP default\n"
    "  --quiet             no progress bar and no summary line\n"
    "\n"
    "Under mpirun or srun (a build with MPI) the frames, or the texel rows of\n"
    "one frame, are shared among the ranks, rank 0 writing every file: DIR is\n"
    "that of one process; seabake(1), PARALLEL RUNS WITH MPI.\n";

/* ------------------------------------------------------------- the setup */

/* The exports project the sensor's image (--emission-space sensor). */
static bool bake_sensor(const sea_cli_bake *s)
{
    return (s->opt.pov || s->opt.blender) && s->opt.emission_space == SEA_BAKE_SPACE_SENSOR;
}

static sea_status bake_parse(const sea_cli_args *args, sea_cli_bake *s, sea_error *err)
{
    memset(s, 0, sizeof *s);
    sea_bake_options *o = &s->opt;
    sea_bake_options_default(o);
    sea_status st;
    if ((st = sea_cli_scene_arg(args, &s->scene_path, err)) != SEA_OK)
        return st;
    o->scene_file = s->scene_path;
    const char *out = sea_cli_args_get(args, "o");
    if (out == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "missing -o DIR (the output directory)");
    size_t len = strlen(out);
    while (len > 1 && out[len - 1] == '/')
        len--;
    if (len == 0)
        return sea_fail(err, SEA_ERR_PARSE, "-o: empty directory name");
    if ((st = sea_cli_opt_exr(args, &o->exr, err)) != SEA_OK)
        return st;
    bool framed;
    if ((st = sea_cli_opt_frames(args, &framed, &o->first, &o->last, &o->frame_rate, err)) !=
        SEA_OK)
        return st;
    o->framed = framed;
    o->pov = sea_cli_given(args, "pov");
    long view_k;
    if ((st = sea_cli_opt_integer(args, "emission-texels", 1, SEA_BAKE_VIEW_K_MAX, o->view_k,
                                  &view_k, err)) != SEA_OK)
        return st;
    if (view_k % 2 == 0)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--emission-texels: %ld is even (allowed: odd, 1 to %d: the texels must "
                        "hold the facet centres)",
                        view_k, SEA_BAKE_VIEW_K_MAX);
    o->view_k = (int)view_k;
    o->blender = sea_cli_given(args, "blender");
    const char *space = sea_cli_args_get(args, "emission-space");
    if (space != NULL && strcmp(space, "sensor") != 0 && strcmp(space, "map") != 0)
        return sea_fail(err, SEA_ERR_PARSE, "--emission-space: '%s' is not sensor or map", space);
    if (space != NULL && !o->pov && !o->blender)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--emission-space applies only with --pov or --blender (it chooses what "
                        "their sea shows)");
    if (space != NULL && strcmp(space, "map") == 0)
        o->emission_space = SEA_BAKE_SPACE_MAP;
    s->explain = sea_cli_given(args, "explain");
    s->quiet = sea_cli_given(args, "quiet");
    const char *png = sea_cli_args_get(args, "png");
    if (png != NULL && strcmp(png, "none") != 0)
        return sea_fail(err, SEA_ERR_PARSE,
                        "--png: '%s' is not none (allowed: none, no previews; a bake's "
                        "previews are named after their maps)",
                        png);
    if (png != NULL)
        o->previews = 0;
    if ((st = sea_cli_opt_threads(args, err)) != SEA_OK)
        return st;
    sea_cli_model model;
    if ((st = sea_cli_opt_model(args, &model, err)) != SEA_OK)
        return st;
    if ((st = sea_cli_load_scene(args, s->scene_path, &s->sc, err)) != SEA_OK)
        return st;
    sea_cli_apply_model(&model, &s->sc);
    if ((st = sea_cli_check_frame_times(s->sc.time, framed, o->first, o->last, o->frame_rate,
                                        err)) != SEA_OK)
        return st;
    if ((st = sea_bake_options_check(o, &s->sc, err)) != SEA_OK)
        return st;
    if ((s->dir = strndup(out, len)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    return SEA_OK;
}

/* ------------------------------------------------------------ progress */

/* SIGINT, SIGTERM or SIGHUP during a bake (sea_cli_signals_catch): the
 * bake stops at the next map it would write (or within a row of the frame
 * it computes), removes its temporary directory, and then dies of the
 * signal, DIR untouched. */
sea_status sea_cli_bake_interrupted(sea_error *err)
{
    return sea_fail(err, SEA_ERR_IO, "interrupted by signal %d: the output directory is left as "
                                     "it was", sea_cli_interrupted());
}

/* The progress bar (with the writer's progress, or the program's own
 * frames' under MPI: bake_mpi.c). */
/* The writer's progress callback (the fraction of the whole bake): the bar
 * on a terminal, and a stop as soon as a signal came. */
static int bake_progress_whole(void *ctx, double fraction)
{
    sea_cli_bake_progress *p = ctx;
    const double x = fraction * (double)p->bar.count;
    size_t i = x > 0.0 ? (size_t)ceil(x) - 1 : 0;
    if (i >= p->bar.count)
        i = p->bar.count - 1;
    p->bar.index = i;
    return sea_cli_progress_if(&p->bar, p->on, x - (double)i);
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

/* Rank 0: every frame into the writer, its own computed by the writer,
 * the others' received (under MPI), then the finish. */
static sea_status bake_all(const sea_cli_bake *s, const sea_view *r, const char *tmp,
                           sea_cli_bake_stats *stats, sea_error *err)
{
    const long first = s->opt.framed ? s->opt.first : 0, last = s->opt.framed ? s->opt.last : 0;
    memset(stats, 0, sizeof *stats);
    sea_cli_bake_progress prog = {{"bake", 0, (size_t)(last - first + 1), -1, 0.0},
                                  !s->quiet && isatty(STDERR_FILENO)};
    sea_bake_writer *w = NULL;
    sea_status st = sea_bake_writer_alloc(r, &s->opt, tmp, bake_progress_whole, &prog, &w, err);
    /* under MPI: the others' levels, and which ranks still send */
    const int size = sea_cli_mpi_size();
    sea_cli_bake_inbox in;
    if (st == SEA_OK)
        st = sea_cli_bake_inbox_alloc(&in, s, r, err);
    else
        memset(&in, 0, sizeof in);
    long f = first;
    for (; f <= last && st == SEA_OK; ++f) {
        const int owner = size > 1 ? sea_cli_bake_owner(s, f) : 0;
        prog.bar.index = (size_t)(f - first);
        if (size == 1 || (s->opt.framed && owner == 0))
            st = sea_bake_writer_frame(w, err);
        else
            st = sea_cli_bake_frame_mpi(&in, s, r, w, owner, f, &prog, stats, err);
        /* a signal's message, whatever stopped the bake */
        if (sea_cli_interrupted() != 0)
            st = sea_cli_bake_interrupted(err);
        sea_cli_bake_answer(&in, owner, st);
    }
    sea_cli_bake_inbox_free(&in, s, w, f);
    if (st == SEA_OK)
        st = sea_bake_writer_finish(w, err);
    sea_cli_progress_end(&prog.bar);
    if (w != NULL) {
        sea_bake_stats ws;
        sea_bake_writer_stats(w, &ws);
        stats->texels = ws.texels;
        stats->compute += ws.maps;
        stats->write += ws.files;
        stats->parts.waves += ws.parts.waves;
        stats->parts.image += ws.parts.image;
        stats->parts.optics += ws.parts.optics;
        stats->parts.view += ws.parts.view;
    }
    sea_bake_writer_free(w);
    return st;
}

static sea_status run_bake(const sea_cli_args *args, FILE *out, sea_error *err)
{
    (void)out; /* files go to DIR, the summary to standard error */
    const double start = sea_cli_seconds();
    sea_cli_bake s;
    sea_view *r = NULL;
    sea_bake_dir *od = NULL;
    sea_cli_bake_stats stats = {0};
    double prepare = 0.0;
    /* under MPI rank 0 alone owns the directory (see sea_cli_bake_send_frames) */
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
        st = sea_view_alloc(&s.sc, &r, err);
        prepare = sea_cli_seconds() - t0;
        /* no sensor's image to render: the pixels' plans are not needed
         * (the maps' view texels plan theirs as they go) */
        if (st == SEA_OK && !bake_sensor(&s))
            sea_view_drop_pixels(r);
    }
    st = sea_cli_mpi_agree(st, 0, NULL, err);
    if (st == SEA_OK && s.explain && rank == 0)
        sea_cli_explain("bake", s.scene_path, r);
    if (st == SEA_OK)
        st = rank == 0       ? bake_all(&s, r, sea_bake_dir_path(od), &stats, err)
             : s.opt.framed ? sea_cli_bake_send_frames(&s, r, err)
                            : sea_cli_bake_send_rows(&s, r, err);
    if (st == SEA_OK && sea_cli_interrupted() != 0)
        st = sea_cli_bake_interrupted(err);
    /* rank 0's error first: it holds the first failure of any rank */
    st = sea_cli_mpi_agree(st, rank, NULL, err);
    if (st == SEA_OK && rank == 0)
        st = sea_bake_dir_commit(od, err);
    sea_bake_dir_free(od);
    st = sea_cli_mpi_agree(st, rank, NULL, err);
    /* Under MPI the job ends together: the error is reported, not died of. */
    if (sea_cli_interrupted() != 0 && st != SEA_OK && size == 1) {
        /* the temporary directory is gone: die of the signal, as asked */
        sea_view_free(r);
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
    sea_view_free(r);
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
    {"emissivity", 0},
    {"set", SEA_CLI_OPT_ACCUMULATE},
    {"unset", SEA_CLI_OPT_ACCUMULATE},
    {"png", 0},
    {"threads", 0},
    {"quiet", SEA_CLI_OPT_FLAG}};

const sea_cli_command sea_cli_cmd_bake = {
    "bake", "per-level EXR maps, previews and a manifest of a scene file", BAKE_HELP,
    BAKE_OPTIONS, SEA_CLI_COUNT(BAKE_OPTIONS), run_bake};
