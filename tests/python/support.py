"""Shared helpers of the Python binding tests: synthetic grids and an
Ashikhmin-Shirley model written directly in numpy (docs/models.md, eq. 4.28 of the thesis)."""

import math

import numpy as np

import brdffit

DOT_FLOOR = 1e-4


def radians(degrees):
    """Degrees to radians, as an array."""
    return np.asarray(degrees, dtype=np.float64) * (math.pi / 180.0)


def small_axes():
    """A small regular layout: theta_i 0..75 step 15, theta_o 0..75 step 7.5,
    phi_o 0..180 step 20 (6 * 11 * 10 = 660 samples)."""
    return (radians(np.arange(0.0, 76.0, 15.0)), radians(np.arange(0.0, 76.0, 7.5)),
            radians(np.arange(0.0, 181.0, 20.0)))


def grid_angles(axes):
    """Sample angles (theta_i, phi_i, theta_o, phi_o) of a regular grid, sample order."""
    ti, to, po = np.meshgrid(*axes, indexing="ij")
    ti, to, po = ti.reshape(-1), to.reshape(-1), po.reshape(-1)
    return ti, np.full_like(ti, math.pi), to, po


def model_grid(model, params, n_channels, axes=None):
    """A regular grid holding ``model`` evaluated at ``params`` (no noise)."""
    axes = small_axes() if axes is None else axes
    values = model.eval_angles(*grid_angles(axes), params, n_channels)
    return brdffit.Grid.from_regular(*axes, values.T)


def geometry(theta_i, phi_i, theta_o, phi_o):
    """The clamped dot products (docs/definitions.md, Geometry) of direction pairs."""
    l = np.stack([np.sin(theta_i) * np.cos(phi_i), np.sin(theta_i) * np.sin(phi_i),
                  np.cos(theta_i)])
    v = np.stack([np.sin(theta_o) * np.cos(phi_o), np.sin(theta_o) * np.sin(phi_o),
                  np.cos(theta_o)])
    h = l + v
    h = h / np.linalg.norm(h, axis=0)
    clamp = lambda x: np.clip(x, DOT_FLOOR, 1.0)  # noqa: E731
    return clamp(l[2]), clamp(v[2]), clamp(h[2]), clamp(np.sum(h * v, axis=0))


def as_lobe(ns, nl, nv, nh, hv):
    """(ns+1)/(8 pi) (n.h)^ns / ((h.v) max(n.l, n.v)) and its ns-derivative (4.29)."""
    denom = 8.0 * math.pi * hv * np.maximum(nl, nv)
    p = nh ** ns
    return (ns + 1.0) * p / denom, ((ns + 1.0) * p * np.log(nh) + p) / denom


def as_reference(theta_i, phi_i, theta_o, phi_o, ns, cd, cs):
    """Ashikhmin-Shirley (4.28) per channel: array (n_channels, n)."""
    nl, nv, nh, hv = geometry(theta_i, phi_i, theta_o, phi_o)
    lobe, _ = as_lobe(ns, nl, nv, nh, hv)
    cd = np.asarray(cd, dtype=np.float64)[:, None]
    cs = np.asarray(cs, dtype=np.float64)[:, None]
    return cd / math.pi + cs * lobe[None, :]


AS_PARAMS = [
    brdffit.ParamInfo("ns", brdffit.ParamFlags.LOG_SCALE, 1e-3, 1e6, 50.0),
    brdffit.ParamInfo("cd", brdffit.ParamFlags.PER_CHANNEL | brdffit.ParamFlags.LINEAR,
                      0.0, math.inf, 0.2),
    brdffit.ParamInfo("cs", brdffit.ParamFlags.PER_CHANNEL | brdffit.ParamFlags.LINEAR,
                      0.0, math.inf, 0.2),
]


def python_as_eval(batch, params, nc):
    """Ashikhmin-Shirley (4.28) as a Python model callback, from the batch
    geometry the library supplies (params: ns, cd[nc], cs[nc])."""
    ns, cd, cs = params[0], params[1:1 + nc], params[1 + nc:1 + 2 * nc]
    denom = 8.0 * math.pi * batch["hv"] * np.maximum(batch["nl"], batch["nv"])
    p = np.exp(ns * batch["log_nh"])
    lobe = (ns + 1.0) * p / denom
    values = cd[:, None] / math.pi + cs[:, None] * lobe[None, :]
    if not batch["want_jacobian"]:
        return values, None
    dlobe = (1.0 + (ns + 1.0) * batch["log_nh"]) * p / denom
    n = batch["n"]
    jac = np.empty((3, nc, n))
    jac[0] = cs[:, None] * dlobe[None, :]
    jac[1] = 1.0 / math.pi
    jac[2] = lobe[None, :]
    return values, jac


def python_as_model(name="python-as", eval_fn=python_as_eval):
    """The numpy Ashikhmin-Shirley model as a :class:`brdffit.Model`."""
    return brdffit.Model.custom(name, AS_PARAMS, eval_fn)


def relative_difference(a, b, floor=1e-300):
    """Largest |a - b| / max(|b|, floor) over two arrays."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), floor))) if a.size else 0.0
