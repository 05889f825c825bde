/* claims.c - reads tests/claims.csv (see claims.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"

static const char *const HEADER = "id,page,section,figure,command,extract,kind,stated,tolerance,"
                                  "reason";
enum { NFIELDS = 10 };

/* Splits one CSV record (no embedded newlines) into fields; quoted fields
 * may hold commas and "" for a quote.  The count, or -1. */
static int split(const char *line, char f[NFIELDS][CLAIM_FIELD_MAX])
{
    int k = 0;
    const char *p = line;
    for (;;) {
        if (k == NFIELDS)
            return -1;
        size_t len = 0;
        char *o = f[k];
        if (*p == '"') {
            p++;
            for (;;) {
                if (*p == '\0')
                    return -1; /* unterminated */
                if (*p == '"') {
                    if (p[1] == '"') {
                        p += 2;
                        if (len + 1 < CLAIM_FIELD_MAX)
                            o[len++] = '"';
                        continue;
                    }
                    p++;
                    break;
                }
                if (len + 1 >= CLAIM_FIELD_MAX)
                    return -1;
                o[len++] = *p++;
            }
        } else {
            while (*p != ',' && *p != '\0' && *p != '\n' && *p != '\r') {
                if (len + 1 >= CLAIM_FIELD_MAX)
                    return -1;
                o[len++] = *p++;
            }
        }
        o[len] = '\0';
        k++;
        if (*p == ',') {
            p++;
            continue;
        }
        if (*p == '\0' || *p == '\n' || *p == '\r')
            return k;
        return -1; /* text after a closing quote */
    }
}

static int number(const char *s, double *x)
{
    char *end;
    *x = strtod(s, &end);
    return end != s && *end == '\0' && isfinite(*x);
}

/* "A", "A+Kse" or "Kse". */
static int tolerance(const char *s, double *tol, double *k)
{
    char buf[CLAIM_FIELD_MAX];
    snprintf(buf, sizeof buf, "%s", s);
    *tol = 0.0;
    *k = 0.0;
    size_t n = strlen(buf);
    if (n >= 2 && strcmp(buf + n - 2, "se") == 0) {
        buf[n - 2] = '\0';
        char *plus = strrchr(buf, '+');
        /* a '+' that is an exponent's sign belongs to A */
        while (plus != NULL && plus > buf && (plus[-1] == 'e' || plus[-1] == 'E'))
            plus = NULL;
        const char *kpart = plus != NULL ? plus + 1 : buf;
        if (plus != NULL) {
            *plus = '\0';
            if (!number(buf, tol))
                return 0;
        }
        return number(kpart, k) && *k >= 0.0 && *tol >= 0.0;
    }
    return number(buf, tol) && *tol >= 0.0;
}

int claims_load(const char *path, claim **out, size_t *n, char *msg, size_t msglen)
{
    *out = NULL;
    *n = 0;
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        snprintf(msg, msglen, "%s: cannot open", path);
        return -1;
    }
    char line[4 * CLAIM_FIELD_MAX];
    static char fld[NFIELDS][CLAIM_FIELD_MAX];
    int lineno = 0, header = 0;
    size_t cap = 0;
    claim *c = NULL;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        if (line[0] == '#' || line[0] == '\n')
            continue;
        if (strchr(line, '\n') == NULL && !feof(f)) {
            snprintf(msg, msglen, "%s:%d: line too long", path, lineno);
            goto fail;
        }
        if (!header) {
            line[strcspn(line, "\r\n")] = '\0';
            if (strcmp(line, HEADER) != 0) {
                snprintf(msg, msglen, "%s:%d: header is not %s", path, lineno, HEADER);
                goto fail;
            }
            header = 1;
            continue;
        }
        if (split(line, fld) != NFIELDS) {
            snprintf(msg, msglen, "%s:%d: not %d fields", path, lineno, NFIELDS);
            goto fail;
        }
        if (*n == cap) {
            cap = cap ? 2 * cap : 64;
            claim *g = realloc(c, cap * sizeof *c);
            if (g == NULL) {
                snprintf(msg, msglen, "out of memory");
                goto fail;
            }
            c = g;
        }
        claim *r = &c[*n];
        memset(r, 0, sizeof *r);
        r->line = lineno;
        if (strlen(fld[0]) >= sizeof r->id || strlen(fld[1]) >= sizeof r->page ||
            strlen(fld[2]) >= sizeof r->section || strlen(fld[3]) >= sizeof r->figure ||
            fld[0][0] == '\0') {
            snprintf(msg, msglen, "%s:%d: id, page, section or figure empty or too long", path,
                     lineno);
            goto fail;
        }
        strcpy(r->id, fld[0]);
        strcpy(r->page, fld[1]);
        strcpy(r->section, fld[2]);
        strcpy(r->figure, fld[3]);
        strcpy(r->command, fld[4]);
        strcpy(r->extract, fld[5]);
        strcpy(r->reason, fld[9]);
        if (strcmp(fld[6], "=") == 0)
            r->kind = CLAIM_EQ;
        else if (strcmp(fld[6], "<=") == 0)
            r->kind = CLAIM_LE;
        else if (strcmp(fld[6], ">=") == 0)
            r->kind = CLAIM_GE;
        else {
            snprintf(msg, msglen, "%s:%d: kind '%s' (allowed: =, <=, >=)", path, lineno, fld[6]);
            goto fail;
        }
        if (!number(fld[7], &r->stated) || !tolerance(fld[8], &r->tol, &r->se_mult)) {
            snprintf(msg, msglen, "%s:%d: stated '%s' or tolerance '%s' is no number", path,
                     lineno, fld[7], fld[8]);
            goto fail;
        }
        if (r->reason[0] == '\0' || r->command[0] == '\0') {
            snprintf(msg, msglen, "%s:%d: %s: no command or no reason", path, lineno, r->id);
            goto fail;
        }
        if (claims_find(c, *n, r->id) != NULL) {
            snprintf(msg, msglen, "%s:%d: id %s twice", path, lineno, r->id);
            goto fail;
        }
        (*n)++;
    }
    fclose(f);
    if (!header || *n == 0) {
        snprintf(msg, msglen, "%s: no claims", path);
        free(c);
        *n = 0;
        return -1;
    }
    *out = c;
    return 0;
fail:
    fclose(f);
    free(c);
    *n = 0;
    return -1;
}

const claim *claims_find(const claim *c, size_t n, const char *id)
{
    for (size_t i = 0; i < n; i++)
        if (strcmp(c[i].id, id) == 0)
            return &c[i];
    return NULL;
}

int claim_holds(const claim *c, double measured, double se, double *lo, double *hi)
{
    const double t = c->tol + c->se_mult * (se > 0.0 ? se : 0.0);
    *lo = c->kind == CLAIM_LE ? -INFINITY : c->stated - t;
    *hi = c->kind == CLAIM_GE ? INFINITY : c->stated + t;
    return measured >= *lo && measured <= *hi;
}

const char *claim_kind_name(claim_kind k)
{
    return k == CLAIM_EQ ? "=" : k == CLAIM_LE ? "<=" : ">=";
}
