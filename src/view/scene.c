/* scene.c - the scene file (man/seabake-scene.5) and spectral response curves.
 *
 * A scene is INI text read with inih.  inih gives the handler no line number
 * (the Debian build leaves INI_HANDLER_LINENO off), so the file is read into
 * memory and handed to ini_parse_stream() one line at a time by our own
 * reader, which counts the lines: inih calls the handler for a line before
 * it asks for the next one, so the count is the line of the key.  The
 * reader also checks section names (inih reports no section that holds no
 * key), removes indentation (inih would take an indented line for the
 * continuation of the previous value) and '#' comments after a value (inih
 * only knows ';' there).
 *
 * Every key is described once in SEA_KEYS: its section, kind, range, unit
 * and conversion to SI.  Messages are built from that table, so a range in
 * an error message is the range that was checked. */
#include "config.h"

#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "seabake.h"
#include "base/textfile.h"

static const double SEA_DEG = M_PI / 180.0;  /* degrees -> radians */
static const double SEA_UM = 1e-6;           /* micrometres -> metres */
static const double SEA_PER_UM = 1e6;        /* per micrometre -> per metre */
/* Scene files and response curves are small; larger files are refused
 * before they are read into memory. */
static const long SEA_SCENE_BYTES_MAX = 1L << 20;
static const long SEA_RESPONSE_BYTES_MAX = 64L << 20;
/* Raw values quoted in messages are cut to this many characters. */
enum { SEA_QUOTE_MAX = 60 };

/* ------------------------------------------------------------ text files */

/* ------------------------------------------------------ response curves */

static sea_status response_push(sea_response *r, size_t *cap, double wavelength, double value)
{
    if (r->n == *cap) {
        size_t ncap = *cap ? 2 * *cap : 64;
        double *nw = realloc(r->wavelength, ncap * sizeof *nw);
        if (nw == NULL)
            return SEA_ERR_NOMEM;
        r->wavelength = nw;
        double *nv = realloc(r->value, ncap * sizeof *nv);
        if (nv == NULL)
            return SEA_ERR_NOMEM;
        r->value = nv;
        *cap = ncap;
    }
    r->wavelength[r->n] = wavelength;
    r->value[r->n] = value;
    r->n++;
    return SEA_OK;
}

sea_status sea_response_load(const char *path, sea_response *r, sea_error *err)
{
    sea_status st;
    char *text = NULL;
    size_t cap = 0;
    long lineno = 0;
    int header = 0, i_wl = 0, any_positive = 0;
    memset(r, 0, sizeof *r);
    if ((st = sea_read_text(path, SEA_RESPONSE_BYTES_MAX, "text file", &text, err)) != SEA_OK)
        return st;
    char *cursor = text;
    for (char *p; (p = sea_text_next_line(&cursor, &lineno)) != NULL;) {
        char *comma = strchr(p, ',');
        if (comma == NULL || strchr(comma + 1, ',') != NULL) {
            st = sea_fail(err, SEA_ERR_PARSE, "%s:%ld: need exactly two comma-separated fields",
                          path, lineno);
            goto fail;
        }
        *comma = '\0';
        char *field[2] = { sea_text_trim(p), sea_text_trim(comma + 1) };
        if (!header) {
            if (strcmp(field[0], "wavelength_um") == 0 && strcmp(field[1], "response") == 0) {
                i_wl = 0;
            } else if (strcmp(field[0], "response") == 0 &&
                       strcmp(field[1], "wavelength_um") == 0) {
                i_wl = 1;
            } else {
                st = sea_fail(err, SEA_ERR_PARSE,
                              "%s:%ld: the header must name the columns wavelength_um,response",
                              path, lineno);
                goto fail;
            }
            header = 1;
            continue;
        }
        double wl_um, value;
        if (sea_text_real(field[i_wl], &wl_um) != 0 || !isfinite(wl_um) || wl_um <= 0.0) {
            st = sea_fail(err, SEA_ERR_PARSE,
                          "%s:%ld: wavelength_um: '%.*s' is not a positive number", path, lineno,
                          SEA_QUOTE_MAX, field[i_wl]);
            goto fail;
        }
        if (sea_text_real(field[1 - i_wl], &value) != 0 || !isfinite(value)) {
            st = sea_fail(err, SEA_ERR_PARSE, "%s:%ld: response: '%.*s' is not a number", path,
                          lineno, SEA_QUOTE_MAX, field[1 - i_wl]);
            goto fail;
        }
        /* values as read, to as many digits as tell them from the bound */
        char v_txt[SEA_TEXT_REAL_CHARS], max_txt[SEA_TEXT_REAL_CHARS];
        if (!(value >= 0.0 && value <= SEA_RESPONSE_MAX)) {
            st = sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: response: %s is outside [0, %s]", path,
                          lineno, sea_text_format_real(value, v_txt),
                          sea_text_format_real(SEA_RESPONSE_MAX, max_txt));
            goto fail;
        }
        if (!(wl_um <= SEA_RESPONSE_WAVELENGTH_MAX_UM)) {
            st = sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: wavelength_um: %s is outside (0, %s]",
                          path, lineno, sea_text_format_real(wl_um, v_txt),
                          sea_text_format_real(SEA_RESPONSE_WAVELENGTH_MAX_UM, max_txt));
            goto fail;
        }
        double wl = wl_um * SEA_UM;
        if (!isnormal(wl)) { /* a positive number of micrometres too small for metres */
            st = sea_fail(err, SEA_ERR_DOMAIN, "%s:%ld: wavelength_um: %s is outside (0, %s]",
                          path, lineno, sea_text_format_real(wl_um, v_txt),
                          sea_text_format_real(SEA_RESPONSE_WAVELENGTH_MAX_UM, max_txt));
            goto fail;
        }
        if (r->n > 0 && !(wl > r->wavelength[r->n - 1])) {
            char prev_txt[SEA_TEXT_REAL_CHARS];
            st = sea_fail(err, SEA_ERR_PARSE,
                          "%s:%ld: wavelength_um: %s does not increase (previous row %s)", path,
                          lineno, sea_text_format_real(wl_um, v_txt),
                          sea_text_format_real(r->wavelength[r->n - 1] / SEA_UM, prev_txt));
            goto fail;
        }
        if ((st = response_push(r, &cap, wl, value)) != SEA_OK) {
            sea_fail(err, st, "%s: out of memory", path);
            goto fail;
        }
        any_positive |= value > 0.0;
    }
    if (!header) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: no header row wavelength_um,response", path);
        goto fail;
    }
    if (r->n < 2) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: a response needs at least two rows (found %zu)",
                      path, r->n);
        goto fail;
    }
    if (!any_positive) {
        st = sea_fail(err, SEA_ERR_DOMAIN, "%s: the response is zero everywhere", path);
        goto fail;
    }
    free(text);
    return SEA_OK;
fail:
    free(text);
    sea_response_free(r);
    return st;
}

void sea_response_free(sea_response *r)
{
    if (r == NULL)
        return;
    free(r->wavelength);
    free(r->value);
    memset(r, 0, sizeof *r);
}

/* ---------------------------------------------------------- key table */

typedef enum {
    SEC_SEA, SEC_SWELL, SEC_SUN, SEC_SKY, SEC_ATMOSPHERE, SEC_SENSOR, SEC_MODEL, SEC_COUNT
} sea_section;
static const char *const SEA_SECTIONS[SEC_COUNT] = { "sea", "swell", "sun", "sky", "atmosphere",
                                                     "sensor", "model" };
#define SEA_SECTION_LIST "sea, swell, sun, sky, atmosphere, sensor, model"

typedef enum {
    KIND_REAL,   /* a number, range [lo, hi] (see flags), times scale */
    KIND_INT,    /* an integer in [lo, hi] */
    KIND_SEED,   /* an unsigned integer in [0, 2^32 - 1] */
    KIND_CHOICE, /* a name from a fixed list */
    KIND_WATER,  /* a table name or a CSV path */
    KIND_BAND,   /* A:B in micrometres */
    KIND_PATH    /* a CSV path */
} key_kind;

enum {
    LO_OPEN = 1, /* (lo, ... instead of [lo, ... */
    HI_OPEN = 2, /* ..., hi) instead of ..., hi] */
    EVEN = 4,    /* an even integer */
    REQUIRED = 8,
    AUTO = 16    /* KIND_INT: or "auto", stored as 0 */
};

typedef enum {
    K_WIND_SPEED, K_WIND_DIRECTION, K_FETCH, K_SEA_TEMPERATURE, K_SALINITY, K_WATER, K_SEED,
    K_TIME, K_LOOP_PERIOD,
    K_SWELL_HEIGHT, K_SWELL_PERIOD, K_SWELL_DIRECTION, K_SWELL_SPREAD, K_SWELL_GAMMA,
    K_SWELL_DOUGLAS,
    K_SUN_ZENITH, K_SUN_AZIMUTH, K_SUN_IRRADIANCE, K_SUN_TEMPERATURE, K_SUN_SOLID_ANGLE,
    K_SUN_TRANSMITTANCE, K_SUN_ANGULAR_RADIUS,
    K_SKY_RADIANCE, K_SKY_TEMPERATURE, K_SKY_MODEL, K_SKY_ZENITH_EMISSIVITY,
    K_SKY_TABLE, K_AIR_TEMPERATURE, K_EXTINCTION, K_ATMOSPHERE_TABLE,
    K_X, K_Y, K_ALTITUDE, K_LOOK_ZENITH, K_LOOK_AZIMUTH, K_ROLL, K_POLARIZER, K_HFOV, K_WIDTH,
    K_HEIGHT,
    K_WAVELENGTH, K_BAND, K_RESPONSE, K_SAMPLES,
    K_PSF_SIGMA, K_F_NUMBER, K_PITCH, K_MTF, K_FILL_FACTOR, K_NETD, K_NETD_TEMPERATURE,
    K_NOISE_SEED, K_FPN_GAIN, K_FPN_OFFSET, K_FPN_SEED, K_GAIN, K_OFFSET, K_BIT_DEPTH,
    K_METHOD, K_N, K_FINEST, K_GRID, K_EMISSIVITY, K_EARTH, K_WINDOWS, K_TOLERANCE,
    K_REFLECTIONS, K_SHADOWING, K_SCALES,
    K_COUNT
} key_id;

static int windows_from_name(const char *name)
{
    if (strcmp(name, "view") == 0)
        return SEA_WINDOWS_VIEW;
    if (strcmp(name, "clipmap") == 0)
        return SEA_WINDOWS_CLIPMAP;
    return -1;
}

static int sky_model_from_name(const char *name)
{
    if (strcmp(name, "isotropic") == 0)
        return SEA_SKY_ISOTROPIC;
    if (strcmp(name, "clear") == 0)
        return SEA_SKY_CLEAR;
    if (strcmp(name, "table") == 0)
        return SEA_SKY_TABLE;
    return -1;
}

static int earth_from_name(const char *name)
{
    if (strcmp(name, "flat") == 0)
        return SEA_EARTH_FLAT;
    if (strcmp(name, "spherical") == 0)
        return SEA_EARTH_SPHERICAL;
    return -1;
}

typedef struct {
    sea_section section;
    const char *name;
    key_kind kind;
    double lo, hi;
    unsigned flags;
    double scale;      /* KIND_REAL: factor to SI after the range check */
    const char *unit;  /* as the user writes the value, for messages */
    size_t offset;     /* of the double or int in sea_scene */
    int (*from_name)(const char *name); /* KIND_CHOICE */
    const char *names;                  /* KIND_CHOICE: the allowed names; KIND_PATH: the
                                           CSV file's columns */
} key_spec;

#define INF INFINITY
#define AT(field) offsetof(sea_scene, field)
#define REAL(sec, name, lo, hi, flags, scale, unit, field)                                    \
    { sec, name, KIND_REAL, lo, hi, flags, scale, unit, AT(field), NULL, NULL }
#define INT(sec, name, lo, hi, flags, unit, field)                                            \
    { sec, name, KIND_INT, lo, hi, flags, 1.0, unit, AT(field), NULL, NULL }
#define CSV(sec, name, columns, field)                                                        \
    { sec, name, KIND_PATH, 0, 0, 0, 1.0, "", AT(field), NULL, columns }
#define CHOICE(sec, name, fn, names, field)                                                   \
    { sec, name, KIND_CHOICE, 0, 0, 0, 1.0, "", AT(field), fn, names }
#define SEED(sec, name, field)                                                                \
    { sec, name, KIND_SEED, 0, 4294967295.0, 0, 1.0, "", AT(field), NULL, NULL }
/* A choice is stored, reset and copied as an int (set_key, reset_key): each
 * enum a CHOICE key fills must be an int's size. */
_Static_assert(sizeof(sea_sky_model) == sizeof(int) && sizeof(sea_facet_method) == sizeof(int) &&
                   sizeof(sea_emis_method) == sizeof(int) && sizeof(sea_earth) == sizeof(int) &&
                   sizeof(sea_windows) == sizeof(int) && sizeof(sea_shadowing) == sizeof(int),
               "a CHOICE key's enum is stored as an int");

/* Indexed by key_id.  "any finite" is (-inf, inf); ranges follow seabake.h. */
static const key_spec SEA_KEYS[K_COUNT] = {
    [K_WIND_SPEED] = REAL(SEC_SEA, "wind_speed", SEA_WIND_MIN, SEA_WIND_MAX, REQUIRED, 1.0,
                          "m/s", wind_speed),
    [K_WIND_DIRECTION] = REAL(SEC_SEA, "wind_direction", -INF, INF, LO_OPEN | HI_OPEN, SEA_DEG,
                              "deg", wind_dir),
    [K_FETCH] = REAL(SEC_SEA, "fetch", SEA_FETCH_MIN, INF, 0, 1.0, "m", fetch),
    [K_SEA_TEMPERATURE] = REAL(SEC_SEA, "temperature", 271.0, 313.0, 0, 1.0, "K", temperature),
    [K_SALINITY] = REAL(SEC_SEA, "salinity", 0.0, SEA_SALINITY_MAX, 0, 1.0, "g/kg", salinity),
    [K_WATER] = { SEC_SEA, "water", KIND_WATER, 0, 0, 0, 1.0, "", AT(water_table), NULL, NULL },
    [K_SEED] = SEED(SEC_SEA, "seed", seed),
    [K_TIME] = REAL(SEC_SEA, "time", -SEA_TIME_MAX, SEA_TIME_MAX, 0, 1.0, "s", time),
    [K_LOOP_PERIOD] = REAL(SEC_SEA, "loop_period", 0.0, INF, HI_OPEN, 1.0, "s", loop_period),

    /* [swell]: the offsets are swell[0]'s; a later section's are shifted by
     * its index times sizeof(sea_scene_swell) */
    [K_SWELL_HEIGHT] = REAL(SEC_SWELL, "height", SEA_SWELL_HS_MIN, SEA_SWELL_HS_MAX, 0, 1.0, "m",
                            swell[0].sw.hs),
    [K_SWELL_PERIOD] = REAL(SEC_SWELL, "period", SEA_SWELL_TP_MIN, SEA_SWELL_TP_MAX, 0, 1.0, "s",
                            swell[0].sw.tp),
    [K_SWELL_DIRECTION] = REAL(SEC_SWELL, "direction", -INF, INF, LO_OPEN | HI_OPEN, SEA_DEG,
                               "deg", swell[0].sw.dir),
    [K_SWELL_SPREAD] = REAL(SEC_SWELL, "spread", SEA_SWELL_SPREAD_MIN_DEG,
                            SEA_SWELL_SPREAD_MAX_DEG, 0, SEA_DEG, "deg", swell[0].sw.spread),
    [K_SWELL_GAMMA] = REAL(SEC_SWELL, "gamma", SEA_SWELL_GAMMA_MIN, SEA_SWELL_GAMMA_MAX, 0, 1.0,
                           "", swell[0].sw.gamma),
    [K_SWELL_DOUGLAS] = INT(SEC_SWELL, "douglas", 1, 8, 0, "", swell[0].douglas),

    [K_SUN_ZENITH] = REAL(SEC_SUN, "zenith", 0.0, 180.0, 0, SEA_DEG, "deg", sun_zenith),
    [K_SUN_AZIMUTH] = REAL(SEC_SUN, "azimuth", -INF, INF, LO_OPEN | HI_OPEN, SEA_DEG, "deg",
                           sun_azimuth),
    [K_SUN_IRRADIANCE] = REAL(SEC_SUN, "irradiance", 0.0, 1e5, 0, SEA_PER_UM, "W m^-2 um^-1",
                              sun_irradiance),
    [K_SUN_TEMPERATURE] = REAL(SEC_SUN, "temperature", 0.0, 10000.0, LO_OPEN, 1.0, "K",
                               sun_temperature),
    [K_SUN_SOLID_ANGLE] = REAL(SEC_SUN, "solid_angle", 0.0, 0.01, LO_OPEN, 1.0, "sr",
                               sun_solid_angle),
    [K_SUN_TRANSMITTANCE] = REAL(SEC_SUN, "transmittance", 0.0, 1.0, 0, 1.0, "",
                                 sun_transmittance),
    [K_SUN_ANGULAR_RADIUS] = REAL(SEC_SUN, "angular_radius", 0.0, 5.0, 0, SEA_DEG, "deg",
                                  sun_radius),

    [K_SKY_RADIANCE] = REAL(SEC_SKY, "radiance", 0.0, 1e3, 0, SEA_PER_UM,
                            "W m^-2 sr^-1 um^-1", sky_radiance),
    [K_SKY_TEMPERATURE] = REAL(SEC_SKY, "temperature", 0.0, 400.0, LO_OPEN, 1.0, "K",
                               sky_temperature),
    [K_SKY_MODEL] = CHOICE(SEC_SKY, "model", sky_model_from_name, "isotropic, clear, table",
                           sky_model),
    [K_SKY_TABLE] = CSV(SEC_SKY, "table", "zenith_deg,wavelength_um,radiance", sky_table_file),
    [K_ATMOSPHERE_TABLE] = CSV(SEC_ATMOSPHERE, "table",
                               "range_m,wavelength_um,transmittance,path_radiance",
                               atmosphere_table_file),
    [K_SKY_ZENITH_EMISSIVITY] = REAL(SEC_SKY, "zenith_emissivity", 0.0, 1.0, LO_OPEN, 1.0, "",
                                     sky_zenith_emissivity),

    [K_AIR_TEMPERATURE] = REAL(SEC_ATMOSPHERE, "air_temperature", 0.0, 400.0, LO_OPEN, 1.0, "K",
                               air_temperature),
    [K_EXTINCTION] = REAL(SEC_ATMOSPHERE, "extinction", 0.0, 1e3, 0, 1e-3, "1/km", extinction),

    [K_X] = REAL(SEC_SENSOR, "x", -SEA_SENSOR_XY_MAX, SEA_SENSOR_XY_MAX, 0, 1.0, "m", sensor_x),
    [K_Y] = REAL(SEC_SENSOR, "y", -SEA_SENSOR_XY_MAX, SEA_SENSOR_XY_MAX, 0, 1.0, "m", sensor_y),
    [K_ALTITUDE] = REAL(SEC_SENSOR, "altitude", 0.0, 1e6, LO_OPEN | REQUIRED, 1.0, "m",
                        altitude),
    [K_LOOK_ZENITH] = REAL(SEC_SENSOR, "look_zenith", 0.0, 90.0, HI_OPEN, SEA_DEG, "deg",
                           look_zenith),
    [K_LOOK_AZIMUTH] = REAL(SEC_SENSOR, "look_azimuth", -INF, INF, LO_OPEN | HI_OPEN, SEA_DEG,
                            "deg", look_azimuth),
    [K_ROLL] = REAL(SEC_SENSOR, "roll", -INF, INF, LO_OPEN | HI_OPEN, SEA_DEG, "deg", roll),
    [K_POLARIZER] = REAL(SEC_SENSOR, "polarizer", -180.0, 180.0, 0, SEA_DEG, "deg", polarizer),
    [K_HFOV] = REAL(SEC_SENSOR, "hfov", SEA_HFOV_MIN_DEG, 170.0, REQUIRED, SEA_DEG, "deg", hfov),
    [K_WIDTH] = INT(SEC_SENSOR, "width", 1, 16384, REQUIRED, "pixels", width),
    [K_HEIGHT] = INT(SEC_SENSOR, "height", 1, 16384, REQUIRED, "pixels", height),
    [K_WAVELENGTH] = REAL(SEC_SENSOR, "wavelength", 0.0, INF, LO_OPEN | HI_OPEN, SEA_UM, "um",
                          wavelength),
    [K_BAND] = { SEC_SENSOR, "band", KIND_BAND, 0, 0, 0, SEA_UM, "um", AT(band_min), NULL,
                 NULL },
    [K_RESPONSE] = CSV(SEC_SENSOR, "response", "wavelength_um,response", response_file),
    [K_SAMPLES] = INT(SEC_SENSOR, "samples", 1, SEA_SCENE_BAND_MAX, 0, "", band_samples),
    /* the camera (imager.c): ranges from seabake.h's SEA_IMAGER_ macros */
    [K_PSF_SIGMA] = REAL(SEC_SENSOR, "psf_sigma", 0.0, SEA_IMAGER_SIGMA_MAX, LO_OPEN, 1.0,
                         "pixels", psf_sigma),
    [K_F_NUMBER] = REAL(SEC_SENSOR, "f_number", SEA_IMAGER_F_NUMBER_MIN, SEA_IMAGER_F_NUMBER_MAX,
                        0, 1.0, "", f_number),
    [K_PITCH] = REAL(SEC_SENSOR, "pitch", SEA_IMAGER_PITCH_MIN_UM, SEA_IMAGER_PITCH_MAX_UM, 0,
                     SEA_UM, "um", pitch),
    [K_MTF] = CSV(SEC_SENSOR, "mtf", "cycles_per_pixel,mtf", mtf_file),
    [K_FILL_FACTOR] = REAL(SEC_SENSOR, "fill_factor", 0.0, 1.0, LO_OPEN, 1.0, "", fill_factor),
    [K_NETD] = REAL(SEC_SENSOR, "netd", 0.0, SEA_IMAGER_NETD_MAX, LO_OPEN, 1.0, "K", netd),
    [K_NETD_TEMPERATURE] = REAL(SEC_SENSOR, "netd_temperature", SEA_IMAGER_T_MIN,
                                SEA_IMAGER_T_MAX, 0, 1.0, "K", netd_temperature),
    [K_NOISE_SEED] = SEED(SEC_SENSOR, "noise_seed", noise_seed),
    [K_FPN_GAIN] = REAL(SEC_SENSOR, "fpn_gain", 0.0, SEA_IMAGER_FPN_GAIN_MAX, 0, 1.0, "",
                        fpn_gain),
    [K_FPN_OFFSET] = REAL(SEC_SENSOR, "fpn_offset", 0.0, SEA_IMAGER_FPN_OFFSET_MAX, 0, 1.0, "K",
                          fpn_offset),
    [K_FPN_SEED] = SEED(SEC_SENSOR, "fpn_seed", fpn_seed),
    [K_GAIN] = REAL(SEC_SENSOR, "gain", 0.0, SEA_IMAGER_GAIN_MAX, LO_OPEN, 1.0,
                    "counts per radiance unit", gain),
    [K_OFFSET] = REAL(SEC_SENSOR, "offset", -SEA_IMAGER_OFFSET_MAX, SEA_IMAGER_OFFSET_MAX, 0, 1.0,
                      "counts", offset),
    [K_BIT_DEPTH] = INT(SEC_SENSOR, "bit_depth", SEA_IMAGER_BITS_MIN, SEA_IMAGER_BITS_MAX, 0,
                        "bits", bit_depth),

    [K_METHOD] = CHOICE(SEC_MODEL, "method", sea_facet_method_from_name,
                        "variable-step, variable-step-2n, one-meter", method),
    [K_N] = INT(SEC_MODEL, "n", 0, 20, 0, "", n),
    [K_FINEST] = REAL(SEC_MODEL, "finest", SEA_FINEST_MIN, 1000.0, 0, 1.0, "m", finest),
    [K_GRID] = INT(SEC_MODEL, "grid", 16, 4096, EVEN | AUTO, "facets", grid),
    [K_EMISSIVITY] = CHOICE(SEC_MODEL, "emissivity", sea_emis_method_from_name,
                            "auto, fast, full", emissivity_method),
    [K_EARTH] = CHOICE(SEC_MODEL, "earth", earth_from_name, "flat, spherical", earth),
    [K_WINDOWS] = CHOICE(SEC_MODEL, "windows", windows_from_name, "view, clipmap", windows),
    [K_TOLERANCE] = REAL(SEC_MODEL, "tolerance", 0.0, 0.1, LO_OPEN, 1.0, "", tolerance),
    [K_REFLECTIONS] = CHOICE(SEC_MODEL, "reflections", sea_reflections_from_name,
                             "auto, 1, 2, 3", reflections),
    [K_SHADOWING] = CHOICE(SEC_MODEL, "shadowing", sea_shadowing_from_name, "smith, correlated",
                           shadowing),
    [K_SCALES] = INT(SEC_MODEL, "scales", 1, 2, 0, "", scales),
};

#undef INF
#undef AT
#undef REAL
#undef INT
#undef CHOICE
#undef CSV
#undef SEED

/* "1e+06" reads worse than "1000000" in a range. */
static void format_bound(char *buf, size_t size, double v)
{
    if (isinf(v))
        snprintf(buf, size, "%sinf", v < 0 ? "-" : "");
    else
        snprintf(buf, size, "%.10g", v);
}

/* The "allowed" part of a message for key k. */
static void allowed_text(const key_spec *k, char *buf, size_t size)
{
    char lo[32], hi[32];
    const char *unit_sep = k->unit[0] != '\0' ? " " : "";
    switch (k->kind) {
    case KIND_CHOICE:
        snprintf(buf, size, "%s", k->names);
        return;
    case KIND_WATER:
        snprintf(buf, size, "hale-querry, segelstein, or the path of a CSV file "
                            "(wavelength_um,n,k) containing a '/' or a '.'");
        return;
    case KIND_BAND:
        snprintf(buf, size, "A:B in um with 0 < A < B");
        return;
    case KIND_PATH:
        snprintf(buf, size, "the path of a readable CSV file (%s), relative to the scene "
                            "file's directory",
                 k->names);
        return;
    case KIND_SEED:
        snprintf(buf, size, "an integer in [0, 4294967295]");
        return;
    case KIND_INT:
        format_bound(lo, sizeof lo, k->lo);
        format_bound(hi, sizeof hi, k->hi);
        snprintf(buf, size, "%s%s in [%s, %s]%s%s", (k->flags & AUTO) ? "auto or " : "",
                 (k->flags & EVEN) ? "an even integer" : "an integer", lo, hi, unit_sep, k->unit);
        return;
    case KIND_REAL:
        if (isinf(k->lo) && isinf(k->hi)) {
            snprintf(buf, size, "any finite value%s%s", k->unit[0] ? " in " : "", k->unit);
            return;
        }
        format_bound(lo, sizeof lo, k->lo);
        format_bound(hi, sizeof hi, k->hi);
        snprintf(buf, size, "%c%s, %s%c%s%s", (k->flags & LO_OPEN) ? '(' : '[', lo, hi,
                 (k->flags & HI_OPEN) ? ')' : ']', unit_sep, k->unit);
        return;
    }
    snprintf(buf, size, "?");
}

static int in_range(const key_spec *k, double v)
{
    int lo_ok = (k->flags & LO_OPEN) ? v > k->lo : v >= k->lo;
    int hi_ok = (k->flags & HI_OPEN) ? v < k->hi : v <= k->hi;
    return lo_ok && hi_ok;
}

/* ------------------------------------------------------------- loader */

typedef struct {
    const char *path;      /* the scene file, as given */
    const char *text;      /* its contents */
    size_t len, pos;       /* reader position */
    long lineno;           /* line last handed to inih */
    long section_line[SEC_COUNT]; /* first [section] line, 0 if absent */
    long key_line[K_COUNT];       /* line of each key, 0 if absent */
    sea_scene sc;
    sea_status status;     /* first error */
    long err_line;
    sea_error err;
    const char *const *overrides; /* "section.key=value", applied after the file */
    size_t n_overrides;
    long swell_line[SEA_SWELL_MAX]; /* each [swell] section's line */
} loader;

/* Override i stands at "line" SEA_OVERRIDE_LINE + i: after every line of the
 * file (so it wins a conflict and is named as the later key), and messages
 * about it name the override instead of a file line. */
static const long SEA_OVERRIDE_LINE = 1L << 40;

static bool is_override_line(const loader *ld, long line)
{
    return line >= SEA_OVERRIDE_LINE && (size_t)(line - SEA_OVERRIDE_LINE) < ld->n_overrides;
}

static void vrecord(loader *ld, sea_status st, long line, const char *fmt, va_list ap)
    __attribute__((format(printf, 4, 0)));
static void vrecord(loader *ld, sea_status st, long line, const char *fmt, va_list ap)
{
    if (ld->status != SEA_OK)
        return;
    char what[SEA_ERROR_MSG_MAX];
    vsnprintf(what, sizeof what, fmt, ap);
    if (is_override_line(ld, line)) {
        const char *o = ld->overrides[line - SEA_OVERRIDE_LINE];
        sea_fail(&ld->err, st, "%s %.*s: %s", strchr(o, '=') ? "--set" : "--unset",
                 SEA_QUOTE_MAX, o, what);
    }
    else if (line > 0)
        sea_fail(&ld->err, st, "%s:%ld: %s", ld->path, line, what);
    else
        sea_fail(&ld->err, st, "%s: %s", ld->path, what);
    ld->status = st;
    ld->err_line = line;
}

/* Records the first error, "FILE:LINE: message"; returns 0 for inih. */
static int fail_line(loader *ld, sea_status st, long line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int fail_line(loader *ld, sea_status st, long line, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vrecord(ld, st, line, fmt, ap);
    va_end(ap);
    return 0;
}

/* Records "FILE:LINE: [section] key: message (allowed: RANGE)"; returns 0. */
static int fail_key(loader *ld, sea_status st, long line, key_id id, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static int fail_key(loader *ld, sea_status st, long line, key_id id, const char *fmt, ...)
{
    const key_spec *k = &SEA_KEYS[id];
    char what[SEA_ERROR_MSG_MAX / 2], allowed[SEA_ERROR_MSG_MAX / 2];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    allowed_text(k, allowed, sizeof allowed);
    return fail_line(ld, st, line, "[%s] %s: %s (allowed: %s)", SEA_SECTIONS[k->section],
                     k->name, what, allowed);
}

static int section_index(const char *name)
{
    for (int s = 0; s < SEC_COUNT; s++)
        if (strcmp(name, SEA_SECTIONS[s]) == 0)
            return s;
    return -1;
}

/* The keys of section sec, comma-separated. */
static void section_keys(int sec, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < K_COUNT && used < size; i++)
        if ((int)SEA_KEYS[i].section == sec)
            used += (size_t)snprintf(buf + used, size - used, "%s%s", used ? ", " : "",
                                     SEA_KEYS[i].name);
}

static const double SEA_SWELL_SPREAD_DEFAULT_DEG = 15.0, SEA_SWELL_GAMMA_DEFAULT = 3.3;

/* The [swell] section being read: its height and period, from its keys or
 * its Douglas code; returns 0 (an error recorded) or 1. */
static int finish_swell(loader *ld)
{
    if (ld->sc.n_swell == 0 || ld->status != SEA_OK)
        return ld->status == SEA_OK;
    sea_scene_swell *s = &ld->sc.swell[ld->sc.n_swell - 1];
    const long line = ld->swell_line[ld->sc.n_swell - 1];
    double hs, tp;
    if (s->douglas != 0 && sea_swell_douglas(s->douglas, &hs, &tp) == 0) {
        if (ld->key_line[K_SWELL_HEIGHT] == 0)
            s->sw.hs = hs;
        if (ld->key_line[K_SWELL_PERIOD] == 0)
            s->sw.tp = tp;
        return 1;
    }
    if (ld->key_line[K_SWELL_HEIGHT] == 0 || ld->key_line[K_SWELL_PERIOD] == 0)
        return fail_key(ld, SEA_ERR_DOMAIN, line,
                        ld->key_line[K_SWELL_HEIGHT] == 0 ? K_SWELL_HEIGHT : K_SWELL_PERIOD,
                        "missing required key (a [swell] needs height and period, or douglas)");
    return 1;
}

/* A [swell] header at `line`: the previous swell is complete, a new one
 * starts with the defaults and its keys unseen.  Returns 0 (an error
 * recorded) or 1. */
static int begin_swell(loader *ld, long line)
{
    if (!finish_swell(ld))
        return 0;
    if (ld->sc.n_swell >= SEA_SWELL_MAX) {
        fail_line(ld, SEA_ERR_DOMAIN, line, "[swell]: too many swells (allowed: at most %d "
                  "[swell] sections)", SEA_SWELL_MAX);
        return 0;
    }
    sea_scene_swell *s = &ld->sc.swell[ld->sc.n_swell];
    memset(s, 0, sizeof *s);
    s->sw.dir = NAN; /* the wind's, once it is known */
    s->sw.spread = SEA_SWELL_SPREAD_DEFAULT_DEG * SEA_DEG;
    s->sw.gamma = SEA_SWELL_GAMMA_DEFAULT;
    ld->swell_line[ld->sc.n_swell] = line;
    ld->sc.n_swell++;
    for (int i = 0; i < K_COUNT; i++)
        if (SEA_KEYS[i].section == SEC_SWELL)
            ld->key_line[i] = 0;
    return 1;
}

/* inih's fgets-like reader over the file text: one line per call, counted,
 * cleaned of indentation and '#' comments, section names checked. */
static char *read_line(char *str, int num, void *stream)
{
    loader *ld = stream;
    if (ld->status != SEA_OK || ld->pos >= ld->len)
        return NULL;
    const char *p = ld->text + ld->pos;
    const char *nl = memchr(p, '\n', ld->len - ld->pos);
    size_t n = nl != NULL ? (size_t)(nl - p) : ld->len - ld->pos; /* without '\n' */
    ld->pos += n + (nl != NULL);
    ld->lineno++;
    /* inih needs room for the '\n' and the NUL, and takes a line that
     * fills its buffer for one too long. */
    const int max_line = num - 2;
    if (n > (size_t)max_line) {
        fail_line(ld, SEA_ERR_PARSE, ld->lineno,
                  "line too long: %zu characters (allowed: at most %d)", n, max_line);
        return NULL;
    }
    memcpy(str, p, n);
    str[n] = '\0';
    char *s = str;
    if (ld->lineno == 1 && strncmp(s, "\xEF\xBB\xBF", 3) == 0) /* UTF-8 byte order mark */
        s += 3;
    while (*s != '\0' && isspace((unsigned char)*s))
        s++;
    if (*s != '\0' && *s != '#' && *s != ';') {
        for (char *c = s + 1; *c != '\0'; c++)
            if (*c == '#' && isspace((unsigned char)c[-1])) {
                *c = '\0';
                break;
            }
    }
    if (*s == '[') {
        char *close = strchr(s, ']');
        if (close != NULL) {
            char name[64];
            size_t l = (size_t)(close - s - 1);
            snprintf(name, sizeof name, "%.*s", (int)(l < sizeof name ? l : sizeof name - 1),
                     s + 1);
            int sec = section_index(name);
            if (sec < 0) {
                fail_line(ld, SEA_ERR_PARSE, ld->lineno,
                          "[%.*s]: unknown section (allowed: " SEA_SECTION_LIST ")",
                          SEA_QUOTE_MAX, name);
                return NULL;
            }
            if (ld->section_line[sec] == 0)
                ld->section_line[sec] = ld->lineno;
            if (sec == SEC_SWELL && !begin_swell(ld, ld->lineno))
                return NULL;
        }
    }
    memmove(str, s, strlen(s) + 1);
    size_t l = strlen(str);
    str[l] = '\n';
    str[l + 1] = '\0';
    return str;
}

/* Resolves a path given in the scene against the scene file's directory
 * (one given by an override is taken as typed: relative to the working
 * directory). */
static int resolve_path(loader *ld, key_id id, const char *value, char *out)
{
    const char *slash = strrchr(ld->path, '/');
    int dir_len = (value[0] == '/' || slash == NULL || is_override_line(ld, ld->lineno))
                      ? 0
                      : (int)(slash - ld->path + 1);
    int len = snprintf(out, SEA_SCENE_PATH_MAX, "%.*s%s", dir_len, ld->path, value);
    if (len < 0 || len >= SEA_SCENE_PATH_MAX)
        return fail_key(ld, SEA_ERR_DOMAIN, ld->lineno, id,
                        "the resolved path is longer than %d characters",
                        SEA_SCENE_PATH_MAX - 1);
    return 1;
}

static int set_value(loader *ld, key_id id, const char *value)
{
    const key_spec *k = &SEA_KEYS[id];
    char *base = (char *)&ld->sc;
    if (k->section == SEC_SWELL) /* the current [swell] */
        base += (size_t)(ld->sc.n_swell - 1) * sizeof(sea_scene_swell);
    long line = ld->lineno;
    switch (k->kind) {
    case KIND_REAL: {
        double v;
        const int r = sea_text_real(value, &v);
        if (r > 0)
            return fail_key(ld, SEA_ERR_DOMAIN, line, id, "%.*s is out of range",
                            SEA_QUOTE_MAX, value);
        if (r != 0)
            return fail_key(ld, SEA_ERR_PARSE, line, id, "'%.*s' is not a number",
                            SEA_QUOTE_MAX, value);
        if (!in_range(k, v))
            return fail_key(ld, SEA_ERR_DOMAIN, line, id, "%.*s is out of range", SEA_QUOTE_MAX,
                            value);
        *(double *)(base + k->offset) = v * k->scale;
        return 1;
    }
    case KIND_INT: {
        if ((k->flags & AUTO) && strcmp(value, "auto") == 0) {
            *(int *)(base + k->offset) = 0;
            return 1;
        }
        char *end;
        errno = 0;
        long v = strtol(value, &end, 10);
        if (end == value || *end != '\0' || errno == ERANGE)
            return fail_key(ld, SEA_ERR_PARSE, line, id, "'%.*s' is not an integer",
                            SEA_QUOTE_MAX, value);
        if (v < k->lo || v > k->hi || ((k->flags & EVEN) && v % 2 != 0))
            return fail_key(ld, SEA_ERR_DOMAIN, line, id, "%ld is out of range", v);
        *(int *)(base + k->offset) = (int)v;
        return 1;
    }
    case KIND_SEED: {
        char *end;
        errno = 0;
        /* strtoul would accept "-1" as ULONG_MAX. */
        unsigned long long v = strtoull(value, &end, 10);
        if (!isdigit((unsigned char)value[0]) || *end != '\0' || errno == ERANGE)
            return fail_key(ld, SEA_ERR_PARSE, line, id, "'%.*s' is not an unsigned integer",
                            SEA_QUOTE_MAX, value);
        if (v > 4294967295ULL)
            return fail_key(ld, SEA_ERR_DOMAIN, line, id, "%llu is out of range", v);
        *(unsigned long *)(base + k->offset) = (unsigned long)v;
        return 1;
    }
    case KIND_CHOICE: {
        int v = k->from_name(value);
        if (v < 0)
            return fail_key(ld, SEA_ERR_PARSE, line, id, "unknown name '%.*s'", SEA_QUOTE_MAX,
                            value);
        *(int *)(base + k->offset) = v;
        return 1;
    }
    case KIND_WATER: {
        /* Anything that looks like a file name is a file, so that a
         * misspelt table name is reported as such. */
        if (strchr(value, '/') == NULL && strchr(value, '.') == NULL) {
            int t = sea_water_table_from_name(value);
            if (t < 0)
                return fail_key(ld, SEA_ERR_PARSE, line, id, "unknown table '%.*s'",
                                SEA_QUOTE_MAX, value);
            ld->sc.water_table = t;
            ld->sc.water_file[0] = '\0';
            return 1;
        }
        ld->sc.water_table = SEA_WATER_FILE;
        return resolve_path(ld, id, value, ld->sc.water_file);
    }
    case KIND_BAND: {
        char buf[256];
        snprintf(buf, sizeof buf, "%s", value);
        char *colon = strchr(buf, ':');
        double a, b;
        if (colon == NULL)
            return fail_key(ld, SEA_ERR_PARSE, line, id, "'%.*s' is not A:B", SEA_QUOTE_MAX,
                            value);
        *colon = '\0';
        if (sea_text_real(sea_text_trim(buf), &a) != 0 || sea_text_real(sea_text_trim(colon + 1), &b) != 0)
            return fail_key(ld, SEA_ERR_PARSE, line, id, "'%.*s' is not A:B (two numbers)",
                            SEA_QUOTE_MAX, value);
        if (!(a > 0.0 && a < b && isfinite(b)))
            return fail_key(ld, SEA_ERR_DOMAIN, line, id, "%.*s is out of range", SEA_QUOTE_MAX,
                            value);
        ld->sc.band_min = a * SEA_UM;
        ld->sc.band_max = b * SEA_UM;
        return 1;
    }
    case KIND_PATH:
        return resolve_path(ld, id, value, (char *)&ld->sc + k->offset);
    }
    return fail_key(ld, SEA_ERR_PARSE, line, id, "internal error: unknown kind");
}

static int on_key(void *user, const char *section, const char *name, const char *value)
{
    loader *ld = user;
    long line = ld->lineno;
    if (ld->status != SEA_OK)
        return 0;
    int sec = section_index(section);
    if (sec < 0) /* the reader has refused every unknown section */
        return fail_line(ld, SEA_ERR_PARSE, line,
                         "%.*s: key outside any section (allowed: after a [sea], [swell], "
                         "[sun], [sky], [atmosphere], [sensor] or [model] line)",
                         SEA_QUOTE_MAX, name);
    int id = -1;
    for (int i = 0; i < K_COUNT && id < 0; i++)
        if ((int)SEA_KEYS[i].section == sec && strcmp(SEA_KEYS[i].name, name) == 0)
            id = i;
    if (id < 0) {
        char keys[SEA_ERROR_MSG_MAX - 128]; /* every key of [sensor]: 244 characters */
        section_keys(sec, keys, sizeof keys);
        return fail_line(ld, SEA_ERR_PARSE, line, "[%s] %.*s: unknown key (allowed: %s)",
                         SEA_SECTIONS[sec], SEA_QUOTE_MAX, name, keys);
    }
    if (is_override_line(ld, ld->key_line[id]))
        return fail_line(ld, SEA_ERR_PARSE, line,
                         "[%s] %s: overridden twice, first by --set %.*s (allowed: once)",
                         SEA_SECTIONS[sec], name, SEA_QUOTE_MAX,
                         ld->overrides[ld->key_line[id] - SEA_OVERRIDE_LINE]);
    if (ld->key_line[id] != 0 && !is_override_line(ld, line))
        return fail_line(ld, SEA_ERR_PARSE, line,
                         "[%s] %s: duplicate key, first given on line %ld (allowed: once)",
                         SEA_SECTIONS[sec], name, ld->key_line[id]);
    ld->key_line[id] = line;
    if (value[0] == '\0')
        return fail_key(ld, SEA_ERR_PARSE, line, id, "empty value");
    return set_value(ld, id, value);
}

/* The text of line number `line` (1-based), cut for a message. */
static void quote_line(const char *text, long line, char *buf, size_t size)
{
    const char *p = text;
    for (long i = 1; i < line && p != NULL; i++)
        if ((p = strchr(p, '\n')) != NULL)
            p++;
    if (p == NULL)
        p = "";
    size_t n = strcspn(p, "\r\n");
    if (n > SEA_QUOTE_MAX)
        n = SEA_QUOTE_MAX;
    snprintf(buf, size, "%.*s", (int)n, p);
}

/* Two keys that exclude each other: the error names the later one. */
static void check_conflict(loader *ld, key_id a, key_id b, const char *rule)
{
    if (ld->key_line[a] == 0 || ld->key_line[b] == 0)
        return;
    key_id later = ld->key_line[a] > ld->key_line[b] ? a : b;
    key_id other = later == a ? b : a;
    char where[SEA_QUOTE_MAX + 32];
    const long ol = ld->key_line[other];
    if (is_override_line(ld, ol))
        snprintf(where, sizeof where, "--set %.*s", SEA_QUOTE_MAX,
                 ld->overrides[ol - SEA_OVERRIDE_LINE]);
    else
        snprintf(where, sizeof where, "line %ld", ol);
    fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[later],
              "[%s] %s: conflicts with %s on %s (allowed: %s)",
              SEA_SECTIONS[SEA_KEYS[later].section], SEA_KEYS[later].name,
              SEA_KEYS[other].name, where, rule);
}

static void check_required(loader *ld, key_id id)
{
    const key_spec *k = &SEA_KEYS[id];
    if (ld->key_line[id] != 0)
        return;
    long line = ld->section_line[k->section];
    if (line > 0)
        fail_key(ld, SEA_ERR_DOMAIN, line, id, "missing required key");
    else
        fail_key(ld, SEA_ERR_DOMAIN, 0, id, "missing required key (no [%s] section)",
                 SEA_SECTIONS[k->section]);
}

/* Key id, when given, needs one of the n keys `needs`, named by `keys`:
 * "[section] key: needs KEYS: WHY (allowed: with KEYS)" at its line. */
static void check_needs(loader *ld, key_id id, const key_id *needs, size_t n, const char *keys,
                        const char *why)
{
    if (ld->status != SEA_OK || ld->key_line[id] == 0)
        return;
    for (size_t i = 0; i < n; i++)
        if (ld->key_line[needs[i]] != 0)
            return;
    fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[id], "[%s] %s: needs %s: %s (allowed: with %s)",
              SEA_SECTIONS[SEA_KEYS[id].section], SEA_KEYS[id].name, keys, why, keys);
}

/* The camera's keys (seabake-model(7), THE CAMERA): one optics, and each
 * key that only qualifies another with it. */
static void check_camera(loader *ld)
{
    static const char OPTICS[] = "one optics: psf_sigma, f_number (with pitch) or mtf";
    check_conflict(ld, K_PSF_SIGMA, K_F_NUMBER, OPTICS);
    check_conflict(ld, K_PSF_SIGMA, K_MTF, OPTICS);
    check_conflict(ld, K_F_NUMBER, K_MTF, OPTICS);
    static const key_id F_NUMBER[] = { K_F_NUMBER }, PITCH[] = { K_PITCH }, NETD[] = { K_NETD },
                        FPN[] = { K_FPN_GAIN, K_FPN_OFFSET }, GAIN[] = { K_GAIN },
                        AT_T[] = { K_NETD, K_FPN_OFFSET, K_F_NUMBER };
    check_needs(ld, K_F_NUMBER, PITCH, 1, "pitch",
                "the diffraction cutoff, pitch / (wavelength f_number), is in cycles per pixel");
    check_needs(ld, K_PITCH, F_NUMBER, 1, "f_number", "pitch only scales the diffraction PSF");
    check_needs(ld, K_NOISE_SEED, NETD, 1, "netd", "it seeds the temporal noise");
    check_needs(ld, K_FPN_SEED, FPN, 2, "fpn_gain or fpn_offset", "it seeds their pattern");
    check_needs(ld, K_OFFSET, GAIN, 1, "gain", "counts = offset + gain radiance");
    check_needs(ld, K_BIT_DEPTH, GAIN, 1, "gain", "it bounds the counts");
    check_needs(ld, K_NETD_TEMPERATURE, AT_T, 3, "netd, fpn_offset or f_number",
                "they are stated (f_number: the band weighted) at this temperature");
}

/* Cross-key rules, once every key is read. */
static void check_scene(loader *ld)
{
    const sea_scene *sc = &ld->sc;
    finish_swell(ld);
    for (int i = 0; i < sc->n_swell; i++)
        if (isnan(sc->swell[i].sw.dir))
            ld->sc.swell[i].sw.dir = sc->wind_dir;
    static const char SUN_RULE[] =
        "irradiance alone, or any of temperature, solid_angle, transmittance";
    check_conflict(ld, K_SUN_IRRADIANCE, K_SUN_TEMPERATURE, SUN_RULE);
    check_conflict(ld, K_SUN_IRRADIANCE, K_SUN_SOLID_ANGLE, SUN_RULE);
    check_conflict(ld, K_SUN_IRRADIANCE, K_SUN_TRANSMITTANCE, SUN_RULE);
    check_conflict(ld, K_SUN_SOLID_ANGLE, K_SUN_ANGULAR_RADIUS,
                   "solid_angle or angular_radius, not both: each gives the other");
    if (ld->key_line[K_SUN_ANGULAR_RADIUS] == 0) /* the disc of the solid angle */
        ld->sc.sun_radius = acos(1.0 - sc->sun_solid_angle / (2.0 * M_PI));
    else if (ld->key_line[K_SUN_IRRADIANCE] == 0) /* the solid angle of the disc */
        ld->sc.sun_solid_angle = 2.0 * M_PI * (1.0 - cos(sc->sun_radius));
    check_conflict(ld, K_SKY_RADIANCE, K_SKY_TEMPERATURE, "radiance or temperature, not both");
    if (sc->sky_model != SEA_SKY_ISOTROPIC) { /* radiance, temperature: the isotropic sky's */
        const char *rule = sc->sky_model == SEA_SKY_CLEAR
                               ? "model = clear takes zenith_emissivity and the [atmosphere] "
                                 "air_temperature, not radiance or temperature"
                               : "model = table takes table, not radiance or temperature";
        check_conflict(ld, K_SKY_MODEL, K_SKY_RADIANCE, rule);
        check_conflict(ld, K_SKY_MODEL, K_SKY_TEMPERATURE, rule);
    }
    if (sc->sky_model == SEA_SKY_CLEAR) {
        if (ld->status == SEA_OK && ld->key_line[K_SKY_ZENITH_EMISSIVITY] == 0)
            fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_SKY_MODEL],
                      "[sky] model = clear: missing zenith_emissivity (allowed: (0, 1], the "
                      "sky's emissivity toward the zenith)");
        if (ld->status == SEA_OK && ld->key_line[K_AIR_TEMPERATURE] == 0)
            fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_SKY_MODEL],
                      "[sky] model = clear: missing [atmosphere] air_temperature (allowed: "
                      "(0, 400] K, the air the clear sky radiates at)");
    } else if (sc->sky_model == SEA_SKY_TABLE) {
        if (ld->status == SEA_OK && ld->key_line[K_SKY_TABLE] == 0)
            fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_SKY_MODEL],
                      "[sky] model = table: missing table (allowed: a CSV file "
                      "zenith_deg,wavelength_um,radiance)");
    }
    if (sc->sky_model != SEA_SKY_TABLE && ld->key_line[K_SKY_TABLE] != 0)
        fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_SKY_TABLE],
                  "[sky] table: needs model = table (allowed: with model = table only)");
    if (sc->sky_model != SEA_SKY_CLEAR && ld->key_line[K_SKY_ZENITH_EMISSIVITY] != 0) {
        fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_SKY_ZENITH_EMISSIVITY],
                  "[sky] zenith_emissivity: needs model = clear (allowed: with model = clear "
                  "only)");
    }
    check_conflict(ld, K_EXTINCTION, K_ATMOSPHERE_TABLE, "extinction or table, not both");
    if (ld->status == SEA_OK && ld->key_line[K_EXTINCTION] != 0 &&
        ld->key_line[K_AIR_TEMPERATURE] == 0)
        fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_EXTINCTION],
                  "[atmosphere] extinction: needs air_temperature (allowed: with air_temperature: "
                  "the path radiates (1 - transmittance) B(T_air))");
    check_conflict(ld, K_WAVELENGTH, K_BAND, "wavelength or band, not both");
    if (ld->key_line[K_N] != 0 && sc->method != SEA_METHOD_VARIABLE_STEP_2N)
        check_conflict(ld, K_N, K_METHOD, "n with method = variable-step-2n only");
    if (ld->key_line[K_BAND] == 0) {
        if (ld->key_line[K_RESPONSE] != 0)
            fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_RESPONSE],
                      "[sensor] response: needs a band (allowed: with band only)");
        if (ld->key_line[K_SAMPLES] != 0)
            fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_SAMPLES],
                      "[sensor] samples: needs a band (allowed: with band only)");
    }
    check_camera(ld);
    for (int i = 0; i < K_COUNT; i++)
        if (SEA_KEYS[i].flags & REQUIRED)
            check_required(ld, (key_id)i);
    if (ld->key_line[K_WAVELENGTH] == 0 && ld->key_line[K_BAND] == 0) {
        long line = ld->section_line[SEC_SENSOR];
        fail_line(ld, SEA_ERR_DOMAIN, line,
                  "[sensor] wavelength: missing: give wavelength or band "
                  "(allowed: wavelength in um, or band = A:B in um)");
    }
}

/* A computed bound (a table's end in um), to 15 digits: the rounding of
 * its conversion is not part of it. */
static const char *bound_text(double v, char *buf)
{
    snprintf(buf, SEA_TEXT_REAL_CHARS, "%.15g", v);
    return buf;
}

/* The wavelength or band against the water table, and the response curve. */
static void check_files(loader *ld)
{
    sea_scene *sc = &ld->sc;
    sea_water *w = NULL;
    sea_error e;
    sea_status st;
    if (ld->status != SEA_OK)
        return;
    if (sc->water_file[0] != '\0')
        st = sea_water_load(sc->water_file, sc->salinity, &w, &e);
    else
        st = sea_water_alloc(sc->water_table, sc->salinity, &w, &e);
    if (st != SEA_OK) {
        long line = ld->key_line[K_WATER] ? ld->key_line[K_WATER] : ld->key_line[K_SALINITY];
        fail_line(ld, st, line, "[sea] water: %s", e.msg);
        return;
    }
    double wl_min, wl_max;
    sea_water_range(w, &wl_min, &wl_max);
    key_id id = ld->key_line[K_BAND] != 0 ? K_BAND : K_WAVELENGTH;
    double lo = id == K_BAND ? sc->band_min : sc->wavelength;
    double hi = id == K_BAND ? sc->band_max : sc->wavelength;
    /* Values to as many digits as tell them from the bounds (a band
     * ending 1e-7 um past the table must not read as its end); the bounds,
     * converted from wavenumbers, to 15 digits, below their rounding. */
    char t_lo[SEA_TEXT_REAL_CHARS], t_hi[SEA_TEXT_REAL_CHARS];
    char w_lo[SEA_TEXT_REAL_CHARS], w_hi[SEA_TEXT_REAL_CHARS];
    if (lo < wl_min || hi > wl_max) {
        char given[2 * SEA_TEXT_REAL_CHARS + 1];
        if (id == K_BAND)
            snprintf(given, sizeof given, "%s:%s", sea_text_format_real(lo / SEA_UM, t_lo),
                     sea_text_format_real(hi / SEA_UM, t_hi));
        else
            snprintf(given, sizeof given, "%s", sea_text_format_real(lo / SEA_UM, t_lo));
        fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[id],
                  "[sensor] %s: %s um is outside the water table (allowed: %s-%s um, %s)",
                  SEA_KEYS[id].name, given, bound_text(wl_min / SEA_UM, w_lo),
                  bound_text(wl_max / SEA_UM, w_hi), sea_water_describe(w));
    }
    sea_water_free(w);
    if (ld->status != SEA_OK)
        return;
    /* the tables cover the wavelengths */
    const struct {
        key_id id;
        const char *file;
        sea_status (*load)(const char *, sea_grid **, sea_error *);
    } tables[] = { { K_SKY_TABLE, sc->sky_table_file, sea_sky_table_load },
                   { K_ATMOSPHERE_TABLE, sc->atmosphere_table_file, sea_atmosphere_table_load } };
    for (size_t t = 0; t < 2 && ld->status == SEA_OK; t++) {
        if (tables[t].file[0] == '\0')
            continue;
        sea_grid *g = NULL;
        const key_id tid = tables[t].id;
        const char *sec = SEA_SECTIONS[SEA_KEYS[tid].section];
        if ((st = tables[t].load(tables[t].file, &g, &e)) != SEA_OK) {
            fail_line(ld, st, ld->key_line[tid], "[%s] table: %s", sec, e.msg);
            return;
        }
        size_t nx;
        double x_max, w_min, w_max;
        sea_grid_axes(g, &nx, &x_max, &w_min, &w_max);
        sea_grid_free(g);
        if (lo < w_min || hi > w_max)
            fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[tid],
                      "[%s] table: %s covers %s-%s um, not the sensor's %s-%s um "
                      "(allowed: a table over the wavelength or band)",
                      sec, tables[t].file, bound_text(w_min / SEA_UM, w_lo),
                      bound_text(w_max / SEA_UM, w_hi),
                      sea_text_format_real(lo / SEA_UM, t_lo),
                      sea_text_format_real(hi / SEA_UM, t_hi));
    }
    /* the camera's MTF table */
    if (ld->status == SEA_OK && sc->mtf_file[0] != '\0') {
        sea_mtf_table t;
        if ((st = sea_imager_mtf_load(sc->mtf_file, &t, &e)) != SEA_OK)
            fail_line(ld, st, ld->key_line[K_MTF], "[sensor] mtf: %s", e.msg);
        else
            sea_imager_mtf_free(&t);
    }
    if (ld->status != SEA_OK || sc->response_file[0] == '\0')
        return;

    sea_response r;
    if ((st = sea_response_load(sc->response_file, &r, &e)) != SEA_OK) {
        fail_line(ld, st, ld->key_line[K_RESPONSE], "[sensor] response: %s", e.msg);
        return;
    }
    /* The curve is 0 outside its rows: it must be positive somewhere in the band. */
    int positive = 0;
    for (size_t i = 0; i + 1 < r.n && !positive; i++)
        positive = r.wavelength[i + 1] > sc->band_min && r.wavelength[i] < sc->band_max &&
                   (r.value[i] > 0.0 || r.value[i + 1] > 0.0);
    if (!positive)
        fail_line(ld, SEA_ERR_DOMAIN, ld->key_line[K_RESPONSE],
                  "[sensor] response: %s is zero over the band %.6g:%.6g um (allowed: a "
                  "curve that is positive somewhere in the band)",
                  sc->response_file, sc->band_min / SEA_UM, sc->band_max / SEA_UM);
    sea_response_free(&r);
}

void sea_scene_defaults(sea_scene *sc)
{
    memset(sc, 0, sizeof *sc);
    sc->wind_speed = NAN;
    sc->wind_dir = 0.0;
    sc->fetch = INFINITY;
    sc->temperature = 288.0;
    sc->salinity = 35.0;
    sc->water_table = SEA_WATER_HALE_QUERRY;
    sc->seed = 1;
    sc->time = 0.0;
    sc->loop_period = 0.0;
    sc->sun_zenith = 40.0 * SEA_DEG;
    sc->sun_azimuth = 180.0 * SEA_DEG;
    sc->sun_irradiance = -1.0;
    sc->sun_temperature = 5778.0;
    sc->sun_solid_angle = 6.8e-5;
    sc->sun_radius = acos(1.0 - 6.8e-5 / (2.0 * M_PI)); /* 0.2666 deg */
    sc->sun_transmittance = 1.0;
    sc->sky_radiance = -1.0;
    sc->sky_temperature = 250.0;
    sc->sensor_x = sc->sensor_y = 0.0;
    sc->altitude = NAN;
    sc->look_zenith = 0.0;
    sc->look_azimuth = 180.0 * SEA_DEG;
    sc->roll = 0.0;
    sc->polarizer = NAN;
    sc->hfov = NAN;
    sc->width = sc->height = 0;
    sc->wavelength = -1.0;
    sc->band_min = sc->band_max = -1.0;
    sc->band_samples = 0;
    sc->method = SEA_METHOD_VARIABLE_STEP;
    sc->n = 1;
    sc->finest = 1.0;
    sc->grid = SEA_GRID_AUTO;
    sc->emissivity_method = SEA_EMIS_AUTO;
    sc->earth = SEA_EARTH_FLAT;
    sc->windows = SEA_WINDOWS_VIEW;
    sc->tolerance = 1e-3;
    sc->reflections = SEA_REFLECTIONS_AUTO;
    sc->reference = 0;
    sc->shadowing = SEA_SHADOW_CORRELATED;
    sc->scales = 2;
    sc->sky_model = SEA_SKY_ISOTROPIC;
    sc->sky_zenith_emissivity = NAN;
    sc->air_temperature = NAN;
    sc->extinction = 0.0;
    /* the camera: absent */
    sc->psf_sigma = NAN;
    sc->f_number = NAN;
    sc->pitch = NAN;
    sc->mtf_file[0] = '\0';
    sc->fill_factor = NAN;
    sc->netd = NAN;
    sc->netd_temperature = 300.0;
    sc->noise_seed = 1;
    sc->fpn_gain = NAN;
    sc->fpn_offset = NAN;
    sc->fpn_seed = 1;
    sc->gain = NAN;
    sc->offset = NAN;
    sc->bit_depth = 14;
}

sea_status sea_scene_spectrum(const sea_scene *sc, sea_spectrum *s, sea_error *err)
{
    sea_status st = sea_spectrum_init(sc->wind_speed, sc->fetch, sc->wind_dir, s, err);
    for (int i = 0; i < sc->n_swell && st == SEA_OK; i++)
        st = sea_spectrum_add_swell(s, &sc->swell[i].sw, err);
    return st;
}

/* Applies the overrides "section.key=value" through the file's own key
 * handler, so that each is validated exactly as the same line in the file. */
/* Override "section.key" (no '='): the key as if the file had not given
 * it, its default back.  Returns 0 (an error recorded) or 1. */
static int unset_key(loader *ld, const char *section, const char *name)
{
    const long line = ld->lineno;
    const int sec = section_index(section);
    int id = -1;
    for (int i = 0; i < K_COUNT && id < 0; i++)
        if ((int)SEA_KEYS[i].section == sec && strcmp(SEA_KEYS[i].name, name) == 0)
            id = i;
    if (id < 0) {
        char keys[SEA_ERROR_MSG_MAX - 128];
        section_keys(sec, keys, sizeof keys);
        return fail_line(ld, SEA_ERR_PARSE, line, "[%s] %.*s: unknown key (allowed: %s)",
                         SEA_SECTIONS[sec], SEA_QUOTE_MAX, name, keys);
    }
    if (sec == SEC_SWELL)
        return fail_line(ld, SEA_ERR_PARSE, line,
                         "[swell] %s: a swell's keys cannot be removed one by one (allowed: "
                         "keys of the other sections)",
                         name);
    if (is_override_line(ld, ld->key_line[id]))
        return fail_line(ld, SEA_ERR_PARSE, line,
                         "[%s] %s: overridden twice, first by --set %.*s (allowed: once)",
                         SEA_SECTIONS[sec], name, SEA_QUOTE_MAX,
                         ld->overrides[ld->key_line[id] - SEA_OVERRIDE_LINE]);
    sea_scene d;
    sea_scene_defaults(&d);
    const key_spec *k = &SEA_KEYS[id];
    char *to = (char *)&ld->sc + k->offset;
    const char *from = (const char *)&d + k->offset;
    switch (k->kind) {
    case KIND_REAL:
        memcpy(to, from, sizeof(double));
        break;
    case KIND_INT:
    case KIND_CHOICE:
        memcpy(to, from, sizeof(int));
        break;
    case KIND_SEED:
        memcpy(to, from, sizeof(unsigned long));
        break;
    case KIND_WATER:
        ld->sc.water_table = d.water_table;
        memcpy(ld->sc.water_file, d.water_file, sizeof d.water_file);
        break;
    case KIND_BAND:
        ld->sc.band_min = d.band_min;
        ld->sc.band_max = d.band_max;
        break;
    case KIND_PATH:
        memcpy(to, from, SEA_SCENE_PATH_MAX);
        break;
    }
    /* absent: the checks of keys that exclude or need each other, and the
     * values derived from absent keys, see it so (a later --set of it sets
     * it again) */
    ld->key_line[id] = 0;
    return 1;
}

static void apply_overrides(loader *ld)
{
    for (size_t i = 0; i < ld->n_overrides && ld->status == SEA_OK; i++) {
        const char *o = ld->overrides[i];
        ld->lineno = SEA_OVERRIDE_LINE + (long)i;
        const char *dot = strchr(o, '.'), *eq = strchr(o, '=');
        if (eq == NULL && dot != NULL && dot != o && dot[1] != '\0') { /* section.key: unset */
            char section[32], key[64];
            const size_t ls = (size_t)(dot - o), lk = strlen(dot + 1);
            if (ls >= sizeof section || lk >= sizeof key) {
                fail_line(ld, SEA_ERR_PARSE, ld->lineno, "not SECTION.KEY (too long)");
                return;
            }
            snprintf(section, sizeof section, "%.*s", (int)ls, o);
            snprintf(key, sizeof key, "%s", dot + 1);
            if (section_index(sea_text_trim(section)) < 0) {
                fail_line(ld, SEA_ERR_PARSE, ld->lineno,
                          "[%.*s]: unknown section (allowed: " SEA_SECTION_LIST ")",
                          SEA_QUOTE_MAX, sea_text_trim(section));
                return;
            }
            unset_key(ld, sea_text_trim(section), sea_text_trim(key));
            continue;
        }
        if (dot == NULL || eq == NULL || dot > eq || dot == o || eq == dot + 1) {
            fail_line(ld, SEA_ERR_PARSE, ld->lineno,
                      "not SECTION.KEY=VALUE (allowed: e.g. sea.wind_speed=12)");
            return;
        }
        char section[32], key[64], value[SEA_SCENE_PATH_MAX];
        const size_t ls = (size_t)(dot - o), lk = (size_t)(eq - dot - 1), lv = strlen(eq + 1);
        if (ls >= sizeof section || lk >= sizeof key || lv >= sizeof value) {
            fail_line(ld, SEA_ERR_PARSE, ld->lineno, "too long (allowed: a value of at most %zu "
                      "characters)", sizeof value - 1);
            return;
        }
        snprintf(section, sizeof section, "%.*s", (int)ls, o);
        snprintf(key, sizeof key, "%.*s", (int)lk, dot + 1);
        snprintf(value, sizeof value, "%s", eq + 1);
        if (section_index(sea_text_trim(section)) < 0) {
            fail_line(ld, SEA_ERR_PARSE, ld->lineno,
                      "[%.*s]: unknown section (allowed: " SEA_SECTION_LIST ")",
                      SEA_QUOTE_MAX, sea_text_trim(section));
            return;
        }
        /* swell.KEY: the file's last [swell], or a new one */
        if (strcmp(sea_text_trim(section), "swell") == 0 && ld->sc.n_swell == 0 &&
            !begin_swell(ld, ld->lineno))
            return;
        on_key(ld, sea_text_trim(section), sea_text_trim(key), sea_text_trim(value));
    }
}

sea_status sea_scene_load(const char *path, sea_scene *sc, sea_error *err)
{
    return sea_scene_load_with(path, NULL, 0, sc, err);
}

sea_status sea_scene_load_with(const char *path, const char *const *overrides, size_t n_overrides,
                               sea_scene *sc, sea_error *err)
{
    char *text = NULL;
    sea_status st = sea_read_text(path, SEA_SCENE_BYTES_MAX, "text file", &text, err);
    if (st != SEA_OK)
        return st;
    loader *ld = calloc(1, sizeof *ld);
    if (ld == NULL) {
        free(text);
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
    }
    ld->path = path;
    ld->text = text;
    ld->len = strlen(text);
    ld->overrides = overrides;
    ld->n_overrides = n_overrides;
    sea_scene_defaults(&ld->sc);

    int r = ini_parse_stream(read_line, ld, on_key, ld);
    /* inih reports the first line it could not parse; our own errors come
     * from the handler or the reader.  The earlier one wins. */
    if (r > 0 && (ld->status == SEA_OK || r < ld->err_line)) {
        char quoted[SEA_QUOTE_MAX + 1];
        quote_line(text, r, quoted, sizeof quoted);
        ld->status = SEA_OK;
        fail_line(ld, SEA_ERR_PARSE, r,
                  "syntax error: '%s' (allowed: [section], key = value, or a comment starting "
                  "with ; or #)",
                  quoted);
    } else if (r < 0 && ld->status == SEA_OK) {
        fail_line(ld, r == -2 ? SEA_ERR_NOMEM : SEA_ERR_IO, 0, "cannot be parsed (inih %d)", r);
    }
    apply_overrides(ld);
    check_scene(ld);
    check_files(ld);
    ld->sc.tolerance_given = ld->key_line[K_TOLERANCE] != 0;

    st = ld->status;
    if (st == SEA_OK)
        *sc = ld->sc;
    else if (err != NULL)
        *err = ld->err;
    free(ld);
    free(text);
    return st;
}
