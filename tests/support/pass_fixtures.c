#include "pass_fixtures.h"

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
