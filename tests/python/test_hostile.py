"""A hostile caller: what the binding must survive without crashing the
interpreter or losing an error (issue findings on the Python binding).

Closing or changing a fit during its run (from its callbacks and from
other threads), exceptions and Ctrl-C during a run, and arguments the C
library must never see: paths with NUL, complex numbers, transposed model
output, odd exception subclasses, non-buffer data, bytes names, and a
library that is not libbrdffit; a channel count beyond the joint fit's
limit, refused with a named status."""

import ctypes.util
import os
import signal
import subprocess
import sys
import threading
import unittest

import numpy as np

import brdffit
from brdffit import BrdffitError, Fit, Grid, Model, Status

import support

TRUTH = {"ns": 120.0, "cd": [0.3, 0.2, 0.1], "cs": [0.4, 0.35, 0.3]}
START = {"ns": 20.0, "cd": 0.5, "cs": 0.1}


class Fixture(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.model = Model.builtin("ashikhmin-shirley")
        cls.grid = support.model_grid(cls.model, cls.model.pack_params(TRUTH, 3), 3)

    def joint(self, model=None, **options):
        return Fit(self.grid, model or self.model, pipeline="joint", start=START, **options)


class CloseAndChangeDuringRun(Fixture):
    def expect_closed_run(self, fit):
        with self.assertRaises(BrdffitError) as cm:
            fit.run()
        self.assertEqual(cm.exception.status, Status.E_BAD_HANDLE)
        self.assertTrue(fit.closed)
        with self.assertRaises(BrdffitError) as cm:
            fit.params
        self.assertEqual(cm.exception.status, Status.E_BAD_HANDLE)

    def test_close_from_the_iteration_callback(self):
        f = self.joint()
        f.set_callback(lambda info: f.close())
        self.expect_closed_run(f)

    def test_close_from_a_python_model(self):
        calls = []

        def closing(batch, params, nc):
            calls.append(1)
            if len(calls) == 4:
                f.close()
            return support.python_as_eval(batch, params, nc)
        f = self.joint(support.python_as_model("closing", closing))
        self.expect_closed_run(f)

    def test_close_from_another_thread(self):
        f = self.joint()

        def callback(info):
            t = threading.Thread(target=f.close)
            t.start()
            t.join()
        f.set_callback(callback)
        self.expect_closed_run(f)
        f.close()  # idempotent

    def test_changes_from_another_thread_are_refused(self):
        f = self.joint()
        seen = []

        def change():
            for call in (lambda: f.set_callback(None), lambda: f.set_callback(print),
                         lambda: setattr(f, "cap", 0.5), lambda: f.set_start(None),
                         lambda: f.params):
                try:
                    call()
                    seen.append("accepted")
                except BrdffitError as exc:
                    seen.append(exc.status)

        def callback(info):
            if not seen:
                t = threading.Thread(target=change)
                t.start()
                t.join()
        f.set_callback(callback)
        f.run()
        self.assertEqual(seen, [Status.E_INVALID_ARGUMENT] * 5)
        self.assertLess(abs(f.params_by_name()["ns"] - 120.0), 1e-3)
        f.cap = 0.5  # after the run, changes are accepted again
        self.assertEqual(f.cap, 0.5)

    def test_changes_from_the_callback_stop_the_run(self):
        f = self.joint()
        f.set_callback(lambda info: f.set_callback(None))
        with self.assertRaises(BrdffitError) as cm:
            f.run()
        self.assertEqual(cm.exception.status, Status.E_INVALID_ARGUMENT)
        self.assertIn("running", cm.exception.message)


class ExceptionsStopTheRun(Fixture):
    def raising_model(self, exc_type, after):
        """A Python model that raises at every trial point of the LM run (a
        call without the Jacobian) after its first `after` calls, which the
        library alone would take as rejected steps; counts its raises."""
        raised = []

        def model(batch, params, nc):
            model.calls += 1
            if model.calls > after and not batch["want_jacobian"]:
                exc = exc_type("raised at call %d" % model.calls)
                raised.append(exc)
                raise exc
            return support.python_as_eval(batch, params, nc)
        model.calls = 0
        return support.python_as_model("raising", model), raised

    def test_exception_at_a_trial_point(self):
        for pipeline in ("joint", "two-stage"):
            for threads in (1, 4):
                with self.subTest(pipeline=pipeline, threads=threads):
                    m, raised = self.raising_model(NameError, 6)
                    f = Fit(self.grid, m, pipeline=pipeline, start=START, threads=threads)
                    with self.assertRaises(BrdffitError) as cm:
                        f.run()
                    self.assertEqual(cm.exception.status, Status.E_MODEL_FAILED)
                    self.assertIs(cm.exception.__cause__, raised[0])
                    # the first exception stopped the run: a pass or two more at most
                    self.assertLessEqual(len(raised), 8)

    def test_keyboard_interrupt_in_a_python_model(self):
        for threads in (1, 4):
            with self.subTest(threads=threads):
                calls = []

                def interrupting(batch, params, nc):
                    calls.append(1)
                    if len(calls) == interrupting.at:
                        os.kill(os.getpid(), signal.SIGINT)
                    return support.python_as_eval(batch, params, nc)
                interrupting.at = 0
                f = self.joint(support.python_as_model("ctrl-c", interrupting), threads=threads)
                f.run()
                full, interrupting.at = len(calls), 6
                del calls[:]
                with self.assertRaises(KeyboardInterrupt):
                    f.run()
                self.assertEqual(f.stop_reason, "cancelled")
                self.assertLess(len(calls), full)

    def test_sigint_while_the_library_runs(self):
        # a run of a built-in model spends its time in C, where Python's
        # handler cannot run: the binding cancels the fit itself
        axes = (support.radians(np.linspace(0, 85, 60)), support.radians(np.linspace(0, 85, 80)),
                support.radians(np.linspace(0, 180, 120)))
        grid = support.model_grid(self.model, self.model.pack_params(TRUTH, 3), 3, axes)
        f = Fit(grid, self.model, pipeline="joint", start={"ns": 2.0, "cd": 0.9, "cs": 0.01})
        f.run()
        full = f.iterations
        timer = threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        with self.assertRaises(KeyboardInterrupt):
            f.run()
        timer.join()
        self.assertEqual(f.stop_reason, "cancelled")
        self.assertLess(f.iterations, full)


class Arguments(Fixture):
    def test_path_with_nul(self):
        for load in (Grid.load_csv, Grid.load_merl):
            with self.assertRaises(ValueError):
                load("data.csv\0ignored")

    def test_buffers_must_be_bytes(self):
        for bad in (5, 3.0, [1, 2]):
            with self.assertRaises(TypeError):
                Grid.load_csv_bytes(bad)
            with self.assertRaises(TypeError):
                Grid.load_merl_bytes(bad)
        g = Grid.load_csv_bytes(bytearray(b"theta_i,theta_o,phi_o,r\n0,0,0,0.1\n"))
        self.assertEqual(g.sample_count, 1)

    def test_bytes_names(self):
        self.assertEqual(Model.builtin(b"lambert").name, "lambert")
        with self.assertRaises(TypeError):
            Model.builtin(5)
        with self.assertRaises(ValueError):
            Model.builtin("lambert\0phong")
        self.assertEqual(self.model.param_index(b"cd"), 1)

    def test_complex_numbers_refused(self):
        p = self.model.pack_params(TRUTH, 3)
        with self.assertRaises(TypeError):
            self.model.eval_grid(self.grid, p + 1j)
        with self.assertRaises(TypeError):
            Grid.from_regular(*support.small_axes(), np.ones((660, 1)) * (1 + 1j))
        f = self.joint()
        with self.assertRaises(TypeError):
            f.cap = 0.5 + 0.5j
        with self.assertRaises(TypeError):
            f.set_start(p + 0j)

        def complex_model(batch, params, nc):
            values, jac = support.python_as_eval(batch, params, nc)
            return values + 1e-3j, jac
        m = support.python_as_model("complex", complex_model)
        with self.assertRaises(BrdffitError) as cm:
            m.eval_grid(self.grid, p)
        self.assertIsInstance(cm.exception.__cause__, TypeError)

    def test_transposed_output_refused(self):
        def transposed(batch, params, nc):
            values, jac = support.python_as_eval(batch, params, nc)
            return values.T, jac
        m = support.python_as_model("transposed", transposed)
        with self.assertRaises(BrdffitError) as cm:
            m.eval_grid(self.grid, self.model.pack_params(TRUTH, 3))
        self.assertEqual(cm.exception.status, Status.E_MODEL_FAILED)
        self.assertIsInstance(cm.exception.__cause__, ValueError)
        self.assertIn("shape", str(cm.exception.__cause__))

    def test_error_subclass_without_init(self):
        class Odd(BrdffitError):
            def __init__(self):  # never calls BrdffitError.__init__
                Exception.__init__(self, "odd")

        def odd(batch, params, nc):
            raise Odd()
        m = support.python_as_model("odd", odd)
        unraisable, hook = [], sys.unraisablehook
        sys.unraisablehook = unraisable.append  # an exception escaping the handler lands here
        try:
            with self.assertRaises(BrdffitError) as cm:
                m.eval_grid(self.grid, self.model.pack_params(TRUTH, 3))
        finally:
            sys.unraisablehook = hook
        self.assertEqual(unraisable, [])
        self.assertEqual(cm.exception.status, Status.E_MODEL_FAILED)
        self.assertIsInstance(cm.exception.__cause__, Odd)

    def test_wrong_library_is_an_oserror(self):
        libm = ctypes.util.find_library("m")
        if libm is None:
            self.skipTest("no libm to load instead")
        env = dict(os.environ, BRDFFIT_LIBRARY=libm)
        out = subprocess.run([sys.executable, "-c", "try:\n import brdffit\nexcept OSError as e:"
                              "\n print('OSError', e)\nexcept BaseException as e:\n print("
                              "type(e).__name__, e)"], env=env, capture_output=True, text=True)
        self.assertTrue(out.stdout.startswith("OSError"), out.stdout + out.stderr)
        self.assertIn("is not libbrdffit", out.stdout)


class Limits(unittest.TestCase):
    def test_channel_limit_is_named(self):
        # 2048 channels of Ashikhmin-Shirley: 4097 parameters at once
        axis = np.array([0.0, 0.5])
        grid = Grid.from_regular(axis, axis, np.array([0.0, 1.5]), np.full((8, 2048), 0.1))
        model = Model.builtin("ashikhmin-shirley")
        for pipeline in ("joint", "auto"):
            with self.assertRaises(BrdffitError) as cm:
                Fit(grid, model, pipeline=pipeline).run()
            self.assertEqual(cm.exception.status, Status.E_TOO_LARGE)
            self.assertIn("4096", str(cm.exception))
            self.assertIn("two-stage", str(cm.exception))


if __name__ == "__main__":
    unittest.main(verbosity=2)
