/* Messages, time, file names, growable strings with JSON and CSV quoting. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"

void cli_error(const char *file, const char *fmt, ...)
{
    char msg[CLI_MSG_SIZE];
    va_list ap;
    char *p;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    for (p = msg; *p != '\0'; p++) /* one line, whatever the message holds */
        if (*p == '\n' || *p == '\r') *p = ' ';
    if (file != NULL)
        fprintf(stderr, "brdffit: %s: %s\n", file, msg);
    else
        fprintf(stderr, "brdffit: %s\n", msg);
}

int cli_usage_error(const char *command, const char *fmt, ...)
{
    char msg[CLI_MSG_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (command != NULL)
        cli_error(NULL, "%s (see brdffit %s --help)", msg, command);
    else
        cli_error(NULL, "%s (see brdffit --help)", msg);
    return CLI_USAGE;
}

void cli_format(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, size, fmt, ap);
    va_end(ap);
}

void cli_shortest(char *buf, size_t size, double x)
{
    int p, digits = 1;
    double a = fabs(x);
    if (a >= 1.0 && a < 1e15) digits = (int)floor(log10(a)) + 1; /* 120, not 1.2e+02 */
    for (p = 1; p <= 17; p++) {
        snprintf(buf, size, "%.*g", p > digits ? p : digits, x);
        if (strtod(buf, NULL) == x) return;
    }
}

double cli_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void cli_base_name(const char *path, char *out, size_t size)
{
    const char *base = strrchr(path, '/'), *dot;
    size_t len;
    base = base != NULL ? base + 1 : path;
    dot = strrchr(base, '.');
    len = dot != NULL && dot != base ? (size_t)(dot - base) : strlen(base);
    if (len >= size) len = size - 1;
    memcpy(out, base, len);
    out[len] = '\0';
}

/* --- growable strings -------------------------------------------------------------- */

void cli_buf_init(cli_buf *b)
{
    b->data = NULL;
    b->len = b->cap = 0;
    b->failed = 0;
}

void cli_buf_free(cli_buf *b)
{
    free(b->data);
    cli_buf_init(b);
}

static int reserve(cli_buf *b, size_t extra)
{
    size_t need = b->len + extra + 1, cap = b->cap ? b->cap : 256;
    char *p;
    if (b->failed) return 0;
    if (need <= b->cap) return 1;
    while (cap < need) cap *= 2;
    p = realloc(b->data, cap);
    if (p == NULL) {
        b->failed = 1;
        return 0;
    }
    b->data = p;
    b->cap = cap;
    return 1;
}

void cli_buf_printf(cli_buf *b, const char *fmt, ...)
{
    va_list ap;
    int n;
    va_start(ap, fmt);
    n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0 || !reserve(b, (size_t)n)) {
        b->failed = 1;
        return;
    }
    va_start(ap, fmt);
    vsnprintf(b->data + b->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
}

void cli_buf_write(cli_buf *b, const char *data, size_t size)
{
    if (!reserve(b, size)) return;
    memcpy(b->data + b->len, data, size);
    b->len += size;
    b->data[b->len] = '\0';
}

void cli_buf_puts(cli_buf *b, const char *s)
{
    cli_buf_write(b, s, strlen(s));
}

/* Length of the valid UTF-8 sequence at s, 0 if invalid. */
static size_t utf8_length(const unsigned char *s)
{
    size_t n, i;
    unsigned cp;
    if (s[0] < 0x80) return 1;
    if (s[0] >= 0xc2 && s[0] <= 0xdf)
        n = 2, cp = s[0] & 0x1fu;
    else if (s[0] >= 0xe0 && s[0] <= 0xef)
        n = 3, cp = s[0] & 0x0fu;
    else if (s[0] >= 0xf0 && s[0] <= 0xf4)
        n = 4, cp = s[0] & 0x07u;
    else
        return 0;
    for (i = 1; i < n; i++) {
        if ((s[i] & 0xc0) != 0x80) return 0;
        cp = (cp << 6) | (s[i] & 0x3fu);
    }
    if ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10ffff)) ||
        (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    return n;
}

void cli_buf_json_string(cli_buf *b, const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    cli_buf_puts(b, "\"");
    while (*p != '\0') {
        size_t n = utf8_length(p);
        if (*p == '"' || *p == '\\')
            cli_buf_printf(b, "\\%c", *p);
        else if (*p == '\n')
            cli_buf_puts(b, "\\n");
        else if (*p == '\t')
            cli_buf_puts(b, "\\t");
        else if (*p == '\r')
            cli_buf_puts(b, "\\r");
        else if (*p < 0x20 || *p == 0x7f)
            cli_buf_printf(b, "\\u%04x", *p);
        else if (n == 0)
            cli_buf_puts(b, "\\ufffd");
        else
            cli_buf_write(b, (const char *)p, n);
        p += n == 0 ? 1 : n;
    }
    cli_buf_puts(b, "\"");
}

void cli_buf_json_number(cli_buf *b, double x)
{
    if (isfinite(x))
        cli_buf_printf(b, "%.17g", x);
    else
        cli_buf_puts(b, "null");
}

void cli_buf_csv_field(cli_buf *b, const char *s)
{
    const char *p;
    if (strpbrk(s, ",\"\r\n") == NULL) {
        cli_buf_puts(b, s);
        return;
    }
    cli_buf_puts(b, "\"");
    for (p = s; *p != '\0'; p++) {
        if (*p == '"') cli_buf_write(b, "\"", 1); /* a quote is doubled */
        cli_buf_write(b, p, 1);
    }
    cli_buf_puts(b, "\"");
}
