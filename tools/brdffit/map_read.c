/* Reading a texel map (map.h): a CSV file whose first column names the
 * texel and whose other columns are the library's CSV (either form). The
 * first texel's rows make the geometry grid through brdffit_load_csv_buffer(),
 * with every check of the library's reader; every other texel must have the
 * same directions in the same order, and only its values are read. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "map.h"

#define PI 3.14159265358979323846

typedef struct line {
    char *text;    /* NUL-terminated, no line end */
    size_t number; /* 1-based, counting every line of the file */
} line;

typedef struct reader {
    map_data *m;
    line *lines;   /* header and data lines */
    size_t n_lines, n_fields, n_angles;
    int regular;
    size_t *index;  /* n_samples: creation-order sample of each row of a texel */
    double *angles; /* n_samples * n_angles: the first texel's angles */
    char **fields;
    char *msg;
    size_t msg_size;
} reader;

static int bad(reader *rd, size_t line_no, const char *what)
{
    if (line_no > 0) cli_format(rd->msg, rd->msg_size, "line %zu: %s", line_no, what);
    else cli_format(rd->msg, rd->msg_size, "%s", what);
    return -1;
}

static char *read_all(const char *path, size_t *size, char *msg, size_t msg_size)
{
    FILE *f = fopen(path, "rb");
    char *text = NULL;
    size_t cap = 0, n = 0, got;
    if (f == NULL) {
        cli_format(msg, msg_size, "cannot open the file");
        return NULL;
    }
    do {
        if (n + 65536 + 1 > cap) {
            char *t = realloc(text, cap = 2 * cap + 65536 + 1);
            if (t == NULL) break;
            text = t;
        }
        n += got = fread(text + n, 1, cap - n - 1, f);
    } while (got > 0);
    if (ferror(f) || text == NULL || n + 1 > cap) {
        cli_format(msg, msg_size, "cannot read the file");
        free(text);
        text = NULL;
    } else {
        text[n] = '\0';
        *size = n;
    }
    fclose(f);
    return text;
}

static int blank_or_comment(const char *s)
{
    while (*s == ' ' || *s == '\t') s++;
    return *s == '\0' || *s == '#';
}

/* Cut the text into lines; keep the header and the data lines. */
static int split_lines(reader *rd, char *text, size_t size)
{
    size_t cap = 1024, number = 0;
    char *p = text;
    if (size >= 3 && memcmp(p, "\xef\xbb\xbf", 3) == 0) p += 3;
    rd->lines = malloc(cap * sizeof *rd->lines);
    while (rd->lines != NULL && *p != '\0') {
        char *end = strchr(p, '\n'), *next = end ? end + 1 : p + strlen(p);
        if (end != NULL) *end = '\0';
        if (end != NULL && end > p && end[-1] == '\r') end[-1] = '\0';
        number++;
        if (!blank_or_comment(p)) {
            if (rd->n_lines == cap) {
                line *l = realloc(rd->lines, (cap *= 2) * sizeof *l);
                if (l == NULL) break;
                rd->lines = l;
            }
            rd->lines[rd->n_lines].text = p;
            rd->lines[rd->n_lines++].number = number;
        }
        p = next;
    }
    if (rd->lines == NULL || *p != '\0') return bad(rd, 0, "out of memory");
    if (rd->n_lines < 2) return bad(rd, 0, "no header and data rows");
    return 0;
}

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t') s++;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t')) *--e = '\0';
    return s;
}

/* Cut a line into at most `max` trimmed fields; returns their count. */
static size_t cut_fields(char *s, char **fields, size_t max)
{
    size_t n = 0;
    for (;;) {
        char *comma = strchr(s, ',');
        if (comma != NULL) *comma = '\0';
        if (n < max) fields[n] = trim(s);
        n++;
        if (comma == NULL) return n;
        s = comma + 1;
    }
}

/* The texel's name: the first field of a data line (not cut). */
static size_t name_length(const char *s)
{
    const char *comma = strchr(s, ',');
    return comma != NULL ? (size_t)(comma - s) : strlen(s);
}

static int same_texel(const char *a, const char *b)
{
    size_t n = name_length(a);
    return n == name_length(b) && strncmp(a, b, n) == 0;
}

static const char *after_texel(const char *s)
{
    const char *comma = strchr(s, ',');
    return comma != NULL ? comma + 1 : "";
}

static int header(reader *rd)
{
    char *copy = malloc(strlen(rd->lines[0].text) + 1), *f[8];
    size_t n;
    int ok;
    if (copy == NULL) return bad(rd, 0, "out of memory");
    strcpy(copy, rd->lines[0].text);
    n = cut_fields(copy, f, 8);
    ok = n >= 2 && strcmp(f[0], "texel") == 0;
    if (ok && n >= 5 && strcmp(f[1], "theta_i") == 0 && strcmp(f[2], "phi_i") == 0 &&
        strcmp(f[3], "theta_o") == 0 && strcmp(f[4], "phi_o") == 0)
        rd->n_angles = n >= 6 && strcmp(f[5], "weight") == 0 ? 5 : 4;
    else if (ok && n >= 4 && strcmp(f[1], "theta_i") == 0 && strcmp(f[2], "theta_o") == 0 &&
             strcmp(f[3], "phi_o") == 0)
        rd->n_angles = 3, rd->regular = 1;
    else
        ok = 0;
    rd->n_fields = n;
    free(copy);
    if (!ok || rd->n_fields < 2 + rd->n_angles)
        return bad(rd, rd->lines[0].number,
                   "the header must be texel, then theta_i,theta_o,phi_o or "
                   "theta_i,phi_i,theta_o,phi_o[,weight], then at least one channel");
    rd->m->n_channels = rd->n_fields - 1 - rd->n_angles;
    return 0;
}

/* The first texel's rows as the library's CSV, with the file's line
 * numbers (other lines become comments), into a geometry grid. */
static int load_geometry(reader *rd)
{
    cli_buf b;
    brdffit_error err;
    size_t i, l = 1, ns = 1;
    while (ns + 1 < rd->n_lines && same_texel(rd->lines[1].text, rd->lines[ns + 1].text)) ns++;
    rd->m->n_samples = ns;
    cli_buf_init(&b);
    for (i = 0; i <= ns; i++) {
        for (; l < rd->lines[i].number; l++) cli_buf_puts(&b, "#\n");
        cli_buf_puts(&b, after_texel(rd->lines[i].text));
        cli_buf_puts(&b, "\n");
        l++;
    }
    if (b.failed) {
        cli_buf_free(&b);
        return bad(rd, 0, "out of memory");
    }
    if (brdffit_load_csv_buffer(&rd->m->grid, b.data, b.len, NULL, &err) != BRDFFIT_OK) {
        char what[CLI_MSG_SIZE];
        cli_format(what, sizeof what, "the first texel's rows: %s", err.message);
        cli_buf_free(&b);
        return bad(rd, 0, what);
    }
    cli_buf_free(&b);
    if (brdffit_grid_sample_count(rd->m->grid) != ns)
        return bad(rd, 0, "the first texel's rows do not make one sample each");
    return 0;
}

static int parse_number(const char *s, double *out)
{
    char *end;
    if (*s == '\0' || strspn(s, "0123456789+-.eE") != strlen(s)) return 0;
    *out = strtod(s, &end);
    return *end == '\0';
}

/* Axis index of an angle in degrees, converted as the library does. */
static size_t axis_index(const brdffit_grid *g, brdffit_axis axis, double deg)
{
    const double *x;
    size_t n, k, best = 0;
    double rad = deg * PI / 180.0;
    if (brdffit_grid_axis(g, axis, &x, &n) != BRDFFIT_OK) return 0;
    for (k = 1; k < n; k++)
        if (fabs(x[k] - rad) < fabs(x[best] - rad)) best = k;
    return best;
}

/* Row r of the first texel: its angles, and its sample in creation order. */
static void first_row(reader *rd, size_t r, const double *ang)
{
    const brdffit_grid *g = rd->m->grid;
    size_t n_to, n_po, i, j, k;
    const double *x;
    memcpy(rd->angles + r * rd->n_angles, ang, rd->n_angles * sizeof *ang);
    if (!rd->regular) {
        rd->index[r] = r;
        return;
    }
    brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_O, &x, &n_to);
    brdffit_grid_axis(g, BRDFFIT_AXIS_PHI_O, &x, &n_po);
    i = axis_index(g, BRDFFIT_AXIS_THETA_I, ang[0]);
    j = axis_index(g, BRDFFIT_AXIS_THETA_O, ang[1]);
    k = axis_index(g, BRDFFIT_AXIS_PHI_O, ang[2]);
    rd->index[r] = (i * n_to + j) * n_po + k;
}

static int is_nan_text(const char *s)
{
    return (s[0] == 'n' || s[0] == 'N') && (s[1] == 'a' || s[1] == 'A') &&
           (s[2] == 'n' || s[2] == 'N') && s[3] == '\0';
}

/* Data line q (texel q / ns, row q % ns). */
static int data_line(reader *rd, size_t q)
{
    map_data *m = rd->m;
    const line *ln = &rd->lines[q + 1];
    size_t ns = m->n_samples, nc = m->n_channels, t = q / ns, r = q % ns, a, c;
    double ang[5], *v;
    unsigned char *miss;
    char what[CLI_MSG_SIZE];
    if (cut_fields(ln->text, rd->fields, rd->n_fields) != rd->n_fields)
        return bad(rd, ln->number, "wrong number of fields (the header has others)");
    if (r == 0) m->texel[t] = rd->fields[0];
    else if (strcmp(m->texel[t], rd->fields[0]) != 0) {
        cli_format(what, sizeof what,
                   "texel \"%s\" starts before texel \"%s\" has its %zu rows (every texel "
                   "needs the first texel's rows, in the same order)",
                   rd->fields[0], m->texel[t], ns);
        return bad(rd, ln->number, what);
    }
    for (a = 0; a < rd->n_angles; a++)
        if (!parse_number(rd->fields[1 + a], &ang[a]))
            return bad(rd, ln->number, "malformed angle or weight");
    if (t == 0) first_row(rd, r, ang);
    else if (memcmp(ang, rd->angles + r * rd->n_angles, rd->n_angles * sizeof *ang) != 0) {
        cli_format(what, sizeof what,
                   "texel \"%s\": the directions differ from row %zu of the first texel (line "
                   "%zu); every texel needs the same samples in the same order",
                   m->texel[t], r + 1, rd->lines[r + 1].number);
        return bad(rd, ln->number, what);
    }
    v = m->values + (t * ns + rd->index[r]) * nc;
    miss = m->missing + (t * ns + rd->index[r]) * nc;
    for (c = 0; c < nc; c++) {
        const char *f = rd->fields[1 + rd->n_angles + c];
        miss[c] = *f == '\0' || is_nan_text(f);
        v[c] = 0.0;
        if (!miss[c] && !parse_number(f, &v[c])) {
            cli_format(what, sizeof what, "column %zu: malformed number '%s'",
                       2 + rd->n_angles + c, f);
            return bad(rd, ln->number, what);
        }
    }
    return 0;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Every texel's rows are consecutive: no name twice. */
static int check_names(reader *rd)
{
    map_data *m = rd->m;
    char **sorted = malloc(m->n_texels * sizeof *sorted);
    size_t t;
    int rc = 0;
    if (sorted == NULL) return bad(rd, 0, "out of memory");
    memcpy(sorted, m->texel, m->n_texels * sizeof *sorted);
    qsort(sorted, m->n_texels, sizeof *sorted, by_name);
    for (t = 1; t < m->n_texels && rc == 0; t++)
        if (strcmp(sorted[t - 1], sorted[t]) == 0) {
            char what[CLI_MSG_SIZE];
            cli_format(what, sizeof what,
                       "texel \"%s\" appears in two places (the rows of a texel must be "
                       "consecutive)",
                       sorted[t]);
            rc = bad(rd, 0, what);
        }
    free(sorted);
    return rc;
}

static int read_texels(reader *rd)
{
    map_data *m = rd->m;
    size_t n_rows = rd->n_lines - 1, q, per;
    if (n_rows % m->n_samples != 0)
        return bad(rd, 0, "the rows are not a whole number of texels of the first texel's size");
    m->n_texels = n_rows / m->n_samples;
    per = m->n_samples * m->n_channels;
    m->texel = calloc(m->n_texels, sizeof *m->texel);
    m->values = malloc(m->n_texels * per * sizeof *m->values);
    m->missing = malloc(m->n_texels * per);
    rd->index = malloc(m->n_samples * sizeof *rd->index);
    rd->angles = malloc(m->n_samples * rd->n_angles * sizeof *rd->angles);
    rd->fields = malloc(rd->n_fields * sizeof *rd->fields);
    if (!m->texel || !m->values || !m->missing || !rd->index || !rd->angles || !rd->fields)
        return bad(rd, 0, "out of memory");
    for (q = 0; q < n_rows; q++)
        if (data_line(rd, q) != 0) return -1;
    return check_names(rd);
}

int map_read(const char *path, map_data *m, char *msg, size_t msg_size)
{
    reader rd;
    size_t size = 0;
    int rc;
    memset(m, 0, sizeof *m);
    memset(&rd, 0, sizeof rd);
    rd.m = m, rd.msg = msg, rd.msg_size = msg_size;
    m->text = read_all(path, &size, msg, msg_size);
    if (m->text == NULL) return -1;
    rc = split_lines(&rd, m->text, size);
    if (rc == 0) rc = header(&rd);
    if (rc == 0) rc = load_geometry(&rd);
    if (rc == 0) rc = read_texels(&rd);
    free(rd.lines), free(rd.index), free(rd.angles), free(rd.fields);
    if (rc != 0) map_free(m);
    return rc;
}

void map_free(map_data *m)
{
    brdffit_grid_destroy(m->grid);
    free(m->text), free(m->texel), free(m->values), free(m->missing);
    memset(m, 0, sizeof *m);
}
