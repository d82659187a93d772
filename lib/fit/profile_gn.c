/* The profile at one shape point: see profile_gn.h.
 *
 * For one shape point the objective's residuals depend on the colours c of
 * each channel alone, so the Gauss-Newton model of the cost,
 * |r + J d|^2 with d = c - c0, is a small bounded least-squares problem per
 * channel in the K x K block of J^T J and the K entries of J^T r: minimise
 * c^T H c - 2 (H c0 - g)^T c inside the colours' bounds (fit/lsq.h). The
 * steps stop when the model predicts a decrease below BF_PROFILE_GN_RTOL
 * of the cost (no pass is spent on a step that cannot count) or a step
 * achieves one; a step that does not lower the true cost is halved (the
 * box is convex, so every halved step stays feasible). Under the relative
 * objective the residuals are linear in the colours: the first step is
 * exact and the model then predicts nothing more. A model affine in its
 * colour (fit/layout.h) needs nothing more: J and r are taken at the
 * current colours, so the model of the cost holds the colour-free offset.
 *
 * The blocks come from the colour passes over the shape cache when the
 * model has one (pass_colour.c: no model evaluation per step), else from
 * NORMAL passes, whose colour entries are gathered into the same layout:
 * per channel [cost, J^T r (K), J^T J (K x K)]. With the cache the steps
 * start from the colours of the objective linearised at the measured
 * values (COLOUR_VARPRO), which is the Gauss-Newton step from a model
 * equal to the data: exact under the relative objective, and closer to
 * the optimum than the squared-value colours under the others (the steps
 * without the cache start from those, or from the previous scan point's
 * colours, whichever costs less). */
#include "fit/profile_gn.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "fit/lsq.h"
#include "fit/varpro.h"

/* Step halvings tried before a step counts as failed. */
#define BF_PROFILE_GN_HALVINGS 5
/* Relative cost decrease below which the steps stop at a scan point: by
 * then the steps converge about a hundredfold each (the next ones would
 * change the scan cost by ~1e-8 relative), and every competing minimum is
 * polished. */
#define BF_PROFILE_GN_RTOL 1e-6
/* The same for the start of a polish, which LM takes from there: in a flat
 * valley (two lobes fitted to one-lobe data) its path depends on the
 * start's last digits, so they are converged (the steps are colour passes
 * over the cache, once per polish). */
#define BF_PROFILE_GN_RTOL_START 1e-12

/* The steps of one shape point. */
typedef struct gn {
    bf_stage *st;
    int cached; /* colour passes over the shape cache, else NORMAL and COST */
    size_t K, stride;
    double *blk;                   /* nc * stride: the blocks at st->p, when fresh */
    double *kept;                  /* nc * stride: blocks set aside */
    double *from, *target, *point; /* n each */
    int fresh;                     /* blk belongs to st->p */
    double rtol;                   /* BF_PROFILE_GN_RTOL or _START */
} gn;

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

/* Vector entry of colour q of channel m. */
static size_t colour_entry(const bf_stage *st, size_t q, size_t m)
{
    return st->vindex[st->pb.ly.linear[q] * st->pb.nc + m];
}

/* The blocks and the cost at st->p into g->blk and *f. */
static brdffit_status blocks(gn *g, double *f)
{
    bf_stage *st = g->st;
    const size_t n = st->n, nc = st->pb.nc, K = g->K;
    size_t m, q, r;
    if (g->cached) {
        BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_COLOUR_NORMAL));
        memcpy(g->blk, st->acc, nc * g->stride * sizeof *g->blk);
    } else {
        const double *jtr = st->acc + 1, *jtj = st->acc + 1 + n;
        BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_NORMAL));
        for (m = 0; m < nc; m++) {
            double *b = g->blk + m * g->stride;
            b[0] = m == 0 ? st->acc[0] : 0.0; /* the cost, whole */
            for (q = 0; q < K; q++) {
                size_t e = colour_entry(st, q, m);
                b[1 + q] = jtr[e];
                for (r = 0; r < K; r++) b[1 + K + q * K + r] = jtj[e * n + colour_entry(st, r, m)];
            }
        }
    }
    for (*f = 0.0, m = 0; m < nc; m++) *f += g->blk[m * g->stride];
    g->fresh = 1;
    return BRDFFIT_OK;
}

/* The cost at st->p into *f (the blocks there too when `normal`). */
static brdffit_status cost_at(gn *g, int normal, double *f)
{
    if (normal) return blocks(g, f);
    BF_RETURN_IF_ERROR(bf_stage_pass(g->st, g->cached ? BF_PASS_COLOUR_COST : BF_PASS_COST));
    *f = g->st->acc[0];
    g->fresh = 0;
    return BRDFFIT_OK;
}

/* The Gauss-Newton target of channel m's colours into g->target (vector
 * layout) from its block at st->p; returns the decrease of the cost the
 * model predicts for the step. */
static double channel_step(gn *g, size_t m)
{
    const bf_stage *st = g->st;
    const size_t K = g->K;
    const double *blk = g->blk + m * g->stride, *jtr = blk + 1, *H = blk + 1 + K;
    size_t q, r, e[BF_LSQ_MAX];
    double b[BF_LSQ_MAX] = {0}, lo[BF_LSQ_MAX] = {0}, hi[BF_LSQ_MAX] = {0}, c[BF_LSQ_MAX];
    double d[BF_LSQ_MAX], rise = 0.0;
    for (q = 0; q < K; q++) {
        e[q] = colour_entry(st, q, m);
        lo[q] = st->fixed[e[q]] ? st->p[e[q]] : st->lower[e[q]];
        hi[q] = st->fixed[e[q]] ? st->p[e[q]] : st->upper[e[q]];
    }
    for (q = 0; q < K; q++) {
        b[q] = -jtr[q];
        for (r = 0; r < K; r++) b[q] += H[q * K + r] * st->p[e[r]];
    }
    bf_bounded_lsq(K, H, b, lo, hi, c);
    for (q = 0; q < K; q++) {
        g->target[e[q]] = fmin(fmax(c[q], lo[q]), hi[q]);
        d[q] = g->target[e[q]] - st->p[e[q]];
    }
    /* |r + J d|^2 - |r|^2 = 2 g^T d + d^T H d */
    for (q = 0; q < K; q++) {
        double hd = 0.0;
        for (r = 0; r < K; r++) hd += H[q * K + r] * d[r];
        rise += d[q] * (2.0 * jtr[q] + hd);
    }
    return -rise;
}

/* One step from st->p (cost f, blocks fresh): the full step to the
 * channels' targets, halved until the cost falls. On success st->p is the
 * new point and *f its cost; otherwise st->p is restored and *moved 0.
 * *predicted is the model's decrease; a step predicted to lower the cost
 * by less than g->rtol of it is not tried. */
static brdffit_status gn_step(gn *g, double *f, int *moved, double *predicted)
{
    bf_stage *st = g->st;
    size_t m, e, h;
    double t = 1.0, fn;
    *moved = 0;
    memcpy(g->from, st->p, st->n * sizeof *g->from);
    memcpy(g->target, st->p, st->n * sizeof *g->target);
    for (*predicted = 0.0, m = 0; m < st->pb.nc; m++) *predicted += channel_step(g, m);
    if (!(*predicted > g->rtol * *f)) return BRDFFIT_OK;
    for (h = 0; h < BF_PROFILE_GN_HALVINGS; h++, t *= 0.5) {
        for (e = 0; e < st->n; e++) st->p[e] = g->from[e] + t * (g->target[e] - g->from[e]);
        /* the full step's blocks are the next step's; a halved step's too
         * when they cost no model evaluation */
        BF_RETURN_IF_ERROR(cost_at(g, h == 0 || g->cached, &fn));
        if (fn < *f) {
            *f = fn;
            *moved = 1;
            return BRDFFIT_OK;
        }
    }
    memcpy(st->p, g->from, st->n * sizeof *g->from);
    g->fresh = 0;
    return BRDFFIT_OK;
}

/* The start of the steps: the squared-value colours in st->p, or the
 * colours of `warm` (another shape point's, clamped into this point's
 * bounds) when their cost is lower. On return st->p is the start, *f its
 * cost and its blocks fresh. */
static brdffit_status warm_start(gn *g, const double *warm, double *f)
{
    bf_stage *st = g->st;
    const size_t n = st->n, nc = st->pb.nc;
    size_t q, m;
    double fw;
    BF_RETURN_IF_ERROR(blocks(g, f));
    if (warm == NULL) return BRDFFIT_OK;
    memcpy(g->point, st->p, n * sizeof *g->point);
    memcpy(g->kept, g->blk, nc * g->stride * sizeof *g->kept);
    for (q = 0; q < g->K; q++)
        for (m = 0; m < nc; m++) {
            size_t e = colour_entry(st, q, m);
            if (!st->fixed[e]) st->p[e] = fmin(fmax(warm[e], st->lower[e]), st->upper[e]);
        }
    BF_RETURN_IF_ERROR(cost_at(g, g->cached, &fw));
    if (fw < *f) {
        *f = fw;
        return BRDFFIT_OK;
    }
    memcpy(st->p, g->point, n * sizeof *g->point);
    memcpy(g->blk, g->kept, nc * g->stride * sizeof *g->blk);
    g->fresh = 1;
    return BRDFFIT_OK;
}

static brdffit_status gn_steps(gn *g, const double *warm, double *cost)
{
    double f = 0.0, before, predicted;
    int step, moved = 1;
    BF_RETURN_IF_ERROR(warm_start(g, warm, &f));
    for (step = 0; step < BF_PROFILE_GN_STEPS && moved; step++) {
        if (!g->fresh) BF_RETURN_IF_ERROR(blocks(g, &f));
        before = f;
        BF_RETURN_IF_ERROR(gn_step(g, &f, &moved, &predicted));
        if (!(predicted > g->rtol * before)) break;
        if (moved && before - f <= g->rtol * before) break;
    }
    *cost = f; /* the cost at st->p: of its blocks or of the accepted step */
    return BRDFFIT_OK;
}

/* The Gauss-Newton steps from the colours in st->p, on the colour passes
 * when `cached`, to the polish start's tolerance when `start`. */
static brdffit_status profile_steps(bf_stage *st, int cached, int start, const double *warm,
                                    double *cost)
{
    const brdffit_allocator *a = &st->run->fit->alloc;
    const size_t K = st->pb.ly.n_linear, stride = 1 + K + K * K, nb = st->pb.nc * stride;
    gn g;
    brdffit_status status;
    double *work = bf_calloc(a, 3 * st->n + 2 * nb, sizeof *work);
    if (work == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    g.st = st;
    g.cached = cached;
    g.K = K;
    g.stride = stride;
    g.from = work;
    g.target = work + st->n;
    g.point = work + 2 * st->n;
    g.blk = work + 3 * st->n;
    g.kept = g.blk + nb;
    g.fresh = 0;
    g.rtol = start ? BF_PROFILE_GN_RTOL_START : BF_PROFILE_GN_RTOL;
    status = gn_steps(&g, warm, cost);
    bf_free(a, work);
    return status;
}

/* The stage's shape cache, made at its first use. */
static brdffit_status shape_cache(bf_stage *st)
{
    if (st->shape != NULL) return BRDFFIT_OK;
    st->shape = bf_calloc(&st->run->fit->alloc, bf_pass_shape_size(&st->pb), sizeof *st->shape);
    if (st->shape == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    st->pb.shape = st->shape;
    return BRDFFIT_OK;
}

brdffit_status bf_profile_point(bf_stage *st, const double *warm, int start, double *cost)
{
    const int squares = st->pb.objective == BRDFFIT_OBJECTIVE_SQUARES;
    if (st->pb.colour) { /* the colours from the shape cache */
        BF_RETURN_IF_ERROR(shape_cache(st));
        BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_SHAPE));
        BF_RETURN_IF_ERROR(bf_varpro_profile(st, BF_PASS_COLOUR_VARPRO, cost));
        return squares ? BRDFFIT_OK : profile_steps(st, 1, start, NULL, cost);
    }
    BF_RETURN_IF_ERROR(bf_varpro_profile(st, BF_PASS_VARPRO, cost));
    if (squares) return BRDFFIT_OK;
    if (per_channel_colours(st)) return profile_steps(st, 0, start, warm, cost);
    BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_COST));
    *cost = st->acc[0];
    return BRDFFIT_OK;
}
