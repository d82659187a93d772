/* libFuzzer harness for what the other harnesses do not reach: grids made
 * in memory (regular, or scattered with given weights), their weights,
 * interpolation (brdffit_grid_eval), the derived grids (channel mean,
 * clear coat), model evaluation and the Jacobian check at parameters
 * anywhere inside the bounds, and every picture function with odd options
 * and strides.
 *
 * Input layout (bytes past the end read as 0):
 *   flags    bit 0 scattered grid, 1 missing mask, 2 given weights
 *            (scattered), 3 options of a newer (larger) struct, bits 4-5
 *            channels - 1, bit 6 rerun one picture with a failing
 *            allocation, bit 7 log_y in the plot
 *   sizes    regular: bits 0-1, 2-3, 4-5 number of theta_i, theta_o, phi_o
 *            values - 1, bit 6 axes start at 0, bit 7 end at their maximum;
 *            scattered: 1 + sizes % 16 samples
 *   angles   regular: one byte per axis value (the gap to the previous one
 *            - 1); scattered: 4 bytes per sample (see angle_code)
 *   values   one code byte per value (see value_code)
 *   missing  with the mask: one bit per value
 *   weights  with given weights: one code byte per sample
 *   cap, weighting flags, three light/view pairs (4 angle bytes each), the
 *   clear-coat R0, the model index, one byte per parameter entry (placed
 *   inside its bounds, the ends included), image options (gain, gamma,
 *   scale, block columns, gap), three stride paddings, the sphere size and
 *   light, the plot size and its values, the failing allocation.
 *
 * Checks: every status is a documented one with a message; weights are
 * finite, >= 0 and sum to at most 1 with solid-angle weighting;
 * interpolated values lie between the grid's smallest and largest; derived
 * grids pass the grid invariants; model values and derivatives are finite;
 * a Jacobian report names an existing entry; pictures never write outside
 * their pixels (the row padding and a guard after the buffer keep their
 * bytes); a picture whose allocation fails returns exactly
 * BRDFFIT_E_OUT_OF_MEMORY; nothing leaks. A violation aborts. */
#include <float.h>
#include <stddef.h>
#include <stdint.h>

#include "fuzz_common.h"

#define MAX_AXIS 4
#define MAX_CHANNELS 4
#define MAX_SAMPLES 64
#define MAX_VALUES (MAX_SAMPLES * MAX_CHANNELS)
#define MAX_VECTOR 64
#define GUARD 64
#define PI 3.14159265358979323846
#define HALF_PI 1.5707963267948966

typedef struct reader {
    const unsigned char *data;
    size_t size, pos;
} reader;

static unsigned next(reader *r)
{
    return r->pos < r->size ? r->data[r->pos++] : 0u;
}

/* A value code: zero, tiny, denormal, huge, near DBL_MAX, or ordinary. */
static double value_code(unsigned v)
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

/* An angle in [lo, hi] (the ends, tiny offsets from them, or a step). */
static double angle_code(unsigned v, double lo, double hi)
{
    if (v == 0) return lo;
    if (v == 255) return hi;
    if (v == 1) return lo + ldexp(1.0, -1074);
    if (v == 254) return nextafter(hi, lo);
    return lo + (hi - lo) * (v / 255.0);
}

typedef struct eval_case {
    unsigned flags, sizes;
    size_t nc, n_samples, n_axis[3];
    double axis[3][MAX_AXIS];
    double ang[4][MAX_SAMPLES]; /* scattered: theta_i, phi_i, theta_o, phi_o */
    double values[MAX_VALUES], weights[MAX_SAMPLES];
    unsigned char missing[MAX_VALUES];
} eval_case;

static void decode_axes(reader *r, eval_case *ec)
{
    static const double range[3] = {HALF_PI, HALF_PI, PI};
    size_t a, k;
    for (a = 0; a < 3; a++) {
        double pos[MAX_AXIS], total;
        size_t n = ec->n_axis[a] = 1 + ((ec->sizes >> (2 * a)) & 3u);
        for (k = 0; k < n; k++)
            pos[k] = (k == 0 ? ((ec->sizes & 64u) ? 0.0 : 1.0 + next(r))
                             : pos[k - 1] + 1.0 + next(r));
        total = (ec->sizes & 128u) && pos[n - 1] > 0.0 ? pos[n - 1] : 256.0 * MAX_AXIS;
        for (k = 0; k < n; k++) ec->axis[a][k] = range[a] * (pos[k] / total);
        if (ec->sizes & 128u) ec->axis[a][n - 1] = range[a];
    }
    ec->n_samples = ec->n_axis[0] * ec->n_axis[1] * ec->n_axis[2];
}

static void decode_grid(reader *r, eval_case *ec)
{
    size_t s, k, n_values;
    memset(ec, 0, sizeof *ec);
    ec->flags = next(r);
    ec->sizes = next(r);
    ec->nc = 1 + ((ec->flags >> 4) & 3u);
    if (ec->flags & 1u) {
        ec->n_samples = 1 + ec->sizes % 16u;
        for (s = 0; s < ec->n_samples; s++) {
            ec->ang[0][s] = angle_code(next(r), 0.0, HALF_PI);
            ec->ang[1][s] = angle_code(next(r), -2.0 * PI, 2.0 * PI);
            ec->ang[2][s] = angle_code(next(r), 0.0, HALF_PI);
            ec->ang[3][s] = angle_code(next(r), -2.0 * PI, 2.0 * PI);
        }
    } else {
        decode_axes(r, ec);
    }
    n_values = ec->n_samples * ec->nc;
    for (k = 0; k < n_values; k++) ec->values[k] = value_code(next(r));
    for (k = 0; (ec->flags & 2u) && k < n_values; k += 8) {
        unsigned bits = next(r), b;
        for (b = 0; b < 8 && k + b < n_values; b++) ec->missing[k + b] = (bits >> b) & 1u;
    }
    for (s = 0; (ec->flags & 5u) == 5u && s < ec->n_samples; s++)
        ec->weights[s] = value_code(next(r));
}

static brdffit_status make_grid(const eval_case *ec, brdffit_grid **g, const brdffit_allocator *a,
                                brdffit_error *err)
{
    const unsigned char *miss = (ec->flags & 2u) ? ec->missing : NULL;
    if (ec->flags & 1u)
        return brdffit_grid_create_scattered(g, ec->n_samples, ec->ang[0], ec->ang[1], ec->ang[2],
                                             ec->ang[3], ec->nc, ec->values, miss,
                                             (ec->flags & 4u) ? ec->weights : NULL, a, err);
    {
        brdffit_axes axes;
        axes.theta_i = ec->axis[0], axes.n_theta_i = ec->n_axis[0];
        axes.theta_o = ec->axis[1], axes.n_theta_o = ec->n_axis[1];
        axes.phi_o = ec->axis[2], axes.n_phi_o = ec->n_axis[2];
        return brdffit_grid_create_regular(g, &axes, ec->nc, ec->values, miss, a, err);
    }
}

/* A status other than OK must be one of `allowed` and carry a message. */
static void expect_one_of(brdffit_status st, const brdffit_error *err, const brdffit_status *allowed,
                          size_t n)
{
    size_t k;
    int ok = 0;
    if (st == BRDFFIT_OK) return;
    for (k = 0; k < n; k++) ok |= st == allowed[k];
    if (!ok) fprintf(stderr, "unexpected status %s: %s\n", brdffit_status_name(st), err->message);
    fuzz_require(ok);
    fuzz_require(err->status == st && err->message[0] != '\0');
}

#include "fuzz_eval_checks.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    reader r = {data, size, 0};
    eval_case ec;
    brdffit_grid *g = NULL;
    brdffit_error err;
    fuzz_alloc fa;
    brdffit_status st;
    decode_grid(&r, &ec);
    fuzz_alloc_init(&fa, 0);
    st = make_grid(&ec, &g, &fa.hook, &err);
    if (st != BRDFFIT_OK) {
        fuzz_check_failure(st, g, &err);
    } else {
        fuzz_check_grid(g);
        check_weights_and_eval(&r, g);
        check_derived(&r, g, &fa);
        check_model_and_pictures(&r, g, ec.flags, &fa);
        brdffit_grid_destroy(g);
    }
    fuzz_require(fa.live == 0);
    return 0;
}
