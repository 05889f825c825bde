/* indep.h - independent implementations of the formulas the tests judge the
 * model by: the Fresnel reflectance of an absorbing medium, Smith's
 * shadowing, the effective emissivity (Eq 7) and reflectivity (Eq 13) of a
 * Gaussian slope distribution.  Written from the textbook forms, in their
 * own arithmetic, and sharing no code with src/: the Monte Carlo ray tracer
 * (tests/mc.c) takes its Fresnel from here, and the unit tests compare the
 * library's results with these (tests/test_mc.c, tests/test_render.c).
 * Angles in radians; N = n + i k with n > 0, k >= 0.  Slow (adaptive GSL
 * quadrature, about 1 ms an emissivity) and accurate to about 1e-10. */
#ifndef SEA_TEST_INDEP_H
#define SEA_TEST_INDEP_H

#include <complex.h>

/* Born & Wolf's u, v (Principles of Optics, 7th ed., section 14.4.1): the
 * real and imaginary parts of w = sqrt(N^2 - sin^2 psi), Im w >= 0, from
 * u^2 - v^2 = n^2 - k^2 - sin^2 psi and u v = n k, in real arithmetic. */
void indep_fresnel_uv(double cos_psi, double n, double k, double *u, double *v);

/* Unpolarised Fresnel reflectance (|r_s|^2 + |r_p|^2) / 2 at local incidence
 * psi, cos_psi in [0, 1], in Born & Wolf's real form:
 *   R_s = ((cos psi - u)^2 + v^2) / ((cos psi + u)^2 + v^2)
 *   R_p = R_s ((u - sin psi tan psi)^2 + v^2) / ((u + sin psi tan psi)^2 + v^2)
 * (R_p / R_s = |w cos psi - sin^2 psi|^2 / |w cos psi + sin^2 psi|^2, an
 * identity of the amplitudes below).  1 at cos_psi = 0. */
double indep_fresnel(double cos_psi, double n, double k);

/* The complex amplitudes, in the sign convention of the ray tracer's p
 * vectors (p = k x s for the incident and the reflected wave, so that
 * r_p = -r_s at normal incidence):
 *   r_s = (cos psi - w) / (cos psi + w)
 *   r_p = -r_s (w cos psi - sin^2 psi) / (w cos psi + sin^2 psi)
 * with w = u + i v from indep_fresnel_uv.  (The second is the ratio form of
 * r_p = (N^2 cos psi - w) / (N^2 cos psi + w): multiply out with
 * w^2 = N^2 - sin^2 psi.) */
void indep_fresnel_amplitudes(double cos_psi, double complex N, double complex *rs,
                              double complex *rp);

/* Smith's Lambda (PHYSICS section 6) for a Gaussian slope along the view of
 * mean m and deviation s > 0: tan theta [s phi(z) - (mu - m) Q(z)],
 * mu = cot theta, z = (mu - m) / s.  0 at theta = 0. */
double indep_smith_lambda(double theta, double m, double s);

/* The visibility of a facet of standardised slope t = (gamma_X - m_X)/s_X
 * along the view, z = (cot theta - m_X)/s_X: 1 for Smith's shadowing (its
 * constant 1/(1 + Lambda) cancels in Eq 7), or a slope-dependent function. */
typedef double (*indep_visibility)(double z, double t);

/* Eq 7: the effective emissivity of Gaussian slopes (mean mx, my,
 * covariance cxx, cyy, cxy, positive definite) seen from (theta, phi),
 * theta in [0, pi/2): the average of 1 - rho(psi) over the seen facets
 * weighted by their projected area and vis (NULL: Smith's, 1), that is
 *   int int (1 - rho) P g vis dgX dgY / int int P g vis dgX dgY,
 * g = (cos theta - gamma_X sin theta)+, each integral adaptive (outer over
 * gamma_X to the visibility limit, inner over gamma_Y given gamma_X).  With
 * vis NULL the denominator is also checked against its closed form
 * cos theta (1 - m_X tan theta + Lambda) (Eq 10: D (1 + Lambda)): NAN when
 * they differ by more than 1e-9 relative. */
double indep_emissivity(double complex N, double mx, double my, double cxx, double cyy,
                        double cxy, double theta, double phi, indep_visibility vis);

/* Eq 13 with Smith's bistatic shadowing (Eq 14a-d, PHYSICS section 8): the
 * effective reflectivity rho~(inc; obs), per steradian of incidence, of
 * Gaussian slopes (positive definite covariance), 0 where the mirror facet
 * faces away from either direction. */
double indep_reflectivity(double complex N, double mx, double my, double cxx, double cyy,
                          double cxy, double theta_i, double phi_i, double theta_o,
                          double phi_o);

#endif
