/* bakedir.h - the bake directory: every file `seabake bake` writes, written
 * by the library.  Installed as <seabake/bakedir.h>; ownership and the
 * thread-safety words follow seabake.h, and nothing here prints or exits:
 * what the program shows (a progress bar, notes, a summary) comes through
 * the callbacks and sea_bake_stats.
 *
 * A bake directory holds, for every high-resolution clipmap level l and
 * frame, single-part scanline EXR maps of plain R, G, B(, A) channels (Y
 * alone for emission), <group>_<l>[_<FFFF>].exr, and an 8-bit PNG preview of
 * each (groups moments, moments2, optics, normal, roughness, emission);
 * manifest.json, which places every map in the world, gives the scene, the
 * sensor, the units, the emission scale and lists every file of the
 * directory ("files"); with the exports (pov, blender) also horizon.exr (the
 * low-resolution sea to the horizon), sensor[_FFFF].exr (the sensor's image,
 * emission space sensor) with the waves' heights height_<l>[_FFFF].png (POV)
 * and .exr (Blender), the POV-Ray scene (scene.pov, sea.inc, scene.ini,
 * seabake.inc: <seabake/povray.h>) and the Blender import script
 * (seabake_import.py: <seabake/blender.h>).  seabake(1), BAKE, describes
 * every file and channel.
 *
 * Three layers, each usable alone:
 *  - sea_bake_write: a whole bake of a prepared scene (sea_view_alloc)
 *    into a directory that is replaced atomically.
 *  - sea_bake_dir: the atomic directory.  Files go into a fresh sibling
 *    DIR.tmp.XXXXXX; the commit puts it in place of DIR; a failed or
 *    abandoned bake leaves DIR as it was.
 *  - sea_bake_writer: the files of a bake, written into a directory frame by
 *    frame and level by level.  It computes a frame itself
 *    (sea_bake_writer_frame), or takes the levels of a frame computed
 *    elsewhere (sea_bake_writer_frame_begin, sea_bake_writer_level for each
 *    high-resolution level, sea_bake_writer_frame_end), so that a program
 *    that shares the work among processes (seabake under MPI: whole frames,
 *    or the texel rows of one frame, sea_bake_frame_rows) moves the levels'
 *    bytes itself and gives them to the one writer.  Either way the files
 *    are the same, byte for byte.
 *
 * Memory.  The writer holds one level's maps at a time (the largest level's
 * buffers, a few of them for the threads writing a level's files at once).
 * The first frame sets what every frame shares (the emission scale, from its
 * largest radiance, and the previews' tone curves, from its texels of every
 * level), so its emission maps and toned previews wait for the whole frame:
 * their data go to a spill file per level (.spill_<l>, a dot file in the
 * directory, removed before the frame ends). */
#ifndef SEABAKE_BAKEDIR_H
#define SEABAKE_BAKEDIR_H

#include <stddef.h>

#include "exr.h"
#include "seabake.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- options */

/* Frame numbers in file names carry at least this many digits, as
 * Blender's "####"; frames are numbered 0 to SEA_BAKE_FRAME_MAX, at most
 * SEA_BAKE_FRAMES_MAX of them in one bake. */
enum { SEA_BAKE_FRAME_DIGITS = 4, SEA_BAKE_FRAME_MAX = 999999, SEA_BAKE_FRAMES_MAX = 100000 };

/* What the exported sea shows where the sensor sees it (pov or blender). */
typedef enum {
    SEA_BAKE_SPACE_SENSOR = 0, /* the sensor's image, sensor[_FFFF].exr, projected from
                                  the sensor onto rings that carry the waves */
    SEA_BAKE_SPACE_MAP         /* each level's emission map on flat rings */
} sea_bake_space;

typedef struct {
    sea_exr_options exr;   /* channels float or half, compression none, zip or piz */
    int framed;            /* 0: one frame at the scene's time, no number in names */
    long first, last;      /* framed: frames first..last, 0 <= first <= last <=
                              SEA_BAKE_FRAME_MAX, at most SEA_BAKE_FRAMES_MAX */
    double frame_rate;     /* framed: Hz, > 0; frame f at the scene's time + f / rate */
    int view_k;            /* emission texels per facet side: odd, 1 to SEA_BAKE_VIEW_K_MAX */
    int pov;               /* also the POV-Ray scene */
    int blender;           /* also the Blender import script */
    sea_bake_space emission_space; /* read only with pov or blender */
    int previews;          /* the PNG preview of every map (0: none, nor their
                              names in the manifest) */
    const char *scene_file; /* the manifest's "scene_file" (may be NULL: null) */
} sea_bake_options;

/* seabake bake's defaults: float, zip, one frame (first = last = 0, rate 25),
 * view_k 3, no exports, emission space sensor, previews, no scene file.
 * Fills o. */
void sea_bake_options_default(sea_bake_options *o);
/* SEA_OK when o can bake the scene sc: the ranges above, and for pov or
 * blender an isotropic sky and no atmosphere (the exports' sky is one
 * radiance: a sky that changes with the zenith angle or air along the
 * camera's rays would show wrong there).  Otherwise SEA_ERR_DOMAIN naming
 * the field.  Pure. */
sea_status sea_bake_options_check(const sea_bake_options *o, const sea_scene *sc,
                                  sea_error *err);
/* The time of frame f of a bake with options o of a scene whose time is
 * time0 (s): time0 + f / frame_rate when framed, else time0.  Pure. */
double sea_bake_options_frame_time(const sea_bake_options *o, double time0, long f);

/* Where a bake's time went, and what it baked. */
typedef struct {
    size_t texels;        /* high-resolution texels written, every frame */
    double maps;          /* s computing: the frames this writer computed (the
                             sensor's image included) and the horizon */
    double files;         /* s writing files */
    sea_bake_times parts; /* the frames' own parts (sea_bake_frame_each's) */
} sea_bake_stats;

/* ------------------------------------------------------------ the writer */

typedef struct sea_bake_writer sea_bake_writer;

/* Starts a bake of r (sea_view_alloc of the scene) with options o
 * (sea_bake_options_check against r's scene: SEA_ERR_DOMAIN) into dir, an
 * existing directory, normally empty (the manifest's "files" lists every
 * file in it; sea_bake_dir_path gives the atomic one).  Allocates the map
 * buffers.  progress (may be NULL) gets the fraction of the whole bake done
 * (frames first to last, computing and writing, as sea_progress_fn says);
 * it is also asked, with the fraction it was last given, before each
 * level's files, and a non-zero answer stops the bake (SEA_ERR_CANCELLED).
 * The writer keeps pointers to r and to progress's ctx, which must outlive
 * it, and copies o (its scene_file) and dir.  Reads r; *out is the caller's,
 * freed with sea_bake_writer_free(). */
sea_status sea_bake_writer_alloc(const sea_view *r, const sea_bake_options *o, const char *dir,
                                 sea_progress_fn progress, void *ctx, sea_bake_writer **out,
                                 sea_error *err);
void sea_bake_writer_free(sea_bake_writer *w);

/* The frame the writer takes next: first, first + 1, ... (0 when not
 * framed); past the last once every frame is in.  Reads w. */
long sea_bake_writer_next_frame(const sea_bake_writer *w);
/* Whether sea_bake_writer_frame_end needs the frame's sensor image (the
 * exports project it: pov or blender with emission space sensor).  Reads w. */
int sea_bake_writer_wants_view(const sea_bake_writer *w);

/* Computes the next frame (sea_bake_frame_image, or sea_bake_frame_each
 * without the sensor's image: one level's maps held at a time) and writes
 * all its files: sea_bake_writer_frame_begin, _level and _frame_end in one.
 * Threads: OpenMP (the files do not depend on their number).  Fills w. */
sea_status sea_bake_writer_frame(sea_bake_writer *w, sea_error *err);

/* The next frame from levels computed elsewhere.  frame_begin: frame must
 * be sea_bake_writer_next_frame (SEA_ERR_DOMAIN otherwise).  Then
 * sea_bake_writer_level for each high-resolution level of the frame, in
 * any order, once; its signature is sea_bake_level_fn's, so that it is
 * passed to sea_bake_frame_each as each with the writer as each_ctx: b
 * holds every level's header and level l's maps (moments, optics, view; as
 * sea_bake_frame gives them, from the same preparation as the writer's r,
 * SEA_ERR_DOMAIN otherwise), read only during the call.  Then frame_end,
 * b the frame's headers (every level's; no maps needed) and view the
 * frame's sensor image (sea_view_render_frame at the frame's time) when
 * sea_bake_writer_wants_view, else NULL.  Fills w. */
sea_status sea_bake_writer_frame_begin(sea_bake_writer *w, long frame, sea_error *err);
sea_status sea_bake_writer_level(void *w, const sea_bake *b, size_t l, sea_error *err);
sea_status sea_bake_writer_frame_end(sea_bake_writer *w, const sea_bake *b,
                                     const sea_image *view, sea_error *err);

/* After the last frame: the POV-Ray scene (pov), the Blender script
 * (blender) and manifest.json, written last (listing every file then in
 * the directory).  Fills w. */
sea_status sea_bake_writer_finish(sea_bake_writer *w, sea_error *err);

/* What the writer did so far (its own computing and writing: the caller
 * that computes frames elsewhere times that itself).  Reads w. */
void sea_bake_writer_stats(const sea_bake_writer *w, sea_bake_stats *out);

/* After any failure a writer only frees: every other call returns
 * SEA_ERR_DOMAIN. */

/* --------------------------------------------------- the atomic directory */

/* What a bake directory reports besides its errors (sea_bake_dir_hooks). */
typedef enum {
    SEA_BAKE_NOTE_WAITING, /* another bake holds the directory's lock: waiting for it */
    SEA_BAKE_NOTE_REMOVED, /* a killed bake's temporary directory was removed */
    SEA_BAKE_NOTE_RESTORED /* a directory a killed commit had moved aside was put back */
} sea_bake_note;
/* A note: text is one line, without a newline, valid during the call. */
typedef void (*sea_bake_note_fn)(void *ctx, sea_bake_note kind, const char *text);

typedef struct {
    const char *opt;       /* how messages name the directory's origin, "OPT: ..."
                              and "choose another OPT" (a program's "-o"); NULL:
                              "... choose another directory" */
    sea_bake_note_fn note; /* may be NULL */
    /* Asked (with 0) when a wait for the lock is interrupted by a signal: a
     * non-zero answer gives up (SEA_ERR_IO "cannot lock"); may be NULL. */
    sea_progress_fn progress;
    void *ctx;             /* of both */
} sea_bake_dir_hooks;

typedef struct sea_bake_dir sea_bake_dir;

/* Checks path and creates the temporary directory, before any work: its
 * parent must exist and be writable; path must not be '.', '..', '/' nor a
 * mount point; an existing path must be a directory that may be replaced,
 * which is one that is empty or a bake (a manifest.json with "format":
 * "seabake-bake" whose "files" names every other entry, each a regular
 * file): anything else is refused (SEA_ERR_DOMAIN, naming the first entry
 * the manifest does not list), untouched.  A symbolic link to a directory
 * is followed: the directory it points to is replaced, the link kept.
 *
 * Concurrency.  Creating the temporary directory and the commit happen
 * under an flock on PARENT/.BASE.lock (created once, left in place, empty),
 * so two bakes into one path both succeed, the later commit winning (a note
 * SEA_BAKE_NOTE_WAITING while one waits).  Each bake holds an flock on its
 * temporary directory while it lives: under the lock, a BASE.tmp.XXXXXX
 * whose flock can be taken belongs to a bake that was killed and is removed
 * (SEA_BAKE_NOTE_REMOVED), as is any BASE.old.XXXXXX (one exists only
 * inside a commit); if path is missing, its old copy is put back instead
 * (SEA_BAKE_NOTE_RESTORED).  Each only with seabake's marker inside, never
 * on a name alone (src/tempfile.c).
 *
 * hooks (may be NULL) are copied.  On failure *out is NULL and nothing is
 * left behind.  Thread-safe; the directory is the caller's, released with
 * sea_bake_dir_free(). */
sea_status sea_bake_dir_begin(const char *path, const sea_bake_dir_hooks *hooks,
                              sea_bake_dir **out, sea_error *err);
/* The temporary directory the files go into (owned by d; NULL once
 * committed). */
const char *sea_bake_dir_path(const sea_bake_dir *d);
/* Puts the temporary directory in place of path, under the lock: an
 * existing directory, checked again to be replaceable, is moved aside,
 * the new one renamed in, the old one removed.  On failure path is as it
 * was.  Fills d. */
sea_status sea_bake_dir_commit(sea_bake_dir *d, sea_error *err);
/* Removes the temporary directory unless committed, and frees d (NULL: a
 * no-op). */
void sea_bake_dir_free(sea_bake_dir *d);

/* ------------------------------------------------------------ one call */

/* The whole bake of r with options o into path, replaced atomically
 * (sea_bake_dir_begin with no hooks but progress, a sea_bake_writer, every
 * frame, finish, commit): path is as it was on any failure.  The directory
 * is that of `seabake bake SCENE -o PATH` with the same options, byte for
 * byte.  progress as sea_bake_writer_alloc's; stats (may be NULL) gets the
 * writer's.  A caller whose options do not need the sensor's image
 * (sea_bake_writer_wants_view: no exports, or emission space map) may call
 * sea_view_drop_pixels(r) first to save memory.  Reads r. */
sea_status sea_bake_write(const sea_view *r, const sea_bake_options *o, const char *path,
                          sea_progress_fn progress, void *ctx, sea_bake_stats *stats,
                          sea_error *err);

#ifdef __cplusplus
}
#endif
#endif /* SEABAKE_BAKEDIR_H */
