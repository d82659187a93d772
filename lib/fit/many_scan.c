/* What the items of a batch share: see many_scan.h. */
#include "fit/many_scan.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "fit/pass_fused.h"
#include "fit/plausible.h"
#include "fit/run.h"
#include "fit/scan.h"

/* ---- the plans ---------------------------------------------------------------------------- */

static brdffit_status make_plans(bf_batch *b, const brdffit_fit *fit)
{
    brdffit_error err;
    brdffit_status st = bf_run_plans(fit, &b->plan, &b->plan_sa, &err);
    size_t n1;
    if (st != BRDFFIT_OK) return st == BRDFFIT_E_OUT_OF_MEMORY ? st : BRDFFIT_OK;
    n1 = b->plan.n_chunks * BF_CHUNK;
    b->weights = bf_calloc(&fit->alloc, n1 + b->plan_sa.n_chunks * BF_CHUNK, sizeof(double));
    if (b->weights == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    bf_weight_plan_fill(&b->plan, b->weights);
    bf_weight_plan_fill(&b->plan_sa, b->weights + n1);
    b->plan.cached = b->weights;
    b->plan_sa.cached = b->weights + n1;
    b->has_plans = 1;
    return BRDFFIT_OK;
}

int bf_batch_plans(const brdffit_fit *fit, bf_weight_plan *plan, bf_weight_plan *plan_sa)
{
    if (fit->batch == NULL || !fit->batch->has_plans) return 0;
    *plan = fit->batch->plan;
    *plan_sa = fit->batch->plan_sa;
    plan->grid = plan_sa->grid = fit->grid; /* presence and values: this fit's */
    return 1;
}

/* ---- the scan basis ----------------------------------------------------------------------- */

/* Whether auto's stage st can take its VARPRO sums from a basis table: a
 * model in basis form whose linear parameters are the kernel's basis
 * functions in order, without a colour-free offset. */
static int tabulable(const bf_stage *st, bf_basis_form *form)
{
    const bf_problem *pb = &st->pb;
    size_t q;
    if (pb->kernel == NULL || pb->ly.offset) return 0;
    bf_kernel_form(pb->kernel, form);
    if (pb->ly.n_linear != form->n_linear) return 0;
    for (q = 0; q < form->n_linear; q++)
        if (pb->ly.linear[q] != form->n_shape + q) return 0;
    return 1;
}

/* Chunk ci's weights as the stage's VARPRO pass reads them: the plan's
 * (cached) or, when the fused loop takes the pass, its base weights times
 * their factors (the loop's products, bf_weight_plan_base()). */
static void chunk_weights(const bf_batch *b, const bf_weight_plan *plan, size_t ci, size_t *first,
                          size_t *n, double *w)
{
    bf_weight_piece piece[2];
    size_t np, k, i;
    bf_weight_plan_chunk(plan, ci, first, n, w);
    if (!b->single) return;
    np = bf_weight_plan_base(plan, ci, piece);
    for (k = 0; k < np; k++)
        for (i = 0; i < piece[k].count; i++)
            w[piece[k].first - *first + i] =
                (double)plan->base[piece[k].first + i] * piece[k].factor;
}

/* The basis at every grid point into cols (column-major, n_rows each,
 * point j's B_q at column j * L + q), the weights and the coat factors;
 * usable[j] 0 where a value is not finite. */
static void fill_columns(bf_batch *b, bf_stage *st, const bf_scan *sc, size_t n_shape, double *cols)
{
    const bf_problem *pb = &st->pb;
    double u[BF_MAX_DIMS], shape[BF_KERNEL_MAX_SHAPE], w[BF_CHUNK];
    size_t j, ci, k, q, i, first, n;
    for (j = 0; j < b->n_points; j++) {
        bf_scan_grid_point(sc, j, u);
        bf_scan_set_point(st, sc, u);
        for (k = 0; k < n_shape; k++) shape[k] = st->p[st->vindex[k * pb->nc]];
        b->has_bounds = bf_plausible_cheap(st, b->bounds + j * b->L);
        b->usable[j] = 1;
        for (ci = 0; ci < pb->plan->n_chunks; ci++) {
            brdffit_batch geo;
            bf_basis basis;
            chunk_weights(b, pb->plan, ci, &first, &n, w);
            bf_grid_batch(pb->grid, first, n, &geo);
            bf_kernel_basis(pb->kernel, &geo, 0, n, shape, &basis);
            for (i = 0; i < n; i++) {
                size_t row = ci * BF_CHUNK + i;
                for (q = 0; q < b->L; q++) {
                    double v = basis.b[q][i];
                    cols[(j * b->L + q) * b->n_rows + row] = v;
                    if (!isfinite(v)) b->usable[j] = 0;
                }
                if (j > 0) continue;
                b->w2[row] = w[i] * w[i];
                b->coat[row] = pb->clearcoat > 0.0
                                   ? 1.0 / bf_grid_coat_divisor(pb->clearcoat, geo.lz[i])
                                   : 1.0;
            }
        }
    }
}

/* Keep each distinct column once: b->col[j * L + q] its index among the
 * kept ones, whose data are moved to the front of cols; returns how many
 * are kept. */
static size_t dedupe(bf_batch *b, double *cols)
{
    size_t c, d, kept = 0, bytes = b->n_rows * sizeof *cols;
    for (c = 0; c < b->n_points * b->L; c++) {
        for (d = 0; d < kept; d++)
            if (memcmp(cols + d * b->n_rows, cols + c * b->n_rows, bytes) == 0) break;
        if (d == kept) {
            if (kept != c) memcpy(cols + kept * b->n_rows, cols + c * b->n_rows, bytes);
            kept++;
        }
        b->col[c] = d;
    }
    return kept;
}

/* The kept columns row-major into b->basis, and every point's Gram. */
static void pack(bf_batch *b, const double *cols)
{
    size_t j, q, r, row, c, L = b->L;
    for (c = 0; c < b->n_cols; c++)
        for (row = 0; row < b->n_rows; row++)
            b->basis[row * b->stride + c] = cols[c * b->n_rows + row];
    for (j = 0; j < b->n_points; j++)
        for (q = 0; q < L; q++)
            for (r = 0; r < L; r++) {
                const double *x = cols + b->col[j * L + q] * b->n_rows;
                const double *y = cols + b->col[j * L + r] * b->n_rows;
                double g = 0.0;
                for (row = 0; row < b->n_rows; row++) g += b->w2[row] * x[row] * y[row];
                b->gram[(j * L + q) * L + r] = g;
            }
}

static brdffit_status alloc_table(bf_batch *b, const brdffit_allocator *a, double **cols)
{
    size_t P = b->n_points, L = b->L;
    *cols = bf_calloc(a, P * L * b->n_rows, sizeof **cols);
    b->col = bf_calloc(a, P * L, sizeof *b->col);
    b->w2 = bf_calloc(a, 2 * b->n_rows + P * L * L + P * L, sizeof *b->w2);
    b->usable = bf_calloc(a, P, 1);
    if (*cols == NULL || b->col == NULL || b->w2 == NULL || b->usable == NULL)
        return BRDFFIT_E_OUT_OF_MEMORY;
    b->coat = b->w2 + b->n_rows;
    b->gram = b->coat + b->n_rows;
    b->bounds = b->gram + P * L * L;
    return BRDFFIT_OK;
}

/* The scan basis of auto's stage st, when it has one that fits in
 * BF_BATCH_SCAN_MAX. */
static brdffit_status make_table(bf_batch *b, bf_stage *st, const brdffit_allocator *a)
{
    bf_basis_form form;
    bf_scan sc;
    double *cols = NULL;
    brdffit_status status;
    size_t P = bf_scan_layout(st, &sc), bytes;
    if (P == 0 || !tabulable(st, &form)) return BRDFFIT_OK;
    b->n_points = P;
    b->nc = st->pb.nc;
    b->L = form.n_linear;
    b->n_rows = st->pb.plan->n_chunks * BF_CHUNK;
    b->single = bf_fused_serves_any(&st->pb, BF_PASS_VARPRO);
    if (!bf_mul_size(P * b->L, b->n_rows, &bytes) || !bf_mul_size(bytes, sizeof(double), &bytes) ||
        bytes > BF_BATCH_SCAN_MAX) {
        b->n_points = 0;
        return BRDFFIT_OK;
    }
    status = alloc_table(b, a, &cols);
    if (status == BRDFFIT_OK) {
        fill_columns(b, st, &sc, form.n_shape, cols);
        b->n_cols = dedupe(b, cols);
        b->stride = (b->n_cols + BF_BATCH_COLS - 1) / BF_BATCH_COLS * BF_BATCH_COLS;
        b->basis = bf_calloc(a, b->n_rows * b->stride, sizeof *b->basis);
        if (b->basis == NULL) status = BRDFFIT_E_OUT_OF_MEMORY;
    }
    if (status == BRDFFIT_OK) pack(b, cols);
    bf_free(a, cols);
    /* one thread's products: W R per channel, then (W R)^T B and R^T W R */
    b->work_size = b->nc * b->n_rows + b->nc * (b->n_cols + 1);
    return status;
}

/* Auto's stage over the private fit, as an item's run sets it up (its
 * values are not read), for the scan basis. */
static brdffit_status make_scan(bf_batch *b, brdffit_fit *fit)
{
    bf_run run;
    bf_result res;
    bf_stage st;
    char message[BF_FIT_MESSAGE_SIZE];
    brdffit_status status;
    if (fit->pipeline != BRDFFIT_PIPELINE_AUTO) return BRDFFIT_OK;
    memset(&run, 0, sizeof run);
    memset(&res, 0, sizeof res);
    res.message = message;
    run.fit = fit;
    run.result = &res;
    bf_batch_plans(fit, &run.plan, &run.plan_sa);
    bf_pool_start(&run.pool, 0);
    status = bf_stage_init(&st, &run, fit->nc, BF_SOURCE_CHANNELS, 0, 0);
    if (status == BRDFFIT_OK)
        status = make_table(b, &st, &fit->alloc);
    else if (status != BRDFFIT_E_OUT_OF_MEMORY)
        status = BRDFFIT_OK; /* the items say why */
    bf_stage_free(&st);
    bf_pool_stop(&run.pool);
    if (status != BRDFFIT_OK) b->n_points = 0;
    return status;
}

brdffit_status bf_batch_init(bf_batch *b, brdffit_fit *fit)
{
    memset(b, 0, sizeof *b);
    BF_RETURN_IF_ERROR(make_plans(b, fit));
    if (!b->has_plans) return BRDFFIT_OK;
    fit->batch = b; /* the stage below reads the plans from it */
    return make_scan(b, fit);
}

void bf_batch_free(bf_batch *b, const brdffit_allocator *a)
{
    if (b->has_plans) {
        b->plan.cached = b->plan_sa.cached = NULL;
        bf_weight_plan_free(&b->plan, a);
        bf_weight_plan_free(&b->plan_sa, a);
    }
    bf_free(a, b->weights);
    bf_free(a, b->col);
    bf_free(a, b->w2);
    bf_free(a, b->usable);
    bf_free(a, b->basis);
    memset(b, 0, sizeof *b);
}

/* ---- an item's sums ----------------------------------------------------------------------- */

/* Two lanes of a product: the baseline instruction set's vector, so that
 * the block's eight sums stay in four registers (each lane adds in row
 * order, as a scalar loop would); read where a double may lie (the
 * caller's allocator promises no more alignment). */
typedef double bf_lane2 __attribute__((vector_size(2 * sizeof(double)), aligned(sizeof(double))));

/* (W R)^T B for columns [c, c + BF_BATCH_COLS) of one channel's y = W R
 * into out (the columns past n_cols are padding, left out). */
static void block_product(const bf_batch *b, const double *y, size_t c, double *out)
{
    bf_lane2 a0 = {0.0, 0.0}, a1 = a0, a2 = a0, a3 = a0;
    double acc[BF_BATCH_COLS];
    size_t row, n = b->n_cols - c < BF_BATCH_COLS ? b->n_cols - c : BF_BATCH_COLS;
    for (row = 0; row < b->n_rows; row++) {
        const bf_lane2 *x = (const bf_lane2 *)(b->basis + row * b->stride + c);
        const bf_lane2 yr = {y[row], y[row]};
        a0 += x[0] * yr;
        a1 += x[1] * yr;
        a2 += x[2] * yr;
        a3 += x[3] * yr;
    }
    memcpy(acc, &a0, sizeof a0);
    memcpy(acc + 2, &a1, sizeof a1);
    memcpy(acc + 4, &a2, sizeof a2);
    memcpy(acc + 6, &a3, sizeof a3);
    memcpy(out, acc, n * sizeof *out);
}

/* The item's weighted values W R of every channel over the table's rows,
 * R^T W R, and (W R)^T B for every kept column, into fit->batch_work. R is
 * the pass's: the value times 1 / the coat's divisor, rounded to single
 * precision in the grid's scaled units when the fused loop reads it (the
 * same bits as its input; exact back in the grid's units). */
static void item_products(const bf_batch *b, const brdffit_fit *fit, const bf_problem *pb)
{
    double *y = fit->batch_work, *prod = y + b->nc * b->n_rows, *rr = prod + b->nc * b->n_cols;
    double w[BF_CHUNK];
    const double scale = bf_grid_fscale(fit->grid), unit = b->single ? 1.0 / scale : 1.0;
    size_t m, ci, i, c, first, n;
    for (m = 0; m < b->nc; m++) {
        const double *v = bf_grid_values(fit->grid, m);
        double *ym = y + m * b->n_rows, sum = 0.0;
        memset(ym, 0, b->n_rows * sizeof *ym);
        for (ci = 0; ci < pb->plan->n_chunks; ci++) {
            bf_weight_plan_chunk(pb->plan, ci, &first, &n, w);
            for (i = 0; i < n; i++) {
                double r = v[first + i] * b->coat[ci * BF_CHUNK + i];
                if (b->single) r = (double)(float)(r * scale) * unit;
                ym[ci * BF_CHUNK + i] = b->w2[ci * BF_CHUNK + i] * r;
                sum += ym[ci * BF_CHUNK + i] * r;
            }
        }
        rr[m] = sum;
        memset(prod + m * b->n_cols, 0, b->n_cols * sizeof *prod);
    }
    for (m = 0; m < b->nc; m++)
        for (c = 0; c < b->n_cols; c += BF_BATCH_COLS)
            block_product(b, y + m * b->n_rows, c, prod + m * b->n_cols + c);
}

/* Whether the batch's scan basis serves auto's stage st at grid point
 * flat (the sums need an item without a missing value as well). */
static int serves(const bf_stage *st, size_t flat)
{
    const bf_batch *b = st->run->fit->batch;
    return b != NULL && flat < b->n_points && st->pb.nc == b->nc &&
           st->pb.source == BF_SOURCE_CHANNELS;
}

const double *bf_batch_point_basis(const bf_stage *st, size_t flat, const size_t **col,
                                   size_t *stride, size_t *n_rows)
{
    const bf_batch *b = st->run->fit->batch;
    if (!serves(st, flat) || !b->usable[flat]) return NULL;
    *col = b->col + flat * b->L;
    *stride = b->stride;
    *n_rows = b->n_rows;
    return b->basis;
}

int bf_batch_scan_bounds(bf_stage *st, size_t flat)
{
    const bf_batch *b = st->run->fit->batch;
    if (!serves(st, flat)) return 0;
    if (b->has_bounds) bf_plausible_apply(st, b->bounds + flat * b->L);
    return 1;
}

int bf_batch_scan_sums(bf_stage *st, size_t flat)
{
    const brdffit_fit *fit = st->run->fit;
    const bf_batch *b = fit->batch;
    const double *prod, *rr, *G;
    size_t L, stride, m, q, r;
    if (!serves(st, flat) || !b->usable[flat] || bf_grid_has_missing(fit->grid)) return 0;
    /* values out of single precision's reach: the pass takes the double
     * route, with the plan's own weights */
    if (b->single && !(bf_grid_fscale(fit->grid) > 0.0)) return 0;
    if (!st->run->batch_ready) {
        item_products(b, fit, &st->pb);
        st->run->batch_ready = 1;
    }
    L = b->L;
    stride = 1 + L + L * L;
    prod = fit->batch_work + b->nc * b->n_rows;
    rr = prod + b->nc * b->n_cols;
    G = b->gram + flat * L * L;
    for (m = 0; m < b->nc; m++) {
        double *acc = st->acc + m * stride;
        acc[0] = rr[m];
        for (q = 0; q < L; q++) {
            acc[1 + q] = prod[m * b->n_cols + b->col[flat * L + q]];
            for (r = 0; r < L; r++) acc[1 + L + q * L + r] = G[q * L + r];
        }
    }
    for (q = 0; q < b->nc * stride; q++)
        if (!isfinite(st->acc[q])) return 0; /* the pass says why */
    return 1;
}
