/* radiometry.h - what turns a facet's optics into radiance, for view.c and
 * radiometry.c only: the band's spectral samples (wavelengths, weights,
 * water's index), the sun's irradiance, the sky's and the sea's and the
 * air's blackbody radiances per sample, the sky's and the atmosphere's
 * tables, and the brightness temperature of a band radiance
 * (seabake-model(7), RADIANCE, THE SKY AND THE AIR).  Made once by
 * sea_view_alloc, read-only after: read from many threads. */
#ifndef SEA_VIEW_RADIOMETRY_H
#define SEA_VIEW_RADIOMETRY_H

#include <complex.h>

#include "seabake.h"
#include "internal.h"

/* The band radiance's table for the brightness temperature: ln T uniform
 * over 30-6000 K. */
enum { SEA_TB_N = 256 };

typedef struct {
    const sea_scene *sc; /* the view's scene */
    sea_water *water;
    size_t nsamp;
    double *wl, *wt, *esun, *lsky;
    double *lsea;    /* blackbody radiance at the sea's temperature, per sample */
    double *pa, *pb; /* per sample, B(lambda, T) = pa / expm1(pb / T) */
    double *lair;    /* ... at the air's ([atmosphere] air_temperature), 0 without */
    sea_sky sky;     /* the sky's model over the samples (radiance: lsky, lair or a table's
                        profile) */
    /* tables ([sky] model = table, [atmosphere] table): the grids, and per
     * sample their profiles on the grid's x (zenith or range) */
    sea_grid *sky_grid, *atm_grid;
    size_t sky_nx, atm_nx;
    double *sky_x, *sky_v;             /* sky_v[k sky_nx + i] */
    double *atm_x, *atm_tau, *atm_path; /* [k atm_nx + i] */
    double atm_range_max;
    double air_L;    /* sum_k w_k lair[k]: the band's B(T_air), SI */
    double complex *N;
    double wsum;
    /* the band's ln radiance at ln T = TB_LNT0 + k TB_STEP (several samples):
     * the brightness temperature's first guess */
    double tb_lnL[SEA_TB_N];
} sea_radiometry;

/* The water of sc (its table or file, its salinity) and the sky's and
 * the atmosphere's tables when sc names them, into rad (zeroed by the
 * caller; rad->sc = sc).  Release with sea_radiometry_free. */
SEA_INTERNAL sea_status sea_radiometry_alloc(const sea_scene *sc, sea_radiometry *rad,
                                             sea_error *err);
/* Frees what rad holds (not rad itself); takes a zeroed one. */
SEA_INTERNAL void sea_radiometry_free(sea_radiometry *rad);
/* k spectral samples: one wavelength, or a Gauss-Legendre rule of k nodes
 * on the band weighted by the response; everything per sample with them
 * (replacing any earlier samples). */
SEA_INTERNAL sea_status sea_radiometry_samples(sea_radiometry *rad, size_t k,
                                               const sea_response *resp, sea_error *err);
/* Radiance of a facet with stats st seen from obs under model, sun from sun
 * (sun_up: above the horizon), summed over the samples with their weights
 * (SI); band means of emissivity and reflectivity through *e and *rho; per
 * sample in Lk when not NULL; per sample its linear polarisation Q and U in
 * the view's frame (reference e_v; one hit) in Qk and Uk when Qk is not
 * NULL (then Uk neither). */
SEA_INTERNAL sea_status sea_radiometry_facet(const sea_radiometry *rad, const sea_model *model,
                                             const sea_slope_stats *st, sea_dir obs, sea_dir sun,
                                             int sun_up, double *L, double *e, double *rho,
                                             double *Lk, double *Qk, double *Uk, sea_error *err);
/* sum_k w_k tau_k(range) X_k: the part of a per-sample polarised radiance
 * that reaches the sensor through the air (the path radiance is not
 * polarised); sum_k w_k X_k without air. */
SEA_INTERNAL double sea_radiometry_transmitted(const sea_radiometry *rad, const double *Xk,
                                               double range);
/* Brightness temperature of a band radiance L (SI, > 0). */
SEA_INTERNAL double sea_radiometry_temperature(const sea_radiometry *rad, double L);
/* Radiance unit of the images: per um for one wavelength (SI is per m). */
SEA_INTERNAL double sea_radiometry_unit(const sea_radiometry *rad);
/* The extinction of the air, 1/m: 0 without [atmosphere]. */
SEA_INTERNAL double sea_radiometry_extinction(const sea_radiometry *rad);
/* What the sensor receives of a sea point at range (m) of radiance L. */
SEA_INTERNAL double sea_radiometry_through_air(const sea_radiometry *rad, double L,
                                               const double *Lk, double range);

#endif
