/* test_multires.c - the multiresolution sea (src/multires.c) against closed
 * forms: the resolved surface reproduces a plane and its projected area;
 * a sinusoid hides, at grazing angles, exactly the stretch the tangent
 * construction gives; LEAN footprint averages are exact; the query is one
 * function for the render and the bake, and heights stand along the local
 * vertical of the sphere; and the mean emissivity of grazing images at
 * 1 m facets against the low-resolution value. */
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "unit.h"

/* The moments of a facet centred at (x, y) on the surface z(x, y) with
 * slope (sx, sy) there and sub-facet covariance c. */
static sea_moments facet(double z, double sx, double sy, const sea_cov2 *c)
{
    sea_moments m = { sx, sy, sx * sx + c->xx, sx * sy + c->xy, sy * sy + c->yy, z };
    return m;
}

/* The gradient bound the marches order rays by (look: a ray above
 * another by more than the surface can rise between them starts at the
 * other's hit): on random heightfields of rough facets (independent
 * heights and slopes, the worst case for the patches' overshoot) and of a
 * smooth wave, the patch gradient at 2e5 random points (inside and beyond
 * the outer facet centres) never exceeds it, and it is not vacuous (within
 * 8 times the largest gradient met). */
static void test_gradient_bound(void)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 5);
    const sea_cov2 c = { 0.01, 0.01, 0.0 };
    double worst_ratio = 0.0, loosest = INFINITY;
    for (int kind = 0; kind < 3; kind++) {
        const double L = kind == 2 ? 4.0 : 1.0;
        const sea_rect r = { L, -7, 3, 24, 17 };
        sea_moments *m = malloc(24 * 17 * sizeof *m);
        CU_ASSERT_PTR_NOT_NULL_FATAL(m);
        for (size_t q = 0; q < 24 * 17; q++) {
            const double x = (r.i0 + (double)(q % 24) + 0.5) * L;
            m[q] = kind < 2 ? facet(gsl_ran_gaussian(rng, kind == 0 ? 0.3 : 0.05),
                                    gsl_ran_gaussian(rng, 0.4), gsl_ran_gaussian(rng, 0.4), &c)
                            : facet(0.7 * sin(0.4 * x), 0.28 * cos(0.4 * x), 0.0, &c);
        }
        sea_heightfield *hf = NULL;
        sea_error err;
        CU_ASSERT_EQUAL_FATAL(sea_heightfield_alloc(&r, m, &hf, &err), SEA_OK);
        free(m);
        const double g = sea_heightfield_gradient_bound(hf);
        double seen = 0.0;
        for (int k = 0; k < 200000; k++) {
            const double x = (r.i0 - 1.0 + 26.0 * gsl_rng_uniform(rng)) * L;
            const double y = (r.j0 - 1.0 + 19.0 * gsl_rng_uniform(rng)) * L;
            const sea_moments p = sea_heightfield_at(hf, x, y);
            seen = fmax(seen, hypot(p.mx, p.my));
        }
        worst_ratio = fmax(worst_ratio, seen / g);
        loosest = fmin(loosest, seen / g);
        sea_heightfield_free(hf);
    }
    gsl_rng_free(rng);
    MEASURED("gradient bound: largest gradient met / bound %.3f (never above 1), loosest %.3f\n",
             worst_ratio, loosest);
    CU_ASSERT(worst_ratio <= 1.0);
    CU_ASSERT(loosest >= 1.0 / 8.0);
}

/* The ordering look() relies on, with the real march: rays A and B from
 * one point, of slopes k = d_z / |d_h| and map directions w = d_h / |d_h|,
 * B above A by k_B - k_A >= 2 gmax |w_B - w_A|, on a rough random
 * heightfield at 60-88 deg from the vertical.  At every horizontal
 * distance B is above A by more than the surface rises between their map
 * points, so B meets the surface no nearer (horizontally) than A; the
 * march can miss a hit where a ray only touches a crest, so where B's hit
 * comes nearer, A must have missed: a dense march along A (steps of L /
 * 400) then finds A on or under the surface before that distance. */
static void test_ray_order(void)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 9);
    const sea_cov2 c = { 0.01, 0.01, 0.0 };
    const double L = 1.0;
    const sea_rect r = { L, 0, 0, 128, 128 };
    sea_moments *m = malloc(128 * 128 * sizeof *m);
    CU_ASSERT_PTR_NOT_NULL_FATAL(m);
    for (size_t q = 0; q < 128 * 128; q++)
        m[q] = facet(gsl_ran_gaussian(rng, 0.05), gsl_ran_gaussian(rng, 0.1),
                     gsl_ran_gaussian(rng, 0.1), &c);
    sea_heightfield *hf = NULL;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_heightfield_alloc(&r, m, &hf, &err), SEA_OK);
    free(m);
    const double g = sea_heightfield_gradient_bound(hf);
    const double o[3] = { 1.0, 1.0, 2.0 };
    int pairs = 0, ordered = 0, explained = 0, unexplained = 0;
    const int N = UNIT_QUICK ? 300 : 3000;
    for (int k = 0; k < N; k++) {
        const double th = (60.0 + 28.0 * gsl_rng_uniform(rng)) * DEG;
        const double ph = (20.0 + 50.0 * gsl_rng_uniform(rng)) * DEG;
        const double dA[3] = { sin(th) * cos(ph), sin(th) * sin(ph), -cos(th) };
        /* B: up by dth, turned by dph, at the bound (2 gmax) or beyond */
        const double dth = (0.02 + 0.3 * gsl_rng_uniform(rng)) * DEG;
        const double thB = th + dth;
        double dB[3] = { sin(thB) * cos(ph), sin(thB) * sin(ph), -cos(thB) };
        const double lift = -1.0 / tan(thB) + 1.0 / tan(th);
        /* the largest turn the test allows (|w_B - w_A| = 2 sin(turn / 2)),
         * then a share of it */
        const double turn = gsl_rng_uniform(rng) * lift / (2.0 * g);
        dB[0] = sin(thB) * cos(ph + turn);
        dB[1] = sin(thB) * sin(ph + turn);
        if (!(lift >= 2.0 * g * hypot(cos(ph + turn) - cos(ph), sin(ph + turn) - sin(ph))))
            continue;
        double tA, tB;
        if (!sea_heightfield_trace(hf, o, dA, 1e6, &tA) ||
            !sea_heightfield_trace(hf, o, dB, 1e6, &tB))
            continue;
        pairs++;
        const double sA = tA * sin(th), sB = tB * sin(thB); /* horizontal distances */
        if (sB >= sA - 1e-9) {
            ordered++;
            continue;
        }
        int under = 0;
        for (double t = 0.0; t * sin(th) <= sB && !under; t += L / 400.0) {
            const double x = o[0] + t * dA[0], y = o[1] + t * dA[1], z = o[2] + t * dA[2];
            under = z <= sea_heightfield_at(hf, x, y).h;
        }
        explained += under;
        unexplained += !under;
    }
    sea_heightfield_free(hf);
    gsl_rng_free(rng);
    MEASURED("ray order: %d pairs meeting the surface, B's hit not nearer than A's in %d, nearer "
             "in %d (A missed a hit the dense march finds), unexplained %d\n",
             pairs, ordered, explained, unexplained);
    CU_ASSERT(pairs >= N / 2);
    CU_ASSERT_EQUAL(unexplained, 0);
}

/* A tilted plane z = z0 + a x + b y: the Hermite surface through its facet
 * centres is the plane itself (a cubic Hermite patch reproduces linear
 * functions), so every ray meets it where the ray meets the plane, and
 * reads the plane's slope and the facets' covariance there.  Projected
 * area (Eq 9b): a bundle of parallel rays of cross-section dA, seen from
 * direction u (zenith theta, azimuth phi), meets the plane over a
 * horizontal area dA / (cos theta - s_X sin theta) = dA / (g cos theta),
 * s_X the slope along phi, g = 1 - s_X tan theta: a facet tilted toward the
 * sensor gets more rays per unit of horizontal area, one tilted away fewer.
 * Checked on small bundles (three rays 1 cm apart) at unremarkable angles,
 * g from 0.29 to 1.09, to 1e-6 relative (the crossings are refined to 1e-9
 * of a facet).  The plane's numbers are dyadic, so that the heightfield's
 * float facets (sea_facet) hold them exactly. */
static void test_plane_projected_area(void)
{
    const double z0 = 0.375, a = 0.125, b = -0.0625, L = 2.0;
    const sea_cov2 c = { 0x3p-8, 0x1p-8, 0x1p-9 };
    const sea_rect r = { L, -20, -20, 40, 40 };
    sea_moments *m = malloc(40 * 40 * sizeof *m);
    CU_ASSERT_PTR_NOT_NULL_FATAL(m);
    for (size_t j = 0; j < 40; j++)
        for (size_t i = 0; i < 40; i++) {
            const double x = (r.i0 + (double)i + 0.5) * L, y = (r.j0 + (double)j + 0.5) * L;
            m[j * 40 + i] = facet(z0 + a * x + b * y, a, b, &c);
        }
    sea_heightfield *hf = NULL;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_heightfield_alloc(&r, m, &hf, &err), SEA_OK);
    free(m);
    const double views[4][2] = { { 71.3, 0.9 }, { 71.3, 0.9 + M_PI }, { 80.0, 0.0 },
                                 { 37.4, 2.2 } };
    double worst = 0.0, worst_hit = 0.0;
    for (int k = 0; k < 4; k++) {
        const double th = views[k][0] * DEG, ph = views[k][1];
        const double u[3] = { sin(th) * cos(ph), sin(th) * sin(ph), cos(th) };
        const double d[3] = { -u[0], -u[1], -u[2] };
        /* two unit vectors across the bundle */
        double e1[3] = { -sin(ph), cos(ph), 0.0 };
        const double e2[3] = { u[1] * e1[2] - u[2] * e1[1], u[2] * e1[0] - u[0] * e1[2],
                               u[0] * e1[1] - u[1] * e1[0] };
        const double sX = a * cos(ph) + b * sin(ph), g = 1.0 - sX * tan(th);
        for (int p = 0; p < 9; p++) {
            const double px = -23.0 + 6.1 * p, py = 17.0 - 4.3 * p;
            const double P[3] = { px, py, z0 + a * px + b * py }, T = 30.0, delta = 0.01;
            double hit[3][2];
            for (int q = 0; q < 3; q++) {
                double o[3], t;
                for (int i = 0; i < 3; i++)
                    o[i] = P[i] + T * u[i] + (q == 1 ? delta * e1[i] : q == 2 ? delta * e2[i] : 0.0);
                CU_ASSERT_FATAL(sea_heightfield_trace(hf, o, d, 1e3, &t));
                hit[q][0] = o[0] + t * d[0];
                hit[q][1] = o[1] + t * d[1];
                const double z = o[2] + t * d[2];
                worst_hit = fmax(worst_hit, fabs(z - (z0 + a * hit[q][0] + b * hit[q][1])));
                if (q == 0) {
                    const sea_moments mm = sea_heightfield_at(hf, hit[q][0], hit[q][1]);
                    ASSERT_ABS(mm.mx, a, 1e-12);
                    ASSERT_ABS(mm.my, b, 1e-12);
                    ASSERT_ABS(mm.mxx - mm.mx * mm.mx, c.xx, 1e-12);
                    ASSERT_ABS(mm.mxy - mm.mx * mm.my, c.xy, 1e-12);
                    ASSERT_ABS(mm.h, z, 1e-9);
                }
            }
            const double area = fabs((hit[1][0] - hit[0][0]) * (hit[2][1] - hit[0][1]) -
                                     (hit[1][1] - hit[0][1]) * (hit[2][0] - hit[0][0]));
            const double want = delta * delta / (g * cos(th));
            worst = fmax(worst, fabs(area - want) / want);
        }
    }
    MEASURED("tilted plane: rays on the plane to %.1e m, horizontal area per ray bundle within "
             "%.1e of dA / (g cos theta), g = 0.29..1.09\n",
             worst_hit, worst);
    CU_ASSERT(worst < 1e-6);
    CU_ASSERT(worst_hit < 1e-8);
    sea_heightfield_free(hf);
}

/* The shadow of one crest of h = a cos(k x) seen along +x at zenith theta
 * (rays descending with slope mu = cot theta).  The tangent construction:
 * the last ray that touches the crest's lee side does so where the surface
 * falls as steeply as the ray, h'(x_t) = -mu, a k sin(k x_t) = mu with
 * k x_t in (0, pi/2) (the surface is concave there, so it drops away below
 * the ray beyond); the ray meets the surface again at x_s, the root of
 * h(x_s) = h(x_t) - mu (x_s - x_t) in (x_t, x_t + lambda).  Everything in
 * (x_t, x_s) is hidden, the rest of the period seen: the hidden fraction
 * is (x_s - x_t) / lambda (0 when a k <= mu: no slope exceeds the ray's).
 * A point is seen when the ray aimed at it from the sensor side meets the
 * surface there first.  Sampled at N = 2000 points of one period, against
 * the closed form to 2 / N (a sample on each boundary) plus the Hermite
 * surface's departure from the cosine (a^-1 |dh| ~ (k L)^4 / 384 = 2e-7,
 * which moves the tangent point by far less). */
static double tangent_hidden(double a, double k, double mu, double *xt, double *xs)
{
    if (a * k <= mu) {
        *xt = *xs = 0.0;
        return 0.0;
    }
    const double lam = 2.0 * M_PI / k;
    *xt = asin(mu / (a * k)) / k;
    const double ht = a * cos(k * *xt);
    double lo = *xt + 1e-7 * lam, hi = *xt + lam; /* f(lo) < 0 < f(hi) = mu lambda */
    for (int it = 0; it < 200; it++) {
        const double mid = 0.5 * (lo + hi);
        if (a * cos(k * mid) - (ht - mu * (mid - *xt)) < 0.0)
            lo = mid;
        else
            hi = mid;
    }
    *xs = 0.5 * (lo + hi);
    return (*xs - *xt) / lam;
}

static void test_sinusoid_occlusion(void)
{
    const double lam = 20.0, k = 2.0 * M_PI / lam, L = lam / 64.0;
    const size_t nx = 64 * 6, ny = 4;
    const sea_rect r = { L, 0, 0, nx, ny };
    const sea_cov2 c0 = { 0.0, 0.0, 0.0 };
    const double amps[2] = { 0.8, 0.45 };
    const double zeniths[3] = { 80.0, 84.3, 87.1 };
    const int N = UNIT_QUICK ? 400 : 2000;
    for (int ia = 0; ia < 2; ia++) {
        const double a = amps[ia];
        sea_moments *m = malloc(nx * ny * sizeof *m);
        CU_ASSERT_PTR_NOT_NULL_FATAL(m);
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                const double x = ((double)i + 0.5) * L;
                m[j * nx + i] = facet(a * cos(k * x), -a * k * sin(k * x), 0.0, &c0);
            }
        sea_heightfield *hf = NULL;
        sea_error err;
        CU_ASSERT_EQUAL_FATAL(sea_heightfield_alloc(&r, m, &hf, &err), SEA_OK);
        free(m);
        for (int iz = 0; iz < 3; iz++) {
            const double th = zeniths[iz] * DEG, mu = 1.0 / tan(th);
            const double d[3] = { sin(th), 0.0, -cos(th) };
            double xt, xs;
            const double want = tangent_hidden(a, k, mu, &xt, &xs);
            /* one period from a crest in the middle of the lattice */
            const double x0 = 3.0 * lam, y = 0.5 * ny * L, T = 40.0;
            int hidden = 0, wrong = 0;
            for (int s = 0; s < N; s++) {
                const double x = x0 + (s + 0.5) / N * lam;
                const double P[3] = { x, y, a * cos(k * x) };
                const double o[3] = { P[0] - T * d[0], P[1], P[2] - T * d[2] };
                double t;
                CU_ASSERT_FATAL(sea_heightfield_trace(hf, o, d, 2.0 * T, &t));
                const int seen = t > T - 1e-3;
                hidden += !seen;
                /* and where: inside (x_t, x_s) of this period, away from
                 * its ends by more than a sample */
                const double xr = x - x0;
                const double edge = lam / N;
                if (want > 0.0 && xr > xt + edge && xr < xs - edge)
                    wrong += seen;
                else if (want == 0.0 || xr < xt - edge || xr > xs + edge)
                    wrong += !seen;
            }
            const double got = (double)hidden / N;
            MEASURED("sinusoid a k = %.3f at %.1f deg (mu %.3f): hidden %.4f, tangent "
                     "construction %.4f, %d points on the wrong side\n",
                     a * k, zeniths[iz], mu, got, want, wrong);
            ASSERT_ABS(got, want, 2.0 / N + 1e-4);
            CU_ASSERT_EQUAL(wrong, 0);
        }
        sea_heightfield_free(hf);
    }
}

/* Bad lattices are refused. */
static void test_heightfield_errors(void)
{
    sea_moments m[4] = { { 0 } };
    sea_heightfield *hf = NULL;
    sea_error err;
    const sea_rect thin = { 1.0, 0, 0, 4, 1 };
    CU_ASSERT_EQUAL(sea_heightfield_alloc(&thin, m, &hf, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "2 x 2") != NULL);
    CU_ASSERT_PTR_NULL(hf);
    const sea_rect flat = { 0.0, 0, 0, 2, 2 };
    CU_ASSERT_EQUAL(sea_heightfield_alloc(&flat, m, &hf, &err), SEA_ERR_DOMAIN);
    m[2].mx = NAN;
    const sea_rect ok = { 1.0, 0, 0, 2, 2 };
    CU_ASSERT_EQUAL(sea_heightfield_alloc(&ok, m, &hf, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "not finite") != NULL);
    sea_heightfield_free(NULL);
}

/* A scene of the multiresolution sea: one-meter (every level the box
 * average of the 1 m sub-facets), clipmap windows of 64 facets (every level
 * from 1 m, concentric), a view 50 deg from nadir. */
static sea_scene lean_scene(void)
{
    sea_scene sc;
    sea_scene_defaults(&sc);
    sc.wind_speed = 9.0;
    sc.wind_dir = 61.7 * DEG;
    sc.altitude = 40.0;
    sc.look_zenith = 50.0 * DEG;
    sc.look_azimuth = 200.0 * DEG;
    sc.hfov = 40.0 * DEG;
    sc.width = sc.height = 24;
    sc.wavelength = 4e-6;
    sc.method = SEA_METHOD_ONE_METER;
    sc.grid = UNIT_QUICK ? 32 : 64; /* under valgrind, a quarter of the facets */
    sc.windows = SEA_WINDOWS_CLIPMAP;
    sc.emissivity_method = SEA_EMIS_FAST;
    return sc;
}

/* lean_scene seen 15 m up, look_zenith_deg from nadir through a 20 degree
 * field (grazing, with the horizon in view), flat or round earth, the
 * windows around the pixels that read them. */
static sea_scene grazing_scene(int round_earth, double look_zenith_deg)
{
    sea_scene sc = lean_scene();
    sc.method = SEA_METHOD_VARIABLE_STEP;
    sc.windows = SEA_WINDOWS_VIEW;
    sc.earth = round_earth ? SEA_EARTH_SPHERICAL : SEA_EARTH_FLAT;
    sc.look_zenith = look_zenith_deg * DEG;
    sc.hfov = 20.0 * DEG;
    sc.altitude = 15.0;
    return sc;
}

static void prepare_frame(const sea_scene *sc, sea_view **r, sea_multires_frame **f)
{
    sea_error err;
    sea_status st = sea_view_alloc(sc, r, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  prepare: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    st = sea_multires_frame_alloc(sea_view_multires(*r), sc->time, NULL, NULL, f, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  frame: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
}

/* prepare_frame, and the bake's lean frame of the same sea and time. */
static void prepare_frames(const sea_scene *sc, sea_view **r, sea_multires_frame **f,
                           sea_multires_frame **lean)
{
    prepare_frame(sc, r, f);
    sea_error err;
    *lean = NULL;
    sea_status st =
        sea_multires_frame_alloc_lean(sea_view_multires(*r), sc->time, NULL, NULL, lean, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  lean frame: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
}

/* LEAN footprint averages are exact: at a facet centre the surface's point
 * moments are the facet's own; the footprint average (sea_multires_average,
 * what a pixel does with its rays' points) of the four centres of a 2 x 2
 * block of level l is the moments of the level l + 1 facet they tile
 * (one-meter: both are box averages of the same 1 m sub-facets, and the
 * sub-facet covariance C_<1m is the same), to the float the frame keeps
 * each slope value in (sea_facet: 2^-24 = 6e-8 relative; the average of four
 * and the coarse facet each round once, so 1e-6 of the values' size is 16
 * of those roundings), and at a facet centre exactly in double arithmetic
 * (1e-12). */
static void test_lean_footprint(void)
{
    sea_scene sc = lean_scene();
    sea_view *r;
    sea_multires_frame *f;
    prepare_frame(&sc, &r, &f);
    const sea_clip_level *lv;
    const size_t n = sea_view_levels(r, &lv);
    CU_ASSERT_FATAL(n >= 4 && !lv[0].low_res && !lv[1].low_res && !lv[2].low_res);
    double worst = 0.0, worst_node = 0.0;
    size_t blocks = 0;
    for (size_t l = 0; l + 1 < n && !lv[l + 1].low_res; l++) {
        const sea_clip_level *a = &lv[l], *b = &lv[l + 1];
        const sea_facet *ma = sea_heightfield_facets(sea_multires_frame_level(f, a->level));
        const sea_facet *mb = sea_heightfield_facets(sea_multires_frame_level(f, b->level));
        const sea_heightfield *ha = sea_multires_frame_level(f, a->level);
        /* coarse facets whose four fine ones lie well inside level l's
         * window (full weight there, no coarser level showing through) */
        for (long cj = b->j0; cj < b->j0 + (long)b->ny; cj += 3)
            for (long ci = b->i0; ci < b->i0 + (long)b->nx; ci += 3) {
                const long i = 2 * ci - a->i0, j = 2 * cj - a->j0;
                if (i < 8 || j < 8 || i + 10 > (long)a->nx || j + 10 > (long)a->ny)
                    continue;
                double x[4], y[4];
                const double w[4] = { 1.0, 1.0, 1.0, 1.0 };
                for (int q = 0; q < 4; q++) {
                    const long ii = i + (q & 1), jj = j + (q >> 1);
                    x[q] = (a->i0 + ii + 0.5) * a->facet;
                    y[q] = (a->j0 + jj + 0.5) * a->facet;
                    const sea_moments p = sea_heightfield_at(ha, x[q], y[q]);
                    const sea_moments sm = sea_facet_moments(&ma[jj * (long)a->nx + ii]),
                                      *s = &sm;
                    worst_node = fmax(worst_node, fabs(p.mx - s->mx) + fabs(p.my - s->my) +
                                                      fabs(p.mxx - s->mxx) +
                                                      fabs(p.mxy - s->mxy) +
                                                      fabs(p.myy - s->myy) + fabs(p.h - s->h));
                }
                const sea_level_blend bl = { a->level, -1, 0.0 };
                const sea_moments avg = sea_multires_average(f, bl, 4, x, y, w);
                const sea_moments cm =
                                      sea_facet_moments(&mb[(cj - b->j0) * (long)b->nx + (ci - b->i0)]),
                                  *c = &cm;
                const double size = fabs(c->mx) + fabs(c->my) + fabs(c->mxx) + fabs(c->mxy) +
                                    fabs(c->myy) + fabs(c->h);
                worst = fmax(worst, (fabs(avg.mx - c->mx) + fabs(avg.my - c->my) +
                                     fabs(avg.mxx - c->mxx) + fabs(avg.mxy - c->mxy) +
                                     fabs(avg.myy - c->myy) + fabs(avg.h - c->h)) /
                                        size);
                blocks++;
            }
    }
    MEASURED("LEAN footprint: %zu blocks of 2 x 2 facets average to the coarse facet within "
             "%.1e of its size; point moments at facet centres within %.1e of the facet's\n",
             blocks, worst, worst_node);
    CU_ASSERT(blocks > (UNIT_QUICK ? 20u : 100u));
    CU_ASSERT(worst < 1e-6);
    CU_ASSERT(worst_node < 1e-12);
    sea_multires_frame_free(f);
    sea_view_free(r);
}

/* The render's rays ordered across pixel rows (sea_multires_pixel_hinted,
 * as sea_view_render_rows runs it: blocks of SEA_RENDER_ROW_BLOCK rows, each
 * bottom row first, a pixel's rays starting where those of the pixel below
 * met the sea when the ordering allows): the samples are sea_multires_pixel's
 * but where a ray grazes a crest and the march's samples decide, at most
 * 0.2 % of the pixels (measured); grazing views of a flat and a round
 * earth.  A hint that claims hits 3 times as far as they were (rays then
 * start beyond their first hit) changes many more, so the comparison can
 * tell. */
static void test_hinted_rows(void)
{
    for (int earth = 0; earth < 2; earth++) {
        sea_scene sc = grazing_scene(earth, 85.0);
        sc.width = 40;
        sc.height = 4 * SEA_RENDER_ROW_BLOCK;
        sea_view *r;
        sea_multires_frame *f;
        prepare_frame(&sc, &r, &f);
        const size_t W = (size_t)sc.width;
        sea_multires_hint *h = malloc(2 * W * sizeof *h);
        CU_ASSERT_PTR_NOT_NULL_FATAL(h);
        size_t sea = 0, differ[2] = { 0, 0 }, hinted = 0;
        for (int bad = 0; bad < 2; bad++)
            for (int j_lo = 0; j_lo < sc.height; j_lo += SEA_RENDER_ROW_BLOCK)
                for (int j = j_lo + SEA_RENDER_ROW_BLOCK - 1; j >= j_lo; j--) {
                    sea_multires_hint *below = j + 1 < j_lo + SEA_RENDER_ROW_BLOCK
                                                   ? h + (size_t)((j + 1) % 2) * W
                                                   : NULL;
                    sea_multires_hint *top = h + (size_t)(j % 2) * W;
                    for (size_t i = 0; i < W; i++) {
                        if (bad && below != NULL)
                            for (int m = 0; m < below[i].n; m++)
                                below[i].s[m] *= 3.0;
                        sea_multires_sample a, b;
                        sea_multires_pixel_hinted(f, (int)i, j, below ? &below[i] : NULL, &top[i],
                                                  &a);
                        sea_multires_pixel(f, (int)i, j, &b);
                        if (!b.hit)
                            continue;
                        sea += !bad;
                        hinted += !bad && below != NULL && below[i].n > 0;
                        const double d = fabs(a.moments.mx - b.moments.mx) +
                                         fabs(a.moments.my - b.moments.my) +
                                         fabs(a.range - b.range) / b.range;
                        differ[bad] += !(d <= 1e-9);
                    }
                }
        free(h);
        MEASURED("rows ordered (%s): %zu sea pixels, %zu with a hint; %zu differ (a hint 3 times "
                 "too far: %zu)\n",
                 earth ? "round" : "flat", sea, hinted, differ[0], differ[1]);
        CU_ASSERT(sea > W * (size_t)sc.height / 2);
        CU_ASSERT(hinted > sea / 2);
        CU_ASSERT(differ[0] <= sea / 500);
        CU_ASSERT(differ[1] > sea / 20);
        sea_multires_frame_free(f);
        sea_view_free(r);
    }
}

/* One query: sea_multires_look at pixel centres is sea_multires_pixel, bit
 * for bit; every sea pixel's rays meet the surface; the point met is on
 * the surface along the pixel's ray (a one-ray pixel).  Spherical earth:
 * heights stand along the local vertical of the sphere, so the point met,
 * at `range` along the pixel's ray from the sensor, stands above its map
 * point by the surface's height there, measured from the sphere's centre
 * (to 1e-6 m).  A bake's lean frame (sea_multires_frame_alloc_lean: no
 * stored bounds of the finest cells, computed as the march asks) answers
 * every query bit for bit as the render's frame does, at pixel centres and
 * between them. */
static void test_query(void)
{
    for (int earth = 0; earth < 2; earth++) {
        sea_scene sc = grazing_scene(earth, 84.0);
        sea_view *r;
        sea_multires_frame *f, *lean;
        prepare_frames(&sc, &r, &f, &lean);
        const sea_camera *cam = sea_view_camera(r);
        size_t sea = 0, same = 0, one = 0, sky = 0, lean_same = 0;
        double worst = 0.0;
        for (int j = 0; j < sc.height; j++)
            for (int i = 0; i < sc.width; i++) {
                /* a: the pixel; b: a look at its centre; lc: the lean
                 * frame's; fo, lo: both frames' between pixel centres */
                sea_multires_sample a, b, lc, fo, lo;
                sea_multires_pixel(f, i, j, &a);
                sea_multires_look(f, i + 0.5, j + 0.5, &b);
                same += memcmp(&a, &b, sizeof a) == 0;
                sea_multires_look(lean, i + 0.5, j + 0.5, &lc);
                sea_multires_look(f, i + 0.25, j + 0.75, &fo);
                sea_multires_look(lean, i + 0.25, j + 0.75, &lo);
                lean_same += memcmp(&a, &lc, sizeof a) == 0 && memcmp(&fo, &lo, sizeof fo) == 0;
                if (!a.hit) {
                    sky++;
                    continue;
                }
                sea++;
                CU_ASSERT(a.rays >= 1);
                if (a.rays != 1)
                    continue;
                /* the surface under the point met, and the ray */
                double d[3], q[3], n[3];
                sea_camera_ray(cam, i + 0.5, j + 0.5, d);
                const double p[3] = { cam->pos[0] + a.range * d[0], cam->pos[1] + a.range * d[1],
                                      cam->pos[2] + a.range * d[2] };
                double height;
                if (earth) {
                    const double R = SEA_EARTH_RADIUS;
                    const double pc[3] = { p[0] - cam->pos[0], p[1] - cam->pos[1], p[2] + R };
                    height = sqrt(pc[0] * pc[0] + pc[1] * pc[1] + pc[2] * pc[2]) - R;
                } else {
                    height = p[2];
                }
                sea_camera_sea_point(cam, a.x, a.y, q, n);
                const double w = 1.0;
                const sea_moments s = sea_multires_average(f, a.blend, 1, &a.x, &a.y, &w);
                worst = fmax(worst, fabs(height - s.h) + fabs(a.height - s.h));
                one++;
            }
        MEASURED("query (%s earth): %zu sea pixels, %zu sky, look = pixel for %zu of %d; %zu "
                 "one-ray pixels on the surface to %.1e m; lean frame = frame for %zu\n",
                 earth ? "spherical" : "flat", sea, sky, same, sc.width * sc.height, one, worst,
                 lean_same);
        CU_ASSERT_EQUAL(same, (size_t)(sc.width * sc.height));
        CU_ASSERT_EQUAL(lean_same, (size_t)(sc.width * sc.height));
        sea_multires_frame_free(lean);
        CU_ASSERT(sea > 0 && sky > 0);
        CU_ASSERT(one > 10);
        CU_ASSERT(worst < 1e-6);
        sea_multires_frame_free(f);
        sea_view_free(r);
    }
}

/* The mean emissivity of a grazing image at 1 m facets against the
 * low-resolution value, and why they differ.  A 900 x 60 view at 70 and 80
 * deg of a 10 m/s sea, 4 um, wind across and along the view, each pixel's
 * footprint about 0.8 m (every pixel on the 1 m level), against the same
 * pixels' low-resolution emissivity (Eq 12 for both: the difference is
 * what is tested).  The derivation (multires.c): a ray counts the resolved
 * facet it meets by its projected area g = 1 - m_X tan theta and shows
 * that facet's own eps~ (Eq 7 normalised by its D), while the
 * low-resolution Eq 7 is the mixture of the same facets each counted by
 * its front-facing area g + Lambda (Lambda of its sub-facets: Smith's
 * uncorrelated shadowing).  So, over the level's facets under the view:
 *  - counted by g + Lambda, their eps~ is the low-resolution value (within
 *    2e-3: the window's own slopes, a realisation, measured 1e-3);
 *  - the image's mean exceeds the low-resolution value by what counting
 *    them by g instead adds (within 2e-3: measured 6e-4 to 1.2e-3; counting
 *    by horizontal area, the old bias, or by D of Eq 10, or by g twice,
 *    differ from it by 0.01 to 0.04 at 80 deg);
 *  - at 70 deg both are within 2e-3 of the low-resolution value (measured
 *    1e-3); at 80 deg the image is above it, by Smith's share (measured
 *    +0.006 across the wind, +0.011 along), and never below by more than
 *    1e-3 (the old image was 0.03 below).
 * These hold with Smith's shadowing (shadowing = smith).  With the
 * correlated function (the scenes' default) low resolution is no longer
 * Smith's mixture of the facets, and the image's gap at 80 deg shrinks
 * (test_grazing_mean). */
static void grazing_case(double theta_deg, double wind_deg, int shadowing, int scales,
                         int reflections, double *image, double *facets_g, double *facets_smith)
{
    sea_scene sc;
    sea_scene_defaults(&sc);
    sc.shadowing = shadowing;
    sc.scales = scales;
    sc.reflections = reflections;
    const double pixel = 6e-4; /* rad */
    sc.wind_speed = 10.0;
    sc.wind_dir = wind_deg * DEG;
    sc.look_zenith = theta_deg * DEG;
    sc.look_azimuth = 180.0 * DEG; /* toward west: the sensor is east (+x) of the sea it sees */
    sc.width = 900;
    sc.height = 60;
    sc.hfov = sc.width * pixel;
    /* footprint = range x pixel / sqrt(cos theta) = 0.8 m at the centre */
    sc.altitude = 0.8 * pow(cos(sc.look_zenith), 1.5) / pixel;
    sc.wavelength = 4e-6;
    sc.grid = 1024;
    sc.emissivity_method = SEA_EMIS_FAST;
    sc.sun_zenith = 120.0 * DEG;
    sea_view *r;
    sea_multires_frame *f;
    prepare_frame(&sc, &r, &f);
    sea_error err;
    const sea_moments lrm = sea_view_lr_moments(r);
    const sea_slope_stats lrs = sea_moments_stats(&lrm);
    const sea_dir sun = { sc.sun_zenith, 0.0 };
    double sum = 0.0, xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    size_t n = 0, off = 0;
    for (int j = 0; j < sc.height; j++)
        for (int i = 0; i < sc.width; i++) {
            sea_multires_sample s;
            sea_multires_pixel(f, i, j, &s);
            CU_ASSERT_FATAL(s.hit);
            off += s.level != 0;
            const sea_slope_stats st = sea_moments_stats(&s.moments);
            sea_facet_optics o, ol;
            CU_ASSERT_EQUAL_FATAL(sea_view_facet_optics(r, &st, s.obs, sun, &o, &err), SEA_OK);
            CU_ASSERT_EQUAL_FATAL(sea_view_facet_optics(r, &lrs, s.obs, sun, &ol, &err), SEA_OK);
            sum += o.emissivity - ol.emissivity;
            n++;
            xmin = fmin(xmin, s.x);
            xmax = fmax(xmax, s.x);
            ymin = fmin(ymin, s.y);
            ymax = fmax(ymax, s.y);
        }
    CU_ASSERT_EQUAL(off, 0);
    *image = sum / (double)n;
    /* the 1 m facets under the view, seen from the central direction
     * (toward +x: azimuth 0) */
    const sea_clip_level *lv;
    sea_view_levels(r, &lv);
    CU_ASSERT_FATAL(lv[0].level == 0 && !lv[0].low_res);
    const sea_facet *m = sea_heightfield_facets(sea_multires_frame_level(f, 0));
    const sea_dir obs = { sc.look_zenith, 0.0 };
    sea_facet_optics olr;
    CU_ASSERT_EQUAL_FATAL(sea_view_facet_optics(r, &lrs, obs, sun, &olr, &err), SEA_OK);
    double sg = 0.0, wg = 0.0, sl = 0.0, wl = 0.0;
    for (size_t j = 0; j < lv[0].ny; j++)
        for (size_t i = 0; i < lv[0].nx; i++) {
            const double x = ((double)lv[0].i0 + (double)i + 0.5) * lv[0].facet;
            const double y = ((double)lv[0].j0 + (double)j + 0.5) * lv[0].facet;
            if (x < xmin || x > xmax || y < ymin || y > ymax)
                continue;
            const sea_slope_stats st = sea_facet_stats(&m[j * lv[0].nx + i]);
            sea_facet_optics o;
            CU_ASSERT_EQUAL_FATAL(sea_view_facet_optics(r, &st, obs, sun, &o, &err), SEA_OK);
            double mX, sX;
            sea_slope_project(&st, obs.phi, &mX, &sX);
            const double g = 1.0 - mX * tan(obs.theta);
            const double lam = sea_shadow_lambda(obs.theta, mX, sX);
            sg += g * o.emissivity;
            wg += g;
            sl += (g + lam) * o.emissivity;
            wl += g + lam;
        }
    *facets_g = sg / wg - olr.emissivity;
    *facets_smith = sl / wl - olr.emissivity;
    sea_multires_frame_free(f);
    sea_view_free(r);
}

static void test_grazing_mean(void)
{
    if (UNIT_QUICK)
        return; /* 12 frames of 1 m facets over 500 m: minutes under a memory checker */
    const double thetas[3] = { 70.0, 80.0, 85.0 }, winds[2] = { 90.0, 0.0 };
    for (int a = 0; a < 3; a++)
        for (int w = 0; w < 2; w++) {
            /* the scenes' default: correlated shadowing, two scales.  The
             * 1 m level and low resolution agree (the targets: 2e-3 at 70
             * deg, 5e-3 at 80); measured -0.0011 / -0.0001 at 70 deg,
             * +0.0005 / +0.0034 at 80 and +0.0047 / +0.0060 at 85 (across /
             * along the wind; seed 1, 60 rows) */
            double di, dg, ds;
            grazing_case(thetas[a], winds[w], SEA_SHADOW_CORRELATED, 2, 1, &di, &dg, &ds);
            MEASURED("grazing %g deg, wind %s the view, two scales: image - LR %+.4f\n",
                     thetas[a], w ? "along" : "across", di);
            ASSERT_ABS(di, 0.0, thetas[a] < 75.0 ? 2e-3 : thetas[a] < 82.0 ? 4e-3 : 8e-3);
            /* the default model (second hits in the sea around, which
             * low resolution shares): the image's second hits average to
             * low resolution's, so the difference stays two scales' */
            double d2, g2, s2;
            grazing_case(thetas[a], winds[w], SEA_SHADOW_CORRELATED, 2, SEA_REFLECTIONS_AUTO, &d2,
                         &g2, &s2);
            MEASURED("grazing %g deg, wind %s the view, the default model: image - LR %+.4f\n",
                     thetas[a], w ? "along" : "across", d2);
            ASSERT_ABS(d2, 0.0, thetas[a] < 75.0 ? 2e-3 : thetas[a] < 82.0 ? 4e-3 : 8e-3);
            if (thetas[a] > 82.0)
                continue;
            double image, g, smith;
            grazing_case(thetas[a], winds[w], SEA_SHADOW_SMITH, 1, 1, &image, &g, &smith);
            double ci, cg, cs;
            grazing_case(thetas[a], winds[w], SEA_SHADOW_CORRELATED, 1, 1, &ci, &cg, &cs);
            MEASURED("grazing %g deg, wind %s the view, correlated shadowing: image - LR %+.4f\n",
                     thetas[a], w ? "along" : "across", ci);
            /* correlated shadowing moves low resolution toward what the
             * waves' geometry shows: measured -0.0010 / -0.0000 at 70 deg,
             * +0.0034 / +0.0079 at 80 (Smith's: +0.0056 / +0.0113) */
            if (thetas[a] < 75.0)
                ASSERT_ABS(ci, 0.0, 2e-3);
            else
                CU_ASSERT(fabs(ci) < fabs(image) - 2e-3 && fabs(ci) <= 9e-3);
            MEASURED("grazing %g deg, wind %s the view: image - LR %+.4f; facets by g + Lambda "
                     "- LR %+.4f, by g - LR %+.4f\n",
                     thetas[a], w ? "along" : "across", image, smith, g);
            ASSERT_ABS(smith, 0.0, 2e-3);
            ASSERT_ABS(image, g, 2e-3);
            CU_ASSERT(image > -1e-3);
            if (thetas[a] < 75.0)
                ASSERT_ABS(image, 0.0, 2e-3);
        }
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The plan's median (sea_select_kth_d) against a sort: every k of arrays of
 * 1-40 values and some k of arrays of 2000, drawn with many ties, sorted,
 * reversed, organ-pipe and constant; exact (a selection moves values, it
 * computes none). */
static void test_select_kth(void)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 5);
    static double v[2000], w[2000];
    int wrong = 0, cases = 0;
    for (int it = 0; it < 3000; it++) {
        const size_t n = it < 200 ? 2000 : 1 + (size_t)gsl_rng_uniform_int(rng, 40);
        const int kind = it % 5;
        for (size_t q = 0; q < n; q++)
            v[q] = kind == 0   ? (double)gsl_rng_uniform_int(rng, 3)
                   : kind == 1 ? (double)q
                   : kind == 2 ? (double)(n - q)
                   : kind == 3 ? (double)(q < n / 2 ? q : n - q)
                               : gsl_rng_uniform(rng) - 0.5;
        if (it % 50 == 49)
            for (size_t q = 0; q < n; q++)
                v[q] = 7.0;
        memcpy(w, v, n * sizeof *v);
        qsort(w, n, sizeof *w, cmp_double);
        const size_t ks = n <= 40 ? n : 8;
        for (size_t a = 0; a < ks; a++) {
            const size_t k = n <= 40 ? a : (size_t)gsl_rng_uniform_int(rng, n);
            double u[2000];
            memcpy(u, v, n * sizeof *v);
            sea_select_kth_d(u, n, k);
            wrong += u[k] != w[k];
            cases++;
        }
    }
    MEASURED("select_kth: %d of %d selections differ from the sort\n", wrong, cases);
    CU_ASSERT_EQUAL(wrong, 0);
    gsl_rng_free(rng);
}

/* Where the window of a pixel's one level is at full weight, its surface
 * reads that level's heightfield directly (multires.c, surf_alone), not
 * the chain of levels: the heights, gradients, moments and bounds there
 * must be the chain's bit for bit (signed zeros aside: the chain's sums
 * start from +0), in a render's frame and in a bake's lean one (finest
 * bounds from the nodes), flat and round earth. */
static void test_level_alone(void)
{
    for (int earth = 0; earth < 2; earth++) {
        sea_scene sc = grazing_scene(earth, 84.0);
        sea_view *r;
        sea_multires_frame *f, *lean;
        prepare_frames(&sc, &r, &f, &lean);
        size_t checked = 0, checked_lean = 0;
        const size_t bad = sea_multires_alone_check(f, 4000, &checked);
        const size_t bad_lean = sea_multires_alone_check(lean, 4000, &checked_lean);
        MEASURED("level alone (%s earth): %zu of %zu points differ, lean frame %zu of %zu\n",
                 earth ? "round" : "flat", bad, checked, bad_lean, checked_lean);
        CU_ASSERT_EQUAL(bad, 0);
        CU_ASSERT_EQUAL(bad_lean, 0);
        /* the view's high-resolution levels have full-weight parts */
        CU_ASSERT(checked >= 2 * 4000);
        CU_ASSERT_EQUAL(checked_lean, checked);
        sea_multires_frame_free(lean);
        sea_multires_frame_free(f);
        sea_view_free(r);
    }
}

int test_multires_register(void)
{
    CU_pSuite s = CU_add_suite("multires", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "tilted plane: projected area", test_plane_projected_area) ||
           !CU_add_test(s, "heightfield: the gradient bound", test_gradient_bound) ||
           !CU_add_test(s, "rays ordered by the gradient bound", test_ray_order) ||
           !CU_add_test(s, "rays ordered across pixel rows", test_hinted_rows) ||
           !CU_add_test(s, "the plan's median: selection against a sort", test_select_kth) ||
           !CU_add_test(s, "sinusoid: the tangent construction's shadow",
                        test_sinusoid_occlusion) ||
           !CU_add_test(s, "heightfield errors", test_heightfield_errors) ||
           !CU_add_test(s, "LEAN footprint averages", test_lean_footprint) ||
           !CU_add_test(s, "one query; heights along the sphere's vertical", test_query) ||
           !CU_add_test(s, "a level alone where its window is at full weight", test_level_alone) ||
           !CU_add_test(s, "grazing images at 1 m facets against low resolution",
                        test_grazing_mean);
}
