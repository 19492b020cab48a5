//! Mitsuba's own test scenes and the Cornell box converted, with spot checks, and malformed
//! files failing at their line.

// Mitsuba's values are kept as it prints them, beyond single precision.
#![allow(clippy::excessive_precision)]

use super::super::{document_from_str, load_xml, XmlOptions};
use crate::description::validate;
use crate::description::*;
use crate::description::{ConstantDesc, DirectionalDesc, EnvMapDesc, PointDesc};
use std::path::{Path, PathBuf};

fn shared(rel: &str) -> PathBuf {
    appel_testdata::path(rel)
}

const SCENES: &str = "mitsuba-data/tests/scenes";

fn load(rel: &str) -> Description {
    let path = shared(rel);
    let d = load_xml(&path, &XmlOptions::default()).unwrap_or_else(|e| panic!("{rel}: {e}"));
    validate::validate(&d).unwrap_or_else(|e| panic!("{rel}: {e:?}"));
    d
}

fn close(a: &[f32], b: &[f32], tol: f32) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

fn rgb(t: &TextureDesc) -> [f32; 3] {
    match t {
        TextureDesc::Rgb(c) => *c,
        TextureDesc::Value(v) => [*v; 3],
        other => panic!("not a constant: {other:?}"),
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn every_scene_with_supported_plugins_converts() {
    for rel in [
        "floating_sphere/test_directional_direct.xml",
        "infinite_mirrors/scene_path.xml",
        "instancing/test_instancing_path.xml",
        "bsdf_spheres/test_arealight_path.xml",
        "bsdf_spheres/test_constant_path.xml",
        "bsdf_spheres/test_envmap_path.xml",
        "bsdf_spheres/test_pointlight_path.xml",
        "bsdf_spheres/test_roughdielectric_path.xml",
        "bsdf_spheres/test_roughplastic_linear_path.xml",
        "bsdf_spheres/test_roughplastic_nonlinear_path.xml",
        "bsdf_spheres/test_textured_diffuse_path.xml",
        "bsdf_spheres/test_textured_roughconductor_path.xml",
        "bsdf_spheres/test_texturedprincipled1_path.xml",
        "bsdf_spheres/test_texturedprincipled2_path.xml",
        "bsdf_spheres/test_texturedprincipledthin_path.xml",
        "bsdf_spheres/test_normalmap_path.xml",
        "bsdf_spheres/test_normalmap_roughconductor_path.xml",
        "bsdf_spheres/test_normalmap_identity_roughconductor_path.xml",
        "bsdf_spheres/test_bumpmap_path.xml",
        "mesh_attributes/test_mesh_attributes_1_face_direct.xml",
        "mesh_attributes/test_mesh_attributes_3_face_direct.xml",
        "mesh_attributes/test_mesh_attributes_3_vertex_direct.xml",
    ] {
        let d = load(&format!("{SCENES}/{rel}"));
        assert!(!d.shapes.is_empty() || !d.instances.is_empty(), "{rel}");
        for s in &d.shapes {
            if let ShapeDesc::Mesh(MeshShapeDesc { file: f, .. }) = s {
                assert!(
                    Path::new(f).is_absolute() && Path::new(f).is_file(),
                    "{rel}: {f}"
                );
            }
        }
    }
}

#[test]
fn plugins_appel_lacks_fail_at_their_line() {
    let e = err(&format!(
        "<scene version=\"3.0.0\">{CAMERA}\n\n    <shape type=\"bsplinecurve\">\n    </shape>\n</scene>"
    ));
    assert!(
        e.starts_with("scene.xml:3:5: <shape type=\"bsplinecurve\">: unsupported shape plugin"),
        "{e}"
    );
    let e = err(&format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<medium type=\"fog\"/>\n</scene>"
    ));
    assert!(
        e.starts_with(
            "scene.xml:2:1: <medium type=\"fog\">: unsupported medium plugin \"fog\" (supported: \
             homogeneous, heterogeneous)"
        ),
        "{e}"
    );
}

fn convert_ok(text: &str) -> Description {
    let doc = document_from_str(text, Path::new("scene.xml"), &XmlOptions::default()).unwrap();
    let d = super::convert(&doc).unwrap_or_else(|e| panic!("{e}"));
    validate::validate(&d).unwrap_or_else(|e| panic!("{e:?}"));
    d
}

/// Media declared at the top level, nested in shapes or referenced, their phase functions and
/// volumes, the sensor's medium and the volpath integrator.
#[test]
fn media_convert_with_their_phases_and_interfaces() {
    let d = convert_ok(
        "<scene version=\"3.0.0\">
  <integrator type=\"volpath\"><integer name=\"max_depth\" value=\"7\"/></integrator>
  <medium type=\"homogeneous\" id=\"fog\">
    <rgb name=\"sigma_t\" value=\"0.5, 0.25, 1\"/><float name=\"scale\" value=\"2\"/>
    <phase type=\"blendphase\"><float name=\"weight\" value=\"0.25\"/>
      <phase type=\"rayleigh\"/><phase type=\"hg\"><float name=\"g\" value=\"-0.3\"/></phase>
    </phase>
  </medium>
  <sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><ref id=\"fog\"/></sensor>
  <shape type=\"sphere\">
    <bsdf type=\"null\"/>
    <ref name=\"exterior\" id=\"fog\"/>
    <medium type=\"heterogeneous\" name=\"interior\">
      <volume type=\"constvolume\" name=\"sigma_t\"><float name=\"value\" value=\"3\"/></volume>
      <float name=\"albedo\" value=\"0.5\"/>
    </medium>
  </shape>
</scene>",
    );
    assert_eq!(d.render.integrator, IntegratorName::VolPath);
    assert_eq!(d.render.max_depth, 7);
    assert_eq!(d.camera.medium.as_deref(), Some("fog"));
    let MediumDesc::Homogeneous(fog) = &d.media["fog"] else {
        panic!("{:?}", d.media)
    };
    assert_eq!(fog.sigma_t, Some(ColorDesc::Rgb([0.5, 0.25, 1.0])));
    assert_eq!(fog.scale, 2.0);
    let PhaseDesc::BlendPhase(b) = &fog.phase else {
        panic!("{:?}", fog.phase)
    };
    assert_eq!(b.weight, 0.25);
    assert_eq!(b.phases[1], PhaseDesc::Hg(HgDesc { g: -0.3 }));
    let ShapeDesc::Sphere(s) = &d.shapes[0] else {
        panic!()
    };
    assert_eq!(s.exterior.as_deref(), Some("fog"));
    let inner = s.interior.as_deref().unwrap();
    let MediumDesc::Heterogeneous(h) = &d.media[inner] else {
        panic!("{:?}", d.media)
    };
    assert_eq!(h.sigma_t.as_ref().unwrap().constant(), Some([3.0; 3]));
    assert_eq!(h.albedo.as_deref(), Some(&VolumeDesc::Value(0.5)));
    assert!(matches!(
        d.materials[s.material.as_deref().unwrap()],
        MaterialDesc::Null(_)
    ));
}

/// What Appel cannot do with media fails at its line, naming what is missing.
#[test]
fn media_appel_lacks_fail_at_their_line() {
    let scene = |body: &str| format!("<scene version=\"3.0.0\">{CAMERA}\n{body}\n</scene>");
    let e = err(&scene("<integrator type=\"volpathmis\"/>"));
    assert!(
        e.starts_with("scene.xml:2:1: <integrator type=\"volpathmis\">: Appel has no volpathmis")
            && e.contains("spectral MIS"),
        "{e}"
    );
    let e = err(&scene(
        "<medium type=\"homogeneous\">\n  <phase type=\"sggx\"/>\n</medium>",
    ));
    assert!(
        e.starts_with("scene.xml:3:3: <phase type=\"sggx\">: unsupported phase plugin"),
        "{e}"
    );
    let e = err(&scene(
        "<medium type=\"homogeneous\">\n  <phase type=\"hg\"><float name=\"g\" value=\"1.5\"/></phase>\n</medium>",
    ));
    assert!(
        e.starts_with("scene.xml:3:") && e.contains("between -1 and 1"),
        "{e}"
    );
    let e = err(&scene(
        "<medium type=\"homogeneous\">\n  <float name=\"density\" value=\"2\"/>\n</medium>",
    ));
    assert!(
        e.starts_with("scene.xml:3:3: <float name=\"density\">"),
        "{e}"
    );
    let e = err(&scene(
        "<medium type=\"heterogeneous\">\n  <volume type=\"noise\" name=\"sigma_t\"/>\n</medium>",
    ));
    assert!(
        e.starts_with("scene.xml:3:3: <volume type=\"noise\">: unsupported volume plugin"),
        "{e}"
    );
    let e = err(&scene(
        "<medium type=\"homogeneous\" id=\"m\"/>\n<shape type=\"sphere\">\n  <ref name=\"inside\" id=\"m\"/>\n</shape>",
    ));
    assert!(
        e.starts_with("scene.xml:4:3:") && e.contains("interior"),
        "{e}"
    );
    let e = err(&scene(
        "<medium type=\"homogeneous\">\n  <rgb name=\"albedo\" value=\"0.5, 1.5, 0.5\"/>\n</medium>",
    ));
    assert!(e.starts_with("scene.xml:3:3:"), "{e}");
}

/// various_shapes: the cylinder keeps its transform, the serialized mesh is a mesh file, and the
/// sdfgrid inside a shapegroup becomes one shape per instance with the composed transform.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn various_shapes_converts_every_shape() {
    let d = load(&format!(
        "{SCENES}/various_shapes/test_various_shapes_path.xml"
    ));
    let kinds: Vec<&str> = d
        .shapes
        .iter()
        .map(|s| match s {
            ShapeDesc::Sphere(_) => "sphere",
            ShapeDesc::Cylinder(_) => "cylinder",
            ShapeDesc::Disk(_) => "disk",
            ShapeDesc::Rectangle(_) => "rectangle",
            ShapeDesc::Cube(_) => "cube",
            ShapeDesc::Mesh(_) => "mesh",
            ShapeDesc::SdfGrid(_) => "sdfgrid",
            _ => "other",
        })
        .collect();
    assert_eq!(
        kinds,
        [
            "sphere",
            "cylinder",
            "disk",
            "rectangle",
            "mesh",
            "mesh",
            "mesh",
            "cube",
            "cube",
            "sdfgrid"
        ]
    );
    let ShapeDesc::Mesh(m) = &d.shapes[4] else {
        unreachable!()
    };
    assert!(m
        .file
        .ends_with("serialized/rectangle_normals_uv.serialized"));
    let ShapeDesc::Cylinder(c) = &d.shapes[1] else {
        unreachable!()
    };
    // Scaled by 1.5 across the axis and 2 along it: the axis keeps length 2.
    let m = c.to_world();
    assert!((m.x_axis.truncate().length() - 1.5).abs() < 1e-5);
    assert!((m.z_axis.truncate().length() - 2.0).abs() < 1e-5);
    let ShapeDesc::SdfGrid(g) = &d.shapes[9] else {
        unreachable!()
    };
    assert_eq!(g.normals, SdfNormalsDesc::Smooth);
    assert!(g.file.ends_with("torus_sdfgrid.vol"));
    // Scaled by 2 and 2.5, then rotated: the grid's unit cube is 5 across.
    let t = g.transform.as_ref().unwrap().matrix();
    assert!((t.x_axis.truncate().length() - 5.0).abs() < 1e-4);
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn cornell_box() {
    let d = load("bitterli-scenes/cornell-box/mitsuba/scene_v3.xml");
    let c = &d.camera;
    assert_eq!(c.kind, CameraKind::Perspective);
    assert!(close(&c.eye, &[0.0, 1.0, 6.8], 1e-6), "{c:?}");
    assert!(close(&c.look_at, &[0.0, 1.0, 5.8], 1e-6), "{c:?}");
    assert!(close(&c.up, &[0.0, 1.0, 0.0], 1e-6), "{c:?}");
    assert_eq!((c.fov, c.fov_axis), (19.5, FovAxis::X));
    assert_eq!((c.width, c.height), (1024, 1024));
    let r = &d.render;
    assert_eq!(
        (r.integrator, r.max_depth, r.spp),
        (IntegratorName::Path, 65, 64)
    );
    assert_eq!(r.filter, FilterDesc::Tent { radius: 1.0 });
    assert_eq!(r.sampler, Some(SamplerName::Independent));
    // Eight rectangles and cubes, the light among them.
    assert_eq!(d.shapes.len(), 8);
    let light = d.shapes.iter().find(|s| s.emitter().is_some()).unwrap();
    let ShapeDesc::Rectangle(light) = light else {
        panic!("{light:?}")
    };
    assert_eq!(
        rgb(&light.emitter.as_ref().unwrap().radiance),
        [17.0, 12.0, 4.0]
    );
    let m = light.transform.as_ref().unwrap().matrix.unwrap();
    assert!(
        close(&m[0], &[0.235, -1.66103e-8, -7.80685e-9, -0.005], 1e-9),
        "{m:?}"
    );
    assert_eq!(
        d.shapes
            .iter()
            .filter(|s| matches!(s, ShapeDesc::Cube(_)))
            .count(),
        2
    );
    let MaterialDesc::TwoSided(left) = &d.materials["LeftWallBSDF"] else {
        panic!("{:?}", d.materials["LeftWallBSDF"]);
    };
    let MaterialDesc::Diffuse(front) = &d.materials[&left.front] else {
        panic!("{:?}", d.materials[&left.front]);
    };
    assert_eq!(rgb(&front.reflectance), [0.63, 0.065, 0.05]);

    // -D overrides the file's defaults.
    let path = shared("bitterli-scenes/cornell-box/mitsuba/scene_v3.xml");
    let options = XmlOptions {
        params: vec![("spp".into(), "8".into()), ("resx".into(), "64".into())],
    };
    let d = load_xml(&path, &options).unwrap();
    assert_eq!(
        (d.render.spp, d.camera.width, d.camera.height),
        (8, 64, 1024)
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn floating_sphere_and_mirrors() {
    let d = load(&format!(
        "{SCENES}/floating_sphere/test_directional_direct.xml"
    ));
    // `moment` is read through to the nested integrator, chosen by `$integrator`.
    assert_eq!(d.render.integrator, IntegratorName::Direct);
    assert_eq!((d.render.spp, d.camera.width), (32, 48));
    assert_eq!(
        d.lights,
        vec![LightDesc::Directional(DirectionalDesc {
            direction: [0.0, 0.0, -1.0],
            color: [1.0; 3],
            intensity: 1.0
        })]
    );
    let ShapeDesc::Mesh(sphere) = &d.shapes[1] else {
        panic!("{:?}", d.shapes[1])
    };
    assert!(sphere.file.ends_with("common/meshes/sphere.obj"));
    let m = sphere.transform.as_ref().unwrap().matrix.unwrap();
    assert_eq!(m[0], [0.1, 0.0, 0.0, 0.0]);
    assert_eq!(m[2], [0.0, 0.0, 0.1, 1.0]);
    // Both shapes share the one referenced BSDF.
    assert_eq!(d.shapes[0].material(), Some("diffuse_bsdf"));
    assert_eq!(d.shapes[1].material(), d.shapes[0].material());

    let d = load(&format!("{SCENES}/infinite_mirrors/scene_path.xml"));
    assert_eq!((d.render.max_depth, d.render.spp), (8, 64));
    assert_eq!(d.camera.near_clip, 1.0);
    let MaterialDesc::Conductor(c) = &d.materials[d.shapes[0].material().unwrap()] else {
        panic!()
    };
    assert_eq!((c.eta, c.k), (Some([0.789; 3]), Some([6.15; 3])));
    let LightDesc::EnvMap(EnvMapDesc { file, scale, .. }) = &d.lights[0] else {
        panic!("{:?}", d.lights)
    };
    assert!(
        file.ends_with("common/textures/museum.exr") && *scale == 1.0,
        "{file}"
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn instancing() {
    let d = load(&format!("{SCENES}/instancing/test_instancing_path.xml"));
    // The group's mesh is declared once and placed three times; its sphere and rectangle are
    // added per instance.
    assert_eq!(d.meshes.len(), 1);
    assert_eq!(d.instances.len(), 3);
    assert_eq!(d.shapes.len(), 6);
    let spheres: Vec<&SphereDesc> = d
        .shapes
        .iter()
        .filter_map(|s| match s {
            ShapeDesc::Sphere(s) => Some(s),
            _ => None,
        })
        .collect();
    assert_eq!(spheres.len(), 3);
    // Second instance: rotate 45 about y, scale 1.5, translate z 2, after the group's own
    // scale 0.5 and translate x -1.
    let h = std::f32::consts::FRAC_1_SQRT_2 * 1.5;
    assert!(
        close(&spheres[1].center, &[-h, 0.0, 2.0 + h], 1e-5),
        "{:?}",
        spheres[1]
    );
    assert!((spheres[1].radius - 0.75).abs() < 1e-6);
    let m = d.instances[1].transform.as_ref().unwrap().matrix.unwrap();
    assert!(close(&m[2], &[-h, 0.0, h, 2.0], 1e-5), "{m:?}");
    assert_eq!(
        d.lights[0],
        LightDesc::Point(PointDesc {
            position: [-5.0, -6.0, 0.0],
            color: [300.0; 3],
            intensity: 1.0
        })
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn bsdf_spheres_parameters() {
    let d = load(&format!("{SCENES}/bsdf_spheres/test_arealight_path.xml"));
    // Spectra as Mitsuba 3.9.1's scalar_rgb makes them (its Python module, `mi.traverse`).
    let lamp = d.shapes.iter().find_map(|s| s.emitter()).unwrap();
    let radiance = rgb(&lamp.radiance);
    assert!(
        close(&radiance, &[20.7108364, 10.8546343, 2.77115202], 1e-4),
        "{radiance:?}"
    );
    let MaterialDesc::Diffuse(light) = &d.materials["light"] else {
        panic!()
    };
    let r = rgb(&light.reflectance);
    assert!(
        close(&r, &[0.77636677, 0.779810011, 0.77602911], 1e-6),
        "{r:?}"
    );
    // The fragment's camera and its twelve objects beside the lamp.
    assert!(close(&d.camera.eye, &[-24.0, 0.0, 0.0], 0.0));
    assert_eq!((d.render.spp, d.shapes.len()), (128, 13));
    let MaterialDesc::Mask(leaf) = &d.materials["mask"] else {
        panic!("{:?}", d.materials.keys())
    };
    assert!(matches!(
        d.materials[&leaf.material],
        MaterialDesc::TwoSided(_)
    ));

    let d = load(&format!(
        "{SCENES}/bsdf_spheres/test_roughdielectric_path.xml"
    ));
    let MaterialDesc::RoughDielectric(g) = &d.materials["roughdielectric"] else {
        panic!("{:?}", d.materials)
    };
    assert_eq!(g.int_ior, IorDesc::Named("bk7".into()));
    assert_eq!(g.alpha, Some(TextureDesc::Value(0.02)));
    assert_eq!(g.distribution, DistributionDesc::Beckmann);

    let d = load(&format!(
        "{SCENES}/bsdf_spheres/test_textured_roughconductor_path.xml"
    ));
    let MaterialDesc::RoughConductor(m) = &d.materials["roughconductor"] else {
        panic!("{:?}", d.materials)
    };
    assert_eq!(m.material.as_deref(), Some("a-C"));
    assert_eq!(
        m.alpha_u,
        Some(TextureDesc::Texture(TextureNode::Checkerboard {
            color0: [0.05; 3],
            color1: [0.3; 3],
            to_uv: Some([[25.0, 0.0, 0.0], [0.0, 25.0, 0.0], [0.0, 0.0, 1.0]]),
        }))
    );

    let d = load(&format!(
        "{SCENES}/bsdf_spheres/test_textured_diffuse_path.xml"
    ));
    let MaterialDesc::Diffuse(w) = &d.materials["diffuse"] else {
        panic!("{:?}", d.materials.keys())
    };
    let TextureDesc::Texture(TextureNode::Bitmap { file, raw, .. }) = &w.reflectance else {
        panic!("{w:?}")
    };
    assert!(file.ends_with("common/textures/wood.jpg") && !raw, "{file}");
}

fn err(text: &str) -> String {
    document_from_str(text, Path::new("scene.xml"), &XmlOptions::default())
        .and_then(|doc| super::convert(&doc))
        .unwrap_err()
        .to_string()
}

const CAMERA: &str = "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>";

#[test]
fn malformed_scenes_fail_at_their_line() {
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<bsdf type=\"velvet\"/>\n<shape type=\"sphere\"/>\n</scene>"));
    assert!(e.starts_with("scene.xml:2:1: <bsdf type=\"velvet\">: unsupported BSDF plugin \"velvet\" (supported: diffuse, conductor"), "{e}");
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"sphere\">\n  <bsdf type=\"velvet\"/>\n</shape>\n</scene>"));
    assert!(
        e.starts_with("scene.xml:3:3: <bsdf type=\"velvet\">: unsupported BSDF plugin"),
        "{e}"
    );
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"sphere\">\n  <float name=\"radius\" value=\"x1\"/>\n</shape></scene>"));
    assert!(
        e.starts_with("scene.xml:3:3: <float name=\"radius\">: could not parse the number \"x1\""),
        "{e}"
    );
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"sphere\">\n  <float name=\"radiu\" value=\"1\"/>\n</shape></scene>"));
    assert!(e.starts_with("scene.xml:3:3: <float name=\"radiu\">: parameter \"radiu\" is not supported by <shape type=\"sphere\">"), "{e}");
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"sphere\">\n<bsdf type=\"diffuse\">\n</scene>"));
    assert!(e.starts_with("scene.xml:"), "{e}");
    let e = err(&format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"serialized\"/>\n</scene>"
    ));
    assert!(
        e.starts_with(
            "scene.xml:2:1: <shape type=\"serialized\">: needs a <string name=\"filename\">"
        ),
        "{e}"
    );
    let e = err(&format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"cylinder\">\n<float name=\"radius\" value=\"-1\"/></shape>\n</scene>"
    ));
    assert!(
        e.starts_with("scene.xml:3:1: <float name=\"radius\">: the radius must be positive"),
        "{e}"
    );
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"obj\">\n<string name=\"filename\" value=\"none.obj\"/></shape>\n</scene>"));
    assert!(
        e.starts_with("scene.xml:3:1: <string name=\"filename\">: file \"none.obj\" not found"),
        "{e}"
    );
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"sphere\"><bsdf type=\"diffuse\">\n<rgb name=\"reflectance\" value=\"2\"/></bsdf></shape>\n</scene>"));
    assert!(
        e.starts_with(
            "scene.xml:3:1: <rgb name=\"reflectance\">: an RGB reflectance must lie in [0, 1]"
        ),
        "{e}"
    );
    let e = err(&format!("<scene version=\"3.0.0\">{CAMERA}\n<shape type=\"sphere\"><transform name=\"to_world\"><scale x=\"2\"/></transform></shape>\n</scene>"));
    assert!(
        e.starts_with("scene.xml:2:1: <shape type=\"sphere\">: a sphere's to_world may only"),
        "{e}"
    );
    let e = err("<scene version=\"3.0.0\">\n<shape type=\"sphere\"/></scene>");
    assert!(e.contains("the scene has no <sensor>"), "{e}");
    let e = err(&format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<emitter type=\"timed_sunsky\"/></scene>"
    ));
    assert!(
        e.starts_with("scene.xml:2:1: <emitter type=\"timed_sunsky\">: unsupported emitter plugin"),
        "{e}"
    );
}

/// An emitter's parameters are checked by its plugin's own rules, in the XML as in TOML, each
/// reported at the property's line.
#[test]
fn emitter_parameters_fail_at_their_property() {
    let e = load_err(&format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<emitter type=\"sunsky\">\n\
         <float name=\"turbidity\" value=\"11\"/></emitter></scene>"
    ));
    assert!(
        e.starts_with("scene.xml:3:1: ") && e.contains("`turbidity` must lie in [1, 10], got 11"),
        "{e}"
    );
    let e = load_err(&format!(
        "<scene version=\"3.0.0\">{CAMERA}\n<emitter type=\"sunsky\">\n\
         <vector name=\"sun_direction\" x=\"0\" y=\"1\" z=\"0\"/>\n\
         <float name=\"hour\" value=\"12\"/></emitter></scene>"
    ));
    assert!(
        e.starts_with("scene.xml:4:1: ") && e.contains("not both (`hour`)"),
        "{e}"
    );
    let toml_error = crate::description::description_from_str(
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n\
         [[light]]\ntype = \"spot\"\nposition = [0, 1, 0]\nlook_at = [0, 0, 0]\n\
         cutoff_angle = 95\n",
        crate::description::parse::Syntax::Toml,
        Path::new("scene.toml"),
    )
    .unwrap_err()
    .to_string();
    assert!(
        toml_error.starts_with("scene.toml:9:")
            && toml_error.contains("`cutoff_angle` must lie in (0, 90]"),
        "{toml_error}"
    );
}

#[test]
fn a_missing_include_names_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("main.xml");
    std::fs::write(&main, format!("<scene version=\"3.0.0\">{CAMERA}\n\n    <include filename=\"fragments/none.xml\"/>\n</scene>")).unwrap();
    let e = load_xml(&main, &XmlOptions::default())
        .unwrap_err()
        .to_string();
    let at = format!(
        "{}:3:5: <include>: included file \"fragments/none.xml\" not found",
        main.display()
    );
    assert!(e.starts_with(&at), "{e}");
}

#[test]
fn defaults_of_a_minimal_scene_are_mitsubas() {
    let doc = document_from_str(
        &format!("<scene version=\"3.0.0\">{CAMERA}<shape type=\"sphere\"/><emitter type=\"constant\"><spectrum name=\"radiance\" value=\"2\"/></emitter></scene>"),
        Path::new("scene.xml"),
        &XmlOptions::default(),
    )
    .unwrap();
    let d = super::convert(&doc).unwrap();
    // No integrator: Mitsuba's path tracer; no film: 768 x 576; no sampler: 4 samples.
    assert_eq!(
        (d.render.integrator, d.render.max_depth),
        (IntegratorName::Path, -1)
    );
    assert_eq!(
        (d.camera.width, d.camera.height, d.render.spp),
        (768, 576, 4)
    );
    assert_eq!((d.camera.fov_axis, d.camera.near_clip), (FovAxis::X, 0.01));
    // No BSDF: Mitsuba's diffuse of reflectance 0.5.
    let name = d.shapes[0].material().unwrap();
    assert_eq!(
        d.materials[name],
        MaterialDesc::Diffuse(DiffuseDesc {
            reflectance: TextureDesc::Value(0.5)
        })
    );
    let ShapeDesc::Sphere(sphere) = &d.shapes[0] else {
        panic!("{:?}", d.shapes[0])
    };
    assert_eq!((sphere.center, sphere.radius), ([0.0; 3], 1.0));
    // A uniform spectrum inside an emitter: Mitsuba 3.9.1 gives 2 x (1.2048, 0.9483, 0.9089).
    let LightDesc::Constant(ConstantDesc { radiance }) = d.lights[0] else {
        panic!()
    };
    assert!(
        close(&radiance, &[2.40958786, 1.89658201, 1.81783211], 1e-6),
        "{radiance:?}"
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn load_description_reads_xml_by_extension() {
    let path = shared(&format!("{SCENES}/instancing/test_instancing_path.xml"));
    let loaded = crate::format::load(&path, &Default::default()).unwrap();
    assert_eq!(loaded.description.instances.len(), 3);
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.xml");
    std::fs::write(
        &bad,
        "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>",
    )
    .unwrap();
    let e = crate::format::load(&bad, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with(&format!("{}:3:", bad.display())), "{e}");
}

/// The error of loading `text` as `scene.xml` (converted and validated), with the folder's name
/// taken off.
fn load_err(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.xml");
    std::fs::write(&path, text).unwrap();
    let e = crate::format::load(&path, &Default::default())
        .map(|_| ())
        .unwrap_err()
        .to_string();
    e.replace(&format!("{}/", dir.path().display()), "")
}

/// Problems that only the validation of the converted description finds are reported at the
/// line and column of the parameter that gave the value, or of the element that made the entry.
#[test]
fn validation_errors_point_at_the_xml_line() {
    let scene = |body: &str| format!("<scene version=\"3.0.0\">{CAMERA}\n{body}\n</scene>");
    for (body, expected) in [
        (
            "<shape type=\"sphere\">\n  <bsdf type=\"dielectric\">\n    <float name=\"int_ior\" value=\"-0\"/>\n  </bsdf>\n</shape>",
            "scene.xml:4:5: in the converted scene, materials.dielectric.int_ior: `int_ior`, an index of refraction, must be positive, got -0",
        ),
        (
            "<bsdf type=\"roughdielectric\" id=\"frosted\">\n  <string name=\"ext_ior\" value=\"unobtainium\"/>\n</bsdf>",
            "scene.xml:3:3: in the converted scene, materials.frosted.ext_ior: unknown index of refraction `unobtainium`",
        ),
        (
            "<shape type=\"sphere\">\n  <float name=\"radius\" value=\"-1\"/>\n</shape>",
            "scene.xml:3:3: in the converted scene, shape[0].radius: `radius` must be a positive number, got -1",
        ),
        (
            "<shape type=\"sphere\"/>\n<shape type=\"rectangle\">\n  <emitter type=\"area\">\n    <rgb name=\"radiance\" value=\"-1, 1, 1\"/>\n  </emitter>\n</shape>",
            "scene.xml:5:5: in the converted scene, shape[1].emitter.radiance: `radiance` must not be negative",
        ),
        (
            "<emitter type=\"point\">\n  <rgb name=\"intensity\" value=\"1, -1, 1\"/>\n</emitter>",
            "scene.xml:3:3: in the converted scene, light[0].color: `color` must not be negative",
        ),
        (
            "<bsdf type=\"conductor\">\n  <string name=\"material\" value=\"Xx\"/>\n</bsdf>",
            "scene.xml:3:3: in the converted scene, materials.conductor.material: unknown conductor `Xx`",
        ),
        (
            "<bsdf type=\"roughplastic\">\n  <texture type=\"checkerboard\" name=\"alpha\"/>\n</bsdf>",
            "scene.xml:3:3: in the converted scene, materials.roughplastic.alpha: a rough plastic's `alpha` must be a number",
        ),
    ] {
        let e = load_err(&scene(body));
        assert!(e.starts_with(expected), "expected {expected}\n     got {e}");
    }
}

/// The same check in a TOML scene is at the value's line.
#[test]
fn a_non_positive_index_of_refraction_is_an_error_at_its_line() {
    let toml = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[materials.glass]\ntype = \"dielectric\"\nint_ior = -0.0\n";
    let e = crate::description::description_from_str(
        toml,
        crate::description::parse::Syntax::Toml,
        Path::new("scene.toml"),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("scene.toml:7:11: materials.glass.int_ior: `int_ior`, an index of refraction, must be positive, got -0"),
        "{e}"
    );
}

/// Mitsuba's `thinlens`: a perspective camera with `aperture_radius` (required) and
/// `focus_distance` (by default `far_clip`); `perspective` reads `focus_distance` and ignores it;
/// bad values, a missing radius and a scaling transform are errors at their line.
#[test]
fn thinlens_sensors_have_an_aperture_and_a_plane_in_focus() {
    let scene = |sensor: &str| {
        format!("<scene version=\"3.0.0\">\n{sensor}\n<shape type=\"sphere\"/>\n</scene>")
    };
    let convert = |sensor: &str| {
        let doc = document_from_str(
            &scene(sensor),
            Path::new("scene.xml"),
            &XmlOptions::default(),
        )
        .unwrap();
        super::convert(&doc).unwrap()
    };
    let d = convert(
        "<sensor type=\"thinlens\">\n  <float name=\"fov\" value=\"40\"/>\n  \
         <float name=\"aperture_radius\" value=\"0.2\"/>\n  \
         <float name=\"focus_distance\" value=\"3\"/>\n  <transform name=\"to_world\">\
         <lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>\n</sensor>",
    );
    let c = &d.camera;
    assert_eq!(c.kind, CameraKind::Perspective);
    assert_eq!((c.aperture_radius, c.focus_distance), (0.2, Some(3.0)));
    assert_eq!(
        (c.fov, c.fov_axis, c.eye),
        (40.0, FovAxis::X, [0.0, 0.0, 5.0])
    );
    let d = convert(
        "<sensor type=\"thinlens\">\n  <float name=\"aperture_radius\" value=\"0.5\"/>\n  \
         <float name=\"far_clip\" value=\"50\"/>\n</sensor>",
    );
    assert_eq!(
        (d.camera.aperture_radius, d.camera.focus_distance),
        (0.5, Some(50.0))
    );
    let d = convert(
        "<sensor type=\"perspective\">\n  <float name=\"focus_distance\" value=\"3\"/>\n</sensor>",
    );
    assert_eq!(
        (d.camera.aperture_radius, d.camera.focus_distance),
        (0.0, None)
    );
    for (sensor, expected) in [
        (
            "<sensor type=\"thinlens\">\n  <float name=\"aperture_radius\" value=\"-1\"/>\n</sensor>",
            "scene.xml:3:3: <float name=\"aperture_radius\">: aperture_radius must be 0 (a pinhole) or a positive number of scene units, got -1",
        ),
        (
            "<sensor type=\"thinlens\">\n  <float name=\"aperture_radius\" value=\"0.1\"/>\n  <float name=\"focus_distance\" value=\"0\"/>\n</sensor>",
            "scene.xml:4:3: <float name=\"focus_distance\">: focus_distance must be a positive distance, got 0",
        ),
        (
            "<sensor type=\"thinlens\">\n  <float name=\"fov\" value=\"40\"/>\n</sensor>",
            "scene.xml:2:1: <sensor type=\"thinlens\">: a thinlens sensor needs <float name=\"aperture_radius\">",
        ),
        (
            "<sensor type=\"thinlens\">\n  <float name=\"aperture_radius\" value=\"0.1\"/>\n  <transform name=\"to_world\"><scale value=\"2\"/></transform>\n</sensor>",
            "scene.xml:4:3: <transform name=\"to_world\">: a thinlens camera's transform must not scale",
        ),
    ] {
        let e = err(&scene(sensor));
        assert!(e.starts_with(expected), "expected {expected}\n     got {e}");
    }
}

/// Appel's own `bdpt` plugin takes `strategy_images`, `unweighted` or `weighted`; another value
/// is an error at the integrator's line.
#[test]
fn bdpt_strategy_images_convert() {
    let scene = |body: &str| format!("<scene version=\"3.0.0\">{CAMERA}\n{body}\n</scene>");
    let d = convert_ok(&scene(
        "<integrator type=\"bdpt\">\n  <string name=\"strategy_images\" value=\"weighted\"/>\n</integrator>",
    ));
    assert_eq!(
        d.render.bdpt.and_then(|b| b.strategy_images),
        Some(crate::description::StrategyImages::Weighted)
    );
    let e = err(&scene(
        "<integrator type=\"bdpt\">\n  <string name=\"strategy_images\" value=\"all\"/>\n</integrator>",
    ));
    assert!(
        e.starts_with("scene.xml:2:1:") && e.contains("\"unweighted\" or \"weighted\""),
        "{e}"
    );
}
