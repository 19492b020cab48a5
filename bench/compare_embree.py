#!/usr/bin/env python3
"""Appel against Intel Embree, on the same camera rays.

For each mesh: `appel convert` writes its triangles in Appel's order; `appel render` writes the `depth`,
`shapeid` and `primid` AOVs of a raycast render through an explicit camera; the same camera rays (Appel's
exact pixel convention, computed here in float32) are cast with Embree through the `embreex` package.
The script reports hit/miss agreement, same-triangle agreement and depth agreement, and exits 1 when
they fall below the thresholds of the acceptance criteria (99.99%, 99.9%, 1e-5 relative).

With --time it also times closest-hit queries on those rays: Embree's `run` (rtcIntersect1 per ray,
one thread) against `appel bench` on the same camera with one thread.

    python3 -m pip install -r bench/requirements.txt
    python3 bench/compare_embree.py ../shared/data/common-3d-test-models/stanford-bunny.obj.gz
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HIT_MISS_MIN = 0.9999
SAME_PRIM_MIN = 0.999
DEPTH_REL_TOL = 1e-5


def read_ply(path):
    """Binary little-endian PLY as written by `appel convert`: vertices, triangles, shape offsets."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    shapes = {}
    nv = nf = 0
    for line in header:
        words = line.split()
        if words[:3] == ["comment", "appel", "shape"]:
            shapes[int(words[3])] = int(words[4])
        elif words[:2] == ["element", "vertex"]:
            nv = int(words[2])
        elif words[:2] == ["element", "face"]:
            nf = int(words[2])
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=end).reshape(nv, 3)
    faces = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", (3,))]), count=nf, offset=end + 12 * nv)
    assert (faces["n"] == 3).all()
    return vertices, faces["i"], shapes


def camera_for(vertices, fov):
    """A camera on a diagonal that fits the bounding sphere: the same arguments go to both renderers."""
    lo, hi = vertices.min(axis=0).astype(np.float64), vertices.max(axis=0).astype(np.float64)
    centre = (lo + hi) / 2
    radius = np.linalg.norm(hi - lo) / 2
    direction = np.array([0.6, 0.45, 0.8])
    direction /= np.linalg.norm(direction)
    distance = radius / math.sin(math.radians(fov) / 2) * 1.05
    eye = centre + distance * direction
    return eye.astype(np.float32), centre.astype(np.float32), np.array([0, 1, 0], np.float32)


def camera_rays(eye, look_at, up, fov, w, h):
    """Appel's exact convention (README, 'Camera'), in float32 like Appel."""
    f32 = np.float32

    def normalize(v):
        return v / np.sqrt((v * v).sum(axis=-1, keepdims=True))

    forward = normalize(look_at - eye)
    right = normalize(np.cross(forward, up))
    true_up = np.cross(right, forward)
    t = f32(math.tan(math.radians(fov) * 0.5))
    i = np.arange(w, dtype=f32) + f32(0.5)
    j = np.arange(h, dtype=f32) + f32(0.5)
    u = (f32(2) * i / f32(w) - f32(1)) * t * f32(w) / f32(h)
    v = (f32(1) - f32(2) * j / f32(h)) * t
    uu, vv = np.meshgrid(u, v)
    d = forward[None, None, :] + uu[..., None] * right[None, None, :] + vv[..., None] * true_up[None, None, :]
    d = normalize(d.astype(f32)).reshape(-1, 3)
    o = np.broadcast_to(eye, d.shape).copy()
    return o.astype(f32), d.astype(f32)


def read_aovs(path):
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        ch = f.channels()
        return ch["depth"].pixels.reshape(-1), ch["shapeid"].pixels.reshape(-1), ch["primid"].pixels.reshape(-1)


def vec(v):
    return ",".join(f"{x:.9g}" for x in v)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("meshes", nargs="+", help="mesh files (or scene files) Appel can load")
    ap.add_argument("--appel", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "appel"))
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--fov", type=float, default=40.0)
    ap.add_argument("--accel", default="bvh", help="Appel structure(s), comma-separated")
    ap.add_argument("--time", action="store_true", help="also time both on the same rays, one thread")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    from embreex import rtcore_scene as rtcs
    from embreex.mesh_construction import TriangleMesh

    w, h = (int(x) for x in args.size.lower().split("x"))
    ok = True
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in args.meshes:
            ply = os.path.join(tmp, "mesh.ply")
            subprocess.run([args.appel, "convert", mesh, "-o", ply], check=True)
            vertices, triangles, shapes = read_ply(ply)
            eye, look_at, up = camera_for(vertices, args.fov)
            cam = ["--eye", vec(eye), "--look-at", vec(look_at), "--up", vec(up), "--fov", str(args.fov), "--size", args.size]
            origins, dirs = camera_rays(eye, look_at, up, args.fov, w, h)

            scene = rtcs.EmbreeScene()
            TriangleMesh(scene, vertices[triangles])
            start = time.perf_counter()
            res = scene.run(origins, dirs, output=1)
            embree_seconds = time.perf_counter() - start
            e_prim = res["primID"].astype(np.int64)
            e_hit = e_prim >= 0
            e_t = res["tfar"]

            for accel in args.accel.split(","):
                exr = os.path.join(tmp, "aov.exr")
                subprocess.run(
                    [args.appel, "render", mesh, "-o", exr, "--quiet", "--aov", "depth,primid", "--integrator", "raycast",
                     "--spp", "1", "--accel", accel] + cam,
                    check=True, stdout=subprocess.DEVNULL)
                depth, shape_id, prim_id = read_aovs(exr)
                a_hit = prim_id != 0xFFFFFFFF
                offsets = np.zeros(int(shape_id[a_hit].max(initial=0)) + 1, np.int64)
                for s, first in shapes.items():
                    if s < len(offsets):
                        offsets[s] = first
                a_prim = np.where(a_hit, offsets[np.where(a_hit, shape_id, 0)] + prim_id, -1)

                both = a_hit & e_hit
                hit_agree = float((a_hit == e_hit).mean())
                same_prim = float((a_prim[both] == e_prim[both]).mean()) if both.any() else 1.0
                rel = np.abs(depth[both] - e_t[both]) / np.maximum(np.abs(e_t[both]), 1e-30)
                depth_ok = float((rel <= DEPTH_REL_TOL).mean()) if both.any() else 1.0
                r = {
                    "mesh": os.path.basename(mesh), "accel": accel, "triangles": int(len(triangles)),
                    "pixels": int(w * h), "hits": int(e_hit.sum()), "hit_miss_agreement": hit_agree,
                    "same_primid": same_prim, "depth_within_1e-5": depth_ok,
                    "max_depth_rel_error": float(rel.max()) if both.any() else 0.0,
                }
                r["pass"] = hit_agree >= HIT_MISS_MIN and same_prim >= SAME_PRIM_MIN and depth_ok >= SAME_PRIM_MIN
                if args.time:
                    r["embree_mrays_1t"] = len(origins) / embree_seconds / 1e6
                    out = subprocess.run(
                        [args.appel, "bench", mesh, "--accel", accel, "--threads", "1", "--json"] + cam,
                        check=True, capture_output=True, text=True).stdout
                    b = json.loads(out.strip().splitlines()[-1])
                    r["appel_mrays_1t"] = b["primary_mrays_1t"]
                    r["ratio"] = r["appel_mrays_1t"] / r["embree_mrays_1t"]
                ok &= r["pass"]
                results.append(r)
                if args.json:
                    print(json.dumps(r))
                else:
                    line = (f"{r['mesh']:<28} {accel:<7} {r['triangles']:>9} tris  hit/miss {100 * hit_agree:8.4f}%  "
                            f"same primid {100 * same_prim:8.4f}%  depth<=1e-5 {100 * depth_ok:8.4f}%  "
                            f"{'PASS' if r['pass'] else 'FAIL'}")
                    if args.time:
                        line += f"  Mrays/s 1 thread: appel {r['appel_mrays_1t']:.2f} embree {r['embree_mrays_1t']:.2f}"
                    print(line)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
