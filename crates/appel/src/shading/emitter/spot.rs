//! Mitsuba's `spot` emitter: a point light whose intensity is full inside `beam_width` of its axis,
//! falls linearly in angle to zero at `cutoff_angle`, optionally modulated by a texture projected
//! through the cone.

use super::emission::uniform_cone;
use super::{EmitterRay, EmitterSample};
use crate::shading::texture::Texture;
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct SpotLight {
    /// Light-to-world transform: the spot sits at the origin looking down +z.
    to_world: Mat4,
    from_world: Mat4,
    position: Vec3,
    pub intensity: Vec3,
    /// Projected through the cone: uv (0.5, 0.5) on the axis, the cone's edge at 0 and 1.
    pub texture: Option<Texture>,
    cutoff: f32,
    beam: f32,
    cos_cutoff: f32,
    cos_beam: f32,
    /// tan(cutoff): the half-width of the texture's projection plane at z = 1.
    uv_factor: f32,
}

impl SpotLight {
    /// Angles in degrees; Mitsuba's defaults are a cutoff of 20 and a beam width of 3/4 of it (see
    /// [`SpotLight::with_defaults`]). A beam width above the cutoff is clamped to it.
    pub fn new(
        to_world: Mat4,
        intensity: Vec3,
        cutoff_deg: f32,
        beam_width_deg: f32,
        texture: Option<Texture>,
    ) -> Self {
        let cutoff = cutoff_deg.to_radians();
        let beam = beam_width_deg.to_radians().min(cutoff);
        Self {
            to_world,
            from_world: to_world.inverse(),
            position: to_world.transform_point3(Vec3::ZERO),
            intensity,
            texture,
            cutoff,
            beam,
            cos_cutoff: cutoff.cos(),
            cos_beam: beam.cos(),
            uv_factor: cutoff.tan(),
        }
    }

    pub fn with_defaults(to_world: Mat4, intensity: Vec3) -> Self {
        Self::new(to_world, intensity, 20.0, 15.0, None)
    }

    pub fn to_world(&self) -> &Mat4 {
        &self.to_world
    }

    /// 1 inside the beam, (cutoff - θ) / (cutoff - beam) in the transition, 0 outside the cutoff.
    fn falloff(&self, local: Vec3) -> f32 {
        let cos_theta = local.normalize().z;
        if cos_theta <= self.cos_cutoff {
            0.0
        } else if cos_theta >= self.cos_beam {
            1.0
        } else {
            (self.cutoff - cos_theta.acos()) / (self.cutoff - self.beam)
        }
    }

    /// Intensity toward local direction `local` (away from the light).
    fn intensity_toward(&self, local: Vec3) -> Vec3 {
        let f = self.falloff(local);
        if f <= 0.0 {
            return Vec3::ZERO;
        }
        let mut i = self.intensity * f;
        if let Some(t) = &self.texture {
            let uv = Vec2::new(
                0.5 + 0.5 * local.x / (local.z * self.uv_factor),
                0.5 + 0.5 * local.y / (local.z * self.uv_factor),
            );
            i *= t.eval(uv);
        }
        i
    }

    pub fn sample_li(&self, p: Vec3) -> Option<EmitterSample> {
        let to = self.position - p;
        let dist2 = to.length_squared();
        if dist2.is_nan() || dist2 <= 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = to / dist;
        let local = self.from_world.transform_vector3(-wi);
        let i = self.intensity_toward(local);
        if i == Vec3::ZERO {
            return None;
        }
        Some(EmitterSample {
            wi,
            dist,
            weight: i / dist2,
            pdf: 1.0,
            delta: true,
        })
    }

    /// Φ = I ∫ falloff dω = 2π I (1 + (sin b - sin c) / (c - b)) for beam b < cutoff c (the linear
    /// ramp integrated against sin θ), 2π I (1 - cos c) when they are equal; a texture scales it
    /// by its mean.
    pub fn power(&self) -> Vec3 {
        let (b, c) = (self.beam, self.cutoff);
        let solid_angle = if c - b > 1e-6 {
            2.0 * PI * (1.0 + (b.sin() - c.sin()) / (c - b))
        } else {
            2.0 * PI * (1.0 - c.cos())
        };
        let tex = self.texture.as_ref().map_or(Vec3::ONE, Texture::mean);
        self.intensity * tex * solid_angle
    }
}

impl super::EmitterPlugin for SpotLight {
    const NAME: &'static str = "spot";
    const DELTA: bool = true;
    const INFINITE: bool = false;

    #[inline]
    fn position(&self) -> Option<Vec3> {
        Some(self.position)
    }

    fn sample_li(&self, p: glam::Vec3, _u: glam::Vec2) -> Option<super::EmitterSample> {
        SpotLight::sample_li(self, p)
    }

    fn pdf_ray_dir(&self, _normal: Vec3, dir: Vec3) -> f32 {
        let local = self.from_world.transform_vector3(dir).normalize();
        if local.z > self.cos_cutoff {
            1.0 / (2.0 * PI * (1.0 - self.cos_cutoff))
        } else {
            0.0
        }
    }

    /// Uniform directions in the cone of the cutoff angle (Mitsuba's `spot`): the ray carries
    /// the intensity toward it over that density. Directions are mapped by the light's
    /// transform, a rotation for Mitsuba's `lookat` (a scale would change the densities).
    fn sample_ray(&self, _u_pos: glam::Vec2, u_dir: glam::Vec2) -> Option<EmitterRay> {
        let (local, pdf_dir) = uniform_cone(u_dir, self.cos_cutoff);
        let i = self.intensity_toward(local);
        if i == Vec3::ZERO {
            return None;
        }
        Some(EmitterRay {
            origin: self.position,
            origin_error: Vec3::ZERO,
            dir: self.to_world.transform_vector3(local).normalize(),
            normal: Vec3::ZERO,
            uv: glam::Vec2::ZERO,
            weight: i / pdf_dir,
            pdf_pos: 1.0,
            pdf_dir,
        })
    }

    fn power(&self) -> glam::Vec3 {
        SpotLight::power(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mitsuba's `look_at` frame: z toward the target, x = normalize(up × z), y = z × x.
    fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Mat4 {
        let z = (target - origin).normalize();
        let x = up.cross(z).normalize();
        let y = z.cross(x);
        Mat4::from_cols(
            x.extend(0.0),
            y.extend(0.0),
            z.extend(0.0),
            origin.extend(1.0),
        )
    }

    #[test]
    fn falloff_matches_mitsuba() {
        let t = look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 0.0, 3.2), Vec3::Z);
        let spot = SpotLight::new(t, Vec3::new(10.0, 20.0, 30.0), 25.0, 10.0, None);
        // Mitsuba 3.9 `spot` (cutoff 25, beam 10, same look_at): sample_direction's weights.
        let cases = [
            (
                Vec3::new(1.0, 0.0, 3.2),
                Some([2.475_247_1, 4.950_494_3, 7.425_741_7]),
            ),
            (
                Vec3::new(1.3, 0.0, 3.0),
                Some([2.403_599, 4.807_198, 7.210_797]),
            ),
            (
                Vec3::new(0.4, -1.0, 3.5),
                Some([0.918_066_14, 1.836_132_3, 2.754_198_3]),
            ),
            (
                Vec3::new(1.0, 0.0, 4.0),
                Some([0.552_739_44, 1.105_478_9, 1.658_218_3]),
            ),
            (Vec3::new(2.0, 0.0, 3.0), None),
        ];
        for (p, want) in cases {
            let got = spot.sample_li(p).map(|s| s.weight);
            match (got, want) {
                (Some(g), Some(w)) => {
                    let w = Vec3::from_array(w);
                    assert!(
                        (g - w).abs().max_element() < 1e-5 * w.max_element(),
                        "{p}: {g} vs {w}"
                    );
                }
                (None, None) => {}
                other => panic!("{p}: {other:?}"),
            }
        }
    }

    #[test]
    fn power_is_the_integrated_falloff() {
        let spot = SpotLight::with_defaults(Mat4::IDENTITY, Vec3::ONE);
        // Midpoint rule over θ of 2π falloff(θ) sin θ.
        let n = 20_000;
        let mut sum = 0.0f64;
        for k in 0..n {
            let theta = (k as f64 + 0.5) / n as f64 * 0.5 * std::f64::consts::PI;
            let local = Vec3::new(theta.sin() as f32, 0.0, theta.cos() as f32);
            sum += spot.falloff(local) as f64 * theta.sin();
        }
        let numeric = 2.0 * std::f64::consts::PI * sum * 0.5 * std::f64::consts::PI / n as f64;
        assert!(
            (spot.power().x as f64 / numeric - 1.0).abs() < 1e-3,
            "{} vs {numeric}",
            spot.power().x
        );
    }
}
