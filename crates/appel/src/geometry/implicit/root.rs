//! The first root of `f(o + t d)` on a stretch of a ray, by interval root isolation (Mitchell 1990,
//! "Robust ray intersection with interval arithmetic"; Knoll et al. 2009, "Fast ray tracing of
//! arbitrary implicit surfaces with interval and affine arithmetic").
//!
//! Depth-first over `[t0, t1]`, nearer half first: a stretch whose interval enclosure excludes 0
//! cannot hold a root and is dropped. A stretch where the enclosure of the derivative along the ray
//! excludes 0 is monotonic (Mitchell 1990, section 4): it holds one root if the ends differ in sign,
//! refined directly, and none otherwise. The others are halved down to `width`. The first stretch that
//! survives at that width holds the first root (up to `width`), which is then refined:
//! - with a sign change at its ends, by Newton's method safeguarded by bisection, to full precision;
//! - without one (a tangent touch, or a thin feature crossed twice inside the stretch), by one Newton
//!   step from the midpoint: it is accepted if it lands inside the stretch. A double root
//!   `a (t - t_c)^2` sends the step to `(m + t_c) / 2`, inside; a ray leaving the surface from just
//!   above it has its root behind the origin, outside, and is rejected, so secondary rays never re-hit
//!   the surface they leave even where interval overestimation cannot exclude their first stretch.
//!
//! A stretch at the finest width whose enclosure is unbounded holds a singularity (a pole of `1/x`),
//! where `f` changes sign without a root; it is skipped.

use super::dual::Dual;
use super::interval::Interval;
use super::num::Num;
use super::slope::Slope;
use super::tape::Tape;
use glam::DVec3;

/// Scratch space for evaluations, reused across the many evaluations of one ray.
#[derive(Default)]
pub struct Scratch {
    stack: Vec<(f64, f64)>,
    slopes: Vec<Slope>,
    duals: Vec<Dual>,
    values: Vec<f64>,
}

/// Upper limit on interval evaluations for one ray; a formula that needs more (a fractal-like
/// pathological one) is reported as missed rather than stalling the render.
pub const MAX_EVALUATIONS: usize = 1 << 16;

pub struct RaySegment {
    pub o: DVec3,
    pub d: DVec3,
}

impl RaySegment {
    fn point(&self, t: f64) -> [f64; 3] {
        (self.o + t * self.d).to_array()
    }

    fn value(&self, tape: &Tape, t: f64, s: &mut Scratch) -> f64 {
        tape.eval(self.point(t), &mut s.values)
    }

    /// `f` and `df/dt` at `t`, by dual numbers.
    fn value_slope(&self, tape: &Tape, t: f64, s: &mut Scratch) -> (f64, f64) {
        let p = self.point(t);
        let r = tape.eval(
            [Dual::var(p[0], 0), Dual::var(p[1], 1), Dual::var(p[2], 2)],
            &mut s.duals,
        );
        (r.v, r.g.dot(self.d))
    }

    /// Enclosures of `f` and of `df/dt` over `t in [a, b]`.
    fn enclosure(&self, tape: &Tape, a: f64, b: f64, s: &mut Scratch) -> Slope {
        let t = Interval::new(a, b);
        let coord = |axis: usize| Slope {
            v: Interval::constant(self.o[axis]).add(t.mul(Interval::constant(self.d[axis]))),
            d: Interval::constant(self.d[axis]),
        };
        tape.eval([coord(0), coord(1), coord(2)], &mut s.slopes)
    }
}

/// The first root in `[t0, t1]`, isolated to `width` then refined; `None` if there is none.
pub fn first_root(
    tape: &Tape,
    ray: &RaySegment,
    t0: f64,
    t1: f64,
    width: f64,
    s: &mut Scratch,
) -> Option<f64> {
    let mut stack = std::mem::take(&mut s.stack);
    stack.clear();
    stack.push((t0, t1));
    let result = isolate(tape, ray, width, &mut stack, s);
    s.stack = stack;
    result
}

fn isolate(
    tape: &Tape,
    ray: &RaySegment,
    width: f64,
    stack: &mut Vec<(f64, f64)>,
    s: &mut Scratch,
) -> Option<f64> {
    let mut evaluations = 0;
    while let Some((a, b)) = stack.pop() {
        evaluations += 1;
        if evaluations > MAX_EVALUATIONS {
            return None;
        }
        let Slope { v: f, d: df } = ray.enclosure(tape, a, b, s);
        if !f.contains_zero() {
            continue;
        }
        if !df.contains_zero() {
            // Monotonic here: one root if the ends differ in sign, none otherwise.
            // A root exactly at t = 0 is the surface a ray starts on: not a hit (t must be > 0).
            let fa = ray.value(tape, a, s);
            if fa == 0.0 {
                if a > 0.0 {
                    return Some(a);
                }
                continue;
            }
            let fb = ray.value(tape, b, s);
            if fb == 0.0 {
                return Some(b);
            }
            if (fa < 0.0) != (fb < 0.0) {
                return Some(newton_bisection(tape, ray, a, b, fa, s));
            }
            continue;
        }
        let m = 0.5 * (a + b);
        if b - a <= width || m <= a || m >= b {
            // An unbounded enclosure at the finest width means a pole (`1/x` at 0), where the sign
            // changes without a root: not a surface.
            if !(f.lo.is_finite() && f.hi.is_finite()) {
                continue;
            }
            if let Some(t) = refine(tape, ray, a, b, s) {
                return Some(t);
            }
            continue;
        }
        stack.push((m, b));
        stack.push((a, m));
    }
    None
}

/// Inside a stretch `[a, b]` whose enclosure contains 0: the root, or `None` (see module docs).
fn refine(tape: &Tape, ray: &RaySegment, a: f64, b: f64, s: &mut Scratch) -> Option<f64> {
    let fa = ray.value(tape, a, s);
    if fa == 0.0 && a > 0.0 {
        return Some(a);
    }
    let fb = ray.value(tape, b, s);
    if fa != 0.0 && fa.signum() != fb.signum() && !fb.is_nan() && !fa.is_nan() {
        return Some(newton_bisection(tape, ray, a, b, fa, s));
    }
    let m = 0.5 * (a + b);
    let (f, df) = ray.value_slope(tape, m, s);
    if f == 0.0 {
        return Some(m);
    }
    // A thin feature crossed twice inside the stretch, with the midpoint inside it.
    if fa != 0.0 && (f < 0.0) != (fa < 0.0) && !fa.is_nan() && !f.is_nan() {
        return Some(newton_bisection(tape, ray, a, m, fa, s));
    }
    let t = m - f / df;
    (t > 0.0 && t >= a && t <= b).then_some(t)
}

/// A root in `[a, b]` where `f(a)` (= `fa`) and `f(b)` differ in sign: Newton steps while they stay
/// inside the bracket and shrink it, bisection otherwise (Press et al., `rtsafe`).
fn newton_bisection(
    tape: &Tape,
    ray: &RaySegment,
    mut a: f64,
    mut b: f64,
    fa: f64,
    s: &mut Scratch,
) -> f64 {
    let neg_at_a = fa < 0.0;
    let mut t = 0.5 * (a + b);
    for _ in 0..100 {
        let (f, df) = ray.value_slope(tape, t, s);
        if f == 0.0 || f.is_nan() {
            return t;
        }
        if (f < 0.0) == neg_at_a {
            a = t;
        } else {
            b = t;
        }
        let newton = t - f / df;
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
    use super::super::parse::parse;
    use super::*;

    fn tape(s: &str) -> Tape {
        Tape::compile(&parse(s).unwrap())
    }

    fn root(f: &str, o: [f64; 3], d: [f64; 3], t1: f64) -> Option<f64> {
        let ray = RaySegment {
            o: DVec3::from(o),
            d: DVec3::from(d),
        };
        first_root(&tape(f), &ray, 0.0, t1, 1e-7 * t1, &mut Scratch::default())
    }

    #[test]
    fn finds_the_nearer_of_two_roots() {
        let t = root(
            "x^2 + y^2 + z^2 - 1",
            [0.0, 0.0, -5.0],
            [0.0, 0.0, 1.0],
            10.0,
        )
        .unwrap();
        assert!((t - 4.0).abs() < 1e-12, "{t}");
    }

    #[test]
    fn a_thin_slab_far_along_the_ray_is_found() {
        // |z - 7| < 1e-6: a slab two micrometres thick at distance 7 of a 10-long segment. No sign
        // change at any coarse sample: only the interval test can find it.
        let t = root("abs(z - 7) - 1e-6", [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 10.0).unwrap();
        assert!((t - (7.0 - 1e-6)).abs() < 1e-9, "{t}");
        let t = root(
            "(x - 0.3)^2 + y^2 + (z - 9)^2 - 1e-10",
            [0.3, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            10.0,
        )
        .unwrap();
        assert!((t - (9.0 - 1e-5)).abs() < 1e-9, "{t}");
    }

    #[test]
    fn tangent_touch_is_reported() {
        // The sphere's touch below can come out as an exact 0 by cancellation in `1 + z^2 - 1`; a
        // parabolic cylinder `y = (z - 3.3)^2` touched along y = 0 has no such cancellation:
        // f = -(t - 3.3)^2 is never 0 at a computed point, only the double-root acceptance finds it.
        // (3.3 is not a dyadic fraction of 10, so no midpoint lands on it exactly.)
        let t = root("y - (z - 3.3)^2", [0.0; 3], [0.0, 0.0, 1.0], 10.0).unwrap();
        assert!((t - 3.3).abs() < 1e-6, "{t}");
        let t = root(
            "y - (x - 1.32)^2 - (z - 3.3)^2",
            [0.0; 3],
            [0.4, 0.0, 1.0],
            10.0,
        )
        .unwrap();
        assert!((t - 3.3).abs() < 1e-6, "{t}");
        let t = root(
            "x^2 + y^2 + z^2 - 1",
            [0.0, 1.0, -5.0],
            [0.0, 0.0, 1.0],
            10.0,
        )
        .unwrap();
        assert!((t - 5.0).abs() < 1e-5, "{t}");
        assert!(root(
            "x^2 + y^2 + z^2 - 1",
            [0.0, 1.001, -5.0],
            [0.0, 0.0, 1.0],
            10.0
        )
        .is_none());
    }

    #[test]
    fn a_ray_starting_exactly_on_the_surface_finds_the_next_root() {
        // Origin on the sphere, pointing through it: the root at t = 0 is not a hit, the far side is.
        let t = root(
            "x^2 + y^2 + z^2 - 1",
            [0.0, 0.0, -1.0],
            [0.0, 0.0, 1.0],
            10.0,
        )
        .unwrap();
        assert!((t - 2.0).abs() < 1e-12, "{t}");
    }

    #[test]
    fn empty_stretches_and_degenerate_formulas_terminate() {
        assert!(root("x^2 + 1", [0.0; 3], [1.0, 0.0, 0.0], 10.0).is_none());
        // Zero everywhere: the first point after the start is a root.
        let t = root("x - x", [0.0; 3], [1.0, 0.0, 0.0], 10.0).unwrap();
        assert!(t > 0.0 && t < 1e-5, "{t}");
        assert!(root("1/x", [-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 2.0).is_none());
        // Infinitely many roots accumulating at 0: the first one after the start is found.
        let t = root("sin(1/x)", [0.01, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0).unwrap();
        assert!(
            (0.01 + t - 1.0 / (31.0 * std::f64::consts::PI)).abs() < 1e-9,
            "{t}"
        );
    }
}
