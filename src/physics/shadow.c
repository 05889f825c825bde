/* shadow.c - Smith shadowing for a Gaussian slope with a non-zero mean
 * (Eq 9c-9e, 10, 14c).
 *
 * Everything rests on one function, G(t) = phi(t) - t Q(t) = int_t^inf Q,
 * the first partial moment of the standard normal: for gamma ~ N(m, s^2),
 *   E[(gamma - mu)+] = s G((mu - m)/s),  E[(mu - gamma)+] = s G((m - mu)/s).
 * For large t the two terms of G cancel (at t = 30 the direct form keeps
 * only 5 digits): G / phi = 1 - t Q/phi comes from Laplace's continued
 * fraction of the Mills ratio, Q/phi = 1/(t + 1/(t + 2/(t + 3/(t + ...)))),
 * 1 - t Q/phi = 1/(1 + t K), K = t + 2/(t + 3/(t + ...)), once, into a
 * table of polynomials (below). */
#include "config.h"

#include <math.h>
#include <stdlib.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
/* sea_shadow_correlated_scale's node loop in AVX2 when the caller asks
 * (sea_optics decides at run time; never required at build time). */
#define SEA_SHADOW_AVX2 1
#endif

#include "seabake.h"
#include "internal.h"

/* G(|t|) = phi(t) x^2 f(x), x = 1 / (1 + |t|) in (0, 1], and G(t) = G(-t)
 * - t below 0: f = (G / phi) (1 + t)^2 is smooth on [0, 1] (1 at both
 * ends), held as SEA_G_PIECES polynomials of degree SEA_G_DEGREE in
 * u = 2 (x N - i) - 1 on each piece i, interpolated at Chebyshev nodes.
 * The table is computed in double (g_table_build): f from erfc up to
 * t = 1, beyond from Laplace's continued fraction to depth SEA_G_CF_BUILD.
 * Against a long double reference over [-12, 12] G is within 7.8e-15
 * relative (the rounding of t^2 / 2 inside exp, 1e-16 t^2 / 2, dominates;
 * the erfc and continued-fraction forms used before were 2.5e-14 off),
 * and costs one exp, one division and a degree-5 polynomial: 10 ns
 * against 76 ns over t in [0, 6].  Building it takes 13 M instructions
 * (1.5 M divisions of the continued fractions), 8 % of those of a 4 x 4
 * render (callgrind), which every process that used G paid, so it is part
 * of the sources, as the correlated table below is: src/physics/shadow_g_table.h,
 * written by src/physics/gen-shadow-table.c (`make shadow-table`) from
 * g_table_build in exact hexadecimal; sea_shadow_g_table_drift tells how
 * far the code here now is from it. */
enum { SEA_G_PIECES = 256, SEA_G_DEGREE = 5, SEA_G_CF_BUILD = 2000 };
#ifdef SEA_CS_GENERATOR
static double sea_g_table[SEA_G_PIECES][SEA_G_DEGREE + 1];
#else
#include "shadow_g_table.h"
#endif

static double g_ratio_scaled(double x)
{
    if (!(x < 1.0))
        return 1.0;
    const double t = 1.0 / x - 1.0;
    double R;
    if (t <= 1.0) {
        const double Q = 0.5 * erfc(t * M_SQRT1_2);
        R = 1.0 - t * Q / (0.39894228040143267794 * exp(-0.5 * t * t));
    } else {
        double K = t;
        for (int j = SEA_G_CF_BUILD; j >= 2; j--)
            K = t + j / K;
        R = 1.0 / (1.0 + t * K);
    }
    return R * (1.0 + t) * (1.0 + t);
}

static void g_table_build(double table[SEA_G_PIECES][SEA_G_DEGREE + 1])
{
    enum { D = SEA_G_DEGREE };
    /* Chebyshev polynomials in the power basis: T[j][p] */
    double T[D + 1][D + 1] = { { 0.0 } };
    T[0][0] = 1.0;
    T[1][1] = 1.0;
    for (int j = 2; j <= D; j++)
        for (int p = 0; p <= D; p++)
            T[j][p] = (p > 0 ? 2.0 * T[j - 1][p - 1] : 0.0) - T[j - 2][p];
    for (int i = 0; i < SEA_G_PIECES; i++) {
        const double half = 0.5 / SEA_G_PIECES, mid = (i + 0.5) / SEA_G_PIECES;
        double fv[D + 1], a[D + 1];
        for (int k = 0; k <= D; k++)
            fv[k] = g_ratio_scaled(mid + half * cos(M_PI * (k + 0.5) / (D + 1)));
        for (int j = 0; j <= D; j++) {
            double sum = 0.0;
            for (int k = 0; k <= D; k++)
                sum += fv[k] * cos(M_PI * j * (k + 0.5) / (D + 1));
            a[j] = sum * (j == 0 ? 1.0 : 2.0) / (D + 1);
        }
        for (int p = 0; p <= D; p++) {
            double c = 0.0;
            for (int j = 0; j <= D; j++)
                c += a[j] * T[j][p];
            table[i][p] = c;
        }
    }
}

double sea_shadow_g_table_drift(void)
{
    double (*fresh)[SEA_G_DEGREE + 1] = malloc(sizeof(double[SEA_G_PIECES][SEA_G_DEGREE + 1]));
    if (fresh == NULL)
        return INFINITY;
    g_table_build(fresh);
    double d = 0.0;
    for (int i = 0; i < SEA_G_PIECES; i++)
        for (int p = 0; p <= SEA_G_DEGREE; p++)
            d = fmax(d, fabs(fresh[i][p] - sea_g_table[i][p]));
    free(fresh);
    return d;
}

/* Zenith angles below this are nadir: tan(theta) < 1e-12 contributes
 * nothing representable to Lambda or D. */
static const double SEA_NADIR_THETA = 1e-12;

/* f(x) of G(at) = phi(at) x^2 f(x), x = 1 / (1 + at), at >= 0 (the table
 * holds x in (0, 1], so any at). */
static double g_poly(double at, double *x_out)
{
    const double x = 1.0 / (1.0 + at);
    const double s = x * SEA_G_PIECES;
    int i = (int)s;
    if (i > SEA_G_PIECES - 1)
        i = SEA_G_PIECES - 1;
    const double u = 2.0 * (s - i) - 1.0;
    const double *c = sea_g_table[i];
    double p = c[SEA_G_DEGREE];
    for (int k = SEA_G_DEGREE - 1; k >= 0; k--)
        p = p * u + c[k];
    *x_out = x;
    return p;
}

double sea_shadow_G(double t)
{
    const double at = fabs(t);
    if (!(at < 40.0)) /* phi underflows: G(t) = max(-t, 0) (NaN stays NaN) */
        return t > 0.0 ? 0.0 : t < 0.0 ? -t : t;
    double x;
    const double p = g_poly(at, &x);
    const double g = 0.39894228040143267794 * exp(-0.5 * at * at) * p * x * x;
    return t < 0.0 ? g + at : g;
}

double sea_shadow_log_visible(double mu, double m, double s)
{
    if (s <= 0.0)
        return log(fmax(mu - m, 0.0));
    const double z = (mu - m) / s;
    if (z > 0.0)
        return log((mu - m) + s * sea_shadow_G(z));
    /* s G(t), t = -z >= 0, in logs: ln phi(t) = -ln sqrt(2 pi) - t^2 / 2 */
    double x;
    const double p = g_poly(-z, &x);
    return log(s) - 0.91893853320467274178 - 0.5 * z * z + log(p) + 2.0 * log(x);
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

/* The column coordinate of u is NU sqrt(u / U_MAX) = sqrt(u B2): one
 * product and a square root (no division) per node. */
static const double SEA_CS_B2 = (double)SEA_CS_NU * SEA_CS_NU / SEA_CS_U_MAX;

/* The z part of the interpolation: the four rows and their weights
 * (sea_cs_rows, internal.h). */
static void cs_rows_of(double z, sea_cs_rows *r)
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

/* The table column interval j of u > 0 and the offset *f in it (the one
 * place the column coordinate is found: cs_at, cs_comb_at and the range of
 * columns a rule's nodes reach agree by construction). */
static int cs_column(double u, double *f)
{
    double b = sqrt(u * SEA_CS_B2);
    b = b > SEA_CS_NU ? SEA_CS_NU : b;
    int j = (int)b;
    j = j >= SEA_CS_NU ? SEA_CS_NU - 1 : j;
    *f = b - j;
    return j;
}

/* C at u = z - t > 0 from the rows (Catmull-Rom in both index coordinates:
 * continuous slopes, so the emissivity's Gauss-Legendre rules see no
 * kinks; one-sided at the grid's ends). */
static double cs_at(const sea_cs_rows *r, double u)
{
    double f;
    const int j = cs_column(u, &f);
    double wb[4];
    sea_catmull_rom(f, wb);
    const int j0 = cs_clamp(j - 1, SEA_CS_NU), j1 = j, j2 = j + 1, j3 = cs_clamp(j + 2, SEA_CS_NU);
    double acc = 0.0;
    for (int p = 0; p < 4; p++) {
        const double *row = sea_cs_table[r->row[p]];
        acc += r->wa[p] * (wb[0] * row[j0] + wb[1] * row[j1] + wb[2] * row[j2] + wb[3] * row[j3]);
    }
    return acc;
}

void sea_shadow_correlated_z(double z, sea_cs_z *h)
{
    h->z = z;
    h->past = !(z <= SEA_CS_Z_MAX); /* (also NaN) past Z_MAX facets are as good as unshadowed */
    if (!h->past)
        cs_rows_of(z, &h->r);
}

double sea_shadow_correlated_zt(const sea_cs_z *h, double t)
{
    if (h->past)
        return 1.0;
    const double u = h->z - t;
    return u > 0.0 ? cs_at(&h->r, u) : 0.0;
}

double sea_shadow_correlated(double z, double t)
{
    sea_cs_z h;
    sea_shadow_correlated_z(z, &h);
    return sea_shadow_correlated_zt(&h, t);
}

/* C at u > 0 from the combined row comb of sea_shadow_correlated_scale
 * (the portable loop's arithmetic, which cs_scale_avx2 repeats). */
static inline double cs_comb_at(const double *comb, double u)
{
    double f;
    const int j = cs_column(u, &f);
    double wb[4];
    sea_catmull_rom(f, wb);
    const int j0 = cs_clamp(j - 1, SEA_CS_NU), j3 = cs_clamp(j + 2, SEA_CS_NU);
    return wb[0] * comb[j0] + wb[1] * comb[j] + wb[2] * comb[j + 1] + wb[3] * comb[j3];
}

#ifdef SEA_SHADOW_AVX2
/* The combined row over columns jlo .. jhi, four at a time (the scalar
 * loop's operations and order); returns the first column not done. */
__attribute__((target("avx2"))) static int cs_comb_avx2(const double wa[4], const double *r0,
                                                        const double *r1, const double *r2,
                                                        const double *r3, int jlo, int jhi,
                                                        double *comb)
{
    const __m256d a0 = _mm256_set1_pd(wa[0]), a1 = _mm256_set1_pd(wa[1]);
    const __m256d a2 = _mm256_set1_pd(wa[2]), a3 = _mm256_set1_pd(wa[3]);
    int j = jlo;
    for (; j + 3 <= jhi; j += 4) {
        const __m256d v = _mm256_add_pd(
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, _mm256_loadu_pd(r0 + j)),
                                        _mm256_mul_pd(a1, _mm256_loadu_pd(r1 + j))),
                          _mm256_mul_pd(a2, _mm256_loadu_pd(r2 + j))),
            _mm256_mul_pd(a3, _mm256_loadu_pd(r3 + j)));
        _mm256_storeu_pd(comb + j, v);
    }
    return j;
}

/* Four nodes at a time: the same IEEE operations in the same order as
 * cs_comb_at (no fused multiply-add), so the same bits.  Nodes with u <= 0
 * get 0; their lanes read the row at ulo (> 0), inside what was combined.
 * comb[-1] and comb[SEA_CS_NU + 1] must hold comb[0] and comb[SEA_CS_NU]
 * where the combined columns reach the table's ends (cs_comb_at's clamps). */
__attribute__((target("avx2"))) static int cs_scale_avx2(const double *comb, double z, double mid,
                                                         double half, const double *x, int n,
                                                         double ulo, double *w)
{
    const __m256d vz = _mm256_set1_pd(z), vmid = _mm256_set1_pd(mid), vhalf = _mm256_set1_pd(half);
    const __m256d vlo = _mm256_set1_pd(ulo), zero = _mm256_setzero_pd();
    const __m256d b2 = _mm256_set1_pd(SEA_CS_B2), nu = _mm256_set1_pd(SEA_CS_NU);
    const __m256d sign = _mm256_set1_pd(-0.0), half1 = _mm256_set1_pd(0.5);
    const __m256d two = _mm256_set1_pd(2.0), three = _mm256_set1_pd(3.0);
    const __m256d four = _mm256_set1_pd(4.0), five = _mm256_set1_pd(5.0);
    const __m128i last = _mm_set1_epi32(SEA_CS_NU - 1);
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        const __m256d u =
            _mm256_sub_pd(vz, _mm256_add_pd(vmid, _mm256_mul_pd(vhalf, _mm256_loadu_pd(x + k))));
        const __m256d pos = _mm256_cmp_pd(u, zero, _CMP_GT_OQ);
        const __m256d uu = _mm256_blendv_pd(vlo, u, pos);
        __m256d b = _mm256_sqrt_pd(_mm256_mul_pd(uu, b2));
        b = _mm256_min_pd(b, nu);
        __m128i j = _mm256_cvttpd_epi32(b);
        j = _mm_min_epi32(j, last);
        const __m256d f = _mm256_sub_pd(b, _mm256_cvtepi32_pd(j));
        const __m256d f2 = _mm256_mul_pd(f, f), f3 = _mm256_mul_pd(f2, f);
        const __m256d w0 = _mm256_mul_pd(
            half1, _mm256_sub_pd(_mm256_add_pd(_mm256_xor_pd(f3, sign), _mm256_mul_pd(two, f2)), f));
        const __m256d w1 = _mm256_mul_pd(
            half1,
            _mm256_add_pd(_mm256_sub_pd(_mm256_mul_pd(three, f3), _mm256_mul_pd(five, f2)), two));
        const __m256d w2 = _mm256_mul_pd(
            half1, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_xor_pd(three, sign), f3),
                                               _mm256_mul_pd(four, f2)),
                                 f));
        const __m256d w3 = _mm256_mul_pd(half1, _mm256_sub_pd(f3, f2));
        /* each node's four values comb[j - 1 .. j + 2] are one load (the
         * guards hold the clamped ends), the four loads transposed */
        int jj[4];
        _mm_storeu_si128((__m128i *)jj, j);
        __m256d c[4] = { _mm256_loadu_pd(comb + jj[0] - 1), _mm256_loadu_pd(comb + jj[1] - 1),
                         _mm256_loadu_pd(comb + jj[2] - 1), _mm256_loadu_pd(comb + jj[3] - 1) };
        sea_transpose4_avx2(c);
        const __m256d c0 = c[0], c1 = c[1], c2 = c[2], c3 = c[3];
        const __m256d v = _mm256_add_pd(
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(w0, c0), _mm256_mul_pd(w1, c1)),
                          _mm256_mul_pd(w2, c2)),
            _mm256_mul_pd(w3, c3));
        _mm256_storeu_pd(w + k, _mm256_and_pd(pos, _mm256_mul_pd(_mm256_loadu_pd(w + k), v)));
    }
    return k;
}
#endif

/* The same C at many u for one z: the z part of the interpolation is done
 * once, as one row (the four rows' combination over the columns the nodes
 * reach), and each node reads four values of it. */
void sea_shadow_correlated_scale(double z, double mid, double half, const double *x, int n,
                                 double *w, int avx2)
{
    sea_cs_z h;
    sea_shadow_correlated_z(z, &h);
    if (h.past)
        return;
    const sea_cs_rows r = h.r;
    /* the columns the nodes reach, from the smallest and largest u > 0 */
    double ulo = INFINITY, uhi = 0.0;
    for (int k = 0; k < n; k++) {
        const double u = z - (mid + half * x[k]);
        if (u > 0.0) {
            ulo = u < ulo ? u : ulo;
            uhi = u > uhi ? u : uhi;
        }
    }
    if (!(uhi > 0.0)) {
        for (int k = 0; k < n; k++)
            w[k] = 0.0;
        return;
    }
    double unused;
    const int jlo = cs_clamp(cs_column(ulo, &unused) - 1, SEA_CS_NU);
    const int jhi = cs_clamp(cs_column(uhi, &unused) + 2, SEA_CS_NU);
    double padded[SEA_CS_NU + 3], *comb = padded + 1; /* guards at -1 and NU + 1 */
    const double *r0 = sea_cs_table[r.row[0]], *r1 = sea_cs_table[r.row[1]];
    const double *r2 = sea_cs_table[r.row[2]], *r3 = sea_cs_table[r.row[3]];
    int j = jlo;
#ifdef SEA_SHADOW_AVX2
    if (avx2)
        j = cs_comb_avx2(r.wa, r0, r1, r2, r3, jlo, jhi, comb);
#endif
    for (; j <= jhi; j++)
        comb[j] = r.wa[0] * r0[j] + r.wa[1] * r1[j] + r.wa[2] * r2[j] + r.wa[3] * r3[j];
    comb[jlo - 1] = comb[jlo]; /* (read only at the table's ends, as clamped) */
    comb[jhi + 1] = comb[jhi];
    int k = 0;
#ifdef SEA_SHADOW_AVX2
    if (avx2)
        k = cs_scale_avx2(comb, z, mid, half, x, n, ulo, w);
#else
    (void)avx2;
#endif
    for (; k < n; k++) {
        const double u = z - (mid + half * x[k]);
        w[k] = u > 0.0 ? w[k] * cs_comb_at(comb, u) : 0.0;
    }
}
#endif
