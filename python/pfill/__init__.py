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
from ._pfill import (  # noqa: F401
    Cancelled,
    Error,
    FillResult,
    __version__,
    builtin_shapes,
    check,
    contacts,
    devices,
    fill,
    load_mesh,
    surface,
)

__all__ = ["fill", "check", "contacts", "surface", "load_mesh", "devices", "builtin_shapes", "FillResult", "Error", "Cancelled"]
