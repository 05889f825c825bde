/* compare.c - the compare subcommand of seabake: how far one radiance image
 * is from another (a default render from its --reference, say), pixel by
 * pixel, relative to the second. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

static const char COMPARE_HELP[] =
    "Usage: seabake compare A.exr B.exr [--tolerance T] [--channel C]\n"
    "\n"
    "How far image A is from image B, pixel by pixel, relative to B: |A - B| / |B|\n"
    "over the pixels where B is not 0 (the sky and the sea alike).  Prints one\n"
    "CSV row: the pixels compared, the largest relative difference and where it\n"
    "is (x right, y down from the top-left pixel), the rms, and how many\n"
    "pixels differ by more than T.  With --tolerance T the exit status is 1\n"
    "when any does: 'seabake compare default.exr reference.exr --tolerance\n"
    "1e-3' checks a render against its --reference (seabake(1), REFERENCE).\n"
    "\n"
    "Options:\n"
    "  --tolerance T       relative, (0, 1]; exit status 1 when any pixel differs\n"
    "                      by more; default: report only\n"
    "  --channel C         the channel compared in both files (default Y, the\n"
    "                      radiance of seabake render)\n"
    "\n"
    "Columns: pixels,max_rel,max_x,max_y,rms_rel,over_tolerance\n";

static const sea_cli_option COMPARE_OPTIONS[] = {
    {"a", SEA_CLI_OPT_POSITIONAL}, {"b", SEA_CLI_OPT_POSITIONAL}, {"tolerance", 0},
    {"channel", 0}};

/* The channel of one image, or a message naming the file. */
static sea_status read_channel(const char *path, const char *channel, sea_exr_image *img,
                               const float **data, sea_error *err)
{
    sea_error lib = {{0}};
    sea_status st = sea_exr_read(path, img, &lib);
    if (st != SEA_OK)
        return sea_fail(err, st, "%s", lib.msg);
    *data = sea_exr_image_channel(img, channel);
    if (*data == NULL)
        return sea_fail(err, SEA_ERR_PARSE, "'%s' has no channel '%s'", path, channel);
    return SEA_OK;
}

static sea_status run_compare(const sea_cli_args *args, FILE *out, sea_error *err)
{
    const char *a = sea_cli_args_get(args, "a");
    const char *b = sea_cli_args_get(args, "b");
    if (a == NULL || b == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "compare needs two images, A.exr and B.exr");
    static const sea_cli_range tol_range = {0.0, 1.0, true, false, ""};
    double tol = NAN;
    sea_status st = sea_cli_opt_number(args, "tolerance", &tol_range, NAN, &tol, err);
    if (st != SEA_OK)
        return st;
    const char *channel = sea_cli_args_get(args, "channel");
    if (channel == NULL)
        channel = "Y";
    sea_exr_image ia = {0}, ib = {0};
    const float *da = NULL, *db = NULL;
    if ((st = read_channel(a, channel, &ia, &da, err)) == SEA_OK)
        st = read_channel(b, channel, &ib, &db, err);
    if (st == SEA_OK && (ia.width != ib.width || ia.height != ib.height))
        st = sea_fail(err, SEA_ERR_DOMAIN, "'%s' is %d x %d, '%s' %d x %d: not the same pixels", a,
                      ia.width, ia.height, b, ib.width, ib.height);
    if (st == SEA_OK) {
        size_t n = 0, over = 0;
        double worst = 0.0, s2 = 0.0;
        int wx = 0, wy = 0;
        for (int y = 0; y < ia.height && st == SEA_OK; y++)
            for (int x = 0; x < ia.width; x++) {
                const size_t q = (size_t)y * (size_t)ia.width + (size_t)x;
                const double va = da[q], vb = db[q];
                if (!isfinite(va) || !isfinite(vb)) {
                    st = sea_fail(err, SEA_ERR_NUMERIC,
                                  "pixel (%d, %d) is not a finite number in '%s'", x, y,
                                  isfinite(va) ? b : a);
                    break;
                }
                if (vb == 0.0)
                    continue;
                const double r = fabs(va - vb) / fabs(vb);
                if (r > worst || n == 0) {
                    worst = r;
                    wx = x;
                    wy = y;
                }
                s2 += r * r;
                over += r > tol;
                n++;
            }
        if (st == SEA_OK) {
            fprintf(out, "pixels,max_rel,max_x,max_y,rms_rel,over_tolerance\n");
            fprintf(out, "%zu,%.6g,%d,%d,%.6g,%zu\n", n, worst, wx, wy,
                    n > 0 ? sqrt(s2 / (double)n) : 0.0, isnan(tol) ? 0 : over);
            st = sea_cli_check_written(out, err);
            if (st == SEA_OK && !isnan(tol) && over > 0)
                st = sea_fail(err, SEA_ERR_NUMERIC,
                              "%zu of %zu pixels of '%s' differ from '%s' by more than %g "
                              "(the largest %.3g at (%d, %d))",
                              over, n, a, b, tol, worst, wx, wy);
        }
    }
    sea_exr_image_free(&ia);
    sea_exr_image_free(&ib);
    return st;
}

const sea_cli_command sea_cli_cmd_compare = {
    "compare", "how far one radiance image is from another, pixel by pixel", COMPARE_HELP,
    COMPARE_OPTIONS, SEA_CLI_COUNT(COMPARE_OPTIONS), run_compare};
