/* claims_check.c - every row of tests/claims.csv (see claims.h): the page
 * still states the figure in the section named; a "unit FILE" row's test
 * file names the claim (the unit test asserts it, ASSERT_CLAIM); any other
 * row's command is run and what it prints must meet the figure at the
 * tolerance given.  Run by tests/claims.sh from the build directory:
 *
 *   tests/claims_check CLAIMS_CSV
 *
 * with SEABAKE (the program), SEABAKE_WRAPPER (a checker put before it,
 * may be empty) and top_srcdir in the environment.  Prints a line per
 * check, "FAIL: ..." for each failure, and "claims: N passed, M failed";
 * exits 1 on any failure. */
#include <math.h>
#include <regex.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "claims.h"

static int passed, failed;

static void fail(const claim *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void fail(const claim *c, const char *fmt, ...)
{
    va_list ap;
    failed++;
    printf("FAIL: claims: %s (tests/claims.csv:%d): ", c->id, c->line);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
}

/* The whole of a file, or NULL. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    char *s = malloc(cap);
    size_t got;
    while (s != NULL && (got = fread(s + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (n + 1 == cap) {
            char *t = realloc(s, cap *= 2);
            if (t == NULL) {
                free(s);
                s = NULL;
            }
            s = t;
        }
    }
    fclose(f);
    if (s != NULL)
        s[n] = '\0';
    return s;
}

/* A heading of the page: a roff .SH or .SS line (its text, quotes
 * removed), or a Markdown "#" line; into title.  Whether line is one. */
static int heading(const char *line, size_t len, char *title, size_t tlen)
{
    const char *t;
    if (len > 4 && (strncmp(line, ".SH ", 4) == 0 || strncmp(line, ".SS ", 4) == 0))
        t = line + 4;
    else if (len > 1 && line[0] == '#') {
        t = line;
        while (*t == '#')
            t++;
        while (*t == ' ')
            t++;
    } else
        return 0;
    size_t k = 0;
    for (; t < line + len && k + 1 < tlen; t++)
        if (*t != '"')
            title[k++] = *t;
    title[k] = '\0';
    return 1;
}

/* Whether the section `section` of text states figure (roff's \- read as
 * -): the section's lines joined by spaces, so that a figure may run over a
 * line break (Markdown's list indentation and roff's requests aside). */
static int page_states(const char *text, const char *section, const char *figure)
{
    int in = 0, found_section = 0, found = 0;
    char title[256];
    size_t cap = strlen(text) + 2, k = 0;
    char *norm = malloc(cap);
    if (norm == NULL)
        return 0;
    norm[0] = '\0';
    for (const char *p = text; *p && !found;) {
        const char *e = strchr(p, '\n');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (heading(p, len, title, sizeof title)) {
            if (in)
                found = strstr(norm, figure) != NULL;
            in = strcmp(title, section) == 0;
            found_section |= in;
            k = 0;
            norm[0] = '\0';
        } else if (in) {
            size_t i = 0;
            while (i < len && p[i] == ' ')
                i++; /* a list item's indentation */
            if (k > 0 && k + 1 < cap)
                norm[k++] = ' ';
            for (; i < len && k + 1 < cap; i++) {
                if (p[i] == '\\' && i + 1 < len && p[i + 1] == '-') {
                    norm[k++] = '-';
                    i++;
                } else
                    norm[k++] = p[i];
            }
            norm[k] = '\0';
        }
        p += len + (e != NULL);
    }
    if (in && !found)
        found = strstr(norm, figure) != NULL;
    free(norm);
    return found ? 1 : found_section ? 0 : -1;
}

/* s with every "{srcdir}" replaced by srcdir and "{tmp}" by the scratch
 * directory CLAIMS_TMP, into out. */
static void expand(const char *s, const char *srcdir, char *out, size_t olen)
{
    size_t k = 0;
    const char *tmp = getenv("CLAIMS_TMP");
    while (*s && k + 1 < olen) {
        if (strncmp(s, "{srcdir}", 8) == 0) {
            k += (size_t)snprintf(out + k, olen - k, "%s", srcdir);
            s += 8;
        } else if (strncmp(s, "{tmp}", 5) == 0) {
            k += (size_t)snprintf(out + k, olen - k, "%s", tmp != NULL ? tmp : "/tmp");
            s += 5;
        } else
            out[k++] = *s++;
    }
    out[k < olen ? k : olen - 1] = '\0';
}

static void check_value(const claim *c, double v, const char *where)
{
    double lo, hi;
    char a[256], b[2 * CLAIM_FIELD_MAX + 256];
    if (claim_holds(c, v, 0.0, &lo, &hi)) {
        passed++;
        printf("claims: %s: %s%.8g, stated %s %.8g (within [%.8g, %.8g])\n", c->id, where, v,
               claim_kind_name(c->kind), c->stated, lo, hi);
    } else {
        snprintf(a, sizeof a, "%s%.8g", where, v);
        snprintf(b, sizeof b, "[%.8g, %.8g] (%s: \"%s\" %s %.8g, tolerance %g; %s)", lo, hi,
                 c->page, c->figure, claim_kind_name(c->kind), c->stated, c->tol, c->reason);
        fail(c, "measured %s, outside %s", a, b);
    }
}

/* Runs the row's command and compares what it prints. */
static void run(const claim *c, const char *srcdir, const char *seabake, const char *wrapper)
{
    char cmd[4 * CLAIM_FIELD_MAX], args[2 * CLAIM_FIELD_MAX];
    const int regex = strncmp(c->extract, "re:", 3) == 0;
    if (!regex && strncmp(c->extract, "col:", 4) != 0) {
        fail(c, "extract '%s': not col:NAME or re:REGEX", c->extract);
        return;
    }
    if (strncmp(c->command, "seabake ", 8) == 0) {
        expand(c->command + 8, srcdir, args, sizeof args);
        snprintf(cmd, sizeof cmd, "%s '%s' %s %s", wrapper, seabake, args,
                 regex ? "2>&1" : "2>/dev/null");
    } else if (strncmp(c->command, "tests/", 6) == 0) {
        expand(c->command, srcdir, args, sizeof args);
        snprintf(cmd, sizeof cmd, "./%s %s", args, regex ? "2>&1" : "2>/dev/null");
    } else {
        fail(c, "command '%s': not seabake, tests/PROG, unit FILE or same ID", c->command);
        return;
    }
    FILE *p = popen(cmd, "r");
    char *out = NULL;
    size_t cap = 0, n = 0, got;
    char buf[4096];
    while (p != NULL && (got = fread(buf, 1, sizeof buf, p)) > 0) {
        if (n + got + 1 > cap) {
            cap = 2 * (n + got + 1);
            char *t = realloc(out, cap);
            if (t == NULL)
                break;
            out = t;
        }
        memcpy(out + n, buf, got);
        n += got;
    }
    const int status = p != NULL ? pclose(p) : -1;
    if (out != NULL)
        out[n] = '\0';
    if (out == NULL || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        /* what it printed first says why (emis_rule_check exits 1 above its
         * promise, after printing the largest difference) */
        fail(c, "'%s' failed (exit status %d): %.300s", cmd,
             status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1,
             out != NULL ? out : "(no output)");
        free(out);
        return;
    }
    if (regex) {
        regex_t re;
        regmatch_t m[2];
        if (regcomp(&re, c->extract + 3, REG_EXTENDED) != 0) {
            fail(c, "bad regular expression '%s'", c->extract + 3);
        } else {
            if (regexec(&re, out, 2, m, 0) != 0 || m[1].rm_so < 0) {
                fail(c, "'%s' printed nothing matching /%s/", cmd, c->extract + 3);
            } else {
                char num[64];
                size_t len = (size_t)(m[1].rm_eo - m[1].rm_so);
                snprintf(num, sizeof num, "%.*s", (int)(len < 63 ? len : 63), out + m[1].rm_so);
                char *end;
                const double v = strtod(num, &end);
                if (end == num || *end != '\0')
                    fail(c, "matched '%s', not a number (/%s/)", num, c->extract + 3);
                else
                    check_value(c, v, "");
            }
            regfree(&re);
        }
        free(out);
        return;
    }
    /* col:NAME: every data row of the CSV on stdout (its comment lines,
     * a leading '#', aside) */
    const char *name = c->extract + 4;
    char *save = NULL, *line = strtok_r(out, "\n", &save);
    while (line != NULL && line[0] == '#')
        line = strtok_r(NULL, "\n", &save);
    int col = -1, rows = 0;
    if (line != NULL) {
        int k = 0;
        for (char *s2 = NULL, *f = strtok_r(line, ",", &s2); f != NULL; f = strtok_r(NULL, ",", &s2), k++)
            if (strcmp(f, name) == 0)
                col = k;
    }
    if (col < 0) {
        fail(c, "'%s' printed no column %s", cmd, name);
        free(out);
        return;
    }
    while ((line = strtok_r(NULL, "\n", &save)) != NULL) {
        if (line[0] == '#')
            continue;
        int k = 0;
        char *f = line, *next;
        for (; k < col && f != NULL; k++) {
            next = strchr(f, ',');
            f = next ? next + 1 : NULL;
        }
        char *end;
        const double v = f != NULL ? strtod(f, &end) : NAN;
        char where[64];
        snprintf(where, sizeof where, "row %d: ", ++rows);
        if (f == NULL || end == f)
            fail(c, "%s%s: no number", where, name); /* both strings */
        else
            check_value(c, v, where);
    }
    if (rows == 0)
        fail(c, "'%s' printed no row", cmd);
    free(out);
}

int main(int argc, char **argv)
{
    const char *srcdir = getenv("top_srcdir"), *seabake = getenv("SEABAKE");
    const char *wrapper = getenv("SEABAKE_WRAPPER");
    if (argc != 2 || srcdir == NULL || seabake == NULL) {
        fprintf(stderr, "usage: top_srcdir=DIR SEABAKE=PROG claims_check CLAIMS_CSV\n");
        return 2;
    }
    claim *c;
    size_t n;
    char msg[512], path[1024];
    if (claims_load(argv[1], &c, &n, msg, sizeof msg) != 0) {
        printf("FAIL: claims: %s\nclaims: 0 passed, 1 failed\n", msg);
        return 1;
    }
    for (size_t i = 0; i < n; i++) {
        /* the page states the figure where the row says */
        snprintf(path, sizeof path, "%s/%s", srcdir, c[i].page);
        char *text = slurp(path);
        const int st = text != NULL ? page_states(text, c[i].section, c[i].figure) : -2;
        free(text);
        if (st == 1)
            passed++;
        else if (st == -2)
            fail(&c[i], "cannot read %s", c[i].page);
        else if (st == -1)
            fail(&c[i], "%s has no section \"%s\"", c[i].page, c[i].section);
        else
            fail(&c[i], "%s, section \"%s\", does not state \"%s\"", c[i].page, c[i].section,
                 c[i].figure);
        if (strncmp(c[i].command, "same ", 5) == 0) {
            /* the figure of another row, stated again: measured there */
            const claim *o = claims_find(c, n, c[i].command + 5);
            if (o != NULL && strncmp(o->command, "same ", 5) != 0 && o->kind == c[i].kind &&
                o->stated == c[i].stated && o->tol == c[i].tol && o->se_mult == c[i].se_mult) {
                passed++;
                printf("claims: %s: the figure of %s\n", c[i].id, o->id);
            } else
                fail(&c[i], "%s: no such row, or another figure or tolerance", c[i].command);
        } else if (strncmp(c[i].command, "unit ", 5) == 0) {
            /* the unit test asserts it: its file names the id */
            char quoted[80];
            snprintf(path, sizeof path, "%s/%s", srcdir, c[i].command + 5);
            snprintf(quoted, sizeof quoted, "\"%s\"", c[i].id);
            text = slurp(path);
            if (text != NULL && strstr(text, quoted) != NULL) {
                passed++;
                printf("claims: %s: asserted by %s\n", c[i].id, c[i].command + 5);
            } else
                fail(&c[i], "%s does not name it (%s)", c[i].command + 5, quoted);
            free(text);
        } else
            run(&c[i], srcdir, seabake, wrapper != NULL ? wrapper : "");
    }
    free(c);
    printf("claims: %d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
