/* The verdict on a fitted result: warnings a caller should see before
 * using the parameters (fit.h, brdffit_fit_warnings()). Every test reads the
 * finished result only; none changes it. docs/fitting.md lists them. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/core.h"
#include "fit/fit_internal.h"
#include "models/lobes.h"

/* A shape parameter this close to a finite bound (relative, in the units it
 * is optimised in) sits on it. */
#define BF_BOUND_TOL 1e-6
/* Two lobes whose shape parameters differ by less than this factor are one. */
#define BF_LOBE_RATIO 1.25
/* A Fresnel term above this, with some colour above 1, is in the valley
 * where the term tends to 1 and the colours grow without bound. */
#define BF_FRESNEL_EDGE 0.99
/* A colour below this fraction of the largest colour counts as 0. */
#define BF_ZERO_COLOUR 1e-6
/* A lobe's tabulated albedo bound (models/lobes.h) is at most 2.3 % above
 * the integral (0.1 % quadrature plus twice a cell's largest midpoint
 * excess, 1.1 %); a colour times the bound above 1 + this margin is a
 * directional albedo above 1 for certain. */
#define BF_LOBE_ALBEDO_MARGIN 0.03
/* Radians given as degrees: every polar angle below pi/2 degrees. */
#define BF_RADIAN_POLAR (BF_HALF_PI * BF_PI / 180.0)

typedef struct verdict {
    const brdffit_fit *fit;
    char *text;    /* NULL, or the buffer for the text of warning `only` */
    size_t size;
    unsigned only;
} verdict;

static const brdffit_param_info *param(const verdict *v, size_t k)
{
    return brdffit_model_param(v->fit->model, k);
}

static double value(const verdict *v, size_t k, size_t c)
{
    return v->fit->result.params[brdffit_model_vector_index(v->fit->model, k, c, v->fit->nc)];
}

static int is_shape(const verdict *v, size_t k)
{
    unsigned flags = param(v, k)->flags;
    return !v->fit->fixed[k] && !(flags & (BRDFFIT_PARAM_LINEAR | BRDFFIT_PARAM_PER_CHANNEL));
}

/* Record warning `w`; write its text when it is the one asked for. */
static unsigned say(verdict *v, unsigned w, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static unsigned say(verdict *v, unsigned w, const char *fmt, ...)
{
    if (v->text != NULL && v->only == w) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(v->text, v->size, fmt, ap);
        va_end(ap);
    }
    return w;
}

static int near_bound(double x, double bound, int log_scale)
{
    if (!isfinite(bound)) return 0;
    if (log_scale && bound > 0.0 && x > 0.0) return fabs(log(x / bound)) <= BF_BOUND_TOL;
    return fabs(x - bound) <= BF_BOUND_TOL * fmax(fabs(bound), 1.0);
}

static unsigned at_bound(verdict *v)
{
    size_t k, n = brdffit_model_param_count(v->fit->model);
    for (k = 0; k < n; k++) {
        const brdffit_param_info *p = param(v, k);
        int log_scale = (p->flags & BRDFFIT_PARAM_LOG_SCALE) != 0;
        double x = value(v, k, 0);
        if (!is_shape(v, k)) continue;
        if (near_bound(x, p->lower, log_scale) || near_bound(x, p->upper, log_scale))
            return say(v, BRDFFIT_WARN_AT_BOUND, "%s = %g is at a bound of its range [%g, %g]",
                       p->name, x, p->lower, p->upper);
    }
    return 0;
}

/* Declared index of the parameter called `name`, or the count if none. */
static size_t find(const verdict *v, const char *name)
{
    size_t k = 0;
    if (brdffit_model_param_find(v->fit->model, name, &k) != BRDFFIT_OK)
        return brdffit_model_param_count(v->fit->model);
    return k;
}

static double channel_max(const verdict *v, size_t k, size_t *channel)
{
    size_t c;
    double top = value(v, k, 0);
    *channel = 0;
    for (c = 1; c < v->fit->nc; c++)
        if (value(v, k, c) > top) {
            top = value(v, k, c);
            *channel = c;
        }
    return top;
}

static double colour_max(const verdict *v)
{
    size_t k, c, n = brdffit_model_param_count(v->fit->model);
    double top = 0.0;
    for (k = 0; k < n; k++)
        if (param(v, k)->flags & BRDFFIT_PARAM_LINEAR)
            for (c = 0; c < v->fit->nc; c++) top = fmax(top, value(v, k, c));
    return top;
}

/* The Lambert term cd of the built-in models (with Fresnel: (1 - Rs) cd). */
static unsigned diffuse(verdict *v)
{
    size_t n = brdffit_model_param_count(v->fit->model), cd = find(v, "cd"), rs = find(v, "Rs");
    size_t c;
    double top, scale;
    if (cd == n || !(param(v, cd)->flags & BRDFFIT_PARAM_PER_CHANNEL)) return 0;
    scale = rs < n ? 1.0 - value(v, rs, 0) : 1.0;
    top = channel_max(v, cd, &c);
    if (top <= BF_ZERO_COLOUR * colour_max(v) && n > 1 && !v->fit->fixed[cd])
        return say(v, BRDFFIT_WARN_NO_DIFFUSE,
                   "cd is 0 in every channel: the fit has no diffuse term");
    if (scale * top > 1.0)
        return say(v, BRDFFIT_WARN_ALBEDO,
                   "the diffuse albedo is %g in channel %zu: above 1, not physical",
                   scale * top, c);
    return 0;
}

/* Each specular lobe of a linear colour with a tabulated albedo: its
 * largest directional albedo over the tables' incidence angles, colour
 * times the bound, in every channel. */
static unsigned lobe_albedo(verdict *v)
{
    const bf_lobes *lobes = bf_model_lobes(v->fit->model);
    size_t i, c;
    if (lobes == NULL) return 0;
    for (i = 0; i < lobes->n; i++) {
        const bf_lobe_desc *l = &lobes->lobe[i];
        double f = l->fresnel == BF_NO_PARAM ? 1.0 : value(v, l->fresnel, 0);
        double bound = bf_lobe_albedo_bound(l, value(v, l->shape, 0), f);
        double top = channel_max(v, l->colour, &c);
        if (bound > 0.0 && top * bound > 1.0 + BF_LOBE_ALBEDO_MARGIN)
            return say(v, BRDFFIT_WARN_ALBEDO,
                       "the directional albedo of the lobe of %s is about %.3g in channel %zu: "
                       "above 1, not physical",
                       param(v, l->colour)->name, top * bound, c);
    }
    return 0;
}

static unsigned fresnel(verdict *v)
{
    static const char *const names[] = {"Rs", "F0"};
    size_t i, n = brdffit_model_param_count(v->fit->model);
    for (i = 0; i < 2; i++) {
        size_t k = find(v, names[i]);
        double top;
        if (k == n || v->fit->fixed[k] || value(v, k, 0) <= BF_FRESNEL_EDGE) continue;
        top = colour_max(v);
        if (top > 1.0)
            return say(v, BRDFFIT_WARN_FRESNEL_VALLEY,
                       "%s = %.6g tends to 1 while colours grow to %g: the cost's valley "
                       "where the Fresnel term and the colours trade off",
                       names[i], value(v, k, 0), top);
    }
    return 0;
}

static unsigned stop(verdict *v)
{
    brdffit_stop_reason r = v->fit->result.stop;
    if (r == BRDFFIT_STOP_MAX_ITERATIONS || r == BRDFFIT_STOP_MAX_EVALUATIONS)
        return say(v, BRDFFIT_WARN_ITERATION_LIMIT, "the last optimizer run ended at its %s",
                   r == BRDFFIT_STOP_MAX_ITERATIONS ? "iteration limit" : "evaluation limit");
    if (r == BRDFFIT_STOP_STALLED)
        return say(v, BRDFFIT_WARN_STALLED,
                   "the last optimizer run stalled: it stopped where a parameter's "
                   "derivatives vanished, not at a converged point");
    if (r == BRDFFIT_STOP_CANCELLED || r == BRDFFIT_STOP_CALLBACK)
        return say(v, BRDFFIT_WARN_STOPPED_EARLY, "the fit was %s before it converged",
                   r == BRDFFIT_STOP_CANCELLED ? "cancelled" : "stopped by its callback");
    return 0;
}

/* Two lobes: shape parameters "<x>1" and "<x>2" with colours "cs1", "cs2". */
static unsigned lobes(verdict *v)
{
    size_t k, n = brdffit_model_param_count(v->fit->model), c1 = find(v, "cs1"),
              c2 = find(v, "cs2"), ch;
    double zero;
    if (c1 == n || c2 == n) return 0;
    zero = BF_ZERO_COLOUR * colour_max(v);
    if (channel_max(v, c1, &ch) <= zero || channel_max(v, c2, &ch) <= zero)
        return say(v, BRDFFIT_WARN_LOBES_MERGED,
                   "one lobe's colour (%s) is 0 in every channel: the fit has one lobe",
                   channel_max(v, c1, &ch) <= zero ? "cs1" : "cs2");
    for (k = 0; k + 1 < n; k++) {
        const char *a = param(v, k)->name, *b = param(v, k + 1)->name;
        size_t len = strlen(a);
        double x = value(v, k, 0), y = value(v, k + 1, 0);
        if (len < 2 || strlen(b) != len || strncmp(a, b, len - 1) != 0 || a[len - 1] != '1' ||
            b[len - 1] != '2' || !(x > 0.0) || !(y > 0.0))
            continue;
        if (fmax(x, y) < BF_LOBE_RATIO * fmin(x, y))
            return say(v, BRDFFIT_WARN_LOBES_MERGED,
                       "the lobes are not separated: %s = %g and %s = %g", a, x, b, y);
    }
    return 0;
}

/* Largest polar angle of the grid (light or view). */
static double largest_polar(const brdffit_grid *g)
{
    size_t s, n = brdffit_grid_sample_count(g), count;
    const double *axis;
    double top = 0.0, ti, pi_, to, po;
    if (brdffit_grid_get_kind(g) == BRDFFIT_GRID_REGULAR) {
        if (brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_I, &axis, &count) == BRDFFIT_OK)
            top = axis[count - 1];
        if (brdffit_grid_axis(g, BRDFFIT_AXIS_THETA_O, &axis, &count) == BRDFFIT_OK)
            top = fmax(top, axis[count - 1]);
        return top;
    }
    for (s = 0; s < n; s++)
        if (brdffit_grid_sample_angles(g, s, &ti, &pi_, &to, &po) == BRDFFIT_OK)
            top = fmax(top, fmax(ti, to));
    return top;
}

static unsigned radians(verdict *v)
{
    double top = largest_polar(v->fit->grid);
    if (top > 0.0 && top <= BF_RADIAN_POLAR * (1.0 + 1e-9))
        return say(v, BRDFFIT_WARN_DEGREES_AS_RADIANS,
                   "every polar angle is at most %.4g degrees: were angles in radians given "
                   "as degrees?",
                   top * 180.0 / BF_PI);
    return 0;
}

/* The fit against each channel's best constant, in E's measure. */
static unsigned mean(verdict *v)
{
    const bf_result *r = &v->fit->result;
    double fitted = 0.0, plain = 0.0;
    size_t c;
    for (c = 0; c < v->fit->nc; c++) {
        fitted += r->metrics[4 * c + 1];
        plain += r->metrics[4 * c];
    }
    if (v->fit->objective == BRDFFIT_OBJECTIVE_SQUARES) {
        /* the cost the fit minimised */
        double cost = 0.0;
        for (c = 0; c < v->fit->nc; c++) cost += r->metrics[4 * c + 3];
        if (!(r->mean_cost > 0.0) || cost < r->mean_cost) return 0;
        return say(v, BRDFFIT_WARN_NO_BETTER_THAN_MEAN,
                   "the fit's cost, %g, is no smaller than %g, that of each channel's best "
                   "constant value: the model explains none of the data's variation",
                   cost, r->mean_cost);
    }
    if (!(r->mean_error > 0.0) || fitted < r->mean_error || plain < r->mean_plain) return 0;
    return say(v, BRDFFIT_WARN_NO_BETTER_THAN_MEAN,
               "the fit's squared errors, %g in Ngan's measure and %g unweighted, are no "
               "smaller than %g and %g, those of each channel's best constant value: the "
               "model explains none of the data's variation",
               fitted, plain, r->mean_error, r->mean_plain);
}

static unsigned judge(verdict *v)
{
    unsigned albedo = diffuse(v);
    if (!(albedo & BRDFFIT_WARN_ALBEDO)) albedo |= lobe_albedo(v);
    return at_bound(v) | albedo | fresnel(v) | stop(v) | lobes(v) | radians(v) | mean(v);
}

unsigned brdffit_fit_warnings(const brdffit_fit *fit)
{
    verdict v;
    if (fit == NULL || fit->magic != BF_MAGIC_FIT || !fit->has_result) return 0;
    memset(&v, 0, sizeof v);
    v.fit = fit;
    return judge(&v);
}

brdffit_status brdffit_fit_warning_text(const brdffit_fit *fit, unsigned warning, char *buf,
                                        size_t size)
{
    verdict v;
    if (fit == NULL || buf == NULL || size == 0) return BRDFFIT_E_INVALID_ARGUMENT;
    if (fit->magic != BF_MAGIC_FIT) return BRDFFIT_E_BAD_HANDLE;
    buf[0] = '\0';
    if (!fit->has_result) return BRDFFIT_E_NOT_READY;
    if (brdffit_warning_name(warning) == NULL) return BRDFFIT_E_INVALID_ARGUMENT;
    memset(&v, 0, sizeof v);
    v.fit = fit;
    v.text = buf;
    v.size = size;
    v.only = warning;
    return (judge(&v) & warning) ? BRDFFIT_OK : BRDFFIT_E_NOT_FOUND;
}

const char *brdffit_warning_name(unsigned warning)
{
    switch (warning) {
    case BRDFFIT_WARN_AT_BOUND: return "at-bound";
    case BRDFFIT_WARN_NO_DIFFUSE: return "no-diffuse";
    case BRDFFIT_WARN_ALBEDO: return "albedo-above-1";
    case BRDFFIT_WARN_FRESNEL_VALLEY: return "fresnel-valley";
    case BRDFFIT_WARN_ITERATION_LIMIT: return "iteration-limit";
    case BRDFFIT_WARN_STOPPED_EARLY: return "stopped-early";
    case BRDFFIT_WARN_LOBES_MERGED: return "lobes-merged";
    case BRDFFIT_WARN_DEGREES_AS_RADIANS: return "radians-as-degrees";
    case BRDFFIT_WARN_STALLED: return "stalled";
    case BRDFFIT_WARN_NO_BETTER_THAN_MEAN: return "no-better-than-mean";
    default: return NULL;
    }
}
