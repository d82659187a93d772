/* The checks of fuzz_eval.c, one group per function family (included once,
 * by fuzz_eval.c, after its decoding helpers). */
#ifndef BRDFFIT_FUZZ_EVAL_CHECKS_H
#define BRDFFIT_FUZZ_EVAL_CHECKS_H

static const brdffit_status no_data[] = {BRDFFIT_E_NO_DATA};

/* Weights for a decoded cap and flags: finite, >= 0; with solid-angle
 * weighting they sum to at most 1 (exactly 1 without the cosine factor)
 * over a scattered grid and over each theta_i of a regular grid. */
static void check_weights(reader *r, const brdffit_grid *g)
{
    size_t n = brdffit_grid_sample_count(g), s;
    unsigned cap_byte = next(r), flags = next(r) & 3u;
    double cap = cap_byte == 255u ? BRDFFIT_DEFAULT_CAP : cap_byte / 254.0 * HALF_PI;
    double w[MAX_SAMPLES], sum = 0.0;
    brdffit_error err;
    brdffit_status st = brdffit_grid_weights(g, cap, flags, w, &err);
    expect_one_of(st, &err, no_data, 1);
    if (st != BRDFFIT_OK) return;
    fuzz_require(brdffit_grid_active_count(g, cap) > 0);
    for (s = 0; s < n; s++) {
        fuzz_require(isfinite(w[s]) && w[s] >= 0.0);
        sum += w[s];
    }
    if (brdffit_grid_get_kind(g) == BRDFFIT_GRID_REGULAR) {
        const double *ti;
        size_t n_ti = 0, active = 0;
        fuzz_require(brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_I, &ti, &n_ti) == BRDFFIT_OK);
        while (active < n_ti && ti[active] <= cap + 1e-9) active++;
        sum /= (double)active; /* the mean over theta_i of the per-theta_i sums */
    }
    if (flags & BRDFFIT_WEIGHT_SOLID_ANGLE) fuzz_require(sum <= 1.0 + 1e-9);
    if (flags == BRDFFIT_WEIGHT_SOLID_ANGLE) fuzz_require(sum >= 1.0 - 1e-9);
}

/* Interpolation at three decoded light/view pairs: between the smallest and
 * the largest value of each channel (a weighted mean of neighbours). */
static void check_weights_and_eval(reader *r, const brdffit_grid *g)
{
    static const brdffit_status allowed[] = {BRDFFIT_E_NO_DATA, BRDFFIT_E_UNSUPPORTED};
    size_t n = brdffit_grid_sample_count(g), nc = brdffit_grid_channel_count(g), k, c, s;
    check_weights(r, g);
    for (k = 0; k < 3; k++) {
        double ti = angle_code(next(r), -PI, PI), pi_ = angle_code(next(r), -4 * PI, 4 * PI);
        double to = angle_code(next(r), -PI, PI), po = angle_code(next(r), -4 * PI, 4 * PI);
        double out[MAX_CHANNELS];
        brdffit_error err;
        brdffit_status st = brdffit_grid_eval(g, ti, pi_, to, po, out, &err);
        expect_one_of(st, &err, allowed, 2);
        if (st == BRDFFIT_E_UNSUPPORTED) return;
        for (c = 0; c < nc; c++) {
            const double *v;
            double hi = 0.0;
            fuzz_require(brdffit_grid_values(g, c, &v) == BRDFFIT_OK);
            for (s = 0; s < n; s++) hi = fmax(hi, v[s]);
            fuzz_require(isfinite(out[c]) && out[c] >= 0.0 && out[c] <= hi * (1.0 + 1e-12));
        }
    }
}

/* The channel mean and the clear-coat grid of g: the grid invariants, and
 * with one failing allocation exactly OUT_OF_MEMORY. */
static void check_derived(reader *r, const brdffit_grid *g, fuzz_alloc *fa)
{
    static const brdffit_status coat_errors[] = {BRDFFIT_E_RANGE};
    unsigned coat = next(r), fail = next(r) % 8u;
    double r0 = coat == 255u ? 1.0 : coat / 256.0;
    brdffit_grid *d = NULL;
    brdffit_error err;
    brdffit_status st = brdffit_grid_channel_mean(&d, g, &fa->hook, &err);
    expect_one_of(st, &err, no_data, 1);
    if (st == BRDFFIT_OK) {
        fuzz_require(brdffit_grid_channel_count(d) == 1);
        fuzz_check_grid(d);
    }
    brdffit_grid_destroy(d);
    st = brdffit_grid_clearcoat(&d, g, r0, &fa->hook, &err);
    if (coat == 255u) fuzz_require(st == BRDFFIT_E_INVALID_ARGUMENT);
    else expect_one_of(st, &err, coat_errors, 1);
    if (st == BRDFFIT_OK) fuzz_check_grid(d);
    brdffit_grid_destroy(d);
    d = NULL;
    fa->allocs = 0;
    fa->fail_at = 1 + fail;
    st = brdffit_grid_channel_mean(&d, g, &fa->hook, &err);
    fa->fail_at = 0;
    if (st != BRDFFIT_E_NO_DATA)
        fuzz_require(st == (fa->allocs >= 1 + fail ? BRDFFIT_E_OUT_OF_MEMORY : BRDFFIT_OK));
    fuzz_require((st == BRDFFIT_OK) == (d != NULL));
    brdffit_grid_destroy(d);
}

/* A parameter entry inside [lower, upper], the ends included. */
static double param_code(unsigned v, const brdffit_param_info *p)
{
    double lo = p->lower, hi = p->upper;
    if (v == 0) return lo;
    if (v == 255) return isfinite(hi) ? hi : DBL_MAX;
    if (!isfinite(hi)) return v >= 250 ? DBL_MAX / (double)(255 - v) : lo + value_code(v);
    if ((p->flags & BRDFFIT_PARAM_LOG_SCALE) && lo > 0.0) return lo * pow(hi / lo, v / 255.0);
    return lo + (hi - lo) * (v / 255.0);
}

static void decode_params(reader *r, const brdffit_model *m, size_t nc, double *x)
{
    size_t k, c;
    for (k = 0; k < brdffit_model_param_count(m); k++) {
        const brdffit_param_info *p = brdffit_model_param(m, k);
        size_t width = (p->flags & BRDFFIT_PARAM_PER_CHANNEL) ? nc : 1;
        for (c = 0; c < width; c++)
            x[brdffit_model_vector_index(m, k, c, nc)] = param_code(next(r), p);
    }
}

static const brdffit_status model_errors[] = {BRDFFIT_E_NONFINITE, BRDFFIT_E_MODEL_FAILED};

/* Model values and Jacobian over the grid, and the Jacobian check. */
static void check_model(const brdffit_model *m, const brdffit_grid *g, const double *x)
{
    size_t n = brdffit_grid_sample_count(g), nc = brdffit_grid_channel_count(g), i;
    size_t np = brdffit_model_param_count(m);
    double values[MAX_VALUES], jac[8 * MAX_VALUES];
    brdffit_jacobian_report rep;
    brdffit_error err;
    brdffit_status st = brdffit_model_eval_grid(m, g, 0, n, x, values, np <= 8 ? jac : NULL,
                                                &err);
    expect_one_of(st, &err, model_errors, 2);
    for (i = 0; st == BRDFFIT_OK && i < n * nc; i++) fuzz_require(isfinite(values[i]));
    for (i = 0; st == BRDFFIT_OK && np <= 8 && i < np * n * nc; i++) fuzz_require(isfinite(jac[i]));
    memset(&rep, 0, sizeof rep);
    rep.struct_size = sizeof rep;
    st = brdffit_model_check_jacobian(m, g, x, &rep, &err);
    expect_one_of(st, &err, model_errors, 2);
    if (st != BRDFFIT_OK) return;
    fuzz_require(!(rep.worst_error < 0.0));
    fuzz_require(rep.param < np && rep.channel < nc && rep.sample < n);
}

/* Options decoded from the input: odd but mostly valid values; with flag
 * bit 3 the struct of a newer header (larger, unknown tail). */
typedef struct newer_options {
    brdffit_image_options o;
    unsigned char tail[24];
} newer_options;

static void decode_options(reader *r, unsigned flags, newer_options *n)
{
    brdffit_image_options_init(&n->o);
    memset(n->tail, 0xa5, sizeof n->tail);
    if (flags & 8u) n->o.struct_size = sizeof *n;
    n->o.gain = value_code(next(r));
    n->o.difference_gain = value_code(next(r));
    n->o.exposure = value_code(next(r));
    n->o.gamma = 0.05 + next(r) / 20.0; /* 0.05 .. 12.8: both ends refused */
    n->o.scale = next(r) % 5u;         /* 0 refused */
    n->o.block_columns = 1 + next(r) % 4u;
    n->o.block_gap = next(r) % 4u;
    n->o.log_y = (flags >> 7) & 1u;
}

#include "fuzz_eval_pictures.h"

static void check_model_and_pictures(reader *r, const brdffit_grid *g, unsigned flags,
                                     fuzz_alloc *fa)
{
    size_t nc = brdffit_grid_channel_count(g);
    unsigned index = next(r) % (unsigned)brdffit_model_builtin_count();
    brdffit_model *m = NULL;
    double x[MAX_VECTOR];
    newer_options opts;
    fuzz_require(brdffit_model_create(&m, brdffit_model_builtin_name(index), &fa->hook, NULL) ==
                 BRDFFIT_OK);
    fuzz_require(brdffit_model_vector_size(m, nc) <= MAX_VECTOR);
    decode_params(r, m, nc, x);
    check_model(m, g, x);
    decode_options(r, flags, &opts);
    check_pictures(r, g, m, x, &opts.o, fa);
    brdffit_model_destroy(m);
}

#endif
