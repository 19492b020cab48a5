//! Normal- and bump-mapped BSDFs through [`Material::bsdf`]: sampling follows the pdf, weights
//! are eval over pdf, no energy is gained, and the wrappers compose with two-sided materials as
//! Mitsuba's do. (They are not reciprocal: the terminator shadowing and the choice between a
//! normal and its flipped twin look at one direction only, as in Mitsuba.)

use super::*;
use crate::shading::bsdf::{DiffuseMaterial, MicrofacetKind, RoughConductorMaterial};
use crate::shading::chi2::{Chi2Test, Config, Pcg32};
use crate::shading::spectra;

fn dir(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z).normalize()
}

fn diffuse(c: f32) -> Material {
    Material::Diffuse(DiffuseMaterial {
        reflectance: Texture::Constant(Vec3::splat(c)),
    })
}

fn rough_conductor() -> Material {
    let (eta, k) = spectra::conductor("Al").unwrap();
    Material::RoughConductor(RoughConductorMaterial {
        roughness: Roughness {
            kind: MicrofacetKind::Ggx,
            alpha_u: Texture::Constant(Vec3::splat(0.25)),
            alpha_v: Texture::Constant(Vec3::splat(0.05)),
            sample_visible: true,
        },
        eta,
        k,
        specular: Texture::Constant(Vec3::ONE),
    })
}

fn white_conductor() -> Material {
    Material::RoughConductor(RoughConductorMaterial {
        roughness: Roughness {
            kind: MicrofacetKind::Beckmann,
            alpha_u: Texture::Constant(Vec3::splat(0.3)),
            alpha_v: Texture::Constant(Vec3::splat(0.3)),
            sample_visible: true,
        },
        eta: Vec3::ZERO,
        k: Vec3::ONE,
        specular: Texture::Constant(Vec3::ONE),
    })
}

/// A normal map of one colour around `inner` (material 1), as material 0.
fn normal_mapped(rgb: Vec3, inner: Material, shadowing: bool) -> Vec<Material> {
    vec![
        Material::NormalMap {
            normals: Texture::Constant(rgb),
            inner: 1,
            flip_invalid: true,
            shadowing,
        },
        inner,
    ]
}

fn point(wo: Vec3) -> SurfacePoint<'static> {
    SurfacePoint {
        uv: Vec2::new(0.3, 0.6),
        attributes: None,
        wo,
        dpdu: Vec3::X,
        dpdv: Vec3::Y,
        n: Vec3::Z,
        bitangent_sign: 1.0,
    }
}

/// Tilted normals (in map colours): strongly, mildly, and one pointing below the horizon.
const TILTS: [[f32; 3]; 3] = [[0.85, 0.4, 0.8], [0.45, 0.6, 0.95], [0.9, 0.5, 0.45]];

fn wos() -> [Vec3; 3] {
    [
        dir(0.1, 0.05, 1.0),
        dir(0.6, -0.4, 0.7),
        dir(-0.8, 0.3, 0.15),
    ]
}

#[test]
fn mapped_sampling_follows_the_pdf() {
    let test = Chi2Test::new(Config {
        samples: 40_000,
        cos_theta_bins: 24,
        phi_bins: 48,
        tests: 2 * TILTS.len() * wos().len(),
        ..Default::default()
    });
    for inner in [diffuse(0.7), rough_conductor()] {
        for tilt in TILTS {
            let materials = normal_mapped(Vec3::from(tilt), inner.clone(), true);
            for wo in wos() {
                let b = Material::bsdf(&materials, 0, &point(wo));
                let o = test.run(
                    |u1, u2| b.sample(wo, u1, u2).map(|s| s.wi),
                    |wi| b.eval_pdf(wo, wi).1,
                );
                if o.success_rate == 0.0 {
                    // A normal below the horizon that flipping cannot bring up: nothing is
                    // reflected, and the pdf says so.
                    assert_eq!(o.pdf_integral, 0.0, "{tilt:?} wo = {wo}: {o}");
                    continue;
                }
                assert!(o.passed, "{tilt:?} wo = {wo}: {o}");
                assert!(
                    (o.pdf_integral - o.success_rate).abs() < 0.01,
                    "{tilt:?} wo = {wo}: {o}"
                );
                // Weights are eval / pdf, and sampled directions are above both surfaces.
                let mut rng = Pcg32::new(3, 9);
                for _ in 0..200 {
                    let Some(s) = b.sample(wo, rng.next_f32(), rng.next_vec2()) else {
                        continue;
                    };
                    let (f, pdf) = b.eval_pdf(wo, s.wi);
                    assert!(s.wi.z > 0.0, "{s:?}");
                    assert!((s.pdf - pdf).abs() <= 2e-3 * pdf, "{s:?} vs {pdf}");
                    let w = f / pdf;
                    assert!(
                        (s.weight - w).abs().max_element() <= 2e-3 * w.max_element() + 1e-6,
                        "{s:?} vs {w}"
                    );
                }
            }
        }
    }
}

#[test]
fn mapped_white_bsdfs_gain_no_energy() {
    let n = 100_000;
    for inner in [diffuse(1.0), white_conductor()] {
        for tilt in TILTS {
            let materials = normal_mapped(Vec3::from(tilt), inner.clone(), false);
            for wo in wos() {
                let b = Material::bsdf(&materials, 0, &point(wo));
                let mut rng = Pcg32::new(5, 1);
                let mut sum = Vec3::ZERO;
                for _ in 0..n {
                    if let Some(s) = b.sample(wo, rng.next_f32(), rng.next_vec2()) {
                        sum += s.weight;
                    }
                }
                let albedo = sum / n as f32;
                assert!(albedo.max_element() <= 1.01, "{tilt:?} wo = {wo}: {albedo}");
            }
        }
    }
}

#[test]
fn an_identity_map_is_the_plain_bsdf() {
    let plain = [rough_conductor()];
    let mapped = normal_mapped(Vec3::new(0.5, 0.5, 1.0), rough_conductor(), true);
    let mut rng = Pcg32::new(8, 8);
    for wo in wos() {
        let a = Material::bsdf(&plain, 0, &point(wo));
        let b = Material::bsdf(&mapped, 0, &point(wo));
        for _ in 0..50 {
            let wi = dir(
                rng.next_f32() - 0.5,
                rng.next_f32() - 0.5,
                rng.next_f32() + 0.01,
            );
            assert_eq!(a.eval_pdf(wo, wi), b.eval_pdf(wo, wi));
        }
        let (u1, u2) = (rng.next_f32(), rng.next_vec2());
        assert_eq!(a.sample(wo, u1, u2), b.sample(wo, u1, u2));
    }
}

/// A map tilting the normal by 45 degrees about y: a diffuse surface lit along the tilted normal
/// reflects `1/pi` times the terminator shadowing of light 45 degrees off the base normal, and
/// light from below the tilted surface or from below the base surface is rejected.
#[test]
fn tilted_diffuse_by_hand() {
    let t = std::f32::consts::FRAC_1_SQRT_2;
    let rgb = (Vec3::new(t, 0.0, t) + Vec3::ONE) * 0.5;
    let materials = normal_mapped(rgb, diffuse(1.0), true);
    let wo = Vec3::Z;
    let b = Material::bsdf(&materials, 0, &point(wo));
    let (f, _) = b.eval_pdf(wo, Vec3::new(t, 0.0, t));
    let g = 2.0 / (1.0 + (1.0f32 + 1.0 / 8.0).sqrt());
    assert!(
        (f - Vec3::splat(std::f32::consts::FRAC_1_PI * g))
            .abs()
            .max_element()
            < 1e-5,
        "{f}"
    );
    // At 30 degrees from the base normal, on the far side of the tilt: cos 75 degrees, shadowed
    // by 2 / (1 + sqrt(1 + tan^2(45) / 8 * tan^2(30))).
    let wi = dir(-0.5, 0.0, 3f32.sqrt() / 2.0);
    let (f, _) = b.eval_pdf(wo, wi);
    let g = 2.0 / (1.0 + (1.0f32 + 1.0 / 8.0 / 3.0).sqrt());
    let want = (75f32).to_radians().cos() * std::f32::consts::FRAC_1_PI * g;
    assert!((f.x - want).abs() < 1e-5, "{f} vs {want}");
    // Below the tilted surface (but above the base one), and below the base one (but above the
    // tilted one).
    assert_eq!(b.eval_pdf(wo, dir(-1.0, 0.0, 0.5)).0, Vec3::ZERO);
    assert_eq!(b.eval_pdf(wo, dir(1.0, 0.0, -0.5)), (Vec3::ZERO, 0.0));
}

/// Mitsuba's bumpmap takes the height field's gradient against dp/du and dp/dv: a height rising
/// along u at slope 1 (per unit of u, with |dp/du| = 1) tilts the normal 45 degrees towards -u.
#[test]
fn a_bump_ramp_tilts_like_the_equivalent_normal_map() {
    let ramp = std::sync::Arc::new(crate::io::bitmap_read::Bitmap {
        width: 2,
        height: 1,
        channels: 1,
        data: vec![0.0, 1.0],
    });
    // Bilinear between the two pixel centres (u = 0.25 and 0.75): slope 2 per unit u.
    let height = Texture::Bitmap(crate::shading::texture::BitmapTexture::new(
        ramp,
        crate::shading::texture::Filter::Bilinear,
        crate::shading::texture::Wrap::Clamp,
        glam::Mat3::IDENTITY,
    ));
    let bumped = vec![
        Material::BumpMap {
            height,
            scale: 0.5,
            inner: 1,
            flip_invalid: true,
            shadowing: true,
        },
        diffuse(0.8),
    ];
    let t = std::f32::consts::FRAC_1_SQRT_2;
    let mapped = normal_mapped(
        (Vec3::new(-t, 0.0, t) + Vec3::ONE) * 0.5,
        diffuse(0.8),
        true,
    );
    let mut rng = Pcg32::new(2, 4);
    for wo in wos() {
        let at = SurfacePoint {
            uv: Vec2::new(0.5, 0.5),
            ..point(wo)
        };
        let a = Material::bsdf(&bumped, 0, &at);
        let b = Material::bsdf(&mapped, 0, &at);
        for _ in 0..20 {
            let wi = dir(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32());
            let (fa, pa) = a.eval_pdf(wo, wi);
            let (fb, pb) = b.eval_pdf(wo, wi);
            assert!((fa - fb).abs().max_element() < 1e-5 && (pa - pb).abs() < 1e-5);
        }
    }
}

/// A two-sided material outside a normal map mirrors the directions it sees (the map applies to
/// the mirrored ones); inside, the mirror applies in the perturbed frame.
#[test]
fn two_sided_and_maps_compose() {
    let rgb = Vec3::new(0.7, 0.45, 0.9);
    let outside = {
        let mut m = vec![Material::TwoSided { front: 1, back: 1 }];
        m.extend(
            normal_mapped(rgb, rough_conductor(), true)
                .into_iter()
                .map(|m| match m {
                    Material::NormalMap {
                        normals,
                        flip_invalid,
                        shadowing,
                        ..
                    } => Material::NormalMap {
                        normals,
                        inner: 2,
                        flip_invalid,
                        shadowing,
                    },
                    other => other,
                }),
        );
        m
    };
    let mirror = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
    let front = normal_mapped(rgb, rough_conductor(), true);
    let mut rng = Pcg32::new(4, 2);
    for wo in wos() {
        // From behind, the two-sided map is the front map seen in the mirror.
        let back = Material::bsdf(&outside, 0, &point(mirror(wo)));
        let reference = Material::bsdf(&front, 0, &point(wo));
        for _ in 0..20 {
            let wi = dir(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32());
            assert_eq!(
                back.eval_pdf(mirror(wo), mirror(wi)),
                reference.eval_pdf(wo, wi)
            );
        }
        let (u1, u2) = (rng.next_f32(), rng.next_vec2());
        let s = back.sample(mirror(wo), u1, u2).map(|s| mirror(s.wi));
        assert_eq!(s, reference.sample(wo, u1, u2).map(|s| s.wi));
    }
    // Inside: a normal map around a two-sided material; from above it is the plain map.
    let inside = vec![
        Material::NormalMap {
            normals: Texture::Constant(rgb),
            inner: 1,
            flip_invalid: true,
            shadowing: true,
        },
        Material::TwoSided { front: 2, back: 2 },
        rough_conductor(),
    ];
    for wo in wos() {
        let a = Material::bsdf(&inside, 0, &point(wo));
        let b = Material::bsdf(&front, 0, &point(wo));
        let wi = dir(0.2, 0.3, 0.9);
        assert_eq!(a.eval_pdf(wo, wi), b.eval_pdf(wo, wi));
    }
}

/// A blend of a diffuse and a rough conductor: its samples follow the blended pdf, the blended
/// value is the mix, and a white blend gains no energy (the mean sample weight is the mix of the
/// parts' albedos).
#[test]
fn blend_sampling_follows_the_mixed_pdf() {
    let test = Chi2Test::new(Config {
        samples: 40_000,
        cos_theta_bins: 24,
        phi_bins: 48,
        tests: 3 * wos().len(),
        ..Default::default()
    });
    for w in [0.0, 0.3, 0.8] {
        let materials = vec![
            Material::Blend {
                weight: Texture::Constant(Vec3::splat(w)),
                first: 1,
                second: 2,
            },
            diffuse(1.0),
            white_conductor(),
        ];
        for wo in wos() {
            let b = Material::bsdf(&materials, 0, &point(wo));
            let o = test.run(
                |u1, u2| b.sample(wo, u1, u2).map(|s| s.wi),
                |wi| b.eval_pdf(wo, wi).1,
            );
            assert!(o.passed, "w = {w} wo = {wo}: {o}");
            assert!((o.pdf_integral - o.success_rate).abs() < 0.01, "{o}");
            let a = Material::bsdf(&materials[1..2], 0, &point(wo));
            let c = Material::bsdf(&[white_conductor()], 0, &point(wo));
            let wi = dir(0.3, -0.2, 0.9);
            let (f, _) = b.eval_pdf(wo, wi);
            let mix = a.eval_pdf(wo, wi).0 * (1.0 - w) + c.eval_pdf(wo, wi).0 * w;
            assert!((f - mix).abs().max_element() < 1e-6);
            let mut rng = Pcg32::new(1, 7);
            let n = 50_000;
            let mut sum = Vec3::ZERO;
            for _ in 0..n {
                if let Some(s) = b.sample(wo, rng.next_f32(), rng.next_vec2()) {
                    sum += s.weight;
                }
            }
            let albedo = sum / n as f32;
            assert!(albedo.max_element() <= 1.01, "w = {w} wo = {wo}: {albedo}");
        }
    }
}

/// The TOML schema: the three wrappers read with Mitsuba's names and defaults, and blends of
/// wrappers or maps of maps are refused.
#[test]
fn toml_wrappers_parse_and_validate() {
    use crate::description::description_from_str;
    use crate::description::parse::Syntax;
    use crate::description::MaterialDesc;
    let base = r#"
[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
[[shape]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "top"
[materials.d]
type = "diffuse"
[materials.c]
type = "roughconductor"
"#;
    let parse = |extra: &str| {
        description_from_str(
            &format!("{base}{extra}"),
            Syntax::Toml,
            std::path::Path::new("t.toml"),
        )
    };
    let d = parse(
        r#"
[materials.top]
type = "normalmap"
normalmap = [0.5, 0.5, 1.0]
material = "b"
[materials.b]
type = "blendbsdf"
weight = { type = "mesh_attribute", name = "face_weight" }
materials = ["d", "c"]
[materials.bump]
type = "bumpmap"
bumpmap = 0.3
scale = 0.02
material = "d"
"#,
    )
    .unwrap();
    let MaterialDesc::NormalMap(n) = &d.materials["top"] else {
        panic!("{:?}", d.materials["top"]);
    };
    assert!(n.flip_invalid_normals && n.use_shadowing_function);
    let MaterialDesc::BumpMap(b) = &d.materials["bump"] else {
        panic!()
    };
    assert_eq!(b.scale, 0.02);
    assert!(matches!(d.materials["b"], MaterialDesc::Blend(_)));
    let e = parse(
        r#"
[materials.top]
type = "blendbsdf"
materials = ["d", "t2"]
[materials.t2]
type = "twosided"
front = "d"
"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("plain materials"), "{e}");
    let e = parse(
        r#"
[materials.top]
type = "normalmap"
normalmap = [0.5, 0.5, 1.0]
material = "b2"
[materials.b2]
type = "bumpmap"
bumpmap = 1.0
material = "d"
"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("cannot wrap one another"), "{e}");
}

/// A left-handed tangent frame (glTF's w = -1) reads the map's y the other way round: the map
/// tilting toward +y shades as its mirror image, tilting toward -y, does in a right-handed one,
/// and unlike the unmirrored map.
#[test]
fn negative_bitangent_sign_mirrors_the_map_s_y() {
    let toward_y = normal_mapped(Vec3::new(0.5, 0.85, 0.85), rough_conductor(), true);
    let toward_minus_y = normal_mapped(Vec3::new(0.5, 0.15, 0.85), rough_conductor(), true);
    let mut rng = Pcg32::new(7, 3);
    let mut differs = false;
    for wo in wos() {
        let left = SurfacePoint {
            bitangent_sign: -1.0,
            ..point(wo)
        };
        let a = Material::bsdf(&toward_y, 0, &left);
        let b = Material::bsdf(&toward_minus_y, 0, &point(wo));
        let c = Material::bsdf(&toward_y, 0, &point(wo));
        for _ in 0..20 {
            let wi = dir(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32());
            let (fa, pa) = a.eval_pdf(wo, wi);
            let (fb, pb) = b.eval_pdf(wo, wi);
            let (fc, _) = c.eval_pdf(wo, wi);
            assert!((fa - fb).abs().max_element() < 1e-5 && (pa - pb).abs() < 1e-5);
            differs |= (fa - fc).abs().max_element() > 1e-2;
        }
    }
    assert!(differs);
}

/// Regularizing a surface regularizes its leaves: both BSDFs of a blend, seen from behind
/// through a two-sided wrapper, with the blend's weight and the mirroring kept, so that its
/// value is the blend of the regularized leaves at the mirrored directions.
#[test]
fn regularizing_a_surface_regularizes_both_blended_bsdfs() {
    let materials = vec![
        Material::TwoSided { front: 1, back: 1 },
        Material::Blend {
            weight: Texture::Constant(Vec3::splat(0.3)),
            first: 2,
            second: 3,
        },
        rough_conductor(),
        Material::Dielectric(crate::shading::bsdf::DielectricMaterial {
            eta: 1.5,
            reflectance: Texture::Constant(Vec3::ONE),
            transmittance: Texture::Constant(Vec3::ONE),
        }),
    ];
    let wo = dir(0.3, -0.2, -0.9);
    let s = Material::bsdf(&materials, 0, &point(wo));
    let r = s.regularized();
    assert!(s.flip_outer && r.flip_outer);
    let AnyBsdf::RoughConductor(first) = r.bsdf else {
        panic!("{r:?}");
    };
    // The conductor's (0.25, 0.05) widened to (0.3, 0.1).
    assert_eq!(
        (first.distribution.alpha_u, first.distribution.alpha_v),
        (0.3, 0.1)
    );
    let Some((AnyBsdf::RoughDielectric(second), w)) = r.blend else {
        panic!("{r:?}");
    };
    assert_eq!(w, 0.3);
    assert_eq!(second.distribution.alpha_u, 0.1);
    assert!(s.flags().is_delta());
    assert!(!r.flags().is_delta());
    let mirror = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
    for wi in [dir(-0.3, 0.25, -0.9), dir(0.1, 0.4, 0.9)] {
        let (f, pdf) = r.eval_pdf(wo, wi);
        let (f1, p1) = r.bsdf.eval_pdf(mirror(wo), mirror(wi));
        let (f2, p2) = AnyBsdf::RoughDielectric(second).eval_pdf(mirror(wo), mirror(wi));
        assert!((f - (f1 * 0.7 + f2 * 0.3)).abs().max_element() < 1e-6);
        assert!((pdf - (p1 * 0.7 + p2 * 0.3)).abs() < 1e-5 * pdf.max(1.0));
    }
}
