//! Pixel reconstruction filters, with Mitsuba 3's shapes and defaults. A sample at film position
//! `p` adds to every pixel whose centre `c` has `|p - c| < radius` on both axes, with the weight
//! `eval(p.x - c.x) * eval(p.y - c.y)` (a separable filter, splatted as Mitsuba's image blocks do).

use crate::description::FilterDesc;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filter {
    /// Weight 1 inside the radius (0.5: each sample counts in its own pixel only).
    Box { radius: f32 },
    /// `max(0, 1 - |x| / radius)`.
    Tent { radius: f32 },
    /// `max(0, exp(-x^2 / (2 stddev^2)) - exp(-radius^2 / (2 stddev^2)))` with `radius = 4 stddev`:
    /// the Gaussian shifted to reach zero at its radius, as Mitsuba's `gaussian`.
    Gaussian { stddev: f32 },
}

impl Filter {
    pub fn new(d: &FilterDesc) -> Self {
        match *d {
            FilterDesc::Box { radius } => Filter::Box { radius },
            FilterDesc::Tent { radius } => Filter::Tent { radius },
            FilterDesc::Gaussian { stddev } => Filter::Gaussian { stddev },
        }
    }

    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box { radius } | Filter::Tent { radius } => radius,
            Filter::Gaussian { stddev } => 4.0 * stddev,
        }
    }

    /// The one-dimensional weight at offset `x` from a pixel centre.
    #[inline]
    pub fn eval(&self, x: f32) -> f32 {
        match *self {
            Filter::Box { radius } => {
                if x.abs() < radius {
                    1.0
                } else {
                    0.0
                }
            }
            Filter::Tent { radius } => (1.0 - x.abs() / radius).max(0.0),
            Filter::Gaussian { stddev } => {
                let alpha = -1.0 / (2.0 * stddev * stddev);
                let r = 4.0 * stddev;
                ((alpha * x * x).exp() - (alpha * r * r).exp()).max(0.0)
            }
        }
    }

    /// Whether each sample reaches exactly its own pixel with weight 1 (the box of radius 1/2), so
    /// that the film can skip the splat.
    pub fn is_pixel_box(&self) -> bool {
        matches!(*self, Filter::Box { radius } if radius == 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_have_mitsubas_shapes() {
        let tent = Filter::Tent { radius: 1.0 };
        assert_eq!(tent.eval(0.0), 1.0);
        assert_eq!(tent.eval(0.5), 0.5);
        assert_eq!(tent.eval(1.5), 0.0);
        let g = Filter::Gaussian { stddev: 0.5 };
        assert_eq!(g.radius(), 2.0);
        assert!((g.eval(0.0) - (1.0 - (-8.0f32).exp())).abs() < 1e-6);
        assert_eq!(g.eval(2.0), 0.0);
        let b = Filter::Box { radius: 0.5 };
        assert!(b.is_pixel_box());
        assert_eq!((b.eval(0.49), b.eval(0.5)), (1.0, 0.0));
    }
}
