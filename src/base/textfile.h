/* textfile.h - library-internal: reading a whole text file (scene files,
 * response curves, water tables) with the same checks and messages. */
#ifndef SEABAKE_TEXTFILE_H
#define SEABAKE_TEXTFILE_H

#include "internal.h"
#include "seabake.h"

/* Reads the regular file path into a NUL-terminated malloc'ed *out.
 * SEA_ERR_IO when it cannot be opened, is not a regular file or a read
 * fails; SEA_ERR_PARSE when it is larger than max_bytes or holds a NUL
 * byte ("contains a NUL byte: not a <kind>", kind e.g. "text file");
 * SEA_ERR_NOMEM.  Messages start with the path. */
SEA_INTERNAL sea_status sea_read_text(const char *path, long max_bytes, const char *kind,
                                      char **out, sea_error *err);

/* The next line of a text being read in place (*cursor: where the rest
 * starts, NULL at the end; *lineno counts every line, the one returned
 * included) that holds something: trimmed, neither empty nor a '#'
 * comment; NULL when none is left.  The line's end is overwritten.  A
 * UTF-8 byte order mark at the start of the text is skipped, as scene
 * files skip it. */
SEA_INTERNAL char *sea_text_next_line(char **cursor, long *lineno);
/* The length of a UTF-8 byte order mark at s (3), or 0 when s does not
 * start with one. */
SEA_INTERNAL size_t sea_text_bom(const char *s);
/* Trims blanks (and a CR) at both ends, in place. */
SEA_INTERNAL char *sea_text_trim(char *s);
/* strtod over the whole string into *out: 0; -1 for no number, trailing
 * text or NaN, 1 for a value beyond double range (1e400; infinities
 * written as such are numbers: the range checks decide about them).  A value below the normal range
 * (4.9e-324, 1e-400) is a number: strtod's subnormal or zero, as the
 * command line reads it. */
SEA_INTERNAL int sea_text_real(const char *s, double *out);
/* The shortest "%.*g" text of v (1 to 17 significant digits) that reads
 * back as v, into buf (at least SEA_TEXT_REAL_CHARS bytes): a message
 * that says 1000.0000001 is out of [0, 1000] must not print "1000". */
enum { SEA_TEXT_REAL_CHARS = 32 };
SEA_INTERNAL const char *sea_text_format_real(double v, char *buf);

#endif /* SEABAKE_TEXTFILE_H */
