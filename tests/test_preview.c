/* test_preview.c - PNG previews: values land where the linear ramp or the
 * tone curve puts them (read back with libpng), rows top-down, nothing left
 * on failure; RGB previews round-trip; tEXt chunks are there; quantiles by
 * selection equal those of a sort. */
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

static int cmp_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Selection gives the order statistics a sort gives: random data, many
 * ties (a sky), sorted and reversed input, NaN and infinities skipped. */
static void test_quantiles_vs_sort(void)
{
    const size_t N = 10007;
    float *v = malloc(N * sizeof *v), *s = malloc(N * sizeof *s);
    CU_ASSERT_FATAL(v != NULL && s != NULL);
    unsigned seed = 12345;
    const double p[] = {0.0, 0.005, 0.25, 0.5, 0.5, 0.9, 0.995, 1.0};
    const size_t np = sizeof p / sizeof p[0];
    for (int kind = 0; kind < 5; kind++) {
        size_t m = 0;
        for (size_t i = 0; i < N; i++) {
            seed = seed * 1103515245u + 12345u;
            const float r = (float)((seed >> 8) & 0xffff) / 65536.0f;
            float x = kind == 0   ? r
                      : kind == 1 ? (r < 0.4f ? 260.0f : 280.0f + 200.0f * r * r)
                      : kind == 2 ? (float)i
                      : kind == 3 ? (float)(N - i)
                                  : (float)(i % 7);
            if (i % 101 == 3)
                x = i % 2 ? NAN : INFINITY;
            v[i] = x;
            if (isfinite(x))
                s[m++] = x;
        }
        qsort(s, m, sizeof *s, cmp_float);
        double q[8];
        CU_ASSERT_EQUAL(sea_png_quantiles(v, N, p, np, q), m);
        for (size_t i = 0; i < np; i++)
            CU_ASSERT_EQUAL(q[i], s[(size_t)floor(p[i] * (double)(m - 1))]);
        double lo, hi;
        sea_png_range(v, N, 0.005, &lo, &hi);
        CU_ASSERT_EQUAL(lo, s[(size_t)floor(0.005 * (double)(m - 1))]);
        CU_ASSERT_EQUAL(hi, s[(size_t)ceil(0.995 * (double)(m - 1))]);
    }
    /* none finite */
    v[0] = NAN;
    double q[1] = {0.0};
    CU_ASSERT_EQUAL(sea_png_quantiles(v, 1, p, 1, q), 0u);
    CU_ASSERT(isnan(q[0]));
    free(v);
    free(s);
}

/* The tone curve: lo black, hi white, the knee at SEA_PNG_KNEE_GREY,
 * linear below it, monotonic, slope continuous at the knee; linear when
 * the tail is short; invalid curves refused. */
static void test_tone_curve(void)
{
    sea_png_tone t;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_png_tone_init(260.0, 305.0, 503.0, &t, &err), SEA_OK);
    CU_ASSERT_EQUAL(t.knee, 305.0);
    CU_ASSERT_EQUAL(sea_png_tone_map(&t, 260.0), 0.0);
    CU_ASSERT_EQUAL(sea_png_tone_map(&t, 200.0), 0.0);
    CU_ASSERT_EQUAL(sea_png_tone_map(&t, 503.0), 1.0);
    CU_ASSERT_EQUAL(sea_png_tone_map(&t, 1e9), 1.0);
    CU_ASSERT(fabs(sea_png_tone_map(&t, 305.0) - SEA_PNG_KNEE_GREY) < 1e-12);
    CU_ASSERT(fabs(sea_png_tone_map(&t, 282.5) - 0.5 * SEA_PNG_KNEE_GREY) < 1e-12);
    double prev = -1.0;
    for (double v = 250.0; v <= 510.0; v += 0.25) {
        const double g = sea_png_tone_map(&t, v);
        CU_ASSERT(g >= prev && g >= 0.0 && g <= 1.0);
        prev = g;
    }
    /* linear on each ramp: the upper one through (305, G) and (503, 1) */
    CU_ASSERT(fabs(sea_png_tone_map(&t, 404.0) - 0.5 * (1.0 + SEA_PNG_KNEE_GREY)) < 1e-12);
    /* a short tail: linear lo to hi */
    CU_ASSERT_EQUAL_FATAL(sea_png_tone_init(288.0, 303.4, 304.2, &t, &err), SEA_OK);
    CU_ASSERT_EQUAL(t.knee, t.hi);
    CU_ASSERT(fabs(sea_png_tone_map(&t, 296.1) - 0.5) < 1e-12);
    CU_ASSERT_EQUAL(sea_png_tone_linear(1.0, 3.0, &t, &err), SEA_OK);
    CU_ASSERT(fabs(sea_png_tone_map(&t, 2.5) - 0.75) < 1e-12);
    CU_ASSERT_EQUAL(sea_png_tone_init(3.0, 4.0, 3.0, &t, &err), SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_png_tone_init(1.0, 0.5, 3.0, &t, &err), SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_png_tone_linear(1.0, INFINITY, &t, &err), SEA_ERR_DOMAIN);
    /* automatic: knee = 2 median - lo, lo the 0.5 % quantile, hi the max */
    float v[1001];
    for (int i = 0; i <= 1000; i++)
        v[i] = i < 400 ? 260.0f : i < 800 ? 280.0f + (float)(i - 400) / 40.0f : 300.0f + (float)(i - 800);
    sea_png_tone_auto(v, 1001, &t);
    CU_ASSERT_EQUAL(t.lo, 260.0);
    CU_ASSERT_EQUAL(t.hi, 500.0);
    CU_ASSERT(fabs(t.knee - (2.0 * (280.0 + 100.0 / 40.0) - 260.0)) < 1e-4);
    /* more than half at the minimum: the knee at the 99.5 % quantile */
    for (int i = 0; i <= 1000; i++)
        v[i] = i < 600 ? 260.0f : (float)i;
    sea_png_tone_auto(v, 1001, &t);
    CU_ASSERT(t.knee > 990.0 && t.knee <= 1000.0);
    /* constant */
    for (int i = 0; i <= 1000; i++)
        v[i] = 5.0f;
    sea_png_tone_auto(v, 1001, &t);
    CU_ASSERT(t.lo < 5.0 && t.hi > 5.0 && t.knee == t.hi);
}

/* Reads any PNG as 16-bit linear RGB through the simplified API. */
static int read_rgb(const char *path, int *w, int *h, png_uint_16 **out, unsigned *format)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return -1;
    *format = img.format;
    img.format = PNG_FORMAT_LINEAR_RGB;
    *out = malloc(PNG_IMAGE_SIZE(img));
    if (*out == NULL || !png_image_finish_read(&img, NULL, *out, 0, NULL)) {
        free(*out);
        png_image_free(&img);
        return -1;
    }
    *w = (int)img.width;
    *h = (int)img.height;
    return 0;
}

/* What the low-level reader sees of a PNG. */
typedef struct {
    int color_type, bits, gama, n_text;
    png_uint_32 width, height;
    unsigned v[64]; /* the first samples */
    char key[80], text[80];
} raw_png;

static int read_raw(const char *path, raw_png *r)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return -1;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    unsigned char *volatile row = NULL;
    if (info == NULL || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        free(row);
        fclose(f);
        return -1;
    }
    png_init_io(png, f);
    png_read_info(png, info);
    memset(r, 0, sizeof *r);
    r->color_type = png_get_color_type(png, info);
    r->bits = png_get_bit_depth(png, info);
    r->gama = png_get_valid(png, info, PNG_INFO_gAMA) != 0;
    r->width = png_get_image_width(png, info);
    r->height = png_get_image_height(png, info);
    row = malloc(png_get_rowbytes(png, info));
    const size_t spp = r->color_type == PNG_COLOR_TYPE_RGB ? 3 : 1;
    size_t k = 0;
    for (png_uint_32 y = 0; y < r->height; y++) {
        png_read_row(png, row, NULL);
        for (size_t x = 0; x < spp * r->width && k < 64; x++)
            r->v[k++] = r->bits == 16 ? (unsigned)row[2 * x] << 8 | row[2 * x + 1] : row[x];
    }
    png_read_end(png, info);
    png_textp t;
    png_get_text(png, info, &t, &r->n_text);
    if (r->n_text > 0) {
        snprintf(r->key, sizeof r->key, "%s", t[0].key);
        snprintf(r->text, sizeof r->text, "%s", t[0].text);
    }
    png_destroy_read_struct(&png, &info, NULL);
    free(row);
    fclose(f);
    return 0;
}

/* RGB previews: colour type 2, values as given (no gAMA: the codes read
 * back exactly), text chunks there, failures leave nothing. */
static void test_rgb_round_trip(void)
{
    char dir[512], path[600];
    tmp_dir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/rgb.png", dir);
    const int W = 5, H = 2;
    float v[30];
    for (int i = 0; i < 30; i++)
        v[i] = (float)i / 29.0f;
    v[0] = -1.0f; /* clamps */
    v[29] = 2.0f;
    const sea_png_text text[] = {{"seabake:range_K", "260:503"}, {"Comment", "a test"}};
    sea_error err;
    for (int bits = 8; bits <= 16; bits += 8) {
        CU_ASSERT_EQUAL_FATAL(sea_png_write_rgb(path, W, H, v, bits, text, 2, &err), SEA_OK);
        raw_png r;
        CU_ASSERT_EQUAL_FATAL(read_raw(path, &r), 0);
        CU_ASSERT_EQUAL(r.color_type, PNG_COLOR_TYPE_RGB);
        CU_ASSERT_EQUAL(r.bits, bits);
        CU_ASSERT_EQUAL(r.width, (png_uint_32)W);
        CU_ASSERT_EQUAL(r.height, (png_uint_32)H);
        CU_ASSERT(!r.gama);
        const double top = bits == 16 ? 65535.0 : 255.0;
        for (int i = 0; i < 30; i++)
            CU_ASSERT_EQUAL((double)r.v[i], (double)lround(fmin(fmax(v[i], 0.0f), 1.0f) * top));
        CU_ASSERT_EQUAL(r.n_text, 2);
        CU_ASSERT_STRING_EQUAL(r.key, "seabake:range_K");
        CU_ASSERT_STRING_EQUAL(r.text, "260:503");
    }
    /* and through the simplified API: 3 channels, 5 x 2 */
    int w = 0, h = 0;
    png_uint_16 *q = NULL;
    unsigned format = 0;
    CU_ASSERT_EQUAL_FATAL(read_rgb(path, &w, &h, &q, &format), 0);
    CU_ASSERT(format & PNG_FORMAT_FLAG_COLOR);
    CU_ASSERT(w == W && h == H);
    free(q);
    unlink(path);
    /* NaN, a bad keyword, a bad depth: no file */
    const sea_png_text bad[] = {{"", "x"}};
    CU_ASSERT_EQUAL(sea_png_write_rgb(path, W, H, v, 8, bad, 1, &err), SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_png_write_rgb(path, W, H, v, 12, NULL, 0, &err), SEA_ERR_DOMAIN);
    v[7] = NAN;
    CU_ASSERT_EQUAL(sea_png_write_rgb(path, W, H, v, 8, NULL, 0, &err), SEA_ERR_NUMERIC);
    CU_ASSERT(strstr(err.msg, "(2, 0)") != NULL);
    CU_ASSERT(access(path, F_OK) != 0);
    CU_ASSERT_EQUAL(rmdir(dir), 0);
}

/* A toned grey preview: black at lo, the knee's grey at the knee, white
 * at hi; its text chunk is there. */
static void test_toned_gray(void)
{
    char dir[512], path[600];
    tmp_dir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/t.png", dir);
    const float v[5] = {260.0f, 305.0f, 503.0f, 282.5f, 404.0f};
    sea_png_tone t;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_png_tone_init(260.0, 305.0, 503.0, &t, &err), SEA_OK);
    const sea_png_text text[] = {{"seabake:range_K", "260:503"}};
    CU_ASSERT_EQUAL_FATAL(sea_png_write_toned(path, 5, 1, v, &t, 16, text, 1, &err), SEA_OK);
    int w, h, bits;
    unsigned *q = NULL;
    CU_ASSERT_EQUAL_FATAL(read_gray(path, &w, &h, &bits, &q), 0);
    CU_ASSERT_EQUAL(q[0], 0u);
    CU_ASSERT(fabs((double)q[1] - SEA_PNG_KNEE_GREY * 65535.0) <= 1.0);
    CU_ASSERT_EQUAL(q[2], 65535u);
    CU_ASSERT(fabs((double)q[3] - 0.5 * SEA_PNG_KNEE_GREY * 65535.0) <= 1.0);
    CU_ASSERT(fabs((double)q[4] - 0.9 * 65535.0) <= 1.0);
    free(q);
    raw_png r;
    CU_ASSERT_EQUAL_FATAL(read_raw(path, &r), 0);
    CU_ASSERT_EQUAL(r.color_type, PNG_COLOR_TYPE_GRAY);
    CU_ASSERT(r.gama);
    CU_ASSERT_STRING_EQUAL(r.key, "seabake:range_K");
    CU_ASSERT_STRING_EQUAL(r.text, "260:503");
    unlink(path);
    CU_ASSERT_EQUAL(rmdir(dir), 0);
}

int test_preview_register(void)
{
    CU_pSuite s = CU_add_suite("preview", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "16- and 8-bit round trip", test_round_trip_16) ||
           !CU_add_test(s, "failures leave nothing", test_failures_leave_nothing) ||
           !CU_add_test(s, "display range", test_range) ||
           !CU_add_test(s, "quantiles by selection = sort", test_quantiles_vs_sort) ||
           !CU_add_test(s, "tone curve", test_tone_curve) ||
           !CU_add_test(s, "RGB round trip", test_rgb_round_trip) ||
           !CU_add_test(s, "toned grey and text", test_toned_gray);
}
