/* claims.h - tests/claims.csv: every figure the manuals promise, where it is
 * promised, how it is measured, and the tolerance it is held to.  The
 * unit tests read their figures from it (ASSERT_CLAIM, tests/unit.h);
 * tests/claims_check runs the commands it lists and checks that each page
 * still states each figure in the section named, so that the pages, the
 * table and the measurements cannot drift apart.
 *
 * Columns (RFC 4180 quoting; '#' starts a comment line):
 *   id         a name, unique
 *   page       man/seabake-model.7, man/seabake.1 or README.md
 *   section    the .SH or .SS heading (README: the "## " heading) whose text
 *              states the figure
 *   figure     the figure as the page writes it (roff's \- read as -)
 *   command    "unit FILE": asserted by the unit test in FILE, which names
 *              the id; otherwise a command, "seabake ..." or "tests/PROG ..."
 *              (run from the build directory; {srcdir} is the source tree)
 *   extract    with a command: "col:NAME" (that column of every CSV row of
 *              stdout) or "re:REGEX" (the first number the regular
 *              expression's group 1 matches in stdout and stderr)
 *   kind       "=" (|measured - stated| <= tolerance) or "<=" (measured <=
 *              stated + tolerance) or ">=" (measured >= stated - tolerance)
 *   stated     the figure as a number
 *   tolerance  "A", "A+Kse" or "Kse": A absolute, plus K standard errors of
 *              the reference the measurement is compared with (the unit test
 *              computes them; a command has none)
 *   reason     why that tolerance */
#ifndef SEA_TEST_CLAIMS_H
#define SEA_TEST_CLAIMS_H

#include <stddef.h>

enum { CLAIM_FIELD_MAX = 512 };

typedef enum { CLAIM_EQ, CLAIM_LE, CLAIM_GE } claim_kind;

typedef struct {
    char id[64], page[64], section[128], figure[64];
    char command[CLAIM_FIELD_MAX], extract[CLAIM_FIELD_MAX], reason[CLAIM_FIELD_MAX];
    claim_kind kind;
    double stated;
    double tol, se_mult; /* tolerance = tol + se_mult x standard error */
    int line;            /* in the file */
} claim;

/* Reads path into *out (malloc'd, n rows).  0, or -1 with a message in msg
 * (file, line, reason). */
int claims_load(const char *path, claim **out, size_t *n, char *msg, size_t msglen);
/* The row of id, or NULL. */
const claim *claims_find(const claim *c, size_t n, const char *id);
/* Whether measured meets c given the reference's standard error se (0 for
 * none); *lo, *hi: the interval it had to fall in. */
int claim_holds(const claim *c, double measured, double se, double *lo, double *hi);
/* "=", "<=" or ">=". */
const char *claim_kind_name(claim_kind k);

#endif
