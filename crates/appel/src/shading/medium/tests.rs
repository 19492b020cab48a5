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

/// A grid of random values, a third of them zero (sparse, as clouds are).
fn random_grid(rng: &mut Pcg32, res: [usize; 3], nearest: bool) -> Volume {
    let n = res.iter().product::<usize>();
    let data = (0..n)
        .map(|_| {
            let v = rng.next_f32();
            if v < 0.33 {
                0.0
            } else {
                v
            }
        })
        .collect();
    let mut v = grid(res, 1, data);
    if let VolumeValues::Grid(g) = &mut v.values {
        g.nearest = nearest;
    }
    v
}

fn medium_over(sigma_t: Volume) -> Heterogeneous {
    Heterogeneous::new(
        sigma_t,
        grid([1, 1, 1], 1, vec![0.5]),
        7.0,
        Phase::Isotropic(Isotropic),
    )
}

/// Every majorant cell bounds the extinction at every point in it, for trilinear and nearest
/// lookups, over majorant grids from one cell (the global majorant) to one cell per sample, and
/// at points beyond the cube (the lookups clamp).
#[test]
fn local_majorants_bound_the_extinction() {
    let mut rng = Pcg32::new(5, 5);
    for nearest in [false, true] {
        let mut m = medium_over(random_grid(&mut rng, [9, 6, 13], nearest));
        for res in [[1, 1, 1], [3, 2, 4], [9, 6, 13], [5, 7, 2]] {
            m.set_majorant_resolution(res);
            for _ in 0..20_000 {
                let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 1.2 - 0.1;
                let (sigma_t, sigma_s) = m.coefficients(p);
                let bound = m.majorants.at(p);
                assert!(
                    sigma_t.max_element() <= bound,
                    "{res:?} nearest {nearest}: {sigma_t} above {bound} at {p}"
                );
                assert!((sigma_s - sigma_t * 0.5).abs().max_element() < 1e-5);
            }
        }
    }
}

/// The local majorants are tight where the grid is empty: in a grid whose one dense block sits
/// in a corner, only the cells the block's interpolation reaches are above zero.
#[test]
fn local_majorants_are_zero_where_the_grid_is_empty() {
    let corner = |x: usize, y: usize, z: usize| x < 4 && y < 4 && z < 4;
    let mut data = vec![0.0f32; 16 * 16 * 16];
    for (i, v) in data.iter_mut().enumerate() {
        if corner(i % 16, i / 16 % 16, i / 256) {
            *v = 8.0;
        }
    }
    let m = medium_over(grid([16, 16, 16], 1, data));
    assert_eq!(m.majorants.resolution, [4, 4, 4]);
    // The block fills cell 0 along each axis; interpolation in cell 1 reaches back half a
    // sample to sample 3, in the block, and cell 2 reads nothing of it.
    let busy: Vec<usize> = (0..64).filter(|&i| m.majorants.max[i] > 0.0).collect();
    assert_eq!(busy, vec![0, 1, 4, 5, 16, 17, 20, 21]);
    assert!((m.majorants.max[0] / 56.0 - 1.0).abs() < 1e-5);
}

/// A ray's walk through the majorant grid covers its part inside the box, segment after segment
/// without gaps, and each segment's majorant is that of the cell its points are in.
#[test]
fn the_walk_covers_the_ray_in_its_cells() {
    let mut rng = Pcg32::new(9, 3);
    let mut v = random_grid(&mut rng, [9, 6, 13], false);
    v.to_local = Mat4::from_scale_rotation_translation(
        Vec3::new(2.0, 1.0, 3.0),
        glam::Quat::from_rotation_y(0.4),
        Vec3::new(-1.0, 0.2, 0.5),
    )
    .inverse();
    let mut m = medium_over(v);
    m.set_majorant_resolution([3, 2, 4]);
    let mut walked = 0;
    for i in 0..2_000 {
        // Rays from around the box toward points near it, from inside it, and along the axes
        // (a zero component never crosses a face on its axis).
        let to_world = m.sigma_t.to_local.inverse();
        let near_box = |rng: &mut Pcg32, spread: f32| {
            let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            to_world.transform_point3((u - 0.5) * spread + 0.5)
        };
        let origin = near_box(&mut rng, if i % 3 == 0 { 0.9 } else { 3.0 });
        let mut dir = near_box(&mut rng, 1.2) - origin;
        if i % 5 == 0 {
            dir = [Vec3::X, -Vec3::Y, Vec3::Z, -Vec3::X, Vec3::Y][i / 5 % 5];
        }
        let ray = Ray::new(origin, dir.normalize());
        let t_max = 2.0 + 8.0 * rng.next_f32();
        let range = m.sigma_t.range(&ray, t_max);
        let segments: Vec<MajorantSegment> = m.majorants(&ray, t_max).collect();
        let Some((t0, t1)) = range else {
            assert!(segments.is_empty());
            continue;
        };
        walked += 1;
        assert_eq!(segments.first().map(|s| s.t0), Some(t0));
        assert_eq!(segments.last().map(|s| s.t1), Some(t1));
        for w in segments.windows(2) {
            assert_eq!(w[0].t1, w[1].t0);
        }
        for s in &segments {
            assert!(s.t0 <= s.t1);
            if s.t1 - s.t0 < 1e-4 {
                continue;
            }
            for f in [0.01, 0.5, 0.99] {
                let t = s.t0 + (s.t1 - s.t0) * f;
                let local = m.sigma_t.to_local.transform_point3(ray.at(t));
                assert_eq!(s.majorant.x, m.majorants.at(local), "{ray:?} at {t}");
                assert!(m.coefficients(ray.at(t)).0.x <= s.majorant.x);
            }
        }
    }
    assert!(walked > 1_000, "{walked} rays met the box");
}
