/* preview.h - grey and RGB PNG previews (libpng) and their tone curves, written atomically: to a
 * temporary name in the destination's directory, renamed when complete.
 * Installed as <seabake/preview.h>; the thread-safety words follow
 * seabake.h. */
#ifndef SEABAKE_PREVIEW_H
#define SEABAKE_PREVIEW_H

#include <stdbool.h>
#include <stddef.h>

#include "seabake.h"

/* Writes width x height values (row 0 at the top) as an 8- or 16-bit
 * grayscale PNG: lo maps to black, hi to white, linearly, clamped; values
 * are stored as they are (no gamma: the file carries gAMA 1.0 so viewers
 * show the linear ramp).  lo < hi, both finite; NaN values are refused.
 * bits: 8 or 16.  Thread-safe: reads data; threads writing the same path at
 * once each write a temporary file of their own, and the last rename wins. */
sea_status sea_png_write_gray(const char *path, int width, int height, const float *data,
                              double lo, double hi, int bits, sea_error *err);

/* Robust display range of the finite values of data (n of them): the
 * fraction `clip` and 1 - clip quantiles (clip in [0, 0.5)); a constant
 * image gets [v - 0.5, v + 0.5] (or [v - |v|/2, v + |v|/2]) so that lo < hi.
 * The quantiles are the values at indices floor(clip (m - 1)) and
 * ceil((1 - clip) (m - 1)) of the m finite values sorted, found by
 * selection in a copy of data (O(m); the values a sort gives); [0, 1] when
 * no copy can be allocated.
 * Thread-safe. */
void sea_png_range(const float *data, size_t n, double clip, double *lo, double *hi);

/* ------------------------------------------------------------ tone curves */

/* The grey level of the knee of a tone curve, as a fraction of white. */
#define SEA_PNG_KNEE_GREY 0.8

/* A tone curve from values to grey in [0, 1], two linear ramps: from lo
 * (black) to knee (grey G = SEA_PNG_KNEE_GREY), and from knee to hi
 * (white), gentler, for a hot tail (a sun glint):
 *   g = G (v - lo) / (knee - lo)                     lo <= v <= knee
 *   g = G + (1 - G) (v - knee) / (hi - knee)         knee <= v <= hi
 * Values outside [lo, hi] clamp.  knee == hi is one ramp from lo to hi
 * (sea_png_tone_init makes it so whenever the upper ramp would be the
 * steeper, hi <= lo + (knee - lo) / G).  Linear in the value on each ramp,
 * so grey differences read as value differences, at two scales. */
typedef struct {
    double lo, knee, hi;
} sea_png_tone;

/* The curve through lo, knee, hi (lo < hi, finite; lo < knee; knee >= hi
 * or NaN: one ramp).  SEA_ERR_DOMAIN otherwise.  Thread-safe. */
sea_status sea_png_tone_init(double lo, double knee, double hi, sea_png_tone *tone,
                             sea_error *err);
/* A linear curve, lo to hi (as sea_png_tone_init(lo, NAN, hi)). */
sea_status sea_png_tone_linear(double lo, double hi, sea_png_tone *tone, sea_error *err);
/* The automatic curve of the finite values of data (n of them): lo the
 * 0.5 % quantile, hi the maximum, knee = 2 median - lo (the median
 * mirrored about the black point: the top of the bulk of a scene whose
 * hot tail, a sun glint, covers less than half of it), one ramp to hi when
 * the tail is short (see sea_png_tone); a median equal to lo (more than half
 * the image at its coldest value) puts the knee at the 99.5 % quantile.  A
 * constant image gets lo, hi = v -/+ 0.5 (or |v|/2).  Quantiles are order
 * statistics (index floor(p (m - 1)) of the m sorted finite values) found
 * by selection, O(m).  Thread-safe (selects in a copy; with no memory,
 * the linear [0, 1]). */
void sea_png_tone_auto(const float *data, size_t n, sea_png_tone *tone);
/* The sea's curve, for a scene whose sky would take most of the grey
 * scale (issue 45: an 8-12 um sea under a 265 K sky sat at 72-100 % grey):
 * linear from the SEA_PNG_SEA_CLIP to the 1 - SEA_PNG_SEA_CLIP quantile of
 * the finite values of the sea pixels alone (level[i] > 0; level 0 is the
 * sky), every other value clamped (the sky black or white, a glint
 * brighter than the 99.5 % quantile white).  A constant sea gets v -/+ 0.5
 * (or |v|/2).  Returns the sea pixels used; with none (or no memory: then
 * (size_t)-1), the curve is sea_png_tone_auto's over every value.
 * Thread-safe. */
#define SEA_PNG_SEA_CLIP 0.005
size_t sea_png_tone_sea(const float *data, const float *level, size_t n, sea_png_tone *tone);
/* Whether the sky lies far from the sea, so far that a curve over both
 * leaves the sea a sliver of grey: with R = q995 - q005 the sea's own
 * range (SEA_PNG_SEA_CLIP quantiles of the sea pixels, level > 0), the
 * median of the sky pixels (level 0, finite values) is below q005 - R or
 * above q995 + R.  False when either has no pixel, or without memory.
 * Thread-safe. */
bool sea_png_sky_apart(const float *data, const float *level, size_t n);

/* The grey of value v, in [0, 1] (NaN: 0). */
double sea_png_tone_map(const sea_png_tone *tone, double v);

/* Order statistics of the finite values of data (n of them): q[i] = the
 * value at index floor(p[i] (m - 1)) of the m finite values sorted
 * ascending, p[i] in [0, 1] (clamped); NaN when there are none.  Found by
 * selection (quickselect in a copy), O(m) on average: the same values a
 * sort gives.  Returns m, or (size_t)-1 without memory (q all NaN).
 * Thread-safe. */
size_t sea_png_quantiles(const float *data, size_t n, const double *p, size_t np, double *q);

/* ------------------------------------------------------------------ text */

/* A tEXt chunk: key 1 to 79 printable Latin-1 characters, value text. */
typedef struct {
    const char *key, *value;
} sea_png_text;

/* As sea_png_write_gray, through a tone curve, with n_text tEXt chunks. */
sea_status sea_png_write_toned(const char *path, int width, int height, const float *data,
                               const sea_png_tone *tone, int bits, const sea_png_text *text,
                               size_t n_text, sea_error *err);

/* Writes an 8- or 16-bit RGB PNG: rgb holds width x height pixels of three
 * values each (R, G, B, row 0 at the top), in [0, 1] (clamped; NaN
 * refused), stored linearly with gAMA 1.0 as the grey previews; n_text tEXt
 * chunks.  Atomic and thread-safe as sea_png_write_gray. */
sea_status sea_png_write_rgb(const char *path, int width, int height, const float *rgb, int bits,
                             const sea_png_text *text, size_t n_text, sea_error *err);

#endif /* SEABAKE_PREVIEW_H */
