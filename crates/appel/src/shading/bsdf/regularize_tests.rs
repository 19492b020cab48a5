//! [`Bsdf::regularized`]: pbrt-v4's roughness rule on every BSDF, the rough twins of smooth ones
//! sampling their densities, rough BSDFs left bit for bit, and smooth glass keeping its albedo.

use super::*;
use crate::shading::bsdf::layered::{Interface, Layered, Metal};
use crate::shading::bsdf::microfacet::regularized_alpha;

fn ggx(au: f32, av: f32) -> Microfacet {
    Microfacet::new(MicrofacetKind::Ggx, au, av, true)
}

fn beckmann(au: f32, av: f32, visible: bool) -> Microfacet {
    Microfacet::new(MicrofacetKind::Beckmann, au, av, visible)
}

fn alphas(d: &Microfacet) -> (f32, f32) {
    (d.alpha_u, d.alpha_v)
}

fn glass() -> Dielectric {
    Dielectric::new(1.5, Vec3::new(0.9, 0.8, 0.7), Vec3::new(0.5, 0.7, 0.9))
}

fn copper() -> Conductor {
    let (eta, k) = spectra::conductor("Cu").unwrap();
    Conductor::new(eta, k, Vec3::new(1.0, 0.9, 0.8))
}

fn no_layer() -> layered::Layer {
    layer(0.01, 0.0, 0.0, 10, 1)
}

#[test]
fn regularized_roughness_follows_pbrts_rule() {
    // pbrt-v4's TrowbridgeReitzDistribution::Regularize, value by value (doubling is exact in
    // f32, so these are equalities).
    for (alpha, expected) in [
        (0.0, 0.1),
        (Microfacet::MIN_ALPHA, 0.1),
        (0.05, 0.1),
        (0.1, 0.2),
        (0.12, 0.24),
        (0.2, 0.3),
        (0.29, 0.3),
        (0.3, 0.3),
        (0.5, 0.5),
        (1.2, 1.2),
    ] {
        assert_eq!(regularized_alpha(alpha), expected, "alpha {alpha}");
    }
    assert_eq!(alphas(&Microfacet::regularized_smooth()), (0.1, 0.1));
    assert_eq!(Microfacet::regularized_smooth().kind, MicrofacetKind::Ggx);

    // Smooth dielectric and conductor: their rough twins of GGX 0.1, everything else kept.
    let AnyBsdf::RoughDielectric(g) = AnyBsdf::Dielectric(glass()).regularized() else {
        panic!("a smooth dielectric regularizes to a rough one");
    };
    assert_eq!(g.distribution, ggx(0.1, 0.1));
    let smooth = glass();
    assert_eq!(
        (g.eta, g.specular_reflectance, g.specular_transmittance),
        (
            smooth.eta,
            smooth.specular_reflectance,
            smooth.specular_transmittance
        )
    );
    let AnyBsdf::RoughConductor(c) = AnyBsdf::Conductor(copper()).regularized() else {
        panic!("a smooth conductor regularizes to a rough one");
    };
    assert_eq!(c.distribution, ggx(0.1, 0.1));
    let smooth = copper();
    assert_eq!(
        (c.eta, c.k, c.specular_reflectance),
        (smooth.eta, smooth.k, smooth.specular_reflectance)
    );

    // Rough ones: per axis, the kind and the sampling kept.
    let (eta, k) = spectra::conductor("Au").unwrap();
    for (d, expected) in [
        (ggx(0.05, 0.1), ggx(0.1, 0.2)),
        (beckmann(0.2, 0.5, true), beckmann(0.3, 0.5, true)),
        (beckmann(0.05, 0.2, false), beckmann(0.1, 0.3, false)),
    ] {
        let metal = AnyBsdf::RoughConductor(RoughConductor::new(d, eta, k, Vec3::ONE));
        let AnyBsdf::RoughConductor(r) = metal.regularized() else {
            panic!("{metal:?}");
        };
        assert_eq!(r.distribution, expected);
        assert_eq!(r, RoughConductor::new(expected, eta, k, Vec3::ONE));
        let glass = AnyBsdf::RoughDielectric(RoughDielectric::new(d, 1.33, Vec3::ONE, Vec3::ONE));
        let AnyBsdf::RoughDielectric(r) = glass.regularized() else {
            panic!("{glass:?}");
        };
        assert_eq!(
            r,
            RoughDielectric::new(expected, 1.33, Vec3::ONE, Vec3::ONE)
        );
    }

    // Phong, as the Monte Carlo integrators see it: glass and mirror.
    let AnyBsdf::RoughDielectric(g) = AnyBsdf::Phong(Phong::glass(1.5)).regularized() else {
        panic!("phong glass regularizes to rough glass");
    };
    assert_eq!((g.distribution, g.eta), (ggx(0.1, 0.1), 1.5));
    let AnyBsdf::RoughConductor(c) = AnyBsdf::Phong(Phong::mirror(Vec3::splat(0.8))).regularized()
    else {
        panic!("a phong mirror regularizes to a rough mirror");
    };
    assert_eq!(c.distribution, ggx(0.1, 0.1));
}

/// The tables of a rough plastic of `d` over index 1.5, as a material computes them at load.
fn plastic_params(d: Microfacet) -> RoughPlasticParams {
    RoughPlasticParams::precompute(d, 1.5, true, 0.5, 1.0)
}

#[test]
fn regularized_plastics_have_the_coating_tables_of_their_roughness() {
    let diffuse = Vec3::new(0.2, 0.5, 0.8);
    let AnyBsdf::RoughPlastic(r) = plastic(true, diffuse).regularized() else {
        panic!("a smooth plastic regularizes to a rough one");
    };
    let expected = plastic_params(ggx(0.1, 0.1));
    assert_eq!(r.distribution, ggx(0.1, 0.1));
    assert_eq!(
        r.external_transmittance[..],
        expected.external_transmittance[..]
    );
    assert_eq!((r.eta, r.nonlinear), (1.5, true));
    assert_eq!(
        (r.diffuse_reflectance, r.specular_reflectance),
        (diffuse, Vec3::ONE)
    );
    // The lobe choice weighs the reflectances as before, and the base is as bright: the smooth
    // plastic's own sampling weight and internal reflectance.
    let AnyBsdf::Plastic(p) = plastic(true, diffuse) else {
        unreachable!()
    };
    assert_eq!(r.specular_sampling_weight, p.specular_sampling_weight);
    assert_eq!(r.internal_reflectance, p.fdr_int);

    // A rough plastic widens step by step, each step with its roughness's transmittance, the
    // kind and the internal reflectance kept, until the rule leaves it (0.3).
    let params = plastic_params(beckmann(0.1, 0.1, false));
    let mut b = AnyBsdf::RoughPlastic(RoughPlastic::new(&params, diffuse, Vec3::ONE));
    for alpha in [0.2, 0.3] {
        b = b.regularized();
        let AnyBsdf::RoughPlastic(r) = b else {
            panic!("{b:?}");
        };
        let expected = plastic_params(beckmann(alpha, alpha, false));
        assert_eq!(r.distribution, beckmann(alpha, alpha, false));
        assert_eq!(
            r.external_transmittance[..],
            expected.external_transmittance[..]
        );
        assert_eq!(r.internal_reflectance, params.internal_reflectance);
    }
    assert_eq!(b.regularized(), b);
}

#[test]
fn regularized_coated_bsdfs_widen_both_interfaces() {
    let base = Diffuse::new(Vec3::splat(0.5));
    let smooth = AnyBsdf::CoatedDiffuse(Layered {
        top: Interface::new(1.5, 0.0, 0.0),
        base,
        layer: no_layer(),
    });
    assert!(smooth.flags().is_delta());
    let AnyBsdf::CoatedDiffuse(r) = smooth.regularized() else {
        panic!("{smooth:?}");
    };
    assert_eq!(r.top.distribution, ggx(0.1, 0.1));
    assert_eq!((r.top.eta, r.base, r.layer), (1.5, base, no_layer()));
    assert!(!smooth.regularized().flags().is_delta());

    let (eta, k) = spectra::conductor("Cu").unwrap();
    let coated = AnyBsdf::CoatedConductor(Layered {
        top: Interface::new(1.5, 0.2, 0.05),
        base: Metal::new(eta, k, 0.0, 0.12),
        layer: no_layer(),
    });
    let AnyBsdf::CoatedConductor(r) = coated.regularized() else {
        panic!("{coated:?}");
    };
    assert_eq!(alphas(&r.top.distribution), (0.3, 0.1));
    assert_eq!(alphas(&r.base.distribution), (0.1, 0.24));
    assert_eq!((r.base.eta, r.base.k), (eta, k));
}

#[test]
fn regularized_principled_lobes_follow_pbrts_rule() {
    // roughness 0.3: alpha 0.09 on both axes; clearcoat gloss 0.3: GTR1 alpha 0.0703.
    let p = Principled {
        roughness: 0.3,
        ..principled(0.2, 0.5, 0.8, 0.0)
    };
    let AnyBsdf::Principled(r) = AnyBsdf::Principled(p).regularized() else {
        unreachable!()
    };
    let (au, av) = alphas(&p.main_distribution());
    assert!((au - 0.09).abs() < 1e-6 && au == av);
    assert_eq!(
        alphas(&r.main_distribution()),
        (regularized_alpha(au), regularized_alpha(av))
    );
    assert!((r.main_distribution().alpha_u - 0.18).abs() < 1e-6);
    let coat = p.clearcoat_alpha();
    assert!((coat - 0.0703).abs() < 1e-6);
    assert_eq!(r.clearcoat_alpha(), regularized_alpha(coat));
    // Only the lobes' alphas change: Burley's roughness (of the retro-reflection) stays.
    assert_eq!(
        Principled {
            regularizations: 0,
            ..r
        },
        p
    );

    // Anisotropic thin sheet: alpha 0.16 / sqrt(0.55) along u, 0.16 sqrt(0.55) along v.
    let t = principled_thin(0.5, 0.8);
    let AnyBsdf::PrincipledThin(r) = AnyBsdf::PrincipledThin(t).regularized() else {
        unreachable!()
    };
    for (before, after) in [
        (t.reflection_distribution(), r.reflection_distribution()),
        (t.transmission_distribution(), r.transmission_distribution()),
    ] {
        assert_eq!(
            alphas(&after),
            (
                regularized_alpha(before.alpha_u),
                regularized_alpha(before.alpha_v)
            )
        );
    }
    assert_eq!(r.reflection_distribution().alpha_u, 0.3);
    assert!((r.reflection_distribution().alpha_v - 2.0 * 0.16 * 0.55f32.sqrt()).abs() < 1e-6);
}

/// The rough twins of smooth BSDFs pass the chi-square and weight checks every rough BSDF
/// passes, on both sides of the dielectric.
#[test]
fn regularized_smooth_bsdfs_sample_their_pdf() {
    let transmissive = [
        AnyBsdf::Dielectric(glass()).regularized(),
        AnyBsdf::Dielectric(Dielectric::new(1.0 / 1.33, Vec3::ONE, Vec3::ONE)).regularized(),
    ];
    let reflective = [
        AnyBsdf::Conductor(copper()).regularized(),
        plastic(false, Vec3::new(0.2, 0.5, 0.8)).regularized(),
        AnyBsdf::Principled(Principled {
            roughness: 0.1,
            ..principled(0.3, 0.0, 0.9, 0.6)
        })
        .regularized(),
    ];
    for b in transmissive.iter().chain(&reflective) {
        assert!(!b.flags().is_delta(), "{b:?}");
    }
    let wos_both = [
        dir(0.1, 0.05, 1.0),
        dir(0.6, -0.4, 0.7),
        dir(-0.3, 0.95, 0.08),
        dir(0.2, 0.1, -0.97),
        dir(-0.5, 0.5, -0.7),
    ];
    check_sampling(
        &transmissive,
        &wos_both,
        transmissive.len() * wos_both.len(),
    );
    check_sampling(&reflective, &wos_above(), reflective.len() * 3);
}

/// Rough BSDFs at roughness 0.3 or more, and BSDFs without microfacet lobes, come back bit for
/// bit (their Debug forms print every f32 exactly).
#[test]
fn regularizing_rough_bsdfs_changes_nothing() {
    let (eta, k) = spectra::conductor("Al").unwrap();
    let mut bsdfs = vec![
        AnyBsdf::Diffuse(Diffuse::new(Vec3::new(0.2, 0.5, 0.8))),
        AnyBsdf::ThinDielectric(ThinDielectric::new(1.5, Vec3::ONE, Vec3::ONE)),
        AnyBsdf::Null(Null),
        AnyBsdf::Phong(Phong::matte(Vec3::splat(0.5))),
        // Index-matched: pbrt-v4 keeps it specular at any roughness.
        AnyBsdf::Dielectric(Dielectric::new(1.0, Vec3::ONE, Vec3::ONE)),
        AnyBsdf::RoughPlastic(RoughPlastic::new(
            &plastic_params(ggx(0.4, 0.4)),
            Vec3::splat(0.5),
            Vec3::ONE,
        )),
        AnyBsdf::CoatedDiffuse(Layered {
            top: Interface::new(1.5, 0.3, 0.45),
            base: Diffuse::new(Vec3::splat(0.5)),
            layer: layer(0.2, 0.8, 0.6, 16, 1),
        }),
        AnyBsdf::CoatedConductor(Layered {
            top: Interface::new(1.5, 0.5, 0.3),
            base: Metal::new(eta, k, 0.3, 0.9),
            layer: no_layer(),
        }),
        AnyBsdf::Principled(Principled {
            roughness: 0.6,
            ..principled(0.3, 0.5, 0.0, 0.0)
        }),
        AnyBsdf::PrincipledThin(PrincipledThin {
            roughness: 0.9,
            anisotropic: 0.0,
            eta: 2.0,
            ..principled_thin(0.5, 0.8)
        }),
    ];
    for d in [ggx(0.3, 0.3), ggx(0.5, 0.3), beckmann(0.3, 0.8, false)] {
        bsdfs.push(AnyBsdf::RoughConductor(RoughConductor::new(
            d,
            eta,
            k,
            Vec3::ONE,
        )));
        bsdfs.push(AnyBsdf::RoughDielectric(RoughDielectric::new(
            d,
            1.5,
            Vec3::ONE,
            Vec3::ONE,
        )));
    }
    for b in bsdfs {
        let r = b.regularized();
        assert_eq!(r, b);
        assert_eq!(format!("{r:?}"), format!("{b:?}"));
    }
}

/// The mean sample weight from `wo`, and the mean energy throughput (the refraction's radiance
/// scaling `1 / η²` undone, see [`energy`]).
fn mean_weight(bsdf: &AnyBsdf, wo: Vec3, n: usize) -> (Vec3, Vec3) {
    let mut rng = Pcg32::new(17, 3);
    let (mut weight, mut energy_sum) = (Vec3::ZERO, Vec3::ZERO);
    for _ in 0..n {
        if let Some(s) = bsdf.sample(wo, rng.next_f32(), rng.next_vec2()) {
            weight += s.weight;
            energy_sum += energy(&s);
        }
    }
    (weight / n as f32, energy_sum / n as f32)
}

/// Roughening is a redistribution: a regularized smooth BSDF scatters about what the smooth one
/// does, losing only the little that single-scattering microfacet models lose to masking at
/// roughness 0.1. White glass conserves energy from both sides, even near the critical angle
/// (inside, `cos θ = 0.745` for index 1.5), where roughening moves light between reflection and
/// refraction; coloured glass (so that the split shows) keeps its albedo away from that angle,
/// as do the mirror and the plastic.
#[test]
fn regularized_smooth_bsdfs_keep_their_albedo() {
    let n = 100_000;
    let white = AnyBsdf::Dielectric(Dielectric::new(1.5, Vec3::ONE, Vec3::ONE));
    let near_critical = dir(0.5, 0.0, -0.874);
    let below = [dir(0.1, 0.2, -1.0), dir(0.9, 0.0, -0.45)];
    let above = [
        dir(0.1, 0.05, 1.0),
        dir(0.6, -0.4, 0.7),
        dir(0.9, 0.1, 0.45),
    ];
    for wo in above.iter().chain(&below).chain([&near_critical]) {
        let (_, a) = mean_weight(&white, *wo, n);
        let (_, b) = mean_weight(&white.regularized(), *wo, n);
        assert!((a - Vec3::ONE).abs().max_element() < 1e-5, "{wo}: {a}");
        assert!(
            b.max_element() <= 1.0 && b.min_element() > 0.95,
            "wo = {wo}: {b}"
        );
    }
    for smooth in [
        AnyBsdf::Dielectric(glass()),
        AnyBsdf::Conductor(copper()),
        plastic(false, Vec3::new(0.2, 0.5, 0.8)),
    ] {
        let rough = smooth.regularized();
        let two_sided = matches!(smooth, AnyBsdf::Dielectric(_));
        let wos = above
            .iter()
            .chain(below.iter().take(if two_sided { 2 } else { 0 }));
        for &wo in wos {
            let (a, _) = mean_weight(&smooth, wo, n);
            let (b, _) = mean_weight(&rough, wo, n);
            let relative = ((b - a) / a).abs().max_element();
            assert!(
                relative < 0.05,
                "{smooth:?} wo = {wo}: smooth {a}, regularized {b}"
            );
        }
    }
}
