/* The CSV loader, part 1: the header and the rows (docs/formats.md).
 *
 * Two passes over the text: the first finds the header and counts the data
 * rows, the second parses them into arrays sized by that count (so memory
 * stays proportional to the input). Values may be negative (measurement
 * noise is data); only infinite ones are refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "load/csv_internal.h"

/* ---- lines and fields --------------------------------------------------- */

static size_t count_fields(const bf_line *l)
{
    size_t k, n = 1;
    for (k = 0; k < l->len; k++) n += l->p[k] == ',';
    return n;
}

/* The next field starting at *pos; advances *pos past its comma. Past the
 * last field it gives empty fields. */
static void next_field(const bf_line *l, size_t *pos, const char **p, size_t *len)
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

/* ---- the header ---------------------------------------------------------- */

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
    bf_trim(&p, &len);
    bf_excerpt(buf, size, p, len);
}

/* The optional weight column: a header field "weight", allowed only in
 * the scattered form and only right after phi_o. */
static brdffit_status find_weight_column(const bf_line *l, csv_layout *lay, brdffit_error *err)
{
    size_t pos = 0, k, len;
    const char *p;
    for (k = 0; k < lay->n_fields; k++) {
        next_field(l, &pos, &p, &len);
        bf_trim(&p, &len);
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

static brdffit_status parse_header(const bf_line *l, csv_layout *lay, brdffit_error *err)
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
    bf_trim(&p, &len);
    lay->scattered = field_is(p, len, "phi_i");
    lay->n_angles = lay->scattered ? 4 : 3;
    names = lay->scattered ? scattered_names : grid_names;
    for (pos = 0, k = 0; k < lay->n_fields; k++) {
        next_field(l, &pos, &p, &len);
        bf_trim(&p, &len);
        bf_excerpt(buf, sizeof buf, p, len);
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

static brdffit_status number_error(const csv_layout *lay, const bf_line *l, size_t col,
                                   brdffit_status st, const char *what, const char *p, size_t len,
                                   brdffit_error *err)
{
    char name[40], text[40];
    column_name(lay, col, name, sizeof name);
    bf_trim(&p, &len);
    bf_excerpt(text, sizeof text, p, len);
    return bf_fail(err, st, "line %zu, column %zu (%s): %s '%s'", l->number, col + 1, name, what,
                   text);
}

static brdffit_status parse_angle(const csv_layout *lay, const bf_line *l, size_t col,
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

static brdffit_status parse_value(const csv_layout *lay, const bf_line *l, size_t col,
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
    *out += 0.0;
    return BRDFFIT_OK;
}

/* A sample weight: a finite number >= 0, never missing. */
static brdffit_status parse_weight(const csv_layout *lay, const bf_line *l, const char *p,
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

static brdffit_status parse_row(const csv_layout *lay, const bf_line *l, size_t r, csv_data *d,
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

void bf_csv_data_free(csv_data *d, const brdffit_allocator *a)
{
    bf_free(a, d->angles);
    bf_free(a, d->values);
    bf_free(a, d->missing);
    bf_free(a, d->lines);
    bf_free(a, d->weights);
    memset(d, 0, sizeof *d);
}

brdffit_status bf_csv_oom(brdffit_error *err)
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
        bf_csv_data_free(d, a);
        return bf_csv_oom(err);
    }
    return BRDFFIT_OK;
}

/* Header, row count, and every row parsed. */
brdffit_status bf_csv_read_rows(const char *text, size_t size, csv_layout *lay, csv_data *d,
                                const brdffit_allocator *a, brdffit_error *err)
{
    bf_text r;
    bf_line l;
    size_t n_rows = 0, row;
    bf_text start;
    bf_text_init(&r, text, size);
    if (!bf_text_next_data_line(&r, &l, '#')) return bf_fail(err, BRDFFIT_E_PARSE, "empty file: no header line");
    BF_RETURN_IF_ERROR(parse_header(&l, lay, err));
    start = r;
    while (bf_text_next_data_line(&r, &l, '#')) n_rows++;
    if (n_rows == 0)
        return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: header but no data rows",
                       lay->header.number);
    BF_RETURN_IF_ERROR(data_alloc(d, lay, n_rows, a, err));
    for (r = start, row = 0; bf_text_next_data_line(&r, &l, '#'); row++) {
        brdffit_status st = parse_row(lay, &l, row, d, err);
        if (st != BRDFFIT_OK) {
            bf_csv_data_free(d, a);
            return st;
        }
    }
    return BRDFFIT_OK;
}
