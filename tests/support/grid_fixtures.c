#define _POSIX_C_SOURCE 200809L
#include "grid_fixtures.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "test_support.h"

#define FX_PI 3.14159265358979323846

double fx_value(double theta_i, double theta_o, double phi_o, size_t channel)
{
    return 0.1 + 0.05 * (double)channel + 0.3 * cos(theta_i) * cos(theta_o) +
           0.2 * (1.0 + sin(theta_i + 2.0 * theta_o)) * (1.0 + cos(phi_o)) + 0.01 * phi_o;
}

double *fx_values(const brdffit_axes *axes, size_t n_channels)
{
    size_t n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o, i, j, k, c, s = 0;
    double *v = malloc(n * n_channels * sizeof(double));
    if (v == NULL) return NULL;
    for (i = 0; i < axes->n_theta_i; i++)
        for (j = 0; j < axes->n_theta_o; j++)
            for (k = 0; k < axes->n_phi_o; k++, s++)
                for (c = 0; c < n_channels; c++)
                    v[s * n_channels + c] =
                        fx_value(axes->theta_i[i], axes->theta_o[j], axes->phi_o[k], c);
    return v;
}

void fx_axes_set(fx_axes *a, const double *ti, size_t n_ti, const double *to, size_t n_to,
                 const double *po, size_t n_po)
{
    const double *src[3] = {ti, to, po};
    size_t n[3] = {n_ti, n_to, n_po}, k, m;
    for (k = 0; k < 3; k++)
        for (m = 0; m < n[k]; m++) {
            a->deg[k][m] = src[k][m];
            a->rad[k][m] = DEG(src[k][m]);
        }
    a->axes.theta_i = a->rad[0];
    a->axes.n_theta_i = n_ti;
    a->axes.theta_o = a->rad[1];
    a->axes.n_theta_o = n_to;
    a->axes.phi_o = a->rad[2];
    a->axes.n_phi_o = n_po;
}

static int append(char **buf, size_t *len, size_t *cap, const char *text)
{
    size_t n = strlen(text);
    if (*len + n + 1 > *cap) {
        size_t c = (*cap + n + 1) * 2;
        char *b = realloc(*buf, c);
        if (b == NULL) return 0;
        *buf = b;
        *cap = c;
    }
    memcpy(*buf + *len, text, n + 1);
    *len += n;
    return 1;
}

char *fx_csv_regular(const fx_axes *a, size_t n_channels, const double *values,
                     const unsigned char *mask, const char *missing_text, int shuffle)
{
    size_t n_ti = a->axes.n_theta_i, n_to = a->axes.n_theta_o, n_po = a->axes.n_phi_o;
    size_t n = n_ti * n_to * n_po, r, c, len = 0, cap = 0;
    size_t *order = malloc(n * sizeof(size_t));
    char *buf = NULL, field[128];
    uint32_t seed = 12345u;
    if (order == NULL) return NULL;
    for (r = 0; r < n; r++) order[r] = r;
    for (r = n; shuffle && r > 1; r--) { /* Fisher-Yates with a fixed LCG */
        size_t k, t;
        seed = seed * 1664525u + 1013904223u;
        k = (size_t)(seed >> 8) % r;
        t = order[r - 1], order[r - 1] = order[k], order[k] = t;
    }
    append(&buf, &len, &cap, "# written by the tests\ntheta_i,theta_o,phi_o");
    for (c = 0; c < n_channels; c++) {
        snprintf(field, sizeof field, ",ch%zu", c);
        append(&buf, &len, &cap, field);
    }
    append(&buf, &len, &cap, "\n");
    for (r = 0; r < n; r++) {
        size_t s = order[r], i = s / (n_to * n_po), j = s / n_po % n_to, k = s % n_po;
        snprintf(field, sizeof field, "%.17g,%.17g,%.17g", a->deg[0][i], a->deg[1][j],
                 a->deg[2][k]);
        append(&buf, &len, &cap, field);
        for (c = 0; c < n_channels; c++) {
            size_t v = s * n_channels + c;
            if (mask != NULL && mask[v])
                snprintf(field, sizeof field, ",%s", missing_text);
            else
                snprintf(field, sizeof field, ",%.17g", values[v]);
            append(&buf, &len, &cap, field);
        }
        append(&buf, &len, &cap, "\n");
    }
    free(order);
    return buf;
}

int fx_tempdir_make(fx_tempdir *t)
{
    const char *base = getenv("TMPDIR");
    if (base == NULL || base[0] == '\0') base = "/tmp";
    snprintf(t->path, sizeof t->path, "%s/brdffit-test-XXXXXX", base);
    return mkdtemp(t->path) != NULL;
}

void fx_tempdir_path(const fx_tempdir *t, const char *name, char *out, size_t size)
{
    snprintf(out, size, "%s/%s", t->path, name);
}

int fx_write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    int ok;
    if (f == NULL) return 0;
    ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok;
}

void fx_tempdir_remove(fx_tempdir *t, const char *const *names, size_t n_names)
{
    char path[512];
    size_t k;
    for (k = 0; k < n_names; k++) {
        fx_tempdir_path(t, names[k], path, sizeof path);
        remove(path);
    }
    rmdir(t->path);
}

void fx_put_le32(unsigned char *p, int v)
{
    uint32_t u = (uint32_t)v;
    p[0] = (unsigned char)u, p[1] = (unsigned char)(u >> 8);
    p[2] = (unsigned char)(u >> 16), p[3] = (unsigned char)(u >> 24);
}

void fx_put_le64(unsigned char *p, double v)
{
    uint64_t u;
    int k;
    memcpy(&u, &v, sizeof u);
    for (k = 0; k < 8; k++) p[k] = (unsigned char)(u >> (8 * k));
}

double fx_merl_theta_h(size_t ih)
{
    double u = (ih + 0.5) / 90.0;
    return u * u * (FX_PI / 2);
}

double fx_merl_theta_d(size_t id)
{
    return (id + 0.5) / 90.0 * (FX_PI / 2);
}

double fx_merl_phi_d(size_t ip)
{
    return (ip + 0.5) / 180.0 * FX_PI;
}

unsigned char *fx_merl_image(fx_merl_fn fn, int d0, int d1, int d2)
{
    unsigned char *img = malloc(FX_MERL_SIZE);
    size_t ih, id, ip, c;
    if (img == NULL) return NULL;
    fx_put_le32(img, d0);
    fx_put_le32(img + 4, d1);
    fx_put_le32(img + 8, d2);
    for (c = 0; c < 3; c++)
        for (ih = 0; ih < 90; ih++)
            for (id = 0; id < 90; id++)
                for (ip = 0; ip < 180; ip++) {
                    size_t cell = (ih * 90 + id) * 180 + ip;
                    double v =
                        fn(fx_merl_theta_h(ih), fx_merl_theta_d(id), fx_merl_phi_d(ip), (int)c);
                    fx_put_le64(img + 12 + (c * FX_MERL_CELLS + cell) * 8, v);
                }
    return img;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void fx_half_diff(const double l[3], const double v[3], double *theta_h, double *theta_d,
                  double *phi_d)
{
    double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]}, len = sqrt(dot3(h, h));
    double th, ph, xa[3], ya[3], pd;
    h[0] /= len, h[1] /= len, h[2] /= len;
    th = acos(h[2] > 1.0 ? 1.0 : h[2]);
    ph = atan2(h[1], h[0]);
    /* axes of the half-vector frame */
    xa[0] = cos(ph) * cos(th), xa[1] = sin(ph) * cos(th), xa[2] = -sin(th);
    ya[0] = -sin(ph), ya[1] = cos(ph), ya[2] = 0.0;
    *theta_h = th;
    *theta_d = acos(fmin(1.0, fmax(-1.0, dot3(l, h))));
    pd = atan2(dot3(l, ya), dot3(l, xa));
    if (pd < 0.0) pd += FX_PI;
    if (pd >= FX_PI) pd -= FX_PI;
    *phi_d = pd;
}

void fx_merl_coords(double theta_h, double theta_d, double phi_d, double pos[3])
{
    pos[0] = sqrt(theta_h / (FX_PI / 2)) * 90.0;
    pos[1] = theta_d / (FX_PI / 2) * 90.0;
    pos[2] = phi_d / FX_PI * 180.0;
}

void fx_dir(double theta, double phi, double out[3])
{
    out[0] = sin(theta) * cos(phi);
    out[1] = sin(theta) * sin(phi);
    out[2] = cos(theta);
}
