"""The general optimizer and damping policies from Python: known minima in
residual and normal form, covariance against numpy, bounds, fixed
parameters, Python damping policies that imitate the built-in ones step for
step (in an optimizer and in a fit), errors and their exact status codes."""

import math
import pydoc
import unittest

import numpy as np

import brdffit
from brdffit import BrdffitError, DampingPolicy, Optimizer, PythonDamping, Status

import support

T = np.linspace(0.0, 1.0, 25)
NOISE = 0.01 * np.sin(37.0 * T)  # fixed, deterministic "noise"


def decay(y):
    """Residual form of a * exp(-b t) - y."""
    def fn(x, jacobian):
        e = np.exp(-x[1] * T)
        r = x[0] * e - y
        return r, (np.stack([e, -x[0] * T * e], axis=1) if jacobian else None)
    return fn


def decay_normal(y):
    """The same problem in normal-equation form."""
    residual = decay(y)

    def fn(x, derivatives):
        r, jac = residual(x, derivatives)
        if not derivatives:
            return float(r @ r), None, None
        return float(r @ r), jac.T @ jac, jac.T @ r
    return fn


def rosenbrock(x, jacobian):
    """Rosenbrock's function as two residuals (minimum (1, 1))."""
    r = np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])
    return r, (np.array([[-20.0 * x[0], 10.0], [-1.0, 0.0]]) if jacobian else None)


class PyMarquardt(PythonDamping):
    """Marquardt's policy (optim.h) in Python."""

    def __init__(self):
        super().__init__("py-marquardt")

    def start(self):
        return 1e-3

    def accepted(self, rho, lam):
        return lam * 0.1

    def rejected(self, rho, lam):
        return lam * 10.0


class PyNielsen(PythonDamping):
    """Nielsen's policy (optim.h) in Python, with its state nu in the object."""

    def __init__(self):
        super().__init__("py-nielsen")
        self.nu = None

    def start(self):
        self.nu = 2.0
        return 1e-3

    def accepted(self, rho, lam):
        q = 2.0 * rho - 1.0
        self.nu = 2.0
        return lam * max(1.0 / 3.0, 1.0 - q * q * q)

    def rejected(self, rho, lam):
        lam *= self.nu
        if self.nu < 1e150:
            self.nu *= 2.0
        return lam


class PyThesis(PythonDamping):
    """The thesis's policy in Python."""

    def start(self):
        return 1e-3

    def accepted(self, rho, lam):
        return max(lam * 0.5, 1e-4)

    def rejected(self, rho, lam):
        return min(lam * 2.0, 1.0)


class Failing(PyMarquardt):
    def rejected(self, rho, lam):
        raise ZeroDivisionError("policy bug")


class FailingOnAccept(PyMarquardt):
    def accepted(self, rho, lam):
        raise ZeroDivisionError("policy bug")


def run_rosenbrock(policy):
    opt = Optimizer(2, residuals=rosenbrock, n_rows=2, damping=policy)
    x = opt.run([-1.2, 1.0])
    return opt, x


class OptimizerTest(unittest.TestCase):
    def test_residual_form_recovers_known_parameters(self):
        opt = Optimizer(2, residuals=decay(2.0 * np.exp(-3.0 * T)), n_rows=T.size)
        x = opt.run([1.0, 1.0])
        np.testing.assert_allclose(x, [2.0, 3.0], rtol=1e-10)
        self.assertLess(opt.final_cost, 1e-20)
        self.assertGreater(opt.initial_cost, opt.final_cost)
        self.assertIn(opt.stop_reason, ("gradient", "zero-cost", "step", "cost"))
        self.assertGreaterEqual(opt.evaluations, opt.iterations)

    def test_normal_form_equals_residual_form(self):
        y = 2.0 * np.exp(-3.0 * T) + NOISE
        a, b = Optimizer(2, residuals=decay(y), n_rows=T.size), \
            Optimizer(2, normal=decay_normal(y), n_rows=T.size)
        xa, xb = a.run([1.0, 1.0]), b.run([1.0, 1.0])
        np.testing.assert_allclose(xb, xa, rtol=1e-9)
        self.assertAlmostEqual(b.final_cost / a.final_cost, 1.0, places=9)
        np.testing.assert_allclose(b.std_errors(), a.std_errors(), rtol=1e-6)

    def test_covariance_against_numpy(self):
        y = 2.0 * np.exp(-3.0 * T) + NOISE
        opt = Optimizer(2, residuals=decay(y), n_rows=T.size)
        x = opt.run([1.0, 1.0])
        r, jac = decay(y)(x, True)
        expected = (r @ r) / (T.size - 2) * np.linalg.inv(jac.T @ jac)
        np.testing.assert_allclose(opt.covariance(), expected, rtol=1e-6)
        np.testing.assert_allclose(opt.std_errors(), np.sqrt(np.diag(expected)), rtol=1e-6)
        self.assertGreater(opt.condition, 1.0)

    def test_bounds_and_fixed(self):
        fn = decay(2.0 * np.exp(-3.0 * T))
        opt = Optimizer(2, residuals=fn, n_rows=T.size, bounds=([0.0, 0.0], [10.0, 2.5]))
        x = opt.run([1.0, 1.0])
        self.assertEqual(x[1], 2.5)
        self.assertEqual(opt.covariance()[1, 1], 0.0)
        opt = Optimizer(2, residuals=fn, n_rows=T.size, fixed=[False, True])
        x = opt.run([1.0, 3.0])
        self.assertEqual(x[1], 3.0)
        self.assertAlmostEqual(x[0], 2.0, places=10)

    def test_settings_and_callback(self):
        opt = Optimizer(2, residuals=rosenbrock, n_rows=2, max_iterations=7, gtol=1e-12)
        self.assertEqual(opt.max_iterations, 7)
        self.assertEqual(opt.gtol, 1e-12)
        self.assertEqual(opt.scaling, "marquardt")
        opt.scaling = "levenberg"
        self.assertEqual(opt.scaling, "levenberg")
        opt.run([-1.2, 1.0])
        self.assertEqual((opt.iterations, opt.stop_reason), (7, "max-iterations"))
        seen = []
        opt.set_callback(lambda info: seen.append(info.iteration) or info.iteration == 3)
        opt.run([-1.2, 1.0])
        self.assertEqual((seen, opt.stop_reason, opt.iterations), ([1, 2, 3], "callback", 3))
        cost, lam = opt.history()
        self.assertEqual((cost.size, lam.size), (4, 4))

    def test_errors_have_exact_status(self):
        cases = [
            (lambda: Optimizer(0), Status.E_INVALID_ARGUMENT),
            (lambda: Optimizer(2).run([1.0, 1.0]), Status.E_NOT_READY),
            (lambda: Optimizer(2, residuals=rosenbrock, n_rows=2).run([math.nan, 1.0]),
             Status.E_NONFINITE),
            (lambda: Optimizer(2).set_bounds([1.0, 1.0], [0.0, 2.0]),
             Status.E_INVALID_ARGUMENT),
            (lambda: setattr(Optimizer(2), "gtol", -1.0), Status.E_INVALID_ARGUMENT),
        ]
        for make, status in cases:
            with self.assertRaises(BrdffitError) as ctx:
                make()
            self.assertEqual(ctx.exception.status, status, ctx.exception)
        with self.assertRaises(TypeError):
            Optimizer(2, tolerance=1.0)
        with self.assertRaises(ValueError):
            Optimizer(2, residuals=rosenbrock, n_rows=2).run([1.0])

    def test_problem_exception_is_raised(self):
        def bad(x, jacobian):
            raise KeyError("problem bug")
        with self.assertRaises(KeyError) as ctx:
            Optimizer(2, residuals=bad, n_rows=2).run([0.0, 0.0])
        self.assertEqual(ctx.exception.__cause__.status, Status.E_CALLBACK_FAILED)

        calls = []

        def later(x, jacobian):  # fails at the first trial point
            calls.append(1)
            if len(calls) > 2:
                raise KeyError("later")
            return rosenbrock(x, jacobian)
        opt = Optimizer(2, residuals=later, n_rows=2)
        with self.assertRaises(KeyError):
            opt.run([-1.2, 1.0])
        self.assertEqual(opt.stop_reason, "cancelled")

    def test_docs(self):
        text = pydoc.render_doc(brdffit.Optimizer)
        self.assertIn("residual form", text.lower())
        self.assertIn("set_normal", text)
        self.assertTrue(brdffit.image.texture.__doc__)


class DampingTest(unittest.TestCase):
    def test_python_policies_imitate_the_builtin_ones(self):
        for name, policy in (("marquardt", PyMarquardt()), ("nielsen", PyNielsen()),
                             ("thesis", PyThesis("py-thesis"))):
            ref, x_ref = run_rosenbrock(DampingPolicy.builtin(name))
            got, x_got = run_rosenbrock(policy)
            _, lam = ref.history()
            self.assertTrue(np.any(np.diff(lam) > 0), "%s: no rejected step" % name)
            self.assertEqual(got.iterations, ref.iterations, name)
            np.testing.assert_array_equal(x_got, x_ref)
            for a, b in zip(got.history(), ref.history()):
                np.testing.assert_array_equal(a, b)
            np.testing.assert_allclose(x_got, [1.0, 1.0], rtol=1e-8)

    def test_policies_differ(self):
        a, _ = run_rosenbrock("marquardt")
        b, _ = run_rosenbrock("thesis")
        self.assertFalse(np.array_equal(a.history()[1], b.history()[1]))
        c, _ = run_rosenbrock(None)
        d, _ = run_rosenbrock("nielsen")
        np.testing.assert_array_equal(c.history()[1], d.history()[1])
        with self.assertRaises(ValueError):
            DampingPolicy.builtin("fast")

    def test_policy_exception_is_raised(self):
        opt = Optimizer(2, residuals=rosenbrock, n_rows=2, damping=Failing())
        with self.assertRaises(ZeroDivisionError):
            opt.run([-1.2, 1.0])
        self.assertEqual(opt.stop_reason, "cancelled")

    def test_fit_with_python_policy_equals_builtin(self):
        model = brdffit.Model.builtin("ashikhmin-shirley")
        truth = model.pack_params({"ns": 60.0, "cd": [0.3, 0.2, 0.1],
                                   "cs": [0.2, 0.25, 0.3]}, 3)
        grid = support.model_grid(model, truth, 3)
        for name, policy in (("marquardt", PyMarquardt()), ("nielsen", PyNielsen())):
            ref = brdffit.Fit(grid, model, pipeline="joint")
            ref.set_damping(name)
            ref.run()
            got = brdffit.Fit(grid, model, pipeline="joint")
            got.set_damping(policy)
            got.run()
            self.assertEqual(got.iterations, ref.iterations, name)
            np.testing.assert_array_equal(got.params, ref.params)
            np.testing.assert_array_equal(got.history()[1], ref.history()[1])
            np.testing.assert_allclose(got.params, truth, rtol=1e-6)
        # the fit's first step is bounded (its start radius), so it need not
        # be rejected: the policy fails on an accepted step
        fit = brdffit.Fit(grid, model, pipeline="joint")
        fit.set_damping(FailingOnAccept())
        fit.set_start({"ns": 5.0})
        with self.assertRaises(ZeroDivisionError):
            fit.run()


if __name__ == "__main__":
    unittest.main()
