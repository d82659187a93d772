/* The one place where the library reads files.
 *
 * Only regular files are read: a FIFO, a device or a socket is refused
 * before a byte is read (a FIFO is opened without waiting for a writer),
 * and so is a file that reports a size of 0 but has content (files of
 * /proc and /sys), whose size cannot be known in advance. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/core.h"
#include "load/load_internal.h"

/* A fixed text for the common causes (strerror() is not thread-safe
 * everywhere). */
static const char *errno_text(int errnum)
{
    switch (errnum) {
    case ENOENT: return ": no such file or directory";
    case EACCES: return ": permission denied";
    case EISDIR: return ": is a directory";
    case ELOOP: return ": too many levels of symbolic links (a symlink loop?)";
    case ENOTDIR: return ": a component of the path is not a directory";
    case ENAMETOOLONG: return ": file name too long";
    case EMFILE:
    case ENFILE: return ": too many open files";
    case ENXIO: return ": no such device or address";
    case EPERM: return ": operation not permitted";
    case EIO: return ": input/output error";
    case ENOMEM: return ": out of memory";
    case EOVERFLOW: return ": file too large";
    default: return errnum != 0 ? ": system error" : "";
    }
}

/* What a non-regular file is, for the message. */
static const char *file_kind(mode_t mode)
{
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO or pipe";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

static brdffit_status io_error(brdffit_error *err, const char *what, const char *path, int errnum)
{
    return bf_fail(err, BRDFFIT_E_IO, "cannot %s '%s'%s", what, path, errno_text(errnum));
}

/* Opens a regular file: without blocking on a FIFO, and checking the type
 * of what was opened (not of what the path named a moment before). */
static brdffit_status open_regular(bf_file *f, const char *path, brdffit_error *err)
{
    struct stat st;
    int fd, flags, e;
    errno = 0;
    fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) return io_error(err, "open", path, errno);
    if (fstat(fd, &st) != 0) {
        e = errno;
        close(fd);
        return io_error(err, "examine", path, e);
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return bf_fail(err, BRDFFIT_E_IO, "cannot read '%s': %s, not a regular file", path,
                       file_kind(st.st_mode));
    }
    flags = fcntl(fd, F_GETFL);
    if (flags == -1 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == -1 ||
        (f->fp = fdopen(fd, "rb")) == NULL) {
        e = errno;
        close(fd);
        return io_error(err, "open", path, e);
    }
    return BRDFFIT_OK;
}

brdffit_status bf_file_open(bf_file *f, const char *path, brdffit_error *err)
{
    long end;
    int c;
    f->fp = NULL;
    f->size = 0;
    BF_RETURN_IF_ERROR(open_regular(f, path, err));
    /* Probe one byte first: a file that cannot be read fails here. */
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
    if (end == 0 && c != EOF) {
        bf_file_close(f);
        return bf_fail(err, BRDFFIT_E_IO,
                       "cannot read '%s': it reports a size of 0 but is not empty (a /proc or "
                       "/sys file?); copy it to a regular file first", path);
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
