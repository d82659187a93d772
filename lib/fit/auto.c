/* The auto pipeline: no start values. The global scan (scan.h) of the
 * profile cost (varpro.h) finds the best minima of the shape parameters;
 * each competing one is polished by Levenberg-Marquardt over every free
 * parameter and the best polish is the result. */
#include <math.h>
#include <string.h>

#include "core/core.h"
#include "fit/lobe_starts.h"
#include "fit/pipelines.h"
#include "fit/plausible.h"
#include "fit/profile_gn.h"
#include "fit/scan.h"

/* The best polish so far: its cost and its stage in the trace. */
typedef struct best_polish {
    double cost;
    size_t stage;
} best_polish;

/* Keep the LM run just made when it beats the best so far: its
 * parameters, standard errors, covariance (st->cov, of the same run) and
 * report, and the only polish the trace
 * keeps. `work` has 2 n doubles: the run's parameters and standard errors. */
static brdffit_status keep_if_best(bf_stage *st, best_polish *best, const double *work)
{
    bf_result *r = st->run->result;
    if (!(st->cost < best->cost)) {
        bf_trace_keep(&r->trace, st->traced, 0);
        return BRDFFIT_OK;
    }
    if (best->cost < HUGE_VAL) bf_trace_keep(&r->trace, best->stage, 0);
    best->cost = st->cost;
    best->stage = st->traced;
    memcpy(r->params, work, st->n * sizeof *work);
    memcpy(r->std_errors, work + st->n, st->n * sizeof *work);
    if (r->cov != NULL) memcpy(r->cov, st->cov, st->n * st->n * sizeof *r->cov);
    return bf_result_keep_report(r, st->opt, &st->run->fit->alloc);
}

/* Plausibility: the colours' bounds at the polished shape (work, n
 * doubles, then its standard errors), polished again from there while the
 * result breaks them, at most BF_REBOUNDS times (each run replaces the one
 * before in the trace); then clamped to them. */
#define BF_REBOUNDS 4
static brdffit_status rebound(bf_stage *st, double *work)
{
    double *start = work + 2 * st->n;
    int i;
    for (i = 0; i < BF_REBOUNDS && !st->run->cancelled; i++) {
        memcpy(st->p, work, st->n * sizeof *st->p);
        BF_RETURN_IF_ERROR(bf_plausible_bounds(st, 1));
        if (bf_plausible_within(st, work)) break;
        memcpy(start, work, st->n * sizeof *start);
        bf_trace_keep(&st->run->result->trace, st->traced, 0);
        BF_RETURN_IF_ERROR(bf_stage_lm(st, start, work, work + st->n));
    }
    if (i < BF_REBOUNDS || st->run->cancelled) return BRDFFIT_OK;
    /* still creeping over: the colours clamped to the bounds at the final
     * shape, a plausible point, and its cost */
    memcpy(st->p, work, st->n * sizeof *st->p);
    BF_RETURN_IF_ERROR(bf_plausible_bounds(st, 1));
    bf_plausible_clamp(st, work);
    memcpy(st->p, work, st->n * sizeof *st->p);
    BF_RETURN_IF_ERROR(bf_stage_pass(st, BF_PASS_COST));
    st->cost = st->acc[0];
    return BRDFFIT_OK;
}

/* One polish: LM over every free parameter from start (n values, not
 * work), labelled `label`; its colours brought within the bounds at its
 * own shape, kept when best. `work` has 2 n doubles. */
static brdffit_status polish_from(bf_stage *st, const double *start, size_t label,
                                  best_polish *best, double *work)
{
    st->kind = BRDFFIT_STAGE_POLISH;
    st->label = label;
    BF_RETURN_IF_ERROR(bf_stage_lm(st, start, work, work + st->n));
    BF_RETURN_IF_ERROR(rebound(st, work));
    return keep_if_best(st, best, work);
}

/* Polish candidate i with LM over every free parameter; the best polish
 * so far is in the run's result. `work` has 3 n doubles. */
static brdffit_status polish(bf_stage *st, const bf_scan *sc, size_t i, best_polish *best,
                             double *work)
{
    double cost, *start = work + 2 * st->n;
    bf_scan_set_point(st, sc, sc->best[i].u);
    BF_RETURN_IF_ERROR(bf_plausible_bounds(st, 1)); /* every bound at the candidate's shape */
    BF_RETURN_IF_ERROR(bf_profile_point(st, NULL, 1, &cost));
    memcpy(start, st->p, st->n * sizeof *start);
    return polish_from(st, start, i, best, work);
}

/* Whether to polish once more from the model's start values: when the
 * best polish made no iteration, it left a scan point as it was (LM found
 * no descent from it, e.g. on a plateau where a colour grows without
 * bound), and the result must never be an unpolished scan point when a
 * descent exists; and always for a model affine in its colour (layout.h):
 * its scan runs over roughnesses whose lobe width goes as their square
 * (alpha = r^2), two points a decade of r are one of alpha, and under a
 * coat the coarse grid's best minima can all be the two lobes swapped. */
static int wants_repolish(const bf_stage *st)
{
    const bf_result *r = st->run->result;
    if (st->run->cancelled) return 0;
    if (st->pb.ly.offset) return 1;
    return r->iterations == 0 && r->stop == BRDFFIT_STOP_STALLED;
}

/* The polish from the model's start values (labelled with the number of
 * candidates), when wants_repolish(). */
static brdffit_status repolish(bf_stage *st, const bf_scan *sc, best_polish *best, double *work)
{
    if (!wants_repolish(st)) return BRDFFIT_OK;
    return polish_from(st, st->base, sc->n_best, best, work);
}

/* The polishes from two lobes' further starts (lobe_starts.h), labelled
 * with the number of candidates plus 1 and 2. `work` has 3 n doubles. */
static brdffit_status lobe_polish(bf_stage *st, const bf_scan *sc, best_polish *best, double *work)
{
    const brdffit_allocator *a = &st->run->fit->alloc;
    double *starts = bf_calloc(a, (BF_LOBE_STARTS + 1) * st->n, sizeof *starts);
    size_t n = 0, i;
    brdffit_status status;
    if (starts == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    memcpy(starts + BF_LOBE_STARTS * st->n, st->run->result->params, st->n * sizeof *starts);
    status = bf_lobe_starts(st, sc, starts + BF_LOBE_STARTS * st->n, best->cost, starts, &n);
    for (i = 0; i < n && status == BRDFFIT_OK && !st->run->cancelled; i++)
        status = polish_from(st, starts + i * st->n, sc->n_best + 1 + i, best, work);
    bf_free(a, starts);
    return status;
}

/* A coat of negligible weight leaves its roughness all but undetermined
 * and LM crawls along it, to its iteration limit, while the other
 * parameters are still short of their optimum: when the best polish has
 * such a coat (bf_coat_faint()), it is polished again with the coat's
 * roughness held, then once more with every parameter free from there
 * (the result's errors and convergence are a free run's). Labelled with
 * the number of candidates plus 1 + BF_LOBE_STARTS and plus 2 +
 * BF_LOBE_STARTS. `work` has 3 n doubles. */
static brdffit_status coat_settle(bf_stage *st, const bf_scan *sc, best_polish *best, double *work)
{
    double *start = work + 2 * st->n;
    size_t e = bf_coat_faint(st, st->run->result->params);
    brdffit_status status;
    if (e == st->n || st->run->cancelled) return BRDFFIT_OK;
    memcpy(start, st->run->result->params, st->n * sizeof *start);
    st->kind = BRDFFIT_STAGE_POLISH;
    st->label = sc->n_best + 1 + BF_LOBE_STARTS;
    st->fixed[e] = 1;
    status = bf_stage_lm(st, start, work, work + st->n);
    st->fixed[e] = 0;
    BF_RETURN_IF_ERROR(status);
    bf_trace_keep(&st->run->result->trace, st->traced, 0);
    if (st->run->cancelled) return BRDFFIT_OK;
    memcpy(start, work, st->n * sizeof *start);
    return polish_from(st, start, st->label + 1, best, work);
}

/* A cancel during the scan: the best point seen so far, unpolished. */
static brdffit_status cancelled_result(bf_stage *st, const bf_scan *sc)
{
    bf_result *r = st->run->result;
    double cost;
    if (sc->n_best == 0)
        memcpy(st->p, st->base, st->n * sizeof *st->p);
    else
        bf_scan_set_point(st, sc, sc->best[0].u);
    BF_RETURN_IF_ERROR(bf_plausible_bounds(st, 0));
    BF_RETURN_IF_ERROR(bf_profile_point(st, NULL, 1, &cost));
    memcpy(r->params, st->p, st->n * sizeof *r->params);
    memset(r->std_errors, 0, st->n * sizeof *r->std_errors);
    if (r->cov != NULL) memset(r->cov, 0, st->n * st->n * sizeof *r->cov);
    return BRDFFIT_OK;
}

/* Polish the best minimum and every other one whose scan cost is within a
 * factor 2 of it (the profile cost comes from normal equations and can
 * mislead by rounding when minima are close), every one kept for a model
 * affine in its colour (its coarse scan: wants_repolish()). Competing minima of one
 * shape parameter are refined first; a single one needs no refinement: LM
 * converges from anywhere in its basin. */
static brdffit_status polish_all(bf_stage *st, bf_scan *sc)
{
    const brdffit_allocator *a = &st->run->fit->alloc;
    size_t n_polish = 1, i;
    best_polish best = {HUGE_VAL, 0};
    double *work;
    brdffit_status status = BRDFFIT_OK;
    while (n_polish < sc->n_best &&
           (st->pb.ly.offset || sc->best[n_polish].cost <= 2.0 * sc->best[0].cost))
        n_polish++;
    if (sc->nd == 1 && n_polish > 1) BF_RETURN_IF_ERROR(bf_scan_refine(st, sc, n_polish));
    if (st->run->cancelled) return cancelled_result(st, sc);
    work = bf_calloc(a, 3 * st->n, sizeof *work);
    if (work == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    for (i = 0; i < n_polish && status == BRDFFIT_OK && !st->run->cancelled; i++)
        status = polish(st, sc, i, &best, work);
    if (status == BRDFFIT_OK && best.cost < HUGE_VAL) status = repolish(st, sc, &best, work);
    if (status == BRDFFIT_OK && best.cost < HUGE_VAL) status = lobe_polish(st, sc, &best, work);
    if (status == BRDFFIT_OK && best.cost < HUGE_VAL) status = coat_settle(st, sc, &best, work);
    if (status == BRDFFIT_OK && !(best.cost < HUGE_VAL))
        status = BRDFFIT_E_NOT_READY; /* cancelled before any polish */
    bf_free(a, work);
    return status;
}

/* Why an auto fit failed, in the run's message. */
static brdffit_status auto_fail(bf_stage *st, brdffit_status status)
{
    if (status == BRDFFIT_E_OUT_OF_MEMORY && st->status == BRDFFIT_OK) return status;
    return bf_stage_fail(st, status, "auto fit");
}

/* Variable projection solves at most BF_LSQ_MAX linear parameters. */
static brdffit_status check_projectable(bf_run *run)
{
    bf_layout ly;
    bf_layout_init(&ly, run->fit->model, run->fit->nc);
    if (bf_layout_projectable(&ly)) return BRDFFIT_OK;
    return bf_say(run->result->message, BRDFFIT_E_UNSUPPORTED,
                  "the auto pipeline solves at most %d linear parameters exactly; model '%s' "
                  "has %zu (use the joint or two-stage pipeline)",
                  BF_LSQ_MAX, brdffit_model_name(run->fit->model), ly.n_linear);
}

brdffit_status bf_pipeline_auto(bf_run *run)
{
    bf_stage st;
    bf_scan sc;
    brdffit_status status = check_projectable(run);
    if (status != BRDFFIT_OK) return status;
    status = bf_stage_init(&st, run, run->fit->nc, BF_SOURCE_CHANNELS, 0, 0);
    if (status != BRDFFIT_OK) return status;
    status = bf_scan_run(&st, &sc);
    if (status == BRDFFIT_OK) status = polish_all(&st, &sc);
    if (status == BRDFFIT_OK && run->result->stop == BRDFFIT_STOP_NONE)
        status = bf_result_keep_report(run->result, NULL, &run->fit->alloc); /* no polish */
    if (status != BRDFFIT_OK) status = auto_fail(&st, status);
    bf_stage_free(&st);
    return status;
}
