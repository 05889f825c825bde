/* test_sensor.c - pinhole rays on a flat and a spherical sea, against
 * closed forms: range, observation angles, footprint size, projection. */
#include <string.h>

#include "unit.h"
#include "internal.h"

static sea_camera camera(double h, double zen_deg, double az_deg, double roll_deg,
                         double hfov_deg, int w, int hgt, sea_earth e)
{
    sea_camera c;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_camera_init(10.0, -20.0, h, zen_deg * DEG, az_deg * DEG, roll_deg * DEG,
                                          hfov_deg * DEG, w, hgt, e, &c, &err),
                          SEA_OK);
    return c;
}

/* Nadir view: the centre ray meets the sea below the sensor at range h,
 * seen from the zenith; a pixel there covers h/f metres (f the focal length
 * in pixels), exactly, on a flat sea. */
static void test_nadir(void)
{
    const sea_camera c = camera(389.0, 0.0, 90.0, 0.0, 60.0, 500, 400, SEA_EARTH_FLAT);
    sea_pixel_geom g;
    sea_camera_pixel(&c, 250.0, 200.0, &g);
    CU_ASSERT_EQUAL(g.hit, 1);
    ASSERT_ABS(g.x, 10.0, 1e-9);
    ASSERT_ABS(g.y, -20.0, 1e-9);
    ASSERT_REL(g.range, 389.0, 1e-12, 0.0);
    ASSERT_ABS(g.obs.theta, 0.0, 1e-9);
    const double f = 250.0 / tan(30.0 * DEG);
    ASSERT_REL(c.focal, f, 1e-12, 0.0);
    ASSERT_REL(g.footprint, 389.0 / f, 1e-9, 0.0);
    /* the top of the image points toward the look azimuth (north here) */
    sea_camera_pixel(&c, 250.0, 0.0, &g);
    CU_ASSERT(g.y > -20.0 + 100.0);
    ASSERT_ABS(g.x, 10.0, 1e-9);
    /* and the right edge is east */
    sea_camera_pixel(&c, 500.0, 200.0, &g);
    CU_ASSERT(g.x > 10.0 + 100.0);
}

/* Oblique view: at the image centre, range h / cos(theta), the sensor seen
 * at (theta, look azimuth + 180 deg), and a footprint of r/f across by
 * r/(f cos theta) along the view: L = r / (f sqrt(cos theta)) to O(1/f). */
static void test_oblique(void)
{
    const double h = 500.0, th = 36.0 * DEG;
    const sea_camera c = camera(h, 36.0, 30.0, 0.0, 40.0, 640, 480, SEA_EARTH_FLAT);
    sea_pixel_geom g;
    sea_camera_pixel(&c, 320.0, 240.0, &g);
    CU_ASSERT_EQUAL_FATAL(g.hit, 1);
    ASSERT_REL(g.range, h / cos(th), 1e-12, 0.0);
    ASSERT_ABS(g.obs.theta, th, 1e-12);
    ASSERT_ABS(g.obs.phi, 210.0 * DEG, 1e-12);
    ASSERT_ABS(g.x, 10.0 + h * tan(th) * cos(30.0 * DEG), 1e-8);
    ASSERT_ABS(g.y, -20.0 + h * tan(th) * sin(30.0 * DEG), 1e-8);
    ASSERT_REL(g.footprint, g.range / (c.focal * sqrt(cos(th))), 2.0 / c.focal, 0.0);
    /* footprints grow toward the top of the image (farther away) */
    sea_pixel_geom top, bottom;
    sea_camera_pixel(&c, 320.0, 10.0, &top);
    sea_camera_pixel(&c, 320.0, 470.0, &bottom);
    CU_ASSERT(top.footprint > g.footprint && g.footprint > bottom.footprint);
    CU_ASSERT(top.obs.theta > th && bottom.obs.theta < th);
}

/* Projection inverts the ray: every hit point lands back on its pixel. */
static void test_projection_round_trip(void)
{
    const sea_camera c = camera(120.0, 70.0, -45.0, 12.0, 75.0, 320, 200, SEA_EARTH_FLAT);
    double worst = 0.0;
    for (int v = 0; v <= 200; v += 20)
        for (int u = 0; u <= 320; u += 32) {
            sea_pixel_geom g;
            sea_camera_pixel(&c, u, v, &g);
            if (!g.hit)
                continue;
            const double p[3] = { g.x, g.y, 0.0 };
            double pu, pv;
            CU_ASSERT_FATAL(sea_camera_project(&c, p, &pu, &pv));
            worst = fmax(worst, fmax(fabs(pu - u), fabs(pv - v)));
        }
    CU_ASSERT(worst < 1e-6);
    /* points behind the camera do not project */
    const double behind[3] = { 10.0 - 1000.0 * cos(-45.0 * DEG), -20.0 - 1000.0 * sin(-45.0 * DEG), 0.0 };
    double pu, pv;
    CU_ASSERT_EQUAL(sea_camera_project(&c, behind, &pu, &pv), 0);
}

/* Roll by 90 deg turns the image axes: right' = up. */
static void test_roll(void)
{
    const sea_camera a = camera(100.0, 30.0, 0.0, 0.0, 50.0, 100, 100, SEA_EARTH_FLAT);
    const sea_camera b = camera(100.0, 30.0, 0.0, 90.0, 50.0, 100, 100, SEA_EARTH_FLAT);
    for (int i = 0; i < 3; i++) {
        ASSERT_ABS(b.right[i], a.up[i], 1e-12);
        ASSERT_ABS(b.up[i], -a.right[i], 1e-12);
        ASSERT_ABS(b.fwd[i], a.fwd[i], 1e-15);
    }
}

/* A spherical Earth: near nadir it is the flat sea; toward the horizon the
 * range and local zenith follow the triangle sensor-centre-point, and rays
 * above the dip angle acos(R/(R+h)) miss. */
static void test_spherical(void)
{
    const double R = SEA_EARTH_RADIUS, h = 20.0;
    const sea_camera flat = camera(h, 30.0, 0.0, 0.0, 10.0, 101, 101, SEA_EARTH_FLAT);
    const sea_camera sph = camera(h, 30.0, 0.0, 0.0, 10.0, 101, 101, SEA_EARTH_SPHERICAL);
    sea_pixel_geom gf, gs;
    sea_camera_pixel(&flat, 50.5, 50.5, &gf);
    sea_camera_pixel(&sph, 50.5, 50.5, &gs);
    ASSERT_REL(gs.range, gf.range, 1e-6, 0.0);
    /* the local vertical there is tilted by the arc angle d/R */
    ASSERT_ABS(gs.obs.theta - gf.obs.theta, hypot(gs.x - 10.0, gs.y + 20.0) / R, 1e-9);
    ASSERT_REL(gs.footprint, gf.footprint, 1e-5, 0.0);

    const double dip = acos(R / (R + h));
    const double zen = M_PI / 2.0 + dip; /* ray zenith of the horizon */
    sea_camera c;
    sea_error err;
    /* look just below the horizon: hits; the centre ray's nadir angle is
     * pi - zen - eps */
    const double eps = 2e-4;
    CU_ASSERT_EQUAL_FATAL(sea_camera_init(0.0, 0.0, h, M_PI - zen - eps, 0.0, 0.0, 1.0 * DEG, 11,
                                          11, SEA_EARTH_SPHERICAL, &c, &err),
                          SEA_OK);
    sea_pixel_geom g;
    sea_camera_pixel(&c, 5.5, 5.5, &g);
    CU_ASSERT_EQUAL_FATAL(g.hit, 1);
    /* triangle sensor-centre-point: |p - C| = R, |s - C| = R + h */
    const double nadir = M_PI - zen - eps; /* ray angle from the downward vertical */
    const double t_exact = (R + h) * cos(nadir) - sqrt(R * R - (R + h) * (R + h) * sin(nadir) * sin(nadir));
    ASSERT_REL(g.range, t_exact, 1e-9, 0.0);
    /* local zenith of the sensor seen from the point: sin(theta)/ (R + h) = sin(nadir) / R */
    ASSERT_ABS(g.obs.theta, asin((R + h) * sin(nadir) / R), 1e-7);
    CU_ASSERT(g.obs.theta > 89.0 * DEG);
    /* the map position is the arc length along the surface; the angle at
     * the centre is theta - nadir */
    const double alpha = M_PI - nadir - (M_PI - g.obs.theta);
    ASSERT_REL(hypot(g.x, g.y), R * alpha, 1e-6, 0.0);
    /* above the horizon: sky */
    sea_camera_pixel(&c, 5.5, -200.0, &g);
    CU_ASSERT_EQUAL(g.hit, 0);
    CU_ASSERT(isinf(g.footprint));
    CU_ASSERT(g.ray.theta < M_PI / 2.0);
    /* the flat sea is hit by the same ray, nearer */
    CU_ASSERT_EQUAL_FATAL(sea_camera_init(0.0, 0.0, h, M_PI - zen - eps, 0.0, 0.0, 1.0 * DEG, 11,
                                          11, SEA_EARTH_FLAT, &c, &err),
                          SEA_OK);
    sea_camera_pixel(&c, 5.5, 5.5, &g);
    ASSERT_REL(g.range, h / cos(nadir), 1e-12, 0.0);
    CU_ASSERT(g.range < t_exact);
}

/* A pixel's geometry from corners found once for the image
 * (sea_camera_corner, sea_camera_pixel_cornered, as the multiresolution
 * plan does) is sea_camera_pixel's, bit for bit but the angles it leaves
 * out (obs, ray): every pixel of a flat and a round-earth view whose
 * horizon crosses the image (sky pixels, pixels with a corner in the sky),
 * rolled. */
static void test_shared_corners(void)
{
    for (int e = 0; e < 2; e++) {
        const sea_camera c = camera(25.0, 86.0, 40.0, 7.0, 30.0, 61, 47,
                                    e ? SEA_EARTH_SPHERICAL : SEA_EARTH_FLAT);
        int mismatches = 0, sky = 0, cut = 0;
        for (int j = 0; j < 47; j++)
            for (int i = 0; i < 61; i++) {
                double px[4], py[4];
                const int ci[4] = { i, i + 1, i + 1, i }, cj[4] = { j, j, j + 1, j + 1 };
                int all = 1;
                for (int k = 0; k < 4; k++)
                    all &= sea_camera_corner(&c, ci[k], cj[k], &px[k], &py[k]);
                sea_pixel_geom a, b;
                memset(&a, 0, sizeof a);
                memset(&b, 0, sizeof b);
                sea_camera_pixel(&c, i + 0.5, j + 0.5, &a);
                sea_camera_pixel_cornered(&c, i + 0.5, j + 0.5, px, py, all, &b);
                a.obs = a.ray = (sea_dir){ 0.0, 0.0 };
                mismatches += memcmp(&a, &b, sizeof a) != 0;
                sky += !a.hit;
                cut += a.hit && !all;
            }
        CU_ASSERT_EQUAL(mismatches, 0);
        CU_ASSERT(sky > 0);
        CU_ASSERT(cut > 0);
    }
}

static void test_bad_camera(void)
{
    sea_camera c;
    sea_error err;
    CU_ASSERT_EQUAL(sea_camera_init(0, 0, 0.0, 0, 0, 0, 1.0, 10, 10, SEA_EARTH_FLAT, &c, &err),
                    SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "altitude") != NULL);
    CU_ASSERT_EQUAL(sea_camera_init(0, 0, 10, M_PI / 2, 0, 0, 1.0, 10, 10, SEA_EARTH_FLAT, &c, &err),
                    SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_camera_init(0, 0, 10, 0, 0, 0, 0.0, 10, 10, SEA_EARTH_FLAT, &c, &err),
                    SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_camera_init(0, 0, 10, 0, 0, 0, 1.0, 0, 10, SEA_EARTH_FLAT, &c, &err),
                    SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_camera_init(NAN, 0, 10, 0, 0, 0, 1.0, 10, 10, SEA_EARTH_FLAT, &c, &err),
                    SEA_ERR_DOMAIN);
}

int test_sensor_register(void)
{
    CU_pSuite s = CU_add_suite("sensor", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "nadir", test_nadir) || !CU_add_test(s, "oblique", test_oblique) ||
           !CU_add_test(s, "projection round trip", test_projection_round_trip) ||
           !CU_add_test(s, "roll", test_roll) ||
           !CU_add_test(s, "spherical Earth", test_spherical) ||
           !CU_add_test(s, "shared corners", test_shared_corners) ||
           !CU_add_test(s, "bad camera", test_bad_camera);
}
