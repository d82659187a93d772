/* A probe-like minimal loop for bench_core: the 16 sums of the
 * Ashikhmin-Shirley normal pass on 3 channels (cost, the 6 entries of G,
 * the 9 of H; pass_fused.c) in one register-resident loop over contiguous
 * arrays of the active samples prepared beforehand (weight, ln n.h, the
 * lobe geometry, measured values): no chunks, no driver, no weights
 * computed. The floor the library's pass is measured against. */
#ifndef BRDFFIT_BENCH_PROBE_H
#define BRDFFIT_BENCH_PROBE_H

#include <stddef.h>

#include "brdffit/brdffit.h"

typedef struct probe_data {
    size_t n;
    double *store, *w, *x, *g, *m[3];
    double ns, k, dk, cd[3], cs[3];
} probe_data;

#define PROBE_SUMS 16

/* The active samples [first[b], first[b] + count[b]) of the grid (3
 * channels) at Ashikhmin-Shirley parameters ns = params[0], cd_c =
 * params[vindex[3 + c]], cs_c = params[vindex[6 + c]]; 0 on failure. */
int probe_init(probe_data *pd, const brdffit_grid *grid, double cap, const size_t *first,
               const size_t *count, size_t n_blocks, const double *params, const size_t *vindex);
void probe_free(probe_data *pd);

/* The sums with the widest vectors this CPU runs (avx512 != 0) or with
 * AVX2 at most (avx512 == 0); out gets PROBE_SUMS doubles. */
void probe_normal(const probe_data *pd, int avx512, double *out);

#endif
