//! pbrt-v4 scene files from the Bitterli collection, rendered from their own `.pbrt` files and
//! compared with Tungsten's reference renders beside them (see `reference/mod.rs` for the
//! statistics), and a scene whose geometry is missing.

#[allow(dead_code)] // the shared helpers include the XML readers this file does not use
mod reference;

use appel::description::Description;
use appel::description::{DistributionDesc, FilterDesc, MaterialDesc, TextureDesc};
use appel::scene::IntegratorKind;
use reference::{
    compare_within, reference, render_loaded, save_side_by_side, shared, tent_blur_allowance,
    Comparison, Setup,
};

/// Renders `scene` at `w x h` (a whole fraction of the reference's resolution) with a box
/// filter, `spp` samples and pbrt's `maxdepth` set to `depth` (the scenes' originals: the copies
/// in shared/data were edited down for speed), changed by `as_rendered` where the reference was
/// rendered from something the pbrt file does not say, and compares the whole image with the
/// reference averaged to the same size. `unresolved` names the reference's values the render
/// cannot be expected to resolve at this sample count (see [`isolated_highlights`]): each may be
/// off by up to that much before the z-test counts the rest.
fn compare_with_reference(
    scene: &str,
    reference_exr: &str,
    (w, h): (u32, u32),
    spp: u32,
    depth: i32,
    as_rendered: impl FnOnce(&mut Description),
    unresolved: Unresolved,
) -> (Comparison, Comparison) {
    let (scene, ref_path) = (shared(scene), shared(reference_exr));
    let loaded = appel::format::load(&scene, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let film = render_loaded(loaded, &Setup { spp, block: 1 }, |d| {
        (d.camera.width, d.camera.height) = (w, h);
        d.render.filter = FilterDesc::Box { radius: 0.5 };
        // pbrt's maxdepth counts bounces, Appel's max_depth path vertices.
        d.render.max_depth = depth + 1;
        as_rendered(d);
    });
    let r = reference(&ref_path, w, h);
    let ref_width = appel::io::bitmap_read::read_bitmap(&ref_path, true)
        .unwrap()
        .width;
    let with_unresolved = |r: &[[f32; 3]]| -> Vec<[f32; 3]> {
        let blur = tent_blur_allowance(r, w as usize, ref_width / w);
        let extra = unresolved(r, w as usize);
        blur.iter()
            .zip(&extra)
            .map(|(a, b)| std::array::from_fn(|c| a[c] + b[c]))
            .collect()
    };
    let c = compare_within(&film, &r, &with_unresolved(&r));
    save_side_by_side(
        &scene
            .parent()
            .unwrap()
            .parent()
            .unwrap()
            .file_name()
            .unwrap()
            .to_string_lossy(),
        &film,
        &r,
    );
    eprintln!("{}: {c:?}", scene.display());
    // The same render against a reference made 3% darker, which must fail.
    let darker: Vec<[f32; 3]> = r.iter().map(|p| p.map(|c| c * 0.97)).collect();
    let c_darker = compare_within(&film, &darker, &with_unresolved(&darker));
    (c, c_darker)
}

/// The allowance for the values of a reference (of the given width) that a render cannot resolve.
type Unresolved = fn(&[[f32; 3]], usize) -> Vec<[f32; 3]>;

/// Every value is resolved.
fn none_unresolved(reference: &[[f32; 3]], _: usize) -> Vec<[f32; 3]> {
    vec![[0.0; 3]; reference.len()]
}

/// The reference's isolated highlights: values more than four times every 4-neighbour's (a
/// light seen through glass, a small fraction of the pixel). A pixel sample finds such a highlight with
/// the chance of its share of the pixel's area, so at a few dozen samples per pixel a render
/// either misses it or hits it a few times, and the pixel's own variance says nothing of how
/// far off that is: such a value may be off by all of it.
fn isolated_highlights(reference: &[[f32; 3]], w: usize) -> Vec<[f32; 3]> {
    let h = reference.len() / w;
    (0..reference.len())
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let neighbours = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then_some(i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then_some(i + w),
            ];
            std::array::from_fn(|c| {
                let brightest = neighbours
                    .iter()
                    .flatten()
                    .map(|&j| reference[j][c])
                    .fold(0.0f32, f32::max);
                if reference[i][c] > 4.0 * brightest {
                    reference[i][c]
                } else {
                    0.0
                }
            })
        })
        .collect()
}

/// [`compare_with_reference`], asserting that the render matches and that the comparison can
/// fail.
fn check(
    scene: &str,
    reference_exr: &str,
    size: (u32, u32),
    spp: u32,
    depth: i32,
    as_rendered: impl FnOnce(&mut Description),
) {
    check_with(
        scene,
        reference_exr,
        size,
        spp,
        depth,
        as_rendered,
        none_unresolved,
    )
}

/// [`check`] with values of the reference the render cannot resolve.
fn check_with(
    scene: &str,
    reference_exr: &str,
    size: (u32, u32),
    spp: u32,
    depth: i32,
    as_rendered: impl FnOnce(&mut Description),
    unresolved: Unresolved,
) {
    let (c, c_darker) = compare_with_reference(
        scene,
        reference_exr,
        size,
        spp,
        depth,
        as_rendered,
        unresolved,
    );
    assert!(c.passes(), "{scene}: {c:?}");
    assert!(!c_darker.passes(), "a 3% bias passed: {c_darker:?}");
}

/// The Cornell box from its pbrt file (trianglemesh walls and boxes, a one-sided area light,
/// named diffuse materials) against Tungsten at 64 x 64.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn cornell_box_pbrt_against_tungsten() {
    check(
        "bitterli-scenes/cornell-box/pbrt/scene-v4.pbrt",
        "bitterli-scenes/cornell-box/pbrt/TungstenRender.exr",
        (64, 64),
        128,
        65,
        |_| {},
    );
}

/// Bitterli's volumetric caustic: a glass ball in a box of scattering gas, lit by a tiny area
/// light, rendered by `volpath` (the file's integrator) against Tungsten at 64 x 64. Tungsten's
/// scene (`scene.json` of Tungsten's example scenes) renders with `max_bounces` 6, which in
/// Tungsten counts the vertices after the camera as Appel's `max_depth` does: pbrt's `maxdepth`
/// 5. The pbrt export says 7, and its two extra bounces of multiple scattering brighten the
/// image by 16-24% (what `volumetric_caustic_as_the_file_says_is_not_tungsten_s_image` checks).
///
/// Only the image means are compared: the focused caustic on the floor (light -> glass ball ->
/// floor) reaches the camera only through paths that hit the 0.005-unit light by chance, which
/// a unidirectional tracer finds too rarely at this sample count (Tungsten rendered it
/// bidirectionally), so those pixels are far too dark.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn volumetric_caustic_pbrt_against_tungsten() {
    let (c, _) = compare_with_reference(
        "bitterli-scenes/volumetric-caustic/pbrt/scene-v4.pbrt",
        "bitterli-scenes/volumetric-caustic/pbrt/TungstenRender.exr",
        (64, 64),
        256,
        5,
        |_| {},
        none_unresolved,
    );
    let means_agree =
        |c: &Comparison| (0..3).all(|i| (c.mean_ratio[i] - 1.0).abs() <= c.ratio_tolerance[i]);
    assert!(means_agree(&c), "{c:?}");
    // Tight enough that a bias of the size of one extra bounce (14%) cannot pass.
    assert!(c.ratio_tolerance.iter().all(|&t| t < 0.05), "{c:?}");
}

/// The file's `maxdepth` 7 is not how Tungsten rendered the scene: its image is brighter than
/// Tungsten's beyond the comparison's tolerance.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn volumetric_caustic_as_the_file_says_is_not_tungsten_s_image() {
    let (c, _) = compare_with_reference(
        "bitterli-scenes/volumetric-caustic/pbrt/scene-v4.pbrt",
        "bitterli-scenes/volumetric-caustic/pbrt/TungstenRender.exr",
        (32, 32),
        128,
        7,
        |_| {},
        none_unresolved,
    );
    assert!(!c.passes(), "{c:?}");
    assert!(c.mean_ratio.iter().all(|&r| r > 1.05), "{c:?}");
}

/// The Cornell box rendered by `bdpt` (as the file's `path`, Tungsten's integrator) against
/// Tungsten at 64 x 64.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn cornell_box_pbrt_bdpt_against_tungsten() {
    check(
        "bitterli-scenes/cornell-box/pbrt/scene-v4.pbrt",
        "bitterli-scenes/cornell-box/pbrt/TungstenRender.exr",
        (64, 64),
        64,
        65,
        |d| d.render.integrator = IntegratorKind::Bdpt,
    );
}

/// Veach's bidirectional test scene (a floor lamp lights the room by way of the ceiling, a wall
/// lamp's small bright light sits in a rough conductor shade, a glass egg on the table) by the
/// file's own `bdpt`, `maxdepth 7`, against Tungsten at 64 x 64, except the egg's highlight (the
/// wall lamp's light seen through the egg, about 0.1% of a 128 x 128 pixel:
/// [`isolated_highlights`]).
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn veach_bidir_pbrt_bdpt_against_tungsten() {
    check_with(
        "bitterli-scenes/veach-bidir/pbrt/scene-v4.pbrt",
        "bitterli-scenes/veach-bidir/pbrt/TungstenRender.exr",
        (64, 64),
        64,
        7,
        |d| assert_eq!(d.render.integrator, IntegratorKind::Bdpt),
        isolated_highlights,
    );
}

/// How Tungsten rendered Veach's MIS scene, where the pbrt-v4 export lost it: in Tungsten's
/// scene the four plates are `rough_conductor` with `albedo` 0.3 (a factor on the reflectance)
/// and the `beckmann` distribution (the roughnesses are Beckmann alphas), and the path tracer's
/// `max_bounces` is 2, which in Tungsten is direct lighting only (it samples the lights at the
/// first `max_bounces - 1` surfaces): pbrt's `maxdepth` 1. The file's plates are pbrt-v4's only
/// microfacet model, Trowbridge-Reitz, with no such factor, and its `maxdepth` is 3.
#[derive(Clone, Copy)]
struct VeachMisAsRendered {
    plate_albedo: f32,
    distribution: DistributionDesc,
    maxdepth: i32,
}

const TUNGSTEN_VEACH_MIS: VeachMisAsRendered = VeachMisAsRendered {
    plate_albedo: 0.3,
    distribution: DistributionDesc::Beckmann,
    maxdepth: 1,
};

fn veach_mis(as_rendered: VeachMisAsRendered) -> (Comparison, Comparison) {
    compare_with_reference(
        "bitterli-scenes/veach-mis/pbrt/scene-v4.pbrt",
        "bitterli-scenes/veach-mis/pbrt/TungstenRender.exr",
        (160, 90),
        64,
        as_rendered.maxdepth,
        |d| {
            let mut plates = 0;
            for m in d.materials.values_mut() {
                if let MaterialDesc::RoughConductor(c) = m {
                    c.specular_reflectance = TextureDesc::Value(as_rendered.plate_albedo);
                    c.distribution = as_rendered.distribution;
                    plates += 1;
                }
            }
            assert_eq!(plates, 4, "the scene's four rough conductor plates");
        },
        none_unresolved,
    )
}

/// Veach's multiple importance sampling test: four rough conductor plates reflecting three
/// spherical lights of very different sizes and radiances, against Tungsten at 160 x 90, the
/// whole image, with the plates and the path depth as Tungsten rendered them
/// ([`TUNGSTEN_VEACH_MIS`]). Everything else is the pbrt file read with pbrt-v4's meaning: the
/// camera's `Transform` (a mirror image), the `N` normals and orientation of the meshes, the
/// conductors' `rgb` eta and k, the spheres' emission and the black `diffuse` behind it.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn veach_mis_pbrt_against_tungsten() {
    let (c, c_darker) = veach_mis(TUNGSTEN_VEACH_MIS);
    assert!(c.passes(), "{c:?}");
    assert!(!c_darker.passes(), "a 3% bias passed: {c_darker:?}");
}

/// Each of the three things the export lost shows in the image: with any one of them as the
/// pbrt file has it, the comparison fails (the plates at full reflectance are 1.4 to 1.6 times
/// as bright over the whole image; GGX's longer tails widen the highlights; a second bounce
/// lights the floor in the plates' shadow, which is black in Tungsten's image).
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn veach_mis_as_the_file_says_is_not_tungsten_s_image() {
    let variants = [
        VeachMisAsRendered {
            plate_albedo: 1.0,
            ..TUNGSTEN_VEACH_MIS
        },
        VeachMisAsRendered {
            distribution: DistributionDesc::Ggx,
            ..TUNGSTEN_VEACH_MIS
        },
        VeachMisAsRendered {
            maxdepth: 3,
            ..TUNGSTEN_VEACH_MIS
        },
    ];
    for v in variants {
        let (c, _) = veach_mis(v);
        assert!(
            !c.passes(),
            "albedo {}, {:?}, maxdepth {}: {c:?}",
            v.plate_albedo,
            v.distribution,
            v.maxdepth
        );
    }
}

/// The killeroo scenes include geometry files that are not in shared/data: the error names the
/// missing file and the line of the `Include`.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn a_missing_geometry_file_is_named() {
    let scene = shared("pbrt-v4-killeroos/killeroos/killeroo-simple.pbrt");
    let e = appel::format::load(&scene, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("geometry/killeroo.pbrt"), "{e}");
    assert!(e.contains("killeroo-simple.pbrt:55:"), "{e}");
    let gold = shared("pbrt-v4-killeroos/killeroos/killeroo-coated-gold.pbrt");
    // This one fails earlier, at its texture, which is missing too.
    let e = appel::format::load(&gold, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("textures/lines.png"), "{e}");
    assert!(e.contains("killeroo-coated-gold.pbrt:42:"), "{e}");
}

/// pbrt-v4's `coateddiffuse` and `coatedconductor` load as the stochastic layered BSDFs, with
/// pbrt's parameters, and render: under a white sky of radiance 1 neither sphere reflects more
/// than arrives, and each shows its colour (the red base, the gold metal).
#[test]
fn coated_materials_render() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/coated.pbrt");
    let loaded = appel::format::load(&scene, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let m = &loaded.description.materials;
    let diffuse = m
        .values()
        .find_map(|m| match m {
            MaterialDesc::CoatedDiffuse(d) => Some(d.clone()),
            _ => None,
        })
        .expect("a coateddiffuse");
    assert_eq!(diffuse.reflectance, TextureDesc::Rgb([0.8, 0.25, 0.2]));
    // pbrt's remaproughness: alpha = sqrt(roughness).
    assert_eq!(diffuse.alpha, TextureDesc::Value(0.05f64.sqrt() as f32));
    assert_eq!((diffuse.thickness, diffuse.g), (0.05, 0.3));
    assert_eq!((diffuse.maxdepth, diffuse.nsamples), (16, 2));
    assert_eq!(diffuse.albedo, TextureDesc::Rgb([0.3; 3]));
    let metal = m
        .values()
        .find_map(|m| match m {
            MaterialDesc::CoatedConductor(c) => Some(c.clone()),
            _ => None,
        })
        .expect("a coatedconductor");
    assert_eq!(
        metal.interface_alpha,
        TextureDesc::Value(0.1f64.sqrt() as f32)
    );
    assert!(metal.conductor_eta.is_some() && metal.conductor_k.is_some());

    let film = render_loaded(loaded, &Setup { spp: 64, block: 1 }, |_| {});
    let w = film.width as usize;
    let mean = |x0: usize, x1: usize| {
        let mut s = [0.0f64; 3];
        for y in 8..16 {
            for x in x0..x1 {
                let p = film.rgb[y * w + x];
                for k in 0..3 {
                    assert!(p[k].is_finite() && p[k] >= 0.0, "{p:?}");
                    s[k] += p[k] as f64;
                }
            }
        }
        s.map(|v| v / ((x1 - x0) * 8) as f64)
    };
    // pbrt's camera space is left-handed: the sphere at -x is on the right of the image.
    let (gold, red) = (mean(8, 16), mean(w - 16, w - 8));
    for c in [gold, red] {
        assert!(c.iter().all(|&v| v <= 1.02), "{c:?}");
    }
    // The red base shows through the coating; gold reflects red and green over blue.
    assert!(red[0] > 1.5 * red[2] && red[0] > 0.3, "{red:?}");
    assert!(
        gold[0] > gold[2] && gold[1] > gold[2] && gold[0] > 0.3,
        "{gold:?}"
    );
}

/// An `infinite` light with an image reads it as pbrt-v4 writes it (an equal-area octahedral
/// map, here a PFM file): a uniform image of radiance 0.5 lights a diffuse sphere as the
/// constant `"rgb L" [0.5 0.5 0.5]` does, pixel blocks agreeing within their noise.
#[test]
fn an_equal_area_environment_image_lights_as_its_constant() {
    let dir = tempfile::tempdir().unwrap();
    let mut pfm = b"PF\n8 8\n-1.0\n".to_vec();
    for _ in 0..8 * 8 * 3 {
        pfm.extend(0.5f32.to_le_bytes());
    }
    std::fs::write(dir.path().join("sky.pfm"), pfm).unwrap();
    let scene = |light: &str| {
        let text = format!(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\n\
             Film \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\n\
             Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" [ 4 ]\n\
             WorldBegin\nAttributeBegin\nRotate 30 1 0 0\n{light}\nAttributeEnd\n\
             Material \"diffuse\" \"rgb reflectance\" [ 0.6 0.5 0.4 ]\n\
             Shape \"sphere\" \"float radius\" [ 1 ]\n"
        );
        let path = dir.path().join(format!("{}.pbrt", light.len()));
        std::fs::write(&path, text).unwrap();
        let loaded =
            appel::format::load(&path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
        render_loaded(loaded, &Setup { spp: 64, block: 4 }, |_| {})
    };
    let image = scene("LightSource \"infinite\" \"string filename\" \"sky.pfm\"");
    let constant = scene("LightSource \"infinite\" \"rgb L\" [ 0.5 0.5 0.5 ]");
    let (mut worst, mut mean_a, mut mean_b) = (0.0f64, 0.0f64, 0.0f64);
    for (i, (a, b)) in image.rgb.iter().zip(&constant.rgb).enumerate() {
        for c in 0..3 {
            let sd = ((image.variance[i][c] + constant.variance[i][c]) as f64)
                .sqrt()
                .max(1e-4);
            worst = worst.max((a[c] - b[c]).abs() as f64 / sd);
            mean_a += a[c] as f64;
            mean_b += b[c] as f64;
        }
    }
    // 64 blocks of 3 channels: a 5-sigma excursion is improbable for identical expectations.
    assert!(worst < 5.0, "worst block {worst} standard deviations apart");
    assert!((mean_a / mean_b - 1.0).abs() < 0.02, "{mean_a} vs {mean_b}");
}
