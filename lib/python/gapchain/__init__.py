"""gapchain: forced, damped rows of bodies with clearances, from Python.

The compiled library (C++) in-process: scenes as dicts, keyword arguments or scene files,
results as dicts of NumPy arrays. Reduced units as in the README: time t = f0 t_phys (in
natural periods, f0 = sqrt(K/M) / (2 pi)), frequencies f_r = f / f0, forces F = k_j p_j /
sqrt(fc) (F_m, eq 19); see help() of each function and docs/python.md.

Functions: simulate, modes, bifurcation, poincare, spectrum, lyapunov, classify, regime_map,
sweep, orbit, continuation, attractors, basin_fractions. Bad input raises ValueError naming the
key; numerical outcomes are in each result's "status".
"""

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
