#!/usr/bin/env python3
"""Appel's volpath against Mitsuba 3's on the participating-media scenes, on the same machine and
thread count: the sibling of mitsuba_compare.py (whose Mitsuba worker, Appel runs and error
measures it uses), for scenes whose own integrator is Mitsuba's `volpath`.

Scenes: the media references' HG cloud (a 16^3 heterogeneous grid) and homogeneous sphere
(crates/appel/tests/reference/media/, compared at equal time with their Mitsuba references), and
a sparse 64^3 grid with one dense lump in a corner (bench/media/sparse_cloud.xml; its grid is
written here, and it has no reference: samples per second only).

    /tmp/mivenv/bin/python bench/mitsuba_media_compare.py [--threads 2] [--repeat 3] [--quick]
        [--appel PATH]

Every figure is the median of --repeat runs; llvm_ad_rgb is timed after one warm-up render.
"""

import argparse
import math
import os
import struct
import sys
import tempfile

import mitsuba_compare as mc

MEDIA = os.path.join(mc.ROOT, "crates/appel/tests/reference/media")
SPARSE = os.path.join(mc.ROOT, "bench/media/sparse_cloud.xml")

# name, file, reference (or None), spp for samples per second, seconds of the equal-time renders.
SCENES = [
    ("hg_cloud", os.path.join(MEDIA, "hg_cloud.xml"), os.path.join(MEDIA, "hg_cloud.exr"), 1024, 10.0),
    ("homogeneous_sphere", os.path.join(MEDIA, "homogeneous_sphere.xml"),
     os.path.join(MEDIA, "homogeneous_sphere.exr"), 1024, 10.0),
    ("sparse_cloud", SPARSE, None, 1024, 0.0),
]


def write_sparse(path, n=64):
    """A lumpy ball of radius 0.12 centred at (0.25, 0.3, 0.25) of the unit cube, density in
    [0, 1] falling to zero at its rim, and zero everywhere else; x fastest."""
    values = []
    centre = (0.25, 0.3, 0.25)
    for z in range(n):
        for y in range(n):
            for x in range(n):
                p = [(c + 0.5) / n - o for c, o in zip((x, y, z), centre)]
                r = math.sqrt(sum(c * c for c in p)) / 0.12
                lumps = 0.6 + 0.4 * math.sin(40 * p[0]) * math.cos(30 * p[1] + 1) * math.sin(20 * p[2] + 2)
                values.append(max(0.0, 1.0 - r) * lumps)
    header = b"VOL" + bytes([3]) + struct.pack("<iiiii", 1, n, n, n, 1)
    header += struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    with open(path, "wb") as f:
        f.write(header + struct.pack(f"<{len(values)}f", *values))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--threads", default="2", help="thread counts, comma-separated")
    ap.add_argument("--repeat", type=int, default=3, help="runs per figure (median reported)")
    ap.add_argument("--quick", action="store_true", help="a tenth of the samples and budgets")
    ap.add_argument("--appel", default=mc.APPEL, help="the appel binary")
    ap.add_argument("--no-llvm", action="store_true", help="skip Mitsuba's llvm_ad_rgb")
    args = ap.parse_args()
    mc.APPEL = args.appel
    if not os.path.exists(mc.APPEL):
        sys.exit(f"{mc.APPEL} is missing: run `cargo build --release` first")
    sparse_vol = os.path.join(os.path.dirname(SPARSE), "sparse.vol")
    if not os.path.exists(sparse_vol):
        write_sparse(sparse_vol)
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    threads = [int(t) for t in args.threads.split(",")]
    scale = 0.1 if args.quick else 1.0
    variants = ["scalar_rgb"] + ([] if args.no_llvm else ["llvm_ad_rgb"])
    tmp = tempfile.mkdtemp(prefix="appel-mitsuba-media-")
    rows, sps = [], {}
    for name, scene, ref, spp, budget in SCENES:
        spp = max(1, int(spp * scale))
        size = mi.load_file(scene).sensors()[0].film().crop_size()
        size = (int(size[0]), int(size[1]))
        for t in threads:
            a = [mc.appel_sps(scene, size, spp, t, False, 1) for _ in range(args.repeat)]
            rates = {"appel": mc.med([r["msamples_per_second"] for r in a])}
            for v in variants:
                def rate():
                    r = mc.mitsuba(v, scene, size, spp, t, False, None)
                    return size[0] * size[1] * r["spp"] / r["seconds"] / 1e6
                rates[v] = mc.med([rate() for _ in range(args.repeat)])
            sps[(name, t)] = rates
            rows.append((name, f"{size[0]}x{size[1]}", spp, t, rates))
    print("Samples per second (millions; median of %d runs)" % args.repeat)
    print(f"{'scene':<20} {'size':>7} {'spp':>5} {'thr':>3} {'Appel':>8} {'scalar_rgb':>10} "
          f"{'llvm_ad_rgb':>11} {'Appel/scalar':>12} {'Appel/llvm':>10}")
    for name, sz, spp, t, r in rows:
        l = r.get("llvm_ad_rgb", float("nan"))
        print(f"{name:<20} {sz:>7} {spp:>5} {t:>3} {r['appel']:>8.3f} {r['scalar_rgb']:>10.3f} "
              f"{l:>11.3f} {r['appel'] / r['scalar_rgb']:>12.2f} {r['appel'] / l:>10.2f}")
    sys.stdout.flush()

    t = threads[0]
    print()
    print(f"Error at equal time ({t} threads; median of {args.repeat} renders; Mitsuba with different seeds)")
    print(f"{'scene':<20} {'budget s':>8} {'renderer':>11} {'spp':>5} {'time s':>7} {'RMSE':>10} "
          f"{'relMSE':>10}")
    for name, scene, ref, spp, budget in SCENES:
        if ref is None:
            continue
        budget *= scale
        rates = sps[(name, t)]
        reference = mc.read_rgb(ref)
        px = reference.shape[0] * reference.shape[1]
        size = (reference.shape[1], reference.shape[0])
        for who in ["appel"] + variants:
            n = max(1, round(budget * rates[who] * 1e6 / px))
            used = n
            times, rmses, rels = [], [], []
            for k in range(args.repeat):
                if who == "appel":
                    image = os.path.join(tmp, f"appel-{k}.exr")
                    secs = mc.appel_render(scene, size, n, t, False, image)
                else:
                    image = os.path.join(tmp, f"mitsuba-{k}.npy")
                    r = mc.mitsuba(who, scene, size, n, t, False, None, image, k + 1)
                    secs, used = r["seconds"], r["spp"]
                rmse, rel = mc.errors(mc.read_rgb(image), reference)
                times.append(secs)
                rmses.append(rmse)
                rels.append(rel)
            print(f"{name:<20} {budget:>8.1f} {who:>11} {used:>5} {mc.med(times):>7.2f} "
                  f"{mc.med(rmses):>10.5f} {mc.med(rels):>10.5f}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
