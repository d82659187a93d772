/* Assembly of values and Jacobians from the basis blocks of a kernel: the
 * per-channel part of every built-in model, plain multiply-adds only; and
 * the accessor functions through which other layers read a kernel
 * (models/basis.h). */
#include <string.h>

#include "models/kernel.h"
#include "models/model_internal.h"

/* out[i] = sum over linear m of p_{m,c} b[m][i]. */
static void assemble_values(const bf_kernel *k, const bf_basis *bs, size_t count, const double *lin,
                            size_t nc, size_t c, double *restrict out)
{
    const double p0 = lin[c];
    const double *restrict b0 = bs->b[0];
    size_t m, i;
    for (i = 0; i < count; i++) out[i] = p0 * b0[i];
    for (m = 1; m < k->n_linear; m++) {
        const double pm = lin[m * nc + c];
        const double *restrict bm = bs->b[m];
        for (i = 0; i < count; i++) out[i] += pm * bm[i];
    }
}

/* out[i] = sum over linear m depending on shape s of p_{m,c} db[s][m][i]
 * (every shape parameter influences at least one basis function). */
static void assemble_shape(const bf_kernel *k, const bf_basis *bs, size_t s, size_t count,
                           const double *lin, size_t nc, size_t c, double *restrict out)
{
    size_t m, i, filled = 0;
    for (m = 0; m < k->n_linear; m++) {
        const double pm = lin[m * nc + c];
        const double *restrict dm = bs->db[s][m];
        if (!(k->dep[s] & (1u << m))) continue;
        if (filled++ == 0)
            for (i = 0; i < count; i++) out[i] = pm * dm[i];
        else
            for (i = 0; i < count; i++) out[i] += pm * dm[i];
    }
}

static void assemble_block(const bf_kernel *k, const bf_basis *bs, size_t first, size_t count,
                           size_t n, const double *params, size_t nc, double *values,
                           double *jacobian)
{
    const double *lin = params + k->n_shape;
    size_t c, s, m;
    for (c = 0; c < nc; c++) {
        assemble_values(k, bs, count, lin, nc, c, values + c * n + first);
        if (jacobian == NULL) continue;
        for (s = 0; s < k->n_shape; s++)
            assemble_shape(k, bs, s, count, lin, nc, c, jacobian + (s * nc + c) * n + first);
        for (m = 0; m < k->n_linear; m++)
            memcpy(jacobian + ((k->n_shape + m) * nc + c) * n + first, bs->b[m],
                   count * sizeof(double));
    }
}

brdffit_status bf_kernel_run(const bf_kernel *k, const brdffit_batch *batch, const double *params,
                             size_t n_channels, double *values, double *jacobian)
{
    bf_basis bs;
    size_t first, count;
    for (first = 0; first < batch->n; first += count) {
        count = batch->n - first;
        if (count > BF_KERNEL_BLOCK) count = BF_KERNEL_BLOCK;
        k->basis(batch, first, count, params, &bs);
        assemble_block(k, &bs, first, count, batch->n, params, n_channels, values, jacobian);
    }
    return BRDFFIT_OK;
}

/* ---- the basis form as other layers see it (models/basis.h) ---------------- */

const bf_kernel *bf_model_basis(const brdffit_model *m)
{
    const bf_kernel *k = m->kernel;
    return k != NULL && m->n_params == k->n_shape + k->n_linear ? k : NULL;
}

int bf_model_affine(const brdffit_model *m, size_t *colour)
{
    if (m->affine == 0 || m->affine > m->n_params) return 0;
    *colour = m->affine - 1;
    return 1;
}

void bf_kernel_form(const bf_kernel *k, bf_basis_form *out)
{
    size_t s;
    out->n_shape = k->n_shape;
    out->n_linear = k->n_linear;
    for (s = 0; s < BF_KERNEL_MAX_SHAPE; s++) out->dep[s] = k->dep[s];
}

int bf_kernel_lobe(const bf_kernel *k, double theta, bf_lobe *out)
{
    if (k->lobe == NULL) return 0;
    if (k->n_shape > 0) k->lobe(theta, out);
    return 1;
}

bf_microfacet bf_kernel_microfacet(const bf_kernel *k)
{
    return k->mf;
}

void bf_kernel_basis(const bf_kernel *k, const brdffit_batch *batch, size_t first, size_t count,
                     const double *shape, bf_basis *out)
{
    k->basis(batch, first, count, shape, out);
}
