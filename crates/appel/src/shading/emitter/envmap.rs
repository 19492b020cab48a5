//! Mitsuba's `envmap` emitter: radiance from a latitude-longitude image at infinity.
//!
//! Conventions (Mitsuba 3, src/emitters/envmap.cpp): in the emitter's frame +y is up; a direction
//! d has u = atan2(d.x, -d.z) / 2π and v = acos(d.y) / π. Rows are samples at the polar angles
//! θ = π y / (height - 1), so the first row is the north pole and the last the south pole;
//! columns are samples at u = (x + 1/2) / width, the image wrapping around in u. Radiance is the
//! bilinear blend of the four samples around (u, v), times `scale`.
//!
//! Sampling: one piecewise-constant cell per bilinear patch (between two neighbouring rows and
//! columns), weighted by the patch's mean luminance times its solid angle (which carries the sin θ
//! of the lat-long map), and inside the patch uniformly in u and cos θ, so that the density in
//! solid angle is constant over each patch and bounded at the poles. Mitsuba warps a bilinear
//! density instead; both are unbiased and agree in expectation.

use super::distribution::Distribution2D;
use super::EmitterSample;
use crate::error::{Error, Location, Result};
use crate::io::bitmap_read::{read_bitmap, Bitmap};
use crate::shading::texture::luminance;
use glam::{Mat3, Mat4, Vec2, Vec3};
use std::f32::consts::PI;
use std::path::Path;

#[derive(Clone, Debug)]
pub struct EnvMap {
    /// Columns of the image; the stored rows have one more, a copy of the first (the wrap in u).
    width: usize,
    height: usize,
    /// Linear RGB, `(width + 1) * height` samples, top row first.
    texels: Vec<Vec3>,
    pub scale: f32,
    to_world: Mat3,
    from_world: Mat3,
    /// Over the `width` by `height - 1` patches.
    distribution: Distribution2D,
    /// cos θ of each row of samples.
    row_cos: Vec<f32>,
    /// Per row of patches: 1 / (the solid angle of one patch).
    inv_patch_solid_angle: Vec<f32>,
    /// ∫ L dω over the sphere, before `scale`.
    radiance_integral: Vec3,
    /// Radius of the scene's bounding sphere, through whose cross-section the power is counted.
    pub scene_radius: f32,
}

impl EnvMap {
    /// Reads a lat-long image (EXR, HDR, or an sRGB-decoded PNG or JPEG).
    pub fn load(path: &Path, to_world: Mat4, scale: f32) -> Result<Self> {
        let bitmap = read_bitmap(path, false)?;
        Self::new(&bitmap, to_world, scale).map_err(|m| Error::input(Location::file(path), m))
    }

    /// `to_world` is used for its rotation only. Grey images are taken as grey RGB; alpha is
    /// ignored. Mitsuba's minimum size, 2 by 3 pixels, applies.
    pub fn new(bitmap: &Bitmap, to_world: Mat4, scale: f32) -> std::result::Result<Self, String> {
        let (width, height) = (bitmap.width as usize, bitmap.height as usize);
        if width < 2 || height < 3 {
            return Err(format!(
                "an environment map must be at least 2x3 pixels, this one is {width}x{height}"
            ));
        }
        if !(1..=4).contains(&bitmap.channels) {
            return Err(format!("unsupported channel count {}", bitmap.channels));
        }
        let padded = width + 1;
        let mut texels = Vec::with_capacity(padded * height);
        for y in 0..height as u32 {
            let row_start = texels.len();
            for x in 0..width as u32 {
                let p = bitmap.pixel(x, y);
                texels.push(if bitmap.channels <= 2 {
                    Vec3::splat(p[0])
                } else {
                    Vec3::new(p[0], p[1], p[2])
                });
            }
            texels.push(texels[row_start]);
        }

        let dtheta = PI / (height - 1) as f32;
        let row_cos: Vec<f32> = (0..height).map(|y| (y as f32 * dtheta).cos()).collect();
        let dphi = 2.0 * PI / width as f32;
        // cos θj - cos θj+1 as a product of sines, which keeps its precision near the poles.
        let patch_solid_angle: Vec<f32> = (0..height - 1)
            .map(|j| {
                let (a, b) = (j as f32 * dtheta, (j + 1) as f32 * dtheta);
                dphi * 2.0 * (0.5 * (a + b)).sin() * (0.5 * (b - a)).sin()
            })
            .collect();
        let mut weights = Vec::with_capacity(width * (height - 1));
        let mut integral = [0.0f64; 3];
        for (j, &omega) in patch_solid_angle.iter().enumerate() {
            for i in 0..width {
                let corners = [
                    texels[j * padded + i],
                    texels[j * padded + i + 1],
                    texels[(j + 1) * padded + i],
                    texels[(j + 1) * padded + i + 1],
                ];
                // The mean of the corners is the bilinear patch's mean over (u, v).
                let mean = 0.25 * corners.iter().copied().sum::<Vec3>();
                // Negative channels clamped, so that a weight is zero only where all radiance is.
                weights.push(luminance(mean.max(Vec3::ZERO)) * omega);
                for (s, c) in integral.iter_mut().zip(mean.to_array()) {
                    *s += (c * omega) as f64;
                }
            }
        }
        let rot = Mat3::from_mat4(to_world);
        Ok(Self {
            width,
            height,
            texels,
            scale,
            to_world: rot,
            from_world: rot.inverse(),
            distribution: Distribution2D::new(&weights, width, height - 1),
            row_cos,
            inv_patch_solid_angle: patch_solid_angle.iter().map(|w| 1.0 / w).collect(),
            radiance_integral: Vec3::new(
                integral[0] as f32,
                integral[1] as f32,
                integral[2] as f32,
            ),
            scene_radius: 1.0,
        })
    }

    /// Half a texel in u: where the first column's samples sit.
    fn half_texel(&self) -> f32 {
        0.5 / self.width as f32
    }

    /// Mitsuba's lat-long coordinates of a unit direction in the emitter's frame.
    fn direction_to_uv(d: Vec3) -> Vec2 {
        Vec2::new(
            d.x.atan2(-d.z) * (0.5 / PI),
            d.y.clamp(-1.0, 1.0).acos() * (1.0 / PI),
        )
    }

    /// The bilinear lookup at lat-long `uv`, before `scale`.
    fn lookup(&self, uv: Vec2) -> Vec3 {
        // u wraps around; v is clamped, so that the south pole (v = 1) stays on the last row.
        let su = uv.x - self.half_texel();
        let mut s = Vec2::new(su - su.floor(), uv.y.clamp(0.0, 1.0));
        s *= Vec2::new(self.width as f32, (self.height - 1) as f32);
        let ix = (s.x as usize).min(self.width - 1);
        let iy = (s.y as usize).min(self.height - 2);
        let (wx, wy) = (s.x - ix as f32, s.y - iy as f32);
        let padded = self.width + 1;
        let i = iy * padded + ix;
        let t = &self.texels;
        let top = t[i] * (1.0 - wx) + t[i + 1] * wx;
        let bottom = t[i + padded] * (1.0 - wx) + t[i + padded + 1] * wx;
        top * (1.0 - wy) + bottom * wy
    }

    /// Radiance arriving along world direction `d` (toward the scene from -d's side of the sky).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let local = (self.from_world * d).normalize_or_zero();
        self.lookup(Self::direction_to_uv(local)) * self.scale
    }

    pub fn sample_li(&self, u: Vec2) -> Option<EmitterSample> {
        let (x, [ix, iy]) = {
            let (x, _, cell) = self.distribution.sample(u);
            (x, cell)
        };
        let pmf = self.distribution.pmf_cell(ix, iy);
        if pmf.is_nan() || pmf <= 0.0 {
            return None;
        }
        let fy = (x.y * (self.height - 1) as f32 - iy as f32).clamp(0.0, 1.0);
        let cos_theta = self.row_cos[iy] + fy * (self.row_cos[iy + 1] - self.row_cos[iy]);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let uu = x.x + self.half_texel();
        let phi = 2.0 * PI * uu;
        let local = Vec3::new(phi.sin() * sin_theta, cos_theta, -phi.cos() * sin_theta);
        let pdf = pmf * self.inv_patch_solid_angle[iy];
        let uv = Vec2::new(uu, cos_theta.clamp(-1.0, 1.0).acos() / PI);
        let wi = (self.to_world * local).normalize();
        Some(EmitterSample {
            wi,
            dist: f32::INFINITY,
            weight: self.lookup(uv) * self.scale / pdf,
            pdf,
            delta: false,
        })
    }

    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        let local = (self.from_world * wi).normalize_or_zero();
        let uv = Self::direction_to_uv(local);
        let mut su = uv.x - self.half_texel();
        su -= su.floor();
        let ix = ((su * self.width as f32) as usize).min(self.width - 1);
        let iy = ((uv.y * (self.height - 1) as f32) as usize).min(self.height - 2);
        self.distribution.pmf_cell(ix, iy) * self.inv_patch_solid_angle[iy]
    }

    /// The flux entering the scene's bounding sphere: Φ = π r² ∫ L dω.
    pub fn power(&self) -> Vec3 {
        PI * self.scene_radius * self.scene_radius * self.scale * self.radiance_integral
    }
}

impl super::EmitterPlugin for EnvMap {
    const NAME: &'static str = "envmap";
    const DELTA: bool = false;
    const INFINITE: bool = true;

    #[inline]
    fn sample_li(&self, _p: glam::Vec3, u: glam::Vec2) -> Option<super::EmitterSample> {
        EnvMap::sample_li(self, u)
    }

    #[inline]
    fn pdf_li(&self, _p: glam::Vec3, wi: glam::Vec3, _light_point: glam::Vec3, _light_normal: glam::Vec3) -> f32 {
        EnvMap::pdf_li(self, wi)
    }

    #[inline]
    fn radiance_env(&self, d: glam::Vec3) -> glam::Vec3 {
        self.radiance(d)
    }

    fn power(&self) -> glam::Vec3 {
        EnvMap::power(self)
    }

    fn set_scene_bounds(&mut self, _center: glam::Vec3, radius: f32) {
        self.scene_radius = radius;
    }
}

#[cfg(test)]
mod tests {
    use super::super::chi2_sphere::{assert_fits, Rng, Spec};
    use super::super::Emitter;
    use super::*;

    fn museum() -> std::path::PathBuf {
        appel_testdata::path("mitsuba-data/common/textures/museum.exr")
    }

    fn close(a: Vec3, b: [f32; 3], rel: f32) -> bool {
        let b = Vec3::from_array(b);
        (a - b).abs().max_element() <= rel * b.abs().max_element() + 1e-7
    }

    #[test]
    fn lookups_match_mitsuba_on_a_small_map() {
        // 4x3 pixels (x + 1, 10 (y + 1), 100 + x + 10 y); Mitsuba 3.9's `envmap` eval at the
        // equator for u = 0.125, 0.375, 0, 0.0625 gave [1, 20, 110], [2, 20, 111],
        // [2.5, 20, 111.5], [1.75, 20, 110.75], and [2.5, 10, 101.5] at +y, [2.5, 30, 121.5] at -y.
        let mut data = Vec::new();
        for y in 0..3 {
            for x in 0..4 {
                data.extend([
                    x as f32 + 1.0,
                    10.0 * (y + 1) as f32,
                    100.0 + (x + 10 * y) as f32,
                ]);
            }
        }
        let bitmap = Bitmap {
            width: 4,
            height: 3,
            channels: 3,
            data,
        };
        let env = EnvMap::new(&bitmap, Mat4::IDENTITY, 1.0).unwrap();
        let at = |u: f32| {
            let phi = 2.0 * PI * u;
            env.radiance(Vec3::new(phi.sin(), 0.0, -phi.cos()))
        };
        assert!(close(at(0.125), [1.0, 20.0, 110.0], 1e-5));
        assert!(close(at(0.375), [2.0, 20.0, 111.0], 1e-5));
        assert!(close(at(0.0), [2.5, 20.0, 111.5], 1e-5));
        assert!(close(at(0.0625), [1.75, 20.0, 110.75], 1e-5));
        assert!(close(env.radiance(Vec3::Y), [2.5, 10.0, 101.5], 1e-5));
        assert!(close(env.radiance(-Vec3::Y), [2.5, 30.0, 121.5], 1e-5));
        let tiny = Bitmap {
            width: 2,
            height: 2,
            channels: 3,
            data: vec![1.0; 12],
        };
        assert!(EnvMap::new(&tiny, Mat4::IDENTITY, 1.0)
            .unwrap_err()
            .contains("2x3"));
    }

    #[test]
    #[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
    fn museum_radiance_matches_mitsuba() {
        let dirs = [
            Vec3::new(0.3, 0.5, -0.8),
            Vec3::new(-0.7, 0.1, 0.2),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.2, 0.9, 0.1),
            Vec3::new(0.999, 0.01, -0.02),
        ];
        // Mitsuba 3.9 `envmap` eval of museum.exr along these directions (si.wi = -d): as is,
        // then with to_world = rotate(y, 30 degrees) and scale = 2.5.
        let plain = [
            [0.354_965_18, 0.306_833_83, 0.268_860_94],
            [2.262_018, 1.984_022_1, 1.557_657],
            [0.000_315_904_62, 0.000_203_132_63, 0.000_136_613_85],
            [0.256_564_2, 0.133_662_06, 0.061_893_925],
            [0.178_016_28, 0.070_251_84, 0.031_670_176],
        ];
        let turned = [
            [1.114_032_5, 0.668_869_3, 0.445_902_88],
            [6.964_009, 7.032_747_3, 4.485_23],
            [0.000_789_761_54, 0.000_507_831_6, 0.000_341_534_62],
            [0.624_089_36, 0.322_698_5, 0.144_843_79],
            [0.751_779_1, 0.355_441_45, 0.202_502_83],
        ];
        let a = EnvMap::load(&museum(), Mat4::IDENTITY, 1.0).unwrap();
        let b = EnvMap::load(&museum(), Mat4::from_rotation_y(30f32.to_radians()), 2.5).unwrap();
        for (d, (p, t)) in dirs.iter().zip(plain.iter().zip(&turned)) {
            let d = d.normalize();
            assert!(
                close(a.radiance(d), *p, 1e-4),
                "{d}: {} vs {p:?}",
                a.radiance(d)
            );
            assert!(
                close(b.radiance(d), *t, 1e-4),
                "{d}: {} vs {t:?}",
                b.radiance(d)
            );
        }
    }

    #[test]
    #[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
    fn museum_sampling_fits_its_density() {
        let env = EnvMap::load(&museum(), Mat4::from_rotation_x(0.3), 1.0).unwrap();
        let e = Emitter::EnvMap(env.clone());
        assert_fits(
            "envmap",
            // The density jumps at every one of the 130,560 patches: a fine fixed grid (about 8
            // points per patch side) rather than refinement.
            &Spec {
                k: 96,
                depth: 0,
                ..Spec::sphere(300_000)
            },
            |u| e.sample_li(Vec3::ZERO, u).map(|s| s.wi),
            |wi| e.pdf_li(Vec3::ZERO, wi, Vec3::ZERO, Vec3::ZERO),
            1.0,
            0.01,
        );
        // Weights are radiance over density, both as seen from outside.
        let mut rng = Rng::new(9);
        for _ in 0..1000 {
            let s = e.sample_li(Vec3::ZERO, rng.vec2()).unwrap();
            let pdf = e.pdf_li(Vec3::ZERO, s.wi, Vec3::ZERO, Vec3::ZERO);
            assert!((pdf / s.pdf - 1.0).abs() < 1e-3, "{pdf} vs {}", s.pdf);
            let w = e.radiance_env(s.wi) / pdf;
            assert!((w - s.weight).abs().max_element() <= 2e-3 * w.max_element() + 1e-6);
        }
        // The density integrates to one: one direction per patch (its centre) times its solid
        // angle, which holds exactly for a density constant over each patch.
        let (w, h) = (env.width, env.height);
        let mut integral = 0.0f64;
        for j in 0..h - 1 {
            let cos = 0.5 * (env.row_cos[j] + env.row_cos[j + 1]);
            let sin = (1.0 - cos * cos).sqrt();
            for i in 0..w {
                let phi = 2.0 * PI * ((i as f32 + 0.5) / w as f32 + env.half_texel());
                let local = Vec3::new(phi.sin() * sin, cos, -phi.cos() * sin);
                integral +=
                    (env.pdf_li(env.to_world * local) / env.inv_patch_solid_angle[j]) as f64;
            }
        }
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
    }

    #[test]
    fn a_uniform_map_has_the_constant_power() {
        let bitmap = Bitmap {
            width: 8,
            height: 5,
            channels: 1,
            data: vec![2.0; 40],
        };
        let mut e = Emitter::EnvMap(EnvMap::new(&bitmap, Mat4::IDENTITY, 1.5).unwrap());
        let mut c = Emitter::Constant(super::super::ConstantEnvironment::new(Vec3::splat(3.0)));
        e.set_scene_bounds(Vec3::ONE, 2.0);
        c.set_scene_bounds(Vec3::ONE, 2.0);
        assert!(
            (e.power() / c.power() - 1.0).abs() < 1e-5,
            "{} vs {}",
            e.power(),
            c.power()
        );
        // A uniform map is sampled uniformly: density 1 / 4π everywhere.
        let pdf = e.pdf_li(
            Vec3::ZERO,
            Vec3::new(0.3, -0.4, 0.5).normalize(),
            Vec3::ZERO,
            Vec3::ZERO,
        );
        assert!((pdf * 4.0 * PI - 1.0).abs() < 1e-4);
    }

    #[test]
    fn a_bad_file_is_an_error_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sky.exr");
        std::fs::write(&path, b"v/1\x01garbage that is no EXR header").unwrap();
        let err = EnvMap::load(&path, Mat4::IDENTITY, 1.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("sky.exr"), "{err}");
    }
}
