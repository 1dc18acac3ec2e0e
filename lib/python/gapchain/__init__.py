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

import collections.abc as _abc
import functools as _functools
import math as _math
import numbers as _numbers
import os as _os
import re as _re
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

from . import _gapchain  # noqa: E402  (after NumPy is importable)
from ._gapchain import __version__  # noqa: E402

# The one list of the module's functions: each is the compiled one behind _typed() (below).
_FUNCTIONS = ("simulate", "modes", "bifurcation", "poincare", "spectrum", "lyapunov", "classify",
              "regime_map", "sweep", "orbit", "continuation", "attractors", "basin_fractions")


def _signature(message):
    """(name, type) of each parameter in the signature pybind11 lists in its TypeError, how
    many may be given by position (those before "*"), and the names listed without a default."""
    for line in message.splitlines():
        line = line.strip()
        if line.startswith("1. ("):
            text = line[len("1. ("):line.rfind(")")]
            break
    else:
        return [], 0, []
    parts, depth, start = [], 0, 0
    for i, c in enumerate(text):
        depth += c == "["
        depth -= c == "]"
        if c == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    positional = parts.index("*") if "*" in parts else len(parts)
    return ([(p.split(":")[0].strip(), p.split(":")[1].split("=")[0].strip())
             for p in parts if ":" in p], positional,
            [p.split(":")[0].strip() for p in parts if ":" in p and "=" not in p])


def _is_bool(value):
    kind = type(value)
    return isinstance(value, bool) or (kind.__module__ == "numpy" and
                                       kind.__name__ in ("bool_", "bool"))


def _fits(kind, value):
    """Whether value is of the parameter kind: no bool for a number, no fraction for an integer
    (pybind11 would take True as 1 and truncate 3.7 to 3), no 0.5 for a flag; NumPy scalars and
    0-d arrays, Decimal for a number, and 0 or 1 for a flag are accepted. None is not a flag:
    pybind11 took it as False, so classify(confirm=None) skipped the Newton confirmation."""
    if getattr(value, "ndim", None) == 0 and hasattr(value, "item"):
        value = value.item()
    if kind.startswith("Optional[") and kind.endswith("]"):
        return value is None or _fits(kind[9:-1], value)
    if kind == "int":
        return isinstance(value, _numbers.Integral) and not _is_bool(value)
    if kind == "float":
        # An array of one entry has __float__ too: box=np.array([1.0]) ran as box=1.
        if getattr(value, "ndim", 0) != 0:
            return False
        return (isinstance(value, _numbers.Real) or
                (hasattr(value, "__float__") and not isinstance(value, (str, bytes)))) \
            and not _is_bool(value)
    if kind == "bool":
        return _is_bool(value) or (
            isinstance(value, _numbers.Integral) and value in (0, 1))
    if kind == "str":
        return isinstance(value, str)
    if kind.startswith("List[") and kind.endswith("]"):
        if getattr(value, "ndim", 1) != 1:
            return False
        if hasattr(value, "tolist"):
            value = value.tolist()
        return isinstance(value, _abc.Sequence) and not isinstance(value, (str, bytes)) and \
            all(_fits(kind[5:-1], v) for v in value)
    return True


_KINDS = {"int": "an integer", "float": "a number", "bool": "True or False", "str": "a string",
          "List[float]": "a list of numbers", "List[str]": "a list of strings"}


def _shown(value):
    text = repr(value).replace("\n", " ")
    return text if len(text) <= 60 else text[:57] + "..."


def _wrong_argument(name, parameters, positional, args, kwargs):
    """One line naming the first argument of the wrong kind, or None."""
    names = [p for p, _ in parameters]
    if parameters and len(args) > positional:
        return "%s(): takes %d positional argument%s (%s), got %d" % (
            name, positional, "" if positional == 1 else "s", ", ".join(names[:positional]),
            len(args))
    given = dict(zip(names, args))
    for key in kwargs:
        if key in given:
            return "%s(): got two values for %s" % (name, key)
    given.update(kwargs)
    for parameter, kind in parameters:
        if parameter in given and not _fits(kind, given[parameter]):
            value = given[parameter]
            optional = kind.startswith("Optional[") and kind.endswith("]")
            return "%s: must be %s%s, got %s (%s)" % (
                parameter, _KINDS.get(kind[9:-1] if optional else kind, kind),
                " or None" if optional else "", _shown(value), type(value).__name__)
    progress = given.get("progress")
    if progress is not None and not callable(progress):
        return "progress: must be a callable(fraction) or None, got %s (%s)" % (
            _shown(progress), type(progress).__name__)
    return None


def _out_of_range(name, parameters, args, kwargs):
    """(exception class, message): ValueError for an integer of the right kind that the C++ type
    cannot hold (a value out of range, as the library's own range errors), else TypeError."""
    given = dict(zip((p for p, _ in parameters), args))
    given.update(kwargs)
    for parameter, kind in parameters:
        value = given.get(parameter)
        if kind.startswith("Optional[") and kind.endswith("]"):
            kind = kind[9:-1]
        # An integer too large for a double (from_=10**400) is a value out of range.
        if kind == "float" and isinstance(value, _numbers.Integral) and _fits(kind, value):
            try:
                float(value)
            except OverflowError:
                return ValueError, "%s: must be a finite number, |x| <= 1.8e308, got %s" % (
                    parameter, _shown(value))
        if kind == "int" and _fits(kind, value):
            # The library's own limit (attractors.cpp), so that -1 and 2**63 read alike.
            if parameter == "seed" and not 0 <= value <= 2 ** 62:
                return ValueError, ("seed: must be an integer in [0, 2^62 = %d], got %r"
                                    % (2 ** 62, value))
            # Where the library did not name its own range (_library_range()).
            if not -2 ** 63 <= value < 2 ** 63:
                return ValueError, "%s: must be an integer in [-2**63, 2**63), got %r" % (
                    parameter, value)
            if not -2 ** 31 <= value < 2 ** 31:
                return ValueError, "%s: must be an integer in [-2**31, 2**31), got %r" % (
                    parameter, value)
    return TypeError, "%s(): arguments of the wrong type; see help(gapchain.%s)" % (name, name)


_INT32 = (-2 ** 31, 2 ** 31 - 1)


def _beyond_int32(parameters, args, kwargs):
    """(args, kwargs) with every integer argument beyond the 32-bit range clamped to it, and
    [(parameter, clamped value, given value)] of those; empty where none is beyond it. pybind11
    refuses such an integer for a C++ int with a TypeError that names no range."""
    names = [p for p, kind in parameters if kind in ("int", "Optional[int]")]
    clamped, args, kwargs = [], list(args), dict(kwargs)
    positions = {p: i for i, (p, _) in enumerate(parameters)}

    def clamp(name, value):
        if getattr(value, "ndim", None) == 0 and hasattr(value, "item"):
            value = value.item()
        if not isinstance(value, _numbers.Integral) or _is_bool(value):
            return value
        inside = min(max(int(value), _INT32[0]), _INT32[1])
        if inside != value:
            clamped.append((name, inside, value))
        return inside

    for name in names:
        if name == "seed":  # the library's own limit, named by _out_of_range()
            continue
        if name in kwargs:
            kwargs[name] = clamp(name, kwargs[name])
        elif positions[name] < len(args):
            args[positions[name]] = clamp(name, args[positions[name]])
    return args, kwargs, clamped


def _library_range(function, parameters, args, kwargs, renamed_message):
    """The library's own message for an integer argument beyond the 32-bit range, naming the
    key's accepted range ("steps: must be an integer in [1, 10000000], got 8589934592"): the call
    again with the integer clamped to the 32-bit range, which every integer parameter's own
    range refuses (a test asks each of them), and the given value put back into the message of
    the parameter it names (renamed_message() names it as the argument). None where no integer
    was beyond it, or the library did not refuse the clamped call."""
    args, kwargs, clamped = _beyond_int32(parameters, args, kwargs)
    if not clamped:
        return None
    try:
        function(*args, **kwargs)
    except ValueError as error:
        message = renamed_message(str(error), kwargs)
        for name, inside, given in clamped:
            if message.startswith(name + ":"):
                message = _re.sub(r"got %d$" % inside, "got %d" % given, message)
        return message
    except Exception:  # noqa: BLE001  (any other refusal: the type-range message stands)
        return None
    return None


def _one_line(message):
    """message with its control characters escaped (a newline as \\n)."""
    return "".join({"\n": "\\n", "\r": "\\r", "\t": "\\t"}.get(c, "\\x%02x" % ord(c))
                   if ord(c) < 0x20 or ord(c) == 0x7f else c for c in message)


def _unencodable(value):
    """Whether value (a str or os.PathLike) is text UTF-8 cannot encode: a lone surrogate, as
    os.fsdecode makes of undecodable file names."""
    if isinstance(value, _os.PathLike):
        value = _os.fspath(value)
    if not isinstance(value, str):
        return False
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        return True
    return False


def _not_utf8(names, args, kwargs):
    """One line naming the first argument, keyword or path that _unencodable(), or None:
    pybind11 raised RuntimeError "Unable to cast Python instance" for it."""
    bad = _unencodable
    for i, value in enumerate(args):
        if bad(value):
            name = names[i] if i < len(names) else "argument %d" % (i + 1)
            return "%s: must be valid UTF-8 text, got %s" % (name, _shown(value))
    for key, value in kwargs.items():
        if bad(key):
            return "keyword %s: must be valid UTF-8 text" % _shown(key)
        if bad(value):
            return "%s: must be valid UTF-8 text, got %s" % (key, _shown(value))
    return None


def _typed(function):
    """function, with its arguments checked against its C++ signature first: one line naming
    the argument of the wrong kind, instead of pybind11's multi-line list of signatures or a
    silent conversion (True as 1, 3.7 as 3)."""
    try:
        function(*([None] * 64))  # too many: pybind11 lists the signature, runs nothing
        parameters, positional, required, closed = [], 0, [], False
    except TypeError as error:
        # Those listed without a default, too: pybind11 said only "incompatible function
        # arguments" when one was left out (basin_fractions(samples=3) without from_, to, steps).
        parameters, positional, required = _signature(str(error))
        # Without **kwargs every keyword is a parameter: name a misspelt one (pybind11 said
        # only "incompatible function arguments").
        closed = bool(parameters) and "**kwargs" not in str(error)
    names = [p for p, _ in parameters]

    # The library names the options behind these arguments (the command-line tools map them to
    # their flags the same way).
    renamed = [(field + ":", argument + ":") for field, argument in
               (("transient_periods", "transient"), ("record_periods", "record"),
                ("from", "from_"), ("parameter", "param"), ("slice.resolution", "resolution"),
                ("section.phase", "phase"), ("section.level", "level"),
                ("section.trigger", "trigger"), ("section.record", "record"),
                ("run.scheme", "scheme"), ("samples", "attractors"))
               if argument in (p for p, _ in parameters)]

    @_functools.wraps(function)
    def call(*args, **kwargs):
        bad = _not_utf8(names, args, kwargs)
        if bad:
            raise ValueError(bad)
        unknown = [key for key in kwargs if closed and key not in names]
        if unknown:
            raise TypeError(_one_line("%s: unknown keyword of %s(); accepted: %s" % (
                unknown[0], function.__name__, ", ".join(names))))
        wrong = _wrong_argument(function.__name__, parameters, positional, args, kwargs)
        if wrong:
            raise TypeError(wrong)
        given = set(names[:len(args)]) | set(kwargs)
        missing = [p for p in required if p not in given]
        if missing:
            raise TypeError("%s(): missing required argument%s: %s" % (
                function.__name__, "" if len(missing) == 1 else "s", ", ".join(missing)))
        try:
            return function(*args, **kwargs)
        except TypeError as error:
            if "incompatible function arguments" not in str(error):
                raise
            library = _library_range(function, parameters, args, kwargs, renamed_message)
            if library:
                raise ValueError(library) from None
            kind, message = _out_of_range(function.__name__, parameters, args, kwargs)
            raise kind(message) from None
        except ValueError as error:
            message = renamed_message(str(error), kwargs)
            if message != str(error):
                raise ValueError(message) from None
            raise

    def renamed_message(message, kwargs):
        # One line, as the tools print it: a newline in the user's text (a variable, a path)
        # split the message.
        message = _one_line(message)
        for field, argument in renamed:
            # A keyword of that very name (a scene key, transient_periods=...) keeps it.
            if message.startswith(field) and field[:-1] not in kwargs:
                return argument + message[len(field):]
        return message
    return call


globals().update((name, _typed(getattr(_gapchain, name))) for name in _FUNCTIONS)

__all__ = list(_FUNCTIONS) + ["__version__"]


def _scene_json(value, key=""):
    """A scene or study dict (or one keyword's value, named key) as JSON text for the library
    (called by it): NumPy scalars and arrays become numbers and lists; a non-finite number
    becomes its text ("nan", "inf"), which the scene reader refuses naming the key and its
    range; a value JSON cannot hold raises ValueError naming its dotted key."""
    import json

    def plain(v, key):
        if isinstance(v, dict):
            for k in v:  # JSON's keys are strings: json.dumps' TypeError named none
                if not isinstance(k, str):
                    raise ValueError("%s: keys must be strings, got %r (%s)"
                                     % (key or "scene", k, type(k).__name__))
                plain(k, key)
            return {k: plain(x, "%s.%s" % (key, k) if key else str(k)) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [plain(x, "%s[%d]" % (key, i)) for i, x in enumerate(v)]
        if _unencodable(v):
            raise ValueError("%s: must be valid UTF-8 text, got %s" % (key or "scene", _shown(v)))
        if v is None or isinstance(v, (bool, str)):
            return v
        if hasattr(v, "tolist"):  # NumPy scalars and arrays
            listed = v.tolist()
            if type(listed) is type(v):  # a long double stays itself: recursion without end
                if not isinstance(v, _numbers.Real):
                    raise ValueError("%s: must be a number, string, list or object, got %s"
                                     % (key or "scene", type(v).__name__))
                listed = float(v)
                if _math.isinf(listed) and not abs(v) == float("inf"):
                    raise ValueError("%s: must be a finite number within the double range, got %s"
                                     % (key or "scene", v))
            return plain(listed, key)
        if isinstance(v, _numbers.Integral):
            return int(v)
        if isinstance(v, _numbers.Real):
            if not _math.isfinite(float(v)):
                # JSON holds no NaN or infinity. A key's value is passed as text, which the
                # scene reader refuses naming the key and its range, as for a keyword; an array
                # entry is named here (the reader would only say the array is not numbers).
                if key.endswith("]"):
                    raise ValueError("%s: must be a finite number, got %r" % (key, float(v)))
                return repr(float(v))
            return float(v)
        raise ValueError("%s: must be a number, string, list or object, got %s"
                         % (key or "scene", type(v).__name__))

    return json.dumps(plain(value, key))
