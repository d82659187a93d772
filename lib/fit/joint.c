/* The pipelines that start from the start values: joint (one LM run over
 * every parameter of every channel) and two-stage (the thesis's method:
 * the shape and mean colours fitted to the channel mean, then each
 * channel's colours with the shape held). */
#include <string.h>

#include "core/core.h"
#include "fit/pipelines.h"

brdffit_status bf_pipeline_joint(bf_run *run)
{
    bf_result *r = run->result;
    bf_stage st;
    brdffit_status status = bf_stage_init(&st, run, run->fit->nc, BF_SOURCE_CHANNELS, 0, 0);
    if (status != BRDFFIT_OK) return status;
    st.kind = BRDFFIT_STAGE_JOINT;
    status = bf_stage_lm(&st, st.base, r->params, r->std_errors);
    if (status == BRDFFIT_OK && r->cov != NULL)
        memcpy(r->cov, st.cov, st.n * st.n * sizeof *r->cov);
    if (status == BRDFFIT_OK) status = bf_result_keep_report(r, st.opt, &run->fit->alloc);
    bf_stage_free(&st);
    return status;
}

/* The covariance of channel c's entries (the run's result is zero
 * elsewhere): shared with shared from stage 1, per-channel with
 * per-channel from stage 2 (`second`, when given), 0 between the two (the
 * stages estimate them apart: stage 2 holds the shape); all 0 when
 * `first_se` is 0, as place_channel() sets the standard errors. */
static void place_covariance(bf_run *run, const bf_stage *first, int first_se,
                             const bf_stage *second, size_t c)
{
    const brdffit_model *model = run->fit->model;
    size_t nc = run->fit->nc, nv = run->fit->n_vec, np = first->pb.ly.n_params, k, l;
    double *cov = run->result->cov;
    if (cov == NULL) return;
    for (k = 0; k < np; k++) {
        size_t to = brdffit_model_vector_index(model, k, c, nc);
        int per_k = (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        for (l = 0; l < np; l++) {
            size_t at = brdffit_model_vector_index(model, l, c, nc);
            int per_l = (brdffit_model_param(model, l)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
            double v = 0.0;
            if (second != NULL && per_k && per_l)
                v = second->cov[second->vindex[k] * second->n + second->vindex[l]];
            else if (first_se && (second == NULL || (!per_k && !per_l)))
                v = first->cov[first->vindex[k] * first->n + first->vindex[l]];
            cov[to * nv + at] = v;
        }
    }
}

/* Stage 1's result (natural units, nc = 1 layout) for channel c of the
 * result, its standard errors zero when `se1` is NULL; per-channel entries
 * of stage 2 (`p2`, `se2`) when given; and their covariance. */
static void place_channel(bf_run *run, const bf_stage *first, const double *p1, const double *se1,
                          const bf_stage *second, const double *p2, const double *se2, size_t c)
{
    const brdffit_model *model = run->fit->model;
    size_t nc = run->fit->nc, k;
    for (k = 0; k < first->pb.ly.n_params; k++) {
        size_t to = brdffit_model_vector_index(model, k, c, nc), from = first->vindex[k];
        int per = (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        if (second != NULL && per) {
            run->result->params[to] = p2[second->vindex[k]];
            run->result->std_errors[to] = se2[second->vindex[k]];
        } else {
            run->result->params[to] = p1[from];
            run->result->std_errors[to] = se1 != NULL ? se1[from] : 0.0;
        }
    }
    place_covariance(run, first, se1 != NULL, second, c);
}

/* Stage 2 of the thesis: channel c's per-channel parameters with the shape
 * of stage 1 (p1, se1) held. `work` has 2 n doubles. */
static brdffit_status second_stage(bf_run *run, const bf_stage *first, const double *p1,
                                   const double *se1, size_t c, int last, double *work)
{
    bf_stage st;
    brdffit_status status = bf_stage_init(&st, run, 1, BF_SOURCE_ONE_CHANNEL, c, 1);
    if (status != BRDFFIT_OK) return status;
    st.kind = BRDFFIT_STAGE_CHANNEL;
    st.label = c;
    status = bf_stage_lm(&st, p1, work, work + st.n);
    if (status == BRDFFIT_OK) place_channel(run, first, p1, se1, &st, work, work + st.n, c);
    if (status == BRDFFIT_OK && last)
        status = bf_result_keep_report(run->result, st.opt, &run->fit->alloc);
    bf_stage_free(&st);
    return status;
}

/* Stage 1, then stage 2 for every channel; a cancel between stages
 * reports stage 1 for the channels not reached. `work` has 4 n doubles. */
static brdffit_status two_stages(bf_run *run, bf_stage *first, double *work)
{
    size_t c, n = first->n, nc = run->fit->nc;
    double *p1 = work, *se1 = work + n;
    brdffit_status status;
    first->kind = BRDFFIT_STAGE_MEAN;
    status = bf_stage_lm(first, first->base, p1, se1);
    for (c = 0; status == BRDFFIT_OK && c < nc && !run->cancelled; c++)
        status = second_stage(run, first, p1, se1, c, c + 1 == nc, work + 2 * n);
    if (status != BRDFFIT_OK || !run->cancelled || c == nc) return status;
    for (; c < nc; c++) place_channel(run, first, p1, NULL, NULL, NULL, NULL, c);
    return bf_result_keep_report(run->result, first->opt, &run->fit->alloc);
}

brdffit_status bf_pipeline_two_stage(bf_run *run)
{
    bf_stage first;
    double *work;
    brdffit_status status = bf_stage_init(&first, run, 1, BF_SOURCE_MEAN, 0, 0);
    if (status != BRDFFIT_OK) return status;
    work = bf_calloc(&run->fit->alloc, 4 * first.n, sizeof *work);
    status = work != NULL ? two_stages(run, &first, work) : BRDFFIT_E_OUT_OF_MEMORY;
    bf_free(&run->fit->alloc, work);
    bf_stage_free(&first);
    return status;
}
