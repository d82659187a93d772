/* The record of a run's stages: see trace.h. */
#include "fit/trace.h"

#include <string.h>

#include "core/core.h"

void bf_trace_free(bf_trace *t, const brdffit_allocator *a)
{
    bf_free(a, t->stages);
    bf_free(a, t->entries);
    memset(t, 0, sizeof *t);
}

/* Room for `more` items after `n` in *buf (capacity *cap, items of
 * `size` bytes), growing by doubling. */
static brdffit_status reserve(void **buf, size_t *cap, size_t n, size_t more, size_t size,
                              const brdffit_allocator *a)
{
    size_t want = *cap > 0 ? *cap : 16;
    void *grown;
    if (n + more <= *cap) return BRDFFIT_OK;
    while (want < n + more) {
        if (want > ((size_t)-1 / 2) / size) return BRDFFIT_E_OUT_OF_MEMORY;
        want *= 2;
    }
    grown = bf_calloc(a, want, size);
    if (grown == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    if (n > 0) memcpy(grown, *buf, n * size);
    bf_free(a, *buf);
    *buf = grown;
    *cap = want;
    return BRDFFIT_OK;
}

static brdffit_status add_stage(bf_trace *t, const brdffit_allocator *a,
                                brdffit_fit_stage_kind kind, size_t index)
{
    brdffit_fit_stage *s;
    void *buf = t->stages;
    brdffit_status status = reserve(&buf, &t->cap_stages, t->n_stages, 1, sizeof *s, a);
    t->stages = buf;
    if (status != BRDFFIT_OK) return status;
    s = &t->stages[t->n_stages++];
    memset(s, 0, sizeof *s);
    s->kind = kind;
    s->index = index;
    s->first = t->n_entries;
    s->stop = BRDFFIT_STOP_NONE;
    return BRDFFIT_OK;
}

static brdffit_status reserve_entries(bf_trace *t, const brdffit_allocator *a, size_t more)
{
    void *buf = t->entries;
    brdffit_status status =
        reserve(&buf, &t->cap_entries, t->n_entries, more, sizeof(bf_trace_entry), a);
    t->entries = buf;
    return status;
}

brdffit_status bf_trace_scan(bf_trace *t, const brdffit_allocator *a, double cost)
{
    brdffit_fit_stage *s;
    bf_trace_entry *e;
    if (t->n_stages == 0 || t->stages[t->n_stages - 1].kind != BRDFFIT_STAGE_SCAN)
        BF_RETURN_IF_ERROR(add_stage(t, a, BRDFFIT_STAGE_SCAN, 0));
    BF_RETURN_IF_ERROR(reserve_entries(t, a, 1));
    s = &t->stages[t->n_stages - 1];
    e = &t->entries[t->n_entries];
    if (s->length > 0 && e[-1].cost < cost) cost = e[-1].cost;
    e->cost = cost;
    e->lambda = 0.0;
    e->stage = t->n_stages - 1;
    t->n_entries++;
    s->length++;
    s->evaluations++;
    return BRDFFIT_OK;
}

brdffit_status bf_trace_lm(bf_trace *t, const brdffit_allocator *a, brdffit_fit_stage_kind kind,
                           size_t index, const brdffit_optimizer *opt, size_t *stage)
{
    size_t n = brdffit_optimizer_history(opt, NULL, NULL), i;
    brdffit_fit_stage *s;
    double *cost, *lambda;
    BF_RETURN_IF_ERROR(reserve_entries(t, a, n));
    cost = bf_calloc(a, 2 * n + 1, sizeof *cost);
    if (cost == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    if (add_stage(t, a, kind, index) != BRDFFIT_OK) {
        bf_free(a, cost);
        return BRDFFIT_E_OUT_OF_MEMORY;
    }
    lambda = cost + n;
    brdffit_optimizer_history(opt, cost, lambda);
    for (i = 0; i < n; i++) {
        bf_trace_entry *e = &t->entries[t->n_entries++];
        e->cost = cost[i];
        e->lambda = lambda[i];
        e->stage = t->n_stages - 1;
    }
    bf_free(a, cost);
    s = &t->stages[t->n_stages - 1];
    s->length = n;
    s->stop = brdffit_optimizer_stop_reason(opt);
    s->iterations = brdffit_optimizer_iterations(opt);
    s->evaluations = brdffit_optimizer_evaluations(opt);
    s->converged = brdffit_optimizer_converged(opt);
    s->kept = 1;
    *stage = t->n_stages - 1;
    return BRDFFIT_OK;
}

void bf_trace_keep(bf_trace *t, size_t stage, int kept)
{
    if (stage < t->n_stages) t->stages[stage].kept = kept != 0;
}

int bf_trace_converged(const bf_trace *t)
{
    size_t i, kept = 0;
    for (i = 0; i < t->n_stages; i++) {
        const brdffit_fit_stage *s = &t->stages[i];
        if (s->kind == BRDFFIT_STAGE_SCAN || !s->kept) continue;
        if (!s->converged) return 0;
        kept++;
    }
    return kept > 0;
}
