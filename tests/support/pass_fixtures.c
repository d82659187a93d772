#include "pass_fixtures.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "grid_fixtures.h"
#include "test_support.h"

brdffit_grid *fx_pass_grid(size_t nc)
{
    const brdffit_axes *axes = brdffit_axes_default();
    double *v = fx_values(axes, nc);
    brdffit_grid *g = NULL;
    assert_non_null(v);
    assert_int_equal(brdffit_grid_create_regular(&g, axes, nc, v, NULL, NULL, NULL), BRDFFIT_OK);
    free(v);
    return g;
}

void fx_pass_problem(bf_problem *pb, const brdffit_grid *grid, const brdffit_model *model,
                     const bf_weight_plan *plan, size_t nc, bf_source source, double coat)
{
    memset(pb, 0, sizeof *pb);
    pb->grid = grid;
    pb->model = model;
    pb->plan = plan;
    pb->plan_sa = plan;
    pb->nc = nc;
    pb->source = source;
    pb->clearcoat = coat;
    pb->threads = 1;
    bf_layout_init(&pb->ly, model, nc);
}

void fx_pass_start(const bf_problem *pb, double *params)
{
    const size_t nc = pb->nc, np = brdffit_model_param_count(pb->model);
    size_t k, c;
    for (k = 0; k < np; k++) {
        const brdffit_param_info *p = brdffit_model_param(pb->model, k);
        for (c = 0; c < nc; c++) {
            double v = p->start * (1.0 + 0.1 * (double)c);
            if (v == 0.0) v = 0.05 + 0.02 * (double)c;
            params[pb->vindex[k * nc + c]] = fmin(fmax(v, p->lower), p->upper);
        }
    }
}
