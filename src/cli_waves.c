/* cli_waves.c - the large-scale wave subcommands of seabake:
 *
 * - slopes: the facet slope moments of one seeded realisation of the waves
 *   (Variable Step, Variable Step L/2^n, 1 Meter Step; seabake-model(7)) over
 *   a rectangle of facets centred on the origin, as CSV or EXR;
 * - convergence: the paper's Fig. 5-6 study, high-resolution emissivity and
 *   reflectivity of growing facets against the low-resolution values, with a
 *   CSV table and a gnuplot chart;
 * - bench: speed of the wave generators, and speed against accuracy of the
 *   optics (cli_bench.c).
 *
 * Every option is validated before anything is allocated or written; sizes
 * that cannot fit in memory are refused with sea_check_size.  Files are
 * written under a temporary name in their directory and renamed when
 * complete, so a failure leaves nothing behind. */
#include <complex.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli.h"
#include "exr.h"

extern char **environ;

/* ------------------------------------------------------------ constants */

/* Facets per side of slopes: also the largest EXR image side. */
#define SEA_CLI_SIDE_MAX 65536
/* Largest facet and finest size: far beyond convergence to low resolution. */
#define SEA_CLI_LENGTH_MAX 1e6
/* Largest FFT patch the library plans (sea_waves_params.fft_size). */
#define SEA_CLI_FFT_MAX 16384
/* Largest sub-facet exponent (2^20 sub-facets per side), as the library. */
#define SEA_CLI_N_MAX 20
/* The convergence sweep: L = 2^(x-1) m, x = 1..11 (1 m to 1024 m), as in
 * the paper's Fig. 5-6; facets per side; the 1 Meter Step FFT patch. */
#define SEA_CLI_CONV_X_MAX 11
#define SEA_CLI_CONV_FACETS_MAX 256
#define SEA_CLI_CONV_FACETS_DEFAULT 16
#define SEA_CLI_CONV_FFT_MAX 4096
static const double SEA_CLI_CONV_TOL_DEFAULT = 1e-3;
/* The paper's finest resolution (MATISSE): sub-facets of at least 1 m. */
static const double SEA_CLI_CONV_FINEST = 1.0;
/* Relative slack when comparing lengths, so that sizes typed as decimals
 * (0.1 x 2^n) are not refused for rounding: a ratio is a power of two
 * within it, as in the library's own test (sea_facet_method_n). */
static const double SEA_CLI_LENGTH_REL_TOL = 1e-9;

/* Exit status of a child whose exec failed (glibc's posix_spawn, shells). */
enum { SEA_CLI_EXEC_FAILED = 127 };

/* The bench: U10 = 10 m/s, facets of 4 m. */
static const double SEA_CLI_BENCH_WIND = 10.0;
static const double SEA_CLI_BENCH_FACET = 4.0;
/* Side of the sub-rectangle sampled with the converted sinusoids. */
#define SEA_CLI_BENCH_SUB 32

static const sea_cli_range SEA_CLI_RANGE_WIND = {SEA_WIND_MIN, SEA_WIND_MAX, false, false, "m/s"};
static const sea_cli_range SEA_CLI_RANGE_FETCH = {SEA_FETCH_MIN, INFINITY, false, false, "m"};
static const sea_cli_range SEA_CLI_RANGE_AZIMUTH = {-INFINITY, INFINITY, true, true, "degrees"};
static const sea_cli_range SEA_CLI_RANGE_LENGTH = {0.0, SEA_CLI_LENGTH_MAX, true, false, "m"};
static const sea_cli_range SEA_CLI_RANGE_TIME = {-INFINITY, INFINITY, true, true, "s"};
static const sea_cli_range SEA_CLI_RANGE_LOOP = {0.0, INFINITY, false, true, "s"};
static const sea_cli_range SEA_CLI_RANGE_ZENITH = {0.0, 90.0, false, true, "degrees"};
static const sea_cli_range SEA_CLI_RANGE_TOL = {0.0, 1.0, true, true, ""};
static const sea_cli_range SEA_CLI_RANGE_SIZE[2] = {
    {1.0, SEA_CLI_SIDE_MAX, false, false, "facets"},
    {1.0, SEA_CLI_SIDE_MAX, false, false, "facets"}};
/* A THETA,PHI pair: signed zenith and azimuth. */
static const sea_cli_range SEA_CLI_RANGE_DIRECTION[2] = {
    {-90.0, 90.0, true, true, "degrees"},
    {-INFINITY, INFINITY, true, true, "degrees"}};

/* ------------------------------------------------------------ help texts */

static const char SEA_CLI_HELP_SLOPES[] =
    "Usage: seabake slopes --wind U --facet L [OPTIONS]\n"
    "\n"
    "Slope moments of a rectangle of facets of one seeded realisation of the\n"
    "large-scale waves (Variable Step, Variable Step L/2^n, 1 Meter Step): the\n"
    "mean slope, the raw second moments (sub-facet covariance included) and the\n"
    "mean height of each facet.  NX x NY facets of size L centred on the origin;\n"
    "rows j outer, i inner.  A one-line summary goes to standard error.\n"
    "\n"
    "Sea state:\n"
    "  --wind U            wind speed at 10 m, m/s, [0.5, 40] (required)\n"
    "  --fetch F           fetch, m, [1000, inf]; default inf (fully developed)\n"
    "  --wind-dir DEG      wind azimuth from the x axis, degrees; default 0\n"
    "\n"
    "Facets:\n"
    "  --facet L           facet size, m, (0, 1e6] (required)\n"
    "  --size NX,NY        facets along x and y, each 1..65536; default 64,64\n"
    "  --method M          variable-step (default), variable-step-2n or one-meter\n"
    "  --n N               sub-facet exponent of variable-step-2n, 0..20: 2^N x 2^N\n"
    "                      sub-facets of L/2^N (required with it, refused otherwise)\n"
    "\n"
    "Waves:\n"
    "  --seed S            unsigned integer, the same seed gives the same sea;\n"
    "                      default 1\n"
    "  --time T            time, s; default 0 (waves travel downwind)\n"
    "  --finest L0         finest facet size of the wave plan, m, (0, 1e6];\n"
    "                      default 1\n"
    "  --generator G       sinusoids or fft; default fft for one-meter, sinusoids\n"
    "                      otherwise.  The FFT patch is the smallest power of two\n"
    "                      covering the rectangle (at most 16384 x L0), so it\n"
    "                      never repeats\n"
    "  --loop-period T     s, >= 0: frequencies rounded to multiples of 2 pi/T, so\n"
    "                      the sea repeats after T; default 0 (no loop)\n"
    "\n"
    "Output:\n"
    "  -o FILE             FILE.csv or FILE.exr, written atomically; default CSV\n"
    "                      on standard output\n"
    "  --quiet             no summary on standard error\n"
    "\n"
    "Columns: i,j,x_m,y_m,mx,my,mxx,mxy,myy,h\n"
    "  i, j: facet indices (facet (0,0) has its lower-left corner at the origin);\n"
    "  x_m, y_m: facet centre, m; mx, my: mean slope; mxx = mx^2 + Cxx,\n"
    "  mxy = mx my + Cxy, myy = my^2 + Cyy; h: mean height of the generated\n"
    "  waves, m.  EXR: channels mx, my, mxx, mxy, myy, h (FLOAT, ZIP), image\n"
    "  row 0 = the largest j (north up), attributes seabake:*.\n";

static const char SEA_CLI_HELP_CONVERGENCE[] =
    "Usage: seabake convergence --wavelength UM --wind LIST --theta DEG [OPTIONS]\n"
    "\n"
    "Convergence of the high-resolution effective emissivity and reflectivity to\n"
    "the low-resolution ones as the facet grows (the paper's Fig. 5-6): for each\n"
    "wind and each size L = 2^(x-1) m, x = 1..11, K x K facets centred on the\n"
    "origin of one seeded sea (the same seed for every wind).  Writes\n"
    "DIR/convergence.csv and DIR/convergence.png (gnuplot) and prints a table and\n"
    "the converged size per wind.\n"
    "\n"
    "Geometry:\n"
    "  --theta DEG         observation zenith, degrees, [0, 90) (required)\n"
    "  --phi DEG           observation azimuth, degrees; default 0\n"
    "  --inc THETA,PHI     source direction, signed zenith in (-90, 90) and\n"
    "                      azimuth; default -THETA,PHI (specular)\n"
    "\n"
    "Sea:\n"
    "  --wind LIST         wind speeds at 10 m, m/s, [0.5, 40] (required)\n"
    "  --fetch F           fetch, m, [1000, inf]; default inf (fully developed)\n"
    "  --wind-dir DEG      wind azimuth from the x axis, degrees; default 0\n"
    "  --seed S            unsigned integer; default 1\n"
    "  --method M          variable-step (default), variable-step-2n or one-meter\n"
    "                      (FFT patch of min(4096, K L) m per size)\n"
    "  --n N               sub-facet exponent of variable-step-2n, 0..20; sub-facets\n"
    "                      stay >= 1 m (n = min(N, x - 1))\n"
    "  --facets K          facets per side, 1..256; default 16\n"
    "  --sizes X1:X2       sweep x = X1..X2 only, 1 <= X1 <= X2 <= 11; default 1:11\n"
    "  --tolerance T       relative, (0, 1); default 0.001: converged when every\n"
    "                      larger size has max |HR - LR| <= T |LR|\n"
    "\n"
    "Water:\n"
    "  --wavelength UM     wavelength, um, > 0 (required), inside the water table\n"
    "  --water TABLE       hale-querry (default), segelstein, or a CSV file with\n"
    "                      columns wavelength_um,n,k\n"
    "  --salinity S        salinity, g/kg, [0, 45]; default 35\n"
    "\n"
    "Output:\n"
    "  -o DIR              output directory, created if missing; default .\n"
    "  --quiet             no progress line on standard error\n"
    "\n"
    "LIST is A:B:STEP, A,B,C or one value.\n"
    "CSV columns: wind_m_s,x,L_m,facets,n,emis_lr,emis_origin,emis_mean,\n"
    "  emis_rms_dev,emis_max_dev,refl_lr,refl_origin,refl_mean,refl_rms_dev,\n"
    "  refl_max_dev,var_mx,var_my (dev = HR - LR over the facets; origin = the\n"
    "  facet with its lower-left corner at the origin; facets = per side).\n";

static const char SEA_CLI_HELP_BENCH[] =
    "Usage: seabake bench [--quick] [-o DIR] [--threads N]\n"
    "\n"
    "Speed of the large-scale wave generators (best of 3 runs, 1 with --quick):\n"
    "facets per second of each method at U10 = 10 m/s, L = 4 m, and the cost of\n"
    "an FFT plan's waves summed as sinusoids against the FFT itself.  Then the\n"
    "optics on one thread over a fixed set of conditions (896; 56 with --quick):\n"
    "seconds per call and max/RMS error against the adaptive Eq 7 reference of\n"
    "the emissivity by full, fast (Eq 12), auto (the default) and fixed product\n"
    "rules GL 8..128 x GH 4..16, of the reflectivity and of the energy balance.\n"
    "Then whole images of the scenes of examples/fig7-9.ini scaled down to 96 x 96\n"
    "pixels (32 x 32 with --quick): seconds per image and max/RMS relative radiance\n"
    "error against a reference (sub-facets down to L0 on the same waves and the\n"
    "adaptive Eq 7) of variable-step, variable-step-2n n = 1, 2, 3 and one-meter.\n"
    "Prints tables and writes DIR/bench.csv, DIR/speed_accuracy.png (optics) and\n"
    "DIR/image_speed_accuracy.png (images) with gnuplot.\n"
    "\n"
    "  --quick             smaller sizes and condition set, fewer runs\n"
    "  -o DIR              output directory, created if missing; default .\n"
    "  --threads N         OpenMP threads, 1..1024; default: the OpenMP default\n"
    "\n"
    "CSV columns: quantity,method,settings,seconds_per_call,max_error,rms_error,\n"
    "  conditions (waves: seconds per facet or cell; empty errors: no reference).\n";

/* ------------------------------------------------------- option helpers */

/* --seed: a decimal unsigned integer, read exactly (not through a double). */
static sea_status opt_seed(const sea_cli_args *args, unsigned long *out, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "seed");
    if (!text) {
        *out = 1;
        return SEA_OK;
    }
    size_t len = strlen(text);
    if (len == 0 || strspn(text, "0123456789") != len)
        return sea_fail(err, SEA_ERR_PARSE, "--seed: '%s' is not an unsigned integer", text);
    errno = 0;
    unsigned long v = strtoul(text, NULL, 10);
    if (errno == ERANGE)
        return sea_fail(err, SEA_ERR_DOMAIN, "--seed: %s is outside [0, %lu]", text, ULONG_MAX);
    *out = v;
    return SEA_OK;
}

/* --method (default variable-step) and --n, which only variable-step-2n
 * takes and requires. */
static sea_status opt_facet_method(const sea_cli_args *args, sea_facet_method *method, int *n,
                                   sea_error *err)
{
    const char *text = sea_cli_args_get(args, "method");
    int m = sea_facet_method_from_name(text ? text : "variable-step");
    if (m < 0)
        return sea_fail(err, SEA_ERR_PARSE,
                        "--method: '%s' is not one of variable-step, variable-step-2n, one-meter",
                        text);
    *method = (sea_facet_method)m;
    *n = 0;
    if (*method != SEA_METHOD_VARIABLE_STEP_2N) {
        if (sea_cli_given(args, "n"))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "--n applies only to --method variable-step-2n, not %s",
                            sea_facet_method_name(*method));
        return SEA_OK;
    }
    long v;
    sea_status st =
        sea_cli_require(args, "n", " (the sub-facet exponent of variable-step-2n)", err);
    if (st == SEA_OK)
        st = sea_cli_opt_integer(args, "n", 0, SEA_CLI_N_MAX, 0, &v, err);
    if (st == SEA_OK)
        *n = (int)v;
    return st;
}

/* Sea state from --wind (one value), --fetch, --wind-dir. */
static sea_status opt_sea_state(const sea_cli_args *args, double *wind, double *fetch,
                                double *wind_dir_deg, sea_error *err)
{
    sea_status st = sea_cli_require(args, "wind", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wind", &SEA_CLI_RANGE_WIND, 0.0, wind, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "fetch", &SEA_CLI_RANGE_FETCH, INFINITY, fetch, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wind-dir", &SEA_CLI_RANGE_AZIMUTH, 0.0, wind_dir_deg, err);
    return st;
}

/* --threads N: sets the OpenMP thread count. */
static sea_status opt_threads(const sea_cli_args *args, sea_error *err)
{
    long n;
    sea_status st = sea_cli_opt_integer(args, "threads", 1, 1024, 0, &n, err);
    if (st != SEA_OK)
        return st;
#ifdef _OPENMP
    if (n > 0)
        omp_set_num_threads((int)n);
#endif
    return SEA_OK;
}

static int max_threads(void)
{
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

/* --------------------------------------------------------------- numbers */

/* e with r = 2^e, e in [0, emax], within SEA_CLI_LENGTH_REL_TOL; false if r
 * is not such a power of two. */
static bool pow2_exponent(double r, int emax, int *e)
{
    const double m = round(log2(r));
    if (!(m >= 0.0) || m > emax || fabs(r - exp2(m)) > SEA_CLI_LENGTH_REL_TOL * r)
        return false;
    *e = (int)m;
    return true;
}

/* The smallest power of two >= x (x >= 1, finite). */
static double pow2_ceil(double x)
{
    double e = ceil(log2(x));
    if (exp2(e - 1.0) >= x)
        e -= 1.0;
    if (exp2(e) < x)
        e += 1.0;
    return exp2(e);
}

/* ------------------------------------------------------------------ files */

/* A file written under "<path>.tmp.XXXXXX" next to its destination (as the
 * EXR writer does) and renamed over it only when complete. */
typedef struct {
    const char *path;
    char *tmp;
    FILE *f;
} atomic_file;

static sea_status atomic_open(atomic_file *af, const char *opt, const char *path, sea_error *err)
{
    *af = (atomic_file){path, NULL, NULL};
    size_t len = strlen(path) + sizeof ".tmp.XXXXXX";
    af->tmp = malloc(len);
    if (af->tmp == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    snprintf(af->tmp, len, "%s.tmp.XXXXXX", path);
    int fd = mkstemp(af->tmp);
    if (fd < 0) {
        int e = errno;
        free(af->tmp);
        af->tmp = NULL;
        return sea_fail(err, SEA_ERR_IO, "%s: cannot create a file next to '%s': %s", opt, path,
                        strerror(e));
    }
    /* mkstemp creates mode 0600; a new output file gets 0666 less the umask. */
    mode_t mask = umask(0);
    umask(mask);
    if (fchmod(fd, 0666 & ~mask) != 0 || (af->f = fdopen(fd, "w")) == NULL) {
        int e = errno;
        close(fd);
        unlink(af->tmp);
        free(af->tmp);
        af->tmp = NULL;
        return sea_fail(err, SEA_ERR_IO, "%s: cannot open '%s': %s", opt, path, strerror(e));
    }
    return SEA_OK;
}

/* Removes the temporary file; nothing is left at the destination. */
static void atomic_abort(atomic_file *af)
{
    if (af->f != NULL)
        fclose(af->f);
    if (af->tmp != NULL) {
        unlink(af->tmp);
        free(af->tmp);
    }
    af->f = NULL;
    af->tmp = NULL;
}

static sea_status atomic_commit(atomic_file *af, const char *opt, sea_error *err)
{
    /* The data reach the disk before the rename, or a crash could leave an
     * empty file under the final name. */
    int e = 0;
    if (fflush(af->f) != 0 || ferror(af->f) || fsync(fileno(af->f)) != 0)
        e = errno ? errno : EIO;
    if (fclose(af->f) != 0 && e == 0)
        e = errno;
    af->f = NULL;
    if (e != 0) {
        atomic_abort(af);
        return sea_fail(err, SEA_ERR_IO, "%s: cannot write '%s': %s", opt, af->path, strerror(e));
    }
    if (rename(af->tmp, af->path) != 0) {
        e = errno;
        atomic_abort(af);
        return sea_fail(err, SEA_ERR_IO, "%s: cannot rename the finished file to '%s': %s", opt,
                        af->path, strerror(e));
    }
    free(af->tmp);
    af->tmp = NULL;
    return SEA_OK;
}

/* mkdir -p dir, then checks that it is a writable directory. */
static sea_status make_dir(const char *opt, const char *dir, sea_error *err)
{
    if (dir[0] == '\0')
        return sea_fail(err, SEA_ERR_PARSE, "%s: empty directory name", opt);
    char *p = strdup(dir);
    if (p == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    for (char *s = p + 1; *s; ++s) {
        if (*s != '/')
            continue;
        *s = '\0';
        if (mkdir(p, 0777) != 0 && errno != EEXIST) {
            int e = errno;
            sea_status st = sea_fail(err, SEA_ERR_IO, "%s: cannot create directory '%s': %s", opt,
                                     p, strerror(e));
            free(p);
            return st;
        }
        *s = '/';
    }
    free(p);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot create directory '%s': %s", opt, dir,
                        strerror(errno));
    struct stat sb;
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_IO, "%s: '%s' is not a directory", opt, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot write into directory '%s': %s", opt, dir,
                        strerror(errno));
    return SEA_OK;
}

/* ================================================================ slopes */

static const sea_cli_option SEA_CLI_SLOPES_OPTIONS[] = {
    {"wind", 0},       {"fetch", 0},     {"wind-dir", 0},  {"facet", 0},
    {"method", 0},     {"n", 0},         {"seed", 0},      {"time", 0},
    {"size", 0},       {"finest", 0},    {"generator", 0}, {"loop-period", 0},
    {"o", SEA_CLI_OPT_SHORT},          {"quiet", SEA_CLI_OPT_FLAG}};

typedef enum { SLOPES_STDOUT, SLOPES_CSV, SLOPES_EXR } slopes_output;

/* Everything slopes computes from, validated. */
typedef struct {
    double wind, fetch, wind_dir_deg;
    double facet, finest, time, loop_period;
    sea_facet_method method;
    int n; /* sub-facet exponent in use (one-meter: log2(L/L0)) */
    unsigned long seed;
    size_t nx, ny;
    sea_waves_kind kind;
    size_t fft_size;
    slopes_output output;
    const char *path;
    bool quiet;
} slopes_setup;

static const char *generator_name(sea_waves_kind k)
{
    return k == SEA_WAVES_FFT ? "fft" : "sinusoids";
}

static sea_status slopes_size(const sea_cli_args *args, size_t *nx, size_t *ny, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "size");
    double v[2];
    sea_status st = sea_cli_parse_tuple("--size", text ? text : "64,64", 2, SEA_CLI_RANGE_SIZE,
                                        "NX,NY", v, err);
    if (st != SEA_OK)
        return st;
    for (int q = 0; q < 2; ++q)
        if (v[q] != floor(v[q]))
            return sea_fail(err, SEA_ERR_DOMAIN, "--size: %g is not an integer", v[q]);
    *nx = (size_t)v[0];
    *ny = (size_t)v[1];
    return SEA_OK;
}

/* The generator and, for FFT, the patch: the smallest power of two of
 * points that covers the rectangle, so that it never repeats. */
static sea_status slopes_generator(const sea_cli_args *args, slopes_setup *s, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "generator");
    if (text == NULL)
        s->kind = s->method == SEA_METHOD_ONE_METER ? SEA_WAVES_FFT : SEA_WAVES_SINUSOIDS;
    else if (strcmp(text, "sinusoids") == 0)
        s->kind = SEA_WAVES_SINUSOIDS;
    else if (strcmp(text, "fft") == 0)
        s->kind = SEA_WAVES_FFT;
    else
        return sea_fail(err, SEA_ERR_PARSE, "--generator: '%s' is not one of sinusoids, fft",
                        text);
    s->fft_size = 0;
    if (s->kind != SEA_WAVES_FFT)
        return SEA_OK;

    const double delta = s->facet / exp2(s->n);
    int m;
    if (!pow2_exponent(delta / s->finest, 62, &m))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--generator fft samples steps of --finest %g m times 2^m: the "
                        "sub-facet size %g m is not one (use --generator sinusoids)",
                        s->finest, delta);
    /* Each side holds the rectangle, and the level grid of the sub-facets
     * has at least two cells (the library samples up to half a period). */
    const double side = s->nx > s->ny ? (double)s->nx : (double)s->ny;
    double need = fmax(side * s->facet / s->finest, 2.0 * delta / s->finest);
    need = pow2_ceil(fmax(need, 2.0));
    if (need > SEA_CLI_FFT_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--size %zu,%zu: %g m x %g m needs an FFT patch of %.0f points per side "
                        "at --finest %g m, above the limit of %d (use --generator sinusoids, a "
                        "smaller --size or --facet, or a larger --finest)",
                        s->nx, s->ny, (double)s->nx * s->facet, (double)s->ny * s->facet, need,
                        s->finest, SEA_CLI_FFT_MAX);
    s->fft_size = (size_t)need;
    return SEA_OK;
}

static sea_status slopes_parse(const sea_cli_args *args, slopes_setup *s, sea_error *err)
{
    sea_status st = opt_sea_state(args, &s->wind, &s->fetch, &s->wind_dir_deg, err);
    if (st == SEA_OK)
        st = sea_cli_require(args, "facet", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "facet", &SEA_CLI_RANGE_LENGTH, 0.0, &s->facet, err);
    if (st == SEA_OK)
        st = opt_facet_method(args, &s->method, &s->n, err);
    if (st == SEA_OK)
        st = opt_seed(args, &s->seed, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "time", &SEA_CLI_RANGE_TIME, 0.0, &s->time, err);
    if (st == SEA_OK)
        st = slopes_size(args, &s->nx, &s->ny, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "finest", &SEA_CLI_RANGE_LENGTH, 1.0, &s->finest, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "loop-period", &SEA_CLI_RANGE_LOOP, 0.0, &s->loop_period,
                                err);
    if (st != SEA_OK)
        return st;

    s->quiet = sea_cli_given(args, "quiet");
    s->path = sea_cli_args_get(args, "o");
    s->output = SLOPES_STDOUT;
    if (s->path != NULL) {
        if (sea_cli_has_suffix(s->path, ".csv"))
            s->output = SLOPES_CSV;
        else if (sea_cli_has_suffix(s->path, ".exr"))
            s->output = SLOPES_EXR;
        else
            return sea_fail(err, SEA_ERR_PARSE, "-o: '%s' must end in .csv or .exr", s->path);
    }

    /* The sub-facets: L / 2^n, at least the plan's finest size. */
    if (s->method == SEA_METHOD_ONE_METER) {
        if (!pow2_exponent(s->facet / s->finest, SEA_CLI_N_MAX, &s->n))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "--facet: one-meter needs L = --finest %g m times 2^n, n in [0, "
                            "%d]; %g m is not",
                            s->finest, SEA_CLI_N_MAX, s->facet);
    }
    const double delta = s->facet / exp2(s->n);
    if (delta < s->finest * (1.0 - SEA_CLI_LENGTH_REL_TOL)) {
        if (s->n == 0)
            return sea_fail(err, SEA_ERR_DOMAIN, "--facet: %g m is below --finest %g m",
                            s->facet, s->finest);
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--n: sub-facets of %g m / 2^%d = %g m are below --finest %g m", s->facet,
                        s->n, delta, s->finest);
    }
    return slopes_generator(args, s, err);
}

static sea_status slopes_csv(FILE *f, const char *where, const sea_rect *r,
                             const sea_moments *mo, sea_error *err)
{
    fputs("i,j,x_m,y_m,mx,my,mxx,mxy,myy,h\n", f);
    for (size_t j = 0; j < r->ny; ++j) {
        /* Lattice indices (I is complex.h's imaginary unit). */
        const long fj = r->j0 + (long)j;
        for (size_t i = 0; i < r->nx; ++i) {
            const long fi = r->i0 + (long)i;
            const sea_moments *m = &mo[j * r->nx + i];
            fprintf(f, "%ld,%ld,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", fi, fj,
                    ((double)fi + 0.5) * r->step, ((double)fj + 0.5) * r->step, m->mx, m->my,
                    m->mxx, m->mxy, m->myy, m->h);
        }
        if (ferror(f))
            return sea_fail(err, SEA_ERR_IO, "cannot write to %s", where);
    }
    return SEA_OK;
}

static sea_status slopes_exr(const slopes_setup *s, const sea_rect *r, const sea_moments *mo,
                             sea_error *err)
{
    const size_t np = r->nx * r->ny;
    float *buf = malloc(6 * np * sizeof(float));
    if (buf == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu image", r->nx, r->ny);
    /* Row 0 of the image is the northernmost facet row (the largest j). */
    for (size_t row = 0; row < r->ny; ++row) {
        const size_t j = r->ny - 1 - row;
        for (size_t i = 0; i < r->nx; ++i) {
            const sea_moments *m = &mo[j * r->nx + i];
            const size_t d = row * r->nx + i;
            buf[d] = (float)m->mx;
            buf[np + d] = (float)m->my;
            buf[2 * np + d] = (float)m->mxx;
            buf[3 * np + d] = (float)m->mxy;
            buf[4 * np + d] = (float)m->myy;
            buf[5 * np + d] = (float)m->h;
        }
    }
    const sea_exr_channel ch[] = {{"mx", buf},           {"my", buf + np},
                                  {"mxx", buf + 2 * np}, {"mxy", buf + 3 * np},
                                  {"myy", buf + 4 * np}, {"h", buf + 5 * np}};
    char facet[32], n[16], wind[32], dir[32], fetch[32], seed[32], t[32], origin[64], finest[32],
        loop[32], fft[32];
    snprintf(facet, sizeof facet, "%.10g", s->facet);
    snprintf(n, sizeof n, "%d", s->n);
    snprintf(wind, sizeof wind, "%.10g", s->wind);
    snprintf(dir, sizeof dir, "%.10g", s->wind_dir_deg);
    snprintf(fetch, sizeof fetch, isinf(s->fetch) ? "inf" : "%.10g", s->fetch);
    snprintf(seed, sizeof seed, "%lu", s->seed);
    snprintf(t, sizeof t, "%.10g", s->time);
    snprintf(origin, sizeof origin, "%.10g,%.10g", (double)r->i0 * r->step,
             (double)r->j0 * r->step);
    snprintf(finest, sizeof finest, "%.10g", s->finest);
    snprintf(loop, sizeof loop, "%.10g", s->loop_period);
    snprintf(fft, sizeof fft, "%zu", s->fft_size);
    const sea_exr_attr attrs[] = {{"seabake:method", sea_facet_method_name(s->method)},
                                  {"seabake:facet_m", facet},
                                  {"seabake:n", n},
                                  {"seabake:wind", wind},
                                  {"seabake:wind_dir_deg", dir},
                                  {"seabake:fetch_m", fetch},
                                  {"seabake:seed", seed},
                                  {"seabake:time_s", t},
                                  {"seabake:origin", origin},
                                  {"seabake:generator", generator_name(s->kind)},
                                  {"seabake:finest_m", finest},
                                  {"seabake:loop_period_s", loop},
                                  {"seabake:fft_size", fft}};
    const size_t n_attrs = sizeof attrs / sizeof attrs[0] - (s->kind == SEA_WAVES_FFT ? 0 : 1);
    const sea_exr_options opt = {SEA_EXR_FLOAT, SEA_EXR_ZIP};
    sea_status st = sea_exr_write(s->path, (int)r->nx, (int)r->ny, ch, 6, attrs, n_attrs, &opt,
                                  err);
    free(buf);
    return st;
}

/* One line on stderr: the generated part (variance of the facet means) plus
 * the sub-facet part (mean of M - m m^T) against the low-resolution
 * covariance; the ratio is near 1 on a rectangle much larger than the
 * longest waves. */
static sea_status slopes_summary(const slopes_setup *s, const sea_spectrum *spec,
                                 const sea_rect *r, const sea_moments *mo, sea_error *err)
{
    const size_t np = r->nx * r->ny;
    double mx = 0.0, my = 0.0;
    for (size_t q = 0; q < np; ++q) {
        mx += mo[q].mx;
        my += mo[q].my;
    }
    mx /= (double)np;
    my /= (double)np;
    sea_cov2 var = {0.0, 0.0, 0.0}, sub = {0.0, 0.0, 0.0}, lr;
    for (size_t q = 0; q < np; ++q) {
        const double dx = mo[q].mx - mx, dy = mo[q].my - my;
        var.xx += dx * dx;
        var.yy += dy * dy;
        var.xy += dx * dy;
        sub.xx += mo[q].mxx - mo[q].mx * mo[q].mx;
        sub.yy += mo[q].myy - mo[q].my * mo[q].my;
        sub.xy += mo[q].mxy - mo[q].mx * mo[q].my;
    }
    var.xx /= (double)np;
    var.yy /= (double)np;
    var.xy /= (double)np;
    sub.xx /= (double)np;
    sub.yy /= (double)np;
    sub.xy /= (double)np;
    sea_status st = sea_spectrum_slope_cov(spec, 0.0, &lr, err);
    if (st != SEA_OK)
        return st;
    fprintf(stderr,
            "slopes: %zu x %zu facets of %g m, %s n=%d (%s): mean slope %.4g,%.4g; variance of "
            "facet means xx,yy,xy %.4g,%.4g,%.4g; mean sub-facet covariance %.4g,%.4g,%.4g; "
            "(variance + sub-facet)/LR x %.4f, y %.4f\n",
            r->nx, r->ny, s->facet, sea_facet_method_name(s->method), s->n,
            generator_name(s->kind), mx, my, var.xx, var.yy, var.xy, sub.xx, sub.yy, sub.xy,
            (var.xx + sub.xx) / lr.xx, (var.yy + sub.yy) / lr.yy);
    return SEA_OK;
}

static sea_status run_slopes(const sea_cli_args *args, FILE *out, sea_error *err)
{
    slopes_setup s;
    sea_spectrum spec;
    sea_waves *waves = NULL;
    sea_moments *mo = NULL;
    atomic_file af = {NULL, NULL, NULL};
    sea_status st = slopes_parse(args, &s, err);
    if (st != SEA_OK)
        return st;
    const size_t np = s.nx * s.ny;
    /* The moments, and the float image when writing EXR, before any work. */
    char what[64];
    snprintf(what, sizeof what, "--size %zu,%zu", s.nx, s.ny);
    const size_t per_facet = sizeof(sea_moments) + (s.output == SLOPES_EXR ? 6 * sizeof(float) : 0);
    if ((st = sea_check_size(np, per_facet, what, err)) != SEA_OK)
        return st;
    if (s.output != SLOPES_STDOUT &&
        (st = sea_cli_check_parent_writable("-o", s.path, err)) != SEA_OK)
        return st;
    if ((st = sea_spectrum_init(&spec, s.wind, s.fetch, sea_cli_radians(s.wind_dir_deg), err)) !=
        SEA_OK)
        return st;

    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = s.kind;
    p.finest = s.finest;
    p.seed = s.seed;
    p.loop_period = s.loop_period;
    if (s.kind == SEA_WAVES_FFT)
        p.fft_size = s.fft_size;
    if ((st = sea_waves_create(&spec, &p, &waves, err)) != SEA_OK)
        goto done;
    mo = malloc(np * sizeof *mo);
    if (mo == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu x %zu facets", s.nx, s.ny);
        goto done;
    }
    const sea_rect rect = {s.facet, -(long)(s.nx / 2), -(long)(s.ny / 2), s.nx, s.ny};
    if ((st = sea_waves_facets(waves, &rect, s.n, s.time, mo, err)) != SEA_OK)
        goto done;
    for (size_t q = 0; q < np; ++q) {
        const sea_moments *m = &mo[q];
        if (!isfinite(m->mx) || !isfinite(m->my) || !isfinite(m->mxx) || !isfinite(m->mxy) ||
            !isfinite(m->myy) || !isfinite(m->h)) {
            st = sea_fail(err, SEA_ERR_NUMERIC, "the moments of facet %zu are not finite", q);
            goto done;
        }
    }

    switch (s.output) {
    case SLOPES_STDOUT:
        st = slopes_csv(out, "standard output", &rect, mo, err);
        break;
    case SLOPES_CSV:
        if ((st = atomic_open(&af, "-o", s.path, err)) != SEA_OK)
            break;
        if ((st = slopes_csv(af.f, s.path, &rect, mo, err)) != SEA_OK)
            break;
        st = atomic_commit(&af, "-o", err);
        break;
    case SLOPES_EXR:
        st = slopes_exr(&s, &rect, mo, err);
        break;
    }
    if (st == SEA_OK && !s.quiet)
        st = slopes_summary(&s, &spec, &rect, mo, err);
done:
    atomic_abort(&af);
    free(mo);
    sea_waves_free(waves);
    return st;
}

/* =========================================================== convergence */

static const sea_cli_option SEA_CLI_CONVERGENCE_OPTIONS[] = {
    {"wavelength", 0}, {"water", 0},     {"salinity", 0},  {"wind", 0},
    {"fetch", 0},      {"wind-dir", 0},  {"theta", 0},     {"phi", 0},
    {"inc", 0},        {"seed", 0},      {"method", 0},    {"n", 0},
    {"facets", 0},     {"sizes", 0},     {"tolerance", 0}, {"o", SEA_CLI_OPT_SHORT},
    {"quiet", SEA_CLI_OPT_FLAG}};

typedef struct {
    double wavelength_um;
    double complex N;
    double theta_deg, phi_deg, inc_deg[2];
    sea_dir obs, inc;
    sea_cli_list winds;
    double fetch, wind_dir_deg;
    unsigned long seed;
    sea_facet_method method;
    int n;
    long K;
    int x1, x2;
    double tol;
    const char *dir;
    const char *water, *salinity;
    bool progress;
} conv_setup;

/* One row of the table: one wind, one size. */
typedef struct {
    double wind, L;
    int x, n;
    size_t facets; /* per side */
    double emis_lr, emis_origin, emis_mean, emis_rms, emis_max;
    double refl_lr, refl_origin, refl_mean, refl_rms, refl_max;
    double var_mx, var_my;
} conv_row;

/* --sizes X1:X2 (or one X). */
static sea_status conv_sizes(const sea_cli_args *args, int *x1, int *x2, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "sizes");
    *x1 = 1;
    *x2 = SEA_CLI_CONV_X_MAX;
    if (text == NULL)
        return SEA_OK;
    const sea_cli_range r = {1.0, SEA_CLI_CONV_X_MAX, false, false, ""};
    const char *colon = strchr(text, ':');
    char first[64];
    double a, b;
    if (colon != NULL && (strchr(colon + 1, ':') || (size_t)(colon - text) >= sizeof first))
        return sea_fail(err, SEA_ERR_PARSE, "--sizes: '%s' is not X1:X2", text);
    if (colon != NULL) {
        memcpy(first, text, (size_t)(colon - text));
        first[colon - text] = '\0';
    }
    sea_status st = sea_cli_parse_number("--sizes", colon ? first : text, &r, &a, err);
    if (st == SEA_OK)
        st = colon ? sea_cli_parse_number("--sizes", colon + 1, &r, &b, err) : SEA_OK;
    if (st != SEA_OK)
        return st;
    if (!colon)
        b = a;
    if (a != floor(a) || b != floor(b))
        return sea_fail(err, SEA_ERR_DOMAIN, "--sizes: '%s' must hold integers", text);
    if (a > b)
        return sea_fail(err, SEA_ERR_DOMAIN, "--sizes: '%s' runs backwards (X1 <= X2)", text);
    *x1 = (int)a;
    *x2 = (int)b;
    return SEA_OK;
}

static sea_status conv_parse(const sea_cli_args *args, conv_setup *c, sea_error *err)
{
    long K;
    sea_status st = sea_cli_require(args, "wind", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_parse_list("--wind", sea_cli_args_get(args, "wind"), &SEA_CLI_RANGE_WIND,
                                &c->winds, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "fetch", &SEA_CLI_RANGE_FETCH, INFINITY, &c->fetch, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wind-dir", &SEA_CLI_RANGE_AZIMUTH, 0.0, &c->wind_dir_deg,
                                err);
    if (st == SEA_OK)
        st = sea_cli_require(args, "theta", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "theta", &SEA_CLI_RANGE_ZENITH, 0.0, &c->theta_deg, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "phi", &SEA_CLI_RANGE_AZIMUTH, 0.0, &c->phi_deg, err);
    if (st != SEA_OK)
        return st;
    /* The default incidence is the specular one of Fig. 6. */
    c->inc_deg[0] = -c->theta_deg;
    c->inc_deg[1] = c->phi_deg;
    const char *inc = sea_cli_args_get(args, "inc");
    if (inc != NULL &&
        (st = sea_cli_parse_tuple("--inc", inc, 2, SEA_CLI_RANGE_DIRECTION, "THETA,PHI",
                                  c->inc_deg, err)) != SEA_OK)
        return st;
    c->obs = sea_dir_fold(sea_cli_radians(c->theta_deg), sea_cli_radians(c->phi_deg));
    c->inc = sea_dir_fold(sea_cli_radians(c->inc_deg[0]), sea_cli_radians(c->inc_deg[1]));

    if ((st = opt_seed(args, &c->seed, err)) != SEA_OK ||
        (st = opt_facet_method(args, &c->method, &c->n, err)) != SEA_OK ||
        (st = sea_cli_opt_integer(args, "facets", 1, SEA_CLI_CONV_FACETS_MAX,
                                  SEA_CLI_CONV_FACETS_DEFAULT, &K, err)) != SEA_OK ||
        (st = conv_sizes(args, &c->x1, &c->x2, err)) != SEA_OK ||
        (st = sea_cli_opt_number(args, "tolerance", &SEA_CLI_RANGE_TOL, SEA_CLI_CONV_TOL_DEFAULT,
                                 &c->tol, err)) != SEA_OK)
        return st;
    c->K = K;
    c->dir = sea_cli_args_get(args, "o");
    if (c->dir == NULL)
        c->dir = ".";
    c->water = sea_cli_args_get(args, "water");
    if (c->water == NULL)
        c->water = "hale-querry";
    c->salinity = sea_cli_args_get(args, "salinity");
    if (c->salinity == NULL)
        c->salinity = "35";
    c->progress = !sea_cli_given(args, "quiet") && isatty(STDERR_FILENO);
    /* The water table is read last: a typing mistake is reported first. */
    return sea_cli_water(args, &c->wavelength_um, &c->N, err);
}

/* Emissivity toward obs and reflectivity inc -> obs of each facet; the
 * facets are independent, so threads change nothing in the result. */
static sea_status conv_optics(const conv_setup *c, const sea_optics *optics,
                              const sea_moments *mo, size_t count, double *emis, double *refl,
                              sea_error *err)
{
    int *status = malloc(count * sizeof *status);
    if (status == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
#pragma omp parallel for schedule(dynamic, 4)
    for (long q = 0; q < (long)count; ++q) {
        const sea_slope_stats st = sea_moments_stats(&mo[q]);
        status[q] = (int)sea_emissivity(optics, SEA_EMIS_AUTO, c->N, &st, c->obs, &emis[q], NULL);
        refl[q] = sea_reflectivity(c->N, &st, c->inc, c->obs);
    }
    sea_status res = SEA_OK;
    for (size_t q = 0; q < count && res == SEA_OK; ++q) {
        if (status[q] != SEA_OK) {
            /* Again, in this thread, for the message. */
            const sea_slope_stats st = sea_moments_stats(&mo[q]);
            sea_error lib = {{0}};
            res = sea_emissivity(optics, SEA_EMIS_AUTO, c->N, &st, c->obs, &emis[q], &lib);
            if (res == SEA_OK)
                res = SEA_ERR_NUMERIC;
            res = sea_fail(err, res, "emissivity of facet %zu: %s", q, lib.msg);
        } else if (!isfinite(emis[q]) || !isfinite(refl[q])) {
            res = sea_fail(err, SEA_ERR_NUMERIC,
                           "emissivity or reflectivity of facet %zu is not finite", q);
        }
    }
    free(status);
    return res;
}

/* Mean, RMS and largest |.| of v - ref. */
static void deviations(const double *v, size_t n, double ref, double *mean, double *rms,
                       double *max)
{
    double s = 0.0, s2 = 0.0, m = 0.0;
    for (size_t q = 0; q < n; ++q) {
        const double d = v[q] - ref;
        s += v[q];
        s2 += d * d;
        m = fmax(m, fabs(d));
    }
    *mean = s / (double)n;
    *rms = sqrt(s2 / (double)n);
    *max = m;
}

static double variance(const sea_moments *mo, size_t n, bool y)
{
    double s = 0.0, s2 = 0.0;
    for (size_t q = 0; q < n; ++q)
        s += y ? mo[q].my : mo[q].mx;
    const double mean = s / (double)n;
    for (size_t q = 0; q < n; ++q) {
        const double d = (y ? mo[q].my : mo[q].mx) - mean;
        s2 += d * d;
    }
    return s2 / (double)n;
}

static void conv_progress(const conv_setup *c, double wind, double L, size_t done, size_t total)
{
    if (!c->progress)
        return;
    fprintf(stderr, "\rconvergence: U=%g m/s L=%g m (%zu/%zu)   ", wind, L, done, total);
    fflush(stderr);
}

/* Every size of one wind: rows[0 .. x2 - x1]. */
static sea_status conv_wind(const conv_setup *c, const sea_optics *optics, double wind,
                            conv_row *rows, size_t *done, size_t total, sea_error *err)
{
    sea_spectrum spec;
    sea_cov2 lr;
    sea_waves *waves = NULL;
    const size_t kmax = (size_t)c->K * (size_t)c->K;
    sea_moments *mo = malloc(kmax * sizeof *mo);
    double *emis = malloc(kmax * sizeof *emis), *refl = malloc(kmax * sizeof *refl);
    sea_status st = SEA_OK;
    if (mo == NULL || emis == NULL || refl == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu facets", kmax);
        goto done;
    }
    if ((st = sea_spectrum_init(&spec, wind, c->fetch, sea_cli_radians(c->wind_dir_deg), err)) !=
            SEA_OK ||
        (st = sea_spectrum_slope_cov(&spec, 0.0, &lr, err)) != SEA_OK)
        goto done;
    /* Low resolution: zero mean, the covariance of every wave (Eq 15). */
    const sea_slope_stats lr_stats = {{0.0, 0.0}, lr};
    double emis_lr, refl_lr;
    sea_error lib = {{0}};
    if ((st = sea_emissivity(optics, SEA_EMIS_AUTO, c->N, &lr_stats, c->obs, &emis_lr, &lib)) !=
        SEA_OK) {
        st = sea_fail(err, st, "low-resolution emissivity at %g m/s: %s", wind, lib.msg);
        goto done;
    }
    refl_lr = sea_reflectivity(c->N, &lr_stats, c->inc, c->obs);

    sea_waves_params p;
    sea_waves_params_default(&p);
    p.finest = SEA_CLI_CONV_FINEST;
    p.seed = c->seed;
    if (c->method != SEA_METHOD_ONE_METER &&
        (st = sea_waves_create(&spec, &p, &waves, err)) != SEA_OK)
        goto done;

    for (int x = c->x1; x <= c->x2; ++x) {
        const double L = exp2(x - 1);
        size_t K = (size_t)c->K;
        int n = 0;
        switch (c->method) {
        case SEA_METHOD_VARIABLE_STEP:
            n = 0;
            break;
        case SEA_METHOD_VARIABLE_STEP_2N:
            n = c->n < x - 1 ? c->n : x - 1; /* sub-facets of at least 1 m */
            break;
        case SEA_METHOD_ONE_METER: {
            /* A patch per size that covers the K x K facets, up to 4096 m:
             * fewer facets beyond (the patch never repeats).  Sizes that
             * need the same patch share it: the same parameters would draw
             * the same waves again. */
            double N = pow2_ceil(fmax((double)K * L / SEA_CLI_CONV_FINEST, 2.0));
            if (N > SEA_CLI_CONV_FFT_MAX)
                N = SEA_CLI_CONV_FFT_MAX;
            if ((double)K * L > N * SEA_CLI_CONV_FINEST)
                K = (size_t)fmax(1.0, floor(N * SEA_CLI_CONV_FINEST / L));
            n = x - 1;
            if (waves != NULL && p.fft_size == (size_t)N)
                break;
            sea_waves_free(waves);
            waves = NULL;
            p.kind = SEA_WAVES_FFT;
            p.fft_size = (size_t)N;
            if ((st = sea_waves_create(&spec, &p, &waves, err)) != SEA_OK)
                goto done;
            break;
        }
        }
        const size_t count = K * K;
        const sea_rect rect = {L, -(long)(K / 2), -(long)(K / 2), K, K};
        conv_progress(c, wind, L, *done + 1, total);
        if ((st = sea_waves_facets(waves, &rect, n, 0.0, mo, err)) != SEA_OK ||
            (st = conv_optics(c, optics, mo, count, emis, refl, err)) != SEA_OK)
            goto done;
        /* Facet (0, 0), whose lower-left corner is the origin. */
        const size_t origin = (K / 2) * K + K / 2;
        conv_row *r = &rows[x - c->x1];
        r->wind = wind;
        r->x = x;
        r->L = L;
        r->facets = K;
        r->n = n;
        r->emis_lr = emis_lr;
        r->refl_lr = refl_lr;
        r->emis_origin = emis[origin];
        r->refl_origin = refl[origin];
        deviations(emis, count, emis_lr, &r->emis_mean, &r->emis_rms, &r->emis_max);
        deviations(refl, count, refl_lr, &r->refl_mean, &r->refl_rms, &r->refl_max);
        r->var_mx = variance(mo, count, false);
        r->var_my = variance(mo, count, true);
        ++*done;
    }
done:
    sea_waves_free(waves);
    free(mo);
    free(emis);
    free(refl);
    return st;
}

/* Index of the smallest size from which every larger size is within the
 * tolerance; n when even the largest is not. */
static size_t conv_converged(const conv_row *rows, size_t n, bool refl, double tol)
{
    size_t first = n;
    for (size_t i = n; i-- > 0;) {
        const double dev = refl ? rows[i].refl_max : rows[i].emis_max;
        const double lr = refl ? rows[i].refl_lr : rows[i].emis_lr;
        if (!(dev <= tol * fabs(lr)))
            break;
        first = i;
    }
    return first;
}

static sea_status conv_csv(const conv_setup *c, const conv_row *rows, size_t nrows,
                           const char *path, sea_error *err)
{
    atomic_file af;
    sea_status st = atomic_open(&af, "-o", path, err);
    if (st != SEA_OK)
        return st;
    FILE *f = af.f;
    fprintf(f,
            "# seabake convergence: high- to low-resolution effective emissivity and "
            "reflectivity (Caillault et al. 2007, Fig. 5-6)\n");
    fprintf(f,
            "# wavelength_um=%.10g theta_obs_deg=%.10g phi_obs_deg=%.10g theta_inc_deg=%.10g "
            "phi_inc_deg=%.10g\n",
            c->wavelength_um, c->theta_deg, c->phi_deg, c->inc_deg[0], c->inc_deg[1]);
    fprintf(f, "# seed=%lu method=%s", c->seed, sea_facet_method_name(c->method));
    if (c->method == SEA_METHOD_VARIABLE_STEP_2N)
        fprintf(f, " n=%d", c->n);
    fprintf(f, " generator=%s finest_m=%g facets_per_side=%ld tolerance=%.10g\n",
            c->method == SEA_METHOD_ONE_METER ? "fft" : "sinusoids", SEA_CLI_CONV_FINEST, c->K,
            c->tol);
    char fetch[32];
    snprintf(fetch, sizeof fetch, isinf(c->fetch) ? "inf" : "%.10g", c->fetch);
    fprintf(f, "# fetch_m=%s wind_dir_deg=%.10g water=%s salinity_g_kg=%s index=%.10g+%.10gi\n",
            fetch, c->wind_dir_deg, c->water, c->salinity, creal(c->N), cimag(c->N));
    fprintf(f, "# dev = HR - LR over the facets; origin = facet (0,0), lower-left corner at the "
               "origin; facets = facets per side; var_m = variance of the facet mean slopes\n");
    fputs("wind_m_s,x,L_m,facets,n,emis_lr,emis_origin,emis_mean,emis_rms_dev,emis_max_dev,"
          "refl_lr,refl_origin,refl_mean,refl_rms_dev,refl_max_dev,var_mx,var_my\n",
          f);
    for (size_t i = 0; i < nrows; ++i) {
        const conv_row *r = &rows[i];
        fprintf(f,
                "%.10g,%d,%.10g,%zu,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,"
                "%.10g,%.10g,%.10g\n",
                r->wind, r->x, r->L, r->facets, r->n, r->emis_lr, r->emis_origin, r->emis_mean,
                r->emis_rms, r->emis_max, r->refl_lr, r->refl_origin, r->refl_mean, r->refl_rms,
                r->refl_max, r->var_mx, r->var_my);
    }
    if (ferror(f)) {
        atomic_abort(&af);
        return sea_fail(err, SEA_ERR_IO, "-o: cannot write '%s'", path);
    }
    return atomic_commit(&af, "-o", err);
}

static void conv_table(FILE *out, const conv_setup *c, const conv_row *rows, size_t nrows,
                       size_t per_wind)
{
    fprintf(out, "%7s %3s %6s %6s %3s  %-11s %-11s %-10s  %-11s %-11s %-10s\n", "U10_m_s", "x",
            "L_m", "facets", "n", "emis_lr", "emis_origin", "max_dev/lr", "refl_lr",
            "refl_origin", "max_dev/lr");
    for (size_t i = 0; i < nrows; ++i) {
        const conv_row *r = &rows[i];
        /* A zero LR value (a direction no facet reflects into) has no
         * relative deviation: "-" rather than an infinity. */
        char rel[2][32];
        const double dev[2] = {r->emis_max, r->refl_max}, lr[2] = {r->emis_lr, r->refl_lr};
        for (int q = 0; q < 2; ++q) {
            if (lr[q] != 0.0)
                snprintf(rel[q], sizeof rel[q], "%.3g", dev[q] / fabs(lr[q]));
            else
                snprintf(rel[q], sizeof rel[q], "-");
        }
        fprintf(out, "%7g %3d %6g %6zu %3d  %-11.8f %-11.8f %-10s  %-11.6g %-11.6g %s\n",
                r->wind, r->x, r->L, r->facets, r->n, r->emis_lr, r->emis_origin, rel[0],
                r->refl_lr, r->refl_origin, rel[1]);
    }
    fputc('\n', out);
    const double last_L = exp2(c->x2 - 1);
    for (size_t w = 0; w < nrows / per_wind; ++w) {
        const conv_row *r = &rows[w * per_wind];
        const size_t ie = conv_converged(r, per_wind, false, c->tol);
        const size_t ir = conv_converged(r, per_wind, true, c->tol);
        fprintf(out, "U10 = %g m/s: emissivity ", r->wind);
        if (ie < per_wind)
            fprintf(out, "within %g%% of LR for L >= %g m", 100.0 * c->tol, r[ie].L);
        else
            fprintf(out, "within %g%% of LR not reached by %g m", 100.0 * c->tol, last_L);
        if (ir < per_wind)
            fprintf(out, ", reflectivity for L >= %g m\n", r[ir].L);
        else
            fprintf(out, ", reflectivity not reached by %g m\n", last_L);
    }
}

typedef struct {
    const conv_setup *c;
    const conv_row *rows;
    size_t nrows, per_wind;
} conv_chart;

/* The gnuplot script: two panels, one curve set per wind, the data inline. */
static char *conv_script(const void *ctx)
{
    const conv_chart *cc = ctx;
    const conv_setup *c = cc->c;
    const conv_row *rows = cc->rows;
    const size_t nrows = cc->nrows, per_wind = cc->per_wind;
    sea_cli_script script;
    FILE *f = sea_cli_gnuplot_begin(&script, 1400, 560);
    if (f == NULL)
        return NULL;
    const size_t nwind = nrows / per_wind;
    for (size_t w = 0; w < nwind; ++w) {
        fprintf(f, "$W%zu << EOD\n", w);
        for (size_t i = 0; i < per_wind; ++i) {
            const conv_row *r = &rows[w * per_wind + i];
            fprintf(f, "%d %.10g %.10g %.10g %.10g %.10g %.10g %.10g %.10g\n", r->x,
                    r->emis_origin, r->emis_mean, r->emis_rms, r->emis_lr, r->refl_origin,
                    r->refl_mean, r->refl_rms, r->refl_lr);
        }
        fputs("EOD\n", f);
    }
    fprintf(f,
            "set multiplot layout 1,2 title '%g µm, observation (%g°, %g°), incidence (%g°, "
            "%g°), seed %lu, %s, %ld x %ld facets'\n",
            c->wavelength_um, c->theta_deg, c->phi_deg, c->inc_deg[0], c->inc_deg[1], c->seed,
            sea_facet_method_name(c->method), c->K, c->K);
    fprintf(f, "set xrange [%g:%g]\n", c->x1 - 0.5, c->x2 + 0.5);
    fputs("set xtics 1\nset xlabel 'x   (L = 2^{x-1} m)'\nset grid\n"
          "set key outside bottom center horizontal maxrows 3 font ',9'\n"
          "set x2tics (",
          f);
    for (int x = c->x1; x <= c->x2; ++x)
        fprintf(f, "%s'%g m' %d", x > c->x1 ? ", " : "", exp2(x - 1), x);
    fputs(")\n", f);
    fprintf(f, "set x2range [%g:%g]\n", c->x1 - 0.5, c->x2 + 0.5);
    const char *panel[2] = {"Effective emissivity", "Effective reflectivity (1/sr)"};
    for (int q = 0; q < 2; ++q) {
        const int col = 2 + 4 * q; /* origin, mean, rms, lr */
        fprintf(f, "set title '%s'\nset ylabel '%s'\nplot ", panel[q],
                q == 0 ? "emissivity" : "reflectivity (1/sr)");
        for (size_t w = 0; w < nwind; ++w) {
            const int lc = (int)w + 1;
            const double U = rows[w * per_wind].wind;
            fprintf(f,
                    "%s$W%zu using 1:%d with linespoints lc %d lw 2 pt 7 title 'U10 = %g m/s, "
                    "origin facet', \\\n"
                    "  $W%zu using 1:%d:%d with yerrorbars lc %d pt 6 title 'U10 = %g m/s, mean "
                    "± RMS dev.', \\\n"
                    "  $W%zu using 1:%d with lines lc %d dt 2 lw 2 title 'U10 = %g m/s, LR'",
                    w > 0 ? ", \\\n  " : "", w, col, lc, U, w, col + 1, col + 2, lc, U, w,
                    col + 3, lc, U);
        }
        fputc('\n', f);
    }
    fputs("unset multiplot\nset output\n", f);
    return sea_cli_gnuplot_end(&script);
}

/* Feeds script to gnuplot's standard input; gnuplot's standard output (the
 * PNG) goes to out_fd.  *absent is set when there is no gnuplot to run. */
static sea_status run_gnuplot(const char *script, int out_fd, bool *absent, sea_error *err)
{
    *absent = false;
    int fd[2];
    if (pipe(fd) != 0)
        return sea_fail(err, SEA_ERR_IO, "cannot create a pipe to gnuplot: %s", strerror(errno));
    posix_spawn_file_actions_t fa;
    if (posix_spawn_file_actions_init(&fa) != 0) {
        close(fd[0]);
        close(fd[1]);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory to run gnuplot");
    }
    FILE *log = tmpfile(); /* gnuplot's complaints, for the message */
    posix_spawn_file_actions_adddup2(&fa, fd[0], STDIN_FILENO);
    posix_spawn_file_actions_addclose(&fa, fd[0]);
    posix_spawn_file_actions_addclose(&fa, fd[1]);
    posix_spawn_file_actions_adddup2(&fa, out_fd, STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&fa, out_fd);
    if (log != NULL)
        posix_spawn_file_actions_adddup2(&fa, fileno(log), STDERR_FILENO);
    char arg0[] = "gnuplot";
    char *argv[] = {arg0, NULL};
    pid_t pid;
    int rc = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(fd[0]);
    if (rc != 0) {
        close(fd[1]);
        if (log != NULL)
            fclose(log);
        if (rc == ENOENT) {
            *absent = true;
            return sea_fail(err, SEA_ERR_NUMERIC, "gnuplot not found");
        }
        return sea_fail(err, SEA_ERR_IO, "cannot run gnuplot: %s", strerror(rc));
    }
    /* A gnuplot that stops reading must not kill seabake with SIGPIPE. */
    struct sigaction ignore, saved;
    memset(&ignore, 0, sizeof ignore);
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGPIPE, &ignore, &saved);
    size_t left = strlen(script);
    const char *p = script;
    while (left > 0) {
        ssize_t w = write(fd[1], p, left);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            break;
        p += w;
        left -= (size_t)w;
    }
    close(fd[1]);
    sigaction(SIGPIPE, &saved, NULL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    char first[200] = "";
    if (log != NULL) {
        rewind(log);
        /* gnuplot's first non-blank complaint line. */
        while (fgets(first, sizeof first, log) != NULL &&
               strspn(first, " \t\r\n^") == strlen(first))
            first[0] = '\0';
        first[strcspn(first, "\r\n")] = '\0';
        fclose(log);
    }
    /* Where posix_spawnp cannot report a failed exec (under valgrind, say),
     * the child exits with 127 and says nothing, as a shell would. */
    if (WIFEXITED(status) && WEXITSTATUS(status) == SEA_CLI_EXEC_FAILED && first[0] == '\0') {
        *absent = true;
        return sea_fail(err, SEA_ERR_NUMERIC, "gnuplot not found");
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || left > 0)
        return sea_fail(err, SEA_ERR_IO, "gnuplot failed%s%s", first[0] ? ": " : "", first);
    return SEA_OK;
}

/* A chart's gnuplot script, drawing to its standard output. */
typedef char *(*chart_script_fn)(const void *ctx);

/* DIR/NAME.png drawn by gnuplot through a temporary name; csv names the
 * table already written, for the message when gnuplot is missing. */
static sea_status write_chart(const char *dir, const char *name, chart_script_fn script_fn,
                              const void *ctx, const char *csv, sea_error *err)
{
    char file[64], tmpl[80];
    snprintf(file, sizeof file, "%s.png", name);
    snprintf(tmpl, sizeof tmpl, ".%s.png.tmp.XXXXXX", name);
    char *png = sea_cli_path_join(dir, file);
    char *tmp = sea_cli_path_join(dir, tmpl);
    char *script = NULL;
    sea_status st = SEA_OK;
    int fd;
    if (png == NULL || tmp == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        goto done;
    }
    if ((fd = mkstemp(tmp)) < 0) {
        st = sea_fail(err, SEA_ERR_IO, "-o: cannot create a file in '%s': %s", dir,
                      strerror(errno));
        free(tmp);
        tmp = NULL;
        goto done;
    }
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    if ((script = script_fn(ctx)) == NULL) {
        close(fd);
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the gnuplot script");
        goto done;
    }
    bool absent;
    st = run_gnuplot(script, fd, &absent, err);
    if (close(fd) != 0 && st == SEA_OK)
        st = sea_fail(err, SEA_ERR_IO, "-o: cannot write the chart in '%s': %s", dir,
                      strerror(errno));
    if (st != SEA_OK) {
        if (absent)
            st = sea_fail(err, SEA_ERR_NUMERIC, "gnuplot not found: %s written, chart not drawn",
                          csv);
        goto done;
    }
    struct stat sb;
    if (stat(tmp, &sb) != 0 || sb.st_size == 0) {
        st = sea_fail(err, SEA_ERR_IO, "gnuplot wrote no chart");
        goto done;
    }
    if (rename(tmp, png) != 0) {
        st = sea_fail(err, SEA_ERR_IO, "-o: cannot rename the chart to '%s': %s", png,
                      strerror(errno));
        goto done;
    }
    free(tmp);
    tmp = NULL;
done:
    if (tmp != NULL) {
        unlink(tmp);
        free(tmp);
    }
    free(png);
    free(script);
    return st;
}

static sea_status run_convergence(const sea_cli_args *args, FILE *out, sea_error *err)
{
    conv_setup c;
    memset(&c, 0, sizeof c);
    sea_optics *optics = NULL;
    conv_row *rows = NULL;
    char *csv = NULL;
    sea_status st = conv_parse(args, &c, err);
    if (st != SEA_OK)
        goto done;
    if ((st = make_dir("-o", c.dir, err)) != SEA_OK)
        goto done;
    if ((csv = sea_cli_path_join(c.dir, "convergence.csv")) == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        goto done;
    }
    const size_t per_wind = (size_t)(c.x2 - c.x1 + 1), nrows = c.winds.n * per_wind;
    rows = calloc(nrows, sizeof *rows);
    if (rows == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu rows", nrows);
        goto done;
    }
    if ((st = sea_optics_alloc(&optics, err)) != SEA_OK)
        goto done;
    size_t done_rows = 0;
    for (size_t w = 0; w < c.winds.n && st == SEA_OK; ++w)
        st = conv_wind(&c, optics, c.winds.values[w], rows + w * per_wind, &done_rows, nrows, err);
    if (c.progress)
        fputs("\r\033[K", stderr);
    if (st != SEA_OK)
        goto done;
    if ((st = conv_csv(&c, rows, nrows, csv, err)) != SEA_OK)
        goto done;
    conv_table(out, &c, rows, nrows, per_wind);
    fflush(out);
    if (ferror(out)) {
        st = sea_fail(err, SEA_ERR_IO, "cannot write to standard output");
        goto done;
    }
    const conv_chart cc = {&c, rows, nrows, per_wind};
    st = write_chart(c.dir, "convergence", conv_script, &cc, "convergence.csv", err);
done:
    sea_optics_free(optics);
    sea_cli_list_free(&c.winds);
    free(rows);
    free(csv);
    return st;
}

/* ================================================================= bench */

static const sea_cli_option SEA_CLI_BENCH_OPTIONS[] = {
    {"quick", SEA_CLI_OPT_FLAG}, {"o", SEA_CLI_OPT_SHORT}, {"threads", 0}};

typedef struct {
    const char *method;
    char settings[128];
    size_t facets;
    double seconds;
} bench_row;

static void bench_print(FILE *out, const bench_row *r, int threads)
{
    fprintf(out, "%-6s %-18s %-46s %9zu %10.4g %11.4g %3d\n", "waves", r->method, r->settings,
            r->facets, r->seconds, (double)r->facets / r->seconds, threads);
    fflush(out);
}

/* Facets per second of one method: the plan is made once (its time is in
 * the settings), the facets computed reps times, the best time kept. */
static sea_status bench_facets(const sea_spectrum *spec, sea_waves_kind kind, size_t fft_size,
                               sea_facet_method method, int n_arg, size_t side, int reps,
                               bench_row *row, sea_error *err)
{
    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = kind;
    p.finest = 1.0;
    if (kind == SEA_WAVES_FFT)
        p.fft_size = fft_size;
    sea_waves *w = NULL;
    sea_moments *mo = NULL;
    int n;
    const double t0 = sea_cli_seconds();
    sea_status st = sea_waves_create(spec, &p, &w, err);
    const double plan = sea_cli_seconds() - t0;
    if (st == SEA_OK)
        st = sea_facet_method_n(w, method, n_arg, SEA_CLI_BENCH_FACET, &n, err);
    if (st == SEA_OK)
        st = sea_check_size(side * side, sizeof *mo, "bench facet moments", err);
    if (st != SEA_OK)
        goto done;
    if ((mo = malloc(side * side * sizeof *mo)) == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu x %zu facets", side, side);
        goto done;
    }
    const sea_rect rect = {SEA_CLI_BENCH_FACET, -(long)(side / 2), -(long)(side / 2), side, side};
    row->method = sea_facet_method_name(method);
    row->facets = side * side;
    row->seconds = INFINITY;
    for (int r = 0; r < reps && st == SEA_OK; ++r) {
        const double t1 = sea_cli_seconds();
        st = sea_waves_facets(w, &rect, n, 0.0, mo, err);
        row->seconds = fmin(row->seconds, sea_cli_seconds() - t1);
    }
    if (kind == SEA_WAVES_FFT)
        snprintf(row->settings, sizeof row->settings, "fft N=%zu L=%gm n=%d U10=%g plan=%.3gs",
                 fft_size, SEA_CLI_BENCH_FACET, n, SEA_CLI_BENCH_WIND, plan);
    else
        snprintf(row->settings, sizeof row->settings,
                 "sinusoids %zu waves L=%gm n=%d U10=%g plan=%.3gs", sea_waves_count(w),
                 SEA_CLI_BENCH_FACET, n, SEA_CLI_BENCH_WIND, plan);
done:
    free(mo);
    sea_waves_free(w);
    return st;
}

/* An FFT plan's whole grid at step L0, against the same waves summed as
 * sinusoids on a 32 x 32 corner of it: time per cell and agreement. */
static sea_status bench_fft_vs_sinusoids(const sea_spectrum *spec, size_t N, int reps,
                                         bench_row rows[2], double *max_rel_diff,
                                         sea_error *err)
{
    sea_waves_params p;
    sea_waves_params_default(&p);
    p.kind = SEA_WAVES_FFT;
    p.finest = 1.0;
    p.fft_size = N;
    sea_waves *fft = NULL, *sin = NULL;
    double *full = NULL, *sub = NULL;
    const size_t S = SEA_CLI_BENCH_SUB;
    sea_status st = sea_waves_create(spec, &p, &fft, err);
    if (st == SEA_OK)
        st = sea_waves_to_sinusoids(fft, &sin, err);
    if (st == SEA_OK)
        st = sea_check_size(3 * N * N, sizeof(double), "bench FFT grid", err);
    if (st != SEA_OK)
        goto done;
    full = malloc(3 * N * N * sizeof *full);
    sub = malloc(3 * S * S * sizeof *sub);
    if (full == NULL || sub == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu grid", N, N);
        goto done;
    }
    const sea_rect rf = {1.0, -(long)(N / 2), -(long)(N / 2), N, N};
    const sea_rect rs = {1.0, -(long)(S / 2), -(long)(S / 2), S, S};
    rows[0] = (bench_row){"fft-sample", "", N * N, INFINITY};
    rows[1] = (bench_row){"sinusoids-sample", "", S * S, INFINITY};
    for (int r = 0; r < reps && st == SEA_OK; ++r) {
        const double t0 = sea_cli_seconds();
        st = sea_waves_sample(fft, &rf, 0.0, full, full + N * N, full + 2 * N * N, err);
        rows[0].seconds = fmin(rows[0].seconds, sea_cli_seconds() - t0);
    }
    for (int r = 0; r < reps && st == SEA_OK; ++r) {
        const double t0 = sea_cli_seconds();
        st = sea_waves_sample(sin, &rs, 0.0, sub, sub + S * S, sub + 2 * S * S, err);
        rows[1].seconds = fmin(rows[1].seconds, sea_cli_seconds() - t0);
    }
    if (st != SEA_OK)
        goto done;
    /* Largest difference of each field over the corner, relative to the
     * field's largest magnitude over the whole grid. */
    *max_rel_diff = 0.0;
    for (int q = 0; q < 3; ++q) {
        const double *F = full + (size_t)q * N * N, *G = sub + (size_t)q * S * S;
        double scale = 0.0, diff = 0.0;
        for (size_t i = 0; i < N * N; ++i)
            scale = fmax(scale, fabs(F[i]));
        for (size_t j = 0; j < S; ++j)
            for (size_t i = 0; i < S; ++i) {
                const size_t fj = (size_t)(rs.j0 - rf.j0) + j, fi = (size_t)(rs.i0 - rf.i0) + i;
                diff = fmax(diff, fabs(F[fj * N + fi] - G[j * S + i]));
            }
        *max_rel_diff = fmax(*max_rel_diff, scale > 0.0 ? diff / scale : diff);
    }
    snprintf(rows[0].settings, sizeof rows[0].settings, "fft N=%zu step=1m %zu modes U10=%g", N,
             sea_waves_count(fft), SEA_CLI_BENCH_WIND);
    snprintf(rows[1].settings, sizeof rows[1].settings,
             "same waves as sinusoids %zux%zu cells max_rel_diff=%.2g", S, S, *max_rel_diff);
done:
    free(full);
    free(sub);
    sea_waves_free(sin);
    sea_waves_free(fft);
    return st;
}

typedef struct {
    const sea_cli_bench_row *rows;
    size_t n;
} bench_chart;

static char *bench_chart_script(const void *ctx)
{
    const bench_chart *bc = ctx;
    return sea_cli_bench_chart_script(bc->rows, bc->n);
}

static char *bench_image_chart_script(const void *ctx)
{
    const bench_chart *bc = ctx;
    return sea_cli_bench_image_chart_script(bc->rows, bc->n);
}

static sea_status run_bench(const sea_cli_args *args, FILE *out, sea_error *err)
{
    const bool quick = sea_cli_given(args, "quick");
    const char *dir = sea_cli_args_get(args, "o");
    char *csv = NULL;
    atomic_file af = {NULL, NULL, NULL};
    enum { NROWS = 6 };
    bench_row rows[NROWS];
    size_t nrows = 0;
    double diff = 0.0;
    sea_spectrum spec;
    sea_cli_bench_row *orows = NULL, *irows = NULL;
    size_t nopt = 0, nimg = 0;
    sea_cli_bench_summary sum;
    sea_status st = opt_threads(args, err);
    if (st != SEA_OK)
        return st;
    if (dir == NULL)
        dir = ".";
    if ((st = make_dir("-o", dir, err)) != SEA_OK)
        return st;
    if ((csv = sea_cli_path_join(dir, "bench.csv")) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    const int threads = max_threads(), reps = quick ? 1 : 3;
    const size_t side = quick ? 256 : 1024, patch = quick ? 1024 : 4096, N = quick ? 128 : 256;
    if ((st = sea_spectrum_init(&spec, SEA_CLI_BENCH_WIND, INFINITY, 0.0, err)) != SEA_OK)
        goto done;

    fprintf(out, "%-6s %-18s %-46s %9s %10s %11s %3s\n", "section", "method", "settings",
            "facets", "seconds", "facets/s", "thr");
    static const struct {
        sea_waves_kind kind;
        sea_facet_method method;
        int n;
    } cases[] = {{SEA_WAVES_SINUSOIDS, SEA_METHOD_VARIABLE_STEP, 0},
                 {SEA_WAVES_SINUSOIDS, SEA_METHOD_VARIABLE_STEP_2N, 2},
                 {SEA_WAVES_FFT, SEA_METHOD_ONE_METER, 0},
                 {SEA_WAVES_FFT, SEA_METHOD_VARIABLE_STEP, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        if ((st = bench_facets(&spec, cases[i].kind, patch, cases[i].method, cases[i].n, side,
                               reps, &rows[nrows], err)) != SEA_OK)
            goto done;
        bench_print(out, &rows[nrows++], threads);
    }
    if ((st = bench_fft_vs_sinusoids(&spec, N, reps, &rows[nrows], &diff, err)) != SEA_OK)
        goto done;
    bench_print(out, &rows[nrows++], threads);
    bench_print(out, &rows[nrows++], threads);
    const double per_fft = rows[4].seconds / (double)rows[4].facets;
    const double per_sin = rows[5].seconds / (double)rows[5].facets;
    fprintf(out,
            "\nFFT to sinusoids at equal spectrum resolution (N = %zu, step 1 m): FFT %.3g s per "
            "cell, sinusoids %.3g s per cell, ratio %.4g; max |difference| %.3g relative\n",
            N, per_fft, per_sin, per_sin / per_fft, diff);

    /* The optics: speed against accuracy, one thread. */
    fputs("\nOptics, one thread, errors against the adaptive Eq 7 reference (full):\n", out);
    fprintf(out, "%-12s %-11s %-52s %10s %10s %10s\n", "quantity", "method", "settings",
            "s/call", "max err", "rms err");
    if ((st = sea_cli_bench_optics(quick, &orows, &nopt, &sum, err)) != SEA_OK)
        goto done;
    for (size_t i = 0; i < nopt; ++i) {
        const sea_cli_bench_row *r = &orows[i];
        fprintf(out, "%-12s %-11s %-52s %10.3g ", r->quantity, r->method, r->settings,
                r->seconds);
        /* No reference (the closed-form reflectivity): "-", as bench.csv
         * leaves the fields empty; seabake never prints NaN. */
        if (isnan(r->max_err))
            fprintf(out, "%10s %10s\n", "-", "-");
        else
            fprintf(out, "%10.3g %10.3g\n", r->max_err, r->rms_err);
    }
    fprintf(out,
            "\nDefault emissivity (auto) over %zu conditions, theta <= 85 deg: %.3g s per call, "
            "%.4g times faster than full (%.3g s); max |error| %.3g, RMS %.3g\n"
            "Eq 12 (fast): %.3g s per call, %.4g times faster than full; max |error| %.3g, "
            "RMS %.3g\n",
            sum.conditions, sum.auto_seconds, sum.full_seconds / sum.auto_seconds,
            sum.full_seconds, sum.auto_max, sum.auto_rms, sum.fast_seconds,
            sum.full_seconds / sum.fast_seconds, sum.fast_max, sum.fast_rms);
    fflush(out);

    /* Whole images: the paper's scenes, scaled down. */
    if ((st = sea_cli_bench_images(quick, threads, &irows, &nimg, err)) != SEA_OK)
        goto done;
    fputs("\nWhole images, relative radiance error against the reference (the first row of "
          "each scene):\n",
          out);
    fprintf(out, "%-17s %-66s %10s %10s %10s\n", "method", "settings", "s/image", "max err",
            "rms err");
    for (size_t i = 0; i < nimg; ++i) {
        const sea_cli_bench_row *r = &irows[i];
        fprintf(out, "%-17s %-66s %10.3g %10.3g %10.3g\n", r->method, r->settings, r->seconds,
                r->max_err, r->rms_err);
    }
    if (nimg > 0)
        fprintf(out, "(%s)\n", irows[0].conditions);
    fflush(out);

    if ((st = atomic_open(&af, "-o", csv, err)) != SEA_OK)
        goto done;
    fputs("quantity,method,settings,seconds_per_call,max_error,rms_error,conditions\n", af.f);
    for (size_t i = 0; i < nrows; ++i) {
        /* Per facet (per cell for the samplers); the one error is the
         * sinusoids' largest difference from the FFT on the same cells. */
        fprintf(af.f, "waves,%s,%s %zu facets,%.6g,", rows[i].method, rows[i].settings,
                rows[i].facets, rows[i].seconds / (double)rows[i].facets);
        if (i == 5)
            fprintf(af.f, "%.6g,", diff);
        else
            fputs(",", af.f);
        fprintf(af.f, ",U10=%g m/s; %d threads\n", SEA_CLI_BENCH_WIND, threads);
    }
    for (size_t i = 0; i < nopt; ++i) {
        const sea_cli_bench_row *r = &orows[i];
        fprintf(af.f, "%s,%s,%s,%.6g,", r->quantity, r->method, r->settings, r->seconds);
        if (isnan(r->max_err))
            fputs(",,", af.f);
        else
            fprintf(af.f, "%.6g,%.6g,", r->max_err, r->rms_err);
        fprintf(af.f, "%s\n", r->conditions);
    }
    for (size_t i = 0; i < nimg; ++i) {
        const sea_cli_bench_row *r = &irows[i];
        fprintf(af.f, "%s,%s,%s,%.6g,%.6g,%.6g,%s\n", r->quantity, r->method, r->settings,
                r->seconds, r->max_err, r->rms_err, r->conditions);
    }
    if ((st = atomic_commit(&af, "-o", err)) != SEA_OK)
        goto done;
    const bench_chart bc = {orows, nopt};
    if ((st = write_chart(dir, "speed_accuracy", bench_chart_script, &bc, "bench.csv", err)) !=
        SEA_OK)
        goto done;
    /* Seconds per image and per-pixel errors do not share the optics'
     * scales: a second chart. */
    const bench_chart bi = {irows, nimg};
    if ((st = write_chart(dir, "image_speed_accuracy", bench_image_chart_script, &bi, "bench.csv",
                          err)) != SEA_OK)
        goto done;
    if (ferror(out))
        st = sea_fail(err, SEA_ERR_IO, "cannot write to standard output");
done:
    atomic_abort(&af);
    free(orows);
    free(irows);
    free(csv);
    return st;
}

/* ---------------------------------------------------------- the commands */

#define SEA_CLI_COUNT(a) (sizeof(a) / sizeof((a)[0]))

const sea_cli_command sea_cli_waves_commands[] = {
    {"slopes", "facet slope moments of one seeded sea (CSV or EXR)", SEA_CLI_HELP_SLOPES,
     SEA_CLI_SLOPES_OPTIONS, SEA_CLI_COUNT(SEA_CLI_SLOPES_OPTIONS), run_slopes},
    {"convergence", "high- to low-resolution convergence (paper Fig. 5-6)",
     SEA_CLI_HELP_CONVERGENCE, SEA_CLI_CONVERGENCE_OPTIONS,
     SEA_CLI_COUNT(SEA_CLI_CONVERGENCE_OPTIONS), run_convergence},
    {"bench", "speed of the wave generators; speed against accuracy of the optics",
     SEA_CLI_HELP_BENCH, SEA_CLI_BENCH_OPTIONS,
     SEA_CLI_COUNT(SEA_CLI_BENCH_OPTIONS), run_bench},
};
const size_t sea_cli_waves_n_commands = SEA_CLI_COUNT(sea_cli_waves_commands);
