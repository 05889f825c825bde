/* spectrum.c - the Elfouhaily et al. (1997) directional wave spectrum, the
 * swells added to it, and the slope covariance of the waves above a cutoff
 * (Eq 15, 17).
 *
 * Formulas and constants as in seabake-model(7), THE SEA SPECTRUM.  The short-wave
 * curvature uses F_m = L_PM J_p exp(-(k/k_m - 1)^2 / 4), the variant that
 * carries the long-wave peak factors L_PM J_p into the short-wave term (as in
 * the spectrum's widely used erratum form); the paper's sigma_x = 0.19,
 * sigma_y = 0.16 at U10 = 10 m/s are reproduced (0.1898, 0.1586). */
#include "config.h"

#include <math.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include "seabake.h"

static const double SEA_G = 9.81;       /* gravity, m/s^2 */
static const double SEA_K_M = 370.0;    /* gravity-capillary wavenumber, rad/m */
static const double SEA_C_M = 0.23;     /* minimum phase speed, m/s */
static const double SEA_X0 = 2.2e4;     /* fetch scale of Omega_c */
static const double SEA_KAPPA = 0.4;    /* von Karman */
/* alpha_m: junction of the low-wind continuation, in ln(u_star / c_m).
 * Elfouhaily's 1e-2 (1 + ln x) is positive down to ln x = -1 (U10 = 2.74 m/s
 * fully developed), and a continuation of value and slope must leave it
 * before its zero.  It leaves at -0.9 (U10 = 2.98 m/s): from 3 m/s up the
 * spectrum is the published one, and below, where the formula heads for
 * zero, alpha_m decays like x^10 instead.  (The earlier junction, -3/4 or
 * 3.40 m/s, replaced the formula where it is well defined: the slope
 * variance came out 2.3 % above the published spectrum's at 3 m/s.) */
static const double SEA_ALPHA_M_JUNCTION = -0.9;
/* Integration limits in k relative to k_p and k_m.  Below k_p/40, L_PM =
 * exp(-1.25 * 1600) vanishes; above 60 k_m the short-wave Gaussian is below
 * exp(-840).  Both tails are far below double precision of the integral. */
static const double SEA_K_LOW_OVER_KP = 1.0 / 40.0;
static const double SEA_K_HIGH_OVER_KM = 60.0;
enum { SEA_QUAD_LIMIT = 1000 };

double sea_spectrum_omega(double k)
{
    const double r = k / SEA_K_M;
    return sqrt(SEA_G * k * (1.0 + r * r));
}

static double phase_speed(double k)
{
    const double r = k / SEA_K_M;
    return sqrt(SEA_G / k * (1.0 + r * r));
}

double sea_spectrum_alpha_m(double x)
{
    const double lx = log(x);
    if (lx > 0.0)
        return 1e-2 * (1.0 + 3.0 * log(x));
    if (lx >= SEA_ALPHA_M_JUNCTION)
        return 1e-2 * (1.0 + lx);
    /* f(l) = (1 + l0) exp((l - l0) / (1 + l0)) matches 1 + l and its slope
     * at l0 and decays like x^(1 / (1 + l0)) = x^10 for l0 = -0.9. */
    const double f0 = 1.0 + SEA_ALPHA_M_JUNCTION;
    return 1e-2 * f0 * exp((lx - SEA_ALPHA_M_JUNCTION) / f0);
}

int sea_spectrum_alpha_m_continued(const sea_spectrum *s)
{
    return log(s->u_star / SEA_C_M) < SEA_ALPHA_M_JUNCTION;
}

sea_status sea_spectrum_init(double wind_speed, double fetch, double wind_dir, sea_spectrum *s,
                             sea_error *err)
{
    if (!(wind_speed >= SEA_WIND_MIN && wind_speed <= SEA_WIND_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "wind speed %g m/s is outside [%g, %g] m/s",
                        wind_speed, SEA_WIND_MIN, SEA_WIND_MAX);
    if (!(fetch >= SEA_FETCH_MIN)) /* also refuses NaN; INFINITY is allowed */
        return sea_fail(err, SEA_ERR_DOMAIN, "fetch %g m is outside [%g, inf] m", fetch,
                        SEA_FETCH_MIN);
    if (!isfinite(wind_dir))
        return sea_fail(err, SEA_ERR_DOMAIN, "wind direction is not finite");

    const double U = wind_speed;
    s->wind_speed = U;
    s->fetch = fetch;
    s->wind_dir = wind_dir;
    s->k0 = SEA_G / (U * U);
    if (isinf(fetch)) {
        s->omega_c = 0.84; /* fully developed */
    } else {
        const double X = s->k0 * fetch;
        s->omega_c = 0.84 * pow(tanh(pow(X / SEA_X0, 0.4)), -0.75);
    }
    s->k_p = s->k0 * s->omega_c * s->omega_c;
    s->c_p = phase_speed(s->k_p);
    const double Omega = U / s->c_p;
    s->alpha_p = 6e-3 * sqrt(Omega);
    s->gamma = s->omega_c < 1.0 ? 1.7 : 1.7 + 6.0 * log10(s->omega_c);
    s->delta = 0.08 * (1.0 + 4.0 * pow(s->omega_c, -3.0));
    /* Friction velocity from the log law with Charnock-like roughness
     * z0 = 3.7e-5 (U^2/g) (U/c_p)^0.9, which does not depend on u*. */
    const double z0 = 3.7e-5 * (U * U / SEA_G) * pow(U / s->c_p, 0.9);
    s->u_star = SEA_KAPPA * U / log(10.0 / z0);
    s->alpha_m = sea_spectrum_alpha_m(s->u_star / SEA_C_M);
    s->n_swell = 0;
    return SEA_OK;
}

/* ------------------------------------------------------------- swell */

/* JONSWAP peak widths below and above the peak (Hasselmann et al. 1973). */
static const double SEA_SWELL_SIGMA_LO = 0.07, SEA_SWELL_SIGMA_HI = 0.09;

/* The JONSWAP shape in x = omega / omega_p without its scale: S(omega) =
 * alpha g^2 omega_p^-5 jonswap_shape(x), and x^pow times it. */
static double jonswap_shape(double x, double gamma)
{
    const double sg = x <= 1.0 ? SEA_SWELL_SIGMA_LO : SEA_SWELL_SIGMA_HI;
    const double r = exp(-(x - 1.0) * (x - 1.0) / (2.0 * sg * sg));
    const double x4 = x * x * x * x;
    return exp(-1.25 / x4) * pow(gamma, r) / (x4 * x);
}

typedef struct {
    double gamma;
    int power;
} shape_args;

static double shape_moment(double x, void *params)
{
    const shape_args *a = params;
    return pow(x, a->power) * jonswap_shape(x, a->gamma);
}

/* int_{x0}^{SEA_SWELL_BAND_HI} x^power shape(x) dx, with a break at the peak. */
static sea_status shape_integral(double gamma, int power, double x0, double *out, sea_error *err)
{
    *out = 0.0;
    if (!(x0 < SEA_SWELL_BAND_HI))
        return SEA_OK;
    gsl_integration_workspace *ws = gsl_integration_workspace_alloc(SEA_QUAD_LIMIT);
    if (ws == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    shape_args a = { gamma, power };
    gsl_function F = { shape_moment, &a };
    double pts[3], abserr;
    size_t np = 0;
    pts[np++] = x0;
    if (x0 < 1.0)
        pts[np++] = 1.0;
    pts[np++] = SEA_SWELL_BAND_HI;
    int rc = gsl_integration_qagp(&F, pts, np, 0.0, SEA_SPECTRUM_REL_TOL, SEA_QUAD_LIMIT, ws,
                                  out, &abserr);
    gsl_integration_workspace_free(ws);
    if (rc != GSL_SUCCESS)
        return sea_fail(err, SEA_ERR_NUMERIC, "swell spectrum integral did not converge: %s",
                        gsl_strerror(rc));
    return SEA_OK;
}

sea_status sea_spectrum_add_swell(sea_spectrum *s, const sea_swell *sw, sea_error *err)
{
    if (s->n_swell < 0 || s->n_swell >= SEA_SWELL_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "swell %d: at most %d swells", s->n_swell + 1,
                        SEA_SWELL_MAX);
    if (!(sw->hs >= SEA_SWELL_HS_MIN && sw->hs <= SEA_SWELL_HS_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "swell height %g m is outside [%g, %g] m", sw->hs,
                        SEA_SWELL_HS_MIN, SEA_SWELL_HS_MAX);
    if (!(sw->tp >= SEA_SWELL_TP_MIN && sw->tp <= SEA_SWELL_TP_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "swell peak period %g s is outside [%g, %g] s",
                        sw->tp, SEA_SWELL_TP_MIN, SEA_SWELL_TP_MAX);
    if (!isfinite(sw->dir))
        return sea_fail(err, SEA_ERR_DOMAIN, "swell direction is not finite");
    const double deg = 180.0 / M_PI;
    /* a hair of slack: a spread given in degrees comes back through pi/180 */
    if (!(sw->spread * deg >= SEA_SWELL_SPREAD_MIN_DEG * (1.0 - 1e-12) &&
          sw->spread * deg <= SEA_SWELL_SPREAD_MAX_DEG * (1.0 + 1e-12)))
        return sea_fail(err, SEA_ERR_DOMAIN, "swell spread %g deg is outside [%g, %g] deg",
                        sw->spread * deg, SEA_SWELL_SPREAD_MIN_DEG, SEA_SWELL_SPREAD_MAX_DEG);
    if (!(sw->gamma >= SEA_SWELL_GAMMA_MIN && sw->gamma <= SEA_SWELL_GAMMA_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "swell peak enhancement %g is outside [%g, %g]",
                        sw->gamma, SEA_SWELL_GAMMA_MIN, SEA_SWELL_GAMMA_MAX);
    sea_swell w = *sw;
    w.omega_p = 2.0 * M_PI / w.tp;
    double i0;
    sea_status st = shape_integral(w.gamma, 0, SEA_SWELL_BAND_LO, &i0, err);
    if (st != SEA_OK)
        return st;
    /* m0 = alpha g^2 omega_p^-4 i0 = (hs/4)^2 */
    const double q = w.hs / 4.0, wp2 = w.omega_p * w.omega_p;
    w.alpha = q * q * wp2 * wp2 / (SEA_G * SEA_G * i0);
    s->swell[s->n_swell++] = w;
    return SEA_OK;
}

int sea_swell_douglas(int d, double *hs, double *tp)
{
    /* height class low, moderate, heavy; length class short, average, long */
    static const double height[3] = { 1.0, 3.0, 5.0 }, length[3] = { 75.0, 150.0, 300.0 };
    static const int code[8][2] = { { 0, 1 }, { 0, 2 }, { 1, 0 }, { 1, 1 },
                                    { 1, 2 }, { 2, 0 }, { 2, 1 }, { 2, 2 } };
    if (d < 1 || d > 8)
        return -1;
    *hs = height[code[d - 1][0]];
    *tp = sqrt(2.0 * M_PI * length[code[d - 1][1]] / SEA_G);
    return 0;
}

void sea_swell_band(const sea_swell *sw, double *k_lo, double *k_hi)
{
    const double lo = SEA_SWELL_BAND_LO * sw->omega_p, hi = SEA_SWELL_BAND_HI * sw->omega_p;
    *k_lo = lo * lo / SEA_G;
    *k_hi = hi * hi / SEA_G;
}

double sea_swell_curvature(const sea_swell *sw, double k)
{
    if (!(k > 0.0))
        return 0.0;
    const double omega = sqrt(SEA_G * k), x = omega / sw->omega_p;
    if (x < SEA_SWELL_BAND_LO || x > SEA_SWELL_BAND_HI)
        return 0.0;
    /* S(k) = S(omega) d omega / d k = S(omega) g / (2 omega), with
     * S(omega) = alpha g^2 omega_p^-5 shape(x) */
    const double wp = sw->omega_p, wp5 = wp * wp * wp * wp * wp;
    const double S_omega = sw->alpha * SEA_G * SEA_G / wp5 * jonswap_shape(x, sw->gamma);
    return k * k * k * S_omega * SEA_G / (2.0 * omega);
}

double sea_swell_direction_density(const sea_swell *sw, double phi)
{
    const double d = remainder(phi - sw->dir, 2.0 * M_PI), sg = sw->spread;
    double sum = 0.0;
    for (int n = -3; n <= 3; n++) {
        const double u = (d + 2.0 * M_PI * n) / sg;
        sum += exp(-0.5 * u * u);
    }
    return sum / (sg * sqrt(2.0 * M_PI));
}

double sea_spectrum_k_low(const sea_spectrum *s)
{
    double k = s->k_p * SEA_K_LOW_OVER_KP;
    for (int i = 0; i < s->n_swell; i++) {
        double lo, hi;
        sea_swell_band(&s->swell[i], &lo, &hi);
        k = fmin(k, lo);
    }
    return k;
}

/* Slope variance int_kc^inf B_i(k)/k dk of a swell: with k = omega^2/g,
 * k^2 S(k) dk = omega^4/g^2 S(omega) d omega = alpha x^4 shape(x) dx. */
static sea_status swell_slope_variance(const sea_swell *sw, double kc, double *out,
                                       sea_error *err)
{
    const double xc = sqrt(SEA_G * kc) / sw->omega_p;
    double m;
    sea_status st = shape_integral(sw->gamma, 4, fmax(xc, SEA_SWELL_BAND_LO), &m, err);
    *out = sw->alpha * m;
    return st;
}

double sea_spectrum_curvature(const sea_spectrum *s, double k)
{
    const double c = phase_speed(k);
    const double Omega = s->wind_speed / s->c_p;
    const double q = sqrt(k / s->k_p) - 1.0;
    const double Gamma = exp(-q * q / (2.0 * s->delta * s->delta));
    const double ratio = s->k_p / k;
    const double L_PM = exp(-1.25 * ratio * ratio);
    const double J_p = pow(s->gamma, Gamma);
    const double F_p = L_PM * J_p * exp(-(Omega / sqrt(10.0)) * q);
    const double B_l = 0.5 * s->alpha_p * (s->c_p / c) * F_p;
    const double r = k / SEA_K_M - 1.0;
    const double F_m = L_PM * J_p * exp(-0.25 * r * r);
    const double B_h = 0.5 * s->alpha_m * (SEA_C_M / c) * F_m;
    return B_l + B_h;
}

double sea_spectrum_omni(const sea_spectrum *s, double k)
{
    return sea_spectrum_curvature(s, k) / (k * k * k);
}

double sea_spectrum_spreading(const sea_spectrum *s, double k)
{
    const double c = phase_speed(k);
    const double a0 = log(2.0) / 4.0;
    const double a_p = 4.0;
    const double a_m = 0.13 * s->u_star / SEA_C_M;
    return tanh(a0 + a_p * pow(c / s->c_p, 2.5) + a_m * pow(SEA_C_M / c, 2.5));
}

double sea_spectrum_directional(const sea_spectrum *s, double k, double phi)
{
    const double Phi = (1.0 + sea_spectrum_spreading(s, k) * cos(2.0 * (phi - s->wind_dir))) /
                       (2.0 * M_PI);
    return sea_spectrum_omni(s, k) * Phi / k + sea_spectrum_directional_swell(s, k, phi);
}

double sea_spectrum_directional_swell(const sea_spectrum *s, double k, double phi)
{
    double sum = 0.0;
    for (int i = 0; i < s->n_swell; i++) {
        const double B = sea_swell_curvature(&s->swell[i], k);
        if (B > 0.0)
            sum += B / (k * k * k * k) * sea_swell_direction_density(&s->swell[i], phi);
    }
    return sum;
}

typedef struct {
    const sea_spectrum *s;
    double sign; /* +1: along the wind, -1: across */
} slope_integrand_args;

/* In ln k: k^2 S(k) (1 +- Delta/2)/2 dk = B(k) (1 +- Delta/2)/2 d(ln k). */
static double slope_integrand(double lnk, void *params)
{
    const slope_integrand_args *a = params;
    const double k = exp(lnk);
    return sea_spectrum_curvature(a->s, k) * 0.5 *
           (1.0 + 0.5 * a->sign * sea_spectrum_spreading(a->s, k));
}

sea_status sea_spectrum_slope_cov(const sea_spectrum *s, double kc, sea_cov2 *out,
                                  sea_error *err)
{
    if (!(kc >= 0.0) || !isfinite(kc))
        return sea_fail(err, SEA_ERR_DOMAIN, "cutoff wavenumber %g rad/m must be >= 0 and finite",
                        kc);
    const double k_lo = fmax(kc, s->k_p * SEA_K_LOW_OVER_KP);
    const double k_hi = SEA_K_M * SEA_K_HIGH_OVER_KM;
    double var[2] = { 0.0, 0.0 };
    if (k_lo < k_hi) {
        gsl_integration_workspace *ws = gsl_integration_workspace_alloc(SEA_QUAD_LIMIT);
        if (ws == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        /* Break points at the spectral peak and at k_m, where the integrand
         * has its two humps, when they fall inside the interval. */
        double pts[4];
        size_t np = 0;
        pts[np++] = log(k_lo);
        if (s->k_p > k_lo && s->k_p < k_hi)
            pts[np++] = log(s->k_p);
        if (SEA_K_M > k_lo && SEA_K_M < k_hi && SEA_K_M != s->k_p)
            pts[np++] = log(SEA_K_M);
        if (np == 3 && pts[1] > pts[2]) {
            double t = pts[1];
            pts[1] = pts[2];
            pts[2] = t;
        }
        pts[np++] = log(k_hi);
        for (int i = 0; i < 2; i++) {
            slope_integrand_args args = { s, i == 0 ? 1.0 : -1.0 };
            gsl_function F = { slope_integrand, &args };
            double abserr;
            int rc = gsl_integration_qagp(&F, pts, np, 0.0, SEA_SPECTRUM_REL_TOL, SEA_QUAD_LIMIT,
                                          ws, &var[i], &abserr);
            if (rc != GSL_SUCCESS) {
                gsl_integration_workspace_free(ws);
                return sea_fail(err, SEA_ERR_NUMERIC,
                                "slope variance integral (kc = %g rad/m) did not converge: %s", kc,
                                gsl_strerror(rc));
            }
        }
        gsl_integration_workspace_free(ws);
    }
    /* Rotate diag(sigma_u^2, sigma_c^2) from the wind frame to x, y. */
    const double c = cos(s->wind_dir), sn = sin(s->wind_dir);
    out->xx = var[0] * c * c + var[1] * sn * sn;
    out->yy = var[0] * sn * sn + var[1] * c * c;
    out->xy = (var[0] - var[1]) * c * sn;
    for (int i = 0; i < s->n_swell; i++) {
        const sea_swell *sw = &s->swell[i];
        double m;
        sea_status st = swell_slope_variance(sw, kc, &m, err);
        if (st != SEA_OK)
            return st;
        /* the wrapped normal's mean of cos 2(phi - dir) */
        const double c2 = exp(-2.0 * sw->spread * sw->spread);
        out->xx += 0.5 * m * (1.0 + c2 * cos(2.0 * sw->dir));
        out->yy += 0.5 * m * (1.0 - c2 * cos(2.0 * sw->dir));
        out->xy += 0.5 * m * c2 * sin(2.0 * sw->dir);
    }
    return SEA_OK;
}
