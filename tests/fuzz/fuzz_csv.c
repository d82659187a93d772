/* libFuzzer harness for the CSV loader (brdffit_load_csv_buffer). */
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
    st = brdffit_load_csv_buffer(&g, (const char *)data, size, &fa.hook, &err);
    allocs = fa.allocs;
    if (st != BRDFFIT_OK) {
        fuzz_check_failure(st, g, &err);
    } else {
        brdffit_grid *m = NULL;
        fuzz_check_grid(g);
        fuzz_require(brdffit_grid_channel_mean(&m, g, NULL, NULL) == BRDFFIT_OK);
        fuzz_check_grid(m);
        brdffit_grid_destroy(m);
        brdffit_grid_destroy(g);
    }
    fuzz_require(fa.live == 0);
    /* the same input again, failing one of the allocations it made: out of
     * memory, and no leak */
    if (allocs > 0) {
        fuzz_alloc_init(&fa, 1 + (size > 0 ? data[size - 1] : 0) % allocs);
        g = NULL;
        st = brdffit_load_csv_buffer(&g, (const char *)data, size, &fa.hook, &err);
        fuzz_require(st == BRDFFIT_E_OUT_OF_MEMORY);
        fuzz_check_failure(st, g, &err);
        fuzz_require(fa.live == 0);
    }
    return 0;
}
