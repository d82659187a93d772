/* The CSV loader's two halves: csv_rows.c reads the header and the rows,
 * csv.c makes the grid. Not installed. */
#ifndef BRDFFIT_CSV_INTERNAL_H
#define BRDFFIT_CSV_INTERNAL_H

#include "load/load_internal.h"

typedef struct csv_layout {
    int scattered;
    int weight; /* scattered form: column 5 holds each sample's weight */
    size_t n_angles, n_channels, n_fields;
    bf_line header;
} csv_layout;

typedef struct csv_data {
    size_t n_rows;
    double *angles;         /* [k * n_rows + r], degrees */
    double *values;         /* [r * n_channels + c] */
    unsigned char *missing; /* [r * n_channels + c] */
    size_t *lines;          /* line of row r */
    double *weights;        /* row weights, or NULL without a weight column */
    size_t n_missing;
} csv_data;

/* Header, row count, and every row parsed into *d (freed with
 * bf_csv_data_free(); nothing to free on failure). */
brdffit_status bf_csv_read_rows(const char *text, size_t size, csv_layout *lay, csv_data *d,
                                const brdffit_allocator *a, brdffit_error *err);
void bf_csv_data_free(csv_data *d, const brdffit_allocator *a);
brdffit_status bf_csv_oom(brdffit_error *err);

#endif /* BRDFFIT_CSV_INTERNAL_H */
