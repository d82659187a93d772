/* Scattered grids: samples with their own light and view directions,
 * stored sorted by max(theta_i, theta_o) so that every cap is a prefix. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"

/* ---- scattered grids ---------------------------------------------------- */

typedef struct sort_item {
    double key;
    size_t index;
} sort_item;

/* Radix digits of the key: non-negative doubles order like their bit
 * patterns read as unsigned integers. */
#define BF_RADIX_BITS 11
#define BF_RADIX_SIZE ((size_t)1 << BF_RADIX_BITS)

static size_t radix_digit(double key, unsigned shift)
{
    uint64_t u;
    memcpy(&u, &key, sizeof u);
    return (size_t)(u >> shift) & (BF_RADIX_SIZE - 1);
}

/* Stable LSD radix sort by key (all keys >= +0); returns the buffer that
 * holds the result. Passes where every key has the same digit are skipped. */
static sort_item *radix_sort(sort_item *items, sort_item *tmp, size_t n)
{
    size_t count[BF_RADIX_SIZE], s, d;
    unsigned shift;
    for (shift = 0; shift < 64; shift += BF_RADIX_BITS) {
        size_t pos = 0;
        sort_item *t;
        memset(count, 0, sizeof count);
        for (s = 0; s < n; s++) count[radix_digit(items[s].key, shift)]++;
        if (count[radix_digit(items[0].key, shift)] == n) continue;
        for (d = 0; d < BF_RADIX_SIZE; d++) {
            size_t c = count[d];
            count[d] = pos;
            pos += c;
        }
        for (s = 0; s < n; s++) tmp[count[radix_digit(items[s].key, shift)]++] = items[s];
        t = items, items = tmp, tmp = t;
    }
    return items;
}

static int is_sorted(const sort_item *items, size_t n)
{
    size_t s;
    for (s = 1; s < n; s++)
        if (items[s].key < items[s - 1].key) return 0;
    return 1;
}

static brdffit_status check_direction(double theta, double phi, size_t s, const char *which,
                                      brdffit_error *err)
{
    if (!(theta >= 0.0 && theta <= BF_HALF_PI))
        return bf_fail(err, BRDFFIT_E_RANGE, "theta_%s of sample %zu (%g) is outside [0, pi/2]",
                       which, s, theta);
    if (!(phi >= -2.0 * BF_PI && phi <= 2.0 * BF_PI))
        return bf_fail(err, BRDFFIT_E_RANGE, "phi_%s of sample %zu (%g) is outside [-2 pi, 2 pi]",
                       which, s, phi);
    return BRDFFIT_OK;
}

typedef struct scattered_input {
    size_t n;
    const double *theta_i, *phi_i, *theta_o, *phi_o, *weights;
} scattered_input;

static brdffit_status check_scattered(const scattered_input *in, brdffit_error *err)
{
    size_t s;
    for (s = 0; s < in->n; s++) {
        BF_RETURN_IF_ERROR(check_direction(in->theta_i[s], in->phi_i[s], s, "i", err));
        BF_RETURN_IF_ERROR(check_direction(in->theta_o[s], in->phi_o[s], s, "o", err));
        if (in->weights != NULL && !(in->weights[s] >= 0.0 && isfinite(in->weights[s])))
            return bf_fail(err, BRDFFIT_E_RANGE,
                           "weight of sample %zu (%g) is not a finite number >= 0", s,
                           in->weights[s]);
    }
    return BRDFFIT_OK;
}

/* The stored order: stable by max(theta_i, theta_o). Writes the source
 * index of every stored sample into order (n entries). */
static brdffit_status sort_samples(brdffit_grid *g, const scattered_input *in, size_t *order,
                                   brdffit_error *err)
{
    size_t s, n = in->n;
    sort_item *items = bf_calloc(&g->alloc, n, 2 * sizeof(sort_item)), *sorted;
    if (items == NULL) return bf_grid_oom(err);
    for (s = 0; s < n; s++) {
        double a = in->theta_i[s], b = in->theta_o[s];
        items[s].key = (a > b ? a : b) + 0.0; /* + 0.0 turns -0 into +0 */
        items[s].index = s;
    }
    sorted = is_sorted(items, n) ? items : radix_sort(items, items + n, n);
    for (s = 0; s < n; s++) {
        order[s] = sorted[s].index;
        g->max_theta[s] = sorted[s].key;
    }
    bf_free(&g->alloc, items);
    return BRDFFIT_OK;
}

static brdffit_status fill_scattered(brdffit_grid *g, const scattered_input *in,
                                     const double *values, const unsigned char *missing,
                                     brdffit_error *err)
{
    size_t s, n = in->n;
    size_t *order = bf_calloc(&g->alloc, n, sizeof(size_t));
    brdffit_status st;
    if (order == NULL) return bf_grid_oom(err);
    st = sort_samples(g, in, order, err);
    if (st == BRDFFIT_OK) {
        bf_grid_store_values(g, values, missing, order);
        for (s = 0; s < n; s++) {
            size_t k = order[s];
            bf_geometry_set(&g->geo, s, in->theta_i[k], in->phi_i[k], in->theta_o[k], in->phi_o[k]);
            if (g->sample_weight != NULL) g->sample_weight[s] = in->weights[k];
        }
        bf_grid_store_float_values(g);
        bf_grid_base_weights(g);
    }
    /* kept for views (view.c) unless it is the identity */
    for (s = 0; st == BRDFFIT_OK && s < n && order[s] == s; s++) continue;
    if (st == BRDFFIT_OK && s < n) g->order = order;
    else bf_free(&g->alloc, order);
    return st;
}

brdffit_status brdffit_grid_create_scattered(brdffit_grid **out, size_t n_samples,
                                             const double *theta_i, const double *phi_i,
                                             const double *theta_o, const double *phi_o,
                                             size_t n_channels, const double *values,
                                             const unsigned char *missing, const double *weights,
                                             const brdffit_allocator *alloc, brdffit_error *err)
{
    scattered_input in;
    size_t n_missing = 0;
    brdffit_grid *g = NULL;
    brdffit_status st;
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (theta_i == NULL || phi_i == NULL || theta_o == NULL || phi_o == NULL || values == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "an angle or value array is NULL");
    if (n_samples == 0 || n_channels == 0)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "n_samples or n_channels is 0");
    if (!bf_grid_check_alloc(alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    BF_RETURN_IF_ERROR(bf_grid_check_sizes(n_samples, n_channels, err));
    in.n = n_samples, in.theta_i = theta_i, in.phi_i = phi_i, in.theta_o = theta_o;
    in.phi_o = phi_o, in.weights = weights;
    BF_RETURN_IF_ERROR(check_scattered(&in, err));
    BF_RETURN_IF_ERROR(
        bf_grid_check_values(values, missing, n_samples, n_channels, &n_missing, err));
    BF_RETURN_IF_ERROR(bf_grid_new(&g, alloc, BRDFFIT_GRID_SCATTERED, n_samples, n_channels, err));
    st = bf_grid_alloc_missing(g, n_missing, err);
    g->max_theta = bf_calloc(&g->alloc, n_samples, sizeof(double));
    if (weights != NULL) g->sample_weight = bf_calloc(&g->alloc, n_samples, sizeof(double));
    if (st == BRDFFIT_OK && (g->max_theta == NULL || (weights && !g->sample_weight)))
        st = bf_grid_oom(err);
    if (st == BRDFFIT_OK) st = fill_scattered(g, &in, values, missing, err);
    if (st != BRDFFIT_OK) {
        bf_grid_free(g);
        return st;
    }
    *out = g;
    return BRDFFIT_OK;
}
