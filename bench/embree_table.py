#!/usr/bin/env python3
"""Appel's structures against Embree, one markdown table for several targets.

Runs `appel bench TARGET --embree --json` for each target (mesh files, scene files, built-in or
generated benchmark scenes) and prints, per target and structure, build time, bytes and Mrays/s for
camera, incoherent and shadow rays, each with its ratio to Embree measured in the same run.

    python3 bench/embree_table.py ../shared/data/common-3d-test-models/stanford-bunny.obj.gz uniform \
        --accel kdtree,bvh --threads 1 -- --triangles 1000000
Arguments after `--` go to every `appel bench` call.
"""

import argparse
import sys
from pathlib import Path

from appel_json import DEFAULT_APPEL, bench_rows, split_extra


def run(appel, target, accel, threads, extra):
    return bench_rows(appel, target, accel, extra + (["--threads", str(threads)] if threads else []))


def main():
    argv, extra = split_extra(sys.argv[1:])
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("targets", nargs="+")
    ap.add_argument("--accel", default="kdtree,bvh")
    ap.add_argument("--threads", type=int, default=0, help="threads of the Nt columns (default: all)")
    ap.add_argument("--one-thread", action="store_true", help="report the 1-thread figures")
    ap.add_argument("--appel", default=DEFAULT_APPEL)
    args = ap.parse_args(argv)
    suffix = "_1t" if args.one_thread else ""
    print(
        "| target | triangles | accel | build ms | MB | camera Mrays/s | incoherent | shadow (any hit) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for target in args.targets:
        rows = run(args.appel, target, args.accel, args.threads, extra)
        # Each row against the Embree of its own triangle test (robust for watertight, the
        # default for Moller-Trumbore), as `appel bench --embree` pairs them.
        peers = {r["triangle"]: r for r in rows if r["accel"].startswith("embree")}

        def cell(r, key):
            embree = peers[r["triangle"]]
            v, e = r[key + suffix], embree[key + suffix]
            if r is embree:
                return f"{v:.3g}"
            return f"{v:.3g} ({v / e:.2f}x)" if e > 0 else f"{v:.3g}"

        for r in rows:
            embree = peers[r["triangle"]]
            build = f"{r['build_ms']:.0f}"
            if r is not embree and embree["build_ms"] > 0:
                build += f" ({r['build_ms'] / embree['build_ms']:.2f}x)"
            print(
                f"| {Path(target).name} | {r['triangles']:,} | {r['accel']} ({r['triangle']}) | {build} | "
                f"{r['bytes'] / 1e6:.1f} | {cell(r, 'primary_mrays')} | "
                f"{cell(r, 'incoherent_mrays')} | {cell(r, 'shadow_mrays')} |"
            )
        for r in rows:
            mine = r.get("packet8_mrays" + suffix)
            if r["accel"].startswith("embree"):
                print(f"| | | {r['accel']} rtcIntersect8 | | | {mine:.3g} | | |")
            elif mine:
                packet = peers[r["triangle"]].get("packet8_mrays" + suffix)
                ratio = f" ({mine / packet:.2f}x)" if packet else ""
                print(f"| | | {r['accel']} ({r['triangle']}) packets of 8 | | | {mine:.3g}{ratio} | | |")
    threads = "1 thread" if args.one_thread else f"{rows[0]['threads']} threads"
    print(f"\nMrays/s with {threads}; in brackets, the ratio to Embree in the same run.")


if __name__ == "__main__":
    main()
