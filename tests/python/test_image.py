"""Pictures as numpy arrays (brdffit.image): textures against a numpy layout
of the encoded values, spheres of a Lambertian surface against the closed
form, plots, and bad input with its exact status code."""

import math
import unittest

import numpy as np

import brdffit
from brdffit import BrdffitError, Status, image

import support

BACKGROUND = (48, 48, 48)


def encode(v, gamma=1.0):
    """The byte image.h specifies: round(255 * clip(v, 0, 1)^(1/gamma))."""
    return np.floor(255.0 * np.clip(v, 0.0, 1.0) ** (1.0 / gamma) + 0.5).astype(np.uint8)


def texture_layout(values, shape):
    """A texture of stacked theta_i blocks, one row per theta_o and one column
    per signed azimuth (-phi_last .. 0 .. +phi_last, phi_0 = 0 shared)."""
    n_ti, n_to, n_po = shape
    v = values.reshape(n_ti, n_to, n_po, -1)
    signed = np.concatenate([v[:, :, :0:-1], v], axis=2)  # columns -phi_last .. +phi_last
    return signed.reshape(n_ti * n_to, 2 * n_po - 1, -1)


def lambert_sphere(cd, size, exposure=math.pi):
    """Lambert (cd / pi) lit and seen head-on: exposure * cd / pi * n_z; NaN outside."""
    c = (2.0 * np.arange(size) + 1.0) / size - 1.0
    u, w = np.meshgrid(c, -c)
    nz2 = 1.0 - u * u - w * w
    nz = np.sqrt(np.where(nz2 >= 0.0, nz2, np.nan))
    return exposure * np.asarray(cd)[None, None, :] / math.pi * nz[:, :, None]


class TextureTest(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(7)
        self.axes = support.small_axes()
        self.shape = tuple(a.size for a in self.axes)
        self.values = rng.uniform(0.0, 0.4, size=(int(np.prod(self.shape)), 3))
        self.grid = brdffit.Grid.from_regular(*self.axes, self.values)

    def test_measured_layout_and_encoding(self):
        pic = image.texture(self.grid, gamma=1.0, gain=2.0)
        n_ti, n_to, n_po = self.shape
        self.assertEqual(pic.shape, (n_ti * n_to, 2 * n_po - 1, 3))
        self.assertEqual(pic.dtype, np.uint8)
        self.assertEqual(image.texture_size(self.grid), (2 * n_po - 1, n_ti * n_to))
        expected = encode(2.0 * texture_layout(self.values, self.shape))
        np.testing.assert_array_equal(pic, expected)
        gamma = image.texture(self.grid)  # defaults: gain 3, gamma 2.2
        diff = np.abs(gamma.astype(int) - encode(3.0 * texture_layout(self.values, self.shape),
                                                 2.2))
        self.assertLessEqual(diff.max(), 1)

    def test_scale_and_blocks(self):
        pic = image.texture(self.grid, scale=2, block_columns=3, block_gap=1)
        n_ti, n_to, n_po = self.shape
        self.assertEqual(pic.shape, (2 * (2 * n_to) + 1, 3 * 2 * (2 * n_po - 1) + 2, 3))
        self.assertEqual(tuple(pic[0, 2 * (2 * n_po - 1)]), BACKGROUND)  # the gap

    def test_model_and_difference(self):
        model = brdffit.Model.builtin("ashikhmin-shirley")
        params = model.pack_params({"ns": 30.0, "cd": [0.3, 0.2, 0.1],
                                    "cs": [0.1, 0.1, 0.1]}, 3)
        grid = support.model_grid(model, params, 3)
        measured = image.texture(grid)
        np.testing.assert_array_equal(image.texture(grid, "model", model, params), measured)
        self.assertEqual(image.texture(grid, "difference", model, params).max(), 0)
        brighter = params.copy()
        brighter[1:4] *= 2.0  # the model now lies above the measurement: red, no blue
        diff = image.texture(grid, "difference", model, brighter)
        self.assertGreater(diff[:, :, 0].max(), 0)
        self.assertEqual(diff[:, :, 2].max(), 0)
        with self.assertRaises(ValueError):
            image.texture(grid, "model")

    def test_errors(self):
        scattered = brdffit.Grid.from_scattered([0.1], [0.0], [0.2], [0.0], [[0.5]])
        with self.assertRaises(BrdffitError) as ctx:
            image.texture(scattered)
        self.assertEqual(ctx.exception.status, Status.E_UNSUPPORTED)
        with self.assertRaises(BrdffitError) as ctx:
            image.texture(self.grid, scale=65)
        self.assertEqual(ctx.exception.status, Status.E_INVALID_ARGUMENT)
        with self.assertRaises(TypeError):
            image.texture(self.grid, brightness=2.0)


class SphereTest(unittest.TestCase):
    def test_model_sphere_is_the_closed_form(self):
        model = brdffit.Model.builtin("lambert")
        cd = [0.2, 0.5, 0.9]
        pic = image.sphere_model(model, cd, size=64, gamma=1.0)
        expected = lambert_sphere(cd, 64)
        inside = ~np.isnan(expected[:, :, 0])
        diff = np.abs(pic[inside].astype(float) - 255.0 * expected[inside])
        self.assertLessEqual(diff.max(), 0.5 + 1e-9)
        self.assertTrue(np.all(pic[~inside] == BACKGROUND))
        grey = image.sphere_model(model, [0.5], size=16)
        self.assertTrue(np.all(grey[..., 0] == grey[..., 2]))

    def test_measured_sphere_matches_the_model_sphere(self):
        model = brdffit.Model.builtin("lambert")
        cd = [0.2, 0.5, 0.9]
        axes = brdffit.default_axes()
        grid = support.model_grid(model, np.array(cd), 3, axes)
        measured = image.sphere_measured(grid, size=48, light_theta=0.3, light_phi=1.0)
        modelled = image.sphere_model(model, cd, 3, size=48, light_theta=0.3, light_phi=1.0)
        self.assertLessEqual(np.abs(measured.astype(int) - modelled).max(), 1)
        self.assertGreater(int(measured.max()), 100)

    def test_errors(self):
        model = brdffit.Model.builtin("lambert")
        with self.assertRaises(BrdffitError) as ctx:
            image.sphere_model(model, [0.5], size=8, light_theta=4.0)
        self.assertEqual(ctx.exception.status, Status.E_INVALID_ARGUMENT)
        with self.assertRaises(ValueError):
            image.sphere_model(model, [0.5], size=0)


class PlotTest(unittest.TestCase):
    def test_plot_colours(self):
        cost = 10.0 ** -np.arange(8.0)
        pic = image.plot(cost, 120, 80, log_y=True)
        self.assertEqual(pic.shape, (80, 120, 3))
        self.assertEqual(tuple(pic[0, 0]), BACKGROUND)
        colours = {tuple(p) for p in pic.reshape(-1, 3)}
        self.assertIn((255, 190, 40), colours)   # the curve
        self.assertIn((200, 200, 200), colours)  # the axes
        axes_only = image.plot([], 120, 80)
        self.assertNotIn((255, 190, 40), {tuple(p) for p in axes_only.reshape(-1, 3)})

    def test_errors(self):
        for values, width, status in (([1.0, math.nan], 64, Status.E_NONFINITE),
                                      ([1.0, 2.0], 8, Status.E_INVALID_ARGUMENT)):
            with self.assertRaises(BrdffitError) as ctx:
                image.plot(values, width, 64)
            self.assertEqual(ctx.exception.status, status)


if __name__ == "__main__":
    unittest.main()
