//! Phase functions against their densities (chi-square), their normalisation and mean cosine,
//! and the volumes' lookups and bounds.

use super::volume::{Grid, VolumeValues};
use super::*;
use crate::io::grid_volume::GridVolume;
use crate::shading::chi2::{Chi2Test, Config, Pcg32};
use glam::Mat4;
use std::f32::consts::PI;

fn phases() -> Vec<(&'static str, Phase)> {
    let hg = |g| Phase::Hg(HenyeyGreenstein { g });
    vec![
        ("isotropic", Phase::Isotropic(Isotropic)),
        ("hg forward", hg(0.7)),
        ("hg backward", hg(-0.5)),
        ("hg nearly isotropic", hg(0.0005)),
        ("rayleigh", Phase::Rayleigh(Rayleigh)),
        (
            "blend",
            Phase::BlendPhase(BlendPhase {
                weight: 0.3,
                phases: Box::new([Phase::Rayleigh(Rayleigh), hg(-0.8)]),
            }),
        ),
    ]
}

/// A direction of travel off the chi-square grid's axes.
fn travel() -> Vec3 {
    Vec3::new(0.3, -0.5, 0.8).normalize()
}

/// Each sampler draws its density, which integrates to 1 (the phase functions are normalised),
/// and its value is that density (so the weight is 1).
#[test]
fn phase_functions_sample_their_densities() {
    let all = phases();
    let d = travel();
    for (name, p) in &all {
        let outcome = Chi2Test::new(Config {
            tests: all.len(),
            ..Default::default()
        })
        .run(
            |u1, u2| p.sample(d, u1, u2).map(|s| s.wo),
            |wo| p.pdf(d, wo),
        );
        assert!(outcome.passed, "{name}: {outcome}");
        assert!(
            (outcome.pdf_integral - 1.0).abs() < 1e-3,
            "{name}: {outcome}"
        );
        let mut rng = Pcg32::new(3, 1);
        for _ in 0..200 {
            let s = p
                .sample(d, rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()))
                .unwrap();
            assert!((s.pdf - p.pdf(d, s.wo)).abs() <= 1e-4 * s.pdf, "{name}");
            assert!((s.weight - p.eval(d, s.wo) / s.pdf).abs() < 1e-4, "{name}");
            assert!((s.weight - 1.0).abs() < 1e-4, "{name}: {}", s.weight);
        }
    }
}

/// Henyey-Greenstein's `g` is the mean cosine between the travel direction and the scattered
/// one (positive forward), estimated from samples; Rayleigh's and the isotropic one's is 0.
#[test]
fn mean_cosines() {
    let d = travel();
    let n = 200_000;
    for (g, p) in [
        (0.7, Phase::Hg(HenyeyGreenstein { g: 0.7 })),
        (-0.5, Phase::Hg(HenyeyGreenstein { g: -0.5 })),
        (0.0, Phase::Rayleigh(Rayleigh)),
        (0.0, Phase::Isotropic(Isotropic)),
    ] {
        let mut rng = Pcg32::new(11, 2);
        let mut sum = 0.0f64;
        let mut sum2 = 0.0f64;
        for _ in 0..n {
            let s = p
                .sample(d, rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()))
                .unwrap();
            let c = s.wo.dot(d) as f64;
            sum += c;
            sum2 += c * c;
        }
        let mean = sum / n as f64;
        let sd = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!(
            (mean - g).abs() < 4.0 * sd + 1e-4,
            "{}: {mean} vs {g}",
            p.name()
        );
    }
    // Forward is along the travel direction (Mitsuba's convention, written with wi = -d).
    let hg = HenyeyGreenstein { g: 0.5 };
    assert!(hg.eval(d, d) > hg.eval(d, -d));
    let expected = (1.0 - 0.25) / (4.0 * PI * 0.5f32.powi(3));
    assert!((hg.eval(d, d) - expected).abs() < 1e-4 * expected);
    assert!((Rayleigh.eval(d, d) - 3.0 / (8.0 * PI)).abs() < 1e-6);
}

fn grid(resolution: [usize; 3], channels: usize, data: Vec<f32>) -> Volume {
    Volume {
        to_local: Mat4::IDENTITY,
        values: VolumeValues::Grid(Grid::new(
            GridVolume {
                resolution,
                channels,
                data,
            },
            false,
        )),
    }
}

/// Samples sit at cell centres, values between them are trilinear, and points beyond the outer
/// centres take the border's values (Mitsuba's clamp).
#[test]
fn grids_interpolate_between_cell_centres() {
    let data: Vec<f32> = (0..8).map(|i| i as f32).collect();
    let v = grid([2, 2, 2], 1, data);
    assert_eq!(v.eval(Vec3::new(0.25, 0.25, 0.25)), Vec3::splat(0.0));
    assert_eq!(v.eval(Vec3::new(0.75, 0.75, 0.75)), Vec3::splat(7.0));
    // Halfway in x between samples 0 and 1.
    assert!((v.eval(Vec3::new(0.5, 0.25, 0.25)).x - 0.5).abs() < 1e-6);
    // The mean of all eight at the centre.
    assert!((v.eval(Vec3::splat(0.5)).x - 3.5).abs() < 1e-6);
    assert_eq!(v.eval(Vec3::new(0.0, 0.0, 0.0)), Vec3::splat(0.0));
    assert_eq!(v.eval(Vec3::new(1.5, 0.9, 0.9)), Vec3::splat(7.0));
    assert_eq!(v.max(), 7.0);
    let rgb = grid([1, 1, 1], 3, vec![0.1, 0.2, 0.3]);
    assert_eq!(rgb.eval(Vec3::splat(0.3)), Vec3::new(0.1, 0.2, 0.3));
}

/// A ray meets the unit cube where it is, through the volume's transform.
#[test]
fn volumes_bound_their_box() {
    let mut v = grid([1, 1, 1], 1, vec![1.0]);
    v.to_local = Mat4::from_scale_rotation_translation(
        Vec3::splat(2.0),
        glam::Quat::IDENTITY,
        Vec3::new(1.0, 0.0, 0.0),
    )
    .inverse();
    // The box is [1, 3] x [0, 2] x [0, 2].
    let ray = Ray::new(Vec3::new(0.0, 1.0, 1.0), Vec3::X);
    let (t0, t1) = v.range(&ray, 100.0).unwrap();
    assert!(
        (t0 - 1.0).abs() < 1e-6 && (t1 - 3.0).abs() < 1e-6,
        "{t0} {t1}"
    );
    assert_eq!(v.range(&ray, 2.0).unwrap().1, 2.0);
    assert!(v.range(&ray, 0.5).is_none());
    let miss = Ray::new(Vec3::new(0.0, 5.0, 1.0), Vec3::X);
    assert!(v.range(&miss, 100.0).is_none());
}

/// The heterogeneous medium's majorant bounds its extinction everywhere (trilinear values never
/// exceed the largest sample).
#[test]
fn the_majorant_bounds_the_extinction() {
    let mut rng = Pcg32::new(5, 5);
    let data: Vec<f32> = (0..4 * 3 * 5).map(|_| rng.next_f32()).collect();
    let m = Heterogeneous::new(
        grid([4, 3, 5], 1, data),
        grid([1, 1, 1], 1, vec![0.5]),
        7.0,
        Phase::Isotropic(Isotropic),
    );
    for _ in 0..10_000 {
        let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 1.2 - 0.1;
        let (sigma_t, sigma_s) = m.coefficients(p);
        assert!(sigma_t.max_element() <= m.majorant().x * (1.0 + 1e-6));
        assert!((sigma_s - sigma_t * 0.5).abs().max_element() < 1e-6);
    }
}
