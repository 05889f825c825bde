/* convert.c - the convert subcommand of seabake: the channels of an EXR
 * file seabake wrote (a render, its AOVs, the camera's image, a bake's
 * maps) as a NumPy .npy array or a CSV table, for those who analyse images
 * without an OpenEXR module (issue 45). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "cli.h"

static const char CONVERT_HELP[] =
    "Usage: seabake convert IN.exr OUT.npy|OUT.csv [--format npy|csv]\n"
    "                       [--channel NAME[,NAME...]]... [--quiet]\n"
    "\n"
    "The channels of an EXR file as an array NumPy loads (np.load) or as a CSV\n"
    "table.  IN is any EXR seabake writes: single-part scanline, FLOAT or HALF\n"
    "channels, no, ZIP or PIZ compression (render's image and AOVs, the\n"
    "camera's image, a bake's maps).  The format is OUT's extension (.npy or\n"
    ".csv, any case) unless --format names it.  OUT is written under a\n"
    "temporary name and renamed when complete: on any error nothing is left.\n"
    "\n"
    ".npy: NumPy format 1.0, little-endian float32 ('<f4'), C order, row 0\n"
    "the top row of the image: shape (H, W) for one channel, (H, W, C) for C\n"
    "channels, the last axis in the channel order below.  HALF channels are\n"
    "widened to float32, which holds every half value exactly: the array is\n"
    "bit for bit what the EXR holds.\n"
    ".csv: a header line x,y,NAME..., then one line a pixel, y from 0 at the\n"
    "top, x from 0 at the left, x varying fastest; values printed with %.9g,\n"
    "which reads back (strtof, Python's float) as the same binary32 value.\n"
    "\n"
    "Channel order: the --channel names in the order given; without\n"
    "--channel, every channel of IN in the file's order (EXR sorts them by\n"
    "name: T before Y, emissivity before reflectivity).  A summary line on\n"
    "standard error states the size and the order; nothing goes to standard\n"
    "output.\n"
    "\n"
    "Options:\n"
    "  --format F          npy or csv: the format whatever OUT's extension\n"
    "                      (which must then not name the other one)\n"
    "  --channel NAME      a channel of IN (e.g. Y, T); repeatable, or a comma\n"
    "                      list; default every channel\n"
    "  --quiet             no summary line\n";

static const sea_cli_option CONVERT_OPTIONS[] = {{"in", SEA_CLI_OPT_POSITIONAL},
                                                 {"out", SEA_CLI_OPT_POSITIONAL},
                                                 {"format", 0},
                                                 {"channel", SEA_CLI_OPT_ACCUMULATE},
                                                 {"quiet", SEA_CLI_OPT_FLAG}};

typedef enum { CONVERT_NPY, CONVERT_CSV } convert_format;

/* The format from --format, else from OUT's extension. */
static sea_status convert_format_of(const sea_cli_args *args, const char *out,
                                    convert_format *fmt, sea_error *err)
{
    const bool npy_ext = sea_cli_has_suffix(out, ".npy"), csv_ext = sea_cli_has_suffix(out, ".csv");
    const char *given = sea_cli_args_get(args, "format");
    if (given == NULL) {
        if (!npy_ext && !csv_ext)
            return sea_fail(err, SEA_ERR_PARSE,
                            "'%s': unknown output format (allowed: a name ending in .npy or "
                            ".csv, or --format npy|csv)",
                            out);
        *fmt = npy_ext ? CONVERT_NPY : CONVERT_CSV;
        return SEA_OK;
    }
    if (strcmp(given, "npy") == 0)
        *fmt = CONVERT_NPY;
    else if (strcmp(given, "csv") == 0)
        *fmt = CONVERT_CSV;
    else
        return sea_fail(err, SEA_ERR_PARSE, "--format: '%s' is not a format (allowed: npy, csv)",
                        given);
    if ((*fmt == CONVERT_NPY && csv_ext) || (*fmt == CONVERT_CSV && npy_ext))
        return sea_fail(err, SEA_ERR_DOMAIN, "--format %s, but '%s' ends in .%s", given, out,
                        npy_ext ? "npy" : "csv");
    return SEA_OK;
}

/* "T, Y": the channels of img, for messages. */
static void channel_list(const sea_exr_image *img, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (size_t c = 0; c < img->n_channels && used < size; c++) {
        int w = snprintf(buf + used, size - used, "%s%s", c ? ", " : "", img->names[c]);
        if (w < 0)
            break;
        used += (size_t)w;
    }
}

/* The indices into img of the channels asked for (every --channel value,
 * each a comma list), in order; all of img's without --channel.  *idx is
 * malloc'ed, *n of them. */
static sea_status select_channels(const sea_cli_args *args, const char *in,
                                  const sea_exr_image *img, size_t **idx, size_t *n,
                                  sea_error *err)
{
    const size_t given = sea_cli_args_count(args, "channel");
    size_t cap = img->n_channels;
    for (size_t i = 0; i < given; i++)
        for (const char *p = sea_cli_args_nth(args, "channel", i); *p; p++)
            cap += *p == ',';
    cap += given;
    *n = 0;
    if ((*idx = malloc(cap * sizeof **idx)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    if (given == 0) {
        for (size_t c = 0; c < img->n_channels; c++)
            (*idx)[(*n)++] = c;
        return SEA_OK;
    }
    char present[512];
    channel_list(img, present, sizeof present);
    for (size_t i = 0; i < given; i++) {
        const char *list = sea_cli_args_nth(args, "channel", i);
        for (const char *p = list;;) {
            const char *end = strchr(p, ',');
            const size_t len = end ? (size_t)(end - p) : strlen(p);
            if (len == 0)
                return sea_fail(err, SEA_ERR_PARSE, "--channel: '%s' has an empty name", list);
            size_t c = 0;
            while (c < img->n_channels &&
                   !(strlen(img->names[c]) == len && strncmp(img->names[c], p, len) == 0))
                c++;
            if (c == img->n_channels)
                return sea_fail(err, SEA_ERR_DOMAIN, "--channel: '%s' has no channel '%.*s' (its "
                                "channels: %s)", in, (int)len, p, present);
            for (size_t k = 0; k < *n; k++)
                if ((*idx)[k] == c)
                    return sea_fail(err, SEA_ERR_DOMAIN, "--channel: '%.*s' given twice",
                                    (int)len, p);
            (*idx)[(*n)++] = c;
            if (end == NULL)
                break;
            p = end + 1;
        }
    }
    return SEA_OK;
}

/* The reader's failure on path, or, for a readable file that does not
 * begin with the EXR magic number 76 2f 31 01, one saying so (the
 * decoder's words for it, "Error reading from stream", name no cause). */
static sea_status read_failure(const char *path, sea_status st, const sea_error *lib,
                               sea_error *err)
{
    static const unsigned char EXR_MAGIC[4] = {0x76, 0x2f, 0x31, 0x01};
    unsigned char head[4] = {0};
    FILE *f = fopen(path, "rb");
    const size_t got = f != NULL ? fread(head, 1, sizeof head, f) : 0;
    const bool readable = f != NULL && !ferror(f); /* a directory opens, but not reads */
    if (f != NULL)
        fclose(f);
    if (readable && (got < sizeof head || memcmp(head, EXR_MAGIC, sizeof head) != 0))
        return sea_fail(err, st, "'%s' is not an OpenEXR file (it does not begin with the EXR "
                        "magic number 76 2f 31 01)", path);
    return sea_fail(err, st, "%s", lib->msg);
}

/* The summary line: what was read, the shape and the channel order. */
static void print_summary(const char *in, const char *out, convert_format fmt,
                          const sea_exr_image *img, const size_t *idx, size_t n)
{
    size_t halves = 0;
    for (size_t k = 0; k < n; k++)
        halves += img->pixel[idx[k]] == SEA_EXR_HALF;
    fprintf(stderr, "convert: '%s' -> '%s': %d x %d pixels, ", in, out, img->width, img->height);
    if (fmt == CONVERT_NPY && n == 1)
        fprintf(stderr, "float32 shape (%d, %d), channel ", img->height, img->width);
    else if (fmt == CONVERT_NPY)
        fprintf(stderr, "float32 shape (%d, %d, %zu), last axis ", img->height, img->width, n);
    else
        fprintf(stderr, "CSV columns x,y then ");
    for (size_t k = 0; k < n; k++)
        fprintf(stderr, "%s%s", k ? "," : "", img->names[idx[k]]);
    if (halves > 0)
        fprintf(stderr, " (%zu half channel%s, widened exactly)", halves, halves == 1 ? "" : "s");
    fputc('\n', stderr);
}

/* Writes the chosen planes of img to out, atomically. */
static sea_status write_output(const char *out, convert_format fmt, const sea_exr_image *img,
                               const size_t *idx, size_t n, sea_error *err)
{
    const float **planes = malloc(n * sizeof *planes);
    const char **names = malloc(n * sizeof *names);
    if (planes == NULL || names == NULL) {
        free(planes);
        free(names);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    }
    for (size_t k = 0; k < n; k++) {
        planes[k] = img->data[idx[k]];
        names[k] = img->names[idx[k]];
    }
    sea_cli_atomic_file af;
    sea_status st = sea_cli_atomic_open(&af, "convert", out, err);
    if (st == SEA_OK) {
        sea_error lib = {{0}};
        const size_t w = (size_t)img->width, h = (size_t)img->height;
        st = fmt == CONVERT_NPY ? sea_arrays_write_npy(af.f, w, h, planes, n, &lib)
                                : sea_arrays_write_csv(af.f, w, h, names, planes, n, &lib);
        if (st != SEA_OK) {
            sea_cli_atomic_abort(&af);
            sea_fail(err, st, "'%s': %s", out, lib.msg);
        } else {
            st = sea_cli_atomic_commit(&af, "convert", err);
        }
    }
    free(planes);
    free(names);
    return st;
}

static sea_status run_convert(const sea_cli_args *args, FILE *out_stream, sea_error *err)
{
    (void)out_stream; /* the data go to OUT, the summary to stderr */
    const char *in = sea_cli_args_get(args, "in");
    const char *out = sea_cli_args_get(args, "out");
    if (in == NULL || out == NULL || in[0] == '\0' || out[0] == '\0')
        return sea_fail(err, SEA_ERR_DOMAIN, "convert needs IN.exr and OUT.npy or OUT.csv");
    convert_format fmt = CONVERT_NPY;
    sea_status st = convert_format_of(args, out, &fmt, err);
    if (st != SEA_OK)
        return st;
    /* a typing mistake in OUT's directory is reported before the read */
    if ((st = sea_cli_check_parent_writable("convert", out, err)) != SEA_OK)
        return st;
    sea_exr_image img = {0};
    sea_error lib = {{0}};
    if ((st = sea_exr_read(in, &img, &lib)) != SEA_OK)
        return read_failure(in, st, &lib, err);
    size_t *idx = NULL, n = 0;
    st = select_channels(args, in, &img, &idx, &n, err);
    if (st == SEA_OK) {
        sea_cli_clean_stale_files("convert", out);
        st = write_output(out, fmt, &img, idx, n, err);
    }
    if (st == SEA_OK && !sea_cli_given(args, "quiet"))
        print_summary(in, out, fmt, &img, idx, n);
    free(idx);
    sea_exr_image_free(&img);
    return st;
}

const sea_cli_command sea_cli_cmd_convert = {
    "convert", "an EXR image's channels as a NumPy .npy array or a CSV table", CONVERT_HELP,
    CONVERT_OPTIONS, SEA_CLI_COUNT(CONVERT_OPTIONS), run_convert};
