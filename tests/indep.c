/* indep.c - independent implementations of the formulas the tests judge the
 * model by (see indep.h).  Nothing here calls the library: the formulas are
 * written from their textbook forms (PHYSICS conventions: directions point
 * away from the surface, slopes gamma = grad z, the view's azimuth gives
 * the X axis), in other arithmetic than src/ (real Born & Wolf u, v instead
 * of a complex square root; adaptive GSL quadrature instead of the
 * library's fixed rules and tables). */
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <math.h>
#include <stdlib.h>

#include "indep.h"

void indep_fresnel_uv(double c, double n, double k, double *u, double *v)
{
    const double s2 = 1.0 - c * c;
    const double a = n * n - k * k - s2, b = 2.0 * n * k;
    const double r = hypot(a, b);
    /* u^2 = (r + a)/2 and v^2 = (r - a)/2: take the one that does not
     * cancel, the other from u v = n k */
    if (a >= 0.0) {
        *u = sqrt(0.5 * (r + a));
        *v = *u > 0.0 ? n * k / *u : 0.0;
    } else {
        *v = sqrt(0.5 * (r - a));
        *u = *v > 0.0 ? n * k / *v : 0.0;
    }
}

double indep_fresnel(double c, double n, double k)
{
    if (!(c > 0.0))
        return 1.0;
    if (c > 1.0)
        c = 1.0;
    double u, v;
    indep_fresnel_uv(c, n, k, &u, &v);
    const double st = (1.0 - c * c) / c; /* sin psi tan psi */
    const double Rs = ((c - u) * (c - u) + v * v) / ((c + u) * (c + u) + v * v);
    const double Rp = Rs * ((u - st) * (u - st) + v * v) / ((u + st) * (u + st) + v * v);
    return 0.5 * (Rs + Rp);
}

void indep_fresnel_amplitudes(double c, double complex N, double complex *rs, double complex *rp)
{
    if (c < 0.0)
        c = 0.0;
    if (c > 1.0)
        c = 1.0;
    double u, v;
    indep_fresnel_uv(c, creal(N), cimag(N), &u, &v);
    const double complex w = CMPLX(u, v);
    const double s2 = 1.0 - c * c;
    *rs = (c - w) / (c + w);
    *rp = -*rs * (w * c - s2) / (w * c + s2);
}

static const double INV_SQRT_2PI = 0.39894228040143267794;

double indep_smith_lambda(double theta, double m, double s)
{
    if (!(theta > 0.0))
        return 0.0;
    const double mu = 1.0 / tan(theta), z = (mu - m) / s;
    const double phi = INV_SQRT_2PI * exp(-0.5 * z * z), Q = 0.5 * erfc(z / M_SQRT2);
    return fmax(tan(theta) * (s * phi - (mu - m) * Q), 0.0);
}

/* ---------------------------------------------------------------- Eq 7 */

/* Standardised slopes beyond 12 deviations carry exp(-72) of the weight. */
static const double SPAN = 12.0;
enum { WS = 2000 };
/* Absolute tolerance of each integral (the integrands are O(1) Gaussian
 * weights): well below the 1e-9 the tests ask of the ratio.  A relative
 * tolerance alone cannot be met where the correlated visibility, a
 * piecewise cubic, makes the rule's error estimate stall at rounding. */
static const double EPS_ABS = 1e-13;

typedef struct {
    double n, k, cos_t, sin_t;
    double mX, sX;          /* gamma_X */
    double mY0, bY, sY;     /* gamma_Y | gamma_X: mY0 + bY (gamma_X - mX), sY */
    double z;               /* (cot theta - mX) / sX */
    indep_visibility vis;
    double gX;              /* the outer integral's current gamma_X */
    int num;                /* 1: numerator (1 - rho), 0: denominator (1) */
    gsl_integration_workspace *inner;
    int failed;
} eq7;

static double inner_integrand(double u, void *p)
{
    const eq7 *e = p;
    const double gY = e->mY0 + e->bY * (e->gX - e->mX) + e->sY * u;
    const double cpsi = (e->cos_t - e->gX * e->sin_t) / sqrt(1.0 + e->gX * e->gX + gY * gY);
    return INV_SQRT_2PI * exp(-0.5 * u * u) * (1.0 - indep_fresnel(cpsi, e->n, e->k));
}

static double outer_integrand(double t, void *p)
{
    eq7 *e = p;
    e->gX = e->mX + e->sX * t;
    const double g = e->cos_t - e->gX * e->sin_t;
    if (!(g > 0.0))
        return 0.0;
    double w = INV_SQRT_2PI * exp(-0.5 * t * t) * g;
    if (e->vis != NULL)
        w *= e->vis(e->z, t);
    if (!e->num)
        return w;
    double r, err;
    gsl_function F = { inner_integrand, e };
    if (gsl_integration_qag(&F, -SPAN, SPAN, EPS_ABS, 1e-12, WS, GSL_INTEG_GAUSS21, e->inner, &r,
                            &err) != GSL_SUCCESS)
        e->failed = 1;
    return w * r;
}

double indep_emissivity(double complex N, double mx, double my, double cxx, double cyy,
                        double cxy, double theta, double phi, indep_visibility vis)
{
    if (!(theta >= 0.0 && theta < M_PI / 2.0) || !(cxx > 0.0 && cyy > 0.0) ||
        !(cxx * cyy > cxy * cxy))
        return NAN;
    const double c = cos(phi), s = sin(phi);
    const double cXX = cxx * c * c + 2.0 * cxy * c * s + cyy * s * s;
    const double cYY = cxx * s * s - 2.0 * cxy * c * s + cyy * c * c;
    const double cXY = (cyy - cxx) * c * s + cxy * (c * c - s * s);
    eq7 e = { .n = creal(N), .k = cimag(N), .cos_t = cos(theta), .sin_t = sin(theta),
              .mX = mx * c + my * s, .sX = sqrt(cXX), .mY0 = -mx * s + my * c,
              .bY = cXY / cXX, .sY = sqrt(cYY - cXY * cXY / cXX), .vis = vis };
    e.z = theta > 0.0 ? (1.0 / tan(theta) - e.mX) / e.sX : INFINITY;
    const double hi = fmin(e.z, SPAN);
    if (!(hi > -SPAN))
        return NAN; /* nothing in view */
    gsl_integration_workspace *wo = gsl_integration_workspace_alloc(WS);
    e.inner = gsl_integration_workspace_alloc(WS);
    double num = NAN, den = NAN, err;
    if (wo != NULL && e.inner != NULL) {
        /* Break points: the visibility's own (its table ends at z - t = 12,
         * where it turns constant) and the limit, where C(z, t) rises like a
         * root from 0 (qagp's extrapolation takes that end point) */
        double pts[3] = { -SPAN, 0.0, hi };
        size_t np = 2;
        pts[1] = hi;
        if (vis != NULL && e.z - 12.0 > -SPAN && e.z - 12.0 < hi) {
            pts[1] = e.z - 12.0;
            pts[2] = hi;
            np = 3;
        }
        gsl_function F = { outer_integrand, &e };
        for (e.num = 1; e.num >= 0; e.num--) {
            double *out = e.num ? &num : &den;
            const int r = vis != NULL
                              ? gsl_integration_qagp(&F, pts, np, EPS_ABS, 1e-11, WS, wo, out, &err)
                              : gsl_integration_qag(&F, -SPAN, hi, EPS_ABS, 1e-11, WS,
                                                    GSL_INTEG_GAUSS21, wo, out, &err);
            if (r != GSL_SUCCESS)
                e.failed = 1;
        }
    }
    gsl_integration_workspace_free(wo);
    gsl_integration_workspace_free(e.inner);
    if (e.failed || !(den > 0.0))
        return NAN;
    if (vis == NULL) {
        /* Eq 10: the seen facets' projected area is D (1 + Lambda) */
        const double tan_t = tan(theta), L = indep_smith_lambda(theta, e.mX, e.sX);
        const double closed = e.cos_t * (1.0 - e.mX * tan_t + L);
        if (!(fabs(den - closed) <= 1e-9 * closed))
            return NAN;
    }
    return num / den;
}

/* --------------------------------------------------------------- Eq 13 */

double indep_reflectivity(double complex N, double mx, double my, double cxx, double cyy,
                          double cxy, double ti, double pi_, double to, double po)
{
    const double ui[3] = { sin(ti) * cos(pi_), sin(ti) * sin(pi_), cos(ti) };
    const double uo[3] = { sin(to) * cos(po), sin(to) * sin(po), cos(to) };
    const double dot = ui[0] * uo[0] + ui[1] * uo[1] + ui[2] * uo[2];
    const double den = ui[2] + uo[2];
    if (!(den > 0.0) || !(cxx * cyy > cxy * cxy))
        return NAN;
    /* Eq 14a-b: the slope of the facet that mirrors inc into obs */
    const double gx0 = -(uo[0] + ui[0]) / den, gy0 = -(uo[1] + ui[1]) / den;
    /* its normal bisects the two directions: cos psi0 = |u_i + u_o| / 2 */
    const double cpsi0 = sqrt(fmax(0.5 * (1.0 + dot), 0.0));
    const double co = cos(po), so = sin(po), ci = cos(pi_), si = sin(pi_);
    const double g = 1.0 - (gx0 * co + gy0 * so) * tan(to);
    if (!(g > 0.0))
        return 0.0;
    /* the bivariate Gaussian density at gamma_0 */
    const double det = cxx * cyy - cxy * cxy;
    const double dx = gx0 - mx, dy = gy0 - my;
    const double q = (cyy * dx * dx - 2.0 * cxy * dx * dy + cxx * dy * dy) / det;
    const double P = exp(-0.5 * q) / (2.0 * M_PI * sqrt(det));
    /* Eq 14d */
    const double J = (1.0 + dot) / (den * den * den);
    /* Eq 14c: Lambda of each direction with the slopes along its own azimuth */
    const double mXo = mx * co + my * so, sXo = sqrt(cxx * co * co + 2.0 * cxy * co * so + cyy * so * so);
    const double mXi = mx * ci + my * si, sXi = sqrt(cxx * ci * ci + 2.0 * cxy * ci * si + cyy * si * si);
    const double Lo = indep_smith_lambda(to, mXo, sXo), Li = indep_smith_lambda(ti, mXi, sXi);
    const double D = 1.0 - mXo * tan(to) / (1.0 + Lo);
    return indep_fresnel(cpsi0, creal(N), cimag(N)) * P * g * J / ((1.0 + Lo + Li) * D);
}
