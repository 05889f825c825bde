/* preview.c - grayscale PNG previews through libpng, written atomically. */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

/* Encodes rows into an open stream; returns 0 on success. */
static int encode(FILE *f, int width, int height, const float *data, double lo, double hi,
                  int bits, png_err_ctx *ctx)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, ctx, on_png_error,
                                              on_png_warning);
    if (png == NULL) {
        snprintf(ctx->msg, sizeof ctx->msg, "cannot create a PNG writer");
        return -1;
    }
    png_infop info = png_create_info_struct(png);
    const size_t bpp = bits == 16 ? 2 : 1;
    unsigned char *volatile row = malloc((size_t)width * bpp);
    if (info == NULL || row == NULL) {
        snprintf(ctx->msg, sizeof ctx->msg, "out of memory");
        free(row);
        png_destroy_write_struct(&png, info ? &info : NULL);
        return -1;
    }
    if (setjmp(png_jmpbuf(png))) {
        free(row);
        png_destroy_write_struct(&png, &info);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, bits, PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_gAMA(png, info, 1.0);
    png_write_info(png, info);
    const double top = bits == 16 ? 65535.0 : 255.0, scale = top / (hi - lo);
    for (int y = 0; y < height; y++) {
        for (int x = 0; x < width; x++) {
            double v = ((double)data[(size_t)y * (size_t)width + (size_t)x] - lo) * scale;
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
    return 0;
}

sea_status sea_png_write_gray(const char *path, int width, int height, const float *data,
                              double lo, double hi, int bits, sea_error *err)
{
    if (width < 1 || height < 1 || width > 1 << 20 || height > 1 << 20)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: image size %d x %d outside [1, 2^20]", path,
                        width, height);
    if (bits != 8 && bits != 16)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: PNG depth %d must be 8 or 16", path, bits);
    if (!(isfinite(lo) && isfinite(hi) && lo < hi))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: display range [%g, %g] must be finite, lo < hi",
                        path, lo, hi);
    const size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; i++)
        if (isnan(data[i]))
            return sea_fail(err, SEA_ERR_NUMERIC, "%s: pixel (%zu, %zu) is NaN", path,
                            i % (size_t)width, i / (size_t)width);
    const size_t len = strlen(path);
    char *tmp = malloc(len + 16);
    if (tmp == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    /* O_EXCL with a fresh suffix rather than mkstemp, whose 0600 mode would
     * reach the renamed file: the preview gets the umask's permissions. */
    static unsigned counter;
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; attempt++) {
        unsigned tag;
#pragma omp atomic capture
        tag = ++counter;
        snprintf(tmp, len + 16, "%s.tmp.%06x", path,
                 (unsigned)(((unsigned)getpid() * 2654435761u) ^ (tag * 40503u)) & 0xffffffu);
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST)
            break;
    }
    if (fd < 0) {
        sea_status st = sea_fail(err, SEA_ERR_IO, "%s: cannot create a temporary file: %s", path,
                                 strerror(errno));
        free(tmp);
        return st;
    }
    FILE *f = fdopen(fd, "wb");
    if (f == NULL) {
        sea_status st = sea_fail(err, SEA_ERR_IO, "%s: %s", path, strerror(errno));
        close(fd);
        unlink(tmp);
        free(tmp);
        return st;
    }
    png_err_ctx ctx = { { 0 } };
    int rc = encode(f, width, height, data, lo, hi, bits, &ctx);
    if (rc == 0 && (fflush(f) != 0 || ferror(f))) {
        snprintf(ctx.msg, sizeof ctx.msg, "%s", strerror(errno));
        rc = -1;
    }
    if (fclose(f) != 0 && rc == 0) {
        snprintf(ctx.msg, sizeof ctx.msg, "%s", strerror(errno));
        rc = -1;
    }
    if (rc == 0 && rename(tmp, path) != 0) {
        snprintf(ctx.msg, sizeof ctx.msg, "cannot rename into place: %s", strerror(errno));
        rc = -1;
    }
    if (rc != 0) {
        unlink(tmp);
        free(tmp);
        return sea_fail(err, SEA_ERR_IO, "%s: %s", path, ctx.msg);
    }
    free(tmp);
    return SEA_OK;
}

static int compare_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

void sea_png_range(const float *data, size_t n, double clip, double *lo, double *hi)
{
    float *v = malloc((n > 0 ? n : 1) * sizeof *v);
    size_t m = 0;
    if (v != NULL)
        for (size_t i = 0; i < n; i++)
            if (isfinite(data[i]))
                v[m++] = data[i];
    if (m == 0) {
        free(v);
        *lo = 0.0;
        *hi = 1.0;
        return;
    }
    qsort(v, m, sizeof *v, compare_float);
    if (!(clip >= 0.0 && clip < 0.5))
        clip = 0.0;
    const size_t a = (size_t)floor(clip * (double)(m - 1)), b = (size_t)ceil((1.0 - clip) * (double)(m - 1));
    *lo = v[a];
    *hi = v[b];
    free(v);
    if (!(*hi > *lo)) {
        const double c = *lo, d = c != 0.0 ? 0.5 * fabs(c) : 0.5;
        *lo = c - d;
        *hi = c + d;
    }
}
