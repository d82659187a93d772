/* See rgl_writer.h. The tensor file layout (Mitsuba's TensorFile, the RGL
 * database's container): "tensor_file\0", version 1.0, uint32 field
 * count, field headers (uint16 name length, name, uint16 rank, uint8 type,
 * uint64 offset, uint64 shape...), then the data, little-endian. */
#include "rgl_writer.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define VX 9 /* vndf resolution */
#define VY 7
#define NDF_X 5
#define NDF_Y 4
#define WARP_B (-0.4)
#define CLAMP_LO (1.0 - 0.999999940395355225)

static double warp_a(size_t b)
{
    return 0.5 + 0.25 * (double)b;
}

/* inverse of F(t) = (t + k t^2 / 2) / (1 + k / 2) */
static double inv_cdf(double k, double s)
{
    return (-1.0 + sqrt(1.0 + 2.0 * k * s * (1.0 + k / 2.0))) / k;
}

static double cdf(double k, double t)
{
    return (t + k * t * t / 2.0) / (1.0 + k / 2.0);
}

double fx_rgl_warp(const fx_rgl_spec *spec, size_t b, const double s[2], double u[2])
{
    double a = warp_a(b), sx = s[0], sy = s[1];
    (void)spec;
    sx = sx < CLAMP_LO ? CLAMP_LO : sx > 1.0 - CLAMP_LO ? 1.0 - CLAMP_LO : sx;
    sy = sy < CLAMP_LO ? CLAMP_LO : sy > 1.0 - CLAMP_LO ? 1.0 - CLAMP_LO : sy;
    u[0] = inv_cdf(a, sx);
    u[1] = inv_cdf(WARP_B, sy);
    return (1.0 + a * u[0]) * (1.0 + WARP_B * u[1]) / ((1.0 + a / 2.0) * (1.0 + WARP_B / 2.0));
}

void fx_rgl_warp_inverse(const fx_rgl_spec *spec, size_t b, const double u[2], double s[2])
{
    (void)spec;
    s[0] = cdf(warp_a(b), u[0]);
    s[1] = cdf(WARP_B, u[1]);
}

double fx_rgl_ndf(const double u[2])
{
    return 0.8 + 0.6 * u[0];
}

double fx_rgl_sigma(const double u[2])
{
    return 1.2 - 0.3 * u[0];
}

void fx_rgl_normal(const double u[2], double phi_i, double m[3])
{
    double tm = u[0] * u[0] * PI / 2.0, pm = (2.0 * u[1] - 1.0) * PI + phi_i;
    m[0] = sin(tm) * cos(pm), m[1] = sin(tm) * sin(pm), m[2] = cos(tm);
}

/* ---- the stored values ------------------------------------------------------------ */

/* f_r cos theta_o / (D / (4 sigma)) at sample node (k, l) of light (a, b). */
static double stored(const fx_rgl_spec *sp, size_t a, size_t b, size_t c, size_t k, size_t l)
{
    double s[2], u[2], wi[3], m[3], wo[3], ui[2], d, scale = 1.0;
    size_t j;
    s[0] = (double)k / (double)(sp->nx - 1), s[1] = (double)l / (double)(sp->ny - 1);
    fx_rgl_warp(sp, b, s, u);
    wi[0] = sin(sp->theta_i[b]) * cos(sp->phi_i[a]);
    wi[1] = sin(sp->theta_i[b]) * sin(sp->phi_i[a]);
    wi[2] = cos(sp->theta_i[b]);
    fx_rgl_normal(u, sp->phi_i[a], m);
    d = wi[0] * m[0] + wi[1] * m[1] + wi[2] * m[2];
    for (j = 0; j < 3; j++) wo[j] = 2.0 * d * m[j] - wi[j];
    if (wo[2] <= 0.0) return 0.0;
    ui[0] = sqrt(sp->theta_i[b] / (PI / 2.0)), ui[1] = (sp->phi_i[a] + PI) / (2.0 * PI);
    if (sp->jacobian) scale = fx_rgl_ndf(u) / (4.0 * fx_rgl_sigma(ui));
    return sp->brdf(wi, wo, c) * wo[2] / scale;
}

/* ---- the container ---------------------------------------------------------------- */

typedef struct field {
    const char *name;
    int dtype; /* 1 uint8, 10 float32 */
    size_t ndim, shape[5], count;
    float *f;
    unsigned char *u8;
} field;

static void put(unsigned char **p, unsigned long long v, int n)
{
    int k;
    for (k = 0; k < n; k++) *(*p)++ = (unsigned char)(v >> (8 * k));
}

static size_t header_size(const field *f, size_t n)
{
    size_t k, s = 18;
    for (k = 0; k < n; k++) s += 2 + strlen(f[k].name) + 2 + 1 + 8 + 8 * f[k].ndim;
    return s;
}

static unsigned char *write_fields(const field *f, size_t n, size_t *size)
{
    size_t k, j, off = header_size(f, n), total = off;
    unsigned char *buf, *p;
    for (k = 0; k < n; k++) total += f[k].count * (f[k].dtype == 1 ? 1 : 4);
    buf = malloc(total);
    if (buf == NULL) return NULL;
    p = buf;
    memcpy(p, "tensor_file", 12), p += 12;
    *p++ = 1, *p++ = 0;
    put(&p, n, 4);
    for (k = 0; k < n; k++) {
        put(&p, strlen(f[k].name), 2);
        memcpy(p, f[k].name, strlen(f[k].name)), p += strlen(f[k].name);
        put(&p, f[k].ndim, 2);
        put(&p, (unsigned long long)f[k].dtype, 1);
        put(&p, off, 8);
        for (j = 0; j < f[k].ndim; j++) put(&p, f[k].shape[j], 8);
        off += f[k].count * (f[k].dtype == 1 ? 1 : 4);
    }
    for (k = 0; k < n; k++)
        for (j = 0; j < f[k].count; j++) {
            uint32_t u;
            if (f[k].dtype == 1) {
                *p++ = f[k].u8[j];
                continue;
            }
            memcpy(&u, &f[k].f[j], 4);
            put(&p, u, 4);
        }
    *size = total;
    return buf;
}

static void set_field(field *f, const char *name, size_t ndim, const size_t *shape)
{
    size_t k;
    memset(f, 0, sizeof *f);
    f->name = name, f->dtype = 10, f->ndim = ndim, f->count = 1;
    for (k = 0; k < ndim; k++) f->shape[k] = shape[k], f->count *= shape[k];
    f->f = calloc(f->count, sizeof(float));
}

static void fill_light(const fx_rgl_spec *sp, field *f)
{
    size_t ti[1] = {sp->n_theta}, pi[1] = {sp->n_phi}, k;
    set_field(&f[0], "theta_i", 1, ti);
    set_field(&f[1], "phi_i", 1, pi);
    for (k = 0; k < sp->n_theta; k++) f[0].f[k] = (float)sp->theta_i[k];
    for (k = 0; k < sp->n_phi; k++) f[1].f[k] = (float)sp->phi_i[k];
}

static void fill_2d(field *ndf, field *sigma)
{
    size_t sh[2] = {NDF_Y, NDF_X}, x, y;
    set_field(ndf, "ndf", 2, sh);
    set_field(sigma, "sigma", 2, sh);
    for (y = 0; y < NDF_Y; y++)
        for (x = 0; x < NDF_X; x++) {
            double u[2];
            u[0] = (double)x / (NDF_X - 1), u[1] = (double)y / (NDF_Y - 1);
            ndf->f[y * NDF_X + x] = (float)fx_rgl_ndf(u);
            sigma->f[y * NDF_X + x] = (float)fx_rgl_sigma(u);
        }
}

static void fill_vndf(const fx_rgl_spec *sp, field *f)
{
    size_t sh[4] = {sp->n_phi, sp->n_theta, VY, VX}, a, b, x, y, i = 0;
    set_field(f, "vndf", 4, sh);
    for (a = 0; a < sp->n_phi; a++)
        for (b = 0; b < sp->n_theta; b++)
            for (y = 0; y < VY; y++)
                for (x = 0; x < VX; x++)
                    f->f[i++] = (float)((1.0 + warp_a(b) * x / (VX - 1.0)) *
                                        (1.0 + WARP_B * y / (VY - 1.0)));
}

static void fill_values(const fx_rgl_spec *sp, field *f, field *wl)
{
    size_t sh[5] = {sp->n_phi, sp->n_theta, sp->nc, sp->ny, sp->nx}, nw[1] = {sp->nc};
    size_t a, b, c, k, l, i = 0;
    set_field(f, sp->rgb ? "rgb" : "spectra", 5, sh);
    set_field(wl, "wavelengths", 1, nw);
    for (c = 0; c < sp->nc; c++) wl->f[c] = (float)(400.0 + 100.0 * (double)c);
    for (a = 0; a < sp->n_phi; a++)
        for (b = 0; b < sp->n_theta; b++)
            for (c = 0; c < sp->nc; c++)
                for (l = 0; l < sp->ny; l++)
                    for (k = 0; k < sp->nx; k++) f->f[i++] = (float)stored(sp, a, b, c, k, l);
}

unsigned char *fx_rgl_file(const fx_rgl_spec *sp, size_t *size)
{
    field f[9];
    size_t n = sp->rgb ? 8 : 9, k, one[1] = {1};
    size_t lum[4] = {sp->n_phi, sp->n_theta, sp->ny, sp->nx};
    unsigned char flag = (unsigned char)(sp->jacobian != 0), *out;
    fill_light(sp, f);
    fill_2d(&f[2], &f[3]);
    fill_vndf(sp, &f[4]);
    fill_values(sp, &f[5], &f[8]);
    set_field(&f[6], "luminance", 4, lum);
    for (k = 0; k < f[6].count; k++) f[6].f[k] = 1.0f;
    set_field(&f[7], "jacobian", 1, one);
    f[7].dtype = 1, f[7].u8 = &flag;
    out = write_fields(f, n, size);
    for (k = 0; k < 9; k++) free(f[k].f);
    return out;
}
