"""Where the Python tests and the bench scripts find the shared test data: the folder named by
the APPEL_DATA environment variable, otherwise `shared/data` beside the checkout
(`../shared/data` from the repository's root). The Rust tests use the same rule (the
`appel-testdata` crate)."""

import os
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]


def data_dir():
    """The shared data folder (it may not exist)."""
    named = os.environ.get("APPEL_DATA")
    return pathlib.Path(named) if named else ROOT.parent / "shared" / "data"


def path(*parts):
    """The path of a file in the shared data, or None if it is absent."""
    p = data_dir().joinpath(*parts)
    return p if p.exists() else None
