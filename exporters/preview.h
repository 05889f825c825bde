/* preview.h - grayscale PNG previews (libpng), written atomically: to a
 * temporary name in the destination's directory, renamed when complete.
 * Installed as <seabake/preview.h>; the thread-safety words follow
 * seabake.h. */
#ifndef SEABAKE_PREVIEW_H
#define SEABAKE_PREVIEW_H

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
 * Thread-safe (sorts a copy of data; [0, 1] when none can be allocated). */
void sea_png_range(const float *data, size_t n, double clip, double *lo, double *hi);

#endif /* SEABAKE_PREVIEW_H */
