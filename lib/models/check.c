/* brdffit_model_check_jacobian(): a model's analytic Jacobian against
 * finite differences over every sample of a grid.
 *
 * The grid is walked in chunks of BF_CHUNK samples, twice: the first walk
 * finds, for every parameter and channel, the largest resolvable numeric
 * derivative s (|numeric| minus its rounding bound); the second compares
 * the analytic derivatives with the numeric ones. Memory stays
 * proportional to one chunk. The metric is documented at the declaration
 * in model.h. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"
#include "models/model_internal.h"

/* Relative rounding error allowed for each value a stencil uses: the
 * rounding bound of a numeric derivative is BF_ROUNDING sum |w_i f_i| / 2h. */
#define BF_ROUNDING (16.0 * DBL_EPSILON)

/* The finite-difference stencil of one vector entry. */
typedef enum stencil_kind {
    STENCIL_SKIP,
    STENCIL_CENTRAL,
    STENCIL_FORWARD,
    STENCIL_BACKWARD
} stencil_kind;

typedef struct stencil {
    stencil_kind kind;
    double h;
} stencil;

typedef struct jc_work {
    const brdffit_model *m;
    const brdffit_grid *grid;
    size_t nc, nv;
    double *x;     /* the parameter vector, perturbed one entry at a time (nv) */
    double *jac;   /* analytic Jacobian of one chunk (n_params * nc * BF_CHUNK) */
    double *f0;    /* values at x (nc * BF_CHUNK) */
    double *fa;    /* values at the first stencil point */
    double *fb;    /* values at the second stencil point */
    double *num;   /* numeric derivative of one entry */
    double *rnd;   /* its rounding bound */
    double *scale; /* largest |numeric| per parameter and channel (n_params * nc) */
    brdffit_jacobian_report *report;
    brdffit_error *err;
} jc_work;

/* Central differences with h = 1e-6 max(|x|, 1e-3) when x +- h lie within
 * the bounds; otherwise the second-order one-sided stencil on the side that
 * has room for two steps; no check when neither side has. */
static stencil choose_stencil(double x, const brdffit_param_info *p)
{
    stencil st;
    st.h = 1e-6 * fmax(fabs(x), 1e-3);
    if (x - st.h >= p->lower && x + st.h <= p->upper)
        st.kind = STENCIL_CENTRAL;
    else if (x + 2.0 * st.h <= p->upper)
        st.kind = STENCIL_FORWARD;
    else if (x - 2.0 * st.h >= p->lower)
        st.kind = STENCIL_BACKWARD;
    else
        st.kind = STENCIL_SKIP;
    return st;
}

/* Values of samples [first, first + count) at w->x into out (and the
 * Jacobian into w->jac when `with_jacobian`), checked for NaN and Inf. */
static brdffit_status eval_chunk(jc_work *w, size_t first, size_t count, double *out,
                                 int with_jacobian)
{
    brdffit_batch batch;
    double *jac = with_jacobian ? w->jac : NULL;
    bf_geometry_batch(&w->grid->geo, first, count, &batch);
    BF_RETURN_IF_ERROR(bf_model_eval(w->m, &batch, w->x, w->nc, out, jac, w->err));
    return bf_model_check_outputs(w->m, count, w->nc, out, jac, first, w->err);
}

/* Values with entry j moved to x_j + delta. */
static brdffit_status eval_shifted(jc_work *w, size_t j, double delta, size_t first, size_t count,
                                   double *out)
{
    const double x = w->x[j];
    brdffit_status st;
    w->x[j] = x + delta;
    st = eval_chunk(w, first, count, out, 0);
    w->x[j] = x;
    return st;
}

/* w->num = numeric derivative of every value of the chunk by entry j
 * (w->f0 must hold the values at x). */
static brdffit_status numeric_entry(jc_work *w, size_t j, stencil st, size_t first, size_t count)
{
    const size_t n = w->nc * count;
    const double h = st.h, r = BF_ROUNDING / (2.0 * h);
    const double *f0 = w->f0, *fa = w->fa, *fb = w->fb;
    size_t i;
    if (st.kind == STENCIL_CENTRAL) {
        BF_RETURN_IF_ERROR(eval_shifted(w, j, h, first, count, w->fa));
        BF_RETURN_IF_ERROR(eval_shifted(w, j, -h, first, count, w->fb));
        for (i = 0; i < n; i++) {
            w->num[i] = (fa[i] - fb[i]) / (2.0 * h);
            w->rnd[i] = r * (fabs(fa[i]) + fabs(fb[i]));
        }
        return BRDFFIT_OK;
    }
    {
        const double sign = st.kind == STENCIL_FORWARD ? 1.0 : -1.0;
        BF_RETURN_IF_ERROR(eval_shifted(w, j, sign * h, first, count, w->fa));
        BF_RETURN_IF_ERROR(eval_shifted(w, j, sign * 2.0 * h, first, count, w->fb));
        for (i = 0; i < n; i++) {
            w->num[i] = sign * (-3.0 * f0[i] + 4.0 * fa[i] - fb[i]) / (2.0 * h);
            w->rnd[i] = r * (3.0 * fabs(f0[i]) + 4.0 * fabs(fa[i]) + fabs(fb[i]));
        }
    }
    return BRDFFIT_OK;
}

static void update_scale(jc_work *w, size_t k, size_t c, size_t count)
{
    const double *nu = w->num + c * count, *rd = w->rnd + c * count;
    double *s = &w->scale[k * w->nc + c];
    size_t i;
    for (i = 0; i < count; i++) *s = fmax(*s, fabs(nu[i]) - rd[i]);
}

static void compare(jc_work *w, size_t k, size_t c, size_t first, size_t count)
{
    const double tiny = 1e-6 * w->scale[k * w->nc + c];
    const double *an = w->jac + (k * w->nc + c) * count;
    const double *nu = w->num + c * count, *rd = w->rnd + c * count;
    brdffit_jacobian_report *r = w->report;
    size_t i;
    for (i = 0; i < count; i++) {
        const double den = fmax(fabs(nu[i]), tiny);
        const double d = fmax(fabs(an[i] - nu[i]) - rd[i], 0.0);
        const double e = den > 0.0 ? d / den : d;
        if (!(e > r->worst_error)) continue;
        r->worst_error = e;
        r->param = k;
        r->channel = c;
        r->sample = first + i;
        r->analytic = an[i];
        r->numeric = nu[i];
    }
}

/* One walk over a chunk: every vector entry's numeric derivative, then
 * either the scale update (compare_pass 0) or the comparison. */
static brdffit_status walk_chunk(jc_work *w, size_t first, size_t count, int compare_pass)
{
    size_t k, e, c, j = 0;
    BF_RETURN_IF_ERROR(eval_chunk(w, first, count, w->f0, compare_pass));
    for (k = 0; k < w->m->n_params; k++) {
        const brdffit_param_info *p = &w->m->params[k];
        const int per = (p->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        for (e = 0; e < (per ? w->nc : 1); e++, j++) {
            const stencil st = choose_stencil(w->x[j], p);
            if (st.kind == STENCIL_SKIP) continue;
            BF_RETURN_IF_ERROR(numeric_entry(w, j, st, first, count));
            for (c = per ? e : 0; c < (per ? e + 1 : w->nc); c++) {
                if (compare_pass)
                    compare(w, k, c, first, count);
                else
                    update_scale(w, k, c, count);
            }
        }
    }
    return BRDFFIT_OK;
}

static brdffit_status walk_grid(jc_work *w, int compare_pass)
{
    size_t first, count;
    for (first = 0; first < w->grid->n_samples; first += count) {
        count = w->grid->n_samples - first;
        if (count > BF_CHUNK) count = BF_CHUNK;
        BF_RETURN_IF_ERROR(walk_chunk(w, first, count, compare_pass));
    }
    return BRDFFIT_OK;
}

/* Every entry finite and within its parameter's bounds. */
static brdffit_status check_vector(const brdffit_model *m, size_t nc, const double *x,
                                   brdffit_error *err)
{
    size_t k, e, j = 0;
    for (k = 0; k < m->n_params; k++) {
        const brdffit_param_info *p = &m->params[k];
        const size_t width = (p->flags & BRDFFIT_PARAM_PER_CHANNEL) ? nc : 1;
        for (e = 0; e < width; e++, j++) {
            if (isfinite(x[j]) && x[j] >= p->lower && x[j] <= p->upper) continue;
            return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                           "model \"%s\": parameter \"%s\" (vector entry %zu) is %g, "
                           "outside [%g, %g]",
                           m->name, p->name, j, x[j], p->lower, p->upper);
        }
    }
    return BRDFFIT_OK;
}

/* Allocate the work arrays as one block (owned by w->jac). */
static brdffit_status alloc_work(jc_work *w, brdffit_error *err)
{
    size_t per_values, n_jac, n_scale, total;
    double *p;
    if (!bf_mul_size(w->nc, BF_CHUNK, &per_values) ||
        !bf_mul_size(per_values, w->m->n_params, &n_jac) ||
        !bf_mul_size(w->nc, w->m->n_params, &n_scale) || !bf_add_size(n_jac, n_scale, &total) ||
        !bf_add_size(total, w->nv, &total) || per_values > SIZE_MAX / 5 ||
        !bf_add_size(total, 5 * per_values, &total))
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "model \"%s\": Jacobian check size overflows",
                       w->m->name);
    p = bf_calloc(&w->m->alloc, total, sizeof(double));
    if (p == NULL)
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory checking model \"%s\"",
                       w->m->name);
    w->jac = p;
    w->scale = w->jac + n_jac;
    w->x = w->scale + n_scale;
    w->f0 = w->x + w->nv;
    w->fa = w->f0 + per_values;
    w->fb = w->fa + per_values;
    w->num = w->fb + per_values;
    w->rnd = w->num + per_values;
    return BRDFFIT_OK;
}

static brdffit_status check_args(const brdffit_model *model, const brdffit_grid *grid,
                                 const double *params, const brdffit_jacobian_report *report,
                                 brdffit_error *err)
{
    const size_t need = offsetof(brdffit_jacobian_report, numeric) + sizeof(double);
    if (model == NULL || grid == NULL || params == NULL || report == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "model, grid, params or report is NULL");
    if (!bf_model_ok(model))
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "model handle is invalid or was destroyed");
    if (!bf_grid_ok(grid))
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid handle is invalid or was destroyed");
    if (report->struct_size < need)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                       "report struct_size %zu is too small (at least %zu)", report->struct_size,
                       need);
    if (brdffit_model_vector_size(model, grid->n_channels) == 0)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "model \"%s\": parameter vector too large",
                       model->name);
    return check_vector(model, grid->n_channels, params, err);
}

brdffit_status brdffit_model_check_jacobian(const brdffit_model *model, const brdffit_grid *grid,
                                            const double *params, brdffit_jacobian_report *report,
                                            brdffit_error *err)
{
    jc_work w;
    brdffit_status st;
    BF_RETURN_IF_ERROR(check_args(model, grid, params, report, err));
    memset(&w, 0, sizeof w);
    w.m = model;
    w.grid = grid;
    w.nc = grid->n_channels;
    w.nv = brdffit_model_vector_size(model, w.nc);
    w.report = report;
    w.err = err;
    BF_RETURN_IF_ERROR(alloc_work(&w, err));
    memcpy(w.x, params, w.nv * sizeof(double));
    report->worst_error = 0.0;
    report->param = report->channel = report->sample = 0;
    report->analytic = report->numeric = 0.0;
    st = walk_grid(&w, 0);
    if (st == BRDFFIT_OK) st = walk_grid(&w, 1);
    bf_free(&model->alloc, w.jac);
    return st;
}
