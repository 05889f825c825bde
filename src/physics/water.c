/* water.c - optical constants of sea water and the Fresnel reflectance.
 *
 * A pure-water table (n, k against wavelength) plus the sea-water minus
 * pure-water correction of Pinkley & Williams (1976), scaled linearly with
 * salinity as the PARMIO ocean model does:
 *   n_sea = n_pure + dn (S / 34.482),  k_sea = k_pure + dk (S / 34.482).
 * Both tables are interpolated linearly in wavenumber, the variable in which
 * the absorption bands are tabulated. */
#include "config.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "seabake.h"
#include "base/textfile.h"
#include "water_data.h"

/* Salinity of the standard sea water that the correction table describes. */
static const double SEA_CORRECTION_SALINITY = 34.482; /* g/kg */
/* User tables larger than this are refused rather than read into memory. */
static const long SEA_TABLE_BYTES_MAX = 64L << 20;

typedef struct {
    size_t len;
    double *nu; /* wavenumber, 1/m, strictly increasing */
    double *a;  /* n (or dn) */
    double *b;  /* k (or dk) */
} sea_table;

struct sea_water {
    sea_table pure;
    sea_table salt;       /* empty when salinity is 0 */
    double salt_scale;    /* S / 34.482 */
    double nu_min, nu_max;
    char describe[256];
};

static void table_free(sea_table *t)
{
    free(t->nu);
    free(t->a);
    free(t->b);
    memset(t, 0, sizeof *t);
}

static sea_status table_push(sea_table *t, size_t *cap, double nu, double a, double b)
{
    if (t->len == *cap) {
        size_t ncap = *cap ? 2 * *cap : 128;
        double *nnu = realloc(t->nu, ncap * sizeof *nnu);
        if (nnu == NULL)
            return SEA_ERR_NOMEM;
        t->nu = nnu;
        double *na = realloc(t->a, ncap * sizeof *na);
        if (na == NULL)
            return SEA_ERR_NOMEM;
        t->a = na;
        double *nb = realloc(t->b, ncap * sizeof *nb);
        if (nb == NULL)
            return SEA_ERR_NOMEM;
        t->b = nb;
        *cap = ncap;
    }
    t->nu[t->len] = nu;
    t->a[t->len] = a;
    t->b[t->len] = b;
    t->len++;
    return SEA_OK;
}

/* Splits one CSV line in place into at most max fields; returns the count. */
static int split_fields(char *line, char **field, int max)
{
    int n = 0;
    char *p = line;
    while (n < max) {
        while (*p == ' ' || *p == '\t')
            p++;
        field[n++] = p;
        char *comma = strchr(p, ',');
        if (comma == NULL)
            break;
        *comma = '\0';
        p = comma + 1;
    }
    for (int i = 0; i < n; i++) { /* trim trailing blanks */
        size_t l = strlen(field[i]);
        while (l > 0 && (field[i][l - 1] == ' ' || field[i][l - 1] == '\t' ||
                         field[i][l - 1] == '\r'))
            field[i][--l] = '\0';
    }
    return n;
}

/* A finite number (sea_text_real, which also reads an underflow as the
 * subnormal or zero it is). */
static int parse_double(const char *s, double *out)
{
    double v;
    if (sea_text_real(s, &v) != 0 || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

enum { SEA_CSV_FIELDS_MAX = 16 };

/* Allowed values of a table's two value columns, [a_min, a_max] and
 * [b_min, b_max]. */
typedef struct {
    double a_min, a_max, b_min, b_max;
} table_bounds;

/* Any finite number (the sea-water correction's signed differences). */
static const table_bounds ANY_FINITE = {-DBL_MAX, DBL_MAX, -DBL_MAX, DBL_MAX};
/* n and k of water. */
static const table_bounds WATER_NK = {SEA_WATER_N_MIN, SEA_WATER_N_MAX, 0.0, SEA_WATER_K_MAX};

/* What table_parse knows of the columns: the names asked for, the bounds
 * of the values, and from the header each column's index (-1 until
 * found), whether x is a wavenumber, and the header's field count. */
typedef struct {
    const char *source, *col_a, *col_b;
    const table_bounds *bounds;
    int ix, ia, ib, x_is_wavenumber, nfields;
} table_cols;

/* The header row: finds the x column (wavenumber_cm1 before
 * wavelength_um) and the two value columns. */
static sea_status table_header(table_cols *tc, char *const *field, int n, long lineno,
                               sea_error *err)
{
    for (int i = 0; i < n; i++) {
        if (strcmp(field[i], "wavelength_um") == 0 && tc->ix < 0) {
            tc->ix = i;
            tc->x_is_wavenumber = 0;
        } else if (strcmp(field[i], "wavenumber_cm1") == 0) {
            tc->ix = i;
            tc->x_is_wavenumber = 1;
        } else if (strcmp(field[i], tc->col_a) == 0) {
            tc->ia = i;
        } else if (strcmp(field[i], tc->col_b) == 0) {
            tc->ib = i;
        }
    }
    if (tc->ix < 0 || tc->ia < 0 || tc->ib < 0)
        return sea_fail(err, SEA_ERR_PARSE,
                        "%s:%ld: header must name the columns wavelength_um (or "
                        "wavenumber_cm1), %s and %s",
                        tc->source, lineno, tc->col_a, tc->col_b);
    tc->nfields = n;
    return SEA_OK;
}

/* A data row: its wavenumber *nu (1/m) and values *a, *b, each a number
 * within its bounds. */
static sea_status table_row(const table_cols *tc, char *const *field, int n, long lineno,
                            double *nu_out, double *a_out, double *b_out, sea_error *err)
{
    const char *source = tc->source, *col_a = tc->col_a, *col_b = tc->col_b;
    const table_bounds *bounds = tc->bounds;
    const int ix = tc->ix, x_is_wavenumber = tc->x_is_wavenumber;
    if (n != tc->nfields)
        return sea_fail(err, SEA_ERR_PARSE, "%s:%ld: %d fields, the header has %d", source,
                        lineno, n, tc->nfields);
    double x, a, b;
    if (parse_double(field[ix], &x) != 0 || x <= 0.0)
        return sea_fail(err, SEA_ERR_PARSE, "%s:%ld: %s: '%s' is not a positive number", source,
                        lineno, x_is_wavenumber ? "wavenumber_cm1" : "wavelength_um",
                        field[ix]);
    if (parse_double(field[tc->ia], &a) != 0)
        return sea_fail(err, SEA_ERR_PARSE, "%s:%ld: %s: '%s' is not a number", source, lineno,
                        col_a, field[tc->ia]);
    if (parse_double(field[tc->ib], &b) != 0)
        return sea_fail(err, SEA_ERR_PARSE, "%s:%ld: %s: '%s' is not a number", source, lineno,
                        col_b, field[tc->ib]);
    /* the value as read, to as many digits as tell it from the bound */
    char v_txt[SEA_TEXT_REAL_CHARS], lo_txt[SEA_TEXT_REAL_CHARS], hi_txt[SEA_TEXT_REAL_CHARS];
    if (!(a >= bounds->a_min && a <= bounds->a_max))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: %s: %s is outside [%s, %s]", source, lineno,
                        col_a, sea_text_format_real(a, v_txt),
                        sea_text_format_real(bounds->a_min, lo_txt),
                        sea_text_format_real(bounds->a_max, hi_txt));
    if (!(b >= bounds->b_min && b <= bounds->b_max))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: %s: %s is outside [%s, %s]", source, lineno,
                        col_b, sea_text_format_real(b, v_txt),
                        sea_text_format_real(bounds->b_min, lo_txt),
                        sea_text_format_real(bounds->b_max, hi_txt));
    double nu = x_is_wavenumber ? x * 100.0 : 1e6 / x; /* 1/m */
    /* Both nu and the wavelength 1/nu must be finite: 1e6 / 2e-307
     * overflowed to an infinite wavenumber, and sea_water_range then
     * gave 0 as the shortest wavelength (found by the water fuzz
     * target). */
    if (!(isfinite(nu) && nu > 0.0 && isfinite(1.0 / nu)))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: %s: %g is outside the range of numbers",
                        source, lineno, x_is_wavenumber ? "wavenumber_cm1" : "wavelength_um", x);
    *nu_out = nu;
    *a_out = a;
    *b_out = b;
    return SEA_OK;
}

/* Whether nu continues t's rows strictly monotonically (0) or not (-1). */
static int table_monotonic(const sea_table *t, double nu)
{
    if (t->len == 0)
        return 0;
    double prev = t->nu[t->len - 1];
    double first = t->nu[0];
    int increasing = t->len > 1 ? t->nu[1] > first : nu > prev;
    return nu == prev || (nu > prev) != increasing ? -1 : 0;
}

/* Reverses t's rows, from decreasing to increasing wavenumber. */
static void table_reverse(sea_table *t)
{
    for (size_t i = 0, j = t->len - 1; i < j; i++, j--) {
        double v;
        v = t->nu[i], t->nu[i] = t->nu[j], t->nu[j] = v;
        v = t->a[i], t->a[i] = t->a[j], t->a[j] = v;
        v = t->b[i], t->b[i] = t->b[j], t->b[j] = v;
    }
}

/* Parses CSV text whose header names the columns.  The x column is either
 * "wavelength_um" or "wavenumber_cm1" (the first of col_x that is present);
 * col_a and col_b name the two value columns, whose values must lie within
 * bounds.  Rows are stored by increasing wavenumber and must be strictly
 * monotonic in the file.  source names the text in messages
 * ("file.csv:12: ..."). */
static sea_status table_parse(const char *text, const char *source, const char *col_a,
                              const char *col_b, const table_bounds *bounds, sea_table *out,
                              sea_error *err)
{
    sea_status st = SEA_OK;
    size_t cap = 0;
    table_cols tc = { source, col_a, col_b, bounds, -1, -1, -1, 0, 0 };
    long lineno = 0;
    char *copy = strdup(text);
    if (copy == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", source);
    memset(out, 0, sizeof *out);

    for (char *line = copy, *next; line != NULL; line = next) {
        next = strchr(line, '\n');
        if (next != NULL)
            *next++ = '\0';
        /* a UTF-8 byte order mark, as sea_text_next_line skips it */
        char *p = ++lineno == 1 ? line + sea_text_bom(line) : line;
        while (*p == ' ' || *p == '\t' || *p == '\r')
            p++;
        if (*p == '\0' || *p == '#')
            continue;
        char *field[SEA_CSV_FIELDS_MAX];
        int n = split_fields(p, field, SEA_CSV_FIELDS_MAX);
        if (tc.ix < 0) { /* header row */
            if ((st = table_header(&tc, field, n, lineno, err)) != SEA_OK)
                goto fail;
            continue;
        }
        double nu = 0.0, a = 0.0, b = 0.0; /* (set by table_row when it returns SEA_OK) */
        if ((st = table_row(&tc, field, n, lineno, &nu, &a, &b, err)) != SEA_OK)
            goto fail;
        if (table_monotonic(out, nu) != 0) {
            st = sea_fail(err, SEA_ERR_PARSE,
                          "%s:%ld: rows must be strictly monotonic in wavelength", source,
                          lineno);
            goto fail;
        }
        if ((st = table_push(out, &cap, nu, a, b)) != SEA_OK) {
            sea_fail(err, st, "%s: out of memory", source);
            goto fail;
        }
    }
    if (out->len < 2) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: a table needs at least two data rows (found %zu)",
                      source, out->len);
        goto fail;
    }
    if (out->nu[0] > out->nu[1]) /* store by increasing wavenumber */
        table_reverse(out);
    free(copy);
    return SEA_OK;
fail:
    free(copy);
    table_free(out);
    return st;
}

/* Linear interpolation in wavenumber; nu must lie inside the table. */
static void table_eval(const sea_table *t, double nu, double *a, double *b)
{
    size_t lo = 0, hi = t->len - 1;
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (t->nu[mid] <= nu)
            lo = mid;
        else
            hi = mid;
    }
    double w = (nu - t->nu[lo]) / (t->nu[hi] - t->nu[lo]);
    *a = t->a[lo] + w * (t->a[hi] - t->a[lo]);
    *b = t->b[lo] + w * (t->b[hi] - t->b[lo]);
}

static const char *builtin_text(const char *name)
{
    for (const sea_data_file *f = sea_data_files; f->name != NULL; f++)
        if (strcmp(f->name, name) == 0)
            return f->text;
    return NULL;
}

/* A copy of table t (NOMEM: out is left empty). */
static int table_copy(const sea_table *t, sea_table *out)
{
    const size_t bytes = t->len * sizeof(double);
    memset(out, 0, sizeof *out);
    out->nu = malloc(bytes);
    out->a = malloc(bytes);
    out->b = malloc(bytes);
    if (out->nu == NULL || out->a == NULL || out->b == NULL) {
        table_free(out);
        return 0;
    }
    memcpy(out->nu, t->nu, bytes);
    memcpy(out->a, t->a, bytes);
    memcpy(out->b, t->b, bytes);
    out->len = t->len;
    return 1;
}

/* The built-in tables, parsed once per process: every command reads the
 * pure-water table and the 3694-row sea-water correction at least twice
 * (the scene's check of its wavelengths, then the optics), and the two
 * parses (strtod of 18 000 numbers each) were 17 % of the instructions of
 * a 4 x 4 render (callgrind).
 * The first caller parses the text with table_parse, as a user's file is
 * parsed, and every caller gets a copy of the result (or of its error):
 * the same numbers bit for bit.  The parsed tables live until the process
 * ends. */
enum { BUILTIN_SLOTS = 8 };
static struct {
    const char *text; /* the built-in text parsed (NULL: slot free) */
    const char *col_a;
    sea_status st;
    sea_error err;
    sea_table t;
} builtin_parsed[BUILTIN_SLOTS];
static pthread_mutex_t builtin_lock = PTHREAD_MUTEX_INITIALIZER;

static sea_status builtin_parse(const char *name, const char *source, const char *col_a,
                                const char *col_b, const table_bounds *bounds, sea_table *out,
                                sea_error *err)
{
    const char *text = builtin_text(name);
    memset(out, 0, sizeof *out);
    if (text == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "no built-in table %s", name);
    sea_status st = SEA_OK;
    sea_error e = { { 0 } };
    sea_table copy = { 0 };
    pthread_mutex_lock(&builtin_lock);
    size_t k = 0;
    while (k < BUILTIN_SLOTS && builtin_parsed[k].text != NULL &&
           !(builtin_parsed[k].text == text && strcmp(builtin_parsed[k].col_a, col_a) == 0))
        k++;
    if (k == BUILTIN_SLOTS) { /* (more tables than slots: parsed each time) */
        pthread_mutex_unlock(&builtin_lock);
        return table_parse(text, source, col_a, col_b, bounds, out, err);
    }
    if (builtin_parsed[k].text == NULL) {
        builtin_parsed[k].st =
            table_parse(text, source, col_a, col_b, bounds, &builtin_parsed[k].t,
                        &builtin_parsed[k].err);
        builtin_parsed[k].col_a = col_a;
        builtin_parsed[k].text = text;
    }
    st = builtin_parsed[k].st;
    if (st != SEA_OK)
        e = builtin_parsed[k].err;
    else if (!table_copy(&builtin_parsed[k].t, &copy))
        st = sea_fail(&e, SEA_ERR_NOMEM, "%s: out of memory", source);
    pthread_mutex_unlock(&builtin_lock);
    if (st != SEA_OK) {
        if (err != NULL)
            *err = e;
        return st;
    }
    *out = copy;
    return SEA_OK;
}

static const struct {
    const char *name, *file, *cite;
} SEA_TABLES[] = {
    [SEA_WATER_HALE_QUERRY] = { "hale-querry", "water_nk_hale_querry",
                                "Hale & Querry 1973, Appl. Opt. 12, 555 (25 C)" },
    [SEA_WATER_SEGELSTEIN] = { "segelstein", "water_nk_segelstein",
                               "Segelstein 1981, M.S. thesis, UMKC" },
};

int sea_water_table_from_name(const char *name)
{
    for (size_t i = 0; i < sizeof SEA_TABLES / sizeof SEA_TABLES[0]; i++)
        if (strcmp(name, SEA_TABLES[i].name) == 0)
            return (int)i;
    return -1;
}

/* n and k at wavenumber nu in [nu_min, nu_max]: the table plus the
 * sea-water correction scaled by salinity (k before clamping at 0). */
static void water_eval(const sea_water *w, double nu, double *n, double *k)
{
    table_eval(&w->pure, nu, n, k);
    if (w->salt.len > 0) {
        double dn, dk;
        table_eval(&w->salt, nu, &dn, &dk);
        *n += dn * w->salt_scale;
        *k += dk * w->salt_scale;
    }
}

/* The corrected index within the bounds of water's (the table's own rows
 * were checked when parsed; the correction moves n by up to 0.03 and could
 * take a table's n = 1.0 below 1).  It is piecewise linear in nu with
 * breakpoints at the rows of both tables, so its extremes are at those rows
 * and at the range's ends. */
static sea_status check_corrected(const sea_water *w, const char *what, double salinity,
                                  sea_error *err)
{
    const sea_table *tables[2] = {&w->pure, &w->salt};
    for (int t = 0; t < 2; t++) {
        for (size_t i = 0; i < tables[t]->len + 2; i++) {
            double nu = i < tables[t]->len ? tables[t]->nu[i]
                                           : i == tables[t]->len ? w->nu_min : w->nu_max;
            if (!(nu >= w->nu_min && nu <= w->nu_max))
                continue;
            double n, k;
            water_eval(w, nu, &n, &k);
            if (!(n >= SEA_WATER_N_MIN && n <= SEA_WATER_N_MAX && k <= SEA_WATER_K_MAX))
                return sea_fail(err, SEA_ERR_DOMAIN,
                                "%s: with the sea-water correction at salinity %g g/kg, n = %.6g, "
                                "k = %.6g at %.6g um (allowed: n in [%g, %g], k in [0, %g])",
                                what, salinity, n, k, 1e6 / nu, SEA_WATER_N_MIN,
                                SEA_WATER_N_MAX, SEA_WATER_K_MAX);
        }
    }
    return SEA_OK;
}

/* Takes ownership of *pure; adds the salinity correction. */
static sea_status water_finish(sea_table *pure, double salinity, const char *what,
                               sea_water **out, sea_error *err)
{
    sea_status st;
    sea_water *w = calloc(1, sizeof *w);
    if (w == NULL) {
        table_free(pure);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    }
    w->pure = *pure;
    memset(pure, 0, sizeof *pure);
    w->nu_min = w->pure.nu[0];
    w->nu_max = w->pure.nu[w->pure.len - 1];
    if (salinity > 0.0) {
        st = builtin_parse("seawater_correction", "seawater_correction.csv", "n_salt_corr",
                           "k_salt_corr", &ANY_FINITE, &w->salt, err);
        if (st != SEA_OK)
            goto fail;
        w->salt_scale = salinity / SEA_CORRECTION_SALINITY;
        w->nu_min = fmax(w->nu_min, w->salt.nu[0]);
        w->nu_max = fmin(w->nu_max, w->salt.nu[w->salt.len - 1]);
        if (w->nu_min >= w->nu_max) {
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "%s does not overlap the sea-water correction (2.40-15.62 um)", what);
            goto fail;
        }
        if ((st = check_corrected(w, what, salinity, err)) != SEA_OK)
            goto fail;
    }
    snprintf(w->describe, sizeof w->describe,
             "%s; sea-water correction Pinkley & Williams 1976 at salinity %g g/kg", what,
             salinity);
    *out = w;
    return SEA_OK;
fail:
    sea_water_free(w);
    return st;
}

static sea_status check_salinity(double salinity, sea_error *err)
{
    if (!(salinity >= 0.0 && salinity <= SEA_SALINITY_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "salinity %g g/kg is outside [0, %g] g/kg",
                        salinity, SEA_SALINITY_MAX);
    return SEA_OK;
}

sea_status sea_water_alloc(sea_water_table table, double salinity, sea_water **out,
                           sea_error *err)
{
    sea_table pure;
    sea_status st;
    *out = NULL;
    if ((unsigned)table >= sizeof SEA_TABLES / sizeof SEA_TABLES[0])
        return sea_fail(err, SEA_ERR_DOMAIN, "unknown water table %d", (int)table);
    if ((st = check_salinity(salinity, err)) != SEA_OK)
        return st;
    char source[64];
    snprintf(source, sizeof source, "%s.csv", SEA_TABLES[table].file);
    st = builtin_parse(SEA_TABLES[table].file, source, "n", "k", &WATER_NK, &pure, err);
    if (st != SEA_OK)
        return st;
    return water_finish(&pure, salinity, SEA_TABLES[table].cite, out, err);
}

sea_status sea_water_load(const char *path, double salinity, sea_water **out, sea_error *err)
{
    sea_status st;
    sea_table pure;
    char *text = NULL;
    *out = NULL;
    if ((st = check_salinity(salinity, err)) != SEA_OK)
        return st;
    if ((st = sea_read_text(path, SEA_TABLE_BYTES_MAX, "CSV text file", &text, err)) != SEA_OK)
        return st;
    if ((st = table_parse(text, path, "n", "k", &WATER_NK, &pure, err)) != SEA_OK)
        goto done;
    st = water_finish(&pure, salinity, path, out, err);
done:
    free(text);
    return st;
}

void sea_water_free(sea_water *w)
{
    if (w == NULL)
        return;
    table_free(&w->pure);
    table_free(&w->salt);
    free(w);
}

void sea_water_range(const sea_water *w, double *wl_min, double *wl_max)
{
    *wl_min = 1.0 / w->nu_max;
    *wl_max = 1.0 / w->nu_min;
}

const char *sea_water_describe(const sea_water *w)
{
    return w->describe;
}

sea_status sea_water_index(const sea_water *w, double wavelength, double complex *N,
                           sea_error *err)
{
    /* The range in wavelength, exactly as sea_water_range gives it (and the
     * scene file is checked against): 1/(1/x) need not be x, so testing the
     * wavenumber instead refused the table's own end (15.5 um: "outside
     * the water table (2.4-15.5 um)").  The wavenumber is then clamped. */
    double wl_min, wl_max;
    sea_water_range(w, &wl_min, &wl_max);
    if (!(wavelength >= wl_min && wavelength <= wl_max))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "wavelength %.6g um is outside the water table (%.6g-%.6g um)",
                        wavelength * 1e6, wl_min * 1e6, wl_max * 1e6);
    const double nu = fmin(fmax(1.0 / wavelength, w->nu_min), w->nu_max);
    double n, k;
    water_eval(w, nu, &n, &k);
    *N = n + I * fmax(k, 0.0);
    return SEA_OK;
}

double sea_fresnel_unpolarized(double cos_psi, double complex N)
{
    /* In real arithmetic: the complex square root and the two complex
     * divisions (csqrt, __divdc3, which guard against overflow that the
     * bounded indices of water cannot reach) cost 6x as much.  With
     * N^2 = A + iB and w = sqrt(N^2 - sin^2 psi) = p + iq (principal root,
     * p >= 0): |r_s|^2 = ((c - p)^2 + q^2)/((c + p)^2 + q^2) and
     * |r_p|^2 = ((Ac - p)^2 + (Bc - q)^2)/((Ac + p)^2 + (Bc + q)^2). */
    const double c = fmin(fmax(cos_psi, 0.0), 1.0);
    const double n = creal(N), k = cimag(N);
    const double A = (n - k) * (n + k), B = 2.0 * n * k;
    /* |z| without hypot's overflow guard: |a|, B <= 2 n^2 + 2 k^2 for the
     * bounded indices of water (SEA_WATER_N_MAX, SEA_WATER_K_MAX). */
    const double a = A - (1.0 - c * c), mod = sqrt(a * a + B * B);
    /* p = sqrt((|z| + a)/2), q = B/(2p); where a < 0 the sum cancels, so
     * q = sign(B) sqrt((|z| - a)/2) first and p = |B|/(2|q|). */
    double p, q;
    if (a >= 0.0) {
        p = sqrt(0.5 * (mod + a));
        q = p > 0.0 ? 0.5 * B / p : 0.0;
    } else {
        q = copysign(sqrt(0.5 * (mod - a)), B);
        p = 0.5 * fabs(B) / fabs(q);
    }
    const double cs_m = c - p, cs_p = c + p;
    const double rs_den = cs_p * cs_p + q * q;
    const double rs2 = rs_den > 0.0 ? (cs_m * cs_m + q * q) / rs_den : 1.0;
    const double Ac = A * c, Bc = B * c;
    const double rp_num = (Ac - p) * (Ac - p) + (Bc - q) * (Bc - q);
    const double rp_den = (Ac + p) * (Ac + p) + (Bc + q) * (Bc + q);
    /* A denominator is 0 only at grazing incidence on a lossless medium of
     * index 1 (c = 0, w = 0): the limit is total reflection. */
    const double rp2 = rp_den > 0.0 ? rp_num / rp_den : 1.0;
    /* A passive surface reflects at most what falls on it: the bound keeps
     * 1 - rho >= 0 where total reflection rounds to 1 + 2e-16 (n < 1). */
    return fmin(0.5 * (rs2 + rp2), 1.0);
}
