/* The fused inner loop of the basis route (pass_fused.c): models of the
 * lobe form (models/basis.h: Lambert, Ashikhmin-Shirley and its two-lobe
 * variant, Phong, Blinn-Phong) and of the microfacet form (GGX,
 * Cook-Torrance and their two-lobe variants, Ward, Ward-Duer, and
 * ashikhmin-shirley-fresnel with Rs in place of F0) on 1 or 3 channels, one
 * register-resident sweep per chunk. Not installed. */
#ifndef BRDFFIT_FIT_PASS_FUSED_H
#define BRDFFIT_FIT_PASS_FUSED_H

#include <stddef.h>

#include "fit/pass_route.h"

/* Versions of the fused loop for x86-64 (gcc and clang): AVX-512, AVX2
 * and the baseline, chosen per problem at run time. */
#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__) && \
    !defined(BRDFFIT_NO_CLONES)
#define BF_FUSED_HAVE_ISA 1
#else
#define BF_FUSED_HAVE_ISA 0
#endif

/* The best version this machine runs (BF_ISA_*). */
unsigned bf_fused_best_isa(void);

/* Set pb->isa (the best version), pb->lobe and pb->mf once per problem
 * (bf_pass_prepare(), after pb->kernel). */
void bf_fused_prepare(bf_problem *pb);

/* Whether the fused loop accumulates the problem's passes of this kind
 * (COST, NORMAL, VARPRO of a kernel of the lobe form or the microfacet
 * form with at most two lobes and 1 or 3 channels; COST and NORMAL under
 * the squares objective only, VARPRO under any, as it sums squared values;
 * a weighting with the solid angle, whose weights the grid holds in single
 * precision (bf_weight_plan_base()), and values that a power of two brings
 * into single precision (bf_grid_fscale()); the basis route's own checks,
 * a kernel and no missing values, come first). */
int bf_fused_serves(const bf_problem *pb, bf_pass_kind kind);

/* bf_fused_serves() but for the values: whether the fused loop takes the
 * problem's passes of this kind whenever the grid's values fit single
 * precision (a batch's shared state, made before any item's values, then
 * weighs as the loop does: many_scan.c). */
int bf_fused_serves_any(const bf_problem *pb, bf_pass_kind kind);

/* Whether the fused loop reads the measured values in place (channel
 * values, no clear-coat compensation, a grid or view with single-precision
 * values): then the route's block hook takes the pass and the driver loads
 * nothing. */
int bf_fused_in_place(const bf_problem *pb, bf_pass_kind kind);

/* Doubles of the fused loop's per-thread accumulator (lanes of sums). */
size_t bf_fused_acc_size(const bf_problem *pb, bf_pass_kind kind);

/* Accumulate chunks [c0, c1) of the plan when the loop reads the values
 * in place (bf_fused_in_place()), joined into runs of contiguous samples;
 * else return 0 (the route's block hook, pass_route.h). */
int bf_fused_block(const bf_problem *pb, bf_pass_kind kind, const double *params, bf_scratch *sc,
                   size_t c0, size_t c1);

/* Accumulate one chunk of n samples whose measured values the driver
 * loaded into sc->meas (chunk sc->chunk from sample sc->first); works in
 * sc->vals. */
void bf_fused_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params, bf_scratch *sc,
                    size_t n);

/* Doubles of the largest reduced accumulator (NORMAL, two microfacet
 * lobes, 3 channels: 1 + 7 x 7 + 3 x 7). */
#define BF_FUSED_REDUCED_MAX 71

/* Reduce the summed lanes into the basis route's accumulator layout
 * (pass_basis.c: NORMAL [cost, G (NE x NE, upper), H (nc x NE)], VARPRO
 * [G (L x L, upper), b (nc x L), rr (nc)], COST [cost]); at most
 * BF_FUSED_REDUCED_MAX doubles. */
void bf_fused_reduce(const bf_problem *pb, bf_pass_kind kind, const double *lanes,
                     double *basis_acc);

#endif /* BRDFFIT_FIT_PASS_FUSED_H */
