/* emissivity.c - the effective emissivity of a wind-roughened sea through libseabake.
 *
 * Sea water (Hale & Querry table, salinity 35 g/kg) at 4 um, a fully developed sea at
 * 10 m/s seen at low resolution (the slope covariance of all the waves of the Elfouhaily
 * spectrum), viewed along the wind at a few zenith angles; it prints a table of the rough
 * sea's emissivity beside a flat sea's (no slopes: 1 - Fresnel reflectance).
 * `seabake emissivity --wavelength 4 --wind 10 --theta 0,30,60,70,80,85` computes the same.
 *
 *   cc emissivity.c $(pkg-config --cflags --libs seabake) -o emissivity && ./emissivity */
#include <math.h>
#include <stdio.h>

#include <seabake.h>

/* Every call that can fail returns a status and fills a message. */
static int failed(const char *what, sea_status st, const sea_error *err)
{
    fprintf(stderr, "emissivity: %s: %s (%s)\n", what, err->msg, sea_status_name(st));
    return 1;
}

int main(void)
{
    const double deg = 0.017453292519943295; /* pi / 180 */
    const double wavelength = 4e-6;          /* m */
    const double theta_deg[] = { 0, 30, 60, 70, 80, 85 };
    sea_error err = { { 0 } };
    sea_status st;

    sea_init(); /* first: GSL errors become statuses instead of aborting */

    /* The water's complex refractive index N = n + i k from the built-in table. */
    sea_water *water = NULL;
    double complex N;
    if ((st = sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &water, &err)) != SEA_OK)
        return failed("water table", st, &err);
    st = sea_water_index(water, wavelength, &N, &err);
    sea_water_free(water); /* N is a copy: the table is no longer needed */
    if (st != SEA_OK)
        return failed("refractive index", st, &err);

    /* Low-resolution slope statistics: zero mean, covariance of every wave (kc = 0). */
    sea_spectrum spectrum;
    sea_slope_stats slopes = { { 0.0, 0.0 }, { 0.0, 0.0, 0.0 } }, flat = slopes;
    if ((st = sea_spectrum_init(10.0, INFINITY, 0.0, &spectrum, &err)) != SEA_OK ||
        (st = sea_spectrum_slope_cov(&spectrum, 0.0, &slopes.cov, &err)) != SEA_OK)
        return failed("slope statistics", st, &err);

    /* The default model (what the program computes): built once, then only read (it
     * could serve many threads).  Its tables need the spectrum and the low-resolution
     * statistics of the sea its facets' mirror rays meet. */
    sea_model_params mp;
    sea_model_params_default(&mp);
    sea_model *model = NULL;
    if ((st = sea_model_alloc(&mp, &spectrum, &slopes, NULL, &N, 1, NULL, &model, &err)) !=
        SEA_OK)
        return failed("default model", st, &err);
    /* The paper's model: a quadrature plan with Smith's shadowing, one hit, one scale. */
    sea_optics *optics = NULL;
    if ((st = sea_optics_alloc(&optics, &err)) != SEA_OK) {
        sea_model_free(model);
        return failed("quadrature plan", st, &err);
    }
    sea_optics_set_shadowing(optics, SEA_SHADOW_SMITH);

    printf("# %.1f um, n = %.4f, k = %.4f; 10 m/s: sigma_x^2 = %.5f, sigma_y^2 = %.5f\n",
           wavelength * 1e6, creal(N), cimag(N), slopes.cov.xx, slopes.cov.yy);
    printf("theta_deg  emissivity  the_paper  flat_sea\n");
    for (size_t i = 0; i < sizeof theta_deg / sizeof theta_deg[0]; i++) {
        const sea_dir view = sea_dir_fold(theta_deg[i] * deg, 0.0); /* toward the sensor */
        double eps, eps_paper, eps_flat;
        if ((st = sea_model_emissivity(model, &slopes, view, &eps, NULL, &err)) != SEA_OK ||
            (st = sea_emissivity(optics, SEA_EMIS_AUTO, N, &slopes, view, &eps_paper, &err)) !=
                SEA_OK ||
            (st = sea_emissivity(optics, SEA_EMIS_AUTO, N, &flat, view, &eps_flat, &err)) !=
                SEA_OK) {
            sea_optics_free(optics);
            sea_model_free(model);
            return failed("emissivity", st, &err);
        }
        printf("%9.1f  %10.6f  %9.6f  %8.6f\n", theta_deg[i], eps, eps_paper, eps_flat);
    }
    sea_model_free(model);
    sea_optics_free(optics);
    return 0;
}
