/* waves.c - one seeded realisation of the large-scale waves and the facet
 * slope moments of the Variable Step, L/2^n and 1 Meter Step methods (Eq
 * 16-19; seabake-model(7), TWO SCALES and LARGE-SCALE WAVES).
 *
 * A plan (sea_waves) holds the wave components; sampling evaluates the waves
 * with |k| <= pi/step at cell centres of any lattice.  Two generators:
 *
 * - sum of sinusoids: components sorted by |k|, so the waves of a facet of
 *   size L are a prefix of the list.  A lattice is evaluated in tiles; in a
 *   tile each component is the product of a column factor a e^{i(kx x + p)}
 *   and a row factor e^{i ky y}, each computed with sin/cos from the cell's
 *   absolute index, so a cell's value does not depend on the tile, the
 *   rectangle or the thread that computed it.
 * - FFT: a periodic patch of N x N cells of the finest size L0 (period
 *   P = N L0).  A lattice of step L0 2^m is one inverse real FFT of size
 *   N/2^m holding the modes with |k| < pi/step, shifted to the cell centres.
 *   Tiling is kept out of sight by refusing rectangles wider than P: the
 *   caller sizes the patch to the area it needs (seabake slopes does).
 */
#define _GNU_SOURCE /* sincos */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <string.h>
#include <unistd.h>

#include <fftw3.h>

/* The sum-of-sinusoids tile's inner loop four doubles wide where the CPU
 * has AVX2 (chosen at run time, so the program still runs everywhere):
 * the same operations on the same values, lane by lane, and no FMA (the
 * clone does not enable it), so the sums are bit for bit those of the
 * SSE2 path. */
#if defined(__x86_64__) && defined(__GNUC__) && defined(__ELF__) && !defined(__SANITIZE_ADDRESS__)
#define SEA_WIDE_SIMD __attribute__((target_clones("avx2", "default")))
#else
#define SEA_WIDE_SIMD
#endif
#include <gsl/gsl_integration.h>
#include <gsl/gsl_rng.h>

#include "seabake.h"
#include "internal.h"

/* The lowest bin edge lies at or below k_p/4: there L_PM = exp(-20), so the
 * waves left out hold less than 1e-8 of the height and slope variance. */
static const double SEA_WAVES_K_LOW_OVER_KP = 0.25;
/* Cells per tile side when sampling sinusoids: the sin/cos of the row and
 * column factors (TX + TY per component) are small beside the TX TY
 * products. */
enum { TILE_X = 256, TILE_Y = 64 };
/* Gauss-Legendre order of the per-bin spectrum integrals: a bin spans
 * ln 2 / B in ln k, over which B(k) is smooth; 16 points are exact to
 * double precision. */
enum { BIN_GL_ORDER = 16 };
/* Largest sub-facet exponent: 2^20 sub-facets per side. */
enum { SEA_N_MAX = 20 };

typedef struct {
    double kx, ky, k, amplitude, phase, omega;
} component;

struct sea_waves {
    sea_waves_params p;
    sea_spectrum s;
    double k_max;      /* pi / L0 */
    int strict;        /* cut at |k| < kc (FFT modes) rather than |k| <= kc */
    /* sinusoids: sorted by k */
    size_t ncomp;
    component *comp;
    /* FFT: full plane of N x N modes, index (iy mod N) N + (ix mod N) */
    size_t N;
    double dk;
    double *amp, *phs;
    uint32_t *modes;   /* indices of the modes with amp > 0, for sea_waves_get */
    size_t nmodes;
    uint8_t *swell_mode; /* with swell: 1 where a swell holds most of the mode (it travels
                            along its own k), else NULL */
    /* FFT: the inverse real transform of level m (M = N / 2^m cells a side,
     * 2^m <= N/2: the steps fft_level accepts), planned once here and only
     * executed by the sampling calls, on arrays aligned as plan_align */
    size_t nlevels;
    fftw_plan *plans;
    int plan_align;    /* fftw_alignment_of the planning arrays */
};

/* FFTW's planner is not thread-safe; execution is. */
static pthread_mutex_t fftw_planner_lock = PTHREAD_MUTEX_INITIALIZER;

/* The same lock for the library's other plans (imager.c). */
void sea_fftw_planner_lock(void)
{
    pthread_mutex_lock(&fftw_planner_lock);
}

void sea_fftw_planner_unlock(void)
{
    pthread_mutex_unlock(&fftw_planner_lock);
}

void sea_waves_params_default(sea_waves_params *p)
{
    p->kind = SEA_WAVES_SINUSOIDS;
    p->finest = 1.0;
    p->seed = 1;
    p->loop_period = 0.0;
    p->bins_per_octave = 8;
    p->directions = 32;
    p->fft_size = 1024;
}

size_t sea_memory_available(void)
{
    size_t avail = SIZE_MAX;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0 && (unsigned long)pages <= SIZE_MAX / (unsigned long)page)
        avail = (size_t)pages * (size_t)page;
    /* A limit set on this process (ulimit -v, -d) binds before the RAM. */
    const int limits[] = { RLIMIT_AS, RLIMIT_DATA };
    for (size_t i = 0; i < sizeof limits / sizeof limits[0]; i++) {
        struct rlimit rl;
        if (getrlimit(limits[i], &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
            rl.rlim_cur < avail)
            avail = (size_t)rl.rlim_cur;
    }
    return avail;
}

sea_status sea_time_check(double t, sea_error *err)
{
    if (fabs(t) <= SEA_TIME_MAX)
        return SEA_OK;
    return sea_fail(err, SEA_ERR_DOMAIN, "time %g s is outside [%.10g, %.10g] s", t, -SEA_TIME_MAX,
                    SEA_TIME_MAX);
}

sea_status sea_check_size(size_t count, size_t size, const char *what, sea_error *err)
{
    const size_t avail = sea_memory_available();
    if (size != 0 && count > SIZE_MAX / size)
        return sea_fail(err, SEA_ERR_NOMEM, "%s: %zu x %zu bytes overflows the address space",
                        what, count, size);
    if (count * size > avail)
        return sea_fail(err, SEA_ERR_NOMEM, "%s needs %.3g GiB; this machine has %.3g GiB", what,
                        (double)count * (double)size / 1073741824.0,
                        (double)avail / 1073741824.0);
    return SEA_OK;
}

/* Statistics of mean (mx, my) and covariance (xx, xy, yy) made positive
 * semi-definite against round-off: diagonal >= 0, |xy| <= sqrt(xx yy). */
static sea_slope_stats stats_psd(double mx, double my, double xx, double xy, double yy)
{
    sea_slope_stats st;
    st.mean.x = mx;
    st.mean.y = my;
    st.cov.xx = fmax(xx, 0.0);
    st.cov.yy = fmax(yy, 0.0);
    const double lim = sqrt(st.cov.xx * st.cov.yy);
    st.cov.xy = fmin(fmax(xy, -lim), lim);
    return st;
}

sea_slope_stats sea_moments_stats(const sea_moments *mo)
{
    return stats_psd(mo->mx, mo->my, mo->mxx - mo->mx * mo->mx, mo->mxy - mo->mx * mo->my,
                     mo->myy - mo->my * mo->my);
}

_Static_assert(sizeof(sea_facet) == 32, "sea_facet: 32 bytes, none of them padding");

sea_facet sea_facet_of(const sea_moments *mo)
{
    const sea_slope_stats st = sea_moments_stats(mo);
    const sea_facet f = { mo->h,          (float)mo->mx,    (float)mo->my,
                          (float)st.cov.xx, (float)st.cov.xy, (float)st.cov.yy, 0.0f };
    return f;
}

sea_moments sea_facet_moments(const sea_facet *f)
{
    const double mx = f->mx, my = f->my;
    const sea_moments mo = { mx, my, mx * mx + f->cxx, mx * my + f->cxy, my * my + f->cyy, f->h };
    return mo;
}

sea_slope_stats sea_facet_stats(const sea_facet *f)
{
    return stats_psd(f->mx, f->my, f->cxx, f->cxy, f->cyy);
}

/* splitmix64: decorrelates (seed, stream) into a generator seed. */
static uint64_t mix64(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static unsigned long stream_seed(unsigned long seed, int64_t stream)
{
    return (unsigned long)(mix64((uint64_t)seed ^ mix64((uint64_t)stream)) & 0xffffffffu);
}

/* Signed angular frequency: |omega| from the dispersion relation, rounded to
 * a multiple of 2 pi/T for a loop period T, with the sign that makes the
 * phase velocity point downwind (non-negative projection on the wind). */
static double wave_omega(const sea_waves_params *p, const sea_spectrum *s, double kx, double ky)
{
    const double k = hypot(kx, ky);
    double om = sea_spectrum_omega(k);
    if (p->loop_period > 0.0) {
        const double w0 = 2.0 * M_PI / p->loop_period;
        om = w0 * fmax(1.0, round(om / w0));
    }
    const double along = kx * cos(s->wind_dir) + ky * sin(s->wind_dir);
    return along >= 0.0 ? om : -om;
}

static void fft_mode_k(const sea_waves *w, size_t idx, double *kx, double *ky);

/* A swell's wave travels along its own k: omega > 0, rounded as above. */
static double swell_omega(const sea_waves_params *p, double k)
{
    double om = sea_spectrum_omega(k);
    if (p->loop_period > 0.0) {
        const double w0 = 2.0 * M_PI / p->loop_period;
        om = w0 * fmax(1.0, round(om / w0));
    }
    return om;
}

/* The angular frequency of FFT mode idx at (kx, ky). */
static double mode_omega(const sea_waves *w, size_t idx, double kx, double ky)
{
    if (w->swell_mode != NULL && w->swell_mode[idx])
        return swell_omega(&w->p, hypot(kx, ky));
    return wave_omega(&w->p, &w->s, kx, ky);
}

static int compare_component(const void *a, const void *b)
{
    const component *x = a, *y = b;
    return (x->k > y->k) - (x->k < y->k);
}

/* Slope-weighted integrals of one bin [k1, k2] in ln k:
 * i0 = int B(k) dln k = int k^2 S dk, i2 = int B Delta dln k. */
static void bin_integrals(const sea_spectrum *s, const gsl_integration_glfixed_table *gl,
                          double k1, double k2, double *i0, double *i2)
{
    const double a = log(k1), b = log(k2);
    *i0 = *i2 = 0.0;
    for (size_t q = 0; q < gl->n; q++) {
        double x, wq;
        gsl_integration_glfixed_point(a, b, q, &x, &wq, gl);
        const double k = exp(x), B = sea_spectrum_curvature(s, k);
        *i0 += wq * B;
        *i2 += wq * B * sea_spectrum_spreading(s, k);
    }
}

/* The swells' components, after the wind sea's: for each swell, bins on the
 * same edges pi 2^(j/B) over its band, each with `directions` components
 * spread over 10 standard deviations of its directions (a whole turn for a
 * wider spread), from a random offset, each carrying the bin's slope
 * variance times its direction's weight (the density at its direction,
 * normalised to sum 1); a random log-uniform k in the bin and a random
 * phase, from a stream per (seed, swell, bin).  The bins of the wind sea
 * keep their streams: a scene with a swell has the same wind sea. */
static sea_status add_swell_components(sea_waves *w, sea_error *err)
{
    const sea_waves_params *p = &w->p;
    const double B = p->bins_per_octave;
    const size_t ndir = (size_t)p->directions;
    size_t total = 0;
    long jl[SEA_SWELL_MAX], jh[SEA_SWELL_MAX];
    for (int i = 0; i < w->s.n_swell; i++) {
        double klo, khi;
        sea_swell_band(&w->s.swell[i], &klo, &khi);
        jl[i] = (long)floor(B * log2(klo / M_PI));
        jh[i] = (long)ceil(B * log2(fmin(khi, w->k_max) / M_PI) - 1e-9) - 1;
        if (jh[i] >= jl[i])
            total += (size_t)(jh[i] - jl[i] + 1) * ndir;
    }
    if (total == 0)
        return SEA_OK;
    sea_status st = sea_check_size(w->ncomp + total, sizeof(component), "wave components", err);
    if (st != SEA_OK)
        return st;
    component *grown = realloc(w->comp, (w->ncomp + total) * sizeof(component));
    double *weight = malloc(ndir * sizeof(double));
    gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc(BIN_GL_ORDER);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (grown != NULL)
        w->comp = grown;
    if (grown == NULL || weight == NULL || gl == NULL || rng == NULL) {
        free(weight);
        gsl_rng_free(rng);
        gsl_integration_glfixed_table_free(gl);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu swell components", total);
    }
    size_t n = w->ncomp;
    for (int i = 0; i < w->s.n_swell; i++) {
        const sea_swell *sw = &w->s.swell[i];
        double klo, khi;
        sea_swell_band(sw, &klo, &khi);
        const double width = fmin(10.0 * sw->spread, 2.0 * M_PI), dphi = width / (double)ndir;
        for (long j = jl[i]; j <= jh[i]; j++) {
            const double k1 = M_PI * exp2((double)j / B), k2 = M_PI * exp2((double)(j + 1) / B);
            /* the bin's share of the band, the cut at the band's edges kept
             * out of the quadrature */
            const double a = log(fmax(k1, klo)), b = log(fmin(k2, khi));
            double i0 = 0.0;
            for (size_t q = 0; b > a && q < gl->n; q++) {
                double x, wq;
                gsl_integration_glfixed_point(a, b, q, &x, &wq, gl);
                i0 += wq * sea_swell_curvature(sw, exp(x));
            }
            gsl_rng_set(rng, stream_seed(p->seed, j + ((int64_t)(i + 1) << 40)));
            const double first = sw->dir - 0.5 * width + dphi * gsl_rng_uniform(rng);
            double wsum = 0.0;
            for (size_t d = 0; d < ndir; d++)
                wsum += weight[d] = sea_swell_direction_density(sw, first + dphi * (double)d);
            for (size_t d = 0; d < ndir; d++) {
                const double u = gsl_rng_uniform(rng), phase = 2.0 * M_PI * gsl_rng_uniform(rng);
                const double k = k1 * pow(k2 / k1, u);
                if (k > w->k_max || !(i0 > 0.0))
                    continue;
                const double var = i0 * weight[d] / wsum, az = first + dphi * (double)d;
                component *c = &w->comp[n++];
                c->k = k;
                c->kx = k * cos(az);
                c->ky = k * sin(az);
                c->amplitude = sqrt(2.0 * var) / k;
                c->phase = phase;
                c->omega = swell_omega(p, k);
            }
        }
    }
    free(weight);
    gsl_rng_free(rng);
    gsl_integration_glfixed_table_free(gl);
    w->ncomp = n;
    return SEA_OK;
}

static sea_status create_sinusoids(sea_waves *w, sea_error *err)
{
    const sea_waves_params *p = &w->p;
    const double B = p->bins_per_octave;
    /* Bin j = [pi 2^(j/B), pi 2^((j+1)/B)]. */
    const double k_lo = w->s.k_p * SEA_WAVES_K_LOW_OVER_KP;
    const long j_lo = (long)floor(B * log2(k_lo / M_PI));
    const long j_hi = (long)ceil(B * log2(w->k_max / M_PI) - 1e-9) - 1;
    if (j_hi < j_lo) {
        w->ncomp = 0;
        return w->s.n_swell > 0 ? add_swell_components(w, err) : SEA_OK;
    }
    const size_t nbins = (size_t)(j_hi - j_lo + 1), ndir = (size_t)p->directions;
    sea_status st = sea_check_size(nbins * ndir, sizeof(component), "wave components", err);
    if (st != SEA_OK)
        return st;
    w->comp = malloc(nbins * ndir * sizeof(component));
    gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc(BIN_GL_ORDER);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (w->comp == NULL || gl == NULL || rng == NULL) {
        gsl_rng_free(rng);
        gsl_integration_glfixed_table_free(gl);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu wave components",
                        nbins * ndir);
    }
    const double dphi = 2.0 * M_PI / (double)ndir;
    size_t n = 0;
    for (long j = j_lo; j <= j_hi; j++) {
        const double k1 = M_PI * exp2((double)j / B), k2 = M_PI * exp2((double)(j + 1) / B);
        double i0, i2;
        bin_integrals(&w->s, gl, k1, k2, &i0, &i2);
        gsl_rng_set(rng, stream_seed(p->seed, j));
        const double offset = dphi * gsl_rng_uniform(rng);
        for (size_t d = 0; d < ndir; d++) {
            const double u = gsl_rng_uniform(rng), phase = 2.0 * M_PI * gsl_rng_uniform(rng);
            const double k = k1 * pow(k2 / k1, u);
            if (k > w->k_max)
                continue;
            const double psi = offset + dphi * (double)d; /* from the wind axis */
            /* Slope variance of this direction's share of the bin; summed
             * over the evenly spaced directions it gives the bin's
             * sigma_u^2 = i0/2 + i2/4 and sigma_c^2 = i0/2 - i2/4 exactly. */
            const double var = fmax(i0 + i2 * cos(2.0 * psi), 0.0) * dphi / (2.0 * M_PI);
            component *c = &w->comp[n++];
            const double az = psi + w->s.wind_dir;
            c->k = k;
            c->kx = k * cos(az);
            c->ky = k * sin(az);
            c->amplitude = sqrt(2.0 * var) / k;
            c->phase = phase;
            c->omega = wave_omega(p, &w->s, c->kx, c->ky);
        }
    }
    gsl_rng_free(rng);
    gsl_integration_glfixed_table_free(gl);
    w->ncomp = n;
    if (w->s.n_swell > 0 && (st = add_swell_components(w, err)) != SEA_OK)
        return st;
    n = w->ncomp;
    /* Stable order for equal k (not expected with random k): qsort is not
     * stable, but ties have equal k, so any order gives the same prefixes. */
    qsort(w->comp, n, sizeof(component), compare_component);
    return SEA_OK;
}

static size_t wrap_index(long i, size_t n)
{
    long r = i % (long)n;
    return (size_t)(r < 0 ? r + (long)n : r);
}

static sea_status create_fft(sea_waves *w, sea_error *err)
{
    const size_t N = w->p.fft_size;
    w->N = N;
    w->dk = 2.0 * M_PI / ((double)N * w->p.finest);
    sea_status st = sea_check_size(N * N, 2 * sizeof(double) + sizeof(uint32_t),
                                   "FFT wave patch", err);
    if (st != SEA_OK)
        return st;
    w->amp = malloc(N * N * sizeof(double));
    w->phs = malloc(N * N * sizeof(double));
    w->modes = malloc(N * N * sizeof(uint32_t));
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    if (w->amp == NULL || w->phs == NULL || w->modes == NULL || rng == NULL) {
        gsl_rng_free(rng);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu FFT patch", N, N);
    }
    /* Phases in a fixed order (ky, then kx, from -N/2), one per cell. */
    gsl_rng_set(rng, stream_seed(w->p.seed, INT64_MIN));
    const long h = (long)N / 2;
    for (long iy = -h; iy < h; iy++)
        for (long ix = -h; ix < h; ix++)
            w->phs[wrap_index(iy, N) * N + wrap_index(ix, N)] = 2.0 * M_PI * gsl_rng_uniform(rng);
    gsl_rng_free(rng);
    const double dk = w->dk, kmax = w->k_max;
#pragma omp parallel for schedule(static)
    for (long iy = -h; iy < h; iy++) {
        for (long ix = -h; ix < h; ix++) {
            const double kx = dk * (double)ix, ky = dk * (double)iy, k = hypot(kx, ky);
            double a = 0.0;
            if (k > 0.0 && k < kmax) {
                /* Slope variance of the mode k^2 Psi dk^2 = a^2 k^2 / 2. */
                const double psi = sea_spectrum_directional(&w->s, k, atan2(ky, kx));
                a = sqrt(2.0 * psi * dk * dk);
            }
            w->amp[wrap_index(iy, N) * N + wrap_index(ix, N)] = a;
        }
    }
    size_t n = 0;
    for (size_t i = 0; i < N * N; i++)
        if (w->amp[i] > 0.0)
            w->modes[n++] = (uint32_t)i;
    w->nmodes = n;
    if (w->s.n_swell > 0) {
        w->swell_mode = calloc(N * N, 1);
        if (w->swell_mode == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu FFT patch", N,
                            N);
        for (size_t m = 0; m < n; m++) {
            const size_t idx = w->modes[m];
            double kx, ky;
            fft_mode_k(w, idx, &kx, &ky);
            const double k = hypot(kx, ky), phi = atan2(ky, kx);
            const double psw = sea_spectrum_directional_swell(&w->s, k, phi);
            w->swell_mode[idx] = psw > sea_spectrum_directional(&w->s, k, phi) - psw;
        }
    }
    return SEA_OK;
}

/* Plans the inverse real FFT of every level the sampling calls may ask for,
 * with FFTW_ESTIMATE (as chosen before the plans were kept: FFTW_MEASURE
 * would overwrite the arrays, time transforms that may never run and make
 * the plan, so the round-off, depend on the machine's load).  The planning
 * arrays are those of the largest level; the smaller levels plan on their
 * prefixes, which have the same alignment. */
static sea_status create_fft_plans(sea_waves *w, sea_error *err)
{
    const size_t N = w->N, mh = N / 2 + 1;
    size_t n = 0;
    while (((size_t)2 << n) <= N) /* 2^m <= N/2 */
        n++;
    sea_status st = sea_check_size(N * mh, sizeof(fftw_complex) + 2 * sizeof(double),
                                   "FFT planning arrays", err);
    if (st != SEA_OK)
        return st;
    w->plans = calloc(n, sizeof *w->plans);
    fftw_complex *in = fftw_malloc(N * mh * sizeof(fftw_complex));
    double *out = fftw_malloc(N * N * sizeof(double));
    if (w->plans == NULL || in == NULL || out == NULL) {
        fftw_free(in);
        fftw_free(out);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for planning a %zu x %zu FFT", N,
                        N);
    }
    w->nlevels = n;
    w->plan_align = fftw_alignment_of(out);
    sea_fftw_planner_lock();
    for (size_t m = 0; m < n && st == SEA_OK; m++) {
        const size_t M = N >> m;
        w->plans[m] = fftw_plan_dft_c2r_2d((int)M, (int)M, in, out, FFTW_ESTIMATE);
        if (w->plans[m] == NULL)
            st = sea_fail(err, SEA_ERR_NOMEM, "FFTW could not plan a %zu x %zu transform", M,
                          M);
    }
    sea_fftw_planner_unlock();
    fftw_free(in);
    fftw_free(out);
    return st;
}

sea_status sea_waves_alloc(const sea_spectrum *s, const sea_waves_params *p, sea_waves **out,
                            sea_error *err)
{
    *out = NULL;
    if (p->kind != SEA_WAVES_SINUSOIDS && p->kind != SEA_WAVES_FFT)
        return sea_fail(err, SEA_ERR_DOMAIN, "unknown wave generator %d", (int)p->kind);
    if (!(p->finest >= SEA_FINEST_MIN && p->finest <= SEA_FINEST_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN, "finest facet size %g m is outside [%g, %g] m",
                        p->finest, SEA_FINEST_MIN, SEA_FINEST_MAX);
    if (!(p->loop_period >= 0.0) || !isfinite(p->loop_period))
        return sea_fail(err, SEA_ERR_DOMAIN, "loop period %g s must be >= 0 and finite",
                        p->loop_period);
    if (p->kind == SEA_WAVES_SINUSOIDS) {
        if (p->bins_per_octave < 1 || p->bins_per_octave > 64)
            return sea_fail(err, SEA_ERR_DOMAIN, "bins per octave %d outside [1, 64]",
                            p->bins_per_octave);
        if (p->directions < 5 || p->directions > 1024)
            return sea_fail(err, SEA_ERR_DOMAIN, "directions per bin %d outside [5, 1024]",
                            p->directions);
    } else if (p->fft_size < 2 || p->fft_size > 16384 || p->fft_size % 2 != 0) {
        return sea_fail(err, SEA_ERR_DOMAIN, "FFT size %zu must be even, in [2, 16384]",
                        p->fft_size);
    }
    sea_waves *w = calloc(1, sizeof *w);
    if (w == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    w->p = *p;
    w->s = *s;
    w->k_max = M_PI / p->finest;
    w->strict = p->kind == SEA_WAVES_FFT;
    sea_status st = p->kind == SEA_WAVES_SINUSOIDS ? create_sinusoids(w, err) : create_fft(w, err);
    if (st == SEA_OK && p->kind == SEA_WAVES_FFT)
        st = create_fft_plans(w, err);
    if (st != SEA_OK) {
        sea_waves_free(w);
        return st;
    }
    *out = w;
    return SEA_OK;
}

sea_status sea_waves_to_sinusoids(const sea_waves *w, sea_waves **out, sea_error *err)
{
    *out = NULL;
    const size_t n = sea_waves_count(w);
    sea_status st = sea_check_size(n, sizeof(component), "wave components", err);
    if (st != SEA_OK)
        return st;
    sea_waves *c = calloc(1, sizeof *c);
    component *list = malloc((n > 0 ? n : 1) * sizeof(component));
    if (c == NULL || list == NULL) {
        free(c);
        free(list);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for %zu wave components", n);
    }
    c->p = w->p;
    c->p.kind = SEA_WAVES_SINUSOIDS;
    c->s = w->s;
    c->k_max = w->k_max;
    c->strict = w->strict;
    for (size_t i = 0; i < n; i++) {
        const sea_wave o = sea_waves_get(w, i);
        list[i] = (component){ o.kx, o.ky, hypot(o.kx, o.ky), o.amplitude, o.phase, o.omega };
    }
    qsort(list, n, sizeof(component), compare_component);
    c->comp = list;
    c->ncomp = n;
    *out = c;
    return SEA_OK;
}

void sea_waves_free(sea_waves *w)
{
    if (w == NULL)
        return;
    free(w->comp);
    free(w->amp);
    free(w->phs);
    free(w->modes);
    free(w->swell_mode);
    if (w->plans != NULL) {
        sea_fftw_planner_lock();
        for (size_t m = 0; m < w->nlevels; m++)
            if (w->plans[m] != NULL)
                fftw_destroy_plan(w->plans[m]);
        sea_fftw_planner_unlock();
        free(w->plans);
    }
    free(w);
}

size_t sea_waves_count(const sea_waves *w)
{
    return w->p.kind == SEA_WAVES_SINUSOIDS ? w->ncomp : w->nmodes;
}

static void fft_mode_k(const sea_waves *w, size_t idx, double *kx, double *ky)
{
    const size_t N = w->N;
    long ix = (long)(idx % N), iy = (long)(idx / N);
    if (ix >= (long)N / 2)
        ix -= (long)N;
    if (iy >= (long)N / 2)
        iy -= (long)N;
    *kx = w->dk * (double)ix;
    *ky = w->dk * (double)iy;
}

sea_wave sea_waves_get(const sea_waves *w, size_t i)
{
    sea_wave o;
    if (w->p.kind == SEA_WAVES_SINUSOIDS) {
        const component *c = &w->comp[i];
        o.kx = c->kx;
        o.ky = c->ky;
        o.amplitude = c->amplitude;
        o.phase = c->phase;
        o.omega = c->omega;
    } else {
        const size_t idx = w->modes[i];
        fft_mode_k(w, idx, &o.kx, &o.ky);
        o.amplitude = w->amp[idx];
        o.phase = w->phs[idx];
        o.omega = mode_omega(w, idx, o.kx, o.ky);
    }
    return o;
}

const sea_waves_params *sea_waves_params_of(const sea_waves *w)
{
    return &w->p;
}

const sea_spectrum *sea_waves_spectrum(const sea_waves *w)
{
    return &w->s;
}

double sea_waves_period(const sea_waves *w)
{
    return w->p.kind == SEA_WAVES_FFT ? (double)w->N * w->p.finest : INFINITY;
}

/* Number of sinusoids with k <= kc (a prefix of the sorted list). */
static size_t prefix_count(const sea_waves *w, double kc)
{
    size_t lo = 0, hi = w->ncomp;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (w->strict ? w->comp[mid].k < kc : w->comp[mid].k <= kc)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

sea_cov2 sea_waves_generated_cov(const sea_waves *w, double kc)
{
    sea_cov2 c = { 0.0, 0.0, 0.0 };
    const size_t n = sea_waves_count(w);
    for (size_t i = 0; i < n; i++) {
        const sea_wave o = sea_waves_get(w, i);
        const double k = hypot(o.kx, o.ky);
        if (w->strict ? k >= kc : k > kc)
            continue;
        /* slope = -a k sin(.): variance a^2 k^2 / 2 along k. */
        const double v = 0.5 * o.amplitude * o.amplitude;
        c.xx += v * o.kx * o.kx;
        c.yy += v * o.ky * o.ky;
        c.xy += v * o.kx * o.ky;
    }
    return c;
}

void sea_waves_at(const sea_waves *w, double kc, double x, double y, double t, double *h,
                  sea_vec2 *slope)
{
    double hh = 0.0, sx = 0.0, sy = 0.0;
    const size_t n = sea_waves_count(w);
    for (size_t i = 0; i < n; i++) {
        const sea_wave o = sea_waves_get(w, i);
        const double k = hypot(o.kx, o.ky);
        if (w->strict ? k >= kc : k > kc) {
            if (w->p.kind == SEA_WAVES_SINUSOIDS)
                break; /* sorted */
            continue;
        }
        double sn, cs;
        sincos(o.kx * x + o.ky * y - o.omega * t + o.phase, &sn, &cs);
        hh += o.amplitude * cs;
        sx -= o.amplitude * o.kx * sn;
        sy -= o.amplitude * o.ky * sn;
    }
    if (h != NULL)
        *h = hh;
    if (slope != NULL) {
        slope->x = sx;
        slope->y = sy;
    }
}

/* ------------------------------------------------------------ sampling */

/* a e^{i(k ((c0 + m + 1/2) step) + p0)} for m < n into re, im: sincos at
 * the start of each run of B = ceil(sqrt n) cells and of the B steps
 * within a run, the rest by one complex product (each value within a few
 * ulps of its own sincos, with no drift along the row): 2 sqrt n sincos
 * instead of n. */
static void phasors(double a, double k, double p0, long c0, double step, size_t n,
                    double *restrict re, double *restrict im)
{
    size_t B = 1;
    while (B * B < n)
        B++;
    double wre[TILE_X], wim[TILE_X]; /* B <= 16 */
    for (size_t j = 0; j < B; j++)
        sincos(k * ((double)j * step), &wim[j], &wre[j]);
    for (size_t m0 = 0; m0 < n; m0 += B) {
        double sn, cs;
        sincos(k * (((double)(c0 + (long)m0) + 0.5) * step) + p0, &sn, &cs);
        const double zr = a * cs, zi = a * sn;
        const size_t e = n - m0 < B ? n - m0 : B;
        for (size_t j = 0; j < e; j++) {
            re[m0 + j] = zr * wre[j] - zi * wim[j];
            im[m0 + j] = zr * wim[j] + zi * wre[j];
        }
    }
}

/* Sums of the first nc sinusoids at the centres of cells [i0, i0+nx) x
 * [j0, j0+ny) of size step (nx <= TILE_X, ny <= TILE_Y) into h, sx, sy
 * (nx * ny each, overwritten).  The components go four at a time over each
 * row (TILE_BLOCK), the last few one at a time: a cell's sums are loaded
 * and stored once per four rather than once per component, and each cell
 * adds the components in their order (SEA_TILE_ADD), so the sums are bit
 * for bit those of one component at a time. */
enum { TILE_BLOCK = 4 };
/* A component's share at cell i of a row: column factor (re, im), row
 * factor (rr, ri), wavenumber (kx, ky). */
#define SEA_TILE_ADD(re, im, rr, ri, kx, ky)                                                      \
    do {                                                                                          \
        const double r_ = (re)[i] * (rr) - (im)[i] * (ri);                                        \
        const double m_ = (re)[i] * (ri) + (im)[i] * (rr);                                        \
        hv += r_;                                                                                 \
        xv -= (kx) * m_;                                                                          \
        yv -= (ky) * m_;                                                                          \
    } while (0)
SEA_WIDE_SIMD
static void sinusoid_tile(const sea_waves *w, size_t nc, double step, long i0, long j0, size_t nx,
                          size_t ny, double t, double *restrict h, double *restrict sx,
                          double *restrict sy)
{
    const size_t np = nx * ny;
    memset(h, 0, np * sizeof *h);
    memset(sx, 0, np * sizeof *sx);
    memset(sy, 0, np * sizeof *sy);
    /* the block's column and row factors and wavenumbers */
    double bre[TILE_BLOCK][TILE_X], bim[TILE_BLOCK][TILE_X];
    double brr[TILE_BLOCK][TILE_Y], bri[TILE_BLOCK][TILE_Y], bkx[TILE_BLOCK], bky[TILE_BLOCK];
    for (size_t c = 0; c < nc; c += TILE_BLOCK) {
        const size_t m = nc - c < TILE_BLOCK ? nc - c : TILE_BLOCK;
        for (size_t b = 0; b < m; b++) {
            const component *o = &w->comp[c + b];
            phasors(o->amplitude, o->kx, o->phase - o->omega * t, i0, step, nx, bre[b], bim[b]);
            phasors(1.0, o->ky, 0.0, j0, step, ny, brr[b], bri[b]);
            bkx[b] = o->kx;
            bky[b] = o->ky;
        }
        for (size_t j = 0; j < ny; j++) {
            double *restrict hj = h + j * nx, *restrict xj = sx + j * nx, *restrict yj = sy + j * nx;
            if (m == TILE_BLOCK) {
                const double *restrict re0 = bre[0], *restrict re1 = bre[1],
                                       *restrict re2 = bre[2], *restrict re3 = bre[3];
                const double *restrict im0 = bim[0], *restrict im1 = bim[1],
                                       *restrict im2 = bim[2], *restrict im3 = bim[3];
                const double kx0 = bkx[0], kx1 = bkx[1], kx2 = bkx[2], kx3 = bkx[3];
                const double ky0 = bky[0], ky1 = bky[1], ky2 = bky[2], ky3 = bky[3];
                const double rr0 = brr[0][j], ri0 = bri[0][j], rr1 = brr[1][j], ri1 = bri[1][j];
                const double rr2 = brr[2][j], ri2 = bri[2][j], rr3 = brr[3][j], ri3 = bri[3][j];
#pragma omp simd
                for (size_t i = 0; i < nx; i++) {
                    double hv = hj[i], xv = xj[i], yv = yj[i];
                    SEA_TILE_ADD(re0, im0, rr0, ri0, kx0, ky0);
                    SEA_TILE_ADD(re1, im1, rr1, ri1, kx1, ky1);
                    SEA_TILE_ADD(re2, im2, rr2, ri2, kx2, ky2);
                    SEA_TILE_ADD(re3, im3, rr3, ri3, kx3, ky3);
                    hj[i] = hv;
                    xj[i] = xv;
                    yj[i] = yv;
                }
                continue;
            }
            for (size_t b = 0; b < m; b++) {
                const double *restrict re = bre[b], *restrict im = bim[b];
                const double rr = brr[b][j], ri = bri[b][j], kx = bkx[b], ky = bky[b];
#pragma omp simd
                for (size_t i = 0; i < nx; i++) {
                    double hv = hj[i], xv = xj[i], yv = yj[i];
                    SEA_TILE_ADD(re, im, rr, ri, kx, ky);
                    hj[i] = hv;
                    xj[i] = xv;
                    yj[i] = yv;
                }
            }
        }
    }
}
#undef SEA_TILE_ADD

/* Checks a lattice step against an FFT plan: step = L0 2^m; returns the
 * level m (the index of its FFTW plan) through *level and its grid size
 * M = N / 2^m through *M. */
static sea_status fft_level(const sea_waves *w, double step, size_t *level, size_t *M,
                            sea_error *err)
{
    const double r = step / w->p.finest;
    const double m = round(log2(r));
    if (!(m >= 0.0) || fabs(r - exp2(m)) > 1e-9 * r || exp2(m) > (double)w->N / 2.0)
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "step %g m: an FFT plan samples steps %g m x 2^m up to %g m "
                        "(half its period)",
                        step, w->p.finest, w->p.finest * (double)w->N / 2.0);
    *level = (size_t)m;
    *M = w->N >> (int)m;
    return SEA_OK;
}

/* The whole level grid M x M (level m = `level`) of step `step` at time t:
 * h, sx, sy (M*M each, row by row, cell (i, j) centred at
 * ((i + 1/2) step, (j + 1/2) step)).  Executes the level's plan, made by
 * sea_waves_alloc: FFTW's new-array execute is thread-safe, so sampling
 * takes no lock. */
static sea_status fft_sample_level(const sea_waves *w, double step, size_t level, size_t M,
                                   double t, double *h, double *sx, double *sy, sea_error *err)
{
    assert(level < w->nlevels && (w->N >> level) == M);
    const size_t N = w->N, mh = M / 2 + 1;
    fftw_complex *in[3];
    double *outs[3] = { h, sx, sy };
    for (int f = 0; f < 3; f++)
        in[f] = fftw_malloc(M * mh * sizeof(fftw_complex));
    if (in[0] == NULL || in[1] == NULL || in[2] == NULL) {
        for (int f = 0; f < 3; f++)
            fftw_free(in[f]);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu FFT", M, M);
    }
    const double kc = M_PI / step, dk = w->dk;
#pragma omp parallel for schedule(static)
    for (size_t r = 0; r < M; r++) {
        const long iy = r < M / 2 ? (long)r : (long)r - (long)M;
        for (size_t c = 0; c < mh; c++) {
            const long ix = (long)c;
            const double kx = dk * (double)ix, ky = dk * (double)iy;
            const double k = hypot(kx, ky);
            double complex H = 0.0;
            if (k > 0.0 && k < kc) {
                /* h = sum over the plane of A cos(k.x - omega t + phase):
                 * the coefficient at k gathers the wave k and its mirror -k. */
                const size_t ip = wrap_index(iy, N) * N + wrap_index(ix, N);
                const size_t im = wrap_index(-iy, N) * N + wrap_index(-ix, N);
                const double om = mode_omega(w, ip, kx, ky);
                const double omm = mode_omega(w, im, -kx, -ky);
                H = 0.5 * (w->amp[ip] * cexp(I * (w->phs[ip] - om * t)) +
                           w->amp[im] * cexp(-I * (w->phs[im] - omm * t)));
                H *= cexp(I * 0.5 * step * (kx + ky)); /* to the cell centres */
            }
            const size_t q = r * mh + c;
            double complex *o0 = (double complex *)in[0], *o1 = (double complex *)in[1],
                           *o2 = (double complex *)in[2];
            o0[q] = H;
            o1[q] = I * kx * H;
            o2[q] = I * ky * H;
        }
    }
    /* FFTW's new-array execute needs the alignment the plan was made with
     * (fftw_malloc's, as in[f] have): an output aligned otherwise goes
     * through a buffer. */
    const fftw_plan plan = w->plans[level];
    double *buf = NULL;
    sea_status st = SEA_OK;
    for (int f = 0; f < 3 && st == SEA_OK; f++) {
        if (outs[f] == NULL)
            continue;
        if (fftw_alignment_of(outs[f]) == w->plan_align) {
            fftw_execute_dft_c2r(plan, in[f], outs[f]);
            continue;
        }
        if (buf == NULL && (buf = fftw_malloc(M * M * sizeof(double))) == NULL) {
            st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu FFT", M, M);
            break;
        }
        fftw_execute_dft_c2r(plan, in[f], buf);
        memcpy(outs[f], buf, M * M * sizeof(double));
    }
    fftw_free(buf);
    for (int f = 0; f < 3; f++)
        fftw_free(in[f]);
    return st;
}

static sea_status check_rect(const sea_waves *w, const sea_rect *r, sea_error *err)
{
    if (!(r->step > 0.0) || !isfinite(r->step))
        return sea_fail(err, SEA_ERR_DOMAIN, "step %g m must be > 0 and finite", r->step);
    if (r->step < w->p.finest * (1.0 - 1e-12))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "step %g m is below the finest facet size %g m of the wave plan",
                        r->step, w->p.finest);
    if (r->nx == 0 || r->ny == 0)
        return sea_fail(err, SEA_ERR_DOMAIN, "empty rectangle (%zu x %zu cells)", r->nx, r->ny);
    const double lim = 9.0e15; /* cell indices stay exact in a double */
    if (fabs((double)r->i0) + (double)r->nx > lim || fabs((double)r->j0) + (double)r->ny > lim)
        return sea_fail(err, SEA_ERR_DOMAIN, "rectangle indices too large");
    return SEA_OK;
}

sea_status sea_waves_sample(const sea_waves *w, const sea_rect *r, double t, double *h,
                            double *sx, double *sy, sea_error *err)
{
    sea_status st = check_rect(w, r, err);
    if (st != SEA_OK)
        return st;
    if ((st = sea_time_check(t, err)) != SEA_OK)
        return st;
    const size_t nx = r->nx, ny = r->ny;
    if ((st = sea_check_size(nx, ny * sizeof(double) * 3, "sampled fields", err)) != SEA_OK)
        return st;
    if (w->p.kind == SEA_WAVES_FFT) {
        size_t level, M;
        if ((st = fft_level(w, r->step, &level, &M, err)) != SEA_OK)
            return st;
        if (nx > M || ny > M)
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "rectangle %zu x %zu cells of %g m exceeds the FFT period %g m; "
                            "plan a larger patch",
                            nx, ny, r->step, sea_waves_period(w));
        double *f = malloc(3 * M * M * sizeof(double));
        if (f == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu grid", M, M);
        if ((st = fft_sample_level(w, r->step, level, M, t, f, f + M * M, f + 2 * M * M,
                                   err)) != SEA_OK) {
            free(f);
            return st;
        }
        double *dst[3] = { h, sx, sy };
        for (int q = 0; q < 3; q++) {
            if (dst[q] == NULL)
                continue;
            const double *src = f + (size_t)q * M * M;
            for (size_t j = 0; j < ny; j++) {
                const size_t sj = wrap_index(r->j0 + (long)j, M);
                for (size_t i = 0; i < nx; i++)
                    dst[q][j * nx + i] = src[sj * M + wrap_index(r->i0 + (long)i, M)];
            }
        }
        free(f);
        return SEA_OK;
    }
    const size_t nc = prefix_count(w, M_PI / r->step);
    const size_t tx = (nx + TILE_X - 1) / TILE_X, ty = (ny + TILE_Y - 1) / TILE_Y;
    int fail = 0;
#pragma omp parallel
    {
        double *buf = malloc(3 * TILE_X * TILE_Y * sizeof(double));
        if (buf == NULL) {
#pragma omp atomic write
            fail = 1;
        }
#pragma omp for schedule(dynamic) collapse(2)
        for (size_t b = 0; b < ty; b++) {
            for (size_t a = 0; a < tx; a++) {
                if (buf == NULL)
                    continue;
                const size_t ox = a * TILE_X, oy = b * TILE_Y;
                const size_t wx = nx - ox < TILE_X ? nx - ox : TILE_X;
                const size_t wy = ny - oy < TILE_Y ? ny - oy : TILE_Y;
                double *th = buf, *tsx = buf + TILE_X * TILE_Y, *tsy = buf + 2 * TILE_X * TILE_Y;
                sinusoid_tile(w, nc, r->step, r->i0 + (long)ox, r->j0 + (long)oy, wx, wy, t, th,
                              tsx, tsy);
                for (size_t j = 0; j < wy; j++) {
                    const size_t d = (oy + j) * nx + ox;
                    if (h != NULL)
                        memcpy(h + d, th + j * wx, wx * sizeof(double));
                    if (sx != NULL)
                        memcpy(sx + d, tsx + j * wx, wx * sizeof(double));
                    if (sy != NULL)
                        memcpy(sy + d, tsy + j * wx, wx * sizeof(double));
                }
            }
        }
        free(buf);
    }
    if (fail)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for sampling tiles");
    return SEA_OK;
}

/* ---------------------------------------------------------------- facets */

int sea_facet_method_from_name(const char *name)
{
    if (strcmp(name, "variable-step") == 0)
        return SEA_METHOD_VARIABLE_STEP;
    if (strcmp(name, "variable-step-2n") == 0)
        return SEA_METHOD_VARIABLE_STEP_2N;
    if (strcmp(name, "one-meter") == 0)
        return SEA_METHOD_ONE_METER;
    return -1;
}

const char *sea_facet_method_name(sea_facet_method m)
{
    switch (m) {
    case SEA_METHOD_VARIABLE_STEP: return "variable-step";
    case SEA_METHOD_VARIABLE_STEP_2N: return "variable-step-2n";
    case SEA_METHOD_ONE_METER: return "one-meter";
    }
    return "unknown";
}

sea_status sea_facet_method_n(const sea_waves *w, sea_facet_method m, int n, double L, int *out_n,
                              sea_error *err)
{
    const double L0 = w->p.finest;
    switch (m) {
    case SEA_METHOD_VARIABLE_STEP:
        *out_n = 0;
        return SEA_OK;
    case SEA_METHOD_VARIABLE_STEP_2N:
        if (n < 0 || n > SEA_N_MAX)
            return sea_fail(err, SEA_ERR_DOMAIN, "n = %d outside [0, %d]", n, SEA_N_MAX);
        *out_n = n;
        return SEA_OK;
    case SEA_METHOD_ONE_METER: {
        const double r = L / L0, e = round(log2(r));
        if (!(e >= 0.0) || e > SEA_N_MAX || fabs(r - exp2(e)) > 1e-9 * r)
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "one-meter: facet size %g m must be the finest size %g m times "
                            "2^n, n in [0, %d]",
                            L, L0, SEA_N_MAX);
        *out_n = (int)e;
        return SEA_OK;
    }
    }
    return sea_fail(err, SEA_ERR_DOMAIN, "unknown facet method %d", (int)m);
}

typedef struct {
    double h, sx, sy, sxx, sxy, syy;
} sums;

static void add_point(sums *s, double h, double x, double y)
{
    s->h += h;
    s->sx += x;
    s->sy += y;
    s->sxx += x * x;
    s->sxy += x * y;
    s->syy += y * y;
}

static sea_moments finish(const sums *s, double count, const sea_cov2 *sub)
{
    sea_moments m;
    m.h = s->h / count;
    m.mx = s->sx / count;
    m.my = s->sy / count;
    m.mxx = s->sxx / count + sub->xx;
    m.mxy = s->sxy / count + sub->xy;
    m.myy = s->syy / count + sub->yy;
    return m;
}

sea_status sea_waves_facets(const sea_waves *w, const sea_rect *r, int n, double t,
                            sea_moments *out, sea_error *err)
{
    sea_status st = check_rect(w, r, err);
    if (st != SEA_OK)
        return st;
    if (n < 0 || n > SEA_N_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "n = %d outside [0, %d]", n, SEA_N_MAX);
    if ((st = sea_time_check(t, err)) != SEA_OK)
        return st;
    const size_t sub = (size_t)1 << n;
    const double delta = r->step / (double)sub;
    if (delta < w->p.finest * (1.0 - 1e-12))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "sub-facets of %g m / 2^%d = %g m are below the finest facet size %g m "
                        "of the wave plan",
                        r->step, n, delta, w->p.finest);
    sea_cov2 csub;
    if ((st = sea_spectrum_slope_cov(&w->s, M_PI / delta, &csub, err)) != SEA_OK)
        return st;
    const size_t nx = r->nx, ny = r->ny;
    const double count = (double)sub * (double)sub;

    if (w->p.kind == SEA_WAVES_FFT) {
        size_t level, M;
        if ((st = fft_level(w, delta, &level, &M, err)) != SEA_OK)
            return st;
        if ((double)nx * (double)sub > (double)M || (double)ny * (double)sub > (double)M)
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "rectangle %zu x %zu facets of %g m exceeds the FFT period %g m; "
                            "plan a larger patch",
                            nx, ny, r->step, sea_waves_period(w));
        if ((st = sea_check_size(M * M, 3 * sizeof(double), "FFT level grid", err)) != SEA_OK)
            return st;
        double *f = malloc(3 * M * M * sizeof(double));
        if (f == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for a %zu x %zu grid", M, M);
        if ((st = fft_sample_level(w, delta, level, M, t, f, f + M * M, f + 2 * M * M, err)) !=
            SEA_OK) {
            free(f);
            return st;
        }
        const double *fh = f, *fx = f + M * M, *fy = f + 2 * M * M;
#pragma omp parallel for schedule(static)
        for (size_t j = 0; j < ny; j++) {
            for (size_t i = 0; i < nx; i++) {
                sums s = { 0 };
                for (size_t b = 0; b < sub; b++) {
                    const size_t row = wrap_index((r->j0 + (long)j) * (long)sub + (long)b, M) * M;
                    for (size_t a = 0; a < sub; a++) {
                        const size_t q = row + wrap_index((r->i0 + (long)i) * (long)sub + (long)a, M);
                        add_point(&s, fh[q], fx[q], fy[q]);
                    }
                }
                out[j * nx + i] = finish(&s, count, &csub);
            }
        }
        free(f);
        return SEA_OK;
    }

    /* Sinusoids: each task takes a band of facet rows (as many as fit in a
     * tile's height, at least one); its sub-cells are sampled in tiles of
     * at most TILE_X x TILE_Y and summed into the band's facets in a fixed
     * order, so the result does not depend on the thread count. */
    const size_t nc = prefix_count(w, M_PI / delta);
    const size_t band = sub < TILE_Y ? TILE_Y / sub : 1;
    const size_t cx = sub < TILE_X ? (TILE_X / sub) * sub : TILE_X;
    const size_t ntask = (ny + band - 1) / band;
    int fail = 0;
#pragma omp parallel
    {
        double *buf = malloc(3 * TILE_X * TILE_Y * sizeof(double));
        sums *acc = malloc(band * nx * sizeof(sums));
        if (buf == NULL || acc == NULL) {
#pragma omp atomic write
            fail = 1;
        }
#pragma omp for schedule(dynamic)
        for (size_t task = 0; task < ntask; task++) {
            if (buf == NULL || acc == NULL)
                continue;
            const size_t jf = task * band, rows = ny - jf < band ? ny - jf : band;
            memset(acc, 0, rows * nx * sizeof(sums));
            const long sj0 = (r->j0 + (long)jf) * (long)sub, si0 = r->i0 * (long)sub;
            const size_t total_x = nx * sub, total_y = rows * sub;
            for (size_t oy = 0; oy < total_y; oy += TILE_Y) {
                const size_t wy = total_y - oy < TILE_Y ? total_y - oy : TILE_Y;
                for (size_t ox = 0; ox < total_x; ox += cx) {
                    const size_t wx = total_x - ox < cx ? total_x - ox : cx;
                    double *th = buf, *tsx = buf + TILE_X * TILE_Y,
                           *tsy = buf + 2 * TILE_X * TILE_Y;
                    sinusoid_tile(w, nc, delta, si0 + (long)ox, sj0 + (long)oy, wx, wy, t, th,
                                  tsx, tsy);
                    for (size_t b = 0; b < wy; b++) {
                        sums *arow = acc + ((oy + b) / sub) * nx;
                        for (size_t a = 0; a < wx; a++) {
                            const size_t q = b * wx + a;
                            add_point(&arow[(ox + a) / sub], th[q], tsx[q], tsy[q]);
                        }
                    }
                }
            }
            for (size_t j = 0; j < rows; j++)
                for (size_t i = 0; i < nx; i++)
                    out[(jf + j) * nx + i] = finish(&acc[j * nx + i], count, &csub);
        }
        free(buf);
        free(acc);
    }
    if (fail)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for sampling tiles");
    return SEA_OK;
}
