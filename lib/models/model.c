/* The model handle: creation from a definition, metadata, the layout of the
 * parameter vector, and evaluation with its checks. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"
#include "models/model_internal.h"

/* Largest number of declared parameters of a user model. */
#define BF_MAX_PARAMS 1024
#define BF_KNOWN_FLAGS                                                                       \
    ((unsigned)(BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR | BRDFFIT_PARAM_LOG_SCALE | \
                BRDFFIT_PARAM_FIXED))
/* create_custom reads every field up to and including destroy. */
#define BF_DEF_MIN_SIZE (offsetof(brdffit_model_def, destroy) + sizeof(void (*)(void *)))

void brdffit_model_def_init(brdffit_model_def *def)
{
    const brdffit_model_def init = BRDFFIT_MODEL_DEF_INIT;
    if (def != NULL) *def = init;
}

int bf_model_ok(const brdffit_model *m)
{
    return m != NULL && m->magic == BF_MAGIC_MODEL;
}

static brdffit_status check_model(const brdffit_model *m, brdffit_error *err)
{
    if (m == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "model is NULL");
    if (m->magic != BF_MAGIC_MODEL)
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "model handle is invalid or was destroyed");
    return BRDFFIT_OK;
}

/* --- creation ------------------------------------------------------------- */

static brdffit_status check_param(const brdffit_param_info *p, size_t index, brdffit_error *err)
{
    const brdffit_status bad = BRDFFIT_E_INVALID_ARGUMENT;
    if (p->name == NULL || p->name[0] == '\0')
        return bf_fail(err, bad, "parameter %zu has no name", index);
    if (p->flags & ~BF_KNOWN_FLAGS)
        return bf_fail(err, bad, "parameter \"%s\" has unknown flag bits 0x%x", p->name,
                       p->flags & ~BF_KNOWN_FLAGS);
    if ((p->flags & BRDFFIT_PARAM_LINEAR) && !(p->flags & BRDFFIT_PARAM_PER_CHANNEL))
        return bf_fail(err, bad, "linear parameter \"%s\" must be per-channel", p->name);
    if (isnan(p->lower) || isnan(p->upper) || !isfinite(p->start))
        return bf_fail(err, bad, "parameter \"%s\": bounds must not be NaN, start must be finite",
                       p->name);
    if (!(p->lower <= p->start && p->start <= p->upper))
        return bf_fail(err, bad, "parameter \"%s\": needs lower <= start <= upper (%g, %g, %g)",
                       p->name, p->lower, p->start, p->upper);
    if ((p->flags & BRDFFIT_PARAM_LOG_SCALE) && !(p->lower > 0.0))
        return bf_fail(err, bad, "log-scale parameter \"%s\" needs lower > 0 (lower is %g)",
                       p->name, p->lower);
    return BRDFFIT_OK;
}

static brdffit_status check_params(const brdffit_param_info *params, size_t n, brdffit_error *err)
{
    size_t i, j;
    for (i = 0; i < n; i++) BF_RETURN_IF_ERROR(check_param(&params[i], i, err));
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n; j++)
            if (strcmp(params[i].name, params[j].name) == 0)
                return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                               "parameter name \"%s\" is used twice", params[i].name);
    return BRDFFIT_OK;
}

static brdffit_status check_def(const brdffit_model_def *def, brdffit_error *err)
{
    const brdffit_status bad = BRDFFIT_E_INVALID_ARGUMENT;
    if (def->struct_size < BF_DEF_MIN_SIZE)
        return bf_fail(err, bad,
                       "model definition struct_size %zu is too small (at least %zu; "
                       "initialise it with BRDFFIT_MODEL_DEF_INIT)",
                       def->struct_size, (size_t)BF_DEF_MIN_SIZE);
    if (def->name == NULL || def->name[0] == '\0')
        return bf_fail(err, bad, "model definition has no name");
    if (def->n_params == 0 || def->n_params > BF_MAX_PARAMS)
        return bf_fail(err, bad, "model \"%s\": n_params is %zu, must be 1 .. %d", def->name,
                       def->n_params, BF_MAX_PARAMS);
    if (def->params == NULL) return bf_fail(err, bad, "model \"%s\": params is NULL", def->name);
    if (def->eval == NULL) return bf_fail(err, bad, "model \"%s\": eval is NULL", def->name);
    return check_params(def->params, def->n_params, err);
}

/* Free everything the handle owns; never calls the destroy callback. */
static void free_model(brdffit_model *m)
{
    const brdffit_allocator a = m->alloc;
    size_t i;
    if (m->params != NULL)
        for (i = 0; i < m->n_params; i++) bf_free(&a, (char *)m->params[i].name);
    bf_free(&a, m->params);
    bf_free(&a, m->name);
    m->magic = BF_MAGIC_DEAD;
    bf_free(&a, m);
}

/* Copy the name and the parameter table; 0 when out of memory. */
static int copy_def(brdffit_model *m, const brdffit_model_def *def)
{
    size_t i;
    m->name = bf_strdup(&m->alloc, def->name);
    if (m->name == NULL) return 0;
    m->params = bf_calloc(&m->alloc, def->n_params, sizeof *m->params);
    if (m->params == NULL) return 0;
    m->n_params = def->n_params;
    for (i = 0; i < def->n_params; i++) {
        m->params[i] = def->params[i];
        m->params[i].name = bf_strdup(&m->alloc, def->params[i].name);
        if (m->params[i].name == NULL) return 0;
    }
    return 1;
}

brdffit_status brdffit_model_create_custom(brdffit_model **out, const brdffit_model_def *def,
                                           const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    brdffit_model *m;
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (def == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "model definition is NULL");
    if (!bf_alloc_init(&a, alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator needs both alloc and free");
    BF_RETURN_IF_ERROR(check_def(def, err));
    m = bf_calloc(&a, 1, sizeof *m);
    if (m == NULL)
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory creating model \"%s\"",
                       def->name);
    m->magic = BF_MAGIC_MODEL;
    m->alloc = a;
    if (!copy_def(m, def)) {
        free_model(m);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory creating model \"%s\"",
                       def->name);
    }
    m->eval = def->eval;
    m->user = def->user;
    m->destroy = def->destroy;
    *out = m;
    return BRDFFIT_OK;
}

void brdffit_model_destroy(brdffit_model *model)
{
    if (!bf_model_ok(model)) return;
    if (model->destroy != NULL) model->destroy(model->user);
    free_model(model);
}

/* --- metadata and the parameter vector -------------------------------------- */

const char *brdffit_model_name(const brdffit_model *model)
{
    return bf_model_ok(model) ? model->name : NULL;
}

size_t brdffit_model_param_count(const brdffit_model *model)
{
    return bf_model_ok(model) ? model->n_params : 0;
}

const brdffit_param_info *brdffit_model_param(const brdffit_model *model, size_t index)
{
    if (!bf_model_ok(model) || index >= model->n_params) return NULL;
    return &model->params[index];
}

brdffit_status brdffit_model_param_find(const brdffit_model *model, const char *name, size_t *index)
{
    size_t i;
    BF_RETURN_IF_ERROR(check_model(model, NULL));
    if (name == NULL || index == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    for (i = 0; i < model->n_params; i++) {
        if (strcmp(model->params[i].name, name) == 0) {
            *index = i;
            return BRDFFIT_OK;
        }
    }
    return BRDFFIT_E_NOT_FOUND;
}

/* Entries parameter k takes in the vector. */
static size_t param_width(const brdffit_param_info *p, size_t n_channels)
{
    return (p->flags & BRDFFIT_PARAM_PER_CHANNEL) ? n_channels : 1;
}

size_t brdffit_model_vector_size(const brdffit_model *model, size_t n_channels)
{
    size_t k, size = 0;
    if (!bf_model_ok(model) || n_channels == 0) return 0;
    for (k = 0; k < model->n_params; k++)
        if (!bf_add_size(size, param_width(&model->params[k], n_channels), &size)) return 0;
    return size;
}

size_t brdffit_model_vector_index(const brdffit_model *model, size_t param, size_t channel,
                                  size_t n_channels)
{
    size_t k, index = 0;
    if (brdffit_model_vector_size(model, n_channels) == 0) return (size_t)-1;
    if (param >= model->n_params) return (size_t)-1;
    for (k = 0; k < param; k++) index += param_width(&model->params[k], n_channels);
    if (!(model->params[param].flags & BRDFFIT_PARAM_PER_CHANNEL)) return index;
    return channel < n_channels ? index + channel : (size_t)-1;
}

brdffit_status brdffit_model_default_params(const brdffit_model *model, size_t n_channels,
                                            double *params)
{
    size_t k, c, j = 0;
    BF_RETURN_IF_ERROR(check_model(model, NULL));
    if (params == NULL || brdffit_model_vector_size(model, n_channels) == 0)
        return BRDFFIT_E_INVALID_ARGUMENT;
    for (k = 0; k < model->n_params; k++)
        for (c = 0; c < param_width(&model->params[k], n_channels); c++)
            params[j++] = model->params[k].start;
    return BRDFFIT_OK;
}

/* --- evaluation ------------------------------------------------------------- */

brdffit_status bf_model_eval(const brdffit_model *m, const brdffit_batch *batch,
                             const double *params, size_t n_channels, double *values,
                             double *jacobian, brdffit_error *err)
{
    const brdffit_status st = m->eval(batch, params, n_channels, values, jacobian, m->user);
    if (st == BRDFFIT_OK) return BRDFFIT_OK;
    return bf_fail(err, BRDFFIT_E_MODEL_FAILED, "model \"%s\" failed: its evaluation returned %s",
                   m->name, brdffit_status_name(st));
}

/* Whether every x[i] is finite (its exponent bits are not all set); an
 * integer OR reduction, which compilers vectorise. */
static size_t first_nonfinite(const double *x, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(x[i])) break;
    return i;
}

/* The declared parameter holding vector entry j. */
static size_t entry_param(const brdffit_model *m, size_t n_channels, size_t j)
{
    size_t k, end = 0;
    for (k = 0; k + 1 < m->n_params; k++) {
        end += param_width(&m->params[k], n_channels);
        if (j < end) break;
    }
    return k;
}

/* Outputs of an evaluation of n samples; `offset` is added to the sample
 * index in messages. The sizes were checked by the caller. */
brdffit_status bf_model_check_outputs(const brdffit_model *m, size_t n, size_t n_channels,
                                      const double *values, const double *jacobian, size_t offset,
                                      brdffit_error *err)
{
    const size_t per_param = n * n_channels;
    size_t i;
    if (!bf_all_finite(values, per_param)) {
        i = first_nonfinite(values, per_param);
        return bf_fail(err, BRDFFIT_E_NONFINITE,
                       "model \"%s\" produced a non-finite value (%g) at sample %zu, channel %zu",
                       m->name, values[i], offset + i % n, i / n);
    }
    if (jacobian == NULL || bf_all_finite(jacobian, per_param * m->n_params)) return BRDFFIT_OK;
    i = first_nonfinite(jacobian, per_param * m->n_params);
    return bf_fail(err, BRDFFIT_E_NONFINITE,
                   "model \"%s\" produced a non-finite derivative (%g) with respect to \"%s\" "
                   "at sample %zu, channel %zu",
                   m->name, jacobian[i], m->params[i / per_param].name, offset + i % per_param % n,
                   i % per_param / n);
}

/* Check the parameter vector and the output sizes of an evaluation of
 * `count` samples. */
static brdffit_status check_eval_args(const brdffit_model *m, size_t count, size_t n_channels,
                                      const double *params, brdffit_error *err)
{
    size_t nv = brdffit_model_vector_size(m, n_channels), total, j;
    if (n_channels == 0) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "n_channels is 0");
    if (nv == 0 || !bf_mul_size(count, n_channels, &total) ||
        !bf_mul_size(total, m->n_params, &total) || !bf_mul_size(total, sizeof(double), &total))
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "model \"%s\": evaluation size overflows",
                       m->name);
    for (j = 0; j < nv; j++)
        if (!isfinite(params[j]))
            return bf_fail(err, BRDFFIT_E_NONFINITE,
                           "model \"%s\": parameter \"%s\" (vector entry %zu) is %g", m->name,
                           m->params[entry_param(m, n_channels, j)].name, j, params[j]);
    return BRDFFIT_OK;
}

static brdffit_status check_grid(const brdffit_grid *grid, brdffit_error *err)
{
    if (grid == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "grid is NULL");
    if (!bf_grid_ok(grid))
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid handle is invalid or was destroyed");
    return BRDFFIT_OK;
}

brdffit_status brdffit_model_eval_grid(const brdffit_model *model, const brdffit_grid *grid,
                                       size_t first, size_t count, const double *params,
                                       double *values, double *jacobian, brdffit_error *err)
{
    brdffit_batch batch;
    BF_RETURN_IF_ERROR(check_model(model, err));
    BF_RETURN_IF_ERROR(check_grid(grid, err));
    if (params == NULL || values == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "params or values is NULL");
    if (first > grid->n_samples || count > grid->n_samples - first)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                       "samples %zu + %zu lie outside the grid's %zu samples", first, count,
                       grid->n_samples);
    BF_RETURN_IF_ERROR(check_eval_args(model, count, grid->n_channels, params, err));
    if (count == 0) return BRDFFIT_OK;
    bf_geometry_batch(&grid->geo, first, count, &batch);
    BF_RETURN_IF_ERROR(
        bf_model_eval(model, &batch, params, grid->n_channels, values, jacobian, err));
    return bf_model_check_outputs(model, count, grid->n_channels, values, jacobian, first, err);
}

static brdffit_status check_angle(const char *what, size_t s, double angle, int polar,
                                  brdffit_error *err)
{
    if (!isfinite(angle)) return bf_fail(err, BRDFFIT_E_RANGE, "%s[%zu] is not finite", what, s);
    if (polar && !(angle >= 0.0 && angle <= BF_HALF_PI))
        return bf_fail(err, BRDFFIT_E_RANGE, "%s[%zu] = %g lies outside [0, pi/2]", what, s, angle);
    return BRDFFIT_OK;
}

static brdffit_status check_angles(size_t count, const double *theta_i, const double *phi_i,
                                   const double *theta_o, const double *phi_o, brdffit_error *err)
{
    size_t s;
    for (s = 0; s < count; s++) {
        BF_RETURN_IF_ERROR(check_angle("theta_i", s, theta_i[s], 1, err));
        BF_RETURN_IF_ERROR(check_angle("phi_i", s, phi_i[s], 0, err));
        BF_RETURN_IF_ERROR(check_angle("theta_o", s, theta_o[s], 1, err));
        BF_RETURN_IF_ERROR(check_angle("phi_o", s, phi_o[s], 0, err));
    }
    return BRDFFIT_OK;
}

brdffit_status brdffit_model_eval_angles(const brdffit_model *model, size_t count,
                                         const double *theta_i, const double *phi_i,
                                         const double *theta_o, const double *phi_o,
                                         size_t n_channels, const double *params, double *values,
                                         double *jacobian, brdffit_error *err)
{
    bf_geometry g;
    brdffit_batch batch;
    brdffit_status st;
    size_t s;
    BF_RETURN_IF_ERROR(check_model(model, err));
    if (theta_i == NULL || phi_i == NULL || theta_o == NULL || phi_o == NULL || params == NULL ||
        values == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "an angle, params or values is NULL");
    BF_RETURN_IF_ERROR(check_eval_args(model, count, n_channels, params, err));
    BF_RETURN_IF_ERROR(check_angles(count, theta_i, phi_i, theta_o, phi_o, err));
    if (count == 0) return BRDFFIT_OK;
    if (!bf_geometry_alloc(&g, &model->alloc, count))
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory evaluating model \"%s\"",
                       model->name);
    for (s = 0; s < count; s++) bf_geometry_set(&g, s, theta_i[s], phi_i[s], theta_o[s], phi_o[s]);
    bf_geometry_batch(&g, 0, count, &batch);
    st = bf_model_eval(model, &batch, params, n_channels, values, jacobian, err);
    if (st == BRDFFIT_OK)
        st = bf_model_check_outputs(model, count, n_channels, values, jacobian, 0, err);
    bf_geometry_free(&g, &model->alloc);
    return st;
}
