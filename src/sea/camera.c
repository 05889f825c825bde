/* camera.c - a pinhole sensor above a flat or spherical sea (seabake-model(7),
 * SENSOR, FOOTPRINTS AND CLIPMAP LEVELS; ROUND EARTH): pixel rays, where they
 * meet the sea, the local observation direction and the IRA projection size L
 * of each pixel.
 *
 * The footprint of a pixel is the quadrilateral its four corner rays cut on
 * the sea; L is the square root of its area, so L follows range, pixel
 * angle and local incidence together (L ~ range * pixel angle /
 * sqrt(cos theta) on a flat sea), and it grows without bound toward the
 * horizon. */
#include "config.h"

#include <math.h>

#include "seabake.h"
#include "internal.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize3(double a[3])
{
    const double n = sqrt(dot3(a, a));
    a[0] /= n;
    a[1] /= n;
    a[2] /= n;
}

sea_status sea_camera_init(double x, double y, double altitude, double look_zenith,
                           double look_azimuth, double roll, double hfov, int width,
                           int height, sea_earth earth, sea_camera *c, sea_error *err)
{
    if (!(fabs(x) <= SEA_SENSOR_XY_MAX && fabs(y) <= SEA_SENSOR_XY_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "sensor position (%g, %g) m outside [%g, %g] m", x,
                        y, -SEA_SENSOR_XY_MAX, SEA_SENSOR_XY_MAX);
    if (!(altitude > 0.0 && altitude <= 1e6))
        return sea_fail(err, SEA_ERR_DOMAIN, "sensor altitude %g m outside (0, 1e6]", altitude);
    if (!(look_zenith >= 0.0 && look_zenith < M_PI / 2.0))
        return sea_fail(err, SEA_ERR_DOMAIN, "look zenith %g deg outside [0, 90)",
                        look_zenith * 180.0 / M_PI);
    if (!isfinite(look_azimuth) || !isfinite(roll))
        return sea_fail(err, SEA_ERR_DOMAIN, "look azimuth and roll must be finite");
    /* (the scene's conversion of the bound, so that it is accepted) */
    if (!(hfov >= SEA_HFOV_MIN_DEG * (M_PI / 180.0) && hfov <= 170.0 * M_PI / 180.0))
        return sea_fail(err, SEA_ERR_DOMAIN, "horizontal field of view %g deg outside [%g, 170]",
                        hfov * 180.0 / M_PI, SEA_HFOV_MIN_DEG);
    if (width < 1 || width > 16384 || height < 1 || height > 16384)
        return sea_fail(err, SEA_ERR_DOMAIN, "image size %d x %d outside [1, 16384]", width,
                        height);
    if (earth != SEA_EARTH_FLAT && earth != SEA_EARTH_SPHERICAL)
        return sea_fail(err, SEA_ERR_DOMAIN, "unknown earth model %d", (int)earth);
    c->pos[0] = x;
    c->pos[1] = y;
    c->pos[2] = altitude;
    const double st = sin(look_zenith), ct = cos(look_zenith);
    const double sp = sin(look_azimuth), cp = cos(look_azimuth);
    c->fwd[0] = st * cp;
    c->fwd[1] = st * sp;
    c->fwd[2] = -ct;
    /* Right is horizontal, 90 deg clockwise from the look azimuth; up =
     * right x fwd, which at nadir points toward the look azimuth. */
    double r[3] = { sp, -cp, 0.0 }, u[3];
    cross3(r, c->fwd, u);
    normalize3(u);
    const double sr = sin(roll), cr = cos(roll);
    for (int i = 0; i < 3; i++) {
        c->right[i] = cr * r[i] + sr * u[i];
        c->up[i] = cr * u[i] - sr * r[i];
    }
    c->focal = 0.5 * (double)width / tan(0.5 * hfov);
    c->width = width;
    c->height = height;
    c->earth = earth;
    return SEA_OK;
}

void sea_camera_ray(const sea_camera *c, double u, double v, double d[3])
{
    const double a = u - 0.5 * c->width, b = v - 0.5 * c->height;
    for (int i = 0; i < 3; i++)
        d[i] = c->focal * c->fwd[i] + a * c->right[i] - b * c->up[i];
    normalize3(d);
}

/* Where ray d from the sensor meets the sea: point q (world), local normal
 * n, map coordinates (x, y), range t.  Returns 0 if it misses. */
static int intersect(const sea_camera *c, const double d[3], double q[3], double n[3],
                     double *x, double *y, double *t)
{
    if (c->earth == SEA_EARTH_FLAT) {
        if (!(d[2] < 0.0))
            return 0;
        *t = -c->pos[2] / d[2];
        for (int i = 0; i < 3; i++)
            q[i] = c->pos[i] + *t * d[i];
        q[2] = 0.0;
        n[0] = n[1] = 0.0;
        n[2] = 1.0;
        *x = q[0];
        *y = q[1];
        return isfinite(*t);
    }
    /* Sphere of radius R centred below the nadir point: |p + t d - C| = R
     * with p - C = (0, 0, R + h).  t^2 + 2 b t + cc = 0, b = (R + h) d_z,
     * cc = (R + h)^2 - R^2 = h (2R + h). */
    const double R = SEA_EARTH_RADIUS, h = c->pos[2];
    const double b = (R + h) * d[2], cc = h * (2.0 * R + h);
    const double disc = b * b - cc;
    if (!(disc >= 0.0) || b >= 0.0)
        return 0;
    /* nearer root, without cancellation: t = cc / (-b + sqrt(disc)) */
    *t = cc / (-b + sqrt(disc));
    const double pc[3] = { *t * d[0], *t * d[1], R + h + *t * d[2] }; /* from the centre */
    for (int i = 0; i < 3; i++)
        n[i] = pc[i] / R;
    normalize3(n);
    q[0] = c->pos[0] + pc[0];
    q[1] = c->pos[1] + pc[1];
    q[2] = pc[2] - R;
    /* azimuthal equidistant map coordinates from the nadir point */
    const double horiz = hypot(pc[0], pc[1]);
    const double arc = R * atan2(horiz, pc[2]);
    if (horiz > 0.0) {
        *x = c->pos[0] + arc * pc[0] / horiz;
        *y = c->pos[1] + arc * pc[1] / horiz;
    } else {
        *x = c->pos[0];
        *y = c->pos[1];
    }
    return 1;
}

int sea_camera_hits(const sea_camera *c, double u, double v)
{
    double x, y;
    return sea_camera_corner(c, u, v, &x, &y);
}

/* The local frame of a sea point of vertical n: east e (x projected on the
 * tangent plane: n is never along x for the scenes a sensor sees, its tilt
 * is at most a few degrees) and north nn = n x e. */
static void local_frame(const double n[3], double e[3], double nn[3])
{
    e[0] = 1.0 - n[0] * n[0];
    e[1] = -n[0] * n[1];
    e[2] = -n[0] * n[2];
    normalize3(e);
    cross3(n, e, nn);
}

sea_dir sea_camera_local_dir(const sea_pixel_geom *g, const double d[3])
{
    const double *n = g->normal;
    double e[3], nn[3];
    local_frame(n, e, nn);
    const double cz = fmax(-1.0, fmin(1.0, dot3(d, n)));
    sea_dir o = { acos(cz), atan2(dot3(d, nn), dot3(d, e)) };
    if (o.phi < 0.0)
        o.phi += 2.0 * M_PI;
    return o;
}

/* The footprint of g from its four corner points (map coordinates: corners
 * 0..3 at (u, v) + (-1/2, -1/2), (1/2, -1/2), (1/2, 1/2), (-1/2, 1/2)), or
 * none when a corner misses the sea (corners_hit 0). */
static void footprint_of(const double px[4], const double py[4], int corners_hit,
                         sea_pixel_geom *g)
{
    if (!corners_hit) {
        g->footprint = g->footprint_u = g->footprint_v = INFINITY;
        g->edge_u[0] = g->edge_u[1] = g->edge_v[0] = g->edge_v[1] = 0.0;
        return;
    }
    /* the quadrilateral of the four corner rays, area = half the cross
     * product of its diagonals, in map coordinates */
    const double ax = px[2] - px[0], ay = py[2] - py[0], bx = px[3] - px[1], by = py[3] - py[1];
    g->footprint = sqrt(0.5 * fabs(ax * by - ay * bx));
    /* edges along the image axes: the mean of the two edges along u
     * (corners 0 -> 1 and 3 -> 2) and along v (0 -> 3 and 1 -> 2) */
    g->edge_u[0] = 0.5 * (px[1] - px[0] + px[2] - px[3]);
    g->edge_u[1] = 0.5 * (py[1] - py[0] + py[2] - py[3]);
    g->edge_v[0] = 0.5 * (px[3] - px[0] + px[2] - px[1]);
    g->edge_v[1] = 0.5 * (py[3] - py[0] + py[2] - py[1]);
    g->footprint_u = hypot(g->edge_u[0], g->edge_u[1]);
    g->footprint_v = hypot(g->edge_v[0], g->edge_v[1]);
}

/* sea_camera_pixel up to the footprint: returns 0 for a sky pixel (g then
 * complete); without angles, g.ray and g.obs are left 0. */
static int pixel_centre(const sea_camera *c, double u, double v, int angles, sea_pixel_geom *g)
{
    double d[3], q[3];
    sea_camera_ray(c, u, v, d);
    g->hit = intersect(c, d, q, g->normal, &g->x, &g->y, &g->range);
    g->ray = g->obs = (sea_dir){ 0.0, 0.0 };
    if (angles) {
        const double cz = fmax(-1.0, fmin(1.0, d[2]));
        g->ray.theta = acos(cz);
        g->ray.phi = atan2(d[1], d[0]);
        if (g->ray.phi < 0.0)
            g->ray.phi += 2.0 * M_PI;
    }
    if (!g->hit) {
        g->x = g->y = g->range = 0.0;
        footprint_of(NULL, NULL, 0, g);
        g->normal[0] = g->normal[1] = 0.0;
        g->normal[2] = 1.0;
        return 0;
    }
    if (angles) {
        const double back[3] = { -d[0], -d[1], -d[2] };
        g->obs = sea_camera_local_dir(g, back);
    }
    return 1;
}

int sea_camera_corner(const sea_camera *c, double u, double v, double *x, double *y)
{
    double d[3], q[3], n[3], t;
    sea_camera_ray(c, u, v, d);
    return intersect(c, d, q, n, x, y, &t);
}

void sea_camera_pixel(const sea_camera *c, double u, double v, sea_pixel_geom *g)
{
    if (!pixel_centre(c, u, v, 1, g))
        return;
    double px[4], py[4];
    const double du[4] = { -0.5, 0.5, 0.5, -0.5 }, dv[4] = { -0.5, -0.5, 0.5, 0.5 };
    int all = 1;
    for (int k = 0; k < 4 && all; k++)
        all = sea_camera_corner(c, u + du[k], v + dv[k], &px[k], &py[k]);
    footprint_of(px, py, all, g);
}

void sea_camera_pixel_cornered(const sea_camera *c, double u, double v, const double px[4],
                               const double py[4], int corners_hit, sea_pixel_geom *g)
{
    if (pixel_centre(c, u, v, 0, g))
        footprint_of(px, py, corners_hit, g);
}

int sea_camera_project(const sea_camera *c, const double p[3], double *u, double *v)
{
    const double d[3] = { p[0] - c->pos[0], p[1] - c->pos[1], p[2] - c->pos[2] };
    const double z = dot3(d, c->fwd);
    if (!(z > 0.0))
        return 0;
    *u = 0.5 * c->width + c->focal * dot3(d, c->right) / z;
    *v = 0.5 * c->height - c->focal * dot3(d, c->up) / z;
    return 1;
}

/* Sea point of map coordinates (x, y) (sea_camera_pixel's mapping): world point q
 * and local vertical n.  Flat: (x, y, 0) and +z.  Spherical: the point of
 * the sphere through the nadir point at arc length |(x, y) - nadir| from
 * it, in the direction of (x, y) - nadir (azimuthal equidistant). */
void sea_camera_sea_point(const sea_camera *c, double x, double y, double q[3], double n[3])
{
    if (c->earth == SEA_EARTH_FLAT) {
        q[0] = x;
        q[1] = y;
        q[2] = 0.0;
        n[0] = n[1] = 0.0;
        n[2] = 1.0;
        return;
    }
    const double R = SEA_EARTH_RADIUS;
    const double dx = x - c->pos[0], dy = y - c->pos[1], arc = hypot(dx, dy);
    const double a = arc / R;
    const double horiz = R * sin(a);
    const double pc[3] = { arc > 0.0 ? horiz * dx / arc : 0.0, arc > 0.0 ? horiz * dy / arc : 0.0,
                           R * cos(a) }; /* from the centre */
    q[0] = c->pos[0] + pc[0];
    q[1] = c->pos[1] + pc[1];
    q[2] = pc[2] - R;
    for (int i = 0; i < 3; i++)
        n[i] = pc[i] / R;
}

void sea_camera_stokes_frame(const sea_camera *c, double u, double v, const double normal[3],
                             sea_dir obs, double *cos_2psi, double *sin_2psi)
{
    double d[3], e[3], nn[3], ev[3];
    sea_camera_ray(c, u, v, d);
    local_frame(normal, e, nn);
    /* e_v = (-cos theta cos phi, -cos theta sin phi, sin theta) locally */
    const double st = sin(obs.theta), ct = cos(obs.theta);
    const double sp = sin(obs.phi), cp = cos(obs.phi);
    for (int k = 0; k < 3; k++)
        ev[k] = -ct * cp * e[k] - ct * sp * nn[k] + st * normal[k];
    /* the image's up across the ray, and its right (d x up) */
    const double ud = dot3(c->up, d);
    const double up[3] = { c->up[0] - ud * d[0], c->up[1] - ud * d[1], c->up[2] - ud * d[2] };
    double right[3];
    cross3(d, up, right);
    const double a = dot3(ev, up), b = dot3(ev, right), h = a * a + b * b;
    *cos_2psi = h > 0.0 ? (a - b) * (a + b) / h : 1.0;
    *sin_2psi = h > 0.0 ? 2.0 * a * b / h : 0.0;
}
