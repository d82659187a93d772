/* The profile under a non-squares objective: see profile_gn.h.
 *
 * For one shape point the objective's residuals depend on the colours c of
 * each channel alone, so the Gauss-Newton model of the cost,
 * |r + J d|^2 with d = c - c0, is a small bounded least-squares problem per
 * channel in the K x K block of J^T J and the K entries of J^T r that the
 * fused NORMAL pass gives (fit/pass.h): minimise c^T H c - 2 (H c0 - g)^T c
 * inside the colours' bounds (fit/lsq.h). A step that does not lower the
 * true cost is halved; the box is convex, so every halved step stays
 * feasible. Under the relative objective the residuals are linear in the
 * colours and the first step is exact. A model affine in its colour
 * (fit/layout.h) needs nothing more: J and r are taken at the current
 * colours, so the model of the cost already holds the colour-free offset. */
#include "fit/profile_gn.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "fit/lsq.h"

/* Step halvings tried before a step counts as failed. */
#define BF_PROFILE_GN_HALVINGS 5
/* Relative cost decrease below which the steps stop: by then the steps
 * converge about a hundredfold each (the next ones would change the scan
 * cost by ~1e-8 relative), and every competing minimum is polished. */
#define BF_PROFILE_GN_RTOL 1e-6

/* Whether every linear parameter is per channel (each channel then has its
 * own K colours, as variable projection assumes). */
static int per_channel_colours(const bf_stage *st)
{
    const bf_problem *pb = &st->pb;
    size_t q, K = pb->ly.n_linear;
    if (K == 0 || K > BF_LSQ_MAX) return 0;
    for (q = 0; q < K; q++)
        if (!(brdffit_model_param(pb->model, pb->ly.linear[q])->flags & BRDFFIT_PARAM_PER_CHANNEL))
            return 0;
    return 1;
}

/* The Gauss-Newton target of channel m's colours into `target` (vector
 * layout) from the NORMAL pass in st->acc at st->p. */
static void channel_step(const bf_stage *st, size_t m, double *target)
{
    const bf_problem *pb = &st->pb;
    size_t K = pb->ly.n_linear, n = st->n, q, r, e[BF_LSQ_MAX];
    double H[BF_LSQ_MAX * BF_LSQ_MAX] = {0}, b[BF_LSQ_MAX] = {0}, lo[BF_LSQ_MAX] = {0};
    double hi[BF_LSQ_MAX] = {0}, c[BF_LSQ_MAX];
    const double *jtr = st->acc + 1, *jtj = st->acc + 1 + n;
    for (q = 0; q < K; q++) {
        e[q] = st->vindex[pb->ly.linear[q] * pb->nc + m];
        lo[q] = st->fixed[e[q]] ? st->p[e[q]] : st->lower[e[q]];
        hi[q] = st->fixed[e[q]] ? st->p[e[q]] : st->upper[e[q]];
    }
    for (q = 0; q < K; q++) {
        b[q] = -jtr[e[q]];
        for (r = 0; r < K; r++) {
            H[q * K + r] = jtj[e[q] * n + e[r]];
            b[q] += H[q * K + r] * st->p[e[r]];
        }
    }
    bf_bounded_lsq(K, H, b, lo, hi, c);
    for (q = 0; q < K; q++) target[e[q]] = fmin(fmax(c[q], lo[q]), hi[q]);
}

/* One step from st->p (cost f, NORMAL pass in st->acc): the full step to
 * the channels' targets, tried with a NORMAL pass (accepted, it is the
 * next step's pass: most steps cost one pass), then halved with COST
 * passes until the cost falls. On success st->p is the new point, *f its
 * cost and *fresh whether st->acc holds its NORMAL pass; otherwise st->p
 * is restored and *moved 0. */
static brdffit_status gn_step(bf_stage *st, double *f, double *from, double *target, int *moved,
                              int *fresh)
{
    size_t m, e, h;
    double t = 1.0;
    memcpy(from, st->p, st->n * sizeof *from);
    memcpy(target, st->p, st->n * sizeof *target);
    for (m = 0; m < st->pb.nc; m++) channel_step(st, m, target);
    *moved = 0;
    for (h = 0; h < BF_PROFILE_GN_HALVINGS; h++, t *= 0.5) {
        for (e = 0; e < st->n; e++) st->p[e] = from[e] + t * (target[e] - from[e]);
        BF_RETURN_IF_ERROR(bf_stage_pass(st, h == 0 ? BF_PASS_NORMAL : BF_PASS_COST));
        if (st->acc[0] < *f) {
            *f = st->acc[0];
            *moved = 1;
            *fresh = h == 0;
            return BRDFFIT_OK;
        }
    }
    memcpy(st->p, from, st->n * sizeof *from);
    return BRDFFIT_OK;
}

/* The start of the steps: the squared-value colours in st->p, or the
 * colours of `warm` (another shape point's, clamped into this point's
 * bounds) when their cost is lower. On return st->p is the start, *f its
 * cost, and *fresh whether st->acc holds its NORMAL pass. `work` has
 * n + 1 + n + n * n doubles (the point and its NORMAL sums, saved). */
static brdffit_status warm_start(bf_stage *st, const double *warm, double *work, double *f,
                                 int *fresh)
{
    const bf_problem *pb = &st->pb;
    size_t n = st->n, n_acc = 1 + n + n * n, q, m;
    double f0;
    BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_NORMAL));
    *f = f0 = st->acc[0];
    *fresh = 1;
    if (warm == NULL) return BRDFFIT_OK;
    memcpy(work, st->p, n * sizeof *work);
    memcpy(work + n, st->acc, n_acc * sizeof *work);
    for (q = 0; q < pb->ly.n_linear; q++)
        for (m = 0; m < pb->nc; m++) {
            size_t e = st->vindex[pb->ly.linear[q] * pb->nc + m];
            if (!st->fixed[e]) st->p[e] = fmin(fmax(warm[e], st->lower[e]), st->upper[e]);
        }
    BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_COST));
    if (st->acc[0] < f0) {
        *f = st->acc[0];
        *fresh = 0;
        return BRDFFIT_OK;
    }
    memcpy(st->p, work, n * sizeof *work);
    memcpy(st->acc, work + n, n_acc * sizeof *work);
    return BRDFFIT_OK;
}

static brdffit_status gn_steps(bf_stage *st, const double *warm, double *cost, double *work)
{
    double f = 0.0, before;
    int step, moved = 1, fresh = 0;
    BF_RETURN_IF_ERROR(warm_start(st, warm, work + 2 * st->n, &f, &fresh));
    for (step = 0; step < BF_PROFILE_GN_STEPS && moved; step++) {
        if (!fresh) {
            BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_NORMAL));
            f = st->acc[0];
        }
        before = f;
        BF_RETURN_IF_ERROR(gn_step(st, &f, work, work + st->n, &moved, &fresh));
        if (moved && before - f <= BF_PROFILE_GN_RTOL * before) break;
    }
    *cost = f; /* the cost at st->p: the last NORMAL pass's or the accepted step's */
    return BRDFFIT_OK;
}

brdffit_status bf_profile_gn(bf_stage *st, double *cost)
{
    return bf_profile_gn_from(st, NULL, cost);
}

brdffit_status bf_profile_gn_from(bf_stage *st, const double *warm, double *cost)
{
    const brdffit_allocator *a = &st->run->fit->alloc;
    double *work;
    brdffit_status status;
    if (st->pb.objective == BRDFFIT_OBJECTIVE_SQUARES) return BRDFFIT_OK;
    if (!per_channel_colours(st)) {
        BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_COST));
        *cost = st->acc[0];
        return BRDFFIT_OK;
    }
    work = bf_calloc(a, 4 * st->n + 1 + st->n * st->n, sizeof *work);
    if (work == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    status = gn_steps(st, warm, cost, work);
    bf_free(a, work);
    return status;
}
