/* The fused inner loop of every fit: see pass.h. */
#include "fit/pass.h"
#include "fit/pass_internal.h"

#include <math.h>
#include <string.h>

#include "core/core.h"
#include "models/model_internal.h"

typedef struct worker {
    const bf_problem *pb;
    bf_pass_kind kind;
    const double *params;
    size_t chunk_begin, chunk_end;
    scratch sc;
    brdffit_status status;
    brdffit_error err;
} worker;

static int wants_jacobian(bf_pass_kind kind)
{
    return kind == BF_PASS_NORMAL || kind == BF_PASS_VARPRO;
}

size_t bf_pass_acc_size(const bf_problem *pb, bf_pass_kind kind)
{
    size_t k = pb->n_linear;
    switch (kind) {
    case BF_PASS_COST: return 1;
    case BF_PASS_NORMAL: return 1 + pb->n_vec + pb->n_vec * pb->n_vec;
    case BF_PASS_VARPRO: return pb->nc * (1 + k + k * k);
    case BF_PASS_METRICS: return pb->nc * 4;
    }
    return 0;
}

static size_t max_acc_size(const bf_problem *pb)
{
    static const bf_pass_kind kinds[] = {BF_PASS_COST, BF_PASS_NORMAL, BF_PASS_VARPRO,
                                         BF_PASS_METRICS};
    size_t n = 0, i;
    for (i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
        size_t a = bf_pass_acc_size(pb, kinds[i]);
        if (a > n) n = a;
        if (bf_basis_usable(pb) && (a = bf_basis_acc_size(pb, kinds[i])) > n) n = a;
    }
    return n;
}

/* Doubles of scratch one thread needs (accumulator included): the basis
 * route needs its basis block, the generic one room for the Jacobian. */
static size_t scratch_size(const bf_problem *pb)
{
    return 4 * BF_CHUNK + 3 * pb->nc * BF_CHUNK + max_acc_size(pb) +
           (bf_basis_usable(pb) ? bf_basis_scratch_size(pb)
                                : pb->model->n_params * pb->nc * BF_CHUNK);
}

static size_t thread_count(const bf_problem *pb)
{
    size_t threads = pb->threads < 1 ? 1 : pb->threads;
    if (threads > BF_MAX_THREADS) threads = BF_MAX_THREADS;
    if (threads > pb->plan->n_chunks) threads = pb->plan->n_chunks ? pb->plan->n_chunks : 1;
    return threads;
}

size_t bf_pass_work_size(const bf_problem *pb)
{
    return thread_count(pb) * scratch_size(pb);
}

static void scratch_carve(scratch *sc, double *p, const bf_problem *pb, bf_pass_kind kind,
                          size_t n_acc)
{
    size_t cb = pb->nc * BF_CHUNK;
    sc->w = p;
    sc->wsa = p + BF_CHUNK;
    sc->ww = p + 2 * BF_CHUNK;
    sc->d = p + 3 * BF_CHUNK;
    sc->meas = p + 4 * BF_CHUNK;
    sc->pres = sc->meas + cb;
    sc->vals = sc->pres + cb;
    p = sc->vals + cb;
    sc->jac = NULL;
    sc->basis = NULL;
    if (bf_basis_usable(pb)) {
        sc->basis = p;
        p += bf_basis_scratch_size(pb);
    } else {
        if (wants_jacobian(kind)) sc->jac = p;
        p += pb->model->n_params * cb;
    }
    sc->acc = p;
    memset(sc->acc, 0, n_acc * sizeof *sc->acc);
}

/* Clear-coat factor 1 / (1 - F(theta_i)) of SPEC section 2. */
static double clearcoat_factor(double r0, double cos_i)
{
    double c = cos_i < BF_DOT_FLOOR ? BF_DOT_FLOOR : (cos_i > 1.0 ? 1.0 : cos_i);
    double m = 1.0 - c, m5 = m * m * m * m * m;
    return 1.0 / ((1.0 - r0) * (1.0 - m5));
}

/* Measured value and presence of grid channel `src` for samples [first, first + n). */
static void load_channel(const brdffit_grid *g, size_t src, size_t first, size_t n, double *meas,
                         double *present)
{
    const double *v = g->values + src * g->n_samples + first;
    size_t s;
    memcpy(meas, v, n * sizeof *meas);
    if (g->missing == NULL) {
        for (s = 0; s < n; s++) present[s] = 1.0;
        return;
    }
    for (s = 0; s < n; s++) present[s] = g->missing[src * g->n_samples + first + s] ? 0.0 : 1.0;
}

static void load_mean(const brdffit_grid *g, size_t first, size_t n, double *meas,
                      double *present)
{
    size_t s, c;
    for (s = 0; s < n; s++) {
        double sum = 0.0, count = 0.0;
        for (c = 0; c < g->n_channels; c++) {
            size_t at = c * g->n_samples + first + s;
            if (g->missing != NULL && g->missing[at]) continue;
            sum += g->values[at];
            count += 1.0;
        }
        meas[s] = count > 0.0 ? sum / count : 0.0;
        present[s] = count > 0.0 ? 1.0 : 0.0;
    }
}

/* Fill meas[m][s] and pres[m][s] for samples [first, first + n). */
void bf_pass_load_measured(const bf_problem *pb, size_t first, size_t n, scratch *sc)
{
    const brdffit_grid *g = pb->grid;
    size_t m, s;
    for (m = 0; m < pb->nc; m++) {
        double *meas = sc->meas + m * n, *pres = sc->pres + m * n;
        if (pb->source == BF_SOURCE_MEAN)
            load_mean(g, first, n, meas, pres);
        else
            load_channel(g, pb->source == BF_SOURCE_ONE_CHANNEL ? pb->source_channel : m, first,
                         n, meas, pres);
        if (pb->clearcoat > 0.0)
            for (s = 0; s < n; s++)
                meas[s] *= clearcoat_factor(pb->clearcoat, g->geo.lz[first + s]);
    }
}

/* Sum of a[s] * b[s] with four independent partial sums, so the compiler
 * can keep the loop in vector registers without reassociating anything:
 * the result is the same on every machine. */
BF_VECTOR_CLONES
double bf_pass_dot(const double *restrict a, const double *restrict b, size_t n)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    size_t s = 0;
    for (; s + 4 <= n; s += 4) {
        s0 += a[s] * b[s];
        s1 += a[s + 1] * b[s + 1];
        s2 += a[s + 2] * b[s + 2];
        s3 += a[s + 3] * b[s + 3];
    }
    for (; s < n; s++) s0 += a[s] * b[s];
    return (s0 + s1) + (s2 + s3);
}

/* Row weights w * present of channel m into rw. */
static void row_weights(const scratch *sc, size_t m, size_t n, double *restrict rw)
{
    const double *restrict pres = sc->pres + m * n;
    size_t s;
    for (s = 0; s < n; s++) rw[s] = sc->w[s] * pres[s];
}

/* Weighted residuals rd = rw * (value - measured) of channel m. */
static void weighted_residuals(const scratch *sc, size_t m, size_t n, double *restrict rd)
{
    const double *restrict meas = sc->meas + m * n, *restrict val = sc->vals + m * n;
    const double *restrict rw = sc->ww;
    size_t s;
    for (s = 0; s < n; s++) rd[s] = rw[s] * (val[s] - meas[s]);
}

static void scale_rows(double *restrict x, const double *restrict rw, size_t n)
{
    size_t s;
    for (s = 0; s < n; s++) x[s] *= rw[s];
}

/* J^T J, J^T r and the cost of the weighted rows: every Jacobian column is
 * scaled by the row weight in place, then all sums are plain dot products. */
static void accumulate_normal(const bf_problem *pb, scratch *sc, size_t n)
{
    size_t nv = pb->n_vec, np = pb->model->n_params, nc = pb->nc, m, k, l;
    double *jtr = sc->acc + 1, *jtj = sc->acc + 1 + nv;
    for (m = 0; m < nc; m++) {
        row_weights(sc, m, n, sc->ww);
        weighted_residuals(sc, m, n, sc->d);
        sc->acc[0] += bf_pass_dot(sc->d, sc->d, n);
        for (k = 0; k < np; k++) scale_rows(sc->jac + (k * nc + m) * n, sc->ww, n);
        for (k = 0; k < np; k++) {
            const double *jk = sc->jac + (k * nc + m) * n;
            size_t a = pb->vindex[k * nc + m];
            jtr[a] += bf_pass_dot(jk, sc->d, n);
            for (l = k; l < np; l++) {
                size_t b = pb->vindex[l * nc + m];
                size_t lo = a < b ? a : b, hi = a < b ? b : a;
                jtj[lo * nv + hi] += bf_pass_dot(jk, sc->jac + (l * nc + m) * n, n);
            }
        }
    }
}

/* Gram matrix of the weighted linear columns and their products with the
 * weighted measurement. */
static void accumulate_varpro(const bf_problem *pb, scratch *sc, size_t n)
{
    size_t K = pb->n_linear, stride = 1 + K + K * K, nc = pb->nc, m, q, r;
    for (m = 0; m < nc; m++) {
        double *acc = sc->acc + m * stride, *b = acc + 1, *G = acc + 1 + K;
        double *rm = sc->d;
        row_weights(sc, m, n, sc->ww);
        memcpy(rm, sc->meas + m * n, n * sizeof *rm);
        scale_rows(rm, sc->ww, n);
        acc[0] += bf_pass_dot(rm, rm, n);
        for (q = 0; q < K; q++) scale_rows(sc->jac + (pb->linear[q] * nc + m) * n, sc->ww, n);
        for (q = 0; q < K; q++) {
            const double *bq = sc->jac + (pb->linear[q] * nc + m) * n;
            b[q] += bf_pass_dot(bq, rm, n);
            for (r = q; r < K; r++)
                G[q * K + r] += bf_pass_dot(bq, sc->jac + (pb->linear[r] * nc + m) * n, n);
        }
    }
}

static void accumulate_cost(const bf_problem *pb, scratch *sc, size_t n)
{
    size_t m;
    for (m = 0; m < pb->nc; m++) {
        row_weights(sc, m, n, sc->ww);
        weighted_residuals(sc, m, n, sc->d);
        sc->acc[0] += bf_pass_dot(sc->d, sc->d, n);
    }
}

static void accumulate_metrics(const bf_problem *pb, scratch *sc, size_t first, size_t n)
{
    const double *lz = pb->grid->geo.lz + first;
    size_t m, s;
    for (m = 0; m < pb->nc; m++) {
        const double *meas = sc->meas + m * n, *val = sc->vals + m * n, *pres = sc->pres + m * n;
        double *acc = sc->acc + 4 * m;
        for (s = 0; s < n; s++) {
            double d = val[s] - meas[s], c = lz[s] > 0.0 ? lz[s] : 0.0;
            acc[0] += pres[s] * d * d;
            acc[1] += pres[s] * sc->wsa[s] * c * c * d * d;
            acc[2] += pres[s] * sc->wsa[s];
            acc[3] += pres[s] * sc->w[s] * sc->w[s] * d * d;
        }
    }
}

/* Whether this pass takes the basis route (built-in model, no missing values). */
static int basis_pass(const bf_problem *pb, bf_pass_kind kind)
{
    return kind != BF_PASS_METRICS && bf_basis_usable(pb);
}

static brdffit_status run_chunk(worker *wk, size_t ci)
{
    const bf_problem *pb = wk->pb;
    scratch *sc = &wk->sc;
    size_t first, n;
    brdffit_batch batch;
    bf_weight_plan_chunk(pb->plan, ci, &first, &n, sc->w);
    if (wk->kind == BF_PASS_METRICS) bf_weight_plan_chunk(pb->plan_sa, ci, &first, &n, sc->wsa);
    bf_pass_load_measured(pb, first, n, sc);
    bf_geometry_batch(&pb->grid->geo, first, n, &batch);
    if (basis_pass(pb, wk->kind)) {
        bf_basis_chunk(pb, wk->kind, wk->params, sc, &batch, sc->basis);
        return BRDFFIT_OK;
    }
    BF_RETURN_IF_ERROR(bf_model_eval(pb->model, &batch, wk->params, pb->nc, sc->vals, sc->jac,
                                     &wk->err));
    switch (wk->kind) {
    case BF_PASS_COST: accumulate_cost(pb, sc, n); break;
    case BF_PASS_NORMAL: accumulate_normal(pb, sc, n); break;
    case BF_PASS_VARPRO: accumulate_varpro(pb, sc, n); break;
    case BF_PASS_METRICS: accumulate_metrics(pb, sc, first, n); break;
    }
    return BRDFFIT_OK;
}

static void run_worker(worker *wk)
{
    size_t ci;
    wk->status = BRDFFIT_OK;
    for (ci = wk->chunk_begin; ci < wk->chunk_end; ci++) {
        wk->status = run_chunk(wk, ci);
        if (wk->status != BRDFFIT_OK) break;
    }
}

/* Mirror the upper triangles accumulated by NORMAL and VARPRO. */
static void mirror(const bf_problem *pb, bf_pass_kind kind, double *acc)
{
    size_t i, j, m;
    if (kind == BF_PASS_NORMAL) {
        double *jtj = acc + 1 + pb->n_vec;
        for (i = 0; i < pb->n_vec; i++)
            for (j = 0; j < i; j++) jtj[i * pb->n_vec + j] = jtj[j * pb->n_vec + i];
    } else if (kind == BF_PASS_VARPRO) {
        size_t K = pb->n_linear, stride = 1 + K + K * K;
        for (m = 0; m < pb->nc; m++) {
            double *G = acc + m * stride + 1 + K;
            for (i = 0; i < K; i++)
                for (j = 0; j < i; j++) G[i * K + j] = G[j * K + i];
        }
    }
}

static void worker_task(void *arg, size_t task)
{
    worker *wk = arg;
    run_worker(&wk[task]);
}

static int all_finite(const double *a, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

brdffit_status bf_pass(const bf_problem *pb, bf_pass_kind kind, const double *params,
                       double *acc, brdffit_error *err)
{
    worker wk[BF_MAX_THREADS];
    size_t threads = thread_count(pb), per = scratch_size(pb), t, i;
    size_t n_acc = bf_pass_acc_size(pb, kind), n_chunks = pb->plan->n_chunks;
    int basis = basis_pass(pb, kind);
    size_t n_part = basis ? bf_basis_acc_size(pb, kind) : n_acc;
    for (t = 0; t < threads; t++) {
        wk[t].pb = pb;
        wk[t].kind = kind;
        wk[t].params = params;
        wk[t].chunk_begin = n_chunks * t / threads;
        wk[t].chunk_end = n_chunks * (t + 1) / threads;
        wk[t].err.message[0] = '\0';
        scratch_carve(&wk[t].sc, pb->work + t * per, pb, kind, n_part);
    }
    bf_pool_run(pb->pool, worker_task, wk, threads);
    for (t = 0; t < threads; t++) {
        if (wk[t].status == BRDFFIT_OK) continue;
        if (err != NULL) *err = wk[t].err;
        return wk[t].status;
    }
    /* partial sums in block order, into the first block's accumulator */
    for (t = 1; t < threads; t++)
        for (i = 0; i < n_part; i++) wk[0].sc.acc[i] += wk[t].sc.acc[i];
    if (basis) bf_basis_finish(pb, kind, params, wk[0].sc.acc, acc);
    else memcpy(acc, wk[0].sc.acc, n_acc * sizeof *acc);
    mirror(pb, kind, acc);
    if (!all_finite(acc, n_acc))
        return bf_fail(err, BRDFFIT_E_NONFINITE,
                       "model '%s' or the data gave a non-finite value in a pass",
                       pb->model->name);
    return BRDFFIT_OK;
}

brdffit_status bf_count_rows(const bf_problem *pb, size_t *rows, brdffit_error *err)
{
    double w[BF_CHUNK], meas[BF_CHUNK], present[BF_CHUNK];
    size_t ci, first, n, m, s, count = 0;
    (void)err;
    (void)meas;
    for (ci = 0; ci < pb->plan->n_chunks; ci++) {
        bf_weight_plan_chunk(pb->plan, ci, &first, &n, w);
        for (m = 0; m < pb->nc; m++) {
            if (pb->source == BF_SOURCE_MEAN)
                load_mean(pb->grid, first, n, meas, present);
            else
                load_channel(pb->grid,
                             pb->source == BF_SOURCE_ONE_CHANNEL ? pb->source_channel : m,
                             first, n, meas, present);
            for (s = 0; s < n; s++) count += present[s] != 0.0 && w[s] != 0.0;
        }
    }
    *rows = count;
    return BRDFFIT_OK;
}
