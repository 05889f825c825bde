/* emissivity.c - the emissivity and energy subcommands of seabake, in one
 * file because they share one loop: both evaluate the quadrature plan
 * toward each direction of a theta x phi grid and differ only in the call
 * and the last columns of the CSV (Eq 7 or 12; Eq 21). */
#include <math.h>
#include <stdio.h>

#include "cli.h"

/* ------------------------------------------------------------ help texts */

#define SEA_CLI_HELP_EMISSIVITY_RULE \
    "  --emissivity M      auto (default: Eq 7, Gauss rule sized from the slope\n" \
    "                      spreads, within 1e-6 of full to 85 deg), fast (Eq 12)\n" \
    "                      or full (Eq 7, adaptive reference quadrature)\n"

#define SEA_CLI_HELP_GRID \
    "  --theta LIST        signed zenith angles of observation, degrees,\n" \
    "                      (-90, 90); (-theta, phi) is (theta, phi + 180)\n" \
    "  --phi LIST          azimuths of observation, degrees, any finite;\n" \
    "                      default 0\n"

static const char SEA_CLI_HELP_EMISSIVITY[] =
    "Usage: seabake emissivity --wavelength UM (--wind U | --cov SXX,SYY,SXY)\n"
    "                          --theta LIST [--phi LIST] [OPTIONS]\n"
    "\n"
    "Effective emissivity of a facet seen from each direction (Eq 7 or 12).\n"
    "Rows: theta outer, phi inner.\n"
    "\n"
    "Directions:\n"
    SEA_CLI_HELP_GRID
    SEA_CLI_HELP_EMISSIVITY_RULE
    "  --reflections R     auto (default: a second hit in the sea around wherever\n"
    "                      it moves the emissivity by more than a hundredth of\n"
    "                      --tolerance) or 1 to 3 surface hits (1: the paper):\n"
    "                      a facet's mirror ray may meet the sea again and\n"
    "                      bring its emission\n"
    SEA_CLI_HELP_SHADOWING
    "  --scales N          2 (default with --wind): the slopes of the waves\n"
    "                      longer than the half-variance split carry facets,\n"
    "                      each with its own Eq 7 (within 1.5e-3 of ray-traced\n"
    "                      sea surfaces to 82 deg, 4.6e-3 at 85, where one\n"
    "                      scale is 8e-3 and 20e-3 low); or 1 (default with\n"
    "                      --cov: one Gaussian surface, the paper)\n"
    "  --tolerance T       relative, (0, 0.1]; default 1e-3: how finely the\n"
    "                      model's parts are computed\n"
    "  --reference         every approximation replaced by its exact form\n"
    "  --stokes            also the polarised part of the Stokes emissivity in\n"
    "                      the view's frame (+Q vertical): columns e_q, e_u and\n"
    "                      dolp = sqrt(e_q^2 + e_u^2) / emissivity\n"
    SEA_CLI_HELP_WATER
    SEA_CLI_HELP_SLOPE_STATS
    "\n" SEA_CLI_HELP_LIST "\n"
    "Columns: wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity\n"
    "         (and e_q,e_u,dolp with --stokes)\n";

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
    SEA_CLI_HELP_EMISSIVITY_RULE
    SEA_CLI_HELP_SHADOWING
    SEA_CLI_HELP_WATER
    SEA_CLI_HELP_SLOPE_STATS
    "\n" SEA_CLI_HELP_LIST "\n"
    "Columns: wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity,\n"
    "         reflectance,total\n";

/* ---------------------------------------------------- emissivity, energy */

static const sea_cli_option SEA_CLI_EMISSIVITY_OPTIONS[] = {
    SEA_CLI_SEA_OPTIONS, {"theta", 0}, {"phi", 0}, {"emissivity", 0}, {"reflections", 0},
    {"shadowing", 0}, {"scales", 0}, {"tolerance", 0}, {"reference", SEA_CLI_OPT_FLAG},
    {"stokes", SEA_CLI_OPT_FLAG}};
static const sea_cli_option SEA_CLI_ENERGY_OPTIONS[] = {
    SEA_CLI_SEA_OPTIONS, {"theta", 0}, {"phi", 0}, {"emissivity", 0}, {"shadowing", 0}};

/* The two subcommands that evaluate one observation direction at a time
 * with the quadrature plan differ only in the call and the last columns. */
typedef enum { SEA_CLI_EMISSIVITY, SEA_CLI_ENERGY } sea_cli_quantity;

/* The model of the emissivity subcommand: the library's default
 * (sea_model_params_default) with the options' changes.  The sea around and
 * two scales need the sea spectrum (--wind); with --cov the given
 * statistics are the whole sea, one scale by default.  *spectral, *lr and
 * *fine: what sea_model_alloc takes. */
typedef struct {
    sea_model_params mp;
    int has_spectrum;
    sea_spectrum spectrum;
    sea_slope_stats lr;
    sea_cov2 fine;
} emis_model;

static sea_status model_inputs(const sea_cli_args *args, const sea_cli_sea *sea,
                               emis_model *em, sea_error *err)
{
    sea_model_params_default(&em->mp);
    sea_status st = sea_cli_opt_emissivity(args, &em->mp.method, err);
    long reflections = SEA_REFLECTIONS_AUTO, scales = 0;
    if (st == SEA_OK)
        st = sea_cli_opt_reflections(args, SEA_REFLECTIONS_AUTO, &reflections, err);
    if (st == SEA_OK)
        st = sea_cli_opt_shadowing(args, SEA_SHADOW_CORRELATED, &em->mp.shadowing, err);
    if (st == SEA_OK)
        st = sea_cli_opt_integer(args, "scales", 1, 2, 0, &scales, err);
    static const sea_cli_range tol = {0.0, 0.1, true, false, ""};
    if (st == SEA_OK)
        st = sea_cli_opt_number(args, "tolerance", &tol, 1e-3, &em->mp.tolerance, err);
    if (st != SEA_OK)
        return st;
    em->mp.reflections = (int)reflections;
    em->mp.reference = sea_cli_given(args, "reference");
    em->has_spectrum = sea_cli_args_get(args, "cov") == NULL && sea_cli_args_get(args, "wind") != NULL;
    if (scales == 2 && !em->has_spectrum)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "--scales 2 splits the sea spectrum's slopes: give --wind, not --cov");
    em->mp.scales = scales > 0 ? (int)scales : em->has_spectrum ? 2 : 1;
    em->lr = (sea_slope_stats){ { 0.0, 0.0 }, sea->stats.cov };
    em->fine = sea->stats.cov;
    if (em->has_spectrum) {
        double wind, fetch;
        if ((st = sea_cli_sea_state(args, &em->spectrum, &wind, &fetch, err)) != SEA_OK)
            return st;
        sea_error lib = {{0}};
        if ((st = sea_spectrum_slope_cov(&em->spectrum, 0.0, &em->lr.cov, &lib)) != SEA_OK)
            return sea_fail(err, st, "the sea's slopes: %s", lib.msg);
    }
    return SEA_OK;
}

/* The CSV's first line: the model, as a comment. */
static void model_comment(FILE *out, const emis_model *em)
{
    char refl[32];
    if (em->mp.reflections == SEA_REFLECTIONS_AUTO)
        snprintf(refl, sizeof refl, "auto");
    else
        snprintf(refl, sizeof refl, "%d", em->mp.reflections);
    fprintf(out,
            "# seabake emissivity: %s shadowing, %d scale%s, reflections %s, tolerance %g, "
            "rule %s%s%s\n",
            sea_shadowing_name(em->mp.shadowing), em->mp.scales, em->mp.scales == 1 ? "" : "s",
            refl, em->mp.tolerance, sea_emis_method_name(em->mp.method),
            em->mp.reference ? ", reference (every approximation exact)" : "",
            em->mp.shadowing == SEA_SHADOW_SMITH && em->mp.scales == 1 && em->mp.reflections == 1
                ? " (the paper's model)"
                : "");
}

static sea_status direction_row(FILE *out, sea_cli_quantity what, const sea_optics *optics,
                                sea_emis_method method, const sea_model *model, int stokes,
                                const sea_cli_sea *sea, double t, double f, sea_error *err)
{
    sea_dir v = sea_dir_fold(sea_cli_radians(t), sea_cli_radians(f));
    sea_error lib = {{0}};
    sea_energy e = {0.0, 0.0, 0.0};
    double q = 0.0, u = 0.0;
    sea_status st;
    const char *name;
    switch (what) {
    case SEA_CLI_EMISSIVITY:
        name = "emissivity";
        st = sea_model_emissivity(model, &sea->stats, v, &e.emissivity, NULL, &lib);
        if (st == SEA_OK && stokes) {
            name = "Stokes emissivity";
            st = sea_model_polarisation(model, &sea->stats, v, &q, &u, &lib);
        }
        break;
    case SEA_CLI_ENERGY:
    default:
        name = "energy balance";
        st = sea_energy_balance(optics, method, sea->N, &sea->stats, v, &e, &lib);
        break;
    }
    if (st != SEA_OK)
        return sea_fail(err, st, "%s at theta = %g, phi = %g degrees: %s", name, t, f, lib.msg);
    if (!isfinite(e.emissivity) || !isfinite(e.reflectance) || !isfinite(e.total) ||
        !isfinite(q) || !isfinite(u))
        return sea_cli_not_finite(name, t, f, err);
    fprintf(out, "%.10g,%.10g,%.10g,", sea->wavelength_um, t, f);
    sea_cli_print_sea_columns(out, sea);
    if (what == SEA_CLI_EMISSIVITY && stokes)
        fprintf(out, ",%.10g,%.10g,%.10g,%.10g\n", e.emissivity, q, u,
                e.emissivity > 0.0 ? hypot(q, u) / e.emissivity : 0.0);
    else if (what == SEA_CLI_EMISSIVITY)
        fprintf(out, ",%.10g\n", e.emissivity);
    else
        fprintf(out, ",%.10g,%.10g,%.10g\n", e.emissivity, e.reflectance, e.total);
    return sea_cli_check_written(out, err);
}

static sea_status run_directions(const sea_cli_args *args, FILE *out, sea_cli_quantity what,
                                 sea_error *err)
{
    sea_cli_list theta = {NULL, 0}, phi = {NULL, 0};
    sea_optics *optics = NULL;
    sea_model *model = NULL;
    sea_emis_method method = SEA_EMIS_AUTO;
    emis_model em;
    sea_cli_sea sea;
    sea_status st = sea_cli_direction_grid(args, &theta, &phi, err);
    if (st == SEA_OK)
        st = sea_cli_opt_emissivity(args, &method, err);
    sea_shadowing shadowing = SEA_SHADOW_CORRELATED;
    if (st == SEA_OK)
        st = sea_cli_opt_shadowing(args, SEA_SHADOW_CORRELATED, &shadowing, err);
    if (st == SEA_OK)
        st = sea_cli_sea_inputs(args, &sea, err);
    if (st == SEA_OK && what == SEA_CLI_EMISSIVITY) {
        st = model_inputs(args, &sea, &em, err);
        sea_error lib = {{0}};
        if (st == SEA_OK &&
            (st = sea_model_alloc(&em.mp, em.has_spectrum ? &em.spectrum : NULL, &em.lr, &em.fine,
                                  &sea.N, 1, NULL, &model, &lib)) != SEA_OK)
            st = sea_fail(err, st, "the model: %s", lib.msg);
    }
    if (st == SEA_OK)
        st = sea_optics_alloc(&optics, err);
    if (st != SEA_OK)
        goto done;
    sea_optics_set_shadowing(optics, shadowing);

    const int stokes = what == SEA_CLI_EMISSIVITY && sea_cli_given(args, "stokes");
    if (what == SEA_CLI_EMISSIVITY)
        model_comment(out, &em);
    fputs("wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity", out);
    fputs(what != SEA_CLI_EMISSIVITY ? ",reflectance,total\n" : stokes ? ",e_q,e_u,dolp\n" : "\n",
          out);
    for (size_t i = 0; i < theta.n && st == SEA_OK; ++i)
        for (size_t j = 0; j < phi.n && st == SEA_OK; ++j)
            st = direction_row(out, what, optics, method, model, stokes, &sea, theta.values[i],
                               phi.values[j], err);
done:
    sea_model_free(model);
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

/* --------------------------------------------------------------- command */

const sea_cli_command sea_cli_cmd_emissivity = {
    "emissivity", "effective emissivity toward a list of directions", SEA_CLI_HELP_EMISSIVITY,
    SEA_CLI_EMISSIVITY_OPTIONS, SEA_CLI_COUNT(SEA_CLI_EMISSIVITY_OPTIONS), run_emissivity};

const sea_cli_command sea_cli_cmd_energy = {
    "energy", "emissivity plus hemispherical reflectance (energy balance)",
    SEA_CLI_HELP_ENERGY, SEA_CLI_ENERGY_OPTIONS, SEA_CLI_COUNT(SEA_CLI_ENERGY_OPTIONS),
    run_energy};
