/* The one place where the library reads files. */
#include <errno.h>
#include <limits.h>
#include <stdio.h>

#include "core/core.h"
#include "load/load_internal.h"

/* A fixed text for the common causes (strerror() is not thread-safe
 * everywhere). */
static const char *errno_text(int errnum)
{
    switch (errnum) {
    case ENOENT: return ": no such file or directory";
    case EACCES: return ": permission denied";
#ifdef EISDIR
    case EISDIR: return ": is a directory";
#endif
    default: return "";
    }
}

static brdffit_status io_error(brdffit_error *err, const char *what, const char *path, int errnum)
{
    return bf_fail(err, BRDFFIT_E_IO, "cannot %s '%s'%s", what, path, errno_text(errnum));
}

brdffit_status bf_file_open(bf_file *f, const char *path, brdffit_error *err)
{
    long end;
    int c;
    f->fp = NULL;
    f->size = 0;
    errno = 0;
    f->fp = fopen(path, "rb");
    if (f->fp == NULL) return io_error(err, "open", path, errno);
    /* Probe one byte first: a directory opens, but does not read. */
    c = fgetc(f->fp);
    if (c == EOF && ferror(f->fp)) {
        int e = errno;
        bf_file_close(f);
        return io_error(err, "read", path, e);
    }
    if (fseek(f->fp, 0, SEEK_END) != 0 || (end = ftell(f->fp)) < 0 ||
        (unsigned long)end > (unsigned long)((size_t)-1 >> 1)) {
        int e = errno;
        bf_file_close(f);
        return io_error(err, "find the size of", path, e);
    }
    f->size = (size_t)end;
    return BRDFFIT_OK;
}

brdffit_status bf_file_read(bf_file *f, size_t offset, void *buf, size_t n, const char *path,
                            brdffit_error *err)
{
    if (offset > (size_t)LONG_MAX || fseek(f->fp, (long)offset, SEEK_SET) != 0)
        return io_error(err, "position in", path, errno);
    if (fread(buf, 1, n, f->fp) != n) return io_error(err, "read", path, errno);
    return BRDFFIT_OK;
}

void bf_file_close(bf_file *f)
{
    if (f->fp != NULL) fclose(f->fp);
    f->fp = NULL;
}

brdffit_status bf_file_read_all(const char *path, size_t max_size, const brdffit_allocator *alloc,
                                char **data, size_t *size, brdffit_error *err)
{
    bf_file f;
    char *buf;
    brdffit_status st;
    *data = NULL;
    *size = 0;
    BF_RETURN_IF_ERROR(bf_file_open(&f, path, err));
    if (f.size > max_size) {
        bf_file_close(&f);
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "'%s' has %zu bytes, more than the %zu allowed",
                       path, f.size, max_size);
    }
    buf = bf_malloc(alloc, f.size + 1);
    if (buf == NULL) {
        bf_file_close(&f);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory reading '%s' (%zu bytes)", path,
                       f.size);
    }
    st = bf_file_read(&f, 0, buf, f.size, path, err);
    bf_file_close(&f);
    if (st != BRDFFIT_OK) {
        bf_free(alloc, buf);
        return st;
    }
    buf[f.size] = '\0';
    *data = buf;
    *size = f.size;
    return BRDFFIT_OK;
}
