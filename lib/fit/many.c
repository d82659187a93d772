/* Many fits over one geometry (many.h): one private fit per thread over a
 * grid view whose values are replaced per item; items handed out one at a
 * time from a shared counter, so any thread may fit any item and each
 * item's result depends on the item alone. */
#include "brdffit/many.h"

#include <math.h>
#include <stdatomic.h>
#include <stddef.h>
#include <string.h>

#include "core/core.h"
#include "fit/fit_internal.h"
#include "fit/many_scan.h"
#include "fit/pool.h"
#include "grid/grid_internal.h"
#include "models/models.h"

/* The first version of brdffit_many_out ends with n_run. */
#define BF_MANY_OUT_V1 (offsetof(brdffit_many_out, n_run) + sizeof(size_t))
/* Progress is reported at least every n_items / BF_MANY_STEPS items. */
#define BF_MANY_STEPS 256

typedef struct many_worker {
    brdffit_grid view;      /* the prototype's geometry, this thread's values */
    double *values;         /* n_samples * n_channels: the view's values */
    unsigned char *mask;    /* as many bytes: the view's missing mask */
    brdffit_fit *fit;       /* private, over the view */
} many_worker;

typedef struct many_job {
    brdffit_fit *proto;
    size_t n_items, per_item; /* values per item */
    const double *values;
    const unsigned char *missing;
    brdffit_many_out *out;
    brdffit_many_progress_fn progress;
    void *user;
    size_t step, reported;    /* progress: report every step items; last count reported */
    many_worker *workers;
    bf_batch batch;           /* what every item shares (many_scan.h) */
    atomic_size_t next, done;
    atomic_int stop;
} many_job;

static void worker_free(many_worker *w, const brdffit_allocator *a)
{
    if (w->fit != NULL) bf_free(a, w->fit->batch_work);
    brdffit_fit_destroy(w->fit);
    bf_free(a, w->values);
}

/* Copy every option of the prototype but the thread count and callback. */
static void copy_options(brdffit_fit *dst, const brdffit_fit *src)
{
    dst->pipeline = src->pipeline;
    dst->cap = src->cap;
    dst->weighting = src->weighting;
    dst->clearcoat = src->clearcoat;
    dst->threads = 1;
    dst->max_iterations = src->max_iterations;
    dst->objective = src->objective;
    dst->plausible = src->plausible;
    dst->sandwich = src->sandwich;
    dst->damping = src->damping;
    memcpy(dst->start, src->start, src->n_vec * sizeof *src->start);
    memcpy(dst->fixed, src->fixed, brdffit_model_param_count(src->model));
}

static brdffit_status worker_init(many_worker *w, const brdffit_fit *proto, size_t per_item)
{
    const brdffit_allocator *a = &proto->alloc;
    /* the view's values (grid_internal.h), then the mask bytes: one block;
     * zero until an item's values are set (the batch's shared state reads
     * none) */
    w->values = bf_calloc(a, per_item, BF_GRID_VIEW_BYTES + 1);
    if (w->values == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    w->mask = (unsigned char *)w->values + per_item * BF_GRID_VIEW_BYTES;
    bf_grid_view_init(&w->view, proto->grid, w->values);
    BF_RETURN_IF_ERROR(brdffit_fit_create(&w->fit, &w->view, proto->model, a, NULL));
    copy_options(w->fit, proto);
    return BRDFFIT_OK;
}

static void set_nan(double *p, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) p[k] = NAN;
}

/* Item i's outputs: from the private fit after a success, else empty. */
static void write_item(const many_job *job, const brdffit_fit *fit, size_t i,
                       brdffit_status status)
{
    brdffit_many_out *o = job->out;
    size_t nv = job->proto->n_vec;
    int ok = status == BRDFFIT_OK;
    if (o->status) o->status[i] = status;
    if (o->params && !(ok && brdffit_fit_params(fit, o->params + i * nv) == BRDFFIT_OK))
        set_nan(o->params + i * nv, nv);
    if (o->std_errors && !(ok && brdffit_fit_std_errors(fit, o->std_errors + i * nv) == 0))
        set_nan(o->std_errors + i * nv, nv);
    if (o->cost && !(ok && brdffit_fit_error(fit, BRDFFIT_METRIC_COST, BRDFFIT_ALL_CHANNELS,
                                             o->cost + i) == BRDFFIT_OK))
        o->cost[i] = NAN;
    if (o->rms && !(ok && brdffit_fit_error(fit, BRDFFIT_METRIC_RMS, BRDFFIT_ALL_CHANNELS,
                                            o->rms + i) == BRDFFIT_OK))
        o->rms[i] = NAN;
    if (o->ngan && !(ok && brdffit_fit_error(fit, BRDFFIT_METRIC_NGAN, BRDFFIT_ALL_CHANNELS,
                                             o->ngan + i) == BRDFFIT_OK))
        o->ngan[i] = NAN;
    if (o->stop) o->stop[i] = ok ? brdffit_fit_stop_reason(fit) : BRDFFIT_STOP_NONE;
    if (o->iterations) o->iterations[i] = ok ? brdffit_fit_iterations(fit) : 0;
    if (o->warnings) o->warnings[i] = ok ? brdffit_fit_warnings(fit) : 0;
}

static void run_item(many_job *job, many_worker *w, size_t i)
{
    const unsigned char *miss = job->missing ? job->missing + i * job->per_item : NULL;
    brdffit_status st =
        bf_grid_view_set(&w->view, job->values + i * job->per_item, miss, w->mask, NULL);
    if (st == BRDFFIT_OK) st = brdffit_fit_run(w->fit);
    write_item(job, w->fit, i, st);
}

static int stopping(many_job *job)
{
    return atomic_load(&job->stop) || atomic_load(&job->proto->cancel);
}

/* On the calling thread: report when `step` more items are done. */
static void report(many_job *job, size_t done, int last)
{
    if (job->progress == NULL || done == job->reported) return;
    if (!last && done - job->reported < job->step) return;
    job->reported = done;
    if (job->progress(job->user, done, job->n_items) != 0) atomic_store(&job->stop, 1);
}

static void worker_task(void *arg, size_t t)
{
    many_job *job = arg;
    while (!stopping(job)) {
        size_t i = atomic_fetch_add(&job->next, 1), done;
        if (i >= job->n_items) break;
        run_item(job, &job->workers[t], i);
        done = atomic_fetch_add(&job->done, 1) + 1;
        if (t == 0) report(job, done, 0);
    }
}

static brdffit_status check_args(brdffit_fit *proto, size_t n_items, const double *values,
                                 const brdffit_many_out *out, size_t *per_item)
{
    size_t ns, nc, total;
    if (proto == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    if (proto->magic != BF_MAGIC_FIT) return BRDFFIT_E_BAD_HANDLE;
    proto->message[0] = '\0';
    if (!bf_grid_ok(proto->grid) || !bf_model_ok(proto->model))
        return bf_say(proto->message, BRDFFIT_E_BAD_HANDLE, "grid or model was destroyed");
    if (out == NULL || out->struct_size < BF_MANY_OUT_V1)
        return bf_say(proto->message, BRDFFIT_E_INVALID_ARGUMENT,
                      "out is NULL or its struct_size is below the first version's");
    if (values == NULL && n_items > 0)
        return bf_say(proto->message, BRDFFIT_E_INVALID_ARGUMENT, "values is NULL");
    ns = brdffit_grid_sample_count(proto->grid);
    nc = brdffit_grid_channel_count(proto->grid);
    if (!bf_mul_size(ns, nc, per_item) || !bf_mul_size(*per_item, n_items, &total) ||
        !bf_mul_size(total, sizeof(double), &total))
        return bf_say(proto->message, BRDFFIT_E_TOO_LARGE,
                      "%zu items of %zu samples x %zu channels are too many", n_items, ns, nc);
    return BRDFFIT_OK;
}

/* Run the items on `n` workers (the calling thread and n - 1 helpers). */
static void run_all(many_job *job, size_t n)
{
    bf_pool pool;
    size_t i, run;
    bf_pool_start(&pool, n - 1);
    bf_pool_run(&pool, worker_task, job, n);
    bf_pool_stop(&pool);
    run = atomic_load(&job->next);
    if (run > job->n_items) run = job->n_items;
    for (i = run; i < job->n_items; i++) write_item(job, NULL, i, BRDFFIT_E_NOT_READY);
    job->out->n_run = run;
    report(job, run, 1);
}

/* The workers, and what their items share, made on the first worker's
 * fit; each worker's fit reads it with a scratch of its own. */
static brdffit_status make_workers(many_job *job, size_t n)
{
    const brdffit_allocator *a = &job->proto->alloc;
    size_t t;
    job->workers = bf_calloc(a, n, sizeof *job->workers);
    if (job->workers == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    for (t = 0; t < n; t++)
        if (worker_init(&job->workers[t], job->proto, job->per_item) != BRDFFIT_OK)
            return BRDFFIT_E_OUT_OF_MEMORY;
    BF_RETURN_IF_ERROR(bf_batch_init(&job->batch, job->workers[0].fit));
    for (t = 0; t < n; t++) {
        brdffit_fit *fit = job->workers[t].fit;
        fit->batch = &job->batch;
        fit->no_errors = job->out->std_errors == NULL;
        if (job->batch.work_size == 0) continue;
        fit->batch_work = bf_calloc(a, job->batch.work_size, sizeof(double));
        if (fit->batch_work == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    }
    return BRDFFIT_OK;
}

static void free_workers(many_job *job, size_t n)
{
    size_t t;
    if (job->workers != NULL) {
        for (t = 0; t < n; t++) worker_free(&job->workers[t], &job->proto->alloc);
        bf_free(&job->proto->alloc, job->workers);
    }
    bf_batch_free(&job->batch, &job->proto->alloc);
}

brdffit_status brdffit_fit_many(brdffit_fit *prototype, size_t n_items, const double *values,
                                const unsigned char *missing, brdffit_many_out *out,
                                brdffit_many_progress_fn progress, void *user)
{
    many_job job;
    size_t n;
    brdffit_status st;
    memset(&job, 0, sizeof job);
    st = check_args(prototype, n_items, values, out, &job.per_item);
    if (st == BRDFFIT_OK && n_items > 0) {
        n = prototype->threads < n_items ? prototype->threads : n_items;
        job.proto = prototype, job.n_items = n_items, job.values = values;
        job.missing = missing, job.out = out, job.progress = progress, job.user = user;
        job.step = (n_items + BF_MANY_STEPS - 1) / BF_MANY_STEPS;
        atomic_init(&job.next, 0);
        atomic_init(&job.done, 0);
        atomic_init(&job.stop, 0);
        st = make_workers(&job, n);
        if (st == BRDFFIT_OK) run_all(&job, n);
        else bf_say(prototype->message, st, "out of memory for the batch's threads");
        free_workers(&job, n);
    } else if (st == BRDFFIT_OK) {
        out->n_run = 0;
    }
    if (prototype != NULL && prototype->magic == BF_MAGIC_FIT)
        atomic_store(&prototype->cancel, 0); /* the request is consumed */
    return st;
}
