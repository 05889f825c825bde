/* exr.h - single-part scanline OpenEXR files through the OpenEXR C API
 * (libOpenEXRCore), written atomically.  Installed as <seabake/exr.h>;
 * ownership and the thread-safety words follow seabake.h.
 *
 * Files are what Blender 3.4 and POV-Ray 3.7 read (seabake(1), bake):
 * one part, scanline, lossless compression, FLOAT or HALF channels.
 * Row 0 of every buffer is the top row of the image.
 *
 * Writing goes to a temporary in the destination's directory, a directory
 * "<path>.tmp.XXXXXX" holding the data and a marker that names its writer
 * (so that a later run can prove it stale if the writer dies); the data is
 * renamed over the destination only when the whole file is written; on any
 * failure the temporary is removed and the destination is untouched. */
#ifndef SEABAKE_EXR_H
#define SEABAKE_EXR_H

#include <stddef.h>

#include "seabake.h"

typedef enum {
    SEA_EXR_FLOAT = 0, /* 32-bit IEEE */
    SEA_EXR_HALF       /* 16-bit, about 3.3 significant digits */
} sea_exr_pixel;

typedef enum {
    SEA_EXR_NONE = 0,
    SEA_EXR_ZIP,  /* zlib, 16 scanlines per chunk */
    SEA_EXR_PIZ   /* wavelet, 32 scanlines per chunk */
} sea_exr_compression;

/* One channel: its name (1..31 printable ASCII characters, unique in a file)
 * and width * height values, row 0 at the top. */
typedef struct {
    const char *name;
    const float *data;
} sea_exr_channel;

/* A string attribute stored in the header (name 1..63 characters, not one
 * of the required EXR attributes; value any NUL-terminated text). */
typedef struct {
    const char *name;
    const char *value;
} sea_exr_attr;

typedef struct {
    sea_exr_pixel pixel;
    sea_exr_compression compression;
} sea_exr_options;

/* Writes width x height pixels (1..65536 each) of n_channels (1..64)
 * channels to path, with n_attrs string attributes (attrs may be NULL when
 * n_attrs is 0); opt NULL means FLOAT, no compression.  Values must be
 * finite, and within +-65504 for HALF (a NaN, an infinity or a value beyond
 * the half range is refused with SEA_ERR_NUMERIC naming the channel and
 * pixel, and nothing is written).  Invalid sizes, names or options are
 * SEA_ERR_DOMAIN, also with nothing written.  SEA_ERR_IO names the path and
 * the OpenEXR or system error.  Thread-safe: reads the caller's channels
 * and attributes; threads writing the same path at once each write a
 * temporary file of their own, and the last rename wins. */
sea_status sea_exr_write(const char *path, int width, int height, const sea_exr_channel *channels,
                         size_t n_channels, const sea_exr_attr *attrs, size_t n_attrs,
                         const sea_exr_options *opt, sea_error *err);

/* An image read back: channel names in file order (sorted), each with
 * width * height floats, row 0 at the top.  Free with sea_exr_image_free. */
typedef struct {
    int width, height;
    size_t n_channels;
    char **names;
    float **data;
    sea_exr_pixel *pixel; /* per channel, as stored */
    size_t n_attrs;       /* string attributes other than the required ones */
    char **attr_names, **attr_values;
} sea_exr_image;

/* Reads every channel of a single-part scanline file (FLOAT or HALF
 * channels) as floats.  SEA_ERR_IO if the file cannot be opened or decoded,
 * SEA_ERR_PARSE if it is tiled, deep, multi-part or has UINT channels.
 * Thread-safe; fills out, which the caller releases with
 * sea_exr_image_free() (on failure it holds nothing to free). */
sea_status sea_exr_read(const char *path, sea_exr_image *out, sea_error *err);
/* The channel called name, or NULL.  Reads img; the data are owned by img. */
const float *sea_exr_image_channel(const sea_exr_image *img, const char *name);
/* The value of string attribute name, or NULL.  Reads img; the string is
 * owned by img. */
const char *sea_exr_image_attr(const sea_exr_image *img, const char *name);
/* Accepts NULL or a zeroed image; leaves it zeroed. */
void sea_exr_image_free(sea_exr_image *img);

#endif /* SEABAKE_EXR_H */
