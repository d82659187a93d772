"""Fit: agreement with the C library to 1e-12, recovery of known parameters
(built-in and Python models), options, history, threads, errors, lifetime."""

import gc
import math
import os
import subprocess
import tempfile
import unittest

import numpy as np

import brdffit
from brdffit import BrdffitError, Fit, Grid, Model, Status, Weighting

import support
from support import radians

TRUTH = {"ns": 120.0, "cd": [0.3, 0.2, 0.1], "cs": [0.4, 0.35, 0.3]}

# The configurations of tests/python/fit_reference.c, through the binding.
REFERENCE_CONFIGS = {
    "auto": ("ashikhmin-shirley", {}),
    "joint": ("ashikhmin-shirley-fresnel", dict(
        pipeline="joint", cap=60.0 * (math.pi / 180.0), weighting=Weighting.COSINE,
        threads=1, max_iterations=40, fixed=["Rs"],
        start={"ns": 60.0, "Rs": 0.25, "cd": 0.2, "cs": 0.3})),
    "two-stage": ("blinn-phong", dict(
        pipeline="two-stage", weighting=Weighting.SOLID_ANGLE, clearcoat=0.04, threads=3,
        start=[30.0, 0.2, 0.2, 0.2, 0.3, 0.3, 0.3])),
}


def run_reference(program, csv_path):
    """Run the C reference program; returns {config: {key: list of floats}}."""
    out = subprocess.run([program, csv_path], check=True, stdout=subprocess.PIPE,
                         universal_newlines=True).stdout
    results = {}
    for line in out.splitlines():
        config, key, *numbers = line.split()
        results.setdefault(config, {})[key] = [float(x) for x in numbers]
    return results


class MatchesTheCLibrary(unittest.TestCase):
    """The binding passes data and options through unchanged: the same fits
    made by a C program give the same numbers to 1e-12."""

    @classmethod
    def setUpClass(cls):
        program = os.environ.get("BRDFFIT_FIT_REFERENCE")
        if not program:
            raise unittest.SkipTest("BRDFFIT_FIT_REFERENCE (the python_fit_reference "
                                    "program) is not set; ctest sets it")
        cls.tmp = tempfile.TemporaryDirectory()
        cls.csv = os.path.join(cls.tmp.name, "synthetic.csv")
        cls.reference = run_reference(program, cls.csv)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def compare(self, grid, config):
        model_name, options = REFERENCE_CONFIGS[config]
        want = self.reference[config]
        with Model.builtin(model_name) as model, Fit(grid, model, **options) as fit:
            fit.run()
            self.assertLess(support.relative_difference(fit.params, want["params"], 1e-300),
                            1e-12)
            self.assertLess(support.relative_difference(fit.std_errors, want["std_errors"],
                                                        1e-300), 1e-12)
            errors = [fit.error(m) for m in ("rms", "ngan", "cost")]
            self.assertLess(support.relative_difference(errors, want["errors"]), 1e-12)
            iterations, stop, passes = want["run"]
            self.assertEqual(fit.iterations, iterations)
            self.assertEqual(fit.stop_reason, brdffit.STOP_REASONS[int(stop)])
            self.assertEqual(fit.passes, passes)

    def test_configs_on_the_loaded_csv(self):
        self.assertEqual(set(self.reference), set(REFERENCE_CONFIGS))
        grid = Grid.load_csv(self.csv)
        self.assertEqual(grid.shape, (9, 17, 19, 3))
        for config in REFERENCE_CONFIGS:
            with self.subTest(config=config):
                self.compare(grid, config)

    def test_configs_on_a_grid_from_arrays(self):
        loaded = Grid.load_csv(self.csv)
        grid = Grid.from_regular(*loaded.axes, loaded.values)
        for config in REFERENCE_CONFIGS:
            with self.subTest(config=config):
                self.compare(grid, config)

    def test_fixed_parameter_held(self):
        self.assertEqual(self.reference["joint"]["params"][1], 0.25)


class Recovery(unittest.TestCase):
    def setUp(self):
        self.builtin = Model.builtin("ashikhmin-shirley")
        self.truth = self.builtin.pack_params(TRUTH, 3)
        self.grid = support.model_grid(self.builtin, self.truth, 3)

    def test_builtin_auto(self):
        fit = Fit(self.grid, self.builtin).run()
        # the built-in model's passes read single-precision weights, lobe
        # geometry and values: the noise-free data's fit ends within 1e-7
        # of the truth (relative), not at rounding level
        self.assertLess(support.relative_difference(fit.params, self.truth), 1e-7)
        by_name = fit.params_by_name()
        self.assertAlmostEqual(by_name["ns"], 120.0, delta=120.0 * 1e-7)
        np.testing.assert_allclose(by_name["cd"], TRUTH["cd"], rtol=1e-7)
        self.assertIn(fit.stop_reason, brdffit.STOP_REASONS)
        # within 1e-6 of the values' own rms (the peak reaches ~10)
        scale = float(np.sqrt(np.mean(self.grid.values ** 2)))
        self.assertLess(fit.error("rms"), 1e-6 * scale)
        self.assertLess(fit.error("rms", channel=2), 1e-6 * scale)

    def test_objectives(self):
        """Every objective recovers the data's own parameters; the cost is the
        objective's, the same parameters giving different costs."""
        costs = {}
        for objective in brdffit.fit.OBJECTIVES:
            with self.subTest(objective=objective):
                fit = Fit(self.grid, self.builtin, objective=objective).run()
                self.assertEqual(fit.objective, objective)
                self.assertLess(support.relative_difference(fit.params, self.truth), 1e-6)
                joint = Fit(self.grid, self.builtin, objective=objective, pipeline="joint",
                            start=self.truth * 1.2).run()
                self.assertLess(support.relative_difference(joint.params, self.truth), 1e-6)
                off = Fit(self.grid, self.builtin, objective=objective, pipeline="joint",
                          start=self.truth * 1.2, max_iterations=1).run()
                costs[objective] = off.error("cost")
        self.assertEqual(len(set(costs.values())), len(costs))
        # the default minimises the cube root: the same cost at the same point
        default = Fit(self.grid, self.builtin, pipeline="joint", start=self.truth * 1.2,
                      max_iterations=1).run()
        self.assertEqual(default.error("cost"), costs["cube-root"])
        fit = Fit(self.grid, self.builtin)
        self.assertEqual(fit.objective, "cube-root")
        fit.objective = 1
        self.assertEqual(fit.objective, "log")
        with self.assertRaises(ValueError):
            fit.objective = "absolute"
        with self.assertRaises(BrdffitError) as cm:
            fit.objective = 4
        self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)

    def test_plausible(self):
        """On by default; off, an albedo above 1 is fitted as it is."""
        truth = self.builtin.pack_params({"ns": 80.0, "cd": [1.6, 0.3, 0.2],
                                          "cs": [0.2, 0.2, 0.2]}, 3)
        grid = support.model_grid(self.builtin, truth, 3)
        fit = Fit(grid, self.builtin)
        self.assertEqual(fit.plausible, 1)
        p = fit.run().params_by_name()
        self.assertLessEqual(p["cd"][0], 1.0)
        off = Fit(grid, self.builtin, plausible=False).run()
        self.assertEqual(off.plausible, 0)
        self.assertEqual(Fit(grid, self.builtin, plausible=2).plausible, 2)
        self.assertAlmostEqual(off.params_by_name()["cd"][0], 1.6, delta=1e-6)
        self.assertIn("albedo-above-1", [name for name, _ in off.warnings()])

    def test_python_model_auto_and_joint(self):
        model = support.python_as_model()
        reference = Fit(self.grid, self.builtin).run().params
        for pipeline in ("auto", "joint", "two-stage"):
            with self.subTest(pipeline=pipeline):
                fit = Fit(self.grid, model, pipeline=pipeline, start={"ns": 80.0}).run()
                self.assertLess(support.relative_difference(fit.params, self.truth), 1e-7)
                self.assertLess(support.relative_difference(fit.params, reference), 1e-7)

    def test_python_model_noisy_matches_builtin(self):
        rng = np.random.RandomState(11)
        noisy = Grid.from_regular(*support.small_axes(),
                                  self.grid.values * (1.0 + 0.05 * rng.uniform(-1, 1, (660, 3))))
        a = Fit(noisy, self.builtin).run()
        b = Fit(noisy, support.python_as_model()).run()
        self.assertLess(support.relative_difference(b.params, a.params), 1e-7)
        # the built-in fit's optimum moves with its single-precision inputs
        self.assertAlmostEqual(b.error("rms") / a.error("rms"), 1.0, places=6)

    def test_threads(self):
        model = support.python_as_model()
        one = Fit(self.grid, model, threads=1).run()
        for threads in (2, 4):
            with self.subTest(threads=threads):
                fit = Fit(self.grid, model, threads=threads)
                self.assertEqual(fit.threads, threads)
                fit.run()
                self.assertLess(support.relative_difference(fit.params, one.params), 1e-10)
        fit = Fit(self.grid, self.builtin, threads=4).run()
        self.assertLess(support.relative_difference(fit.params, one.params), 1e-7)
        with self.assertRaises(BrdffitError) as cm:
            Fit(self.grid, self.builtin, threads=0)
        self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)
        self.assertEqual(cm.exception.message, "value 0 out of range for fit setting 5")

    def test_history_non_increasing(self):
        rng = np.random.RandomState(5)
        noisy = Grid.from_regular(*support.small_axes(),
                                  self.grid.values * (1.0 + 0.05 * rng.uniform(-1, 1, (660, 3))))
        fit = Fit(noisy, self.builtin, pipeline="joint",
                  start={"ns": 10.0, "cd": 0.05, "cs": 1.0}).run()
        cost, lam = fit.history()
        self.assertEqual(cost.size, fit.iterations + 1)
        self.assertEqual(lam.size, cost.size)
        self.assertGreater(fit.iterations, 3)
        self.assertTrue(np.all(np.diff(cost) <= 0.0), cost)
        self.assertLess(cost[-1], cost[0])
        self.assertTrue(np.all(lam > 0.0))

    def test_warnings(self):
        self.assertEqual(Fit(self.grid, self.builtin).run().warnings(), [])
        self.assertEqual(Fit(self.grid, self.builtin).warnings(), [])
        short = Fit(self.grid, self.builtin, pipeline="joint", max_iterations=1).run()
        self.assertEqual(short.stop_reason, "max-iterations")
        self.assertEqual(short.warnings(), [
            ("iteration-limit", "the last optimizer run ended at its iteration limit")])

    def test_shader(self):
        fit = Fit(self.grid, self.builtin).run()
        p = fit.params_by_name()
        rs, cd, cs = fit.shader()
        self.assertAlmostEqual(rs, max(p["cs"]), places=12)
        np.testing.assert_allclose(cs, p["cs"] / rs, rtol=1e-12)
        np.testing.assert_allclose(cd, p["cd"] / (1.0 - rs), rtol=1e-12)
        lambert = Fit(self.grid, Model.builtin("lambert")).run()
        with self.assertRaises(BrdffitError) as cm:
            lambert.shader()
        self.assertEqual(cm.exception.status, Status.E_UNSUPPORTED)

    def test_callback_and_cancel(self):
        seen = []

        def stop_at_two(info):
            seen.append(info)
            return info.iteration >= 2
        start = {"ns": 10.0}
        fit = Fit(self.grid, self.builtin, pipeline="joint", start=start,
                  callback=stop_at_two).run()
        self.assertEqual(fit.stop_reason, "callback")
        self.assertEqual(fit.iterations, 2)
        self.assertEqual([i.iteration for i in seen], [1, 2])
        self.assertEqual(seen[-1].x.size, 7)

        fit.set_callback(lambda info: fit.cancel())
        fit.run()
        self.assertEqual(fit.stop_reason, "cancelled")

        def broken(info):
            raise KeyError("from the callback")
        fit.set_callback(broken)
        with self.assertRaises(KeyError):
            fit.run()
        fit.set_callback(None)
        fit.run()
        self.assertNotIn(fit.stop_reason, ("callback", "cancelled", "none"))


class OptionsAndErrors(unittest.TestCase):
    def setUp(self):
        self.model = Model.builtin("ashikhmin-shirley")
        self.grid = support.model_grid(self.model, self.model.pack_params(TRUTH, 3), 3)

    def test_defaults_and_round_trip(self):
        fit = Fit(self.grid, self.model)
        self.assertEqual(fit.pipeline, "auto")
        self.assertEqual(fit.cap, brdffit.DEFAULT_CAP)
        self.assertEqual(fit.weighting, Weighting.DEFAULT)
        self.assertEqual(fit.clearcoat, 0.0)
        self.assertEqual(fit.threads, 1)
        self.assertEqual(fit.objective, "cube-root")
        self.assertEqual(fit.plausible, 1)
        self.assertEqual(fit.param_count, 7)
        fit.configure(pipeline="two-stage", cap=1.0, weighting=Weighting.COSINE,
                      clearcoat=0.05, max_iterations=17)
        self.assertEqual((fit.pipeline, fit.cap, fit.weighting, fit.clearcoat,
                          fit.max_iterations),
                         ("two-stage", 1.0, Weighting.COSINE, 0.05, 17))
        with self.assertRaises(ValueError):
            fit.pipeline = "sideways"
        for name, value in (("cap", 2.0), ("clearcoat", 1.0), ("weighting", 4),
                            ("max_iterations", 0), ("pipeline", 3)):
            with self.subTest(option=name):
                with self.assertRaises(BrdffitError) as cm:
                    setattr(fit, name, value)
                self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)
                self.assertIn("out of range", cm.exception.message)

    def test_results_before_run(self):
        fit = Fit(self.grid, self.model)
        with self.assertRaises(BrdffitError) as cm:
            fit.params
        self.assertEqual(cm.exception.status, Status.E_NOT_READY)
        self.assertEqual(cm.exception.status_name, "BRDFFIT_E_NOT_READY")
        self.assertEqual(fit.stop_reason, "none")
        self.assertEqual(fit.history()[0].size, 0)

    def test_start_values(self):
        fit = Fit(self.grid, self.model, pipeline="joint")
        with self.assertRaises(BrdffitError) as cm:
            fit.set_start({"cd": -1.0})
        self.assertEqual(cm.exception.status, Status.E_RANGE)
        self.assertIn("cd", cm.exception.message)
        with self.assertRaises(ValueError):
            fit.set_start([1.0, 2.0])
        fit.set_start({"ns": 33.0})
        fit.set_fixed("ns")
        fit.run()
        self.assertEqual(fit.params_by_name()["ns"], 33.0)
        fit.set_fixed({"ns": False})
        fit.run()
        self.assertAlmostEqual(fit.params_by_name()["ns"], 120.0, delta=1e-4)
        with self.assertRaises(BrdffitError) as cm:
            fit.set_fixed(7)
        self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)

    def test_no_data_inside_the_cap(self):
        axes = (radians([20.0, 40.0]), radians([20.0, 40.0]), radians([0.0, 180.0]))
        grid = Grid.from_regular(*axes, np.ones((8, 1)))
        fit = Fit(grid, Model.builtin("lambert"), cap=radians(10.0))
        with self.assertRaises(BrdffitError) as cm:
            fit.run()
        self.assertEqual(cm.exception.status, Status.E_NO_DATA)
        self.assertTrue(cm.exception.message)

    def test_python_model_failure_in_fit(self):
        def broken(batch, params, nc):
            raise RuntimeError("model exploded")
        fit = Fit(self.grid, support.python_as_model("broken", broken))
        with self.assertRaises(BrdffitError) as cm:
            fit.run()
        self.assertEqual(cm.exception.status, Status.E_MODEL_FAILED)
        self.assertIsInstance(cm.exception.__cause__, RuntimeError)

    def test_fit_keeps_grid_and_model_alive(self):
        grid = support.model_grid(self.model, self.model.pack_params(TRUTH, 3), 3)
        model = support.python_as_model()
        fit = Fit(grid, model)
        grid.close()  # deferred: the fit still uses it
        self.assertTrue(grid.closed)
        with self.assertRaises(BrdffitError) as cm:
            grid.sample_count
        self.assertEqual(cm.exception.status, Status.E_BAD_HANDLE)
        with self.assertRaises(BrdffitError):
            Fit(grid, model)
        del grid, model
        gc.collect()
        fit.run()
        self.assertAlmostEqual(fit.params_by_name()["ns"], 120.0, delta=1e-4)
        fit.close()
        with self.assertRaises(BrdffitError) as cm:
            fit.params
        self.assertEqual(cm.exception.status, Status.E_BAD_HANDLE)

    def test_context_manager(self):
        with Fit(self.grid, self.model) as fit:
            fit.run()
        self.assertTrue(fit.closed)
        self.assertEqual(self.grid.sample_count, 660)  # the grid itself stays open


if __name__ == "__main__":
    unittest.main(verbosity=2)
