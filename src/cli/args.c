/* args.c - exit codes, option scanning and number/list parsing for the
 * seabake program (the accessors of the options the subcommands share are
 * options.c's).  Every failure leaves a one-line message naming the
 * option, the text the user gave and what would have been accepted. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli.h"

/* Longest number token we copy out of a list for strtod; anything longer is
 * not a sensible decimal number. */
enum { SEA_CLI_TOKEN_MAX = 128 };

sea_cli_exit sea_cli_exit_code(sea_status status)
{
    switch (status) {
    case SEA_OK:
        return SEA_CLI_EXIT_OK;
    case SEA_ERR_DOMAIN:
    case SEA_ERR_PARSE:
        return SEA_CLI_EXIT_USAGE;
    case SEA_ERR_IO:
        return SEA_CLI_EXIT_IO;
    case SEA_ERR_NOMEM:
    case SEA_ERR_NUMERIC:
    case SEA_ERR_CANCELLED:
        return SEA_CLI_EXIT_RUNTIME;
    }
    return SEA_CLI_EXIT_RUNTIME;
}

double sea_cli_radians(double degrees)
{
    /* Dividing first keeps multiples of 180 exact: 180 / 180 * pi == pi. */
    return degrees / 180.0 * M_PI;
}

/* ---------------------------------------------------------------- options */

static bool is_help(const char *tok)
{
    return strcmp(tok, "--help") == 0 || strcmp(tok, "-h") == 0;
}

/* Reads the option at argv[*i] and advances *i past it and its value.
 * *opt is the index in the option table, or -1 for --help.  *bare counts
 * the bare arguments read so far: the n-th is the value of the table's
 * n-th positional option. */
static sea_status scan_one(const sea_cli_args *a, int *i, long *opt, const char **value,
                           int *bare, sea_error *err)
{
    const char *tok = a->argv[*i];
    if (is_help(tok)) {
        *opt = -1;
        *value = NULL;
        ++*i;
        return SEA_OK;
    }
    /* "-o" names a SEA_CLI_OPT_SHORT option, "--name" any other. */
    const bool single = tok[0] == '-' && tok[1] != '-' && tok[1] != '\0';
    if (!single && (strncmp(tok, "--", 2) != 0 || tok[2] == '\0')) {
        if (tok[0] == '-' && tok[1] != '\0')
            return sea_fail(err, SEA_ERR_PARSE, "unknown option '%s'", tok);
        /* A bare argument is the value of the next positional option, if
         * any; beyond the last, the last's again (refused by the parse). */
        long last = -1;
        int seen = 0;
        for (size_t k = 0; k < a->n_options; ++k) {
            if (!(a->options[k].flags & SEA_CLI_OPT_POSITIONAL))
                continue;
            last = (long)k;
            if (seen++ == *bare)
                break;
        }
        if (last >= 0) {
            *opt = last;
            *value = tok;
            ++*i;
            ++*bare;
            return SEA_OK;
        }
        return sea_fail(err, SEA_ERR_PARSE,
                        "unexpected argument '%s' (every value follows its --option)", tok);
    }
    const char *dash = single ? "-" : "--";
    const char *name = tok + strlen(dash);
    const char *eq = strchr(name, '=');
    size_t len = eq ? (size_t)(eq - name) : strlen(name);
    if (!single && len == 4 && strncmp(name, "help", 4) == 0)
        return sea_fail(err, SEA_ERR_PARSE, "--help takes no value");
    for (size_t k = 0; k < a->n_options; ++k) {
        const char *cand = a->options[k].name;
        const bool short_opt = (a->options[k].flags & SEA_CLI_OPT_SHORT) != 0;
        if (a->options[k].flags & SEA_CLI_OPT_POSITIONAL)
            continue; /* it has no dashed form */
        if (strlen(cand) != len || strncmp(cand, name, len) != 0 || short_opt != single)
            continue;
        *opt = (long)k;
        if (a->options[k].flags & SEA_CLI_OPT_FLAG) {
            if (eq)
                return sea_fail(err, SEA_ERR_PARSE, "%s%s takes no value", dash, cand);
            *value = tok; /* non-NULL: the flag was given */
            ++*i;
        } else if (eq) {
            *value = eq + 1;
            ++*i;
        } else {
            if (*i + 1 >= a->argc)
                return sea_fail(err, SEA_ERR_PARSE, "%s%s needs a value", dash, cand);
            *value = a->argv[*i + 1];
            *i += 2;
        }
        return SEA_OK;
    }
    return sea_fail(err, SEA_ERR_PARSE, "unknown option '%s%.*s'", dash, (int)len, name);
}

sea_status sea_cli_args_parse(sea_cli_args *args, const sea_cli_option *options, size_t n_options,
                              int argc, char **argv, sea_error *err)
{
    *args = (sea_cli_args){options, n_options, argc, argv, false};
    const char *positional[SEA_CLI_POSITIONAL_MAX] = { NULL };
    int bare = 0;
    for (int i = 0; i < argc;) {
        long opt;
        const char *value;
        sea_status st = scan_one(args, &i, &opt, &value, &bare, err);
        if (st != SEA_OK)
            return st;
        if (opt < 0) {
            args->help = true;
        } else if (options[opt].flags & SEA_CLI_OPT_POSITIONAL) {
            /* which positional this is: a second value for the last one is
             * one argument too many */
            int k = 0;
            for (long o = 0; o < opt; o++)
                k += (options[o].flags & SEA_CLI_OPT_POSITIONAL) != 0;
            if (k >= SEA_CLI_POSITIONAL_MAX || positional[k])
                return sea_fail(err, SEA_ERR_PARSE,
                                "unexpected argument '%s' ('%s' was given first; one is taken)",
                                value, k < SEA_CLI_POSITIONAL_MAX ? positional[k] : "");
            positional[k] = value;
        }
    }
    return SEA_OK;
}

/* The option scan is repeated by the accessors instead of being stored:
 * argv already holds every value, so parsing needs no allocation. */
static const char *find_value(const sea_cli_args *args, const char *name, size_t nth, bool last,
                              size_t *count)
{
    const char *found = NULL;
    size_t seen = 0;
    int bare = 0;
    for (int i = 0; i < args->argc;) {
        long opt;
        const char *value;
        if (scan_one(args, &i, &opt, &value, &bare, NULL) != SEA_OK)
            break; /* cannot happen after a successful sea_cli_args_parse */
        if (opt < 0 || strcmp(args->options[opt].name, name) != 0)
            continue;
        if (last || seen == nth)
            found = value;
        ++seen;
        if (!last && seen > nth)
            break;
    }
    if (count)
        *count = seen;
    return found;
}

const char *sea_cli_args_get(const sea_cli_args *args, const char *name)
{
    return find_value(args, name, 0, true, NULL);
}

size_t sea_cli_args_count(const sea_cli_args *args, const char *name)
{
    size_t n;
    find_value(args, name, 0, true, &n);
    return n;
}

const char *sea_cli_args_nth(const sea_cli_args *args, const char *name, size_t i)
{
    return find_value(args, name, i, false, NULL);
}

/* ---------------------------------------------------------------- numbers */

static void format_bound(char *buf, size_t size, double v)
{
    if (isinf(v))
        snprintf(buf, size, "%sinf", v < 0 ? "-" : "");
    else
        snprintf(buf, size, "%.15g", v); /* 1000000, not 1e+06 */
}

/* Writes "(-90, 90) degrees" into buf. */
static void format_range(char *buf, size_t size, const sea_cli_range *r)
{
    char lo[32], hi[32];
    format_bound(lo, sizeof lo, r->lo);
    format_bound(hi, sizeof hi, r->hi);
    snprintf(buf, size, "%c%s, %s%c%s%s", r->lo_open ? '(' : '[', lo, hi, r->hi_open ? ')' : ']',
             r->unit && r->unit[0] ? " " : "", r->unit ? r->unit : "");
}

static bool in_range(double v, const sea_cli_range *r)
{
    bool above_lo = v > r->lo || (!r->lo_open && v == r->lo);
    bool below_hi = v < r->hi || (!r->hi_open && v == r->hi);
    return above_lo && below_hi;
}

/* Checks v (shown to the user as text) against r; NULL means any finite. */
static sea_status check_range(const char *opt, const char *shown, double v, const sea_cli_range *r,
                              sea_error *err)
{
    static const sea_cli_range any_finite = {-INFINITY, INFINITY, true, true, ""};
    if (!r)
        r = &any_finite;
    if (in_range(v, r))
        return SEA_OK;
    if (isinf(v))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: %s is not a finite number", opt, shown);
    char range[96];
    format_range(range, sizeof range, r);
    return sea_fail(err, SEA_ERR_DOMAIN, "%s: %s is outside %s", opt, shown, range);
}

static bool is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* Parses the number in [begin, end) of whole (whole is quoted in messages
 * when the token is only part of it). */
static sea_status parse_token(const char *opt, const char *whole, const char *begin,
                              const char *end, const sea_cli_range *r, double *out, sea_error *err)
{
    while (begin < end && is_blank(*begin))
        ++begin;
    while (end > begin && is_blank(end[-1]))
        --end;
    size_t len = (size_t)(end - begin);
    bool part = begin != whole || *end != '\0';
    char tok[SEA_CLI_TOKEN_MAX];
    if (len >= sizeof tok)
        return sea_fail(err, SEA_ERR_PARSE, "%s: '%.40s...' is not a number", opt, begin);
    memcpy(tok, begin, len);
    tok[len] = '\0';

    /* strtod also takes hexadecimal, "nan" and "infinity"; only plain
     * decimal numbers and an explicit inf are part of the interface. */
    const char *body = tok + (tok[0] == '+' || tok[0] == '-');
    double v;
    if (strcasecmp(body, "inf") == 0 || strcasecmp(body, "infinity") == 0) {
        v = tok[0] == '-' ? -INFINITY : INFINITY;
    } else {
        bool plain = len > 0 && strspn(tok, "+-.0123456789eE") == len;
        char *stop = NULL;
        errno = 0;
        v = plain ? strtod(tok, &stop) : NAN;
        if (!plain || stop != tok + len || isnan(v)) {
            if (part)
                return sea_fail(err, SEA_ERR_PARSE, "%s: '%s' is not a number (in '%s')", opt, tok,
                                whole);
            return sea_fail(err, SEA_ERR_PARSE, "%s: '%s' is not a number", opt, tok);
        }
        if (errno == ERANGE && isinf(v))
            return sea_fail(err, SEA_ERR_DOMAIN, "%s: %s is too large", opt, tok);
    }
    sea_status st = check_range(opt, tok, v, r, err);
    if (st != SEA_OK)
        return st;
    *out = v;
    return SEA_OK;
}

sea_status sea_cli_parse_number(const char *opt, const char *text, const sea_cli_range *range,
                                double *out, sea_error *err)
{
    return parse_token(opt, text, text, text + strlen(text), range, out, err);
}

static size_t count_char(const char *s, char c)
{
    size_t n = 0;
    for (; *s; ++s)
        n += *s == c;
    return n;
}

sea_status sea_cli_parse_tuple(const char *opt, const char *text, size_t n,
                               const sea_cli_range *ranges, const char *form, double *out,
                               sea_error *err)
{
    if (count_char(text, ',') + 1 != n)
        return sea_fail(err, SEA_ERR_PARSE,
                        "%s: expected %s (%zu comma-separated numbers), got '%s'", opt, form, n,
                        text);
    const char *begin = text;
    for (size_t i = 0; i < n; ++i) {
        const char *end = strchr(begin, ',');
        if (!end)
            end = begin + strlen(begin);
        sea_status st =
            parse_token(opt, text, begin, end, ranges ? &ranges[i] : NULL, &out[i], err);
        if (st != SEA_OK)
            return st;
        begin = end + 1;
    }
    return SEA_OK;
}

void sea_cli_list_free(sea_cli_list *list)
{
    if (!list)
        return;
    free(list->values);
    list->values = NULL;
    list->n = 0;
}

static sea_status list_alloc(const char *opt, size_t n, sea_cli_list *out, sea_error *err)
{
    out->values = malloc(n * sizeof *out->values);
    if (!out->values)
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory for %zu values", opt, n);
    out->n = n;
    return SEA_OK;
}

/* "A:B:STEP". */
static sea_status parse_range_list(const char *opt, const char *text, const sea_cli_range *r,
                                   sea_cli_list *out, sea_error *err)
{
    const char *c1 = strchr(text, ':');
    const char *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    if (!c2 || strchr(c2 + 1, ':') || strchr(text, ','))
        return sea_fail(err, SEA_ERR_PARSE, "%s: '%s' is not a list (A:B:STEP, A,B,C or one value)",
                        opt, text);
    double a, b, step;
    sea_status st = parse_token(opt, text, text, c1, r, &a, err);
    if (st == SEA_OK)
        st = parse_token(opt, text, c1 + 1, c2, r, &b, err);
    if (st == SEA_OK)
        st = parse_token(opt, text, c2 + 1, c2 + strlen(c2), NULL, &step, err);
    if (st != SEA_OK)
        return st;
    if (!(step > 0))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: the step of '%s' must be > 0", opt, text);
    if (a > b)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: '%s' runs backwards (A:B:STEP needs A <= B)", opt,
                        text);
    double count = floor((b - a) / step + SEA_CLI_LIST_END_TOL) + 1.0;
    if (!(count <= SEA_CLI_LIST_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: '%s' has %.0f values, more than %d", opt, text,
                        count, SEA_CLI_LIST_MAX);
    size_t n = (size_t)count;
    st = list_alloc(opt, n, out, err);
    if (st != SEA_OK)
        return st;
    for (size_t i = 0; i < n; ++i) {
        double v = a + (double)i * step;
        /* The last value lands on B up to rounding; snap it, and never step
         * past B, so that every value stays inside the checked range. */
        if (v > b || (i + 1 == n && fabs(v - b) <= SEA_CLI_LIST_END_TOL * step))
            v = b;
        out->values[i] = v;
    }
    return SEA_OK;
}

sea_status sea_cli_parse_list(const char *opt, const char *text, const sea_cli_range *range,
                              sea_cli_list *out, sea_error *err)
{
    *out = (sea_cli_list){NULL, 0};
    if (strchr(text, ':'))
        return parse_range_list(opt, text, range, out, err);
    size_t n = count_char(text, ',') + 1;
    if (n > SEA_CLI_LIST_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: %zu values, more than %d", opt, n,
                        SEA_CLI_LIST_MAX);
    sea_status st = list_alloc(opt, n, out, err);
    if (st != SEA_OK)
        return st;
    const char *begin = text;
    for (size_t i = 0; i < n; ++i) {
        const char *end = strchr(begin, ',');
        if (!end)
            end = begin + strlen(begin);
        st = parse_token(opt, text, begin, end, range, &out->values[i], err);
        if (st != SEA_OK) {
            sea_cli_list_free(out);
            return st;
        }
        begin = end + 1;
    }
    return SEA_OK;
}
