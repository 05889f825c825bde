/* mc_model_refresh.c - recomputes the model columns of the ray-tracing
 * tables in tests/data after a change of the model, leaving the ray
 * tracer's columns (minutes of CPU to regenerate) as they are.  Built by
 * make check, not run by it:
 *
 *   tests/mc_model_refresh NOTE ../tests/data/mc_emissivity.csv \
 *       ../tests/data/mc_sea_emissivity.csv ../tests/data/mc_sea_full_emissivity.csv \
 *       ../tests/data/mc_sea_all_hits.csv
 *
 * Each file is rewritten in place (through a temporary file and a rename):
 * its comment lines are kept and "# NOTE" is added after them; every data
 * row keeps its text up to the model columns, which are recomputed as the
 * oracle programs compute them and written in their formats:
 *   mc_emissivity.csv (tests/mc_oracle.c): model = sea_emissivity, default
 *     rule, Smith's shadowing, at the row's wavelength and slope variances;
 *   mc_sea_*_emissivity.csv (tests/mc_sea_oracle.c): model_smith and
 *     model_corr, the same with Smith's and the correlated shadowing, at
 *     4 um and the row's covariance;
 *   mc_sea_all_hits.csv (tests/mc_sea_oracle.c -f means): those two at the
 *     row's wavelength, and model_default, the default model made for the
 *     row's wind's spectrum with the row's covariance as the low
 *     resolution and the indices of 4 and 10 um (as the oracle makes it).
 * tests/test_mc.c checks these columns against today's model to 1e-6, so
 * a change of the model shows there until this has been run. */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "seabake.h"

enum { LINE_MAX_LEN = 4096, MAX_FIELDS = 32 };

/* Splits line (modified) at commas into at most MAX_FIELDS fields. */
static int split(char *line, char *f[MAX_FIELDS])
{
    int n = 0;
    for (char *p = line; n < MAX_FIELDS;) {
        f[n++] = p;
        p = strchr(p, ',');
        if (p == NULL)
            break;
        *p++ = '\0';
    }
    return n;
}

static int refresh(const char *path, const char *note, const sea_optics *smith,
                   const sea_optics *corr, const sea_water *water)
{
    FILE *in = fopen(path, "r");
    if (in == NULL) {
        fprintf(stderr, "mc_model_refresh: cannot read %s\n", path);
        return 1;
    }
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *out = fopen(tmp, "w");
    if (out == NULL) {
        fclose(in);
        fprintf(stderr, "mc_model_refresh: cannot write %s\n", tmp);
        return 1;
    }
    char line[LINE_MAX_LEN], copy[LINE_MAX_LEN];
    int kind = 0, rows = 0, lineno = 0, bad = 0;
    double worst = 0.0;
    while (!bad && fgets(line, sizeof line, in)) {
        lineno++;
        if (line[0] == '#') {
            fputs(line, out);
            continue;
        }
        if (kind == 0) {
            /* the header: which table */
            fprintf(out, "# %s\n", note);
            fputs(line, out);
            if (strstr(line, ",model_smith,model_corr,model_default") != NULL)
                kind = 3;
            else if (strstr(line, ",model_smith,model_corr") != NULL)
                kind = 2;
            else if (strstr(line, ",multi,model") != NULL)
                kind = 1;
            else {
                fprintf(stderr, "mc_model_refresh: %s:%d: not a table of the oracles\n", path,
                        lineno);
                bad = 1;
            }
            continue;
        }
        line[strcspn(line, "\r\n")] = '\0';
        memcpy(copy, line, sizeof copy);
        char *f[MAX_FIELDS];
        const int n = split(copy, f);
        sea_error err;
        double complex N;
        if (kind == 1 && n == 17) {
            /* wind, wavelength, theta, phi, sxx, syy, ..., model */
            const double wl = atof(f[1]);
            const sea_slope_stats st = { { 0, 0 }, { atof(f[4]), atof(f[5]), 0 } };
            const sea_dir v = { atof(f[2]) * M_PI / 180, atof(f[3]) * M_PI / 180 };
            double model;
            if (sea_water_index(water, wl * 1e-6, &N, &err) != SEA_OK ||
                sea_emissivity(smith, SEA_EMIS_AUTO, N, &st, v, &model, &err) != SEA_OK) {
                fprintf(stderr, "mc_model_refresh: %s:%d: %s\n", path, lineno, err.msg);
                bad = 1;
                break;
            }
            worst = fmax(worst, fabs(model - atof(f[16])));
            *strrchr(line, ',') = '\0';
            fprintf(out, "%s,%.9f\n", line, model);
        } else if (kind == 2 && n == 10) {
            /* wind, seed, theta, phi, sxx, syy, sxy, eps1, model_smith, model_corr */
            const sea_slope_stats st = { { 0, 0 }, { atof(f[4]), atof(f[5]), atof(f[6]) } };
            const sea_dir v = { atof(f[2]) * M_PI / 180, atof(f[3]) * M_PI / 180 };
            double ms, mc;
            if (sea_water_index(water, 4e-6, &N, &err) != SEA_OK ||
                sea_emissivity(smith, SEA_EMIS_AUTO, N, &st, v, &ms, &err) != SEA_OK ||
                sea_emissivity(corr, SEA_EMIS_AUTO, N, &st, v, &mc, &err) != SEA_OK) {
                fprintf(stderr, "mc_model_refresh: %s:%d: %s\n", path, lineno, err.msg);
                bad = 1;
                break;
            }
            worst = fmax(worst, fmax(fabs(ms - atof(f[8])), fabs(mc - atof(f[9]))));
            *strrchr(line, ',') = '\0';
            *strrchr(line, ',') = '\0';
            fprintf(out, "%s,%.9f,%.9f\n", line, ms, mc);
        } else if (kind == 3 && n == 16) {
            /* wind, wavelength, theta, phi, sxx, syy, sxy, eps1, eps1_se, eps,
             * eps_se, multi, model_smith, model_corr, model_default, period_m */
            const sea_slope_stats st = { { 0, 0 }, { atof(f[4]), atof(f[5]), atof(f[6]) } };
            const sea_dir v = { atof(f[2]) * M_PI / 180, atof(f[3]) * M_PI / 180 };
            const double wl = atof(f[1]);
            double complex NN[2];
            double ms, mc, md[2];
            sea_spectrum sp;
            sea_model_params mp;
            sea_model_params_default(&mp);
            sea_model *m = NULL;
            if (!(wl == 4.0 || wl == 10.0)) {
                fprintf(stderr, "mc_model_refresh: %s:%d: wavelength %g (the table's: 4, 10)\n",
                        path, lineno, wl);
                bad = 1;
                break;
            }
            if (sea_water_index(water, 4e-6, &NN[0], &err) != SEA_OK ||
                sea_water_index(water, 10e-6, &NN[1], &err) != SEA_OK ||
                sea_emissivity(smith, SEA_EMIS_AUTO, NN[wl == 10.0], &st, v, &ms, &err) != SEA_OK ||
                sea_emissivity(corr, SEA_EMIS_AUTO, NN[wl == 10.0], &st, v, &mc, &err) != SEA_OK ||
                sea_spectrum_init(atof(f[0]), INFINITY, 0.0, &sp, &err) != SEA_OK ||
                sea_model_alloc(&mp, &sp, &st, NULL, NN, 2, NULL, &m, &err) != SEA_OK ||
                sea_model_emissivity(m, &st, v, md, NULL, &err) != SEA_OK) {
                fprintf(stderr, "mc_model_refresh: %s:%d: %s\n", path, lineno, err.msg);
                sea_model_free(m);
                bad = 1;
                break;
            }
            sea_model_free(m);
            const double mdef = md[wl == 10.0];
            worst = fmax(worst, fmax(fabs(ms - atof(f[12])),
                                     fmax(fabs(mc - atof(f[13])), fabs(mdef - atof(f[14])))));
            for (int c = 0; c < 4; c++)
                *strrchr(line, ',') = '\0';
            fprintf(out, "%s,%.9f,%.9f,%.9f,%s\n", line, ms, mc, mdef, f[15]);
        } else {
            fprintf(stderr, "mc_model_refresh: %s:%d: %d columns, not the table's\n", path,
                    lineno, n);
            bad = 1;
            break;
        }
        rows++;
    }
    fclose(in);
    if (fclose(out) != 0 || bad || rows == 0) {
        remove(tmp);
        if (!bad)
            fprintf(stderr, "mc_model_refresh: %s: no rows written\n", path);
        return 1;
    }
    if (rename(tmp, path) != 0) {
        remove(tmp);
        fprintf(stderr, "mc_model_refresh: cannot replace %s\n", path);
        return 1;
    }
    fprintf(stderr, "mc_model_refresh: %s: %d rows, model columns moved by at most %.3g\n", path,
            rows, worst);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: mc_model_refresh NOTE TABLE.csv...\n");
        return 2;
    }
    sea_init();
    sea_error err;
    sea_water *water = NULL;
    sea_optics *smith = NULL, *corr = NULL;
    if (sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &water, &err) != SEA_OK ||
        sea_optics_alloc(&smith, &err) != SEA_OK || sea_optics_alloc(&corr, &err) != SEA_OK) {
        fprintf(stderr, "mc_model_refresh: %s\n", err.msg);
        return 1;
    }
    sea_optics_set_shadowing(smith, SEA_SHADOW_SMITH);
    sea_optics_set_shadowing(corr, SEA_SHADOW_CORRELATED);
    int rc = 0;
    for (int a = 2; a < argc; a++)
        rc |= refresh(argv[a], argv[1], smith, corr, water);
    sea_optics_free(smith);
    sea_optics_free(corr);
    sea_water_free(water);
    return rc;
}
