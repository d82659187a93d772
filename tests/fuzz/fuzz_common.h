/* Shared by the fuzz harnesses: a counting allocator that can fail the Nth
 * allocation, and checks of the invariants every grid must satisfy. A
 * violated invariant aborts, which both libFuzzer and the corpus driver
 * report. */
#ifndef BRDFFIT_FUZZ_COMMON_H
#define BRDFFIT_FUZZ_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdffit/brdffit.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

typedef struct fuzz_alloc {
    brdffit_allocator hook;
    size_t allocs, live, fail_at;
} fuzz_alloc;

static void *fuzz_alloc_fn(size_t size, void *ctx)
{
    fuzz_alloc *fa = ctx;
    void *p;
    if (++fa->allocs == fa->fail_at) return NULL;
    p = malloc(size);
    if (p != NULL) fa->live++;
    return p;
}

static void fuzz_free_fn(void *ptr, void *ctx)
{
    fuzz_alloc *fa = ctx;
    fa->live--;
    free(ptr);
}

static void fuzz_alloc_init(fuzz_alloc *fa, size_t fail_at)
{
    fa->hook.alloc = fuzz_alloc_fn;
    fa->hook.free = fuzz_free_fn;
    fa->hook.ctx = fa;
    fa->allocs = fa->live = 0;
    fa->fail_at = fail_at;
}

/* A violated invariant names itself on stderr before the abort, so a stored
 * crash input says what it breaks. */
#define fuzz_require(ok) fuzz_require_at((ok) != 0, #ok, __FILE__, __LINE__)

static void fuzz_require_at(int ok, const char *what, const char *file, int line)
{
    if (ok) return;
    fprintf(stderr, "%s:%d: invariant failed: %s\n", file, line, what);
    abort();
}

/* A failed load leaves no grid and a terminated message with its status. */
static void fuzz_check_failure(brdffit_status st, const brdffit_grid *g, const brdffit_error *err)
{
    fuzz_require(g == NULL);
    fuzz_require(err->status == st);
    fuzz_require(memchr(err->message, '\0', sizeof err->message) != NULL);
    fuzz_require(err->message[0] != '\0');
}

/* Every value finite (negative values are data), missing ones 0; weights and interpolation
 * finite as well. */
static void fuzz_check_grid(const brdffit_grid *g)
{
    size_t n = brdffit_grid_sample_count(g), nc = brdffit_grid_channel_count(g), s, c;
    size_t n_missing = 0;
    double *w, out[8];
    fuzz_require(n > 0 && nc > 0);
    for (c = 0; c < nc; c++) {
        const double *v;
        fuzz_require(brdffit_grid_values(g, c, &v) == BRDFFIT_OK);
        for (s = 0; s < n; s++) {
            int miss = brdffit_grid_is_missing(g, s, c);
            fuzz_require(isfinite(v[s]));
            fuzz_require(!miss || v[s] == 0.0);
            n_missing += (size_t)miss;
        }
    }
    fuzz_require(n_missing == brdffit_grid_missing_count(g));
    for (s = 0; s < n; s++) {
        double t[4];
        fuzz_require(brdffit_grid_sample_angles(g, s, &t[0], &t[1], &t[2], &t[3]) == BRDFFIT_OK);
        fuzz_require(t[0] >= 0.0 && t[0] <= 1.5707963267948967 && t[2] >= 0.0 &&
                     t[2] <= 1.5707963267948967);
    }
    w = malloc(n * sizeof(double));
    if (w != NULL) {
        brdffit_status st =
            brdffit_grid_weights(g, BRDFFIT_DEFAULT_CAP, BRDFFIT_WEIGHT_DEFAULT, w, NULL);
        fuzz_require(st == BRDFFIT_OK || st == BRDFFIT_E_NO_DATA);
        for (s = 0; st == BRDFFIT_OK && s < n; s++) fuzz_require(isfinite(w[s]) && w[s] >= 0.0);
        free(w);
    }
    if (brdffit_grid_get_kind(g) == BRDFFIT_GRID_REGULAR && nc <= 8) {
        brdffit_status st = brdffit_grid_eval(g, 0.4, 1.0, 0.9, -2.0, out, NULL);
        fuzz_require(st == BRDFFIT_OK || st == BRDFFIT_E_NO_DATA);
        for (c = 0; c < nc; c++) fuzz_require(isfinite(out[c]));
    }
}

#endif
