/* multires.c - the multiresolution sea: which clipmap levels a view needs
 * and where, one realisation of their facets' moments and heights at a
 * time t, and what a ray of the sensor sees on them.  The render and the
 * bake ask it the same question (sea_multires_look); neither reaches into
 * the other.
 *
 * Plan (sea_multires_alloc, once per scene).  A sea pixel of footprint F
 * (the square root of the area its corner rays cut on the mean surface)
 * wants the level l = round(log2(F / L0)); where the footprint is so
 * elongated that its long side exceeds SUB_MAX F (beyond 89 deg from
 * nadir) it wants the level of (long side) / SUB_MAX instead, so that
 * SUB_MAX rays along it still see one facet each.  Level l is a window of
 * at most grid x grid facets of L0 2^l over the ground points of the pixels
 * that want it (centred on them when they do not fit); a pixel outside its
 * level's window uses the next coarser level that holds it.  From the first
 * level whose waves above the facet size hold less than `tolerance` of the
 * slope variance, levels are low-resolution: m = 0, C = C_LR, h = 0, no
 * synthesis and no facets.
 *
 * No seams.  Moments are linear (LEAN), so blending them is averaging
 * surfaces: a pixel whose log2(F/L0) lies within BLEND_HALF of the midpoint
 * between two levels mixes them, reaching 50/50 at the midpoint; and within
 * a band of facets at a window's edge a level fades into the next coarser
 * one (as geometry clipmaps do).  Heights blend with the same weights, so a
 * pixel's surface is the same mixture as its moments.
 *
 * Frame (sea_multires_frame_alloc, once per time).  Each high-resolution
 * level's facets get their moments and mean height from the wave plan
 * (sea_waves_facets: the waves longer than the facets), and the level's
 * resolved surface (sea_heightfield): bicubic Hermite patches through the
 * facet centres with the facets' heights and mean slopes there, and a
 * pyramid of bounds on its height for marching rays.  A coarser level's
 * surface is the band-limited version of a finer one (fewer of the same
 * waves), so levels agree where they blend.
 *
 * Query (sea_multires_look, any number of threads).  A pixel's rays meet
 * its surface (the heights along the local vertical of the plane or the
 * sphere), not the mean surface: a facet tilted toward the sensor is met by
 * more rays, one tilted away by fewer, and a trough behind a crest by none.
 * Each ray reads the moments of the point it meets (the surface's own slope
 * there as the mean, so geometry and moments agree), and the pixel averages
 * them (LEAN) over its footprint.
 *
 * Why no ray carries a projected-area weight of its own.  Eq 7 gives the
 * emissivity of slope statistics P as eps~ = N / D with N = E_P[(1 - rho)
 * g S] and D = E_P[g S] (Eq 10): an average over the visible sub-facets,
 * each counted by its projected area g.  Both are linear in P, so Eq 7 on a
 * mixture of points r of horizontal areas a_r gives sum a_r N_r / sum a_r
 * D_r = sum (a_r D_r) eps~_r / sum a_r D_r: every point counted by its
 * projected area a_r D_r.  A camera counts a point by the solid angle it
 * fills, and the rays of a pixel are equal shares of that solid angle.  So:
 *  - a pixel of one ray shows eps~ of the point it meets.  The rays of the
 *    whole image meet the resolved surface with a density proportional to
 *    its projected area (1 - s_X tan theta, s its slope, Eq 9b) and not at
 *    all where it is hidden, so the image mean is the projected-area mean
 *    of eps~ over what the sensor sees, as in the low-resolution Eq 7.  D
 *    normalises each point's own sub-facets only and is not applied again:
 *    multiplying by it (or by g) would count the projected area twice, and
 *    reading the moments under the mean-plane point instead (every facet by
 *    its horizontal area) was the bias this module removes.
 *  - a pixel of several rays evaluates Eq 7 once, on the LEAN average of its
 *    rays' moments; ray r enters it with a_r = 1 / D_r, its horizontal area
 *    per unit projected area.  Then Eq 7 on the mixture is sum N_r / D_r /
 *    sum 1 = the mean of the rays' eps~: each ray counts once, as its solid
 *    angle does.  (LEAN's one-Gaussian summary of the mixture is the only
 *    approximation.)
 * At the low-resolution limit the average of the moments of every point of
 * a level's surface, by horizontal area, is m = 0 and the generated plus
 * sub-facet covariance, C_LR: the mean of the image equals the
 * low-resolution emissivity up to what the Smith shadowing of Eq 9c-9e
 * leaves out.  Smith counts each resolved facet by its front-facing area,
 * g + Lambda of its own sub-facets, and hides a fraction of it
 * independently of its slope; the resolved surface hides the facets behind
 * crests, which lean away.  At grazing angles the image at fine levels is
 * therefore a little above the low-resolution value, toward ray-traced
 * truth (man/seabake.1, IMAGES).
 *
 * Footprint.  A pixel's rays are a grid of nu x nv over its square in the
 * image, one per RAY_SPACING facets of its level along each image axis (at
 * least one, at most SUB_MAX): where the footprint spans several facets the
 * pixel averages them, weighted as above, and the rays that a crest stops
 * never reach the trough behind it.  Each ray averages the point moments
 * at ku x kv points of its share of the footprint (POINT_SPACING facets
 * apart, equal horizontal areas: LEAN's box filter, with Eq 7 supplying the
 * projected area), so no pixel point-samples the surface.  A pixel whose
 * every level is low-resolution needs no ray: its surface is the flat mean
 * surface. */
#include "config.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "seabake.h"
#include "internal.h"

/* The reference's low-resolution threshold (sea_scene.reference): levels
 * from the first whose longer waves carry less than this share of the
 * slope variance are low-resolution. */
static const double SEA_REFERENCE_LR_SHARE = 1e-12;
/* The default's: a level is low-resolution when its longer waves carry
 * less than this fraction of the tolerance of the slope variance. */
static const double SEA_LR_SHARE_OF_TOL = 1e-3;
/* Half-width, in log2 of the footprint, of the band around a level
 * midpoint where two levels are blended. */
static const double BLEND_HALF = 0.15;
/* The finest and coarsest level exponents considered. */
enum { LEVEL_MAX = SEA_CLIP_MAX_LEVELS - 1 };
/* Rays per pixel along each image axis, at most, and the footprint
 * points each ray averages along each axis, at most: a footprint may be
 * SUB_MAX RAY_POINTS_MAX / 2 facets long before its level is chosen by its
 * long side (beyond about 89.5 deg from nadir), not by its area. */
enum { SUB_MAX = 8, RAY_POINTS_MAX = 3 };
_Static_assert(SUB_MAX == sizeof ((sea_multires_hint *)0)->k / sizeof(double),
               "a hint holds a row of rays");
/* Rays are at most RAY_SPACING facets of the pixel's level apart (a crest
 * that hides part of the footprint is seen at that resolution), the points
 * each ray averages at most POINT_SPACING facets of the finest level read
 * (two points per facet: the footprint average of the level's shortest
 * waves, two facets long, is sampled at four points per wavelength). */
static const double RAY_SPACING = 2.0, POINT_SPACING = 0.5;
/* The projected-area normalisation D of a ray's moments is used as 1/D in
 * a pixel's average; a point seen edge-on (D -> 0) would then take the
 * whole pixel.  Below this D (a point tilted away by nearly its visibility
 * limit, whose sub-facets the sensor barely sees) the weight stops growing. */
static const double RAY_D_MIN = 0.05;
/* Safety factor on the gradient bound in the test that lets a ray start
 * its march where the ray below it met the surface (look): the argument is
 * exact on a flat Earth; on the sphere the heights and map distances of the
 * two rays at one horizontal distance differ from it by that distance over
 * the Earth's radius (3e-3 at 20 km). */
static const double RAY_ORDER_MARGIN = 2.0;
/* Marching: the finest step is this fraction of the finest facet read
 * (the surface's shortest waves are two facets long, so a ray samples each
 * of their crests at four points or more); steps double while the ray
 * clears the height bounds under them. */
static const double STEP_MIN_FACETS = 0.5;
enum { STEP_START = 8, MARCH_ITER_MAX = 1 << 22, REFINE_ITER_MAX = 64, GRAZE_ITER_MAX = 4 };
/* A crossing is refined until the ray's height above the surface there is
 * this fraction of the finest step (1e-9 m on 1 m facets), or its bracket
 * along the ray shrinks below REFINE_REL_T of it: the point met then does
 * not depend on the path the march took to bracket it (its steps differ
 * with the windows' bounds), to far below anything the moments change
 * over. */
static const double REFINE_REL_Z = 1e-9, REFINE_REL_T = 1e-12;
/* Pyramid levels of a heightfield's bounds: 2^40 cells per side. */
enum { HF_MIP_MAX = 40 };

/* fmin and fmax without their NaN handling, inlined (the hot loops of the
 * march compare finite values). */
static inline double min2(double a, double b)
{
    return a < b ? a : b;
}

static inline double max2(double a, double b)
{
    return a > b ? a : b;
}

/* ------------------------------------------------------- the heightfield */

struct sea_heightfield {
    double L, inv_L;
    long i0, j0;
    size_t nx, ny;
    sea_facet *m; /* nx ny nodes, row j (south first), x fastest; owned */
    float *lo, *hi; /* bounds of the cells between nodes, every pyramid level,
                       rounded outward to float; without the finest when
                       lazy (off[0] unused) */
    int lazy; /* the finest level's bounds computed from the nodes as the
                 march asks (cell_bounds_f, finest_bound): 8 bytes a node
                 less, 6 % more time (large bakes' frames) */
    size_t off[HF_MIP_MAX], w[HF_MIP_MAX], h[HF_MIP_MAX];
    int nmip;
    double gmax; /* a bound on the surface's gradient, |grad h| (hf_build) */
};

/* Cubic Hermite basis on [0, 1]: H0, H1 take the values at 0 and 1, G0, G1
 * the slopes (per unit of u). */
static inline void hermite(double u, double *h0, double *h1, double *g0, double *g1)
{
    const double u1 = 1.0 - u;
    *h0 = (1.0 + 2.0 * u) * u1 * u1;
    *h1 = u * u * (3.0 - 2.0 * u);
    *g0 = u * u1 * u1;
    *g1 = -u * u * u1;
}

static inline void hermite_d(double u, double *h0, double *h1, double *g0, double *g1)
{
    *h0 = 6.0 * u * (u - 1.0);
    *h1 = -*h0;
    *g0 = (1.0 - u) * (1.0 - 3.0 * u);
    *g1 = u * (3.0 * u - 2.0);
}

/* The cell of map point (x, y): lower-left node (i, j), position (u, v) in
 * [0, 1]^2 inside it, and (ex, ey) the distance (m, signed) beyond the
 * outer node centres, where the surface continues linearly. */
typedef struct {
    size_t i, j;
    double u, v, ex, ey;
} hf_cell;

static inline void locate_1d(double f, size_t n, double L, size_t *i, double *u, double *e)
{
    *e = 0.0;
    if (!(f >= 0.0)) { /* also NaN */
        *e = isfinite(f) ? f * L : 0.0;
        f = 0.0;
    } else if (f > (double)(n - 1)) {
        *e = (f - (double)(n - 1)) * L;
        f = (double)(n - 1);
    }
    size_t k = (size_t)f;
    if (k > n - 2)
        k = n - 2;
    *i = k;
    *u = f - (double)k;
}

static inline void hf_locate(const sea_heightfield *hf, double x, double y, hf_cell *c)
{
    locate_1d(x * hf->inv_L - (double)hf->i0 - 0.5, hf->nx, hf->L, &c->i, &c->u, &c->ex);
    locate_1d(y * hf->inv_L - (double)hf->j0 - 0.5, hf->ny, hf->L, &c->j, &c->v, &c->ey);
}

/* Height, and its gradient when zx is not NULL. */
static inline double hf_eval(const sea_heightfield *hf, double x, double y, double *zx, double *zy,
                             hf_cell *cell)
{
    hf_cell c;
    hf_locate(hf, x, y, &c);
    const double L = hf->L;
    const sea_facet *a = hf->m + c.j * hf->nx + c.i, *b = a + 1, *cc = a + hf->nx,
                    *d = cc + 1;
    double hu0, hu1, gu0, gu1, hv0, hv1, gv0, gv1;
    hermite(c.u, &hu0, &hu1, &gu0, &gu1);
    hermite(c.v, &hv0, &hv1, &gv0, &gv1);
    /* along x on the rows j and j + 1, then along y */
    const double r0 = hu0 * a->h + hu1 * b->h + L * (gu0 * a->mx + gu1 * b->mx);
    const double r1 = hu0 * cc->h + hu1 * d->h + L * (gu0 * cc->mx + gu1 * d->mx);
    const double s0 = hu0 * a->my + hu1 * b->my, s1 = hu0 * cc->my + hu1 * d->my;
    double z = hv0 * r0 + hv1 * r1 + L * (gv0 * s0 + gv1 * s1);
    const int ext = c.ex != 0.0 || c.ey != 0.0;
    if (zx != NULL || ext) {
        double du0, du1, dgu0, dgu1, dv0, dv1, dgv0, dgv1;
        hermite_d(c.u, &du0, &du1, &dgu0, &dgu1);
        hermite_d(c.v, &dv0, &dv1, &dgv0, &dgv1);
        const double q0 = du0 * a->h + du1 * b->h + L * (dgu0 * a->mx + dgu1 * b->mx);
        const double q1 = du0 * cc->h + du1 * d->h + L * (dgu0 * cc->mx + dgu1 * d->mx);
        const double p0 = du0 * a->my + du1 * b->my, p1 = du0 * cc->my + du1 * d->my;
        const double gx = (hv0 * q0 + hv1 * q1 + L * (gv0 * p0 + gv1 * p1)) / L;
        const double gy = (dv0 * r0 + dv1 * r1 + L * (dgv0 * s0 + dgv1 * s1)) / L;
        z += gx * c.ex + gy * c.ey;
        if (zx != NULL) {
            *zx = gx;
            *zy = gy;
        }
    }
    if (cell != NULL)
        *cell = c;
    return z;
}

/* The moments of the surface point above (x, y): its slope s as the mean,
 * s s^T + C as the raw second moments with C the facets' covariance
 * interpolated bilinearly (inside the outer centres), its height as h. */
static sea_moments hf_point(const sea_heightfield *hf, double x, double y)
{
    double sx, sy;
    hf_cell c;
    const double z = hf_eval(hf, x, y, &sx, &sy, &c);
    const sea_facet *a = hf->m + c.j * hf->nx + c.i, *b = a + 1, *cc = a + hf->nx,
                    *d = cc + 1;
    const double w00 = (1.0 - c.u) * (1.0 - c.v), w10 = c.u * (1.0 - c.v),
                 w01 = (1.0 - c.u) * c.v, w11 = c.u * c.v;
    double cxx = w00 * a->cxx + w10 * b->cxx + w01 * cc->cxx + w11 * d->cxx;
    double cyy = w00 * a->cyy + w10 * b->cyy + w01 * cc->cyy + w11 * d->cyy;
    double cxy = w00 * a->cxy + w10 * b->cxy + w01 * cc->cxy + w11 * d->cxy;
    cxx = max2(cxx, 0.0);
    cyy = max2(cyy, 0.0);
    const double lim = sqrt(cxx * cyy);
    cxy = min2(max2(cxy, -lim), lim);
    sea_moments o = { sx, sy, sx * sx + cxx, sx * sy + cxy, sy * sy + cyy, z };
    return o;
}

/* Bounds of the patch of cell (i, j) from its Bezier control points (the
 * patch lies in their convex hull), widened on the border cells by what
 * the linear continuation beyond the outer centres adds over half a facet. */
static void cell_bounds(const sea_heightfield *hf, size_t i, size_t j, double *lo, double *hi)
{
    const double L3 = hf->L / 3.0;
    const sea_facet *q[4] = { hf->m + j * hf->nx + i, hf->m + j * hf->nx + i + 1,
                              hf->m + (j + 1) * hf->nx + i, hf->m + (j + 1) * hf->nx + i + 1 };
    const double sx[4] = { 1.0, -1.0, 1.0, -1.0 }, sy[4] = { 1.0, 1.0, -1.0, -1.0 };
    double a = INFINITY, b = -INFINITY, gx = 0.0, gy = 0.0;
    for (int k = 0; k < 4; k++) {
        const double dx = sx[k] * L3 * q[k]->mx, dy = sy[k] * L3 * q[k]->my;
        a = min2(a, q[k]->h + min2(dx, 0.0) + min2(dy, 0.0));
        b = max2(b, q[k]->h + max2(dx, 0.0) + max2(dy, 0.0));
        gx = max2(gx, fabs(q[k]->mx));
        gy = max2(gy, fabs(q[k]->my));
    }
    double ext = 0.0;
    if (i == 0 || i + 2 == hf->nx)
        ext += 0.5 * hf->L * gx;
    if (j == 0 || j + 2 == hf->ny)
        ext += 0.5 * hf->L * gy;
    *lo = a - ext;
    *hi = b + ext;
}

/* nextafterf(f, -INFINITY) and nextafterf(f, INFINITY) of a float f that
 * is not NaN, inline (the march's finest bounds, cell_bounds_f). */
static inline float float_below(float f)
{
    if (f == 0.0f)
        return -0x1p-149f;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    u = f > 0.0f ? u - 1u : u + 1u;
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline float float_above(float f)
{
    if (f == 0.0f)
        return 0x1p-149f;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    u = f > 0.0f ? u + 1u : u - 1u;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* [a, b] rounded outward to float: the largest float <= a, the smallest
 * >= b. */
static inline void round_out(double a, double b, float *lo, float *hi)
{
    float fa = (float)a, fb = (float)b;
    if ((double)fa > a)
        fa = float_below(fa);
    if ((double)fb < b)
        fb = float_above(fb);
    *lo = fa;
    *hi = fb;
}

/* cell_bounds rounded outward to float: what the pyramid's finest level
 * holds. */
static inline void cell_bounds_f(const sea_heightfield *hf, size_t i, size_t j, float *lo,
                                 float *hi)
{
    double a, b;
    cell_bounds(hf, i, j, &a, &b);
    round_out(a, b, lo, hi);
}

/* Bounds of cell (i, j) of pyramid level k. */
static inline void hf_cell_bounds(const sea_heightfield *hf, int k, size_t i, size_t j, float *lo,
                                  float *hi)
{
    if (k == 0 && hf->lazy) {
        cell_bounds_f(hf, i, j, lo, hi);
    } else {
        *lo = hf->lo[hf->off[k] + j * hf->w[k] + i];
        *hi = hf->hi[hf->off[k] + j * hf->w[k] + i];
    }
}

static sea_status hf_build(sea_heightfield *hf, sea_error *err)
{
    size_t w = hf->nx - 1, h = hf->ny - 1, total = 0;
    int k = 0;
    for (;; k++) {
        if (k >= HF_MIP_MAX)
            return sea_fail(err, SEA_ERR_DOMAIN, "heightfield of %zu x %zu facets is too large",
                            hf->nx, hf->ny);
        hf->off[k] = total;
        hf->w[k] = w;
        hf->h[k] = h;
        if (k > 0 || !hf->lazy)
            total += w * h;
        if (w == 1 && h == 1)
            break;
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    hf->nmip = k + 1;
    /* The gradient of a cell's patch along x: (1/L) H0'(u) (h0 - h1) over
     * the rows, |H0'| <= 3/2; the x slopes' terms G0', G1' (each at most 1
     * in size); the y slopes' terms H0'(u) G_j(v) (my_0j - my_1j), |G_j| <=
     * 4/27: at most 1.5 D + 2 M + 0.89 M, D the largest height step between
     * neighbouring nodes over L, M the largest node slope; the same along
     * y, and sqrt(2) times that for the gradient (the linear continuation
     * beyond the outer centres has a border point's gradient). */
    double D = 0.0, M = 0.0;
    /* (rows on every thread: a maximum is the same in any order) */
#pragma omp parallel for schedule(static) reduction(max : D, M)
    for (size_t j = 0; j < hf->ny; j++)
        for (size_t i = 0; i < hf->nx; i++) {
            const sea_facet *q = hf->m + j * hf->nx + i;
            M = max2(M, max2(fabs(q->mx), fabs(q->my)));
            if (i + 1 < hf->nx)
                D = max2(D, fabs(q[1].h - q->h));
            if (j + 1 < hf->ny)
                D = max2(D, fabs(q[hf->nx].h - q->h));
        }
    hf->gmax = M_SQRT2 * (1.5 * D * hf->inv_L + 2.9 * M);
    sea_status st = sea_check_size(total, 2 * sizeof(float), "heightfield bounds", err);
    if (st != SEA_OK)
        return st;
    hf->lo = malloc((total > 0 ? total : 1) * sizeof(float));
    hf->hi = malloc((total > 0 ? total : 1) * sizeof(float));
    if (hf->lo == NULL || hf->hi == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the bounds of %zu x %zu facets",
                        hf->nx, hf->ny);
    if (!hf->lazy) {
#pragma omp parallel for schedule(static)
        for (size_t j = 0; j < hf->h[0]; j++)
            for (size_t i = 0; i < hf->w[0]; i++)
                cell_bounds_f(hf, i, j, &hf->lo[j * hf->w[0] + i], &hf->hi[j * hf->w[0] + i]);
    }
    for (int m = 1; m < hf->nmip; m++) {
        float *clo = hf->lo + hf->off[m], *chi = hf->hi + hf->off[m];
        const size_t pw = hf->w[m - 1], ph = hf->h[m - 1];
#pragma omp parallel for schedule(static) if (hf->w[m] * hf->h[m] > 4096)
        for (size_t j = 0; j < hf->h[m]; j++)
            for (size_t i = 0; i < hf->w[m]; i++) {
                float a = INFINITY, b = -INFINITY;
                for (size_t jj = 2 * j; jj < 2 * j + 2 && jj < ph; jj++)
                    for (size_t ii = 2 * i; ii < 2 * i + 2 && ii < pw; ii++) {
                        float lo, hi;
                        hf_cell_bounds(hf, m - 1, ii, jj, &lo, &hi);
                        a = lo < a ? lo : a;
                        b = hi > b ? hi : b;
                    }
                clo[j * hf->w[m] + i] = a;
                chi[j * hf->w[m] + i] = b;
            }
    }
    return SEA_OK;
}

/* Takes ownership of m (malloc'd), even on failure. */
static sea_status hf_adopt(const sea_rect *r, sea_facet *m, int lazy, sea_heightfield **out,
                           sea_error *err)
{
    *out = NULL;
    sea_heightfield *hf = calloc(1, sizeof *hf);
    if (hf == NULL) {
        free(m);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    }
    hf->L = r->step;
    hf->inv_L = 1.0 / r->step;
    hf->i0 = r->i0;
    hf->j0 = r->j0;
    hf->nx = r->nx;
    hf->ny = r->ny;
    hf->m = m;
    hf->lazy = lazy;
    sea_status st = hf_build(hf, err);
    if (st != SEA_OK) {
        sea_heightfield_free(hf);
        return st;
    }
    *out = hf;
    return SEA_OK;
}

/* n facets of the moments m (sea_facet_of), malloc'd; NULL when out of
 * memory. */
static sea_facet *facets_of(const sea_moments *m, size_t n)
{
    sea_facet *facets = malloc(n * sizeof *facets);
    if (facets != NULL) {
#pragma omp parallel for schedule(static)
        for (size_t q = 0; q < n; q++)
            facets[q] = sea_facet_of(&m[q]);
    }
    return facets;
}

static sea_status hf_check_rect(const sea_rect *r, sea_error *err)
{
    if (!(r->step > 0.0) || !isfinite(r->step))
        return sea_fail(err, SEA_ERR_DOMAIN, "facet size %g m must be > 0 and finite", r->step);
    if (r->nx < 2 || r->ny < 2)
        return sea_fail(err, SEA_ERR_DOMAIN, "a heightfield needs at least 2 x 2 facets (got %zu x %zu)",
                        r->nx, r->ny);
    return sea_check_size(r->nx * r->ny, sizeof(sea_facet), "heightfield", err);
}

/* Takes ownership of facets (malloc'd), even on failure; checks them. */
static sea_status hf_adopt_checked(const sea_rect *r, sea_facet *facets, sea_heightfield **out,
                                   sea_error *err)
{
    for (size_t q = 0; q < r->nx * r->ny; q++) {
        const sea_facet *f = &facets[q];
        if (!isfinite(f->h) || !isfinite(f->mx) || !isfinite(f->my) || !isfinite(f->cxx) ||
            !isfinite(f->cxy) || !isfinite(f->cyy)) {
            free(facets);
            return sea_fail(err, SEA_ERR_DOMAIN, "moments of facet %zu are not finite in float", q);
        }
    }
    return hf_adopt(r, facets, 0, out, err);
}

sea_status sea_heightfield_alloc(const sea_rect *r, const sea_moments *m, sea_heightfield **out,
                                 sea_error *err)
{
    *out = NULL;
    sea_status st = hf_check_rect(r, err);
    if (st != SEA_OK)
        return st;
    for (size_t q = 0; q < r->nx * r->ny; q++)
        if (!isfinite(m[q].h) || !isfinite(m[q].mx) || !isfinite(m[q].my) ||
            !isfinite(m[q].mxx) || !isfinite(m[q].mxy) || !isfinite(m[q].myy))
            return sea_fail(err, SEA_ERR_DOMAIN, "moments of facet %zu are not finite", q);
    sea_facet *facets = facets_of(m, r->nx * r->ny);
    if (facets == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu x %zu facets", r->nx, r->ny);
    return hf_adopt_checked(r, facets, out, err);
}

sea_status sea_heightfield_alloc_facets(const sea_rect *r, const sea_facet *f,
                                        sea_heightfield **out, sea_error *err)
{
    *out = NULL;
    sea_status st = hf_check_rect(r, err);
    if (st != SEA_OK)
        return st;
    sea_facet *facets = malloc(r->nx * r->ny * sizeof *facets);
    if (facets == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu x %zu facets", r->nx, r->ny);
    memcpy(facets, f, r->nx * r->ny * sizeof *facets);
    return hf_adopt_checked(r, facets, out, err);
}

void sea_heightfield_free(sea_heightfield *hf)
{
    if (hf == NULL)
        return;
    free(hf->m);
    free(hf->lo);
    free(hf->hi);
    free(hf);
}

const sea_facet *sea_heightfield_facets(const sea_heightfield *hf)
{
    return hf->m;
}

sea_moments sea_heightfield_at(const sea_heightfield *hf, double x, double y)
{
    return hf_point(hf, x, y);
}

void sea_heightfield_range(const sea_heightfield *hf, double *lo, double *hi)
{
    float a, b;
    hf_cell_bounds(hf, hf->nmip - 1, 0, 0, &a, &b);
    *lo = a;
    *hi = b;
}

double sea_heightfield_gradient_bound(const sea_heightfield *hf)
{
    return hf->gmax;
}

static inline size_t cell_index(double f, size_t ncell)
{
    if (!(f > 0.0))
        return 0;
    if (f >= (double)(ncell - 1))
        return ncell - 1;
    return (size_t)f;
}

/* A node's slope term d = L3 m along one axis, at the corners it has in
 * the cells queried (low: on a cell's low side, sign +; high: on a cell's
 * high side, sign -): the least and the greatest of min(+-d, 0) and
 * max(+-d, 0) over them. */
static inline void side_terms(double d, int low, int high, double *lo, double *hi)
{
    if (low && high) {
        *lo = -fabs(d);
        *hi = fabs(d);
    } else if (low) {
        *lo = min2(d, 0.0);
        *hi = max2(d, 0.0);
    } else {
        *lo = min2(-d, 0.0);
        *hi = max2(-d, 0.0);
    }
}

/* The finest level's bounds over cells ca..cb x ra..rb (at most 2 x 2),
 * none of them on the border (no linear continuation): the smallest and
 * largest of cell_bounds_f over them, without computing each cell.  A
 * node's term in cell_bounds is h + min(+-L3 mx, 0) + min(+-L3 my, 0), the
 * sign by its corner of the cell (+ on the cell's low side); over the
 * cells it is a corner of here, the least of its terms takes the sign
 * that makes each part least: -|L3 mx| where it is a corner on both sides,
 * the one sign where on one (the same doubles cell_bounds adds: +-L3 mx is
 * exact either way).  Rounding down to float is monotone, so the least of
 * the cells' rounded bounds is the rounded least: these are hf_bound's
 * values bit for bit, from at most 3 x 3 nodes instead of 4 cells' 16. */
static void finest_bound(const sea_heightfield *hf, size_t ca, size_t cb, size_t ra, size_t rb,
                         double *lo, double *hi)
{
    const double L3 = hf->L / 3.0;
    double a = INFINITY, b = -INFINITY;
    for (size_t j = ra; j <= rb + 1; j++) {
        const int ylow = j <= rb, yhigh = j > ra; /* corner on a cell's low / high side */
        const sea_facet *q = hf->m + j * hf->nx;
        for (size_t i = ca; i <= cb + 1; i++) {
            double xmin, xmax, ymin, ymax;
            side_terms(L3 * q[i].mx, i <= cb, i > ca, &xmin, &xmax);
            side_terms(L3 * q[i].my, ylow, yhigh, &ymin, &ymax);
            a = min2(a, q[i].h + xmin + ymin);
            b = max2(b, q[i].h + xmax + ymax);
        }
    }
    float fa, fb;
    round_out(a, b, &fa, &fb);
    *lo = fa;
    *hi = fb;
}

/* Bounds of the surface over the map rectangle [x0, x1] x [y0, y1]: the
 * pyramid level at which the rectangle spans at most 2 x 2 cells. */
static void hf_bound(const sea_heightfield *hf, double x0, double y0, double x1, double y1,
                     double *lo, double *hi)
{
    const double ox = (double)hf->i0 + 0.5, oy = (double)hf->j0 + 0.5, s = hf->inv_L;
    size_t ca = cell_index(x0 * s - ox, hf->w[0]), cb = cell_index(x1 * s - ox, hf->w[0]);
    size_t ra = cell_index(y0 * s - oy, hf->h[0]), rb = cell_index(y1 * s - oy, hf->h[0]);
    /* the pyramid level where the rectangle spans at most 2 x 2 cells:
     * from the bit length of its larger extent, then at most two more */
    const size_t span = (cb - ca) > (rb - ra) ? cb - ca : rb - ra;
    int k = span > 1 ? 62 - __builtin_clzll((unsigned long long)span) : 0;
    if (k < 0)
        k = 0;
    while ((cb >> k) - (ca >> k) > 1 || (rb >> k) - (ra >> k) > 1)
        k++;
    ca >>= k;
    cb >>= k;
    ra >>= k;
    rb >>= k;
    if (k == 0 && hf->lazy && ca > 0 && cb + 2 < hf->nx && ra > 0 && rb + 2 < hf->ny) {
        finest_bound(hf, ca, cb, ra, rb, lo, hi);
        return;
    }
    float a = INFINITY, b = -INFINITY;
    for (size_t j = ra; j <= rb; j++)
        for (size_t i = ca; i <= cb; i++) {
            float l, h;
            hf_cell_bounds(hf, k, i, j, &l, &h);
            a = l < a ? l : a;
            b = h > b ? h : b;
        }
    *lo = a;
    *hi = b;
}

/* ---------------------------------------------------------------- rays */

/* A ray from the sensor: flat, the points o + t d with height z; spherical,
 * o = (nadir x, nadir y, altitude) and the heights along the local vertical
 * of the sphere, map points azimuthal equidistant from the nadir point (the
 * ray stays in the vertical plane through it, so its map path is straight). */
typedef struct {
    double o[3], d[3];
    int sphere;
    double dh;     /* horizontal length of d */
    double ux, uy; /* d's horizontal direction, unit (0 when vertical) */
} ray;

static void ray_init(ray *r, const sea_camera *cam, const double d[3])
{
    memcpy(r->o, cam->pos, sizeof r->o);
    memcpy(r->d, d, sizeof r->d);
    r->sphere = cam->earth == SEA_EARTH_SPHERICAL;
    r->dh = sqrt(d[0] * d[0] + d[1] * d[1]);
    r->ux = r->dh > 0.0 ? d[0] / r->dh : 0.0;
    r->uy = r->dh > 0.0 ? d[1] / r->dh : 0.0;
}

static void ray_point(const ray *r, double t, double *x, double *y, double *z)
{
    if (!r->sphere) {
        *x = r->o[0] + t * r->d[0];
        *y = r->o[1] + t * r->d[1];
        *z = r->o[2] + t * r->d[2];
        return;
    }
    const double R = SEA_EARTH_RADIUS, h = r->o[2];
    const double horiz = t * r->dh, e = h + t * r->d[2], pz = R + e;
    /* Within 19 km of the nadir point (q = horiz / pz < 3e-3), the first
     * terms of the series of |p| - R = pz (sqrt(1 + q^2) - 1) + e and of
     * arc = R atan(q), each within 1e-16 relative (q^6); beyond, the exact
     * forms ((|p|^2 - R^2) / (|p| + R) without cancellation). */
    const double q = horiz / pz, q2 = q * q;
    double arc;
    if (q < 3e-3) {
        *z = e + pz * q2 * (0.5 - q2 * (0.125 - q2 * 0.0625));
        arc = R * q * (1.0 - q2 * (1.0 / 3.0 - q2 * (1.0 / 5.0)));
    } else {
        const double h2 = horiz * horiz;
        *z = (e * (2.0 * R + e) + h2) / (sqrt(h2 + pz * pz) + R);
        arc = R * atan2(horiz, pz);
    }
    *x = r->o[0] + arc * r->ux;
    *y = r->o[1] + arc * r->uy;
}

/* Ray length where the ray comes down to height z: the first crossing
 * (near = 1) or, spherical, the second (near = 0, where it rises back).
 * Returns 0 when it never reaches z. */
static int ray_t_at(const ray *r, double z, int near, double *t)
{
    if (!r->sphere) {
        if (!(r->d[2] < 0.0))
            return 0;
        *t = fmax((z - r->o[2]) / r->d[2], 0.0);
        return 1;
    }
    const double R = SEA_EARTH_RADIUS, h = r->o[2];
    const double b = (R + h) * r->d[2], c = (h - z) * (2.0 * R + h + z);
    const double disc = b * b - c;
    if (!(disc >= 0.0))
        return 0;
    const double s = sqrt(disc);
    if (near) {
        if (c <= 0.0) {
            *t = 0.0; /* already below z */
            return 1;
        }
        if (b >= 0.0)
            return 0;
        *t = c / (-b + s);
        return 1;
    }
    *t = -b + s;
    return *t >= 0.0;
}

/* d/dt of the ray's height and map point at t (spherical: to first order
 * in the angle from the nadir point, ample for locating a minimum). */
static void ray_rate(const ray *r, double t, double *dz, double *dx, double *dy)
{
    double ds = r->dh; /* map distance per unit t */
    *dz = r->d[2];
    if (r->sphere) {
        const double R = SEA_EARTH_RADIUS, pz = R + r->o[2] + t * r->d[2];
        const double horiz = t * r->dh;
        *dz = (horiz * r->dh + pz * r->d[2]) / sqrt(horiz * horiz + pz * pz);
        ds = R * (r->dh * pz - horiz * r->d[2]) / (pz * pz + horiz * horiz);
    }
    *dx = ds * r->ux;
    *dy = ds * r->uy;
}

/* ------------------------------------------------------------- surfaces */

typedef struct {
    int hit;
    double x, y;     /* mean-surface point of the pixel centre */
    double eu[2], ev[2]; /* the footprint's edges along u and v, map vectors */
    int level, neighbour;
    double alpha;
    uint32_t need;
    unsigned char nu, nv; /* rays along u and v */
    unsigned char ku, kv; /* footprint points per ray along u and v */
} mr_pixel;

struct sea_multires {
    sea_scene sc;
    sea_camera cam;
    sea_spectrum spec;
    sea_waves *waves;
    sea_moments lr;
    int first_lr;
    sea_clip_level lev[SEA_CLIP_MAX_LEVELS]; /* indexed by level exponent */
    int used[SEA_CLIP_MAX_LEVELS];
    sea_clip_level compact[SEA_CLIP_MAX_LEVELS];
    size_t ncompact;
    size_t npix;
    mr_pixel *px;
    /* pixels whose ground point lies outside the window (or in the fading
     * band) of the level their footprint asks for, and the grid that would
     * hold them all (the largest side any level's pixels need) */
    size_t fallback;
    size_t grid_needed;
};

/* A level's window on the map, the part of it at full weight, and what
 * its edge weight needs. */
typedef struct {
    double x0, y0, x1, y1;     /* the window */
    double fx0, fy0, fx1, fy1; /* inside its fading band */
    double inv_band;           /* 1 / band width, m^-1 */
} mr_window;

/* The bounds a march needs of the chain of levels from l down to the
 * low-resolution level: its heights' range and a bound on its gradient
 * (chain_extent). */
typedef struct {
    double zlo, zhi, gmax;
} mr_extent;

struct sea_multires_frame {
    const sea_multires *mr;
    double t;
    sea_heightfield *hf[SEA_CLIP_MAX_LEVELS];
    mr_window win[SEA_CLIP_MAX_LEVELS];
    mr_extent ext[SEA_CLIP_MAX_LEVELS]; /* by the chain's finest level */
};

/* What a ray marches: one lone heightfield (everywhere, weight 1), or the
 * blend of a frame's levels a pixel reads. */
typedef struct {
    const sea_heightfield *lone;
    const sea_multires_frame *f;
    sea_level_blend b;
    double zlo, zhi;   /* bounds of the whole surface */
    double step_min;   /* m */
    double gmax;       /* a bound on the surface's gradient (surface_init) */
    /* A blend of one high-resolution level: where its window is at full
     * weight (shrunk by a facet), the chain is that level alone, read
     * directly (surf_alone): its heightfield and that rectangle (hf NULL:
     * never). */
    const sea_heightfield *hf;
    double ax0, ay0, ax1, ay1;
} surface;

/* Weight of window lv at (x, y): 1 inside, fading to 0 over the outer
 * band of facets (at least 2, a sixteenth of the window), 0 outside. */
static double edge_band(const sea_clip_level *lv)
{
    return fmax(2.0, fmin((double)lv->nx, (double)lv->ny) / 16.0);
}

static double edge_weight(const sea_clip_level *lv, double x, double y)
{
    const double fx = x / lv->facet - (double)lv->i0, fy = y / lv->facet - (double)lv->j0;
    const double nx = (double)lv->nx, ny = (double)lv->ny;
    const double edge = min2(min2(fx, nx - fx), min2(fy, ny - fy));
    if (!(edge > 0.0))
        return 0.0;
    return min2(1.0, edge / edge_band(lv));
}

/* edge_weight of the frame's window of level q (the same value, from the
 * window's corners in metres). */
static inline double win_weight(const mr_window *w, double x, double y)
{
    const double edge = min2(min2(x - w->x0, w->x1 - x), min2(y - w->y0, w->y1 - y));
    if (!(edge > 0.0))
        return 0.0;
    return min2(1.0, edge * w->inv_band);
}

/* Height of level l's chain at (x, y): l faded into the coarser levels
 * where its window ends, down to the flat low-resolution level. */
static double chain_height(const sea_multires_frame *f, int l, double x, double y)
{
    const sea_multires *mr = f->mr;
    double z = 0.0, rest = 1.0;
    for (int q = l; q < mr->first_lr && rest > 0.0; q++) {
        if (!mr->used[q])
            continue;
        const double w = win_weight(&f->win[q], x, y);
        if (w <= 0.0)
            continue;
        z += rest * w * hf_eval(f->hf[q], x, y, NULL, NULL, NULL);
        rest -= rest * w;
    }
    return z; /* the rest is the low-resolution level, at height 0 */
}

/* The same with the gradient of the chain's levels (weighted as the
 * heights; the fades' own gradients, over bands of facets, are left out). */
static double chain_height_grad(const sea_multires_frame *f, int l, double x, double y,
                                double *gx, double *gy)
{
    const sea_multires *mr = f->mr;
    double z = 0.0, rest = 1.0;
    *gx = *gy = 0.0;
    for (int q = l; q < mr->first_lr && rest > 0.0; q++) {
        if (!mr->used[q])
            continue;
        const double w = win_weight(&f->win[q], x, y);
        if (w <= 0.0)
            continue;
        double sx, sy;
        const double h = hf_eval(f->hf[q], x, y, &sx, &sy, NULL);
        z += rest * w * h;
        *gx += rest * w * sx;
        *gy += rest * w * sy;
        rest -= rest * w;
    }
    return z;
}

static void axpy(sea_moments *acc, double w, const sea_moments *m)
{
    acc->mx += w * m->mx;
    acc->my += w * m->my;
    acc->mxx += w * m->mxx;
    acc->mxy += w * m->mxy;
    acc->myy += w * m->myy;
    acc->h += w * m->h;
}

/* The point moments of level l's chain at (x, y) into o (NULL: the
 * weights alone); *dominant gets the level of largest weight (and *dw that
 * weight). */
static void chain_moments(const sea_multires_frame *f, int l, double x, double y, sea_moments *o,
                          int *dominant, double *dw)
{
    const sea_multires *mr = f->mr;
    if (o != NULL)
        memset(o, 0, sizeof *o);
    double rest = 1.0, best = -1.0;
    *dominant = mr->first_lr;
    for (int q = l; q <= LEVEL_MAX && rest > 0.0; q++) {
        if (q >= mr->first_lr) {
            if (o != NULL)
                axpy(o, rest, &mr->lr);
            if (rest > best) {
                best = rest;
                *dominant = mr->first_lr;
            }
            break;
        }
        if (!mr->used[q])
            continue;
        const double w = win_weight(&f->win[q], x, y);
        if (w <= 0.0)
            continue;
        const double share = rest * w;
        if (o != NULL) {
            const sea_moments m = hf_point(f->hf[q], x, y);
            axpy(o, share, &m);
        }
        if (share > best) {
            best = share;
            *dominant = q;
        }
        rest -= share;
    }
    *dw = best;
}

/* Bounds of level l's chain over a map rectangle. */
static void chain_bound(const sea_multires_frame *f, int l, double x0, double y0, double x1,
                        double y1, double *lo, double *hi)
{
    const sea_multires *mr = f->mr;
    for (int q = l; q < mr->first_lr; q++) {
        if (!mr->used[q])
            continue;
        const mr_window *w = &f->win[q];
        if (x1 <= w->x0 || x0 >= w->x1 || y1 <= w->y0 || y0 >= w->y1)
            continue;
        double a, b;
        hf_bound(f->hf[q], x0, y0, x1, y1, &a, &b);
        *lo = min2(*lo, a);
        *hi = max2(*hi, b);
        if (x0 >= w->fx0 && x1 <= w->fx1 && y0 >= w->fy0 && y1 <= w->fy1)
            return; /* full weight: no coarser level shows through */
    }
    *lo = min2(*lo, 0.0);
    *hi = max2(*hi, 0.0);
}

/* The level's heightfield where the chain at (x, y) is that level alone
 * (weight 1: the chain's sums give its values bit for bit, but for the
 * sign of a zero, which they make +0, the same number to every use), else
 * NULL.  Blends of two levels do not take it: 13 % of the mast view's
 * rays, and reading both levels so made its render 0.7 % more
 * instructions, not fewer.  (The march's surf_ functions are inlined
 * always: sea_multires_alone_check calls them too, and GCC then kept them
 * apart, 0.7 % more instructions again.) */
static inline const sea_heightfield *surf_alone(const surface *s, double x, double y)
{
    return s->hf != NULL && x >= s->ax0 && x <= s->ax1 && y >= s->ay0 && y <= s->ay1 ? s->hf
                                                                                  : NULL;
}

static inline __attribute__((always_inline)) double
surf_height(const surface *s, double x, double y)
{
    if (s->lone != NULL)
        return hf_eval(s->lone, x, y, NULL, NULL, NULL);
    const sea_heightfield *hf = surf_alone(s, x, y);
    if (hf != NULL)
        return hf_eval(hf, x, y, NULL, NULL, NULL);
    double z = chain_height(s->f, s->b.level, x, y);
    if (s->b.neighbour >= 0 && s->b.alpha > 0.0)
        z = (1.0 - s->b.alpha) * z + s->b.alpha * chain_height(s->f, s->b.neighbour, x, y);
    return z;
}

static inline __attribute__((always_inline)) double
surf_height_grad(const surface *s, double x, double y, double *gx, double *gy)
{
    if (s->lone != NULL)
        return hf_eval(s->lone, x, y, gx, gy, NULL);
    const sea_heightfield *hf = surf_alone(s, x, y);
    if (hf != NULL)
        return hf_eval(hf, x, y, gx, gy, NULL);
    double z = chain_height_grad(s->f, s->b.level, x, y, gx, gy);
    if (s->b.neighbour >= 0 && s->b.alpha > 0.0) {
        double nx, ny;
        const double zn = chain_height_grad(s->f, s->b.neighbour, x, y, &nx, &ny);
        const double a = s->b.alpha;
        z = (1.0 - a) * z + a * zn;
        *gx = (1.0 - a) * *gx + a * nx;
        *gy = (1.0 - a) * *gy + a * ny;
    }
    return z;
}

static inline __attribute__((always_inline)) void
surf_bound(const surface *s, double x0, double y0, double x1, double y1, double *lo, double *hi)
{
    if (s->lone != NULL) {
        hf_bound(s->lone, x0, y0, x1, y1, lo, hi);
        return;
    }
    const sea_heightfield *hf = surf_alone(s, x0, y0);
    if (hf != NULL && surf_alone(s, x1, y1) != NULL) {
        hf_bound(hf, x0, y0, x1, y1, lo, hi);
        return;
    }
    *lo = INFINITY;
    *hi = -INFINITY;
    chain_bound(s->f, s->b.level, x0, y0, x1, y1, lo, hi);
    if (s->b.neighbour >= 0 && s->b.alpha > 0.0)
        chain_bound(s->f, s->b.neighbour, x0, y0, x1, y1, lo, hi);
}

static sea_moments surf_moments(const surface *s, double x, double y, int *dominant)
{
    if (s->lone != NULL) {
        *dominant = -1;
        return hf_point(s->lone, x, y);
    }
    const sea_heightfield *hf = surf_alone(s, x, y);
    if (hf != NULL) {
        *dominant = s->b.level;
        return hf_point(hf, x, y);
    }
    sea_moments o, n;
    double w, wn;
    chain_moments(s->f, s->b.level, x, y, &o, dominant, &w);
    if (s->b.neighbour >= 0 && s->b.alpha > 0.0) {
        int dn;
        chain_moments(s->f, s->b.neighbour, x, y, &n, &dn, &wn);
        sea_moments mix = { 0 };
        axpy(&mix, 1.0 - s->b.alpha, &o);
        axpy(&mix, s->b.alpha, &n);
        o = mix;
    }
    return o;
}

/* The range and gradient bound of the chain of levels from finest down
 * (the frame's levels and windows made), kept in f->ext[finest]. */
static mr_extent chain_extent(const sea_multires_frame *f, int finest)
{
    const sea_multires *mr = f->mr;
    mr_extent e = { 0.0, 0.0, 0.0 }; /* the low-resolution level ends every chain */
    /* The gradient of a chain sum_q c_q h_q, c_q = w_q prod_(p < q) (1 -
     * w_p): sum c_q grad h_q (sum c_q <= 1: at most the largest gmax) plus
     * sum h_q grad c_q, |grad c_q| <= sum_(p <= q) |grad w_p|, each fade
     * Lipschitz with its inv_band; the blend of two chains is convex. */
    double g = 0.0, bands = 0.0;
    int n = 0;
    for (int q = finest; q < mr->first_lr; q++) {
        if (!mr->used[q])
            continue;
        double lo, hi;
        sea_heightfield_range(f->hf[q], &lo, &hi);
        e.zlo = fmin(e.zlo, lo);
        e.zhi = fmax(e.zhi, hi);
        g = fmax(g, f->hf[q]->gmax);
        bands += f->win[q].inv_band;
        n++;
    }
    e.gmax = g + fmax(-e.zlo, e.zhi) * n * bands;
    return e;
}

/* The blend's levels' bounds (chain_extent, once a frame) and finest
 * facet. */
static void surface_init(surface *s, const sea_multires_frame *f, sea_level_blend b)
{
    const sea_multires *mr = f->mr;
    memset(s, 0, sizeof *s);
    s->f = f;
    s->b = b;
    int finest = b.neighbour >= 0 && b.alpha > 0.0 && b.neighbour < b.level ? b.neighbour
                                                                             : b.level;
    if (finest > mr->first_lr)
        finest = mr->first_lr;
    const mr_extent *e = &f->ext[finest];
    s->zlo = e->zlo;
    s->zhi = e->zhi;
    s->gmax = e->gmax;
    s->step_min = STEP_MIN_FACETS * mr->lev[finest].facet;
    if (!(b.neighbour >= 0 && b.alpha > 0.0) && b.level < mr->first_lr && mr->used[b.level]) {
        const mr_window *w = &f->win[b.level];
        const double m = mr->lev[b.level].facet;
        s->hf = f->hf[b.level];
        s->ax0 = w->fx0 + m;
        s->ay0 = w->fy0 + m;
        s->ax1 = w->fx1 - m;
        s->ay1 = w->fy1 - m;
    }
}

/* Where a level is read alone (surf_alone): for every high-resolution
 * level, at n points of its rectangle (and rectangles of up to 8 facets
 * from them), the heights, gradients, moments and bounds read that way
 * against the chain's sums.  Returns the number of points where any
 * differs in any bit (but for the sign of a zero: the chain's sums start
 * from +0, the same number to every use); *checked gets the points
 * compared. */
size_t sea_multires_alone_check(const sea_multires_frame *f, size_t n, size_t *checked)
{
    const sea_multires *mr = f->mr;
    uint64_t u = 0x9E3779B97F4A7C15u;
    size_t bad = 0, pts = 0;
    for (int l = 0; l < mr->first_lr; l++) {
        if (!mr->used[l])
            continue;
        surface s, c;
        surface_init(&s, f, (sea_level_blend){ l, -1, 0.0 });
        c = s;
        c.hf = NULL; /* the chain's sums */
        if (s.hf == NULL || !(s.ax0 < s.ax1 && s.ay0 < s.ay1))
            continue;
        const double m = mr->lev[l].facet;
        for (size_t k = 0; k < n; k++) {
            double r[4];
            for (int q = 0; q < 4; q++) {
                u = u * 6364136223846793005u + 1442695040888963407u;
                r[q] = (double)(u >> 11) * 0x1p-53;
            }
            const double x = s.ax0 + r[0] * (s.ax1 - s.ax0), y = s.ay0 + r[1] * (s.ay1 - s.ay0);
            const double x1 = fmin(x + 8.0 * m * r[2], s.ax1), y1 = fmin(y + 8.0 * m * r[3], s.ay1);
            struct {
                double z, zg, gx, gy, lo, hi;
                sea_moments mo;
                int dom;
            } v[2];
            memset(v, 0, sizeof v); /* (the padding too: compared whole) */
            for (int w = 0; w < 2; w++) {
                const surface *t = w ? &c : &s;
                v[w].z = surf_height(t, x, y) + 0.0;
                v[w].zg = surf_height_grad(t, x, y, &v[w].gx, &v[w].gy) + 0.0;
                v[w].gx += 0.0;
                v[w].gy += 0.0;
                const sea_moments mo = surf_moments(t, x, y, &v[w].dom);
                axpy(&v[w].mo, 1.0, &mo);
                surf_bound(t, x, y, x1, y1, &v[w].lo, &v[w].hi);
            }
            bad += memcmp(&v[0], &v[1], sizeof v[0]) != 0;
            pts++;
        }
    }
    if (checked != NULL)
        *checked = pts;
    return bad;
}

/* The root in (0, 1) of the cubic Hermite interpolant of f on [a, a + h]
 * through fa > 0 >= fb with rates da < 0 and db < 0 (per unit t) when it
 * falls all along (then it has one root there): a few Newton steps from
 * the secant's root, kept while they stay inside.  -1 when it does not
 * fall all along. */
static double hermite_root(double fa, double da, double fb, double db, double h)
{
    const double m0 = da * h, m1 = db * h;
    if (!(m0 < 0.0 && m1 < 0.0))
        return -1.0;
    const double c2 = 3.0 * (fb - fa) - 2.0 * m0 - m1, c3 = 2.0 * (fa - fb) + m0 + m1;
    if (c3 < 0.0) { /* the rate's maximum inside must be negative too */
        const double u = -c2 / (3.0 * c3);
        if (u > 0.0 && u < 1.0 && !(m0 + u * (2.0 * c2 + 3.0 * u * c3) < 0.0))
            return -1.0;
    }
    double u = fa / (fa - fb);
    for (int k = 0; k < 3; k++) {
        const double p = fa + u * (m0 + u * (c2 + u * c3));
        const double dp = m0 + u * (2.0 * c2 + 3.0 * u * c3);
        const double un = u - p / dp;
        if (!(un > 0.0 && un < 1.0))
            break;
        u = un;
    }
    return u;
}

/* Illinois (modified regula falsi) on [a, b], f(a) > 0 >= f(b): the ray
 * length where it meets the surface.  With the rates da and db at the ends
 * (finite; NAN where unknown) the first sample is the root of the cubic
 * Hermite interpolant, where it has one: about 3 samples a crossing
 * instead of 4.6 on examples/mast.ini. */
static double refine(const surface *s, const ray *r, double a, double fa, double b, double fb,
                     double da, double db)
{
    const double tol_z = REFINE_REL_Z * s->step_min, tol_t = REFINE_REL_T * s->step_min;
    const double u0 = isfinite(da) && isfinite(db) ? hermite_root(fa, da, fb, db, b - a) : -1.0;
    int side = 0;
    for (int it = 0; it < REFINE_ITER_MAX && b - a > tol_t; it++) {
        double c = it == 0 && u0 > 0.0 ? a + (b - a) * u0 : b - fb * (b - a) / (fb - fa);
        if (!(c > a && c < b))
            c = 0.5 * (a + b);
        double x, y, z;
        ray_point(r, c, &x, &y, &z);
        const double fc = z - surf_height(s, x, y);
        if (fc > 0.0) {
            a = c;
            fa = fc;
            if (side == 1)
                fb *= 0.5;
            side = 1;
        } else {
            b = c;
            fb = fc;
            if (side == -1)
                fa *= 0.5;
            side = -1;
        }
        if (fabs(fc) <= tol_z)
            return c;
    }
    return b;
}

/* The ray's height above the surface at t, its point there (x, y, z) as
 * ray_point gives it, and its rate of change. */
static double above_at(const surface *s, const ray *r, double t, double x, double y, double z,
                       double *rate)
{
    double dz, dx, dy, gx, gy;
    ray_rate(r, t, &dz, &dx, &dy);
    const double h = surf_height_grad(s, x, y, &gx, &gy);
    *rate = dz - gx * dx - gy * dy;
    return z - h;
}

static double above(const surface *s, const ray *r, double t, double *rate)
{
    double x, y, z;
    ray_point(r, t, &x, &y, &z);
    return above_at(s, r, t, x, y, z, rate);
}

/* A step [a, b] at the finest scale over which the ray stays above the
 * surface at both ends but comes down toward it and leaves again (fa' < 0 <
 * fb'): the ray passes over a crest, and may graze it between the two
 * samples.  The minimum of the ray's height above the surface is located
 * from the cubic through the ends' values and rates, a few times over the
 * shrinking bracket; returns 1 and *tc with f(tc) <= 0 when the ray dips
 * under the crest there. */
static int graze(const surface *s, const ray *r, double a, double fa, double da, double b,
                 double fb, double db, double *tc, double *fc)
{
    for (int it = 0; it < GRAZE_ITER_MAX; it++) {
        /* cubic Hermite of f on [a, b] in u = (t - a) / h; its derivative
         * is the quadratic c1 + 2 c2 u + 3 c3 u^2 */
        const double h = b - a, m0 = da * h, m1 = db * h;
        const double c1 = m0, c2 = 3.0 * (fb - fa) - 2.0 * m0 - m1, c3 = 2.0 * (fa - fb) + m0 + m1;
        double u = 0.5;
        if (fabs(c3) > 1e-300) {
            const double disc = c2 * c2 - 3.0 * c3 * c1;
            if (disc >= 0.0) {
                const double q = -(c2 + copysign(sqrt(disc), c2));
                const double u1 = q / (3.0 * c3), u2 = q != 0.0 ? c1 / q : u1;
                /* the root where the derivative goes from - to + */
                u = (u1 > 0.0 && u1 < 1.0 && 2.0 * c2 + 6.0 * c3 * u1 > 0.0) ? u1 : u2;
            }
        } else if (c2 > 0.0) {
            u = -c1 / (2.0 * c2);
        }
        if (!(u > 0.0 && u < 1.0))
            u = 0.5;
        const double t = a + u * h;
        double d;
        const double f = above(s, r, t, &d);
        if (f <= 0.0) {
            *tc = t;
            *fc = f;
            return 1;
        }
        if (d < 0.0) {
            a = t;
            fa = f;
            da = d;
        } else {
            b = t;
            fb = f;
            db = d;
        }
        /* far above the surface compared with the bracket's slope change:
         * no dip */
        if (fmin(fa, fb) > 0.5 * (db - da) * (b - a))
            return 0;
    }
    return 0;
}

/* The first crossing of the surface by the ray in [t_a, t_b]: the ray
 * steps along, doubling its step while it stays above the surface's bounds
 * under the step and dropping it fourfold where it does not, down to
 * step_min, where it samples the surface (height and rate); a sign change,
 * or a dip under a crest between two samples (graze), is refined.  Returns
 * 1 and *t. */
static int march(const surface *s, const ray *r, double t_a, double t_b, double *t_hit)
{
    double t = t_a, x, y, z, f = 0.0, df = 0.0;
    ray_point(r, t, &x, &y, &z);
    double ell = STEP_START * s->step_min;
    int have_f = 0;
    /* spherical: where the ray is lowest (it rises beyond) */
    const double t_low =
        r->sphere ? -(SEA_EARTH_RADIUS + r->o[2]) * r->d[2] : INFINITY;
    for (long it = 0; it < MARCH_ITER_MAX && t < t_b; it++) {
        double t1 = r->dh > 0.0 ? t + ell / r->dh : t_b;
        if (!(t1 < t_b))
            t1 = t_b;
        double x1, y1, z1;
        ray_point(r, t1, &x1, &y1, &z1);
        double zmin = min2(z, z1);
        if (t_low > t && t_low < t1) {
            double xl, yl, zl;
            ray_point(r, t_low, &xl, &yl, &zl);
            zmin = min2(zmin, zl);
        }
        double lo, hi;
        surf_bound(s, min2(x, x1), min2(y, y1), max2(x, x1), max2(y, y1), &lo, &hi);
        if (zmin > hi) { /* clear of the surface over the whole step */
            t = t1;
            x = x1;
            y = y1;
            z = z1;
            have_f = 0;
            ell *= 2.0;
            continue;
        }
        double th;
        if (z > hi && t < t_low && ray_t_at(r, hi, 1, &th) && th > t && th < t1) {
            /* above the bounds until th: go there */
            t = th;
            ray_point(r, t, &x, &y, &z);
            have_f = 0;
            continue;
        }
        if (ell > s->step_min) {
            ell = max2(0.25 * ell, s->step_min);
            continue;
        }
        if (!have_f) {
            f = above_at(s, r, t, x, y, z, &df);
            have_f = 1;
            if (f <= 0.0) {
                *t_hit = t;
                return 1;
            }
        }
        double df1;
        const double f1 = above_at(s, r, t1, x1, y1, z1, &df1);
        if (f1 <= 0.0) {
            *t_hit = refine(s, r, t, f, t1, f1, df, df1);
            return 1;
        }
        double tc, fc;
        if (df < 0.0 && df1 > 0.0 && graze(s, r, t, f, df, t1, f1, df1, &tc, &fc)) {
            *t_hit = refine(s, r, t, f, tc, fc, NAN, NAN);
            return 1;
        }
        t = t1;
        x = x1;
        y = y1;
        z = z1;
        f = f1;
        df = df1;
    }
    return 0;
}

/* The ray's search range: from where it comes down to the surface's top to
 * where it passes below its bottom (or, spherical, leaves its band again). */
static int ray_range(const surface *s, const ray *r, double *t_a, double *t_b)
{
    if (!ray_t_at(r, s->zhi, 1, t_a))
        return 0;
    if (ray_t_at(r, s->zlo, 1, t_b))
        return 1;
    return r->sphere && ray_t_at(r, s->zhi, 0, t_b);
}

int sea_heightfield_trace(const sea_heightfield *hf, const double o[3], const double d[3],
                          double tmax, double *t)
{
    surface s;
    memset(&s, 0, sizeof s);
    s.lone = hf;
    sea_heightfield_range(hf, &s.zlo, &s.zhi);
    s.step_min = STEP_MIN_FACETS * hf->L;
    s.gmax = hf->gmax;
    ray r;
    memcpy(r.o, o, sizeof r.o);
    memcpy(r.d, d, sizeof r.d);
    r.sphere = 0;
    r.dh = sqrt(d[0] * d[0] + d[1] * d[1]);
    r.ux = r.dh > 0.0 ? d[0] / r.dh : 0.0;
    r.uy = r.dh > 0.0 ? d[1] / r.dh : 0.0;
    double t_a, t_b;
    if (!ray_range(&s, &r, &t_a, &t_b))
        return 0;
    /* within the lattice's rectangle */
    const double X[2] = { (double)hf->i0 * hf->L, (double)(hf->i0 + (long)hf->nx) * hf->L };
    const double Y[2] = { (double)hf->j0 * hf->L, (double)(hf->j0 + (long)hf->ny) * hf->L };
    const double *lim[2] = { X, Y };
    for (int a = 0; a < 2; a++) {
        if (d[a] == 0.0) {
            if (o[a] < lim[a][0] || o[a] > lim[a][1])
                return 0;
            continue;
        }
        double ta = (lim[a][0] - o[a]) / d[a], tb = (lim[a][1] - o[a]) / d[a];
        if (ta > tb) {
            const double tmp = ta;
            ta = tb;
            tb = tmp;
        }
        t_a = fmax(t_a, ta);
        t_b = fmin(t_b, tb);
    }
    t_b = fmin(t_b, tmax);
    t_a = fmax(t_a, 0.0);
    if (!(t_a <= t_b))
        return 0;
    return march(&s, &r, t_a, t_b, t);
}

/* ------------------------------------------------------------- the plan */

void sea_multires_drop_pixels(sea_multires *mr)
{
    free(mr->px);
    mr->px = NULL;
}

void sea_multires_free(sea_multires *mr)
{
    if (mr == NULL)
        return;
    sea_waves_free(mr->waves);
    free(mr->px);
    free(mr);
}

size_t sea_multires_fallback(const sea_multires *mr, size_t *grid_needed)
{
    if (grid_needed != NULL)
        *grid_needed = mr->grid_needed;
    return mr->fallback;
}

size_t sea_multires_levels(const sea_multires *mr, const sea_clip_level **levels)
{
    *levels = mr->compact;
    return mr->ncompact;
}

const sea_waves *sea_multires_waves(const sea_multires *mr)
{
    return mr->waves;
}

sea_moments sea_multires_lr_moments(const sea_multires *mr)
{
    return mr->lr;
}

const sea_camera *sea_multires_camera(const sea_multires *mr)
{
    return &mr->cam;
}

static void to_moments(const sea_slope_stats *st, sea_moments *m)
{
    m->mx = st->mean.x;
    m->my = st->mean.y;
    m->mxx = st->mean.x * st->mean.x + st->cov.xx;
    m->mxy = st->mean.x * st->mean.y + st->cov.xy;
    m->myy = st->mean.y * st->mean.y + st->cov.yy;
    m->h = 0.0;
}

/* The levels a footprint of log2(F / L0) = lam reads: the nearest level,
 * blended with its neighbour (weight alpha, up to 1/2 at the midpoint)
 * within BLEND_HALF of the midpoint between them.  Every low-resolution
 * level is the same surface (m = 0, C = C_LR), so levels from first_lr on
 * are first_lr; a neighbour equal to the level is none (-1, alpha 0). */
static sea_level_blend choose_levels(const sea_multires *mr, double lam)
{
    const double c = fmin(fmax(lam, 0.0), (double)LEVEL_MAX);
    int l = (int)lround(c);
    const double d = lam - l;
    int nb = -1;
    double a = 0.0;
    if (fabs(d) > 0.5 - BLEND_HALF) {
        nb = l + (d > 0.0 ? 1 : -1);
        a = fmin(0.5 * (fabs(d) - (0.5 - BLEND_HALF)) / BLEND_HALF, 0.5);
        if (nb < 0 || nb > LEVEL_MAX) {
            nb = -1;
            a = 0.0;
        }
    }
    if (l > mr->first_lr)
        l = mr->first_lr;
    if (nb > mr->first_lr)
        nb = mr->first_lr;
    if (nb == l) {
        nb = -1;
        a = 0.0;
    }
    return (sea_level_blend){ l, nb, a };
}

static unsigned char count_of(double n, double cap)
{
    return (unsigned char)fmin(fmax(n, 1.0), cap);
}

/* What a pixel of mean-surface geometry g reads; how many rays it sends
 * along each image axis and how many points of the footprint each ray
 * averages (the footprint's extent over RAY_SPACING facets of its level,
 * and over POINT_SPACING facets of the finest level it reads, rounded up
 * beyond a quarter). */
static void pixel_choice(const sea_multires *mr, const sea_pixel_geom *g, mr_pixel *p)
{
    const double L0 = mr->sc.finest;
    p->hit = g->hit;
    p->x = g->x;
    p->y = g->y;
    memcpy(p->eu, g->edge_u, sizeof p->eu);
    memcpy(p->ev, g->edge_v, sizeof p->ev);
    double lam = (double)LEVEL_MAX;
    if (isfinite(g->footprint)) {
        const double along = fmax(g->footprint_u, g->footprint_v);
        lam = log2(fmax(g->footprint, along / (0.5 * SUB_MAX * RAY_POINTS_MAX)) / L0);
    }
    const sea_level_blend b = choose_levels(mr, lam);
    p->level = b.level;
    p->neighbour = b.neighbour;
    p->alpha = b.alpha;
    p->need = 0;
    p->nu = p->nv = p->ku = p->kv = 1;
    if (!g->hit)
        return;
    p->need = (uint32_t)1 << p->level;
    if (p->neighbour >= 0)
        p->need |= (uint32_t)1 << p->neighbour;
    /* (a pixel whose level is low-resolution but whose neighbour is not
     * reads that neighbour's facets: its footprint is averaged as at any
     * level, or the neighbour's mean slopes would be point-sampled) */
    const int reads_facets = p->level < mr->first_lr ||
                             (p->neighbour >= 0 && p->neighbour < mr->first_lr && p->alpha > 0.0);
    if (isfinite(g->footprint) && reads_facets) {
        const double L = mr->lev[p->level].facet;
        const int fine = p->neighbour >= 0 && p->neighbour < p->level ? p->neighbour : p->level;
        const double Lf = mr->lev[fine].facet;
        p->nu = count_of(ceil(g->footprint_u / (RAY_SPACING * L) - 0.25), SUB_MAX);
        p->nv = count_of(ceil(g->footprint_v / (RAY_SPACING * L) - 0.25), SUB_MAX);
        p->ku = count_of(ceil(g->footprint_u / (p->nu * POINT_SPACING * Lf) - 0.25),
                         RAY_POINTS_MAX);
        p->kv = count_of(ceil(g->footprint_v / (p->nv * POINT_SPACING * Lf) - 0.25),
                         RAY_POINTS_MAX);
    }
}

/* Median x and y of the ground points of the pixels that want level l
 * (of those that read it, if none wants it). */
static sea_status median_point(const sea_multires *mr, int l, double *mx, double *my,
                               sea_error *err)
{
    double *v = malloc(2 * mr->npix * sizeof(double));
    if (v == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu pixels", mr->npix);
    size_t n = 0;
    for (int pass = 0; pass < 2 && n == 0; pass++)
        for (size_t q = 0; q < mr->npix; q++) {
            const mr_pixel *p = &mr->px[q];
            if (!p->hit || (pass == 0 ? p->level != l : !(p->need & ((uint32_t)1 << l))))
                continue;
            v[n] = p->x;
            v[mr->npix + n] = p->y;
            n++;
        }
    if (n == 0) {
        free(v);
        *mx = *my = 0.0;
        return SEA_OK;
    }
    sea_select_kth_d(v, n, n / 2);
    sea_select_kth_d(v + mr->npix, n, n / 2);
    *mx = v[n / 2];
    *my = v[mr->npix + n / 2];
    free(v);
    return SEA_OK;
}

/* The cell indices floor(v / L) of a level's ground points must fit a long,
 * and stay exact in a double as the wave sampler checks them: beyond this
 * (a look point 1e16 m away at a look zenith 1e-13 deg short of 90) the
 * conversion would be undefined. */
static const double SEA_CELL_INDEX_MAX = 9.0e15;

static sea_status check_cells(int level, double L, double x, double y, sea_error *err)
{
    if (fabs(x / L) < SEA_CELL_INDEX_MAX && fabs(y / L) < SEA_CELL_INDEX_MAX)
        return SEA_OK;
    return sea_fail(err, SEA_ERR_DOMAIN,
                    "level %d: the sea it shows reaches (%.6g, %.6g) m, beyond the %.3g cells of "
                    "%g m its indices hold (allowed: a view whose sea, [sensor] x and y "
                    "included, lies within %.3g m of the map's origin)",
                    level, x, y, SEA_CELL_INDEX_MAX, L, SEA_CELL_INDEX_MAX * L);
}

/* The memory a view of npix pixels holds at once, checked as a whole
 * before anything is allocated (each array alone may fit while together
 * they do not: 16384^2 pixels need 22 GiB of geometry and 5 GiB of image).
 * The per-level moments and heights are bounded by the grid and checked
 * when known. */
static sea_status check_plan(size_t npix, sea_error *err)
{
    const double GiB = 1073741824.0;
    const double image = (double)npix * 5.0 * sizeof(float);       /* sea_image_alloc */
    const double geometry = (double)npix * (double)sizeof(mr_pixel); /* mr->px */
    const double scratch = (double)npix * 2.0 * sizeof(double);     /* median_point */
    const double need = image + geometry + scratch;
    const double avail = (double)sea_memory_available();
    if (need > avail)
        return sea_fail(err, SEA_ERR_NOMEM,
                        "the render of %zu pixels needs %.3g GiB (image %.3g, per-pixel geometry "
                        "%.3g, scratch %.3g GiB); this process may use %.3g GiB",
                        npix, need / GiB, image / GiB, geometry / GiB, scratch / GiB,
                        avail / GiB);
    return SEA_OK;
}

/* The low-resolution moments and each level's share of the slope variance
 * it generates; the first level whose share stays under the
 * low-resolution threshold is the low-resolution one.  *tr_lr: the trace
 * of the whole sea's slope covariance. */
static sea_status plan_levels(sea_multires *mr, double *tr_lr, sea_error *err)
{
    const sea_scene *sc = &mr->sc;
    sea_status st;
    sea_cov2 lr;
    if ((st = sea_spectrum_slope_cov(&mr->spec, 0.0, &lr, err)) != SEA_OK)
        return st;
    const sea_slope_stats lrs = { { 0.0, 0.0 }, lr };
    to_moments(&lrs, &mr->lr);
    const double L0 = sc->finest;

    /* low-resolution threshold: a thousandth of the tolerance, or for the
     * reference (every pixel at the level it asks for) where the longer
     * waves carry nothing a double can tell from none.  (At the tolerance
     * itself, the heights of the waves a level then drops still moved the
     * pixels near the horizon of mast.ini by up to 5.4 % and midwave.ini's by
     * 1.2 %; a wind sea's slope variance falls from 1e-5 to 1e-14 in an
     * octave beyond its peak, so the thousandth costs a level or none.) */
    *tr_lr = lr.xx + lr.yy;
    const double lr_share =
        sc->reference ? SEA_REFERENCE_LR_SHARE : SEA_LR_SHARE_OF_TOL * sc->tolerance;
    mr->first_lr = LEVEL_MAX;
    for (int l = 0; l <= LEVEL_MAX; l++) {
        sea_cov2 c;
        if ((st = sea_spectrum_slope_cov(&mr->spec, M_PI / (L0 * exp2(l)), &c, err)) != SEA_OK)
            return st;
        const double share = *tr_lr > 0.0 ? 1.0 - (c.xx + c.yy) / *tr_lr : 0.0;
        mr->lev[l].level = l;
        mr->lev[l].facet = L0 * exp2(l);
        mr->lev[l].generated_share = fmax(share, 0.0);
        if (share < lr_share && mr->first_lr == LEVEL_MAX)
            mr->first_lr = l;
    }
    return SEA_OK;
}

/* Per-pixel geometry and level choice, into mr->px (allocated).  Each
 * pixel corner is shared by four pixels: a thread finds the corners of
 * image line v = j + 1 once and keeps them for row j + 1
 * (sea_camera_pixel_cornered: the same geometry as sea_camera_pixel). */
static void plan_pixels(sea_multires *mr)
{
    const sea_camera *cam = &mr->cam;
    const size_t W = (size_t)cam->width, H = (size_t)cam->height;
#pragma omp parallel
    {
        /* (without memory for them, each pixel finds its own) */
        double *line = malloc(4 * (W + 1) * sizeof *line);
        unsigned char *met = malloc(2 * (W + 1));
        double *top = line, *bot = line != NULL ? line + 2 * (W + 1) : NULL;
        unsigned char *top_hit = met, *bot_hit = met != NULL ? met + W + 1 : NULL;
        size_t last = SIZE_MAX;
#pragma omp for schedule(dynamic, 8)
        for (size_t j = 0; j < H; j++) {
            if (line == NULL || met == NULL) {
                for (size_t i = 0; i < W; i++) {
                    sea_pixel_geom g;
                    sea_camera_pixel(cam, (double)i + 0.5, (double)j + 0.5, &g);
                    pixel_choice(mr, &g, &mr->px[j * W + i]);
                }
                continue;
            }
            if (last != SIZE_MAX && last + 1 == j) {
                double *sw = top;
                top = bot;
                bot = sw;
                unsigned char *sh = top_hit;
                top_hit = bot_hit;
                bot_hit = sh;
            } else {
                for (size_t i = 0; i <= W; i++)
                    top_hit[i] = (unsigned char)sea_camera_corner(cam, (double)i, (double)j,
                                                                  &top[2 * i], &top[2 * i + 1]);
            }
            for (size_t i = 0; i <= W; i++)
                bot_hit[i] = (unsigned char)sea_camera_corner(cam, (double)i, (double)(j + 1),
                                                              &bot[2 * i], &bot[2 * i + 1]);
            last = j;
            for (size_t i = 0; i < W; i++) {
                const double px[4] = { top[2 * i], top[2 * i + 2], bot[2 * i + 2], bot[2 * i] };
                const double py[4] = { top[2 * i + 1], top[2 * i + 3], bot[2 * i + 3],
                                       bot[2 * i + 1] };
                const int all = top_hit[i] && top_hit[i + 1] && bot_hit[i + 1] && bot_hit[i];
                sea_pixel_geom g;
                sea_camera_pixel_cornered(cam, (double)i + 0.5, (double)j + 0.5, px, py, all, &g);
                pixel_choice(mr, &g, &mr->px[j * W + i]);
            }
        }
        free(line);
        free(met);
    }
}

/* The levels some pixel reads (a level none reads is not scanned), as
 * bits, and each level's count of pixels that chose it. */
static uint32_t plan_needed(sea_multires *mr)
{
    uint32_t needed = 0;
    size_t count[LEVEL_MAX + 1] = { 0 };
#pragma omp parallel for schedule(static) reduction(| : needed) reduction(+ : count[:LEVEL_MAX + 1])
    for (size_t q = 0; q < mr->npix; q++) {
        needed |= mr->px[q].need;
        if (mr->px[q].hit)
            count[mr->px[q].level]++;
    }
    for (int l = 0; l <= LEVEL_MAX; l++)
        mr->lev[l].pixels = count[l];
    return needed;
}

/* The bounding box of the ground points of the pixels that read level l
 * (empty: xmin > xmax).  The level before's pixels in its window's fading
 * edge (or outside it), edge_lv unless NULL, read level l too: marked
 * here, their bits returned. */
static uint32_t level_bounds(sea_multires *mr, int l, const sea_clip_level *edge_lv,
                             double box[4])
{
    const uint32_t bit = (uint32_t)1 << l;
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    /* (on every thread: extremes are the same in any order) */
    uint32_t more = 0;
#pragma omp parallel for schedule(static) reduction(min : xmin, ymin) reduction(max : xmax, ymax) \
    reduction(| : more)
    for (size_t q = 0; q < mr->npix; q++) {
        mr_pixel *p = &mr->px[q];
        if (edge_lv != NULL && (p->need & (bit >> 1)) && edge_weight(edge_lv, p->x, p->y) < 1.0) {
            p->need |= bit;
            more |= bit;
        }
        if (!(p->need & bit))
            continue;
        xmin = min2(xmin, p->x);
        xmax = max2(xmax, p->x);
        ymin = min2(ymin, p->y);
        ymax = max2(ymax, p->y);
    }
    box[0] = xmin, box[1] = xmax, box[2] = ymin, box[3] = ymax;
    return more;
}

/* High-resolution level l's window from the bounding box of its pixels
 * (xmin > xmax: none), capped at grid x grid facets, or for a clipmap
 * grid x grid facets around the look point. */
static sea_status level_window(sea_multires *mr, int l, const double box[4], int clipmap,
                               double look_x, double look_y, sea_error *err)
{
    const sea_scene *sc = &mr->sc;
    sea_clip_level *lv = &mr->lev[l];
    const double xmin = box[0], xmax = box[1], ymin = box[2], ymax = box[3];
    sea_status st;
    const double L = lv->facet;
    /* grid = auto: as large as the level's pixels need, up to the
     * largest grid a scene may ask (a clipmap, which no pixel sizes,
     * keeps the old default) */
    size_t grid = sc->grid > 0 ? (size_t)sc->grid : clipmap ? 256 : SEA_GRID_AUTO_MAX;
    long i_lo, i_hi, j_lo, j_hi;
    if (xmin <= xmax) {
        st = check_cells(l, L, fmax(fabs(xmin), fabs(xmax)), fmax(fabs(ymin), fabs(ymax)), err);
        if (st != SEA_OK)
            return st;
        /* margin: the fading edge (see edge_weight) plus one facet, so
         * that a window that is not capped holds its pixels at full
         * weight */
        const double span = fmax(xmax - xmin, ymax - ymin) / L;
        const long margin = (long)ceil(fmax(2.0, (span + 2.0) / 14.0)) + 2;
        i_lo = (long)floor(xmin / L) - margin, i_hi = (long)floor(xmax / L) + margin;
        j_lo = (long)floor(ymin / L) - margin, j_hi = (long)floor(ymax / L) + margin;
        const size_t side = (size_t)(i_hi - i_lo + 1) > (size_t)(j_hi - j_lo + 1)
                                ? (size_t)(i_hi - i_lo + 1)
                                : (size_t)(j_hi - j_lo + 1);
        if (side > mr->grid_needed)
            mr->grid_needed = side + (side & 1);
    } else {
        /* No pixel reads this level (a clipmap window all the same):
         * the bounds stay infinite, and converting them is undefined. */
        i_lo = i_hi = j_lo = j_hi = 0;
    }
    if (clipmap) {
        /* concentric: grid x grid facets around the look point */
        if ((st = check_cells(l, L, look_x, look_y, err)) != SEA_OK)
            return st;
        i_lo = (long)floor(look_x / L) - (long)grid / 2;
        j_lo = (long)floor(look_y / L) - (long)grid / 2;
        i_hi = i_lo + (long)grid - 1;
        j_hi = j_lo + (long)grid - 1;
    } else if ((size_t)(i_hi - i_lo + 1) > grid || (size_t)(j_hi - j_lo + 1) > grid) {
        /* capped: centre on the median ground point of the pixels whose
         * footprint chose this level (the bounding box also holds
         * pixels pushed up from finer windows) */
        double cxm = 0.0, cym = 0.0;
        if ((st = median_point(mr, l, &cxm, &cym, err)) != SEA_OK ||
            (st = check_cells(l, L, cxm, cym, err)) != SEA_OK)
            return st;
        if ((size_t)(i_hi - i_lo + 1) > grid) {
            i_lo = (long)floor(cxm / L) - (long)grid / 2;
            i_hi = i_lo + (long)grid - 1;
        }
        if ((size_t)(j_hi - j_lo + 1) > grid) {
            j_lo = (long)floor(cym / L) - (long)grid / 2;
            j_hi = j_lo + (long)grid - 1;
        }
    }
    lv->i0 = i_lo;
    lv->j0 = j_lo;
    lv->nx = (size_t)(i_hi - i_lo + 1);
    lv->ny = (size_t)(j_hi - j_lo + 1);
    return SEA_OK;
}

/* High-resolution level l's sub-facets: 2^sub_n per side by the method,
 * and their share of the slope variance (tr_lr: the whole sea's). */
static sea_status level_sub_facets(sea_multires *mr, int l, double tr_lr, sea_error *err)
{
    const sea_scene *sc = &mr->sc;
    sea_clip_level *lv = &mr->lev[l];
    const double L = lv->facet;
    switch (sc->method) {
    case SEA_METHOD_VARIABLE_STEP: lv->sub_n = 0; break;
    case SEA_METHOD_VARIABLE_STEP_2N: lv->sub_n = sc->n < l ? sc->n : l; break;
    case SEA_METHOD_ONE_METER: lv->sub_n = l; break;
    }
    if (lv->sub_n > 0) {
        /* The sub-facets resolve the waves between L / 2^n and L: the
         * slope variance they move from C into the spread of the mean
         * slopes.  Below the tolerance of the total, variable-step-2n
         * skips them (one-meter is the reference and keeps them). */
        sea_cov2 c_l, c_fine;
        sea_status st;
        if ((st = sea_spectrum_slope_cov(&mr->spec, M_PI / L, &c_l, err)) != SEA_OK ||
            (st = sea_spectrum_slope_cov(&mr->spec, M_PI * exp2(lv->sub_n) / L, &c_fine,
                                         err)) != SEA_OK)
            return st;
        const double band = (c_l.xx + c_l.yy) - (c_fine.xx + c_fine.yy);
        lv->sub_share = tr_lr > 0.0 ? fmax(band, 0.0) / tr_lr : 0.0;
        if (sc->method == SEA_METHOD_VARIABLE_STEP_2N && lv->sub_share < sc->tolerance) {
            lv->sub_n = 0;
            lv->sub_skipped = 1;
        }
    }
    return SEA_OK;
}

/* Windows, finest first: the bounding box of the ground points that read
 * a level, capped at grid x grid facets around their centre.  Pixels
 * outside a window, or in its fading edge, read the next coarser level
 * too, so that level's window covers them.  *any_hr: 1 if some
 * high-resolution level is used; *fft_cells: the power of two (>= 2)
 * that spans every such level's window in cells of the finest size. */
static sea_status plan_windows(sea_multires *mr, double tr_lr, int *any_hr, size_t *fft_cells,
                               sea_error *err)
{
    const sea_scene *sc = &mr->sc;
    const sea_camera *cam = &mr->cam;
    sea_status st;
    uint32_t needed = plan_needed(mr);
    /* The centre of clipmap windows: where the optical axis meets the sea,
     * else the nadir point. */
    double look_x = cam->pos[0], look_y = cam->pos[1];
    {
        sea_pixel_geom g;
        sea_camera_pixel(cam, 0.5 * cam->width, 0.5 * cam->height, &g);
        if (g.hit) {
            look_x = g.x;
            look_y = g.y;
        }
    }
    /* the level before's pixels in its window's fading edge (or outside
     * it), which read this level too: found in this level's pass */
    const sea_clip_level *edge_lv = NULL; /* (level l - 1) */
    for (int l = 0; l <= LEVEL_MAX; l++) {
        sea_clip_level *lv = &mr->lev[l];
        const uint32_t bit = (uint32_t)1 << l;
        double box[4] = { INFINITY, -INFINITY, INFINITY, -INFINITY };
        if ((needed & bit) || edge_lv != NULL)
            needed |= level_bounds(mr, l, edge_lv, box);
        edge_lv = NULL;
        const int clipmap = sc->windows == SEA_WINDOWS_CLIPMAP && l < mr->first_lr;
        if (!(box[0] <= box[1]) && !clipmap)
            continue;
        mr->used[l] = 1;
        lv->low_res = l >= mr->first_lr;
        if (lv->low_res)
            continue;
        *any_hr = 1;
        if ((st = level_window(mr, l, box, clipmap, look_x, look_y, err)) != SEA_OK ||
            (st = level_sub_facets(mr, l, tr_lr, err)) != SEA_OK)
            return st;
        const size_t ext = (lv->nx > lv->ny ? lv->nx : lv->ny) << l;
        while (*fft_cells < ext)
            *fft_cells *= 2;
        if (l < LEVEL_MAX && (needed & bit))
            edge_lv = lv; /* (the next level's pass) */
    }
    return SEA_OK;
}

/* The pixels that fall back to a coarser level than they ask for, for
 * want of a larger grid. */
static size_t plan_fallback(const sea_multires *mr)
{
    size_t fb = 0;
#pragma omp parallel for schedule(static) reduction(+ : fb)
    for (size_t q = 0; q < mr->npix; q++) {
        const mr_pixel *p = &mr->px[q];
        if (!p->hit || p->level >= mr->first_lr)
            continue;
        const sea_clip_level *lv = &mr->lev[p->level];
        fb += edge_weight(lv, p->x, p->y) < 1.0;
    }
    return fb;
}

/* The waves the high-resolution levels read: a sum of components, or for
 * one-meter an FFT patch of fft_cells cells of the finest size. */
static sea_status plan_waves(sea_multires *mr, size_t fft_cells, sea_error *err)
{
    const sea_scene *sc = &mr->sc;
    const double L0 = sc->finest;
    sea_waves_params wp;
    sea_waves_params_default(&wp);
    wp.finest = L0;
    wp.seed = sc->seed;
    wp.loop_period = sc->loop_period;
    if (sc->method == SEA_METHOD_ONE_METER) {
        wp.kind = SEA_WAVES_FFT;
        if (fft_cells > 16384)
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "one-meter: the levels span %zu cells of %g m, beyond the "
                            "16384-cell FFT patch; use variable-step-2n or a smaller grid",
                            fft_cells, L0);
        wp.fft_size = fft_cells;
    }
    return sea_waves_alloc(&mr->spec, &wp, &mr->waves, err);
}

sea_status sea_multires_alloc(const sea_scene *sc, const sea_camera *cam, sea_multires **out,
                             sea_error *err)
{
    *out = NULL;
    sea_multires *mr = calloc(1, sizeof *mr);
    if (mr == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    mr->sc = *sc;
    mr->cam = *cam;
    sea_status st;
#define TRY(expr)                                                                                 \
    do {                                                                                          \
        if ((st = (expr)) != SEA_OK)                                                              \
            goto fail;                                                                            \
    } while (0)
    TRY(sea_scene_spectrum(sc, &mr->spec, err));
    double tr_lr;
    TRY(plan_levels(mr, &tr_lr, err));

    /* per-pixel geometry and level choice */
    mr->npix = (size_t)cam->width * (size_t)cam->height;
    TRY(check_plan(mr->npix, err));
    mr->px = malloc(mr->npix * sizeof(mr_pixel));
    if (mr->px == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu pixels", mr->npix);
        goto fail;
    }
    plan_pixels(mr);

    size_t fft_cells = 2;
    int any_hr = 0;
    TRY(plan_windows(mr, tr_lr, &any_hr, &fft_cells, err));
    /* Every pixel falls back to a coarser level when outside its window:
     * the low-resolution level closes the chain. */
    mr->used[mr->first_lr] = 1;
    mr->lev[mr->first_lr].low_res = 1;
    mr->fallback = plan_fallback(mr);
    if (any_hr)
        TRY(plan_waves(mr, fft_cells, err));
#undef TRY
    for (int l = 0; l < SEA_CLIP_MAX_LEVELS; l++)
        if (mr->used[l])
            mr->compact[mr->ncompact++] = mr->lev[l];
    *out = mr;
    return SEA_OK;
fail:
    sea_multires_free(mr);
    return st;
}

/* ------------------------------------------------------------ the frame */

void sea_multires_frame_free(sea_multires_frame *f)
{
    if (f == NULL)
        return;
    for (int l = 0; l < SEA_CLIP_MAX_LEVELS; l++)
        sea_heightfield_free(f->hf[l]);
    free(f);
}

static sea_status frame_alloc(const sea_multires *mr, double t, sea_progress_fn progress,
                              void *ctx, int lazy, sea_multires_frame **out, sea_error *err)
{
    *out = NULL;
    if (sea_time_check(t, err) != SEA_OK)
        return SEA_ERR_DOMAIN;
    sea_multires_frame *f = calloc(1, sizeof *f);
    if (f == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    f->mr = mr;
    f->t = t;
    double work = 0.0, done = 0.0;
    for (int l = 0; l < mr->first_lr; l++)
        if (mr->used[l])
            work += (double)(mr->lev[l].nx * mr->lev[l].ny);
    sea_status st = SEA_OK;
    for (int l = 0; l < mr->first_lr && st == SEA_OK; l++) {
        const sea_clip_level *lv = &mr->lev[l];
        if (!mr->used[l])
            continue;
        if ((st = sea_check_size(lv->nx * lv->ny, sizeof(sea_moments), "clipmap level", err)) !=
            SEA_OK)
            break;
        sea_moments *m = malloc(lv->nx * lv->ny * sizeof *m);
        if (m == NULL) {
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for level %d", l);
            break;
        }
        const sea_rect rect = { lv->facet, lv->i0, lv->j0, lv->nx, lv->ny };
        st = sea_waves_facets(mr->waves, &rect, lv->sub_n, t, m, err);
        /* kept as facets (sea_facet: the slopes in float), 16 bytes a
         * node less (400 MB at six levels of 2048^2) */
        sea_facet *facets = st == SEA_OK ? facets_of(m, lv->nx * lv->ny) : NULL;
        free(m);
        if (facets == NULL) {
            if (st == SEA_OK)
                st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for level %d", l);
            break;
        }
        st = hf_adopt(&rect, facets, lazy, &f->hf[l], err);
        const double L = lv->facet, band = edge_band(lv) * L;
        mr_window *w = &f->win[l];
        w->x0 = (double)lv->i0 * L;
        w->y0 = (double)lv->j0 * L;
        w->x1 = w->x0 + (double)lv->nx * L;
        w->y1 = w->y0 + (double)lv->ny * L;
        w->fx0 = w->x0 + band;
        w->fy0 = w->y0 + band;
        w->fx1 = w->x1 - band;
        w->fy1 = w->y1 - band;
        w->inv_band = 1.0 / band;
        done += (double)(lv->nx * lv->ny);
        if (st == SEA_OK && progress != NULL && progress(ctx, done / work) != 0)
            st = sea_fail(err, SEA_ERR_CANCELLED, "cancelled after synthesising level %d", l);
    }
    if (st != SEA_OK) {
        sea_multires_frame_free(f);
        return st;
    }
    for (int l = 0; l <= mr->first_lr; l++)
        f->ext[l] = chain_extent(f, l);
    *out = f;
    return SEA_OK;
}

sea_status sea_multires_frame_alloc(const sea_multires *mr, double t, sea_progress_fn progress,
                                    void *ctx, sea_multires_frame **out, sea_error *err)
{
    return frame_alloc(mr, t, progress, ctx, 0, out, err);
}

sea_status sea_multires_frame_alloc_lean(const sea_multires *mr, double t,
                                         sea_progress_fn progress, void *ctx,
                                         sea_multires_frame **out, sea_error *err)
{
    return frame_alloc(mr, t, progress, ctx, 1, out, err);
}

sea_facet *sea_multires_frame_flip_rows(sea_multires_frame *f, int level)
{
    sea_heightfield *hf = f->hf[level];
    const size_t nx = hf->nx, ny = hf->ny;
#pragma omp parallel for schedule(static)
    for (size_t j = 0; j < ny / 2; j++) {
        sea_facet *a = hf->m + j * nx, *b = hf->m + (ny - 1 - j) * nx;
        for (size_t i = 0; i < nx; i++) {
            const sea_facet t = a[i];
            a[i] = b[i];
            b[i] = t;
        }
    }
    return hf->m;
}

const sea_heightfield *sea_multires_frame_level(const sea_multires_frame *f, int level)
{
    if (level < 0 || level >= SEA_CLIP_MAX_LEVELS)
        return NULL;
    return f->hf[level];
}

/* ------------------------------------------------------------ the query */

/* A local direction at map point (x, y) of the camera's sea. */
static sea_dir local_dir_at(const sea_camera *cam, double x, double y, const double d[3],
                            double n[3], double q[3])
{
    sea_pixel_geom g;
    sea_camera_sea_point(cam, x, y, q, g.normal);
    if (n != NULL)
        memcpy(n, g.normal, sizeof g.normal);
    return sea_camera_local_dir(&g, d);
}

/* Whether ray B stays above the surface wherever a ray A of slope kA =
 * d_z / |d_h| and map direction (uxA, uyA) from the same sensor does (both
 * at one horizontal distance), as look_rays() explains: B above A by more than
 * the surface can rise between their map points. */
static int ray_above(const ray *B, double kA, double uxA, double uyA, double gmax)
{
    const double lift = B->d[2] / B->dh - kA;
    const double drift = hypot(B->ux - uxA, B->uy - uyA);
    return lift >= RAY_ORDER_MARGIN * gmax * drift;
}

static int same_blend(const sea_level_blend *a, const sea_level_blend *b)
{
    return a->level == b->level && a->neighbour == b->neighbour && a->alpha == b->alpha;
}

/* look()'s pixel that reads the low-resolution level alone: the flat mean
 * surface under its centre, no ray to march.  back: toward the sensor. */
static inline void look_flat(const sea_multires *mr, const mr_pixel *p, const double back[3],
                             sea_multires_sample *out)
{
    const sea_camera *cam = &mr->cam;
    double q[3];
    out->x = p->x;
    out->y = p->y;
    out->obs = local_dir_at(cam, p->x, p->y, back, out->normal, q);
    out->range = sqrt((q[0] - cam->pos[0]) * (q[0] - cam->pos[0]) +
                      (q[1] - cam->pos[1]) * (q[1] - cam->pos[1]) +
                      (q[2] - cam->pos[2]) * (q[2] - cam->pos[2]));
    out->moments = mr->lr;
    out->level = mr->first_lr;
    out->rays = 1;
}

/* The rays' hits, the lowest row of rays first.  At a horizontal
 * distance s from the sensor a ray of slope k = d_z / |d_h| and map
 * direction w = d_h / |d_h| is at z0 + k s over the map point o + s w.
 * A ray B above ray A (of the same column) by more than the surface can
 * rise between their map points, k_B - k_A >= RAY_ORDER_MARGIN gmax
 * |w_B - w_A| (both sides grow as s), stays above the surface wherever
 * A does, so B meets it no nearer than A did, and its march starts at
 * that horizontal distance (the same first hit: only the march's path
 * to it differs).  dc: the ray through the pixel centre (u, v); hit_t[k]:
 * where ray k met the surface, -1 if it did not. */
static inline void look_rays(const surface *s, const sea_camera *cam, double u, double v,
                             const double dc[3], const mr_pixel *p,
                             const sea_multires_hint *below, const sea_level_blend *blend,
                             ray *rays, double *hit_t)
{
    const int nu = p->nu, nv = p->nv;
    for (int b = nv - 1; b >= 0; b--)
        for (int a = 0; a < nu; a++) {
            const int k = b * nu + a;
            ray *r = &rays[k];
            /* the pixel's centre ray when the ray's image point is the
             * centre's, bit for bit (one ray at a pixel centre) */
            const double ur = u - 0.5 + (a + 0.5) / nu, vr = v - 0.5 + (b + 0.5) / nv;
            double d[3];
            if (ur == u && vr == v)
                memcpy(d, dc, sizeof d);
            else
                sea_camera_ray(cam, ur, vr, d);
            ray_init(r, cam, d);
            hit_t[k] = -1.0;
            double t_a, t_b, t;
            if (!ray_range(s, r, &t_a, &t_b))
                continue;
            /* the horizontal distance B's march may start at: A's hit */
            double s0 = -1.0;
            if (b + 1 < nv && hit_t[k + nu] >= 0.0 && r->dh > 0.0 && rays[k + nu].dh > 0.0) {
                const ray *A = &rays[k + nu];
                if (ray_above(r, A->d[2] / A->dh, A->ux, A->uy, s->gmax))
                    s0 = hit_t[k + nu] * A->dh;
            } else if (b + 1 == nv && below != NULL && below->n > 0 && r->dh > 0.0 &&
                       same_blend(&below->blend, blend)) {
                /* the pixel below's top rays, on the same surface */
                for (int m = 0; m < below->n; m++)
                    if (below->s[m] > s0 &&
                        ray_above(r, below->k[m], below->ux[m], below->uy[m], s->gmax))
                        s0 = below->s[m];
            }
            if (s0 >= 0.0) {
                const double t0 = s0 / r->dh;
                if (t0 >= t_b)
                    continue; /* above the surface over its whole range */
                t_a = fmax(t_a, t0);
            }
            if (march(s, r, t_a, t_b, &t))
                hit_t[k] = t;
        }
}

/* The top row of rays (nu of them), for the pixel above. */
static inline void look_top(const ray *rays, const double *hit_t, int nu,
                            const sea_level_blend *blend, sea_multires_hint *top)
{
    top->blend = *blend;
    for (int a = 0; a < nu; a++) {
        const ray *A = &rays[a];
        if (!(A->dh > 0.0))
            continue;
        top->k[top->n] = A->d[2] / A->dh;
        top->ux[top->n] = A->ux;
        top->uy[top->n] = A->uy;
        top->s[top->n] = hit_t[a] >= 0.0 ? hit_t[a] * A->dh : -1.0;
        top->n++;
    }
}

/* The pixel's moments, point met and height: each ray's share of the
 * footprint around the point it met, weighted by 1 / D when the pixel
 * has many rays (view azimuth cos cphi, sin sphi); or, when every ray
 * passed above the waves, what lies under the pixel centre's
 * mean-surface point. */
static inline void look_footprint(const surface *s, const mr_pixel *p, const ray *rays,
                                  const double *hit_t, double cphi, double sphi,
                                  sea_multires_sample *out)
{
    const int nu = p->nu, nv = p->nv, ku = p->ku, kv = p->kv, many = nu * nv > 1;
    sea_moments acc = { 0 };
    double wsum = 0.0, sx = 0.0, sy = 0.0, sz = 0.0;
    for (int b = 0; b < nv; b++)
        for (int a = 0; a < nu; a++) {
            const int k = b * nu + a;
            if (!(hit_t[k] >= 0.0))
                continue; /* passes above the waves (a grazing ray near the horizon) */
            const ray *r = &rays[k];
            double x, y, z;
            ray_point(r, hit_t[k], &x, &y, &z);
            /* the ray's share of the footprint, around the point it met:
             * ku x kv points, equal horizontal areas (LEAN's box filter) */
            sea_moments m = { 0 };
            for (int j = 0; j < kv; j++)
                for (int i = 0; i < ku; i++) {
                    const double ou = ((i + 0.5) / ku - 0.5) / nu, ov = ((j + 0.5) / kv - 0.5) / nv;
                    int dom;
                    const sea_moments q = surf_moments(s, x + ou * p->eu[0] + ov * p->ev[0],
                                                       y + ou * p->eu[1] + ov * p->ev[1], &dom);
                    axpy(&m, 1.0 / (ku * kv), &q);
                }
            double w = 1.0;
            if (many) {
                /* horizontal area per unit of projected area: 1 / D, of
                 * the slopes along the view (Eq 6: m_X and s_X from the
                 * moments, M_XX - m_X^2 = s_X^2) */
                const double mX = m.mx * cphi + m.my * sphi;
                const double MXX = m.mxx * cphi * cphi + 2.0 * m.mxy * cphi * sphi +
                                   m.myy * sphi * sphi;
                const double sX = sqrt(fmax(MXX - mX * mX, 0.0));
                w = 1.0 / fmax(sea_shadow_D(out->obs.theta, mX, sX), RAY_D_MIN);
            }
            axpy(&acc, w, &m);
            wsum += w;
            sx += w * x;
            sy += w * y;
            sz += w * z;
            out->rays++;
        }
    if (wsum > 0.0) {
        const double k = 1.0 / wsum;
        acc.mx *= k;
        acc.my *= k;
        acc.mxx *= k;
        acc.mxy *= k;
        acc.myy *= k;
        acc.h *= k;
        out->x = sx * k;
        out->y = sy * k;
        out->height = sz * k;
    } else {
        /* every ray passed above the waves: what lies under the mean-surface
         * point of the pixel centre */
        int dom;
        acc = surf_moments(s, p->x, p->y, &dom);
        out->x = p->x;
        out->y = p->y;
        out->height = acc.h;
    }
    out->moments = acc;
}

/* The range to the point met and the level the sample reports: the
 * pixel's, or its neighbour's where that weighs more. */
static inline void look_range_level(const sea_multires_frame *f, const mr_pixel *p,
                                    sea_multires_sample *out)
{
    const sea_camera *cam = &f->mr->cam;
    /* the point met: above the mean-surface point under it (the map
     * offset is at most a few hundred metres, along the ray's azimuth) */
    double q[3], n[3];
    sea_camera_sea_point(cam, out->x, out->y, q, n);
    for (int k = 0; k < 3; k++)
        q[k] += out->height * n[k];
    out->range = sqrt((q[0] - cam->pos[0]) * (q[0] - cam->pos[0]) +
                      (q[1] - cam->pos[1]) * (q[1] - cam->pos[1]) +
                      (q[2] - cam->pos[2]) * (q[2] - cam->pos[2]));
    double dw;
    chain_moments(f, p->level, out->x, out->y, NULL, &out->level, &dw);
    if (p->neighbour >= 0 && p->alpha > 0.0) {
        int dn;
        double wn;
        chain_moments(f, p->neighbour, out->x, out->y, NULL, &dn, &wn);
        if (p->alpha * wn > (1.0 - p->alpha) * dw)
            out->level = dn;
    }
}

/* One pixel's sample (per pixel, in the render's inner loop: its phases
 * are static inline so that the split costs no call). */
static void look(const sea_multires_frame *f, double u, double v, const mr_pixel *p,
                 const sea_multires_hint *below, sea_multires_hint *top,
                 sea_multires_sample *out)
{
    if (top != NULL)
        top->n = 0;
    const sea_multires *mr = f->mr;
    const sea_camera *cam = &mr->cam;
    memset(out, 0, sizeof *out);
    out->blend = (sea_level_blend){ p->level, p->neighbour, p->alpha };
    if (!p->hit)
        return;
    out->hit = 1;
    double dc[3], back[3];
    sea_camera_ray(cam, u, v, dc);
    for (int k = 0; k < 3; k++)
        back[k] = -dc[k];
    const int lr_only = p->level >= mr->first_lr &&
                        (p->neighbour < 0 || p->alpha <= 0.0 || p->neighbour >= mr->first_lr);
    if (lr_only) {
        look_flat(mr, p, back, out);
        return;
    }
    surface s;
    surface_init(&s, f, out->blend);
    const int many = p->nu * p->nv > 1;
    /* one local frame for the pixel, at its mean-surface point: its rays
     * and the points they meet are within a footprint (and the waves'
     * heights) of it, where the vertical of the sphere turns by 1e-5 rad at
     * most */
    double qm[3];
    out->obs = local_dir_at(cam, p->x, p->y, back, out->normal, qm);
    /* the view azimuth of the 1/D weights below (a pixel of one ray has
     * none) */
    double cphi = 1.0, sphi = 0.0;
    if (many) {
        cphi = cos(out->obs.phi);
        sphi = sin(out->obs.phi);
    }
    double hit_t[SUB_MAX * SUB_MAX];
    ray rays[SUB_MAX * SUB_MAX];
    look_rays(&s, cam, u, v, dc, p, below, &out->blend, rays, hit_t);
    if (top != NULL)
        look_top(rays, hit_t, p->nu, &out->blend, top);
    look_footprint(&s, p, rays, hit_t, cphi, sphi, out);
    look_range_level(f, p, out);
}

/* look() at image point (u, v) with its pixel's plan made now (as
 * sea_multires_alloc makes it at pixel centres, bit for bit). */
static void look_planned(const sea_multires_frame *f, double u, double v,
                         const sea_multires_hint *below, sea_multires_hint *top,
                         sea_multires_sample *out)
{
    sea_pixel_geom g;
    sea_camera_pixel(&f->mr->cam, u, v, &g);
    mr_pixel p;
    pixel_choice(f->mr, &g, &p);
    look(f, u, v, &p, below, top, out);
}

void sea_multires_pixel_hinted(const sea_multires_frame *f, int i, int j,
                               const sea_multires_hint *below, sea_multires_hint *top,
                               sea_multires_sample *out)
{
    const sea_multires *mr = f->mr;
    if (mr->px == NULL) { /* dropped (sea_multires_drop_pixels): the same plan, now */
        look_planned(f, (double)i + 0.5, (double)j + 0.5, below, top, out);
        return;
    }
    const mr_pixel *p = &mr->px[(size_t)j * (size_t)mr->cam.width + (size_t)i];
    look(f, (double)i + 0.5, (double)j + 0.5, p, below, top, out);
}

void sea_multires_pixel(const sea_multires_frame *f, int i, int j, sea_multires_sample *out)
{
    sea_multires_pixel_hinted(f, i, j, NULL, NULL, out);
}

void sea_multires_look(const sea_multires_frame *f, double u, double v, sea_multires_sample *out)
{
    look_planned(f, u, v, NULL, NULL, out);
}

int sea_multires_look_at(const sea_multires_frame *f, double x, double y, sea_multires_sample *out,
                         double *u, double *v)
{
    double q[3], n[3];
    sea_camera_sea_point(&f->mr->cam, x, y, q, n);
    memset(out, 0, sizeof *out);
    if (!sea_camera_project(&f->mr->cam, q, u, v))
        return 0;
    sea_multires_look(f, *u, *v, out);
    return out->hit;
}

sea_moments sea_multires_average(const sea_multires_frame *f, sea_level_blend b, size_t n,
                                 const double *x, const double *y, const double *w)
{
    surface s;
    surface_init(&s, f, b);
    sea_moments acc = { 0 };
    double wsum = 0.0;
    for (size_t k = 0; k < n; k++) {
        int dom;
        const sea_moments m = surf_moments(&s, x[k], y[k], &dom);
        axpy(&acc, w[k], &m);
        wsum += w[k];
    }
    if (wsum > 0.0) {
        const double k = 1.0 / wsum;
        acc.mx *= k;
        acc.my *= k;
        acc.mxx *= k;
        acc.mxy *= k;
        acc.myy *= k;
        acc.h *= k;
    }
    return acc;
}
