/* internal.h - library-internal: marks what the library's objects share with one another
 * but do not export.
 *
 * A declaration marked SEA_INTERNAL links between the objects of libseabake, and into the
 * seabake program and the tests, which link the library statically (Makefile.am), but is not
 * exported from the shared library: it is not part of the installed interface (seabake.h,
 * seabake/exr.h, seabake/preview.h), and a user's program cannot come to depend on it. */
#ifndef SEABAKE_INTERNAL_H
#define SEABAKE_INTERNAL_H

#include <stddef.h>

#include "seabake.h"

#define SEA_INTERNAL __attribute__((visibility("hidden")))

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
/* The AVX2 loops' 4 x 4 transpose: r[m] holds lane m of the four inputs
 * (four loads of four doubles become four vectors of one component each). */
__attribute__((target("avx2"))) static inline void sea_transpose4_avx2(__m256d r[4])
{
    const __m256d l01 = _mm256_unpacklo_pd(r[0], r[1]), h01 = _mm256_unpackhi_pd(r[0], r[1]);
    const __m256d l23 = _mm256_unpacklo_pd(r[2], r[3]), h23 = _mm256_unpackhi_pd(r[2], r[3]);
    r[0] = _mm256_permute2f128_pd(l01, l23, 0x20);
    r[1] = _mm256_permute2f128_pd(h01, h23, 0x20);
    r[2] = _mm256_permute2f128_pd(l01, l23, 0x31);
    r[3] = _mm256_permute2f128_pd(h01, h23, 0x31);
}
#endif

/* waves.c: FFTW's planner is not thread-safe (its execution is): every
 * plan the library makes or destroys holds this lock meanwhile. */
SEA_INTERNAL void sea_fftw_planner_lock(void);
SEA_INTERNAL void sea_fftw_planner_unlock(void);

/* imager.c: the apparent temperature of a radiance as sea_imager_apply
 * computes it, in double (the frame stores floats), for the tests. */
struct sea_imager;
SEA_INTERNAL double sea_imager_temperature(const struct sea_imager *im, double radiance);

/* planck.c: the black body L(lambda, T) = a / expm1(b / T), a and b of lambda. */
SEA_INTERNAL void sea_planck_coefficients(double wavelength, double *a, double *b);

/* optics.c: whether the plan's emissivity runs its AVX2 loops (returns the
 * setting in force: on only where the processor has AVX2), so that the
 * tests compare them with the portable loops. */
struct sea_optics;
SEA_INTERNAL int sea_optics_set_simd(struct sea_optics *p, int on);
/* Whether reflections >= 2 sum the second hits' reflectances and
 * emissivities through the spectral basis of a band's Fresnel tables (on by
 * default; off: each table, for the tests that compare the two). */
SEA_INTERNAL void sea_optics_set_spectral_basis(struct sea_optics *p, int on);
/* The rank of the spectral basis of the block N[0..n) (built if need be), 0
 * when it has none (an index without a table, none within its tolerance,
 * or one that would not halve the lookups); *err (err not NULL): its
 * largest difference from a table's reflectance, measured (NAN: none). */
SEA_INTERNAL int sea_optics_spectral_rank(const struct sea_optics *p, const double complex *N,
                                          size_t n, double *err);
/* optics.c, for polar.c: the nodes of the emissivity's fixed rules
 * (sea_emissivity_n with method SEA_EMIS_AUTO or SEA_EMIS_FAST, or *rule),
 * so that another facet quantity is averaged exactly as the emissivity
 * averages 1 - rho: node q is a facet of slope (gX, gY) in the frame of the
 * view azimuth (X along it, Y to its left), cos psi toward v and weight w
 * (projected area, shadowing and the rule's weights; the weights sum to 1,
 * none when every facet is turned away).  *exact: the emissivity evaluates
 * the Fresnel formula at these nodes, not the plan's table (a facet
 * without slope spread).  At most SEA_FACET_NODES_MAX nodes.  Errors as
 * sea_emissivity_n's, and SEA_ERR_DOMAIN for SEA_EMIS_FULL; reads p. */
typedef struct {
    double gX, gY, cos_psi, w;
} sea_facet_node;
enum { SEA_FACET_NODES_MAX = SEA_EMIS_GL_MAX * SEA_EMIS_GH_MAX };
SEA_INTERNAL sea_status sea_optics_facet_nodes(const struct sea_optics *p, sea_emis_method method,
                                               const sea_emis_rule *rule,
                                               const sea_slope_stats *st, sea_dir v,
                                               sea_facet_node *nodes, size_t *count, int *exact,
                                               sea_error *err);
/* polar.c: cos 2chi and sin 2chi of the direction proportional to a e_v +
 * b e_h of a view's frame (the p axis of a facet of normal n has a = n.e_v,
 * b = n.e_h); (0, 0) when a = b = 0, where nothing is polarised. */
SEA_INTERNAL void sea_polar_plane_angle(double a, double b, double *c2, double *s2);
/* optics.c, for polar.c and model.c: what the second hits add to the
 * Stokes emissivity toward v (seabake-model(7), POLARISATION), Q and U per
 * index in the sensor's frame per unit contrast between the sea's
 * blackbody and a uniform sky, at reflections >= 2 over the split rule
 * sea_emissivity_multi_n's second hits take (with ar, the sea around ar,
 * as sea_emissivity_around_n): the facets met send their emission E_(R-1)
 * and their one-hit polarisation back to the facet seen, whose Mueller
 * matrix reflects both (with ar, at ar's reflections, whatever the
 * argument).  Errors as sea_emissivity_multi_n's; reads p. */
SEA_INTERNAL sea_status sea_optics_polar_hits(const struct sea_optics *p, sea_emis_method method,
                                              const sea_emis_rule *rule, const double complex *N,
                                              size_t n, const sea_slope_stats *st, sea_dir v,
                                              int reflections, const struct sea_around *ar,
                                              double *dq, double *du, sea_error *err);
/* 1 - rho(psi) of index N as the emissivity reads it at a node: the plan's
 * table of N where it has one and exact is 0, else the formula.  Reads p
 * (may build N's table under p's lock). */
SEA_INTERNAL double sea_optics_one_minus_rho(const struct sea_optics *p, double complex N,
                                             int exact, double cos_psi);
/* SEA_EMIS_FULL's adaptive average of nval <= SEA_FACET_VALUES_MAX facet
 * values, fn(gX, gY, cos psi, ctx, vals) in the frame above, one adaptive
 * quadrature each (about 1 ms); errors as sea_emissivity's; reads p. */
enum { SEA_FACET_VALUES_MAX = 4 };
typedef void (*sea_facet_fn)(double gX, double gY, double cos_psi, void *ctx, double *vals);
SEA_INTERNAL sea_status sea_optics_facet_mean_full(const struct sea_optics *p,
                                                   const sea_slope_stats *st, sea_dir v,
                                                   sea_facet_fn fn, void *ctx, int nval,
                                                   double *out, sea_error *err);

/* gridtable.c: the interval [x[i], x[i + 1]] of an increasing x (n >= 2)
 * that holds at, x[i] < at <= x[i + 1] inside, i clamped to [0, n - 2]
 * outside (bisection). */
SEA_INTERNAL size_t sea_interval_of(const double *x, size_t n, double at);

/* Puts the k-th smallest of v[0..m) (k < m) at v[k], smaller-or-equal
 * values before it and greater-or-equal after (as C++ nth_element): Hoare
 * partitions around a median of three, O(m) on average.  One body for the
 * preview's float maps (sea_select_kth_f) and the plan's double ground
 * points (sea_select_kth_d). */
#define SEA_SELECT_KTH(name, T)                                                                \
    static inline void name(T *v, size_t m, size_t k)                                          \
    {                                                                                          \
        size_t lo = 0, hi = m - 1;                                                             \
        while (hi > lo) {                                                                      \
            const size_t mid = lo + (hi - lo) / 2;                                             \
            T a = v[lo], b = v[mid], c = v[hi];                                                \
            const T pivot =                                                                    \
                a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));        \
            size_t i = lo, j = hi;                                                             \
            while (i <= j) {                                                                   \
                while (v[i] < pivot)                                                           \
                    i++;                                                                       \
                while (v[j] > pivot)                                                           \
                    j--;                                                                       \
                if (i <= j) {                                                                  \
                    const T t = v[i];                                                          \
                    v[i] = v[j];                                                               \
                    v[j] = t;                                                                  \
                    i++;                                                                       \
                    if (j == 0)                                                                \
                        break;                                                                 \
                    j--;                                                                       \
                }                                                                              \
            }                                                                                  \
            /* now v[lo..j] <= pivot <= v[i..hi], and j < i */                                 \
            if (k <= j)                                                                        \
                hi = j;                                                                        \
            else if (k >= i)                                                                   \
                lo = i;                                                                        \
            else                                                                               \
                return; /* j < k < i: v[k] == pivot */                                         \
        }                                                                                      \
    }
SEA_SELECT_KTH(sea_select_kth_f, float)
SEA_SELECT_KTH(sea_select_kth_d, double)

/* Catmull-Rom weights of the four nodes around the fraction f
 * in [0, 1] between the middle two (the correlated function's table and
 * twoscale.c's read them). */
static inline void sea_catmull_rom(double f, double w[4])
{
    const double f2 = f * f, f3 = f2 * f;
    w[0] = 0.5 * (-f3 + 2.0 * f2 - f);
    w[1] = 0.5 * (3.0 * f3 - 5.0 * f2 + 2.0);
    w[2] = 0.5 * (-3.0 * f3 + 4.0 * f2 + f);
    w[3] = 0.5 * (f3 - f2);
}

/* tempfile.c: seabake's temporaries and the marker that proves them its
 * own (see there).  SEA_TEMP_MARKER is the marker's file name inside a
 * temporary directory. */
#define SEA_TEMP_MARKER ".seabake-temporary"
/* Writes the marker (kind, target: tlen bytes, this pid and host) into dir,
 * O_EXCL and O_NOFOLLOW; 0 or an errno. */
SEA_INTERNAL int sea_temp_marker_write(const char *dir, const char *kind, const char *target,
                                       size_t tlen);
/* 1 if dir holds a marker of this kind and target that this user wrote. */
SEA_INTERNAL int sea_temp_marker_is(const char *dir, const char *kind, const char *target,
                                    size_t tlen);
/* Removes dir's marker, if any. */
SEA_INTERNAL void sea_temp_marker_remove(const char *dir);
/* A file written atomically: PATH.tmp.XXXXXX (dir, flock'ed through
 * dir_fd while it lives) holding the marker (kind "file", target PATH's
 * name) and the data, dir/NAME (data). */
typedef struct sea_temp_file {
    char *dir, *data;
    int dir_fd;
} sea_temp_file;
/* Creates the temporary for path and opens its data for writing (O_EXCL,
 * mode 0666 less the umask) into *fd, which the caller owns and closes,
 * its data synced, before the commit.  0 or an errno (t then holds
 * nothing). */
SEA_INTERNAL int sea_temp_open(sea_temp_file *t, const char *path, int *fd);
/* Renames the data onto path and removes the temporary, whatever the
 * rename did; 0 or rename's errno. */
SEA_INTERNAL int sea_temp_commit(sea_temp_file *t, const char *path);
/* Removes the temporary (nothing reaches path); safe on one committed,
 * aborted or never opened. */
SEA_INTERNAL void sea_temp_abort(sea_temp_file *t);
/* Removes, in dir, the file temporaries of dead processes (marker of kind
 * "file" by this user, flock free) whose target is prefix, or prefix then
 * '.' or '_' (an empty prefix: every one), calling removed (may be NULL)
 * with each one's path; returns how many.  Nothing else is touched: a
 * temporary that holds more than its data and marker stays. */
SEA_INTERNAL size_t sea_temp_clean(const char *dir, const char *prefix,
                                   void (*removed)(void *ctx, const char *path), void *ctx);

/* tempfile.c, paths: "dir/name" and the directory part of path ("." for a
 * bare name), malloc'ed (NULL without memory); sea_remove_tree removes a
 * directory tree that seabake made, best effort, following no link
 * (0 or -1). */
SEA_INTERNAL char *sea_path_join(const char *dir, const char *name);
SEA_INTERNAL char *sea_path_parent(const char *path);
SEA_INTERNAL int sea_remove_tree(const char *path);

/* The text of exporters/povray/seabake.inc and of
 * exporters/blender/seabake_import.py, NUL-terminated (the generated
 * povray_inc.c and blender_py.c; the Blender script's public face is
 * sea_blender_script(): a function, so that the text's size is no part of
 * the library's interface). */
SEA_INTERNAL extern const char sea_pov_include_text[];
SEA_INTERNAL extern const char sea_blender_import_text[];

/* waves.c: SEA_ERR_DOMAIN "time T s is outside [-1000000000, 1000000000] s" unless
 * |t| <= SEA_TIME_MAX (NaN included). */
SEA_INTERNAL sea_status sea_time_check(double t, sea_error *err);

/* shadow.c, for the tests: the largest difference between G's polynomials
 * compiled in (src/physics/shadow_g_table.h) and those the code computes now (0
 * where the table was made; INFINITY when out of memory). */
SEA_INTERNAL double sea_shadow_g_table_drift(void);
/* shadow.c: sea_shadow_visible and sea_shadow_hidden of (mu, m, s) at
 * once, from one G (identical values). */
SEA_INTERNAL void sea_shadow_split(double mu, double m, double s, double *visible,
                                   double *hidden);
/* shadow.c: ln sea_shadow_visible(mu, m, s), finite where the moment itself
 * underflows (facets turned away by 38 standard deviations and more: the
 * few that face mu); -inf where no facet faces it (s = 0, m >= mu). */
SEA_INTERNAL double sea_shadow_log_visible(double mu, double m, double s);
/* shadow.c: sea_shadow_correlated(z, t) for many t at one z, the same
 * bits: the interpolation's rows in z found once (sea_shadow_correlated_z),
 * then each t's value (sea_shadow_correlated_zt). */
typedef struct {
    int row[4];
    double wa[4];
} sea_cs_rows;
typedef struct {
    double z;
    int past; /* z beyond the table (or NaN): C = 1 */
    sea_cs_rows r;
} sea_cs_z;
SEA_INTERNAL void sea_shadow_correlated_z(double z, sea_cs_z *h);
SEA_INTERNAL double sea_shadow_correlated_zt(const sea_cs_z *h, double t);
/* shadow.c: w[k] *= sea_shadow_correlated(z, mid + half x[k]) for k < n,
 * the same values (to rounding: the interpolation's rows in z are combined
 * once), in AVX2 when avx2 is non-zero and the CPU has it (the same bits
 * as without). */
SEA_INTERNAL void sea_shadow_correlated_scale(double z, double mid, double half, const double *x,
                                              int n, double *w, int avx2);

/* optics.c, the sun's disc: the probability of N(mu, Cu) over the disc
 * |u| <= radius by quadrature, and the mean over it of a Gaussian density
 * of precision Q centred at mu, relative to its value at 0, by the
 * mean-value series summed to convergence; sea_reflectivity_disc_n
 * chooses. */
SEA_INTERNAL double sea_disc_mass(const struct sea_optics *p, const double Cu[2][2],
                                  const double mu[2], double radius, int nodes);
SEA_INTERNAL double sea_disc_series(const double Q[2][2], const double mu[2], double radius);

/* multires.c, the render's rays ordered across pixel rows: what a pixel's
 * top row of rays tells the pixel above it (the rays' slopes d_z / |d_h|,
 * map directions, and the horizontal distances where they met the surface,
 * -1 for none, on the surface of blend).  sea_multires_pixel with below
 * the hint of pixel (i, j + 1) (or NULL) and top (or NULL) filled for
 * pixel (i, j - 1): the same first hits (a ray of pixel (i, j) that the
 * ordering shows to be above one of below's rays until that one's hit
 * starts its march there), so the same sample but where a ray grazes a
 * crest and the march's samples decide. */
typedef struct {
    int n;
    sea_level_blend blend;
    double k[8], ux[8], uy[8], s[8];
} sea_multires_hint;
/* multires.c: sea_multires_frame_alloc, but the frame's surfaces keep no
 * bounds of their finest cells (8 bytes a facet, 200 MB at six levels of
 * 2048^2) and compute them from the facets as the march asks, bit for bit
 * the same: the same answers, 6 % slower (a bake's frames, where the
 * bounds would take more than 64 MB: bake.c). */
SEA_INTERNAL sea_status sea_multires_frame_alloc_lean(const sea_multires *mr, double t,
                                                      sea_progress_fn progress, void *ctx,
                                                      sea_multires_frame **out, sea_error *err);
/* multires.c, for the tests: where a blend of one level reads that
 * level's heightfield alone (its window at full weight), the heights,
 * gradients, moments and bounds against the chain's sums, at n points of
 * each high-resolution level: the number of points where any differs in
 * any bit (0), and in *checked the points compared. */
SEA_INTERNAL size_t sea_multires_alone_check(const sea_multires_frame *f, size_t n,
                                             size_t *checked);
/* multires.c: turns the rows of level `level`'s facets (a
 * high-resolution level of f) upside down in place and returns them: north
 * first after one call, south first again after the next.  While they are
 * north first nothing may read f's surfaces (the bake hands them to its
 * caller so). */
SEA_INTERNAL sea_facet *sea_multires_frame_flip_rows(sea_multires_frame *f, int level);
SEA_INTERNAL void sea_multires_pixel_hinted(const sea_multires_frame *f, int i, int j,
                                            const sea_multires_hint *below,
                                            sea_multires_hint *top, sea_multires_sample *out);

/* view.c, for the tests: with lean non-zero a bake of r computes the
 * finest bounds of its surfaces from the nodes as the rays ask, as it does
 * when storing them would take more than BAKE_STORED_BOUNDS_MAX (bake.c);
 * the same bounds, bit for bit. */
SEA_INTERNAL void sea_view_set_bake_lean(sea_view *r, int lean);
SEA_INTERNAL int sea_view_bake_lean(const sea_view *r);
/* view.c, for the bake: sea_view_render_frame from the frame f of r's
 * multiresolution sea at time t (sea_multires_frame_alloc of
 * sea_view_multires(r)), not one of its own: the same pixels. */
SEA_INTERNAL sea_status sea_view_render_frame_in(const sea_view *r, const sea_multires_frame *f,
                                            double t, sea_image *img, sea_error *err);
/* SEA_ERR_DOMAIN unless img is the scene's size (sea_view_render_rows' check). */
SEA_INTERNAL sea_status sea_view_check_image(const sea_view *r, const sea_image *img,
                                               sea_error *err);

/* camera.c, for the render's Stokes planes: the angle psi from the image's
 * up axis (across the ray through image point (u, v), +psi toward the
 * image's right) to e_v, the vertical of the view frame (seabake.h,
 * POLARISATION) at the sea point of vertical `normal` seen from obs (its
 * local direction to the sensor), as cos 2psi and sin 2psi; (1, 0) where
 * e_v has no component across the ray.  Pure. */
SEA_INTERNAL void sea_camera_stokes_frame(const sea_camera *c, double u, double v,
                                          const double normal[3], sea_dir obs, double *cos_2psi,
                                          double *sin_2psi);
/* camera.c, for the multiresolution plan.  Where the ray through image
 * point (u, v) meets the sea: 1 and its map point (x, y) as
 * sea_camera_pixel gives it, or 0 (a miss; x and y then unspecified). */
SEA_INTERNAL int sea_camera_corner(const sea_camera *c, double u, double v, double *x, double *y);
/* sea_camera_pixel's hit, x, y, range, normal and footprint (bit for bit;
 * obs and ray are left 0) with the four corners of the pixel already
 * found: (px[k], py[k]) the sea_camera_corner points of (u, v) + (-1/2,
 * -1/2), (1/2, -1/2), (1/2, 1/2), (-1/2, 1/2), k = 0..3, and corners_hit 1
 * when all four met the sea (else px, py are not read).  Neighbouring
 * pixels share corners, so an image's corners can be found once each. */
SEA_INTERNAL void sea_camera_pixel_cornered(const sea_camera *c, double u, double v,
                                            const double px[4], const double py[4],
                                            int corners_hit, sea_pixel_geom *g);

#endif /* SEABAKE_INTERNAL_H */
