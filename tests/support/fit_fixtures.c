#include "fit_fixtures.h"

#include <math.h>
#include <stdlib.h>

#include "test_support.h"

double fx_uniform(uint64_t *state)
{
    /* xorshift64*: small, deterministic and good enough for test noise */
    uint64_t x = *state;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *state = x;
    return (double)((x * UINT64_C(2685821657736338717)) >> 11) * 0x1.0p-53;
}

double fx_normal(uint64_t *state)
{
    double u1 = fx_uniform(state), u2 = fx_uniform(state);
    if (u1 < 1e-300) u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

brdffit_grid *fx_grid_from_model(const brdffit_model *model, const double *params, size_t nc,
                                 const brdffit_axes *axes, double noise, uint64_t seed)
{
    size_t n, s, c, i, j, k;
    double *ti, *pi, *to, *po, *planar, *values;
    brdffit_grid *grid = NULL;
    brdffit_error err;
    uint64_t state = seed ? seed : 1;
    if (axes == NULL) axes = brdffit_axes_default();
    n = axes->n_theta_i * axes->n_theta_o * axes->n_phi_o;
    ti = malloc(n * sizeof *ti);
    pi = malloc(n * sizeof *pi);
    to = malloc(n * sizeof *to);
    po = malloc(n * sizeof *po);
    planar = malloc(n * nc * sizeof *planar);
    values = malloc(n * nc * sizeof *values);
    assert_non_null(ti);
    assert_non_null(pi);
    assert_non_null(to);
    assert_non_null(po);
    assert_non_null(planar);
    assert_non_null(values);
    for (i = 0, s = 0; i < axes->n_theta_i; i++)
        for (j = 0; j < axes->n_theta_o; j++)
            for (k = 0; k < axes->n_phi_o; k++, s++) {
                ti[s] = axes->theta_i[i];
                pi[s] = 3.14159265358979323846;
                to[s] = axes->theta_o[j];
                po[s] = axes->phi_o[k];
            }
    if (brdffit_model_eval_angles(model, n, ti, pi, to, po, nc, params, planar, NULL, &err) ==
        BRDFFIT_OK) {
        for (s = 0; s < n; s++)
            for (c = 0; c < nc; c++) {
                double v = planar[c * n + s] * (1.0 + noise * fx_normal(&state));
                values[s * nc + c] = v > 0.0 ? v : 0.0;
            }
        if (brdffit_grid_create_regular(&grid, axes, nc, values, NULL, NULL, &err) != BRDFFIT_OK)
            grid = NULL;
    }
    free(ti);
    free(pi);
    free(to);
    free(po);
    free(planar);
    free(values);
    return grid;
}

brdffit_grid *fx_grid_from_named(const char *name, const double *params, size_t nc,
                                 const brdffit_axes *axes, double noise, uint64_t seed)
{
    brdffit_model *model = NULL;
    brdffit_grid *grid;
    if (brdffit_model_create(&model, name, NULL, NULL) != BRDFFIT_OK) return NULL;
    grid = fx_grid_from_model(model, params, nc, axes, noise, seed);
    brdffit_model_destroy(model);
    return grid;
}

void fx_vector(const brdffit_model *model, size_t nc, const double values[][8], double *vec)
{
    size_t k, c, np = brdffit_model_param_count(model);
    for (k = 0; k < np; k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < nc; c++) {
            size_t at = brdffit_model_vector_index(model, k, c, nc);
            vec[at] = (info->flags & BRDFFIT_PARAM_PER_CHANNEL) ? values[k][c] : values[k][0];
        }
    }
}

brdffit_axes fx_small_axes(double *ti, double *to, double *po)
{
    brdffit_axes ax;
    size_t i;
    for (i = 0; i < 9; i++) ti[i] = (9.0 * (double)i) * 3.14159265358979323846 / 180.0;
    for (i = 0; i < 13; i++) to[i] = (6.5 * (double)i) * 3.14159265358979323846 / 180.0;
    for (i = 0; i < 12; i++) po[i] = (double)i * 3.14159265358979323846 / 11.0;
    ax.theta_i = ti;
    ax.n_theta_i = 9;
    ax.theta_o = to;
    ax.n_theta_o = 13;
    ax.phi_o = po;
    ax.n_phi_o = 12;
    return ax;
}
