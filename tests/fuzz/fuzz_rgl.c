/* libFuzzer harness for the RGL .bsdf loader (brdffit_load_rgl_buffer), in
 * both forms: as measured, and resampled onto small axes. Each form is
 * loaded again with one of its allocations failing. */
#include "fuzz_common.h"

static void load_form(const unsigned char *data, size_t size, const brdffit_axes *axes)
{
    brdffit_grid *g = NULL;
    brdffit_error err;
    fuzz_alloc fa;
    brdffit_status st;
    size_t allocs;
    memset(&err, 0, sizeof err);
    fuzz_alloc_init(&fa, 0);
    st = brdffit_load_rgl_buffer(&g, data, size, axes, &fa.hook, &err);
    allocs = fa.allocs;
    if (st == BRDFFIT_OK) {
        fuzz_require(brdffit_grid_get_kind(g) ==
                     (axes != NULL ? BRDFFIT_GRID_REGULAR : BRDFFIT_GRID_SCATTERED));
        fuzz_check_grid(g);
        brdffit_grid_destroy(g);
    } else {
        fuzz_check_failure(st, g, &err);
    }
    fuzz_require(fa.live == 0);
    if (allocs == 0) return;
    fuzz_alloc_init(&fa, 1 + size % allocs);
    g = NULL;
    st = brdffit_load_rgl_buffer(&g, data, size, axes, &fa.hook, &err);
    fuzz_require(st == BRDFFIT_E_OUT_OF_MEMORY);
    fuzz_check_failure(st, g, &err);
    fuzz_require(fa.live == 0);
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    static const double ti[3] = {0.0, 0.5, 1.2}, to[4] = {0.0, 0.4, 0.9, 1.5};
    static const double po[3] = {0.0, 1.5, 3.14159265358979};
    static const brdffit_axes axes = {ti, 3, to, 4, po, 3};
    load_form(data, size, NULL);
    load_form(data, size, &axes);
    return 0;
}
