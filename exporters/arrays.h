/* arrays.h - images as arrays other programs read without OpenEXR: NumPy's
 * .npy (format version 1.0) and CSV, one row a pixel.  Installed as
 * <seabake/arrays.h>; ownership and the thread-safety words follow
 * seabake.h.
 *
 * An image here is width x height pixels of n planes (channels), each plane
 * width * height floats, row 0 at the top (as sea_exr_read returns them).
 * The writers write to the caller's open stream and never close it; the
 * caller makes the file atomic (seabake convert writes to a temporary name
 * and renames it). */
#ifndef SEABAKE_ARRAYS_H
#define SEABAKE_ARRAYS_H

#include <stddef.h>
#include <stdio.h>

#include "seabake.h"

/* The .npy data start at a multiple of this many bytes (NumPy's
 * ARRAY_ALIGN). */
enum { SEA_ARRAYS_NPY_ALIGN = 64 };

/* The header of a .npy file, version 1.0, of a C-order little-endian
 * float32 array: the magic "\x93NUMPY", the version bytes 1 and 0, the
 * header length (uint16, little-endian), then the dictionary
 *   {'descr': '<f4', 'fortran_order': False, 'shape': (H, W), }
 * with shape (H, W) for one plane and (H, W, C) for C > 1, padded with
 * spaces and ended with '\n' so that the whole header is a multiple of
 * SEA_ARRAYS_NPY_ALIGN bytes.  Writes at most size bytes into buf and
 * returns the header's length, or 0 when it does not fit (size < 128
 * always fits one of at most 2^31 x 2^31 x 2^31).  Thread-safe. */
size_t sea_arrays_npy_header(size_t height, size_t width, size_t n_planes, unsigned char *buf,
                             size_t size);

/* Writes the .npy file of the image to f: the header above, then for each
 * pixel in row-major order (y, then x) its n_planes values, as IEEE binary32
 * little-endian whatever the host's order: the floats bit for bit (NaN
 * payloads included).  n_planes >= 1, width, height >= 1.  SEA_ERR_DOMAIN
 * for bad sizes, SEA_ERR_IO when the stream reports an error.  Reads
 * planes; thread-safe on distinct streams. */
sea_status sea_arrays_write_npy(FILE *f, size_t width, size_t height, const float *const *planes,
                                size_t n_planes, sea_error *err);

/* The shortest printf precision that gives back every binary32 exactly
 * (FLT_DECIMAL_DIG): "%.9g" text read by strtof is the same float. */
enum { SEA_ARRAYS_CSV_DIGITS = 9 };

/* Writes the image to f as CSV: a header line "x,y,NAME1,NAME2,...", then
 * one line a pixel, in row-major order (y from 0 at the top, then x from 0
 * at the left): x, y, and the planes' values printed with "%.9g" (exact for
 * binary32: strtof, or Python's float(), gives back the same value; NaN
 * and infinities as "nan", "inf", "-inf").  names[i] names plane i and must
 * hold no comma, quote or line break (SEA_ERR_DOMAIN).  SEA_ERR_IO when
 * the stream reports an error.  Thread-safe on distinct streams. */
sea_status sea_arrays_write_csv(FILE *f, size_t width, size_t height, const char *const *names,
                                const float *const *planes, size_t n_planes, sea_error *err);

#endif /* SEABAKE_ARRAYS_H */
