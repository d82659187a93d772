/* A sphere lit by a point light, seen orthographically from +z, shaded
 * with the measured BRDF of a grid or with a model. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "image/image_internal.h"

/* Local light and view directions of the lit pixels of one row. */
typedef struct sphere_row {
    double *theta_i, *phi_i, *theta_o, *phi_o, *cos_i;
    size_t *x;      /* pixel column of each lit point */
    double *values; /* model: n_channels * size, channel-major; grid: n_channels */
    size_t count;
} sphere_row;

/* Where f comes from. */
typedef struct sphere_source {
    const brdffit_grid *grid; /* measured, or NULL */
    const brdffit_model *model;
    const double *params;
    size_t n_channels;
} sphere_source;

typedef struct vec3 {
    double x, y, z;
} vec3;

static double dot(vec3 a, vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static vec3 cross(vec3 a, vec3 b)
{
    vec3 r = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    return r;
}

static vec3 normalize(vec3 a)
{
    double n = sqrt(dot(a, a));
    vec3 r = {a.x / n, a.y / n, a.z / n};
    return r;
}

static double polar(double z)
{
    return acos(z > 1.0 ? 1.0 : (z < 0.0 ? 0.0 : z));
}

/* Express l and v in a tangent frame around n and store the angles as lit
 * point number row->count. */
static void add_point(sphere_row *row, vec3 n, vec3 l, size_t x)
{
    const vec3 v = {0.0, 0.0, 1.0}, ey = {0.0, 1.0, 0.0}, ex = {1.0, 0.0, 0.0};
    vec3 t = normalize(cross(fabs(n.y) < 0.9 ? ey : ex, n));
    vec3 b = cross(n, t);
    size_t k = row->count++;
    row->cos_i[k] = dot(n, l);
    row->theta_i[k] = polar(row->cos_i[k]);
    row->phi_i[k] = atan2(dot(l, b), dot(l, t));
    row->theta_o[k] = polar(n.z);
    row->phi_o[k] = atan2(dot(v, b), dot(v, t));
    row->x[k] = x;
}

static void paint(unsigned char *p, const double *f, size_t step, size_t n, double cos_i,
                  const brdffit_image_options *o)
{
    double rgb[3];
    bf_image_channels_to_rgb(f, n, step, rgb);
    bf_image_encode_rgb(rgb, o->exposure * cos_i, o->gamma, p);
}

static brdffit_status shade_measured(const sphere_source *src, const sphere_row *row,
                                     unsigned char *line, const brdffit_image_options *o,
                                     brdffit_error *err)
{
    size_t k;
    for (k = 0; k < row->count; k++) {
        unsigned char *p = line + 3 * row->x[k];
        brdffit_status st = brdffit_grid_eval(src->grid, row->theta_i[k], row->phi_i[k],
                                              row->theta_o[k], row->phi_o[k], row->values, NULL);
        if (st == BRDFFIT_E_NO_DATA)
            memcpy(p, o->missing, 3);
        else if (st != BRDFFIT_OK)
            return bf_fail(err, st, "interpolating the grid failed: %s", brdffit_status_string(st));
        else
            paint(p, row->values, 1, src->n_channels, row->cos_i[k], o);
    }
    return BRDFFIT_OK;
}

static brdffit_status shade_model(const sphere_source *src, const sphere_row *row,
                                  unsigned char *line, const brdffit_image_options *o,
                                  brdffit_error *err)
{
    size_t k;
    if (row->count == 0) return BRDFFIT_OK;
    BF_RETURN_IF_ERROR(brdffit_model_eval_angles(src->model, row->count, row->theta_i, row->phi_i,
                                                 row->theta_o, row->phi_o, src->n_channels,
                                                 src->params, row->values, NULL, err));
    for (k = 0; k < row->count; k++)
        paint(line + 3 * row->x[k], row->values + k, row->count, src->n_channels, row->cos_i[k], o);
    return BRDFFIT_OK;
}

/* Lay out the row's points; background outside the disc, black where the
 * light is below the local horizon. */
static void collect_row(sphere_row *row, unsigned char *line, size_t y, size_t size, vec3 l,
                        const brdffit_image_options *o)
{
    static const unsigned char black[3] = {0, 0, 0};
    double w = 1.0 - (2.0 * (double)y + 1.0) / (double)size;
    size_t x;
    row->count = 0;
    for (x = 0; x < size; x++) {
        double u = (2.0 * (double)x + 1.0) / (double)size - 1.0, r2 = u * u + w * w;
        vec3 n;
        if (r2 > 1.0) {
            memcpy(line + 3 * x, o->background, 3);
            continue;
        }
        n.x = u;
        n.y = w;
        n.z = sqrt(1.0 - r2);
        if (dot(n, l) <= 0.0)
            memcpy(line + 3 * x, black, 3);
        else
            add_point(row, n, l, x);
    }
}

static brdffit_status alloc_row(sphere_row *row, const brdffit_allocator *a, size_t size,
                                size_t n_values)
{
    size_t n;
    memset(row, 0, sizeof *row);
    if (!bf_mul_size(size, 5, &n) || !bf_add_size(n, n_values, &n)) return BRDFFIT_E_TOO_LARGE;
    row->theta_i = bf_calloc(a, n, sizeof(double));
    row->x = bf_calloc(a, size, sizeof(size_t));
    if (row->theta_i == NULL || row->x == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    row->phi_i = row->theta_i + size;
    row->theta_o = row->phi_i + size;
    row->phi_o = row->theta_o + size;
    row->cos_i = row->phi_o + size;
    row->values = row->cos_i + size;
    return BRDFFIT_OK;
}

static void free_row(sphere_row *row, const brdffit_allocator *a)
{
    bf_free(a, row->theta_i);
    bf_free(a, row->x);
}

static brdffit_status check_light(double theta, double phi, brdffit_error *err)
{
    if (!(theta >= 0.0 && theta <= BF_PI) || !isfinite(phi))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT,
                       "light direction (%g, %g) out of range: polar angle in [0, pi], finite "
                       "azimuth",
                       theta, phi);
    return BRDFFIT_OK;
}

static brdffit_status render(unsigned char *pixels, size_t stride, size_t size,
                             const sphere_source *src, double light_theta, double light_phi,
                             const brdffit_image_options *opts, const brdffit_allocator *alloc,
                             brdffit_error *err)
{
    brdffit_image_options o;
    brdffit_allocator a;
    sphere_row row;
    brdffit_status st = BRDFFIT_OK;
    vec3 l;
    size_t y, n_values;
    BF_RETURN_IF_ERROR(bf_image_options(&o, opts, err));
    BF_RETURN_IF_ERROR(bf_image_check_buffer(pixels, stride, size, size, 1, err));
    BF_RETURN_IF_ERROR(check_light(light_theta, light_phi, err));
    if (!bf_alloc_init(&a, alloc))
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "allocator lacks alloc or free");
    if (!bf_mul_size(src->n_channels, src->grid != NULL ? 1 : size, &n_values))
        return bf_fail(err, BRDFFIT_E_TOO_LARGE, "too many channels");
    st = alloc_row(&row, &a, size, n_values);
    if (st != BRDFFIT_OK) {
        free_row(&row, &a);
        return bf_fail(err, st,
                       st == BRDFFIT_E_OUT_OF_MEMORY ? "out of memory rendering a sphere"
                                                     : "sphere too large");
    }
    l.x = sin(light_theta) * cos(light_phi);
    l.y = sin(light_theta) * sin(light_phi);
    l.z = cos(light_theta);
    for (y = 0; y < size && st == BRDFFIT_OK; y++) {
        unsigned char *line = pixels + y * stride;
        collect_row(&row, line, y, size, l, &o);
        st = src->grid != NULL ? shade_measured(src, &row, line, &o, err)
                               : shade_model(src, &row, line, &o, err);
    }
    free_row(&row, &a);
    return st;
}

brdffit_status brdffit_image_sphere_measured(unsigned char *pixels, size_t stride, size_t size,
                                             const brdffit_grid *grid, double light_theta,
                                             double light_phi, const brdffit_image_options *opts,
                                             const brdffit_allocator *alloc, brdffit_error *err)
{
    sphere_source src;
    brdffit_grid_kind kind;
    if (grid == NULL) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "grid is NULL");
    kind = brdffit_grid_get_kind(grid);
    if (kind == 0) return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "grid handle is invalid or destroyed");
    if (kind != BRDFFIT_GRID_REGULAR)
        return bf_fail(err, BRDFFIT_E_UNSUPPORTED, "a measured sphere needs a regular grid");
    src.grid = grid;
    src.model = NULL;
    src.params = NULL;
    src.n_channels = brdffit_grid_channel_count(grid);
    return render(pixels, stride, size, &src, light_theta, light_phi, opts, alloc, err);
}

brdffit_status brdffit_image_sphere_model(unsigned char *pixels, size_t stride, size_t size,
                                          const brdffit_model *model, const double *params,
                                          size_t n_channels, double light_theta, double light_phi,
                                          const brdffit_image_options *opts,
                                          const brdffit_allocator *alloc, brdffit_error *err)
{
    sphere_source src;
    if (model == NULL || params == NULL)
        return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "model or params is NULL");
    if (n_channels == 0) return bf_fail(err, BRDFFIT_E_INVALID_ARGUMENT, "n_channels is 0");
    if (brdffit_model_name(model) == NULL || brdffit_model_param_count(model) == 0)
        return bf_fail(err, BRDFFIT_E_BAD_HANDLE, "model handle is invalid or destroyed");
    src.grid = NULL;
    src.model = model;
    src.params = params;
    src.n_channels = n_channels;
    return render(pixels, stride, size, &src, light_theta, light_phi, opts, alloc, err);
}
