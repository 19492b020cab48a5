//! Mitsuba's `area` emitter: a shape whose surface emits radiance (a texture over its uv) from the
//! side its normal points to only.

use super::shape_sampler::ShapeSampler;
use super::emission::sampled_point_error;
use super::{EmitterRay, EmitterSample, PositionSample};
use crate::shading::bsdf::warp::square_to_cosine_hemisphere;
use crate::shading::frame::ShadingFrame;
use crate::shading::texture::Texture;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct AreaEmitter {
    pub radiance: Texture,
    pub shape: ShapeSampler,
}

impl AreaEmitter {
    pub fn new(radiance: Texture, shape: ShapeSampler) -> Self {
        Self { radiance, shape }
    }

    /// One-sided: `w` must leave the side `n` points to.
    pub fn radiance(&self, n: Vec3, uv: Vec2, w: Vec3) -> Vec3 {
        if n.dot(w) > 0.0 {
            self.radiance.eval(uv)
        } else {
            Vec3::ZERO
        }
    }

    /// A point of the shape as the shape sampler picks it, kept only if `p` sees its emitting side.
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<EmitterSample> {
        let s = self.shape.sample_direction(p, u)?;
        if s.wi.dot(s.shape.normal) >= 0.0 || s.pdf.is_nan() || s.pdf <= 0.0 {
            return None;
        }
        Some(EmitterSample {
            wi: s.wi,
            dist: s.dist,
            weight: self.radiance.eval(s.shape.uv) / s.pdf,
            pdf: s.pdf,
            delta: false,
        })
    }

    /// Zero for directions reaching the back of the surface, which [`sample_li`](Self::sample_li)
    /// never returns.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, light_point: Vec3, light_normal: Vec3) -> f32 {
        if wi.dot(light_normal) >= 0.0 {
            return 0.0;
        }
        self.shape.pdf_direction(p, wi, light_point, light_normal)
    }

    /// A point by area; its direction cosine-weighted about the normal (the emitter is
    /// Lambertian), so that the ray carries `L π / pdf_pos`.
    pub fn sample_ray(&self, u_pos: Vec2, u_dir: Vec2) -> Option<EmitterRay> {
        let ps = self.sample_position(u_pos)?;
        let local = square_to_cosine_hemisphere(u_dir);
        if local.z <= 0.0 {
            return None;
        }
        let dir = ShadingFrame::from_normal(ps.normal).to_world(local);
        Some(EmitterRay {
            origin: ps.point,
            origin_error: ps.point_error,
            dir,
            normal: ps.normal,
            uv: ps.uv,
            weight: self.radiance.eval(ps.uv) * (PI / ps.pdf),
            pdf_pos: ps.pdf,
            pdf_dir: local.z / PI,
        })
    }

    /// A point of the shape uniformly by area.
    pub fn sample_position(&self, u: Vec2) -> Option<PositionSample> {
        let (point, normal, uv, pdf) = self.shape.sample_area(u);
        if pdf.is_nan() || pdf <= 0.0 || !point.is_finite() {
            return None;
        }
        Some(PositionSample {
            point,
            point_error: sampled_point_error(point, 1.0 / pdf.sqrt()),
            normal,
            uv,
            pdf,
        })
    }

    /// Φ = π A L̄ for a one-sided Lambertian emitter, L̄ the texture's mean.
    pub fn power(&self) -> Vec3 {
        PI * self.shape.area() * self.radiance.mean()
    }
}

impl super::EmitterPlugin for AreaEmitter {
    const NAME: &'static str = "area";
    const DELTA: bool = false;
    const INFINITE: bool = false;

    #[inline]
    fn sample_li(&self, p: glam::Vec3, u: glam::Vec2) -> Option<super::EmitterSample> {
        AreaEmitter::sample_li(self, p, u)
    }

    #[inline]
    fn pdf_li(&self, p: glam::Vec3, wi: glam::Vec3, light_point: glam::Vec3, light_normal: glam::Vec3) -> f32 {
        AreaEmitter::pdf_li(self, p, wi, light_point, light_normal)
    }

    #[inline]
    fn radiance_area(&self, n: glam::Vec3, uv: glam::Vec2, w: glam::Vec3) -> glam::Vec3 {
        self.radiance(n, uv, w)
    }

    #[inline]
    fn sample_ray(&self, u_pos: Vec2, u_dir: Vec2) -> Option<EmitterRay> {
        AreaEmitter::sample_ray(self, u_pos, u_dir)
    }

    /// Cosine-weighted about the normal, on its emitting side.
    #[inline]
    fn pdf_ray_dir(&self, normal: Vec3, dir: Vec3) -> f32 {
        (normal.dot(dir) / PI).max(0.0)
    }

    #[inline]
    fn pdf_position(&self) -> f32 {
        let area = self.shape.area();
        if area > 0.0 {
            1.0 / area
        } else {
            0.0
        }
    }

    #[inline]
    fn sample_position(&self, u: Vec2) -> Option<PositionSample> {
        AreaEmitter::sample_position(self, u)
    }

    fn power(&self) -> glam::Vec3 {
        AreaEmitter::power(self)
    }
}

#[cfg(test)]
mod tests {
    use super::super::chi2_sphere::Rng;
    use super::super::Emitter;
    use super::*;
    use glam::{Mat4, Quat};

    /// Irradiance at `p` on a surface of normal `n`, estimated from `n` light samples.
    fn irradiance(e: &Emitter, p: Vec3, n: Vec3, samples: usize) -> Vec3 {
        let mut rng = Rng::new(11);
        let mut sum = Vec3::ZERO;
        for _ in 0..samples {
            if let Some(s) = e.sample_li(p, rng.vec2()) {
                sum += s.weight * s.wi.dot(n).max(0.0);
            }
        }
        sum / samples as f32
    }

    #[test]
    fn irradiance_from_a_sphere_is_pi_l_sin2() {
        // A uniformly emitting sphere seen whole: E = π L (r / d)² (its cone's projected area).
        let l = Vec3::new(1.0, 2.0, 4.0);
        let e = Emitter::Area(AreaEmitter::new(
            Texture::Constant(l),
            ShapeSampler::Sphere {
                center: Vec3::new(0.0, 0.0, 5.0),
                radius: 2.0,
            },
        ));
        let e_est = irradiance(&e, Vec3::ZERO, Vec3::Z, 20_000);
        let exact = PI * l * (2.0f32 / 5.0).powi(2);
        assert!(
            (e_est / exact - Vec3::ONE).abs().max_element() < 0.005,
            "{e_est} vs {exact}"
        );
        // Inside, the one-sided sphere faces away: no light.
        assert!(e
            .sample_li(Vec3::new(0.0, 0.0, 5.5), Vec2::splat(0.3))
            .is_none());
    }

    #[test]
    fn irradiance_from_a_disk_on_its_axis() {
        // A disk of radius R at height h, facing the point: E = π L R² / (h² + R²).
        let l = Vec3::splat(3.0);
        let (r, h) = (1.5f32, 2.0f32);
        let e = Emitter::Area(AreaEmitter::new(
            Texture::Constant(l),
            ShapeSampler::Disk {
                // Flipped to face -z, toward the origin.
                to_world: Mat4::from_scale_rotation_translation(
                    Vec3::splat(r),
                    Quat::from_rotation_x(PI),
                    Vec3::new(0.0, 0.0, h),
                ),
            },
        ));
        let e_est = irradiance(&e, Vec3::ZERO, Vec3::Z, 100_000);
        let exact = PI * l * r * r / (h * h + r * r);
        assert!(
            (e_est / exact - Vec3::ONE).abs().max_element() < 0.01,
            "{e_est} vs {exact}"
        );
        // From above the disk sees its back: nothing.
        assert!(irradiance(&e, Vec3::new(0.0, 0.0, 4.0), -Vec3::Z, 100) == Vec3::ZERO);
    }

    #[test]
    fn weights_are_radiance_over_pdf_and_one_sided() {
        let tex = Texture::Checkerboard(crate::shading::texture::Checkerboard {
            color0: Vec3::new(1.0, 0.5, 0.25),
            color1: Vec3::new(0.1, 0.2, 0.3),
            to_uv: glam::Mat3::from_scale(Vec2::splat(4.0)),
        });
        let shape = ShapeSampler::Rectangle {
            to_world: Mat4::from_rotation_translation(Quat::from_rotation_x(PI), Vec3::Z * 3.0),
        };
        let e = Emitter::Area(AreaEmitter::new(tex.clone(), shape.clone()));
        let p = Vec3::new(0.2, -0.3, 0.0);
        let mut rng = Rng::new(2);
        for _ in 0..100 {
            let u = rng.vec2();
            let s = e.sample_li(p, u).expect("the rectangle faces p");
            let ds = shape.sample_direction(p, u).unwrap();
            let (x, n) = (p + s.dist * s.wi, ds.shape.normal);
            let pdf = e.pdf_li(p, s.wi, x, n);
            assert!((pdf / s.pdf - 1.0).abs() < 1e-4);
            let radiance = e.radiance_area(n, ds.shape.uv, -s.wi);
            assert!(
                (s.weight - radiance / pdf).abs().max_element() < 1e-4 * s.weight.max_element()
            );
            assert_eq!(radiance, tex.eval(ds.shape.uv));
            // The back side emits nothing and has no density.
            assert_eq!(e.radiance_area(n, ds.shape.uv, s.wi), Vec3::ZERO);
            assert_eq!(e.pdf_li(p, -s.wi, x, n), 0.0);
        }
        assert!(!e.is_delta() && !e.is_infinite());
        // Φ = π A L̄: area 4, mean colour 0.5 (c0 + c1).
        let expect = PI * 4.0 * (0.5 * (1.75 + 0.6)) / 3.0;
        assert!((e.power() - expect).abs() < 1e-4);
    }
}
