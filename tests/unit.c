/* unit.c - runs every CUnit suite; exits non-zero on any failure. */
#include <CUnit/Basic.h>
#include <stdio.h>

#include "unit.h"

int main(void)
{
    sea_init();
    if (CU_initialize_registry() != CUE_SUCCESS)
        return 2;
    if (test_water_register() || test_spectrum_register() || test_shadow_register() ||
        test_optics_register() || test_waves_register() || test_scene_register() ||
        test_sensor_register() || test_multires_register() || test_render_register() ||
        test_bake_register() || test_preview_register() || test_exr_register() ||
        test_stability_register() || test_mc_register()) {
        fprintf(stderr, "unit: cannot register the suites: %s\n", CU_get_error_msg());
        CU_cleanup_registry();
        return 2;
    }
    CU_basic_set_mode(CU_BRM_VERBOSE);
    CU_basic_run_tests();
    unsigned failed = CU_get_number_of_tests_failed();
    unsigned run = CU_get_number_of_tests_run();
    unsigned asserts_failed = CU_get_number_of_failures();
    int failed_registry = CU_get_number_of_suites_failed();
    printf("\nunit: %u passed, %u failed\n", run - failed, failed);
    CU_cleanup_registry();
    return (failed || asserts_failed || failed_registry) ? 1 : 0;
}
