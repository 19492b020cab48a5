#!/usr/bin/env python3
"""Regenerates the participating-media reference images of crates/appel/tests/reference/media:
writes the cloud's grid (cloud.vol, Mitsuba's binary volume format) and renders every scene of
the folder with Mitsuba 3 (scalar_rgb, its own volpath) at high sample counts into NAME.exr.

    /tmp/mivenv/bin/python scripts/media_references.py [--spp N] [NAME ...]

Each scene renders with its own sample count (SPP below) unless --spp is given.
"""

import argparse
import math
import struct
from pathlib import Path

FOLDER = Path(__file__).resolve().parent.parent / "crates/appel/tests/reference/media"
# The samples per pixel each stored reference was rendered with.
SPP = {
    "homogeneous_sphere": 32768,
    "hg_cloud": 32768,
    "camera_in_fog": 8192,
    "dielectric_medium": 16384,
    "spot_in_fog": 16384,
}


def write_cloud(path, n=16):
    """A lumpy blob: a ball whose density falls to zero at its rim, modulated by three waves;
    values in [0, 1], x fastest."""
    values = []
    for z in range(n):
        for y in range(n):
            for x in range(n):
                p = [(c + 0.5) / n - 0.5 for c in (x, y, z)]
                r = math.sqrt(sum(c * c for c in p)) / 0.5
                lumps = 0.6 + 0.4 * math.sin(9 * p[0]) * math.cos(7 * p[1] + 1) * math.sin(5 * p[2] + 2)
                values.append(max(0.0, 1.0 - r) * lumps)
    header = b"VOL" + bytes([3]) + struct.pack("<iiiii", 1, n, n, n, 1)
    header += struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    path.write_bytes(header + struct.pack(f"<{len(values)}f", *values))


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--spp", type=int, help="instead of each scene's own count (SPP)")
    parser.add_argument("names", nargs="*", default=list(SPP))
    args = parser.parse_args()
    write_cloud(FOLDER / "cloud.vol")
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    for name in args.names:
        scene = mi.load_file(str(FOLDER / f"{name}.xml"))
        spp = args.spp or SPP[name]
        image = mi.render(scene, spp=spp, seed=1)
        bitmap = mi.Bitmap(image).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32)
        bitmap.write(str(FOLDER / f"{name}.exr"))
        print(f"{name}.exr at {spp} spp")


if __name__ == "__main__":
    main()
