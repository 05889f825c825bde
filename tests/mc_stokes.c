/* mc_stokes.c - the ray tracer's Stokes vectors (see mc_stokes.h). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "indep.h"
#include "mc_stokes.h"

/* mc_trace's random stream (mc.c): the same start points for the same seed */
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

static inline void cross(const double a[3], const double b[3], double r[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Stokes (I, Q, U, V) of the coherency matrix C = E E^H of the components
 * (E_1, E_2) in a frame (f_1, f_2): I = |E_1|^2 + |E_2|^2,
 * Q = |E_1|^2 - |E_2|^2, U = 2 Re(E_1 E_2*), V = -2 Im(E_1 E_2*); so U is
 * the radiance along (f_1 + f_2)/sqrt 2 minus that along (f_1 - f_2)/sqrt 2. */
static void coherency_of(const double S[4], double complex C[2][2])
{
    C[0][0] = 0.5 * (S[0] + S[1]);
    C[1][1] = 0.5 * (S[0] - S[1]);
    C[0][1] = 0.5 * (S[2] - I * S[3]);
    C[1][0] = 0.5 * (S[2] + I * S[3]);
}

static void stokes_of(const double complex C[2][2], double S[4])
{
    S[0] = creal(C[0][0] + C[1][1]);
    S[1] = creal(C[0][0] - C[1][1]);
    S[2] = 2.0 * creal(C[0][1]);
    S[3] = -2.0 * cimag(C[0][1]);
}

/* The Mueller matrix of the Jones matrix J: column k is J C J^H for the
 * k-th unit Stokes vector (the map is linear in C). */
static void mueller_of(const double complex J[2][2], double M[4][4])
{
    for (int k = 0; k < 4; k++) {
        double S[4] = { 0, 0, 0, 0 }, T[4];
        S[k] = 1.0;
        double complex C[2][2], JC[2][2], D[2][2];
        coherency_of(S, C);
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++)
                JC[a][b] = J[a][0] * C[0][b] + J[a][1] * C[1][b];
        for (int a = 0; a < 2; a++)
            for (int b = 0; b < 2; b++)
                D[a][b] = JC[a][0] * conj(J[b][0]) + JC[a][1] * conj(J[b][1]);
        stokes_of(D, T);
        for (int r = 0; r < 4; r++)
            M[r][k] = T[r];
    }
}

/* The rotation from frame (a1, a2) into frame (b1, b2) across the same
 * direction: E_b = R E_a with R_kl = b_k . a_l. */
static void rotation_of(const double a1[3], const double a2[3], const double b1[3],
                        const double b2[3], double M[4][4])
{
    const double complex J[2][2] = { { dot(b1, a1), dot(b1, a2) }, { dot(b2, a1), dot(b2, a2) } };
    mueller_of(J, M);
}

static void mat_mul(const double A[4][4], const double B[4][4], double R[4][4])
{
    double T[4][4];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double acc = 0.0;
            for (int k = 0; k < 4; k++)
                acc += A[i][k] * B[k][j];
            T[i][j] = acc;
        }
    memcpy(R, T, sizeof T);
}

static void mat_vec_add(const double A[4][4], const double x[4], double y[4])
{
    for (int i = 0; i < 4; i++)
        y[i] += A[i][0] * x[0] + A[i][1] * x[1] + A[i][2] * x[2] + A[i][3] * x[3];
}

typedef struct {
    double complex x[3];
} cvec3;

static double cnorm2(const cvec3 *e)
{
    double s = 0.0;
    for (int k = 0; k < 3; k++)
        s += creal(e->x[k] * conj(e->x[k]));
    return s;
}

enum { CHUNK = 4096, MAX_HITS = 1000 };
/* A ray whose unpolarised throughput falls below this is stopped (the rest
 * counted as black: out by at most this much per ray). */
static const double W_STOP = 1e-6;

int mc_trace_stokes(const mc_surface *s, sea_dir v, const double complex *N, int nwl,
                    long rays, unsigned long seed, mc_stokes_tally *out)
{
    memset(out, 0, sizeof *out);
    if (nwl < 1 || nwl > MC_MAXWL || rays < 1 || !(v.theta >= 0 && v.theta < M_PI / 2))
        return -1;
    out->rays = rays;
    out->nwl = nwl;
    const long nchunk = (rays + CHUNK - 1) / CHUNK;
    mc_stokes_tally *part = calloc((size_t)nchunk, sizeof *part);
    if (part == NULL)
        return -1;
    const double V[3] = { sin(v.theta) * cos(v.phi), sin(v.theta) * sin(v.phi), cos(v.theta) };
    /* the sensor's frame (seabake.h, POLARISATION) */
    const double e_h[3] = { -sin(v.phi), cos(v.phi), 0.0 };
    double e_v[3];
    cross(V, e_h, e_v);
    const int n = s->n;
#pragma omp parallel for schedule(dynamic, 1)
    for (long c = 0; c < nchunk; c++) {
        mc_stokes_tally *T = &part[c];
        const long r_end = (c + 1) * CHUNK < rays ? (c + 1) * CHUNK : rays;
        for (long r = c * CHUNK; r < r_end; r++) {
            uint64_t st = (uint64_t)seed * 0x2545f4914f6cdd1dULL ^ (uint64_t)r;
            splitmix(&st);
            double D[3] = { -V[0], -V[1], -V[2] };
            double o[3] = { n * uniform01(&st), n * uniform01(&st), s->hmax };
            double P[MC_MAXWL][4][4], S[MC_MAXWL][4];
            cvec3 Fv[MC_MAXWL], Fh[MC_MAXWL];
            double f1[3], f2[3]; /* the current segment's frame */
            memcpy(f1, e_v, sizeof f1);
            memcpy(f2, e_h, sizeof f2);
            for (int q = 0; q < nwl; q++) {
                memset(P[q], 0, sizeof P[q]);
                for (int k = 0; k < 4; k++)
                    P[q][k][k] = 1.0, S[q][k] = 0.0;
                for (int k = 0; k < 3; k++)
                    Fv[q].x[k] = e_v[k], Fh[q].x[k] = e_h[k];
            }
            long skip = -1;
            int hits = 0, escaped = 0;
            for (;;) {
                const double d[3] = { s->Ai[0][0] * D[0] + s->Ai[0][1] * D[1],
                                      s->Ai[1][0] * D[0] + s->Ai[1][1] * D[1], D[2] };
                mc_hit H;
                const int k = mc_first_hit(s, o, d, skip, &H);
                if (k == 0 && hits > 0) {
                    escaped = 1;
                    break;
                }
                if (k <= 0) {
                    T->leaks++;
                    T->stopped++;
                    break;
                }
                hits++;
                if (hits == 2)
                    T->multi++;
                const double gx = s->Ai[0][0] * H.gx + s->Ai[1][0] * H.gy;
                const double gy = s->Ai[0][1] * H.gx + s->Ai[1][1] * H.gy;
                const double ln = sqrt(1 + gx * gx + gy * gy);
                const double nn[3] = { -gx / ln, -gy / ln, 1 / ln };
                const double cpsi = fmin(fmax(-dot(D, nn), 0.0), 1.0);
                double R[3] = { D[0] + 2 * cpsi * nn[0], D[1] + 2 * cpsi * nn[1],
                                D[2] + 2 * cpsi * nn[2] };
                const double lr = sqrt(dot(R, R));
                for (int m = 0; m < 3; m++)
                    R[m] /= lr;
                /* s across the plane of incidence (any at normal incidence) */
                double sv[3];
                cross(D, nn, sv);
                double ls = sqrt(dot(sv, sv));
                if (ls < 1e-12) {
                    double a2[3] = { 1, 0, 0 };
                    if (fabs(nn[0]) > 0.9)
                        a2[0] = 0, a2[1] = 1;
                    cross(a2, nn, sv);
                    ls = sqrt(dot(sv, sv));
                }
                for (int m = 0; m < 3; m++)
                    sv[m] /= ls;
                /* p = k x s for each wave: the traced ray (k = D in, R out)
                 * and the light emitted or reflected back (k = -R in, -D out) */
                double p_in[3], p_out[3], mD[3] = { -D[0], -D[1], -D[2] },
                                         mR[3] = { -R[0], -R[1], -R[2] };
                double l_in[3], l_out[3];
                cross(D, sv, p_in);
                cross(R, sv, p_out);
                cross(mR, sv, l_in);
                cross(mD, sv, l_out);
                double B[4][4];
                rotation_of(l_out, sv, f1, f2, B);
                double pmax = 0.0;
                for (int q = 0; q < nwl; q++) {
                    double complex rs, rp;
                    indep_fresnel_amplitudes(cpsi, N[q], &rs, &rp);
                    const double Rs = creal(rs * conj(rs)), Rp = creal(rp * conj(rp));
                    /* forward: this facet's emission, then its reflection */
                    const double Se[4] = { 1.0 - 0.5 * (Rs + Rp), 0.5 * (Rs - Rp), 0.0, 0.0 };
                    double PB[4][4];
                    mat_mul(P[q], B, PB);
                    if (hits == 1) {
                        double s1[4] = { 0, 0, 0, 0 };
                        mat_vec_add(PB, Se, s1);
                        for (int m = 0; m < 4; m++)
                            T->e1[q][m] += s1[m];
                    }
                    mat_vec_add(PB, Se, S[q]);
                    const double complex Jr[2][2] = { { rp, 0 }, { 0, rs } };
                    double M[4][4];
                    mueller_of(Jr, M);
                    mat_mul(PB, M, P[q]);
                    pmax = fmax(pmax, P[q][0][0]);
                    /* reciprocal: the incident fields reflected */
                    cvec3 *F[2] = { &Fv[q], &Fh[q] };
                    for (int m = 0; m < 2; m++) {
                        double complex as = 0, ap = 0;
                        for (int t = 0; t < 3; t++)
                            as += F[m]->x[t] * sv[t], ap += F[m]->x[t] * p_in[t];
                        as *= rs;
                        ap *= rp;
                        for (int t = 0; t < 3; t++)
                            F[m]->x[t] = as * sv[t] + ap * p_out[t];
                    }
                }
                memcpy(f1, l_in, sizeof f1);
                memcpy(f2, sv, sizeof f2);
                if (pmax < W_STOP || hits >= MAX_HITS) {
                    T->stopped++;
                    break;
                }
                const double oi = o[0] + H.t * d[0], oj = o[1] + H.t * d[1];
                o[0] = oi - n * floor(oi / n);
                o[1] = oj - n * floor(oj / n);
                o[2] += H.t * d[2];
                long fi = (long)floor(o[0]), fj = (long)floor(o[1]);
                if (fi >= n)
                    o[0] = fi = 0;
                if (fj >= n)
                    o[1] = fj = 0;
                skip = (fj * n + fi) == (H.tri >> 1) ? H.tri : -1;
                memcpy(D, R, sizeof D);
            }
            for (int q = 0; q < nwl; q++) {
                double J[3];
                if (escaped) {
                    const double nv = cnorm2(&Fv[q]), nh = cnorm2(&Fh[q]);
                    double complex x = 0;
                    for (int t = 0; t < 3; t++)
                        x += Fv[q].x[t] * conj(Fh[q].x[t]);
                    J[0] = 1.0 - 0.5 * (nv + nh);
                    J[1] = 0.5 * (nh - nv);
                    J[2] = -creal(x);
                } else { /* stopped: the rest is black, absorbed whatever its polarisation */
                    for (int m = 0; m < 4; m++)
                        S[q][m] += P[q][m][0];
                    J[0] = 1.0, J[1] = J[2] = 0.0;
                }
                for (int m = 0; m < 4; m++)
                    T->e[q][m] += S[q][m];
                for (int m = 0; m < 3; m++) {
                    T->recip[q][m] += J[m];
                    T->max_route_diff = fmax(T->max_route_diff, fabs(S[q][m] - J[m]));
                }
            }
        }
    }
    for (long c = 0; c < nchunk; c++) {
        const mc_stokes_tally *T = &part[c];
        for (int q = 0; q < nwl; q++) {
            for (int m = 0; m < 4; m++)
                out->e[q][m] += T->e[q][m], out->e1[q][m] += T->e1[q][m];
            for (int m = 0; m < 3; m++)
                out->recip[q][m] += T->recip[q][m];
        }
        out->max_route_diff = fmax(out->max_route_diff, T->max_route_diff);
        out->multi += T->multi;
        out->stopped += T->stopped;
        out->leaks += T->leaks;
    }
    free(part);
    return 0;
}
