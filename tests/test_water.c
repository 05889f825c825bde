/* test_water.c - optical constants, Fresnel and Planck. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "unit.h"

static double complex index_at(sea_water_table t, double salinity, double wl_um)
{
    sea_water *w = NULL;
    double complex N = 0;
    CU_ASSERT_FATAL(sea_water_alloc(t, salinity, &w, NULL) == SEA_OK);
    CU_ASSERT(sea_water_index(w, wl_um * 1e-6, &N, NULL) == SEA_OK);
    sea_water_free(w);
    return N;
}

/* Table rows are reproduced exactly (same digits as the CSV, data/README.md
 * hand checks): tolerance 1e-12, rounding only. */
static void test_hale_querry_rows(void)
{
    double complex N = index_at(SEA_WATER_HALE_QUERRY, 0.0, 4.0);
    ASSERT_REL(creal(N), 1.351, 1e-12, 0);
    ASSERT_REL(cimag(N), 0.00460, 1e-12, 0);
    N = index_at(SEA_WATER_HALE_QUERRY, 0.0, 11.0);
    ASSERT_REL(creal(N), 1.153, 1e-12, 0);
    ASSERT_REL(cimag(N), 0.0968, 1e-12, 0);
}

/* Segelstein's n is about 0.02 below Hale & Querry in 3-13 um and k agrees
 * (data/README.md): |dn| < 0.035, k within 25 % (band edges differ most). */
static void test_segelstein_vs_hale_querry(void)
{
    const double wl[] = { 3.7, 4.0, 8.5, 10.0, 11.0, 12.0 };
    for (size_t i = 0; i < sizeof wl / sizeof wl[0]; i++) {
        double complex a = index_at(SEA_WATER_HALE_QUERRY, 0.0, wl[i]);
        double complex b = index_at(SEA_WATER_SEGELSTEIN, 0.0, wl[i]);
        CU_ASSERT(fabs(creal(a) - creal(b)) < 0.035);
        ASSERT_REL(cimag(b), cimag(a), 0.25, 0);
    }
}

/* Linear interpolation in wavenumber: halfway in wavenumber between the
 * 4.0 and 4.1 um rows the index is the mean of the rows (1e-12). */
static void test_interpolation_in_wavenumber(void)
{
    double complex a = index_at(SEA_WATER_HALE_QUERRY, 0.0, 4.0);
    double complex b = index_at(SEA_WATER_HALE_QUERRY, 0.0, 4.1);
    double nu_mid = 0.5 * (1.0 / 4.0 + 1.0 / 4.1);
    double complex m = index_at(SEA_WATER_HALE_QUERRY, 0.0, 1.0 / nu_mid);
    ASSERT_REL(creal(m), 0.5 * (creal(a) + creal(b)), 1e-12, 0);
    ASSERT_REL(cimag(m), 0.5 * (cimag(a) + cimag(b)), 1e-12, 0);
}

/* The correction scales linearly with salinity (1e-12) and is small: under
 * 0.03 in n across the band (Pinkley & Williams: a few 1e-3 to 1e-2). */
static void test_salinity_correction(void)
{
    const double wl[] = { 3.0, 4.0, 8.0, 10.0, 12.5 };
    for (size_t i = 0; i < sizeof wl / sizeof wl[0]; i++) {
        double complex p = index_at(SEA_WATER_HALE_QUERRY, 0.0, wl[i]);
        double complex h = index_at(SEA_WATER_HALE_QUERRY, 17.5, wl[i]);
        double complex s = index_at(SEA_WATER_HALE_QUERRY, 35.0, wl[i]);
        ASSERT_ABS(creal(s - p), 2.0 * creal(h - p), 1e-12);
        ASSERT_ABS(cimag(s - p), 2.0 * cimag(h - p), 1e-12);
        CU_ASSERT(fabs(creal(s - p)) < 0.03);
        CU_ASSERT(cimag(s) >= 0.0);
    }
    /* At 10 um the sea-water correction is not zero. */
    double complex p = index_at(SEA_WATER_HALE_QUERRY, 0.0, 10.0);
    double complex s = index_at(SEA_WATER_HALE_QUERRY, 35.0, 10.0);
    CU_ASSERT(fabs(creal(s - p)) > 1e-4);
}

static void test_out_of_range(void)
{
    sea_water *w = NULL;
    sea_error err = { "" };
    double complex N;
    CU_ASSERT_FATAL(sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL) == SEA_OK);
    CU_ASSERT(sea_water_index(w, 2.0e-6, &N, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "2.4") != NULL);
    CU_ASSERT(sea_water_index(w, 16.0e-6, &N, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "15.5") != NULL);
    double lo, hi;
    sea_water_range(w, &lo, &hi);
    ASSERT_REL(lo, 2.4e-6, 1e-9, 0);
    ASSERT_REL(hi, 15.5e-6, 1e-9, 0);
    sea_water_free(w);
    CU_ASSERT(sea_water_alloc(SEA_WATER_HALE_QUERRY, 50.0, &w, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(w == NULL);
    CU_ASSERT(strstr(err.msg, "45") != NULL);
    CU_ASSERT(sea_water_table_from_name("segelstein") == SEA_WATER_SEGELSTEIN);
    CU_ASSERT(sea_water_table_from_name("nope") == -1);
    sea_water_free(NULL);
}

/* The ends of the range sea_water_range gives are inside it for
 * sea_water_index, and so is the table's last row as a user writes it
 * (15.5 um of Hale & Querry): found by tests/fuzz/fuzz_water.c, the index
 * once tested the wavenumber 1/x, which need not round back. */
static void test_range_ends(void)
{
    static const double salinity[2] = {0.0, 35.0};
    for (int t = 0; t < 2; t++) {
        for (int s = 0; s < 2; s++) {
            sea_water *w = NULL;
            double lo, hi;
            double complex N;
            CU_ASSERT_FATAL(sea_water_alloc((sea_water_table)t, salinity[s], &w, NULL) == SEA_OK);
            sea_water_range(w, &lo, &hi);
            CU_ASSERT(sea_water_index(w, lo, &N, NULL) == SEA_OK);
            CU_ASSERT(sea_water_index(w, hi, &N, NULL) == SEA_OK);
            CU_ASSERT(sea_water_index(w, nextafter(lo, 0.0), &N, NULL) == SEA_ERR_DOMAIN);
            CU_ASSERT(sea_water_index(w, nextafter(hi, 1.0), &N, NULL) == SEA_ERR_DOMAIN);
            sea_water_free(w);
        }
    }
    double complex N = index_at(SEA_WATER_HALE_QUERRY, 0.0, 15.5);
    ASSERT_REL(creal(N), 1.297, 1e-12, 0);
    ASSERT_REL(cimag(N), 0.414, 1e-12, 0);
    N = index_at(SEA_WATER_HALE_QUERRY, 35.0, 15.5);
    CU_ASSERT(creal(N) > 1.2 && creal(N) < 1.4);
}

static char *write_temp(const char *text)
{
    char *path = strdup("/tmp/seabake-test-XXXXXX");
    int fd = mkstemp(path);
    CU_ASSERT_FATAL(fd >= 0);
    CU_ASSERT(write(fd, text, strlen(text)) == (ssize_t)strlen(text));
    close(fd);
    return path;
}

static void expect_load_error(const char *text, sea_status want, const char *needle)
{
    char *path = write_temp(text);
    sea_water *w = NULL;
    sea_error err = { "" };
    CU_ASSERT(sea_water_load(path, 0.0, &w, &err) == want);
    CU_ASSERT(w == NULL);
    if (strstr(err.msg, needle) == NULL)
        fprintf(stderr, "  message '%s' lacks '%s'\n", err.msg, needle);
    CU_ASSERT(strstr(err.msg, needle) != NULL);
    unlink(path);
    free(path);
}

static void test_user_table(void)
{
    char *path = write_temp("# my table\nwavelength_um,n,k\n3.0,1.40,0.01\n5.0,1.30,0.02\n");
    sea_water *w = NULL;
    double complex N;
    CU_ASSERT_FATAL(sea_water_load(path, 0.0, &w, NULL) == SEA_OK);
    CU_ASSERT(sea_water_index(w, 3.0e-6, &N, NULL) == SEA_OK);
    ASSERT_REL(creal(N), 1.40, 1e-12, 0);
    CU_ASSERT(sea_water_index(w, 6.0e-6, &N, NULL) == SEA_ERR_DOMAIN);
    sea_water_free(w);
    unlink(path);
    free(path);

    expect_load_error("lambda,n,k\n3,1.3,0.1\n4,1.3,0.1\n", SEA_ERR_PARSE, ":1: header");
    expect_load_error("wavelength_um,n,k\n3,1.3,0.1\n4,x,0.1\n", SEA_ERR_PARSE, ":3: n: 'x'");
    expect_load_error("wavelength_um,n,k\n3,1.3,0.1\n4,1.3\n", SEA_ERR_PARSE, ":3: 2 fields");
    expect_load_error("wavelength_um,n,k\n3,1.3,0.1\n4,1.3,0.1\n3.5,1.3,0.1\n", SEA_ERR_PARSE,
                      ":4: rows must be strictly monotonic");
    expect_load_error("wavelength_um,n,k\n3,1.3,0.1\n", SEA_ERR_PARSE, "at least two");
    expect_load_error("wavelength_um,n,k\n3,1.3,-0.1\n4,1.3,0.1\n", SEA_ERR_DOMAIN,
                      ":2: k: -0.1 is outside [0, 10]");
    /* What no water is: n below 1 (emissivity 5e-4 at 80 deg) or a k whose
     * square overflows Fresnel's N^2, refused at their line. */
    expect_load_error("wavelength_um,n,k\n3,1.3,0.1\n4,0.31,0.1\n", SEA_ERR_DOMAIN,
                      ":3: n: 0.31 is outside [1, 3]");
    expect_load_error("wavelength_um,n,k\n3,1.3,9.9e304\n4,1.3,0.1\n", SEA_ERR_DOMAIN,
                      ":2: k: 9.9e+304 is outside [0, 10]");
    sea_water *w2 = NULL;
    sea_error err = { "" };
    CU_ASSERT(sea_water_load("/nonexistent/table.csv", 0.0, &w2, &err) == SEA_ERR_IO);
    CU_ASSERT(strstr(err.msg, "/nonexistent/table.csv") != NULL);
}

/* The built-in tables are parsed once per process and copied to every
 * caller (water.c): each caller's indices are those of a fresh parse of
 * the same CSV file (sea_water_load, which parses every time) bit for bit,
 * at 997 wavelengths over the table's range, the first allocation and the
 * later ones alike; and 17 allocations on every thread at once (with the
 * sea-water correction, cached too) all give the same values bit for bit. */
static void test_builtin_parsed_once(void)
{
    static const struct {
        sea_water_table t;
        const char *file;
    } tabs[] = { { SEA_WATER_HALE_QUERRY, "water_nk_hale_querry.csv" },
                 { SEA_WATER_SEGELSTEIN, "water_nk_segelstein.csv" } };
    enum { NW = 997, NT = 16 };
    for (size_t k = 0; k < sizeof tabs / sizeof tabs[0]; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/data/%s", SEA_TOP_SRCDIR, tabs[k].file);
        sea_water *w[3] = { NULL, NULL, NULL };
        CU_ASSERT_FATAL(sea_water_alloc(tabs[k].t, 0.0, &w[0], NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_water_alloc(tabs[k].t, 0.0, &w[1], NULL) == SEA_OK);
        CU_ASSERT_FATAL(sea_water_load(path, 0.0, &w[2], NULL) == SEA_OK);
        double lo, hi;
        sea_water_range(w[2], &lo, &hi);
        int mismatches = 0;
        for (int i = 0; i < NW; i++) {
            const double wl = lo + (hi - lo) * i / (NW - 1);
            double complex N[3];
            for (int m = 0; m < 3; m++)
                CU_ASSERT(sea_water_index(w[m], wl, &N[m], NULL) == SEA_OK);
            mismatches += memcmp(&N[0], &N[2], sizeof N[0]) != 0;
            mismatches += memcmp(&N[1], &N[2], sizeof N[0]) != 0;
        }
        CU_ASSERT_EQUAL(mismatches, 0);
        for (int m = 0; m < 3; m++)
            sea_water_free(w[m]);
    }
    static double complex seq[NW], par[NT][NW];
    int failures = 0;
#pragma omp parallel for schedule(static, 1) reduction(+ : failures)
    for (int t = -1; t < NT; t++) {
        /* t = -1: the reference row, allocated beside the others */
        sea_water *w = NULL;
        double complex *row = t < 0 ? seq : par[t];
        const sea_status st = sea_water_alloc(SEA_WATER_HALE_QUERRY, 35.0, &w, NULL);
        failures += st != SEA_OK;
        for (int i = 0; i < NW && st == SEA_OK; i++)
            failures += sea_water_index(w, (2.5 + 12.5 * i / (NW - 1)) * 1e-6, &row[i], NULL) !=
                        SEA_OK;
        sea_water_free(w);
    }
    CU_ASSERT_EQUAL(failures, 0);
    int mismatches = 0;
    for (int t = 0; t < NT; t++)
        mismatches += memcmp(par[t], seq, sizeof seq) != 0;
    CU_ASSERT_EQUAL(mismatches, 0);
}

/* Normal incidence: rho = ((n-1)^2 + k^2)/((n+1)^2 + k^2) (closed form, 1e-14). */
/* A table whose n is within bounds can leave them with the sea-water
 * correction (n = 1.0 at 15.5 um, dn = -0.018 at 35 g/kg): refused at load
 * time, naming the salinity, and accepted for pure water.  Found by
 * tests/fuzz/fuzz_water.c (the index gave n = 0.984). */
static void test_corrected_bounds(void)
{
    char *path = write_temp("wavelength_um,n,k\n2.4,1.279,9.56E-4\n15.5,1.0,0.414\n");
    sea_water *w = NULL;
    sea_error err = { "" };
    CU_ASSERT(sea_water_load(path, 35.0, &w, &err) == SEA_ERR_DOMAIN);
    CU_ASSERT(w == NULL);
    CU_ASSERT(strstr(err.msg, "salinity 35") != NULL);
    CU_ASSERT(strstr(err.msg, "15.5 um") != NULL);
    CU_ASSERT(sea_water_load(path, 0.0, &w, &err) == SEA_OK);
    sea_water_free(w);
    unlink(path);
    free(path);
    /* A wavelength whose wavenumber overflows (1e6 / 2e-307 um), or a
     * wavenumber whose wavelength does: refused (found by
     * tests/fuzz/fuzz_water.c: the range's shortest wavelength was 0). */
    expect_load_error("wavelength_um,n,k\n2,1.279,6E-4\n2.2250738585072014e-307,1.2,0\n",
                      SEA_ERR_DOMAIN, "wavelength_um");
    expect_load_error("wavenumber_cm1,n,k\n1000,1.279,6E-4\n1e308,1.2,0\n", SEA_ERR_DOMAIN,
                      "wavenumber_cm1");
    /* The shipped tables stay within the bounds at every salinity. */
    for (int t = 0; t < 2; t++) {
        CU_ASSERT(sea_water_alloc((sea_water_table)t, SEA_SALINITY_MAX, &w, NULL) == SEA_OK);
        sea_water_free(w);
    }
}

static void test_fresnel_normal(void)
{
    const double complex N = 1.351 + 0.0046 * I;
    const double n = creal(N), k = cimag(N);
    const double want = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    ASSERT_REL(sea_fresnel_unpolarized(1.0, N), want, 1e-14, 0);
    ASSERT_ABS(sea_fresnel_unpolarized(0.0, N), 1.0, 1e-15);
    /* Never above 1: beyond the critical angle of n < 1 (total reflection)
     * the formula rounds to 1 + 2e-16, which made an emissivity -2.2e-16. */
    for (int i = 0; i <= 900; i++) {
        const double rho = sea_fresnel_unpolarized(cos(i * M_PI / 1800.0), 0.474261 + 0.0 * I);
        CU_ASSERT(rho >= 0.0 && rho <= 1.0);
    }
}

/* k = 0: the complex formula reduces to Eq 1 (sin/tan form), 1e-13. */
static void test_fresnel_real_index(void)
{
    const double n = 1.33;
    const double psis[] = { 0.1, 0.6174, 1.0, 1.4 };
    for (size_t i = 0; i < 4; i++) {
        double ti = psis[i], tt = asin(sin(ti) / n);
        double s = sin(ti - tt) / sin(ti + tt), t = tan(ti - tt) / tan(ti + tt);
        ASSERT_REL(sea_fresnel_unpolarized(cos(ti), n + 0.0 * I), 0.5 * (s * s + t * t), 1e-13, 0);
    }
}

/* Against the CODATA radiation constants c1L = 1.191042972e-16 W m^2 sr^-1,
 * c2 = 1.438776877e-2 m K, given to 10 digits (relative 3e-10); the
 * exponent c2/(lambda T) <= 19 here amplifies that to 6e-9, so 2e-8.  The
 * round trip holds to 1e-12. */
static void test_planck(void)
{
    const double wl[] = { 3.0e-6, 4.0e-6, 10.0e-6, 12.0e-6 };
    const double T[] = { 250.0, 288.0, 300.0, 5778.0 };
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double L = sea_planck_radiance(wl[i], T[j]);
            double want = 1.191042972e-16 / pow(wl[i], 5) / expm1(1.438776877e-2 / (wl[i] * T[j]));
            ASSERT_REL(L, want, 2e-8, 0);
            ASSERT_REL(sea_planck_brightness_temperature(wl[i], L), T[j], 1e-12, 0);
            /* dL/dT against a central difference of step h = 1e-4 T: its
             * truncation error, about (h/T)^2 x^2 / 6 with x = hc/(lambda k T)
             * up to 19 here, stays below 1e-6 relative */
            const double h = 1e-4 * T[j];
            const double fd = (sea_planck_radiance(wl[i], T[j] + h) -
                               sea_planck_radiance(wl[i], T[j] - h)) / (2.0 * h);
            ASSERT_REL(sea_planck_radiance_dT(wl[i], T[j]), fd, 1e-5, 0);
        }
    /* Textbook: 9.92 W m^-2 sr^-1 um^-1 at 10 um, 300 K. */
    ASSERT_REL(sea_planck_radiance(10e-6, 300.0) * 1e-6, 9.92, 1e-3, 0);
}

int test_water_register(void)
{
    CU_pSuite s = CU_add_suite("water", NULL, NULL);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "Hale & Querry rows", test_hale_querry_rows) ||
           !CU_add_test(s, "Segelstein vs Hale & Querry", test_segelstein_vs_hale_querry) ||
           !CU_add_test(s, "interpolation in wavenumber", test_interpolation_in_wavenumber) ||
           !CU_add_test(s, "salinity correction", test_salinity_correction) ||
           !CU_add_test(s, "out of range", test_out_of_range) ||
           !CU_add_test(s, "the range's ends are in range", test_range_ends) ||
           !CU_add_test(s, "user table and its errors", test_user_table) ||
           !CU_add_test(s, "built-in tables parsed once, copied alike",
                        test_builtin_parsed_once) ||
           !CU_add_test(s, "bounds after the sea-water correction", test_corrected_bounds) ||
           !CU_add_test(s, "Fresnel normal incidence", test_fresnel_normal) ||
           !CU_add_test(s, "Fresnel real index = Eq 1", test_fresnel_real_index) ||
           !CU_add_test(s, "Planck and brightness temperature", test_planck);
}
