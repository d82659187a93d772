/* Physical plausibility: see plausible.h.
 *
 * At one shape the model is linear in its colours, and so is each term's
 * directional albedo: term q with colour c_q reflects c_q A_q(theta_i) of
 * the light from theta_i, A_q the albedo of the term with colour 1. So
 * c_q <= 1 / max A_q is a box bound that the profile (varpro.h,
 * profile_gn.h) and the polish honour exactly at that shape.
 *
 * Setting 1 (the default) takes the cheap bounds everywhere, scan and
 * polish: cd <= 1, and for a built-in model's specular lobe 1 / A from
 * the lobe's tabulated albedo (models/lobes.h; an upper bound on A, so the
 * colour bound is at most 0.1 % + the table's step tighter than the true
 * one). Setting 2 takes the full integral at every polish start and
 * result instead (it costs about as much as a pass over a large grid per
 * term): the albedo of all K terms from one brdffit_model_albedo() call
 * with K channels, channel j holding colour 1 in term j and 0 in the
 * others; its scan keeps the cheap bounds. */
#include "fit/plausible.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "models/lobes.h"

/* Incidence angles (degrees) over which the largest albedo is taken. */
static const double ANGLES_DEG[] = BF_ALBEDO_ANGLES_DEG;
#define N_ANGLES (sizeof ANGLES_DEG / sizeof ANGLES_DEG[0])

static int has_param(const brdffit_model *model, const char *name, size_t *index)
{
    size_t k, n = brdffit_model_param_count(model);
    for (k = 0; k < n; k++)
        if (strcmp(brdffit_model_param(model, k)->name, name) == 0) {
            if (index != NULL) *index = k;
            return 1;
        }
    return 0;
}

/* The K-channel vector of unit terms at the shape of st->p into v. */
static void unit_terms(const bf_stage *st, size_t K, double *v)
{
    const bf_problem *pb = &st->pb;
    const brdffit_model *model = pb->model;
    size_t k, j, q;
    for (k = 0; k < pb->ly.n_params; k++)
        for (j = 0; j < K; j++)
            v[brdffit_model_vector_index(model, k, j, K)] = st->p[st->vindex[k * pb->nc]];
    for (q = 0; q < K; q++)
        for (j = 0; j < K; j++)
            v[brdffit_model_vector_index(model, pb->ly.linear[q], j, K)] = q == j ? 1.0 : 0.0;
}

/* bound[q]: the upper bound of colour q at the shape of st->p. */
static brdffit_status term_bounds(bf_stage *st, size_t K, double *bound)
{
    const brdffit_model *model = st->pb.model;
    const brdffit_allocator *a = &st->run->fit->alloc;
    size_t nv = brdffit_model_vector_size(model, K), q, t;
    double angles[N_ANGLES], *v = bf_calloc(a, nv + N_ANGLES * K, sizeof *v);
    brdffit_status status;
    if (v == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    for (t = 0; t < N_ANGLES; t++) angles[t] = ANGLES_DEG[t] * BF_PI / 180.0;
    unit_terms(st, K, v);
    status = brdffit_model_albedo(model, v, K, angles, N_ANGLES, 0, v + nv, &st->err);
    for (q = 0; status == BRDFFIT_OK && q < K; q++) {
        double top = 0.0;
        for (t = 0; t < N_ANGLES; t++) top = fmax(top, v[nv + t * K + q]);
        bound[q] = top > 0.0 ? 1.0 / top : HUGE_VAL;
    }
    if (status != BRDFFIT_OK) st->status = status;
    bf_free(a, v);
    return status;
}

/* The cheap bound: a diffuse colour cd <= 1 (the albedo of a Lambertian
 * cd; the substrate's reflectance of the Fresnel model, Ashikhmin and
 * Shirley 2000, whose bound closes the valley Rs -> 1, cd -> inf). */
static void diffuse_bound(const bf_stage *st, size_t K, double *bound)
{
    size_t q, cd;
    if (!has_param(st->pb.model, "cd", &cd)) return;
    for (q = 0; q < K; q++)
        if (st->pb.ly.linear[q] == cd) bound[q] = fmin(bound[q], 1.0);
}

/* The value of declared shared parameter k at the shape of st->p. */
static double shape_value(const bf_stage *st, size_t k)
{
    return st->p[st->vindex[k * st->pb.nc]];
}

/* The cheap lobe bounds: colour <= 1 / A, A the tabulated bound on the
 * lobe's largest albedo at the shape of st->p (built-in models only). */
static void lobe_bounds(const bf_stage *st, size_t K, double *bound)
{
    const bf_lobes *lobes = bf_model_lobes(st->pb.model);
    size_t l, q;
    for (l = 0; lobes != NULL && l < lobes->n; l++) {
        const bf_lobe_desc *d = &lobes->lobe[l];
        double f = d->fresnel == BF_NO_PARAM ? 1.0 : shape_value(st, d->fresnel);
        double top = bf_lobe_albedo_bound(d, shape_value(st, d->shape), f);
        for (q = 0; q < K; q++)
            if (st->pb.ly.linear[q] == d->colour && top > 0.0)
                bound[q] = fmin(bound[q], 1.0 / top);
    }
}

/* Whether plausibility bounds the stage's colours at all: an affine
 * model's colour (layout.h) keeps its declared bounds (its unit term
 * carries the colour-free offset, no albedo of c alone). */
static int bounded(const bf_stage *st)
{
    size_t K = st->pb.ly.n_linear;
    return st->run->fit->plausible && K > 0 && K <= BF_LSQ_MAX && !st->pb.ly.offset;
}

int bf_plausible_cheap(const bf_stage *st, double *bound)
{
    size_t K = st->pb.ly.n_linear, q;
    if (!bounded(st)) return 0;
    for (q = 0; q < K; q++) bound[q] = HUGE_VAL;
    lobe_bounds(st, K, bound);
    diffuse_bound(st, K, bound);
    return 1;
}

brdffit_status bf_plausible_bounds(bf_stage *st, int full)
{
    size_t K = st->pb.ly.n_linear, q;
    double bound[BF_LSQ_MAX];
    if (!(full && st->run->fit->plausible >= 2)) {
        if (bf_plausible_cheap(st, bound)) bf_plausible_apply(st, bound);
        return BRDFFIT_OK;
    }
    if (!bounded(st)) return BRDFFIT_OK;
    for (q = 0; q < K; q++) bound[q] = HUGE_VAL;
    BF_RETURN_IF_ERROR(term_bounds(st, K, bound));
    diffuse_bound(st, K, bound);
    bf_plausible_apply(st, bound);
    return BRDFFIT_OK;
}

void bf_plausible_apply(bf_stage *st, const double *bound)
{
    const bf_problem *pb = &st->pb;
    size_t K = pb->ly.n_linear, q, m;
    for (q = 0; q < K; q++) {
        double declared = brdffit_model_param(pb->model, pb->ly.linear[q])->upper;
        for (m = 0; m < pb->nc; m++) {
            size_t e = st->vindex[pb->ly.linear[q] * pb->nc + m];
            double hi = fmax(fmin(declared, bound[q]), st->lower[e]);
            if (st->fixed[e]) continue;
            st->upper[e] = hi;
            st->oupper[e] = st->logs[e] ? log(hi) : hi;
        }
    }
}

int bf_plausible_within(const bf_stage *st, const double *params)
{
    const bf_problem *pb = &st->pb;
    size_t q, m;
    for (q = 0; q < pb->ly.n_linear && q < BF_LSQ_MAX; q++)
        for (m = 0; m < pb->nc; m++) {
            size_t e = st->vindex[pb->ly.linear[q] * pb->nc + m];
            if (params[e] > st->upper[e] * (1.0 + 1e-9)) return 0;
        }
    return 1;
}

void bf_plausible_clamp(const bf_stage *st, double *params)
{
    const bf_problem *pb = &st->pb;
    size_t q, m;
    for (q = 0; q < pb->ly.n_linear && q < BF_LSQ_MAX; q++)
        for (m = 0; m < pb->nc; m++) {
            size_t e = st->vindex[pb->ly.linear[q] * pb->nc + m];
            if (params[e] > st->upper[e]) params[e] = st->upper[e];
        }
}
