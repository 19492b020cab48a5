//! A chi-square goodness-of-fit test of a direction sampler against its claimed solid-angle
//! density (after Mitsuba's `chi2` module): directions are binned over a spherical cap in equal
//! steps of cos θ and φ about an axis, the density is integrated over each bin, bins expecting
//! fewer than five samples are pooled, and Pearson's statistic is turned into a p-value.

use glam::{Vec2, Vec3};
use std::f64::consts::PI;

/// Where to bin and how much to sample.
pub struct Spec {
    /// Axis of the binned cap (unit).
    pub axis: Vec3,
    /// Directions with cos θ below this fall outside the bins (and must have zero density there).
    pub cos_min: f64,
    pub n_theta: usize,
    pub n_phi: usize,
    pub samples: usize,
    pub seed: u64,
}

impl Spec {
    pub fn sphere(samples: usize) -> Self {
        Self {
            axis: Vec3::Z,
            cos_min: -1.0,
            n_theta: 24,
            n_phi: 48,
            samples,
            seed: 7,
        }
    }

    pub fn cap(axis: Vec3, cos_min: f64, samples: usize) -> Self {
        Self {
            axis: axis.normalize(),
            cos_min,
            n_theta: 16,
            n_phi: 32,
            samples,
            seed: 7,
        }
    }
}

/// SplitMix64: independent uniform numbers, as the test's multinomial model assumes.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn vec2(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }
}

/// The outcome: the p-value and the integral of the density over the cap.
pub struct Outcome {
    pub p_value: f64,
    pub integral: f64,
}

/// Runs the test; `Err` names the first bin that received samples where the density is zero.
pub fn test(
    spec: &Spec,
    mut sample: impl FnMut(Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) -> Result<Outcome, String> {
    let (t1, t2) = crate::math::orthonormal_basis(spec.axis);
    let bins = spec.n_theta * spec.n_phi;
    let dcos = (1.0 - spec.cos_min) / spec.n_theta as f64;
    let dphi = 2.0 * PI / spec.n_phi as f64;
    let dir = |cos: f64, phi: f64| {
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        ((sin * phi.cos()) as f32 * t1 + (sin * phi.sin()) as f32 * t2 + cos as f32 * spec.axis)
            .normalize()
    };

    let mut observed = vec![0.0f64; bins + 1];
    let mut rng = Rng::new(spec.seed);
    for _ in 0..spec.samples {
        let bin = sample(rng.vec2()).and_then(|d| {
            let cos = d.dot(spec.axis) as f64;
            if cos < spec.cos_min {
                return None;
            }
            let mut phi = (d.dot(t2) as f64).atan2(d.dot(t1) as f64);
            if phi < 0.0 {
                phi += 2.0 * PI;
            }
            let it = (((1.0 - cos) / dcos) as usize).min(spec.n_theta - 1);
            let ip = ((phi / dphi) as usize).min(spec.n_phi - 1);
            Some(it * spec.n_phi + ip)
        });
        observed[bin.unwrap_or(bins)] += 1.0;
    }

    // Each bin's probability by the midpoint rule on a k x k grid in (cos θ, φ), where the
    // solid-angle measure is flat.
    const K: usize = 12;
    let mut expected = vec![0.0f64; bins + 1];
    let mut integral = 0.0;
    for it in 0..spec.n_theta {
        for ip in 0..spec.n_phi {
            let mut sum = 0.0;
            for a in 0..K {
                let cos = 1.0 - (it as f64 + (a as f64 + 0.5) / K as f64) * dcos;
                for b in 0..K {
                    let phi = (ip as f64 + (b as f64 + 0.5) / K as f64) * dphi;
                    sum += pdf(dir(cos, phi)) as f64;
                }
            }
            let prob = sum * dcos * dphi / (K * K) as f64;
            integral += prob;
            expected[it * spec.n_phi + ip] = prob * spec.samples as f64;
        }
    }
    expected[bins] = (spec.samples as f64 * (1.0 - integral)).max(0.0);

    // Pearson's statistic over bins expecting at least 5, the others pooled together.
    let mut chi2 = 0.0;
    let mut dof = 0usize;
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    for (i, (&o, &e)) in observed.iter().zip(&expected).enumerate() {
        if e == 0.0 && o > 0.0 && i < bins {
            return Err(format!(
                "{o} samples in bin (θ {}, φ {}) of zero density",
                i / spec.n_phi,
                i % spec.n_phi
            ));
        }
        if e < 5.0 {
            pool_obs += o;
            pool_exp += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pool_exp > 0.0 {
        chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        dof += 1;
    } else if pool_obs > 0.0 {
        return Err(format!(
            "{pool_obs} samples where the density integrates to zero"
        ));
    }
    let dof = dof.saturating_sub(1).max(1);
    Ok(Outcome {
        p_value: gamma_q(dof as f64 / 2.0, chi2 / 2.0),
        integral,
    })
}

/// Asserts the test passes at significance 1% and that the density integrates to `mass` over the
/// cap (within `tol`).
pub fn assert_fits(
    name: &str,
    spec: &Spec,
    sample: impl FnMut(Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
    mass: f64,
    tol: f64,
) {
    let out = test(spec, sample, pdf).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(
        out.p_value > 0.01,
        "{name}: chi-square rejects the sampler (p = {:.2e})",
        out.p_value
    );
    assert!(
        (out.integral - mass).abs() < tol,
        "{name}: the density integrates to {} over the bins, expected {mass}",
        out.integral
    );
}

/// ln Γ(x) for x > 0 (Lanczos's approximation, g = 7, nine terms).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, &c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised upper incomplete gamma function Q(a, x) = P(χ²_{2a} > 2x): its power series
/// below x = a + 1, Legendre's continued fraction (by Lentz's method) above.
fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * prefactor
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        prefactor * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p_values_of_known_statistics() {
        // χ² with 2 degrees of freedom: Q = exp(-x / 2).
        assert!((gamma_q(1.0, 1.5) - (-1.5f64).exp()).abs() < 1e-12);
        // χ² = 124.342 with 100 degrees of freedom is the 5% critical value.
        assert!((gamma_q(50.0, 124.342 / 2.0) - 0.05).abs() < 1e-4);
        assert!((gamma_q(5.0, 2.0) - 0.947_346_982_656_289).abs() < 1e-9);
    }

    #[test]
    fn rejects_a_wrong_density() {
        // Uniform sphere samples against a density twice too large on the upper half, and half on
        // the lower: the harness must notice.
        let spec = Spec::sphere(50_000);
        let sample = |u: Vec2| Some(super::super::warp::square_to_sphere(u));
        let wrong = |d: Vec3| if d.z > 0.0 { 1.5 } else { 0.5 } / (4.0 * std::f32::consts::PI);
        let out = test(&spec, sample, wrong).unwrap();
        assert!(out.p_value < 1e-6, "p = {}", out.p_value);
        let right = |_: Vec3| 1.0 / (4.0 * std::f32::consts::PI);
        assert_fits("uniform sphere", &spec, sample, right, 1.0, 1e-6);
    }
}
