#!/usr/bin/env python3
"""Appel's BVH against Embree on every ray kind and the build, repeated: medians of per-run ratios.

On a machine whose speed swings from run to run, one run's ratio says little. This runs
`appel bench TARGET --accel bvh --embree --json` `--repeat` times per target (alternating the
binaries given to `--appel`, so that a before/after pair sees the same conditions) and prints,
per target and binary, the median and range of Appel / Embree for camera, incoherent and shadow
rays (1 thread), camera-ray packets of 8 against `rtcIntersect8`, and the build time (each ratio
from one run).

    python3 bench/embree_ratios.py ../shared/data/common-3d-test-models/stanford-bunny.obj.gz \\
        --repeat 5 --appel /tmp/appel_before,target/release/appel -- --runs 5 --builds 3 --threads 1
Arguments after `--` go to every `appel bench` call.
"""

import argparse
import statistics
import sys
from pathlib import Path

from appel_json import DEFAULT_APPEL, bench_rows, split_extra

# (column, key in the JSON): rates are Appel / Embree (above 1: Appel faster), the build is
# Appel's time / Embree's (below 1: Appel faster).
COLUMNS = [
    ("camera", "primary_mrays_1t"),
    ("incoherent", "incoherent_mrays_1t"),
    ("shadow", "shadow_mrays_1t"),
    ("packets / rtcIntersect8", "packet8_mrays_1t"),
    ("build", "build_ms"),
]


def bench(appel, target, extra):
    rows = bench_rows(appel, target, "bvh", extra)
    bvh = next(r for r in rows if r["accel"] == "bvh")
    emb = next(r for r in rows if r["accel"].startswith("embree"))
    return {key: bvh[key] / emb[key] for _, key in COLUMNS}


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
    for _ in range(args.repeat):
        for target in args.targets:
            for appel in binaries:
                for key, r in bench(appel, target, extra).items():
                    ratios.setdefault((target, appel, key), []).append(r)
    print("| target | binary | " + " | ".join(c for c, _ in COLUMNS) + " |")
    print("|---|---|" + "---|" * len(COLUMNS))
    for target in args.targets:
        for appel in binaries:
            cells = []
            for _, key in COLUMNS:
                v = ratios[(target, appel, key)]
                cells.append(f"{statistics.median(v):.2f}x ({min(v):.2f}-{max(v):.2f})")
            print(f"| {Path(target).name} | {appel} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
