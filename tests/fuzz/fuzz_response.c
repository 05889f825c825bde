/* fuzz_response.c - libFuzzer target: the spectral response curve loader
 * (sea_response_load) on arbitrary CSV text, checking what it promises of
 * a curve it accepts. */
#include <math.h>

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[128];
    fuzz_write("response.csv", data, size, path, sizeof path);
    sea_error err = {{0}};
    sea_response r;
    sea_status st = sea_response_load(path, &r, &err);
    fuzz_check_error(st, &err);
    if (st != SEA_OK) {
        FUZZ_ASSERT(r.n == 0 && r.wavelength == NULL && r.value == NULL);
        return 0;
    }
    FUZZ_ASSERT(r.n >= 2);
    int positive = 0;
    for (size_t i = 0; i < r.n; i++) {
        FUZZ_ASSERT(isfinite(r.wavelength[i]) && r.wavelength[i] > 0.0);
        FUZZ_ASSERT(r.wavelength[i] <= SEA_RESPONSE_WAVELENGTH_MAX_UM * 1e-6 * (1 + 1e-15));
        FUZZ_ASSERT(i == 0 || r.wavelength[i] > r.wavelength[i - 1]);
        FUZZ_ASSERT(r.value[i] >= 0.0 && r.value[i] <= SEA_RESPONSE_MAX);
        positive |= r.value[i] > 0.0;
    }
    FUZZ_ASSERT(positive);
    sea_response_free(&r);
    FUZZ_ASSERT(r.n == 0 && r.wavelength == NULL);
    return 0;
}
