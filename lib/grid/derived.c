/* The values derived from a grid, computed here only: channel values with
 * their presence, the channel mean, the clear-coat divisor, the rows of a
 * fit; used by the derived grids (brdffit_grid_channel_mean(),
 * brdffit_grid_clearcoat(), at the end of this file) and by the fit's
 * passes alike.
 * Also what other layers read of a grid, through functions rather than its
 * fields. See grid_internal.h. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"

int bf_grid_has_missing(const brdffit_grid *g)
{
    return g->missing != NULL;
}

const double *bf_grid_values(const brdffit_grid *g, size_t c)
{
    return g->values + c * g->n_samples;
}

/* Scale the values by a power of two so that the largest |value| lies in
 * [0.5, 1), then round them to single precision: within the float range
 * whatever the data's units (values below 2^-150 of the largest become 0). */
void bf_grid_store_float_values(brdffit_grid *g)
{
    size_t v, n = g->n_samples * g->n_channels;
    double top = 0.0;
    int e;
    /* as fmax(top, |value|), NaN included (it never wins), without the call */
    for (v = 0; v < n; v++) {
        double a = fabs(g->values[v]);
        top = a > top ? a : top;
    }
    g->fscale = 1.0;
    if (top > 0.0) {
        (void)frexp(top, &e); /* top = f 2^e, f in [0.5, 1) */
        g->fscale = e >= -1000 && e <= 1000 ? ldexp(1.0, -e) : 0.0;
    }
    if (g->fvalues == NULL) return;
    for (v = 0; v < n; v++) g->fvalues[v] = (float)(g->values[v] * g->fscale);
}

const float *bf_grid_fvalues(const brdffit_grid *g, size_t c)
{
    return g->fvalues == NULL ? NULL : g->fvalues + c * g->n_samples;
}

double bf_grid_fscale(const brdffit_grid *g)
{
    return g->fscale;
}

const bf_geometry *bf_grid_geometry(const brdffit_grid *g)
{
    return &g->geo;
}

void bf_grid_batch(const brdffit_grid *g, size_t first, size_t count, brdffit_batch *out)
{
    bf_geometry_batch(&g->geo, first, count, out);
}

void bf_grid_load_channel(const brdffit_grid *g, size_t c, size_t first, size_t n, double *meas,
                          double *present)
{
    const double *v = g->values + c * g->n_samples + first;
    size_t s;
    memcpy(meas, v, n * sizeof *meas);
    if (g->missing == NULL) {
        for (s = 0; s < n; s++) present[s] = 1.0;
        return;
    }
    for (s = 0; s < n; s++) present[s] = g->missing[c * g->n_samples + first + s] ? 0.0 : 1.0;
}

size_t bf_grid_sample_mean(const brdffit_grid *g, size_t s, double *mean)
{
    size_t c, n = 0;
    double sum = 0.0;
    for (c = 0; c < g->n_channels; c++) {
        if (g->missing != NULL && g->missing[c * g->n_samples + s]) continue;
        sum += g->values[c * g->n_samples + s];
        n++;
    }
    if (n > 0 && !isfinite(sum)) { /* overflow: average the scaled values */
        double top = 0.0;
        sum = 0.0;
        for (c = 0; c < g->n_channels; c++)
            if (g->missing == NULL || !g->missing[c * g->n_samples + s]) {
                sum += g->values[c * g->n_samples + s] / (double)n;
                top = fmax(top, g->values[c * g->n_samples + s]);
            }
        /* values near DBL_MAX: the rounded quotients may sum past it; the
         * mean never lies above the largest value */
        *mean = fmin(sum, top);
        return n;
    }
    *mean = n > 0 ? sum / (double)n : 0.0;
    return n;
}

void bf_grid_load_mean(const brdffit_grid *g, size_t first, size_t n, double *meas,
                       double *present)
{
    size_t s, c;
    if (g->missing != NULL) {
        for (s = 0; s < n; s++)
            present[s] = bf_grid_sample_mean(g, first + s, &meas[s]) ? 1.0 : 0.0;
        return;
    }
    /* Nothing missing: bf_grid_sample_mean's sums in the same order, one
     * channel row at a time (so the loops vectorise), and the sample's own
     * call where a sum overflows. */
    for (s = 0; s < n; s++) meas[s] = 0.0;
    for (c = 0; c < g->n_channels; c++) {
        const double *v = g->values + c * g->n_samples + first;
        for (s = 0; s < n; s++) meas[s] += v[s];
    }
    for (s = 0; s < n; s++) {
        present[s] = 1.0;
        if (isfinite(meas[s])) meas[s] /= (double)g->n_channels;
        else bf_grid_sample_mean(g, first + s, &meas[s]);
    }
}

/* Present values of the selected channel (see bf_grid_count_rows) for
 * samples [first, first + n) into present. */
static void load_present(const brdffit_grid *g, size_t channel, size_t first, size_t n,
                         double *meas, double *present)
{
    if (channel == BF_GRID_MEAN) bf_grid_load_mean(g, first, n, meas, present);
    else bf_grid_load_channel(g, channel, first, n, meas, present);
}

size_t bf_grid_count_rows(const bf_weight_plan *plan, size_t channel)
{
    const brdffit_grid *g = plan->grid;
    double w[BF_CHUNK], meas[BF_CHUNK], present[BF_CHUNK];
    size_t ci, first, n, c, s, count = 0;
    size_t c0 = channel == BF_GRID_EVERY_CHANNEL ? 0 : channel;
    size_t c1 = channel == BF_GRID_EVERY_CHANNEL ? g->n_channels : c0 + 1;
    for (ci = 0; ci < plan->n_chunks; ci++) {
        bf_weight_plan_chunk(plan, ci, &first, &n, w);
        for (c = c0; c < c1; c++) {
            load_present(g, channel == BF_GRID_MEAN ? BF_GRID_MEAN : c, first, n, meas, present);
            for (s = 0; s < n; s++) count += present[s] != 0.0 && w[s] != 0.0;
        }
    }
    return count;
}

/* ---- derived grids ------------------------------------------------------ */

static brdffit_status check_derive_args(brdffit_grid **out, const brdffit_grid *grid,
                                        const brdffit_allocator *alloc, brdffit_error *err)
{
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (grid == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "grid is NULL");
    if (grid->magic != BF_MAGIC_GRID)
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid handle is invalid or destroyed");
    if (!bf_grid_check_alloc(alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    return BRDFFIT_OK;
}

static void *copy_block(const brdffit_allocator *a, const void *src, size_t bytes)
{
    void *p = bf_malloc(a, bytes);
    if (p != NULL) memcpy(p, src, bytes);
    return p;
}

/* Copy src's samples (geometry, axes, sample weights) into g. */
static brdffit_status copy_shape(brdffit_grid *g, const brdffit_grid *src, brdffit_error *err)
{
    size_t n = src->n_samples;
    memcpy(g->geo.block, src->geo.block, bf_geometry_bytes(n));
    g->geo.w_norm[0] = src->geo.w_norm[0];
    g->geo.w_norm[1] = src->geo.w_norm[1];
    if (src->kind == BRDFFIT_GRID_REGULAR) {
        brdffit_axes axes = {src->axis[0],   src->n_axis[0], src->axis[1],
                             src->n_axis[1], src->axis[2],   src->n_axis[2]};
        return bf_grid_copy_axes(g, &axes, err);
    }
    g->max_theta = copy_block(&g->alloc, src->max_theta, n * sizeof(double));
    if (g->max_theta == NULL) return bf_grid_oom(err);
    if (src->order != NULL) {
        g->order = copy_block(&g->alloc, src->order, n * sizeof(size_t));
        if (g->order == NULL) return bf_grid_oom(err);
    }
    if (src->sample_weight == NULL) return BRDFFIT_OK;
    g->sample_weight = copy_block(&g->alloc, src->sample_weight, n * sizeof(double));
    return g->sample_weight == NULL ? bf_grid_oom(err) : BRDFFIT_OK;
}

/* A new grid with src's samples and n_channels values per sample (to be
 * filled by the caller), nothing missing yet. */
static brdffit_status clone_shape(brdffit_grid **out, const brdffit_grid *src, size_t n_channels,
                                  const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_grid *g = NULL;
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_grid_new(&g, alloc, src->kind, src->n_samples, n_channels, err));
    st = copy_shape(g, src, err);
    if (st != BRDFFIT_OK) {
        bf_grid_free(g);
        return st;
    }
    *out = g;
    return BRDFFIT_OK;
}

static int src_missing(const brdffit_grid *g, size_t c, size_t s)
{
    return g->missing != NULL && g->missing[c * g->n_samples + s];
}

static size_t count_all_missing(const brdffit_grid *g)
{
    size_t s, c, count = 0;
    if (g->missing == NULL) return 0;
    for (s = 0; s < g->n_samples; s++) {
        for (c = 0; c < g->n_channels && src_missing(g, c, s); c++) continue;
        count += c == g->n_channels;
    }
    return count;
}

brdffit_status brdffit_grid_channel_mean(brdffit_grid **out, const brdffit_grid *grid,
                                         const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_grid *g = NULL;
    size_t s;
    brdffit_status st;
    BF_RETURN_IF_ERROR(check_derive_args(out, grid, alloc, err));
    BF_RETURN_IF_ERROR(clone_shape(&g, grid, 1, alloc, err));
    st = bf_grid_alloc_missing(g, count_all_missing(grid), err);
    if (st != BRDFFIT_OK) {
        bf_grid_free(g);
        return st;
    }
    for (s = 0; s < g->n_samples; s++) {
        double mean;
        size_t present = bf_grid_sample_mean(grid, s, &mean);
        g->values[s] = mean;
        if (present == 0) g->missing[s] = 1;
    }
    bf_grid_store_float_values(g);
    *out = g;
    return BRDFFIT_OK;
}

static brdffit_status apply_coat(brdffit_grid *g, const brdffit_grid *src, double r0,
                                 brdffit_error *err)
{
    size_t s, c, n = g->n_samples;
    for (s = 0; s < n; s++) {
        double d = bf_grid_coat_divisor(r0, src->geo.lz[s]);
        for (c = 0; c < g->n_channels; c++) {
            size_t v = c * n + s;
            g->values[v] = src->values[v] / d;
            if (!isfinite(g->values[v]))
                return bf_fail(err, BRDFFIT_E_RANGE,
                               "clear-coat compensation of sample %zu, channel %zu overflows", s,
                               c);
        }
    }
    return BRDFFIT_OK;
}

brdffit_status brdffit_grid_clearcoat(brdffit_grid **out, const brdffit_grid *grid, double r0,
                                      const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_grid *g = NULL;
    brdffit_status st;
    BF_RETURN_IF_ERROR(check_derive_args(out, grid, alloc, err));
    if (!(r0 >= 0.0 && r0 < 1.0))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "r0 = %g is outside [0, 1)", r0);
    BF_RETURN_IF_ERROR(clone_shape(&g, grid, grid->n_channels, alloc, err));
    st = bf_grid_alloc_missing(g, grid->n_missing, err);
    if (st == BRDFFIT_OK && g->missing != NULL)
        memcpy(g->missing, grid->missing, g->n_samples * g->n_channels);
    if (st == BRDFFIT_OK) st = apply_coat(g, grid, r0, err);
    if (st == BRDFFIT_OK) bf_grid_store_float_values(g);
    if (st != BRDFFIT_OK) {
        bf_grid_free(g);
        return st;
    }
    *out = g;
    return BRDFFIT_OK;
}
