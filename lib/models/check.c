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

/* The finite-difference stencils, in the order they are tried. */
typedef enum stencil_kind { STENCIL_CENTRAL, STENCIL_FORWARD, STENCIL_BACKWARD } stencil_kind;

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
 * has room for two steps; no check when neither side has. A stencil point
 * that overflows to infinity counts as outside the bounds. */
static int stencil_fits(stencil_kind kind, double x, double h, const brdffit_param_info *p)
{
    const double lo = kind == STENCIL_CENTRAL ? x - h : kind == STENCIL_FORWARD ? x : x - 2.0 * h;
    const double hi = kind == STENCIL_CENTRAL ? x + h : kind == STENCIL_FORWARD ? x + 2.0 * h : x;
    return isfinite(lo) && isfinite(hi) && lo >= p->lower && hi <= p->upper;
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

/* Values with entry j moved to x_j + delta. Infinite values there (and no
 * NaN) set *over: the step left the model's range of finite values, which
 * is the check's problem, not the model's. */
static brdffit_status eval_shifted(jc_work *w, size_t j, double delta, size_t first, size_t count,
                                   double *out, int *over)
{
    const double x = w->x[j];
    const size_t n = w->nc * count;
    brdffit_batch batch;
    brdffit_status st;
    size_t i;
    w->x[j] = x + delta;
    bf_geometry_batch(&w->grid->geo, first, count, &batch);
    st = bf_model_eval(w->m, &batch, w->x, w->nc, out, NULL, w->err);
    w->x[j] = x;
    BF_RETURN_IF_ERROR(st);
    for (i = 0; i < n && !isnan(out[i]); i++) *over |= isinf(out[i]);
    if (i == n && *over) return BRDFFIT_OK;
    *over = 0;
    return bf_model_check_outputs(w->m, count, w->nc, out, NULL, first, w->err);
}

/* Numeric derivative and rounding bound of value i from the stencil's
 * values; values near DBL_MAX are divided by 2h before they are combined.
 * Returns 0 when the derivative is beyond the range of doubles. */
static int difference(jc_work *w, stencil_kind kind, double h, size_t i)
{
    const double a = w->fa[i], b = w->fb[i], z = w->f0[i], s = 2.0 * h;
    const double sign = kind == STENCIL_BACKWARD ? -1.0 : 1.0;
    if (kind == STENCIL_CENTRAL) {
        w->num[i] = (a - b) / s;
        w->rnd[i] = BF_ROUNDING / s * (fabs(a) + fabs(b));
        if (!isfinite(w->num[i]) || !isfinite(w->rnd[i])) {
            w->num[i] = a / s - b / s;
            w->rnd[i] = BF_ROUNDING * (fabs(a) / s + fabs(b) / s);
        }
    } else {
        w->num[i] = sign * (-3.0 * z + 4.0 * a - b) / s;
        w->rnd[i] = BF_ROUNDING / s * (3.0 * fabs(z) + 4.0 * fabs(a) + fabs(b));
        if (!isfinite(w->num[i]) || !isfinite(w->rnd[i])) {
            w->num[i] = sign * (-3.0 * (z / s) + 4.0 * (a / s) - b / s);
            w->rnd[i] = BF_ROUNDING * (3.0 * (fabs(z) / s) + 4.0 * (fabs(a) / s) + fabs(b) / s);
        }
    }
    return isfinite(w->num[i]) && isfinite(w->rnd[i]);
}

/* w->num = numeric derivative of every value of the chunk by entry j of
 * parameter p (w->f0 must hold the values at x), from the first stencil
 * that fits the bounds and does not overflow. *usable = 0 when none does:
 * the entry cannot be checked by differences there. */
static brdffit_status numeric_entry(jc_work *w, size_t j, const brdffit_param_info *p,
                                    size_t first, size_t count, int *usable)
{
    static const double steps[3][2] = {{1.0, -1.0}, {1.0, 2.0}, {-1.0, -2.0}};
    const double h = 1e-6 * fmax(fabs(w->x[j]), 1e-3);
    const size_t n = w->nc * count;
    int kind;
    size_t i;
    *usable = 0;
    for (kind = STENCIL_CENTRAL; kind <= STENCIL_BACKWARD && !*usable; kind++) {
        int over = 0;
        if (!stencil_fits((stencil_kind)kind, w->x[j], h, p)) continue;
        BF_RETURN_IF_ERROR(eval_shifted(w, j, steps[kind][0] * h, first, count, w->fa, &over));
        if (!over)
            BF_RETURN_IF_ERROR(eval_shifted(w, j, steps[kind][1] * h, first, count, w->fb, &over));
        for (i = 0, *usable = !over; i < n && *usable; i++)
            *usable = difference(w, (stencil_kind)kind, h, i);
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
            int usable;
            BF_RETURN_IF_ERROR(numeric_entry(w, j, p, first, count, &usable));
            if (!usable) continue;
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
