/* libFuzzer harness for the ASTM E1392 loader (brdffit_load_astm_buffer). */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    brdffit_grid *g = NULL;
    brdffit_error err;
    fuzz_alloc fa;
    brdffit_status st;
    size_t allocs;
    memset(&err, 0, sizeof err);
    fuzz_alloc_init(&fa, 0);
    st = brdffit_load_astm_buffer(&g, (const char *)data, size, &fa.hook, &err);
    allocs = fa.allocs;
    if (st != BRDFFIT_OK) {
        fuzz_check_failure(st, g, &err);
    } else {
        fuzz_require(brdffit_grid_get_kind(g) == BRDFFIT_GRID_SCATTERED);
        fuzz_check_grid(g);
        brdffit_grid_destroy(g);
    }
    fuzz_require(fa.live == 0);
    /* the same input again, failing one of its allocations */
    if (allocs > 0) {
        fuzz_alloc_init(&fa, 1 + (size > 0 ? data[size - 1] : 0) % allocs);
        g = NULL;
        st = brdffit_load_astm_buffer(&g, (const char *)data, size, &fa.hook, &err);
        fuzz_require(st == BRDFFIT_E_OUT_OF_MEMORY);
        fuzz_check_failure(st, g, &err);
        fuzz_require(fa.live == 0);
    }
    return 0;
}
