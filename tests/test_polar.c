/* test_polar.c - polarisation (src/optics/polar.c): the Fresnel reflectances per
 * polarisation, the one-hit Stokes emissivity and reflectivities, their
 * symmetries, and their agreement with the scalar model. */
#include <complex.h>
#include <float.h>
#include <string.h>

#include "internal.h"
#include "unit.h"
#include "indep.h"
#include "mc_stokes.h"

#ifndef SEA_TOP_SRCDIR
#define SEA_TOP_SRCDIR "."
#endif

static sea_optics *P;  /* the default optics (correlated shadowing) */
static sea_optics *PS; /* Smith's shadowing */
static double complex N4, N10; /* sea water at 4 and 10 um, salinity 35 (Hale & Querry) */

static int setup(void)
{
    sea_water *w = NULL;
    if (sea_optics_alloc(&P, NULL) != SEA_OK || sea_optics_alloc(&PS, NULL) != SEA_OK ||
        sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) != SEA_OK ||
        sea_water_index(w, 4e-6, &N4, NULL) != SEA_OK ||
        sea_water_index(w, 10e-6, &N10, NULL) != SEA_OK)
        return 1;
    sea_water_free(w);
    sea_optics_set_shadowing(PS, SEA_SHADOW_SMITH);
    return 0;
}

static int teardown(void)
{
    sea_optics_free(P);
    sea_optics_free(PS);
    return 0;
}

/* The low-resolution slope statistics of a wind sea (wind along x). */
static sea_slope_stats lr(double wind)
{
    sea_spectrum s;
    sea_slope_stats st = { { 0, 0 }, { 0, 0, 0 } };
    CU_ASSERT(sea_spectrum_init(wind, INFINITY, 0.0, &s, NULL) == SEA_OK);
    CU_ASSERT(sea_spectrum_slope_cov(&s, 0.0, &st.cov, NULL) == SEA_OK);
    return st;
}

static sea_stokes pol(const sea_optics *p, sea_emis_method m, double complex N,
                      const sea_slope_stats *st, double theta, double phi)
{
    sea_stokes e = { NAN, NAN, NAN };
    sea_error err = { "" };
    sea_status s = sea_polar_emissivity(p, m, NULL, N, st, (sea_dir){ theta, phi }, &e, &err);
    if (s != SEA_OK)
        fprintf(stderr, "  polar emissivity: %s\n", err.msg);
    CU_ASSERT(s == SEA_OK);
    return e;
}

/* Fresnel's degree of polarisation of a flat sea's emission at theta. */
static double fresnel_dop(double complex N, double theta)
{
    double Rs, Rp;
    sea_polar_fresnel(cos(theta), N, &Rs, &Rp);
    return (Rs - Rp) / (2.0 - Rs - Rp);
}

/* R_s and R_p: their mean is the unpolarised reflectance to 1e-15 (the
 * same arithmetic; a few roundings apart at most), and each is the square
 * modulus of tests/indep.c's amplitudes (Born & Wolf's real form, its own
 * arithmetic) and of the complex formula written out with csqrt, to 1e-13
 * relative (a few ulps of cancellation in c - p near normal incidence of
 * an index close to 1; near Brewster's angle R_p falls to 4e-9 and
 * cancellation costs it 1e-12 of itself, so the check is relative to
 * max(R, 1e-4)).  Normal incidence: R_s = R_p = |(N-1)/(N+1)|^2; grazing:
 * 1; R_p <= R_s everywhere (to rounding: at normal incidence they are
 * equal, 1 ulp apart). */
static void test_fresnel(void)
{
    const double complex Ns[] = { N4, N10, 1.33 + 0.0 * I, 1.2 + 0.5 * I, 1.05 + 0.001 * I };
    for (size_t k = 0; k < sizeof Ns / sizeof Ns[0]; k++) {
        const double complex N = Ns[k];
        for (int i = 0; i <= 200; i++) {
            const double c = i / 200.0;
            double Rs, Rp;
            sea_polar_fresnel(c, N, &Rs, &Rp);
            ASSERT_REL(0.5 * (Rs + Rp), sea_fresnel_unpolarized(c, N), 1e-15, 0.0);
            CU_ASSERT(Rp <= Rs * (1.0 + 4 * DBL_EPSILON) && Rp >= 0.0 && Rs <= 1.0);
            double complex rs, rp;
            indep_fresnel_amplitudes(c, N, &rs, &rp);
            ASSERT_REL(Rs, creal(rs * conj(rs)), 1e-13, 1e-4);
            ASSERT_REL(Rp, creal(rp * conj(rp)), 1e-13, 1e-4);
            const double complex w = csqrt(N * N - (1.0 - c * c));
            const double complex a = (c - w) / (c + w), b = (N * N * c - w) / (N * N * c + w);
            ASSERT_REL(Rs, creal(a * conj(a)), 1e-13, 1e-4);
            ASSERT_REL(Rp, creal(b * conj(b)), 1e-13, 1e-4);
        }
        double Rs, Rp;
        sea_polar_fresnel(1.0, N, &Rs, &Rp);
        const double complex r0 = (N - 1.0) / (N + 1.0);
        ASSERT_REL(Rs, creal(r0 * conj(r0)), 1e-14, 0.0);
        ASSERT_REL(Rp, Rs, 1e-14, 0.0);
        sea_polar_fresnel(0.0, N, &Rs, &Rp);
        ASSERT_ABS(Rs, 1.0, 1e-15);
        ASSERT_ABS(Rp, 1.0, 1e-15);
    }
}

/* A flat sea emits Fresnel's polarisation: with C = 0 exactly the facet
 * population is one mirror (the formula itself), to 1e-12; with slope
 * variances of 1e-14 the facets tilt by 1e-7 and move DoLP by O(1e-14)
 * relative: the 1e-9.  U = 0 (the mirror lies in the view's
 * plane).  Every method, both shadowings, 4 and 10 um, 0.1-85 deg. */
static void test_flat_sea(void)
{
    const double ths[] = { 0.1, 23.4, 47.3, 0.6174 / DEG, 70.0, 80.0, 85.0 };
    const sea_emis_method ms[] = { SEA_EMIS_AUTO, SEA_EMIS_FAST, SEA_EMIS_FULL };
    const double complex Ns[] = { N4, N10 };
    const sea_optics *ps[] = { P, PS };
    double worst = 0.0;
    for (int cv = 0; cv < 2; cv++) {
        const double var = cv == 0 ? 0.0 : 1e-14;
        const sea_slope_stats st = { { 0, 0 }, { var, 1.3 * var, 0.2 * var } };
        for (size_t a = 0; a < sizeof ths / sizeof ths[0]; a++)
            for (int k = 0; k < 2; k++)
                for (int m = 0; m < 3; m++)
                    for (int q = 0; q < 2; q++) {
                        const double th = ths[a] * DEG, phi = 0.3;
                        const sea_stokes e = pol(ps[q], ms[m], Ns[k], &st, th, phi);
                        const double want = fresnel_dop(Ns[k], th);
                        const double dop = e.q / e.i;
                        worst = fmax(worst, fabs(dop - want));
                        ASSERT_ABS(dop, want, cv == 0 ? 1e-12 : 1e-9);
                        ASSERT_ABS(e.u, 0.0, cv == 0 ? 1e-15 : 1e-9);
                        ASSERT_REL(e.i, 1.0 - sea_fresnel_unpolarized(cos(th), Ns[k]),
                                   cv == 0 ? 1e-12 : 1e-9, 0.0);
                    }
    }
    printf("measured: flat sea DoLP - Fresnel's, worst %.3g\n", worst);
    ASSERT_CLAIM("polar_flat_dolp", worst, 0.0);
}

/* e_I is the scalar emissivity of the same method: the same nodes, the
 * same 1 - rho; 1e-12 (summation order only: measured 1e-16).  Rough seas
 * of 5-15 m/s, a tilted correlated one, 0-85 deg, both shadowings, the
 * auto, fast and reference methods and a fixed rule. */
static void test_intensity_is_scalar(void)
{
    sea_slope_stats sts[4] = { lr(5), lr(10), lr(15), lr(10) };
    sts[3].mean = (sea_vec2){ 0.15, -0.15 };
    sts[3].cov.xy = 0.3 * sqrt(sts[3].cov.xx * sts[3].cov.yy);
    const double ths[] = { 0, 0.6174 / DEG, 60, 75, 85 };
    const sea_emis_method ms[] = { SEA_EMIS_AUTO, SEA_EMIS_FAST, SEA_EMIS_FULL };
    const sea_optics *ps[] = { P, PS };
    double worst = 0.0;
    for (int s = 0; s < 4; s++)
        for (size_t a = 0; a < sizeof ths / sizeof ths[0]; a++)
            for (int m = 0; m < 3; m++)
                for (int q = 0; q < 2; q++) {
                    if (ms[m] == SEA_EMIS_FULL && (q == 0 || s == 1 || a % 2))
                        continue; /* (a millisecond apiece: a sample) */
                    const sea_dir v = { ths[a] * DEG, 0.9 };
                    double e;
                    CU_ASSERT(sea_emissivity(ps[q], ms[m], N10, &sts[s], v, &e, NULL) == SEA_OK);
                    const sea_stokes S = pol(ps[q], ms[m], N10, &sts[s], v.theta, v.phi);
                    worst = fmax(worst, fabs(S.i - e));
                    ASSERT_ABS(S.i, e, 1e-12);
                }
    const sea_emis_rule rule = { 23, 5 };
    const sea_slope_stats st = lr(10);
    const sea_dir v = { 78 * DEG, 0.4 };
    double e;
    sea_stokes S;
    CU_ASSERT(sea_emissivity_rule(P, rule, N4, &st, v, &e, NULL) == SEA_OK);
    CU_ASSERT(sea_polar_emissivity(P, SEA_EMIS_AUTO, &rule, N4, &st, v, &S, NULL) == SEA_OK);
    ASSERT_ABS(S.i, e, 1e-12);
    printf("measured: |e_I - sea_emissivity| worst %.3g\n", worst);
    ASSERT_CLAIM("polar_ei_scalar", worst, 0.0);
}

/* The Stokes vector of the many-index call is the single call's, bit for
 * bit; the auto rule's Q and U agree with the adaptive reference's within
 * 1e-6 (the rule's accuracy on the scalar, sea_emissivity_auto_rule). */
static void test_many_and_reference(void)
{
    const sea_slope_stats st = lr(10);
    const double complex N[3] = { N4, N10, 1.25 + 0.08 * I };
    sea_stokes out[3];
    for (int a = 0; a < 3; a++) {
        const sea_dir v = { (40 + 20 * a) * DEG, 0.7 };
        CU_ASSERT(sea_polar_emissivity_n(P, SEA_EMIS_AUTO, NULL, N, 3, &st, v, out, NULL) ==
                  SEA_OK);
        for (int k = 0; k < 3; k++) {
            const sea_stokes one = pol(P, SEA_EMIS_AUTO, N[k], &st, v.theta, v.phi);
            CU_ASSERT(memcmp(&one, &out[k], sizeof one) == 0);
            const sea_stokes ref = pol(P, SEA_EMIS_FULL, N[k], &st, v.theta, v.phi);
            ASSERT_ABS(out[k].q, ref.q, 1e-6);
            ASSERT_ABS(out[k].u, ref.u, 1e-6);
        }
    }
}

/* Symmetry.  A slope law symmetric about the view's vertical plane (the
 * wind along or across the view, no cross-view mean slope) emits no U:
 * each facet has its mirror image across the plane, of opposite sin 2chi;
 * the Gauss-Hermite nodes are symmetric, so the sums cancel to rounding
 * (1e-15 of values below 0.1).  Mirroring the law (C_xy -> -C_xy,
 * m_y -> -m_y, viewed from -phi) flips U and keeps I and Q: 1e-14.
 * Isotropic slopes seen from nadir: DoLP 0 by symmetry, which the auto
 * rule (Gauss-Legendre along X, Gauss-Hermite across) meets within its own
 * error, measured 7e-9 (1e-8 asserted), the adaptive reference within
 * 1e-10. */
static void test_symmetry(void)
{
    const sea_slope_stats st10 = lr(10);
    for (int k = 0; k < 2; k++) {
        const double complex N = k ? N10 : N4;
        for (int a = 0; a < 4; a++) {
            const double th = (20 + 20 * a + 5 * (a == 3)) * DEG;
            for (int f = 0; f < 4; f++) {
                const double phi = f * M_PI / 2;
                sea_slope_stats st = st10;
                /* a mean slope along the view keeps the symmetry */
                st.mean = (sea_vec2){ 0.05 * cos(phi), 0.05 * sin(phi) };
                const sea_stokes e = pol(P, SEA_EMIS_AUTO, N, &st, th, phi);
                ASSERT_ABS(e.u, 0.0, 1e-15);
                CU_ASSERT(e.q > 0.0);
            }
            sea_slope_stats st = st10, mir = st10;
            st.cov.xy = 0.4 * sqrt(st.cov.xx * st.cov.yy);
            st.mean = (sea_vec2){ 0.03, 0.07 };
            mir.cov.xy = -st.cov.xy;
            mir.mean = (sea_vec2){ 0.03, -0.07 };
            const double phi = 0.6174;
            const sea_stokes e = pol(P, SEA_EMIS_AUTO, N, &st, th, phi);
            const sea_stokes m = pol(P, SEA_EMIS_AUTO, N, &mir, th, -phi);
            CU_ASSERT(fabs(e.u) > 1e-5); /* (a real U to flip) */
            ASSERT_ABS(m.u, -e.u, 1e-14);
            ASSERT_ABS(m.q, e.q, 1e-14);
            ASSERT_ABS(m.i, e.i, 1e-14);
        }
        const sea_slope_stats iso = { { 0, 0 }, { 0.03, 0.03, 0 } };
        for (int f = 0; f < 3; f++) {
            const sea_stokes e = pol(P, SEA_EMIS_AUTO, N, &iso, 0.0, 0.5 * f);
            ASSERT_ABS(sea_stokes_dolp(&e), 0.0, 1e-8);
            const sea_stokes r = pol(P, SEA_EMIS_FULL, N, &iso, 0.0, 0.5 * f);
            ASSERT_ABS(sea_stokes_dolp(&r), 0.0, 1e-10);
        }
    }
}

/* Nadir: the flat sea's DoLP vanishes as theta^2 (Fresnel), and a rough
 * sea's, anisotropic, is the small excess of the facets tilted along the
 * wind over those across it: measured below 1e-3 at 5-15 m/s, decreasing
 * toward nadir from 10 deg. */
static void test_nadir(void)
{
    for (int k = 0; k < 2; k++) {
        const double complex N = k ? N10 : N4;
        ASSERT_ABS(fresnel_dop(N, 0.0), 0.0, 1e-16);
        CU_ASSERT(fresnel_dop(N, 1e-3) < 1e-6);
        for (int w = 5; w <= 15; w += 5) {
            const sea_slope_stats st = lr(w);
            const sea_stokes e0 = pol(P, SEA_EMIS_AUTO, N, &st, 0.0, 0.0);
            const sea_stokes e10 = pol(P, SEA_EMIS_AUTO, N, &st, 10 * DEG, 0.0);
            CU_ASSERT(sea_stokes_dolp(&e0) < 1e-3);
            CU_ASSERT(sea_stokes_dolp(&e0) < sea_stokes_dolp(&e10));
        }
    }
}

/* Emission is p-polarised: Q > 0 from 9 to 85 deg, 4 and 10 um, 5, 10,
 * 15 m/s, wind along, across and oblique; DoLP in [0, 1] from 1 deg.
 * Below about 5 deg across the wind Q < 0: there the polarisation of the
 * facets tilted along the wind (the steeper slopes) outweighs the view's
 * own, a DoLP below 5e-4 (measured; test_nadir bounds it). */
static void test_p_polarised(void)
{
    for (int w = 5; w <= 15; w += 5) {
        const sea_slope_stats st = lr(w);
        for (int k = 0; k < 2; k++)
            for (int a = 1; a <= 85; a += 4)
                for (int f = 0; f < 3; f++) {
                    const sea_stokes e =
                        pol(P, SEA_EMIS_AUTO, k ? N10 : N4, &st, a * DEG, f * 0.7);
                    if (a >= 9)
                        CU_ASSERT(e.q > 0.0);
                    CU_ASSERT(sea_stokes_dolp(&e) >= 0.0 && sea_stokes_dolp(&e) <= 1.0);
                }
    }
}

/* The emission DoLP seabake-model(7) states for 10 m/s along the view at
 * 10 um (its claims, tests/claims.csv): 60, 70, 80 and 85 deg, to their
 * rounding (a deterministic quadrature). */
static void test_dolp_figures(void)
{
    const sea_slope_stats st = lr(10.0);
    static const struct {
        const char *id;
        double theta;
    } fig[] = { { "polar_dolp_60", 60.0 }, { "polar_dolp_70", 70.0 }, { "polar_dolp_80", 80.0 },
                { "polar_dolp_85", 85.0 } };
    for (size_t i = 0; i < sizeof fig / sizeof fig[0]; i++) {
        const sea_stokes e = pol(P, SEA_EMIS_AUTO, N10, &st, fig[i].theta * DEG, 0.0);
        ASSERT_CLAIM(fig[i].id, 100.0 * sea_stokes_dolp(&e), 0.0);
    }
}

/* Reflectivities.  The sky's is what the emissivity leaves, s-polarised:
 * (1 - e_I, -e_Q, -e_U) to rounding, so a sky at the sea's temperature
 * leaves no polarisation.  The sun's: I is sea_reflectivity; for a glint in
 * the view's plane (inc opposite obs in azimuth) the mirror facet's plane
 * is the view's, U = 0 and Q / I = (R_p - R_s)/(R_p + R_s) at psi0 = the
 * half-angle between the directions (1e-12); a source off the plane gives
 * U, and its mirror image across the plane the opposite U. */
static void test_reflectivity(void)
{
    const sea_slope_stats st = lr(10);
    const sea_dir v = { 72 * DEG, 0.2 };
    sea_stokes e, r;
    CU_ASSERT(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N10, &st, v, &e, NULL) == SEA_OK);
    CU_ASSERT(sea_polar_reflectivity_sky(P, SEA_EMIS_AUTO, NULL, N10, &st, v, &r, NULL) ==
              SEA_OK);
    ASSERT_ABS(r.i, 1.0 - e.i, 1e-15);
    ASSERT_ABS(r.q + e.q, 0.0, 0.0);
    ASSERT_ABS(r.u + e.u, 0.0, 0.0);
    for (int a = 0; a < 4; a++) {
        const double th_o = (30 + 15 * a) * DEG, th_i = (20 + 10 * a) * DEG;
        const sea_dir obs = { th_o, 0.3 }, inc = { th_i, 0.3 + M_PI };
        sea_stokes s;
        sea_polar_reflectivity(N4, &st, inc, obs, &s);
        ASSERT_REL(s.i, sea_reflectivity(N4, &st, inc, obs), 1e-15, 0.0);
        double Rs, Rp;
        sea_polar_fresnel(cos(0.5 * (th_o + th_i)), N4, &Rs, &Rp);
        ASSERT_REL(s.q / s.i, (Rp - Rs) / (Rp + Rs), 1e-12, 0.0);
        ASSERT_ABS(s.u / s.i, 0.0, 1e-12);
        CU_ASSERT(s.q < 0.0);
        const sea_dir inc2 = { th_i, 0.3 + M_PI - 0.4 }, inc3 = { th_i, 0.3 + M_PI + 0.4 };
        sea_stokes s2, s3;
        sea_polar_reflectivity(N4, &st, inc2, obs, &s2);
        sea_polar_reflectivity(N4, &st, inc3, obs, &s3);
        const sea_slope_stats iso = { { 0, 0 }, { 0.03, 0.03, 0 } };
        sea_polar_reflectivity(N4, &iso, inc2, obs, &s2);
        sea_polar_reflectivity(N4, &iso, inc3, obs, &s3);
        CU_ASSERT(fabs(s2.u) > 1e-3 * s2.i);
        ASSERT_REL(s3.u, -s2.u, 1e-12, 0.0);
        ASSERT_REL(s3.q, s2.q, 1e-12, 0.0);
    }
    /* a mirror facet facing away: nothing */
    sea_stokes z;
    const sea_slope_stats flat = { { 0, 0 }, { 0, 0, 0 } };
    sea_polar_reflectivity(N4, &flat, (sea_dir){ 0.5, 0 }, (sea_dir){ 0.5, 0 }, &z);
    CU_ASSERT(z.i == 0.0 && z.q == 0.0 && z.u == 0.0);
    sea_stokes zero = { 0, 0, 0 };
    CU_ASSERT(sea_stokes_dolp(&zero) == 0.0);
}

/* Every documented error: a view at or beyond 90 deg, invalid statistics,
 * a rule out of range; the status and a message. */
static void test_errors(void)
{
    const sea_slope_stats st = lr(10);
    sea_stokes e;
    sea_error err = { "" };
    CU_ASSERT(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N4, &st, (sea_dir){ M_PI_2, 0 }, &e,
                                   &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "zenith") != NULL);
    CU_ASSERT(sea_polar_emissivity(P, SEA_EMIS_FULL, NULL, N4, &st, (sea_dir){ 2.0, 0 }, &e,
                                   &err) == SEA_ERR_DOMAIN);
    sea_slope_stats bad = st;
    bad.cov.xx = -1.0;
    err.msg[0] = '\0';
    CU_ASSERT(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N4, &bad, (sea_dir){ 1.0, 0 }, &e,
                                   &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(err.msg[0] != '\0');
    const sea_emis_rule r = { 0, 3 };
    CU_ASSERT(sea_polar_emissivity(P, SEA_EMIS_AUTO, &r, N4, &st, (sea_dir){ 1.0, 0 }, &e,
                                   &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "product rule") != NULL);
    CU_ASSERT(sea_polar_reflectivity_sky(P, (sea_emis_method)7, NULL, N4, &st,
                                         (sea_dir){ 1.0, 0 }, &e, &err) == SEA_ERR_DOMAIN);
}


/* ------------------------------------------ the ray tracer's Stokes vectors */

/* The tracer on a flat surface: one hit per ray, Fresnel's emission in the
 * view's plane, DoLP (R_s - R_p)/(2 - R_s - R_p) to 1e-12 and U = V = 0; its
 * forward (Mueller) and reciprocal (Jones) routes agree to 1e-13. */
static void test_mc_flat(void)
{
    mc_surface s;
    const sea_cov2 zero = { 0, 0, 0 };
    CU_ASSERT_FATAL(mc_surface_gaussian(&s, 32, 4.0, &zero, 7) == 0);
    const double complex N[2] = { N4, N10 };
    for (int a = 0; a < 3; a++) {
        const sea_dir v = { (35 + 25 * a) * DEG, 0.6174 * a };
        mc_stokes_tally T;
        CU_ASSERT_FATAL(mc_trace_stokes(&s, v, N, 2, 500, 11, &T) == 0);
        CU_ASSERT(T.multi == 0 && T.leaks == 0);
        CU_ASSERT(T.max_route_diff < 1e-13);
        for (int k = 0; k < 2; k++) {
            ASSERT_ABS(T.e[k][1] / T.e[k][0], fresnel_dop(N[k], v.theta), 1e-12);
            ASSERT_ABS(T.e[k][2] / T.e[k][0], 0.0, 1e-12);
            ASSERT_ABS(T.e[k][3] / T.e[k][0], 0.0, 1e-12);
        }
    }
    mc_surface_free(&s);
}

/* On a rough surface (10 m/s slopes, 70 and 85 deg, oblique to the wind so
 * that U lives): the two routes agree ray by ray to 1e-12 (every hit's
 * frame, rotation and sign), and e_I is mc_trace's eps_pol on the same rays
 * (its own polarised tracer; the two stop a ray at throughput 1e-6 by
 * slightly different rules, so 2e-6). */
static void test_mc_routes(void)
{
    mc_surface s;
    const sea_slope_stats st = lr(10);
    CU_ASSERT_FATAL(mc_surface_gaussian(&s, 128, 6.0, &st.cov, 3) == 0);
    const double complex N[2] = { N4, N10 };
    const long rays = 4000;
    for (int a = 0; a < 2; a++) {
        const sea_dir v = { (70 + 15 * a) * DEG, 0.7 };
        mc_stokes_tally T;
        mc_tally U;
        CU_ASSERT_FATAL(mc_trace_stokes(&s, v, N, 2, rays, 5, &T) == 0);
        CU_ASSERT_FATAL(mc_trace(&s, v, N, 2, rays, 5, &U) == 0);
        CU_ASSERT(T.multi > 0 && T.multi == U.multi);
        CU_ASSERT(T.max_route_diff < 1e-12);
        for (int k = 0; k < 2; k++) {
            ASSERT_ABS(T.e[k][0] / rays, U.eps_pol[k] / rays, 2e-6);
            CU_ASSERT(fabs(T.e[k][2]) > 1e-4 * rays);
            for (int m = 0; m < 3; m++)
                ASSERT_ABS(T.e[k][m] / rays, T.recip[k][m] / rays, 1e-12);
        }
    }
    mc_surface_free(&s);
}

/* tests/data/mc_stokes.csv (tests/mc_stokes_oracle.c). */
enum { MCS_ROWS_MAX = 128 };
typedef struct {
    /* (lower case: complex.h takes I) */
    double wind, wl, theta, phi, sxx, syy, i, i_se, q, q_se, u, u_se, v, dolp, dolp_se, i1, q1,
        u1, dolp1, dolp1_se, multi, model_i, model_q, model_u, model_dolp;
} mcs_row;

static int mcs_read(mcs_row *rows, int max)
{
    FILE *f = fopen(SEA_TOP_SRCDIR "/tests/data/mc_stokes.csv", "r");
    if (f == NULL)
        return -1;
    char line[1024];
    int n = 0, header = 0;
    while (fgets(line, sizeof line, f) != NULL && n < max) {
        if (line[0] == '#')
            continue;
        if (!header) {
            header = 1;
            continue;
        }
        double *x = &rows[n].wind;
        char *p = line, *end;
        int k = 0;
        for (; k < (int)(sizeof(mcs_row) / sizeof(double)); k++) {
            x[k] = strtod(p, &end);
            if (end == p)
                break;
            p = *end == ',' ? end + 1 : end;
        }
        if (k == (int)(sizeof(mcs_row) / sizeof(double)))
            n++;
    }
    fclose(f);
    return n;
}

/* The one-hit model against the ray-traced truth, 60 rows: 60-85 deg, 4
 * and 10 um, 5-15 m/s, wind along the view and at 45 deg.
 *  - The model's columns are today's sea_polar_emissivity (1e-8: the
 *    table's 8 printed decimals).
 *  - Model against the tracer's first hits (the quantity the model
 *    computes): DoLP, Q and U within 4 standard errors of the seed-to-seed
 *    spread plus 2e-5 (the triangle mesh's own bias, which test_mc.c bounds
 *    for the scalar at 2e-5 too); 60 rows at 4 sigma: a false alarm
 *    with probability 4e-3.  Measured: worst 2.5 sigma (10 m/s, 4 um,
 *    75 deg).
 *  - Model against all hits: the second hits lower the DoLP, which the
 *    one-hit model does not see: model - all-hits DoLP is the tracer's own
 *    first-hit minus all-hit DoLP within the same 4 sigma (both sigmas)
 *    + 2e-5; measured 0.7-5.8e-3 over 60-80 deg and 1.2-1.6e-3 at 85 deg
 *    (seabake-model(7), POLARISATION), asserted below 6e-3 and 2e-3.
 *  - V (circular) is below 1e-5 everywhere: not carrying it costs nothing. */
static void test_mc_table(void)
{
    mcs_row rows[MCS_ROWS_MAX];
    const int n = mcs_read(rows, MCS_ROWS_MAX);
    CU_ASSERT_FATAL(n == 60);
    sea_water *w = NULL;
    CU_ASSERT_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) == SEA_OK);
    double worst_z = 0.0, gap85_lo = 1.0, gap85_hi = 0.0, gap_hi = 0.0;
    for (int i = 0; i < n; i++) {
        const mcs_row *r = &rows[i];
        double complex N;
        CU_ASSERT(sea_water_index(w, r->wl * 1e-6, &N, NULL) == SEA_OK);
        /* (the wind's statistics themselves: the table prints 6 digits) */
        const sea_slope_stats st = lr(r->wind);
        ASSERT_REL(st.cov.xx, r->sxx, 1e-5, 0.0);
        ASSERT_REL(st.cov.yy, r->syy, 1e-5, 0.0);
        const sea_stokes e = pol(P, SEA_EMIS_AUTO, N, &st, r->theta * DEG, r->phi * DEG);
        ASSERT_ABS(e.i, r->model_i, 1e-8);
        ASSERT_ABS(e.q, r->model_q, 1e-8);
        ASSERT_ABS(e.u, r->model_u, 1e-8);
        const double dolp = sea_stokes_dolp(&e);
        const double z = (dolp - r->dolp1) / r->dolp1_se;
        worst_z = fmax(worst_z, fabs(z));
        ASSERT_ABS(dolp, r->dolp1, 4.0 * r->dolp1_se + 2e-5);
        const double gap = dolp - r->dolp, mc_gap = r->dolp1 - r->dolp;
        ASSERT_ABS(gap, mc_gap, 4.0 * hypot(r->dolp_se, r->dolp1_se) + 2e-5);
        CU_ASSERT(gap > 0.0);
        if (r->theta == 85.0)
            gap85_lo = fmin(gap85_lo, gap), gap85_hi = fmax(gap85_hi, gap);
        else
            gap_hi = fmax(gap_hi, gap);
        CU_ASSERT(fabs(r->v) < 1e-5);
    }
    CU_ASSERT(gap_hi < 6e-3);
    CU_ASSERT(gap85_hi < 2e-3);
    printf("measured: model DoLP vs ray-traced first hits, worst %.2f sigma; model - all hits "
           "at 85 deg %.2e..%.2e, elsewhere up to %.2e\n",
           worst_z, gap85_lo, gap85_hi, gap_hi);
    ASSERT_CLAIM("polar_mc_first_hits", worst_z, 0.0);
    ASSERT_CLAIM("polar_mc_gap_max", 1e3 * gap_hi, 0.0);
    sea_water_free(w);
}

/* Every hit: sea_polar_emissivity_multi_n at reflections = 2 against the
 * tracer's every-hit columns of the same 60 rows.
 *  - e_I is sea_emissivity_multi_n's value, bit for bit.
 *  - DoLP within 1e-3 of the tracer's every-hit DoLP (one hit: 5.8e-3 off).
 *    What is left is mostly e_I: the scalar second hit sits up to 3.1e-3
 *    above the tracer's I at 85 deg (test_mc.c bounds it), which divides
 *    the DoLP by as much; and the third hits the model leaves out.
 *    Measured 8.3e-4 (10 m/s, 4 um, 85 deg, the wind at 45 deg).
 *  - U within 4 standard errors + 2e-5 (as the first hits; measured
 *    2.1 sigma): the facets met's own polarisation, turned into the seen
 *    facet's axes and reflected by its Mueller matrix, carries U's sign;
 *    without it the DoLP would be up to 7e-3 low.
 *  - The second hits only lower the DoLP below the one-hit model's. */
static void test_mc_table_every_hit(void)
{
    mcs_row rows[MCS_ROWS_MAX];
    const int n = mcs_read(rows, MCS_ROWS_MAX);
    CU_ASSERT_FATAL(n == 60);
    sea_water *w = NULL;
    CU_ASSERT_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) == SEA_OK);
    double worst = 0.0, worst_u = 0.0;
    for (int i = 0; i < n; i++) {
        const mcs_row *r = &rows[i];
        double complex N;
        CU_ASSERT(sea_water_index(w, r->wl * 1e-6, &N, NULL) == SEA_OK);
        const sea_slope_stats st = lr(r->wind);
        const sea_dir v = { r->theta * DEG, r->phi * DEG };
        sea_stokes e;
        double eps = NAN;
        CU_ASSERT_FATAL(sea_polar_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N, 1, &st, v, 2, &e,
                                                     NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N, 1, &st, v, 2, &eps,
                                               NULL) == SEA_OK);
        CU_ASSERT(e.i == eps);
        const double dolp = sea_stokes_dolp(&e);
        worst = fmax(worst, fabs(dolp - r->dolp));
        ASSERT_ABS(dolp, r->dolp, 1e-3);
        CU_ASSERT(dolp < r->model_dolp);
        worst_u = fmax(worst_u, fabs(e.u - r->u) / r->u_se);
        ASSERT_ABS(e.u, r->u, 4.0 * r->u_se + 2e-5);
    }
    printf("measured: every hit, model DoLP - tracer's worst %.2e; U worst %.2f sigma\n", worst,
           worst_u);
    ASSERT_CLAIM("polar_mc_every_hit", 1e3 * worst, 0.0);
    ASSERT_CLAIM("polar_mc_every_hit_u", worst_u, 0.0);
    sea_water_free(w);
}

/* The second hits' polarisation in the sea around: its tables against the
 * same read at every mirror ray (exact), over 3-20 m/s, 40-88 deg, every
 * 35 deg of azimuth, half the sea's slope variance with and without a mean
 * slope, 4 and 10 um: within 3e-5 of e_Q, e_U (measured 1.7e-5, at 20 m/s,
 * 80 deg, where the table's E_B itself moves as much); sea_model_polarisation is the one-hit value
 * where the model follows one hit, and gains the second hits where it
 * follows two. */
static void test_around_polar(void)
{
    double complex N[2] = { N4, N10 };
    double worst = 0.0;
    for (int wi = 0; wi < 3; wi++) {
        const double wind = (const double[]){ 3.0, 10.0, 20.0 }[wi];
        sea_spectrum spec;
        sea_slope_stats low = { { 0, 0 }, { 0, 0, 0 } };
        CU_ASSERT_FATAL(sea_spectrum_init(wind, INFINITY, 0.3, &spec, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_spectrum_slope_cov(&spec, 0.0, &low.cov, NULL) == SEA_OK);
        sea_around *ar = NULL, *ax = NULL;
        CU_ASSERT_FATAL(sea_around_alloc(P, &low, N, 2, 2, NULL, 0, &ar, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_around_alloc(P, &low, N, 2, 2, NULL, 1, &ax, NULL) == SEA_OK);
        for (int th = 40; th <= 88; th += 4)
            for (int ph = 0; ph < 360; ph += 35)
                for (int mi = 0; mi < 2; mi++) {
                    sea_slope_stats st = low;
                    st.cov.xx *= 0.5, st.cov.yy *= 0.5, st.cov.xy *= 0.5;
                    if (mi)
                        st.mean = (sea_vec2){ 0.1, -0.05 };
                    const sea_dir v = { th * DEG, ph * DEG };
                    double qa[2], ua[2], qx[2], ux[2];
                    CU_ASSERT_FATAL(sea_optics_polar_hits(P, SEA_EMIS_AUTO, NULL, N, 2, &st, v, 2,
                                                          ar, qa, ua, NULL) == SEA_OK);
                    CU_ASSERT_FATAL(sea_optics_polar_hits(P, SEA_EMIS_AUTO, NULL, N, 2, &st, v, 2,
                                                          ax, qx, ux, NULL) == SEA_OK);
                    for (int k = 0; k < 2; k++) {
                        worst = fmax(worst, fmax(fabs(qa[k] - qx[k]), fabs(ua[k] - ux[k])));
                        ASSERT_ABS(qa[k], qx[k], 3e-5);
                        ASSERT_ABS(ua[k], ux[k], 3e-5);
                    }
                }
        sea_around_free(ar);
        sea_around_free(ax);
    }
    printf("measured: the sea around's polarisation tables, worst %.2e from exact\n", worst);
    ASSERT_CLAIM("polar_around_table", worst, 0.0);
    /* the model: one hit where it follows one, else one + the second hits */
    sea_spectrum spec;
    sea_slope_stats low = { { 0, 0 }, { 0, 0, 0 } };
    CU_ASSERT_FATAL(sea_spectrum_init(10.0, INFINITY, 0.0, &spec, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_spectrum_slope_cov(&spec, 0.0, &low.cov, NULL) == SEA_OK);
    sea_model_params mp;
    sea_model_params_default(&mp);
    mp.scales = 1;
    sea_model *m = NULL;
    CU_ASSERT_FATAL(sea_model_alloc(&mp, &spec, &low, NULL, N, 2, NULL, &m, NULL) == SEA_OK);
    int seen[3] = { 0, 0, 0 };
    for (int th = 0; th <= 85; th += 5) {
        const sea_dir v = { th * DEG, 0.4 };
        double q[2], u[2];
        sea_stokes one[2];
        CU_ASSERT_FATAL(sea_model_polarisation(m, &low, v, q, u, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_polar_emissivity_n(sea_model_optics(m), SEA_EMIS_AUTO, NULL, N, 2,
                                               &low, v, one, NULL) == SEA_OK);
        const int hits = sea_model_hits(m, &low, v);
        seen[hits] = 1;
        for (int k = 0; k < 2; k++) {
            if (hits == 1) {
                CU_ASSERT(q[k] == one[k].q && u[k] == one[k].u);
            } else {
                sea_stokes e;
                CU_ASSERT_FATAL(sea_polar_emissivity_multi_n(sea_model_optics(m), SEA_EMIS_AUTO,
                                                             NULL, &N[k], 1, &low, v, 2, &e,
                                                             NULL) == SEA_OK);
                if (th >= 70) /* (the second hits are in) */
                    CU_ASSERT(fabs(q[k] - one[k].q) > 1e-4);
                ASSERT_ABS(q[k], e.q, 3e-5);
                ASSERT_ABS(u[k], e.u, 3e-5);
            }
        }
    }
    CU_ASSERT(seen[1] && seen[2]); /* (both kinds were met) */
    sea_model_free(m);
}

/* Published figures.  Henderson, Theiler and Villeneuve (2003), "The
 * polarized emissivity of a wind-roughened sea surface: A Monte Carlo
 * model", Remote Sensing of Environment, doi:10.1016/j.rse.2003.09.003,
 * abstract: the
 * reflected component "affects nearly 10% of the ray paths at emission
 * angles between 60 and 80 [deg] at wind speeds >= 5 m/s, increasing the
 * effective emissivity by as much as 0.03".  Their tracer, like ours,
 * follows Stokes vectors through every hit (Cox-Munk slopes; ours the
 * spectrum's, 6 % more mean square slope at 10 m/s).  From the table over
 * 60-80 deg, 5-15 m/s: the largest share of rays hitting twice or more,
 * "nearly 10%", read as 7-10 % (measured 9.2 %), and the largest gain of
 * emissivity over the first hit, "as much as 0.03", read as 0.025-0.035
 * (one significant figure; measured 0.027).
 * Shaw (1999), "Degree of linear polarization in spectral radiances from
 * water-viewing infrared radiometers", Applied Optics 38(15), 3157,
 * abstract: the highest p polarisation, "~4-10%", is found in the 4-5 and
 * 8-14 um windows, increasing with angle up to about 75 deg.  That is the
 * radiance's DoLP under a sky, which the sky's s-polarised reflection can
 * only lower below the emission's own; so the emission's DoLP at 10 um
 * over 70-80 deg (its largest values, where Shaw's peaks) must reach into
 * 4-10 % and not exceed 10 %: measured 4.0-8.2 % (ray-traced, all hits) at
 * 5-15 m/s.  A loose bracket, not a figure read off a curve: the papers'
 * curves are behind their publishers' pay walls. */
static void test_published(void)
{
    mcs_row rows[MCS_ROWS_MAX];
    const int n = mcs_read(rows, MCS_ROWS_MAX);
    CU_ASSERT_FATAL(n == 60);
    double multi = 0.0, gain = 0.0, lo = 1.0, hi = 0.0;
    for (int i = 0; i < n; i++) {
        const mcs_row *r = &rows[i];
        if (r->theta >= 60.0 && r->theta <= 80.0) {
            multi = fmax(multi, r->multi);
            gain = fmax(gain, r->i - r->i1);
        }
        if (r->wl == 10.0 && r->theta >= 70.0 && r->theta <= 80.0)
            lo = fmin(lo, r->dolp), hi = fmax(hi, r->dolp);
    }
    printf("measured: Henderson et al. 2003: rays hitting twice, max %.3f; emissivity gain, "
           "max %.4f; Shaw 1999: 10 um emission DoLP at 70-80 deg %.4f..%.4f\n",
           multi, gain, lo, hi);
    CU_ASSERT(multi >= 0.07 && multi <= 0.10);
    CU_ASSERT(gain >= 0.025 && gain <= 0.035);
    CU_ASSERT(hi >= 0.04 && hi <= 0.10);
    /* the table's own figures, as seabake-model(7) states them */
    ASSERT_CLAIM("polar_henderson_multi", 100.0 * multi, 0.0);
    ASSERT_CLAIM("polar_henderson_gain", gain, 0.0);
}

/* ------------------------------------------------------ the rendered image */

/* A night view at 75 deg, 10 um, 10 m/s, the sky at 0 K (so the sea's own
 * emission alone), 33 x 33 pixels over 10 deg: one hit, one scale, the
 * model sea_polar_emissivity is. */
static sea_scene night_scene(void)
{
    sea_scene sc;
    sea_scene_defaults(&sc);
    sc.wind_speed = 10.0;
    sc.wind_dir = 0.0;
    sc.temperature = 290.0;
    sc.sun_zenith = 120.0 * M_PI / 180.0;
    sc.sky_radiance = 0.0;
    sc.altitude = 30.0;
    sc.look_zenith = 75.0 * M_PI / 180.0;
    sc.look_azimuth = M_PI;
    sc.hfov = 10.0 * M_PI / 180.0;
    sc.width = sc.height = 33;
    sc.wavelength = 10e-6;
    sc.reflections = 1;
    sc.scales = 1;
    return sc;
}

/* Renders sc with its Stokes planes (stokes != 0) or without. */
static void render_stokes(const sea_scene *sc, int stokes, sea_image *img)
{
    sea_view *r = NULL;
    sea_error err;
    sea_status st = sea_view_alloc(sc, &r, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  prepare: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_image_alloc(sc->width, sc->height, img, &err), SEA_OK);
    if (stokes)
        CU_ASSERT_EQUAL_FATAL(sea_image_alloc_stokes(img, &err), SEA_OK);
    st = sea_view_render_frame(r, 0.0, img, NULL, NULL, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  frame: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    sea_view_free(r);
}

/* The image's polarisation against the model's, and what must not move:
 *  - I is the radiance, bit for bit, and asking for the Stokes planes
 *    leaves the radiance bit for bit as without them;
 *  - every sea pixel's emission is p-polarised: Q > 0 along the image's up
 *    axis, DoLP within (0.02, 0.12) (the tracer's first hits at 75 deg,
 *    10 um: 4-8 %, tests/data/mc_stokes.csv);
 *  - the image's mean Q / I is the one-hit model's e_Q / e_I on the sea's
 *    slope statistics seen from 75 deg (sea_polar_emissivity), within 10 %
 *    of it: the resolved facets the pixels see spread the ratio, and their
 *    mean is not the ratio of the means (measured 3.6 %);
 *  - seen from 20 km through 2 deg, every pixel is low-resolution (m = 0,
 *    the whole sea's covariance): the centre pixel, whose ray is the camera
 *    axis (frame angle psi = 0, view zenith 75 deg exactly on the flat
 *    sea), has Q / I and U / I of the model itself, with the wind at 45 deg
 *    to the view (e_U = 0.0016: U's sign and size in the camera's frame),
 *    to the float planes' rounding (1e-6 of I). */
static void night_check(double wind_dir, int low_res)
{
    sea_scene sc = night_scene();
    sc.wind_dir = wind_dir;
    if (low_res) {
        sc.altitude = 20000.0;
        sc.hfov = 2.0 * M_PI / 180.0;
    }
    sea_image img, plain;
    render_stokes(&sc, 1, &img);
    render_stokes(&sc, 0, &plain);
    const size_t n = (size_t)sc.width * (size_t)sc.height;
    CU_ASSERT(memcmp(img.radiance, plain.radiance, n * sizeof(float)) == 0);
    CU_ASSERT(memcmp(img.radiance, img.stokes_i, n * sizeof(float)) == 0);
    CU_ASSERT(plain.stokes_q == NULL);
    double mean = 0.0, mean_u = 0.0;
    size_t sea = 0;
    int p_pol = 1;
    for (size_t i = 0; i < n; i++) {
        if (!(img.level[i] > 0.0f))
            continue;
        const sea_stokes px = { img.stokes_i[i], img.stokes_q[i], img.stokes_u[i] };
        const double dolp = sea_stokes_dolp(&px);
        p_pol = p_pol && px.q > 0.0 && dolp > 0.02 && dolp < 0.12;
        mean += px.q / px.i;
        mean_u += px.u / px.i;
        sea++;
    }
    CU_ASSERT_FATAL(sea == n);
    CU_ASSERT(p_pol);
    mean /= (double)sea;
    mean_u /= (double)sea;
    /* the model on the whole sea's slopes */
    sea_spectrum spec;
    sea_slope_stats st = { { 0.0, 0.0 }, { 0.0, 0.0, 0.0 } };
    CU_ASSERT_FATAL(sea_spectrum_init(sc.wind_speed, INFINITY, sc.wind_dir, &spec, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_spectrum_slope_cov(&spec, 0.0, &st.cov, NULL) == SEA_OK);
    sea_water *w = NULL;
    double complex N;
    sea_optics *p = NULL;
    CU_ASSERT_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_water_index(w, sc.wavelength, &N, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_optics_alloc(&p, NULL) == SEA_OK);
    sea_optics_set_shadowing(p, sc.shadowing);
    sea_stokes e;
    CU_ASSERT_FATAL(sea_polar_emissivity(p, SEA_EMIS_AUTO, NULL, N, &st,
                                         (sea_dir){ sc.look_zenith, 0.0 }, &e, NULL) == SEA_OK);
    printf("\n    measured: night image (wind %.0f deg) mean Q/I %.5f, model e_Q/e_I %.5f "
           "(%.2f %%); mean U/I %.3g, model e_U/e_I %.3g\n",
           wind_dir * 180.0 / M_PI, mean, e.q / e.i, 100.0 * fabs(mean / (e.q / e.i) - 1.0),
           mean_u, e.u / e.i);
    if (low_res) {
        const size_t c = 16 * 33 + 16;
        CU_ASSERT(img.level[c] > 100.0f); /* low-resolution */
        ASSERT_ABS(img.stokes_q[c] / img.stokes_i[c], e.q / e.i, 1e-6);
        ASSERT_ABS(img.stokes_u[c] / img.stokes_i[c], e.u / e.i, 1e-6);
        CU_ASSERT(fabs(e.u / e.i) > 1e-3);
    } else if (wind_dir == 0.0) {
        ASSERT_CLAIM("polar_image_bound", fabs(mean / (e.q / e.i) - 1.0), 0.0);
        ASSERT_CLAIM("polar_image_mean", 100.0 * fabs(mean / (e.q / e.i) - 1.0), 0.0);
    } else {
        CU_ASSERT(fabs(mean / (e.q / e.i) - 1.0) < 0.10);
    }
    sea_optics_free(p);
    sea_water_free(w);
    sea_image_free(&img);
    sea_image_free(&plain);
}

/* The night scene seen from 20 km through 2 deg at zenith zen (deg), the
 * wind at 45 deg: every pixel low-resolution. */
static sea_scene far_scene(double zen)
{
    sea_scene sc = night_scene();
    sc.wind_dir = 45.0 * DEG;
    sc.altitude = 20000.0;
    sc.hfov = 2.0 * DEG;
    sc.look_zenith = zen * DEG;
    return sc;
}

/* Its render with the Stokes planes; the centre pixel's index (the camera
 * axis's ray), checked low-resolution. */
static size_t render_far(const sea_scene *sc, sea_image *img)
{
    render_stokes(sc, 1, img);
    const size_t c = 16 * 33 + 16;
    CU_ASSERT(img->level[c] > 100.0f);
    return c;
}

/* The whole sea of scene sc: its low-resolution slope statistics (m = 0,
 * the wind's covariance) and water's index at its wavelength. */
static void scene_sea(const sea_scene *sc, sea_slope_stats *lr, double complex *N)
{
    sea_spectrum spec;
    *lr = (sea_slope_stats){ { 0.0, 0.0 }, { 0.0, 0.0, 0.0 } };
    CU_ASSERT_FATAL(sea_spectrum_init(sc->wind_speed, INFINITY, sc->wind_dir, &spec, NULL) ==
                    SEA_OK);
    CU_ASSERT_FATAL(sea_spectrum_slope_cov(&spec, 0.0, &lr->cov, NULL) == SEA_OK);
    sea_water *w = NULL;
    CU_ASSERT_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) == SEA_OK);
    CU_ASSERT(sea_water_index(w, sc->wavelength, N, NULL) == SEA_OK);
    sea_water_free(w);
}

/* The render follows the second hits' polarisation where its model
 * follows two hits: seen from 20 km through 2 deg at 75 deg, the wind at
 * 45 deg, reflections = 2, the centre pixel (low resolution, the camera
 * axis) has sea_polar_emissivity_multi_n's Q / I and U / I within 5e-5
 * (the sea around's tables, 1.7e-5 of e_Q, test_around_polar, and the
 * float planes), 4e-3 from the one-hit values. */
static void test_render_every_hit(void)
{
    sea_scene sc = far_scene(75.0);
    sc.reflections = 2;
    sea_image img;
    const size_t c = render_far(&sc, &img);
    sea_slope_stats st;
    double complex N;
    scene_sea(&sc, &st, &N);
    sea_stokes e, one;
    const sea_dir v = { sc.look_zenith, 0.0 };
    CU_ASSERT_FATAL(sea_polar_emissivity_multi_n(P, SEA_EMIS_AUTO, NULL, &N, 1, &st, v, 2, &e,
                                                 NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N, &st, v, &one, NULL) == SEA_OK);
    const double q = img.stokes_q[c] / img.stokes_i[c], u = img.stokes_u[c] / img.stokes_i[c];
    printf("\n    measured: every hit, centre pixel Q/I %.6f U/I %.6f; model %.6f %.6f; one hit "
           "%.6f %.6f\n", q, u, e.q / e.i, e.u / e.i, one.q / one.i, one.u / one.i);
    ASSERT_ABS(q, e.q / e.i, 5e-5);
    ASSERT_ABS(u, e.u / e.i, 5e-5);
    CU_ASSERT(fabs(q - one.q / one.i) > 2e-3);
    sea_image_free(&img);
}

/* Two scales (seabake-model(7), TWO SCALES) as Stokes vectors:
 *  - sea_polar_emissivity_two_scale's e_I is sea_emissivity_two_scale's
 *    value to 1e-15 (the same mixture; measured 2.2e-16);
 *  - a vanishing resolved band gives the one-scale Stokes emissivity;
 *  - the mirror image of the view (wind and mean slope mirrored) negates
 *    e_U and keeps e_Q, to 1e-14;
 *  - at 85 deg, 4 um, e_Q moves up at 5 m/s and down at 15 m/s (1.5e-3);
 *  - the table's polarisation (sea_two_scale_polar_delta, how = 0) within
 *    2.5e-4 of the quadrature at the reference's orders (how = 2) over
 *    10 m/s, 62-86 deg, 8 azimuths, 3 mean slopes, 2 shares of the resolved
 *    band, 4 and 10 um (measured 1.3e-4; 2.2e-4 over 4-18 m/s, at 18 m/s,
 *    86 deg with a mean slope 0.2 across the view); at the table's orders
 *    without interpolation (how = 1) within 3e-5 (measured 2.0e-5). */
static void test_two_scale_polar(void)
{
    sea_spectrum spec;
    CU_ASSERT_FATAL(sea_spectrum_init(10.0, INFINITY, 0.4, &spec, NULL) == SEA_OK);
    sea_cov2 res, sub, all;
    double kh;
    CU_ASSERT_FATAL(sea_spectrum_split_half(&spec, 0.0, &kh, &res, &sub, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_spectrum_slope_cov(&spec, 0.0, &all, NULL) == SEA_OK);
    double worst_i = 0.0;
    for (int th = 50; th <= 88; th += 6) {
        const sea_dir v = { th * DEG, 1.1 };
        const sea_slope_stats sb = { { 0.05, -0.02 }, sub };
        sea_stokes e;
        double e0;
        CU_ASSERT_FATAL(sea_polar_emissivity_two_scale(P, N4, &sb, res, v, &e, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_emissivity_two_scale(P, N4, &sb, res, v, &e0, NULL) == SEA_OK);
        worst_i = fmax(worst_i, fabs(e.i - e0));
        ASSERT_ABS(e.i, e0, 1e-15);
        /* no resolved band: one scale */
        sea_stokes one, none;
        CU_ASSERT_FATAL(sea_polar_emissivity_two_scale(P, N4, &sb, (sea_cov2){ 0, 0, 0 }, v, &none,
                                                       NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N4, &sb, v, &one, NULL) ==
                        SEA_OK);
        CU_ASSERT(none.q == one.q && none.u == one.u && none.i == one.i);
        /* the mirror image */
        const sea_slope_stats mb = { { 0.05, 0.02 }, { sub.xx, sub.yy, -sub.xy } };
        const sea_cov2 mres = { res.xx, res.yy, -res.xy };
        sea_stokes m;
        CU_ASSERT_FATAL(sea_polar_emissivity_two_scale(P, N4, &mb, mres, (sea_dir){ v.theta, -v.phi },
                                                       &m, NULL) == SEA_OK);
        ASSERT_ABS(m.q, e.q, 1e-14);
        ASSERT_ABS(m.u, -e.u, 1e-14);
    }
    /* the size at 85 deg, 4 um, wind along the view: e_Q moves by either
     * sign with the wind (5 and 15 m/s), so two scales' change is not the
     * emissivity's taken unpolarised */
    double dq[2];
    for (int k = 0; k < 2; k++) {
        sea_spectrum sw;
        sea_cov2 r2, s2, a2;
        CU_ASSERT_FATAL(sea_spectrum_init(k ? 15.0 : 5.0, INFINITY, 0.0, &sw, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_spectrum_split_half(&sw, 0.0, &kh, &r2, &s2, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_spectrum_slope_cov(&sw, 0.0, &a2, NULL) == SEA_OK);
        const sea_slope_stats sb2 = { { 0.0, 0.0 }, s2 }, lr2 = { { 0.0, 0.0 }, a2 };
        const sea_dir v = { 85.0 * DEG, 0.0 };
        sea_stokes e2, e1;
        CU_ASSERT_FATAL(sea_polar_emissivity_two_scale(P, N4, &sb2, r2, v, &e2, NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N4, &lr2, v, &e1, NULL) ==
                        SEA_OK);
        dq[k] = e2.q - e1.q;
    }
    printf("measured: two scales move e_Q at 85 deg by %.2e (5 m/s) and %.2e (15 m/s)\n", dq[0],
           dq[1]);
    CU_ASSERT(dq[0] > 0.0 && dq[1] < 0.0);
    ASSERT_CLAIM("polar_two_scale_size", fabs(dq[1]), 0.0);
    double complex N[2] = { N4, N10 };
    sea_two_scale_table *t = NULL;
    CU_ASSERT_FATAL(sea_two_scale_table_alloc(P, N, 2, sub, all, 0.4, &t, NULL) == SEA_OK);
    double worst_tab = 0.0, worst_dir = 0.0;
    /* (small under a memory checker: the same code, fewer nodes) */
    const int dth = UNIT_QUICK ? 24 : 4, dph = UNIT_QUICK ? 135 : 45;
    for (int th = 62; th <= 86; th += dth)
        for (int ph = 0; ph < 360; ph += dph)
            for (int mi = 0; mi < 3; mi++)
                for (int fi = 0; fi < 2; fi++) {
                    const double f = fi ? 1.0 : 0.5;
                    sea_slope_stats st = { { 0.0, 0.0 },
                                           { sub.xx + f * (all.xx - sub.xx),
                                             sub.yy + f * (all.yy - sub.yy),
                                             sub.xy + f * (all.xy - sub.xy) } };
                    if (mi == 1)
                        st.mean = (sea_vec2){ 0.1, -0.05 };
                    if (mi == 2)
                        st.mean = (sea_vec2){ -0.05, 0.2 };
                    const sea_dir v = { th * DEG, ph * DEG };
                    double q[3][2], u[3][2];
                    for (int how = 0; how < 3; how++)
                        CU_ASSERT_FATAL(sea_two_scale_polar_delta(t, v, &st, how, q[how], u[how],
                                                                  NULL) == SEA_OK);
                    for (int k = 0; k < 2; k++) {
                        worst_tab = fmax(worst_tab, fmax(fabs(q[0][k] - q[2][k]),
                                                         fabs(u[0][k] - u[2][k])));
                        worst_dir = fmax(worst_dir, fmax(fabs(q[1][k] - q[2][k]),
                                                         fabs(u[1][k] - u[2][k])));
                    }
                }
    printf("measured: two scales' polarisation: e_I %.2e from the scalar; table %.2e and direct "
           "%.2e from the reference's orders\n",
           worst_i, worst_tab, worst_dir);
    CU_ASSERT(worst_tab < 2.5e-4);
    CU_ASSERT(worst_dir < 3e-5);
    if (!UNIT_QUICK) {
        ASSERT_CLAIM("polar_two_scale_table", worst_tab, 0.0);
        ASSERT_CLAIM("polar_two_scale_direct", worst_dir, 0.0);
    }
    CU_ASSERT(worst_tab > 0.0); /* (the table was read) */
    sea_two_scale_table_free(t);
}

/* Two scales in the render: seen from 20 km through 2 deg at 80 deg, 10
 * um, 10 m/s, the wind at 45 deg, one hit, scales = 2, the centre pixel
 * (low resolution) has the Q / I and U / I of
 * sea_polar_emissivity_two_scale on the whole sea's split within 1e-4
 * (the two tables at a facet without mean slope; measured 1e-6), where
 * treating two scales' change as unpolarised would be 3.1e-4 off in
 * Q / I. */
static void test_render_two_scales(void)
{
    sea_scene sc = far_scene(80.0);
    sc.scales = 2;
    sea_image img;
    const size_t c = render_far(&sc, &img);
    sea_spectrum spec;
    CU_ASSERT_FATAL(sea_spectrum_init(sc.wind_speed, INFINITY, sc.wind_dir, &spec, NULL) == SEA_OK);
    sea_cov2 res, sub, all;
    double kh;
    CU_ASSERT_FATAL(sea_spectrum_split_half(&spec, 0.0, &kh, &res, &sub, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_spectrum_slope_cov(&spec, 0.0, &all, NULL) == SEA_OK);
    double complex N;
    sea_water *w = NULL;
    CU_ASSERT_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_water_index(w, sc.wavelength, &N, NULL) == SEA_OK);
    const sea_dir v = { sc.look_zenith, 0.0 };
    const sea_slope_stats sb = { { 0.0, 0.0 }, sub }, lr = { { 0.0, 0.0 }, all };
    sea_stokes e, one;
    CU_ASSERT_FATAL(sea_polar_emissivity_two_scale(P, N, &sb, res, v, &e, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N, &lr, v, &one, NULL) == SEA_OK);
    const double q = img.stokes_q[c] / img.stokes_i[c], u = img.stokes_u[c] / img.stokes_i[c];
    printf("\n    measured: two scales, centre pixel Q/I %.6f U/I %.6f; model %.6f %.6f; "
           "unpolarised two scales %.6f\n",
           q, u, e.q / e.i, e.u / e.i, one.q / e.i);
    ASSERT_ABS(q, e.q / e.i, 1e-4);
    ASSERT_ABS(u, e.u / e.i, 1e-4);
    CU_ASSERT(fabs(one.q / e.i - e.q / e.i) > 2e-4);
    ASSERT_CLAIM("polar_two_scale_render", fabs(one.q / e.i - e.q / e.i), 0.0);
    sea_water_free(w);
    sea_image_free(&img);
}

/* A sky that varies with the zenith, reflected once (sea_polar_sky_n):
 *  - a uniform sky gives (1 - e_I, -e_Q, -e_U) L of sea_polar_emissivity
 *    (Q and U to 1e-15; I to 1e-9 of L: e_I reads the Fresnel table);
 *  - a clear sky (zenith emissivity 0.3, 10 m/s): I is the scalar's K_1
 *    (sea_emissivity_sky_n at one hit) to its Fresnel table's 1e-9, and Q
 *    and U by the auto rule within 1e-3 of the reflected sky's I from the
 *    adaptive reference at 60-88 deg (measured 8.3e-4, at 60 deg, where
 *    the rule's own I is 2.0e-3 off it: the rule was tuned for the
 *    emissivity, and the reflected sky is a small part of the radiance
 *    there). */
static void test_sky_polar(void)
{
    const sea_slope_stats st = lr(10);
    const double Lk[1] = { 2.5 };
    const sea_sky iso = { SEA_SKY_ISOTROPIC, NAN, Lk, 0, NULL };
    const sea_sky clear = { SEA_SKY_CLEAR, 0.3, Lk, 0, NULL };
    double worst = 0.0;
    for (int a = 0; a < 5; a++) {
        const sea_dir v = { (const double[]){ 60, 70, 80, 85, 88 }[a] * DEG, 0.3 };
        sea_stokes r, e, rc, rf;
        CU_ASSERT_FATAL(sea_polar_sky_n(P, SEA_EMIS_AUTO, NULL, &N10, 1, &st, v, &iso, &r, NULL) ==
                        SEA_OK);
        CU_ASSERT_FATAL(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N10, &st, v, &e, NULL) ==
                        SEA_OK);
        ASSERT_ABS(r.i, (1.0 - e.i) * Lk[0], 1e-9 * Lk[0]);
        ASSERT_ABS(r.q, -e.q * Lk[0], 1e-15);
        ASSERT_ABS(r.u, -e.u * Lk[0], 1e-15);
        double eps, k;
        CU_ASSERT_FATAL(sea_polar_sky_n(P, SEA_EMIS_AUTO, NULL, &N10, 1, &st, v, &clear, &rc,
                                        NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_emissivity_sky_n(P, SEA_EMIS_AUTO, NULL, &N10, 1, &st, v, 1, &clear,
                                             &eps, &k, NULL) == SEA_OK);
        ASSERT_ABS(rc.i, k, 1e-9);
        CU_ASSERT_FATAL(sea_polar_sky_n(P, SEA_EMIS_FULL, NULL, &N10, 1, &st, v, &clear, &rf,
                                        NULL) == SEA_OK);
        worst = fmax(worst, fmax(fabs(rc.q - rf.q), fabs(rc.u - rf.u)) / rf.i);
        ASSERT_ABS(rc.q, rf.q, 1e-3 * rf.i);
        ASSERT_ABS(rc.u, rf.u, 1e-3 * rf.i);
    }
    printf("measured: clear sky's Stokes reflection, auto rule against the adaptive reference "
           "%.2e of I\n", worst);
    ASSERT_CLAIM("polar_sky_rule", worst, 0.0);
}

/* In the render: the far scene at 80 deg under a clear sky (air at 280 K,
 * zenith emissivity 0.3), one hit, one scale: the centre pixel's Q / I is
 * (e_Q B_sea + q_sky) / (e_I B_sea + I_sky) of sea_polar_emissivity and
 * sea_polar_sky_n within 1e-4 (measured to the float planes), where the
 * uniform sky of the same reflected radiance would be 1e-3 off. */
static void test_render_clear_sky(void)
{
    sea_scene sc = far_scene(80.0);
    sc.sky_model = SEA_SKY_CLEAR;
    sc.sky_zenith_emissivity = 0.3;
    sc.air_temperature = 280.0;
    sea_image img;
    const size_t c = render_far(&sc, &img);
    sea_slope_stats st;
    double complex N;
    scene_sea(&sc, &st, &N);
    const double B = sea_planck_radiance(sc.wavelength, sc.temperature);
    const double Lk[1] = { sea_planck_radiance(sc.wavelength, sc.air_temperature) };
    const sea_sky clear = { SEA_SKY_CLEAR, sc.sky_zenith_emissivity, Lk, 0, NULL };
    const sea_dir v = { sc.look_zenith, 0.0 };
    sea_stokes e, r;
    CU_ASSERT_FATAL(sea_polar_emissivity(P, SEA_EMIS_AUTO, NULL, N, &st, v, &e, NULL) == SEA_OK);
    CU_ASSERT_FATAL(sea_polar_sky_n(P, SEA_EMIS_AUTO, NULL, &N, 1, &st, v, &clear, &r, NULL) ==
                    SEA_OK);
    /* (complex.h takes I) */
    const double Ir = e.i * B + r.i, Qr = e.q * B + r.q, Ur = e.u * B + r.u;
    const double L_eff = r.i / (1.0 - e.i), Q_uniform = e.q * (B - L_eff);
    const double q = img.stokes_q[c] / img.stokes_i[c], u = img.stokes_u[c] / img.stokes_i[c];
    printf("\n    measured: clear sky, centre pixel Q/I %.6f U/I %.6f; model %.6f %.6f; as a "
           "uniform sky %.6f\n", q, u, Qr / Ir, Ur / Ir, Q_uniform / Ir);
    ASSERT_ABS(q, Qr / Ir, 1e-4);
    ASSERT_ABS(u, Ur / Ir, 1e-4);
    CU_ASSERT(fabs(Q_uniform / Ir - Qr / Ir) > 1e-3);
    ASSERT_CLAIM("polar_sky_render", q, 0.0);
    ASSERT_CLAIM("polar_sky_uniform", Q_uniform / Ir, 0.0);
    sea_image_free(&img);
}

static void test_render_night(void)
{
    night_check(0.0, 0);
    night_check(45.0 * M_PI / 180.0, 0);
    night_check(45.0 * M_PI / 180.0, 1);
}

/* The camera's frame.  Rolled by rho (sea_camera_init: right' = right cos
 * rho + up sin rho, so up' = up cos rho - right sin rho), the image's axes
 * turn and the view's e_v (the unrolled up at the centre pixel, the same
 * sea point: odd sizes) lies at psi = rho from up' toward right'.  So at
 * 90 deg Q and U are negated, and at 45 deg Q' = -U and U' = Q; I is
 * unchanged.  The wind at 45 deg to the view gives U its own value.  Seen
 * from 20 km through 2 deg (every pixel low-resolution, as in
 * test_render_night), so that the pixel's rays, which turn with the image,
 * read the same slopes.  To float rounding, 1e-6 of I. */
static void test_render_roll(void)
{
    sea_scene sc = night_scene();
    sc.wind_dir = 45.0 * M_PI / 180.0;
    sc.altitude = 20000.0;
    sc.hfov = 2.0 * M_PI / 180.0;
    sea_image a, b, h;
    render_stokes(&sc, 1, &a);
    sc.roll = 90.0 * M_PI / 180.0;
    render_stokes(&sc, 1, &b);
    sc.roll = 45.0 * M_PI / 180.0;
    render_stokes(&sc, 1, &h);
    const size_t c = 16 * 33 + 16;
    const double tol = 1e-6 * a.stokes_i[c];
    ASSERT_REL(b.stokes_i[c], a.stokes_i[c], 1e-6, 0.0);
    ASSERT_ABS(b.stokes_q[c], -a.stokes_q[c], tol);
    ASSERT_ABS(b.stokes_u[c], -a.stokes_u[c], tol);
    ASSERT_ABS(h.stokes_q[c], -a.stokes_u[c], tol);
    ASSERT_ABS(h.stokes_u[c], a.stokes_q[c], tol);
    CU_ASSERT(a.stokes_q[c] > 0.0f);
    CU_ASSERT(fabs(a.stokes_u[c]) > 10.0 * tol); /* U is not 0 */
    sea_image_free(&a);
    sea_image_free(&b);
    sea_image_free(&h);
}

/* A polarizer at 0, 45, 90 and 135 deg reads I + Q cos 2a + U sin 2a, so
 * (p0 + p90) / 2 = I, (p0 - p90) / 2 = Q, (p45 - p135) / 2 = U: to float
 * rounding of the planes (1e-6 of I), on tiny.ini's glint (sun in view: the
 * glint s-polarised, Q < 0). */
static void test_render_polarizer(void)
{
    sea_scene sc = night_scene();
    sc.sun_zenith = 50.0 * M_PI / 180.0;
    sc.sun_azimuth = M_PI;
    sc.look_zenith = 60.0 * M_PI / 180.0;
    sc.hfov = 40.0 * M_PI / 180.0;
    sc.wavelength = 4e-6;
    sc.reflections = SEA_REFLECTIONS_AUTO;
    /* (one scale under a memory checker: each of the four renders makes
     * its own two-scale tables; test_render_two_scales reads them) */
    sc.scales = UNIT_QUICK ? 1 : 2;
    sea_image st;
    render_stokes(&sc, 1, &st);
    sea_image pol[4];
    for (int k = 0; k < 4; k++) {
        sc.polarizer = 45.0 * k * M_PI / 180.0;
        render_stokes(&sc, 0, &pol[k]);
    }
    const size_t n = (size_t)sc.width * (size_t)sc.height;
    double worst = 0.0, qneg = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double Ii = st.stokes_i[i];
        worst = fmax(worst, fabs(0.5 * (pol[0].radiance[i] + pol[2].radiance[i]) - Ii) / Ii);
        worst = fmax(worst, fabs(0.5 * (pol[0].radiance[i] - pol[2].radiance[i]) - st.stokes_q[i]) / Ii);
        worst = fmax(worst, fabs(0.5 * (pol[1].radiance[i] - pol[3].radiance[i]) - st.stokes_u[i]) / Ii);
        qneg += st.stokes_q[i] < 0.0f;
    }
    CU_ASSERT(worst < 1e-6);
    CU_ASSERT(qneg > 0.5 * (double)n);
    sea_image_free(&st);
    for (int k = 0; k < 4; k++)
        sea_image_free(&pol[k]);
}

/* In a blackbody enclosure (no sun, a uniform sky at the sea's temperature)
 * nothing is polarised, whatever the model: Q = U = 0 to rounding (1e-9 of
 * I), at the default reflections and two scales as at one hit. */
static void test_render_enclosure(void)
{
    for (int k = 0; k < 2; k++) {
        sea_scene sc = night_scene();
        sc.sky_radiance = -1.0;
        sc.sky_temperature = sc.temperature;
        if (k == 1) {
            sc.reflections = SEA_REFLECTIONS_AUTO;
            sc.scales = 2;
        }
        sea_image img;
        render_stokes(&sc, 1, &img);
        const size_t n = (size_t)sc.width * (size_t)sc.height;
        double worst = 0.0;
        for (size_t i = 0; i < n; i++)
            worst = fmax(worst, (fabs(img.stokes_q[i]) + fabs(img.stokes_u[i])) / img.stokes_i[i]);
        ASSERT_CLAIM("polar_enclosure", worst, 0.0);
        sea_image_free(&img);
    }
}

int test_polar_register(void)
{
    CU_pSuite s = CU_add_suite("polar", setup, teardown);
    if (s == NULL)
        return 1;
    return CU_add_test(s, "Fresnel R_s, R_p", test_fresnel) == NULL ||
           CU_add_test(s, "flat sea: Fresnel's DoLP", test_flat_sea) == NULL ||
           CU_add_test(s, "e_I = scalar emissivity", test_intensity_is_scalar) == NULL ||
           CU_add_test(s, "many indices, reference", test_many_and_reference) == NULL ||
           CU_add_test(s, "symmetry of U", test_symmetry) == NULL ||
           CU_add_test(s, "nadir", test_nadir) == NULL ||
           CU_add_test(s, "emission p-polarised", test_p_polarised) == NULL ||
           CU_add_test(s, "DoLP figures", test_dolp_figures) == NULL ||
           CU_add_test(s, "reflectivities", test_reflectivity) == NULL ||
           CU_add_test(s, "errors", test_errors) == NULL ||
           CU_add_test(s, "ray tracer: flat sea", test_mc_flat) == NULL ||
           CU_add_test(s, "ray tracer: two routes", test_mc_routes) == NULL ||
           CU_add_test(s, "model vs ray-traced DoLP", test_mc_table) == NULL ||
           CU_add_test(s, "every hit vs ray-traced DoLP", test_mc_table_every_hit) == NULL ||
           CU_add_test(s, "second hits in the sea around", test_around_polar) == NULL ||
           CU_add_test(s, "published figures", test_published) == NULL ||
           CU_add_test(s, "render: night emission", test_render_night) == NULL ||
           CU_add_test(s, "render: every hit", test_render_every_hit) == NULL ||
           CU_add_test(s, "two scales", test_two_scale_polar) == NULL ||
           CU_add_test(s, "render: two scales", test_render_two_scales) == NULL ||
           CU_add_test(s, "a sky that varies", test_sky_polar) == NULL ||
           CU_add_test(s, "render: clear sky", test_render_clear_sky) == NULL ||
           CU_add_test(s, "render: the camera's frame", test_render_roll) == NULL ||
           CU_add_test(s, "render: polarizer", test_render_polarizer) == NULL ||
           CU_add_test(s, "render: enclosure", test_render_enclosure) == NULL;
}
