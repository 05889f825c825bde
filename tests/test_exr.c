/* test_exr.c - OpenEXR writing and reading (exporters/exr.c).
 *
 * Files go to a fresh directory from mkdtemp under $TMPDIR (or /tmp),
 * removed by the suite cleanup.  Files the exporter must refuse (tiled,
 * multi-part, UINT) and foreign layouts are made with the OpenEXR C API
 * directly, so these tests do not depend on the code under test. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif
#include <openexr.h>

#include "exr.h"
#include "unit.h"

static char tmp_dir[4096];

/* ------------------------------------------------------------ helpers */

static void join(char *out, size_t n, const char *name)
{
    snprintf(out, n, "%s/%s", tmp_dir, name);
}

/* Removes a directory tree (files and directories only). */
static void remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        char p[8192];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat sb;
        if (lstat(p, &sb) == 0 && S_ISDIR(sb.st_mode)) {
            chmod(p, 0700);
            remove_tree(p);
        } else {
            unlink(p);
        }
    }
    closedir(d);
    rmdir(dir);
}

/* Empties the suite directory between tests. */
static void clear_dir(void)
{
    remove_tree(tmp_dir);
    mkdir(tmp_dir, 0700);
}

/* Entries in dir other than . and .. */
static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
            n++;
    closedir(d);
    return n;
}

static unsigned char *slurp(const char *path, size_t *len)
{
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    unsigned char *buf = NULL;
    size_t cap = 0;
    for (;;) {
        if (*len == cap) {
            cap = cap ? 2 * cap : 65536;
            unsigned char *nb = realloc(buf, cap);
            if (nb == NULL)
                break;
            buf = nb;
        }
        size_t n = fread(buf + *len, 1, cap - *len, f);
        if (n == 0)
            break;
        *len += n;
    }
    fclose(f);
    return buf;
}

static void put_file(const char *path, const void *bytes, size_t n)
{
    FILE *f = fopen(path, "wb");
    CU_ASSERT_FATAL(f != NULL);
    CU_ASSERT(fwrite(bytes, 1, n, f) == n);
    fclose(f);
}

/* Fixed-seed generator (64-bit LCG, high bits). */
static uint32_t rnd_next(uint64_t *s)
{
    *s = *s * 6364136223846793005u + 1442695040888963407u;
    return (uint32_t)(*s >> 32);
}

/* Arbitrary finite float bit patterns: every exponent, subnormals, -0. */
static void fill_any_finite(float *v, size_t n, uint64_t seed)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t b;
        do
            b = rnd_next(&seed);
        while (((b >> 23) & 0xffu) == 0xffu);
        if (i == 1)
            b = 0x80000000u; /* -0 */
        if (i == 2)
            b = 0x00000001u; /* smallest subnormal */
        memcpy(&v[i], &b, sizeof b);
    }
}

static int bits_equal(const float *a, const float *b, size_t n)
{
    return memcmp(a, b, n * sizeof(float)) == 0;
}

static int has(const char *msg, const char *part)
{
    if (strstr(msg, part) != NULL)
        return 1;
    fprintf(stderr, "  message \"%s\" lacks \"%s\"\n", msg, part);
    return 0;
}

static const sea_exr_compression COMPRESSIONS[] = { SEA_EXR_NONE, SEA_EXR_ZIP, SEA_EXR_PIZ };

/* -------------------------------- files written with the C API directly */

typedef enum { RAW_TILED, RAW_MULTIPART, RAW_UINT, RAW_FOREIGN } raw_kind;

static void quiet(exr_const_context_t c, exr_result_t code, const char *msg)
{
    (void)c;
    (void)code;
    (void)msg;
}

/* A 4 x 6 image of one channel "V" holding vals (row-major, first row =
 * smallest y).  RAW_FOREIGN: data window (5,-3)-(8,2) inside a larger
 * display window, DECREASING_Y line order, ZIPS compression, HALF. */
static exr_attr_box2i_t box(int x0, int y0, int x1, int y1)
{
    exr_attr_box2i_t b;
    b.min.x = x0;
    b.min.y = y0;
    b.max.x = x1;
    b.max.y = y1;
    return b;
}

static exr_result_t raw_write(const char *path, raw_kind kind, const float *vals)
{
    enum { W = 4, H = 6 };
    static const uint32_t zeros[W * H];
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet;
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    int nparts = kind == RAW_MULTIPART ? 2 : 1;
    exr_attr_box2i_t dw = box(0, 0, W - 1, H - 1);
    for (int p = 0; p < nparts && rv == EXR_ERR_SUCCESS; p++) {
        int idx = 0;
        rv = exr_add_part(ctx, kind == RAW_MULTIPART ? (p ? "b" : "a") : NULL,
                          kind == RAW_TILED ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &idx);
        if (rv == EXR_ERR_SUCCESS && kind == RAW_FOREIGN) {
            exr_attr_box2i_t disp = box(0, -10, 20, 10);
            exr_attr_v2f_t swc;
            swc.x = swc.y = 0.0f;
            dw = box(5, -3, 5 + W - 1, -3 + H - 1);
            rv = exr_initialize_required_attr(ctx, idx, &disp, &dw, 1.0f, &swc, 1.0f,
                                              EXR_LINEORDER_DECREASING_Y, EXR_COMPRESSION_ZIPS);
        } else if (rv == EXR_ERR_SUCCESS) {
            rv = exr_initialize_required_attr_simple(ctx, idx, W, H, EXR_COMPRESSION_NONE);
        }
        if (rv == EXR_ERR_SUCCESS && kind == RAW_TILED)
            rv = exr_set_tile_descriptor(ctx, idx, 2, 2, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_add_channel(ctx, idx, "V",
                                 kind == RAW_UINT      ? EXR_PIXEL_UINT
                                 : kind == RAW_FOREIGN ? EXR_PIXEL_HALF
                                                       : EXR_PIXEL_FLOAT,
                                 EXR_PERCEPTUALLY_LINEAR, 1, 1);
    }
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctx);
    for (int p = 0; p < nparts && rv == EXR_ERR_SUCCESS; p++) {
        int32_t nchunks = 0, lines = 1;
        rv = exr_get_chunk_count(ctx, p, &nchunks);
        if (rv == EXR_ERR_SUCCESS && kind != RAW_TILED)
            rv = exr_get_scanlines_per_chunk(ctx, p, &lines);
        for (int32_t i = 0; i < nchunks && rv == EXR_ERR_SUCCESS; i++) {
            /* The library takes chunks in index order whatever the line
             * order (it validates ci == last + 1). */
            int32_t ci = i;
            exr_chunk_info_t cinfo;
            size_t x0 = 0, y0 = 0;
            if (kind == RAW_TILED) {
                int tx = ci % (W / 2), ty = ci / (W / 2);
                rv = exr_write_tile_chunk_info(ctx, p, tx, ty, 0, 0, &cinfo);
                x0 = (size_t)tx * 2;
                y0 = (size_t)ty * 2;
            } else {
                rv = exr_write_scanline_chunk_info(ctx, p, dw.min.y + ci * lines, &cinfo);
                y0 = (size_t)(cinfo.start_y - dw.min.y);
            }
            exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
            if (rv == EXR_ERR_SUCCESS)
                rv = exr_encoding_initialize(ctx, p, &cinfo, &enc);
            if (rv != EXR_ERR_SUCCESS)
                break;
            exr_coding_channel_info_t *ch = &enc.channels[0];
            ch->user_data_type = kind == RAW_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = 4;
            ch->user_pixel_stride = 4;
            ch->user_line_stride = 4 * W;
            ch->encode_from_ptr = kind == RAW_UINT
                                      ? (const uint8_t *)(zeros + y0 * W + x0)
                                      : (const uint8_t *)(vals + y0 * W + x0);
            rv = exr_encoding_choose_default_routines(ctx, p, &enc);
            if (rv == EXR_ERR_SUCCESS)
                rv = exr_encoding_run(ctx, p, &enc);
            exr_encoding_destroy(ctx, &enc);
        }
    }
    exr_result_t frv = exr_finish(&ctx);
    return rv != EXR_ERR_SUCCESS ? rv : frv;
}

/* --------------------------------------------------------------- tests */

/* FLOAT is stored bit for bit: any finite pattern (subnormals, -0, every
 * exponent) comes back identical, for one pixel, sizes that are not
 * multiples of the 16 (ZIP) or 32 (PIZ) scanlines of a chunk, and all
 * three compressions. */
static void test_float_round_trip(void)
{
    static const int sizes[][2] = { { 1, 1 }, { 37, 53 }, { 16, 33 }, { 100, 64 }, { 1, 70 } };
    char path[8192];
    join(path, sizeof path, "float.exr");
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        int w = sizes[s][0], h = sizes[s][1];
        size_t n = (size_t)w * (size_t)h;
        float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
        CU_ASSERT_FATAL(a != NULL && b != NULL && c != NULL);
        fill_any_finite(a, n, 11 + s);
        fill_any_finite(b, n, 101 + s);
        fill_any_finite(c, n, 1001 + s);
        sea_exr_channel ch[] = { { "mx", a }, { "my", b }, { "sxx", c } };
        for (size_t k = 0; k < 3; k++) {
            sea_exr_options opt = { SEA_EXR_FLOAT, COMPRESSIONS[k] };
            sea_error err = { "" };
            sea_status st = sea_exr_write(path, w, h, ch, 3, NULL, 0, &opt, &err);
            if (st != SEA_OK)
                fprintf(stderr, "  %dx%d comp %zu: %s\n", w, h, k, err.msg);
            CU_ASSERT_FATAL(st == SEA_OK);
            sea_exr_image img = { 0 };
            st = sea_exr_read(path, &img, &err);
            if (st != SEA_OK)
                fprintf(stderr, "  %dx%d comp %zu: %s\n", w, h, k, err.msg);
            CU_ASSERT_FATAL(st == SEA_OK);
            CU_ASSERT(img.width == w && img.height == h);
            CU_ASSERT_FATAL(img.n_channels == 3);
            for (size_t j = 0; j < 3; j++) {
                CU_ASSERT(strcmp(img.names[j], ch[j].name) == 0); /* already sorted */
                CU_ASSERT(img.pixel[j] == SEA_EXR_FLOAT);
                const float *got = sea_exr_image_channel(&img, ch[j].name);
                CU_ASSERT_FATAL(got != NULL);
                if (!bits_equal(got, ch[j].data, n))
                    fprintf(stderr, "  %dx%d comp %zu channel %s differs\n", w, h, k, ch[j].name);
                CU_ASSERT(bits_equal(got, ch[j].data, n));
            }
            CU_ASSERT(img.n_attrs == 0);
            sea_exr_image_free(&img);
            CU_ASSERT(count_entries(tmp_dir) == 1); /* no temporary file left */
        }
        free(a);
        free(b);
        free(c);
    }
    clear_dir();
}

/* The whole file as bytes (malloc'ed), *n its size. */
static unsigned char *file_bytes(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    CU_ASSERT_FATAL(f != NULL);
    fseek(f, 0, SEEK_END);
    *n = (size_t)ftell(f);
    rewind(f);
    unsigned char *b = malloc(*n);
    CU_ASSERT_FATAL(b != NULL && fread(b, 1, *n, f) == *n);
    fclose(f);
    return b;
}

/* Chunks compressed on several threads (a batch at a time) and written in
 * order: the file is the same, byte for byte, as with one thread, for every
 * codec and pixel type, with more chunks than one batch holds. */
static void test_threads_same_file(void)
{
#ifdef _OPENMP
    const int w = 300, h = 16 * 40 + 7; /* ZIP: 40 chunks of 16 lines and a short one */
    const size_t n = (size_t)w * (size_t)h;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    CU_ASSERT_FATAL(a != NULL && b != NULL);
    fill_any_finite(a, n, 5);
    for (size_t i = 0; i < n; i++)
        b[i] = (float)sin(0.001 * (double)i); /* compressible */
    sea_exr_channel ch[] = { { "R", a }, { "G", b } };
    char p1[8192], p2[8192];
    join(p1, sizeof p1, "one.exr");
    join(p2, sizeof p2, "many.exr");
    const int saved = omp_get_max_threads();
    for (size_t k = 0; k < 3; k++)
        for (int half = 0; half < 2; half++) {
            sea_exr_options opt = { half ? SEA_EXR_HALF : SEA_EXR_FLOAT, COMPRESSIONS[k] };
            sea_error err = { "" };
            if (half) /* inside half range */
                for (size_t i = 0; i < n; i++)
                    a[i] = (float)fmod((double)i * 0.37, 100.0);
            omp_set_num_threads(1);
            CU_ASSERT_FATAL(sea_exr_write(p1, w, h, ch, 2, NULL, 0, &opt, &err) == SEA_OK);
            omp_set_num_threads(3);
            CU_ASSERT_FATAL(sea_exr_write(p2, w, h, ch, 2, NULL, 0, &opt, &err) == SEA_OK);
            size_t n1, n2;
            unsigned char *f1 = file_bytes(p1, &n1), *f2 = file_bytes(p2, &n2);
            CU_ASSERT(n1 == n2 && memcmp(f1, f2, n1) == 0);
            free(f1);
            free(f2);
        }
    omp_set_num_threads(saved);
    free(a);
    free(b);
    clear_dir();
#endif
}

/* HALF: values spread over 1e-3..1e3 in magnitude (inside the normal half
 * range, 6.1e-5..65504) come back within the rounding of an 11-bit
 * significand, relative 2^-11; values that are halves exactly (0.5, -3.25,
 * 1024, 65504) come back exactly; 0.1 does not (proof it was rounded). */
static void test_half_round_trip(void)
{
    enum { W = 29, H = 41 };
    const double rel_tol = 1.0 / 2048.0; /* 2^-11 */
    static const float exact[] = { 0.5f, -3.25f, 1024.0f, 65504.0f, -65504.0f, 0.0f };
    float v[W * H];
    uint64_t seed = 6174;
    for (int i = 0; i < W * H; i++) {
        double u = rnd_next(&seed) / 4294967296.0;
        double mag = pow(10.0, -3.0 + 6.0 * u);
        v[i] = (float)((rnd_next(&seed) & 1u) ? -mag : mag);
    }
    for (size_t i = 0; i < sizeof exact / sizeof exact[0]; i++)
        v[i] = exact[i];
    v[W * H - 1] = 0.1f;
    char path[8192];
    join(path, sizeof path, "half.exr");
    sea_exr_channel ch[] = { { "h", v } };
    for (size_t k = 0; k < 3; k++) {
        sea_exr_options opt = { SEA_EXR_HALF, COMPRESSIONS[k] };
        sea_error err = { "" };
        CU_ASSERT_FATAL(sea_exr_write(path, W, H, ch, 1, NULL, 0, &opt, &err) == SEA_OK);
        sea_exr_image img = { 0 };
        CU_ASSERT_FATAL(sea_exr_read(path, &img, &err) == SEA_OK);
        CU_ASSERT_FATAL(img.n_channels == 1 && img.width == W && img.height == H);
        CU_ASSERT(img.pixel[0] == SEA_EXR_HALF);
        const float *r = img.data[0];
        double worst = 0.0;
        for (int i = 0; i < W * H; i++)
            worst = fmax(worst, fabs((double)r[i] - v[i]) / fmax(fabs(v[i]), 1e-30));
        if (!(worst <= rel_tol))
            fprintf(stderr, "  HALF worst relative error %.3g > 2^-11\n", worst);
        CU_ASSERT(worst <= rel_tol);
        for (size_t i = 0; i < sizeof exact / sizeof exact[0]; i++)
            CU_ASSERT(r[i] == exact[i]);
        CU_ASSERT(r[W * H - 1] != 0.1f);
        ASSERT_REL(r[W * H - 1], 0.1, rel_tol, 0);
        sea_exr_image_free(&img);
    }
    clear_dir();
}

/* Beyond 65504 a half would be infinite: refused for HALF (nothing
 * written), accepted for FLOAT. */
static void test_half_range(void)
{
    float v[6] = { 1, 2, 3, 4, -70000.0f, 6 };
    char path[8192];
    join(path, sizeof path, "range.exr");
    sea_exr_channel ch[] = { { "Z", v } };
    sea_exr_options half = { SEA_EXR_HALF, SEA_EXR_ZIP }, flt = { SEA_EXR_FLOAT, SEA_EXR_ZIP };
    sea_error err = { "" };
    CU_ASSERT(sea_exr_write(path, 3, 2, ch, 1, NULL, 0, &half, &err) == SEA_ERR_NUMERIC);
    CU_ASSERT(has(err.msg, "channel 'Z' pixel (1, 1)"));
    CU_ASSERT(count_entries(tmp_dir) == 0);
    CU_ASSERT(sea_exr_write(path, 3, 2, ch, 1, NULL, 0, &flt, &err) == SEA_OK);
    clear_dir();
}

/* Channels given out of order (the file sorts them, upper case first)
 * come back under their own names, each with its own data. */
static void test_channel_order(void)
{
    enum { W = 7, H = 5 };
    static const char *names[] = { "zeta", "B", "alpha", "G", "R", "cov.xy" };
    enum { N = sizeof names / sizeof names[0] };
    static const char *sorted[] = { "B", "G", "R", "alpha", "cov.xy", "zeta" };
    float data[N][W * H];
    sea_exr_channel ch[N];
    for (int c = 0; c < N; c++) {
        for (int i = 0; i < W * H; i++)
            data[c][i] = 100.0f * (float)c + 0.25f * (float)i;
        ch[c] = (sea_exr_channel){ names[c], data[c] };
    }
    char path[8192];
    join(path, sizeof path, "order.exr");
    for (size_t k = 0; k < 3; k++) {
        sea_exr_options opt = { SEA_EXR_FLOAT, COMPRESSIONS[k] };
        sea_error err = { "" };
        CU_ASSERT_FATAL(sea_exr_write(path, W, H, ch, N, NULL, 0, &opt, &err) == SEA_OK);
        sea_exr_image img = { 0 };
        CU_ASSERT_FATAL(sea_exr_read(path, &img, &err) == SEA_OK);
        CU_ASSERT_FATAL(img.n_channels == N);
        for (int c = 0; c < N; c++) {
            CU_ASSERT(strcmp(img.names[c], sorted[c]) == 0);
            const float *got = sea_exr_image_channel(&img, names[c]);
            CU_ASSERT_FATAL(got != NULL);
            CU_ASSERT(bits_equal(got, data[c], W * H));
        }
        CU_ASSERT(sea_exr_image_channel(&img, "missing") == NULL);
        sea_exr_image_free(&img);
    }
    clear_dir();
}

/* Row 0 is the top: in an uncompressed file, scanline y = r (EXR counts y
 * down from the top of the display window, which starts at 0) holds buffer
 * row r.  Checked on the raw bytes, then through the reader with a
 * gradient. */
static void test_row0_top(void)
{
    enum { W = 3, H = 5 };
    float g[W * H];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            g[y * W + x] = 0.25f + 1.5f * (float)y + 0.001f * (float)x;
    char path[8192];
    join(path, sizeof path, "rows.exr");
    sea_exr_channel ch[] = { { "g", g } };
    sea_exr_options opt = { SEA_EXR_FLOAT, SEA_EXR_NONE };
    sea_error err = { "" };
    CU_ASSERT_FATAL(sea_exr_write(path, W, H, ch, 1, NULL, 0, &opt, &err) == SEA_OK);

    size_t len = 0;
    unsigned char *bytes = slurp(path, &len);
    CU_ASSERT_FATAL(bytes != NULL);
    for (int y = 0; y < H; y++) {
        /* Chunk: int32 y, int32 byte count, then the row, little-endian. */
        unsigned char pat[8 + 4 * W];
        uint32_t words[2 + W];
        words[0] = (uint32_t)y;
        words[1] = 4u * W;
        for (int x = 0; x < W; x++)
            memcpy(&words[2 + x], &g[y * W + x], 4);
        for (int i = 0; i < 2 + W; i++)
            for (int b = 0; b < 4; b++)
                pat[4 * i + b] = (unsigned char)(words[i] >> (8 * b));
        int found = 0;
        for (size_t o = 0; o + sizeof pat <= len && !found; o++)
            found = memcmp(bytes + o, pat, sizeof pat) == 0;
        if (!found)
            fprintf(stderr, "  scanline %d does not hold buffer row %d\n", y, y);
        CU_ASSERT(found);
    }
    free(bytes);

    sea_exr_image img = { 0 };
    CU_ASSERT_FATAL(sea_exr_read(path, &img, &err) == SEA_OK);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            CU_ASSERT(img.data[0][y * W + x] == g[y * W + x]);
    sea_exr_image_free(&img);
    clear_dir();
}

/* The reader does not assume our own layout: a data window starting at
 * (5, -3), DECREASING_Y chunks, ZIPS, HALF; row 0 is the data window's
 * smallest y.  The values are exact halves. */
static void test_read_foreign_layout(void)
{
    float v[4 * 6];
    for (int i = 0; i < 24; i++)
        v[i] = 0.5f * (float)i - 3.0f;
    char path[8192];
    join(path, sizeof path, "foreign.exr");
    exr_result_t rv = raw_write(path, RAW_FOREIGN, v);
    if (rv != EXR_ERR_SUCCESS)
        fprintf(stderr, "  making %s: %s\n", path, exr_get_default_error_message(rv));
    CU_ASSERT_FATAL(rv == EXR_ERR_SUCCESS);
    sea_exr_image img = { 0 };
    sea_error err = { "" };
    sea_status st = sea_exr_read(path, &img, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  %s\n", err.msg);
    CU_ASSERT_FATAL(st == SEA_OK);
    CU_ASSERT(img.width == 4 && img.height == 6 && img.n_channels == 1);
    CU_ASSERT(img.pixel[0] == SEA_EXR_HALF);
    CU_ASSERT(bits_equal(img.data[0], v, 24));
    sea_exr_image_free(&img);
    clear_dir();
}

/* String attributes come back exactly, required attributes are not
 * reported, names up to 63 characters (long-name flag) work. */
static void test_attributes(void)
{
    char longval[1001];
    for (int i = 0; i < 1000; i++)
        longval[i] = (char)('a' + i % 26);
    longval[1000] = '\0';
    const char *name63 = "a_name_of_sixty_three_characters_for_the_long_name_flag_0123456";
    CU_ASSERT_FATAL(strlen(name63) == 63);
    sea_exr_attr attrs[] = {
        { "seabake.version", "0.1.0" },
        { "wind", "10 m/s from 045\xc2\xb0 (N\xc3\xb8rth-east)" },
        { "empty", "" },
        { "long", longval },
        { name63, "long name" },
    };
    enum { NA = sizeof attrs / sizeof attrs[0] };
    float v[4] = { 1, 2, 3, 4 };
    sea_exr_channel ch[] = { { "v", v } };
    char path[8192];
    join(path, sizeof path, "attrs.exr");
    sea_error err = { "" };
    sea_status st = sea_exr_write(path, 2, 2, ch, 1, attrs, NA, NULL, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  %s\n", err.msg);
    CU_ASSERT_FATAL(st == SEA_OK);
    sea_exr_image img = { 0 };
    CU_ASSERT_FATAL(sea_exr_read(path, &img, &err) == SEA_OK);
    CU_ASSERT(img.n_attrs == NA);
    for (int a = 0; a < NA; a++) {
        const char *got = sea_exr_image_attr(&img, attrs[a].name);
        CU_ASSERT_FATAL(got != NULL);
        CU_ASSERT(strcmp(got, attrs[a].value) == 0);
    }
    CU_ASSERT(sea_exr_image_attr(&img, "compression") == NULL);
    CU_ASSERT(sea_exr_image_attr(&img, "nothing") == NULL);
    sea_exr_image_free(&img);
    clear_dir();
}

/* A NaN or infinity is SEA_ERR_NUMERIC naming the channel and the pixel,
 * and no file (nor temporary file) appears. */
static void test_non_finite(void)
{
    enum { W = 5, H = 4 };
    float ok[W * H], bad[W * H];
    for (int i = 0; i < W * H; i++)
        ok[i] = bad[i] = (float)i;
    bad[2 * W + 3] = NAN;
    bad[3 * W + 4] = INFINITY;
    char path[8192];
    join(path, sizeof path, "nan.exr");
    sea_exr_channel ch[] = { { "ok", ok }, { "my", bad } };
    sea_error err = { "" };
    CU_ASSERT(sea_exr_write(path, W, H, ch, 2, NULL, 0, NULL, &err) == SEA_ERR_NUMERIC);
    CU_ASSERT(has(err.msg, "channel 'my' pixel (3, 2) is NaN"));
    CU_ASSERT(count_entries(tmp_dir) == 0);
    bad[2 * W + 3] = 0.0f;
    CU_ASSERT(sea_exr_write(path, W, H, ch, 2, NULL, 0, NULL, &err) == SEA_ERR_NUMERIC);
    CU_ASSERT(has(err.msg, "channel 'my' pixel (4, 3) is inf"));
    bad[3 * W + 4] = -INFINITY;
    CU_ASSERT(sea_exr_write(path, W, H, ch, 2, NULL, 0, NULL, &err) == SEA_ERR_NUMERIC);
    CU_ASSERT(has(err.msg, "is -inf"));
    CU_ASSERT(count_entries(tmp_dir) == 0);
}

/* A directory that cannot hold the file: SEA_ERR_IO naming the path and
 * the system's reason, and nothing is left anywhere. */
static void test_unwritable_directory(void)
{
    float v[1] = { 1 };
    sea_exr_channel ch[] = { { "v", v } };
    sea_error err = { "" };
    char path[8192];

    join(path, sizeof path, "missing/out.exr");
    CU_ASSERT(sea_exr_write(path, 1, 1, ch, 1, NULL, 0, NULL, &err) == SEA_ERR_IO);
    CU_ASSERT(has(err.msg, path));
    CU_ASSERT(has(err.msg, strerror(ENOENT)));
    CU_ASSERT(count_entries(tmp_dir) == 0);

    char file[8192];
    join(file, sizeof file, "plain");
    put_file(file, "x", 1);
    join(path, sizeof path, "plain/out.exr");
    CU_ASSERT(sea_exr_write(path, 1, 1, ch, 1, NULL, 0, NULL, &err) == SEA_ERR_IO);
    CU_ASSERT(has(err.msg, strerror(ENOTDIR)));
    CU_ASSERT(count_entries(tmp_dir) == 1);

    /* Permissions do not stop root, so this part runs for other users. */
    if (geteuid() != 0) {
        char ro[8192];
        join(ro, sizeof ro, "ro");
        CU_ASSERT_FATAL(mkdir(ro, 0500) == 0);
        join(path, sizeof path, "ro/out.exr");
        CU_ASSERT(sea_exr_write(path, 1, 1, ch, 1, NULL, 0, NULL, &err) == SEA_ERR_IO);
        CU_ASSERT(has(err.msg, strerror(EACCES)));
        CU_ASSERT(count_entries(ro) == 0);
    }
    clear_dir();
}

/* An existing destination survives every kind of failed write byte for
 * byte: invalid input (refused before any I/O), a write that fails
 * half-way (file size limit: EFBIG from the write callback), and a rename
 * that fails (the destination is a directory). */
static void test_existing_file_kept(void)
{
    enum { W = 64, H = 64 };
    static float v[W * H];
    for (int i = 0; i < W * H; i++)
        v[i] = (float)i * 0.37f;
    sea_exr_channel good[] = { { "a", v }, { "b", v }, { "c", v } };
    char path[8192];
    join(path, sizeof path, "keep.exr");
    sea_error err = { "" };
    CU_ASSERT_FATAL(sea_exr_write(path, W, H, good, 3, NULL, 0, NULL, &err) == SEA_OK);
    size_t len0 = 0, len1 = 0;
    unsigned char *before = slurp(path, &len0);
    CU_ASSERT_FATAL(before != NULL && len0 > 3 * W * H * 4);

    sea_exr_channel badname[] = { { "a", v }, { "", v } };
    CU_ASSERT(sea_exr_write(path, W, H, badname, 2, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);

    /* A limit below the image size makes the write callback fail. */
    struct rlimit old;
    CU_ASSERT_FATAL(getrlimit(RLIMIT_FSIZE, &old) == 0);
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    struct rlimit small = { 4096, old.rlim_max };
    CU_ASSERT_FATAL(setrlimit(RLIMIT_FSIZE, &small) == 0);
    sea_status st = sea_exr_write(path, W, H, good, 3, NULL, 0, NULL, &err);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, old_handler);
    CU_ASSERT(st == SEA_ERR_IO);
    CU_ASSERT(has(err.msg, path));
    CU_ASSERT(has(err.msg, strerror(EFBIG)));

    unsigned char *after = slurp(path, &len1);
    CU_ASSERT_FATAL(after != NULL);
    CU_ASSERT(len0 == len1 && memcmp(before, after, len0) == 0);
    CU_ASSERT(count_entries(tmp_dir) == 1);
    free(before);
    free(after);

    char dir[8192];
    join(dir, sizeof dir, "adir.exr");
    CU_ASSERT_FATAL(mkdir(dir, 0700) == 0);
    CU_ASSERT(sea_exr_write(dir, W, H, good, 3, NULL, 0, NULL, &err) == SEA_ERR_IO);
    CU_ASSERT(has(err.msg, dir));
    CU_ASSERT(count_entries(tmp_dir) == 2); /* keep.exr and the directory */
    CU_ASSERT(count_entries(dir) == 0);
    clear_dir();
}

/* Invalid arguments are SEA_ERR_DOMAIN and write nothing: sizes, channel
 * counts, names (duplicate, empty, too long, control character), missing
 * data, attributes (reserved, duplicate, missing value), options. */
static void test_invalid_arguments(void)
{
    static float v[4] = { 1, 2, 3, 4 };
    char path[8192];
    join(path, sizeof path, "bad.exr");
    sea_error err = { "" };
    sea_exr_channel one[] = { { "v", v } };

    sea_exr_channel dup[] = { { "R", v }, { "G", v }, { "R", v } };
    CU_ASSERT(sea_exr_write(path, 2, 2, dup, 3, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(has(err.msg, "'R' given twice"));

    CU_ASSERT(sea_exr_write(path, 0, 2, one, 1, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_exr_write(path, 2, 65537, one, 1, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_exr_write(path, 2, 2, one, 0, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_exr_write(path, 2, 2, NULL, 1, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_exr_write("", 2, 2, one, 1, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);

    sea_exr_channel many[65];
    static char names[65][8];
    for (int c = 0; c < 65; c++) {
        snprintf(names[c], sizeof names[c], "c%02d", c);
        many[c] = (sea_exr_channel){ names[c], v };
    }
    CU_ASSERT(sea_exr_write(path, 2, 2, many, 65, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);

    const char *bad_names[] = { "", "abcdefghijklmnopqrstuvwxyz012345", "tab\there", NULL };
    for (size_t i = 0; i < sizeof bad_names / sizeof bad_names[0]; i++) {
        sea_exr_channel ch[] = { { bad_names[i], v } };
        CU_ASSERT(sea_exr_write(path, 2, 2, ch, 1, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);
    }
    sea_exr_channel nodata[] = { { "v", NULL } };
    CU_ASSERT(sea_exr_write(path, 2, 2, nodata, 1, NULL, 0, NULL, &err) == SEA_ERR_DOMAIN);

    sea_exr_attr reserved[] = { { "compression", "none" } };
    CU_ASSERT(sea_exr_write(path, 2, 2, one, 1, reserved, 1, NULL, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(has(err.msg, "reserved"));
    sea_exr_attr twice[] = { { "k", "1" }, { "k", "2" } };
    CU_ASSERT(sea_exr_write(path, 2, 2, one, 1, twice, 2, NULL, &err) == SEA_ERR_DOMAIN);
    sea_exr_attr novalue[] = { { "k", NULL } };
    CU_ASSERT(sea_exr_write(path, 2, 2, one, 1, novalue, 1, NULL, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_exr_write(path, 2, 2, one, 1, NULL, 1, NULL, &err) == SEA_ERR_DOMAIN);

    sea_exr_options badopt = { SEA_EXR_FLOAT, (sea_exr_compression)7 };
    CU_ASSERT(sea_exr_write(path, 2, 2, one, 1, NULL, 0, &badopt, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(count_entries(tmp_dir) == 0);

    /* The limits themselves are allowed: 64 channels, 31-character names. */
    sea_exr_channel edge[64];
    for (int c = 0; c < 64; c++)
        edge[c] = many[c];
    edge[0].name = "abcdefghijklmnopqrstuvwxyz01234";
    CU_ASSERT(sea_exr_write(path, 2, 2, edge, 64, NULL, 0, NULL, &err) == SEA_OK);
    sea_exr_image img = { 0 };
    CU_ASSERT(sea_exr_read(path, &img, &err) == SEA_OK);
    CU_ASSERT(img.n_channels == 64);
    CU_ASSERT(sea_exr_image_channel(&img, "abcdefghijklmnopqrstuvwxyz01234") != NULL);
    sea_exr_image_free(&img);
    clear_dir();
}

/* Not an EXR file, a missing file, an empty file, a directory and a
 * truncated EXR file are SEA_ERR_IO; the image stays empty. */
static void test_read_io_errors(void)
{
    char path[8192];
    sea_error err = { "" };
    sea_exr_image img;

    join(path, sizeof path, "text.exr");
    const char text[] = "this is not an OpenEXR file, only some text\n";
    put_file(path, text, sizeof text - 1);
    CU_ASSERT(sea_exr_read(path, &img, &err) == SEA_ERR_IO);
    CU_ASSERT(has(err.msg, path));
    CU_ASSERT(img.n_channels == 0 && img.names == NULL && img.data == NULL);
    sea_exr_image_free(&img);

    join(path, sizeof path, "empty.exr");
    put_file(path, "", 0);
    CU_ASSERT(sea_exr_read(path, &img, &err) == SEA_ERR_IO);

    join(path, sizeof path, "absent.exr");
    CU_ASSERT(sea_exr_read(path, &img, &err) == SEA_ERR_IO);
    CU_ASSERT(has(err.msg, strerror(ENOENT)));

    CU_ASSERT(sea_exr_read(tmp_dir, &img, &err) == SEA_ERR_IO);

    /* Truncated inside the pixel data. */
    enum { W = 40, H = 40 };
    static float v[W * H];
    for (int i = 0; i < W * H; i++)
        v[i] = (float)i;
    sea_exr_channel ch[] = { { "v", v } };
    join(path, sizeof path, "cut.exr");
    CU_ASSERT_FATAL(sea_exr_write(path, W, H, ch, 1, NULL, 0, NULL, &err) == SEA_OK);
    CU_ASSERT_FATAL(truncate(path, 3000) == 0);
    CU_ASSERT(sea_exr_read(path, &img, &err) == SEA_ERR_IO);
    CU_ASSERT(img.n_channels == 0 && img.data == NULL);
    clear_dir();
}

/* Tiled, multi-part and UINT files are SEA_ERR_PARSE (the files are valid:
 * made with the C API directly). */
static void test_read_unsupported(void)
{
    static const struct {
        raw_kind kind;
        const char *name, *says;
    } cases[] = {
        { RAW_TILED, "tiled.exr", "tiled" },
        { RAW_MULTIPART, "multi.exr", "2 parts" },
        { RAW_UINT, "uint.exr", "unsigned integers" },
    };
    float v[24] = { 0 };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[8192];
        join(path, sizeof path, cases[i].name);
        exr_result_t rv = raw_write(path, cases[i].kind, v);
        if (rv != EXR_ERR_SUCCESS)
            fprintf(stderr, "  making %s: %s\n", cases[i].name, exr_get_default_error_message(rv));
        CU_ASSERT_FATAL(rv == EXR_ERR_SUCCESS);
        sea_exr_image img = { 0 };
        sea_error err = { "" };
        CU_ASSERT(sea_exr_read(path, &img, &err) == SEA_ERR_PARSE);
        CU_ASSERT(has(err.msg, cases[i].says));
        CU_ASSERT(img.n_channels == 0 && img.names == NULL);
        sea_exr_image_free(&img);
    }
    clear_dir();
}

/* Freeing is safe on a zeroed image, twice in a row, and on NULL. */
static void test_free_zeroed(void)
{
    sea_exr_image img = { 0 };
    sea_exr_image_free(&img);
    sea_exr_image_free(&img);
    sea_exr_image_free(NULL);
    CU_ASSERT(sea_exr_image_channel(&img, "x") == NULL);
    CU_ASSERT(sea_exr_image_attr(&img, "x") == NULL);
}

static int suite_init(void)
{
    const char *base = getenv("TMPDIR");
    if (base == NULL || base[0] == '\0')
        base = "/tmp";
    snprintf(tmp_dir, sizeof tmp_dir, "%s/seabake-exr.XXXXXX", base);
    return mkdtemp(tmp_dir) == NULL;
}

static int suite_cleanup(void)
{
    remove_tree(tmp_dir);
    return 0;
}

int test_exr_register(void)
{
    CU_pSuite s = CU_add_suite("exr", suite_init, suite_cleanup);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "FLOAT round trip, bit exact", test_float_round_trip) ||
           !CU_add_test(s, "threads write the same file", test_threads_same_file) ||
           !CU_add_test(s, "HALF round trip within 2^-11", test_half_round_trip) ||
           !CU_add_test(s, "HALF range refused", test_half_range) ||
           !CU_add_test(s, "channels matched by name", test_channel_order) ||
           !CU_add_test(s, "row 0 is the top", test_row0_top) ||
           !CU_add_test(s, "foreign layout read", test_read_foreign_layout) ||
           !CU_add_test(s, "string attributes", test_attributes) ||
           !CU_add_test(s, "NaN and inf refused", test_non_finite) ||
           !CU_add_test(s, "unwritable directory", test_unwritable_directory) ||
           !CU_add_test(s, "existing file kept on failure", test_existing_file_kept) ||
           !CU_add_test(s, "invalid arguments", test_invalid_arguments) ||
           !CU_add_test(s, "read I/O errors", test_read_io_errors) ||
           !CU_add_test(s, "unsupported files refused", test_read_unsupported) ||
           !CU_add_test(s, "free on a zeroed image", test_free_zeroed);
}
