/* The "tensor_file" container of the RGL material database (Dupuy and
 * Jakob 2018; the format of Mitsuba's TensorFile): the 12 bytes
 * "tensor_file\0", version bytes 1 and 0, a little-endian uint32 field
 * count, then per field a uint16 name length, the name, a uint16 rank, a
 * uint8 type code, a uint64 data offset and one uint64 per dimension. The
 * data of each field lie at its offset, little-endian, row-major. Every
 * field is checked to lie inside the file (docs/formats.md). */
#include <string.h>

#include "core/core.h"
#include "load/tensor_internal.h"

#define TENSOR_MAGIC "tensor_file"
#define TENSOR_HEADER ((size_t)18)
#define TENSOR_MIN_FIELD ((size_t)13) /* a field header with an empty name and rank 0 */

static const size_t type_sizes[12] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 2, 4, 8};

static uint64_t le_bytes(const unsigned char *p, int n)
{
    uint64_t v = 0;
    int k;
    for (k = n - 1; k >= 0; k--) v = v << 8 | p[k];
    return v;
}

typedef struct cursor {
    const unsigned char *data;
    size_t size, pos;
} cursor;

/* n bytes from the header, or 0 when the file ends first. */
static int take(cursor *c, size_t n, const unsigned char **p)
{
    if (c->size - c->pos < n) return 0;
    *p = c->data + c->pos;
    c->pos += n;
    return 1;
}

static brdffit_status truncated(size_t field, brdffit_error *err)
{
    return bf_fail(err, BRDFFIT_E_FORMAT, "truncated tensor file: the header of field %zu ends "
                                          "past the end of the file", field);
}

static brdffit_status read_shape(cursor *c, bf_tensor_field *f, size_t index, brdffit_error *err)
{
    size_t k, bytes = type_sizes[f->dtype], count = 1;
    const unsigned char *p;
    for (k = 0; k < f->ndim; k++) {
        uint64_t n;
        if (!take(c, 8, &p)) return truncated(index, err);
        n = le_bytes(p, 8);
        if (n > (uint64_t)((size_t)-1) || !bf_mul_size(count, (size_t)n, &count))
            return bf_fail(err, BRDFFIT_E_FORMAT, "tensor field '%.*s' is too large",
                           (int)f->name_len, f->name);
        f->shape[k] = (size_t)n;
    }
    f->count = count;
    if (!bf_mul_size(count, bytes, &bytes) || f->offset > c->size || bytes > c->size - f->offset)
        return bf_fail(err, BRDFFIT_E_FORMAT,
                       "tensor field '%.*s' lies outside the file (%zu bytes)", (int)f->name_len,
                       f->name, c->size);
    f->data = c->data + f->offset;
    return BRDFFIT_OK;
}

static brdffit_status read_field(cursor *c, bf_tensor_field *f, size_t index, brdffit_error *err)
{
    const unsigned char *p;
    uint64_t offset;
    memset(f, 0, sizeof *f);
    if (!take(c, 2, &p)) return truncated(index, err);
    f->name_len = (size_t)le_bytes(p, 2);
    if (!take(c, f->name_len, &p)) return truncated(index, err);
    f->name = (const char *)p;
    if (!take(c, 11, &p)) return truncated(index, err);
    f->ndim = (size_t)le_bytes(p, 2);
    f->dtype = p[2];
    offset = le_bytes(p + 3, 8);
    if (f->dtype < 1 || f->dtype > BF_DTYPE_FLOAT64)
        return bf_fail(err, BRDFFIT_E_FORMAT, "tensor field '%.*s' has unknown type code %d",
                       (int)f->name_len, f->name, f->dtype);
    if (f->ndim > BF_TENSOR_MAX_DIM)
        return bf_fail(err, BRDFFIT_E_FORMAT,
                       "tensor field '%.*s' has %zu dimensions, more than the %d allowed",
                       (int)f->name_len, f->name, f->ndim, BF_TENSOR_MAX_DIM);
    if (offset > (uint64_t)c->size)
        return bf_fail(err, BRDFFIT_E_FORMAT,
                       "tensor field '%.*s' lies outside the file (%zu bytes)", (int)f->name_len,
                       f->name, c->size);
    f->offset = (size_t)offset;
    return read_shape(c, f, index, err);
}

static brdffit_status check_header(const unsigned char *data, size_t size, size_t *n_fields,
                                   brdffit_error *err)
{
    uint64_t n;
    if (size < TENSOR_HEADER || memcmp(data, TENSOR_MAGIC, 12) != 0)
        return bf_fail(err, BRDFFIT_E_FORMAT, "not a tensor file: it does not start with "
                                              "\"tensor_file\"");
    if (data[12] != 1 || data[13] != 0)
        return bf_fail(err, BRDFFIT_E_FORMAT, "tensor file version %d.%d, expected 1.0",
                       data[12], data[13]);
    n = le_bytes(data + 14, 4);
    if (n > (size - TENSOR_HEADER) / TENSOR_MIN_FIELD)
        return bf_fail(err, BRDFFIT_E_FORMAT,
                       "truncated tensor file: %lu fields cannot fit in %zu bytes",
                       (unsigned long)n, size);
    *n_fields = (size_t)n;
    return BRDFFIT_OK;
}

static int same_name(const bf_tensor_field *f, const char *name, size_t len)
{
    return f->name_len == len && memcmp(f->name, name, len) == 0;
}

brdffit_status bf_tensor_parse(bf_tensor *t, const unsigned char *data, size_t size,
                               const brdffit_allocator *a, brdffit_error *err)
{
    cursor c = {data, size, TENSOR_HEADER};
    size_t k, n = 0;
    memset(t, 0, sizeof *t);
    BF_RETURN_IF_ERROR(check_header(data, size, &n, err));
    t->fields = bf_calloc(a, n > 0 ? n : 1, sizeof(bf_tensor_field));
    if (t->fields == NULL)
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory reading a tensor file");
    for (k = 0; k < n; k++) {
        brdffit_status st = read_field(&c, &t->fields[k], k, err);
        if (st != BRDFFIT_OK) {
            bf_tensor_free(t, a);
            return st;
        }
    }
    t->n = n;
    return BRDFFIT_OK;
}

void bf_tensor_free(bf_tensor *t, const brdffit_allocator *a)
{
    bf_free(a, t->fields);
    t->fields = NULL;
    t->n = 0;
}

const bf_tensor_field *bf_tensor_find(const bf_tensor *t, const char *name, int *twice)
{
    const bf_tensor_field *found = NULL;
    size_t k;
    *twice = 0;
    for (k = 0; k < t->n; k++) {
        if (!same_name(&t->fields[k], name, strlen(name))) continue;
        if (found != NULL) *twice = 1;
        if (found == NULL) found = &t->fields[k];
    }
    return found;
}

double bf_tensor_f32(const bf_tensor_field *f, size_t i)
{
    uint32_t u = (uint32_t)le_bytes(f->data + 4 * i, 4);
    float v;
    memcpy(&v, &u, sizeof v);
    return (double)v;
}

int bf_tensor_is_tensor_file(const void *data, size_t size)
{
    return size >= 12 && memcmp(data, TENSOR_MAGIC, 12) == 0;
}
