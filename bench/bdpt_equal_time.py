#!/usr/bin/env python3
"""Bidirectional path tracing against path tracing at equal time, on Bitterli's pbrt-v4 scenes
whose light is hard to reach from the camera, against Tungsten's reference renders.

For each scene and integrator, `appel render --time-limit SECONDS` at 128x128 on --threads
threads, --repeat times; the image is compared with Tungsten's 1024x1024 reference averaged
down over 8x8 blocks (a box filter), and the median over the runs of these figures is reported:
  * the image mean over Tungsten's (per channel, then their mean);
  * the relative MSE, mean((x - ref)^2 / (ref^2 + 1e-2)) (Rousselle et al. 2011, as
    bench/mitsuba_compare.py), and the RMSE;
  * the camera rays per pixel the time allowed (for `path` the samples per pixel plus one, the
    ray of the AOVs; for `bdpt` the same for its camera half: the light half traces as many
    light paths, one batch of W x H per sample, in the other half of the time).
water-caustic's reference has a non-finite pixel where it sees the light: the 8x8 block that
holds it is left out of every figure, in both images. Its figures are also given apart for the
pixels that see the scene through the water (the first hit of the ray through the pixel centre
is a water mesh, by `appel render --integrator raycast --aov shapeid`) and for the rest.
The scenes are rendered from a copy of their pbrt file beside a link to their models, with the
pixel filter set to a box of half a pixel: each pixel then estimates the mean of the radiance
over its square, which is what the block average of the reference is (the files' triangle
filter would blur both integrators' images away from it). Everything else is the file's:
`maxdepth`, materials, lights; the integrator is the command line's.

Needs: the release binary (`cargo build --release -p appel-cli`, or --appel PATH), the shared
data (scripts/shared_data.py), and Python with numpy and mitsuba (only to read and write EXR
and PNG: `pip install mitsuba numpy`). Not run in CI (minutes of CPU).

    python3 bench/bdpt_equal_time.py [--threads 2] [--repeat 3] [--scenes veach-bidir]
        [--png docs/images/veach-bidir-bdpt-vs-path.png]
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import shared_data  # noqa: E402

DATA = str(shared_data.data_dir())
SIZE = 128
REF_SIZE = 1024

# name, seconds: the budgets.
SCENES = [("veach-bidir", 30.0), ("water-caustic", 60.0)]
INTEGRATORS = ["path", "bdpt"]  # --integrators adds others (sppm, for water-caustic)


def scene_copy(name, tmp):
    """The scene's pbrt file with a box filter of half a pixel, in `tmp`, its models linked."""
    src_dir = os.path.join(DATA, "bitterli-scenes", name, "pbrt")
    with open(os.path.join(src_dir, "scene-v4.pbrt")) as f:
        text = f.read()
    box = 'PixelFilter "box" "float xradius" [ 0.5 ] "float yradius" [ 0.5 ]'
    text, n = re.subn(r'PixelFilter\s+"\w+"(\s+"[^"]+"\s*\[[^\]]*\])*', box, text, count=1)
    assert n == 1, f"{name}: no PixelFilter"
    out_dir = os.path.join(tmp, name)
    os.makedirs(out_dir, exist_ok=True)
    models = os.path.join(out_dir, "models")
    if not os.path.exists(models):
        os.symlink(os.path.join(src_dir, "models"), models)
    path = os.path.join(out_dir, "scene-v4.pbrt")
    with open(path, "w") as f:
        f.write(text)
    return path


def read_rgb(path):
    import mitsuba as mi
    import numpy as np

    mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
    return np.array(bmp)[..., :3].astype(np.float64)


def reference(name):
    img = read_rgb(os.path.join(DATA, "bitterli-scenes", name, "pbrt", "TungstenRender.exr"))
    assert img.shape[0] == REF_SIZE and img.shape[1] == REF_SIZE, img.shape
    b = REF_SIZE // SIZE
    return img.reshape(SIZE, b, SIZE, b, 3).mean(axis=(1, 3))


def render(appel, scene, integrator, seconds, threads, image, max_depth=None):
    cmd = [appel, "render", scene, "-o", image, "--integrator", integrator,
           "--size", f"{SIZE}x{SIZE}", "--threads", str(threads),
           "--time-limit", str(seconds), "--spp", "65536", "-q"]
    if max_depth is not None:
        cmd += ["--max-depth", str(max_depth)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    text = out.stdout + out.stderr
    m = re.search(r"render ([0-9.]+)s", text)
    rays = re.search(r"camera (\d+)", text)
    return float(m.group(1)), int(rays.group(1)) / (SIZE * SIZE), " ".join(cmd)


def figures(img, ref, mask):
    """Mean over Tungsten's, relative MSE and RMSE over the pixels of `mask`."""
    import numpy as np

    img, ref = img[mask], ref[mask]
    d = img - ref
    rel = float(np.mean(d * d / (ref * ref + 1e-2)))
    rmse = float(np.sqrt(np.mean(d * d)))
    ratio = img.mean(axis=0) / ref.mean(axis=0)
    return float(ratio.mean()), rel, rmse


def through_water(appel, scene, tmp):
    """The pixels whose centre ray first meets a shape made with the material "Water"."""
    import mitsuba as mi
    import numpy as np

    with open(scene) as f:
        text = f.read()
    water, shape, material = [], 0, None
    for line in text.splitlines():
        m = re.match(r'\s*NamedMaterial\s+"([^"]+)"', line)
        if m:
            material = m.group(1)
        if re.match(r'\s*Shape\s+"', line):
            if material == "Water":
                water.append(shape)
            shape += 1
    image = os.path.join(tmp, "shapeid.exr")
    subprocess.run([appel, "render", scene, "-o", image, "--integrator", "raycast", "--aov",
                    "shapeid", "--size", f"{SIZE}x{SIZE}", "--spp", "1", "-q"], check=True,
                   capture_output=True)
    ids = np.array(mi.Bitmap(image))[..., 3]
    return np.isin(ids, np.array(water, dtype=ids.dtype))


def srgb8(img):
    import numpy as np

    v = np.clip(img, 0.0, 1.0)
    v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1.0 / 2.4) - 0.055)
    return (v * 255.0 + 0.5).astype(np.uint8)


def write_png(path, images, scale=2):
    """The images side by side, each pixel drawn scale x scale, sRGB."""
    import mitsuba as mi
    import numpy as np

    gap = np.ones((SIZE * scale, 4, 3), dtype=np.uint8) * 255
    parts = []
    for i, img in enumerate(images):
        if i:
            parts.append(gap)
        parts.append(np.repeat(np.repeat(srgb8(img), scale, axis=0), scale, axis=1))
    mi.Bitmap(np.ascontiguousarray(np.concatenate(parts, axis=1))).write(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--appel", default=os.path.join(ROOT, "target", "release", "appel"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scenes", default=",".join(n for n, _ in SCENES))
    ap.add_argument("--integrators", default=",".join(INTEGRATORS),
                    help="comma-separated: path, bdpt, sppm, ...")
    ap.add_argument("--seconds", type=float, help="one budget for every scene (default: the issue's)")
    ap.add_argument("--png", help="write the first scene's last path and bdpt images and the "
                    "reference side by side to this PNG")
    ap.add_argument("--keep", help="folder to keep the EXR images in")
    ap.add_argument("--max-depth", type=int, help="Appel's max_depth instead of the file's (8 "
                    "renders water-caustic as Tungsten did: its max_bounces 8, the file's 9)")
    args = ap.parse_args()
    import numpy as np

    wanted = args.scenes.split(",")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out_dir = args.keep or tmp
        os.makedirs(out_dir, exist_ok=True)
        for name, seconds in SCENES:
            if name not in wanted:
                continue
            seconds = args.seconds or seconds
            scene = scene_copy(name, tmp)
            ref = reference(name)
            finite = np.isfinite(ref).all(axis=2)
            ref = np.where(finite[..., None], ref, 0.0)
            parts = [("", finite)]
            if name == "water-caustic":
                water = through_water(args.appel, scene, tmp)
                parts += [(" (through the water)", finite & water),
                          (" (not through the water)", finite & ~water)]
            last = {}
            for integrator in args.integrators.split(","):
                runs = []
                for k in range(args.repeat):
                    image = os.path.join(out_dir, f"{name}-{integrator}-{k}.exr")
                    t, spp, cmd = render(args.appel, scene, integrator, seconds, args.threads,
                                         image, args.max_depth)
                    img = read_rgb(image)
                    runs.append([figures(img, ref, m) for _, m in parts] + [(t, spp)])
                    last[integrator] = img
                    ratio, rel, rmse = runs[-1][0]
                    print(f"  {name} {integrator} run {k}: mean/Tungsten {ratio:.3f} "
                          f"relMSE {rel:.4g} RMSE {rmse:.4g} {t:.1f} s, camera rays/pixel "
                          f"{spp:.0f}", flush=True)
                spp = statistics.median(r[-1][1] for r in runs)
                for p, (label, _) in enumerate(parts):
                    med = [statistics.median(r[p][i] for r in runs) for i in range(3)]
                    rows.append((name + label, seconds, integrator, *med, spp, cmd))
            if args.png and name == wanted[0]:
                write_png(args.png, [last["path"], last["bdpt"], ref])
    print(f"\n{SIZE}x{SIZE}, {args.threads} threads, median of {args.repeat}")
    print("| scene | time limit | integrator | mean / Tungsten | relative MSE | RMSE | "
          "camera rays / pixel |")
    print("|---|---|---|---|---|---|---|")
    for name, seconds, integrator, ratio, rel, rmse, spp, _ in rows:
        print(f"| {name} | {seconds:.0f} s | {integrator} | {ratio:.3f} | {rel:.4g} | "
              f"{rmse:.4g} | {spp:.0f} |")
    for name in dict.fromkeys(r[0] for r in rows):
        by = {r[2]: r for r in rows if r[0] == name}
        if "path" in by and "bdpt" in by:
            print(f"{name}: bdpt's relative MSE / path's = {by['bdpt'][4] / by['path'][4]:.3f}")
    print("\ncommands (the scene a copy with a box filter, see the docstring):")
    for r in rows:
        print("  " + r[-1])


if __name__ == "__main__":
    main()
