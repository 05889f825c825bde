/* horizon.c - the low-resolution sea out to the horizon, for the exports
 * (sea_bake_horizon_alloc in seabake.h).
 *
 * A polar grid around the sensor's nadir point.  Its extent comes from the
 * image: the map points of the pixel corners and centres that meet the sea (the
 * farthest sets the last ring; on a sphere with sky in view the last ring
 * is the horizon itself), their azimuths (a sector, or the full turn).
 * The nodes start uniform in the sensor's view angle and in azimuth and are
 * refined where linear interpolation misses the radiance at an interval's
 * midpoint: each pass tests every interval of one direction at every node
 * of the other, and an interval that fails gets its midpoint, whose values
 * the test has just computed.  On a sphere a ring interval is also split
 * until the chord's midpoint projects within a quarter pixel of the
 * sphere's, so that the mesh's silhouette is the horizon's. */
#include "config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "seabake.h"

enum { HZ_START_ARC = 16, HZ_START_AZ = 16, HZ_PASSES = 64 };

typedef struct {
    const sea_view *r;
    const sea_camera *cam;
    sea_slope_stats lr;
    double sun[3];
    double x0, y0;
} hz_ctx;

/* The radiance seabake render gives a low-resolution pixel at the map
 * point (arc, az), in the images' units: across the air along the range
 * from the sensor to the point (sea_view_facet_seen).  At the horizon itself the view
 * is tangent: the local zenith angle is held just below 90 deg. */
static sea_status hz_radiance(const hz_ctx *c, double arc, double az, double *L, sea_error *err)
{
    double q[3], d[3];
    sea_pixel_geom g;
    sea_camera_sea_point(c->cam, c->x0 + arc * cos(az), c->y0 + arc * sin(az), q, g.normal);
    for (int k = 0; k < 3; k++)
        d[k] = c->cam->pos[k] - q[k];
    const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++)
        d[k] /= len;
    sea_dir obs = sea_camera_local_dir(&g, d);
    obs.theta = fmin(obs.theta, 89.999 * M_PI / 180.0);
    const sea_dir sun = sea_camera_local_dir(&g, c->sun);
    sea_facet_optics o;
    sea_status st = sea_view_facet_seen(c->r, &c->lr, obs, sun, len, &o, err);
    if (st == SEA_OK && !(isfinite(o.seen) && o.seen >= 0.0))
        st = sea_fail(err, SEA_ERR_NUMERIC, "horizon: radiance %g at %.6g m, azimuth %.6g deg",
                      o.seen, arc, az * 180.0 / M_PI);
    *L = o.seen;
    return st;
}

/* The sensor's angle from nadir to the sea point at map distance arc. */
static double view_angle(const sea_camera *cam, double arc)
{
    if (cam->earth == SEA_EARTH_FLAT)
        return atan2(arc, cam->pos[2]);
    const double R = SEA_EARTH_RADIUS, a = arc / R;
    /* the point, seen from the sensor: horizontal R sin a, down R(1-cos a) + h */
    return atan2(R * sin(a), R * (1.0 - cos(a)) + cam->pos[2]);
}

/* The map distance whose view angle is t, at most arc_max: on a flat sea
 * h tan t; on a sphere by bisection (monotonic up to the horizon) to a
 * tolerance relative to the result.  (One relative to arc_max left the
 * near rings all alike where arc_max was 1e17 m, a look zenith 1e-7 deg
 * short of 90: their arcs were not increasing.) */
static double arc_of_angle(const sea_camera *cam, double t, double arc_max)
{
    if (cam->earth == SEA_EARTH_FLAT)
        return fmin(cam->pos[2] * tan(t), arc_max);
    double lo = 0.0, hi = arc_max;
    for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; it++) {
        const double mid = 0.5 * (lo + hi);
        if (view_angle(cam, mid) < t)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Pixel-angle distance, as the sensor sees them, between world points p and q. */
static double seen_angle(const sea_camera *cam, const double p[3], const double q[3])
{
    double a[3], b[3];
    for (int k = 0; k < 3; k++) {
        a[k] = p[k] - cam->pos[k];
        b[k] = q[k] - cam->pos[k];
    }
    const double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                          a[0] * b[1] - a[1] * b[0] };
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                 a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

/* Extent from the pixels' corners and centres (a half-pixel lattice: on a
 * flat sea the centre of a pixel at the horizon meets the sea farther than
 * its lower corners): farthest map distance of a point on the sea, whether
 * a point sees the sky, and the azimuths' span about the camera's
 * horizontal look direction (lo, hi, radians from it). */
static void image_extent(const sea_camera *cam, double x0, double y0, double *arc_max, int *sky,
                         double *lo, double *hi, int *nadir_seen)
{
    const double phi_c = atan2(cam->fwd[1], cam->fwd[0]);
    double amax = 0.0, dlo = INFINITY, dhi = -INFINITY;
    int any_sky = 0;
    const int W = cam->width, H = cam->height;
#pragma omp parallel for schedule(static) reduction(max : amax, dhi) reduction(min : dlo)        \
    reduction(| : any_sky)
    for (int v = 0; v <= 2 * H; v++)
        for (int u = 0; u <= 2 * W; u++) {
            sea_pixel_geom g;
            sea_camera_pixel(cam, 0.5 * u, 0.5 * v, &g);
            if (!g.hit) {
                any_sky = 1;
                continue;
            }
            const double dx = g.x - x0, dy = g.y - y0, arc = hypot(dx, dy);
            amax = fmax(amax, arc);
            if (arc > 0.0) {
                double d = atan2(dy, dx) - phi_c;
                d = remainder(d, 2.0 * M_PI);
                dlo = fmin(dlo, d);
                dhi = fmax(dhi, d);
            }
        }
    *arc_max = amax;
    *sky = any_sky;
    *lo = dlo;
    *hi = dhi;
    double q[3], n[3], u, v;
    sea_camera_sea_point(cam, x0, y0, q, n);
    *nadir_seen = sea_camera_project(cam, q, &u, &v) && u >= 0.0 && u <= W && v >= 0.0 && v <= H;
}

void sea_bake_horizon_free(sea_bake_horizon *h)
{
    if (h == NULL)
        return;
    free(h->arc);
    free(h->az);
    free(h->radiance);
    memset(h, 0, sizeof *h);
}

/* Inserts value x after index i of the n-long array *a (capacity cap). */
static void insert_at(double *a, size_t n, size_t i, double x)
{
    memmove(a + i + 2, a + i + 1, (n - i - 1) * sizeof *a);
    a[i + 1] = x;
}

/* The refinement of a horizon grid: the grid (rows are arcs, with a
 * stride of cap: inserting a column moves values within rows, inserting
 * a row moves rows), the midpoints of the intervals under test, and per
 * interval whether it passed (then only nodes new in the other direction
 * are tested again) and the largest error seen; per node, whether it is
 * new since the other direction's last pass.  st and first: the first
 * failure of any thread. */
typedef struct {
    const hz_ctx *c;
    sea_bake_horizon *h;
    double tol, az0, az1;
    double px; /* a pixel's angle at the centre of the image, rad */
    size_t cap, na, nz;
    double *grid, *mid, *err_r, *err_c;
    unsigned char *ok_r, *ok_c, *new_r, *new_c, *split;
    sea_status st;
    sea_error first;
} hz_refine;

/* Keeps the first failure of the threads (e1) in z. */
static void hz_failed(hz_refine *z, const sea_error *e1)
{
#pragma omp critical(sea_horizon_error)
    if (z->st == SEA_OK) {
        z->st = SEA_ERR_NUMERIC;
        z->first = *e1;
    }
}

/* The map distance the grid reaches (*arc_max) and its azimuths [*az0,
 * *az1] (a full turn when the nadir point is seen or the view spans half
 * a turn or more: h->full_turn). */
static sea_status hz_range(const hz_ctx *c, sea_bake_horizon *h, double *arc_max, double *az0,
                           double *az1, sea_error *err)
{
    double lo, hi;
    int sky, nadir_seen;
    image_extent(c->cam, c->x0, c->y0, arc_max, &sky, &lo, &hi, &nadir_seen);
    if (!(*arc_max > 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN, "horizon: no pixel corner of the image meets the sea");
    if (c->cam->earth == SEA_EARTH_SPHERICAL) {
        const double R = SEA_EARTH_RADIUS, hz = R * acos(R / (R + c->cam->pos[2]));
        *arc_max = sky ? hz : fmin(hz, *arc_max * (1.0 + 1e-3));
    } else {
        *arc_max *= 1.0 + 1e-3;
    }
    const double phi_c = atan2(c->cam->fwd[1], c->cam->fwd[0]);
    h->full_turn = nadir_seen || !(hi - lo < M_PI);
    if (h->full_turn) {
        *az0 = phi_c - M_PI;
        *az1 = phi_c + M_PI;
    } else {
        const double margin = 0.01 * (hi - lo) + 1e-3;
        *az0 = phi_c + lo - margin;
        *az1 = phi_c + hi + margin;
    }
    return SEA_OK;
}

/* Start: uniform in the view angle (the outermost ring exactly at
 * arc_max) and in azimuth, into h->arc and h->az; the counts into z. */
static void hz_start(hz_refine *z, double arc_max)
{
    const sea_camera *cam = z->c->cam;
    sea_bake_horizon *h = z->h;
    const double t_max = view_angle(cam, arc_max);
    size_t na = HZ_START_ARC + 1, nz = HZ_START_AZ + 1;
    for (size_t i = 0; i < na; i++)
        h->arc[i] = i == 0 ? 0.0
                    : i + 1 == na
                        ? arc_max
                        : arc_of_angle(cam, t_max * (double)i / (double)(na - 1), arc_max);
    /* The exports need increasing arcs: a ring that rounds onto its
     * neighbour (or onto arc_max) is dropped. */
    size_t kept = 1;
    for (size_t i = 1; i + 1 < na; i++)
        if (h->arc[i] > h->arc[kept - 1] && h->arc[i] < arc_max)
            h->arc[kept++] = h->arc[i];
    h->arc[kept++] = arc_max;
    na = kept;
    for (size_t j = 0; j < nz; j++)
        h->az[j] = z->az0 + (z->az1 - z->az0) * (double)j / (double)(nz - 1);
    z->na = na;
    z->nz = nz;
}

/* The radiance at every start node. */
static void hz_fill(hz_refine *z)
{
    const size_t na = z->na, nz = z->nz, cap = z->cap;
#pragma omp parallel for schedule(dynamic, 1) collapse(2)
    for (size_t i = 0; i < na; i++)
        for (size_t j = 0; j < nz; j++) {
            sea_error e1;
            if (hz_radiance(z->c, z->h->arc[i], z->h->az[j], &z->grid[i * cap + j], &e1) !=
                SEA_OK)
                hz_failed(z, &e1);
        }
}

/* On a spherical earth, how far radial interval i (midpoint at arc am)
 * bends away from its chord: the angle the sensor sees between the
 * chord's middle and the interval's, in quarter pixels (> 1: split it);
 * 0 on a flat sea or for an interval tested before. */
static double hz_curvature(const hz_refine *z, size_t i, double am)
{
    const hz_ctx *c = z->c;
    const sea_bake_horizon *h = z->h;
    double geo = 0.0;
    if (!z->ok_r[i] && c->cam->earth == SEA_EARTH_SPHERICAL) {
        const double az = 0.5 * (z->az0 + z->az1);
        double qa[3], qb[3], qm[3], n[3], ch[3];
        sea_camera_sea_point(c->cam, c->x0 + h->arc[i] * cos(az), c->y0 + h->arc[i] * sin(az),
                             qa, n);
        sea_camera_sea_point(c->cam, c->x0 + h->arc[i + 1] * cos(az),
                             c->y0 + h->arc[i + 1] * sin(az), qb, n);
        sea_camera_sea_point(c->cam, c->x0 + am * cos(az), c->y0 + am * sin(az), qm, n);
        for (int k = 0; k < 3; k++)
            ch[k] = 0.5 * (qa[k] + qb[k]);
        geo = seen_angle(c->cam, ch, qm) / (0.25 * z->px);
    }
    return geo;
}

/* Radial intervals: midpoints at the azimuth nodes (an interval that
 * passed before: at the new ones; one that splits: at all); marks those
 * to split. */
static void hz_test_rows(hz_refine *z)
{
    const sea_bake_horizon *h = z->h;
    const size_t na = z->na, nz = z->nz, cap = z->cap;
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t i = 0; i < na - 1; i++) {
        const double am = 0.5 * (h->arc[i] + h->arc[i + 1]);
        double bad = z->ok_r[i] ? z->err_r[i] : 0.0;
        sea_error e1;
        int failed = 0;
        for (int fill = 0; fill < 2 && !failed; fill++) {
            for (size_t j = 0; j < nz && !failed; j++) {
                const int untested = !z->ok_r[i] || z->new_c[j];
                if (fill == 0 ? !untested : untested)
                    continue;
                double L;
                failed = hz_radiance(z->c, am, h->az[j], &L, &e1) != SEA_OK;
                z->mid[i * cap + j] = L;
                const double lin = 0.5 * (z->grid[i * cap + j] + z->grid[(i + 1) * cap + j]);
                bad = fmax(bad, fabs(L - lin) / fmax(L, 1e-300));
            }
            if (fill == 0) {
                const double geo = hz_curvature(z, i, am);
                /* (a midpoint that rounds onto an end splits nothing) */
                z->split[i] = (bad > z->tol || geo > 1.0) && na < cap && am > h->arc[i] &&
                              am < h->arc[i + 1];
                if (!z->split[i] || !z->ok_r[i])
                    break; /* nothing left to fill */
            }
        }
        if (failed)
            hz_failed(z, &e1);
        z->err_r[i] = bad;
    }
}

/* Inserts the rows of the radial intervals marked to split; returns how
 * many. */
static size_t hz_split_rows(hz_refine *z)
{
    sea_bake_horizon *h = z->h;
    const size_t cap = z->cap;
    size_t na = z->na, added = 0;
    memset(z->new_c, 0, z->nz);
    memset(z->new_r, 0, na);
    for (size_t i = na - 1; i-- > 0;) {
        z->ok_r[i] = 1;
        if (!z->split[i] || na + 1 > cap)
            continue;
        /* a row after row i: the rows below move down one */
        memmove(z->grid + (i + 2) * cap, z->grid + (i + 1) * cap,
                (na - i - 1) * cap * sizeof *z->grid);
        memcpy(z->grid + (i + 1) * cap, z->mid + i * cap, z->nz * sizeof *z->grid);
        insert_at(h->arc, na, i, 0.5 * (h->arc[i] + h->arc[i + 1]));
        /* interval i becomes two, untested; the new row is new */
        memmove(z->ok_r + i + 1, z->ok_r + i, na - 1 - i);
        memmove(z->err_r + i + 1, z->err_r + i, (na - 1 - i) * sizeof *z->err_r);
        z->ok_r[i] = z->ok_r[i + 1] = 0;
        z->err_r[i] = z->err_r[i + 1] = 0.0;
        memmove(z->new_r + i + 2, z->new_r + i + 1, na - i - 1);
        z->new_r[i + 1] = 1;
        na++;
        added++;
    }
    z->na = na;
    return added;
}

/* Azimuthal intervals: midpoints at the arc nodes, likewise. */
static void hz_test_cols(hz_refine *z)
{
    const sea_bake_horizon *h = z->h;
    const size_t na = z->na, nz = z->nz, cap = z->cap;
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t j = 0; j < nz - 1; j++) {
        const double zm = 0.5 * (h->az[j] + h->az[j + 1]);
        double bad = z->ok_c[j] ? z->err_c[j] : 0.0;
        sea_error e1;
        int failed = 0;
        for (int fill = 0; fill < 2 && !failed; fill++) {
            for (size_t i = 0; i < na && !failed; i++) {
                const int untested = !z->ok_c[j] || z->new_r[i];
                if (fill == 0 ? !untested : untested)
                    continue;
                double L;
                failed = hz_radiance(z->c, h->arc[i], zm, &L, &e1) != SEA_OK;
                z->mid[j * cap + i] = L; /* column j's midpoints, by arc */
                const double lin = 0.5 * (z->grid[i * cap + j] + z->grid[i * cap + j + 1]);
                bad = fmax(bad, fabs(L - lin) / fmax(L, 1e-300));
            }
            if (fill == 0) {
                z->split[j] = bad > z->tol && nz < cap && zm > h->az[j] && zm < h->az[j + 1];
                if (!z->split[j] || !z->ok_c[j])
                    break;
            }
        }
        if (failed)
            hz_failed(z, &e1);
        z->err_c[j] = bad;
    }
}

/* Inserts the columns of the azimuthal intervals marked to split;
 * returns how many. */
static size_t hz_split_cols(hz_refine *z)
{
    sea_bake_horizon *h = z->h;
    const size_t cap = z->cap, na = z->na;
    size_t nz = z->nz, added = 0;
    memset(z->new_r, 0, na);
    memset(z->new_c, 0, nz);
    for (size_t j = nz - 1; j-- > 0;) {
        z->ok_c[j] = 1;
        if (!z->split[j] || nz + 1 > cap)
            continue;
        for (size_t i = 0; i < na; i++)
            insert_at(z->grid + i * cap, nz, j, z->mid[j * cap + i]);
        insert_at(h->az, nz, j, 0.5 * (h->az[j] + h->az[j + 1]));
        memmove(z->ok_c + j + 1, z->ok_c + j, nz - 1 - j);
        memmove(z->err_c + j + 1, z->err_c + j, (nz - 1 - j) * sizeof *z->err_c);
        z->ok_c[j] = z->ok_c[j + 1] = 0;
        z->err_c[j] = z->err_c[j + 1] = 0.0;
        memmove(z->new_c + j + 2, z->new_c + j + 1, nz - j - 1);
        z->new_c[j + 1] = 1;
        nz++;
        added++;
    }
    z->nz = nz;
    return added;
}

/* Refines the grid until every interval passes, no interval can split
 * (the cap), HZ_PASSES passes, or a failure (z->st); returns the largest
 * error of an interval. */
static double hz_refine_grid(hz_refine *z, sea_error *err)
{
    const size_t cap = z->cap;
    z->mid = malloc(cap * cap * sizeof *z->mid);
    z->err_r = calloc(cap, sizeof *z->err_r);
    z->err_c = calloc(cap, sizeof *z->err_c);
    z->ok_r = calloc(cap, 1);
    z->ok_c = calloc(cap, 1);
    z->new_r = calloc(cap, 1);
    z->new_c = calloc(cap, 1);
    z->split = calloc(cap, 1);
    if (z->mid == NULL || z->err_r == NULL || z->err_c == NULL || z->ok_r == NULL ||
        z->ok_c == NULL || z->new_r == NULL || z->new_c == NULL || z->split == NULL)
        z->st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the horizon grid");
    z->px = 2.0 * atan(0.5 * z->c->cam->width / z->c->cam->focal) / z->c->cam->width;
    for (int pass = 0; pass < HZ_PASSES && z->st == SEA_OK; pass++) {
        hz_test_rows(z);
        if (z->st != SEA_OK)
            break;
        size_t added = hz_split_rows(z);
        hz_test_cols(z);
        if (z->st != SEA_OK)
            break;
        added += hz_split_cols(z);
        if (added == 0)
            break;
    }
    double worst = 0.0;
    for (size_t i = 0; z->st == SEA_OK && i + 1 < z->na; i++)
        worst = fmax(worst, z->err_r[i]);
    for (size_t j = 0; z->st == SEA_OK && j + 1 < z->nz; j++)
        worst = fmax(worst, z->err_c[j]);
    free(z->mid);
    free(z->err_r);
    free(z->err_c);
    free(z->ok_r);
    free(z->ok_c);
    free(z->new_r);
    free(z->new_c);
    free(z->split);
    return worst;
}

sea_status sea_bake_horizon_alloc(const sea_view *r, double tol, sea_bake_horizon *h,
                                 sea_error *err)
{
    memset(h, 0, sizeof *h);
    if (!(tol >= 1e-5 && tol <= 0.1))
        return sea_fail(err, SEA_ERR_DOMAIN, "horizon: tolerance %g (allowed: 1e-5 to 0.1)", tol);
    const sea_scene *sc = sea_view_scene(r);
    hz_ctx c = { r, sea_view_camera(r), { { 0, 0 }, { 0, 0, 0 } }, { 0, 0, 0 }, 0, 0 };
    const sea_moments lrm = sea_view_lr_moments(r);
    c.lr = sea_moments_stats(&lrm);
    c.sun[0] = sin(sc->sun_zenith) * cos(sc->sun_azimuth);
    c.sun[1] = sin(sc->sun_zenith) * sin(sc->sun_azimuth);
    c.sun[2] = cos(sc->sun_zenith);
    c.x0 = h->x0 = c.cam->pos[0];
    c.y0 = h->y0 = c.cam->pos[1];

    hz_refine z = { .c = &c, .h = h, .tol = tol, .cap = SEA_HORIZON_MAX_NODES, .st = SEA_OK,
                    .first = { "" } };
    double arc_max;
    sea_status st = hz_range(&c, h, &arc_max, &z.az0, &z.az1, err);
    if (st != SEA_OK)
        return st;
    const size_t cap = z.cap;
    h->arc = malloc(cap * sizeof *h->arc);
    h->az = malloc(cap * sizeof *h->az);
    z.grid = malloc(cap * cap * sizeof *z.grid);
    if (h->arc == NULL || h->az == NULL || z.grid == NULL) {
        free(z.grid);
        sea_bake_horizon_free(h);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the horizon grid");
    }
    hz_start(&z, arc_max);
    hz_fill(&z);
    const double worst = hz_refine_grid(&z, err);
    if (z.st != SEA_OK) {
        if (z.first.msg[0] != '\0' && err != NULL)
            *err = z.first;
        free(z.grid);
        sea_bake_horizon_free(h);
        return z.st;
    }
    const size_t na = z.na, nz = z.nz;
    h->n_arc = na;
    h->n_az = nz;
    h->max_err = worst;
    h->radiance = malloc(na * nz * sizeof *h->radiance);
    if (h->radiance == NULL) {
        free(z.grid);
        sea_bake_horizon_free(h);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the horizon grid");
    }
    for (size_t i = 0; i < na; i++)
        memcpy(h->radiance + i * nz, z.grid + i * cap, nz * sizeof *z.grid);
    free(z.grid);
    return SEA_OK;
}
