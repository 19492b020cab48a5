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
