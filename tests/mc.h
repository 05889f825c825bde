/* mc.h - an independent Monte Carlo ray tracer over periodic random sea
 * surfaces: the test oracle of the model's effective emissivity at grazing
 * views (tests/mc_oracle.c writes the table, tests/test_mc.c checks the
 * oracle itself).  It uses nothing of the library: its Fresnel reflectance
 * is tests/indep.c's (Born & Wolf's real form and the amplitudes written
 * from it, checked against closed forms in tests/test_mc.c), and it is
 * given the slope statistics it is asked to reproduce.
 *
 * Surface.  Heights h[j n + i] on the vertices (i, j) of a periodic n x n
 * index grid; the physical horizontal position of vertex (i, j) is
 * A (i, j)^T (A a 2x2 matrix: the cell size, possibly sheared), z = h.  Each
 * cell is two triangles: (0,0) (1,0) (0,1) and (1,0) (1,1) (0,1).  A
 * triangle's index-space gradient g is a forward difference of the heights;
 * its physical slope is gamma = A^-T g.  All triangles have the same
 * horizontal area, so the mesh's slope distribution is the equal-weight
 * distribution of the 2 n^2 gammas.
 *
 * Tracing.  Rays are traced in index space (a linear map of the horizontal
 * plane keeps planes planes and straight lines straight, so hits are exact):
 * a 2-D DDA over the cells (unwrapped indices, heights read modulo n), in
 * each cell the segment split at the diagonal and each half tested against
 * its triangle's plane (a linear function of the path length: exact root);
 * a ray going up above the global maximum height has escaped. */
#ifndef SEA_TEST_MC_H
#define SEA_TEST_MC_H

#include <complex.h>

#include "seabake.h"

typedef struct {
    int n;             /* grid size */
    double *h;         /* n * n heights */
    double A[2][2];    /* physical (x, y) = A (i, j) */
    double Ai[2][2];   /* A^-1 */
    double hmin, hmax; /* height bounds */
    sea_cov2 cov;      /* measured slope covariance of the triangles */
    sea_vec2 mean;     /* their mean slope (0 to rounding on a periodic mesh) */
} mc_surface;

/* A periodic Gaussian random surface with a Gaussian correlation function
 * (height spectrum exp(-k^T Q^-1 k / 4) in index space, Q = C / (ell^2 tr C / 2)):
 * white noise filtered by FFTW.  Then the mesh's triangle slope covariance M
 * (index space) is measured and A = C^-1/2 M^1/2 chosen so that the mesh's
 * slope covariance is target exactly (to rounding): the triangles' slopes
 * are exactly Gaussian (linear in the Gaussian heights).  target positive
 * definite, or all zero (a flat surface, A = identity).  ell: correlation
 * length in cells.  Returns 0, or -1 (allocation, bad arguments). */
int mc_surface_gaussian(mc_surface *s, int n, double ell, const sea_cov2 *target,
                        unsigned long seed);
/* n x n white noise of unit variance (seed, as mc_surface_gaussian draws
 * it), its spectrum multiplied by amplitude(kx, ky, ctx) (wavenumbers in
 * radians per cell) and its mean removed, into h (n * n).  0, or -1. */
int mc_filtered_noise(int n, unsigned long seed, double (*amplitude)(double kx, double ky, void *ctx),
                      void *ctx, double *h);
/* A comma-separated list of numbers into out (at most max): the count, or
 * -1 if malformed (the oracles' options). */
int mc_parse_list(const char *s, double *out, int max);
/* The oracles' options, "-x VALUE" pairs: the next one's letter and value
 * from argv[*a] on (advancing *a); 1, 0 when none is left, -1 if malformed. */
int mc_next_option(int argc, char **argv, int *a, int *opt, const char **value);
/* The options the grid oracles (mc_oracle, mc_stokes_oracle) share, their
 * defaults set by the caller: -n GRID, -l ELL_CELLS, -s SEEDS, -r RAYS,
 * -S FIRST_SEED, -w WINDS, -L WAVELENGTHS_UM (at most MC_MAXWL), -t
 * THETAS_DEG, -p PHIS_DEG (lists of at most MC_LIST_MAX), -o FILE. */
enum { MC_LIST_MAX = 16 };
typedef struct {
    int n, seeds;
    double ell;
    long rays;
    unsigned long seed0;
    double winds[MC_LIST_MAX], wls[MC_LIST_MAX], ths[MC_LIST_MAX], phs[MC_LIST_MAX];
    int nw, nl, nt, np;
    const char *outpath;
} mc_grid_options;
/* Parses argv over o's defaults: 0, or -1 for an unknown option, a
 * malformed one, or a value out of range (n >= 8, seeds >= 2, rays >= 1,
 * every list non-empty, ell > 0). */
int mc_grid_options_parse(int argc, char **argv, mc_grid_options *o);
/* The threads an OpenMP parallel region gets (1 without OpenMP). */
int mc_threads(void);
/* The mean of x[0..k) and its standard error (k >= 2). */
void mc_mean_se(const double *x, int k, double *mean, double *se);
/* A surface from given heights (copied) and cell matrix A (invertible). */
int mc_surface_from_heights(mc_surface *s, int n, const double *h, const double A[2][2]);
void mc_surface_free(mc_surface *s);

enum { MC_MAXWL = 4, MC_NBOUNCE = 6 };

/* Sums over rays of a beam (divide by rays for the means). */
typedef struct {
    long rays;
    int nwl;
    /* per index: first-hit absorption 1 - rho(psi1) (single bounce), total
     * absorbed with the unpolarised rho at every hit (eps), total absorbed
     * with the polarisation followed (two orthogonal Jones states, complex
     * r_s and r_p at every hit: eps_pol); squares for the per-ray spread */
    double eps1[MC_MAXWL], eps[MC_MAXWL], eps_pol[MC_MAXWL];
    double eps1_sq[MC_MAXWL], eps_sq[MC_MAXWL];
    /* energy escaping after k bounces (k = 1 .. MC_NBOUNCE - 1, the last bin
     * k >= MC_NBOUNCE - 1), unpolarised weights */
    double escaped[MC_MAXWL][MC_NBOUNCE];
    /* weight left when a ray was stopped (weight < 1e-6 or too many
     * bounces): counted as absorbed in eps, so this bounds that bias */
    double residual[MC_MAXWL];
    double max_energy_err; /* max over rays |absorbed + escaped - 1| */
    long first_up;         /* first hits on triangles with gamma_x > 0 */
    long multi;            /* rays hitting the surface more than once */
    long leaks;            /* rays found below the surface (should be 0) */
    long stopped;          /* rays stopped by the bounce or path limits */
} mc_tally;

/* Traces `rays` rays of a parallel beam arriving from v (travelling along
 * -v), their start points uniform over one period of the horizontal plane
 * at z = hmax (so hits are distributed by visible projected area), and
 * sums, for each of the nwl <= MC_MAXWL indices N, the absorbed energy.
 * Reproducible: ray r uses random numbers derived from (seed, r) only, and
 * partial sums are added in a fixed order, whatever the number of OpenMP
 * threads.  Returns 0, or -1 for bad arguments. */
int mc_trace(const mc_surface *s, sea_dir v, const double complex *N, int nwl, long rays,
             unsigned long seed, mc_tally *out);

/* The tracer's ray-surface intersection, for tests/mc_stokes.c: the first
 * hit of o + t d, t > 0 (o and d's horizontal parts in index space, z
 * physical), skipping triangle skip (-1: none): 1 and *out (path length,
 * index-space gradient of the triangle, its id), 0 on escape, -1 on a leak
 * or the path limit. */
typedef struct {
    double t, gx, gy;
    long tri;
} mc_hit;
int mc_first_hit(const mc_surface *s, const double o[3], const double d[3], long skip,
                 mc_hit *out);

#endif
