/* spectrum.c - the spectrum subcommand of seabake: the slope covariance
 * of the waves shorter than a facet, from the Elfouhaily et al. (1997)
 * spectrum, as CSV (one row per facet size). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli.h"

/* ------------------------------------------------------------ help text */

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

/* -------------------------------------------------------------- spectrum */

static const sea_cli_option SEA_CLI_SPECTRUM_OPTIONS[] = {
    {"wind", 0}, {"fetch", 0}, {"wind-dir", 0}, {"facet", 0}};

static sea_status run_spectrum(const sea_cli_args *args, FILE *out, sea_error *err)
{
    sea_spectrum spec;
    double wind, fetch;
    sea_cli_list facets = {NULL, 0};
    sea_cov2 *cov = NULL;
    double *kc = NULL;
    sea_status st = sea_cli_require(args, "wind", NULL, err);
    if (st == SEA_OK)
        st = sea_cli_sea_state(args, &spec, &wind, &fetch, err);
    if (st == SEA_OK)
        st = sea_cli_opt_list(args, "facet", &SEA_CLI_RANGE_FACET, "0", &facets, err);
    if (st != SEA_OK)
        goto done;
    /* Every row is computed before the header is printed: a facet size
     * the spectrum refuses leaves standard output empty. */
    cov = malloc(facets.n * sizeof *cov);
    kc = malloc(facets.n * sizeof *kc);
    if (cov == NULL || kc == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu facet sizes", facets.n);
        goto done;
    }
    for (size_t i = 0; i < facets.n; ++i)
        if ((st = sea_cli_facet_cov(&spec, facets.values[i], &kc[i], &cov[i], err)) != SEA_OK)
            goto done;

    fputs("wind_ms,fetch_m,facet_m,kc_radm,sigma_x2,sigma_y2,sigma_xy\n", out);
    for (size_t i = 0; i < facets.n; ++i) {
        /* No inf is ever printed: an infinite (fully developed) fetch is 0. */
        fprintf(out, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", wind,
                isinf(fetch) ? 0.0 : fetch, facets.values[i], kc[i], cov[i].xx, cov[i].yy,
                cov[i].xy);
        if ((st = sea_cli_check_written(out, err)) != SEA_OK)
            goto done;
    }
done:
    free(cov);
    free(kc);
    sea_cli_list_free(&facets);
    return st;
}

/* --------------------------------------------------------------- command */

const sea_cli_command sea_cli_cmd_spectrum = {
    "spectrum", "slope covariance of the Elfouhaily et al. (1997) spectrum", SEA_CLI_HELP_SPECTRUM,
    SEA_CLI_SPECTRUM_OPTIONS, SEA_CLI_COUNT(SEA_CLI_SPECTRUM_OPTIONS), run_spectrum};
