#!/usr/bin/env python3
"""Appel's path tracer against Mitsuba 3 on the same machine and thread count.

Two measurements per scene:
  * samples per second: Appel through `appel bench --scene FILE --spp N --json`, Mitsuba's
    scalar_rgb and llvm_ad_rgb through `mi.render` (llvm timed after one warm-up render, so the
    JIT's kernel cache is warm);
  * error at equal time: each renderer gets the samples per pixel that its measured rate fits in
    the same budget of seconds, and the image's RMSE and relative MSE against the reference are
    reported, with the time the render really took.

Every figure is the median of --repeat runs. Mitsuba runs in a child process per measurement,
since a variant and a thread count are set once per process. Not run in CI: it needs Mitsuba 3
(`pip install mitsuba`), the release binary and minutes of CPU.

    nice -n 5 cargo build --release
    python3 bench/mitsuba_compare.py [--threads 2,1] [--repeat 3] [--quick] [--sampler multijitter]

`--sampler` renders the Cornell box with another sampler than its file's `independent`, in both
renderers: Mitsuba's own (`multijitter`, `stratified`, `ldsampler`), which Appel reads as its
Owen-scrambled Sobol sampler. The sphere scene keeps its own (set in an included fragment).
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
APPEL = os.path.join(ROOT, "target", "release", "appel")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import shared_data  # noqa: E402

DATA = str(shared_data.data_dir())

CORNELL = os.path.join(DATA, "bitterli-scenes/cornell-box/mitsuba/scene_v3.xml")
CORNELL_REF = os.path.join(DATA, "bitterli-scenes/cornell-box/mitsuba/scene_v3.exr")
SPHERES_DIR = os.path.join(DATA, "mitsuba-data/tests/scenes/bsdf_spheres")
SPHERES = os.path.join(SPHERES_DIR, "test_roughplastic_linear_path.xml")
SPHERES_REF = os.path.join(SPHERES_DIR, "refs/test_roughplastic_linear_ref_rgb.exr")

# name, file, reference, (w, h) for samples per second, spp for it, (w, h) of the reference,
# seconds of the equal-time renders, whether the resolution is a load_file parameter.
SCENES = [
    ("cornell-box", CORNELL, CORNELL_REF, (256, 256), 32, (1024, 1024), 10.0, True),
    ("roughplastic spheres", SPHERES, SPHERES_REF, (48, 48), 512, (48, 48), 1.0, False),
]


# ---------------------------------------------------------------------------------------------
# Mitsuba, in a child process


def mitsuba_worker(job):
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(job["variant"])
    kwargs = {}
    if job["res_param"]:
        kwargs = {"resx": job["size"][0], "resy": job["size"][1]}
    scene = mi.load_file(job["scene"], **kwargs)
    # After loading: with one thread, loading the sphere scene's OBJ files deadlocks in scalar_rgb.
    dr.set_thread_count(job["threads"])
    integrator = None
    if job.get("max_depth") is not None:
        # The sphere scenes wrap the path tracer in a `moment` integrator (extra channels for the
        # regression tests); render with the plain one so both renderers do the same work.
        integrator = mi.load_dict({"type": "path", "max_depth": job["max_depth"]})
    size = scene.sensors()[0].film().crop_size()

    def once(spp, seed):
        start = time.perf_counter()
        img = mi.render(scene, spp=spp, seed=seed, integrator=integrator)
        arr = np.array(img)  # waits for the LLVM kernels
        return time.perf_counter() - start, arr

    if job["variant"].startswith("llvm"):
        once(job["spp"], 0)
    seconds, arr = once(job["spp"], job.get("seed", 1))
    # Stratified samplers round the count up (multijitter to a product of two integers).
    spp = int(scene.sensors()[0].sampler().sample_count())
    out = {"seconds": seconds, "width": int(size[0]), "height": int(size[1]), "spp": spp}
    if job.get("image"):
        np.save(job["image"], arr[..., :3].astype(np.float32))
    print(json.dumps(out))


def llvm_env():
    """Dr.Jit 1.5 emits intrinsics (fminimum) that LLVM 14 and 15 cannot select: point it at the
    newest libLLVM installed (Debian: `apt-get install libllvm19`) unless DRJIT_LIBLLVM_PATH says."""
    env = dict(os.environ)
    if "DRJIT_LIBLLVM_PATH" not in env:
        libs = []
        for d in ["/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib"]:
            if os.path.isdir(d):
                for f in os.listdir(d):
                    m = re.fullmatch(r"libLLVM-(\d+)\.so", f)
                    if m and int(m.group(1)) >= 16:
                        libs.append((int(m.group(1)), os.path.join(d, f)))
        if libs:
            env["DRJIT_LIBLLVM_PATH"] = max(libs)[1]
    return env


def mitsuba(variant, scene, size, spp, threads, res_param, max_depth, image=None, seed=1):
    job = dict(variant=variant, scene=scene, size=size, spp=spp, threads=threads,
               res_param=res_param, max_depth=max_depth, image=image, seed=seed)
    out = subprocess.run([sys.executable, __file__, "--mitsuba-worker", json.dumps(job)],
                         check=True, capture_output=True, text=True, env=llvm_env(), timeout=600).stdout
    # Mitsuba's log lines may leave a colour escape before the JSON on its line.
    last = out.strip().splitlines()[-1]
    return json.loads(last[last.index("{"):])


# ---------------------------------------------------------------------------------------------
# Appel, through the release binary


def size_args(size, res_param):
    # Mitsuba's sphere scenes fix their film at 48x48; Appel renders them at that size too.
    return ["--size", f"{size[0]}x{size[1]}"] if res_param else []


def appel_sps(scene, size, spp, threads, res_param, runs):
    cmd = [APPEL, "bench", "--scene", scene, "--spp", str(spp), "--threads", str(threads),
           "--frames", str(runs), "--json"] + size_args(size, res_param)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def appel_render(scene, size, spp, threads, res_param, image):
    # Appel's image is a pure function of the scene: repeats differ in time only.
    cmd = [APPEL, "render", scene, "-o", image, "--spp", str(spp), "--threads", str(threads)
           ] + size_args(size, res_param)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    m = re.search(r"render ([0-9.]+)s", out)
    return float(m.group(1))


# ---------------------------------------------------------------------------------------------
# Images and errors


def read_rgb(path):
    import mitsuba as mi
    import numpy as np

    if path.endswith(".npy"):
        return np.load(path)
    bmp = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
    return np.array(bmp)[..., :3]


def errors(img, ref):
    import numpy as np

    d = img.astype(np.float64) - ref.astype(np.float64)
    rmse = float(np.sqrt(np.mean(d * d)))
    # Relative MSE as in Rousselle et al.: bright pixels do not swamp the rest.
    rel = float(np.mean(d * d / (ref.astype(np.float64) ** 2 + 1e-2)))
    return rmse, rel


def med(xs):
    return statistics.median(xs)


# ---------------------------------------------------------------------------------------------


def with_sampler(scene, sampler, tmp):
    """A copy of `scene` in `tmp` whose sampler plugin is `sampler` (the Cornell box refers to no
    other file, so the copy renders the same scene)."""
    with open(scene) as f:
        text = f.read()
    text, n = re.subn(r'<sampler type="[a-z]+"', f'<sampler type="{sampler}"', text)
    if n != 1:
        sys.exit(f"{scene}: expected one <sampler> element, found {n}")
    out = os.path.join(tmp, f"{sampler}-{os.path.basename(scene)}")
    with open(out, "w") as f:
        f.write(text)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--threads", default="2,1", help="thread counts, comma-separated")
    ap.add_argument("--repeat", type=int, default=3, help="runs per figure (median reported)")
    ap.add_argument("--equal-time-threads", type=int, default=2,
                    help="thread count of the equal-time error comparison (0: skip it)")
    ap.add_argument("--quick", action="store_true", help="a tenth of the samples and budgets")
    ap.add_argument("--sampler", choices=["independent", "multijitter", "stratified", "ldsampler"],
                    help="the Cornell box's sampler in both renderers (default: the file's)")
    ap.add_argument("--mitsuba-worker", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.mitsuba_worker:
        mitsuba_worker(json.loads(args.mitsuba_worker))
        return
    if not os.path.exists(APPEL):
        sys.exit(f"{APPEL} is missing: run `cargo build --release` first")
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    threads = [int(t) for t in args.threads.split(",")]
    scale = 0.1 if args.quick else 1.0
    tmp = tempfile.mkdtemp(prefix="appel-mitsuba-")
    scenes = [(name, with_sampler(scene, args.sampler, tmp) if args.sampler and scene == CORNELL
               else scene, *rest) for name, scene, *rest in SCENES]
    rows = []
    sps = {}
    for name, scene, ref, size, spp, ref_size, budget, res_param in scenes:
        spp = max(1, int(spp * scale))
        max_depth = None if res_param else 2
        for t in threads:
            a = [appel_sps(scene, size, spp, t, res_param, 1) for _ in range(args.repeat)]
            a_sps = med([r["msamples_per_second"] for r in a])
            def rate(variant):
                r = mitsuba(variant, scene, size, spp, t, res_param, max_depth)
                return size[0] * size[1] * r["spp"] / r["seconds"] / 1e6

            s_sps = med([rate("scalar_rgb") for _ in range(args.repeat)])
            l_sps = med([rate("llvm_ad_rgb") for _ in range(args.repeat)])
            sps[(name, t)] = {"appel": a_sps, "scalar_rgb": s_sps, "llvm_ad_rgb": l_sps}
            rows.append((name, f"{size[0]}x{size[1]}", spp, t, a_sps, s_sps, l_sps,
                         a[0]["rays_per_sample"]))
    print("Samples per second (millions; median of %d runs)" % args.repeat)
    print(f"{'scene':<22} {'size':>9} {'spp':>5} {'thr':>3} {'Appel':>8} {'scalar_rgb':>10} "
          f"{'llvm_ad_rgb':>11} {'Appel/scalar':>12} {'rays/sample':>11}")
    for name, sz, spp, t, a, s, l, rps in rows:
        print(f"{name:<22} {sz:>9} {spp:>5} {t:>3} {a:>8.3f} {s:>10.3f} {l:>11.3f} {a / s:>12.2f} "
              f"{rps:>11.2f}")
    sys.stdout.flush()

    t = args.equal_time_threads
    if t == 0:
        return
    print()
    print(f"Error at equal time ({t} threads; median of {args.repeat} renders; Mitsuba with different seeds)")
    print(f"{'scene':<22} {'budget s':>8} {'renderer':>11} {'spp':>5} {'time s':>7} {'RMSE':>10} "
          f"{'relMSE':>10}")
    for name, scene, ref, size, spp, ref_size, budget, res_param in scenes:
        budget *= scale
        max_depth = None if res_param else 2
        rates = sps.get((name, t))
        if rates is None:
            continue
        reference = read_rgb(ref)
        px = ref_size[0] * ref_size[1]
        for who in ["appel", "llvm_ad_rgb"]:
            n = max(1, round(budget * rates[who] * 1e6 / px))
            used = n
            times, rmses, rels = [], [], []
            for k in range(args.repeat):
                if who == "appel":
                    image = os.path.join(tmp, f"appel-{k}.exr")
                    secs = appel_render(scene, ref_size, n, t, res_param, image)
                else:
                    image = os.path.join(tmp, f"mitsuba-{k}.npy")
                    r = mitsuba(who, scene, ref_size, n, t, res_param, max_depth, image, k + 1)
                    secs, used = r["seconds"], r["spp"]
                rmse, rel = errors(read_rgb(image), reference)
                times.append(secs)
                rmses.append(rmse)
                rels.append(rel)
            print(f"{name:<22} {budget:>8.1f} {who:>11} {used:>5} {med(times):>7.2f} "
                  f"{med(rmses):>10.5f} {med(rels):>10.5f}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
