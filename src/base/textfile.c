/* textfile.c - reading a whole text file, for every text input of the
 * library. */
#include "config.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "textfile.h"

sea_status sea_read_text(const char *path, long max_bytes, const char *kind, char **out,
                         sea_error *err)
{
    sea_status st = SEA_OK;
    char *text = NULL;
    *out = NULL;
    /* Non-blocking, so that a FIFO (or a device) is refused by the check
     * below instead of blocking the open until a writer appears. */
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        close(fd);
        return sea_fail(err, SEA_ERR_IO, "%s: not a regular file", path);
    }
    FILE *f = fdopen(fd, "rb");
    if (f == NULL) {
        close(fd);
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
    }
    if (sb.st_size > max_bytes) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: %lld bytes is larger than the %ld allowed", path,
                      (long long)sb.st_size, max_bytes);
        goto done;
    }
    const size_t size = (size_t)sb.st_size;
    if ((text = malloc(size + 1)) == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    if (fread(text, 1, size, f) != size) {
        st = sea_fail(err, SEA_ERR_IO, "%s: read error", path);
        goto done;
    }
    text[size] = '\0';
    if (strlen(text) != size) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: contains a NUL byte: not a %s", path, kind);
        goto done;
    }
    *out = text;
    text = NULL;
done:
    free(text);
    fclose(f);
    return st;
}

size_t sea_text_bom(const char *s)
{
    return strncmp(s, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

char *sea_text_next_line(char **cursor, long *lineno)
{
    while (*cursor != NULL) {
        char *line = *cursor;
        char *next = strchr(line, '\n');
        if (next != NULL)
            *next++ = '\0';
        *cursor = next;
        /* Editors on Windows start UTF-8 files with a byte order mark,
         * which would otherwise become part of the first header name. */
        if (++*lineno == 1)
            line += sea_text_bom(line);
        char *p = sea_text_trim(line);
        if (*p != '\0' && *p != '#')
            return p;
    }
    return NULL;
}

char *sea_text_trim(char *s)
{
    while (*s != '\0' && isspace((unsigned char)*s))
        s++;
    size_t l = strlen(s);
    while (l > 0 && isspace((unsigned char)s[l - 1]))
        s[--l] = '\0';
    return s;
}

int sea_text_real(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    /* ERANGE with a finite result is an underflow (a subnormal or zero),
     * still the nearest double; with an infinite one, an overflow. */
    if (end == s || *end != '\0' || isnan(v))
        return -1;
    if (errno == ERANGE && isinf(v))
        return 1;
    *out = v;
    return 0;
}

const char *sea_text_format_real(double v, char *buf)
{
    /* At least the digits before the point below 1e15, so that a bound
     * reads 1000000, not 1e+06. */
    const double mag = fabs(v);
    int digits = mag >= 1.0 && mag < 1e15 ? (int)floor(log10(mag)) + 1 : 1;
    for (; digits <= 17; digits++) {
        snprintf(buf, SEA_TEXT_REAL_CHARS, "%.*g", digits, v);
        if (strtod(buf, NULL) == v || !isfinite(v))
            break;
    }
    return buf;
}
