/* manifest.c - a bake directory's manifest.json (bakedir.h), through cJSON:
 * the format and its version, the scene that was baked (the keys of the
 * models in use only), the sensor's camera, the frames, every level
 * (facet size, origin, extent, texels, channels and units; a
 * low-resolution level's constants), the horizon mesh and the sensor's
 * image of the exports, what the Blender import needs, and "files": every
 * file of the directory, which is what lets a later bake replace it
 * (atomicdir.c). */
#include "config.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bakedir_internal.h"
#include "blender.h"

static const int BAKE_MANIFEST_VERSION = 1;

#define BAKE_GROUPS SEA_BAKE_GROUPS
#define BAKE_Q SEA_BAKE_Q

double sea_manifest_sky_radiance(const sea_view *r)
{
    const sea_scene *sc = sea_view_scene(r);
    const double *wl, *wt;
    const size_t n = sea_view_samples(r, &wl, &wt);
    double L = 0.0;
    for (size_t i = 0; i < n; i++)
        L += wt[i] * (sc->sky_radiance >= 0.0 ? sc->sky_radiance
                                              : sea_planck_radiance(wl[i], sc->sky_temperature));
    return sc->wavelength > 0.0 ? 1e-6 * L : L;
}

static cJSON *number_or_null(double v)
{
    return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

static cJSON *vec(const double *v, size_t n)
{
    return cJSON_CreateDoubleArray(v, (int)n);
}

static double deg(double rad)
{
    return rad * 180.0 / M_PI;
}

/* [sea] and its [swell] sections. */
static void sea_json(cJSON *o, const sea_scene *sc)
{
    static const char *const tables[] = {"hale-querry", "segelstein"};
    cJSON *sea = cJSON_AddObjectToObject(o, "sea");
    cJSON_AddNumberToObject(sea, "wind_speed_m_s", sc->wind_speed);
    cJSON_AddNumberToObject(sea, "wind_direction_deg", deg(sc->wind_dir));
    cJSON_AddItemToObject(sea, "fetch_m", number_or_null(sc->fetch)); /* null: infinite */
    cJSON_AddNumberToObject(sea, "temperature_K", sc->temperature);
    cJSON_AddNumberToObject(sea, "salinity_g_kg", sc->salinity);
    cJSON_AddStringToObject(sea, "water", sc->water_file[0] ? sc->water_file
                                          : sc->water_table >= 0 && sc->water_table < 2
                                              ? tables[sc->water_table]
                                              : "?");
    cJSON_AddNumberToObject(sea, "seed", (double)sc->seed);
    cJSON_AddNumberToObject(sea, "time_s", sc->time);
    cJSON_AddNumberToObject(sea, "loop_period_s", sc->loop_period);
    if (sc->n_swell > 0) { /* (absent without: a bake of no swell is as before) */
        cJSON *swells = cJSON_AddArrayToObject(o, "swell");
        for (int i = 0; i < sc->n_swell; i++) {
            const sea_swell *w = &sc->swell[i].sw;
            cJSON *one = cJSON_CreateObject();
            cJSON_AddNumberToObject(one, "height_m", w->hs);
            cJSON_AddNumberToObject(one, "period_s", w->tp);
            cJSON_AddNumberToObject(one, "direction_deg", deg(w->dir));
            cJSON_AddNumberToObject(one, "spread_deg", deg(w->spread));
            cJSON_AddNumberToObject(one, "gamma", w->gamma);
            cJSON_AddItemToObject(one, "douglas", sc->swell[i].douglas
                                                      ? cJSON_CreateNumber(sc->swell[i].douglas)
                                                      : cJSON_CreateNull());
            cJSON_AddItemToArray(swells, one);
        }
    }
}

static void sun_json(cJSON *o, const sea_scene *sc)
{
    cJSON *sun = cJSON_AddObjectToObject(o, "sun");
    cJSON_AddNumberToObject(sun, "zenith_deg", deg(sc->sun_zenith));
    cJSON_AddNumberToObject(sun, "azimuth_deg", deg(sc->sun_azimuth));
    cJSON_AddItemToObject(sun, "irradiance_W_m2_um",
                          sc->sun_irradiance >= 0.0 ? cJSON_CreateNumber(sc->sun_irradiance * 1e-6)
                                                    : cJSON_CreateNull());
    cJSON_AddNumberToObject(sun, "temperature_K", sc->sun_temperature);
    cJSON_AddNumberToObject(sun, "solid_angle_sr", sc->sun_solid_angle);
    cJSON_AddNumberToObject(sun, "transmittance", sc->sun_transmittance);
}

static void sky_json(cJSON *o, const sea_scene *sc)
{
    /* The sky and the air that were used: an isotropic sky's radiance (null:
     * from its temperature), a clear sky's zenith emissivity, a table's
     * file; the keys of a model that was not used are left out, so that
     * no default reads as part of the scene. */
    cJSON *sky = cJSON_AddObjectToObject(o, "sky");
    cJSON_AddStringToObject(sky, "model", sc->sky_model == SEA_SKY_CLEAR   ? "clear"
                                          : sc->sky_model == SEA_SKY_TABLE ? "table"
                                                                           : "isotropic");
    if (sc->sky_model == SEA_SKY_ISOTROPIC) {
        cJSON_AddItemToObject(sky, "radiance_W_m2_sr_um",
                              sc->sky_radiance >= 0.0
                                  ? cJSON_CreateNumber(sc->sky_radiance * 1e-6)
                                  : cJSON_CreateNull());
        cJSON_AddNumberToObject(sky, "temperature_K", sc->sky_temperature);
    } else if (sc->sky_model == SEA_SKY_CLEAR) {
        cJSON_AddNumberToObject(sky, "zenith_emissivity", sc->sky_zenith_emissivity);
    } else {
        cJSON_AddStringToObject(sky, "table", sc->sky_table_file);
    }
    /* null: no [atmosphere] (the paper's vacuum) */
    if (isnan(sc->air_temperature) && sc->atmosphere_table_file[0] == '\0') {
        cJSON_AddNullToObject(o, "atmosphere");
    } else {
        cJSON *air = cJSON_AddObjectToObject(o, "atmosphere");
        cJSON_AddItemToObject(air, "air_temperature_K", number_or_null(sc->air_temperature));
        if (sc->atmosphere_table_file[0] != '\0')
            cJSON_AddStringToObject(air, "table", sc->atmosphere_table_file);
        else
            cJSON_AddNumberToObject(air, "extinction_per_km", sc->extinction * 1e3);
    }
}

/* The camera's keys (absent without: a bake of no camera is as before).
 * Recorded, not applied: the maps and exports are the ideal radiance's
 * (seabake(1), bake). */
static void camera_keys_json(cJSON *sen, const sea_scene *sc)
{
    sea_imager_params p;
    if (!sea_imager_params_from_scene(sc, &p))
        return;
    static const char *const optics[] = {"none", "gaussian", "diffraction", "table"};
    cJSON *c = cJSON_AddObjectToObject(sen, "camera");
    cJSON_AddBoolToObject(c, "applied", 0);
    cJSON_AddStringToObject(c, "optics", optics[p.psf]);
    if (p.psf == SEA_PSF_GAUSSIAN)
        cJSON_AddNumberToObject(c, "psf_sigma_px", p.psf_sigma);
    if (p.psf == SEA_PSF_DIFFRACTION) {
        cJSON_AddNumberToObject(c, "f_number", p.f_number);
        cJSON_AddNumberToObject(c, "pitch_um", p.pitch * 1e6);
    }
    if (p.psf == SEA_PSF_TABLE)
        cJSON_AddStringToObject(c, "mtf", sc->mtf_file);
    cJSON_AddNumberToObject(c, "fill_factor", p.fill_factor);
    cJSON_AddNumberToObject(c, "netd_K", p.netd);
    cJSON_AddNumberToObject(c, "netd_temperature_K", p.netd_temperature);
    cJSON_AddNumberToObject(c, "noise_seed", (double)p.noise_seed);
    cJSON_AddNumberToObject(c, "fpn_gain", p.fpn_gain);
    cJSON_AddNumberToObject(c, "fpn_offset_K", p.fpn_offset);
    cJSON_AddNumberToObject(c, "fpn_seed", (double)p.fpn_seed);
    if (p.gain > 0.0) {
        cJSON_AddNumberToObject(c, "gain", p.gain);
        cJSON_AddNumberToObject(c, "offset", p.offset);
        cJSON_AddNumberToObject(c, "bit_depth", p.bit_depth);
    } else {
        cJSON_AddNullToObject(c, "gain");
    }
}

static void sensor_json(cJSON *o, const sea_scene *sc)
{
    cJSON *sen = cJSON_AddObjectToObject(o, "sensor");
    cJSON_AddNumberToObject(sen, "x_m", sc->sensor_x);
    cJSON_AddNumberToObject(sen, "y_m", sc->sensor_y);
    cJSON_AddNumberToObject(sen, "altitude_m", sc->altitude);
    cJSON_AddNumberToObject(sen, "look_zenith_deg", deg(sc->look_zenith));
    cJSON_AddNumberToObject(sen, "look_azimuth_deg", deg(sc->look_azimuth));
    cJSON_AddNumberToObject(sen, "roll_deg", deg(sc->roll));
    cJSON_AddNumberToObject(sen, "hfov_deg", deg(sc->hfov));
    cJSON_AddNumberToObject(sen, "width", sc->width);
    cJSON_AddNumberToObject(sen, "height", sc->height);
    if (sc->wavelength > 0.0) {
        cJSON_AddNumberToObject(sen, "wavelength_um", sc->wavelength * 1e6);
        cJSON_AddNullToObject(sen, "band_um");
    } else {
        cJSON_AddNullToObject(sen, "wavelength_um");
        const double band[2] = {sc->band_min * 1e6, sc->band_max * 1e6};
        cJSON_AddItemToObject(sen, "band_um", vec(band, 2));
    }
    cJSON_AddStringToObject(sen, "response", sc->response_file);
    cJSON_AddNumberToObject(sen, "samples", sc->band_samples);
    camera_keys_json(sen, sc);
}

static void model_json(cJSON *o, const sea_scene *sc)
{
    cJSON *mod = cJSON_AddObjectToObject(o, "model");
    cJSON_AddStringToObject(mod, "method", sea_facet_method_name(sc->method));
    cJSON_AddNumberToObject(mod, "n", sc->n);
    cJSON_AddNumberToObject(mod, "finest_m", sc->finest);
    if (sc->grid == SEA_GRID_AUTO)
        cJSON_AddStringToObject(mod, "grid", "auto");
    else
        cJSON_AddNumberToObject(mod, "grid", sc->grid);
    cJSON_AddStringToObject(mod, "emissivity",
                            sea_emis_method_name(sc->emissivity_method));
    cJSON_AddStringToObject(mod, "earth", sc->earth == SEA_EARTH_FLAT ? "flat" : "spherical");
    cJSON_AddStringToObject(mod, "windows",
                            sc->windows == SEA_WINDOWS_CLIPMAP ? "clipmap" : "view");
    cJSON_AddNumberToObject(mod, "tolerance", sc->tolerance);
    if (sc->reflections == SEA_REFLECTIONS_AUTO)
        cJSON_AddStringToObject(mod, "reflections", "auto");
    else
        cJSON_AddNumberToObject(mod, "reflections", sc->reflections);
    cJSON_AddBoolToObject(mod, "reference", sc->reference != 0);
    cJSON_AddStringToObject(mod, "shadowing", sea_shadowing_name(sc->shadowing));
    cJSON_AddNumberToObject(mod, "scales", sc->scales);
}

static cJSON *scene_json(const sea_scene *sc)
{
    cJSON *o = cJSON_CreateObject();
    sea_json(o, sc);
    sun_json(o, sc);
    sky_json(o, sc);
    sensor_json(o, sc);
    model_json(o, sc);
    return o;
}

static cJSON *camera_json(const sea_camera *c, double hfov)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddItemToObject(o, "position_m", vec(c->pos, 3));
    cJSON_AddItemToObject(o, "forward", vec(c->fwd, 3));
    cJSON_AddItemToObject(o, "right", vec(c->right, 3));
    cJSON_AddItemToObject(o, "up", vec(c->up, 3));
    cJSON_AddNumberToObject(o, "focal_px", c->focal);
    cJSON_AddNumberToObject(o, "width", c->width);
    cJSON_AddNumberToObject(o, "height", c->height);
    cJSON_AddNumberToObject(o, "hfov_deg", deg(hfov));
    cJSON_AddStringToObject(o, "earth", c->earth == SEA_EARTH_FLAT ? "flat" : "spherical");
    cJSON_AddStringToObject(o, "frame", "world x east, y north, z up, m; image u right, v down");
    return o;
}

static cJSON *moments_json(const sea_moments *m)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "mx", m->mx);
    cJSON_AddNumberToObject(o, "my", m->my);
    cJSON_AddNumberToObject(o, "mxx", m->mxx);
    cJSON_AddNumberToObject(o, "myy", m->myy);
    cJSON_AddNumberToObject(o, "mxy", m->mxy);
    cJSON_AddNumberToObject(o, "h", m->h);
    return o;
}

static cJSON *rect_json(const sea_clip_level *lv)
{
    cJSON *o = cJSON_CreateObject();
    const double origin[2] = {(double)lv->i0 * lv->facet, (double)lv->j0 * lv->facet};
    const double extent[2] = {(double)lv->nx * lv->facet, (double)lv->ny * lv->facet};
    cJSON_AddItemToObject(o, "origin_m", vec(origin, 2));
    cJSON_AddItemToObject(o, "extent_m", vec(extent, 2));
    return o;
}

/* The levels array: geometry from the first frame's bake; high-resolution
 * levels get a "frames" array that sea_manifest_frame fills. */
static cJSON *levels_json(const sea_scene *sc, const sea_bake *b)
{
    cJSON *arr = cJSON_CreateArray();
    for (size_t l = 0; l < b->n_levels; l++) {
        const sea_bake_level *bl = &b->levels[l];
        const sea_clip_level *lv = &bl->level;
        cJSON *o = cJSON_CreateObject();
        cJSON_AddItemToArray(arr, o);
        cJSON_AddNumberToObject(o, "index", lv->level);
        cJSON_AddNumberToObject(o, "facet_m", lv->facet);
        cJSON_AddBoolToObject(o, "low_res", lv->low_res);
        cJSON_AddNumberToObject(o, "generated_share", lv->generated_share);
        cJSON_AddNumberToObject(o, "sub_n", lv->sub_n);
        /* the hole: the next finer high-resolution level's rectangle */
        if (l > 0 && !b->levels[l - 1].level.low_res)
            cJSON_AddItemToObject(o, "hole", rect_json(&b->levels[l - 1].level));
        else
            cJSON_AddNullToObject(o, "hole");
        if (lv->low_res) {
            cJSON_AddItemToObject(o, "moments", moments_json(&bl->lr_moments));
            cJSON *op = cJSON_AddObjectToObject(o, "optics");
            cJSON_AddNumberToObject(op, "emissivity", bl->lr_optics.emissivity);
            cJSON_AddNumberToObject(op, "reflectivity", bl->lr_optics.reflectivity);
            cJSON_AddNumberToObject(op, "radiance", bl->lr_optics.radiance);
            cJSON_AddNumberToObject(op, "temperature", bl->lr_optics.temperature);
            cJSON_AddNumberToObject(op, "obs_theta_deg", deg(bl->lr_obs.theta));
            cJSON_AddNumberToObject(op, "obs_phi_deg", deg(bl->lr_obs.phi));
            cJSON_AddNumberToObject(op, "sun_theta_deg", deg(bl->lr_sun.theta));
            cJSON_AddNumberToObject(op, "sun_phi_deg", deg(bl->lr_sun.phi));
            cJSON_AddStringToObject(op, "toward", "the image centre");
            continue;
        }
        const double origin[2] = {(double)lv->i0 * lv->facet, (double)lv->j0 * lv->facet};
        const double extent[2] = {(double)lv->nx * lv->facet, (double)lv->ny * lv->facet};
        const double texels[2] = {(double)lv->nx, (double)lv->ny};
        const double first[2] = {(double)lv->i0, (double)lv->j0};
        cJSON_AddItemToObject(o, "origin_m", vec(origin, 2));
        cJSON_AddItemToObject(o, "extent_m", vec(extent, 2));
        cJSON_AddItemToObject(o, "texels", vec(texels, 2));
        const double etex[2] = {texels[0] * (double)bl->view_k, texels[1] * (double)bl->view_k};
        cJSON_AddItemToObject(o, "emission_texels", vec(etex, 2));
        cJSON_AddItemToObject(o, "first_facet", vec(first, 2));
        cJSON *maps = cJSON_AddObjectToObject(o, "maps");
        for (size_t g = 0; g < BAKE_N_GROUPS; g++) {
            cJSON *chs = cJSON_AddArrayToObject(maps, BAKE_GROUPS[g].name);
            for (size_t c = 0; c < BAKE_GROUPS[g].n; c++) {
                const bake_quantity k = BAKE_GROUPS[g].q[c];
                cJSON *ch = cJSON_CreateObject();
                cJSON_AddStringToObject(ch, "channel", sea_bakemaps_channel(g, c));
                cJSON_AddStringToObject(ch, "quantity", BAKE_Q[k].name);
                cJSON_AddStringToObject(ch, "unit", sea_bakemaps_unit(sc, k));
                cJSON_AddStringToObject(ch, "meaning", BAKE_Q[k].meaning);
                cJSON_AddItemToArray(chs, ch);
            }
        }
        cJSON_AddArrayToObject(o, "frames");
    }
    return arr;
}

/* What the Blender import needs: the script and the values it needs that
 * the rest of the manifest does not give directly. */
static cJSON *blender_json(const sea_bake_writer *w)
{
    const sea_view *r = w->r;
    const double scale = w->scale;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "script", SEA_BLENDER_SCRIPT);
    cJSON_AddStringToObject(o, "command",
                            "blender -b --factory-startup --python " SEA_BLENDER_SCRIPT
                            " -- manifest.json [--frame F] [--material emission|visible] "
                            "[--save FILE.blend] [--render OUT.exr] "
                            "[--render-frames OUT_####.exr]");
    cJSON *written = cJSON_AddArrayToObject(o, "written");
    cJSON_AddItemToArray(written, cJSON_CreateString(SEA_BLENDER_SCRIPT));
    /* As the POV-Ray scene's sky: band-weighted, in the maps' units; a
     * directional sky by direction (sky_table), its horizon's value here. */
    if (w->sky.n > 0) {
        cJSON_AddNumberToObject(o, "sky_radiance", w->sky.value[0] / scale);
        cJSON_AddNumberToObject(o, "sky_emission", w->sky.value[0]);
        cJSON *t = cJSON_AddObjectToObject(o, "sky_table");
        cJSON_AddStringToObject(t, "coordinate",
                                "s = sqrt(max(cos zenith, 0)) of the ray's direction (world z "
                                "up): the sky's radiance x emission_scale toward it is "
                                "emission, linear in s between the nodes (the horizon's at and "
                                "below it), as seabake render gives a sky pixel");
        cJSON_AddItemToObject(t, "s", vec(w->sky.s, w->sky.n));
        cJSON_AddItemToObject(t, "emission", vec(w->sky.value, w->sky.n));
        cJSON_AddNumberToObject(t, "max_relative_error", w->sky.max_err);
    } else {
        cJSON_AddNumberToObject(o, "sky_radiance", sea_manifest_sky_radiance(r));
        cJSON_AddNumberToObject(o, "sky_emission", sea_manifest_sky_radiance(r) * scale);
    }
    /* The normal maps need no Blender-specific copy: (n + 1) / 2 with +x
     * east and +y north is the Normal Map node's tangent space for UVs
     * that run east and north, as the import's do. */
    cJSON_AddStringToObject(o, "normal_map", "normal");
    cJSON_AddStringToObject(o, "normal_map_encoding",
                            "tangent space of the UV map (u east, v north): colour = 0.5 + 0.5 n, "
                            "Non-Color, as Blender's Normal Map node reads it");
    return o;
}

/* The horizon mesh for the Blender import: its nodes and map. */
static cJSON *horizon_json(const sea_bake_horizon *hz, const sea_camera *cam)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "exr", SEA_BAKE_HORIZON_MAP);
    cJSON_AddStringToObject(o, "grid",
                            "node (i, j) at map point nadir + arc_m[i] (cos, sin)(azimuth_deg[j]) "
                            "(spherical: azimuthal equidistant, on the sphere); map texel (j, "
                            "row n_arc - 1 - i) holds the radiance the sensor receives from it "
                            "(across the air along the range: tau L + path with [atmosphere]) "
                            "x emission_scale");
    const double nadir[2] = {hz->x0, hz->y0};
    cJSON_AddItemToObject(o, "nadir_m", vec(nadir, 2));
    cJSON_AddStringToObject(o, "earth", cam->earth == SEA_EARTH_FLAT ? "flat" : "spherical");
    cJSON_AddNumberToObject(o, "earth_radius_m", SEA_EARTH_RADIUS);
    cJSON_AddItemToObject(o, "arc_m", vec(hz->arc, hz->n_arc));
    double *deg_az = malloc(hz->n_az * sizeof *deg_az);
    if (deg_az != NULL) {
        for (size_t j = 0; j < hz->n_az; j++)
            deg_az[j] = deg(hz->az[j]);
        cJSON_AddItemToObject(o, "azimuth_deg", vec(deg_az, hz->n_az));
        free(deg_az);
    }
    cJSON_AddBoolToObject(o, "full_turn", hz->full_turn);
    cJSON_AddNumberToObject(o, "max_error", hz->max_err);
    return o;
}

cJSON *sea_manifest_alloc(const sea_bake_writer *w, const sea_bake *b)
{
    const sea_scene *sc = w->sc;
    const sea_camera *cam = sea_view_camera(w->r);
    const sea_bake_options *o = &w->o;
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "format", "seabake-bake");
    cJSON_AddNumberToObject(m, "version", BAKE_MANIFEST_VERSION);
    cJSON_AddStringToObject(m, "generator", PACKAGE_STRING);
    if (o->scene_file != NULL)
        cJSON_AddStringToObject(m, "scene_file", o->scene_file);
    else
        cJSON_AddNullToObject(m, "scene_file");
    cJSON_AddItemToObject(m, "scene", scene_json(sc));
    cJSON_AddItemToObject(m, "camera", camera_json(cam, sc->hfov));
    cJSON_AddNumberToObject(m, "seed", (double)sc->seed);
    cJSON_AddNumberToObject(m, "time_s", sc->time);
    cJSON_AddBoolToObject(m, "framed", o->framed != 0);
    cJSON_AddNumberToObject(m, "frame_rate_hz", o->frame_rate);
    cJSON_AddArrayToObject(m, "frames");
    cJSON_AddStringToObject(m, "pixel_type", o->exr.pixel == SEA_EXR_HALF ? "half" : "float");
    cJSON_AddStringToObject(m, "compression",
                            o->exr.compression == SEA_EXR_NONE  ? "none"
                            : o->exr.compression == SEA_EXR_PIZ ? "piz"
                                                                : "zip");
    cJSON_AddStringToObject(m, "rows", "row 0 = north edge (largest y); texel (i, row) = facet "
                                       "(i0 + i, j0 + ny - 1 - row)");
    cJSON_AddNumberToObject(m, "emission_scale", w->scale);
    cJSON *u = cJSON_AddObjectToObject(m, "units");
    for (size_t k = 0; k < Q_COUNT; k++)
        cJSON_AddStringToObject(u, BAKE_Q[k].name, sea_bakemaps_unit(sc, (bake_quantity)k));
    cJSON_AddStringToObject(m, "roughness_convention",
                            "GGX in Blender's Principled BSDF: alpha = sqrt(C_xx + C_yy) "
                            "(Beckmann-equivalent width), roughness = sqrt(alpha); anisotropy = "
                            "(l1 - l2) / (l1 + l2); rotation = major-axis angle from east / 2 pi");
    cJSON_AddItemToObject(m, "levels", levels_json(sc, b));
    if (w->have_hz)
        cJSON_AddItemToObject(m, "horizon", horizon_json(&w->hz, cam));
    if (w->sensor) {
        /* the sensor's image, projected by the exports where it sees */
        cJSON *s = cJSON_AddObjectToObject(m, "sensor");
        cJSON_AddStringToObject(s, "quantity", "radiance x emission_scale of each pixel, as "
                                               "seabake render gives it; row 0 at the top");
        cJSON_AddNumberToObject(s, "width", cam->width);
        cJSON_AddNumberToObject(s, "height", cam->height);
        cJSON_AddArrayToObject(s, "frames");
    }
    if (o->blender)
        cJSON_AddItemToObject(m, "blender", blender_json(w));
    return m;
}

/* The manifest entry of a level at one frame: its files' names. */
static sea_status files_json(const sea_bake_writer *w, int level, cJSON *files, sea_error *err)
{
    for (size_t g = 0; g < BAKE_N_GROUPS; g++) {
        const char *name = BAKE_GROUPS[g].name;
        char *exr_name = sea_bakemaps_name(name, level, w->o.framed, w->frame, ".exr");
        char *png_name = sea_bakemaps_name(name, level, w->o.framed, w->frame, ".png");
        cJSON *f = exr_name && png_name ? cJSON_AddObjectToObject(files, name) : NULL;
        const int ok = f != NULL && cJSON_AddStringToObject(f, "exr", exr_name) &&
                       (!w->o.previews || cJSON_AddStringToObject(f, "png", png_name));
        free(exr_name);
        free(png_name);
        if (!ok)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    }
    return SEA_OK;
}

/* The "height" object of level lv's entry for the frame (the heights
 * bakemaps.c wrote, over [lo, hi]). */
static sea_status height_json(const sea_bake_writer *w, const sea_clip_level *lv, double lo,
                              double hi, cJSON *entry, sea_error *err)
{
    const int S = sea_bakemaps_height_samples(lv);
    char *png = sea_bakemaps_name("height", lv->level, w->o.framed, w->frame, ".png");
    char *exr = sea_bakemaps_name("height", lv->level, w->o.framed, w->frame, ".exr");
    cJSON *o = png != NULL && exr != NULL ? cJSON_AddObjectToObject(entry, "height") : NULL;
    const int ok =
        o != NULL && cJSON_AddNumberToObject(o, "samples_per_facet", S) &&
        cJSON_AddNumberToObject(o, "width", (double)(S * (int)lv->nx + 1)) &&
        cJSON_AddNumberToObject(o, "height", (double)(S * (int)lv->ny + 1)) &&
        cJSON_AddNumberToObject(o, "min_m", lo) && cJSON_AddNumberToObject(o, "max_m", hi) &&
        (!w->o.pov || cJSON_AddStringToObject(o, "png", png)) &&
        (!w->o.blender || cJSON_AddStringToObject(o, "exr", exr));
    free(png);
    free(exr);
    return ok ? SEA_OK : sea_fail(err, SEA_ERR_NOMEM, "out of memory");
}

sea_status sea_manifest_frame(sea_bake_writer *w, const sea_bake *b, const char *sensor_exr,
                              sea_error *err)
{
    cJSON *m = w->manifest;
    const long f = w->frame;
    const double t = w->t;
    if (sensor_exr != NULL) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "frame", (double)f);
        cJSON_AddNumberToObject(e, "time_s", t);
        cJSON_AddStringToObject(e, "exr", sensor_exr);
        cJSON_AddItemToArray(cJSON_GetObjectItem(cJSON_GetObjectItem(m, "sensor"), "frames"), e);
    }
    cJSON *fr = cJSON_CreateObject();
    cJSON_AddNumberToObject(fr, "frame", (double)f);
    cJSON_AddNumberToObject(fr, "time_s", t);
    cJSON_AddItemToArray(cJSON_GetObjectItem(m, "frames"), fr);
    cJSON *levels = cJSON_GetObjectItem(m, "levels");
    sea_status st = SEA_OK;
    for (size_t l = 0; l < b->n_levels && st == SEA_OK; l++) {
        if (b->levels[l].level.low_res)
            continue;
        cJSON *entry = cJSON_CreateObject();
        cJSON_AddNumberToObject(entry, "frame", (double)f);
        cJSON_AddNumberToObject(entry, "time_s", t);
        cJSON *files = cJSON_AddObjectToObject(entry, "files");
        cJSON_AddItemToArray(cJSON_GetObjectItem(cJSON_GetArrayItem(levels, (int)l), "frames"),
                             entry);
        st = files_json(w, b->levels[l].level.level, files, err);
        if (st == SEA_OK && w->height_lo != NULL) {
            const size_t h = l * w->n_frames + (size_t)(f - w->first);
            st = height_json(w, &b->levels[l].level, w->height_lo[h], w->height_hi[h], entry,
                             err);
        }
    }
    return st;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The manifest's "files": every file in the directory, sorted, the
 * manifest itself included (the temporary directory's marker and the spill
 * files, dot files, are not part of the bake).  A later bake replaces the
 * directory only if this list names everything in it (atomicdir.c). */
static sea_status list_files(const char *dir, cJSON *m, sea_error *err)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return sea_fail(err, SEA_ERR_IO, "cannot read '%s': %s", dir, strerror(errno));
    /* room for one more name than read: manifest.json */
    size_t n = 0, cap = 64;
    char **names = malloc(cap * sizeof *names);
    int nomem = names == NULL;
    struct dirent *e;
    while (!nomem && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || strcmp(e->d_name, "manifest.json") == 0)
            continue;
        if (n + 2 > cap) {
            char **more = realloc(names, 2 * cap * sizeof *names);
            if ((nomem = more == NULL))
                break;
            names = more;
            cap *= 2;
        }
        nomem = (names[n] = strdup(e->d_name)) == NULL;
        n += !nomem;
    }
    closedir(d);
    if (!nomem)
        nomem = (names[n] = strdup("manifest.json")) == NULL;
    n += !nomem;
    cJSON *files = NULL;
    if (!nomem) {
        qsort(names, n, sizeof *names, compare_names);
        files = cJSON_CreateStringArray((const char *const *)names, (int)n);
        nomem = files == NULL || !cJSON_AddItemToObject(m, "files", files);
    }
    for (size_t i = 0; i < n; ++i)
        free(names[i]);
    free(names);
    return nomem ? sea_fail(err, SEA_ERR_NOMEM, "out of memory") : SEA_OK;
}

/* Writes text to dir/name (a plain write: the directory as a whole is
 * what appears atomically). */
static sea_status write_text(const char *dir, const char *name, const char *text, sea_error *err)
{
    char *path = sea_path_join(dir, name);
    sea_status st = SEA_OK;
    if (text == NULL || path == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    } else {
        FILE *f = fopen(path, "w");
        if (f == NULL) {
            st = sea_fail(err, SEA_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
        } else {
            const int ok = fputs(text, f) >= 0;
            if (fclose(f) != 0 || !ok)
                st = sea_fail(err, SEA_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
        }
    }
    free(path);
    return st;
}

sea_status sea_manifest_write(const sea_bake_writer *w, sea_error *err)
{
    sea_status st = list_files(w->dir, w->manifest, err);
    if (st != SEA_OK)
        return st;
    char *text = cJSON_Print(w->manifest);
    char *line = NULL;
    if (text != NULL && (line = malloc(strlen(text) + 2)) != NULL)
        snprintf(line, strlen(text) + 2, "%s\n", text);
    st = write_text(w->dir, "manifest.json", line, err);
    free(text);
    free(line);
    return st;
}
