"""Model: built-in models against formulas computed in numpy, parameter
vectors, Python models (evaluation, Jacobian check, failures)."""

import gc
import math
import unittest

import numpy as np

from brdffit import BrdffitError, Model, ParamFlags, ParamInfo, Status

import support
from support import radians

# A few directions: (theta_i, phi_i, theta_o, phi_o), degrees; off the plane
# of incidence and near the mirror direction too.
DIRECTIONS = radians([
    [0.0, 180.0, 0.0, 0.0],
    [30.0, 180.0, 30.0, 0.0],     # mirror direction
    [30.0, 180.0, 25.0, 10.0],    # near it
    [45.0, 90.0, 60.0, 200.0],
    [70.0, 10.0, 20.0, 140.0],
    [15.0, -60.0, 80.0, 300.0],
]).T

TRUTH = {"ns": 120.0, "cd": [0.3, 0.2, 0.1], "cs": [0.4, 0.35, 0.3]}


class BuiltinModels(unittest.TestCase):
    def setUp(self):
        self.model = Model.builtin("ashikhmin-shirley")
        self.params = self.model.pack_params(TRUTH, 3)

    def test_builtin_names(self):
        names = Model.builtin_names()
        for name in ("lambert", "phong", "blinn-phong", "ashikhmin-shirley",
                     "ashikhmin-shirley-fresnel", "cook-torrance", "ggx", "ward", "lafortune",
                     "gltf"):
            self.assertIn(name, names)
        for name in names:
            with Model.builtin(name) as m:
                self.assertEqual(m.name, name)
                self.assertGreaterEqual(m.param_count, 1)

    def test_unknown_model(self):
        with self.assertRaises(BrdffitError) as cm:
            Model.builtin("no-such-model")
        self.assertEqual(cm.exception.status, Status.E_NOT_FOUND)
        self.assertIn("no-such-model", cm.exception.message)

    def test_param_info(self):
        info = self.model.param_info
        self.assertEqual([p.name for p in info], ["ns", "cd", "cs"])
        self.assertEqual(info[0].flags, ParamFlags.LOG_SCALE)
        self.assertGreater(info[0].lower, 0.0)
        for p in info[1:]:
            self.assertEqual(p.flags, ParamFlags.PER_CHANNEL | ParamFlags.LINEAR)
            self.assertEqual(p.lower, 0.0)
            self.assertTrue(p.per_channel)

    def test_vector_layout(self):
        m = self.model
        self.assertEqual(m.vector_size(3), 7)
        self.assertEqual(m.vector_size(1), 3)
        self.assertEqual(m.vector_index("ns", 2, 3), 0)
        self.assertEqual([m.vector_index("cd", c, 3) for c in range(3)], [1, 2, 3])
        self.assertEqual([m.vector_index(2, c, 3) for c in range(3)], [4, 5, 6])
        np.testing.assert_array_equal(self.params, [120.0, 0.3, 0.2, 0.1, 0.4, 0.35, 0.3])
        back = m.unpack_params(self.params, 3)
        self.assertEqual(back["ns"], 120.0)
        np.testing.assert_array_equal(back["cs"], TRUTH["cs"])
        np.testing.assert_array_equal(m.default_params(2), [50.0, 0.2, 0.2, 0.2, 0.2])
        with self.assertRaises(BrdffitError) as cm:
            m.param_index("nope")
        self.assertEqual(cm.exception.status, Status.E_NOT_FOUND)
        with self.assertRaises(BrdffitError) as cm:
            m.vector_index("cd", 3, 3)
        self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)

    def test_ashikhmin_shirley_matches_formula(self):
        got = self.model.eval_angles(*DIRECTIONS, self.params)
        want = support.as_reference(*DIRECTIONS, TRUTH["ns"], TRUTH["cd"], TRUTH["cs"])
        self.assertEqual(got.shape, (3, DIRECTIONS.shape[1]))
        self.assertLess(support.relative_difference(got, want), 1e-13)

    def test_ashikhmin_shirley_jacobian_matches_formula(self):
        values, jac = self.model.eval_angles(*DIRECTIONS, self.params, jacobian=True)
        self.assertEqual(jac.shape, (3, 3, DIRECTIONS.shape[1]))
        lobe, dlobe = support.as_lobe(TRUTH["ns"], *support.geometry(*DIRECTIONS))
        cs = np.array(TRUTH["cs"])[:, None]
        self.assertLess(support.relative_difference(jac[0], cs * dlobe), 1e-12)
        np.testing.assert_allclose(jac[1], 1.0 / math.pi, rtol=1e-15)
        self.assertLess(support.relative_difference(jac[2], np.broadcast_to(lobe, (3, 6))),
                        1e-13)
        # Values are linear in the colours: value = sum of colour * derivative.
        np.testing.assert_allclose(values, jac[1] * np.array(TRUTH["cd"])[:, None] +
                                   jac[2] * cs, rtol=1e-14)

    def test_eval_grid_equals_eval_angles(self):
        grid = support.model_grid(self.model, self.params, 3)
        whole = self.model.eval_grid(grid, self.params)
        np.testing.assert_array_equal(whole, grid.values.T)
        part, jac = self.model.eval_grid(grid, self.params, first=10, count=5, jacobian=True)
        ti, pi, to, po = grid.sample_angles()
        again, jac2 = self.model.eval_angles(ti[10:15], pi[10:15], to[10:15], po[10:15],
                                             self.params, 3, jacobian=True)
        np.testing.assert_array_equal(part, again)
        np.testing.assert_array_equal(jac, jac2)

    def test_check_jacobian(self):
        grid = support.model_grid(self.model, self.params, 3)
        rep = self.model.check_jacobian(grid, self.params)
        self.assertLess(rep.worst_error, 1e-5)
        self.assertIn(rep.param_name, ("ns", "cd", "cs"))

    def test_bad_input(self):
        with self.assertRaises(BrdffitError) as cm:
            self.model.eval_angles(2.0, 0.0, 0.1, 0.0, self.params)
        self.assertEqual(cm.exception.status, Status.E_RANGE)
        with self.assertRaises(ValueError):
            self.model.eval_angles(0.1, 0.0, 0.1, 0.0, self.params[:-1], n_channels=3)
        with self.assertRaises(BrdffitError) as cm:
            self.model.vector_size(0)
        self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)


class PythonModels(unittest.TestCase):
    def setUp(self):
        self.builtin = Model.builtin("ashikhmin-shirley")
        self.params = self.builtin.pack_params(TRUTH, 3)
        self.grid = support.model_grid(self.builtin, self.params, 3)

    def test_matches_builtin(self):
        model = support.python_as_model()
        self.assertEqual(model.name, "python-as")
        self.assertEqual(model.param_info, support.AS_PARAMS)
        got, jac = model.eval_angles(*DIRECTIONS, self.params, jacobian=True)
        want, wjac = self.builtin.eval_angles(*DIRECTIONS, self.params, jacobian=True)
        self.assertLess(support.relative_difference(got, want), 1e-13)
        self.assertLess(support.relative_difference(jac, wjac, 1e-12), 1e-12)
        values = model.eval_grid(self.grid, self.params)
        self.assertLess(support.relative_difference(values, self.grid.values.T), 1e-13)

    def test_jacobian_check(self):
        model = support.python_as_model()
        rep = model.check_jacobian(self.grid, self.params)
        self.assertLess(rep.worst_error, 1e-5)

    def test_jacobian_check_finds_a_wrong_derivative(self):
        def wrong(batch, params, nc):
            values, jac = support.python_as_eval(batch, params, nc)
            if jac is not None:
                jac[0] *= 1.01
            return values, jac
        rep = support.python_as_model("wrong", wrong).check_jacobian(self.grid, self.params)
        self.assertEqual(rep.param_name, "ns")
        self.assertGreater(rep.worst_error, 5e-3)
        self.assertAlmostEqual(rep.analytic / rep.numeric, 1.01, places=4)

    def test_model_outlives_its_function(self):
        def make():
            scale = 2.0

            def lambert(batch, params, nc):
                return np.repeat(scale * params[:, None] / math.pi, batch["n"], axis=1), None
            return Model.custom("lambert2", [("cd", ParamFlags.PER_CHANNEL, 0, 10, 0.5)],
                                lambert)
        model = make()
        gc.collect()
        v = model.eval_angles(DIRECTIONS[0], DIRECTIONS[1], DIRECTIONS[2], DIRECTIONS[3],
                              [0.25, 0.5], n_channels=2)
        np.testing.assert_allclose(v, np.array([[0.5], [1.0]]) / math.pi *
                                   np.ones((1, DIRECTIONS.shape[1])), rtol=1e-15)

    def test_exception_becomes_model_failure(self):
        def broken(batch, params, nc):
            raise ZeroDivisionError("broken model")
        model = support.python_as_model("broken", broken)
        with self.assertRaises(BrdffitError) as cm:
            model.eval_angles(*DIRECTIONS, self.params)
        e = cm.exception
        self.assertEqual(e.status, Status.E_MODEL_FAILED)
        self.assertIn('"broken"', e.message)
        self.assertIn("BRDFFIT_E_CALLBACK_FAILED", e.message)
        self.assertIsInstance(e.__cause__, ZeroDivisionError)
        with self.assertRaises(BrdffitError):
            model.check_jacobian(self.grid, self.params)

    def test_model_returns_a_status(self):
        def domain(batch, params, nc):
            raise BrdffitError(Status.E_RANGE, "ns out of its domain")
        model = support.python_as_model("domain", domain)
        with self.assertRaises(BrdffitError) as cm:
            model.eval_grid(self.grid, self.params)
        self.assertEqual(cm.exception.status, Status.E_MODEL_FAILED)
        self.assertIn("BRDFFIT_E_RANGE", cm.exception.message)

    def test_wrong_output_shapes(self):
        def short(batch, params, nc):
            return np.zeros(batch["n"]), None

        def no_jacobian(batch, params, nc):
            return support.python_as_eval(batch, params, nc)[0], None
        with self.assertRaises(BrdffitError) as cm:
            support.python_as_model("short", short).eval_angles(*DIRECTIONS, self.params)
        self.assertIsInstance(cm.exception.__cause__, ValueError)
        m = support.python_as_model("nojac", no_jacobian)
        m.eval_angles(*DIRECTIONS, self.params)  # values alone are fine
        with self.assertRaises(BrdffitError) as cm:
            m.eval_angles(*DIRECTIONS, self.params, jacobian=True)
        self.assertIn("no Jacobian", str(cm.exception.__cause__))

    def test_nonfinite_output(self):
        def nan_model(batch, params, nc):
            return np.full((nc, batch["n"]), np.nan), None
        with self.assertRaises(BrdffitError) as cm:
            support.python_as_model("nan", nan_model).eval_angles(*DIRECTIONS, self.params)
        self.assertEqual(cm.exception.status, Status.E_NONFINITE)

    def test_invalid_definitions(self):
        ok = ParamInfo("a", ParamFlags.NONE, 0.0, 1.0, 0.5)
        cases = [
            [ok, ParamInfo("a", ParamFlags.NONE, 0.0, 1.0, 0.5)],    # duplicate name
            [ParamInfo("ns", ParamFlags.LOG_SCALE, 0.0, 10.0, 1.0)],  # log scale, lower 0
            [ParamInfo("a", ParamFlags.NONE, 1.0, 0.0, 0.5)],         # lower > upper
            [ParamInfo("c", ParamFlags.LINEAR, 0.0, 1.0, 0.5)],       # linear but shared
        ]
        for params in cases:
            with self.subTest(params=params):
                with self.assertRaises(BrdffitError) as cm:
                    Model.custom("bad", params, support.python_as_eval)
                self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)
                self.assertTrue(cm.exception.message)
        with self.assertRaises(ValueError):
            Model.custom("empty", [], support.python_as_eval)


if __name__ == "__main__":
    unittest.main(verbosity=2)
