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
