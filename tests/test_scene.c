/* test_scene.c - scene files (man/seabake-scene.5) and response curves.
 *
 * Fixtures: tests/scenes/ holds a complete scene; every error case is
 * written to a fresh temporary directory, so that relative paths and line
 * numbers are known exactly.  Conversions are checked for exact equality:
 * they are one multiplication each, the same one as below. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "unit.h"

#ifndef SEA_TOP_SRCDIR
#define SEA_TOP_SRCDIR "."
#endif

static char tmpdir[64];

static int scene_setup(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/seabake-scene-XXXXXX");
    return mkdtemp(tmpdir) == NULL;
}

static int scene_teardown(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    return system(cmd) != 0;
}

/* Writes text to tmpdir/name; returns the path in a static buffer. */
static const char *write_file(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "wb");
    CU_ASSERT_FATAL(f != NULL);
    CU_ASSERT(fwrite(text, 1, strlen(text), f) == strlen(text));
    fclose(f);
    return path;
}

static int contains(const char *msg, const char *needle)
{
    if (strstr(msg, needle) != NULL)
        return 1;
    fprintf(stderr, "\n  message '%s'\n  lacks   '%s'\n", msg, needle);
    return 0;
}

/* A valid scene, 8 lines; error cases append to it. */
#define BASE                                                                                   \
    "[sea]\n"                                                                                  \
    "wind_speed = 10\n"                                                                        \
    "[sensor]\n"                                                                               \
    "altitude = 500\n"                                                                         \
    "hfov = 30\n"                                                                              \
    "width = 64\n"                                                                             \
    "height = 48\n"                                                                            \
    "wavelength = 4\n"

static void test_full_file(void)
{
    sea_scene sc;
    sea_error err = { "" };
    const char *path = SEA_TOP_SRCDIR "/tests/scenes/full.ini";
    sea_status st = sea_scene_load(path, &sc, &err);
    if (st != SEA_OK)
        fprintf(stderr, "\n  %s\n", err.msg);
    CU_ASSERT_FATAL(st == SEA_OK);
    CU_ASSERT(sc.wind_speed == 12.5);
    CU_ASSERT(sc.wind_dir == 30 * (M_PI / 180.0));
    CU_ASSERT(sc.fetch == 250000.0);
    CU_ASSERT(sc.temperature == 290.5);
    CU_ASSERT(sc.salinity == 30.0);
    CU_ASSERT(sc.water_table == SEA_WATER_SEGELSTEIN);
    CU_ASSERT(sc.water_file[0] == '\0');
    CU_ASSERT(sc.seed == 4294967295UL);
    CU_ASSERT(sc.time == 12.25);
    CU_ASSERT(sc.loop_period == 60.0);
    CU_ASSERT(sc.sun_zenith == 60 * (M_PI / 180.0));
    CU_ASSERT(sc.sun_azimuth == -45 * (M_PI / 180.0));
    CU_ASSERT(sc.sun_irradiance < 0.0);
    CU_ASSERT(sc.sun_temperature == 5800.0);
    CU_ASSERT(sc.sun_solid_angle == 7e-5);
    CU_ASSERT(sc.sun_transmittance == 0.6);
    CU_ASSERT(sc.sky_radiance < 0.0);
    CU_ASSERT(sc.sky_temperature == 260.0);
    CU_ASSERT(sc.sensor_x == -120.5);
    CU_ASSERT(sc.sensor_y == 75.0);
    CU_ASSERT(sc.altitude == 1500.0);
    CU_ASSERT(sc.look_zenith == 36 * (M_PI / 180.0));
    CU_ASSERT(sc.look_azimuth == 90 * (M_PI / 180.0));
    CU_ASSERT(sc.roll == 2.5 * (M_PI / 180.0));
    CU_ASSERT(sc.hfov == 20 * (M_PI / 180.0));
    CU_ASSERT(sc.width == 640);
    CU_ASSERT(sc.height == 480);
    CU_ASSERT(sc.wavelength < 0.0);
    CU_ASSERT(sc.band_min == 3.5 * 1e-6);
    CU_ASSERT(sc.band_max == 4.5 * 1e-6);
    CU_ASSERT(strcmp(sc.response_file, SEA_TOP_SRCDIR "/tests/scenes/full_response.csv") == 0);
    CU_ASSERT(sc.band_samples == 33);
    CU_ASSERT(sc.method == SEA_METHOD_ONE_METER);
    CU_ASSERT(sc.finest == 0.5);
    CU_ASSERT(sc.grid == 512);
    CU_ASSERT(sc.emissivity_method == SEA_EMIS_FAST);
    CU_ASSERT(sc.earth == SEA_EARTH_SPHERICAL);
    CU_ASSERT(sc.windows == SEA_WINDOWS_CLIPMAP);
    CU_ASSERT(sc.tolerance == 1e-4 && sc.tolerance_given == 1);
    CU_ASSERT(sc.reflections == 2);
    CU_ASSERT(sc.f_number == 2.5);
    CU_ASSERT(sc.pitch == 15 * 1e-6);
    CU_ASSERT(isnan(sc.psf_sigma) && sc.mtf_file[0] == '\0');
    CU_ASSERT(sc.fill_factor == 0.8);
    CU_ASSERT(sc.netd == 0.025);
    CU_ASSERT(sc.netd_temperature == 295.0);
    CU_ASSERT(sc.noise_seed == 4000000000UL);
    CU_ASSERT(sc.fpn_gain == 0.002);
    CU_ASSERT(sc.fpn_offset == 0.03);
    CU_ASSERT(sc.fpn_seed == 12);
    CU_ASSERT(sc.gain == 1500.0);
    CU_ASSERT(sc.offset == -250.5);
    CU_ASSERT(sc.bit_depth == 16);
    /* ... which the camera takes as they are */
    sea_imager_params p;
    CU_ASSERT(sea_imager_params_from_scene(&sc, &p) == 1);
    CU_ASSERT(p.psf == SEA_PSF_DIFFRACTION && p.f_number == 2.5 && p.pitch == 15 * 1e-6);
    CU_ASSERT(p.fill_factor == 0.8 && p.netd == 0.025 && p.netd_temperature == 295.0);
    CU_ASSERT(p.noise_seed == 4000000000ULL && p.fpn_seed == 12);
    CU_ASSERT(p.fpn_gain == 0.002 && p.fpn_offset == 0.03);
    CU_ASSERT(p.gain == 1500.0 && p.offset == -250.5 && p.bit_depth == 16);
}

/* Spectral quantities: W m^-2 um^-1 -> W m^-2 m^-1 and per sr likewise. */
static void test_radiometric_units(void)
{
    sea_scene sc;
    sea_error err = { "" };
    const char *path = write_file("units.ini", BASE "[sun]\nirradiance = 9.5\n"
                                                    "[sky]\nradiance = 0.25\n"
                                                    "[sea]\nfetch = inf\n");
    CU_ASSERT_FATAL(sea_scene_load(path, &sc, &err) == SEA_OK);
    CU_ASSERT(sc.sun_irradiance == 9.5 * 1e6);
    CU_ASSERT(sc.sky_radiance == 0.25 * 1e6);
    CU_ASSERT(isinf(sc.fetch) && sc.fetch > 0);
    CU_ASSERT(sc.wavelength == 4 * 1e-6);
    CU_ASSERT(sc.band_min < 0.0 && sc.band_max < 0.0);
}

static void test_defaults(void)
{
    sea_scene sc, def;
    sea_error err = { "" };
    sea_scene_defaults(&def);
    CU_ASSERT(isnan(def.wind_speed) && isnan(def.altitude) && isnan(def.hfov));
    CU_ASSERT(def.width == 0 && def.height == 0 && def.wavelength < 0.0);
    const char *path = write_file("min.ini", BASE);
    CU_ASSERT_FATAL(sea_scene_load(path, &sc, &err) == SEA_OK);
    CU_ASSERT(sc.wind_speed == 10.0);
    CU_ASSERT(sc.altitude == 500.0);
    CU_ASSERT(sc.hfov == 30 * (M_PI / 180.0));
    CU_ASSERT(sc.width == 64 && sc.height == 48);
    CU_ASSERT(sc.wavelength == 4e-6);
    /* The documented defaults (seabake.h, seabake-scene(5)). */
    CU_ASSERT(sc.wind_dir == 0.0);
    CU_ASSERT(isinf(sc.fetch));
    CU_ASSERT(sc.temperature == 288.0);
    CU_ASSERT(sc.salinity == 35.0);
    CU_ASSERT(sc.water_table == SEA_WATER_HALE_QUERRY && sc.water_file[0] == '\0');
    CU_ASSERT(sc.seed == 1);
    CU_ASSERT(sc.time == 0.0 && sc.loop_period == 0.0);
    CU_ASSERT(sc.sun_zenith == 40 * (M_PI / 180.0));
    CU_ASSERT(sc.sun_azimuth == 180 * (M_PI / 180.0));
    CU_ASSERT(sc.sun_irradiance < 0.0);
    CU_ASSERT(sc.sun_temperature == 5778.0);
    CU_ASSERT(sc.sun_solid_angle == 6.8e-5);
    CU_ASSERT(sc.sun_transmittance == 1.0);
    CU_ASSERT(sc.sky_radiance < 0.0);
    CU_ASSERT(sc.sky_temperature == 250.0);
    CU_ASSERT(sc.sensor_x == 0.0 && sc.sensor_y == 0.0);
    CU_ASSERT(sc.look_zenith == 0.0);
    CU_ASSERT(sc.look_azimuth == 180 * (M_PI / 180.0));
    CU_ASSERT(sc.roll == 0.0);
    CU_ASSERT(sc.band_min < 0.0 && sc.response_file[0] == '\0' && sc.band_samples == 0);
    CU_ASSERT(sc.method == SEA_METHOD_VARIABLE_STEP && sc.n == 1);
    CU_ASSERT(sc.finest == 1.0 && sc.grid == SEA_GRID_AUTO);
    CU_ASSERT(sc.emissivity_method == SEA_EMIS_AUTO && sc.earth == SEA_EARTH_FLAT);
    CU_ASSERT(sc.windows == SEA_WINDOWS_VIEW);
    CU_ASSERT(sc.tolerance == 1e-3 && sc.tolerance_given == 0);
    CU_ASSERT(sc.reflections == SEA_REFLECTIONS_AUTO);
    CU_ASSERT(sc.reference == 0);
    /* no camera: every key absent, the image is the radiance alone */
    CU_ASSERT(isnan(sc.psf_sigma) && isnan(sc.f_number) && isnan(sc.pitch));
    CU_ASSERT(sc.mtf_file[0] == '\0' && isnan(sc.fill_factor) && isnan(sc.netd));
    CU_ASSERT(sc.netd_temperature == 300.0 && sc.noise_seed == 1 && sc.fpn_seed == 1);
    CU_ASSERT(isnan(sc.fpn_gain) && isnan(sc.fpn_offset) && isnan(sc.gain) && isnan(sc.offset));
    CU_ASSERT(sc.bit_depth == 14);
    sea_imager_params p;
    CU_ASSERT(sea_imager_params_from_scene(&sc, &p) == 0);
    /* Every optional field of the loaded scene is the default's. */
    def.wind_speed = sc.wind_speed;
    def.altitude = sc.altitude;
    def.hfov = sc.hfov;
    def.width = sc.width;
    def.height = sc.height;
    def.wavelength = sc.wavelength;
    CU_ASSERT(memcmp(&def, &sc, sizeof sc) == 0);
}

/* Comments after values with ';' or '#', CRLF line ends, a byte order mark,
 * indentation, "key: value" and blanks around '='. */
static void test_syntax_variants(void)
{
    sea_scene sc;
    sea_error err = { "" };
    const char *path = write_file("variants.ini",
                                  "\xEF\xBB\xBF; a comment\r\n"
                                  "[sea]\r\n"
                                  "  wind_speed=7.5 ; m/s\r\n"
                                  "\tseed: 42 # the sea\r\n"
                                  "# [sun] commented out\r\n"
                                  "[sensor]\r\n"
                                  "altitude   =   500   \r\n"
                                  "hfov = 30\r\nwidth = 64\r\nheight = 48\r\n"
                                  "band = 3.5 : 4.1\r\n"
                                  "[model]\r\nmethod = variable-step-2n\r\nn = 3\r\n");
    sea_status st = sea_scene_load(path, &sc, &err);
    if (st != SEA_OK)
        fprintf(stderr, "\n  %s\n", err.msg);
    CU_ASSERT_FATAL(st == SEA_OK);
    CU_ASSERT(sc.wind_speed == 7.5);
    CU_ASSERT(sc.seed == 42);
    CU_ASSERT(sc.sun_zenith == 40 * (M_PI / 180.0));
    CU_ASSERT(sc.altitude == 500.0);
    CU_ASSERT(sc.band_min == 3.5e-6 && sc.band_max == 4.1 * 1e-6);
    CU_ASSERT(sc.n == 3);
}

typedef struct {
    const char *text;
    sea_status status;
    long line;           /* 0: the message names the file without a line */
    const char *key;     /* "[section] key" as in the message */
    const char *allowed; /* a piece of the allowed range */
} error_case;

/* Message needles below were checked against the rules in seabake.h, not
 * copied from the output. */
static const error_case CASES[] = {
    /* syntax and names: SEA_ERR_PARSE */
    { BASE "[seas]\n", SEA_ERR_PARSE, 9, "[seas]: unknown section",
      "(allowed: sea, swell, sun, sky, atmosphere, sensor, model)" },
    /* swells */
    { BASE "[swell]\nheight = 2\n", SEA_ERR_DOMAIN, 9, "[swell] period: missing required key",
      "(allowed: [3, 30] s)" },
    { BASE "[swell]\nperiod = 9\n[swell]\ndouglas = 3\n", SEA_ERR_DOMAIN, 9,
      "[swell] height: missing required key", "(allowed: [0.01, 20] m)" },
    { BASE "[swell]\nheight = 25\n", SEA_ERR_DOMAIN, 10, "[swell] height: 25 is out of range",
      "(allowed: [0.01, 20] m)" },
    { BASE "[swell]\nheight = 2\nperiod = 2.5\n", SEA_ERR_DOMAIN, 11,
      "[swell] period: 2.5 is out of range", "(allowed: [3, 30] s)" },
    { BASE "[swell]\ndouglas = 9\n", SEA_ERR_DOMAIN, 10, "[swell] douglas: 9 is out of range",
      "(allowed: an integer in [1, 8])" },
    { BASE "[swell]\ndouglas = 2\nspread = 70\n", SEA_ERR_DOMAIN, 11,
      "[swell] spread: 70 is out of range", "(allowed: [1, 60] deg)" },
    { BASE "[swell]\ndouglas = 2\ngamma = 0.5\n", SEA_ERR_DOMAIN, 11,
      "[swell] gamma: 0.5 is out of range", "(allowed: [1, 10])" },
    { BASE "[swell]\ndouglas = 2\ndouglas = 3\n", SEA_ERR_PARSE, 11,
      "[swell] douglas: duplicate key", "first given on line 10" },
    { BASE "[swell]\ndouglas = 1\n[swell]\ndouglas = 2\n[swell]\ndouglas = 3\n"
           "[swell]\ndouglas = 4\n[swell]\ndouglas = 5\n",
      SEA_ERR_DOMAIN, 17, "[swell]: too many swells", "(allowed: at most 4 [swell] sections)" },
    { BASE "[sun]\nzenit = 40\n", SEA_ERR_PARSE, 10, "[sun] zenit: unknown key",
      "(allowed: zenith, azimuth, irradiance, temperature, solid_angle, transmittance, "
      "angular_radius)" },
    { BASE "altitude = 600\n", SEA_ERR_PARSE, 9, "[sensor] altitude: duplicate key",
      "first given on line 4" },
    { "wind_speed = 10\n" BASE, SEA_ERR_PARSE, 1, "wind_speed: key outside any section",
      "after a [sea]" },
    { BASE "wind_speed 10\n", SEA_ERR_PARSE, 9, "syntax error: 'wind_speed 10'",
      "(allowed: [section], key = value" },
    { BASE "[sky\n", SEA_ERR_PARSE, 9, "syntax error: '[sky'", "(allowed: [section]" },
    { BASE "[model]\nfinest = 1m\n", SEA_ERR_PARSE, 10, "[model] finest: '1m' is not a number",
      "(allowed: [0.001, 1000] m)" },
    { BASE "x = nan\n", SEA_ERR_PARSE, 9, "[sensor] x: 'nan' is not a number",
      "(allowed: [-10000000, 10000000] m)" },
    { BASE "y = -1e20\n", SEA_ERR_DOMAIN, 9, "[sensor] y: -1e20 is out of range",
      "(allowed: [-10000000, 10000000] m)" },
    { BASE "roll =\n", SEA_ERR_PARSE, 9, "[sensor] roll: empty value",
      "(allowed: any finite value in deg)" },
    { BASE "samples = 12.5\n", SEA_ERR_PARSE, 9, "[sensor] samples: '12.5' is not an integer",
      "(allowed: an integer in [1, 4096])" },
    { BASE "[sea]\nseed = -1\n", SEA_ERR_PARSE, 10, "[sea] seed: '-1' is not an unsigned",
      "(allowed: an integer in [0, 4294967295])" },
    { BASE "[model]\nmethod = variable\n", SEA_ERR_PARSE, 10,
      "[model] method: unknown name 'variable'",
      "(allowed: variable-step, variable-step-2n, one-meter)" },
    { BASE "[model]\nemissivity = slow\n", SEA_ERR_PARSE, 10, "[model] emissivity",
      "(allowed: auto, fast, full)" },
    { BASE "[model]\nearth = round\n", SEA_ERR_PARSE, 10, "[model] earth",
      "(allowed: flat, spherical)" },
    { BASE "[model]\nwindows = nested\n", SEA_ERR_PARSE, 10,
      "[model] windows: unknown name 'nested'", "(allowed: view, clipmap)" },
    { BASE "[sea]\nwater = hale-query\n", SEA_ERR_PARSE, 10,
      "[sea] water: unknown table 'hale-query'", "(allowed: hale-querry, segelstein, or" },
    { "[sensor]\nband = 3-5\n", SEA_ERR_PARSE, 2, "[sensor] band: '3-5' is not A:B",
      "(allowed: A:B in um with 0 < A < B)" },
    /* ranges: SEA_ERR_DOMAIN */
    { "[sea]\nwind_speed = 50\n[sensor]\n", SEA_ERR_DOMAIN, 2,
      "[sea] wind_speed: 50 is out of range", "(allowed: [0.5, 40] m/s)" },
    { BASE "[sea]\ntemperature = 350\n", SEA_ERR_DOMAIN, 10,
      "[sea] temperature: 350 is out of range", "(allowed: [271, 313] K)" },
    { BASE "[sea]\nfetch = 999\n", SEA_ERR_DOMAIN, 10, "[sea] fetch: 999 is out of range",
      "(allowed: [1000, inf] m)" },
    { BASE "[sea]\nsalinity = 46\n", SEA_ERR_DOMAIN, 10, "[sea] salinity",
      "(allowed: [0, 45] g/kg)" },
    { BASE "[sea]\nloop_period = -1\n", SEA_ERR_DOMAIN, 10, "[sea] loop_period",
      "(allowed: [0, inf) s)" },
    { BASE "[sea]\nseed = 4294967296\n", SEA_ERR_DOMAIN, 10, "[sea] seed: 4294967296 is out",
      "[0, 4294967295]" },
    { BASE "[sun]\nzenith = 181\n", SEA_ERR_DOMAIN, 10, "[sun] zenith: 181 is out of range",
      "(allowed: [0, 180] deg)" },
    { BASE "[sun]\nirradiance = -1\n", SEA_ERR_DOMAIN, 10, "[sun] irradiance",
      "(allowed: [0, 100000] W m^-2 um^-1)" },
    { BASE "[sun]\ntemperature = 0\n", SEA_ERR_DOMAIN, 10, "[sun] temperature",
      "(allowed: (0, 10000] K)" },
    { BASE "[sun]\nsolid_angle = 0.1\n", SEA_ERR_DOMAIN, 10, "[sun] solid_angle",
      "(allowed: (0, 0.01] sr)" },
    { BASE "[sun]\ntransmittance = 1.5\n", SEA_ERR_DOMAIN, 10, "[sun] transmittance",
      "(allowed: [0, 1])" },
    { BASE "[sky]\nradiance = 2000\n", SEA_ERR_DOMAIN, 10, "[sky] radiance",
      "(allowed: [0, 1000] W m^-2 sr^-1 um^-1)" },
    { BASE "[sky]\ntemperature = 500\n", SEA_ERR_DOMAIN, 10, "[sky] temperature",
      "(allowed: (0, 400] K)" },
    { "[sensor]\naltitude = inf\n", SEA_ERR_DOMAIN, 2, "[sensor] altitude: inf is out of range",
      "(allowed: (0, 1000000] m)" },
    { BASE "look_zenith = 90\n", SEA_ERR_DOMAIN, 9, "[sensor] look_zenith: 90 is out",
      "(allowed: [0, 90) deg)" },
    { "[sensor]\nhfov = 0\n", SEA_ERR_DOMAIN, 2, "[sensor] hfov: 0 is out of range",
      "(allowed: [1e-06, 170] deg)" },
    { "[sensor]\nwidth = 0\n", SEA_ERR_DOMAIN, 2, "[sensor] width: 0 is out of range",
      "(allowed: an integer in [1, 16384] pixels)" },
    { "[sensor]\nwavelength = -4\n", SEA_ERR_DOMAIN, 2, "[sensor] wavelength",
      "(allowed: (0, inf) um)" },
    { "[sensor]\nband = 5:3\n", SEA_ERR_DOMAIN, 2, "[sensor] band: 5:3 is out of range",
      "0 < A < B" },
    { BASE "[model]\nn = 21\n", SEA_ERR_DOMAIN, 10, "[model] n: 21 is out of range",
      "(allowed: an integer in [0, 20])" },
    { BASE "[model]\ngrid = 255\n", SEA_ERR_DOMAIN, 10, "[model] grid: 255 is out of range",
      "(allowed: auto or an even integer in [16, 4096] facets)" },
    { BASE "[model]\ntolerance = 0\n", SEA_ERR_DOMAIN, 10, "[model] tolerance",
      "(allowed: (0, 0.1])" },
    { BASE "[sky]\nmodel = clear\n[atmosphere]\nair_temperature = 288\n", SEA_ERR_DOMAIN, 10,
      "[sky] model = clear: missing zenith_emissivity", "(0, 1]" },
    { BASE "[sky]\nmodel = clear\nzenith_emissivity = 0.7\n", SEA_ERR_DOMAIN, 10,
      "[sky] model = clear: missing [atmosphere] air_temperature", "(0, 400] K" },
    { BASE "[sky]\ntemperature = 250\nmodel = clear\nzenith_emissivity = 0.7\n[atmosphere]\n"
      "air_temperature = 288\n", SEA_ERR_DOMAIN, 11, "[sky] model: conflicts with temperature",
      "model = clear takes zenith_emissivity" },
    { BASE "[sky]\nzenith_emissivity = 0.7\n", SEA_ERR_DOMAIN, 10,
      "[sky] zenith_emissivity: needs model = clear", "with model = clear only" },
    { BASE "[sky]\nmodel = clear\nzenith_emissivity = 0\n", SEA_ERR_DOMAIN, 11,
      "[sky] zenith_emissivity", "(0, 1]" },
    { BASE "[sky]\nmodel = cloudy\n", SEA_ERR_PARSE, 10, "[sky] model", "isotropic, clear" },
    { BASE "[atmosphere]\nextinction = 0.1\n", SEA_ERR_DOMAIN, 10,
      "[atmosphere] extinction: needs air_temperature", "with air_temperature" },
    { BASE "[atmosphere]\nair_temperature = 288\nextinction = -1\n", SEA_ERR_DOMAIN, 11,
      "[atmosphere] extinction", "[0, 1000] 1/km" },
    { BASE "[sky]\nmodel = table\n", SEA_ERR_DOMAIN, 10, "[sky] model = table: missing table",
      "zenith_deg,wavelength_um,radiance" },
    { BASE "[sky]\ntable = sky.csv\n", SEA_ERR_DOMAIN, 10, "[sky] table: needs model = table",
      "with model = table only" },
    { BASE "[atmosphere]\nair_temperature = 288\nextinction = 0.1\ntable = a.csv\n",
      SEA_ERR_DOMAIN, 12, "[atmosphere] table: conflicts with extinction",
      "extinction or table, not both" },
    { BASE "[sky]\nmodel = table\ntable = nowhere.csv\n", SEA_ERR_IO, 11, "[sky] table: ",
      "/nowhere.csv: cannot open" },
    { BASE "[sun]\nsolid_angle = 1e-4\nangular_radius = 0.3\n", SEA_ERR_DOMAIN, 11,
      "[sun] angular_radius: conflicts with solid_angle", "each gives the other" },
    { BASE "[sun]\nangular_radius = 6\n", SEA_ERR_DOMAIN, 10, "[sun] angular_radius",
      "[0, 5] deg" },
    { BASE "[model]\nreflections = 4\n", SEA_ERR_PARSE, 10, "[model] reflections", "auto, 1, 2, 3" },
    { BASE "[model]\nreflections = 2.5\n", SEA_ERR_PARSE, 10, "[model] reflections", "auto, 1, 2, 3" },
    { BASE "[model]\nfinest = 1001\n", SEA_ERR_DOMAIN, 10, "[model] finest", "[0.001, 1000] m" },
    /* a denormal is a number (strtod's underflow), refused by the range;
     * one beyond double range is out of range too */
    { BASE "[model]\nfinest = 4.9e-324\n", SEA_ERR_DOMAIN, 10, "[model] finest", "[0.001, 1000] m" },
    { BASE "[model]\nfinest = 1e-4\n", SEA_ERR_DOMAIN, 10, "[model] finest", "[0.001, 1000] m" },
    { BASE "[model]\nfinest = 1e400\n", SEA_ERR_DOMAIN, 10, "[model] finest: 1e400 is out of range",
      "[0.001, 1000] m" },
    /* missing keys: the section's line, or no line without the section */
    { "[sea]\n[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\nheight = 48\nwavelength = 4\n",
      SEA_ERR_DOMAIN, 1, "[sea] wind_speed: missing required key", "(allowed: [0.5, 40] m/s)" },
    { "[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\nheight = 48\nwavelength = 4\n",
      SEA_ERR_DOMAIN, 0, "[sea] wind_speed: missing required key (no [sea] section)",
      "(allowed: [0.5, 40] m/s)" },
    { "[sea]\nwind_speed = 10\n", SEA_ERR_DOMAIN, 0,
      "[sensor] altitude: missing required key (no [sensor] section)",
      "(allowed: (0, 1000000] m)" },
    { "[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nwidth = 64\nheight = 48\n"
      "wavelength = 4\n",
      SEA_ERR_DOMAIN, 3, "[sensor] hfov: missing required key", "(allowed: [1e-06, 170] deg)" },
    { "[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\nheight = 48\n"
      "wavelength = 4\n",
      SEA_ERR_DOMAIN, 3, "[sensor] width: missing required key", "[1, 16384] pixels" },
    { "[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\n"
      "wavelength = 4\n",
      SEA_ERR_DOMAIN, 3, "[sensor] height: missing required key", "[1, 16384] pixels" },
    { "[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\nheight = 48\n",
      SEA_ERR_DOMAIN, 3, "[sensor] wavelength: missing: give wavelength or band",
      "(allowed: wavelength in um, or band = A:B in um)" },
    /* conflicts: the later key, naming the earlier one's line */
    { BASE "band = 3:5\n", SEA_ERR_DOMAIN, 9, "[sensor] band: conflicts with wavelength on line 8",
      "(allowed: wavelength or band, not both)" },
    { BASE "[sun]\nirradiance = 10\ntransmittance = 0.5\n", SEA_ERR_DOMAIN, 11,
      "[sun] transmittance: conflicts with irradiance on line 10",
      "(allowed: irradiance alone, or any of temperature, solid_angle, transmittance)" },
    { BASE "[sun]\ntemperature = 5000\nirradiance = 10\n", SEA_ERR_DOMAIN, 11,
      "[sun] irradiance: conflicts with temperature on line 10", "(allowed: irradiance alone" },
    { BASE "[sun]\nsolid_angle = 1e-4\nirradiance = 10\n", SEA_ERR_DOMAIN, 11,
      "[sun] irradiance: conflicts with solid_angle on line 10", "(allowed: irradiance alone" },
    { BASE "[sky]\ntemperature = 250\nradiance = 0.2\n", SEA_ERR_DOMAIN, 11,
      "[sky] radiance: conflicts with temperature on line 10",
      "(allowed: radiance or temperature, not both)" },
    { BASE "[model]\nn = 2\nmethod = variable-step\n", SEA_ERR_DOMAIN, 11,
      "[model] method: conflicts with n on line 10",
      "(allowed: n with method = variable-step-2n only)" },
    { BASE "response = r.csv\n", SEA_ERR_DOMAIN, 9, "[sensor] response: needs a band",
      "(allowed: with band only)" },
    { BASE "samples = 8\n", SEA_ERR_DOMAIN, 9, "[sensor] samples: needs a band",
      "(allowed: with band only)" },
    /* against the water table (Hale & Querry with salinity 35: 2.4-15.5 um) */
    { "[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\n"
      "height = 48\nwavelength = 1.5\n",
      SEA_ERR_DOMAIN, 8, "[sensor] wavelength: 1.5 um is outside the water table",
      "(allowed: 2.4-15.5 um, Hale & Querry" },
    { "[sea]\nwind_speed = 10\nwater = segelstein\nsalinity = 0\n[sensor]\naltitude = 500\n"
      "hfov = 30\nwidth = 64\nheight = 48\nband = 3:16\n",
      SEA_ERR_DOMAIN, 10, "[sensor] band: 3:16 um is outside the water table",
      "(allowed: 2.4099054-15.595525 um, Segelstein" },
    /* unreadable files named in the scene: SEA_ERR_IO, the resolved path */
    { BASE "[sea]\nwater = nowhere.csv\n", SEA_ERR_IO, 10, "[sea] water: ",
      "/nowhere.csv: cannot open" },
    { "[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\nheight = 48\n"
      "band = 3:5\nresponse = sub/missing.csv\n",
      SEA_ERR_IO, 9, "[sensor] response: ", "/sub/missing.csv: cannot open" },
    /* the camera: its keys are [sensor]'s */
    { BASE "psf = 1\n", SEA_ERR_PARSE, 9, "[sensor] psf: unknown key",
      "samples, psf_sigma, f_number, pitch, mtf, fill_factor, netd, netd_temperature, "
      "noise_seed, fpn_gain, fpn_offset, fpn_seed, gain, offset, bit_depth)" },
    /* the camera: ranges */
    { BASE "psf_sigma = 0\n", SEA_ERR_DOMAIN, 9, "[sensor] psf_sigma: 0 is out of range",
      "(allowed: (0, 64] pixels)" },
    { BASE "psf_sigma = 65\n", SEA_ERR_DOMAIN, 9, "[sensor] psf_sigma: 65 is out of range",
      "(allowed: (0, 64] pixels)" },
    { BASE "f_number = 0.3\npitch = 15\n", SEA_ERR_DOMAIN, 9,
      "[sensor] f_number: 0.3 is out of range", "(allowed: [0.5, 100])" },
    { BASE "f_number = 2\npitch = 0.05\n", SEA_ERR_DOMAIN, 10,
      "[sensor] pitch: 0.05 is out of range", "(allowed: [0.1, 1000] um)" },
    { BASE "fill_factor = 1.2\n", SEA_ERR_DOMAIN, 9, "[sensor] fill_factor: 1.2 is out",
      "(allowed: (0, 1])" },
    { BASE "netd = 0\n", SEA_ERR_DOMAIN, 9, "[sensor] netd: 0 is out of range",
      "(allowed: (0, 10] K)" },
    { BASE "netd = 0.05\nnetd_temperature = 600\n", SEA_ERR_DOMAIN, 10,
      "[sensor] netd_temperature: 600 is out of range", "(allowed: [150, 500] K)" },
    { BASE "netd = 0.05\nnoise_seed = -3\n", SEA_ERR_PARSE, 10,
      "[sensor] noise_seed: '-3' is not an unsigned", "(allowed: an integer in [0, 4294967295])" },
    { BASE "fpn_gain = 0.5\n", SEA_ERR_DOMAIN, 9, "[sensor] fpn_gain: 0.5 is out of range",
      "(allowed: [0, 0.1])" },
    { BASE "fpn_offset = 20\n", SEA_ERR_DOMAIN, 9, "[sensor] fpn_offset: 20 is out of range",
      "(allowed: [0, 10] K)" },
    { BASE "gain = 0\n", SEA_ERR_DOMAIN, 9, "[sensor] gain: 0 is out of range",
      "(allowed: (0, 1e+12] counts per radiance unit)" },
    { BASE "gain = 100\noffset = 2e9\n", SEA_ERR_DOMAIN, 10, "[sensor] offset: 2e9 is out of",
      "(allowed: [-1000000000, 1000000000] counts)" },
    { BASE "gain = 100\nbit_depth = 20\n", SEA_ERR_DOMAIN, 10,
      "[sensor] bit_depth: 20 is out of range", "(allowed: an integer in [8, 16] bits)" },
    { BASE "gain = 100\nbit_depth = 12.5\n", SEA_ERR_PARSE, 10,
      "[sensor] bit_depth: '12.5' is not an integer", "(allowed: an integer in [8, 16] bits)" },
    /* the camera: one optics, and each key with the key it qualifies */
    { BASE "psf_sigma = 1.5\nf_number = 2\npitch = 15\n", SEA_ERR_DOMAIN, 10,
      "[sensor] f_number: conflicts with psf_sigma on line 9",
      "(allowed: one optics: psf_sigma, f_number (with pitch) or mtf)" },
    { BASE "mtf = m.csv\npsf_sigma = 1.5\n", SEA_ERR_DOMAIN, 10,
      "[sensor] psf_sigma: conflicts with mtf on line 9", "(allowed: one optics" },
    { BASE "f_number = 2\npitch = 15\nmtf = m.csv\n", SEA_ERR_DOMAIN, 11,
      "[sensor] mtf: conflicts with f_number on line 9", "(allowed: one optics" },
    { BASE "f_number = 2\n", SEA_ERR_DOMAIN, 9, "[sensor] f_number: needs pitch",
      "(allowed: with pitch)" },
    { BASE "pitch = 15\n", SEA_ERR_DOMAIN, 9, "[sensor] pitch: needs f_number",
      "(allowed: with f_number)" },
    { BASE "psf_sigma = 1\npitch = 15\n", SEA_ERR_DOMAIN, 10, "[sensor] pitch: needs f_number",
      "(allowed: with f_number)" },
    { BASE "noise_seed = 3\n", SEA_ERR_DOMAIN, 9, "[sensor] noise_seed: needs netd",
      "(allowed: with netd)" },
    { BASE "netd = 0.05\nfpn_seed = 3\n", SEA_ERR_DOMAIN, 10,
      "[sensor] fpn_seed: needs fpn_gain or fpn_offset", "(allowed: with fpn_gain or fpn_offset)" },
    { BASE "offset = 10\n", SEA_ERR_DOMAIN, 9, "[sensor] offset: needs gain",
      "(allowed: with gain)" },
    { BASE "bit_depth = 12\n", SEA_ERR_DOMAIN, 9, "[sensor] bit_depth: needs gain",
      "(allowed: with gain)" },
    { BASE "netd_temperature = 290\n", SEA_ERR_DOMAIN, 9,
      "[sensor] netd_temperature: needs netd, fpn_offset or f_number",
      "(allowed: with netd, fpn_offset or f_number)" },
    /* the camera's MTF file: read at load, its errors at their own line */
    { BASE "mtf = none.csv\n", SEA_ERR_IO, 9, "[sensor] mtf: ", "/none.csv: cannot open" },
};

static void check_error(const char *text, sea_status want, long line, const char *key,
                        const char *allowed, int print)
{
    sea_scene sc;
    sea_error err = { "" };
    memset(&sc, 0x5a, sizeof sc);
    const char *path = write_file("s.ini", text);
    sea_status st = sea_scene_load(path, &sc, &err);
    if (st != want)
        fprintf(stderr, "\n  status %s, expected %s: %s\n", sea_status_name(st),
                sea_status_name(want), err.msg);
    CU_ASSERT(st == want);
    char where[300];
    if (line > 0)
        snprintf(where, sizeof where, "%s:%ld: ", path, line);
    else
        snprintf(where, sizeof where, "%s: ", path);
    /* the place comes first, then the key, then the rule */
    CU_ASSERT(strncmp(err.msg, where, strlen(where)) == 0 || !contains(err.msg, where));
    CU_ASSERT(contains(err.msg, key));
    CU_ASSERT(contains(err.msg, allowed));
    CU_ASSERT(strstr(err.msg, key) < strstr(err.msg, allowed) || !strstr(err.msg, allowed));
    /* sc is written only on success */
    unsigned char untouched[sizeof sc];
    memset(untouched, 0x5a, sizeof untouched);
    CU_ASSERT(memcmp(&sc, untouched, sizeof sc) == 0);
    if (print)
        MEASURED("scene error: %s\n", err.msg);
}

static void test_errors(void)
{
    for (size_t i = 0; i < sizeof CASES / sizeof CASES[0]; i++) {
        const error_case *c = &CASES[i];
        /* three of them are printed for the record */
        int print = strstr(c->key, "zenit:") || strstr(c->key, "temperature: 350") ||
                    strstr(c->key, "transmittance: conflicts");
        check_error(c->text, c->status, c->line, c->key, c->allowed, print);
    }
}

static void test_long_line(void)
{
    /* The Debian build of inih reads lines of at most 200 bytes with the
     * newline and the NUL. */
    char text[600], key[64];
    snprintf(text, sizeof text, BASE "[sea]\nwater = ./%0250d.csv\n", 0);
    snprintf(key, sizeof key, "line too long: %zu characters",
             strlen("water = ./.csv") + 250);
    check_error(text, SEA_ERR_PARSE, 10, key, "(allowed: at most 198)", 0);
    /* 198 characters are accepted (the file then does not exist). */
    snprintf(text, sizeof text, BASE "[sea]\nwater = ./%0184d.csv\n", 0);
    CU_ASSERT(strlen(strrchr(text, 'w')) == 198 + 1);
    check_error(text, SEA_ERR_IO, 10, "[sea] water: ", ".csv: cannot open", 0);
}

static void test_missing_scene(void)
{
    sea_scene sc;
    sea_error err = { "" };
    char path[300];
    snprintf(path, sizeof path, "%s/absent.ini", tmpdir);
    CU_ASSERT(sea_scene_load(path, &sc, &err) == SEA_ERR_IO);
    CU_ASSERT(contains(err.msg, path));
    CU_ASSERT(sea_scene_load(tmpdir, &sc, &err) == SEA_ERR_IO); /* a directory */
    CU_ASSERT(contains(err.msg, "not a regular file"));
    CU_ASSERT(sea_scene_load(path, &sc, NULL) == SEA_ERR_IO);   /* err may be NULL */
}

/* Relative paths are taken from the scene file's directory, absolute ones
 * are kept, and the stored path is the one that was read. */
static void test_relative_paths(void)
{
    char sub[128], text[1024], abs_resp[300];
    snprintf(sub, sizeof sub, "%s/data", tmpdir);
    CU_ASSERT_FATAL(mkdir(sub, 0700) == 0);
    write_file("data/nk.csv", "wavelength_um,n,k\n3.0,1.40,0.01\n5.0,1.30,0.02\n");
    write_file("data/resp.csv", "wavelength_um,response\n3.5,1\n4.5,1\n");
    const char *path = write_file("rel.ini", "[sea]\nwind_speed = 10\nwater = data/nk.csv\n"
                                             "salinity = 0\n[sensor]\naltitude = 500\n"
                                             "hfov = 30\nwidth = 64\nheight = 48\n"
                                             "band = 3.6:4.4\nresponse = data/resp.csv\n");
    char scene[300];
    snprintf(scene, sizeof scene, "%s", path);
    sea_scene sc;
    sea_error err = { "" };
    sea_status st = sea_scene_load(scene, &sc, &err);
    if (st != SEA_OK)
        fprintf(stderr, "\n  %s\n", err.msg);
    CU_ASSERT_FATAL(st == SEA_OK);
    char want[300];
    snprintf(want, sizeof want, "%s/data/nk.csv", tmpdir);
    CU_ASSERT(strcmp(sc.water_file, want) == 0);
    CU_ASSERT(sc.water_table == SEA_WATER_FILE);
    snprintf(want, sizeof want, "%s/data/resp.csv", tmpdir);
    CU_ASSERT(strcmp(sc.response_file, want) == 0);

    /* The user table is the one used: 5.2 um is outside it. */
    snprintf(text, sizeof text, "[sea]\nwind_speed = 10\nwater = data/nk.csv\nsalinity = 0\n"
                                "[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\nheight = 48\n"
                                "wavelength = 5.2\n");
    check_error(text, SEA_ERR_DOMAIN, 10, "[sensor] wavelength: 5.2 um", "(allowed: 3-5 um", 0);

    /* An absolute path is kept as it is. */
    snprintf(abs_resp, sizeof abs_resp, "%s/data/resp.csv", tmpdir);
    snprintf(text, sizeof text, "[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\n"
                                "width = 64\nheight = 48\nband = 3.6:4.4\nresponse = %s\n",
             abs_resp);
    path = write_file("data/abs.ini", text);
    snprintf(scene, sizeof scene, "%s", path);
    CU_ASSERT_FATAL(sea_scene_load(scene, &sc, &err) == SEA_OK);
    CU_ASSERT(strcmp(sc.response_file, abs_resp) == 0);

    /* A response that is zero over the band is refused at load. */
    write_file("data/far.csv", "wavelength_um,response\n8,1\n9,1\n");
    check_error("[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\n"
                "height = 48\nband = 3.6:4.4\nresponse = data/far.csv\n",
                SEA_ERR_DOMAIN, 9, "[sensor] response: ", "is zero over the band 3.6:4.4 um", 0);
    /* Errors inside the response file keep its own place. */
    write_file("data/bad.csv", "wavelength_um,response\n3.5,1\n3.4,1\n");
    snprintf(want, sizeof want, "%s/data/bad.csv:3: wavelength_um", tmpdir);
    check_error("[sea]\nwind_speed = 10\n[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\n"
                "height = 48\nband = 3.6:4.4\nresponse = data/bad.csv\n",
                SEA_ERR_PARSE, 9, "[sensor] response: ", want, 0);
    /* ... and so do errors inside the camera's MTF table, resolved as the
     * response is. */
    write_file("data/mtf.csv", "cycles_per_pixel,mtf\n0,1\n0.5,0.4\n0.8,0.1\n");
    path = write_file("mtf.ini", BASE "mtf = data/mtf.csv\n");
    snprintf(scene, sizeof scene, "%s", path);
    CU_ASSERT_FATAL(sea_scene_load(scene, &sc, &err) == SEA_OK);
    snprintf(want, sizeof want, "%s/data/mtf.csv", tmpdir);
    CU_ASSERT(strcmp(sc.mtf_file, want) == 0);
    write_file("data/badmtf.csv", "cycles_per_pixel,mtf\n0,1\n0.5,1.5\n");
    snprintf(want, sizeof want, "%s/data/badmtf.csv:3: mtf: 1.5 is outside [0, 1]", tmpdir);
    check_error(BASE "mtf = data/badmtf.csv\n", SEA_ERR_DOMAIN, 9, "[sensor] mtf: ", want, 0);
    /* ... and so do errors inside the water table. */
    write_file("data/badnk.csv", "wavelength_um,n\n3.0,1.40\n5.0,1.30\n");
    snprintf(want, sizeof want, "%s/data/badnk.csv:1: header", tmpdir);
    check_error(BASE "[sea]\nwater = data/badnk.csv\n", SEA_ERR_PARSE, 10, "[sea] water: ", want,
                0);
}

static void test_response_load(void)
{
    sea_response r;
    sea_error err = { "" };
    const char *path = write_file("resp.csv", "# a filter\n\nresponse, wavelength_um\n"
                                              "0.0, 3.7\n0.5,3.9\n1.0 ,4.1\n0,4.3\n");
    CU_ASSERT_FATAL(sea_response_load(path, &r, &err) == SEA_OK);
    CU_ASSERT(r.n == 4);
    CU_ASSERT(r.wavelength[0] == 3.7 * 1e-6 && r.wavelength[3] == 4.3 * 1e-6);
    CU_ASSERT(r.value[1] == 0.5 && r.value[2] == 1.0 && r.value[3] == 0.0);
    sea_response_free(&r);
    CU_ASSERT(r.n == 0 && r.wavelength == NULL && r.value == NULL);
    sea_response_free(&r);  /* twice is harmless */
    sea_response_free(NULL);

    static const struct {
        const char *text;
        sea_status status;
        const char *where;  /* after the path */
        const char *needle;
    } bad[] = {
        { "lambda,response\n3,1\n4,1\n", SEA_ERR_PARSE, ":1: ", "wavelength_um,response" },
        { "wavelength_um,response,extra\n3,1,0\n", SEA_ERR_PARSE, ":1: ", "two" },
        { "# c\nwavelength_um,response\n3,1\n4\n", SEA_ERR_PARSE, ":4: ", "two" },
        { "wavelength_um,response\n3,1\nx,1\n", SEA_ERR_PARSE, ":3: ", "wavelength_um: 'x'" },
        { "wavelength_um,response\n3,1\n-4,1\n", SEA_ERR_PARSE, ":3: ", "positive" },
        { "wavelength_um,response\n3,1\n4,inf\n", SEA_ERR_PARSE, ":3: ", "response: 'inf'" },
        { "wavelength_um,response\n3,1\n4,-0.1\n", SEA_ERR_DOMAIN, ":3: ", "-0.1 is outside [0, 1000000]" },
        { "wavelength_um,response\n3,1\n4,1e300\n", SEA_ERR_DOMAIN, ":3: ", "1e+300 is outside [0, 1000000]" },
        { "wavelength_um,response\n3,1\n4e7,1\n", SEA_ERR_DOMAIN, ":3: ", "40000000 is outside (0, 1000]" },
        /* positive in micrometres, but 0 (or subnormal) in metres */
        { "wavelength_um,response\n1e-320,1\n4,1\n", SEA_ERR_DOMAIN, ":2: ",
          "1e-320 is outside (0, 1000]" },
        { "wavelength_um,response\n3,1\n4,1\n4,1\n", SEA_ERR_PARSE, ":4: ", "does not increase" },
        { "wavelength_um,response\n3,1\n", SEA_ERR_PARSE, ": ", "at least two rows (found 1)" },
        { "# only comments\n", SEA_ERR_PARSE, ": ", "no header" },
        { "wavelength_um,response\n3,0\n4,0\n", SEA_ERR_DOMAIN, ": ", "zero everywhere" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char where[300];
        memset(&r, 0x5a, sizeof r);
        path = write_file("bad.csv", bad[i].text);
        snprintf(where, sizeof where, "%s%s", path, bad[i].where);
        CU_ASSERT(sea_response_load(path, &r, &err) == bad[i].status);
        CU_ASSERT(r.n == 0 && r.wavelength == NULL && r.value == NULL);
        CU_ASSERT(strncmp(err.msg, where, strlen(where)) == 0 || !contains(err.msg, where));
        CU_ASSERT(contains(err.msg, bad[i].needle));
    }
    char absent[300];
    snprintf(absent, sizeof absent, "%s/absent.csv", tmpdir);
    CU_ASSERT(sea_response_load(absent, &r, &err) == SEA_ERR_IO);
    CU_ASSERT(contains(err.msg, absent));
}

/* The complete example of seabake-scene(5) loads as the paper's Fig. 8. */
/* --set: each override is validated as the same key in the file, replaces
 * the file's value, and errors name the override rather than a line. */
static void test_overrides(void)
{
    char path[300]; /* write_file's buffer is reused below */
    snprintf(path, sizeof path, "%s", write_file("over.ini", BASE));
    sea_scene sc;
    sea_error err = { "" };
    const char *ok[] = { "sea.wind_speed=12.5", "sensor.width = 32", "model.tolerance=1e-2",
                         "sky.temperature=250" };
    CU_ASSERT_FATAL(sea_scene_load_with(path, ok, 4, &sc, &err) == SEA_OK);
    CU_ASSERT(sc.wind_speed == 12.5 && sc.width == 32 && sc.height == 48);
    CU_ASSERT(sc.tolerance == 1e-2 && sc.sky_temperature == 250.0);
    CU_ASSERT(sc.tolerance_given == 1); /* by an override */
    /* a required key may come from an override alone */
    const char *nofile = write_file("over_missing.ini", "[sea]\n[sensor]\naltitude = 500\n"
                                    "hfov = 30\nwidth = 64\nheight = 48\nwavelength = 4\n");
    const char *wind[] = { "sea.wind_speed=7" };
    CU_ASSERT(sea_scene_load_with(nofile, wind, 1, &sc, &err) == SEA_OK && sc.wind_speed == 7.0);
    static const struct {
        const char *set;
        sea_status status;
        const char *needle;
    } bad[] = {
        { "sea.wind_speed=abc", SEA_ERR_PARSE,
          "--set sea.wind_speed=abc: [sea] wind_speed: 'abc' is not a number (allowed:" },
        { "sea.wind_speed=1e9", SEA_ERR_DOMAIN, "--set sea.wind_speed=1e9: [sea] wind_speed:" },
        { "sea.wind=3", SEA_ERR_PARSE, "--set sea.wind=3: [sea] wind: unknown key (allowed:" },
        { "ocean.wind_speed=3", SEA_ERR_PARSE, "--set ocean.wind_speed=3: [ocean]: unknown section" },
        { "wind_speed=3", SEA_ERR_PARSE, "--set wind_speed=3: not SECTION.KEY=VALUE" },
        /* no "=": removes the key, and wind_speed is required */
        { "sea.wind_speed", SEA_ERR_DOMAIN, "[sea] wind_speed: missing required key" },
        { "sea.wind_speed=", SEA_ERR_PARSE, "--set sea.wind_speed=: [sea] wind_speed: empty value" },
        { "sensor.band=3.5:4.5", SEA_ERR_DOMAIN,
          "--set sensor.band=3.5:4.5: [sensor] band: conflicts with wavelength on line 8" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const char *one[] = { bad[i].set };
        CU_ASSERT(sea_scene_load_with(path, one, 1, &sc, &err) == bad[i].status);
        CU_ASSERT(contains(err.msg, bad[i].needle));
    }
    const char *twice[] = { "sea.wind_speed=3", "sea.wind_speed=4" };
    CU_ASSERT(sea_scene_load_with(path, twice, 2, &sc, &err) == SEA_ERR_PARSE);
    CU_ASSERT(contains(err.msg, "--set sea.wind_speed=4: [sea] wind_speed: overridden twice, "
                                "first by --set sea.wind_speed=3"));
}

/* [swell] sections: several, each complete, the Douglas code filling what
 * is not given, the direction the wind's unless given; --set swell.KEY
 * reaches the last one (or makes one). */
/* An override "section.key" removes the file's key: its default back,
 * before or after a --set of a key it excludes; not a swell's key. */
static void test_unset(void)
{
    const char *path = SEA_TOP_SRCDIR "/examples/midwave.ini";
    sea_scene sc, d;
    sea_error err;
    sea_scene_defaults(&d);
    const char *a[] = { "sensor.wavelength=4", "sensor.band" };
    CU_ASSERT_EQUAL_FATAL(sea_scene_load_with(path, a, 2, &sc, &err), SEA_OK);
    ASSERT_ABS(sc.wavelength, 4e-6, 1e-18);
    CU_ASSERT(sc.band_min == d.band_min && sc.band_max == d.band_max);
    const char *b[] = { "sea.wind_direction" };
    CU_ASSERT_EQUAL_FATAL(sea_scene_load_with(path, b, 1, &sc, &err), SEA_OK);
    CU_ASSERT(sc.wind_dir == d.wind_dir);
    const char *c[] = { "sensor.band" }; /* no wavelength left: as a file without */
    sea_scene bare;
    sea_error e2;
    const sea_status sb = sea_scene_load_with(path, c, 1, &bare, &e2);
    if (sb == SEA_OK)
        CU_ASSERT(bare.band_min == d.band_min && bare.wavelength == d.wavelength);
    const char *w[] = { "swell.height=2", "swell.period=10", "swell.spread" };
    CU_ASSERT_EQUAL(sea_scene_load_with(path, w, 3, &sc, &err), SEA_ERR_PARSE);
    CU_ASSERT(strstr(err.msg, "--unset swell.spread: [swell] spread") != NULL);
    const char *u[] = { "sensor.nokey" };
    CU_ASSERT_EQUAL(sea_scene_load_with(path, u, 1, &sc, &err), SEA_ERR_PARSE);
    CU_ASSERT(strstr(err.msg, "--unset sensor.nokey: [sensor] nokey: unknown key") != NULL);
}

static void test_swells(void)
{
    char path[300];
    snprintf(path, sizeof path, "%s",
             write_file("swell.ini", "[sea]\nwind_speed = 10\nwind_direction = 30\n"
                                     "[swell]\nheight = 2.5\nperiod = 11\ndirection = -90\n"
                                     "spread = 10\ngamma = 5\n"
                                     "[sensor]\naltitude = 500\nhfov = 30\nwidth = 64\n"
                                     "height = 48\nwavelength = 4\n"
                                     "[swell]\ndouglas = 7\nperiod = 13\n"));
    sea_scene sc;
    sea_error err = { "" };
    sea_status st = sea_scene_load(path, &sc, &err);
    if (st != SEA_OK)
        fprintf(stderr, "\n  %s\n", err.msg);
    CU_ASSERT_FATAL(st == SEA_OK);
    CU_ASSERT_FATAL(sc.n_swell == 2);
    CU_ASSERT(sc.swell[0].sw.hs == 2.5 && sc.swell[0].sw.tp == 11.0);
    ASSERT_ABS(sc.swell[0].sw.dir, -90.0 * DEG, 1e-15);
    ASSERT_ABS(sc.swell[0].sw.spread, 10.0 * DEG, 1e-15);
    CU_ASSERT(sc.swell[0].sw.gamma == 5.0 && sc.swell[0].douglas == 0);
    /* Douglas 7: heavy (5 m), average (150 m) -- the period given wins */
    CU_ASSERT(sc.swell[1].douglas == 7 && sc.swell[1].sw.hs == 5.0 && sc.swell[1].sw.tp == 13.0);
    ASSERT_ABS(sc.swell[1].sw.dir, 30.0 * DEG, 1e-15); /* the wind's */
    ASSERT_ABS(sc.swell[1].sw.spread, 15.0 * DEG, 1e-15);
    CU_ASSERT(sc.swell[1].sw.gamma == 3.3);
    /* the scene's sea carries both */
    sea_spectrum sp;
    CU_ASSERT_FATAL(sea_scene_spectrum(&sc, &sp, &err) == SEA_OK);
    CU_ASSERT(sp.n_swell == 2 && sp.swell[1].hs == 5.0 && sp.wind_speed == 10.0);
    /* an override reaches the last [swell] */
    const char *set[] = { "swell.height=1.5" };
    CU_ASSERT_FATAL(sea_scene_load_with(path, set, 1, &sc, &err) == SEA_OK);
    CU_ASSERT(sc.n_swell == 2 && sc.swell[0].sw.hs == 2.5 && sc.swell[1].sw.hs == 1.5);
    /* ... or makes one in a scene without */
    snprintf(path, sizeof path, "%s", write_file("noswell.ini", BASE));
    CU_ASSERT_FATAL(sea_scene_load(path, &sc, &err) == SEA_OK);
    CU_ASSERT(sc.n_swell == 0);
    const char *make[] = { "swell.height=1", "swell.period=8" };
    CU_ASSERT_FATAL(sea_scene_load_with(path, make, 2, &sc, &err) == SEA_OK);
    CU_ASSERT(sc.n_swell == 1 && sc.swell[0].sw.hs == 1.0 && sc.swell[0].sw.tp == 8.0);
    const char *half[] = { "swell.height=1" };
    CU_ASSERT(sea_scene_load_with(path, half, 1, &sc, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(contains(err.msg, "[swell] period: missing required key"));
}

static void test_manual_example(void)
{
    const char *man = SEA_TOP_SRCDIR "/man/seabake-scene.5";
    FILE *f = fopen(man, "r");
    CU_ASSERT_FATAL(f != NULL);
    char line[512], text[8192] = "";
    size_t used = 0;
    int in_example = 0, done = 0;
    while (!done && fgets(line, sizeof line, f) != NULL) {
        if (strncmp(line, ".EX", 3) == 0) {
            in_example = 1;
            used = 0;
            text[0] = '\0';
            continue;
        }
        if (strncmp(line, ".EE", 3) == 0) {
            done = in_example && strstr(text, "\n[sea]\n") != NULL;
            in_example = 0;
            continue;
        }
        if (!in_example)
            continue;
        /* undo the roff escapes the manual uses: \- \e \(dq \& */
        for (const char *p = line; *p != '\0' && used + 1 < sizeof text; p++) {
            if (p[0] == '\\' && p[1] == '-') {
                text[used++] = '-';
                p++;
            } else if (p[0] == '\\' && p[1] == 'e') {
                text[used++] = '\\';
                p++;
            } else if (p[0] == '\\' && p[1] == '&') {
                p++;
            } else if (strncmp(p, "\\(dq", 4) == 0) {
                text[used++] = '"';
                p += 3;
            } else {
                text[used++] = *p;
            }
        }
        text[used] = '\0';
    }
    fclose(f);
    CU_ASSERT_FATAL(done);
    const char *path = write_file("fig8.ini", text);
    sea_scene sc;
    sea_error err = { "" };
    sea_status st = sea_scene_load(path, &sc, &err);
    if (st != SEA_OK)
        fprintf(stderr, "\n  %s\n", err.msg);
    CU_ASSERT_FATAL(st == SEA_OK);
    CU_ASSERT(sc.wind_speed == 15.0);
    CU_ASSERT(sc.temperature == 288.0);
    CU_ASSERT(sc.altitude == 500.0);
    CU_ASSERT(sc.look_zenith == 36 * (M_PI / 180.0));
    CU_ASSERT(sc.sun_zenith == 40 * (M_PI / 180.0));
    /* sun opposite the sensor: the camera looks toward the sun's azimuth */
    CU_ASSERT(fabs(remainder(sc.sun_azimuth - sc.look_azimuth, 2 * M_PI)) < 1e-12);
    CU_ASSERT(sc.wavelength == 4e-6);
    CU_ASSERT(sc.width == 500 && sc.height == 500);
}

int test_scene_register(void)
{
    CU_pSuite s = CU_add_suite("scene", scene_setup, scene_teardown);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "full file, every key converted", test_full_file) ||
           !CU_add_test(s, "spectral radiometric units", test_radiometric_units) ||
           !CU_add_test(s, "defaults", test_defaults) ||
           !CU_add_test(s, "comments, CRLF, BOM, indentation", test_syntax_variants) ||
           !CU_add_test(s, "every error names FILE:LINE, key and range", test_errors) ||
           !CU_add_test(s, "line longer than inih accepts", test_long_line) ||
           !CU_add_test(s, "unreadable scene file", test_missing_scene) ||
           !CU_add_test(s, "relative paths and referenced files", test_relative_paths) ||
           !CU_add_test(s, "response curves and their errors", test_response_load) ||
           !CU_add_test(s, "overrides (--set)", test_overrides) ||
           !CU_add_test(s, "swells", test_swells) ||
           !CU_add_test(s, "unset", test_unset) ||
           !CU_add_test(s, "manual example (Fig. 8)", test_manual_example);
}
