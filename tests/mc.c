/* mc.c - the Monte Carlo ray-tracing oracle (see mc.h). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <fftw3.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "indep.h"
#include "mc.h"

#ifdef _OPENMP
#include <omp.h>
#endif

/* ------------------------------------------------------------- surfaces */

static void surface_finish(mc_surface *s)
{
    int n = s->n;
    double det = s->A[0][0] * s->A[1][1] - s->A[0][1] * s->A[1][0];
    s->Ai[0][0] = s->A[1][1] / det;
    s->Ai[0][1] = -s->A[0][1] / det;
    s->Ai[1][0] = -s->A[1][0] / det;
    s->Ai[1][1] = s->A[0][0] / det;
    double lo = INFINITY, hi = -INFINITY;
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int i1 = (i + 1) % n, j1 = (j + 1) % n;
            double h00 = s->h[j * n + i], h10 = s->h[j * n + i1];
            double h01 = s->h[j1 * n + i], h11 = s->h[j1 * n + i1];
            lo = fmin(lo, h00);
            hi = fmax(hi, h00);
            double g[2][2] = { { h10 - h00, h01 - h00 }, { h11 - h01, h11 - h10 } };
            for (int t = 0; t < 2; t++) {
                double gx = s->Ai[0][0] * g[t][0] + s->Ai[1][0] * g[t][1];
                double gy = s->Ai[0][1] * g[t][0] + s->Ai[1][1] * g[t][1];
                sx += gx;
                sy += gy;
                sxx += gx * gx;
                syy += gy * gy;
                sxy += gx * gy;
            }
        }
    double m = 2.0 * n * n;
    s->hmin = lo;
    s->hmax = hi;
    s->mean.x = sx / m;
    s->mean.y = sy / m;
    s->cov.xx = sxx / m - s->mean.x * s->mean.x;
    s->cov.yy = syy / m - s->mean.y * s->mean.y;
    s->cov.xy = sxy / m - s->mean.x * s->mean.y;
}

int mc_surface_from_heights(mc_surface *s, int n, const double *h, const double A[2][2])
{
    memset(s, 0, sizeof *s);
    if (n < 2 || A[0][0] * A[1][1] - A[0][1] * A[1][0] == 0)
        return -1;
    s->n = n;
    s->h = malloc(sizeof(double) * n * n);
    if (s->h == NULL)
        return -1;
    memcpy(s->h, h, sizeof(double) * n * n);
    memcpy(s->A, A, sizeof s->A);
    surface_finish(s);
    return 0;
}

/* Square root of a symmetric positive definite 2x2 matrix [[a, b], [b, c]]. */
static void sqrt2(double a, double b, double c, double r[2][2])
{
    double sd = sqrt(a * c - b * b), t = sqrt(a + c + 2 * sd);
    r[0][0] = (a + sd) / t;
    r[1][1] = (c + sd) / t;
    r[0][1] = r[1][0] = b / t;
}

static void mul2(const double a[2][2], const double b[2][2], double r[2][2])
{
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
}

/* n x n white noise of unit variance (seed), its spectrum multiplied by
 * amplitude(kx, ky) (radians per cell) and its mean removed, back in h. */
int mc_filtered_noise(int n, unsigned long seed, double (*amplitude)(double kx, double ky, void *ctx),
                      void *ctx, double *h)
{
    int nc = n / 2 + 1;
    fftw_complex *H = fftw_malloc(sizeof(fftw_complex) * n * nc);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (H == NULL || rng == NULL) {
        fftw_free(H);
        gsl_rng_free(rng);
        return -1;
    }
    fftw_plan fwd = fftw_plan_dft_r2c_2d(n, n, h, H, FFTW_ESTIMATE);
    fftw_plan inv = fftw_plan_dft_c2r_2d(n, n, H, h, FFTW_ESTIMATE);
    gsl_rng_set(rng, seed);
    for (long k = 0; k < (long)n * n; k++)
        h[k] = gsl_ran_gaussian_ziggurat(rng, 1.0);
    fftw_execute(fwd);
    for (int j = 0; j < n; j++) {
        double ky = 2 * M_PI * (j <= n / 2 ? j : j - n) / n;
        for (int i = 0; i < nc; i++) {
            double kx = 2 * M_PI * i / n;
            double f = amplitude(kx, ky, ctx);
            H[j * nc + i][0] *= f;
            H[j * nc + i][1] *= f;
        }
    }
    H[0][0] = H[0][1] = 0; /* zero mean height */
    fftw_execute(inv);
    fftw_destroy_plan(fwd);
    fftw_destroy_plan(inv);
    gsl_rng_free(rng);
    fftw_free(H);
    return 0;
}

/* The Gaussian correlation's amplitude: exp(-k^T Q^-1 k / 8). */
typedef struct {
    double qxx, qyy, qxy;
} gauss_filter;

static double gauss_amplitude(double kx, double ky, void *ctx)
{
    const gauss_filter *g = ctx;
    return exp(-(g->qxx * kx * kx + 2 * g->qxy * kx * ky + g->qyy * ky * ky) / 8);
}

int mc_next_option(int argc, char **argv, int *a, int *opt, const char **value)
{
    if (*a >= argc)
        return 0;
    const char *o = argv[*a];
    if (*a + 1 >= argc || o[0] != '-' || strlen(o) != 2)
        return -1;
    *opt = o[1];
    *value = argv[*a + 1];
    *a += 2;
    return 1;
}

int mc_grid_options_parse(int argc, char **argv, mc_grid_options *o)
{
    int at = 1, opt, r;
    const char *v;
    while ((r = mc_next_option(argc, argv, &at, &opt, &v)) > 0) {
        switch (opt) {
        case 'n': o->n = atoi(v); break;
        case 'l': o->ell = atof(v); break;
        case 's': o->seeds = atoi(v); break;
        case 'r': o->rays = atol(v); break;
        case 'S': o->seed0 = strtoul(v, NULL, 10); break;
        case 'w': o->nw = mc_parse_list(v, o->winds, MC_LIST_MAX); break;
        case 'L': o->nl = mc_parse_list(v, o->wls, MC_MAXWL); break;
        case 't': o->nt = mc_parse_list(v, o->ths, MC_LIST_MAX); break;
        case 'p': o->np = mc_parse_list(v, o->phs, MC_LIST_MAX); break;
        case 'o': o->outpath = v; break;
        default: return -1;
        }
    }
    if (r < 0 || o->n < 8 || o->seeds < 2 || o->rays < 1 || o->nw < 1 || o->nl < 1 ||
        o->nt < 1 || o->np < 1 || !(o->ell > 0))
        return -1;
    return 0;
}

int mc_threads(void)
{
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

void mc_mean_se(const double *x, int k, double *mean, double *se)
{
    double a = 0.0, q = 0.0;
    for (int s = 0; s < k; s++)
        a += x[s] / k;
    for (int s = 0; s < k; s++)
        q += (x[s] - a) * (x[s] - a) / (k - 1);
    *mean = a;
    *se = sqrt(q / k);
}

int mc_parse_list(const char *s, double *out, int max)
{
    int k = 0;
    char *end;
    while (*s && k < max) {
        out[k++] = strtod(s, &end);
        if (end == s)
            return -1;
        s = *end == ',' ? end + 1 : end;
    }
    return *s ? -1 : k;
}

int mc_surface_gaussian(mc_surface *s, int n, double ell, const sea_cov2 *C, unsigned long seed)
{
    memset(s, 0, sizeof *s);
    double tr = C->xx + C->yy, det = C->xx * C->yy - C->xy * C->xy;
    const double ID[2][2] = { { 1, 0 }, { 0, 1 } };
    if (n < 4 || n % 2 || !(ell > 0))
        return -1;
    if (C->xx == 0 && C->yy == 0 && C->xy == 0) {
        double *z = calloc((size_t)n * n, sizeof *z);
        int r = z == NULL ? -1 : mc_surface_from_heights(s, n, z, ID);
        free(z);
        return r;
    }
    if (!(C->xx > 0 && C->yy > 0 && det > 0))
        return -1;
    double *h = fftw_malloc(sizeof(double) * n * n);
    /* Q = C / (ell^2 tr C / 2): correlation exp(-r^T Q r) (index units),
     * amplitude spectrum sqrt(exp(-k^T Q^-1 k / 4)); Q^-1 = ell^2 (tr/2) C^-1. */
    double q = ell * ell * tr / 2 / det;
    gauss_filter g = { q * C->yy, q * C->xx, -q * C->xy };
    if (h == NULL || mc_filtered_noise(n, seed, gauss_amplitude, &g, h)) {
        fftw_free(h);
        return -1;
    }
    /* Measure the index-space slope covariance M with A = I, then
     * A = C^-1/2 M^1/2 gives A^-T M A^-1 = C. */
    int r = mc_surface_from_heights(s, n, h, ID);
    fftw_free(h);
    if (r)
        return r;
    double M[2][2], Ci[2][2], Ch[2][2];
    sqrt2(s->cov.xx, s->cov.xy, s->cov.yy, M);
    sqrt2(C->xx, C->xy, C->yy, Ch);
    double dch = Ch[0][0] * Ch[1][1] - Ch[0][1] * Ch[1][0];
    Ci[0][0] = Ch[1][1] / dch;
    Ci[1][1] = Ch[0][0] / dch;
    Ci[0][1] = Ci[1][0] = -Ch[0][1] / dch;
    mul2(Ci, M, s->A);
    surface_finish(s);
    return 0;
}

void mc_surface_free(mc_surface *s)
{
    if (s) {
        free(s->h);
        s->h = NULL;
    }
}

/* ---------------------------------------------------------------- rays */

static inline uint64_t splitmix(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static inline double uniform01(uint64_t *x)
{
    return (splitmix(x) >> 11) * 0x1.0p-53;
}

typedef struct {
    double t;       /* path length to the hit */
    double gx, gy;  /* index-space gradient of the triangle hit */
    long tri;       /* its id: (cell << 1) | upper */
} hit;

/* First hit of the ray o + t d (index-space horizontal, physical z; d's
 * horizontal part is A^-1 of a unit physical direction's), t > 0, skipping
 * triangle `skip`.  Returns 1 on a hit, 0 on escape, -1 when the ray is
 * found below the surface (a leak) or the path limit is reached. */
static int first_hit(const mc_surface *s, const double o[3], const double d[3], long skip,
                     hit *out)
{
    const int n = s->n;
    long ci = (long)floor(o[0]), cj = (long)floor(o[1]);
    int sx = d[0] > 0 ? 1 : -1, sy = d[1] > 0 ? 1 : -1;
    double tdx = d[0] != 0 ? 1.0 / fabs(d[0]) : INFINITY;
    double tdy = d[1] != 0 ? 1.0 / fabs(d[1]) : INFINITY;
    double tmx = d[0] != 0 ? ((d[0] > 0 ? ci + 1 : ci) - o[0]) / d[0] : INFINITY;
    double tmy = d[1] != 0 ? ((d[1] > 0 ? cj + 1 : cj) - o[1]) / d[1] : INFINITY;
    /* below hmin a ray must have hit, above hmax it has escaped: bound t
     * there (so that vertical rays end) */
    double span = s->hmax - s->hmin + 1;
    double tlim = d[2] < 0   ? (s->hmin - span - o[2]) / d[2]
                  : d[2] > 0 ? (s->hmax + span - o[2]) / d[2]
                             : INFINITY;
    double t0 = 0;
    const long max_steps = 64L * n;
    for (long step = 0; step < max_steps; step++) {
        double t1 = fmin(fmin(tmx, tmy), tlim);
        double z0 = o[2] + t0 * d[2];
        if (d[2] >= 0 && z0 > s->hmax)
            return 0;
        int wi = (int)(((ci % n) + n) % n), wj = (int)(((cj % n) + n) % n);
        int i1 = wi + 1 == n ? 0 : wi + 1, j1 = wj + 1 == n ? 0 : wj + 1;
        double h00 = s->h[wj * n + wi], h10 = s->h[wj * n + i1];
        double h01 = s->h[j1 * n + wi], h11 = s->h[j1 * n + i1];
        long cell = (long)wj * n + wi;
        /* u + v - 1 along the segment; split at the diagonal */
        double u0 = o[0] - ci, v0 = o[1] - cj;
        double w0 = u0 + t0 * d[0] + v0 + t0 * d[1] - 1;
        double w1 = u0 + t1 * d[0] + v0 + t1 * d[1] - 1;
        double ta[2], tb[2];
        int up[2], np = 0;
        if ((w0 < 0) != (w1 < 0) && d[0] + d[1] != 0) {
            double td = (1 - u0 - v0) / (d[0] + d[1]);
            td = fmin(fmax(td, t0), t1);
            ta[0] = t0, tb[0] = td, up[0] = w0 >= 0;
            ta[1] = td, tb[1] = t1, up[1] = w1 >= 0;
            np = 2;
        } else {
            ta[0] = t0, tb[0] = t1, up[0] = (w0 + w1) >= 0;
            np = 1;
        }
        for (int p = 0; p < np; p++) {
            long tri = (cell << 1) | up[p];
            if (tri == skip || !(tb[p] > ta[p]) || tb[p] <= 0)
                continue;
            double gx, gy, zc; /* plane: z = zc + gx u + gy v */
            if (up[p]) {
                gx = h11 - h01, gy = h11 - h10;
                zc = h11 - gx - gy;
            } else {
                gx = h10 - h00, gy = h01 - h00;
                zc = h00;
            }
            double fa = o[2] + ta[p] * d[2] - (zc + gx * (u0 + ta[p] * d[0]) + gy * (v0 + ta[p] * d[1]));
            double fb = o[2] + tb[p] * d[2] - (zc + gx * (u0 + tb[p] * d[0]) + gy * (v0 + tb[p] * d[1]));
            if (fb < 0) {
                double t = fa > 0 ? ta[p] + (tb[p] - ta[p]) * (fa / (fa - fb)) : ta[p];
                out->t = t;
                out->gx = gx;
                out->gy = gy;
                out->tri = tri;
                return 1;
            }
        }
        if (t1 == tlim) /* escaped, or below the surface without a hit: a leak */
            return d[2] > 0 ? 0 : -1;
        if (d[2] > 0 && o[2] + t1 * d[2] > s->hmax)
            return 0;
        t0 = t1;
        if (tmx < tmy) {
            ci += sx;
            tmx += tdx;
        } else {
            cj += sy;
            tmy += tdy;
        }
    }
    return -1;
}

int mc_first_hit(const mc_surface *s, const double o[3], const double d[3], long skip,
                 mc_hit *out)
{
    hit h;
    const int k = first_hit(s, o, d, skip, &h);
    if (k == 1)
        *out = (mc_hit){ h.t, h.gx, h.gy, h.tri };
    return k;
}

typedef struct {
    double complex x, y, z;
} cvec;

static inline void cross(const double a[3], const double b[3], double r[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double cnorm2(const cvec *e)
{
    return creal(e->x * conj(e->x) + e->y * conj(e->y) + e->z * conj(e->z));
}

enum { CHUNK = 4096, MAX_BOUNCES = 1000 };
#define W_MIN 1e-6

int mc_trace(const mc_surface *s, sea_dir v, const double complex *N, int nwl, long rays,
             unsigned long seed, mc_tally *out)
{
    memset(out, 0, sizeof *out);
    if (nwl < 1 || nwl > MC_MAXWL || rays < 1 || !(v.theta >= 0 && v.theta < M_PI / 2))
        return -1;
    out->rays = rays;
    out->nwl = nwl;
    long nchunk = (rays + CHUNK - 1) / CHUNK;
    mc_tally *part = calloc((size_t)nchunk, sizeof *part);
    if (part == NULL)
        return -1;
    const double V[3] = { sin(v.theta) * cos(v.phi), sin(v.theta) * sin(v.phi), cos(v.theta) };
    const int n = s->n;
#pragma omp parallel for schedule(dynamic, 1)
    for (long c = 0; c < nchunk; c++) {
        mc_tally *T = &part[c];
        long r_end = (c + 1) * CHUNK < rays ? (c + 1) * CHUNK : rays;
        for (long r = c * CHUNK; r < r_end; r++) {
            uint64_t st = (uint64_t)seed * 0x2545f4914f6cdd1dULL ^ (uint64_t)r;
            splitmix(&st);
            double D[3] = { -V[0], -V[1], -V[2] }; /* physical unit direction */
            double o[3] = { n * uniform01(&st), n * uniform01(&st), s->hmax };
            /* two orthogonal polarisation states per index */
            double e1[3], e2[3], ax[3] = { 0, 0, 1 };
            if (fabs(D[2]) > 0.9)
                ax[0] = 1, ax[2] = 0;
            cross(D, ax, e1);
            double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
            for (int k = 0; k < 3; k++)
                e1[k] /= l;
            cross(D, e1, e2);
            cvec E[MC_MAXWL][2];
            double w[MC_MAXWL], wpol[MC_MAXWL], absorbed[MC_MAXWL], apol[MC_MAXWL];
            for (int k = 0; k < nwl; k++) {
                E[k][0] = (cvec){ e1[0], e1[1], e1[2] };
                E[k][1] = (cvec){ e2[0], e2[1], e2[2] };
                w[k] = wpol[k] = 1;
                absorbed[k] = apol[k] = 0;
            }
            long skip = -1;
            int bounces = 0, escaped = 0;
            for (;;) {
                double d[3] = { s->Ai[0][0] * D[0] + s->Ai[0][1] * D[1],
                                s->Ai[1][0] * D[0] + s->Ai[1][1] * D[1], D[2] };
                hit H;
                int k = first_hit(s, o, d, skip, &H);
                if (k == 0 && bounces > 0) { /* escaped upward */
                    escaped = 1;
                    for (int q = 0; q < nwl; q++)
                        T->escaped[q][bounces < MC_NBOUNCE ? bounces : MC_NBOUNCE - 1] += w[q];
                    break;
                }
                if (k <= 0) { /* a leak, the path limit, or a beam ray missing the surface */
                    T->leaks++;
                    T->stopped++;
                    break;
                }
                bounces++;
                /* physical normal of the triangle */
                double gx = s->Ai[0][0] * H.gx + s->Ai[1][0] * H.gy;
                double gy = s->Ai[0][1] * H.gx + s->Ai[1][1] * H.gy;
                double ln = sqrt(1 + gx * gx + gy * gy);
                double nn[3] = { -gx / ln, -gy / ln, 1 / ln };
                double cpsi = -(D[0] * nn[0] + D[1] * nn[1] + D[2] * nn[2]);
                cpsi = fmin(fmax(cpsi, 0.0), 1.0);
                double R[3] = { D[0] + 2 * cpsi * nn[0], D[1] + 2 * cpsi * nn[1],
                                D[2] + 2 * cpsi * nn[2] };
                /* s and p unit vectors, p = k x s for both waves */
                double sv[3], pi_[3], pr[3];
                cross(D, nn, sv);
                double ls = sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]);
                if (ls < 1e-12) { /* normal incidence: any s */
                    double a2[3] = { 1, 0, 0 };
                    if (fabs(nn[0]) > 0.9)
                        a2[0] = 0, a2[1] = 1;
                    cross(a2, nn, sv);
                    ls = sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]);
                }
                for (int q = 0; q < 3; q++)
                    sv[q] /= ls;
                cross(D, sv, pi_);
                cross(R, sv, pr);
                if (bounces == 1)
                    T->first_up += gx > 0;
                else if (bounces == 2)
                    T->multi++;
                double wmax = 0;
                for (int q = 0; q < nwl; q++) {
                    /* the tracer's own Fresnel (tests/indep.c): Born & Wolf's
                     * real form for the unpolarised weight, the amplitudes
                     * for the polarised one */
                    double rho = indep_fresnel(cpsi, creal(N[q]), cimag(N[q]));
                    if (bounces == 1) {
                        T->eps1[q] += 1 - rho;
                        T->eps1_sq[q] += (1 - rho) * (1 - rho);
                    }
                    absorbed[q] += w[q] * (1 - rho);
                    w[q] *= rho;
                    double complex rs, rp;
                    indep_fresnel_amplitudes(cpsi, N[q], &rs, &rp);
                    double before = 0, after = 0;
                    for (int m = 0; m < 2; m++) {
                        cvec *e = &E[q][m];
                        before += cnorm2(e);
                        double complex as = e->x * sv[0] + e->y * sv[1] + e->z * sv[2];
                        double complex ap = e->x * pi_[0] + e->y * pi_[1] + e->z * pi_[2];
                        as *= rs;
                        ap *= rp;
                        e->x = as * sv[0] + ap * pr[0];
                        e->y = as * sv[1] + ap * pr[1];
                        e->z = as * sv[2] + ap * pr[2];
                        after += cnorm2(e);
                    }
                    apol[q] += (before - after) / 2;
                    wpol[q] = after / 2;
                    wmax = fmax(wmax, fmax(w[q], wpol[q]));
                }
                if (wmax < W_MIN || bounces >= MAX_BOUNCES) {
                    T->stopped += bounces >= MAX_BOUNCES;
                    break;
                }
                /* continue from the hit point, wrapped into the period */
                double oi = o[0] + H.t * d[0], oj = o[1] + H.t * d[1];
                o[0] = oi - n * floor(oi / n);
                o[1] = oj - n * floor(oj / n);
                o[2] += H.t * d[2];
                long fi = (long)floor(o[0]), fj = (long)floor(o[1]);
                if (fi >= n) /* rounding at the far edge */
                    o[0] = fi = 0;
                if (fj >= n)
                    o[1] = fj = 0;
                /* the reflected ray cannot hit its own plane again */
                skip = (fj * n + fi) == (H.tri >> 1) ? H.tri : -1;
                double lr = sqrt(R[0] * R[0] + R[1] * R[1] + R[2] * R[2]);
                for (int q = 0; q < 3; q++)
                    D[q] = R[q] / lr;
            }
            for (int q = 0; q < nwl; q++) {
                if (!escaped) { /* stopped: the weight left counts as absorbed */
                    T->residual[q] += w[q];
                    absorbed[q] += w[q];
                    apol[q] += wpol[q];
                    w[q] = wpol[q] = 0;
                }
                T->eps[q] += absorbed[q];
                T->eps_sq[q] += absorbed[q] * absorbed[q];
                T->eps_pol[q] += apol[q];
                double err = fmax(fabs(absorbed[q] + w[q] - 1), fabs(apol[q] + wpol[q] - 1));
                if (err > T->max_energy_err)
                    T->max_energy_err = err;
            }
        }
    }
    for (long c = 0; c < nchunk; c++) {
        const mc_tally *T = &part[c];
        for (int q = 0; q < nwl; q++) {
            out->eps1[q] += T->eps1[q];
            out->eps[q] += T->eps[q];
            out->eps_pol[q] += T->eps_pol[q];
            out->eps1_sq[q] += T->eps1_sq[q];
            out->eps_sq[q] += T->eps_sq[q];
            out->residual[q] += T->residual[q];
            for (int b = 0; b < MC_NBOUNCE; b++)
                out->escaped[q][b] += T->escaped[q][b];
        }
        out->max_energy_err = fmax(out->max_energy_err, T->max_energy_err);
        out->first_up += T->first_up;
        out->multi += T->multi;
        out->leaks += T->leaks;
        out->stopped += T->stopped;
    }
    free(part);
    return 0;
}
