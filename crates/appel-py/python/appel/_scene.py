"""Scenes: loading, rendering and ray and point queries."""

import json
import os
import sys

import numpy as np

from . import _appel
from ._image import aov_set, image_from
from ._mesh import Mesh


def _json(d):
    def default(x):
        if isinstance(x, np.ndarray):
            return x.tolist()
        if isinstance(x, np.generic):
            return x.item()
        if isinstance(x, os.PathLike):
            return os.fspath(x)
        raise TypeError(f"{type(x).__name__} is not a scene value")

    try:
        return json.dumps(d or {}, default=default)
    except TypeError as e:
        raise ValueError(f"overrides: {e}") from None


def _coords(name, x):
    if isinstance(x, np.ndarray):
        if x.dtype not in (np.float32, np.float64):
            raise ValueError(f"{name}: expected float32 or float64, got {x.dtype}")
    else:
        try:
            x = np.asarray(x, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise ValueError(f"{name}: expected an array of numbers ({e})") from None
    if x.ndim < 1 or x.shape[-1] != 3:
        raise ValueError(f"{name}: expected shape (..., 3), got {x.shape}")
    if not x.dtype.isnative:
        x = x.astype(x.dtype.newbyteorder("="))
    return np.ascontiguousarray(x)


def _progress(progress, total):
    """A callback taking the pixels done, and a function closing the bar."""
    if callable(progress):
        return progress, lambda: None
    if not progress:
        return None, lambda: None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        def report(done):
            print(f"\rrendering {100 * done // max(total, 1):3d}%", end="", file=sys.stderr)

        return report, lambda: print(file=sys.stderr)
    bar = tqdm(total=total, unit="px", unit_scale=True, desc="rendering")

    def update(done):
        bar.update(max(0, min(done, total) - bar.n))

    def close():
        update(total)
        bar.close()

    return update, close


class Scene:
    """A scene ready to render and to answer ray queries. Made by :func:`load`, :func:`load_dict`,
    :func:`builtin` or :meth:`Scene.from_meshes`."""

    def __init__(self, native, source=None):
        self._native = native
        #: How the scene was made, so that workers can make it again: ``("file", path,
        #: overrides)``, ``("builtin", name, overrides)``, ``("dict", d, base_dir)`` or None.
        self.source = source

    @classmethod
    def from_meshes(cls, meshes, transforms=None, camera=None, accel="bvh"):
        """A scene of meshes. Without ``transforms``, mesh ``i`` is shape ``i`` where its vertices
        are. With them (one 4x4 matrix per mesh, or None for the identity), entry ``i`` is shape
        ``i`` and instance ``i``; a Mesh object given several times is stored once. ``camera`` is
        a dict of camera keys (by default the camera frames the bounds)."""
        if isinstance(meshes, Mesh):
            meshes = [meshes]
        meshes = list(meshes)
        for k, m in enumerate(meshes):
            if not isinstance(m, Mesh):
                raise ValueError(f"meshes[{k}]: expected an appel.Mesh, got {type(m).__name__}")
        placements = None
        natives = meshes
        if transforms is not None:
            transforms = list(transforms)
            if len(transforms) != len(meshes):
                raise ValueError(
                    f"transforms: {len(transforms)} transforms for {len(meshes)} meshes"
                )
            unique, index = [], {}
            placements = []
            for k, (m, t) in enumerate(zip(meshes, transforms)):
                if id(m) not in index:
                    index[id(m)] = len(unique)
                    unique.append(m)
                t = np.eye(4) if t is None else np.asarray(t, dtype=np.float64)
                if t.shape != (4, 4) or not np.isfinite(t).all():
                    raise ValueError(f"transforms[{k}]: expected a finite 4x4 matrix")
                placements.append((index[id(m)], np.ascontiguousarray(t, dtype=np.float32)))
            natives = unique
        native = _appel.NativeScene.from_meshes(
            [m._native() for m in natives], placements, _json(camera), accel
        )
        return cls(native, None)

    @property
    def size(self):
        """``(width, height)`` of the image."""
        return self._native.size()

    @property
    def camera(self):
        """The camera as a dict of the scene schema's keys."""
        return json.loads(self._native.camera_json())

    @property
    def bounds(self):
        lo, hi = self._native.bounds()
        return np.array(lo, dtype=np.float32), np.array(hi, dtype=np.float32)

    @property
    def is_closed(self):
        """Whether the triangles close a consistently oriented surface (signed distances)."""
        return self._native.is_closed()

    def render(self, spp=1, integrator=None, aovs=(), threads=None, progress=False,
               camera=None, window=None):
        """Renders an :class:`Image`. ``integrator`` overrides the scene's (one of
        ``appel.INTEGRATORS``); ``aovs`` names AOVs to return; ``progress`` shows a bar (tqdm, notebooks
        too) or is a callable given the pixels done. ``camera`` is a dict of camera keys for
        this render; ``window`` = ``(x0, y0, x1, y1)`` renders only those pixels of the image,
        each bit for bit the full render's."""
        names = aov_set(aovs)
        if window is not None:
            window = tuple(int(v) for v in window)
            total = max(0, (window[2] - window[0]) * (window[3] - window[1]))
        else:
            w, h = self.size
            total = w * h
        report, close = _progress(progress, total)
        try:
            arrays = self._native.render(
                spp, integrator, _json(camera), window, threads, report
            )
        finally:
            close()
        return image_from(arrays, names)

    def intersect(self, origins, directions, tnear=0.0, tfar=np.inf, threads=None,
                  geometric_only=False, normal=None, out=None):
        """Closest hits in ``(tnear, tfar)``: a dict of ``t_hit`` (inf on a miss), ``prim_ids``,
        ``shape_ids``, ``instance_ids`` (uint32, 4294967295 on a miss), ``uv`` (..., 2),
        ``normal`` (..., 3, unit geometric normal) and ``position`` (..., 3).

        With ``geometric_only=True`` only what the traversal finds is reported, as Embree's
        ``rtcIntersect1`` does: ``t_hit``, the three ids and ``uv``, plus ``normal`` if
        ``normal=True``; the values are those of the full call, at a fraction of its cost.
        ``out`` is then a dict of arrays to write into instead of new ones (such as the dict a
        previous call returned, for rays of the same shape); it is returned, and ``normal`` is
        computed if it has that key."""
        o, d = _coords("origins", origins), _coords("directions", directions)
        if not geometric_only:
            if out is not None or normal is not None:
                raise ValueError("out and normal: only with geometric_only=True")
            return self._native.intersect(o, d, float(tnear), float(tfar), threads)
        lead = o.shape[:-1]
        if out is None:
            out = {
                "t_hit": np.empty(lead, np.float32),
                "prim_ids": np.empty(lead, np.uint32),
                "shape_ids": np.empty(lead, np.uint32),
                "instance_ids": np.empty(lead, np.uint32),
                "uv": np.empty(lead + (2,), np.float32),
            }
            if normal:
                out["normal"] = np.empty(lead + (3,), np.float32)
        elif not isinstance(out, dict):
            raise ValueError(f"out: expected a dict of arrays, got {type(out).__name__}")
        elif normal is not None and bool(normal) != ("normal" in out):
            raise ValueError("normal: out has no 'normal' array" if normal
                             else "normal=False, but out has a 'normal' array")
        self._native.intersect_geometric(o, d, float(tnear), float(tfar), threads, out)
        return out

    def occluded(self, origins, directions, tnear=0.0, tfar=np.inf, threads=None):
        """Whether anything lies on each ray in ``(tnear, tfar)``: a bool array."""
        return self._native.occluded(
            _coords("origins", origins), _coords("directions", directions),
            float(tnear), float(tfar), threads,
        )

    def count_intersections(self, origins, directions, tnear=0.0, tfar=np.inf, threads=None):
        """How many surfaces each ray meets: an int32 array."""
        return self._native.count_intersections(
            _coords("origins", origins), _coords("directions", directions),
            float(tnear), float(tfar), threads,
        )

    def list_intersections(self, origins, directions, tnear=0.0, tfar=np.inf, threads=None):
        """Every hit of every ray, nearest first, in CSR form: the hits of ray ``r`` (in the
        flattened order of the leading shape) are ``ray_splits[r]:ray_splits[r + 1]`` of
        ``t_hit``, ``prim_ids``, ``shape_ids`` and ``instance_ids``."""
        return self._native.list_intersections(
            _coords("origins", origins), _coords("directions", directions),
            float(tnear), float(tfar), threads,
        )

    def contains(self, points, threads=None):
        """Whether each point is inside the volume the scene's triangles close (exact also next
        to the surface): a bool array."""
        return self._native.contains(_coords("points", points), threads)

    def closest_point(self, points, threads=None):
        """The nearest point of the scene's triangles: a dict of ``position``, ``distance``,
        ``prim_ids``, ``shape_ids``, ``instance_ids`` and ``signed_distance`` (negative inside;
        NaN when the triangles do not close a surface)."""
        return self._native.closest_point(_coords("points", points), threads)

    def __repr__(self):
        w, h = self.size
        return f"<appel.Scene {w}x{h}, source={self.source!r}>"


def load(path, params=None, **kwargs):
    """Any scene Appel reads, as ``appel render`` does: a scene file (TOML, JSON, Mitsuba 3 XML,
    pbrt-v4), a mesh file to frame (``bunny.ply``, ``assets.zip:inner.obj``) or a built-in
    scene's name.

    Keyword arguments that are camera or render keys (``width``, ``height``, ``size``, ``eye``,
    ``spp``, ``integrator``, ``bvh``, ``octree``, ...) override the scene's, after the file is read:
    ``load("s.toml", width=64, height=64, spp=4)``. For a Mitsuba XML file any other keyword is a
    parameter (``-D name=value``): ``load("scene.xml", resx=128)``. ``params`` passes parameters
    by name whatever the name, such as a parameter called ``spp``:
    ``load("scene.xml", params={"spp": 16})``. Values are passed as their text."""
    path = os.fspath(path)
    if params is not None and not isinstance(params, dict):
        raise ValueError(f"params: expected a dict of name to value, got {type(params).__name__}")
    native = _appel.NativeScene.load(path, _json(kwargs), _json(params))
    source = dict(kwargs)
    if params:
        source["params"] = dict(params)
    if not os.path.exists(path) and path in builtin_names():
        return Scene(native, ("builtin", path, source))
    return Scene(native, ("file", os.path.abspath(path), source))


def load_dict(d, base_dir=None):
    """A scene from a dict with the TOML schema; file names are relative to ``base_dir``
    (default: the current folder)."""
    if not isinstance(d, dict):
        raise ValueError(f"d: expected a dict with the scene schema, got {type(d).__name__}")
    base = os.path.abspath(os.fspath(base_dir) if base_dir is not None else os.getcwd())
    native = _appel.NativeScene.from_json(_json(d), base, "<dict>")
    return Scene(native, ("dict", d, base))


def builtin(name, **overrides):
    """A built-in scene (``builtin_names()``), with camera and render keys overridden."""
    native = _appel.NativeScene.builtin(name, _json(overrides))
    return Scene(native, ("builtin", name, dict(overrides)))


def builtin_names():
    return list(_appel.builtin_names())
