//! Assets as their authors meant them: glTF and MTL textures reach the rendered image, cut-outs
//! let light through, meshes load from zip archives, and malformed files give errors that name
//! them.

use appel::accel::TraversalStats;
use appel::io::load_mesh;
use appel::render::{render, Film, RenderOptions};
use appel::scene::{IntegratorKind, Scene};
use appel::scene_build::{model_description, view_model};
use glam::{Vec2, Vec3};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `appel render FILE` at `w` x `h` with `spp` samples: the automatic view of a mesh file.
fn render_model(path: &Path, w: u32, h: u32, spp: u32) -> (Scene, Film) {
    render_model_with(path, w, h, spp, |_| {})
}

/// [`render_model`] with the description changed by `edit` first.
fn render_model_with(
    path: &Path,
    w: u32,
    h: u32,
    spp: u32,
    edit: impl Fn(&mut appel::description::Description),
) -> (Scene, Film) {
    let file = path.file_name().unwrap().to_str().unwrap();
    let mut base = model_description(file);
    (base.camera.width, base.camera.height) = (w, h);
    edit(&mut base);
    let mut scene = Scene::new(&base, path.parent().unwrap()).unwrap_or_else(|e| panic!("{e}"));
    let view = view_model(&scene, &base, None).unwrap();
    scene.set_view(&view).unwrap();
    scene.settings.integrator = view.render.integrator;
    scene.settings.max_depth = view.render.max_depth;
    scene.settings.spp = spp;
    let film = render(&scene, &RenderOptions::default()).unwrap().0;
    (scene, film)
}

/// The uv seen through each pixel's centre (ignoring cut-outs), or `None` on a miss.
fn pixel_uvs(scene: &Scene) -> Vec<Option<Vec2>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut stats = TraversalStats::default();
    let mut out = vec![];
    for j in 0..h {
        for i in 0..w {
            let ray = scene.camera.pixel_ray(i, j);
            out.push(
                scene
                    .intersect(&ray, f32::INFINITY, &mut stats)
                    .map(|hit| scene.geometry.interaction_with(&ray, &hit, true).uv),
            );
        }
    }
    out
}

fn chromaticity(c: Vec3) -> Option<Vec2> {
    let s = c.x + c.y + c.z;
    (s > 1e-3).then(|| Vec2::new(c.x / s, c.y / s))
}

fn correlation(a: &[f32], b: &[f32]) -> f32 {
    let n = a.len() as f32;
    let (ma, mb) = (a.iter().sum::<f32>() / n, b.iter().sum::<f32>() / n);
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += (x - ma) * (y - mb);
        aa += (x - ma) * (x - ma);
        bb += (y - mb) * (y - mb);
    }
    ab / (aa * bb).sqrt()
}

fn srgb_to_linear(v: u8) -> f32 {
    appel::io::bitmap_read::srgb_to_linear(v as f32 / 255.0)
}

/// DamagedHelmet, framed as `appel render` frames it: the colour of each pixel must follow the
/// base colour texture at the uv that pixel sees, read here from the GLB independently of the
/// renderer. The chromaticities (colour without brightness) of the render and of the texture are
/// correlated over the pixels that see the helmet; a flat material (one colour, "white clay")
/// leaves the render's chromaticity constant, uncorrelated with the texture's.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn damaged_helmet_colours_follow_its_base_colour_texture() {
    let path = appel_testdata::path("gltf-models/DamagedHelmet/glTF-Binary/DamagedHelmet.glb");
    let (scene, film) = render_model(&path, 96, 72, 8);
    assert_eq!(scene.settings.integrator, IntegratorKind::Path);
    let glb = gltf::Gltf::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let material = glb.document.materials().next().unwrap();
    let info = material
        .pbr_metallic_roughness()
        .base_color_texture()
        .unwrap();
    let gltf::image::Source::View { view, .. } = info.texture().source().source() else {
        panic!("the helmet's base colour is embedded");
    };
    let blob = glb.blob.as_ref().unwrap();
    let bytes = &blob[view.offset()..view.offset() + view.length()];
    let texture = image::load_from_memory(bytes).unwrap().to_rgb8();
    let (tw, th) = texture.dimensions();
    let texel = |uv: Vec2| {
        let x = ((uv.x.rem_euclid(1.0) * tw as f32) as u32).min(tw - 1);
        let y = ((uv.y.rem_euclid(1.0) * th as f32) as u32).min(th - 1);
        let p = texture.get_pixel(x, y);
        Vec3::new(
            srgb_to_linear(p[0]),
            srgb_to_linear(p[1]),
            srgb_to_linear(p[2]),
        )
    };
    let correlations = |scene: &Scene, film: &Film| {
        let (mut rendered, mut expected) = ([vec![], vec![]], [vec![], vec![]]);
        for (k, uv) in pixel_uvs(scene).into_iter().enumerate() {
            let Some(uv) = uv else { continue };
            let (Some(r), Some(t)) = (chromaticity(film.rgb[k]), chromaticity(texel(uv))) else {
                continue;
            };
            for c in 0..2 {
                rendered[c].push(r[c]);
                expected[c].push(t[c]);
            }
        }
        assert!(
            rendered[0].len() > 1000,
            "{} pixels see the helmet",
            rendered[0].len()
        );
        [0, 1].map(|c| correlation(&rendered[c], &expected[c]))
    };
    let textured = correlations(&scene, &film);
    // The control: the same view with one flat material over the whole helmet.
    let (clay, clay_film) = render_model_with(&path, 96, 72, 8, |d| {
        d.materials.insert(
            "clay".into(),
            toml::from_str("type = \"diffuse\"\nreflectance = 0.8").unwrap(),
        );
        if let appel::description::ShapeDesc::Mesh(m) = &mut d.shapes[0] {
            m.material = Some("clay".into());
        }
    });
    let flat = correlations(&clay, &clay_film);
    eprintln!("chromaticity correlations (red, green): textured {textured:?}, flat {flat:?}");
    for c in 0..2 {
        assert!(textured[c] > 0.4, "textured: {textured:?}");
        // Flat clay's chromaticity varies only where the pixel filter blends in the background
        // at the silhouette, which has nothing to do with the texture.
        assert!(flat[c].is_nan() || flat[c] < 0.2, "flat: {flat:?}");
    }
}

/// The GLB with its JSON chunk changed by `edit` (the binary chunk kept as it is).
fn rewrite_glb(bytes: &[u8], edit: impl FnOnce(&mut serde_json::Value)) -> Vec<u8> {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    edit(&mut json);
    let mut chunk = serde_json::to_vec(&json).unwrap();
    while !chunk.len().is_multiple_of(4) {
        chunk.push(b' ');
    }
    let rest = &bytes[20 + json_len..];
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((20 + chunk.len() + rest.len()) as u32).to_le_bytes());
    out.extend((chunk.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(chunk);
    out.extend(rest);
    out
}

/// [`render_model`] with a directional light beside the framing's sky: under a uniform sky alone,
/// diffuse shading hardly depends on the normal (a cosine-sampled bounce carries the albedo
/// whichever way the normal points), so a normal map would show only in the speculars.
fn render_model_lit(path: &Path, w: u32, h: u32, spp: u32) -> Film {
    let file = path.file_name().unwrap().to_str().unwrap();
    let mut base = model_description(file);
    (base.camera.width, base.camera.height) = (w, h);
    let mut scene = Scene::new(&base, path.parent().unwrap()).unwrap_or_else(|e| panic!("{e}"));
    let mut view = view_model(&scene, &base, None).unwrap();
    view.lights.push(appel::description::LightDesc::Directional(
        appel::description::DirectionalDesc {
            direction: [0.4, -0.6, -0.7],
            color: [1.0; 3],
            intensity: 3.0,
        },
    ));
    scene.set_view(&view).unwrap();
    scene.settings.integrator = view.render.integrator;
    scene.settings.max_depth = view.render.max_depth;
    scene.settings.spp = spp;
    render(&scene, &RenderOptions::default()).unwrap().0
}

/// DamagedHelmet's normal map reaches the image: lit from one side and rendered without its
/// `normalTexture`, the helmet looks clearly different; with a flat normal map (0.5, 0.5, 1 everywhere, stored as
/// floats so that it is exactly the unperturbed normal) instead, it looks the same as without
/// one, to float noise.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn damaged_helmet_normal_map_tilts_and_a_flat_one_does_not() {
    let path = appel_testdata::path("gltf-models/DamagedHelmet/glTF-Binary/DamagedHelmet.glb");
    let bytes = std::fs::read(&path).unwrap();
    let dir = tempfile::tempdir().unwrap();
    exr::prelude::write_rgb_file(dir.path().join("flat.exr"), 4, 4, |_, _| {
        (0.5f32, 0.5f32, 1.0f32)
    })
    .unwrap();
    // Every normal tilted by 53 degrees toward the tangent.
    exr::prelude::write_rgb_file(dir.path().join("tilted.exr"), 4, 4, |_, _| {
        (0.9f32, 0.5f32, 0.8f32)
    })
    .unwrap();
    let write = |name: &str, edit: &dyn Fn(&mut serde_json::Value)| {
        let p = dir.path().join(name);
        std::fs::write(&p, rewrite_glb(&bytes, edit)).unwrap();
        p
    };
    let none = write("none.glb", &|j| {
        for m in j["materials"].as_array_mut().unwrap() {
            m.as_object_mut().unwrap().remove("normalTexture");
        }
    });
    let with_map = |name: &str, image: &str| {
        let image = image.to_string();
        write(name, &move |j: &mut serde_json::Value| {
            let images = j["images"].as_array_mut().unwrap();
            images.push(serde_json::json!({ "uri": image }));
            let image = images.len() - 1;
            let textures = j["textures"].as_array_mut().unwrap();
            textures.push(serde_json::json!({ "source": image }));
            let texture = textures.len() - 1;
            for m in j["materials"].as_array_mut().unwrap() {
                m["normalTexture"] = serde_json::json!({ "index": texture });
            }
        })
    };
    let flat = with_map("flat.glb", "flat.exr");
    let tilted_glb = with_map("tilted.glb", "tilted.exr");
    let (w, h, spp) = (96, 72, 16);
    let mapped = render_model_lit(&path, w, h, spp);
    let without = render_model_lit(&none, w, h, spp);
    let flat = render_model_lit(&flat, w, h, spp);
    let tilted_film = render_model_lit(&tilted_glb, w, h, spp);
    let mean = |f: &Film| f.rgb.iter().map(|c| c.x + c.y + c.z).sum::<f32>() / f.rgb.len() as f32;
    // As displayed: clamped to [0, 1], so that a few fireflies do not decide.
    let mean_abs_diff = |a: &Film, b: &Film| {
        a.rgb
            .iter()
            .zip(&b.rgb)
            .map(|(x, y)| (x.min(Vec3::ONE) - y.min(Vec3::ONE)).abs().element_sum())
            .sum::<f32>()
            / a.rgb.len() as f32
    };
    if let Ok(dir) = std::env::var("APPEL_REFERENCE_PNG") {
        for (name, f) in [("mapped", &mapped), ("without", &without)] {
            let img = image::RgbImage::from_fn(w, h, |x, y| {
                let c = f.rgb[(y * w + x) as usize];
                image::Rgb(
                    c.to_array()
                        .map(|v| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8),
                )
            });
            img.save(Path::new(&dir).join(format!("helmet_{name}.png")))
                .unwrap();
        }
    }
    let scale = mean(&without);
    // The sampler draws the same numbers for each render, so a small tilt moves a pixel's
    // paths, and its value, only a little: the helmet's map, mostly flat but for its panel
    // lines, rivets and scratches, shows as many pixels changed by a few percent.
    let changed = |a: &Film, b: &Film| {
        a.rgb
            .iter()
            .zip(&b.rgb)
            .filter(|(x, y)| {
                let (x, y) = (x.min(Vec3::ONE), y.min(Vec3::ONE));
                (x - y).abs().max_element() > 0.02 * x.max(y).max_element().max(0.05)
            })
            .count() as f32
            / a.rgb.len() as f32
    };
    let mapped_diff = mean_abs_diff(&mapped, &without) / scale;
    let mapped_changed = changed(&mapped, &without);
    let tilted_diff = mean_abs_diff(&tilted_film, &without) / scale;
    let flat_diff = mean_abs_diff(&flat, &without) / scale;
    let identical = flat.rgb == without.rgb;
    eprintln!(
        "relative mean |difference| from no normal map: helmet's map {mapped_diff} ({mapped_changed} of the pixels changed by over 2%), tilted {tilted_diff}, flat {flat_diff} (identical: {identical})"
    );
    assert!(tilted_diff > 0.02, "{tilted_diff}");
    assert!(mapped_changed > 0.01, "{mapped_changed}");
    assert!(flat_diff < 1e-4, "{flat_diff}");
}

/// FlightHelmet's textures are not in the shared data: the model renders with its factors and a
/// warning names a missing texture.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn flight_helmet_without_its_textures_renders_with_a_warning() {
    let path = appel_testdata::path("gltf-models/FlightHelmet/glTF/FlightHelmet.gltf");
    let (scene, film) = render_model(&path, 24, 32, 1);
    let w = scene.from_files.warnings.join("\n");
    assert!(
        w.contains("FlightHelmet_Materials_") && w.contains("does not exist"),
        "{w}"
    );
    assert!(film.rgb.iter().all(|c| c.is_finite()));
}

/// A 4x1 PNG: opaque red on the left half, fully transparent green on the right.
fn red_and_hole_png() -> Vec<u8> {
    let px = [[255u8, 0, 0, 255]; 2]
        .into_iter()
        .chain([[0, 255, 0, 0]; 2])
        .flatten()
        .collect();
    let img = image::RgbaImage::from_raw(4, 1, px).unwrap();
    let mut out = std::io::Cursor::new(vec![]);
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// A unit quad in the z = 0 plane with uv (0..1, 0..1), with material `m` from `quad.mtl`.
const QUAD_OBJ: &str = "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";

const QUAD_MTL: &str =
    "newmtl m\nKd 1 1 1\nmap_Kd -clamp on tex/rh.png\nmap_d -clamp on tex/rh.png\n";

/// MTL `map_Kd` colours the surface and `map_d` cuts it out: where the map is opaque the quad is
/// red, where it is transparent the render sees the sky behind it (the quad is lit by the preview
/// sky of radiance 0.5 and the framing's lights; the sky seen directly is exactly 0.5).
#[test]
fn mtl_texture_maps_colour_and_cut_out() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    std::fs::write(dir.path().join("tex/rh.png"), red_and_hole_png()).unwrap();
    std::fs::write(dir.path().join("quad.obj"), QUAD_OBJ).unwrap();
    std::fs::write(dir.path().join("quad.mtl"), QUAD_MTL).unwrap();
    let (scene, film) = render_model(&dir.path().join("quad.obj"), 40, 30, 16);
    assert!(
        scene.from_files.warnings.is_empty(),
        "{:?}",
        scene.from_files.warnings
    );
    let (mut red, mut hole) = (0, 0);
    for (k, uv) in pixel_uvs(&scene).into_iter().enumerate() {
        let Some(uv) = uv else { continue };
        let c = film.rgb[k];
        // Away from the quad's edges (the pixel filter reaches past them) and from the texels'
        // boundary (bilinear lookups blend the middle texels between u = 0.375 and 0.625).
        if !(0.15..0.85).contains(&uv.y) {
            continue;
        }
        if (0.15..0.3).contains(&uv.x) {
            assert!(c.x > 4.0 * c.y.max(c.z) && c.x > 0.05, "uv {uv}: {c}");
            red += 1;
        } else if (0.7..0.85).contains(&uv.x) {
            assert!(
                (c - Vec3::splat(0.5)).abs().max_element() < 1e-3,
                "uv {uv}: {c}"
            );
            hole += 1;
        }
    }
    assert!(
        red > 20 && hole > 20,
        "{red} red and {hole} see-through pixels"
    );
}

fn write_zip(path: &Path, files: &[(&str, &[u8])]) {
    let mut zip = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    for (name, bytes) in files {
        zip.start_file(*name, zip::write::SimpleFileOptions::default())
            .unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap();
}

/// A zip with one mesh file is opened by the archive's name, and the files its MTL refers to come
/// from inside the archive; with two, the entry must be named, and the error lists them.
#[test]
fn zip_archives_pick_their_mesh_file() {
    let dir = tempfile::tempdir().unwrap();
    let png = red_and_hole_png();
    let one = dir.path().join("one.zip");
    write_zip(
        &one,
        &[
            ("model/quad.obj", QUAD_OBJ.as_bytes()),
            ("model/quad.mtl", QUAD_MTL.as_bytes()),
            ("model/tex/rh.png", &png),
        ],
    );
    let m = load_mesh(&one).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.triangle_count(), 2);
    assert_eq!(m.materials[0].name, "m");
    assert!(m.materials[0].diffuse_map.is_some());
    assert_eq!(m.images.len(), 1);
    assert_eq!(m.images[0].bytes.as_deref().unwrap(), &png);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    // The same entry named explicitly.
    let explicit = PathBuf::from(format!("{}:model/quad.obj", one.display()));
    assert_eq!(load_mesh(&explicit).unwrap().triangle_count(), 2);

    let two = dir.path().join("two.zip");
    write_zip(
        &two,
        &[
            ("a.obj", QUAD_OBJ.as_bytes()),
            ("b/c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".as_bytes()),
            ("readme.txt", b"two meshes"),
        ],
    );
    let e = load_mesh(&two).unwrap_err().to_string();
    assert!(
        e.contains("two.zip") && e.contains("`a.obj`") && e.contains("`b/c.obj`"),
        "{e}"
    );
    let c = PathBuf::from(format!("{}:b/c.obj", two.display()));
    assert_eq!(load_mesh(&c).unwrap().triangle_count(), 1);
    // The OBJ without its MTL in the archive loads, with the default material.
    let a = load_mesh(&PathBuf::from(format!("{}:a.obj", two.display()))).unwrap();
    assert!(a.materials.is_empty());
    let missing = PathBuf::from(format!("{}:b/none.obj", two.display()));
    let e = load_mesh(&missing).unwrap_err().to_string();
    assert!(
        e.contains("two.zip") && e.contains("b/none.obj") && e.contains("`a.obj`"),
        "{e}"
    );
    let none = dir.path().join("none.zip");
    write_zip(&none, &[("readme.txt", b"no mesh")]);
    let e = load_mesh(&none).unwrap_err().to_string();
    assert!(e.contains("none.zip") && e.contains("no mesh file"), "{e}");
}

/// Damaged archives are errors that name them, never panics: garbage, a truncated archive, and
/// an archive whose entry is not a mesh.
#[test]
fn malformed_zip_archives_are_errors_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let garbage = dir.path().join("garbage.zip");
    std::fs::write(&garbage, b"PK\x03\x04 this is not really a zip archive").unwrap();
    let e = load_mesh(&garbage).unwrap_err().to_string();
    assert!(e.contains("garbage.zip") && e.contains("zip"), "{e}");

    let good = dir.path().join("good.zip");
    write_zip(
        &good,
        &[("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".as_bytes())],
    );
    let bytes = std::fs::read(&good).unwrap();
    for cut in [10, bytes.len() / 2, bytes.len() - 5] {
        let truncated = dir.path().join("cut.zip");
        std::fs::write(&truncated, &bytes[..cut]).unwrap();
        let e = load_mesh(&truncated).unwrap_err().to_string();
        assert!(e.contains("cut.zip"), "cut at {cut}: {e}");
    }
    let e = load_mesh(&PathBuf::from(format!("{}:m.txt", good.display())))
        .unwrap_err()
        .to_string();
    assert!(e.contains("good.zip") && e.contains("m.txt"), "{e}");
    let e = load_mesh(&dir.path().join("absent.zip"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("absent.zip"), "{e}");
}

/// The shared Sponza archive (the Dabrovic atrium: an OBJ without MTL or textures) opens by the
/// archive's name.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn sponza_zip_loads() {
    let path = appel_testdata::path("sponza/sponza.zip");
    let m = load_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.triangle_count(), 66_454);
}

/// A one-triangle glTF with a material and a texture whose parts can be broken.
fn gltf_with(material: &str, textures: &str, images: &str) -> String {
    // Three vec3 positions (36 bytes) and three vec2 uvs (24 bytes), all zero.
    let data = base64_zeros(60);
    format!(
        r#"{{"asset": {{"version": "2.0"}},
"buffers": [{{"byteLength": 60, "uri": "data:application/octet-stream;base64,{data}"}}],
"bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 24}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [0, 0, 0]}},
              {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "material": 0}}]}}],
"materials": [{material}], "textures": [{textures}], "images": [{images}],
"nodes": [{{"mesh": 0}}], "scenes": [{{"nodes": [0]}}]}}"#
    )
}

fn base64_zeros(n: usize) -> String {
    "A".repeat(n.div_ceil(3) * 4)
}

/// Broken materials, textures and images in a glTF file are errors naming the file, or (a missing
/// image file) a warning; none panics.
#[test]
fn malformed_gltf_materials_are_errors_naming_the_file() {
    let parse = |text: &str| {
        appel::io::gltf::parse_gltf_with(text.as_bytes(), Path::new("bad.gltf"), &|uri| {
            Err(format!("`{uri}` does not exist"))
        })
    };
    let ok_texture = r#"{"source": 0}"#;
    let png = r#"{"uri": "t.png"}"#;
    // A missing image file: a warning, the model still loads.
    let m = parse(&gltf_with(
        r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}"#,
        ok_texture,
        png,
    ))
    .unwrap();
    assert!(m.warnings[0].contains("t.png"), "{:?}", m.warnings);
    assert!(m.materials[0].diffuse_map.is_some());
    for (what, material, texture, image) in [
        (
            "texture index out of range",
            r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 7}}}"#,
            ok_texture,
            png,
        ),
        (
            "image index out of range",
            r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}"#,
            r#"{"source": 3}"#,
            png,
        ),
        (
            "image view outside its buffer",
            r#"{"emissiveTexture": {"index": 0}}"#,
            ok_texture,
            r#"{"bufferView": 9, "mimeType": "image/png"}"#,
        ),
        (
            "bad base64 image",
            r#"{"pbrMetallicRoughness": {"metallicRoughnessTexture": {"index": 0}}}"#,
            ok_texture,
            r#"{"uri": "data:image/png;base64,@@@"}"#,
        ),
        (
            "clearcoat texture out of range",
            r#"{"extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatTexture": {"index": 5}}}}"#,
            ok_texture,
            png,
        ),
        (
            "alpha mode unknown",
            r#"{"alphaMode": "SOMETIMES"}"#,
            ok_texture,
            png,
        ),
    ] {
        let e = parse(&gltf_with(material, texture, image))
            .err()
            .unwrap_or_else(|| panic!("{what}: accepted"))
            .to_string();
        assert!(e.contains("bad.gltf"), "{what}: {e}");
    }
}

/// glTF lights and cameras come out in world space, placed by their nodes.
#[test]
fn gltf_lights_and_cameras_follow_their_nodes() {
    let text = gltf_with(r#"{}"#, r#"{"source": 0}"#, r#"{"uri": "t.png"}"#).replace(
        r#""nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]"#,
        r#""extensionsUsed": ["KHR_lights_punctual"],
"extensions": {"KHR_lights_punctual": {"lights": [
  {"type": "spot", "intensity": 5, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.4}},
  {"type": "directional", "color": [1, 0.5, 0.25]},
  {"type": "spot", "spot": {}}]}},
"cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1, "aspectRatio": 2}}],
"nodes": [{"mesh": 0, "children": [1, 2, 3, 4]},
          {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
          {"rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 1}}},
          {"translation": [0, 0, 5], "camera": 0},
          {"extensions": {"KHR_lights_punctual": {"light": 2}}}],
"scenes": [{"nodes": [0]}]"#,
    );
    let m = appel::io::gltf::parse_gltf_with(text.as_bytes(), Path::new("l.gltf"), &|_| {
        Err("no".into())
    })
    .unwrap_or_else(|e| panic!("{e}"));
    use appel::description::LightDesc;
    match &m.lights[0] {
        LightDesc::Spot(appel::description::SpotDesc {
            position,
            look_at,
            intensity,
            cutoff_angle,
            beam_width,
            ..
        }) => {
            assert_eq!(*position, [0.0, 2.0, 0.0]);
            assert_eq!(*look_at, [0.0, 2.0, -1.0]);
            assert_eq!(*intensity, 5.0);
            assert!((cutoff_angle - 0.4f32.to_degrees()).abs() < 1e-4);
            assert!((beam_width.unwrap() - 0.2f32.to_degrees()).abs() < 1e-4);
        }
        other => panic!("{other:?}"),
    }
    match &m.lights[1] {
        // -z turned by -90 degrees about x: straight down.
        LightDesc::Directional(appel::description::DirectionalDesc {
            direction, color, ..
        }) => {
            assert!((Vec3::from(*direction) - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-5);
            assert_eq!(*color, [1.0, 0.5, 0.25]);
        }
        other => panic!("{other:?}"),
    }
    // A spot with the extension's default cones (inner 0) is a valid spot: its full-intensity
    // cone is the smallest Appel's spot allows, not an invalid zero.
    assert!(
        matches!(m.lights[2], LightDesc::Spot(_)),
        "{:?}",
        m.lights[2]
    );
    m.lights[2].check().unwrap_or_else(|e| panic!("{e:?}"));
    let c = &m.cameras[0];
    assert_eq!(c.camera.eye, [0.0, 0.0, 5.0]);
    assert_eq!(c.camera.look_at, [0.0, 0.0, 4.0]);
    assert!((c.camera.fov - 0.5f32.to_degrees()).abs() < 1e-4);
    assert_eq!(c.aspect, Some(2.0));
}
