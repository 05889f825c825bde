/* mc_stokes.h - the Monte Carlo ray tracer (tests/mc.h) carrying Stokes
 * vectors: the polarised emissivity of a rough sea, all hits, by two
 * independent routes along the same rays.
 *
 * Forward, Mueller matrices.  A ray traced from the sensor along -v meets
 * facets 1, 2, ..., k and leaves (or is stopped).  Facet j emits toward the
 * point before it (1 - R_p along the p of its plane of incidence, 1 - R_s
 * along s, incoherently) and that light reaches the sensor through the
 * reflections of facets j-1, ..., 1.  Every segment of the path carries a
 * frame (two unit vectors across it): the sensor's (e_v, e_h, seabake.h's
 * POLARISATION) on the first, the (p, s) of the facet at its far end on
 * the others.  With P_j the Mueller matrix from segment j's frame to the
 * sensor's, facet j's emission in its (p, s) frame S_j adds
 *     P_{j-1} B_j S_j  to the sensor's Stokes vector, and
 *     P_j = P_{j-1} B_j M_j,
 * B_j the rotation from facet j's outgoing (p, s) frame into segment j-1's
 * frame and M_j the reflection (the Mueller matrix of diag(r_p, r_s), the
 * amplitudes of tests/indep.c, V carried: two reflections of absorbing
 * water turn U into V and back).  The sky is at 0 K: a ray that escapes
 * adds nothing, so the sum is the Stokes emissivity (e_I, e_Q, e_U, e_V)
 * per unit black-body radiance.  A ray stopped (throughput P_00 < 1e-6, or
 * 1000 hits) adds P's first column: the rest as black.
 *
 * Reciprocal, Jones fields.  The same path traced with the incident fields
 * e_v and e_h (complex 3-vectors reflected at every hit, as mc_trace
 * does): the absorptance of a beam polarised along e is 1 - |F_e|^2 (1 when
 * stopped), and by Kirchhoff's law for each polarisation
 *     e_I = 1 - (|F_v|^2 + |F_h|^2)/2,  e_Q = (|F_h|^2 - |F_v|^2)/2,
 *     e_U = -Re(F_v . conj F_h).
 * The two routes share only the path and the Fresnel amplitudes: they
 * agree ray by ray to rounding (max_route_diff), which checks the frames,
 * rotations and signs of the forward one. */
#ifndef SEA_TEST_MC_STOKES_H
#define SEA_TEST_MC_STOKES_H

#include "mc.h"

typedef struct {
    long rays;
    int nwl;
    /* sums over rays, per index: the Stokes emissivity (I, Q, U, V) of all
     * hits, forward; that of the first hit alone (what a one-hit model
     * computes); the reciprocal route's (I, Q, U) */
    double e[MC_MAXWL][4], e1[MC_MAXWL][4], recip[MC_MAXWL][3];
    double max_route_diff; /* max over rays and components |forward - reciprocal| */
    long multi;            /* rays hitting the surface more than once */
    long stopped;          /* rays stopped (throughput or hit limits) */
    long leaks;            /* rays found below the surface (should be 0) */
} mc_stokes_tally;

/* Traces the rays mc_trace traces (the same start points for the same
 * seed) and sums their Stokes emissivities in the sensor's frame of v.
 * Reproducible whatever the number of OpenMP threads.  0, or -1 for bad
 * arguments or no memory. */
int mc_trace_stokes(const mc_surface *s, sea_dir v, const double complex *N, int nwl,
                    long rays, unsigned long seed, mc_stokes_tally *out);

#endif
