/* libFuzzer harness for fitting (brdffit_fit_run): a small regular grid and
 * every fit option are decoded from the input, then fitted.
 *
 * Input layout (bytes past the end read as 0):
 *   model     built-in model index, mod the number of built-ins + 1; the
 *             last index is the harness's own lobe model (see lobe_eval)
 *   flags     bits 0-1 pipeline (3 = auto), 2-3 weighting flags, 4 two
 *             threads, 5 missing mask, 6 rerun with a failing allocation,
 *             7 own start values
 *   layout    bits 0-1 channels - 1, 2-3 damping policy, 4 raw doubles
 *   iters     maximum iterations 1 + iters % 20
 *   cap       255 = default, else cap / 254 * pi/2
 *   coat      < 128: no clear coat, else R0 = (coat - 128) / 128 * 0.99
 *   sizes     bits 0-1, 2-3, 4-5: number of theta_i, theta_o, phi_o values
 *             - 1; bit 6: every axis starts at 0; bit 7: every axis ends at
 *             its maximum (pi/2 or pi)
 *   axes      one byte per axis value: the gap to the previous one - 1
 *   values    per value one code byte (see decode_value), or with raw
 *             doubles 8 bytes taken as they are (negative ones mirrored,
 *             non-finite ones missing)
 *   missing   with the missing mask: one bit per value
 *   start     with own start values: one byte per vector entry, placed
 *             inside the entry's bounds
 *   fixed     bit k holds declared parameter k fixed (k < 8)
 *   seed      which allocation of the rerun fails
 *   cancel    with the lobe model: 0, or cancel the fit from inside the
 *             model at its cancel-th evaluation of each run (in the global
 *             scan, in an LM run or in the error figures)
 *
 * On success every parameter, standard error and error figure must be
 * finite and every parameter inside its bounds; failures must be one of
 * the documented statuses with a message; no allocation may leak; a run
 * whose allocation fails must say so exactly, and the same handle must
 * then reproduce the first result. A violation aborts. */
#include <float.h>
#include <stdint.h>

#include "fuzz_common.h"

#define MAX_AXIS 4
#define MAX_CHANNELS 4
#define MAX_SAMPLES (MAX_AXIS * MAX_AXIS * MAX_AXIS)
#define MAX_VALUES (MAX_SAMPLES * MAX_CHANNELS)
#define MAX_VECTOR 64

typedef struct reader {
    const unsigned char *data;
    size_t size, pos;
} reader;

static unsigned next(reader *r)
{
    return r->pos < r->size ? r->data[r->pos++] : 0u;
}

/* The options decoded from the input. */
typedef struct fit_case {
    size_t model, nc, n_axis[3], n_vec;
    unsigned pipeline, weighting, damping, max_iter;
    int threads2, has_missing, oom, own_start, raw;
    double cap, coat;
    double axis[3][MAX_AXIS];
    double values[MAX_VALUES];
    unsigned char missing[MAX_VALUES];
    unsigned char start_bytes[MAX_VECTOR];
    unsigned fixed;
    unsigned seed;
    unsigned cancel;
} fit_case;

/* ---- the lobe model: cd / pi + cs (n.h)^k, which can cancel its fit ---- */

typedef struct lobe_user {
    brdffit_fit *fit;
    unsigned cancel_at, evals;
} lobe_user;

static const brdffit_param_info lobe_params[] = {
    {"k", BRDFFIT_PARAM_LOG_SCALE, 1e-2, 1e5, 10.0},
    {"cd", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.2},
    {"cs", BRDFFIT_PARAM_PER_CHANNEL | BRDFFIT_PARAM_LINEAR, 0.0, HUGE_VAL, 0.2},
};

static brdffit_status lobe_eval(const brdffit_batch *b, const double *p, size_t nc, double *values,
                                double *jac, void *user)
{
    lobe_user *u = user;
    size_t n = b->n, s, c;
    if (++u->evals == u->cancel_at) brdffit_fit_cancel(u->fit);
    for (c = 0; c < nc; c++)
        for (s = 0; s < n; s++) {
            double lobe = exp(p[0] * b->log_nh[s]);
            values[c * n + s] = p[1 + c] / 3.14159265358979323846 + p[1 + nc + c] * lobe;
            if (jac == NULL) continue;
            jac[c * n + s] = p[1 + nc + c] * lobe * b->log_nh[s];
            jac[(nc + c) * n + s] = 1.0 / 3.14159265358979323846;
            jac[(2 * nc + c) * n + s] = lobe;
        }
    return BRDFFIT_OK;
}

static brdffit_status make_model(brdffit_model **out, size_t index, lobe_user *user,
                                 const brdffit_allocator *alloc)
{
    brdffit_model_def def = BRDFFIT_MODEL_DEF_INIT;
    if (index < brdffit_model_builtin_count())
        return brdffit_model_create(out, brdffit_model_builtin_name(index), alloc, NULL);
    def.name = "lobe";
    def.n_params = 3;
    def.params = lobe_params;
    def.eval = lobe_eval;
    def.user = user;
    return brdffit_model_create_custom(out, &def, alloc, NULL);
}

/* A value code: zero, tiny, denormal, huge, near DBL_MAX, or ordinary. */
static double decode_value(unsigned v)
{
    unsigned low = v & 31u;
    switch (v >> 5) {
    case 0: return 0.0;
    case 1: return ldexp(1.0 + low / 32.0, -1000);
    case 2: return ldexp((double)(low + 1), -1074);
    case 3: return ldexp(1.0 + low / 32.0, 1000);
    case 4: return DBL_MAX * (1.0 - low / 64.0);
    case 5: return low / 16.0;
    default: return ldexp(1.0 + (v & 7u) / 8.0, (int)((v >> 3) & 7u) - 4);
    }
}

static double raw_value(reader *r, unsigned char *missing)
{
    unsigned char b[8];
    double v;
    int k;
    for (k = 0; k < 8; k++) b[k] = (unsigned char)next(r);
    memcpy(&v, b, sizeof v);
    if (!isfinite(v)) {
        *missing = 1;
        return 0.0;
    }
    return fabs(v);
}

/* Strictly increasing axis values in [0, range]. */
static void decode_axis(reader *r, double *axis, size_t n, double range, unsigned style)
{
    double pos[MAX_AXIS], total;
    size_t k;
    for (k = 0; k < n; k++) {
        double gap = 1.0 + next(r);
        pos[k] = (k == 0 ? ((style & 1u) ? 0.0 : gap) : pos[k - 1] + gap);
    }
    total = (style & 2u) && pos[n - 1] > 0.0 ? pos[n - 1] : 256.0 * MAX_AXIS;
    for (k = 0; k < n; k++) axis[k] = range * (pos[k] / total);
    if (style & 2u) axis[n - 1] = range;
}

static void decode(reader *r, fit_case *fc)
{
    static const double range[3] = {1.5707963267948966, 1.5707963267948966, 3.14159265358979323846};
    unsigned flags, layout, cap, coat, sizes;
    size_t a, k, n_values;
    memset(fc, 0, sizeof *fc);
    fc->model = next(r) % (brdffit_model_builtin_count() + 1);
    flags = next(r);
    fc->pipeline = (flags & 3u) == 3u ? 0u : flags & 3u;
    fc->weighting = (flags >> 2) & 3u;
    fc->threads2 = (flags >> 4) & 1u;
    fc->has_missing = (flags >> 5) & 1u;
    fc->oom = (flags >> 6) & 1u;
    fc->own_start = (flags >> 7) & 1u;
    layout = next(r);
    fc->nc = 1 + (layout & 3u);
    fc->damping = (layout >> 2) & 3u;
    fc->raw = (layout >> 4) & 1u;
    fc->max_iter = 1 + next(r) % 20u;
    cap = next(r);
    fc->cap = cap == 255u ? BRDFFIT_DEFAULT_CAP : cap / 254.0 * 1.5707963267948966;
    coat = next(r);
    fc->coat = coat < 128u ? 0.0 : (coat - 128u) / 128.0 * 0.99;
    sizes = next(r);
    for (a = 0; a < 3; a++) {
        fc->n_axis[a] = 1 + ((sizes >> (2 * a)) & 3u);
        decode_axis(r, fc->axis[a], fc->n_axis[a], range[a], sizes >> 6);
    }
    n_values = fc->n_axis[0] * fc->n_axis[1] * fc->n_axis[2] * fc->nc;
    for (k = 0; k < n_values; k++)
        fc->values[k] = fc->raw ? raw_value(r, &fc->missing[k]) : decode_value(next(r));
    for (k = 0; fc->has_missing && k < n_values; k += 8) {
        unsigned bits = next(r), b;
        for (b = 0; b < 8 && k + b < n_values; b++)
            fc->missing[k + b] |= (unsigned char)((bits >> b) & 1u);
    }
    for (k = 0; fc->own_start && k < MAX_VECTOR; k++) fc->start_bytes[k] = (unsigned char)next(r);
    fc->fixed = next(r);
    fc->seed = next(r);
    fc->cancel = next(r);
}

/* A start value inside [lower, upper] from a byte. */
static double start_in_bounds(const brdffit_param_info *info, unsigned b)
{
    double t = b / 255.0, lo = info->lower, hi = info->upper, v;
    int logs = (info->flags & BRDFFIT_PARAM_LOG_SCALE) != 0;
    if (!isfinite(lo)) lo = -1e3;
    if (!isfinite(hi)) hi = logs ? lo * 1e6 : lo + 1e3;
    v = logs ? exp(log(lo) + t * (log(hi) - log(lo))) : lo + t * (hi - lo);
    return fmin(fmax(v, info->lower), info->upper);
}

static const brdffit_damping *policy(unsigned which)
{
    switch (which) {
    case 1: return brdffit_damping_thesis();
    case 2: return brdffit_damping_marquardt();
    default: return brdffit_damping_nielsen();
    }
}

static void configure(brdffit_fit *fit, const brdffit_model *model, const fit_case *fc)
{
    double start[MAX_VECTOR];
    size_t k, c;
    fuzz_require(brdffit_fit_set(fit, BRDFFIT_FIT_PIPELINE, fc->pipeline) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_set(fit, BRDFFIT_FIT_CAP, fc->cap) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_set(fit, BRDFFIT_FIT_WEIGHTING, fc->weighting) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_set(fit, BRDFFIT_FIT_CLEARCOAT, fc->coat) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_set(fit, BRDFFIT_FIT_THREADS, fc->threads2 ? 2 : 1) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_set(fit, BRDFFIT_FIT_MAX_ITERATIONS, fc->max_iter) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_set_damping(fit, policy(fc->damping)) == BRDFFIT_OK);
    for (k = 0; k < brdffit_model_param_count(model) && k < 8; k++)
        fuzz_require(brdffit_fit_set_fixed(fit, k, (fc->fixed >> k) & 1u) == BRDFFIT_OK);
    if (!fc->own_start) return;
    for (k = 0; k < brdffit_model_param_count(model); k++)
        for (c = 0; c < fc->nc; c++) {
            size_t e = brdffit_model_vector_index(model, k, c, fc->nc);
            start[e] = start_in_bounds(brdffit_model_param(model, k), fc->start_bytes[e]);
        }
    fuzz_require(brdffit_fit_set_start(fit, start) == BRDFFIT_OK);
}

/* What a successful run must satisfy. */
static void check_result(const brdffit_fit *fit, const brdffit_model *model, const fit_case *fc,
                         double *params)
{
    double se[MAX_VECTOR], v, rs, cd[MAX_CHANNELS], cs[MAX_CHANNELS];
    size_t k, c, m, n = brdffit_fit_param_count(fit), hist;
    fuzz_require(n == fc->n_vec);
    fuzz_require(brdffit_fit_params(fit, params) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_std_errors(fit, se) == BRDFFIT_OK);
    for (k = 0; k < brdffit_model_param_count(model); k++) {
        const brdffit_param_info *info = brdffit_model_param(model, k);
        for (c = 0; c < fc->nc; c++) {
            size_t e = brdffit_model_vector_index(model, k, c, fc->nc);
            fuzz_require(isfinite(params[e]));
            fuzz_require(params[e] >= info->lower && params[e] <= info->upper);
            /* HUGE_VAL: a parameter the data do not determine */
            fuzz_require((isfinite(se[e]) && se[e] >= 0.0) || se[e] == HUGE_VAL);
        }
    }
    for (m = 0; m <= BRDFFIT_METRIC_COST; m++) {
        fuzz_require(brdffit_fit_error(fit, (brdffit_fit_metric)m, BRDFFIT_ALL_CHANNELS, &v) ==
                     BRDFFIT_OK);
        fuzz_require(isfinite(v) && v >= 0.0);
        for (c = 0; c < fc->nc; c++) {
            fuzz_require(brdffit_fit_error(fit, (brdffit_fit_metric)m, c, &v) == BRDFFIT_OK);
            fuzz_require(isfinite(v) && v >= 0.0);
        }
    }
    fuzz_require(brdffit_fit_iterations(fit) <= fc->max_iter);
    fuzz_require((unsigned)brdffit_fit_stop_reason(fit) <= BRDFFIT_STOP_STALLED);
    hist = brdffit_fit_history(fit, NULL, NULL);
    fuzz_require(hist == 0 || hist == brdffit_fit_iterations(fit) + 1);
    if (brdffit_fit_shader(fit, &rs, cd, cs) == BRDFFIT_OK) {
        fuzz_require(isfinite(rs));
        for (c = 0; c < fc->nc; c++) fuzz_require(isfinite(cd[c]) && isfinite(cs[c]));
    }
}

static void check_failure(brdffit_status st, const brdffit_fit *fit)
{
    fuzz_require(st == BRDFFIT_E_NO_DATA || st == BRDFFIT_E_RANGE || st == BRDFFIT_E_NONFINITE ||
                 st == BRDFFIT_E_MODEL_FAILED || st == BRDFFIT_E_NUMERICAL);
    fuzz_require(brdffit_fit_message(fit)[0] != '\0');
    fuzz_require(brdffit_fit_params(fit, (double[MAX_VECTOR]){0}) == BRDFFIT_E_NOT_READY);
}

/* The rerun: one allocation of the run fails, then none on the same handle. */
static void rerun(brdffit_fit *fit, fuzz_alloc *fa, const fit_case *fc, lobe_user *lobe,
                  brdffit_status first, const double *params, size_t run_allocs)
{
    double again[MAX_VECTOR];
    brdffit_status st;
    fa->fail_at = fa->allocs + 1 + fc->seed % run_allocs;
    lobe->evals = 0;
    st = brdffit_fit_run(fit);
    fuzz_require(st == BRDFFIT_E_OUT_OF_MEMORY);
    fuzz_require(brdffit_fit_message(fit)[0] != '\0');
    fa->fail_at = 0;
    lobe->evals = 0;
    st = brdffit_fit_run(fit);
    fuzz_require(st == first);
    if (st != BRDFFIT_OK) return;
    fuzz_require(brdffit_fit_params(fit, again) == BRDFFIT_OK);
    fuzz_require(memcmp(again, params, fc->n_vec * sizeof *params) == 0);
}

static void fit_grid(const brdffit_grid *grid, fit_case *fc, fuzz_alloc *fa)
{
    brdffit_model *model = NULL;
    brdffit_fit *fit = NULL;
    brdffit_status st;
    double params[MAX_VECTOR];
    size_t before;
    lobe_user lobe = {NULL, fc->cancel, 0};
    fuzz_require(make_model(&model, fc->model, &lobe, &fa->hook) == BRDFFIT_OK);
    fuzz_require(brdffit_fit_create(&fit, grid, model, &fa->hook, NULL) == BRDFFIT_OK);
    lobe.fit = fit;
    fc->n_vec = brdffit_model_vector_size(model, fc->nc);
    fuzz_require(fc->n_vec > 0 && fc->n_vec <= MAX_VECTOR);
    configure(fit, model, fc);
    before = fa->allocs;
    st = brdffit_fit_run(fit);
    if (st == BRDFFIT_OK)
        check_result(fit, model, fc, params);
    else
        check_failure(st, fit);
    if (fc->oom && fa->allocs > before) rerun(fit, fa, fc, &lobe, st, params, fa->allocs - before);
    brdffit_fit_destroy(fit);
    brdffit_model_destroy(model);
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    reader r = {data, size, 0};
    fit_case fc;
    brdffit_axes axes;
    brdffit_grid *grid = NULL;
    brdffit_error err;
    fuzz_alloc fa;
    brdffit_status st;
    decode(&r, &fc);
    axes.theta_i = fc.axis[0], axes.n_theta_i = fc.n_axis[0];
    axes.theta_o = fc.axis[1], axes.n_theta_o = fc.n_axis[1];
    axes.phi_o = fc.axis[2], axes.n_phi_o = fc.n_axis[2];
    fuzz_alloc_init(&fa, 0);
    st = brdffit_grid_create_regular(&grid, &axes, fc.nc, fc.values,
                                     fc.has_missing || fc.raw ? fc.missing : NULL, &fa.hook, &err);
    if (st == BRDFFIT_OK) {
        fuzz_check_grid(grid);
        fit_grid(grid, &fc, &fa);
        brdffit_grid_destroy(grid);
    } else {
        fuzz_check_failure(st, grid, &err);
    }
    fuzz_require(fa.live == 0);
    return 0;
}
