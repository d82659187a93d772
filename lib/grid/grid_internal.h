/* Internal layout of the measurement grid, its derived geometry and the
 * streaming weight plan used by fits. Not installed. */
#ifndef BRDFFIT_GRID_INTERNAL_H
#define BRDFFIT_GRID_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "brdffit/batch.h"
#include "brdffit/grid.h"
#include "core/core.h"

/* Largest number of samples in one chunk handed to a model. */
#define BF_CHUNK 64

/* Derived per-sample geometry, structure of arrays (one allocation). The
 * first twelve fields mirror brdffit_batch. The rest are what the fit's
 * fused passes read per sample (pass_fused.c) besides log_nh: log_rv =
 * ln r.v, the Phong lobe's logarithm (BF_LOG_RV_NONE where r.v <= 0,
 * else ln(min(max(r.v, DBL_MIN), 1))), and, in single precision so that a
 * pass streams fewer bytes, as_g = 1 / (8 pi h.v max(n.l, n.v)) (the
 * Ashikhmin-Shirley lobe's geometry) and the residual weights of the two
 * weightings with the solid angle (brdffit_grid_weights()) before the
 * cap's normalisation: w_base[BF_BASE_DEFAULT] of BRDFFIT_WEIGHT_DEFAULT
 * and w_base[BF_BASE_SOLID_ANGLE] of BRDFFIT_WEIGHT_SOLID_ANGLE, scaled
 * into [0, 1]: scattered grids' divided by their largest (w_norm),
 * regular grids' the product of the three axes' factors (the cells of the
 * whole axes, without a cap) each divided by its axis's largest (w_norm
 * 0); a plan's factors make them its weights (bf_weight_plan_base()).
 * Every float is the double value rounded once. (The logarithms stay in
 * double: exp(ns x) would carry the rounding of x times ns.) */
typedef struct bf_geometry {
    double *lx, *ly, *lz, *vx, *vy, *vz;
    double *nl, *nv, *nh, *hv, *log_nh, *rv;
    double *log_rv;
    float *as_g;
    float *w_base[2];
    double w_norm[2];
    void *block; /* the single allocation holding all arrays */
} bf_geometry;

/* log_rv where r.v <= 0 (the Phong lobe is 0 there): below ln(DBL_MIN). */
#define BF_LOG_RV_NONE (-1000.0)

/* The two weightings of w_base. */
#define BF_BASE_DEFAULT 0
#define BF_BASE_SOLID_ANGLE 1

/* Bytes of the geometry of n samples (0 on overflow). */
size_t bf_geometry_bytes(size_t n);

/* Allocate arrays for n samples; returns 0 on overflow or failure. */
int bf_geometry_alloc(bf_geometry *g, const brdffit_allocator *a, size_t n);
void bf_geometry_free(bf_geometry *g, const brdffit_allocator *a);
/* Derive the geometry of sample s from light (theta_i, phi_i) and view
 * (theta_o, phi_o), radians; guarded at grazing angles (never NaN/Inf). */
void bf_geometry_set(bf_geometry *g, size_t s, double theta_i, double phi_i, double theta_o,
                     double phi_o);
/* cos(theta) of a polar angle, exactly 0 where theta is 90 degrees to
 * within the rounding of a double (|cos theta| <= 1e-15; the double
 * nearest pi/2 itself gives 6.1e-17), so that a grazing light or view lies
 * exactly on the horizon (docs/definitions.md, Geometry). */
double bf_cos_polar(double theta);
/* A batch view of samples [first, first + count). */
void bf_geometry_batch(const bf_geometry *g, size_t first, size_t count, brdffit_batch *out);

struct brdffit_grid {
    uint32_t magic; /* BF_MAGIC_GRID */
    brdffit_allocator alloc;
    brdffit_grid_kind kind;
    size_t n_samples, n_channels, n_missing;
    double *axis[3]; /* regular: theta_i, theta_o, phi_o (radians) */
    size_t n_axis[3];
    bf_geometry geo;
    double *values;         /* [c * n_samples + s]; missing values are 0 */
    float *fvalues;         /* the values times fscale in single precision ([c * n_samples
                             * + s], after the doubles in the allocation of values, a
                             * view's in its caller's buffer), read in place by the fused
                             * passes (pass_fused.c) */
    double fscale;          /* the power of two that brings the largest |value| into
                             * [0.5, 1) (1 when every value is 0); 0 when none does (the
                             * largest is below 2^-1000 or above 2^1000): the fused
                             * passes then leave the grid to the other routes */
    unsigned char *missing; /* NULL when nothing is missing, else [c * n_samples + s] */
    double *sample_weight;  /* scattered: NULL (uniform) or one per sample */
    double *max_theta;      /* scattered: max(theta_i, theta_o), ascending */
    size_t *order;          /* scattered: NULL when the input was in stored order, else
                              * the input row of every stored sample */
};

/* Set g->fscale from the values and, when g->fvalues is not NULL, fill
 * it (derived.c); every constructor calls it once its values are set. */
void bf_grid_store_float_values(brdffit_grid *g);

/* Fill g->geo.w_base and w_norm from the axes (regular grids) or the
 * sample weights and the geometry (scattered grids) (weights.c); the
 * constructors call it once those are set. */
void bf_grid_base_weights(brdffit_grid *g);

/* Validate a grid handle (non-NULL, magic). */
int bf_grid_ok(const brdffit_grid *g);

/* ---- what the constructors share (grid.c) ---------------------------------- */

/* Every size derived from (n_samples, n_channels) must fit in size_t. */
brdffit_status bf_grid_check_sizes(size_t n_samples, size_t n_channels, brdffit_error *err);
/* BRDFFIT_E_OUT_OF_MEMORY with the grid's message. */
brdffit_status bf_grid_oom(brdffit_error *err);
/* A grid with its value and geometry arrays allocated (sizes checked by
 * bf_grid_check_sizes() first); the caller fills every value. */
brdffit_status bf_grid_new(brdffit_grid **out, const brdffit_allocator *alloc,
                           brdffit_grid_kind kind, size_t n_samples, size_t n_channels,
                           brdffit_error *err);
/* Copy the three axes into g (one allocation). */
brdffit_status bf_grid_copy_axes(brdffit_grid *g, const brdffit_axes *axes, brdffit_error *err);
/* Free a grid whatever its state of construction. */
void bf_grid_free(brdffit_grid *g);
/* Allocate the missing mask when n_missing > 0. */
brdffit_status bf_grid_alloc_missing(brdffit_grid *g, size_t n_missing, brdffit_error *err);
/* Whether an allocator given by the caller is complete (or NULL). */
int bf_grid_check_alloc(const brdffit_allocator *alloc);
/* Count the missing values and check every present one is finite. */
brdffit_status bf_grid_check_values(const double *values, const unsigned char *missing,
                                    size_t n_samples, size_t n_channels, size_t *n_missing,
                                    brdffit_error *err);
/* Store interleaved input per channel (sample s from input row order[s],
 * or s when order is NULL); missing values become 0. */
void bf_grid_store_values(brdffit_grid *g, const double *values, const unsigned char *missing,
                          const size_t *order);

/* Streaming weights for fits: active samples (theta_i, theta_o <= cap) in
 * chunks of at most BF_CHUNK contiguous samples, each with its residual
 * weight factor (brdffit_grid_weights() semantics). Chunks are independent,
 * so threads may take disjoint sets of them. */
typedef struct bf_weight_plan {
    const brdffit_grid *grid;
    size_t n_chunks;
    size_t n_active; /* active samples */
    double scale;    /* normalisation factor */
    double divisor;  /* scattered given weights are divided by it first (1 or their largest) */
    unsigned flags;
    /* regular grids */
    size_t n_ti_act, n_to_act, chunks_per_ti;
    double *w_ti, *w_to, *w_po; /* one allocation, w_ti owns it */
    double top_to, top_po;      /* what w_to and w_po were divided by (1: nothing) */
    /* the base form (bf_weight_plan_base()): the grid's base weights of the
     * plan's weighting (NULL: none) times base_factor, or base_last from
     * sample base_split of a theta_i block on (regular grids: the last
     * active view row, whose cells the cap cuts) */
    const float *base;
    double base_factor, base_last;
    size_t base_split;
    /* NULL, or every chunk's weights computed once (bf_weight_plan_fill()),
     * chunk i's at [i * BF_CHUNK], borrowed: bf_weight_plan_chunk() then
     * copies them (the same bits) instead of computing them */
    const double *cached;
} bf_weight_plan;

/* Samples [first, first + count) whose weights are the grid's base
 * weights times factor. */
typedef struct bf_weight_piece {
    size_t first, count;
    double factor;
} bf_weight_piece;

brdffit_status bf_weight_plan_init(bf_weight_plan *p, const brdffit_grid *g, double cap,
                                   unsigned flags, const brdffit_allocator *a, brdffit_error *err);
void bf_weight_plan_free(bf_weight_plan *p, const brdffit_allocator *a);
/* Chunk `index` (< n_chunks): its first sample, its length, and its weights
 * written to `weights` (room for BF_CHUNK doubles). */
void bf_weight_plan_chunk(const bf_weight_plan *p, size_t index, size_t *first, size_t *count,
                          double *weights);
/* The samples of chunk `index` as one or two pieces whose weights are
 * p->base[s] * factor, equal to bf_weight_plan_chunk()'s but for the
 * single-precision rounding of the base weights (relative 2^-24); 0 when
 * the plan has no base form (p->base NULL: a weighting without the solid
 * angle, or factors out of the double range). */
size_t bf_weight_plan_base(const bf_weight_plan *p, size_t index, bf_weight_piece piece[2]);

/* Every chunk's weights into out (n_chunks * BF_CHUNK doubles, chunk i's
 * at [i * BF_CHUNK], the rest of a short chunk 0), for p->cached: a plan
 * shared by many fits over one geometry (brdffit_fit_many()) computes
 * them once. */
void bf_weight_plan_fill(const bf_weight_plan *p, double *out);

/* ---- views (view.c) --------------------------------------------------------- */

/* A view: a grid struct sharing the geometry, axes, sample weights and
 * order of `geometry` (borrowed, read only) with values of its own in the
 * caller's buffer `values` (n_samples * n_channels values of
 * BF_GRID_VIEW_BYTES each: the doubles, then their single-precision copy),
 * set by bf_grid_view_set(). A view reads like a grid made from the same
 * directions and values, bit for bit; it owns nothing, is never destroyed
 * and must not outlive `geometry`. */
#define BF_GRID_VIEW_BYTES (sizeof(double) + sizeof(float))
void bf_grid_view_init(brdffit_grid *view, const brdffit_grid *geometry, double *values);
/* Set the view's values from interleaved input in the sample order the
 * geometry grid was created with (as brdffit_grid_create_*() take them);
 * missing may be NULL; mask is the caller's buffer of n_samples *
 * n_channels bytes, used only when a value is missing. BRDFFIT_E_RANGE for
 * a present value that is not finite (the view then holds no values). */
brdffit_status bf_grid_view_set(brdffit_grid *view, const double *values,
                                const unsigned char *missing, unsigned char *mask,
                                brdffit_error *err);

/* ---- what other layers read of a grid (derived.c) ------------------------- */

/* Whether any value of the grid is marked missing. */
int bf_grid_has_missing(const brdffit_grid *g);

/* Channel c's measured values (n_samples doubles, missing ones 0), for
 * the fused passes that read them in place. */
const double *bf_grid_values(const brdffit_grid *g, size_t c);

/* Channel c's values times bf_grid_fscale() in single precision, for the
 * fused passes that read them in place (NULL for a grid without values). */
const float *bf_grid_fvalues(const brdffit_grid *g, size_t c);

/* The power of two of bf_grid_fvalues() (grid field fscale): 0 when the
 * values cannot be scaled into single precision. */
double bf_grid_fscale(const brdffit_grid *g);

/* The whole geometry of the grid (its arrays start at sample 0). */
const bf_geometry *bf_grid_geometry(const brdffit_grid *g);

/* The geometry of samples [first, first + count) as a batch. */
void bf_grid_batch(const brdffit_grid *g, size_t first, size_t count, brdffit_batch *out);

/* Measured values of channel c for samples [first, first + n) into meas,
 * and 1 (present) or 0 (missing) into present. */
void bf_grid_load_channel(const brdffit_grid *g, size_t c, size_t first, size_t n, double *meas,
                          double *present);

/* Mean of the present values of sample s into *mean (0 when none is
 * present); returns how many are present. When their sum overflows, the
 * mean of the values divided by their count (finite for finite values). */
size_t bf_grid_sample_mean(const brdffit_grid *g, size_t s, double *mean);

/* The channel mean of samples [first, first + n) (bf_grid_sample_mean)
 * into meas, and 1 or 0 (no channel present) into present. */
void bf_grid_load_mean(const brdffit_grid *g, size_t first, size_t n, double *meas,
                       double *present);

/* Clear-coat divisor 1 - F(theta_i) = (1 - r0) (1 - (1 - cos theta_i)^5),
 * F Schlick's approximation with reflectance r0 at normal incidence and
 * cos theta_i clamped to [BF_DOT_FLOOR, 1] (docs/definitions.md): a
 * compensated value is the measured one divided by it. Inline: the pass
 * calls it per sample. */
static inline double bf_grid_coat_divisor(double r0, double cos_i)
{
    double c = cos_i > BF_DOT_FLOOR ? (cos_i < 1.0 ? cos_i : 1.0) : BF_DOT_FLOOR;
    double m = 1.0 - c, m5 = m * m * m * m * m;
    return (1.0 - r0) * (1.0 - m5);
}

/* Channel selectors of bf_grid_count_rows() besides a channel index. */
#define BF_GRID_EVERY_CHANNEL ((size_t)-1)
#define BF_GRID_MEAN ((size_t)-2)

/* Rows of a fit over the plan's samples: the values with a non-zero
 * weight and present, of one channel, of every channel, or of the channel
 * mean (BF_GRID_MEAN: a sample counts once when any channel is present). */
size_t bf_grid_count_rows(const bf_weight_plan *plan, size_t channel);

#endif /* BRDFFIT_GRID_INTERNAL_H */
