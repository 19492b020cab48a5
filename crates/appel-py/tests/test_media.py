"""Participating media from Python: a Mitsuba scene with a grid medium read by ``appel.load`` and
media described in a dict, rendered by ``volpath`` and checked against the CLI's render of the
same file and against Beer-Lambert's law."""

import json
import pathlib
import subprocess

import numpy as np
import pytest

import appel

MEDIA = pathlib.Path(__file__).resolve().parents[3] / "crates/appel/tests/reference/media"


def test_a_grid_medium_from_xml_renders_as_the_cli_renders_it(tmp_path, cli):
    """The heterogeneous cloud (its grid a file beside the XML) loads with its medium and renders
    with volpath to the bytes `appel render` writes for the same file, size, samples and seed."""
    xml = MEDIA / "hg_cloud.xml"
    scene = appel.load(xml, width=24, height=18)
    img = scene.render(spp=8, integrator="volpath")
    assert img.rgb.shape == (18, 24, 3) and np.isfinite(img.rgb).all() and img.rgb.mean() > 0
    ours, theirs = tmp_path / "py.exr", tmp_path / "cli.exr"
    img.save(ours)
    subprocess.run([cli, "render", str(xml), "--size", "24x18", "--spp", "8", "--integrator",
                    "volpath", "-q", "-o", str(theirs)], check=True, capture_output=True)
    assert ours.read_bytes() == theirs.read_bytes()


def slab(medium):
    """An orthographic view down -z through the slab 0 < z < 1 of `medium`, bounded by a null
    cube, onto an emitter of radiance 1 at z = -1: every camera ray crosses the slab at right
    angles."""
    return {
        "camera": {"type": "orthographic", "eye": [0, 0, 3], "look_at": [0, 0, 0],
                   "half_width": 0.5, "width": 8, "height": 8},
        "render": {"integrator": "volpath", "max_depth": -1, "spp": 256},
        "materials": {"boundary": {"type": "null"}},
        "media": {"ink": medium},
        "shape": [
            {"type": "cube", "material": "boundary", "interior": "ink",
             "transform": {"scale": [2.0, 2.0, 0.5], "translate": [0.0, 0.0, 0.5]}},
            {"type": "rectangle", "transform": {"scale": 4.0, "translate": [0.0, 0.0, -1.0]},
             "emitter": {"radiance": 1.0}},
        ],
    }


# The grid's cells hold the same absorption, so the slab is homogeneous in effect, but it is
# tracked with null collisions (one majorant, 2, for three different extinctions).
GRID = {"type": "values", "resolution": [2, 2, 1], "channels": 3,
        "values": [0.5, 1.0, 2.0] * 4,
        "transform": {"scale": [4.0, 4.0, 1.0], "translate": [-2.0, -2.0, 0.0]}}


@pytest.mark.parametrize("medium", [
    {"type": "homogeneous", "sigma_t": [0.5, 1.0, 2.0], "albedo": 0.0},
    {"type": "heterogeneous", "sigma_a": GRID, "sigma_s": 0.0},
], ids=["homogeneous", "absorption grid"])
def test_a_dict_medium_follows_beer_lambert(tmp_path, medium):
    """Through an absorbing slab of thickness 1 the emitter's light is exp(-sigma_a) per
    channel: the image mean within 4 standard errors (from the variance AOV). The dict written
    as a JSON file and loaded renders the same image."""
    d = slab(medium)
    img = appel.load_dict(d).render(spp=256, aovs=("variance",))
    n = img.rgb.shape[0] * img.rgb.shape[1]
    mean = img.rgb.reshape(-1, 3).astype(np.float64).mean(axis=0)
    error = np.sqrt(img.aovs["variance"].reshape(-1, 3).astype(np.float64).sum(axis=0)) / n
    expected = np.exp(-np.array([0.5, 1.0, 2.0]))
    assert (np.abs(mean - expected) <= 4 * error + 1e-4).all(), (mean, error, expected)
    f = tmp_path / "slab.json"
    f.write_text(json.dumps(d))
    assert np.array_equal(appel.load(f).render(spp=256).rgb, img.rgb)
