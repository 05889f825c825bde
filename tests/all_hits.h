/* all_hits.h - the every-hit table of the ray tracer over sea-spectrum
 * surfaces (tests/data/mc_sea_all_hits.csv, tests/mc_sea_oracle.c -f means)
 * and the models as they are held against it: by the unit test
 * (tests/test_mc.c, test_default_all_hits and test_models_all_hits) and by
 * the benchmark of the physics choices (bench/physics_truth.c,
 * scripts/bench-physics), so that both compute the same figures.
 *
 * The surfaces lack the waves shorter than 0.32 m (and longer than their
 * period, 328 m), so a model of two scales made for the wind's spectrum
 * (sea_model_alloc) splits a slope variance the surfaces do not have.  The
 * models of the surfaces' sea are made instead as the default makes a
 * sea's, with the split at half of the surfaces' own slope variance: the
 * one-scale model of the same parameters (sea_model_emissivity, scales =
 * 1), plus the two-scale table's addition (sea_two_scale_delta), clamped to
 * [0, 1], which is sea_model_emissivity's own composition (test_mc.c checks
 * it equal to the bit with the spectrum's split). */
#ifndef SEA_TEST_ALL_HITS_H
#define SEA_TEST_ALL_HITS_H

#include <complex.h>
#include <math.h>

#include "seabake.h"

/* The table's columns, in its order. */
enum {
    AH_WIND, /* m/s */
    AH_WL,   /* um: 4 or 10 */
    AH_THETA,
    AH_PHI, /* deg; 0 along the wind, 90 across */
    AH_SXX,
    AH_SYY,
    AH_SXY, /* the surfaces' mean slope covariance */
    AH_EPS1,
    AH_EPS1_SE,
    AH_EPS,
    AH_EPS_SE, /* every hit, and its standard error */
    AH_MULTI,
    AH_SMITH,
    AH_CORR,
    AH_DEFAULT, /* the model columns (mc_model_refresh) */
    AH_PERIOD,  /* m: the surfaces' period, their longest wave */
    AH_COLS
};
enum { AH_ROWS_MAX = 160 };
#define AH_HEADER                                                                                 \
    "wind_ms,wavelength_um,theta_deg,phi_deg,sxx,syy,sxy,eps1,eps1_se,eps,eps_se,multi,"          \
    "model_smith,model_corr,model_default,period_m"

/* Reads the table at path into x (at most max rows): the number of rows, or
 * -1 with a message on stderr (unreadable, another header, a short row). */
int all_hits_read(const char *path, double x[][AH_COLS], int max);
/* The end of the rows of one wind from row a: one set of surfaces, one
 * covariance and one period. */
int all_hits_wind_end(double x[][AH_COLS], int n, int a);
/* The table's indices: sea water at 4 and 10 um, Hale & Querry, salinity
 * 35, as N[0], N[1] (the column AH_WL picks N[wl == 10]). */
sea_status all_hits_indices(double complex N[2], sea_error *err);

/* The physics choices the benchmark compares, in its order. */
enum {
    AH_PAPER,      /* one hit, Smith's shadowing, one scale */
    AH_CORRELATED, /* one hit, correlated, one scale */
    AH_TWO_SCALES, /* one hit, correlated, two scales */
    AH_TWO_HITS,   /* two hits, correlated, two scales */
    AH_THREE_HITS, /* three hits */
    AH_DEFAULT_MODEL, /* sea_model_params_default: auto hits, correlated, two scales, T 1e-3 */
    AH_NMODELS
};
/* Model k's parameters and a name without spaces (paper, correlated,
 * two_scales, two_hits, three_hits, default). */
void all_hits_model_params(int k, sea_model_params *mp, const char **name);

/* A model made for a wind's surfaces. */
typedef struct {
    sea_model *one;          /* the parameters with scales = 1 */
    sea_two_scale_table *ts; /* scales = 2: the table of the split; else NULL */
    size_t n;
} all_hits_model;
/* mp's model for the wind's spectrum sp, low resolution lr (mean 0, the
 * surfaces' covariance) and the indices N[0..n).  period > 0: the two
 * scales split at half of lr's slope variance from the surfaces' longest
 * wave, of that period in m (the surfaces' sea: the row's AH_PERIOD); 0:
 * at half of the spectrum's whole variance, as sea_model_alloc splits it.
 * The tolerance must be above the finest (2e-4, where sea_model_emissivity
 * takes the additions by quadrature) and not the reference: SEA_ERR_DOMAIN
 * otherwise. */
sea_status all_hits_model_alloc(const sea_model_params *mp, const sea_spectrum *sp,
                                const sea_slope_stats *lr, double period, const double complex *N,
                                size_t n, all_hits_model *out, sea_error *err);
/* The emissivity eps[0..n) of a facet of statistics st toward v:
 * sea_model_emissivity's composition with this model's split. */
sea_status all_hits_model_emissivity(const all_hits_model *m, const sea_slope_stats *st,
                                     sea_dir v, double *eps, sea_error *err);
void all_hits_model_free(all_hits_model *m);

#endif
