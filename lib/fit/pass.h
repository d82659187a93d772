/* One pass over the active samples of a grid: the fused inner loop of every
 * fit. A pass evaluates the model chunk by chunk (never more than BF_CHUNK
 * samples at a time, so the Jacobian is never stored whole) and accumulates
 * one of:
 *   COST    [cost]
 *   NORMAL  [cost, J^T r (n), J^T J (n * n, upper triangle then mirrored)]
 *           in model-parameter space, n = model vector size, r = w (M - R)
 *           under the squares objective, else the objective's residual
 *           (brdffit_objective) with J its Jacobian
 *   COST and NORMAL follow pb->objective; VARPRO is always the squares of
 *   values (the auto scan's profile); METRICS's last sum is the
 *   objective's sum of r^2
 *   VARPRO  per channel m: [R^T W R, B^T W R (K), B^T W B (K * K)], B the
 *           columns of the K linear parameters, W = diag(w^2)
 *   METRICS per channel m: [sum d^2, sum a (cos d)^2, sum a, sum (w d)^2],
 *           d = M - R, a the solid-angle weight alone
 *   SANDWICH [sum_i (r_i / (1 - h_i))^2 J_i^T J_i (n * n)], the rows i and
 *           r, J of NORMAL, h_i = J_i B J_i^T with B = pb->bread (the
 *           covariance's pseudo-inverse of J^T J, model-parameter space),
 *           1 - h_i floored at 1e-8 as the optimizer's own sandwich does:
 *           the meat of the HC3 sandwich covariance
 * and the colour passes of auto's profile at one shape point
 * (pass_colour.c), which need the shape cache pb->shape:
 *   SHAPE   no sums: fills pb->shape with what the model's values take
 *           from params' shape alone (bf_pass_shape_size())
 *   COLOUR_COST    [cost] as COST, from the cache at params' colours
 *   COLOUR_NORMAL  per channel m: [cost of m, J^T r (K), J^T J (K * K)]
 *           of channel m's K colours (the layout's linear parameters in
 *           their order), the colour block of NORMAL, from the cache
 *   COLOUR_VARPRO  VARPRO's sums of the objective linearised at the
 *           measured values, rows w T'(R) (M - R) with T the objective's
 *           transform (VARPRO itself under the squares objective), from
 *           the cache
 * The chunks are split into `threads` contiguous blocks, run by the pool's
 * helpers and the calling thread, and the blocks' partial sums are added in
 * block order, so a pass is deterministic for a given thread count. The
 * fused loop's versions (pass_fused.c) sum in lanes of a fixed layout, so
 * every version gives the same bits too.
 *
 * How a chunk is accumulated is a route (fit/pass_route.h): the basis route
 * for models in basis form (models/basis.h) on grids without missing
 * values, for COST, NORMAL and VARPRO under every objective; the generic
 * route for any model and objective, and for METRICS. bf_pass_prepare()
 * chooses it once per problem; SANDWICH needs each row's Jacobian and
 * always takes the generic route, SHAPE and the colour passes the colour
 * route. */
#ifndef BRDFFIT_FIT_PASS_H
#define BRDFFIT_FIT_PASS_H

#include <stdatomic.h>
#include <stddef.h>

#include "brdffit/fit.h"
#include "brdffit/model.h"
#include "fit/layout.h"
#include "fit/pool.h"
#include "grid/grid_internal.h"
#include "models/basis.h"

typedef enum bf_source { BF_SOURCE_CHANNELS, BF_SOURCE_ONE_CHANNEL, BF_SOURCE_MEAN } bf_source;

typedef enum bf_pass_kind {
    BF_PASS_COST,
    BF_PASS_NORMAL,
    BF_PASS_VARPRO,
    BF_PASS_METRICS,
    BF_PASS_SANDWICH,
    BF_PASS_SHAPE,
    BF_PASS_COLOUR_COST,
    BF_PASS_COLOUR_NORMAL,
    BF_PASS_COLOUR_VARPRO
} bf_pass_kind;

#define BF_MAX_THREADS 64

/* Versions of the fused loop (pass_fused.h): the plain C loop, then the
 * vector ones for the baseline instruction set, AVX2 and AVX-512; the
 * last two with fused multiply-add, as the plain C loop with fma() of
 * math.h (BF_ISA_PLAIN_FMA, their reference in the tests; slow where the
 * CPU has no FMA). */
#define BF_ISA_PLAIN 0u
#define BF_ISA_BASE 1u
#define BF_ISA_AVX2 2u
#define BF_ISA_AVX512 3u
#define BF_ISA_PLAIN_FMA 4u

struct bf_route;

typedef struct bf_problem {
    const brdffit_grid *grid;
    const brdffit_model *model;
    const bf_weight_plan *plan;    /* the fit's residual weights */
    const bf_weight_plan *plan_sa; /* solid angle alone, for METRICS */
    size_t nc;                     /* model channels */
    bf_source source;
    size_t source_channel;         /* BF_SOURCE_ONE_CHANNEL */
    double clearcoat;              /* R0; 0 = off */
    brdffit_objective objective;   /* what COST, NORMAL and METRICS's cost sum */
    double delta;                  /* the objective's floor (brdffit_objective) */
    bf_layout ly;                  /* the model's vector layout for nc channels */
    const size_t *vindex;          /* [k * nc + m]: vector index of declared k, channel m */
    size_t threads;                /* blocks of a pass (at most BF_MAX_THREADS) */
    bf_pool *pool;                 /* helper threads for the blocks; NULL: the caller runs all */
    double *work;                  /* bf_pass_work_size() doubles, owned by the caller */
    int sandwich;                  /* SANDWICH passes will be run (the generic route's
                                    * scratch is sized in whatever the route) */
    const double *bread;           /* SANDWICH: n_vec * n_vec (J^T J)^+, borrowed */
    const double *terms;           /* bf_pass_terms_size() doubles filled by bf_pass_terms(),
                                    * owned by the caller: what the objective's rows take
                                    * from the measured values and the geometry alone,
                                    * computed once rather than in every pass; NULL under
                                    * the squares objective, which needs none */
    int colour;                    /* colour passes will be run (their route's scratch is
                                    * sized in) */
    double *shape;                 /* bf_pass_shape_size() doubles, owned by the caller:
                                    * the shape cache SHAPE fills and the colour passes
                                    * read; NULL when no colour pass runs */
    /* set by bf_pass_prepare() */
    const bf_kernel *kernel;       /* the model's basis form, NULL when it has none */
    const struct bf_route *route;  /* how chunks are accumulated */
    unsigned isa;                  /* the fused loop's version (BF_ISA_*): the best the
                                    * machine runs; a test may lower it */
    int lobe;                      /* 1 + its lobes when the kernel has the lobe form
                                    * or the microfacet form (models/basis.h), else 0 */
    int mf;                        /* the microfacet form's family (bf_microfacet),
                                    * BF_MF_NONE for the lobe form */
} bf_problem;

/* Choose the route of every pass of the problem from the routes' table;
 * call once after setting every other field but `work` (sized after it). */
void bf_pass_prepare(bf_problem *pb);

/* Doubles of workspace a pass of any kind needs (all threads together). */
size_t bf_pass_work_size(const bf_problem *pb);

/* Doubles of the objective's terms (pb->terms): 0 under the squares
 * objective; nc per sample under log and relative, nc + 1 under cube-root
 * ([m * n_samples + s] for model channel m, then cbrt(cos theta_i)). */
size_t bf_pass_terms_size(const bf_problem *pb);

/* Fill the objective's terms for every sample of the grid; call after
 * `work` is set (it loads the measured values in the first thread's
 * scratch), then set pb->terms = terms. */
void bf_pass_terms(const bf_problem *pb, double *terms);

/* Doubles of the shape cache (pb->shape): (K + 1) per sample for a model
 * affine in its colour, K for a model in basis form whose K linear
 * parameters are its basis's colours; 0 for any other model, which has no
 * colour passes. Call after bf_pass_prepare(). */
size_t bf_pass_shape_size(const bf_problem *pb);

/* Size of the accumulator of a pass, in doubles. */
size_t bf_pass_acc_size(const bf_problem *pb, bf_pass_kind kind);

/* Run a pass at model parameters `params` (natural units, model vector
 * layout; for VARPRO the linear entries are ignored, and VARPRO needs
 * bf_layout_projectable()). acc receives
 * bf_pass_acc_size() doubles. Never allocates: it works in pb->work. */
brdffit_status bf_pass(const bf_problem *pb, bf_pass_kind kind, const double *params,
                       double *acc, brdffit_error *err);

/* Number of (sample, channel) values the weights include with a non-zero
 * factor and a present measurement. */
brdffit_status bf_count_rows(const bf_problem *pb, size_t *rows, brdffit_error *err);

#endif /* BRDFFIT_FIT_PASS_H */
