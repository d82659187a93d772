/* The ASTM E1392 loader (docs/formats.md): the text files of the ASTM
 * E1392 standard practice for angle-resolved scatter data, the format of
 * the Cornell gonioreflectometer measurements.
 *
 * A header of keyword lines ("KEYWORD value...") ends with the VARS line
 * naming the columns; the data rows follow, one sample per row. The angle
 * columns are theta_i, phi_i (optional: 0 when absent), theta_s, phi_s;
 * every other column is a channel (R, G, B, a band such as "550nm", ...).
 * Two passes: the first counts the rows, the second parses them into
 * arrays of that size. */
#include <math.h>
#include <string.h>

#include "brdffit/load.h"
#include "core/core.h"
#include "load/astm_internal.h"

/* ---- tokens ------------------------------------------------------------ */

/* The next field of a data row: separated by a comma, by blanks, or by
 * both; two commas in a row delimit an empty field. 0 past the last. */
int bf_astm_token(const bf_line *l, size_t *pos, const char **p, size_t *len)
{
    size_t k = *pos, start;
    while (k < l->len && bf_is_blank(l->p[k])) k++;
    if (k >= l->len) return 0;
    start = k;
    while (k < l->len && l->p[k] != ',' && !bf_is_blank(l->p[k])) k++;
    *p = l->p + start;
    *len = k - start;
    while (k < l->len && bf_is_blank(l->p[k])) k++;
    if (k < l->len && l->p[k] == ',') k++;
    *pos = k;
    return 1;
}

/* The next name of the VARS list after `pos`: comma-separated when the
 * list has a comma (names may hold blanks), else blank-separated. */
static int next_name(const bf_line *l, int commas, size_t *pos, const char **p, size_t *len)
{
    const char *c;
    if (!commas) return bf_astm_token(l, pos, p, len);
    if (*pos > l->len) return 0;
    *p = l->p + *pos;
    c = memchr(*p, ',', l->len - *pos);
    *len = c != NULL ? (size_t)(c - *p) : l->len - *pos;
    *pos += *len + 1;
    bf_trim(p, len);
    return 1;
}

/* ---- the header ---------------------------------------------------------- */

static int word_is(const char *p, size_t len, const char *w)
{
    size_t k;
    if (strlen(w) != len) return 0;
    for (k = 0; k < len; k++) {
        char c = p[k] >= 'A' && p[k] <= 'Z' ? (char)(p[k] - 'A' + 'a') : p[k];
        if (c != w[k]) return 0;
    }
    return 1;
}

/* Role of a column name: BF_ASTM_THETA_I .. BF_ASTM_PHI_S, or -1 (a channel). */
static int angle_role(const char *p, size_t len)
{
    static const char *const names[4][3] = {{"theta_i", "theta_i", "theta_i"},
                                            {"phi_i", "phi_i", "phi_i"},
                                            {"theta_s", "theta_r", "theta_o"},
                                            {"phi_s", "phi_r", "phi_o"}};
    int r, k;
    for (r = 0; r < 4; r++)
        for (k = 0; k < 3; k++)
            if (word_is(p, len, names[r][k])) return r;
    return -1;
}

static brdffit_status parse_vars(const bf_line *l, size_t start, astm_layout *lay,
                                 brdffit_error *err)
{
    size_t pos = start, len, col = 0;
    const char *p;
    int r, commas = memchr(l->p + start, ',', l->len - start) != NULL;
    for (r = 0; r < 4; r++) lay->col[r] = (size_t)-1;
    while (next_name(l, commas, &pos, &p, &len)) {
        r = angle_role(p, len);
        if (len == 0)
            return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: VARS name %zu is empty", l->number,
                           col + 1);
        if (r >= 0 && lay->col[r] != (size_t)-1)
            return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: VARS names '%.*s' twice", l->number,
                           (int)len, p);
        if (r >= 0) lay->col[r] = col;
        col++;
    }
    lay->n_fields = col;
    for (r = 0; r < 4; r++)
        if (r != BF_ASTM_PHI_I && lay->col[r] == (size_t)-1)
            return bf_fail(err, BRDFFIT_E_PARSE,
                           "line %zu: VARS lacks %s (the columns are theta_i, phi_i, theta_s, "
                           "phi_s and the channels)",
                           l->number, r == 0 ? "theta_i" : r == 2 ? "theta_s" : "phi_s");
    lay->n_channels = col - 3 - (lay->col[BF_ASTM_PHI_I] != (size_t)-1);
    if (lay->n_channels == 0)
        return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: VARS names no value column", l->number);
    lay->vars = *l, lay->vars_start = start, lay->vars_commas = commas;
    return BRDFFIT_OK;
}

/* A NUM_POINTS value: a non-negative integer. */
static brdffit_status parse_count(const bf_line *l, const char *p, size_t len, astm_layout *lay,
                                  brdffit_error *err)
{
    double v;
    bf_trim(&p, &len);
    if (bf_parse_number(p, len, &v) != BF_NUMBER_OK || v < 0.0 || v != floor(v) || v > 4e18)
        return bf_fail(err, BRDFFIT_E_PARSE, "line %zu: NUM_POINTS '%.*s' is not a count",
                       l->number, (int)(len < 40 ? len : 40), p);
    lay->num_points = (size_t)v;
    lay->has_num_points = 1;
    return BRDFFIT_OK;
}

static int is_keyword_char(char c)
{
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
           c == '_';
}

brdffit_status bf_astm_header(bf_text *r, astm_layout *lay, brdffit_error *err)
{
    bf_line l;
    memset(lay, 0, sizeof *lay);
    while (bf_text_next_data_line(r, &l, '\0')) {
        size_t k = 0, end;
        while (bf_is_blank(l.p[k])) k++;
        end = k;
        while (end < l.len && is_keyword_char(l.p[end])) end++;
        if (end == k || !(l.p[k] >= 'A' && l.p[k] <= 'Z'))
            return bf_fail(err, BRDFFIT_E_PARSE,
                           "line %zu: expected a header keyword (the header ends with VARS)",
                           l.number);
        if (word_is(l.p + k, end - k, "vars") && end - k == 4)
            return parse_vars(&l, end, lay, err);
        if (end - k == 10 && memcmp(l.p + k, "NUM_POINTS", 10) == 0)
            BF_RETURN_IF_ERROR(parse_count(&l, l.p + end, l.len - end, lay, err));
    }
    return bf_fail(err, BRDFFIT_E_PARSE,
                   lay->has_num_points || r->line > 0 ? "no VARS line: the header never ends"
                                                      : "empty file: no ASTM E1392 header");
}

void bf_astm_column_name(const astm_layout *lay, size_t col, char *buf, size_t size)
{
    size_t pos = lay->vars_start, k;
    const char *p = "";
    size_t len = 0;
    for (k = 0; k <= col; k++)
        if (!next_name(&lay->vars, lay->vars_commas, &pos, &p, &len)) len = 0;
    bf_excerpt(buf, size, p, len);
}
