#!/usr/bin/env python3
"""Tiles on a Dask LocalCluster: the wall time of `appel.distributed.render` with 1 and with 2
single-threaded worker processes, beside a local render with 1 and 2 threads, for one scene.

    .venv/bin/python bench/dask_scaling.py mirror-room --size 640x480 --spp 16
    .venv/bin/python bench/dask_scaling.py ../shared/data/bitterli-scenes/cornell-box/mitsuba/scene_v3.xml --size 256x256 --spp 64

A scene is a built-in name or a scene file. Each figure is the median of --repeat renders after one
warm-up render, which loads and builds the scene on every worker (what the cache then saves).
"""

import argparse
import pathlib
import statistics
import time

import numpy as np

import appel
from appel import distributed


def median_seconds(call, repeat):
    call()  # warm-up: workers load and cache the scene
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        image = call()
        times.append(time.perf_counter() - start)
    return statistics.median(times), image


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("scene")
    p.add_argument("--size", default="640x480")
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--tile", default="128x128")
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args()
    from dask.distributed import Client, LocalCluster

    width, height = (int(x) for x in args.size.split("x"))
    tile = tuple(int(x) for x in args.tile.split("x"))
    if pathlib.Path(args.scene).exists():
        scene = appel.load(args.scene, width=width, height=height)
    else:
        scene = appel.builtin(args.scene, width=width, height=height)
    rows = []
    for threads in (1, 2):
        t, local = median_seconds(lambda: scene.render(spp=args.spp, threads=threads), args.repeat)
        rows.append((f"local render, {threads} thread(s)", t))
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            t, tiled = median_seconds(
                lambda: distributed.render(scene, client, tile=tile, spp=args.spp, progress=False),
                args.repeat)
        assert np.array_equal(tiled.rgb, local.rgb), "tiles differ from the local render"
        rows.append((f"Dask LocalCluster, {workers} worker(s) x 1 thread", t))
    base = rows[2][1]
    print(f"{args.scene} {width}x{height}, {args.spp} spp, tiles {tile[0]}x{tile[1]}")
    print("| run | seconds (median) | speed-up vs 1 worker |")
    print("|---|---|---|")
    for name, t in rows:
        print(f"| {name} | {t:.3f} | {base / t:.2f} |")


if __name__ == "__main__":
    main()
