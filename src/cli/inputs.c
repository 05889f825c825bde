/* inputs.c - what the physics subcommands (spectrum, emissivity, energy,
 * reflectivity) share: options that exclude each other, --emissivity, the
 * water's complex index, the sea state and the facet's slope statistics,
 * the direction grid, and the CSV columns of the sea.  A value that is not
 * finite is never printed: the command stops with SEA_ERR_NUMERIC. */
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* ------------------------------------------------------------ constants */

static const double SEA_CLI_M_PER_UM = 1e-6;
/* Mean slopes beyond 5 (79 degrees of tilt) are not a sea surface. */
#define SEA_CLI_MEAN_MAX 5.0
/* Slope variances beyond 10 are far outside any wind-roughened sea
 * (Cox & Munk give about 0.05 at 10 m/s). */
#define SEA_CLI_VAR_MAX 10.0
/* Relative slack on SXY^2 <= SXX*SYY, as in sea_slope_stats_check, so that
 * a covariance typed with exact decimals is not refused for rounding. */
static const double SEA_CLI_COV_REL_TOL = 1e-12;
static const double SEA_CLI_SALINITY_DEFAULT = 35.0;

static const sea_cli_range SEA_CLI_RANGE_WAVELENGTH = {0.0, INFINITY, true, true, "um"};
static const sea_cli_range SEA_CLI_RANGE_THETA = {-90.0, 90.0, true, true, "degrees"};
static const sea_cli_range SEA_CLI_RANGE_SALINITY = {
    0.0, SEA_SALINITY_MAX, false, false, "g/kg"};
static const sea_cli_range SEA_CLI_RANGE_MEAN[2] = {
    {-SEA_CLI_MEAN_MAX, SEA_CLI_MEAN_MAX, false, false, ""},
    {-SEA_CLI_MEAN_MAX, SEA_CLI_MEAN_MAX, false, false, ""}};
static const sea_cli_range SEA_CLI_RANGE_COV[3] = {
    {0.0, SEA_CLI_VAR_MAX, false, false, ""},
    {0.0, SEA_CLI_VAR_MAX, false, false, ""},
    {-SEA_CLI_VAR_MAX, SEA_CLI_VAR_MAX, false, false, ""}};
/* The library's bounds on a water index (those of a user water table):
 * n in [1, 3], k in [0, 10]. */
static const sea_cli_range SEA_CLI_RANGE_INDEX[2] = {
    {SEA_WATER_N_MIN, SEA_WATER_N_MAX, false, false, ""},
    {0.0, SEA_WATER_K_MAX, false, false, ""}};

/* ------------------------------------------------------- option helpers */

/* Refuses name2 when name1 was given. */
sea_status sea_cli_exclusive(const sea_cli_args *args, const char *name1, const char *name2,
                             sea_error *err)
{
    if (sea_cli_given(args, name1) && sea_cli_given(args, name2))
        return sea_fail(err, SEA_ERR_DOMAIN, "--%s cannot be combined with --%s", name2, name1);
    return SEA_OK;
}

sea_status sea_cli_opt_emissivity(const sea_cli_args *args, sea_emis_method *out, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "emissivity");
    int m = sea_emis_method_from_name(text ? text : "auto");
    if (m < 0)
        return sea_fail(err, SEA_ERR_PARSE, "--emissivity: '%s' is not one of auto, fast, full",
                        text);
    *out = (sea_emis_method)m;
    return SEA_OK;
}

sea_status sea_cli_opt_shadowing(const sea_cli_args *args, sea_shadowing def, sea_shadowing *out,
                                 sea_error *err)
{
    const char *text = sea_cli_args_get(args, "shadowing");
    if (text == NULL) {
        *out = def;
        return SEA_OK;
    }
    int s = sea_shadowing_from_name(text);
    if (s < 0)
        return sea_fail(err, SEA_ERR_PARSE, "--shadowing: '%s' is not one of smith, correlated",
                        text);
    *out = (sea_shadowing)s;
    return SEA_OK;
}

/* ---------------------------------------------------------- sea inputs */

static sea_status water_index(const sea_cli_args *args, sea_cli_sea *sea, sea_error *err)
{
    sea_status st = sea_cli_require(args, "wavelength", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wavelength", &SEA_CLI_RANGE_WAVELENGTH, 0.0,
                                &sea->wavelength_um, err);
    if (st != SEA_OK)
        return st;

    const char *index = sea_cli_args_get(args, "index");
    if (index) {
        /* The index replaces the table; the wavelength is then only a label. */
        double nk[2];
        if ((st = sea_cli_exclusive(args, "index", "water", err)) != SEA_OK ||
            (st = sea_cli_exclusive(args, "index", "salinity", err)) != SEA_OK ||
            (st = sea_cli_parse_tuple("--index", index, 2, SEA_CLI_RANGE_INDEX, "N,K", nk, err)) !=
                SEA_OK)
            return st;
        sea->N = nk[0] + I * nk[1];
        return SEA_OK;
    }

    double salinity;
    st = sea_cli_opt_number(args, "salinity", &SEA_CLI_RANGE_SALINITY, SEA_CLI_SALINITY_DEFAULT,
                            &salinity, err);
    if (st != SEA_OK)
        return st;
    const char *name = sea_cli_args_get(args, "water");
    if (!name)
        name = "hale-querry";
    if (name[0] == '\0')
        return sea_fail(err, SEA_ERR_PARSE, "--water: empty table name");

    sea_water *water = NULL;
    sea_error lib = {{0}};
    int table = sea_water_table_from_name(name);
    st = table >= 0 ? sea_water_alloc((sea_water_table)table, salinity, &water, &lib)
                    : sea_water_load(name, salinity, &water, &lib);
    if (st != SEA_OK) {
        sea_water_free(water);
        return sea_fail(err, st, "--water: %s", lib.msg);
    }
    st = sea_water_index(water, sea->wavelength_um * SEA_CLI_M_PER_UM, &sea->N, &lib);
    sea_water_free(water);
    if (st != SEA_OK)
        return sea_fail(err, st, "--wavelength: %s", lib.msg);
    if (!isfinite(creal(sea->N)) || !isfinite(cimag(sea->N)))
        return sea_fail(err, SEA_ERR_NUMERIC,
                        "--water: the refractive index at %g um is not finite", sea->wavelength_um);
    return SEA_OK;
}

sea_status sea_cli_water(const sea_cli_args *args, double *wavelength_um, double complex *N,
                         sea_error *err)
{
    sea_cli_sea sea;
    sea_status st = water_index(args, &sea, err);
    if (st != SEA_OK)
        return st;
    *wavelength_um = sea.wavelength_um;
    *N = sea.N;
    return SEA_OK;
}

/* Sea state from --wind, --fetch, --wind-dir (--wind must be given: the
 * callers require it with their own message). */
sea_status sea_cli_sea_state(const sea_cli_args *args, sea_spectrum *spec, double *wind,
                             double *fetch, sea_error *err)
{
    double wind_dir_deg;
    sea_status st = sea_cli_opt_sea_state(args, wind, fetch, &wind_dir_deg, err);
    if (st != SEA_OK)
        return st;
    return sea_spectrum_init(*wind, *fetch, sea_cli_radians(wind_dir_deg), spec, err);
}

/* Covariance of the waves shorter than a facet of size L (0: all waves). */
sea_status sea_cli_facet_cov(const sea_spectrum *spec, double facet, double *kc, sea_cov2 *cov,
                             sea_error *err)
{
    *kc = facet > 0.0 ? M_PI / facet : 0.0;
    if (!isfinite(*kc))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--facet: %g m is too small (its cutoff wavenumber pi/L is not finite)",
                        facet);
    sea_error lib = {{0}};
    sea_status st = sea_spectrum_slope_cov(spec, *kc, cov, &lib);
    if (st != SEA_OK)
        return sea_fail(err, st, "slope covariance for --facet %g: %s", facet, lib.msg);
    if (!isfinite(cov->xx) || !isfinite(cov->yy) || !isfinite(cov->xy))
        return sea_fail(err, SEA_ERR_NUMERIC, "slope covariance for --facet %g is not finite",
                        facet);
    return SEA_OK;
}

static sea_status slope_stats(const sea_cli_args *args, sea_slope_stats *stats, sea_error *err)
{
    double mean[2] = {0.0, 0.0};
    const char *text = sea_cli_args_get(args, "mean");
    sea_status st = SEA_OK;
    if (text)
        st = sea_cli_parse_tuple("--mean", text, 2, SEA_CLI_RANGE_MEAN, "MX,MY", mean, err);
    if (st != SEA_OK)
        return st;
    stats->mean = (sea_vec2){mean[0], mean[1]};

    text = sea_cli_args_get(args, "cov");
    if (text) {
        static const char *const spectral[] = {"facet", "wind", "fetch", "wind-dir"};
        for (size_t i = 0; i < sizeof spectral / sizeof spectral[0]; ++i)
            if ((st = sea_cli_exclusive(args, "cov", spectral[i], err)) != SEA_OK)
                return st;
        double c[3];
        st = sea_cli_parse_tuple("--cov", text, 3, SEA_CLI_RANGE_COV, "SXX,SYY,SXY", c, err);
        if (st != SEA_OK)
            return st;
        if (c[2] * c[2] > c[0] * c[1] * (1.0 + SEA_CLI_COV_REL_TOL))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "--cov: SXY = %g is outside [-%g, %g] (SXY^2 <= SXX*SYY)", c[2],
                            sqrt(c[0] * c[1]), sqrt(c[0] * c[1]));
        stats->cov = (sea_cov2){c[0], c[1], c[2]};
    } else {
        sea_spectrum spec;
        double wind, fetch, facet, kc;
        if ((st = sea_cli_require(args, "wind", " (or give the slope covariance with --cov)",
                                  err)) != SEA_OK ||
            (st = sea_cli_sea_state(args, &spec, &wind, &fetch, err)) != SEA_OK ||
            (st = sea_cli_opt_number(args, "facet", &SEA_CLI_RANGE_FACET, 0.0, &facet, err)) !=
                SEA_OK ||
            (st = sea_cli_facet_cov(&spec, facet, &kc, &stats->cov, err)) != SEA_OK)
            return st;
    }
    return sea_slope_stats_check(stats, err);
}

/* Parses every input of an optics subcommand; the water table is read last
 * so that a typing mistake is reported before any file is opened. */
sea_status sea_cli_sea_inputs(const sea_cli_args *args, sea_cli_sea *sea, sea_error *err)
{
    sea_status st = slope_stats(args, &sea->stats, err);
    if (st != SEA_OK)
        return st;
    return water_index(args, sea, err);
}

void sea_cli_print_sea_columns(FILE *out, const sea_cli_sea *sea)
{
    const sea_slope_stats *s = &sea->stats;
    fprintf(out, "%.10g,%.10g,%.10g,%.10g,%.10g", s->mean.x, s->mean.y, s->cov.xx, s->cov.yy,
            s->cov.xy);
}

sea_status sea_cli_not_finite(const char *what, double theta_deg, double phi_deg, sea_error *err)
{
    return sea_fail(err, SEA_ERR_NUMERIC,
                    "%s at theta = %g, phi = %g degrees is not finite; nothing printed for it",
                    what, theta_deg, phi_deg);
}

/* --theta (required) and --phi (default 0) as lists. */
sea_status sea_cli_direction_grid(const sea_cli_args *args, sea_cli_list *theta,
                                  sea_cli_list *phi, sea_error *err)
{
    sea_status st = sea_cli_require(args, "theta", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_list(args, "theta", &SEA_CLI_RANGE_THETA, NULL, theta, err);
    if (st == SEA_OK)
        st = sea_cli_opt_list(args, "phi", &SEA_CLI_RANGE_AZIMUTH, "0", phi, err);
    return st;
}
