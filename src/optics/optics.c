/* optics.c - effective emissivity (Eq 7, 12), effective reflectivity and
 * BRDF (Eq 13, 14, 20) and the energy balance (Eq 21).
 *
 * Emissivity as an average.  With the D normalisation of Eq 10 the Smith
 * factor 1/(1 + Lambda) cancels between numerator and denominator of Eq 7,
 * which becomes the average of 1 - rho(psi) over the facets seen from v,
 * weighted by their projected area:
 *     eps = E_w[1 - rho(psi)],  w(gamma) = P(gamma) (cos th - gamma_X sin th)+.
 * (Indeed int P g over the seen facets is 1 + Lambda - m_X tan th
 * = D (1 + Lambda).)  So eps is in [0, 1] by construction, and every rule
 * below is self-normalised: the same nodes integrate the weight, which
 * removes the quadrature error of the weight itself.
 *
 * In the standardised variable t = (gamma_X - m_X)/s_X the weight is
 * (z - t)+ phi(t) (times s_X sin th), z = (cot th - m_X)/s_X, so one rule fits
 * every view from nadir (z -> inf, a plain Gaussian) to grazing views of a
 * tilted facet (z -> -inf, a Gamma(2)-shaped sliver of width 1/|z| below z).
 * Given gamma_X, gamma_Y is Gaussian with the conditional mean and variance
 * of the projected covariance.
 *
 * Reflectance as an average.  For a fixed observation v, the map from the
 * facet slope gamma to the mirror incidence w_i is one to one, with
 * d w_i = |J|^-1 d gamma (Eq 14d).  Hence
 *     int rho~(w_i; v) dw_i = E_w[rho(psi) (1 + L_o)/(1 + L_o + L_i) 1{w_i up}],
 * an integral over the slope PDF that resolves a glint of any width. */
#include "config.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
/* The emissivity's node loops in AVX2, chosen at run time (never required
 * at build time): the same IEEE operations in the same order as the
 * portable loops (no fused multiply-add), so the same bits. */
#define SEA_OPTICS_AVX2 1
#endif

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_linalg.h>

#include "seabake.h"
#include "internal.h"

/* fmax and fmin inline (the library's are calls, on the emissivity's
 * every node): the same values, a NaN argument losing to a number. */
static inline double sea_fmax(double a, double b)
{
    return a > b || __builtin_isnan(b) ? a : b;
}

static inline double sea_fmin(double a, double b)
{
    return a < b || __builtin_isnan(b) ? a : b;
}

/* Gauss-Legendre nodes of the reflectance's inner (gamma_Y) integral: a
 * smooth integrand over the exact mirror-up window, vanishing linearly at
 * its ends, for which 128 nodes reach round-off. */
enum { SEA_GL_INNER_NODES = 128 };
/* The standard normal weight is cut at |t| = 10: phi(10) = 7.7e-23. */
static const double SEA_T_CUT = 10.0;
/* The fixed product rules of sea_emissivity_rule and the default cut it at
 * |t| = 6 instead: the tail beyond holds 2e-9 of the weight, so the cut
 * moves an average of values in [0, 1] by less than that, and the nodes are
 * not spent on a tail that does not count at a 1e-4 target. */
static const double SEA_RULE_T_CUT = 6.0;
/* Orders of the default rule as functions of the slope spreads (see
 * sea_emissivity_auto_rule): Gauss-Legendre nodes n_gl = ceil(A + B s_X),
 * Gauss-Hermite nodes n_gh = ceil(C + D s + E s^2), s = s_Y|X (the
 * SEA_EMIS_AUTO_* coefficients of seabake.h).  Refitted
 * for 1e-6 (the orders 16 + 12 s_X and 2 + 6 s + 16 s^2 reached 1.3e-6 on
 * the bench's 896 conditions and 3.0e-6 on random ones, the cross-slope
 * rule short where s_Y|X is 0.2-0.45). */
/* A slope standard deviation below this is a delta distribution: the
 * rules could not resolve a narrower one in double precision. */
static const double SEA_S_DELTA = 1e-13;
/* Regularisation of the slope covariance in the 2-D PDF of Eq 13, so that a
 * flat sea (C = 0) gives a finite, very tall glint instead of 0/0. */
static const double SEA_COV_REG = 1e-18;
/* Adaptive reference: tolerances and workspace size.  GSL may stop with
 * GSL_EROUND when round-off keeps it from the requested tolerance (the
 * reflectance integrand has kinks where the mirror-up region meets the
 * +-10 sigma window); such a result is accepted when its own error estimate
 * is below SEA_REF_ACCEPT (relative) or SEA_REF_ABS_TOL, which still bounds
 * an energy total to 1e-5, a hundredth of the 1e-3 effects it is used to see. */
static const double SEA_REF_REL_TOL = 1e-10;
static const double SEA_REF_INNER_REL_TOL = 1e-10;
static const double SEA_REF_ABS_TOL = 1e-14;
static const double SEA_REF_ACCEPT = 1e-5;
static const double SEA_REF_INNER_ABS_ACCEPT = 1e-10;
/* ... and an outer numerator whose error is below this fraction of the
 * weight integral, i.e. an error below 1e-6 on the average itself. */
static const double SEA_REF_AVG_ACCEPT = 1e-6;
enum { SEA_REF_LIMIT = 256 };
/* Zenith angles below this are nadir (see shadow.c). */
static const double SEA_NADIR_THETA = 1e-12;

/* Node tables of every order up to the maxima, the rule of order n at
 * offset n (n - 1)/2: a fixed rule then costs no allocation per call. */
#define SEA_TRI(n) ((n) * ((n) + 1) / 2)
/* Fresnel reflectance of one index tabulated in cos psi on [0, 1], for the
 * emissivity's quadrature nodes: SEA_FRESNEL_INTERVALS equal intervals and
 * 4-point Lagrange interpolation (one-sided at the ends), stored as each
 * interval's cubic in monomials of the offset in it.  A table is used
 * only where it was checked, when built, against the formula at every
 * interval's midpoint and near grazing incidence: within
 * SEA_FRESNEL_TABLE_TOL absolute (measured on water, 1.09-1.48 + 0.001-0.42 i:
 * below 1e-11); otherwise (an index near 1, whose reflectance jumps at
 * grazing) the formula is evaluated at every node.  Up to
 * SEA_FRESNEL_CACHE indices are tabulated per plan (a band's samples); any
 * more are evaluated directly. */
enum { SEA_FRESNEL_INTERVALS = 2048, SEA_FRESNEL_CACHE = 64 };
static const double SEA_FRESNEL_TABLE_TOL = 1e-10;
typedef struct {
    double complex N;
    int usable;
    /* interval k: the cubic through its 4 nodes as a polynomial in the
     * offset t = u - k in [0, 1], u = c M (a0 + t (a1 + t (a2 + t a3))) */
    double a[SEA_FRESNEL_INTERVALS][4];
} fresnel_table;

/* Indices whose tables are looked up at once (stack arrays), by
 * sea_emissivity_n and by one recursion of the multiple reflections. */
enum { SEA_EMIS_BLOCK = 32 };
/* The second hits' spectral basis of a block of tables (spectral_basis_of):
 * rank functions B_r of cos psi and weights A_kr such that reflectance k
 * is sum_r A_kr B_r(cos psi) within SEA_BASIS_TOL.  The B_r are cubics on
 * SEA_BASIS_INTERVALS intervals of [0, 1] (a 32nd of the tables'; 16
 * samples of water over 3-5 and 8-12 um then have bases of rank 5 and 6
 * within 1.9e-7 and 4.3e-7 of every table, against 1.3e-6 and 1.8e-6 on 32
 * intervals), one interval's coefficients of every B_r side by side:
 *     c[(q 4 + i) lanes + r] = coefficient i of B_r on interval q,
 * lanes = rank rounded up to 4 (zeros beyond), so a node reads one
 * interval's block (16 KB in all at rank 8, within the first-level cache)
 * and evaluates every B_r at once. */
enum { SEA_BASIS_INTERVALS = 64, SEA_BASIS_SHIFT = 5 };
_Static_assert(SEA_BASIS_INTERVALS << SEA_BASIS_SHIFT == SEA_FRESNEL_INTERVALS,
               "a basis interval is a whole number of table intervals");
enum { SEA_BASIS_CACHE = 8, SEA_BASIS_RANK_MAX = 8 };
static const double SEA_BASIS_TOL = 2e-6;
typedef struct {
    size_t n;
    double complex N[SEA_EMIS_BLOCK];
    int rank;  /* 0: none (none within SEA_BASIS_TOL of rank <= SEA_BASIS_RANK_MAX, or
                * one that would not halve the lookups: basis_build) */
    int lanes; /* rank rounded up to a multiple of 4 */
    double err; /* the largest difference from a table, measured */
    double A[SEA_BASIS_RANK_MAX][SEA_EMIS_BLOCK]; /* A[r][k] */
    double *c;
} spectral_basis;

struct sea_optics {
    /* The Fresnel tables, filled on first use of an index under the lock;
     * n_fresnel is published after its table is complete, so readers scan
     * without the lock.  The spectral bases likewise. */
    pthread_mutex_t fresnel_lock;
    atomic_size_t n_fresnel;
    fresnel_table *fresnel[SEA_FRESNEL_CACHE];
    atomic_size_t n_basis;
    spectral_basis *basis[SEA_BASIS_CACHE];
    int use_basis; /* the second hits' inner sums through the spectral basis */
    gsl_integration_glfixed_table *gl_inner;
    double gl_x[SEA_TRI(SEA_EMIS_GL_MAX)]; /* Gauss-Legendre nodes on [-1, 1] */
    double gl_w[SEA_TRI(SEA_EMIS_GL_MAX)];
    double gh_x[SEA_TRI(SEA_EMIS_GH_MAX)]; /* probabilists' Hermite nodes */
    double gh_w[SEA_TRI(SEA_EMIS_GH_MAX)]; /* normalised weights (sum 1) */
    int avx2;                              /* this processor runs the AVX2 loops */
    sea_shadowing shadowing;
};

sea_status sea_optics_alloc(sea_optics **out, sea_error *err)
{
    *out = NULL;
    sea_optics *p = calloc(1, sizeof *p);
    if (p == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    pthread_mutex_init(&p->fresnel_lock, NULL);
    atomic_init(&p->n_fresnel, 0);
    atomic_init(&p->n_basis, 0);
    p->use_basis = 1;
    /* the default model's (sea_model_params_default): the paper's Smith
     * shadowing is one sea_optics_set_shadowing away */
    p->shadowing = SEA_SHADOW_CORRELATED;
#ifdef SEA_OPTICS_AVX2
    __builtin_cpu_init();
    p->avx2 = __builtin_cpu_supports("avx2") != 0;
#endif
    p->gl_inner = gsl_integration_glfixed_table_alloc(SEA_GL_INNER_NODES);
    if (p->gl_inner == NULL)
        goto nomem;
    for (int n = 1; n <= SEA_EMIS_GL_MAX; n++) {
        gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc((size_t)n);
        if (gl == NULL)
            goto nomem;
        for (int i = 0; i < n; i++)
            gsl_integration_glfixed_point(-1.0, 1.0, (size_t)i, &p->gl_x[SEA_TRI(n - 1) + i],
                                          &p->gl_w[SEA_TRI(n - 1) + i], gl);
        gsl_integration_glfixed_table_free(gl);
    }
    for (int n = 1; n <= SEA_EMIS_GH_MAX; n++) {
        gsl_integration_fixed_workspace *gh =
            gsl_integration_fixed_alloc(gsl_integration_fixed_hermite, (size_t)n, 0.0, 0.5, 0.0,
                                        0.0);
        if (gh == NULL)
            goto nomem;
        const double *x = gsl_integration_fixed_nodes(gh);
        const double *w = gsl_integration_fixed_weights(gh);
        double sum = 0.0;
        for (int i = 0; i < n; i++)
            sum += w[i];
        for (int i = 0; i < n; i++) {
            p->gh_x[SEA_TRI(n - 1) + i] = x[i];
            p->gh_w[SEA_TRI(n - 1) + i] = w[i] / sum;
        }
        gsl_integration_fixed_free(gh);
    }
    *out = p;
    return SEA_OK;
nomem:
    sea_optics_free(p);
    return sea_fail(err, SEA_ERR_NOMEM, "out of memory (quadrature tables)");
}

int sea_optics_set_simd(sea_optics *p, int on)
{
    p->avx2 = 0;
#ifdef SEA_OPTICS_AVX2
    p->avx2 = on && __builtin_cpu_supports("avx2") != 0;
#else
    (void)on;
#endif
    return p->avx2;
}

void sea_optics_set_spectral_basis(sea_optics *p, int on)
{
    p->use_basis = on != 0;
}

void sea_optics_free(sea_optics *p)
{
    if (p == NULL)
        return;
    if (p->gl_inner != NULL)
        gsl_integration_glfixed_table_free(p->gl_inner);
    const size_t n = atomic_load(&p->n_fresnel);
    for (size_t i = 0; i < n; i++)
        free(p->fresnel[i]);
    const size_t nb = atomic_load(&p->n_basis);
    for (size_t i = 0; i < nb; i++) {
        free(p->basis[i]->c);
        free(p->basis[i]);
    }
    pthread_mutex_destroy(&p->fresnel_lock);
    free(p);
}

int sea_emis_method_from_name(const char *name)
{
    if (strcmp(name, "auto") == 0)
        return SEA_EMIS_AUTO;
    if (strcmp(name, "fast") == 0)
        return SEA_EMIS_FAST;
    if (strcmp(name, "full") == 0)
        return SEA_EMIS_FULL;
    return -1;
}

int sea_reflections_from_name(const char *name)
{
    if (strcmp(name, "auto") == 0)
        return SEA_REFLECTIONS_AUTO;
    for (int r = 1; r <= SEA_REFLECTIONS_MAX; r++) {
        char d[2] = { (char)('0' + r), '\0' };
        if (strcmp(name, d) == 0)
            return r;
    }
    return -1;
}

void sea_optics_set_shadowing(sea_optics *p, sea_shadowing s)
{
    p->shadowing = s == SEA_SHADOW_CORRELATED ? SEA_SHADOW_CORRELATED : SEA_SHADOW_SMITH;
}

sea_shadowing sea_optics_shadowing(const sea_optics *p)
{
    return p->shadowing;
}

int sea_shadowing_from_name(const char *name)
{
    if (strcmp(name, "smith") == 0)
        return SEA_SHADOW_SMITH;
    if (strcmp(name, "correlated") == 0)
        return SEA_SHADOW_CORRELATED;
    return -1;
}

const char *sea_shadowing_name(sea_shadowing s)
{
    return s == SEA_SHADOW_CORRELATED ? "correlated" : "smith";
}

const char *sea_emis_method_name(sea_emis_method m)
{
    switch (m) {
    case SEA_EMIS_AUTO: return "auto";
    case SEA_EMIS_FAST: return "fast";
    case SEA_EMIS_FULL: return "full";
    }
    return "?";
}

/* ------------------------------------------------------- the view frame */

/* Slope statistics in the frame of the view azimuth (Eq 6, 8) and the
 * standardised visibility limit. */
typedef struct {
    double cos_th, sin_th, phi;
    double cos_phi, sin_phi;
    double m_X, m_Y;      /* mean */
    double s_X;           /* std of gamma_X */
    double b_YX;          /* regression of gamma_Y on t: C_XY / s_X */
    double s_Y_given_X;   /* conditional std of gamma_Y */
    double c_XX, c_YY, c_XY;
    double z;             /* (cot th - m_X)/s_X; +inf at nadir */
    double t_lo, t_hi;    /* where the weight lives */
    double t_ref;         /* min(z, 0): the weight's exponent is taken relative to it */
    int delta;            /* s_X below SEA_S_DELTA */
    int corr;             /* weights times sea_shadow_correlated(z, t) */
} view_frame;

/* Where the weight lives, for a standard normal cut at |t| = t_cut.  Upper
 * end: the visibility limit z, or the cut.  Lower end: the cut, or for
 * z < 0 the point where (z - t) phi(t) has fallen by exp(-t_cut^2/2) from
 * the edge: with t = z - u, log decay |z| u + u^2/2 = t_cut^2/2. */
static void view_window(const view_frame *f, double t_cut, double *t_lo, double *t_hi)
{
    *t_hi = sea_fmin(f->z, t_cut);
    const double az = fabs(f->z);
    *t_lo = isinf(f->z) ? -t_cut : sea_fmin(-t_cut, f->z - (sqrt(az * az + t_cut * t_cut) - az));
}

/* The frame from the view's cosines (cos_th, sin_th >= 0; azimuth phi of
 * cosine c, sine s); nadir: the view is the zenith (no shadowing). */
static void view_frame_init_cs(const sea_optics *p, const sea_slope_stats *st, double cos_th,
                               double sin_th, double phi, double c, double s, int nadir,
                               view_frame *f)
{
    const sea_cov2 *C = &st->cov;
    f->cos_th = cos_th;
    f->sin_th = sin_th;
    f->phi = phi;
    f->cos_phi = c;
    f->sin_phi = s;
    f->m_X = st->mean.x * c + st->mean.y * s;
    f->m_Y = -st->mean.x * s + st->mean.y * c;
    f->c_XX = sea_fmax(C->xx * c * c + 2.0 * C->xy * s * c + C->yy * s * s, 0.0);
    f->c_YY = sea_fmax(C->xx * s * s - 2.0 * C->xy * s * c + C->yy * c * c, 0.0);
    f->c_XY = (C->yy - C->xx) * s * c + C->xy * (c * c - s * s);
    f->s_X = sqrt(f->c_XX);
    f->delta = f->s_X < SEA_S_DELTA;
    if (f->delta) {
        f->b_YX = 0.0;
        f->s_Y_given_X = sqrt(f->c_YY);
    } else {
        f->b_YX = f->c_XY / f->s_X;
        f->s_Y_given_X = sqrt(sea_fmax(f->c_YY - f->b_YX * f->b_YX, 0.0));
    }
    if (nadir || f->delta) {
        f->z = INFINITY;
    } else {
        f->z = (f->cos_th / f->sin_th - f->m_X) / f->s_X;
    }
    view_window(f, SEA_T_CUT, &f->t_lo, &f->t_hi);
    f->t_ref = sea_fmin(f->z, 0.0);
    /* the correlated function is a visibility from above the surface: a
     * view from below (a facet met again, MULTIPLE REFLECTIONS) counts by
     * its projected area alone */
    f->corr = p != NULL && p->shadowing == SEA_SHADOW_CORRELATED && isfinite(f->z) &&
              f->cos_th > 0.0;
}

static void view_frame_init(const sea_optics *p, const sea_slope_stats *st, sea_dir v,
                            view_frame *f)
{
    view_frame_init_cs(p, st, cos(v.theta), sin(v.theta), v.phi, cos(v.phi), sin(v.phi),
                       v.theta < SEA_NADIR_THETA, f);
}

/* Projected-area weight (cos th - gamma_X sin th)+ phi(t), up to a constant.
 * The constant is exp(t_ref^2 / 2): when the mean slope hides nearly every
 * facet (z < 0), the weight lives in t <= z, and exp(-t^2/2) alone would
 * underflow for z < -38 (say theta = 89 deg, m_X = 0.5, s_X = 0.005), turning
 * an emissivity of 6e-4 into 0/0 -> 0.  Relative to its value at t = z
 * the exponent is <= 0 over the window and the averages, ratios of two
 * integrals of this weight, are unchanged. */
static double view_weight(const view_frame *f, double t)
{
    const double gX = f->m_X + f->s_X * t;
    const double g = f->cos_th - gX * f->sin_th;
    if (!(g > 0.0))
        return 0.0;
    const double w = g * exp(-0.5 * (t - f->t_ref) * (t + f->t_ref));
    return f->corr ? w * sea_shadow_correlated(f->z, t) : w;
}

/* exp(x) for the fixed rules' weights, x in [-700, 0] (clamped below):
 * x = k ln 2 + r, |r| <= ln 2 / 2 (ln 2 in two parts, k ln2_hi exact),
 * Taylor to r^13 (truncation 4e-18) by Estrin's scheme, times 2^k
 * exactly; within 2.2 ulp of the exact value (measured on 2e7 points of
 * [-700, 0]; Horner's rule, 1.2 ulp, is a chain three times as long).
 * Written once for the portable loop and once in AVX2 with the same
 * operations in the same order, so both give the same bits. */
static const double SEA_EXP_LOG2E = 1.4426950408889634074;
static const double SEA_EXP_LN2_HI = 6.93147180369123816490e-01;
static const double SEA_EXP_LN2_LO = 1.90821492927058770002e-10;
static const double SEA_EXP_MIN = -700.0;
static const double SEA_EXP_TAYLOR[14] = {
    1.0, 1.0, 1.0 / 2, 1.0 / 6, 1.0 / 24, 1.0 / 120, 1.0 / 720, 1.0 / 5040, 1.0 / 40320,
    1.0 / 362880, 1.0 / 3628800, 1.0 / 39916800, 1.0 / 479001600, 1.0 / 6227020800.0,
};

static inline double exp_rule(double x)
{
    x = x < SEA_EXP_MIN ? SEA_EXP_MIN : x;
    const double k = floor(x * SEA_EXP_LOG2E + 0.5);
    const double r = (x - k * SEA_EXP_LN2_HI) - k * SEA_EXP_LN2_LO;
    /* Estrin's scheme (a chain 4 products deep instead of Horner's 13) */
    const double *c = SEA_EXP_TAYLOR;
    const double r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
    const double p0 = c[0] + c[1] * r, p1 = c[2] + c[3] * r, p2 = c[4] + c[5] * r;
    const double p3 = c[6] + c[7] * r, p4 = c[8] + c[9] * r, p5 = c[10] + c[11] * r;
    const double p6 = c[12] + c[13] * r;
    const double q0 = p0 + p1 * r2, q1 = p2 + p3 * r2, q2 = p4 + p5 * r2;
    const double s0 = q0 + q1 * r4, s1 = q2 + p6 * r4;
    /* times 2^k, exactly: k >= -1010 here, so 2^k is a normal number put
     * together in the exponent bits (as the AVX2 loop does), without
     * ldexp's call */
    const union { uint64_t u; double d; } two_k = { (uint64_t)((int64_t)k + 1023) << 52 };
    return (s0 + s1 * r8) * two_k.d;
}

/* The fixed rules' weight at node t: view_weight with exp_rule. */
static inline double rule_weight(const view_frame *f, double t)
{
    const double gX = f->m_X + f->s_X * t;
    const double g = f->cos_th - gX * f->sin_th;
    return g > 0.0 ? g * exp_rule(-0.5 * (t - f->t_ref) * (t + f->t_ref)) : 0.0;
}

/* A facet quantity averaged over the seen facets: fn(gX, gY, cos psi, ctx). */
typedef double (*facet_fn)(const view_frame *f, double gX, double gY, double cos_psi,
                           void *ctx);

static double cos_psi_of(const view_frame *f, double gX, double gY)
{
    return (f->cos_th - gX * f->sin_th) / sqrt(1.0 + gX * gX + gY * gY);
}

/* A fixed product rule: n_gl Gauss-Legendre nodes in t over the window of
 * the cut t_cut, and n_gh Gauss-Hermite nodes over the conditional gamma_Y
 * (Eq 7), or n_gh = 0 for gamma_Y = m_Y in psi (Eq 11-12). */
typedef struct {
    int n_gl, n_gh;
    double t_cut;
} fixed_rule;

/* ------------------------------------------ adaptive reference (Eq 7) */

typedef struct {
    const view_frame *f;
    facet_fn fn;
    void *ctx;
    int mirror_up;     /* integrate only where the mirror ray leaves upwards */
    const gsl_integration_glfixed_table *gl_inner; /* inner rule when mirror_up */
    gsl_integration_workspace *ws_in;
    double t;          /* current outer node */
    int status;        /* first GSL failure */
} ref_args;

/* The mirror ray of the view direction on facet (gX, gY) (view frame)
 * points up iff 2 (cos th - gX sin th)/(1 + gX^2 + gY^2) > cos th, i.e.
 * gY^2 < R(gX) = 1 - 2 gX tan th - gX^2, so for gX strictly between
 * -tan th -+ sec th.  Integrating over that region exactly avoids the kink
 * the integrand has on its boundary. */
static double mirror_up_R(const view_frame *f, double gX)
{
    return 1.0 - 2.0 * gX * f->sin_th / f->cos_th - gX * gX;
}

/* GSL status, with a round-off stop of small estimated error counted as success. */
static int ref_status(int rc, double result, double abserr, double rel, double abs_floor)
{
    if (rc == GSL_EROUND && abserr <= rel * fabs(result) + abs_floor)
        return GSL_SUCCESS;
    return rc;
}

static double ref_inner(double u, void *params)
{
    ref_args *a = params;
    const view_frame *f = a->f;
    const double gX = f->delta ? f->m_X : f->m_X + f->s_X * a->t;
    const double gY = f->m_Y + f->b_YX * a->t + f->s_Y_given_X * u;
    return exp(-0.5 * u * u) * a->fn(f, gX, gY, cos_psi_of(f, gX, gY), a->ctx);
}

/* Normalised average of fn over gamma_Y given the outer node t. */
static double ref_inner_mean(ref_args *a, double t)
{
    a->t = t;
    if (a->f->s_Y_given_X < SEA_S_DELTA) {
        const double gX = a->f->delta ? a->f->m_X : a->f->m_X + a->f->s_X * t;
        const double gY = a->f->m_Y + a->f->b_YX * t;
        if (a->mirror_up && !(gY * gY < mirror_up_R(a->f, gX)))
            return 0.0;
        return a->fn(a->f, gX, gY, cos_psi_of(a->f, gX, gY), a->ctx);
    }
    double u_lo = -SEA_T_CUT, u_hi = SEA_T_CUT;
    if (a->mirror_up) {
        const double gX = a->f->delta ? a->f->m_X : a->f->m_X + a->f->s_X * t;
        const double R = mirror_up_R(a->f, gX);
        if (!(R > 0.0))
            return 0.0;
        const double mY = a->f->m_Y + a->f->b_YX * t, sY = a->f->s_Y_given_X;
        u_lo = sea_fmax(u_lo, (-sqrt(R) - mY) / sY);
        u_hi = sea_fmin(u_hi, (sqrt(R) - mY) / sY);
        if (!(u_lo < u_hi))
            return 0.0;
    }
    if (a->mirror_up) {
        double acc = 0.0;
        for (size_t k = 0; k < SEA_GL_INNER_NODES; k++) {
            double u, wk;
            gsl_integration_glfixed_point(u_lo, u_hi, k, &u, &wk, a->gl_inner);
            acc += wk * ref_inner(u, a);
        }
        return acc / sqrt(2.0 * M_PI);
    }
    gsl_function F = { ref_inner, a };
    double r, e;
    int rc = gsl_integration_qag(&F, u_lo, u_hi, SEA_REF_ABS_TOL,
                                 SEA_REF_INNER_REL_TOL, SEA_REF_LIMIT, GSL_INTEG_GAUSS21,
                                 a->ws_in, &r, &e);
    /* The inner average multiplies an outer weight of order one. */
    rc = ref_status(rc, r, e, SEA_REF_ACCEPT, SEA_REF_INNER_ABS_ACCEPT);
    if (rc != GSL_SUCCESS && a->status == GSL_SUCCESS)
        a->status = rc;
    return r / sqrt(2.0 * M_PI);
}

static double ref_outer(double t, void *params)
{
    ref_args *a = params;
    const double w = view_weight(a->f, t);
    return w > 0.0 ? w * ref_inner_mean(a, t) : 0.0;
}

static double ref_outer_weight(double t, void *params)
{
    return view_weight(params, t);
}

static sea_status expect_reference(const sea_optics *p, const view_frame *f, facet_fn fn,
                                   void *ctx, int mirror_up, double *out, sea_error *err)
{
    sea_status st = SEA_OK;
    ref_args a = { f, fn, ctx, mirror_up, p->gl_inner, NULL, 0.0, GSL_SUCCESS };
    gsl_integration_workspace *ws_out = gsl_integration_workspace_alloc(SEA_REF_LIMIT);
    a.ws_in = gsl_integration_workspace_alloc(SEA_REF_LIMIT);
    if (ws_out == NULL || a.ws_in == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory (quadrature workspace)");
        goto done;
    }
    if (f->delta) {
        *out = f->cos_th - f->m_X * f->sin_th > 0.0 ? ref_inner_mean(&a, 0.0) : 0.0;
    } else {
        gsl_function F = { ref_outer, &a };
        gsl_function W = { ref_outer_weight, (void *)f };
        double num = 0.0, den = 0.0, e;
        double t_lo = f->t_lo, t_hi = f->t_hi;
        if (mirror_up) { /* gX within -tan th -+ sec th */
            const double tn = f->sin_th / f->cos_th, sc = 1.0 / f->cos_th;
            t_lo = sea_fmax(t_lo, (-tn - sc - f->m_X) / f->s_X);
            t_hi = sea_fmin(t_hi, (sc - tn - f->m_X) / f->s_X);
        }
        /* The weight integral first: it sets the scale of what an error in
         * the numerator means for the average. */
        int rc = gsl_integration_qag(&W, f->t_lo, f->t_hi, SEA_REF_ABS_TOL, SEA_REF_REL_TOL,
                                     SEA_REF_LIMIT, GSL_INTEG_GAUSS21, ws_out, &den, &e);
        rc = ref_status(rc, den, e, SEA_REF_ACCEPT, SEA_REF_ABS_TOL);
        if (rc == GSL_SUCCESS && t_lo < t_hi) {
            rc = gsl_integration_qag(&F, t_lo, t_hi, SEA_REF_ABS_TOL, SEA_REF_REL_TOL,
                                     SEA_REF_LIMIT, GSL_INTEG_GAUSS21, ws_out, &num, &e);
            rc = ref_status(rc, num, e, SEA_REF_ACCEPT, SEA_REF_AVG_ACCEPT * den);
        }
        *out = den > 0.0 ? num / den : 0.0;
    }
    if (a.status != GSL_SUCCESS)
        st = sea_fail(err, SEA_ERR_NUMERIC, "adaptive facet quadrature did not converge: %s",
                      gsl_strerror(a.status));
done:
    gsl_integration_workspace_free(ws_out);
    gsl_integration_workspace_free(a.ws_in);
    return st;
}

/* The default's orders, from the spreads of the view frame: see
 * sea_emissivity_auto_rule. */
static sea_emis_rule auto_rule(const view_frame *f)
{
    const double s = f->s_Y_given_X;
    const double n_gl = ceil(SEA_EMIS_AUTO_GL_A + SEA_EMIS_AUTO_GL_B * f->s_X);
    const double n_gh =
        ceil(SEA_EMIS_AUTO_GH_C + SEA_EMIS_AUTO_GH_D * s + SEA_EMIS_AUTO_GH_E * s * s);
    return (sea_emis_rule){ (int)sea_fmin(n_gl, SEA_EMIS_GL_MAX),
                            (int)sea_fmin(n_gh, SEA_EMIS_GH_MAX) };
}

/* ------------------------------------------------------------ emissivity */

/* Where a piecewise cubic on M equal intervals of [0, 1] is read for c
 * (clamped to [0, 1]): interval *k and offset t in [0, 1] (c = 1 is the end
 * of the last interval). */
static inline double interval_pos(double c, int M, int *k)
{
    const double u = (c < 0.0 ? 0.0 : c > 1.0 ? 1.0 : c) * M;
    int i = (int)u;
    i = i > M - 1 ? M - 1 : i;
    *k = i;
    return u - i;
}

/* Where the Fresnel table is read for c. */
static inline double fresnel_pos(double c, int *k)
{
    return interval_pos(c, SEA_FRESNEL_INTERVALS, k);
}

/* The table's cubic of interval k at offset t, clamped to [0, 1] (a
 * reflectance, as the formula's). */
static inline double cubic_at(const fresnel_table *tb, int k, double t)
{
    const double *a = tb->a[k];
    return a[0] + t * (a[1] + t * (a[2] + t * a[3]));
}

static inline double fresnel_eval(const fresnel_table *tb, int k, double t)
{
    const double r = cubic_at(tb, k, t);
    return r < 0.0 ? 0.0 : r > 1.0 ? 1.0 : r;
}

/* The table's interpolation at c in [0, 1]. */
static inline double fresnel_interp(const fresnel_table *tb, double c)
{
    int k;
    const double t = fresnel_pos(c, &k);
    return fresnel_eval(tb, k, t);
}

/* Interval k interpolates the 4 nodes k - 1 .. k + 2 (one-sided at the
 * ends: 0 .. 3 and M - 3 .. M), the Lagrange cubic written in monomials of
 * the offset t from node k: no division and 3 multiply-adds per value. */
static void fresnel_build(fresnel_table *tb, double complex N)
{
    enum { M = SEA_FRESNEL_INTERVALS };
    double v[M + 1];
    tb->N = N;
    for (int k = 0; k <= M; k++)
        v[k] = sea_fresnel_unpolarized((double)k / M, N);
    for (int k = 0; k < M; k++) {
        const int b = k < 1 ? 0 : k > M - 2 ? M - 3 : k - 1;
        const double *w = &v[b];
        /* P(x) on the nodes x = 0..3 in monomials of x ... */
        double c[4] = {
            w[0],
            (-11.0 * w[0] + 18.0 * w[1] - 9.0 * w[2] + 2.0 * w[3]) / 6.0,
            (2.0 * w[0] - 5.0 * w[1] + 4.0 * w[2] - w[3]) / 2.0,
            (-w[0] + 3.0 * w[1] - 3.0 * w[2] + w[3]) / 6.0,
        };
        /* ... shifted to x = x0 + t (Taylor coefficients at x0 = k - b by
         * repeated synthetic division) */
        const double x0 = k - b;
        for (int i = 0; i < 3; i++)
            for (int m = 2; m >= i; m--)
                c[m] += x0 * c[m + 1];
        memcpy(tb->a[k], c, sizeof c);
    }
    double worst = 0.0;
    for (int k = 0; k < M; k++) {
        const double c = (k + 0.5) / M;
        worst = sea_fmax(worst, fabs(fresnel_interp(tb, c) - sea_fresnel_unpolarized(c, N)));
    }
    static const double near_grazing[] = { 1e-9, 1e-6, 1e-4, 1e-3 };
    for (size_t k = 0; k < sizeof near_grazing / sizeof near_grazing[0]; k++)
        worst = sea_fmax(worst, fabs(fresnel_interp(tb, near_grazing[k]) -
                                 sea_fresnel_unpolarized(near_grazing[k], N)));
    tb->usable = worst <= SEA_FRESNEL_TABLE_TOL;
}

/* The usable table of N, built on first use; NULL when the formula must be
 * evaluated (no usable table, or the cache is full).  The plan is const to
 * its users: its cache is filled under its own lock. */
static const fresnel_table *fresnel_of(const sea_optics *pc, double complex N, size_t *hint)
{
    sea_optics *p = (sea_optics *)pc;
    size_t n = atomic_load_explicit(&p->n_fresnel, memory_order_acquire);
    /* A band's samples were tabulated in order: the slot after the
     * previous sample's first. */
    const size_t h = *hint;
    *hint = h + 1;
    if (h < n && p->fresnel[h]->N == N)
        return p->fresnel[h]->usable ? p->fresnel[h] : NULL;
    for (size_t i = 0; i < n; i++)
        if (p->fresnel[i]->N == N) {
            *hint = i + 1;
            return p->fresnel[i]->usable ? p->fresnel[i] : NULL;
        }
    const fresnel_table *found = NULL;
    pthread_mutex_lock(&p->fresnel_lock);
    n = atomic_load_explicit(&p->n_fresnel, memory_order_relaxed);
    size_t i = 0;
    while (i < n && p->fresnel[i]->N != N)
        i++;
    *hint = i + 1;
    if (i < n) {
        found = p->fresnel[i];
    } else if (n < SEA_FRESNEL_CACHE) {
        fresnel_table *t = malloc(sizeof *t);
        if (t != NULL) { /* out of memory: the formula, no table */
            fresnel_build(t, N);
            p->fresnel[n] = t;
            atomic_store_explicit(&p->n_fresnel, n + 1, memory_order_release);
            found = t;
        }
    }
    pthread_mutex_unlock(&p->fresnel_lock);
    return found != NULL && found->usable ? found : NULL;
}

/* rho(psi) of index N at cos psi = c, from its table when it has one
 * (hint as fresnel_of's). */
static double fresnel_at(const sea_optics *p, double complex N, double c, size_t *hint)
{
    const fresnel_table *tb = fresnel_of(p, N, hint);
    return tb != NULL ? fresnel_interp(tb, c) : sea_fresnel_unpolarized(c, N);
}

/* What the emissivity integrates: 1 - rho(psi) of index N, from its table
 * when it has one. */
typedef struct {
    double complex N;
    const fresnel_table *table;
} emis_ctx;

static inline double one_minus_rho(const emis_ctx *e, double cos_psi)
{
    return 1.0 - (e->table != NULL ? fresnel_interp(e->table, cos_psi)
                                   : sea_fresnel_unpolarized(cos_psi, e->N));
}

/* rho(psi) of e as 1 - one_minus_rho(e, cos_psi) gives it (the same bits),
 * with the table position (k, t) of cos_psi found once for every index;
 * exact: the formula, whatever the table. */
static inline double rho_at(const emis_ctx *e, int exact, int k, double t, double cos_psi)
{
    if (exact || e->table == NULL)
        return 1.0 - (1.0 - sea_fresnel_unpolarized(cos_psi, e->N));
    return 1.0 - (1.0 - fresnel_eval(e->table, k, t));
}

static double emissivity_fn(const view_frame *f, double gX, double gY, double cos_psi,
                            void *ctx)
{
    (void)f, (void)gX, (void)gY;
    return one_minus_rho(ctx, cos_psi);
}

static sea_status check_dir(sea_dir v, const char *what, sea_error *err)
{
    if (!(v.theta >= 0.0 && v.theta < M_PI_2) || !isfinite(v.phi))
        return sea_fail(err, SEA_ERR_DOMAIN, "%s zenith %g deg is outside [0, 90) deg", what,
                        v.theta * 180.0 / M_PI);
    return SEA_OK;
}

sea_status sea_emissivity(const sea_optics *p, sea_emis_method method, double complex N,
                          const sea_slope_stats *st, sea_dir v, double *out, sea_error *err)
{
    if (method != SEA_EMIS_FULL) /* the fixed rules: one index of the many-index path */
        return sea_emissivity_n(p, method, NULL, &N, 1, st, v, out, err);
    sea_status s;
    if ((s = check_dir(v, "view", err)) != SEA_OK || (s = sea_slope_stats_check(st, err)) != SEA_OK)
        return s;
    view_frame f;
    view_frame_init(p, st, v, &f);
    /* The reference evaluates the formula itself, never a table. */
    emis_ctx e = { N, NULL };
    return expect_reference(p, &f, emissivity_fn, &e, 0, out, err);
}

/* The nodes of a fixed product rule (Eq 7: n_gl Gauss-Legendre nodes in t
 * over the window of the cut t_cut, n_gh Gauss-Hermite nodes over the
 * conditional gamma_Y; Eq 12: n_gh = 0, gamma_Y = m_Y in psi, Eq 11): the
 * outer weights w_i (0 where a node lies on turned-away facets), the inner
 * weights (the rule's Gauss-Hermite weights, shared, or 1 for Eq 12) and
 * cos psi at every node.  Computed once for the view; an integrand of psi
 * (1 - rho for each index) then sums over them. */
typedef struct {
    int n_i, n_j;          /* n_j = 1 for Eq 12 (weight 1) */
    int zero;              /* every facet turned away: the result is 0 */
    int plain;             /* no outer average (delta): the result is the inner sum */
    double w_i[SEA_EMIS_GL_MAX], w_j[SEA_EMIS_GH_MAX];
    /* (+ 4: the AVX2 loops write whole vectors past a row's end) */
    double cos_psi[SEA_EMIS_GL_MAX * SEA_EMIS_GH_MAX + 4];
    /* Where every node (of positive w_i) reads a Fresnel table: the same
     * for every index, so found once (table_positions) when a table is used. */
    int tab_k[SEA_EMIS_GL_MAX * SEA_EMIS_GH_MAX + 4];
    double tab_t[SEA_EMIS_GL_MAX * SEA_EMIS_GH_MAX + 4];
    /* Node q = i n_j + j's weight w_i w_j (0 where w_i is not positive),
     * n_q of them, then zeros (with positions 0, 0) to a multiple of 4:
     * the table sums run over every node at once (flat_sum). */
    double w_q[SEA_EMIS_GL_MAX * SEA_EMIS_GH_MAX + 4];
    int n_q;
    int positioned;        /* tab_k and tab_t are filled */
    int avx2;              /* the AVX2 loops (sea_optics.avx2) */
} fixed_nodes;

#ifdef SEA_OPTICS_AVX2
/* inner_nodes' loop and then fresnel_pos for the row, four nodes at a time.
 * Loads and stores whole vectors (masked ones are slow on some
 * processors): x may be read, and cos_psi, k and t written, up to 3 nodes
 * past n, which every caller's arrays allow (a following row overwritten
 * later, or spare room); what lies there is never summed. */
__attribute__((target("avx2"))) static void row_nodes_avx2(double num, double one_gX2,
                                                           double mY, double s, const double *x,
                                                           int n, double *cos_psi, int *k,
                                                           double *t)
{
    const __m256d vnum = _mm256_set1_pd(num), vone = _mm256_set1_pd(one_gX2);
    const __m256d vmY = _mm256_set1_pd(mY), vs = _mm256_set1_pd(s);
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
    const __m256d M = _mm256_set1_pd((double)SEA_FRESNEL_INTERVALS);
    const __m128i last = _mm_set1_epi32(SEA_FRESNEL_INTERVALS - 1);
    for (int j = 0; j < n; j += 4) {
        const __m256d gY = _mm256_add_pd(vmY, _mm256_mul_pd(vs, _mm256_loadu_pd(x + j)));
        const __m256d c =
            _mm256_div_pd(vnum, _mm256_sqrt_pd(_mm256_add_pd(vone, _mm256_mul_pd(gY, gY))));
        const __m256d u = _mm256_mul_pd(_mm256_min_pd(_mm256_max_pd(c, zero), one), M);
        const __m128i ki = _mm_min_epi32(_mm256_cvttpd_epi32(u), last);
        _mm256_storeu_pd(cos_psi + j, c);
        _mm256_storeu_pd(t + j, _mm256_sub_pd(u, _mm256_cvtepi32_pd(ki)));
        _mm_storeu_si128((__m128i *)(k + j), ki);
    }
}

/* The cubics of four coefficient rows c0..c3 (a0 a1 a2 a3 each, one row a
 * lane after the transpose) at the offsets tt: cubic_at's operations in the
 * same order, four lanes at once. */
__attribute__((target("avx2"))) static inline __m256d cubic4(__m256d c0, __m256d c1, __m256d c2,
                                                             __m256d c3, __m256d tt)
{
    __m256d a[4] = { c0, c1, c2, c3 };
    sea_transpose4_avx2(a);
    __m256d v = _mm256_add_pd(a[2], _mm256_mul_pd(tt, a[3]));
    v = _mm256_add_pd(a[1], _mm256_mul_pd(tt, v));
    return _mm256_add_pd(a[0], _mm256_mul_pd(tt, v));
}

/* 1 - the reflectance: cubic4 clamped to [0, 1] (fresnel_eval's). */
__attribute__((target("avx2"))) static inline __m256d one_minus_cubic4(__m256d c0, __m256d c1,
                                                                       __m256d c2, __m256d c3,
                                                                       __m256d tt)
{
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
    const __m256d v = cubic4(c0, c1, c2, c3, tt);
    return _mm256_sub_pd(one, _mm256_min_pd(_mm256_max_pd(v, zero), one));
}

/* The sum over the nodes of w_q (1 - rho) from table tb, four nodes at a
 * time (fresnel_eval's operations; each node's four coefficients are one
 * load, transposed): lane m adds the nodes q = m mod 4 in the order of q,
 * and the lanes are added as (0 + 1) + (2 + 3), as flat_sum does. */
__attribute__((target("avx2"))) static double flat_sum_avx2(const fresnel_table *tb,
                                                            const fixed_nodes *nd)
{
    const int *k = nd->tab_k;
    const double *t = nd->tab_t, *w = nd->w_q;
    __m256d acc = _mm256_setzero_pd();
    for (int q = 0; q < nd->n_q; q += 4) {
        const __m256d c0 = _mm256_loadu_pd(tb->a[k[q]]), c1 = _mm256_loadu_pd(tb->a[k[q + 1]]);
        const __m256d c2 = _mm256_loadu_pd(tb->a[k[q + 2]]), c3 = _mm256_loadu_pd(tb->a[k[q + 3]]);
        acc = _mm256_add_pd(acc, _mm256_mul_pd(_mm256_loadu_pd(w + q),
                                               one_minus_cubic4(c0, c1, c2, c3,
                                                                _mm256_loadu_pd(t + q))));
    }
    double l[4];
    _mm256_storeu_pd(l, acc);
    return (l[0] + l[1]) + (l[2] + l[3]);
}

/* flat_sum_avx2 of four tables at once, one table a lane: node q's four
 * coefficient rows, one from each table, transposed, into accumulator
 * q mod 4; each table's sums in flat_sum_avx2's order. */
__attribute__((target("avx2"))) static void flat_sum4_avx2(const fresnel_table *const tb[4],
                                                           const fixed_nodes *nd, double out[4])
{
    const int *k = nd->tab_k;
    const double *t = nd->tab_t, *w = nd->w_q;
    const __m256d zero = _mm256_setzero_pd();
    __m256d acc[4] = { zero, zero, zero, zero };
    for (int q = 0; q < nd->n_q; q += 4)
        for (int m = 0; m < 4; m++) {
            const int kq = k[q + m];
            const __m256d c0 = _mm256_loadu_pd(tb[0]->a[kq]), c1 = _mm256_loadu_pd(tb[1]->a[kq]);
            const __m256d c2 = _mm256_loadu_pd(tb[2]->a[kq]), c3 = _mm256_loadu_pd(tb[3]->a[kq]);
            const __m256d v = one_minus_cubic4(c0, c1, c2, c3, _mm256_set1_pd(t[q + m]));
            acc[m] = _mm256_add_pd(acc[m], _mm256_mul_pd(_mm256_set1_pd(w[q + m]), v));
        }
    _mm256_storeu_pd(out, _mm256_add_pd(_mm256_add_pd(acc[0], acc[1]),
                                        _mm256_add_pd(acc[2], acc[3])));
}
#endif

#ifdef SEA_OPTICS_AVX2
/* nodes_fixed's outer weights w_i = wx_i rule_weight(t_i), clamped at 0,
 * t_i = mid + half x_i, four nodes at a time (exp_rule's operations, 2^k
 * put together in the exponent bits).  Reads x and wx, and writes w, up
 * to 3 nodes past n: the node tables run on (or end on a multiple of 4)
 * and w has room. */
__attribute__((target("avx2"))) static void rule_weights_avx2(const view_frame *f, double mid,
                                                              double half, const double *x,
                                                              const double *wx, int n, double *w)
{
    const __m256d vmid = _mm256_set1_pd(mid), vhalf = _mm256_set1_pd(half);
    const __m256d mX = _mm256_set1_pd(f->m_X), sX = _mm256_set1_pd(f->s_X);
    const __m256d ct = _mm256_set1_pd(f->cos_th), st = _mm256_set1_pd(f->sin_th);
    const __m256d tr = _mm256_set1_pd(f->t_ref), mhalf = _mm256_set1_pd(-0.5);
    const __m256d zero = _mm256_setzero_pd(), point5 = _mm256_set1_pd(0.5);
    const __m256d lo = _mm256_set1_pd(SEA_EXP_MIN), log2e = _mm256_set1_pd(SEA_EXP_LOG2E);
    const __m256d ln2hi = _mm256_set1_pd(SEA_EXP_LN2_HI), ln2lo = _mm256_set1_pd(SEA_EXP_LN2_LO);
    /* k + 2^52 + 2^51 holds k + 2^51 in its low mantissa bits */
    const __m256d magic = _mm256_set1_pd(6755399441055744.0);
    const __m256i bias = _mm256_set1_epi64x(1023 - 2251799813685248LL);
    for (int i = 0; i < n; i += 4) {
        const __m256d t = _mm256_add_pd(vmid, _mm256_mul_pd(vhalf, _mm256_loadu_pd(x + i)));
        const __m256d gX = _mm256_add_pd(mX, _mm256_mul_pd(sX, t));
        const __m256d g = _mm256_sub_pd(ct, _mm256_mul_pd(gX, st));
        __m256d e = _mm256_mul_pd(_mm256_mul_pd(mhalf, _mm256_sub_pd(t, tr)), _mm256_add_pd(t, tr));
        e = _mm256_max_pd(e, lo);
        const __m256d k = _mm256_floor_pd(_mm256_add_pd(_mm256_mul_pd(e, log2e), point5));
        const __m256d r =
            _mm256_sub_pd(_mm256_sub_pd(e, _mm256_mul_pd(k, ln2hi)), _mm256_mul_pd(k, ln2lo));
        /* Estrin's scheme: exp_rule's operations */
        const __m256d r2 = _mm256_mul_pd(r, r), r4 = _mm256_mul_pd(r2, r2);
        const __m256d r8 = _mm256_mul_pd(r4, r4);
#define SEA_PAIR(a) \
    _mm256_add_pd(_mm256_set1_pd(SEA_EXP_TAYLOR[a]), \
                  _mm256_mul_pd(_mm256_set1_pd(SEA_EXP_TAYLOR[(a) + 1]), r))
        const __m256d p0 = SEA_PAIR(0), p1 = SEA_PAIR(2), p2 = SEA_PAIR(4), p3 = SEA_PAIR(6);
        const __m256d p4 = SEA_PAIR(8), p5 = SEA_PAIR(10), p6 = SEA_PAIR(12);
#undef SEA_PAIR
        const __m256d q0 = _mm256_add_pd(p0, _mm256_mul_pd(p1, r2));
        const __m256d q1 = _mm256_add_pd(p2, _mm256_mul_pd(p3, r2));
        const __m256d q2 = _mm256_add_pd(p4, _mm256_mul_pd(p5, r2));
        const __m256d s0 = _mm256_add_pd(q0, _mm256_mul_pd(q1, r4));
        const __m256d s1 = _mm256_add_pd(q2, _mm256_mul_pd(p6, r4));
        const __m256d p = _mm256_add_pd(s0, _mm256_mul_pd(s1, r8));
        const __m256i kb = _mm256_castpd_si256(_mm256_add_pd(k, magic));
        const __m256d two_k =
            _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_add_epi64(kb, bias), 52));
        const __m256d ex = _mm256_mul_pd(p, two_k);
        /* g > 0 ? g ex : 0, then wx times it, then clamped at 0 */
        const __m256d v = _mm256_and_pd(_mm256_cmp_pd(g, zero, _CMP_GT_OQ), _mm256_mul_pd(g, ex));
        const __m256d wv = _mm256_mul_pd(_mm256_loadu_pd(wx + i), v);
        _mm256_storeu_pd(w + i, _mm256_and_pd(_mm256_cmp_pd(wv, zero, _CMP_GT_OQ), wv));
    }
}
#endif

/* The sum over the nodes of w_q (1 - rho) from table tb, in four running
 * sums (node q into sum q mod 4) added as (0 + 1) + (2 + 3): the order of
 * flat_sum_avx2's lanes, so both give the same bits.  A node of weight 0
 * adds +0 there and nothing here (its positions may be unset). */
static double flat_sum(const fixed_nodes *nd, const fresnel_table *tb)
{
#ifdef SEA_OPTICS_AVX2
    if (nd->avx2)
        return flat_sum_avx2(tb, nd);
#endif
    double l[4] = { 0.0, 0.0, 0.0, 0.0 };
    for (int q = 0; q < nd->n_q; q++)
        if (nd->w_q[q] > 0.0)
            l[q & 3] += nd->w_q[q] * (1.0 - fresnel_eval(tb, nd->tab_k[q], nd->tab_t[q]));
    return (l[0] + l[1]) + (l[2] + l[3]);
}

static void inner_nodes(const sea_optics *p, const view_frame *f, int n_gh, double gX, double mY,
                        fixed_nodes *nd, int i)
{
    if (n_gh == 0) {
        nd->cos_psi[i] = cos_psi_of(f, gX, f->m_Y);
        return;
    }
    /* cos_psi_of with what does not change along gamma_Y hoisted (the same
     * operations in the same order, so the same bits): a loop of one
     * square root and one division per node, which the compiler vectorises. */
    const double *x = &p->gh_x[SEA_TRI(n_gh - 1)];
    const double num = f->cos_th - gX * f->sin_th, one_gX2 = 1.0 + gX * gX;
    const double s = f->s_Y_given_X;
    double *out = &nd->cos_psi[i * n_gh];
#ifdef SEA_OPTICS_AVX2
    if (nd->avx2) { /* the table positions too, nearly free here */
        row_nodes_avx2(num, one_gX2, mY, s, x, n_gh, out, &nd->tab_k[i * n_gh],
                       &nd->tab_t[i * n_gh]);
        return;
    }
#endif
    for (int j = 0; j < n_gh; j++) {
        const double gY = mY + s * x[j];
        out[j] = num / sqrt(one_gX2 + gY * gY);
    }
}

#ifdef SEA_OPTICS_AVX2
/* inner_nodes of every row (positive w_i or not) in one loop over the
 * nodes, four at a time: node q = i n_gh + j's cos psi and table position,
 * the same operations as row_nodes_avx2 (so the same bits), with each
 * row's terms spread over its nodes first.  Writes up to 3 nodes past the
 * last (the arrays have room). */
__attribute__((target("avx2"))) static void all_nodes_avx2(const sea_optics *p,
                                                           const view_frame *f, double mid,
                                                           double half, const double *x,
                                                           int n_gl, int n_gh, fixed_nodes *nd)
{
    enum { NQ = SEA_EMIS_GL_MAX * SEA_EMIS_GH_MAX + 4 };
    double num[NQ], one[NQ], gy[NQ];
    const double *xj = &p->gh_x[SEA_TRI(n_gh - 1)];
    const double s = f->s_Y_given_X;
    for (int i = 0; i < n_gl; i++) {
        const double t = mid + half * x[i];
        const double gX = f->m_X + f->s_X * t, mY = f->m_Y + f->b_YX * t;
        const double nm = f->cos_th - gX * f->sin_th, on = 1.0 + gX * gX;
        const double wi = nd->w_i[i];
        for (int j = 0; j < n_gh; j++) {
            const int q = i * n_gh + j;
            num[q] = nm;
            one[q] = on;
            gy[q] = mY + s * xj[j];
            nd->w_q[q] = wi * nd->w_j[j]; /* (nodes_fixed's product) */
        }
    }
    const int n = n_gl * n_gh;
    for (int q = n; q < ((n + 3) & ~3); q++)
        num[q] = 0.0, one[q] = 1.0, gy[q] = 0.0;
    const __m256d zero = _mm256_setzero_pd(), vone = _mm256_set1_pd(1.0);
    const __m256d M = _mm256_set1_pd((double)SEA_FRESNEL_INTERVALS);
    const __m128i last = _mm_set1_epi32(SEA_FRESNEL_INTERVALS - 1);
    for (int q = 0; q < n; q += 4) {
        const __m256d gY = _mm256_loadu_pd(gy + q);
        const __m256d c = _mm256_div_pd(
            _mm256_loadu_pd(num + q),
            _mm256_sqrt_pd(_mm256_add_pd(_mm256_loadu_pd(one + q), _mm256_mul_pd(gY, gY))));
        const __m256d u = _mm256_mul_pd(_mm256_min_pd(_mm256_max_pd(c, zero), vone), M);
        const __m128i ki = _mm_min_epi32(_mm256_cvttpd_epi32(u), last);
        _mm256_storeu_pd(nd->cos_psi + q, c);
        _mm256_storeu_pd(nd->tab_t + q, _mm256_sub_pd(u, _mm256_cvtepi32_pd(ki)));
        _mm_storeu_si128((__m128i *)(nd->tab_k + q), ki);
    }
}
#endif

static void table_positions(fixed_nodes *nd);

static void nodes_fixed(const sea_optics *p, const view_frame *f, fixed_rule r, fixed_nodes *nd)
{
    nd->zero = nd->plain = 0;
    nd->n_q = 0;
    nd->avx2 = p->avx2;
    nd->positioned = p->avx2 && r.n_gh > 0;
    nd->n_j = r.n_gh > 0 ? r.n_gh : 1;
    if (r.n_gh > 0)
        memcpy(nd->w_j, &p->gh_w[SEA_TRI(r.n_gh - 1)], (size_t)r.n_gh * sizeof(double));
    else
        nd->w_j[0] = 1.0;
    if (f->delta) {
        nd->zero = f->cos_th - f->m_X * f->sin_th <= 0.0;
        nd->plain = 1;
        nd->n_i = 1;
        nd->w_i[0] = 1.0;
        inner_nodes(p, f, r.n_gh, f->m_X, f->m_Y, nd, 0);
        return;
    }
    double t_lo, t_hi;
    view_window(f, r.t_cut, &t_lo, &t_hi);
    const double half = 0.5 * (t_hi - t_lo), mid = 0.5 * (t_hi + t_lo);
    const double *x = &p->gl_x[SEA_TRI(r.n_gl - 1)], *wx = &p->gl_w[SEA_TRI(r.n_gl - 1)];
    nd->n_i = r.n_gl;
    /* the weights first, then the rows: the rows' square roots and
     * divisions, free of calls, overlap one another */
#ifdef SEA_OPTICS_AVX2
    if (p->avx2) {
        rule_weights_avx2(f, mid, half, x, wx, r.n_gl, nd->w_i);
    } else
#endif
    {
        for (int i = 0; i < r.n_gl; i++) {
            const double t = mid + half * x[i];
            const double w = wx[i] * rule_weight(f, t);
            nd->w_i[i] = w > 0.0 ? w : 0.0;
        }
    }
    if (f->corr)
        sea_shadow_correlated_scale(f->z, mid, half, x, r.n_gl, nd->w_i, p->avx2);
#ifdef SEA_OPTICS_AVX2
    if (p->avx2 && r.n_gh > 0) {
        all_nodes_avx2(p, f, mid, half, x, r.n_gl, r.n_gh, nd);
    } else
#endif
    {
        for (int i = 0; i < r.n_gl; i++) {
            if (nd->w_i[i] > 0.0) {
                const double t = mid + half * x[i];
                inner_nodes(p, f, r.n_gh, f->m_X + f->s_X * t, f->m_Y + f->b_YX * t, nd, i);
            }
        }
    }
    table_positions(nd); /* (the AVX2 loop found them already) */
    if (r.n_gh > 0) {
        /* the nodes' weights for the table sums (w_i >= 0: clamped, or
         * scaled by the correlated function), zeros to a multiple of 4 */
        const int n = r.n_gl * r.n_gh;
        if (!nd->positioned) /* (all_nodes_avx2 wrote them) */
            for (int i = 0; i < r.n_gl; i++) {
                double *wq = &nd->w_q[i * r.n_gh];
                const double wi = nd->w_i[i];
                for (int j = 0; j < r.n_gh; j++)
                    wq[j] = wi * nd->w_j[j];
            }
        nd->n_q = (n + 3) & ~3;
        for (int q = n; q < nd->n_q; q++) {
            nd->w_q[q] = 0.0;
            nd->tab_k[q] = 0;
            nd->tab_t[q] = 0.0;
        }
    }
}

/* 1 - rho averaged over the nodes: the inner sums weighted by w_i over the
 * sum of w_i; with every facet turned away (the limit of a sliver at
 * grazing) 0; in the delta case (s_X = 0) the inner sum alone. */
static double emissivity_of_nodes(const fixed_nodes *nd, const emis_ctx *ec)
{
    /* A facet without slope spread (delta) has a handful of nodes: the
     * formula itself, so a mirror facet's emissivity stays 1 - rho(psi_m)
     * to round-off. */
    const emis_ctx exact = { ec->N, NULL }, *e = nd->plain ? &exact : ec;
    if (nd->zero)
        return 0.0;
    double num = 0.0, den = 0.0;
    if (!nd->plain && nd->n_j > 1 && e->table != NULL) {
        /* the table at the positions found once for every index, over
         * every node at once */
        for (int i = 0; i < nd->n_i; i++)
            if (nd->w_i[i] > 0.0)
                den += nd->w_i[i];
        return den > 0.0 ? flat_sum(nd, e->table) / den : 0.0;
    }
    for (int i = 0; i < nd->n_i; i++) {
        const double w = nd->w_i[i];
        if (!nd->plain && w <= 0.0)
            continue;
        const double *c = &nd->cos_psi[i * nd->n_j];
        double acc;
        if (nd->n_j == 1 && nd->w_j[0] == 1.0) {
            acc = one_minus_rho(e, c[0]);
        } else {
            acc = 0.0;
            for (int j = 0; j < nd->n_j; j++)
                acc += nd->w_j[j] * one_minus_rho(e, c[j]);
        }
        if (nd->plain)
            return acc;
        num += w * acc;
        den += w;
    }
    return den > 0.0 ? num / den : 0.0;
}

/* emissivity_of_nodes for four indices with tables at once, each summed in
 * the same order (the same values): four independent chains of additions
 * instead of one, for a band's samples.  Needs the table positions and
 * the general case (not zero, not plain, several inner nodes). */
static void emissivity_of_nodes4(const fixed_nodes *nd, const fresnel_table *const tb[4],
                                 double out[4])
{
    double den = 0.0, a[4];
    for (int i = 0; i < nd->n_i; i++)
        if (nd->w_i[i] > 0.0)
            den += nd->w_i[i];
#ifdef SEA_OPTICS_AVX2
    if (nd->avx2) {
        flat_sum4_avx2(tb, nd, a);
    } else
#endif
    {
        for (int m = 0; m < 4; m++)
            a[m] = flat_sum(nd, tb[m]);
    }
    for (int m = 0; m < 4; m++)
        out[m] = den > 0.0 ? a[m] / den : 0.0;
}

/* The table positions of the nodes emissivity_of_nodes reads through a
 * table (positive w_i, an inner rule of several nodes). */
static void table_positions(fixed_nodes *nd)
{
    if (nd->zero || nd->plain || nd->n_j == 1 || nd->positioned)
        return;
    for (int i = 0; i < nd->n_i; i++) {
        if (!(nd->w_i[i] > 0.0))
            continue;
        const int o = i * nd->n_j;
        for (int j = 0; j < nd->n_j; j++)
            nd->tab_t[o + j] = fresnel_pos(nd->cos_psi[o + j], &nd->tab_k[o + j]);
    }
}

/* emissivity_of_nodes of n indices, four with tables at once where the
 * nodes allow (emissivity_of_nodes4: the same values). */
static void emissivity_of_nodes_n(const fixed_nodes *nd, const emis_ctx *ec, size_t n,
                                  double *out)
{
    const int general = !nd->zero && !nd->plain && nd->n_j > 1;
    for (size_t i = 0; i < n;) {
        const fresnel_table *tb[4] = { ec[i].table };
        size_t g = 1;
        while (general && ec[i].table != NULL && g < 4 && i + g < n &&
               (tb[g] = ec[i + g].table) != NULL)
            g++;
        if (g < 2) {
            out[i] = emissivity_of_nodes(nd, &ec[i]);
            i++;
            continue;
        }
        for (size_t m = g; m < 4; m++)
            tb[m] = tb[g - 1];
        double o4[4];
        emissivity_of_nodes4(nd, tb, o4);
        for (size_t m = 0; m < g; m++)
            out[i + m] = o4[m];
        i += g;
    }
}

/* The fixed rule of a call: the given orders, Eq 12's 64 nodes (fast), or
 * the default's orders from the view frame (auto, and full where a fixed
 * rule is needed). */
/* ------------------------------------------------------ spectral basis */

/* The second hits' emissivity sums the n Fresnel tables of a block of
 * spectral samples over the same nodes, n table lookups a node.  A band's
 * tables are nearly linearly dependent (water over 3-5 um: singular values
 * 1, 3.4e-2, 1.9e-3, 5.5e-5, 1.6e-5, 5.1e-7, 3.1e-8, 2.2e-10 of the
 * first), so the singular value decomposition of the matrix of their
 * cubics' coefficients gives functions B_r = sum_k A_kr rho_k (the
 * singular value times the left singular vector) and weights A_kr (the
 * right singular vectors, from the n x n triangle of the matrix's QR
 * factorisation: a third of the instructions of decomposing the 8192 x n
 * matrix itself, and no left vector formed); each B_r is put on the basis's
 * coarser intervals (the cubic through its values at
 * 0, 1/3, 2/3 and 1 of each), and the rank is the smallest whose sum_r
 * A_kr B_r is within SEA_BASIS_TOL of every table at 4 points of each of
 * the table's intervals (the reflectance is smooth in cos psi: an index
 * near 1, whose reflectance jumps at grazing, has no table).  The sums
 * then take one lookup of the basis a node instead of n of the tables:
 *     sum_q w_q (1 - rho_k) = W - sum_r A_kr sum_q w_q B_r,
 * W = sum_q w_q, unclamped (the tables clamp rho to [0, 1]). */
static double basis_cubic(const double *c, int lanes, int r, int q, double t)
{
    const double *a = &c[(size_t)q * 4 * (size_t)lanes + (size_t)r];
    return a[0] + t * (a[(size_t)lanes] + t * (a[2 * (size_t)lanes] + t * a[3 * (size_t)lanes]));
}

/* Where the basis is read for cos psi c. */
static inline double basis_pos(double c, int *q)
{
    return interval_pos(c, SEA_BASIS_INTERVALS, q);
}

/* Whether a basis of rank r halves the lookups of n indices: a node reads
 * lanes / 4 vectors (lanes: r rounded up to a multiple of 4) instead of
 * n / 4 tables. */
static int basis_halves(int r, size_t n)
{
    return 2 * ((r + 3) & ~3) <= (int)n;
}

static spectral_basis *basis_build(const emis_ctx *ec, size_t n)
{
    enum { M = SEA_FRESNEL_INTERVALS, C = 4 * SEA_FRESNEL_INTERVALS, MB = SEA_BASIS_INTERVALS };
    enum { RATIO = 1 << SEA_BASIS_SHIFT };
    const int max_rank = (int)n < SEA_BASIS_RANK_MAX ? (int)n : SEA_BASIS_RANK_MAX;
    const int max_lanes = (max_rank + 3) & ~3;
    spectral_basis *b = calloc(1, sizeof *b);
    /* where not even rank 1 would halve the lookups (fewer than 8
     * indices), no basis and no decomposition to make */
    if (!basis_halves(1, n)) {
        if (b != NULL) {
            b->n = n;
            for (size_t k = 0; k < n; k++)
                b->N[k] = ec[k].N;
        }
        return b;
    }
    gsl_matrix *X = gsl_matrix_alloc(C, n);
    gsl_matrix *T = gsl_matrix_calloc(n, n), *V = gsl_matrix_alloc(n, n);
    gsl_vector *S = gsl_vector_alloc(n), *tau = gsl_vector_alloc(n);
    double *c = calloc((size_t)MB * 4 * (size_t)max_lanes, sizeof *c);
    int ok = b != NULL && X != NULL && T != NULL && V != NULL && S != NULL && tau != NULL &&
             c != NULL;
    if (ok) {
        b->n = n;
        for (size_t k = 0; k < n; k++) {
            b->N[k] = ec[k].N;
            for (int q = 0; q < M; q++)
                for (int i = 0; i < 4; i++)
                    gsl_matrix_set(X, 4 * (size_t)q + (size_t)i, k, ec[k].table->a[q][i]);
        }
        /* X = Q T: T has X's right singular vectors and singular values
         * (an n x n decomposition instead of C x n) */
        ok = gsl_linalg_QR_decomp(X, tau) == GSL_SUCCESS;
        for (size_t i = 0; ok && i < n; i++)
            for (size_t j = i; j < n; j++)
                gsl_matrix_set(T, i, j, gsl_matrix_get(X, i, j));
        ok = ok && gsl_linalg_SV_decomp_jacobi(T, V, S) == GSL_SUCCESS;
        /* largest first (the rank's terms are the leading ones) */
        for (size_t i = 0; ok && i + 1 < n; i++)
            ok = gsl_vector_get(S, i) >= gsl_vector_get(S, i + 1);
    }
    for (int r = 0; ok && r < max_rank; r++) {
        /* B_r = sum_k V_kr rho_k (sigma_r times the left singular vector)
         * on the coarse intervals: the cubic through its values at t = 0,
         * 1/3, 2/3, 1 of each */
        for (int Q = 0; Q < MB; Q++) {
            double y[4];
            for (int m = 0; m < 4; m++) {
                const double u = (Q + m / 3.0) * RATIO;
                const int q = u >= M ? M - 1 : (int)u;
                const double t = u - q;
                double v = 0.0;
                for (size_t k = 0; k < n; k++)
                    v += gsl_matrix_get(V, k, (size_t)r) * cubic_at(ec[k].table, q, t);
                y[m] = v;
            }
            double *a = &c[(size_t)Q * 4 * (size_t)max_lanes + (size_t)r];
            a[0] = y[0];
            a[(size_t)max_lanes] = 0.5 * (-11.0 * y[0] + 18.0 * y[1] - 9.0 * y[2] + 2.0 * y[3]);
            a[2 * (size_t)max_lanes] = 4.5 * (2.0 * y[0] - 5.0 * y[1] + 4.0 * y[2] - y[3]);
            a[3 * (size_t)max_lanes] = 4.5 * (-y[0] + 3.0 * y[1] - 3.0 * y[2] + y[3]);
        }
        for (size_t k = 0; k < n; k++)
            b->A[r][k] = gsl_matrix_get(V, k, (size_t)r);
    }
    /* the smallest rank within the tolerance, at 4 points of every table
     * interval: each point's residual after the first R terms, one term
     * more a rank (subtracted in the order of r, as a sum from scratch) */
    int rank = 0;
    double err = 0.0;
    double *res = ok ? malloc(n * (size_t)M * 4 * sizeof *res) : NULL;
    if (res != NULL)
        for (size_t k = 0; k < n; k++)
            for (int q = 0; q < M; q++)
                for (int m = 0; m < 4; m++)
                    res[(k * M + (size_t)q) * 4 + (size_t)m] = cubic_at(ec[k].table, q, 0.25 * m);
    for (int R = 1; res != NULL && R <= max_rank && rank == 0; R++) {
        double worst = 0.0;
        for (size_t k = 0; k < n; k++)
            for (int q = 0; q < M; q++)
                for (int m = 0; m < 4; m++) {
                    const double t = 0.25 * m, u = (q + t) / RATIO;
                    const int Q = (int)u < MB ? (int)u : MB - 1;
                    double *v = &res[(k * M + (size_t)q) * 4 + (size_t)m];
                    *v -= b->A[R - 1][k] * basis_cubic(c, max_lanes, R - 1, Q, u - Q);
                    worst = sea_fmax(worst, fabs(*v));
                }
        if (worst <= SEA_BASIS_TOL)
            rank = R, err = worst;
    }
    free(res);
    if (!basis_halves(rank, n))
        rank = 0;
    if (b != NULL && ok && rank > 0) {
        /* the blocks at the rank's own width */
        b->rank = rank;
        b->lanes = (rank + 3) & ~3;
        b->err = err;
        b->c = malloc((size_t)MB * 4 * (size_t)b->lanes * sizeof *b->c);
        if (b->c == NULL)
            b->rank = 0;
        else
            for (size_t e = 0; e < (size_t)MB * 4; e++)
                for (int r = 0; r < b->lanes; r++)
                    b->c[e * (size_t)b->lanes + (size_t)r] =
                        r < rank ? c[e * (size_t)max_lanes + (size_t)r] : 0.0;
    }
    gsl_matrix_free(X);
    gsl_matrix_free(T);
    gsl_matrix_free(V);
    gsl_vector_free(S);
    gsl_vector_free(tau);
    free(c);
    return b;
}

/* The first nb bases': the one of the block ec[0..n), or NULL. */
static const spectral_basis *find_basis(const sea_optics *p, const emis_ctx *ec, size_t n,
                                        size_t nb)
{
    for (size_t i = 0; i < nb; i++) {
        const spectral_basis *b = p->basis[i];
        size_t k = 0;
        while (b->n == n && k < n && b->N[k] == ec[k].N)
            k++;
        if (k == n)
            return b;
    }
    return NULL;
}

/* The basis of the block ec[0..n) (every index tabulated), built on first
 * use under the tables' lock; NULL when there is none to use. */
static const spectral_basis *spectral_basis_of(const sea_optics *pc, const emis_ctx *ec, size_t n)
{
    sea_optics *p = (sea_optics *)pc;
    if (!p->use_basis || n < 1 || n > SEA_EMIS_BLOCK)
        return NULL;
    for (size_t k = 0; k < n; k++)
        if (ec[k].table == NULL)
            return NULL;
    size_t nb = atomic_load_explicit(&p->n_basis, memory_order_acquire);
    const spectral_basis *found = find_basis(p, ec, n, nb);
    if (found == NULL) {
        pthread_mutex_lock(&p->fresnel_lock);
        nb = atomic_load_explicit(&p->n_basis, memory_order_relaxed);
        found = find_basis(p, ec, n, nb);
        if (found == NULL && nb < SEA_BASIS_CACHE) {
            spectral_basis *b = basis_build(ec, n);
            if (b != NULL) { /* out of memory: no basis */
                p->basis[nb] = b;
                atomic_store_explicit(&p->n_basis, nb + 1, memory_order_release);
                found = b;
            }
        }
        pthread_mutex_unlock(&p->fresnel_lock);
    }
    return found != NULL && found->rank > 0 ? found : NULL;
}

int sea_optics_spectral_rank(const sea_optics *p, const double complex *N, size_t n, double *err)
{
    emis_ctx ec[SEA_EMIS_BLOCK];
    size_t slot = 0;
    if (n > SEA_EMIS_BLOCK)
        return 0;
    for (size_t k = 0; k < n; k++)
        ec[k] = (emis_ctx){ N[k], fresnel_of(p, N[k], &slot) };
    const spectral_basis *b = spectral_basis_of(p, ec, n);
    if (err != NULL)
        *err = b != NULL ? b->err : NAN;
    return b != NULL ? b->rank : 0;
}


#ifdef SEA_OPTICS_AVX2
/* basis_sums with four B_r a vector: one node's interval block is lanes / 4
 * vectors of each coefficient. */
__attribute__((target("avx2"))) static double basis_sums_avx2(const fixed_nodes *nd,
                                                              const spectral_basis *b, double *G)
{
    const size_t L = (size_t)b->lanes;
    const __m256d zero = _mm256_setzero_pd();
    __m256d acc[SEA_BASIS_RANK_MAX / 4] = { zero, zero };
    double W = 0.0;
    for (int q = 0; q < nd->n_q; q++) {
        const double w = nd->w_q[q];
        if (!(w > 0.0))
            continue;
        W += w;
        int Q;
        const __m256d tt = _mm256_set1_pd(basis_pos(nd->cos_psi[q], &Q));
        const __m256d ww = _mm256_set1_pd(w);
        const double *a = &b->c[(size_t)Q * 4 * L];
        for (size_t v = 0; v < L; v += 4) {
            __m256d y = _mm256_loadu_pd(a + 3 * L + v);
            y = _mm256_add_pd(_mm256_loadu_pd(a + 2 * L + v), _mm256_mul_pd(tt, y));
            y = _mm256_add_pd(_mm256_loadu_pd(a + L + v), _mm256_mul_pd(tt, y));
            y = _mm256_add_pd(_mm256_loadu_pd(a + v), _mm256_mul_pd(tt, y));
            acc[v / 4] = _mm256_add_pd(acc[v / 4], _mm256_mul_pd(ww, y));
        }
    }
    for (size_t v = 0; v < L; v += 4)
        _mm256_storeu_pd(G + v, acc[v / 4]);
    return W;
}
#endif

/* G_r = sum_q w_q B_r(cos psi_q) over the nodes of positive weight, r <
 * lanes (the general nodes: not zero, not plain, n_j > 1); returns W =
 * sum_q w_q over them. */
static double basis_sums(const fixed_nodes *nd, const spectral_basis *b, double *G)
{
#ifdef SEA_OPTICS_AVX2
    if (nd->avx2)
        return basis_sums_avx2(nd, b, G);
#endif
    double W = 0.0;
    for (int r = 0; r < b->lanes; r++)
        G[r] = 0.0;
    for (int q = 0; q < nd->n_q; q++) {
        const double w = nd->w_q[q];
        if (!(w > 0.0))
            continue;
        W += w;
        int Q;
        const double t = basis_pos(nd->cos_psi[q], &Q);
        for (int r = 0; r < b->rank; r++)
            G[r] += w * basis_cubic(b->c, b->lanes, r, Q, t);
    }
    return W;
}

/* emissivity_of_nodes_n through the basis b of the block (the general
 * nodes: not zero, not plain, n_j > 1). */
/* The emissivity of every index of the block over the general nodes nd,
 * through the basis b, as e0 - sum_r A_rk g_r: e0 = W / den and g_r =
 * G_r / den (0 where den is not positive), W the sum of the nodes' weights,
 * G_r basis_sums', den the sum of the outer weights. */
static void basis_emissivity(const fixed_nodes *nd, const spectral_basis *b, double *e0,
                             double *g)
{
    double den = 0.0;
    for (int i = 0; i < nd->n_i; i++)
        if (nd->w_i[i] > 0.0)
            den += nd->w_i[i];
    const double W = basis_sums(nd, b, g);
    const double inv = den > 0.0 ? 1.0 / den : 0.0;
    *e0 = W * inv;
    for (int r = 0; r < b->rank; r++)
        g[r] *= inv;
}

static void emissivity_of_nodes_basis(const fixed_nodes *nd, const spectral_basis *b,
                                      double *out)
{
    double e0, g[SEA_BASIS_RANK_MAX];
    basis_emissivity(nd, b, &e0, g);
    const size_t n = b->n;
    for (size_t k = 0; k < n; k++)
        out[k] = e0;
    for (int r = 0; r < b->rank; r++)
        for (size_t k = 0; k < n; k++)
            out[k] -= b->A[r][k] * g[r];
}

/* The basis functions at cos psi c, B[0..rank). */
static void basis_at(const spectral_basis *b, double c, double *B)
{
    int Q;
    const double t = basis_pos(c, &Q);
    for (int r = 0; r < b->rank; r++)
        B[r] = basis_cubic(b->c, b->lanes, r, Q, t);
}

/* The reflectance of every index of the block at cos psi c through its
 * basis (unclamped). */
static void basis_rho(const spectral_basis *b, double c, double *rho)
{
    double B[SEA_BASIS_RANK_MAX];
    basis_at(b, c, B);
    const size_t n = b->n;
    for (size_t k = 0; k < n; k++)
        rho[k] = 0.0;
    for (int r = 0; r < b->rank; r++)
        for (size_t k = 0; k < n; k++)
            rho[k] += b->A[r][k] * B[r];
}

static fixed_rule fixed_rule_of(const view_frame *f, sea_emis_method method,
                                const sea_emis_rule *rule)
{
    if (rule != NULL)
        return (fixed_rule){ rule->n_gl, rule->n_gh, SEA_RULE_T_CUT };
    if (method == SEA_EMIS_FAST)
        return (fixed_rule){ 64, 0, SEA_T_CUT };
    const sea_emis_rule a = auto_rule(f);
    return (fixed_rule){ a.n_gl, a.n_gh, SEA_RULE_T_CUT };
}

/* A fixed product rule's orders within their tables (NULL: none given). */
static sea_status check_rule(const sea_emis_rule *rule, sea_error *err)
{
    if (rule != NULL && (rule->n_gl < 1 || rule->n_gl > SEA_EMIS_GL_MAX || rule->n_gh < 0 ||
                         rule->n_gh > SEA_EMIS_GH_MAX))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "product rule %d x %d is outside 1..%d Gauss-Legendre x 0..%d "
                        "Gauss-Hermite nodes",
                        rule->n_gl, rule->n_gh, SEA_EMIS_GL_MAX, SEA_EMIS_GH_MAX);
    return SEA_OK;
}

sea_status sea_emissivity_n(const sea_optics *p, sea_emis_method method,
                            const sea_emis_rule *rule, const double complex *N, size_t n,
                            const sea_slope_stats *st, sea_dir v, double *out, sea_error *err)
{
    sea_status s;
    if (rule == NULL && method == SEA_EMIS_FULL) {
        for (size_t i = 0; i < n; i++)
            if ((s = sea_emissivity(p, method, N[i], st, v, &out[i], err)) != SEA_OK)
                return s;
        return SEA_OK;
    }
    if ((s = check_rule(rule, err)) != SEA_OK)
        return s;
    if (rule == NULL && method != SEA_EMIS_AUTO && method != SEA_EMIS_FAST)
        return sea_fail(err, SEA_ERR_DOMAIN, "unknown emissivity method %d", (int)method);
    if ((s = check_dir(v, "view", err)) != SEA_OK || (s = sea_slope_stats_check(st, err)) != SEA_OK)
        return s;
    view_frame f;
    view_frame_init(p, st, v, &f);
    const fixed_rule r = fixed_rule_of(&f, method, rule);
    fixed_nodes nd;
    nodes_fixed(p, &f, r, &nd);
    size_t slot = 0; /* where the next index's table is looked for first */
    for (size_t i0 = 0; i0 < n; i0 += SEA_EMIS_BLOCK) {
        const size_t m = n - i0 < SEA_EMIS_BLOCK ? n - i0 : SEA_EMIS_BLOCK;
        emis_ctx ec[SEA_EMIS_BLOCK];
        for (size_t k = 0; k < m; k++)
            ec[k] = (emis_ctx){ N[i0 + k], fresnel_of(p, N[i0 + k], &slot) };
        emissivity_of_nodes_n(&nd, ec, m, &out[i0]);
    }
    return SEA_OK;
}

sea_emis_rule sea_emissivity_auto_rule(const sea_slope_stats *st, sea_dir v)
{
    view_frame f;
    view_frame_init(NULL, st, v, &f); /* (the orders do not depend on the shadowing) */
    return auto_rule(&f);
}

sea_status sea_emissivity_rule(const sea_optics *p, sea_emis_rule rule, double complex N,
                               const sea_slope_stats *st, sea_dir v, double *out, sea_error *err)
{
    return sea_emissivity_n(p, SEA_EMIS_AUTO, &rule, &N, 1, st, v, out, err);
}

/* ---------------------------------------------------------- reflectivity */

static void dir_vec(sea_dir d, double u[3])
{
    u[0] = sin(d.theta) * cos(d.phi);
    u[1] = sin(d.theta) * sin(d.phi);
    u[2] = cos(d.theta);
}

/* Bivariate normal density, covariance regularised by SEA_COV_REG: its
 * logarithm, and itself. */
static double slope_log_pdf(const sea_slope_stats *st, double gx, double gy)
{
    const double xx = st->cov.xx + SEA_COV_REG, yy = st->cov.yy + SEA_COV_REG;
    const double xy = st->cov.xy;
    const double det = sea_fmax(xx * yy - xy * xy, SEA_COV_REG * SEA_COV_REG);
    const double dx = gx - st->mean.x, dy = gy - st->mean.y;
    const double q = (yy * dx * dx - 2.0 * xy * dx * dy + xx * dy * dy) / det;
    return -0.5 * q - log(2.0 * M_PI * sqrt(det));
}

static double slope_pdf(const sea_slope_stats *st, double gx, double gy)
{
    const double xx = st->cov.xx + SEA_COV_REG, yy = st->cov.yy + SEA_COV_REG;
    const double xy = st->cov.xy;
    const double det = sea_fmax(xx * yy - xy * xy, SEA_COV_REG * SEA_COV_REG);
    const double dx = gx - st->mean.x, dy = gy - st->mean.y;
    const double q = (yy * dx * dx - 2.0 * xy * dx * dy + xx * dy * dy) / det;
    return exp(-0.5 * q) / (2.0 * M_PI * sqrt(det));
}

/* Below this D's numerator E[(cot - gamma_X)+] (a far tail of the slopes),
 * g/D (its reciprocal) and the density of the mirror facet are formed in
 * logs: directly, 1/D overflows while the density underflows, and their
 * product, a density of the visible facets and so of moderate size, came
 * out NaN (a mean slope of (-5, 5) seen 60 deg off at azimuth 119 deg).
 * Above it the product stays below 1e218 (the density is at most
 * 1 / (2 pi SEA_COV_REG)). */
static const double SEA_VISIBLE_DIRECT_MIN = 1e-200;

/* Shadowing terms along one direction: Lambda, and the ratio g/D of Eq 13
 * for a facet of slope gX along that azimuth (0 if the facet is hidden). */
static double lambda_along(const sea_slope_stats *st, sea_dir d)
{
    double m, s;
    sea_slope_project(st, d.phi, &m, &s);
    return sea_shadow_lambda(d.theta, m, s);
}

/* Everything of Eq 13-14 but the Fresnel factor: the mirror facet's cos psi0,
 * its slope density, g/D, the bistatic shadowing S and the Jacobian J (kept
 * apart, so that rho(psi0) pdf g/D S J is multiplied in one order whatever
 * the index); zero when there is no mirror facet seen from obs. */
typedef struct {
    int zero;
    int tail; /* pdf holds pdf g/D, formed in logs, and g_over_D is 1 */
    double cos_psi0, pdf, g_over_D, S, J;
    double ui[3], uo[3]; /* inc and obs as unit vectors (dir_vec's values) */
    double ci, si, cpi, spi; /* cos and sin of inc's zenith and azimuth */
} mirror_geom;

static void mirror_geom_of(const sea_slope_stats *st, sea_dir inc, sea_dir obs, mirror_geom *m)
{
    double *ui = m->ui, *uo = m->uo;
    m->zero = 1;
    m->tail = 0;
    m->ci = cos(inc.theta), m->si = sin(inc.theta), m->cpi = cos(inc.phi), m->spi = sin(inc.phi);
    ui[0] = m->si * m->cpi;
    ui[1] = m->si * m->spi;
    ui[2] = m->ci;
    dir_vec(obs, uo);
    /* Half vector h = ui + uo: 1 + cos(ui, uo) = |h|^2 / 2.  Written as a
     * sum of squares it keeps its relative accuracy where 1 + ui.uo
     * cancels, sun and view both grazing on opposite sides (|h|^2 =
     * 4 cos^2 theta, 1e-17 at theta = 90 - 1e-7 deg, while 1 + ui.uo is
     * then round-off). */
    const double h[3] = { ui[0] + uo[0], ui[1] + uo[1], ui[2] + uo[2] };
    const double cos_sum = h[2];
    const double h2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    if (!(cos_sum > 0.0) || !(h2 > 0.0))
        return; /* both on the horizon, or opposite: no mirror facet */
    /* Eq 14a-b: slope of the facet whose normal bisects inc and obs. */
    const double gx0 = -h[0] / cos_sum;
    const double gy0 = -h[1] / cos_sum;
    m->J = 0.5 * h2 / (cos_sum * cos_sum * cos_sum); /* Eq 14d */
    m->cos_psi0 = 0.5 * sqrt(h2);
    /* g/D toward obs (Eq 9b, 10), written without tan theta_o:
     * g/D = (cot - gX)(1 + L_o) / E[(cot - gamma_X)+].  The mirror facet
     * always faces obs: cot th_o - gX = |h|^2 / (2 sin th_o cos_sum) > 0,
     * used in this form because cot - gX, a difference of two terms, is
     * round-off (and may come out negative) when both directions graze. */
    double m_o, s_o, L_o = 0.0, log_g_over_D = 0.0;
    m->g_over_D = 1.0;
    sea_slope_project(st, obs.phi, &m_o, &s_o);
    if (obs.theta >= SEA_NADIR_THETA) {
        const double tn = tan(obs.theta), mu = 1.0 / tn;
        const double mu_minus_gX = 0.5 * h2 / (sin(obs.theta) * cos_sum);
        double vis, hid;
        sea_shadow_split(mu, m_o, s_o, &vis, &hid);
        if (vis >= SEA_VISIBLE_DIRECT_MIN) {
            L_o = tn * hid; /* sea_shadow_lambda(obs.theta, m_o, s_o) */
            m->g_over_D = mu_minus_gX * (1.0 + L_o) / vis;
        } else {
            const double log_vis = sea_shadow_log_visible(mu, m_o, s_o);
            if (!(log_vis > -INFINITY))
                return; /* no facet seen from obs */
            L_o = tn * hid;
            log_g_over_D = log(mu_minus_gX * (1.0 + L_o)) - log_vis;
            m->tail = 1;
        }
    }
    const double L_i = lambda_along(st, inc);
    m->S = 1.0 / (1.0 + L_o + L_i); /* Eq 14c */
    m->pdf = m->tail ? exp(slope_log_pdf(st, gx0, gy0) + log_g_over_D)
                     : slope_pdf(st, gx0, gy0);
    m->zero = 0;
}

static double mirror_reflectivity(const mirror_geom *m, double complex N)
{
    if (m->zero)
        return 0.0;
    return sea_fresnel_unpolarized(m->cos_psi0, N) * m->pdf * m->g_over_D * m->S * m->J;
}

double sea_reflectivity(double complex N, const sea_slope_stats *st, sea_dir inc, sea_dir obs)
{
    mirror_geom m;
    mirror_geom_of(st, inc, obs, &m);
    return mirror_reflectivity(&m, N);
}

void sea_reflectivity_n(const double complex *N, size_t n, const sea_slope_stats *st,
                        sea_dir inc, sea_dir obs, double *out)
{
    mirror_geom m;
    mirror_geom_of(st, inc, obs, &m);
    for (size_t i = 0; i < n; i++)
        out[i] = mirror_reflectivity(&m, N[i]);
}

double sea_brdf(double complex N, const sea_slope_stats *st, sea_dir inc, sea_dir obs)
{
    return sea_reflectivity(N, st, inc, obs) / cos(inc.theta);
}

/* ------------------------------------------------------------ energy */

typedef struct {
    double complex N;
    const sea_slope_stats *st;
    double L_o;
} reflectance_ctx;

/* rho(psi) (1 + L_o)/(1 + L_o + L_i) for the facet (gX, gY) in the view
 * frame, 0 when the mirror ray goes below the horizon. */
static double reflectance_fn(const view_frame *f, double gX, double gY, double cos_psi,
                             void *vctx)
{
    const reflectance_ctx *c = vctx;
    const double inv_norm = 1.0 / sqrt(1.0 + gX * gX + gY * gY);
    /* u_i = 2 (n . u_o) n - u_o with u_o = (sin th, 0, cos th) in the view
     * frame and n = (-gX, -gY, 1)/|.|. */
    const double two_c = 2.0 * cos_psi * inv_norm;
    const double ix = -two_c * gX - f->sin_th;
    const double iy = -two_c * gY;
    const double iz = two_c - f->cos_th;
    if (!(iz > 0.0))
        return 0.0;
    const double theta_i = atan2(hypot(ix, iy), iz);
    const sea_dir inc = { theta_i, f->phi + atan2(iy, ix) };
    const double L_i = lambda_along(c->st, inc);
    return sea_fresnel_unpolarized(cos_psi, c->N) * (1.0 + c->L_o) / (1.0 + c->L_o + L_i);
}

sea_status sea_energy_balance(const sea_optics *p, sea_emis_method method, double complex N,
                              const sea_slope_stats *st, sea_dir v, sea_energy *out,
                              sea_error *err)
{
    sea_status s;
    if ((s = sea_emissivity(p, method, N, st, v, &out->emissivity, err)) != SEA_OK)
        return s;
    view_frame f;
    view_frame_init(p, st, v, &f);
    reflectance_ctx c = { N, st, lambda_along(st, v) };
    /* The reflectance is integrated by the adaptive rule over the exact region
     * where the mirror ray leaves upwards, whatever the emissivity method:
     * an energy check needs that accuracy, and it is not a hot path. */
    if ((s = expect_reference(p, &f, reflectance_fn, &c, 1, &out->reflectance, err)) != SEA_OK)
        return s;
    out->total = out->emissivity + out->reflectance;
    return SEA_OK;
}

/* ------------------------------------------------- multiple reflections */

/* The emissivity with up to R surface hits (R >= 2).  Seen from v, a facet
 * A of the sub-facet distribution emits 1 - rho(psi_A); the rest of what the
 * sensor receives from A comes along the mirror ray r = 2 (n.v) n - v.  In
 * the paper (R = 1) r always brings the sky.  Here r meets the surface again
 * with the probability
 *     P = Lambda(r) / (1 + Lambda(v) + Lambda(r))    (r up; 1 when r points down),
 * the complement of the bistatic Smith factor (1 + L_v)/(1 + L_v + L_r) that
 * Eq 14c and the energy balance give the escaping ray, so that emission and
 * escaping reflection add to exactly 1 when nothing is absorbed twice.
 * What r meets is again the slope distribution, weighted by the projected
 * area seen along r: the facet B is seen from o = -r, which lies below the
 * horizon when r rises.  The weight (cos th_o - gamma_X sin th_o)+ p(gamma)
 * of the emissivity holds for such o as well (it is the rate at which a
 * ray of that direction meets facets of slope gamma, as for a ray from the
 * sensor), so B emits E_{R-1}(o): the same average, one hit fewer, toward a
 * zenith angle in (90, 180) deg for a rising ray.  After B the mirror ray
 * leaves again with P = L_r'/(1 + L_r') (B was met from below: no
 * visibility condition from above), and so on:
 *     E_R(v) = E_w[(1 - rho_A) + rho_A P_A E_{R-1}(-r_A)],  E_1 = Eq 7.
 * The sky then sees 1 - E_R, which is what an isotropic sky's reflection
 * is (Eq 23), so Kirchhoff's closure holds at every R. */

/* Indices handled at once by one recursion (stack arrays). */
enum { SEA_MULTI_BLOCK = SEA_EMIS_BLOCK };
/* The emissivity of a facet met again multiplies rho P <= 0.4, so it takes
 * 0.35 of the default orders (at least 4 x 2 nodes): over 16 samples at
 * 3-5 um, 3-15 m/s, 60-88 deg, three azimuths, mean slopes 0 and (0.1,
 * -0.05), half and all of the low-resolution slope variance, E_2 is within
 * 1.5e-5 of its value at twice the orders (half the orders: 4.6e-6; a
 * quarter: 7.4e-4), and midwave.ini at R = 2 takes 13 % less CPU than at
 * half. */
static const double SEA_MULTI_INNER_SCALE = 0.35;
enum { SEA_MULTI_INNER_GL_MIN = 4, SEA_MULTI_INNER_GH_MIN = 2 };
/* A mirror ray that meets the surface again with a probability below this
 * escapes: what it would bring, at most P times one, is dropped from E_R,
 * and from K_R alike (the closure holds), and the facets it would meet are
 * not computed. */
static const double SEA_MULTI_P_NEGLIGIBLE = 1e-9;
/* So is one whose node's share of the average times P is below this (the
 * far nodes of a rule, a steep facet whose mirror ray falls): at most 1e-11
 * each, 1e-8 over the largest rule. */
static const double SEA_MULTI_SHARE_NEGLIGIBLE = 1e-11;
/* The second hits' split rule (second_hit): a piece of the window takes
 * SPLIT_SCALE times n_gl nodes times its share of the window, at least
 * SPLIT_MIN, and across the slope (Gauss-Hermite in gamma_Y given gamma_X)
 * CROSS_SCALE times n_gh nodes, at least CROSS_MIN.  Against the same rule
 * at orders 128 x 16 (itself within 8.3e-6 of 64 x 12), 16 samples over
 * 3-5 um, 3-15 m/s, 60-88 deg, three azimuths, half the Cox-Munk slope
 * variances (a 1 m facet's sub-facets) and all of them (low resolution):
 * within 7.3e-5 without a mean slope and 1.31e-4 with (0.1, -0.05).
 * All n_gh across: 3.3e-5 and 1.28e-4, at twice the cost (an emissivity
 * at 80 deg, 10 m/s: 13 us instead of 7).  0.75 n_gl along: 1.4e-5 with
 * the mean slope, at 1.3 times the cost of mast.ini at R = 2.  Without the
 * nodes crowded toward the root on a rising piece (second_hit) the mean
 * slope left E_2 1.3e-3 off; the unsplit rule was 1.7e-3 off without a
 * mean slope. */
static const double SEA_MULTI_SPLIT_SCALE = 0.5, SEA_MULTI_SPLIT_MIN = 3.0;
static const double SEA_MULTI_CROSS_SCALE = 0.5, SEA_MULTI_CROSS_MIN = 2.0;

/* The frame's direction (x, y, z) (x along the view's azimuth, y across;
 * any length) in the sea's axes, normalised, g[0..2]. */
static void frame_vec_to_global(const view_frame *f, double x, double y, double z, double g[3])
{
    const double l = 1.0 / sqrt(x * x + y * y + z * z);
    g[0] = (x * f->cos_phi - y * f->sin_phi) * l;
    g[1] = (x * f->sin_phi + y * f->cos_phi) * l;
    g[2] = z * l;
}

/* The view frame toward the unit vector g (any zenith angle), for the
 * facets met again: its azimuth by cosine and sine alone (phi NAN: only
 * the energy balance's reflectance_fn reads the angle, an atan2 a node
 * of the outer rule saved). */
static void view_frame_of_vec(const sea_optics *p, const sea_slope_stats *st, const double g[3],
                              view_frame *f)
{
    const double h = sqrt(g[0] * g[0] + g[1] * g[1]); /* a unit vector: no overflow */
    const double c = h > 0.0 ? g[0] / h : 1.0, s = h > 0.0 ? g[1] / h : 0.0;
    view_frame_init_cs(p, st, g[2], h, NAN, c, s, g[2] > 0.0 && h < SEA_NADIR_THETA, f);
    /* a facet met again counts by its projected area along the ray alone
     * (the rate at which the ray meets it), whatever the shadowing */
    f->corr = 0;
}

/* Smith's Lambda toward the unit vector g, g[2] > 0 (sea_shadow_lambda
 * without angles), or 0 where it is certainly below SEA_MULTI_P_NEGLIGIBLE,
 * which bounds P: there Lambda = s G(t) / mu with t = (mu - m) / s > 0,
 * and G(t) < phi(t) / (1 + t^2) (the Mills ratio's lower bound
 * Q(t) > phi(t) t / (1 + t^2)), so the exact value, at one exp, is not
 * needed. */
static double lambda_toward(const sea_slope_stats *st, const double g[3])
{
    const double h = sqrt(g[0] * g[0] + g[1] * g[1]);
    if (!(h >= SEA_NADIR_THETA))
        return 0.0;
    const double c = g[0] / h, s = g[1] / h, mu = g[2] / h;
    const sea_cov2 *C = &st->cov;
    const double var = C->xx * c * c + 2.0 * C->xy * s * c + C->yy * s * s;
    const double m = st->mean.x * c + st->mean.y * s, sd = sqrt(var > 0.0 ? var : 0.0);
    if (sd > 0.0) {
        const double t = (mu - m) / sd;
        if (t > 0.0 && sd * 0.39894228040143267794 * exp(-0.5 * t * t) / ((1.0 + t * t) * mu) <
                           SEA_MULTI_P_NEGLIGIBLE)
            return 0.0;
    }
    return sea_shadow_hidden(mu, m, sd) / mu;
}

double sea_sky_radiance(const sea_sky *sky, size_t k, double cos_zenith)
{
    switch (sky->model) {
    case SEA_SKY_CLEAR: {
        /* [1 - (1 - eps_z)^(1/cos)] B(T_air): at and below the horizon the
         * path is opaque (eps_z > 0), B(T_air) */
        const double t = 1.0 - sky->zenith_emissivity;
        const double f = cos_zenith > 0.0 ? 1.0 - pow(t, 1.0 / cos_zenith) : 1.0;
        return f * sky->radiance[k];
    }
    case SEA_SKY_TABLE: {
        const double th = cos_zenith >= 1.0 ? 0.0 : cos_zenith > 0.0 ? acos(cos_zenith) : M_PI_2;
        return sea_profile_at(sky->zenith, &sky->radiance[k * sky->n_zenith], sky->n_zenith, th);
    }
    case SEA_SKY_ISOTROPIC:
    default:
        return sky->radiance[k];
    }
}

/* The mirror ray of the facet of slope (gX, gY) (frame f, cos psi cpsi >
 * 0) in the sea's axes, g (unit): r = 2 (n.v) n - v. */
static void mirror_of_node(const view_frame *f, double gX, double gY, double cpsi, double g[3])
{
    const double two_c = 2.0 * cpsi / sqrt(1.0 + gX * gX + gY * gY);
    frame_vec_to_global(f, -two_c * gX - f->sin_th, -two_c * gY, two_c - f->cos_th, g);
}

/* The chance that the mirror ray g meets the sea again (1 when it falls),
 * 0 where negligible (SEA_MULTI_P_NEGLIGIBLE; or its node's share of the
 * average, share, times it below SEA_MULTI_SHARE_NEGLIGIBLE). */
static double hit_chance(const sea_slope_stats *st, const double g[3], double L_in, double share)
{
    double P = 1.0;
    if (g[2] > 0.0) {
        const double L_r = lambda_toward(st, g);
        P = L_r / (1.0 + L_in + L_r);
        if (P < SEA_MULTI_P_NEGLIGIBLE)
            P = 0.0;
    }
    return P * share < SEA_MULTI_SHARE_NEGLIGIBLE ? 0.0 : P;
}

/* The sea around a facet (seabake-model(7), MULTIPLE REFLECTIONS): what
 * its mirror rays meet again.  A mirror ray travels metres before it meets
 * the sea again, farther than the finest facets are long, so the facets it
 * meets, and the chance that it meets any, are those of the sea as a whole:
 * the low-resolution slope statistics (m = 0, C_LR), whatever the facet it
 * left.  (A facet as large as the hop carries nearly all the slope variance
 * itself, so its own statistics are nearly these.)  Then what the second
 * hit reads depends on the mirror ray's direction alone, and is tabulated
 * once per scene: the emissivity E_(R-1) of the facets met toward -r, and
 * with a sky model the sky they reflect, K_(R-1), per index, on a grid of
 * the direction's zenith cosine u_z = x |x|, x in [-1, 1] (2 SEA_AROUND_HALF
 * intervals: fine near the horizon, where the chance of meeting the sea climbs
 * to 1 over a few hundredths of u_z on a calm sea) and of
 * cos^2 of its azimuth to the wind (the sea's slopes are symmetric about
 * the wind and across it: SEA_AROUND_NW nodes on [0, 1]), read by
 * Catmull-Rom in both.  exact: every read evaluated at its direction
 * instead (the reference). */
enum { SEA_AROUND_HALF = 64, SEA_AROUND_NW = 9 };
/* Stored as two halves, x <= 0 and x >= 0, each of SEA_AROUND_HALF + 1
 * nodes in x and SEA_AROUND_NW in the azimuth, padded with one ghost node
 * on every side (the linear extrapolation 2 f_0 - f_1 of the last two:
 * neither axis is an angle the values are even in, and no stencil crosses
 * the horizon, which parts the facets seen from above from those seen
 * from below), so that a read takes the 4 x 4 nodes around it unchecked. */
enum { SEA_AROUND_ROWS = SEA_AROUND_HALF + 3, SEA_AROUND_COLS = SEA_AROUND_NW + 2,
       SEA_AROUND_CELLS = 2 * SEA_AROUND_ROWS * SEA_AROUND_COLS };
struct sea_around {
    const sea_optics *p;
    sea_slope_stats lr; /* the sea around: m = 0, C_LR */
    double cw, sw;      /* its principal axes: the wind's azimuth */
    int reflections;    /* of the facets the sensor sees; the table holds E_(R-1) */
    int exact;
    size_t n;
    double complex *N;
    int has_sky;
    sea_sky sky;        /* the caller's, which must outlive this */
    /* cell c = (half SEA_AROUND_ROWS + row) SEA_AROUND_COLS + col: E and K
     * at [c n + k]; P[c] the chance a rising mirror ray -u meets the sea,
     * given nothing of the facet it left: Lambda / (1 + Lambda), Lambda =
     * lambda_toward(lr, -u), 1 where -u falls */
    double *E, *K, *P;
    /* The facets met's one-hit polarisation toward -u per index, in -u's
     * frame (sea_optics_polar_hits): Q at [c n + k], and U / sin 2Delta,
     * Delta the azimuth of -u from the wind (U is odd about the wind and
     * across it), at U[c n + k]; filled on the first read that asks
     * (around_polar), under polar_lock. */
    double *Q, *U;
    pthread_mutex_t polar_lock;
    atomic_int polarised;
    /* the second hits' orders (second_hit_around) */
    double split_scale, split_min, cross_scale, cross_min;
};

static int emis_multi_rec(const sea_optics *p, const sea_slope_stats *st, const view_frame *fd,
                          double L_in, const emis_ctx *ec, size_t n, int R, const fixed_rule *r0,
                          const sea_sky *sky, size_t k0, const spectral_basis *sb,
                          const sea_around *ar, double *out, double *kout);

/* The reflectance of the block's indices at cos psi c: through the basis
 * sb where there is one (the second hits), else each index's table (the
 * formula where exact), as rho_at. */
static void rho_of_block(const emis_ctx *ec, size_t n, const spectral_basis *sb, int exact,
                         double c, double *rho)
{
    if (sb != NULL) {
        basis_rho(sb, c, rho);
        return;
    }
    int tk;
    const double tt = fresnel_pos(c, &tk);
    for (size_t k = 0; k < n; k++)
        rho[k] = rho_at(&ec[k], exact, tk, tt, c);
}

/* The rule of the facets met again, seen from f: the auto rule at
 * SEA_MULTI_INNER_SCALE of its orders. */
static fixed_rule met_rule(const view_frame *f)
{
    const sea_emis_rule h = auto_rule(f);
    const double n_gl = ceil(h.n_gl * SEA_MULTI_INNER_SCALE);
    const double n_gh = ceil(h.n_gh * SEA_MULTI_INNER_SCALE);
    return (fixed_rule){ (int)sea_fmax(SEA_MULTI_INNER_GL_MIN, n_gl),
                         (int)sea_fmax(SEA_MULTI_INNER_GH_MIN, n_gh), SEA_RULE_T_CUT };
}

/* The facets met by the mirror ray g with one hit left and no sky model
 * (what emis_multi_rec gives at R = 1, sky NULL), through the basis b: their
 * emissivity toward -g is e0 - sum_r A_rk g_r for index k (basis_emissivity).
 * Returns 1; 0 when no facet is turned toward the ray (it escapes); -1
 * where the nodes are not the basis's (no spread, or one cross-slope node:
 * emis_multi_rec sums the tables). */
static int met_basis(const sea_optics *p, const sea_slope_stats *st, const double g[3],
                     const spectral_basis *b, double *e0, double *gr)
{
    const double o[3] = { -g[0], -g[1], -g[2] };
    view_frame fo;
    view_frame_of_vec(p, st, o, &fo);
    fixed_nodes nd;
    nodes_fixed(p, &fo, met_rule(&fo), &nd);
    if (nd.zero)
        return 0;
    if (nd.plain || nd.n_j <= 1)
        return -1;
    basis_emissivity(&nd, b, e0, gr);
    return 1;
}

/* What the mirror rays that meet the sea again add (R >= 2), per index k:
 *     T_k = E_w[rho_k P E_(R-1),k(-r)],
 *     D_k = E_w[rho_k P (K_(R-1),k(-r) - L_sky,k(r))]   (sky not NULL),
 * over the facets seen from f, with the emission's weight.  P has a kink
 * where the mirror ray is horizontal (1 where it falls; above, Lambda /
 * (1 + Lambda_v + Lambda) tends to 1 with a finite slope), and a product
 * Gauss rule across a kink converges only as its order squared (n_gl = 20
 * left E_2 up to 1.7e-3 from its converged value).  So for each
 * cross-slope node the Gauss-Legendre part in t is split where r_z = 0 (a
 * quadratic in t: gamma_X and gamma_Y are linear in it), each piece taking
 * SEA_MULTI_SPLIT_SCALE n_gl nodes times its share of the window (at least
 * SEA_MULTI_SPLIT_MIN).  On a piece where the ray rises P climbs to 1 at
 * the root, over a short stretch of t when the mean surface falls away
 * along the ray (Lambda of a ray just above the horizon is then small),
 * so there the nodes crowd toward the root (t = root -+ L u^2, Gauss-
 * Legendre in u; a piece between two roots is halved first).  Each
 * cross-slope node's average is normalised by its own weights (the same
 * integral), and the delta case (no spread along the view) has no t.
 * w_tot: the integral of the weight (rule a's estimate), for the nodes'
 * shares of the average. */
/* The pieces of the window [t_lo, t_hi] between the roots of r_z = 0 for
 * the facets gamma_X = aX + bX t, gamma_Y = aY + bY t seen from f:
 * c (1 + gX^2 + gY^2) - 2 (c - gX s) = 0, r_z of the sign of -(qa t^2 +
 * qb t + qc).  cut[0..nc) the ends (at most 5), root[i] whether cut i is a
 * root; a piece between two roots where the ray rises is cut in two, so
 * that a rising piece has one root end. */
typedef struct {
    double cut[5], qa, qb, qc;
    int root[5], nc;
} mirror_pieces;

static void mirror_pieces_of(const view_frame *f, double aX, double bX, double aY, double bY,
                             double t_lo, double t_hi, mirror_pieces *mp)
{
    double *cut = mp->cut;
    int nc = 0;
    cut[nc++] = t_lo;
    double qa = 0.0, qb = 0.0, qc = 0.0;
    if (!f->delta) {
        const double c = f->cos_th, s = f->sin_th;
        qa = c * (bX * bX + bY * bY);
        qb = 2.0 * c * (aX * bX + aY * bY) + 2.0 * s * bX;
        qc = c * (aX * aX + aY * aY - 1.0) + 2.0 * s * aX;
        double roots[2];
        int nr = 0;
        if (fabs(qa) > 0.0) {
            const double disc = qb * qb - 4.0 * qa * qc;
            if (disc > 0.0) {
                /* the stable pair of roots */
                const double q = -0.5 * (qb + copysign(sqrt(disc), qb));
                roots[nr++] = q / qa;
                if (q != 0.0)
                    roots[nr++] = qc / q;
            }
        } else if (qb != 0.0) {
            roots[nr++] = -qc / qb;
        }
        if (nr == 2 && roots[1] < roots[0]) {
            const double x = roots[0];
            roots[0] = roots[1];
            roots[1] = x;
        }
        for (int r = 0; r < nr; r++)
            if (roots[r] > cut[nc - 1] && roots[r] < t_hi)
                cut[nc++] = roots[r];
    }
    cut[nc++] = t_hi;
    int *root = mp->root;
    root[0] = 0;
    root[1] = nc > 2;
    root[2] = nc > 3;
    root[3] = root[4] = 0;
    if (nc == 4) {
        const double tm = 0.5 * (cut[1] + cut[2]);
        if ((qa * tm + qb) * tm + qc < 0.0) {
            cut[4] = cut[3];
            cut[3] = cut[2];
            cut[2] = tm;
            root[2] = 0;
            root[3] = 1;
            nc = 5;
        }
    }
    mp->qa = qa;
    mp->qb = qb;
    mp->qc = qc;
    mp->nc = nc;
}

/* A read's stencil in the sea around's tables (around_at). */
typedef struct {
    size_t c0;
    double wz[4], ww[4];
} around_stencil_t;
static void around_values(const sea_around *ar, const double o[3], size_t k0, size_t n,
                          const emis_ctx *ec, const spectral_basis *sb, double *e, double *kv,
                          double *pinf, around_stencil_t *sten);

/* The second hits' split rule: over the cross-slope nodes j (Gauss-Hermite
 * in gamma_Y given gamma_X, cross_scale times rule a's n_gh, at least
 * cross_min), the pieces of the view window the mirror ray's horizon
 * crossings cut (mirror_pieces_of), and each piece's nodes t (split_scale
 * times n_gl times its share of the window, at least split_min; crowded
 * toward the root on a rising piece), node(ctx, w_j, w, gX, gY) for every
 * node of positive weight w (the rule's, projected area and shadowing),
 * then cross(ctx, w_j, den) with den the sum of node j's weights.  The
 * three sums over it (second_hit, second_hit_around and the
 * polarisation's polar_hits_block) differ only in what a node adds;
 * always inlined, so that the callbacks are direct calls in each. */
typedef void (*hit_node_fn)(void *ctx, double w_j, double w, double gX, double gY);
typedef void (*hit_cross_fn)(void *ctx, double w_j, double den);
static inline __attribute__((always_inline)) void
walk_second_hits(const sea_optics *p, const view_frame *f, fixed_rule a, double split_scale,
                 double split_min, double cross_scale, double cross_min, hit_node_fn node,
                 hit_cross_fn cross, void *ctx)
{
    const int n_gh =
        a.n_gh > 0 ? (int)sea_fmin(a.n_gh, sea_fmax(cross_min, ceil(cross_scale * a.n_gh))) : 0;
    const int nj = n_gh > 0 ? n_gh : 1;
    const double *xj = n_gh > 0 ? &p->gh_x[SEA_TRI(n_gh - 1)] : NULL;
    const double *wj = n_gh > 0 ? &p->gh_w[SEA_TRI(n_gh - 1)] : NULL;
    double t_lo = 0.0, t_hi = 0.0;
    if (!f->delta)
        view_window(f, a.t_cut, &t_lo, &t_hi);
    /* the correlated shadowing's rows at the walk's z, found once */
    sea_cs_z cz;
    if (f->corr)
        sea_shadow_correlated_z(f->z, &cz);
    for (int j = 0; j < nj; j++) {
        const double w_j = wj != NULL ? wj[j] : 1.0;
        const double x_j = xj != NULL ? xj[j] : 0.0;
        /* gamma_X = aX + bX t, gamma_Y = aY + bY t (Eq 12: gamma_Y = m_Y) */
        const double aX = f->m_X, bX = f->delta ? 0.0 : f->s_X;
        const double aY = n_gh == 0 ? f->m_Y : f->m_Y + f->s_Y_given_X * x_j;
        const double bY = n_gh == 0 || f->delta ? 0.0 : f->b_YX;
        mirror_pieces mp;
        mirror_pieces_of(f, aX, bX, aY, bY, t_lo, t_hi, &mp);
        double den = 0.0;
        for (int piece = 0; piece + 1 < mp.nc; piece++) {
            const double ta = mp.cut[piece], tb = mp.cut[piece + 1];
            const double half = 0.5 * (tb - ta), mid = 0.5 * (tb + ta);
            /* the delta case: one node, weight 1 */
            const int m = f->delta ? 1
                                   : (int)sea_fmin(SEA_EMIS_GL_MAX,
                                                   sea_fmax(split_min, ceil(split_scale * a.n_gl *
                                                                            (tb - ta) /
                                                                            (t_hi - t_lo))));
            /* Where the ray rises P climbs to 1 at the root, steeply when
             * the mean surface falls away along the ray (0.06 to 1 over
             * 0.12 of t at 85 deg, 3 m/s, mean slope (0.1, -0.05)), so the
             * nodes crowd toward the root: t = root -+ (tb - ta) u^2, u in
             * [0, 1]. */
            int toward = 0; /* +1: the root is tb, -1: ta */
            if (!f->delta && (mp.qa * mid + mp.qb) * mid + mp.qc < 0.0 &&
                mp.root[piece] != mp.root[piece + 1])
                toward = mp.root[piece + 1] ? 1 : -1;
            const double *gx = &p->gl_x[SEA_TRI(m - 1)], *gw = &p->gl_w[SEA_TRI(m - 1)];
            for (int i = 0; i < m; i++) {
                double t = 0.0, dt = 1.0;
                if (!f->delta) {
                    if (toward == 0) {
                        t = mid + half * gx[i];
                        dt = half * gw[i];
                    } else {
                        const double u = 0.5 * (gx[i] + 1.0), L = tb - ta;
                        t = toward > 0 ? tb - L * u * u : ta + L * u * u;
                        dt = L * u * gw[i];
                    }
                }
                double w = f->delta ? 1.0 : dt * rule_weight(f, t);
                if (f->corr && w > 0.0)
                    w *= sea_shadow_correlated_zt(&cz, t);
                if (!(w > 0.0))
                    continue;
                den += w;
                node(ctx, w_j, w, aX + bX * t, aY + bY * t);
            }
        }
        cross(ctx, w_j, den);
    }
}

/* Two sums per index over a cross-slope node's nodes, acc, folded into
 * out at the node's end as out += w_j acc / den (the second hits' T and D,
 * or Q and U). */
typedef struct {
    size_t n;
    double *out[2];
    double acc[2][SEA_MULTI_BLOCK];
} node_sums;

static inline void node_sums_fold(node_sums *s, double w_j, double den)
{
    if (den > 0.0)
        for (size_t k = 0; k < s->n; k++) {
            s->out[0][k] += w_j * s->acc[0][k] / den;
            s->out[1][k] += w_j * s->acc[1][k] / den;
        }
    for (size_t k = 0; k < s->n; k++)
        s->acc[0][k] = s->acc[1][k] = 0.0;
}

/* The chance that the mirror ray toward -o meets the sea around again,
 * from the table's pinf = Lambda / (1 + Lambda) of the ray: p / (1 + L_in
 * (1 - p)), Eq 14c's bistatic factor (1 where the ray falls); 0 where
 * negligible (SEA_MULTI_P_NEGLIGIBLE, or times the node's share w_j w /
 * w_tot below SEA_MULTI_SHARE_NEGLIGIBLE), as hit_chance. */
static inline double around_chance(double pinf, const double o[3], double L_in, double w_j,
                                   double w, double w_tot)
{
    const double P = o[2] >= 0.0 ? 1.0 : pinf / (1.0 + L_in * (1.0 - pinf));
    return P < SEA_MULTI_P_NEGLIGIBLE || P * w_j * w / w_tot < SEA_MULTI_SHARE_NEGLIGIBLE ? 0.0
                                                                                            : P;
}

/* second_hit_around's sums: per cross-slope node and over them (T, D). */
typedef struct {
    const view_frame *f;
    double L_in, w_tot;
    const emis_ctx *ec;
    size_t n, k0;
    const sea_sky *sky;
    const spectral_basis *sb;
    const sea_around *ar;
    node_sums sums;
} around_sums;

static inline __attribute__((always_inline)) void around_node(void *ctx, double w_j, double w,
                                                              double gX, double gY)
{
    around_sums *c = ctx;
    const view_frame *f = c->f;
    const size_t n = c->n;
    const double inv = 1.0 / sqrt(1.0 + gX * gX + gY * gY);
    const double cpsi = (f->cos_th - gX * f->sin_th) * inv;
    if (!(cpsi > 0.0))
        return;
    /* the mirror ray 2 (n.v) n - v, a unit vector, in the sea's axes */
    const double two_c = 2.0 * cpsi * inv;
    const double x = -two_c * gX - f->sin_th, y = -two_c * gY;
    const double cph = f->cos_phi, sph = f->sin_phi;
    const double o[3] = { -(x * cph - y * sph), -(x * sph + y * cph), -(two_c - f->cos_th) };
    double eB[SEA_MULTI_BLOCK], kB[SEA_MULTI_BLOCK], pinf;
    around_values(c->ar, o, c->k0, n, c->ec, c->sb, eB, c->sky != NULL ? kB : NULL, &pinf, NULL);
    const double P = around_chance(pinf, o, c->L_in, w_j, w, c->w_tot);
    if (P == 0.0)
        return;
    double rho[SEA_MULTI_BLOCK];
    rho_of_block(c->ec, n, c->sb, f->delta, cpsi, rho);
    const double wP = w * P;
    for (size_t k = 0; k < n; k++)
        c->sums.acc[0][k] += wP * rho[k] * eB[k];
    if (c->sky != NULL) {
        for (size_t k = 0; k < n; k++)
            c->sums.acc[1][k] +=
                wP * rho[k] * (kB[k] - sea_sky_radiance(c->sky, c->k0 + k, -o[2]));
    }
}

static inline __attribute__((always_inline)) void around_cross(void *ctx, double w_j, double den)
{
    node_sums_fold(&((around_sums *)ctx)->sums, w_j, den);
}

/* second_hit in the sea around ar (seabake-model(7), MULTIPLE
 * REFLECTIONS): the same split rule at ar's orders, each node's mirror ray
 * g read from ar's table (or evaluated, ar->exact): the facets met's
 * E_(R-1) and K_(R-1) toward -g, and P = p / (1 + L_in (1 - p)) with p =
 * Lambda_g / (1 + Lambda_g) of the sea around (Eq 14c's bistatic factor
 * Lambda_g / (1 + L_in + Lambda_g); 1 where g falls). */
static void second_hit_around(const sea_optics *p, const view_frame *f, double L_in,
                              const emis_ctx *ec, size_t n, fixed_rule a, double w_tot,
                              const sea_sky *sky, size_t k0, const spectral_basis *sb,
                              const sea_around *ar, double *T, double *D)
{
    for (size_t k = 0; k < n; k++)
        T[k] = D[k] = 0.0;
    around_sums c = { f, L_in, w_tot, ec, n, k0, sky, sb, ar, { n, { T, D }, { { 0.0 } } } };
    walk_second_hits(p, f, a, ar->split_scale, ar->split_min, ar->cross_scale, ar->cross_min,
                     around_node, around_cross, &c);
}

/* second_hit's sums: per cross-slope node (num, knum; factored: X, Y)
 * and over them (T, D; XT, YT). */
typedef struct {
    const sea_optics *p;
    const sea_slope_stats *st;
    const view_frame *f;
    double L_in, w_tot;
    const emis_ctx *ec;
    size_t n, k0;
    int R, factored;
    const sea_sky *sky;
    const spectral_basis *sb;
    node_sums sums; /* T, D */
    /* factored: sum rho_k P E_1,k through the basis, rho_k = sum_r A_rk
     * B_r and E_1,k = e0 - sum_q A_qk g_q, as X_r = sum w P B_r e0 and
     * Y_rq = sum w P B_r g_q, the indices only at the end; XT and YT the
     * cross-slope nodes' X and Y, each scaled by its w_j / den, summed
     * (the sum over the indices is linear in them: once) */
    double X[SEA_BASIS_RANK_MAX], Y[SEA_BASIS_RANK_MAX][SEA_BASIS_RANK_MAX];
    double XT[SEA_BASIS_RANK_MAX], YT[SEA_BASIS_RANK_MAX][SEA_BASIS_RANK_MAX];
} hit_sums;

static inline __attribute__((always_inline)) void hit_node(void *ctx, double w_j, double w,
                                                           double gX, double gY)
{
    hit_sums *c = ctx;
    const sea_optics *p = c->p;
    const view_frame *f = c->f;
    const spectral_basis *sb = c->sb;
    const size_t n = c->n;
    const double cpsi = cos_psi_of(f, gX, gY);
    if (!(cpsi > 0.0))
        return;
    double g[3];
    mirror_of_node(f, gX, gY, cpsi, g);
    const double P = hit_chance(c->st, g, c->L_in, w_j * w / c->w_tot);
    if (P == 0.0)
        return;
    if (c->factored) {
        double e0, gr[SEA_BASIS_RANK_MAX];
        const int got = met_basis(p, c->st, g, sb, &e0, gr);
        if (got == 0)
            return;
        if (got > 0) {
            double bA[SEA_BASIS_RANK_MAX];
            basis_at(sb, cpsi, bA);
            for (int r = 0; r < sb->rank; r++) {
                const double cw = w * P * bA[r];
                c->X[r] += cw * e0;
                for (int q = 0; q < sb->rank; q++)
                    c->Y[r][q] += cw * gr[q];
            }
            return;
        }
    }
    double eB[SEA_MULTI_BLOCK], kB[SEA_MULTI_BLOCK];
    const double o[3] = { -g[0], -g[1], -g[2] };
    view_frame fo;
    view_frame_of_vec(p, c->st, o, &fo);
    /* no facet turned toward the ray (a slope distribution without
     * spread, tilted): there is nothing to meet, and the ray escapes (so
     * the closure holds) */
    if (!emis_multi_rec(p, c->st, &fo, 0.0, c->ec, n, c->R - 1, NULL, c->sky, c->k0, sb, NULL,
                        eB, c->sky != NULL ? kB : NULL))
        return;
    double rho[SEA_MULTI_BLOCK];
    rho_of_block(c->ec, n, sb, f->delta, cpsi, rho);
    for (size_t k = 0; k < n; k++) {
        c->sums.acc[0][k] += w * rho[k] * P * eB[k];
        if (c->sky != NULL)
            c->sums.acc[1][k] +=
                w * rho[k] * P * (kB[k] - sea_sky_radiance(c->sky, c->k0 + k, g[2]));
    }
}

static inline __attribute__((always_inline)) void hit_cross(void *ctx, double w_j, double den)
{
    hit_sums *c = ctx;
    const spectral_basis *sb = c->sb;
    node_sums_fold(&c->sums, w_j, den);
    if (c->factored && den > 0.0) {
        const double cw = w_j / den;
        for (int r = 0; r < sb->rank; r++) {
            c->XT[r] += cw * c->X[r];
            for (int q = 0; q < sb->rank; q++)
                c->YT[r][q] += cw * c->Y[r][q];
        }
    }
    if (c->factored)
        for (int r = 0; r < sb->rank; r++) {
            c->X[r] = 0.0;
            for (int q = 0; q < sb->rank; q++)
                c->Y[r][q] = 0.0;
        }
}

/* The second hits of the facet's mirror rays (seabake-model(7), MULTIPLE
 * REFLECTIONS): over walk_second_hits's nodes, every mirror ray g's hit
 * chance P and the facets met's E_(R-1) and K_(R-1) toward -g
 * (recursively, or through the basis when factored), into T and D per
 * index; in the sea around ar, second_hit_around.  It runs per facet and
 * per hit at reflections >= 2 (the render's inner loop). */
static void second_hit(const sea_optics *p, const sea_slope_stats *st, const view_frame *f,
                       double L_in, const emis_ctx *ec, size_t n, int R, fixed_rule a,
                       double w_tot, const sea_sky *sky, size_t k0, const spectral_basis *sb,
                       const sea_around *ar, double *T, double *D)
{
    if (ar != NULL) {
        second_hit_around(p, f, L_in, ec, n, a, w_tot, sky, k0, sb, ar, T, D);
        return;
    }
    for (size_t k = 0; k < n; k++)
        T[k] = D[k] = 0.0;
    /* one hit left and no sky model: the facets met's emissivity through
     * the basis, summed over the indices once (met_basis) */
    const int factored = sb != NULL && sky == NULL && R == 2;
    hit_sums c = { .p = p, .st = st, .f = f, .L_in = L_in, .w_tot = w_tot, .ec = ec, .n = n,
                   .k0 = k0, .R = R, .factored = factored, .sky = sky, .sb = sb,
                   .sums = { n, { T, D }, { { 0.0 } } } };
    walk_second_hits(p, f, a, SEA_MULTI_SPLIT_SCALE, SEA_MULTI_SPLIT_MIN, SEA_MULTI_CROSS_SCALE,
                     SEA_MULTI_CROSS_MIN, hit_node, hit_cross, &c);
    if (factored)
        for (size_t k = 0; k < n; k++) {
            double v = 0.0;
            for (int r = 0; r < sb->rank; r++) {
                double y = c.XT[r];
                for (int q = 0; q < sb->rank; q++)
                    y -= sb->A[q][k] * c.YT[r][q];
                v += sb->A[r][k] * y;
            }
            T[k] += v;
        }
}

/* E_R toward d (zenith in [0, pi)) for indices N[0..n), n <= SEA_MULTI_BLOCK,
 * and, when sky is not NULL, the sky's radiance that reaches d by
 * reflections, K_R (indices k0 .. k0 + n of the sky's arrays):
 *     E_R(v) = E_1(v) + E_w[rho_A P_A E_(R-1)(-r_A)],
 *     K_R(v) = E_w[rho_A L_sky(r_A)] + E_w[rho_A P_A (K_(R-1)(-r_A) - L_sky(r_A))],
 *     K_1(v) = E_w[rho_A L_sky(r_A)]   (a falling r_A: the horizon's sky),
 * so that E_R + K_R / L = 1 under a uniform sky of radiance L, at every R:
 * E_1 and K_1 by the rule a (emissivity_of_nodes, as reflections = 1), the
 * second hits by second_hit's split rule of the same orders.  first: fd is
 * the sensor's frame and *r0 the rule of its facets (the one reflections =
 * 1 uses); otherwise fd looks at facets met again, by the auto rule at
 * SEA_MULTI_INNER_SCALE of its orders.  Returns 0 when no facet is turned
 * toward fd (then out and kout are 0), else 1. */
static int emis_multi_rec(const sea_optics *p, const sea_slope_stats *st, const view_frame *fd,
                          double L_in, const emis_ctx *ec, size_t n, int R, const fixed_rule *r0,
                          const sea_sky *sky, size_t k0, const spectral_basis *sb,
                          const sea_around *ar, double *out, double *kout)
{
    const int first = r0 != NULL;
    const view_frame f = *fd;
    const fixed_rule a = first ? *r0 : met_rule(&f);
    fixed_nodes nd;
    nodes_fixed(p, &f, a, &nd);
    /* through the spectral basis when there is one, but for the paper's
     * single reflection (R = 1 sums each table, to the bit) */
    const spectral_basis *b1 = !first || R >= 2 ? sb : NULL;
    if (b1 != NULL && !nd.zero && !nd.plain && nd.n_j > 1)
        emissivity_of_nodes_basis(&nd, sb, out);
    else
        emissivity_of_nodes_n(&nd, ec, n, out);
    if (kout != NULL)
        for (size_t k = 0; k < n; k++)
            kout[k] = 0.0;
    if (nd.zero)
        return 0;
    if (R <= 1 && sky == NULL)
        return 1;
    if (sky != NULL) {
        /* K_1: the sky toward each facet's mirror ray, over the rule's nodes */
        double t_lo, t_hi;
        view_window(&f, a.t_cut, &t_lo, &t_hi);
        const double half = 0.5 * (t_hi - t_lo), mid = 0.5 * (t_hi + t_lo);
        double knum[SEA_MULTI_BLOCK] = { 0.0 }, den = 0.0;
        for (int i = 0; i < nd.n_i; i++) {
            const double wi = nd.w_i[i];
            if (!nd.plain && wi <= 0.0)
                continue;
            const double tt = nd.plain ? 0.0 : mid + half * p->gl_x[SEA_TRI(a.n_gl - 1) + i];
            const double gX = nd.plain ? f.m_X : f.m_X + f.s_X * tt;
            for (int j = 0; j < nd.n_j; j++) {
                const double cpsi = nd.cos_psi[i * nd.n_j + j];
                /* Eq 12 (n_gh = 0): gamma_Y = m_Y, as inner_nodes */
                const double gY = a.n_gh == 0 ? f.m_Y
                                              : f.m_Y + (nd.plain ? 0.0 : f.b_YX * tt) +
                                                    f.s_Y_given_X * p->gh_x[SEA_TRI(a.n_gh - 1) + j];
                double g[3];
                mirror_of_node(&f, gX, gY, cpsi, g);
                double rho[SEA_MULTI_BLOCK];
                rho_of_block(ec, n, b1, nd.plain, cpsi, rho);
                for (size_t k = 0; k < n; k++)
                    knum[k] += (nd.plain ? 1.0 : wi) * nd.w_j[j] * rho[k] *
                               sea_sky_radiance(sky, k0 + k, g[2]);
            }
            den += nd.plain ? 1.0 : wi;
        }
        for (size_t k = 0; k < n; k++)
            kout[k] = den > 0.0 ? knum[k] / den : 0.0;
    }
    if (R >= 2) {
        /* the weight's integral, as rule a estimates it */
        double w_tot = 1.0;
        if (!nd.plain) {
            double t_lo, t_hi, s = 0.0;
            view_window(&f, a.t_cut, &t_lo, &t_hi);
            for (int i = 0; i < nd.n_i; i++)
                s += nd.w_i[i] > 0.0 ? nd.w_i[i] : 0.0;
            w_tot = 0.5 * (t_hi - t_lo) * s;
        }
        double T[SEA_MULTI_BLOCK], D[SEA_MULTI_BLOCK];
        second_hit(p, st, &f, L_in, ec, n, R, a, w_tot, sky, k0, sb, ar, T, D);
        for (size_t k = 0; k < n; k++) {
            out[k] += T[k];
            if (kout != NULL)
                kout[k] += D[k];
        }
    }
    return 1;
}

/* The common part of sea_emissivity_multi_n and sea_emissivity_sky_n. */
static sea_status emissivity_general(const sea_optics *p, sea_emis_method method,
                                     const sea_emis_rule *rule, const double complex *N, size_t n,
                                     const sea_slope_stats *st, sea_dir v, int reflections,
                                     const sea_sky *sky, const sea_around *ar, double *out,
                                     double *sky_out, sea_error *err)
{
    if (reflections < 1 || reflections > SEA_REFLECTIONS_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "reflections %d is outside 1..%d", reflections,
                        SEA_REFLECTIONS_MAX);
    if (reflections == 1 && sky == NULL)
        return sea_emissivity_n(p, method, rule, N, n, st, v, out, err);
    sea_status s;
    if ((s = check_rule(rule, err)) != SEA_OK)
        return s;
    if ((s = check_dir(v, "view", err)) != SEA_OK || (s = sea_slope_stats_check(st, err)) != SEA_OK)
        return s;
    /* the sensor's facets by the rule reflections = 1 would use (full: auto) */
    view_frame f;
    view_frame_init(p, st, v, &f);
    const fixed_rule r0 = fixed_rule_of(&f, method, rule);
    /* the sensor's facets are seen: the mirror ray's chance is conditioned
     * on it (Eq 14c); the facets met again were met from below */
    const double L_in = lambda_along(ar != NULL ? &ar->lr : st, v);
    for (size_t k0 = 0; k0 < n; k0 += SEA_MULTI_BLOCK) {
        const size_t m = n - k0 < SEA_MULTI_BLOCK ? n - k0 : SEA_MULTI_BLOCK;
        emis_ctx ec[SEA_MULTI_BLOCK];
        size_t slot = 0;
        for (size_t k = 0; k < m; k++)
            ec[k] = (emis_ctx){ N[k0 + k], fresnel_of(p, N[k0 + k], &slot) };
        (void)emis_multi_rec(p, st, &f, L_in, ec, m, reflections, &r0, sky, k0,
                             spectral_basis_of(p, ec, m), ar, &out[k0],
                             sky != NULL ? &sky_out[k0] : NULL);
    }
    return SEA_OK;
}

sea_status sea_emissivity_sky_n(const sea_optics *p, sea_emis_method method,
                                const sea_emis_rule *rule, const double complex *N, size_t n,
                                const sea_slope_stats *st, sea_dir v, int reflections,
                                const sea_sky *sky, double *eps, double *sky_out, sea_error *err)
{
    if (sky == NULL ||
        (sky->model != SEA_SKY_ISOTROPIC && sky->model != SEA_SKY_CLEAR &&
         sky->model != SEA_SKY_TABLE) ||
        (sky->model == SEA_SKY_CLEAR &&
         !(sky->zenith_emissivity > 0.0 && sky->zenith_emissivity <= 1.0)) ||
        (sky->model == SEA_SKY_TABLE && (sky->n_zenith < 2 || sky->zenith == NULL)))
        return sea_fail(err, SEA_ERR_DOMAIN, "sky model %d or zenith emissivity out of range",
                        sky != NULL ? (int)sky->model : -1);
    return emissivity_general(p, method, rule, N, n, st, v, reflections, sky, NULL, eps, sky_out,
                              err);
}

sea_status sea_emissivity_multi_n(const sea_optics *p, sea_emis_method method,
                                  const sea_emis_rule *rule, const double complex *N, size_t n,
                                  const sea_slope_stats *st, sea_dir v, int reflections,
                                  double *out, sea_error *err)
{
    return emissivity_general(p, method, rule, N, n, st, v, reflections, NULL, NULL, out, NULL,
                              err);
}

/* ------------------------------------------------------- the sea around */

/* The facets of the sea around seen toward o, with R - 1 hits left:
 * E_(R-1) (and K_(R-1) with a sky) for indices k0 .. k0 + n, directly. */
static void around_direct(const sea_around *ar, const double o[3], size_t k0, size_t n,
                          const emis_ctx *ec, const spectral_basis *sb, double *e, double *kv)
{
    view_frame fo;
    view_frame_of_vec(ar->p, &ar->lr, o, &fo);
    /* the sea around is homogeneous: its own facets are its around */
    const int sky = ar->has_sky && kv != NULL; /* (kv NULL: E alone) */
    if (!emis_multi_rec(ar->p, &ar->lr, &fo, 0.0, ec, n, ar->reflections - 1, NULL,
                        sky ? &ar->sky : NULL, k0, sb, NULL, e, sky ? kv : NULL))
        for (size_t k = 0; k < n; k++)
            e[k] = 0.0; /* no facet faces o: nothing is met (escapes) */
    if (!ar->has_sky && kv != NULL)
        for (size_t k = 0; k < n; k++)
            kv[k] = 0.0;
}

/* The node row and the weights of a position x >= 0 on an axis of nn
 * intervals: the stencil's first node is the returned row of the padded
 * table (the ghost is row 0). */
static inline int around_stencil(double x, int nn, double w[4])
{
    int i = (int)x;
    if (i > nn - 1)
        i = nn - 1;
    sea_catmull_rom(x - i, w);
    return i;
}

/* The stencil of a read toward o: the first cell c0 of its 4 x 4 cells
 * (rows SEA_AROUND_COLS apart) and the weights along u_z (wz) and the
 * azimuth (ww). */
static size_t around_at(const sea_around *ar, const double o[3], double wz[4], double ww[4])
{
    /* the half and x = sqrt|u_z| in it, from the horizon; cos^2 of the
     * azimuth to the wind */
    const int below = o[2] < 0.0;
    const double xz = sqrt(fabs(o[2])) * SEA_AROUND_HALF;
    const double h2 = o[0] * o[0] + o[1] * o[1];
    const double a = o[0] * ar->cw + o[1] * ar->sw;
    const double xw = (h2 > 0.0 ? sea_fmin(a * a / h2, 1.0) : 1.0) * (SEA_AROUND_NW - 1);
    /* below: row r of the half is x = -(HALF - r)/HALF, so from the
     * horizon the rows run backwards */
    int rz = around_stencil(xz, SEA_AROUND_HALF, wz);
    if (below) {
        rz = SEA_AROUND_HALF - 1 - rz;
        double t = wz[0];
        wz[0] = wz[3];
        wz[3] = t;
        t = wz[1];
        wz[1] = wz[2];
        wz[2] = t;
    }
    const int cw = around_stencil(xw, SEA_AROUND_NW - 1, ww);
    return ((size_t)(below ? 0 : 1) * SEA_AROUND_ROWS + (size_t)rz) * SEA_AROUND_COLS + (size_t)cw;
}

/* The 4 x 4 stencil from cell c0 of a table of na values a cell, for
 * indices k0 .. k0 + n: out[k]. */
static inline void around_read(const double *T, size_t c0, size_t na, size_t k0, size_t n,
                               const double wz[4], const double ww[4], double *out)
{
    const double *base = T + c0 * na + k0;
    const size_t row = (size_t)SEA_AROUND_COLS * na;
    for (size_t k = 0; k < n; k++) {
        const double *q = base + k;
        double v = 0.0;
        for (int r = 0; r < 4; r++, q += row)
            v += wz[r] * ((ww[0] * q[0] + ww[1] * q[na]) + (ww[2] * q[2 * na] + ww[3] * q[3 * na]));
        out[k] = v;
    }
}

static void around_values(const sea_around *ar, const double o[3], size_t k0, size_t n,
                          const emis_ctx *ec, const spectral_basis *sb, double *e, double *kv,
                          double *pinf, around_stencil_t *sten)
{
    if (ar->exact) {
        const double g[3] = { -o[0], -o[1], -o[2] };
        const double L = g[2] > 0.0 ? lambda_toward(&ar->lr, g) : INFINITY;
        *pinf = isinf(L) ? 1.0 : L / (1.0 + L);
        around_direct(ar, o, k0, n, ec, sb, e, kv);
        return;
    }
    double wz[4], ww[4];
    const size_t c0 = around_at(ar, o, wz, ww);
    if (sten != NULL) {
        sten->c0 = c0;
        memcpy(sten->wz, wz, sizeof wz);
        memcpy(sten->ww, ww, sizeof ww);
    }
    const int below = o[2] < 0.0;
    around_read(ar->E, c0, ar->n, k0, n, wz, ww, e);
    if (kv != NULL) {
        if (ar->has_sky)
            around_read(ar->K, c0, ar->n, k0, n, wz, ww, kv);
        else
            for (size_t k = 0; k < n; k++)
                kv[k] = 0.0;
    }
    if (!below) {
        *pinf = 1.0;
    } else {
        double v;
        around_read(ar->P, c0, 1, 0, 1, wz, ww, &v);
        *pinf = sea_fmin(sea_fmax(v, 0.0), 1.0);
    }
}

/* The table's cell of row r (0 .. HALF, from x = -1 in the lower half,
 * from the horizon in the upper) and azimuth node j, ghosts aside. */
static size_t around_cell(int half, int r, int j)
{
    return ((size_t)half * SEA_AROUND_ROWS + (size_t)(r + 1)) * SEA_AROUND_COLS + (size_t)(j + 1);
}

/* The ghosts of one array of m values a cell: f(-1) = 2 f(0) - f(1) at
 * every edge of each half (the corners from the filled edges). */
static void around_ghosts(double *v, size_t m)
{
    for (int half = 0; half < 2; half++) {
        for (int j = 0; j < SEA_AROUND_NW; j++) {
            const size_t lo = around_cell(half, -1, j), hi = around_cell(half, SEA_AROUND_HALF + 1, j);
            const size_t a0 = around_cell(half, 0, j), a1 = around_cell(half, 1, j);
            const size_t b0 = around_cell(half, SEA_AROUND_HALF, j),
                         b1 = around_cell(half, SEA_AROUND_HALF - 1, j);
            for (size_t k = 0; k < m; k++) {
                v[lo * m + k] = 2.0 * v[a0 * m + k] - v[a1 * m + k];
                v[hi * m + k] = 2.0 * v[b0 * m + k] - v[b1 * m + k];
            }
        }
        for (int r = -1; r <= SEA_AROUND_HALF + 1; r++) {
            const size_t lo = around_cell(half, r, -1), hi = around_cell(half, r, SEA_AROUND_NW);
            const size_t a0 = around_cell(half, r, 0), a1 = around_cell(half, r, 1);
            const size_t b0 = around_cell(half, r, SEA_AROUND_NW - 1),
                         b1 = around_cell(half, r, SEA_AROUND_NW - 2);
            for (size_t k = 0; k < m; k++) {
                v[lo * m + k] = 2.0 * v[a0 * m + k] - v[a1 * m + k];
                v[hi * m + k] = 2.0 * v[b0 * m + k] - v[b1 * m + k];
            }
        }
    }
}

sea_status sea_around_alloc(const sea_optics *p, const sea_slope_stats *lr,
                            const double complex *N, size_t n, int reflections, const sea_sky *sky,
                            int exact, sea_around **out, sea_error *err)
{
    *out = NULL;
    sea_status st = sea_slope_stats_check(lr, err);
    if (st != SEA_OK)
        return st;
    if (reflections < 2 || reflections > SEA_REFLECTIONS_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "the sea around: reflections %d (allowed: 2..%d)",
                        reflections, SEA_REFLECTIONS_MAX);
    if (n < 1)
        return sea_fail(err, SEA_ERR_DOMAIN, "the sea around: no index");
    sea_around *ar = calloc(1, sizeof *ar);
    if (ar == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the sea around");
    pthread_mutex_init(&ar->polar_lock, NULL);
    atomic_init(&ar->polarised, 0);
    ar->p = p;
    ar->lr = *lr;
    /* the covariance's principal axis (the wind's, for the spectrum's) */
    const double ang = 0.5 * atan2(2.0 * lr->cov.xy, lr->cov.xx - lr->cov.yy);
    ar->cw = cos(ang);
    ar->sw = sin(ang);
    ar->reflections = reflections;
    ar->exact = exact != 0;
    ar->split_scale = SEA_MULTI_SPLIT_SCALE;
    ar->split_min = SEA_MULTI_SPLIT_MIN;
    ar->cross_scale = SEA_MULTI_CROSS_SCALE;
    ar->cross_min = SEA_MULTI_CROSS_MIN;
    ar->n = n;
    ar->has_sky = sky != NULL;
    if (sky != NULL)
        ar->sky = *sky;
    const size_t cells = (size_t)SEA_AROUND_CELLS * n;
    ar->N = malloc(n * sizeof *ar->N);
    if (!ar->exact) {
        ar->E = calloc(cells, sizeof *ar->E);
        ar->K = calloc(cells, sizeof *ar->K);
        ar->P = calloc(SEA_AROUND_CELLS, sizeof *ar->P);
        ar->Q = calloc(cells, sizeof *ar->Q);
        ar->U = calloc(cells, sizeof *ar->U);
    }
    if (ar->N == NULL || (!ar->exact && (ar->E == NULL || ar->K == NULL || ar->P == NULL ||
                                         ar->Q == NULL || ar->U == NULL))) {
        sea_around_free(ar);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the sea around's table");
    }
    memcpy(ar->N, N, n * sizeof *N);
    if (!ar->exact) {
        /* every node direct: row r of the lower half at x = -(HALF - r) /
         * HALF, of the upper at x = r / HALF, u_z = x |x|; azimuth node j
         * at cos^2 = j / (NW - 1) to the wind, acos(sqrt(c2)) from it */
        enum { NODES = 2 * (SEA_AROUND_HALF + 1) * SEA_AROUND_NW };
#pragma omp parallel for schedule(dynamic, 4) if (NODES * n > 64)
        for (int q = 0; q < NODES; q++) {
            const int half = q / ((SEA_AROUND_HALF + 1) * SEA_AROUND_NW);
            const int r = (q / SEA_AROUND_NW) % (SEA_AROUND_HALF + 1), j = q % SEA_AROUND_NW;
            const double x = half == 0 ? -(double)(SEA_AROUND_HALF - r) / SEA_AROUND_HALF
                                       : (double)r / SEA_AROUND_HALF;
            const double uz = x * fabs(x);
            const double c2 = (double)j / (SEA_AROUND_NW - 1);
            const double h = sqrt(fmax(1.0 - uz * uz, 0.0));
            const double ca = sqrt(c2), sa = sqrt(fmax(1.0 - c2, 0.0));
            const double o[3] = { h * (ar->cw * ca - ar->sw * sa), h * (ar->sw * ca + ar->cw * sa),
                                  uz };
            const size_t c = around_cell(half, r, j);
            const double g[3] = { -o[0], -o[1], -o[2] };
            const double L = g[2] > 0.0 ? lambda_toward(&ar->lr, g) : INFINITY;
            ar->P[c] = isinf(L) ? 1.0 : L / (1.0 + L);
            for (size_t k0 = 0; k0 < n; k0 += SEA_MULTI_BLOCK) {
                const size_t m = n - k0 < SEA_MULTI_BLOCK ? n - k0 : SEA_MULTI_BLOCK;
                emis_ctx ec[SEA_MULTI_BLOCK];
                size_t slot = 0;
                for (size_t k = 0; k < m; k++)
                    ec[k] = (emis_ctx){ N[k0 + k], fresnel_of(p, N[k0 + k], &slot) };
                const size_t at = c * n + k0;
                around_direct(ar, o, k0, m, ec, spectral_basis_of(p, ec, m), &ar->E[at],
                              &ar->K[at]);
            }
        }
        around_ghosts(ar->E, n);
        around_ghosts(ar->K, n);
        around_ghosts(ar->P, 1);
    }
    *out = ar;
    return SEA_OK;
}

void sea_around_set_orders(sea_around *ar, double split_scale, double split_min,
                           double cross_scale, double cross_min)
{
    ar->split_scale = split_scale;
    ar->split_min = split_min;
    ar->cross_scale = cross_scale;
    ar->cross_min = cross_min;
}

void sea_around_free(sea_around *ar)
{
    if (ar == NULL)
        return;
    free(ar->N);
    free(ar->E);
    free(ar->K);
    free(ar->P);
    free(ar->Q);
    free(ar->U);
    pthread_mutex_destroy(&ar->polar_lock);
    free(ar);
}

sea_status sea_emissivity_around_n(const sea_optics *p, sea_emis_method method,
                                   const sea_emis_rule *rule, const double complex *N, size_t n,
                                   const sea_slope_stats *st, sea_dir v, const sea_around *ar,
                                   const sea_sky *sky, double *eps, double *sky_out,
                                   sea_error *err)
{
    if (ar == NULL || ar->n != n || ar->has_sky != (sky != NULL))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "the sea around was made for %zu indices %s a sky; asked for %zu %s",
                        ar != NULL ? ar->n : 0, ar != NULL && ar->has_sky ? "with" : "without", n,
                        sky != NULL ? "with" : "without");
    return emissivity_general(p, method, rule, N, n, st, v, ar->reflections, sky, ar, eps,
                              sky_out, err);
}

/* ------------------------------------------------------------ sun disc */

/* The sun as a disc of angular radius a: the reflectivity averaged over
 * the disc's incidence directions, (1/Omega) int_disc rho~(w_i; obs) dw_i.
 * The mirror map sends the disc to a small ellipse in slope space,
 * gamma = gamma0 + M u, |u| <= a (M: the mirror slope's derivatives along
 * two orthogonal tangents at the sun's centre); rho, g/D and S hardly vary
 * over it (a = 0.27 deg), so the average is rho g/D S Mass / Omega, Mass the
 * slope distribution's probability inside the ellipse.  When the density is
 * nearly linear over the ellipse Mass = p(gamma0) |det M| pi a^2 and this is
 * the point sun's rho~ (J = |det M|): the disc is then skipped, when the
 * second-order term, (a^2/8) lambda_max(M^T C^-1 M) (1 + d^2), d the
 * centre's Mahalanobis distance, is below skip_rel.  Else Mass is that of
 * the Gaussian N(M^-1 (m - gamma0), M^-1 C M^-T) in u over the disc: up to
 * a second-order term of SEA_DISC_SERIES_MAX, p(gamma0) |det M| pi a^2 times
 * the density's mean over the disc relative to its centre's (the
 * mean-value series, sea_disc_series); beyond, by quadrature, the inner
 * direction exactly (erf), the outer by Gauss-Legendre in u1 = a sin t
 * over where it lives (8 standard deviations). */
enum { SEA_DISC_NODES = 64 };
/* Up to this second-order term the series (sea_disc_series, summed to
 * convergence: within 1.3e-13 of 64-node quadrature, tests/test_optics.c)
 * replaces the quadrature, which takes 64 nodes beyond. */
static const double SEA_DISC_SERIES_MAX = 1.0;

static void mirror_slope(const double ui[3], const double uo[3], double g[2])
{
    const double h[3] = { ui[0] + uo[0], ui[1] + uo[1], ui[2] + uo[2] };
    g[0] = -h[0] / h[2];
    g[1] = -h[1] / h[2];
}

/* The probability of the Gaussian N(mu, Cu) over the disc |u| <= a: the
 * inner direction exactly (erfc of positive arguments), the outer by
 * Gauss-Legendre in u1 = a sin t over where it lives (8 standard
 * deviations). */
double sea_disc_mass(const sea_optics *p, const double Cu[2][2], const double mu[2],
                     double radius, int nodes)
{
    const double s1 = sqrt(Cu[0][0]);
    const double beta = Cu[0][1] / Cu[0][0];
    const double sc = sqrt(sea_fmax(Cu[1][1] - beta * Cu[0][1], 1e-300));
    const double lo = sea_fmax(-radius, mu[0] - 8.0 * s1), hi = sea_fmin(radius, mu[0] + 8.0 * s1);
    double mass = 0.0;
    if (lo < hi) {
        const double t_lo = asin(lo / radius), t_hi = asin(hi / radius);
        const double half = 0.5 * (t_hi - t_lo), mid = 0.5 * (t_hi + t_lo);
        const double *x = &p->gl_x[SEA_TRI(nodes - 1)];
        const double *w = &p->gl_w[SEA_TRI(nodes - 1)];
        for (int i = 0; i < nodes; i++) {
            const double t = mid + half * x[i];
            const double u1 = radius * sin(t), du = radius * cos(t);
            const double z1 = (u1 - mu[0]) / s1;
            const double hh = sqrt(sea_fmax(radius * radius - u1 * u1, 0.0));
            /* P(|X| < hh), X ~ N(mc, sc): the same for -mc, and with the
             * mean on the negative side both erfc are of positive
             * arguments (two values near 2 would cancel in the tail) */
            const double mc = fabs(mu[1] + beta * (u1 - mu[0]));
            const double inner = 0.5 * (erfc((mc - hh) / (M_SQRT2 * sc)) -
                                        erfc((mc + hh) / (M_SQRT2 * sc)));
            mass += half * w[i] * du * exp(-0.5 * z1 * z1) / (s1 * sqrt(2.0 * M_PI)) * inner;
        }
    }
    return mass;
}

/* The mean of a Gaussian density f over the disc |u| <= a, over f(0): the
 * disc's mean-value series, sum over k of a^2k Lap^k f(0) / (4^k k!
 * (k+1)!), summed until its terms are below 1e-17 of the sum.  The
 * Laplacian's powers come from the heat kernel: sum_k s^k Lap^k f(0) / k!
 * is f smoothed by N(0, 2 s I) at 0, for f of precision Q centred at mu
 * G(s) = det(I + 2 s Q)^(-1/2) exp(mu.Q.mu / 2 - mu.(Q^-1 + 2 s I)^-1.mu / 2),
 * whose logarithm's coefficients are l_n = v.P^(n-1).v + tr(P^n) / (2 n x)
 * in s / x, with v = Q mu, x = a^2 / 4 and P = -2 x Q (both sequences by
 * Cayley-Hamilton, u_(n+1) = tr P u_n - det P u_(n-1)); exp of the series
 * by g_k = (1/k) sum_j j l_j g_(k-j) (in powers of s / x), and the mean is
 * sum_k g_k / (k+1)!.  Within 1.3e-13 of 64-node quadrature up to a
 * second-order term of 2 (33 terms at most up to 1, 47 up to 2; the 2-term
 * form used before was 1.3e-7 off by 0.004; tests/test_optics.c). */
double sea_disc_series(const double Q[2][2], const double mu[2], double radius)
{
    enum { K_MAX = 64 };
    const double x = 0.25 * radius * radius;
    const double v[2] = { Q[0][0] * mu[0] + Q[0][1] * mu[1], Q[1][0] * mu[0] + Q[1][1] * mu[1] };
    const double P[2][2] = { { -2.0 * x * Q[0][0], -2.0 * x * Q[0][1] },
                             { -2.0 * x * Q[1][0], -2.0 * x * Q[1][1] } };
    const double trP = P[0][0] + P[1][1], detP = P[0][0] * P[1][1] - P[0][1] * P[1][0];
    const double Pv[2] = { P[0][0] * v[0] + P[0][1] * v[1], P[1][0] * v[0] + P[1][1] * v[1] };
    /* s_n = v.P^(n-1).v and t_n = tr P^n: (s_(n-1), s_n), (t_(n-1), t_n) */
    double s0 = v[0] * v[0] + v[1] * v[1], s1 = v[0] * Pv[0] + v[1] * Pv[1];
    double t0 = 2.0, t1 = trP;
    double l[K_MAX + 1], g[K_MAX + 1];
    g[0] = 1.0;
    double sum = 1.0, fact = 1.0; /* (k + 1)! */
    int small = 0;
    for (int k = 1; k <= K_MAX; k++) {
        double s_k = s0, t_k = t1;
        if (k >= 2) {
            t_k = trP * t1 - detP * t0;
            t0 = t1;
            t1 = t_k;
            s_k = s1;
            if (k >= 3) {
                s_k = trP * s1 - detP * s0;
                s0 = s1;
                s1 = s_k;
            }
        }
        l[k] = x * s_k + t_k / (2.0 * k);
        double acc = 0.0;
        for (int j = 1; j <= k; j++)
            acc += j * l[j] * g[k - j];
        g[k] = acc / k;
        fact *= (double)(k + 1);
        const double term = g[k] / fact;
        sum += term;
        if (fabs(term) <= 1e-17 * fabs(sum)) {
            if (++small == 2)
                break;
        } else {
            small = 0;
        }
    }
    return sum;
}

void sea_reflectivity_disc_n(const sea_optics *p, const double complex *N, size_t n,
                             const sea_slope_stats *st, sea_dir inc, sea_dir obs, double radius,
                             double skip_rel, double negligible, double *out)
{
    /* the point sun's rho~ (the geometry found once, for the disc too);
     * rho(psi0) from the index's table (within 1e-10 of the formula) */
    mirror_geom m;
    mirror_geom_of(st, inc, obs, &m);
    size_t slot = 0;
    for (size_t i = 0; i < n; i++)
        out[i] = m.zero ? 0.0
                        : fresnel_at(p, N[i], m.cos_psi0, &slot) * m.pdf * m.g_over_D * m.S *
                              m.J;
    /* In the slopes' far tail (m.tail) the disc's Gaussian mass underflows
     * as the point density does: the point sun's value stands. */
    if (!(radius > 0.0) || m.tail)
        return;
    const double *ui = m.ui, *uo = m.uo;
    double g0[2];
    if (!(ui[2] + uo[2] > 0.0))
        return;
    mirror_slope(ui, uo, g0);
    /* M: derivatives of the mirror slope along e1 (zenith) and e2 (azimuth)
     * (the sines and cosines of dir_vec's ui) */
    const double hz = ui[2] + uo[2];
    const double h[3] = { ui[0] + uo[0], ui[1] + uo[1], hz };
    const double ct = m.ci, stt = m.si, cp = m.cpi, sp = m.spi;
    const double e[2][3] = { { ct * cp, ct * sp, -stt }, { -sp, cp, 0.0 } };
    double M[2][2]; /* M[row: gamma x, y][col: e1, e2] */
    for (int c = 0; c < 2; c++) {
        M[0][c] = -(e[c][0] * hz - h[0] * e[c][2]) / (hz * hz);
        M[1][c] = -(e[c][1] * hz - h[1] * e[c][2]) / (hz * hz);
    }
    const double det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
    if (!(fabs(det) > 0.0))
        return;
    const double xx = st->cov.xx + SEA_COV_REG, yy = st->cov.yy + SEA_COV_REG, xy = st->cov.xy;
    const double cdet = sea_fmax(xx * yy - xy * xy, SEA_COV_REG * SEA_COV_REG);
    /* C^-1 */
    const double ixx = yy / cdet, iyy = xx / cdet, ixy = -xy / cdet;
    /* Q = M^T C^-1 M, its largest eigenvalue */
    double Q[2][2];
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++)
            Q[a][b] = M[0][a] * (ixx * M[0][b] + ixy * M[1][b]) +
                      M[1][a] * (ixy * M[0][b] + iyy * M[1][b]);
    const double tr = Q[0][0] + Q[1][1], dq = Q[0][0] * Q[1][1] - Q[0][1] * Q[1][0];
    const double lmax = 0.5 * tr + sqrt(sea_fmax(0.25 * tr * tr - dq, 0.0));
    const double dx = g0[0] - st->mean.x, dy = g0[1] - st->mean.y;
    const double d2 = ixx * dx * dx + 2.0 * ixy * dx * dy + iyy * dy * dy;
    if (radius * radius / 8.0 * lmax * (1.0 + d2) < skip_rel)
        return;
    if (negligible > 0.0) {
        /* the density over the ellipse is at most exp(-(d - a sqrt(lmax))^2 / 2)
         * over exp(-d^2 / 2) times the centre's */
        double big = 0.0;
        int zero = 0;
        for (size_t i = 0; i < n; i++) {
            big = sea_fmax(big, out[i]);
            zero |= !(out[i] > 0.0);
        }
        if (!zero && big * exp(radius * sqrt(lmax * d2)) < negligible)
            return;
    }
    /* the Gaussian in u: mean M^-1 (m - gamma0), covariance M^-1 C M^-T,
     * precision Q */
    const double Mi[2][2] = { { M[1][1] / det, -M[0][1] / det }, { -M[1][0] / det, M[0][0] / det } };
    const double mu[2] = { Mi[0][0] * -dx + Mi[0][1] * -dy, Mi[1][0] * -dx + Mi[1][1] * -dy };
    double Cu[2][2];
    const double C[2][2] = { { xx, xy }, { xy, yy } };
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) {
            double sacc = 0.0;
            for (int k = 0; k < 2; k++)
                for (int l = 0; l < 2; l++)
                    sacc += Mi[a][k] * C[k][l] * Mi[b][l];
            Cu[a][b] = sacc;
        }
    /* the point value is rho pdf g/D S J with J = |det M|; the disc's is
     * rho g/D S Mass / Omega, Omega = pi a^2 (to a^4) */
    const double pdf0 = slope_pdf(st, g0[0], g0[1]);
    const double point_per = pdf0 * fabs(det); /* what out[] holds per rho g/D S */
    if (m.zero)
        return;
    const double second = radius * radius / 8.0 * lmax * (1.0 + d2);
    const double disc_per = second <= SEA_DISC_SERIES_MAX
                                ? point_per * sea_disc_series(Q, mu, radius)
                                : sea_disc_mass(p, Cu, mu, radius, SEA_DISC_NODES) /
                                      (M_PI * radius * radius);
    slot = 0;
    for (size_t i = 0; i < n; i++) {
        if (point_per > 0.0 && out[i] > 0.0)
            out[i] *= disc_per / point_per;
        else
            out[i] = fresnel_at(p, N[i], m.cos_psi0, &slot) * m.g_over_D * m.S * disc_per;
    }
}


/* ------------------------------------- the emissivity's nodes, for others */

/* sea_optics_facet_nodes (internal.h): the nodes sea_emissivity_n sums,
 * with their facet slopes put back from the rule's abscissae (the same
 * operations as nodes_fixed's and inner_nodes'), their weights w_i w_j
 * over the sum of the w_i (so that they sum to 1, as the emissivity's
 * average divides), cos psi as the emissivity reads it. */
/* The nodes of rule r over the facets seen in frame f, as
 * sea_optics_facet_nodes lists them; *count 0 when every facet is turned
 * away. */
static void frame_nodes(const sea_optics *p, const view_frame *fp, fixed_rule r,
                        sea_facet_node *nodes, size_t *count, int *exact)
{
    const view_frame f = *fp;
    fixed_nodes nd;
    nodes_fixed(p, &f, r, &nd);
    /* a facet without slope spread evaluates the formula (emissivity_of_nodes) */
    *exact = nd.plain;
    *count = 0;
    if (nd.zero)
        return;
    double t_lo, t_hi;
    view_window(&f, r.t_cut, &t_lo, &t_hi);
    const double half = 0.5 * (t_hi - t_lo), mid = 0.5 * (t_hi + t_lo);
    const double *x = &p->gl_x[SEA_TRI(r.n_gl - 1)];
    const double *xj = r.n_gh > 0 ? &p->gh_x[SEA_TRI(r.n_gh - 1)] : NULL;
    double den = 0.0;
    for (int i = 0; i < nd.n_i; i++)
        if (nd.plain || nd.w_i[i] > 0.0)
            den += nd.w_i[i];
    if (!(den > 0.0))
        return;
    size_t q = 0;
    for (int i = 0; i < nd.n_i; i++) {
        if (!nd.plain && !(nd.w_i[i] > 0.0))
            continue;
        const double t = nd.plain ? 0.0 : mid + half * x[i];
        const double gX = nd.plain ? f.m_X : f.m_X + f.s_X * t;
        const double mY = nd.plain ? f.m_Y : f.m_Y + f.b_YX * t;
        for (int j = 0; j < nd.n_j; j++) {
            nodes[q].gX = gX;
            nodes[q].gY = r.n_gh == 0 ? f.m_Y : mY + f.s_Y_given_X * xj[j];
            nodes[q].cos_psi = nd.cos_psi[i * nd.n_j + j];
            nodes[q].w = nd.w_i[i] * nd.w_j[j] / den;
            q++;
        }
    }
    *count = q;
}

sea_status sea_optics_facet_nodes(const sea_optics *p, sea_emis_method method,
                                  const sea_emis_rule *rule, const sea_slope_stats *st, sea_dir v,
                                  sea_facet_node *nodes, size_t *count, int *exact, sea_error *err)
{
    sea_status s;
    *count = 0;
    *exact = 0;
    if (rule == NULL && method != SEA_EMIS_AUTO && method != SEA_EMIS_FAST)
        return sea_fail(err, SEA_ERR_DOMAIN, "no fixed nodes for emissivity method %d",
                        (int)method);
    if ((s = check_rule(rule, err)) != SEA_OK)
        return s;
    if ((s = check_dir(v, "view", err)) != SEA_OK || (s = sea_slope_stats_check(st, err)) != SEA_OK)
        return s;
    view_frame f;
    view_frame_init(p, st, v, &f);
    frame_nodes(p, &f, fixed_rule_of(&f, method, rule), nodes, count, exact);
    return SEA_OK;
}

double sea_optics_one_minus_rho(const sea_optics *p, double complex N, int exact, double cos_psi)
{
    size_t slot = 0;
    const emis_ctx e = { N, exact ? NULL : fresnel_of(p, N, &slot) };
    return one_minus_rho(&e, cos_psi);
}

/* sea_optics_facet_mean_full (internal.h): expect_reference, the adaptive
 * rule of SEA_EMIS_FULL, for each value of fn in turn. */
typedef struct {
    sea_facet_fn fn;
    void *ctx;
    int which;
} facet_full_ctx;

static double facet_full_fn(const view_frame *f, double gX, double gY, double cos_psi, void *ctx)
{
    (void)f;
    const facet_full_ctx *c = ctx;
    double vals[SEA_FACET_VALUES_MAX];
    c->fn(gX, gY, cos_psi, c->ctx, vals);
    return vals[c->which];
}

sea_status sea_optics_facet_mean_full(const sea_optics *p, const sea_slope_stats *st, sea_dir v,
                                      sea_facet_fn fn, void *ctx, int nval, double *out,
                                      sea_error *err)
{
    sea_status s;
    if (nval < 1 || nval > SEA_FACET_VALUES_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "%d facet values is outside 1..%d", nval,
                        SEA_FACET_VALUES_MAX);
    if ((s = check_dir(v, "view", err)) != SEA_OK || (s = sea_slope_stats_check(st, err)) != SEA_OK)
        return s;
    view_frame f;
    view_frame_init(p, st, v, &f);
    for (int k = 0; k < nval; k++) {
        facet_full_ctx c = { fn, ctx, k };
        if ((s = expect_reference(p, &f, facet_full_fn, &c, 0, &out[k], err)) != SEA_OK)
            return s;
    }
    return SEA_OK;
}

/* ------------------------------------------ the second hits' polarisation */

/* The one-hit Stokes emission of the facets seen in frame fo (met_rule's
 * nodes) per index: Q and U in fo's frame (reference e_v of its view),
 * per unit contrast (polar.c); q or u NULL: not asked. */
static void met_stokes(const sea_optics *p, const view_frame *fo, const double complex *N,
                       size_t n, double *q, double *u)
{
    sea_facet_node nodes[SEA_FACET_NODES_MAX];
    size_t count;
    int exact;
    frame_nodes(p, fo, met_rule(fo), nodes, &count, &exact);
    for (size_t k = 0; k < n; k++) {
        if (q != NULL)
            q[k] = 0.0;
        if (u != NULL)
            u[k] = 0.0;
    }
    for (size_t i = 0; i < count; i++) {
        double c2, s2;
        sea_polar_plane_angle(fo->sin_th + nodes[i].gX * fo->cos_th, -nodes[i].gY, &c2, &s2);
        for (size_t k = 0; k < n; k++) {
            double Rs, Rp;
            sea_polar_fresnel(nodes[i].cos_psi, N[k], &Rs, &Rp);
            const double pol = 0.5 * (Rs - Rp) * nodes[i].w;
            if (q != NULL)
                q[k] += pol * c2;
            if (u != NULL)
                u[k] += pol * s2;
        }
    }
}

/* The facets of the sea around ar seen toward o: the one-hit Stokes
 * emission of indices k0 .. k0 + n, Q and U (either NULL: not asked) in
 * o's frame, directly. */
static void around_polar_direct(const sea_around *ar, const double o[3], size_t k0, size_t n,
                                double *q, double *u)
{
    view_frame fo;
    view_frame_of_vec(ar->p, &ar->lr, o, &fo);
    met_stokes(ar->p, &fo, &ar->N[k0], n, q, u);
}

/* The direction of the table's node of zenith cosine uz at azimuth delta
 * from the wind, toward which the facets met are seen. */
static void around_node_dir(const sea_around *ar, double uz, double delta, double o[3])
{
    const double h = sqrt(fmax(1.0 - uz * uz, 0.0)), ca = cos(delta), sa = sin(delta);
    o[0] = h * (ar->cw * ca - ar->sw * sa);
    o[1] = h * (ar->sw * ca + ar->cw * sa);
    o[2] = uz;
}

/* Fills ar->Q and ar->U at the nodes of ar->E (U / sin 2Delta: along the
 * wind and across it, where sin 2Delta = 0, from 1e-4 rad off the axis,
 * where the ratio is its limit to 1e-8), then the ghosts. */
static void around_polar_fill(sea_around *ar)
{
    const size_t n = ar->n;
    enum { NODES = 2 * (SEA_AROUND_HALF + 1) * SEA_AROUND_NW };
    static const double OFF_AXIS = 1e-4;
#pragma omp parallel for schedule(dynamic, 4) if (NODES * n > 64)
    for (int q = 0; q < NODES; q++) {
        const int half = q / ((SEA_AROUND_HALF + 1) * SEA_AROUND_NW);
        const int r = (q / SEA_AROUND_NW) % (SEA_AROUND_HALF + 1), j = q % SEA_AROUND_NW;
        const double x = half == 0 ? -(double)(SEA_AROUND_HALF - r) / SEA_AROUND_HALF
                                   : (double)r / SEA_AROUND_HALF;
        const double uz = x * fabs(x);
        const double delta = acos(sqrt((double)j / (SEA_AROUND_NW - 1)));
        const size_t c = around_cell(half, r, j) * n;
        const int on_axis = j == 0 || j == SEA_AROUND_NW - 1;
        double o[3];
        around_node_dir(ar, uz, delta, o);
        around_polar_direct(ar, o, 0, n, &ar->Q[c], on_axis ? NULL : &ar->U[c]);
        const double d = on_axis ? (j == 0 ? M_PI_2 - OFF_AXIS : OFF_AXIS) : delta;
        if (on_axis) {
            around_node_dir(ar, uz, d, o);
            around_polar_direct(ar, o, 0, n, NULL, &ar->U[c]);
        }
        const double s2d = sin(2.0 * d);
        for (size_t k = 0; k < n; k++)
            ar->U[c + k] /= s2d;
    }
    around_ghosts(ar->Q, n);
    around_ghosts(ar->U, n);
}

/* The facets met toward o in the sea around ar: Q and U of indices k0 ..
 * k0 + n in o's frame, from ar's tables at around_values's stencil sten,
 * or directly where ar is exact.
 * The tables are filled on the first read, under ar's lock, as the
 * optics fill their Fresnel tables: ar is otherwise read-only. */
static void around_polar(const sea_around *ar, const double o[3], const around_stencil_t *sten,
                         size_t k0, size_t n, double *q, double *u)
{
    if (ar->exact) {
        around_polar_direct(ar, o, k0, n, q, u);
        return;
    }
    if (!atomic_load_explicit(&ar->polarised, memory_order_acquire)) {
        sea_around *w = (sea_around *)ar;
        pthread_mutex_lock(&w->polar_lock);
        if (!atomic_load_explicit(&w->polarised, memory_order_relaxed)) {
            around_polar_fill(w);
            atomic_store_explicit(&w->polarised, 1, memory_order_release);
        }
        pthread_mutex_unlock(&w->polar_lock);
    }
    const size_t c0 = sten->c0, na = ar->n;
    const double *wz = sten->wz, *ww = sten->ww;
    const double h = hypot(o[0], o[1]);
    const double ca = h > 0.0 ? (o[0] * ar->cw + o[1] * ar->sw) / h : 1.0;
    const double sa = h > 0.0 ? (o[1] * ar->cw - o[0] * ar->sw) / h : 0.0;
    const double s2 = 2.0 * sa * ca;
    for (int t = 0; t < 2; t++) {
        const double *T = (t == 0 ? ar->Q : ar->U) + k0;
        double *out = t == 0 ? q : u;
        for (size_t k = 0; k < n; k++) {
            double v = 0.0;
            for (int r = 0; r < 4; r++) {
                const double *c = T + (c0 + (size_t)r * SEA_AROUND_COLS) * na + k;
                v += wz[r] * ((ww[0] * c[0] + ww[1] * c[na]) + (ww[2] * c[2 * na] + ww[3] * c[3 * na]));
            }
            out[k] = t == 0 ? v : v * s2;
        }
    }
}

/* cos 2chi and sin 2chi of the angle chi from o's reference e_v toward
 * its e_h to the p axis k x s of light travelling along o (a view) and
 * met by a facet of normal nA (the sea's axes): s the normal to the plane
 * of incidence, nA x o. */
static void incidence_angle(const double o[3], const double nA[3], double *c2, double *s2)
{
    double s[3] = { nA[1] * o[2] - nA[2] * o[1], nA[2] * o[0] - nA[0] * o[2],
                    nA[0] * o[1] - nA[1] * o[0] };
    const double ls = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (!(ls > 1e-12)) { /* normal incidence: no plane, nothing rotates */
        *c2 = 1.0;
        *s2 = 0.0;
        return;
    }
    for (int i = 0; i < 3; i++)
        s[i] /= ls;
    const double a[3] = { o[1] * s[2] - o[2] * s[1], o[2] * s[0] - o[0] * s[2],
                          o[0] * s[1] - o[1] * s[0] };
    /* o's frame as view_frame_of_vec makes it */
    const double h = sqrt(o[0] * o[0] + o[1] * o[1]);
    const double cp = h > 0.0 ? o[0] / h : 1.0, sp = h > 0.0 ? o[1] / h : 0.0;
    const double ca = -o[2] * (a[0] * cp + a[1] * sp) + a[2] * h;
    const double sa = -a[0] * sp + a[1] * cp;
    sea_polar_plane_angle(ca, sa, c2, s2);
}

/* The reflection of air -> water at cos psi c in the (p, s) axes k x s
 * before and after it (r_p = -r_s at normal incidence): R_s, R_p and
 * Re(r_p conj(r_s)), what becomes of U.  One complex root, no complex
 * division: r_p conj(r_s) = (N^2 c - w)(c + w)* conj(...) / (|N^2 c + w|^2
 * |c + w|^2) written out. */
static void fresnel_ps(double c, double complex N, double *Rs, double *Rp, double *ps)
{
    const double complex N2 = N * N, w = csqrt(N2 - 1.0 + c * c);
    const double complex ns = c - w, ds = c + w, np = N2 * c - w, dp = N2 * c + w;
    const double ds2 = creal(ds) * creal(ds) + cimag(ds) * cimag(ds);
    const double dp2 = creal(dp) * creal(dp) + cimag(dp) * cimag(dp);
    const double ns2 = creal(ns) * creal(ns) + cimag(ns) * cimag(ns);
    const double np2 = creal(np) * creal(np) + cimag(np) * cimag(np);
    *Rs = ds2 > 0.0 ? fmin(ns2 / ds2, 1.0) : 1.0;
    *Rp = dp2 > 0.0 ? fmin(np2 / dp2, 1.0) : 1.0;
    /* (np / dp) conj(ns / ds) = np conj(ns) conj(dp) ds / (|dp|^2 |ds|^2) */
    const double complex z = np * conj(ns) * conj(dp) * ds;
    *ps = ds2 > 0.0 && dp2 > 0.0 ? creal(z) / (dp2 * ds2) : -1.0;
}

typedef struct {
    const sea_optics *p;
    const sea_slope_stats *met; /* the facets met's: ar's, or st's */
    const view_frame *f;
    double L_in, w_tot;
    const emis_ctx *ec;
    double complex N[SEA_MULTI_BLOCK];
    size_t n, k0;
    int R;
    const sea_around *ar;
    node_sums sums; /* dq, du */
} polar_sums;

static void polar_node(void *ctx, double w_j, double w, double gX, double gY)
{
    polar_sums *c = ctx;
    const view_frame *f = c->f;
    const size_t n = c->n;
    const double cpsi = cos_psi_of(f, gX, gY);
    if (!(cpsi > 0.0))
        return;
    double g[3];
    mirror_of_node(f, gX, gY, cpsi, g);
    const double o[3] = { -g[0], -g[1], -g[2] };
    double eB[SEA_MULTI_BLOCK], qB[SEA_MULTI_BLOCK], uB[SEA_MULTI_BLOCK], P;
    if (c->ar != NULL) {
        around_stencil_t sten;
        double pinf;
        around_values(c->ar, o, c->k0, n, c->ec, NULL, eB, NULL, &pinf, &sten);
        P = around_chance(pinf, o, c->L_in, w_j, w, c->w_tot);
        if (P == 0.0)
            return;
        around_polar(c->ar, o, &sten, c->k0, n, qB, uB);
    } else {
        P = hit_chance(c->met, g, c->L_in, w_j * w / c->w_tot);
        if (P == 0.0)
            return;
        view_frame fo;
        view_frame_of_vec(c->p, c->met, o, &fo);
        if (!emis_multi_rec(c->p, c->met, &fo, 0.0, c->ec, n, c->R - 1, NULL, NULL, c->k0, NULL,
                            NULL, eB, NULL))
            return;
        met_stokes(c->p, &fo, c->N, n, qB, uB);
    }
    /* B's (Q, U) into A's axes (ci, si), A's outgoing axes into the
     * sensor's frame (c2, s2) */
    double nA[3], ci, si, c2, s2;
    frame_vec_to_global(f, -gX, -gY, 1.0, nA);
    incidence_angle(o, nA, &ci, &si);
    sea_polar_plane_angle(f->sin_th + gX * f->cos_th, -gY, &c2, &s2);
    const double wP = w * P;
    for (size_t k = 0; k < n; k++) {
        double Rs, Rp, ps;
        fresnel_ps(cpsi, c->N[k], &Rs, &Rp, &ps);
        const double qin = qB[k] * ci + uB[k] * si, uin = uB[k] * ci - qB[k] * si;
        const double Qa = 0.5 * (Rp - Rs) * eB[k] + 0.5 * (Rs + Rp) * qin;
        const double Ua = ps * uin;
        c->sums.acc[0][k] += wP * (Qa * c2 - Ua * s2);
        c->sums.acc[1][k] += wP * (Qa * s2 + Ua * c2);
    }
}

static void polar_cross(void *ctx, double w_j, double den)
{
    node_sums_fold(&((polar_sums *)ctx)->sums, w_j, den);
}

/* The second hits' Q and U of the indices ec[0..n) (k0 onward in ar's
 * tables) over walk_second_hits's nodes (at ar's orders in the sea around
 * ar): each mirror ray g of a facet A seen from f meets the sea with the
 * chance P, and the facets B met toward o = -g send their emission
 * E_(R-1) (unpolarised) and their one-hit polarisation (Q_B, U_B in o's
 * frame) back to A, whose Mueller matrix in its (p, s) axes reflects them
 * as
 *     Q' = (R_p - R_s)/2 P E_B + (R_s + R_p)/2 P Q_B',  U' = Re(r_p r_s*) P U_B',
 * (Q_B', U_B') turned into A's axes, per unit contrast between the sea's
 * blackbody and a uniform sky; turned into the sensor's frame. */
static void polar_hits_block(const sea_optics *p, const sea_slope_stats *st, const view_frame *f,
                             double L_in, const emis_ctx *ec, size_t n, int R, fixed_rule a,
                             double w_tot, size_t k0, const sea_around *ar, double *dq,
                             double *du)
{
    polar_sums c = { .p = p, .met = ar != NULL ? &ar->lr : st, .f = f, .L_in = L_in,
                     .w_tot = w_tot, .ec = ec, .n = n, .k0 = k0, .R = R, .ar = ar,
                     .sums = { n, { dq, du }, { { 0.0 } } } };
    for (size_t k = 0; k < n; k++) {
        c.N[k] = ec[k].N;
        dq[k] = du[k] = 0.0;
    }
    walk_second_hits(p, f, a, ar != NULL ? ar->split_scale : SEA_MULTI_SPLIT_SCALE,
                     ar != NULL ? ar->split_min : SEA_MULTI_SPLIT_MIN,
                     ar != NULL ? ar->cross_scale : SEA_MULTI_CROSS_SCALE,
                     ar != NULL ? ar->cross_min : SEA_MULTI_CROSS_MIN, polar_node, polar_cross, &c);
}

sea_status sea_optics_polar_hits(const sea_optics *p, sea_emis_method method,
                                 const sea_emis_rule *rule, const double complex *N, size_t n,
                                 const sea_slope_stats *st, sea_dir v, int reflections,
                                 const sea_around *ar, double *dq, double *du, sea_error *err)
{
    sea_status s;
    if (ar != NULL)
        reflections = ar->reflections;
    if (reflections < 2 || reflections > SEA_REFLECTIONS_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "the second hits' polarisation: reflections %d "
                        "(allowed: 2..%d)", reflections, SEA_REFLECTIONS_MAX);
    if (ar != NULL && ar->n != n)
        return sea_fail(err, SEA_ERR_DOMAIN, "the sea around was made for %zu indices; asked "
                        "for %zu", ar->n, n);
    if ((s = check_rule(rule, err)) != SEA_OK)
        return s;
    if ((s = check_dir(v, "view", err)) != SEA_OK || (s = sea_slope_stats_check(st, err)) != SEA_OK)
        return s;
    for (size_t k = 0; k < n; k++)
        dq[k] = du[k] = 0.0;
    view_frame f;
    view_frame_init(p, st, v, &f);
    const fixed_rule a = fixed_rule_of(&f, method, rule);
    fixed_nodes nd;
    nodes_fixed(p, &f, a, &nd);
    if (nd.zero)
        return SEA_OK;
    /* the weight's integral, as emis_multi_rec's */
    double w_tot = 1.0;
    if (!nd.plain) {
        double t_lo, t_hi, sum = 0.0;
        view_window(&f, a.t_cut, &t_lo, &t_hi);
        for (int i = 0; i < nd.n_i; i++)
            sum += nd.w_i[i] > 0.0 ? nd.w_i[i] : 0.0;
        w_tot = 0.5 * (t_hi - t_lo) * sum;
    }
    const double L_in = lambda_along(ar != NULL ? &ar->lr : st, v);
    for (size_t k0 = 0; k0 < n; k0 += SEA_MULTI_BLOCK) {
        const size_t m = n - k0 < SEA_MULTI_BLOCK ? n - k0 : SEA_MULTI_BLOCK;
        emis_ctx ec[SEA_MULTI_BLOCK];
        size_t slot = 0;
        for (size_t k = 0; k < m; k++)
            ec[k] = (emis_ctx){ N[k0 + k], fresnel_of(p, N[k0 + k], &slot) };
        polar_hits_block(p, st, &f, L_in, ec, m, reflections, a, w_tot, k0, ar, &dq[k0],
                         &du[k0]);
    }
    return SEA_OK;
}
