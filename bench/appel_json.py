"""What the benchmark scripts share: the arguments after `--`, and runs of `appel bench --json`."""

import json
import subprocess
import sys
from pathlib import Path

# The release build of this checkout.
DEFAULT_APPEL = str(Path(__file__).resolve().parent.parent / "target" / "release" / "appel")


def split_extra(argv):
    """`argv` up to `--`, and what follows it (passed to every `appel bench` call)."""
    if "--" in argv:
        i = argv.index("--")
        return argv[:i], argv[i + 1 :]
    return argv, []


def bench_rows(appel, target, accel, extra):
    """The JSON rows of `appel bench TARGET --accel ACCEL --embree --json EXTRA...`, one per
    structure and one for Embree; exits with appel's message if it fails."""
    cmd = [appel, "bench", target, "--accel", accel, "--embree", "--json"] + extra
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{out.stderr}")
    return [json.loads(line) for line in out.stdout.splitlines() if line.strip()]
