"""Loading of the shared library and ctypes declarations of the public C API.

Every function the binding calls is declared here with argument and return
types that mirror ``include/brdffit/*.h`` exactly: ``size_t`` is
``c_size_t``, enums are ``c_int``, handles are opaque ``c_void_p`` values.
Nothing outside this package should need this module.
"""

import ctypes
import ctypes.util
import os

import numpy as np

from ctypes import (CFUNCTYPE, POINTER, Structure, c_char, c_char_p, c_double, c_int,
                    c_size_t, c_uint, c_ubyte, c_void_p)

#: The ABI (major version) of the C library this binding was written for.
ABI_MAJOR = 0

# Fixed sizes and constants from the headers.
ERROR_MESSAGE_SIZE = 256                   # BRDFFIT_ERROR_MESSAGE_SIZE
DEFAULT_CAP = 1.3089969389957472           # BRDFFIT_DEFAULT_CAP (75 degrees)
ALL_CHANNELS = ctypes.c_size_t(-1).value   # BRDFFIT_ALL_CHANNELS, (size_t)-1
NO_INDEX = ctypes.c_size_t(-1).value       # (size_t)-1 from brdffit_model_vector_index


class Error(Structure):
    """struct brdffit_error (status.h)."""
    _fields_ = [("status", c_int), ("message", c_char * ERROR_MESSAGE_SIZE)]


class Axes(Structure):
    """struct brdffit_axes (grid.h)."""
    _fields_ = [("theta_i", POINTER(c_double)), ("n_theta_i", c_size_t),
                ("theta_o", POINTER(c_double)), ("n_theta_o", c_size_t),
                ("phi_o", POINTER(c_double)), ("n_phi_o", c_size_t)]


class Batch(Structure):
    """struct brdffit_batch (model.h)."""
    _fields_ = [("struct_size", c_size_t), ("n", c_size_t),
                ("lx", POINTER(c_double)), ("ly", POINTER(c_double)),
                ("lz", POINTER(c_double)), ("vx", POINTER(c_double)),
                ("vy", POINTER(c_double)), ("vz", POINTER(c_double)),
                ("nl", POINTER(c_double)), ("nv", POINTER(c_double)),
                ("nh", POINTER(c_double)), ("hv", POINTER(c_double)),
                ("log_nh", POINTER(c_double)), ("rv", POINTER(c_double))]


#: Names of the geometry arrays of a batch, in struct order.
BATCH_ARRAYS = ("lx", "ly", "lz", "vx", "vy", "vz", "nl", "nv", "nh", "hv", "log_nh", "rv")


class ParamInfo(Structure):
    """struct brdffit_param_info (model.h)."""
    _fields_ = [("name", c_char_p), ("flags", c_uint), ("lower", c_double),
                ("upper", c_double), ("start", c_double)]


#: brdffit_model_eval_fn
EVAL_FN = CFUNCTYPE(c_int, POINTER(Batch), POINTER(c_double), c_size_t,
                    POINTER(c_double), POINTER(c_double), c_void_p)
#: void (*destroy)(void *user)
DESTROY_FN = CFUNCTYPE(None, c_void_p)


class ModelDef(Structure):
    """struct brdffit_model_def (model.h)."""
    _fields_ = [("struct_size", c_size_t), ("name", c_char_p), ("n_params", c_size_t),
                ("params", POINTER(ParamInfo)), ("eval", EVAL_FN), ("user", c_void_p),
                ("destroy", DESTROY_FN)]


class JacobianReport(Structure):
    """struct brdffit_jacobian_report (model.h)."""
    _fields_ = [("struct_size", c_size_t), ("worst_error", c_double), ("param", c_size_t),
                ("channel", c_size_t), ("sample", c_size_t), ("analytic", c_double),
                ("numeric", c_double)]


class Iteration(Structure):
    """struct brdffit_iteration (optim.h)."""
    _fields_ = [("struct_size", c_size_t), ("iteration", c_size_t), ("accepted", c_int),
                ("cost", c_double), ("lambda_", c_double), ("rho", c_double),
                ("x", POINTER(c_double)), ("n_params", c_size_t)]


#: brdffit_iteration_fn
ITERATION_FN = CFUNCTYPE(c_int, POINTER(Iteration), c_void_p)

_P = c_void_p            # any opaque handle
_PP = POINTER(c_void_p)  # handle out-parameter
_D = POINTER(c_double)
_E = POINTER(Error)
_ALLOC = c_void_p        # const brdffit_allocator *: the binding always passes NULL

# name: (restype, argtypes)
_PROTOTYPES = {
    # status.h, version.h
    "brdffit_status_string": (c_char_p, [c_int]),
    "brdffit_status_name": (c_char_p, [c_int]),
    "brdffit_version_number": (c_uint, []),
    "brdffit_version_string": (c_char_p, []),
    # grid.h
    "brdffit_axes_default": (POINTER(Axes), []),
    "brdffit_grid_create_regular": (c_int, [_PP, POINTER(Axes), c_size_t, _D,
                                            POINTER(c_ubyte), _ALLOC, _E]),
    "brdffit_grid_create_scattered": (c_int, [_PP, c_size_t, _D, _D, _D, _D, c_size_t, _D,
                                              POINTER(c_ubyte), _D, _ALLOC, _E]),
    "brdffit_grid_destroy": (None, [_P]),
    "brdffit_grid_get_kind": (c_int, [_P]),
    "brdffit_grid_sample_count": (c_size_t, [_P]),
    "brdffit_grid_channel_count": (c_size_t, [_P]),
    "brdffit_grid_missing_count": (c_size_t, [_P]),
    "brdffit_grid_axis": (c_int, [_P, c_int, POINTER(_D), POINTER(c_size_t)]),
    "brdffit_grid_sample_angles": (c_int, [_P, c_size_t, _D, _D, _D, _D]),
    "brdffit_grid_values": (c_int, [_P, c_size_t, POINTER(_D)]),
    "brdffit_grid_is_missing": (c_int, [_P, c_size_t, c_size_t]),
    "brdffit_grid_active_count": (c_size_t, [_P, c_double]),
    "brdffit_grid_weights": (c_int, [_P, c_double, c_uint, _D, _E]),
    "brdffit_grid_channel_mean": (c_int, [_PP, _P, _ALLOC, _E]),
    "brdffit_grid_clearcoat": (c_int, [_PP, _P, c_double, _ALLOC, _E]),
    "brdffit_grid_eval": (c_int, [_P, c_double, c_double, c_double, c_double, _D, _E]),
    # load.h
    "brdffit_load_csv": (c_int, [_PP, c_char_p, _ALLOC, _E]),
    "brdffit_load_csv_buffer": (c_int, [_PP, c_char_p, c_size_t, _ALLOC, _E]),
    "brdffit_load_merl": (c_int, [_PP, c_char_p, POINTER(Axes), _ALLOC, _E]),
    "brdffit_load_merl_buffer": (c_int, [_PP, c_void_p, c_size_t, POINTER(Axes), _ALLOC,
                                         _E]),
    "brdffit_load_astm": (c_int, [_PP, c_char_p, _ALLOC, _E]),
    "brdffit_load_astm_buffer": (c_int, [_PP, c_char_p, c_size_t, _ALLOC, _E]),
    "brdffit_load_rgl": (c_int, [_PP, c_char_p, POINTER(Axes), _ALLOC, _E]),
    "brdffit_load_rgl_buffer": (c_int, [_PP, c_void_p, c_size_t, POINTER(Axes), _ALLOC,
                                        _E]),
    # model.h
    "brdffit_model_def_init": (None, [POINTER(ModelDef)]),
    "brdffit_model_builtin_count": (c_size_t, []),
    "brdffit_model_builtin_name": (c_char_p, [c_size_t]),
    "brdffit_model_create": (c_int, [_PP, c_char_p, _ALLOC, _E]),
    "brdffit_model_create_custom": (c_int, [_PP, POINTER(ModelDef), _ALLOC, _E]),
    "brdffit_model_destroy": (None, [_P]),
    "brdffit_model_name": (c_char_p, [_P]),
    "brdffit_model_param_count": (c_size_t, [_P]),
    "brdffit_model_param": (POINTER(ParamInfo), [_P, c_size_t]),
    "brdffit_model_param_find": (c_int, [_P, c_char_p, POINTER(c_size_t)]),
    "brdffit_model_vector_size": (c_size_t, [_P, c_size_t]),
    "brdffit_model_vector_index": (c_size_t, [_P, c_size_t, c_size_t, c_size_t]),
    "brdffit_model_default_params": (c_int, [_P, c_size_t, _D]),
    "brdffit_model_eval_grid": (c_int, [_P, _P, c_size_t, c_size_t, _D, _D, _D, _E]),
    "brdffit_model_eval_angles": (c_int, [_P, c_size_t, _D, _D, _D, _D, c_size_t, _D, _D,
                                          _D, _E]),
    "brdffit_model_check_jacobian": (c_int, [_P, _P, _D, POINTER(JacobianReport), _E]),
    # optim.h (only what the fit reports use)
    "brdffit_stop_reason_string": (c_char_p, [c_int]),
    # fit.h
    "brdffit_fit_create": (c_int, [_PP, _P, _P, _ALLOC, _E]),
    "brdffit_fit_destroy": (None, [_P]),
    "brdffit_fit_message": (c_char_p, [_P]),
    "brdffit_fit_set": (c_int, [_P, c_int, c_double]),
    "brdffit_fit_get": (c_int, [_P, c_int, _D]),
    "brdffit_fit_set_start": (c_int, [_P, _D]),
    "brdffit_fit_set_fixed": (c_int, [_P, c_size_t, c_int]),
    "brdffit_fit_set_callback": (c_int, [_P, ITERATION_FN, c_void_p]),
    "brdffit_fit_cancel": (None, [_P]),
    "brdffit_fit_run": (c_int, [_P]),
    "brdffit_fit_param_count": (c_size_t, [_P]),
    "brdffit_fit_params": (c_int, [_P, _D]),
    "brdffit_fit_std_errors": (c_int, [_P, _D]),
    "brdffit_fit_covariance": (c_int, [_P, _D]),
    "brdffit_fit_error": (c_int, [_P, c_int, c_size_t, _D]),
    "brdffit_fit_shader": (c_int, [_P, _D, _D, _D]),
    "brdffit_fit_stop_reason": (c_int, [_P]),
    "brdffit_fit_iterations": (c_size_t, [_P]),
    "brdffit_fit_history": (c_size_t, [_P, _D, _D]),
    "brdffit_fit_passes": (c_size_t, [_P]),
    "brdffit_fit_warnings": (c_uint, [_P]),
    "brdffit_fit_warning_text": (c_int, [_P, c_uint, c_char_p, c_size_t]),
    "brdffit_warning_name": (c_char_p, [c_uint]),
}


def _candidates():
    """Library names to try, most specific first."""
    env = os.environ.get("BRDFFIT_LIBRARY")
    if env:
        return [env]
    names = []
    try:  # written by `cmake --install`: the library installed with this package
        from . import _install
        names.append(_install.library_path())
    except ImportError:
        pass
    found = ctypes.util.find_library("brdffit")
    if found:
        names.append(found)
    names += ["libbrdffit.so.%d" % ABI_MAJOR, "libbrdffit.so",
              "libbrdffit.%d.dylib" % ABI_MAJOR, "libbrdffit.dylib", "brdffit.dll"]
    return names


def _load():
    """Open the shared library and declare every prototype."""
    errors = []
    for name in _candidates():
        try:
            lib = ctypes.CDLL(name)
            break
        except OSError as exc:
            errors.append("%s: %s" % (name, exc))
    else:
        raise OSError("cannot load the libbrdffit shared library; set BRDFFIT_LIBRARY to its "
                      "full path (tried: %s)" % "; ".join(errors))
    for fname, (restype, argtypes) in _PROTOTYPES.items():
        try:
            fn = getattr(lib, fname)
        except AttributeError:
            raise OSError("%s is not libbrdffit (it lacks %s); set BRDFFIT_LIBRARY to the "
                          "library's full path" % (name, fname)) from None
        fn.restype = restype
        fn.argtypes = argtypes
    major = lib.brdffit_version_number() // 10000
    if major != ABI_MAJOR:
        raise OSError("libbrdffit %s has ABI %d; this binding needs ABI %d"
                      % (lib.brdffit_version_string().decode(), major, ABI_MAJOR))
    return lib


lib = _load()


def dptr(array):
    """A ``double *`` to the data of a float64 C-contiguous numpy array (or NULL for None)."""
    if array is None:
        return None
    return array.ctypes.data_as(_D)


def bptr(array):
    """An ``unsigned char *`` to the data of a uint8 C-contiguous numpy array (or NULL)."""
    if array is None:
        return None
    return array.ctypes.data_as(POINTER(c_ubyte))


# ---- optim.h (damping policies, general optimizer), image.h, fit damping ----
# Declared after the fit API above; used by optim.py and image.py.

#: void (*init)(void *state, double *lambda, void *user)
DAMPING_INIT_FN = CFUNCTYPE(None, c_void_p, POINTER(c_double), c_void_p)
#: void (*accept / reject)(void *state, double rho, double *lambda, void *user)
DAMPING_STEP_FN = CFUNCTYPE(None, c_void_p, c_double, POINTER(c_double), c_void_p)


class Damping(Structure):
    """struct brdffit_damping (optim.h)."""
    _fields_ = [("struct_size", c_size_t), ("name", c_char_p), ("state_size", c_size_t),
                ("init", DAMPING_INIT_FN), ("accept", DAMPING_STEP_FN),
                ("reject", DAMPING_STEP_FN), ("user", c_void_p)]


#: brdffit_residual_fn
RESIDUAL_FN = CFUNCTYPE(c_int, POINTER(c_double), POINTER(c_double), POINTER(c_double),
                        c_void_p)
#: brdffit_normal_fn
NORMAL_FN = CFUNCTYPE(c_int, POINTER(c_double), POINTER(c_double), POINTER(c_double),
                      POINTER(c_double), c_void_p)


class ImageOptions(Structure):
    """struct brdffit_image_options (image.h)."""
    _fields_ = [("struct_size", c_size_t), ("gain", c_double), ("difference_gain", c_double),
                ("exposure", c_double), ("gamma", c_double), ("background", c_ubyte * 3),
                ("missing", c_ubyte * 3), ("foreground", c_ubyte * 3), ("curve", c_ubyte * 3),
                ("scale", c_size_t), ("block_columns", c_size_t), ("block_gap", c_size_t),
                ("log_y", c_int)]


class FitStage(Structure):
    """struct brdffit_fit_stage (fit.h)."""
    _fields_ = [("kind", c_int), ("index", c_size_t), ("first", c_size_t),
                ("length", c_size_t), ("stop", c_int), ("iterations", c_size_t),
                ("evaluations", c_size_t), ("converged", c_int), ("kept", c_int)]


_U8 = POINTER(c_ubyte)
_SZ = POINTER(c_size_t)
_DAMP = POINTER(Damping)
_OPTS = POINTER(ImageOptions)
_PROTOTYPES_OPTIM_IMAGE = {
    "brdffit_damping_thesis": (_DAMP, []),
    "brdffit_damping_marquardt": (_DAMP, []),
    "brdffit_damping_nielsen": (_DAMP, []),
    "brdffit_optimizer_create": (c_int, [_PP, c_size_t, _ALLOC, _E]),
    "brdffit_optimizer_destroy": (None, [_P]),
    "brdffit_optimizer_param_count": (c_size_t, [_P]),
    "brdffit_optimizer_message": (c_char_p, [_P]),
    "brdffit_optimizer_set_residuals": (c_int, [_P, c_size_t, RESIDUAL_FN, c_void_p]),
    "brdffit_optimizer_set_normal": (c_int, [_P, c_size_t, NORMAL_FN, c_void_p]),
    "brdffit_optimizer_set_damping": (c_int, [_P, _DAMP]),
    "brdffit_optimizer_set": (c_int, [_P, c_int, c_double]),
    "brdffit_optimizer_get": (c_int, [_P, c_int, _D]),
    "brdffit_optimizer_set_bounds": (c_int, [_P, _D, _D]),
    "brdffit_optimizer_set_fixed": (c_int, [_P, _U8]),
    "brdffit_optimizer_set_callback": (c_int, [_P, ITERATION_FN, c_void_p]),
    "brdffit_optimizer_cancel": (None, [_P]),
    "brdffit_optimizer_run": (c_int, [_P, _D]),
    "brdffit_optimizer_stop_reason": (c_int, [_P]),
    "brdffit_optimizer_initial_cost": (c_double, [_P]),
    "brdffit_optimizer_final_cost": (c_double, [_P]),
    "brdffit_optimizer_iterations": (c_size_t, [_P]),
    "brdffit_optimizer_evaluations": (c_size_t, [_P]),
    "brdffit_optimizer_last_improvement": (c_size_t, [_P]),
    "brdffit_optimizer_used_fallback": (c_int, [_P]),
    "brdffit_optimizer_history": (c_size_t, [_P, _D, _D]),
    "brdffit_optimizer_condition": (c_double, [_P]),
    "brdffit_optimizer_covariance": (c_int, [_P, _D]),
    "brdffit_optimizer_std_errors": (c_int, [_P, _D]),
    "brdffit_fit_set_damping": (c_int, [_P, _DAMP]),
    "brdffit_fit_converged": (c_int, [_P]),
    "brdffit_fit_stage_count": (c_size_t, [_P]),
    "brdffit_fit_stage_info": (c_int, [_P, c_size_t, POINTER(FitStage), c_size_t]),
    "brdffit_fit_stage_name": (c_char_p, [c_int]),
    "brdffit_fit_history_all": (c_size_t, [_P, _D, _D, _SZ]),
    "brdffit_image_options_init": (None, [_OPTS]),
    "brdffit_image_texture_size": (c_int, [_P, _OPTS, _SZ, _SZ, _E]),
    "brdffit_image_texture": (c_int, [_U8, c_size_t, c_int, _P, _P, _D, _OPTS, _ALLOC, _E]),
    "brdffit_image_sphere_measured": (c_int, [_U8, c_size_t, c_size_t, _P, c_double, c_double,
                                              _OPTS, _ALLOC, _E]),
    "brdffit_image_sphere_model": (c_int, [_U8, c_size_t, c_size_t, _P, _D, c_size_t,
                                           c_double, c_double, _OPTS, _ALLOC, _E]),
    "brdffit_image_plot": (c_int, [_U8, c_size_t, c_size_t, c_size_t, _D, c_size_t, _OPTS,
                                   _E]),
}
for _name, (_restype, _argtypes) in _PROTOTYPES_OPTIM_IMAGE.items():
    _fn = getattr(lib, _name)
    _fn.restype, _fn.argtypes = _restype, _argtypes


def as_float64(values, what):
    """``values`` as a C-contiguous float64 numpy array. Complex values are
    refused (numpy would drop their imaginary part)."""
    a = np.asarray(values)
    if np.iscomplexobj(a):
        raise TypeError("%s must be real numbers, got complex values" % what)
    a = np.asarray(a, dtype=np.float64)
    return a if a.flags.c_contiguous else np.ascontiguousarray(a)


def c_string(text, what):
    """``text`` (str or bytes) as NUL-free bytes for a C string argument."""
    if isinstance(text, str):
        data = text.encode("utf-8")
    elif isinstance(text, (bytes, bytearray)):
        data = bytes(text)
    else:
        raise TypeError("%s must be a str or bytes, got %s" % (what, type(text).__name__))
    if b"\0" in data:
        raise ValueError("%s contains a NUL character: %r" % (what, text))
    return data
