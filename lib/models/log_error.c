/* The look error: the compressive log error of a model against a grid's
 * values over the samples within a cap,
 *
 *     sqrt(sum a_s d_sc^2 / sum a_s),  d = ln(1 + cos(theta_i) M) - ln(1 + cos(theta_i) R),
 *
 * a_s the solid-angle weight of brdffit_grid_weights(), both sums over the
 * present values of the channels asked for. The same figure whatever a fit
 * minimised. */
#include <math.h>

#include "core/core.h"
#include "grid/grid_internal.h"
#include "models/model_internal.h"

#define ALL_CHANNELS ((size_t)-1)

typedef struct log_sums {
    double num, den;
} log_sums;

static int is_missing(const brdffit_grid *g, size_t s, size_t c)
{
    return g->missing != NULL && g->missing[c * g->n_samples + s];
}

/* Adds chunk [first, first + count) with weights w and model values m
 * (m[c * count + t]) to the sums. */
static brdffit_status add_chunk(const brdffit_model *model, const brdffit_grid *g, size_t channel,
                                size_t first, size_t count, const double *w, const double *m,
                                log_sums *sums, brdffit_error *err)
{
    size_t t, c, nc = g->n_channels;
    for (c = 0; c < nc; c++) {
        if (channel != ALL_CHANNELS && c != channel) continue;
        for (t = 0; t < count; t++) {
            size_t s = first + t;
            double ci = g->geo.lz[s] > 0.0 ? g->geo.lz[s] : 0.0, mv = m[c * count + t], d;
            if (is_missing(g, s, c)) continue;
            if (mv < 0.0)
                return bf_fail(err, BRDFFIT_E_RANGE,
                               "model \"%s\" is negative (%g) at grid sample %zu, channel %zu",
                               model->name, mv, s, c);
            d = log1p(ci * mv) - log1p(ci * g->values[c * g->n_samples + s]);
            sums->num += w[t] * d * d;
            sums->den += w[t];
        }
    }
    return BRDFFIT_OK;
}

static brdffit_status check_args(const brdffit_model *model, const brdffit_grid *grid,
                                 const double *params, size_t channel, const double *out,
                                 brdffit_error *err)
{
    if (model == NULL || grid == NULL || params == NULL || out == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "model, grid, params or out is NULL");
    if (!bf_model_ok(model))
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "model handle is invalid or was destroyed");
    if (!bf_grid_ok(grid))
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid handle is invalid or was destroyed");
    if (channel != ALL_CHANNELS && channel >= grid->n_channels)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "channel %zu: the grid has %zu", channel,
                       grid->n_channels);
    return BRDFFIT_OK;
}

static brdffit_status accumulate(const brdffit_model *model, const brdffit_grid *grid,
                                 const double *params, size_t channel, const bf_weight_plan *plan,
                                 double *m, log_sums *sums, brdffit_error *err)
{
    double w[BF_CHUNK];
    size_t k, first, count;
    for (k = 0; k < plan->n_chunks; k++) {
        bf_weight_plan_chunk(plan, k, &first, &count, w);
        BF_RETURN_IF_ERROR(
            brdffit_model_eval_grid(model, grid, first, count, params, m, NULL, err));
        BF_RETURN_IF_ERROR(add_chunk(model, grid, channel, first, count, w, m, sums, err));
    }
    return BRDFFIT_OK;
}

brdffit_status brdffit_model_log_error(const brdffit_model *model, const brdffit_grid *grid,
                                       const double *params, double cap, size_t channel,
                                       double *out, brdffit_error *err)
{
    bf_weight_plan plan;
    log_sums sums = {0.0, 0.0};
    double *m;
    brdffit_status st;
    BF_RETURN_IF_ERROR(check_args(model, grid, params, channel, out, err));
    BF_RETURN_IF_ERROR(
        bf_weight_plan_init(&plan, grid, cap, BRDFFIT_WEIGHT_SOLID_ANGLE, &model->alloc, err));
    m = bf_calloc(&model->alloc, grid->n_channels, BF_CHUNK * sizeof(double));
    if (m == NULL) {
        bf_weight_plan_free(&plan, &model->alloc);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory for the log error");
    }
    st = accumulate(model, grid, params, channel, &plan, m, &sums, err);
    bf_free(&model->alloc, m);
    bf_weight_plan_free(&plan, &model->alloc);
    if (st != BRDFFIT_OK) return st;
    if (!(sums.den > 0.0))
        return bf_fail(err, BRDFFIT_E_NO_DATA,
                       "no present value with a non-zero weight lies within the cap of %g rad",
                       cap);
    *out = sqrt(sums.num / sums.den);
    return BRDFFIT_OK;
}
