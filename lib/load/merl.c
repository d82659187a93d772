/* The MERL binary loader (docs/definitions.md, MERL files).
 *
 * A MERL file holds 90 x 90 x 180 cells over the half/difference angles
 * (theta_h, theta_d, phi_d) of Rusinkiewicz's parameterisation: theta_h
 * index = sqrt(theta_h / (pi/2)) * 90, theta_d index = theta_d / (pi/2) * 90,
 * phi_d index = phi_d / pi * 180 with phi_d folded into [0, pi). The
 * half/difference frame: h = Rz(phi_h) Ry(theta_h) z, and a direction pair
 * (l, v) has the difference vector d = Ry(-theta_h) Rz(-phi_h) l; v is l
 * mirrored about h, so in that frame v = (-d_x, -d_y, d_z). */
#include <math.h>
#include <string.h>

#include "brdffit/load.h"
#include "core/core.h"
#include "load/load_internal.h"
#include "load/merl_measure.h"

#define MERL_TH 90
#define MERL_TD 90
#define MERL_PD 180
#define MERL_CELLS ((size_t)MERL_TH * MERL_TD * MERL_PD)
#define MERL_HEADER ((size_t)12)
#define MERL_SIZE (MERL_HEADER + 3 * MERL_CELLS * sizeof(double))

static const double merl_scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
static const char *const channel_names[3] = {"red", "green", "blue"};

/* ---- bytes ------------------------------------------------------------- */

static int32_t le32(const unsigned char *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    int32_t v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static double le64(const unsigned char *p)
{
    double v;
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__) && \
    __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy(&v, p, sizeof v); /* the file's byte order already */
#else
    uint64_t u = 0;
    int k;
    for (k = 7; k >= 0; k--) u = u << 8 | p[k];
    memcpy(&v, &u, sizeof v);
#endif
    return v;
}

/* Value of channel c in cell (raw, unscaled). */
static double cell_value(const unsigned char *data, size_t c, size_t cell)
{
    return le64(data + MERL_HEADER + (c * MERL_CELLS + cell) * sizeof(double));
}

/* ---- checks -------------------------------------------------------------- */

static brdffit_status check_header(const unsigned char *data, size_t size, brdffit_error *err)
{
    int32_t d0, d1, d2;
    if (size < MERL_HEADER)
        return bf_fail(err, BRDFFIT_E_FORMAT,
                       "truncated MERL file: %zu bytes, expected %zu (no complete header)", size,
                       (size_t)MERL_SIZE);
    d0 = le32(data), d1 = le32(data + 4), d2 = le32(data + 8);
    if (d0 != MERL_TH || d1 != MERL_TD || d2 != MERL_PD)
        return bf_fail(err, BRDFFIT_E_FORMAT,
                       "MERL dimensions are %ld x %ld x %ld, expected 90 x 90 x 180", (long)d0,
                       (long)d1, (long)d2);
    if (size != MERL_SIZE)
        return bf_fail(err, BRDFFIT_E_FORMAT, "%s MERL file: expected %zu bytes, found %zu",
                       size < MERL_SIZE ? "truncated" : "oversized", (size_t)MERL_SIZE, size);
    return BRDFFIT_OK;
}

static void cell_indices(size_t cell, size_t *ih, size_t *id, size_t *ip)
{
    *ip = cell % MERL_PD;
    *id = cell / MERL_PD % MERL_TD;
    *ih = cell / MERL_PD / MERL_TD;
}

/* Every value finite; counts the cells with at least one measured channel. */
static brdffit_status check_values(const unsigned char *data, size_t *n_measured,
                                   brdffit_error *err)
{
    size_t c, cell, count = 0;
    for (cell = 0; cell < MERL_CELLS; cell++) {
        int measured = 0;
        for (c = 0; c < 3; c++) {
            double v = cell_value(data, c, cell);
            if (!isfinite(v)) {
                size_t ih, id, ip;
                cell_indices(cell, &ih, &id, &ip);
                return bf_fail(err, BRDFFIT_E_RANGE,
                               "MERL %s value of cell (theta_h %zu, theta_d %zu, phi_d %zu) "
                               "is %s",
                               channel_names[c], ih, id, ip, isnan(v) ? "NaN" : "infinite");
            }
            measured |= v >= 0.0;
        }
        count += (size_t)measured;
    }
    if (count == 0) return bf_fail(err, BRDFFIT_E_NO_DATA, "MERL file has no measured cell");
    *n_measured = count;
    return BRDFFIT_OK;
}

/* ---- half/difference angles ------------------------------------------------ */

static double polar_of(double x, double y, double z)
{
    return atan2(sqrt(x * x + y * y), z);
}

/* Sines and cosines of the cell centre angles, per axis. */
typedef struct merl_trig {
    double sh[MERL_TH], ch[MERL_TH], sd[MERL_TD], cd[MERL_TD], sp[MERL_PD], cp[MERL_PD];
} merl_trig;

static void trig_init(merl_trig *t)
{
    size_t k;
    for (k = 0; k < MERL_TH; k++) {
        double u = (k + 0.5) / MERL_TH, th = u * u * BF_HALF_PI;
        t->sh[k] = sin(th), t->ch[k] = cos(th);
    }
    for (k = 0; k < MERL_TD; k++) {
        double td = (k + 0.5) / MERL_TD * BF_HALF_PI;
        t->sd[k] = sin(td), t->cd[k] = cos(td);
    }
    for (k = 0; k < MERL_PD; k++) {
        double pd = (k + 0.5) / MERL_PD * BF_PI;
        t->sp[k] = sin(pd), t->cp[k] = cos(pd);
    }
}

/* Light and view of the centre of cell (ih, id, ip), phi_h = 0. */
static void cell_directions(const merl_trig *t, size_t ih, size_t id, size_t ip, double l[3],
                            double v[3])
{
    double ch = t->ch[ih], sh = t->sh[ih];
    double dx = t->sd[id] * t->cp[ip], dy = t->sd[id] * t->sp[ip], dz = t->cd[id];
    /* l = Ry(theta_h) d, v = Ry(theta_h) (-dx, -dy, dz) */
    l[0] = dx * ch + dz * sh, l[1] = dy, l[2] = dz * ch - dx * sh;
    v[0] = -dx * ch + dz * sh, v[1] = -dy, v[2] = dz * ch + dx * sh;
}

static size_t clamp_index(double x, size_t n)
{
    if (!(x > 0.0)) return 0;
    return x >= (double)(n - 1) ? n - 1 : (size_t)x;
}

/* The MERL cell holding the direction pair (l, v). */
static size_t cell_of(const double l[3], const double v[3])
{
    double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
    double len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    double th, ph, x, y, z, dx, dz, td, pd;
    if (len > 1e-12)
        h[0] /= len, h[1] /= len, h[2] /= len;
    else
        h[0] = 0.0, h[1] = 0.0, h[2] = 1.0; /* opposite directions */
    th = polar_of(h[0], h[1], h[2]);
    ph = atan2(h[1], h[0]);
    /* d = Ry(-th) Rz(-ph) l */
    x = l[0] * cos(ph) + l[1] * sin(ph);
    y = -l[0] * sin(ph) + l[1] * cos(ph);
    z = l[2];
    dx = x * cos(th) - z * sin(th);
    dz = x * sin(th) + z * cos(th);
    td = polar_of(dx, y, dz);
    pd = atan2(y, dx);
    if (pd < 0.0) pd += BF_PI;
    if (pd >= BF_PI) pd -= BF_PI;
    return (clamp_index(sqrt(th / BF_HALF_PI) * MERL_TH, MERL_TH) * MERL_TD +
            clamp_index(td / BF_HALF_PI * MERL_TD, MERL_TD)) *
               MERL_PD +
           clamp_index(pd / BF_PI * MERL_PD, MERL_PD);
}

/* Scaled value of channel c in cell; returns 0 when unmeasured. */
static int measured_value(const unsigned char *data, size_t c, size_t cell, double *out)
{
    double v = cell_value(data, c, cell);
    *out = v >= 0.0 ? v * merl_scale[c] : 0.0;
    return v >= 0.0;
}

/* ---- the scattered form ----------------------------------------------------- */

typedef struct merl_arrays {
    double *angles; /* 4 n: theta_i, phi_i, theta_o, phi_o */
    double *values; /* 3 n, interleaved */
    unsigned char *missing;
    double *weights; /* scattered: n cell measures (sr^2) */
} merl_arrays;

static void arrays_free(merl_arrays *m, const brdffit_allocator *a)
{
    bf_free(a, m->angles);
    bf_free(a, m->values);
    bf_free(a, m->missing);
    bf_free(a, m->weights);
}

static brdffit_status arrays_alloc(merl_arrays *m, size_t n, const brdffit_allocator *a,
                                   brdffit_error *err)
{
    m->angles = bf_calloc(a, n, 4 * sizeof(double));
    m->values = bf_calloc(a, n, 3 * sizeof(double));
    m->missing = bf_calloc(a, n, 3);
    m->weights = bf_calloc(a, n, sizeof(double));
    if (m->angles && m->values && m->missing && m->weights) return BRDFFIT_OK;
    arrays_free(m, a);
    return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while loading MERL data");
}

static int cell_measured(const unsigned char *data, size_t cell)
{
    size_t c;
    for (c = 0; c < 3; c++)
        if (cell_value(data, c, cell) >= 0.0) return 1;
    return 0;
}

/* Store the measured cell as sample s (s < n) if it lies above the horizon. */
static int keep_cell(const unsigned char *data, const merl_trig *t, const bf_merl_measure *mu,
                     size_t cell, merl_arrays *m, size_t n, size_t s)
{
    size_t ih, id, ip, c;
    double l[3], v[3];
    if (!cell_measured(data, cell)) return 0;
    cell_indices(cell, &ih, &id, &ip);
    cell_directions(t, ih, id, ip, l, v);
    if (!(l[2] > 0.0 && v[2] > 0.0)) return 0;
    for (c = 0; c < 3; c++)
        m->missing[s * 3 + c] =
            (unsigned char)!measured_value(data, c, cell, &m->values[s * 3 + c]);
    m->angles[s] = polar_of(l[0], l[1], l[2]);
    m->angles[n + s] = atan2(l[1], l[0]);
    m->angles[2 * n + s] = polar_of(v[0], v[1], v[2]);
    m->angles[3 * n + s] = atan2(v[1], v[0]);
    m->weights[s] = bf_merl_cell_measure(mu, ih, id, ip);
    return 1;
}

static brdffit_status load_scattered(brdffit_grid **out, const unsigned char *data,
                                     size_t n_measured, const brdffit_allocator *a,
                                     brdffit_error *err)
{
    merl_arrays m = {NULL, NULL, NULL, NULL};
    merl_trig t;
    bf_merl_measure mu;
    size_t cell, s = 0, n = n_measured;
    brdffit_status st;
    BF_RETURN_IF_ERROR(arrays_alloc(&m, n, a, err));
    trig_init(&t);
    bf_merl_measure_init(&mu);
    for (cell = 0; cell < MERL_CELLS; cell++) s += (size_t)keep_cell(data, &t, &mu, cell, &m, n, s);
    if (s == 0) {
        arrays_free(&m, a);
        return bf_fail(err, BRDFFIT_E_NO_DATA,
                       "no measured MERL cell has light and view above the horizon");
    }
    /* the angle blocks are laid out for n samples; s <= n are used */
    st = brdffit_grid_create_scattered(out, s, m.angles, m.angles + n, m.angles + 2 * n,
                                       m.angles + 3 * n, 3, m.values, m.missing, m.weights, a, err);
    arrays_free(&m, a);
    return st;
}

/* ---- the regular form ----------------------------------------------------------- */

static int resample(const unsigned char *data, const brdffit_axes *axes, merl_arrays *m)
{
    size_t i, j, k, c, s = 0;
    int any = 0;
    for (i = 0; i < axes->n_theta_i; i++) {
        double ti = axes->theta_i[i];
        double l[3] = {-sin(ti), 0.0, cos(ti)};
        for (j = 0; j < axes->n_theta_o; j++) {
            double to = axes->theta_o[j];
            for (k = 0; k < axes->n_phi_o; k++, s++) {
                double po = axes->phi_o[k];
                double v[3] = {sin(to) * cos(po), sin(to) * sin(po), cos(to)};
                size_t cell = cell_of(l, v);
                for (c = 0; c < 3; c++) {
                    int ok = measured_value(data, c, cell, &m->values[s * 3 + c]);
                    m->missing[s * 3 + c] = (unsigned char)!ok;
                    any |= ok;
                }
            }
        }
    }
    return any;
}

static brdffit_status load_regular(brdffit_grid **out, const unsigned char *data,
                                   const brdffit_axes *axes, const brdffit_allocator *a,
                                   brdffit_error *err)
{
    merl_arrays m = {NULL, NULL, NULL, NULL};
    size_t n = 0;
    brdffit_status st;
    BF_RETURN_IF_ERROR(bf_load_axes_count(axes, 3, &n, err));
    m.values = bf_calloc(a, n, 3 * sizeof(double));
    m.missing = bf_calloc(a, n, 3);
    if (m.values == NULL || m.missing == NULL) {
        arrays_free(&m, a);
        return bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY, "out of memory while loading MERL data");
    }
    if (!resample(data, axes, &m))
        st = bf_fail(err, BRDFFIT_E_NO_DATA, "no grid sample falls into a measured MERL cell");
    else
        st = brdffit_grid_create_regular(out, axes, 3, m.values, m.missing, a, err);
    arrays_free(&m, a);
    return st;
}

/* ---- entry points ------------------------------------------------------------------ */

/* Every argument, the axes included, before any byte of the data is read. */
static brdffit_status check_args(brdffit_grid **out, const void *in, const brdffit_axes *axes,
                                 const brdffit_allocator *alloc, brdffit_allocator *a,
                                 brdffit_error *err)
{
    size_t n;
    BF_RETURN_IF_ERROR(bf_load_begin(out, in, NULL, alloc, a, err));
    return axes != NULL ? bf_load_axes_count(axes, 3, &n, err) : BRDFFIT_OK;
}

static brdffit_status decode(brdffit_grid **out, const unsigned char *data, size_t size,
                             const brdffit_axes *axes, const brdffit_allocator *a,
                             brdffit_error *err)
{
    size_t n_measured = 0;
    BF_RETURN_IF_ERROR(check_header(data, size, err));
    BF_RETURN_IF_ERROR(check_values(data, &n_measured, err));
    if (axes == NULL) return load_scattered(out, data, n_measured, a, err);
    return load_regular(out, data, axes, a, err);
}

brdffit_status brdffit_load_merl_buffer(brdffit_grid **out, const void *data, size_t size,
                                        const brdffit_axes *axes, const brdffit_allocator *alloc,
                                        brdffit_error *err)
{
    brdffit_allocator a;
    BF_RETURN_IF_ERROR(check_args(out, data, axes, alloc, &a, err));
    return decode(out, data, size, axes, &a, err);
}

/* Read a MERL file whole, after its header and size have been checked. */
static brdffit_status read_file(const char *path, const brdffit_allocator *a, unsigned char **data,
                                brdffit_error *err)
{
    unsigned char header[MERL_HEADER] = {0};
    bf_file f;
    brdffit_status st = BRDFFIT_OK;
    *data = NULL;
    BF_RETURN_IF_ERROR(bf_file_open(&f, path, err));
    if (f.size >= MERL_HEADER) st = bf_file_read(&f, 0, header, MERL_HEADER, path, err);
    if (st == BRDFFIT_OK) st = check_header(header, f.size, err);
    if (st == BRDFFIT_OK) {
        *data = bf_malloc(a, MERL_SIZE);
        st = *data == NULL ? bf_fail(err, BRDFFIT_E_OUT_OF_MEMORY,
                                     "out of memory reading '%s' (%zu bytes)", path, MERL_SIZE)
                           : bf_file_read(&f, 0, *data, MERL_SIZE, path, err);
    }
    bf_file_close(&f);
    if (st != BRDFFIT_OK) {
        bf_free(a, *data);
        *data = NULL;
    }
    return st;
}

brdffit_status brdffit_load_merl(brdffit_grid **out, const char *path, const brdffit_axes *axes,
                                 const brdffit_allocator *alloc, brdffit_error *err)
{
    brdffit_allocator a;
    unsigned char *data = NULL;
    brdffit_status st;
    BF_RETURN_IF_ERROR(check_args(out, path, axes, alloc, &a, err));
    BF_RETURN_IF_ERROR(read_file(path, &a, &data, err));
    st = decode(out, data, MERL_SIZE, axes, &a, err);
    bf_free(&a, data);
    return st;
}
