/* render_previews.c - the previews of seabake render (render.h): the tone
 * curves of the grey previews, fixed by the first frame (--png-tone,
 * --png-range), the level preview's colours, and each frame's PNG files. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "preview.h"
#include "render.h"

/* -------------------------------------------------------------- previews */


/* The colour of facet size f (m) in the level preview, in [0, 1]: hue =
 * the fractional part of 0.618034 log2(f / 1 m) turns (the golden ratio:
 * successive sizes far apart on the colour wheel; 1 m red), saturation
 * 0.85, value 1; a low-resolution level in stripes of that colour and
 * grey 0.4 (low_res; x + y picks the stripe); the sky (0) black. */
static void level_colour(double f, bool low_res, int x, int y, float rgb[3])
{
    if (!(f > 0.0)) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        return;
    }
    if (low_res && ((x + y) / 4) % 2 == 1) {
        rgb[0] = rgb[1] = rgb[2] = 0.4f;
        return;
    }
    const double turns = 0.6180339887498949 * log2(f);
    const double h = 6.0 * (turns - floor(turns)), s = 0.85, v = 1.0;
    const int i = (int)h % 6;
    const double fr = h - floor(h), p = v * (1 - s), q = v * (1 - s * fr);
    const double t = v * (1 - s * (1 - fr));
    const double c[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)c[i][k];
}

/* The tone curve of one grey AOV (or the main preview: AOV_TEMPERATURE)
 * from the first frame: temperature over every pixel (or --png-range),
 * emissivity and reflectivity over the sea pixels (the sky has 0). */
static sea_status preview_tone(const sea_cli_render *s, const sea_image *img, int k,
                               render_previews *pv, sea_error *err)
{
    const size_t npix = (size_t)img->width * (size_t)img->height;
    sea_png_tone *t = &pv->tone[k];
    const bool kelvin = k == AOV_TEMPERATURE;
    bool from_sea = false; /* the sea's curve (sea_png_tone_sea) was made */
    if (kelvin && s->png_range) {
        sea_png_tone_linear(s->png_lo, s->png_hi, t, NULL);
    } else if (kelvin) {
        from_sea = s->png_tone == RENDER_TONE_SEA ||
                  (s->png_tone == RENDER_TONE_AUTO &&
                   sea_png_sky_apart(img->temperature, img->level, npix));
        if (from_sea) {
            /* no sea pixel, or no memory: the scene's curve after all */
            const size_t used = sea_png_tone_sea(img->temperature, img->level, npix, t);
            from_sea = used != 0 && used != (size_t)-1;
        } else
            sea_png_tone_auto(img->temperature, npix, t);
    } else {
        const float *plane = k == AOV_EMISSIVITY ? img->emissivity : img->reflectivity;
        float *sea = malloc((npix > 0 ? npix : 1) * sizeof *sea);
        if (sea == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        size_t m = 0;
        for (size_t q = 0; q < npix; q++)
            if (img->level[q] > 0.0f)
                sea[m++] = plane[q];
        sea_png_tone_auto(sea, m, t);
        free(sea);
    }
    const char *unit = kelvin ? " K" : "";
    if (t->knee < t->hi)
        snprintf(pv->text[k], sizeof pv->text[k],
                 "%s: linear %.6g%s black, %.6g%s %.0f %% grey; linear to %.6g%s white",
                 RENDER_AOVS[k].quantity, t->lo, unit, t->knee, unit, 100.0 * SEA_PNG_KNEE_GREY,
                 t->hi, unit);
    else
        snprintf(pv->text[k], sizeof pv->text[k], "%s: linear %.6g%s black to %.6g%s white%s",
                 RENDER_AOVS[k].quantity, t->lo, unit, t->hi, unit,
                 from_sea ? " (the sea's 0.5-99.5 % quantiles; sky clamped)" : "");
    snprintf(pv->range[k], sizeof pv->range[k], "%.6g:%.6g", t->lo, t->hi);
    return SEA_OK;
}

sea_status render_previews_setup(const sea_cli_render *s, const sea_image *img,
                                render_previews *pv, sea_error *err)
{
    sea_status st = SEA_OK;
    for (int k = AOV_EMISSIVITY; k < AOV_COUNT && st == SEA_OK; k++)
        if (k == AOV_TEMPERATURE || s->aov[k])
            st = preview_tone(s, img, k, pv, err);
    size_t used = 0;
    pv->palette[0] = '\0';
    for (size_t l = 0; l < pv->n_levels && used < sizeof pv->palette; l++) {
        float c[3];
        level_colour(pv->levels[l].facet, false, 0, 0, c);
        int w = snprintf(pv->palette + used, sizeof pv->palette - used, "%s%.10g m%s #%02x%02x%02x",
                         l ? ", " : "", pv->levels[l].facet, pv->levels[l].low_res ? " (LR)" : "",
                         (unsigned)lround(255 * c[0]), (unsigned)lround(255 * c[1]),
                         (unsigned)lround(255 * c[2]));
        if (w < 0)
            break;
        used += (size_t)w;
    }
    pv->ready = st == SEA_OK;
    return st;
}

sea_status render_write_preview(const sea_cli_render *s, const sea_image *img, int k,
                                const render_previews *pv, const char *path, sea_error *err)
{
    const int w = img->width, h = img->height;
    if (k == AOV_LEVEL) {
        const size_t npix = (size_t)w * (size_t)h;
        float *rgb = malloc(3 * npix * sizeof *rgb);
        if (rgb == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                const size_t q = (size_t)y * (size_t)w + (size_t)x;
                const double f = img->level[q];
                bool lr = false;
                for (size_t l = 0; l < pv->n_levels; l++)
                    if (fabs(pv->levels[l].facet - f) <= 1e-6 * f)
                        lr = pv->levels[l].low_res != 0;
                level_colour(f, lr, x, y, rgb + 3 * q);
            }
        const sea_png_text text[] = {{"seabake:quantity", RENDER_AOVS[k].quantity},
                                     {"seabake:palette", pv->palette}};
        sea_status st = sea_png_write_rgb(path, w, h, rgb, s->png_depth, text, 2, err);
        free(rgb);
        return st;
    }
    const int t = k < 0 ? AOV_TEMPERATURE : k;
    const float *plane = t == AOV_EMISSIVITY     ? img->emissivity
                         : t == AOV_REFLECTIVITY ? img->reflectivity
                                                 : img->temperature;
    const sea_png_text text[] = {{"seabake:quantity", RENDER_AOVS[t].quantity},
                                 {t == AOV_TEMPERATURE ? "seabake:range_K" : "seabake:range",
                                  pv->range[t]},
                                 {"seabake:tone", pv->text[t]}};
    return sea_png_write_toned(path, w, h, plane, &pv->tone[t], s->png_depth, text, 3, err);
}

