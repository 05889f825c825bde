/* reflectivity.c - the reflectivity subcommand of seabake: the effective
 * reflectivity (Eq 13) and BRDF (Eq 20) for one incidence and a list of
 * observation directions (--obs pairs or a theta x phi grid), as CSV. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* ------------------------------------------------------------ help text */

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
    SEA_CLI_HELP_SLOPE_STATS
    "\n" SEA_CLI_HELP_LIST "\n"
    "Columns: wavelength_um,theta_inc_deg,phi_inc_deg,theta_deg,phi_deg,mx,my,\n"
    "         sxx,syy,sxy,reflectivity,brdf_per_sr\n";

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
        return sea_cli_not_finite("reflectivity", t, f, err);
    fprintf(out, "%.10g,%.10g,%.10g,%.10g,%.10g,", sea->wavelength_um, inc_deg[0], inc_deg[1], t,
            f);
    sea_cli_print_sea_columns(out, sea);
    fprintf(out, ",%.10g,%.10g\n", rho, brdf);
    return sea_cli_check_written(out, err);
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
        if ((st = sea_cli_exclusive(args, "obs", "theta", err)) != SEA_OK ||
            (st = sea_cli_exclusive(args, "obs", "phi", err)) != SEA_OK ||
            (st = obs_pairs(args, &pairs, err)) != SEA_OK)
            goto done;
    } else if (!sea_cli_given(args, "theta")) {
        st = sea_fail(err, SEA_ERR_DOMAIN,
                      "missing observation directions: give --obs THETA,PHI or --theta LIST");
        goto done;
    } else if ((st = sea_cli_direction_grid(args, &theta, &phi, err)) != SEA_OK) {
        goto done;
    }
    if ((st = sea_cli_sea_inputs(args, &sea, err)) != SEA_OK)
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

/* --------------------------------------------------------------- command */

const sea_cli_command sea_cli_cmd_reflectivity = {
    "reflectivity", "effective reflectivity and BRDF for one incidence", SEA_CLI_HELP_REFLECTIVITY,
    SEA_CLI_REFLECTIVITY_OPTIONS, SEA_CLI_COUNT(SEA_CLI_REFLECTIVITY_OPTIONS), run_reflectivity};
