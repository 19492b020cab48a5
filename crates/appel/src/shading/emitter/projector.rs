//! Mitsuba 3's `projector` emitter: the reciprocal of a perspective camera, a pinhole that
//! projects an irradiance image into the scene. The image lies on the plane z = 1 in front of the
//! pinhole; its value there is the irradiance (times π and `scale`) that a plane perpendicular to
//! the axis at unit distance receives, so that a constant image lights such a plane uniformly.

use super::{EmitterRay, EmitterSample};
use crate::shading::texture::Texture;
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct Projector {
    /// Projector-to-world transform: the pinhole at the origin looking down +z, image x to the
    /// left (+x) and up (+y) as in Mitsuba's `lookat`.
    from_world: Mat4,
    to_world: Mat4,
    position: Vec3,
    /// The local +z axis in world space (not normalized when `to_world` scales, as in Mitsuba).
    axis: Vec3,
    irradiance: Texture,
    scale: f32,
    /// tan of half the horizontal field of view.
    tan_half_x: f32,
    /// Image width over height.
    aspect: f32,
}

impl Projector {
    /// `tan_half_x` spans the image's width; `aspect` is its width over its height.
    pub fn new(
        to_world: Mat4,
        irradiance: Texture,
        scale: f32,
        tan_half_x: f32,
        aspect: f32,
    ) -> Self {
        Self {
            from_world: to_world.inverse(),
            to_world,
            position: to_world.transform_point3(Vec3::ZERO),
            axis: to_world.transform_vector3(Vec3::Z),
            irradiance,
            scale,
            tan_half_x,
            aspect,
        }
    }

    /// The image coordinates of local point `local` (Mitsuba's perspective `camera_to_sample`:
    /// u runs right to left along x, v top to bottom along y), or `None` outside the image.
    fn uv(&self, local: Vec3) -> Option<Vec2> {
        if local.z <= 0.0 {
            return None;
        }
        let k = 0.5 / (local.z * self.tan_half_x);
        let uv = Vec2::new(0.5 - k * local.x, 0.5 - k * self.aspect * local.y);
        ((0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y)).then_some(uv)
    }

    pub fn sample_li(&self, p: Vec3) -> Option<EmitterSample> {
        let local = self.from_world.transform_point3(p);
        let uv = self.uv(local)?;
        let to = self.position - p;
        let dist2 = to.length_squared();
        if dist2.is_nan() || dist2 <= 0.0 || !dist2.is_finite() {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = to / dist;
        // Irradiance π·scale·E(uv)/z² on a plane perpendicular to the axis, which the plane
        // receives at cos θ from an intensity I/dist²: I/dist² = π·scale·E(uv) / (z² cos θ).
        let cos_theta = -self.axis.dot(wi);
        if cos_theta <= 0.0 {
            return None;
        }
        let weight = self.irradiance.eval(uv) * (PI * self.scale / (local.z * local.z * cos_theta));
        Some(EmitterSample {
            wi,
            dist,
            weight,
            pdf: 1.0,
            delta: true,
        })
    }

    /// The flux through the image rectangle at z = 1: its irradiance π·scale·mean(E) times its
    /// area, 2 tan(fov_x/2) by 2 tan(fov_x/2) / aspect.
    pub fn power(&self) -> Vec3 {
        let width = 2.0 * self.tan_half_x;
        let area = width * width / self.aspect;
        self.irradiance.mean() * (PI * self.scale * area)
    }
}

impl super::EmitterPlugin for Projector {
    const NAME: &'static str = "projector";
    const DELTA: bool = true;
    const INFINITE: bool = false;

    #[inline]
    fn position(&self) -> Option<Vec3> {
        Some(self.position)
    }

    fn sample_li(&self, p: glam::Vec3, _u: glam::Vec2) -> Option<super::EmitterSample> {
        Projector::sample_li(self, p)
    }

    /// The density of [`EmitterPlugin::sample_ray`]'s directions (see there), zero outside the
    /// image.
    fn pdf_ray_dir(&self, _normal: Vec3, dir: Vec3) -> f32 {
        let local = self.from_world.transform_vector3(dir);
        if local.z.is_nan() || local.z <= 0.0 {
            return 0.0;
        }
        let q = local / local.z;
        if self.uv(q).is_none() {
            return 0.0;
        }
        let half_y = self.tan_half_x / self.aspect;
        let area = 4.0 * self.tan_half_x * half_y;
        let q_len = q.length();
        let mq_len = self.to_world.transform_vector3(q / q_len).length();
        let det = glam::Mat3::from_mat4(self.to_world).determinant().abs();
        if det.is_nan() || det <= 0.0 {
            return 0.0;
        }
        q_len.powi(3) * mq_len.powi(3) / (det * area)
    }

    /// A point of the image rectangle at z = 1, uniformly by area, and the direction through it.
    /// The intensity toward world direction `w` is `sample_li`'s weight at unit distance,
    /// `π scale E / (z_w² cos θ)`; the direction's density is the rectangle's, `1 / area`, times
    /// `|q|³` (from the plane to directions at the pinhole) and the transform's change of solid
    /// angle, `|M q̂|³ / |det M|` (1 for a rotation).
    fn sample_ray(&self, _u_pos: glam::Vec2, u_dir: glam::Vec2) -> Option<EmitterRay> {
        let half_y = self.tan_half_x / self.aspect;
        let q = Vec3::new(
            (1.0 - 2.0 * u_dir.x) * self.tan_half_x,
            (1.0 - 2.0 * u_dir.y) * half_y,
            1.0,
        );
        let uv = self.uv(q)?;
        let area = 4.0 * self.tan_half_x * half_y;
        let q_len = q.length();
        let mq = self.to_world.transform_vector3(q / q_len);
        let det = glam::Mat3::from_mat4(self.to_world).determinant().abs();
        let mq_len = mq.length();
        if !(det > 0.0 && mq_len > 0.0) {
            return None;
        }
        let dir = mq / mq_len;
        let pdf_dir = q_len.powi(3) * mq_len.powi(3) / (det * area);
        let z = self.from_world.transform_vector3(dir).z;
        let cos_theta = self.axis.dot(dir);
        if !(z > 0.0 && cos_theta > 0.0) {
            return None;
        }
        let intensity = self.irradiance.eval(uv) * (PI * self.scale / (z * z * cos_theta));
        Some(EmitterRay {
            origin: self.position,
            origin_error: Vec3::ZERO,
            dir,
            normal: Vec3::ZERO,
            uv: glam::Vec2::ZERO,
            weight: intensity / pdf_dir,
            pdf_pos: 1.0,
            pdf_dir,
        })
    }

    fn power(&self) -> glam::Vec3 {
        Projector::power(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant image lights a plane perpendicular to the axis uniformly with irradiance
    /// π·scale·E / z², and nothing outside the field of view.
    #[test]
    fn a_constant_image_lights_a_facing_plane_uniformly() {
        let e = Vec3::new(0.5, 1.0, 2.0);
        let p = Projector::new(Mat4::IDENTITY, Texture::Constant(e), 3.0, 1.0, 2.0);
        let z = 4.0;
        for (x, y) in [(0.0, 0.0), (3.0, 1.0), (-3.9, -1.9), (1.0, -1.5)] {
            let s = p.sample_li(Vec3::new(x, y, z)).expect("inside the image");
            // Irradiance on the plane = weight · cos of the incidence (the plane faces -z).
            let irradiance = s.weight * s.wi.dot(-Vec3::Z);
            let want = e * (PI * 3.0 / (z * z));
            assert!(
                (irradiance - want).abs().max_element() < 1e-5,
                "{x},{y}: {irradiance}"
            );
        }
        assert!(p.sample_li(Vec3::new(4.1, 0.0, z)).is_none());
        assert!(p.sample_li(Vec3::new(0.0, 2.1, z)).is_none());
        assert!(p.sample_li(Vec3::new(0.0, 0.0, -1.0)).is_none());
    }

    /// The power is the irradiance integrated over the lit part of a far plane.
    #[test]
    fn power_is_the_integrated_irradiance() {
        let p = Projector::new(Mat4::IDENTITY, Texture::Constant(Vec3::ONE), 1.0, 0.7, 1.5);
        let (z, n) = (10.0f32, 400);
        let (hx, hy) = (0.7 * z, 0.7 * z / 1.5);
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let x = -hx + (i as f32 + 0.5) / n as f32 * 2.0 * hx;
                let y = -hy + (j as f32 + 0.5) / n as f32 * 2.0 * hy;
                let s = p.sample_li(Vec3::new(x, y, z)).unwrap();
                sum += (s.weight.x * s.wi.dot(-Vec3::Z)) as f64;
            }
        }
        let flux = sum * (4.0 * hx as f64 * hy as f64) / (n * n) as f64;
        assert!(
            (flux / p.power().x as f64 - 1.0).abs() < 1e-3,
            "{flux} vs {}",
            p.power().x
        );
    }
}
