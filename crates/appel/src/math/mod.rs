//! Vectors, rays, bounding boxes and floating-point error bounds.

mod aabb;
mod f64x2;
mod f64x4;
mod float;
mod ray;
mod ray_box;

pub use aabb::Aabb;
pub use f64x2::{F64x2, Lanes, Mask2};
pub use f64x4::Avx2;
#[cfg(target_arch = "x86_64")]
pub use f64x4::{F64x4, Mask4, RayF64x4};
pub use float::{
    gamma, offset_ray_origin, offset_ray_origin_by, offset_ray_origin_to_side, surface_offset,
};
pub use glam::{Vec2, Vec3};
pub use ray::{Ray, RayF64};
pub use ray_box::{far_scale, RayBox};

/// An orthonormal basis (`s`, `t`, `n`) around a unit vector `n` (Duff et al. 2017, "Building an
/// orthonormal basis, revisited"): branch-free and continuous except at the sign flip of `n.z`.
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}
