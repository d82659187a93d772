/* Helpers shared by the loaders: the one place that reads files, and the
 * locale-independent number parser. Not installed. */
#ifndef BRDFFIT_LOAD_INTERNAL_H
#define BRDFFIT_LOAD_INTERNAL_H

#include <stddef.h>
#include <stdio.h>

#include "brdffit/alloc.h"
#include "brdffit/grid.h"
#include "brdffit/status.h"

/* Largest number of values a loader accepts (2^31). */
#define BF_LOAD_MAX_VALUES ((size_t)1 << 31)

/* The checks every loader makes first: out not NULL (and set to NULL),
 * in not NULL, a complete allocator (copied into *a), and axes (when not
 * NULL) as bf_load_axes_count() checks them for one channel. */
brdffit_status bf_load_begin(brdffit_grid **out, const void *in, const brdffit_axes *axes,
                             const brdffit_allocator *alloc, brdffit_allocator *a,
                             brdffit_error *err);
/* Number of combinations of the axes: not empty, at most
 * BF_LOAD_MAX_VALUES / n_channels of them, each axis inside its range and
 * strictly increasing (the statuses of brdffit_grid_create_regular()), so
 * that bad axes are refused before a file is opened. */
brdffit_status bf_load_axes_count(const brdffit_axes *axes, size_t n_channels, size_t *n_samples,
                                  brdffit_error *err);

/* An open file whose size is known. */
typedef struct bf_file {
    FILE *fp;
    size_t size;
} bf_file;

/* Open path for binary reading and find its size (BRDFFIT_E_IO when it
 * cannot be opened, positioned or read). */
brdffit_status bf_file_open(bf_file *f, const char *path, brdffit_error *err);
/* Read exactly n bytes at offset into buf (BRDFFIT_E_IO on failure). */
brdffit_status bf_file_read(bf_file *f, size_t offset, void *buf, size_t n, const char *path,
                            brdffit_error *err);
void bf_file_close(bf_file *f);
/* Read a whole file of at most max_size bytes into a new buffer (one extra
 * NUL byte after the data). BRDFFIT_E_TOO_LARGE beyond max_size, checked
 * before anything is allocated. */
brdffit_status bf_file_read_all(const char *path, size_t max_size, const brdffit_allocator *alloc,
                                char **data, size_t *size, brdffit_error *err);

/* ---- text: lines (ending in '\n' or "\r\n") and fields ---- */

typedef struct bf_line {
    const char *p;
    size_t len;    /* without the line end */
    size_t number; /* 1-based */
} bf_line;

typedef struct bf_text {
    const char *data;
    size_t size, pos, line;
} bf_text;

/* Start reading data[0..size), skipping a UTF-8 byte order mark. */
void bf_text_init(bf_text *r, const char *data, size_t size);
/* The next line; 0 at the end of the text. */
int bf_text_next_line(bf_text *r, bf_line *out);
/* The next line that is not blank (spaces and tabs only) and does not
 * start (after blanks) with `comment` ('\0': no comments). */
int bf_text_next_data_line(bf_text *r, bf_line *out, char comment);
int bf_line_blank(const bf_line *l, char comment);
int bf_is_blank(char c);
/* Trim spaces and tabs from both ends. */
void bf_trim(const char **p, size_t *len);
/* A printable excerpt of p[0..len) for messages, cut with "...". */
void bf_excerpt(char *buf, size_t size, const char *p, size_t len);

/* Outcome of parsing one decimal number. */
typedef enum bf_number_kind {
    BF_NUMBER_OK = 0,       /* *value holds the correctly rounded value */
    BF_NUMBER_EMPTY = 1,    /* empty field */
    BF_NUMBER_NAN = 2,      /* "nan", any case */
    BF_NUMBER_INF = 3,      /* infinite: "inf", "infinity" or overflow */
    BF_NUMBER_MALFORMED = 4 /* anything else */
} bf_number_kind;

/* Parse [+-]digits[.digits][(e|E)[+-]digits] (at least one mantissa
 * digit), or nan / inf / infinity, from s[0..len) without looking at the
 * locale. Spaces and tabs around the number are ignored. Values that
 * overflow give BF_NUMBER_INF with *value = +-HUGE_VAL. */
bf_number_kind bf_parse_number(const char *s, size_t len, double *value);

#endif /* BRDFFIT_LOAD_INTERNAL_H */
