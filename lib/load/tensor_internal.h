/* The "tensor_file" container (tensor.c): named fields with a type, a
 * shape and their data, as the RGL material database stores its BRDFs.
 * Not installed. */
#ifndef BRDFFIT_TENSOR_INTERNAL_H
#define BRDFFIT_TENSOR_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "brdffit/alloc.h"
#include "brdffit/status.h"

#define BF_TENSOR_MAX_DIM 8

/* Type codes of the format. */
enum { BF_DTYPE_UINT8 = 1, BF_DTYPE_FLOAT32 = 10, BF_DTYPE_FLOAT64 = 11 };

typedef struct bf_tensor_field {
    const char *name; /* not NUL-terminated; points into the file */
    size_t name_len;
    int dtype;
    size_t ndim, shape[BF_TENSOR_MAX_DIM];
    size_t count;              /* product of the shape */
    size_t offset;
    const unsigned char *data; /* count elements, inside the file */
} bf_tensor_field;

typedef struct bf_tensor {
    bf_tensor_field *fields;
    size_t n;
} bf_tensor;

/* Parse the header of data[0..size) (borrowed while *t is used):
 * BRDFFIT_E_FORMAT naming what is wrong, BRDFFIT_E_OUT_OF_MEMORY. */
brdffit_status bf_tensor_parse(bf_tensor *t, const unsigned char *data, size_t size,
                               const brdffit_allocator *a, brdffit_error *err);
void bf_tensor_free(bf_tensor *t, const brdffit_allocator *a);
/* The field of that name, or NULL; *twice tells whether the name is given
 * more than once (names are only checked where they are looked up, so the
 * cost stays linear in the number of fields). */
const bf_tensor_field *bf_tensor_find(const bf_tensor *t, const char *name, int *twice);
/* Element i of a float32 field. */
double bf_tensor_f32(const bf_tensor_field *f, size_t i);
/* Whether the bytes start like a tensor file. */
int bf_tensor_is_tensor_file(const void *data, size_t size);

#endif /* BRDFFIT_TENSOR_INTERNAL_H */
