/* planck.c - black-body spectral radiance and brightness temperature. */
#include "config.h"

#include <math.h>

#include "seabake.h"
#include "internal.h"

/* SI 2019 exact constants. */
static const double SEA_H = 6.62607015e-34;  /* Planck, J s */
static const double SEA_C = 299792458.0;     /* speed of light, m/s */
static const double SEA_KB = 1.380649e-23;   /* Boltzmann, J/K */

/* L = 2 h c^2 / lambda^5 / (exp(h c / (lambda k T)) - 1); expm1 keeps the
 * Rayleigh-Jeans end accurate. */
double sea_planck_radiance(double wavelength, double temperature)
{
    const double c1 = 2.0 * SEA_H * SEA_C * SEA_C;
    const double c2 = SEA_H * SEA_C / SEA_KB;
    return c1 / pow(wavelength, 5) / expm1(c2 / (wavelength * temperature));
}

/* dL/dT = L x e^x / (e^x - 1) / T = L x / (1 - e^-x) / T, x = h c / (lambda k T). */
double sea_planck_radiance_dT(double wavelength, double temperature)
{
    const double x = SEA_H * SEA_C / (SEA_KB * wavelength * temperature);
    return sea_planck_radiance(wavelength, temperature) * x / (-expm1(-x)) / temperature;
}

/* T = (h c / (lambda k)) / ln(1 + 2 h c^2 / (lambda^5 L)). */
double sea_planck_brightness_temperature(double wavelength, double radiance)
{
    const double c1 = 2.0 * SEA_H * SEA_C * SEA_C;
    const double c2 = SEA_H * SEA_C / SEA_KB;
    return c2 / wavelength / log1p(c1 / (pow(wavelength, 5) * radiance));
}

/* L = a / expm1(b / T) with a = c1 / lambda^5 and b = c2 / lambda: what does
 * not depend on the temperature, for a caller that evaluates many. */
void sea_planck_coefficients(double wavelength, double *a, double *b)
{
    const double c1 = 2.0 * SEA_H * SEA_C * SEA_C;
    const double c2 = SEA_H * SEA_C / SEA_KB;
    *a = c1 / pow(wavelength, 5);
    *b = c2 / wavelength;
}

/* ------------------------------------------------------------ a band */

double sea_band_radiance(const sea_band *b, double temperature)
{
    double L = 0.0;
    for (size_t i = 0; i < b->n; i++)
        L += b->weight[i] * sea_planck_radiance(b->wavelength[i], temperature);
    return b->unit * L;
}

double sea_band_radiance_dT(const sea_band *b, double temperature)
{
    double d = 0.0;
    for (size_t i = 0; i < b->n; i++)
        d += b->weight[i] * sea_planck_radiance_dT(b->wavelength[i], temperature);
    return b->unit * d;
}

/* The bracket of the band's brightness temperature, K: every scene of
 * seabake lies far inside it, and a black body's band radiance is
 * increasing in T over it. */
static const double SEA_BAND_T_LO = 1.0, SEA_BAND_T_HI = 1e5;

double sea_band_temperature(const sea_band *b, double radiance)
{
    if (!(radiance > 0.0))
        return 0.0;
    if (b->n == 1)
        return sea_planck_brightness_temperature(b->wavelength[0],
                                                 radiance / (b->unit * b->weight[0]));
    /* first guess: the middle sample's temperature of the mean radiance */
    double wsum = 0.0;
    for (size_t i = 0; i < b->n; i++)
        wsum += b->weight[i];
    double T = sea_planck_brightness_temperature(b->wavelength[b->n / 2],
                                                 radiance / (b->unit * wsum));
    double lo = SEA_BAND_T_LO, hi = SEA_BAND_T_HI;
    if (!(T > lo && T < hi))
        T = 300.0;
    /* L(T) is increasing and convex in T over the bracket's useful part:
     * Newton converges quadratically; a step leaving the bracket bisects */
    for (int it = 0; it < 200; it++) {
        const double f = sea_band_radiance(b, T) - radiance;
        const double df = sea_band_radiance_dT(b, T);
        if (f > 0.0)
            hi = T;
        else
            lo = T;
        double Tn = T - f / df;
        if (!(Tn > lo && Tn < hi))
            Tn = 0.5 * (lo + hi);
        if (fabs(Tn - T) <= 1e-13 * T)
            return Tn;
        T = Tn;
    }
    return T;
}
