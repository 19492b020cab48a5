//! Implicit surfaces `f(x, y, z) = 0` given as a formula, inside a user-given bounding box.
//!
//! The formula is parsed ([`parse`]), compiled to a flat tape ([`tape`]) and evaluated three ways
//! from that one tape: f64 values, intervals ([`interval`], for root isolation along rays, see
//! [`root`]) and dual numbers ([`dual`], for normals and Newton steps). `f < 0` is the inside, so the
//! normal `grad f / |grad f|` points out. `docs/implicit.md` has the grammar and the guarantees.

pub mod dual;
pub mod interval;
pub mod num;
pub mod parse;
pub mod root;
pub mod slope;
pub mod tape;

pub use parse::FormulaError;
pub use tape::Tape;

use super::{PrimHit, SurfaceInteraction};
use crate::math::{gamma, Aabb, Ray, Vec2, Vec3};
use dual::Dual;
use glam::DVec3;
use root::{first_root, RaySegment, Scratch};
use std::cell::RefCell;

/// Roots are isolated to this fraction of the bounding box's diagonal.
pub const RELATIVE_WIDTH: f64 = 1e-7;

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// A compiled implicit surface and the box it is searched in.
#[derive(Clone, Debug, PartialEq)]
pub struct Implicit {
    pub tape: Tape,
    pub bounds: Aabb,
}

impl Implicit {
    pub fn new(formula: &str, bounds: Aabb) -> Result<Self, FormulaError> {
        Ok(Self {
            tape: Tape::compile(&parse::parse(formula)?),
            bounds,
        })
    }

    fn diagonal(&self) -> f64 {
        self.bounds.extent().as_dvec3().length()
    }

    /// First root of `f(o + t d)` in `(0, t_max)` within the box. The `u` of the hit carries the part
    /// of the f64 root that does not fit in the f32 `t`, so the interaction starts from the full
    /// precision root.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        let (t_enter, t_exit) = self.bounds.slab_intersect(ray, ray.dir.recip(), t_max)?;
        let seg = RaySegment {
            o: ray.origin.as_dvec3(),
            d: ray.dir.as_dvec3(),
        };
        let dlen = seg.d.length();
        if !(dlen > 0.0 && dlen.is_finite()) {
            return None;
        }
        let t1 = (t_exit as f64).min(t_max as f64);
        let width = RELATIVE_WIDTH * self.diagonal() / dlen;
        let t = SCRATCH.with(|s| {
            first_root(
                &self.tape,
                &seg,
                t_enter as f64,
                t1,
                width,
                &mut s.borrow_mut(),
            )
        })?;
        let t32 = t as f32;
        if !(t > 0.0 && t32 > 0.0 && t32 < t_max) {
            return None;
        }
        Some(PrimHit {
            t: t32,
            u: (t - t32 as f64) as f32,
            v: 0.0,
            sub: 0,
        })
    }

    fn grad(&self, p: DVec3) -> Dual {
        self.tape.eval(
            [Dual::var(p.x, 0), Dual::var(p.y, 1), Dual::var(p.z, 2)],
            &mut Vec::with_capacity(self.tape.len()),
        )
    }

    /// The hit point, moved onto the surface by Newton steps along the gradient, and the normal there.
    ///
    /// Where the gradient vanishes or is not finite (a cusp, such as the heart's), the normal falls back
    /// to `-ray.dir` (facing the viewer), so shading stays defined.
    pub fn interaction(&self, ray: &Ray, hit: &PrimHit) -> SurfaceInteraction {
        let t = hit.t as f64 + hit.u as f64;
        let mut p = ray.origin.as_dvec3() + t * ray.dir.as_dvec3();
        let diag = self.diagonal();
        let mut g = self.grad(p);
        for _ in 0..2 {
            let g2 = g.g.length_squared();
            if !(g2 > 0.0 && g2.is_finite() && g.v.is_finite()) {
                break;
            }
            let step = g.g * (g.v / g2);
            // Only small corrections: a big step means the linear model is not to be trusted here.
            if step.length() > 1e-4 * diag {
                break;
            }
            p -= step;
            g = self.grad(p);
        }
        let glen = g.g.length();
        let (n, dist) = if glen > 0.0 && glen.is_finite() && g.v.is_finite() {
            (
                (g.g / glen).as_vec3(),
                (g.v.abs() / glen).min(RELATIVE_WIDTH * diag),
            )
        } else {
            (-ray.dir.normalize(), RELATIVE_WIDTH * diag)
        };
        let p32 = p.as_vec3();
        // Rounding to f32, plus the first-order distance that remains to the surface.
        let p_error = gamma(2) * p32.abs() + Vec3::splat(dist as f32);
        // Spherical coordinates about the box centre, as arc lengths on a sphere of the box's size.
        let c = self.bounds.center();
        let dir = (p32 - c).normalize_or(Vec3::Y);
        let r = 0.5 * self.bounds.extent().min_element();
        let phi = dir.z.atan2(dir.x) + std::f32::consts::PI;
        let theta = dir.y.clamp(-1.0, 1.0).acos();
        SurfaceInteraction {
            p: p32,
            p_error,
            n,
            ns: n,
            uv: Vec2::new(phi, theta) * r,
            // Not a parametrization of the surface: the shading frame picks its own tangent.
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            tangent: None,
        }
    }
}

#[cfg(test)]
pub(crate) mod tests;
