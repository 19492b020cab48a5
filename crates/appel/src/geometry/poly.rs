//! Real roots of low-degree polynomials on an interval, by isolating them between the roots of the
//! derivative (where the polynomial is monotonic) and refining each bracket with safeguarded Newton
//! (Collins & Loos 1976 in spirit; Press et al., `rtsafe`, for the refinement). Unlike the closed-form
//! quartic (Ferrari), no step cancels catastrophically: each root is found to the precision the
//! evaluation of the polynomial allows.

/// Up to four roots, ascending.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Roots {
    pub count: usize,
    pub values: [f64; 4],
}

impl Roots {
    fn push(&mut self, t: f64) {
        // A root found at the shared end of two brackets would come twice.
        if self.count > 0 && self.values[self.count - 1] == t {
            return;
        }
        if self.count < 4 {
            self.values[self.count] = t;
            self.count += 1;
        }
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.count]
    }
}

/// `sum c[i] t^i` by Horner's rule.
pub fn eval(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * t + ci)
}

/// Value and derivative.
fn eval_slope(c: &[f64], t: f64) -> (f64, f64) {
    let mut v = 0.0;
    let mut d = 0.0;
    for &ci in c.iter().rev() {
        d = d * t + v;
        v = v * t + ci;
    }
    (v, d)
}

/// The real roots in `[lo, hi]` of `sum c[i] t^i` (ascending coefficients, degree at most 4).
/// Double roots are found only where they are exact zeros of the computed polynomial.
pub fn real_roots(c: &[f64], lo: f64, hi: f64) -> Roots {
    real_roots_with(c, lo, hi, |t| eval_slope(c, t))
}

/// Like [`real_roots`], but the signs and Newton steps at the top level come from `f` (value and
/// derivative), a more accurate evaluation of the same polynomial (such as a factored form); the
/// coefficients `c` only locate the critical points that separate the roots.
pub fn real_roots_with(c: &[f64], lo: f64, hi: f64, f: impl Fn(f64) -> (f64, f64)) -> Roots {
    let mut roots = Roots::default();
    let mut n = c.len().min(5);
    while n > 0 && c[n - 1] == 0.0 {
        n -= 1;
    }
    let c = &c[..n];
    if n <= 1 || lo.partial_cmp(&hi).is_none_or(|o| o.is_gt()) {
        return roots;
    }
    if n == 2 {
        let t = -c[0] / c[1];
        if t >= lo && t <= hi {
            roots.push(t);
        }
        return roots;
    }
    let mut deriv = [0.0; 4];
    for i in 1..n {
        deriv[i - 1] = i as f64 * c[i];
    }
    let crit = real_roots(&deriv[..n - 1], lo, hi);
    let mut a = lo;
    let mut fa = f(a).0;
    for &b in crit.as_slice().iter().chain(std::iter::once(&hi)) {
        let fb = f(b).0;
        if fa == 0.0 {
            roots.push(a);
        } else if fb != 0.0 && (fa < 0.0) != (fb < 0.0) {
            roots.push(bracketed(&f, a, b, fa));
        }
        a = b;
        fa = fb;
    }
    if fa == 0.0 {
        roots.push(a);
    }
    roots
}

/// The root in `[a, b]` of a polynomial monotonic there, with `f(a) = fa` and `f(b)` of the other sign.
fn bracketed(f: impl Fn(f64) -> (f64, f64), mut a: f64, mut b: f64, fa: f64) -> f64 {
    let neg_at_a = fa < 0.0;
    let mut t = 0.5 * (a + b);
    for _ in 0..100 {
        let (v, dv) = f(t);
        if v == 0.0 {
            return t;
        }
        if (v < 0.0) == neg_at_a {
            a = t;
        } else {
            b = t;
        }
        let newton = t - v / dv;
        let next = if newton > a && newton < b {
            newton
        } else {
            0.5 * (a + b)
        };
        if next == t || next <= a || next >= b {
            return t;
        }
        t = next;
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_roots(r: &[f64]) -> Vec<f64> {
        let mut c = vec![1.0];
        for &x in r {
            let mut next = vec![0.0; c.len() + 1];
            for (i, &ci) in c.iter().enumerate() {
                next[i + 1] += ci;
                next[i] -= x * ci;
            }
            c = next;
        }
        c
    }

    #[test]
    fn quartic_with_four_real_roots() {
        let r = real_roots(&from_roots(&[-3.0, 0.5, 1.0, 7.25]), -10.0, 10.0);
        assert_eq!(r.count, 4);
        for (a, b) in r.as_slice().iter().zip([-3.0, 0.5, 1.0, 7.25]) {
            assert!((a - b).abs() < 1e-12, "{a} {b}");
        }
        let r = real_roots(&from_roots(&[-3.0, 0.5, 1.0, 7.25]), 0.9, 7.0);
        assert_eq!(r.as_slice().len(), 1);
    }

    #[test]
    fn close_roots_and_no_roots() {
        let r = real_roots(&from_roots(&[1.0, 1.0 + 1e-6, 5.0, 6.0]), 0.0, 10.0);
        assert_eq!(r.count, 4);
        assert!((r.values[1] - (1.0 + 1e-6)).abs() < 1e-9);
        // (t^2 + 1)(t^2 + 4) has no real roots.
        assert_eq!(real_roots(&[4.0, 0.0, 5.0, 0.0, 1.0], -10.0, 10.0).count, 0);
        // Degenerate leading coefficients reduce the degree.
        assert_eq!(
            real_roots(&[-2.0, 1.0, 0.0, 0.0, 0.0], 0.0, 5.0).as_slice(),
            &[2.0]
        );
    }
}
