/* all_hits.c - the every-hit table and the models held against it (see
 * all_hits.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "all_hits.h"

int all_hits_read(const char *path, double x[][AH_COLS], int max)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "%s: cannot read\n", path);
        return -1;
    }
    char line[1024];
    int header = 0, n = 0, lineno = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        if (line[0] == '#')
            continue;
        if (!header) {
            line[strcspn(line, "\r\n")] = '\0';
            if (strcmp(line, AH_HEADER) != 0) {
                fprintf(stderr, "%s:%d: the header is not %s\n", path, lineno, AH_HEADER);
                goto fail;
            }
            header = 1;
            continue;
        }
        if (n == max) {
            fprintf(stderr, "%s:%d: more than %d rows\n", path, lineno, max);
            goto fail;
        }
        const char *p = line;
        char *end;
        for (int k = 0; k < AH_COLS; k++) {
            x[n][k] = strtod(p, &end);
            if (end == p || !isfinite(x[n][k]) || (k + 1 < AH_COLS && *end != ',')) {
                fprintf(stderr, "%s:%d: not %d numbers\n", path, lineno, AH_COLS);
                goto fail;
            }
            p = end + 1;
        }
        n++;
    }
    fclose(f);
    if (!header || n == 0) {
        fprintf(stderr, "%s: no rows\n", path);
        return -1;
    }
    return n;
fail:
    fclose(f);
    return -1;
}

int all_hits_wind_end(double x[][AH_COLS], int n, int a)
{
    int b = a;
    while (b < n && x[b][AH_WIND] == x[a][AH_WIND] && x[b][AH_SXX] == x[a][AH_SXX] &&
           x[b][AH_SYY] == x[a][AH_SYY] && x[b][AH_SXY] == x[a][AH_SXY] &&
           x[b][AH_PERIOD] == x[a][AH_PERIOD])
        b++;
    return b;
}

sea_status all_hits_indices(double complex N[2], sea_error *err)
{
    sea_water *w = NULL;
    sea_status s = sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, err);
    if (s == SEA_OK && (s = sea_water_index(w, 4e-6, &N[0], err)) == SEA_OK)
        s = sea_water_index(w, 10e-6, &N[1], err);
    sea_water_free(w);
    return s;
}

void all_hits_model_params(int k, sea_model_params *mp, const char **name)
{
    static const char *const names[AH_NMODELS] = { "paper",    "correlated", "two_scales",
                                                   "two_hits", "three_hits", "default" };
    sea_model_params_default(mp);
    *name = k >= 0 && k < AH_NMODELS ? names[k] : "?";
    switch (k) {
    case AH_PAPER:
        mp->shadowing = SEA_SHADOW_SMITH;
        mp->scales = 1;
        mp->reflections = 1;
        break;
    case AH_CORRELATED:
        mp->scales = 1;
        mp->reflections = 1;
        break;
    case AH_TWO_SCALES:
        mp->reflections = 1;
        break;
    case AH_TWO_HITS:
        mp->reflections = 2;
        break;
    case AH_THREE_HITS:
        mp->reflections = 3;
        break;
    default:
        break;
    }
}

sea_status all_hits_model_alloc(const sea_model_params *mp, const sea_spectrum *sp,
                                const sea_slope_stats *lr, double period, const double complex *N,
                                size_t n, all_hits_model *out, sea_error *err)
{
    memset(out, 0, sizeof *out);
    out->n = n;
    if (mp->reference || !(mp->tolerance > 2e-4))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "all_hits_model: tolerance %g or the reference (allowed: above 2e-4, "
                        "where the two scales' additions come from their table)",
                        mp->tolerance);
    sea_model_params p1 = *mp;
    p1.scales = 1;
    sea_status s = sea_model_alloc(&p1, sp, lr, NULL, N, n, NULL, &out->one, err);
    if (s != SEA_OK || mp->scales != 2)
        return s;
    sea_cov2 res, sub, total;
    double k;
    if (period > 0.0) {
        /* the surfaces' sea: half of their own slope variance resolved from
         * their longest wave (as test_two_scale_table splits them) */
        s = sea_spectrum_split_at(sp, 2.0 * M_PI / period, 0.5 * (lr->cov.xx + lr->cov.yy), &k,
                                  &res, &sub, err);
        total = lr->cov;
        sub = (sea_cov2){ total.xx - res.xx, total.yy - res.yy, total.xy - res.xy };
    } else {
        /* the spectrum's whole variance, as sea_model_alloc */
        s = sea_spectrum_split_half(sp, 0.0, &k, &res, &sub, err);
        total = (sea_cov2){ sub.xx + res.xx, sub.yy + res.yy, sub.xy + res.xy };
    }
    if (s == SEA_OK)
        s = sea_two_scale_table_alloc(sea_model_optics(out->one), N, n, sub, total, sp->wind_dir,
                                      &out->ts, err);
    if (s != SEA_OK)
        all_hits_model_free(out);
    return s;
}

sea_status all_hits_model_emissivity(const all_hits_model *m, const sea_slope_stats *st,
                                     sea_dir v, double *eps, sea_error *err)
{
    sea_status s = sea_model_emissivity(m->one, st, v, eps, NULL, err);
    if (s != SEA_OK || m->ts == NULL)
        return s;
    double d[SEA_SCENE_BAND_MAX];
    if ((s = sea_two_scale_delta(m->ts, v, st, d, err)) != SEA_OK)
        return s;
    /* sea_model_emissivity's composition (no directional sky) */
    for (size_t i = 0; i < m->n; i++)
        if (d[i] != 0.0)
            eps[i] = fmin(fmax(eps[i] + d[i], 0.0), 1.0);
    return SEA_OK;
}

void all_hits_model_free(all_hits_model *m)
{
    sea_two_scale_table_free(m->ts);
    sea_model_free(m->one);
    m->ts = NULL;
    m->one = NULL;
}
