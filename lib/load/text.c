/* Lines and fields of the text loaders (CSV, ASTM E1392). */
#include <string.h>

#include "load/load_internal.h"

void bf_text_init(bf_text *r, const char *data, size_t size)
{
    r->data = data;
    r->size = size;
    r->pos = 0;
    r->line = 0;
    if (size >= 3 && memcmp(data, "\xEF\xBB\xBF", 3) == 0) r->pos = 3; /* UTF-8 BOM */
}

int bf_text_next_line(bf_text *r, bf_line *out)
{
    const char *start, *nl;
    if (r->pos >= r->size) return 0;
    start = r->data + r->pos;
    nl = memchr(start, '\n', r->size - r->pos);
    out->p = start;
    out->len = nl != NULL ? (size_t)(nl - start) : r->size - r->pos;
    out->number = ++r->line;
    r->pos += out->len + (nl != NULL);
    if (out->len > 0 && start[out->len - 1] == '\r') out->len--;
    return 1;
}

int bf_is_blank(char c)
{
    return c == ' ' || c == '\t';
}

int bf_line_blank(const bf_line *l, char comment)
{
    size_t k = 0;
    while (k < l->len && bf_is_blank(l->p[k])) k++;
    return k == l->len || (comment != '\0' && l->p[k] == comment);
}

int bf_text_next_data_line(bf_text *r, bf_line *out, char comment)
{
    while (bf_text_next_line(r, out))
        if (!bf_line_blank(out, comment)) return 1;
    return 0;
}

void bf_trim(const char **p, size_t *len)
{
    while (*len > 0 && bf_is_blank((*p)[0])) (*p)++, (*len)--;
    while (*len > 0 && bf_is_blank((*p)[*len - 1])) (*len)--;
}

void bf_excerpt(char *buf, size_t size, const char *p, size_t len)
{
    size_t k, n = len < size - 4 ? len : size - 4;
    for (k = 0; k < n; k++) buf[k] = p[k] >= 0x20 && p[k] < 0x7f ? p[k] : '?';
    if (n < len) buf[n++] = '.', buf[n++] = '.', buf[n++] = '.';
    buf[n] = '\0';
}
