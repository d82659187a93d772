/* bench_core: the inner loop. For the default grid (19 x 37 x 36 samples,
 * 3 channels) at caps 75 and 90 degrees and every built-in model:
 *   value     brdffit_model_eval_grid() without Jacobian over the active samples
 *   val+jac   brdffit_model_eval_grid() with Jacobian (the public vtable path)
 *   cost      bf_pass(BF_PASS_COST)
 *   normal    bf_pass(BF_PASS_NORMAL): the fused normal-equation pass of every LM step
 *   varpro    bf_pass(BF_PASS_VARPRO): the pass of the auto pipeline's scan
 *   naive     the naive reference of naive.c (same accumulator as normal)
 * Rows are active samples x channels; figures are ns per row (median).
 * Then, for ashikhmin-shirley at cap 90, in the same run: the normal pass
 * with the best version of the fused loop this CPU runs and with AVX2 at
 * most, the probe-like minimal loop of probe.c likewise, and the naive
 * pass. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "datasets.h"
#include "fit/pass.h"
#include "grid/grid_internal.h"
#include "harness.h"
#include "naive.h"
#include "probe.h"

#define DEG (3.14159265358979323846 / 180.0)
#define MAX_BLOCKS 64
#define CAP_TOL 1e-9

typedef enum measure_kind {
    K_VALUE,
    K_VALUE_JAC,
    K_COST,
    K_NORMAL,
    K_VARPRO,
    K_NAIVE_VALUE,
    K_NAIVE_JAC,
    K_NAIVE,
    K_COUNT
} measure_kind;

static const char *const kind_names[K_COUNT] = {"value",           "value_jac",   "cost_pass",
                                                "normal_pass",     "varpro_pass", "naive_value",
                                                "naive_value_jac", "naive_normal"};

/* The naive counterpart of each library measurement (K_COUNT: none). */
static const measure_kind naive_of[K_COUNT] = {K_NAIVE_VALUE, K_NAIVE_JAC, K_COUNT, K_NAIVE,
                                               K_COUNT,       K_COUNT,     K_COUNT, K_COUNT};

typedef struct block {
    size_t first, count;
} block;

typedef struct core_case {
    const brdffit_grid *grid;
    brdffit_model *model;
    const naive_model *naive;
    size_t nc, n_params, n_vec;
    double cap;
    double *params;
    block blocks[MAX_BLOCKS];
    size_t n_blocks, active, rows, max_block;
    double *values, *jac;
    bh_counter counter;
    brdffit_allocator alloc;
    bf_weight_plan plan;
    bf_problem pb;
    size_t *vindex;
    double *acc, *work;
    naive_data nd;
    double *nd_store, *nacc, *nrow, *nvalues, *njac;
    brdffit_error err;
} core_case;

/* ---- set-up ------------------------------------------------------------------ */

static size_t axis_active(const double *x, size_t n, double cap)
{
    size_t i = 0;
    while (i < n && x[i] <= cap + CAP_TOL) i++;
    return i;
}

/* Contiguous runs of active samples of the regular grid. */
static int find_blocks(core_case *cc)
{
    const double *ti, *to, *po;
    size_t n_ti, n_to, n_po, a_ti, a_to, i;
    brdffit_grid_axis(cc->grid, BRDFFIT_AXIS_THETA_I, &ti, &n_ti);
    brdffit_grid_axis(cc->grid, BRDFFIT_AXIS_THETA_O, &to, &n_to);
    brdffit_grid_axis(cc->grid, BRDFFIT_AXIS_PHI_O, &po, &n_po);
    a_ti = axis_active(ti, n_ti, cc->cap);
    a_to = axis_active(to, n_to, cc->cap);
    if (a_to == n_to) { /* whole theta_i blocks: one run */
        cc->blocks[0].first = 0;
        cc->blocks[0].count = a_ti * n_to * n_po;
        cc->n_blocks = 1;
    } else {
        if (a_ti > MAX_BLOCKS) return 0;
        for (i = 0; i < a_ti; i++) {
            cc->blocks[i].first = i * n_to * n_po;
            cc->blocks[i].count = a_to * n_po;
        }
        cc->n_blocks = a_ti;
    }
    cc->active = 0;
    cc->max_block = 0;
    for (i = 0; i < cc->n_blocks; i++) {
        cc->active += cc->blocks[i].count;
        if (cc->blocks[i].count > cc->max_block) cc->max_block = cc->blocks[i].count;
    }
    cc->rows = cc->active * cc->nc;
    return cc->active == brdffit_grid_active_count(cc->grid, cc->cap);
}

static void *xmalloc(size_t n, size_t size)
{
    return calloc(n ? n : 1, size);
}

static brdffit_status setup_problem(core_case *cc)
{
    size_t n_acc;
    bf_problem *pb = &cc->pb;
    BH_TRY(bf_weight_plan_init(&cc->plan, cc->grid, cc->cap, BRDFFIT_WEIGHT_DEFAULT, &cc->alloc,
                               &cc->err));
    memset(pb, 0, sizeof *pb);
    pb->grid = cc->grid;
    pb->model = cc->model;
    pb->plan = &cc->plan;
    pb->plan_sa = &cc->plan;
    pb->nc = cc->nc;
    pb->source = BF_SOURCE_CHANNELS;
    pb->objective = BRDFFIT_OBJECTIVE_SQUARES; /* the passes of the squares cost */
    pb->threads = 1;
    bf_layout_init(&pb->ly, cc->model, cc->nc);
    bf_layout_entries(&pb->ly, cc->model, cc->vindex, NULL);
    pb->vindex = cc->vindex;
    bf_pass_prepare(pb);
    n_acc = bf_pass_acc_size(pb, BF_PASS_NORMAL);
    if (bf_pass_acc_size(pb, BF_PASS_VARPRO) > n_acc) n_acc = bf_pass_acc_size(pb, BF_PASS_VARPRO);
    cc->acc = xmalloc(n_acc, sizeof(double));
    cc->work = xmalloc(bf_pass_work_size(pb), sizeof(double));
    if (cc->acc == NULL || cc->work == NULL) return BRDFFIT_E_OUT_OF_MEMORY;
    pb->work = cc->work;
    return BRDFFIT_OK;
}

/* The naive pass's inputs: angles, weights and values of the active samples. */
static brdffit_status setup_naive(core_case *cc)
{
    size_t n = cc->active, nc = cc->nc, b, s, c, t = 0;
    double *w = xmalloc(brdffit_grid_sample_count(cc->grid), sizeof *w), *st;
    brdffit_status status = BRDFFIT_E_OUT_OF_MEMORY;
    cc->nd_store = xmalloc(n * (5 + nc), sizeof(double));
    if (w == NULL || cc->nd_store == NULL) goto done;
    status = brdffit_grid_weights(cc->grid, cc->cap, BRDFFIT_WEIGHT_DEFAULT, w, &cc->err);
    if (status != BRDFFIT_OK) goto done;
    st = cc->nd_store;
    for (b = 0; b < cc->n_blocks; b++)
        for (s = cc->blocks[b].first; s < cc->blocks[b].first + cc->blocks[b].count; s++, t++) {
            brdffit_grid_sample_angles(cc->grid, s, &st[t], &st[n + t], &st[2 * n + t],
                                       &st[3 * n + t]);
            st[4 * n + t] = w[s];
            for (c = 0; c < nc; c++) {
                const double *vals;
                brdffit_grid_values(cc->grid, c, &vals);
                st[(5 + c) * n + t] = vals[s];
            }
        }
    cc->nd.n = n;
    cc->nd.nc = nc;
    cc->nd.theta_i = st, cc->nd.phi_i = st + n, cc->nd.theta_o = st + 2 * n;
    cc->nd.phi_o = st + 3 * n, cc->nd.weight = st + 4 * n, cc->nd.meas = st + 5 * n;
    cc->nvalues = xmalloc(nc * n, sizeof(double));
    cc->njac = xmalloc(nc * n * cc->n_vec, sizeof(double));
    if (cc->nvalues == NULL || cc->njac == NULL) status = BRDFFIT_E_OUT_OF_MEMORY;
done:
    free(w);
    return status;
}

static void case_free(core_case *cc)
{
    if (cc->plan.grid != NULL) bf_weight_plan_free(&cc->plan, &cc->alloc);
    brdffit_model_destroy(cc->model);
    free(cc->params);
    free(cc->values);
    free(cc->jac);
    free(cc->vindex);
    free(cc->acc);
    free(cc->work);
    free(cc->nd_store);
    free(cc->nacc);
    free(cc->nrow);
    free(cc->nvalues);
    free(cc->njac);
    memset(cc, 0, sizeof *cc);
}

static brdffit_status alloc_buffers(core_case *cc)
{
    size_t acc = 1 + cc->n_vec + cc->n_vec * cc->n_vec;
    cc->params = xmalloc(cc->n_vec, sizeof(double));
    cc->values = xmalloc(cc->nc * cc->max_block, sizeof(double));
    cc->jac = xmalloc(cc->n_params * cc->nc * cc->max_block, sizeof(double));
    cc->vindex = xmalloc(cc->n_params * cc->nc, sizeof(size_t));
    cc->nacc = xmalloc(acc, sizeof(double));
    cc->nrow = xmalloc(cc->n_vec, sizeof(double));
    if (!cc->params || !cc->values || !cc->jac || !cc->vindex || !cc->nacc || !cc->nrow)
        return BRDFFIT_E_OUT_OF_MEMORY;
    return BRDFFIT_OK;
}

static brdffit_status case_init(core_case *cc, const brdffit_grid *grid, const char *name,
                                double cap)
{
    memset(cc, 0, sizeof *cc);
    cc->grid = grid;
    cc->cap = cap;
    cc->nc = brdffit_grid_channel_count(grid);
    cc->alloc = bh_counter_allocator(&cc->counter);
    bh_counter_init(&cc->counter);
    BH_TRY(brdffit_model_create(&cc->model, name, NULL, &cc->err));
    cc->naive = naive_find(name);
    cc->n_params = brdffit_model_param_count(cc->model);
    cc->n_vec = brdffit_model_vector_size(cc->model, cc->nc);
    if (!find_blocks(cc))
        return bh_error(&cc->err, "active samples do not match brdffit_grid_active_count()");
    BH_TRY(alloc_buffers(cc));
    BH_TRY(brdffit_model_default_params(cc->model, cc->nc, cc->params));
    BH_TRY(setup_problem(cc));
    return setup_naive(cc);
}

/* ---- the runs ----------------------------------------------------------------- */

static int eval_blocks(core_case *cc, double *jac)
{
    size_t b;
    for (b = 0; b < cc->n_blocks; b++)
        if (brdffit_model_eval_grid(cc->model, cc->grid, cc->blocks[b].first, cc->blocks[b].count,
                                    cc->params, cc->values, jac, &cc->err) != BRDFFIT_OK)
            return 1;
    return 0;
}

static int run_value(void *ctx)
{
    return eval_blocks(ctx, NULL);
}

static int run_value_jac(void *ctx)
{
    core_case *cc = ctx;
    return eval_blocks(cc, cc->jac);
}

static int run_pass(core_case *cc, bf_pass_kind kind)
{
    return bf_pass(&cc->pb, kind, cc->params, cc->acc, &cc->err) != BRDFFIT_OK;
}

static int run_cost(void *ctx)
{
    return run_pass(ctx, BF_PASS_COST);
}

static int run_normal(void *ctx)
{
    return run_pass(ctx, BF_PASS_NORMAL);
}

static int run_varpro(void *ctx)
{
    return run_pass(ctx, BF_PASS_VARPRO);
}

static int run_naive_value(void *ctx)
{
    core_case *cc = ctx;
    naive_value_pass(cc->naive, &cc->nd, cc->params, cc->n_vec, cc->nvalues);
    return 0;
}

static int run_naive_jac(void *ctx)
{
    core_case *cc = ctx;
    naive_jacobian_pass(cc->naive, &cc->nd, cc->params, cc->n_vec, cc->nvalues, cc->njac);
    return 0;
}

static int run_naive(void *ctx)
{
    core_case *cc = ctx;
    naive_normal_pass(cc->naive, &cc->nd, cc->params, cc->n_vec, cc->nacc, cc->nrow);
    return 0;
}

static const bh_run_fn runs[K_COUNT] = {run_value,  run_value_jac,   run_cost,      run_normal,
                                        run_varpro, run_naive_value, run_naive_jac, run_naive};

static int is_naive(measure_kind k)
{
    return k == K_NAIVE_VALUE || k == K_NAIVE_JAC || k == K_NAIVE;
}

/* ---- the check: naive and fused accumulators agree --------------------------------- */

/* max |a - b| / max |b| over n entries. */
static double block_error(const double *a, const double *b, size_t n)
{
    double diff = 0.0, scale = 0.0;
    size_t i;
    for (i = 0; i < n; i++) {
        diff = fmax(diff, fabs(a[i] - b[i]));
        scale = fmax(scale, fabs(b[i]));
    }
    return scale > 0.0 ? diff / scale : diff;
}

/* Largest relative difference of the cost, J^T r and J^T J blocks. */
static double naive_error(core_case *cc)
{
    size_t n = cc->n_vec;
    double e;
    if (run_normal(cc) != 0) return HUGE_VAL;
    run_naive(cc);
    e = block_error(cc->nacc, cc->acc, 1);
    e = fmax(e, block_error(cc->nacc + 1, cc->acc + 1, n));
    return fmax(e, block_error(cc->nacc + 1 + n, cc->acc + 1 + n, n * n));
}

/* ---- measuring and reporting ---------------------------------------------------------- */

typedef struct figures {
    bh_stats st[K_COUNT];
    int have[K_COUNT];
    double check; /* naive_error(), NaN without a naive model */
} figures;

static int measure_case(const bh_options *opt, core_case *cc, figures *f)
{
    size_t k, warm = opt->smoke ? 0 : 2;
    memset(f, 0, sizeof *f);
    f->check = NAN;
    for (k = 0; k < K_COUNT; k++) {
        size_t reps = bh_repeats(opt, is_naive((measure_kind)k) ? 11 : 21);
        if (is_naive((measure_kind)k) && cc->naive == NULL) continue;
        if (k == K_VARPRO && cc->pb.ly.n_linear == 0) continue;
        if (bh_measure(runs[k], cc, warm, reps, &f->st[k]) != 0) return 0;
        f->have[k] = 1;
    }
    if (cc->naive != NULL) f->check = naive_error(cc);
    return 1;
}

static double per_row(const figures *f, measure_kind k, size_t rows)
{
    return f->have[k] ? f->st[k].median_ns / (double)rows : NAN;
}

/* Naive time over library time for measurement k; NaN without a naive one. */
static double naive_ratio(const figures *f, measure_kind k)
{
    measure_kind n = naive_of[k];
    if (n == K_COUNT || !f->have[n] || !f->have[k]) return NAN;
    return f->st[n].median_ns / f->st[k].median_ns;
}

/* The same from the CPU times, which other work on the machine disturbs less. */
static double naive_ratio_cpu(const figures *f, measure_kind k)
{
    measure_kind n = naive_of[k];
    if (n == K_COUNT || !f->have[n] || !f->have[k]) return NAN;
    return f->st[n].median_cpu_ns / f->st[k].median_cpu_ns;
}

static void json_case(bh_output *out, const core_case *cc, const figures *f)
{
    size_t k;
    for (k = 0; k < K_COUNT; k++) {
        bh_record r;
        char name[160];
        if (!f->have[k]) continue;
        snprintf(name, sizeof name, "%s/cap%.0f/%s", brdffit_model_name(cc->model), cc->cap / DEG,
                 kind_names[k]);
        bh_rec_begin(&r, out, name);
        bh_rec_str(&r, "model", brdffit_model_name(cc->model));
        bh_rec_str(&r, "kind", kind_names[k]);
        bh_rec_num(&r, "cap_deg", cc->cap / DEG);
        bh_rec_int(&r, "active_samples", cc->active);
        bh_rec_int(&r, "params", cc->n_vec);
        bh_rec_stats(&r, &f->st[k], cc->rows);
        if (naive_of[k] != K_COUNT) {
            bh_rec_num(&r, "ratio_vs_naive", naive_ratio(f, k));
            bh_rec_num(&r, "ratio_vs_naive_cpu", naive_ratio_cpu(f, k));
        }
        if (k == K_NAIVE) bh_rec_num(&r, "max_rel_diff_vs_normal", f->check);
        bh_rec_end(&r, out);
    }
}

static void table_head(bh_output *out)
{
    bh_table(out, "ns per residual row (median); rows = active samples x 3 channels; "
                  "n.* = naive reference; x* = naive / library\n");
    bh_table(out, "%-25s %3s %5s %7s %7s %7s %7s %7s %7s %7s %7s %6s %6s %6s %7s\n", "model", "cap",
             "rows", "value", "n.value", "val+jac", "n.jac", "cost", "normal", "n.norm", "varpro",
             "x val", "x jac", "x norm", "check");
}

static void table_case(bh_output *out, const core_case *cc, const figures *f)
{
    char check[32] = "-";
    size_t r = cc->rows;
    if (!isnan(f->check)) snprintf(check, sizeof check, "%.0e", f->check);
    bh_table(out,
             "%-25s %3.0f %5zu %7.2f %7.1f %7.2f %7.1f %7.2f %7.2f %7.1f %7.2f %6.1f %6.1f %6.1f "
             "%7s\n",
             brdffit_model_name(cc->model), cc->cap / DEG, r, per_row(f, K_VALUE, r),
             per_row(f, K_NAIVE_VALUE, r), per_row(f, K_VALUE_JAC, r), per_row(f, K_NAIVE_JAC, r),
             per_row(f, K_COST, r), per_row(f, K_NORMAL, r), per_row(f, K_NAIVE, r),
             per_row(f, K_VARPRO, r), naive_ratio(f, K_VALUE), naive_ratio(f, K_VALUE_JAC),
             naive_ratio(f, K_NORMAL), check);
}

/* What the targets need: ashikhmin-shirley at cap 90. */
typedef struct target_figures {
    double ns_per_row, ratio, ratio_cpu, avx2_ns_per_row;
    size_t rows;
    int avx512;
} target_figures;

static int run_case(bh_output *out, const brdffit_grid *grid, const char *name, double cap,
                    target_figures *tf)
{
    core_case cc;
    figures f;
    brdffit_status st;
    char label[128];
    int ok;
    snprintf(label, sizeof label, "%s/cap%.0f", name, cap / DEG);
    if (!bh_selected(out->opt, label)) return 1;
    st = case_init(&cc, grid, name, cap);
    ok = st == BRDFFIT_OK && measure_case(out->opt, &cc, &f);
    if (!ok) {
        bh_fail(out, "%s at cap %.0f: %s", name, cap / DEG, cc.err.message);
    } else {
        table_case(out, &cc, &f);
        json_case(out, &cc, &f);
        /* the fused loop reads its inputs in single precision
         * (docs/benchmarks.md): agreement to 1e-6, not to rounding */
        if (!isnan(f.check) && !(f.check <= 1e-6))
            bh_fail(out, "%s at cap %.0f: naive and fused normal equations differ by %.3g", name,
                    cap / DEG, f.check);
        if (strcmp(name, "ashikhmin-shirley") == 0 && cap > 89.0 * DEG) {
            tf->ns_per_row = per_row(&f, K_NORMAL, cc.rows);
            tf->ratio = naive_ratio(&f, K_NORMAL);
            tf->ratio_cpu = naive_ratio_cpu(&f, K_NORMAL);
            tf->rows = cc.rows;
        }
    }
    case_free(&cc);
    return ok;
}

/* ---- the fused pass against the probe loop, same run ----------------------------- */

typedef struct probe_ctx {
    core_case *cc;
    probe_data pd;
    int avx512;
    double sums[PROBE_SUMS];
} probe_ctx;

static int run_probe(void *ctx)
{
    probe_ctx *p = ctx;
    probe_normal(&p->pd, p->avx512, p->sums);
    return 0;
}

static void probe_line(bh_output *out, const char *what, const bh_stats *st, size_t rows,
                       double ref_ns)
{
    bh_record r;
    char name[96];
    bh_table(out, "%-44s %8.3f %8.3f %8.2f\n", what, st->median_ns / (double)rows,
             st->median_cpu_ns / (double)rows, ref_ns / st->median_ns);
    snprintf(name, sizeof name, "ashikhmin-shirley/cap90/%s", what);
    bh_rec_begin(&r, out, name);
    bh_rec_stats(&r, st, rows);
    bh_rec_num(&r, "ratio_vs_naive", ref_ns / st->median_ns);
    bh_rec_end(&r, out);
}

/* The normal pass with the best fused version and with AVX2 at most, the
 * probe with AVX-512 and AVX2, the naive pass: one run, same data. */
static int probe_section(bh_output *out, const brdffit_grid *grid, target_figures *tf)
{
    core_case cc;
    probe_ctx pc;
    bh_stats st[5];
    size_t first[MAX_BLOCKS], count[MAX_BLOCKS], b, reps = bh_repeats(out->opt, 21);
    size_t warm = out->opt->smoke ? 0 : 2;
    unsigned best;
    int ok = 0;
    memset(&pc, 0, sizeof pc);
    if (case_init(&cc, grid, "ashikhmin-shirley", 90.0 * DEG) != BRDFFIT_OK) goto done;
    for (b = 0; b < cc.n_blocks; b++) first[b] = cc.blocks[b].first, count[b] = cc.blocks[b].count;
    pc.cc = &cc;
    if (!probe_init(&pc.pd, grid, cc.cap, first, count, cc.n_blocks, cc.params, cc.vindex))
        goto done;
    best = cc.pb.isa;
    pc.avx512 = 1;
    if (bh_measure(run_normal, &cc, warm, reps, &st[0]) || bh_measure(run_probe, &pc, warm, reps,
                                                                      &st[2]))
        goto done;
    cc.pb.isa = best < BF_ISA_AVX2 ? best : BF_ISA_AVX2;
    pc.avx512 = 0;
    if (bh_measure(run_normal, &cc, warm, reps, &st[1]) || bh_measure(run_probe, &pc, warm, reps,
                                                                      &st[3]) ||
        bh_measure(run_naive, &cc, warm > 0, bh_repeats(out->opt, 5), &st[4]))
        goto done;
    bh_table(out, "\nashikhmin-shirley, cap 90, %zu rows, same run: ns per row (wall, cpu), "
                  "naive / this\n", cc.rows);
    probe_line(out, best == BF_ISA_AVX512 ? "fused_normal_avx512" : "fused_normal_best", &st[0],
               cc.rows, st[4].median_ns);
    probe_line(out, "fused_normal_avx2", &st[1], cc.rows, st[4].median_ns);
    probe_line(out, best == BF_ISA_AVX512 ? "probe_avx512" : "probe_best", &st[2], cc.rows,
               st[4].median_ns);
    probe_line(out, "probe_avx2", &st[3], cc.rows, st[4].median_ns);
    probe_line(out, "naive_normal", &st[4], cc.rows, st[4].median_ns);
    tf->ns_per_row = st[0].median_ns / (double)cc.rows;
    tf->avx2_ns_per_row = st[1].median_ns / (double)cc.rows;
    tf->avx512 = best == BF_ISA_AVX512;
    ok = 1;
done:
    if (!ok) bh_fail(out, "the probe section failed: %s", cc.err.message);
    probe_free(&pc.pd);
    case_free(&cc);
    return ok;
}

static void report_targets(bh_output *out, const target_figures *tf)
{
    char measured[64];
    bh_table(out, "\n");
    snprintf(measured, sizeof measured, "%.2f ns/row", tf->ns_per_row);
    bh_target(out, "fused NORMAL pass, ashikhmin-shirley, 75,924 rows (cap 90)", measured,
              "<= 1 ns/row", tf->ns_per_row <= 1.0);
    if (tf->avx512) {
        snprintf(measured, sizeof measured, "%.2f ns/row", tf->ns_per_row);
        bh_target(out, "fused NORMAL pass with AVX-512, ashikhmin-shirley (cap 90)", measured,
                  "<= 0.6 ns/row", tf->ns_per_row <= 0.6);
    }
    snprintf(measured, sizeof measured, "%.2f ns/row", tf->avx2_ns_per_row);
    bh_target(out, "fused NORMAL pass with AVX2, ashikhmin-shirley (cap 90)", measured,
              "<= 1 ns/row", tf->avx2_ns_per_row <= 1.0);
    snprintf(measured, sizeof measured, "%.1fx (cpu %.1fx)", tf->ratio, tf->ratio_cpu);
    bh_target(out, "fused NORMAL pass vs naive reference, ashikhmin-shirley", measured, ">= 30x",
              tf->ratio >= 30.0);
}

int main(int argc, char **argv)
{
    static const double caps[] = {75.0 * DEG, 90.0 * DEG};
    bh_options opt;
    bh_output out;
    brdffit_grid *grid = NULL;
    brdffit_error err;
    target_figures tf = {NAN, NAN, NAN, NAN, 0, 0};
    size_t m, c;
    int code;
    if (!bh_parse_args(argc, argv, "The inner loop: model evaluation and fused passes per row.",
                       &opt, &code))
        return code;
    if (!bh_output_open(&out, &opt, "inner loop on the default grid, data set P1")) return 1;
    if (bd_default_grid(&grid, BD_P1, BD_SEED, NULL, &err) != BRDFFIT_OK) {
        bh_fail(&out, "creating the grid: %s", err.message);
        return bh_output_close(&out);
    }
    table_head(&out);
    for (c = 0; c < 2; c++)
        for (m = 0; m < brdffit_model_builtin_count(); m++)
            run_case(&out, grid, brdffit_model_builtin_name(m), caps[c], &tf);
    if (opt.filter == NULL || bh_selected(&opt, "probe")) probe_section(&out, grid, &tf);
    if (opt.filter == NULL) report_targets(&out, &tf);
    brdffit_grid_destroy(grid);
    return bh_output_close(&out);
}
