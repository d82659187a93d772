/* Loading a measurement by file type: MERL binary or CSV. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

static long le32(const unsigned char *p)
{
    unsigned long v = (unsigned long)p[0] | ((unsigned long)p[1] << 8) |
                      ((unsigned long)p[2] << 16) | ((unsigned long)p[3] << 24);
    return (long)v;
}

/* A MERL file starts with the int32 dimensions 90, 90, 180. */
static int looks_like_merl(const char *path)
{
    unsigned char head[12];
    FILE *f = fopen(path, "rb");
    size_t n;
    if (f == NULL) return 0;
    n = fread(head, 1, sizeof head, f);
    fclose(f);
    return n == sizeof head && le32(head) == 90 && le32(head + 4) == 90 && le32(head + 8) == 180;
}

brdffit_status cli_load(const char *path, brdffit_grid **grid, const char **what, char *msg,
                        size_t msg_size)
{
    brdffit_error err;
    brdffit_status st;
    int merl = has_suffix(path, ".binary") || looks_like_merl(path);
    *grid = NULL;
    if (merl) {
        *what = "MERL binary, resampled onto the default axes";
        st = brdffit_load_merl(grid, path, brdffit_axes_default(), NULL, &err);
    } else {
        *what = "CSV";
        st = brdffit_load_csv(grid, path, NULL, &err);
    }
    if (st != BRDFFIT_OK) cli_format(msg, msg_size, "%s", err.message);
    return st;
}
