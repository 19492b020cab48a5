//! Delta and ratio tracking over local majorants against closed forms: a grid whose one dense
//! block fills a corner and is empty elsewhere, its transmittance along rays through and past
//! the block integrated numerically, tracked with the grid of majorants and with one global
//! majorant (which must agree: the majorants change the variance and the cost, never the
//! expectation).

use super::{medium_transmittance, sample_flight};
use crate::math::{Ray, Vec3};
use crate::render::sampler::{IndependentSampler, Sampler};
use crate::shading::medium::volume::{Grid, VolumeValues};
use crate::shading::medium::{Heterogeneous, Isotropic, Medium, Phase, Volume};
use glam::Mat4;

const ALBEDO: f32 = 0.6;

/// 16^3 samples over the box `[0, 2]^3`, 9 in the 4^3 samples of the corner at the origin and
/// 0 elsewhere; the albedo constant.
fn corner_medium(majorant_resolution: [usize; 3]) -> Medium {
    let mut data = vec![0.0f32; 16 * 16 * 16];
    for (i, v) in data.iter_mut().enumerate() {
        if i % 16 < 4 && i / 16 % 16 < 4 && i / 256 < 4 {
            *v = 9.0;
        }
    }
    let sigma_t = Volume {
        to_local: Mat4::from_scale(Vec3::splat(2.0)).inverse(),
        values: VolumeValues::Grid(Grid {
            resolution: [16, 16, 16],
            channels: 1,
            data,
            nearest: false,
        }),
    };
    let albedo = Volume {
        to_local: Mat4::IDENTITY,
        values: VolumeValues::Constant(Vec3::splat(ALBEDO)),
    };
    let mut m = Heterogeneous::new(sigma_t, albedo, 1.0, Phase::Isotropic(Isotropic));
    m.set_majorant_resolution(majorant_resolution);
    Medium::Heterogeneous(m)
}

/// Rays through the dense corner (where a global majorant is tight), along its edge (partly
/// in it) and through the empty rest only.
fn rays() -> [(Ray, f32); 3] {
    [
        (
            Ray::new(
                Vec3::new(-1.0, 0.2, 0.25),
                Vec3::new(1.0, 0.05, 0.02).normalize(),
            ),
            4.0,
        ),
        (
            Ray::new(
                Vec3::new(0.3, -0.5, 0.45),
                Vec3::new(0.1, 1.0, 0.15).normalize(),
            ),
            3.5,
        ),
        (
            Ray::new(
                Vec3::new(2.5, 1.5, 1.2),
                Vec3::new(-1.0, -0.1, 0.2).normalize(),
            ),
            3.0,
        ),
    ]
}

/// The extinction at `p`: the grid's inside its box `[0, 2]^3`, 0 outside (where the grid's
/// lookup would clamp).
fn extinction(m: &Medium, p: Vec3) -> f64 {
    if p.min_element() < 0.0 || p.max_element() > 2.0 {
        return 0.0;
    }
    m.coefficients(p).0.x as f64
}

/// The optical depth `∫ sigma_t` from the ray's origin to each of `steps + 1` evenly spaced
/// distances up to `t_end`, by the midpoint rule on that fine partition (trilinear extinction
/// is smooth between sample planes).
fn optical_depths(m: &Medium, ray: &Ray, t_end: f32, steps: usize) -> Vec<f64> {
    let h = t_end as f64 / steps as f64;
    let mut tau = 0.0f64;
    let mut out = Vec::with_capacity(steps + 1);
    out.push(0.0);
    for i in 0..steps {
        let t = (i as f64 + 0.5) * h;
        tau += extinction(m, ray.at(t as f32)) * h;
        out.push(tau);
    }
    out
}

/// Mean and standard error.
fn mean_error(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

fn assert_close(estimates: &[f64], expected: f64, what: &str) {
    let (mean, error) = mean_error(estimates);
    assert!(
        (mean - expected).abs() <= 4.5 * error + 1e-6,
        "{what}: {mean} +- {error}, expected {expected}"
    );
}

const N: usize = 20_000;
const STEPS: usize = 40_000;

/// Ratio tracking's transmittance is the closed form's, with local and with global majorants.
#[test]
fn ratio_tracking_over_local_majorants_is_unbiased() {
    let mut sampler = IndependentSampler::new(11);
    sampler.start_pixel_sample(0, 0, 0);
    for (k, (ray, t_end)) in rays().into_iter().enumerate() {
        let exact = (-optical_depths(&corner_medium([1, 1, 1]), &ray, t_end, STEPS)[STEPS]).exp();
        for res in [[4, 4, 4], [1, 1, 1]] {
            let m = corner_medium(res);
            let estimates: Vec<f64> = (0..N)
                .map(|i| medium_transmittance(&m, &ray, t_end, i % 3, &mut sampler).x as f64)
                .collect();
            assert_close(&estimates, exact, &format!("ray {k}, majorants {res:?}"));
        }
    }
}

/// Delta tracking's free flights: reaching the end has the transmittance's expectation, and
/// scattering before distance `t` that of `∫ T(s) sigma_s(s) ds` up to `t`, with local and with
/// global majorants.
#[test]
fn delta_tracking_over_local_majorants_is_unbiased() {
    let mut sampler = IndependentSampler::new(12);
    sampler.start_pixel_sample(0, 0, 0);
    for (k, (ray, t_end)) in rays().into_iter().enumerate() {
        let reference = corner_medium([1, 1, 1]);
        let tau = optical_depths(&reference, &ray, t_end, STEPS);
        let h = t_end as f64 / STEPS as f64;
        // Scattering before each quarter of the way.
        let quarters = [0.25, 0.5, 0.75, 1.0].map(|q| (q * STEPS as f64) as usize);
        let scattered: Vec<f64> = quarters
            .iter()
            .map(|&end| {
                (0..end)
                    .map(|i| {
                        let t = (i as f64 + 0.5) * h;
                        let sigma = extinction(&reference, ray.at(t as f32));
                        (-0.5 * (tau[i] + tau[i + 1])).exp() * sigma * ALBEDO as f64 * h
                    })
                    .sum()
            })
            .collect();
        for res in [[4, 4, 4], [1, 1, 1]] {
            let m = corner_medium(res);
            let flights: Vec<(Option<f32>, f64)> = (0..N)
                .map(|i| {
                    let f = sample_flight(&m, &ray, t_end, i % 3, &mut sampler);
                    let t = f.scatter.map(|p| (p - ray.origin).dot(ray.dir));
                    (t, f.weight.x as f64)
                })
                .collect();
            let what = format!("ray {k}, majorants {res:?}");
            let escaped: Vec<f64> = flights
                .iter()
                .map(|&(t, w)| if t.is_none() { w } else { 0.0 })
                .collect();
            assert_close(&escaped, (-tau[STEPS]).exp(), &format!("{what}, escape"));
            for (q, &end) in quarters.iter().enumerate() {
                let t_q = end as f32 * h as f32;
                let before: Vec<f64> = flights
                    .iter()
                    .map(|&(t, w)| if t.is_some_and(|t| t < t_q) { w } else { 0.0 })
                    .collect();
                assert_close(
                    &before,
                    scattered[q],
                    &format!("{what}, scattering before {t_q}"),
                );
            }
        }
    }
}
