"""Loading, meshes, rendering and images: dtypes, shapes, errors, and agreement with the CLI."""

import subprocess

import numpy as np
import pytest

import appel

TETRA_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
TETRA_I = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def test_builtin_overrides_and_sizes():
    s = appel.builtin("whitted", width=40, height=30, spp=2)
    assert s.size == (40, 30)
    assert s.camera["width"] == 40
    assert "whitted" in appel.builtin_names()
    with pytest.raises(ValueError, match="not a built-in scene"):
        appel.builtin("nope")
    with pytest.raises(ValueError, match="unknown override `colour`"):
        appel.builtin("whitted", colour=1)
    with pytest.raises(ValueError, match="width"):
        appel.builtin("whitted", width=-3)


def test_load_errors_name_the_file(tmp_path):
    with pytest.raises(FileNotFoundError):
        appel.load(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text('[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[[shape]]\ntype = "sphere"\n'
                   'center = [0, 0, 0]\nradius = -1\n')
    with pytest.raises(ValueError, match=r"bad\.toml:\d+:\d+: shape\[0\]\.radius"):
        appel.load(bad)


def test_load_dict_matches_the_file(tmp_path):
    d = {
        "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "width": 24, "height": 16},
        "shape": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.0}],
    }
    a = appel.load_dict(d).render(aovs=("depth",))
    f = tmp_path / "s.json"
    import json

    f.write_text(json.dumps(d))
    b = appel.load(f).render(aovs=("depth",))
    assert np.array_equal(a.rgb, b.rgb) and np.array_equal(a.aovs["depth"], b.aovs["depth"])
    with pytest.raises(ValueError, match="<dict>"):
        appel.load_dict({"camera": {"eye": [0, 0, 5]}})


def test_render_arrays_have_the_promised_dtypes_and_misses():
    img = appel.builtin("whitted", width=32, height=24).render(
        aovs=("depth", "normal", "primid", "instanceid"))
    assert img.rgb.dtype == np.float32 and img.rgb.shape == (24, 32, 3)
    a = img.aovs
    assert set(a) == {"depth", "normal", "primid", "shapeid", "instanceid"}
    assert a["depth"].dtype == np.float32 and a["depth"].shape == (24, 32)
    assert a["normal"].dtype == np.float32 and a["normal"].shape == (24, 32, 3)
    for k in ("primid", "shapeid", "instanceid"):
        assert a[k].dtype == np.uint32 and a[k].shape == (24, 32)
    miss = np.isinf(a["depth"])
    assert miss.any() and (~miss).any()
    assert (a["primid"][miss] == 4294967295).all() and (a["shapeid"][miss] == appel.MISS).all()
    assert (a["instanceid"] == 4294967295).all()  # nothing instanced
    with pytest.raises(ValueError, match="unknown AOV 'albedo'"):
        appel.builtin("whitted", width=8, height=8).render(aovs=("albedo",))
    with pytest.raises(ValueError, match="unknown integrator `magic`"):
        appel.builtin("whitted", width=8, height=8).render(integrator="magic")


def test_png_and_exr_are_the_cli_bytes(tmp_path, cli):
    """Image.save writes exactly what `appel render` writes for the same scene and settings."""
    img = appel.builtin("whitted", width=48, height=32).render(
        spp=2, aovs=("depth", "normal", "primid"))
    for ext, aov in (("png", []), ("exr", ["--aov", "depth,normal,primid"])):
        ours, theirs = tmp_path / f"py.{ext}", tmp_path / f"cli.{ext}"
        img.save(ours)
        subprocess.run([cli, "render", "whitted", "--size", "48x32", "--spp", "2", "-q",
                        "-o", str(theirs)] + aov, check=True, capture_output=True)
        assert ours.read_bytes() == theirs.read_bytes(), ext
    png = img._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert png == (tmp_path / "py.png").read_bytes()


def test_path_tracing_with_variance_is_thread_independent():
    s = appel.builtin("whitted", width=20, height=16)
    a = s.render(spp=4, integrator="path", aovs=("variance",), threads=1)
    b = s.render(spp=4, integrator="path", aovs=("variance",), threads=2)
    assert np.array_equal(a.rgb, b.rgb) and a.aovs["variance"].shape == (16, 20, 3)
    # The scene's own settings come back after a render that changed them.
    c = s.render()
    assert np.array_equal(c.rgb, appel.builtin("whitted", width=20, height=16).render().rgb)


def test_windows_are_the_full_render_bit_for_bit():
    s = appel.builtin("whitted", width=50, height=37)
    for kw in ({}, {"spp": 3}, {"spp": 2, "integrator": "path"}):
        full = s.render(aovs=("depth", "primid"), **kw)
        part = s.render(aovs=("depth", "primid"), window=(7, 3, 41, 30), **kw)
        assert np.array_equal(part.rgb, full.rgb[3:30, 7:41]), kw
        assert np.array_equal(part.aovs["primid"], full.aovs["primid"][3:30, 7:41])
    with pytest.raises(ValueError, match="window"):
        s.render(window=(0, 0, 60, 10))


def test_progress_callback_reaches_every_pixel():
    seen = []
    appel.builtin("whitted", width=64, height=64).render(spp=8, progress=seen.append)
    assert seen == [] or seen[-1] <= 64 * 64


def test_mesh_checks_name_the_argument():
    for dtype in (np.float32, np.float64):
        appel.Mesh(TETRA_V.astype(dtype), TETRA_I)
    for dtype in (np.int8, np.uint8, np.int16, np.uint16, np.int32, np.uint32, np.int64,
                  np.uint64):
        m = appel.Mesh(TETRA_V, TETRA_I.astype(dtype))
        assert m.indices.dtype == np.uint32
    cases = [
        ((TETRA_V[:, :2], TETRA_I), "vertices: expected shape"),
        ((TETRA_V.astype(np.int32), TETRA_I), "vertices: expected float32 or float64"),
        ((np.where(TETRA_V == 1, np.nan, TETRA_V), TETRA_I), "vertices: row 1 is not finite"),
        ((TETRA_V, TETRA_I[:, :2]), "indices: expected shape"),
        ((TETRA_V, TETRA_I.astype(np.float32)), "indices: expected an integer dtype"),
        ((TETRA_V, TETRA_I + 1), "indices: row 1 has index 4, out of range for 4 vertices"),
        ((TETRA_V, TETRA_I - 1), "indices: row 0 has index -1"),
    ]
    for args, message in cases:
        with pytest.raises(ValueError, match=message):
            appel.Mesh(*args)
    with pytest.raises(ValueError, match="normals: expected 4 rows"):
        appel.Mesh(TETRA_V, TETRA_I, normals=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="uvs: expected shape"):
        appel.Mesh(TETRA_V, TETRA_I, uvs=np.zeros((4, 3)))


def test_from_meshes_places_instances():
    m = appel.Mesh(TETRA_V, TETRA_I)
    t = np.eye(4)
    t[:3, 3] = [5, 0, 0]
    s = appel.Scene.from_meshes([m, m], transforms=[None, t],
                                camera={"width": 16, "height": 16})
    h = s.intersect(np.array([[0.1, 0.1, 5.0], [5.1, 0.1, 5.0]]), np.array([[0, 0, -1.0]] * 2))
    assert list(h["instance_ids"]) == [0, 1] and list(h["shape_ids"]) == [0, 1]
    assert np.allclose(h["t_hit"], [4.2, 4.2], atol=1e-5)
    with pytest.raises(ValueError, match="transforms: 1 transforms for 2 meshes"):
        appel.Scene.from_meshes([m, m], transforms=[t])
    with pytest.raises(ValueError, match="accel: unknown structure"):
        appel.Scene.from_meshes([m], accel="octopus")


XML_SCENE = """<scene version="3.0.0">
    <default name="res" value="16"/>
    <default name="spp" value="2"/>
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/></film>
    </sensor>
    <shape type="sphere"><bsdf type="diffuse"/></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
</scene>
"""


def test_load_passes_mitsuba_parameters(tmp_path):
    xml = tmp_path / "scene.xml"
    xml.write_text(XML_SCENE)
    assert appel.load(xml).size == (16, 16)
    # A keyword that is not a camera or render key is a parameter of the XML file.
    s = appel.load(xml, res=24)
    assert s.size == (24, 24)
    # `spp` is a render key, so as a keyword it overrides `[render] spp`; `params` passes it to
    # the file as the parameter `$spp` whatever its name.
    with pytest.raises(ValueError, match="override `spp`"):
        appel.load(xml, spp="many")
    with pytest.raises(ValueError, match=r"scene\.xml:\d+"):
        appel.load(xml, params={"spp": "many"})
    assert appel.load(xml, spp=3, params={"spp": 5, "res": 10}).size == (10, 10)
    # Overrides win over parameters.
    assert appel.load(xml, res=24, width=8).size == (8, 24)
    # A parameter the file cannot use is an error at its place in the file.
    with pytest.raises(ValueError, match=r"scene\.xml:\d+"):
        appel.load(xml, res="wide")
    with pytest.raises(ValueError, match="params: expected a dict"):
        appel.load(xml, params=["res", "8"])


def test_load_rejects_parameters_where_the_format_takes_none(tmp_path):
    toml = tmp_path / "s.toml"
    toml.write_text('[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 8\nheight = 8\n\n'
                    '[[shape]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = 1\n')
    with pytest.raises(ValueError, match="unknown override `res`"):
        appel.load(toml, res=8)
    with pytest.raises(ValueError, match=r"parameters \(res\) are read by a scene file of mitsuba"):
        appel.load(toml, params={"res": 8})


def test_load_reads_a_mesh_inside_an_archive(tmp_path):
    import zipfile
    archive = tmp_path / "assets.zip"
    with zipfile.ZipFile(archive, "w") as z:
        z.writestr("tetra/inner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                   "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
        z.writestr("other.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    s = appel.load(f"{archive}:tetra/inner.obj", width=16, height=12)
    assert s.size == (16, 12)
    lo, hi = s.bounds
    np.testing.assert_array_equal(lo, [0, 0, 0])
    np.testing.assert_array_equal(hi, [1, 1, 1])
    with pytest.raises(ValueError, match="missing.obj"):
        appel.load(f"{archive}:missing.obj")
    with pytest.raises(FileNotFoundError, match="no such mesh file"):
        appel.load(f"{tmp_path / 'none.zip'}:inner.obj")


@pytest.mark.parametrize("accel, table", [
    ("octree", {"max_prims": 2, "max_depth": 4}),
    ("bsp", None),
    ("grid", None),
])
def test_every_structure_table_is_an_override(accel, table):
    if table is None:
        table = {}
    s = appel.builtin("whitted", width=16, height=12, accel=accel, **{accel: table})
    assert s.size == (16, 12)
    with pytest.raises(ValueError, match=f"override `{accel}`"):
        appel.builtin("whitted", **{accel: {"no_such_option": 1}})
