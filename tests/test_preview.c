/* test_preview.c - PNG previews: values land where the linear ramp puts
 * them (read back with libpng), rows top-down, nothing left on failure. */
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "preview.h"
#include "unit.h"

/* Reads a grayscale PNG into 16-bit values; returns 0 on success. */
static int read_gray(const char *path, int *w, int *h, int *bits, unsigned **out)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return -1;
    *bits = (img.format & PNG_FORMAT_FLAG_LINEAR) ? 16 : 8;
    img.format = PNG_FORMAT_LINEAR_Y; /* 16-bit linear gray */
    png_uint_16 *buf = malloc(PNG_IMAGE_SIZE(img));
    if (buf == NULL || !png_image_finish_read(&img, NULL, buf, 0, NULL)) {
        free(buf);
        png_image_free(&img);
        return -1;
    }
    *w = (int)img.width;
    *h = (int)img.height;
    *out = malloc((size_t)*w * (size_t)*h * sizeof **out);
    for (size_t i = 0; i < (size_t)*w * (size_t)*h; i++)
        (*out)[i] = buf[i];
    free(buf);
    return 0;
}

static void tmp_dir(char *dir, size_t n)
{
    const char *base = getenv("TMPDIR");
    snprintf(dir, n, "%s/seabake-png.XXXXXX", base ? base : "/tmp");
    CU_ASSERT_FATAL(mkdtemp(dir) != NULL);
}

/* A 16-bit ramp round-trips: value v maps to 65535 (v - lo)/(hi - lo),
 * rounded (one count), clamped outside [lo, hi]; row 0 is the top. */
static void test_round_trip_16(void)
{
    char dir[512], path[600];
    tmp_dir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/ramp.png", dir);
    const int W = 7, H = 3;
    float v[21];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            v[y * W + x] = (float)(x - 1) * 0.25f + (float)y * 10.0f;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_png_write_gray(path, W, H, v, 0.0, 1.0, 16, &err), SEA_OK);
    int w, h, bits;
    unsigned *q = NULL;
    CU_ASSERT_EQUAL_FATAL(read_gray(path, &w, &h, &bits, &q), 0);
    CU_ASSERT_EQUAL(w, W);
    CU_ASSERT_EQUAL(h, H);
    CU_ASSERT_EQUAL(bits, 16);
    for (int x = 0; x < W; x++) {
        const double expect = fmin(fmax((x - 1) * 0.25, 0.0), 1.0) * 65535.0;
        CU_ASSERT(fabs((double)q[x] - expect) <= 1.0);
        CU_ASSERT_EQUAL(q[W + x], 65535u); /* rows below are >= 10: white */
    }
    free(q);
    /* 8 bits */
    CU_ASSERT_EQUAL_FATAL(sea_png_write_gray(path, W, H, v, -0.25, 1.25, 8, &err), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(read_gray(path, &w, &h, &bits, &q), 0);
    CU_ASSERT_EQUAL(bits, 8);
    CU_ASSERT(q[0] == 0u && q[W - 1] == 65535u);
    free(q);
    unlink(path);
    rmdir(dir);
}

/* Refused input leaves no file, and an existing one untouched. */
static void test_failures_leave_nothing(void)
{
    char dir[512], path[600];
    tmp_dir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/x.png", dir);
    float v[4] = { 0.0f, 1.0f, NAN, 2.0f };
    sea_error err;
    CU_ASSERT_EQUAL(sea_png_write_gray(path, 2, 2, v, 0.0, 1.0, 16, &err), SEA_ERR_NUMERIC);
    CU_ASSERT(strstr(err.msg, "(0, 1)") != NULL);
    CU_ASSERT(access(path, F_OK) != 0);
    v[2] = 0.5f;
    CU_ASSERT_EQUAL(sea_png_write_gray(path, 2, 2, v, 1.0, 1.0, 16, &err), SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_png_write_gray(path, 2, 2, v, 0.0, 1.0, 12, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(access(path, F_OK) != 0);
    char bad[700];
    snprintf(bad, sizeof bad, "%s/no/such/dir/x.png", dir);
    CU_ASSERT_EQUAL(sea_png_write_gray(bad, 2, 2, v, 0.0, 1.0, 8, &err), SEA_ERR_IO);
    CU_ASSERT(strstr(err.msg, bad) != NULL);
    /* the directory holds nothing else (no temporary left) */
    CU_ASSERT_EQUAL(rmdir(dir), 0);
}

static void test_range(void)
{
    float v[101];
    for (int i = 0; i <= 100; i++)
        v[i] = (float)i;
    v[50] = NAN;
    double lo, hi;
    sea_png_range(v, 101, 0.01, &lo, &hi);
    CU_ASSERT(lo >= 0.0 && lo <= 2.0);
    CU_ASSERT(hi >= 98.0 && hi <= 100.0);
    const float c[3] = { 5.0f, 5.0f, 5.0f };
    sea_png_range(c, 3, 0.01, &lo, &hi);
    CU_ASSERT(lo < 5.0 && hi > 5.0);
}

int test_preview_register(void)
{
    CU_pSuite s = CU_add_suite("preview", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "16- and 8-bit round trip", test_round_trip_16) ||
           !CU_add_test(s, "failures leave nothing", test_failures_leave_nothing) ||
           !CU_add_test(s, "display range", test_range);
}
