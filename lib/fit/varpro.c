/* Variable projection: see varpro.h. */
#include "fit/varpro.h"

#include <math.h>

#include "core/core.h"
#include "fit/lsq.h"

brdffit_status bf_varpro_profile(bf_stage *st, double *cost)
{
    const bf_problem *pb = &st->pb;
    size_t K = pb->ly.n_linear, stride = 1 + K + K * K, m, q;
    double lo[BF_LSQ_MAX], hi[BF_LSQ_MAX], c[BF_LSQ_MAX], total = 0.0;
    for (q = 0; q < K; q++) {
        size_t e = st->vindex[pb->ly.linear[q] * pb->nc];
        lo[q] = st->lower[e];
        hi[q] = st->upper[e];
    }
    BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_VARPRO));
    for (m = 0; m < pb->nc; m++) {
        const double *acc = st->acc + m * stride;
        double f = bf_bounded_lsq(K, acc + 1 + K, acc + 1, lo, hi, c);
        total += fmax(acc[0] + f, 0.0);
        for (q = 0; q < K; q++) st->p[st->vindex[pb->ly.linear[q] * pb->nc + m]] = c[q];
    }
    *cost = total;
    return BRDFFIT_OK;
}
