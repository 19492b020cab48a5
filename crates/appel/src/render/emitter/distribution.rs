//! Piecewise-constant distributions on [0, 1] and [0, 1]² (pbrt-v4 section A.4 and A.5): a
//! cumulative table built once, inverted by binary search per sample.

use glam::Vec2;

/// A piecewise-constant density on [0, 1] with `n` equal bins, proportional to non-negative weights.
/// Also serves as a discrete distribution over the bins.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// The weights as given (negative or non-finite ones read as zero).
    func: Vec<f32>,
    /// `cdf[i]` is the probability of bins `0..i`; `cdf[n] = 1`.
    cdf: Vec<f32>,
    /// Sum of the weights (not divided by `n`).
    sum: f64,
}

impl Distribution1D {
    /// Weights all zero (or none) give the uniform distribution, so that sampling never fails.
    pub fn new(weights: &[f32]) -> Self {
        let clean = |w: f32| if w.is_finite() && w > 0.0 { w } else { 0.0 };
        let func: Vec<f32> = weights.iter().map(|&w| clean(w)).collect();
        let mut sum = 0.0f64;
        let mut cdf = Vec::with_capacity(func.len() + 1);
        cdf.push(0.0);
        // The running sum is kept in f64 so that long tables (an environment map's rows) stay exact
        // to f32 precision at their end.
        let mut acc = Vec::with_capacity(func.len());
        for &f in &func {
            sum += f as f64;
            acc.push(sum);
        }
        let n = func.len().max(1) as f64;
        for (i, &a) in acc.iter().enumerate() {
            cdf.push(if sum > 0.0 {
                (a / sum) as f32
            } else {
                ((i + 1) as f64 / n) as f32
            });
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Self { func, cdf, sum }
    }

    pub fn len(&self) -> usize {
        self.func.len()
    }

    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// Sum of the weights; zero when they were all zero.
    pub fn sum(&self) -> f64 {
        self.sum
    }

    /// Probability of bin `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        match (self.cdf.get(i), self.cdf.get(i + 1)) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// The bin whose cumulative interval holds `u`, never one of probability zero.
    fn find(&self, u: f32) -> usize {
        // First index with cdf[index] > u, minus one; bins of zero probability have an empty
        // interval and so are never returned.
        let n = self.func.len();
        let i = self.cdf.partition_point(|&c| c <= u);
        i.saturating_sub(1).min(n.saturating_sub(1))
    }

    /// Picks a bin with probability `pmf`: (index, probability, `u` rescaled to [0, 1) within the bin
    /// so that it can be used again).
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let i = self.find(u);
        let p = self.pmf(i);
        let reuse = if p > 0.0 {
            ((u - self.cdf[i]) / p).clamp(0.0, ONE_MINUS_EPSILON)
        } else {
            0.0
        };
        (i, p, reuse)
    }

    /// A point of [0, 1) with density `pdf`: (x, density at x, bin index).
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let (i, p, reuse) = self.sample_discrete(u);
        let n = self.func.len() as f32;
        let x = ((i as f32 + reuse) / n).min(ONE_MINUS_EPSILON);
        (x, p * n, i)
    }

    /// Density at `x` in [0, 1] (zero outside).
    pub fn pdf(&self, x: f32) -> f32 {
        if !(0.0..=1.0).contains(&x) || self.func.is_empty() {
            return 0.0;
        }
        let n = self.func.len();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.pmf(i) * n as f32
    }
}

/// The largest f32 below one: samples stay in [0, 1).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A piecewise-constant density on [0, 1]² over an `nx` by `ny` grid of cells: a marginal over rows
/// (y) and one conditional distribution over x per row.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    rows: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// `weights` in row-major order, `nx` per row.
    pub fn new(weights: &[f32], nx: usize, ny: usize) -> Self {
        assert_eq!(
            weights.len(),
            nx * ny,
            "Distribution2D: weights must be nx * ny"
        );
        let rows: Vec<Distribution1D> = weights.chunks(nx).map(Distribution1D::new).collect();
        let row_sums: Vec<f32> = rows.iter().map(|r| r.sum() as f32).collect();
        let marginal = Distribution1D::new(&row_sums);
        Self { rows, marginal }
    }

    pub fn nx(&self) -> usize {
        self.rows.first().map_or(0, Distribution1D::len)
    }

    pub fn ny(&self) -> usize {
        self.rows.len()
    }

    /// A point of [0, 1)² with its density, and the cell it fell in.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32, [usize; 2]) {
        let (y, pdf_y, iy) = self.marginal.sample_continuous(u.y);
        let (x, pdf_x, ix) = self.rows[iy].sample_continuous(u.x);
        (Vec2::new(x, y), pdf_x * pdf_y, [ix, iy])
    }

    /// Probability of cell (`ix`, `iy`).
    pub fn pmf_cell(&self, ix: usize, iy: usize) -> f32 {
        match self.rows.get(iy) {
            Some(row) => self.marginal.pmf(iy) * row.pmf(ix),
            None => 0.0,
        }
    }

    /// Density at `p` in [0, 1]² (zero outside).
    pub fn pdf(&self, p: Vec2) -> f32 {
        if !(0.0..=1.0).contains(&p.x) || !(0.0..=1.0).contains(&p.y) || self.rows.is_empty() {
            return 0.0;
        }
        let (nx, ny) = (self.nx(), self.ny());
        let ix = ((p.x * nx as f32) as usize).min(nx - 1);
        let iy = ((p.y * ny as f32) as usize).min(ny - 1);
        self.pmf_cell(ix, iy) * (nx * ny) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::super::chi2_sphere::Rng;
    use super::*;

    /// Pearson's statistic of `counts` against `probs` times the total, and its degrees of
    /// freedom; probabilities of zero must see no samples.
    fn pearson(counts: &[f64], probs: &[f64]) -> (f64, usize) {
        let n: f64 = counts.iter().sum();
        let mut chi2 = 0.0;
        let mut dof = 0;
        for (&o, &p) in counts.iter().zip(probs) {
            if p == 0.0 {
                assert_eq!(o, 0.0, "samples in a bin of zero probability");
                continue;
            }
            chi2 += (o - n * p).powi(2) / (n * p);
            dof += 1;
        }
        (chi2, dof - 1)
    }

    #[test]
    fn one_dimensional_sampling_matches_its_density() {
        let weights = [0.5, 0.0, 3.0, 1.0, 0.0, 2.5, 0.25, 4.0];
        let d = Distribution1D::new(&weights);
        let total: f32 = weights.iter().sum();
        for (i, w) in weights.iter().enumerate() {
            assert!((d.pmf(i) - w / total).abs() < 1e-6);
        }
        // Density integrates to one (midpoint rule, exact for a step function on this grid).
        let m = 800;
        let integral: f32 = (0..m)
            .map(|k| d.pdf((k as f32 + 0.5) / m as f32))
            .sum::<f32>()
            / m as f32;
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
        // Samples over 32 sub-bins (four per bin) against the density's mass there.
        let sub = 32;
        let mut counts = vec![0.0; sub];
        let mut rng = Rng::new(3);
        for _ in 0..200_000 {
            let (x, pdf, i) = d.sample_continuous(rng.next_f32());
            assert!((0.0..1.0).contains(&x));
            assert_eq!(pdf, d.pdf(x));
            assert_eq!(i, (x * 8.0) as usize);
            counts[(x * sub as f32) as usize] += 1.0;
        }
        let probs: Vec<f64> = (0..sub).map(|k| d.pmf(k / 4) as f64 / 4.0).collect();
        let (chi2, dof) = pearson(&counts, &probs);
        // The 0.1% critical value of χ² with 23 degrees of freedom is 49.7.
        assert_eq!(dof, 23);
        assert!(chi2 < 49.7, "chi2 {chi2}");
    }

    #[test]
    fn two_dimensional_sampling_matches_its_density() {
        let (nx, ny) = (5, 4);
        let weights: Vec<f32> = (0..nx * ny)
            .map(|i| {
                if i % 7 == 3 {
                    0.0
                } else {
                    1.0 + (i * i % 11) as f32
                }
            })
            .collect();
        let d = Distribution2D::new(&weights, nx, ny);
        let total: f32 = weights.iter().sum();
        let mut counts = vec![0.0; nx * ny];
        let mut rng = Rng::new(5);
        for _ in 0..200_000 {
            let (p, pdf, [ix, iy]) = d.sample(rng.vec2());
            assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            assert!(
                (pdf - d.pdf(p)).abs() <= 1e-5 * pdf,
                "{pdf} vs {}",
                d.pdf(p)
            );
            assert_eq!(
                [ix, iy],
                [(p.x * nx as f32) as usize, (p.y * ny as f32) as usize]
            );
            counts[iy * nx + ix] += 1.0;
        }
        let probs: Vec<f64> = weights.iter().map(|&w| (w / total) as f64).collect();
        for (k, &p) in probs.iter().enumerate() {
            assert!((d.pmf_cell(k % nx, k / nx) as f64 - p).abs() < 1e-6);
        }
        let (chi2, dof) = pearson(&counts, &probs);
        // The 0.1% critical value of χ² with 16 degrees of freedom is 39.25.
        assert_eq!(dof, 16);
        assert!(chi2 < 39.25, "chi2 {chi2}");
        // The density integrates to one.
        let m = 100;
        let mut integral = 0.0;
        for a in 0..m {
            for b in 0..m {
                integral += d.pdf(Vec2::new(
                    (a as f32 + 0.5) / m as f32,
                    (b as f32 + 0.5) / m as f32,
                ));
            }
        }
        assert!((integral / (m * m) as f32 - 1.0).abs() < 1e-4);
    }

    #[test]
    fn zero_weights_are_uniform_and_never_stuck() {
        let d = Distribution1D::new(&[0.0, 0.0]);
        assert_eq!(d.pmf(1), 0.5);
        assert_eq!(d.sample_discrete(0.75).0, 1);
        let d = Distribution1D::new(&[0.0, 1.0, 0.0]);
        assert_eq!(d.sample_discrete(0.0).0, 1);
        assert_eq!(d.sample_discrete(ONE_MINUS_EPSILON).0, 1);
        assert_eq!(d.pdf(0.1), 0.0);
    }
}
