// Ceres Solver's Levenberg-Marquardt on a problem given as libbrdffit's
// residual callback (bench_ceres.h): one cost function of all the rows on
// one parameter block, dense QR, the problem's analytic Jacobian. Built
// only when CMake finds Ceres (Debian: libceres-dev).
#include "bench_ceres.h"

#include <ceres/ceres.h>

#include <vector>

namespace {

class CallbackCost : public ceres::CostFunction {
  public:
    CallbackCost(brdffit_residual_fn fn, void *user, size_t n, size_t m) : fn_(fn), user_(user)
    {
        set_num_residuals(static_cast<int>(m));
        mutable_parameter_block_sizes()->push_back(static_cast<int>(n));
    }

    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override
    {
        double *jac = jacobians != nullptr ? jacobians[0] : nullptr;
        return fn_(parameters[0], residuals, jac, user_) == BRDFFIT_OK;
    }

  private:
    brdffit_residual_fn fn_;
    void *user_;
};

} // namespace

extern "C" int bench_ceres_solve(brdffit_residual_fn fn, void *user, size_t n, size_t m,
                                 const bench_ceres_settings *settings, double *x,
                                 bench_ceres_result *result)
{
    try {
        ceres::Problem::Options popt;
        ceres::Problem problem(popt);
        problem.AddResidualBlock(new CallbackCost(fn, user, n, m), nullptr, x);
        ceres::Solver::Options opt;
        opt.minimizer_type = ceres::TRUST_REGION;
        opt.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
        opt.linear_solver_type = ceres::DENSE_QR;
        opt.max_num_iterations = settings->max_iterations;
        opt.function_tolerance = settings->function_tolerance;
        opt.gradient_tolerance = settings->gradient_tolerance;
        opt.parameter_tolerance = settings->parameter_tolerance;
        opt.logging_type = ceres::SILENT;
        opt.minimizer_progress_to_stdout = false;
        opt.num_threads = 1;
        ceres::Solver::Summary summary;
        ceres::Solve(opt, &problem, &summary);
        result->converged = summary.termination_type == ceres::CONVERGENCE;
        result->iterations =
            static_cast<size_t>(summary.num_successful_steps + summary.num_unsuccessful_steps);
        return 0;
    } catch (...) {
        return 1;
    }
}
