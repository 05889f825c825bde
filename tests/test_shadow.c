/* test_shadow.c - Smith shadowing with a non-zero mean. */
#include <gsl/gsl_integration.h>
#include <gsl/gsl_sf_erf.h>

#include "unit.h"

static double Q_fn(double u, void *p)
{
    (void)p;
    return 0.5 * gsl_sf_erfc(u / M_SQRT2);
}

/* G(t) = int_t^inf Q, by adaptive quadrature to 1e-13: agreement 1e-11
 * across the direct and continued-fraction branches (t = 3 is the switch). */
static void test_G_vs_quadrature(void)
{
    const double ts[] = { -6.0, -1.0, 0.0, 0.6174, 2.9, 3.1, 5.0, 10.0, 20.0 };
    gsl_integration_workspace *ws = gsl_integration_workspace_alloc(500);
    gsl_function F = { Q_fn, NULL };
    for (size_t i = 0; i < sizeof ts / sizeof ts[0]; i++) {
        double r, e;
        CU_ASSERT(gsl_integration_qag(&F, ts[i], ts[i] + 40.0, 0.0, 1e-13, 500,
                                      GSL_INTEG_GAUSS61, ws, &r, &e) == 0);
        ASSERT_REL(sea_shadow_G(ts[i]), r, 1e-11, 0);
    }
    gsl_integration_workspace_free(ws);
}

/* Asymptotics where the direct form fails: G(t) ~ phi(t)/t^2 (1 - 3/t^2 +
 * 15/t^4 - 105/t^6 + 945/t^8), truncation < 1e-10 at t = 30; identity
 * G(t) - G(-t) = -t to 1e-15 relative. */
static void test_G_tail_and_identity(void)
{
    double t = 30.0, it2 = 1.0 / (t * t);
    double phi = exp(-0.5 * t * t) / sqrt(2 * M_PI);
    double series = phi * it2 * (1 - 3 * it2 + 15 * it2 * it2 - 105 * pow(it2, 3) + 945 * pow(it2, 4));
    ASSERT_REL(sea_shadow_G(t), series, 1e-10, 0);
    CU_ASSERT(sea_shadow_G(37.0) > 0.0); /* phi(38.6) underflows double */
    for (double x = -8.0; x <= 8.0; x += 0.37)
        ASSERT_REL(sea_shadow_G(x) - sea_shadow_G(-x), -x, 1e-13, 1e-3);
}

typedef struct { double theta, m, s; } lam_args;
static double lambda_integrand(double g, void *p)
{
    const lam_args *a = p;
    double z = (g - a->m) / a->s;
    return (g * tan(a->theta) - 1.0) * exp(-0.5 * z * z) / (a->s * sqrt(2 * M_PI));
}

/* Closed form vs the defining integral (Eq 9e) by quadrature, 1e-9. */
static void test_lambda_vs_quadrature(void)
{
    const lam_args cases[] = { { 0.6174, 0.0, 0.19 },  { 70 * DEG, 0.15, 0.19 },
                               { 80 * DEG, -0.15, 0.16 }, { 85 * DEG, 0.3, 0.05 },
                               { 88 * DEG, -0.5, 0.3 }, { 45 * DEG, 1.0, 0.2 } };
    gsl_integration_workspace *ws = gsl_integration_workspace_alloc(500);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        lam_args a = cases[i];
        gsl_function F = { lambda_integrand, &a };
        double mu = 1.0 / tan(a.theta), r, e;
        CU_ASSERT(gsl_integration_qag(&F, mu, fmax(mu, a.m) + 30 * a.s, 1e-300, 1e-12, 500,
                                      GSL_INTEG_GAUSS61, ws, &r, &e) == 0);
        ASSERT_REL(sea_shadow_lambda(a.theta, a.m, a.s), r, 1e-9, 1e-300);
    }
    gsl_integration_workspace_free(ws);
}

/* m = 0: the classic Lambda = (exp(-nu^2)/(nu sqrt(pi)) - erfc(nu))/2,
 * nu = cot(theta)/(sqrt 2 s), where it does not cancel (nu <= 2): 1e-12. */
static void test_lambda_zero_mean_classic(void)
{
    const double s = 0.19;
    for (double th = 60 * DEG; th < 89.9 * DEG; th += 2.5 * DEG) {
        double nu = 1.0 / tan(th) / (M_SQRT2 * s);
        double classic = 0.5 * (exp(-nu * nu) / (nu * sqrt(M_PI)) - erfc(nu));
        ASSERT_REL(sea_shadow_lambda(th, 0.0, s), classic, 1e-12, 0);
    }
}

/* Finite, >= 0 and monotone from nadir to 89.99 deg for any mean and any
 * width (down to 1e-4 and 0); 0 <= D <= 1 + max(-m, 0) tan and D = 1 - m tan/(1+L)
 * where that form does not cancel (1e-12). */
static void test_lambda_sweep(void)
{
    const double ms[] = { -1.0, -0.15, 0.0, 0.103, 0.15, 1.0 };
    const double ss[] = { 0.0, 1e-4, 0.05, 0.19, 1.0 };
    for (size_t i = 0; i < 6; i++)
        for (size_t j = 0; j < 5; j++) {
            double prev = 0.0;
            for (double th = 0.0; th <= 89.99 * DEG + 1e-12; th += 0.01 * DEG) {
                double L = sea_shadow_lambda(th, ms[i], ss[j]);
                double D = sea_shadow_D(th, ms[i], ss[j]);
                if (!(isfinite(L) && L >= 0.0 && L >= prev * (1 - 1e-12) && isfinite(D) &&
                      D >= 0.0 && D <= 1.0 + fmax(-ms[i], 0.0) * tan(th) + 1e-12)) {
                    fprintf(stderr, "  m %g s %g th %g: L %g prev %g D %g\n", ms[i], ss[j],
                            th / DEG, L, prev, D);
                    CU_FAIL("Lambda or D out of bounds");
                    break;
                }
                prev = L;
            }
            CU_ASSERT(sea_shadow_lambda(0.0, ms[i], ss[j]) == 0.0);
            CU_ASSERT(sea_shadow_D(0.0, ms[i], ss[j]) == 1.0);
        }
    for (double th = 5 * DEG; th < 80 * DEG; th += 5 * DEG) {
        double L = sea_shadow_lambda(th, 0.12, 0.19);
        ASSERT_REL(sea_shadow_D(th, 0.12, 0.19), 1.0 - 0.12 * tan(th) / (1.0 + L), 1e-12, 0);
    }
    /* Mean zero: D = 1 at every angle (Eq 10). */
    ASSERT_REL(sea_shadow_D(85 * DEG, 0.0, 0.19), 1.0, 1e-13, 0);
}

int test_shadow_register(void)
{
    CU_pSuite s = CU_add_suite("shadow", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "G vs quadrature", test_G_vs_quadrature) ||
           !CU_add_test(s, "G tail and identity", test_G_tail_and_identity) ||
           !CU_add_test(s, "Lambda vs quadrature", test_lambda_vs_quadrature) ||
           !CU_add_test(s, "Lambda zero-mean classic", test_lambda_zero_mean_classic) ||
           !CU_add_test(s, "Lambda and D sweep to 89.99 deg", test_lambda_sweep);
}
