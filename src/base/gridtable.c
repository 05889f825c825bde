/* gridtable.c - tables of a quantity on a grid of (x, wavelength): the
 * sky's radiance by zenith angle (model = table) and the atmosphere's
 * transmittance and path radiance by range ([atmosphere] table), as
 * MODTRAN or libRadtran write them.  A CSV text file: '#' comments, a
 * header naming the columns (any order), one row per grid point; the rows
 * must fill the grid x_1 < ... < x_n by wavelength_1 < ... < wavelength_m
 * exactly once each, in any order.  Values are interpolated linearly in x
 * and in wavelength. */
#include "config.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "seabake.h"
#include "internal.h"
#include "textfile.h"

static const long SEA_GRID_BYTES_MAX = 64L << 20;
enum { SEA_GRID_COLS_MAX = 4, SEA_GRID_QUOTE = 60 };

typedef struct {
    const char *name;
    double lo, hi;    /* allowed range, inclusive */
    const char *unit; /* for messages */
    double scale;     /* to SI */
} grid_col;

typedef struct {
    size_t ncols;     /* 2 axes + values */
    grid_col col[SEA_GRID_COLS_MAX];
    int lit;          /* the two values of a row may not both be 0 */
} grid_spec;

struct sea_grid {
    size_t nx, nw, nv;
    double *x, *w;    /* axes, SI (radians or m; m) */
    double *v;        /* v[(i nw + j) nv + c] */
};

/* The sky: zenith_deg in [0, 90] (radians inside), wavelength, radiance in
 * W m^-2 sr^-1 um^-1 (per m inside). */
static const grid_spec SKY_SPEC = {
    3,
    { { "zenith_deg", 0.0, 90.0, "deg", M_PI / 180.0 },
      { "wavelength_um", 1e-3, 1e3, "um", 1e-6 },
      { "radiance", 0.0, 1e3, "W m^-2 sr^-1 um^-1", 1e6 } },
    0
};
/* The atmosphere: range_m in [0, 1e7], wavelength, transmittance in [0, 1],
 * path radiance.  A path that neither transmits nor radiates (both 0) is an
 * air at 0 K, which no table describes: the sea behind it would show
 * radiance 0, which has no brightness temperature. */
static const grid_spec ATM_SPEC = {
    4,
    { { "range_m", 0.0, 1e7, "m", 1.0 },
      { "wavelength_um", 1e-3, 1e3, "um", 1e-6 },
      { "transmittance", 0.0, 1.0, "", 1.0 },
      { "path_radiance", 0.0, 1e3, "W m^-2 sr^-1 um^-1", 1e6 } },
    1
};

void sea_grid_free(sea_grid *g)
{
    if (g == NULL)
        return;
    free(g->x);
    free(g->w);
    free(g->v);
    free(g);
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Sorted distinct values of a[0..n) into *out (malloc'ed), their count. */
static size_t distinct(const double *a, size_t n, size_t stride, double **out)
{
    double *s = malloc((n ? n : 1) * sizeof *s);
    if (s == NULL)
        return 0;
    for (size_t i = 0; i < n; i++)
        s[i] = a[i * stride];
    qsort(s, n, sizeof *s, cmp_double);
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (m == 0 || s[i] != s[m - 1])
            s[m++] = s[i];
    *out = s;
    return m;
}

static size_t index_of(const double *a, size_t n, double v)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = (lo + hi) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

size_t sea_interval_of(const double *x, size_t n, double at)
{
    const size_t i = index_of(x, n, at);
    const size_t lo = i == 0 ? 0 : i - 1;
    return lo > n - 2 ? n - 2 : lo;
}

/* Splits line p at its commas in place: its fields into field[] (at most
 * SEA_GRID_COLS_MAX + 1 kept); returns how many there are. */
static size_t split_fields(char *p, char *field[SEA_GRID_COLS_MAX + 1])
{
    size_t nf = 0;
    for (char *f = p;; nf++) {
        char *comma = strchr(f, ',');
        if (nf < SEA_GRID_COLS_MAX + 1)
            field[nf] = f;
        if (comma == NULL) {
            nf++;
            break;
        }
        *comma = '\0';
        f = comma + 1;
    }
    return nf;
}

/* The header row: each of the spec's columns named once, in any order;
 * order[field] = column of the spec. */
static sea_status grid_header(const char *path, long lineno, const grid_spec *spec,
                              char *const *field, int *order, sea_error *err)
{
    const size_t nc = spec->ncols;
    int seen[SEA_GRID_COLS_MAX] = { 0 };
    for (size_t f = 0; f < nc; f++) {
        const char *name = sea_text_trim(field[f]);
        size_t c = 0;
        while (c < nc && strcmp(name, spec->col[c].name) != 0)
            c++;
        if (c == nc || seen[c]++)
            return sea_fail(err, SEA_ERR_PARSE,
                            "%s:%ld: the header must name the columns %s,%s,%s%s%s (any "
                            "order), not '%.*s'",
                            path, lineno, spec->col[0].name, spec->col[1].name,
                            spec->col[2].name, nc > 3 ? "," : "",
                            nc > 3 ? spec->col[3].name : "", SEA_GRID_QUOTE, name);
        order[f] = (int)c;
    }
    return SEA_OK;
}

/* A data row: each field a number within its column's range, into row[]
 * (by the spec's columns, SI). */
static sea_status grid_row(const char *path, long lineno, const grid_spec *spec,
                           char *const *field, const int *order, double *row, sea_error *err)
{
    const size_t nc = spec->ncols;
    for (size_t f = 0; f < nc; f++) {
        const grid_col *c = &spec->col[order[f]];
        const char *t = sea_text_trim(field[f]);
        double v;
        if (sea_text_real(t, &v) != 0)
            return sea_fail(err, SEA_ERR_PARSE, "%s:%ld: %s: '%.*s' is not a number", path,
                            lineno, c->name, SEA_GRID_QUOTE, t);
        if (!(v >= c->lo && v <= c->hi)) {
            /* as many digits as tell the value from the bound it passed */
            char v_txt[SEA_TEXT_REAL_CHARS], lo[SEA_TEXT_REAL_CHARS], hi[SEA_TEXT_REAL_CHARS];
            return sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: %s: %s is out of range (allowed: "
                            "[%s, %s]%s%s)", path, lineno, c->name,
                            sea_text_format_real(v, v_txt), sea_text_format_real(c->lo, lo),
                            sea_text_format_real(c->hi, hi), c->unit[0] ? " " : "", c->unit);
        }
        row[order[f]] = v * c->scale;
    }
    if (spec->lit && row[2] == 0.0 && row[3] == 0.0)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "%s:%ld: %s 0 and %s 0: a path that neither transmits nor radiates "
                        "(allowed: %s > 0 where %s is 0, as the air radiates (1 - %s) "
                        "B(T_air))",
                        path, lineno, spec->col[2].name, spec->col[3].name, spec->col[3].name,
                        spec->col[2].name, spec->col[2].name);
    return SEA_OK;
}

/* The grid of g from the n rows read (nc values each, SI; lines: their
 * line numbers): its distinct first and second columns, every pair once. */
static sea_status grid_fill(const char *path, const grid_spec *spec, const double *rows,
                            const long *lines, size_t n, sea_grid *g, sea_error *err)
{
    const size_t nc = spec->ncols;
    g->nv = nc - 2;
    g->nx = distinct(rows, n, nc, &g->x);
    g->nw = distinct(rows + 1, n, nc, &g->w);
    if (g->x == NULL || g->w == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
    if (g->nx < 2)
        return sea_fail(err, SEA_ERR_PARSE, "%s: %zu distinct %s, at least 2 needed", path,
                        g->nx, spec->col[0].name);
    if (n != g->nx * g->nw)
        return sea_fail(err, SEA_ERR_PARSE,
                        "%s: %zu rows do not fill the grid of %zu %s by %zu wavelength_um (%zu "
                        "rows; allowed: every pair once)",
                        path, n, g->nx, spec->col[0].name, g->nw, g->nx * g->nw);
    g->v = malloc(n * g->nv * sizeof *g->v);
    unsigned char *got = calloc(n, 1);
    if (g->v == NULL || got == NULL) {
        free(got);
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
    }
    for (size_t r = 0; r < n; r++) {
        const size_t i = index_of(g->x, g->nx, rows[r * nc]);
        const size_t j = index_of(g->w, g->nw, rows[r * nc + 1]);
        const size_t q = i * g->nw + j;
        if (got[q]++) {
            free(got);
            return sea_fail(err, SEA_ERR_PARSE, "%s:%ld: %s %g, wavelength_um %g: given twice",
                            path, lines[r], spec->col[0].name, rows[r * nc] / spec->col[0].scale,
                            rows[r * nc + 1] / spec->col[1].scale);
        }
        for (size_t c = 0; c < g->nv; c++)
            g->v[q * g->nv + c] = rows[r * nc + 2 + c];
    }
    free(got);
    return SEA_OK;
}

static sea_status grid_load(const char *path, const grid_spec *spec, sea_grid **out,
                            sea_error *err)
{
    *out = NULL;
    char *text = NULL;
    sea_status st = sea_read_text(path, SEA_GRID_BYTES_MAX, "CSV text file", &text, err);
    if (st != SEA_OK)
        return st;
    const size_t nc = spec->ncols;
    int order[SEA_GRID_COLS_MAX]; /* order[field] = column of the spec */
    double *rows = NULL;          /* nc per row, SI */
    long *lines = NULL;
    size_t n = 0, cap = 0;
    int header = 0;
    long lineno = 0;
    char *cursor = text;
    for (char *p; (p = sea_text_next_line(&cursor, &lineno)) != NULL;) {
        char *field[SEA_GRID_COLS_MAX + 1];
        const size_t nf = split_fields(p, field);
        if (nf != nc) {
            st = sea_fail(err, SEA_ERR_PARSE, "%s:%ld: %zu fields, expected %zu (%s,%s,%s%s%s)",
                          path, lineno, nf, nc, spec->col[0].name, spec->col[1].name,
                          spec->col[2].name, nc > 3 ? "," : "", nc > 3 ? spec->col[3].name : "");
            goto fail;
        }
        if (!header) {
            if ((st = grid_header(path, lineno, spec, field, order, err)) != SEA_OK)
                goto fail;
            header = 1;
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 256;
            double *nr = realloc(rows, cap * nc * sizeof *nr);
            long *nl = nr != NULL ? realloc(lines, cap * sizeof *nl) : NULL;
            if (nr != NULL)
                rows = nr;
            if (nl == NULL) {
                st = sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
                goto fail;
            }
            lines = nl;
        }
        if ((st = grid_row(path, lineno, spec, field, order, rows + n * nc, err)) != SEA_OK)
            goto fail;
        lines[n++] = lineno;
    }
    if (!header) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: no header row (%s,%s,...)", path,
                      spec->col[0].name, spec->col[1].name);
        goto fail;
    }
    sea_grid *g = calloc(1, sizeof *g);
    if (g == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
        goto fail;
    }
    *out = g;
    if ((st = grid_fill(path, spec, rows, lines, n, g, err)) != SEA_OK)
        goto fail;
    free(rows);
    free(lines);
    free(text);
    return SEA_OK;
fail:
    sea_grid_free(*out);
    *out = NULL;
    free(rows);
    free(lines);
    free(text);
    return st;
}

sea_status sea_sky_table_load(const char *path, sea_grid **out, sea_error *err)
{
    sea_status st = grid_load(path, &SKY_SPEC, out, err);
    if (st == SEA_OK && ((*out)->x[0] != 0.0 || (*out)->x[(*out)->nx - 1] != M_PI_2)) {
        st = sea_fail(err, SEA_ERR_DOMAIN,
                      "%s: zenith_deg runs from %g to %g (allowed: from 0 to 90, the whole sky)",
                      path, (*out)->x[0] * 180.0 / M_PI, (*out)->x[(*out)->nx - 1] * 180.0 / M_PI);
        sea_grid_free(*out);
        *out = NULL;
    }
    return st;
}

sea_status sea_atmosphere_table_load(const char *path, sea_grid **out, sea_error *err)
{
    sea_status st = grid_load(path, &ATM_SPEC, out, err);
    if (st == SEA_OK && (*out)->x[0] != 0.0) {
        st = sea_fail(err, SEA_ERR_DOMAIN,
                      "%s: range_m starts at %g (allowed: from 0, the sensor)", path, (*out)->x[0]);
        sea_grid_free(*out);
        *out = NULL;
    }
    return st;
}

void sea_grid_axes(const sea_grid *g, size_t *nx, double *x_max, double *w_min, double *w_max)
{
    *nx = g->nx;
    *x_max = g->x[g->nx - 1];
    *w_min = g->w[0];
    *w_max = g->w[g->nw - 1];
}

sea_status sea_grid_profile(const sea_grid *g, double wavelength, size_t column, double *x,
                            double *out, sea_error *err)
{
    if (column >= g->nv)
        return sea_fail(err, SEA_ERR_DOMAIN, "column %zu of %zu", column, g->nv);
    if (!(wavelength >= g->w[0] && wavelength <= g->w[g->nw - 1]))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "wavelength %g um is outside the table's %g-%g um", wavelength * 1e6,
                        g->w[0] * 1e6, g->w[g->nw - 1] * 1e6);
    size_t j = index_of(g->w, g->nw, wavelength);
    double a = 0.0;
    if (j > 0 && g->w[j] != wavelength) {
        j--;
        a = (wavelength - g->w[j]) / (g->w[j + 1] - g->w[j]);
    }
    for (size_t i = 0; i < g->nx; i++) {
        const double v0 = g->v[(i * g->nw + j) * g->nv + column];
        const double v1 = a > 0.0 ? g->v[(i * g->nw + j + 1) * g->nv + column] : v0;
        x[i] = g->x[i];
        out[i] = (1.0 - a) * v0 + a * v1;
    }
    return SEA_OK;
}

double sea_profile_at(const double *x, const double *v, size_t n, double at)
{
    if (!(at > x[0]))
        return v[0];
    if (!(at < x[n - 1]))
        return v[n - 1];
    const size_t i = index_of(x, n, at) - 1; /* x[i] < at <= x[i + 1] */
    const double a = (at - x[i]) / (x[i + 1] - x[i]);
    return (1.0 - a) * v[i] + a * v[i + 1];
}
