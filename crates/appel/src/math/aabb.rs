use super::{gamma, Ray};
use glam::Vec3;

/// An axis-aligned bounding box. The empty box has `min = +inf`, `max = -inf`, so that `union` with it
/// is the identity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.include(p))
    }

    pub fn include(self, p: Vec3) -> Self {
        Self::new(self.min.min(p), self.max.max(p))
    }

    pub fn union(self, o: Aabb) -> Self {
        Self::new(self.min.min(o.min), self.max.max(o.max))
    }

    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn surface_area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    pub fn largest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Slab test (Kay & Kajiya 1986, in the form of Williams et al. 2005): returns the parametric
    /// interval `(t_enter, t_exit)` of the ray inside the box clipped to `[0, t_max]`, or `None`.
    ///
    /// `inv_dir` is `1 / ray.dir`: a direction component of `+0` or `-0` gives `+inf` or `-inf`, whose
    /// slab is then either the whole line or empty, correctly. The far distance is scaled by
    /// `1 + 2 gamma(3)` (pbrt-v4, Ize 2013) so that rounding never loses a hit on the box.
    #[inline]
    pub fn slab_intersect(&self, ray: &Ray, inv_dir: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let mut t_enter = 0.0f32;
        let mut t_exit = t_max;
        for axis in 0..3 {
            let (t_near, t_far) = slab(
                self.min[axis],
                self.max[axis],
                ray.origin[axis],
                inv_dir[axis],
            )?;
            // NaN-safe: comparisons with NaN keep the previous bound.
            if t_near > t_enter {
                t_enter = t_near;
            }
            if t_far < t_exit {
                t_exit = t_far;
            }
            if t_enter > t_exit {
                return None;
            }
        }
        Some((t_enter, t_exit))
    }
}

/// One slab of the slab test. With `origin` exactly on a plane of the slab and a zero direction
/// component, `0 * inf` is NaN: such a ray runs inside the plane of the face and we count it inside.
#[inline]
fn slab(lo: f32, hi: f32, origin: f32, inv_dir: f32) -> Option<(f32, f32)> {
    if inv_dir.is_infinite() {
        // Parallel to the slab: inside for every t, or never.
        return if origin >= lo && origin <= hi {
            Some((f32::NEG_INFINITY, f32::INFINITY))
        } else {
            None
        };
    }
    let mut t_near = (lo - origin) * inv_dir;
    let mut t_far = (hi - origin) * inv_dir;
    if t_near > t_far {
        std::mem::swap(&mut t_near, &mut t_far);
    }
    Some((t_near, t_far * (1.0 + 2.0 * gamma(3))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Aabb {
        Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
    }

    fn hit(o: Vec3, d: Vec3) -> Option<(f32, f32)> {
        unit_box().slab_intersect(&Ray::new(o, d), d.recip(), f32::INFINITY)
    }

    #[test]
    fn ray_through_the_box_gets_entry_and_exit() {
        let (t0, t1) = hit(Vec3::new(-3.0, 0.0, 0.0), Vec3::X).unwrap();
        assert!((t0 - 2.0).abs() < 1e-6);
        assert!((t1 - 4.0).abs() < 1e-5);
    }

    #[test]
    fn positive_and_negative_zero_components_are_both_handled() {
        for zero in [0.0f32, -0.0] {
            let d = Vec3::new(1.0, zero, zero);
            assert!(hit(Vec3::new(-3.0, 0.5, -0.5), d).is_some());
            assert!(hit(Vec3::new(-3.0, 1.5, 0.0), d).is_none());
            assert!(hit(Vec3::new(-3.0, 0.0, -1.5), d).is_none());
        }
    }

    #[test]
    fn ray_in_the_plane_of_a_face_counts_as_inside() {
        assert!(hit(Vec3::new(-3.0, 1.0, 0.0), Vec3::X).is_some());
    }

    #[test]
    fn box_behind_the_ray_is_missed_t_exit_must_be_non_negative() {
        assert!(hit(Vec3::new(3.0, 0.0, 0.0), Vec3::X).is_none());
        // Origin inside: t_enter clamps to 0, t_exit is positive.
        let (t0, t1) = hit(Vec3::ZERO, Vec3::X).unwrap();
        assert_eq!(t0, 0.0);
        assert!(t1 >= 1.0);
    }

    #[test]
    fn t_max_clips_the_interval() {
        let b = unit_box();
        let r = Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
        assert!(b.slab_intersect(&r, r.dir.recip(), 1.5).is_none());
        assert!(b.slab_intersect(&r, r.dir.recip(), 2.5).is_some());
    }

    #[test]
    fn union_with_empty_is_identity() {
        let b = unit_box();
        assert_eq!(b.union(Aabb::EMPTY), b);
        assert!(Aabb::EMPTY.is_empty());
        assert_eq!(Aabb::EMPTY.surface_area(), 0.0);
    }
}
