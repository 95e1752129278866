"""pfill: fill closed triangle meshes with densely packed spheres.

    import pfill
    r = pfill.fill("spot.obj", count=500, seed=1)
    r.positions, r.radii, r.colours, r.metrics["packing_fraction"]

fill() takes a mesh file, a built-in shape name (pfill.builtin_shapes()) or
a (vertices, triangles) pair of arrays, and every option of `pfill fill` by
its command-line name with underscores. Errors are pfill.Error (a
RuntimeError) with the command line's one-line messages; Ctrl-C stops a fill
with KeyboardInterrupt.
"""
import functools as _functools
import numbers as _numbers
import re as _re

from . import _pfill
from ._pfill import (  # noqa: F401
    Cancelled,
    Error,
    FillResult,
    __version__,
    builtin_shapes,
    contacts,
    devices,
    load_mesh,
    read_particles,
    surface,
)


def _one_line_type_errors(function):
    """pybind11 answers a keyword of the wrong type with every signature over
    many lines; say in one line which keyword wants what (issue 33)."""
    types = dict(_re.findall(r"(\w+): ([\w\[\]., ]+?)(?: = [^,]*)?(?:, |\) ->)", function.__doc__.splitlines()[0]))

    @_functools.wraps(function)
    def wrapper(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as e:
            if "incompatible function arguments" not in str(e):
                raise
            for name, value in kwargs.items():
                wanted = types.get(name, "")
                if "int" in wanted and not (isinstance(value, _numbers.Integral) or (value is None and "Optional" in wanted)):
                    problem = f"{name} must be a whole number, not {value!r:.60}"
                elif "float" in wanted and not (isinstance(value, _numbers.Real) or (value is None and "Optional" in wanted)):
                    problem = f"{name} must be a number, not {value!r:.60}"
                elif wanted == "str" and not isinstance(value, str):
                    problem = f"{name} must be text, not {value!r:.60}"
                else:
                    continue
                raise TypeError(f"{function.__name__}(): {problem}") from None
            raise TypeError(f"{function.__name__}(): an argument has the wrong type; see help(pfill.{function.__name__})") from None

    return wrapper


fill = _one_line_type_errors(_pfill.fill)
check = _one_line_type_errors(_pfill.check)

__all__ = ["fill", "check", "contacts", "surface", "read_particles", "load_mesh", "devices", "builtin_shapes", "FillResult", "Error", "Cancelled"]
