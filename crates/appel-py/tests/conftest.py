import os
import pathlib
import shutil

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
SHARED = ROOT.parent / "shared" / "data"


@pytest.fixture(scope="session")
def cli():
    """The `appel` binary of this checkout (built by `cargo test --release --workspace`)."""
    exe = ROOT / "target" / "release" / "appel"
    if not exe.exists():
        found = shutil.which("appel")
        if not found:
            pytest.skip("no appel binary: run `cargo build --release` first")
        exe = pathlib.Path(found)
    return str(exe)


def shared(*parts):
    p = SHARED.joinpath(*parts)
    if not p.exists():
        pytest.skip(f"{p} is absent (../shared beside the repository)")
    return p
