/* arrays.c - .npy and CSV writers of images (arrays.h). */
#include "config.h"

#include <errno.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "arrays.h"

/* The largest side and plane count the header is sized for (see
 * sea_arrays_npy_header); EXR images are far smaller (65536 a side, 64
 * channels in seabake's writer). */
static const size_t ARRAYS_SIDE_MAX = (size_t)1 << 31;

/* "\x93NUMPY", major 1, minor 0, then the uint16 header length. */
static const unsigned char NPY_MAGIC[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
enum { NPY_PREAMBLE = 10 }; /* magic, version, length */

size_t sea_arrays_npy_header(size_t height, size_t width, size_t n_planes, unsigned char *buf,
                             size_t size)
{
    char dict[160];
    int n;
    if (n_planes == 1)
        n = snprintf(dict, sizeof dict,
                     "{'descr': '<f4', 'fortran_order': False, 'shape': (%zu, %zu), }", height,
                     width);
    else
        n = snprintf(dict, sizeof dict,
                     "{'descr': '<f4', 'fortran_order': False, 'shape': (%zu, %zu, %zu), }", height,
                     width, n_planes);
    if (n < 0 || (size_t)n >= sizeof dict)
        return 0;
    /* the dictionary, then spaces up to the boundary, the last byte '\n'
     * (as NumPy pads it) */
    const size_t used = NPY_PREAMBLE + (size_t)n + 1;
    const size_t total = (used + SEA_ARRAYS_NPY_ALIGN - 1) / SEA_ARRAYS_NPY_ALIGN *
                         SEA_ARRAYS_NPY_ALIGN;
    if (total > size || total - NPY_PREAMBLE > UINT16_MAX)
        return 0;
    const size_t hlen = total - NPY_PREAMBLE;
    memcpy(buf, NPY_MAGIC, sizeof NPY_MAGIC);
    buf[8] = (unsigned char)(hlen & 0xff);
    buf[9] = (unsigned char)(hlen >> 8);
    memcpy(buf + NPY_PREAMBLE, dict, (size_t)n);
    memset(buf + NPY_PREAMBLE + n, ' ', total - NPY_PREAMBLE - (size_t)n - 1);
    buf[total - 1] = '\n';
    return total;
}

/* SEA_ERR_DOMAIN unless the sizes are ones the writers take. */
static sea_status check_sizes(size_t width, size_t height, const float *const *planes,
                              size_t n_planes, sea_error *err)
{
    if (width < 1 || height < 1 || width > ARRAYS_SIDE_MAX || height > ARRAYS_SIDE_MAX ||
        n_planes < 1 || n_planes > ARRAYS_SIDE_MAX || planes == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "image of %zu x %zu pixels and %zu planes: need 1 to 2^31 of each", width,
                        height, n_planes);
    for (size_t c = 0; c < n_planes; c++)
        if (planes[c] == NULL)
            return sea_fail(err, SEA_ERR_DOMAIN, "plane %zu has no data", c);
    /* one row of bytes must be addressable */
    if (width > SIZE_MAX / 4 / n_planes)
        return sea_fail(err, SEA_ERR_DOMAIN, "a row of %zu pixels of %zu planes is too large",
                        width, n_planes);
    return SEA_OK;
}

sea_status sea_arrays_write_npy(FILE *f, size_t width, size_t height, const float *const *planes,
                                size_t n_planes, sea_error *err)
{
    sea_status st = check_sizes(width, height, planes, n_planes, err);
    if (st != SEA_OK)
        return st;
    unsigned char header[256];
    const size_t hlen = sea_arrays_npy_header(height, width, n_planes, header, sizeof header);
    if (hlen == 0)
        return sea_fail(err, SEA_ERR_DOMAIN, ".npy header of shape (%zu, %zu, %zu) too long",
                        height, width, n_planes);
    const size_t row_bytes = 4 * width * n_planes;
    errno = 0; /* what a failed write sets is the reason given */
    unsigned char *row = malloc(row_bytes);
    if (row == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a row of %zu bytes", row_bytes);
    bool ok = fwrite(header, 1, hlen, f) == hlen;
    for (size_t y = 0; y < height && ok; y++) {
        unsigned char *b = row;
        for (size_t x = 0; x < width; x++)
            for (size_t c = 0; c < n_planes; c++) {
                /* the bits of the float, least significant byte first */
                uint32_t u;
                memcpy(&u, &planes[c][y * width + x], sizeof u);
                b[0] = (unsigned char)(u & 0xff);
                b[1] = (unsigned char)((u >> 8) & 0xff);
                b[2] = (unsigned char)((u >> 16) & 0xff);
                b[3] = (unsigned char)(u >> 24);
                b += 4;
            }
        ok = fwrite(row, 1, row_bytes, f) == row_bytes;
    }
    free(row);
    if (!ok || ferror(f))
        return sea_fail(err, SEA_ERR_IO, "cannot write the .npy data: %s",
                        errno ? strerror(errno) : "write error");
    return SEA_OK;
}

sea_status sea_arrays_write_csv(FILE *f, size_t width, size_t height, const char *const *names,
                                const float *const *planes, size_t n_planes, sea_error *err)
{
    sea_status st = check_sizes(width, height, planes, n_planes, err);
    if (st != SEA_OK)
        return st;
    for (size_t c = 0; c < n_planes; c++)
        if (names == NULL || names[c] == NULL || names[c][0] == '\0' ||
            strpbrk(names[c], ",\"\r\n") != NULL)
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "channel name '%s' cannot be a CSV column (empty, or a comma, quote "
                            "or line break in it)",
                            names && names[c] ? names[c] : "(null)");
    errno = 0; /* what a failed write sets is the reason given */
    fputs("x,y", f);
    for (size_t c = 0; c < n_planes; c++)
        fprintf(f, ",%s", names[c]);
    fputc('\n', f);
    for (size_t y = 0; y < height && !ferror(f); y++)
        for (size_t x = 0; x < width; x++) {
            fprintf(f, "%zu,%zu", x, y);
            for (size_t c = 0; c < n_planes; c++)
                fprintf(f, ",%.*g", SEA_ARRAYS_CSV_DIGITS, (double)planes[c][y * width + x]);
            fputc('\n', f);
        }
    if (ferror(f))
        return sea_fail(err, SEA_ERR_IO, "cannot write the CSV rows: %s",
                        errno ? strerror(errno) : "write error");
    return SEA_OK;
}
