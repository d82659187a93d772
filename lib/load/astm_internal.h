/* The ASTM E1392 loader's two halves: astm.c reads the header, astm_rows.c
 * the rows and makes the grid. Not installed. */
#ifndef BRDFFIT_ASTM_INTERNAL_H
#define BRDFFIT_ASTM_INTERNAL_H

#include "load/load_internal.h"

enum { BF_ASTM_THETA_I = 0, BF_ASTM_PHI_I = 1, BF_ASTM_THETA_S = 2, BF_ASTM_PHI_S = 3 };

typedef struct astm_layout {
    size_t n_fields, n_channels;
    size_t col[4]; /* column of each angle; (size_t)-1 for a missing phi_i */
    size_t num_points;
    int has_num_points;
    bf_line vars; /* for the column names in messages */
    size_t vars_start;
    int vars_commas;
} astm_layout;

/* The header up to and including the VARS line. */
brdffit_status bf_astm_header(bf_text *r, astm_layout *lay, brdffit_error *err);
/* The next field of a data row (commas and/or blanks); 0 past the last. */
int bf_astm_token(const bf_line *l, size_t *pos, const char **p, size_t *len);
/* Name of column col (0-based) for messages. */
void bf_astm_column_name(const astm_layout *lay, size_t col, char *buf, size_t size);

#endif /* BRDFFIT_ASTM_INTERNAL_H */
