/* The library's own sphere picture of a model, as a binary PPM, for the
 * renderer comparison of tests/export (export_threejs_render):
 *
 *   sphere_picture MODEL CHANNELS SIZE THETA_DEG PHI_DEG OUT.ppm NAME=V[,V...]...
 *
 * renders brdffit_image_sphere_model() with the default picture options
 * (exposure pi, gamma 2.2, background 48 48 48) for the parameter vector
 * given by name: a per-channel parameter takes CHANNELS values (or one for
 * all), the others one value; parameters not named keep the model's
 * defaults. Exits 0 on success, 1 with a message otherwise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdffit/brdffit.h"

static int fail(const char *what, const char *detail)
{
    fprintf(stderr, "sphere_picture: %s%s%s\n", what, detail[0] ? ": " : "", detail);
    return 1;
}

/* One NAME=V[,V...] argument into the vector. */
static int set_param(const brdffit_model *model, size_t nc, double *params, char *arg)
{
    char *eq = strchr(arg, '='), *p, *end;
    size_t k, c, n = 0;
    double v[64];
    if (eq == NULL) return -1;
    *eq = '\0';
    if (brdffit_model_param_find(model, arg, &k) != BRDFFIT_OK) return -1;
    for (p = eq + 1; n < 64; p = end + 1) {
        v[n++] = strtod(p, &end);
        if (end == p || (*end != ',' && *end != '\0')) return -1;
        if (*end == '\0') break;
    }
    for (c = 0; c < nc; c++) {
        const int per = (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
        if (!per && c > 0) break;
        params[brdffit_model_vector_index(model, k, c, nc)] = v[n == 1 ? 0 : (c < n ? c : n - 1)];
    }
    return 0;
}

static int write_ppm(const char *path, const unsigned char *px, size_t size)
{
    FILE *f = fopen(path, "wb");
    int ok;
    if (f == NULL) return -1;
    fprintf(f, "P6\n%zu %zu\n255\n", size, size);
    ok = fwrite(px, 3, size * size, f) == size * size;
    return (fclose(f) == 0 && ok) ? 0 : -1;
}

int main(int argc, char **argv)
{
    const double deg = 3.14159265358979323846 / 180.0;
    brdffit_model *model = NULL;
    brdffit_error err;
    double *params = NULL;
    unsigned char *px = NULL;
    size_t nc, size, i;
    int rc = 1;
    if (argc < 7) return fail("usage: MODEL CHANNELS SIZE THETA PHI OUT NAME=V...", "");
    nc = (size_t)strtoul(argv[2], NULL, 10);
    size = (size_t)strtoul(argv[3], NULL, 10);
    if (nc < 1 || nc > 64 || size < 1 || size > 4096) return fail("bad channels or size", "");
    if (brdffit_model_create(&model, argv[1], NULL, &err) != BRDFFIT_OK)
        return fail("model", err.message);
    params = malloc(brdffit_model_vector_size(model, nc) * sizeof *params);
    px = malloc(3 * size * size);
    if (params == NULL || px == NULL) {
        fail("out of memory", "");
        goto done;
    }
    if (brdffit_model_default_params(model, nc, params) != BRDFFIT_OK) {
        fail("defaults", "");
        goto done;
    }
    for (i = 7; i < (size_t)argc; i++)
        if (set_param(model, nc, params, argv[i]) != 0) {
            fail("bad parameter", argv[i]);
            goto done;
        }
    if (brdffit_image_sphere_model(px, 3 * size, size, model, params, nc, atof(argv[4]) * deg,
                                   atof(argv[5]) * deg, NULL, NULL, &err) != BRDFFIT_OK) {
        fail("sphere", err.message);
        goto done;
    }
    if (write_ppm(argv[6], px, size) != 0) {
        fail("cannot write", argv[6]);
        goto done;
    }
    rc = 0;
done:
    free(px);
    free(params);
    brdffit_model_destroy(model);
    return rc;
}
