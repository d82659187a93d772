/* The CSV loader (SPEC section 2b).
 *
 * Two passes over the text: the first finds the header and counts the data
 * rows, the second parses them into arrays sized by that count (so memory
 * stays proportional to the input). Grid-form rows are then matched to the
 * sorted distinct axis values; sorting the rows by sample index finds
 * duplicates and gaps without any array sized by the axis product. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdffit/load.h"
#include "core/core.h"
#include "load/load_internal.h"

/* ---- lines and fields --------------------------------------------------- */

typedef struct csv_line {
    const char *p;
    size_t len;
    size_t number; /* 1-based */
} csv_line;

typedef struct csv_reader {
    const char *data;
    size_t size, pos, line;
} csv_reader;

static int next_line(csv_reader *r, csv_line *out)
{
    const char *start, *nl;
    if (r->pos >= r->size) return 0;
    start = r->data + r->pos;
    nl = memchr(start, '\n', r->size - r->pos);
    out->p = start;
    out->len = nl != NULL ? (size_t)(nl - start) : r->size - r->pos;
    out->number = ++r->line;
    r->pos += out->len + (nl != NULL);
    if (out->len > 0 && start[out->len - 1] == '\r') out->len--;
    return 1;
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* Blank lines and '#' comments carry no data. */
static int skippable(const csv_line *l)
{
    size_t k = 0;
    while (k < l->len && is_blank(l->p[k])) k++;
    return k == l->len || l->p[k] == '#';
}

static int next_data_line(csv_reader *r, csv_line *out)
{
    while (next_line(r, out))
        if (!skippable(out)) return 1;
    return 0;
}

static size_t count_fields(const csv_line *l)
{
    size_t k, n = 1;
    for (k = 0; k < l->len; k++) n += l->p[k] == ',';
    return n;
}

/* The next field starting at *pos; advances *pos past its comma. Past the
 * last field it gives empty fields. */
static void next_field(const csv_line *l, size_t *pos, const char **p, size_t *len)
{
    const char *start, *comma;
    if (*pos > l->len) {
        *p = l->p + l->len;
        *len = 0;
        return;
    }
    start = l->p + *pos;
    comma = memchr(start, ',', l->len - *pos);
    *p = start;
    *len = comma != NULL ? (size_t)(comma - start) : l->len - *pos;
    *pos += *len + 1;
}

static void trim(const char **p, size_t *len)
{
    while (*len > 0 && is_blank((*p)[0])) (*p)++, (*len)--;
    while (*len > 0 && is_blank((*p)[*len - 1])) (*len)--;
}

/* A printable excerpt of text for messages. */
static void excerpt(char *buf, size_t size, const char *p, size_t len)
{
    size_t k, n = len < size - 4 ? len : size - 4;
    for (k = 0; k < n; k++) buf[k] = p[k] >= 0x20 && p[k] < 0x7f ? p[k] : '?';
    if (n < len) buf[n++] = '.', buf[n++] = '.', buf[n++] = '.';
    buf[n] = '\0';
}

/* ---- the header ---------------------------------------------------------- */

typedef struct csv_layout {
    int scattered;
    int weight; /* scattered form: column 5 holds each sample's weight */
    size_t n_angles, n_channels, n_fields;
    csv_line header;
} csv_layout;

static const char *const grid_names[3] = {"theta_i", "theta_o", "phi_o"};
static const char *const scattered_names[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};

static int field_is(const char *p, size_t len, const char *name)
{
    return strlen(name) == len && memcmp(p, name, len) == 0;
}

/* Name of column `col` (0-based) for messages. */
static void column_name(const csv_layout *lay, size_t col, char *buf, size_t size)
{
    size_t pos = 0, k;
    const char *p = "";
    size_t len = 0;
    for (k = 0; k <= col; k++) next_field(&lay->header, &pos, &p, &len);
    trim(&p, &len);
    excerpt(buf, size, p, len);
}

/* The optional weight column: a header field "weight", allowed only in
 * the scattered form and only right after phi_o. */
static brdffit_status find_weight_column(const csv_line *l, csv_layout *lay, brdffit_error *err)
{
    size_t pos = 0, k, len;
    const char *p;
    for (k = 0; k < lay->n_fields; k++) {
        next_field(l, &pos, &p, &len);
        trim(&p, &len);
        if (!field_is(p, len, "weight")) continue;
        if (!lay->scattered)
            return bf_fail(err, BRDFFIT_E_PARSE,
                           "line %zu, column %zu: the grid form has no weight column (its "
                           "weights follow from the axes)",
                           l->number, k + 1);
        if (k != 4)
            return bf_fail(err, BRDFFIT_E_PARSE,
                           "line %zu, column %zu: the weight column must directly follow phi_o "
                           "(column 5)",
                           l->number, k + 1);
        lay->weight = 1;
    }
    return BRDFFIT_OK;
}

static brdffit_status parse_header(const csv_line *l, csv_layout *lay, brdffit_error *err)
{
    const char *const *names;
    size_t pos = 0, k, len;
    const char *p;
    char buf[40];
    memset(lay, 0, sizeof *lay);
    lay->header = *l;
    lay->n_fields = count_fields(l);
    next_field(l, &pos, &p, &len);
    next_field(l, &pos, &p, &len);
    trim(&p, &len);
    lay->scattered = field_is(p, len, "phi_i");
    lay->n_angles = lay->scattered ? 4 : 3;
    names = lay->scattered ? scattered_names : grid_names;
    for (pos = 0, k = 0; k < lay->n_fields; k++) {
        next_field(l, &pos, &p, &len);
        trim(&p, &len);
        excerpt(buf, sizeof buf, p, len);
        if (k < lay->n_angles && !field_is(p, len, names[k]))
            return bf_fail(err, BRDFFIT_E_PARSE,
                           "line %zu, column %zu: unknown header '%s' (expected '%s'; the "
                           "header is theta_i,theta_o,phi_o,... or theta_i,phi_i,theta_o,"
                           "phi_o,...)",
                           l->number, k + 1, buf, names[k]);
        if (k >= lay->n_angles && len == 0)
            return bf_fail(err, BRDFFIT_E_PARSE, "line %zu, column %zu: empty channel name",
                           l->number, k + 1);
    }
    BF_RETURN_IF_ERROR(find_weight_column(l, lay, err));
    if (lay->n_fields <= lay->n_angles + (size_t)lay->weight)
        return bf_fail(err, BRDFFIT_E_PARSE,
                       "line %zu: header needs %zu angle columns%s and at least one channel",
                       l->number, lay->n_angles, lay->weight ? ", the weight" : "");
    lay->n_channels = lay->n_fields - lay->n_angles - (size_t)lay->weight;
    return BRDFFIT_OK;
}

/* ---- the rows -------------------------------------------------------------- */

typedef struct csv_data {
    size_t n_rows;
    double *angles;         /* [k * n_rows + r], degrees */
    double *values;         /* [r * n_channels + c] */
    unsigned char *missing; /* [r * n_channels + c] */
    size_t *lines;          /* line of row r */
    double *weights;        /* row weights, or NULL without a weight column */
    size_t n_missing;
} csv_data;

static brdffit_status number_error(const csv_layout *lay, const csv_line *l, size_t col,
                                   brdffit_status st, const char *what, const char *p, size_t len,
                                   brdffit_error *err)
{
    char name[40], text[40];
    column_name(lay, col, name, sizeof name);
    trim(&p, &len);
    excerpt(text, sizeof text, p, len);
    return bf_fail(err, st, "line %zu, column %zu (%s): %s '%s'", l->number, col + 1, name, what,
                   text);
}

static brdffit_status parse_angle(const csv_layout *lay, const csv_line *l, size_t col,
                                  const char *p, size_t len, double *out, brdffit_error *err)
{
    bf_number_kind kind = bf_parse_number(p, len, out);
    int polar = lay->scattered ? (col == 0 || col == 2) : col < 2;
    double lo = polar ? 0.0 : (lay->scattered ? -360.0 : 0.0);
    double hi = polar ? 90.0 : (lay->scattered ? 360.0 : 180.0);
    if (kind == BF_NUMBER_EMPTY || kind == BF_NUMBER_NAN)
        return number_error(lay, l, col, BRDFFIT_E_PARSE, "missing angle", p, len, err);
    if (kind == BF_NUMBER_MALFORMED)
        return number_error(lay, l, col, BRDFFIT_E_PARSE, "malformed number", p, len, err);
    if (kind == BF_NUMBER_INF)
        return number_error(lay, l, col, BRDFFIT_E_RANGE, "infinite angle", p, len, err);
    if (*out < lo || *out > hi) {
        char what[64];
        bf_format(what, sizeof what, "angle outside [%g, %g] degrees", lo, hi);
        return number_error(lay, l, col, BRDFFIT_E_RANGE, what, p, len, err);
    }
    *out += 0.0; /* -0 becomes +0 */
    return BRDFFIT_OK;
}

static brdffit_status parse_value(const csv_layout *lay, const csv_line *l, size_t col,
                                  const char *p, size_t len, double *out, unsigned char *missing,
                                  brdffit_error *err)
{
    bf_number_kind kind = bf_parse_number(p, len, out);
    *missing = kind == BF_NUMBER_EMPTY || kind == BF_NUMBER_NAN;
    if (*missing) {
        *out = 0.0;
        return BRDFFIT_OK;
    }
    if (kind == BF_NUMBER_MALFORMED)
        return number_error(lay, l, col, BRDFFIT_E_PARSE, "malformed number", p, len, err);
    if (kind == BF_NUMBER_INF)
        return number_error(lay, l, col, BRDFFIT_E_RANGE, "infinite value", p, len, err);
    if (*out < 0.0)
        return number_error(lay, l, col, BRDFFIT_E_RANGE, "negative value", p, len, err);
    *out += 0.0;
    return BRDFFIT_OK;
}

/* A sample weight: a finite number >= 0, never missing. */
static brdffit_status parse_weight(const csv_layout *lay, const csv_line *l, const char *p,
                                   size_t len, double *out, brdffit_error *err)
{
    bf_number_kind kind = bf_parse_number(p, len, out);
    if (kind == BF_NUMBER_EMPTY || kind == BF_NUMBER_NAN)
        return number_error(lay, l, 4, BRDFFIT_E_PARSE, "missing weight", p, len, err);
    if (kind == BF_NUMBER_MALFORMED)
        return number_error(lay, l, 4, BRDFFIT_E_PARSE, "malformed number", p, len, err);
    if (kind == BF_NUMBER_INF)
        return number_error(lay, l, 4, BRDFFIT_E_RANGE, "infinite weight", p, len, err);
    if (*out < 0.0) return number_error(lay, l, 4, BRDFFIT_E_RANGE, "negative weight", p, len, err);
    *out += 0.0;
    return BRDFFIT_OK;
}

static brdffit_status parse_row(const csv_layout *lay, const csv_line *l, size_t r, csv_data *d,
                                brdffit_error *err)
{
    size_t pos = 0, k, n = count_fields(l), nc = lay->n_channels;
    const char *p;
    size_t len;
    if (n != lay->n_fields)
        return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: expected %zu columns, found %zu", l->number,
                       lay->n_fields, n);
    for (k = 0; k < lay->n_angles; k++) {
        next_field(l, &pos, &p, &len);
        BF_RETURN_IF_ERROR(parse_angle(lay, l, k, p, len, &d->angles[k * d->n_rows + r], err));
    }
    if (lay->weight) {
        next_field(l, &pos, &p, &len);
        BF_RETURN_IF_ERROR(parse_weight(lay, l, p, len, &d->weights[r], err));
    }
    for (k = 0; k < nc; k++) {
        size_t v = r * nc + k;
        next_field(l, &pos, &p, &len);
        BF_RETURN_IF_ERROR(parse_value(lay, l, lay->n_fields - nc + k, p, len, &d->values[v],
                                       &d->missing[v], err));
        d->n_missing += d->missing[v];
    }
    d->lines[r] = l->number;
    return BRDFFIT_OK;
}

static void data_free(csv_data *d, const brdffit_allocator *a)
{
    bf_free(a, d->angles);
    bf_free(a, d->values);
    bf_free(a, d->missing);
    bf_free(a, d->lines);
    bf_free(a, d->weights);
    memset(d, 0, sizeof *d);
}

static brdffit_status oom(brdffit_error *err)
{
    return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while loading CSV data");
}

static brdffit_status data_alloc(csv_data *d, const csv_layout *lay, size_t n_rows,
                                 const brdffit_allocator *a, brdffit_error *err)
{
    size_t n_values, n_angles;
    memset(d, 0, sizeof *d);
    d->n_rows = n_rows;
    if (!bf_mul_size(n_rows, lay->n_channels, &n_values) || n_values > BF_LOAD_MAX_VALUES ||
        !bf_mul_size(n_rows, lay->n_angles, &n_angles))
        return bf_fail(err, BRDFFIT_E_TOO_LARGE,
                       "%zu rows of %zu channels are more than the %zu values allowed", n_rows,
                       lay->n_channels, BF_LOAD_MAX_VALUES);
    d->angles = bf_calloc(a, n_angles, sizeof(double));
    d->values = bf_calloc(a, n_values, sizeof(double));
    d->missing = bf_calloc(a, n_values, 1);
    d->lines = bf_calloc(a, n_rows, sizeof(size_t));
    if (lay->weight) d->weights = bf_calloc(a, n_rows, sizeof(double));
    if (d->angles == NULL || d->values == NULL || d->missing == NULL || d->lines == NULL ||
        (lay->weight && d->weights == NULL)) {
        data_free(d, a);
        return oom(err);
    }
    return BRDFFIT_OK;
}

/* Header, row count, and every row parsed. */
static brdffit_status read_rows(const char *text, size_t size, csv_layout *lay, csv_data *d,
                                const brdffit_allocator *a, brdffit_error *err)
{
    csv_reader r = {text, size, 0, 0};
    csv_line l;
    size_t n_rows = 0, row;
    csv_reader start;
    if (size >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) r.pos = 3; /* UTF-8 BOM */
    if (!next_data_line(&r, &l)) return bf_fail(err, BRDFFIT_E_PARSE, "empty file: no header line");
    BF_RETURN_IF_ERROR(parse_header(&l, lay, err));
    start = r;
    while (next_data_line(&r, &l)) n_rows++;
    if (n_rows == 0)
        return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: header but no data rows",
                       lay->header.number);
    BF_RETURN_IF_ERROR(data_alloc(d, lay, n_rows, a, err));
    for (r = start, row = 0; next_data_line(&r, &l); row++) {
        brdffit_status st = parse_row(lay, &l, row, d, err);
        if (st != BRDFFIT_OK) {
            data_free(d, a);
            return st;
        }
    }
    return BRDFFIT_OK;
}

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
                                         d->n_missing > 0 ? d->missing : NULL, d->weights, a, err);
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
    if (block == NULL) return oom(err);
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
                               grid_names[k], ax->deg[k][m - 1], ax->deg[k][m]);
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
    if (b->keys == NULL) return oom(err);
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
        return oom(err);
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
    BF_RETURN_IF_ERROR(read_rows(text, size, &lay, &d, a, err));
    st = lay.scattered ? build_scattered(out, &d, &lay, a, err) : build_grid(out, &d, &lay, a, err);
    data_free(&d, a);
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
