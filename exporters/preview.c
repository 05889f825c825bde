/* preview.c - grey and RGB PNG previews through libpng, written atomically,
 * and their tone curves. */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdbool.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "internal.h"
#include "preview.h"

/* libpng reports errors through longjmp; the message is kept here. */
typedef struct {
    char msg[256];
} png_err_ctx;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_err_ctx *c = png_get_error_ptr(png);
    snprintf(c->msg, sizeof c->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

/* What encode writes: grey values through a tone curve, or RGB triples
 * in [0, 1]. */
typedef struct {
    int width, height, bits;
    const float *data;        /* grey: one value a pixel; rgb: three */
    const sea_png_tone *tone; /* NULL: RGB */
    const sea_png_text *text;
    size_t n_text;
} png_job;

/* Encodes rows into an open stream; returns 0 on success. */
static int encode(FILE *f, const png_job *job, png_err_ctx *ctx)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, ctx, on_png_error,
                                              on_png_warning);
    if (png == NULL) {
        snprintf(ctx->msg, sizeof ctx->msg, "cannot create a PNG writer");
        return -1;
    }
    png_infop info = png_create_info_struct(png);
    const int width = job->width, height = job->height, bits = job->bits;
    const size_t spp = job->tone ? 1 : 3, bpp = (bits == 16 ? 2 : 1) * spp;
    unsigned char *volatile row = malloc((size_t)width * bpp);
    png_textp volatile text = job->n_text ? calloc(job->n_text, sizeof(png_text)) : NULL;
    if (info == NULL || row == NULL || (job->n_text && text == NULL)) {
        snprintf(ctx->msg, sizeof ctx->msg, "out of memory");
        free(row);
        free(text);
        png_destroy_write_struct(&png, info ? &info : NULL);
        return -1;
    }
    if (setjmp(png_jmpbuf(png))) {
        free(row);
        free(text);
        png_destroy_write_struct(&png, &info);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, bits,
                 job->tone ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (job->tone)
        png_set_gAMA(png, info, 1.0);
    for (size_t i = 0; i < job->n_text; i++) {
        text[i].compression = PNG_TEXT_COMPRESSION_NONE;
        text[i].key = (png_charp)job->text[i].key;
        text[i].text = (png_charp)job->text[i].value;
    }
    if (job->n_text)
        png_set_text(png, info, text, (int)job->n_text);
    /* A preview is written once and looked at: deflate's fastest level and
     * one filter (Sub) instead of zlib's default level 6 and libpng's
     * per-row choice among five.  On a bake's 36 previews (512 x 512 facets,
     * six levels): 1.9 -> 0.36 s of CPU, 5.9 -> 7.1 MB. */
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_write_info(png, info);
    const double top = bits == 16 ? 65535.0 : 255.0;
    for (int y = 0; y < height; y++) {
        for (size_t x = 0; x < (size_t)width * spp; x++) {
            const double d = job->data[(size_t)y * (size_t)width * spp + x];
            double v = top * (job->tone ? sea_png_tone_map(job->tone, d) : d);
            v = v < 0.0 ? 0.0 : v > top ? top : v;
            const unsigned q = (unsigned)lround(v);
            if (bits == 16) {
                row[2 * x] = (unsigned char)(q >> 8); /* PNG is big-endian */
                row[2 * x + 1] = (unsigned char)(q & 0xff);
            } else {
                row[x] = (unsigned char)q;
            }
        }
        png_write_row(png, row);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    free(row);
    free(text);
    return 0;
}

/* A tEXt keyword: 1 to 79 printable Latin-1 characters, no leading,
 * trailing or double space. */
static int bad_keyword(const char *k)
{
    const size_t n = strlen(k);
    if (n < 1 || n > 79 || k[0] == ' ' || k[n - 1] == ' ')
        return 1;
    for (size_t i = 0; i < n; i++) {
        const unsigned char c = (unsigned char)k[i];
        if (c < 32 || (c > 126 && c < 161) || (c == ' ' && k[i + 1] == ' '))
            return 1;
    }
    return 0;
}

/* Checks a job, then writes it to a temporary name renamed to path. */
static sea_status write_job(const char *path, const png_job *job, sea_error *err)
{
    const int width = job->width, height = job->height, bits = job->bits;
    if (width < 1 || height < 1 || width > 1 << 20 || height > 1 << 20)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: image size %d x %d outside [1, 2^20]", path,
                        width, height);
    if (bits != 8 && bits != 16)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: PNG depth %d must be 8 or 16", path, bits);
    for (size_t i = 0; i < job->n_text; i++)
        if (job->text[i].key == NULL || job->text[i].value == NULL ||
            bad_keyword(job->text[i].key))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "%s: text keyword '%s' is not 1 to 79 printable characters", path,
                            job->text[i].key ? job->text[i].key : "(null)");
    const size_t spp = job->tone ? 1 : 3, n = (size_t)width * (size_t)height * spp;
    for (size_t i = 0; i < n; i++)
        if (isnan(job->data[i]))
            return sea_fail(err, SEA_ERR_NUMERIC, "%s: pixel (%zu, %zu) is NaN", path,
                            i / spp % (size_t)width, i / spp / (size_t)width);
    /* seabake's marked temporary beside path (tempfile.c): mode 0666 less
     * the umask, and a later run can prove it stale if this one dies */
    sea_temp_file tmp;
    int fd;
    const int te = sea_temp_open(&tmp, path, &fd);
    if (te != 0)
        return sea_fail(err, te == ENOMEM ? SEA_ERR_NOMEM : SEA_ERR_IO,
                        "%s: cannot create a temporary file: %s", path, strerror(te));
    FILE *f = fdopen(fd, "wb");
    if (f == NULL) {
        sea_status st = sea_fail(err, SEA_ERR_IO, "%s: %s", path, strerror(errno));
        close(fd);
        sea_temp_abort(&tmp);
        return st;
    }
    png_err_ctx ctx = { { 0 } };
    int rc = encode(f, job, &ctx);
    if (rc == 0 && (fflush(f) != 0 || ferror(f))) {
        snprintf(ctx.msg, sizeof ctx.msg, "%s", strerror(errno));
        rc = -1;
    }
    if (fclose(f) != 0 && rc == 0) {
        snprintf(ctx.msg, sizeof ctx.msg, "%s", strerror(errno));
        rc = -1;
    }
    if (rc != 0) {
        sea_temp_abort(&tmp);
        return sea_fail(err, SEA_ERR_IO, "%s: %s", path, ctx.msg);
    }
    const int ce = sea_temp_commit(&tmp, path);
    if (ce != 0)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot rename into place: %s", path,
                        strerror(ce));
    return SEA_OK;
}

sea_status sea_png_write_gray(const char *path, int width, int height, const float *data,
                              double lo, double hi, int bits, sea_error *err)
{
    if (!(isfinite(lo) && isfinite(hi) && lo < hi))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: display range [%g, %g] must be finite, lo < hi",
                        path, lo, hi);
    const sea_png_tone tone = {lo, hi, hi};
    const png_job job = {width, height, bits, data, &tone, NULL, 0};
    return write_job(path, &job, err);
}

sea_status sea_png_write_toned(const char *path, int width, int height, const float *data,
                               const sea_png_tone *tone, int bits, const sea_png_text *text,
                               size_t n_text, sea_error *err)
{
    if (tone == NULL || !(isfinite(tone->lo) && isfinite(tone->hi) && tone->lo < tone->hi) ||
        !(tone->knee > tone->lo && tone->knee <= tone->hi))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: tone curve is not one of sea_png_tone_init",
                        path);
    const png_job job = {width, height, bits, data, tone, text, n_text};
    return write_job(path, &job, err);
}

sea_status sea_png_write_rgb(const char *path, int width, int height, const float *rgb, int bits,
                             const sea_png_text *text, size_t n_text, sea_error *err)
{
    const png_job job = {width, height, bits, rgb, NULL, text, n_text};
    return write_job(path, &job, err);
}

/* ------------------------------------------------------------ tone curves */

sea_status sea_png_tone_init(double lo, double knee, double hi, sea_png_tone *tone,
                             sea_error *err)
{
    if (!(isfinite(lo) && isfinite(hi) && lo < hi) || isinf(knee) || knee <= lo)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "tone curve: lo %g, knee %g, hi %g: need finite lo < knee, lo < hi", lo,
                        knee, hi);
    tone->lo = lo;
    tone->hi = hi;
    /* one ramp when the knee is at or above hi, or when the upper ramp
     * would be steeper than the lower: hi <= lo + (knee - lo) / G */
    const bool two = !isnan(knee) && knee < hi && hi > lo + (knee - lo) / SEA_PNG_KNEE_GREY;
    tone->knee = two ? knee : hi;
    return SEA_OK;
}

sea_status sea_png_tone_linear(double lo, double hi, sea_png_tone *tone, sea_error *err)
{
    return sea_png_tone_init(lo, NAN, hi, tone, err);
}

double sea_png_tone_map(const sea_png_tone *t, double v)
{
    if (!(v > t->lo))
        return 0.0; /* and NaN */
    if (v >= t->hi)
        return 1.0;
    if (t->knee >= t->hi)
        return (v - t->lo) / (t->hi - t->lo);
    const double G = SEA_PNG_KNEE_GREY;
    if (v <= t->knee)
        return G * (v - t->lo) / (t->knee - t->lo);
    const double g = G + (1.0 - G) * (v - t->knee) / (t->hi - t->knee);
    return g < 1.0 ? g : 1.0;
}

/* ------------------------------------------------------------- quantiles */

/* The finite values of data in a fresh array; *m of them.  NULL without
 * memory. */
static float *finite_copy(const float *data, size_t n, size_t *m)
{
    float *v = malloc((n > 0 ? n : 1) * sizeof *v);
    *m = 0;
    if (v != NULL)
        for (size_t i = 0; i < n; i++)
            if (isfinite(data[i]))
                v[(*m)++] = data[i];
    return v;
}

/* The order statistics at idx[0..k) (ascending) of v[0..m), m > 0, in out;
 * reorders v. */
static void select_sorted(float *v, size_t m, const size_t *idx, size_t k, double *out)
{
    size_t base = 0;
    for (size_t i = 0; i < k; i++) {
        if (i == 0 || idx[i] != idx[i - 1]) {
            sea_select_kth_f(v + base, m - base, idx[i] - base);
            base = idx[i];
        }
        out[i] = v[idx[i]];
    }
}

size_t sea_png_quantiles(const float *data, size_t n, const double *p, size_t np, double *q)
{
    size_t m;
    for (size_t i = 0; i < np; i++)
        q[i] = NAN;
    float *v = finite_copy(data, n, &m);
    if (v == NULL)
        return (size_t)-1;
    if (m > 0 && np > 0) {
        size_t *idx = malloc(np * sizeof *idx), *order = malloc(np * sizeof *order);
        double *out = malloc(np * sizeof *out);
        if (idx == NULL || order == NULL || out == NULL) {
            free(idx);
            free(order);
            free(out);
            free(v);
            return (size_t)-1;
        }
        /* the indices in ascending order (insertion sort: np is small) */
        for (size_t i = 0; i < np; i++) {
            const double pi = p[i] > 0.0 ? (p[i] < 1.0 ? p[i] : 1.0) : 0.0;
            const size_t k = (size_t)floor(pi * (double)(m - 1));
            size_t j = i;
            while (j > 0 && idx[j - 1] > k) {
                idx[j] = idx[j - 1];
                order[j] = order[j - 1];
                j--;
            }
            idx[j] = k;
            order[j] = i;
        }
        select_sorted(v, m, idx, np, out);
        for (size_t i = 0; i < np; i++)
            q[order[i]] = out[i];
        free(idx);
        free(order);
        free(out);
    }
    free(v);
    return m;
}

void sea_png_range(const float *data, size_t n, double clip, double *lo, double *hi)
{
    size_t m;
    float *v = finite_copy(data, n, &m);
    if (v == NULL || m == 0) {
        free(v);
        *lo = 0.0;
        *hi = 1.0;
        return;
    }
    if (!(clip >= 0.0 && clip < 0.5))
        clip = 0.0;
    const size_t idx[2] = {(size_t)floor(clip * (double)(m - 1)),
                           (size_t)ceil((1.0 - clip) * (double)(m - 1))};
    double out[2];
    select_sorted(v, m, idx, 2, out);
    *lo = out[0];
    *hi = out[1];
    free(v);
    if (!(*hi > *lo)) {
        const double c = *lo, d = c != 0.0 ? 0.5 * fabs(c) : 0.5;
        *lo = c - d;
        *hi = c + d;
    }
}

void sea_png_tone_auto(const float *data, size_t n, sea_png_tone *tone)
{
    static const double p[4] = {0.005, 0.5, 0.995, 1.0};
    double q[4];
    const size_t m = sea_png_quantiles(data, n, p, 4, q);
    if (m == 0 || m == (size_t)-1) {
        sea_png_tone_linear(0.0, 1.0, tone, NULL);
        return;
    }
    double lo = q[0], hi = q[3];
    if (!(hi > lo)) {
        const double c = lo, d = c != 0.0 ? 0.5 * fabs(c) : 0.5;
        sea_png_tone_linear(c - d, c + d, tone, NULL);
        return;
    }
    double knee = 2.0 * q[1] - lo;
    if (!(knee > lo))
        knee = q[2] > lo ? q[2] : hi;
    sea_png_tone_init(lo, knee, hi, tone, NULL);
}

/* The finite values of the sea pixels (level > 0) and of the sky (level
 * 0) in two fresh arrays, *ns and *nk of them; false without memory. */
static bool split_sea_sky(const float *data, const float *level, size_t n, float **sea,
                          size_t *ns, float **sky, size_t *nk)
{
    *sea = malloc((n > 0 ? n : 1) * sizeof **sea);
    *sky = malloc((n > 0 ? n : 1) * sizeof **sky);
    *ns = *nk = 0;
    if (*sea == NULL || *sky == NULL) {
        free(*sea);
        free(*sky);
        *sea = *sky = NULL;
        return false;
    }
    for (size_t i = 0; i < n; i++)
        if (isfinite(data[i])) {
            if (level[i] > 0.0f)
                (*sea)[(*ns)++] = data[i];
            else
                (*sky)[(*nk)++] = data[i];
        }
    return true;
}

size_t sea_png_tone_sea(const float *data, const float *level, size_t n, sea_png_tone *tone)
{
    float *sea, *sky;
    size_t ns, nk;
    if (!split_sea_sky(data, level, n, &sea, &ns, &sky, &nk)) {
        sea_png_tone_auto(data, n, tone);
        return (size_t)-1;
    }
    free(sky);
    if (ns == 0) {
        free(sea);
        sea_png_tone_auto(data, n, tone);
        return 0;
    }
    static const double p[2] = {SEA_PNG_SEA_CLIP, 1.0 - SEA_PNG_SEA_CLIP};
    double q[2];
    const size_t m = sea_png_quantiles(sea, ns, p, 2, q);
    free(sea);
    if (m == (size_t)-1) {
        sea_png_tone_auto(data, n, tone);
        return (size_t)-1;
    }
    if (!(q[1] > q[0])) {
        const double c = q[0], d = c != 0.0 ? 0.5 * fabs(c) : 0.5;
        q[0] = c - d;
        q[1] = c + d;
    }
    sea_png_tone_linear(q[0], q[1], tone, NULL);
    return ns;
}

bool sea_png_sky_apart(const float *data, const float *level, size_t n)
{
    float *sea, *sky;
    size_t ns, nk;
    if (!split_sea_sky(data, level, n, &sea, &ns, &sky, &nk))
        return false;
    bool apart = false;
    if (ns > 0 && nk > 0) {
        static const double ps[2] = {SEA_PNG_SEA_CLIP, 1.0 - SEA_PNG_SEA_CLIP}, pk[1] = {0.5};
        double qs[2], qk[1];
        if (sea_png_quantiles(sea, ns, ps, 2, qs) != (size_t)-1 &&
            sea_png_quantiles(sky, nk, pk, 1, qk) != (size_t)-1) {
            const double range = qs[1] - qs[0];
            apart = qk[0] < qs[0] - range || qk[0] > qs[1] + range;
        }
    }
    free(sea);
    free(sky);
    return apart;
}
