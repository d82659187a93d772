/* The pass driver: the fused inner loop of every fit (pass.h). It splits
 * the chunks into blocks, one per thread, loads each chunk's weights and
 * measured values, hands the chunk to the problem's route
 * (pass_route.h) and adds the blocks' partial sums in block order. */
#include "fit/pass.h"
#include "fit/pass_fused.h"
#include "fit/pass_route.h"

#include <math.h>
#include <string.h>

#include "core/core.h"

/* The routes, most specialised first: a problem takes the first that
 * serves it. */
static const bf_route *const routes[] = {&bf_route_basis, &bf_route_generic};

typedef struct worker {
    const bf_problem *pb;
    const bf_route *route;
    bf_pass_kind kind;
    const double *params;
    size_t chunk_begin, chunk_end;
    bf_scratch sc;
    brdffit_status status;
    brdffit_error err;
} worker;

void bf_pass_prepare(bf_problem *pb)
{
    size_t i;
    pb->kernel = bf_model_basis(pb->model);
    pb->route = &bf_route_generic;
    bf_fused_prepare(pb);
    for (i = 0; i < sizeof routes / sizeof routes[0]; i++)
        if (routes[i]->serves(pb)) {
            pb->route = routes[i];
            break;
        }
}

/* The route that accumulates passes of this kind: the problem's when it
 * takes the kind, else the generic route. SANDWICH needs each row's
 * Jacobian and always takes the generic route; SHAPE and the colour passes
 * take the colour route. */
static const bf_route *route_for(const bf_problem *pb, bf_pass_kind kind)
{
    if (kind == BF_PASS_SANDWICH) return &bf_route_generic; /* rows, one at a time */
    if (bf_route_colour.kinds & (1u << kind)) return &bf_route_colour;
    return (pb->route->kinds & (1u << kind)) ? pb->route : &bf_route_generic;
}

/* Doubles of the routes' own scratch: the problem's route's, the generic
 * route's when SANDWICH passes will run (METRICS, the other kind the basis
 * route leaves to it, needs none of it), the colour route's when colour
 * passes will. */
static size_t own_size(const bf_problem *pb)
{
    size_t own = pb->route->scratch_size(pb), other;
    if (pb->sandwich && (other = bf_route_generic.scratch_size(pb)) > own) own = other;
    if (pb->colour && (other = bf_route_colour.scratch_size(pb)) > own) own = other;
    return own;
}

size_t bf_pass_acc_size(const bf_problem *pb, bf_pass_kind kind)
{
    size_t k = pb->ly.n_linear, nv = pb->ly.n_vec;
    switch (kind) {
    case BF_PASS_COST: return 1;
    case BF_PASS_NORMAL: return 1 + nv + nv * nv;
    case BF_PASS_VARPRO: return pb->nc * (1 + k + k * k);
    case BF_PASS_METRICS: return pb->nc * 4;
    case BF_PASS_SANDWICH: return nv * nv;
    case BF_PASS_SHAPE: return 0;
    case BF_PASS_COLOUR_COST: return 1;
    case BF_PASS_COLOUR_NORMAL:
    case BF_PASS_COLOUR_VARPRO: return pb->nc * (1 + k + k * k);
    }
    return 0;
}

/* Largest accumulator of any kind: the final one or a route's partial one
 * (SANDWICH's, n * n on the generic route, is smaller than NORMAL's). */
static size_t max_acc_size(const bf_problem *pb)
{
    static const bf_pass_kind kinds[] = {BF_PASS_COST, BF_PASS_NORMAL, BF_PASS_VARPRO,
                                         BF_PASS_METRICS};
    size_t n = 0, i, a;
    for (i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
        if ((a = bf_pass_acc_size(pb, kinds[i])) > n) n = a;
        if ((a = pb->route->acc_size(pb, kinds[i])) > n) n = a;
    }
    return n;
}

/* Doubles of scratch one thread needs (accumulator included). */
static size_t scratch_size(const bf_problem *pb)
{
    return 4 * BF_CHUNK + 3 * pb->nc * BF_CHUNK + max_acc_size(pb) + own_size(pb);
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

static void scratch_carve(bf_scratch *sc, double *p, const bf_problem *pb, size_t n_acc)
{
    size_t cb = pb->nc * BF_CHUNK;
    sc->w = p;
    sc->wsa = p + BF_CHUNK;
    sc->ww = p + 2 * BF_CHUNK;
    sc->d = p + 3 * BF_CHUNK;
    sc->meas = p + 4 * BF_CHUNK;
    sc->pres = sc->meas + cb;
    sc->vals = sc->pres + cb;
    sc->own = sc->vals + cb;
    sc->acc = sc->own + own_size(pb);
    memset(sc->acc, 0, n_acc * sizeof *sc->acc);
}

/* Measured values (clear-coat compensated when asked) and presence of the
 * chunk's samples, meas[m][s] and pres[m][s] for every model channel m. */
static void load_measured(const bf_problem *pb, const brdffit_batch *batch, size_t first,
                          bf_scratch *sc)
{
    size_t m, s, n = batch->n;
    for (m = 0; m < pb->nc; m++) {
        double *meas = sc->meas + m * n, *pres = sc->pres + m * n;
        if (pb->source == BF_SOURCE_MEAN)
            bf_grid_load_mean(pb->grid, first, n, meas, pres);
        else
            bf_grid_load_channel(pb->grid,
                                 pb->source == BF_SOURCE_ONE_CHANNEL ? pb->source_channel : m,
                                 first, n, meas, pres);
        if (pb->clearcoat > 0.0)
            for (s = 0; s < n; s++)
                meas[s] *= 1.0 / bf_grid_coat_divisor(pb->clearcoat, batch->lz[s]);
    }
}

size_t bf_pass_terms_size(const bf_problem *pb)
{
    const size_t n = pb->grid->n_samples;
    switch (pb->objective) {
    case BRDFFIT_OBJECTIVE_LOG:
    case BRDFFIT_OBJECTIVE_RELATIVE: return pb->nc * n;
    case BRDFFIT_OBJECTIVE_CUBE_ROOT: return (pb->nc + 1) * n;
    case BRDFFIT_OBJECTIVE_SQUARES: break;
    }
    return 0;
}

void bf_pass_terms(const bf_problem *pb, double *terms)
{
    const size_t ns = pb->grid->n_samples;
    bf_scratch sc;
    size_t first, n, m;
    if (bf_pass_terms_size(pb) == 0) return;
    scratch_carve(&sc, pb->work, pb, 0);
    for (first = 0; first < ns; first += n) {
        brdffit_batch batch;
        n = ns - first < BF_CHUNK ? ns - first : BF_CHUNK;
        bf_grid_batch(pb->grid, first, n, &batch);
        load_measured(pb, &batch, first, &sc);
        for (m = 0; m < pb->nc; m++)
            bf_objective_terms(pb, sc.meas + m * n, batch.lz, n, terms + m * ns + first,
                               m == 0 && pb->objective == BRDFFIT_OBJECTIVE_CUBE_ROOT
                                   ? terms + pb->nc * ns + first
                                   : NULL);
    }
}

/* Whether the worker's route reads the chunk's measured values from the
 * scratch (every route may read what it needs in place, or need none). */
static int reads_measured(const worker *wk)
{
    if (wk->route == &bf_route_basis) return !bf_basis_in_place(wk->pb, wk->kind);
    if (wk->route == &bf_route_colour) return !bf_colour_in_place(wk->pb, wk->kind);
    return !bf_generic_in_place(wk->pb, wk->kind);
}

static brdffit_status run_chunk(worker *wk, size_t ci)
{
    const bf_problem *pb = wk->pb;
    bf_scratch *sc = &wk->sc;
    size_t first, n;
    brdffit_batch batch;
    bf_weight_plan_chunk(pb->plan, ci, &first, &n, sc->w);
    if (wk->kind == BF_PASS_METRICS) bf_weight_plan_chunk(pb->plan_sa, ci, &first, &n, sc->wsa);
    bf_grid_batch(pb->grid, first, n, &batch);
    sc->first = first;
    sc->chunk = ci;
    if (reads_measured(wk)) load_measured(pb, &batch, first, sc);
    return wk->route->chunk(pb, wk->kind, wk->params, sc, &batch, &wk->err);
}

static void worker_task(void *arg, size_t task)
{
    worker *wk = (worker *)arg + task;
    size_t ci;
    wk->status = BRDFFIT_OK;
    if (wk->route->block != NULL &&
        wk->route->block(wk->pb, wk->kind, wk->params, &wk->sc, wk->chunk_begin, wk->chunk_end))
        return;
    for (ci = wk->chunk_begin; ci < wk->chunk_end; ci++) {
        wk->status = run_chunk(wk, ci);
        if (wk->status != BRDFFIT_OK) break;
    }
}

/* Mirror the upper triangles accumulated by NORMAL, SANDWICH and VARPRO. */
static void mirror(const bf_problem *pb, bf_pass_kind kind, double *acc)
{
    size_t i, j, m, nv = pb->ly.n_vec;
    if (kind == BF_PASS_NORMAL) {
        double *jtj = acc + 1 + nv;
        for (i = 0; i < nv; i++)
            for (j = 0; j < i; j++) jtj[i * nv + j] = jtj[j * nv + i];
    } else if (kind == BF_PASS_SANDWICH) {
        for (i = 0; i < nv; i++)
            for (j = 0; j < i; j++) acc[i * nv + j] = acc[j * nv + i];
    } else if (kind == BF_PASS_VARPRO || kind == BF_PASS_COLOUR_NORMAL ||
               kind == BF_PASS_COLOUR_VARPRO) {
        size_t K = pb->ly.n_linear, stride = 1 + K + K * K;
        for (m = 0; m < pb->nc; m++) {
            double *G = acc + m * stride + 1 + K;
            for (i = 0; i < K; i++)
                for (j = 0; j < i; j++) G[i * K + j] = G[j * K + i];
        }
    }
}

/* Set up one worker per block of chunks; returns the block count. */
static size_t start_workers(worker *wk, const bf_problem *pb, const bf_route *route,
                            bf_pass_kind kind, const double *params)
{
    size_t threads = thread_count(pb), per = scratch_size(pb), t;
    size_t n_chunks = pb->plan->n_chunks, n_part = route->acc_size(pb, kind);
    for (t = 0; t < threads; t++) {
        wk[t].pb = pb;
        wk[t].route = route;
        wk[t].kind = kind;
        wk[t].params = params;
        wk[t].chunk_begin = n_chunks * t / threads;
        wk[t].chunk_end = n_chunks * (t + 1) / threads;
        wk[t].err.message[0] = '\0';
        scratch_carve(&wk[t].sc, pb->work + t * per, pb, n_part);
    }
    return threads;
}

brdffit_status bf_pass(const bf_problem *pb, bf_pass_kind kind, const double *params, double *acc,
                       brdffit_error *err)
{
    worker wk[BF_MAX_THREADS];
    const bf_route *route = route_for(pb, kind);
    size_t threads = start_workers(wk, pb, route, kind, params), t, i;
    size_t n_acc = bf_pass_acc_size(pb, kind), n_part = route->acc_size(pb, kind);
    bf_pool_run(pb->pool, worker_task, wk, threads);
    for (t = 0; t < threads; t++) {
        if (wk[t].status == BRDFFIT_OK) continue;
        if (err != NULL) *err = wk[t].err;
        return wk[t].status;
    }
    /* partial sums in block order, into the first block's accumulator */
    for (t = 1; t < threads; t++)
        for (i = 0; i < n_part; i++) wk[0].sc.acc[i] += wk[t].sc.acc[i];
    route->finish(pb, kind, params, wk[0].sc.acc, acc);
    mirror(pb, kind, acc);
    if (!bf_all_finite(acc, n_acc))
        return bf_fail(err, BRDFFIT_E_NONFINITE,
                       "model '%s' or the data gave a non-finite value in a pass",
                       brdffit_model_name(pb->model));
    return BRDFFIT_OK;
}

brdffit_status bf_count_rows(const bf_problem *pb, size_t *rows, brdffit_error *err)
{
    size_t m;
    (void)err;
    if (pb->source == BF_SOURCE_MEAN) {
        *rows = pb->nc * bf_grid_count_rows(pb->plan, BF_GRID_MEAN);
        return BRDFFIT_OK;
    }
    if (pb->source == BF_SOURCE_ONE_CHANNEL) {
        *rows = pb->nc * bf_grid_count_rows(pb->plan, pb->source_channel);
        return BRDFFIT_OK;
    }
    for (*rows = 0, m = 0; m < pb->nc; m++) *rows += bf_grid_count_rows(pb->plan, m);
    return BRDFFIT_OK;
}
