"""Grid: creation from arrays and files, properties, derived grids, errors."""

import math
import os
import struct
import tempfile
import unittest

import numpy as np

import brdffit
from brdffit import BrdffitError, Grid, Status, Weighting

from support import radians


def uneven_axes():
    return (radians([0.0, 10.0, 35.0]), radians([0.0, 5.0, 20.0, 60.0]),
            radians([0.0, 30.0, 90.0, 180.0, ]))


def direction(theta, phi):
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


class GridFromArrays(unittest.TestCase):
    def setUp(self):
        self.axes = uneven_axes()
        self.rng = np.random.RandomState(7)
        self.values = self.rng.uniform(0.0, 2.0, size=(3, 4, 4, 2))

    def test_regular_round_trip(self):
        with Grid.from_regular(*self.axes, self.values) as g:
            self.assertEqual(g.kind, "regular")
            self.assertEqual(g.sample_count, 48)
            self.assertEqual(len(g), 48)
            self.assertEqual(g.channel_count, 2)
            self.assertEqual(g.missing_count, 0)
            self.assertEqual(g.shape, (3, 4, 4, 2))
            for got, want in zip(g.axes, self.axes):
                np.testing.assert_array_equal(got, want)
            np.testing.assert_array_equal(g.values, self.values.reshape(48, 2))
            self.assertFalse(g.missing.any())
        self.assertTrue(g.closed)

    def test_layouts_agree(self):
        flat = Grid.from_regular(*self.axes, self.values.reshape(48, 2))
        np.testing.assert_array_equal(flat.values, self.values.reshape(48, 2))
        one = Grid.from_regular(*self.axes, self.values[..., 0])
        self.assertEqual(one.channel_count, 1)
        np.testing.assert_array_equal(one.values[:, 0], self.values[..., 0].reshape(-1))

    def test_sample_angles_follow_layout(self):
        g = Grid.from_regular(*self.axes, self.values)
        ti, pi, to, po = g.sample_angles()
        s = (2 * 4 + 1) * 4 + 3  # i=2, j=1, k=3
        self.assertEqual((ti[s], to[s], po[s]), (self.axes[0][2], self.axes[1][1],
                                                 self.axes[2][3]))
        np.testing.assert_array_equal(pi, np.full(48, math.pi))

    def test_missing_values(self):
        missing = np.zeros((48, 2), dtype=bool)
        missing[[3, 17, 40], [0, 1, 1]] = True
        g = Grid.from_regular(*self.axes, self.values.reshape(48, 2), missing=missing)
        self.assertEqual(g.missing_count, 3)
        np.testing.assert_array_equal(g.missing, missing)
        expect = self.values.reshape(48, 2).copy()
        expect[missing] = 0.0
        np.testing.assert_array_equal(g.values, expect)
        masked = np.ma.masked_array(self.values.reshape(48, 2), mask=missing)
        np.testing.assert_array_equal(Grid.from_regular(*self.axes, masked).missing, missing)

    def test_scattered_stored_sorted(self):
        ti = radians([60.0, 10.0, 30.0, 10.0])
        pi = radians([180.0, 0.0, 90.0, -45.0])
        to = radians([5.0, 40.0, 0.0, 20.0])
        po = radians([0.0, 10.0, 20.0, 300.0])
        values = np.array([[1.0], [2.0], [3.0], [4.0]])
        g = Grid.from_scattered(ti, pi, to, po, values, weights=[1.0, 2.0, 3.0, 4.0])
        self.assertEqual(g.kind, "scattered")
        self.assertIsNone(g.axes)
        self.assertEqual(g.shape, (4, 1))
        order = np.argsort(np.maximum(ti, to), kind="stable")  # 4, 3, 2, 1 -> [3, 2, 1, 0]
        # The grid gives the directions back (azimuths may come back in another turn).
        gti, gpi, gto, gpo = g.sample_angles()
        np.testing.assert_allclose(direction(gti, gpi), direction(ti, pi)[:, order], atol=1e-15)
        np.testing.assert_allclose(direction(gto, gpo), direction(to, po)[:, order], atol=1e-15)
        np.testing.assert_array_equal(g.values[:, 0], values[order, 0])
        # The solid-angle factor follows the given weights (up to the normalisation).
        w = g.weights(cap=math.pi / 2, flags=Weighting.SOLID_ANGLE)
        ratio = w / np.array([1.0, 2.0, 3.0, 4.0])[order]
        np.testing.assert_allclose(ratio, ratio[0], rtol=1e-15)
        self.assertGreater(ratio[0], 0.0)


class GridWeightsAndDerived(unittest.TestCase):
    def setUp(self):
        self.axes = (radians([0.0, 20.0, 40.0, 80.0]), radians([0.0, 30.0, 60.0, 85.0]),
                     radians([0.0, 90.0, 180.0]))
        rng = np.random.RandomState(3)
        self.values = rng.uniform(0.1, 1.0, size=(48, 3))
        self.grid = Grid.from_regular(*self.axes, self.values)
        self.ti, _, self.to, _ = self.grid.sample_angles()

    def test_active_count_and_plain_weights(self):
        cap = radians(50.0)
        inside = (self.ti <= cap) & (self.to <= cap)
        self.assertEqual(self.grid.active_count(cap), int(inside.sum()))
        np.testing.assert_array_equal(self.grid.weights(cap, Weighting.NONE),
                                      inside.astype(float))
        np.testing.assert_allclose(self.grid.weights(cap, Weighting.COSINE),
                                   np.where(inside, np.cos(self.ti), 0.0), rtol=1e-15)
        self.assertEqual(self.grid.weights().shape, (48,))

    def test_eval_at_nodes_and_between(self):
        s = (1 * 4 + 2) * 3 + 1
        got = self.grid.eval(self.axes[0][1], math.pi, self.axes[1][2], self.axes[2][1])
        np.testing.assert_allclose(got, self.values[s], rtol=1e-14)
        mid = self.grid.eval(self.axes[0][1], math.pi, self.axes[1][2], radians(45.0))
        np.testing.assert_allclose(mid, 0.5 * (self.values[s - 1] + self.values[s]), rtol=1e-12)
        both = self.grid.eval(self.axes[0][1], math.pi, self.axes[1][2],
                              [self.axes[2][1], radians(45.0)])
        self.assertEqual(both.shape, (2, 3))
        np.testing.assert_allclose(both[1], mid, rtol=1e-15)

    def test_channel_mean(self):
        mean = self.grid.channel_mean()
        self.assertEqual(mean.channel_count, 1)
        np.testing.assert_allclose(mean.values[:, 0], self.values.mean(axis=1), rtol=1e-14)

    def test_channel_mean_skips_missing(self):
        missing = np.zeros((48, 3), dtype=bool)
        missing[5, 0] = True
        missing[9, :] = True
        g = Grid.from_regular(*self.axes, self.values, missing=missing)
        mean = g.channel_mean()
        self.assertAlmostEqual(mean.values[5, 0], self.values[5, 1:].mean(), places=14)
        self.assertEqual(mean.missing_count, 1)
        self.assertTrue(mean.missing[9, 0])

    def test_clearcoat(self):
        r0 = 0.04
        coat = self.grid.clearcoat(r0)
        f = r0 + (1.0 - r0) * (1.0 - np.maximum(np.cos(self.ti), 1e-4)) ** 5
        np.testing.assert_allclose(coat.values, self.values / (1.0 - f)[:, None], rtol=1e-14)

    def test_closed_grid(self):
        g = Grid.from_regular(*self.axes, self.values)
        g.close()
        g.close()  # idempotent
        with self.assertRaises(BrdffitError) as cm:
            g.sample_count
        self.assertEqual(cm.exception.status, Status.E_BAD_HANDLE)


CSV_GRID = """# a 2 x 2 x 2 grid, rows out of order
theta_i,theta_o,phi_o,r,g
0,0,0,0.5,0.25
10,20,180,0.125,nan
0,20,180,1,2
10,0,0,3,
0,0,180,4,5
0,20,0,6,7
10,0,180,8,9
10,20,0,10,11
"""


class GridFromCsv(unittest.TestCase):
    def check_csv_grid(self, g):
        self.assertEqual(g.kind, "regular")
        self.assertEqual(g.shape, (2, 2, 2, 2))
        for got, deg in zip(g.axes, ([0.0, 10.0], [0.0, 20.0], [0.0, 180.0])):
            np.testing.assert_allclose(got, radians(deg), rtol=1e-15)
        self.assertEqual(g.missing_count, 2)
        expect = np.array([[0.5, 0.25], [4, 5], [6, 7], [1, 2],
                           [3, 0], [8, 9], [10, 11], [0.125, 0]])
        np.testing.assert_array_equal(g.values, expect)
        missing = np.zeros((8, 2), dtype=bool)
        missing[4, 1] = missing[7, 1] = True
        np.testing.assert_array_equal(g.missing, missing)

    def test_bytes_and_str(self):
        self.check_csv_grid(Grid.load_csv_bytes(CSV_GRID.encode()))
        self.check_csv_grid(Grid.load_csv_bytes(CSV_GRID))

    def test_file(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "grid.csv")
            with open(path, "w") as f:
                f.write(CSV_GRID)
            self.check_csv_grid(Grid.load_csv(path))

    def test_scattered_form(self):
        g = Grid.load_csv_bytes("theta_i,phi_i,theta_o,phi_o,v\n"
                                "30,180,10,0,0.5\n10,-90,5,45,0.25\n")
        self.assertEqual(g.kind, "scattered")
        ti, pi, to, po = g.sample_angles()
        np.testing.assert_allclose(direction(ti, pi), direction(radians([10.0, 30.0]),
                                                                radians([-90.0, 180.0])),
                                   atol=1e-15)
        np.testing.assert_allclose(direction(to, po), direction(radians([5.0, 10.0]),
                                                                radians([45.0, 0.0])),
                                   atol=1e-15)
        np.testing.assert_array_equal(g.values[:, 0], [0.25, 0.5])

    def test_malformed_number(self):
        data = "theta_i,theta_o,phi_o,r\n0,0,0,1\n0,0,90,abc\n"
        with self.assertRaises(BrdffitError) as cm:
            Grid.load_csv_bytes(data)
        e = cm.exception
        self.assertIs(type(e), BrdffitError)
        self.assertEqual(e.status, Status.E_PARSE)
        self.assertEqual(e.status_name, "BRDFFIT_E_PARSE")
        self.assertEqual(e.message, "line 3, column 4 (r): malformed number 'abc'")
        self.assertEqual(str(e), "BRDFFIT_E_PARSE: " + e.message)

    def test_errors_name_the_place(self):
        cases = [
            ("theta_i,theta_o,phi_o,r\n0,0,0,-inf\n", Status.E_RANGE, "line 2, column 4"),
            ("theta_i,theta_o,phi_o,r\n0,95,0,1\n", Status.E_RANGE, "line 2, column 2"),
            ("theta_i,theta_o,phi_o,r\n0,0,0\n", Status.E_PARSE, "line 2"),
            ("theta_i,theta_o,phi_o,r\n0,0,0,1\n0,0,90,1\n10,0,0,1\n",
             Status.E_INCOMPLETE_GRID, None),
            ("theta_i,theta_o,phi_o,r\n0,0,0,1\n0,0,0,2\n", Status.E_DUPLICATE, None),
            ("", Status.E_PARSE, None),
        ]
        for data, status, fragment in cases:
            with self.subTest(data=data):
                with self.assertRaises(BrdffitError) as cm:
                    Grid.load_csv_bytes(data)
                self.assertEqual(cm.exception.status, status)
                if fragment:
                    self.assertIn(fragment, cm.exception.message)

    def test_missing_file(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "does-not-exist.csv")
            with self.assertRaises(BrdffitError) as cm:
                Grid.load_csv(path)
        self.assertEqual(cm.exception.status, Status.E_IO)
        self.assertIn("does-not-exist.csv", cm.exception.message)


def merl_bytes(fill):
    """A complete MERL file with every cell set to ``fill`` (three channels)."""
    header = struct.pack("<3i", 90, 90, 180)
    return header + np.full(3 * 90 * 90 * 180, fill, dtype="<f8").tobytes()


def tensor_file(fields):
    """A tensor file of (name, numpy array) fields (float32 or uint8)."""
    header = b"tensor_file\0" + bytes([1, 0]) + struct.pack("<I", len(fields))
    size = len(header) + sum(2 + len(n) + 2 + 1 + 8 + 8 * a.ndim for n, a in fields)
    heads, blobs = b"", b""
    for name, a in fields:
        code = 1 if a.dtype == np.uint8 else 10
        heads += struct.pack("<H", len(name)) + name.encode() + struct.pack("<HBQ", a.ndim, code,
                                                                            size + len(blobs))
        heads += b"".join(struct.pack("<Q", n) for n in a.shape)
        blobs += a.astype("<f4" if code == 10 else "u1").tobytes()
    return header + heads + blobs


class GridFromAstmAndRgl(unittest.TestCase):
    def test_astm(self):
        g = Grid.load_astm_bytes("SOURCE x\nVARS theta_i,phi_i,theta_s,phi_s,R,G,B\n"
                                 "10,0,20,180,0.5,-0.01,0.2\n")
        self.assertEqual(g.kind, "scattered")
        np.testing.assert_array_equal(g.values, [[0.5, -0.01, 0.2]])

    def test_rgl_uniform_warp(self):
        # a constant VNDF warps the unit square onto itself; no jacobian
        # flag: f_r = stored value / cos theta_o
        n = 5
        f32 = np.float32
        fields = [("theta_i", np.array([0.0, 0.5], f32)), ("phi_i", np.array([0.0], f32)),
                  ("ndf", np.ones((2, 2), f32)), ("sigma", np.ones((2, 2), f32)),
                  ("vndf", np.ones((1, 2, 3, 3), f32)),
                  ("rgb", np.full((1, 2, 3, n, n), 0.25, f32)),
                  ("jacobian", np.array([0], np.uint8))]
        g = Grid.load_rgl_bytes(tensor_file(fields))
        self.assertEqual(g.kind, "scattered")
        self.assertEqual(g.channel_count, 3)
        to = g.sample_angles()[2]
        self.assertGreater(g.sample_count, 20)
        want = np.repeat((0.25 / np.cos(to))[:, None], 3, axis=1)
        np.testing.assert_allclose(g.values, want, rtol=1e-6)
        small = Grid.load_rgl_bytes(tensor_file(fields),
                                    axes=(radians([0, 30]), radians([0, 45]), radians([0, 180])))
        self.assertEqual(small.shape, (2, 2, 2, 3))


class GridFromMerl(unittest.TestCase):
    def test_constant_file(self):
        data = merl_bytes(1500.0)
        g = Grid.load_merl_bytes(data)
        self.assertEqual(g.kind, "scattered")
        self.assertEqual(g.channel_count, 3)
        self.assertGreater(g.sample_count, 1000000)
        # One value per channel: the MERL scale factors times 1500.
        for c, scale in enumerate((1.0, 1.15, 1.66)):
            p = g.values[:, c]
            np.testing.assert_allclose(p, scale, rtol=1e-15)
        regular = Grid.load_merl_bytes(data, regular=True)
        self.assertEqual(regular.shape, (19, 37, 36, 3))
        for got, want in zip(regular.axes, brdffit.default_axes()):
            np.testing.assert_array_equal(got, want)
        small = Grid.load_merl_bytes(data, axes=(radians([0, 30]), radians([0, 45]),
                                                 radians([0, 180])))
        self.assertEqual(small.shape, (2, 2, 2, 3))

    def test_file_and_truncation(self):
        data = merl_bytes(-1.0)  # nothing measured
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "empty.binary")
            with open(path, "wb") as f:
                f.write(data)
            with self.assertRaises(BrdffitError) as cm:
                Grid.load_merl(path)
            self.assertEqual(cm.exception.status, Status.E_NO_DATA)
        with self.assertRaises(BrdffitError) as cm:
            Grid.load_merl_bytes(data[:1000])
        self.assertEqual(cm.exception.status, Status.E_FORMAT)


class GridBadInput(unittest.TestCase):
    def setUp(self):
        self.axes = uneven_axes()
        self.values = np.ones((48, 1))

    def expect(self, status, fn, *args, **kwargs):
        with self.assertRaises(BrdffitError) as cm:
            fn(*args, **kwargs)
        self.assertEqual(cm.exception.status, status)
        self.assertTrue(cm.exception.message)
        return cm.exception

    def test_values_rejected_by_the_library(self):
        for bad in (np.nan, -np.inf, np.inf):
            v = self.values.copy()
            v[10, 0] = bad
            self.expect(Status.E_RANGE, Grid.from_regular, *self.axes, v)

    def test_negative_values_are_data(self):
        v = self.values.copy()
        v[10, 0] = -1e-3
        g = Grid.from_regular(*self.axes, v)
        self.assertEqual(g.values[10, 0], -1e-3)

    def test_axes_rejected_by_the_library(self):
        ti, to, po = self.axes
        self.expect(Status.E_INVALID_ARGUMENT, Grid.from_regular, ti[::-1], to, po, self.values)
        self.expect(Status.E_RANGE, Grid.from_regular, ti, to, po + 1.0, self.values)
        self.expect(Status.E_INVALID_ARGUMENT, Grid.from_regular, [], to, po, np.ones((0, 1)))

    def test_shapes_rejected_in_python(self):
        with self.assertRaises(ValueError):
            Grid.from_regular(*self.axes, np.ones((47, 1)))
        with self.assertRaises(ValueError):
            Grid.from_regular(*self.axes, self.values, missing=np.zeros(3, dtype=bool))
        with self.assertRaises(ValueError):
            Grid.from_scattered([0.1], [0.0, 1.0], [0.1], [0.0], [1.0])

    def test_operations_rejected(self):
        g = Grid.from_regular(*self.axes, self.values)
        self.expect(Status.E_INVALID_ARGUMENT, g.weights, cap=2.0)
        self.expect(Status.E_INVALID_ARGUMENT, g.weights, flags=8)
        self.expect(Status.E_INVALID_ARGUMENT, g.clearcoat, 1.0)
        self.expect(Status.E_INVALID_ARGUMENT, g.eval, math.nan, 0.0, 0.0, 0.0)
        s = Grid.from_scattered([0.1], [0.0], [0.2], [1.0], [1.0])
        self.expect(Status.E_UNSUPPORTED, s.eval, 0.1, 0.0, 0.2, 1.0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
