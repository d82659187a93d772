/* The ASTM E1392 loader, part 2: the data rows and the grid
 * (docs/formats.md).
 *
 * Angles are degrees, as the standard has them; a file whose every polar
 * angle lies within pi/2 and every azimuth within 2 pi in magnitude is
 * read as radians (as some public files and readers have them; no real
 * measurement in degrees stays below 1.6 degrees). A negative polar angle
 * is the direction on the other side of the normal: (|theta|, phi + 180
 * degrees). Values may be negative (noise); "nan" or an empty field marks
 * a missing value. */
#include <math.h>
#include <string.h>

#include "brdffit/load.h"
#include "core/core.h"
#include "load/astm_internal.h"

/* Rounding allowed beyond the polar and azimuth limits, radians (files
 * print angles with a few decimals: 1.5708 for pi/2). */
#define ANGLE_SLACK 1e-4

typedef struct astm_data {
    size_t n_rows;
    double *angles;         /* [k * n_rows + r], file units; k in theta_i, phi_i, theta_s, phi_s */
    double *values;         /* [r * n_channels + c] */
    unsigned char *missing; /* [r * n_channels + c] */
    size_t *lines;          /* line of row r */
    size_t n_missing;
} astm_data;

static void data_free(astm_data *d, const brdffit_allocator *a)
{
    bf_free(a, d->angles);
    bf_free(a, d->values);
    bf_free(a, d->missing);
    bf_free(a, d->lines);
    memset(d, 0, sizeof *d);
}

static brdffit_status oom(brdffit_error *err)
{
    return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while loading ASTM data");
}

static brdffit_status data_alloc(astm_data *d, const astm_layout *lay, size_t n,
                                 const brdffit_allocator *a, brdffit_error *err)
{
    size_t nv;
    memset(d, 0, sizeof *d);
    d->n_rows = n;
    if (!bf_mul_size(n, lay->n_channels, &nv) || nv > BF_LOAD_MAX_VALUES)
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "%zu rows of %zu channels are more than the %zu "
                       "values allowed", n, lay->n_channels, BF_LOAD_MAX_VALUES);
    d->angles = bf_calloc(a, n, 4 * sizeof(double));
    d->values = bf_calloc(a, nv, sizeof(double));
    d->missing = bf_calloc(a, nv, 1);
    d->lines = bf_calloc(a, n, sizeof(size_t));
    if (d->angles == NULL || d->values == NULL || d->missing == NULL || d->lines == NULL) {
        data_free(d, a);
        return oom(err);
    }
    return BRDFFIT_OK;
}

static brdffit_status field_error(const astm_layout *lay, size_t line, size_t col,
                                  brdffit_status st, const char *what, const char *p, size_t len,
                                  brdffit_error *err)
{
    char name[40], text[40];
    bf_astm_column_name(lay, col, name, sizeof name);
    bf_excerpt(text, sizeof text, p, len);
    return bf_fail(err, st, "line %zu, column %zu (%s): %s '%s'", line, col + 1, name, what, text);
}

static int angle_of(const astm_layout *lay, size_t col)
{
    int k;
    for (k = 0; k < 4; k++)
        if (lay->col[k] == col) return k;
    return -1;
}

static brdffit_status parse_field(const astm_layout *lay, const bf_line *l, size_t col,
                                  const char *p, size_t len, astm_data *d, size_t r, size_t *ch,
                                  brdffit_error *err)
{
    double v;
    int k = angle_of(lay, col);
    bf_number_kind kind = bf_parse_number(p, len, &v);
    if (kind == BF_NUMBER_MALFORMED)
        return field_error(lay, l->number, col, BRDFFIT_E_PARSE, "malformed number", p, len, err);
    if (k >= 0) {
        if (kind == BF_NUMBER_EMPTY || kind == BF_NUMBER_NAN)
            return field_error(lay, l->number, col, BRDFFIT_E_PARSE, "missing angle", p, len, err);
        if (kind == BF_NUMBER_INF)
            return field_error(lay, l->number, col, BRDFFIT_E_RANGE, "infinite angle", p, len, err);
        d->angles[(size_t)k * d->n_rows + r] = v + 0.0;
        return BRDFFIT_OK;
    }
    if (kind == BF_NUMBER_INF)
        return field_error(lay, l->number, col, BRDFFIT_E_RANGE, "infinite value", p, len, err);
    d->missing[r * lay->n_channels + *ch] = kind == BF_NUMBER_EMPTY || kind == BF_NUMBER_NAN;
    d->n_missing += d->missing[r * lay->n_channels + *ch];
    d->values[r * lay->n_channels + (*ch)++] = kind == BF_NUMBER_OK ? v + 0.0 : 0.0;
    return BRDFFIT_OK;
}

static brdffit_status parse_row(const astm_layout *lay, const bf_line *l, size_t r, astm_data *d,
                                brdffit_error *err)
{
    size_t pos = 0, col = 0, ch = 0, len;
    const char *p;
    while (bf_astm_token(l, &pos, &p, &len)) {
        if (col < lay->n_fields)
            BF_RETURN_IF_ERROR(parse_field(lay, l, col, p, len, d, r, &ch, err));
        col++;
    }
    if (col != lay->n_fields)
        return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: expected %zu values (as VARS names), "
                       "found %zu", l->number, lay->n_fields, col);
    d->lines[r] = l->number;
    return BRDFFIT_OK;
}

static brdffit_status read_rows(const char *text, size_t size, astm_layout *lay, astm_data *d,
                                const brdffit_allocator *a, brdffit_error *err)
{
    bf_text r, start;
    bf_line l;
    size_t n = 0, row;
    bf_text_init(&r, text, size);
    BF_RETURN_IF_ERROR(bf_astm_header(&r, lay, err));
    start = r;
    while (bf_text_next_data_line(&r, &l, '\0')) n++;
    if (lay->has_num_points && n != lay->num_points)
        return bf_fail(err, BRDFFIT_E_PARSE, "NUM_POINTS is %zu but the file has %zu data rows",
                       lay->num_points, n);
    if (n == 0) return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: VARS but no data rows",
                               lay->vars.number);
    BF_RETURN_IF_ERROR(data_alloc(d, lay, n, a, err));
    for (r = start, row = 0; bf_text_next_data_line(&r, &l, '\0'); row++) {
        brdffit_status st = parse_row(lay, &l, row, d, err);
        if (st != BRDFFIT_OK) {
            data_free(d, a);
            return st;
        }
    }
    return BRDFFIT_OK;
}

/* ---- units and directions ----------------------------------------------------------- */

static int in_radians(const astm_data *d)
{
    size_t k, n = d->n_rows;
    for (k = 0; k < 4 * n; k++) {
        double limit = (k / n) % 2 == 0 ? BF_HALF_PI : 2.0 * BF_PI;
        if (fabs(d->angles[k]) > limit + ANGLE_SLACK) return 0;
    }
    return 1;
}

/* Row r's angles to radians in range, or a range error naming the field. */
static brdffit_status convert_row(const astm_layout *lay, astm_data *d, size_t r, double unit,
                                  brdffit_error *err)
{
    size_t n = d->n_rows, k;
    for (k = 0; k < 4; k += 2) {
        double *t = &d->angles[k * n + r], *p = &d->angles[(k + 1) * n + r];
        double th = *t * unit, ph = *p * unit;
        if (fabs(th) > BF_HALF_PI + ANGLE_SLACK || fabs(ph) > 2.0 * BF_PI + ANGLE_SLACK) {
            int polar = fabs(th) > BF_HALF_PI + ANGLE_SLACK;
            size_t col = lay->col[polar ? k : k + 1];
            char what[64];
            bf_format(what, sizeof what, "angle outside [%s] %s", polar
                      ? (unit == 1.0 ? "-pi/2, pi/2" : "-90, 90") : (unit == 1.0 ? "-2 pi, 2 pi"
                      : "-360, 360"), unit == 1.0 ? "radians" : "degrees");
            return bf_fail(err, BRDFFIT_E_RANGE, "line %zu, column %zu: %s", d->lines[r],
                           col + 1, what);
        }
        if (th < 0.0) th = -th, ph += ph > 0.0 ? -BF_PI : BF_PI;
        *t = fmin(th, BF_HALF_PI);
        *p = fmax(-2.0 * BF_PI, fmin(ph, 2.0 * BF_PI));
    }
    return BRDFFIT_OK;
}

static brdffit_status load_text(brdffit_grid **out, const char *text, size_t size,
                                const brdffit_allocator *a, brdffit_error *err)
{
    astm_layout lay;
    astm_data d;
    size_t r, n;
    double unit;
    brdffit_status st = BRDFFIT_OK;
    BF_RETURN_IF_ERROR(read_rows(text, size, &lay, &d, a, err));
    n = d.n_rows;
    unit = in_radians(&d) ? 1.0 : BF_PI / 180.0;
    for (r = 0; st == BRDFFIT_OK && r < n; r++) st = convert_row(&lay, &d, r, unit, err);
    if (st == BRDFFIT_OK)
        st = brdffit_grid_create_scattered(out, n, d.angles, d.angles + n, d.angles + 2 * n,
                                           d.angles + 3 * n, lay.n_channels, d.values,
                                           d.n_missing > 0 ? d.missing : NULL, NULL, a, err);
    data_free(&d, a);
    return st;
}

/* ---- entry points ----------------------------------------------------------------- */

brdffit_status brdffit_load_astm_buffer(brdffit_grid **out, const char *data, size_t size,
                                        const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    BF_RETURN_IF_ERROR(bf_load_begin(out, data, NULL, alloc, &a, err));
    return load_text(out, data, size, &a, err);
}

brdffit_status brdffit_load_astm(brdffit_grid **out, const char *path,
                                 const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    char *text = NULL;
    size_t size = 0;
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_load_begin(out, path, NULL, alloc, &a, err));
    BF_RETURN_IF_ERROR(bf_file_read_all(path, (size_t)-1 >> 1, &a, &text, &size, err));
    st = load_text(out, text, size, &a, err);
    bf_free(&a, text);
    return st;
}
