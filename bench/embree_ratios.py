#!/usr/bin/env python3
"""Appel's BVH against Embree like for like, on every ray kind and the build, repeated: medians.

`appel bench TARGET --accel bvh --embree --json` measures both pairings on the same rays: Appel's
watertight test beside Embree's robust mode, and Appel's Moller-Trumbore test beside Embree's
default, each ratio taken within one run (the `vs_embree` of each bvh row). On a machine whose
speed swings from run to run, one run's ratio says little: this runs it `--repeat` times per
target (alternating the binaries given to `--appel`, so that a before/after pair sees the same
conditions) and prints, per target, binary and pairing, the median and range of Appel / Embree for
camera, incoherent, shadow and path-bounce rays (1 thread), camera-ray packets of 8 against `rtcIntersect8`, and
the build time, with the bytes per triangle of both.

    python3 bench/embree_ratios.py ../shared/data/common-3d-test-models/stanford-bunny.obj.gz \\
        --repeat 5 --appel /tmp/appel_before,target/release/appel -- --runs 5 --builds 3 --threads 1
Arguments after `--` go to every `appel bench` call (`--triangle moller` measures one pairing).
"""

import argparse
import statistics
import sys
from pathlib import Path

from appel_json import DEFAULT_APPEL, bench_rows, split_extra

# (column, key in `vs_embree`): rates are Appel / Embree (above 1: Appel faster), the build is
# Appel's time / Embree's (below 1: Appel faster).
COLUMNS = [
    ("camera", "camera_1t"),
    ("incoherent", "incoherent_1t"),
    ("shadow", "shadow_1t"),
    ("path bounces", "path_1t"),
    ("packets / rtcIntersect8", "packet8_1t"),
    ("build", "build"),
]


def bench(appel, target, extra):
    """{(triangle test, Embree row): (ratios, Appel's bytes per triangle, Embree's)} of one run."""
    rows = bench_rows(appel, target, "bvh", extra)
    embree = {r["accel"]: r for r in rows if r["accel"].startswith("embree")}
    out = {}
    for r in rows:
        v = r.get("vs_embree")
        if r["accel"] == "bvh" and v:
            peer = embree[v["peer"]]
            out[(r["triangle"], v["peer"])] = (v, r["bytes_per_triangle"], peer["bytes_per_triangle"])
    if not out:
        sys.exit(f"{target}: no bvh row with Embree ratios")
    return out


def main():
    argv, extra = split_extra(sys.argv[1:])
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("targets", nargs="+")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument(
        "--appel",
        default=DEFAULT_APPEL,
        help="comma-separated appel binaries, alternated run by run",
    )
    args = ap.parse_args(argv)
    binaries = args.appel.split(",")
    ratios = {}
    sizes = {}
    for _ in range(args.repeat):
        for target in args.targets:
            for appel in binaries:
                for pairing, (v, ours, theirs) in bench(appel, target, extra).items():
                    for _, key in COLUMNS:
                        ratios.setdefault((target, appel, pairing, key), []).append(v.get(key))
                    sizes[(target, appel, pairing)] = (ours, theirs)
    print(
        "| target | binary | pairing | "
        + " | ".join(c for c, _ in COLUMNS)
        + " | bytes/triangle (Embree) |"
    )
    print("|---|---|---|" + "---|" * (len(COLUMNS) + 1))
    for target in args.targets:
        for appel in binaries:
            pairings = sorted({k[2] for k in sizes if k[0] == target and k[1] == appel})
            # Watertight first, as Appel's default.
            for pairing in sorted(pairings, key=lambda p: p[0] != "watertight"):
                cells = []
                for _, key in COLUMNS:
                    v = [x for x in ratios[(target, appel, pairing, key)] if x is not None]
                    cells.append(
                        f"{statistics.median(v):.2f}x ({min(v):.2f}-{max(v):.2f})" if v else "-"
                    )
                ours, theirs = sizes[(target, appel, pairing)]
                label = f"{pairing[0]} / {pairing[1]}"
                print(
                    f"| {Path(target).name} | {appel} | {label} | "
                    + " | ".join(cells)
                    + f" | {ours:.1f} ({theirs:.1f}) |"
                )


if __name__ == "__main__":
    main()
