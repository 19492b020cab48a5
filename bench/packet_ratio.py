#!/usr/bin/env python3
"""Camera-ray packets of eight against Embree's rtcIntersect8, repeated: medians over repeats.

Runs `appel bench TARGET --accel bvh --embree --json` `--repeat` times per target and prints, for
one thread (and all threads), the median of Appel's single-ray and packet rates, Embree's single-ray
and packet rates, and the median of the per-run ratios (each ratio is from one run, so both sides
saw the same machine load).

    python3 bench/packet_ratio.py ../shared/data/common-3d-test-models/stanford-bunny.obj.gz \\
        --repeat 5 -- --runs 5 --threads 2
Arguments after `--` go to every `appel bench` call.
"""

import argparse
import statistics
import sys
from pathlib import Path

from appel_json import DEFAULT_APPEL, bench_rows, split_extra


def main():
    argv, extra = split_extra(sys.argv[1:])
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("targets", nargs="+")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--appel", default=DEFAULT_APPEL)
    args = ap.parse_args(argv)
    print("| target | threads | bvh single | bvh packets of 8 | embree rtcIntersect1 | embree rtcIntersect8 | packets / embree packets | packets / bvh single |")
    print("|---|---|---|---|---|---|---|---|")
    for target in args.targets:
        runs = []
        for _ in range(args.repeat):
            rows = bench_rows(args.appel, target, "bvh", extra)
            bvh = next(r for r in rows if r["accel"] == "bvh")
            emb = next(r for r in rows if r["accel"].startswith("embree"))
            if bvh.get("packet8_mismatches"):
                sys.exit(f"{target}: {bvh['packet8_mismatches']} packet hits differ from single rays")
            runs.append((bvh, emb))
        for suffix, label in (("_1t", "1"), ("", str(runs[0][0]["threads"]))):
            med = lambda f: statistics.median(f(b, e) for b, e in runs)
            print(
                f"| {Path(target).name} | {label} | {med(lambda b, e: b['primary_mrays' + suffix]):.3g} | "
                f"{med(lambda b, e: b['packet8_mrays' + suffix]):.3g} | "
                f"{med(lambda b, e: e['primary_mrays' + suffix]):.3g} | "
                f"{med(lambda b, e: e['packet8_mrays' + suffix]):.3g} | "
                f"{med(lambda b, e: b['packet8_mrays' + suffix] / e['packet8_mrays' + suffix]):.2f}x | "
                f"{med(lambda b, e: b['packet8_mrays' + suffix] / b['primary_mrays' + suffix]):.2f}x |"
            )


if __name__ == "__main__":
    main()
