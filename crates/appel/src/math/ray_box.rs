//! A ray prepared for many ray-box (slab) tests, and the rounding bound that keeps those tests
//! conservative. Every structure clips rays to boxes with these: the BVH at each node, the grid,
//! kd-tree, octree and BSP at their root cell.

use super::{gamma, Ray};

/// A ray prepared for box tests: reciprocal direction and the sign of each component (the sign bit,
/// so that `-0` counts as negative and gets `1 / -0 = -inf`).
#[derive(Clone, Copy)]
pub struct RayBox {
    pub o: [f32; 3],
    pub inv: [f32; 3],
    pub neg: [bool; 3],
}

/// `1 + 2 gamma(3)`: scaling the far slab distance by this keeps the slab test conservative under
/// rounding (pbrt-v4 section 6.8.2, after Ize 2013, "Robust BVH ray traversal").
#[inline]
pub fn far_scale() -> f32 {
    1.0 + 2.0 * gamma(3)
}

impl RayBox {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let inv = ray.dir.recip();
        Self {
            o: ray.origin.into(),
            inv: inv.into(),
            neg: [
                ray.dir.x.is_sign_negative(),
                ray.dir.y.is_sign_negative(),
                ray.dir.z.is_sign_negative(),
            ],
        }
    }

    /// Slab test against `[min, max]` clipped to `[0, t_max]`. A zero direction component gives an
    /// infinite `inv`: the slab distances are then `+-inf` (outside or inside the slab), or NaN when the
    /// origin lies exactly on the slab's plane; `f32::max`/`min` ignore a NaN, which counts such a ray
    /// as inside, like [`super::Aabb::slab_intersect`].
    #[inline(always)]
    pub fn hits(&self, min: &[f32; 3], max: &[f32; 3], t_max: f32, far: f32) -> bool {
        let mut t0 = 0.0f32;
        let mut t1 = t_max;
        for a in 0..3 {
            let (lo, hi) = if self.neg[a] {
                (max[a], min[a])
            } else {
                (min[a], max[a])
            };
            t0 = t0.max((lo - self.o[a]) * self.inv[a]);
            t1 = t1.min((hi - self.o[a]) * self.inv[a] * far);
        }
        t0 <= t1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Aabb, Vec3};

    /// The node test and the box's own slab test agree on rays that clearly hit or miss, and the
    /// node test keeps a ray that touches the box only at a grazing rounding distance.
    #[test]
    fn node_test_agrees_with_the_box_slab_test() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let far = far_scale();
        for (o, d) in [
            (Vec3::new(-3.0, 0.2, 0.1), Vec3::X),
            (Vec3::new(-3.0, 1.5, 0.0), Vec3::X),
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.3, -0.4, 0.5)),
            (Vec3::new(-3.0, 1.0, 0.0), Vec3::new(1.0, -0.0, 0.0)),
            (Vec3::new(4.0, 4.0, 4.0), Vec3::new(1.0, 1.0, 1.0)),
            (Vec3::new(4.0, 4.0, 4.0), Vec3::new(-1.0, -1.0, -1.0)),
        ] {
            let r = Ray::new(o, d);
            let rb = RayBox::new(&r);
            let box_test = b.slab_intersect(&r, Vec3::from(rb.inv), f32::INFINITY * far);
            assert_eq!(
                rb.hits(&b.min.into(), &b.max.into(), f32::INFINITY, far),
                box_test.is_some(),
                "{o} {d}"
            );
        }
        assert!(far > 1.0 && far < 1.0 + 1e-6);
    }
}
