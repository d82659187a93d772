/* The CSV loader, part 2: the grids (docs/formats.md).
 *
 * The rows come from csv_rows.c. Grid-form rows are matched to the sorted
 * distinct axis values; sorting the rows by sample index finds duplicates
 * and gaps without any array sized by the axis product. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdffit/load.h"
#include "core/core.h"
#include "load/csv_internal.h"

static const char *const csv_grid_names[3] = {"theta_i", "theta_o", "phi_o"};
/* ---- degrees to radians ----------------------------------------------------- */

static double to_radians(double deg, double limit)
{
    double r = deg * BF_PI / 180.0;
    if (r > limit) return limit;
    if (r < -limit) return -limit;
    return r;
}

/* ---- the scattered form ------------------------------------------------------ */

static brdffit_status build_scattered(brdffit_grid **out, csv_data *d, const csv_layout *lay,
                                      const brdffit_allocator *a, brdffit_error *err)
{
    size_t k, r, n = d->n_rows;
    for (k = 0; k < 4; k++) {
        double limit = k % 2 == 0 ? BF_HALF_PI : 2.0 * BF_PI;
        for (r = 0; r < n; r++) d->angles[k * n + r] = to_radians(d->angles[k * n + r], limit);
    }
    return brdffit_grid_create_scattered(out, n, d->angles, d->angles + n, d->angles + 2 * n,
                                         d->angles + 3 * n, lay->n_channels, d->values,
                                         d->n_missing > 0 ? d->missing : NULL, d->weights, a,
                                         err);
}

/* ---- the grid form ------------------------------------------------------------- */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct grid_axes {
    double *deg[3]; /* distinct values, ascending, degrees; deg[0] owns the block */
    size_t n[3];
} grid_axes;

/* Sorted distinct values of each angle column (one block of 3 n_rows). */
static brdffit_status find_axes(const csv_data *d, grid_axes *ax, const brdffit_allocator *a,
                                brdffit_error *err)
{
    size_t k, r, n = d->n_rows;
    double *block = bf_calloc(a, n, 3 * sizeof(double));
    if (block == NULL) return bf_csv_oom(err);
    memcpy(block, d->angles, 3 * n * sizeof(double));
    for (k = 0; k < 3; k++) {
        double *x = block + k * n;
        size_t m = 1;
        qsort(x, n, sizeof(double), cmp_double);
        for (r = 1; r < n; r++)
            if (x[r] != x[m - 1]) x[m++] = x[r];
        ax->deg[k] = x;
        ax->n[k] = m;
    }
    return BRDFFIT_OK;
}

static size_t index_of(const double *x, size_t n, double v)
{
    size_t lo = 0, hi = n;
    while (hi - lo > 1) {
        size_t m = lo + (hi - lo) / 2;
        if (x[m] <= v)
            lo = m;
        else
            hi = m;
    }
    return lo;
}

typedef struct row_key {
    size_t sample, row;
} row_key;

static int cmp_key(const void *a, const void *b)
{
    const row_key *x = a, *y = b;
    if (x->sample != y->sample) return x->sample < y->sample ? -1 : 1;
    return (x->row > y->row) - (x->row < y->row);
}

static void sample_degrees(const grid_axes *ax, size_t s, double deg[3])
{
    deg[2] = ax->deg[2][s % ax->n[2]];
    deg[1] = ax->deg[1][s / ax->n[2] % ax->n[1]];
    deg[0] = ax->deg[0][s / ax->n[2] / ax->n[1]];
}

static brdffit_status check_cover(const row_key *keys, size_t n, size_t n_samples,
                                  const grid_axes *ax, const csv_data *d, brdffit_error *err)
{
    size_t r, expected = 0;
    double deg[3];
    for (r = 1; r < n; r++) {
        if (keys[r].sample != keys[r - 1].sample) continue;
        sample_degrees(ax, keys[r].sample, deg);
        return bf_fail(err, BRDFFIT_E_DUPLICATE,
                       "theta_i = %.17g, theta_o = %.17g, phi_o = %.17g degrees is given "
                       "twice: lines %zu and %zu",
                       deg[0], deg[1], deg[2], d->lines[keys[r - 1].row], d->lines[keys[r].row]);
    }
    for (r = 0; r < n && keys[r].sample == expected; r++) expected++;
    if (expected == n_samples) return BRDFFIT_OK;
    sample_degrees(ax, expected, deg);
    return bf_fail(err, BRDFFIT_E_INCOMPLETE_GRID,
                   "no row for theta_i = %.17g, theta_o = %.17g, phi_o = %.17g degrees", deg[0],
                   deg[1], deg[2]);
}

/* Axes in radians; adjacent degree values must stay apart. */
static brdffit_status axes_radians(const grid_axes *ax, double *rad[3], brdffit_error *err)
{
    size_t k, m;
    for (k = 0; k < 3; k++) {
        double limit = k == 2 ? BF_PI : BF_HALF_PI;
        for (m = 0; m < ax->n[k]; m++) {
            rad[k][m] = to_radians(ax->deg[k][m], limit);
            if (m > 0 && !(rad[k][m] > rad[k][m - 1]))
                return bf_fail(err, BRDFFIT_E_RANGE,
                               "%s values %.17g and %.17g degrees are too close to tell apart",
                               csv_grid_names[k], ax->deg[k][m - 1], ax->deg[k][m]);
        }
    }
    return BRDFFIT_OK;
}

typedef struct grid_build {
    grid_axes ax;
    row_key *keys;
    double *rad, *values;
    unsigned char *missing;
} grid_build;

static void build_free(grid_build *b, const brdffit_allocator *a)
{
    bf_free(a, b->ax.deg[0]);
    bf_free(a, b->keys);
    bf_free(a, b->rad);
    bf_free(a, b->values);
    bf_free(a, b->missing);
}

static brdffit_status sort_rows(grid_build *b, const csv_data *d, size_t nc,
                                const brdffit_allocator *a, size_t *n_samples, brdffit_error *err)
{
    size_t r, n = d->n_rows, prod = 0, nv = 0;
    const size_t *nx = b->ax.n;
    if (!bf_mul_size(nx[0], nx[1], &prod) || !bf_mul_size(prod, nx[2], &prod) ||
        !bf_mul_size(prod, nc, &nv) || nv > BF_LOAD_MAX_VALUES)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE,
                       "the distinct angles span %zu x %zu x %zu combinations of %zu "
                       "channel(s), more than the %zu values allowed",
                       nx[0], nx[1], nx[2], nc, BF_LOAD_MAX_VALUES);
    b->keys = bf_calloc(a, n, sizeof(row_key));
    if (b->keys == NULL) return bf_csv_oom(err);
    for (r = 0; r < n; r++) {
        size_t i = index_of(b->ax.deg[0], nx[0], d->angles[r]);
        size_t j = index_of(b->ax.deg[1], nx[1], d->angles[n + r]);
        size_t k = index_of(b->ax.deg[2], nx[2], d->angles[2 * n + r]);
        b->keys[r].sample = (i * nx[1] + j) * nx[2] + k;
        b->keys[r].row = r;
    }
    qsort(b->keys, n, sizeof(row_key), cmp_key);
    *n_samples = prod;
    return BRDFFIT_OK;
}

static brdffit_status build_arrays(grid_build *b, const csv_data *d, size_t nc,
                                   const brdffit_allocator *a, brdffit_error *err)
{
    size_t s, c, n = d->n_rows;
    b->rad = bf_calloc(a, b->ax.n[0] + b->ax.n[1] + b->ax.n[2], sizeof(double));
    b->values = bf_calloc(a, n * nc, sizeof(double));
    if (d->n_missing > 0) b->missing = bf_calloc(a, n * nc, 1);
    if (b->rad == NULL || b->values == NULL || (d->n_missing > 0 && b->missing == NULL))
        return bf_csv_oom(err);
    for (s = 0; s < n; s++) {
        size_t row = b->keys[s].row;
        for (c = 0; c < nc; c++) {
            b->values[s * nc + c] = d->values[row * nc + c];
            if (b->missing) b->missing[s * nc + c] = d->missing[row * nc + c];
        }
    }
    return BRDFFIT_OK;
}

static brdffit_status build_grid(brdffit_grid **out, const csv_data *d, const csv_layout *lay,
                                 const brdffit_allocator *a, brdffit_error *err)
{
    grid_build b;
    brdffit_axes axes;
    double *rad[3];
    size_t n_samples = 0;
    brdffit_status st;
    memset(&b, 0, sizeof b);
    st = find_axes(d, &b.ax, a, err);
    if (st == BRDFFIT_OK) st = sort_rows(&b, d, lay->n_channels, a, &n_samples, err);
    if (st == BRDFFIT_OK) st = check_cover(b.keys, d->n_rows, n_samples, &b.ax, d, err);
    if (st == BRDFFIT_OK) st = build_arrays(&b, d, lay->n_channels, a, err);
    if (st == BRDFFIT_OK) {
        rad[0] = b.rad, rad[1] = rad[0] + b.ax.n[0], rad[2] = rad[1] + b.ax.n[1];
        st = axes_radians(&b.ax, rad, err);
    }
    if (st == BRDFFIT_OK) {
        axes.theta_i = rad[0], axes.n_theta_i = b.ax.n[0];
        axes.theta_o = rad[1], axes.n_theta_o = b.ax.n[1];
        axes.phi_o = rad[2], axes.n_phi_o = b.ax.n[2];
        st = brdffit_grid_create_regular(out, &axes, lay->n_channels, b.values, b.missing, a, err);
    }
    build_free(&b, a);
    return st;
}

/* ---- entry points ------------------------------------------------------------ */

static brdffit_status load_text(brdffit_grid **out, const char *text, size_t size,
                                const brdffit_allocator *a, brdffit_error *err)
{
    csv_layout lay;
    csv_data d;
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_csv_read_rows(text, size, &lay, &d, a, err));
    st = lay.scattered ? build_scattered(out, &d, &lay, a, err) : build_grid(out, &d, &lay, a, err);
    bf_csv_data_free(&d, a);
    return st;
}

static brdffit_status check_args(brdffit_grid **out, const void *in, const brdffit_allocator *alloc,
                                 brdffit_allocator *a, brdffit_error *err)
{
    if (out == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (in == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "path or data is NULL");
    if (!bf_alloc_init(a, alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    return BRDFFIT_OK;
}

brdffit_status brdffit_load_csv_buffer(brdffit_grid **out, const char *data, size_t size,
                                       const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    BF_RETURN_IF_ERROR(check_args(out, data, alloc, &a, err));
    return load_text(out, data, size, &a, err);
}

brdffit_status brdffit_load_csv(brdffit_grid **out, const char *path,
                                const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    char *text = NULL;
    size_t size = 0;
    brdffit_status st;
    BF_RETURN_IF_ERROR(check_args(out, path, alloc, &a, err));
    BF_RETURN_IF_ERROR(bf_file_read_all(path, (size_t)-1 >> 1, &a, &text, &size, err));
    st = load_text(out, text, size, &a, err);
    bf_free(&a, text);
    return st;
}
