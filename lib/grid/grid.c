/* The measurement grid: the default axes, allocation and validation shared
 * by every constructor, regular grids, and the accessors. Scattered grids
 * are made in scattered.c, derived grids in derived.c. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "grid/grid_internal.h"

/* ---- the default axes ------------------------------------------------- */

#define BF_DEG(d) ((d)*BF_PI / 180.0)
#define BF_TI(i) BF_DEG(5.0 * (i))
#define BF_TO(j) BF_DEG(2.5 * (j))
#define BF_PO(k) ((k)*BF_PI / 35.0)

static const double default_theta_i[19] = {BF_TI(0),  BF_TI(1),  BF_TI(2),  BF_TI(3),  BF_TI(4),
                                           BF_TI(5),  BF_TI(6),  BF_TI(7),  BF_TI(8),  BF_TI(9),
                                           BF_TI(10), BF_TI(11), BF_TI(12), BF_TI(13), BF_TI(14),
                                           BF_TI(15), BF_TI(16), BF_TI(17), BF_TI(18)};

static const double default_theta_o[37] = {
    BF_TO(0),  BF_TO(1),  BF_TO(2),  BF_TO(3),  BF_TO(4),  BF_TO(5),  BF_TO(6),  BF_TO(7),
    BF_TO(8),  BF_TO(9),  BF_TO(10), BF_TO(11), BF_TO(12), BF_TO(13), BF_TO(14), BF_TO(15),
    BF_TO(16), BF_TO(17), BF_TO(18), BF_TO(19), BF_TO(20), BF_TO(21), BF_TO(22), BF_TO(23),
    BF_TO(24), BF_TO(25), BF_TO(26), BF_TO(27), BF_TO(28), BF_TO(29), BF_TO(30), BF_TO(31),
    BF_TO(32), BF_TO(33), BF_TO(34), BF_TO(35), BF_TO(36)};

static const double default_phi_o[36] = {
    BF_PO(0),  BF_PO(1),  BF_PO(2),  BF_PO(3),  BF_PO(4),  BF_PO(5),  BF_PO(6),  BF_PO(7),
    BF_PO(8),  BF_PO(9),  BF_PO(10), BF_PO(11), BF_PO(12), BF_PO(13), BF_PO(14), BF_PO(15),
    BF_PO(16), BF_PO(17), BF_PO(18), BF_PO(19), BF_PO(20), BF_PO(21), BF_PO(22), BF_PO(23),
    BF_PO(24), BF_PO(25), BF_PO(26), BF_PO(27), BF_PO(28), BF_PO(29), BF_PO(30), BF_PO(31),
    BF_PO(32), BF_PO(33), BF_PO(34), BF_PO(35)};

static const brdffit_axes default_axes = {default_theta_i, 19, default_theta_o, 37,
                                          default_phi_o,   36};

const brdffit_axes *brdffit_axes_default(void)
{
    return &default_axes;
}

/* ---- allocation --------------------------------------------------------- */

int bf_grid_ok(const brdffit_grid *g)
{
    return g != NULL && g->magic == BF_MAGIC_GRID;
}

void bf_grid_free(brdffit_grid *g)
{
    brdffit_allocator a = g->alloc;
    bf_free(&a, g->axis[0]);
    bf_geometry_free(&g->geo, &a);
    bf_free(&a, g->values);
    bf_free(&a, g->missing);
    bf_free(&a, g->sample_weight);
    bf_free(&a, g->max_theta);
    bf_free(&a, g->order);
    g->magic = BF_MAGIC_DEAD;
    bf_free(&a, g);
}

void brdffit_grid_destroy(brdffit_grid *grid)
{
    if (grid == NULL || grid->magic != BF_MAGIC_GRID) return;
    bf_grid_free(grid);
}

/* Every size derived from (n_samples, n_channels) must fit in size_t. */
brdffit_status bf_grid_check_sizes(size_t n_samples, size_t n_channels, brdffit_error *err)
{
    size_t n_values, bytes;
    if (!bf_mul_size(n_samples, n_channels, &n_values) ||
        !bf_mul_size(n_values, sizeof(double) + sizeof(float), &bytes) ||
        bf_geometry_bytes(n_samples) == 0)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "grid of %zu samples x %zu channels is too large",
                       n_samples, n_channels);
    return BRDFFIT_OK;
}

brdffit_status bf_grid_oom(brdffit_error *err)
{
    return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while creating a grid");
}

/* A grid with its value and geometry arrays allocated; every caller fills
 * all values. Sizes are checked by bf_grid_check_sizes() first. */
brdffit_status bf_grid_new(brdffit_grid **out, const brdffit_allocator *alloc,
                               brdffit_grid_kind kind, size_t n_samples, size_t n_channels,
                               brdffit_error *err)
{
    brdffit_allocator a;
    brdffit_grid *g;
    bf_alloc_init(&a, alloc);
    g = bf_calloc(&a, 1, sizeof *g);
    if (g == NULL) return bf_grid_oom(err);
    g->magic = BF_MAGIC_GRID;
    g->alloc = a;
    g->kind = kind;
    g->n_samples = n_samples;
    g->n_channels = n_channels;
    /* the values and their single-precision copy, filled by callers */
    g->values = bf_malloc(&a, n_samples * n_channels * (sizeof(double) + sizeof(float)));
    if (g->values != NULL) g->fvalues = (float *)(void *)(g->values + n_samples * n_channels);
    if (g->values == NULL || !bf_geometry_alloc(&g->geo, &a, n_samples)) {
        bf_grid_free(g);
        return bf_grid_oom(err);
    }
    *out = g;
    return BRDFFIT_OK;
}

brdffit_status bf_grid_alloc_missing(brdffit_grid *g, size_t n_missing, brdffit_error *err)
{
    g->n_missing = n_missing;
    if (n_missing == 0) return BRDFFIT_OK;
    g->missing = bf_calloc(&g->alloc, g->n_samples * g->n_channels, 1);
    return g->missing == NULL ? bf_grid_oom(err) : BRDFFIT_OK;
}

/* ---- validation --------------------------------------------------------- */

int bf_grid_check_alloc(const brdffit_allocator *alloc)
{
    brdffit_allocator a;
    return bf_alloc_init(&a, alloc);
}

/* Count the missing values and check every present one: finite (negative
 * values are measurement noise, kept as data). */
brdffit_status bf_grid_check_values(const double *values, const unsigned char *missing,
                                   size_t n_samples, size_t n_channels, size_t *n_missing,
                                   brdffit_error *err)
{
    size_t v, n = n_samples * n_channels, count = 0;
    if (missing == NULL && bf_all_finite(values, n)) { /* the usual case, branch-free */
        *n_missing = 0;
        return BRDFFIT_OK;
    }
    for (v = 0; v < n; v++) {
        if (missing != NULL && missing[v]) {
            count++;
            continue;
        }
        if (!isfinite(values[v]))
            return bf_fail(err, BRDFFIT_E_RANGE, "value of sample %zu, channel %zu is not finite",
                           v / n_channels, v % n_channels);
    }
    *n_missing = count;
    return BRDFFIT_OK;
}

/* Store interleaved input per channel; missing values become 0. */
void bf_grid_store_values(brdffit_grid *g, const double *values, const unsigned char *missing,
                         const size_t *order)
{
    size_t s, c, n = g->n_samples, nc = g->n_channels;
    if (missing == NULL && g->missing == NULL) { /* nothing to mask: no branch per value */
        for (s = 0; s < n; s++) {
            const double *row = values + (order != NULL ? order[s] : s) * nc;
            for (c = 0; c < nc; c++) g->values[c * n + s] = row[c] + 0.0;
        }
        return;
    }
    for (s = 0; s < n; s++) {
        size_t src = order != NULL ? order[s] : s;
        for (c = 0; c < nc; c++) {
            size_t v = src * nc + c;
            int miss = missing != NULL && missing[v];
            g->values[c * n + s] = miss ? 0.0 : values[v] + 0.0;
            if (g->missing != NULL) g->missing[c * n + s] = (unsigned char)miss;
        }
    }
}

static const char *const axis_names[3] = {"theta_i", "theta_o", "phi_o"};

static brdffit_status check_axis(const double *x, size_t n, int which, brdffit_error *err)
{
    double hi = which == BRDFFIT_AXIS_PHI_O ? BF_PI : BF_HALF_PI;
    size_t k;
    for (k = 0; k < n; k++) {
        if (!(x[k] >= 0.0 && x[k] <= hi))
            return bf_fail(err, BRDFFIT_E_RANGE, "%s[%zu] = %g is outside [0, %.17g]",
                           axis_names[which], k, x[k], hi);
        if (k > 0 && !(x[k] > x[k - 1]))
            return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                           "%s is not strictly increasing at index %zu (%.17g after %.17g)",
                           axis_names[which], k, x[k], x[k - 1]);
    }
    return BRDFFIT_OK;
}

/* ---- regular grids ------------------------------------------------------ */

static brdffit_status check_axes_args(const brdffit_axes *axes, size_t *n_samples,
                                      brdffit_error *err)
{
    const double *p[3];
    size_t n[3], k, prod = 1;
    if (axes == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "axes is NULL");
    p[0] = axes->theta_i, p[1] = axes->theta_o, p[2] = axes->phi_o;
    n[0] = axes->n_theta_i, n[1] = axes->n_theta_o, n[2] = axes->n_phi_o;
    for (k = 0; k < 3; k++) {
        if (p[k] == NULL || n[k] == 0)
            return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "axis %s is NULL or empty",
                           axis_names[k]);
        if (!bf_mul_size(prod, n[k], &prod))
            return bf_fail(err, BRDFFIT_E_TOO_LARGE, "axes of %zu x %zu x %zu are too large", n[0],
                           n[1], n[2]);
    }
    *n_samples = prod;
    return BRDFFIT_OK;
}

brdffit_status bf_grid_copy_axes(brdffit_grid *g, const brdffit_axes *axes, brdffit_error *err)
{
    size_t total = axes->n_theta_i + axes->n_theta_o + axes->n_phi_o;
    double *block = bf_malloc(&g->alloc, total * sizeof(double));
    if (block == NULL) return bf_grid_oom(err);
    g->axis[0] = block;
    g->axis[1] = block + axes->n_theta_i;
    g->axis[2] = g->axis[1] + axes->n_theta_o;
    g->n_axis[0] = axes->n_theta_i;
    g->n_axis[1] = axes->n_theta_o;
    g->n_axis[2] = axes->n_phi_o;
    memcpy(g->axis[0], axes->theta_i, axes->n_theta_i * sizeof(double));
    memcpy(g->axis[1], axes->theta_o, axes->n_theta_o * sizeof(double));
    memcpy(g->axis[2], axes->phi_o, axes->n_phi_o * sizeof(double));
    return BRDFFIT_OK;
}

static void regular_geometry(brdffit_grid *g)
{
    size_t i, j, k, s = 0;
    for (i = 0; i < g->n_axis[0]; i++)
        for (j = 0; j < g->n_axis[1]; j++)
            for (k = 0; k < g->n_axis[2]; k++)
                bf_geometry_set(&g->geo, s++, g->axis[0][i], BF_PI, g->axis[1][j], g->axis[2][k]);
}

brdffit_status brdffit_grid_create_regular(brdffit_grid **out, const brdffit_axes *axes,
                                           size_t n_channels, const double *values,
                                           const unsigned char *missing,
                                           const brdffit_allocator *alloc, brdffit_error *err)
{
    size_t n_samples = 0, n_missing = 0;
    brdffit_grid *g = NULL;
    brdffit_status st;
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (values == NULL || n_channels == 0)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "values is NULL or n_channels is 0");
    if (!bf_grid_check_alloc(alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    BF_RETURN_IF_ERROR(check_axes_args(axes, &n_samples, err));
    BF_RETURN_IF_ERROR(bf_grid_check_sizes(n_samples, n_channels, err));
    BF_RETURN_IF_ERROR(check_axis(axes->theta_i, axes->n_theta_i, 0, err));
    BF_RETURN_IF_ERROR(check_axis(axes->theta_o, axes->n_theta_o, 1, err));
    BF_RETURN_IF_ERROR(check_axis(axes->phi_o, axes->n_phi_o, 2, err));
    BF_RETURN_IF_ERROR(
        bf_grid_check_values(values, missing, n_samples, n_channels, &n_missing, err));
    BF_RETURN_IF_ERROR(bf_grid_new(&g, alloc, BRDFFIT_GRID_REGULAR, n_samples, n_channels, err));
    st = bf_grid_copy_axes(g, axes, err);
    if (st == BRDFFIT_OK) st = bf_grid_alloc_missing(g, n_missing, err);
    if (st != BRDFFIT_OK) {
        bf_grid_free(g);
        return st;
    }
    bf_grid_store_values(g, values, missing, NULL);
    bf_grid_store_float_values(g);
    regular_geometry(g);
    bf_grid_base_weights(g);
    *out = g;
    return BRDFFIT_OK;
}

/* ---- accessors ---------------------------------------------------------- */

brdffit_grid_kind brdffit_grid_get_kind(const brdffit_grid *grid)
{
    return bf_grid_ok(grid) ? grid->kind : (brdffit_grid_kind)0;
}

size_t brdffit_grid_sample_count(const brdffit_grid *grid)
{
    return bf_grid_ok(grid) ? grid->n_samples : 0;
}

size_t brdffit_grid_channel_count(const brdffit_grid *grid)
{
    return bf_grid_ok(grid) ? grid->n_channels : 0;
}

size_t brdffit_grid_missing_count(const brdffit_grid *grid)
{
    return bf_grid_ok(grid) ? grid->n_missing : 0;
}

static brdffit_status check_handle(const brdffit_grid *grid)
{
    if (grid == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    return grid->magic == BF_MAGIC_GRID ? BRDFFIT_OK : BRDFFIT_E_BAD_HANDLE;
}

brdffit_status brdffit_grid_axis(const brdffit_grid *grid, brdffit_axis axis, const double **values,
                                 size_t *count)
{
    BF_RETURN_IF_ERROR(check_handle(grid));
    if (values == NULL || count == NULL || (unsigned)axis > 2u) return BRDFFIT_E_INVALID_ARGUMENT;
    if (grid->kind != BRDFFIT_GRID_REGULAR) return BRDFFIT_E_UNSUPPORTED;
    *values = grid->axis[axis];
    *count = grid->n_axis[axis];
    return BRDFFIT_OK;
}

static double polar_of(double x, double y, double z)
{
    return atan2(sqrt(x * x + y * y), z);
}

brdffit_status brdffit_grid_sample_angles(const brdffit_grid *grid, size_t sample, double *theta_i,
                                          double *phi_i, double *theta_o, double *phi_o)
{
    double a[4];
    const bf_geometry *geo;
    BF_RETURN_IF_ERROR(check_handle(grid));
    if (sample >= grid->n_samples) return BRDFFIT_E_INVALID_ARGUMENT;
    geo = &grid->geo;
    if (grid->kind == BRDFFIT_GRID_REGULAR) {
        size_t n_to = grid->n_axis[1], n_po = grid->n_axis[2];
        a[0] = grid->axis[0][sample / (n_to * n_po)];
        a[1] = BF_PI;
        a[2] = grid->axis[1][sample / n_po % n_to];
        a[3] = grid->axis[2][sample % n_po];
    } else {
        a[0] = polar_of(geo->lx[sample], geo->ly[sample], geo->lz[sample]);
        a[1] = atan2(geo->ly[sample], geo->lx[sample]);
        a[2] = polar_of(geo->vx[sample], geo->vy[sample], geo->vz[sample]);
        a[3] = atan2(geo->vy[sample], geo->vx[sample]);
    }
    if (theta_i != NULL) *theta_i = a[0];
    if (phi_i != NULL) *phi_i = a[1];
    if (theta_o != NULL) *theta_o = a[2];
    if (phi_o != NULL) *phi_o = a[3];
    return BRDFFIT_OK;
}

brdffit_status brdffit_grid_values(const brdffit_grid *grid, size_t channel, const double **values)
{
    BF_RETURN_IF_ERROR(check_handle(grid));
    if (values == NULL || channel >= grid->n_channels) return BRDFFIT_E_INVALID_ARGUMENT;
    *values = grid->values + channel * grid->n_samples;
    return BRDFFIT_OK;
}

int brdffit_grid_is_missing(const brdffit_grid *grid, size_t sample, size_t channel)
{
    if (!bf_grid_ok(grid) || grid->missing == NULL) return 0;
    if (sample >= grid->n_samples || channel >= grid->n_channels) return 0;
    return grid->missing[channel * grid->n_samples + sample] != 0;
}
