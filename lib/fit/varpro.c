/* Variable projection: see varpro.h. */
#include "fit/varpro.h"

#include <math.h>

#include "core/core.h"
#include "fit/lsq.h"

/* The best bounded colours of channel m from its sums acc = [r^T W r, b,
 * G], written into st->p. A held colour (st->fixed) keeps its value c_h in
 * st->p: its part of c^T G c - 2 b^T c is a constant, and it moves the free
 * colours' right-hand side to b_f - G_fh c_h. Returns the channel's cost. */
static double channel_colours(bf_stage *st, size_t m, const double *acc, const double *lo,
                              const double *hi, int quick)
{
    const bf_problem *pb = &st->pb;
    size_t K = pb->ly.n_linear, idx[BF_LSQ_MAX], e[BF_LSQ_MAX], nf = 0, i, j;
    const double *G = acc + 1 + K, *b = acc + 1;
    /* only the first nf (nf x nf) entries are set and read */
    double Gf[BF_LSQ_MAX * BF_LSQ_MAX], bf[BF_LSQ_MAX], lf[BF_LSQ_MAX];
    double hf[BF_LSQ_MAX], c[BF_LSQ_MAX], held = 0.0;
    for (i = 0; i < K; i++) {
        e[i] = st->vindex[pb->ly.linear[i] * pb->nc + m];
        if (!st->fixed[e[i]]) idx[nf++] = i;
    }
    for (i = 0; i < K; i++) /* the constant part of the held colours */
        if (st->fixed[e[i]]) {
            double gc = 0.0;
            for (j = 0; j < K; j++)
                if (st->fixed[e[j]]) gc += G[i * K + j] * st->p[e[j]];
            held += st->p[e[i]] * (gc - 2.0 * b[i]);
        }
    for (i = 0; i < nf; i++) {
        bf[i] = b[idx[i]];
        for (j = 0; j < K; j++)
            if (st->fixed[e[j]]) bf[i] -= G[idx[i] * K + j] * st->p[e[j]];
        for (j = 0; j < nf; j++) Gf[i * nf + j] = G[idx[i] * K + idx[j]];
        lf[i] = lo[idx[i]];
        hf[i] = hi[idx[i]];
    }
    held +=
        quick ? bf_bounded_lsq_quick(nf, Gf, bf, lf, hf, c) : bf_bounded_lsq(nf, Gf, bf, lf, hf, c);
    for (i = 0; i < nf; i++) st->p[e[idx[i]]] = c[i];
    return fmax(acc[0] + held, 0.0);
}

/* The colours of every channel from the sums in st->acc. */
static void solve(bf_stage *st, double *cost, int quick)
{
    const bf_problem *pb = &st->pb;
    size_t K = pb->ly.n_linear, stride = 1 + K + K * K, m, q;
    double lo[BF_LSQ_MAX], hi[BF_LSQ_MAX], total = 0.0;
    for (q = 0; q < K; q++) {
        size_t e = st->vindex[pb->ly.linear[q] * pb->nc];
        lo[q] = st->lower[e];
        hi[q] = st->upper[e];
    }
    for (m = 0; m < pb->nc; m++)
        total += channel_colours(st, m, st->acc + m * stride, lo, hi, quick);
    *cost = total;
}

void bf_varpro_solve(bf_stage *st, double *cost)
{
    solve(st, cost, 1);
}

brdffit_status bf_varpro_profile(bf_stage *st, bf_pass_kind kind, double *cost)
{
    BF_RETURN_IF_ERROR(bf_stage_pass(st, kind));
    solve(st, cost, 0);
    return BRDFFIT_OK;
}
