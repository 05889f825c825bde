/* imager.c - a camera's image of a rendered radiance image: optics blur,
 * the detector's active area, temporal and fixed-pattern noise, counts
 * (seabake.h, "the camera"; seabake-model(7), THE CAMERA).
 *
 * Plan once (sea_imager_alloc: the transfer function on the image's DCT
 * grid, the FFTW plans, the fixed pattern, the band's temperature table),
 * apply per frame (sea_imager_apply: one DCT pair, then one pass over the
 * pixels).  The noise is a counter-based hash of (seed, frame, pixel), so
 * a frame is the same whatever the threads. */
#include "config.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <fftw3.h>
#include <gsl/gsl_integration.h>

#include "seabake.h"
#include "internal.h"
#include "textfile.h"

/* MTF tables are a few hundred rows; larger files are refused unread. */
static const long SEA_MTF_BYTES_MAX = 16L << 20;
/* The image sizes a scene allows. */
enum { SEA_IMAGER_SIDE_MAX = 16384 };
/* The radial MTF is tabulated from 0 to the corner of the DCT grid,
 * sqrt(2)/2 cycles per pixel, at this many points h apart and read
 * linearly between them: the diffraction MTF of a 64-sample band is 64
 * acos a point, too many for every pixel.  The largest interpolation
 * error is at a diffraction cutoff nu_c, where M = 1.2 (1 - s)^(3/2) to
 * first order: about 0.4 (h / nu_c)^(3/2), below 1e-6 for nu_c above 0.3
 * cycles per pixel (4e-5 at 0.02, a PSF 50 pixels wide); elsewhere
 * h^2 M'' / 8, below 1e-8 (tests/test_imager.c: 3.2e-8 at nu_c = 1.6,
 * with the float image's rounding). */
enum { SEA_MTF_NODES = 16384 };
static const double SEA_NU_CORNER = 0.70710678118654757; /* sqrt(2) / 2 */
/* The apparent temperature's table: ln L at ln T uniform over 30-6000 K
 * (as render.c's, four times denser), read by the cubic through the four
 * nodes around ln L: within 1e-9 relative of sea_band_temperature (1e-10
 * measured, tests/test_imager.c), so that no Newton step (a Planck sum
 * over the band, a pixel) is needed.  Each interval's cubic is stored as
 * its four coefficients, and a guide of uniform cells in ln L finds the
 * interval in a step or two (instead of a bisection and a Lagrange form):
 * 28 ns a pixel with its loads and stores instead of 61.  Outside the
 * table, sea_band_temperature itself. */
enum { SEA_IM_TB_N = 1024, SEA_IM_GUIDE_N = 4096 };
static const double SEA_IM_TB_LNT0 = 3.4011973816621555;            /* ln 30 */
static const double SEA_IM_TB_STEP = 5.2983173665480363 / 1023.0; /* ln(6000/30) / (N - 1) */

struct sea_imager {
    sea_imager_params p; /* p.mtf points to mtf below */
    sea_mtf_table mtf;   /* a copy of the table (none unless SEA_PSF_TABLE) */
    int width, height;
    /* the band */
    sea_band band; /* points to wl, wt */
    double *wl, *wt;
    double *airy_w; /* diffraction: the samples' shares of the band's PSF */
    double tb_lnL[SEA_IM_TB_N];
    int tb_first; /* first node of tb_lnL that is finite (short waves underflow at 30 K) */
    /* interval a's cubic: ln T = c0 + t (c1 + t (c2 + t c3)), t = ln L - tb_lnL[a] */
    double tb_coef[SEA_IM_TB_N][4];
    int guide[SEA_IM_GUIDE_N]; /* cell k's first interval */
    double guide_lo, guide_inv;
    /* the filter: H on the DCT grid, normalised (NULL when there is none) */
    double *H;
    fftw_plan forward, inverse;
    /* the noise */
    double sigma_L;              /* temporal noise's radiance, image units */
    float *fpn_gain, *fpn_offset; /* per pixel (NULL: none): g_q, and o_q in image units */
    double max_count;            /* 2^bits - 1 */
};

/* ------------------------------------------------------------ the noise
 *
 * A counter-based generator: the k-th draw of a stream of key K is
 * mix(K + k gamma), SplitMix64's output function (Steele, Lea and Flood
 * 2014: mix is Stafford's "Mix13" finaliser, gamma the golden ratio's 64
 * bits), so any draw is computed from (key, k) alone, in any order, on any
 * thread.  Keys: K(seed, tag, frame) = mix(mix(mix(seed + gamma) + tag
 * gamma) + frame gamma), each step a bijection, so distinct frames (and
 * tags, for one seed) give distinct keys; two streams overlap only if
 * their keys differ by a multiple of gamma smaller than twice the pixels,
 * a chance of 4 N / 2^64 (1e-12 for 2 million pixels).  Pixels 2k and
 * 2k + 1 (in row-major order) share the draws 2k and 2k + 1 as uniforms
 * u1, u2 in (0, 1) (53 bits, offset by half a unit): r = sqrt(-2 ln u1),
 * z_2k = r cos(2 pi u2), z_2k+1 = r sin(2 pi u2), two independent
 * standard normals (Box and Muller 1958) for one logarithm. */
static const uint64_t SEA_GAMMA = 0x9E3779B97F4A7C15ULL;
enum { TAG_FPN_GAIN = 1, TAG_FPN_OFFSET = 2, TAG_TEMPORAL = 3 };

static inline uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

static uint64_t stream_key(uint64_t seed, uint64_t tag, uint64_t frame)
{
    return mix64(mix64(mix64(seed + SEA_GAMMA) + tag * SEA_GAMMA) + frame * SEA_GAMMA);
}

static inline double uniform_open(uint64_t x)
{
    return ((double)(x >> 11) + 0.5) * 0x1.0p-53;
}

/* The normals of pixels 2k and 2k + 1 of the stream key. */
static inline void normal_pair(uint64_t key, uint64_t k, double z[2])
{
    const double u1 = uniform_open(mix64(key + (2 * k + 1) * SEA_GAMMA));
    const double u2 = uniform_open(mix64(key + (2 * k + 2) * SEA_GAMMA));
    const double r = sqrt(-2.0 * log(u1));
    z[0] = r * cos(2.0 * M_PI * u2);
    z[1] = r * sin(2.0 * M_PI * u2);
}

/* n normals of the stream key into out (float). */
static void normals_fill(uint64_t key, double scale, double add, size_t n, float *out)
{
#pragma omp parallel for schedule(static)
    for (long k = 0; k < (long)((n + 1) / 2); k++) {
        double z[2];
        normal_pair(key, (uint64_t)k, z);
        out[2 * k] = (float)(add + scale * z[0]);
        if ((size_t)(2 * k + 1) < n)
            out[2 * k + 1] = (float)(add + scale * z[1]);
    }
}

/* ------------------------------------------------------------ MTF table */

static sea_status mtf_push(sea_mtf_table *t, size_t *cap, double f, double v)
{
    if (t->n == *cap) {
        const size_t ncap = *cap ? 2 * *cap : 64;
        double *nf = realloc(t->frequency, ncap * sizeof *nf);
        if (nf == NULL)
            return SEA_ERR_NOMEM;
        t->frequency = nf;
        double *nv = realloc(t->value, ncap * sizeof *nv);
        if (nv == NULL)
            return SEA_ERR_NOMEM;
        t->value = nv;
        *cap = ncap;
    }
    t->frequency[t->n] = f;
    t->value[t->n] = v;
    t->n++;
    return SEA_OK;
}

sea_status sea_imager_mtf_load(const char *path, sea_mtf_table *t, sea_error *err)
{
    sea_status st;
    char *text = NULL;
    size_t cap = 0;
    long lineno = 0;
    int header = 0, i_f = 0;
    memset(t, 0, sizeof *t);
    if ((st = sea_read_text(path, SEA_MTF_BYTES_MAX, "text file", &text, err)) != SEA_OK)
        return st;
    char *cursor = text;
    for (char *line; (line = sea_text_next_line(&cursor, &lineno)) != NULL;) {
        char *comma = strchr(line, ',');
        if (comma == NULL || strchr(comma + 1, ',') != NULL) {
            st = sea_fail(err, SEA_ERR_PARSE, "%s:%ld: need exactly two comma-separated fields",
                          path, lineno);
            goto fail;
        }
        *comma = '\0';
        char *field[2] = { sea_text_trim(line), sea_text_trim(comma + 1) };
        if (!header) {
            if (strcmp(field[0], "cycles_per_pixel") == 0 && strcmp(field[1], "mtf") == 0) {
                i_f = 0;
            } else if (strcmp(field[0], "mtf") == 0 &&
                       strcmp(field[1], "cycles_per_pixel") == 0) {
                i_f = 1;
            } else {
                st = sea_fail(err, SEA_ERR_PARSE,
                              "%s:%ld: the header must name the columns cycles_per_pixel,mtf",
                              path, lineno);
                goto fail;
            }
            header = 1;
            continue;
        }
        double f, v;
        char f_txt[SEA_TEXT_REAL_CHARS], v_txt[SEA_TEXT_REAL_CHARS], b_txt[SEA_TEXT_REAL_CHARS];
        if (sea_text_real(field[i_f], &f) != 0 || !isfinite(f)) {
            st = sea_fail(err, SEA_ERR_PARSE, "%s:%ld: cycles_per_pixel: '%.60s' is not a number",
                          path, lineno, field[i_f]);
            goto fail;
        }
        if (sea_text_real(field[1 - i_f], &v) != 0 || !isfinite(v)) {
            st = sea_fail(err, SEA_ERR_PARSE, "%s:%ld: mtf: '%.60s' is not a number", path,
                          lineno, field[1 - i_f]);
            goto fail;
        }
        if (!(f >= 0.0 && f <= SEA_IMAGER_MTF_FREQ_MAX)) {
            st = sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: cycles_per_pixel: %s is outside [0, %s]",
                          path, lineno, sea_text_format_real(f, f_txt),
                          sea_text_format_real(SEA_IMAGER_MTF_FREQ_MAX, b_txt));
            goto fail;
        }
        if (!(v >= 0.0 && v <= 1.0)) {
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "%s:%ld: mtf: %s is outside [0, 1] (an MTF is at most its value at "
                          "0)",
                          path, lineno, sea_text_format_real(v, v_txt));
            goto fail;
        }
        if (t->n == 0 && !(f == 0.0 && v == 1.0)) {
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "%s:%ld: the first row is %s,%s (allowed: 0,1: an MTF normalised at "
                          "frequency 0)",
                          path, lineno, sea_text_format_real(f, f_txt),
                          sea_text_format_real(v, v_txt));
            goto fail;
        }
        if (t->n > 0 && !(f > t->frequency[t->n - 1])) {
            st = sea_fail(err, SEA_ERR_PARSE,
                          "%s:%ld: cycles_per_pixel: %s does not increase (previous row %s)",
                          path, lineno, sea_text_format_real(f, f_txt),
                          sea_text_format_real(t->frequency[t->n - 1], b_txt));
            goto fail;
        }
        if (mtf_push(t, &cap, f, v) != SEA_OK) {
            st = sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
            goto fail;
        }
    }
    if (!header) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: no header row cycles_per_pixel,mtf", path);
        goto fail;
    }
    if (t->n < 2) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: an MTF needs at least two rows (found %zu)", path,
                      t->n);
        goto fail;
    }
    free(text);
    return SEA_OK;
fail:
    free(text);
    sea_imager_mtf_free(t);
    return st;
}

void sea_imager_mtf_free(sea_mtf_table *t)
{
    if (t == NULL)
        return;
    free(t->frequency);
    free(t->value);
    memset(t, 0, sizeof *t);
}

/* The table's MTF at nu: linear between rows, the last value beyond. */
static double mtf_table_at(const sea_mtf_table *t, double nu)
{
    if (nu >= t->frequency[t->n - 1])
        return t->value[t->n - 1];
    const size_t i = sea_interval_of(t->frequency, t->n, nu);
    const double a = (nu - t->frequency[i]) / (t->frequency[i + 1] - t->frequency[i]);
    return (1.0 - a) * t->value[i] + a * t->value[i + 1];
}

/* ------------------------------------------------------------ parameters */

void sea_imager_params_default(sea_imager_params *p)
{
    memset(p, 0, sizeof *p);
    p->psf = SEA_PSF_NONE;
    p->psf_sigma = 0.0;
    p->f_number = 0.0;
    p->pitch = 0.0;
    p->mtf = NULL;
    p->fill_factor = 1.0;
    p->netd = 0.0;
    p->netd_temperature = 300.0;
    p->noise_seed = 1;
    p->fpn_gain = 0.0;
    p->fpn_offset = 0.0;
    p->fpn_seed = 1;
    p->gain = 0.0;
    p->offset = 0.0;
    p->bit_depth = 14;
}

int sea_imager_params_from_scene(const sea_scene *sc, sea_imager_params *p)
{
    sea_imager_params_default(p);
    int any = 0;
    if (!isnan(sc->psf_sigma)) {
        p->psf = SEA_PSF_GAUSSIAN;
        p->psf_sigma = sc->psf_sigma;
        any = 1;
    }
    if (!isnan(sc->f_number)) {
        p->psf = SEA_PSF_DIFFRACTION;
        p->f_number = sc->f_number;
        p->pitch = sc->pitch;
        any = 1;
    }
    if (sc->mtf_file[0] != '\0') {
        p->psf = SEA_PSF_TABLE;
        any = 1;
    }
    if (!isnan(sc->fill_factor)) {
        p->fill_factor = sc->fill_factor;
        any = 1;
    }
    if (!isnan(sc->netd)) {
        p->netd = sc->netd;
        any = 1;
    }
    if (!isnan(sc->fpn_gain)) {
        p->fpn_gain = sc->fpn_gain;
        any = 1;
    }
    if (!isnan(sc->fpn_offset)) {
        p->fpn_offset = sc->fpn_offset;
        any = 1;
    }
    if (!isnan(sc->gain)) {
        p->gain = sc->gain;
        p->offset = isnan(sc->offset) ? 0.0 : sc->offset;
        any = 1;
    }
    p->netd_temperature = sc->netd_temperature;
    p->noise_seed = sc->noise_seed;
    p->fpn_seed = sc->fpn_seed;
    p->bit_depth = sc->bit_depth;
    return any;
}

/* "camera: name: value is out of range (allowed: [lo, hi] unit)", "(lo"
 * when lo_open: the scene's form (the value to as many digits as tell it
 * from the bound, the bounds as the scene prints them). */
static sea_status range_fail(const char *name, double v, double lo, double hi, int lo_open,
                             const char *unit, sea_error *err)
{
    char v_txt[SEA_TEXT_REAL_CHARS];
    return sea_fail(err, SEA_ERR_DOMAIN,
                    "camera: %s: %s is out of range (allowed: %c%.10g, %.10g]%s%s)", name,
                    sea_text_format_real(v, v_txt), lo_open ? '(' : '[', lo, hi,
                    unit[0] ? " " : "", unit);
}

static sea_status check_range(const char *name, double v, double lo, double hi, int lo_open,
                              const char *unit, sea_error *err)
{
    if ((lo_open ? v > lo : v >= lo) && v <= hi)
        return SEA_OK;
    return range_fail(name, v, lo, hi, lo_open, unit, err);
}

static sea_status check_params(const sea_imager_params *p, const sea_band *b, int width,
                               int height, sea_error *err)
{
    sea_status st;
#define CHECK(expr)                                                                            \
    do {                                                                                       \
        if ((st = (expr)) != SEA_OK)                                                           \
            return st;                                                                         \
    } while (0)
    if (width < 1 || width > SEA_IMAGER_SIDE_MAX || height < 1 || height > SEA_IMAGER_SIDE_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: image size %d x %d is outside [1, %d] pixels a side", width,
                        height, SEA_IMAGER_SIDE_MAX);
    switch (p->psf) {
    case SEA_PSF_NONE:
        break;
    case SEA_PSF_GAUSSIAN:
        CHECK(check_range("psf_sigma", p->psf_sigma, 0.0, SEA_IMAGER_SIGMA_MAX, 1, "pixels",
                          err));
        break;
    case SEA_PSF_DIFFRACTION:
        CHECK(check_range("f_number", p->f_number, SEA_IMAGER_F_NUMBER_MIN,
                          SEA_IMAGER_F_NUMBER_MAX, 0, "", err));
        /* in metres against the bounds times 1e-6, the product the scene
         * makes of a value in um: a scene's bound passes here too */
        if (!(p->pitch >= SEA_IMAGER_PITCH_MIN_UM * 1e-6 &&
              p->pitch <= SEA_IMAGER_PITCH_MAX_UM * 1e-6))
            return range_fail("pitch", p->pitch * 1e6, SEA_IMAGER_PITCH_MIN_UM,
                              SEA_IMAGER_PITCH_MAX_UM, 0, "um", err);
        break;
    case SEA_PSF_TABLE: {
        const sea_mtf_table *t = p->mtf;
        if (t == NULL || t->n < 2)
            return sea_fail(err, SEA_ERR_DOMAIN, "camera: mtf: a table of at least two rows is "
                                                 "needed");
        if (!(t->frequency[0] == 0.0 && t->value[0] == 1.0))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "camera: mtf: the first row must be 0,1 (an MTF normalised at 0)");
        for (size_t i = 0; i < t->n; i++) {
            if (!(t->value[i] >= 0.0 && t->value[i] <= 1.0) ||
                !(t->frequency[i] <= SEA_IMAGER_MTF_FREQ_MAX) ||
                (i > 0 && !(t->frequency[i] > t->frequency[i - 1])))
                return sea_fail(err, SEA_ERR_DOMAIN,
                                "camera: mtf: row %zu (%g, %g) is not an MTF (allowed: "
                                "frequencies increasing in [0, %g] cycles per pixel, values "
                                "in [0, 1])",
                                i + 1, t->frequency[i], t->value[i], SEA_IMAGER_MTF_FREQ_MAX);
        }
        break;
    }
    default:
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: psf: %d is no kind (allowed: none, gaussian, diffraction, "
                        "table)",
                        (int)p->psf);
    }
    CHECK(check_range("fill_factor", p->fill_factor, 0.0, 1.0, 1, "", err));
    CHECK(check_range("netd", p->netd, 0.0, SEA_IMAGER_NETD_MAX, 0, "K", err));
    CHECK(check_range("netd_temperature", p->netd_temperature, SEA_IMAGER_T_MIN,
                      SEA_IMAGER_T_MAX, 0, "K", err));
    CHECK(check_range("fpn_gain", p->fpn_gain, 0.0, SEA_IMAGER_FPN_GAIN_MAX, 0, "", err));
    CHECK(check_range("fpn_offset", p->fpn_offset, 0.0, SEA_IMAGER_FPN_OFFSET_MAX, 0, "K",
                      err));
    CHECK(check_range("gain", p->gain, 0.0, SEA_IMAGER_GAIN_MAX, 0, "counts per radiance unit",
                      err));
    CHECK(check_range("offset", p->offset, -SEA_IMAGER_OFFSET_MAX, SEA_IMAGER_OFFSET_MAX, 0,
                      "counts", err));
    if (p->bit_depth < SEA_IMAGER_BITS_MIN || p->bit_depth > SEA_IMAGER_BITS_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: bit_depth: %d is out of range (allowed: an integer in [%d, %d])",
                        p->bit_depth, SEA_IMAGER_BITS_MIN, SEA_IMAGER_BITS_MAX);
    /* the band */
    if (b == NULL || b->n < 1 || b->wavelength == NULL || b->weight == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "camera: the band needs at least one sample");
    double wsum = 0.0;
    for (size_t i = 0; i < b->n; i++) {
        if (!(b->wavelength[i] > 0.0 && isfinite(b->wavelength[i])) ||
            !(b->weight[i] >= 0.0 && isfinite(b->weight[i])))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "camera: band sample %zu: wavelength %g m, weight %g (allowed: a "
                            "positive wavelength, a weight >= 0)",
                            i, b->wavelength[i], b->weight[i]);
        wsum += b->weight[i];
    }
    if (!(wsum > 0.0) || (b->n == 1 && !(b->weight[0] > 0.0)))
        return sea_fail(err, SEA_ERR_DOMAIN, "camera: the band's weights are all 0 (allowed: "
                                             "some positive)");
    if (!(b->unit > 0.0 && isfinite(b->unit)))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: the band's unit %g is not positive (allowed: 1e-6 for one "
                        "wavelength, 1 for a band)",
                        b->unit);
#undef CHECK
    return SEA_OK;
}

/* ------------------------------------------------------- transfer function */

/* The incoherent MTF of a circular pupil at s = nu / nu_c. */
static double mtf_circular(double s)
{
    if (s >= 1.0)
        return 0.0;
    return (2.0 / M_PI) * (acos(s) - s * sqrt(1.0 - s * s));
}

static double sinc(double x)
{
    if (fabs(x) < 1e-8)
        return 1.0;
    return sin(M_PI * x) / (M_PI * x);
}

/* The optics' MTF at radial frequency nu (cycles per pixel), exactly. */
static double optics_mtf(const sea_imager *im, double nu)
{
    const sea_imager_params *p = &im->p;
    switch (p->psf) {
    case SEA_PSF_GAUSSIAN:
        return exp(-2.0 * M_PI * M_PI * p->psf_sigma * p->psf_sigma * nu * nu);
    case SEA_PSF_DIFFRACTION: {
        /* the MTF of the band's mean Airy pattern (airy_weights) */
        double m = 0.0;
        for (size_t i = 0; i < im->band.n; i++)
            m += im->airy_w[i] * mtf_circular(nu * im->wl[i] * p->f_number / p->pitch);
        return m;
    }
    case SEA_PSF_TABLE:
        return mtf_table_at(&im->mtf, nu);
    case SEA_PSF_NONE:
    default:
        return 1.0;
    }
}

/* The samples' shares of the band's PSF: its weights times the radiance
 * of a black body at netd_temperature, normalised; a scene near that
 * temperature adds the samples' Airy patterns in these proportions. */
static sea_status airy_weights(sea_imager *im, sea_error *err)
{
    const size_t n = im->band.n;
    if ((im->airy_w = malloc(n * sizeof *im->airy_w)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "camera: out of memory");
    double w = 0.0;
    for (size_t i = 0; i < n; i++) {
        im->airy_w[i] = im->wt[i] * sea_planck_radiance(im->wl[i], im->p.netd_temperature);
        w += im->airy_w[i];
    }
    if (!(w > 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: the band carries no radiance at %g K: no PSF follows",
                        im->p.netd_temperature);
    for (size_t i = 0; i < n; i++)
        im->airy_w[i] /= w;
    return SEA_OK;
}

/* The detector's active area against the render's full pixel, along one
 * axis. */
static double detector_ratio(const sea_imager *im, double nu)
{
    const double a = sqrt(im->p.fill_factor);
    return sinc(a * nu) / sinc(nu);
}

double sea_imager_mtf(const sea_imager *im, double nu_x, double nu_y)
{
    return optics_mtf(im, hypot(nu_x, nu_y)) * detector_ratio(im, nu_x) *
           detector_ratio(im, nu_y);
}

int sea_imager_filters(const sea_imager *im)
{
    return im->H != NULL;
}

int sea_imager_counts(const sea_imager *im)
{
    return im->p.gain > 0.0;
}

double sea_imager_noise_radiance(const sea_imager *im)
{
    return im->sigma_L;
}

/* H on the DCT grid: entry (ky, kx) at ky W + kx, frequency (kx / 2W,
 * ky / 2H) cycles per pixel, times the transforms' normalisation 1 / (4 W H)
 * (FFTW's REDFT01 inverts REDFT10 up to 2n a dimension). */
static sea_status make_filter(sea_imager *im, sea_error *err)
{
    const int W = im->width, Hh = im->height;
    const size_t n = (size_t)W * (size_t)Hh;
    double *radial = malloc((SEA_MTF_NODES + 1) * sizeof *radial);
    double *dx = malloc((size_t)W * sizeof *dx), *dy = malloc((size_t)Hh * sizeof *dy);
    im->H = fftw_alloc_real(n);
    double *scratch = fftw_alloc_real(n);
    sea_status st = SEA_OK;
    if (radial == NULL || dx == NULL || dy == NULL || im->H == NULL || scratch == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "camera: out of memory for the %d x %d filter", W, Hh);
        goto done;
    }
    const double h = SEA_NU_CORNER / SEA_MTF_NODES;
    for (int i = 0; i <= SEA_MTF_NODES; i++)
        radial[i] = optics_mtf(im, i * h);
    for (int x = 0; x < W; x++)
        dx[x] = detector_ratio(im, x / (2.0 * W));
    for (int y = 0; y < Hh; y++)
        dy[y] = detector_ratio(im, y / (2.0 * Hh));
    const double norm = 1.0 / (4.0 * (double)W * (double)Hh);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < Hh; y++) {
        const double nu_y = y / (2.0 * Hh);
        for (int x = 0; x < W; x++) {
            const double nu = hypot(x / (2.0 * W), nu_y);
            const double t = fmin(nu / h, (double)SEA_MTF_NODES);
            const int i = (int)fmin(t, SEA_MTF_NODES - 1.0);
            const double a = t - i;
            const double m = (1.0 - a) * radial[i] + a * radial[i + 1];
            im->H[(size_t)y * W + x] = m * dx[x] * dy[y] * norm;
        }
    }
    /* Plan in place on a scratch array (FFTW_ESTIMATE does not touch it);
     * sea_imager_apply executes the plans on arrays of its own, which
     * fftw_alloc_real aligns as this one.  FFTW_MEASURE took 4.8 s to plan
     * at 1920 x 1080 for a transform no faster. */
    sea_fftw_planner_lock();
    im->forward = fftw_plan_r2r_2d(Hh, W, scratch, scratch, FFTW_REDFT10, FFTW_REDFT10,
                                   FFTW_ESTIMATE);
    im->inverse = fftw_plan_r2r_2d(Hh, W, scratch, scratch, FFTW_REDFT01, FFTW_REDFT01,
                                   FFTW_ESTIMATE);
    sea_fftw_planner_unlock();
    if (im->forward == NULL || im->inverse == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "camera: FFTW cannot plan a %d x %d DCT", W, Hh);
done:
    free(radial);
    free(dx);
    free(dy);
    fftw_free(scratch);
    return st;
}

/* ---------------------------------------------------------- temperature */

static void make_temperature_table(sea_imager *im)
{
    im->tb_first = SEA_IM_TB_N;
    for (int j = SEA_IM_TB_N - 1; j >= 0; j--) {
        const double L = sea_band_radiance(&im->band, exp(SEA_IM_TB_LNT0 + j * SEA_IM_TB_STEP));
        im->tb_lnL[j] = L > 0.0 ? log(L) : -INFINITY;
        if (!(L > 0.0) || (j + 1 < SEA_IM_TB_N && !(im->tb_lnL[j] < im->tb_lnL[j + 1])))
            break;
        im->tb_first = j;
    }
    const int f = im->tb_first;
    if (f + 4 > SEA_IM_TB_N)
        return;
    /* each interval's cubic: Newton's divided differences on the nodes
     * a - 1 .. a + 2 (abscissae relative to node a), expanded to powers */
    for (int a = f + 1; a <= SEA_IM_TB_N - 3; a++) {
        double d[4], c[4];
        for (int j = 0; j < 4; j++) {
            d[j] = im->tb_lnL[a - 1 + j] - im->tb_lnL[a];
            c[j] = SEA_IM_TB_LNT0 + (a - 1 + j) * SEA_IM_TB_STEP;
        }
        for (int level = 1; level < 4; level++)
            for (int j = 3; j >= level; j--)
                c[j] = (c[j] - c[j - 1]) / (d[j] - d[j - level]);
        /* p(t) = c0 + (t - d0)(c1 + (t - d1)(c2 + (t - d2) c3)), from the inside out */
        double poly[4] = { c[3], 0.0, 0.0, 0.0 };
        for (int j = 2; j >= 0; j--) {
            /* poly <- poly (t - d_j) + c_j */
            for (int m = 3; m >= 1; m--)
                poly[m] = poly[m - 1] - d[j] * poly[m];
            poly[0] = c[j] - d[j] * poly[0];
        }
        memcpy(im->tb_coef[a], poly, sizeof poly);
    }
    im->guide_lo = im->tb_lnL[f + 1];
    const double width = (im->tb_lnL[SEA_IM_TB_N - 2] - im->guide_lo) / SEA_IM_GUIDE_N;
    im->guide_inv = 1.0 / width;
    for (int k = 0; k < SEA_IM_GUIDE_N; k++) {
        const size_t a = sea_interval_of(im->tb_lnL + f, (size_t)(SEA_IM_TB_N - f),
                                         im->guide_lo + k * width);
        im->guide[k] = f + (int)a < f + 1 ? f + 1 : f + (int)a;
    }
}

/* The apparent temperature of a radiance in the image's units: the
 * table's cubic in ln L where ln L lies between its second and
 * next-to-last finite nodes, else sea_band_temperature; 0 for L <= 0. */
double sea_imager_temperature(const sea_imager *im, double L)
{
    if (!(L > 0.0))
        return 0.0;
    if (im->band.n == 1)
        return sea_planck_brightness_temperature(im->wl[0], L / (im->band.unit * im->wt[0]));
    const int f = im->tb_first;
    const double lnL = log(L);
    if (f + 4 > SEA_IM_TB_N || !(lnL > im->tb_lnL[f + 1] && lnL < im->tb_lnL[SEA_IM_TB_N - 2]))
        return sea_band_temperature(&im->band, L);
    const double g = (lnL - im->guide_lo) * im->guide_inv;
    int a = im->guide[g < SEA_IM_GUIDE_N - 1 ? (int)g : SEA_IM_GUIDE_N - 1];
    /* the interval tb_lnL[a] < ln L <= tb_lnL[a + 1] (the guide's cell
     * starts at or before ln L; the step back only guards its rounding) */
    while (lnL > im->tb_lnL[a + 1])
        a++;
    while (a > f + 1 && lnL <= im->tb_lnL[a])
        a--;
    const double t = lnL - im->tb_lnL[a];
    const double *c = im->tb_coef[a];
    return exp(c[0] + t * (c[1] + t * (c[2] + t * c[3])));
}

/* ------------------------------------------------------------- the plan */

sea_status sea_imager_alloc(const sea_imager_params *p, const sea_band *band, int width,
                            int height, sea_imager **out, sea_error *err)
{
    *out = NULL;
    sea_status st = check_params(p, band, width, height, err);
    if (st != SEA_OK)
        return st;
    sea_imager *im = calloc(1, sizeof *im);
    if (im == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "camera: out of memory");
    im->p = *p;
    im->p.mtf = NULL;
    im->width = width;
    im->height = height;
    const size_t npix = (size_t)width * (size_t)height;
    /* copies: nothing of the caller's is kept */
    im->wl = malloc(band->n * sizeof *im->wl);
    im->wt = malloc(band->n * sizeof *im->wt);
    if (im->wl == NULL || im->wt == NULL)
        goto nomem;
    memcpy(im->wl, band->wavelength, band->n * sizeof *im->wl);
    memcpy(im->wt, band->weight, band->n * sizeof *im->wt);
    im->band = (sea_band){ band->n, im->wl, im->wt, band->unit };
    if (p->psf == SEA_PSF_TABLE) {
        im->mtf.n = p->mtf->n;
        im->mtf.frequency = malloc(p->mtf->n * sizeof(double));
        im->mtf.value = malloc(p->mtf->n * sizeof(double));
        if (im->mtf.frequency == NULL || im->mtf.value == NULL)
            goto nomem;
        memcpy(im->mtf.frequency, p->mtf->frequency, p->mtf->n * sizeof(double));
        memcpy(im->mtf.value, p->mtf->value, p->mtf->n * sizeof(double));
        im->p.mtf = &im->mtf;
    }
    make_temperature_table(im);
    im->max_count = ldexp(1.0, p->bit_depth) - 1.0;
    /* the filter, when there is one to apply */
    if (p->psf == SEA_PSF_DIFFRACTION && (st = airy_weights(im, err)) != SEA_OK)
        goto fail;
    if (p->psf != SEA_PSF_NONE || p->fill_factor < 1.0)
        if ((st = make_filter(im, err)) != SEA_OK)
            goto fail;
    /* the noise, in radiance: NETD and the offsets' kelvins times dL/dT */
    const double dLdT = sea_band_radiance_dT(&im->band, p->netd_temperature);
    im->sigma_L = p->netd * dLdT;
    if (p->fpn_gain > 0.0) {
        if ((im->fpn_gain = malloc(npix * sizeof(float))) == NULL)
            goto nomem;
        normals_fill(stream_key(p->fpn_seed, TAG_FPN_GAIN, 0), p->fpn_gain, 1.0, npix,
                     im->fpn_gain);
    }
    if (p->fpn_offset > 0.0) {
        if ((im->fpn_offset = malloc(npix * sizeof(float))) == NULL)
            goto nomem;
        normals_fill(stream_key(p->fpn_seed, TAG_FPN_OFFSET, 0), p->fpn_offset * dLdT, 0.0,
                     npix, im->fpn_offset);
    }
    *out = im;
    return SEA_OK;
nomem:
    st = sea_fail(err, SEA_ERR_NOMEM, "camera: out of memory for a %d x %d image", width, height);
fail:
    sea_imager_free(im);
    return st;
}

void sea_imager_free(sea_imager *im)
{
    if (im == NULL)
        return;
    if (im->forward != NULL || im->inverse != NULL) {
        sea_fftw_planner_lock();
        if (im->forward != NULL)
            fftw_destroy_plan(im->forward);
        if (im->inverse != NULL)
            fftw_destroy_plan(im->inverse);
        sea_fftw_planner_unlock();
    }
    fftw_free(im->H);
    free(im->wl);
    free(im->wt);
    free(im->airy_w);
    sea_imager_mtf_free(&im->mtf);
    free(im->fpn_gain);
    free(im->fpn_offset);
    free(im);
}

/* ------------------------------------------------------------ a frame */

sea_status sea_imager_image_alloc(const sea_imager *im, sea_imager_image *out, sea_error *err)
{
    memset(out, 0, sizeof *out);
    const size_t n = (size_t)im->width * (size_t)im->height;
    out->width = im->width;
    out->height = im->height;
    out->radiance = calloc(n, sizeof(float));
    out->temperature = calloc(n, sizeof(float));
    if (sea_imager_counts(im))
        out->counts = calloc(n, sizeof(uint16_t));
    if (out->radiance == NULL || out->temperature == NULL ||
        (sea_imager_counts(im) && out->counts == NULL)) {
        sea_imager_image_free(out);
        return sea_fail(err, SEA_ERR_NOMEM, "camera: out of memory for a %d x %d frame",
                        im->width, im->height);
    }
    return SEA_OK;
}

void sea_imager_image_free(sea_imager_image *out)
{
    if (out == NULL)
        return;
    free(out->radiance);
    free(out->temperature);
    free(out->counts);
    memset(out, 0, sizeof *out);
}

sea_status sea_imager_apply(const sea_imager *im, const sea_image *img, uint64_t frame,
                            sea_imager_image *out, sea_error *err)
{
    const int W = im->width, Hh = im->height;
    if (img->width != W || img->height != Hh || img->radiance == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: the image is %d x %d, the camera's %d x %d (allowed: the "
                        "same size)",
                        img->width, img->height, W, Hh);
    if (out->width != W || out->height != Hh || out->radiance == NULL ||
        out->temperature == NULL || (sea_imager_counts(im) && out->counts == NULL))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: the output frame is not allocated for this camera "
                        "(sea_imager_image_alloc)");
    const long n = (long)W * (long)Hh;
    double *buf = NULL;
    if (im->H != NULL) {
        if ((buf = fftw_alloc_real((size_t)n)) == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "camera: out of memory for a %d x %d transform",
                            W, Hh);
#pragma omp parallel for schedule(static)
        for (long q = 0; q < n; q++)
            buf[q] = img->radiance[q];
        fftw_execute_r2r(im->forward, buf, buf);
#pragma omp parallel for schedule(static)
        for (long q = 0; q < n; q++)
            buf[q] *= im->H[q];
        fftw_execute_r2r(im->inverse, buf, buf);
    }
    const uint64_t key = stream_key(im->p.noise_seed, TAG_TEMPORAL, frame);
    const double sigma = im->sigma_L, gain = im->p.gain, offset = im->p.offset;
    const double max_count = im->max_count;
    const int counts = sea_imager_counts(im);
    size_t high = 0, low = 0;
    /* pixels in pairs, which share their normal draws */
#pragma omp parallel for schedule(static) reduction(+ : high, low)
    for (long k = 0; k < (n + 1) / 2; k++) {
        double z[2] = { 0.0, 0.0 };
        if (sigma > 0.0)
            normal_pair(key, (uint64_t)k, z);
        for (long q = 2 * k; q < 2 * k + 2 && q < n; q++) {
            double L = buf != NULL ? buf[q] : (double)img->radiance[q];
            if (im->fpn_gain != NULL)
                L *= im->fpn_gain[q];
            if (im->fpn_offset != NULL)
                L += im->fpn_offset[q];
            L += sigma * z[q - 2 * k];
            out->radiance[q] = (float)L;
            out->temperature[q] = (float)sea_imager_temperature(im, L);
            if (!counts)
                continue;
            const double v = offset + gain * L;
            if (v > max_count) {
                out->counts[q] = (uint16_t)max_count;
                high++;
            } else if (!(v >= 0.0)) {
                out->counts[q] = 0;
                low++;
            } else {
                out->counts[q] = (uint16_t)floor(v + 0.5);
            }
        }
    }
    fftw_free(buf);
    out->saturated_high = high;
    out->saturated_low = low;
    return SEA_OK;
}

/* ------------------------------------------------------------ the scene */

sea_status sea_imager_from_render(const sea_view *r, sea_imager **out, sea_error *err)
{
    *out = NULL;
    const sea_scene *sc = sea_view_scene(r);
    sea_imager_params p;
    if (!sea_imager_params_from_scene(sc, &p))
        return SEA_OK;
    sea_mtf_table t = { 0, NULL, NULL };
    sea_status st;
    if (p.psf == SEA_PSF_TABLE) {
        if ((st = sea_imager_mtf_load(sc->mtf_file, &t, err)) != SEA_OK)
            return st;
        p.mtf = &t;
    }
    sea_band band;
    sea_view_band(r, &band);
    st = sea_imager_alloc(&p, &band, sc->width, sc->height, out, err);
    sea_imager_mtf_free(&t);
    return st;
}

/* ------------------------------------------------------------ tolerance */

double sea_imager_tolerance_from_netd(const sea_band *b, double netd, double netd_temperature,
                                      double scene_temperature, double fraction)
{
    return fraction * netd * sea_band_radiance_dT(b, netd_temperature) /
           sea_band_radiance(b, scene_temperature);
}

/* The band's rule for the tolerance before the render chooses its samples:
 * (dL/dT) / L varies smoothly over a band (0.020 to 0.0136 per K from 8 to
 * 12 um at 300 K), which 64 Gauss-Legendre nodes integrate far below the
 * tolerance's own precision. */
enum { SEA_TOL_BAND_NODES = 64 };

static double response_at(const sea_response *resp, double wl)
{
    if (resp->n == 0)
        return 1.0;
    if (wl < resp->wavelength[0] || wl > resp->wavelength[resp->n - 1])
        return 0.0;
    const size_t lo = sea_interval_of(resp->wavelength, resp->n, wl);
    const double a = (wl - resp->wavelength[lo]) / (resp->wavelength[lo + 1] - resp->wavelength[lo]);
    return (1.0 - a) * resp->value[lo] + a * resp->value[lo + 1];
}

sea_status sea_imager_scene_tolerance(const sea_scene *sc, double fraction, double *tol,
                                      sea_error *err)
{
    if (isnan(sc->netd) || !(sc->netd > 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: no [sensor] netd: the tolerance cannot follow from it");
    if (!(fraction > 0.0 && fraction <= 1.0))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: the NETD's fraction %g is outside (0, 1]", fraction);
    if (sc->wavelength > 0.0) {
        const double one = 1.0;
        const sea_band b = { 1, &sc->wavelength, &one, 1e-6 };
        *tol = sea_imager_tolerance_from_netd(&b, sc->netd, sc->netd_temperature, sc->temperature,
                                              fraction);
        return SEA_OK;
    }
    sea_response resp = { 0, NULL, NULL };
    sea_status st;
    if (sc->response_file[0] != '\0' &&
        (st = sea_response_load(sc->response_file, &resp, err)) != SEA_OK)
        return st;
    double wl[SEA_TOL_BAND_NODES], wt[SEA_TOL_BAND_NODES];
    gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc(SEA_TOL_BAND_NODES);
    if (gl == NULL) {
        sea_response_free(&resp);
        return sea_fail(err, SEA_ERR_NOMEM, "camera: out of memory for a quadrature rule");
    }
    for (size_t i = 0; i < SEA_TOL_BAND_NODES; i++) {
        double x, w;
        gsl_integration_glfixed_point(sc->band_min, sc->band_max, i, &x, &w, gl);
        wl[i] = x;
        wt[i] = w * response_at(&resp, x);
    }
    gsl_integration_glfixed_table_free(gl);
    sea_response_free(&resp);
    const sea_band b = { SEA_TOL_BAND_NODES, wl, wt, 1.0 };
    *tol = sea_imager_tolerance_from_netd(&b, sc->netd, sc->netd_temperature, sc->temperature,
                                          fraction);
    if (!(*tol > 0.0 && isfinite(*tol)))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "camera: the response is zero over the band: no tolerance follows");
    return SEA_OK;
}
