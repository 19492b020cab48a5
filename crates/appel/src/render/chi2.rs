//! Chi-square goodness-of-fit test of a direction sampler against its claimed density, after the
//! tests of Mitsuba 3 (`mitsuba/python/chi2.py`) and pbrt-v3/v4 (`chi2test`).
//!
//! The sphere is cut into `cos_theta_bins x phi_bins` cells of equal solid angle, uniform in
//! `cos θ ∈ [-1, 1]` and `φ ∈ [-π, π)` (in these coordinates `dω = d(cos θ) dφ`, so a cell's
//! probability is the plain double integral of the pdf over it). The sampler is run `samples`
//! times with random numbers from [`Pcg32`]; each returned direction is counted in its cell. The
//! expected count of a cell is `samples` times the pdf integrated over the cell by adaptive Simpson
//! quadrature (nested 1D rules, as Mitsuba's `integrate` does). Cells expected to receive fewer than
//! [`MIN_EXPECTED`] samples are pooled, lowest first, into one cell (Pearson's statistic is only
//! chi-square distributed when every expected count is at least about 5), then
//! `X² = Σ (observed - expected)² / expected` is compared with the chi-square distribution of
//! `cells - 1` degrees of freedom. The hypothesis "the samples follow the pdf" is rejected when
//! the p-value is below the significance level corrected for the number of tests run (Šidák:
//! `1 - (1 - α)^(1 / tests)`), so a suite of many tests keeps an overall false-failure rate `α`.
//!
//! A sampler may fail (return `None`): the pdf must then integrate to the probability of success,
//! since expected counts are taken against the number of attempts. A direction that lands in a
//! cell whose expected count is zero is a failure by itself (the sampler produces what the pdf says
//! is impossible), as is a direction that is not finite and unit length.
//!
//! Usage (an emitter's or a BSDF's sampler; `u1` is a scalar for a discrete choice, `u2` a 2D
//! point for the direction):
//! ```ignore
//! let outcome = chi2::Chi2Test::new(chi2::Config { tests: 12, ..Default::default() })
//!     .run(|u1, u2| bsdf.sample(wo, u1, u2).map(|s| s.wi), |wi| bsdf.pdf(wo, wi));
//! assert!(outcome.passed, "{outcome}");
//! ```

use crate::math::{Vec2, Vec3};
use std::f64::consts::PI;
use std::fmt;

/// Cells expected to receive fewer samples than this are pooled (the usual rule of thumb for
/// Pearson's test, also Mitsuba's and pbrt's).
pub(crate) const MIN_EXPECTED: f64 = 5.0;

/// The PCG32 generator (O'Neill 2014, "PCG: a family of simple fast space-efficient statistically
/// good algorithms for random number generation"): small, fast and reproducible, so that every
/// test sees the same samples on every run.
#[derive(Clone, Debug)]
pub(crate) struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    pub(crate) fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Pcg32 {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    pub(crate) fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1): the top 24 bits, so that every value is exactly representable.
    pub(crate) fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    pub(crate) fn next_vec2(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }
}

/// How a test is run.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Config {
    /// Cells along `cos θ` (keep it even so that the horizon is a cell boundary: one-sided
    /// densities jump there, which quadrature across a cell would blur).
    pub cos_theta_bins: usize,
    /// Cells along `φ`.
    pub phi_bins: usize,
    /// Calls of the sampler.
    pub samples: usize,
    /// Overall significance level `α`.
    pub significance: f64,
    /// Number of tests in the suite sharing `α` (Šidák correction).
    pub tests: usize,
    /// Seed of the random numbers.
    pub seed: u64,
    /// Relative tolerance of the adaptive quadrature of each cell.
    pub tolerance: f64,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            cos_theta_bins: 32,
            phi_bins: 64,
            samples: 200_000,
            significance: 0.01,
            tests: 1,
            seed: 7,
            tolerance: 1e-4,
        }
    }
}

/// What a test found.
#[derive(Clone, Debug)]
pub(crate) struct Outcome {
    pub passed: bool,
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// The per-test significance after the Šidák correction.
    pub threshold: f64,
    /// Total of the expected counts over `samples` (the integral of the pdf over the sphere).
    pub pdf_integral: f64,
    /// Fraction of the attempts that returned a direction.
    pub success_rate: f64,
    /// Why the test failed, when it did.
    pub reason: String,
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "chi2 {}: X^2 = {:.2}, dof = {}, p = {:.3e} (threshold {:.3e}), pdf integral = {:.5}, success rate = {:.5}{}{}",
            if self.passed { "passed" } else { "FAILED" },
            self.statistic,
            self.dof,
            self.p_value,
            self.threshold,
            self.pdf_integral,
            self.success_rate,
            if self.reason.is_empty() { "" } else { ": " },
            self.reason
        )
    }
}

/// A chi-square test with its configuration.
pub(crate) struct Chi2Test {
    pub config: Config,
}

impl Chi2Test {
    pub(crate) fn new(config: Config) -> Self {
        Chi2Test { config }
    }

    /// Index of the cell holding unit direction `w`.
    fn cell(&self, w: Vec3) -> usize {
        let c = &self.config;
        let u = ((w.z as f64 + 1.0) * 0.5 * c.cos_theta_bins as f64) as usize;
        let phi = (w.y as f64).atan2(w.x as f64);
        let v = ((phi + PI) / (2.0 * PI) * c.phi_bins as f64) as usize;
        u.min(c.cos_theta_bins - 1) * c.phi_bins + v.min(c.phi_bins - 1)
    }

    /// Counts where the sampler's directions land.
    pub(crate) fn histogram(
        &self,
        mut sample: impl FnMut(f32, Vec2) -> Option<Vec3>,
    ) -> Result<(Vec<f64>, usize), String> {
        let c = &self.config;
        let mut counts = vec![0.0; c.cos_theta_bins * c.phi_bins];
        let mut rng = Pcg32::new(c.seed, 0x5eed);
        let mut successes = 0;
        for _ in 0..c.samples {
            let u1 = rng.next_f32();
            let u2 = rng.next_vec2();
            if let Some(w) = sample(u1, u2) {
                if !w.is_finite() || (w.length() - 1.0).abs() > 1e-3 {
                    return Err(format!(
                        "sample({u1}, {u2}) returned {w}, not a unit direction"
                    ));
                }
                counts[self.cell(w)] += 1.0;
                successes += 1;
            }
        }
        Ok((counts, successes))
    }

    /// Expected counts: `samples` times the pdf integrated over each cell.
    pub(crate) fn expected(&self, pdf: impl Fn(Vec3) -> f32) -> Vec<f64> {
        let c = &self.config;
        let f = |cos_theta: f64, phi: f64| -> f64 {
            let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
            let w = Vec3::new(
                (sin_theta * phi.cos()) as f32,
                (sin_theta * phi.sin()) as f32,
                cos_theta as f32,
            );
            let p = pdf(w) as f64;
            if p.is_finite() {
                p
            } else {
                0.0
            }
        };
        let du = 2.0 / c.cos_theta_bins as f64;
        let dv = 2.0 * PI / c.phi_bins as f64;
        let mut expected = Vec::with_capacity(c.cos_theta_bins * c.phi_bins);
        for i in 0..c.cos_theta_bins {
            let (u0, u1) = (-1.0 + i as f64 * du, -1.0 + (i + 1) as f64 * du);
            for j in 0..c.phi_bins {
                let (v0, v1) = (-PI + j as f64 * dv, -PI + (j + 1) as f64 * dv);
                let integral = integrate_2d(&f, (u0, u1), (v0, v1), c.tolerance);
                expected.push(integral * c.samples as f64);
            }
        }
        expected
    }

    /// Runs the test: histogram of `sample`, expected counts from `pdf`, pooled Pearson statistic.
    pub(crate) fn run(
        &self,
        sample: impl FnMut(f32, Vec2) -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f32,
    ) -> Outcome {
        let c = &self.config;
        let threshold = 1.0 - (1.0 - c.significance).powf(1.0 / c.tests.max(1) as f64);
        let mut outcome = Outcome {
            passed: false,
            statistic: 0.0,
            dof: 0,
            p_value: 0.0,
            threshold,
            pdf_integral: 0.0,
            success_rate: 0.0,
            reason: String::new(),
        };
        let (observed, successes) = match self.histogram(sample) {
            Ok(h) => h,
            Err(reason) => {
                outcome.reason = reason;
                return outcome;
            }
        };
        outcome.success_rate = successes as f64 / c.samples as f64;
        let expected = self.expected(pdf);
        outcome.pdf_integral = expected.iter().sum::<f64>() / c.samples as f64;
        let (statistic, dof, reason) = pearson(&observed, &expected);
        outcome.statistic = statistic;
        outcome.dof = dof;
        if let Some(reason) = reason {
            outcome.reason = reason;
            return outcome;
        }
        outcome.p_value = chi2_survival(dof as f64, statistic);
        outcome.passed = outcome.p_value >= threshold;
        if !outcome.passed {
            outcome.reason = "the samples do not follow the pdf".into();
        }
        outcome
    }
}

/// Pearson's statistic over cells, those expected below [`MIN_EXPECTED`] pooled lowest first;
/// returns it, the degrees of freedom, and a reason to fail outright (samples where the pdf is
/// zero, or too few cells to test).
pub(crate) fn pearson(observed: &[f64], expected: &[f64]) -> (f64, usize, Option<String>) {
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let mut statistic = 0.0;
    let mut cells = 0;
    let (mut pooled_obs, mut pooled_exp) = (0.0, 0.0);
    for &i in &order {
        let (o, e) = (observed[i], expected[i]);
        if e <= 0.0 {
            // Mitsuba tolerates a handful of stray samples from rounding at cell edges; more
            // than 1e-5 of all samples where the density is zero is a sampler bug.
            if o > 0.0 && o > 1e-5 * observed.iter().sum::<f64>() {
                return (
                    0.0,
                    0,
                    Some(format!(
                        "{o} samples in a cell of zero probability (cell {i})"
                    )),
                );
            }
            pooled_obs += o;
            continue;
        }
        if e < MIN_EXPECTED {
            pooled_obs += o;
            pooled_exp += e;
            if pooled_exp >= MIN_EXPECTED {
                statistic += (pooled_obs - pooled_exp).powi(2) / pooled_exp;
                cells += 1;
                pooled_obs = 0.0;
                pooled_exp = 0.0;
            }
            continue;
        }
        statistic += (o - e).powi(2) / e;
        cells += 1;
    }
    if pooled_exp > 0.0 {
        // The remainder of the pooled cells, too small alone, joins the statistic as one cell.
        statistic += (pooled_obs - pooled_exp).powi(2) / pooled_exp;
        cells += 1;
    }
    if cells < 2 {
        return (statistic, 0, Some("fewer than two cells to compare".into()));
    }
    (statistic, cells - 1, None)
}

/// Adaptive Simpson quadrature of `f` over `[a, b]` (Kuncir 1962; Lyness 1969 for the
/// Richardson correction `(S2 - S1) / 15`).
fn adaptive_simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tolerance: f64) -> f64 {
    fn step(
        f: &dyn Fn(f64) -> f64,
        (a, b): (f64, f64),
        (fa, fm, fb): (f64, f64, f64),
        whole: f64,
        eps: f64,
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
        let (flm, frm) = (f(lm), f(rm));
        let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
        let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
        let delta = left + right - whole;
        if depth == 0 || delta.abs() <= 15.0 * eps {
            return left + right + delta / 15.0;
        }
        step(f, (a, m), (fa, flm, fm), left, 0.5 * eps, depth - 1)
            + step(f, (m, b), (fm, frm, fb), right, 0.5 * eps, depth - 1)
    }
    // Start from four panels, so that a peak inside the interval is not missed by the first
    // estimate agreeing with itself at three points.
    let n = 4;
    let h = (b - a) / n as f64;
    let mut total = 0.0;
    let mut estimates = [0.0; 4];
    let mut values = [(0.0, 0.0, 0.0); 4];
    for (k, (est, val)) in estimates.iter_mut().zip(values.iter_mut()).enumerate() {
        let (x0, x1) = (a + k as f64 * h, a + (k + 1) as f64 * h);
        let (f0, fm, f1) = (f(x0), f(0.5 * (x0 + x1)), f(x1));
        *est = h / 6.0 * (f0 + 4.0 * fm + f1);
        *val = (f0, fm, f1);
    }
    let scale = estimates.iter().map(|e| e.abs()).sum::<f64>().max(1e-300);
    let eps = tolerance * scale;
    for (k, (est, (f0, fm, f1))) in estimates.iter().zip(values).enumerate() {
        let (x0, x1) = (a + k as f64 * h, a + (k + 1) as f64 * h);
        total += step(f, (x0, x1), (f0, fm, f1), *est, eps / n as f64, 12);
    }
    total
}

/// Double integral over a rectangle by nested adaptive Simpson rules.
fn integrate_2d(
    f: &dyn Fn(f64, f64) -> f64,
    (u0, u1): (f64, f64),
    (v0, v1): (f64, f64),
    tolerance: f64,
) -> f64 {
    let inner = |u: f64| adaptive_simpson(&|v| f(u, v), v0, v1, tolerance);
    adaptive_simpson(&inner, u0, u1, tolerance)
}

/// `ln Γ(x)` for `x > 0` by the Lanczos approximation (g = 7, nine coefficients; Lanczos 1964,
/// coefficients of Godfrey), with the reflection formula below 1/2. Relative error near 1e-15.
pub(crate) fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
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
        // Γ(x) Γ(1 - x) = π / sin(πx)
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut sum = C[0];
    for (k, c) in C.iter().enumerate().skip(1) {
        sum += c / (x + k as f64);
    }
    let t = x + G + 0.5;
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// Regularized lower incomplete gamma `P(a, x) = γ(a, x) / Γ(a)`: its power series for
/// `x < a + 1`, else `1 - Q` from the continued fraction of the upper function (evaluated by the
/// modified Lentz method; Press et al., "Numerical Recipes", section 6.2, for the split).
pub(crate) fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x < a + 1.0 {
        gamma_p_series(a, x)
    } else {
        1.0 - gamma_q_fraction(a, x)
    }
}

/// Regularized upper incomplete gamma `Q(a, x) = 1 - P(a, x)`, accurate in the far tail.
pub(crate) fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    if x < a + 1.0 {
        1.0 - gamma_p_series(a, x)
    } else {
        gamma_q_fraction(a, x)
    }
}

/// `P(a, x) = x^a e^-x / Γ(a + 1) Σ_n x^n / ((a + 1) ... (a + n))`.
fn gamma_p_series(a: f64, x: f64) -> f64 {
    let mut term = 1.0 / a;
    let mut sum = term;
    let mut ap = a;
    for _ in 0..10_000 {
        ap += 1.0;
        term *= x / ap;
        sum += term;
        if term.abs() < sum.abs() * 1e-16 {
            break;
        }
    }
    (sum.ln() - x + a * x.ln() - ln_gamma(a)).exp()
}

/// `Q(a, x) = x^a e^-x / Γ(a) · 1 / (x + 1 - a - 1·(1 - a) / (x + 3 - a - 2·(2 - a) / (x + 5 - a - ...)))`.
fn gamma_q_fraction(a: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..10_000 {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        if d.abs() < TINY {
            d = TINY;
        }
        c = b + an / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < 1e-16 {
            break;
        }
    }
    (a * x.ln() - x - ln_gamma(a)).exp() * h
}

/// Probability that a chi-square variable of `dof` degrees of freedom exceeds `x`: the p-value
/// of Pearson's statistic, `Q(dof / 2, x / 2)`.
pub(crate) fn chi2_survival(dof: f64, x: f64) -> f64 {
    gamma_q(0.5 * dof, 0.5 * x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_gamma_matches_factorials_and_half_integers() {
        let mut fact = 1.0f64;
        for n in 1..20 {
            // Γ(n) = (n - 1)!
            assert!((ln_gamma(n as f64) - fact.ln()).abs() < 1e-12, "n = {n}");
            fact *= n as f64;
        }
        // Γ(1/2) = √π
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-13);
        // Γ(0.1) = 9.513507698668732 (tabulated)
        assert!((ln_gamma(0.1) - 9.513_507_698_668_732f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn incomplete_gamma_known_values() {
        // a = 1: P(1, x) = 1 - e^-x.
        for x in [0.01f64, 0.5, 1.0, 3.0, 10.0, 40.0] {
            assert!((gamma_p(1.0, x) - (1.0 - (-x).exp())).abs() < 1e-13);
            assert!((gamma_q(1.0, x) / (-x).exp() - 1.0).abs() < 1e-10);
        }
        // Chi-square with 2 dof: survival e^(-x/2); with 1 dof: erfc(sqrt(x/2)).
        assert!((chi2_survival(2.0, 7.0) - (-3.5f64).exp()).abs() < 1e-13);
        // erfc(sqrt(2.5)) = 0.025347318677468252 (Python's math.erfc).
        assert!((chi2_survival(1.0, 5.0) - 0.025_347_318_677_468_252).abs() < 1e-12);
        // Tabulated quantiles: P(X > 3.841459) = 0.05 for 1 dof; P(X > 23.209251) = 0.01 for
        // 10 dof; P(X > 1106.969) = 0.01 for 1000 dof.
        assert!((chi2_survival(1.0, 3.841_459) - 0.05).abs() < 1e-6);
        assert!((chi2_survival(10.0, 23.209_251) - 0.01).abs() < 1e-6);
        assert!((chi2_survival(1000.0, 1106.969) - 0.01).abs() < 1e-5);
        // Both branches agree where they meet.
        let (a, x) = (7.5, 8.5);
        assert!((gamma_p_series(a, x) + gamma_q_fraction(a, x) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn quadrature_of_a_peaked_function() {
        // ∫∫ over [-1, 1]² of a narrow Gaussian of total mass 1 (σ = 0.02).
        let s = 0.02f64;
        let f = |u: f64, v: f64| (-(u * u + v * v) / (2.0 * s * s)).exp() / (2.0 * PI * s * s);
        let total = integrate_2d(&f, (-1.0, 1.0), (-1.0, 1.0), 1e-6);
        assert!((total - 1.0).abs() < 1e-4, "{total}");
    }

    /// Uniform sphere sampling (u2 mapped to cos θ and φ).
    fn uniform_sphere(u: Vec2) -> Vec3 {
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u.y;
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// Cosine-weighted hemisphere sampling by Malley's method.
    fn cosine_hemisphere(u: Vec2) -> Vec3 {
        let r = u.x.sqrt();
        let phi = 2.0 * std::f32::consts::PI * u.y;
        let (x, y) = (r * phi.cos(), r * phi.sin());
        Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
    }

    fn quick() -> Chi2Test {
        Chi2Test::new(Config {
            samples: 100_000,
            cos_theta_bins: 16,
            phi_bins: 32,
            tests: 4,
            ..Default::default()
        })
    }

    #[test]
    fn accepts_correct_samplers() {
        let t = quick();
        let o = t.run(
            |_, u| Some(uniform_sphere(u)),
            |_| 1.0 / (4.0 * std::f32::consts::PI),
        );
        assert!(o.passed, "{o}");
        assert!((o.pdf_integral - 1.0).abs() < 1e-6, "{o}");
        let o = t.run(
            |_, u| Some(cosine_hemisphere(u)),
            |w| w.z.max(0.0) / std::f32::consts::PI,
        );
        assert!(o.passed, "{o}");
        // A sampler failing half of the time, with a pdf integrating to one half.
        let o = t.run(
            |u1, u| (u1 < 0.5).then(|| cosine_hemisphere(u)),
            |w| 0.5 * w.z.max(0.0) / std::f32::consts::PI,
        );
        assert!(o.passed, "{o}");
        assert!((o.success_rate - 0.5).abs() < 0.01);
    }

    #[test]
    fn rejects_wrong_samplers() {
        let t = quick();
        // Cosine-weighted samples against a uniform-hemisphere pdf.
        let o = t.run(
            |_, u| Some(cosine_hemisphere(u)),
            |w| {
                if w.z > 0.0 {
                    0.5 / std::f32::consts::PI
                } else {
                    0.0
                }
            },
        );
        assert!(!o.passed, "{o}");
        // A slightly wrong density: cos^1.1 sampled as cos.
        let o = t.run(
            |_, u| Some(cosine_hemisphere(u)),
            |w| w.z.max(0.0).powf(1.1) * 2.1 / (2.0 * std::f32::consts::PI),
        );
        assert!(!o.passed, "{o}");
        // Samples where the pdf is zero.
        let o = t.run(
            |_, u| Some(uniform_sphere(u)),
            |w| w.z.max(0.0) / std::f32::consts::PI,
        );
        assert!(!o.passed && !o.reason.is_empty(), "{o}");
        // Not unit length.
        let o = t.run(|_, u| Some(2.0 * uniform_sphere(u)), |_| 0.25);
        assert!(!o.passed, "{o}");
    }
}
