//! The pbrt reader on small scenes written here: directives, the graphics state, mappings and
//! their errors.

use super::{load_pbrt, PbrtScene};
use crate::description::*;
use std::path::PathBuf;

/// Writes `text` as `a.pbrt` in a fresh folder and reads it.
fn load(text: &str) -> crate::error::Result<PbrtScene> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir: PathBuf = std::env::temp_dir().join(format!(
        "appel-pbrt-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("a.pbrt");
    std::fs::write(&path, text).unwrap();
    load_pbrt(&path)
}

fn err(text: &str) -> String {
    load(text).map(|_| ()).unwrap_err().to_string()
}

/// A camera whose frame is right-handed in world space (`Scale -1 1 1` before `LookAt`, as
/// pbrt's exporters write it): the world is not mirrored.
const CAMERA: &str =
    "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n";

#[test]
fn a_lookat_camera_mirrors_the_world_as_pbrt_sees_it() {
    // pbrt's LookAt puts world +x on the left of this image; Appel's camera has +x on the
    // right, so the sphere moves to x = -1.
    let s = load(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
         Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n\
         WorldBegin\nTranslate 1 0 0\nShape \"sphere\" \"float radius\" 0.5\n",
    )
    .unwrap();
    let d = &s.description;
    assert_eq!((d.camera.width, d.camera.height), (200, 100));
    assert_eq!(d.camera.fov, 30.0);
    assert_eq!(d.camera.fov_axis, FovAxis::Smaller);
    let ShapeDesc::Sphere(sphere) = &d.shapes[0] else {
        panic!("{:?}", d.shapes)
    };
    assert!((sphere.center[0] + 1.0).abs() < 1e-6, "{sphere:?}");
    assert_eq!(sphere.radius, 0.5);
    // With a right-handed camera frame nothing is mirrored.
    let s = load(&format!(
        "{CAMERA}WorldBegin\nTranslate 1 0 0\nShape \"sphere\"\n"
    ))
    .unwrap();
    let ShapeDesc::Sphere(sphere) = &s.description.shapes[0] else {
        panic!()
    };
    assert!((sphere.center[0] - 1.0).abs() < 1e-6, "{sphere:?}");
}

#[test]
fn maxdepth_counts_bounces() {
    let s = load(&format!(
        "Integrator \"path\" \"integer maxdepth\" 3\n{CAMERA}WorldBegin\n"
    ))
    .unwrap();
    assert_eq!(s.description.render.max_depth, 4);
    assert_eq!(s.description.render.integrator, IntegratorName::Path);
    // pbrt's default: volpath with maxdepth 5; its default sampler takes 16 samples.
    let s = load(&format!("{CAMERA}WorldBegin\n")).unwrap();
    assert_eq!(s.description.render.max_depth, 6);
    assert_eq!(s.description.render.spp, 16);
}

/// pbrt's bdpt and lightpath are Appel's bdpt and ptracer; other integrators that estimate the
/// same light transport are path traced with a warning at their line, keeping their depth; one
/// that computes something else is an error.
#[test]
fn other_estimators_of_the_same_light_are_path_traced() {
    for (name, appel) in [
        ("bdpt", IntegratorName::Bdpt),
        ("lightpath", IntegratorName::Ptracer),
    ] {
        let s = load(&format!(
            "Integrator \"{name}\" \"integer maxdepth\" 7\n{CAMERA}WorldBegin\n"
        ))
        .unwrap();
        assert_eq!(s.description.render.integrator, appel);
        assert_eq!(s.description.render.max_depth, 8);
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    }
    let images = |params: &str| {
        load(&format!(
            "Integrator \"bdpt\" {params}\n{CAMERA}WorldBegin\n"
        ))
        .unwrap()
        .description
        .render
        .bdpt
        .and_then(|b| b.strategy_images)
    };
    assert_eq!(images(""), None);
    assert_eq!(
        images("\"bool visualizeweights\" true"),
        Some(crate::description::StrategyImages::Weighted)
    );
    assert_eq!(
        images("\"bool visualizestrategies\" true"),
        Some(crate::description::StrategyImages::Unweighted)
    );
    let e = err(&format!(
        "Integrator \"bdpt\" \"bool visualizestrategies\" true\n  \"bool visualizeweights\" true\n{CAMERA}WorldBegin\n"
    ));
    assert!(e.contains(":2:") && e.contains("choose one"), "{e}");
    let regularize = |integrator: &str| {
        load(&format!(
            "Integrator \"{integrator}\" \"bool regularize\" true\n{CAMERA}WorldBegin\n"
        ))
    };
    let bdpt = regularize("bdpt").unwrap().description.render.bdpt;
    assert!(bdpt.is_some_and(|b| b.regularize));
    let e = regularize("path").unwrap_err().to_string();
    assert!(e.contains("supported by bdpt only"), "{e}");
    let s = load(&format!(
        "Integrator \"sppm\" \"integer maxdepth\" 7 \"float radius\" 0.01 \
         \"integer photonsperiteration\" 5000 \"integer seed\" 3\n{CAMERA}WorldBegin\n"
    ))
    .unwrap();
    assert_eq!(s.description.render.integrator, IntegratorName::Sppm);
    assert_eq!(s.description.render.max_depth, 8);
    let sppm = s.description.render.sppm.unwrap();
    assert_eq!((sppm.radius, sppm.photons_per_iteration), (0.01, 5000));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let e = err(&format!(
        "Integrator \"sppm\"\n  \"float radius\" -1\n{CAMERA}WorldBegin\n"
    ));
    assert!(
        e.contains("a.pbrt:2:3") && e.contains("radius must be positive"),
        "{e}"
    );
    for name in ["mlt", "simplepath"] {
        let s = load(&format!(
            "Integrator \"{name}\" \"integer maxdepth\" 7\n{CAMERA}WorldBegin\n"
        ))
        .unwrap();
        assert_eq!(s.description.render.integrator, IntegratorName::Path);
        assert_eq!(s.description.render.max_depth, 8);
        assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
        assert!(
            s.warnings[0].contains("a.pbrt:1:1") && s.warnings[0].contains(name),
            "{:?}",
            s.warnings
        );
    }
    let e = err(&format!(
        "Integrator \"ambientocclusion\"\n{CAMERA}WorldBegin\n"
    ));
    assert!(
        e.contains("a.pbrt:1:1") && e.contains("unsupported integrator \"ambientocclusion\""),
        "{e}"
    );
}

#[test]
fn errors_name_the_file_and_line() {
    let e = err(&format!("{CAMERA}WorldBegin\nFoo 1 2\n"));
    assert!(e.contains("a.pbrt:5:1") && e.contains("Foo"), "{e}");
    let e = err(&format!(
        "{CAMERA}WorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"cloud\"\n"
    ));
    assert!(
        e.contains("a.pbrt:5:") && e.contains("unsupported medium \"cloud\""),
        "{e}"
    );
    let e = err(&format!(
        "{CAMERA}WorldBegin\nMediumInterface \"fog\" \"\"\n"
    ));
    assert!(
        e.contains("a.pbrt:5:1") && e.contains("no medium is named \"fog\""),
        "{e}"
    );
    let e = err(&format!("{CAMERA}WorldBegin\nShape \"cylinder\"\n"));
    assert!(e.contains("unsupported shape \"cylinder\""), "{e}");
    let e = err(&format!("{CAMERA}WorldBegin\nInclude \"nowhere.pbrt\"\n"));
    assert!(
        e.contains("a.pbrt:5:1") && e.contains("nowhere.pbrt"),
        "{e}"
    );
    let e = err(&format!("{CAMERA}WorldBegin\nAttributeBegin\n"));
    assert!(e.contains("AttributeBegin has no AttributeEnd"), "{e}");
    let e = err(&format!(
        "{CAMERA}WorldBegin\nShape \"plymesh\" \"string filename\" \"gone.ply\"\n"
    ));
    assert!(e.contains("gone.ply") && e.contains("a.pbrt:5:1"), "{e}");
}

#[test]
fn unused_parameters_are_warnings() {
    let s = load(&format!(
        "{CAMERA}WorldBegin\nShape \"sphere\" \"float radius\" 2\n  \"float bogus\" 3\n"
    ))
    .unwrap();
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("a.pbrt:6:3") && s.warnings[0].contains("bogus"));
}

#[test]
fn opaque_materials_are_two_sided_and_roughness_is_remapped() {
    let s = load(&format!(
        "{CAMERA}WorldBegin\n\
         MakeNamedMaterial \"metal\" \"string type\" \"conductor\" \"float roughness\" 0.04\n\
         MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"float eta\" 1.33\n\
         NamedMaterial \"metal\"\nShape \"sphere\"\nNamedMaterial \"glass\"\nShape \"sphere\"\n"
    ))
    .unwrap();
    let m = &s.description.materials;
    assert_eq!(
        m["metal"],
        MaterialDesc::TwoSided(TwoSidedDesc {
            front: "metal.bsdf".into(),
            back: None
        })
    );
    let MaterialDesc::RoughConductor(c) = &m["metal.bsdf"] else {
        panic!("{m:?}")
    };
    // remaproughness (default true): alpha = sqrt(roughness).
    assert_eq!(c.alpha, Some(TextureDesc::Value(0.2)));
    assert_eq!(c.distribution, DistributionDesc::Ggx);
    let MaterialDesc::Dielectric(g) = &m["glass"] else {
        panic!("{m:?}")
    };
    assert_eq!(g.int_ior, IorDesc::Value(1.33));
    assert_eq!(s.description.shapes[1].material(), Some("glass"));
}

#[test]
fn attributes_scope_the_material_and_area_light() {
    let s = load(&format!(
        "{CAMERA}WorldBegin\nAttributeBegin\nMaterial \"dielectric\"\n\
         AreaLightSource \"diffuse\" \"rgb L\" [ 4 2 1 ] \"float scale\" 2\nShape \"sphere\"\n\
         AttributeEnd\nShape \"sphere\"\n"
    ))
    .unwrap();
    let shapes = &s.description.shapes;
    let e = shapes[0].emitter().expect("emits");
    assert_eq!(e.radiance, TextureDesc::Rgb([8.0, 4.0, 2.0]));
    assert!(shapes[1].emitter().is_none());
    assert_eq!(shapes[1].material(), Some("pbrt-default-diffuse"));
}

#[test]
fn reverse_orientation_turns_triangles_around() {
    let tri =
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n";
    let s = load(&format!(
        "{CAMERA}WorldBegin\n{tri}AttributeBegin\nReverseOrientation\n{tri}AttributeEnd\n"
    ))
    .unwrap();
    let idx = |i: usize| match &s.description.shapes[i] {
        ShapeDesc::TriangleMesh(t) => t.indices[0],
        other => panic!("{other:?}"),
    };
    assert_eq!(idx(0), [0, 1, 2]);
    assert_eq!(idx(1), [0, 2, 1]);
}

#[test]
fn object_instances_place_their_shapes() {
    let s = load(&format!(
        "{CAMERA}WorldBegin\nObjectBegin \"ball\"\nTranslate 0 1 0\nShape \"sphere\"\nObjectEnd\n\
         Translate 5 0 0\nObjectInstance \"ball\"\nTranslate 5 0 0\nObjectInstance \"ball\"\n"
    ))
    .unwrap();
    let centers: Vec<[f32; 3]> = s
        .description
        .shapes
        .iter()
        .map(|s| match s {
            ShapeDesc::Sphere(x) => x.center,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(centers, vec![[5.0, 1.0, 0.0], [10.0, 1.0, 0.0]]);
}

#[test]
fn checkerboards_map_pbrts_squares() {
    let s = load(&format!(
        "{CAMERA}WorldBegin\nTexture \"c\" \"spectrum\" \"checkerboard\" \"float uscale\" 4\n\
         \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1]\n\
         Material \"diffuse\" \"texture reflectance\" \"c\"\nShape \"sphere\"\n"
    ))
    .unwrap();
    let m = s.description.materials.values().find_map(|m| match m {
        MaterialDesc::Diffuse(d) => Some(d.reflectance.clone()),
        _ => None,
    });
    assert_eq!(
        m,
        Some(TextureDesc::Texture(TextureNode::Checkerboard {
            color0: [1.0, 0.0, 0.0],
            color1: [0.0, 0.0, 1.0],
            to_uv: Some([[2.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 1.0]]),
        }))
    );
}

#[test]
fn object_meshes_become_appel_instances() {
    let s = load(&format!(
        "{CAMERA}WorldBegin\nObjectBegin \"tri\"\nMaterial \"conductor\"\n\
         Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\nObjectEnd\n\
         Translate 5 0 0\nObjectInstance \"tri\"\nScale 2 2 2\nObjectInstance \"tri\"\n"
    ))
    .unwrap();
    let d = &s.description;
    assert!(d.shapes.is_empty(), "{:?}", d.shapes);
    let mesh = &d.meshes["object tri"];
    assert!(mesh.file.is_empty());
    assert_eq!(mesh.triangles.len(), 1);
    assert_eq!(mesh.triangles[0].positions[1], [1.0, 0.0, 0.0]);
    assert!(mesh.triangles[0].material.is_some());
    let placed: Vec<[[f32; 4]; 4]> = d
        .instances
        .iter()
        .map(|i| i.transform.as_ref().unwrap().matrix.unwrap())
        .collect();
    assert_eq!(
        placed,
        vec![
            [
                [1.0, 0.0, 0.0, 5.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0]
            ],
            [
                [2.0, 0.0, 0.0, 5.0],
                [0.0, 2.0, 0.0, 0.0],
                [0.0, 0.0, 2.0, 0.0],
                [0.0, 0.0, 0.0, 1.0]
            ],
        ]
    );
    crate::description::validate::validate(d).unwrap();
}

/// Problems that only the validation of the converted description finds are reported at the
/// line of the parameter that gave the value, or of the directive that made the entry.
#[test]
fn validation_errors_point_at_the_directive() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    for (options, expected) in [
        (
            "Sampler \"halton\"\n  \"integer pixelsamples\" 100000\n",
            "a.pbrt:5:3: in the converted scene, render.spp: `spp` must be between 1 and 65536, got 100000",
        ),
        (
            "Integrator \"path\"\n  \"integer maxdepth\" 5000\n",
            "a.pbrt:5:3: in the converted scene, render.max_depth: `max_depth` must be between",
        ),
    ] {
        let dir = std::env::temp_dir().join(format!(
            "appel-pbrt-valid-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.pbrt");
        std::fs::write(&path, format!("{CAMERA}{options}WorldBegin\nShape \"sphere\"\n")).unwrap();
        let e = crate::format::load(&path, &Default::default())
            .map(|_| ())
            .unwrap_err()
            .to_string();
        let e = e.replace(&format!("{}/", dir.display()), "");
        assert!(e.starts_with(expected), "{e}");
    }
}

/// An `infinite` light with an image is the equal-area environment map of that file, in the
/// light's frame (the CTM, mirrored as the world is); a missing image is named.
#[test]
fn an_infinite_light_image_is_an_equal_area_map() {
    let scene = format!(
        "{CAMERA}WorldBegin\nAttributeBegin\nRotate -90 1 0 0\n\
         LightSource \"infinite\" \"string filename\" \"sky.pfm\" \"float scale\" [ 2 ]\nAttributeEnd\n"
    );
    // The image must exist where the scene file is: written beside the file `load` makes.
    let e = err(&scene);
    assert!(
        e.contains("\"sky.pfm\" is missing") && e.contains("a.pbrt:"),
        "{e}"
    );
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("sky.pfm"),
        b"PF\n1 1\n-1\n\0\0\x80?\0\0\x80?\0\0\x80?",
    )
    .unwrap();
    let path = dir.path().join("s.pbrt");
    std::fs::write(&path, &scene).unwrap();
    let s = load_pbrt(&path).unwrap_or_else(|e| panic!("{e}"));
    let [LightDesc::EqualAreaEnvMap(l)] = &s.description.lights[..] else {
        panic!("{:?}", s.description.lights);
    };
    assert!(l.file.ends_with("sky.pfm") && l.scale == 2.0, "{l:?}");
    // Rotate -90 about x takes the light's +z (the image's centre) to the world's +y.
    let m = l.transform.as_ref().unwrap().matrix();
    let up = m.transform_vector3(glam::Vec3::Z);
    assert!((up - glam::Vec3::Y).length() < 1e-5, "{up}");
}

/// pbrt-v4's thin lens: `lensradius` and `focaldistance` (default 10^6) become the camera's
/// aperture and focus distance; without a lens there is no focus distance to keep; bad values
/// fail at their parameter's line.
#[test]
fn lens_parameters_make_a_thin_lens() {
    let camera = |params: &str| {
        format!(
            "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
             {params}\nWorldBegin\n"
        )
    };
    let d = load(&camera(
        "\"float lensradius\" 0.1 \"float focaldistance\" 4",
    ))
    .unwrap()
    .description;
    assert_eq!(
        (d.camera.aperture_radius, d.camera.focus_distance),
        (0.1, Some(4.0))
    );
    let d = load(&camera("\"float lensradius\" 0.2"))
        .unwrap()
        .description;
    assert_eq!(
        (d.camera.aperture_radius, d.camera.focus_distance),
        (0.2, Some(1e6))
    );
    let s = load(&camera("\"float focaldistance\" 3")).unwrap();
    assert_eq!(
        (
            s.description.camera.aperture_radius,
            s.description.camera.focus_distance
        ),
        (0.0, None)
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // A uniform scale in the camera transform scales the lens with the scene, as in pbrt.
    let d = load(
        "Scale -2 2 2\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float lensradius\" 0.1 \
         \"float focaldistance\" 4\nWorldBegin\n",
    )
    .unwrap()
    .description;
    let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
    assert!(close(d.camera.aperture_radius, 0.05), "{:?}", d.camera);
    assert!(
        close(d.camera.focus_distance.unwrap(), 2.0),
        "{:?}",
        d.camera
    );
    // The orthographic camera has the same lens.
    let d = load(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float lensradius\" \
         0.5 \"float focaldistance\" 2\nWorldBegin\n",
    )
    .unwrap()
    .description;
    assert_eq!(d.camera.kind, CameraKind::Orthographic);
    assert_eq!(
        (d.camera.aperture_radius, d.camera.focus_distance),
        (0.5, Some(2.0))
    );
    for (params, expected) in [
        (
            "\"float lensradius\" -0.1",
            "a.pbrt:4:1: \"lensradius\" must be 0 (a pinhole) or positive, got -0.1",
        ),
        (
            "\"float lensradius\" 0.1 \"float focaldistance\" 0",
            "a.pbrt:4:24: \"focaldistance\" must be a positive distance, got 0",
        ),
        (
            "\"float focaldistance\" -2",
            "a.pbrt:4:1: \"focaldistance\" must be a positive distance, got -2",
        ),
    ] {
        let e = err(&camera(params));
        assert!(e.ends_with(expected), "expected {expected}\n     got {e}");
    }
}

/// pbrt-v4's media: a homogeneous medium inside an `interface` sphere and around the camera,
/// the default integrator rendering them, and a uniform grid as a three-channel grid of
/// extinction over its box.
#[test]
fn media_and_their_interfaces() {
    let s = load(&format!(
        "MakeNamedMedium \"air\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.01 0.02 0.03] \
         \"rgb sigma_s\" [0.1 0.1 0.1]\nMediumInterface \"\" \"air\"\n{CAMERA}WorldBegin\n\
         MakeNamedMedium \"ink\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 2 3] \
         \"rgb sigma_s\" [1 0 1] \"float scale\" 2 \"float g\" 0.5\n\
         AttributeBegin\nMaterial \"interface\"\nMediumInterface \"ink\" \"air\"\n\
         Shape \"sphere\" \"float radius\" 1\nAttributeEnd\n\
         AttributeBegin\nMaterial \"interface\"\nMediumInterface \"air\"\nShape \"sphere\" \"float radius\" 3\n\
         AttributeEnd\nAttributeBegin\nMaterial \"interface\"\nShape \"sphere\" \"float radius\" 5\nAttributeEnd\n\
         MakeNamedMedium \"smoke\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"integer ny\" 1 \
         \"integer nz\" 1 \"float density\" [0.5 1] \"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 1 1] \
         \"rgb sigma_a\" [0 0 0] \"rgb sigma_s\" [1 2 4]\n"
    ))
    .unwrap();
    let d = &s.description;
    assert_eq!(d.render.integrator, IntegratorName::VolPath);
    assert_eq!(d.camera.medium.as_deref(), Some("air"));
    // The interface sphere whose two sides are the same medium bounds nothing: it is dropped.
    // AttributeEnd restores the state before it (vacuum inside, air outside).
    assert_eq!(d.shapes.len(), 2);
    let ShapeDesc::Sphere(outer) = &d.shapes[1] else {
        panic!("{:?}", d.shapes)
    };
    assert_eq!((outer.radius, outer.interior.as_deref()), (5.0, None));
    assert_eq!(outer.exterior.as_deref(), Some("air"));
    let ShapeDesc::Sphere(sphere) = &d.shapes[0] else {
        panic!("{:?}", d.shapes)
    };
    assert_eq!(sphere.interior.as_deref(), Some("ink"));
    assert_eq!(sphere.exterior.as_deref(), Some("air"));
    assert!(matches!(
        d.materials[sphere.material.as_deref().unwrap()],
        MaterialDesc::Null(_)
    ));
    let MediumDesc::Homogeneous(ink) = &d.media["ink"] else {
        panic!()
    };
    let (sigma_t, albedo) = ink.sigma_t_albedo();
    assert_eq!(sigma_t, [2.0, 2.0, 4.0]);
    assert_eq!(albedo, VolumeDesc::Rgb([0.5, 0.0, 0.25]));
    assert_eq!(
        (ink.scale, &ink.phase),
        (2.0, &PhaseDesc::Hg(HgDesc { g: 0.5 }))
    );
    let MediumDesc::Heterogeneous(smoke) = &d.media["smoke"] else {
        panic!()
    };
    let VolumeDesc::Volume(VolumeNode::Values {
        resolution,
        channels,
        values,
        transform,
    }) = smoke.sigma_t.as_deref().unwrap()
    else {
        panic!("{:?}", smoke.sigma_t)
    };
    assert_eq!((*resolution, *channels), ([2, 1, 1], 3));
    assert_eq!(values, &vec![0.5, 1.0, 2.0, 1.0, 2.0, 4.0]);
    // The unit cube onto the box [-1, 1]^3 (the camera's frame keeps the world unmirrored).
    let m = transform.as_ref().unwrap().matrix();
    assert!((m.transform_point3(glam::Vec3::ZERO) - glam::Vec3::splat(-1.0)).length() < 1e-6);
    assert!((m.transform_point3(glam::Vec3::ONE) - glam::Vec3::ONE).length() < 1e-6);
    assert_eq!(
        smoke.albedo.as_deref(),
        Some(&VolumeDesc::Rgb([1.0, 1.0, 1.0]))
    );
}

/// pbrt-v4's `rgbgrid`: absorption and scattering as RGB grids of their own over one box (an
/// absent one is 1 everywhere), both times `scale`; its mistakes are errors at their line.
#[test]
fn rgb_grid_media() {
    let s = load(&format!(
        "{CAMERA}WorldBegin\n\
         MakeNamedMedium \"smoke\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"float scale\" 3\n\
         \"rgb sigma_a\" [0.1 0.2 0.3  0.4 0.5 0.6] \"rgb sigma_s\" [1 2 3  4 5 6] \"float g\" -0.3\n\
         \"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 1 1]\n\
         MakeNamedMedium \"mist\" \"string type\" \"rgbgrid\" \"rgb sigma_s\" [0.5 0.25 0]\n"
    ))
    .unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let MediumDesc::Heterogeneous(smoke) = &d.media["smoke"] else {
        panic!()
    };
    assert_eq!(
        (smoke.sigma_t.as_ref(), smoke.albedo.as_ref()),
        (None, None)
    );
    assert_eq!(
        (smoke.scale, &smoke.phase),
        (3.0, &PhaseDesc::Hg(HgDesc { g: -0.3 }))
    );
    let grid = |v: &Option<Box<VolumeDesc>>| match v.as_deref().unwrap() {
        VolumeDesc::Volume(VolumeNode::Values {
            resolution,
            channels,
            values,
            transform,
        }) => (
            *resolution,
            *channels,
            values.clone(),
            transform.clone().unwrap(),
        ),
        other => panic!("{other:?}"),
    };
    let (res_a, ch_a, a, ta) = grid(&smoke.sigma_a);
    let (res_s, ch_s, sv, ts) = grid(&smoke.sigma_s);
    assert_eq!((res_a, ch_a, res_s, ch_s), ([2, 1, 1], 3, [2, 1, 1], 3));
    assert_eq!(a, vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6]);
    assert_eq!(sv, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert_eq!(ta, ts);
    let m = ta.matrix();
    assert!((m.transform_point3(glam::Vec3::ZERO) - glam::Vec3::splat(-1.0)).length() < 1e-6);
    assert!((m.transform_point3(glam::Vec3::ONE) - glam::Vec3::ONE).length() < 1e-6);
    let MediumDesc::Heterogeneous(mist) = &d.media["mist"] else {
        panic!()
    };
    assert_eq!(mist.sigma_a.as_deref(), Some(&VolumeDesc::Value(1.0)));
    assert_eq!(grid(&mist.sigma_s).2, vec![0.5, 0.25, 0.0]);

    let medium = |params: &str| {
        err(&format!(
            "{CAMERA}WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"rgbgrid\"\n{params}\n"
        ))
    };
    let e = medium("\"integer nx\" 2 \"integer ny\" 2\n  \"rgb sigma_a\" [1 1 1  1 1 1  1 1 1]");
    assert!(
        e.contains("a.pbrt:7:3") && e.contains("2 x 2 x 1 cells need 4 rgb values"),
        "{e}"
    );
    let e = medium("\"rgb sigma_a\" [1 1 1] \"float sigma_s\" 2");
    assert!(
        e.contains("a.pbrt:6:") && e.contains("\"sigma_s\" must be rgb"),
        "{e}"
    );
    let e = medium("\"float g\" 0.2");
    assert!(
        e.contains("a.pbrt:5:1") && e.contains("needs \"rgb sigma_a\" or \"rgb sigma_s\""),
        "{e}"
    );
    let e = medium("\"rgb sigma_s\" [1 1 1] \"rgb Le\" [1 1 1]");
    assert!(
        e.contains("a.pbrt:6:") && e.contains("emitting media are not supported"),
        "{e}"
    );
    let e = medium("\"rgb sigma_s\" [1 -1 1]");
    assert!(
        e.contains("a.pbrt:6:") && e.contains("must not be negative"),
        "{e}"
    );
    // A parameter rgbgrid does not know is reported at its line, as pbrt reports unused ones.
    let s = load(&format!(
        "{CAMERA}WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb sigma_s\" [1 1 1]\n\
         \"float density\" [1]\n"
    ))
    .unwrap();
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(
        s.warnings[0].contains("a.pbrt:6:1") && s.warnings[0].contains("density"),
        "{:?}",
        s.warnings
    );
}
