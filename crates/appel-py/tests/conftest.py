import os
import pathlib
import shutil
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "scripts"))
import shared_data  # noqa: E402


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
    """The path of a file in the shared data; the test is skipped, with the reason in pytest's
    summary, if it is absent."""
    p = shared_data.path(*parts)
    if p is None:
        pytest.skip(f"needs ../shared/data: {shared_data.data_dir().joinpath(*parts)} is absent")
    return p
