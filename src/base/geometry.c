/* geometry.c - directions and projected slope statistics (Eq 6, 8). */
#include "config.h"

#include <math.h>

#include "seabake.h"

/* Relative slack allowed on xy^2 <= xx yy, for covariances that went
 * through a rotation and lost the last bits. */
static const double SEA_COV_PSD_REL_SLACK = 1e-12;

sea_dir sea_dir_fold(double theta_signed, double phi)
{
    sea_dir d = { fabs(theta_signed), phi };
    if (theta_signed < 0.0)
        d.phi += M_PI;
    d.phi = fmod(d.phi, 2.0 * M_PI);
    if (d.phi < 0.0)
        d.phi += 2.0 * M_PI;
    return d;
}

sea_status sea_slope_stats_check(const sea_slope_stats *st, sea_error *err)
{
    const sea_cov2 *c = &st->cov;
    if (!isfinite(st->mean.x) || !isfinite(st->mean.y))
        return sea_fail(err, SEA_ERR_DOMAIN, "mean slope (%g, %g) is not finite",
                        st->mean.x, st->mean.y);
    if (!isfinite(c->xx) || !isfinite(c->yy) || !isfinite(c->xy))
        return sea_fail(err, SEA_ERR_DOMAIN, "slope covariance is not finite");
    if (c->xx < 0.0 || c->yy < 0.0)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "slope variances must be >= 0 (got sxx = %g, syy = %g)", c->xx, c->yy);
    if (c->xy * c->xy > c->xx * c->yy * (1.0 + SEA_COV_PSD_REL_SLACK))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "slope covariance is not positive semi-definite: sxy^2 = %g > sxx*syy = %g",
                        c->xy * c->xy, c->xx * c->yy);
    return SEA_OK;
}

void sea_slope_project(const sea_slope_stats *st, double phi, double *m_X, double *s_X)
{
    const double c = cos(phi), s = sin(phi);
    const sea_cov2 *C = &st->cov;
    double var = C->xx * c * c + 2.0 * C->xy * s * c + C->yy * s * s;
    *m_X = st->mean.x * c + st->mean.y * s;
    *s_X = sqrt(var > 0.0 ? var : 0.0);
}
