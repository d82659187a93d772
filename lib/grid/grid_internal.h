/* Internal layout of the measurement grid, its derived geometry and the
 * streaming weight plan used by fits. Not installed. */
#ifndef BRDFFIT_GRID_INTERNAL_H
#define BRDFFIT_GRID_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "brdffit/grid.h"
#include "brdffit/model.h"

/* Largest number of samples in one chunk handed to a model. */
#define BF_CHUNK 64

/* Derived per-sample geometry, structure of arrays (one allocation). The
 * fields mirror brdffit_batch. */
typedef struct bf_geometry {
    double *lx, *ly, *lz, *vx, *vy, *vz;
    double *nl, *nv, *nh, *hv, *log_nh, *rv;
    double *block; /* the single allocation holding all arrays */
} bf_geometry;

/* Allocate arrays for n samples; returns 0 on overflow or failure. */
int bf_geometry_alloc(bf_geometry *g, const brdffit_allocator *a, size_t n);
void bf_geometry_free(bf_geometry *g, const brdffit_allocator *a);
/* Derive the geometry of sample s from light (theta_i, phi_i) and view
 * (theta_o, phi_o), radians; guarded at grazing angles (never NaN/Inf). */
void bf_geometry_set(bf_geometry *g, size_t s, double theta_i, double phi_i, double theta_o,
                     double phi_o);
/* A batch view of samples [first, first + count). */
void bf_geometry_batch(const bf_geometry *g, size_t first, size_t count, brdffit_batch *out);

struct brdffit_grid {
    uint32_t magic; /* BF_MAGIC_GRID */
    brdffit_allocator alloc;
    brdffit_grid_kind kind;
    size_t n_samples, n_channels, n_missing;
    double *axis[3];   /* regular: theta_i, theta_o, phi_o (radians) */
    size_t n_axis[3];
    bf_geometry geo;
    double *values;          /* [c * n_samples + s]; missing values are 0 */
    unsigned char *missing;  /* NULL when nothing is missing, else [c * n_samples + s] */
    double *sample_weight;   /* scattered: NULL (uniform) or one per sample */
    double *max_theta;       /* scattered: max(theta_i, theta_o), ascending */
};

/* Validate a grid handle (non-NULL, magic). */
int bf_grid_ok(const brdffit_grid *g);

/* Streaming weights for fits: active samples (theta_i, theta_o <= cap) in
 * chunks of at most BF_CHUNK contiguous samples, each with its residual
 * weight factor (brdffit_grid_weights() semantics). Chunks are independent,
 * so threads may take disjoint sets of them. */
typedef struct bf_weight_plan {
    const brdffit_grid *grid;
    size_t n_chunks;
    size_t n_active;  /* active samples */
    double scale;     /* normalisation factor */
    double divisor;   /* scattered given weights are divided by it first (1 or their largest) */
    unsigned flags;
    /* regular grids */
    size_t n_ti_act, n_to_act, chunks_per_ti;
    double *w_ti, *w_to, *w_po; /* one allocation, w_ti owns it */
} bf_weight_plan;

brdffit_status bf_weight_plan_init(bf_weight_plan *p, const brdffit_grid *g, double cap,
                                   unsigned flags, const brdffit_allocator *a,
                                   brdffit_error *err);
void bf_weight_plan_free(bf_weight_plan *p, const brdffit_allocator *a);
/* Chunk `index` (< n_chunks): its first sample, its length, and its weights
 * written to `weights` (room for BF_CHUNK doubles). */
void bf_weight_plan_chunk(const bf_weight_plan *p, size_t index, size_t *first, size_t *count,
                          double *weights);

#endif /* BRDFFIT_GRID_INTERNAL_H */
