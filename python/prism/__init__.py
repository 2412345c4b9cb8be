"""Prism from Python: load a glTF scene once, render it with any integrator, get NumPy arrays.

    import prism
    session = prism.Session("scenes/spheres.gltf", threads=2)
    render = session.render(integrator="whitted", spp=16, resolution=(320, 240))
    render.image          # (240, 320, 4) float32, scene-linear RGBA
    render.write("out.exr", preview="out.png")

Errors are prism.RequestError (a ValueError; `.field` names the option as job files spell
it) and prism.LoadError (a RuntimeError), with the one-line messages `prism render` prints.
See docs/python.md.
"""

from ._prism import (  # noqa: F401  (the package's public names)
    LoadError,
    Render,
    RequestError,
    Session,
    __version__,
    compare_images,
    integrators,
    read_exr,
)

__all__ = [
    "LoadError",
    "Render",
    "RequestError",
    "Session",
    "compare_images",
    "integrators",
    "read_exr",
]
