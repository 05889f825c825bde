/* cli.h - the seabake program's command-line layer (src/cli/): option
 * scanning, number and list parsing, the helpers the subcommands share and
 * the subcommands themselves, one file each.  Nothing here is part of
 * libseabake; this is the only code that sees argv, stdout, stderr or an
 * exit code.
 *
 * Errors.  Every helper returns a sea_status and fills a sea_error whose
 * message names the option, the offending text and the allowed range.
 * Usage mistakes are reported as SEA_ERR_PARSE (malformed text, unknown
 * option) or SEA_ERR_DOMAIN (missing, conflicting or out-of-range value);
 * sea_cli_exit_code() turns any status into the program's exit code.
 *
 * Ownership.  Option values point into argv and live as long as it does.
 * A sea_cli_list owns its values; release it with sea_cli_list_free(). */
#ifndef SEABAKE_CLI_H
#define SEABAKE_CLI_H

#include <complex.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <sys/types.h>

#include "exr.h"
#include "seabake.h"

/* ------------------------------------------------------------ exit codes */

typedef enum {
    SEA_CLI_EXIT_OK = 0,
    SEA_CLI_EXIT_RUNTIME = 1, /* SEA_ERR_NUMERIC, SEA_ERR_NOMEM */
    SEA_CLI_EXIT_USAGE = 2,   /* SEA_ERR_DOMAIN, SEA_ERR_PARSE */
    SEA_CLI_EXIT_IO = 3       /* SEA_ERR_IO, including a failed write to stdout */
} sea_cli_exit;

sea_cli_exit sea_cli_exit_code(sea_status status);

/* --------------------------------------------------------------- options */

/* An option takes a value, as "--name value" or "--name=value"; the value
 * may begin with '-' (negative numbers).  A SEA_CLI_OPT_FLAG option takes
 * none ("--quiet").  A SEA_CLI_OPT_SHORT option is written with one dash
 * ("-o FILE", "-o=FILE") and only so.  A repeated option replaces the
 * earlier value, unless it is SEA_CLI_OPT_ACCUMULATE, whose values are all
 * kept in order.  "--help" and "-h" are understood by every subcommand.
 * A SEA_CLI_OPT_POSITIONAL option has no dashed form: its value is a bare
 * argument, the n-th bare argument going to the table's n-th positional
 * option ("seabake render SCENE.ini", "seabake compare A.exr B.exr"); a
 * table holds at most SEA_CLI_POSITIONAL_MAX, and a bare argument beyond
 * them is an error. */
enum { SEA_CLI_POSITIONAL_MAX = 2 };
enum {
    SEA_CLI_OPT_ACCUMULATE = 1u,
    SEA_CLI_OPT_FLAG = 2u,
    SEA_CLI_OPT_SHORT = 4u,
    SEA_CLI_OPT_POSITIONAL = 8u
};

typedef struct {
    const char *name; /* without the leading dashes */
    unsigned flags;
} sea_cli_option;

typedef struct {
    const sea_cli_option *options;
    size_t n_options;
    int argc;
    char **argv; /* the subcommand's arguments, not including its name */
    bool help;   /* --help or -h was given */
} sea_cli_args;

/* Scans argv[0..argc) against the option table.  Fails with SEA_ERR_PARSE
 * on an unknown option, a missing value or a bare argument the table has
 * no positional option for (or a second one). */
sea_status sea_cli_args_parse(sea_cli_args *args, const sea_cli_option *options, size_t n_options,
                              int argc, char **argv, sea_error *err);
/* The last value given for option name, or NULL if it was not given (a
 * flag that was given has a non-NULL value). */
const char *sea_cli_args_get(const sea_cli_args *args, const char *name);
/* Number of times option name was given, and its i-th value (0-based). */
size_t sea_cli_args_count(const sea_cli_args *args, const char *name);
const char *sea_cli_args_nth(const sea_cli_args *args, const char *name, size_t i);

/* ---------------------------------------------------------------- numbers */

/* An interval of allowed values, printed in messages as e.g.
 * "(-90, 90) degrees".  An infinite end is accepted as a value only when
 * it is closed (fetch: [1000, inf]); NaN is never accepted. */
typedef struct {
    double lo, hi;
    bool lo_open, hi_open;
    const char *unit; /* "degrees", "m/s", "" ... */
} sea_cli_range;

/* Parses one decimal number (surrounding blanks allowed, nothing else after
 * it) and checks it against range (NULL: any finite number). */
sea_status sea_cli_parse_number(const char *opt, const char *text, const sea_cli_range *range,
                                double *out, sea_error *err);

/* Exactly n comma-separated numbers, the i-th checked against ranges[i];
 * form names them in messages ("SXX,SYY,SXY"). */
sea_status sea_cli_parse_tuple(const char *opt, const char *text, size_t n,
                               const sea_cli_range *ranges, const char *form, double *out,
                               sea_error *err);

/* A LIST: "A:B:STEP" (A, A+STEP, ... up to B inclusive within
 * SEA_CLI_LIST_END_TOL * STEP; STEP > 0, A <= B), "A,B,C" or one value;
 * every value in range; at most SEA_CLI_LIST_MAX values. */
#define SEA_CLI_LIST_MAX 100000
#define SEA_CLI_LIST_END_TOL 1e-9
typedef struct {
    double *values;
    size_t n;
} sea_cli_list;

sea_status sea_cli_parse_list(const char *opt, const char *text, const sea_cli_range *range,
                              sea_cli_list *out, sea_error *err);
void sea_cli_list_free(sea_cli_list *list);

/* Degrees to radians, exact for multiples of 180 (so that theta = -30,
 * phi = 0 and theta = 30, phi = 180 fold to the same direction). */
double sea_cli_radians(double degrees);

/* ------------------------------------------------------------ subcommands */

typedef struct {
    const char *name;
    const char *summary; /* one line for the general usage */
    const char *help;    /* full usage text of the subcommand */
    const sea_cli_option *options;
    size_t n_options;
    /* Writes CSV to out.  A failed write is reported as SEA_ERR_IO. */
    sea_status (*run)(const sea_cli_args *args, FILE *out, sea_error *err);
} sea_cli_command;

/* The subcommands, one a file (emissivity.c holds energy too); main.c
 * lists them in the order of the general usage. */
extern const sea_cli_command sea_cli_cmd_spectrum;     /* spectrum.c */
extern const sea_cli_command sea_cli_cmd_emissivity;   /* emissivity.c */
extern const sea_cli_command sea_cli_cmd_reflectivity; /* reflectivity.c */
extern const sea_cli_command sea_cli_cmd_energy;       /* emissivity.c */
extern const sea_cli_command sea_cli_cmd_slopes;       /* slopes.c */
extern const sea_cli_command sea_cli_cmd_convergence;  /* convergence.c */
extern const sea_cli_command sea_cli_cmd_bench;        /* bench.c */
extern const sea_cli_command sea_cli_cmd_render;       /* render.c */
extern const sea_cli_command sea_cli_cmd_bake;         /* bake.c */
extern const sea_cli_command sea_cli_cmd_compare;      /* compare.c */
extern const sea_cli_command sea_cli_cmd_convert;      /* convert.c */

/* Number of elements of an array (option tables). */
#define SEA_CLI_COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* ------------------------------------- option accessors and helpers (args.c) */

/* Option `name` was given. */
bool sea_cli_given(const sea_cli_args *args, const char *name);
/* SEA_ERR_DOMAIN "missing --name<why>" unless option name was given. */
sea_status sea_cli_require(const sea_cli_args *args, const char *name, const char *why,
                           sea_error *err);
/* The [model] keys that render and bake take on the command line:
 * --tolerance T, range (0, 0.1] (NAN when absent), --reflections auto or N,
 * 1 to SEA_REFLECTIONS_MAX (-1 when absent), and --reference.  Parsed
 * before the scene (a typing mistake is reported first), applied after it
 * by sea_cli_apply_model. */
typedef struct {
    double tolerance;
    long reflections; /* SEA_REFLECTIONS_AUTO, 1 .. 3, or -1: the scene's */
    int shadowing; /* a sea_shadowing, or -1: the scene's */
    long scales;   /* 1 or 2, or 0: the scene's */
    int emissivity; /* a sea_emis_method (--emissivity), or -1: the scene's */
    bool reference;
} sea_cli_model;
/* --reflections auto|N (def when absent). */
sea_status sea_cli_opt_reflections(const sea_cli_args *args, long def, long *out, sea_error *err);
sea_status sea_cli_opt_model(const sea_cli_args *args, sea_cli_model *out, sea_error *err);
/* The positional SCENE.ini of render and bake: present and not empty. */
sea_status sea_cli_scene_arg(const sea_cli_args *args, const char **path, sea_error *err);
void sea_cli_apply_model(const sea_cli_model *m, sea_scene *sc);
/* The option's number checked against range, or def when it is absent. */
sea_status sea_cli_opt_number(const sea_cli_args *args, const char *name,
                              const sea_cli_range *range, double def, double *out, sea_error *err);
/* The option's LIST (see sea_cli_parse_list), or the LIST text def. */
sea_status sea_cli_opt_list(const sea_cli_args *args, const char *name, const sea_cli_range *range,
                            const char *def, sea_cli_list *out, sea_error *err);
/* An integer option in [lo, hi], or def when it is absent. */
sea_status sea_cli_opt_integer(const sea_cli_args *args, const char *name, long lo, long hi,
                               long def, long *out, sea_error *err);

/* "--frames A:B": integers in [0, SEA_CLI_FRAME_MAX], A <= B, at most
 * SEA_CLI_FRAMES_MAX frames (as many as a LIST holds). */
#define SEA_CLI_FRAME_MAX 999999
#define SEA_CLI_FRAMES_MAX SEA_CLI_LIST_MAX
sea_status sea_cli_parse_frames(const char *text, long *a, long *b, sea_error *err);

/* The frame options of render and bake: --frames A:B (*framed set when
 * given) and --frame-rate HZ (> 0, default SEA_CLI_FRAME_RATE_DEFAULT, only
 * with --frames). */
#define SEA_CLI_FRAME_RATE_DEFAULT 25.0
/* Frame numbers in the names of render's and bake's files carry at least
 * this many digits, as Blender's "####". */
#define SEA_CLI_FRAME_DIGITS 4
/* The range of the PNG previews of render and bake: the 0.5 % and 99.5 %
 * quantiles, so that a few glint pixels do not flatten the rest. */
#define SEA_CLI_PNG_CLIP 0.005
/* render --png-range LO:HI: kelvin, 0 < LO < HI <= this. */
#define SEA_CLI_PNG_RANGE_MAX 10000.0
sea_status sea_cli_opt_frames(const sea_cli_args *args, bool *framed, long *a, long *b,
                              double *rate, sea_error *err);
/* SEA_ERR_DOMAIN naming --frames and --frame-rate unless every frame's
 * time, time + f / rate for f in [a, b], lies within SEA_TIME_MAX (a rate
 * of 4.9e-324 Hz put frame 1 at an infinite time after frame 0 was
 * written); SEA_OK without --frames.  Checked once the scene's time is
 * known, before any work. */
sea_status sea_cli_check_frame_times(double time, bool framed, long a, long b, double rate,
                                     sea_error *err);

/* The ranges of options that several subcommands take. */
extern const sea_cli_range SEA_CLI_RANGE_WIND;         /* --wind, m/s */
extern const sea_cli_range SEA_CLI_RANGE_FETCH;        /* --fetch, m */
extern const sea_cli_range SEA_CLI_RANGE_AZIMUTH;      /* --wind-dir, --phi, degrees */
extern const sea_cli_range SEA_CLI_RANGE_FACET;        /* --facet, m, [0, 1e6] */
extern const sea_cli_range SEA_CLI_RANGE_DIRECTION[2]; /* THETA,PHI pairs, degrees */

/* Largest sub-facet exponent (2^20 sub-facets per side), as the library. */
#define SEA_CLI_N_MAX 20

/* --seed: a decimal unsigned integer, read exactly (default 1). */
sea_status sea_cli_opt_seed(const sea_cli_args *args, unsigned long *out, sea_error *err);
/* --method of the wave subcommands (default variable-step) and --n, which
 * only variable-step-2n takes and requires (0..SEA_CLI_N_MAX). */
sea_status sea_cli_opt_facet_method(const sea_cli_args *args, sea_facet_method *method, int *n,
                                    sea_error *err);
/* Sea state from --wind (required, one value), --fetch, --wind-dir. */
sea_status sea_cli_opt_sea_state(const sea_cli_args *args, double *wind, double *fetch,
                                 double *wind_dir_deg, sea_error *err);
/* --threads N, 1..sea_cli_threads_max(): sets the OpenMP thread count
 * (bench, render).  The cap is SEA_CLI_THREADS_PER_CPU x the online CPUs,
 * at most SEA_CLI_THREADS_LIMIT. */
#define SEA_CLI_THREADS_PER_CPU 4
#define SEA_CLI_THREADS_LIMIT 1024
long sea_cli_threads_max(void);
sea_status sea_cli_opt_threads(const sea_cli_args *args, sea_error *err);
/* The OpenMP team of this process, started before any work: the threads
 * libgomp will start (omp_get_max_threads, after --threads) are first
 * created and joined as a probe, so that a failure (a low ulimit -v, which
 * libgomp would report by printing "Thread creation failed" and exiting
 * mid-work) is seabake's own SEA_ERR_NOMEM naming the count and the
 * remedy; then the team is made by an empty parallel region, before any
 * file or directory is created. */
sea_status sea_cli_threads_start(sea_error *err);
/* --format float|half (default float) and --compression none|zip|piz
 * (default zip) of render and bake. */
sea_status sea_cli_opt_exr(const sea_cli_args *args, sea_exr_options *out, sea_error *err);
/* The scene file of render and bake with its --set SECTION.KEY=VALUE
 * overrides, in order (sea_scene_load_with). */
sea_status sea_cli_load_scene(const sea_cli_args *args, const char *path, sea_scene *sc,
                              sea_error *err);
/* The smallest power of two >= x (x >= 1, finite). */
double sea_cli_pow2_ceil(double x);

/* --------------------------------------------------------- files (files.c) */

/* s ends with suffix (ASCII case ignored) and is longer than it. */
bool sea_cli_has_suffix(const char *s, const char *suffix);
/* "dir/name", malloc'ed (NULL when out of memory). */
char *sea_cli_path_join(const char *dir, const char *name);
/* The directory part of path ("." for a bare name), malloc'ed. */
char *sea_cli_parent_dir(const char *path);
/* One rule for every output: the output (file or directory) is created,
 * its parent directory must exist.  SEA_ERR_IO, before any computation,
 * "OPT: the directory 'P' does not exist" when it does not, or when it is
 * not a directory we can create files in. */
sea_status sea_cli_check_parent_writable(const char *opt, const char *path, sea_error *err);
/* SEA_ERR_IO "cannot write to standard output" when a write to out failed. */
sea_status sea_cli_check_written(FILE *out, sea_error *err);

/* A file written into seabake's marked temporary "<path>.tmp.XXXXXX/"
 * next to its destination (as the EXR writer does; src/tempfile.c) and
 * renamed over it only when complete. */
struct sea_temp_file;
typedef struct {
    const char *path;
    struct sea_temp_file *tmp;
    FILE *f;
} sea_cli_atomic_file;
/* Creates the temporary file (mode 0666 less the umask); opt names the
 * option in messages. */
sea_status sea_cli_atomic_open(sea_cli_atomic_file *af, const char *opt, const char *path,
                               sea_error *err);
/* Removes the temporary file; nothing is left at the destination.  Safe on
 * a file already committed or aborted, or one that {NULL, NULL, NULL}
 * initialised. */
void sea_cli_atomic_abort(sea_cli_atomic_file *af);
/* Flushes, syncs and renames the file to its destination. */
sea_status sea_cli_atomic_commit(sea_cli_atomic_file *af, const char *opt, sea_error *err);
/* Removes the file temporaries (above) that runs killed before their
 * commit left beside the outputs STEM* (STEM itself, or STEM then '.' or
 * '_': frame numbers, AOVs, extensions), each only with seabake's marker
 * inside and its maker's flock gone (src/tempfile.c), never on a name
 * alone; notes each on standard error as "WHO: removed 'PATH', left by a
 * WHO that was killed".  Returns how many. */
size_t sea_cli_clean_stale_files(const char *who, const char *stem);
/* Creates dir unless it exists (its parent must: nothing is created on
 * the way), then checks that it is a writable directory; *created tells
 * whether this call made it (the caller removes it on failure). */
sea_status sea_cli_make_dir(const char *opt, const char *dir, bool *created, sea_error *err);


/* ------------------------------------------------ signals (progress.c) */

/* SIGINT, SIGTERM and SIGHUP during render and bake: sea_cli_signals_catch
 * installs a handler that records the signal (a signal ignored on entry,
 * as under nohup, stays ignored); the work stops at the next progress
 * callback (the library then fails with SEA_ERR_CANCELLED within a row) or
 * file; the caller cleans up, restores the handlers and dies of the signal
 * with sea_cli_die_of_signal. */
void sea_cli_signals_catch(void);
void sea_cli_signals_restore(void);
/* The signal received since sea_cli_signals_catch, 0 none. */
int sea_cli_interrupted(void);
/* Prints "seabake: error: MSG" and re-raises the recorded signal (the
 * handlers restored first); returns only if that did not end the process. */
void sea_cli_die_of_signal(const char *msg);

/* ------------------------------------------------------------ MPI (mpi.c) */

/* render and bake share their work among the ranks of an MPI launch
 * (seabake(1), PARALLEL RUNS WITH MPI).  sea_cli_mpi_init starts MPI only
 * when the environment shows a launcher (OMPI_COMM_WORLD_SIZE, PMIX_RANK,
 * PMI_RANK), so a plain run never touches MPI; built without MPI it fails
 * (SEA_ERR_DOMAIN) when the launch announces more than one rank
 * (OMPI_COMM_WORLD_SIZE, PMI_SIZE), and is otherwise rank 0 of 1, where
 * every call below is a no-op (send and receive are never reached).  The
 * collective calls (agree, minmax, sum, bcast) must be made by every rank
 * in the same order.  A failed MPI call aborts the job (MPI's default
 * handler).  Only rank 0 reports errors (main.c): a rank's failure reaches
 * it through sea_cli_mpi_agree. */
sea_status sea_cli_mpi_init(int *argc, char ***argv, sea_error *err);
/* A barrier (every rank has cleaned up) and MPI_Finalize; no-op unless
 * MPI was started. */
void sea_cli_mpi_finalize(void);
int sea_cli_mpi_rank(void);
int sea_cli_mpi_size(void);
/* Collective: SEA_OK when st is SEA_OK on every rank; otherwise the status
 * and error of the failing rank with the smallest key (ties: the lowest
 * rank), copied into every rank's err, and that key in *failed_key (may be
 * NULL; LONG_MAX when none failed).  key < LONG_MAX. */
sea_status sea_cli_mpi_agree(sea_status st, long key, long *failed_key, sea_error *err);
/* Collective: *lo the smallest, *hi the largest over the ranks. */
void sea_cli_mpi_minmax(double *lo, double *hi);
/* Collective: *v the sum over the ranks. */
void sea_cli_mpi_sum(size_t *v);
/* Collective: bytes of buf from rank root to every rank. */
void sea_cli_mpi_bcast(void *buf, size_t bytes, int root);
/* How many of items 0 .. n-1 are rank k's when rank k takes k, k + size,
 * ... (render's rows of one frame, bake's texel rows). */
size_t sea_cli_mpi_share(size_t n, int k, int size);
/* Blocking point-to-point bytes (any size: sent in pieces). */
void sea_cli_mpi_send(const void *buf, size_t bytes, int dest, int tag);
void sea_cli_mpi_recv(void *buf, size_t bytes, int source, int tag);
/* Sends that do not wait for the receiver: each buffer (malloc'ed) belongs
 * to the queue from sea_cli_mpi_queue_send, which frees it once it is sent
 * (at the latest in sea_cli_mpi_queue_wait).  A sender that must not stall
 * on a busy receiver queues a frame's data, computes on, and waits later.
 * sea_cli_mpi_queue_send fails only for memory (SEA_ERR_NOMEM, buf freed). */
typedef struct {
    void **bufs;    /* one per request; NULL past a buffer's first piece */
    void *requests; /* MPI_Request[cap] */
    size_t n, cap;
} sea_cli_mpi_queue;
void sea_cli_mpi_queue_init(sea_cli_mpi_queue *q);
sea_status sea_cli_mpi_queue_send(sea_cli_mpi_queue *q, void *buf, size_t bytes, int dest,
                                  int tag, sea_error *err);
/* Waits for every queued send, frees the buffers; the queue stays usable. */
void sea_cli_mpi_queue_wait(sea_cli_mpi_queue *q);
/* Waits, then releases the queue's arrays. */
void sea_cli_mpi_queue_free(sea_cli_mpi_queue *q);
/* The last resort, where the ranks' messages can no longer be matched:
 * prints "seabake: error: MSG (rank k of N: the job is aborted)" and ends
 * every rank (MPI_Abort, exit status 1). */
void sea_cli_mpi_abort(const sea_error *err);
/* Receives and discards a message of bytes sent by sea_cli_mpi_send (when
 * no memory is left even for that, aborts the job: the last resort). */
void sea_cli_mpi_drop(size_t bytes, int source, int tag);

/* --------------------------------------------------- progress (progress.c) */

/* Monotonic wall-clock seconds. */
double sea_cli_seconds(void);

/* A progress bar on standard error (callers show it only on a terminal):
 * "WHAT: [####....]  42% frame 2/5, 1 min 10 s left", redrawn when the
 * percentage changes; the time left is the elapsed time's share of what
 * remains, once a second and a hundredth of the work have passed.
 * index: the frame being done, of count. */
typedef struct {
    const char *what;
    size_t index, count;
    int shown;    /* last percentage printed, -1 none */
    double start; /* sea_cli_seconds() at the first call; 0 before it */
} sea_cli_progress;
/* A sea_progress_fn: fraction of the current frame done; ctx a
 * sea_cli_progress; stops the work once a signal was caught
 * (sea_cli_signals_catch). */
int sea_cli_progress_bar(void *ctx, double fraction);
/* The same where the bar may be off (not a terminal, --quiet): the bar when
 * on; either way non-zero once a signal came (sea_cli_interrupted). */
int sea_cli_progress_if(sea_cli_progress *p, bool on, double fraction);
/* Ends the bar's line (a newline) if anything was drawn. */
void sea_cli_progress_end(sea_cli_progress *p);

/* ---------------------------------------------------- --explain (explain.c) */

/* --explain (render, bake; lines start "WHAT: "): the levels, windows, sub-facets, emissivity
 * rule, wave components, fallbacks and spectral samples that
 * sea_view_alloc chose for the scene file scene_path, and why, on
 * standard error. */
void sea_cli_explain(const char *what, const char *scene_path, const sea_view *r);

/* ------------------------------------------------------ charts (chart.c) */

/* A gnuplot script built in memory.  sea_cli_gnuplot_begin opens it with
 * the lines drawing a width x height PNG (pngcairo if gnuplot has it, else
 * png: encoding, terminal) and returns the stream to write the rest to,
 * NULL when out of memory; sea_cli_gnuplot_end closes it and returns the
 * text (malloc'ed), NULL on failure.  The script names no output file: the
 * PNG goes to gnuplot's standard output, which the caller opens, so that
 * no path (nor any other user string) ever becomes gnuplot syntax: gnuplot
 * expands backquotes and has system(). */
typedef struct {
    FILE *f;
    char *text;
    size_t len;
} sea_cli_script;
FILE *sea_cli_gnuplot_begin(sea_cli_script *s, int width, int height);
char *sea_cli_gnuplot_end(sea_cli_script *s);

/* A chart's gnuplot script, drawing to its standard output. */
typedef char *(*sea_cli_chart_script_fn)(const void *ctx);
/* The chart png drawn by gnuplot into a temporary file beside it, which
 * the caller puts in place with sea_cli_atomic_commit (or removes with
 * sea_cli_atomic_abort) together with its other outputs: nothing is left
 * on a failure.  *absent is set (SEA_ERR_NUMERIC "gnuplot not found") when
 * there is no gnuplot to run. */
sea_status sea_cli_draw_chart(const char *png, sea_cli_chart_script_fn script_fn, const void *ctx,
                              sea_cli_atomic_file *af, bool *absent, sea_error *err);

/* ------------------------------ inputs of the physics subcommands (inputs.c) */

/* What every optics subcommand computes from: the water's complex index
 * at the wavelength and the facet's slope statistics. */
typedef struct {
    double wavelength_um;
    double complex N;
    sea_slope_stats stats;
} sea_cli_sea;

/* The options of the water and of the slope statistics (sea_cli_sea_inputs). */
#define SEA_CLI_SEA_OPTIONS \
    {"wavelength", 0}, {"water", 0}, {"salinity", 0}, {"index", 0}, {"mean", 0}, {"wind", 0}, \
        {"fetch", 0}, {"wind-dir", 0}, {"facet", 0}, \
    { \
        "cov", 0 \
    }

/* Help text shared by the physics subcommands. */
#define SEA_CLI_HELP_LIST \
    "LIST is A:B:STEP (A to B inclusive, STEP > 0), A,B,C or one value;\n" \
    "at most 100000 values.  Options take --opt VALUE or --opt=VALUE.\n"

#define SEA_CLI_HELP_WATER \
    "\nWater:\n" \
    "  --wavelength UM     wavelength, um, > 0 (required); inside the band of the\n" \
    "                      water table (about 2.4-15.5 um) unless --index is given\n" \
    "  --water TABLE       hale-querry (default), segelstein, or a CSV file with\n" \
    "                      columns wavelength_um,n,k\n" \
    "  --salinity S        salinity, g/kg, [0, 45]; default 35\n" \
    "  --index N,K         refractive index n + i k instead of a table, n in\n" \
    "                      [1, 3], k in [0, 10] (as a water table's); not with\n" \
    "                      --water or --salinity\n"

#define SEA_CLI_HELP_SLOPE_STATS \
    "\nSlope statistics:\n" \
    "  --mean MX,MY        mean slope of the facet, each in [-5, 5]; default 0,0\n" \
    "  --wind U            wind speed at 10 m, m/s, [0.5, 40]; required unless --cov\n" \
    "  --fetch F           fetch, m, [1000, inf]; default inf (fully developed)\n" \
    "  --wind-dir DEG      wind azimuth from the x axis, degrees; default 0\n" \
    "  --facet L           facet size, m, [0, 1e6]: covariance of the waves\n" \
    "                      shorter than L (k > pi/L); default 0 = all waves\n" \
    "  --cov SXX,SYY,SXY   slope covariance given directly: SXX, SYY in [0, 10],\n" \
    "                      SXY^2 <= SXX*SYY; not with --wind, --fetch, --wind-dir\n" \
    "                      or --facet\n"

/* Refuses name2 when name1 was given. */
sea_status sea_cli_exclusive(const sea_cli_args *args, const char *name1, const char *name2,
                             sea_error *err);
/* --emissivity of the optics (the scene file's [model] emissivity): auto
 * (default), fast or full. */
#define SEA_CLI_HELP_SHADOWING \
    "  --shadowing S       correlated (default: a facet's chance to be seen\n" \
    "                      depends on its slope; within 1.1e-3 of ray tracing\n" \
    "                      to 85 deg) or smith (the paper's Eq 9c-9e: up to\n" \
    "                      12e-3 low at 75-85 deg)\n"
/* --shadowing smith|correlated, or def when absent. */
sea_status sea_cli_opt_shadowing(const sea_cli_args *args, sea_shadowing def, sea_shadowing *out,
                                 sea_error *err);
sea_status sea_cli_opt_emissivity(const sea_cli_args *args, sea_emis_method *out,
                                  sea_error *err);
/* Sea state from --wind, --fetch, --wind-dir (--wind must be given). */
sea_status sea_cli_sea_state(const sea_cli_args *args, sea_spectrum *spec, double *wind,
                             double *fetch, sea_error *err);
/* Covariance of the waves shorter than a facet of size L (0: all waves). */
sea_status sea_cli_facet_cov(const sea_spectrum *spec, double facet, double *kc, sea_cov2 *cov,
                             sea_error *err);
/* Parses every input of an optics subcommand; the water table is read last
 * so that a typing mistake is reported before any file is opened. */
sea_status sea_cli_sea_inputs(const sea_cli_args *args, sea_cli_sea *sea, sea_error *err);
/* mx,my,sxx,syy,sxy of the sea, without a newline. */
void sea_cli_print_sea_columns(FILE *out, const sea_cli_sea *sea);
/* SEA_ERR_NUMERIC: what at (theta, phi) is not finite. */
sea_status sea_cli_not_finite(const char *what, double theta_deg, double phi_deg, sea_error *err);
/* --theta (required) and --phi (default 0) as lists. */
sea_status sea_cli_direction_grid(const sea_cli_args *args, sea_cli_list *theta,
                                  sea_cli_list *phi, sea_error *err);

/* The complex refractive index of the water at --wavelength (required, um)
 * from --water (table name or CSV file, default hale-querry), --salinity
 * (default 35 g/kg) and, if the subcommand has it, --index.  The same
 * checks and messages as the emissivity subcommand; SEA_ERR_IO for an
 * unreadable table. */
sea_status sea_cli_water(const sea_cli_args *args, double *wavelength_um, double complex *N,
                         sea_error *err);

/* ---------------------------------------------- bench (bench_optics.c) */

/* One row of bench.csv: a time per call and, where there is a reference,
 * the largest and RMS absolute error against it over the conditions (NAN:
 * nothing to compare).  settings and conditions hold no commas. */
typedef struct {
    const char *quantity; /* waves, emissivity, reflectivity, energy */
    char method[24];
    char settings[128];
    double seconds, max_err, rms_err;
    char conditions[224];
} sea_cli_bench_row;

/* The figures the bench's summary quotes. */
typedef struct {
    size_t conditions;
    double full_seconds, auto_seconds, auto_max, auto_rms, fast_seconds, fast_max, fast_rms;
    double corr_seconds, corr_max; /* auto with correlated shadowing, against its reference */
} sea_cli_bench_summary;

/* Emissivity (reference, Eq 12, default, fixed rules), reflectivity and
 * energy rows over the fixed condition set (smaller with quick): a
 * malloc'ed array of *nrows rows. */
sea_status sea_cli_bench_optics(bool quick, sea_cli_bench_row **rows, size_t *nrows,
                                sea_cli_bench_summary *sum, sea_error *err);
/* Whole-image rows (quantity "image"): the scenes of examples/fig7-9.ini
 * scaled down to 96 x 96 pixels (32 x 32 with quick), geometry kept; per
 * scene a reference row (variable-step-2n with sub-facets down to L0 on
 * every level, i.e. one-meter's statistics on the same sinusoids, and the
 * adaptive Eq 7) and rows for variable-step, variable-step-2n n = 1, 2, 3
 * and one-meter (FFT waves: another realisation of the same sea) at the
 * default tolerance and emissivity: seconds per image (prepare and frame,
 * threads threads) and max/RMS relative radiance error per pixel. */
sea_status sea_cli_bench_images(bool quick, int threads, sea_cli_bench_row **rows,
                                size_t *nrows, sea_error *err);
/* gnuplot script of the image rows: seconds per image against the max and
 * RMS error, one colour per scene.  malloc'ed; NULL when out of memory. */
char *sea_cli_bench_image_chart_script(const sea_cli_bench_row *rows, size_t nrows);
/* The row is a reference (its errors are 0 by definition). */
bool sea_cli_bench_is_reference(const sea_cli_bench_row *r);
/* gnuplot script of the emissivity rows: log-log seconds per call against
 * the max error, one labelled point per setting, the Pareto front as a
 * line.  malloc'ed; NULL when out of memory. */
char *sea_cli_bench_chart_script(const sea_cli_bench_row *rows, size_t nrows);

#endif /* SEABAKE_CLI_H */
