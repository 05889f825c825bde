/* fuzz_water.c - libFuzzer target: the water optical-constant table loader
 * (sea_water_load) on arbitrary CSV text, then lookups across the table it
 * accepted.  The first byte picks the salinity (0, 35 or 45 g/kg: with
 * salinity the Pinkley & Williams correction is intersected with the
 * table); the rest is the file. */
#include <math.h>

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const double salinity[3] = {0.0, 35.0, SEA_SALINITY_MAX};
    char path[128];
    if (size < 1)
        return 0;
    double s = salinity[data[0] % 3];
    fuzz_write("water.csv", data + 1, size - 1, path, sizeof path);
    sea_error err = {{0}};
    sea_water *w = NULL;
    sea_status st = sea_water_load(path, s, &w, &err);
    fuzz_check_error(st, &err);
    if (st != SEA_OK) {
        FUZZ_ASSERT(w == NULL);
        return 0;
    }
    double lo, hi;
    sea_water_range(w, &lo, &hi);
    FUZZ_ASSERT(isfinite(lo) && isfinite(hi) && lo > 0.0 && lo < hi);
    FUZZ_ASSERT(sea_water_describe(w) != NULL);
    for (int i = 0; i <= 8; i++) {
        double wl = i == 8 ? hi : lo + (hi - lo) * i / 8.0;
        double complex N;
        st = sea_water_index(w, wl, &N, &err);
        FUZZ_ASSERT(st == SEA_OK);
        FUZZ_ASSERT(creal(N) >= SEA_WATER_N_MIN && creal(N) <= SEA_WATER_N_MAX + 1.0);
        FUZZ_ASSERT(cimag(N) >= 0.0 && isfinite(cimag(N)));
        double rho = sea_fresnel_unpolarized(0.5, N);
        FUZZ_ASSERT(rho >= 0.0 && rho <= 1.0);
    }
    /* Outside the table: an error, never a value. */
    double complex N;
    FUZZ_ASSERT(sea_water_index(w, lo * 0.5, &N, &err) == SEA_ERR_DOMAIN);
    sea_water_free(w);
    return 0;
}
