/* shadow.c - Smith shadowing for a Gaussian slope with a non-zero mean
 * (Eq 9c-9e, 10, 14c).
 *
 * Everything rests on one function, G(t) = phi(t) - t Q(t) = int_t^inf Q,
 * the first partial moment of the standard normal: for gamma ~ N(m, s^2),
 *   E[(gamma - mu)+] = s G((mu - m)/s),  E[(mu - gamma)+] = s G((m - mu)/s).
 * For large t the two terms of G cancel (at t = 30 the direct form keeps
 * only 5 digits), so above t = 3 it is computed from Laplace's continued
 * fraction of the Mills ratio, Q/phi = 1/(t + 1/(t + 2/(t + 3/(t + ...)))),
 * which gives 1 - t Q/phi = 1/(1 + t K), K = t + 2/(t + 3/(t + ...)). */
#include "config.h"

#include <math.h>

#include "seabake.h"
#include "internal.h"

/* Above this t the continued fraction is used (direct form error there
 * about 1e-14; continued fraction with the depth below, < 1e-15). */
static const double SEA_G_CF_THRESHOLD = 3.0;
/* Depth of the continued fraction at t: 10 + 450/t^2 terms, at most 60.
 * Measured against depth 400, the depth that reaches 2e-16 relative is
 * 54 at t = 3, 35 at 4, 26 at 5, 16 at 8, 13 at 10, 7 at 30; this rule
 * gives 60, 39, 28, 18, 15, 10: never fewer, and a fifth of the work at
 * the t of most calls (5-10). */
enum { SEA_G_CF_DEPTH = 60 };
static const double SEA_G_CF_DEPTH_BASE = 10.0, SEA_G_CF_DEPTH_SCALE = 450.0;
/* Zenith angles below this are nadir: tan(theta) < 1e-12 contributes
 * nothing representable to Lambda or D. */
static const double SEA_NADIR_THETA = 1e-12;

double sea_shadow_G(double t)
{
    const double inv_sqrt_2pi = 0.39894228040143267794;
    if (t <= SEA_G_CF_THRESHOLD) {
        if (t < -40.0) /* phi(t) underflows relative to |t|: G = -t + O(phi/t^2) */
            return -t;
        /* libm's erfc: within 2e-15 relative of a long double reference
         * over t in [-45, 3], and 4.6x as fast as GSL's. */
        const double Q = 0.5 * erfc(t * M_SQRT1_2);
        return inv_sqrt_2pi * exp(-0.5 * t * t) - t * Q;
    }
    const int depth = (int)fmin(ceil(SEA_G_CF_DEPTH_BASE + SEA_G_CF_DEPTH_SCALE / (t * t)),
                                (double)SEA_G_CF_DEPTH);
    double K = t;
    for (int j = depth; j >= 2; j--)
        K = t + j / K;
    return inv_sqrt_2pi * exp(-0.5 * t * t) / (1.0 + t * K);
}

/* E[(gamma - mu)+]; s = 0 is the limit max(m - mu, 0). */
double sea_shadow_hidden(double mu, double m, double s)
{
    if (s <= 0.0)
        return fmax(m - mu, 0.0);
    const double z = (mu - m) / s;
    if (z >= 0.0)
        return s * sea_shadow_G(z);
    /* Facets mostly turned away: the small one is the visible moment. */
    return (m - mu) + s * sea_shadow_G(-z);
}

double sea_shadow_visible(double mu, double m, double s)
{
    if (s <= 0.0)
        return fmax(mu - m, 0.0);
    const double z = (mu - m) / s;
    if (z <= 0.0)
        return s * sea_shadow_G(-z);
    return (mu - m) + s * sea_shadow_G(z);
}

void sea_shadow_split(double mu, double m, double s, double *visible, double *hidden)
{
    if (s <= 0.0) {
        *visible = fmax(mu - m, 0.0);
        *hidden = fmax(m - mu, 0.0);
        return;
    }
    /* one G for both: they differ by mu - m (the same operations as
     * sea_shadow_visible and sea_shadow_hidden) */
    const double z = (mu - m) / s;
    if (z >= 0.0) {
        const double sg = s * sea_shadow_G(z);
        *hidden = sg;
        *visible = z == 0.0 ? sg : (mu - m) + sg;
    } else {
        const double sg = s * sea_shadow_G(-z);
        *visible = sg;
        *hidden = (m - mu) + sg;
    }
}

double sea_shadow_lambda(double theta, double m, double s)
{
    if (theta < SEA_NADIR_THETA)
        return 0.0;
    return tan(theta) * sea_shadow_hidden(1.0 / tan(theta), m, s);
}

double sea_shadow_D(double theta, double m, double s)
{
    if (theta < SEA_NADIR_THETA)
        return 1.0;
    const double t = tan(theta);
    const double mu = 1.0 / t;
    /* D = (1 + Lambda - m tan) / (1 + Lambda) with the numerator written as
     * tan(theta) E[(mu - gamma)+], a sum of non-negative terms. */
    double vis, hid;
    sea_shadow_split(mu, m, s, &vis, &hid);
    return t * vis / (1.0 + t * hid);
}

/* ------------------------------------------------ correlated shadowing */

/* Smith's function treats the heights ahead of a facet as independent of
 * the facet's own slope; along a real profile they are not (a facet tilted
 * toward the sensor starts a ray that clears the surface ahead sooner).
 * Following Bourlier, Saillard and Berginc (IEEE Trans. Antennas Propag.
 * 48, 437, 2000; the "correlated Smith" function), the hazard of Smith's
 * derivation is taken under the joint Gaussian law of the profile's height
 * and slope at distance l conditioned on the facet's height z0 and slope
 * t, here for the Gaussian correlation R(l) = exp(-l^2/2) (unit height
 * and slope deviations; the ray rises at z = (cot theta - m)/s):
 *   rate(l) = E[(gamma_l - z)+ ; zeta_l = z0 + z l] / P(zeta_l < z0 + z l)
 *   S(z0, t) = exp(-int_0^inf rate dl),  S(t) = E_z0[S(z0, t)].
 * Past L_END correlations are below 1e-27 and Smith's closed form of the
 * rest, Lambda (-ln Phi(z0 + z L_END)) with Lambda = G(z)/z, is exact.
 * Only the slope dependence changes the emissivity, so the function kept
 * is C(z, t) = S(t) (1 + G(z)/z), Smith's constant divided out. */
static const double SEA_CS_PANELS[] = { 0.0, 1e-3, 5e-3, 0.02, 0.08, 0.2, 0.4, 0.7, 1.0,
                                        1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 11.0 };
enum { SEA_CS_NODES = 16, SEA_CS_Z0_PANELS = 8 };
static const double SEA_CS_Z0_MAX = 8.0;

static double cs_phi(double u) { return 0.39894228040143267794 * exp(-0.5 * u * u); }
static double cs_Phi(double u) { return 0.5 * erfc(-u * M_SQRT1_2); }

/* Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre
 * recurrence; tests/test_shadow.c checks them against GSL's). */
static void cs_gauss_legendre(int n, double *x, double *w)
{
    for (int i = 0; i < n; i++) {
        double r = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = r;
            for (int k = 2; k <= n; k++) {
                const double p2 = ((2 * k - 1) * r * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (r * p1 - p0) / (r * r - 1.0);
            const double step = p1 / dp;
            r -= step;
            if (fabs(step) < 1e-16)
                break;
        }
        x[i] = r;
        w[i] = 2.0 / ((1.0 - r * r) * dp * dp);
    }
}

static double cs_rate(double l, double z0, double t, double z)
{
    const double x = l * l, e = exp(-0.5 * x), e2 = exp(-x);
    /* conditional means and covariance of (zeta_l, gamma_l) given (z0, t) */
    const double mz = e * (z0 + l * t), mg = e * (-l * z0 - (x - 1.0) * t);
    const double szz = -expm1(-x) - x * e2;
    const double sgg = 1.0 - e2 * (1.0 - x + x * x), szg = l * x * e2;
    if (!(szz > 0.0))
        return 0.0;
    const double sz = sqrt(szz), eta = z0 + z * l, a = (eta - mz) / sz;
    const double mc = mg + szg / szz * (eta - mz);
    const double sc = sqrt(fmax(sgg - szg * szg / szz, 1e-300));
    const double below = cs_Phi(a);
    if (!(below > 1e-300))
        return 1e300;
    return cs_phi(a) / sz * sc * sea_shadow_G((z - mc) / sc) / below;
}

double sea_shadow_correlated_exact(double z, double t)
{
    if (!(z > 0.0) || !(t < z))
        return 0.0;
    double x[SEA_CS_NODES], w[SEA_CS_NODES];
    cs_gauss_legendre(SEA_CS_NODES, x, w);
    const int np = (int)(sizeof SEA_CS_PANELS / sizeof SEA_CS_PANELS[0]);
    const double l_end = SEA_CS_PANELS[np - 1], lambda = sea_shadow_G(z) / z;
    double S = 0.0;
    for (int q = 0; q < SEA_CS_Z0_PANELS; q++) {
        const double h = SEA_CS_Z0_MAX / SEA_CS_Z0_PANELS;
        const double zm = -SEA_CS_Z0_MAX + h * (2 * q + 1);
        for (int i = 0; i < SEA_CS_NODES; i++) {
            const double z0 = zm + h * x[i];
            double hazard = -lambda * log(cs_Phi(z0 + z * l_end));
            for (int p = 0; p + 1 < np && hazard < 745.0; p++) {
                const double a = SEA_CS_PANELS[p], b = SEA_CS_PANELS[p + 1];
                const double hh = 0.5 * (b - a), lm = 0.5 * (a + b);
                for (int k = 0; k < SEA_CS_NODES; k++)
                    hazard += hh * w[k] * cs_rate(lm + hh * x[k], z0, t, z);
            }
            S += h * w[i] * cs_phi(z0) * exp(-hazard);
        }
    }
    return S * (1.0 + lambda);
}

#ifndef SEA_CS_GENERATOR /* (the generator computes the table) */
#include "shadow_table.h"

static int cs_clamp(int i, int n) { return i < 0 ? 0 : i > n ? n : i; }

/* The z part of the interpolation: the four rows and their weights. */
typedef struct {
    int row[4];
    double wa[4];
} cs_rows;

static void cs_rows_of(double z, cs_rows *r)
{
    const double zc = z < SEA_CS_Z_MIN ? SEA_CS_Z_MIN : z;
    /* index coordinate: the grid is quadratic */
    double a = SEA_CS_NZ * sqrt((zc - SEA_CS_Z_MIN) / (SEA_CS_Z_MAX - SEA_CS_Z_MIN));
    a = a > SEA_CS_NZ ? SEA_CS_NZ : a;
    int i = (int)a;
    i = i >= SEA_CS_NZ ? SEA_CS_NZ - 1 : i;
    sea_catmull_rom(a - i, r->wa);
    for (int p = 0; p < 4; p++)
        r->row[p] = cs_clamp(i - 1 + p, SEA_CS_NZ);
}

/* C at u = z - t > 0 from the rows (Catmull-Rom in both index coordinates:
 * continuous slopes, so the emissivity's Gauss-Legendre rules see no
 * kinks; one-sided at the grid's ends). */
static double cs_at(const cs_rows *r, double u)
{
    double b = SEA_CS_NU * sqrt(u / SEA_CS_U_MAX);
    b = b > SEA_CS_NU ? SEA_CS_NU : b;
    int j = (int)b;
    j = j >= SEA_CS_NU ? SEA_CS_NU - 1 : j;
    double wb[4];
    sea_catmull_rom(b - j, wb);
    const int j0 = cs_clamp(j - 1, SEA_CS_NU), j1 = j, j2 = j + 1, j3 = cs_clamp(j + 2, SEA_CS_NU);
    double acc = 0.0;
    for (int p = 0; p < 4; p++) {
        const double *row = sea_cs_table[r->row[p]];
        acc += r->wa[p] * (wb[0] * row[j0] + wb[1] * row[j1] + wb[2] * row[j2] + wb[3] * row[j3]);
    }
    return acc;
}

double sea_shadow_correlated(double z, double t)
{
    if (!(z <= SEA_CS_Z_MAX))
        return 1.0; /* (also NaN) past Z_MAX facets are as good as unshadowed */
    const double u = z - t;
    if (!(u > 0.0))
        return 0.0;
    cs_rows r;
    cs_rows_of(z, &r);
    return cs_at(&r, u);
}

void sea_shadow_correlated_scale(double z, double mid, double half, const double *x, int n,
                                 double *w)
{
    if (!(z <= SEA_CS_Z_MAX))
        return;
    cs_rows r;
    cs_rows_of(z, &r);
    for (int k = 0; k < n; k++) {
        const double u = z - (mid + half * x[k]);
        w[k] = u > 0.0 ? w[k] * cs_at(&r, u) : 0.0;
    }
}
#endif
