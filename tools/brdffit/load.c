/* Loading a measurement: the file is read once (a pipe or FIFO works too)
 * and its format told from its content, never from its name: MERL binary
 * (the int32 dimensions 90, 90, 180 first), RGL .bsdf (a "tensor_file"),
 * ASTM E1392 (a header keyword first: an upper-case word), else CSV; other
 * binary content goes to the MERL loader, which names what is wrong. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static long le32(const unsigned char *p)
{
    unsigned long v = (unsigned long)p[0] | ((unsigned long)p[1] << 8) |
                      ((unsigned long)p[2] << 16) | ((unsigned long)p[3] << 24);
    return (long)v;
}

/* The whole file in a new buffer; 0 (msg set) when it cannot be read. */
static int read_all(const char *path, unsigned char **data, size_t *size, char *msg,
                    size_t msg_size)
{
    FILE *f = fopen(path, "rb");
    size_t cap = 1 << 16, n = 0, got;
    unsigned char *buf, *grown;
    *data = NULL, *size = 0;
    if (f == NULL) {
        cli_format(msg, msg_size, "cannot open '%s'%s", path,
                   errno == ENOENT ? ": no such file or directory" : "");
        return 0;
    }
    buf = malloc(cap);
    while (buf != NULL && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n < cap) continue;
        grown = cap > ((size_t)-1 >> 2) ? NULL : realloc(buf, cap * 2);
        if (grown == NULL) free(buf);
        buf = grown, cap *= 2;
    }
    if (buf == NULL || ferror(f)) {
        cli_format(msg, msg_size, buf == NULL ? "out of memory reading '%s'" : "cannot read '%s'",
                   path);
        free(buf);
        fclose(f);
        return 0;
    }
    fclose(f);
    *data = buf, *size = n;
    return 1;
}

/* A NUL byte early on: binary, so MERL (the only other binary format),
 * whose loader then says what is wrong with the header or size. */
static int looks_binary(const unsigned char *p, size_t n)
{
    return memchr(p, '\0', n < 512 ? n : 512) != NULL;
}

/* ASTM E1392 text starts (after blank lines) with an upper-case keyword. */
static int looks_like_astm(const unsigned char *p, size_t n)
{
    size_t k = n >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    while (k < n && (p[k] == ' ' || p[k] == '\t' || p[k] == '\r' || p[k] == '\n')) k++;
    return k < n && p[k] >= 'A' && p[k] <= 'Z';
}

brdffit_status cli_load(const char *path, brdffit_grid **grid, const char **what, char *msg,
                        size_t msg_size)
{
    brdffit_error err;
    brdffit_status st;
    unsigned char *d;
    size_t n;
    *grid = NULL;
    *what = "unreadable";
    if (!read_all(path, &d, &n, msg, msg_size)) return BRDFFIT_E_IO;
    if (n >= 12 && memcmp(d, "tensor_file", 12) == 0) {
        *what = "RGL .bsdf, the samples as measured";
        st = brdffit_load_rgl_buffer(grid, d, n, NULL, NULL, &err);
    } else if ((n >= 12 && le32(d) == 90 && le32(d + 4) == 90 && le32(d + 8) == 180) ||
               looks_binary(d, n)) {
        *what = "MERL binary, resampled onto the default axes";
        st = brdffit_load_merl_buffer(grid, d, n, brdffit_axes_default(), NULL, &err);
    } else if (looks_like_astm(d, n)) {
        *what = "ASTM E1392";
        st = brdffit_load_astm_buffer(grid, (const char *)d, n, NULL, &err);
    } else {
        *what = "CSV";
        st = brdffit_load_csv_buffer(grid, (const char *)d, n, NULL, &err);
    }
    free(d);
    if (st != BRDFFIT_OK) cli_format(msg, msg_size, "%s", err.message);
    return st;
}
