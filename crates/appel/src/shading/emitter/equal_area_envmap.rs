//! pbrt-v4's image `infinite` light: radiance from a square image in the equal-area octahedral
//! mapping ([`super::equal_area`]), looked up at the nearest texel as pbrt-v4's `ImageLe` does.
//!
//! In the emitter's frame +z is the pole at the image's centre. Each texel covers the same solid
//! angle, 4π / n², so the radiance is constant over each texel's patch of the sphere, and a
//! piecewise-constant distribution over the texels proportional to their luminance samples
//! directions in proportion to the radiance exactly (density in solid angle: the square's density
//! over 4π, with no sin θ as a latitude-longitude map has).

use super::distribution::Distribution2D;
use super::equal_area::{sphere_to_square, square_to_sphere};
use super::EmitterSample;
use crate::io::bitmap_read::Bitmap;
use crate::shading::texture::luminance;
use glam::{Mat3, Mat4, Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct EqualAreaEnvMap {
    /// The image is `size` by `size`.
    size: usize,
    /// Linear RGB, top row (v = 0) first.
    texels: Vec<Vec3>,
    pub scale: f32,
    to_world: Mat3,
    from_world: Mat3,
    /// Over the texels, row-major.
    distribution: Distribution2D,
    /// ∫ L dω over the sphere, before `scale`.
    radiance_integral: Vec3,
    /// Radius of the scene's bounding sphere, through whose cross-section the power is counted.
    pub scene_radius: f32,
}

impl EqualAreaEnvMap {
    /// `to_world` is used for its rotation only. Grey images are taken as grey RGB; alpha is
    /// ignored. The image must be square, as pbrt-v4 requires.
    pub fn new(bitmap: &Bitmap, to_world: Mat4, scale: f32) -> std::result::Result<Self, String> {
        let (width, height) = (bitmap.width as usize, bitmap.height as usize);
        if width != height || width == 0 {
            return Err(format!(
                "an equal-area environment map is square; this one is {width}x{height} (a \
                 latitude-longitude map is Mitsuba's `envmap`)"
            ));
        }
        if !(1..=4).contains(&bitmap.channels) {
            return Err(format!("unsupported channel count {}", bitmap.channels));
        }
        let size = width;
        let mut texels = Vec::with_capacity(size * size);
        for y in 0..size as u32 {
            for x in 0..size as u32 {
                let p = bitmap.pixel(x, y);
                let rgb = if bitmap.channels <= 2 {
                    Vec3::splat(p[0])
                } else {
                    Vec3::new(p[0], p[1], p[2])
                };
                // Negative values clamped, as pbrt-v4's `ClampZero` does.
                texels.push(rgb.max(Vec3::ZERO));
            }
        }
        let weights: Vec<f32> = texels.iter().map(|&t| luminance(t)).collect();
        let texel_solid_angle = 4.0 * PI as f64 / (size * size) as f64;
        let mut integral = [0.0f64; 3];
        for t in &texels {
            for (s, c) in integral.iter_mut().zip(t.to_array()) {
                *s += c as f64 * texel_solid_angle;
            }
        }
        let rot = Mat3::from_mat4(to_world);
        Ok(Self {
            size,
            texels,
            scale,
            to_world: rot,
            from_world: rot.inverse(),
            distribution: Distribution2D::new(&weights, size, size),
            radiance_integral: Vec3::new(
                integral[0] as f32,
                integral[1] as f32,
                integral[2] as f32,
            ),
            scene_radius: 1.0,
        })
    }

    /// The texel holding point `p` of the square.
    fn texel_of(&self, p: Vec2) -> (usize, usize) {
        let n = self.size;
        let at = |c: f32| ((c * n as f32) as usize).min(n - 1);
        (at(p.x.max(0.0)), at(p.y.max(0.0)))
    }

    /// The emitter-frame point of the square a world direction looks at.
    fn square_of(&self, d: Vec3) -> Vec2 {
        sphere_to_square((self.from_world * d).normalize_or_zero())
    }

    /// Radiance arriving along world direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (ix, iy) = self.texel_of(self.square_of(d));
        self.texels[iy * self.size + ix] * self.scale
    }

    pub fn sample_li(&self, u: Vec2) -> Option<EmitterSample> {
        let (p, _, [ix, iy]) = self.distribution.sample(u);
        let pdf = self.distribution.pmf_cell(ix, iy) * (self.size * self.size) as f32 / (4.0 * PI);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let wi = (self.to_world * square_to_sphere(p)).normalize();
        Some(EmitterSample {
            wi,
            dist: f32::INFINITY,
            weight: self.texels[iy * self.size + ix] * self.scale / pdf,
            pdf,
            delta: false,
        })
    }

    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        let (ix, iy) = self.texel_of(self.square_of(wi));
        self.distribution.pmf_cell(ix, iy) * (self.size * self.size) as f32 / (4.0 * PI)
    }

    /// The flux entering the scene's bounding sphere: Φ = π r² ∫ L dω.
    pub fn power(&self) -> Vec3 {
        PI * self.scene_radius * self.scene_radius * self.scale * self.radiance_integral
    }
}

impl super::EmitterPlugin for EqualAreaEnvMap {
    const NAME: &'static str = "equalareaenvmap";
    const DELTA: bool = false;
    const INFINITE: bool = true;

    #[inline]
    fn sample_li(&self, _p: Vec3, u: Vec2) -> Option<EmitterSample> {
        EqualAreaEnvMap::sample_li(self, u)
    }

    #[inline]
    fn pdf_li(&self, _p: Vec3, wi: Vec3, _light_point: Vec3, _light_normal: Vec3) -> f32 {
        EqualAreaEnvMap::pdf_li(self, wi)
    }

    #[inline]
    fn radiance_env(&self, d: Vec3) -> Vec3 {
        self.radiance(d)
    }

    fn power(&self) -> Vec3 {
        EqualAreaEnvMap::power(self)
    }

    fn set_scene_bounds(&mut self, _center: Vec3, radius: f32) {
        self.scene_radius = radius;
    }
}

#[cfg(test)]
#[path = "equal_area_envmap_tests.rs"]
mod tests;
