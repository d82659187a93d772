/* Output files: written whole or not at all (atomic replacement of regular
 * files), written through to devices and FIFOs (never replaced), and CSV
 * appends. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

/* Flushes and closes f after the writer ran; returns non-zero on failure. */
static int finish(FILE *f, int failed, char *msg, size_t msg_size)
{
    if (!failed && (fflush(f) != 0 || ferror(f))) {
        cli_format(msg, msg_size, "write failed: %s", strerror(errno));
        failed = 1;
    }
    if (fclose(f) != 0 && !failed) {
        cli_format(msg, msg_size, "write failed: %s", strerror(errno));
        failed = 1;
    }
    return failed;
}

/* A device or a FIFO: opened and written in place, never replaced. A FIFO
 * without a reader is refused instead of waited on. */
static int write_through(const char *path, cli_writer writer, void *ctx, char *msg,
                         size_t msg_size)
{
    int fd = open(path, O_WRONLY | O_NOCTTY | O_NONBLOCK), flags;
    FILE *f;
    if (fd < 0) {
        cli_format(msg, msg_size, "cannot open it for writing: %s%s", strerror(errno),
                   errno == ENXIO ? " (a FIFO nobody reads, or a socket)" : "");
        return -1;
    }
    flags = fcntl(fd, F_GETFL);
    if (flags == -1 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == -1 ||
        (f = fdopen(fd, "wb")) == NULL) {
        cli_format(msg, msg_size, "cannot open it for writing: %s", strerror(errno));
        close(fd);
        return -1;
    }
    return finish(f, writer(f, ctx, msg, msg_size) != 0, msg, msg_size) ? -1 : 0;
}

/* Fills a temporary file next to `path` and renames it over `path`. */
static int replace(const char *path, mode_t mode, cli_writer writer, void *ctx, char *msg,
                   size_t msg_size)
{
    size_t len = strlen(path);
    char *tmp = malloc(len + 16);
    FILE *f;
    int fd, failed;
    if (tmp == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    memcpy(tmp, path, len);
    memcpy(tmp + len, ".tmp-XXXXXX", 12);
    fd = mkstemp(tmp);
    if (fd < 0 || (f = fdopen(fd, "wb")) == NULL) {
        cli_format(msg, msg_size, "cannot create a file next to it: %s", strerror(errno));
        if (fd >= 0) {
            close(fd);
            unlink(tmp);
        }
        free(tmp);
        return -1;
    }
    (void)fchmod(fd, mode); /* mkstemp makes 0600 */
    failed = finish(f, writer(f, ctx, msg, msg_size) != 0, msg, msg_size);
    if (!failed && rename(tmp, path) != 0) {
        cli_format(msg, msg_size, "cannot rename the finished file into place: %s",
                   strerror(errno));
        failed = 1;
    }
    if (failed) unlink(tmp);
    free(tmp);
    return failed ? -1 : 0;
}

int cli_write_atomic(const char *path, cli_writer writer, void *ctx, char *msg, size_t msg_size)
{
    struct stat st, link;
    char *real;
    int rc;
    if (stat(path, &st) != 0) {
        if (errno == ENOENT && lstat(path, &link) == 0) {
            cli_format(msg, msg_size, "a symbolic link to a missing file; not replaced");
            return -1;
        }
        if (errno != ENOENT) {
            cli_format(msg, msg_size, "cannot examine it: %s", strerror(errno));
            return -1;
        }
        return replace(path, 0644, writer, ctx, msg, msg_size); /* a new file */
    }
    if (S_ISDIR(st.st_mode)) {
        cli_format(msg, msg_size, "is a directory");
        return -1;
    }
    if (!S_ISREG(st.st_mode)) return write_through(path, writer, ctx, msg, msg_size);
    if (lstat(path, &link) != 0 || !S_ISLNK(link.st_mode))
        return replace(path, st.st_mode & 07777, writer, ctx, msg, msg_size);
    /* A symbolic link to a regular file: the link stays, its target is replaced. */
    real = realpath(path, NULL);
    if (real == NULL) {
        cli_format(msg, msg_size, "cannot resolve the symbolic link: %s", strerror(errno));
        return -1;
    }
    rc = replace(real, st.st_mode & 07777, writer, ctx, msg, msg_size);
    free(real);
    return rc;
}

/* The first line of an open file (without the line end) equals header?
 * Read in pieces, so a header of any length is compared. */
static int first_line_is(int fd, const char *header)
{
    size_t len = strlen(header), got = 0;
    char buf[4096];
    while (got <= len) {
        size_t want = len + 1 - got, k;
        ssize_t n = pread(fd, buf, want < sizeof buf ? want : sizeof buf, (off_t)got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return got == len; /* the file ends with the header */
        k = (size_t)n;
        if (got + k > len) { /* the piece holds the end of the header and one more byte */
            k = len - got;
            return memcmp(buf, header + got, k) == 0 && (buf[k] == '\n' || buf[k] == '\r');
        }
        if (memcmp(buf, header + got, k) != 0) return 0;
        got += k;
    }
    return 0;
}

static int write_all(int fd, const char *data, size_t size)
{
    while (size > 0) {
        ssize_t n = write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return -1;
        data += n;
        size -= (size_t)n;
    }
    return 0;
}

int cli_append(const char *path, const char *header, const char *data, size_t size, char *msg,
               size_t msg_size)
{
    struct stat st;
    int fd = open(path, O_RDWR | O_APPEND | O_CREAT | O_NOCTTY, 0644), rc = -1, created;
    cli_buf b;
    if (fd < 0) {
        cli_format(msg, msg_size, "cannot open for appending: %s", strerror(errno));
        return -1;
    }
    cli_buf_init(&b);
    if (fstat(fd, &st) != 0) st.st_size = 0, st.st_mode = 0;
    /* only an empty regular file is ours to remove again on failure */
    created = S_ISREG(st.st_mode) && st.st_size == 0;
    if (header != NULL && st.st_size == 0) cli_buf_printf(&b, "%s\n", header);
    cli_buf_write(&b, data, size);
    if (header != NULL && st.st_size != 0 && !first_line_is(fd, header))
        cli_format(msg, msg_size,
                   "its header differs from the columns of this run (another model or "
                   "channel count)");
    else if (b.failed)
        cli_format(msg, msg_size, "out of memory");
    else if (write_all(fd, b.data, b.len) != 0)
        cli_format(msg, msg_size, "write failed: %s", strerror(errno));
    else
        rc = 0;
    if (close(fd) != 0 && rc == 0) {
        cli_format(msg, msg_size, "write failed: %s", strerror(errno));
        rc = -1;
    }
    if (rc != 0 && created) unlink(path); /* leave no empty file behind */
    cli_buf_free(&b);
    return rc;
}
