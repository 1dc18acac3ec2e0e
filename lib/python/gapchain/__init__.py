"""gapchain: forced, damped rows of bodies with clearances, from Python.

The compiled library (C++) in-process: scenes as dicts, keyword arguments or scene files,
results as dicts of NumPy arrays. Reduced units as in the README: time t = f0 t_phys (in
natural periods, f0 = sqrt(K/M) / (2 pi)), frequencies f_r = f / f0, forces F = k_j p_j /
sqrt(fc) (F_m, eq 19); see help() of each function and docs/python.md.

Functions: simulate, modes, bifurcation, poincare, spectrum, lyapunov, classify, regime_map,
sweep, orbit, continuation, attractors, basin_fractions. Bad input raises ValueError naming the
key (TypeError, in one line naming it, for an argument of the wrong type); numerical outcomes
are in each result's "status".
"""

import functools as _functools
import math as _math
import numbers as _numbers
import sys as _sys


def _import_numpy():
    """NumPy comes from Debian's python3-numpy (tools/dev/deps.sh), installed into
    /usr/lib/python3/dist-packages. A Python that does not search that folder (a pyenv or
    venv CPython of the same major.minor version) is pointed at it once; nothing else is
    added to sys.path."""
    try:
        import numpy
        return numpy
    except ImportError:
        pass
    import glob
    debian = "/usr/lib/python3/dist-packages"
    tag = "cpython-%d%d-" % _sys.version_info[:2]
    built_for_us = glob.glob(debian + "/numpy/core/_multiarray_umath." + tag + "*.so")
    if built_for_us and debian not in _sys.path:
        _sys.path.append(debian)
        try:
            import numpy
            return numpy
        except ImportError:
            pass
    raise ImportError("gapchain needs NumPy for this Python (%s): install Debian's "
                      "python3-numpy (sudo apt-get install python3-numpy), which serves the "
                      "CPython version of /usr/bin/python3" % _sys.executable)


_import_numpy()

from ._gapchain import (  # noqa: E402  (after NumPy is importable)
    __version__,
    attractors,
    basin_fractions,
    bifurcation,
    classify,
    continuation,
    lyapunov,
    modes,
    orbit,
    poincare,
    regime_map,
    simulate,
    spectrum,
    sweep,
)



def _signature(message):
    """(name, type) of each parameter in the signature pybind11 lists in its TypeError."""
    for line in message.splitlines():
        line = line.strip()
        if line.startswith("1. ("):
            text = line[len("1. ("):line.rfind(")")]
            break
    else:
        return []
    parts, depth, start = [], 0, 0
    for i, c in enumerate(text):
        depth += c == "["
        depth -= c == "]"
        if c == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    return [(p.split(":")[0].strip(), p.split(":")[1].split("=")[0].strip())
            for p in parts if ":" in p]


def _fits(kind, value):
    if kind == "int":
        return isinstance(value, _numbers.Integral) and not isinstance(value, bool)
    if kind == "float":
        return isinstance(value, _numbers.Real) and not isinstance(value, bool)
    if kind == "bool":
        return isinstance(value, bool) or type(value).__name__ == "bool_"
    if kind == "str":
        return isinstance(value, str)
    if kind.startswith("List[") and kind.endswith("]"):
        if hasattr(value, "tolist"):
            value = value.tolist()
        return isinstance(value, (list, tuple)) and all(_fits(kind[5:-1], v) for v in value)
    return True


_KINDS = {"int": "an integer", "float": "a number", "bool": "True or False", "str": "a string",
          "List[float]": "a list of numbers", "List[str]": "a list of strings"}


def _bad_argument(name, message, args, kwargs):
    """One line naming the argument pybind11 refused and what it accepts."""
    parameters = _signature(message)
    given = dict(zip((p for p, _ in parameters), args))
    given.update(kwargs)
    for parameter, kind in parameters:
        if parameter in given and not _fits(kind, given[parameter]):
            value = given[parameter]
            return "%s: must be %s, got %r (%s)" % (
                parameter, _KINDS.get(kind, kind), value, type(value).__name__)
    for parameter, kind in parameters:  # the right type, beyond what the C++ type holds
        value = given.get(parameter)
        if kind == "int" and _fits(kind, value):
            if parameter == "seed" and not 0 <= value < 2 ** 64:
                return "seed: must be an integer in [0, 2**64), got %r" % value
            if not -2 ** 31 <= value < 2 ** 31:
                return "%s: must be an integer in [-2**31, 2**31), got %r" % (parameter, value)
    return "%s(): arguments of the wrong type; see help(gapchain.%s)" % (name, name)


def _one_line_type_errors(function):
    """function, with pybind11's multi-line list of signatures for arguments of the wrong type
    replaced by one line naming the argument."""
    @_functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as error:
            if "incompatible function arguments" not in str(error):
                raise
            raise TypeError(_bad_argument(function.__name__, str(error), args, kwargs)) from None
    return call


attractors, basin_fractions, bifurcation, classify, continuation, lyapunov, modes, orbit, \
    poincare, regime_map, simulate, spectrum, sweep = (
        _one_line_type_errors(f) for f in (
            attractors, basin_fractions, bifurcation, classify, continuation, lyapunov, modes,
            orbit, poincare, regime_map, simulate, spectrum, sweep))

__all__ = ["simulate", "modes", "bifurcation", "poincare", "spectrum", "lyapunov", "classify",
           "regime_map", "sweep", "orbit", "continuation", "attractors", "basin_fractions",
           "__version__"]


def _scene_json(value):
    """A scene or study dict as JSON text for the library (called by it): NumPy scalars and
    arrays become numbers and lists; a non-finite number, or a value JSON cannot hold, raises
    ValueError naming its dotted key, as the scene parser does for keywords."""
    import json

    def plain(v, key):
        if isinstance(v, dict):
            return {k: plain(x, "%s.%s" % (key, k) if key else str(k)) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [plain(x, "%s[%d]" % (key, i)) for i, x in enumerate(v)]
        if v is None or isinstance(v, (bool, str)):
            return v
        if hasattr(v, "tolist"):  # NumPy scalars and arrays
            return plain(v.tolist(), key)
        if isinstance(v, _numbers.Integral):
            return int(v)
        if isinstance(v, _numbers.Real):
            if not _math.isfinite(float(v)):
                raise ValueError("%s: must be a finite number, got %r" % (key, float(v)))
            return float(v)
        raise ValueError("%s: must be a number, string, list or object, got %s"
                         % (key or "scene", type(v).__name__))

    return json.dumps(plain(value, ""))
