/* unit.h - shared helpers of the CUnit suites. */
#ifndef SEA_TEST_UNIT_H
#define SEA_TEST_UNIT_H

#include <CUnit/CUnit.h>
#include <math.h>
#include <stdio.h>

#include "seabake.h"

#define DEG (M_PI / 180.0)

/* |a - b| <= tol * max(|b|, floor): a relative check that does not divide by 0. */
#define ASSERT_REL(a, b, tol, floor_)                                                          \
    do {                                                                                    \
        double a_ = (a), b_ = (b);                                                          \
        double d_ = fabs(a_ - b_), s_ = fmax(fabs(b_), (floor_));                           \
        if (!(d_ <= (tol) * s_))                                                            \
            fprintf(stderr, "  %s:%d: %s = %.17g, expected %.17g (rel %.3g > %.3g)\n",       \
                    __FILE__, __LINE__, #a, a_, b_, d_ / s_, (double)(tol));                \
        CU_ASSERT(d_ <= (tol) * s_);                                                        \
    } while (0)

#define ASSERT_ABS(a, b, tol)                                                               \
    do {                                                                                    \
        double a_ = (a), b_ = (b);                                                          \
        if (!(fabs(a_ - b_) <= (tol)))                                                      \
            fprintf(stderr, "  %s:%d: %s = %.17g, expected %.17g +- %.3g\n", __FILE__,      \
                    __LINE__, #a, a_, b_, (double)(tol));                                   \
        CU_ASSERT(fabs(a_ - b_) <= (tol));                                                  \
    } while (0)

/* Each suite file registers its suite. */
int test_water_register(void);
int test_spectrum_register(void);
int test_shadow_register(void);
int test_optics_register(void);
int test_waves_register(void);
int test_scene_register(void);
int test_sensor_register(void);
int test_render_register(void);
int test_bake_register(void);
int test_bakedir_register(void);
int test_preview_register(void);
int test_exr_register(void);
int test_arrays_register(void);
int test_stability_register(void);
int test_multires_register(void);
int test_mc_register(void);
int test_imager_register(void);
int test_swell_register(void);
int test_polar_register(void);

/* SEA_UNIT_QUICK set (check-valgrind sets it, and scripts/test for the
 * sanitizer run): the statistical tests that need large areas run on small
 * ones, to exercise the same code under a memory checker in minutes; their
 * statistical tolerances are then not asserted (exactness, finiteness and
 * bounds still are). */
#include <stdlib.h>
#define UNIT_QUICK (getenv("SEA_UNIT_QUICK") != NULL)

/* Figures worth quoting are printed on stdout, prefixed "measured:". */
#define MEASURED(...) (printf("measured: " __VA_ARGS__), fflush(stdout))

/* ASSERT_CLAIM(id, measured, se): the figure tests/claims.csv states for
 * id, asserted with the kind and tolerance it gives there; se is the
 * standard error of the reference the measurement was compared with (0
 * for none), which the tolerance may count in.  Prints a "measured:" line
 * with the figure; an id the table lacks is a failure. */
void unit_claim(const char *id, double measured, double se, const char *file, int line);
/* The row of id in tests/claims.csv (its kind and tolerance), or NULL. */
#include "claims.h"
const claim *unit_claim_find(const char *id);
#define ASSERT_CLAIM(id, measured, se) unit_claim((id), (measured), (se), __FILE__, __LINE__)

/* A check that cannot run here (a processor or build feature is missing):
 * one line "SKIP: unit: WHY" on stdout, which scripts/test counts. */
#define UNIT_SKIP(...) (printf("\nSKIP: unit: " __VA_ARGS__), printf("\n"), fflush(stdout))

#endif
