"""Appel, a CPU ray tracer, from Python: scenes from files, dicts or numpy meshes, renders as
numpy images, and ray and point queries over numpy arrays.

    import appel
    scene = appel.load("scene.toml", width=320, height=240)
    image = scene.render(spp=4, aovs=("depth", "primid"))
    hits = scene.intersect(origins, directions)

Every call that traces rays releases the GIL and runs on ``threads`` threads (default: all cores).
See docs/python.md.
"""

from ._image import Image, AOV_NAMES
from ._mesh import Mesh
from ._scene import Scene, load, load_dict, builtin, builtin_names
from ._appel import MISS, INTEGRATORS as _INTEGRATORS

#: The integrators a scene can be rendered with (``Scene.render(integrator=...)``).
INTEGRATORS = tuple(_INTEGRATORS)

__all__ = [
    "AOV_NAMES",
    "INTEGRATORS",
    "Image",
    "MISS",
    "Mesh",
    "Scene",
    "builtin",
    "builtin_names",
    "load",
    "load_dict",
]
