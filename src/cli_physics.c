/* cli_physics.c - the physics subcommands of seabake: spectrum, emissivity,
 * reflectivity and energy.  Each validates all of its options, builds the
 * water index and the slope statistics, then writes CSV (a header row, one
 * row per case).  A value that is not finite is never printed: the command
 * stops with SEA_ERR_NUMERIC instead. */
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* ------------------------------------------------------------ constants */

static const double SEA_CLI_M_PER_UM = 1e-6;
/* Largest facet size: far beyond the size at which the high-resolution
 * statistics have converged to the low-resolution ones (seabake-model(7)). */
#define SEA_CLI_FACET_MAX 1e6
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
static const sea_cli_range SEA_CLI_RANGE_WIND = {SEA_WIND_MIN, SEA_WIND_MAX, false, false, "m/s"};
static const sea_cli_range SEA_CLI_RANGE_FETCH = {SEA_FETCH_MIN, INFINITY, false, false, "m"};
static const sea_cli_range SEA_CLI_RANGE_AZIMUTH = {-INFINITY, INFINITY, true, true, "degrees"};
static const sea_cli_range SEA_CLI_RANGE_THETA = {-90.0, 90.0, true, true, "degrees"};
static const sea_cli_range SEA_CLI_RANGE_FACET = {0.0, SEA_CLI_FACET_MAX, false, false, "m"};
static const sea_cli_range SEA_CLI_RANGE_SALINITY = {
    0.0, SEA_SALINITY_MAX, false, false, "g/kg"};
static const sea_cli_range SEA_CLI_RANGE_MEAN[2] = {
    {-SEA_CLI_MEAN_MAX, SEA_CLI_MEAN_MAX, false, false, ""},
    {-SEA_CLI_MEAN_MAX, SEA_CLI_MEAN_MAX, false, false, ""}};
static const sea_cli_range SEA_CLI_RANGE_COV[3] = {
    {0.0, SEA_CLI_VAR_MAX, false, false, ""},
    {0.0, SEA_CLI_VAR_MAX, false, false, ""},
    {-SEA_CLI_VAR_MAX, SEA_CLI_VAR_MAX, false, false, ""}};
/* n > 0, k >= 0. */
static const sea_cli_range SEA_CLI_RANGE_INDEX[2] = {
    {0.0, INFINITY, true, true, ""},
    {0.0, INFINITY, false, true, ""}};
/* A THETA,PHI pair: signed zenith and azimuth. */
static const sea_cli_range SEA_CLI_RANGE_DIRECTION[2] = {
    {-90.0, 90.0, true, true, "degrees"},
    {-INFINITY, INFINITY, true, true, "degrees"}};

/* ------------------------------------------------------------ help texts */

#define SEA_CLI_HELP_LIST \
    "LIST is A:B:STEP (A to B inclusive, STEP > 0), A,B,C or one value;\n" \
    "at most 100000 values.  Options take --opt VALUE or --opt=VALUE.\n"

#define SEA_CLI_HELP_WATER \
    "\nWater:\n" \
    "  --wavelength UM     wavelength, um, > 0 (required); inside the band of the\n" \
    "                      water table (about 2.4-15.5 um) unless --index is given\n" \
    "  --water TABLE       hale-querry (default), segelstein, or a CSV file with\n" \
    "                      columns wavelength_um,n,k\n" \
    "  --salinity S        salinity, g/kg, [0, 45]; default 35\n" \
    "  --index N,K         refractive index n + i k instead of a table (n > 0,\n" \
    "                      k >= 0); not with --water or --salinity\n"

#define SEA_CLI_HELP_SLOPES \
    "\nSlope statistics:\n" \
    "  --mean MX,MY        mean slope of the facet, each in [-5, 5]; default 0,0\n" \
    "  --wind U            wind speed at 10 m, m/s, [0.5, 40]; required unless --cov\n" \
    "  --fetch F           fetch, m, [1000, inf]; default inf (fully developed)\n" \
    "  --wind-dir DEG      wind azimuth from the x axis, degrees; default 0\n" \
    "  --facet L           facet size, m, [0, 1e6]: covariance of the waves\n" \
    "                      shorter than L (k > pi/L); default 0 = all waves\n" \
    "  --cov SXX,SYY,SXY   slope covariance given directly: SXX, SYY in [0, 10],\n" \
    "                      SXY^2 <= SXX*SYY; not with --wind, --fetch, --wind-dir\n" \
    "                      or --facet\n"

#define SEA_CLI_HELP_METHOD \
    "  --method M          auto (default: Eq 7, Gauss rule sized from the slope\n" \
    "                      spreads, within 1e-4 of full to 85 deg), fast (Eq 12)\n" \
    "                      or full (Eq 7, adaptive reference quadrature)\n"

#define SEA_CLI_HELP_GRID \
    "  --theta LIST        signed zenith angles of observation, degrees,\n" \
    "                      (-90, 90); (-theta, phi) is (theta, phi + 180)\n" \
    "  --phi LIST          azimuths of observation, degrees, any finite;\n" \
    "                      default 0\n"

static const char SEA_CLI_HELP_SPECTRUM[] =
    "Usage: seabake spectrum --wind U [--fetch F] [--wind-dir DEG] [--facet LIST]\n"
    "\n"
    "Slope covariance of the waves shorter than a facet, from the Elfouhaily et\n"
    "al. (1997) directional spectrum; one row per facet size.\n"
    "\n"
    "  --wind U            wind speed at 10 m, m/s, [0.5, 40] (required)\n"
    "  --fetch F           fetch, m, [1000, inf]; default inf (fully developed)\n"
    "  --wind-dir DEG      wind azimuth from the x axis, degrees; default 0\n"
    "  --facet LIST        facet sizes L, m, [0, 1e6]; 0 = all waves (low\n"
    "                      resolution); default 0\n"
    "\n" SEA_CLI_HELP_LIST "\n"
    "Columns: wind_ms,fetch_m,facet_m,kc_radm,sigma_x2,sigma_y2,sigma_xy\n"
    "  fetch_m is 0 for an infinite fetch; kc_radm = pi/L (0 for L = 0);\n"
    "  sigma_x2, sigma_y2, sigma_xy: slope covariance in the x, y frame.\n";

static const char SEA_CLI_HELP_EMISSIVITY[] =
    "Usage: seabake emissivity --wavelength UM (--wind U | --cov SXX,SYY,SXY)\n"
    "                          --theta LIST [--phi LIST] [OPTIONS]\n"
    "\n"
    "Effective emissivity of a facet seen from each direction (Eq 7 or 12).\n"
    "Rows: theta outer, phi inner.\n"
    "\n"
    "Directions:\n"
    SEA_CLI_HELP_GRID
    SEA_CLI_HELP_METHOD
    SEA_CLI_HELP_WATER
    SEA_CLI_HELP_SLOPES
    "\n" SEA_CLI_HELP_LIST "\n"
    "Columns: wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity\n";

static const char SEA_CLI_HELP_REFLECTIVITY[] =
    "Usage: seabake reflectivity --wavelength UM (--wind U | --cov SXX,SYY,SXY)\n"
    "                            --inc THETA,PHI (--obs THETA,PHI[;THETA,PHI...]... |\n"
    "                            --theta LIST [--phi LIST]) [OPTIONS]\n"
    "\n"
    "Effective reflectivity (Eq 13, per steradian of incidence) and BRDF\n"
    "(Eq 20) for one incidence and a list of observation directions.\n"
    "\n"
    "Directions (degrees, signed zenith in (-90, 90), azimuth any finite):\n"
    "  --inc THETA,PHI     direction of the source (required)\n"
    "  --obs THETA,PHI     observation directions; repeatable, and one value may\n"
    "                      hold several pairs separated by ';'\n"
    "  --theta LIST        instead of --obs: a grid of observation directions,\n"
    "  --phi LIST          theta outer, phi inner (--phi default 0)\n"
    SEA_CLI_HELP_WATER
    SEA_CLI_HELP_SLOPES
    "\n" SEA_CLI_HELP_LIST "\n"
    "Columns: wavelength_um,theta_inc_deg,phi_inc_deg,theta_deg,phi_deg,mx,my,\n"
    "         sxx,syy,sxy,reflectivity,brdf_per_sr\n";

static const char SEA_CLI_HELP_ENERGY[] =
    "Usage: seabake energy --wavelength UM (--wind U | --cov SXX,SYY,SXY)\n"
    "                      --theta LIST [--phi LIST] [OPTIONS]\n"
    "\n"
    "Energy balance (Eq 21): emissivity toward each direction plus the\n"
    "reflectivity integrated over every incidence; total <= 1, the deficit\n"
    "being the energy the single-scattering model loses.  Rows: theta outer,\n"
    "phi inner.\n"
    "\n"
    "Directions:\n"
    SEA_CLI_HELP_GRID
    SEA_CLI_HELP_METHOD
    SEA_CLI_HELP_WATER
    SEA_CLI_HELP_SLOPES
    "\n" SEA_CLI_HELP_LIST "\n"
    "Columns: wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity,\n"
    "         reflectance,total\n";

/* ------------------------------------------------------- option helpers */

/* Refuses name2 when name1 was given. */
static sea_status exclusive(const sea_cli_args *args, const char *name1, const char *name2,
                            sea_error *err)
{
    if (sea_cli_given(args, name1) && sea_cli_given(args, name2))
        return sea_fail(err, SEA_ERR_DOMAIN, "--%s cannot be combined with --%s", name2, name1);
    return SEA_OK;
}

static sea_status opt_method(const sea_cli_args *args, sea_emis_method *out, sea_error *err)
{
    const char *text = sea_cli_args_get(args, "method");
    int m = sea_emis_method_from_name(text ? text : "auto");
    if (m < 0)
        return sea_fail(err, SEA_ERR_PARSE, "--method: '%s' is not one of auto, fast, full", text);
    *out = (sea_emis_method)m;
    return SEA_OK;
}

static sea_status check_written(FILE *out, sea_error *err)
{
    if (ferror(out))
        return sea_fail(err, SEA_ERR_IO, "cannot write to standard output");
    return SEA_OK;
}

/* ---------------------------------------------------------- sea inputs */

/* What every optics subcommand computes from: the water's complex index
 * at the wavelength and the facet's slope statistics. */
typedef struct {
    double wavelength_um;
    double complex N;
    sea_slope_stats stats;
} sea_cli_sea;

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
        if ((st = exclusive(args, "index", "water", err)) != SEA_OK ||
            (st = exclusive(args, "index", "salinity", err)) != SEA_OK ||
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

/* Sea state from --wind, --fetch, --wind-dir (--wind must be given). */
static sea_status sea_state(const sea_cli_args *args, sea_spectrum *spec, double *wind,
                            double *fetch, sea_error *err)
{
    double wind_dir_deg;
    sea_status st = sea_cli_opt_number(args, "wind", &SEA_CLI_RANGE_WIND, 0.0, wind, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "fetch", &SEA_CLI_RANGE_FETCH, INFINITY, fetch, err);
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "wind-dir", &SEA_CLI_RANGE_AZIMUTH, 0.0, &wind_dir_deg, err);
    if (st != SEA_OK)
        return st;
    return sea_spectrum_init(spec, *wind, *fetch, sea_cli_radians(wind_dir_deg), err);
}

/* Covariance of the waves shorter than a facet of size L (0: all waves). */
static sea_status facet_cov(const sea_spectrum *spec, double facet, double *kc, sea_cov2 *cov,
                            sea_error *err)
{
    *kc = facet > 0.0 ? M_PI / facet : 0.0;
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
            if ((st = exclusive(args, "cov", spectral[i], err)) != SEA_OK)
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
            (st = sea_state(args, &spec, &wind, &fetch, err)) != SEA_OK ||
            (st = sea_cli_opt_number(args, "facet", &SEA_CLI_RANGE_FACET, 0.0, &facet, err)) !=
                SEA_OK ||
            (st = facet_cov(&spec, facet, &kc, &stats->cov, err)) != SEA_OK)
            return st;
    }
    return sea_slope_stats_check(stats, err);
}

/* Parses every input of an optics subcommand; the water table is read last
 * so that a typing mistake is reported before any file is opened. */
static sea_status sea_inputs(const sea_cli_args *args, sea_cli_sea *sea, sea_error *err)
{
    sea_status st = slope_stats(args, &sea->stats, err);
    if (st != SEA_OK)
        return st;
    return water_index(args, sea, err);
}

static void print_sea_columns(FILE *out, const sea_cli_sea *sea)
{
    const sea_slope_stats *s = &sea->stats;
    fprintf(out, "%.10g,%.10g,%.10g,%.10g,%.10g", s->mean.x, s->mean.y, s->cov.xx, s->cov.yy,
            s->cov.xy);
}

static sea_status not_finite(const char *what, double theta_deg, double phi_deg, sea_error *err)
{
    return sea_fail(err, SEA_ERR_NUMERIC,
                    "%s at theta = %g, phi = %g degrees is not finite; nothing printed for it",
                    what, theta_deg, phi_deg);
}

/* -------------------------------------------------------------- spectrum */

static const sea_cli_option SEA_CLI_SPECTRUM_OPTIONS[] = {
    {"wind", 0}, {"fetch", 0}, {"wind-dir", 0}, {"facet", 0}};

static sea_status run_spectrum(const sea_cli_args *args, FILE *out, sea_error *err)
{
    sea_spectrum spec;
    double wind, fetch;
    sea_cli_list facets = {NULL, 0};
    sea_status st = sea_cli_require(args, "wind", NULL, err);
    if (st == SEA_OK)
        st = sea_state(args, &spec, &wind, &fetch, err);
    if (st == SEA_OK)
        st = sea_cli_opt_list(args, "facet", &SEA_CLI_RANGE_FACET, "0", &facets, err);
    if (st != SEA_OK)
        goto done;

    fputs("wind_ms,fetch_m,facet_m,kc_radm,sigma_x2,sigma_y2,sigma_xy\n", out);
    for (size_t i = 0; i < facets.n; ++i) {
        sea_cov2 cov;
        double kc;
        if ((st = facet_cov(&spec, facets.values[i], &kc, &cov, err)) != SEA_OK)
            goto done;
        /* No inf is ever printed: an infinite (fully developed) fetch is 0. */
        fprintf(out, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", wind,
                isinf(fetch) ? 0.0 : fetch, facets.values[i], kc, cov.xx, cov.yy, cov.xy);
        if ((st = check_written(out, err)) != SEA_OK)
            goto done;
    }
done:
    sea_cli_list_free(&facets);
    return st;
}

/* ---------------------------------------------------- emissivity, energy */

#define SEA_CLI_SEA_OPTIONS \
    {"wavelength", 0}, {"water", 0}, {"salinity", 0}, {"index", 0}, {"mean", 0}, {"wind", 0}, \
        {"fetch", 0}, {"wind-dir", 0}, {"facet", 0}, \
    { \
        "cov", 0 \
    }

static const sea_cli_option SEA_CLI_EMISSIVITY_OPTIONS[] = {
    SEA_CLI_SEA_OPTIONS, {"theta", 0}, {"phi", 0}, {"method", 0}};
static const sea_cli_option SEA_CLI_ENERGY_OPTIONS[] = {
    SEA_CLI_SEA_OPTIONS, {"theta", 0}, {"phi", 0}, {"method", 0}};

/* --theta (required) and --phi (default 0) as lists. */
static sea_status direction_grid(const sea_cli_args *args, sea_cli_list *theta, sea_cli_list *phi,
                                 sea_error *err)
{
    sea_status st = sea_cli_require(args, "theta", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_opt_list(args, "theta", &SEA_CLI_RANGE_THETA, NULL, theta, err);
    if (st == SEA_OK)
        st = sea_cli_opt_list(args, "phi", &SEA_CLI_RANGE_AZIMUTH, "0", phi, err);
    return st;
}

/* The two subcommands that evaluate one observation direction at a time
 * with the quadrature plan differ only in the call and the last columns. */
typedef enum { SEA_CLI_EMISSIVITY, SEA_CLI_ENERGY } sea_cli_quantity;

static sea_status direction_row(FILE *out, sea_cli_quantity what, const sea_optics *optics,
                                sea_emis_method method, const sea_cli_sea *sea, double t, double f,
                                sea_error *err)
{
    sea_dir v = sea_dir_fold(sea_cli_radians(t), sea_cli_radians(f));
    sea_error lib = {{0}};
    sea_energy e = {0.0, 0.0, 0.0};
    sea_status st;
    const char *name;
    switch (what) {
    case SEA_CLI_EMISSIVITY:
        name = "emissivity";
        st = sea_emissivity(optics, method, sea->N, &sea->stats, v, &e.emissivity, &lib);
        break;
    case SEA_CLI_ENERGY:
    default:
        name = "energy balance";
        st = sea_energy_balance(optics, method, sea->N, &sea->stats, v, &e, &lib);
        break;
    }
    if (st != SEA_OK)
        return sea_fail(err, st, "%s at theta = %g, phi = %g degrees: %s", name, t, f, lib.msg);
    if (!isfinite(e.emissivity) || !isfinite(e.reflectance) || !isfinite(e.total))
        return not_finite(name, t, f, err);
    fprintf(out, "%.10g,%.10g,%.10g,", sea->wavelength_um, t, f);
    print_sea_columns(out, sea);
    if (what == SEA_CLI_EMISSIVITY)
        fprintf(out, ",%.10g\n", e.emissivity);
    else
        fprintf(out, ",%.10g,%.10g,%.10g\n", e.emissivity, e.reflectance, e.total);
    return check_written(out, err);
}

static sea_status run_directions(const sea_cli_args *args, FILE *out, sea_cli_quantity what,
                                 sea_error *err)
{
    sea_cli_list theta = {NULL, 0}, phi = {NULL, 0};
    sea_optics *optics = NULL;
    sea_emis_method method = SEA_EMIS_AUTO;
    sea_cli_sea sea;
    sea_status st = direction_grid(args, &theta, &phi, err);
    if (st == SEA_OK)
        st = opt_method(args, &method, err);
    if (st == SEA_OK)
        st = sea_inputs(args, &sea, err);
    if (st == SEA_OK)
        st = sea_optics_alloc(&optics, err);
    if (st != SEA_OK)
        goto done;

    fputs(what == SEA_CLI_EMISSIVITY
              ? "wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity\n"
              : "wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity,reflectance,total\n",
          out);
    for (size_t i = 0; i < theta.n && st == SEA_OK; ++i)
        for (size_t j = 0; j < phi.n && st == SEA_OK; ++j)
            st =
                direction_row(out, what, optics, method, &sea, theta.values[i], phi.values[j], err);
done:
    sea_optics_free(optics);
    sea_cli_list_free(&theta);
    sea_cli_list_free(&phi);
    return st;
}

static sea_status run_emissivity(const sea_cli_args *args, FILE *out, sea_error *err)
{
    return run_directions(args, out, SEA_CLI_EMISSIVITY, err);
}

static sea_status run_energy(const sea_cli_args *args, FILE *out, sea_error *err)
{
    return run_directions(args, out, SEA_CLI_ENERGY, err);
}

/* ---------------------------------------------------------- reflectivity */

static const sea_cli_option SEA_CLI_REFLECTIVITY_OPTIONS[] = {
    SEA_CLI_SEA_OPTIONS, {"inc", 0}, {"obs", SEA_CLI_OPT_ACCUMULATE}, {"theta", 0}, {"phi", 0}};

/* Observation directions given as pairs (--obs), in degrees. */
typedef struct {
    double *theta, *phi;
    size_t n;
} sea_cli_pairs;

static void pairs_free(sea_cli_pairs *p)
{
    free(p->theta);
    free(p->phi);
    *p = (sea_cli_pairs){NULL, NULL, 0};
}

/* Collects every THETA,PHI pair of every --obs value ("10,0;20,0"). */
static sea_status obs_pairs(const sea_cli_args *args, sea_cli_pairs *pairs, sea_error *err)
{
    size_t count = sea_cli_args_count(args, "obs"), total = 0;
    for (size_t i = 0; i < count; ++i) {
        const char *text = sea_cli_args_nth(args, "obs", i);
        total += 1;
        for (const char *s = text; *s; ++s)
            total += *s == ';';
    }
    if (total > SEA_CLI_LIST_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "--obs: %zu directions, more than %d", total,
                        SEA_CLI_LIST_MAX);
    pairs->theta = malloc(total * sizeof *pairs->theta);
    pairs->phi = malloc(total * sizeof *pairs->phi);
    pairs->n = 0;
    if (!pairs->theta || !pairs->phi)
        return sea_fail(err, SEA_ERR_NOMEM, "--obs: out of memory for %zu directions", total);

    for (size_t i = 0; i < count; ++i) {
        /* A copy, cut at each ';', gives parse_tuple one pair at a time. */
        char *copy = strdup(sea_cli_args_nth(args, "obs", i));
        if (!copy)
            return sea_fail(err, SEA_ERR_NOMEM, "--obs: out of memory");
        sea_status st = SEA_OK;
        for (char *pair = copy; st == SEA_OK && pair;) {
            char *next = strchr(pair, ';');
            if (next)
                *next++ = '\0';
            double d[2];
            st =
                sea_cli_parse_tuple("--obs", pair, 2, SEA_CLI_RANGE_DIRECTION, "THETA,PHI", d, err);
            if (st == SEA_OK) {
                pairs->theta[pairs->n] = d[0];
                pairs->phi[pairs->n] = d[1];
                ++pairs->n;
            }
            pair = next;
        }
        free(copy);
        if (st != SEA_OK)
            return st;
    }
    return SEA_OK;
}

static sea_status reflectivity_row(FILE *out, const sea_cli_sea *sea, const double inc_deg[2],
                                   sea_dir inc, double t, double f, sea_error *err)
{
    sea_dir obs = sea_dir_fold(sea_cli_radians(t), sea_cli_radians(f));
    double rho = sea_reflectivity(sea->N, &sea->stats, inc, obs);
    double brdf = sea_brdf(sea->N, &sea->stats, inc, obs);
    if (!isfinite(rho) || !isfinite(brdf))
        return not_finite("reflectivity", t, f, err);
    fprintf(out, "%.10g,%.10g,%.10g,%.10g,%.10g,", sea->wavelength_um, inc_deg[0], inc_deg[1], t,
            f);
    print_sea_columns(out, sea);
    fprintf(out, ",%.10g,%.10g\n", rho, brdf);
    return check_written(out, err);
}

static sea_status run_reflectivity(const sea_cli_args *args, FILE *out, sea_error *err)
{
    sea_cli_list theta = {NULL, 0}, phi = {NULL, 0};
    sea_cli_pairs pairs = {NULL, NULL, 0};
    sea_cli_sea sea;
    double inc[2];
    const char *inc_text = sea_cli_args_get(args, "inc");
    sea_status st = sea_cli_require(args, "inc", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_parse_tuple("--inc", inc_text, 2, SEA_CLI_RANGE_DIRECTION, "THETA,PHI", inc,
                                 err);
    if (st != SEA_OK)
        goto done;
    if (sea_cli_given(args, "obs")) {
        if ((st = exclusive(args, "obs", "theta", err)) != SEA_OK ||
            (st = exclusive(args, "obs", "phi", err)) != SEA_OK ||
            (st = obs_pairs(args, &pairs, err)) != SEA_OK)
            goto done;
    } else if (!sea_cli_given(args, "theta")) {
        st = sea_fail(err, SEA_ERR_DOMAIN,
                      "missing observation directions: give --obs THETA,PHI or --theta LIST");
        goto done;
    } else if ((st = direction_grid(args, &theta, &phi, err)) != SEA_OK) {
        goto done;
    }
    if ((st = sea_inputs(args, &sea, err)) != SEA_OK)
        goto done;

    sea_dir inc_dir = sea_dir_fold(sea_cli_radians(inc[0]), sea_cli_radians(inc[1]));
    fputs("wavelength_um,theta_inc_deg,phi_inc_deg,theta_deg,phi_deg,mx,my,sxx,syy,sxy,"
          "reflectivity,brdf_per_sr\n",
          out);
    for (size_t i = 0; i < pairs.n && st == SEA_OK; ++i)
        st = reflectivity_row(out, &sea, inc, inc_dir, pairs.theta[i], pairs.phi[i], err);
    for (size_t i = 0; i < theta.n && st == SEA_OK; ++i)
        for (size_t j = 0; j < phi.n && st == SEA_OK; ++j)
            st = reflectivity_row(out, &sea, inc, inc_dir, theta.values[i], phi.values[j], err);
done:
    pairs_free(&pairs);
    sea_cli_list_free(&theta);
    sea_cli_list_free(&phi);
    return st;
}

/* ---------------------------------------------------------- the commands */

#define SEA_CLI_COUNT(a) (sizeof(a) / sizeof((a)[0]))

static const sea_cli_command SEA_CLI_COMMANDS[] = {
    {"spectrum", "slope covariance of the Elfouhaily et al. (1997) spectrum", SEA_CLI_HELP_SPECTRUM,
     SEA_CLI_SPECTRUM_OPTIONS, SEA_CLI_COUNT(SEA_CLI_SPECTRUM_OPTIONS), run_spectrum},
    {"emissivity", "effective emissivity toward a list of directions", SEA_CLI_HELP_EMISSIVITY,
     SEA_CLI_EMISSIVITY_OPTIONS, SEA_CLI_COUNT(SEA_CLI_EMISSIVITY_OPTIONS), run_emissivity},
    {"reflectivity", "effective reflectivity and BRDF for one incidence", SEA_CLI_HELP_REFLECTIVITY,
     SEA_CLI_REFLECTIVITY_OPTIONS, SEA_CLI_COUNT(SEA_CLI_REFLECTIVITY_OPTIONS), run_reflectivity},
    {"energy", "emissivity plus hemispherical reflectance (energy balance)", SEA_CLI_HELP_ENERGY,
     SEA_CLI_ENERGY_OPTIONS, SEA_CLI_COUNT(SEA_CLI_ENERGY_OPTIONS), run_energy},
};

const sea_cli_command *sea_cli_command_find(const char *name)
{
    for (size_t i = 0; i < SEA_CLI_COUNT(SEA_CLI_COMMANDS); ++i)
        if (strcmp(SEA_CLI_COMMANDS[i].name, name) == 0)
            return &SEA_CLI_COMMANDS[i];
    for (size_t i = 0; i < sea_cli_waves_n_commands; ++i)
        if (strcmp(sea_cli_waves_commands[i].name, name) == 0)
            return &sea_cli_waves_commands[i];
    for (size_t i = 0; i < sea_cli_render_n_commands; ++i)
        if (strcmp(sea_cli_render_commands[i].name, name) == 0)
            return &sea_cli_render_commands[i];
    for (size_t i = 0; i < sea_cli_bake_n_commands; ++i)
        if (strcmp(sea_cli_bake_commands[i].name, name) == 0)
            return &sea_cli_bake_commands[i];
    return NULL;
}

void sea_cli_print_usage(FILE *f)
{
    fputs("Usage: seabake SUBCOMMAND [OPTIONS]\n"
          "       seabake help [SUBCOMMAND]\n"
          "       seabake --version\n"
          "\n"
          "Infrared optical properties of a wind-roughened sea surface at any\n"
          "resolution (Caillault et al. 2007, Applied Optics 46, 5471).\n"
          "\n"
          "Subcommands:\n",
          f);
    for (size_t i = 0; i < SEA_CLI_COUNT(SEA_CLI_COMMANDS); ++i)
        fprintf(f, "  %-13s %s\n", SEA_CLI_COMMANDS[i].name, SEA_CLI_COMMANDS[i].summary);
    for (size_t i = 0; i < sea_cli_waves_n_commands; ++i)
        fprintf(f, "  %-13s %s\n", sea_cli_waves_commands[i].name,
                sea_cli_waves_commands[i].summary);
    for (size_t i = 0; i < sea_cli_render_n_commands; ++i)
        fprintf(f, "  %-13s %s\n", sea_cli_render_commands[i].name,
                sea_cli_render_commands[i].summary);
    for (size_t i = 0; i < sea_cli_bake_n_commands; ++i)
        fprintf(f, "  %-13s %s\n", sea_cli_bake_commands[i].name, sea_cli_bake_commands[i].summary);
    fputs("  help          this text, or the options of one subcommand\n"
          "\n"
          "The physics subcommands and slopes write CSV on standard output: a\n"
          "header row, then one row per case; convergence and bench print a table\n"
          "and write their files into a directory; render writes EXR and PNG\n"
          "images of a scene file (seabake-scene(5)), bake its per-level maps and a\n"
          "manifest into a directory.  Exit status: 0 success,\n"
          "1 runtime failure, 2 usage error, 3 input/output error.  See seabake(1).\n",
          f);
}
