/* test_arrays.c - the .npy and CSV writers (exporters/arrays.c) behind
 * seabake convert: their files read back by small independent readers
 * give, bit for bit, the floats sea_exr_read returns for EXR files written
 * in FLOAT and HALF with every compression seabake uses.
 *
 * Files go to a fresh directory from mkdtemp under $TMPDIR (or /tmp),
 * removed by the suite cleanup. */
#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "arrays.h"
#include "exr.h"
#include "unit.h"

static char tmp_dir[4096];

static void join(char *out, size_t n, const char *name)
{
    snprintf(out, n, "%s/%s", tmp_dir, name);
}

/* Fixed-seed generator (64-bit LCG, high bits). */
static uint32_t rnd_next(uint64_t *s)
{
    *s = *s * 6364136223846793005u + 1442695040888963407u;
    return (uint32_t)(*s >> 32);
}

/* Finite float bit patterns of every exponent, -0 and the smallest
 * subnormal among them; within the half range (|v| <= 65504) when
 * half_range, as the EXR writer refuses larger HALF values. */
static void fill_values(float *v, size_t n, uint64_t seed, int half_range)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t b;
        float f;
        do {
            b = rnd_next(&seed);
            memcpy(&f, &b, sizeof f);
        } while (((b >> 23) & 0xffu) == 0xffu || (half_range && !(fabsf(f) <= 65504.0f)));
        if (i == 1)
            b = 0x80000000u; /* -0 */
        if (i == 2)
            b = 0x00000001u; /* smallest subnormal */
        memcpy(&v[i], &b, sizeof b);
    }
}

/* The whole file (malloc'ed), *n bytes. */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    CU_ASSERT_FATAL(f != NULL);
    fseek(f, 0, SEEK_END);
    *n = (size_t)ftell(f);
    rewind(f);
    unsigned char *b = malloc(*n + 1);
    CU_ASSERT_FATAL(b != NULL && fread(b, 1, *n, f) == *n);
    b[*n] = '\0';
    fclose(f);
    return b;
}

/* ------------------------------------------------ a tiny .npy reader */

/* Parses a version 1.0 '<f4' C-order file: its shape (1 to 3 axes) in
 * shape[], the axes in *ndim, and the data (little-endian bytes decoded
 * to floats, malloc'ed) in *data.  Returns 0 on success, or the step that
 * failed. */
static int npy_read(const unsigned char *b, size_t n, size_t shape[3], int *ndim, float **data)
{
    static const unsigned char magic[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
    if (n < 10 || memcmp(b, magic, 8) != 0)
        return 1;
    const size_t hlen = (size_t)b[8] | (size_t)b[9] << 8;
    if ((10 + hlen) % 64 != 0 || 10 + hlen > n || b[10 + hlen - 1] != '\n')
        return 2;
    char dict[1024];
    if (hlen >= sizeof dict)
        return 3;
    memcpy(dict, b + 10, hlen);
    dict[hlen] = '\0';
    if (strstr(dict, "'descr': '<f4'") == NULL || strstr(dict, "'fortran_order': False") == NULL)
        return 4;
    const char *s = strstr(dict, "'shape': (");
    if (s == NULL)
        return 5;
    s += strlen("'shape': (");
    *ndim = 0;
    size_t count = 1;
    while (*s != ')') {
        char *end;
        unsigned long long v = strtoull(s, &end, 10);
        if (end == s || *ndim == 3)
            return 6;
        shape[(*ndim)++] = (size_t)v;
        count *= (size_t)v;
        s = end;
        if (*s == ',')
            s++;
        while (*s == ' ')
            s++;
    }
    if (10 + hlen + 4 * count != n)
        return 7;
    *data = malloc(count * sizeof **data);
    if (*data == NULL)
        return 8;
    const unsigned char *p = b + 10 + hlen;
    for (size_t i = 0; i < count; i++, p += 4) {
        const uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
                           (uint32_t)p[3] << 24;
        memcpy(&(*data)[i], &u, sizeof u);
    }
    return 0;
}

/* ------------------------------------------------------------ tests */

/* The header is version 1.0, 64-byte aligned, space-padded, '\n'-ended,
 * and states the shape: (H, W) for one plane, (H, W, C) for more. */
static void test_npy_header(void)
{
    static const size_t shapes[][3] = {{48, 64, 1}, {86, 50, 3}, {1, 1, 1},
                                       {65536, 65536, 64}, {2147483648u, 2147483648u, 2}};
    for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; k++) {
        unsigned char buf[256];
        const size_t n = sea_arrays_npy_header(shapes[k][0], shapes[k][1], shapes[k][2], buf,
                                               sizeof buf);
        CU_ASSERT_FATAL(n > 0);
        CU_ASSERT(n % SEA_ARRAYS_NPY_ALIGN == 0);
        CU_ASSERT(memcmp(buf, "\x93NUMPY\x01\x00", 8) == 0);
        CU_ASSERT(((size_t)buf[8] | (size_t)buf[9] << 8) == n - 10);
        CU_ASSERT(buf[n - 1] == '\n');
        char want[160];
        if (shapes[k][2] == 1)
            snprintf(want, sizeof want,
                     "{'descr': '<f4', 'fortran_order': False, 'shape': (%zu, %zu), }",
                     shapes[k][0], shapes[k][1]);
        else
            snprintf(want, sizeof want,
                     "{'descr': '<f4', 'fortran_order': False, 'shape': (%zu, %zu, %zu), }",
                     shapes[k][0], shapes[k][1], shapes[k][2]);
        const size_t wl = strlen(want);
        CU_ASSERT(memcmp(buf + 10, want, wl) == 0);
        for (size_t i = 10 + wl; i < n - 1; i++)
            CU_ASSERT(buf[i] == ' ');
    }
    unsigned char small[64];
    CU_ASSERT(sea_arrays_npy_header(48, 64, 1, small, sizeof small) == 0); /* 128 needed */
}

/* EXR (FLOAT and HALF, none, ZIP, PIZ) -> sea_exr_read -> .npy -> the
 * reader above: the same bits, the last axis in the order given. */
static void test_npy_round_trip(void)
{
    static const sea_exr_compression comp[] = {SEA_EXR_NONE, SEA_EXR_ZIP, SEA_EXR_PIZ};
    const int w = 37, h = 53;
    const size_t n = (size_t)w * (size_t)h;
    char exr[8192], npy[8192];
    join(exr, sizeof exr, "in.exr");
    join(npy, sizeof npy, "out.npy");
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    CU_ASSERT_FATAL(a != NULL && b != NULL);
    for (int half = 0; half < 2; half++)
        for (size_t k = 0; k < 3; k++) {
            fill_values(a, n, 7 + k, half);
            fill_values(b, n, 70 + k, half);
            const sea_exr_channel ch[] = {{"T", a}, {"Y", b}};
            const sea_exr_options opt = {half ? SEA_EXR_HALF : SEA_EXR_FLOAT, comp[k]};
            sea_error err = {""};
            CU_ASSERT_FATAL(sea_exr_write(exr, w, h, ch, 2, NULL, 0, &opt, &err) == SEA_OK);
            sea_exr_image img = {0};
            CU_ASSERT_FATAL(sea_exr_read(exr, &img, &err) == SEA_OK);
            CU_ASSERT_FATAL(img.n_channels == 2);
            /* one plane, then both in the order Y, T */
            for (size_t np = 1; np <= 2; np++) {
                const float *planes[2] = {img.data[1], img.data[0]};
                FILE *f = fopen(npy, "wb");
                CU_ASSERT_FATAL(f != NULL);
                CU_ASSERT(sea_arrays_write_npy(f, (size_t)w, (size_t)h, planes, np, &err) ==
                          SEA_OK);
                fclose(f);
                size_t len, shape[3] = {0};
                int ndim = 0;
                float *got = NULL;
                unsigned char *bytes = slurp(npy, &len);
                CU_ASSERT_FATAL(npy_read(bytes, len, shape, &ndim, &got) == 0);
                CU_ASSERT(ndim == (np == 1 ? 2 : 3));
                CU_ASSERT(shape[0] == (size_t)h && shape[1] == (size_t)w);
                CU_ASSERT(np == 1 || shape[2] == 2);
                size_t differ = 0;
                for (size_t q = 0; q < n; q++)
                    for (size_t c = 0; c < np; c++)
                        differ += memcmp(&got[q * np + c], &planes[c][q], 4) != 0;
                if (differ)
                    fprintf(stderr, "  half %d comp %zu planes %zu: %zu values differ\n", half, k,
                            np, differ);
                CU_ASSERT(differ == 0);
                free(got);
                free(bytes);
            }
            sea_exr_image_free(&img);
        }
    free(a);
    free(b);
}

/* CSV: the header, one line a pixel, x fastest, and every value read back
 * by strtof is the same float (%.9g is exact for binary32). */
static void test_csv_round_trip(void)
{
    const size_t w = 29, h = 17, n = w * h;
    char path[8192];
    join(path, sizeof path, "out.csv");
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    CU_ASSERT_FATAL(a != NULL && b != NULL);
    fill_values(a, n, 5, 0);
    fill_values(b, n, 55, 1);
    const float *planes[2] = {a, b};
    const char *names[2] = {"emissivity", "Y"};
    FILE *f = fopen(path, "w");
    CU_ASSERT_FATAL(f != NULL);
    sea_error err = {""};
    CU_ASSERT(sea_arrays_write_csv(f, w, h, names, planes, 2, &err) == SEA_OK);
    fclose(f);
    size_t len;
    char *text = (char *)slurp(path, &len);
    CU_ASSERT_FATAL(strncmp(text, "x,y,emissivity,Y\n", 17) == 0);
    char *p = text + 17;
    size_t rows = 0, differ = 0, misplaced = 0;
    while (*p) {
        char *end;
        const unsigned long x = strtoul(p, &end, 10);
        const unsigned long y = strtoul(end + 1, &end, 10);
        const float va = strtof(end + 1, &end);
        const float vb = strtof(end + 1, &end);
        CU_ASSERT_FATAL(*end == '\n');
        p = end + 1;
        misplaced += x != rows % w || y != rows / w;
        if (rows < n)
            differ += memcmp(&va, &a[rows], 4) != 0 || memcmp(&vb, &b[rows], 4) != 0;
        rows++;
    }
    CU_ASSERT(rows == n);
    CU_ASSERT(misplaced == 0);
    if (differ)
        fprintf(stderr, "  %zu CSV rows do not read back exactly\n", differ);
    CU_ASSERT(differ == 0);
    free(text);
    free(a);
    free(b);
}

/* Refused: no planes, an empty side, a name that breaks the CSV; a
 * stream that fails (/dev/full) is SEA_ERR_IO. */
static void test_errors(void)
{
    float v[4] = {1, 2, 3, 4};
    const float *planes[1] = {v};
    const char *comma[1] = {"a,b"}, *ok[1] = {"Y"};
    char path[8192];
    join(path, sizeof path, "err.csv");
    FILE *f = fopen(path, "w");
    CU_ASSERT_FATAL(f != NULL);
    sea_error err = {""};
    CU_ASSERT(sea_arrays_write_npy(f, 2, 2, planes, 0, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_arrays_write_npy(f, 0, 2, planes, 1, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(sea_arrays_write_csv(f, 2, 2, comma, planes, 1, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "a,b") != NULL);
    fclose(f);
    f = fopen("/dev/full", "w");
    if (f != NULL) {
        enum { W = 300, H = 300 };
        float *big = calloc((size_t)W * H, sizeof *big);
        CU_ASSERT_FATAL(big != NULL);
        const float *bp[1] = {big};
        CU_ASSERT(sea_arrays_write_npy(f, W, H, bp, 1, &err) == SEA_ERR_IO);
        clearerr(f);
        CU_ASSERT(sea_arrays_write_csv(f, W, H, ok, bp, 1, &err) == SEA_ERR_IO);
        fclose(f);
        free(big);
    }
}

static int suite_init(void)
{
    const char *base = getenv("TMPDIR");
    if (base == NULL || base[0] == '\0')
        base = "/tmp";
    snprintf(tmp_dir, sizeof tmp_dir, "%s/seabake-arrays.XXXXXX", base);
    return mkdtemp(tmp_dir) == NULL;
}

static int suite_cleanup(void)
{
    DIR *d = opendir(tmp_dir);
    if (d != NULL) {
        struct dirent *e;
        while ((e = readdir(d)) != NULL) {
            char p[8192];
            snprintf(p, sizeof p, "%s/%s", tmp_dir, e->d_name);
            if (e->d_name[0] != '.')
                unlink(p);
        }
        closedir(d);
    }
    rmdir(tmp_dir);
    return 0;
}

int test_arrays_register(void)
{
    CU_pSuite s = CU_add_suite("arrays", suite_init, suite_cleanup);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, ".npy header, 64-byte aligned", test_npy_header) ||
           !CU_add_test(s, "EXR -> .npy bit exact (FLOAT, HALF)", test_npy_round_trip) ||
           !CU_add_test(s, "CSV reads back exactly", test_csv_round_trip) ||
           !CU_add_test(s, "errors", test_errors);
}
