"""Ray and point queries against independent answers: embreex on shared meshes, brute force in
numpy, the CLI's `appel inside`, and the render's AOVs."""

import json
import subprocess

import numpy as np
import pytest

import appel
from conftest import shared


def icosahedron():
    p = (1 + 5 ** 0.5) / 2
    v = np.array([(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p),
                  (0, -1, -p), (0, 1, -p), (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)],
                 dtype=np.float64)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                  [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                  [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                  [8, 6, 7], [9, 8, 1]])
    return v.astype(np.float32).astype(np.float64), f


def brute_hits(v, f, o, d):
    """Every ray-triangle hit (Moller-Trumbore in f64): a list of sorted (t, prim) per ray."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    e1, e2 = b - a, c - a
    out = []
    for oi, di in zip(o, d):
        pv = np.cross(di, e2)
        det = np.einsum("ij,ij->i", e1, pv)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1 / det
            tv = oi - a
            u = np.einsum("ij,ij->i", tv, pv) * inv
            qv = np.cross(tv, e1)
            w = (qv @ di) * inv
            t = np.einsum("ij,ij->i", e2, qv) * inv
        ok = (np.abs(det) > 1e-12) & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0)
        out.append(sorted(zip(t[ok], np.nonzero(ok)[0])))
    return out


def random_rays(n, seed, radius=3.0):
    rng = np.random.default_rng(seed)
    o = rng.normal(size=(n, 3))
    o = radius * o / np.linalg.norm(o, axis=1, keepdims=True)
    target = rng.uniform(-0.7, 0.7, size=(n, 3))
    return o, target - o


def mesh_scene(v, f):
    return appel.Scene.from_meshes([appel.Mesh(v, f)])


def test_queries_keep_the_leading_shape_and_take_both_float_widths():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    o, d = random_rays(24, 1)
    for dtype in (np.float32, np.float64):
        oo, dd = o.astype(dtype).reshape(2, 3, 4, 3), d.astype(dtype).reshape(2, 3, 4, 3)
        h = s.intersect(oo, dd)
        assert h["t_hit"].shape == (2, 3, 4) and h["uv"].shape == (2, 3, 4, 2)
        assert h["normal"].shape == h["position"].shape == (2, 3, 4, 3)
        assert s.occluded(oo, dd).shape == (2, 3, 4) and s.occluded(oo, dd).dtype == bool
        assert s.count_intersections(oo, dd).dtype == np.int32
        assert s.contains(oo).shape == (2, 3, 4)
        assert s.closest_point(oo)["distance"].shape == (2, 3, 4)
    h = s.intersect(o[:1].tolist(), d[:1].tolist())  # lists are accepted
    assert h["t_hit"].shape == (1,)


def test_query_errors_name_the_argument():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    o, d = random_rays(4, 2)
    with pytest.raises(ValueError, match="origins: expected float32 or float64, got int64"):
        s.intersect(o.astype(np.int64), d)
    with pytest.raises(ValueError, match=r"directions: expected shape \(\.\.\., 3\)"):
        s.intersect(o, d[:, :2])
    bad = o.copy()
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match="origins: entry 2 is not finite"):
        s.occluded(bad, d)
    with pytest.raises(ValueError, match="directions: entry 2 is NaN"):
        s.count_intersections(o, bad)
    with pytest.raises(ValueError, match="shapes"):
        s.intersect(o, d[:3])
    with pytest.raises(ValueError, match="points: entry 2"):
        s.contains(bad)
    with pytest.raises(ValueError, match="tfar"):
        s.intersect(o, d, tnear=2.0, tfar=1.0)
    with pytest.raises(ValueError, match="threads"):
        s.intersect(o, d, threads=0)


def test_every_hit_matches_brute_force_and_intersect_is_the_first():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    o, d = random_rays(300, 3)
    want = brute_hits(v, f, o, d)
    lst = s.list_intersections(o, d)
    counts = s.count_intersections(o, d)
    h = s.intersect(o, d, threads=1)
    occ = s.occluded(o, d)
    splits = lst["ray_splits"]
    assert splits.shape == (301,) and splits[-1] == len(lst["t_hit"])
    for r, hits in enumerate(want):
        got = list(zip(lst["t_hit"][splits[r]:splits[r + 1]],
                       lst["prim_ids"][splits[r]:splits[r + 1]]))
        assert counts[r] == len(got) == len(hits), r
        for (tg, pg), (tw, pw) in zip(got, hits):
            assert abs(tg - tw) < 1e-5 and pg == pw
        assert occ[r] == bool(hits)
        if hits:
            assert h["prim_ids"][r] == hits[0][1] and abs(h["t_hit"][r] - hits[0][0]) < 1e-5
            assert np.allclose(h["position"][r], o[r] + hits[0][0] * d[r], atol=1e-5)
        else:
            assert np.isinf(h["t_hit"][r]) and h["prim_ids"][r] == appel.MISS
    # Rays through the centre cross the closed surface twice.
    assert (counts % 2 == 0).all() and (counts == 2).sum() > 100


def test_tnear_skips_the_near_hits():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    o, d = random_rays(200, 4)
    lst = s.list_intersections(o, d)
    sp = lst["ray_splits"]
    h = s.intersect(o, d)
    # All hits are beyond t = 0.5 (rays start 3 from the unit icosahedron's centre).
    beyond = s.intersect(o, d, tnear=1e-3)
    assert np.array_equal(beyond["t_hit"], h["t_hit"])
    assert np.array_equal(beyond["prim_ids"], h["prim_ids"])
    for r in range(len(o)):
        ts = lst["t_hit"][sp[r]:sp[r + 1]]
        if len(ts) == 2:
            mid = float((ts[0] + ts[1]) / 2)
            one = s.intersect(o[r:r + 1], d[r:r + 1], tnear=mid)
            assert one["t_hit"][0] == ts[1]
            assert s.count_intersections(o[r:r + 1], d[r:r + 1], tnear=mid)[0] == 1
            before = float((mid + ts[1]) / 2)
            assert not s.occluded(o[r:r + 1], d[r:r + 1], tnear=mid, tfar=before)[0]


def test_a_ray_through_an_edge_or_a_vertex_crosses_once():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    # Through vertex 0 and the opposite vertex 3 (the icosahedron is symmetric); then through the
    # midpoints of two opposite edges.
    mid = (v[0] + v[1]) / 2
    o = np.array([v[0] * 3, mid * 3])
    d = -o
    lst = s.list_intersections(o, d)
    assert list(lst["ray_splits"]) == [0, 2, 4]
    assert list(s.count_intersections(o, d)) == [2, 2]
    quad = appel.Scene.from_meshes([appel.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
                                               [[0, 1, 2], [0, 2, 3]])])
    assert quad.count_intersections([[0.5, 0.5, 1.0]], [[0, 0, -1.0]])[0] == 1


def test_spheres_are_hit_twice_and_planes_once():
    s = appel.load_dict({
        "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
        "shape": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.0},
                  {"type": "plane", "point": [0, 0, -3], "normal": [0, 0, 1]}],
    })
    lst = s.list_intersections(np.array([[0, 0, 5.0], [0, 5, 5.0]]),
                               np.array([[0, 0, -1.0], [0, 0, -1.0]]))
    assert list(lst["ray_splits"]) == [0, 3, 4]
    assert np.allclose(lst["t_hit"], [4, 6, 8, 8], atol=1e-5)
    assert list(lst["shape_ids"]) == [0, 0, 1, 1]


def test_contains_is_exact_next_to_the_surface(tmp_path, cli):
    """Points a millionth inside and outside every vertex, edge and face of an icosahedron,
    against `appel inside` (the same answer) and the geometry (the true one)."""
    v, f = icosahedron()
    s = mesh_scene(v, f)
    feats = [v]
    for a, b in ((0, 1), (1, 2), (2, 0)):
        feats.append((v[f[:, a]] + v[f[:, b]]) / 2)
    feats.append(v[f].mean(axis=1))
    feats = np.concatenate(feats)
    pts = np.concatenate([feats * (1 - 1e-6), feats * (1 + 1e-6), [[0, 0, 0], [3, 0, 0]]])
    want = np.r_[np.ones(len(feats), bool), np.zeros(len(feats), bool), [True, False]]
    assert np.array_equal(s.contains(pts.astype(np.float32)), want)
    obj = tmp_path / "ico.obj"
    obj.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v.astype(np.float32).tolist())
                   + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f))
    csv = tmp_path / "p.csv"
    csv.write_text("".join(f"{x!r},{y!r},{z!r}\n" for x, y, z in pts.astype(np.float32).tolist()))
    out = subprocess.run([cli, "inside", str(obj), str(csv), "--json"], check=True,
                         capture_output=True, text=True).stdout
    assert json.loads(out) == want.tolist()


def test_closest_point_against_brute_force_and_signs():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    assert s.is_closed
    rng = np.random.default_rng(5)
    p = rng.uniform(-1.5, 1.5, size=(300, 3))
    c = s.closest_point(p)
    tri = v[f]
    for i, q in enumerate(p):
        # Distance to each triangle by dense sampling is too slow; use the exact answer's
        # triangle and check that no vertex or face-plane projection is nearer.
        d_vertices = np.linalg.norm(v - q, axis=1).min()
        assert c["distance"][i] <= d_vertices + 1e-6
        a, b, cc = tri[c["prim_ids"][i]]
        n = np.cross(b - a, cc - a)
        n /= np.linalg.norm(n)
        assert abs(np.dot(c["position"][i] - a, n)) < 1e-5  # on its triangle's plane
        assert abs(np.linalg.norm(c["position"][i] - q) - c["distance"][i]) < 1e-5
    inside = s.contains(p)
    assert np.array_equal(c["signed_distance"] < 0, inside)
    assert np.allclose(np.abs(c["signed_distance"]), c["distance"])
    open_scene = mesh_scene(v, f[:-1])
    assert not open_scene.is_closed
    assert np.isnan(open_scene.closest_point(p)["signed_distance"]).all()


def test_camera_rays_hit_what_the_render_saw():
    """intersect on the camera's pixel-centre rays gives the render's depth and ids."""
    s = appel.builtin("glass-block", width=40, height=30)
    img = s.render(aovs=("depth", "primid"))
    cam = s.camera
    eye, look, up = (np.array(cam[k], dtype=np.float32) for k in ("eye", "look_at", "up"))
    fwd = look - eye
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    tup = np.cross(right, fwd)
    w, h = 40, 30
    t = np.float32(np.tan(np.radians(cam["fov"]) / 2))
    i, j = np.meshgrid(np.arange(w, dtype=np.float32) + 0.5, np.arange(h, dtype=np.float32) + 0.5)
    u = (2 * i / w - 1) * t * w / h
    vv = (1 - 2 * j / h) * t
    d = fwd + u[..., None] * right + vv[..., None] * tup
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    o = np.broadcast_to(eye, d.shape)
    hit = s.intersect(o.astype(np.float32), d.astype(np.float32))
    agree = hit["prim_ids"] == img.aovs["primid"]
    assert agree.mean() > 0.98  # rounding of the ray directions differs at a few edges
    both = agree & np.isfinite(hit["t_hit"])
    assert np.allclose(hit["t_hit"][both], img.aovs["depth"][both], rtol=1e-4)


def read_obj(path):
    """Vertices and fan-triangulated faces of an OBJ file."""
    v, f = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w and w[0] == "f":
            ids = [int(x.split("/")[0]) for x in w[1:]]
            ids = [i - 1 if i > 0 else len(v) + i for i in ids]
            f.extend([ids[0], ids[k], ids[k + 1]] for k in range(1, len(ids) - 1))
    return np.array(v, dtype=np.float32), np.array(f)


def embree_scene(v, f):
    rtcs = pytest.importorskip("embreex.rtcore_scene")
    mc = pytest.importorskip("embreex.mesh_construction")
    scene = rtcs.EmbreeScene()
    mc.TriangleMesh(scene, v[f].astype(np.float32))
    return scene


@pytest.mark.parametrize("name", ["spot.obj", "suzanne.obj"])
def test_agrees_with_embree_on_shared_meshes(name):
    v, f = read_obj(shared("common-3d-test-models", name))
    s = mesh_scene(v, f)
    es = embree_scene(v, f)
    lo, hi = v.min(0), v.max(0)
    rng = np.random.default_rng(7)
    n = 4000
    o = (rng.uniform(lo, hi, size=(n, 3)) + rng.normal(size=(n, 3)) * (hi - lo)).astype(np.float32)
    d = (rng.uniform(lo, hi, size=(n, 3)) - o).astype(np.float32)
    ours = s.intersect(o, d)
    theirs = es.run(o, d, output=1)
    hit_e = theirs["geomID"] != -1
    hit_a = np.isfinite(ours["t_hit"])
    assert (hit_e == hit_a).mean() > 0.999
    both = hit_e & hit_a
    same = ours["prim_ids"][both] == theirs["primID"][both]
    assert same.mean() > 0.995
    assert np.allclose(ours["t_hit"][both][same], theirs["tfar"][both][same], rtol=1e-4)
    geo = s.intersect(o, d, geometric_only=True, normal=True)
    assert np.array_equal(geo["prim_ids"], ours["prim_ids"])
    assert np.allclose(geo["uv"][both][same], np.stack([theirs["u"], theirs["v"]], -1)[both][same],
                       atol=1e-4)
    ng = theirs["Ng"][both][same]
    ng /= np.linalg.norm(ng, axis=-1, keepdims=True)
    # Embree's Ng follows the winding; Appel's is turned toward the vertex normals if any.
    assert np.allclose(np.abs((geo["normal"][both][same] * ng).sum(-1)), 1, atol=1e-4)
    occ = es.run(o, d, query="OCCLUDED")
    assert (s.occluded(o, d) == (np.asarray(occ) != -1)).mean() > 0.999


GEOMETRIC = ("t_hit", "prim_ids", "shape_ids", "instance_ids", "uv")


def assert_geometric_is_full(s, o, d, **kw):
    """The geometric-only hits equal the full call's, value for value, normals included."""
    full = s.intersect(o, d, **kw)
    geo = s.intersect(o, d, geometric_only=True, normal=True, **kw)
    assert set(geo) == set(GEOMETRIC) | {"normal"}
    for k in GEOMETRIC + ("normal",):
        assert geo[k].dtype == full[k].dtype and geo[k].shape == full[k].shape, k
        assert np.array_equal(geo[k], full[k]), k
    bare = s.intersect(o, d, geometric_only=True, **kw)
    assert set(bare) == set(GEOMETRIC)
    for k in GEOMETRIC:
        assert np.array_equal(bare[k], full[k]), k
    return full


def test_geometric_only_hits_are_the_full_hits():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    o, d = random_rays(2000, 11)
    for dtype_o, dtype_d in ((np.float32, np.float32), (np.float64, np.float64),
                             (np.float32, np.float64), (np.float64, np.float32)):
        full = assert_geometric_is_full(s, o.astype(dtype_o), d.astype(dtype_d), threads=1)
    hit = np.isfinite(full["t_hit"])
    assert 0.3 < hit.mean() < 1  # both hits and misses are compared
    assert (full["prim_ids"][~hit] == appel.MISS).all()
    # Every thread count, the leading shape, and the multi-hit path of tnear > 0.
    assert_geometric_is_full(s, o.reshape(40, 50, 3), d.reshape(40, 50, 3), threads=2)
    assert_geometric_is_full(s, o, d, tnear=1e-3)
    assert_geometric_is_full(s, o, d, tfar=3.0)


def test_geometric_only_on_instances_spheres_and_planes():
    v, f = icosahedron()
    mesh = appel.Mesh(v, f)
    turn = np.array([[0, -2, 0, 3], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], np.float64)
    s = appel.Scene.from_meshes([mesh, mesh], transforms=[None, turn])
    o, d = random_rays(3000, 12, radius=6.0)
    full = assert_geometric_is_full(s, o + [1.5, 0, 0], d)
    assert set(np.unique(full["instance_ids"])) == {0, 1, appel.MISS}
    s = appel.load_dict({
        "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
        "shape": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.0},
                  {"type": "plane", "point": [0, 0, -3], "normal": [0, 0, 1]}],
    })
    full = assert_geometric_is_full(s, o, d)
    assert set(np.unique(full["shape_ids"])) == {0, 1, appel.MISS}


def test_geometric_only_on_a_shared_mesh_with_vertex_normals():
    s = appel.load(shared("common-3d-test-models", "spot.obj"))
    lo, hi = s.bounds
    rng = np.random.default_rng(13)
    o = (rng.uniform(lo, hi, size=(5000, 3)) + rng.normal(size=(5000, 3)) * (hi - lo))
    d = rng.uniform(lo, hi, size=(5000, 3)) - o
    full = assert_geometric_is_full(s, o.astype(np.float32), d.astype(np.float32))
    assert np.isfinite(full["t_hit"]).mean() > 0.2
    # Rays from one point, as a camera's, are traced in packets: the same hits again.
    eye = np.array(s.camera["eye"], np.float32)
    target = rng.uniform(lo, hi, size=(64, 48, 3)).astype(np.float32)
    target.sort(axis=1)  # neighbours close together, as a camera's rays are
    full = assert_geometric_is_full(s, np.broadcast_to(eye, target.shape), target - eye)
    assert np.isfinite(full["t_hit"]).mean() > 0.2


def test_geometric_only_writes_into_the_arrays_given():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    o, d = random_rays(500, 14)
    first = s.intersect(o, d, geometric_only=True, normal=True)
    again = {k: np.full_like(a, 7) for k, a in first.items()}
    keep = {k: a for k, a in again.items()}
    got = s.intersect(o, d, geometric_only=True, out=again)
    assert got is again and all(got[k] is keep[k] for k in keep)
    for k in first:
        assert np.array_equal(got[k], first[k]), k
    # Without a 'normal' array none is written.
    del again["normal"]
    assert set(s.intersect(o[:3], d[:3], geometric_only=True,
                           out={k: a[:3] for k, a in again.items()})) == set(GEOMETRIC)


def test_geometric_only_errors_are_clear():
    v, f = icosahedron()
    s = mesh_scene(v, f)
    o, d = random_rays(6, 15)
    geo = s.intersect(o, d, geometric_only=True)
    bad = d.copy()
    bad[4, 2] = np.nan
    with pytest.raises(ValueError, match="directions: entry 4 is NaN"):
        s.intersect(o, bad, geometric_only=True)
    with pytest.raises(ValueError, match="origins: entry 4 is not finite"):
        s.intersect(bad, d, geometric_only=True)
    with pytest.raises(ValueError, match="origins: expected float32 or float64, got int32"):
        s.intersect(o.astype(np.int32), d, geometric_only=True)
    with pytest.raises(ValueError, match=r"directions: expected shape \(\.\.\., 3\)"):
        s.intersect(o, d[:, :2], geometric_only=True)
    with pytest.raises(ValueError, match="shapes"):
        s.intersect(o, d[:5], geometric_only=True)
    with pytest.raises(ValueError, match="only with geometric_only=True"):
        s.intersect(o, d, out=geo)
    with pytest.raises(ValueError, match="out: expected a dict"):
        s.intersect(o, d, geometric_only=True, out=[geo["t_hit"]])
    with pytest.raises(ValueError, match='out: no array "uv"'):
        s.intersect(o, d, geometric_only=True, out={k: a for k, a in geo.items() if k != "uv"})
    with pytest.raises(ValueError, match="normal: out has no 'normal' array"):
        s.intersect(o, d, geometric_only=True, normal=True, out=geo)
    wrong = [("t_hit", geo["t_hit"].astype(np.float64)),     # dtype
             ("prim_ids", geo["prim_ids"].astype(np.int32)),  # signedness
             ("uv", geo["uv"][:5]),                           # shape
             ("uv", np.empty((6, 4), np.float32)[:, ::2]),    # not contiguous
             ("t_hit", geo["t_hit"].tolist())]                # not an array
    for key, value in wrong:
        with pytest.raises(ValueError, match=f"out\\[\"{key}\"\\]: expected a writeable"):
            s.intersect(o, d, geometric_only=True, out={**geo, key: value})
    frozen = geo["t_hit"].copy()
    frozen.flags.writeable = False
    with pytest.raises(ValueError, match="not writeable"):
        s.intersect(o, d, geometric_only=True, out={**geo, "t_hit": frozen})
    # An output that is also an input (t_hit over the origins' memory) is refused.
    o32 = o.astype(np.float32)
    with pytest.raises(ValueError, match="shares memory"):
        s.intersect(o32, d, geometric_only=True, out={**geo, "t_hit": o32.reshape(-1)[:6]})
    with pytest.raises(ValueError, match="tfar"):
        s.intersect(o, d, tnear=1.0, tfar=1.0, geometric_only=True)
    with pytest.raises(ValueError, match="threads"):
        s.intersect(o, d, geometric_only=True, threads=-1)
