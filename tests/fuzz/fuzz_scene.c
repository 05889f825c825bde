/* fuzz_scene.c - libFuzzer target: the scene loader (sea_scene_load_with)
 * on arbitrary INI text, then, for a scene it accepts, a shrunk render and
 * bake of one frame.
 *
 * Input: the scene file up to the first NUL byte, then up to four
 * NUL-separated overrides "section.key=value" (as seabake's --set; their
 * paths are relative to the working directory).  The scene's directory holds a valid water table "w.csv" and response
 * curve "r.csv", so that `water = w.csv` and `response = r.csv` load.
 *
 * Each execution must take milliseconds, so an accepted scene is shrunk
 * before sea_view_alloc: at most 8 x 6 pixels (2 x 2 with the adaptive
 * emissivity), grid 16, sub-facet exponent <= 3, at most 2 band samples,
 * a tolerance of at least 1e-3, one scale (two build a table of what they
 * add per spectral sample, or integrate it per texel: seconds under the
 * sanitizers; tests/test_optics.c and test_mc.c cover them), and for one-meter a
 * finest size whose FFT patch stays small.  Everything else (geometry, sea
 * state, sun, sky, water, band, response, earth, windows, time) is rendered
 * as loaded.  The API's promises are checked: emissivity in [0, 1], finite radiance and
 * temperature, levels finest first. */
#include <math.h>

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char WATER[] = "wavelength_um,n,k\n2,1.30,0.01\n8,1.25,0.03\n16,1.20,0.40\n";
static const char RESPONSE[] = "wavelength_um,response\n3,0\n4,1\n5,0.5\n11,0\n";

/* Shares of the low-resolution slope variance as render.c computes them:
 * the first level whose longer waves carry less than the tolerance. */
static int first_lr_level(const sea_scene *sc, double finest)
{
    sea_spectrum s;
    sea_cov2 lr, c;
    if (sea_scene_spectrum(sc, &s, NULL) != SEA_OK ||
        sea_spectrum_slope_cov(&s, 0.0, &lr, NULL) != SEA_OK)
        return 0;
    for (int l = 0; l < SEA_CLIP_MAX_LEVELS; l++) {
        if (sea_spectrum_slope_cov(&s, M_PI / (finest * exp2(l)), &c, NULL) != SEA_OK)
            return l;
        if (1.0 - (c.xx + c.yy) / (lr.xx + lr.yy) < sc->tolerance)
            return l;
    }
    return SEA_CLIP_MAX_LEVELS;
}

static void shrink(sea_scene *sc)
{
    const int full = sc->emissivity_method == SEA_EMIS_FULL;
    const int wmax = full ? 2 : 8, hmax = full ? 2 : 6;
    if (sc->width > wmax)
        sc->width = wmax;
    if (sc->height > hmax)
        sc->height = hmax;
    sc->grid = 16;
    if (sc->n > 3)
        sc->n = 3;
    /* below 2e-4 every pixel takes the second hits at full orders and two
     * scales by quadrature: seconds a pixel under the sanitizers (the unit
     * and shell tests render those tolerances) */
    if (sc->tolerance < 1e-3)
        sc->tolerance = 1e-3;
    sc->scales = 1;
    /* each spectral sample has its own two-scale table to build */
    if (sc->band_samples > 2)
        sc->band_samples = 2;
    if (sc->wavelength <= 0.0 && sc->band_samples == 0)
        sc->band_samples = 2;
    /* The finest levels are the costly ones: sums of sinusoids up to
     * pi/finest rad/m, or an FFT patch of 16 << level cells per side. */
    if (sc->finest < 0.05)
        sc->finest = 0.05;
    if (sc->method == SEA_METHOD_ONE_METER)
        while (sc->finest < 1000.0 && (16L << first_lr_level(sc, sc->finest)) > 512)
            sc->finest = fmin(2.0 * sc->finest, 1000.0);
}

static void check_image(const sea_image *img)
{
    const size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++) {
        FUZZ_ASSERT(isfinite(img->radiance[i]));
        FUZZ_ASSERT(isfinite(img->temperature[i]) || img->radiance[i] <= 0.0f);
        FUZZ_ASSERT(img->emissivity[i] >= 0.0f && img->emissivity[i] <= 1.0f);
        FUZZ_ASSERT(img->reflectivity[i] >= 0.0f && isfinite(img->reflectivity[i]));
        FUZZ_ASSERT(img->level[i] >= 0.0f && isfinite(img->level[i]));
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int ready;
    char path[128], aux[128];
    if (!ready) {
        fuzz_write("w.csv", (const uint8_t *)WATER, sizeof WATER - 1, aux, sizeof aux);
        fuzz_write("r.csv", (const uint8_t *)RESPONSE, sizeof RESPONSE - 1, aux, sizeof aux);
        ready = 1;
    }
    /* A copy with a terminating NUL, so that the overrides are strings. */
    char *buf = malloc(size + 1);
    if (!buf)
        return 0;
    memcpy(buf, data, size);
    buf[size] = '\0';
    size_t scene_len = strlen(buf);
    const char *overrides[4];
    size_t n_over = 0;
    for (size_t at = scene_len + 1; at < size && n_over < 4; at += strlen(buf + at) + 1)
        overrides[n_over++] = buf + at;
    fuzz_write("scene.ini", (const uint8_t *)buf, scene_len, path, sizeof path);

    sea_scene sc;
    sea_error err = {{0}};
    sea_status st = sea_scene_load_with(path, overrides, n_over, &sc, &err);
    fuzz_check_error(st, &err);
    free(buf);
    if (st != SEA_OK)
        return 0;
    shrink(&sc);

    sea_view *r = NULL;
    st = sea_view_alloc(&sc, &r, &err);
    fuzz_check_error(st, &err);
    if (st != SEA_OK) {
        FUZZ_ASSERT(r == NULL);
        return 0;
    }
    const sea_clip_level *lv;
    size_t nl = sea_view_levels(r, &lv);
    FUZZ_ASSERT(nl >= 1 && nl <= SEA_CLIP_MAX_LEVELS);
    for (size_t l = 1; l < nl; l++)
        FUZZ_ASSERT(lv[l].level > lv[l - 1].level);

    sea_image img;
    st = sea_image_alloc(sc.width, sc.height, &img, &err);
    FUZZ_ASSERT(st == SEA_OK);
    st = sea_view_render_frame(r, sc.time, &img, NULL, NULL, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK)
        check_image(&img);
    sea_image_free(&img);

    /* The bake of the same frame: every level's maps (16 x 16 texels at
     * most here), view maps of one texel per facet. */
    sea_bake b;
    st = sea_bake_frame(r, sc.time, 1, &b, NULL, NULL, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK) {
        FUZZ_ASSERT(b.n_levels == nl);
        for (size_t l = 0; l < b.n_levels; l++) {
            const sea_bake_level *bl = &b.levels[l];
            FUZZ_ASSERT(bl->lr_optics.emissivity >= 0.0 && bl->lr_optics.emissivity <= 1.0);
            if (bl->optics)
                for (size_t i = 0; i < bl->level.nx * bl->level.ny; i++) {
                    FUZZ_ASSERT(bl->optics[i].emissivity >= 0.0 &&
                                bl->optics[i].emissivity <= 1.0);
                    FUZZ_ASSERT(isfinite(bl->optics[i].radiance));
                }
        }
        sea_bake_free(&b);
    }
    sea_view_free(r);
    return 0;
}
