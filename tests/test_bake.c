/* test_bake.c - baked maps (issue 5): the moments of each level are
 * sea_waves_facets' own, north up; LEAN averaging across levels; normals,
 * roughness and optics as documented; low-resolution levels constant. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "internal.h"
#include "unit.h"

/* A 48 x 48 view 55 deg from nadir: footprints from ~2 to ~9 m, so several
 * high-resolution levels and the low-resolution one. */
static sea_scene bake_scene(void)
{
    sea_scene sc;
    sea_scene_defaults(&sc);
    sc.wind_speed = 10.0;
    sc.wind_dir = 61.7 * DEG;
    sc.altitude = 120.0;
    sc.look_zenith = 55.0 * DEG;
    sc.look_azimuth = 200.0 * DEG;
    sc.hfov = 40.0 * DEG;
    sc.width = sc.height = 48;
    sc.wavelength = 4e-6;
    sc.method = SEA_METHOD_VARIABLE_STEP;
    sc.n = 0;
    sc.grid = 64;
    sc.emissivity_method = SEA_EMIS_FAST;
    sc.sun_zenith = 50.0 * DEG;
    sc.sun_azimuth = 200.0 * DEG; /* in view: a glint */
    return sc;
}

static sea_view *prepare(const sea_scene *sc)
{
    sea_view *r = NULL;
    sea_error err;
    sea_status st = sea_view_alloc(sc, &r, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  prepare: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    return r;
}

static void bake(const sea_view *r, double t, sea_bake *b)
{
    sea_error err;
    sea_status st = sea_bake_frame(r, t, 1, b, NULL, NULL, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  bake: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
}

static size_t count_hr(const sea_bake *b)
{
    size_t n = 0;
    for (size_t l = 0; l < b->n_levels; l++)
        n += !b->levels[l].level.low_res;
    return n;
}

/* Texel (i, row) is facet (i0 + i, j0 + ny - 1 - row) of the very same
 * sea_waves_facets call, as sea_facet_of keeps it: equal bit for bit.  Low-resolution levels have no
 * texels and carry m = 0, C = C_LR. */
static void test_moments_exact(void)
{
    const sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_bake b;
    const double t = 1.37;
    bake(r, t, &b);
    CU_ASSERT(count_hr(&b) >= 2);
    CU_ASSERT(b.n_levels > count_hr(&b)); /* and a low-resolution one */
    CU_ASSERT_EQUAL(b.time, t);
    const sea_moments lr = sea_view_lr_moments(r);
    for (size_t l = 0; l < b.n_levels; l++) {
        const sea_bake_level *bl = &b.levels[l];
        const sea_clip_level *lv = &bl->level;
        if (lv->low_res) {
            CU_ASSERT_PTR_NULL(bl->moments);
            CU_ASSERT_PTR_NULL(bl->optics);
            CU_ASSERT(memcmp(&bl->lr_moments, &lr, sizeof lr) == 0);
            CU_ASSERT_EQUAL(bl->lr_moments.mx, 0.0);
            CU_ASSERT(bl->lr_moments.mxx > 0.0);
            CU_ASSERT(bl->lr_optics.emissivity > 0.0 && bl->lr_optics.emissivity <= 1.0);
            continue;
        }
        const size_t n = lv->nx * lv->ny;
        sea_moments *ref = malloc(n * sizeof *ref);
        CU_ASSERT_PTR_NOT_NULL_FATAL(ref);
        const sea_rect rect = { lv->facet, lv->i0, lv->j0, lv->nx, lv->ny };
        sea_error err;
        CU_ASSERT_EQUAL_FATAL(sea_waves_facets(sea_view_waves(r), &rect, lv->sub_n, t, ref, &err),
                              SEA_OK);
        size_t diff = 0;
        for (size_t row = 0; row < lv->ny; row++)
            for (size_t i = 0; i < lv->nx; i++) {
                const sea_facet want = sea_facet_of(&ref[(lv->ny - 1 - row) * lv->nx + i]);
                diff += memcmp(&bl->moments[row * lv->nx + i], &want, sizeof want) != 0;
            }
        CU_ASSERT_EQUAL(diff, 0);
        free(ref);
    }
    sea_bake_free(&b);
    sea_bake_free(&b); /* a freed bake frees again as nothing */
    sea_view_free(r);
}

/* LEAN across levels.  With sub-facets of the finest size at every level
 * (variable-step-2n, n >= every level: sub_n = l), the texel of level l+1
 * is the mean of the 2 x 2 level-l texels it covers, to the float each
 * texel's slopes are kept in (sea_facet: 2^-24 relative a value, of the
 * fine ones and of the coarse one; the tolerance is 4 such roundings of
 * their sizes, |mx my| + |C_xy| <= sqrt(mxx myy) for mxy), and the height,
 * kept in double, to round-off (1e-9 m).  With Variable Step this cannot hold: the coarse
 * level's slope is taken from waves |k| <= pi/2L only and its C covers the
 * waves between pi/2L and pi/L that the fine level resolves; what holds
 * there is that both levels use the same realisation: the 2 x 2 mean of the
 * fine slope equals the coarse one within the slope std of those waves, and
 * C_coarse >= C_fine (trace). */
static void test_lean_across_levels(void)
{
    sea_scene sc = bake_scene();
    sc.method = SEA_METHOD_VARIABLE_STEP_2N;
    sc.n = 12;
    sea_view *r = prepare(&sc);
    sea_bake b;
    bake(r, 0.61, &b);
    size_t pairs = 0, checked = 0;
    for (size_t l = 0; l + 1 < b.n_levels; l++) {
        const sea_bake_level *f = &b.levels[l], *c = &b.levels[l + 1];
        if (f->level.low_res || c->level.low_res || c->level.level != f->level.level + 1)
            continue;
        CU_ASSERT_EQUAL(f->level.sub_n, f->level.level);
        pairs++;
        const sea_clip_level *lf = &f->level, *lc = &c->level;
        for (size_t jc = 0; jc < lc->ny; jc++)
            for (size_t ic = 0; ic < lc->nx; ic++) {
                /* coarse facet (ci, cj) covers fine facets 2 ci.., 2 cj.. */
                const long ci = lc->i0 + (long)ic, cj = lc->j0 + (long)jc;
                const long fi = 2 * ci - lf->i0, fj = 2 * cj - lf->j0;
                if (fi < 0 || fj < 0 || fi + 1 >= (long)lf->nx || fj + 1 >= (long)lf->ny)
                    continue;
                sea_moments avg = { 0 }, mag = { 0 };
                for (int dj = 0; dj < 2; dj++)
                    for (int di = 0; di < 2; di++) {
                        const size_t row = lf->ny - 1 - (size_t)(fj + dj);
                        const sea_moments m =
                            sea_facet_moments(&f->moments[row * lf->nx + (size_t)(fi + di)]);
                        avg.mx += 0.25 * m.mx;
                        avg.my += 0.25 * m.my;
                        avg.mxx += 0.25 * m.mxx;
                        avg.myy += 0.25 * m.myy;
                        avg.mxy += 0.25 * m.mxy;
                        avg.h += 0.25 * m.h;
                        mag.mx += 0.25 * fabs(m.mx);
                        mag.my += 0.25 * fabs(m.my);
                        mag.mxx += 0.25 * m.mxx;
                        mag.myy += 0.25 * m.myy;
                        mag.mxy += 0.25 * sqrt(m.mxx * m.myy);
                    }
                const sea_moments cm =
                    sea_facet_moments(&c->moments[(lc->ny - 1 - jc) * lc->nx + ic]);
                const sea_moments *m = &cm;
                const double u = 4.0 * 0x1p-24;
                ASSERT_ABS(avg.mx, m->mx, u * (mag.mx + fabs(m->mx)) + 1e-15);
                ASSERT_ABS(avg.my, m->my, u * (mag.my + fabs(m->my)) + 1e-15);
                ASSERT_ABS(avg.mxx, m->mxx, u * (mag.mxx + m->mxx));
                ASSERT_ABS(avg.myy, m->myy, u * (mag.myy + m->myy));
                ASSERT_ABS(avg.mxy, m->mxy, u * (mag.mxy + sqrt(m->mxx * m->myy)));
                ASSERT_ABS(avg.h, m->h, 1e-9);
                checked++;
            }
    }
    CU_ASSERT(pairs >= 1);
    CU_ASSERT(checked > 0);
    MEASURED("bake LEAN: %zu coarse texels over %zu level pairs equal the 2x2 fine mean\n",
             checked, pairs);
    sea_bake_free(&b);
    sea_view_free(r);
}

/* Normal, roughness and optics of every texel, as documented. */
static void test_derived_maps(void)
{
    const sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_bake b;
    bake(r, 0.0, &b);
    /* Eq 23 terms of this scene: sun from its temperature and solid
     * angle, sky a blackbody, one wavelength, radiance per um */
    const double wl = sc.wavelength;
    const double esun = sc.sun_transmittance * sc.sun_solid_angle *
                        sea_planck_radiance(wl, sc.sun_temperature);
    const double lsky = sea_planck_radiance(wl, sc.sky_temperature);
    const double bsea = sea_planck_radiance(wl, sc.temperature);
    size_t bad_norm = 0, bad_rough = 0, bad_opt = 0, bad_eq23 = 0, glint = 0, total = 0;
    for (size_t l = 0; l < b.n_levels; l++) {
        const sea_bake_level *bl = &b.levels[l];
        if (bl->level.low_res)
            continue;
        for (size_t q = 0; q < bl->level.nx * bl->level.ny; q++, total++) {
            const sea_moments mo = sea_facet_moments(&bl->moments[q]), *m = &mo;
            double n[3];
            sea_bake_normal(m, n);
            if (fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0) > 1e-14 || !(n[2] > 0.0) ||
                fabs(-n[0] / n[2] - m->mx) > 1e-14 || fabs(-n[1] / n[2] - m->my) > 1e-14)
                bad_norm++;
            double rough, aniso, rot;
            sea_bake_roughness(m, &rough, &aniso, &rot);
            const sea_slope_stats s = sea_moments_stats(m);
            /* rebuild C from the three numbers */
            const double tr = pow(rough, 4.0), l1 = 0.5 * tr * (1.0 + aniso),
                         l2 = 0.5 * tr * (1.0 - aniso), th = 2.0 * M_PI * rot;
            const double c = cos(th), sn = sin(th);
            const double xx = l1 * c * c + l2 * sn * sn, yy = l1 * sn * sn + l2 * c * c,
                         xy = (l1 - l2) * c * sn;
            const double tol = 1e-10 * tr;
            if (!(rough > 0.0 && rough < 1.0) || !(aniso >= 0.0 && aniso <= 1.0) ||
                !(rot >= 0.0 && rot < 0.5) || fabs(xx - s.cov.xx) > tol ||
                fabs(yy - s.cov.yy) > tol || fabs(xy - s.cov.xy) > tol)
                bad_rough++;
            const sea_facet_optics *o = &bl->optics[q];
            if (!(o->emissivity >= 0.0 && o->emissivity <= 1.0) || !(o->reflectivity >= 0.0) ||
                !isfinite(o->reflectivity) || !(o->radiance > 0.0) || !isfinite(o->radiance) ||
                !(o->temperature > 200.0 && o->temperature < 6000.0))
                bad_opt++;
            const double eq23 =
                1e-6 * (o->reflectivity * esun + (1.0 - o->emissivity) * lsky + o->emissivity * bsea);
            if (fabs(o->radiance - eq23) > 1e-12 * eq23)
                bad_eq23++;
            if (o->temperature > sc.temperature + 1.0)
                glint++;
        }
    }
    CU_ASSERT(total > 1000);
    CU_ASSERT_EQUAL(bad_norm, 0);
    CU_ASSERT_EQUAL(bad_rough, 0);
    CU_ASSERT_EQUAL(bad_opt, 0);
    CU_ASSERT_EQUAL(bad_eq23, 0);
    CU_ASSERT(glint > 0); /* the sun is in view: some texels are brighter than the sea */
    MEASURED("bake: %zu texels, %zu brighter than the sea by more than 1 K (glint)\n", total,
             glint);
    sea_bake_free(&b);
    sea_view_free(r);
}

/* The derived maps on hand-made moments: an isotropic facet, an
 * anisotropic one along 30 deg, a flat one. */
static void test_roughness_convention(void)
{
    const double s2 = 0.0123; /* per-axis slope variance */
    sea_moments iso = { 0.1, -0.2, 0.01 + s2, 0.1 * -0.2, 0.04 + s2, 0.0 };
    double rough, aniso, rot;
    sea_bake_roughness(&iso, &rough, &aniso, &rot);
    ASSERT_REL(rough * rough, sqrt(2.0 * s2), 1e-12, 0.0); /* Beckmann alpha = sqrt(2) sigma */
    ASSERT_ABS(aniso, 0.0, 1e-9);
    const double a = 30.0 * DEG, l1 = 0.02, l2 = 0.005;
    sea_moments an = { 0.0, 0.0, l1 * cos(a) * cos(a) + l2 * sin(a) * sin(a),
                       (l1 - l2) * cos(a) * sin(a), l1 * sin(a) * sin(a) + l2 * cos(a) * cos(a),
                       0.0 };
    sea_bake_roughness(&an, &rough, &aniso, &rot);
    ASSERT_REL(aniso, (l1 - l2) / (l1 + l2), 1e-12, 0.0);
    ASSERT_REL(rot, 30.0 / 360.0, 1e-12, 0.0);
    /* major axis at -30 deg is 150 deg: rotation in [0, 0.5) */
    an.mxy = -an.mxy;
    sea_bake_roughness(&an, &rough, &aniso, &rot);
    ASSERT_REL(rot, 150.0 / 360.0, 1e-12, 0.0);
    const sea_moments flat = { 0 };
    sea_bake_roughness(&flat, &rough, &aniso, &rot);
    CU_ASSERT(rough == 0.0 && aniso == 0.0 && rot == 0.0);
    double n[3];
    sea_bake_normal(&flat, n);
    CU_ASSERT(n[0] == 0.0 && n[1] == 0.0 && n[2] == 1.0);
}

/* The texel optics are those the renderer gives a pixel looking at the
 * texel centre: a spherical-earth bake far out agrees with the flat one
 * near the sensor, and a bad time is refused. */
/* The view maps reproduce seabake render: the multiresolution sea answers
 * the render's pixel (sea_multires_pixel) and the bake's map point
 * (sea_multires_look_at at the pixel's mean-surface point) with the same
 * query, so the optics of the answer toward its directions give the
 * pixel's radiance: exactly (as float) at the pixel centre (the render
 * starts a pixel's rays at the hits of the pixel below where the ordering
 * allows, sea_multires_pixel afresh: the same hits but where a ray grazes a
 * crest, none here); within 1e-5
 * relative through the map point, which comes back through
 * sea_camera_project to within 1e-6 px of the centre and moves each ray's
 * point by about 1e-6 of a facet (a ray that grazes a crest there can
 * switch between the crest and what lies behind it: at most 1 % of the
 * pixels may differ more, measured none).  The grid is 64 facets, so
 * several levels are capped windows with fades.  And the view texel at a
 * facet centre (the middle one of K = 3) holds the facet's own optics
 * wherever that level alone is read. */
static void test_view_matches_render(void)
{
    const sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_error err;
    sea_image img;
    CU_ASSERT_EQUAL_FATAL(sea_image_alloc(sc.width, sc.height, &img, &err), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_view_render_frame(r, 0.0, &img, NULL, NULL, &err), SEA_OK);
    const sea_clip_level *lv;
    sea_view_levels(r, &lv);
    sea_multires_frame *f = NULL;
    CU_ASSERT_EQUAL_FATAL(sea_multires_frame_alloc(sea_view_multires(r), 0.0, NULL, NULL, &f,
                                                   &err),
                          SEA_OK);
    const sea_camera *cam = sea_view_camera(r);
    const double sun[3] = { sin(sc.sun_zenith) * cos(sc.sun_azimuth),
                            sin(sc.sun_zenith) * sin(sc.sun_azimuth), cos(sc.sun_zenith) };
    double worst = 0.0, worst_px = 0.0;
    size_t checked = 0, mixed = 0, exact = 0, off = 0;
    for (int j = 0; j < sc.height; j++)
        for (int i = 0; i < sc.width; i++) {
            sea_pixel_geom g;
            sea_camera_pixel(cam, i + 0.5, j + 0.5, &g);
            if (!g.hit)
                continue;
            const size_t q = (size_t)j * (size_t)sc.width + (size_t)i;
            sea_multires_sample s;
            sea_facet_optics o;
            sea_pixel_geom n;
            /* the render's own query */
            sea_multires_pixel(f, i, j, &s);
            CU_ASSERT_FATAL(s.hit);
            memcpy(n.normal, s.normal, sizeof n.normal);
            sea_slope_stats st = sea_moments_stats(&s.moments);
            CU_ASSERT_EQUAL_FATAL(sea_view_facet_optics(r, &st, s.obs,
                                                          sea_camera_local_dir(&n, sun), &o,
                                                          &err),
                                  SEA_OK);
            exact += (float)o.radiance == img.radiance[q] && (float)o.emissivity == img.emissivity[q];
            /* the bake's, through the map point */
            double u, v;
            CU_ASSERT_FATAL(sea_multires_look_at(f, g.x, g.y, &s, &u, &v));
            worst_px = fmax(worst_px, hypot(u - (i + 0.5), v - (j + 0.5)));
            memcpy(n.normal, s.normal, sizeof n.normal);
            st = sea_moments_stats(&s.moments);
            CU_ASSERT_EQUAL_FATAL(sea_view_facet_optics(r, &st, s.obs,
                                                          sea_camera_local_dir(&n, sun), &o,
                                                          &err),
                                  SEA_OK);
            const double d = fmax(fabs(o.radiance - img.radiance[q]) / img.radiance[q],
                                  fabs(o.emissivity - img.emissivity[q]));
            if (d < 1e-5)
                worst = fmax(worst, d);
            else
                off++;
            checked++;
            mixed += img.level[q] != (float)lv[0].facet;
        }
    MEASURED("view query vs render: %zu pixels (%zu not on the finest level), %zu exact; "
             "through the map point (%.2g px away): max relative difference %.2g, %zu beyond "
             "1e-5\n",
             checked, mixed, exact, worst_px, worst, off);
    CU_ASSERT(checked > 1000);
    CU_ASSERT(mixed > 100);
    CU_ASSERT_EQUAL(exact, checked);
    CU_ASSERT(worst_px < 1e-6);
    CU_ASSERT(off <= checked / 100);
    sea_multires_frame_free(f);

    /* the bake: the middle view texel of each facet */
    sea_bake b;
    CU_ASSERT_EQUAL_FATAL(sea_bake_frame(r, 0.0, 3, &b, NULL, NULL, &err), SEA_OK);
    size_t same = 0, total = 0;
    for (size_t l = 0; l < b.n_levels; l++) {
        const sea_bake_level *bl = &b.levels[l];
        if (bl->level.low_res)
            continue;
        CU_ASSERT_EQUAL(bl->view_k, 3);
        const size_t nx = bl->level.nx, ny = bl->level.ny;
        for (size_t row = 0; row < ny; row++)
            for (size_t i = 0; i < nx; i++) {
                const double v = bl->view[(3 * row + 1) * 3 * nx + 3 * i + 1];
                CU_ASSERT(isfinite(v) && v > 0.0);
                same += v == (float)bl->optics[row * nx + i].radiance;
                total++;
            }
    }
    printf("%zu of %zu middle view texels are their facet's ", same, total);
    CU_ASSERT(same > total / 4);
    CU_ASSERT(same < total);
    sea_bake_free(&b);
    sea_image_free(&img);
    sea_view_free(r);
}

/* A progress function that asks to stop after `left` calls. */
static int stop_after(void *ctx, double fraction)
{
    int *left = ctx;
    CU_ASSERT(fraction >= 0.0 && fraction <= 1.0);
    return --*left < 0;
}

/* Cancelling: the progress function's stop ends the bake with
 * SEA_ERR_CANCELLED and nothing to free; with no stop it runs to the end,
 * its fractions within [0, 1]. */
static void test_cancel(void)
{
    const sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_bake b;
    sea_error err;
    int left = 3;
    CU_ASSERT_EQUAL(sea_bake_frame(r, 0.0, 3, &b, stop_after, &left, &err), SEA_ERR_CANCELLED);
    CU_ASSERT_EQUAL(b.n_levels, 0);
    CU_ASSERT(strstr(err.msg, "cancelled") != NULL);
    left = 1000000;
    CU_ASSERT_EQUAL(sea_bake_frame(r, 0.0, 3, &b, stop_after, &left, &err), SEA_OK);
    CU_ASSERT(left < 1000000);
    sea_bake_free(&b);
    sea_view_free(r);
}

static void test_errors_and_earth(void)
{
    sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_bake b;
    sea_error err;
    CU_ASSERT_EQUAL(sea_bake_frame(r, NAN, 1, &b, NULL, NULL, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "time") != NULL);
    CU_ASSERT_EQUAL(b.n_levels, 0);
    bake(r, 0.0, &b);
    sc.earth = SEA_EARTH_SPHERICAL;
    sea_view *rs = prepare(&sc);
    sea_bake bs;
    bake(rs, 0.0, &bs);
    /* 120 m up, a few hundred metres out: the sphere tilts the view by
     * under 0.01 deg, so the optics agree to 1e-3 relative */
    const sea_bake_level *f = &b.levels[0], *s = &bs.levels[0];
    CU_ASSERT_FATAL(!f->level.low_res && f->level.nx == s->level.nx && f->level.ny == s->level.ny);
    double worst = 0.0;
    for (size_t q = 0; q < f->level.nx * f->level.ny; q++)
        worst = fmax(worst, fabs(f->optics[q].emissivity - s->optics[q].emissivity));
    CU_ASSERT(worst < 1e-3);
    MEASURED("bake: spherical vs flat earth, level 0 emissivity differs by at most %.2g\n", worst);
    sea_bake_free(&b);
    sea_bake_free(&bs);
    sea_view_free(r);
    sea_view_free(rs);
}

/* sea_bake_frame_each: each high-resolution level once, finest first, with
 * the maps of sea_bake_frame bit for bit and only that level's maps held;
 * the headers stay; a failure of the callback stops the bake with its
 * status and message. */
typedef struct {
    const sea_bake *all;
    size_t calls, last, diff, held;
    int fail_at;
} each_ctx;

static sea_status each_level(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    each_ctx *c = ctx;
    const sea_bake_level *bl = &b->levels[l], *ref = &c->all->levels[l];
    CU_ASSERT(c->calls == 0 || l > c->last);
    CU_ASSERT(!bl->level.low_res);
    c->last = l;
    c->calls++;
    for (size_t k = 0; k < b->n_levels; k++)
        c->held += k != l && (b->levels[k].moments || b->levels[k].optics || b->levels[k].view);
    const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
    if (bl->moments == NULL || bl->optics == NULL || bl->view == NULL ||
        memcmp(bl->moments, ref->moments, n * sizeof *bl->moments) != 0 ||
        memcmp(bl->optics, ref->optics, n * sizeof *bl->optics) != 0 ||
        memcmp(bl->view, ref->view, nv * sizeof *bl->view) != 0)
        c->diff++;
    if (c->fail_at >= 0 && (int)c->calls > c->fail_at)
        return sea_fail(err, SEA_ERR_IO, "stopped by the callback at level %zu", l);
    return SEA_OK;
}

static void test_each_level(void)
{
    const sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_bake all, b;
    sea_error err;
    const int k = UNIT_QUICK ? 1 : 3; /* view texels per facet: 1 under valgrind */
    CU_ASSERT_EQUAL_FATAL(sea_bake_frame(r, 0.4, k, &all, NULL, NULL, &err), SEA_OK);
    each_ctx c = {&all, 0, 0, 0, 0, -1};
    CU_ASSERT_EQUAL_FATAL(sea_bake_frame_each(r, 0.4, k, &b, NULL, NULL, each_level, &c, &err),
                          SEA_OK);
    CU_ASSERT_EQUAL(c.calls, count_hr(&all));
    CU_ASSERT_EQUAL(c.diff, 0);
    CU_ASSERT_EQUAL(c.held, 0);
    CU_ASSERT_EQUAL(b.n_levels, all.n_levels);
    for (size_t l = 0; l < b.n_levels; l++) {
        CU_ASSERT(memcmp(&b.levels[l].level, &all.levels[l].level, sizeof b.levels[l].level) == 0);
        CU_ASSERT(memcmp(&b.levels[l].lr_optics, &all.levels[l].lr_optics,
                         sizeof b.levels[l].lr_optics) == 0);
        CU_ASSERT_PTR_NULL(b.levels[l].moments);
        CU_ASSERT_PTR_NULL(b.levels[l].view);
    }
    sea_bake_free(&b);
    /* the callback's failure */
    each_ctx stop = {&all, 0, 0, 0, 0, 1};
    CU_ASSERT_EQUAL(sea_bake_frame_each(r, 0.4, k, &b, NULL, NULL, each_level, &stop, &err),
                    SEA_ERR_IO);
    CU_ASSERT(strstr(err.msg, "stopped by the callback") != NULL);
    CU_ASSERT_EQUAL(stop.calls, 2);
    CU_ASSERT_EQUAL(b.n_levels, 0);
    sea_bake_free(&all);
    sea_view_free(r);
}

/* sea_bake_frame_image: the sensor's image is sea_view_render_frame's bit for
 * bit (every channel), and the levels are sea_bake_frame_each's
 * (each_level compares them with a whole bake's); an image of the wrong
 * size is refused with nothing to free.  The whole bake's surfaces store
 * the bounds of their finest cells, as a bake of this size does; the
 * image's bake computes them as the march asks (sea_view_set_bake_lean,
 * what a bake does when they would take more than 64 MB): the same bounds
 * to the bit, so the same image as the render's frame, which stores them,
 * and the same maps. */
static void test_frame_image(void)
{
    const sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_bake all, b;
    sea_error err;
    const int k = UNIT_QUICK ? 1 : 3;
    CU_ASSERT_EQUAL_FATAL(sea_bake_frame(r, 0.4, k, &all, NULL, NULL, &err), SEA_OK);
    sea_image ref, img, small;
    CU_ASSERT_EQUAL_FATAL(sea_image_alloc(sc.width, sc.height, &ref, &err), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_image_alloc(sc.width, sc.height, &img, &err), SEA_OK);
    CU_ASSERT_EQUAL_FATAL(sea_view_render_frame(r, 0.4, &ref, NULL, NULL, &err), SEA_OK);
    each_ctx c = {&all, 0, 0, 0, 0, -1};
    sea_view_set_bake_lean(r, 1);
    CU_ASSERT_EQUAL_FATAL(
        sea_bake_frame_image(r, 0.4, k, &img, &b, NULL, NULL, each_level, &c, &err), SEA_OK);
    CU_ASSERT_EQUAL(c.calls, count_hr(&all));
    CU_ASSERT_EQUAL(c.diff, 0);
    const size_t np = (size_t)sc.width * (size_t)sc.height;
    CU_ASSERT(memcmp(img.radiance, ref.radiance, np * sizeof *img.radiance) == 0);
    CU_ASSERT(memcmp(img.temperature, ref.temperature, np * sizeof *img.temperature) == 0);
    CU_ASSERT(memcmp(img.level, ref.level, np * sizeof *img.level) == 0);
    CU_ASSERT(memcmp(img.emissivity, ref.emissivity, np * sizeof *img.emissivity) == 0);
    CU_ASSERT(memcmp(img.reflectivity, ref.reflectivity, np * sizeof *img.reflectivity) == 0);
    sea_bake_free(&b);
    CU_ASSERT_EQUAL_FATAL(sea_image_alloc(sc.width - 1, sc.height, &small, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_bake_frame_image(r, 0.4, k, &small, &b, NULL, NULL, NULL, NULL, &err),
                    SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "does not match") != NULL);
    CU_ASSERT_EQUAL(b.n_levels, 0);
    sea_image_free(&small);
    sea_image_free(&img);
    sea_image_free(&ref);
    sea_bake_free(&all);
    sea_view_free(r);
}

/* The horizon grid (sea_bake_horizon_alloc), on both earths, at a mast
 * view with the horizon in view and at a nadir view (the full turn):
 *  - it reaches every pixel centre's sea point: each lies inside the grid
 *    (arc within [0, last ring], azimuth within the span), and on the
 *    sphere with sky in view the last ring is the horizon's distance
 *    R acos(R / (R + h)) to 1e-9;
 *  - its nodes carry seabake render's low-resolution radiance: at every
 *    pixel centre, the grid's bilinear interpolation against the radiance
 *    computed there directly (sea_view_facet_optics toward the sensor) is
 *    within 4 x tol (the refinement bounds the midpoints of each direction
 *    at tol; a cell's centre, interpolated both ways, may add the two and
 *    their cross term);
 *  - a tolerance outside [1e-5, 0.1] is refused. */
static double hz_direct(const sea_view *r, const sea_bake_horizon *h, double arc, double az)
{
    const sea_camera *cam = sea_view_camera(r);
    const sea_scene *sc = sea_view_scene(r);
    double q[3], d[3];
    sea_pixel_geom g;
    sea_camera_sea_point(cam, h->x0 + arc * cos(az), h->y0 + arc * sin(az), q, g.normal);
    for (int k = 0; k < 3; k++)
        d[k] = cam->pos[k] - q[k];
    const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++)
        d[k] /= len;
    const double sv[3] = {sin(sc->sun_zenith) * cos(sc->sun_azimuth),
                          sin(sc->sun_zenith) * sin(sc->sun_azimuth), cos(sc->sun_zenith)};
    const sea_moments m = sea_view_lr_moments(r);
    const sea_slope_stats st = sea_moments_stats(&m);
    sea_facet_optics o;
    sea_error err;
    CU_ASSERT_EQUAL(sea_view_facet_optics(r, &st, sea_camera_local_dir(&g, d),
                                            sea_camera_local_dir(&g, sv), &o, &err),
                    SEA_OK);
    return o.radiance;
}

static size_t hz_find(const double *v, size_t n, double x)
{
    size_t k = 0;
    while (k + 2 < n && v[k + 1] <= x)
        k++;
    return k;
}

static void test_horizon(void)
{
    const double tol = UNIT_QUICK ? 1e-2 : 1e-3; /* fewer nodes under valgrind */
    for (int view = 0; view < 2; view++)
        for (int earth = 0; earth < 2; earth++) {
            sea_scene sc = bake_scene();
            sc.width = sc.height = UNIT_QUICK ? 12 : 24;
            sc.earth = earth ? SEA_EARTH_SPHERICAL : SEA_EARTH_FLAT;
            if (view == 0) { /* a mast: the horizon in view */
                sc.altitude = 20.0;
                sc.look_zenith = 88.0 * DEG;
                sc.hfov = 30.0 * DEG;
                sc.sun_zenith = 75.0 * DEG;
                sc.sun_azimuth = 190.0 * DEG;
            } else {
                sc.look_zenith = 0.0;
            }
            sea_view *r = prepare(&sc);
            sea_bake_horizon h;
            sea_error err;
            CU_ASSERT_EQUAL_FATAL(sea_bake_horizon_alloc(r, tol, &h, &err), SEA_OK);
            CU_ASSERT(h.n_arc >= 2 && h.n_az >= 2 && h.arc[0] == 0.0);
            CU_ASSERT_EQUAL(h.full_turn, view == 1);
            CU_ASSERT(h.max_err <= tol);
            if (view == 0 && earth) {
                const double R = SEA_EARTH_RADIUS, hz = R * acos(R / (R + sc.altitude));
                CU_ASSERT(fabs(h.arc[h.n_arc - 1] - hz) <= 1e-9 * hz);
            }
            const sea_camera *cam = sea_view_camera(r);
            int outside = 0, sea = 0;
            double worst = 0.0;
            for (int j = 0; j < sc.height; j++)
                for (int i = 0; i < sc.width; i++) {
                    sea_pixel_geom g;
                    sea_camera_pixel(cam, i + 0.5, j + 0.5, &g);
                    if (!g.hit)
                        continue;
                    sea++;
                    const double dx = g.x - h.x0, dy = g.y - h.y0, arc = hypot(dx, dy);
                    double az = atan2(dy, dx);
                    while (az < h.az[0])
                        az += 2.0 * M_PI;
                    while (az > h.az[h.n_az - 1])
                        az -= 2.0 * M_PI;
                    if (!(arc <= h.arc[h.n_arc - 1] && az >= h.az[0] && az <= h.az[h.n_az - 1])) {
                        outside++;
                        continue;
                    }
                    const size_t a = hz_find(h.arc, h.n_arc, arc), b = hz_find(h.az, h.n_az, az);
                    const double s = (arc - h.arc[a]) / (h.arc[a + 1] - h.arc[a]);
                    const double t = (az - h.az[b]) / (h.az[b + 1] - h.az[b]);
                    const double *L = h.radiance;
                    const size_t nz = h.n_az;
                    const double lin = (1 - s) * ((1 - t) * L[a * nz + b] + t * L[a * nz + b + 1]) +
                                       s * ((1 - t) * L[(a + 1) * nz + b] +
                                            t * L[(a + 1) * nz + b + 1]);
                    const double direct = hz_direct(r, &h, arc, az);
                    worst = fmax(worst, fabs(lin - direct) / direct);
                }
            MEASURED("horizon (%s, %s): %zu x %zu nodes, last ring %.6g m; %d sea pixels, %d "
                     "outside, worst interpolation %.2e\n",
                     view ? "nadir" : "mast", earth ? "spherical" : "flat", h.n_arc, h.n_az,
                     h.arc[h.n_arc - 1], sea, outside, worst);
            CU_ASSERT(sea > 0);
            CU_ASSERT_EQUAL(outside, 0);
            CU_ASSERT(worst <= 4.0 * tol);
            sea_bake_horizon_free(&h);
            sea_bake_horizon_free(&h); /* harmless twice */
            if (view == 0 && earth == 0) {
                CU_ASSERT_EQUAL(sea_bake_horizon_alloc(r, 0.2, &h, &err), SEA_ERR_DOMAIN);
                CU_ASSERT(strstr(err.msg, "tolerance") != NULL);
                CU_ASSERT_EQUAL(sea_bake_horizon_alloc(r, NAN, &h, &err), SEA_ERR_DOMAIN);
            }
            sea_view_free(r);
        }
}

/* sea_bake_frame_rows: rows row0, row0 + 3, ... of every level's optics and
 * view texels are sea_bake_frame's bit for bit, the moments all of them;
 * the three shares together cover every row; a first row outside
 * [0, step) or a step below 1 is SEA_ERR_DOMAIN. */
typedef struct {
    const sea_bake *all;
    size_t row0, step, calls, diff, rows;
} rows_ctx;

static sea_status rows_level(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    (void)err;
    rows_ctx *c = ctx;
    const sea_bake_level *bl = &b->levels[l], *ref = &c->all->levels[l];
    const size_t nx = bl->level.nx, ny = bl->level.ny, k = bl->view_k;
    c->calls++;
    if (memcmp(bl->moments, ref->moments, nx * ny * sizeof *bl->moments) != 0)
        c->diff++;
    for (size_t row = c->row0; row < ny; row += c->step) {
        c->rows++;
        if (memcmp(bl->optics + row * nx, ref->optics + row * nx, nx * sizeof *bl->optics) != 0 ||
            memcmp(bl->view + row * k * k * nx, ref->view + row * k * k * nx,
                   k * k * nx * sizeof *bl->view) != 0)
            c->diff++;
    }
    return SEA_OK;
}

static void test_bake_rows(void)
{
    const sea_scene sc = bake_scene();
    sea_view *r = prepare(&sc);
    sea_bake all, b;
    sea_error err;
    CU_ASSERT_EQUAL_FATAL(sea_bake_frame(r, 0.4, 3, &all, NULL, NULL, &err), SEA_OK);
    size_t rows = 0, want = 0;
    for (size_t l = 0; l < all.n_levels; l++)
        if (!all.levels[l].level.low_res)
            want += all.levels[l].level.ny;
    for (int row0 = 0; row0 < 3; row0++) {
        rows_ctx c = {&all, (size_t)row0, 3, 0, 0, 0};
        CU_ASSERT_EQUAL_FATAL(
            sea_bake_frame_rows(r, 0.4, 3, row0, 3, &b, NULL, NULL, rows_level, &c, &err), SEA_OK);
        CU_ASSERT_EQUAL(c.calls, count_hr(&all));
        CU_ASSERT_EQUAL(c.diff, 0);
        rows += c.rows;
        sea_bake_free(&b);
    }
    CU_ASSERT_EQUAL(rows, want);
    CU_ASSERT_EQUAL(sea_bake_frame_rows(r, 0.4, 3, 3, 3, &b, NULL, NULL, rows_level, NULL, &err),
                    SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "0 <= first row < step") != NULL);
    CU_ASSERT_EQUAL(sea_bake_frame_rows(r, 0.4, 3, 0, 0, &b, NULL, NULL, rows_level, NULL, &err),
                    SEA_ERR_DOMAIN);
    sea_bake_free(&all);
    sea_view_free(r);
}

/* The view mask's test: sea_camera_hits is sea_camera_pixel's hit, on
 * both earths, over an image that holds the horizon (and beyond it). */
static void test_camera_hits(void)
{
    sea_scene sc = bake_scene();
    sc.look_zenith = 88.0 * DEG;
    size_t hits = 0, total = 0, diff = 0;
    for (int e = 0; e < 2; e++) {
        sc.earth = e ? SEA_EARTH_SPHERICAL : SEA_EARTH_FLAT;
        sea_view *r = prepare(&sc);
        const sea_camera *cam = sea_view_camera(r);
        for (double v = -3.25; v <= cam->height + 3.0; v += 0.37)
            for (double u = -3.5; u <= cam->width + 3.0; u += 0.53) {
                sea_pixel_geom g;
                sea_camera_pixel(cam, u, v, &g);
                const int h = sea_camera_hits(cam, u, v);
                diff += h != g.hit;
                hits += h != 0;
                total++;
            }
        sea_view_free(r);
    }
    CU_ASSERT_EQUAL(diff, 0);
    CU_ASSERT(hits > total / 10 && hits < total - total / 10);
}

/* The air in the maps (issue 45).  With [atmosphere] a view texel holds
 * what the sensor receives of the sea there across the air, tau L + path,
 * as seabake render's pixel: L is the same texel of the same bake without
 * the air (the same waves), the range the one its ray meets the sea at
 * (sea_multires_look_at at the texel's map point) or, for a texel the
 * sensor does not see, the facet centre's on the mean surface.  Checked
 * with Beer-Lambert (tau = exp(-b d), path (1 - tau) B(T_air), B from
 * sea_planck_radiance) and with an [atmosphere] table of an unrelated shape
 * (tau = 1 / (1 + d / 900 m), path rising as d / (d + 400 m), read here by
 * linear interpolation between its rows), each texel within AIR_REL
 * (float maps; measured below).  The optics map keeps the sea-leaving
 * radiance, bit for bit the bake's without air; the horizon grid's nodes
 * carry the air along their range (from sea_view_facet_optics' radiance
 * and the range, within 1e-12). */
static const double AIR_T = 281.3, AIR_EXT = 1.3e-3; /* K, 1/m */
enum { AIR_ROWS = 401 };
static const double AIR_STEP = 50.0; /* m between the table's rows */
static const double AIR_REL = 1e-6;  /* float maps: a few roundings of 6e-8 */

static double air_table_tau(double d)
{
    return 1.0 / (1.0 + d / 900.0);
}

static double air_table_path(double d)
{
    return 0.83 * d / (d + 400.0);
}

/* The table as the render reads it: linear between rows, the last beyond. */
static void air_table_at(double d, double *tau, double *path)
{
    double x = d / AIR_STEP;
    if (x >= AIR_ROWS - 1)
        x = AIR_ROWS - 1;
    const double k = floor(x) < AIR_ROWS - 1 ? floor(x) : AIR_ROWS - 2, a = x - k;
    *tau = (1.0 - a) * air_table_tau(k * AIR_STEP) + a * air_table_tau((k + 1) * AIR_STEP);
    *path = (1.0 - a) * air_table_path(k * AIR_STEP) + a * air_table_path((k + 1) * AIR_STEP);
}

static void air_expect(int table, double d, double B, double *tau, double *path)
{
    if (table) {
        air_table_at(d, tau, path);
    } else {
        *tau = exp(-AIR_EXT * d);
        *path = (1.0 - *tau) * B;
    }
}

static void check_air_maps(int table, const char *table_path)
{
    sea_scene sc = bake_scene();
    sea_view *r0 = prepare(&sc);
    sc.air_temperature = AIR_T;
    if (table)
        snprintf(sc.atmosphere_table_file, sizeof sc.atmosphere_table_file, "%s", table_path);
    else
        sc.extinction = AIR_EXT;
    sea_view *r = prepare(&sc);
    CU_ASSERT(sea_view_has_air(r));
    CU_ASSERT(!sea_view_has_air(r0));
    const double B = sea_planck_radiance(sc.wavelength, AIR_T) * 1e-6; /* per um */
    sea_bake b0, b;
    bake(r0, 0.0, &b0);
    bake(r, 0.0, &b);
    sea_error err;
    sea_multires_frame *f = NULL;
    CU_ASSERT_EQUAL_FATAL(sea_multires_frame_alloc(sea_view_multires(r), 0.0, NULL, NULL, &f,
                                                   &err),
                          SEA_OK);
    const sea_camera *cam = sea_view_camera(r);
    size_t n_ray = 0, n_facet = 0, n_off = 0, n_optics_diff = 0;
    double worst = 0.0, tau_min = 1.0;
    for (size_t l = 0; l < b.n_levels; l++) {
        const sea_bake_level *bl = &b.levels[l], *bl0 = &b0.levels[l];
        const sea_clip_level *lv = &bl->level;
        if (lv->low_res)
            continue;
        CU_ASSERT_EQUAL_FATAL(bl->view_k, 1);
        for (size_t R = 0; R < lv->ny; R++)
            for (size_t i = 0; i < lv->nx; i++) {
                const size_t q = R * lv->nx + i;
                n_optics_diff += bl->optics[q].radiance != bl0->optics[q].radiance;
                const double x = ((double)lv->i0 + (double)i + 0.5) * lv->facet;
                const double y = ((double)lv->j0 + (double)(lv->ny - R) - 0.5) * lv->facet;
                const double L = bl0->view[q], got = bl->view[q];
                /* the ray's range, and the facet centre's */
                double d_ray = -1.0, u, v, p[3], n[3], tau, path;
                sea_multires_sample s;
                if (sea_multires_look_at(f, x, y, &s, &u, &v))
                    d_ray = s.range;
                sea_camera_sea_point(cam, x, y, p, n);
                const double d_facet = hypot(hypot(p[0] - cam->pos[0], p[1] - cam->pos[1]),
                                             p[2] - cam->pos[2]);
                double e_ray = INFINITY, tau_ray = 1.0;
                if (d_ray >= 0.0) {
                    air_expect(table, d_ray, B, &tau_ray, &path);
                    e_ray = fabs(got - (tau_ray * L + path)) / got;
                }
                air_expect(table, d_facet, B, &tau, &path);
                const double e_facet = fabs(got - (tau * L + path)) / got;
                /* the closer of the two (they coincide where the ray meets
                 * the mean surface near the facet centre) */
                if (e_ray <= e_facet && e_ray < AIR_REL) {
                    n_ray++;
                    worst = fmax(worst, e_ray);
                    tau_min = fmin(tau_min, tau_ray);
                } else if (e_facet < AIR_REL) {
                    n_facet++;
                    worst = fmax(worst, e_facet);
                } else {
                    n_off++;
                }
            }
    }
    MEASURED("air in the view texels (%s): %zu along the ray's range, %zu along the facet "
             "centre's, %zu neither; worst relative %.2g; least tau %.3f\n",
             table ? "table" : "Beer-Lambert", n_ray, n_facet, n_off, worst, tau_min);
    CU_ASSERT(n_ray > 500);
    CU_ASSERT(n_facet > 100);
    CU_ASSERT_EQUAL(n_off, 0);
    CU_ASSERT(tau_min < 0.8); /* the air matters */
    CU_ASSERT_EQUAL(n_optics_diff, 0);
    /* the horizon grid */
    sea_bake_horizon h;
    CU_ASSERT_EQUAL_FATAL(sea_bake_horizon_alloc(r, 1e-3, &h, &err), SEA_OK);
    const sea_scene *scr = sea_view_scene(r);
    const double sv[3] = { sin(scr->sun_zenith) * cos(scr->sun_azimuth),
                           sin(scr->sun_zenith) * sin(scr->sun_azimuth), cos(scr->sun_zenith) };
    const sea_moments m = sea_view_lr_moments(r);
    const sea_slope_stats st = sea_moments_stats(&m);
    double hworst = 0.0;
    for (size_t i = 0; i < h.n_arc; i++)
        for (size_t j = 0; j < h.n_az; j++) {
            double p[3], d[3];
            sea_pixel_geom g;
            sea_camera_sea_point(cam, h.x0 + h.arc[i] * cos(h.az[j]),
                                 h.y0 + h.arc[i] * sin(h.az[j]), p, g.normal);
            for (int k = 0; k < 3; k++)
                d[k] = cam->pos[k] - p[k];
            const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int k = 0; k < 3; k++)
                d[k] /= len;
            sea_dir obs = sea_camera_local_dir(&g, d);
            obs.theta = fmin(obs.theta, 89.999 * DEG); /* as horizon.c holds it */
            sea_facet_optics o;
            CU_ASSERT_EQUAL_FATAL(sea_view_facet_optics(r, &st, obs,
                                                          sea_camera_local_dir(&g, sv), &o,
                                                          &err),
                                  SEA_OK);
            CU_ASSERT_EQUAL(o.seen, o.radiance);
            double tau, path;
            air_expect(table, len, B, &tau, &path);
            const double want = tau * o.radiance + path;
            hworst = fmax(hworst, fabs(h.radiance[i * h.n_az + j] - want) / want);
        }
    MEASURED("air at the horizon grid's %zu nodes (%s): worst relative %.2g\n",
             h.n_arc * h.n_az, table ? "table" : "Beer-Lambert", hworst);
    CU_ASSERT(hworst < 1e-12);
    sea_bake_horizon_free(&h);
    sea_multires_frame_free(f);
    sea_bake_free(&b0);
    sea_bake_free(&b);
    sea_view_free(r0);
    sea_view_free(r);
}

static void test_air_in_maps(void)
{
    check_air_maps(0, NULL);
    char dir[] = "/tmp/seabake-air-XXXXXX";
    CU_ASSERT_FATAL(mkdtemp(dir) != NULL);
    char path[128];
    snprintf(path, sizeof path, "%s/atm.csv", dir);
    FILE *f = fopen(path, "w");
    CU_ASSERT_FATAL(f != NULL);
    fputs("range_m,wavelength_um,transmittance,path_radiance\n", f);
    for (int k = 0; k < AIR_ROWS; k++)
        for (int w = 0; w < 2; w++)
            fprintf(f, "%.17g,%.17g,%.17g,%.17g\n", k * AIR_STEP, w ? 4.1 : 3.9,
                    air_table_tau(k * AIR_STEP), air_table_path(k * AIR_STEP));
    fclose(f);
    check_air_maps(1, path);
    remove(path);
    rmdir(dir);
}

int test_bake_register(void)
{
    CU_pSuite s = CU_add_suite("bake", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "moments are sea_waves_facets', north up", test_moments_exact) ||
           !CU_add_test(s, "LEAN averaging across levels", test_lean_across_levels) ||
           !CU_add_test(s, "normal, roughness, optics, Eq 23", test_derived_maps) ||
           !CU_add_test(s, "roughness convention", test_roughness_convention) ||
           !CU_add_test(s, "view maps reproduce seabake render", test_view_matches_render) ||
           !CU_add_test(s, "cancelled by the progress function", test_cancel) ||
           !CU_add_test(s, "one level at a time", test_each_level) ||
           !CU_add_test(s, "the sensor's image from the bake's surfaces", test_frame_image) ||
           !CU_add_test(s, "rows: shares bit for bit", test_bake_rows) ||
           !CU_add_test(s, "horizon grid: extent and interpolation", test_horizon) ||
           !CU_add_test(s, "the view mask's hit test", test_camera_hits) ||
           !CU_add_test(s, "errors, spherical earth", test_errors_and_earth) ||
           !CU_add_test(s, "the air in the view texels and the horizon grid",
                        test_air_in_maps);
}
