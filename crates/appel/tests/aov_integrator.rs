//! Mitsuba's `aov` integrator: its channels are the analytic values of the surface each pixel's
//! centre sees, named as Mitsuba names them, and the nested integrator's image is exactly the one
//! that integrator renders alone.

use appel::description::description_from_str;
use appel::description::parse::Syntax;
use appel::render::{render, Film, RenderOptions};
use appel::scene::Scene;
use glam::Vec3;
use std::path::Path;

const EYE: Vec3 = Vec3::new(0.0, 0.0, 5.0);

/// A unit sphere at the origin seen from `EYE`, lit by a point light, rendered by `render`.
fn sphere_scene(render: &str) -> String {
    format!(
        r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0
width = 33
height = 33

{render}

[[shape]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0

[[light]]
type = "point"
position = [0.0, 3.0, 5.0]
intensity = 20.0
"#
    )
}

fn rendered(text: &str) -> Film {
    let d = description_from_str(text, Syntax::Toml, Path::new("aov.toml")).unwrap();
    let scene = Scene::new(&d, Path::new(".")).unwrap();
    render(&scene, &RenderOptions::default()).unwrap().0
}

fn channel<'a>(film: &'a Film, name: &str) -> &'a [f32] {
    &film
        .channels
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no channel {name}"))
        .values
}

fn v3(film: &Film, name: &str, i: usize) -> Vec3 {
    Vec3::new(
        channel(film, &format!("{name}.X"))[i],
        channel(film, &format!("{name}.Y"))[i],
        channel(film, &format!("{name}.Z"))[i],
    )
}

#[test]
fn sphere_aovs_are_the_analytic_surface() {
    let aov = sphere_scene(
        r#"[render]
integrator = "aov"
spp = 3
seed = 7

[render.aov]
aovs = "dd.y:depth, nn:sh_normal, ng:geo_normal, p:position, s:shape_index, i:prim_index, t:uv"
integrator = "path"
image = "my_image"
"#,
    );
    let film = rendered(&aov);
    let names: Vec<&str> = film.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "my_image.R",
            "my_image.G",
            "my_image.B",
            "my_image.A",
            "dd.y.T",
            "nn.X",
            "nn.Y",
            "nn.Z",
            "ng.X",
            "ng.Y",
            "ng.Z",
            "p.X",
            "p.Y",
            "p.Z",
            "s.I",
            "i.I",
            "t.U",
            "t.V",
        ]
    );
    // The centre pixel looks straight at the sphere: 5 - 1 away.
    let centre = film.index(16, 16);
    assert!((channel(&film, "dd.y.T")[centre] - 4.0).abs() < 1e-5);
    let mut hits = 0;
    for i in 0..film.rgb.len() {
        let depth = channel(&film, "dd.y.T")[i];
        let (p, n, ng) = (v3(&film, "p", i), v3(&film, "nn", i), v3(&film, "ng", i));
        if depth == 0.0 {
            // Misses are zeros, as Mitsuba writes them.
            assert_eq!((p, n, ng), (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO));
            assert_eq!(channel(&film, "s.I")[i], 0.0);
            assert_eq!(channel(&film, "my_image.A")[i], 0.0);
            continue;
        }
        hits += 1;
        // On the sphere, at the distance along the ray, with the sphere's outward normal.
        assert!((p.length() - 1.0).abs() < 1e-4, "{p}");
        assert!((depth - (p - EYE).length()).abs() < 1e-4);
        assert!((n.length() - 1.0).abs() < 1e-5, "{n}");
        assert!((n - p.normalize()).length() < 1e-4, "{n} {p}");
        assert!((ng - n).length() < 1e-4);
        assert!(n.z > 0.0, "the normal faces the camera");
        assert_eq!(channel(&film, "s.I")[i], 1.0);
        assert_eq!(channel(&film, "my_image.A")[i], 1.0);
        assert_eq!(channel(&film, "my_image.R")[i], film.rgb[i].x);
    }
    assert!(hits > 100 && hits < film.rgb.len(), "{hits}");

    // The image is the nested path tracer's, bit for bit.
    let path = rendered(&sphere_scene(
        "[render]\nintegrator = \"path\"\nspp = 3\nseed = 7\n",
    ));
    let bits = |f: &Film| -> Vec<[u32; 3]> {
        f.rgb
            .iter()
            .map(|c| c.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&film), bits(&path));
    assert!(film.rgb.iter().any(|c| c.x > 0.0));
    assert!(path.channels.is_empty());
}

#[test]
fn without_a_nested_integrator_the_image_is_black() {
    let film = rendered(&sphere_scene(
        "[render]\nintegrator = \"aov\"\n\n[render.aov]\naovs = \"d:depth\"\n",
    ));
    assert!(film.rgb.iter().all(|c| *c == Vec3::ZERO));
    assert_eq!(film.channels.len(), 1);
    assert!((channel(&film, "d.T")[film.index(16, 16)] - 4.0).abs() < 1e-5);
}

#[test]
fn a_bad_aov_type_is_an_error_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = sphere_scene(
        "[render]\nintegrator = \"aov\"\n\n[render.aov]\naovs = \"d:depth,a:albedo\"\n",
    );
    let line = text.lines().position(|l| l.starts_with("aovs")).unwrap() + 1;
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    let e = appel::format::load(&path, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains(&format!("scene.toml:{line}:")), "{e}");
    assert!(e.contains("`albedo` is not supported"), "{e}");

    let text = text.replace("a:albedo", "n:normals");
    std::fs::write(&path, &text).unwrap();
    let e = appel::format::load(&path, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains(&format!("scene.toml:{line}:")), "{e}");
    assert!(
        e.contains("unknown AOV type `normals`") && e.contains("sh_normal"),
        "{e}"
    );

    // An integrator without parameters of its own takes no table.
    let text = sphere_scene("[render]\nintegrator = \"path\"\n\n[render.path]\nmax_depth = 3\n");
    std::fs::write(&path, &text).unwrap();
    let e = appel::format::load(&path, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("scene.toml:"), "{e}");
    assert!(e.contains("no table of its own"), "{e}");

    // Unknown integrators list the registry's names.
    let text = sphere_scene("[render]\nintegrator = \"mlt\"\n");
    std::fs::write(&path, &text).unwrap();
    let e = appel::format::load(&path, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("raycast, whitted, path, direct, volpath, aov, bdpt, ptracer, sppm"),
        "{e}"
    );
}
