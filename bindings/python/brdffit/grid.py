"""The measurement grid: measured BRDF values over light and view directions."""

import ctypes
import enum
import os

import numpy as np

from . import _lib
from ._handle import Handle
from ._lib import DEFAULT_CAP, dptr, bptr, lib
from .errors import check, new_error

__all__ = ["Grid", "Weighting", "DEFAULT_CAP", "default_axes"]


class Weighting(enum.IntFlag):
    """Residual weight flags (``brdffit_weighting``)."""
    NONE = 0         #: every sample weighs 1
    SOLID_ANGLE = 1  #: solid angle of the view cell (regular) or the sample weight (scattered)
    COSINE = 2       #: cos theta_i
    DEFAULT = 3      #: both, as in the thesis


_KINDS = {1: "regular", 2: "scattered"}


def _vector(x, name):
    """A 1-D float64 C-contiguous copy-or-view of ``x``."""
    a = _lib.as_float64(x, name)
    if a.ndim == 0:
        a = a.reshape(1)
    if a.ndim != 1:
        raise ValueError("%s must be one-dimensional, got shape %s" % (name, a.shape))
    return a


def _axes_struct(theta_i, theta_o, phi_o):
    """A brdffit_axes over three 1-D arrays; returns (struct, arrays kept alive)."""
    arrays = (_vector(theta_i, "theta_i"), _vector(theta_o, "theta_o"), _vector(phi_o, "phi_o"))
    axes = _lib.Axes(dptr(arrays[0]), arrays[0].size, dptr(arrays[1]), arrays[1].size,
                     dptr(arrays[2]), arrays[2].size)
    return axes, arrays


def default_axes():
    """The thesis's measurement layout (``brdffit_axes_default``), radians.

    Returns:
        (theta_i, theta_o, phi_o): 19, 37 and 36 angles.
    """
    axes = lib.brdffit_axes_default().contents
    return (np.ctypeslib.as_array(axes.theta_i, (axes.n_theta_i,)).copy(),
            np.ctypeslib.as_array(axes.theta_o, (axes.n_theta_o,)).copy(),
            np.ctypeslib.as_array(axes.phi_o, (axes.n_phi_o,)).copy())


def _values_2d(values, n_samples, grid_shape=None):
    """Values as a C-contiguous (n_samples, n_channels) float64 array."""
    v = _lib.as_float64(values, "values")
    if grid_shape is not None and v.shape[:3] == grid_shape and v.ndim in (3, 4):
        v = v.reshape(n_samples, -1)
    elif v.ndim == 1:
        v = v.reshape(-1, 1)
    if v.ndim != 2 or v.shape[0] != n_samples or v.shape[1] < 1:
        raise ValueError("values must have shape (%d, n_channels)%s, got %s"
                         % (n_samples, "" if grid_shape is None else
                            " or %s + (n_channels,)" % (grid_shape,), np.shape(values)))
    return np.ascontiguousarray(v)


def _missing_mask(values, missing, shape):
    """The missing mask as uint8 of ``shape`` (None when nothing is missing)."""
    if missing is None and np.ma.isMaskedArray(values):
        missing = np.ma.getmaskarray(values)
    if missing is None:
        return None
    m = np.asarray(missing, dtype=bool)
    if m.size != shape[0] * shape[1]:
        raise ValueError("missing must have one entry per value (%d), got shape %s"
                         % (shape[0] * shape[1], m.shape))
    return np.ascontiguousarray(m.reshape(shape), dtype=np.uint8)


def _filled(values):
    """Masked arrays with their masked entries set to 0."""
    return np.ma.filled(values, 0.0) if np.ma.isMaskedArray(values) else values


def _path(path):
    """A file name for the C library; one with a NUL byte is refused (C
    would silently stop reading it there)."""
    encoded = os.fsencode(path)
    if b"\0" in encoded:
        raise ValueError("path contains a NUL character: %r" % (path,))
    return encoded


def _buffer(data, text_ok):
    """The bytes of a buffer argument: bytes-like objects (and str when
    text_ok); an int would make bytes(n) NUL bytes, so anything else is refused."""
    if text_ok and isinstance(data, str):
        return data.encode("utf-8")
    if isinstance(data, (bytes, bytearray, memoryview)):
        return bytes(data)
    raise TypeError("data must be bytes-like%s, got %s"
                    % (" or str" if text_ok else "", type(data).__name__))


class Grid(Handle):
    """An immutable measurement grid (``brdffit_grid``).

    Create one with :meth:`from_regular`, :meth:`from_scattered`,
    :meth:`load_csv`, :meth:`load_csv_bytes`, :meth:`load_merl`,
    :meth:`load_merl_bytes`, :meth:`load_astm`, :meth:`load_astm_bytes`,
    :meth:`load_rgl` or :meth:`load_rgl_bytes`. Angles are radians everywhere (the CSV and MERL
    files use degrees and half/difference angles; the loaders convert).
    Values are BRDF values in 1/sr, ``n_channels`` per sample.

    The grid copies everything it is given. Use it as a context manager or
    call :meth:`close` to free it early; a fit that uses the grid keeps it
    alive until the fit is closed.
    """

    _kind = "grid"

    def _destroy_ptr(self, ptr):
        lib.brdffit_grid_destroy(ptr)

    @classmethod
    def _create(cls, fn, *args):
        """Call a creation function ``fn(&out, *args, NULL allocator, &err)``."""
        out = ctypes.c_void_p()
        err = new_error()
        check(fn(ctypes.byref(out), *args, None, ctypes.byref(err)), err)
        return cls(out.value)

    # ---- creation ---------------------------------------------------------

    @classmethod
    def from_regular(cls, theta_i, theta_o, phi_o, values, missing=None):
        """A regular isotropic grid from memory (``brdffit_grid_create_regular``).

        Args:
            theta_i, theta_o, phi_o: the axes in radians, each strictly
                increasing; polar angles in [0, pi/2], azimuths in [0, pi].
            values: shape ``(n_samples, n_channels)`` with sample
                ``s = (i * n_theta_o + j) * n_phi_o + k``, or
                ``(n_theta_i, n_theta_o, n_phi_o, n_channels)``; a 1-D or
                3-D array is one channel. A numpy masked array marks its
                masked values missing.
            missing: None, or a boolean array with one entry per value;
                True marks a value missing (kept out of fits and weights).

        Raises:
            ValueError: for arrays of the wrong shape.
            BrdffitError: what the library rejects, e.g. ``E_RANGE`` for a
                non-finite value (negative values are data), ``E_INVALID_ARGUMENT`` for
                unsorted axes.
        """
        axes, arrays = _axes_struct(theta_i, theta_o, phi_o)
        shape = tuple(a.size for a in arrays)
        n = shape[0] * shape[1] * shape[2]
        v = _values_2d(_filled(values), n, shape)
        m = _missing_mask(values, missing, v.shape)
        return cls._create(lib.brdffit_grid_create_regular, ctypes.byref(axes), v.shape[1],
                           dptr(v), bptr(m))

    @classmethod
    def from_scattered(cls, theta_i, phi_i, theta_o, phi_o, values, missing=None,
                       weights=None):
        """A scattered grid from memory (``brdffit_grid_create_scattered``).

        Args:
            theta_i, phi_i, theta_o, phi_o: one light and view direction per
                sample, radians (polar angles in [0, pi/2], azimuths in
                [-2 pi, 2 pi]).
            values: shape ``(n_samples, n_channels)`` (1-D: one channel).
            missing: None, or a boolean array with one entry per value.
            weights: None for uniform solid-angle weights, or one finite
                weight >= 0 per sample.

        The grid stores the samples sorted by max(theta_i, theta_o), stable;
        :meth:`sample_angles` and :attr:`values` use that stored order.
        """
        angles = [_vector(a, name) for a, name in
                  ((theta_i, "theta_i"), (phi_i, "phi_i"), (theta_o, "theta_o"),
                   (phi_o, "phi_o"))]
        n = angles[0].size
        if any(a.size != n for a in angles):
            raise ValueError("the four angle arrays must have the same length")
        v = _values_2d(_filled(values), n)
        m = _missing_mask(values, missing, v.shape)
        w = None if weights is None else _vector(weights, "weights")
        if w is not None and w.size != n:
            raise ValueError("weights must have one entry per sample (%d)" % n)
        return cls._create(lib.brdffit_grid_create_scattered, n, *[dptr(a) for a in angles],
                           v.shape[1], dptr(v), bptr(m), dptr(w))

    @classmethod
    def load_csv(cls, path):
        """Load a CSV file (grid or scattered form; angles in degrees in the file).

        Raises:
            BrdffitError: ``E_IO`` for a missing file, ``E_PARSE`` /
                ``E_RANGE`` / ``E_INCOMPLETE_GRID`` / ``E_DUPLICATE`` with
                the line and column in the message.
        """
        return cls._create(lib.brdffit_load_csv, _path(path))

    @classmethod
    def load_csv_bytes(cls, data):
        """Load CSV text from memory (``bytes`` or ``str``); as :meth:`load_csv`."""
        data = _buffer(data, True)
        return cls._create(lib.brdffit_load_csv_buffer, data, len(data))

    @staticmethod
    def _merl_axes(axes, regular):
        if axes is None and not regular:
            return None, None
        if axes is None:
            return lib.brdffit_axes_default(), None
        struct, arrays = _axes_struct(*axes)
        return ctypes.byref(struct), (struct, arrays)

    @classmethod
    def load_merl(cls, path, axes=None, regular=False):
        """Load a MERL binary file.

        Args:
            path: the file.
            axes: None, or ``(theta_i, theta_o, phi_o)`` in radians to
                resample onto a regular grid with these axes.
            regular: with ``axes`` None, True resamples onto
                :func:`default_axes`; False (default) gives a scattered grid
                of every measured cell.
        """
        ax, keep = cls._merl_axes(axes, regular)
        grid = cls._create(lib.brdffit_load_merl, _path(path), ax)
        del keep
        return grid

    @classmethod
    def load_merl_bytes(cls, data, axes=None, regular=False):
        """Load MERL binary data from memory; as :meth:`load_merl`."""
        data = _buffer(data, False)
        ax, keep = cls._merl_axes(axes, regular)
        grid = cls._create(lib.brdffit_load_merl_buffer, data, len(data), ax)
        del keep
        return grid

    @classmethod
    def load_astm(cls, path):
        """Load an ASTM E1392 file (e.g. the Cornell measurements) as a
        scattered grid; see docs/formats.md.

        Raises:
            BrdffitError: ``E_IO``, ``E_PARSE`` / ``E_RANGE`` with the line
                and column in the message.
        """
        return cls._create(lib.brdffit_load_astm, _path(path))

    @classmethod
    def load_astm_bytes(cls, data):
        """Load ASTM E1392 text from memory (``bytes`` or ``str``); as :meth:`load_astm`."""
        if isinstance(data, str):
            data = data.encode("utf-8")
        data = bytes(data)
        return cls._create(lib.brdffit_load_astm_buffer, data, len(data))

    @classmethod
    def load_rgl(cls, path, axes=None, regular=False):
        """Load an RGL material database ``.bsdf`` file.

        Args:
            path: the file.
            axes: None, or ``(theta_i, theta_o, phi_o)`` in radians to
                resample onto a regular grid with these axes.
            regular: with ``axes`` None, True resamples onto
                :func:`default_axes`; False (default) gives the samples as
                measured, each weighted by its solid angle.
        """
        ax, keep = cls._merl_axes(axes, regular)
        grid = cls._create(lib.brdffit_load_rgl, _path(path), ax)
        del keep
        return grid

    @classmethod
    def load_rgl_bytes(cls, data, axes=None, regular=False):
        """Load an RGL ``.bsdf`` file from memory; as :meth:`load_rgl`."""
        data = bytes(data)
        ax, keep = cls._merl_axes(axes, regular)
        grid = cls._create(lib.brdffit_load_rgl_buffer, data, len(data), ax)
        del keep
        return grid

    # ---- properties ---------------------------------------------------------

    @property
    def kind(self):
        """``"regular"`` or ``"scattered"``."""
        return _KINDS[lib.brdffit_grid_get_kind(self._handle)]

    @property
    def sample_count(self):
        """Number of samples (direction pairs)."""
        return lib.brdffit_grid_sample_count(self._handle)

    def __len__(self):
        return self.sample_count

    @property
    def channel_count(self):
        """Number of channels per sample."""
        return lib.brdffit_grid_channel_count(self._handle)

    @property
    def missing_count(self):
        """Number of values marked missing."""
        return lib.brdffit_grid_missing_count(self._handle)

    @property
    def axes(self):
        """``(theta_i, theta_o, phi_o)`` of a regular grid (copies, radians); None if scattered."""
        if self.kind != "regular":
            return None
        out = []
        for axis in range(3):
            values = ctypes.POINTER(ctypes.c_double)()
            count = ctypes.c_size_t()
            check(lib.brdffit_grid_axis(self._handle, axis, ctypes.byref(values),
                                        ctypes.byref(count)))
            out.append(np.ctypeslib.as_array(values, (count.value,)).copy())
        return tuple(out)

    @property
    def shape(self):
        """``(n_theta_i, n_theta_o, n_phi_o, n_channels)`` for a regular grid,
        ``(n_samples, n_channels)`` for a scattered one."""
        axes = self.axes
        if axes is None:
            return (self.sample_count, self.channel_count)
        return tuple(a.size for a in axes) + (self.channel_count,)

    @property
    def values(self):
        """A copy of the stored values, shape ``(n_samples, n_channels)``; missing read 0."""
        n, nc = self.sample_count, self.channel_count
        out = np.empty((n, nc))
        for c in range(nc):
            p = ctypes.POINTER(ctypes.c_double)()
            check(lib.brdffit_grid_values(self._handle, c, ctypes.byref(p)))
            out[:, c] = np.ctypeslib.as_array(p, (n,))
        return out

    @property
    def missing(self):
        """Boolean array ``(n_samples, n_channels)``: True where a value is missing."""
        n, nc = self.sample_count, self.channel_count
        out = np.zeros((n, nc), dtype=bool)
        if self.missing_count == 0:
            return out
        h = self._handle
        for s in range(n):
            for c in range(nc):
                out[s, c] = lib.brdffit_grid_is_missing(h, s, c) != 0
        return out

    def sample_angles(self):
        """The directions of every sample in stored order, radians.

        Returns:
            (theta_i, phi_i, theta_o, phi_o): four arrays of ``sample_count``
            values (phi_i is pi on a regular grid).
        """
        n = self.sample_count
        out = np.empty((4, n))
        d = [ctypes.c_double() for _ in range(4)]
        refs = [ctypes.byref(x) for x in d]
        h = self._handle
        for s in range(n):
            check(lib.brdffit_grid_sample_angles(h, s, *refs))
            out[:, s] = [x.value for x in d]
        return tuple(out)

    def active_count(self, cap=DEFAULT_CAP):
        """Number of samples with theta_i <= cap and theta_o <= cap (cap in radians)."""
        return lib.brdffit_grid_active_count(self._handle, float(cap))

    def weights(self, cap=DEFAULT_CAP, flags=Weighting.DEFAULT):
        """The residual weight of every sample (``brdffit_grid_weights``).

        Args:
            cap: angle cap in radians, 0 .. pi/2 (default 75 degrees).
            flags: a combination of :class:`Weighting` flags.

        Returns:
            ``sample_count`` weights; samples beyond the cap get 0.
        """
        out = np.empty(self.sample_count)
        err = new_error()
        check(lib.brdffit_grid_weights(self._handle, float(cap), int(flags), dptr(out),
                                       ctypes.byref(err)), err)
        return out

    def eval(self, theta_i, phi_i, theta_o, phi_o):
        """The measured BRDF interpolated at light/view pairs (regular grids).

        The four angles (radians) broadcast against each other.

        Returns:
            An array of shape ``broadcast shape + (n_channels,)``.
        """
        args = np.broadcast_arrays(*[_lib.as_float64(a, "angles")
                                     for a in (theta_i, phi_i, theta_o, phi_o)])
        shape = args[0].shape
        flat = [a.reshape(-1) for a in args]
        nc = self.channel_count
        out = np.empty((flat[0].size, nc))
        err = new_error()
        h = self._handle
        for i in range(flat[0].size):
            check(lib.brdffit_grid_eval(h, flat[0][i], flat[1][i], flat[2][i], flat[3][i],
                                        dptr(out[i]), ctypes.byref(err)), err)
        return out.reshape(shape + (nc,))

    def channel_mean(self):
        """A new one-channel grid holding the mean over channels (missing values left out)."""
        return self._create(lib.brdffit_grid_channel_mean, self._handle)

    def clearcoat(self, r0):
        """A new grid with every value divided by 1 - F(theta_i), F Schlick's with ``r0``."""
        return self._create(lib.brdffit_grid_clearcoat, self._handle, float(r0))

    def __repr__(self):
        if self._closed:
            return "<brdffit.Grid (closed)>"
        return "<brdffit.Grid %s, %d samples, %d channels, %d missing>" % (
            self.kind, self.sample_count, self.channel_count, self.missing_count)
