/* brdffit map: a texel map in one CSV file (docs/formats.md, Texel maps),
 * read into one geometry grid and the values of every texel, in the
 * layout brdffit_fit_many() takes. */
#ifndef BRDFFIT_CLI_MAP_H
#define BRDFFIT_CLI_MAP_H

#include <stddef.h>

#include "cli.h"

typedef struct map_data {
    char *text;             /* the file, fields cut in place */
    size_t n_texels, n_samples, n_channels;
    char **texel;           /* n_texels: each texel's name (into text) */
    brdffit_grid *grid;     /* geometry (and the first texel's values) */
    double *values;         /* n_texels * n_samples * n_channels, grid creation order */
    unsigned char *missing; /* same layout */
} map_data;

/* Read `path`; 0 on success, else msg says why (with the line). */
int map_read(const char *path, map_data *m, char *msg, size_t msg_size);
void map_free(map_data *m);

#endif
