/* seabake.h - public interface of libseabake, the physics of an infrared,
 * wind-roughened sea surface at any resolution (Caillault et al. 2007,
 * Applied Optics 46, 5471).  Formulas are written out in seabake-model(7); the
 * equation numbers (Eq N) below are the paper's.  Compile and link with
 * `pkg-config --cflags --libs seabake`; examples/emissivity.c (installed in
 * share/seabake/examples) is a short program that uses it.  The bake
 * directory that `seabake bake` writes is <seabake/bakedir.h>'s
 * (examples/bake.c writes one).
 *
 * Conventions.  SI units and radians everywhere; units appear in names only
 * at the edges.  Axes: x along the wind axis of the spectrum frame rotated by
 * the wind direction (see sea_spectrum), z up.  A direction (theta, phi) is
 * u = (sin theta cos phi, sin theta sin phi, cos theta) and points AWAY from
 * the surface (towards the sensor for an observation, towards the source for
 * an incidence).  Functions take theta in [0, pi/2); signed zenith angles of
 * the paper are folded with sea_dir_fold() at the API boundary.  Slopes are
 * gamma = (dz/dx, dz/dy).
 *
 * Ownership.  The caller owns whatever a call returns or fills, except
 * where the call says "owned by":
 *  - an object returned through a pointer-to-pointer (sea_water, sea_optics,
 *    sea_waves, sea_view) is released with its _free(), which accepts
 *    NULL; on failure *out is NULL;
 *  - a struct the caller passes to be filled with allocated arrays
 *    (sea_response, sea_image, sea_bake; sea_exr_image of seabake/exr.h) is
 *    released with its _free(), which accepts NULL or a zeroed struct and
 *    leaves the struct zeroed; on failure it holds nothing to free;
 *  - "owned by X": a pointer into X, valid until X is freed, never freed by
 *    the caller; the strings of the _name() functions are static.
 * No call keeps a pointer to a caller's argument after returning (objects
 * copy what they need), and none prints or exits.
 *
 * Threads.  Each call is marked with one of:
 *  - "pure": depends only on its arguments and writes only its outputs;
 *    any number of threads may call it at once;
 *  - "thread-safe": the same, though it also allocates or reads files;
 *  - "reads X": X is only read, so any number of threads may share one X:
 *    plan once (_alloc, _create, _prepare), execute from many threads;
 *  - "fills X": writes the caller's X; calls from several threads are safe
 *    as long as each fills its own X.
 * Every call that takes a sea_error writes it: one per thread.  An object
 * must not be freed while another thread uses it.  The library keeps no
 * mutable global state, but three process-wide things affect it:
 *  - GSL's error handler, which by default aborts the process.  sea_init()
 *    turns it off; call it once, first in main(), before starting threads
 *    (it is not thread-safe).  Without it, a failing quadrature or GSL
 *    allocation aborts instead of returning SEA_ERR_NUMERIC or
 *    SEA_ERR_NOMEM.  A program that installs its own GSL handler afterwards
 *    must keep one that returns.
 *  - FFTW's planner, which is not thread-safe.  FFT wave plans
 *    (SEA_WAVES_FFT, and a scene's one-meter method) plan their transforms
 *    in sea_waves_alloc (so sea_view_alloc) and destroy them in
 *    sea_waves_free, a camera in its creation and free, under a lock of the
 *    library's own; sampling only executes them, without the lock.  A
 *    program that also plans FFTW transforms in other threads at the same
 *    time must first call fftw_make_planner_thread_safe().
 *  - OpenMP.  sea_waves_alloc (FFT plans), sea_waves_sample,
 *    sea_waves_facets, sea_view_alloc, sea_view_render_frame and
 *    sea_bake_frame spread their work over OpenMP threads (OMP_NUM_THREADS,
 *    omp_set_num_threads()); their results do not depend on the number.
 *    Inside the caller's own parallel region they run on one thread unless
 *    nested parallelism is on; concurrent calls from several threads each
 *    start a team of their own.
 * Text files (sea_scene_load, sea_water_load, sea_response_load) are read
 * with strtod(), which follows LC_NUMERIC: it must have a decimal point
 * (the "C" locale, which a program has until it calls setlocale()).
 *
 * Errors.  A function that is total on its documented domain returns its
 * value.  Anything that can fail returns a sea_status and, when err is not
 * NULL, a message naming what was wrong and the allowed range. */
#ifndef SEABAKE_H
#define SEABAKE_H

#include <complex.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ status */

typedef enum {
    SEA_OK = 0,
    SEA_ERR_DOMAIN,   /* an argument outside its documented range */
    SEA_ERR_PARSE,    /* malformed input text (table, list, number) */
    SEA_ERR_IO,       /* a file could not be read or written */
    SEA_ERR_NOMEM,    /* an allocation failed */
    SEA_ERR_NUMERIC,  /* a quadrature or root finder did not converge */
    SEA_ERR_CANCELLED /* the caller's progress function asked to stop */
} sea_status;

enum { SEA_ERROR_MSG_MAX = 512 };

typedef struct {
    char msg[SEA_ERROR_MSG_MAX];
} sea_error;

/* Writes a printf-style message into err (if err is not NULL) and returns
 * status, so that callers can write `return sea_fail(err, SEA_ERR_DOMAIN, ...)`.
 * Fills err. */
sea_status sea_fail(sea_error *err, sea_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* A short description of status ("value out of range").  Pure; static string. */
const char *sea_status_name(sea_status status);

/* Library start-up: turns GSL's abort-on-error handler off (statuses are
 * checked instead).  Call once, first in main(), before starting threads.
 * Not thread-safe: it sets GSL's process-wide handler (see Threads above);
 * calling it again is harmless. */
void sea_init(void);

/* -------------------------------------------------------------- geometry */

typedef struct {
    double x, y;
} sea_vec2;

/* Symmetric 2x2 slope covariance [[xx, xy], [xy, yy]]. */
typedef struct {
    double xx, yy, xy;
} sea_cov2;

/* Gaussian slope statistics of one facet: mean m and covariance C (Eq 5). */
typedef struct {
    sea_vec2 mean;
    sea_cov2 cov;
} sea_slope_stats;

/* A direction above the surface, theta in [0, pi/2), phi any real. */
typedef struct {
    double theta, phi;
} sea_dir;

/* Folds a signed zenith angle (paper convention, theta in (-pi/2, pi/2)):
 * (-theta, phi) is the direction (theta, phi + pi).  phi is returned in
 * [0, 2 pi).  Pure. */
sea_dir sea_dir_fold(double theta_signed, double phi);

/* Checks that stats are finite, the covariance positive semi-definite
 * (xx >= 0, yy >= 0, xy^2 <= xx yy within 1e-12 relative) and |mean| finite.
 * Pure. */
sea_status sea_slope_stats_check(const sea_slope_stats *st, sea_error *err);

/* Mean m_X and standard deviation s_X of the slope component along azimuth
 * phi (Eq 6, 8): m_X = mx cos phi + my sin phi,
 * s_X^2 = xx cos^2 + 2 xy sin cos + yy sin^2.  Pure. */
void sea_slope_project(const sea_slope_stats *st, double phi, double *m_X, double *s_X);

/* ---------------------------------------------------- water, Fresnel, Planck */

typedef enum {
    SEA_WATER_FILE = -1,       /* not a table: a scene's water from a CSV file
                                  (sea_scene.water_file); sea_water_alloc refuses it */
    SEA_WATER_HALE_QUERRY = 0, /* Hale & Querry 1973, 25 C, 2.4-15.5 um (default) */
    SEA_WATER_SEGELSTEIN       /* Segelstein 1981, 2.41-15.6 um */
} sea_water_table;

/* Sea-water optical constants: a pure-water table n(lambda), k(lambda) plus
 * the Pinkley & Williams (1976) sea-water correction scaled linearly with
 * salinity (zero salinity: pure water).  Interpolation is linear in
 * wavenumber between table rows. */
typedef struct sea_water sea_water;

/* Allowed salinity, g/kg (the densest open ocean is about 41). */
#define SEA_SALINITY_MAX 45.0
/* salinity in g/kg, [0, SEA_SALINITY_MAX].  With salinity > 0 the usable band is the
 * intersection of the table and the correction (2.398-15.62 um).  Thread-safe; *out is
 * the caller's, freed with sea_water_free(), and read-only: share it between threads. */
sea_status sea_water_alloc(sea_water_table table, double salinity, sea_water **out,
                           sea_error *err);
/* The optical constants a water table (or --index) may give: liquid water
 * over 2.4-15.6 um spans n 1.09-1.48, k 0.001-0.42 (both shipped tables);
 * these bounds refuse what no water is (n < 1 gives emissivities near 0 at
 * grazing angles; a huge n or k overflows Fresnel's N^2) with room for any
 * measurement. */
#define SEA_WATER_N_MIN 1.0
#define SEA_WATER_N_MAX 3.0
#define SEA_WATER_K_MAX 10.0
/* A user table: CSV text with '#' comment lines, a header row naming the
 * columns wavelength_um,n,k and at least two rows in strictly monotonic
 * wavelength order; n in [SEA_WATER_N_MIN, SEA_WATER_N_MAX], k in [0,
 * SEA_WATER_K_MAX] (SEA_ERR_DOMAIN naming the file, line and column), and
 * so with the sea-water correction added at salinity > 0 (SEA_ERR_DOMAIN
 * naming the salinity and wavelength).
 * Thread-safe (reads the file; LC_NUMERIC, see Threads); *out as with
 * sea_water_alloc. */
sea_status sea_water_load(const char *path, double salinity, sea_water **out,
                          sea_error *err);
void sea_water_free(sea_water *w);
/* Complex refractive index N = n + i k at wavelength (m).  Fails with
 * SEA_ERR_DOMAIN outside the table, naming the range.  Reads w. */
sea_status sea_water_index(const sea_water *w, double wavelength, double complex *N,
                           sea_error *err);
/* Usable wavelength range, metres.  Reads w. */
void sea_water_range(const sea_water *w, double *wl_min, double *wl_max);
/* One line naming the table, its publication and the salinity.  Reads w;
 * the string is owned by w. */
const char *sea_water_describe(const sea_water *w);
/* Name of a built-in table ("hale-querry", "segelstein"); returns -1 when
 * the name is not a built-in table.  Pure. */
int sea_water_table_from_name(const char *name);

/* Fresnel and Planck: pure. */

/* Unpolarised Fresnel reflectance of air -> water (complex index N, k >= 0)
 * at local incidence psi, cos_psi in [0, 1]:
 * w = sqrt(N^2 - sin^2 psi), r_s = (cos psi - w)/(cos psi + w),
 * r_p = (N^2 cos psi - w)/(N^2 cos psi + w), rho = (|r_s|^2 + |r_p|^2)/2.
 * rho(0 incidence) = ((n-1)^2 + k^2)/((n+1)^2 + k^2); rho(grazing) = 1. */
double sea_fresnel_unpolarized(double cos_psi, double complex N);

/* Planck spectral radiance, W m^-2 sr^-1 m^-1, wavelength in m, T in K (> 0). */
double sea_planck_radiance(double wavelength, double temperature);
/* Its derivative with respect to temperature, W m^-2 sr^-1 m^-1 K^-1. */
double sea_planck_radiance_dT(double wavelength, double temperature);
/* Its inverse: brightness temperature (K) of a spectral radiance > 0. */
double sea_planck_brightness_temperature(double wavelength, double radiance);

/* A band as an image measures it: n >= 1 spectral samples at wavelength[i]
 * (m, > 0) with weights weight[i] (>= 0, not all 0: a band's quadrature
 * weight times the response, m, or 1 for one wavelength), and unit, the
 * image's radiance unit per SI unit (1e-6 for one wavelength, whose images
 * are per um; 1 for a band, in-band W m^-2 sr^-1).  sea_view_band gives
 * a render's.  The arrays are the caller's (no call keeps them). */
typedef struct {
    size_t n;
    const double *wavelength;
    const double *weight;
    double unit;
} sea_band;
/* The band's radiance of a black body at T (K, > 0) in the image's units,
 * L(T) = unit sum_i weight[i] B(wavelength[i], T), and its derivative
 * dL/dT (per K).  Pure. */
double sea_band_radiance(const sea_band *b, double temperature);
double sea_band_radiance_dT(const sea_band *b, double temperature);
/* The brightness temperature of a radiance L in the image's units: the T
 * with sea_band_radiance(b, T) = L, to 1e-12 relative (Newton's method,
 * safeguarded by bisection over [1, 1e5] K; the closed form for one
 * sample); 0 for L <= 0 or NaN, which no temperature gives.  Pure. */
double sea_band_temperature(const sea_band *b, double radiance);

/* ------------------------------------------------ Elfouhaily 1997 spectrum */

/* A swell (seabake-model(7), SWELL): waves from a distant storm, added to
 * the wind sea.  A JONSWAP frequency spectrum (Hasselmann et al. 1973) of
 * peak period tp and peak enhancement gamma, peak widths 0.07 below the peak
 * and 0.09 above, on the band [0.4, 3] times the peak frequency (below, the
 * shape is under e^-48 of its peak; above, the f^-5 tail would give a slope
 * variance that grows with the log of any cut, and the wind sea holds those
 * waves), scaled so that 4 sqrt(m0) = hs; deep-water waves, omega^2 = g k;
 * a wrapped normal distribution of directions of width `spread` around the
 * azimuth `dir` the swell travels toward. */
typedef struct {
    double hs;     /* significant height 4 sqrt(m0), m, [SEA_SWELL_HS_MIN, SEA_SWELL_HS_MAX] */
    double tp;     /* peak period, s, [SEA_SWELL_TP_MIN, SEA_SWELL_TP_MAX] */
    double dir;    /* rad, azimuth the swell travels toward (from the x axis), finite */
    double spread; /* rad, the directions' standard deviation, [SEA_SWELL_SPREAD_MIN_DEG,
                      SEA_SWELL_SPREAD_MAX_DEG] deg */
    double gamma;  /* JONSWAP peak enhancement, [1, 10] (3.3: the JONSWAP mean) */
    /* derived by sea_spectrum_add_swell */
    double omega_p; /* peak angular frequency 2 pi / tp, rad/s */
    double alpha;   /* the shape's scale: 4 sqrt(m0) = hs */
} sea_swell;

#define SEA_SWELL_MAX 4
#define SEA_SWELL_HS_MIN 0.01
#define SEA_SWELL_HS_MAX 20.0
#define SEA_SWELL_TP_MIN 3.0
#define SEA_SWELL_TP_MAX 30.0
#define SEA_SWELL_SPREAD_MIN_DEG 1.0
#define SEA_SWELL_SPREAD_MAX_DEG 60.0
#define SEA_SWELL_GAMMA_MIN 1.0
#define SEA_SWELL_GAMMA_MAX 10.0
/* The swell's band in frequency, in units of its peak frequency. */
#define SEA_SWELL_BAND_LO 0.4
#define SEA_SWELL_BAND_HI 3.0

/* Sea state and the derived constants of the Elfouhaily et al. (1997)
 * directional spectrum, as written out in seabake-model(7), THE SEA SPECTRUM,
 * and the swells added to it (none after sea_spectrum_init).
 * A plain struct: nothing to free. */
typedef struct {
    double wind_speed; /* U10, m/s */
    double fetch;      /* m; INFINITY = fully developed */
    double wind_dir;   /* rad: azimuth of the wind axis from the x axis */
    /* derived by sea_spectrum_init */
    double k0;        /* g / U10^2 */
    double omega_c;   /* inverse wave age */
    double k_p;       /* spectral peak, rad/m */
    double c_p;       /* phase speed at the peak, m/s */
    double u_star;    /* friction velocity, m/s */
    double alpha_p;   /* long-wave (equilibrium range) parameter */
    double alpha_m;   /* short-wave parameter, with the low-wind continuation */
    double gamma;     /* JONSWAP peak enhancement */
    double delta;     /* JONSWAP peak width */
    int n_swell;      /* swells added by sea_spectrum_add_swell, 0..SEA_SWELL_MAX */
    sea_swell swell[SEA_SWELL_MAX];
} sea_spectrum;

/* Allowed ranges: wind_speed in [SEA_WIND_MIN, SEA_WIND_MAX] m/s, fetch in
 * [SEA_FETCH_MIN, inf] m, wind_dir finite. */
#define SEA_WIND_MIN 0.5
#define SEA_WIND_MAX 40.0
#define SEA_FETCH_MIN 1000.0
/* Fills s: the wind sea alone. */
sea_status sea_spectrum_init(double wind_speed, double fetch, double wind_dir,
                             sea_spectrum *s, sea_error *err);
/* Adds a swell of hs, tp, dir, spread, gamma (the rest of *sw is derived)
 * to s.  SEA_ERR_DOMAIN for a value outside its range (messages name it)
 * or a swell beyond SEA_SWELL_MAX; SEA_ERR_NUMERIC if the normalising
 * integral fails.  Every function below counts the swells, except where
 * it says "the wind sea's". */
sea_status sea_spectrum_add_swell(sea_spectrum *s, const sea_swell *sw, sea_error *err);
/* The swell's curvature spectrum k^3 S(k) (0 outside its band) and its
 * directions' density D(phi) over phi in radians, integrating to 1 over a
 * turn (the wrapped normal of standard deviation spread around dir).
 * Pure, after sea_spectrum_add_swell derived sw. */
double sea_swell_curvature(const sea_swell *sw, double k);
double sea_swell_direction_density(const sea_swell *sw, double phi);
/* The wavenumber band [k_lo, k_hi] of a swell, rad/m. */
void sea_swell_band(const sea_swell *sw, double *k_lo, double *k_hi);
/* The lowest wavenumber that holds any of the sea's waves, rad/m: k_p/40
 * for the wind sea, lower for a long swell. */
double sea_spectrum_k_low(const sea_spectrum *s);

/* The spectrum's formulas, sea_spectrum_alpha_m to sea_spectrum_omega, are pure. */

/* Short-wave coefficient alpha_m(x), x = u_star / c_m.  Elfouhaily's 1997 formula,
 * 1e-2 (1 + ln x) for x = u_star / c_m <= 1 and 1e-2 (1 + 3 ln x) above, turns
 * negative for x < 1/e (U10 below 2.74 m/s, fully developed).  Below ln x =
 * -0.9 (U10 = 2.98 m/s) it is continued by 1e-2 (1/10) exp(10 (ln x + 0.9))
 * = 1e-3 e^9 x^10, which matches value and slope at the junction and stays
 * positive; from ln x = -0.9 upwards the 1997 formula is used unchanged. */
double sea_spectrum_alpha_m(double u_star_over_c_m);
/* 1 when s uses that low-wind continuation instead of the 1997 formula
 * (u_star / c_m < exp(-0.9)), 0 otherwise. */
int sea_spectrum_alpha_m_continued(const sea_spectrum *s);
/* The wind sea's curvature spectrum B(k) = k^3 S(k) = B_l + B_h
 * (dimensionless), k > 0. */
double sea_spectrum_curvature(const sea_spectrum *s, double k);
/* The wind sea's omnidirectional height spectrum S(k) = B(k)/k^3, m^3. */
double sea_spectrum_omni(const sea_spectrum *s, double k);
/* The wind sea's spreading Delta(k) in [0, 1): Phi(k, phi) = (1 + Delta cos 2 phi) / (2 pi). */
double sea_spectrum_spreading(const sea_spectrum *s, double k);
/* Directional height spectrum Psi(k, phi) = S(k) Phi(k, phi - wind_dir) / k,
 * m^4, phi the azimuth of the wave vector in the x, y frame, plus every
 * swell's S_i(k) D_i(phi) / k. */
double sea_spectrum_directional(const sea_spectrum *s, double k, double phi);
/* The swells' share of it, sum of S_i(k) D_i(phi) / k (0 without swell). */
double sea_spectrum_directional_swell(const sea_spectrum *s, double k, double phi);
/* Angular frequency with capillarity, omega = sqrt(g k (1 + (k/k_m)^2)). */
double sea_spectrum_omega(double k);

/* Relative accuracy to which slope variances are integrated. */
#define SEA_SPECTRUM_REL_TOL 1e-8
/* Slope covariance of the waves with |k| >= kc (Eq 15, 17) in the x, y frame:
 * along the wind sigma_u^2 = int_kc^inf B(k)/k (1 + Delta/2)/2 dk, across it
 * sigma_c^2 = int B/k (1 - Delta/2)/2 dk, then rotated by wind_dir; each
 * swell adds m = int_kc^inf B_i(k)/k dk times (1 + c cos 2 dir, 1 - c cos 2 dir,
 * c sin 2 dir)/2 to (xx, yy, xy), c = exp(-2 spread^2) (the wrapped normal's
 * mean of cos 2 (phi - dir)).
 * kc = 0 gives the low-resolution (total) covariance; kc = pi/L the part
 * below a facet of size L.  kc >= 0, finite.  Thread-safe (a GSL workspace
 * per call); SEA_ERR_NUMERIC if the quadrature fails, given sea_init(). */
sea_status sea_spectrum_slope_cov(const sea_spectrum *s, double kc, sea_cov2 *out,
                                  sea_error *err);

/* ------------------------------------------------------- Smith shadowing */

/* Every function of this section is pure. */

/* G(t) = phi(t) - t Q(t) = int_t^inf Q(u) du, with phi the standard normal
 * density and Q its upper tail.  Positive, decreasing, G(t) - G(-t) = -t.
 * Evaluated without cancellation for every t (continued fraction for t > 3). */
double sea_shadow_G(double t);
/* For a slope gamma ~ N(m, s^2) and a threshold mu = cot(theta):
 * hidden  = E[(gamma - mu)+] = s G((mu - m)/s)   (facets turned away),
 * visible = E[(mu - gamma)+] = s G((m - mu)/s),
 * visible - hidden = mu - m.  s >= 0 (s = 0: the limits). */
double sea_shadow_hidden(double mu, double m, double s);
double sea_shadow_visible(double mu, double m, double s);
/* Smith Lambda with a non-zero mean (Eq 9e): Lambda = tan(theta) * hidden.
 * theta in [0, pi/2); 0 at nadir, finite, >= 0, increasing with theta. */
double sea_shadow_lambda(double theta, double m, double s);
/* Normalisation D of Eq 10: D = 1 - m tan(theta) / (1 + Lambda)
 *                             = tan(theta) visible / (1 + Lambda).
 * D >= 0; D = 1 for m = 0; D > 1 when the mean slope faces the viewer (m < 0). */
double sea_shadow_D(double theta, double m, double s);
/* Correlated shadowing (an addition; seabake-model(7), SHADOWING): Smith's
 * hazard taken under the law of the heights and slopes ahead conditioned
 * on the facet's own slope (Bourlier, Saillard and Berginc 2000), for a
 * profile with Gaussian correlation.  z = (cot theta - m_X)/s_X, t =
 * (gamma_X - m_X)/s_X the facet's standardised slope along the view;
 * returns C(z, t) = S(t) (1 + Lambda), the probability that a facet of
 * slope t is seen relative to Smith's 1/(1 + Lambda): above 1 for facets
 * turned toward the sensor, about 0.55 for facets grazing the ray.  0 for
 * t >= z.  The _exact form integrates (about 1 ms); sea_shadow_correlated
 * interpolates its table (z clamped to [0.01, 6]: 1 above 6; within
 * 4e-4 of the exact form where facets are seen, tests/test_shadow.c). */
double sea_shadow_correlated_exact(double z, double t);
double sea_shadow_correlated(double z, double t);

/* ------------------------------------------- effective emissivity (Eq 7, 12) */

typedef enum {
    SEA_EMIS_AUTO = 0, /* Eq 7, product Gauss rule sized from the slope spreads (default) */
    SEA_EMIS_FAST,     /* Eq 12: psi' with gamma_Y = m_Y, 1-D Gauss-Legendre */
    SEA_EMIS_FULL      /* Eq 7 by nested adaptive GSL quadrature (reference) */
} sea_emis_method;

/* Parses "auto", "fast", "full"; returns -1 otherwise.  Pure. */
int sea_emis_method_from_name(const char *name);
/* The name of m, as parsed above.  Pure; static string. */
const char *sea_emis_method_name(sea_emis_method m);

/* A fixed product rule for the emissivity average: n_gl Gauss-Legendre
 * nodes in gamma_X across the projected-area weight, cut at 6 standard
 * deviations and at the visibility limit, times n_gh Gauss-Hermite nodes
 * over gamma_Y given gamma_X (Eq 7); n_gh = 0 puts gamma_Y = m_Y in psi
 * instead (Eq 11-12).  Orders 1..SEA_EMIS_GL_MAX and 0..SEA_EMIS_GH_MAX. */
enum { SEA_EMIS_GL_MAX = 128, SEA_EMIS_GH_MAX = 16 };
typedef struct {
    int n_gl, n_gh;
} sea_emis_rule;

/* The quadrature plan: node tables built once, read by many threads.
 * sea_optics_alloc is thread-safe; *out is the caller's, freed with
 * sea_optics_free(); every other call only reads it. */
typedef struct sea_optics sea_optics;
sea_status sea_optics_alloc(sea_optics **out, sea_error *err);
void sea_optics_free(sea_optics *p);

/* Which single-bounce shadowing weighs the facets the sensor sees in the
 * emissivity (and so in the sky the sea reflects, 1 - emissivity, and in
 * the second hits of reflections >= 2): Smith's, independent of the
 * facet's slope (the paper, Eq 9c-9e), or the correlated function above
 * (sea_shadow_correlated, a plan's default as the default model's), which
 * ray-traced Gaussian surfaces follow to 1e-3 at 85 degrees where Smith's
 * is 12e-3 low (seabake-model(7), SHADOWING).  The reflectivity toward the
 * sun keeps Eq 14c's bistatic Smith factor. */
typedef enum {
    SEA_SHADOW_SMITH = 0,
    SEA_SHADOW_CORRELATED
} sea_shadowing;
/* Sets it before p is shared between threads. */
void sea_optics_set_shadowing(sea_optics *p, sea_shadowing s);
sea_shadowing sea_optics_shadowing(const sea_optics *p);
/* Parses "smith", "correlated"; -1 otherwise.  Pure. */
int sea_shadowing_from_name(const char *name);
/* Its name; static string.  Pure. */
const char *sea_shadowing_name(sea_shadowing s);

/* Effective emissivity toward v (Eq 7 or Eq 12, normalised by D).  It is the
 * average of 1 - rho(psi) over the facets seen from v, weighted by their
 * projected area: a value in [0, 1].  N: complex index; st must satisfy
 * sea_slope_stats_check.  Returns SEA_ERR_NUMERIC only if the adaptive
 * reference quadrature fails to converge (given sea_init()).  Reads p:
 * plan once, call from many threads (SEA_EMIS_FULL allocates its GSL
 * workspaces per call). */
sea_status sea_emissivity(const sea_optics *p, sea_emis_method method, double complex N,
                          const sea_slope_stats *st, sea_dir v, double *out,
                          sea_error *err);

/* The rule SEA_EMIS_AUTO uses for st seen from v.  With s_X the spread of
 * gamma_X along the view azimuth and s the spread of gamma_Y given gamma_X:
 *     n_gl = ceil(17 + 12 s_X),  n_gh = ceil(2 + 8 s + 20 s^2),
 * each capped at its maximum.  The view angle enters through the window
 * (cut at the visibility limit), not the orders.  Fitted so that the
 * default is within 1e-6 of SEA_EMIS_FULL, with either shadowing, for
 * theta <= 85 deg, |m| <= 2 and slope variances 1e-5..1 with correlation
 * and anisotropy to 20:1 (measured: at most 6.8e-7 over the bench's 896
 * conditions and 9000 random ones, tests/emis_rule_check; tests/test_optics.c
 * checks 800).
 * st must satisfy sea_slope_stats_check and theta be in [0, pi/2).  Pure. */
sea_emis_rule sea_emissivity_auto_rule(const sea_slope_stats *st, sea_dir v);
/* The rule's coefficients: n_gl = ceil(A + B s_X), n_gh = ceil(C + D s + E s^2). */
#define SEA_EMIS_AUTO_GL_A 17.0
#define SEA_EMIS_AUTO_GL_B 12.0
#define SEA_EMIS_AUTO_GH_C 2.0
#define SEA_EMIS_AUTO_GH_D 8.0
#define SEA_EMIS_AUTO_GH_E 20.0

/* Emissivity toward v by the fixed product rule `rule` (Eq 7, or Eq 12 when
 * rule.n_gh = 0): in [0, 1] whatever the orders.  SEA_ERR_DOMAIN for orders
 * outside their ranges, a direction outside [0, 90) deg or invalid stats.
 * Reads p. */
sea_status sea_emissivity_rule(const sea_optics *p, sea_emis_rule rule, double complex N,
                               const sea_slope_stats *st, sea_dir v, double *out,
                               sea_error *err);

/* The emissivity toward v for n complex indices at once (the spectral
 * samples of a band): out[i] is exactly what sea_emissivity (with method)
 * or sea_emissivity_rule (with *rule, when rule is not NULL) gives for
 * N[i], bit for bit, but what does not depend on the wavelength (the view
 * frame, the nodes and weights, cos psi, the shadowing and projected-area
 * weights) is computed once: only the Fresnel sums are done n times.  A
 * SEA_EMIS_FULL method falls back to n adaptive quadratures.  Same errors;
 * reads p. */
sea_status sea_emissivity_n(const sea_optics *p, sea_emis_method method,
                            const sea_emis_rule *rule, const double complex *N, size_t n,
                            const sea_slope_stats *st, sea_dir v, double *out, sea_error *err);

/* Multiple reflections: the emissivity toward v when the mirror ray of a
 * facet may meet the surface again, up to `reflections` hits in all
 * (1..SEA_REFLECTIONS_MAX; 1 is the paper, exactly sea_emissivity_n).  With
 * R >= 2 the facet average gains rho_A P E_{R-1}, P the probability that the
 * mirror ray meets the surface (the complement of Eq 14c's bistatic Smith
 * factor) and E_{R-1} the emissivity of the facets it meets, seen from
 * below the horizon when the ray rises (seabake-model(7), MULTIPLE
 * REFLECTIONS).  The sky then sees 1 - out[i].  The facets the sensor sees
 * take the nodes reflections = 1 takes (method or rule; the auto rule for
 * SEA_EMIS_FULL), the facets met again the auto rule at 0.35 of its
 * orders (by their projected area alone, whatever the shadowing); the
 * second hits a rule split where the mirror ray is horizontal (P's kink),
 * within 1.3e-4 of its converged value; a mirror ray escapes where P < 1e-9 or
 * its node's share times P < 1e-11 (out[i] moves by less than 1e-8; the
 * closure stays exact).
 * Same errors as sea_emissivity_n, and SEA_ERR_DOMAIN for reflections out
 * of range; reads p. */
enum { SEA_REFLECTIONS_MAX = 3 };
/* reflections = auto: two hits where the second changes a pixel's
 * radiance by more than SEA_AUTO_SKIP times the tolerance, one where it
 * cannot (src/view/view.c). */
enum { SEA_REFLECTIONS_AUTO = 0 };
#define SEA_AUTO_SKIP 0.01
/* Parses "auto" (SEA_REFLECTIONS_AUTO) or a number of hits "1" .. "3";
 * -1 otherwise.  Pure. */
int sea_reflections_from_name(const char *name);
sea_status sea_emissivity_multi_n(const sea_optics *p, sea_emis_method method,
                                  const sea_emis_rule *rule, const double complex *N, size_t n,
                                  const sea_slope_stats *st, sea_dir v, int reflections,
                                  double *out, sea_error *err);

/* Two scales (an addition; seabake-model(7), TWO SCALES): the sea's slopes
 * split into a resolved band of covariance res, carrying facets, and the
 * sub-facet band sub (sub->mean the facets' mean slope, sub->cov on each
 * facet).  The facets, slopes m ~ N(sub->mean, res), count by their
 * projected area 1 - m_X tan(theta) times, with correlated shadowing, the
 * chance sea_shadow_correlated gives them under the resolved band; each
 * shows its own eps~ (sea_emissivity, SEA_EMIS_AUTO, mean m, cov sub->cov).
 * Against ray-traced sea-spectrum surfaces split at half their slope
 * variance: within 1.5e-3 to 82 degrees and 4.6e-3 at 85 (the one scale:
 * 8e-3 and 20e-3 low).  res = 0 is sea_emissivity.  192 evaluations of
 * sea_emissivity (about 0.3 ms).  SEA_ERR_DOMAIN for a res that is no
 * covariance or v outside [0, pi/2), and as sea_emissivity; reads p. */
sea_status sea_emissivity_two_scale(const sea_optics *p, double complex N,
                                    const sea_slope_stats *sub, sea_cov2 res, sea_dir v,
                                    double *out, sea_error *err);
/* The wavenumber k_half that splits the slope variance (trace) of the
 * waves with |k| >= kc in halves, and the two bands' covariances: res of
 * kc <= |k| < k_half, sub of |k| >= k_half.  kc >= 0, finite. */
sea_status sea_spectrum_split_half(const sea_spectrum *s, double kc, double *k_half,
                                   sea_cov2 *res, sea_cov2 *sub, sea_error *err);
/* The same split at any share: the wavenumber k_split where the slope
 * variance (trace) of the waves with kc <= |k| < k_split is `resolved`, and
 * the two bands' covariances.  sea_spectrum_split_half is this with half
 * of the trace of |k| >= kc; a sea that lacks some of the spectrum's short
 * waves (the ray tracer's surfaces, tests/test_mc.c) splits its own
 * variance with it.  SEA_ERR_DOMAIN unless kc >= 0 is finite and 0 <
 * resolved < that trace. */
sea_status sea_spectrum_split_at(const sea_spectrum *s, double kc, double resolved,
                                 double *k_split, sea_cov2 *res, sea_cov2 *sub, sea_error *err);

/* What two scales add to a facet's one-scale emissivity, tabulated per
 * scene for the indices N[0..n) (twoscale.c says how: on the facet's
 * standardised visibility margin along the view, the share of the resolved
 * band its covariance holds, the view's azimuth to the wind and zenith).
 * split_sub: the covariance of the waves shorter than the split
 * (sea_spectrum_split_half's sub), total: the low-resolution covariance;
 * both in the x, y frame, wind_dir the wind's azimuth.  _alloc computes
 * nothing: a row of the table is computed when a query first needs it, by
 * one thread while the others wait.  p must outlive the table.
 * SEA_ERR_DOMAIN unless 0 < tr split_sub < tr total and the n (1 to
 * SEA_SCENE_BAND_MAX) indices are finite. */
typedef struct sea_two_scale_table sea_two_scale_table;
sea_status sea_two_scale_table_alloc(const sea_optics *p, const double complex *N, size_t n,
                                     sea_cov2 split_sub, sea_cov2 total, double wind_dir,
                                     sea_two_scale_table **out, sea_error *err);
/* The addition out[k] for a facet of slope statistics st seen from v,
 * interpolated (Catmull-Rom in every axis), or computed directly where the
 * facet's mean plane faces away from v; 0 for a facet no larger than the
 * split.  Thread-safe; SEA_ERR_NUMERIC if an emissivity fails (then out is
 * 0). */
sea_status sea_two_scale_delta(sea_two_scale_table *t, sea_dir v, const sea_slope_stats *st,
                               double *out, sea_error *err);
/* The same by quadrature at the facet's own statistics (sea_emissivity_two_scale's
 * orders, 24 x 8): the reference the table is checked against.  Reads t. */
sea_status sea_two_scale_delta_exact(const sea_two_scale_table *t, sea_dir v,
                                     const sea_slope_stats *st, double *out, sea_error *err);
/* The same quadrature at the table's orders (12 x 4, within 1e-4 of the
 * exact form: tests/test_mc.c), with no interpolation: what a tolerance
 * finer than the table's own error asks (sea_model_emissivity).  Reads t. */
sea_status sea_two_scale_delta_direct(const sea_two_scale_table *t, sea_dir v,
                                      const sea_slope_stats *st, double *out, sea_error *err);
/* What two scales add to a facet's one-hit Stokes e_Q and e_U (q[k],
 * u[k]; the facets' Stokes emissivities averaged as the emissivity's,
 * sea_polar_emissivity_two_scale, against the one scale): how = 0 from
 * the table's own polarisation part (its cells made as queries first
 * need them, on the same axes but the azimuth over 180 deg, 6 nodes read
 * trigonometrically, and m_Y at -0.4, 0 and 0.4: U changes sign with the
 * view's mirror image), 1 by the quadrature at the
 * table's orders, 2 at the reference's.  Thread-safe; errors as
 * sea_two_scale_delta's. */
sea_status sea_two_scale_polar_delta(sea_two_scale_table *t, sea_dir v, const sea_slope_stats *st,
                                     int how, double *q, double *u, sea_error *err);
/* Rows of the table computed so far.  Thread-safe. */
size_t sea_two_scale_table_rows(const sea_two_scale_table *t);
void sea_two_scale_table_free(sea_two_scale_table *t);

/* The sky's radiance as a function of the zenith angle (Eq 22 instead of
 * the isotropic Eq 23).  isotropic: radiance[k] everywhere; clear:
 * L(theta) = [1 - (1 - eps_z)^(1 / cos theta)] radiance[k], radiance[k] the
 * air's blackbody radiance B(lambda_k, T_air), and B(T_air) at and below
 * the horizon.  Indexed as the N[] of the calls below. */
typedef enum { SEA_SKY_ISOTROPIC = 0, SEA_SKY_CLEAR = 1, SEA_SKY_TABLE = 2 } sea_sky_model;
typedef struct {
    sea_sky_model model;
    double zenith_emissivity; /* clear: eps_z, (0, 1] */
    const double *radiance;   /* per index: the sky's (isotropic) or B(T_air) (clear);
                                 table: the profile, n_zenith values per index */
    size_t n_zenith;          /* table: its zenith angles, radians, increasing from 0 to */
    const double *zenith;     /* pi/2 (at and below the horizon: the last value) */
} sea_sky;
/* L_sky of index k toward a direction of zenith cosine cos_zenith.  Pure. */
double sea_sky_radiance(const sea_sky *sky, size_t k, double cos_zenith);
/* The emissivity toward v (as sea_emissivity_multi_n, out eps[i]) and the
 * sky's radiance reflected toward v, sky_out[i] = E_w[rho L_sky(r)] over
 * the facets seen, r each facet's mirror ray (the sky at the horizon where
 * r falls), with reflections >= 2 the share of r that meets the sea again
 * followed to the facets it meets.  Under a uniform sky of radiance L,
 * eps[i] L_sea + sky_out[i] adds up to L when L_sea = L, at every number of
 * reflections (the isothermal closure).  SEA_ERR_DOMAIN for a sky model
 * or eps_z out of range, and as sea_emissivity_multi_n; reads p. */
sea_status sea_emissivity_sky_n(const sea_optics *p, sea_emis_method method,
                                const sea_emis_rule *rule, const double complex *N, size_t n,
                                const sea_slope_stats *st, sea_dir v, int reflections,
                                const sea_sky *sky, double *eps, double *sky_out, sea_error *err);

/* The sea around a facet, for multiple reflections (seabake-model(7),
 * MULTIPLE REFLECTIONS): a mirror ray meets again the facets of the sea as a
 * whole, of low-resolution statistics lr (m = 0, C_LR), whatever the facet
 * it left, with the chance Eq 14c's bistatic factor gives under lr.  What
 * the second hit reads is then a function of the mirror ray's direction,
 * tabulated here once for the indices N[0..n) (the scene's samples), with
 * `reflections` hits in all (2..SEA_REFLECTIONS_MAX) and, when sky is not
 * NULL, the sky the facets met reflect (sky must outlive the table);
 * exact: no table, every read evaluated at its direction (the reference).
 * p must outlive it.  SEA_ERR_DOMAIN for invalid stats or reflections. */
typedef struct sea_around sea_around;
sea_status sea_around_alloc(const sea_optics *p, const sea_slope_stats *lr,
                            const double complex *N, size_t n, int reflections, const sea_sky *sky,
                            int exact, sea_around **out, sea_error *err);
void sea_around_free(sea_around *ar);
void sea_around_set_orders(sea_around *ar, double split_scale, double split_min,
                           double cross_scale, double cross_min);
/* sea_emissivity_multi_n (sky NULL) or sea_emissivity_sky_n for a facet of
 * statistics st in the sea around ar, with ar's reflections: the facets the
 * sensor sees are st's, the facets their mirror rays meet the sea
 * around's.  ar must have been made for these N[0..n) and with a sky iff
 * sky is not NULL (SEA_ERR_DOMAIN otherwise).  Reads p and ar. */
sea_status sea_emissivity_around_n(const sea_optics *p, sea_emis_method method,
                                   const sea_emis_rule *rule, const double complex *N, size_t n,
                                   const sea_slope_stats *st, sea_dir v, const sea_around *ar,
                                   const sea_sky *sky, double *eps, double *sky_out,
                                   sea_error *err);

/* ------------------------------------------------ the default model (model.c)
 *
 * The emissivity of a facet as the scenes, the calculators and the library
 * compute it by default (seabake-model(7), THE DEFAULT MODEL): correlated
 * shadowing, two scales, and a second surface hit where it changes the
 * result by more than SEA_AUTO_SKIP of the tolerance, in the sea around
 * (sea_around); each part only as finely as the tolerance asks.  With
 * reference = 1 every approximation is replaced by its exact form: the auto
 * rule at full orders, the second hits at converged orders with the sea
 * around evaluated at every mirror ray, two scales by quadrature at the
 * facet's own mean slope and every index, and at least two hits.  The
 * paper's model is shadowing = smith, scales = 1, reflections = 1. */
typedef struct {
    sea_shadowing shadowing; /* SEA_SHADOW_CORRELATED */
    int scales;              /* 1 or 2; 2 */
    int reflections;         /* SEA_REFLECTIONS_AUTO or 1 .. SEA_REFLECTIONS_MAX; auto */
    double tolerance;        /* relative, (0, 0.1]; 1e-3 */
    int reference;           /* 0 */
    sea_emis_method method;  /* the first hit's rule; SEA_EMIS_AUTO */
    /* reflections = auto: the relative change of the result per unit of
     * emissivity (a radiance's, for a render); 1 */
    double sensitivity;
} sea_model_params;
void sea_model_params_default(sea_model_params *mp);
typedef struct sea_model sea_model;
/* The model for the indices N[0..n) (n <= SEA_SCENE_BAND_MAX) of a sea
 * whose spectrum is given (NULL only with scales = 1) and whose low
 * resolution is lr (m = 0, C_LR: the sea around, what the mirror rays
 * meet), with facets down to the sub-facet covariance fine (NULL: lr's;
 * reflections = auto marks where a second hit may matter down to it), under
 * sky (NULL or isotropic: the sky is seen in 1 - eps, Eq 23; else
 * sea_emissivity_sky_n's).  The sky's arrays must outlive the model.
 * Builds the tables now (a few to a few tens of milliseconds), but the
 * two-scale table's rows, which it computes as queries need them.
 * SEA_ERR_DOMAIN for parameters out of range or two scales without a
 * spectrum. */
sea_status sea_model_alloc(const sea_model_params *mp, const sea_spectrum *spectrum,
                           const sea_slope_stats *lr, const sea_cov2 *fine,
                           const double complex *N, size_t n, const sea_sky *sky,
                           sea_model **out, sea_error *err);
void sea_model_free(sea_model *m);
/* The emissivity of a facet of statistics st toward v, eps[i] for N[i],
 * and with a directional sky the sky's radiance it reflects, ksky[i] (may
 * be NULL without one).  Thread-safe (the two-scale table fills its rows
 * under a lock); errors as sea_emissivity_multi_n. */
sea_status sea_model_emissivity(const sea_model *m, const sea_slope_stats *st, sea_dir v,
                                double *eps, double *ksky, sea_error *err);
/* The hits the model follows for st toward v (1 or more).  Reads m. */
int sea_model_hits(const sea_model *m, const sea_slope_stats *st, sea_dir v);
/* The polarised part of the Stokes emissivity of a facet of statistics st
 * toward v under the model, e_Q in q[i] and e_U in u[i] for N[i] (its I
 * is sea_model_emissivity's eps[i]; seabake.h POLARISATION's frame): the
 * one-hit values (sea_polar_emissivity_n, method AUTO) plus, where the
 * model follows a second hit (sea_model_hits), what the facets met send
 * back (sea_polar_emissivity_multi_n's physics, in the sea around, whose
 * polarisation tables are filled on the first call that needs them), and
 * with two scales what they add (sea_two_scale_polar_delta, read as
 * finely as the model reads the emissivity's).  Thread-safe; errors as
 * sea_model_emissivity's. */
sea_status sea_model_polarisation(const sea_model *m, const sea_slope_stats *st, sea_dir v,
                                  double *q, double *u, sea_error *err);
/* Its quadrature plan, with its shadowing (read-only). */
const sea_optics *sea_model_optics(const sea_model *m);
/* scales = 2: the wavelength 2 pi / k_half of the split, m; else 0. */
double sea_model_split_wavelength(const sea_model *m);
/* scales = 2, not the reference: the two-scale table's rows computed. */
size_t sea_model_two_scale_rows(const sea_model *m);
/* The auto rule's orders times emis_scale (the tolerance's, below). */
sea_emis_rule sea_model_emis_rule(double emis_scale, const sea_slope_stats *st, sea_dir v);
/* The tolerance's scale of the auto rule (sea_view_choices). */
double sea_model_emis_scale(double tolerance);

/* Tables on a grid of (x, wavelength) read from CSV files (gridtable.c):
 * a header naming the columns in any order, then every pair of the grid
 * once.  Sky: zenith_deg (from 0 to 90), wavelength_um, radiance
 * (W m^-2 sr^-1 um^-1).  Atmosphere: range_m (from 0), wavelength_um,
 * transmittance ([0, 1]), path_radiance (W m^-2 sr^-1 um^-1), as MODTRAN or
 * libRadtran give them, not both 0 in a row (an opaque path radiates).
 * Errors name the file, line, column and range. */
typedef struct sea_grid sea_grid;
sea_status sea_sky_table_load(const char *path, sea_grid **out, sea_error *err);
sea_status sea_atmosphere_table_load(const char *path, sea_grid **out, sea_error *err);
void sea_grid_free(sea_grid *g);
/* Its number of x values, the last x (SI: radians or m) and wavelengths (m). */
void sea_grid_axes(const sea_grid *g, size_t *nx, double *x_max, double *w_min, double *w_max);
/* Value column `column` (0: radiance or transmittance, 1: path radiance;
 * SI) interpolated linearly at wavelength (m), on the table's x (copied
 * into x[nx], out[nx]).  SEA_ERR_DOMAIN outside the wavelengths. */
sea_status sea_grid_profile(const sea_grid *g, double wavelength, size_t column, double *x,
                            double *out, sea_error *err);
/* Linear interpolation of (x[i], v[i]), x increasing, n >= 2; the end
 * values beyond the ends.  Pure. */
double sea_profile_at(const double *x, const double *v, size_t n, double at);

/* ------------------------------------ effective reflectivity (Eq 13-14, 20) */

/* Effective reflectivity rho~(inc; obs) of Eq 13 with the bistatic Smith
 * shadowing of Eq 14c, per steradian of incidence: the radiance reflected
 * toward obs is int rho~(w_i; obs) L(w_i) dw_i.  >= 0, finite.  Pure. */
double sea_reflectivity(double complex N, const sea_slope_stats *st, sea_dir inc, sea_dir obs);
/* out[i] = sea_reflectivity(N[i], st, inc, obs) for n indices, to the bit,
 * with the geometry (mirror facet, density, shadowing) computed once.  Pure. */
void sea_reflectivity_n(const double complex *N, size_t n, const sea_slope_stats *st,
                        sea_dir inc, sea_dir obs, double *out);
/* The sun as a disc of angular radius `radius` (rad): out[i] = the mean of
 * rho~(w_i; obs) over the disc's directions around inc, so that E_sun out[i]
 * is the glint of a sun of irradiance E_sun and that radius: a calm sea's
 * glint then has the width and the peak radiance rho L_sun of a mirror
 * image of the sun.  Where the slope density is nearly linear over the
 * disc's image in slope space (relative effect below skip_rel) it is the
 * point value of sea_reflectivity_n; radius 0 likewise.  Its rho(psi) comes
 * from p's table of each index (built on first use, under p's lock), within
 * 1e-10 absolute of sea_fresnel_unpolarized's, as the emissivity's does.
 * So too where the disc's value is certainly below `negligible` (units of
 * out; 0: never): the point value times the largest ratio of the slope
 * density over the disc's image to its value at the centre, exp(a
 * sqrt(lambda_max) d), a the radius and d the centre's Mahalanobis
 * distance, bounds it.  A caller passes the reflectivity below which the
 * glint does not matter (the renderer: 1e-3 tolerance of the pixel's other
 * radiance over the sun's irradiance).  Reads p (its Gauss-Legendre nodes
 * and Fresnel tables). */
void sea_reflectivity_disc_n(const sea_optics *p, const double complex *N, size_t n,
                             const sea_slope_stats *st, sea_dir inc, sea_dir obs, double radius,
                             double skip_rel, double negligible, double *out);
/* BRDF f = rho~ / cos(theta_inc) (Eq 20), sr^-1.  Pure. */
double sea_brdf(double complex N, const sea_slope_stats *st, sea_dir inc, sea_dir obs);

/* Energy balance (Eq 21) with v in the observation slot:
 * reflectance = int over the upper hemisphere of rho~(w_i; v) dw_i, computed
 * in slope space (dw_i = d gamma / |J|, Eq 14d), so a glint of any width is
 * resolved; total = emissivity + reflectance <= 1, the deficit being the
 * energy that the single-scattering model sends back into the sea.  Reads
 * p (the reflectance's adaptive quadrature allocates per call; given
 * sea_init(), its failure is SEA_ERR_NUMERIC). */
typedef struct {
    double emissivity, reflectance, total;
} sea_energy;
sea_status sea_energy_balance(const sea_optics *p, sea_emis_method method, double complex N,
                              const sea_slope_stats *st, sea_dir v, sea_energy *out,
                              sea_error *err);


/* ---------------------- large-scale waves (seabake-model(7), LARGE-SCALE WAVES) */

/* Moments of the slopes of one facet, linearly filterable (LEAN mapping):
 * averaging the moments of fine facets gives those of the coarse facet they
 * tile.  mxx = mx^2 + C_xx, mxy = mx my + C_xy, myy = my^2 + C_yy; h is the
 * mean height of the generated (large-scale) waves over the facet, m. */
typedef struct {
    double mx, my, mxx, mxy, myy, h;
} sea_moments;

/* Covariance C = M - m m^T of moments, made positive semi-definite against
 * round-off (diagonal >= 0, |xy| <= sqrt(xx yy)).  Pure. */
sea_slope_stats sea_moments_stats(const sea_moments *mo);

/* A facet's moments as heightfields, frames and bakes keep them, in 32
 * bytes instead of sea_moments' 48: the mean height h (m) in double, and
 * the mean slope (mx, my) and the covariance C = M - m m^T as
 * sea_moments_stats makes it (cxx, cxy, cyy), each the float nearest its
 * double.  Keeping C rather than M keeps C's relative precision (6e-8)
 * however large the mean slope is against the spread; the height stays
 * double because the surface's crests decide which facet a grazing ray
 * meets (a float height moved 0.02 % of the pixels of a mast view at
 * 1920 x 1080 by more than 1e-6, up to 2.5e-5; in double none). */
typedef struct {
    double h;
    float mx, my, cxx, cxy, cyy;
    float zero; /* 0: the struct's 32 bytes all defined (files, MPI and memcmp see them) */
} sea_facet;

/* The facet of moments mo (the slopes rounded to float).  Pure. */
sea_facet sea_facet_of(const sea_moments *mo);
/* Its raw moments in double: mxx = mx^2 + C_xx, mxy = mx my + C_xy, ...  Pure. */
sea_moments sea_facet_moments(const sea_facet *f);
/* Its statistics, C made positive semi-definite again against the
 * rounding (diagonal >= 0, |xy| <= sqrt(xx yy)).  Pure. */
sea_slope_stats sea_facet_stats(const sea_facet *f);

/* The two generators of one seeded realisation of the waves above a facet. */
typedef enum {
    SEA_WAVES_SINUSOIDS = 0, /* sum of sinusoids, any facet size and place */
    SEA_WAVES_FFT            /* periodic patch, inverse real FFT on a constant step */
} sea_waves_kind;

typedef struct {
    sea_waves_kind kind;
    double finest;          /* finest facet size L0, m, [SEA_FINEST_MIN, SEA_FINEST_MAX]:
                             * no wave with |k| > pi/L0 */
    unsigned long seed;     /* same seed, same sea */
    double loop_period;     /* s; > 0: omega rounded to multiples of 2 pi/T; 0: none */
    /* sum of sinusoids */
    int bins_per_octave;    /* wavenumber bins per octave, 1..64 (default 8) */
    int directions;         /* directions per bin, 5..1024 (default 32) */
    /* FFT */
    size_t fft_size;        /* points per side N, even, 2..16384: period N*L0 (default 1024) */
} sea_waves_params;

/* The finest facet sizes a wave plan allows, m.  Below 1 mm (k = pi/L0 >
 * 3100 rad/m, 8.5 times the spectrum's capillary peak k_m = 370 rad/m) the
 * curvature spectrum is below e^-14 of its peak: nothing left to draw but
 * ever more bins.  Above 1 km every wave is sub-facet. */
#define SEA_FINEST_MIN 1e-3
#define SEA_FINEST_MAX 1e6
/* Defaults: sinusoids, finest 1 m, seed 1, no loop, 8 bins/octave, 32
 * directions, FFT 1024 points.  Fills p. */
void sea_waves_params_default(sea_waves_params *p);

typedef struct sea_waves sea_waves;

/* Draws the realisation for sea state s (copied).  Sinusoids: bins of
 * constant width in ln k whose edges are pi 2^(j/B) rad/m (so a facet of
 * 2^i m cuts exactly between bins), from the first edge <= k_p/4 up to
 * pi/L0; each bin holds `directions` components spaced evenly in azimuth
 * from a random offset, with a log-uniform random k inside the bin and a
 * random phase.  A component's slope variance is the bin's share of the
 * slope spectrum along its direction, so the generated covariance of a
 * whole bin is exact.  Random numbers come from a stream per bin, keyed by
 * (seed, j): plans with other finest sizes share the bins they have in
 * common.  FFT: modes k = (2 pi/P)(i, j), 0 < |k| < pi/L0 (the Nyquist
 * row and column hold none), amplitude from Psi at the mode times dk^2, random
 * phase.  Both: deterministic amplitudes, random phases; each wave travels
 * with a phase velocity that has a non-negative component along the wind.
 * FFT plans also plan the inverse FFTW transform of every level they can
 * sample (steps L0 2^m, 2^m <= N/2), with FFTW_ESTIMATE.  Thread-safe (FFT
 * plans: OpenMP, and FFTW's planner under the library's lock); *out is the
 * caller's, freed with sea_waves_free(), and only read by every other call:
 * share it. */
sea_status sea_waves_alloc(const sea_spectrum *s, const sea_waves_params *p, sea_waves **out,
                            sea_error *err);
void sea_waves_free(sea_waves *w);

/* The same waves as a sum-of-sinusoids plan (*out), e.g. an FFT plan's
 * modes evaluated one by one: sampling it reproduces the FFT field to
 * round-off, at the cost of a sum over every mode per cell (it keeps the
 * FFT's cut |k| < pi/step).  Reads w; *out as with sea_waves_alloc. */
sea_status sea_waves_to_sinusoids(const sea_waves *w, sea_waves **out, sea_error *err);

/* One wave: h = amplitude cos(kx x + ky y - omega t + phase), omega signed. */
typedef struct {
    double kx, ky, amplitude, phase, omega;
} sea_wave;

/* The accessors below read w; the pointers they return are owned by w. */
size_t sea_waves_count(const sea_waves *w);
/* Wave i < sea_waves_count(w), in a fixed order. */
sea_wave sea_waves_get(const sea_waves *w, size_t i);
/* The parameters and the sea state w was created with (copies, owned by w). */
const sea_waves_params *sea_waves_params_of(const sea_waves *w);
const sea_spectrum *sea_waves_spectrum(const sea_waves *w);
/* Patch period P = N L0 of an FFT plan, m; INFINITY for sinusoids. */
double sea_waves_period(const sea_waves *w);
/* Covariance of the slopes of the generated waves with |k| <= kc (|k| < kc
 * for an FFT plan, whose Nyquist modes hold nothing): their spatial average
 * over a large area, in the x, y frame. */
sea_cov2 sea_waves_generated_cov(const sea_waves *w, double kc);

/* A lattice of cells of size `step`: cell (i, j) covers [i step, (i+1) step)
 * x [j step, (j+1) step); a rectangle holds nx x ny cells from (i0, j0),
 * stored row by row (x fastest). */
typedef struct {
    double step;
    long i0, j0;
    size_t nx, ny;
} sea_rect;

/* The times at which waves are synthesised lie in [-SEA_TIME_MAX,
 * SEA_TIME_MAX] s (32 years): there the phases omega t of the shortest
 * waves (1500 rad/s at 1 mm) keep 2.4e-4 rad; beyond 1e305 s they
 * overflowed into NaN slopes.  A time outside is SEA_ERR_DOMAIN. */
#define SEA_TIME_MAX 1e9

/* Height and slopes of the waves with |k| <= pi/step at the cell centres,
 * time t (within SEA_TIME_MAX).  Any of h, sx, sy may be NULL.  FFT plans need step = L0 2^m and a
 * rectangle no wider than the period (so no tile repeats in the output).
 * Reads w, fills the caller's h, sx, sy (nx ny values each).  OpenMP; FFT
 * plans execute the FFTW transform sea_waves_alloc planned (see Threads). */
sea_status sea_waves_sample(const sea_waves *w, const sea_rect *r, double t, double *h,
                            double *sx, double *sy, sea_error *err);

/* Height and slope at one point of the waves with |k| <= kc.  Reads w. */
void sea_waves_at(const sea_waves *w, double kc, double x, double y, double t, double *h,
                  sea_vec2 *slope);

/* How the large-scale slopes of a facet of size L are obtained (the paper's
 * section 2.B; seabake-model(7), TWO SCALES). */
typedef enum {
    SEA_METHOD_VARIABLE_STEP = 0, /* slope at the centre, waves |k| <= pi/L; C = C_<L */
    SEA_METHOD_VARIABLE_STEP_2N,  /* 2^n x 2^n sub-facets of L/2^n (Eq 19) */
    SEA_METHOD_ONE_METER          /* sub-facets of the plan's finest size L0 */
} sea_facet_method;

/* Parses "variable-step", "variable-step-2n", "one-meter"; -1 otherwise.
 * Pure. */
int sea_facet_method_from_name(const char *name);
/* The name of m, as parsed above.  Pure; static string. */
const char *sea_facet_method_name(sea_facet_method m);
/* Sub-facet subdivision exponent n of a method for facets of size L:
 * variable-step 0, variable-step-2n n, one-meter log2(L/L0) (L/L0 must be a
 * power of two).  Reads w. */
sea_status sea_facet_method_n(const sea_waves *w, sea_facet_method m, int n, double L,
                              int *out_n, sea_error *err);

/* Moments of the facets of rectangle r (facets of size r->step = L) at time
 * t, sub-facets of L/2^n >= L0 (n = 0: Variable Step).  Each facet gets the
 * mean and raw second moments of its 2^n x 2^n sub-facet slopes plus the
 * covariance C_<L/2^n of the waves shorter than a sub-facet.  Reads w,
 * fills the caller's out (nx * ny moments).  Threads: OpenMP; the result is
 * the same bit for bit for any thread count.  FFT plans execute the FFTW
 * transform sea_waves_alloc planned (see Threads). */
sea_status sea_waves_facets(const sea_waves *w, const sea_rect *r, int n, double t,
                            sea_moments *out, sea_error *err);

/* Bytes of memory this process may use, for refusing sizes that cannot fit:
 * the physical memory, or the address-space or data limit of the process
 * (ulimit -v, -d) when lower.  Thread-safe (asks the system). */
size_t sea_memory_available(void);
/* Checks count * size for overflow and against the physical memory;
 * what names the array in the message.  Thread-safe. */
sea_status sea_check_size(size_t count, size_t size, const char *what, sea_error *err);


/* ---------------------------------------------------------------- sensor */

/* The sea surface: a plane, or a sphere for views reaching the horizon. */
typedef enum { SEA_EARTH_FLAT = 0, SEA_EARTH_SPHERICAL } sea_earth;

/* Earth radius for spherical scenes, m. */
#define SEA_EARTH_RADIUS 6371000.0
/* The sensor's map position x, y lies in [-SEA_SENSOR_XY_MAX,
 * SEA_SENSOR_XY_MAX] m: a quarter of the Earth's circumference, beyond
 * which a flat map means nothing.  There the waves' phases (k x up to 1e10
 * rad at 1 mm facets) keep 1e-6 rad, and the clipmap's cell indices stay
 * far inside a long (1e20 m overflowed them). */
#define SEA_SENSOR_XY_MAX 1e7
/* The narrowest field of view, degrees: 0.0036 arcsec, 1.7 cm seen from
 * the highest sensor (1000 km), narrower than any telescope's.  Below
 * 1e-154 deg the focal length squared overflowed and every ray missed the
 * sea. */
#define SEA_HFOV_MIN_DEG 1e-6

/* A pinhole sensor above the sea.  World frame: x east, y north, z up, the
 * mean sea surface at z = 0 (flat) or a sphere of SEA_EARTH_RADIUS through
 * the sensor's nadir point (spherical).  Image pixel (u, v): u to the right,
 * v down, continuous, (0, 0) the top-left corner, (width, height) the
 * bottom-right; the focal length is (width/2) / tan(hfov/2) pixels. */
typedef struct {
    double pos[3];                /* sensor position, m */
    double fwd[3], right[3], up[3]; /* camera axis and image axes, unit */
    double focal;                 /* pixels */
    int width, height;
    sea_earth earth;
} sea_camera;

/* Camera looking along (look_zenith from nadir, look_azimuth).  Unrolled,
 * the image's right axis is horizontal, 90 deg clockwise (seen from above)
 * from the look azimuth, and its up axis is right x axis; at nadir the top
 * of the image points toward look_azimuth.  roll turns the image axes about
 * the camera axis: right' = right cos(roll) + up sin(roll).  Ranges: x and
 * y [-SEA_SENSOR_XY_MAX, SEA_SENSOR_XY_MAX] m, altitude (0, 1e6] m,
 * look_zenith [0, 90) deg, hfov [SEA_HFOV_MIN_DEG, 170] deg, width and
 * height [1, 16384].  Fills c, a plain struct (nothing to free); the calls
 * below only read it and are pure. */
sea_status sea_camera_init(double x, double y, double altitude, double look_zenith,
                           double look_azimuth, double roll, double hfov, int width,
                           int height, sea_earth earth, sea_camera *c, sea_error *err);

/* What the ray through image point (u, v) meets. */
typedef struct {
    int hit;          /* 1: the sea; 0: the sky */
    double x, y;      /* sea point on the map, m (spherical: azimuthal
                         equidistant from the nadir point) */
    double range;     /* sensor to sea point, m */
    sea_dir obs;      /* direction from the sea point to the sensor, local frame */
    sea_dir ray;      /* direction of the ray in the world frame (sky pixels) */
    double footprint; /* IRA projection size L = sqrt(area of the pixel's
                         footprint), m; INFINITY if a pixel corner misses */
    double edge_u[2], edge_v[2]; /* the footprint's edges along the image's
                         u and v axes (mean of its two edges along each),
                         map vectors, m; 0 if a pixel corner misses */
    double footprint_u, footprint_v; /* their lengths, m; INFINITY if a pixel
                         corner misses */
    double normal[3]; /* local vertical at the sea point */
} sea_pixel_geom;

/* Fills g.  Pure. */
void sea_camera_pixel(const sea_camera *c, double u, double v, sea_pixel_geom *g);
/* sea_camera_pixel's g.hit alone (the ray through (u, v) meets the sea),
 * without the rest of its work.  Pure. */
int sea_camera_hits(const sea_camera *c, double u, double v);
/* Unit direction (world) of the ray through image point (u, v). */
void sea_camera_ray(const sea_camera *c, double u, double v, double d[3]);
/* A world direction (unit vector) in the local frame of sea point g:
 * zenith from g->normal, azimuth counter-clockwise from local east.  Pure. */
sea_dir sea_camera_local_dir(const sea_pixel_geom *g, const double d[3]);
/* Image point (u, v) where the world point p projects; returns 0 if p is
 * behind the camera.  Pure. */
int sea_camera_project(const sea_camera *c, const double p[3], double *u, double *v);
/* World point q and local vertical n of the sea point at map coordinates
 * (x, y), the inverse of sea_camera_pixel's (x, y): flat, (x, y, 0) and +z;
 * spherical, azimuthal equidistant from the nadir point.  Pure. */
void sea_camera_sea_point(const sea_camera *c, double x, double y, double q[3], double n[3]);

/* ---------------------------------------------------------------- scenes */

/* Clipmap windows: `view`, each level as large as the pixels that read it
 * need (at most grid x grid facets); `clipmap`, every high-resolution level
 * grid x grid facets, concentric around the point the optical axis meets
 * (the nadir point if it meets the sky), for maps a 3-D program can view
 * from anywhere near the sensor. */
typedef enum { SEA_WINDOWS_VIEW = 0, SEA_WINDOWS_CLIPMAP } sea_windows;

/* A scene file (INI, man/seabake-scene.5) after validation.  Angles are
 * stored in radians, lengths in metres, wavelengths in metres, temperatures
 * in kelvin; radiances are spectral (W m^-2 sr^-1 m^-1) and irradiances
 * spectral (W m^-2 m^-1) so that band integrals come out in W m^-2 sr^-1. */

enum { SEA_SCENE_PATH_MAX = 4096, SEA_SCENE_BAND_MAX = 4096 };

/* A [swell] section: the swell (sw.hs .. sw.gamma set, the rest derived by
 * sea_spectrum_add_swell) and the Douglas swell code it was given, 0 if none. */
typedef struct {
    sea_swell sw;   /* height, period (required unless douglas), direction (default the
                       wind's), spread (15 deg), gamma (3.3) */
    int douglas;    /* douglas = 1 .. 8: height and period not given taken from
                       sea_swell_douglas(); 0 */
} sea_scene_swell;

/* The Douglas swell code d in [1, 8] (H. P. Douglas, 1921, as the Met Office's
 * Marine Observer's Handbook gives it: low swell < 2 m, moderate 2-4 m, heavy
 * > 4 m; short < 100 m, average 100-200 m, long > 200 m) as one swell:
 * low 1 m, moderate 3 m, heavy 5 m; short 75 m, average 150 m, long 300 m
 * of peak wavelength, the peak period of deep water sqrt(2 pi lambda / g).
 * 1 low (average), 2 low long, 3 moderate short, 4 moderate average,
 * 5 moderate long, 6 heavy short, 7 heavy average, 8 heavy long.  Returns 0
 * and sets *hs (m) and *tp (s), or -1 for a d outside [1, 8].  Pure. */
int sea_swell_douglas(int d, double *hs, double *tp);

typedef struct {
    /* [sea] */
    double wind_speed;        /* wind_speed, m/s, [SEA_WIND_MIN, SEA_WIND_MAX], required */
    double wind_dir;          /* wind_direction, deg -> rad, azimuth the wind blows
                                 toward (downwind), finite; 0 */
    double fetch;             /* fetch, m, [SEA_FETCH_MIN, inf]; inf */
    double temperature;       /* temperature, K, [271, 313]; 288 */
    double salinity;          /* salinity, g/kg, [0, SEA_SALINITY_MAX]; 35 */
    sea_water_table water_table; /* water = hale-querry | segelstein (default
                                 hale-querry), SEA_WATER_FILE with a file; */
    char water_file[SEA_SCENE_PATH_MAX]; /* ... or a CSV path, told apart by a '/' or
                                            a '.' in the value (resolved against the
                                            scene file's directory); "" if a table */
    unsigned long seed;       /* seed, integer [0, 2^32 - 1]; 1 */
    double time;              /* time, s, [-SEA_TIME_MAX, SEA_TIME_MAX]; 0 */
    double loop_period;       /* loop_period, s, >= 0; 0 = none */
    /* [swell] sections, each a swell added to the wind sea, in file order */
    int n_swell;              /* 0 .. SEA_SWELL_MAX; 0 */
    sea_scene_swell swell[SEA_SWELL_MAX];
    /* [sun] */
    double sun_zenith;        /* zenith, deg [0, 180] -> rad; > 90 deg: below the
                                 horizon; 40 (the paper's sun) */
    double sun_azimuth;       /* azimuth, deg -> rad, direction toward the sun, finite;
                                 180 (the paper's sun) */
    double sun_irradiance;    /* irradiance, W m^-2 um^-1 [0, 1e5] -> W m^-2 m^-1 at the
                                 surface, normal to the beam; < 0 when not given */
    double sun_temperature;   /* temperature, K (0, 10000]; 5778 (used without irradiance) */
    double sun_solid_angle;   /* solid_angle, sr (0, 0.01]; 6.8e-5 */
    double sun_radius;        /* angular_radius, deg [0, 5] -> rad; the disc of solid_angle,
                                 acos(1 - solid_angle / 2 pi): 0.2666 deg by default; 0 is a
                                 point (the paper) */
    double sun_transmittance; /* transmittance, [0, 1]; 1 */
    /* [sky] */
    double sky_radiance;      /* radiance, W m^-2 sr^-1 um^-1 [0, 1e3] -> per m; < 0 when
                                 not given */
    double sky_temperature;   /* temperature, K (0, 400]; 250 (used without radiance) */
    sea_sky_model sky_model;  /* model = isotropic | clear | table; isotropic */
    double sky_zenith_emissivity; /* zenith_emissivity, (0, 1], clear only; NAN */
    char sky_table_file[SEA_SCENE_PATH_MAX]; /* table = CSV (zenith_deg,wavelength_um,
                                                radiance), model = table only; "" */
    /* [atmosphere] (absent: none) */
    double air_temperature;   /* air_temperature, K (0, 400]; NAN (no atmosphere) */
    double extinction;        /* extinction, 1/km [0, 1e3] -> 1/m; 0 */
    char atmosphere_table_file[SEA_SCENE_PATH_MAX]; /* table = CSV (range_m,wavelength_um,
                                  transmittance,path_radiance), not with extinction; "" */
    /* [sensor] */
    double sensor_x, sensor_y; /* x, y, m, [-SEA_SENSOR_XY_MAX, SEA_SENSOR_XY_MAX]; 0 */
    double altitude;           /* altitude, m, (0, 1e6], required */
    double look_zenith;        /* look_zenith, deg [0, 90) -> rad: camera axis from
                                  nadir; 0 */
    double look_azimuth;       /* look_azimuth, deg -> rad: where the camera points,
                                  finite; 180 (the paper's phi_obs = 0) */
    double roll;               /* roll, deg -> rad, finite; 0 */
    double polarizer;          /* polarizer, deg [-180, 180] -> rad: the render's radiance
                                  is what a camera behind an ideal linear polariser at
                                  this angle from the image's up axis, toward its right,
                                  reads (I + Q cos 2a + U sin 2a; seabake-model(7),
                                  POLARISATION); NAN (none, the radiance I) */
    double hfov;               /* hfov, deg [SEA_HFOV_MIN_DEG, 170] -> rad, full horizontal
                                  field of view */
    int width, height;         /* width, height, pixels [1, 16384], required */
    double wavelength;         /* wavelength, um -> m, within the water table; single
                                  wavelength; < 0 with a band */
    double band_min, band_max; /* band = A:B, um -> m, 0 < A < B, within the water table;
                                  < 0 with a single wavelength.  Exactly one of
                                  wavelength and band is required. */
    char response_file[SEA_SCENE_PATH_MAX]; /* response = CSV (wavelength_um,response),
                                  resolved like water, band only, positive somewhere in
                                  the band, 0 outside its rows; "" = flat */
    int band_samples;          /* samples, [1, SEA_SCENE_BAND_MAX], band only; 0 = chosen
                                  by tolerance */
    /* [sensor]: the camera (seabake-model(7), THE CAMERA; sea_imager).  All
     * optional: NAN (or "") means the key is absent, and a scene without
     * any of them renders the ideal radiance alone
     * (sea_imager_params_from_scene).  Ranges: the SEA_IMAGER_ macros. */
    double psf_sigma;          /* psf_sigma, pixels (0, 64]; not with f_number or mtf */
    double f_number;           /* f_number, [0.5, 100], with pitch; not with mtf */
    double pitch;              /* pitch, um [0.1, 1000] -> m, with f_number */
    char mtf_file[SEA_SCENE_PATH_MAX]; /* mtf = CSV (cycles_per_pixel,mtf), resolved like
                                          response; "" */
    double fill_factor;        /* fill_factor, (0, 1] (absent: 1) */
    double netd;               /* netd, K (0, 10] */
    double netd_temperature;   /* netd_temperature, K [150, 500]; 300 (with netd,
                                  fpn_offset or f_number) */
    unsigned long noise_seed;  /* noise_seed, [0, 2^32 - 1], with netd; 1 */
    double fpn_gain;           /* fpn_gain, relative std [0, 0.1] */
    double fpn_offset;         /* fpn_offset, K [0, 10] */
    unsigned long fpn_seed;    /* fpn_seed, [0, 2^32 - 1], with fpn_gain or fpn_offset; 1 */
    double gain;               /* gain, counts per radiance unit (0, 1e12] */
    double offset;             /* offset, counts [-1e9, 1e9], with gain (absent: 0) */
    int bit_depth;             /* bit_depth, [8, 16], with gain; 14 */
    /* [model] */
    sea_facet_method method;   /* method = variable-step | variable-step-2n | one-meter;
                                  variable-step (the paper's model) */
    int n;                     /* n, [0, 20], with variable-step-2n; 1 */
    double finest;             /* finest, m, [0.001, 1000]; 1 */
    int grid;                  /* grid = auto | even [16, 4096], a level's largest side in
                                  facets; SEA_GRID_AUTO (0): as large as the level's
                                  pixels need, up to SEA_GRID_AUTO_MAX (256 for
                                  windows = clipmap) */
    sea_emis_method emissivity_method; /* emissivity = auto | fast | full; auto */
    sea_earth earth;           /* earth = flat | spherical; flat */
    sea_windows windows;       /* windows = view | clipmap; view */
    double tolerance;          /* tolerance, relative, (0, 0.1]; 1e-3 */
    int reflections;           /* reflections = auto | 1 .. SEA_REFLECTIONS_MAX, surface hits;
                                  SEA_REFLECTIONS_AUTO (0): a second hit where it changes the
                                  radiance by more than SEA_AUTO_SKIP of the tolerance */
    sea_shadowing shadowing;   /* shadowing = smith | correlated; correlated */
    int scales;                /* scales, [1, 2]: 2 adds the two-scale correction
                                  (sea_two_scale_delta); 2 */
    /* Not a key of the file: the program's --reference.  1: every
     * approximation the tolerance allows replaced by its exact form
     * (seabake(1), REFERENCE), with at least two surface hits. */
    int reference;
    /* Not a key either: 1 when the file or an override gave [model]
     * tolerance, 0 when it is the default, which a program may then
     * derive from the camera's netd (sea_imager_scene_tolerance). */
    int tolerance_given;
} sea_scene;

enum { SEA_GRID_AUTO = 0, SEA_GRID_AUTO_MAX = 4096 };

/* Defaults of every optional key; the required ones are marked unset
 * (wind_speed, altitude, hfov NAN; width, height 0; wavelength, band -1).
 * Fills sc, a plain struct (nothing to free). */
void sea_scene_defaults(sea_scene *sc);
/* The scene's sea: its wind sea (sea_spectrum_init) and every [swell]
 * (sea_spectrum_add_swell).  Errors as theirs. */
sea_status sea_scene_spectrum(const sea_scene *sc, sea_spectrum *s, sea_error *err);
/* Reads and validates a scene file.  Errors name the place and the rule:
 * "FILE:LINE: [section] key: message (allowed: RANGE)" with SEA_ERR_PARSE
 * (syntax, unknown section or key, duplicate key, not a number, unknown
 * name) or SEA_ERR_DOMAIN (out of range, missing required key, conflicting
 * keys, wavelength outside the water table); SEA_ERR_IO when the file, or
 * a water table or response file it names, cannot be read.  A missing key
 * is reported at its section's line, or as "FILE: ..." without the section.
 * Lines are at most 198 characters (the inih build's limit).  sc is written
 * only on success.  Thread-safe (reads the files; LC_NUMERIC, see Threads);
 * fills sc. */
sea_status sea_scene_load(const char *path, sea_scene *sc, sea_error *err);
/* The same, then n_overrides strings "section.key=value" (e.g.
 * "sea.wind_speed=12"), each validated exactly as that key on a line of the
 * file and replacing the file's value, or "section.key" (no '='), which
 * removes the file's key: its default back, as if the file had not given it
 * (not for [swell] keys); a key overridden twice is an error.
 * A path value is taken relative to the working directory, not the scene
 * file's.  Errors about an override read "--set TEXT: [section] key: message
 * (allowed: RANGE)".  The strings are only read during the call.  Thread-safe,
 * as sea_scene_load. */
sea_status sea_scene_load_with(const char *path, const char *const *overrides, size_t n_overrides,
                               sea_scene *sc, sea_error *err);

/* A spectral response curve: n >= 2 rows of strictly increasing wavelength
 * (m, at most SEA_RESPONSE_WAVELENGTH_MAX_UM um) and response in [0,
 * SEA_RESPONSE_MAX] (not all 0), from a CSV with '#' comments and a header
 * naming wavelength_um,response.  Errors name FILE:LINE.  The response is
 * relative (any scale: fractions or percent), so its bound only refuses
 * values no curve holds, whose sums could overflow.  sea_response_load is
 * thread-safe (reads the file; LC_NUMERIC, see Threads) and fills r with
 * arrays the caller releases with sea_response_free(). */
#define SEA_RESPONSE_MAX 1e6
#define SEA_RESPONSE_WAVELENGTH_MAX_UM 1000.0
typedef struct {
    size_t n;
    double *wavelength, *value;
} sea_response;
sea_status sea_response_load(const char *path, sea_response *r, sea_error *err);
void sea_response_free(sea_response *r);

/* --------------------------------------- the resolved surface of one level */

/* The surface of a lattice of facets (a sea_rect: facet (i, j) covers
 * [i L, (i+1) L) x [j L, (j+1) L)) made from the facets' moments: it passes
 * through each facet centre at the facet's mean height h with the facet's
 * mean slope m, joined by bicubic Hermite patches (zero twist) between
 * neighbouring centres, so its slope varies smoothly and reproduces any
 * plane exactly; beyond the outer centres (the lattice's outer half facet)
 * it continues linearly.  A point of it carries moments too: its own slope
 * s as the mean and s s^T + C as the raw second moments, C the facets'
 * covariance M - m m^T interpolated bilinearly (the sub-facet part); at a
 * facet centre these are the facet's own moments.  Read-only after
 * creation: any number of threads may query it. */
typedef struct sea_heightfield sea_heightfield;

/* nx, ny >= 2; m: nx ny finite moments, row j (south first) then x, kept
 * as sea_facet_of makes them (a slope beyond float's range is
 * SEA_ERR_DOMAIN). */
sea_status sea_heightfield_alloc(const sea_rect *r, const sea_moments *m, sea_heightfield **out,
                                 sea_error *err);
/* The same from facets (sea_facet), copied as they are. */
sea_status sea_heightfield_alloc_facets(const sea_rect *r, const sea_facet *f,
                                        sea_heightfield **out, sea_error *err);
void sea_heightfield_free(sea_heightfield *hf);
/* Its facets (rows south first): the moments given, as sea_facet_of
 * rounds them.  The surface passes through these. */
const sea_facet *sea_heightfield_facets(const sea_heightfield *hf);
/* The moments of the surface point above map point (x, y); h is its height. */
sea_moments sea_heightfield_at(const sea_heightfield *hf, double x, double y);
/* Bounds of its height (from the convex hulls of the patches' Bezier
 * control points: at or beyond the true extremes). */
void sea_heightfield_range(const sea_heightfield *hf, double *lo, double *hi);
/* A bound on the size of the surface's gradient, |grad h|, everywhere
 * (from the largest height step between neighbouring facets and the
 * largest facet slope; the marches use it to order rays). */
double sea_heightfield_gradient_bound(const sea_heightfield *hf);
/* The first point of the ray o + t d (flat: x east, y north, z up, d unit,
 * d_z < 0) on the surface, over the lattice's rectangle and t in [0, tmax]:
 * returns 1 and *t, or 0 when the ray leaves the rectangle first.  The ray
 * marches with steps that double while it stays above a pyramid of height
 * bounds and shrink to half a facet near the surface, where a crossing is
 * refined until the ray is within 1e-9 facet of the surface, and where the
 * ray passes over a crest between two samples the lowest point between them
 * is located (a ridge narrower than half a facet that the ray grazes without
 * passing over its top between two samples can still be missed). */
int sea_heightfield_trace(const sea_heightfield *hf, const double o[3], const double d[3],
                          double tmax, double *t);

/* ------------------------------------------------- the multiresolution sea */

/* Optional progress report: fraction done in [0, 1], called by one thread
 * at a time, which may be any of the call's OpenMP threads, not only the
 * caller's: what it touches besides ctx must be safe from another thread.
 * Returns 0 to go on; anything else stops the work, which then fails with
 * SEA_ERR_CANCELLED (soon: within a row of pixels or texels). */
typedef int (*sea_progress_fn)(void *ctx, double fraction);

enum { SEA_CLIP_MAX_LEVELS = 24 };

/* One clipmap level: a window of nx x ny facets of size L0 2^level whose
 * lower-left facet is (i0, j0) (facet (i, j) covers [i L, (i+1) L) x
 * [j L, (j+1) L)).  A low-resolution level holds no facets: its waves
 * above the facet size carry less than the tolerance of the slope
 * variance, so every facet has m = 0, C = C_LR. */
typedef struct {
    int level;
    double facet;     /* m */
    long i0, j0;
    size_t nx, ny;
    int low_res;
    int sub_n;        /* sub-facet exponent of the method at this level (0 when skipped) */
    int sub_skipped;  /* variable-step-2n: sub-facets skipped (sub_n = 0) because the
                         waves between the sub-facet and the facet size carry less than
                         the tolerance of the slope variance (sub_share < tolerance) */
    double sub_share; /* share of the LR slope variance (trace) in the waves from the
                         method's sub-facet size to the facet size (0 for variable-step) */
    double generated_share; /* share of the LR slope variance (trace) in waves >= facet */
    size_t pixels;    /* pixels whose footprint chose this level */
} sea_clip_level;

/* The multiresolution sea of a view (multires.c): the clipmap levels the
 * sensor's pixels need and their windows (plan, once per scene), one
 * realisation of their facets' moments and resolved surfaces at a time t
 * (frame), and what a ray of the sensor sees on them (query).  A pixel reads
 * the level its footprint chooses, blended with a neighbour near the
 * midpoint between two levels and faded into the next coarser level at a
 * window's edge: a sea_level_blend plus the positional fades.  Its rays meet
 * that blend's surface (the heights of its waves longer than the facets,
 * along the local vertical), and it averages the moments where they land:
 * the projected area and hiding of the resolved facets come from which
 * point each ray meets; the sub-facet ones from Eq 7 (see multires.c for
 * why no further weight is due). */
typedef struct sea_multires sea_multires;

/* A pixel's levels: `level`, and `neighbour` (-1: none) with weight alpha
 * in [0, 1/2]; each is faded into the coarser levels where its window ends,
 * down to the low-resolution level (flat, m = 0, C = C_LR). */
typedef struct {
    int level, neighbour;
    double alpha;
} sea_level_blend;

/* Plans the sea seen by cam (copied) for scene sc: the levels, their
 * windows, the wave plan.  Uses the scene's [sea] and [model] keys and
 * sensor position; independent of time. */
sea_status sea_multires_alloc(const sea_scene *sc, const sea_camera *cam, sea_multires **out,
                             sea_error *err);
void sea_multires_free(sea_multires *mr);
/* Frees the per-pixel plans (the footprint, levels and rays of every
 * pixel, 80 bytes a pixel), which only save sea_multires_pixel the work:
 * it then plans each pixel as it goes, the same plan bit for bit. */
void sea_multires_drop_pixels(sea_multires *mr);
/* The levels used, finest first, then the low-resolution one. */
size_t sea_multires_levels(const sea_multires *mr, const sea_clip_level **levels);
/* The pixels whose ground point lies outside the window (or in its fading
 * band) of the level their footprint asks for, which read a coarser level
 * for want of a larger grid; *grid_needed (may be NULL): the grid that
 * would hold every pixel at its level (the largest side any level's pixels
 * need, even).  Reads mr. */
size_t sea_multires_fallback(const sea_multires *mr, size_t *grid_needed);
/* The wave plan (NULL when every level is low-resolution). */
const sea_waves *sea_multires_waves(const sea_multires *mr);
/* Moments of a low-resolution facet: m = 0, C = C_LR, h = 0. */
sea_moments sea_multires_lr_moments(const sea_multires *mr);
const sea_camera *sea_multires_camera(const sea_multires *mr);

/* One realisation at time t (|t| <= SEA_TIME_MAX): every high-resolution level's facet
 * moments (sea_waves_facets with the level's sub-facets) and resolved
 * surface.  progress (may be NULL) gets the share of facets synthesised
 * after each level and may stop the work (SEA_ERR_CANCELLED).  The frame
 * refers to mr, which must outlive it.  Read-only after creation. */
typedef struct sea_multires_frame sea_multires_frame;
sea_status sea_multires_frame_alloc(const sea_multires *mr, double t, sea_progress_fn progress,
                                    void *ctx, sea_multires_frame **out, sea_error *err);
void sea_multires_frame_free(sea_multires_frame *f);
/* Level `level`'s surface (by exponent, as sea_clip_level.level; its
 * facets through sea_heightfield_facets), NULL for levels that
 * are low-resolution or not used. */
const sea_heightfield *sea_multires_frame_level(const sea_multires_frame *f, int level);

/* What a pixel sees. */
typedef struct {
    int hit;               /* 1: the sea; 0: the sky (the mean surface is missed) */
    double x, y;           /* map point under what the rays met (their weighted mean), m */
    double height;         /* height of the point met above the mean surface, m */
    double range;          /* sensor to the point met, m */
    double normal[3];      /* local vertical there (world) */
    sea_dir obs;           /* toward the sensor along the pixel's central ray, local frame */
    sea_moments moments;   /* the LEAN average of the moments where the rays met the
                              surface; h: the mean height met, m */
    sea_level_blend blend; /* the levels the pixel reads */
    int level;             /* exponent of the level of largest weight there */
    int rays;              /* rays that met the surface */
} sea_multires_sample;

/* The pixel (i, j) of the camera (its centre (i + 1/2, j + 1/2)). */
void sea_multires_pixel(const sea_multires_frame *f, int i, int j, sea_multires_sample *out);
/* The pixel-sized square of the image centred on (u, v) (any real u, v):
 * its footprint on the mean surface chooses the levels and the rays, as
 * for a pixel; sea_multires_pixel is this at pixel centres, bit for bit. */
void sea_multires_look(const sea_multires_frame *f, double u, double v, sea_multires_sample *out);
/* What the sensor sees along the ray through the mean-surface point (x, y)
 * of the map: sea_multires_look at the image point (*u, *v) where that point
 * projects.  Returns out->hit (0 also when the point is behind the camera).
 * A renderer that draws a flat map and looks up (x, y) shows there what
 * seabake render shows at (*u, *v). */
int sea_multires_look_at(const sea_multires_frame *f, double x, double y, sea_multires_sample *out,
                         double *u, double *v);
/* The LEAN average of the surface's moments at n map points (x[k], y[k])
 * with weights w[k] >= 0 (not all 0), as blend b reads them: the footprint
 * average of sea_multires_look with the points and weights of its rays. */
sea_moments sea_multires_average(const sea_multires_frame *f, sea_level_blend b, size_t n,
                                 const double *x, const double *y, const double *w);

/* ------------------------------------------------------------- the view */

/* A scene prepared for viewing: what the render and the bake (and the
 * horizon) share.  Made once from a scene by sea_view_alloc, read-only
 * after (sea_view_drop_pixels aside, before it is shared): any number of
 * threads render its frames, bake its maps or evaluate its facets. */
typedef struct sea_view sea_view;

/* Prepares a scene for viewing: camera, water, spectral samples, the
 * per-pixel geometry and the clipmap levels the view needs (and no more),
 * the wave plan.  Independent of time.  Thread-safe (copies sc, reads the
 * water table and response files it names; OpenMP).  *out is the caller's,
 * freed with sea_view_free(); every other call only reads it: prepare
 * once, render frames from many threads. */
sea_status sea_view_alloc(const sea_scene *sc, sea_view **out, sea_error *err);
/* Frees r's per-pixel plans (sea_multires_drop_pixels: 80 bytes a pixel)
 * for a caller that renders no image, or few: renders stay the same pixels,
 * each pixel planned as it is rendered.  Not while another thread uses r. */
void sea_view_drop_pixels(sea_view *r);
void sea_view_free(sea_view *r);
/* The clipmap levels used, finest first, n of them.  Reads r; the array is
 * owned by r. */
size_t sea_view_levels(const sea_view *r, const sea_clip_level **levels);
/* Spectral samples used for the band: wavelengths (m) and weights (m:
 * quadrature weight times response), n of them.  Reads r; the arrays are
 * owned by r. */
size_t sea_view_samples(const sea_view *r, const double **wavelength, const double **weight);
/* The same as a sea_band (the arrays owned by r) with the images' radiance
 * unit: what converts the images' radiances to temperatures and back
 * (sea_band_temperature, sea_band_radiance).  Reads r, fills out. */
void sea_view_band(const sea_view *r, sea_band *out);
/* The brightness temperature (K) of a radiance in the images' units,
 * computed exactly as sea_view_render_frame computes its temperature plane (a
 * table, then Newton's method to 1e-9); 0 for a radiance <= 0 or NaN.
 * Reads r. */
double sea_view_brightness_temperature(const sea_view *r, double radiance);

/* A rendered frame, width x height, row 0 at the top.  radiance: spectral
 * W m^-2 sr^-1 um^-1 for one wavelength, in-band W m^-2 sr^-1 for a band;
 * temperature: brightness temperature, K; level: facet size (m) of the
 * clipmap level a pixel used, 0 for the sky; emissivity and reflectivity
 * (rho~ sun -> sensor, sr^-1): response-weighted band means, 0 for the sky.
 * stokes_i, stokes_q, stokes_u: the linear Stokes parameters of the radiance
 * in the images' units, in the camera's frame (reference: the image's up
 * axis, +45 toward its right; seabake-model(7), POLARISATION), 0 for Q and U
 * of the sky; NULL unless sea_image_alloc_stokes made them.  Q and U are the
 * one-hit model's (whatever reflections and scales the intensity takes);
 * stokes_i is the radiance before the scene's polarizer. */
typedef struct {
    int width, height;
    float *radiance, *temperature, *level, *emissivity, *reflectivity;
    float *stokes_i, *stokes_q, *stokes_u;
} sea_image;

/* Fills img with zeroed planes the caller releases with sea_image_free(). */
sea_status sea_image_alloc(int width, int height, sea_image *img, sea_error *err);
/* Adds the Stokes planes to img (allocated by sea_image_alloc): renders then
 * fill them.  SEA_ERR_NOMEM. */
sea_status sea_image_alloc_stokes(sea_image *img, sea_error *err);
void sea_image_free(sea_image *img);

/* Renders the frame at time t (s, |t| <= SEA_TIME_MAX; the scene's own time is sc->time) into
 * img, allocated for the scene's size.  Reads r, fills img: any number of
 * threads may render from one r at once, each into its own image.  Runs on
 * OpenMP threads itself (see Threads), calling progress (may be NULL) as
 * sea_progress_fn says. */
sea_status sea_view_render_frame(const sea_view *r, double t, sea_image *img,
                            sea_progress_fn progress, void *ctx, sea_error *err);
/* The image's rows come in blocks of SEA_RENDER_ROW_BLOCK (block b: rows
 * b SEA_RENDER_ROW_BLOCK up to the next block or the image's bottom),
 * each rendered bottom row first (a pixel's rays start where the pixel
 * below's met the sea, when that is provably no nearer than their own
 * first hit). */
enum { SEA_RENDER_ROW_BLOCK = 8 };
/* sea_view_render_frame for the row blocks row0, row0 + step, ... of the image
 * only (row0 >= 0, step >= 1, else SEA_ERR_DOMAIN; none when row0 is past
 * the last block): those blocks' rows of img get exactly the values
 * sea_view_render_frame gives them, the other rows are left as they are, and
 * progress counts those rows.  For sharing one frame among processes
 * (seabake render under MPI interleaves the blocks of its ranks). */
sea_status sea_view_render_rows(const sea_view *r, double t, int row0, int step, sea_image *img,
                           sea_progress_fn progress, void *ctx, sea_error *err);

/* What the scene's [model] tolerance T (relative radiance) chose in
 * sea_view_alloc besides the low-resolution levels, the spectral
 * samples and the per-level sub-facets (sea_clip_level.sub_skipped).
 * Each rule is a step in T, with the measurement that sets it:
 *  - emissivity (emissivity = auto only): the auto rule's orders times
 *    emis_scale, rounded up: 1 for T <= SEA_TOL_EMIS_T1 (the default 1e-3
 *    keeps today's rule), 0.65 up to SEA_TOL_EMIS_T2, 0.5 above.  Over theta
 *    0-85 deg, |m| <= 0.57, C = 0.3-1 C_LR, U10 3-20 m/s, 4 and 10 um, the
 *    largest emissivity error against a 128 x 16 rule is 8e-7 (scale 1), 9e-5
 *    (0.65) and 1.7e-3 (0.5): below T/10 in each step; the cost goes as the
 *    square of the scale.
 *  - waves: never.  The same seed gives the same waves at every T, so that
 *    an accuracy study compares the same sea: on examples/midwave.ini the
 *    per-pixel relative rms against T = 1e-3 is 3.7e-5 at T = 1e-2, 1.1e-2
 *    at 5e-2 and 4.4e-2 at 0.1.  (Fewer wave directions at a looser T, as
 *    seabake once chose, drew another sea: rms 1.26 at 1e-2; keeping every
 *    second direction of the same draw still gave 0.52.) */
#define SEA_TOL_EMIS_T1 1e-3
#define SEA_TOL_EMIS_T2 2e-2
typedef struct {
    double tolerance;      /* the scene's */
    double emis_scale;     /* 1, 0.65 or 0.5 (1 unless emissivity = auto) */
    int bins_per_octave;   /* of the wave plan (0 when there is none) */
    int directions;        /* per bin (0 when there is none or for an FFT plan) */
    size_t wave_count;     /* wave components of the plan (0: none) */
    int sub_skipped;       /* levels whose sub-facets the tolerance skipped */
    double two_scale_split; /* scales = 2: the split's wavelength 2 pi / k_half, m; else 0 */
} sea_view_choices;
/* Reads r. */
sea_view_choices sea_view_choices_of(const sea_view *r);
/* The auto rule for st seen from v with its orders times emis_scale in
 * (0, 1], rounded up (at least 2 x 1 nodes).  Pure. */
sea_emis_rule sea_view_emis_rule(double emis_scale, const sea_slope_stats *st, sea_dir v);

/* What prepare chose, read-only, owned by r: the validated scene, the
 * sensor, the wave plan (NULL when every level is low-resolution) and the
 * moments of a low-resolution facet (m = 0, C = C_LR, h = 0).  Each reads r. */
const sea_scene *sea_view_scene(const sea_view *r);
const sea_camera *sea_view_camera(const sea_view *r);
const sea_waves *sea_view_waves(const sea_view *r);
sea_moments sea_view_lr_moments(const sea_view *r);
/* The multiresolution sea the render asks what each pixel sees (owned by r). */
const sea_multires *sea_view_multires(const sea_view *r);

/* Optics of one facet, as sea_view_render_frame computes them for a pixel. */
typedef struct {
    double emissivity;   /* response-weighted band mean of eps~ toward obs, [0, 1] */
    double reflectivity; /* band mean of rho~ sun -> obs, sr^-1 (0 with the sun down) */
    double radiance;     /* Eq 23: W m^-2 sr^-1 um^-1 (one wavelength) or W m^-2 sr^-1
                            (band), the units of sea_image.radiance */
    double temperature;  /* brightness temperature of the radiance, K */
    double seen;         /* what the sensor receives of it: the radiance carried
                            across the air along the range to the sensor
                            (sea_view_facet_seen: tau radiance + path, in the
                            same units); `radiance` itself without [atmosphere]
                            and from sea_view_facet_optics */
} sea_facet_optics;

/* Optics of a facet of statistics st seen from obs with the sun at sun
 * (local directions; the sun counts when sun.theta < pi/2), by the same
 * code as sea_view_render_frame: L = sum_i w_i (rho~ E_sun + (1 - eps) L_sky +
 * eps B(T_sea)).  SEA_ERR_NUMERIC only from the reference quadrature.
 * Reads r, fills out. */
sea_status sea_view_facet_optics(const sea_view *r, const sea_slope_stats *st, sea_dir obs,
                                   sea_dir sun, sea_facet_optics *out, sea_error *err);
/* sea_view_facet_optics of a facet at range (m, >= 0) from the sensor,
 * with out->seen what the sensor receives of it across the air, as
 * sea_view_render_frame gives a pixel that meets the sea at that range:
 * tau L + (1 - tau) B(T_air), tau = exp(-extinction range), or per
 * spectral sample the [atmosphere] table's transmittance x L + path
 * radiance at that range (beyond the table's last range its last row:
 * sea_view_render_frame refuses a pixel there, a bake's texels the sensor does
 * not see may lie there).  Without [atmosphere] seen = radiance exactly.
 * Reads r, fills out. */
sea_status sea_view_facet_seen(const sea_view *r, const sea_slope_stats *st, sea_dir obs,
                                 sea_dir sun, double range, sea_facet_optics *out,
                                 sea_error *err);
/* Non-zero when the air changes what the sensor receives ([atmosphere]
 * with extinction > 0 or a table).  Reads r. */
int sea_view_has_air(const sea_view *r);
/* The sky's band radiance toward a direction of zenith cosine cos_zenith
 * (world frame, +z up), in the images' units, as sea_view_render_frame gives a
 * sky pixel whose ray has that cosine: sum_k w_k L_sky,k(cos_zenith)
 * (sea_sky_radiance; the horizon's value at and below it).  Pure given r. */
double sea_view_sky_toward(const sea_view *r, double cos_zenith);

/* ------------------------------------------------------ the camera (imager.c)
 *
 * What a camera makes of a rendered radiance image (seabake-model(7), THE
 * CAMERA): the optics' blur, the detector's footprint, temporal and
 * fixed-pattern noise, and counts.  The render's pixel already averages
 * the radiance over its whole footprint (a detector of fill factor 1):
 * the camera adds what a real one changes.  In order, per frame:
 *  1. the transfer function H(nu_x, nu_y) = MTF_optics(|nu|) D(nu_x) D(nu_y)
 *     (nu in cycles per pixel, |nu| = sqrt(nu_x^2 + nu_y^2)), applied by
 *     one pair of FFTW transforms: a 2-D DCT-II and its inverse, which is
 *     the DFT of the image mirrored across its four edges (half-sample
 *     symmetric, a pad as wide as the image), so the edges see their own
 *     mirror image rather than the opposite edge.  MTF_optics is
 *      - gaussian:    exp(-2 pi^2 sigma^2 nu^2), sigma in pixels;
 *      - diffraction: sum_i w^_i M(nu / nu_c,i), the circular pupil's
 *                     M(s) = (2/pi)(acos s - s sqrt(1 - s^2)) (0 for s >= 1),
 *                     nu_c,i = pitch / (lambda_i N) cycles per pixel, w^_i the
 *                     band's weights times B(lambda_i, netd_temperature),
 *                     normalised: the MTF of the band's mean Airy pattern
 *                     for a scene near that temperature;
 *      - table:       a measured MTF(nu), interpolated linearly, its last
 *                     value beyond its last row;
 *     and D(nu) = sinc(a nu) / sinc(nu), sinc x = sin(pi x)/(pi x), a =
 *     sqrt(fill_factor): the square active area of side a pitch replaces
 *     the full pixel the render averaged (1 for a fill factor of 1; at
 *     most 1 / sinc(1/2) = 1.57 up to Nyquist, so never a division by 0).
 *  2. fixed-pattern noise: L <- g_q L + o_q, g_q = 1 + fpn_gain z1_q,
 *     o_q = fpn_offset (dL/dT at netd_temperature) z2_q, z standard normal
 *     drawn from fpn_seed alone: the same pattern in every frame;
 *  3. temporal noise: L <- L + netd (dL/dT at netd_temperature) z3_q, z3
 *     drawn from noise_seed and the frame index: a new draw every frame;
 *  4. outputs: that radiance, its apparent brightness temperature for the
 *     band (sea_band_temperature's, to 1e-9 relative; 0 where L <= 0) and,
 *     with a gain, counts c_q = round(offset + gain L_q) clipped to
 *     [0, 2^bits - 1]; a pixel whose offset + gain L_q is above 2^bits - 1
 *     or below 0 is counted as saturated (high or low).
 * The normal draws are a function of (seed, frame, pixel) only, so the
 * image does not depend on the number of threads (seabake-model(7) gives
 * the hash).  The temperature comes from the radiance, not the counts: it
 * carries no quantisation. */
typedef enum {
    SEA_PSF_NONE = 0,    /* no optics blur */
    SEA_PSF_GAUSSIAN,    /* psf_sigma */
    SEA_PSF_DIFFRACTION, /* f_number, pitch, the band's wavelengths */
    SEA_PSF_TABLE        /* mtf */
} sea_psf_kind;

/* A measured optics MTF: n >= 2 rows of frequency (cycles per pixel,
 * strictly increasing from exactly 0, at most SEA_IMAGER_MTF_FREQ_MAX) and
 * value ([0, 1], exactly 1 at frequency 0: an MTF is normalised). */
#define SEA_IMAGER_MTF_FREQ_MAX 100.0
typedef struct {
    size_t n;
    double *frequency, *value;
} sea_mtf_table;
/* Reads one from a CSV with '#' comments and a header naming the columns
 * cycles_per_pixel,mtf (either order).  Errors name FILE:LINE and the
 * rule (SEA_ERR_PARSE, SEA_ERR_DOMAIN; SEA_ERR_IO).  Thread-safe (reads
 * the file; LC_NUMERIC); fills t, released with sea_imager_mtf_free(). */
sea_status sea_imager_mtf_load(const char *path, sea_mtf_table *t, sea_error *err);
void sea_imager_mtf_free(sea_mtf_table *t);

/* The ranges of the parameters (and of the scene keys that give them). */
#define SEA_IMAGER_SIGMA_MAX 64.0      /* psf_sigma, pixels: (0, 64] */
#define SEA_IMAGER_F_NUMBER_MIN 0.5    /* f_number: [0.5, 100] (0.5: the aplanatic limit */
#define SEA_IMAGER_F_NUMBER_MAX 100.0  /*   in air) */
#define SEA_IMAGER_PITCH_MIN_UM 0.1    /* pitch, um: [0.1, 1000] (the parameter */
#define SEA_IMAGER_PITCH_MAX_UM 1000.0 /*   is in m: these times 1e-6) */
#define SEA_IMAGER_NETD_MAX 10.0       /* netd, K: (0, 10] */
#define SEA_IMAGER_T_MIN 150.0         /* netd_temperature, K: [150, 500] */
#define SEA_IMAGER_T_MAX 500.0
#define SEA_IMAGER_FPN_GAIN_MAX 0.1    /* fpn_gain, relative std: [0, 0.1] (g_q > 0
                                          to 10 sigma) */
#define SEA_IMAGER_FPN_OFFSET_MAX 10.0 /* fpn_offset, K: [0, 10] */
#define SEA_IMAGER_GAIN_MAX 1e12       /* gain, counts per radiance unit: (0, 1e12] */
#define SEA_IMAGER_OFFSET_MAX 1e9      /* offset, counts: [-1e9, 1e9] */
#define SEA_IMAGER_BITS_MIN 8          /* bit_depth: [8, 16] */
#define SEA_IMAGER_BITS_MAX 16
/* The fraction of the NETD the model's error may take when the tolerance
 * follows from the camera (sea_imager_tolerance_from_netd). */
#define SEA_IMAGER_NETD_FRACTION 0.1

typedef struct {
    sea_psf_kind psf;          /* SEA_PSF_NONE */
    double psf_sigma;          /* gaussian: pixels, (0, SEA_IMAGER_SIGMA_MAX] */
    double f_number;           /* diffraction: [SEA_IMAGER_F_NUMBER_MIN, _MAX] */
    double pitch;              /* diffraction: m, [SEA_IMAGER_PITCH_MIN_UM, _MAX_UM] 1e-6 */
    const sea_mtf_table *mtf;  /* table: as sea_imager_mtf_load checks it (copied) */
    double fill_factor;        /* active area / pixel area, (0, 1]; 1 */
    double netd;               /* K at netd_temperature, [0, SEA_IMAGER_NETD_MAX]; 0 = none */
    double netd_temperature;   /* K, [SEA_IMAGER_T_MIN, SEA_IMAGER_T_MAX]; 300 */
    uint64_t noise_seed;       /* 1 */
    double fpn_gain;           /* relative std, [0, SEA_IMAGER_FPN_GAIN_MAX]; 0 */
    double fpn_offset;         /* K at netd_temperature, [0, SEA_IMAGER_FPN_OFFSET_MAX]; 0 */
    uint64_t fpn_seed;         /* 1 */
    double gain;               /* counts per radiance unit, [0, SEA_IMAGER_GAIN_MAX];
                                  0 = no counts */
    double offset;             /* counts at zero radiance, [-SEA_IMAGER_OFFSET_MAX, _MAX]; 0 */
    int bit_depth;             /* [SEA_IMAGER_BITS_MIN, _MAX]; 14 */
} sea_imager_params;
/* The defaults above: a camera that changes nothing but adds the
 * temperature of its radiance.  Fills p. */
void sea_imager_params_default(sea_imager_params *p);
/* The parameters the scene's [sensor] camera keys give (p->mtf NULL: the
 * table is sc->mtf_file's).  Returns 1 when the scene gives any of them,
 * 0 when it gives none (then the ideal radiance image is the only one).
 * Pure. */
int sea_imager_params_from_scene(const sea_scene *sc, sea_imager_params *p);

/* The plan: the transfer function on the image's DCT grid, the FFTW plans
 * (made once, under the library's planner lock: see Threads), the
 * fixed-pattern maps, the band's temperature table.  width, height in
 * [1, 16384]; band as sea_band says.  SEA_ERR_DOMAIN naming the parameter,
 * its value and its range; SEA_ERR_NOMEM.  Thread-safe; *out is the
 * caller's, freed with sea_imager_free(); sea_imager_apply only reads it.
 * Memory: 16 bytes a pixel with a PSF or a fill factor below 1 (the
 * transfer function, and the transform's buffer in each apply), 8 with
 * fixed-pattern noise. */
typedef struct sea_imager sea_imager;
sea_status sea_imager_alloc(const sea_imager_params *p, const sea_band *band, int width,
                            int height, sea_imager **out, sea_error *err);
void sea_imager_free(sea_imager *im);
/* The scene's camera for the render r (its band and size, its [sensor]
 * keys, the mtf file read): *out NULL (and SEA_OK) when the scene gives no
 * camera key.  Errors as sea_imager_alloc and sea_imager_mtf_load.
 * Thread-safe (reads r and the file). */
sea_status sea_imager_from_render(const sea_view *r, sea_imager **out, sea_error *err);
/* sea_imager_filters: 1 when the imager filters (a PSF, or a fill factor
 * below 1), else 0; sea_imager_counts: 1 when it makes counts (a gain),
 * else 0.  Reads im. */
int sea_imager_filters(const sea_imager *im);
int sea_imager_counts(const sea_imager *im);
/* The temporal noise's radiance, netd dL/dT at netd_temperature, in the
 * images' units (0 without netd).  Reads im. */
double sea_imager_noise_radiance(const sea_imager *im);
/* The transfer function the imager applies at (nu_x, nu_y), cycles per
 * pixel: MTF_optics(|nu|) D(nu_x) D(nu_y), computed exactly (the plan
 * reads the optics' part from a table: within 1e-6 for a diffraction
 * cutoff above 0.3 cycles per pixel, imager.c).  Reads im. */
double sea_imager_mtf(const sea_imager *im, double nu_x, double nu_y);

/* A camera's frame: width x height, row 0 at the top, as sea_image. */
typedef struct {
    int width, height;
    float *radiance;    /* after optics, detector and noise; the images' units */
    float *temperature; /* apparent brightness temperature of radiance, K */
    uint16_t *counts;   /* NULL when the imager has no gain */
    size_t saturated_high, saturated_low; /* pixels clipped at 2^bits - 1, at 0 */
} sea_imager_image;
/* Fills out with zeroed planes for im's size (counts only when im has a
 * gain), released with sea_imager_image_free(). */
sea_status sea_imager_image_alloc(const sea_imager *im, sea_imager_image *out, sea_error *err);
void sea_imager_image_free(sea_imager_image *out);

/* The camera's frame `frame` (any index; the temporal noise's stream) of
 * the rendered img (its radiance plane; img's size must be im's, else
 * SEA_ERR_DOMAIN).  Same im, img, seeds and frame: the same out, bit for
 * bit, whatever the number of threads.  One DCT pair when im filters
 * (FFTW's new-array execute on a buffer of its own, allocated per call:
 * SEA_ERR_NOMEM).  Reads im, fills out: any number of threads may apply
 * one im at once, each into its own out.  Runs on OpenMP threads. */
sea_status sea_imager_apply(const sea_imager *im, const sea_image *img, uint64_t frame,
                            sea_imager_image *out, sea_error *err);

/* The relative radiance tolerance that keeps the model's error within
 * fraction of the NETD: the NETD's radiance, netd dL/dT at
 * netd_temperature, over the radiance of a black body at the scene's
 * temperature, times fraction:
 *     tol = fraction netd L'(T_netd) / L(T_scene)
 * (at T_scene = T_netd: fraction netd (dL/dT) / L).  netd > 0, both
 * temperatures > 0, fraction > 0 (SEA_IMAGER_NETD_FRACTION by default).
 * The [model] tolerance's range is (0, 0.1]: a caller clamps to it.  Pure. */
double sea_imager_tolerance_from_netd(const sea_band *b, double netd, double netd_temperature,
                                      double scene_temperature, double fraction);
/* The same for a scene before it is prepared (the tolerance decides the
 * render's spectral samples): its wavelength, or its band by a 64-node
 * Gauss-Legendre rule weighted by its response (read from its file), its
 * netd and netd_temperature, and its sea's temperature.  SEA_ERR_DOMAIN
 * when the scene gives no netd; errors of sea_response_load.
 * Thread-safe (reads the response file). */
sea_status sea_imager_scene_tolerance(const sea_scene *sc, double fraction, double *tol,
                                      sea_error *err);

/* ---------------------------------------------------------------- baking */

enum { SEA_BAKE_VIEW_K_MAX = 7 };

/* Maps of one clipmap level at one time.  A texel is a facet: texel (i, r)
 * of an nx x ny level, r = 0 the top (north) row, is facet (i0 + i,
 * j0 + ny - 1 - r), stored at index r nx + i (row 0 = north, as EXR row 0
 * is the image top).  A low-resolution level has no texels (moments and
 * optics NULL): every facet is `lr_moments` (m = 0, C = C_LR) and
 * `lr_optics` holds its optics toward the image centre. */
typedef struct {
    sea_clip_level level;
    sea_facet *moments;       /* nx ny, from sea_waves_facets with level.sub_n (the
                                 frame's surfaces' facets, sea_facet_of) */
    sea_facet_optics *optics; /* nx ny, toward the sensor from each texel centre
                                 (seen: across the air along the range to it) */
    size_t view_k;            /* view texels per facet side */
    float *view;              /* (k nx) x (k ny), rows north first: the radiance the
                                 sensor sees at the centre of view texel (I, R), as
                                 float (the maps are float or half): the
                                 surface sea_multires_look_at finds along the
                                 sensor's ray to map point
                                 ((i0 + (I + 1/2)/k) L, (j0 + ny - (R + 1/2)/k) L),
                                 its radiance carried across the air along the
                                 range the ray meets it at (sea_view_facet_seen),
                                 as seabake render's pixel there */
    sea_moments lr_moments;
    sea_facet_optics lr_optics;
    sea_dir lr_obs, lr_sun;   /* the directions lr_optics was computed for */
} sea_bake_level;

/* Where a bake's computing went: wall-clock seconds of its parts (the
 * calls' own, not the time spent in a sea_bake_level_fn). */
typedef struct {
    double waves;  /* synthesising the frame's facets (and their bounds) */
    double image;  /* the sensor's image from them (sea_bake_frame_image) */
    double optics; /* the texels' own optics toward the sensor */
    double view;   /* the view texels: what the sensor sees at each */
} sea_bake_times;

typedef struct {
    double time;          /* s */
    size_t n_levels;      /* as sea_view_levels: finest first, then the LR level */
    sea_bake_level levels[SEA_CLIP_MAX_LEVELS];
    sea_bake_times seconds; /* of the call that made it */
} sea_bake;

/* Bakes every level of r at time t (|t| <= SEA_TIME_MAX).  The optics of a texel are
 * those of its facet seen from the sensor: the direction from the texel
 * centre (x, y) on the sea (flat: (x, y, 0); spherical: the azimuthal
 * equidistant map point of camera.c placed on the sphere) to the sensor, in
 * the local frame there, and the sun's direction in that frame.  The view
 * optics are the same toward the same directions, of the moments seabake
 * render reads there (so a renderer showing each level's view map inside
 * its window, finest on top, reproduces seabake render), on a grid of
 * view_k x view_k (1 to 7) view texels per facet: radiance is not linear in
 * the moments, so a renderer's bilinear lookup of the view map matches
 * seabake render's bilinear moments better on a finer grid.  Threads:
 * OpenMP, the result independent of their number.  progress (may be NULL)
 * gets the fraction done, as sea_progress_fn says (from any of the call's
 * threads, one at a time).  Reads r, fills out: any number of threads may
 * bake from one r at once, each into its own sea_bake.  On failure *out
 * holds nothing to free; otherwise release it with sea_bake_free(). */
sea_status sea_bake_frame(const sea_view *r, double t, int view_k, sea_bake *out,
                          sea_progress_fn progress, void *ctx, sea_error *err);
void sea_bake_free(sea_bake *b);

/* What sea_bake_frame_each calls when level l of b is complete: b holds
 * every level's header (level, view_k, lr_*) and level l's maps (the maps
 * of the levels before it are already freed).  A status other than SEA_OK
 * (with err filled) stops the bake and is returned. */
typedef sea_status (*sea_bake_level_fn)(void *ctx, const sea_bake *b, size_t l, sea_error *err);

/* sea_bake_frame one level at a time, the same maps: each high-resolution
 * level is computed, handed to each (called on the calling thread, never
 * concurrently), and freed before the next is computed, so that the maps of
 * only one level are held at once.  On success *out holds the headers (no
 * maps; sea_bake_free() is harmless); on failure nothing to free. */
sea_status sea_bake_frame_each(const sea_view *r, double t, int view_k, sea_bake *out,
                               sea_progress_fn progress, void *ctx, sea_bake_level_fn each,
                               void *each_ctx, sea_error *err);

/* sea_bake_frame_each that also renders the sensor's image of the frame
 * into img (allocated for the scene's size), pixel for pixel what
 * sea_view_render_frame gives, from the surfaces the bake synthesises for its
 * levels, before the first level is handed to each: one synthesis of the
 * frame instead of two (bench/clipmap2048.ini: six levels of 2048^2
 * facets).  Its progress does not count the image. */
sea_status sea_bake_frame_image(const sea_view *r, double t, int view_k, sea_image *img,
                                sea_bake *out, sea_progress_fn progress, void *ctx,
                                sea_bake_level_fn each, void *each_ctx, sea_error *err);

/* sea_bake_frame_each for a share of the texels, so that one frame can be
 * baked by several processes: of every high-resolution level only the
 * texel rows row0, row0 + step, ... (rows north first, as stored; 0 <=
 * row0 < step, else SEA_ERR_DOMAIN) get their optics and their view_k rows
 * of view texels, exactly the values sea_bake_frame_each gives them; the
 * other rows' optics and view texels are not computed (their values are
 * unspecified).  The moments and headers are all there.  Each process
 * still synthesises every level's waves.  row0 0, step 1 is
 * sea_bake_frame_each. */
sea_status sea_bake_frame_rows(const sea_view *r, double t, int view_k, int row0, int step,
                               sea_bake *out, sea_progress_fn progress, void *ctx,
                               sea_bake_level_fn each, void *each_ctx, sea_error *err);

/* The low-resolution sea out to the horizon, as the sensor sees it, for
 * exports (one constant cannot hold it: toward the horizon the emissivity
 * falls, the sky's reflection and the glint path change).  A polar grid of
 * map points around the sensor's nadir point, x = x0 + arc cos(az),
 * y = y0 + arc sin(az) ((x0, y0) the sensor's x, y; spherical: the
 * azimuthal equidistant map of camera.c, placed on the sphere by
 * sea_camera_sea_point): at each node the radiance that seabake render
 * gives a low-resolution pixel there (the low-resolution slope statistics
 * seen from the sensor, the sun in the local frame, across the air along
 * the range from the sensor: sea_view_facet_seen), in the images' units.
 * Time does not enter.  The grid reaches every sea point the image's pixel
 * corners and centres meet (spherical: at most the horizon, the farthest ring on it,
 * so the silhouette is the sphere's); the azimuths span those points (the
 * full turn, closed by a repeated first column at az + 2 pi, when the
 * nadir point is in view or they span more than half a turn).  Nodes are
 * refined until linear interpolation between neighbours (what a mesh with
 * this map does) is within tol (relative radiance, [1e-5, 0.1]) of the
 * radiance at every interval's midpoint along each ring and each radius
 * (checked at every node of the other direction), and, on a sphere, until
 * every chord between rings projects within 1/4 pixel of the sphere; at
 * most SEA_HORIZON_MAX_NODES nodes each way (then max_err says how close it
 * got).  Threads: OpenMP.  Fills h; release with sea_bake_horizon_free(). */
#define SEA_HORIZON_MAX_NODES 1024
typedef struct {
    size_t n_arc, n_az;
    double *arc;      /* n_arc map distances from the nadir point, m, increasing from 0 */
    double *az;       /* n_az azimuths, rad, counter-clockwise from east, increasing */
    double *radiance; /* n_arc x n_az, node (i, j) at radiance[i n_az + j] */
    double x0, y0;    /* the nadir point (the sensor's x, y), m */
    double max_err;   /* largest relative midpoint error left */
    int full_turn;    /* 1: az[n_az - 1] = az[0] + 2 pi, the same nodes */
} sea_bake_horizon;
sea_status sea_bake_horizon_alloc(const sea_view *r, double tol, sea_bake_horizon *h,
                                 sea_error *err);
void sea_bake_horizon_free(sea_bake_horizon *h);

/* Tangent-space normal of the mean slope (+x east, +y north, +z up):
 * n = (-mx, -my, 1) / sqrt(mx^2 + my^2 + 1).  Pure. */
void sea_bake_normal(const sea_moments *m, double n[3]);

/* Microfacet parameters of a facet's slope covariance C = M - m m^T for a
 * GGX (Blender Principled BSDF) material.  Convention: the isotropic width
 * is the Beckmann-equivalent alpha = sqrt(C_xx + C_yy) (a Beckmann
 * distribution of width alpha has slope variance alpha^2 / 2 per axis);
 * Blender squares its Roughness input (alpha = roughness^2), so
 * roughness = sqrt(alpha).  anisotropy = (l1 - l2) / (l1 + l2) in [0, 1]
 * from the eigenvalues l1 >= l2 of C (0 for C = 0); rotation = the angle of
 * the major axis counter-clockwise from +x (east), in [0, pi), divided by
 * 2 pi: in [0, 0.5) (Blender's Anisotropic Rotation, 1 = a full turn).
 * Pure. */
void sea_bake_roughness(const sea_moments *m, double *roughness, double *anisotropy,
                        double *rotation);

/* ------------------------------ polarisation (seabake-model(7), POLARISATION) */

/* Linear Stokes parameters (I, Q, U) of a radiance, or of an emissivity or
 * reflectivity per unit black-body or incident radiance.  Circular
 * polarisation (V) is not carried: emission has none, and a single
 * reflection of unpolarised light makes none.
 *
 * The sensor's frame, toward the sensor along v = (theta, phi) (sea_dir):
 *     e_h = (-sin phi, cos phi, 0)   horizontal, z x v / |z x v| for theta > 0,
 *     e_v = v x e_h = (-cos theta cos phi, -cos theta sin phi, sin theta),
 * e_v in the vertical (meridian) plane of the view, the image's "up".
 *     I = I_v + I_h,  Q = I_v - I_h,  U = I(+45) - I(-45),
 * I_v and I_h the radiances through a polariser along e_v and e_h, +-45 along
 * (e_v +- e_h)/sqrt 2.  +Q is vertical, the p polarisation of a flat sea in
 * the plane of the view: emission from water is p-polarised (Q > 0),
 * reflection s-polarised (Q < 0), as in the LWIR literature (Shaw 1999).
 * At nadir the frame is the azimuth phi's. */
typedef struct {
    double i, q, u; /* I, Q, U (complex.h takes the name I) */
} sea_stokes;

/* Degree of linear polarisation sqrt(Q^2 + U^2) / I, in [0, 1] for a
 * physical s; 0 where I <= 0.  Pure. */
double sea_stokes_dolp(const sea_stokes *s);

/* Fresnel reflectances per polarisation, air -> water (complex index N,
 * n > 0, k >= 0) at local incidence psi, cos_psi in [0, 1] (clamped):
 *     w = sqrt(N^2 - sin^2 psi) (principal root),
 *     R_s = |(cos psi - w)/(cos psi + w)|^2,
 *     R_p = |(N^2 cos psi - w)/(N^2 cos psi + w)|^2,
 * each in [0, 1], 1 at grazing; (R_s + R_p)/2 = sea_fresnel_unpolarized
 * to 1e-15 relative (the same real arithmetic).  R_p <= R_s, R_p reaching
 * its minimum near Brewster's angle atan(n).  Pure. */
void sea_polar_fresnel(double cos_psi, double complex N, double *R_s, double *R_p);

/* One-hit Stokes emissivity toward v (Eq 7 per polarisation): the same
 * average over the seen facets, weighted by projected area and shadowing,
 * with the same nodes, as sea_emissivity (method AUTO or FAST) or
 * sea_emissivity_rule (*rule, when not NULL), of each facet's emission
 * (1 - R_p along its local p, 1 - R_s along its local s, psi the facet's
 * local incidence) rotated into the sensor's frame:
 *     e_I = E_w[1 - (R_s + R_p)/2]
 *     e_Q = E_w[(R_s - R_p)/2 cos 2chi],  e_U = E_w[(R_s - R_p)/2 sin 2chi],
 * chi the angle from e_v to the facet's plane of incidence around v: with
 * the facet normal n ~ (-gamma_X, -gamma_Y, 1) in the frame of the view
 * azimuth, a = n.e_v ~ sin theta + gamma_X cos theta, b = n.e_h ~ -gamma_Y,
 *     cos 2chi = (a^2 - b^2)/(a^2 + b^2),  sin 2chi = 2ab/(a^2 + b^2)
 * (0 and 0 at normal incidence, where R_s = R_p).  e_I is sea_emissivity's
 * value (its 1 - rho, from the plan's table where it reads one; to
 * summation order, 1e-15); method SEA_EMIS_FULL averages the three by the
 * adaptive reference (about 3 ms).  A flat sea gives Fresnel's emission,
 * DoLP = (R_s - R_p)/(2 - R_s - R_p); a slope law symmetric about the
 * view's vertical plane gives e_U = 0, and its mirror image the opposite
 * e_U.  Only first hits: the emission the seen facets reflect from facets
 * met again (reflections >= 2) is sea_polar_emissivity_multi_n's.
 * SEA_ERR_DOMAIN for a direction outside [0, 90) deg, invalid stats
 * (sea_slope_stats_check) or orders out of range; SEA_ERR_NUMERIC as
 * sea_emissivity's reference.  Reads p: plan once, call from many threads. */
sea_status sea_polar_emissivity(const sea_optics *p, sea_emis_method method,
                                const sea_emis_rule *rule, double complex N,
                                const sea_slope_stats *st, sea_dir v, sea_stokes *out,
                                sea_error *err);

/* The same for n indices at once (a band's samples): out[i] is what
 * sea_polar_emissivity gives for N[i]; the nodes and their frames are found
 * once.  Same errors; reads p. */
sea_status sea_polar_emissivity_n(const sea_optics *p, sea_emis_method method,
                                  const sea_emis_rule *rule, const double complex *N, size_t n,
                                  const sea_slope_stats *st, sea_dir v, sea_stokes *out,
                                  sea_error *err);

/* The Stokes emissivity with up to `reflections` surface hits (1..
 * SEA_REFLECTIONS_MAX; 1 is sea_polar_emissivity_n): e_I is
 * sea_emissivity_multi_n's value for the same arguments, and e_Q, e_U
 * add to the one-hit values what the facets' mirror rays bring back from
 * the facets they meet again (the same rays, chances and split rule as
 * sea_emissivity_multi_n's second hits): a facet met, B, sends its
 * emission E_(R-1) (taken unpolarised) and its own one-hit polarisation
 * toward the facet seen, A, which reflects them by its Mueller matrix in
 * its own (p, s) axes,
 *     Q' = (R_p - R_s)/2 P E_B + (R_s + R_p)/2 P Q_B,  U' = Re(r_p r_s*) P U_B,
 * P the chance of meeting the sea again, (Q_B, U_B) turned into A's
 * axes, and (Q', U') into the sensor's frame.  Reflected emission is
 * s-polarised, so the second hits lower the degree of polarisation
 * (seabake-model(7), POLARISATION, gives the measured size).  Only the
 * facets met's first polarisation is followed: at reflections = 3, the
 * third hit enters e_Q and e_U through E_B alone.  Under a uniform sky of
 * radiance L the radiance's Q and U are e_Q (B - L) and e_U (B - L).
 * Errors as sea_emissivity_multi_n's; reads p. */
sea_status sea_polar_emissivity_multi_n(const sea_optics *p, sea_emis_method method,
                                        const sea_emis_rule *rule, const double complex *N,
                                        size_t n, const sea_slope_stats *st, sea_dir v,
                                        int reflections, sea_stokes *out, sea_error *err);

/* sea_emissivity_two_scale's average over the facets of their one-hit
 * Stokes emissivities (sea_polar_emissivity, SEA_EMIS_AUTO, in the
 * sensor's frame, which all facets share): e_I is
 * sea_emissivity_two_scale's value to 1e-15, e_Q and e_U what the mixture
 * of tilted facets polarises.  Errors as
 * sea_emissivity_two_scale's; reads p. */
sea_status sea_polar_emissivity_two_scale(const sea_optics *p, double complex N,
                                          const sea_slope_stats *sub, sea_cov2 res, sea_dir v,
                                          sea_stokes *out, sea_error *err);
/* One-hit Stokes reflectivity toward v of an unpolarised sky of uniform
 * radiance L_sky, per unit L_sky: every seen facet reflects the sky in its
 * mirror direction (the one-hit model, in which the sky term of the scalar
 * radiance is (1 - eps~) L_sky) with R_s along s and R_p along p, so
 *     r_I = 1 - e_I,  r_Q = -e_Q,  r_U = -e_U
 * of sea_polar_emissivity's e for the same arguments; the radiance's Stokes
 * vector is then e B(T_sea) + r L_sky (Q = U = 0 for an isotropic black
 * sky at the sea's temperature, as Kirchhoff asks).  Errors as
 * sea_polar_emissivity's; reads p. */
sea_status sea_polar_reflectivity_sky(const sea_optics *p, sea_emis_method method,
                                      const sea_emis_rule *rule, double complex N,
                                      const sea_slope_stats *st, sea_dir v, sea_stokes *out,
                                      sea_error *err);

/* The one-hit Stokes radiance of a sky that varies with the zenith (sky:
 * sea_sky, indexed as N) reflected toward v, out[k] for N[k]: every seen
 * facet (the nodes of sea_polar_emissivity, or SEA_EMIS_FULL's adaptive
 * reference) reflects the sky along its own mirror ray, R_s along s and
 * R_p along p:
 *     I = E_w[rho L(r)],  Q = E_w[(R_p - R_s)/2 L(r) cos 2chi],  U likewise,
 * r the facet's mirror ray.  I is what sea_emissivity_sky_n gives at
 * reflections = 1 (to its Fresnel table's 1e-10); under a uniform sky of
 * radiance L, (1 - e_I, -e_Q, -e_U) L of sea_polar_emissivity.  Errors as
 * sea_polar_emissivity's; reads p. */
sea_status sea_polar_sky_n(const sea_optics *p, sea_emis_method method, const sea_emis_rule *rule,
                           const double complex *N, size_t n, const sea_slope_stats *st,
                           sea_dir v, const sea_sky *sky, sea_stokes *out, sea_error *err);

/* Stokes effective reflectivity rho~(inc; obs) of a collimated unpolarised
 * source (the sun) toward obs, per steradian of incidence (Eq 13-14):
 * out->i = sea_reflectivity(N, st, inc, obs), and the mirror facet's
 * polarisation rotated into obs's frame:
 *     out->q = out->i (R_p - R_s)/(R_p + R_s) cos 2chi0,  out->u = ... sin 2chi0,
 * R at the mirror facet's incidence psi0, chi0 from its normal as above
 * (a = n0.e_v, b = n0.e_h).  0 where sea_reflectivity is 0.  Pure. */
void sea_polar_reflectivity(double complex N, const sea_slope_stats *st, sea_dir inc,
                            sea_dir obs, sea_stokes *out);

#ifdef __cplusplus
}
#endif
#endif /* SEABAKE_H */
