"""brdffit.fit_many (brdffit_fit_many): many value sets on one geometry.
Every item equals a Fit with the same options and one thread on its own
grid, bit for bit, on 1 and 2 threads; NaN values are missing; bad items
are reported per item; progress, cancel and bad arguments behave as
documented."""

import math
import unittest

import numpy as np

import brdffit
from brdffit import Status

import support

NS, NC = 200, 3


def scattered_geometry(seed=7):
    rng = np.random.default_rng(seed)
    ti = rng.uniform(0.0, support.radians(80.0), NS)
    to = rng.uniform(0.0, support.radians(80.0), NS)
    po = rng.uniform(0.0, math.pi, NS)
    return ti, np.full(NS, math.pi), to, po


def texels(model, angles, n, seed=3, noise=0.02):
    rng = np.random.default_rng(seed)
    truth = np.array([model.pack_params({"ns": rng.uniform(20.0, 2000.0),
                                         "cd": rng.uniform(0.05, 0.4, NC),
                                         "cs": rng.uniform(0.02, 0.2, NC)}, NC)
                      for _ in range(n)])
    values = np.array([model.eval_angles(*angles, p, NC).T for p in truth])
    values *= 1.0 + noise * rng.standard_normal(values.shape)
    return truth, values


class FitManyTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.model = brdffit.Model.builtin("ashikhmin-shirley")
        cls.angles = scattered_geometry()
        cls.truth, cls.values = texels(cls.model, cls.angles, 16)
        cls.grid = brdffit.Grid.from_scattered(*cls.angles, cls.values[0])

    def single(self, values, **options):
        """One Fit per item: (status, params, std_errors, cost, iterations)."""
        out = []
        for v in values:
            missing = np.isnan(v)
            try:
                grid = brdffit.Grid.from_scattered(*self.angles, np.where(missing, 0.0, v),
                                                   missing=missing if missing.any() else None)
                with grid, brdffit.Fit(grid, self.model, threads=1, **options) as fit:
                    fit.run()
                    out.append((Status.OK, fit.params, fit.std_errors, fit.error("cost"),
                                fit.iterations))
            except brdffit.BrdffitError as exc:
                out.append((exc.status, None, None, None, None))
        return out

    def check_same(self, result, reference):
        for k, (status, params, se, cost, iterations) in enumerate(reference):
            self.assertEqual(result.status[k], status)
            if status != Status.OK:
                self.assertTrue(np.all(np.isnan(result.params[k])))
                continue
            np.testing.assert_array_equal(result.params[k], params)
            np.testing.assert_array_equal(result.std_errors[k], se)
            self.assertEqual(result.cost[k], cost)
            self.assertEqual(result.iterations[k], iterations)

    def test_equals_single_fits_on_1_and_2_threads(self):
        ref = self.single(self.values)
        for threads in (1, 2):
            with brdffit.Fit(self.grid, self.model, threads=threads) as proto:
                result = brdffit.fit_many(proto, self.values)
            self.assertEqual(result.n_run, len(self.values))
            self.assertTrue(result.ok.all())
            self.check_same(result, ref)
        rel = np.abs(result.params - self.truth) / self.truth
        self.assertLess(np.median(rel), 0.05)  # 2 % noise: near the truth

    def test_options_carry_over(self):
        options = {"pipeline": "joint", "max_iterations": 5, "fixed": ["ns"],
                   "start": {"ns": 100.0}}
        ref = self.single(self.values[:4], **options)
        with brdffit.Fit(self.grid, self.model, threads=2, **options) as proto:
            result = brdffit.fit_many(proto, self.values[:4])
        self.check_same(result, ref)
        np.testing.assert_allclose(result.params[:, 0], 100.0, rtol=1e-14)  # held

    def test_bad_items_and_missing_values(self):
        values = self.values[:5].copy()
        values[1, 10:20, 0] = np.nan  # missing values: fitted
        values[2, 5, 1] = np.inf      # not finite: E_RANGE
        values[3] = np.nan            # nothing: E_NO_DATA
        values[4] *= 1e105            # too large: E_RANGE
        with brdffit.Fit(self.grid, self.model) as proto:
            result = brdffit.fit_many(proto, values)
        self.assertEqual(list(result.status), [Status.OK, Status.OK, Status.E_RANGE,
                                               Status.E_NO_DATA, Status.E_RANGE])
        self.assertEqual(result.error(3), "BRDFFIT_E_NO_DATA: no usable samples")
        self.assertIsNone(result.error(0))
        self.assertEqual(result.stop_reasons()[3], "none")
        ref = self.single(values[:2])
        self.check_same(result, ref + [(int(s),) + (None,) * 4 for s in result.status[2:]])
        mask = np.zeros(values[:2].shape, dtype=bool)
        mask[0, 0, 0] = True
        with brdffit.Fit(self.grid, self.model) as proto:
            masked = brdffit.fit_many(proto, values[:2], missing=mask)
        v0 = values[:1].copy()
        v0[0, 0, 0] = np.nan
        self.check_same(masked, self.single(v0) + ref[1:])

    def test_regular_grid(self):
        axes = support.small_axes()
        angles = support.grid_angles(axes)
        truth, values = texels(self.model, angles, 3, noise=0.0)
        with brdffit.Grid.from_regular(*axes, values[0]) as grid, \
                brdffit.Fit(grid, self.model, threads=2) as proto:
            result = brdffit.fit_many(proto, values.reshape(3, 6, 11, 10, NC))
        np.testing.assert_allclose(result.params, truth, rtol=1e-6)
        for k in range(3):
            with brdffit.Grid.from_regular(*axes, values[k]) as grid, \
                    brdffit.Fit(grid, self.model) as fit:
                np.testing.assert_array_equal(fit.run().params, result.params[k])

    def test_progress_and_cancel(self):
        calls = []
        with brdffit.Fit(self.grid, self.model) as proto:
            result = brdffit.fit_many(proto, self.values,
                                      progress=lambda d, t: calls.append((d, t)))
            self.assertEqual(calls, [(d, 16) for d in range(1, 17)])
            stopped = brdffit.fit_many(proto, self.values, progress=lambda d, t: d >= 3)
            self.assertEqual(stopped.n_run, 3)
            self.assertEqual(list(stopped.status[3:]), [Status.E_NOT_READY] * 13)
            np.testing.assert_array_equal(stopped.params[:3], result.params[:3])

            def boom(done, total):
                raise KeyError("from progress")
            with self.assertRaises(KeyError):
                brdffit.fit_many(proto, self.values, progress=boom)
            # the prototype is usable afterwards, its own result unchanged
            proto.run()
            self.assertEqual(len(brdffit.fit_many(proto, self.values[:2])), 2)

    def test_bad_arguments(self):
        with brdffit.Fit(self.grid, self.model) as proto:
            with self.assertRaises(ValueError):
                brdffit.fit_many(proto, np.zeros(NS * NC + 1))
            empty = brdffit.fit_many(proto, np.zeros((0, NS, NC)))
            self.assertEqual(len(empty), 0)
        with brdffit.Fit(self.grid, support.python_as_model()) as proto:
            with self.assertRaises(ValueError):
                brdffit.fit_many(proto, self.values)


if __name__ == "__main__":
    unittest.main()
