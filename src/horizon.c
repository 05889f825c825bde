/* horizon.c - the low-resolution sea out to the horizon, for the exports
 * (sea_bake_horizon_make in seabake.h).
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
    const sea_render *r;
    const sea_camera *cam;
    sea_slope_stats lr;
    double sun[3];
    double x0, y0;
} hz_ctx;

/* The radiance seabake render gives a low-resolution pixel at the map
 * point (arc, az), in the images' units: across the air along the range
 * from the sensor to the point (sea_render_facet_seen).  At the horizon itself the view
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
    sea_status st = sea_render_facet_seen(c->r, &c->lr, obs, sun, len, &o, err);
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

sea_status sea_bake_horizon_make(const sea_render *r, double tol, sea_bake_horizon *h,
                                 sea_error *err)
{
    memset(h, 0, sizeof *h);
    if (!(tol >= 1e-5 && tol <= 0.1))
        return sea_fail(err, SEA_ERR_DOMAIN, "horizon: tolerance %g (allowed: 1e-5 to 0.1)", tol);
    const sea_scene *sc = sea_render_scene(r);
    hz_ctx c = { r, sea_render_camera(r), { { 0, 0 }, { 0, 0, 0 } }, { 0, 0, 0 }, 0, 0 };
    const sea_moments lrm = sea_render_lr_moments(r);
    c.lr = sea_moments_stats(&lrm);
    c.sun[0] = sin(sc->sun_zenith) * cos(sc->sun_azimuth);
    c.sun[1] = sin(sc->sun_zenith) * sin(sc->sun_azimuth);
    c.sun[2] = cos(sc->sun_zenith);
    c.x0 = h->x0 = c.cam->pos[0];
    c.y0 = h->y0 = c.cam->pos[1];

    double arc_max, lo, hi;
    int sky, nadir_seen;
    image_extent(c.cam, c.x0, c.y0, &arc_max, &sky, &lo, &hi, &nadir_seen);
    if (!(arc_max > 0.0))
        return sea_fail(err, SEA_ERR_DOMAIN, "horizon: no pixel corner of the image meets the sea");
    if (c.cam->earth == SEA_EARTH_SPHERICAL) {
        const double R = SEA_EARTH_RADIUS, hz = R * acos(R / (R + c.cam->pos[2]));
        arc_max = sky ? hz : fmin(hz, arc_max * (1.0 + 1e-3));
    } else {
        arc_max *= 1.0 + 1e-3;
    }
    const double phi_c = atan2(c.cam->fwd[1], c.cam->fwd[0]);
    h->full_turn = nadir_seen || !(hi - lo < M_PI);
    double az0, az1;
    if (h->full_turn) {
        az0 = phi_c - M_PI;
        az1 = phi_c + M_PI;
    } else {
        const double margin = 0.01 * (hi - lo) + 1e-3;
        az0 = phi_c + lo - margin;
        az1 = phi_c + hi + margin;
    }

    const size_t cap = SEA_HORIZON_MAX_NODES;
    h->arc = malloc(cap * sizeof *h->arc);
    h->az = malloc(cap * sizeof *h->az);
    double *grid = malloc(cap * cap * sizeof *grid);
    if (h->arc == NULL || h->az == NULL || grid == NULL) {
        free(grid);
        sea_bake_horizon_free(h);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the horizon grid");
    }
    /* Start: uniform in the view angle (the outermost ring exactly at
     * arc_max) and in azimuth. */
    const double t_max = view_angle(c.cam, arc_max);
    size_t na = HZ_START_ARC + 1, nz = HZ_START_AZ + 1;
    for (size_t i = 0; i < na; i++)
        h->arc[i] = i == 0 ? 0.0
                    : i + 1 == na
                        ? arc_max
                        : arc_of_angle(c.cam, t_max * (double)i / (double)(na - 1), arc_max);
    /* The exports need increasing arcs: a ring that rounds onto its
     * neighbour (or onto arc_max) is dropped. */
    size_t kept = 1;
    for (size_t i = 1; i + 1 < na; i++)
        if (h->arc[i] > h->arc[kept - 1] && h->arc[i] < arc_max)
            h->arc[kept++] = h->arc[i];
    h->arc[kept++] = arc_max;
    na = kept;
    for (size_t j = 0; j < nz; j++)
        h->az[j] = az0 + (az1 - az0) * (double)j / (double)(nz - 1);

    /* grid rows are arcs with a stride of cap: inserting a column moves
     * values within rows, inserting a row moves rows. */
    sea_status st = SEA_OK;
    sea_error first = { "" };
#pragma omp parallel for schedule(dynamic, 1) collapse(2)
    for (size_t i = 0; i < na; i++)
        for (size_t j = 0; j < nz; j++) {
            sea_error e1;
            if (hz_radiance(&c, h->arc[i], h->az[j], &grid[i * cap + j], &e1) != SEA_OK) {
#pragma omp critical(sea_horizon_error)
                if (st == SEA_OK) {
                    st = SEA_ERR_NUMERIC;
                    first = e1;
                }
            }
        }

    /* Per interval: passed (then only nodes new in the other direction are
     * tested again) and the largest error seen; per node: new since the
     * other direction's last pass. */
    double *mid = malloc(cap * cap * sizeof *mid);
    double *err_r = calloc(cap, sizeof *err_r), *err_c = calloc(cap, sizeof *err_c);
    unsigned char *ok_r = calloc(cap, 1), *ok_c = calloc(cap, 1), *new_r = calloc(cap, 1),
                  *new_c = calloc(cap, 1), *split = calloc(cap, 1);
    if (mid == NULL || err_r == NULL || err_c == NULL || ok_r == NULL || ok_c == NULL ||
        new_r == NULL || new_c == NULL || split == NULL)
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the horizon grid");
    const double px = 2.0 * atan(0.5 * c.cam->width / c.cam->focal) / c.cam->width;
    for (int pass = 0; pass < HZ_PASSES && st == SEA_OK; pass++) {
        size_t added = 0;
        /* radial intervals: midpoints at the azimuth nodes (an interval
         * that passed before: at the new ones; one that splits: at all) */
#pragma omp parallel for schedule(dynamic, 1)
        for (size_t i = 0; i < na - 1; i++) {
            const double am = 0.5 * (h->arc[i] + h->arc[i + 1]);
            double bad = ok_r[i] ? err_r[i] : 0.0;
            sea_error e1;
            int failed = 0;
            for (int fill = 0; fill < 2 && !failed; fill++) {
                for (size_t j = 0; j < nz && !failed; j++) {
                    const int untested = !ok_r[i] || new_c[j];
                    if (fill == 0 ? !untested : untested)
                        continue;
                    double L;
                    failed = hz_radiance(&c, am, h->az[j], &L, &e1) != SEA_OK;
                    mid[i * cap + j] = L;
                    const double lin = 0.5 * (grid[i * cap + j] + grid[(i + 1) * cap + j]);
                    bad = fmax(bad, fabs(L - lin) / fmax(L, 1e-300));
                }
                if (fill == 0) {
                    double geo = 0.0;
                    if (!ok_r[i] && c.cam->earth == SEA_EARTH_SPHERICAL) {
                        const double az = 0.5 * (az0 + az1);
                        double qa[3], qb[3], qm[3], n[3], ch[3];
                        sea_camera_sea_point(c.cam, c.x0 + h->arc[i] * cos(az),
                                             c.y0 + h->arc[i] * sin(az), qa, n);
                        sea_camera_sea_point(c.cam, c.x0 + h->arc[i + 1] * cos(az),
                                             c.y0 + h->arc[i + 1] * sin(az), qb, n);
                        sea_camera_sea_point(c.cam, c.x0 + am * cos(az), c.y0 + am * sin(az),
                                             qm, n);
                        for (int k = 0; k < 3; k++)
                            ch[k] = 0.5 * (qa[k] + qb[k]);
                        geo = seen_angle(c.cam, ch, qm) / (0.25 * px);
                    }
                    /* (a midpoint that rounds onto an end splits nothing) */
                    split[i] = (bad > tol || geo > 1.0) && na < cap && am > h->arc[i] &&
                               am < h->arc[i + 1];
                    if (!split[i] || !ok_r[i])
                        break; /* nothing left to fill */
                }
            }
            if (failed) {
#pragma omp critical(sea_horizon_error)
                if (st == SEA_OK) {
                    st = SEA_ERR_NUMERIC;
                    first = e1;
                }
            }
            err_r[i] = bad;
        }
        if (st != SEA_OK)
            break;
        memset(new_c, 0, nz);
        memset(new_r, 0, na);
        for (size_t i = na - 1; i-- > 0;) {
            ok_r[i] = 1;
            if (!split[i] || na + 1 > cap)
                continue;
            /* a row after row i: the rows below move down one */
            memmove(grid + (i + 2) * cap, grid + (i + 1) * cap, (na - i - 1) * cap * sizeof *grid);
            memcpy(grid + (i + 1) * cap, mid + i * cap, nz * sizeof *grid);
            insert_at(h->arc, na, i, 0.5 * (h->arc[i] + h->arc[i + 1]));
            /* interval i becomes two, untested; the new row is new */
            memmove(ok_r + i + 1, ok_r + i, na - 1 - i);
            memmove(err_r + i + 1, err_r + i, (na - 1 - i) * sizeof *err_r);
            ok_r[i] = ok_r[i + 1] = 0;
            err_r[i] = err_r[i + 1] = 0.0;
            memmove(new_r + i + 2, new_r + i + 1, na - i - 1);
            new_r[i + 1] = 1;
            na++;
            added++;
        }
        /* azimuthal intervals: midpoints at the arc nodes, likewise */
#pragma omp parallel for schedule(dynamic, 1)
        for (size_t j = 0; j < nz - 1; j++) {
            const double zm = 0.5 * (h->az[j] + h->az[j + 1]);
            double bad = ok_c[j] ? err_c[j] : 0.0;
            sea_error e1;
            int failed = 0;
            for (int fill = 0; fill < 2 && !failed; fill++) {
                for (size_t i = 0; i < na && !failed; i++) {
                    const int untested = !ok_c[j] || new_r[i];
                    if (fill == 0 ? !untested : untested)
                        continue;
                    double L;
                    failed = hz_radiance(&c, h->arc[i], zm, &L, &e1) != SEA_OK;
                    mid[j * cap + i] = L; /* column j's midpoints, by arc */
                    const double lin = 0.5 * (grid[i * cap + j] + grid[i * cap + j + 1]);
                    bad = fmax(bad, fabs(L - lin) / fmax(L, 1e-300));
                }
                if (fill == 0) {
                    split[j] = bad > tol && nz < cap && zm > h->az[j] && zm < h->az[j + 1];
                    if (!split[j] || !ok_c[j])
                        break;
                }
            }
            if (failed) {
#pragma omp critical(sea_horizon_error)
                if (st == SEA_OK) {
                    st = SEA_ERR_NUMERIC;
                    first = e1;
                }
            }
            err_c[j] = bad;
        }
        if (st != SEA_OK)
            break;
        memset(new_r, 0, na);
        memset(new_c, 0, nz);
        for (size_t j = nz - 1; j-- > 0;) {
            ok_c[j] = 1;
            if (!split[j] || nz + 1 > cap)
                continue;
            for (size_t i = 0; i < na; i++)
                insert_at(grid + i * cap, nz, j, mid[j * cap + i]);
            insert_at(h->az, nz, j, 0.5 * (h->az[j] + h->az[j + 1]));
            memmove(ok_c + j + 1, ok_c + j, nz - 1 - j);
            memmove(err_c + j + 1, err_c + j, (nz - 1 - j) * sizeof *err_c);
            ok_c[j] = ok_c[j + 1] = 0;
            err_c[j] = err_c[j + 1] = 0.0;
            memmove(new_c + j + 2, new_c + j + 1, nz - j - 1);
            new_c[j + 1] = 1;
            nz++;
            added++;
        }
        if (added == 0)
            break;
    }
    double worst = 0.0;
    for (size_t i = 0; st == SEA_OK && i + 1 < na; i++)
        worst = fmax(worst, err_r[i]);
    for (size_t j = 0; st == SEA_OK && j + 1 < nz; j++)
        worst = fmax(worst, err_c[j]);
    free(mid);
    free(err_r);
    free(err_c);
    free(ok_r);
    free(ok_c);
    free(new_r);
    free(new_c);
    free(split);
    if (st != SEA_OK) {
        if (first.msg[0] != '\0' && err != NULL)
            *err = first;
        free(grid);
        sea_bake_horizon_free(h);
        return st;
    }
    h->n_arc = na;
    h->n_az = nz;
    h->max_err = worst;
    h->radiance = malloc(na * nz * sizeof *h->radiance);
    if (h->radiance == NULL) {
        free(grid);
        sea_bake_horizon_free(h);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the horizon grid");
    }
    for (size_t i = 0; i < na; i++)
        memcpy(h->radiance + i * nz, grid + i * cap, nz * sizeof *grid);
    free(grid);
    return SEA_OK;
}
