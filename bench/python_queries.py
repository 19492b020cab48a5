#!/usr/bin/env python3
"""Ray throughput from Python: appel's `Scene.intersect` (full, and `geometric_only=True`) and
`Scene.occluded` against embreex and trimesh on the same numpy arrays, with 1 and 2 threads, and
the cost of crossing into Python as the ratio to the CLI's own figure for the same camera rays
(`appel bench MESH --json`).

    .venv/bin/python bench/python_queries.py ../shared/data/common-3d-test-models/{spot.obj,stanford-bunny.obj.gz}

Run it from the repository root after `scripts/test` (which installs `appel` into .venv with
embreex and trimesh). Every figure is the median of --repeat timed calls, all in this one process.
"""

import argparse
import gzip
import json
import pathlib
import statistics
import subprocess
import sys
import time

import numpy as np

import appel

ROOT = pathlib.Path(__file__).resolve().parents[1]


def read_obj(path):
    """Vertices and faces (polygons fanned) of an .obj or .obj.gz: enough for the peers' meshes."""
    path = pathlib.Path(path)
    opener = gzip.open if path.suffix == ".gz" else open
    vertices, faces = [], []
    with opener(path, "rt") as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(c.split("/")[0]) for c in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                faces.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return np.array(vertices, np.float64), np.array(faces, np.int64)


def read_mesh(path):
    import trimesh

    v, f = read_obj(path)
    return trimesh.Trimesh(v, f, process=False)


def camera_rays(camera):
    """The pinhole rays `appel render` traces through pixel centres (scene/camera.rs's formula)."""
    eye = np.array(camera["eye"], np.float64)
    forward = np.array(camera["look_at"], np.float64) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.array(camera["up"], np.float64))
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    w, h = camera["width"], camera["height"]
    t = np.tan(np.radians(camera["fov"]) / 2)
    i, j = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    u = (2 * i / w - 1) * t * w / h
    v = (1 - 2 * j / h) * t
    d = forward + u[..., None] * right + v[..., None] * true_up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    o = np.broadcast_to(eye, d.shape)
    return o.reshape(-1, 3).astype(np.float32), d.reshape(-1, 3).astype(np.float32)


def incoherent_rays(lo, hi, n, seed=1):
    """Rays from a sphere around the mesh toward random points of its box: no two alike."""
    rng = np.random.default_rng(seed)
    centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo)
    o = rng.normal(size=(n, 3))
    o = centre + radius * o / np.linalg.norm(o, axis=1, keepdims=True)
    target = rng.uniform(lo, hi, size=(n, 3))
    return o.astype(np.float32), (target - o).astype(np.float32)


def median_mrays(call, n, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return n / statistics.median(times) / 1e6


def peers(mesh):
    """The peers that are installed: name -> (threads, function of (origins, directions), which
    of appel's calls it is compared with)."""
    found = {}
    try:
        from embreex import rtcore_scene, mesh_construction

        es = rtcore_scene.EmbreeScene()
        mesh_construction.TriangleMesh(es, mesh.triangles.astype(np.float32))
        found["embreex run(output=1)"] = (1, lambda o, d: es.run(o, d, output=1), "geometric")
        found["embreex run(query='OCCLUDED')"] = (
            1, lambda o, d: es.run(o, d, query="OCCLUDED"), "occluded")
    except ImportError:
        print("embreex is not installed: skipped", file=sys.stderr)
    try:
        from trimesh.ray.ray_pyembree import RayMeshIntersector

        rmi = RayMeshIntersector(mesh)
        found["trimesh (embreex) intersects_location"] = (
            1,
            lambda o, d: rmi.intersects_location(o, d, multiple_hits=False),
            "intersect",
        )
    except ImportError:
        print("trimesh's embree backend is not available: skipped", file=sys.stderr)
    return found


def cli_figures(path, threads):
    exe = ROOT / "target" / "release" / "appel"
    out = subprocess.run(
        [str(exe), "bench", str(path), "--accel", "bvh", "--json", "--threads", str(threads)],
        check=True, capture_output=True, text=True,
    ).stdout
    return json.loads(out.splitlines()[0])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("meshes", nargs="+")
    p.add_argument("--repeat", type=int, default=5)
    args = p.parse_args()
    print("| mesh | triangles | rays | caller | threads | Mrays/s | vs appel's same call and threads |")
    print("|---|---|---|---|---|---|---|")
    for path in args.meshes:
        mesh = read_mesh(path)
        scene = appel.load(path)
        name = pathlib.Path(path).name
        lo, hi = scene.bounds
        cam = camera_rays(scene.camera)
        rays = {"camera": cam, "incoherent": incoherent_rays(lo, hi, len(cam[0]))}
        others = peers(mesh)
        cli = {t: cli_figures(path, t) for t in (1, 2)}
        calls = {
            "intersect": ("appel intersect", lambda o, d, t: scene.intersect(o, d, threads=t)),
            "geometric": ("appel intersect(geometric_only=True)",
                          lambda o, d, t: scene.intersect(o, d, threads=t, geometric_only=True)),
            "occluded": ("appel occluded", lambda o, d, t: scene.occluded(o, d, threads=t)),
        }
        for kind, (o, d) in rays.items():
            ours = {}
            for call, (label, f) in calls.items():
                for threads in (1, 2):
                    ours[call, threads] = median_mrays(
                        lambda: f(o, d, threads), len(o), args.repeat)
                    print(f"| {name} | {len(mesh.faces)} | {kind} | {label} | {threads} "
                          f"| {ours[call, threads]:.2f} | 1.00 |")
            for caller, (threads, f, call) in others.items():
                mr = median_mrays(lambda: f(o, d), len(o), args.repeat)
                print(f"| {name} | {len(mesh.faces)} | {kind} | {caller} | {threads} "
                      f"| {mr:.2f} | {mr / ours[call, threads]:.2f} ({call}) |")
            if kind == "camera":
                for threads in (1, 2):
                    key = "primary_mrays_1t" if threads == 1 else "primary_mrays"
                    mr = cli[threads][key]
                    print(f"| {name} | {len(mesh.faces)} | {kind} | CLI `appel bench` | {threads} "
                          f"| {mr:.2f} | {mr / ours['geometric', threads]:.2f} (geometric) |")


if __name__ == "__main__":
    main()
