/* The canonical lobe order: see canonical.h. The model's value is the same
 * with the lobes swapped, so the cost, the error figures and the verdict
 * do not change; only where each lobe is reported does. */
#include "fit/canonical.h"

#include <string.h>

static size_t find(const brdffit_model *model, const char *name)
{
    size_t k, n = brdffit_model_param_count(model);
    for (k = 0; k < n; k++)
        if (strcmp(brdffit_model_param(model, k)->name, name) == 0) return k;
    return n;
}

/* The first shape parameter "<x>1" followed by "<x>2"; n when none. */
static size_t lobe_shape(const brdffit_model *model)
{
    size_t k, n = brdffit_model_param_count(model);
    for (k = 0; k + 1 < n; k++) {
        const char *a = brdffit_model_param(model, k)->name;
        const char *b = brdffit_model_param(model, k + 1)->name;
        size_t len = strlen(a);
        if (len >= 2 && strlen(b) == len && strncmp(a, b, len - 1) == 0 && a[len - 1] == '1' &&
            b[len - 1] == '2')
            return k;
    }
    return n;
}

/* The built-in two-lobe models, whose lobes are the same function. */
static int two_lobe_builtin(const brdffit_model *model)
{
    static const char *const names[] = {"ashikhmin-shirley-2", "cook-torrance-2", "ggx-2"};
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(brdffit_model_name(model), names[i]) == 0) return 1;
    return 0;
}

static void swap_entries(bf_result *r, size_t a, size_t b)
{
    double t = r->params[a];
    r->params[a] = r->params[b];
    r->params[b] = t;
    t = r->std_errors[a];
    r->std_errors[a] = r->std_errors[b];
    r->std_errors[b] = t;
}

/* Swap declared parameters k and l in every channel. */
static void swap_params(const bf_run *run, size_t k, size_t l)
{
    const brdffit_model *model = run->fit->model;
    size_t c, nc = run->fit->nc;
    int per = (brdffit_model_param(model, k)->flags & BRDFFIT_PARAM_PER_CHANNEL) != 0;
    for (c = 0; c < (per ? nc : 1); c++)
        swap_entries(run->result, brdffit_model_vector_index(model, k, c, nc),
                     brdffit_model_vector_index(model, l, c, nc));
}

void bf_canonical_lobes(bf_run *run)
{
    const brdffit_fit *fit = run->fit;
    const brdffit_model *model = fit->model;
    size_t n = brdffit_model_param_count(model), k = lobe_shape(model);
    size_t c1 = find(model, "cs1"), c2 = find(model, "cs2");
    double x1, x2;
    int exponent;
    /* a user model's lobes need not be the same function: built-in ones only */
    if (!two_lobe_builtin(model) || k == n || c1 == n || c2 == n) return;
    if (fit->fixed[k] || fit->fixed[k + 1] || fit->fixed[c1] || fit->fixed[c2]) return;
    x1 = run->result->params[brdffit_model_vector_index(model, k, 0, fit->nc)];
    x2 = run->result->params[brdffit_model_vector_index(model, k + 1, 0, fit->nc)];
    exponent = strncmp(brdffit_model_param(model, k)->name, "ns", 2) == 0;
    if (exponent ? x1 >= x2 : x1 <= x2) return;
    swap_params(run, k, k + 1);
    swap_params(run, c1, c2);
}
