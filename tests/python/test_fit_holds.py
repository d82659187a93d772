"""Fit: holding and freeing parameters (fix, free), the damping option,
whether the fit converged and its labelled stages, through the binding."""

import unittest

import numpy as np

from brdffit import BrdffitError, Fit, Grid, Model, Stage, Status

import support

TRUTH = {"ns": 120.0, "cd": [0.3, 0.2, 0.1], "cs": [0.4, 0.35, 0.3]}
PIPELINES = ("auto", "joint", "two-stage")


def noisy_grid(model, params, sigma=0.01, seed=5):
    """The model's values on the small layout times (1 + sigma * N(0, 1))."""
    exact = support.model_grid(model, params, 3)
    rng = np.random.RandomState(seed)
    return Grid.from_regular(*support.small_axes(),
                             exact.values * (1.0 + sigma * rng.standard_normal((660, 3))))


class Holds(unittest.TestCase):
    def setUp(self):
        self.model = Model.builtin("ashikhmin-shirley")
        self.grid = noisy_grid(self.model, self.model.pack_params(TRUTH, 3))

    def test_fix_colour_every_pipeline(self):
        """A colour held at its true values (one per channel) comes back
        exactly with standard error 0; the rest is recovered from noisy data."""
        for pipeline in PIPELINES:
            with self.subTest(pipeline=pipeline):
                fit = Fit(self.grid, self.model, pipeline=pipeline, start={"ns": 60.0},
                          fix={"cs": TRUTH["cs"]}).run()
                got, se = fit.params_by_name(), fit.std_errors_by_name()
                self.assertEqual(list(got["cs"]), TRUTH["cs"])
                self.assertEqual(list(se["cs"]), [0.0, 0.0, 0.0])
                self.assertAlmostEqual(got["ns"] / TRUTH["ns"], 1.0, delta=0.02)
                np.testing.assert_allclose(got["cd"], TRUTH["cd"], rtol=0.02)
                self.assertTrue(np.all(se["cd"] > 0.0) and se["ns"] > 0.0)
                self.assertTrue(fit.converged())

    def test_fix_shape(self):
        fit = Fit(self.grid, self.model, fix={"ns": 120.0}).run()
        self.assertEqual(fit.params_by_name()["ns"], 120.0)
        self.assertEqual(fit.std_errors_by_name()["ns"], 0.0)
        np.testing.assert_allclose(fit.params_by_name()["cs"], TRUTH["cs"], rtol=0.02)

    def test_fix_keeps_other_start_values(self):
        """fix() changes only the named start values: after start ns = 1e4,
        fixing cs is the same fit as starting from ns = 1e4 with those cs
        and holding cs; three joint iterations from 1e4 do not reach the
        optimum, so a lost start value would show."""
        def short(**options):
            return Fit(self.grid, self.model, pipeline="joint", max_iterations=3, **options)
        a = short(start={"ns": 1e4})
        a.fix({"cs": TRUTH["cs"]})
        a.run()
        b = short(start={"ns": 1e4, "cs": TRUTH["cs"]}, fixed=["cs"]).run()
        c = short(fix={"cs": TRUTH["cs"]}).run()
        np.testing.assert_array_equal(a.params, b.params)
        self.assertNotEqual(a.params_by_name()["ns"], c.params_by_name()["ns"])
        self.assertFalse(a.converged())

    def test_fix_errors(self):
        fit = Fit(self.grid, self.model)
        with self.assertRaises(BrdffitError) as cm:
            fit.fix({"cs": -1.0})
        self.assertEqual(cm.exception.status, Status.E_RANGE)
        with self.assertRaises(BrdffitError) as cm:
            fit.fix({"zz": 1.0})
        self.assertEqual(cm.exception.status, Status.E_NOT_FOUND)
        with self.assertRaises(ValueError):
            fit.fix({"cs": [0.1, 0.2]})
        # nothing was held by the failed calls: the fit recovers cs
        fit.run()
        np.testing.assert_allclose(fit.params_by_name()["cs"], TRUTH["cs"], rtol=0.02)

    def test_free_default_held_f0(self):
        """GGX holds F0 by default (exactly its start value); free() lets it move."""
        ggx = Model.builtin("ggx")
        truth = {"a": 0.2, "F0": 0.1, "cd": TRUTH["cd"], "cs": [0.5, 0.45, 0.4]}
        grid = noisy_grid(ggx, ggx.pack_params(truth, 3))
        held = Fit(grid, ggx).run()
        self.assertEqual(held.params_by_name()["F0"], ggx.default_params(3)[1])
        free = Fit(grid, ggx, free=["F0"]).run()
        self.assertNotEqual(free.params_by_name()["F0"], ggx.default_params(3)[1])
        self.assertGreater(free.std_errors_by_name()["F0"], 0.0)

    def test_damping_option(self):
        for name in ("nielsen", "marquardt", "thesis"):
            with self.subTest(damping=name):
                fit = Fit(self.grid, self.model, pipeline="joint", damping=name,
                          start={"ns": 60.0}).run()
                self.assertAlmostEqual(fit.params_by_name()["ns"] / TRUTH["ns"], 1.0,
                                       delta=0.02)
        with self.assertRaises(ValueError):
            Fit(self.grid, self.model, damping="fast")


class Report(unittest.TestCase):
    def setUp(self):
        self.model = Model.builtin("ashikhmin-shirley")
        self.grid = support.model_grid(self.model, self.model.pack_params(TRUTH, 3), 3)

    def check_final(self, fit, stage):
        cost, lam = fit.history()
        np.testing.assert_array_equal(stage.cost, cost)
        np.testing.assert_array_equal(stage.lambda_, lam)
        self.assertEqual(stage.stop, fit.stop_reason)
        self.assertEqual(stage.iterations, fit.iterations)

    def test_stages_of_every_pipeline(self):
        auto = Fit(self.grid, self.model).run()
        stages = auto.stages()
        self.assertIsInstance(stages[0], Stage)
        self.assertEqual(stages[0].kind, "scan")
        self.assertEqual(stages[0].stop, "none")
        self.assertFalse(stages[0].kept)
        self.assertEqual(len(stages[0].cost), stages[0].evaluations)
        self.assertTrue(np.all(np.diff(stages[0].cost) <= 0.0))
        self.assertTrue(all(s.kind == "polish" for s in stages[1:]))
        kept = [s for s in stages if s.kept]
        self.assertEqual(len(kept), 1)
        self.check_final(auto, kept[0])
        joint = Fit(self.grid, self.model, pipeline="joint").run()
        self.assertEqual([(s.kind, s.index) for s in joint.stages()], [("joint", 0)])
        self.check_final(joint, joint.stages()[0])
        two = Fit(self.grid, self.model, pipeline="two-stage").run()
        stages = two.stages()
        self.assertEqual([(s.kind, s.index) for s in stages],
                         [("mean", 0), ("channel", 0), ("channel", 1), ("channel", 2)])
        self.assertTrue(all(s.kept and s.converged for s in stages))
        for s in stages:
            self.assertEqual(len(s.cost), s.iterations + 1)
        self.check_final(two, stages[-1])

    def test_converged(self):
        fit = Fit(self.grid, self.model, pipeline="joint")
        self.assertFalse(fit.converged())
        self.assertEqual(fit.stages(), [])
        fit.run()
        self.assertTrue(fit.converged())
        fit.max_iterations = 1
        fit.run()
        self.assertEqual(fit.stop_reason, "max-iterations")
        self.assertFalse(fit.converged())
        self.assertFalse(fit.stages()[0].converged)


if __name__ == "__main__":
    unittest.main(verbosity=2)
