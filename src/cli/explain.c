/* explain.c - --explain of render and bake: the levels, windows,
 * sub-facets, emissivity rule, wave components, fallbacks and spectral
 * samples that sea_view_alloc chose, and why, on standard error. */
#include <math.h>
#include <stdio.h>

#include "cli.h"

/* Wavelengths listed by --explain before "...". */
enum { EXPLAIN_SAMPLES = 16 };

/* --explain of render and bake: what sea_view_alloc chose, and why. */
void sea_cli_explain(const char *what, const char *scene_path, const sea_view *r)
{
    const sea_scene *sc = sea_view_scene(r);
    const sea_clip_level *lv;
    const size_t n = sea_view_levels(r, &lv);
    const size_t npix = (size_t)sc->width * (size_t)sc->height;
    size_t sea_pixels = 0;
    for (size_t i = 0; i < n; ++i)
        sea_pixels += lv[i].pixels;
    char grid[64];
    size_t grid_needed = 0;
    const size_t fallback = sea_multires_fallback(sea_view_multires(r), &grid_needed);
    if (sc->grid == SEA_GRID_AUTO && sc->windows == SEA_WINDOWS_CLIPMAP)
        snprintf(grid, sizeof grid, "grid auto: 256");
    else if (sc->grid == SEA_GRID_AUTO)
        snprintf(grid, sizeof grid, "grid auto: %zu at most", grid_needed);
    else
        snprintf(grid, sizeof grid, "grid %d", sc->grid);
    fprintf(stderr,
            "%s: %s: %d x %d pixels, %zu sea and %zu sky; %zu clipmap level%s of facets "
            "%g m x 2^l (%s, tolerance %g, method %s):\n", what,
            scene_path, sc->width, sc->height, sea_pixels, npix - sea_pixels, n,
            n == 1 ? "" : "s", sc->finest, grid, sc->tolerance,
            sea_facet_method_name(sc->method));
    if (fallback > 0)
        fprintf(stderr,
                "  %zu pixel%s read coarser facets than their footprints ask, outside their "
                "level's window: grid = %zu would hold them\n",
                fallback, fallback == 1 ? "" : "s", grid_needed);
    for (size_t i = 0; i < n; ++i) {
        const sea_clip_level *l = &lv[i];
        if (l->low_res)
            fprintf(stderr,
                    "  level %2d: %.10g m, low-resolution (m = 0, C = C_LR, no facets), generated "
                    "share %.3g, %zu pixels\n",
                    l->level, l->facet, l->generated_share, l->pixels);
        else
            fprintf(stderr,
                    "  level %2d: %.10g m, window %zu x %zu facets from (%ld, %ld) = (%g m, %g m), "
                    "generated share %.3g, %zu pixels, sub-facets 2^%d x 2^%d%s\n",
                    l->level, l->facet, l->nx, l->ny, l->i0, l->j0, (double)l->i0 * l->facet,
                    (double)l->j0 * l->facet, l->generated_share, l->pixels, l->sub_n, l->sub_n,
                    l->sub_skipped ? " (skipped)" : "");
    }
    /* Sub-facets: what each level resolves, and which the tolerance skipped. */
    for (size_t i = 0; i < n; ++i) {
        const sea_clip_level *l = &lv[i];
        if (l->low_res || (l->sub_n == 0 && !l->sub_skipped))
            continue;
        const int want = l->sub_skipped ? (sc->n < l->level ? sc->n : l->level) : l->sub_n;
        fprintf(stderr,
                "  level %2d: sub-facets of %g m resolve %.3g of the slope variance: %s\n",
                l->level, l->facet / (double)(1L << want), l->sub_share,
                l->sub_skipped ? "skipped, less than the tolerance (n = 0)"
                               : "computed, at least the tolerance");
    }
    /* The first low-resolution level is the end of every pixel's chain. */
    for (size_t i = 0; i < n; ++i) {
        if (!lv[i].low_res)
            continue;
        if (sc->reference)
            fprintf(stderr,
                    "  levels from %g m are low-resolution: the waves longer than 2 x %g m carry "
                    "%.3g of the slope variance, less than 1e-12 (the reference: every pixel at "
                    "the level it asks for)\n",
                    lv[i].facet, lv[i].facet, lv[i].generated_share);
        else
            fprintf(stderr,
                    "  levels from %g m are low-resolution: the waves longer than 2 x %g m carry "
                    "%.3g of the slope variance, less than a thousandth of the tolerance (%g)\n",
                    lv[i].facet, lv[i].facet, lv[i].generated_share, 1e-3 * sc->tolerance);
        break;
    }
    fprintf(stderr,
            "  a pixel of footprint F reads level round(log2(F / %g m)), or a coarser one outside "
            "that level's window; \"pixels\" counts the pixels whose footprint chose it\n",
            sc->finest);
    /* The fallbacks of seabake(1), LIMITS AND FALLBACKS, that this scene takes. */
    sea_spectrum sp;
    const int sp_ok = sea_scene_spectrum(sc, &sp, NULL) == SEA_OK;
    /* the swells (seabake-model(7), SWELL) and what they add to the slopes */
    for (int i = 0; sp_ok && i < sp.n_swell; i++) {
        const sea_swell *w = &sp.swell[i];
        sea_spectrum one = sp, none = sp;
        one.n_swell = 0;
        none.n_swell = 0;
        one.swell[0] = *w;
        one.n_swell = 1;
        sea_cov2 c1, c0;
        if (sea_spectrum_slope_cov(&one, 0.0, &c1, NULL) != SEA_OK ||
            sea_spectrum_slope_cov(&none, 0.0, &c0, NULL) != SEA_OK)
            continue;
        fprintf(stderr,
                "%s: swell %d: Hs %g m, peak period %g s (peak wavelength %.0f m), toward %g deg, "
                "spread %g deg, gamma %g%s: slope variance %.3g, %.3g %% of the wind sea's "
                "%.3g\n",
                what, i + 1, w->hs, w->tp, 9.81 * w->tp * w->tp / (2.0 * M_PI),
                w->dir * 180.0 / M_PI, w->spread * 180.0 / M_PI, w->gamma,
                sc->swell[i].douglas ? " (Douglas code)" : "",
                (c1.xx + c1.yy) - (c0.xx + c0.yy),
                100.0 * ((c1.xx + c1.yy) - (c0.xx + c0.yy)) / (c0.xx + c0.yy), c0.xx + c0.yy);
    }
    if (sp_ok && sea_spectrum_alpha_m_continued(&sp))
        fprintf(stderr,
                "%s: fallback: at %g m/s u*/c_m is below exp(-0.9): the short-wave "
                "alpha_m = %.3g comes from the positive low-wind continuation, not Elfouhaily's "
                "1e-2 (1 + ln(u*/c_m)) (seabake(1), LIMITS AND FALLBACKS)\n", what,
                sc->wind_speed, sp.alpha_m);
    if (sc->sun_zenith >= M_PI / 2.0)
        fprintf(stderr,
                "%s: fallback: the sun (zenith %g deg) is below the horizon%s: no sun term, "
                "as with irradiance 0\n", what,
                sc->sun_zenith * 180.0 / M_PI,
                sc->earth == SEA_EARTH_SPHERICAL ? " at the nadir point" : "");
    if (sc->windows == SEA_WINDOWS_CLIPMAP)
        fprintf(stderr, "  windows = clipmap: every high-resolution level is %d x %d facets "
                        "around the point the optical axis meets, whether pixels read it or not\n",
                sc->grid > 0 ? sc->grid : 256, sc->grid > 0 ? sc->grid : 256);
    const sea_view_choices ch = sea_view_choices_of(r);
    if (sc->emissivity_method == SEA_EMIS_AUTO)
        fprintf(stderr,
                "%s: emissivity: auto rule, orders x %g (%s): n_gl = ceil(%g (%g + %g s_X)), "
                "n_gh = ceil(%g (%g + %g s + %g s^2))\n", what,
                ch.emis_scale,
                ch.emis_scale < 1.0 ? "scaled down: the tolerance allows an emissivity error "
                                      "of a tenth of it"
                                    : "the full rule, within 1e-6 of the adaptive Eq 7",
                ch.emis_scale, SEA_EMIS_AUTO_GL_A, SEA_EMIS_AUTO_GL_B, ch.emis_scale,
                SEA_EMIS_AUTO_GH_C, SEA_EMIS_AUTO_GH_D, SEA_EMIS_AUTO_GH_E);
    else
        fprintf(stderr, "%s: emissivity: %s (not scaled by the tolerance)\n", what,
                sea_emis_method_name(sc->emissivity_method));
    if (sc->sky_model == SEA_SKY_CLEAR)
        fprintf(stderr,
                "%s: sky: clear, L(theta) = [1 - (1 - %g)^(1/cos theta)] B(%g K), reflected over "
                "each facet's mirror rays (Eq 22)\n",
                what, sc->sky_zenith_emissivity, sc->air_temperature);
    else if (sc->sky_model == SEA_SKY_TABLE)
        fprintf(stderr,
                "%s: sky: the table %s (radiance by zenith angle and wavelength, linear in "
                "both), reflected over each facet's mirror rays (Eq 22)\n",
                what, sc->sky_table_file);
    else
        fprintf(stderr, "%s: sky: isotropic (Eq 23: the sea reflects it in 1 - emissivity)\n",
                what);
    if (sc->atmosphere_table_file[0] != '\0')
        fprintf(stderr,
                "%s: atmosphere: the table %s: a sea pixel at range d is tau(d) L + "
                "path_radiance(d), linear in range and wavelength\n",
                what, sc->atmosphere_table_file);
    else if (!isnan(sc->air_temperature))
        fprintf(stderr,
                "%s: atmosphere: air at %g K, extinction %g/km: a sea pixel at range d is "
                "tau L + (1 - tau) B(T_air), tau = exp(-extinction d)%s\n",
                what, sc->air_temperature, sc->extinction * 1e3,
                sc->extinction > 0.0 ? "" : " (no extinction: tau = 1)");
    if (sc->reference)
        fprintf(stderr,
                "%s: reference: every approximation the tolerance allows replaced by its exact "
                "form (the auto rule at full orders, second hits at converged orders with the "
                "sea around evaluated at every mirror ray, two scales by quadrature at each "
                "pixel's own mean slope and every sample, twice the spectral samples): the "
                "yardstick of the default, seabake(1), REFERENCE\n",
                what);
    if (sc->reflections == 1 && !sc->reference)
        fprintf(stderr,
                "%s: reflections: 1 (the paper: a facet's mirror ray brings the sky; at 80-85 "
                "deg the emissivity is 0.02-0.035 below ray-traced truth, and examples/mast.ini "
                "is up to 12 %% (rms 1.5 %%) off the reference, seabake-model(7))\n",
                what);
    else if (sc->reflections == SEA_REFLECTIONS_AUTO && !sc->reference)
        fprintf(stderr,
                "%s: reflections: auto (a second hit in the sea around wherever it can move a "
                "pixel by more than %g of the tolerance, none where it cannot; the default, "
                "seabake-model(7), MULTIPLE REFLECTIONS)\n",
                what, SEA_AUTO_SKIP);
    else
        fprintf(stderr,
                "%s: reflections: %d (every facet's mirror ray may meet the sea again, in the "
                "sea around; seabake-model(7) gives the accuracy and the cost)\n",
                what, sc->reflections >= 2 ? sc->reflections : 2);
    if (sc->shadowing == SEA_SHADOW_CORRELATED)
        fprintf(stderr,
                "%s: shadowing: correlated (a facet turned toward the sensor is seen more "
                "often than one grazing the ray; single-bounce emissivity within 1.1e-3 of "
                "ray tracing to 85 deg, seabake-model(7), SHADOWING)\n",
                what);
    else
        fprintf(stderr,
                "%s: shadowing: smith (the paper's Eq 9c-9e, independent of the facet's "
                "slope: the emissivity up to 12e-3 low at 75-85 deg, seabake-model(7))\n",
                what);
    if (sc->scales == 2)
        fprintf(stderr,
                "%s: scales: 2 (the slopes of the waves longer than %.3g m, half the slope "
                "variance, count as facets under the level's own: low resolution within "
                "1.5e-3 of ray-traced sea surfaces to 82 deg, seabake-model(7), TWO SCALES)\n",
                what, ch.two_scale_split);
    else
        fprintf(stderr,
                "%s: scales: 1 (one Gaussian surface, the paper: at 80-85 deg low resolution is "
                "8-20e-3 below ray-traced sea surfaces and 1 m facets, seabake-model(7))\n",
                what);
    if (!isnan(sc->polarizer))
        fprintf(stderr,
                "%s: polarizer: %g deg from the image's up axis: the radiance is what a camera "
                "behind it reads, I + Q cos 2a + U sin 2a (Q and U with the model's hits; "
                "seabake-model(7), POLARISATION)\n",
                what, sc->polarizer * 180.0 / M_PI);
    if (ch.wave_count == 0)
        fprintf(stderr, "%s: waves: none (every level is low-resolution)\n", what);
    else if (ch.directions > 0)
        fprintf(stderr,
                "%s: waves: %zu sinusoids, %d bins per octave x %d directions (the same "
                "at every tolerance)\n",
                what, ch.wave_count, ch.bins_per_octave, ch.directions);
    else
        fprintf(stderr, "%s: waves: %zu FFT modes (the same at every tolerance)\n", what,
                ch.wave_count);
    const double *wl, *wt;
    const size_t k = sea_view_samples(r, &wl, &wt);
    if (sc->wavelength > 0.0) {
        fprintf(stderr, "%s: 1 spectral sample, at %g um\n", what, wl[0] * 1e6);
        return;
    }
    fprintf(stderr, "%s: %zu spectral sample%s over %g-%g um (%s, %s response):", what, k,
            k == 1 ? "" : "s", sc->band_min * 1e6, sc->band_max * 1e6,
            sc->band_samples > 0 ? "samples in the scene" : "chosen by the tolerance",
            sc->response_file[0] ? "the file's" : "flat");
    for (size_t i = 0; i < k && i < EXPLAIN_SAMPLES; ++i)
        fprintf(stderr, "%s%.4g", i ? ", " : " ", wl[i] * 1e6);
    fprintf(stderr, "%s um\n", k > EXPLAIN_SAMPLES ? ", ..." : "");
}
