"""Tiles on a 2-process LocalCluster (1 thread each) reassemble bit for bit into the local render,
also when a worker is killed mid-render; scene errors fail the render and write nothing."""

import concurrent.futures as cf
import os
import signal
import sys
import subprocess
import threading
import time

import numpy as np
import pytest

import appel

distributed = pytest.importorskip("distributed")
from appel import distributed as ad  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def same(a, b):
    assert np.array_equal(a.rgb, b.rgb)
    assert a.aovs.keys() == b.aovs.keys()
    for k in a.aovs:
        assert np.array_equal(a.aovs[k], b.aovs[k]), k


def test_builtin_scene_tiles_are_the_local_render(client):
    s = appel.builtin("whitted", width=90, height=70)
    for kw in ({"spp": 2, "aovs": ("depth", "primid")},
               {"spp": 3, "integrator": "path", "aovs": ("variance",)}):
        local = s.render(**kw)
        remote = ad.render(s, client, tile=(32, 24), progress=False, **kw)
        same(local, remote)


def test_generated_ecosystem_tiles_are_the_local_render(client, cli, tmp_path):
    subprocess.run([cli, "gen", "ecosystem", "-o", str(tmp_path), "--detail", "0.001",
                    "--seed", "1"], check=True, capture_output=True)
    s = appel.load(tmp_path / "ecosystem.toml", width=80, height=60)
    local = s.render(aovs=("depth", "instanceid"))
    remote = ad.render(s, client, tile=(40, 32), aovs=("depth", "instanceid"), progress=False)
    same(local, remote)
    ref = ad.SceneRef.of(s)
    assert ref.sha256 and not ref.builtin
    same(local, ad.render(ref, client, tile=(64, 64), aovs=("depth", "instanceid"),
                          progress=False))


def test_a_killed_worker_loses_only_its_tiles(client):
    s = appel.builtin("whitted", width=96, height=96)
    kw = {"spp": 64, "aovs": ("depth",)}
    local = s.render(**kw)
    out = {}
    t = threading.Thread(target=lambda: out.update(
        image=ad.render(s, client, tile=(16, 16), progress=False, **kw)))
    before = client.run(os.getpid)
    t.start()
    deadline = time.time() + 30
    victim = None
    while victim is None and time.time() < deadline:
        busy = [w for w, tasks in client.processing().items() if tasks]
        if busy:
            victim = busy[0]
        time.sleep(0.05)
    assert victim is not None, "no worker ever had a tile"
    time.sleep(0.2)
    os.kill(before[victim], signal.SIGKILL)
    t.join(120)
    assert "image" in out, "the render did not finish"
    same(local, out["image"])
    client.wait_for_workers(2, timeout=60)
    after = client.run(os.getpid)
    assert before[victim] not in after.values()


def test_scene_errors_fail_the_render_and_write_nothing(client, tmp_path):
    scene_file = tmp_path / "s.toml"
    scene_file.write_text('[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 32\n'
                          'height = 32\n\n[[shape]]\ntype = "sphere"\ncenter = [0, 0, 0]\n'
                          'radius = 1.0\n')
    ref = ad.SceneRef(str(scene_file), {}, "0" * 64)
    with pytest.raises(ad.SceneMismatch, match="SHA-256"):
        ad.render(ref, client, progress=False)
    good = ad.SceneRef.of(appel.load(scene_file))
    scene_file.write_text(scene_file.read_text().replace("1.0", "2.0"))
    out = tmp_path / "frame_{:04d}.png"
    with pytest.raises(ad.SceneMismatch, match="differs"):
        ad.render_frames(good, client, [{}, {}], out=str(out), progress=False)
    assert not list(tmp_path.glob("frame_*"))
    with pytest.raises(ValueError, match="made from arrays"):
        ad.render(appel.Scene.from_meshes([appel.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                                                      [[0, 1, 2]])]), client)


def test_frames_and_executors(tmp_path):
    s = appel.builtin("whitted", width=40, height=30)
    cams = [{"eye": [0, 1.4, 6]}, {"eye": [1, 1.4, 6], "width": 20, "height": 16}]
    with cf.ThreadPoolExecutor(2) as pool:
        paths = ad.render_frames(s, pool, cams, out=str(tmp_path / "f{}.png"), tile=(16, 16),
                                 progress=False)
        assert [os.path.basename(p) for p in paths] == ["f0.png", "f1.png"]
        local = s.render(camera=cams[1])
        assert local.rgb.shape == (16, 20, 3)
        lp = tmp_path / "local.png"
        local.save(lp)
        assert lp.read_bytes() == (tmp_path / "f1.png").read_bytes()
    with cf.ProcessPoolExecutor(2) as pool:
        same(s.render(spp=2), ad.render(s, pool, tile=(16, 16), spp=2, progress=False))


def test_command_line(tmp_path, client):
    addr = client.scheduler.address
    out = tmp_path / "w.exr"
    r = subprocess.run([sys.executable, "-m", "appel.distributed", "whitted", "-o", str(out),
                        "--scheduler", addr, "-D", "width=32", "-D", "height=24", "--tile",
                        "16x16", "--aov", "depth", "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    local = tmp_path / "l.exr"
    appel.builtin("whitted", width=32, height=24).render(aovs=("depth",)).save(local)
    assert out.read_bytes() == local.read_bytes()
