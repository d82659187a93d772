/* The colour route of a pass (pass_route.h): auto's profile at one shape
 * point changes the colours alone, so what depends on the shape alone is
 * computed once per point and every colour pass reads it.
 *
 * At a fixed shape a built-in model is, per channel c,
 *
 *     value_c(s) = sum_q c_{q,c} B_q(s) + B_o(s)
 *
 * with B_q and B_o free of every colour: the basis functions of a model in
 * basis form (models/basis.h; no B_o), or A = dvalue/dc and the value at
 * colour 0 of a model affine in its colour (layout.h, the glTF and OpenPBR
 * models: B_o the offset). SHAPE stores them per sample in pb->shape
 * (bf_pass_shape_size(): [q * n_samples + s], B_o last) from one
 * evaluation of the kernel, or of the affine model on one channel; the
 * colour passes then take each row's value from them with K
 * multiply-adds, transform it with the objective (bf_objective_rows()),
 * and sum the colour block of J^T J (J_q = f B_q, f the row factor) and
 * of J^T r per channel, never evaluating the model nor a shape
 * derivative. */
#include <string.h>

#include "core/core.h"
#include "core/linalg.h"
#include "fit/pass_route.h"
#include "models/basis.h"
#include "models/models.h"

/* The number of colour-free columns of the cache: K, and B_o of an affine
 * model. */
static size_t columns(const bf_problem *pb)
{
    return pb->ly.n_linear + (pb->ly.offset ? 1u : 0u);
}

/* Whether the linear parameters are the basis form's, in its order: then
 * B_q of the kernel is the column of linear[q]. */
static int basis_colours(const bf_problem *pb)
{
    bf_basis_form f;
    size_t q;
    if (pb->kernel == NULL) return 0;
    bf_kernel_form(pb->kernel, &f);
    if (f.n_linear != pb->ly.n_linear) return 0;
    for (q = 0; q < f.n_linear; q++)
        if (pb->ly.linear[q] != f.n_shape + q) return 0;
    return 1;
}

size_t bf_pass_shape_size(const bf_problem *pb)
{
    if (!pb->ly.offset && !basis_colours(pb)) return 0;
    return columns(pb) * pb->grid->n_samples;
}

static int colour_serves(const bf_problem *pb)
{
    return bf_pass_shape_size(pb) > 0;
}

static size_t colour_acc_size(const bf_problem *pb, bf_pass_kind kind)
{
    size_t K = pb->ly.n_linear;
    switch (kind) {
    case BF_PASS_COLOUR_COST: return 1;
    case BF_PASS_COLOUR_NORMAL:
    case BF_PASS_COLOUR_VARPRO: return pb->nc * (1 + K + K * K);
    case BF_PASS_SHAPE: break; /* sums nothing */
    case BF_PASS_COST:
    case BF_PASS_NORMAL:
    case BF_PASS_VARPRO:
    case BF_PASS_METRICS:
    case BF_PASS_SANDWICH: break; /* the other routes' */
    }
    return 0;
}

/* A kernel's basis block, or an affine model's parameter vector on one
 * channel and its Jacobian (SHAPE); the colour passes need none. */
static size_t colour_scratch_size(const bf_problem *pb)
{
    size_t basis = sizeof(bf_basis) / sizeof(double);
    size_t affine = pb->ly.n_params * (1 + BF_CHUNK);
    return pb->ly.offset ? affine : basis;
}

/* SHAPE of a model in basis form: B_q of the chunk's samples. */
static void fill_basis(const bf_problem *pb, const double *params, bf_scratch *sc,
                       const brdffit_batch *batch)
{
    const size_t ns = pb->grid->n_samples, K = pb->ly.n_linear;
    bf_basis *bs = (bf_basis *)(void *)sc->own;
    size_t off, count, q;
    for (off = 0; off < batch->n; off += count) {
        count = batch->n - off < BF_KERNEL_BLOCK ? batch->n - off : BF_KERNEL_BLOCK;
        bf_kernel_basis(pb->kernel, batch, off, count, params, bs);
        for (q = 0; q < K; q++)
            memcpy(pb->shape + q * ns + sc->first + off, bs->b[q], count * sizeof(double));
    }
}

/* SHAPE of a model affine in its colour: the model on one channel at
 * colour 0, whose value is B_o and whose derivative in the colour is A
 * (both the same for every channel, models/basis.h). */
static brdffit_status fill_affine(const bf_problem *pb, const double *params, bf_scratch *sc,
                                  const brdffit_batch *batch, brdffit_error *err)
{
    const brdffit_model *model = pb->model;
    const size_t ns = pb->grid->n_samples, n = batch->n, colour = pb->ly.linear[0];
    double *p1 = sc->own, *jac = sc->own + pb->ly.n_params;
    size_t k;
    for (k = 0; k < pb->ly.n_params; k++) /* on one channel, declared k is entry k */
        p1[k] = k == colour ? 0.0 : params[pb->vindex[k * pb->nc]];
    BF_RETURN_IF_ERROR(bf_model_eval(model, batch, p1, 1, sc->vals, jac, err));
    BF_RETURN_IF_ERROR(bf_model_check_outputs(model, n, 1, sc->vals, jac, sc->first, err));
    memcpy(pb->shape + sc->first, jac + colour * n, n * sizeof(double));
    memcpy(pb->shape + ns + sc->first, sc->vals, n * sizeof(double));
    return BRDFFIT_OK;
}

int bf_colour_in_place(const bf_problem *pb, bf_pass_kind kind)
{
    if (kind == BF_PASS_SHAPE) return 1;
    return kind != BF_PASS_COLOUR_VARPRO && !bf_grid_has_missing(pb->grid) &&
           (pb->objective == BRDFFIT_OBJECTIVE_LOG || pb->objective == BRDFFIT_OBJECTIVE_CUBE_ROOT);
}

/* Row weights w * present of channel m into rw (w alone on a grid without
 * missing values, whose presence may be left unloaded). */
static void row_weights(const bf_problem *pb, const bf_scratch *sc, size_t m, size_t n,
                        double *restrict rw)
{
    const double *restrict pres = sc->pres + m * n;
    size_t s;
    if (!bf_grid_has_missing(pb->grid)) {
        memcpy(rw, sc->w, n * sizeof *rw);
        return;
    }
    for (s = 0; s < n; s++) rw[s] = sc->w[s] * pres[s];
}

/* Channel m's values of the chunk from the cache at params' colours. */
static void values(const bf_problem *pb, const double *params, size_t first, size_t n, size_t m,
                   double *restrict val)
{
    const size_t ns = pb->grid->n_samples, K = pb->ly.n_linear;
    size_t q, s;
    if (pb->ly.offset)
        memcpy(val, pb->shape + K * ns + first, n * sizeof *val);
    else
        memset(val, 0, n * sizeof *val);
    for (q = 0; q < K; q++) {
        const double c = params[pb->vindex[pb->ly.linear[q] * pb->nc + m]];
        const double *restrict b = pb->shape + q * ns + first;
        for (s = 0; s < n; s++) val[s] += c * b[s];
    }
}

/* Lanes of the colour sums: lane l takes the rows s = l (mod BF_COLOUR_LANES)
 * of a chunk, a row past the last full group lane 0, and the lanes are
 * added as bf_dot()'s four (core/linalg.h), so every version of the loop
 * gives the same bits. */
#define BF_COLOUR_LANES 4
/* Sums of K <= BF_KERNEL_MAX_LINEAR colours: r^2, K of u_q r, K (K + 1) / 2
 * of u_q u_t. */
#define BF_COLOUR_SUMS (1 + BF_KERNEL_MAX_LINEAR * (BF_KERNEL_MAX_LINEAR + 3) / 2)

/* One row's sums into lane l (see colour_sums()). */
static inline void row_sums(size_t K, double f, double r, const double *const *b, size_t s,
                            double (*lane)[BF_COLOUR_LANES], size_t l)
{
    double u[BF_KERNEL_MAX_LINEAR];
    size_t q, t, j = 1 + K;
    for (q = 0; q < K; q++) u[q] = f * b[q][s];
    lane[0][l] += r * r;
    for (q = 0; q < K; q++) lane[1 + q][l] += u[q] * r;
    for (q = 0; q < K; q++)
        for (t = q; t < K; t++, j++) lane[j][l] += u[q] * u[t];
}

/* [sum r^2, sum u_q r (K), sum u_q u_t (K x K, upper triangle)] of one
 * channel's n rows r with the weighted columns u_q = f B_q, b[q] the
 * chunk's B_q, added into acc; K a constant of each call (colour_sums()). */
static inline void sums_of(size_t K, size_t n, const double *restrict f, const double *restrict r,
                           const double *const *b, double *acc)
{
    double lane[BF_COLOUR_SUMS][BF_COLOUR_LANES] = {{0.0}};
    size_t s, l, q, t, j = 1 + K;
    for (s = 0; s + BF_COLOUR_LANES <= n; s += BF_COLOUR_LANES)
        for (l = 0; l < BF_COLOUR_LANES; l++) row_sums(K, f[s + l], r[s + l], b, s + l, lane, l);
    for (; s < n; s++) row_sums(K, f[s], r[s], b, s, lane, 0);
#define BF_LANE_TOTAL(i) ((lane[i][0] + lane[i][1]) + (lane[i][2] + lane[i][3]))
    acc[0] += BF_LANE_TOTAL(0);
    for (q = 0; q < K; q++) acc[1 + q] += BF_LANE_TOTAL(1 + q);
    for (q = 0; q < K; q++)
        for (t = q; t < K; t++, j++) acc[1 + K + q * K + t] += BF_LANE_TOTAL(j);
#undef BF_LANE_TOTAL
}

static void colour_sums(const bf_problem *pb, size_t first, size_t n, const double *f,
                        const double *r, double *acc)
{
    const size_t ns = pb->grid->n_samples;
    const double *b[BF_KERNEL_MAX_LINEAR];
    size_t q;
    for (q = 0; q < pb->ly.n_linear; q++) b[q] = pb->shape + q * ns + first;
    switch (pb->ly.n_linear) {
    case 1: sums_of(1, n, f, r, b, acc); break;
    case 2: sums_of(2, n, f, r, b, acc); break;
    default: sums_of(3, n, f, r, b, acc); break;
    }
}

/* COLOUR_COST and COLOUR_NORMAL: channel m's rows transformed by the
 * objective, as every route's (pass_generic.c). */
static void chunk_objective(const bf_problem *pb, bf_pass_kind kind, const double *params,
                            bf_scratch *sc, const brdffit_batch *batch)
{
    const size_t n = batch->n, K = pb->ly.n_linear, stride = 1 + K + K * K;
    size_t m;
    for (m = 0; m < pb->nc; m++) {
        double *val = sc->vals + m * n;
        values(pb, params, sc->first, n, m, val);
        row_weights(pb, sc, m, n, sc->ww);
        bf_objective_rows(pb, m, sc->first, sc->meas + m * n, val, batch->lz, n, sc->d, sc->ww);
        if (kind == BF_PASS_COLOUR_COST)
            sc->acc[0] += bf_dot(sc->d, sc->d, n);
        else
            colour_sums(pb, sc->first, n, sc->ww, sc->d, sc->acc + m * stride);
    }
}

/* COLOUR_VARPRO: VARPRO's sums of the objective linearised at the
 * measured values, rows f (M - R) with f = w dT/dM at M = R
 * (bf_objective_slopes(): w itself under the squares objective, the
 * squares of values), the offset B_o moved to the measured side (as the
 * generic route's VARPRO). */
static void chunk_varpro(const bf_problem *pb, bf_scratch *sc, const brdffit_batch *batch)
{
    const size_t n = batch->n, ns = pb->grid->n_samples, K = pb->ly.n_linear;
    const size_t stride = 1 + K + K * K;
    size_t m, s;
    for (m = 0; m < pb->nc; m++) {
        const double *restrict meas = sc->meas + m * n;
        double *restrict rm = sc->d;
        row_weights(pb, sc, m, n, sc->ww);
        bf_objective_slopes(pb, m, sc->first, meas, batch->lz, n, sc->ww);
        if (pb->ly.offset) {
            const double *restrict off = pb->shape + K * ns + sc->first;
            for (s = 0; s < n; s++) rm[s] = sc->ww[s] * (meas[s] - off[s]);
        } else {
            for (s = 0; s < n; s++) rm[s] = sc->ww[s] * meas[s];
        }
        colour_sums(pb, sc->first, n, sc->ww, rm, sc->acc + m * stride);
    }
}

BF_VECTOR_CLONES
static brdffit_status colour_chunk(const bf_problem *pb, bf_pass_kind kind, const double *params,
                                   bf_scratch *sc, const brdffit_batch *batch, brdffit_error *err)
{
    if (kind == BF_PASS_SHAPE) {
        if (pb->ly.offset) return fill_affine(pb, params, sc, batch, err);
        fill_basis(pb, params, sc, batch);
    } else if (kind == BF_PASS_COLOUR_VARPRO) {
        chunk_varpro(pb, sc, batch);
    } else {
        chunk_objective(pb, kind, params, sc, batch);
    }
    return BRDFFIT_OK;
}

static void colour_finish(const bf_problem *pb, bf_pass_kind kind, const double *params,
                          const double *part, double *acc)
{
    (void)params;
    memcpy(acc, part, colour_acc_size(pb, kind) * sizeof *acc);
}

const bf_route bf_route_colour = {(1u << BF_PASS_SHAPE) | (1u << BF_PASS_COLOUR_COST) |
                                      (1u << BF_PASS_COLOUR_NORMAL) | (1u << BF_PASS_COLOUR_VARPRO),
                                  colour_serves,
                                  colour_acc_size,
                                  colour_scratch_size,
                                  colour_chunk,
                                  colour_finish,
                                  NULL};
