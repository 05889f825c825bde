/* polar.c - polarisation: the Fresnel reflectances per polarisation, the
 * one-hit Stokes emissivity of a facet population and the Stokes
 * reflectivity of an unpolarised sky or sun (seabake.h, POLARISATION;
 * seabake-model(7), POLARISATION).
 *
 * The emissivity is sea_emissivity's average over the seen facets, on its
 * own nodes (sea_optics_facet_nodes): only what each node contributes
 * changes, from 1 - rho to the facet's emission in the sensor's frame.  A
 * facet at local incidence psi emits 1 - R_p along its local p (in its
 * plane of incidence, the plane of its normal n and v) and 1 - R_s along
 * its local s, incoherently: in the facet's frame, with its p axis first,
 *     (I, Q, U) = (1 - (R_s + R_p)/2, (R_s - R_p)/2, 0).
 * Its p axis is the projection of n across v, at angle chi from e_v, so the
 * sensor's frame sees Q cos 2chi and Q sin 2chi; cos chi and sin chi are
 * proportional to n.e_v and n.e_h, whence the rational forms below, free of
 * angles and of any sign convention for the p axis. */
#include "config.h"

#include <math.h>

#include "seabake.h"
#include "internal.h"

double sea_stokes_dolp(const sea_stokes *s)
{
    return s->i > 0.0 ? sqrt(s->q * s->q + s->u * s->u) / s->i : 0.0;
}

void sea_polar_fresnel(double cos_psi, double complex N, double *R_s, double *R_p)
{
    /* sea_fresnel_unpolarized's real arithmetic (water.c), so that the
     * mean of the two is its value: N^2 = A + iB, w = p + iq (p >= 0),
     * |r_s|^2 = ((c - p)^2 + q^2)/((c + p)^2 + q^2),
     * |r_p|^2 = ((Ac - p)^2 + (Bc - q)^2)/((Ac + p)^2 + (Bc + q)^2). */
    const double c = fmin(fmax(cos_psi, 0.0), 1.0);
    const double n = creal(N), k = cimag(N);
    const double A = (n - k) * (n + k), B = 2.0 * n * k;
    const double a = A - (1.0 - c * c), mod = sqrt(a * a + B * B);
    double p, q;
    if (a >= 0.0) {
        p = sqrt(0.5 * (mod + a));
        q = p > 0.0 ? 0.5 * B / p : 0.0;
    } else { /* (the sum cancels: q first) */
        q = copysign(sqrt(0.5 * (mod - a)), B);
        p = 0.5 * fabs(B) / fabs(q);
    }
    const double cs_m = c - p, cs_p = c + p;
    const double rs_den = cs_p * cs_p + q * q;
    const double Ac = A * c, Bc = B * c;
    const double rp_num = (Ac - p) * (Ac - p) + (Bc - q) * (Bc - q);
    const double rp_den = (Ac + p) * (Ac + p) + (Bc + q) * (Bc + q);
    /* a denominator is 0 only at grazing incidence on a lossless medium of
     * index 1: the limit is total reflection */
    *R_s = fmin(rs_den > 0.0 ? (cs_m * cs_m + q * q) / rs_den : 1.0, 1.0);
    *R_p = fmin(rp_den > 0.0 ? rp_num / rp_den : 1.0, 1.0);
}

/* sea_polar_plane_angle (internal.h): the plane of incidence of a facet
 * of normal proportional to (a, b) across v, a along e_v and b along e_h. */
void sea_polar_plane_angle(double a, double b, double *c2, double *s2)
{
    const double r2 = a * a + b * b;
    if (r2 > 0.0) {
        *c2 = (a - b) * (a + b) / r2;
        *s2 = 2.0 * a * b / r2;
    } else {
        *c2 = *s2 = 0.0;
    }
}

/* One facet's Stokes emission toward v, for SEA_EMIS_FULL's adaptive
 * quadrature (vals: 1 - rho, Q, U): its polarised part (R_s - R_p)/2 in
 * the sensor's frame; or with a sky, its reflection of the sky along its
 * mirror ray (zenith cosine 2 cos psi n_z - cos theta, n_z = 1 / sqrt(1 +
 * gamma^2)), R_s along s and R_p along p (vals: I, Q, U). */
typedef struct {
    double complex N;
    double sin_th, cos_th;
    const sea_sky *sky; /* NULL: the emission */
    size_t k;           /* the sky's index */
} facet_ctx;

static void facet_stokes(double gX, double gY, double cos_psi, void *ctx, double *vals)
{
    const facet_ctx *c = ctx;
    double Rs, Rp, c2, s2;
    sea_polar_fresnel(cos_psi, c->N, &Rs, &Rp);
    sea_polar_plane_angle(c->sin_th + gX * c->cos_th, -gY, &c2, &s2);
    if (c->sky == NULL) {
        const double pol = 0.5 * (Rs - Rp);
        vals[0] = 1.0 - sea_fresnel_unpolarized(cos_psi, c->N); /* (the reference's own) */
        vals[1] = pol * c2;
        vals[2] = pol * s2;
        return;
    }
    const double rz = 2.0 * cos_psi / sqrt(1.0 + gX * gX + gY * gY) - c->cos_th;
    const double L = sea_sky_radiance(c->sky, c->k, rz);
    vals[0] = 0.5 * (Rs + Rp) * L;
    vals[1] = 0.5 * (Rp - Rs) * L * c2;
    vals[2] = 0.5 * (Rp - Rs) * L * s2;
}

/* SEA_EMIS_FULL's adaptive average of facet_stokes for each index (sky
 * NULL: the emission). */
static sea_status full_stokes(const sea_optics *p, const double complex *N, size_t n,
                              const sea_slope_stats *st, sea_dir v, const sea_sky *sky,
                              sea_stokes *out, sea_error *err)
{
    for (size_t i = 0; i < n; i++) {
        facet_ctx c = { N[i], sin(v.theta), cos(v.theta), sky, i };
        double m[3];
        sea_status s = sea_optics_facet_mean_full(p, st, v, facet_stokes, &c, 3, m, err);
        if (s != SEA_OK)
            return s;
        out[i] = (sea_stokes){ m[0], m[1], m[2] };
    }
    return SEA_OK;
}

sea_status sea_polar_emissivity_n(const sea_optics *p, sea_emis_method method,
                                  const sea_emis_rule *rule, const double complex *N, size_t n,
                                  const sea_slope_stats *st, sea_dir v, sea_stokes *out,
                                  sea_error *err)
{
    sea_status s;
    const double sin_th = sin(v.theta), cos_th = cos(v.theta);
    if (rule == NULL && method == SEA_EMIS_FULL)
        return full_stokes(p, N, n, st, v, NULL, out, err);
    /* (64 KB: the renderer's threads have the emissivity's 80 KB of nodes
     * on their stacks already) */
    sea_facet_node nodes[SEA_FACET_NODES_MAX];
    double c2[SEA_FACET_NODES_MAX], s2[SEA_FACET_NODES_MAX];
    size_t count;
    int exact;
    if ((s = sea_optics_facet_nodes(p, method, rule, st, v, nodes, &count, &exact, err)) !=
        SEA_OK)
        return s;
    for (size_t q = 0; q < count; q++)
        sea_polar_plane_angle(sin_th + nodes[q].gX * cos_th, -nodes[q].gY, &c2[q], &s2[q]);
    for (size_t i = 0; i < n; i++) {
        double eI = 0.0, eQ = 0.0, eU = 0.0;
        for (size_t q = 0; q < count; q++) {
            double Rs, Rp;
            sea_polar_fresnel(nodes[q].cos_psi, N[i], &Rs, &Rp);
            const double w = nodes[q].w, pol = 0.5 * (Rs - Rp);
            eI += w * sea_optics_one_minus_rho(p, N[i], exact, nodes[q].cos_psi);
            eQ += w * pol * c2[q];
            eU += w * pol * s2[q];
        }
        out[i] = (sea_stokes){ eI, eQ, eU };
    }
    return SEA_OK;
}

sea_status sea_polar_emissivity(const sea_optics *p, sea_emis_method method,
                                const sea_emis_rule *rule, double complex N,
                                const sea_slope_stats *st, sea_dir v, sea_stokes *out,
                                sea_error *err)
{
    return sea_polar_emissivity_n(p, method, rule, &N, 1, st, v, out, err);
}

sea_status sea_polar_emissivity_multi_n(const sea_optics *p, sea_emis_method method,
                                        const sea_emis_rule *rule, const double complex *N,
                                        size_t n, const sea_slope_stats *st, sea_dir v,
                                        int reflections, sea_stokes *out, sea_error *err)
{
    sea_status s = sea_polar_emissivity_n(p, method, rule, N, n, st, v, out, err);
    if (s != SEA_OK || reflections == 1)
        return s;
    enum { BLOCK = 64 };
    for (size_t k0 = 0; k0 < n; k0 += BLOCK) {
        const size_t m = n - k0 < BLOCK ? n - k0 : BLOCK;
        double e[BLOCK], dq[BLOCK], du[BLOCK];
        if ((s = sea_emissivity_multi_n(p, method, rule, &N[k0], m, st, v, reflections, e,
                                        err)) != SEA_OK ||
            (s = sea_optics_polar_hits(p, method, rule, &N[k0], m, st, v, reflections, NULL, dq,
                                       du, err)) != SEA_OK)
            return s;
        for (size_t k = 0; k < m; k++)
            out[k0 + k] = (sea_stokes){ e[k], out[k0 + k].q + dq[k], out[k0 + k].u + du[k] };
    }
    return SEA_OK;
}

sea_status sea_polar_reflectivity_sky(const sea_optics *p, sea_emis_method method,
                                      const sea_emis_rule *rule, double complex N,
                                      const sea_slope_stats *st, sea_dir v, sea_stokes *out,
                                      sea_error *err)
{
    sea_stokes e;
    sea_status s = sea_polar_emissivity(p, method, rule, N, st, v, &e, err);
    if (s != SEA_OK)
        return s;
    /* each facet reflects what it does not emit, polarisation for
     * polarisation: R_s along s, R_p along p */
    *out = (sea_stokes){ 1.0 - e.i, -e.q, -e.u };
    return SEA_OK;
}

sea_status sea_polar_sky_n(const sea_optics *p, sea_emis_method method, const sea_emis_rule *rule,
                           const double complex *N, size_t n, const sea_slope_stats *st,
                           sea_dir v, const sea_sky *sky, sea_stokes *out, sea_error *err)
{
    sea_status s;
    const double sin_th = sin(v.theta), cos_th = cos(v.theta);
    if (rule == NULL && method == SEA_EMIS_FULL)
        return full_stokes(p, N, n, st, v, sky, out, err);
    sea_facet_node nodes[SEA_FACET_NODES_MAX];
    size_t count;
    int exact;
    if ((s = sea_optics_facet_nodes(p, method, rule, st, v, nodes, &count, &exact, err)) !=
        SEA_OK)
        return s;
    for (size_t i = 0; i < n; i++)
        out[i] = (sea_stokes){ 0.0, 0.0, 0.0 };
    for (size_t q = 0; q < count; q++) {
        const sea_facet_node *d = &nodes[q];
        double c2, s2;
        sea_polar_plane_angle(sin_th + d->gX * cos_th, -d->gY, &c2, &s2);
        const double rz = 2.0 * d->cos_psi / sqrt(1.0 + d->gX * d->gX + d->gY * d->gY) - cos_th;
        for (size_t i = 0; i < n; i++) {
            double Rs, Rp;
            sea_polar_fresnel(d->cos_psi, N[i], &Rs, &Rp);
            const double L = d->w * sea_sky_radiance(sky, i, rz), pol = 0.5 * (Rp - Rs) * L;
            out[i].i += 0.5 * (Rs + Rp) * L;
            out[i].q += pol * c2;
            out[i].u += pol * s2;
        }
    }
    return SEA_OK;
}

void sea_polar_reflectivity(double complex N, const sea_slope_stats *st, sea_dir inc,
                            sea_dir obs, sea_stokes *out)
{
    const double r = sea_reflectivity(N, st, inc, obs);
    *out = (sea_stokes){ r, 0.0, 0.0 };
    if (!(r > 0.0))
        return;
    /* the mirror facet's normal is along the half vector u_inc + u_obs (Eq 14a-b) */
    const double si = sin(inc.theta), ci = cos(inc.theta);
    const double so = sin(obs.theta), co = cos(obs.theta);
    const double h[3] = { si * cos(inc.phi) + so * cos(obs.phi),
                          si * sin(inc.phi) + so * sin(obs.phi), ci + co };
    const double hn = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    const double uo[3] = { so * cos(obs.phi), so * sin(obs.phi), co };
    const double cos_psi0 = (h[0] * uo[0] + h[1] * uo[1] + h[2] * uo[2]) / hn;
    const double e_h[3] = { -sin(obs.phi), cos(obs.phi), 0.0 };
    const double e_v[3] = { -co * cos(obs.phi), -co * sin(obs.phi), so };
    double Rs, Rp, c2, s2;
    sea_polar_fresnel(cos_psi0, N, &Rs, &Rp);
    sea_polar_plane_angle(h[0] * e_v[0] + h[1] * e_v[1] + h[2] * e_v[2],
                h[0] * e_h[0] + h[1] * e_h[1], &c2, &s2);
    const double pol = Rs + Rp > 0.0 ? r * (Rp - Rs) / (Rs + Rp) : 0.0;
    out->q = pol * c2;
    out->u = pol * s2;
}
