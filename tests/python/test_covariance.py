"""Fit.covariance() and the errors option through the binding: the
covariance's diagonal is the standard errors squared, held parameters
have zero rows, the sandwich differs from the classic estimate, and a
bad estimator name or a fit without a result raise."""

import unittest

import numpy as np

from brdffit import BrdffitError, Fit, Grid, Model, Status

import support

TRUTH = {"ns": 120.0, "cd": [0.3, 0.2, 0.1], "cs": [0.4, 0.35, 0.3]}


class Covariance(unittest.TestCase):
    def setUp(self):
        self.model = Model.builtin("ashikhmin-shirley")
        exact = support.model_grid(self.model, self.model.pack_params(TRUTH, 3), 3)
        rng = np.random.RandomState(11)
        self.grid = Grid.from_regular(*support.small_axes(),
                                      exact.values * (1.0 + 0.02 * rng.standard_normal((660, 3))))

    def test_diagonal_and_estimators(self):
        covs = {}
        for errors in ("classic", "sandwich"):
            fit = Fit(self.grid, self.model, pipeline="joint", start=TRUTH, errors=errors).run()
            self.assertEqual(fit.errors, errors)
            cov, se = fit.covariance(), fit.std_errors
            self.assertEqual(cov.shape, (fit.param_count, fit.param_count))
            np.testing.assert_array_equal(cov, cov.T)
            np.testing.assert_allclose(np.sqrt(np.diag(cov)), se, rtol=1e-12)
            self.assertTrue(np.all(se > 0.0))
            covs[errors] = cov
        self.assertFalse(np.array_equal(covs["classic"], covs["sandwich"]))

    def test_held_rows_zero(self):
        fit = Fit(self.grid, self.model, pipeline="joint", start=TRUTH, errors="sandwich",
                  fix={"cs": TRUTH["cs"]}).run()
        cov = fit.covariance()
        se = fit.std_errors
        zero = np.flatnonzero(se == 0.0)
        self.assertEqual(len(zero), 3)
        for i in zero:
            self.assertTrue(np.all(cov[i] == 0.0) and np.all(cov[:, i] == 0.0))

    def test_bad_input(self):
        fit = Fit(self.grid, self.model)
        with self.assertRaises(BrdffitError) as ctx:
            fit.covariance()
        self.assertEqual(ctx.exception.status, Status.E_NOT_READY)
        with self.assertRaises(ValueError):
            fit.errors = "robust"
        with self.assertRaises(BrdffitError) as ctx:
            fit.errors = 2
        self.assertEqual(ctx.exception.status, Status.E_INVALID_ARGUMENT)
        self.assertEqual(fit.errors, "classic")


if __name__ == "__main__":
    unittest.main()
