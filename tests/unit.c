/* unit.c - runs every CUnit suite, or only those SEA_UNIT_SUITES names, or
 * all but those SEA_UNIT_SKIP names (commas between names: check-valgrind
 * runs the suites as two processes side by side, tests/unit_half.sh);
 * exits non-zero on any failure. */
#include <CUnit/Basic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"
#include "unit.h"

#ifndef SEA_TOP_SRCDIR
#define SEA_TOP_SRCDIR "."
#endif

static claim *claims;
static size_t nclaims;
static char claims_error[512];

const claim *unit_claim_find(const char *id)
{
    if (claims == NULL && claims_error[0] == '\0' &&
        claims_load(SEA_TOP_SRCDIR "/tests/claims.csv", &claims, &nclaims, claims_error,
                    sizeof claims_error) != 0 && claims_error[0] == '\0')
        snprintf(claims_error, sizeof claims_error, "cannot read tests/claims.csv");
    return claims != NULL ? claims_find(claims, nclaims, id) : NULL;
}

void unit_claim(const char *id, double measured, double se, const char *file, int line)
{
    char msg[1024];
    const claim *c = unit_claim_find(id);
    if (c == NULL) {
        snprintf(msg, sizeof msg, "claim %s: %s", id,
                 claims != NULL ? "not in tests/claims.csv" : claims_error);
        fprintf(stderr, "  %s:%d: %s\n", file, line, msg);
        CU_assertImplementation(CU_FALSE, (unsigned)line, msg, file, "", CU_FALSE);
        return;
    }
    double lo, hi;
    const int ok = claim_holds(c, measured, se, &lo, &hi);
    printf("measured: claim %s (%s, %s): %.6g, stated %s %.6g (within [%.6g, %.6g]%s)\n", id,
           c->page, c->section, measured, claim_kind_name(c->kind), c->stated, lo, hi,
           se > 0.0 ? ", with the reference's standard errors" : "");
    fflush(stdout);
    if (!ok) {
        snprintf(msg, sizeof msg,
                 "claim %s (%s, %s: %s): measured %.6g outside [%.6g, %.6g] (stated %s %.6g, "
                 "tolerance %g + %g se, se %.3g)",
                 id, c->page, c->section, c->figure, measured, lo, hi, claim_kind_name(c->kind),
                 c->stated, c->tol, c->se_mult, se);
        fprintf(stderr, "  %s:%d: %s\n", file, line, msg);
    }
    CU_assertImplementation(ok ? CU_TRUE : CU_FALSE, (unsigned)line, ok ? "claim" : msg, file, "",
                            CU_FALSE);
}

int main(void)
{
    sea_init();
    if (CU_initialize_registry() != CUE_SUCCESS)
        return 2;
    if (test_water_register() || test_spectrum_register() || test_shadow_register() ||
        test_optics_register() || test_waves_register() || test_scene_register() ||
        test_sensor_register() || test_multires_register() || test_render_register() ||
        test_bake_register() || test_bakedir_register() || test_preview_register() ||
        test_exr_register() || test_arrays_register() || test_stability_register() ||
        test_mc_register() || test_imager_register() || test_swell_register() ||
        test_polar_register()) {
        fprintf(stderr, "unit: cannot register the suites: %s\n", CU_get_error_msg());
        CU_cleanup_registry();
        return 2;
    }
    /* SEA_UNIT_SUITES: only the suites it names; SEA_UNIT_SKIP: all but
     * those (names separated by commas); a name that is no suite is an
     * error (a typo must not pass by running nothing, or everything) */
    const char *lists[2] = { getenv("SEA_UNIT_SUITES"), getenv("SEA_UNIT_SKIP") };
    for (int k = 0; k < 2; k++) {
        if (lists[k] == NULL || lists[k][0] == '\0')
            continue;
        if (k == 0)
            for (CU_pSuite s = CU_get_registry()->pSuite; s != NULL; s = s->pNext)
                CU_set_suite_active(s, CU_FALSE);
        char names[1024];
        snprintf(names, sizeof names, "%s", lists[k]);
        for (char *save = NULL, *n = strtok_r(names, ",", &save); n != NULL;
             n = strtok_r(NULL, ",", &save)) {
            CU_pSuite s = CU_get_suite(n);
            if (s == NULL) {
                fprintf(stderr, "unit: %s names \"%s\", which is no suite\n",
                        k == 0 ? "SEA_UNIT_SUITES" : "SEA_UNIT_SKIP", n);
                CU_cleanup_registry();
                return 2;
            }
            CU_set_suite_active(s, k == 0 ? CU_TRUE : CU_FALSE);
        }
    }
    CU_basic_set_mode(CU_BRM_VERBOSE);
    CU_basic_run_tests();
    unsigned failed = CU_get_number_of_tests_failed();
    unsigned run = CU_get_number_of_tests_run();
    unsigned asserts_failed = CU_get_number_of_failures();
    int failed_registry = CU_get_number_of_suites_failed();
    printf("\nunit: %u passed, %u failed\n", run - failed, failed);
    CU_cleanup_registry();
    free(claims);
    return (failed || asserts_failed || failed_registry) ? 1 : 0;
}
