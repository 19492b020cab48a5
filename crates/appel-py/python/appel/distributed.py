"""Rendering across processes and machines: tiles on a Dask cluster (or any
``concurrent.futures.Executor``), reassembled bit for bit into the image a single machine renders.

The scene reaches workers by reference (:class:`SceneRef`: a path, overrides and the file's
SHA-256), never as a built structure; each worker process loads it once and keeps it. A worker
killed mid-render loses only its tiles, which run again elsewhere; a scene error fails the whole
render, and nothing is written.

    python -m appel.distributed scene.toml -o out.exr --scheduler tcp://HOST:8786
"""

import argparse
import concurrent.futures as cf
import hashlib
import json
import os
import socket
import sys
import uuid
from dataclasses import dataclass, field

import numpy as np

from . import _scene
from ._image import Image, aov_set

__all__ = ["SceneRef", "SceneMismatch", "render", "render_frames", "main"]


class SceneMismatch(ValueError):
    """A worker's copy of the scene file is not the one the render was started with."""


def file_sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _file_of(path):
    """The file that holds a scene: the archive of ``x.zip:inner.obj``, else ``path``."""
    at = path.lower().find(".zip:")
    return path[: at + 4] if at >= 0 else path


@dataclass(frozen=True)
class SceneRef:
    """A scene by reference: ``path`` to a scene file (or a built-in name with ``builtin=True``),
    the ``overrides`` of :func:`appel.load`, and the file's ``sha256`` (checked by each worker;
    None skips the check). Picklable; the built scene never travels."""

    path: str
    overrides: dict = field(default_factory=dict)
    sha256: str = None
    builtin: bool = False

    @classmethod
    def of(cls, scene):
        """The reference of a Scene made by :func:`appel.load` or :func:`appel.builtin`."""
        if isinstance(scene, SceneRef):
            return scene
        source = getattr(scene, "source", None)
        if source is None or source[0] not in ("file", "builtin"):
            raise ValueError(
                "scene: only scenes from appel.load or appel.builtin (or a SceneRef) can be "
                "rendered on workers; this one was made from arrays or a dict"
            )
        kind, path, overrides = source
        if kind == "builtin":
            return cls(path, dict(overrides), None, True)
        return cls(path, dict(overrides), file_sha256(_file_of(path)), False)

    def key(self):
        return (self.path, json.dumps(self.overrides, sort_keys=True, default=str),
                self.sha256, self.builtin)

    def load(self):
        if self.builtin:
            return _scene.builtin(self.path, **self.overrides)
        if self.sha256 is not None:
            try:
                have = file_sha256(_file_of(self.path))
            except OSError as e:
                raise SceneMismatch(
                    f"{socket.gethostname()}: cannot read the scene file {self.path}: {e}"
                ) from None
            if have != self.sha256:
                raise SceneMismatch(
                    f"{socket.gethostname()}: {self.path} has SHA-256 {have}, but the render "
                    f"was started with {self.sha256}: the worker's copy differs"
                )
        return _scene.load(self.path, **self.overrides)


# Scenes this worker process has built, by reference (the most recent few).
_CACHE = {}
_CACHE_SIZE = 2


def _cached(ref):
    key = ref.key()
    scene = _CACHE.get(key)
    if scene is None:
        scene = ref.load()
        while len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = scene
    return scene


def _worker_threads():
    try:
        from distributed import get_worker

        return get_worker().state.nthreads
    except Exception:
        return None


def render_tile(ref, window, spp, integrator, aovs, camera, threads):
    """One tile, on a worker: ``(window, rgb, aovs)``."""
    scene = _cached(ref)
    if threads is None:
        threads = _worker_threads()
    image = scene.render(spp=spp, integrator=integrator, aovs=aovs, threads=threads,
                         camera=camera, window=window)
    return window, image.rgb, image.aovs


def _tiles(width, height, tile):
    tw, th = tile
    if tw < 1 or th < 1:
        raise ValueError(f"tile: expected a positive (width, height), got {tile}")
    return [(x, y, min(x + tw, width), min(y + th, height))
            for y in range(0, height, th) for x in range(0, width, tw)]


def _is_dask(client):
    return hasattr(client, "scheduler") and hasattr(client, "gather")


def _is_fault(e):
    """Whether an exception is the loss of a worker (to retry), not an error of the scene."""
    name = type(e).__name__
    if name in ("KilledWorker", "CommClosedError", "BrokenProcessPool", "FutureCancelledError"):
        return True
    return isinstance(e, (cf.process.BrokenProcessPool, cf.CancelledError, EOFError,
                          ConnectionError))


class _Runner:
    """Submits tiles to a Dask client or an executor, retrying lost ones."""

    def __init__(self, client, retries):
        self.client = client
        self.dask = _is_dask(client)
        self.retries = retries
        self.run = uuid.uuid4().hex[:8]

    def submit(self, args, attempt):
        if self.dask:
            x0, y0 = args[1][0], args[1][1]
            key = f"appel-tile-{self.run}-{x0}-{y0}-{attempt}"
            return self.client.submit(render_tile, *args, key=key, pure=False)
        return self.client.submit(render_tile, *args)

    def as_completed(self, futures):
        if self.dask:
            from distributed import as_completed

            return as_completed(futures)
        return cf.as_completed(futures)

    def results(self, jobs, progress=None):
        """Yields each job's result as it comes; a lost job runs again up to ``retries`` times."""
        pending = {}
        for args in jobs:
            pending[self.submit(args, 0)] = (args, 0)
        while pending:
            done = next(iter(self.as_completed(list(pending))))
            args, attempt = pending.pop(done)
            try:
                result = done.result()
            except BaseException as e:
                if _is_fault(e) and attempt < self.retries:
                    pending[self.submit(args, attempt + 1)] = (args, attempt + 1)
                    continue
                for f in pending:
                    f.cancel()
                raise
            if progress is not None:
                progress.update(1)
            yield result


def _bar(total, desc, show):
    if not show:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc=desc, unit="tile")


def _render_image(runner, ref, size, tile, spp, integrator, aovs, camera, threads, bar):
    width, height = size
    jobs = [(ref, w, spp, integrator, aovs, camera, threads) for w in _tiles(width, height, tile)]
    rgb = np.empty((height, width, 3), dtype=np.float32)
    planes = {}
    for (x0, y0, x1, y1), t_rgb, t_aovs in runner.results(jobs, bar):
        rgb[y0:y1, x0:x1] = t_rgb
        for name, a in t_aovs.items():
            if name not in planes:
                planes[name] = np.empty((height, width) + a.shape[2:], dtype=a.dtype)
            planes[name][y0:y1, x0:x1] = a
    return Image(rgb, {a: planes[a] for a in aovs})


def _size(ref, camera):
    """The image size: from the camera overrides if they set it, else from the scene itself
    (loaded here once; a scene that fails to load fails before anything is sent)."""
    scene = ref.load()
    if camera:
        w = camera.get("width", camera.get("size", (None, None))[0])
        h = camera.get("height", camera.get("size", (None, None))[1])
        base_w, base_h = scene.size
        return (w or base_w, h or base_h)
    return scene.size


def render(scene, client, tile=(128, 128), spp=1, aovs=(), retries=2, integrator=None,
           threads=None, progress=True):
    """Renders ``scene`` (a Scene from :func:`appel.load`/:func:`appel.builtin`, or a
    :class:`SceneRef`) in tiles on ``client`` (a ``dask.distributed.Client`` or any
    ``concurrent.futures.Executor``) and returns the :class:`appel.Image`, bit for bit the one
    ``scene.render(spp=spp, integrator=integrator, aovs=aovs)`` returns on one machine."""
    ref = SceneRef.of(scene)
    names = aov_set(aovs)
    size = scene.size if not isinstance(scene, SceneRef) else _size(ref, None)
    tiles = _tiles(size[0], size[1], tuple(tile))
    runner = _Runner(client, retries)
    bar = _bar(len(tiles), "tiles", progress)
    try:
        return _render_image(runner, ref, size, tuple(tile), spp, integrator, names, None,
                             threads, bar)
    finally:
        if bar is not None:
            bar.close()


def render_frames(scene, client, cameras, out="frame_{:04d}.exr", tile=(128, 128), spp=1,
                  aovs=(), retries=2, integrator=None, threads=None, progress=True):
    """Renders one frame per camera (a dict of camera keys each, e.g. ``{"eye": [...]}``) in
    tiles on ``client``; frame ``k`` is written to ``out.format(k)`` once all its tiles are in.
    Returns the paths written. A scene error stops the frames; frames already finished stay."""
    ref = SceneRef.of(scene)
    names = aov_set(aovs)
    runner = _Runner(client, retries)
    paths = []
    for k, camera in enumerate(cameras):
        camera = dict(camera or {})
        size = _size(ref, camera) if k == 0 or camera else size
        tiles = _tiles(size[0], size[1], tuple(tile))
        bar = _bar(len(tiles), f"frame {k}", progress)
        try:
            image = _render_image(runner, ref, size, tuple(tile), spp, integrator, names,
                                  camera, threads, bar)
        finally:
            if bar is not None:
                bar.close()
        path = out.format(k)
        image.save(path)
        paths.append(path)
    return paths


def _override(text):
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    try:
        value = json.loads(value)
    except json.JSONDecodeError:
        pass
    return key.strip(), value


def main(argv=None):
    p = argparse.ArgumentParser(
        prog="python -m appel.distributed",
        description="Render a scene in tiles on a Dask cluster; the image is bit for bit a "
                    "single machine's.")
    p.add_argument("scene", help="a scene file, a mesh file or a built-in scene name")
    p.add_argument("-o", "--output", required=True, help="output image (.png or .exr)")
    p.add_argument("--scheduler", help="address of a Dask scheduler, e.g. tcp://HOST:8786 "
                   "(default: a LocalCluster on this machine)")
    p.add_argument("--workers", type=int, default=None,
                   help="LocalCluster worker processes (default: one per core)")
    p.add_argument("--tile", default="128x128", help="tile size WxH (default 128x128)")
    p.add_argument("--spp", type=int, default=1)
    p.add_argument("--integrator", default=None)
    p.add_argument("--aov", default="", help="comma-separated AOVs for an EXR output")
    p.add_argument("--retries", type=int, default=2)
    p.add_argument("-D", dest="overrides", action="append", type=_override, default=[],
                   metavar="KEY=VALUE", help="override a camera or render key (JSON value)")
    p.add_argument("-q", "--quiet", action="store_true")
    a = p.parse_args(argv)
    try:
        tw, th = (int(v) for v in a.tile.lower().split("x"))
    except ValueError:
        p.error(f"--tile: expected WxH, got {a.tile!r}")
    from distributed import Client, LocalCluster

    overrides = dict(a.overrides)
    if os.path.exists(a.scene) or a.scene not in _scene.builtin_names():
        scene = _scene.load(a.scene, **overrides)
    else:
        scene = _scene.builtin(a.scene, **overrides)
    cluster = None
    if a.scheduler:
        client = Client(a.scheduler)
    else:
        cluster = LocalCluster(n_workers=a.workers or os.cpu_count() or 1,
                               threads_per_worker=1, processes=True,
                               dashboard_address=None if a.quiet else ":8787")
        client = Client(cluster)
    try:
        if not a.quiet and client.dashboard_link:
            print(f"dashboard: {client.dashboard_link}", file=sys.stderr)
        image = render(scene, client, tile=(tw, th), spp=a.spp, aovs=a.aov,
                       retries=a.retries, integrator=a.integrator, progress=not a.quiet)
        image.save(a.output)
    except (ValueError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    if not a.quiet:
        print(f"{a.output}: {image.width}x{image.height}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
